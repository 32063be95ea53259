#!/usr/bin/env bash
# Installs what is missing, then runs every test of the workspace (unit,
# integration, doc tests) in release mode, clippy and rustdoc with warnings as
# errors, checks with h5py alone that an atlas
# file has every dataset of the documented layout, installs the Python package
# from source into a fresh virtual environment and runs its pytest suite and
# examples (scripts/test-python.sh), and ends with one line
# "tests: N passed, M failed" summing every cargo test result and the Python ones.
#
# scripts/test.sh --wheel does all that and then builds the wheel
# (scripts/build-wheel.sh: HDF5 compiled from source, every crate again with
# zig's linker; about 15 minutes on a fresh 2-core machine) and runs the Python
# tests on it with cargo off the PATH: the check of a change to the packaging,
# run before a stop that touches it; CI leaves it out to stay within its time.
#
# scripts/test.sh --quick is the contributor's loop (about two minutes once
# built, docs/performance.md): the workspace's unit tests, the solver's physics
# (crates/solver/tests), the explorer's in-process route tests and the
# integration tests, leaving out those marked slow (#[ignore = "slow: …"]),
# the doc tests, clippy, rustdoc, the reference readers, chromium, the
# gallery and the Python package; it ends with the same closing line. CI runs
# the whole suite (without --wheel), the slow tests included.
set -euo pipefail
cd "$(dirname "$0")/.."
wheel=0
case "${1:-}" in
    ""|--quick) ;;
    --wheel) wheel=1 ;;
    *) echo "test.sh: unknown argument $1 (--quick, --wheel or none)" >&2; exit 2 ;;
esac
if [ "${1:-}" = "--quick" ]; then
    scripts/setup.sh
    export HDF5_USE_FILE_LOCKING=FALSE
    log=$(mktemp)
    trap 'rm -f "$log"' EXIT
    cargo test --workspace --release --tests 2>&1 | tee "$log"
    awk '/^test result:/ { p += $4; f += $6 } END { printf "tests: %d passed, %d failed\n", p, f }' "$log"
    exit 0
fi
# Each step's wall time, so that a slow CI can be read step by step.
t0=$SECONDS
took() { echo "test.sh: $1 took $((SECONDS - t0)) s"; t0=$SECONDS; }
scripts/setup.sh --tests
took "setup"
# An unused dependency is a defect: cargo-machete (built once, into ~/.cargo/bin) finds them.
command -v cargo-machete >/dev/null 2>&1 || cargo install cargo-machete --locked --quiet
cargo machete
took "cargo machete"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# Tests open HDF5 files in their own process while other tests spawn the
# binary: a child inherits those descriptors (libhdf5 opens without
# close-on-exec) and with them HDF5's advisory flock, so a test reopening its
# file could find it locked by an unrelated child. The outputs' own lock
# (store::lock) is separate and stays on.
export HDF5_USE_FILE_LOCKING=FALSE
# The Python extension (crates/python) links into a Python process only: its
# tests are the pytest suite that scripts/test-python.sh runs below (its crate has
# no Rust test; it is in the workspace's selection so that the package's build
# below reuses every dependency this one compiles: crates/python/Cargo.toml).
cargo test --workspace --release -- --include-ignored 2>&1 | tee "$tmp/test.log"
took "cargo test"
# Lints and docs are part of the tests: no warning passes. Both in the dev profile, so that
# they check the dependencies once between them (clippy in release would check them again).
cargo clippy --workspace --all-targets --quiet -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet
took "clippy and rustdoc"
target/release/vibroatlas atlas configs/multi-stop.toml --x omega=0.2:2.5:12 --y delta=0.1:1.5:5 \
    --sweep both --quiet -o "$tmp/check.h5"
/usr/bin/python3 scripts/check_atlas.py "$tmp/check.h5"
# A zoom's file (layout 4: axes on the parent's lattice, entry states) reads as an atlas too.
target/release/vibroatlas zoom "$tmp/check.h5" --x omega=0.4:1.2:9 --y delta=0.3:1.2:4 --quiet -o "$tmp/zoom.h5"
/usr/bin/python3 scripts/check_atlas.py "$tmp/zoom.h5"
# netCDF-4/CF: both xarray engines, label decoding, and plot_atlas.py's colours.
target/release/vibroatlas atlas configs/multi-stop.toml --x omega=0.13:0.53:5 --y delta=0.4:0.8:3 \
    --sweep both --quiet -o "$tmp/netcdf.h5"
target/release/vibroatlas sweep configs/multi-stop.toml --axis omega=0.2:0.5:7 --direction both --quiet \
    -o "$tmp/sweep.h5" >/dev/null
/usr/bin/python3 scripts/check_netcdf.py "$tmp/netcdf.h5" --expect up:M1:omega=0.33,delta=0.6:1-4-4
/usr/bin/python3 scripts/check_netcdf.py "$tmp/sweep.h5" --expect up:M1:omega=0.35:1-4-4
/usr/bin/python3 scripts/check_netcdf.py "$tmp/zoom.h5"
took "the reference readers"
# The explorer in a real browser (chromium through chromedriver); its
# screenshots are kept in target/explore-screenshots.
/usr/bin/python3 scripts/test_explore.py target/release/vibroatlas target/explore-screenshots 2>&1 | tee "$tmp/explore.log"
took "the explorer in chromium"
# Every command of README.md, as printed.
scripts/check_readme.sh
took "check_readme"
# Every figure of docs/gallery.md drawn again by the commands the page prints and compared
# with docs/img pixel for pixel (about five minutes on two cores; legends print cell counts,
# so a change that moves a label moves a pixel).
scripts/gallery.sh --check
took "the gallery"
# The Python package as a user installs it (README's "Python" section): from source, its
# pytest suite (every function against the CLI), the README's and docs/python.md's
# examples, mypy on them.
scripts/test-python.sh 2>&1 | tee "$tmp/python.log"
took "the Python package"
: > "$tmp/wheel.log"
if [ "$wheel" -eq 1 ]; then
    # and as the wheel a user without Rust and libhdf5 installs: the same, with cargo off
    # the PATH. The two builds differ only in how HDF5 is linked.
    scripts/build-wheel.sh --out "$tmp/dist"
    took "the wheel's build"
    VIBROATLAS_VENV=target/wheel-venv scripts/test-python.sh --wheel "$(ls "$tmp"/dist/vibroatlas-*.whl)" 2>&1 \
        | tee "$tmp/wheel.log"
    took "the wheel's tests"
fi
awk '/^test result:/ { p += $4; f += $6 } /^python tests:/ { p += $3; f += $5 }
    /^explore tests:/ { p += $3; f += $5 }
    END { printf "tests: %d passed, %d failed\n", p + 4, f }' "$tmp/test.log" "$tmp/python.log" "$tmp/wheel.log" \
    "$tmp/explore.log"
