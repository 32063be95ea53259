//! Bad input: one clear error line naming the field, exit code 2, no panic (issue 2).

use crate::util::run;

fn expect_error(args: &[&str], field: &str) {
    let out = run(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "args {args:?}: stderr {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line expected: {err}");
    assert!(err.contains(field), "error should name '{field}': {err}");
    assert!(out.stdout.is_empty());
}

fn scene_file(name: &str, text: &str) -> std::path::PathBuf {
    // Shared by tests running at once: made, never emptied (each file's name is its test's).
    let dir = crate::util::scratch_root().join("vibroatlas-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn multi_stop_with(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(crate::util::config("multi-stop.toml")).unwrap();
    assert!(text.contains(from));
    text.replacen(from, to, 1)
}

#[test]
fn malformed_toml() {
    let p = scene_file("malformed.toml", "name = \"x\"\n[parameters\nomega = 1\n");
    // The parser's own message, with the place of the error (an unreadable
    // file also says "scene file").
    expect_error(&["cell", p.to_str().unwrap()], "TOML parse error at line 2");
}

#[test]
fn unknown_key() {
    let p = scene_file("unknown.toml", &multi_stop_with("restitution = \"R\"", "restitution = \"R\"\nelasticity = 1"));
    expect_error(&["cell", p.to_str().unwrap()], "elasticity");
}

/// A value of the wrong type says what was expected, and a parameter's
/// table its own mistake: the parser's words were "data did not match any
/// variant of untagged enum Num" (or `ParamSpec`), whatever the mistake.
#[test]
fn a_value_of_the_wrong_type_says_what_was_expected() {
    for (name, from, to, says) in [
        (
            "bool-number.toml",
            "stiffness = 1",
            "stiffness = true",
            "invalid type: boolean `true`, expected a number or an expression in quotes",
        ),
        (
            "list-number.toml",
            "stiffness = 1",
            "stiffness = [1]",
            "invalid type: sequence, expected a number or an expression in quotes",
        ),
        (
            "bool-parameter.toml",
            "tau = { value = 0.0, doc = \"forcing phase\", symbol = \"τ\" }",
            "tau = false",
            "expected a number, an expression in quotes, or a table",
        ),
        (
            "typo-parameter.toml",
            "mu_m = { value",
            "mu_m = { rnage = \"(0, 1)\", value",
            "unknown field `rnage`, expected one of `value`",
        ),
        (
            "bool-value.toml",
            "mu_m = { value = 0.5",
            "mu_m = { value = true",
            "invalid type: boolean `true`, expected a number or an expression",
        ),
    ] {
        let p = scene_file(name, &multi_stop_with(from, to));
        expect_error(&["cell", p.to_str().unwrap()], says);
    }
}

#[test]
fn missing_parameter_in_expression() {
    let p = scene_file("missing.toml", &multi_stop_with("position = \"-delta1\"", "position = \"-delta9\""));
    expect_error(&["cell", p.to_str().unwrap()], "stops[0].position");
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "omgea=0.3"], "omgea");
}

#[test]
fn mass_ratio_outside_unit_interval() {
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "mu_m=1.5"], "parameters.mu_m");
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "mu_k=0"], "parameters.mu_k");
}

/// A view the file cannot draw names `--view`; an output whose folder is a
/// file says so.
#[test]
fn the_option_that_gave_a_bad_value_is_named() {
    let d = crate::util::scratch("named-option");
    let (a, f) = (d.join("a.h5"), d.join("file"));
    let a = a.to_str().unwrap();
    let atlas = ["atlas", "configs/multi-stop.toml", "--x", "omega=0.3:0.33:2", "--y", "delta=0.7:0.8:2"];
    crate::util::ok(&[&atlas[..], &["--sweep", "up", "--quiet", "-o", a]].concat());
    let png = d.join("x.png");
    let render = ["render", a, "--view", "attractors", "-o", png.to_str().unwrap()];
    expect_error(&render, "--view attractors: render: the file has no attractors: make it with atlas --attractors K");
    std::fs::write(&f, "").unwrap();
    let inside = f.join("x.png");
    let render = ["render", a, "-o", inside.to_str().unwrap()];
    expect_error(&render, &format!("-o: {}: {} is a file, not a folder", inside.display(), f.display()));
    // A folder that takes no file, named before any work, with the option.
    expect_error(&["render", a, "-o", "/proc/x.png"], "-o: /proc/x.png: cannot create a file in /proc: ");
    // A value of --set the scene refuses is the scene's field, with --from as without.
    let from = ["cell", "--from", a, "--at", "omega=0.3,delta=0.7", "--set", "zeta=-1"];
    expect_error(&from, "error: parameters.zeta: must be in [0, inf), got -1");
}

#[test]
fn restitution_outside_unit_interval() {
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "R=1.2"], "parameters.R");
    expect_error(&["cell", "configs/single-stop.toml", "--set", "r=-0.1"], "parameters.r");
    // Without a declared range the stop itself refuses it.
    let p = scene_file(
        "r.toml",
        &multi_stop_with("R = { value = 0.8, range = \"[0, 1]\", doc = \"coefficient of restitution\" }", "R = 1.2"),
    );
    expect_error(&["cell", p.to_str().unwrap()], "stops[0].restitution");
}

#[test]
fn negative_clearance() {
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "delta=-0.1"], "delta");
    expect_error(&["cell", "configs/impact-damper.toml", "--set", "delta=-1"], "delta");
}

#[test]
fn nan_in_set() {
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "omega=nan"], "--set omega");
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "omega=abc"], "--set omega");
    expect_error(&["cell", "configs/multi-stop.toml", "--set", "omega"], "--set");
}

#[test]
fn bad_options() {
    expect_error(&["cell", "configs/multi-stop.toml", "--preset", "quick"], "--preset");
    expect_error(&["cell", "configs/multi-stop.toml", "--integrator", "euler"], "--integrator");
    // A count states its own bound (>= 1) whether it is zero or negative.
    for n_max in ["n_max=0", "n_max=-3"] {
        expect_error(&["cell", "configs/multi-stop.toml", "--accuracy", n_max], "n_max: must be a whole number >= 1");
    }
    expect_error(
        &["cell", "configs/multi-stop.toml", "--accuracy", "chatter_velocity=-1"],
        "chatter_velocity: must be >= 0",
    );
    expect_error(&["cell", "configs/multi-stop.toml", "--accuracy", "chaos_check=2.5"], "chaos_check");
    expect_error(&["cell", "configs/multi-stop.toml", "--accuracy", "chaos_check=-1"], "chaos_check");
    expect_error(&["cell", "configs/missing.toml"], "configs/missing.toml");
    expect_error(&["cell", "configs/multi-stop.toml", "--trace", "/nonexistent-dir/t.csv"], "/nonexistent-dir/t.csv");
}

/// A value that starts with '-' is refused by the option's own check, which
/// names the option (clap named none: "unexpected argument '-1' found").
#[test]
fn negative_values_name_their_option() {
    let plane = ["--x", "omega=0.1:3:4", "--y", "delta=0.05:2:3", "-o", "/nonexistent-dir/o.h5"];
    let atlas = |flag: &'static str, value: &'static str| {
        let mut v = vec!["atlas", "configs/multi-stop.toml", flag, value];
        v.extend(plane);
        v
    };
    for (flag, value) in [("--shard", "-1/2"), ("--attractors", "-1"), ("--seed", "-1"), ("--threads", "-2")] {
        expect_error(&atlas(flag, value), flag);
    }
    let sweep = ["sweep", "configs/multi-stop.toml", "--axis", "omega=0.2:0.4:5", "--section-cap", "-1"];
    expect_error(&sweep, "--section-cap");
    expect_error(&["attractors", "configs/multi-stop.toml", "--box", "-1,-1"], "--box");
    expect_error(&["orbit", "configs/multi-stop.toml", "--n", "-1"], "--n");
}

/// No command: the line lists the commands (it was the program's description).
#[test]
fn no_command_names_the_commands() {
    expect_error(&[], "a command is needed: cell, sweep, atlas");
}

/// A mistyped name of a value, a flag or a command gets one line that lists
/// the names and says which was meant; the library's names read in each place
/// (a bifurcation's kind in either case, the knobs of `--accuracy`).
#[test]
fn a_mistyped_name_says_which_was_meant() {
    let cell = |flag: &'static str, value: &'static str| vec!["cell", "configs/multi-stop.toml", flag, value];
    expect_error(&cell("--preset", "precize"), "[possible values: fast, standard, precise] (did you mean 'precise'?)");
    expect_error(&cell("--integrator", "rk5"), "(did you mean 'rk4'?)");
    expect_error(&cell("--accuracy", "event_tl=1e-9"), "unknown accuracy knob (did you mean 'event_tol'?)");
    expect_error(&cell("--presett", "fast"), "(did you mean '--preset'?)");
    expect_error(&["atlsa", "configs/multi-stop.toml"], "(did you mean 'atlas'?)");
    let sweep = ["sweep", "configs/multi-stop.toml", "--axis", "omega=0.2:0.4:5", "--direction", "downup"];
    expect_error(&sweep, "[possible values: up, down, both, down-up, up-down] (did you mean 'down-up'?)");
    let far = run(&["cell", "configs/multi-stop.toml", "--preset", "zebra"]);
    assert!(!String::from_utf8_lossy(&far.stderr).contains("did you mean"));
    let curve = ["curve", "configs/multi-stop.toml", "--kind", "Pd", "--start", "omega=1", "--free", "omega,delta"];
    let out = run(&curve);
    assert!(
        !String::from_utf8_lossy(&out.stderr).contains("invalid value"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// What an error echoes stays readable: a number written out in 309 digits
/// is shown in exponent form, a 100 000-character name cut with its length.
#[test]
fn echoed_values_stay_short() {
    let out = run(&["cell", "configs/multi-stop.toml", "--state", "1e308,0,0,0"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--state") && err.contains("1e308") && err.len() < 200, "{err}");
    let name = format!("{}=1", "a".repeat(100_000));
    let out = run(&["cell", "configs/multi-stop.toml", "--set", &name]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(err.contains("--set") && err.contains("(100000 characters)") && err.len() < 1000, "{err}");
}

/// A picture's format is checked before any work, naming the option and the
/// user's file (it was checked after the computation, naming a temporary file).
#[test]
fn picture_formats_are_checked_before_the_work() {
    let d = crate::util::scratch("picture-formats");
    let (txt, gif) = (d.join("s.txt"), d.join("x.gif"));
    let (txt, gif) = (txt.to_str().unwrap(), gif.to_str().unwrap());
    expect_error(&["cell", "configs/multi-stop.toml", "--section-png", txt], "--section-png");
    expect_error(&["cell", "configs/multi-stop.toml", "--portrait", gif], "--portrait");
    expect_error(&["continue", "configs/multi-stop.toml", "--axis", "omega=0.3:0.4:5", "--png", gif], "x.gif");
    expect_error(&["sweep", "configs/multi-stop.toml", "--axis", "omega=0.3:0.4:5", "--png", txt], "s.txt");
    let err =
        String::from_utf8_lossy(&run(&["cell", "configs/multi-stop.toml", "--section-png", txt]).stderr).to_string();
    assert!(!err.contains("partial"), "{err}");
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "nothing written");
    std::fs::remove_dir_all(&d).unwrap();
}

/// Issue 3: bad planes, shards, outputs and merges are refused before any work,
/// with nothing left under the final name.
#[test]
fn atlas_bad_input() {
    let dir = crate::util::scratch("atlas-bad");
    let out = dir.join("a.h5");
    let o = out.to_str().unwrap();
    let base = ["atlas", "configs/multi-stop.toml"];
    let with = |extra: &[&str]| -> Vec<String> { base.iter().chain(extra).map(|s| s.to_string()).collect() };
    let check = |args: Vec<String>, field: &str| {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        expect_error(&a, field);
        assert!(!out.exists());
    };
    check(with(&["--x", "omega=1:1:5", "--y", "delta=0.1:1:3", "-o", o]), "--x omega");
    check(with(&["--x", "omega=2:1:5", "--y", "delta=0.1:1:3", "-o", o]), "--x omega");
    check(with(&["--x", "omega=0.1:1:0", "--y", "delta=0.1:1:3", "-o", o]), "--x omega");
    // Issue 43: one value with two different ends dropped STOP without a word.
    check(
        with(&["--x", "omega=0.5:0.9:1", "--y", "delta=0.1:1:3", "-o", o]),
        "--x omega: a count of 1 is one value, but start 0.5 and stop 0.9 differ: give equal ends, or more values",
    );
    check(with(&["--x", "omega=0.1:1:5", "--y", "delta=0.1:1", "-o", o]), "--y");
    check(with(&["--x", "omega=0.1:1:5", "--y", "omega=0.1:1:3", "-o", o]), "--y");
    check(with(&["--x", "omgea=0.1:1:5", "--y", "delta=0.1:1:3", "-o", o]), "omgea");
    check(with(&["--x", "omega=0.1:1:5", "--y", "mu_m=0.5:1.5:3", "-o", o]), "mu_m");
    check(with(&["--x", "omega=0.1:3:100000", "--y", "delta=0:2:100000", "-o", o]), "GiB");
    check(with(&["--x", "omega=0.1:1:5", "--y", "delta=0.1:1:3", "--shard", "3/2", "-o", o]), "--shard");
    check(with(&["--x", "omega=0.1:1:5", "--y", "delta=0.1:1:3", "--sweep", "sideways", "-o", o]), "--sweep");
    check(with(&["--x", "omega=0.1:1:5", "--y", "delta=0.1:1:3", "--threads", "0", "-o", o]), "--threads");
    // The attractor search's own options without the search were ignored.
    let plane = ["--x", "omega=0.1:1:5", "--y", "delta=0.1:1:3", "-o", o];
    check(with(&[&plane[..], &["--seed", "5"]].concat()), "--seed: tunes the attractor search; give --attractors");
    check(with(&[&plane[..], &["--attractors-where", "hysteresis"]].concat()), "--attractors-where: tunes");
    expect_error(
        &[
            "atlas",
            "configs/multi-stop.toml",
            "--x",
            "omega=0.1:1:5",
            "--y",
            "delta=0.1:1:3",
            "-o",
            "/nonexistent-dir/a.h5",
        ],
        "/nonexistent-dir/a.h5",
    );
    expect_error(&["sweep", "configs/multi-stop.toml", "--axis", "omega=0.3:0.3:4"], "--axis omega");
    expect_error(
        &["sweep", "configs/multi-stop.toml", "--axis", "omega=0.3:0.4:4", "--direction", "left"],
        "--direction",
    );

    // Merging files of different grids or scenes.
    let part = |name: &str, args: &[&str]| -> String {
        let p = dir.join(name);
        let mut all =
            vec!["atlas", args[0], "--x", args[1], "--y", "delta=0.5:1:2", "--quiet", "-o", p.to_str().unwrap()];
        all.extend_from_slice(&args[2..]);
        let r = run(&all);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        p.to_str().unwrap().to_string()
    };
    let a = part("p1.h5", &["configs/multi-stop.toml", "omega=1:2:3", "--shard", "1/2"]);
    let b = part("p2.h5", &["configs/multi-stop.toml", "omega=1:2:4", "--shard", "2/2"]);
    let c = part("p3.h5", &["configs/symmetric-stops.toml", "omega=1:2:3", "--shard", "2/2"]);
    let merged = dir.join("m.h5");
    expect_error(&["merge", &a, &b, "-o", merged.to_str().unwrap()], "grid");
    expect_error(&["merge", &a, &c, "-o", merged.to_str().unwrap()], "scene");
    expect_error(&["merge", &a, "configs/multi-stop.toml", "-o", merged.to_str().unwrap()], "configs/multi-stop.toml");
    assert!(!merged.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

fn dry_friction_with(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(crate::util::config("dry-friction.toml")).unwrap();
    assert!(text.contains(from));
    text.replacen(from, to, 1)
}

/// Issue 4: negative kinetic friction, a static limit below it, friction of a
/// mass with itself.
#[test]
fn friction_bad_input() {
    expect_error(&["cell", "configs/dry-friction.toml", "--set", "fk=-0.01"], "fk");
    expect_error(&["cell", "configs/dry-friction.toml", "--set", "fs_ratio=0.5"], "fs_ratio");
    let p = scene_file("fk.toml", &dry_friction_with("kinetic = \"fk\"", "kinetic = \"-0.01\""));
    expect_error(&["cell", p.to_str().unwrap()], "friction[0].kinetic");
    let p = scene_file("fs.toml", &dry_friction_with("static = \"fs_ratio*fk\"", "static = \"0.5*fk\""));
    expect_error(&["cell", p.to_str().unwrap()], "friction[0].static");
    let p = scene_file(
        "self.toml",
        &dry_friction_with("masses = [\"M1\", \"M2\"]\nkinetic", "masses = [\"M1\", \"M1\"]\nkinetic"),
    );
    expect_error(&["cell", p.to_str().unwrap()], "friction[0].masses");
}

/// Issue 6: `orbit` and `continue` refuse bad periods, axes and non-periodic
/// cells without a period.
#[test]
fn orbit_and_continue_bad_input() {
    expect_error(&["orbit", "configs/single-stop.toml", "--n", "0"], "--n");
    expect_error(&["orbit", "configs/dry-friction.toml", "--set", "omega=2"], "--n");
    expect_error(&["continue", "configs/single-stop.toml", "--axis", "omega=1:2:1"], "--axis");
    expect_error(&["continue", "configs/single-stop.toml", "--axis", "nope=1:2:5"], "nope");
    expect_error(&["continue", "configs/single-stop.toml", "--axis", "omega=1:2"], "--axis");
}

/// Issue 5: `bench` rejects a grid, thread list or repeat count it cannot run.
#[test]
fn bench_bad_input() {
    expect_error(&["bench", "--grid", "1"], "--grid");
    expect_error(&["bench", "--threads", "0"], "--threads");
    expect_error(&["bench", "--threads", "two"], "--threads");
    expect_error(&["bench", "--repeat", "0"], "--repeat");
    expect_error(&["bench", "--trade", "--trade-repeat", "0"], "--trade-repeat");
    expect_error(&["bench", "--paper", "--trade-repeat", "0"], "--trade-repeat");
    expect_error(&["bench", "--paper", "--grid", "1"], "--grid");
    expect_error(&["bench", "--paper", "--trade"], "'--paper' cannot be used with '--trade'");
    // The dry-friction scene has no clearance delta: bench's plane is omega-delta.
    expect_error(&["bench", "--grid", "2", "--scene", "configs/dry-friction.toml"], "--scene");
}

/// Issue 20: the options of `curve` and `curves` and of bench's replay name
/// what is wrong (an audit of this round found these accepted or unnamed).
#[test]
fn bad_curve_and_replay_options() {
    let curve = |extra: &[&str]| {
        let mut args = vec!["curve", "configs/dry-friction.toml", "--kind", "pf", "--steps", "2"];
        args.extend_from_slice(extra);
        args.into_iter().map(str::to_string).collect::<Vec<_>>()
    };
    let cases: [(&[&str], &str); 8] = [
        (&["--start", "omega=6.845,fk=0.01", "--free", "omega,omega", "--to", "0.03"], "--free"),
        (&["--start", "omega=6.845,fk=0.01", "--free", "omega,fk,zeta", "--to", "0.03"], "--free"),
        (&["--start", "omega=6.845,fk=0.01,zeta=0.5", "--free", "omega,fk", "--to", "0.03"], "--start"),
        (&["--start", "omega=6.845,fk=-1", "--free", "omega,fk", "--to", "0.03"], "parameters.fk"),
        (&["--start", "omega=6.845,fk=0.01", "--free", "omega,fk", "--to=-0.01"], "--to"),
        (
            &["--start", "omega=6.845,fk=0.01", "--free", "omega,fk", "--to", "0.03", "--bounds", "omega=7:8"],
            "--bounds",
        ),
        (&["--start", "omega=6.845,fk=0.01", "--free", "omega,fk", "--to", "0.03", "--window", "-0.1"], "--window"),
        (&["--start", "omega=6.845,fk=0.01", "--free", "omega,fk", "--to", "0.03", "--steps", "-1"], "--steps"),
    ];
    for (extra, field) in cases {
        let args = curve(extra);
        expect_error(&args.iter().map(String::as_str).collect::<Vec<_>>(), field);
    }
    let d = crate::util::scratch("bad-curves");
    let (a, c) = (d.join("a.h5"), d.join("c.h5"));
    crate::util::ok(&[
        "atlas",
        "configs/multi-stop.toml",
        "--x",
        "omega=0.6:1.6:6",
        "--y",
        "delta=1.2:2:3",
        "--quiet",
        "-o",
        a.to_str().unwrap(),
    ]);
    expect_error(&["curves", a.to_str().unwrap(), "--max", "0", "-o", c.to_str().unwrap()], "--max");
    expect_error(&["curves", d.to_str().unwrap(), "-o", c.to_str().unwrap()], "not a file");
    crate::util::ok(&crate::util::pitchfork("0.02", "1", &["-o", c.to_str().unwrap()]));
    expect_error(&["curves", c.to_str().unwrap(), "-o", d.join("x.h5").to_str().unwrap()], "not an atlas");
}

/// A cell taken from a file made with another scene says so, not only that
/// the file's axis is an unknown parameter of this scene.
#[test]
fn a_cell_of_another_scenes_file_says_so() {
    let d = crate::util::scratch("another-scene");
    let a = d.join("a.h5");
    let a = a.to_str().unwrap();
    crate::util::ok(&[
        "atlas",
        "configs/multi-stop.toml",
        "--x",
        "omega=0.5:1:2",
        "--y",
        "delta=0.5:1:2",
        "--quiet",
        "-o",
        a,
    ]);
    let args = ["cell", "configs/single-stop.toml", "--from", a, "--at", "omega=1,delta=1"];
    expect_error(&args, "--from");
    expect_error(&args, "do not fit this scene (made from another?): parameters.delta: unknown parameter 'delta'");
    // Issue 42, R15: a parameter given twice was read once, the second ignored.
    let twice = ["cell", "configs/multi-stop.toml", "--from", a, "--at", "omega=0.5,delta=0.6,omega=0.3"];
    expect_error(&twice, "--at omega: given twice (0.5 and 0.3)");
    std::fs::remove_dir_all(&d).unwrap();
}

/// Issue 42, R12: a scene "file" that never ends (`/dev/zero`) was read until
/// the memory ran out; a scene or study file is read up to 16 MiB.
#[test]
fn an_endless_scene_file_is_refused() {
    if std::path::Path::new("/dev/zero").exists() {
        expect_error(&["cell", "/dev/zero"], "cannot read scene file /dev/zero: longer than 16777216 bytes");
        expect_error(&["study", "/dev/zero", "-o", "/tmp/never"], "longer than 16777216 bytes");
    }
}

/// Issue 43: `render --sweep hysteresis` of a file without both up and down
/// drew its one sweep without a word.
#[test]
fn hysteresis_needs_up_and_down() {
    let d = crate::util::scratch("hysteresis-needs");
    let f = d.join("up.h5");
    let f = f.to_str().unwrap();
    crate::util::ok(&["sweep", "configs/multi-stop.toml", "--axis", "omega=0.2:0.5:4", "--quiet", "-o", f]);
    let png = d.join("h.png");
    expect_error(
        &["render", f, "--sweep", "hysteresis", "-o", png.to_str().unwrap()],
        "--sweep hysteresis: needs up and down sweeps; the file has up",
    );
    assert!(!png.exists());
}

/// Issue 61: a named pipe given as the scene of `cell` or `sweep` blocked in
/// `open()` for ever; it is refused in one line before it is opened, as a
/// folder is. So is a pipe given as the file `render` reads, or as a
/// picture or trace to write (the sixth audit: those blocked too, leaving
/// a `.partial` file). Each run is given 30 s before the test calls it a hang.
#[test]
fn a_scene_that_is_a_pipe_or_a_folder_is_refused() {
    let d = crate::util::scratch("scene-pipe");
    let fifo = d.join("scene.toml");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let fifo = fifo.to_str().unwrap();
    let single = "configs/single-stop.toml";
    let png = d.join("out.png");
    let png = png.to_str().unwrap();
    let cases = [
        (vec!["cell", fifo], "not a regular file (a named pipe)"),
        (vec!["sweep", fifo, "--axis", "omega=0.2:0.4:3"], "not a regular file (a named pipe)"),
        (vec!["orbit", fifo], "not a regular file (a named pipe)"),
        (vec!["render", fifo, "-o", png], "not a file (an atlas is one HDF5 file)"),
        (vec!["cell", single, "--trace", fifo], "--trace: "),
        (vec!["cell", single, "--portrait", fifo], "--portrait: "),
        (vec!["cell", single, "--section-png", fifo], "--section-png: "),
        (vec!["sweep", single, "--axis", "omega=1:2:3", "--png", fifo], "--png: "),
    ];
    for (args, said) in cases {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_vibroatlas"))
            .args(&args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let until = std::time::Instant::now() + std::time::Duration::from_secs(30);
        while child.try_wait().unwrap().is_none() {
            if std::time::Instant::now() > until {
                child.kill().unwrap();
                panic!("{args:?} hangs on a named pipe");
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(said), "{args:?}: {err}");
    }
    // The pipe is the only thing in the folder: no partial file was left.
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
    expect_error(&["cell", d.to_str().unwrap()], "not a regular file (a folder)");
    std::fs::remove_dir_all(&d).unwrap();
}

/// Issue 61, P1: a large forcing phase was rounded at every event (τ =
/// 62831853073.36665 gave 9-9-0, τ = 1.44e17 1-S-0). τ is reduced mod 2π
/// exactly when the scene is evaluated: the cell is the one of the reduced
/// angle (its residue by Python's decimal with 100 digits of π), bit for bit
/// in everything but the parameter given; 1-1-0 as an independent
/// integrator found.
#[test]
fn a_large_phase_is_the_same_angle() {
    let base = ["configs/single-stop.toml", "--set", "zeta=0.05", "--set", "omega=2.0", "--set"];
    for (large, residue) in
        [("tau=62831853073.36665", "tau=1.5707886731299447"), ("tau=1.44e17", "tau=2.2036341134760633")]
    {
        let mut a = crate::util::cell_json(&[&base[..], &[large]].concat());
        let mut b = crate::util::cell_json(&[&base[..], &[residue]].concat());
        assert_eq!(a["labels"]["M"], "1-1-0", "{large}");
        for v in [&mut a, &mut b] {
            v["parameters"]["tau"] = serde_json::Value::Null;
        }
        assert_eq!(a, b, "{large} against {residue}");
    }
    expect_error(&["cell", "configs/single-stop.toml", "--set", "tau=1e400"], "tau");
}
