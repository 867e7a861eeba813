//! `MARKER/`: each marker on its carrier, placed in the carrier's BCS (QP/REULER or ZP/XP,
//! possibly given in a reference marker RM of the same part).

use super::context::Ctx;
use super::parts::PartStatements;
use crate::bodies::Body;
use crate::frames::{euler313_to_matrix, frame_from_points};
use glam::{DMat3, DVec3};
use linkage_adm::{Dataset, MarkerCarrier};
use std::collections::HashMap;

/// A marker placed in its part's BCS (in ground for ground markers), before the centre of
/// mass is known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PlacedMarker {
    pub body: Body,
    /// Origin in the BCS (in ground for ground markers).
    pub p: DVec3,
    /// Axes in the BCS.
    pub r: DMat3,
    /// The carrier linkage does not model (FLEX_BODY, FE_PART), if any.
    pub unsupported: Option<&'static str>,
}

/// The markers of the dataset (duplicates left out), in definition order.
pub(crate) struct MarkerStatements<'d> {
    /// Marker id → index into `placed` and `statements`.
    pub index: HashMap<u64, usize>,
    pub placed: Vec<PlacedMarker>,
    pub statements: Vec<&'d linkage_adm::Marker>,
}

/// Places every marker. Errors: a duplicate id, an unknown PART, no carrier at all, ZP/XP
/// that define no orientation, an RM that does not exist or is on another part, circular RM
/// references.
pub(crate) fn markers<'d>(
    ds: &'d Dataset,
    parts: &PartStatements,
    cx: &mut Ctx,
) -> MarkerStatements<'d> {
    let mut out = MarkerStatements {
        index: HashMap::with_capacity(ds.markers.len()),
        placed: Vec::with_capacity(ds.markers.len()),
        statements: Vec::with_capacity(ds.markers.len()),
    };
    for m in &ds.markers {
        if out.index.contains_key(&m.header.id) {
            cx.error(
                m.header.span,
                format!("duplicate MARKER id {}", m.header.id),
            );
            continue;
        }
        let (body, unsupported) = carrier(m, parts, cx);
        let p =
            m.qp.as_ref()
                .map_or(DVec3::ZERO, |q| cx.point(&m.header.name, "QP", q));
        let r = axes(m, p, cx);
        out.index.insert(m.header.id, out.placed.len());
        out.placed.push(PlacedMarker {
            body,
            p,
            r,
            unsupported,
        });
        out.statements.push(m);
    }
    resolve_reference_markers(&mut out, cx);
    out
}

/// The body a marker is on, and the carrier linkage does not model if it is on one (such a
/// marker is put on ground; an element that uses it is refused).
fn carrier(
    m: &linkage_adm::Marker,
    parts: &PartStatements,
    cx: &mut Ctx,
) -> (Body, Option<&'static str>) {
    match m.carrier {
        Some(MarkerCarrier::Part(r)) => match parts.index.get(&r.id) {
            Some(b) => (*b, None),
            None => {
                cx.error(
                    r.span,
                    format!("{}: PART {} does not exist", m.header.name, r.id),
                );
                (Body::Ground, None)
            }
        },
        Some(MarkerCarrier::PointMass(r)) => match parts.point_mass_index.get(&r.id) {
            Some(b) => (*b, None),
            None => {
                cx.error(
                    r.span,
                    format!("{}: POINT_MASS {} does not exist", m.header.name, r.id),
                );
                (Body::Ground, None)
            }
        },
        Some(MarkerCarrier::FlexBody(_)) => (Body::Ground, Some("FLEX_BODY")),
        Some(MarkerCarrier::FePart(_)) => (Body::Ground, Some("FE_PART")),
        None => {
            cx.error(
                m.header.span,
                format!(
                    "{}: no PART= and no PART statement before it",
                    m.header.name
                ),
            );
            (Body::Ground, None)
        }
    }
}

/// A marker's axes in its carrier's BCS: from `REULER` (3-1-3 angles), else from the points
/// `ZP` (on +z) and `XP` (in the x-z plane; with `USEXP`, XP is on +x and ZP fixes the x-z
/// plane), else the BCS axes. `qp` is the marker's origin.
fn axes(m: &linkage_adm::Marker, qp: DVec3, cx: &mut Ctx) -> DMat3 {
    if let Some(e) = &m.reuler {
        return euler313_to_matrix(e.value);
    }
    if m.zp.is_none() && m.xp.is_none() {
        return DMat3::IDENTITY;
    }
    let (zp, xp) = (
        m.zp.as_ref().map(|z| cx.point(&m.header.name, "ZP", z)),
        m.xp.as_ref().map(|x| cx.point(&m.header.name, "XP", x)),
    );
    let made = if m.usexp {
        // USEXP: XP is on the +x axis, ZP only fixes the x-z plane. `f` has its z along XP
        // and its x towards ZP: the marker's x is f's z, its z is f's x, and y = z × x = −f's y.
        frame_from_points(qp, xp, zp).map(|f| DMat3::from_cols(f.z_axis, -f.y_axis, f.x_axis))
    } else {
        frame_from_points(qp, zp, xp)
    };
    made.unwrap_or_else(|| {
        let span =
            m.zp.as_ref()
                .or(m.xp.as_ref())
                .map_or(m.header.span, |z| z.span);
        cx.error(
            span,
            format!(
                "{}: ZP/XP do not define an orientation (point coincides with QP)",
                m.header.name
            ),
        );
        DMat3::IDENTITY
    })
}

/// Markers given in a reference marker `RM` of the same part: `p = p_RM + R_RM·QP`,
/// `R = R_RM·R_given`, resolved in dependency order (a chain of RMs takes as many passes as
/// it is long).
fn resolve_reference_markers(ms: &mut MarkerStatements, cx: &mut Ctx) {
    let statements = &ms.statements;
    let mut resolved: Vec<bool> = statements.iter().map(|m| m.rm.is_none()).collect();
    for _ in 0..statements.len() + 1 {
        let mut progress = false;
        for k in 0..statements.len() {
            if resolved[k] {
                continue;
            }
            let Some(rm) = statements[k].rm else {
                continue;
            };
            match ms.index.get(&rm.id) {
                Some(&r) if resolved[r] => {
                    let reference = ms.placed[r];
                    let given = ms.placed[k];
                    if reference.body != given.body {
                        cx.error(
                            rm.span,
                            format!(
                                "{}: RM marker {} is on another part",
                                statements[k].header.name, rm.id
                            ),
                        );
                    }
                    ms.placed[k] = PlacedMarker {
                        p: reference.p + reference.r * given.p,
                        r: reference.r * given.r,
                        ..given
                    };
                    resolved[k] = true;
                    progress = true;
                }
                Some(_) => {}
                None => {
                    cx.error(
                        rm.span,
                        format!(
                            "{}: RM marker {} does not exist",
                            statements[k].header.name, rm.id
                        ),
                    );
                    resolved[k] = true;
                }
            }
        }
        if !progress {
            break;
        }
    }
    for (k, done) in resolved.iter().enumerate() {
        if !done {
            cx.error(
                statements[k].header.span,
                format!("{}: circular RM references", statements[k].header.name),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::build::test_support::{build_text, errors_in_order};
    use crate::Body;
    use glam::DVec3;

    const PARTS: &str = "t\nPART/1, GROUND\nPART/2, QG = 10, 0, 0\n";

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn reference_markers_are_resolved_along_a_chain() {
        // 5 is given in 4, which is given in 3 (rotated 90° about z): resolved in any order.
        let b = build_text(&format!("{PARTS}MARKER/5, PART = 2, QP = 1, 0, 0, RM = 4\nMARKER/4, PART = 2, QP = 0, 2, 0, RM = 3\nMARKER/3, PART = 2, QP = 0, 0, 1, REULER = 90D, 0, 0\nEND\n"))
            .unwrap_or_else(|e| panic!("{e}"));
        let m = &b.model;
        let (p3, r3) = (m.markers[2].p_bm, m.markers[2].r_bm);
        assert!(close(p3, DVec3::new(0.0, 0.0, 1.0)));
        // In 3's axes y is ground −x: 4 sits at (−2, 0, 1) with 3's axes.
        assert!(close(m.markers[1].p_bm, DVec3::new(-2.0, 0.0, 1.0)));
        assert!((m.markers[1].r_bm - r3)
            .abs()
            .to_cols_array()
            .iter()
            .all(|x| *x < 1e-15));
        // 5: 4's x axis is ground y.
        assert!(close(m.markers[0].p_bm, DVec3::new(-2.0, 1.0, 1.0)));
        assert_eq!(m.markers[0].body, Body::Part(0));
        let (p_g, _) = m.marker_in_ground(0);
        assert!(close(p_g, DVec3::new(8.0, 1.0, 1.0)));
    }

    #[test]
    fn zp_xp_orient_a_marker_with_or_without_usexp() {
        let b = build_text(&format!("{PARTS}MARKER/3, PART = 2, QP = 0, 0, 0, ZP = 0, 1, 0, XP = 0, 0, 1, USEXP\nMARKER/4, PART = 2, ZP = 0, 1, 0, XP = 0, 0, 1\nEND\n"))
            .unwrap_or_else(|e| panic!("{e}"));
        // With USEXP, XP is on +x and ZP fixes the x-z plane: z is ZP's direction square to
        // XP's, and the axes are right-handed.
        let usexp = b.model.markers[0].r_bm;
        assert!(close(usexp.x_axis, DVec3::Z));
        assert!(close(usexp.z_axis, DVec3::Y));
        assert!(close(usexp.y_axis, DVec3::X));
        assert!((usexp.determinant() - 1.0).abs() < 1e-12);
        // ZP need not be square to XP: only its part square to x counts.
        let b2 = build_text(&format!(
            "{PARTS}MARKER/3, PART = 2, XP = 2, 0, 0, ZP = 1, 0, 1, USEXP\nEND\n"
        ))
        .unwrap_or_else(|e| panic!("{e}"));
        let slanted = b2.model.markers[0].r_bm;
        assert!(close(slanted.x_axis, DVec3::X));
        assert!(close(slanted.z_axis, DVec3::Z));
        assert!(close(slanted.y_axis, DVec3::Y));
        let plain = b.model.markers[1].r_bm;
        assert!(close(plain.z_axis, DVec3::Y));
        assert!(close(plain.x_axis, DVec3::Z));
    }

    #[test]
    fn marker_errors_name_the_argument() {
        let e = errors_in_order(&format!("{PARTS}MARKER/3, PART = 9\nMARKER/3, PART = 2\nMARKER/4, PART = 2, QP = 1, 1, 1, ZP = 1, 1, 1\nMARKER/5, PART = 2, RM = 6\nMARKER/6, PART = 2, RM = 5\nMARKER/7, PART = 2, RM = 99\nMARKER/8, PART = 1, RM = 4\nEND\n"));
        assert_eq!(
            e,
            [
                (4, 18, "MARKER_3: PART 9 does not exist".to_string()),
                (5, 1, "duplicate MARKER id 3".to_string()),
                (
                    6,
                    35,
                    "MARKER_4: ZP/XP do not define an orientation (point coincides with QP)"
                        .to_string()
                ),
                (9, 26, "MARKER_7: RM marker 99 does not exist".to_string()),
                (
                    10,
                    26,
                    "MARKER_8: RM marker 4 is on another part".to_string()
                ),
                (7, 1, "MARKER_5: circular RM references".to_string()),
                (8, 1, "MARKER_6: circular RM references".to_string()),
            ]
        );
    }
}
