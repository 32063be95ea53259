//! Axis ticks and ranges, as every figure writes and frames them.

/// An axis tick: up to four decimals, never `-0`, negative numbers with a
/// minus sign (U+2212), not a hyphen.
pub(crate) fn tick(v: f64) -> String {
    if v.abs() < 1e-12 {
        return "0".into();
    }
    let text = format!("{:.4}", v);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    let text = if v.abs() >= 1e4 || v.abs() < 1e-3 { format!("{v:.2e}") } else { text.to_string() };
    text.replace('-', "\u{2212}")
}

/// The range of `values` with a margin: 5 % of their span, and at least 5 %
/// of their magnitude (or 1e-3), so that a few points that agree to round-off
/// (a period-n orbit) sit in the middle of readable ticks; `-1..1` when there
/// are none.
pub(crate) fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    let half = (1.1 * half).max(0.05 * mid.abs()).max(1e-3);
    (mid - half, mid + half)
}
