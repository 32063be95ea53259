# Sourced by scripts/build-static.sh and scripts/build-wheel.sh, the two builds that compile
# HDF5 from source. The caller sets NAME (the prefix of its messages) first.
#
#   say TEXT / die TEXT    a line "NAME: TEXT" (die: "NAME: FAIL: TEXT" on stderr, exit 1)
#   apt_install PKG...     Debian packages, through sudo unless root
#   build_tools            cargo, a C compiler, make and objdump, or a clear stop
#   python_venv DIR        a fresh venv at DIR made by Debian's python3
#   find_cmake TOOLS_DIR   sets CMAKE_BIN to a cmake >= CMAKE_MIN (hdf5-metno-src bundles
#                          HDF5 2.x, whose cmake_minimum_required is 3.26; Debian 12's cmake
#                          is 3.25): $CMAKE if set and new enough, else the one on PATH, else
#                          TOOLS_DIR/cmake/bin/cmake, installed there from PyPI when missing.
#   system_libs_only LIB   fails unless LIB needs only the C library, libm, libgcc_s and the
#                          loader; prints the newest glibc symbol version it needs

say() { echo "$NAME: $*"; }
die() { echo "$NAME: FAIL: $*" >&2; exit 1; }

apt_install() {
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    say "installing $* (apt-get)"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}

build_tools() {
    command -v cargo >/dev/null 2>&1 || die "cargo not found; install a Rust toolchain (rustup) first"
    local need=()
    command -v cc >/dev/null 2>&1 || need+=(gcc libc6-dev)
    command -v make >/dev/null 2>&1 || need+=(make)
    command -v objdump >/dev/null 2>&1 || need+=(binutils)
    [ ${#need[@]} -eq 0 ] || apt_install "${need[@]}"
}

CMAKE_MIN=3.26

cmake_ok() {     # cmake_ok BIN: BIN runs and is at least CMAKE_MIN
    local v
    v=$("$1" --version 2>/dev/null | sed -n '1s/^cmake version \([0-9.]*\).*/\1/p') || return 1
    [ -n "$v" ] && [ "$(printf '%s\n%s\n' "$CMAKE_MIN" "$v" | sort -V | head -1)" = "$CMAKE_MIN" ]
}

python_venv() {  # python_venv DIR: a fresh venv at DIR made by Debian's python3
    local py=/usr/bin/python3
    [ -x "$py" ] || py=$(command -v python3) || die "python3 not found"
    if ! "$py" -c 'import ensurepip, venv' >/dev/null 2>&1; then apt_install python3-venv; fi
    rm -rf "$1"
    "$py" -m venv "$1"
}

find_cmake() {
    local tools=$1 c
    CMAKE_BIN=""
    for c in "${CMAKE:-}" "$(command -v cmake || true)" "$tools/cmake/bin/cmake"; do
        if [ -n "$c" ] && cmake_ok "$c"; then CMAKE_BIN=$c; return 0; fi
    done
    say "no cmake >= $CMAKE_MIN; installing one from PyPI into $tools/cmake"
    python_venv "$tools/cmake"
    "$tools/cmake/bin/pip" install -q --disable-pip-version-check "cmake>=$CMAKE_MIN,<4"
    CMAKE_BIN=$tools/cmake/bin/cmake
    cmake_ok "$CMAKE_BIN" || die "could not install cmake >= $CMAKE_MIN"
}

system_libs_only() {
    local lib=$1 extra glibc
    say "ldd $lib"
    ldd "$lib" | sed 's/^/    /'
    # The C library and its loader, libm, libgcc_s (unwinding): on every Linux with glibc.
    local system='^(linux-vdso\.so|linux-gate\.so|ld-linux[-a-z0-9_.]*\.so|libc\.so|libm\.so|libgcc_s\.so|libpthread\.so|libdl\.so|librt\.so)'
    extra=$(ldd "$lib" | awk '{print $1}' | sed 's|.*/||' | grep -Ev "$system" || true)
    [ -z "$extra" ] || die "$lib still needs non-system libraries: $(echo $extra)"
    glibc=$(objdump -T "$lib" | grep -o 'GLIBC_[0-9.]*' | sed 's/GLIBC_//' | sort -Vu | tail -1)
    say "only system libraries (C library, libm, libgcc_s, loader); newest glibc symbol version: $glibc"
    GLIBC_NEEDED=$glibc
}
