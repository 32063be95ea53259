//! The colour of a label: one fixed colour per label text, the same in every
//! map, sweep, study sheet and file (the atlas files store it beside their
//! label tables, so that scripts draw with the same colours). [`colour`] is a
//! pure function of the label (families' rules hash its text).
//!
//! Three tiers:
//!
//! 1. **Fixed colours**: `C` chaotic black `#000000`, `Q` quasi-periodic dark
//!    grey `#666666`, `U` unresolved red `#D52828`, `1-0-0` (no impact) the
//!    neutral grey `#B8B8B8` (CIEDE2000 ΔE 16 from white, the figures'
//!    background).
//! 2. **The curated table** (`TABLE`, 137 labels): the labels that matter,
//!    chosen so that any two of them differ by CIEDE2000 ΔE ≥ 10.25, each is
//!    ΔE ≥ 20 from `C`'s black, ≥ 15 from `Q`, `U`, `1-0-0` and white, and
//!    has CIELAB lightness L* ≥ 25: no periodic label is dark enough to pass
//!    for chaos in a small cell (an earlier table, ΔE ≥ 11 from everything,
//!    had near-blacks such as `3-1-3` `#312108`, 11.8 from `C`). Whatever
//!    labels a map's most frequent ones are, if they are in the table they
//!    are told apart. The table holds every fundamental `1-p-q` with `p, q ≤ 5`, the
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
//! | chattering | 6 or more impacts per forcing period on average at a stop (`p/n` or `q/n >= 6`) | table, or oranges to browns (hue 24°–42°, HSL lightness 0.42–0.65) |
//! | complete chattering | an `S` (the mass sticks) | table, or purples (hue 265°–305°, HSL lightness 0.35–0.70) |
//! | not periodic | `C` chaotic, `Q` quasi-periodic, `U` unresolved | black, dark grey, red |
//!
//! Every periodic colour, table or rule, is at least ΔE 20 from `C`, ΔE 15
//! from `Q`, `U`, `1-0-0` and white, and has L* ≥ 25 (the unit tests check
//! the rules' whole ranges); a label outside the table may come near a
//! table colour, which is why the table holds every label frequent in the
//! shipped scenes. [`delta_e`] is the
//! CIEDE2000 difference used throughout.

use solver::{Count, Label};

/// `1-0-0`, no impact: a neutral grey, ΔE 16 from white.
const NO_IMPACT: [u8; 3] = [184, 184, 184];

/// The colour of a cell without a label (not computed): white, the
/// figures' background, apart from every label's colour.
pub const BLANK: [u8; 3] = [255, 255, 255];

/// A colour faded toward white, three fifths of the way (each channel
/// `(2 c + 3 · 255) / 5`, rounded): the hysteresis view's cells where the
/// up and down sweeps agree, drawn in their label's hue but receding, so
/// that the cells where they differ stand out.
pub fn faded(c: [u8; 3]) -> [u8; 3] {
    c.map(|v| ((2 * u32::from(v) + 3 * 255 + 2) / 5) as u8)
}

/// RGB colour of a label (`1-4-4`, `2-S-3`, `C`, `Q`, `U`).
pub fn colour(label: Label) -> [u8; 3] {
    match label {
        Label::Chaotic => [0, 0, 0],
        Label::Quasiperiodic => [102, 102, 102],
        Label::Unresolved => [213, 40, 40],
        Label::Periodic { n: 1, p: Count::Impacts(0), q: Count::Impacts(0) } => NO_IMPACT,
        Label::Periodic { .. } => {
            // The text on the stack: a map colours every cell by this function.
            let mut buf = [0u8; LONGEST_LABEL];
            let text = text_of(label, &mut buf);
            match TABLE.binary_search_by(|(l, _)| (*l).cmp(text)) {
                Ok(i) => TABLE[i].1,
                Err(_) => hashed(text, Family::of(label)),
            }
        }
    }
}

/// Bytes of the longest label text, `4294967295-4294967295-4294967295`.
const LONGEST_LABEL: usize = 32;

/// The text of `label` (as it prints) written into `buf`.
fn text_of(label: Label, buf: &mut [u8; LONGEST_LABEL]) -> &str {
    use std::io::Write;
    let mut rest = &mut buf[..];
    write!(rest, "{label}").expect("a label's text fits LONGEST_LABEL bytes");
    let len = LONGEST_LABEL - rest.len();
    std::str::from_utf8(&buf[..len]).expect("a label's text is ASCII")
}

/// The family of a label (see the module doc), as legends group labels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Family {
    /// `1-0-0`.
    NoImpact,
    /// `1-p-q`, fewer than 6 impacts per period at each stop.
    Fundamental,
    /// `n-p-q`, `n > 1`, fewer than 6 impacts per forcing period at each stop.
    Subharmonic,
    /// 6 or more impacts per forcing period on average at a stop.
    Chattering,
    /// A stop held the mass (an `S`).
    CompleteChattering,
    /// `C`.
    Chaotic,
    /// `Q`.
    Quasiperiodic,
    /// `U`.
    Unresolved,
}

impl Family {
    /// The family of `label`.
    pub fn of(label: Label) -> Family {
        match label {
            Label::Chaotic => Family::Chaotic,
            Label::Quasiperiodic => Family::Quasiperiodic,
            Label::Unresolved => Family::Unresolved,
            Label::Periodic { n: 1, p: Count::Impacts(0), q: Count::Impacts(0) } => Family::NoImpact,
            Label::Periodic { n, p, q } => match (impacts(p), impacts(q)) {
                (None, _) | (_, None) => Family::CompleteChattering,
                (p, q) if chattering(n, p, q) => Family::Chattering,
                _ if n == 1 => Family::Fundamental,
                _ => Family::Subharmonic,
            },
        }
    }

    /// The family's name as legends write it (`complete chattering`, `no impact`, …).
    pub fn name(self) -> &'static str {
        match self {
            Family::NoImpact => "no impact",
            Family::Fundamental => "fundamental",
            Family::Subharmonic => "subharmonic",
            Family::Chattering => "chattering",
            Family::CompleteChattering => "complete chattering",
            Family::Chaotic => "chaotic",
            Family::Quasiperiodic => "quasi-periodic",
            Family::Unresolved => "unresolved",
        }
    }

    /// A colour standing for the whole family in legends (a member's: its
    /// members vary).
    pub fn colour(self) -> [u8; 3] {
        let periodic = |n, p, q| colour(Label::Periodic { n, p: Count::Impacts(p), q: Count::Impacts(q) });
        match self {
            Family::NoImpact => NO_IMPACT,
            Family::Fundamental => periodic(1, 1, 1),
            Family::Subharmonic => periodic(2, 2, 2),
            Family::Chattering => periodic(1, 6, 6),
            Family::CompleteChattering => colour(Label::Periodic { n: 1, p: Count::Stuck, q: Count::Stuck }),
            Family::Chaotic => colour(Label::Chaotic),
            Family::Quasiperiodic => colour(Label::Quasiperiodic),
            Family::Unresolved => colour(Label::Unresolved),
        }
    }
}

/// CIEDE2000 colour difference ΔE00 (Sharma, Wu and Dalal 2005; kL = kC =
/// kH = 1) between two sRGB colours, through CIELAB with the D65 white: the
/// measure the palette is designed with. About 1 is a just noticeable
/// difference; the table's labels are at least 10.25 apart.
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

/// The impacts of a count, `None` for `S` (the stop held the mass).
fn impacts(c: Count) -> Option<u32> {
    match c {
        Count::Impacts(k) => Some(k),
        Count::Stuck => None,
    }
}

/// Six or more impacts per forcing period on average at a stop.
fn chattering(n: u32, p: Option<u32>, q: Option<u32>) -> bool {
    [p, q].into_iter().flatten().any(|c| c >= 6 * n)
}

/// The family rule of a periodic label outside the table (its text, its
/// family): two numbers in [0, 1] from the hash of its text, placed in its
/// family's range.
fn hashed(text: &str, family: Family) -> [u8; 3] {
    let h = fnv(text);
    let unit = |bits: u64| (bits & 0xffff) as f64 / 65535.0;
    let kind = match family {
        Family::CompleteChattering => Rule::CompleteChattering,
        Family::Chattering => Rule::Chattering,
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
            Rule::Chattering => hsl(24.0 + 18.0 * a, 0.85, 0.42 + 0.23 * b),
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
/// The curated colours, sorted by label (137 labels; scripts/palette_table.py:
/// every two differ by CIEDE2000 dE >= 10.25; each is >= 20 from C, >= 15 from Q,
/// 15 from U, 15 from 1-0-0 and 15 from white, CIELAB L* >= 25).
const TABLE: [(&str, [u8; 3]); 137] = [
    ("1-0-1", [0, 66, 107]),
    ("1-0-2", [49, 115, 140]),
    ("1-0-3", [74, 58, 0]),
    ("1-0-4", [148, 140, 41]),
    ("1-0-5", [115, 74, 99]),
    ("1-0-6", [230, 140, 115]),
    ("1-0-7", [247, 41, 99]),
    ("1-0-8", [140, 0, 16]),
    ("1-0-S", [140, 0, 58]),
    ("1-1-0", [189, 239, 247]),
    ("1-1-1", [0, 107, 173]),
    ("1-1-2", [49, 148, 189]),
    ("1-1-3", [165, 206, 25]),
    ("1-1-4", [206, 255, 0]),
    ("1-1-5", [156, 66, 82]),
    ("1-1-6", [197, 123, 49]),
    ("1-1-S", [99, 90, 123]),
    ("1-10-10", [230, 99, 0]),
    ("1-2-0", [197, 214, 255]),
    ("1-2-1", [156, 214, 247]),
    ("1-2-2", [82, 181, 239]),
    ("1-2-3", [49, 90, 99]),
    ("1-2-4", [189, 181, 49]),
    ("1-2-5", [140, 99, 99]),
    ("1-2-S", [90, 90, 165]),
    ("1-3-0", [189, 222, 206]),
    ("1-3-1", [107, 222, 214]),
    ("1-3-2", [222, 206, 239]),
    ("1-3-3", [0, 239, 74]),
    ("1-3-4", [239, 197, 41]),
    ("1-3-5", [181, 99, 115]),
    ("1-3-S", [156, 49, 115]),
    ("1-4-0", [247, 247, 197]),
    ("1-4-1", [247, 222, 140]),
    ("1-4-2", [230, 247, 140]),
    ("1-4-3", [255, 197, 115]),
    ("1-4-4", [239, 230, 58]),
    ("1-4-5", [173, 132, 148]),
    ("1-4-S", [255, 90, 148]),
    ("1-5-0", [206, 165, 173]),
    ("1-5-1", [247, 206, 206]),
    ("1-5-2", [247, 189, 222]),
    ("1-5-3", [214, 156, 214]),
    ("1-5-4", [239, 148, 181]),
    ("1-5-5", [206, 115, 165]),
    ("1-5-6", [239, 148, 25]),
    ("1-5-S", [58, 66, 115]),
    ("1-6-6", [247, 140, 74]),
    ("1-7-7", [181, 90, 25]),
    ("1-8-8", [156, 58, 0]),
    ("1-9-9", [255, 99, 90]),
    ("1-S-0", [107, 33, 74]),
    ("1-S-1", [123, 16, 115]),
    ("1-S-2", [247, 25, 173]),
    ("1-S-3", [189, 58, 165]),
    ("1-S-4", [165, 66, 239]),
    ("1-S-5", [90, 58, 115]),
    ("1-S-S", [74, 58, 74]),
    ("2-0-2", [115, 82, 41]),
    ("2-0-4", [255, 197, 165]),
    ("2-0-5", [33, 82, 33]),
    ("2-0-6", [107, 115, 25]),
    ("2-0-7", [25, 165, 8]),
    ("2-0-8", [156, 99, 0]),
    ("2-0-S", [66, 58, 173]),
    ("2-1-0", [132, 107, 8]),
    ("2-1-3", [41, 206, 115]),
    ("2-1-S", [132, 107, 189]),
    ("2-2-0", [173, 156, 189]),
    ("2-2-1", [66, 255, 165]),
    ("2-2-2", [148, 148, 123]),
    ("2-2-3", [148, 115, 82]),
    ("2-2-4", [140, 90, 66]),
    ("2-2-S", [239, 115, 230]),
    ("2-3-0", [148, 140, 239]),
    ("2-3-2", [66, 74, 41]),
    ("2-3-S", [173, 107, 181]),
    ("2-4-0", [255, 173, 165]),
    ("2-4-2", [107, 49, 41]),
    ("2-4-4", [148, 132, 123]),
    ("2-4-5", [123, 165, 25]),
    ("2-4-6", [66, 90, 0]),
    ("2-5-4", [197, 173, 107]),
    ("2-6-0", [41, 115, 0]),
    ("2-6-4", [25, 115, 66]),
    ("2-6-6", [181, 140, 49]),
    ("2-8-0", [173, 123, 107]),
    ("2-8-8", [90, 66, 58]),
    ("2-S-0", [148, 99, 132]),
    ("2-S-1", [206, 58, 123]),
    ("2-S-2", [222, 58, 230]),
    ("2-S-3", [181, 115, 239]),
    ("2-S-S", [115, 99, 255]),
    ("3-0-1", [165, 255, 222]),
    ("3-0-4", [181, 247, 173]),
    ("3-1-0", [140, 140, 156]),
    ("3-1-3", [115, 173, 181]),
    ("3-10-10", [74, 66, 49]),
    ("3-13-13", [90, 107, 66]),
    ("3-2-0", [25, 107, 247]),
    ("3-2-4", [58, 66, 82]),
    ("3-3-0", [0, 206, 230]),
    ("3-3-4", [41, 148, 156]),
    ("3-3-6", [58, 181, 140]),
    ("3-4-3", [99, 165, 99]),
    ("3-4-4", [99, 197, 49]),
    ("3-6-3", [230, 206, 173]),
    ("3-6-6", [25, 74, 247]),
    ("3-7-7", [58, 222, 181]),
    ("4-0-2", [140, 206, 156]),
    ("4-0-6", [99, 90, 41]),
    ("4-10-8", [156, 165, 99]),
    ("4-2-0", [49, 148, 123]),
    ("4-2-4", [115, 148, 132]),
    ("4-3-0", [132, 165, 206]),
    ("4-4-0", [206, 165, 148]),
    ("4-4-4", [173, 148, 115]),
    ("4-4-8", [173, 206, 123]),
    ("4-6-0", [82, 123, 99]),
    ("4-6-4", [49, 74, 66]),
    ("4-8-10", [140, 123, 156]),
    ("4-8-4", [181, 173, 239]),
    ("4-S-0", [132, 82, 148]),
    ("5-0-0", [25, 99, 82]),
    ("5-0-5", [99, 132, 140]),
    ("5-10-10", [58, 115, 115]),
    ("5-5-2", [16, 181, 173]),
    ("5-5-3", [132, 189, 173]),
    ("5-5-5", [0, 132, 222]),
    ("5-6-6", [107, 132, 165]),
    ("5-S-0", [115, 33, 239]),
    ("6-0-6", [115, 140, 66]),
    ("6-2-0", [132, 123, 82]),
    ("6-6-0", [197, 197, 156]),
    ("6-S-0", [107, 8, 165]),
    ("7-S-0", [165, 0, 189]),
    ("8-8-8", [41, 140, 58]),
];
/// The smallest CIEDE2000 difference the optimiser reached (tests check it).
#[cfg(test)]
const TABLE_MIN_DE: f64 = 10.25;
// END TABLE

#[cfg(test)]
mod tests {
    use super::*;

    /// The colour of a label written as text (the tests name labels as
    /// the figures print them).
    fn colour(text: &str) -> [u8; 3] {
        super::colour(label(text))
    }

    fn label(text: &str) -> Label {
        text.parse().unwrap_or_else(|e| panic!("{e}"))
    }

    fn family(text: &str) -> &'static str {
        Family::of(label(text)).name()
    }

    const WHITE: [u8; 3] = [255, 255, 255];
    const FIXED: [&str; 4] = ["C", "Q", "U", "1-0-0"];
    /// The module doc's guarantees for every periodic colour, table or rule:
    /// CIEDE2000 ΔE from each fixed colour, from white, and CIELAB L*.
    const FIXED_GAP: [(&str, f64); 4] = [("C", 20.0), ("Q", 15.0), ("U", 15.0), ("1-0-0", 15.0)];
    const WHITE_GAP: f64 = 15.0;
    const L_MIN: f64 = 25.0;

    /// `colour` of every label of the table and every fixed one.
    fn table_and_fixed() -> Vec<(&'static str, [u8; 3])> {
        TABLE.iter().copied().chain(FIXED.map(|l| (l, colour(l)))).collect()
    }

    /// Where a periodic colour breaks the guarantees (empty when it keeps
    /// them), and its smallest margin over them.
    fn broken(c: [u8; 3]) -> (Vec<String>, f64) {
        let mut broken = Vec::new();
        let mut margin = f64::INFINITY;
        let mut check = |what: &str, got: f64, need: f64| {
            margin = margin.min(got - need);
            if got < need {
                broken.push(format!("{what} {got:.2} < {need}"));
            }
        };
        for (f, gap) in FIXED_GAP {
            check(&format!("ΔE from {f}"), delta_e(c, colour(f)), gap);
        }
        check("ΔE from white", delta_e(c, WHITE), WHITE_GAP);
        check("L*", lab(c)[0], L_MIN);
        (broken, margin)
    }

    #[test]
    fn fixed_colours() {
        assert_eq!(colour("C"), [0, 0, 0]);
        assert_eq!(colour("Q"), [102, 102, 102]);
        assert_eq!(colour("U"), [213, 40, 40]);
        assert_eq!(BLANK, WHITE, "a cell not computed is the background's white");
        // No impact: a neutral grey, told apart from the white background
        // (#DDDDDD was ΔE 9 from it).
        let [r, g, b] = colour("1-0-0");
        assert!(r == g && g == b, "1-0-0 is not neutral: {r} {g} {b}");
        let d = delta_e(colour("1-0-0"), WHITE);
        assert!((15.0..20.0).contains(&d), "1-0-0 is ΔE {d:.2} from white");
        assert_eq!(colour("1-1-1"), [0, 107, 173], "1-1-1 keeps (near) Okabe–Ito blue");
    }

    /// The table is sorted (binary search), its labels parse and are not
    /// fixed ones, and `colour` returns its entries.
    #[test]
    fn table_is_well_formed() {
        assert!(TABLE.windows(2).all(|w| w[0].0 < w[1].0), "TABLE is not sorted or has a duplicate");
        for (label, rgb) in TABLE {
            assert!(label.parse::<Label>().is_ok_and(|l| l.npq().is_some()), "{label} is not n-p-q");
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
        assert_eq!(TABLE.len(), 137, "the module doc gives the table's size");
    }

    /// The table's guarantee: any two of its colours differ by CIEDE2000
    /// ΔE ≥ `TABLE_MIN_DE` (what the optimiser reached; the module doc gives
    /// it, and promises at least 10); every one keeps the fixed colours'
    /// gaps (≥ 20 from C, ≥ 15 from Q, U, 1-0-0 and white) and L* ≥ 25.
    const _: () = assert!(TABLE_MIN_DE >= 10.0, "the module doc promises ΔE 10");

    #[test]
    fn table_colours_stay_apart() {
        let mut worst = (f64::INFINITY, "", "");
        let mut margin = (f64::INFINITY, "");
        for (i, &(a, ca)) in TABLE.iter().enumerate() {
            let (bad, m) = broken(ca);
            assert!(bad.is_empty(), "{a} {ca:?}: {}", bad.join(", "));
            if m < margin.0 {
                margin = (m, a);
            }
            for &(b, cb) in &TABLE[..i] {
                let d = delta_e(ca, cb);
                if d < worst.0 {
                    worst = (d, a, b);
                }
            }
        }
        let (d, a, b) = worst;
        println!(
            "closest pair of the table: {a} {b} ΔE {d:.2}; least margin over the gaps {:.2} ({})",
            margin.0, margin.1
        );
        assert!(d >= TABLE_MIN_DE, "{a} and {b} are ΔE {d:.2} apart");
        // The fixed colours among themselves.
        let fixed = table_and_fixed().split_off(TABLE.len());
        for (i, &(a, ca)) in fixed.iter().enumerate() {
            for &(b, cb) in &fixed[..i] {
                assert!(delta_e(ca, cb) >= 15.0, "{a} and {b}: ΔE {:.2}", delta_e(ca, cb));
            }
        }
    }

    /// Labels outside the table: whatever the hash gives, the family rules
    /// keep the same gaps as the table (≥ 20 from C, ≥ 15 from Q, U, 1-0-0
    /// and white, L* ≥ 25; a dense sweep of each rule's two numbers), and
    /// labels fall in the right families.
    #[test]
    fn family_rules_keep_away_from_fixed_colours_and_white() {
        for rule in [Rule::CompleteChattering, Rule::Chattering, Rule::Subharmonic] {
            let mut margin = f64::INFINITY;
            for i in 0..=128 {
                for j in 0..=128 {
                    let c = rule.colour(i as f64 / 128.0, j as f64 / 128.0);
                    let (bad, m) = broken(c);
                    assert!(bad.is_empty(), "{rule:?} at ({i}, {j})/128, {c:?}: {}", bad.join(", "));
                    margin = margin.min(m);
                }
            }
            println!("{rule:?}: least margin over the gaps {margin:.2}");
        }
        for (label, fam) in [("3-S-7", "complete chattering"), ("1-12-3", "chattering"), ("7-5-3", "subharmonic")] {
            assert!(TABLE.binary_search_by(|(t, _)| (*t).cmp(label)).is_err());
            assert_eq!(family(label), fam);
            let c = colour(label);
            assert_eq!(c, colour(label), "the same label, the same colour");
            let (bad, _) = broken(c);
            assert!(bad.is_empty(), "{label} {c:?}: {}", bad.join(", "));
        }
    }

    /// The referee's report on docs/img/map.png and the M2 down map: 3-1-3,
    /// 2-6-4 and 4-6-4 were near-black beside C (ΔE 11.8 and up), 1-0-5 /
    /// 1-1-S and 1-1-1 / 1-0-2 under 12 apart.
    #[test]
    fn dark_labels_are_told_apart_from_chaos() {
        for label in ["3-1-3", "2-6-4", "4-6-4"] {
            let d = delta_e(colour(label), colour("C"));
            assert!(d >= 20.0 && lab(colour(label))[0] >= L_MIN, "{label} {:?}: ΔE {d:.2} from C", colour(label));
        }
        for (a, b) in [("1-0-5", "1-1-S"), ("1-1-1", "1-0-2")] {
            let d = delta_e(colour(a), colour(b));
            assert!(d >= TABLE_MIN_DE, "{a} and {b}: ΔE {d:.2}");
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
        assert_eq!(family("Q"), "quasi-periodic");
        assert_eq!(family("U"), "unresolved");
        // Each family's legend colour is a member's, and they differ.
        let fams = [
            Family::CompleteChattering,
            Family::Chattering,
            Family::Fundamental,
            Family::Subharmonic,
            Family::NoImpact,
            Family::Chaotic,
            Family::Quasiperiodic,
            Family::Unresolved,
        ];
        for (i, a) in fams.iter().enumerate() {
            assert_ne!(a.colour(), WHITE, "{a:?}");
            for b in &fams[..i] {
                assert_ne!(a.colour(), b.colour(), "{a:?} and {b:?}");
            }
        }
        assert_eq!(Family::Fundamental.colour(), colour("1-1-1"));
        assert_eq!(Family::CompleteChattering.colour(), colour("1-S-S"));
        assert_eq!(Family::Chattering.colour(), colour("1-6-6"));
    }

    /// The text a colour is looked up by is the label's as it prints, up to
    /// the longest one.
    #[test]
    fn label_texts_fit() {
        let max = Count::Impacts(u32::MAX);
        for l in [Label::Periodic { n: u32::MAX, p: max, q: max }, label("1-S-3"), label("12-28-12")] {
            let mut buf = [0u8; LONGEST_LABEL];
            assert_eq!(text_of(l, &mut buf), l.to_string());
        }
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

    /// Faded three fifths toward white, rounded: white stays white, black
    /// becomes 153, and each channel is (2 c + 765) / 5 to the nearest.
    #[test]
    fn faded_goes_three_fifths_toward_white() {
        assert_eq!(faded([255, 255, 255]), [255, 255, 255]);
        assert_eq!(faded([0, 0, 0]), [153, 153, 153]);
        for c in 0..=255u8 {
            let exact = (2.0 * f64::from(c) + 765.0) / 5.0;
            assert!((f64::from(faded([c, 0, 0])[0]) - exact).abs() <= 0.5, "{c}");
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
