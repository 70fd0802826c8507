//! Numbers in messages: as Rust's `{}` prints them for magnitudes from 10⁻⁴ to below 10⁶
//! (`0.5`, `250000`), in exponent form beyond (`1e39`, `1e300`, `2.5e-7`), so that no message
//! carries a number of hundreds of digits. Zero, infinities and NaN print as `{}` does.

/// `x` for a message (the library's rule, `spheresweep::error::Num`, which its own errors use).
pub fn num(x: f64) -> String {
    spheresweep::error::Num(x).to_string()
}

/// `n` and the noun, singular for one: `1 frame`, `3 frames`.
pub fn counted(n: u64, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// A time window's end as the kernels take it: the largest `f32` not above the number given,
/// as `f64` reads it (`3.9999999` is `3.9999998`, not the nearer `4`), so that no contact after
/// the time asked for is reported; `inf` and numbers past `f32::MAX` as written (`f32::MAX` for a finite one).
/// What is refused (below zero, NaN) is the query options' to say.
pub fn window_end(text: &str) -> Result<f32, String> {
    let t: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("{text:?} is not a number"))?;
    let rounded = t as f32;
    let end = if f64::from(rounded) > t {
        rounded.next_down()
    } else {
        rounded
    };
    // `-0` is the window [0, 0], said as `0` (adding +0 turns −0 into +0, nothing else).
    Ok(end + 0.0)
}

#[cfg(test)]
mod tests {
    use super::{counted, num, window_end};

    #[test]
    fn a_window_end_rounds_down_to_f32() {
        assert_eq!(window_end("3.9999999"), Ok(4.0f32.next_down()));
        assert_eq!(window_end("4"), Ok(4.0));
        assert_eq!(window_end("0.1"), Ok(0.1f32.next_down()));
        assert!(f64::from(window_end("0.1").unwrap()) < 0.1);
        assert_eq!(window_end("1e39"), Ok(f32::MAX));
        assert_eq!(window_end("inf"), Ok(f32::INFINITY));
        assert!(window_end("-0").unwrap().is_sign_positive());
        assert!(window_end("-1").unwrap() < 0.0);
        assert!(window_end("nan").unwrap().is_nan());
        assert!(window_end("soon").is_err());
    }

    #[test]
    fn one_is_singular_and_every_other_count_plural() {
        assert_eq!(counted(1, "frame", "frames"), "1 frame");
        assert_eq!(counted(0, "frame", "frames"), "0 frames");
        assert_eq!(
            counted(2, "wall collision", "wall collisions"),
            "2 wall collisions"
        );
    }

    #[test]
    fn plain_inside_the_range_exponent_form_outside() {
        for (x, text) in [
            (0.5, "0.5"),
            (-2.0, "-2"),
            (1e-4, "0.0001"),
            (999_999.0, "999999"),
            (1e6, "1e6"),
            (1e39, "1e39"),
            (-1e300, "-1e300"),
            (2.5e-7, "2.5e-7"),
            (0.0, "0"),
            (f64::INFINITY, "inf"),
            (f64::NAN, "NaN"),
        ] {
            assert_eq!(num(x), text, "{x:?}");
        }
    }
}
