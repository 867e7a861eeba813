//! The six equations of a FLEX_BODY node ([`linkage_model::flex_bodies`]): the node body's
//! frame follows the reference body (BCS axes `A`, origin `x`) and the modal coordinates
//! `q_j = (P_mode_j − rest)·axis` (the mode bodies' positions along their guide):
//!
//! - translation, k = x, y, z of the BCS: `(P_node − (x + A s_P))·A e_k − Σ_j Φ_Pj,k q_j = 0`;
//! - rotation (first order in the node's small rotation `θ = Φ*_P q` from the BCS axes, the
//!   orientation primitive's three dot products): `z_n·x_b − θ_y = 0`, `z_n·y_b + θ_x = 0`,
//!   `x_n·y_b − θ_z = 0`.
//!
//! Every term is a primitive quantity (a projection or a dot product), so the Jacobian (the
//! modal columns included: `−Φ_Pj,k` on mode body j's translation along the axis), the
//! velocity-product terms and the Hessians are those of the primitive rows.

use crate::constraints::rows::{BodyDir, BodyPoint, Quantity};
use crate::constraints::system::{RowUnit, Tier};
use glam::DVec3;
use linkage_model::{Body, Model};

/// One node equation: labels, unit, tier and terms `Σ c Q`.
pub struct NodeRow {
    pub label: &'static str,
    pub short: &'static str,
    pub unit: RowUnit,
    pub tier: Tier,
    pub terms: Vec<(f64, Quantity)>,
}

const LABELS: [(&str, &str); 6] = [
    ("Translation of Flex Node Along Xb", "Node.Xb"),
    ("Translation of Flex Node Along Yb", "Node.Yb"),
    ("Translation of Flex Node Along Zb", "Node.Zb"),
    ("Rotation of Flex Node: Zn & Xb", "Zn.Xb"),
    ("Rotation of Flex Node: Zn & Yb", "Zn.Yb"),
    ("Rotation of Flex Node: Xn & Yb", "Xn.Yb"),
];

/// The six equations of node `node` of flex body `body`.
pub fn node_rows(model: &Model, body: usize, node: usize) -> Vec<NodeRow> {
    let b = &model.flex_bodies[body];
    let n = &b.nodes[node];
    let reference = Body::Part(b.reference);
    let node_body = Body::Part(n.part);
    let bcs_axis = |k: usize| BodyDir {
        body: reference,
        v_b: DVec3::AXES[k],
    };
    let node_axis = |k: usize| BodyDir {
        body: node_body,
        v_b: DVec3::AXES[k],
    };
    // q_j: the mode body's origin from its rest point, along the guide.
    let coordinate = |j: usize| Quantity::Proj {
        i: BodyPoint {
            body: Body::Part(b.modes[j].part),
            p_b: DVec3::ZERO,
        },
        j: BodyPoint {
            body: Body::Ground,
            p_b: b.rest,
        },
        e: BodyDir {
            body: Body::Ground,
            v_b: b.axis,
        },
    };
    let modal = |terms: &mut Vec<(f64, Quantity)>, c: &dyn Fn(usize) -> f64| {
        for j in 0..b.modes.len() {
            let cj = c(j);
            if cj != 0.0 {
                terms.push((cj, coordinate(j)));
            }
        }
    };
    let mut out = Vec::with_capacity(6);
    for (k, (label, short)) in LABELS[..3].iter().enumerate() {
        let mut terms = vec![(
            1.0,
            Quantity::Proj {
                i: BodyPoint {
                    body: node_body,
                    p_b: DVec3::ZERO,
                },
                j: BodyPoint {
                    body: reference,
                    p_b: b.bcs_in_body + n.position,
                },
                e: bcs_axis(k),
            },
        )];
        modal(&mut terms, &|j| -n.translation[j][k]);
        out.push(NodeRow {
            label,
            short,
            unit: RowUnit::Length,
            tier: Tier::Translation,
            terms,
        });
    }
    // (node axis, BCS axis, rotation component, sign of θ in the row).
    let rotations = [(2, 0, 1, -1.0), (2, 1, 0, 1.0), (0, 1, 2, -1.0)];
    for (r, (a, c, comp, sign)) in rotations.into_iter().enumerate() {
        let mut terms = vec![(1.0, Quantity::Dot(node_axis(a), bcs_axis(c)))];
        modal(&mut terms, &|j| sign * n.rotation[j][comp]);
        out.push(NodeRow {
            label: LABELS[3 + r].0,
            short: LABELS[3 + r].1,
            unit: RowUnit::Direction,
            tier: Tier::Rotation,
            terms,
        });
    }
    out
}
