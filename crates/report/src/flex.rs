//! FLEX_BODY outputs: the modal coordinates `q_j = (P_mode_j − rest)·axis` and their rates
//! (`linkage_model::flex_bodies`), as CSV columns named after the body:
//! `<body>.q<mode>` and `<body>.qdot<mode>`, per mode in SELMOD order. The node bodies'
//! positions are ordinary part columns (`<body>.node_<id>.x …`).

use glam::DVec3;
use linkage_model::Model;
use linkage_solve::state::State;

/// The column names, `q` then `qdot` for each mode of each flex body.
pub fn modal_columns(model: &Model) -> Vec<String> {
    let mut out = Vec::new();
    for b in &model.flex_bodies {
        for m in &b.modes {
            out.push(format!("{}.q{}", b.origin.name, m.label));
            out.push(format!("{}.qdot{}", b.origin.name, m.label));
        }
    }
    out
}

/// The values of [`modal_columns`] at a state with CM velocities `v` (one per part).
pub fn modal_values(model: &Model, state: &State, v: &[(DVec3, DVec3)]) -> Vec<f64> {
    let mut out = Vec::new();
    for b in &model.flex_bodies {
        for m in &b.modes {
            out.push((state.poses[m.part].p - b.rest).dot(b.axis));
            out.push(v.get(m.part).map_or(0.0, |(v, _)| v.dot(b.axis)));
        }
    }
    out
}
