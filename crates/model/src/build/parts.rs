//! `PART/` and `POINT_MASS/`: ground and the moving bodies, and each moving body's BCS (body
//! coordinate system) in ground.

use super::context::Ctx;
use crate::bodies::Body;
use crate::frames::{euler313_to_matrix, frame_from_points};
use glam::{DMat3, DVec3};
use linkage_adm::{Dataset, Diagnostic, Span};
use std::collections::HashMap;

/// The PART statements sorted into ground and moving parts, with the moving parts' BCS.
pub(crate) struct PartStatements<'d> {
    /// The GROUND part (`None`: the dataset has none, an error was reported).
    pub ground: Option<&'d linkage_adm::Part>,
    /// Part id → the body it is ([`Body::Part`] indexes `moving`).
    pub index: HashMap<u64, Body>,
    /// POINT_MASS id → the body it is (its own id space: `PART/4` and `POINT_MASS/4` differ).
    pub point_mass_index: HashMap<u64, Body>,
    /// Moving parts in definition order, then the point masses in definition order.
    pub moving: Vec<&'d linkage_adm::Part>,
    /// How many of `moving` are PART statements (the rest are point masses).
    pub rigid: usize,
    /// BCS of each moving part in ground: origin `QG` and axes `R_G_bcs`.
    pub bcs: Vec<(DVec3, DMat3)>,
}

impl PartStatements<'_> {
    /// Display name of ground (`ground` when the dataset has no GROUND part).
    pub fn ground_name(&self) -> String {
        self.ground
            .map_or("ground".to_string(), |g| g.header.name.clone())
    }
}

/// Sorts the parts and places their BCS. Errors: a duplicate id, a second GROUND part, no
/// GROUND part, a ZG that coincides with QG.
pub(crate) fn parts<'d>(ds: &'d Dataset, cx: &mut Ctx) -> PartStatements<'d> {
    let mut ground: Option<&linkage_adm::Part> = None;
    let mut index: HashMap<u64, Body> = HashMap::with_capacity(ds.parts.len());
    let mut moving = Vec::new();
    for p in &ds.parts {
        if index.contains_key(&p.header.id) {
            cx.error(p.header.span, format!("duplicate PART id {}", p.header.id));
            continue;
        }
        if p.ground {
            if let Some(g) = ground {
                cx.error(
                    p.header.span,
                    format!(
                        "second GROUND part '{}' (the first is '{}' at line {})",
                        p.header.name, g.header.name, g.header.span.line
                    ),
                );
                continue;
            }
            ground = Some(p);
            index.insert(p.header.id, Body::Ground);
        } else {
            index.insert(p.header.id, Body::Part(moving.len()));
            moving.push(p);
        }
    }
    let rigid = moving.len();
    let mut point_mass_index: HashMap<u64, Body> = HashMap::new();
    for p in &ds.point_masses {
        if point_mass_index.contains_key(&p.header.id) {
            cx.error(
                p.header.span,
                format!("duplicate POINT_MASS id {}", p.header.id),
            );
            continue;
        }
        point_mass_index.insert(p.header.id, Body::Part(moving.len()));
        moving.push(p);
    }
    if ground.is_none() {
        // Placed at the first PART (where a GROUND part is expected), or at line 1.
        let at = ds.parts.first().map_or(Span::new(1, 1), |p| p.header.span);
        cx.errors.push(
            Diagnostic::error(ds.file.clone(), Some(at), "the dataset has no GROUND part")
                .with_hint("add `PART/1, GROUND` before the other parts"),
        );
    }
    let bcs = moving.iter().map(|p| bcs_in_ground(p, cx)).collect();
    PartStatements {
        ground,
        index,
        point_mass_index,
        moving,
        rigid,
        bcs,
    }
}

/// A part's BCS in ground: origin `QG` (0 when not given) and axes from `REULER` (3-1-3
/// angles), else from the points `ZG` (on +z) and `XG` (in the x-z plane), else ground's.
fn bcs_in_ground(p: &linkage_adm::Part, cx: &mut Ctx) -> (DVec3, DMat3) {
    let name = &p.header.name;
    let qg =
        p.qg.as_ref()
            .map_or(DVec3::ZERO, |q| cx.point(name, "QG", q));
    let r = if let Some(e) = &p.reuler {
        euler313_to_matrix(e.value)
    } else if p.zg.is_some() || p.xg.is_some() {
        match frame_from_points(
            qg,
            p.zg.as_ref().map(|z| cx.point(name, "ZG", z)),
            p.xg.as_ref().map(|x| cx.point(name, "XG", x)),
        ) {
            Some(r) => r,
            None => {
                let span = p.zg.as_ref().map_or(p.header.span, |z| z.span);
                cx.error(
                    span,
                    format!(
                        "{}: ZG coincides with QG, the part's z axis is undefined",
                        p.header.name
                    ),
                );
                DMat3::IDENTITY
            }
        }
    } else {
        DMat3::IDENTITY
    };
    (qg, r)
}

#[cfg(test)]
mod tests {
    use crate::build::test_support::{build_text, errors_in_order};
    use glam::DVec3;

    #[test]
    fn bcs_from_reuler_and_from_zg_xg() {
        let b = build_text("t\nPART/1, GROUND\nPART/2, QG = 1, 2, 3, REULER = 90D, 0, 0\nPART/3, QG = 0, 0, 1, ZG = 1, 0, 1, XG = 0, 0, 5\nEND\n")
            .unwrap_or_else(|e| panic!("{e}"));
        let m = &b.model;
        assert_eq!(m.ground_name, "PART_1");
        // No CM marker: the body frame is the BCS.
        assert_eq!(m.parts[0].p_gb, DVec3::new(1.0, 2.0, 3.0));
        // ψ = 90° about z: x_B along ground y.
        assert!((m.parts[0].r_gb.x_axis - DVec3::Y).length() < 1e-15);
        // ZG on +x from QG: z_B = ground x; XG straight above QG: x_B = ground z.
        assert!((m.parts[1].r_gb.z_axis - DVec3::X).length() < 1e-15);
        assert!((m.parts[1].r_gb.x_axis - DVec3::Z).length() < 1e-15);
        assert_eq!(m.parts[1].p_gb, DVec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn ground_must_be_given_once_and_part_ids_unique() {
        let e = errors_in_order("t\nPART/1, GROUND\nPART/2, GROUND\nPART/1, MASS = 1\nPART/3, QG = 1, 1, 1, ZG = 1, 1, 1\nEND\n");
        let messages: Vec<&str> = e.iter().map(|(_, _, m)| m.as_str()).collect();
        assert_eq!(
            messages,
            [
                "second GROUND part 'PART_2' (the first is 'PART_1' at line 2)",
                "duplicate PART id 1",
                "PART_3: ZG coincides with QG, the part's z axis is undefined",
            ]
        );
        assert_eq!((e[2].0, e[2].1), (5, 23));
        let e = errors_in_order("t\nPART/2, MASS = 1\nEND\n");
        assert_eq!(e, [(2, 1, "the dataset has no GROUND part".to_string())]);
    }
}
