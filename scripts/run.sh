#!/usr/bin/env bash
# Installs what is missing, builds in release mode and runs `vibroatlas` with the
# given arguments, e.g. scripts/run.sh cell configs/multi-stop.toml --set omega=0.33
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
mkdir -p out   # the conventional output folder of the README's commands (git-ignored)
cargo build --release --quiet
exec target/release/vibroatlas "$@"
