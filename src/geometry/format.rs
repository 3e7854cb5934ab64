//! Numbers written for people in messages.

/// `x` with three significant digits, without an exponent for ordinary magnitudes.
pub(crate) fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor();
    if !(-6.0..=9.0).contains(&magnitude) {
        return format!("{x:.2e}");
    }
    format!("{x:.*}", (2.0 - magnitude).max(0.0) as usize)
}
