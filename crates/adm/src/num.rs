//! Numbers as Adams users read them.
//!
//! Every number a report prints goes through this module, so that all reports agree:
//! - **text tables** use scientific notation with a fixed number of significant digits and a
//!   two-digit exponent, `-5.160884E+00` ([`sci`]); a value at the rounding noise of the
//!   table it sits in (below [`NOISE_RELATIVE`] of the table's largest magnitude) prints as
//!   zero ([`sci_in`]), and `-0` never appears;
//! - **CSV** fields use at most [`CSV_DIGITS`] significant digits, plain for ordinary
//!   magnitudes and with an exponent otherwise, `60`, `0.05`, `2.148E-31` ([`general`]): short
//!   fields that every CSV reader parses back to within the digits kept.
//!
//! Non-finite values print as `NaN`, `Inf`, `-Inf` (reports refuse them before printing; a
//! printer never panics on them).

/// A value smaller than this fraction of the largest magnitude among the values it is printed
/// with is rounding noise: the solver's residuals are held near 1e-10 of the model's size, and
/// sums of f64 products lose about 1e-15 of their terms. 1e-11 sits between the two.
pub const NOISE_RELATIVE: f64 = 1e-11;

/// Significant digits of the numbers in text tables (`-5.160884E+00`: 13 characters).
pub const TEXT_DIGITS: usize = 7;

/// Significant digits of CSV fields: more than the solver resolves (about 1e-10 of the model's
/// size), fewer than the round-trip noise of f64.
pub const CSV_DIGITS: usize = 12;
/// Significant digits of a time in a message (`simulation stopped at time 0.707445495894`).
pub const TIME_DIGITS: usize = 12;

/// `x` in scientific notation with `digits` significant digits and an exponent of at least
/// two digits: `sci(-5.1608838, 7) == "-5.160884E+00"`, `sci(0.0, 3) == "0.00E+00"`.
pub fn sci(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return non_finite(x);
    }
    let digits = digits.max(1);
    // `-0` and the zero a negative value rounds to would both print a minus sign.
    let x = if x == 0.0 { 0.0 } else { x };
    let s = format!("{:.*e}", digits - 1, x);
    let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
    let e: i32 = exponent.parse().unwrap_or(0);
    let sign = if e < 0 { '-' } else { '+' };
    format!("{mantissa}E{sign}{:02}", e.unsigned_abs())
}

/// [`sci`] of `x` printed among values whose largest magnitude is `scale`: zero when `x` is
/// at the rounding noise of that scale (`|x| ≤ NOISE_RELATIVE · scale`).
pub fn sci_in(x: f64, digits: usize, scale: f64) -> String {
    sci(denoise(x, scale), digits)
}

/// `x`, or zero when it is rounding noise next to `scale`.
pub fn denoise(x: f64, scale: f64) -> f64 {
    if x.is_finite() && x.abs() <= NOISE_RELATIVE * scale {
        0.0
    } else {
        x
    }
}

/// The largest finite magnitude among `values` (0 when there is none): the scale that
/// [`sci_in`] judges noise against.
pub fn scale_of(values: impl IntoIterator<Item = f64>) -> f64 {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(0.0, |m, v| m.max(v.abs()))
}

/// A time in a message: [`general`] with [`TIME_DIGITS`] digits, so that `1e200` prints as
/// `1E+200`, not as 201 digits.
pub fn time_text(t: f64) -> String {
    general(t, TIME_DIGITS)
}

/// `x` with at most `digits` significant digits, in the shortest form that keeps them: plain
/// for magnitudes in [1e-4, 1e`digits`), `mantissaE±XX` otherwise; trailing zeros dropped,
/// `-0` printed as `0`. `general(59.99999999999999, 12) == "60"`.
pub fn general(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return non_finite(x);
    }
    if x == 0.0 {
        return "0".to_string();
    }
    let digits = digits.clamp(1, 17);
    // Round to `digits` significant digits first: the exponent may change (9.9999… → 1E+01).
    let rounded: f64 = format!("{:.*e}", digits - 1, x).parse().unwrap_or(x);
    let a = rounded.abs();
    if (1e-4..10f64.powi(digits as i32)).contains(&a) {
        // Shortest round-trip digits of the rounded value: at most `digits` significant ones.
        let s = format!("{rounded}");
        if s == "-0" {
            "0".to_string()
        } else {
            s
        }
    } else {
        let s = format!("{rounded:e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let e: i32 = exponent.parse().unwrap_or(0);
        let sign = if e < 0 { '-' } else { '+' };
        format!("{mantissa}E{sign}{:02}", e.unsigned_abs())
    }
}

fn non_finite(x: f64) -> String {
    if x.is_nan() {
        "NaN".to_string()
    } else if x > 0.0 {
        "Inf".to_string()
    } else {
        "-Inf".to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scientific_has_two_digit_exponents_and_fixed_digits() {
        assert_eq!(sci(-5.1608838, 7), "-5.160884E+00");
        assert_eq!(sci(30.567841, 7), "3.056784E+01");
        assert_eq!(sci(-5.329071e-15, 4), "-5.329E-15");
        assert_eq!(sci(1.5e200, 3), "1.50E+200");
        assert_eq!(sci(0.0, 3), "0.00E+00");
        assert_eq!(sci(-0.0, 3), "0.00E+00");
        assert_eq!(sci(9.99999999, 3), "1.00E+01");
        assert_eq!(sci(f64::NAN, 3), "NaN");
        assert_eq!(sci(f64::NEG_INFINITY, 3), "-Inf");
    }

    #[test]
    fn times_in_messages_are_short_at_any_magnitude() {
        assert_eq!(time_text(1e200), "1E+200");
        assert_eq!(time_text(5e199), "5E+199");
        assert_eq!(time_text(0.707445495894123), "0.707445495894");
        assert_eq!(time_text(-0.0), "0");
    }

    #[test]
    fn noise_is_judged_against_the_table_scale() {
        let table = [5.160884, 30.56784, -5.329071e-15, 8.362802];
        let scale = scale_of(table);
        assert_eq!(scale, 30.56784);
        assert_eq!(sci_in(table[2], 7, scale), "0.000000E+00");
        assert_eq!(sci_in(table[0], 7, scale), "5.160884E+00");
        // A small value that is not noise next to its table stays.
        assert_eq!(sci_in(1e-9, 3, scale), "1.00E-09");
        assert_eq!(scale_of([f64::NAN, -2.0]), 2.0);
    }

    #[test]
    fn general_form_is_short_and_reads_back() {
        assert_eq!(general(59.99999999999999, 12), "60");
        assert_eq!(general(0.05, 12), "0.05");
        assert_eq!(general(-0.22672492052927715, 12), "-0.226724920529");
        assert_eq!(general(2.1480000000001e-31, 12), "2.148E-31");
        assert_eq!(general(-0.0, 12), "0");
        assert_eq!(general(1e15, 12), "1E+15");
        assert_eq!(general(123456.0, 12), "123456");
        for x in [
            1.0 / 3.0,
            -7.3e-19,
            6.02214076e23,
            std::f64::consts::PI * 1e-5,
            -123.456789e7,
        ] {
            let back: f64 = general(x, 12).parse().unwrap();
            assert!(
                ((back - x) / x).abs() < 5e-12,
                "{x} → {} → {back}",
                general(x, 12)
            );
        }
    }
}
