"""Bad inputs raise Python exceptions with the CLI's one-line messages, the
options named as keyword arguments (the CLI's `--set nosuch` is `nosuch`):
SceneError (a ValueError) for scenes, ValueError for arguments, OSError for
files; never a crash."""
import pytest

try:
    tomllib = pytest.importorskip("tomllib")
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")
import vibroatlas as va

from conftest import DRY, MULTI, cli_error

BROKEN = "name = \"broken\"\n[parameters\nomega = 1\n"


def one_line(e):
    s = str(e.value)
    assert s and "\n" not in s, repr(s)
    return s


def test_scene_error_is_a_value_error():
    assert issubclass(va.SceneError, ValueError)


def test_broken_scene_text():
    with pytest.raises(va.SceneError) as e:
        va.cell(BROKEN)
    assert "TOML parse error" in one_line(e)


def test_scene_missing_key(tmp_path):
    d = tomllib.loads(MULTI.read_text())
    del d["forcing"]
    with pytest.raises(va.SceneError) as e:
        va.cell(d)
    assert "forcing" in one_line(e)
    # the same scene as a file: the CLI's message
    path = tmp_path / "no-forcing.toml"
    path.write_text(MULTI.read_text().replace('[forcing]\nomega = "omega"\nphase = "tau"\n', ""))
    with pytest.raises(va.SceneError) as e:
        va.cell(str(path))
    assert one_line(e) == cli_error("cell", path)


def test_unknown_parameter():
    with pytest.raises(ValueError) as e:
        va.cell(str(MULTI), nosuch=1.0)
    assert not isinstance(e.value, va.SceneError)
    assert one_line(e) == cli_error("cell", MULTI, "--set", "nosuch=1.0").replace("--set nosuch: ", "nosuch: ")
    assert one_line(e).startswith("nosuch: unknown parameter 'nosuch'")


@pytest.mark.parametrize("call", [
    lambda: va.cell(MULTI, preset="ultra"),
    lambda: va.cell(MULTI, integrator="euler"),
    lambda: va.cell(MULTI, accuracy={"nosuch": 3}),
    lambda: va.cell(MULTI, accuracy={"max_periods": -3}),
    lambda: va.sweep(MULTI, axis=("omega", 0.2, 0.4, 11), direction="sideways", progress=False),
    lambda: va.atlas(MULTI, x=("omega", 0.1, 1.0, 0), y=("delta", 0.1, 1.0, 3), progress=False),
    lambda: va.cell(MULTI, mu_k=1.5),
], ids=["preset", "integrator", "knob", "knob-value", "direction", "count", "range"])
def test_bad_option_value(call):
    with pytest.raises(ValueError) as e:
        call()
    one_line(e)


def test_a_mistyped_name_says_which_was_meant():
    """A named option reads through the library's table of names, as the CLI's does."""
    with pytest.raises(ValueError) as e:
        va.cell(MULTI, preset="precize")
    assert one_line(e) == "preset: expected fast, standard or precise, got 'precize' (did you mean 'precise'?)"
    with pytest.raises(ValueError) as e:
        va.sweep(MULTI, axis=("omega", 0.2, 0.4, 11), direction="downup", progress=False)
    assert one_line(e).endswith("got 'downup' (did you mean 'down-up'?)")
    with pytest.raises(ValueError) as e:
        va.cell(MULTI, preset="zebra")
    assert "did you mean" not in one_line(e)


def test_bad_option_value_message():
    with pytest.raises(ValueError) as e:
        va.atlas(MULTI, x=("omega", 0.1, 1.0, 0), y=("delta", 0.1, 1.0, 3), progress=False)
    assert one_line(e) == cli_error("atlas", MULTI, "--x", "omega=0.1:1.0:0", "--y", "delta=0.1:1.0:3",
                                     "-o", "/tmp/vibroatlas-never-written.h5").replace("--x omega: ", "x omega: ")
    assert one_line(e).startswith("x omega: the count must be")


def test_options_are_named_as_keywords(tmp_path):
    """Options named in a message are Python's keyword arguments, never the CLI's flags."""
    grid = dict(x=("omega", 0.1, 1.0, 3), y=("delta", 0.1, 1.0, 2), progress=False)
    cases = [
        (lambda: va.atlas(MULTI, omega=0.3, output=str(tmp_path / "a.h5"), **grid),
         "omega: omega is also an axis of the run, which would override it; remove the params"),
        (lambda: va.atlas(MULTI, threads=0, output=str(tmp_path / "a.h5"), **grid), "threads: must be >= 1"),
        (lambda: va.atlas(MULTI, section_cap=200000, output=str(tmp_path / "a.h5"), **grid),
         "section_cap: at most 100000, got 200000"),
        (lambda: va.atlas(MULTI, attractors=2, attractors_where="hysteresis", sweep="up",
                          output=str(tmp_path / "a.h5"), **grid),
         "attractors_where='hysteresis': needs sweep='both'"),
        (lambda: va.curve(DRY, kind="pf", start={"omega": 6.845, "fk": 0.01},
                          free=("omega", "fk"), to=0.1, n=0), "n: expected a period between 1 and 1000, got 0"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError) as e:
            call()
        assert one_line(e) == message
        assert "--" not in one_line(e)
    # A journal of another run: resume=True, not --resume.
    out = tmp_path / "j.h5"
    (tmp_path / ".j.h5.journal").write_text('{"fingerprint":"x"}\n')
    with pytest.raises(ValueError) as e:
        va.atlas(MULTI, output=str(out), resume=True, **grid)
    assert one_line(e).endswith("the journal belongs to a run with other settings; remove it or run without resume=True")


def test_missing_scene_file(tmp_path):
    missing = tmp_path / "nonexistent.toml"
    with pytest.raises(OSError) as e:
        va.cell(str(missing))
    assert one_line(e) == cli_error("cell", missing)


def test_wrong_types():
    with pytest.raises(TypeError):
        va.cell(MULTI, omega="fast")
    with pytest.raises(TypeError):
        va.atlas(MULTI, x="omega=0.1:1:3", y=("delta", 0.1, 1.0, 3))
    with pytest.raises(TypeError):
        va.cell(42)


def test_a_dict_scene_names_the_field_it_cannot_hold():
    """A value TOML cannot hold is refused naming its field; numpy numbers are numbers."""
    import copy

    import numpy as np
    tomllib = pytest.importorskip("tomllib")

    with open(MULTI, "rb") as f:
        scene = tomllib.load(f)
    for bad, why in ((float("nan"), "not a finite number"), (None, ".*not NoneType")):
        s = copy.deepcopy(scene)
        s["masses"][0]["mass"] = bad
        with pytest.raises(va.SceneError, match=r"^masses\[0\]\.mass: " + why):
            va.cell(s)
    s = copy.deepcopy(scene)
    s["masses"][0]["mass"] = np.float64(s["masses"][0]["mass"])
    assert va.cell(s)["labels"] == va.cell(MULTI)["labels"]
