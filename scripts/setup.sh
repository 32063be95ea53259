#!/usr/bin/env bash
# Installs what vibroatlas needs on a fresh Debian machine with Rust, and nothing
# that is already there. Safe to run repeatedly.
#   libhdf5-dev, pkg-config   HDF5 library the hdf5-metno crate links to
#   fonts-dejavu-core         the font of every PNG
#   python3-h5py              Debian's h5py, for scripts/check_atlas.py (/usr/bin/python3)
#   python3-xarray            xarray, to read the netCDF-4/CF layout (scripts/check_netcdf.py, plot_atlas.py)
#   python3-h5netcdf          xarray's h5netcdf engine (netCDF-4 through h5py)
#   python3-netcdf4           xarray's netcdf4 engine (the netCDF-C library)
#   python3-matplotlib        scripts/plot_atlas.py, and the rendering check of check_netcdf.py
#   python3-mpmath            arbitrary precision for scripts/sticking_reference.py (and its test)
#   poppler-utils             pdffonts and pdftotext, to check the text of PDF figures (tests)
# With --tests (scripts/test.sh), also:
#   chromium, chromium-driver, python3-selenium
#                             a real headless browser on the explorer's page (scripts/test_explore.py)
set -euo pipefail

APT_PACKAGES=(pkg-config libhdf5-dev fonts-dejavu-core python3-h5py python3-xarray python3-h5netcdf
    python3-netcdf4 python3-matplotlib python3-mpmath poppler-utils)
if [ "${1:-}" = "--tests" ]; then
    APT_PACKAGES+=(chromium chromium-driver python3-selenium)
fi

if ! command -v cargo >/dev/null 2>&1; then
    echo "setup: cargo not found; install a Rust toolchain (rustup) first" >&2
    exit 1
fi

missing=()
for p in "${APT_PACKAGES[@]}"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}"
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
