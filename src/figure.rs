//! How the crate writes numbers and counts for a reader: [`format_figure`] for the figures
//! of a run (its summary, the texts of its health notices and warnings), [`fmt_num`] for a
//! value quoted exactly (input errors, `kjoint check`), and [`plural`] for a count.

/// A figure as the crate prints it (the summary, the health warnings): plain notation with 4 significant digits for magnitudes in
/// `[1e-3, 1e6)` (`22.8312` → `22.83`, `0.001234`, `123456`), exponent notation with 3
/// outside (`1.2e-9` → `1.20e-9`, `3.4e7` → `3.40e7`), `0` for zero, and `NaN`, `inf`,
/// `-inf` as such.
pub fn format_figure(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return v.to_string();
    }
    let plain = |v: f64| {
        let digits = v.abs().log10().floor() as i32;
        let decimals = (3 - digits).max(0) as usize;
        format!("{v:.decimals$}")
    };
    let a = v.abs();
    if (1e-3..1e6).contains(&a) {
        let s = plain(v);
        // rounding may carry into the next decade (9.9996 → 10.000): one decimal fewer
        let r: f64 = s.parse().unwrap_or(v);
        if r.abs() >= 1e6 {
            return format!("{v:.2e}");
        }
        if r.abs().log10().floor() > a.log10().floor() {
            return plain(r);
        }
        return s;
    }
    let s = format!("{v:.2e}");
    // 9.996e-4 rounds to 1.00e-3, a plain figure
    match s.parse::<f64>() {
        Ok(r) if (1e-3..1e6).contains(&r.abs()) => plain(r),
        _ => s,
    }
}

/// A number for reports and messages: `Display` for magnitudes in [1e-5, 1e16), exponent
/// form outside (`1e308`, `1.5e-12` instead of 309 or 14 digits). A value that is what a
/// short decimal became through a unit conversion or rapier's f32 is printed as that
/// decimal (`ScF` = 10 mm² in metres, 9.999999999999999e-6, prints `0.00001`; an MJCF
/// damping of 0.1 read through f32, 0.10000000149011612, prints `0.1`): a value whose own
/// shortest decimal takes 16 or 17 digits prints as the shortest decimal of its f32 when it
/// is one exactly, else as its 15 significant digits when they give it back within two
/// units of its last place.
pub fn fmt_num(v: f64) -> String {
    let v = shortest_decimal(v);
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// The value [`fmt_num`] prints for `v`: `v` itself unless its shortest decimal takes 16 or
/// 17 digits (round-off of a shorter one).
fn shortest_decimal(v: f64) -> f64 {
    if !v.is_finite() || v == 0.0 {
        return v;
    }
    // the significant digits of the shortest decimal that reads back as `v`
    let exp = format!("{v:e}");
    let mantissa = exp.split('e').next().unwrap_or("");
    let digits = mantissa.chars().filter(char::is_ascii_digit).count();
    if digits < 16 {
        return v;
    }
    let narrow = v as f32;
    if narrow.is_finite() && f64::from(narrow) == v {
        // (f32's `Display` is its shortest round-trip decimal)
        return narrow.to_string().parse().unwrap_or(v);
    }
    let r: f64 = format!("{v:.14e}").parse().unwrap_or(v);
    if (r - v).abs() <= 2.0 * f64::EPSILON * v.abs() {
        r
    } else {
        v
    }
}

/// `n` and the noun, plural when `n ≠ 1`: `1 joint`, `3 joints`.
pub fn plural(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

#[cfg(test)]
mod tests {
    use super::fmt_num;

    /// What a conversion or f32 made of a short decimal prints as that decimal; any other
    /// value prints whole, so that it reads back to the same bits.
    #[test]
    fn numbers_print_as_the_decimal_they_came_from() {
        assert_eq!(fmt_num(10.0 * 1e-6), "0.00001"); // 9.999999999999999e-6
        assert_eq!(fmt_num(f64::from(0.1f32)), "0.1"); // 0.10000000149011612
        assert_eq!(fmt_num(0.1 + 0.2), "0.3"); // 0.30000000000000004
        assert_eq!(fmt_num(5.72958e8), "572958000");
        assert_eq!(fmt_num(1e308), "1e308");
        // exact values that f32 happens to hold keep every digit (2³⁰ printed 1073741800)
        assert_eq!(fmt_num(1073741824.0), "1073741824");
        assert_eq!(fmt_num(0.75), "0.75");
        assert_eq!(fmt_num(-1.5e-12), "-1.5e-12");
        // not a short decimal: every digit (it reads back to the same value)
        let v = std::f64::consts::PI;
        assert_eq!(fmt_num(v), "3.141592653589793");
        assert_eq!(fmt_num(v).parse::<f64>().unwrap(), v);
        assert_eq!(fmt_num(1.0 + 1e-12), "1.000000000001");
        assert_eq!(fmt_num(0.0), "0");
        assert_eq!(fmt_num(f64::NAN), "NaN");
    }
}
