"""va.atlas against the CLI on the same grid (issue 32: at most 1.1 x).

    python benches/python_atlas.py [--grid 296x196] [--repeat 3] [--threads 2]

Runs the README's main job (the multi-stop scene's reference plane, both
sweeps) with `vibroatlas atlas` (VIBROATLAS_BIN, default
target/release/vibroatlas), with `vibroatlas.atlas(..., output=...)` and
with `vibroatlas.atlas(...)` (the file written in memory) in turns, so that
a slow spell of a shared machine falls on all alike, and prints the best
wall time of each and their ratios to the CLI's. Run it from the
repository root in the environment where the package is installed.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import vibroatlas as va

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--grid", default="296x196", help="NX x NY cells (default: the README's 296x196)")
parser.add_argument("--repeat", type=int, default=3, help="runs of each (best kept)")
parser.add_argument("--threads", type=int, default=2)
a = parser.parse_args()
nx, ny = (int(n) for n in a.grid.split("x"))
binary = os.environ.get("VIBROATLAS_BIN", "target/release/vibroatlas")
scene = "configs/multi-stop.toml"
cli, py, memory = [], [], []
plane = dict(x=("omega", 0.1, 3.05, nx), y=("delta", 0.05, 2.0, ny), sweep="both", threads=a.threads,
             progress=False)
with tempfile.TemporaryDirectory() as tmp:
    for i in range(a.repeat):
        out = os.path.join(tmp, f"cli{i}.h5")
        t0 = time.perf_counter()
        subprocess.run([binary, "atlas", scene, "--x", f"omega=0.1:3.05:{nx}", "--y", f"delta=0.05:2:{ny}",
                        "--sweep", "both", "--threads", str(a.threads), "--quiet", "-o", out], check=True)
        cli.append(time.perf_counter() - t0)
        out = os.path.join(tmp, f"py{i}.h5")
        t0 = time.perf_counter()
        va.atlas(scene, output=out, **plane)
        py.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        va.atlas(scene, **plane)
        memory.append(time.perf_counter() - t0)
        print(f"run {i + 1}: CLI {cli[-1]:.2f} s, va.atlas with output {py[-1]:.2f} s, in memory {memory[-1]:.2f} s",
              flush=True)
best_cli, best_py, best_memory = min(cli), min(py), min(memory)
print(f"{nx} x {ny} cells, both sweeps, {a.threads} threads: best CLI {best_cli:.2f} s, "
      f"best va.atlas {best_py:.2f} s with output (ratio {best_py / best_cli:.3f}), "
      f"{best_memory:.2f} s in memory (ratio {best_memory / best_cli:.3f}), each with reading into a DataTree")
sys.exit(0)
