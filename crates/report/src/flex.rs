//! FLEX_BODY outputs: the dataset's modal coordinates `q = V·η` (`η_j = (P_mode_j − rest)·axis`,
//! V the principal basis or the identity) and their rates
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
        for label in &b.labels {
            out.push(format!("{}.q{label}", b.origin.name));
            out.push(format!("{}.qdot{label}", b.origin.name));
        }
    }
    out
}

/// The dataset's modal coordinates and rates of body `b` (the mode bodies' coordinates
/// through its basis, [`linkage_model::flex_bodies::FlexBody::coordinates`]).
fn coordinates(
    b: &linkage_model::flex_bodies::FlexBody,
    state: &State,
    v: Option<&[(DVec3, DVec3)]>,
) -> (Vec<f64>, Option<Vec<f64>>) {
    let eta: Vec<f64> = b
        .modes
        .iter()
        .map(|m| (state.poses[m.part].p - b.rest).dot(b.axis))
        .collect();
    let rates = v.map(|v| {
        let eta_dot: Vec<f64> = b
            .modes
            .iter()
            .map(|m| v.get(m.part).map_or(0.0, |(v, _)| v.dot(b.axis)))
            .collect();
        b.coordinates(&eta_dot)
    });
    (b.coordinates(&eta), rates)
}

/// The values of [`modal_columns`] at a state with CM velocities `v` (one per part).
pub fn modal_values(model: &Model, state: &State, v: &[(DVec3, DVec3)]) -> Vec<f64> {
    let mut out = Vec::new();
    for b in &model.flex_bodies {
        let (q, qdot) = coordinates(b, state, Some(v));
        let qdot = qdot.unwrap_or_default();
        for (j, x) in q.iter().enumerate() {
            out.push(*x);
            out.push(qdot.get(j).copied().unwrap_or(0.0));
        }
    }
    out
}

/// One modal coordinate in the JSON reports.
#[derive(Clone, Debug, serde::Serialize, PartialEq)]
pub struct ModalJson {
    /// The FLEX_BODY's name.
    pub body: String,
    /// The mode's number (SELMOD).
    pub mode: u64,
    pub q: f64,
    /// `q̇` (absent in static reports).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub qdot: Option<f64>,
}

/// Every modal coordinate at `state` (rates from `v` when given), named after its body.
pub fn modal_json(model: &Model, state: &State, v: Option<&[(DVec3, DVec3)]>) -> Vec<ModalJson> {
    let mut out = Vec::new();
    for b in &model.flex_bodies {
        let (q, qdot) = coordinates(b, state, v);
        for (j, label) in b.labels.iter().enumerate() {
            out.push(ModalJson {
                body: b.origin.name.clone(),
                mode: *label,
                q: q[j],
                qdot: qdot.as_ref().map(|d| d[j]),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    /// One mode (k = 4, m = 1: ω = 2) moving node 1 along y; DMODE = 0.5, VMODE = 3; the BCS
    /// at (1, 2, 3) so that the mode body's position is not the coordinate.
    const ONE_MODE: &str = "t\nPART/1, GROUND\n\
        FLEX_BODY/1, MATRICES = 2, 3, 4, 5, 6, 7, 8, QG = 1, 2, 3, DMODE = 0.5, VMODE = 3\n\
        !adams_view_name='FLEX_BODY_1.SELNOD'\nMATRIX/2, FULL = RORDER, ROWS = 1, COLUMNS = 4, VALUES = 7, 1, 0, 0\n\
        !adams_view_name='GENSTIFF'\nMATRIX/3, FULL = RORDER, ROWS = 1, COLUMNS = 1, VALUES = 4\n\
        !adams_view_name='INVAR1'\nMATRIX/4, FULL = RORDER, ROWS = 1, COLUMNS = 1, VALUES = 2\n\
        !adams_view_name='INVAR2'\nMATRIX/5, FULL = RORDER, ROWS = 3, COLUMNS = 1, VALUES = 1, 0, 0\n\
        !adams_view_name='INVAR6'\nMATRIX/6, FULL = RORDER, ROWS = 1, COLUMNS = 1, VALUES = 1\n\
        !adams_view_name='INVAR7'\nMATRIX/7, FULL = RORDER, ROWS = 3, COLUMNS = 3, VALUES = 1, 0, 0, 0, 1, 0, 0, 0, 1\n\
        !adams_view_name='T_MODES'\nMATRIX/8, FULL = RORDER, ROWS = 3, COLUMNS = 1, VALUES = 0, 1, 0\n\
        MARKER/9, FLEX_BODY = 1, NODE_ID = 7\nEND\n";

    #[test]
    fn modal_coordinates_are_measured_from_rest_along_the_guide() {
        let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), ONE_MODE).unwrap();
        let m = linkage_model::build_model(&ds)
            .unwrap_or_else(|e| panic!("{e}"))
            .model;
        let s = State::input(&m);
        let b = &m.flex_bodies[0];
        assert_eq!(b.modes[0].frequency, 2.0 / std::f64::consts::TAU);
        // The mode body sits at the BCS origin + 0.5 along the guide.
        assert!((s.poses[b.modes[0].part].p - DVec3::new(1.0, 2.0, 3.5)).length() < 1e-15);
        let v: Vec<(DVec3, DVec3)> = m
            .parts
            .iter()
            .map(|p| {
                let v = p.velocity.map(|x| x.unwrap_or(0.0));
                (DVec3::new(v[0], v[1], v[2]), DVec3::ZERO)
            })
            .collect();
        assert_eq!(modal_columns(&m), ["FLEX_BODY_1.q1", "FLEX_BODY_1.qdot1"]);
        assert_eq!(modal_values(&m, &s, &v), [0.5, 3.0]);
        let j = modal_json(&m, &s, None);
        assert_eq!(
            (j[0].body.as_str(), j[0].mode, j[0].q, j[0].qdot),
            ("FLEX_BODY_1", 1, 0.5, None)
        );
        // The node body is at QG + (1, 0, 0) + Φ·q = (2, 2.5, 3).
        let node = b.nodes[0].part;
        assert!((s.poses[node].p - DVec3::new(2.0, 2.5, 3.0)).length() < 1e-15);
    }
}
