//! `CVCV/` (ADM-ELEMENTS §16): a planar curve on one body kept in contact with, and tangent to,
//! a planar curve on another.
//!
//! Errors: a missing ICURVE, IRM, IFLOAT, JCURVE, JRM or JFLOAT; IRM and JRM on one body; a
//! float marker that is not FLOATING or not on its RM marker's body; an unknown CURVE; a curve
//! that is not planar (a CVCV's curves lie in their RM marker's x-y plane: every point has
//! z = 0). A CVCV on a USER curve is not built (the coverage check names it and the USER call).

use super::context::Ctx;
use super::curves::{id_ref, input_pose, numbers, origin_of};
use super::lookup::MarkerTable;
use crate::curves::Curve;
use crate::model::{Constraint, ConstraintKind, CurveOnCurve};
use glam::DVec3;
use linkage_adm::{Dataset, Statement};
use std::collections::HashMap;

/// One side of a CVCV as read: its RM marker, float marker, curve, DISP guess and VEL.
struct Side {
    rm: usize,
    float: usize,
    curve: usize,
    disp: Option<DVec3>,
    vel: Option<f64>,
}

/// The curves a CVCV may name: the matrix curves built (by id) and the USER curves' ids.
struct Known<'a> {
    index: &'a HashMap<u64, usize>,
    built: &'a [Curve],
    user: Vec<u64>,
}

/// Reads side `p` ("I" or "J") of CVCV statement `st` (its `pICURVE`, `pRM`, `pFLOAT`,
/// `pDISP`, `pICM`, `pVEL` arguments).
fn side(
    st: &Statement,
    p: &str,
    name: &str,
    table: &MarkerTable,
    known: &Known,
    cx: &mut Ctx,
) -> Option<Side> {
    let key = |k: &str| format!("{p}{k}");
    let must = |k: &str, cx: &mut Ctx| {
        let r = id_ref(st, k, cx, name);
        if r.is_none() {
            cx.error(st.span, format!("{name}: {k} is missing"));
        }
        r
    };
    let (cv, rm, fl) = (
        must(&key("CURVE"), cx),
        must(&key("RM"), cx),
        must(&key("FLOAT"), cx),
    );
    let (cv, rm, fl) = (cv?, rm?, fl?);
    let rm = table.constraint_marker(cx, rm, name)?;
    let Some(&float) = table.index.get(&fl.id) else {
        cx.error(fl.span, format!("{name}: marker {} does not exist", fl.id));
        return None;
    };
    if !table.markers[float].floating {
        cx.error(
            fl.span,
            format!("{name}: {p}FLOAT marker {} is not FLOATING", fl.id),
        );
        return None;
    }
    if table.markers[float].body != table.markers[rm].body {
        cx.error(
            fl.span,
            format!(
                "{name}: {p}FLOAT marker {} is not on the {p}RM marker's part ({})",
                fl.id,
                table.body_name(table.markers[rm].body)
            ),
        );
        return None;
    }
    let Some(&curve) = known.index.get(&cv.id) else {
        if !known.user.contains(&cv.id) {
            cx.error(cv.span, format!("{name}: CURVE/{} does not exist", cv.id));
        }
        return None;
    };
    if !known.built[curve].planar {
        cx.error(
            cv.span,
            format!(
                "{name}: CURVE/{} is not planar; a CVCV's curves lie in the x-y plane of their \
                 RM marker (every point with z = 0)",
                cv.id
            ),
        );
        return None;
    }
    let disp = numbers(st, &key("DISP")).and_then(|(v, span)| {
        let [x, y, z] = v.as_slice() else {
            cx.error(span, format!("{name}: {p}DISP needs x, y, z"));
            return None;
        };
        let icm = id_ref(st, &format!("{p}ICM"), cx, name)
            .and_then(|r| table.constraint_marker(cx, r, name))
            .unwrap_or(rm);
        let (p_icm, r_icm) = input_pose(table, icm);
        let (p_rm, r_rm) = input_pose(table, rm);
        Some(r_rm.transpose() * (p_icm + r_icm * DVec3::new(*x, *y, *z) - p_rm))
    });
    let vel = numbers(st, &key("VEL")).and_then(|(v, _)| v.first().copied());
    Some(Side {
        rm,
        float,
        curve,
        disp,
        vel,
    })
}

/// Every CVCV whose two curves are matrix curves, appended to `constraints`.
pub(crate) fn cvcvs(
    ds: &Dataset,
    table: &MarkerTable,
    curves: &HashMap<u64, usize>,
    model_curves: &[Curve],
    cx: &mut Ctx,
    constraints: &mut Vec<Constraint>,
) {
    let mut seen = std::collections::HashSet::new();
    let known = Known {
        index: curves,
        built: model_curves,
        user: ds
            .statements
            .iter()
            .filter(|s| s.keyword == "CURVE" && s.arg("FUNCTION").is_some())
            .filter_map(|s| s.id)
            .collect(),
    };
    for (k, st) in ds.statements.iter().enumerate() {
        if st.keyword != "CVCV" {
            continue;
        }
        let origin = origin_of("CVCV", st, k);
        let name = origin.name.clone();
        if !seen.insert(origin.id) {
            cx.error(st.span, format!("duplicate CVCV id {}", origin.id));
            continue;
        }
        let i = side(st, "I", &name, table, &known, cx);
        let j = side(st, "J", &name, table, &known, cx);
        let (Some(i), Some(j)) = (i, j) else { continue };
        let header = linkage_adm::Header {
            id: origin.id,
            name: name.clone(),
            span: st.span,
            statement: k,
        };
        if table
            .two_bodies(cx, Some(i.rm), Some(j.rm), &header)
            .is_none()
        {
            continue;
        }
        constraints.push(Constraint {
            origin,
            kind: ConstraintKind::Cvcv(Box::new(CurveOnCurve {
                irm: i.rm,
                jrm: j.rm,
                ifloat: i.float,
                jfloat: j.float,
                icurve: i.curve,
                jcurve: j.curve,
                idisp: i.disp,
                jdisp: j.disp,
                ivel: i.vel,
                jvel: j.vel,
            })),
        });
    }
}

#[cfg(test)]
mod tests {
    use crate::build::test_support::{errors, ok};
    use crate::model::ConstraintKind;

    /// A square (closed, planar) as MATRIX/5 → CURVE/6, a tilted square (z ≠ 0) as
    /// MATRIX/7 → CURVE/8. Lines 12–15.
    const CURVES: &str = "MATRIX/5, FULL = RORDER, ROWS = 5, COLUMNS = 3, VALUES = 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0, 1, 0, 0\nCURVE/6, CLOSED, CURVE_POINTS, MATRIX = 5\nMATRIX/7, FULL = RORDER, ROWS = 5, COLUMNS = 3, VALUES = 1, 0, 0, 0, 1, 1, -1, 0, 0, 0, -1, -1, 1, 0, 0\nCURVE/8, CLOSED, CURVE_POINTS, MATRIX = 7\n";

    #[test]
    fn a_cvcv_reads_its_markers_curves_and_initial_conditions() {
        let b = ok(&format!(
            "{CURVES}MARKER/9, PART = 1, FLOATING\nCVCV/3, ICURVE = 6, IRM = 20, IFLOAT = 22, JCURVE = 6, JRM = 1, JFLOAT = 9, IDISP = 0, 1, 0, JVEL = 2"
        ));
        let c = b
            .model
            .constraints
            .iter()
            .find_map(|c| match &c.kind {
                ConstraintKind::Cvcv(c) => Some(c.clone()),
                _ => None,
            })
            .expect("the CVCV is built");
        let m = &b.model.markers;
        assert_eq!((m[c.irm].id, m[c.jrm].id), (20, 1));
        assert_eq!((m[c.ifloat].id, m[c.jfloat].id), (22, 9));
        assert_eq!(c.icurve, c.jcurve);
        // IDISP is in IRM's frame: marker 20 is at the CM with the part's axes.
        assert_eq!(c.idisp, Some(glam::DVec3::new(0.0, 1.0, 0.0)));
        assert_eq!((c.ivel, c.jvel), (None, Some(2.0)));
        assert_eq!(
            b.model.constraints[b.model.constraints.len() - 1].description(),
            "Curve-Curve Constraint"
        );
    }

    #[test]
    fn cvcv_errors_name_the_argument() {
        let e = errors(&format!(
            "{CURVES}CVCV/3, ICURVE = 8, IRM = 20, IFLOAT = 22, JCURVE = 6, JRM = 1, JFLOAT = 2"
        ));
        let text: Vec<&str> = e.iter().map(|(_, _, m)| m.as_str()).collect();
        assert!(
            text.iter()
                .any(|m| m.contains("CURVE/8 is not planar") && m.starts_with("CVCV_3")),
            "{text:?}"
        );
        assert!(
            text.iter()
                .any(|m| m.contains("JFLOAT marker 2 is not FLOATING")),
            "{text:?}"
        );
        let e = errors(&format!(
            "{CURVES}CVCV/3, ICURVE = 6, IRM = 20, IFLOAT = 31, JCURVE = 6, JRM = 21, JFLOAT = 22"
        ));
        let text: Vec<&str> = e.iter().map(|(_, _, m)| m.as_str()).collect();
        assert!(
            text.iter()
                .any(|m| m.contains("IFLOAT marker 31 is not on the IRM marker's part")),
            "{text:?}"
        );
        let e = errors(&format!(
            "{CURVES}CVCV/3, ICURVE = 6, IRM = 20, IFLOAT = 22, JCURVE = 6, JRM = 21, JFLOAT = 22"
        ));
        assert_eq!(e.len(), 1, "IRM and JRM on one part: {e:?}");
        assert!(e[0].2.starts_with("CVCV_3"), "{e:?}");
    }
}
