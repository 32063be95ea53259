#!/usr/bin/python3
"""Re-runs the aperiodic cells of an atlas with a record ten times longer, and
tallies what they become: the check behind the per-scene classification
figures of docs/performance.md.

    scripts/check_classes.py ATLAS.h5 [--binary vibroatlas] [--times 10]
        [--limit N] [--class C,Q,U] [--json]

Each `C`, `Q` and `U` cell (at most N of each class per sweep, drawn at
random with a fixed seed, all of them by default) is simulated again with
`vibroatlas cell --from ATLAS --at … --sweep …` from the state the atlas
stored for it, under the atlas's preset and knobs, with `max_periods` times
`--times`. A `C` cell that becomes periodic settled within the longer record;
a `Q` cell that becomes periodic was an orbit; a `C` that becomes `Q` was a
torus. Prints one line per sweep and class, and with `--json` one object.
"""

import argparse
import collections
import json
import random
import shutil
import subprocess
import sys

import h5py
import numpy as np

KINDS = {"chaotic": "C", "quasiperiodic": "Q", "unresolved": "U"}


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("atlas")
    ap.add_argument("--binary", default="vibroatlas")
    ap.add_argument("--times", type=int, default=10)
    ap.add_argument("--limit", type=int, default=0, help="cells per class and sweep (0: all)")
    ap.add_argument("--class", dest="classes", default="C,Q,U")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    wanted = set(args.classes.split(","))
    if not wanted <= set(KINDS.values()):
        sys.exit(f"error: --class: expected some of C, Q, U, got '{args.classes}'")
    if args.times < 1 or args.limit < 0:
        sys.exit("error: --times must be >= 1 and --limit >= 0")
    if shutil.which(args.binary) is None:
        sys.exit(f"error: --binary: '{args.binary}' is not a program here (give target/release/vibroatlas)")
    try:
        f = h5py.File(args.atlas, "r")
    except OSError as e:
        sys.exit(f"error: {args.atlas}: not an atlas that h5py can open ({e})")
    knobs = dict(kv.split("=", 1) for kv in text(f.attrs["knobs"]).split(","))
    max_periods = int(knobs["max_periods"]) * args.times
    xn, yn = text(f.attrs["x"]), text(f.attrs["y"])
    xs, ys = f[xn][...], f[yn][...]
    report = {}
    for sweep in [s for s in ("fresh", "up", "down") if s in f]:
        cls = f[sweep]["class"]
        names = text(cls.attrs["flag_meanings"]).split()
        values = list(cls.attrs["flag_values"])
        grid = cls[...]
        for name, value in zip(names, values):
            kind = KINDS.get(name)
            if kind not in wanted:
                continue
            cells = list(zip(*np.nonzero(grid == value)))
            random.Random(1).shuffle(cells)
            if args.limit:
                cells = cells[: args.limit]
            became = collections.Counter()
            changed = []
            for i, j in cells:
                at = f"{xn}={xs[j]!r},{yn}={ys[i]!r}"
                run = subprocess.run(
                    [args.binary, "cell", "--from", args.atlas, "--at", at, "--sweep", sweep,
                     "--accuracy", f"max_periods={max_periods}", "--json"],
                    capture_output=True, text=True)
                if run.returncode != 0:
                    sys.exit(f"error: {sweep} cell {at}: {run.stderr.strip()}")
                cell = json.loads(run.stdout)
                new = {"periodic": "P"}.get(cell["class"], KINDS.get(cell["class"], "?"))
                became[new] += 1
                if new != kind:
                    labels = ",".join(cell["labels"].values())
                    changed.append({"at": at, "label": labels, "lyapunov": cell.get("lyapunov"),
                                    "reason": cell.get("reason")})
            report[f"{sweep} {kind}"] = {"cells": len(cells), "became": dict(became), "changed": changed}
            if not args.json:
                tally = ", ".join(f"{k} {v}" for k, v in sorted(became.items()))
                print(f"{sweep:5s} {kind}: {len(cells)} cells re-run over {args.times}x the record -> {tally}")
                for c in changed:
                    print(f"      {c['at']}: {c['label']}")
    if args.json:
        json.dump({"atlas": args.atlas, "times": args.times, "max_periods": max_periods, "report": report},
                  sys.stdout, indent=1)
        print()


if __name__ == "__main__":
    main()
