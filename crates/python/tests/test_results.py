"""cell, sweep, attractors and curve return exactly what the CLI prints with
--json for the same arguments (dict equality: every key, every float bit for
bit, as JSON round-trips them)."""
import json
import pytest

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")
import vibroatlas as va

from conftest import CONFIGS, DRY, MULTI, assert_trees_equal, axis, cli, cli_json, open_tree, sets


@pytest.mark.parametrize("params,kw,args", [
    ({}, {}, []),                                                     # the scene's defaults: M1 1-4-4
    ({"omega": 0.295}, {}, []),                                       # chattering
    ({"omega": 0.2, "delta": 0.6}, {}, []),                           # complete chattering
    ({"omega": 0.9, "delta": 0.3}, {"preset": "fast"}, ["--preset", "fast"]),
    ({"omega": 0.33}, {"preset": "precise", "accuracy": {"max_periods": 3000, "n_max": 40}},
     ["--preset", "precise", "--accuracy", "max_periods=3000.0", "--accuracy", "n_max=40.0"]),
    ({"omega": 0.5, "delta": 0.5}, {"integrator": "rk4", "preset": "fast"}, ["--integrator", "rk4", "--preset", "fast"]),
])
def test_cell_equals_cli(params, kw, args):
    r = va.cell(str(MULTI), **kw, **params)
    assert r == cli_json("cell", MULTI, *sets(**params), *args)


@pytest.mark.parametrize("params", [
    {"omega": 2.0},                      # drive-side contact: 1-0-S
    {"omega": 1.0, "f2": 0.05},          # single-sided rattle, with a second harmonic
    {"omega": 0.5},                      # the mean load and the backlash's soft stops
])
def test_gear_backlash_cell_equals_cli(params):
    """Issue 41: soft stops, a load and harmonics give the CLI's answer in Python too."""
    gear = CONFIGS / "gear-backlash.toml"
    r = va.cell(gear, **params)
    assert r == cli_json("cell", gear, *sets(**params))
    assert r["class"] == "periodic"


def test_cell_readme_example():
    r = va.cell(MULTI, omega=0.33, delta=0.6)  # a pathlib.Path
    assert r["labels"]["M1"] == "1-4-4"
    assert r["class"] == "periodic" and r["n"] == 1


def test_cell_scene_as_text_and_dict():
    text = MULTI.read_text()
    ref = cli_json("cell", MULTI, *sets(omega=0.295, delta=0.6))
    assert va.cell(text, omega=0.295, delta=0.6) == ref
    assert va.cell(tomllib.loads(text), omega=0.295, delta=0.6) == ref
    # a varied scene without a file: R as a dict entry, the same as --set R=0.7
    d = tomllib.loads(text)
    d["parameters"]["R"]["value"] = 0.7
    assert va.cell(d, omega=0.295) == cli_json("cell", MULTI, *sets(omega=0.295, R=0.7))


def test_params_order_and_params_dict():
    # --set in the order given; `params` for names that would clash with keywords
    ref = cli_json("cell", MULTI, *sets(delta=0.5, omega=0.4))
    assert va.cell(MULTI, delta=0.5, omega=0.4) == ref
    assert va.cell(MULTI, params={"delta": 0.5}, omega=0.4) == ref


@pytest.mark.parametrize("scene,ax,kw,params", [
    (DRY, ("omega", 8, 4.5, 41), {"direction": "down-up"}, {"fk": 0.01}),     # the issue's sweep, coarser
    (MULTI, ("omega", 0.2, 0.4, 31), {"direction": "both", "threads": 2}, {}),
    (MULTI, ("omega", 0.4, 0.2, 21), {"section_cap": 4, "preset": "fast"}, {"delta": 0.5}),
])
def test_sweep_equals_cli(scene, ax, kw, params):
    r = va.sweep(str(scene), axis=ax, progress=False, **kw, **params)
    args = ["--axis", axis(ax)]
    for k, v in kw.items():
        args += [f"--{k.replace('_', '-')}", str(v)]
    assert r == cli_json("sweep", scene, *sets(**params), *args)


@pytest.mark.parametrize("kw,args", [
    ({"samples": 64, "seed": 1}, ["--samples", "64", "--seed", "1"]),
    ({"samples": 24, "seed": 7, "box": (1.5, 1.0), "threads": 2},
     ["--samples", "24", "--seed", "7", "--box", "1.5,1.0", "--threads", "2"]),
])
def test_attractors_equals_cli(kw, args):
    r = va.attractors(str(MULTI), omega=0.3149, delta=0.7, progress=False, **kw)
    assert r == cli_json("attractors", MULTI, *sets(omega=0.3149, delta=0.7), *args)
    assert len(r["attractors"]) >= 1


def test_cell_from_a_state_equals_cli():
    """state= starts the cell where `cell --state` does; a state of the wrong
    length is refused by the engine, naming it."""
    state = [0.3, -0.1, 0.5, 0.0]
    r = va.cell(MULTI, state=state, omega=0.33)
    assert r == cli_json("cell", MULTI, *sets(omega=0.33), "--state", ",".join(map(str, state)))
    assert r != va.cell(MULTI, omega=0.33)
    with pytest.raises(ValueError, match="state"):
        va.cell(MULTI, state=[0.1, 0.2], omega=0.33)
    with pytest.raises(TypeError, match="state"):
        va.cell(MULTI, state="0.1,0.2", omega=0.33)


def test_curve_bounds_equal_cli():
    """bounds=(lo, hi) keeps A where `curve --bounds A=LO:HI` does."""
    args = ["--kind", "pf", "--start", "omega=6.845,fk=0.01", "--free", "omega,fk", "--to", "0.1", "--steps", "8"]
    ref = cli_json("curve", DRY, *args, "--bounds", "omega=6.84:6.86")
    r = va.curve(DRY, kind="pf", start={"omega": 6.845, "fk": 0.01}, free=("omega", "fk"), to=0.1, steps=8,
                 bounds=(6.84, 6.86))
    assert r == ref
    assert all(6.84 <= p["omega"] <= 6.86 for p in r["points"]), r["points"]
    with pytest.raises(ValueError, match="bounds"):
        va.curve(DRY, kind="pf", start={"omega": 6.845, "fk": 0.01}, free=("omega", "fk"), bounds=(1.0,))


def test_curve_equals_cli(tmp_path):
    args = ["--kind", "pf", "--start", "omega=6.845,fk=0.01", "--free", "omega,fk", "--to", "0.1", "--steps", "8"]
    ref = cli_json("curve", DRY, *args)
    r = va.curve(str(DRY), kind="pf", start={"omega": 6.845, "fk": 0.01}, free=("omega", "fk"), to=0.1, steps=8)
    assert r == ref
    assert r["kind"] == "PF"
    # with a file: the same JSON, and the same file as the CLI's
    out, ref_out = tmp_path / "c.h5", tmp_path / "ref.h5"
    r2 = va.curve(DRY, kind="pf", start=[("omega", 6.845), ("fk", 0.01)], free=["omega", "fk"], to=0.1,
                  steps=8, window=0.05, output=out)
    assert r2 == ref
    cli("curve", DRY, *args, "--window", "0.05", "-o", ref_out)
    assert_trees_equal(open_tree(out), open_tree(ref_out))


def test_cell_result_is_plain_json():
    r = va.cell(MULTI)
    assert json.loads(json.dumps(r)) == r


def test_sweep_writes_its_file_and_returns_its_sections(tmp_path):
    """Issue 43: va.sweep(output=) writes the file `sweep -o` writes, and its
    points carry the period sections `sweep --png` draws, as `--json` does."""
    import h5py

    mine = tmp_path / "py.h5"
    s = va.sweep(MULTI, axis=("omega", 0.28, 0.32, 5), direction="both", output=mine, progress=False)
    theirs = tmp_path / "cli.h5"
    p = cli("sweep", MULTI, "--axis", "omega=0.28:0.32:5", "--direction", "both", "--quiet", "--json",
            "-o", theirs)
    j = json.loads(p.stdout)
    assert [q["period_section"] for q in s["up"]] == [q["period_section"] for q in j["up"]]
    assert all(len(q["period_section"]) >= 1 and len(q["final_state"]) == 4 for q in s["down"])
    with h5py.File(mine) as a, h5py.File(theirs) as b:
        for name in ("up/class", "down/final_state", "up/sections/period/values"):
            assert (a[name][()] == b[name][()]).all(), name
