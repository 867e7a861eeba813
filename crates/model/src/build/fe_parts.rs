//! FE_PART, SECTION, MATERIAL, FE_NODE, FE_LOAD and the markers on FE nodes → the model's
//! [`FePart`]s and their node bodies (see [`crate::fe_parts`]).
//!
//! - Node frames: `p = QG + R_BCS·(x, y, z)`, `R = R_BCS·R313(ψ, θ, φ)` (the FE_PART's BCS
//!   from QG/REULER, ground without them).
//! - Elements join consecutive nodes of NODE_LABELS; a zero-length element is an error.
//! - A marker on an FE_PART is fixed on the node it names (`NODE_LABEL`), or on the node
//!   nearest its `S` (snapped, [decided]; the node's S from FE_NODE, else its arc-length
//!   fraction); its QP/REULER are in the FE_PART's BCS and its offset from the node is kept.
//!   Neither given: an error.
//! - FE_NODE must name an existing FE_PART and node (an error otherwise); its S is kept.

use super::context::{origin, v3, Ctx};
use super::markers::MarkerStatements;
use crate::bodies::{Body, Marker, Part};
use crate::fe_parts::{
    FeElement, FeKind, FeLoad, FeNode, FePart, SectionConstants, FE_PART_STATEMENT,
};
use crate::frames::euler313_to_matrix;
use glam::{DMat3, DVec3};
use linkage_adm::fe_part::{type_fe_data, FeData, FeMarkerNode, FePartStatement, FeSections};
use linkage_adm::{Dataset, MarkerCarrier, Severity};

/// Builds every FE part: appends its node bodies to `parts`, re-places the markers on its
/// nodes (in `markers` and `ms.placed`) and returns the parts.
pub(crate) fn fe_parts(
    ds: &Dataset,
    parts: &mut Vec<Part>,
    markers: &mut [Marker],
    ms: &mut MarkerStatements,
    cx: &mut Ctx,
) -> Vec<FePart> {
    let has_fe = ds
        .statements
        .iter()
        .any(|s| matches!(s.keyword.as_str(), "FE_PART" | "FE_LOAD"))
        || ds
            .markers
            .iter()
            .any(|m| matches!(m.carrier, Some(MarkerCarrier::FePart(_))));
    if !has_fe {
        return Vec::new();
    }
    let (data, diagnostics) = type_fe_data(ds);
    for d in diagnostics {
        match d.severity {
            Severity::Error => cx.errors.push(d),
            _ => cx.warnings.push(d),
        }
    }
    let mut out: Vec<FePart> = Vec::with_capacity(data.parts.len());
    for st in &data.parts {
        if out.iter().any(|p| p.origin.id == st.header.id) {
            cx.error(
                st.header.span,
                format!("duplicate FE_PART id {}", st.header.id),
            );
            continue;
        }
        if let Some(p) = fe_part(st, &data, parts, cx) {
            out.push(p);
        }
    }
    node_s_values(&data, &mut out, cx);
    place_markers(ds, &data, &out, parts, markers, ms, cx);
    loads(&data, &mut out, ms, cx);
    out
}

fn fe_part(
    st: &FePartStatement,
    data: &FeData,
    parts: &mut Vec<Part>,
    cx: &mut Ctx,
) -> Option<FePart> {
    let name = &st.header.name;
    let Some(material) = data.materials.iter().find(|m| m.header.id == st.material.id) else {
        cx.error(
            st.material.span,
            format!("{name}: MATERIAL {} does not exist", st.material.id),
        );
        return None;
    };
    let sections: Vec<SectionConstants> = match &st.sections {
        FeSections::PerNode(rows) => rows.iter().map(|(_, c, _)| *c).collect(),
        FeSections::Statement(id) => {
            let Some(s) = data.sections.iter().find(|s| s.header.id == id.id) else {
                cx.error(id.span, format!("{name}: SECTION {} does not exist", id.id));
                return None;
            };
            vec![s.constants; st.nodes.len()]
        }
    };
    let bcs_p = st.qg.as_ref().map_or(DVec3::ZERO, |q| cx.point(name, "QG", q));
    let bcs_r = st
        .reuler
        .as_ref()
        .map_or(DMat3::IDENTITY, |r| euler313_to_matrix(r.value));
    let poses: Vec<(DVec3, DMat3)> = st
        .nodes
        .iter()
        .map(|n| (bcs_p + bcs_r * v3(n.position), bcs_r * euler313_to_matrix(n.angles)))
        .collect();
    let mut elements = Vec::with_capacity(poses.len() - 1);
    for a in 0..poses.len() - 1 {
        let b = a + 1;
        let chord = poses[b].0 - poses[a].0;
        let length = chord.length();
        if length.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !length.is_finite()
        {
            cx.error(
                st.nodes[b].span,
                format!(
                    "{name}: nodes {} and {} coincide (an element needs a length)",
                    st.nodes[a].label, st.nodes[b].label
                ),
            );
            return None;
        }
        let e0 = element_frame(chord / length, poses[a].1, poses[b].1);
        let (sa, sb) = (sections[a], sections[b]);
        elements.push(FeElement {
            a,
            b,
            length,
            section: SectionConstants {
                area: 0.5 * (sa.area + sb.area),
                iyy: 0.5 * (sa.iyy + sb.iyy),
                izz: 0.5 * (sa.izz + sb.izz),
                iyz: 0.5 * (sa.iyz + sb.iyz),
                jxx: 0.5 * (sa.jxx + sb.jxx),
            },
            r_a_e: poses[a].1.transpose() * e0,
            r_b_e: poses[b].1.transpose() * e0,
        });
    }
    let mut tributary = vec![0.0; poses.len()];
    for e in &elements {
        tributary[e.a] += 0.5 * e.length;
        tributary[e.b] += 0.5 * e.length;
    }
    let total: f64 = elements.iter().map(|e| e.length).sum();
    let rho = material.density;
    let cable = st.kind == FeKind::Cable3d;
    let mut nodes = Vec::with_capacity(poses.len());
    let mut arc = 0.0;
    for (n, (p, r)) in poses.iter().enumerate() {
        if n > 0 {
            arc += elements[n - 1].length;
        }
        let s = &sections[n];
        let l = tributary[n];
        let inertia = if cable {
            DMat3::ZERO
        } else {
            let k = rho * l;
            DMat3::from_cols(
                DVec3::new(k * (s.iyy + s.izz), 0.0, 0.0),
                DVec3::new(0.0, k * s.iyy, -k * s.iyz),
                DVec3::new(0.0, -k * s.iyz, k * s.izz),
            )
        };
        let label = st.nodes[n].label;
        let mut o = origin(FE_PART_STATEMENT, &st.header);
        o.name = format!("{name}.node_{label}");
        o.span = st.nodes[n].span;
        nodes.push(FeNode {
            label,
            part: parts.len(),
            s: arc / total,
        });
        parts.push(Part {
            origin: o,
            mass: rho * s.area * l,
            inertia,
            p_gb: *p,
            r_gb: *r,
            p_b_bcs: r.transpose() * (bcs_p - *p),
            velocity: [None; 6],
            r_b_cm: DMat3::IDENTITY,
            exact: Vec::new(),
            point_mass: cable,
        });
    }
    let e = material.youngs_modulus;
    Some(FePart {
        origin: origin(FE_PART_STATEMENT, &st.header),
        kind: st.kind,
        nodes,
        elements,
        tributary,
        density: rho,
        youngs_modulus: e,
        shear_modulus: e / (2.0 * (1.0 + material.poissons_ratio)),
        cratiok: st.cratiok,
        cratiom: st.cratiom,
        loads: Vec::new(),
    })
}

/// The element frame E₀: x along the chord, z ⟂ x and the mean of the node y axes, y = z × x.
/// When the mean y axis is along the chord, the mean z axis fixes the frame instead.
pub fn element_frame(x: DVec3, r_a: DMat3, r_b: DMat3) -> DMat3 {
    let q = r_a.y_axis + r_b.y_axis;
    let z = x.cross(q);
    let z = if z.length() > 1e-9 * q.length().max(1.0) {
        z.normalize()
    } else {
        let y = (r_a.z_axis + r_b.z_axis).cross(x);
        x.cross(y).normalize_or(x.any_orthonormal_vector())
    };
    DMat3::from_cols(x, z.cross(x), z)
}

/// FE_NODE statements: an error for an unknown FE_PART or node; their S kept.
fn node_s_values(data: &FeData, parts: &mut [FePart], cx: &mut Ctx) {
    for n in &data.nodes {
        let Some(p) = parts.iter_mut().find(|p| p.origin.id == n.fe_part.id) else {
            cx.error(
                n.fe_part.span,
                format!("{}: FE_PART {} does not exist", n.header.name, n.fe_part.id),
            );
            continue;
        };
        match p.nodes.iter_mut().find(|x| x.label == n.label) {
            Some(node) => {
                if let Some(s) = n.s {
                    node.s = s;
                }
            }
            None => cx.error(
                n.header.span,
                format!(
                    "{}: {} has no node {}",
                    n.header.name, p.origin.name, n.label
                ),
            ),
        }
    }
}

/// Markers on FE parts: fixed on their node's body, their pose kept.
fn place_markers(
    ds: &Dataset,
    data: &FeData,
    fe: &[FePart],
    parts: &[Part],
    markers: &mut [Marker],
    ms: &mut MarkerStatements,
    cx: &mut Ctx,
) {
    for (k, st) in ms.statements.iter().enumerate() {
        let Some(MarkerCarrier::FePart(r)) = st.carrier else {
            continue;
        };
        let name = &st.header.name;
        let Some(p) = fe.iter().find(|p| p.origin.id == r.id) else {
            if !ds.statements.iter().any(|s| {
                s.keyword == "FE_PART" && s.id == Some(r.id)
            }) {
                cx.error(r.span, format!("{name}: FE_PART {} does not exist", r.id));
            }
            continue;
        };
        let node_ref = data
            .marker_nodes
            .iter()
            .find(|(id, _)| *id == st.header.id)
            .and_then(|(_, n)| n.clone());
        let node = match node_ref {
            Some(FeMarkerNode::Label(l)) => match p.nodes.iter().find(|n| n.label == l.value) {
                Some(n) => n,
                None => {
                    cx.error(
                        l.span,
                        format!("{name}: {} has no node {}", p.origin.name, l.value),
                    );
                    continue;
                }
            },
            Some(FeMarkerNode::S(s)) => {
                let nearest = p.nodes.iter().min_by(|a, b| {
                    (a.s - s.value)
                        .abs()
                        .total_cmp(&(b.s - s.value).abs())
                });
                match nearest {
                    Some(n) => n,
                    None => continue,
                }
            }
            None => {
                cx.error(
                    st.header.span,
                    format!("{name}: a marker on an FE_PART needs NODE_LABEL or S"),
                );
                continue;
            }
        };
        // The marker's pose was placed in the FE_PART's BCS (as if on ground).
        let statement = data.parts.iter().find(|s| s.header.id == r.id);
        let (bcs_p, bcs_r) = statement.map_or((DVec3::ZERO, DMat3::IDENTITY), |s| {
            (
                s.qg.as_ref().map_or(DVec3::ZERO, |q| v3(q.value)),
                s.reuler
                    .as_ref()
                    .map_or(DMat3::IDENTITY, |e| euler313_to_matrix(e.value)),
            )
        });
        let placed = &mut ms.placed[k];
        let p_g = bcs_p + bcs_r * placed.p;
        let r_g = bcs_r * placed.r;
        let body = &parts[node.part];
        let r_t = body.r_gb.transpose();
        placed.body = Body::Part(node.part);
        placed.p = r_t * (p_g - body.p_gb);
        placed.r = r_t * r_g;
        placed.unsupported = None;
        let m = &mut markers[k];
        m.body = Body::Part(node.part);
        m.p_bm = placed.p;
        m.r_bm = placed.r;
    }
}

/// FE_LOAD statements onto their parts (RM resolved).
fn loads(data: &FeData, fe: &mut [FePart], ms: &MarkerStatements, cx: &mut Ctx) {
    for l in &data.loads {
        let Some(p) = fe.iter_mut().find(|p| p.origin.id == l.fe_part.id) else {
            cx.error(
                l.fe_part.span,
                format!("{}: FE_PART {} does not exist", l.header.name, l.fe_part.id),
            );
            continue;
        };
        let rm = match l.rm {
            None => None,
            Some(r) => match ms.index.get(&r.id) {
                Some(&m) => Some(m),
                None => {
                    cx.error(
                        r.span,
                        format!("{}: marker {} does not exist", l.header.name, r.id),
                    );
                    continue;
                }
            },
        };
        p.loads.push(FeLoad {
            origin: origin("FE_LOAD", &l.header),
            rm,
            force: l.force.clone(),
            torque: l.torque.clone(),
            user: l.user.clone(),
        });
    }
}
