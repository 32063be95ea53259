"""Issue 42: what a reader or a caller gets wrong is said, never a wrong value
or a run that goes on after the call raised: label codes outside the table
(R8), a progress bar that cannot draw (R13), and the messages of R14."""
import os
import sys
import time

import numpy as np
import pytest
import vibroatlas as va

from conftest import MULTI

SMALL = dict(x=("omega", 0.13, 0.53, 5), y=("delta", 0.4, 0.8, 3), progress=False)


def test_a_label_code_outside_the_table_is_refused():
    up = va.atlas(MULTI, sweep="up", **SMALL)["up"].to_dataset()
    assert va.labels(up, "M1").values[0, 0]  # decodes as written
    for bad in (9999, -5):
        ds = up.copy(deep=True)
        code = np.asarray(ds["label_code_M1"].values).copy()
        code[1, 2] = bad
        ds["label_code_M1"].values = code
        with pytest.raises(ValueError) as e:
            va.labels(ds, "M1")
        assert f"code {bad} at" in str(e.value) and "outside the label table" in str(e.value), e.value


def test_label_codes_that_are_not_whole_numbers_are_refused():
    up = va.atlas(MULTI, sweep="up", **SMALL)["up"].to_dataset()
    ds = up.assign(label_code_M1=up.label_code_M1.astype(float) / 3)
    with pytest.raises(ValueError) as e:
        va.labels(ds, "M1")
    assert "not whole numbers" in str(e.value)


def test_a_bar_that_cannot_draw_cancels_the_run(tmp_path, monkeypatch):
    out = tmp_path / "a.h5"
    closed = open(os.devnull, "w")  # noqa: SIM115 (closed at once: a stream that takes no line)
    closed.close()
    monkeypatch.setattr(sys, "stderr", closed)
    with pytest.raises(Exception):
        va.atlas(MULTI, x=("omega", 0.1, 3.05, 30), y=("delta", 0.05, 2, 20), sweep="both", threads=1,
                 output=str(out), progress=True)
    monkeypatch.undo()
    # The cancelled run stops at its next cell and writes nothing, then or later.
    time.sleep(3)
    assert not out.exists()
    assert not [p for p in os.listdir(tmp_path) if p != "a.h5" and not p.startswith(".")], os.listdir(tmp_path)


def test_numbers_and_text_beyond_what_a_scene_holds_are_named():
    up = va.atlas(MULTI, sweep="up", **SMALL)["up"].to_dataset()
    wide = np.asarray(up["max_abs_x_M1"].values).copy()
    wide[0, 0], wide[0, 1] = -1e308, 1e308
    with pytest.raises(ValueError) as e:
        va.plot.quantity(up.assign(max_abs_x_M1=(up.max_abs_x_M1.dims, wide, up.max_abs_x_M1.attrs)), "max_abs_x_M1")
    assert "max_abs_x_M1: its values, -1e+308 to 1e+308, span more than a float holds" in str(e.value), e.value
    with open(MULTI) as f:
        text = f.read()
    with pytest.raises(va.SceneError) as e:
        va.cell(text + "# \ud800\n")
    assert "scene: not text that UTF-8 can hold" in str(e.value), e.value
    import tomllib
    with open(MULTI, "rb") as f:
        table = tomllib.load(f)
    table["masses"][0]["mass"] = 10**400
    with pytest.raises(va.SceneError) as e:
        va.cell(table)
    assert "masses[0].mass: not a finite number, got an integer of 401 digits" in str(e.value), e.value
    table["masses"][0]["mass"] = 2**63  # a float holds it: a mass, far too heavy for the scene's range
    with pytest.raises(va.SceneError) as e:
        va.cell(table)
    assert "u64" not in str(e.value), e.value


def test_an_output_path_may_be_bytes(tmp_path):
    out = os.fsencode(tmp_path / "b.h5")
    va.atlas(MULTI, sweep="up", output=out, **SMALL)
    assert os.path.isfile(out)


def test_a_damaged_file_a_nul_in_a_path_and_a_start_that_is_no_pair_are_named(tmp_path):
    whole = tmp_path / "a.h5"
    va.atlas(MULTI, sweep="up", output=whole, **SMALL)
    cut = tmp_path / "cut.h5"
    cut.write_bytes(whole.read_bytes()[:20000])
    with pytest.raises(OSError) as e:
        va.explore(cut)  # the explorer says why, not only which file
    assert str(e.value).startswith(str(cut)) and "truncated" in str(e.value), e.value
    for call in (lambda p: va.atlas(MULTI, sweep="up", output=p, **SMALL), va.open, va.explore):
        with pytest.raises(ValueError) as e:
            call(str(tmp_path / "a\0b.h5"))
        assert "a path cannot hold a NUL character" in str(e.value) and ".lock" not in str(e.value), e.value
    assert sorted(os.listdir(tmp_path)) == ["a.h5", "cut.h5"]
    with pytest.raises(TypeError) as e:
        va.curve(MULTI, "pd", 5, ("omega", "delta"))
    assert str(e.value).startswith("start: expected two parameters"), e.value


def test_without_standard_error_the_run_has_no_bar(monkeypatch):
    # pythonw, or a process whose sys.stderr is None: the run goes on, unseen
    monkeypatch.setattr(sys, "stderr", None)
    tree = va.atlas(MULTI, x=("omega", 0.1, 3.05, 30), y=("delta", 0.05, 2, 20), sweep="up", threads=1)
    monkeypatch.undo()
    assert tree["up"]["class"].shape == (20, 30)


def test_what_is_no_file_or_no_quantity_is_refused(tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    with pytest.raises(OSError) as e:
        va.open(fifo)  # a pipe would block the reader for ever
    assert "not a regular file" in str(e.value)
    up = va.atlas(MULTI, sweep="up", **SMALL)["up"].to_dataset()
    for name in ("class", "label_code_M1"):
        with pytest.raises(ValueError) as e:
            va.plot.quantity(up, name)
        assert f"{name}: not a quantity of this group (" in str(e.value) and "max_abs_x_M1" in str(e.value), e.value
    with pytest.raises(ValueError) as e:
        va.sweep(MULTI, ("omega", 0.5, 1, 3), threads=10**30)
    assert "threads: must be at most" in str(e.value)
    with pytest.raises((ValueError, OSError)) as e:
        va.atlas(MULTI, output=str(tmp_path / ("k" * 253 + ".h5")), **SMALL)
    assert "its name is 256 bytes" in str(e.value)


def test_label_codes_are_checked_before_a_map_is_drawn():
    up = va.atlas(MULTI, sweep="up", **SMALL)["up"].to_dataset()
    for bad in (2**40, -5):
        code = np.asarray(up["label_code_M1"].values).astype(np.int64)
        code[1, 2] = bad
        with pytest.raises(ValueError) as e:
            va.plot.map(up.assign(label_code_M1=(up.label_code_M1.dims, code)), "M1")
        assert f"code {bad} at" in str(e.value) and "outside the label table" in str(e.value), e.value
    with pytest.raises(ValueError) as e:
        va.atlas(MULTI, resume=True, **SMALL)
    assert "resume: " in str(e.value)
    with pytest.raises(TypeError) as e:
        va.atlas(MULTI, output=3.5, **SMALL)
    assert "output: expected a path" in str(e.value)
    with pytest.raises(va.SceneError) as e:
        va.cell("# " + "x" * (16 << 20) + "\n")
    assert "more than a scene may be" in str(e.value) and len(str(e.value)) < 300


def test_a_scene_dict_that_contains_itself_is_a_scene_error():
    d = {"name": "loop"}
    d["self"] = d
    with pytest.raises(va.SceneError) as e:
        va.cell(d)
    assert "contains itself" in str(e.value)
    deep = {}
    node = deep
    for _ in range(5000):
        node["x"] = {}
        node = node["x"]
    with pytest.raises(va.SceneError):
        va.cell(deep)


def test_what_is_not_a_group_or_a_file_is_named():
    with pytest.raises(TypeError) as e:
        va.labels(None)
    assert "got NoneType" in str(e.value)
    with pytest.raises(TypeError):
        va.plot.map(None)
    with pytest.raises(IsADirectoryError) as e:
        va.open(os.path.dirname(__file__))
    assert "\n" not in str(e.value)
    with pytest.raises(FileNotFoundError):
        va.open("/nonexistent/a.h5")


def test_a_sweep_axis_that_is_not_finite_shows_it_as_given():
    with pytest.raises(ValueError) as e:
        va.sweep(MULTI, axis=("omega", float("nan"), 0.4, 5))
    assert str(e.value) == "axis omega: start and stop must be finite, got NaN and 0.4"


def test_what_a_new_user_mistypes_is_named():
    """Issue 43: a misspelt keyword, a negative count, an unknown mass, a
    progress that is not a bool, and a dict scene's errors."""
    with pytest.raises(TypeError) as e:
        va.cell(MULTI, presett="fast")
    assert "did you mean 'preset'" in str(e.value)
    # Every keyword of the functions is matched, a new one as well (read from their signatures).
    with pytest.raises(TypeError) as e:
        va.atlas(MULTI, ("omega", 0.3, 0.4, 2), ("delta", 0.5, 0.6, 2), quantitis="none")
    assert "did you mean 'quantities'" in str(e.value)
    with pytest.raises(ValueError) as e:
        va.sweep(MULTI, axis=("omega", 0.3, 0.4, 3), threads=-2, progress=False)
    assert str(e.value) == "threads: must be >= 0, got -2"
    with pytest.raises(TypeError) as e:
        va.cell(MULTI, progress="yes")
    assert "progress: expected True or False" in str(e.value)
    up = va.atlas(MULTI, sweep="up", **SMALL)["up"]
    with pytest.raises(ValueError) as e:
        va.plot.map(up, mass="M9")
    assert "this group labels M1, M2" in str(e.value)
    with pytest.raises(va.SceneError) as e:
        va.cell({"name": "x", "parameters": {"omega": {"value": 1.0}}})
    assert str(e.value).startswith("scene: ") and "scene text" not in str(e.value), e.value


def test_mappings_masses_and_keywords_a_function_lacks_are_read_or_named(tmp_path):
    import types

    from conftest import CONFIGS

    tomllib = pytest.importorskip("tomllib")
    # Any Mapping is a scene or an accuracy (the hints say Mapping).
    table = tomllib.loads((CONFIGS / "single-stop.toml").read_text())
    frozen = types.MappingProxyType(table)
    got = va.cell(frozen, accuracy=types.MappingProxyType({"n_max": 40}), omega=2.5)
    assert got["labels"] == va.cell(table, accuracy={"n_max": 40}, omega=2.5)["labels"]
    up = va.atlas(MULTI, sweep="up", **SMALL)["up"].to_dataset()
    for mass, error in (("", ValueError), (0, TypeError)):
        with pytest.raises(error, match="mass|label_code_"):
            va.labels(up, mass)
    # A keyword of the package that this function lacks is not a misspelling of itself.
    path = tmp_path / "a.h5"
    va.atlas(MULTI, sweep="up", output=path, **SMALL)
    with pytest.raises(TypeError, match="'preset': this function does not take it"):
        va.zoom(path, ("omega", 0.2, 0.4, 3), ("delta", 0.5, 0.7, 3), preset="fast", progress=False)
    # The attractor search's options without the search were ignored.
    for keyword in (dict(seed=5), dict(attractors_where="all")):
        with pytest.raises(ValueError, match="tunes the attractor search; give attractors"):
            va.atlas(MULTI, **SMALL, **keyword)
