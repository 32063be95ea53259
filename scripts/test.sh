#!/usr/bin/env bash
# Installs what is missing, then runs every test of the workspace (unit,
# integration, doc tests) in release mode, checks with h5py alone that an atlas
# file has every dataset of the documented layout, and ends with one line
# "tests: N passed, M failed" summing every cargo test result.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cargo test --workspace --release 2>&1 | tee "$tmp/test.log"
target/release/vibroatlas atlas configs/multi-stop.toml --x omega=0.2:2.5:12 --y delta=0.1:1.5:5 \
    --sweep both --quiet -o "$tmp/check.h5"
/usr/bin/python3 scripts/check_atlas.py "$tmp/check.h5"
awk '/^test result:/ { p += $4; f += $6 } END { printf "tests: %d passed, %d failed\n", p + 1, f }' "$tmp/test.log"
