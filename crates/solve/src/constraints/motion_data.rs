//! Data elements in MOTION functions: `VARVAL(id)`, `ARYVAL(id, k)` of NUMBERS and U arrays
//! and `PINVAL(id, k)` replaced by what they stand for, so that a motion stays a function of
//! time (linkage's motions are `f(t)`, differentiated in time by Taylor series).
//!
//! Contract: [`inline_data`] substitutes every such reference (ids written as literals),
//! through chains of VARIABLEs; the result must depend on TIME only. A VARIABLE that depends
//! on the model's state (a measure, a force, a control state), a USER subroutine, an unknown
//! id, a computed id or a cycle of VARIABLEs is an error naming it. Adams plant models use
//! this to drive joints from plant inputs (`MOTION … FUNCTION = VARVAL(3)` with
//! `VARIABLE/3, FUNCTION = 0` or a function of time).

use linkage_expr::{parse, Expr, Function, StateKind};
use linkage_model::forces::ArrayValues;
use linkage_model::Model;

/// The whole number `e` is, if it is one.
fn literal(e: Option<&Expr>) -> Option<u64> {
    match e {
        Some(Expr::Number(v)) if v.fract() == 0.0 && *v >= 0.0 && *v <= 9.0e15 => {
            // Exact: a whole number within f64's exact integer range.
            Some(*v as u64)
        }
        _ => None,
    }
}

/// Why a MOTION function's data references cannot be made a function of time.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MotionDataError {
    #[error("VARIABLE/{0} does not exist")]
    NoVariable(u64),
    #[error("VARIABLE/{0} has no FUNCTION")]
    NoFunction(u64),
    #[error("VARIABLE/{id} ({name}) is a USER subroutine, which linkage cannot run")]
    UserVariable { id: u64, name: String },
    #[error("VARIABLE/{id} ({name}): {message}")]
    Syntax {
        id: u64,
        name: String,
        message: String,
    },
    #[error("{0} with a computed id cannot be resolved")]
    ComputedId(&'static str),
    #[error("{name}({id}, …): the index must be a whole number ≥ 1")]
    Index { name: &'static str, id: u64 },
    #[error("PINPUT/{0} does not exist")]
    NoPinput(u64),
    #[error("PINVAL({id}, {k}): out of range")]
    PinvalRange { id: u64, k: usize },
    #[error("ARRAY/{0} does not exist")]
    NoArray(u64),
    #[error("ARYVAL({id}, {k}): ARRAY/{id} has {len} values")]
    AryvalRange { id: u64, k: usize, len: usize },
    #[error("ARYVAL({0}, …) reads control states or outputs, which change with the model's state")]
    StateArray(u64),
    #[error("VARIABLE/{0} refers to itself through VARVAL")]
    Cycle(u64),
    #[error("in VARIABLE/{variable}: {cause}")]
    Within {
        variable: u64,
        cause: Box<MotionDataError>,
    },
    #[error("it uses a USER subroutine, which linkage cannot run")]
    User,
    #[error(
        "it depends on the model's state (a measure, a force or a control state) through the \
         data elements it uses, while a motion is a function of time"
    )]
    State,
}

/// The expression of VARIABLE `id` of `model`.
fn variable(model: &Model, id: u64) -> Result<Expr, MotionDataError> {
    let v = model
        .variables
        .iter()
        .find(|v| v.origin.id == id)
        .ok_or(MotionDataError::NoVariable(id))?;
    let f = v.function.as_ref().ok_or(MotionDataError::NoFunction(id))?;
    if f.value.user {
        return Err(MotionDataError::UserVariable {
            id,
            name: v.origin.name.clone(),
        });
    }
    parse(&f.value.expr.text).map_err(|e| MotionDataError::Syntax {
        id,
        name: v.origin.name.clone(),
        message: e.message,
    })
}

/// `e` with its data references replaced (module docs); `active` holds the VARIABLEs being
/// expanded (cycle detection).
fn expand(model: &Model, e: &Expr, active: &mut Vec<u64>) -> Result<Expr, MotionDataError> {
    let go = |x: &Expr, active: &mut Vec<u64>| expand(model, x, active).map(Box::new);
    Ok(match e {
        Expr::Number(_)
        | Expr::Degrees(_)
        | Expr::Constant(_)
        | Expr::User(_)
        | Expr::Linked { .. } => e.clone(),
        Expr::Neg(x) => Expr::Neg(go(x, active)?),
        Expr::Binary { op, lhs, rhs } => Expr::Binary {
            op: *op,
            lhs: go(lhs, active)?,
            rhs: go(rhs, active)?,
        },
        Expr::Vector(items) => {
            let [a, b, c] = &**items;
            Expr::Vector(Box::new([
                expand(model, a, active)?,
                expand(model, b, active)?,
                expand(model, c, active)?,
            ]))
        }
        Expr::If { test, lt, eq, gt } => Expr::If {
            test: go(test, active)?,
            lt: go(lt, active)?,
            eq: go(eq, active)?,
            gt: go(gt, active)?,
        },
        Expr::Call {
            func:
                Function::State(kind @ (StateKind::Varval | StateKind::Aryval | StateKind::Pinval)),
            args,
        } => {
            let name = kind.name();
            let id = literal(args.first()).ok_or(MotionDataError::ComputedId(name))?;
            let k = match kind {
                StateKind::Varval => 0,
                _ => literal(args.get(1))
                    .and_then(|k| (k as usize).checked_sub(1))
                    .ok_or(MotionDataError::Index { name, id })?,
            };
            let target = match kind {
                StateKind::Varval => id,
                StateKind::Pinval => {
                    let list = model
                        .controls
                        .pinputs
                        .iter()
                        .find(|l| l.origin.id == id)
                        .ok_or(MotionDataError::NoPinput(id))?;
                    let v = list
                        .variables
                        .get(k)
                        .ok_or(MotionDataError::PinvalRange { id, k: k + 1 })?;
                    model.variables[*v].origin.id
                }
                _ => {
                    let a = model
                        .arrays
                        .iter()
                        .find(|a| a.origin.id == id)
                        .ok_or(MotionDataError::NoArray(id))?;
                    match &a.values {
                        ArrayValues::Numbers(v) => {
                            return v.get(k).map(|x| Expr::Number(*x)).ok_or(
                                MotionDataError::AryvalRange {
                                    id,
                                    k: k + 1,
                                    len: v.len(),
                                },
                            )
                        }
                        ArrayValues::Variables(v) => {
                            let var = v.get(k).ok_or(MotionDataError::AryvalRange {
                                id,
                                k: k + 1,
                                len: v.len(),
                            })?;
                            model.variables[*var].origin.id
                        }
                        ArrayValues::States => return Err(MotionDataError::StateArray(id)),
                    }
                }
            };
            if active.contains(&target) {
                return Err(MotionDataError::Cycle(target));
            }
            active.push(target);
            let inner = expand(model, &variable(model, target)?, active).map_err(|e| {
                MotionDataError::Within {
                    variable: target,
                    cause: Box::new(e),
                }
            })?;
            active.pop();
            inner
        }
        Expr::Call { func, args } => Expr::Call {
            func: *func,
            args: args
                .iter()
                .map(|a| expand(model, a, active))
                .collect::<Result<_, _>>()?,
        },
    })
}

/// `e` with every VARVAL, ARYVAL and PINVAL replaced by its definition (module docs), or why
/// it cannot be a function of time.
pub fn inline_data(model: &Model, e: &Expr) -> Result<Expr, MotionDataError> {
    let mentions = e.any(&mut |x| {
        matches!(
            x,
            Expr::Call {
                func: Function::State(_),
                ..
            }
        )
    });
    if !mentions {
        return Ok(e.clone());
    }
    let out = expand(model, e, &mut Vec::new())?;
    if out.contains_user() {
        return Err(MotionDataError::User);
    }
    if out.uses_state() {
        return Err(MotionDataError::State);
    }
    Ok(out)
}
