#!/usr/bin/env bash
# Builds target/pgo/vibroatlas: the same program as target/release/vibroatlas,
# optimised with the profile of a training run (profile-guided optimisation)
# and across crates (Cargo.toml's `pgo` profile: fat LTO, one codegen unit).
# Every file it writes is the release binary's, bit for bit: the compiler
# never reassociates or fuses floating-point operations, so only the code's
# layout, inlining and branches change (`--check` compares atlases of every
# shipped scene written by both). About 10 % faster on the README's main job;
# the cost is two more builds (12 min from scratch on two cores, with
# the training run), done again when the sources or the commit change
# (docs/performance.md, "A faster build").
#
#   scripts/build-pgo.sh           build if needed; prints the binary's path
#   scripts/build-pgo.sh --check   also build target/release/vibroatlas and compare
#
# Needs rustc's own llvm-profdata (rustup's llvm-tools component, added here
# when missing; exit status 3 when it cannot be had). The training run is small planes of every shipped scene,
# not the main job whose time is reported.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
NAME=build-pgo
say() { echo "$NAME: $*" >&2; }
# fail STATUS MESSAGE: the message, and the exit status (3: a missing tool, 1: any other failure).
fail() {
    local status=$1
    shift
    echo "$NAME: FAIL: $*" >&2
    exit "$status"
}
die() { fail 1 "$@"; }

check=0
case "${1:-}" in
    "") ;;
    --check) check=1 ;;
    *) die "unknown argument $1 (--check or none)" ;;
esac

scripts/setup.sh >&2
export HDF5_USE_FILE_LOCKING=FALSE

# rustc's llvm-profdata: its LLVM must be rustc's own, so the toolchain's, not the system's.
profdata() {
    local host
    host=$(rustc -vV | sed -n 's/^host: //p')
    echo "$(rustc --print sysroot)/lib/rustlib/$host/bin/llvm-profdata"
}
# Without it: exit status 3, so that a caller can tell a missing tool from a failure.
no_tool() { fail 3 "$@"; }
tool=$(profdata)
if [ ! -x "$tool" ]; then
    command -v rustup >/dev/null 2>&1 || no_tool "llvm-profdata not found at $tool and no rustup to add the llvm-tools component"
    say "adding rustup's llvm-tools component (llvm-profdata)"
    rustup component add llvm-tools >&2 || no_tool "rustup could not add the llvm-tools component"
    [ -x "$tool" ] || no_tool "llvm-profdata still not found at $tool"
fi

dir=$ROOT/target/pgo
mkdir -p "$dir"
# One build at a time: two at once would train into one folder.
exec 9>"$dir/.lock"
flock 9

# 1. The instrumented binary, in its own target folder (its flags differ from
#    every other build's), built as the optimised one will be: a profile
#    taken without the same LTO matches few of its functions (measured: no
#    gain at all).
say "building the instrumented binary (target/pgo/train)"
CARGO_TARGET_DIR=$dir/train RUSTFLAGS="-Cprofile-generate=$dir/raw" \
    cargo build --profile pgo --bin vibroatlas --quiet
trained=$dir/train/pgo/vibroatlas

# 2. Its training run, again only when it was rebuilt since the last profile.
if [ ! -s "$dir/merged.profdata" ] || [ "$trained" -nt "$dir/merged.profdata" ]; then
    say "training run: small planes of every shipped scene"
    rm -rf "$dir/raw" "$dir/runs"
    mkdir -p "$dir/runs"
    train() { "$trained" atlas "configs/$1" --x "$2" --y "$3" --sweep both --quiet -o "$dir/runs/${1%.toml}.h5"; }
    train multi-stop.toml omega=0.1:3.05:100 delta=0.05:2:60
    train impact-damper.toml omega=1.3:2.1:40 delta=1:3:30
    train dry-friction.toml omega=3.5:5.6:40 fk=0.005:0.1:30
    train soft-stop.toml omega=0.3:3:40 clearance=0:2:30
    train gear-backlash.toml omega=0.3:2:40 f1=0.05:0.35:30
    train symmetric-stops.toml omega=1.3:2.1:30 delta=0.1:0.6:20
    train single-stop.toml omega=0.5:3:30 sigma=-1:1.5:20
    "$tool" merge -o "$dir/merged.profdata.new" "$dir"/raw/*.profraw
    mv "$dir/merged.profdata.new" "$dir/merged.profdata"
    rm -rf "$dir/runs"
fi

# 3. The optimised binary. The profile is named by its contents, so that a new
#    profile changes RUSTFLAGS and cargo rebuilds.
sum=$(sha256sum "$dir/merged.profdata" | cut -c1-16)
profile=$dir/profile-$sum.profdata
[ -e "$profile" ] || { rm -f "$dir"/profile-*.profdata; cp "$dir/merged.profdata" "$profile"; }
say "building the optimised binary (target/pgo/use, profile pgo)"
CARGO_TARGET_DIR=$dir/use RUSTFLAGS="-Cprofile-use=$profile" \
    cargo build --profile pgo --bin vibroatlas --quiet
# Replaced by a rename, so that a run of the previous binary goes on undisturbed.
if ! cmp -s "$dir/use/pgo/vibroatlas" "$dir/vibroatlas"; then
    cp "$dir/use/pgo/vibroatlas" "$dir/vibroatlas.new"
    mv "$dir/vibroatlas.new" "$dir/vibroatlas"
fi

if [ $check -eq 1 ]; then
    # The same files as the release binary's, dataset by dataset, on every shipped scene.
    cargo build --release --bin vibroatlas --quiet
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    # Every shipped scene has ω and ζ: a plane over both.
    for scene in configs/*.toml; do
        name=$(basename "$scene" .toml)
        for tag in release pgo; do
            bin=target/release/vibroatlas
            [ $tag = release ] || bin=$dir/vibroatlas
            "$bin" atlas "$scene" --x omega=0.3:3:24 --y zeta=0.02:0.2:16 --sweep both --quiet -o "$tmp/$name-$tag.h5"
        done
        /usr/bin/python3 scripts/compare_atlases.py "$tmp/$name-release.h5" "$tmp/$name-pgo.h5" >&2 ||
            die "$name: the optimised binary's atlas differs from the release binary's"
        say "$name: identical dataset by dataset"
    done
fi
echo "$dir/vibroatlas"
