#!/usr/bin/env python3
"""Draws one mass's label map from a vibroatlas file (netCDF-4/CF layout) with
xarray and matplotlib only, no project code. Use Debian's python (python3-xarray,
python3-h5netcdf, python3-matplotlib):

    /usr/bin/python3 scripts/plot_atlas.py atlas.h5 --sweep up --mass M1 -o map.png
    /usr/bin/python3 scripts/plot_atlas.py atlas.h5 --sweep hysteresis -o hysteresis.png

Every label comes from the file: label_code_<mass> indexes the sweep's `label`
table, and each label is drawn in its `label_colour` (the colours of
vibroatlas's own figures), one rectangle per cell. The legend lists every label
present with its number of cells, most frequent first, and names the stops
that p and q count (the scene's [labels.<mass>] table). `--sweep hysteresis`
draws three panels: up | down | the cells where they differ (labels differ, or
the root `hysteresis` flag is set), coloured by the down label, the others
light grey.
"""
import argparse
import tomllib
from collections import Counter

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.colors import BoundaryNorm, ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

NAMES = {"C": "C chaotic", "Q": "Q quasi-periodic", "U": "U unresolved", "not-computed": "not computed"}
SAME = "same"  # hysteresis panel: cells where up and down agree
SAME_COLOUR = (240, 240, 240)  # lighter than the grey of 1-0-0 (221)


def root(path):
    """Root attributes and the root `hysteresis` flag [y, x] (None if absent)."""
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        hyst = ds["hysteresis"].transpose(ds.attrs["y"], ds.attrs["x"]).values if "hysteresis" in ds else None
        return dict(ds.attrs), hyst


def load(path, sweep, mass):
    """(x values, y values, label texts [y, x], {label: RGB}) of one mass in one sweep."""
    attrs, _ = root(path)
    x, y = attrs["x"], attrs["y"]
    with xr.open_dataset(path, engine="h5netcdf", group=sweep) as ds:
        table = ds["label"].values.astype(str)
        codes = ds[f"label_code_{mass}"].transpose(y, x).values
        colours = {t: tuple(int(v) for v in c) for t, c in zip(table, ds["label_colour"].values)}
        return ds[x].values, ds[y].values, table[codes], colours


def stop_names(path, mass):
    """The stops that p and q of `mass` count, from the scene TOML (None if not given)."""
    attrs, _ = root(path)
    labels = tomllib.loads(attrs.get("scene", "")).get("labels", {}).get(mass, {})
    return labels.get("p"), labels.get("q")


def present(texts):
    """[(label, cells)] of the labels present, most frequent first."""
    return sorted(Counter(texts.ravel().tolist()).items(), key=lambda e: (-e[1], e[0]))


def edges(v):
    """Cell edges around centres v (midpoints; a single centre gets a width of 10 % of it)."""
    v = np.asarray(v, float)
    if len(v) == 1:
        h = 0.05 * abs(v[0]) or 0.5
        return np.array([v[0] - h, v[0] + h])
    mid = (v[1:] + v[:-1]) / 2
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def draw(ax, xs, ys, texts, colours):
    """One rectangle per cell, in the colour of its label: a ListedColormap with one
    entry per label present and boundaries between integer codes, so no colour is
    interpolated or stretched."""
    table = [t for t, _ in present(texts)]
    index = {t: i for i, t in enumerate(table)}
    codes = np.vectorize(index.get, otypes=[int])(texts)
    cmap = ListedColormap([np.array(colours[t]) / 255 for t in table])
    norm = BoundaryNorm(np.arange(len(table) + 1) - 0.5, len(table))
    ex, ey = edges(xs), edges(ys)
    ax.pcolormesh(ex, ey, codes, cmap=cmap, norm=norm, shading="flat", antialiased=False, linewidth=0)
    ax.set_xlim(ex[0], ex[-1])
    ax.set_ylim(ey[0], ey[-1])
    if len(ys) == 1:  # a single sweep: one row
        ax.set_yticks(ys)


def legend(fig_or_ax, entries, colours, title, **kw):
    handles = [
        Patch(facecolor=np.array(colours[t]) / 255, edgecolor="0.6", label=f"{NAMES.get(t, t)} ({n})")
        for t, n in entries
    ]
    fig_or_ax.legend(handles=handles, title=title, fontsize=8, title_fontsize=8, ncol=1 + (len(handles) - 1) // 30, **kw)


def legend_title(path, mass):
    p, q = stop_names(path, mass)
    return f"{mass}: n-p-q" + (f", p at {p}, q at {q}" if p and q else "")


def map_figure(path, sweep, mass, with_legend=True):
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
    fig, ax = plt.subplots(figsize=(10, 6))
    draw(ax, xs, ys, texts, colours)
    ax.set_xlabel(attrs["x"])
    ax.set_ylabel(attrs["y"])
    ax.set_title(f"{attrs.get('scene_name', '')}: {mass}, {sweep} sweep")
    legend(ax, present(texts), colours, legend_title(path, mass), loc="upper left", bbox_to_anchor=(1.01, 1))
    fig.tight_layout()
    return fig


def hysteresis_figure(path, mass):
    """up | down | cells where they differ, coloured by the down label."""
    attrs, hyst = root(path)
    xs, ys, up, cu = load(path, "up", mass)
    _, _, down, cd = load(path, "down", mass)
    colours = {**cu, **cd, SAME: SAME_COLOUR}
    differ = up != down
    if hyst is not None:
        differ |= hyst == 1
    diff = np.where(differ, down, SAME)
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.5), sharex=True, sharey=True)
    for ax, texts, name in zip(axes, [up, down, diff], ["up", "down", f"up ≠ down: {differ.sum()} of {differ.size} cells"]):
        draw(ax, xs, ys, texts, colours)
        ax.set_title(name)
        ax.set_xlabel(attrs["x"])
    axes[0].set_ylabel(attrs["y"])
    nu, nd = Counter(up.ravel().tolist()), Counter(down.ravel().tolist())
    labels = sorted(set(nu) | set(nd), key=lambda t: (-(nu[t] + nd[t]), t))
    handles = [
        Patch(facecolor=np.array(colours[t]) / 255, edgecolor="0.6", label=f"{NAMES.get(t, t)} ({nu[t]} up, {nd[t]} down)")
        for t in labels
    ] + [Patch(facecolor=np.array(SAME_COLOUR) / 255, edgecolor="0.6", label=f"same in both ({(~differ).sum()})")]
    fig.legend(handles=handles, title=legend_title(path, mass), fontsize=8, title_fontsize=8, loc="lower center",
               ncol=min(6, len(handles)), bbox_to_anchor=(0.5, 0))
    fig.suptitle(f"{attrs.get('scene_name', '')}: {mass}, hysteresis between the up and down sweeps")
    fig.tight_layout(rect=(0, 0.04 + 0.035 * (1 + len(handles) // 6), 1, 1))
    return fig


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file")
    ap.add_argument("--sweep", help="up, down, fresh (a sweep of the file) or hysteresis; default the first sweep")
    ap.add_argument("--mass", help="default the first labelled mass")
    ap.add_argument("-o", "--output", default="map.png")
    args = ap.parse_args()
    attrs, _ = root(args.file)
    sweep = args.sweep or attrs["sweeps"].split(",")[0]
    mass = args.mass or attrs["masses"].split(",")[0]
    fig = hysteresis_figure(args.file, mass) if sweep == "hysteresis" else map_figure(args.file, sweep, mass)
    fig.savefig(args.output, dpi=120)


if __name__ == "__main__":
    main()
