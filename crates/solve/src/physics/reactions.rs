//! Reaction forces of constraint elements from their multipliers.
//!
//! With equations of motion or equilibrium written `… − Jᵀλ = 0`, the generalised constraint
//! force of row r on the parts is `−λ_r ∇Φ_r`; an element's reaction on its I marker is the sum
//! over its rows on the I marker's part, with the torque moved from the part's centre of mass to
//! the I marker origin. When the I marker is on ground, the reaction is minus the wrench on the
//! parts the element acts on (a joint's J part; every part a general constraint's expression
//! measures), taken about the same point.

use crate::constraints::rows::RowGradient;
use crate::constraints::system::System;
use crate::state::State;
use glam::DVec3;
use linkage_model::{Body, ConstraintKind, Model};

/// Reaction of an element on its I marker: force and torque about the I marker origin, in
/// ground axes, in model force and force × length units.
#[derive(Clone, Debug, PartialEq)]
pub struct Reaction {
    pub element: usize,
    pub force: DVec3,
    pub torque: DVec3,
}

/// Reactions of every joint, primitive, motion and general constraint (not the point masses'
/// rotation holds, which carry no load: no torque acts on a point mass). `rows` are the rows in the solve with their
/// gradients at `s`, `lambda` their multipliers in model force units. Rows not in the solve
/// (redundant ones) carry zero, as in Adams.
pub fn element_reactions(
    model: &Model,
    sys: &System,
    rows: &[(usize, &RowGradient)],
    lambda: &[f64],
    s: &State,
) -> Vec<Reaction> {
    let mut per_element: Vec<Vec<(usize, [f64; 6])>> = vec![Vec::new(); model.constraints.len()];
    for ((r, grad), mu) in rows.iter().zip(lambda) {
        let list = &mut per_element[sys.rows[*r].element];
        for (body, b) in &grad.blocks {
            let slot = match list.iter().position(|(k, _)| k == body) {
                Some(p) => p,
                None => {
                    list.push((*body, [0.0; 6]));
                    list.len() - 1
                }
            };
            for (a, x) in list[slot].1.iter_mut().zip(b) {
                *a -= mu * x;
            }
        }
    }
    let mut reactions = Vec::new();
    for (c, con) in model.constraints.iter().enumerate() {
        if !matches!(
            con.kind,
            ConstraintKind::Joint { .. }
                | ConstraintKind::Jprim { .. }
                | ConstraintKind::Motion { .. }
                | ConstraintKind::Gcon { .. }
                | ConstraintKind::Ptcv(_)
                | ConstraintKind::Cvcv(_)
        ) || linkage_model::build::point_masses::is_rotation_hold(con)
            || con.origin.statement == linkage_model::flex_bodies::FLEX_BODY_STATEMENT
        {
            continue;
        }
        // A general constraint acts on its I marker's part (and whatever its expression
        // measures); its reaction is reported on the I marker.
        let i = match &con.kind {
            ConstraintKind::Gcon { i, .. } => *i,
            _ => match con.markers() {
                Some((i, _)) => i,
                None => continue,
            },
        };
        let p_i = {
            let mk = &model.markers[i];
            let pose = s.pose(mk.body);
            pose.p + pose.r * mk.p_bm
        };
        let wrench_on = |body: Body| -> Option<(DVec3, DVec3)> {
            let k = body.part()?;
            let six = per_element[c]
                .iter()
                .find(|(b, _)| *b == k)
                .map(|(_, x)| *x)
                .unwrap_or([0.0; 6]);
            let f = DVec3::new(six[0], six[1], six[2]);
            let t_cm = DVec3::new(six[3], six[4], six[5]);
            Some((f, t_cm + (s.poses[k].p - p_i).cross(f)))
        };
        // On ground, the I marker carries minus the wrench on every part the element acts on
        // (a joint's J part; the parts a general constraint measures), about the I marker.
        let (force, torque) = match wrench_on(model.markers[i].body) {
            Some(w) => w,
            None => per_element[c]
                .iter()
                .filter_map(|(k, _)| wrench_on(Body::Part(*k)))
                .fold((DVec3::ZERO, DVec3::ZERO), |(f, t), (df, dt)| {
                    (f - df, t - dt)
                }),
        };
        reactions.push(Reaction {
            element: c,
            force,
            torque,
        });
    }
    reactions
}
