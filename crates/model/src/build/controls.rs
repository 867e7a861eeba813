//! Control and system elements resolved and checked: MATRIX (values, or a FILE read relative
//! to the dataset), DIFF, LSE, TFSISO (their arrays, matrices and sizes) and PINPUT/POUTPUT
//! ([`crate::controls`]).
//!
//! Errors (each at the argument at fault): a duplicate id; an ARRAY, MATRIX or VARIABLE that
//! does not exist; an X array of the wrong type or shared by two elements; matrix sizes that
//! do not fit the states, inputs and outputs (A n × n, B n × nu, C ny × n, D ny × nu); an IC
//! array whose size is not n; a U array without VARIABLEs; a transfer function that is not
//! proper; a MATRIX file that is missing or cannot be read (named).

use super::context::{origin, Ctx};
use crate::controls::{
    matrix_file_path, Controls, DenseMatrix, Linear, Matrix, PlantList, StateElement, StateLaw,
};
use crate::forces::{Array, ArrayValues, Variable};
use linkage_adm::{ArrayKind, Dataset, IdRef, MatrixData, MatrixOrder};
use std::collections::{HashMap, HashSet};

/// Every control and system element of `ds`; `variables` and `arrays` are the model's data
/// elements.
pub(crate) fn controls(
    ds: &Dataset,
    variables: &[Variable],
    arrays: &[Array],
    cx: &mut Ctx,
) -> Controls {
    let variable_index: HashMap<u64, usize> = variables
        .iter()
        .enumerate()
        .map(|(k, v)| (v.origin.id, k))
        .collect();
    let array_index: HashMap<u64, &Array> = arrays.iter().map(|a| (a.origin.id, a)).collect();
    let (matrices, unreadable) = matrices(ds, cx);
    let matrix_index: HashMap<u64, &DenseMatrix> =
        matrices.iter().map(|m| (m.origin.id, &m.matrix)).collect();
    let mut b = StateBuilder {
        arrays: &array_index,
        matrices: &matrix_index,
        unreadable: &unreadable,
        owners: HashMap::new(),
        states: Vec::new(),
        count: 0,
    };
    let mut seen = HashSet::new();
    for d in &ds.controls.diffs {
        if !cx.unique(&mut seen, "DIFF", &d.header) {
            continue;
        }
        let ic = d.ic.as_ref().map(|l| l.value.clone()).unwrap_or_default();
        b.push(StateElement {
            origin: origin("DIFF", &d.header),
            law: StateLaw::Diff {
                function: d.function.clone(),
                implicit: d.implicit,
            },
            offset: 0,
            size: 1,
            initial: vec![ic.first().copied().unwrap_or(0.0)],
            initial_rate: vec![ic.get(1).copied().unwrap_or(0.0)],
            static_hold: d.static_hold,
            x_array: None,
            y_array: None,
        });
    }
    let mut seen = HashSet::new();
    for l in &ds.controls.lses {
        if !cx.unique(&mut seen, "LSE", &l.header) {
            continue;
        }
        if let Some(e) = b.lse(l, cx) {
            b.push(e);
        }
    }
    let mut seen = HashSet::new();
    for t in &ds.controls.tfsisos {
        if !cx.unique(&mut seen, "TFSISO", &t.header) {
            continue;
        }
        if let Some(e) = b.tfsiso(t, cx) {
            b.push(e);
        }
    }
    let plant = |lists: &[linkage_adm::PlantList], what: &'static str, cx: &mut Ctx| {
        let mut seen = HashSet::new();
        let mut out = Vec::new();
        for l in lists {
            if !cx.unique(&mut seen, what, &l.header) {
                continue;
            }
            let mut vars = Vec::new();
            for r in &l.variables {
                match variable_index.get(&r.id) {
                    Some(&k) => vars.push(k),
                    None => cx.error(
                        r.span,
                        format!("{}: VARIABLE {} does not exist", l.header.name, r.id),
                    ),
                }
            }
            out.push(PlantList {
                origin: origin(what, &l.header),
                variables: vars,
            });
        }
        out
    };
    let pinputs = plant(&ds.controls.pinputs, "PINPUT", cx);
    let poutputs = plant(&ds.controls.poutputs, "POUTPUT", cx);
    // U arrays must name VARIABLEs: checked where they are used.
    let _ = &variable_index;
    Controls {
        states: b.states,
        count: b.count,
        matrices,
        pinputs,
        poutputs,
    }
}

/// Every MATRIX, its values read (FULL in either order, SPARSE, or a FILE), and the MATRIX
/// ids whose file is missing or cannot be read, with why (an error where a state element
/// uses one; `coverage` names a missing file whoever uses it).
pub(crate) fn matrices(ds: &Dataset, cx: &mut Ctx) -> (Vec<Matrix>, HashMap<u64, String>) {
    let mut unreadable = HashMap::new();
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    for m in &ds.controls.matrices {
        if !cx.unique(&mut seen, "MATRIX", &m.header) {
            continue;
        }
        let matrix = match &m.data {
            MatrixData::Full {
                order,
                rows,
                columns,
                values,
            } => full(*order, *rows, *columns, values),
            MatrixData::Sparse {
                rows,
                columns,
                entries,
            } => {
                let mut d = DenseMatrix::zeros(*rows, *columns);
                for &(i, j, v) in entries {
                    d.set(i - 1, j - 1, v);
                }
                d
            }
            MatrixData::File { name, span, matrix } => {
                let path = matrix_file_path(&ds.file, name);
                let read = std::fs::read_to_string(&path)
                    .map_err(|e| format!("the file '{name}' cannot be read ({e})"))
                    .and_then(|text| {
                        read_adamsmat(&text, matrix.as_deref()).map_err(|e| e.to_string())
                    });
                match read {
                    Ok(d) => d,
                    Err(e) => {
                        let _ = span;
                        unreadable.insert(m.header.id, format!("{}: {e}", m.header.name));
                        continue;
                    }
                }
            }
        };
        out.push(Matrix {
            origin: origin("MATRIX", &m.header),
            matrix,
        });
    }
    (out, unreadable)
}

/// A full matrix from values in row (RORDER) or column (CORDER) order.
fn full(order: MatrixOrder, rows: usize, columns: usize, values: &[f64]) -> DenseMatrix {
    let mut d = DenseMatrix::zeros(rows, columns);
    for (k, &v) in values.iter().enumerate() {
        let (i, j) = match order {
            MatrixOrder::Rows => (k / columns.max(1), k % columns.max(1)),
            MatrixOrder::Columns => (k % rows.max(1), k / rows.max(1)),
        };
        if i < rows && j < columns {
            d.set(i, j, v);
        }
    }
    d
}

/// Reads one matrix of an Adams text matrix file (ADM-ELEMENTS §11): line 1 `ADAMSMAT title`,
/// line 2 the number of matrices, then their names (as many lines as needed), then per
/// matrix the header `NAME FULL RORDER|CORDER rows columns count ( Fortran format )` and its
/// values. Values are read by the format's field width when it is `nFw.d` (or E, D, G), so
/// that fields without separators (`0.000-3.440`) are split as Fortran does; otherwise they
/// are separated by blanks or commas. `SPARSE` matrices list `i j value` triples (an
/// [unconfirmed] layout). `wanted` picks a matrix by name (case-insensitive); without it the
/// file's first matrix.
pub fn read_adamsmat(text: &str, wanted: Option<&str>) -> Result<DenseMatrix, MatrixFileError> {
    let mut lines = text.lines();
    let head = lines.next().unwrap_or("");
    if !head.starts_with("ADAMSMAT") {
        return Err(MatrixFileError::NotAdamsmat(head.chars().take(8).collect()));
    }
    let count: usize = lines
        .next()
        .and_then(|l| l.trim().parse().ok())
        .ok_or(MatrixFileError::NoCount)?;
    let mut names = Vec::new();
    while names.len() < count {
        let line = lines.next().ok_or(MatrixFileError::EndsInNames)?;
        names.extend(line.split_whitespace().map(str::to_string));
    }
    for _ in 0..count {
        let header = loop {
            let l = lines.next().ok_or(MatrixFileError::EndsBeforeHeader)?;
            if !l.trim().is_empty() {
                break l;
            }
        };
        let (fields, format) = match header.find('(') {
            Some(p) => (&header[..p], Some(header[p..].trim())),
            None => (header, None),
        };
        let f: Vec<&str> = fields.split_whitespace().collect();
        let bad = || MatrixFileError::Header(header.trim().to_string());
        let (name, kind) = (f.first().ok_or_else(bad)?, f.get(1).ok_or_else(bad)?);
        let sparse = kind.eq_ignore_ascii_case("SPARSE");
        let num = |k: usize| -> Result<usize, MatrixFileError> {
            f.get(k).and_then(|x| x.parse().ok()).ok_or_else(bad)
        };
        let (order, rows, columns, n) = if sparse {
            (MatrixOrder::Rows, num(2)?, num(3)?, num(4)?)
        } else {
            let order = match f.get(2).map(|s| s.to_ascii_uppercase()) {
                Some(o) if o == "CORDER" => MatrixOrder::Columns,
                Some(o) if o == "RORDER" => MatrixOrder::Rows,
                _ => return Err(bad()),
            };
            (order, num(3)?, num(4)?, num(5)?)
        };
        let wanted_here = wanted.is_none_or(|w| w.eq_ignore_ascii_case(name));
        let per_value = if sparse { 3 } else { 1 };
        let values = read_values(&mut lines, n * per_value, format).map_err(|cause| {
            MatrixFileError::Values {
                matrix: name.to_string(),
                cause,
            }
        })?;
        if !wanted_here {
            continue;
        }
        if sparse {
            let mut d = DenseMatrix::zeros(rows, columns);
            for t in values.chunks_exact(3) {
                let (i, j) = (t[0] as usize, t[1] as usize);
                if i == 0 || j == 0 || i > rows || j > columns {
                    return Err(MatrixFileError::Outside {
                        matrix: name.to_string(),
                        i,
                        j,
                    });
                }
                d.set(i - 1, j - 1, t[2]);
            }
            return Ok(d);
        }
        if n != rows * columns {
            return Err(MatrixFileError::Count {
                matrix: name.to_string(),
                n,
                rows,
                columns,
            });
        }
        return Ok(full(order, rows, columns, &values));
    }
    Err(match wanted {
        Some(w) => MatrixFileError::NoMatrixNamed(w.to_string()),
        None => MatrixFileError::Empty,
    })
}

/// Why an ADAMSMAT file cannot be read ([`read_adamsmat`]; the caller names the file).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MatrixFileError {
    #[error(
        "the matrix file's header '{0}' is not ADAMSMAT (the Adams text format, the one \
         linkage reads)"
    )]
    NotAdamsmat(String),
    #[error("the matrix file's second line is not the number of matrices")]
    NoCount,
    #[error("the matrix file ends in its list of names")]
    EndsInNames,
    #[error("the matrix file ends before a matrix header")]
    EndsBeforeHeader,
    #[error("cannot read the matrix header '{0}'")]
    Header(String),
    #[error("matrix {matrix}: {cause}")]
    Values { matrix: String, cause: ValuesError },
    #[error("matrix {matrix}: entry ({i}, {j}) is outside it")]
    Outside { matrix: String, i: usize, j: usize },
    #[error("matrix {matrix}: {n} values for a {rows} × {columns} matrix")]
    Count {
        matrix: String,
        n: usize,
        rows: usize,
        columns: usize,
    },
    #[error("the matrix file has no matrix named {0}")]
    NoMatrixNamed(String),
    #[error("the matrix file holds no matrix")]
    Empty,
}

/// Why a matrix's values cannot be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ValuesError {
    #[error("'{0}' is not a number")]
    NotANumber(String),
    #[error("{found} of {wanted} values found before the file ends")]
    EndsEarly { found: usize, wanted: usize },
}

/// The field width of a Fortran format `( nFw.d )` (also E, D, G), if it is one.
fn field_width(format: &str) -> Option<usize> {
    let inner = format
        .trim()
        .trim_start_matches('(')
        .trim_end_matches(')')
        .trim();
    let p = inner.find(|c: char| matches!(c.to_ascii_uppercase(), 'F' | 'E' | 'D' | 'G'))?;
    let rest = &inner[p + 1..];
    let w = rest.split('.').next()?.trim();
    w.parse().ok().filter(|w| *w > 0)
}

/// `n` numbers from the following lines (see [`read_adamsmat`]).
fn read_values<'a>(
    lines: &mut impl Iterator<Item = &'a str>,
    n: usize,
    format: Option<&str>,
) -> Result<Vec<f64>, ValuesError> {
    let width = format.and_then(field_width);
    let parse = |s: &str| -> Result<f64, ValuesError> {
        let t = s.trim().replace(['D', 'd'], "E");
        t.parse::<f64>()
            .map_err(|_| ValuesError::NotANumber(s.trim().to_string()))
    };
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let line = lines.next().ok_or(ValuesError::EndsEarly {
            found: out.len(),
            wanted: n,
        })?;
        match width {
            Some(w) => {
                let chars: Vec<char> = line.trim_end().chars().collect();
                for chunk in chars.chunks(w) {
                    let s: String = chunk.iter().collect();
                    if !s.trim().is_empty() && out.len() < n {
                        out.push(parse(&s)?);
                    }
                }
            }
            None => {
                for s in line
                    .split([' ', ',', '\t'])
                    .filter(|s| !s.trim().is_empty())
                {
                    if out.len() < n {
                        out.push(parse(s)?);
                    }
                }
            }
        }
    }
    Ok(out)
}

/// Collects state elements and lays out their states.
struct StateBuilder<'a> {
    arrays: &'a HashMap<u64, &'a Array>,
    matrices: &'a HashMap<u64, &'a DenseMatrix>,
    /// MATRIX ids whose file could not be read, with why.
    unreadable: &'a HashMap<u64, String>,
    /// X and Y arrays already owned, by array id: the owner's name.
    owners: HashMap<u64, String>,
    states: Vec<StateElement>,
    count: usize,
}

impl StateBuilder<'_> {
    fn push(&mut self, mut e: StateElement) {
        e.offset = self.count;
        self.count += e.size;
        self.states.push(e);
    }

    /// The ARRAY `r` of element `name`, of kind `kind` (an untyped array is accepted as IC).
    fn array(&self, name: &str, r: IdRef, kind: ArrayKind, cx: &mut Ctx) -> Option<&Array> {
        let Some(a) = self.arrays.get(&r.id).copied() else {
            cx.error(r.span, format!("{name}: ARRAY {} does not exist", r.id));
            return None;
        };
        let ok = a.kind == Some(kind) || (kind == ArrayKind::Ic && a.kind.is_none());
        if !ok {
            let k = |k: Option<ArrayKind>| match k {
                Some(ArrayKind::X) => "an X",
                Some(ArrayKind::Y) => "a Y",
                Some(ArrayKind::U) => "a U",
                Some(ArrayKind::Ic) | None => "an IC",
            };
            cx.error(
                r.span,
                format!(
                    "{name}: ARRAY {} is {} array where {} array is expected",
                    r.id,
                    k(a.kind),
                    k(Some(kind))
                ),
            );
            return None;
        }
        Some(a)
    }

    /// Claims an X or Y array for `name`: an error when another element owns it.
    fn claim(&mut self, name: &str, r: IdRef, cx: &mut Ctx) -> bool {
        if let Some(other) = self.owners.get(&r.id) {
            cx.error(
                r.span,
                format!("{name}: ARRAY {} already belongs to {other}", r.id),
            );
            return false;
        }
        self.owners.insert(r.id, name.to_string());
        true
    }

    /// The MATRIX `r` of `name`, required to be `rows × columns`.
    fn matrix(
        &self,
        name: &str,
        key: &str,
        r: IdRef,
        (rows, columns): (usize, usize),
        cx: &mut Ctx,
    ) -> Option<DenseMatrix> {
        let Some(m) = self.matrices.get(&r.id) else {
            self.missing_matrix(name, r, cx);
            return None;
        };
        if (m.rows, m.columns) != (rows, columns) {
            cx.error(
                r.span,
                format!(
                    "{name}: {key} (MATRIX {}) is {} × {} but must be {rows} × {columns}",
                    r.id, m.rows, m.columns
                ),
            );
            return None;
        }
        Some((*m).clone())
    }

    /// The error of a MATRIX reference that has no values: it does not exist, or its file
    /// cannot be read (named).
    fn missing_matrix(&self, name: &str, r: IdRef, cx: &mut Ctx) {
        match self.unreadable.get(&r.id) {
            Some(why) => cx.error(r.span, format!("{name}: {why}")),
            None => cx.error(r.span, format!("{name}: MATRIX {} does not exist", r.id)),
        }
    }

    /// The VARIABLEs of a U array.
    fn inputs(&self, name: &str, r: IdRef, cx: &mut Ctx) -> Option<Vec<usize>> {
        let a = self.array(name, r, ArrayKind::U, cx)?;
        match &a.values {
            ArrayValues::Variables(v) => Some(v.clone()),
            _ => {
                cx.error(
                    r.span,
                    format!("{name}: the U array ARRAY {} lists no VARIABLES", r.id),
                );
                None
            }
        }
    }

    fn lse(&mut self, l: &linkage_adm::Lse, cx: &mut Ctx) -> Option<StateElement> {
        let name = l.header.name.clone();
        let x = self.array(&name, l.x, ArrayKind::X, cx)?;
        let a = self.matrices.get(&l.a.id);
        let n = match (a, &x.values) {
            (Some(a), _) => a.rows,
            (None, _) => {
                self.missing_matrix(&name, l.a, cx);
                return None;
            }
        };
        let a = self.matrix(&name, "A", l.a, (n, n), cx)?;
        let inputs = match l.u {
            Some(u) => self.inputs(&name, u, cx)?,
            None => Vec::new(),
        };
        let nu = inputs.len();
        let ny = match l.y {
            Some(y) => {
                let ya = self.array(&name, y, ArrayKind::Y, cx)?;
                let _ = ya;
                match (l.c, l.d) {
                    (Some(c), _) => self.matrices.get(&c.id).map_or(0, |m| m.rows),
                    (None, Some(d)) => self.matrices.get(&d.id).map_or(0, |m| m.rows),
                    (None, None) => {
                        cx.error(y.span, format!("{name}: Y needs C or D"));
                        return None;
                    }
                }
            }
            None => 0,
        };
        let need = |key: &str,
                    m: Option<IdRef>,
                    dims: (usize, usize),
                    needed: bool,
                    b: &Self,
                    cx: &mut Ctx| {
            match m {
                Some(r) => {
                    if !needed {
                        cx.error(
                            r.span,
                            format!(
                                "{name}: {key} needs {}",
                                if key == "B" {
                                    "U"
                                } else if key == "C" {
                                    "Y"
                                } else {
                                    "U and Y"
                                }
                            ),
                        );
                        return None;
                    }
                    b.matrix(&name, key, r, dims, cx)
                }
                None => Some(DenseMatrix::zeros(dims.0, dims.1)),
            }
        };
        let b = need("B", l.b, (n, nu), l.u.is_some(), self, cx)?;
        let c = need("C", l.c, (ny, n), l.y.is_some(), self, cx)?;
        let d = need("D", l.d, (ny, nu), l.u.is_some() && l.y.is_some(), self, cx)?;
        let initial = match l.ic {
            Some(r) => {
                let a = self.array(&name, r, ArrayKind::Ic, cx)?;
                match &a.values {
                    ArrayValues::Numbers(v) if v.len() == n => v.clone(),
                    _ => {
                        cx.error(
                            r.span,
                            format!("{name}: the IC array ARRAY {} must hold {n} numbers", r.id),
                        );
                        return None;
                    }
                }
            }
            None => vec![0.0; n],
        };
        if !self.claim(&name, l.x, cx) || l.y.is_some_and(|y| !self.claim(&name, y, cx)) {
            return None;
        }
        Some(StateElement {
            origin: origin("LSE", &l.header),
            law: StateLaw::Linear(Box::new(Linear { a, b, c, d, inputs })),
            offset: 0,
            size: n,
            initial,
            initial_rate: vec![0.0; n],
            static_hold: l.static_hold,
            x_array: Some(l.x.id),
            y_array: l.y.map(|y| y.id),
        })
    }

    fn tfsiso(&mut self, t: &linkage_adm::Tfsiso, cx: &mut Ctx) -> Option<StateElement> {
        let name = t.header.name.clone();
        self.array(&name, t.x, ArrayKind::X, cx)?;
        self.array(&name, t.y, ArrayKind::Y, cx)?;
        let inputs = self.inputs(&name, t.u, cx)?;
        if inputs.len() != 1 {
            cx.error(
                t.u.span,
                format!("{name}: the U array must hold one VARIABLE (a single input)"),
            );
            return None;
        }
        let Some(law) =
            Linear::transfer_function(&t.numerator.value, &t.denominator.value, inputs[0])
        else {
            cx.error(
                t.denominator.span,
                format!(
                    "{name}: the transfer function must be proper (no more NUMERATOR than \
                     DENOMINATOR coefficients) with a nonzero last DENOMINATOR coefficient"
                ),
            );
            return None;
        };
        if !self.claim(&name, t.x, cx) || !self.claim(&name, t.y, cx) {
            return None;
        }
        let n = law.a.rows;
        Some(StateElement {
            origin: origin("TFSISO", &t.header),
            law: StateLaw::Linear(Box::new(law)),
            offset: 0,
            size: n,
            initial: vec![0.0; n],
            initial_rate: vec![0.0; n],
            static_hold: t.static_hold,
            x_array: Some(t.x.id),
            y_array: Some(t.y.id),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_adamsmat_file_is_read_by_its_fortran_field_widths() {
        // The layout of the documented example (ADM-ELEMENTS §11): fields without separators.
        let text = "ADAMSMAT example\n2\nTRF VALK\n\
                    TRF FULL RORDER 2 2 4 ( 4F8.3 )\n   1.000   2.000   3.000   4.000\n\
                    VALK FULL CORDER 2 2 4 ( 2F6.3 )\n 0.000-3.440\n 1.500 2.000\n";
        let m = read_adamsmat(text, Some("valk")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(m.values, vec![0.0, 1.5, -3.44, 2.0]);
        let m = read_adamsmat(text, None).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(m.values, vec![1.0, 2.0, 3.0, 4.0]);
        assert_eq!(
            read_adamsmat(text, Some("NONE")).unwrap_err(),
            MatrixFileError::NoMatrixNamed("NONE".into())
        );
        assert_eq!(
            read_adamsmat("MATRIXx\n", None).unwrap_err(),
            MatrixFileError::NotAdamsmat("MATRIXx".into())
        );
    }

    #[test]
    fn a_first_order_lag_is_realised_with_its_pole_and_gain() {
        // 2/(0.5 s + 1): ẋ = −2x + 4u, y = x.
        let l = Linear::transfer_function(&[2.0], &[1.0, 0.5], 0).expect("proper");
        assert_eq!(
            (l.a.values.clone(), l.b.values.clone()),
            (vec![-2.0], vec![4.0])
        );
        assert_eq!(
            (l.c.values.clone(), l.d.values.clone()),
            (vec![1.0], vec![0.0])
        );
        // (s + 3)/(s + 1): feed-through 1, ẋ = −x + (3 − 1)u, y = x + u.
        let l = Linear::transfer_function(&[3.0, 1.0], &[1.0, 1.0], 0).expect("proper");
        assert_eq!((l.b.values[0], l.d.values[0]), (2.0, 1.0));
        assert!(Linear::transfer_function(&[1.0, 1.0, 1.0], &[1.0, 1.0], 0).is_none());
        assert!(Linear::transfer_function(&[1.0], &[1.0, 0.0], 0).is_none());
    }
}
