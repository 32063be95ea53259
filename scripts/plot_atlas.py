#!/usr/bin/env python3
"""Plots one mass's label map from a vibroatlas HDF5 file with h5py and
matplotlib only (no project code).

    python3 scripts/plot_atlas.py atlas.h5 --sweep up --mass M1 -o map.png
"""
import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def label_text(cls, npq):
    if cls == 1:
        return "C"
    if cls == 2:
        return "U"
    if cls != 0:
        return ""
    s = lambda v: "S" if v == 65535 else str(v)
    return f"{npq[0]}-{s(npq[1])}-{s(npq[2])}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("file")
    ap.add_argument("--sweep", default=None)
    ap.add_argument("--mass", default=None)
    ap.add_argument("-o", "--output", default="map.png")
    args = ap.parse_args()
    f = h5py.File(args.file, "r")
    sweep = args.sweep or f.attrs["sweeps"].split(",")[0]
    mass = args.mass or f.attrs["masses"].split(",")[0]
    xs, ys = f["axes"][f.attrs["x"]][()], f["axes"][f.attrs["y"]][()]
    cls, lab = f[sweep]["class"][()], f[sweep][f"label_{mass}"][()]
    texts = np.array([[label_text(cls[i, j], lab[i, j]) for j in range(len(xs))] for i in range(len(ys))])
    names, counts = np.unique(texts, return_counts=True)
    order = [n for _, n in sorted(zip(-counts, names))]
    index = {n: k for k, n in enumerate(order)}
    img = np.vectorize(index.get)(texts)
    cmap = plt.get_cmap("tab20", max(len(order), 2))
    fig, ax = plt.subplots(figsize=(10, 6))
    ax.pcolormesh(xs, ys, img, cmap=cmap, vmin=-0.5, vmax=len(order) - 0.5, shading="nearest")
    ax.set_xlabel(f.attrs["x"])
    ax.set_ylabel(f.attrs["y"])
    ax.set_title(f"{f.attrs['scene_name']}: {mass} ({sweep})")
    handles = [plt.Rectangle((0, 0), 1, 1, color=cmap(index[n])) for n in order[:20]]
    ax.legend(handles, order[:20], loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)


if __name__ == "__main__":
    main()
