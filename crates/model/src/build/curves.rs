//! `CURVE/` from a MATRIX and `PTCV/` (ADM-ELEMENTS §14, §15), read from their statements.
//!
//! A CURVE with `FUNCTION = USER(…)` is not built (the coverage check names the USER call and
//! every PTCV on it). Errors: a missing or unknown MATRIX, a matrix that is not n × 3, a curve
//! the B-spline cannot be made of ([`Curve::new`]); a PTCV whose I, RM or JFLOAT marker is
//! missing, I and RM on one body, JFLOAT not FLOATING or not on RM's body, an unknown CURVE.

use super::context::Ctx;
use super::lookup::MarkerTable;
use crate::bodies::{Body, Origin};
use crate::controls::Matrix;
use crate::curves::{Curve, CurveSpec};
use crate::model::{Constraint, ConstraintKind, PointOnCurve};
use glam::{DMat3, DVec3};
use linkage_adm::{Dataset, IdRef, Statement, Value};
use std::collections::HashMap;

pub(super) fn origin_of(keyword: &'static str, st: &Statement, index: usize) -> Origin {
    let id = st.id.unwrap_or(0);
    Origin {
        statement: keyword,
        id,
        name: st
            .view_name
            .clone()
            .unwrap_or_else(|| format!("{keyword}_{id}")),
        span: st.span,
        statement_index: index,
    }
}

/// The numbers of argument `key`.
pub(super) fn numbers(st: &Statement, key: &str) -> Option<(Vec<f64>, linkage_adm::Span)> {
    let a = st.arg(key)?;
    let v = a
        .values
        .iter()
        .filter_map(|v| match v {
            Value::Number { value, .. } => Some(*value),
            _ => None,
        })
        .collect();
    Some((v, a.span))
}

/// The id argument `key` (one whole number).
pub(super) fn id_ref(st: &Statement, key: &str, cx: &mut Ctx, name: &str) -> Option<IdRef> {
    let (v, span) = numbers(st, key)?;
    match v.as_slice() {
        [x] if *x >= 0.0 && x.fract() == 0.0 => Some(IdRef {
            id: *x as u64,
            span,
        }),
        _ => {
            cx.error(span, format!("{name}: {key} must be one id"));
            None
        }
    }
}

/// Every matrix CURVE a PTCV, CVCV or GRAPHICS CURVE (a contact geometry) reads (the others are data nothing uses, which the coverage
/// check names): the curves and the index of each CURVE id in them.
pub(crate) fn curves(
    ds: &Dataset,
    matrices: &[Matrix],
    cx: &mut Ctx,
) -> (Vec<Curve>, HashMap<u64, usize>) {
    let mut out = Vec::new();
    let mut index = HashMap::new();
    let read: std::collections::HashSet<u64> = ds
        .statements
        .iter()
        .flat_map(|s| {
            match s.keyword.as_str() {
                "PTCV" => vec!["CURVE"],
                "CVCV" => vec!["ICURVE", "JCURVE"],
                "GRAPHICS" if s.arg("CURVE").is_some() => vec!["CID"],
                _ => Vec::new(),
            }
            .into_iter()
            .filter_map(move |key| numbers(s, key)?.0.first().map(|&c| c as u64))
        })
        .collect();
    for (k, st) in ds.statements.iter().enumerate() {
        if st.keyword != "CURVE" || !st.id.is_some_and(|id| read.contains(&id)) {
            continue;
        }
        let origin = origin_of("CURVE", st, k);
        if index.contains_key(&origin.id) {
            cx.error(st.span, format!("duplicate CURVE id {}", origin.id));
            continue;
        }
        if st.arg("FUNCTION").is_some() {
            continue;
        }
        let name = origin.name.clone();
        let Some(mref) = id_ref(st, "MATRIX", cx, &name) else {
            cx.error(st.span, format!("{name}: MATRIX (or FUNCTION) is missing"));
            continue;
        };
        let Some(m) = matrices.iter().find(|m| m.origin.id == mref.id) else {
            cx.error(
                mref.span,
                format!(
                    "{name}: MATRIX/{} does not exist or cannot be read",
                    mref.id
                ),
            );
            continue;
        };
        if m.matrix.columns != 3 {
            cx.error(
                mref.span,
                format!(
                    "{name}: MATRIX/{} has {} columns; a curve's matrix has one x, y, z point \
                     per row",
                    mref.id, m.matrix.columns
                ),
            );
            continue;
        }
        let order = match numbers(st, "ORDER") {
            Some((v, span)) => match v.as_slice() {
                [x] if x.fract() == 0.0 && *x >= 0.0 => *x as usize,
                _ => {
                    cx.error(span, format!("{name}: ORDER must be a whole number"));
                    continue;
                }
            },
            None => 4,
        };
        let spec = CurveSpec {
            points: (0..m.matrix.rows)
                .map(|r| DVec3::new(m.matrix.get(r, 0), m.matrix.get(r, 1), m.matrix.get(r, 2)))
                .collect(),
            order,
            closed: st.arg("CLOSED").is_some(),
            through_points: st.arg("CURVE_POINTS").is_some(),
        };
        match Curve::new(origin, &spec) {
            Ok(c) => {
                index.insert(c.origin.id, out.len());
                out.push(c);
            }
            Err(e) => cx.error(st.span, format!("{name}: {e}")),
        }
    }
    (out, index)
}

/// Every PTCV whose curve is a matrix curve, appended to `constraints`.
pub(crate) fn ptcvs(
    ds: &Dataset,
    table: &MarkerTable,
    curves: &HashMap<u64, usize>,
    cx: &mut Ctx,
    constraints: &mut Vec<Constraint>,
) {
    let mut seen = std::collections::HashSet::new();
    let user_curves: Vec<u64> = ds
        .statements
        .iter()
        .filter(|s| s.keyword == "CURVE" && s.arg("FUNCTION").is_some())
        .filter_map(|s| s.id)
        .collect();
    for (k, st) in ds.statements.iter().enumerate() {
        if st.keyword != "PTCV" {
            continue;
        }
        let origin = origin_of("PTCV", st, k);
        let name = origin.name.clone();
        if !seen.insert(origin.id) {
            cx.error(st.span, format!("duplicate PTCV id {}", origin.id));
            continue;
        }
        let marker = |key: &str, cx: &mut Ctx| {
            let r = id_ref(st, key, cx, &name);
            if r.is_none() {
                cx.error(st.span, format!("{name}: {key} is missing"));
            }
            r
        };
        let (i, rm, jf, cv) = (
            marker("I", cx),
            marker("RM", cx),
            marker("JFLOAT", cx),
            marker("CURVE", cx),
        );
        let (Some(i), Some(rm), Some(jf), Some(cv)) = (i, rm, jf, cv) else {
            continue;
        };
        let mi = table.constraint_marker(cx, i, &name);
        let mrm = table.constraint_marker(cx, rm, &name);
        let Some(jfloat) = table.index.get(&jf.id).copied() else {
            cx.error(jf.span, format!("{name}: marker {} does not exist", jf.id));
            continue;
        };
        let header = linkage_adm::Header {
            id: origin.id,
            name: name.clone(),
            span: st.span,
            statement: k,
        };
        let Some((mi, mrm)) = table.two_bodies(cx, mi, mrm, &header) else {
            continue;
        };
        if !table.markers[jfloat].floating {
            cx.error(
                jf.span,
                format!("{name}: JFLOAT marker {} is not FLOATING", jf.id),
            );
            continue;
        }
        if table.markers[jfloat].body != table.markers[mrm].body {
            cx.error(
                jf.span,
                format!(
                    "{name}: JFLOAT marker {} is not on the RM marker's part ({})",
                    jf.id,
                    table.body_name(table.markers[mrm].body)
                ),
            );
            continue;
        }
        let Some(&curve) = curves.get(&cv.id) else {
            if !user_curves.contains(&cv.id) {
                cx.error(cv.span, format!("{name}: CURVE/{} does not exist", cv.id));
            }
            continue;
        };
        let disp = numbers(st, "DISP").and_then(|(v, span)| {
            let [x, y, z] = v.as_slice() else {
                cx.error(span, format!("{name}: DISP needs x, y, z"));
                return None;
            };
            let p = DVec3::new(*x, *y, *z);
            let icm = id_ref(st, "ICM", cx, &name)
                .and_then(|r| table.constraint_marker(cx, r, &name))
                .unwrap_or(mrm);
            let (p_icm, r_icm) = input_pose(table, icm);
            let (p_rm, r_rm) = input_pose(table, mrm);
            Some(r_rm.transpose() * (p_icm + r_icm * p - p_rm))
        });
        let vel = numbers(st, "VEL").and_then(|(v, _)| v.first().copied());
        constraints.push(Constraint {
            origin,
            kind: ConstraintKind::Ptcv(Box::new(PointOnCurve {
                i: mi,
                rm: mrm,
                jfloat,
                curve,
                disp,
                vel,
            })),
        });
    }
}

/// A marker's pose in ground at the input configuration.
pub(super) fn input_pose(table: &MarkerTable, m: usize) -> (DVec3, DMat3) {
    let mk = &table.markers[m];
    match mk.body {
        Body::Ground => (mk.p_bm, mk.r_bm),
        Body::Part(k) => {
            let p = &table.parts[k];
            (p.p_gb + p.r_gb * mk.p_bm, p.r_gb * mk.r_bm)
        }
    }
}
