//! HTML text: escaping and number formatting.

/// `s` with `& < > " '` escaped for HTML text and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// A number as the pages show it: 7 significant digits, trailing zeros dropped, plain for
/// magnitudes in [1e-4, 1e7), otherwise in engineering form (the exponent a multiple of 3:
/// `1.5e-7` → `150e-9`); integers as integers; never `-0`.
pub fn number(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == v.trunc() && v.abs() < 1e15 {
        return format!("{}", v as i64);
    }
    let a = v.abs();
    if !(1e-4..1e7).contains(&a) {
        let e = a.log10().floor() as i32;
        let e3 = e.div_euclid(3) * 3;
        let mantissa = v / 10f64.powi(e3);
        // 7 significant digits of a mantissa in [1, 1000).
        let digits = (6 - (e - e3)).max(0) as usize;
        let m = trimmed(format!("{mantissa:.digits$}"));
        return format!("{m}e{e3}");
    }
    let digits = (6 - a.log10().floor() as i32).max(0) as usize;
    trimmed(format!("{v:.digits$}"))
}

/// `s` without the trailing zeros of its decimals (and `-0` as `0`).
fn trimmed(s: String) -> String {
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// [`number`] of `v` shown among values whose largest magnitude is `scale`: `0` when `v` is
/// rounding noise next to it (below [`linkage_report::num::NOISE_RELATIVE`] of it).
pub fn number_in(v: f64, scale: f64) -> String {
    number(linkage_report::num::denoise(v, scale))
}

/// JSON text safe inside a `<script>` element: every `<` (only ever inside a JSON string) as
/// the escape `\u003c`, so no `</script>` or `<!--` can end or open anything.
pub fn script_json(json: &str) -> String {
    json.replace('<', "\\u003c")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_seven_significant_digits() {
        assert_eq!(number(3.0), "3");
        assert_eq!(number(0.1234567891), "0.1234568");
        assert_eq!(number(-1234.56789), "-1234.568");
        assert_eq!(number(1.5e-7), "150e-9");
        assert_eq!(number(-2.5e-5), "-25e-6");
        assert_eq!(number(12345678.9), "12.34568e6");
        assert_eq!(number(-1e-300), "-1e-300");
        // Noise next to the values it is shown with is 0.
        assert_eq!(number_in(1.94e-16, 0.5), "0");
        assert_eq!(number_in(-3e-3, 0.5), "-0.003");
    }

    #[test]
    fn markup_is_escaped() {
        assert_eq!(escape("<a href='x'>&"), "&lt;a href=&#39;x&#39;&gt;&amp;");
        assert_eq!(script_json("\"</script>\""), "\"\\u003c/script>\"");
    }
}
