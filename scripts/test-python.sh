#!/usr/bin/env bash
# Tests the Python package (crates/python, docs/python.md) as a user gets it:
# makes a fresh virtual environment, installs the package into it with the
# README's command (`pip install ./crates/python`: maturin builds the Rust
# extension, pip pulls numpy, xarray, h5netcdf, h5py, matplotlib and tqdm from
# PyPI), installs pytest, runs crates/python/tests against the CLI binary
# (VIBROATLAS_BIN, default target/release/vibroatlas, built first if missing),
# then runs the README's Python example (the ```py block of its "Python"
# section) and the worked example of docs/python.md in a scratch folder, its
# output compared with the text blocks the page shows (a change that moves a
# number moves the page too).
# Ends with one line "python tests: N passed, M failed" (the examples count as
# tests) and exits non-zero if any failed.
#
#   scripts/test-python.sh                 # a fresh venv in target/python-venv
#   VIBROATLAS_VENV=/tmp/v scripts/test-python.sh
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
venv=${VIBROATLAS_VENV:-$root/target/python-venv}
bin=${VIBROATLAS_BIN:-target/release/vibroatlas}
case "$bin" in /*) ;; *) bin="$root/$bin" ;; esac
export VIBROATLAS_BIN="$bin"
if [ ! -x "$bin" ]; then
    echo "test-python: building $bin"
    cargo build --release --quiet || exit 1
fi

rm -rf "$venv"
if ! python3 -m venv "$venv" >/dev/null 2>&1; then
    # Debian's python3 makes venvs only with python3-venv (ensurepip's wheels)
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    echo "test-python: installing python3-venv"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends python3-venv >/dev/null
    rm -rf "$venv"
    python3 -m venv "$venv" || exit 1
fi
py="$venv/bin/python"
# The README's install command, as printed, inside the venv.
(source "$venv/bin/activate" && pip install ./crates/python) || { echo "python tests: 0 passed, 1 failed (pip install ./crates/python)"; exit 1; }
"$py" -m pip install --quiet pytest mypy || exit 1

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export HDF5_USE_FILE_LOCKING=FALSE MPLBACKEND=Agg
# From the scratch folder, so that `import vibroatlas` is the installed package, never the sources.
(cd "$tmp" && "$py" -m pytest "$root/crates/python/tests" -p no:cacheprovider -rfE) 2>&1 | tee "$tmp/pytest.log"
# pytest's summary line, e.g. "2 failed, 50 passed, 1 error in 20.1s" (none: it did not run)
summary=$(grep -E '^=* ?[0-9]+ (passed|failed|errors?|skipped)' "$tmp/pytest.log" | tail -1)
passed=$(echo "$summary" | awk '{for (i = 1; i < NF; i++) if ($(i+1) ~ /^passed/) n += $i} END {print n + 0}')
failed=$(echo "$summary" | awk '{for (i = 1; i < NF; i++) if ($(i+1) ~ /^(failed|error)/) n += $i} END {print n + 0}')
[ -n "$summary" ] || failed=1

# The examples, in a folder with configs/ and an out/ folder, as the docs run them.
mkdir -p "$tmp/ex/out"
ln -s "$root/configs" "$tmp/ex/configs"
example() {  # NAME FILE [EXPECTED]: runs FILE; with EXPECTED, what it prints must be that text
    if (cd "$tmp/ex" && "$py" "$2") >"$tmp/ex.out" 2>"$tmp/ex.log" \
        && { [ -z "${3:-}" ] || diff -u "$3" "$tmp/ex.out" >"$tmp/ex.diff"; }; then
        echo "test-python: ok    $1"
        passed=$((passed + 1))
    else
        echo "test-python: FAIL  $1"
        tail -n 8 "$tmp/ex.log" | sed 's/^/    /'
        [ -n "${3:-}" ] && [ -s "$tmp/ex.diff" ] && sed 's/^/    /' "$tmp/ex.diff" | head -n 30
        failed=$((failed + 1))
    fi
}
awk '/^## Python/{s=1;next} /^## /{s=0} s&&/^```py$/{f=1;next} /^```/{f=0} s&&f' README.md > "$tmp/readme.py"
if [ -s "$tmp/readme.py" ]; then
    example "README.md, section Python" "$tmp/readme.py"
else
    echo "test-python: README.md has no \`\`\`py block under '## Python' yet"
fi
awk '/^## Worked example/{s=1;next} /^## /{s=0} s&&/^```python$/{f=1;next} /^```/{f=0} s&&f' docs/python.md > "$tmp/worked.py"
# What the page shows it prints: its ```text blocks, in order.
awk '/^## Worked example/{s=1;next} /^## /{s=0} s&&/^```text$/{f=1;next} /^```/{f=0} s&&f' docs/python.md > "$tmp/worked.txt"
if [ -s "$tmp/worked.py" ]; then
    example "docs/python.md, worked example (what it prints, as the page shows it)" "$tmp/worked.py" "$tmp/worked.txt"
else
    echo "test-python: FAIL  docs/python.md has no worked example"
    failed=$((failed + 1))
fi

# The package's type hints (its .pyi stubs) against the two examples, strictly.
if (cd "$tmp" && "$py" -m mypy --strict --no-incremental readme.py worked.py) >"$tmp/mypy.log" 2>&1; then
    echo "test-python: ok    mypy --strict on the README's and docs/python.md's examples"
    passed=$((passed + 1))
else
    echo "test-python: FAIL  mypy --strict on the README's and docs/python.md's examples"
    grep -v ' note: ' "$tmp/mypy.log" | tail -n 12 | sed 's/^/    /'
    failed=$((failed + 1))
fi

echo "python tests: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
