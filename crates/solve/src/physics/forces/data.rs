//! Data elements as expressions see them: VARIABLE expressions (parsed once), ARRAY values
//! and SPLINE interpolation data, by dataset id.
//!
//! `VARVAL(id)` evaluates the VARIABLE's expression in the same environment (see
//! [`crate::physics::measures::StateEnv`]); `ARYVAL(id, n)` is value n (1-based) of an ARRAY: a number
//! of its `NUMBERS`, or `VARVAL` of the n-th of its `VARIABLES`; `AKISPL`/`CUBSPL` read the
//! 1-D SPLINEs. VARIABLEs that call `USER(…)` or do not parse, X/Y arrays (states of
//! LSE/GSE/TFSISO) and 2-D or file splines are kept as "unusable": referencing them from a
//! force is an error that names them, while unused ones do not matter (models often carry
//! output VARIABLEs with measures linkage does not know).

use super::parse_function;
use linkage_adm::Diagnostic;
use linkage_expr::{EvalError, EvalErrorKind, Expr, SplineData};
use linkage_model::forces::{ArrayValues, SplineValues};
use linkage_model::Model;
use std::collections::HashMap;

/// Why a VARIABLE cannot be evaluated.
#[derive(Clone, Debug)]
pub enum VariableProblem {
    /// Its FUNCTION calls a USER subroutine.
    User,
    /// Its FUNCTION does not parse (the diagnostic is located in the expression).
    Syntax(Diagnostic),
}

/// A VARIABLE: its display name and parsed expression.
#[derive(Clone, Debug)]
pub struct VariableData {
    pub name: String,
    pub expr: Result<Expr, VariableProblem>,
}

/// What `ARYVAL` reads.
#[derive(Clone, Debug, PartialEq)]
pub enum ArrayData {
    Numbers(Vec<f64>),
    /// VARIABLE ids.
    Variables(Vec<u32>),
    /// X/Y arrays of LSE/GSE/TFSISO elements (not modelled).
    States,
}

/// The data elements of a model, by dataset id.
#[derive(Clone, Debug, Default)]
pub struct DataElements {
    pub variables: HashMap<u32, VariableData>,
    pub arrays: HashMap<u32, ArrayData>,
    pub splines: HashMap<u32, SplineData>,
    /// SPLINEs that exist but cannot be interpolated, with the reason.
    pub unsupported_splines: HashMap<u32, String>,
}

/// Dataset ids above `u32::MAX` cannot be named in an expression.
fn id32(id: u64) -> Option<u32> {
    u32::try_from(id).ok()
}

impl DataElements {
    /// The parsed expression of VARIABLE/`id`, or the evaluation error that names why it
    /// cannot be used (missing, USER subroutine, syntax error).
    pub fn variable_expr(&self, id: u32) -> Result<&Expr, EvalError> {
        let var = self
            .variables
            .get(&id)
            .ok_or_else(|| EvalError::unknown_reference(format!("VARIABLE/{id} does not exist")))?;
        match &var.expr {
            Ok(e) => Ok(e),
            Err(VariableProblem::User) => Err(EvalError::new(
                EvalErrorKind::UserSubroutine,
                format!(
                    "VARIABLE/{id} ({}) calls a USER subroutine, which cannot be run",
                    var.name
                ),
            )),
            Err(VariableProblem::Syntax(d)) => Err(EvalError::invalid_argument(format!(
                "VARIABLE/{id} cannot be evaluated: {}",
                d.message
            ))),
        }
    }

    /// Parses every VARIABLE expression and prepares arrays and splines. Invalid 1-D spline
    /// data are returned as diagnostics (the spline is then left out); VARIABLE problems are
    /// kept in [`VariableData::expr`].
    pub fn new(model: &Model) -> (DataElements, Vec<Diagnostic>) {
        let mut data = DataElements::default();
        let mut errors = Vec::new();
        for v in &model.variables {
            let Some(id) = id32(v.origin.id) else {
                continue;
            };
            let expr = match &v.function {
                Some(f) if !f.value.user => parse_function(&model.file, f, &v.origin, "FUNCTION")
                    .map_err(|d| {
                        if d.message.contains("USER subroutine") {
                            VariableProblem::User
                        } else {
                            VariableProblem::Syntax(d)
                        }
                    }),
                _ => Err(VariableProblem::User),
            };
            data.variables.insert(
                id,
                VariableData {
                    name: v.origin.name.clone(),
                    expr,
                },
            );
        }
        for a in &model.arrays {
            let Some(id) = id32(a.origin.id) else {
                continue;
            };
            let values = match &a.values {
                ArrayValues::Numbers(n) => ArrayData::Numbers(n.clone()),
                ArrayValues::Variables(v) => ArrayData::Variables(
                    v.iter()
                        .filter_map(|&k| id32(model.variables[k].origin.id))
                        .collect(),
                ),
                ArrayValues::States => ArrayData::States,
            };
            data.arrays.insert(id, values);
        }
        for s in &model.splines {
            let Some(id) = id32(s.origin.id) else {
                continue;
            };
            match &s.values {
                SplineValues::Curve { x, y } => {
                    match SplineData::new(x.clone(), y.clone(), s.linear_extrapolate) {
                        Ok(d) => {
                            data.splines.insert(id, d);
                        }
                        Err(e) => errors.push(Diagnostic::error(
                            model.file.clone(),
                            Some(s.origin.span),
                            format!("{}: {}", s.origin.name, e.message),
                        )),
                    }
                }
                SplineValues::Surface { .. } => {
                    data.unsupported_splines.insert(
                        id,
                        format!(
                            "{} is a 2-D spline (several Y curves); linkage interpolates 1-D splines only",
                            s.origin.element()
                        ),
                    );
                }
                SplineValues::File(name) => {
                    data.unsupported_splines.insert(
                        id,
                        format!(
                            "{} reads its data from the file '{name}', which linkage does not read",
                            s.origin.element()
                        ),
                    );
                }
            }
        }
        (data, errors)
    }
}
