//! Colours of labels. The most frequent labels get distinct colours in legend
//! order; chattering labels (p or q >= 6) share an orange group, complete
//! chattering (an `S`) a purple group, chaotic `C` is black, unresolved `U`
//! red, no impact `1-0-0` light grey, and the rare rest a mid grey "other".

use plotters::style::RGBColor;

/// Distinct colours for the leading labels.
const DISTINCT: [RGBColor; 14] = [
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(23, 190, 207),
    RGBColor(188, 189, 34),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(174, 199, 232),
    RGBColor(152, 223, 138),
    RGBColor(255, 187, 120),
    RGBColor(158, 218, 229),
    RGBColor(219, 219, 141),
    RGBColor(196, 156, 148),
    RGBColor(247, 182, 210),
    RGBColor(57, 59, 121),
];

/// Group of a label in the legend.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Swatch {
    /// A label with its own colour.
    Label(String),
    /// Chattering motions (p or q >= 6).
    Chatter,
    /// Complete chattering (sticking, `S`).
    Sticking,
    /// Rare labels.
    Other,
}

impl Swatch {
    /// Legend text.
    pub fn text(&self) -> String {
        match self {
            Swatch::Label(l) => l.clone(),
            Swatch::Chatter => "chattering (p or q >= 6)".into(),
            Swatch::Sticking => "complete chattering (S)".into(),
            Swatch::Other => "other periodic".into(),
        }
    }
}

fn is_chatter(label: &str) -> bool {
    let parts: Vec<&str> = label.split('-').collect();
    parts.len() == 3 && parts[1..].iter().any(|p| p.parse::<u32>().is_ok_and(|v| v >= 6))
}

/// Assigns swatches and colours to the labels of a legend (most frequent first).
pub fn assign(legend: &[(String, u64)]) -> Vec<(String, Swatch, RGBColor)> {
    let mut next = 0;
    legend
        .iter()
        .map(|(label, _)| {
            let (sw, col) = match label.as_str() {
                "C" => (Swatch::Label("C".into()), RGBColor(0, 0, 0)),
                "U" => (Swatch::Label("U".into()), RGBColor(214, 39, 40)),
                "1-0-0" => (Swatch::Label("1-0-0".into()), RGBColor(225, 225, 225)),
                l if l.contains('S') => (Swatch::Sticking, RGBColor(117, 60, 160)),
                l if is_chatter(l) => (Swatch::Chatter, RGBColor(255, 127, 14)),
                l if next < DISTINCT.len() => {
                    next += 1;
                    (Swatch::Label(l.to_string()), DISTINCT[next - 1])
                }
                _ => (Swatch::Other, RGBColor(150, 150, 150)),
            };
            (label.clone(), sw, col)
        })
        .collect()
}
