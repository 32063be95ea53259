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
# With --wheel WHEEL (scripts/build-wheel.sh), the same tests run on that wheel
# as a user without Rust gets it: `pip install WHEEL[notebook]`, and every step with a
# PATH that has no cargo and no rustc on it; one more test then checks that the
# process running the package never loaded a libhdf5 other than the one h5py's
# own wheel brings (the extension carries its HDF5 inside).
# Ends with one line "python tests: N passed, M failed" (the examples count as
# tests) and exits non-zero if any failed.
#
#   scripts/test-python.sh                 # a fresh venv in target/python-venv
#   scripts/test-python.sh --wheel dist/vibroatlas-0.1.0-cp39-abi3-manylinux2014_x86_64.manylinux_2_17_x86_64.whl
#   scripts/test-python.sh --examples-only # the install and the examples, not the pytest suite
#   VIBROATLAS_VENV=/tmp/v scripts/test-python.sh
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
wheel=""
examples_only=0
while [ $# -gt 0 ]; do
    case "$1" in
        --wheel) wheel=$(cd "$(dirname "${2:?--wheel needs a wheel file}")" && pwd)/$(basename "$2"); shift 2 ;;
        --examples-only) examples_only=1; shift ;;
        *) echo "test-python: unknown argument $1" >&2; exit 2 ;;
    esac
done
venv=${VIBROATLAS_VENV:-$root/target/python-venv}
case "$venv" in /*) ;; *) venv="$root/$venv" ;; esac
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
if [ -n "$wheel" ]; then
    # A PATH without the Rust toolchain: the wheel must install and run without it.
    PATH=$(printf '%s' "$PATH" | tr ':' '\n' \
        | while IFS= read -r d; do [ -x "$d/cargo" ] || [ -x "$d/rustc" ] || printf '%s:' "$d"; done)
    export PATH=${PATH%:}
    if command -v cargo >/dev/null 2>&1 || command -v rustc >/dev/null 2>&1; then
        echo "python tests: 0 passed, 1 failed (cargo still on PATH)"; exit 1
    fi
    echo "test-python: the wheel $wheel, PATH without cargo and rustc: $PATH"
    # The wheel with its notebook extra (ipywidgets, for tqdm's widget in Jupyter).
    (source "$venv/bin/activate" && pip install "$wheel[notebook]") || { echo "python tests: 0 passed, 1 failed (pip install $wheel)"; exit 1; }
else
    # The README's install command, as printed, inside the venv, then the notebook extra's
    # ipywidgets (not `./crates/python[notebook]`, which would build the package again).
    (source "$venv/bin/activate" && pip install ./crates/python) || { echo "python tests: 0 passed, 1 failed (pip install ./crates/python)"; exit 1; }
    "$py" -m pip install --quiet ipywidgets || exit 1
fi
# What the tests use: pytest, mypy, and nbclient with ipykernel to run a notebook in a real kernel.
"$py" -m pip install --quiet pytest mypy nbclient ipykernel || exit 1

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export HDF5_USE_FILE_LOCKING=FALSE MPLBACKEND=Agg
# From the scratch folder, so that `import vibroatlas` is the installed package, never the sources.
if [ "$examples_only" -eq 1 ]; then
    echo "test-python: pytest suite not run here (--examples-only)"
    passed=0 failed=0
else
    (cd "$tmp" && "$py" -m pytest "$root/crates/python/tests" -p no:cacheprovider -rfE) 2>&1 | tee "$tmp/pytest.log"
    # pytest's summary line, e.g. "2 failed, 50 passed, 1 error in 20.1s" (none: it did not run)
    summary=$(grep -E '^=* ?[0-9]+ (passed|failed|errors?|skipped)' "$tmp/pytest.log" | tail -1)
    passed=$(echo "$summary" | awk '{for (i = 1; i < NF; i++) if ($(i+1) ~ /^passed/) n += $i} END {print n + 0}')
    failed=$(echo "$summary" | awk '{for (i = 1; i < NF; i++) if ($(i+1) ~ /^(failed|error)/) n += $i} END {print n + 0}')
    [ -n "$summary" ] || failed=1
fi

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

if [ -n "$wheel" ]; then
    # The libraries the process maps after a cell and an atlas: a libhdf5 may come only
    # from h5py's wheel (h5py.libs), never from the system (the extension's is inside it).
    cat > "$tmp/static.py" <<'PY'
import vibroatlas as va
va.cell("configs/multi-stop.toml", omega=0.9)
va.atlas("configs/multi-stop.toml", x=("omega", 0.3, 1.2, 4), y=("delta", 0.2, 1, 3), sweep="up",
         progress=False)
maps = {line.split()[-1] for line in open("/proc/self/maps") if "libhdf5" in line}
foreign = sorted(m for m in maps if "h5py.libs" not in m)
assert not foreign, f"a libhdf5 outside h5py's wheel was loaded: {foreign}"
print("libhdf5 mapped:", sorted(maps))
PY
    example "the wheel's extension runs without the system's libhdf5" "$tmp/static.py"
    cat "$tmp/ex.out"
fi

echo "python tests: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
