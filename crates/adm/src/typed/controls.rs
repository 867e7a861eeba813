//! The typed control and system elements (ADM-ELEMENTS §6–§12), read by
//! [`crate::typing`]'s control typing.

use super::*;

/// `DIFF/id, FUNCTION = e, IC = y0 [, ẏ0] [, IMPLICIT] [, STATIC_HOLD]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Diff {
    pub header: Header,
    pub function: Located<Function>,
    /// `IC = y0 [, ẏ0]` (1 or 2 values).
    pub ic: Option<Located<Vec<f64>>>,
    pub implicit: bool,
    pub static_hold: bool,
}

/// `LSE/id, X, A [, U, B] [, Y, C] [, D] [, IC] [, STATIC_HOLD]`: ẋ = A x + B u, y = C x + D u.
#[derive(Clone, Debug, PartialEq)]
pub struct Lse {
    pub header: Header,
    pub x: IdRef,
    pub a: IdRef,
    pub u: Option<IdRef>,
    pub b: Option<IdRef>,
    pub y: Option<IdRef>,
    pub c: Option<IdRef>,
    pub d: Option<IdRef>,
    pub ic: Option<IdRef>,
    pub static_hold: bool,
}

/// `TFSISO/id, NUMERATOR = b0, …, DENOMINATOR = a0, …, U, X, Y [, STATIC_HOLD]`:
/// coefficients in ascending powers of s.
#[derive(Clone, Debug, PartialEq)]
pub struct Tfsiso {
    pub header: Header,
    pub numerator: Located<Vec<f64>>,
    pub denominator: Located<Vec<f64>>,
    pub u: IdRef,
    pub x: IdRef,
    pub y: IdRef,
    pub static_hold: bool,
}

/// `GSE/id, …, FUNCTION = USER(…)`: read so that it can be named (linkage runs no user
/// subroutines).
#[derive(Clone, Debug, PartialEq)]
pub struct Gse {
    pub header: Header,
    pub function: Option<Located<Function>>,
}

/// Order of the values of a full matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatrixOrder {
    /// Row by row.
    Rows,
    /// Column by column.
    Columns,
}

/// What a MATRIX holds.
#[derive(Clone, Debug, PartialEq)]
pub enum MatrixData {
    Full {
        order: MatrixOrder,
        rows: usize,
        columns: usize,
        values: Vec<f64>,
    },
    /// `(i, j, value)`, 1-based.
    Sparse {
        rows: usize,
        columns: usize,
        entries: Vec<(usize, usize, f64)>,
    },
    /// `FILE = name [, NAME = matrix]`: the file name as written (relative to the dataset).
    File {
        name: String,
        span: Span,
        matrix: Option<String>,
    },
}

/// `MATRIX/id, …`.
#[derive(Clone, Debug, PartialEq)]
pub struct Matrix {
    pub header: Header,
    pub data: MatrixData,
}

/// `PINPUT/id, VARIABLES = …` or `POUTPUT/id, VARIABLES = …`.
#[derive(Clone, Debug, PartialEq)]
pub struct PlantList {
    pub header: Header,
    pub variables: Vec<IdRef>,
}

/// The control and system statements of a dataset, each kind in definition order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ControlStatements {
    pub diffs: Vec<Diff>,
    pub lses: Vec<Lse>,
    pub tfsisos: Vec<Tfsiso>,
    pub gses: Vec<Gse>,
    pub matrices: Vec<Matrix>,
    pub pinputs: Vec<PlantList>,
    pub poutputs: Vec<PlantList>,
}
