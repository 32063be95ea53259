"""Bad inputs raise Python exceptions with the CLI's one-line messages:
SceneError (a ValueError) for scenes, ValueError for arguments, OSError for
files; never a crash."""
import pytest

try:
    tomllib = pytest.importorskip("tomllib")
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")
import vibroatlas as va

from conftest import MULTI, cli_error

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
    assert one_line(e) == cli_error("cell", MULTI, "--set", "nosuch=1.0")


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


def test_bad_option_value_message():
    with pytest.raises(ValueError) as e:
        va.atlas(MULTI, x=("omega", 0.1, 1.0, 0), y=("delta", 0.1, 1.0, 3), progress=False)
    assert one_line(e) == cli_error("atlas", MULTI, "--x", "omega=0.1:1.0:0", "--y", "delta=0.1:1.0:3",
                                     "-o", "/tmp/vibroatlas-never-written.h5")


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
