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
/// form outside (`1e308`, `1.5e-12` instead of 309 or 14 digits).
pub fn fmt_num(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        format!("{v:e}")
    } else {
        v.to_string()
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
