#!/usr/bin/env bash
# Redraws every figure of docs/gallery.md into docs/img/. Intermediate files
# (atlases, a sweep file, a study) go to out/gallery/ (git-ignored). About five
# minutes on two cores (4 min 35 s to 5 min 9 s on the 2-core Xeon of 2026-11-29), most of
# it the README's reference plane for the print previews and the curves of a
# 96 x 64 map.
#
#   scripts/gallery.sh            # uses target/release/vibroatlas as built
#   scripts/gallery.sh --check    # draws into a scratch folder instead and compares
#                                 # every image with docs/img's pixel by pixel: lists
#                                 # those that differ and fails if any does
#   scripts/gallery.sh --check --quick   # only the first two groups (the maps of a
#                                 # 120 x 80 atlas and the print previews of the
#                                 # reference plane, whose legends print cell counts):
#                                 # about 80 s, a quick check while editing
#                                 # (scripts/test.sh runs the whole --check)
#   VIBROATLAS=path/to/vibroatlas scripts/gallery.sh
#
# Not redrawn here: docs/img/trade.png (`vibroatlas bench --trade -o DIR`, the
# speed/accuracy trade), which measures every preset on a 48 x 48 grid several
# times and takes minutes; see docs/performance.md; and the explorer's
# screenshots docs/img/explore-*.png (scripts/test_explore.py, in chromium).
set -euo pipefail
cd "$(dirname "$0")/.."
check=0
quick=0
for a in "$@"; do
    case "$a" in
        --check) check=1 ;;
        --quick) quick=1 ;;
        *) echo "gallery: unknown argument $a" >&2; exit 2 ;;
    esac
done
bin=${VIBROATLAS:-target/release/vibroatlas}
if [ ! -x "$bin" ]; then
    echo "gallery: $bin not found; build it first (cargo build --release, or scripts/run.sh --version)" >&2
    exit 1
fi
img=docs/img
if [ "$check" -eq 1 ]; then
    img=$(mktemp -d)
    trap 'rm -rf "$img"' EXIT
fi
out=out/gallery
mkdir -p "$img" "$out"
# Compares every PNG drawn into $img with docs/img's, pixel for pixel (not bytes: the same
# picture may be encoded differently); fails if any differs.
compare_with_kept() {
    /usr/bin/python3 - "$img" docs/img <<'PY'
import os, sys
import matplotlib.image as mpimg
import numpy as np
drawn, kept = sys.argv[1], sys.argv[2]


def rgba(path):
    """The image as RGBA floats (an RGB file opaque), whatever channels its file stores."""
    a = mpimg.imread(path)
    if a.ndim == 2:
        a = np.stack([a, a, a], axis=-1)
    if a.shape[2] == 3:
        a = np.concatenate([a, np.ones(a.shape[:2] + (1,), a.dtype)], axis=-1)
    return a


names = sorted(n for n in os.listdir(drawn) if n.endswith(".png"))
differ = []
for n in names:
    a = rgba(os.path.join(drawn, n))
    path = os.path.join(kept, n)
    if not os.path.exists(path):
        differ.append(f"{n}: not in {kept}")
        continue
    b = rgba(path)
    if a.shape != b.shape:
        differ.append(f"{n}: {a.shape[1]} x {a.shape[0]} pixels, {kept} has {b.shape[1]} x {b.shape[0]}")
    elif not np.array_equal(a, b):
        changed = np.any(a != b, axis=-1)
        differ.append(f"{n}: {int(changed.sum())} of {changed.size} pixels differ")
for d in differ:
    print(f"gallery: DIFFERS {d}")
print(f"gallery: {len(names) - len(differ)} of {len(names)} images equal to {kept}'s pixel for pixel")
sys.exit(1 if differ else 0)
PY
}

start=$SECONDS

# Each command as docs/gallery.md prints it (vibroatlas = $bin).
vibroatlas() {
    echo "vibroatlas $*" >&2
    "$bin" "$@"
}

# Label maps, hysteresis, Lyapunov and multiplier views, one row: a 120 x 80
# up- and down-sweep atlas of the reference plane (about 19 000 cells).
vibroatlas atlas configs/multi-stop.toml --x omega=0.1:3.05:120 --y delta=0.05:2:80 --sweep both --quiet -o $out/atlas.h5 >/dev/null
vibroatlas render $out/atlas.h5 -o $img/map.png --sweep up
vibroatlas render $out/atlas.h5 -o $img/map-m2-down.png --sweep down --mass M2
vibroatlas render $out/atlas.h5 -o $img/hysteresis.png --sweep hysteresis
vibroatlas render $out/atlas.h5 -o $img/lyapunov.png --sweep up --view lyapunov
vibroatlas render $out/atlas.h5 -o $img/multiplier.png --sweep up --view multiplier
vibroatlas render $out/atlas.h5 -o $img/row.png --row delta=0.6

# Print sizes: the README's reference plane as PDF at one and two column
# widths, previewed as PNG at 150 dpi (pdftoppm, from poppler-utils).
vibroatlas atlas configs/multi-stop.toml --x omega=0.1:3.05:296 --y delta=0.05:2:196 --sweep both --quiet -o $out/reference.h5 >/dev/null
vibroatlas render $out/reference.h5 -o $out/map-single.pdf --sweep up --size single >/dev/null
vibroatlas render $out/reference.h5 -o $out/hysteresis-double.pdf --sweep hysteresis --size double >/dev/null
pdftoppm -r 150 -png -singlefile $out/map-single.pdf $img/print-map-single
pdftoppm -r 150 -png -singlefile $out/hysteresis-double.pdf $img/print-hysteresis-double
if [ "$quick" -eq 1 ]; then
    echo "gallery: $(ls $img/*.png | wc -l) images (--quick) in $img, $((SECONDS - start)) s" >&2
    [ "$check" -eq 0 ] || compare_with_kept
    exit 0
fi

# Bifurcation diagram of the dry-friction oscillator, up and down.
vibroatlas sweep configs/dry-friction.toml --axis omega=8:4.5:141 --set fk=0.01 --direction both --quiet --png $img/bifurcation.png >/dev/null

# A stored sweep file, redrawn: velocity panel and impact phases.
vibroatlas sweep configs/impact-damper.toml --axis omega=1.3:2.3:201 --direction both --points 64 --quiet -o $out/damper-sweep.h5 >/dev/null
vibroatlas render $out/damper-sweep.h5 -o $img/sweep-file.png --variable v_M2 --impact phase

# Branches of periodic orbits, with their bifurcations.
vibroatlas continue configs/single-stop.toml --axis sigma=0:-1.5:31 --arclength --png $img/branch.png >/dev/null
vibroatlas continue configs/impact-damper.toml --axis omega=1.3:2.3:101 --png $img/branch-ns.png >/dev/null

# Poincaré sections on an invariant circle.
vibroatlas cell configs/impact-damper.toml --set omega=1.55 --section-png $img/sections.png >/dev/null

# Study contact sheet: configs/studies/mass-ratio.toml on a 60 x 40 grid.
cat > $out/mass-ratio.toml <<'EOF'
# configs/studies/mass-ratio.toml on a smaller grid (scripts/gallery.sh)
scene = "../../configs/multi-stop.toml"
parameter = "mu_m"
values = [0.05, 0.25, 0.75, 0.95]
x = "omega=0.1:3.05:60"
y = "delta=0.05:2:40"
sweep = "fresh"
EOF
vibroatlas study $out/mass-ratio.toml -o $out/mass-ratio --quiet >/dev/null
cp $out/mass-ratio/contact-sheet.png $img/contact-sheet.png

# One motion: phase portraits and time series; coexisting attractors and their basins.
vibroatlas cell configs/multi-stop.toml --set omega=0.33 --portrait $img/portrait.png >/dev/null
vibroatlas attractors configs/multi-stop.toml --set omega=0.3149 --set delta=0.7 --samples 64 --png $img/basins.png >/dev/null
vibroatlas atlas configs/multi-stop.toml --x omega=0.25:0.4:16 --y delta=0.5:0.9:9 --sweep both --attractors 16 --quiet -o $out/attractors.h5 >/dev/null
vibroatlas render $out/attractors.h5 -o $img/attractors.png --view attractors

# Basins of attraction over a plane of initial states (docs/basins.md): smooth and intermingled.
vibroatlas basins configs/single-stop.toml --set omega=2.5 --set sigma=1 --set zeta=0.05 --x x_M=-3:1:200 --y v_M=-3:3:200 --quiet -o $out/basins-single.h5 --png $img/basins-single.png >/dev/null
vibroatlas basins configs/impact-damper.toml --set omega=1.3 --set delta=0.5 --preset precise --x x_M2=-0.5:0.5:100 --y v_M2=-3:3:100 --quiet -o $out/basins-damper.h5 --png $img/basins-damper.png >/dev/null
vibroatlas atlas configs/impact-damper.toml --x omega=1.2:2.4:48 --y delta=0.3:1.5:24 --sweep up --attractors 16 --quiet -o $out/damper-attractors.h5 >/dev/null
vibroatlas render $out/damper-attractors.h5 --view basin:0 -o $img/basin-family.png >/dev/null

# A bifurcation curve over a map: the dry-friction pitchfork in (omega, fk).
vibroatlas curve configs/dry-friction.toml --kind pf --start omega=6.845,fk=0.01 --free omega,fk --to 0.1 --steps 18 -o $out/pf.h5 >/dev/null
vibroatlas atlas configs/dry-friction.toml --x omega=6.5:7.1:40 --y fk=0.005:0.1:20 --sweep down --quiet -o $out/friction.h5 >/dev/null
vibroatlas render $out/friction.h5 -o $img/curve-overlay.png --sweep down --curves $out/pf.h5

# The bifurcation curves of a stored map, found by curves and drawn over it.
vibroatlas atlas configs/multi-stop.toml --x omega=0.1:3.05:96 --y delta=0.05:2:64 --sweep both --quiet -o $out/ref96.h5 >/dev/null
vibroatlas curves $out/ref96.h5 --max 40 -o $out/ref96-curves.h5 >/dev/null
vibroatlas render $out/ref96.h5 -o $img/curves.png --sweep up --curves $out/ref96-curves.h5

# Soft stops: the gear pair with backlash and the soft-stop impact oscillator.
vibroatlas atlas configs/gear-backlash.toml --x omega=0.3:2:120 --y f1=0.01:0.3:80 --sweep both --quiet -o $out/gear.h5 >/dev/null
vibroatlas render $out/gear.h5 -o $img/gear.png --sweep down
vibroatlas atlas configs/soft-stop.toml --x omega=0.3:3:120 --y clearance=0:2:80 --sweep both --quiet -o $out/soft.h5 >/dev/null
vibroatlas render $out/soft.h5 -o $img/soft-stop.png --sweep up

# Quantities of the steady motion: the impact damper's primary amplitude (and
# its attenuation, a quantity the scene defines, up and up less down), the
# gear's back-side impact speed (down sweep, and up less down), and a response
# curve with its jump.
vibroatlas atlas configs/impact-damper.toml --x omega=1.3:2.1:80 --y delta=1:3:60 --sweep both --quiet -o $out/damper.h5 >/dev/null
vibroatlas render $out/damper.h5 -o $img/quantity-damper.png --sweep up --view max_abs_x_M1
vibroatlas render $out/damper.h5 -o $img/quantity-attenuation.png --sweep up --view attenuation --contours 4
vibroatlas render $out/damper.h5 -o $img/quantity-attenuation-updown.png --sweep hysteresis --view attenuation
vibroatlas render $out/gear.h5 -o $img/quantity-gear.png --sweep down --view impact_speed_max_B
vibroatlas render $out/gear.h5 -o $img/quantity-gear-updown.png --sweep hysteresis --view impact_speed_max_B
vibroatlas sweep configs/soft-stop.toml --axis omega=0.6:1.8:241 --direction both --variable max_abs_x_M --quiet --png $img/response.png >/dev/null

echo "gallery: $(ls $img/*.png | wc -l) images in $img ($(du -ch $img/*.png | tail -1 | cut -f1)), $((SECONDS - start)) s" >&2
[ "$check" -eq 0 ] || compare_with_kept
