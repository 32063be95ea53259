"""va.atlas returns the file's DataTree: its groups, data variables,
coordinates and attributes equal those of xr.open_datatree on the CLI's file
of the same run (bit for bit); va.open and va.labels."""
import os
import tempfile

import numpy as np
import pytest
import xarray as xr

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")
import vibroatlas as va

from conftest import MULTI, DRY, VOLATILE, assert_trees_equal, axis, cli, open_tree, sets

X = ("omega", 0.1, 3.05, 12)
Y = ("delta", 0.05, 2.0, 8)


def cli_atlas(path, scene, x, y, params=None, args=()):
    cli("atlas", scene, "--x", axis(x), "--y", axis(y), *sets(**(params or {})), *args, "--quiet", "-o", path)
    return open_tree(path)


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    """The README's small atlas (both sweeps) by the CLI and by va.atlas."""
    d = tmp_path_factory.mktemp("both")
    x, y = ("omega", 0.13, 0.53, 5), ("delta", 0.4, 0.8, 3)
    ref = cli_atlas(d / "ref.h5", MULTI, x, y, args=["--sweep", "both", "--threads", "2"])
    t = va.atlas(str(MULTI), x=x, y=y, sweep="both", threads=2, progress=False)
    return t, ref, d / "ref.h5"


def test_atlas_both_equals_cli(both):
    t, ref, _ = both
    assert isinstance(t, xr.DataTree)
    assert {"up", "down"} <= set(t.children)
    assert_trees_equal(t, ref)


@pytest.mark.parametrize("kw,args,params", [
    ({"sweep": "fresh"}, [], {}),
    ({"sweep": "up", "along": "y", "threads": 1, "section_cap": 3},
     ["--sweep", "up", "--along", "y", "--threads", "1", "--section-cap", "3"], {}),
    ({"sweep": "down", "preset": "fast", "accuracy": {"max_periods": 500}},
     ["--sweep", "down", "--preset", "fast", "--accuracy", "max_periods=500.0"], {"mu_k": 0.3}),
    ({"sweep": "fresh", "attractors": 4, "seed": 3}, ["--attractors", "4", "--seed", "3"], {}),
])
def test_atlas_equals_cli(tmp_path, kw, args, params):
    ref = cli_atlas(tmp_path / "ref.h5", MULTI, X, Y, params, args)
    t = va.atlas(MULTI, x=X, y=Y, progress=False, **kw, **params)
    assert_trees_equal(t, ref)
    if "attractors" in kw:
        assert "attractors" in t.children


def test_atlas_output_is_kept(tmp_path):
    out = tmp_path / "a.h5"
    t = va.atlas(MULTI, x=X, y=Y, sweep="both", output=out, progress=False)
    assert out.is_file()
    assert_trees_equal(t, open_tree(out))
    ref = cli_atlas(tmp_path / "ref.h5", MULTI, X, Y, args=["--sweep", "both"])
    assert_trees_equal(open_tree(out), ref)
    assert sorted(os.listdir(tmp_path)) == ["a.h5", "ref.h5"]  # no journal, lock or partial file left


def test_atlas_without_output_leaves_nothing(monkeypatch):
    made = []
    real = tempfile.mkdtemp

    def spy(*a, **k):
        made.append(real(*a, **k))
        return made[-1]

    monkeypatch.setattr(tempfile, "mkdtemp", spy)
    tmp = tempfile.gettempdir()
    before = {n for n in os.listdir(tmp) if n.startswith("vibroatlas")}
    t = va.atlas(MULTI, x=("omega", 0.3, 0.4, 3), y=("delta", 0.5, 0.6, 2), progress=False)
    assert not made, "no temporary folder"
    assert {n for n in os.listdir(tmp) if n.startswith("vibroatlas")} <= before, "no file in the temporary folder"
    assert t["fresh"].ds.label_code_M1.values.shape == (2, 3)
    assert float(t["fresh"].ds.multiplier.sum(skipna=True)) >= 0


def test_atlas_in_memory_equals_the_file_it_would_write(tmp_path):
    """Without output the file is written in memory and read from its bytes:
    the tree equals va.open of the file the same call writes with output
    (values, dtypes, coordinates, attributes; the run's time and provenance
    aside), its datasets sealed with their checksums as the file's are; a
    zoom likewise."""
    kw = dict(x=X, y=Y, sweep="both", attractors=3, threads=2, progress=False)
    memory = va.atlas(MULTI, **kw)
    va.atlas(MULTI, output=tmp_path / "a.h5", **kw)
    with va.open(tmp_path / "a.h5") as f:
        assert_trees_equal(memory, f.load())
    for node in memory.subtree:
        for name, v in node.to_dataset(inherit=False).data_vars.items():
            assert "values_crc32" in v.attrs, f"{node.path}/{name}: not sealed"
    box = dict(x=("omega", 0.1, 1.0875, 5), y=("delta", 0.05, 0.9, 4), progress=False)
    zoomed = va.zoom(tmp_path / "a.h5", **box)
    va.zoom(tmp_path / "a.h5", output=tmp_path / "z.h5", **box)
    with va.open(tmp_path / "z.h5") as f:
        assert_trees_equal(zoomed, f.load())


def test_dry_friction_sweep_both_with_params(tmp_path):
    x, y = ("omega", 4.5, 8.0, 6), ("fk", 0.01, 0.2, 3)
    ref = cli_atlas(tmp_path / "ref.h5", DRY, x, y, args=["--sweep", "both"])
    assert_trees_equal(va.atlas(DRY, x=x, y=y, sweep="both", progress=False), ref)


def test_open_equals_xarray(both):
    _, ref, path = both
    with va.open(path) as t:
        assert isinstance(t, xr.DataTree)
        assert_trees_equal(t.load(), ref, volatile=set())


def test_labels(both):
    t, ref, _ = both
    for sweep in ("up", "down"):
        for mass in ("M1", "M2"):
            lab = va.labels(t[sweep], mass)
            ds = ref[sweep].ds
            expect = ds.label[ds[f"label_code_{mass}"]]
            assert lab.dims == expect.dims == ("delta", "omega")
            assert np.array_equal(lab.values, expect.values.astype(str))
            assert np.array_equal(lab.omega.values, ds.omega.values)
    lab = va.labels(t["up"].ds, "M1")   # a Dataset too
    assert lab.sel(omega=0.33, delta=0.6, method="nearest").item() == "1-4-4"
    assert va.labels(t["up"]).equals(lab)  # default: the first mass, M1
    with pytest.raises(ValueError):
        va.labels(t["up"], "M9")


def test_labels_of_attractors(tmp_path):
    t = va.atlas(MULTI, x=("omega", 0.3, 0.34, 3), y=("delta", 0.6, 0.7, 2), attractors=8, progress=False)
    a = t["attractors"].ds
    lab = va.labels(a, "M1")
    code = a.label_code_M1.values
    assert lab.dims == a.label_code_M1.dims
    table = a.label.values.astype(str)
    assert np.array_equal(lab.values, np.where(code >= 0, table[np.clip(code, 0, None)], ""))
    assert (lab.values != "").sum() == int(a["count"].sum())


def test_atlas_scene_as_text_and_dict(tmp_path):
    """The same plane from the scene's text and from its table: the CLI's
    data; the text is stored as given, a table as TOML the engine writes."""
    x, y = ("omega", 0.3, 0.5, 4), ("delta", 0.5, 0.7, 3)
    ref = cli_atlas(tmp_path / "ref.h5", MULTI, x, y, {"mu_k": 0.3}, ["--sweep", "up"])
    text = MULTI.read_text()
    t = va.atlas(text, x=x, y=y, sweep="up", mu_k=0.3, progress=False)
    assert_trees_equal(t, ref)
    t = va.atlas(tomllib.loads(text), x=x, y=y, sweep="up", mu_k=0.3, progress=False)
    assert_trees_equal(t, ref, volatile=VOLATILE | {"scene"})
    assert tomllib.loads(t.attrs["scene"]) == tomllib.loads(text)


def test_open_sweep_and_curve_files(tmp_path):
    s, c = tmp_path / "sweep.h5", tmp_path / "curve.h5"
    cli("sweep", MULTI, "--axis", "omega=0.2:0.5:7", "--direction", "both", "--quiet", "-o", s)
    cli("curve", DRY, "--kind", "pf", "--start", "omega=6.845,fk=0.01", "--free", "omega,fk", "--to", "0.05",
        "--steps", "4", "-o", c)
    with va.open(s) as t:
        assert_trees_equal(t.load(), open_tree(s), volatile=set())
        assert va.labels(t["up"], "M1").sel(omega=0.35, method="nearest").squeeze().item() == "1-4-4"
    with va.open(c) as t:
        assert_trees_equal(t.load(), open_tree(c), volatile=set())
        assert any(str(k).startswith("curve_") for k in t.children)


def test_quantities_keep_those_named_as_the_cli_keeps_them(tmp_path):
    """quantities= keeps the quantities named, as `--quantities` does: the
    tree of `quantities=["power_in", "max_abs_x_M1"]` equals the CLI's file
    of `--quantities power_in,max_abs_x_M1`; "none" and [] keep none; a name
    the scene does not have is a ValueError naming the keyword."""
    x, y = ("omega", 0.13, 0.53, 3), ("delta", 0.4, 0.8, 2)
    kept = ["power_in", "max_abs_x_M1"]
    ref = cli_atlas(tmp_path / "ref.h5", MULTI, x, y, args=["--quantities", ",".join(kept), "--threads", "1"])
    t = va.atlas(str(MULTI), x=x, y=y, quantities=kept, threads=1, progress=False)
    assert_trees_equal(t, ref)
    every = va.atlas(str(MULTI), x=x, y=y, threads=1, progress=False)
    for k in kept:
        assert k in t["fresh"].data_vars and k in every["fresh"].data_vars
    assert "rms_v_M1" in every["fresh"].data_vars and "rms_v_M1" not in t["fresh"].data_vars
    for none in ("none", []):
        bare = va.atlas(str(MULTI), x=x, y=y, quantities=none, threads=1, progress=False)
        assert set(bare["fresh"].data_vars) < set(t["fresh"].data_vars)
        assert not {"power_in", "max_abs_x_M1", "rms_v_M1"} & set(bare["fresh"].data_vars), none
    with pytest.raises(ValueError, match=r"^quantities: 'bogus' is not a quantity of this scene"):
        va.atlas(str(MULTI), x=x, y=y, quantities=["bogus"], threads=1, progress=False)
    with pytest.raises(TypeError, match="quantities"):
        va.atlas(str(MULTI), x=x, y=y, quantities=3, progress=False)
    for odd in (["power_in", ""], ["power_in,max_abs_x_M1"], ["all", "power_in"]):
        with pytest.raises(ValueError, match=r"^quantities: '.*' is not a name"):
            va.atlas(str(MULTI), x=x, y=y, quantities=odd, progress=False)
    with pytest.raises(ValueError, match=r"^quantities: 'all' stands alone"):
        va.atlas(str(MULTI), x=x, y=y, quantities="all,power_in", progress=False)
