#!/usr/bin/env python3
"""Chooses the curated label colours of crates/maps/src/palette.rs.

    /usr/bin/python3 scripts/palette_table.py            # prints the Rust table
    /usr/bin/python3 scripts/palette_table.py --write    # rewrites it in palette.rs
    /usr/bin/python3 scripts/palette_table.py --scan     # top-20 labels of the reference maps

Needs numpy (Debian's python3-numpy; /usr/bin/python3 has it). Deterministic:
the same list gives the same table.

Every label of LABELS gets one sRGB colour (8 bits a channel) such that the
smallest CIEDE2000 difference between any two of them is as large as the
optimiser can make it, under hard constraints (FIXED_GAP): every colour is at
least 20 from C's black (chaotic must never pass for a periodic label: the
near-blacks #312108 and #423A08 of an earlier table were 11.8 from it and
looked the same in 6-pixel cells), at least 15 from Q, U, 1-0-0 and white
(the figures' background), and has CIELAB lightness L* >= L_MIN (no periodic
label dark enough to read as black). Among the colours that keep that smallest difference, each
label takes the one nearest (CIEDE2000) to its family's colour (`preferred`,
the scheme of the module doc), so that families stay recognisable where
distinctness allows.

The method: candidates are the sRGB grid with 32 levels a channel (those that
meet the constraints above); start from each label's
preferred colour; then, for a rising target t, move the labels one at a time
(the worst placed first) to the candidate nearest their preferred colour among
those at least t from every other colour, or to the candidate farthest from
all the others when none is; stop at the first target that a few passes
cannot reach and keep the last table that reached its target.

To change the table: edit LABELS (the labels that matter are those frequent in
the shipped scenes' maps: `--scan` prints the top 20 of the reference planes
of tests/palette.rs, from the release binary), run with --write, then
`cargo test --release -p vibroatlas-maps palette` and
`cargo test --release --test integration palette`.
"""

import colorsys
import json
import os
import re
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PALETTE_RS = os.path.join(ROOT, "crates", "grid", "src", "palette.rs")

# Fixed colours (not optimised): chaotic, quasi-periodic, unresolved, no impact.
FIXED = {"C": (0, 0, 0), "Q": (102, 102, 102), "U": (213, 40, 40), "1-0-0": (184, 184, 184)}
WHITE_GAP = 15.0  # every colour at least this far from white
FIXED_GAP = {"C": 20.0, "Q": 15.0, "U": 15.0, "1-0-0": 15.0}  # ... and this far from each fixed one
L_MIN = 25.0  # CIELAB lightness of every colour at least this


def _fundamentals():
    return [f"1-{p}-{q}" for p in range(6) for q in range(6) if (p, q) != (0, 0)]


# The curated labels, by family (palette.rs's doc lists the same groups).
LABELS = (
    # Fundamental motions 1-p-q, p, q <= 5 (35 labels).
    _fundamentals()
    # Fundamental chattering seen in the shipped scenes (dry friction's 1-p-p
    # sequence, multi-stop's M2 1-0-q and M1 1-5-6).
    + ["1-0-6", "1-0-7", "1-0-8", "1-1-6", "1-5-6", "1-6-6", "1-7-7", "1-8-8", "1-9-9", "1-10-10"]
    # Complete chattering, n = 1 and 2, and the single stop's n-S-0.
    + ["1-S-S"] + [f"1-S-{q}" for q in range(6)] + [f"1-{p}-S" for p in range(6)]
    + ["2-S-S"] + [f"2-S-{q}" for q in range(4)] + [f"2-{p}-S" for p in range(4)]
    + ["4-S-0", "5-S-0", "6-S-0", "7-S-0"]
    # Subharmonics frequent in the shipped scenes' reference maps.
    + ["2-0-2", "2-0-4", "2-0-5", "2-0-6", "2-0-7", "2-0-8", "2-1-0", "2-1-3", "2-2-0", "2-2-1", "2-2-2",
       "2-2-3", "2-2-4", "2-3-0", "2-3-2", "2-4-0", "2-4-2", "2-4-4", "2-4-5", "2-4-6", "2-5-4",
       "2-6-0", "2-6-4", "2-6-6", "2-8-0", "2-8-8"]
    + ["3-0-1", "3-0-4", "3-1-0", "3-1-3", "3-2-0", "3-2-4", "3-3-0", "3-3-4", "3-3-6", "3-4-3",
       "3-4-4", "3-6-3", "3-6-6", "3-7-7", "3-10-10", "3-13-13"]
    + ["4-0-2", "4-0-6", "4-2-0", "4-2-4", "4-3-0", "4-4-0", "4-4-4", "4-4-8", "4-6-0", "4-6-4",
       "4-8-4", "4-8-10", "4-10-8"]
    + ["5-0-0", "5-0-5", "5-5-2", "5-5-3", "5-5-5", "5-6-6", "5-10-10", "6-0-6", "6-2-0", "6-6-0", "8-8-8"]
)

# Reference planes (as in tests/palette.rs) for --scan.
SCAN = [
    ("multi-stop.toml", ["--x", "omega=0.1:3.05:120", "--y", "delta=0.05:2:80"]),
    ("single-stop.toml", ["--x", "omega=0.5:5:100", "--y", "sigma=-1.5:0.5:64"]),
    ("impact-damper.toml", ["--x", "omega=0.8:2.4:100", "--y", "delta=0.5:3:64"]),
    ("symmetric-stops.toml", ["--x", "omega=0.5:3:100", "--y", "delta=0.05:1:64"]),
    ("dry-friction.toml", ["--x", "omega=1:9:64", "--y", "fk=0.005:0.1:40"]),
]


# --- colour science -------------------------------------------------------

def srgb_to_lab(rgb):
    """CIELAB (D65) of 8-bit sRGB triples (last axis)."""
    c = np.asarray(rgb, float) / 255.0
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    m = np.array([[0.4124564, 0.3575761, 0.1804375],
                  [0.2126729, 0.7151522, 0.0721750],
                  [0.0193339, 0.1191920, 0.9503041]])
    t = (lin @ m.T) / np.array([0.95047, 1.0, 1.08883])
    e, k = 216 / 24389, 24389 / 27
    f = np.where(t > e, np.cbrt(t), (k * t + 16) / 116)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def ciede2000(lab1, lab2):
    """CIEDE2000 difference (kL = kC = kH = 1), broadcasting over the last axis
    (Sharma, Wu and Dalal 2005)."""
    L1, a1, b1 = np.moveaxis(np.asarray(lab1, float), -1, 0)
    L2, a2, b2 = np.moveaxis(np.asarray(lab2, float), -1, 0)
    cb = (np.hypot(a1, b1) + np.hypot(a2, b2)) / 2
    g = 0.5 * (1 - np.sqrt(cb**7 / (cb**7 + 25.0**7)))
    a1p, a2p = (1 + g) * a1, (1 + g) * a2
    c1p, c2p = np.hypot(a1p, b1), np.hypot(a2p, b2)
    h1p = np.degrees(np.arctan2(b1, a1p)) % 360
    h2p = np.degrees(np.arctan2(b2, a2p)) % 360
    zero = c1p * c2p == 0
    dh = h2p - h1p
    dh = np.where(dh > 180, dh - 360, np.where(dh < -180, dh + 360, dh))
    dh = np.where(zero, 0, dh)
    d_hp = 2 * np.sqrt(c1p * c2p) * np.sin(np.radians(dh / 2))
    lbp, cbp, hs = (L1 + L2) / 2, (c1p + c2p) / 2, h1p + h2p
    hbp = np.where(np.abs(h1p - h2p) <= 180, hs / 2, np.where(hs < 360, (hs + 360) / 2, (hs - 360) / 2))
    hbp = np.where(zero, hs, hbp)
    t = (1 - 0.17 * np.cos(np.radians(hbp - 30)) + 0.24 * np.cos(np.radians(2 * hbp))
         + 0.32 * np.cos(np.radians(3 * hbp + 6)) - 0.20 * np.cos(np.radians(4 * hbp - 63)))
    rc = 2 * np.sqrt(cbp**7 / (cbp**7 + 25.0**7))
    rt = -np.sin(np.radians(60 * np.exp(-(((hbp - 275) / 25) ** 2)))) * rc
    sl = 1 + 0.015 * (lbp - 50) ** 2 / np.sqrt(20 + (lbp - 50) ** 2)
    sc, sh = 1 + 0.045 * cbp, 1 + 0.015 * cbp * t
    dl, dc, dhh = (L2 - L1) / sl, (c2p - c1p) / sc, d_hp / sh
    return np.sqrt(dl**2 + dc**2 + dhh**2 + rt * dc * dhh)


def _selftest():
    # Sharma, Wu and Dalal (2005), table 1, pairs 1, 7, 13, 19, 34.
    for l1, l2, want in [((50, 2.6772, -79.7751), (50, 0, -82.7485), 2.0425),
                         ((50, 0, 0), (50, -1, 2), 2.3669),
                         ((50, 2.49, -0.001), (50, -2.49, 0.0011), 7.2195),
                         ((50, 2.5, 0), (73, 25, -18), 27.1492),
                         ((2.0776, 0.0795, -1.135), (0.9033, -0.0636, -0.5514), 0.9082)]:
        got = float(ciede2000(l1, l2))
        assert abs(got - want) < 1e-4, (l1, l2, got, want)


# --- the families' colours --------------------------------------------------

def hsl(h, s, l):
    r, g, b = colorsys.hls_to_rgb((h % 360) / 360, l, s)
    return tuple(round(v * 255) for v in (r, g, b))


def parse(label):
    n, p, q = label.split("-")
    return int(n), None if p == "S" else int(p), None if q == "S" else int(q)


def preferred(label):
    """The family colour a label would like (the module doc's scheme)."""
    n, p, q = parse(label)
    if p is None or q is None:  # complete chattering: purples
        k = (p or 0) + (q or 0)
        return hsl(285, 0.45, 0.35 + 0.05 * (k % 5) + (0.1 if n > 1 else 0))
    if max(p, q) >= 6 * n:  # chattering: oranges to browns
        return hsl(25, 0.8, 0.40 + 0.03 * (max(p, q) % 7))
    if n == 1:  # fundamental: Okabe-Ito hue by max(p, q), lighter p > q, darker p < q
        base = [(0, 114, 178), (86, 180, 233), (0, 158, 115), (240, 228, 66), (204, 121, 167)][max(p, q) - 1]
        d, m = p - q, max(p, q)
        mix, to = (0.7 * d / m, 255) if d > 0 else (0.4 * -d / m, 0)
        return tuple(round(c + mix * (to - c)) for c in base)
    # subharmonic: greens to teals
    return hsl(90 + 15 * (n % 6) + 6 * (p % 4), 0.40, 0.32 + 0.06 * ((p + q) % 5))


# --- the optimiser ----------------------------------------------------------

def optimise(labels, levels=32, passes=12, step=0.05, start=6.0):
    axis = np.round(np.linspace(0, 255, levels))
    pool = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    lab = srgb_to_lab(pool)
    ok = (ciede2000(lab, srgb_to_lab([255, 255, 255])) >= WHITE_GAP) & (lab[:, 0] >= L_MIN)
    for name, rgb in FIXED.items():
        ok &= ciede2000(lab, srgb_to_lab(rgb)) >= FIXED_GAP[name]
    pool, lab = pool[ok], lab[ok]
    pref = np.array([ciede2000(lab, srgb_to_lab(preferred(l))) for l in labels])  # (K, pool)
    k = len(labels)
    idx = np.argmin(pref, 1)
    dist = np.stack([ciede2000(lab, lab[i]) for i in idx], 1)  # (pool, K)

    def pairwise(idx):
        d = ciede2000(lab[idx][:, None], lab[idx][None])
        d[np.arange(k), np.arange(k)] = np.inf
        return d.min(1)

    best, best_t, t = None, 0.0, start
    while True:
        reached = False
        for _ in range(passes):
            for i in np.argsort(pairwise(idx), kind="stable"):
                others = np.delete(dist, i, 1).min(1)
                room = others
                feasible = room >= t
                j = int(np.argmin(np.where(feasible, pref[i], np.inf))) if feasible.any() else int(np.argmax(room))
                idx[i] = j
                dist[:, i] = ciede2000(lab, lab[j])
            if pairwise(idx).min() >= t:
                reached = True
                break
        if not reached:
            break
        best, best_t = idx.copy(), pairwise(idx).min()
        print(f"target {t:.2f}: min dE {best_t:.2f}", file=sys.stderr)
        t = max(t + step, best_t + 0.01)
    return [tuple(int(c) for c in pool[i]) for i in best], best_t


# --- output -----------------------------------------------------------------

def rust_table(labels, colours, min_de):
    rows = sorted(zip(labels, colours))
    out = [f"/// The curated colours, sorted by label ({len(rows)} labels; scripts/palette_table.py:",
           f"/// every two differ by CIEDE2000 dE >= {min_de:.2f}; each is >= {FIXED_GAP['C']:g} from C, >= {FIXED_GAP['Q']:g} from Q,",
           f"/// {FIXED_GAP['U']:g} from U, {FIXED_GAP['1-0-0']:g} from 1-0-0 and {WHITE_GAP:g} from white, CIELAB L* >= {L_MIN:g}).",
           f"const TABLE: [(&str, [u8; 3]); {len(rows)}] = ["]
    for l, (r, g, b) in rows:
        out.append(f'    ("{l}", [{r}, {g}, {b}]),')
    out.append("];")
    out.append("/// The smallest CIEDE2000 difference the optimiser reached (tests check it).")
    out.append("#[cfg(test)]")
    out.append(f"const TABLE_MIN_DE: f64 = {np.floor(min_de * 100) / 100:.2f};")
    return "\n".join(out)


def scan():
    binary = os.path.join(ROOT, "target", "release", "vibroatlas")
    tmp = os.path.join(ROOT, "out", "palette-scan")
    os.makedirs(tmp, exist_ok=True)
    union = set()
    for config, plane in SCAN:
        path = os.path.join(tmp, config.replace(".toml", ".h5"))
        subprocess.run([binary, "atlas", os.path.join(ROOT, "configs", config), *plane, "--sweep", "both",
                        "--quiet", "-o", path], check=True, stdout=subprocess.DEVNULL)
        info = json.loads(subprocess.check_output([binary, "inspect", path, "--json"]))
        for sweep in info["sweeps"]:
            for mass, counts in sweep["labels"].items():
                top = [l for l, _ in sorted(counts.items(), key=lambda lc: (-lc[1], lc[0]))[:20]]
                union.update(top)
                missing = [l for l in top if l not in LABELS and l not in FIXED]
                print(config, sweep["sweep"], mass, " ".join(top), "| not in LABELS:", " ".join(missing) or "-")
    print("union:", " ".join(sorted(union)))


def main():
    _selftest()
    if "--scan" in sys.argv:
        return scan()
    labels = list(dict.fromkeys(LABELS))
    assert len(labels) == len(LABELS), "a label is listed twice"
    assert not set(labels) & set(FIXED)
    colours, min_de = optimise(labels)
    table = rust_table(labels, colours, min_de)
    if "--write" in sys.argv:
        text = open(PALETTE_RS).read()
        begin, end = "// BEGIN TABLE (scripts/palette_table.py)\n", "// END TABLE\n"
        new, count = re.subn(re.escape(begin) + ".*?" + re.escape(end), lambda _: begin + table + "\n" + end,
                             text, flags=re.S)
        assert count == 1, "palette.rs has no table markers"
        open(PALETTE_RS, "w").write(new)
        print(f"{len(labels)} labels, min dE {min_de:.2f}: written to {PALETTE_RS}", file=sys.stderr)
    else:
        print(table)


if __name__ == "__main__":
    main()
