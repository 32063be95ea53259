#!/usr/bin/env python3
"""Reads every dataset of a vibroatlas HDF5 file with h5py alone (no project
code) and checks the documented layout: shapes, codes, CSR sections, legends.

    /usr/bin/python3 scripts/check_atlas.py atlas.h5
Exit status 0 when the file is complete and consistent.
"""
import sys

import h5py
import numpy as np


def check(path):
    f = h5py.File(path, "r")
    a = f.attrs
    for key in ["software", "version", "scene", "preset", "command", "created", "x", "y", "sweeps", "masses", "stops"]:
        assert key in a, f"missing root attribute {key}"
    assert a["software"] == "vibroatlas"
    xs, ys = f["axes"][a["x"]][()], f["axes"][a["y"]][()]
    nx, ny = len(xs), len(ys)
    dim = int(a["dim"])
    masses = [m for m in a["masses"].split(",") if m]
    stops = [s for s in a["stops"].split(",") if s]
    n_read = 0
    for sweep in a["sweeps"].split(","):
        g = f[sweep]
        cls = g["class"][()]
        assert cls.shape == (ny, nx) and set(np.unique(cls)) <= {0, 1, 2, 3, 255}
        for m in masses:
            lab = g[f"label_{m}"][()]
            assert lab.shape == (ny, nx, 3) and lab.dtype == np.uint16
            periodic = cls == 0
            assert (lab[..., 0][periodic] >= 1).all(), "periodic cells have n >= 1"
        assert g["flags"].shape == (ny, nx) and g["symmetry"].shape == (ny, nx)
        lyap, mult = g["lyapunov"][()], g["multiplier"][()]
        assert lyap.shape == (ny, nx) and mult.shape == (ny, nx)
        assert np.isnan(lyap[cls == 0]).all() and np.isnan(mult[cls != 0]).all(), "exponent or multiplier, not both"
        assert (mult[np.isfinite(mult)] >= 0).all()
        fs = g["final_state"][()]
        assert fs.shape == (ny, nx, dim) and np.isfinite(fs[cls != 255]).all()
        assert g["periods"].shape == (ny, nx) and g["events"].shape == (ny, nx)
        g["lines_done"][()]
        for name, cols in [("period", dim)] + [(s, dim + 1) for s in stops]:
            v, o = g["sections"][name]["values"][()], g["sections"][name]["offsets"][()]
            assert v.ndim == 2 and v.shape[1] == cols, f"{sweep}/sections/{name}"
            assert len(o) == nx * ny + 1 and o[0] == 0 and o[-1] == len(v) and (np.diff(o.astype(np.int64)) >= 0).all()
            assert np.isfinite(v).all()
            n_read += 2
        n_read += 10 + len(masses)
        for m in masses:
            labels = [x.decode() if isinstance(x, bytes) else x for x in f["legend"][sweep][m]["label"][()]]
            counts = f["legend"][sweep][m]["count"][()]
            assert len(labels) == len(counts) and counts.sum() == (cls != 255).sum()
            n_read += 2
    if "hysteresis" in f:
        h = f["hysteresis"][()]
        assert h.shape == (ny, nx) and set(np.unique(h)) <= {0, 1}
        n_read += 1
    return n_read, nx, ny


if __name__ == "__main__":
    for p in sys.argv[1:]:
        n, nx, ny = check(p)
        print(f"{p}: ok ({n} datasets read, grid {ny} x {nx})")
