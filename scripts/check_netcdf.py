#!/usr/bin/env python3
"""Checks that vibroatlas files read as netCDF-4/CF, with xarray through both
engines (h5netcdf and netcdf4) and h5py, and no project code. For each file and
each sweep group of the root attribute `sweeps` (and the root, for `hysteresis`):

  * the group opens with both engines; its axis dimensions are named after the
    axis parameters (root attributes x and y) and the coordinate values equal
    /axes/<name>;
  * every gridded data variable (with both axis dimensions) has units and long_name;
  * label_code_<mass> decodes through the label coordinate (ds.label[ds.label_code_M1])
    into the text that class and label_<mass> spell, the same with both engines;
    flag_values/flag_meanings list the label table; label_colour is [label, 3];
  * h5py sees the dimension scales: f[g + "/class"].dims[0][0] is the y axis;
  * every sections/<name> group opens, its CSR offsets end at the number of points;
  * scripts/plot_atlas.py draws each map (rendered to PNG in a temporary folder and
    read back with matplotlib.image) with at least one colour per label present,
    each label's label_colour among them; its figures with legends (screen and
    single-column size) keep every panel, label and legend row inside the figure
    and the legend off the panels; and the hysteresis figure, with up and down,
    counts the cells of /hysteresis and is laid out the same way.

    /usr/bin/python3 scripts/check_netcdf.py FILE... [--expect up:M1:omega=0.33,delta=0.6:1-4-4]

--expect SWEEP:MASS:NAME=VALUE[,NAME=VALUE...]:LABEL (repeatable, applies to every
file) asserts the label of the cell nearest to the point; an axis not named must
have a single value. Prints one "ok" line per file; exits 1 with the reason on
the first failure.
"""
import argparse
import os
import sys
import tempfile

import h5py
import matplotlib.image
import numpy as np
import xarray as xr

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_atlas  # noqa: E402

ENGINES = ["h5netcdf", "netcdf4"]
STUCK = 65535
CLASS_TEXT = {1: "C", 2: "U", 3: "Q", 255: "not-computed"}


class Fail(Exception):
    pass


def need(cond, msg):
    if not cond:
        raise Fail(msg)


def expected_texts(g, mass):
    """Label texts [y, x] spelt by class and label_<mass> (read with h5py)."""
    cls, lab = g["class"][()], g[f"label_{mass}"][()]
    s = lambda v: "S" if v == STUCK else str(v)
    return np.array([[f"{l[0]}-{s(l[1])}-{s(l[2])}" if c == 0 else CLASS_TEXT.get(c, f"class {c}")
                      for c, l in zip(cr, lr)] for cr, lr in zip(cls, lab)])


def check_grid(ds, where, x, y, axes):
    for name in (y, x):
        need(name in ds.dims, f"{where}: no dimension {name!r} (dims {list(ds.dims)})")
        need(name in ds.coords and np.array_equal(ds[name].values, axes[name]),
             f"{where}: coordinate {name} differs from /axes/{name}")
    for name, v in ds.data_vars.items():
        if x in v.dims and y in v.dims:
            for a in ("units", "long_name"):
                need(a in v.attrs, f"{where}: gridded variable {name} has no {a}")


def check_sweep(path, f, sweep, x, y, axes, masses):
    g = f[sweep]
    need(g["class"].dims[0][0].name == f"/{sweep}/{y}", f"{sweep}/class: h5py dims[0][0] is "
         f"{g['class'].dims[0][0].name}, not /{sweep}/{y}")
    decoded = {}
    for engine in ENGINES:
        where = f"{sweep} ({engine})"
        with xr.open_dataset(path, engine=engine, group=sweep) as ds:
            check_grid(ds, where, x, y, axes)
            table = ds["label"].values.astype(str)
            need(ds["label_colour"].shape == (len(table), 3) and ds["label_colour"].dtype == np.uint8,
                 f"{where}: label_colour is {ds['label_colour'].shape} {ds['label_colour'].dtype}, not ({len(table)}, 3) uint8")
            for m in masses:
                code = ds[f"label_code_{m}"]
                need(code.dims == (y, x), f"{where}: label_code_{m} has dims {code.dims}")
                need(list(code.attrs["flag_values"]) == list(range(len(table)))
                     and code.attrs["flag_meanings"].split() == list(table),
                     f"{where}: label_code_{m} flag_values/flag_meanings do not list the label table")
                need(0 <= int(code.min()) and int(code.max()) < len(table), f"{where}: label_code_{m} out of range")
                text = ds["label"][code].values.astype(str)
                want = expected_texts(g, m)
                bad = np.argwhere(text != want)
                need(len(bad) == 0, f"{where}: label_code_{m} decodes to {text[tuple(bad[0])] if len(bad) else ''!r} "
                     f"at [y, x] = {bad[0].tolist() if len(bad) else ''}, class and label_{m} say "
                     f"{want[tuple(bad[0])] if len(bad) else ''!r}")
                decoded.setdefault(m, text)
                need(np.array_equal(decoded[m], text), f"{where}: labels of {m} differ between engines")
        for name in g["sections"]:
            with xr.open_dataset(path, engine=engine, group=f"{sweep}/sections/{name}") as s:
                need(int(s["offsets"][-1]) == s["values"].shape[0], f"{where}: sections/{name} offsets do not end at the points")
    return decoded


def check_pixels(path, sweep, mass, tmp):
    """Renders the map alone to PNG, reads it back, compares its colours with the labels."""
    _, _, texts, colours = plot_atlas.load(path, sweep, mass)
    png = os.path.join(tmp, f"{sweep}_{mass}.png")
    fig = plot_atlas.map_figure(path, sweep, mass, with_legend=False)
    fig.savefig(png, dpi=100)
    plot_atlas.plt.close(fig)
    rgb = np.round(matplotlib.image.imread(png)[..., :3] * 255).astype(np.uint8).reshape(-1, 3)
    seen = {tuple(c) for c in np.unique(rgb, axis=0)}
    labels = [t for t, _ in plot_atlas.present(texts)]
    missing = [t for t in labels if colours[t] not in seen]
    need(not missing, f"{sweep}/{mass}: map has no pixel of the colour of {missing} ({[colours[t] for t in missing]})")
    # A colour is a function of the label text alone (the same in every map), so among the
    # hashed colours of hundreds of long-period labels two may coincide (the legends group
    # those); the map must still show every colour its labels have.
    distinct = {colours[t] for t in labels}
    need(len(seen) >= len(distinct), f"{sweep}/{mass}: {len(seen)} colours in the map for the "
         f"{len(distinct)} colours of its {len(labels)} labels")
    # The figure with its legend renders too, at screen and single-column size,
    # with nothing off the figure and the legend over no panel.
    for size in (None, "single"):
        fig = plot_atlas.map_figure(path, sweep, mass, style=plot_atlas.Style(size))
        bad = plot_atlas.layout_problems(fig)
        need(not bad, f"{sweep}/{mass}: plot_atlas.py's figure (size {size or 'screen'}): {bad[:3]}")
        fig.savefig(os.path.join(tmp, f"{sweep}_{mass}_{size}_legend.png"), dpi=60)
        plot_atlas.plt.close(fig)


def check_hysteresis(path, f, mass, tmp):
    """plot_atlas.py's hysteresis figure: it counts the cells of the root
    `hysteresis` mask (read here with h5py, the cells inspect counts), its three
    panels and legend lie inside the figure, the legend over no panel."""
    counted = []
    fig = plot_atlas.hysteresis_figure(path, mass, report=counted.append)
    want = int(np.count_nonzero(f["hysteresis"][()])) if "hysteresis" in f else None
    need(want is None or counted[0]["coexisting"] == want,
         f"hysteresis: plot_atlas.py counts {counted[0]['coexisting']} coexisting cells, /hysteresis has {want}")
    bad = plot_atlas.layout_problems(fig)
    need(not bad, f"hysteresis: plot_atlas.py's figure: {bad[:3]}")
    fig.savefig(os.path.join(tmp, "hysteresis.png"), dpi=60)
    plot_atlas.plt.close(fig)


def check_expect(decoded, spec, x, y, axes):
    sweep, mass, point, label = spec.split(":")
    need(sweep in decoded and mass in decoded[sweep], f"--expect {spec}: no sweep {sweep} or mass {mass}")
    at = dict(kv.split("=") for kv in point.split(","))
    need(set(at) <= {x, y}, f"--expect {spec}: the axes are {x} and {y}")
    idx = []
    for name in (y, x):
        v = axes[name]
        need(name in at or len(v) == 1, f"--expect {spec}: give {name} (it has {len(v)} values)")
        idx.append(int(np.argmin(np.abs(v - float(at[name])))) if name in at else 0)
    got = decoded[sweep][mass][tuple(idx)]
    need(got == label, f"--expect {spec}: the nearest cell ({x}={axes[x][idx[1]]:g}, {y}={axes[y][idx[0]]:g}) "
         f"is {got!r} in {sweep}/{mass}")


def check(path, expects):
    with h5py.File(path, "r") as f:
        a = f.attrs
        for key in ("Conventions", "title", "history", "source", "x", "y", "masses", "stops", "sweeps", "scene"):
            need(key in a, f"no root attribute {key}")
        x, y = a["x"], a["y"]
        axes = {n: f["axes"][n][()] for n in (x, y)}
        masses = [m for m in a["masses"].split(",") if m]
        sweeps = [s for s in a["sweeps"].split(",") if s]
        decoded = {s: check_sweep(path, f, s, x, y, axes, masses) for s in sweeps}
    for engine in ENGINES:
        with xr.open_dataset(path, engine=engine) as ds:
            check_grid(ds, f"root ({engine})", x, y, axes)
            for key in ("Conventions", "title", "history", "source"):
                need(key in ds.attrs, f"root ({engine}): no global attribute {key}")
    with tempfile.TemporaryDirectory() as tmp:
        for s in sweeps:
            for m in masses:
                check_pixels(path, s, m, tmp)
        if {"up", "down"} <= set(sweeps):
            with h5py.File(path, "r") as f:
                check_hysteresis(path, f, masses[0], tmp)
    for spec in expects:
        check_expect(decoded, spec, x, y, axes)
    return f"{len(axes[y])} x {len(axes[x])} ({y}, {x}), sweeps {','.join(sweeps)}, masses {','.join(masses)}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--expect", action="append", default=[], metavar="SWEEP:MASS:NAME=VALUE,...:LABEL")
    args = ap.parse_args()
    for path in args.files:
        try:
            summary = check(path, args.expect)
        except Fail as e:
            sys.exit(f"check_netcdf: {path}: FAILED: {e}")
        except Exception as e:  # an engine or reader error: say which, exactly
            sys.exit(f"check_netcdf: {path}: FAILED: {type(e).__name__}: {e}")
        print(f"check_netcdf: {path}: ok: {summary}, both engines, {len(args.expect)} expectations")


if __name__ == "__main__":
    main()
