//! JSON reports and CSV time histories as Python values.
//!
//! A JSON array whose items are all numbers becomes a 1-D `float64` numpy array; an array of
//! such arrays, all of one length (at least one row), a 2-D array; other arrays become
//! lists, objects dicts, integers ints, and the rest their Python equivalents. A CSV becomes
//! `{column name: 1-D float64 array}` in column order, the names without the header's unit
//! suffix (`"crank.x"` for `crank.x [m]`), and `{column name: unit}` beside it.

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

/// The numbers of `items` when every one is a number.
fn numbers(items: &[Value]) -> Option<Vec<f64>> {
    items.iter().map(Value::as_f64).collect()
}

/// `value` as a Python object (see the module documentation).
pub fn to_python(py: Python<'_>, value: &Value) -> PyResult<PyObject> {
    Ok(match value {
        Value::Null => py.None(),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any().unbind(),
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i.into_pyobject(py)?.into_any().unbind(),
            (None, Some(u)) => u.into_pyobject(py)?.into_any().unbind(),
            _ => n
                .as_f64()
                .unwrap_or(f64::NAN)
                .into_pyobject(py)?
                .into_any()
                .unbind(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any().unbind(),
        Value::Array(items) => {
            if let (false, Some(xs)) = (items.is_empty(), numbers(items)) {
                return Ok(PyArray1::from_vec(py, xs).into_any().unbind());
            }
            let rows: Option<Vec<Vec<f64>>> = items
                .iter()
                .map(|v| {
                    v.as_array()
                        .filter(|r| !r.is_empty())
                        .and_then(|r| numbers(r))
                })
                .collect();
            if let Some(rows) =
                rows.filter(|r| !r.is_empty() && r.iter().all(|x| x.len() == r[0].len()))
            {
                return Ok(PyArray2::from_vec2(py, &rows)?.into_any().unbind());
            }
            let list = PyList::empty(py);
            for item in items {
                list.append(to_python(py, item)?)?;
            }
            list.into_any().unbind()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, v) in map {
                dict.set_item(k, to_python(py, v)?)?;
            }
            dict.into_any().unbind()
        }
    })
}

/// The fields of one CSV line (RFC 4180 quoting).
fn fields(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut field)),
            (c, _) => field.push(c),
        }
    }
    out.push(field);
    out
}

/// The CSV `text` (a header line, then rows of numbers) as {column: float64 array}, the
/// names plain, and {column: unit} for the columns whose header states one. A field that is
/// not a number (`NaN` included) is NaN.
pub fn csv_columns(py: Python<'_>, text: &str) -> PyResult<(PyObject, PyObject)> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header = lines.next().map(fields).unwrap_or_default();
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); header.len()];
    for line in lines {
        let row = fields(line);
        for (k, column) in columns.iter_mut().enumerate() {
            let x = row
                .get(k)
                .and_then(|f| f.trim().parse::<f64>().ok())
                .unwrap_or(f64::NAN);
            column.push(x);
        }
    }
    let dict = PyDict::new(py);
    let units = PyDict::new(py);
    for (field, column) in header.iter().zip(columns) {
        let (name, unit) = name_and_unit(field);
        dict.set_item(name, PyArray1::from_vec(py, column))?;
        if let Some(unit) = unit {
            units.set_item(name, unit)?;
        }
    }
    Ok((dict.into_any().unbind(), units.into_any().unbind()))
}

/// A CSV header field's name and unit: `crank.x [m]` → (`crank.x`, `m`).
pub fn name_and_unit(field: &str) -> (&str, Option<&str>) {
    let field = field.trim();
    match field.strip_suffix(']').and_then(|f| f.rsplit_once(" [")) {
        Some((name, unit)) if !unit.is_empty() => (name.trim_end(), Some(unit)),
        _ => (field, None),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn header_fields_split_into_name_and_unit() {
        assert_eq!(super::name_and_unit("time [s]"), ("time", Some("s")));
        assert_eq!(
            super::name_and_unit(" JOINT_1.tz [N·mm]"),
            ("JOINT_1.tz", Some("N·mm"))
        );
        assert_eq!(super::name_and_unit("REQUEST_1.f2"), ("REQUEST_1.f2", None));
    }
}
