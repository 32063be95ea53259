#!/usr/bin/env bash
# Installs what is missing, then runs every test of the workspace (unit,
# integration, doc tests) in release mode, and checks with h5py alone that an
# atlas file has every dataset of the documented layout.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo test --workspace --release
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
target/release/vibroatlas atlas configs/multi-stop.toml --x omega=0.2:2.5:12 --y delta=0.1:1.5:5 \
    --sweep both --quiet -o "$tmp/check.h5"
/usr/bin/python3 scripts/check_atlas.py "$tmp/check.h5"
