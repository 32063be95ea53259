"""va.plot draws with the file's colours: in an Agg figure, the pixel at the
centre of every cell has exactly the colour the file stores for that cell's
label (label_colour), and the hysteresis panel splits each coexisting cell
between the up label's colour (above the diagonal) and the down label's."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import vibroatlas as va  # noqa: E402

from conftest import CONFIGS, MULTI, open_tree, cli, axis  # noqa: E402

X = ("omega", 0.1, 3.05, 24)
Y = ("delta", 0.05, 2.0, 16)


@pytest.fixture(scope="module")
def tree(tmp_path_factory):
    path = tmp_path_factory.mktemp("plot") / "a.h5"
    cli("atlas", MULTI, "--x", axis(X), "--y", axis(Y), "--sweep", "both", "--quiet", "-o", path)
    return open_tree(path)


def pixels(fig):
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[:, :, :3]


def pixel_at(ax, img, x, y):
    """The RGB of the pixel under data point (x, y) of ax."""
    px, py = ax.transData.transform((x, y))
    return tuple(int(c) for c in img[img.shape[0] - 1 - int(py), int(px)])


def cell_colours(ds, mass):
    code = ds[f"label_code_{mass}"].values
    return ds["label_colour"].values[code]  # [y, x, rgb]


@pytest.mark.parametrize("sweep,mass", [("up", "M1"), ("down", "M2")])
def test_map_pixels_are_the_files_colours(tree, sweep, mass):
    fig = plt.figure(figsize=(4.8, 3.2), dpi=100)  # 20 pixels a cell
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_axis_off()
    got = va.plot.map(tree[sweep], mass=mass, ax=ax, legend=False)
    assert got is ax
    img = pixels(fig)
    ds = tree[sweep].ds
    want = cell_colours(ds, mass)
    xs, ys = ds.omega.values, ds.delta.values
    for iy in range(len(ys)):
        for ix in range(len(xs)):
            assert pixel_at(ax, img, xs[ix], ys[iy]) == tuple(int(c) for c in want[iy, ix]), (iy, ix)
    plt.close(fig)


def test_known_cell_colour(tree):
    """The cell nearest (ω 0.33, δ 0.6) in the up sweep, by its label text."""
    ds = tree["up"].ds
    c = ds.sel(omega=0.33, delta=0.6, method="nearest")
    text = va.labels(ds, "M1").sel(omega=0.33, delta=0.6, method="nearest").item()
    rgb = tuple(int(v) for v in ds.label_colour.sel(label=text).values)
    fig = plt.figure(figsize=(4.8, 3.2), dpi=100)
    ax = fig.add_axes([0, 0, 1, 1])
    va.plot.map(ds, "M1", ax=ax, legend=False)
    assert pixel_at(ax, pixels(fig), float(c.omega), float(c.delta)) == rgb
    assert va.plot.colours(ds)[text] == rgb
    plt.close(fig)


def test_map_with_legend_returns_axes(tree):
    ax = va.plot.map(tree["up"], "M1")
    assert ax.get_title() == "M1, up sweep"
    assert "ω" in ax.get_xlabel() and "δ" in ax.get_ylabel()
    assert ax.get_legend() is not None
    plt.close(ax.figure)


@pytest.mark.parametrize("rows", [4, 8, 40])
def test_map_legend_is_renders(tree, rows):
    """The legend is the one vibroatlas render draws: at most `rows` rows,
    named labels in the file's colours first, hatched family groups after
    them, and every labelled cell counted once."""
    ds = tree["down"].ds
    ax = va.plot.map(tree["down"], "M2", max_legend=rows)
    handles = ax.get_legend().legend_handles
    assert 0 < len(handles) <= rows
    codes = ds["label_code_M2"].values
    table = va.label_table(ds, ds["label_code_M2"])
    colours = {label: tuple(ds["label_colour"].values[i]) for i, label in enumerate(table)}
    counted, grouped = 0, False
    for h in handles:
        text = h.get_label()
        counted += int(text[text.rindex("(") + 1:-1])
        if h.get_hatch():
            grouped = True
            assert text.startswith("+"), text
            continue
        assert not grouped, "a named label after a group"
        label = text.split()[0]
        assert tuple(round(255 * c) for c in h.get_facecolor()[:3]) == colours[label], label
    assert counted == int((codes >= 0).sum())
    plt.close(ax.figure)


def test_hysteresis_panels(tree):
    fig = plt.figure(figsize=(14.4, 3.2), dpi=100)
    axes = va.plot.hysteresis(tree, mass="M1", fig=fig, legend=False)
    assert len(axes) == 3
    img = pixels(fig)
    up, down = tree["up"].ds, tree["down"].ds
    cu, cd = cell_colours(up, "M1"), cell_colours(down, "M1")
    mask = tree.ds["hysteresis"].transpose("delta", "omega").values == 1
    assert mask.any(), "the test grid has no coexisting cells"
    xs, ys = up.omega.values, up.delta.values
    dx, dy = xs[1] - xs[0], ys[1] - ys[0]
    for iy in range(len(ys)):
        for ix in range(len(xs)):
            x, y = xs[ix], ys[iy]
            assert pixel_at(axes[0], img, x, y) == tuple(int(c) for c in cu[iy, ix])
            assert pixel_at(axes[1], img, x, y) == tuple(int(c) for c in cd[iy, ix])
            upper = pixel_at(axes[2], img, x - 0.3 * dx, y + 0.3 * dy)   # above the rising diagonal
            lower = pixel_at(axes[2], img, x + 0.3 * dx, y - 0.3 * dy)   # below it
            if mask[iy, ix]:
                assert upper == tuple(int(c) for c in cu[iy, ix]), (iy, ix)
                assert lower == tuple(int(c) for c in cd[iy, ix]), (iy, ix)
            else:
                # Agreeing cells: the colours faded three fifths toward white.
                assert upper == tuple((2 * int(c) + 767) // 5 for c in cu[iy, ix]), (iy, ix)
                assert lower == tuple((2 * int(c) + 767) // 5 for c in cd[iy, ix]), (iy, ix)
    plt.close(fig)


def test_hysteresis_default_figure(tree):
    axes = va.plot.hysteresis(tree)
    assert [a.get_title().split(",")[0] for a in axes[:2]] == ["M1", "M1"]
    assert axes[2].get_title().startswith("coexisting motions:")
    plt.close(axes[0].figure)


@pytest.mark.parametrize("quantity", ["multiplier", "lyapunov", "max_abs_x_M1", "impact_speed_max_A1",
                                      "mean_x_M1", "max_abs_x_M1:hysteresis"])
def test_scalar_views_paint_the_colours_render_paints(tmp_path, quantity):
    """va.plot.scalar (and va.plot.quantity, for a quantity of the steady
    motion or a number of the classification, here lyapunov, and
    va.plot.difference, its up less down) draws each cell in the
    colour `render --view` gives it: the
    oracle is the explorer's /api/map, render's own per-cell colours."""
    import json
    import urllib.request

    path = tmp_path / "a.h5"
    cli("atlas", MULTI, "--x", axis(X), "--y", axis(Y), "--sweep", "both", "--quiet", "-o", path)
    tree = open_tree(path)
    ds = tree["up"].ds
    fig, ax = plt.subplots(figsize=(8, 5))
    view = quantity if quantity.endswith(":hysteresis") else f"{quantity}:up"
    if quantity == "multiplier":
        va.plot.scalar(tree["up"], quantity, ax=ax)
    elif view.endswith(":hysteresis"):
        va.plot.difference(tree, quantity.split(":")[0], ax=ax)
    else:
        va.plot.quantity(tree["up"], quantity, ax=ax)
    img = pixels(fig)
    ex = va.explore(path)
    try:
        info = json.load(urllib.request.urlopen(ex.url + "api/atlas"))
        nx, ny = info["x"]["count"], info["y"]["count"]
        with urllib.request.urlopen(ex.url + f"api/map?view={view}") as r:
            want = np.frombuffer(r.read(), np.uint8)[: 3 * nx * ny].reshape(ny, nx, 3)
    finally:
        ex.stop()
    xs, ys = ds["omega"].values, ds["delta"].values
    checked = 0
    for iy in range(0, ny, 3):
        for ix in range(0, nx, 3):
            assert pixel_at(ax, img, xs[ix], ys[iy]) == tuple(int(c) for c in want[iy, ix]), (quantity, iy, ix)
            checked += 1
    assert checked >= 40
    plt.close(fig)
    with pytest.raises(ValueError, match="quantity"):
        va.plot.scalar(tree["up"], "period")
    with pytest.raises(ValueError, match="not a quantity of this group"):
        va.plot.quantity(tree["up"], "period")


def test_axis_labels_draw_subscripts():
    """A symbol's subscript (f_k) is drawn as one, as the CLI's figures draw it."""
    import xarray as xr

    c = xr.DataArray([0.01, 0.02], dims="fk", name="fk",
                     attrs={"symbol": "f_k", "long_name": "kinetic friction force"})
    label = va.plot.axis_label(c)
    assert label == "kinetic friction force f$_{\\mathrm{k}}$"
    fig, ax = plt.subplots()
    ax.set_xlabel(label)
    fig.canvas.draw()  # mathtext parses it
    plt.close(fig)


def test_row_diagram_draws_the_files_sections(tmp_path):
    """va.plot.row draws what `render SWEEP.h5` draws: the period panel holds
    every period-section point of each sweep (as `sweep --json` reports them),
    each impact panel every impact's normal speed |n·v| (read here with h5py),
    the down sweep as rings, and a stop without impacts gets no panel."""
    import h5py

    path = tmp_path / "s.h5"
    s = va.sweep(MULTI, axis=("omega", 0.28, 0.36, 9), direction="both", output=path, progress=False)
    axes = va.plot.row(path)
    with h5py.File(path) as f:
        stops = f.attrs["stops"].split(",")
        normals = np.asarray(f.attrs["stop_normals"], float).reshape(len(stops), -1)
        dof = normals.shape[1]
        speeds = {}
        for sweep in ("up", "down"):
            for k, stop in enumerate(stops):
                values = f[f"{sweep}/sections/{stop}/values"][()]
                offsets = f[f"{sweep}/sections/{stop}/offsets"][()]
                xs = f[f"{sweep}/omega"][()]
                cell = np.searchsorted(offsets, np.arange(len(values)), side="right") - 1
                speeds[sweep, stop] = sorted(zip(xs[cell % len(xs)].tolist(),
                                                 np.abs(values[:, 1 + dof:] @ normals[k]).tolist()))
    with_impacts = [stop for stop in stops if speeds["up", stop] or speeds["down", stop]]
    assert len(axes) == 1 + len(with_impacts)
    assert [a.get_ylabel() for a in axes[1:]] == [f"impact speed at {stop}" for stop in with_impacts]

    def drawn(ax):
        return {c.get_label(): sorted(map(tuple, c.get_offsets().tolist())) for c in ax.collections}

    period = drawn(axes[0])
    for sweep in ("up", "down"):
        want = sorted((q["value"], sec[0]) for q in s[sweep] for sec in q["period_section"])
        np.testing.assert_allclose(period[f"{sweep} sweep"], want, rtol=1e-15, atol=0, err_msg=sweep)
    for ax, stop in zip(axes[1:], with_impacts):
        got = drawn(ax)
        for sweep in ("up", "down"):
            np.testing.assert_allclose(got[f"{sweep} sweep"], speeds[sweep, stop], rtol=1e-15, atol=0,
                                       err_msg=f"{sweep} {stop}")
    ring = [c for c in axes[0].collections if c.get_label() == "down sweep"][0]
    assert len(ring.get_facecolors()) == 0 or ring.get_facecolors()[0][3] == 0, "down sweep drawn as rings"
    assert "x$_{\\mathrm{M1}}$" in axes[0].get_ylabel()
    plt.close(axes[0].figure)


def test_row_diagram_says_contacts_at_a_soft_stop(tmp_path):
    """A soft stop's panel is of contact speeds, as the file's `stop_laws`
    says; a file written before that attribute says so from its scene."""
    import h5py

    import shutil

    path, before = tmp_path / "soft.h5", tmp_path / "before.h5"
    va.sweep(CONFIGS / "soft-stop.toml", axis=("omega", 0.8, 1.2, 5), output=path, progress=False)
    shutil.copy(path, before)
    with h5py.File(before, "r+") as f:
        assert f.attrs["stop_laws"] == "soft"
        del f.attrs["stop_laws"]
    for file in (path, before):
        axes = va.plot.row(file)
        assert [a.get_ylabel() for a in axes[1:]] == ["contact speed at A"], file.name
        plt.close(axes[0].figure)


@pytest.mark.parametrize("view", ["multiplier", "lyapunov"])
def test_map_views_are_the_scalar_views(tree, view):
    """va.plot.map(view=...) draws what va.plot.scalar draws, pixel for pixel."""
    images = []
    for draw in (lambda ax: va.plot.map(tree["up"], ax=ax, view=view),
                 lambda ax: va.plot.scalar(tree["up"], view, ax=ax)):
        fig = plt.figure(figsize=(4.8, 3.2), dpi=100)
        draw(fig.add_axes([0.1, 0.1, 0.6, 0.8]))
        images.append(pixels(fig))
        plt.close(fig)
    assert (images[0] == images[1]).all()
    with pytest.raises(ValueError, match="view 'speed'"):
        va.plot.map(tree["up"], view="speed")


def test_row_refuses_what_render_refuses(tree, tmp_path):
    """A row outside the file, a value that is not a number, a group for the
    tree and a file without section points are refused, each saying so."""
    for at, kind, words in [(5.0, ValueError, "delta = 5.0 is outside the file's 0.05 to 2"),
                            (float("nan"), ValueError, "not a finite number"),
                            ("0.5", TypeError, "expected a number")]:
        with pytest.raises(kind, match=words):
            va.plot.row(tree, at=at)
    with pytest.raises(ValueError, match="got its group 'up'"):
        va.plot.row(tree["up"])
    bare = tmp_path / "bare.h5"
    cli("atlas", MULTI, "--x", "omega=0.3:0.4:3", "--y", "delta=0.5:0.6:2", "--section-cap", "0", "--quiet",
        "-o", bare)
    with pytest.raises(ValueError, match="no section points"):
        va.plot.row(bare)


DOLLARS = r"""
name = 'dollar $\x$'
[parameters]
zeta = { value = 0.05, range = "[0, inf)", symbol = '$\zz$', long_name = 'long $\qq$' }
omega = { value = 2.5, range = "(0, inf)", symbol = "ω$" }
[forcing]
omega = "omega"
[[masses]]
name = 'M$\y$'
mass = 1
force = 1
[[links]]
masses = ['M$\y$']
stiffness = 1
damping = "2*zeta"
[[stops]]
name = 'A$\w$'
mass = 'M$\y$'
side = "above"
position = 0
restitution = 0.8
[labels.'M$\y$']
p = 'A$\w$'
[quantities]
qq = { value = "2*zeta", units = '$\u$', symbol = '$\s$', long_name = '$\ln$' }
"""


def test_names_holding_dollars_are_drawn_letter_for_letter(tmp_path):
    # A `$` pair in a scene's names, symbols and units was parsed as
    # mathtext: every figure of such an (accepted) scene raised on drawing.
    scene = tmp_path / "dollars.toml"
    scene.write_text(DOLLARS)
    path = tmp_path / "d.h5"
    cli("atlas", scene, "--x", "omega=1:3:4", "--y", "zeta=0:0.5:3", "--sweep", "both", "--quiet", "-o", path)
    t = open_tree(path)
    drawn = [va.plot.map(t["up"]), va.plot.quantity(t["up"], "qq"), *va.plot.hysteresis(t)]
    for ax in drawn:
        ax.figure.canvas.draw()
    assert drawn[0].get_title() == r"M\$\y\$, up sweep"
    assert drawn[0].get_ylabel() == r"long \$\qq\$ \$\zz\$"
    plt.close("all")
