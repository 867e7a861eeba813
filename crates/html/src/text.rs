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

/// A number as the tables show it: 7 significant digits (exponent form outside 1e-4…1e7),
/// integers as integers.
pub fn number(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == v.trunc() && v.abs() < 1e15 {
        return format!("{}", v as i64);
    }
    let a = v.abs();
    if !(1e-4..1e7).contains(&a) {
        return format!("{v:.6e}");
    }
    let digits = (6 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
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
        assert_eq!(number(1.5e-7), "1.500000e-7");
    }

    #[test]
    fn markup_is_escaped() {
        assert_eq!(escape("<a href='x'>&"), "&lt;a href=&#39;x&#39;&gt;&amp;");
        assert_eq!(script_json("\"</script>\""), "\"\\u003c/script>\"");
    }
}
