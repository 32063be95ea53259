"""Shared helpers: the CLI binary (env VIBROATLAS_BIN, default
target/release/vibroatlas of the repository), the shipped scenes, and strict
comparisons of DataTrees (values bit for bit, dtypes, dims, attributes)."""
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

ROOT = Path(__file__).resolve().parents[3]
CONFIGS = ROOT / "configs"
MULTI = CONFIGS / "multi-stop.toml"
DRY = CONFIGS / "dry-friction.toml"

# Root attributes that say when and how a file was made, not what it holds.
# attributes_crc32 is the checksum of the text attributes, `command` and
# `created` among them: it differs whenever they do; so does each dataset's
# values_crc32, which binds its values to them.
VOLATILE = {"command", "created", "history", "run_time_s", "source", "git_commit", "attributes_crc32",
            "values_crc32"}


def bin_path():
    b = os.environ.get("VIBROATLAS_BIN") or str(ROOT / "target" / "release" / "vibroatlas")
    b = b if os.path.isabs(b) else str(ROOT / b)
    if not os.access(b, os.X_OK):
        pytest.fail(f"no vibroatlas binary at {b}: build it (cargo build --release) or set VIBROATLAS_BIN")
    return b


def cli(*args, check=True):
    """Runs the CLI; returns the CompletedProcess (text)."""
    p = subprocess.run([bin_path(), *map(str, args)], capture_output=True, text=True, cwd=ROOT,
                       stdin=subprocess.DEVNULL, timeout=300)
    if check and p.returncode != 0:
        raise AssertionError(f"vibroatlas {' '.join(map(str, args))}: exit {p.returncode}: {p.stderr}")
    return p


def cli_json(*args):
    return json.loads(cli(*args, "--json").stdout)


def cli_error(*args):
    """The CLI's one-line error message (without `error: `) for arguments that fail."""
    p = cli(*args, check=False)
    assert p.returncode == 2, (p.returncode, p.stderr)
    line = [x for x in p.stderr.splitlines() if x.startswith("error: ")][-1]
    return line[len("error: "):]


def axis(a):
    """The CLI's NAME=START:STOP:COUNT for an (name, start, stop, count) tuple."""
    name, start, stop, count = a
    return f"{name}={float(start)!r}:{float(stop)!r}:{int(count)}"


def sets(**params):
    out = []
    for k, v in params.items():
        out += ["--set", f"{k}={float(v)!r}"]
    return out


def open_tree(path):
    """xarray's own reader on a file, loaded, the file closed."""
    with xr.open_datatree(path, engine="h5netcdf", phony_dims="sort") as t:
        return t.load()


def same_array(a, b, where):
    assert a.dims == b.dims, f"{where}: dims {a.dims} != {b.dims}"
    assert a.dtype == b.dtype, f"{where}: dtype {a.dtype} != {b.dtype}"
    assert _attrs_equal(a.attrs, b.attrs), f"{where}: attrs differ"
    va, vb = np.asarray(a.values), np.asarray(b.values)
    assert va.shape == vb.shape, f"{where}: shape {va.shape} != {vb.shape}"
    if va.dtype.kind in "fiub":
        assert va.tobytes() == vb.tobytes(), f"{where}: values differ (bit for bit)"
    else:
        assert np.array_equal(va, vb), f"{where}: values differ"


def _attrs_equal(a, b):
    # values_crc32 binds a variable's values (compared themselves) to the
    # file's created and command: it differs between two runs' files.
    a = {k: v for k, v in a.items() if k != "values_crc32"}
    b = {k: v for k, v in b.items() if k != "values_crc32"}
    if a.keys() != b.keys():
        return False
    for k in a:
        x, y = np.asarray(a[k]), np.asarray(b[k])
        if x.shape != y.shape or x.dtype != y.dtype:
            return False
        if x.dtype.kind in "fiub":
            if x.tobytes() != y.tobytes():
                return False
        elif not np.array_equal(x, y):
            return False
    return True


def assert_trees_equal(a, b, volatile=VOLATILE):
    """Same groups; in each, the same data variables and coordinates (values
    bit for bit, dtypes, dims, attributes) and the same group attributes but
    the volatile root ones."""
    pa = sorted(n.path for n in a.subtree)  # noqa: E501
    pb = sorted(n.path for n in b.subtree)
    assert pa == pb, f"groups differ: {set(pa) ^ set(pb)}"
    for path in pa:
        da, db = a[path].to_dataset(inherit=False), b[path].to_dataset(inherit=False)
        assert sorted(da.variables) == sorted(db.variables), f"{path}: variables differ"
        assert sorted(da.coords) == sorted(db.coords), f"{path}: coordinates differ"
        for v in da.variables:
            same_array(da[v].variable, db[v].variable, f"{path.rstrip('/')}/{v}")
        ka = {k: x for k, x in da.attrs.items() if k not in volatile}
        kb = {k: x for k, x in db.attrs.items() if k not in volatile}
        assert ka.keys() == kb.keys(), f"{path}: attributes {set(ka) ^ set(kb)}"
        assert _attrs_equal(ka, kb), f"{path}: attributes differ: " + ", ".join(
            k for k in ka if not _attrs_equal({k: ka[k]}, {k: kb[k]}))


@pytest.fixture(scope="session")
def vb():
    return bin_path()
