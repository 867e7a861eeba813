//! A report's JSON (the structures of `linkage-report`, serialised) rendered as HTML tables.
//!
//! Nothing is recomputed: the scalars of an object make a two-column table, each list of
//! objects a table with one column per key, nested objects a section of their own. A column
//! whose key names a quantity (`position`, `force`, `torque`, `frequency`, …) gets the unit of
//! the report's `units` object in its header; a `residual` column the unit its row states
//! (`residual_unit`). Long lists are cut at [`MAX_ROWS`] rows, saying how many are shown.

use crate::text::{escape, number};
use serde_json::{Map, Value};
use std::fmt::Write;

/// Most rows of one table.
pub const MAX_ROWS: usize = 200;

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

/// A cell: numbers formatted, lists of scalars joined, nested structures summarised.
fn cell(v: &Value) -> String {
    match v {
        Value::Null => "—".into(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => n.as_f64().map_or_else(|| n.to_string(), number),
        Value::String(s) => escape(s),
        Value::Array(a) if a.iter().all(|x| !x.is_array() && !x.is_object()) => {
            a.iter().map(cell).collect::<Vec<_>>().join(", ")
        }
        Value::Array(a) => format!("{} items", a.len()),
        Value::Object(o) => o
            .iter()
            .filter(|(_, x)| !x.is_array() && !x.is_object())
            .map(|(k, x)| format!("{}: {}", escape(k), cell(x)))
            .collect::<Vec<_>>()
            .join("; "),
    }
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
        .collect();
    let level = level.min(4);
    let _ = write!(s, "<h{level}>{}</h{level}>", escape(title));
    for key in ["errors", "warnings"] {
        if let Some(Value::Array(list)) = o.get(key) {
            if !list.is_empty() {
                let one = if key == "errors" { "error" } else { "warning" };
                let _ = write!(s, "<ul class=\"{key}\">");
                for item in list {
                    let _ = write!(s, "<li>{one}: {}</li>", cell(item));
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
                cell(v)
            );
        }
        s.push_str("</table>");
    }
    for (k, v) in o {
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
    let mut columns: Vec<&String> = Vec::new();
    for r in rows {
        if let Value::Object(o) = r {
            for k in o.keys() {
                if !columns.contains(&k) && k != "residual_unit" {
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
    let level = level.min(4);
    let shown = rows.len().min(MAX_ROWS);
    let _ = write!(s, "<h{level}>{} ({} rows", escape(title), rows.len());
    if shown < rows.len() {
        let _ = write!(s, ", the first {shown} shown");
    }
    s.push_str(")</h");
    let _ = write!(s, "{level}><table><tr>");
    for c in &columns {
        let _ = write!(s, "<th>{}</th>", header(c, units));
    }
    s.push_str("</tr>");
    for r in &rows[..shown] {
        s.push_str("<tr>");
        for c in &columns {
            let v = r.get(c.as_str()).unwrap_or(&Value::Null);
            let mut text = cell(v);
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
        assert!(html.contains("<li>error: it failed</li>"), "{html}");
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
            html.contains("steps (250 rows, the first 200 shown)"),
            "{html}"
        );
        assert_eq!(html.matches("<tr>").count(), 201);
    }
}
