#!/usr/bin/env bash
# Prints the JSON of a fixed set of cells and sweeps of the scenes without
# friction. tests/data/frictionless.jsonl was written by this script with the
# solver as it was before friction contacts existed (commit f1986aa); the test
# `frictionless_scenes_are_bit_identical` reruns the same commands and compares
# byte for byte, so adding a scene component never changes the others.
#   scripts/frictionless-reference.sh target/release/vibroatlas > tests/data/frictionless.jsonl
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/vibroatlas}
while IFS= read -r line; do
    # shellcheck disable=SC2086
    "$bin" $line --json
done < tests/data/frictionless.commands
