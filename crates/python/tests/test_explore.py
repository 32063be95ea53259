"""va.zoom and va.explore (issue 39): a zoom returns the DataTree of the
file `vibroatlas zoom` writes, and an aligned box is the parent's cells bit
for bit; the explorer serves the API from a thread of this process and
stops."""
import json
import urllib.error
import urllib.request

import numpy as np
import pytest
import vibroatlas as va

from conftest import MULTI, VOLATILE, assert_trees_equal, cli, open_tree


@pytest.fixture(scope="module")
def parent(tmp_path_factory):
    path = tmp_path_factory.mktemp("zoom") / "parent.h5"
    va.atlas(MULTI, x=("omega", 0.2, 2.0, 37), y=("delta", 0.1, 1.0, 10), sweep="both", output=path,
             progress=False)
    return path


def test_an_aligned_zoom_is_the_parents_cells(parent):
    child = va.zoom(parent, x=("omega", 0.5, 1.0, 11), y=("delta", 0.3, 0.6, 4), progress=False)
    with va.open(parent) as p:
        for sweep in ["up", "down"]:
            for var in ["class", "final_state", "lyapunov", "multiplier", "periods"]:
                want = p[sweep][var].values[2:6, 6:17]
                np.testing.assert_array_equal(child[sweep][var].values, want, err_msg=f"{sweep}/{var}")
            for mass in ["M1", "M2"]:
                got = va.labels(child[sweep], mass).values
                want = va.labels(p[sweep], mass).values[2:6, 6:17]
                assert (got == want).all(), f"{sweep} {mass}"
    assert child.attrs["parent"] == str(parent)
    assert child.attrs["parent_box"] == "omega=0.5:1:11 delta=0.3:0.6:4"


def test_va_zoom_is_the_clis_file(parent, tmp_path):
    box = ("omega", 0.9, 1.3, 9), ("delta", 0.45, 0.85, 5)
    out = tmp_path / "cli.h5"
    cli("zoom", parent, "--x", "omega=0.9:1.3:9", "--y", "delta=0.45:0.85:5", "--quiet", "-o", out)
    with va.open(parent) as tree:  # a DataTree with its file behind it
        mine = va.zoom(tree, x=box[0], y=box[1], progress=False)
    assert_trees_equal(mine, open_tree(out), volatile=VOLATILE | {"parent"})


def test_bad_zooms_raise_one_clear_error(parent, tmp_path):
    with pytest.raises(ValueError, match="x: omega=1.5:2.5 is not within the parent's 0.2 to 2"):
        va.zoom(parent, x=("omega", 1.5, 2.5, 5), y=("delta", 0.1, 1.0, 4), progress=False)
    with pytest.raises(ValueError, match="sweep: "):
        va.zoom(parent, x=("omega", 0.5, 1.0, 5), y=("delta", 0.1, 1.0, 4), sweep="fresh", progress=False)
    with pytest.raises(TypeError, match="parent: expected an atlas file's path"):
        va.zoom(42, x=("omega", 0.5, 1.0, 5), y=("delta", 0.1, 1.0, 4))
    assert not list(tmp_path.iterdir())


def get(url):
    with urllib.request.urlopen(url, timeout=60) as r:
        return json.loads(r.read())


def test_explore_serves_the_api_and_stops(parent):
    ex = va.explore(parent)
    try:
        assert ex.url.startswith("http://127.0.0.1:")
        assert f'src="{ex.url}"' in ex._repr_html_()
        info = get(ex.url + "api/atlas")
        assert (info["x"]["name"], info["y"]["name"], info["sweeps"]) == ("omega", "delta", ["up", "down"])
        omega, delta = info["x"]["values"][7], info["y"]["values"][3]
        cell = get(ex.url + f"api/cell?sweep=down&omega={omega!r}&delta={delta!r}")
        want = json.loads(cli("cell", "--from", parent, "--sweep", "down", "--at",
                              f"omega={omega!r},delta={delta!r}", "--json").stdout)
        assert cell == want
        with pytest.raises(urllib.error.HTTPError) as e:
            urllib.request.urlopen(ex.url + "api/cell?sweep=sideways&omega=1&delta=1", timeout=60)
        assert e.value.code == 400
    finally:
        ex.stop()
    assert "stopped" in repr(ex)
    with pytest.raises(urllib.error.URLError):
        urllib.request.urlopen(ex.url + "api/atlas", timeout=5)


def test_explore_refuses_what_is_not_an_atlas(tmp_path):
    with pytest.raises(OSError, match="not an HDF5 file"):
        va.explore(MULTI)
    with pytest.raises(ValueError, match="port"):
        va.explore(MULTI, port=70000)
