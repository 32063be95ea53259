//! The colour of a label: one fixed colour per label text, the same in every
//! map, sweep, study sheet and file (the atlas files store it beside their
//! label tables, so that scripts draw with the same colours). [`colour`] is a
//! pure function of the text.
//!
//! Three tiers:
//!
//! 1. **Fixed colours**: `C` chaotic black `#000000`, `Q` quasi-periodic dark
//!    grey `#666666`, `U` unresolved red `#D52828`, `1-0-0` (no impact) the
//!    neutral grey `#B8B8B8` (CIEDE2000 ΔE 16 from white, the figures'
//!    background).
//! 2. **The curated table** (`TABLE`, 136 labels): the labels that matter,
//!    chosen so that any two of them differ by CIEDE2000 ΔE ≥ 11 and each is
//!    ΔE ≥ 11 from the fixed colours and ≥ 15 from white. Whatever labels a
//!    map's most frequent ones are, if they are in the table they are told
//!    apart. The table holds every fundamental `1-p-q` with `p, q ≤ 5`, the
//!    complete chattering labels `1-S-q`, `1-p-S` (`p, q ≤ 5`), `1-S-S`,
//!    `2-S-q`, `2-p-S` (`p, q ≤ 3`), `2-S-S` and the single stop's `4-S-0` …
//!    `7-S-0`, the fundamental chattering labels of the shipped scenes (`1-p-p`
//!    up to `1-10-10`, `1-0-6` … `1-0-8`, `1-1-6`, `1-5-6`) and the subharmonics
//!    frequent in their reference maps (tests/palette.rs). The colours come
//!    from `scripts/palette_table.py`, an optimiser that maximises the smallest
//!    pairwise ΔE and, within it, keeps each label as near as it can to its
//!    family's colour below (so 1-1-1 is Okabe–Ito blue, the fundamentals
//!    mostly blues, sky blues, greens and yellows, the complete chattering
//!    labels mostly purples); distinctness comes first, so a family's members
//!    may take any hue. Edit the script's label list and run it with `--write`
//!    to change the table; never edit the table by hand.
//! 3. **Family rules** for every other periodic label, a deterministic
//!    function of the text (FNV-1a, mixed) within the family's range:
//!
//! | family | labels | colours (table labels / others) |
//! |---|---|---|
//! | no impact | `1-0-0` | neutral grey `#B8B8B8` |
//! | fundamental | `1-p-q` with `p, q < 6` | all in the table; preferred hue by `m = max(p, q)`: 1 blue, 2 sky blue, 3 bluish green, 4 yellow, 5 reddish purple, lighter when `p > q`, darker when `p < q` |
//! | subharmonic | `n-p-q`, `n > 1`, fewer than 6 impacts per period at each stop | table, or muted greens to teals (hue 85°–180°, HSL lightness 0.30–0.70) |
//! | chattering | 6 or more impacts per forcing period on average at a stop (`p/n` or `q/n >= 6`) | table, or oranges to browns (hue 24°–42°) |
//! | complete chattering | an `S` (the mass sticks) | table, or purples (hue 265°–305°) |
//! | not periodic | `C` chaotic, `Q` quasi-periodic, `U` unresolved | black, dark grey, red |
//!
//! Every colour, table or rule, is at least ΔE 15 from white and ΔE 10 from
//! `C`, `Q`, `U` and `1-0-0` (the unit tests check the rules' whole ranges);
//! a label outside the table may come near a table colour, which is why the
//! table holds every label frequent in the shipped scenes. [`delta_e`] is the
//! CIEDE2000 difference used throughout.

/// `1-0-0`, no impact: a neutral grey, ΔE 16 from white.
const NO_IMPACT: [u8; 3] = [184, 184, 184];

/// RGB colour of a label text (`1-4-4`, `2-S-3`, `C`, `Q`, `U`). Anything
/// else (for instance `not-computed`) is white.
pub fn colour(label: &str) -> [u8; 3] {
    match label {
        "1-0-0" => NO_IMPACT,
        "C" => [0, 0, 0],
        "Q" => [102, 102, 102],
        "U" => [213, 40, 40],
        _ => match TABLE.binary_search_by(|(l, _)| (*l).cmp(label)) {
            Ok(i) => TABLE[i].1,
            Err(_) => match parse(label) {
                Some((n, p, q)) => hashed(label, n, p, q),
                None => [255, 255, 255],
            },
        },
    }
}

/// A colour standing for a whole family in legends (its members vary).
pub fn family_colour(family: &str) -> [u8; 3] {
    match family {
        "complete chattering" => colour("1-S-S"),
        "chattering" => colour("1-6-6"),
        "fundamental" => colour("1-1-1"),
        "subharmonic" => colour("2-2-2"),
        "no impact" => colour("1-0-0"),
        "chaotic" => colour("C"),
        "quasi-periodic" => colour("Q"),
        "unresolved" => colour("U"),
        _ => [255, 255, 255],
    }
}

/// The family of a label (see the module doc), as written in legends.
pub fn family(label: &str) -> &'static str {
    match label {
        "1-0-0" => "no impact",
        "C" => "chaotic",
        "Q" => "quasi-periodic",
        "U" => "unresolved",
        _ => match parse(label) {
            Some((_, p, q)) if p.is_none() || q.is_none() => "complete chattering",
            Some((n, p, q)) if chattering(n, p, q) => "chattering",
            Some((1, _, _)) => "fundamental",
            Some(_) => "subharmonic",
            None => "other",
        },
    }
}

/// CIEDE2000 colour difference ΔE00 (Sharma, Wu and Dalal 2005; kL = kC =
/// kH = 1) between two sRGB colours, through CIELAB with the D65 white: the
/// measure the palette is designed with. About 1 is a just noticeable
/// difference; the table's labels are at least 11 apart.
pub fn delta_e(a: [u8; 3], b: [u8; 3]) -> f64 {
    ciede2000(lab(a), lab(b))
}

/// CIELAB (D65) of an sRGB colour.
fn lab(rgb: [u8; 3]) -> [f64; 3] {
    let lin = rgb.map(|c| {
        let c = c as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    });
    const M: [[f64; 3]; 3] =
        [[0.4124564, 0.3575761, 0.1804375], [0.2126729, 0.7151522, 0.0721750], [0.0193339, 0.1191920, 0.9503041]];
    const WHITE: [f64; 3] = [0.95047, 1.0, 1.08883];
    let f = |i: usize| {
        let t = (M[i][0] * lin[0] + M[i][1] * lin[1] + M[i][2] * lin[2]) / WHITE[i];
        if t > 216.0 / 24389.0 {
            t.cbrt()
        } else {
            (24389.0 / 27.0 * t + 16.0) / 116.0
        }
    };
    let (fx, fy, fz) = (f(0), f(1), f(2));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// CIEDE2000 of two CIELAB colours.
fn ciede2000([l1, a1, b1]: [f64; 3], [l2, a2, b2]: [f64; 3]) -> f64 {
    let pow7 = |c: f64| c.powi(7) / (c.powi(7) + 25f64.powi(7));
    let c_mean = (a1.hypot(b1) + a2.hypot(b2)) / 2.0;
    let g = 0.5 * (1.0 - pow7(c_mean).sqrt());
    let (a1, a2) = ((1.0 + g) * a1, (1.0 + g) * a2);
    let (c1, c2) = (a1.hypot(b1), a2.hypot(b2));
    let hue = |b: f64, a: f64| if a == 0.0 && b == 0.0 { 0.0 } else { b.atan2(a).to_degrees().rem_euclid(360.0) };
    let (h1, h2) = (hue(b1, a1), hue(b2, a2));
    let chromatic = c1 * c2 != 0.0;
    let dh = match h2 - h1 {
        _ if !chromatic => 0.0,
        d if d > 180.0 => d - 360.0,
        d if d < -180.0 => d + 360.0,
        d => d,
    };
    let d_big_h = 2.0 * (c1 * c2).sqrt() * (dh / 2.0).to_radians().sin();
    let (l_mean, c_mean) = ((l1 + l2) / 2.0, (c1 + c2) / 2.0);
    let h_mean = match h1 + h2 {
        s if !chromatic => s,
        s if (h1 - h2).abs() <= 180.0 => s / 2.0,
        s if s < 360.0 => (s + 360.0) / 2.0,
        s => (s - 360.0) / 2.0,
    };
    let cos = |deg: f64| deg.to_radians().cos();
    let t = 1.0 - 0.17 * cos(h_mean - 30.0) + 0.24 * cos(2.0 * h_mean) + 0.32 * cos(3.0 * h_mean + 6.0)
        - 0.20 * cos(4.0 * h_mean - 63.0);
    let rotation = 30.0 * (-((h_mean - 275.0) / 25.0).powi(2)).exp();
    let r_t = -(2.0 * rotation).to_radians().sin() * 2.0 * pow7(c_mean).sqrt();
    let s_l = 1.0 + 0.015 * (l_mean - 50.0).powi(2) / (20.0 + (l_mean - 50.0).powi(2)).sqrt();
    let s_c = 1.0 + 0.045 * c_mean;
    let s_h = 1.0 + 0.015 * c_mean * t;
    let (dl, dc, dhh) = ((l2 - l1) / s_l, (c2 - c1) / s_c, d_big_h / s_h);
    (dl * dl + dc * dc + dhh * dhh + r_t * dc * dhh).sqrt()
}

/// `(n, p, q)` of a periodic label, `None` for a count that is `S`.
fn parse(label: &str) -> Option<(u32, Option<u32>, Option<u32>)> {
    let mut it = label.split('-');
    let n: u32 = it.next()?.parse().ok()?;
    let count = |s: &str| if s == "S" { Some(None) } else { s.parse().ok().map(Some) };
    let p = count(it.next()?)?;
    let q = count(it.next()?)?;
    (it.next().is_none() && n > 0).then_some((n, p, q))
}

/// Six or more impacts per forcing period on average at a stop.
fn chattering(n: u32, p: Option<u32>, q: Option<u32>) -> bool {
    [p, q].into_iter().flatten().any(|c| c >= 6 * n)
}

/// The family rule of a periodic label outside the table: two numbers in
/// [0, 1] from the hash of its text, placed in its family's range.
fn hashed(label: &str, n: u32, p: Option<u32>, q: Option<u32>) -> [u8; 3] {
    let h = fnv(label);
    let unit = |bits: u64| (bits & 0xffff) as f64 / 65535.0;
    let kind = match (p, q) {
        (None, _) | (_, None) => Rule::CompleteChattering,
        _ if chattering(n, p, q) => Rule::Chattering,
        _ => Rule::Subharmonic,
    };
    kind.colour(unit(h), unit(h >> 16))
}

/// The hashed families' ranges (a fundamental `1-p-q` below 6 impacts is
/// always in the table; should one be missing, it is coloured as a
/// subharmonic).
#[derive(Clone, Copy, Debug)]
enum Rule {
    CompleteChattering,
    Chattering,
    Subharmonic,
}

impl Rule {
    fn colour(self, a: f64, b: f64) -> [u8; 3] {
        match self {
            Rule::CompleteChattering => hsl(265.0 + 40.0 * a, 0.45, 0.35 + 0.35 * b),
            Rule::Chattering => hsl(24.0 + 18.0 * a, 0.85, 0.40 + 0.25 * b),
            Rule::Subharmonic => hsl(85.0 + 95.0 * a, 0.40, 0.30 + 0.40 * b),
        }
    }
}

/// 64-bit FNV-1a hash of a text, with a final mix (MurmurHash3's fmix64) so
/// that labels differing in their last character get unrelated bits.
fn fnv(text: &str) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in text.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h ^= h >> 33;
    h = h.wrapping_mul(0xff51afd7ed558ccd);
    h ^= h >> 33;
    h = h.wrapping_mul(0xc4ceb9fe1a85ec53);
    h ^ (h >> 33)
}

/// RGB of hue (degrees), saturation and lightness in [0, 1].
fn hsl(h: f64, s: f64, l: f64) -> [u8; 3] {
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let hp = (h.rem_euclid(360.0)) / 60.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - c / 2.0;
    [r, g, b].map(|v| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8)
}

// BEGIN TABLE (scripts/palette_table.py)
/// The curated colours, sorted by label (136 labels; scripts/palette_table.py:
/// every two differ by CIEDE2000 dE >= 11.00, and each is that far from C, Q, U
/// and 1-0-0 and 15 from white).
const TABLE: [(&str, [u8; 3]); 136] = [
    ("1-0-1", [0, 66, 107]),
    ("1-0-2", [33, 99, 123]),
    ("1-0-3", [0, 90, 41]),
    ("1-0-4", [107, 49, 0]),
    ("1-0-5", [66, 8, 25]),
    ("1-0-6", [156, 0, 0]),
    ("1-0-7", [156, 74, 49]),
    ("1-0-8", [156, 107, 99]),
    ("1-0-S", [58, 8, 173]),
    ("1-1-0", [148, 181, 255]),
    ("1-1-1", [0, 115, 181]),
    ("1-1-2", [41, 148, 189]),
    ("1-1-3", [66, 82, 25]),
    ("1-1-4", [189, 156, 33]),
    ("1-1-5", [148, 82, 99]),
    ("1-1-6", [255, 181, 123]),
    ("1-1-S", [115, 33, 41]),
    ("1-10-10", [247, 107, 0]),
    ("1-2-0", [189, 173, 255]),
    ("1-2-1", [156, 222, 255]),
    ("1-2-2", [82, 181, 239]),
    ("1-2-3", [25, 41, 49]),
    ("1-2-4", [90, 115, 206]),
    ("1-2-5", [206, 107, 123]),
    ("1-2-S", [107, 58, 82]),
    ("1-3-0", [189, 230, 230]),
    ("1-3-1", [222, 255, 222]),
    ("1-3-2", [82, 148, 230]),
    ("1-3-3", [140, 123, 123]),
    ("1-3-4", [255, 156, 230]),
    ("1-3-5", [206, 49, 99]),
    ("1-3-S", [74, 66, 214]),
    ("1-4-0", [255, 214, 197]),
    ("1-4-1", [255, 239, 181]),
    ("1-4-2", [230, 247, 140]),
    ("1-4-3", [255, 173, 156]),
    ("1-4-4", [247, 230, 66]),
    ("1-4-5", [165, 115, 140]),
    ("1-4-S", [222, 58, 255]),
    ("1-5-0", [255, 58, 140]),
    ("1-5-1", [222, 197, 206]),
    ("1-5-2", [255, 206, 247]),
    ("1-5-3", [206, 165, 197]),
    ("1-5-4", [239, 148, 173]),
    ("1-5-5", [214, 115, 173]),
    ("1-5-6", [239, 140, 8]),
    ("1-5-S", [66, 41, 82]),
    ("1-6-6", [247, 107, 90]),
    ("1-7-7", [181, 82, 0]),
    ("1-8-8", [189, 107, 74]),
    ("1-9-9", [247, 58, 8]),
    ("1-S-0", [140, 33, 140]),
    ("1-S-1", [140, 0, 74]),
    ("1-S-2", [99, 0, 82]),
    ("1-S-3", [222, 49, 173]),
    ("1-S-4", [148, 123, 222]),
    ("1-S-5", [49, 0, 41]),
    ("1-S-S", [58, 0, 99]),
    ("2-0-2", [115, 99, 123]),
    ("2-0-4", [181, 156, 156]),
    ("2-0-5", [25, 49, 0]),
    ("2-0-6", [90, 82, 58]),
    ("2-0-7", [156, 165, 33]),
    ("2-0-S", [66, 90, 156]),
    ("2-1-0", [140, 107, 33]),
    ("2-1-3", [115, 247, 49]),
    ("2-1-S", [49, 49, 123]),
    ("2-2-0", [132, 140, 148]),
    ("2-2-1", [123, 173, 115]),
    ("2-2-2", [58, 214, 107]),
    ("2-2-3", [181, 132, 58]),
    ("2-2-4", [74, 58, 58]),
    ("2-2-S", [173, 0, 58]),
    ("2-3-0", [230, 140, 99]),
    ("2-3-2", [197, 214, 247]),
    ("2-3-S", [173, 99, 189]),
    ("2-4-0", [247, 197, 82]),
    ("2-4-2", [99, 90, 0]),
    ("2-4-4", [206, 173, 115]),
    ("2-4-5", [214, 197, 173]),
    ("2-4-6", [49, 49, 66]),
    ("2-5-4", [173, 173, 197]),
    ("2-6-0", [99, 115, 49]),
    ("2-6-4", [66, 58, 8]),
    ("2-6-6", [148, 173, 189]),
    ("2-8-0", [66, 181, 25]),
    ("2-8-8", [66, 82, 66]),
    ("2-S-0", [132, 0, 206]),
    ("2-S-1", [41, 25, 33]),
    ("2-S-2", [140, 82, 239]),
    ("2-S-3", [206, 132, 230]),
    ("2-S-S", [140, 82, 132]),
    ("3-0-1", [165, 222, 156]),
    ("3-0-4", [90, 123, 140]),
    ("3-1-0", [0, 74, 58]),
    ("3-1-3", [49, 33, 8]),
    ("3-10-10", [49, 49, 33]),
    ("3-13-13", [49, 123, 58]),
    ("3-2-0", [156, 206, 82]),
    ("3-2-4", [156, 222, 197]),
    ("3-3-0", [173, 173, 123]),
    ("3-3-4", [132, 148, 189]),
    ("3-3-6", [0, 230, 247]),
    ("3-4-3", [41, 156, 74]),
    ("3-4-4", [140, 132, 41]),
    ("3-6-3", [25, 181, 132]),
    ("3-6-6", [165, 189, 165]),
    ("3-7-7", [0, 230, 173]),
    ("4-0-2", [206, 165, 140]),
    ("4-0-6", [82, 140, 107]),
    ("4-10-8", [0, 25, 58]),
    ("4-2-0", [115, 189, 197]),
    ("4-2-4", [107, 115, 140]),
    ("4-3-0", [123, 99, 82]),
    ("4-4-0", [156, 140, 165]),
    ("4-4-4", [115, 74, 66]),
    ("4-4-8", [132, 156, 148]),
    ("4-6-0", [156, 148, 132]),
    ("4-6-4", [8, 41, 33]),
    ("4-8-10", [107, 123, 115]),
    ("4-8-4", [123, 115, 90]),
    ("4-S-0", [123, 99, 173]),
    ("5-0-0", [33, 115, 90]),
    ("5-0-5", [0, 74, 82]),
    ("5-10-10", [49, 123, 123]),
    ("5-5-2", [66, 247, 230]),
    ("5-5-3", [66, 197, 181]),
    ("5-5-5", [74, 82, 99]),
    ("5-6-6", [66, 156, 156]),
    ("5-S-0", [181, 33, 123]),
    ("6-0-6", [107, 74, 16]),
    ("6-2-0", [165, 132, 107]),
    ("6-6-0", [107, 148, 41]),
    ("6-S-0", [90, 74, 123]),
    ("7-S-0", [189, 16, 206]),
    ("8-8-8", [132, 140, 99]),
];
/// The smallest CIEDE2000 difference the optimiser reached (tests check it).
#[cfg(test)]
const TABLE_MIN_DE: f64 = 11.00;
// END TABLE

#[cfg(test)]
mod tests {
    use super::*;

    const WHITE: [u8; 3] = [255, 255, 255];
    const FIXED: [&str; 4] = ["C", "Q", "U", "1-0-0"];

    /// `colour` of every label of the table and every fixed one.
    fn table_and_fixed() -> Vec<(&'static str, [u8; 3])> {
        TABLE.iter().copied().chain(FIXED.map(|l| (l, colour(l)))).collect()
    }

    #[test]
    fn fixed_colours() {
        assert_eq!(colour("C"), [0, 0, 0]);
        assert_eq!(colour("Q"), [102, 102, 102]);
        assert_eq!(colour("U"), [213, 40, 40]);
        assert_eq!(colour("not-computed"), WHITE);
        // No impact: a neutral grey, told apart from the white background
        // (#DDDDDD was ΔE 9 from it).
        let [r, g, b] = colour("1-0-0");
        assert!(r == g && g == b, "1-0-0 is not neutral: {r} {g} {b}");
        let d = delta_e(colour("1-0-0"), WHITE);
        assert!((15.0..20.0).contains(&d), "1-0-0 is ΔE {d:.2} from white");
        assert_eq!(colour("1-1-1"), [0, 115, 181], "1-1-1 keeps Okabe–Ito blue");
    }

    /// The table is sorted (binary search), its labels parse and are not
    /// fixed ones, and `colour` returns its entries.
    #[test]
    fn table_is_well_formed() {
        assert!(TABLE.windows(2).all(|w| w[0].0 < w[1].0), "TABLE is not sorted or has a duplicate");
        for (label, rgb) in TABLE {
            assert!(parse(label).is_some(), "{label} is not n-p-q");
            assert!(!FIXED.contains(&label), "{label} is fixed");
            assert_eq!(colour(label), rgb, "{label}");
        }
        // What the module doc promises to hold.
        let mut promised: Vec<String> = (0..6).flat_map(|p| (0..6).map(move |q| format!("1-{p}-{q}"))).collect();
        promised.retain(|l| l != "1-0-0");
        promised.extend((0..6).flat_map(|k| [format!("1-S-{k}"), format!("1-{k}-S")]));
        promised.extend((0..4).flat_map(|k| [format!("2-S-{k}"), format!("2-{k}-S")]));
        promised.extend(["1-S-S", "2-S-S", "4-S-0", "7-S-0", "1-10-10", "1-0-8", "1-1-6", "1-5-6"].map(String::from));
        for l in &promised {
            assert!(TABLE.binary_search_by(|(t, _)| (*t).cmp(l)).is_ok(), "{l} is not in the table");
        }
        assert_eq!(TABLE.len(), 136, "the module doc gives the table's size");
    }

    /// The table's guarantee: any two of its colours, fixed ones included,
    /// differ by CIEDE2000 ΔE ≥ 11 (`TABLE_MIN_DE`, what the optimiser
    /// reached; the module doc says 11), every one is ≥ 15 from white.
    const _: () = assert!(TABLE_MIN_DE >= 11.0, "the module doc promises ΔE 11");

    #[test]
    fn table_colours_stay_apart() {
        let all = table_and_fixed();
        let mut worst = (f64::INFINITY, "", "");
        for (i, &(a, ca)) in all.iter().enumerate() {
            assert!(delta_e(ca, WHITE) >= 15.0, "{a} {ca:?} is ΔE {:.2} from white", delta_e(ca, WHITE));
            for &(b, cb) in &all[..i] {
                let d = delta_e(ca, cb);
                if d < worst.0 {
                    worst = (d, a, b);
                }
            }
        }
        let (d, a, b) = worst;
        println!("closest pair of the table: {a} {b} ΔE {d:.2}");
        assert!(d >= TABLE_MIN_DE, "{a} and {b} are ΔE {d:.2} apart");
    }

    /// Labels outside the table: whatever the hash gives, the family rules
    /// stay ≥ 15 from white and ≥ 10 from C, Q, U and 1-0-0 (a dense sweep
    /// of each rule's two numbers), and labels fall in the right families.
    #[test]
    fn family_rules_keep_away_from_fixed_colours_and_white() {
        let fixed = FIXED.map(colour);
        for rule in [Rule::CompleteChattering, Rule::Chattering, Rule::Subharmonic] {
            let mut worst = (f64::INFINITY, f64::INFINITY);
            for i in 0..=64 {
                for j in 0..=64 {
                    let c = rule.colour(i as f64 / 64.0, j as f64 / 64.0);
                    let to_fixed = fixed.iter().map(|&f| delta_e(c, f)).fold(f64::INFINITY, f64::min);
                    worst = (worst.0.min(delta_e(c, WHITE)), worst.1.min(to_fixed));
                }
            }
            assert!(
                worst.0 >= 15.0 && worst.1 >= 10.0,
                "{rule:?}: ΔE {:.2} from white, {:.2} from fixed",
                worst.0,
                worst.1
            );
        }
        for (label, fam) in [("3-S-7", "complete chattering"), ("1-12-3", "chattering"), ("7-5-3", "subharmonic")] {
            assert!(TABLE.binary_search_by(|(t, _)| (*t).cmp(label)).is_err());
            assert_eq!(family(label), fam);
            let c = colour(label);
            assert_eq!(c, colour(label), "the same label, the same colour");
            assert!(fixed.iter().all(|&f| delta_e(c, f) >= 10.0) && delta_e(c, WHITE) >= 15.0, "{label} {c:?}");
        }
    }

    #[test]
    fn families() {
        assert_eq!(family("1-0-0"), "no impact");
        assert_eq!(family("1-4-4"), "fundamental");
        assert_eq!(family("1-0-3"), "fundamental");
        assert_eq!(family("1-7-6"), "chattering");
        assert_eq!(family("19-19-19"), "subharmonic");
        assert_eq!(family("2-12-12"), "chattering");
        assert_eq!(family("2-11-11"), "subharmonic");
        assert_eq!(family("1-S-S"), "complete chattering");
        assert_eq!(family("1-S-3"), "complete chattering");
        assert_eq!(family("C"), "chaotic");
        assert_eq!(family("not-computed"), "other");
        // Each family's legend colour is a member's, and they differ.
        let fams = ["complete chattering", "chattering", "fundamental", "subharmonic", "no impact", "chaotic"];
        for (i, a) in fams.iter().enumerate() {
            assert_ne!(family_colour(a), WHITE, "{a}");
            for b in &fams[..i] {
                assert_ne!(family_colour(a), family_colour(b), "{a} and {b}");
            }
        }
        assert_eq!(family_colour("fundamental"), colour("1-1-1"));
    }

    /// The user's report (issue 29): these looked the same.
    #[test]
    fn reported_pairs_are_told_apart() {
        for (a, b) in [
            ("1-4-3", "1-4-4"),
            ("5-5-2", "2-6-4"),
            ("2-2-1", "5-5-2"),
            ("5-5-3", "2-3-2"),
            ("1-2-1", "1-1-0"),
            ("1-S-1", "1-S-S"),
            ("1-S-2", "1-S-3"),
            ("1-S-1", "1-S-3"),
        ] {
            let d = delta_e(colour(a), colour(b));
            assert!(d >= 10.0, "{a} and {b}: ΔE {d:.2}");
        }
    }

    /// `delta_e` against Sharma, Wu and Dalal's test data and against the
    /// `palette` crate's CIEDE2000 on every pair of the table's colours.
    #[test]
    fn ciede2000_agrees_with_references() {
        for (x, y, want) in [
            ([50.0, 2.6772, -79.7751], [50.0, 0.0, -82.7485], 2.0425),
            ([50.0, 0.0, 0.0], [50.0, -1.0, 2.0], 2.3669),
            ([50.0, 2.49, -0.001], [50.0, -2.49, 0.0011], 7.2195),
            ([50.0, 2.5, 0.0], [73.0, 25.0, -18.0], 27.1492),
            ([2.0776, 0.0795, -1.135], [0.9033, -0.0636, -0.5514], 0.9082),
            ([60.2574, -34.0099, 36.2677], [60.4626, -34.1751, 39.4387], 1.2644),
        ] {
            let got = ciede2000(x, y);
            assert!((got - want).abs() < 1e-4, "{x:?} {y:?}: {got} against {want}");
        }
        use ::palette::color_difference::Ciede2000;
        use ::palette::{white_point::D65, IntoColor, Lab, Srgb};
        let theirs = |c: [u8; 3]| -> Lab<D65, f64> { Srgb::new(c[0], c[1], c[2]).into_format::<f64>().into_color() };
        let all = table_and_fixed();
        let mut worst = 0.0f64;
        for &(_, a) in &all {
            for &(_, b) in &all {
                worst = worst.max((delta_e(a, b) - theirs(a).difference(theirs(b))).abs());
            }
        }
        assert!(worst < 0.05, "delta_e differs from palette's Ciede2000 by {worst}");
    }
}
