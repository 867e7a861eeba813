//! Data elements: VARIABLE, ARRAY and SPLINE, resolved and checked.

use super::context::{origin, Ctx};
use crate::forces::{Array, ArrayValues, Spline, SplineValues, Variable};
use linkage_adm::{ArrayKind, Dataset};
use std::collections::{HashMap, HashSet};

/// The data elements of a model, each kind in definition order.
#[derive(Debug, Default)]
pub(crate) struct DataElements {
    pub variables: Vec<Variable>,
    pub arrays: Vec<Array>,
    pub splines: Vec<Spline>,
}

/// Resolves every VARIABLE, then every ARRAY (whose `VARIABLES` refer to them), then every
/// SPLINE.
pub(crate) fn data_elements(ds: &Dataset, cx: &mut Ctx) -> DataElements {
    let (variables, variable_index) = variables(ds, cx);
    DataElements {
        variables,
        arrays: arrays(ds, &variable_index, cx),
        splines: splines(ds, cx),
    }
}

/// Every VARIABLE, and VARIABLE id → index. Errors: a duplicate id, FUNCTION missing (a
/// variable refused leaves its id free).
fn variables(ds: &Dataset, cx: &mut Ctx) -> (Vec<Variable>, HashMap<u64, usize>) {
    let mut out = Vec::new();
    let mut variable_index = HashMap::new();
    for v in &ds.variables {
        let h = &v.header;
        if variable_index.contains_key(&h.id) {
            cx.error(h.span, format!("duplicate VARIABLE id {}", h.id));
            continue;
        }
        if v.function.is_none() {
            cx.error(h.span, format!("{}: FUNCTION is missing", h.name));
            continue;
        }
        variable_index.insert(h.id, out.len());
        out.push(Variable {
            origin: origin("VARIABLE", h),
            function: v.function.clone(),
            ic: v.ic.as_ref().map(|l| l.value),
        });
    }
    (out, variable_index)
}

/// Every ARRAY: `NUMBERS`, `VARIABLES` (indices into the variables), or the states of an X or
/// Y array. Errors: a duplicate id, a VARIABLE that does not exist. Warning: a SIZE that
/// differs from the number of values given.
fn arrays(ds: &Dataset, variable_index: &HashMap<u64, usize>, cx: &mut Ctx) -> Vec<Array> {
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    for a in &ds.arrays {
        let h = &a.header;
        if !cx.unique(&mut seen, "ARRAY", h) {
            continue;
        }
        let values = match (&a.numbers, &a.variables, a.kind) {
            (Some(n), _, _) => ArrayValues::Numbers(n.value.clone()),
            (None, Some(vars), _) => {
                let mut idx = Vec::with_capacity(vars.len());
                for r in vars {
                    match variable_index.get(&r.id) {
                        Some(&k) => idx.push(k),
                        None => cx.error(
                            r.span,
                            format!("{}: VARIABLE {} does not exist", h.name, r.id),
                        ),
                    }
                }
                if idx.len() != vars.len() {
                    continue;
                }
                ArrayValues::Variables(idx)
            }
            (None, None, Some(ArrayKind::X | ArrayKind::Y)) => ArrayValues::States,
            (None, None, _) => ArrayValues::Numbers(Vec::new()),
        };
        let len = match &values {
            ArrayValues::Numbers(n) => Some(n.len()),
            ArrayValues::Variables(v) => Some(v.len()),
            ArrayValues::States => None,
        };
        if let (Some(size), Some(len)) = (&a.size, len) {
            if size.value != len && len > 0 {
                let msg = format!(
                    "{}: SIZE = {} but {len} values are given",
                    h.name, size.value
                );
                cx.warn(size.span, msg);
            }
        }
        out.push(Array {
            origin: origin("ARRAY", h),
            kind: a.kind,
            values,
        });
    }
    out
}

/// Every SPLINE (see `spline_values` for the checks).
fn splines(ds: &Dataset, cx: &mut Ctx) -> Vec<Spline> {
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    for s in &ds.splines {
        let h = &s.header;
        if !cx.unique(&mut seen, "SPLINE", h) {
            continue;
        }
        let Some(values) = spline_values(s, cx) else {
            continue;
        };
        out.push(Spline {
            origin: origin("SPLINE", h),
            values,
            linear_extrapolate: s.linear_extrapolate,
        });
    }
    out
}

/// A spline's data: a FILE, a curve `y(x)` (one `Y`, as many values as X), or a surface (one
/// `Y = z_k, y_1, …, y_n` per z). Errors: X or Y missing, fewer than two X values, X not
/// strictly increasing, value counts that do not match.
fn spline_values(s: &linkage_adm::Spline, cx: &mut Ctx) -> Option<SplineValues> {
    let h = &s.header;
    if let Some(f) = &s.file {
        return Some(SplineValues::File(f.value.clone()));
    }
    let (Some(x), Some(first_y)) = (&s.x, s.y.first()) else {
        cx.error(
            h.span,
            format!("{}: X and Y (or FILE) are required", h.name),
        );
        return None;
    };
    if x.value.len() < 2 {
        cx.error(
            x.span,
            format!("{}: at least two X values are needed", h.name),
        );
        return None;
    }
    if let Some(w) = x.value.windows(2).find(|w| w[1] <= w[0]) {
        cx.error(
            x.span,
            format!(
                "{}: X values must be strictly increasing, but {} is followed by {}",
                h.name, w[0], w[1]
            ),
        );
        return None;
    }
    if s.z.is_none() && s.y.len() == 1 {
        if first_y.value.len() != x.value.len() {
            cx.error(
                first_y.span,
                format!(
                    "{}: {} Y values for {} X values",
                    h.name,
                    first_y.value.len(),
                    x.value.len()
                ),
            );
            return None;
        }
        return Some(SplineValues::Curve {
            x: x.value.clone(),
            y: first_y.value.clone(),
        });
    }
    // A 2-D spline: every `Y = z_k, y_1, …, y_n`.
    let mut z = Vec::with_capacity(s.y.len());
    let mut curves = Vec::with_capacity(s.y.len());
    for y in &s.y {
        match y.value.split_first() {
            Some((zk, ys)) if ys.len() == x.value.len() => {
                z.push(*zk);
                curves.push(ys.to_vec());
            }
            _ => {
                cx.error(
                    y.span,
                    format!(
                        "{}: each Y of a 2-D spline needs its z value and {} y values, found {} values",
                        h.name,
                        x.value.len(),
                        y.value.len()
                    ),
                );
                return None;
            }
        }
    }
    Some(SplineValues::Surface {
        x: x.value.clone(),
        z,
        y: curves,
    })
}

#[cfg(test)]
mod tests {
    use crate::build::test_support::{errors, ok};
    use crate::forces::*;

    #[test]
    fn data_elements_variables_arrays_splines() {
        let b = ok("VARIABLE/5, FUNCTION = DM(20, 1), IC = 1\nARRAY/1, IC, SIZE = 2, NUMBERS = 3, 4\nARRAY/2, U, VARIABLES = 5\nARRAY/3, X, SIZE = 4\nSPLINE/1, X = 0, 1, 2, Y = 0, 1, 4, LINEAR_EXTRAPOLATE\nSPLINE/2, X = 0, 1, Y = 0, 5, 6, Y = 1, 7, 8");
        let m = &b.model;
        assert_eq!(m.variables[0].origin.id, 5);
        assert_eq!(m.variables[0].ic, Some(1.0));
        assert_eq!(m.arrays[0].values, ArrayValues::Numbers(vec![3.0, 4.0]));
        assert_eq!(m.arrays[1].values, ArrayValues::Variables(vec![0]));
        assert_eq!(m.arrays[2].values, ArrayValues::States);
        assert_eq!(
            m.splines[0].values,
            SplineValues::Curve {
                x: vec![0.0, 1.0, 2.0],
                y: vec![0.0, 1.0, 4.0]
            }
        );
        assert!(m.splines[0].linear_extrapolate);
        assert_eq!(
            m.splines[1].values,
            SplineValues::Surface {
                x: vec![0.0, 1.0],
                z: vec![0.0, 1.0],
                y: vec![vec![5.0, 6.0], vec![7.0, 8.0]]
            }
        );
        let e = errors(
            "ARRAY/1, U, VARIABLES = 8\nSPLINE/1, X = 0, 0, Y = 1, 2\nSPLINE/2, X = 0, 1, Y = 1",
        );
        assert_eq!(
            e[0],
            (12, 25, "ARRAY_1: VARIABLE 8 does not exist".to_string())
        );
        assert_eq!((e[1].0, e[1].1), (13, 11));
        assert!(e[1].2.contains("strictly increasing"));
        assert_eq!(
            e[2],
            (14, 21, "SPLINE_2: 1 Y values for 2 X values".to_string())
        );
    }
}
