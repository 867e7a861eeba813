//! Data elements as expressions see them: VARIABLE expressions (parsed once), ARRAY values
//! and SPLINE interpolation data, by dataset id.
//!
//! `VARVAL(id)` evaluates the VARIABLE's expression in the same environment (see
//! [`crate::physics::measures::StateEnv`]); `ARYVAL(id, n)` is value n (1-based) of an ARRAY: a number
//! of its `NUMBERS`, or `VARVAL` of the n-th of its `VARIABLES`; `AKISPL`/`CUBSPL` read the
//! 1-D and 2-D SPLINEs. The X array of an LSE or TFSISO reads its states, the Y array its outputs
//! `C x + D u`; `DIF`/`DIF1` read a DIFF's state and rate; `PINVAL`/`POUVAL` the VARIABLEs of
//! a PINPUT/POUTPUT list. VARIABLEs that call `USER(…)` or do not parse, X/Y arrays that no
//! element owns and file splines are kept as "unusable": referencing them from a
//! force is an error that names them, while unused ones do not matter (models often carry
//! output VARIABLEs with measures linkage does not know).
//!
//! `SENVAL(id)` reads the value SENSOR/id stored when it last fired (EVALUATE, else
//! FUNCTION, at the event; ADM-ELEMENTS §5), 0 before it first fires [decided: Adams does not
//! say]. The values are data of the state evaluated (`State::elements.sensors`), so the
//! forces, the requests and the sensors of a run read the same ones; they are written only
//! by a dynamic, quasi-static or kinematic run when a sensor fires
//! (`kernel::sensors::SensorWatch`), and persist across the analyses of one command file
//! (`pipeline::Assembled::continuing` takes them from the state the last analysis left);
//! the IC and static analyses read them as they are (0, or the value of the last firing of
//! an earlier run) [decided].

use super::parse_function;
use linkage_adm::Diagnostic;
use linkage_expr::{EvalError, EvalErrorKind, Expr, SplineData};
use linkage_model::controls::StateLaw;
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
    /// The X array of an LSE or TFSISO: control states `x[offset..offset + size]`.
    States {
        offset: usize,
        size: usize,
    },
    /// The Y array of an LSE or TFSISO: its outputs `y = C x + D u`.
    Outputs(Box<OutputMap>),
    /// An X or Y array that no state element uses.
    Unowned,
}

/// The outputs `y = C x[offset..] + D u` of a linear state element, `u` the values of the
/// VARIABLEs `inputs`.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputMap {
    pub offset: usize,
    pub c: linkage_model::controls::DenseMatrix,
    pub d: linkage_model::controls::DenseMatrix,
    pub inputs: Vec<u32>,
}

/// The data elements of a model, by dataset id.
#[derive(Clone, Debug, Default)]
pub struct DataElements {
    pub variables: HashMap<u32, VariableData>,
    pub arrays: HashMap<u32, ArrayData>,
    pub splines: HashMap<u32, SplineData>,
    /// SPLINEs that exist but cannot be interpolated, with the reason.
    pub unsupported_splines: HashMap<u32, String>,
    /// DIFF id → its state's index in the control states.
    pub diffs: HashMap<u32, usize>,
    /// PINPUT and POUTPUT ids → their VARIABLE ids in order.
    pub pinputs: HashMap<u32, Vec<u32>>,
    pub poutputs: HashMap<u32, Vec<u32>>,
    /// SENSOR id → its index in the model's sensors (and in the stored values a state
    /// carries, `State::elements.sensors`).
    pub sensors: HashMap<u32, usize>,
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
                Some(f) if !f.value.user || model.user.given() => {
                    parse_function(&model.file, f, &v.origin, "FUNCTION", &model.user).map_err(
                        |d| {
                            if d.message.contains("USER subroutine") && !model.user.given() {
                                VariableProblem::User
                            } else {
                                VariableProblem::Syntax(d)
                            }
                        },
                    )
                }
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
                ArrayValues::States => ArrayData::Unowned,
            };
            data.arrays.insert(id, values);
        }
        let variable_id = |k: &usize| id32(model.variables[*k].origin.id);
        for e in &model.controls.states {
            let Some(id) = id32(e.origin.id) else {
                continue;
            };
            if e.origin.statement == "DIFF" {
                data.diffs.insert(id, e.offset);
            }
            if let Some(x) = e.x_array.and_then(id32) {
                data.arrays.insert(
                    x,
                    ArrayData::States {
                        offset: e.offset,
                        size: e.size,
                    },
                );
            }
            if let (Some(y), StateLaw::Linear(l)) = (e.y_array.and_then(id32), &e.law) {
                let map = OutputMap {
                    offset: e.offset,
                    c: l.c.clone(),
                    d: l.d.clone(),
                    inputs: l.inputs.iter().filter_map(variable_id).collect(),
                };
                data.arrays.insert(y, ArrayData::Outputs(Box::new(map)));
            }
        }
        for (lists, out) in [
            (&model.controls.pinputs, &mut data.pinputs),
            (&model.controls.poutputs, &mut data.poutputs),
        ] {
            for l in lists {
                if let Some(id) = id32(l.origin.id) {
                    out.insert(id, l.variables.iter().filter_map(variable_id).collect());
                }
            }
        }
        for (k, s) in model.sensors.iter().enumerate() {
            if let Some(id) = id32(s.origin.id) {
                data.sensors.insert(id, k);
            }
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
                SplineValues::Surface { x, z, y } => {
                    match SplineData::surface(x.clone(), z.clone(), y.clone(), s.linear_extrapolate)
                    {
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
