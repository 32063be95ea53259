"""va.zoom and va.explore (issue 39): a zoom returns the DataTree of the
file `vibroatlas zoom` writes, and an aligned box is the parent's cells bit
for bit; the explorer serves the API from a thread of this process and
stops."""
import json
import time
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


def test_explorer_selected_is_the_clicked_cell_as_va_cell_returns_it(parent, tmp_path):
    """The hand-off to Python (issue 65): the cell the page last asked for
    (a click) is `Explorer.selected`, equal to `va.cell(from_file=…, at=…,
    sweep=…)`, to `cell --from … --json` and to the page's own answer; a
    zoom's child cell too, and a slice at another zeta (`set`)."""
    with va.explore(parent) as ex:
        assert ex.selected is None
        info = get(ex.url + "api/atlas")
        omega, delta = info["x"]["values"][11], info["y"]["values"][4]
        page = get(ex.url + f"api/cell?sweep=down&omega={omega!r}&delta={delta!r}")
        chosen = ex.selected
        assert ex.clicked == {"from_file": str(parent), "at": {"omega": omega, "delta": delta}, "sweep": "down"}
        mine = va.cell(from_file=parent, at={"omega": omega, "delta": delta}, sweep="down")
        want = json.loads(cli("cell", "--from", parent, "--sweep", "down", "--at",
                              f"omega={omega!r},delta={delta!r}", "--json").stdout)
        assert chosen == mine == want == page
        # A refused request does not move the selection.
        with pytest.raises(urllib.error.HTTPError):
            urllib.request.urlopen(ex.url + "api/cell?sweep=down&omega=1", timeout=60)
        assert ex.selected == chosen
        # A cell of a zoom at another zeta: the child's file and values.
        body = json.dumps({"atlas": 0, "x": "omega=0.5:1:6", "y": "delta=0.3:0.6:4", "set": "zeta=0.05"}).encode()
        req = urllib.request.Request(ex.url + "api/zoom", data=body, headers={"Content-Type": "application/json"})
        with urllib.request.urlopen(req, timeout=60) as r:
            job = json.loads(r.read())["job"]
        for _ in range(600):
            state = get(ex.url + f"api/jobs/{job}")
            if state["state"] != "running":
                break
            time.sleep(0.1)
        assert state["state"] == "done", state
        child = get(ex.url + f"api/atlas?atlas={state['child']}")
        assert child["parent"]["box"] == "omega=0.5:1:6 delta=0.3:0.6:4 at zeta=0.05"
        om, de = child["x"]["values"][2], child["y"]["values"][1]
        page = get(ex.url + f"api/cell?atlas={state['child']}&sweep=up&omega={om!r}&delta={de!r}")
        chosen = ex.selected
        assert chosen == page
        assert chosen["parameters"]["zeta"] == 0.05, chosen["parameters"]
    assert ex.selected is None
    with pytest.raises(ValueError, match="at, sweep: given without from_file"):
        va.cell(MULTI, sweep="down")
    with pytest.raises(TypeError, match="at: expected"):
        va.cell(from_file=parent)


def test_explore_refuses_what_is_not_an_atlas(tmp_path):
    with pytest.raises(OSError, match="not an HDF5 file"):
        va.explore(MULTI)
    with pytest.raises(ValueError, match="port"):
        va.explore(MULTI, port=70000)


def test_an_explorer_of_a_relative_path_serves_it_after_a_change_of_folder(parent, monkeypatch):
    # The page reads the file on every request: a path kept relative named
    # another file once the process changed its folder (a notebook's os.chdir).
    monkeypatch.chdir(parent.parent)
    ex = va.explore(parent.name)
    try:
        assert ex.path == str(parent)
        monkeypatch.chdir("/")
        assert get(ex.url + "api/at?ix=1&iy=1")["parameters"]
    finally:
        ex.stop()
    for port in (-1, 65536, 1.5, True):
        with pytest.raises(ValueError, match="port: expected 0 to 65535"):
            va.Explorer(parent, port=port)
