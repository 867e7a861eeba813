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

/// The expression of VARIABLE `id` of `model`.
fn variable(model: &Model, id: u64) -> Result<Expr, String> {
    let v = model
        .variables
        .iter()
        .find(|v| v.origin.id == id)
        .ok_or_else(|| format!("VARIABLE/{id} does not exist"))?;
    let f = v
        .function
        .as_ref()
        .ok_or_else(|| format!("VARIABLE/{id} has no FUNCTION"))?;
    if f.value.user {
        return Err(format!(
            "VARIABLE/{id} ({}) is a USER subroutine, which linkage cannot run",
            v.origin.name
        ));
    }
    parse(&f.value.expr.text)
        .map_err(|e| format!("VARIABLE/{id} ({}): {}", v.origin.name, e.message))
}

/// `e` with its data references replaced (module docs); `active` holds the VARIABLEs being
/// expanded (cycle detection).
fn expand(model: &Model, e: &Expr, active: &mut Vec<u64>) -> Result<Expr, String> {
    let go = |x: &Expr, active: &mut Vec<u64>| expand(model, x, active).map(Box::new);
    Ok(match e {
        Expr::Number(_) | Expr::Degrees(_) | Expr::Constant(_) | Expr::User(_) => e.clone(),
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
            let id = literal(args.first())
                .ok_or_else(|| format!("{name} with a computed id cannot be resolved"))?;
            let k = match kind {
                StateKind::Varval => 0,
                _ => literal(args.get(1))
                    .and_then(|k| (k as usize).checked_sub(1))
                    .ok_or_else(|| {
                        format!("{name}({id}, …): the index must be a whole number ≥ 1")
                    })?,
            };
            let target = match kind {
                StateKind::Varval => id,
                StateKind::Pinval => {
                    let list = model
                        .controls
                        .pinputs
                        .iter()
                        .find(|l| l.origin.id == id)
                        .ok_or_else(|| format!("PINPUT/{id} does not exist"))?;
                    let v = list
                        .variables
                        .get(k)
                        .ok_or_else(|| format!("PINVAL({id}, {}): out of range", k + 1))?;
                    model.variables[*v].origin.id
                }
                _ => {
                    let a = model
                        .arrays
                        .iter()
                        .find(|a| a.origin.id == id)
                        .ok_or_else(|| format!("ARRAY/{id} does not exist"))?;
                    match &a.values {
                        ArrayValues::Numbers(v) => {
                            return v.get(k).map(|x| Expr::Number(*x)).ok_or_else(|| {
                                format!(
                                    "ARYVAL({id}, {}): ARRAY/{id} has {} values",
                                    k + 1,
                                    v.len()
                                )
                            })
                        }
                        ArrayValues::Variables(v) => {
                            let var = v.get(k).ok_or_else(|| {
                                format!(
                                    "ARYVAL({id}, {}): ARRAY/{id} has {} values",
                                    k + 1,
                                    v.len()
                                )
                            })?;
                            model.variables[*var].origin.id
                        }
                        ArrayValues::States => {
                            return Err(format!(
                                "ARYVAL({id}, …) reads control states or outputs, which change \
                                 with the model's state"
                            ))
                        }
                    }
                }
            };
            if active.contains(&target) {
                return Err(format!("VARIABLE/{target} refers to itself through VARVAL"));
            }
            active.push(target);
            let inner = expand(model, &variable(model, target)?, active)
                .map_err(|e| format!("in VARIABLE/{target}: {e}"))?;
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
pub fn inline_data(model: &Model, e: &Expr) -> Result<Expr, String> {
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
        return Err("it uses a USER subroutine, which linkage cannot run".into());
    }
    if out.uses_state() {
        return Err(
            "it depends on the model's state (a measure, a force or a control state) through \
             the data elements it uses, while a motion is a function of time"
                .into(),
        );
    }
    Ok(out)
}
