//! The colour of a label: one fixed colour per label text, the same in every
//! map, sweep, study sheet and file (the atlas files store it beside their
//! label tables, so that scripts draw with the same colours).
//!
//! Families, each with its own hues (colour-blind-safe base colours from the
//! Okabe–Ito set where a family has few members):
//!
//! | family | labels | colours |
//! |---|---|---|
//! | no impact | `1-0-0` | light grey |
//! | fundamental | `1-p-q` with `p, q < 6` | hue by `m = max(p, q)`: 1 blue, 2 sky blue, 3 bluish green, 4 yellow, 5 reddish purple; lighter by `0.7 (p - q)/m` towards white when `p > q`, darker by `0.4 (q - p)/m` towards black (never near it) when `p < q`: every fundamental label its own colour |
//! | subharmonic | `n-p-q`, `n > 1`, fewer than 6 impacts per period at each stop | greens to teals, muted, hue and lightness from the label text |
//! | chattering | 6 or more impacts per forcing period on average at a stop (`p/n` or `q/n >= 6`) | oranges to browns, from the label text |
//! | complete chattering | an `S` (the mass sticks) | purples, from the label text |
//! | not periodic | `C` chaotic, `Q` quasi-periodic, `U` unresolved | black, dark grey, red |
//!
//! Colours within the hashed families are a deterministic function of the
//! label text (FNV-1a, mixed), so no table is needed and a label never changes colour
//! between figures.

/// RGB colour of a label text (`1-4-4`, `2-S-3`, `C`, `Q`, `U`). Anything
/// else (for instance `not-computed`) is white.
pub fn colour(label: &str) -> [u8; 3] {
    match label {
        "1-0-0" => [221, 221, 221],
        "C" => [0, 0, 0],
        "Q" => [102, 102, 102],
        "U" => [213, 40, 40],
        _ => match parse(label) {
            Some((n, p, q)) => periodic(label, n, p, q),
            None => [255, 255, 255],
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

fn periodic(label: &str, n: u32, p: Option<u32>, q: Option<u32>) -> [u8; 3] {
    let h = fnv(label);
    let unit = |bits: u64| (bits & 0xffff) as f64 / 65535.0;
    let (a, b) = (unit(h), unit(h >> 16));
    match (p, q) {
        (None, _) | (_, None) => hsl(265.0 + 40.0 * a, 0.45, 0.35 + 0.35 * b),
        (Some(p), Some(q)) if chattering(n, Some(p), Some(q)) => hsl(18.0 + 22.0 * a, 0.85, 0.40 + 0.25 * b),
        (Some(p), Some(q)) if n == 1 => {
            const BASE: [[u8; 3]; 5] = [[0, 114, 178], [86, 180, 233], [0, 158, 115], [240, 228, 66], [204, 121, 167]];
            let base = BASE[(p.max(q).max(1) - 1) as usize % BASE.len()];
            // Lighter the more p exceeds q, darker the more q exceeds p, in
            // steps of the hue's largest count m = max(p, q), so that the
            // 2m + 1 labels of a hue all differ; never near black (C).
            let (d, m) = (p as f64 - q as f64, p.max(q).max(1) as f64);
            let mix = if d > 0.0 { 0.7 * d / m } else { 0.4 * -d / m };
            let towards = if d > 0.0 { 255.0 } else { 0.0 };
            base.map(|c| (c as f64 + mix * (towards - c as f64)).round() as u8)
        }
        _ => hsl(85.0 + 95.0 * a, 0.40, 0.30 + 0.40 * b),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn families_and_fixed_colours() {
        assert_eq!(colour("C"), [0, 0, 0]);
        assert_eq!(colour("1-1-1"), [0, 114, 178]);
        assert_eq!(family("1-4-4"), "fundamental");
        assert_eq!(family("1-7-6"), "chattering");
        assert_eq!(family("19-19-19"), "subharmonic");
        assert_eq!(family("2-12-12"), "chattering");
        assert_eq!(family("1-S-S"), "complete chattering");
        assert_eq!(family("1-S-3"), "complete chattering");
        // The same label, the same colour; neighbours of a family differ.
        assert_eq!(colour("2-4-2"), colour("2-4-2"));
        let labels =
            ["1-1-1", "1-2-2", "1-2-1", "1-1-2", "1-3-3", "1-3-2", "1-4-4", "1-0-1", "2-2-2", "2-4-2", "3-3-6"];
        for (i, a) in labels.iter().enumerate() {
            for b in &labels[..i] {
                assert_ne!(colour(a), colour(b), "{a} and {b}");
            }
        }
    }

    /// Every fundamental label (`1-p-q`, p and q below 6) has a colour of its
    /// own, apart from the fixed ones, and none is near black (chaotic):
    /// 1-0-4 and 1-1-4 shared one when the darkening saturated.
    #[test]
    fn fundamental_labels_never_share_a_colour() {
        let labels: Vec<String> =
            (0..6).flat_map(|p| (0..6).map(move |q| format!("1-{p}-{q}"))).filter(|l| l != "1-0-0").collect();
        let fixed = ["1-0-0", "C", "Q", "U"].map(colour);
        for (i, a) in labels.iter().enumerate() {
            let ca = colour(a);
            assert!(!fixed.contains(&ca), "{a} takes a fixed colour");
            assert!(ca.iter().map(|&c| c as u32).sum::<u32>() > 120, "{a} is near black: {ca:?}");
            for b in &labels[..i] {
                let cb = colour(b);
                let far = ca.iter().zip(&cb).map(|(&x, &y)| (x as i32 - y as i32).abs()).max().unwrap();
                assert!(far >= 8, "{a} {ca:?} and {b} {cb:?} are not told apart");
            }
        }
    }
}
