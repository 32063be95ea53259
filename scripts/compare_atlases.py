#!/usr/bin/python3
"""Compares two vibroatlas HDF5 files dataset by dataset, bit for bit.

    python3 scripts/compare_atlases.py A.h5 B.h5 [--ignore NAME ...]

Every dataset present in either file is compared by its raw bytes (NaN equal to
the same NaN), and every attribute except those that record when and how a
file was made (created, command, run_time_s, history, source, git_commit, the root's
attributes_crc32 that covers them, each dataset's values_crc32 that binds its values
to created and command, and names given with --ignore). Prints one line per difference and exits 1 when there is any.
"""
import argparse
import sys

import h5py
import numpy as np

# attributes_crc32 covers the root's text attributes, created, command and history among them;
# values_crc32 binds each dataset's values (compared themselves) to created and command.
VOLATILE = {"created", "command", "run_time_s", "history", "git_commit", "source", "attributes_crc32",
            "values_crc32"}


def items(f):
    out = {}

    def visit(name, obj):
        out[name] = obj

    f.visititems(visit)
    return out


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype != b.dtype:
        return False
    if a.dtype.kind in "fc":
        return a.tobytes() == b.tobytes()
    return np.array_equal(a, b)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--ignore", nargs="*", default=[])
    args = ap.parse_args()
    skip = VOLATILE | set(args.ignore)
    diffs = []
    with h5py.File(args.a, "r") as fa, h5py.File(args.b, "r") as fb:
        ia, ib = items(fa), items(fb)
        for name in sorted(set(ia) | set(ib)):
            if name not in ia or name not in ib:
                diffs.append(f"{name}: only in {'A' if name in ia else 'B'}")
                continue
            oa, ob = ia[name], ib[name]
            if isinstance(oa, h5py.Dataset) and isinstance(ob, h5py.Dataset) and not same(oa[()], ob[()]):
                diffs.append(f"{name}: data differ")
        for name in [""] + sorted(set(ia) & set(ib)):
            oa = fa[name] if name else fa
            ob = fb[name] if name else fb
            for k in sorted(set(oa.attrs) | set(ob.attrs)):
                if k in skip or k in ("DIMENSION_LIST", "REFERENCE_LIST"):
                    continue
                if k not in oa.attrs or k not in ob.attrs:
                    diffs.append(f"{name or '/'}@{k}: only in {'A' if k in oa.attrs else 'B'}")
                elif not same(oa.attrs[k], ob.attrs[k]):
                    diffs.append(f"{name or '/'}@{k}: differ")
    for d in diffs:
        print(d)
    print(f"{len(diffs)} differences")
    sys.exit(1 if diffs else 0)


if __name__ == "__main__":
    main()
