//! What expressions read of control states (`DIF`, `DIF1`, `ARYVAL` of X and Y arrays,
//! `PINVAL`, `POUVAL`) and of the sensors (`SENVAL`), kept apart from the state equations ([`crate::physics::controls`]) so
//! that the measures the expressions evaluate through need not depend on those.
//!
//! Numbering of the gradient variables: see [`crate::physics::controls`] (part k's position
//! coordinate c is `6k + c`, its velocity coordinate `6n + 6k + c`, state i `12n + i`, its
//! rate `12n + nx + i`).

use crate::physics::forces::data::{ArrayData, DataElements};
use crate::state::State;
use linkage_expr::{Dual, EvalError, StateRef};

/// The gradient variable of control state `i` (`rate`: of its rate) in a state with `n`
/// parts and `nx` control states.
pub fn state_variable(n: usize, nx: usize, i: usize, rate: bool) -> u32 {
    (12 * n + i + if rate { nx } else { 0 }) as u32
}

/// Value (and gradient) of state `i` or of its rate.
pub(crate) fn state_value(s: &State, i: usize, rate: bool, gradient: bool) -> Dual {
    let c = &s.controls;
    let value = if rate { c.xdot[i] } else { c.x[i] };
    if gradient {
        Dual::variable(value, state_variable(s.poses.len(), c.len(), i, rate))
    } else {
        Dual::constant(value)
    }
}

/// Entry `k` (0-based) of a list of `len`, or the out-of-range error of `NAME(id, k + 1)`.
fn position(name: &str, id: u32, index: u32, len: usize) -> Result<usize, EvalError> {
    let k = (index as usize).saturating_sub(1);
    if index == 0 || k >= len {
        return Err(EvalError::invalid_argument(format!(
            "{name}({id}, {index}): it has {len} values (the index is 1-based)"
        )));
    }
    Ok(k)
}

/// What a state reference other than `VARVAL` reads in `s` (`VARVAL` and `ARYVAL` of a U
/// array call `varval`): `DIF(id)`, `DIF1(id)`, `ARYVAL(id, k)` of every kind of array
/// (NUMBERS, VARIABLES, an X array's states, a Y array's `C x + D u`), `PINVAL`, `POUVAL`.
pub fn read_state(
    data: &DataElements,
    s: &State,
    state: StateRef,
    gradient: bool,
    varval: &dyn Fn(u32, bool) -> Result<Dual, EvalError>,
) -> Result<Dual, EvalError> {
    match state {
        StateRef::Varval(id) => varval(id, gradient),
        StateRef::Senval(id) => {
            let k = *data.sensors.get(&id).ok_or_else(|| {
                EvalError::unknown_reference(format!("SENSOR/{id} does not exist"))
            })?;
            // The value the run stored when the sensor last fired (0 before).
            Ok(Dual::constant(
                s.elements.sensors.get(k).copied().unwrap_or(0.0),
            ))
        }
        StateRef::Dif(id) | StateRef::Dif1(id) => {
            let i = *data
                .diffs
                .get(&id)
                .ok_or_else(|| EvalError::unknown_reference(format!("DIFF/{id} does not exist")))?;
            if i >= s.controls.len() {
                return Err(EvalError::unavailable(format!(
                    "DIFF/{id}: the control states are not part of this analysis"
                )));
            }
            Ok(state_value(
                s,
                i,
                matches!(state, StateRef::Dif1(_)),
                gradient,
            ))
        }
        StateRef::Pinval { id, index } | StateRef::Pouval { id, index } => {
            let (name, list) = match state {
                StateRef::Pinval { .. } => ("PINVAL", data.pinputs.get(&id)),
                _ => ("POUVAL", data.poutputs.get(&id)),
            };
            let list = list.ok_or_else(|| {
                let kind = if name == "PINVAL" {
                    "PINPUT"
                } else {
                    "POUTPUT"
                };
                EvalError::unknown_reference(format!("{kind}/{id} does not exist"))
            })?;
            let k = position(name, id, index, list.len())?;
            varval(list[k], gradient)
        }
        StateRef::Aryval { id, index } => {
            let array = data.arrays.get(&id).ok_or_else(|| {
                EvalError::unknown_reference(format!("ARRAY/{id} does not exist"))
            })?;
            match array {
                ArrayData::Numbers(v) => {
                    let k = position("ARYVAL", id, index, v.len())?;
                    Ok(Dual::constant(v[k]))
                }
                ArrayData::Variables(v) => {
                    let k = position("ARYVAL", id, index, v.len())?;
                    varval(v[k], gradient)
                }
                ArrayData::States { offset, size } => {
                    let k = position("ARYVAL", id, index, *size)?;
                    if offset + k >= s.controls.len() {
                        return Err(EvalError::unavailable(format!(
                            "ARRAY/{id}: the control states are not part of this analysis"
                        )));
                    }
                    Ok(state_value(s, offset + k, false, gradient))
                }
                ArrayData::Outputs(map) => {
                    let k = position("ARYVAL", id, index, map.c.rows.max(map.d.rows))?;
                    let mut y = Dual::constant(0.0);
                    for j in 0..map.c.columns {
                        let c = map.c.get(k, j);
                        if c != 0.0 {
                            if map.offset + j >= s.controls.len() {
                                return Err(EvalError::unavailable(format!(
                                    "ARRAY/{id}: the control states are not part of this \
                                     analysis"
                                )));
                            }
                            y = y + state_value(s, map.offset + j, false, gradient) * c;
                        }
                    }
                    for (j, var) in map.inputs.iter().enumerate() {
                        let d = map.d.get(k, j);
                        if d != 0.0 {
                            y = y + varval(*var, gradient)? * d;
                        }
                    }
                    Ok(y)
                }
                ArrayData::Unowned => Err(EvalError::unavailable(format!(
                    "ARRAY/{id} is an X or Y array that no LSE or TFSISO uses (a GSE's arrays \
                     are filled by USER subroutines, which linkage cannot run)"
                ))),
            }
        }
    }
}
