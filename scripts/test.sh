#!/usr/bin/env bash
# Installs what is missing, then runs every test of the workspace (unit,
# integration, doc tests) in release mode.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo test --workspace --release
