//! Numbers for people: shares of the weight ("0 W", "1.2e-3 W"), forces with units, durations,
//! counts with their noun in the right number. The viewer's panel and the PNG exports use them.

/// A share of the free weight W: "0 W", "0.034 W", "1.2e-3 W".
pub fn share_of_weight(x: f64) -> String {
    // Below what the LPs resolve, and NaN: nothing.
    if x.is_nan() || x.abs() < 5e-13 {
        "0 W".into()
    } else if x.abs() >= 0.01 {
        format!("{} W", trim(&format!("{x:.3}")))
    } else {
        let e = x.log10().floor() as i32;
        format!("{:.1}e{e} W", x / 10f64.powi(e))
    }
}

/// A force in N, kN or MN with three significant digits.
pub fn force(n: f64) -> String {
    let (v, unit) = match n.abs() {
        a if a >= 1e6 => (n / 1e6, "MN"),
        a if a >= 1e3 => (n / 1e3, "kN"),
        _ => (n, "N"),
    };
    let digits = if v.abs() >= 100.0 {
        0
    } else if v.abs() >= 10.0 {
        1
    } else {
        2
    };
    format!("{v:.digits$} {unit}")
}

/// A length in mm below a metre, else in m, with three significant digits: "54.1 mm", "1.25 m".
pub fn length(m: f64) -> String {
    if m.abs() >= 1.0 {
        format!("{m:.3} m")
    } else {
        let mm = 1e3 * m;
        let digits = if mm.abs() >= 100.0 {
            0
        } else if mm.abs() >= 10.0 {
            1
        } else {
            2
        };
        format!("{mm:.digits$} mm")
    }
}

/// A duration: "3.1 ms", "1.25 s".
pub fn duration(seconds: f64) -> String {
    if seconds < 1.0 { format!("{:.1} ms", 1e3 * seconds) } else { format!("{seconds:.2} s") }
}

/// `n` and the noun, plural when n ≠ 1.
pub fn count(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

fn trim(s: &str) -> String {
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_for_people() {
        assert_eq!(share_of_weight(0.0), "0 W");
        assert_eq!(share_of_weight(1e-14), "0 W");
        assert_eq!(share_of_weight(0.0012), "1.2e-3 W");
        assert_eq!(share_of_weight(0.034), "0.034 W");
        assert_eq!(share_of_weight(0.25), "0.25 W");
        assert_eq!(force(1234.0), "1.23 kN");
        assert_eq!(force(56.78), "56.8 N");
        assert_eq!(force(2.5e6), "2.50 MN");
        assert_eq!(length(0.0541), "54.1 mm");
        assert_eq!(length(0.004), "4.00 mm");
        assert_eq!(length(1.25), "1.250 m");
        assert_eq!(duration(0.0031), "3.1 ms");
        assert_eq!(duration(1.25), "1.25 s");
        assert_eq!(count(1, "round"), "1 round");
        assert_eq!(count(3, "round"), "3 rounds");
    }
}
