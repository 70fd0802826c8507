//! Numbers in messages: as written (`40`, `2.5`) in the usual range, in exponent form beyond
//! it, so that `--t-end 1e300` reads `1e300` and not as a 301-digit number.
//! (A shared helper is being added in `crates/cli/src/number.rs`; this one is private to `run`
//! until the two are merged.)

/// `x` for a message: `{}` for magnitudes in `[10⁻⁴, 10⁶)` (and 0), `{:e}` beyond.
pub fn num(x: f64) -> String {
    let a = x.abs();
    if x.is_finite() && a != 0.0 && !(1e-4..1e6).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

#[cfg(test)]
mod tests {
    use super::num;

    #[test]
    fn large_and_small_numbers_are_in_exponent_form() {
        assert_eq!(num(1e300), "1e300");
        assert_eq!(num(-2.5e6), "-2.5e6");
        assert_eq!(num(1e-300), "1e-300");
        assert_eq!(num(40.0), "40");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(999_999.0), "999999");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(f64::NAN), "NaN");
        assert_eq!(num(f64::INFINITY), "inf");
    }
}
