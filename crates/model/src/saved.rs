//! A configuration of the model → the changes of the dataset text that make it read back at
//! that configuration (`ic --save`, `static --save`).
//!
//! What is written [decided; Adams' own file of a moved FE or flexible body is not on the
//! pages seen]:
//! - a moved PART or POINT_MASS: its `QG`/`REULER` (the writer's part poses);
//! - a FLEX_BODY: `QG`/`REULER` of its BCS when the reference body moved, and `DMODE`, one
//!   modal coordinate per mode of the dataset (`q = V·η`, `η_j = (p_mode − rest)·axis`), when a
//!   mode moved. Markers on
//!   its nodes keep their QP/REULER: they are given from the node's undeformed place, which
//!   SELNOD keeps, and DMODE carries the deformation;
//! - an FE_PART: `COORDINATES` with every node's place and 3-1-3 angles (radians) in the
//!   FE_PART's BCS (the labels kept), and every marker on its nodes with its new `QP` and
//!   `REULER` (or `XP`/`ZP` when it was given by points) in that BCS, because a marker's
//!   pose on an FE_PART is read in the BCS and its offset from its node is what is kept.
//!   FE_NODE statements (Adams View's bookkeeping, not read for the geometry) are kept as
//!   read. The beam elements' reference lengths come from the new COORDINATES when read
//!   again: a saved deflected beam is a new, unstressed design, as a saved assembly is.

use crate::fe_parts::FePart;
use crate::frames::{euler313_to_matrix, matrix_to_euler313};
use crate::model::Model;
use glam::{DMat3, DVec3};
use linkage_adm::statement::Value;
use linkage_adm::writer::{ArgumentValues, NewValue, PartPose};
use linkage_adm::{Dataset, MarkerCarrier};

/// What the dataset needs to read back at a configuration.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SavedChanges {
    pub parts: Vec<PartPose>,
    pub arguments: Vec<ArgumentValues>,
}

/// The changes of `ds` (the dataset `model` was built from) for the configuration `poses`
/// (every part of the model: the position of its centre of mass and its axes in ground).
pub fn saved_changes(ds: &Dataset, model: &Model, poses: &[(DVec3, DMat3)]) -> SavedChanges {
    let mut out = SavedChanges::default();
    let moved = |k: usize| {
        let p = &model.parts[k];
        (poses[k].0 - p.p_gb).length() > 0.0 || poses[k].1 != p.r_gb
    };
    for (k, p) in model.parts.iter().enumerate() {
        if model.fe_node(k).is_some() || model.flex_body_of(k).is_some() || !moved(k) {
            continue;
        }
        let (x, r) = poses[k];
        out.parts.push(PartPose {
            statement: p.origin.statement_index,
            qg: (x + r * p.p_b_bcs).to_array(),
            reuler: matrix_to_euler313(&r),
        });
    }
    for b in &model.flex_bodies {
        let statement = b.origin.statement_index;
        if moved(b.reference) {
            let (x, r) = poses[b.reference];
            out.arguments
                .push(point(statement, "QG", x + r * b.bcs_in_body));
            out.arguments.push(angles(statement, "REULER", &r));
        }
        if b.modes.iter().any(|m| moved(m.part)) {
            let eta: Vec<f64> = b
                .modes
                .iter()
                .map(|m| (poses[m.part].0 - b.rest).dot(b.axis))
                .collect();
            let q = b
                .coordinates(&eta)
                .into_iter()
                .map(NewValue::Scaled)
                .collect();
            out.arguments.push(ArgumentValues {
                statement,
                key: "DMODE".into(),
                values: q,
            });
        }
    }
    for fe in &model.fe_parts {
        if fe.nodes.iter().any(|n| moved(n.part)) {
            fe_part(ds, model, fe, poses, &mut out.arguments);
        }
    }
    out
}

/// The COORDINATES of an FE_PART and the poses of the markers on its nodes.
fn fe_part(
    ds: &Dataset,
    model: &Model,
    fe: &FePart,
    poses: &[(DVec3, DMat3)],
    out: &mut Vec<ArgumentValues>,
) {
    let statement = fe.origin.statement_index;
    let Some(st) = ds.statements.get(statement) else {
        return;
    };
    let vector = |key: &str| {
        let a = st.arg(key)?;
        let v: Vec<f64> = a
            .values
            .iter()
            .filter_map(|v| match v {
                Value::Number { value, .. } => Some(*value),
                _ => None,
            })
            .collect();
        (v.len() == 3).then(|| DVec3::new(v[0], v[1], v[2]))
    };
    let bcs_p = vector("QG").unwrap_or(DVec3::ZERO);
    let bcs_r = vector("REULER").map_or(DMat3::IDENTITY, |e| euler313_to_matrix(e.to_array()));
    let in_bcs = |(x, r): (DVec3, DMat3)| (bcs_r.transpose() * (x - bcs_p), bcs_r.transpose() * r);
    // The first COORDINATES is what the reader takes; a repeated one is rewritten alike by
    // the writer.
    if let Some(arg) = st.arg("COORDINATES") {
        let mut values = Vec::with_capacity(arg.values.len());
        for row in arg.values.chunks(7) {
            let node = match row.first() {
                Some(Value::Number { value, .. }) if row.len() == 7 => {
                    fe.nodes.iter().find(|n| n.label as f64 == *value)
                }
                _ => None,
            };
            let Some(node) = node else {
                // Not a node row the reader took: written as read.
                values.extend(row.iter().map(|_| NewValue::Keep));
                continue;
            };
            let (x, r) = in_bcs(poses[node.part]);
            values.push(NewValue::Keep);
            values.extend(x.to_array().map(NewValue::Number));
            values.extend(matrix_to_euler313(&r).map(NewValue::Number));
        }
        out.push(ArgumentValues {
            statement,
            key: "COORDINATES".into(),
            values,
        });
    }
    for m in &ds.markers {
        if !matches!(m.carrier, Some(MarkerCarrier::FePart(r)) if r.id == fe.origin.id) {
            continue;
        }
        let Some(mk) = model.markers.iter().find(|k| k.id == m.header.id) else {
            continue;
        };
        let crate::bodies::Body::Part(k) = mk.body else {
            continue;
        };
        let (x, r) = poses[k];
        let (qp, axes) = in_bcs((x + r * mk.p_bm, r * mk.r_bm));
        let statement = m.header.statement;
        out.push(point(statement, "QP", qp));
        if m.reuler.is_none() && (m.xp.is_some() || m.zp.is_some()) {
            out.push(point(statement, "ZP", qp + axes.z_axis));
            out.push(point(statement, "XP", qp + axes.x_axis));
        } else {
            out.push(angles(statement, "REULER", &axes));
        }
    }
}

fn point(statement: usize, key: &str, p: DVec3) -> ArgumentValues {
    ArgumentValues {
        statement,
        key: key.into(),
        values: p.to_array().map(NewValue::Number).to_vec(),
    }
}

fn angles(statement: usize, key: &str, r: &DMat3) -> ArgumentValues {
    ArgumentValues {
        statement,
        key: key.into(),
        values: matrix_to_euler313(r).map(NewValue::Degrees).to_vec(),
    }
}
