"""va.basins (issue 66): the basins of one point over a grid of two state
components, as an xarray.Dataset equal to the file `vibroatlas basins`
writes; va.plot.basins paints every start in its attractor's stored colour."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import vibroatlas as va  # noqa: E402
import xarray as xr  # noqa: E402

from conftest import CONFIGS, VOLATILE, axis, cli  # noqa: E402

SINGLE = CONFIGS / "single-stop.toml"
POINT = {"omega": 2.5, "sigma": 1.0, "zeta": 0.05}
X, Y = ("x_M", -3, 1, 24), ("v_M", -3, 3, 20)


@pytest.fixture(scope="module")
def ds():
    return va.basins(str(SINGLE), X, Y, progress=False, **POINT)


def test_basins_equal_the_cli_file(ds, tmp_path):
    path = tmp_path / "b.h5"
    cli("basins", SINGLE, *[a for k, v in POINT.items() for a in ("--set", f"{k}={v!r}")], "--x", axis(X),
        "--y", axis(Y), "--quiet", "-o", path)
    with xr.open_dataset(path, engine="h5netcdf") as ref:
        assert sorted(ds.data_vars) == sorted(ref.data_vars)
        for name in ref.variables:
            np.testing.assert_array_equal(ds[name].values, ref[name].values, err_msg=name)
        for key, value in ref.attrs.items():
            if key not in VOLATILE:
                assert ds.attrs[key] == value or (np.isnan(value) and np.isnan(ds.attrs[key])), key
    assert ds["basin"].dims == ("v_M", "x_M")
    assert [str(v) for v in ds["labels_M"].values] == ["1-0-0", "2-1-0"]
    assert np.bincount(ds["basin"].values.ravel()).tolist() == ds["count"].values.tolist()


def test_a_state_and_a_phase_move_the_basins(ds):
    moved = va.basins(str(SINGLE), X, Y, phase=0.0, progress=False, **POINT)
    assert float(moved.attrs["phase"]) == 0.0 and float(ds.attrs["phase"]) == pytest.approx(np.pi / 2)
    assert (moved["basin"].values != ds["basin"].values).any()
    with pytest.raises(ValueError, match="state"):
        va.basins(str(SINGLE), X, Y, state=[0.0], progress=False, **POINT)
    with pytest.raises(ValueError, match="x_Q"):
        va.basins(str(SINGLE), ("x_Q", 0, 1, 4), Y, progress=False, **POINT)


def test_plot_basins_paints_each_start_in_its_attractors_colour(ds):
    fig = plt.figure(figsize=(4.8, 4.0), dpi=100)  # 20 pixels a start
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_axis_off()
    assert va.plot.basins(ds, ax=ax, legend=False) is ax
    # Without the section points, whose dots cover some starts.
    for line in list(ax.lines):
        line.remove()
    fig.canvas.draw()
    img = np.asarray(fig.canvas.buffer_rgba())[:, :, :3]
    rgb = ds["attractor_colour"].values
    ids = ds["basin"].values
    for iy, y in enumerate(ds["v_M"].values):
        for ix, x in enumerate(ds["x_M"].values):
            px, py = ax.transData.transform((x, y))
            got = tuple(int(c) for c in img[img.shape[0] - 1 - int(round(py)), int(round(px))])
            assert got == tuple(int(c) for c in rgb[ids[iy, ix]]), (iy, ix)
    plt.close(fig)
    _, ax = plt.subplots()
    va.plot.basins(ds, ax=ax)
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert texts[0].startswith("M 1-0-0 (") and texts[-1] == "period-section points"
    plt.close("all")
