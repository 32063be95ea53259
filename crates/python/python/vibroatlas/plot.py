"""Label maps with matplotlib, in the colours stored in the file.

Every sweep group stores its label table (`label`) and one RGB colour per
label (`label_colour`, the colours of `vibroatlas render`); these functions
draw each cell as a rectangle in the colour of its label, with no
interpolation (a ListedColormap of the labels present and boundaries between
their codes), so that a figure's pixel inside a cell has exactly that
label's colour.
"""
import math
import numbers
from collections import Counter

import numpy as np

from . import _codes, _dataset, _first_mass, _run, label_table

__all__ = ["map", "hysteresis", "scalar", "quantity", "difference", "row", "portrait", "sections", "colours", "basins"]

# The continuous views' diverging scale, as `vibroatlas render --view
# multiplier|lyapunov` paints it: blue below the neutral value, white at it,
# red above; cells without the number grey.
_LOW, _HIGH, _NONE = (33, 102, 172), (178, 24, 43), (190, 190, 190)
_CENTRE = {"multiplier": 1.0, "lyapunov": 0.0}


def _node_name(ds):
    name = getattr(ds, "name", None)
    return name if isinstance(name, str) and type(ds).__name__ == "DataTree" else None


def edges(v):
    """Cell edges around centres v (midpoints; a single centre gets a width of
    10 % of its value), as scripts/plot_atlas.py draws them."""
    v = np.asarray(v, float)
    if len(v) == 1:
        h = 0.05 * abs(v[0]) or 0.5
        return np.array([v[0] - h, v[0] + h])
    mid = (v[1:] + v[:-1]) / 2
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def colours(ds):
    """{label text: (r, g, b)} (0-255) of a sweep group, from `label_colour`."""
    ds = _dataset(ds)
    table = label_table(ds)
    rgb = np.asarray(ds["label_colour"].values).astype(int)
    return {t: tuple(int(c) for c in rgb[i]) for i, t in enumerate(table)}


def _escaped(text):
    """text as matplotlib is to draw it, letter for letter: a `$` of a name,
    unit or title from a file is not the start of mathtext (a pair of them
    was parsed as markup, and a figure of an accepted scene failed)."""
    return str(text).replace("$", "\\$")


def _subscripts(text):
    """text with its subscripts (as vibroatlas's figures find them: f_k,
    x_M1) written as mathtext subscripts, every other character drawn as
    it is (`_escaped`); a subscript holding a character that mathtext reads
    as markup is written plainly after an underscore."""
    from . import _native

    def sub(t):
        plain = any(c in t for c in "$\\{}_^%#&~")
        return "_" + _escaped(t) if plain else f"$_{{\\mathrm{{{t}}}}}$"

    return "".join(sub(t) if low else _escaped(t) for t, low in _native.subscript_runs(text))


def axis_label(coord):
    """`long_name symbol` of an axis coordinate (the symbol alone where the
    long name is generic), as vibroatlas's figures write it, subscripts
    drawn as subscripts (f_k as f with the subscript k)."""
    name = str(coord.name)
    sym = str(coord.attrs.get("symbol") or name)
    long = str(coord.attrs.get("long_name") or "")
    if long in ("", f"parameter {name}", name, sym):
        text = sym
    elif sym in long:
        text = long
    else:
        text = f"{long} {sym}"
    units = str(coord.attrs.get("units") or "1")
    return _subscripts(text if units in ("1", "") else f"{text} ({units})")


def _grid(ds, mass):
    """(code [y, x] as ints, x coordinate, y coordinate, table, rgb [label, 3])."""
    code, c, table = _codes(ds, mass)
    if code.ndim != 2:
        raise ValueError(f"label_code_{mass} has dims {code.dims}: map draws a sweep group's [y, x] plane")
    ydim, xdim = code.dims
    return c, ds[xdim], ds[ydim], table, np.asarray(ds["label_colour"].values).astype(float) / 255


def _mesh(ax, xs, ys, codes, rgb):
    """One rectangle per cell in its label's colour (codes index rgb)."""
    from matplotlib.colors import BoundaryNorm, ListedColormap

    present = np.unique(codes)
    index = np.searchsorted(present, codes)
    cmap = ListedColormap([rgb[k] if k >= 0 else (1.0, 1.0, 1.0) for k in present])
    norm = BoundaryNorm(np.arange(len(present) + 1) - 0.5, len(present))
    ex, ey = edges(xs), edges(ys)
    m = ax.pcolormesh(ex, ey, index, cmap=cmap, norm=norm, shading="flat", antialiased=False, linewidth=0,
                      rasterized=True)
    ax.set_xlim(ex[0], ex[-1])
    ax.set_ylim(ey[0], ey[-1])
    if len(ys) == 1:
        ax.set_yticks(ys)
    return m


def _legend_handles(counts, max_rows):
    """Patches of the legend rows vibroatlas render draws for these label
    counts in at most max_rows rows: the most frequent labels told apart by
    colour (CIEDE2000 ΔE ≥ 10 from every label named above), the rest in
    hatched family groups."""
    from matplotlib.patches import Patch

    from . import _native

    handles = []
    for swatch, colours, text in _native.legend(list(counts.items()), max_rows):
        c = tuple(v / 255 for v in colours[0])
        if swatch == "hatch":
            handles.append(Patch(facecolor="white", edgecolor=c, hatch="///", linewidth=0.4, label=_escaped(text)))
        else:
            handles.append(Patch(facecolor=c, edgecolor="0.5", linewidth=0.4, label=_escaped(text)))
    return handles


def map(ds, mass=None, ax=None, *, legend=True, title=None, max_legend=12, view="labels"):  # noqa: A001
    """Draws one mass's label map of a sweep group in the file's colours and
    returns the Axes; with view="multiplier" or "lyapunov" the continuous
    view of `vibroatlas render --view` instead (`scalar`; mass and the
    legend do not apply).

    ds: a sweep group (t["up"], t["up"].ds or an xarray Dataset opened with
    group="up"); mass: "M1" (default: the group's first mass); ax: the Axes
    to draw into (default: a new figure); legend: the legend of vibroatlas
    render beside the map, in at most max_legend rows (the most frequent
    labels told apart by colour, with their number of cells, the rest in
    hatched family groups); title:
    default "<mass>, <sweep> sweep" (a DataTree node knows its sweep)."""
    import matplotlib.pyplot as plt

    if view != "labels":
        if view not in _CENTRE:
            raise ValueError(f"view {view!r}: expected labels, multiplier or lyapunov")
        return scalar(ds, view, ax, title=title)

    max_legend = _run.whole("max_legend", max_legend, least=1)
    node = _node_name(ds)
    ds = _dataset(ds)
    mass = _first_mass(ds) if mass is None else _run.text("mass", mass)
    codes, xc, yc, table, rgb = _grid(ds, mass)
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 5), layout="constrained")
    _mesh(ax, xc.values, yc.values, codes, rgb)
    ax.set_xlabel(axis_label(xc))
    ax.set_ylabel(axis_label(yc))
    ax.set_title(title if title is not None else _escaped(f"{mass}, {node} sweep" if node else mass))
    if legend:
        counts = Counter(table[codes[codes >= 0]].tolist())
        ax.legend(handles=_legend_handles(counts, max_legend), loc="upper left",
                  bbox_to_anchor=(1.01, 1.0), borderaxespad=0, fontsize="small", frameon=False,
                  title=_escaped(f"{mass} n-p-q (cells)"), title_fontsize="small")
    return ax


def basins(ds, ax=None, *, legend=True, title=None):
    """Draws a basin map (va.basins, or a `vibroatlas basins` file opened
    with xarray) as `vibroatlas render` draws it and returns the Axes: every
    start in its attractor's colour (`attractor_colour`; light grey where it
    penetrates a stop), the attractors' period-section points as white dots
    ringed in black, and a legend of the attractors with their basin
    fractions."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    ids = np.asarray(ds["basin"].values).astype(np.int64)
    ydim, xdim = ds["basin"].dims
    rgb = np.asarray(ds["attractor_colour"].values).astype(float) / 255
    grey = (225 / 255,) * 3
    codes = np.where(ids >= 0, ids, len(rgb))
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 5.5), layout="constrained")
    _mesh(ax, ds[xdim].values, ds[ydim].values, codes, np.vstack([rgb, [grey]]))
    ax.set_xlabel(_subscripts(f"{xdim} at the start"))
    ax.set_ylabel(_subscripts(f"{ydim} at the start"))
    names = [str(c) for c in ds["component"].values]
    points = np.asarray(ds["section"].values).reshape(-1, len(names))
    ax.plot(points[:, names.index(xdim)], points[:, names.index(ydim)], "o", markersize=4,
            markerfacecolor="white", markeredgecolor="black", markeredgewidth=0.6, linestyle="none")
    phase = float(ds.attrs["phase"])
    ax.set_title(title if title is not None else _escaped(f"{ds.attrs['scene']}: basins at phase {phase:.3f} rad"))
    if legend:
        masses = [m for m in str(ds.attrs.get("masses", "")).split(",") if m]
        handles = []
        for k in range(len(rgb)):
            named = ", ".join(f"{m} {ds[f'labels_{m}'].values[k]}" for m in masses) or str(
                ds["attractor_class"].values[k])
            text = f"{named} ({100 * float(ds['fraction'].values[k]):.1f} %)"
            handles.append(Patch(facecolor=rgb[k], edgecolor="0.5", linewidth=0.4, label=_escaped(text)))
        if (ids < 0).any():
            handles.append(Patch(facecolor=grey, edgecolor="0.5", linewidth=0.4, label="penetrates a stop"))
        handles.append(Line2D([], [], marker="o", markerfacecolor="white", markeredgecolor="black",
                              linestyle="none", label="period-section points"))
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0,
                  fontsize="small", frameon=False)
    return ax


def hysteresis_mask(tree, masses=None):
    """The coexisting cells [y, x] as a bool DataArray: the file's root
    `hysteresis` variable, else (older files) both sweeps periodic and the
    labels of some labelled mass different."""
    from . import labels

    up = _dataset(tree["up"])
    root = tree.to_dataset(inherit=False) if hasattr(tree, "to_dataset") else tree
    first = _first_mass(up)
    dims = up[f"label_code_{first}"].dims
    if "hysteresis" in root:
        return (root["hysteresis"] == 1).transpose(*dims)
    down = _dataset(tree["down"])
    masses = masses or [str(m) for m in up["mass"].values.astype(str)]
    both = (up["class"] == 0) & (down["class"] == 0)
    differ = False
    for m in masses:
        differ = differ | (labels(up, m) != labels(down, m))
    return (both & differ).transpose(*dims)


def _both(tree, what):
    """The DataTree of `tree` (a DataTree, or a path opened), which must hold
    the up and down sweeps that `what` compares."""
    if not hasattr(tree, "children"):
        from . import open as _open

        tree = _open(tree)
    if not {"up", "down"} <= set(tree.children):
        raise ValueError(f"{what} needs the up and down sweeps (atlas sweep='both'); "
                         f"this tree has {', '.join(tree.children) or 'no group'}")
    return tree


def hysteresis(tree, mass=None, fig=None, *, legend=True, max_legend=16):
    """The three panels of `vibroatlas render --sweep hysteresis`: the mass's
    labels in the up sweep | in the down sweep | the cells where two motions
    coexist (the file's hysteresis mask), each cut along its rising diagonal,
    the up label's colour above it and the down label's below; the cells
    both sweeps computed without a hysteresis in the same split with their
    colours faded toward white (one faded colour where the labels agree);
    the rest white. tree: a DataTree with /up and /down (va.atlas(..., sweep="both"),
    va.open), or a path. Returns the three Axes (a list); fig: the Figure to
    draw into (default: a new one)."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    max_legend = _run.whole("max_legend", max_legend, least=1)
    tree = _both(tree, "hysteresis")
    up, down = _dataset(tree["up"]), _dataset(tree["down"])
    mass = _first_mass(up) if mass is None else _run.text("mass", mass)
    mask = np.asarray(hysteresis_mask(tree).values, bool)
    cu, xc, yc, tu, ru = _grid(up, mass)
    cd, _, _, td, rd = _grid(down, mass)
    if fig is None:
        fig = plt.figure(figsize=(16, 5.5), layout="constrained")
    elif legend and fig.get_layout_engine() is None:
        fig.set_layout_engine("constrained")  # room for the legend outside the panels
    axes = list(fig.subplots(1, 3, sharex=True, sharey=True))
    xs, ys = xc.values, yc.values
    _mesh(axes[0], xs, ys, cu, ru)
    _mesh(axes[1], xs, ys, cd, rd)
    ex, ey = edges(xs), edges(ys)
    from . import _native

    def fade(rgb):
        colours = [tuple(c) for c in np.round(rgb * 255).astype(int).tolist()]
        return np.asarray(_native.faded(colours), float).reshape(-1, 3) / 255

    agree = ~mask & (cu >= 0) & (cd >= 0)
    for cells, (up_rgb, down_rgb) in ((agree, (fade(ru), fade(rd))), (mask, (ru, rd))):
        iy, ix = np.nonzero(cells)
        if not len(iy):
            continue
        x0, x1, y0, y1 = ex[ix], ex[ix + 1], ey[iy], ey[iy + 1]
        upper = np.stack([np.stack([x0, y0], -1), np.stack([x0, y1], -1), np.stack([x1, y1], -1)], 1)
        lower = np.stack([np.stack([x0, y0], -1), np.stack([x1, y0], -1), np.stack([x1, y1], -1)], 1)
        faces = np.concatenate([up_rgb[cu[iy, ix]], down_rgb[cd[iy, ix]]])
        axes[2].add_collection(PolyCollection(np.concatenate([upper, lower]), facecolors=faces, edgecolors="none",
                                              linewidths=0, antialiased=False, rasterized=True))
    axes[2].set_xlim(ex[0], ex[-1])
    axes[2].set_ylim(ey[0], ey[-1])
    names = [f"{mass}, up sweep", f"{mass}, down sweep", f"coexisting motions: {int(mask.sum())} cells"]
    for i, (a, name) in enumerate(zip(axes, names)):
        a.set_title(_escaped(name))
        a.set_xlabel(axis_label(xc))
        if i == 0:
            a.set_ylabel(axis_label(yc))
    if legend:
        counts = Counter(tu[cu[cu >= 0]].tolist()) + Counter(td[cd[cd >= 0]].tolist())
        fig.legend(handles=_legend_handles(counts, max_legend), loc="outside right upper",
                   fontsize="small", frameon=False, title=_escaped(f"{mass} n-p-q (cells, up + down)"),
                   title_fontsize="small")
    return axes


def _diverging(t):
    """RGB (0-255) of t in [-1, 1] on the diverging scale, rounded as render rounds."""
    t = np.clip(t, -1.0, 1.0)
    end = np.where(t[..., None] < 0, np.array(_LOW, float), np.array(_HIGH, float))
    w = np.abs(t)[..., None]
    return np.round(255.0 + w * (end - 255.0)).astype(int)


def _about(v, centre):
    """RGB (0-255) of the values `v` on the diverging scale centred at
    `centre`, full colour at the value farthest from it (at 1 from it where
    all are at it), grey where a value is not finite; and that reach."""
    finite = np.isfinite(v)
    reach = float(np.max(np.abs(v[finite] - centre))) if finite.any() else 0.0
    reach = reach if reach > 0 else 1.0
    rgb = np.where(finite[..., None], _diverging((np.where(finite, v, centre) - centre) / reach), np.array(_NONE))
    return rgb, reach


def _diverging_cmap():
    """The diverging scale as a matplotlib colour map, for colour bars."""
    from matplotlib.colors import LinearSegmentedColormap

    return LinearSegmentedColormap.from_list(
        "vibroatlas-diverging", [np.array(_LOW) / 255, (1, 1, 1), np.array(_HIGH) / 255])


def _paint(ds, name, rgb, ax, title):
    """Draws variable `name`'s cells of `ds` in the colours `rgb` (0-255, one
    per cell) on `ax` (a new figure's when None), with the axes' labels and
    `title`; the Axes."""
    import matplotlib.pyplot as plt

    ydim, xdim = ds[name].dims
    present, codes = np.unique(rgb.reshape(-1, 3), axis=0, return_inverse=True)
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 5), layout="constrained")
    _mesh(ax, ds[xdim].values, ds[ydim].values, codes.reshape(rgb.shape[:2]), present / 255.0)
    ax.set_xlabel(axis_label(ds[xdim]))
    ax.set_ylabel(axis_label(ds[ydim]))
    ax.set_title(title)
    return ax


def scalar(ds, quantity="multiplier", ax=None, *, colorbar=True, title=None):
    """Draws one number per cell of a sweep group, as `vibroatlas render
    --view multiplier|lyapunov` does, and returns the Axes: `multiplier`,
    the largest Floquet multiplier modulus of periodic cells, on a diverging
    scale centred at 1 (where stability is lost), or `lyapunov`, the largest
    Lyapunov exponent of cells without a period, centred at 0; blue below,
    white at the centre, red above, reaching full colour at the value
    farthest from it; cells without the number grey. Each cell is drawn in
    exactly the colour render gives it."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize

    if quantity not in _CENTRE:
        raise ValueError(f"quantity: expected multiplier or lyapunov, got {quantity!r}")
    node = _node_name(ds)
    ds = _dataset(ds)
    if quantity not in ds:
        raise ValueError(f"{quantity}: this group has no such variable")
    centre = _CENTRE[quantity]
    rgb, reach = _about(np.asarray(ds[quantity].values, float), centre)
    sweep = f"{node} sweep: " if node else ""
    attrs = ds[quantity].attrs
    ax = _paint(ds, quantity, rgb, ax, title if title is not None else _escaped(sweep + attrs.get("long_name", quantity)))
    if colorbar:
        scale = plt.cm.ScalarMappable(Normalize(centre - reach, centre + reach), _diverging_cmap())
        bar = ax.figure.colorbar(scale, ax=ax)
        bar.set_label(_escaped(attrs.get("symbol", quantity)))
    return ax


# render's sequential scale of a quantity of the steady motion (viridis, five stops).
_SEQUENTIAL = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], float)


def _sequential(t):
    """RGB (0-255) of t in [0, 1] on the sequential scale, rounded as render rounds."""
    t = np.clip(t, 0.0, 1.0) * (len(_SEQUENTIAL) - 1)
    k = np.minimum(np.floor(t).astype(int), len(_SEQUENTIAL) - 2)
    f = (t - k)[..., None]
    return np.round(_SEQUENTIAL[k] + f * (_SEQUENTIAL[k + 1] - _SEQUENTIAL[k])).astype(int)


def quantity(ds, name, ax=None, *, colorbar=True, title=None):
    """Draws a quantity of the steady motion of a sweep group (`max_abs_x_M1`,
    `impact_speed_max_A1`, `power_in`: docs/models.md, section 13), as
    `vibroatlas render --view NAME` does, and returns the Axes: a sequential
    scale (viridis) from the smallest value to the largest, or, where the
    values take both signs, the diverging scale centred at 0 (blue below,
    white at 0, red above, full colour at the value farthest from 0); cells
    without a value grey, each cell in exactly the colour render gives it. As with
    `--view`, `multiplier` and `lyapunov`, the numbers of the classification,
    are drawn as `scalar` draws them."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap, Normalize

    if name in _CENTRE:
        return scalar(ds, name, ax, colorbar=colorbar, title=title)
    node = _node_name(ds)
    ds = _dataset(ds)
    # A quantity is a per-cell variable with its symbol (`class`, a label's
    # code or a state are variables of the group, not quantities).
    stored = [n for n in ds.data_vars if "symbol" in ds[n].attrs and ds[n].dims == ds["class"].dims]
    if name not in stored:
        raise ValueError(f"{name}: not a quantity of this group ({', '.join(stored) or 'it stores none'})")
    v = np.asarray(ds[name].values, float)
    finite = np.isfinite(v)
    lo, hi = (float(v[finite].min()), float(v[finite].max())) if finite.any() else (0.0, 1.0)
    if not math.isfinite(hi - lo):
        raise ValueError(f"{name}: its values, {lo:g} to {hi:g}, span more than a float holds; draw a scaled copy")
    if hi <= lo:
        lo, hi = lo - 0.5, lo + 0.5
    signed = lo < 0.0 < hi
    if signed:
        rgb, reach = _about(v, 0.0)
        lo, hi = -reach, reach
    else:
        rgb = np.where(finite[..., None], _sequential((np.where(finite, v, lo) - lo) / (hi - lo)), np.array(_NONE))
    sweep = f"{node} sweep: " if node else ""
    ax = _paint(ds, name, rgb, ax, title if title is not None else _escaped(sweep + ds[name].attrs.get("long_name", name)))
    if colorbar:
        cmap = _diverging_cmap() if signed else ListedColormap(_sequential(np.linspace(0.0, 1.0, 256)) / 255.0)
        bar = ax.figure.colorbar(plt.cm.ScalarMappable(Normalize(lo, hi), cmap), ax=ax)
        units = ds[name].attrs.get("units", "1")
        bar.set_label(_escaped(name if units == "1" else f"{name} ({units})"))
    return ax


def difference(tree, name, ax=None, *, colorbar=True, title=None):
    """Draws a quantity of the steady motion, the up sweep's value less the
    down sweep's, as `vibroatlas render --view NAME --sweep hysteresis` does,
    and returns the Axes: a diverging scale centred at 0 (white: the two
    legs agree), full colour at the largest difference, cells without a
    value in either sweep grey, each cell in render's colour. tree: a
    DataTree with /up and /down, or a path."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize

    tree = _both(tree, "difference")
    up, down = _dataset(tree["up"]), _dataset(tree["down"])
    if name not in up:
        stored = [n for n in up.data_vars if "symbol" in up[n].attrs and up[n].dims == up["class"].dims]
        raise ValueError(f"{name}: not a quantity of this atlas ({', '.join(stored) or 'it stores none'})")
    rgb, reach = _about(np.asarray(up[name].values, float) - np.asarray(down[name].values, float), 0.0)
    long_name = up[name].attrs.get("long_name", name)
    ax = _paint(up, name, rgb, ax, title if title is not None else _escaped(f"up sweep less down sweep: {long_name}"))
    if colorbar:
        bar = ax.figure.colorbar(plt.cm.ScalarMappable(Normalize(-reach, reach), _diverging_cmap()), ax=ax)
        units = up[name].attrs.get("units", "1")
        bar.set_label(_escaped(f"Δ {name}" if units == "1" else f"Δ {name} ({units})"))
    return ax


# Colours of the sweeps in diagrams (render's): down vermillion rings, up
# blue dots drawn inside them, fresh cells black dots; sizes in points.
_SWEEP_COLOUR = {"down": (213, 94, 0), "up": (0, 114, 178), "fresh": (0, 0, 0)}
_RING_PT, _DOT_PT = 1.7, 0.9


def _names(attr):
    """A list attribute of the file (comma-separated text, or an array)."""
    if isinstance(attr, str):
        return [s for s in attr.split(",") if s]
    return [str(s) for s in np.atleast_1d(attr)]


def _sections(tree, sweep, name):
    """Section `name` (period or a stop) of a sweep: per cell i (iy * nx + ix)
    its rows, as a function of i."""
    node = tree[f"{sweep}/sections/{name}"]
    offsets, values = np.asarray(node["offsets"].values), np.asarray(node["values"].values)
    return lambda cell: values[offsets[cell]:offsets[cell + 1]]


def _stop_events(attrs):
    """`impact` or `contact` per stop, as render's labels say (a soft stop is
    in contact for a while), from the file's `stop_laws`."""
    from . import _native

    laws = attrs.get("stop_laws")
    return [e[:-1] for e in _native.stop_events(None if laws is None else str(laws), str(attrs.get("scene", "")))]


def row(tree, at=None, variable=None, fig=None):
    """The bifurcation diagram of one row of an atlas (or of a sweep file),
    as `vibroatlas render --row NAME=VALUE` (`render SWEEP.h5`) draws it:
    one panel per section against the row's parameter, stacked on a shared
    axis: the period section (the state component `variable` at t = kT,
    default the position of the first labelled mass, x_M1) and, per stop
    with impacts, each impact's normal speed |n·v| just before it; the down
    sweep as vermillion rings, the up sweep as blue dots inside them (where
    they agree both show), fresh cells as black dots.

    tree: a DataTree (va.atlas, va.open) or a path; at: the value of the y
    axis whose nearest row is drawn (default: the first row, a sweep file's
    only one); fig: the figure to draw into. Returns the panels' Axes, top
    to bottom."""
    import matplotlib.pyplot as plt

    from . import open as open_atlas

    if not hasattr(tree, "children"):
        tree = open_atlas(tree)
    attrs = tree.attrs
    sweeps = [s for s in ("down", "up", "fresh") if s in tree.children]
    if not sweeps:
        if getattr(tree, "name", None) in ("down", "up", "fresh"):
            raise ValueError(f"row draws the whole tree (va.open(path)) or a path, got its group {tree.name!r}")
        raise ValueError("no sweep group (up, down or fresh) in this tree")
    if int(attrs.get("section_cap", 1)) == 0:
        raise ValueError("this file keeps no section points (section_cap 0): "
                         "run it again with a section cap above 0 to draw its diagram")
    first = _dataset(tree[sweeps[0]])
    code = first[f"label_code_{_first_mass(first)}"]
    ydim, xdim = code.dims
    xs, ys = first[xdim], first[ydim]
    yv = np.asarray(ys.values, float)
    if at is None:
        iy = 0
    else:
        if isinstance(at, bool) or not isinstance(at, numbers.Real):
            raise TypeError(f"at: expected a number, got {at!r}")
        if not math.isfinite(at):
            raise ValueError(f"at: not a finite number, got {at}")
        lo, hi = float(yv.min()), float(yv.max())
        if not lo - 1e-9 * (1 + abs(lo)) <= at <= hi + 1e-9 * (1 + abs(hi)):
            raise ValueError(f"at: {ydim} = {at} is outside the file's {lo:g} to {hi:g}")
        iy = int(np.argmin(np.abs(yv - float(at))))
    nx = len(xs)
    state = _names(attrs["state_masses"])
    dof = len(state)
    components = [f"x_{m}" for m in state] + [f"v_{m}" for m in state]
    if variable is None:
        masses = _names(attrs["masses"])
        variable = f"x_{masses[0]}" if masses and f"x_{masses[0]}" in components else components[0]
    if variable not in components:
        raise ValueError(f"variable {variable!r}: expected one of {', '.join(components)}")
    k = components.index(variable)
    stops = _names(attrs["stops"])
    events = _stop_events(attrs)
    normals = np.asarray(attrs["stop_normals"], float).reshape(len(stops), dof)
    x = np.asarray(xs.values, float)

    def points(sweep, panel):
        rows = _sections(tree, sweep, "period" if panel == 0 else stops[panel - 1])
        out = []
        for ix in range(nx):
            for r in rows(iy * nx + ix):
                out.append((x[ix], r[k] if panel == 0 else abs(float(normals[panel - 1] @ r[1 + dof:1 + 2 * dof]))))
        return np.array(out, float).reshape(-1, 2)

    series = [{s: points(s, p) for s in sweeps} for p in range(1 + len(stops))]
    shown = [p for p in range(len(series)) if p == 0 or any(len(v) for v in series[p].values())]
    if fig is None:
        fig = plt.figure(figsize=(8, 1.2 + 2.2 * len(shown)), layout="constrained")
    elif fig.get_layout_engine() is None:
        fig.set_layout_engine("constrained")  # the stacked panels' labels apart
    axes = fig.subplots(len(shown), 1, sharex=True, squeeze=False)[:, 0]
    for ax, p in zip(axes, shown):
        for sweep in sweeps:
            pts = series[p][sweep]
            colour = tuple(c / 255 for c in _SWEEP_COLOUR[sweep])
            if sweep == "down":
                ax.scatter(pts[:, 0], pts[:, 1], s=(2 * _RING_PT) ** 2, facecolors="none", edgecolors=colour,
                           linewidths=0.6, label="down sweep")
            else:
                ax.scatter(pts[:, 0], pts[:, 1], s=(2 * _DOT_PT) ** 2, color=colour, linewidths=0,
                           label=f"{sweep} sweep" if sweep == "up" else "fresh cells")
        ax.set_ylabel(_subscripts(f"{variable} at t = kT") if p == 0 else _escaped(f"{events[p - 1]} speed at {stops[p - 1]}"))
    axes[-1].set_xlabel(axis_label(xs))
    silent = [p for p in range(1, len(series)) if p not in shown]
    fixed = f", {axis_label(ys)} = {float(ys.values[iy]):.4g}" if len(ys) > 1 else ""
    none = _escaped("; ".join(f"no {events[p - 1]}s at {stops[p - 1]}" for p in silent))
    axes[0].set_title(f"bifurcation diagram in {axis_label(xs)}{fixed}" + (f"; {none}" if none else ""), wrap=True)
    axes[0].legend(loc="lower center", bbox_to_anchor=(0.5, 1.12), ncols=len(sweeps), frameon=False,
                   fontsize="small")
    return list(axes)


# The masses' curves in portraits (Okabe–Ito, as `vibroatlas cell --portrait`).
_CURVES = [(0, 114, 178), (213, 94, 0), (0, 158, 115), (204, 121, 167)]


def _cell_part(result, key, keyword):
    """result[key] of a va.cell result, or a ValueError naming the keyword that computes it."""
    if not isinstance(result, dict):
        raise TypeError(f"expected the dict of va.cell(..., {keyword}), got {type(result).__name__}")
    if key not in result:
        raise ValueError(f"this cell result has no {key}: compute it with va.cell(..., {keyword})")
    return result[key]


def portrait(result, fig=None):
    """The phase portraits and time series of a cell's steady motion, as
    `vibroatlas cell --portrait FILE` draws them: per mass its (x, v) path
    over the classified window, its frame stops as vertical lines and its
    impacts as black dots; below, every mass's position against time with
    every event marked.

    result: the dict of va.cell(..., portrait=True); fig: the figure to
    draw into. Returns the Axes: the masses' portraits, then the time
    series."""
    import matplotlib.pyplot as plt

    p = _cell_part(result, "portrait", "portrait=True")
    masses = list(p["masses"])
    t, x, v = (np.asarray(p[k], float) for k in ("t", "x", "v"))
    x, v = x.reshape(len(masses), -1), v.reshape(len(masses), -1)
    rows = [i for i, _ in p["events"]]
    impacts = [i for i, what in p["events"] if what.startswith("impact")]
    if fig is None:
        fig = plt.figure(figsize=(max(6.0, 3.4 * len(masses)), 6.5), layout="constrained")
    grid = fig.add_gridspec(2, max(len(masses), 1), height_ratios=[4, 3])
    axes = []
    for k, name in enumerate(masses):
        ax = fig.add_subplot(grid[0, k])
        colour = tuple(c / 255 for c in _CURVES[k % len(_CURVES)])
        ax.plot(x[k], v[k], color=colour, linewidth=0.8)
        for mass, position, stop in p["stops"]:
            if mass == k:
                ax.axvline(position, color="black", linewidth=1.0)
                ax.annotate(_escaped(stop), (position, 1.0), xycoords=("data", "axes fraction"), xytext=(2, -10),
                            textcoords="offset points", fontsize="small")
        ax.plot(x[k][impacts], v[k][impacts], "o", color="black", markersize=2.6, linestyle="none")
        ax.set_xlabel(_subscripts(f"x_{name}"))
        ax.set_ylabel(_subscripts(f"v_{name}"))
        ax.set_title(_escaped(f"{name}: phase portrait"), fontsize="medium")
        axes.append(ax)
    ax = fig.add_subplot(grid[1, :])
    for k, name in enumerate(masses):
        colour = tuple(c / 255 for c in _CURVES[k % len(_CURVES)])
        ax.plot(t, x[k], color=colour, linewidth=0.9, label=_subscripts(f"x_{name}"))
        ax.plot(t[rows], x[k][rows], "o", color="black", markersize=2.6, linestyle="none",
                label="event" if k == len(masses) - 1 else None)
    ax.set_xlabel("t")
    ax.set_ylabel("x")
    ax.set_title("positions against time (events marked)", fontsize="medium")
    ax.legend(loc="center left", bbox_to_anchor=(1.0, 0.5), frameon=False, fontsize="small")
    axes.append(ax)
    fig.suptitle(_escaped(p["title"]), wrap=True)
    return axes


def _padded(values):
    """The axis range of `values` as vibroatlas's figures take it: a margin of
    5 % of their span and at least 5 % of their magnitude (or 1e-3), so that
    points agreeing to round-off (a period-n orbit) sit among readable ticks
    instead of being spread over a range of 1e-10; -1 to 1 without values."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return -1.0, 1.0
    lo, hi = float(v.min()), float(v.max())
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    half = max(1.1 * half, 0.05 * abs(mid), 1e-3)
    return mid - half, mid + half


def sections(result, fig=None):
    """The Poincaré sections of a cell, as `vibroatlas cell --section-png
    FILE` draws them, two panels to a row: the first labelled mass's (x, v)
    at t = kT, then each stop with impacts (phase, speed just before); a
    periodic motion's few distinct points drawn large, a curve or cloud of
    many small.

    result: the dict of va.cell(..., sections=True); fig: the figure to
    draw into. Returns the panels' Axes in order."""
    import matplotlib.pyplot as plt

    s = _cell_part(result, "sections", "sections=True")
    panels = s["panels"]
    cols = min(max(len(panels), 1), 2)
    nrows = max(math.ceil(len(panels) / cols), 1)
    if fig is None:
        fig = plt.figure(figsize=(3.8 * cols, 3.3 * nrows + 0.6), layout="constrained")
    grid = fig.add_gridspec(nrows, cols)
    colour = tuple(c / 255 for c in _CURVES[0])
    axes = []
    for i, panel in enumerate(panels):
        ax = fig.add_subplot(grid[i // cols, i % cols])
        pts = np.asarray(panel["points"], float).reshape(-1, 2)
        (x0, x1), (y0, y1) = _padded(pts[:, 0]), _padded(pts[:, 1])
        # As render: on a 400 x 400 raster of the panel's ranges, few distinct points are a period.
        cells = np.round((pts - [x0, y0]) / [x1 - x0, y1 - y0] * 400)
        distinct = len(np.unique(cells, axis=0))
        ax.plot(pts[:, 0], pts[:, 1], "o", color=colour, linestyle="none",
                markersize=1.2 if distinct > 64 else 3.2, markeredgewidth=0)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_xlabel(_subscripts(panel["x"]))
        ax.set_ylabel(_subscripts(panel["y"]))
        axes.append(ax)
    fig.suptitle(_escaped(s["title"]), wrap=True)
    return axes
