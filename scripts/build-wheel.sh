#!/usr/bin/env bash
# Builds the Python package as a wheel for machines without Rust and without libhdf5:
# dist/vibroatlas-VERSION-cp39-abi3-manylinux2014_x86_64.manylinux_2_17_x86_64.whl, one wheel for every
# CPython >= 3.9 (the stable ABI, abi3) on any x86-64 Linux with glibc >= 2.17. HDF5 (with
# its HL library) and zlib are compiled from source and linked into the extension (the
# cargo feature `static-hdf5`); zig links it against glibc 2.17's symbols, so the wheel
# runs on older systems than the one that built it.
#
#   scripts/build-wheel.sh [--out DIR]     # default DIR: dist
#
# Steps, each stopping the script on failure:
#   1. tools: cargo, a C compiler, make, objdump; a private venv target/wheel-tools with
#      maturin, ziglang and, where the system's is older than 3.26, cmake (all from PyPI);
#   2. maturin build --release --strip --zig --features static-hdf5 --compatibility manylinux_2_17
#      (the first build compiles HDF5 from source: several minutes);
#   3. the extension inside the wheel: fails if it needs a shared library outside the C
#      library (so no libhdf5, no libz); prints the newest glibc symbol version it needs.
# Install it with `pip install dist/vibroatlas-*.whl`; scripts/test-python.sh --wheel WHEEL
# runs the Python tests on it with cargo off the PATH.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD

OUT=dist
while [ $# -gt 0 ]; do
    case "$1" in
        --out) OUT=${2:?--out needs a folder}; shift 2 ;;
        -h|--help) sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "build-wheel: unknown argument $1" >&2; exit 2 ;;
    esac
done

NAME=build-wheel
# shellcheck source=lib/build.sh
. "$ROOT/scripts/lib/build.sh"

# ---- 1. tools -------------------------------------------------------------------------
build_tools
command -v unzip >/dev/null 2>&1 || apt_install unzip
TOOLS=$ROOT/target/wheel-tools
MATURIN_SPEC="maturin>=1.9.4,<2"   # as crates/python/pyproject.toml's build-system
ZIG_SPEC="ziglang>=0.13,<0.14"
if ! "$TOOLS/bin/python" -c 'import ziglang' >/dev/null 2>&1 || [ ! -x "$TOOLS/bin/maturin" ]; then
    say "installing $MATURIN_SPEC and $ZIG_SPEC from PyPI into $TOOLS"
    python_venv "$TOOLS"
    "$TOOLS/bin/pip" install -q --disable-pip-version-check "$MATURIN_SPEC" "$ZIG_SPEC"
fi
find_cmake "$TOOLS"
say "maturin $("$TOOLS/bin/maturin" --version | cut -d' ' -f2), zig $("$TOOLS/bin/python" -m ziglang version), cmake: $CMAKE_BIN"

# ---- 2. build -------------------------------------------------------------------------
# HDF5_DIR would make hdf5-metno-sys link that installation instead of building HDF5.
# maturin --zig finds zig as `python -m ziglang` in the venv on PATH.
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
say "maturin build --release --strip --zig --features static-hdf5 --compatibility manylinux_2_17 -o $OUT"
start=$(date +%s)
before=$(ls "$OUT"/vibroatlas-*.whl 2>/dev/null || true)
rm -f $before
# Its own target folder: zig's linker and flags would otherwise rebuild target/'s every crate.
env -u HDF5_DIR PATH="$TOOLS/bin:$PATH" CMAKE="$CMAKE_BIN" \
    CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$ROOT/target/wheel-build}" \
    "$TOOLS/bin/maturin" build --release --strip --zig --features static-hdf5 \
    --compatibility manylinux_2_17 -m crates/python/Cargo.toml -o "$OUT"
WHEEL=$(ls "$OUT"/vibroatlas-*.whl)
[ "$(echo "$WHEEL" | wc -l)" -eq 1 ] || die "expected one wheel in $OUT, found: $WHEEL"
say "built $WHEEL in $(( $(date +%s) - start )) s, $(du -h "$WHEEL" | cut -f1)"

# ---- 3. the extension's shared libraries ----------------------------------------------
unpacked=$(mktemp -d)
trap 'rm -rf "$unpacked"' EXIT
unzip -q "$WHEEL" -d "$unpacked"
EXT=$(ls "$unpacked"/vibroatlas/_native*.so)
system_libs_only "$EXT"
say "PASS: $WHEEL needs only the C library (glibc >= $GLIBC_NEEDED) and CPython >= 3.9"
