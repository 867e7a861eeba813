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
use linkage_adm::fe_part::{type_fe_data, FeData, FePartStatement, FeSections};
use linkage_adm::FeMarkerNode;
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
    let Some(material) = data
        .materials
        .iter()
        .find(|m| m.header.id == st.material.id)
    else {
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
    let bcs_p = st
        .qg
        .as_ref()
        .map_or(DVec3::ZERO, |q| cx.point(name, "QG", q));
    let bcs_r = st
        .reuler
        .as_ref()
        .map_or(DMat3::IDENTITY, |r| euler313_to_matrix(r.value));
    let poses: Vec<(DVec3, DMat3)> = st
        .nodes
        .iter()
        .map(|n| {
            (
                bcs_p + bcs_r * v3(n.position),
                bcs_r * euler313_to_matrix(n.angles),
            )
        })
        .collect();
    let mut elements = Vec::with_capacity(poses.len() - 1);
    for a in 0..poses.len() - 1 {
        let b = a + 1;
        let chord = poses[b].0 - poses[a].0;
        let length = chord.length();
        if length.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !length.is_finite() {
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
            if !ds
                .statements
                .iter()
                .any(|s| s.keyword == "FE_PART" && s.id == Some(r.id))
            {
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
                let nearest = p
                    .nodes
                    .iter()
                    .min_by(|a, b| (a.s - s.value).abs().total_cmp(&(b.s - s.value).abs()));
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

#[cfg(test)]
mod tests {
    use crate::build::test_support::{errors, ok};
    use crate::Body;
    use glam::DVec3;

    /// Three nodes along the BCS x axis (1 m elements), the BCS at (1, 2, 3) turned 90° about
    /// z; markers on node 3 (with an offset), at S = 0.45 and on node 1.
    const BEAM: &str =
        "FE_PART/7, TYPE = 3DBEAM, NODE_LABELS = 1, 2, 3, QG = 1, 2, 3, REULER = 90D, 0, 0\n\
        , COORDINATES = 1, 0, 0, 0, 0, 0, 0, 2, 1, 0, 0, 0, 0, 0, 3, 2, 0, 0, 0, 0, 0\n\
        , SECTION = 4, MATERIAL = 5\n\
        SECTION/4, AREA = 2, IYY = 3, IZZ = 1, JXX = 4\n\
        MATERIAL/5, DENSITY = 10, YOUNGS_MODULUS = 100, POISSONS_RATIO = 0.25\n\
        MARKER/70, FE_PART = 7, NODE_LABEL = 3, QP = 2, 0.5, 0\n\
        MARKER/71, FE_PART = 7, S = 0.45\nMARKER/72, FE_PART = 7, NODE_LABEL = 1";

    #[test]
    fn nodes_are_bodies_with_lumped_mass_and_markers_ride_on_them() {
        let b = ok(BEAM);
        let m = &b.model;
        let p = &m.fe_parts[0];
        assert_eq!(p.nodes.len(), 3);
        assert_eq!(p.elements.len(), 2);
        assert_eq!(p.shear_modulus, 40.0);
        // Node 2 at QG + R·(1, 0, 0) = (1, 3, 3); half of each adjacent element: m = ρ·A·1.
        let n2 = &m.parts[p.nodes[1].part];
        assert_eq!(n2.origin.name, "FE_PART_7.node_2");
        assert!((n2.p_gb - DVec3::new(1.0, 3.0, 3.0)).length() < 1e-12);
        assert!((n2.mass - 20.0).abs() < 1e-12);
        // Rotary inertia ρ·ΣL/2·(Iyy + Izz, Iyy, Izz).
        assert!((n2.inertia.x_axis.x - 40.0).abs() < 1e-12);
        assert!((n2.inertia.y_axis.y - 30.0).abs() < 1e-12);
        assert!((m.parts[p.nodes[0].part].mass - 10.0).abs() < 1e-12);
        // Marker 70 on node 3 keeps its offset (0, 0.5, 0) in the BCS = (−0.5, 0, 0) in ground.
        let k70 = m.markers.iter().position(|x| x.id == 70).unwrap();
        assert_eq!(m.markers[k70].body, Body::Part(p.nodes[2].part));
        let (pg, _) = m.marker_in_ground(k70);
        assert!((pg - DVec3::new(0.5, 4.0, 3.0)).length() < 1e-12, "{pg:?}");
        // S = 0.45 snaps to node 2 (S = 0.5).
        let k71 = m.markers.iter().position(|x| x.id == 71).unwrap();
        assert_eq!(m.markers[k71].body, Body::Part(p.nodes[1].part));
        assert_eq!(m.fe_marker_nodes(0), [0, 1, 2]);
        assert_eq!(m.fe_node(p.nodes[2].part), Some((0, 2)));
        assert_eq!(m.fe_node(0), None);
    }

    #[test]
    fn fe_reference_errors_name_the_statement() {
        let e = errors(&BEAM.replace("MATERIAL = 5", "MATERIAL = 6"));
        assert!(
            e.iter().any(|x| x.2.contains("MATERIAL 6 does not exist")),
            "{e:?}"
        );
        let e = errors(&BEAM.replace("NODE_LABEL = 3, QP", "NODE_LABEL = 9, QP"));
        assert!(e.iter().any(|x| x.2.contains("has no node 9")), "{e:?}");
        let e = errors(&format!("{BEAM}\nMARKER/73, FE_PART = 7"));
        assert!(
            e.iter().any(|x| x.2.contains("needs NODE_LABEL or S")),
            "{e:?}"
        );
        let e = errors(&BEAM.replace("2, 1, 0, 0, 0, 0, 0, 3", "2, 0, 0, 0, 0, 0, 0, 3"));
        assert!(e.iter().any(|x| x.2.contains("coincide")), "{e:?}");
        let e = errors(&format!("{BEAM}\nFE_NODE/1, FE_PART = 8, LABEL = 1"));
        assert!(
            e.iter().any(|x| x.2.contains("FE_PART 8 does not exist")),
            "{e:?}"
        );
    }
}
