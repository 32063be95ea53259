#!/usr/bin/env python3
"""Draws one mass's label map from a vibroatlas file (netCDF-4/CF layout) with
xarray and matplotlib only, no project code. Use Debian's python (python3-xarray,
python3-h5netcdf, python3-matplotlib):

    /usr/bin/python3 scripts/plot_atlas.py atlas.h5 --sweep up --mass M1 -o map.png
    /usr/bin/python3 scripts/plot_atlas.py atlas.h5 --sweep hysteresis -o hysteresis.png
    /usr/bin/python3 scripts/plot_atlas.py atlas.h5 --sweep up --size single -o map.pdf

Every label comes from the file: label_code_<mass> indexes the sweep's `label`
table, and each label is drawn in its `label_colour` (the colours of
vibroatlas's own figures), one rectangle per cell. The legend is drawn as
`vibroatlas render` draws it: the most frequent labels one by one with their
number of cells, as many as fit, and the rest summed per family of
crates/maps/src/palette.rs (`+ K more chattering (cells)`; `+ K chattering
(cells)` where that gains a column), its swatch white and hatched in the
colour of the family's most frequent label, so that it cannot be taken for a
listed label; a family of one label is that label's own row. The legend lies
outside the panels, beside or below them, in as many columns as fit; the
layout is checked after drawing (nothing off the figure, no legend row over a
panel, its labels or a title) and a problem is printed as a warning.

`--sweep hysteresis` draws three panels: up | down | the cells where the two
sweeps end on different periodic motions, i.e. the file's root `hysteresis`
mask, the cells `vibroatlas inspect` and `render` count (both sweeps periodic
and the labels of some labelled mass differ). Each such cell shows both of
the mass's labels: split along its rising diagonal, the up label's colour in
the upper-left triangle and the down label's in the lower-right, or, where
cells are smaller than 1.4 mm on the page, in diagonal stripes of the two
colours; the other cells are white. One legend: the labels of both sweeps
(cells summed over up and down), then the most frequent (up, down) pairs of
those cells. The script prints that count and, on a line of its own, the
number of cells whose labels of the mass differ at all (also where a sweep is
C, Q or U, which the mask leaves out).

Axis labels come from the coordinate variables' `long_name` and `symbol`
attributes (`forcing frequency ω`); without them (the generic `parameter
omega` of older files), a parameter named after a Greek letter gets that
letter (omega: ω, delta: δ, mu_m: μ_m), any other its name.

Sizes: without --size a screen figure (10 x 6 in, three panels 16 x 6 in,
10 pt); --size single (86 mm wide) or double (178 mm), their height chosen
for the content, or WxH in mm; --font-size PT (default 8 with --size) and
--dpi (default 300; the resolution of a PNG and of the maps inside a PDF or
SVG).
"""
import argparse
import functools
import math
import os
import re
import sys
import tomllib
from collections import Counter

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.colors import BoundaryNorm, ListedColormap  # noqa: E402
from matplotlib.font_manager import FontProperties  # noqa: E402
from matplotlib.patches import Polygon, Rectangle  # noqa: E402
from matplotlib.transforms import Bbox  # noqa: E402

NAMES = {"C": "C chaotic", "Q": "Q quasi-periodic", "U": "U unresolved", "not-computed": "not computed"}
# Families of crates/maps/src/palette.rs `family()`, in the order legends list them.
FAMILIES = ["no impact", "fundamental", "subharmonic", "chattering", "complete chattering",
            "chaotic", "quasi-periodic", "unresolved", "not computed", "other"]
GREEK = {g: chr(c) for g, c in [
    ("alpha", 0x3B1), ("beta", 0x3B2), ("gamma", 0x3B3), ("delta", 0x3B4), ("epsilon", 0x3B5),
    ("zeta", 0x3B6), ("eta", 0x3B7), ("theta", 0x3B8), ("kappa", 0x3BA), ("lambda", 0x3BB),
    ("mu", 0x3BC), ("nu", 0x3BD), ("xi", 0x3BE), ("rho", 0x3C1), ("sigma", 0x3C3), ("tau", 0x3C4),
    ("phi", 0x3C6), ("chi", 0x3C7), ("psi", 0x3C8), ("omega", 0x3C9)]}
WHITE = (255, 255, 255)
GROUP_PAIRS = (90, 90, 90)  # hatch of the row summing the pairs not listed (as vibroatlas render draws it)
MM = 1 / 25.4  # inches per mm
SIZES_MM = {"single": 86.0, "double": 178.0}


# ---------------------------------------------------------------- reading

def root(path):
    """Root attributes and the root `hysteresis` flag [y, x] (None if absent)."""
    st = os.stat(path)
    return _root(path, st.st_mtime_ns, st.st_size)


@functools.lru_cache(maxsize=8)
def _root(path, mtime, size):
    """root() of one version of the file (read once), with the root coordinates'
    attributes under the key `coordinate attributes`."""
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        hyst = ds["hysteresis"].transpose(ds.attrs["y"], ds.attrs["x"]).values if "hysteresis" in ds else None
        attrs = dict(ds.attrs)
        attrs["coordinate attributes"] = {n: dict(ds[n].attrs) for n in (attrs["x"], attrs["y"]) if n in ds.variables}
        return attrs, hyst


def load(path, sweep, mass):
    """(x values, y values, label texts [y, x], {label: RGB}) of one mass in one sweep."""
    attrs, _ = root(path)
    x, y = attrs["x"], attrs["y"]
    with xr.open_dataset(path, engine="h5netcdf", group=sweep) as ds:
        table = ds["label"].values.astype(str)
        codes = ds[f"label_code_{mass}"].transpose(y, x).values
        colours = {t: tuple(int(v) for v in c) for t, c in zip(table, ds["label_colour"].values)}
        return ds[x].values, ds[y].values, table[codes], colours


def classes(path, sweep):
    """`class` [y, x] of a sweep as u8 codes (0 periodic; 255 not computed)."""
    attrs, _ = root(path)
    with xr.open_dataset(path, engine="h5netcdf", group=sweep, mask_and_scale=False) as ds:
        return ds["class"].transpose(attrs["y"], attrs["x"]).values


def hysteresis_mask(path, masses):
    """The file's /hysteresis mask [y, x] as booleans; for a file without it, the
    same definition computed from the sweeps: both periodic and the labels of
    some labelled mass differ (crates/maps/src/hysteresis.rs)."""
    _, hyst = root(path)
    if hyst is not None:
        return hyst == 1
    both = (classes(path, "up") == 0) & (classes(path, "down") == 0)
    differ = np.zeros_like(both)
    for m in masses:
        differ |= load(path, "up", m)[2] != load(path, "down", m)[2]
    return both & differ


def stop_names(path, mass):
    """The stops that p and q of `mass` count: the root attributes p_stops and
    q_stops, else the scene TOML's [labels.<mass>] table (None if not given)."""
    attrs, _ = root(path)
    masses = [m for m in attrs.get("masses", "").split(",") if m]
    ps = attrs.get("p_stops", "").split(",")
    qs = attrs.get("q_stops", "").split(",")
    if mass in masses and len(ps) == len(masses) == len(qs) and ps[masses.index(mass)]:
        i = masses.index(mass)
        return ps[i], qs[i] or None
    labels = tomllib.loads(attrs.get("scene", "")).get("labels", {}).get(mass, {})
    return labels.get("p"), labels.get("q")


def symbol(name):
    """Greek letter for a parameter named after one (omega: ω, mu_m: μ_m, delta12:
    δ12), else the name."""
    m = re.fullmatch(r"([A-Za-z]+)(_?)(\w*)", name)
    if m and m.group(1).lower() in GREEK:
        g = GREEK[m.group(1).lower()]
        return g.upper() if m.group(1)[0].isupper() and g.upper() != g else g + m.group(2) + m.group(3)
    return name


def axis_label(path, name, short=False):
    """Axis label of coordinate `name`: `long_name symbol` from its attributes
    (the generic long_name `parameter <name>` of older files is not shown; with
    short, only the symbol), the symbol falling back to a Greek letter, then the
    name; units unless `1`."""
    a = root(path)[0]["coordinate attributes"].get(name, {})
    sym = str(a.get("symbol") or symbol(name))
    long = str(a.get("long_name") or "")
    if short or long in ("", f"parameter {name}", name, sym):
        text = sym
    elif sym in long:
        text = long
    else:
        text = f"{long} {sym}"
    units = str(a.get("units") or "1")
    return text if units in ("1", "") else f"{text} ({units})"


def present(texts):
    """[(label, cells)] of the labels present, most frequent first."""
    return sorted(Counter(np.asarray(texts).ravel().tolist()).items(), key=lambda e: (-e[1], e[0]))


def family(label):
    """The family of a label, as crates/maps/src/palette.rs `family()` names it
    (a symmetry suffix ` S`/` AS` is ignored; `not-computed` is its own)."""
    base = label.split(" ")[0]
    if base == "1-0-0":
        return "no impact"
    if base in ("C", "Q", "U"):
        return {"C": "chaotic", "Q": "quasi-periodic", "U": "unresolved"}[base]
    if base == "not-computed":
        return "not computed"
    parts = base.split("-")
    try:
        n = int(parts[0])
        counts = [None if c == "S" else int(c) for c in parts[1:]]
    except ValueError:
        return "other"
    if len(parts) != 3 or n <= 0:
        return "other"
    if None in counts:
        return "complete chattering"
    if any(c >= 6 * n for c in counts):
        return "chattering"
    return "fundamental" if n == 1 else "subharmonic"


# ---------------------------------------------------------------- drawing the cells

def edges(v):
    """Cell edges around centres v (midpoints; a single centre gets a width of 10 % of it)."""
    v = np.asarray(v, float)
    if len(v) == 1:
        h = 0.05 * abs(v[0]) or 0.5
        return np.array([v[0] - h, v[0] + h])
    mid = (v[1:] + v[:-1]) / 2
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def rgb01(c):
    return tuple(np.asarray(c, float) / 255)


def draw(ax, xs, ys, texts, colours):
    """One rectangle per cell, in the colour of its label: a ListedColormap with one
    entry per label present and boundaries between integer codes, so no colour is
    interpolated or stretched."""
    table = [t for t, _ in present(texts)]
    index = {t: i for i, t in enumerate(table)}
    codes = np.vectorize(index.get, otypes=[int])(texts)
    cmap = ListedColormap([rgb01(colours[t]) for t in table])
    norm = BoundaryNorm(np.arange(len(table) + 1) - 0.5, len(table))
    ex, ey = edges(xs), edges(ys)
    ax.pcolormesh(ex, ey, codes, cmap=cmap, norm=norm, shading="flat", antialiased=False, linewidth=0,
                  rasterized=True)
    ax.set_xlim(ex[0], ex[-1])
    ax.set_ylim(ey[0], ey[-1])
    if len(ys) == 1:  # a single sweep: one row
        ax.set_yticks(ys)


def split_mode(ax, xs, ys, dpi):
    """How the coexisting cells are drawn in `ax` at `dpi` (layout done):
    `split` (each cell cut along its diagonal) when a cell is at least 4 stripe
    widths on each side, else `stripes` (diagonal stripes of the up and down
    colours running across the cells, a fixed width on the page), and the stripe
    width in pixels (0.35 mm, at least 2 pixels)."""
    k = max(2, round(0.35 * MM * dpi))
    bb = ax.get_window_extent()
    cell = min(bb.width / len(xs), bb.height / len(ys))
    return ("split" if cell >= 4 * k else "stripes"), k


def draw_split(ax, xs, ys, mask, up, down, colours, mode, k):
    """The coexisting cells (mask) with both labels, as an image with one pixel
    per device pixel of the panel (no resampling, nothing lost between pixels):
    mode `split`: the up label's colour in each cell's upper-left triangle, the
    down label's in its lower-right one; `stripes`: diagonal stripes k pixels
    wide alternating the up and down colours. Other cells white."""
    ex, ey = edges(xs), edges(ys)
    bb = ax.get_window_extent()
    nx_px, ny_px = max(1, int(round(bb.width))), max(1, int(round(bb.height)))
    # data coordinates of the pixel centres (y from the bottom)
    px = ex[0] + (np.arange(nx_px) + 0.5) / nx_px * (ex[-1] - ex[0])
    py = ey[0] + (np.arange(ny_px) + 0.5) / ny_px * (ey[-1] - ey[0])
    cx = np.clip(np.searchsorted(ex, px, side="right") - 1, 0, len(xs) - 1)
    cy = np.clip(np.searchsorted(ey, py, side="right") - 1, 0, len(ys) - 1)
    table = sorted(set(up[mask].tolist()) | set(down[mask].tolist()))
    index = {t: i + 1 for i, t in enumerate(table)}  # 0: white
    palette = np.array([WHITE] + [colours[t] for t in table], dtype=np.uint8)
    code = np.vectorize(lambda t: index.get(t, 0), otypes=[np.int32])
    up_c = np.where(mask, code(up), 0)
    down_c = np.where(mask, code(down), 0)
    CY, CX = np.meshgrid(cy, cx, indexing="ij")
    if mode == "split":
        u = ((px - ex[cx]) / (ex[cx + 1] - ex[cx]))[None, :]
        v = ((py - ey[cy]) / (ey[cy + 1] - ey[cy]))[:, None]
        upper = v > u  # above the diagonal from lower left to upper right
    else:
        i, j = np.meshgrid(np.arange(ny_px), np.arange(nx_px), indexing="ij")
        upper = ((j - i) // k) % 2 == 0
    img = palette[np.where(upper, up_c[CY, CX], down_c[CY, CX])]
    ax.imshow(img, extent=(ex[0], ex[-1], ey[0], ey[-1]), origin="lower", interpolation="none", aspect="auto")
    ax.set_xlim(ex[0], ex[-1])
    ax.set_ylim(ey[0], ey[-1])


# ---------------------------------------------------------------- legends

class Row:
    """One legend row: a swatch (one colour, or two split diagonally), hatched
    when it stands for a group of labels, and its text."""

    def __init__(self, text, colours, hatched=False):
        self.text, self.colours, self.hatched = text, colours, hatched


class Section:
    """A legend section: title lines, then rows for the entries most frequent
    first, as many listed one by one as fit, the rest summed per group.
    entries: [(text, colours, cells, group)], most frequent first."""

    def __init__(self, title, entries, group_text, head=(), tail=(), group_colour=None):
        self.title, self.entries, self.group_text = list(title), entries, group_text
        self.group_colour = group_colour  # hatch colour of every group row (None: its most frequent entry's)
        self.head, self.tail = list(head), list(tail)
        self.short = False  # group rows `+ K <family> (cells)`, without `more`, where that gains columns
        self.stripes = False  # two-colour swatches in stripes rather than split

    def rows(self, k):
        """Head rows, the first k entries, one row per group of the others (a
        group of one entry is that entry's own row), tail rows."""
        rows = list(self.head) + [Row(t, c) for t, c, _, _ in self.entries[:k]]
        rest = {}
        for t, c, n, g in self.entries[k:]:
            e = rest.setdefault(g, [0, 0, c, t])  # entries, cells, colours and text of the most frequent
            e[0] += 1
            e[1] += n
        order = {f: i for i, f in enumerate(FAMILIES)}
        key = lambda g: tuple(order.get(f, len(order)) for f in (g if isinstance(g, tuple) else (g,)))
        for g in sorted(rest, key=key):
            count, cells, c, text = rest[g]
            if count == 1:
                rows.append(Row(text, c))
            else:
                text = self.group_text(g, count, cells, self.short)
                rows.append(Row(text, [self.group_colour or c[0]], hatched=True))
        return rows + list(self.tail)

    def fit(self, capacity, quiet=False):
        """The rows for the largest k whose rows fit in `capacity` (all of them
        grouped, cut to capacity, if even that does not fit)."""
        for k in range(min(len(self.entries), max(capacity, 0)), -1, -1):
            rows = self.rows(k)
            if len(rows) <= capacity:
                return rows
        if quiet:
            return None
        print(f"plot_atlas: warning: the legend has room for {capacity} rows, fewer than its "
              f"{len(rows)} groups; some are left out (use a larger --size or a smaller --font-size)", file=sys.stderr)
        keep = max(capacity - len(self.tail), 0)
        return (rows[:keep] + self.tail)[:max(capacity, 0)]


class Metrics:
    """Sizes in points of the legend's text at font size fs."""

    def __init__(self, fig, fs):
        self.fig, self.fs = fig, fs
        self.renderer = fig.canvas.get_renderer()
        self.font, self.bold = FontProperties(size=fs), FontProperties(size=fs, weight="bold")
        self.row = 1.45 * fs
        self.swatch = 1.0 * fs
        self.gap = 0.5 * fs
        self.colgap = 1.2 * fs
        self.pad = 0.4 * fs
        self.cache = {}

    def width(self, text, bold=False):
        key = (text, bold)
        if key not in self.cache:
            w, _, _ = self.renderer.get_text_width_height_descent(text, self.bold if bold else self.font, ismath=False)
            self.cache[key] = w * 72 / self.fig.dpi
        return self.cache[key]

    def title_w(self, section):
        return max([self.width(t, bold=True) for t in section.title] or [0])

    def rows_w(self, rows):
        return self.swatch + self.gap + max([self.width(r.text) for r in rows] or [0])

    def need_w(self, section):
        """Width of the section in one column, however many entries are listed."""
        widest = max(self.rows_w(section.rows(k)) for k in range(len(section.entries) + 1))
        return max(widest, self.title_w(section)) + 2 * self.pad


class Placed:
    """A section laid out in columns: its rows, columns, rows a column, column
    widths, and its size in points."""

    def __init__(self, m, section, rows, ncol):
        self.section, self.rows, self.ncol = section, rows, ncol
        self.per_col = math.ceil(len(rows) / ncol) if rows else 0
        cols = [rows[i:i + self.per_col] for i in range(0, len(rows), self.per_col or 1)]
        self.colws = [m.rows_w(c) for c in cols]  # each column as wide as its own rows
        self.w = max(sum(self.colws) + (len(cols) - 1) * m.colgap, m.title_w(section)) + 2 * m.pad
        self.h = (len(section.title) + self.per_col) * m.row + 2 * m.pad
        self.listed = sum(1 for r in rows if not r.hatched)


def place_section(m, section, w, h=None, max_rows=10 ** 6):
    """The best layout of a section in a box w points wide and h tall (None: as
    tall as it needs, at most max_rows rows a column, never fewer than with
    every entry grouped): the most entries listed, then the fewest rows a
    column, then group rows written `+ K more <family> (cells)` rather than the
    shorter `+ K <family> (cells)`. None if even its grouped rows do not fit."""
    best, best_key = None, None
    full = len(section.rows(len(section.entries)))
    least = len(section.rows(0))
    for short in (False, True):
        section.short = short
        for ncol in range(1, max(1, full) + 1):
            if h is None:
                per_col = max(math.ceil(least / ncol), min(max_rows, math.ceil(full / ncol)))
            else:
                per_col = int((h - 2 * m.pad) // m.row) - len(section.title)
            rows = section.fit(ncol * per_col, quiet=True)
            if rows is None:
                continue
            p = Placed(m, section, rows, ncol)
            if p.w > w + 0.01:
                if ncol * m.swatch > w:
                    break
                continue
            key = (p.listed, -p.per_col, not short, -ncol)
            if best is None or key > best_key:
                best, best_key = p, key
            if len(rows) == full and ncol * per_col >= full:
                break  # every entry listed: more columns only spread them out
    section.short = False
    return best


def place_forced(m, section, w, h):
    """Fallback when nothing fits: one column, rows cut to the height (warns)."""
    per_col = max(0, int((h - 2 * m.pad) // m.row) - len(section.title))
    return Placed(m, section, section.fit(per_col), 1)


def draw_swatch(ax, x, y, s, row, artists, stripes=False):
    """Swatch of side s with its top-left corner at (x, y) (points, y down): one
    colour; two split along the rising diagonal (up upper-left, down
    lower-right) or, with stripes, in diagonal stripes like the panel; a group
    of labels white, hatched in its colour (as `vibroatlas render` draws it), so
    that it cannot be taken for a listed label."""
    cs = row.colours
    square = Rectangle((x, y - s), s, s, facecolor="white" if row.hatched else rgb01(cs[0]), edgecolor="none")
    artists.append(ax.add_patch(square))
    if row.hatched:  # lines x' + y' = c s (falling), in the colour
        segs = []
        for c in np.arange(1 / 3, 2, 1 / 3):
            x0, x1 = max(0, c * s - s), min(s, c * s)
            segs.append([(x + x0, y - s + c * s - x0), (x + x1, y - s + c * s - x1)])
        artists.append(ax.add_collection(LineCollection(segs, colors=[rgb01(cs[0])], linewidths=1.1,
                                                        capstyle="butt")))
    elif len(cs) == 2 and not stripes:
        artists.append(ax.add_patch(Polygon([(x + s, y - s), (x + s, y), (x, y - s)], facecolor=rgb01(cs[1]),
                                            edgecolor="none")))
    elif len(cs) == 2:
        b = s / 4  # bands of the down colour between the lines y' = x' + c b and y' = x' + (c + 1) b
        for c in (-4, -2, 0, 2):
            band = Polygon([(x - s, y - 2 * s + c * b), (x + 2 * s, y + s + c * b),
                            (x + 2 * s, y + s + (c + 1) * b), (x - s, y - 2 * s + (c + 1) * b)],
                           facecolor=rgb01(cs[1]), edgecolor="none")
            ax.add_patch(band)
            band.set_clip_path(square)  # (checked as the square: the band itself is longer)
    artists.append(ax.add_patch(Rectangle((x, y - s), s, s, facecolor="none", edgecolor="0.35", linewidth=0.5)))


def draw_section(ax, m, p, x, y, artists):
    """Draws a placed section with its top-left corner at (x, y) in points (y
    down from the top of the legend area): title lines, then rows in columns,
    top to bottom."""
    ty = y + m.pad
    for line in p.section.title:
        artists.append(ax.text(x + m.pad, -(ty + m.row / 2), line, fontproperties=m.bold, va="center", ha="left"))
        ty += m.row
    for i, row in enumerate(p.rows):
        c = i // p.per_col
        cx = x + m.pad + sum(p.colws[:c]) + c * m.colgap
        cy = ty + (i % p.per_col) * m.row
        if row.colours:
            draw_swatch(ax, cx, -(cy + (m.row - m.swatch) / 2), m.swatch, row, artists, p.section.stripes)
        artists.append(ax.text(cx + m.swatch + m.gap, -(cy + m.row / 2), row.text, fontproperties=m.font,
                               va="center", ha="left"))


def label_section(title, counts, colours):
    entries = [(f"{NAMES.get(t, t)} ({n})", [colours[t]], n, family(t)) for t, n in counts]
    return Section(title, entries, lambda g, k, n, short: f"+ {k}{'' if short else ' more'} {g} ({n})")


def pair_section(pairs, colours, n_white, mass_same):
    """(up, down) pairs of the coexisting cells, most frequent first."""
    entries = []
    for (u, d), n in pairs:
        note = " *" if u == d else ""
        entries.append((f"{NAMES.get(u, u)} / {NAMES.get(d, d)} ({n}){note}", [colours[u], colours[d]], n, "pairs"))
    tail = [Row(f"white: same motion ({n_white})", [WHITE])]
    if mass_same:
        tail.append(Row(f"* same label, another mass differs ({mass_same})", None))
    return Section(["coexisting motions (cells)", "\u25e4 up / \u25e2 down label"], entries,
                   lambda g, k, n, short: f"+ {k}{'' if short else ' more'} pairs ({n})", tail=tail,
                   group_colour=GROUP_PAIRS)


# ---------------------------------------------------------------- figure layout

class Style:
    """Figure size (inches; height None: chosen from the content), font size, dpi."""

    def __init__(self, size=None, font_size=None, dpi=300):
        self.paper = size is not None
        self.w, self.h = parse_size(size) if size else (None, None)
        self.fs = font_size or (8 if self.paper else 10)
        self.dpi = dpi


def parse_size(text):
    """single | double | WxH (mm) -> (width, height or None) in inches."""
    if text in SIZES_MM:
        return SIZES_MM[text] * MM, None
    m = re.fullmatch(r"\s*([0-9.]+)\s*[x×]\s*([0-9.]+)\s*(mm)?\s*", text)
    if not m:
        raise argparse.ArgumentTypeError(f"--size {text!r}: use single, double or WxH in mm (e.g. 120x80)")
    w, h = float(m.group(1)), float(m.group(2))
    if w < 30 or h < 25:
        raise argparse.ArgumentTypeError(f"--size {text}: at least 30 x 25 mm")
    return w * MM, h * MM


def plan(style, panels, sections, title=None):
    """Figure size (inches), legend placement (`right` or `below`), the legend
    area's size asked for (inches: its width beside, its height below) and the
    first height (below) or width (beside) ratio of the legend to the panels:
    beside, as wide as its widest section (at most 42 % of the figure); below,
    as tall as its sections need (at most 12 rows a column at a single-column
    width, 8 under three panels, 10 wider; at most 45 % of a figure whose
    height is given)."""
    probe = plt.figure(dpi=style.dpi)
    m = Metrics(probe, style.fs)
    if not style.paper:
        w, h = (10.0, 6.0) if panels == 1 else (16.0, 6.0)
        place = "right"
    else:
        w, h = style.w, style.h
        if h is not None:
            place = "right" if w / h >= (1.3 if panels == 1 else 2.6) else "below"
        else:
            place = "right" if panels == 1 and w >= 150 * MM else "below"
    if place == "right":
        want = min(max(m.need_w(s) for s in sections) / 72, 0.42 * w)
        if h is None:
            h = 0.62 * w
        ratio = want / (w - want) * panels
    else:
        max_rows = 10 if w >= 120 * MM else 12 if panels == 1 else 8
        placed = arrange(m, sections, "below", w * 72 - 4, None, max_rows=max_rows)
        want = max(y + p.h for p, _, y in placed) / 72
        if h is None:  # the panels keep a pleasant aspect, the legend below them
            panel_w = (w - 0.6 - 0.1 * (panels - 1)) / panels
            h = panel_w * (0.72 if panels == 1 else 0.95) + 0.55 + (0.2 if title else 0) + want
        else:
            want = min(want, 0.45 * h)
        ratio = want / (h - want)
    plt.close(probe)
    return (w, h), place, want, ratio


def arrange(m, sections, where, bw, bh, max_rows=10 ** 6):
    """[(placed section, x, y)] in a legend area bw points wide and bh tall
    (None: as tall as they need, at most max_rows rows a column). Beside the
    panels (`right`) the sections are stacked; below them side by side when
    they fit, else stacked; whichever lists the most entries, those of the
    first section (the labels) counted twice (then is the lowest; the lowest
    first when the height is free). Stacked, the later section (the pairs)
    lists at least 3 entries."""
    options = []
    if len(sections) == 1:
        p = place_section(m, sections[0], bw, bh, max_rows) or place_forced(m, sections[0], bw, bh or m.row * 3)
        return [(p, 0, 0)]
    if where == "below":  # side by side: try splits of the width
        for f in np.arange(0.3, 0.76, 0.05):
            a = place_section(m, sections[0], f * bw, bh, max_rows)
            b = a and place_section(m, sections[1], bw - a.w, bh, max_rows)
            if a and b:
                options.append(([(a, 0, 0), (b, a.w, 0)], 2 * a.listed + b.listed, max(a.h, b.h)))
    # stacked
    if bh is None:
        a = place_section(m, sections[0], bw, None, max_rows)
        b = place_section(m, sections[1], bw, None, max_rows)
        if a and b:
            options.append(([(a, 0, 0), (b, 0, a.h)], 2 * a.listed + b.listed, a.h + b.h))
    else:
        # the later section (the pairs) at least its title, tail and 3 entries;
        # every split of the height between the two by whole rows
        k = min(len(sections[1].entries), 3)
        least = (len(sections[1].title) + len(sections[1].rows(k))) * m.row + 2 * m.pad
        for hb in np.arange(least, bh, m.row):
            a = place_section(m, sections[0], bw, bh - hb)
            b = a and place_section(m, sections[1], bw, bh - a.h)
            if a and b and b.listed >= k:
                options.append(([(a, 0, 0), (b, 0, a.h)], 2 * a.listed + b.listed, a.h + b.h))
    if not options:
        a = place_forced(m, sections[0], bw, (bh or 1e9) * 0.6)
        b = place_forced(m, sections[1], bw, (bh or 1e9) - a.h)
        return [(a, 0, 0), (b, 0, a.h)]
    if bh is None:  # the height is free: the lowest, then the most listed
        return min(options, key=lambda o: (o[2], -o[1]))[0]
    return max(options, key=lambda o: (o[1], -o[2]))[0]


def layout_problems(fig):
    """What is wrong with a drawn figure's layout: a panel (with its ticks and
    labels), a title or a legend row off the figure, a legend row over a panel,
    its labels or the title, panels or their titles overlapping. Empty when all
    is well."""
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    tol = 1.0  # pixels
    inside = lambda b: (b.x0 >= -tol and b.y0 >= -tol and b.x1 <= fig.bbox.width + tol
                        and b.y1 <= fig.bbox.height + tol)
    problems = []
    panels = [a for a in fig.axes if a.axison]
    tight = {a: a.get_tightbbox(r) for a in panels}
    titles = [(t.get_text(), t.get_window_extent(r)) for t in fig.texts if t.get_text()]
    titles += [(a.title.get_text(), a.title.get_window_extent(r)) for a in panels if a.get_title()]
    titles += [(t.get_text(), t.get_window_extent(r)) for a in panels for t in (a.xaxis.label, a.yaxis.label)
               if t.get_text()]
    for a in panels:
        if not inside(tight[a]):
            problems.append(f"panel '{a.get_title()}' (with its labels) runs off the figure")
    for i, (text, b) in enumerate(titles):
        if not inside(b):
            problems.append(f"title {text!r} runs off the figure")
        for other, c in titles[i + 1:]:
            if b.overlaps(c):
                problems.append(f"titles or axis labels {text!r} and {other!r} overlap")
    for art in getattr(fig, "_legend_artists", []):
        b = art.get_window_extent(r)
        what = art.get_text() if hasattr(art, "get_text") else type(art).__name__
        if not inside(b):
            problems.append(f"legend {what!r} runs off the figure")
        if b.width <= 0:
            continue
        hit = [t for t, c in titles if b.overlaps(c)]
        hit += [f"panel '{a.get_title()}'" for a in panels if b.overlaps(tight[a])]
        if hit:
            problems.append(f"legend {what!r} overlaps {hit[0]}")
    for i, a in enumerate(panels):
        for c in panels[i + 1:]:
            if a.get_window_extent(r).overlaps(c.get_window_extent(r)):
                problems.append(f"panels '{a.get_title()}' and '{c.get_title()}' overlap")
    return problems


# ---------------------------------------------------------------- figures

def legend_title(path, mass):
    """Legend heading lines: the mass and what p and q count."""
    p, q = stop_names(path, mass)
    return [f"{mass} label n-p-q (cells)"] + ([f"p: impacts at {p}, q: at {q}"] if p and q else [])


def label_axes(ax, path, attrs, ylabel=True, short=False):
    ax.set_xlabel(axis_label(path, attrs["x"], short))
    if ylabel:
        ax.set_ylabel(axis_label(path, attrs["y"], short))


def labels_too_long(axes):
    """Whether an axis label is longer than its panel (drawn figure)."""
    for a in axes:
        bb = a.get_window_extent()
        if a.xaxis.label.get_text() and a.xaxis.label.get_window_extent().width > bb.width:
            return True
        if a.yaxis.label.get_text() and a.yaxis.label.get_window_extent().height > bb.height:
            return True
    return False


def map_figure(path, sweep, mass, with_legend=True, style=None):
    """Figure of one mass's labels in one sweep. Without the legend the map fills
    the whole figure, 4 pixels a cell at dpi 100 (for checks that read the pixels)."""
    xs, ys, texts, colours = load(path, sweep, mass)
    attrs, _ = root(path)
    if not with_legend:
        fig = plt.figure(figsize=(max(4 * len(xs), 100) / 100, max(4 * len(ys), 100) / 100), dpi=100)
        ax = fig.add_axes([0, 0, 1, 1])
        ax.set_axis_off()
        draw(ax, xs, ys, texts, colours)
        return fig
    style = style or Style()
    sections = [label_section(legend_title(path, mass), present(texts), colours)]
    title = None
    name = f"{mass}, {sweep} sweep" if style.paper else f"{attrs.get('scene_name', '')}: {mass}, {sweep} sweep"

    def build(ratio, short=False):
        fig, axes, leg = _frame(style, 1, title, place, size, ratio)
        draw(axes[0], xs, ys, texts, colours)
        axes[0].set_title(name, fontsize=style.fs)
        label_axes(axes[0], path, attrs, short=short)
        style_ticks(axes, style)
        return fig, axes, leg

    size, place, want, ratio = plan(style, 1, sections, title)
    return finish_with(build, place, sections, style, ratio, want)


def style_ticks(axes, style):
    for a in axes:
        a.tick_params(labelsize=style.fs, length=3 if style.paper else 4, width=0.6)
        a.xaxis.label.set_size(style.fs)
        a.yaxis.label.set_size(style.fs)
        for s in a.spines.values():
            s.set_linewidth(0.6)


def hysteresis_counts(path, mass):
    """(mask, up texts, down texts, colours, counts) for the hysteresis view;
    counts: cells, coexisting (the file's mask), differing labels of the mass
    (any class), and mask cells where the mass's labels agree."""
    attrs, _ = root(path)
    masses = [m for m in attrs["masses"].split(",") if m]
    xs, ys, up, cu = load(path, "up", mass)
    _, _, down, cd = load(path, "down", mass)
    mask = hysteresis_mask(path, masses)
    counts = dict(cells=mask.size, coexisting=int(mask.sum()), differ=int((up != down).sum()),
                  mass_same=int((mask & (up == down)).sum()))
    return xs, ys, mask, up, down, {**cu, **cd}, counts


def hysteresis_figure(path, mass, style=None, report=None):
    """up | down | the coexisting cells (file's hysteresis mask), each split:
    up label upper-left, down label lower-right; cells smaller than 4 stripe
    widths (1.4 mm) in diagonal stripes of both colours instead."""
    attrs, _ = root(path)
    xs, ys, mask, up, down, colours, counts = hysteresis_counts(path, mass)
    if report:
        report(counts)
    style = style or Style()
    both = Counter(up.ravel().tolist()) + Counter(down.ravel().tolist())
    pairs = sorted(Counter(zip(up[mask].tolist(), down[mask].tolist())).items(), key=lambda e: (-e[1], e[0]))
    title_lines = legend_title(path, mass)
    title_lines[0] = f"{mass} label n-p-q (cells, up + down)"
    sections = [label_section(title_lines, sorted(both.items(), key=lambda e: (-e[1], e[0])), colours),
                pair_section(pairs, colours, counts["cells"] - counts["coexisting"], counts["mass_same"])]
    title = None if style.paper else f"{attrs.get('scene_name', '')}: {mass}, hysteresis between the up and down sweeps"
    names = [f"{mass}, up sweep", f"{mass}, down sweep", f"coexisting motions: {counts['coexisting']} cells"]
    if style.paper and style.w < 120 * MM:  # narrow panels: short titles (the mass is in the legend)
        names = ["up sweep", "down sweep", f"coexisting\n({counts['coexisting']} cells)"]

    def build(ratio, short=False):
        fig, axes, leg = _frame(style, 3, title, place, size, ratio)
        draw(axes[0], xs, ys, up, colours)
        draw(axes[1], xs, ys, down, colours)
        ex, ey = edges(xs), edges(ys)  # the coexisting cells come once the panel's size is known
        axes[2].set_xlim(ex[0], ex[-1])
        axes[2].set_ylim(ey[0], ey[-1])
        for i, (a, name) in enumerate(zip(axes, names)):
            a.set_title(name, fontsize=style.fs)
            label_axes(a, path, attrs, ylabel=(i == 0), short=short)
            if i:
                a.sharey(axes[0])
                a.tick_params(labelleft=False)
        style_ticks(axes, style)
        return fig, axes, leg

    def after(fig, axes):
        mode, k = split_mode(axes[2], xs, ys, fig.dpi)
        draw_split(axes[2], xs, ys, mask, up, down, colours, mode, k)
        if mode == "stripes":  # cells too small to split: stripes, and the legend says so
            sections[1].stripes = True
            sections[1].title[1] = "up / down label (striped)"

    size, place, want, ratio = plan(style, 3, sections, title)
    return finish_with(build, place, sections, style, ratio, want, after)


def _frame(style, panels, title, place, size, ratio):
    fig = plt.figure(figsize=tuple(size), dpi=style.dpi, layout="constrained")
    fig.get_layout_engine().set(w_pad=2 / 72, h_pad=2 / 72, wspace=0.02, hspace=0.02)
    if place == "right":
        gs = fig.add_gridspec(1, panels + 1, width_ratios=[1] * panels + [ratio])
        axes = [fig.add_subplot(gs[0, i]) for i in range(panels)]
        leg = fig.add_subplot(gs[0, panels])
    else:
        gs = fig.add_gridspec(2, panels, height_ratios=[1, ratio])
        axes = [fig.add_subplot(gs[0, i]) for i in range(panels)]
        leg = fig.add_subplot(gs[1, :])
    leg.set_axis_off()
    if title:
        fig.suptitle(title, fontsize=style.fs + 1)
    return fig, axes, leg


def finish_with(build, place, sections, style, ratio, want, after=None):
    """Lays the figure out with constrained layout, redoing it with a larger
    legend ratio until the legend area has the size asked for (`want` inches),
    freezes the layout, calls after(fig, axes) (drawing what depends on the
    panels' size in pixels), then draws the legend into its area."""
    short = False  # axis labels: `long_name symbol`, or the symbol alone where longer than a panel
    fig, axes, leg = build(ratio, short)
    w, h = fig.get_size_inches()
    for _ in range(6):
        fig.canvas.draw()
        box = leg.get_position()
        got = box.width * w if place == "right" else box.height * h
        redo = not short and labels_too_long(axes)
        short = short or redo
        if (got >= want * 0.995 or got <= 0) and not redo:
            break
        if got < want * 0.995 and got > 0:
            ratio *= want / got * 1.01
        plt.close(fig)
        fig, axes, leg = build(ratio, short)
    fig.canvas.draw()
    fig.set_layout_engine("none")
    if after:
        after(fig, axes)
    return finish_draw(fig, leg, place, sections, style)


def finish_draw(fig, leg, place, sections, style):
    w, h = fig.get_size_inches()
    m = Metrics(fig, style.fs)
    box = leg.get_position()
    if place == "right":  # beside the panels the legend may use the figure's whole height
        pad = 2 / 72 / h
        top = min(t.get_window_extent().y0 / fig.bbox.height for t in fig.texts) - pad if fig.texts else 1 - pad
        box = Bbox.from_extents(box.x0, pad, box.x1, top)
    else:  # below them, the figure's whole width
        pad = 2 / 72 / w
        box = Bbox.from_extents(pad, box.y0, 1 - pad, box.y1)
    leg.set_position(box)
    bw, bh = box.width * w * 72, box.height * h * 72
    leg.set_xlim(0, bw)
    leg.set_ylim(-bh, 0)
    artists = []
    for p, x, y in arrange(m, sections, place, bw, bh):
        draw_section(leg, m, p, x, y, artists)
    fig._legend_artists = artists
    return fig


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file")
    ap.add_argument("--sweep", help="up, down, fresh (a sweep of the file) or hysteresis; default the first sweep")
    ap.add_argument("--mass", help="default the first labelled mass")
    ap.add_argument("-o", "--output", default="map.png")
    ap.add_argument("--size", help="single (86 mm wide), double (178 mm) or WxH in mm; default a screen figure")
    ap.add_argument("--font-size", type=float, metavar="PT",
                    help="font size in points (default 8 with --size, else 10)")
    ap.add_argument("--dpi", type=float, default=300, help="resolution of a PNG (default 300)")
    args = ap.parse_args()
    try:
        style = Style(args.size, args.font_size, args.dpi)
    except argparse.ArgumentTypeError as e:
        ap.error(str(e))
    attrs, _ = root(args.file)
    sweep = args.sweep or attrs["sweeps"].split(",")[0]
    mass = args.mass or attrs["masses"].split(",")[0]
    masses = [m for m in attrs["masses"].split(",") if m]
    if mass not in masses:
        ap.error(f"--mass {mass}: the file labels {', '.join(masses)}")
    if sweep == "hysteresis":
        if not {"up", "down"} <= set(attrs["sweeps"].split(",")):
            ap.error("--sweep hysteresis needs a file with up and down sweeps (atlas --sweep both)")

        def report(c):
            print(f"coexisting motions: {c['coexisting']} of {c['cells']} cells "
                  "(the file's hysteresis mask, as inspect and render count: up and down both periodic, "
                  "labels of some mass differ)")
            print(f"{mass} labels differ: {c['differ']} of {c['cells']} cells "
                  "(any class: also where either sweep is C, Q or U)")
            if c["mass_same"]:
                print(f"  {c['mass_same']} coexisting cells have the same {mass} label (another mass's label differs)")

        fig = hysteresis_figure(args.file, mass, style, report)
    else:
        if sweep not in attrs["sweeps"].split(","):
            ap.error(f"--sweep {sweep}: the file has {attrs['sweeps']} (or hysteresis)")
        fig = map_figure(args.file, sweep, mass, style=style)
    for p in layout_problems(fig):
        print(f"plot_atlas: warning: {p}", file=sys.stderr)
    fig.savefig(args.output, dpi=style.dpi)
    w, h = fig.get_size_inches()
    print(f"wrote {args.output}: {w / MM:.0f} x {h / MM:.0f} mm, {style.fs:g} pt, {style.dpi:g} dpi")


if __name__ == "__main__":
    main()
