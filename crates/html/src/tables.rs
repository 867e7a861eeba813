//! A report's JSON (the structures of `linkage-report`, serialised) rendered as HTML tables.
//!
//! Nothing is recomputed: the scalars of an object make a two-column table, each list of
//! objects a table with one column per key, nested objects a section of their own, titled in
//! words (`final_state` → "Final state"). A column whose key names a quantity (`position`,
//! `force`, `torque`, `frequency`, …) gets the unit of the report's `units` object in its
//! header; a `residual` column the unit its row states (`residual_unit`). Numbers are shown
//! with [`crate::text::number`]; a number at the rounding noise of the values it is shown
//! with (its column, or its own list) is 0, and a residual or error below
//! [`ROUNDING_RESIDUAL`] is "0 (rounding)". The top level's errors and warnings are the
//! page's verdict ([`crate::verdict`]), not repeated here; linear's zero-frequency modes
//! (`zero`) are counted, not listed. Long lists are cut at [`MAX_ROWS`] rows, saying how many
//! are shown.

use crate::text::{escape, number_in};
use serde_json::{Map, Value};
use std::fmt::Write;

/// Most rows of one table.
pub const MAX_ROWS: usize = 200;

/// A residual or error (a key naming one: `max_residual`, `velocity_error`, `imbalance`) below
/// this is rounding (f64 sums of model-size terms lose about 1e-15 of them; the solvers stop
/// near 1e-10), shown as "0 (rounding)".
pub const ROUNDING_RESIDUAL: f64 = 1e-12;

/// Keys the tables leave out: bookkeeping of the JSON layout.
const HIDDEN_KEYS: [&str; 2] = ["schema_version", "zero"];

/// A title in words: `final_state` → `Final state`.
fn title_words(key: &str) -> String {
    let words = key.replace('_', " ");
    let mut c = words.chars();
    match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect(),
        None => words,
    }
}

/// The largest finite magnitude among the numbers of `v` (lists of numbers included).
fn magnitude(v: &Value) -> f64 {
    match v {
        Value::Number(n) => n.as_f64().filter(|x| x.is_finite()).map_or(0.0, f64::abs),
        Value::Array(a) if a.iter().all(|x| !x.is_array() && !x.is_object()) => {
            a.iter().map(magnitude).fold(0.0, f64::max)
        }
        _ => 0.0,
    }
}

fn residual_like(key: &str) -> bool {
    ["residual", "error", "imbalance"]
        .iter()
        .any(|w| key.contains(w))
}

/// The unit of a key, from the report's `units` object (`None`: no unit or unknown).
fn unit_of(key: &str, units: Option<&Map<String, Value>>) -> Option<String> {
    let units = units?;
    let quantity = match key {
        "position" | "length" | "characteristic_length" => "length",
        "reuler" | "angle" => "angle",
        "velocity" => "velocity",
        "angular_velocity" => "angular_velocity",
        "acceleration" => "acceleration",
        "angular_acceleration" => "angular_acceleration",
        "force" | "imbalance" => "force",
        "torque" => "torque",
        "frequency" | "undamped_frequency" | "real" | "imag" => "frequency",
        "time" | "end_time" | "settling_time_used" | "settling_time_limit" => "time",
        "mass" => "mass",
        _ => return None,
    };
    units.get(quantity)?.as_str().map(str::to_string)
}

fn header(key: &str, units: Option<&Map<String, Value>>) -> String {
    let name = key.replace('_', " ");
    match unit_of(key, units) {
        Some(u) => format!("{} [{}]", escape(&name), escape(&u)),
        None => escape(&name),
    }
}

/// A cell: numbers formatted (noise next to `scale` as 0), lists of scalars joined, nested
/// structures summarised.
fn cell(v: &Value, scale: f64) -> String {
    match v {
        Value::Null => "—".into(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => n
            .as_f64()
            .map_or_else(|| n.to_string(), |x| number_in(x, scale)),
        Value::String(s) => escape(s),
        Value::Array(a) if a.iter().all(|x| !x.is_array() && !x.is_object()) => a
            .iter()
            .map(|x| cell(x, scale))
            .collect::<Vec<_>>()
            .join(", "),
        Value::Array(a) => format!("{} items", a.len()),
        Value::Object(o) => o
            .iter()
            .filter(|(_, x)| !x.is_array() && !x.is_object())
            .map(|(k, x)| format!("{}: {}", escape(k), cell(x, magnitude(x))))
            .collect::<Vec<_>>()
            .join("; "),
    }
}

/// A value of a two-column table: a residual or error below [`ROUNDING_RESIDUAL`] is
/// "0 (rounding)"; a list's noise is judged against its largest member.
fn scalar_cell(key: &str, v: &Value) -> String {
    if let Some(x) = v.as_f64() {
        if residual_like(key) && x.abs() < ROUNDING_RESIDUAL {
            return "0 (rounding)".into();
        }
    }
    cell(v, magnitude(v))
}

/// The tables of a report object `report`, sections titled from its keys.
pub fn report_tables(report: &Value) -> String {
    let mut s = String::new();
    if let Value::Object(o) = report {
        let units = o.get("units").and_then(Value::as_object);
        object_tables(&mut s, "Summary", o, units, 2);
    }
    s
}

/// Whether a key of the top-level object is shown by the page elsewhere (its verdict).
fn shown_elsewhere(level: usize, key: &str) -> bool {
    level == 2 && (key == "errors" || key == "warnings")
}

fn object_tables(
    s: &mut String,
    title: &str,
    o: &Map<String, Value>,
    units: Option<&Map<String, Value>>,
    level: usize,
) {
    let scalars: Vec<(&String, &Value)> = o
        .iter()
        .filter(|(_, v)| match v {
            Value::Array(a) => a.iter().all(|x| !x.is_array() && !x.is_object()) && !a.is_empty(),
            Value::Object(_) => false,
            _ => true,
        })
        .filter(|(k, _)| k.as_str() != "errors" && k.as_str() != "warnings")
        .filter(|(k, _)| !HIDDEN_KEYS.contains(&k.as_str()))
        .collect();
    let level = level.min(4);
    let _ = write!(s, "<h{level}>{}</h{level}>", escape(&title_words(title)));
    for key in ["errors", "warnings"] {
        if shown_elsewhere(level, key) {
            continue;
        }
        if let Some(Value::Array(list)) = o.get(key) {
            if !list.is_empty() {
                let one = if key == "errors" { "error" } else { "warning" };
                let _ = write!(s, "<ul class=\"{key}\">");
                for item in list {
                    let _ = write!(s, "<li>{one}: {}</li>", cell(item, magnitude(item)));
                }
                s.push_str("</ul>");
            }
        }
    }
    if !scalars.is_empty() {
        s.push_str("<table class=\"kv\">");
        for (k, v) in scalars {
            let _ = write!(
                s,
                "<tr><th>{}</th><td>{}</td></tr>",
                header(k, units),
                scalar_cell(k, v)
            );
        }
        s.push_str("</table>");
    }
    for (k, v) in o {
        // Linear's eigenvalues repeat the modes' real and imaginary parts.
        if k == "eigenvalues" && o.contains_key("modes") {
            continue;
        }
        match v {
            Value::Object(inner) => object_tables(s, k, inner, units, level + 1),
            Value::Array(a) if a.iter().any(Value::is_object) => {
                list_table(s, k, a, units, level + 1)
            }
            _ => {}
        }
    }
}

fn list_table(
    s: &mut String,
    title: &str,
    rows: &[Value],
    units: Option<&Map<String, Value>>,
    level: usize,
) {
    // Zero-frequency modes are counted, not listed.
    let is_zero = |r: &Value| r.get("zero").and_then(Value::as_bool) == Some(true);
    let zeros = rows.iter().filter(|r| is_zero(r)).count();
    let rows: Vec<&Value> = rows.iter().filter(|r| !is_zero(r)).collect();
    let mut columns: Vec<&String> = Vec::new();
    for r in &rows {
        if let Value::Object(o) = r {
            for k in o.keys() {
                if !columns.contains(&k)
                    && k != "residual_unit"
                    && !HIDDEN_KEYS.contains(&k.as_str())
                {
                    columns.push(k);
                }
            }
        }
    }
    // The name first (JSON objects come with their keys sorted).
    if let Some(k) = columns.iter().position(|c| c.as_str() == "name") {
        let name = columns.remove(k);
        columns.insert(0, name);
    }
    // Each column's noise is judged against its largest magnitude.
    let scales: Vec<f64> = columns
        .iter()
        .map(|c| {
            rows.iter()
                .filter_map(|r| r.get(c.as_str()))
                .map(magnitude)
                .fold(0.0, f64::max)
        })
        .collect();
    let level = level.min(4);
    let shown = rows.len().min(MAX_ROWS);
    let _ = write!(
        s,
        "<h{level}>{} ({} row{}",
        escape(&title_words(title)),
        rows.len(),
        if rows.len() == 1 { "" } else { "s" }
    );
    if shown < rows.len() {
        let _ = write!(s, ", the first {shown} shown");
    }
    if zeros > 0 {
        let _ = write!(
            s,
            "; {zeros} at zero frequency (rigid-body motions) not listed"
        );
    }
    s.push_str(")</h");
    let _ = write!(s, "{level}><table><tr>");
    for c in &columns {
        let _ = write!(s, "<th>{}</th>", header(c, units));
    }
    s.push_str("</tr>");
    for r in &rows[..shown] {
        s.push_str("<tr>");
        for (c, scale) in columns.iter().zip(&scales) {
            let v = r.get(c.as_str()).unwrap_or(&Value::Null);
            let mut text = cell(v, *scale);
            if c.as_str() == "residual" {
                if let Some(u) = r.get("residual_unit").and_then(Value::as_str) {
                    text = format!("{text} {}", escape(u));
                }
            }
            let _ = write!(s, "<td>{text}</td>");
        }
        s.push_str("</tr>");
    }
    s.push_str("</table>");
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn rounding_noise_is_zero_and_keys_are_words() {
        let report = json!({
            "units": {"length": "meter", "force": "newton"},
            "max_residual": 1.94e-16,
            "schema_version": 1,
            "final_state": [
                {"name": "crank", "position": [0.5, -1.2e-17, 0.0]},
                {"name": "rocker", "position": [2.0, 1.0, 3e-18]}
            ],
            "modes": [
                {"number": 1, "frequency": 2.3e-12, "zero": true},
                {"number": 2, "frequency": 6.366, "zero": false}
            ],
            "eigenvalues": [{"real": 0.0, "imag": 6.366}]
        });
        let html = report_tables(&report);
        assert!(html.contains("<h3>Final state (2 rows)</h3>"), "{html}");
        // -1.2e-17 m and 3e-18 m next to 2 m are rounding noise.
        assert!(html.contains("<td>crank</td><td>0.5, 0, 0</td>"), "{html}");
        assert!(html.contains("<td>rocker</td><td>2, 1, 0</td>"), "{html}");
        assert!(
            html.contains("<th>max residual</th><td>0 (rounding)</td>"),
            "{html}"
        );
        assert!(!html.contains("schema"), "{html}");
        // The zero-frequency mode is counted, not listed; eigenvalues are not repeated.
        assert!(
            html.contains(
                "<h3>Modes (1 row; 1 at zero frequency (rigid-body motions) not listed)</h3>"
            ),
            "{html}"
        );
        assert!(
            !html.contains("2.3e-12") && !html.contains("Eigenvalues"),
            "{html}"
        );
    }

    #[test]
    fn a_list_of_parts_becomes_a_table_with_units_in_its_headers() {
        let report = json!({
            "title": "pendulum",
            "units": {"length": "meter", "angle": "degree", "force": "newton"},
            "converged": true,
            "parts": [{"name": "arm", "position": [0.0, -0.7, 0.0], "reuler": [90.0, 0.0, 0.0]}],
            "redundant": [{"residual": 0.25, "residual_unit": "mm"}],
            "errors": ["it failed"]
        });
        let html = report_tables(&report);
        assert!(html.contains("<th>position [meter]</th>"), "{html}");
        assert!(html.contains("<th>reuler [degree]</th>"), "{html}");
        assert!(
            html.contains("<td>arm</td><td>0, -0.7, 0</td><td>90, 0, 0</td>"),
            "{html}"
        );
        assert!(html.contains("<td>0.25 mm</td>"), "{html}");
        // The top level's errors are the page's verdict, not repeated here.
        assert!(!html.contains("it failed"), "{html}");
        assert!(
            html.contains("<tr><th>converged</th><td>true</td></tr>"),
            "{html}"
        );
    }

    #[test]
    fn long_lists_say_how_many_rows_are_shown() {
        let rows: Vec<Value> = (0..250).map(|k| json!({"n": k})).collect();
        let html = report_tables(&json!({ "steps": rows }));
        assert!(
            html.contains("Steps (250 rows, the first 200 shown)"),
            "{html}"
        );
        assert_eq!(html.matches("<tr>").count(), 201);
    }
}
