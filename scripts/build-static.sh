#!/usr/bin/env bash
# Builds the binary for cluster nodes: vibroatlas with the cargo feature `static-hdf5`,
# HDF5 (with its HL library) and zlib compiled from source and linked statically,
# so that it needs only the C library (docs/cluster.md, "A binary for any node").
#
#   scripts/build-static.sh [TARGET_DIR] [--compare-with BIN | --no-compare]
#
#   TARGET_DIR          cargo target directory of the static build (default: target-static
#                       in the repository); the binary is TARGET_DIR/release/vibroatlas
#   --compare-with BIN  the default build whose file of the check run is compared with the
#                       static build's (default: target/release/vibroatlas, brought up to
#                       date with `cargo build --release` first)
#   --no-compare        skip that comparison
#
# Steps, each stopping the script on failure:
#   1. tools: cmake >= 3.26 (HDF5's build; Debian 12's cmake is 3.25, so a newer one is
#      installed from PyPI into TARGET_DIR/tools/cmake, a private venv), a C compiler, make;
#   2. cargo build --release --features static-hdf5 (the first build compiles HDF5 from
#      source: several minutes);
#   3. ldd of the binary: fails if it needs a shared library outside the C library
#      (libc, libm, libgcc_s, the dynamic loader, and glibc's own libpthread/libdl/librt);
#      prints the newest glibc symbol version it needs (the minimum glibc of a node);
#   4. a tiny atlas with the static binary, then `inspect` of it;
#   5. the same run with the default build, compared dataset by dataset
#      (scripts/compare_atlases.py): the two files must hold the same data.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD

TARGET_DIR=""
COMPARE_WITH=""
COMPARE=1
while [ $# -gt 0 ]; do
    case "$1" in
        --compare-with) COMPARE_WITH=${2:?--compare-with needs a binary}; shift 2 ;;
        --no-compare) COMPARE=0; shift ;;
        -h|--help) sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        -*) echo "build-static: unknown option $1" >&2; exit 2 ;;
        *) [ -z "$TARGET_DIR" ] || { echo "build-static: one TARGET_DIR only" >&2; exit 2; }
           TARGET_DIR=$1; shift ;;
    esac
done
TARGET_DIR=${TARGET_DIR:-$ROOT/target-static}
mkdir -p "$TARGET_DIR"
TARGET_DIR=$(cd "$TARGET_DIR" && pwd)
# Keep a build folder inside the repository out of `git status`.
[ -e "$TARGET_DIR/.gitignore" ] || printf '*\n' > "$TARGET_DIR/.gitignore"

NAME=build-static
# shellcheck source=lib/build.sh
. "$ROOT/scripts/lib/build.sh"

# ---- 1. tools -------------------------------------------------------------------------
build_tools
find_cmake "$TARGET_DIR/tools"
say "cmake: $CMAKE_BIN ($("$CMAKE_BIN" --version | head -1))"

# ---- 2. build -------------------------------------------------------------------------
# HDF5_DIR would make hdf5-metno-sys link that installation instead of building HDF5.
say "cargo build --release --features static-hdf5 (target dir $TARGET_DIR)"
start=$(date +%s)
env -u HDF5_DIR CMAKE="$CMAKE_BIN" CARGO_TARGET_DIR="$TARGET_DIR" \
    cargo build --release --features static-hdf5
BIN=$TARGET_DIR/release/vibroatlas
say "built $BIN in $(( $(date +%s) - start )) s, $(du -h "$BIN" | cut -f1) ($(stat -c %s "$BIN") bytes)"

# ---- 3. shared libraries --------------------------------------------------------------
system_libs_only "$BIN"
glibc=$GLIBC_NEEDED
say "a node needs glibc >= $glibc"

# ---- 4. a tiny atlas ------------------------------------------------------------------
CHECK=${TMPDIR:-/tmp}/vibroatlas-static-check
rm -rf "$CHECK"
mkdir -p "$CHECK"
RUN=(atlas configs/multi-stop.toml --x omega=0.2:2.5:6 --y delta=0.1:1.5:4 --sweep both --quiet)
say "vibroatlas ${RUN[*]} -o $CHECK/static-check.h5"
"$BIN" "${RUN[@]}" -o "$CHECK/static-check.h5"
"$BIN" inspect "$CHECK/static-check.h5"

# ---- 5. the same run with the default build -------------------------------------------
if [ "$COMPARE" -eq 1 ]; then
    scripts/setup.sh   # libhdf5-dev for the default build, python3-h5py for the comparison
    if [ -z "$COMPARE_WITH" ]; then
        say "building the default binary (cargo build --release, as scripts/run.sh does)"
        cargo build --release --quiet
        COMPARE_WITH=${CARGO_TARGET_DIR:-$ROOT/target}/release/vibroatlas
    fi
    [ -x "$COMPARE_WITH" ] || die "no default binary $COMPARE_WITH"
    say "the same run with the default build $COMPARE_WITH"
    "$COMPARE_WITH" "${RUN[@]}" -o "$CHECK/default-check.h5"
    say "compare_atlases.py static default"
    /usr/bin/python3 scripts/compare_atlases.py "$CHECK/static-check.h5" "$CHECK/default-check.h5" \
        || die "the static build's file differs from the default build's (above)"
fi
say "PASS: $BIN needs only the C library (glibc >= $glibc); copy it to the nodes (docs/cluster.md)"
