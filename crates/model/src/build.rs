//! Dataset → [`Model`]: resolve references, place frames, move inertia to the centre of mass.
//!
//! Every problem is collected (not just the first) and returned as diagnostics carrying the
//! position of the offending argument or statement.

use crate::frames::{euler313_to_matrix, frame_from_points};
use crate::inertia::{
    check_physical, rotate_tensor, tensor_from_ip, to_centre_of_mass, InertiaDefect,
};
use crate::model::*;
use crate::units::{self, Units};
use glam::{DMat3, DVec3};
use linkage_adm::{
    CouplerDof, Dataset, Diagnostic, Diagnostics, Header, IdRef, JointType, MarkerCarrier,
    MotionDof, MotionTarget, Span,
};
use std::collections::HashMap;
use std::sync::Arc;

/// Relative tolerance of the inertia validity check (principal moments, triangle inequality).
pub const INERTIA_RELATIVE_TOLERANCE: f64 = 1e-9;

/// The model and the non-fatal findings made while building it (dataset warnings included).
pub struct Built {
    pub model: Model,
    pub warnings: Vec<Diagnostic>,
}

struct Ctx {
    file: Arc<str>,
    errors: Vec<Diagnostic>,
    warnings: Vec<Diagnostic>,
}

impl Ctx {
    fn error(&mut self, span: Span, msg: impl Into<String>) {
        self.errors
            .push(Diagnostic::error(self.file.clone(), Some(span), msg));
    }
    fn warn(&mut self, span: Span, msg: impl Into<String>) {
        self.warnings
            .push(Diagnostic::warning(self.file.clone(), Some(span), msg));
    }
}

fn origin(statement: &'static str, h: &Header) -> Origin {
    Origin {
        statement,
        id: h.id,
        name: h.name.clone(),
        span: h.span,
        statement_index: h.statement,
    }
}

fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// Builds the model. Errors: unknown or duplicate ids, a joint whose markers are on the same
/// part, zero or several GROUND parts, negative mass, non-physical inertia, markers on
/// carriers linkage does not model (POINT_MASS, FLEX_BODY, FE_PART) used by constraints or
/// forces, invalid force or data elements ([`crate::forces`]), …
pub fn build_model(ds: &Dataset) -> Result<Built, Diagnostics> {
    let mut cx = Ctx {
        file: ds.file.clone(),
        errors: Vec::new(),
        warnings: ds.warnings.clone(),
    };
    let units = build_units(ds, &mut cx);
    let gravity = ds.accgrav.as_ref().map_or(DVec3::ZERO, |g| v3(g.gravity));

    // --- parts -----------------------------------------------------------------------------
    let mut ground: Option<&linkage_adm::Part> = None;
    let mut part_index: HashMap<u64, Body> = HashMap::new();
    let mut part_stmts = Vec::new();
    for p in &ds.parts {
        if part_index.contains_key(&p.header.id) {
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
            part_index.insert(p.header.id, Body::Ground);
        } else {
            part_index.insert(p.header.id, Body::Part(part_stmts.len()));
            part_stmts.push(p);
        }
    }
    if ground.is_none() {
        cx.errors.push(
            Diagnostic::error(ds.file.clone(), None, "the dataset has no GROUND part")
                .with_hint("add `PART/1, GROUND`"),
        );
    }
    // BCS of each moving part in ground.
    let mut bcs: Vec<(DVec3, DMat3)> = Vec::with_capacity(part_stmts.len());
    for p in &part_stmts {
        let qg = p.qg.as_ref().map_or(DVec3::ZERO, |q| v3(q.value));
        let r = if let Some(e) = &p.reuler {
            euler313_to_matrix(e.value)
        } else if p.zg.is_some() || p.xg.is_some() {
            match frame_from_points(
                qg,
                p.zg.as_ref().map(|z| v3(z.value)),
                p.xg.as_ref().map(|x| v3(x.value)),
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
        bcs.push((qg, r));
    }

    // --- markers in their part's BCS -------------------------------------------------------
    let mut marker_index: HashMap<u64, usize> = HashMap::new();
    // (body, position in BCS (ground coords for ground), axes in BCS) + unsupported carrier note
    let mut raw: Vec<(Body, DVec3, DMat3, Option<&'static str>)> = Vec::new();
    let mut markers_src = Vec::new();
    for m in &ds.markers {
        if marker_index.contains_key(&m.header.id) {
            cx.error(
                m.header.span,
                format!("duplicate MARKER id {}", m.header.id),
            );
            continue;
        }
        let (body, unsupported) = match m.carrier {
            Some(MarkerCarrier::Part(r)) => match part_index.get(&r.id) {
                Some(b) => (*b, None),
                None => {
                    cx.error(
                        r.span,
                        format!("{}: PART {} does not exist", m.header.name, r.id),
                    );
                    (Body::Ground, None)
                }
            },
            Some(MarkerCarrier::PointMass(_)) => (Body::Ground, Some("POINT_MASS")),
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
        };
        let qp = m.qp.as_ref().map_or(DVec3::ZERO, |q| v3(q.value));
        let r = if let Some(e) = &m.reuler {
            euler313_to_matrix(e.value)
        } else if m.zp.is_some() || m.xp.is_some() {
            let (zp, xp) = (
                m.zp.as_ref().map(|z| v3(z.value)),
                m.xp.as_ref().map(|x| v3(x.value)),
            );
            let made = if m.usexp {
                // USEXP: XP is on the +x axis, ZP only fixes the x-z plane.
                frame_from_points(qp, xp, zp)
                    .map(|f| DMat3::from_cols(f.y_axis, f.z_axis, f.x_axis))
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
        } else {
            DMat3::IDENTITY
        };
        marker_index.insert(m.header.id, raw.len());
        raw.push((body, qp, r, unsupported));
        markers_src.push(m);
    }
    // RM: QP/REULER given in a reference marker of the same part.
    let mut resolved: Vec<bool> = markers_src.iter().map(|m| m.rm.is_none()).collect();
    for _ in 0..markers_src.len() + 1 {
        let mut progress = false;
        for k in 0..markers_src.len() {
            if resolved[k] {
                continue;
            }
            let Some(rm) = markers_src[k].rm else {
                continue;
            };
            match marker_index.get(&rm.id) {
                Some(&r) if resolved[r] => {
                    let (rb, rp, rr, _) = raw[r];
                    let (b, qp, q, u) = raw[k];
                    if rb != b {
                        cx.error(
                            rm.span,
                            format!(
                                "{}: RM marker {} is on another part",
                                markers_src[k].header.name, rm.id
                            ),
                        );
                    }
                    raw[k] = (b, rp + rr * qp, rr * q, u);
                    resolved[k] = true;
                    progress = true;
                }
                Some(_) => {}
                None => {
                    cx.error(
                        rm.span,
                        format!(
                            "{}: RM marker {} does not exist",
                            markers_src[k].header.name, rm.id
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
                markers_src[k].header.span,
                format!("{}: circular RM references", markers_src[k].header.name),
            );
        }
    }

    // --- centre of mass, inertia -------------------------------------------------------------
    let marker_on =
        |cx: &mut Ctx, r: IdRef, part: usize, what: &str, pname: &str| -> Option<usize> {
            match marker_index.get(&r.id) {
                Some(&m) if raw[m].0 == Body::Part(part) => Some(m),
                Some(_) => {
                    cx.error(
                        r.span,
                        format!("{pname}: {what} marker {} is not on this part", r.id),
                    );
                    None
                }
                None => {
                    cx.error(
                        r.span,
                        format!("{pname}: {what} marker {} does not exist", r.id),
                    );
                    None
                }
            }
        };
    let mut parts = Vec::with_capacity(part_stmts.len());
    let mut cm_in_bcs = Vec::with_capacity(part_stmts.len());
    for (k, p) in part_stmts.iter().enumerate() {
        let name = p.header.name.as_str();
        let mass = match &p.mass {
            Some(m) if m.value < 0.0 || !m.value.is_finite() => {
                cx.error(
                    m.span,
                    format!("{name}: mass must not be negative (MASS = {})", m.value),
                );
                0.0
            }
            Some(m) => m.value,
            None => 0.0,
        };
        let cm = p.cm.and_then(|r| marker_on(&mut cx, r, k, "CM", name));
        let c = cm.map_or(DVec3::ZERO, |m| raw[m].1);
        let im = match p.im {
            Some(r) => marker_on(&mut cx, r, k, "IM", name),
            None => cm,
        };
        let mut inertia = DMat3::ZERO;
        if let Some(ip) = &p.ip {
            let t = tensor_from_ip(ip.value);
            let (p_im, r_im) = im.map_or((DVec3::ZERO, DMat3::IDENTITY), |m| (raw[m].1, raw[m].2));
            let about_im = rotate_tensor(&t, &r_im);
            inertia = to_centre_of_mass(&about_im, mass, p_im - c);
            match check_physical(&inertia, INERTIA_RELATIVE_TOLERANCE) {
                Ok(()) => {}
                Err(InertiaDefect::Negative(why)) => cx.error(
                    ip.span,
                    format!("{name}: non-physical inertia about the centre of mass: {why}"),
                ),
                Err(InertiaDefect::Triangle(why)) => cx.warn(
                    ip.span,
                    format!(
                        "{name}: non-physical inertia about the centre of mass: {why}; no \
                         rigid body has it, but no principal moment is negative, so the \
                         analyses use it as given (as Adams does)"
                    ),
                ),
            }
        }
        if mass > 0.0 && p.ip.is_none() {
            cx.warn(
                p.header.span,
                format!("{name}: MASS given without IP: its inertia is zero"),
            );
        }
        let (qg, r) = bcs[k];
        cm_in_bcs.push(c);
        parts.push(Part {
            origin: origin("PART", &p.header),
            mass,
            inertia,
            p_gb: qg + r * c,
            r_gb: r,
            p_b_bcs: -c,
            velocity: p.velocity,
            r_b_cm: cm.map_or(DMat3::IDENTITY, |m| raw[m].2),
            exact: p.exact.clone(),
        });
    }
    let markers: Vec<Marker> = markers_src
        .iter()
        .zip(&raw)
        .map(|(m, &(body, p, r, _))| {
            let p_bm = match body {
                Body::Part(k) => p - cm_in_bcs[k],
                Body::Ground => p,
            };
            Marker {
                id: m.header.id,
                name: m.header.name.clone(),
                span: m.header.span,
                body,
                p_bm,
                r_bm: r,
                floating: m.floating,
            }
        })
        .collect();

    // --- constraints ---------------------------------------------------------------------------
    let mut constraints: Vec<Constraint> = Vec::new();
    // A marker usable by a constraint: exists, fixed, on a part or ground.
    let use_marker = |cx: &mut Ctx, r: IdRef, elem: &str| -> Option<usize> {
        match marker_index.get(&r.id) {
            None => {
                cx.error(r.span, format!("{elem}: marker {} does not exist", r.id));
                None
            }
            Some(&m) => {
                if let Some(kind) = raw[m].3 {
                    cx.error(
                        r.span,
                        format!(
                            "{elem}: marker {} is on a {kind}, which linkage does not model",
                            r.id
                        ),
                    );
                    None
                } else if markers_src[m].floating {
                    cx.error(
                        r.span,
                        format!(
                            "{elem}: marker {} is FLOATING; a constraint needs a fixed marker",
                            r.id
                        ),
                    );
                    None
                } else {
                    Some(m)
                }
            }
        }
    };
    let two_bodies =
        |cx: &mut Ctx, i: Option<usize>, j: Option<usize>, h: &Header| -> Option<(usize, usize)> {
            let (i, j) = (i?, j?);
            if markers[i].body == markers[j].body {
                let b = match markers[i].body {
                    Body::Ground => ground.map_or("ground".to_string(), |g| g.header.name.clone()),
                    Body::Part(k) => parts[k].origin.name.clone(),
                };
                cx.error(
                    h.span,
                    format!(
                        "{}: I marker {} and J marker {} are both on {b}",
                        h.name, markers[i].id, markers[j].id
                    ),
                );
                return None;
            }
            Some((i, j))
        };

    let mut joint_index: HashMap<u64, usize> = HashMap::new();
    for jt in &ds.joints {
        if joint_index.contains_key(&jt.header.id) {
            cx.error(
                jt.header.span,
                format!("duplicate JOINT id {}", jt.header.id),
            );
            continue;
        }
        let i = use_marker(&mut cx, jt.i, &jt.header.name);
        let j = use_marker(&mut cx, jt.j, &jt.header.name);
        let Some((i, j)) = two_bodies(&mut cx, i, j, &jt.header) else {
            continue;
        };
        let pd = jt.pd.as_ref().map(|v| v.value);
        let pitch = jt.pitch.as_ref().map(|v| v.value);
        match jt.kind {
            JointType::Rackpin if pd.is_none_or(|v| v == 0.0) => {
                cx.error(
                    jt.header.span,
                    format!(
                        "{}: RACKPIN needs a non-zero PD (pitch diameter)",
                        jt.header.name
                    ),
                );
                continue;
            }
            JointType::Screw if pitch.is_none_or(|v| v == 0.0) => {
                cx.error(
                    jt.header.span,
                    format!("{}: SCREW needs a non-zero PITCH", jt.header.name),
                );
                continue;
            }
            _ => {}
        }
        let mut initial = JointInitial::default();
        let pair = |v: &linkage_adm::Located<Vec<f64>>| {
            (v.value.first().copied(), v.value.get(1).copied())
        };
        if let Some(ic) = &jt.ic {
            initial.span = Some(ic.span);
            match jt.kind {
                JointType::Revolute => initial.rotation = pair(ic),
                JointType::Translational => initial.translation = pair(ic),
                _ => cx.warn(
                    ic.span,
                    format!(
                        "{}: IC applies to revolute and translational joints only; ignored",
                        jt.header.name
                    ),
                ),
            }
        }
        if let Some(v) = &jt.ictran {
            initial.span = Some(v.span);
            initial.translation = pair(v);
        }
        if let Some(v) = &jt.icrot {
            initial.span = initial.span.or(Some(v.span));
            initial.rotation = pair(v);
        }
        joint_index.insert(jt.header.id, constraints.len());
        constraints.push(Constraint {
            origin: origin("JOINT", &jt.header),
            kind: ConstraintKind::Joint {
                kind: jt.kind,
                i,
                j,
                initial,
                pd,
                pitch,
            },
        });
    }
    let mut seen = HashMap::new();
    for jp in &ds.jprims {
        if seen.insert(jp.header.id, ()).is_some() {
            cx.error(
                jp.header.span,
                format!("duplicate JPRIM id {}", jp.header.id),
            );
            continue;
        }
        let i = use_marker(&mut cx, jp.i, &jp.header.name);
        let j = use_marker(&mut cx, jp.j, &jp.header.name);
        let Some((i, j)) = two_bodies(&mut cx, i, j, &jp.header) else {
            continue;
        };
        constraints.push(Constraint {
            origin: origin("JPRIM", &jp.header),
            kind: ConstraintKind::Jprim {
                kind: jp.kind,
                i,
                j,
            },
        });
    }
    // Couplers and gears refer to joints.
    let joint_of =
        |cx: &mut Ctx, r: IdRef, elem: &str, cons: &[Constraint]| -> Option<(usize, JointType)> {
            match joint_index.get(&r.id) {
                None => {
                    cx.error(r.span, format!("{elem}: JOINT {} does not exist", r.id));
                    None
                }
                Some(&c) => match &cons[c].kind {
                    ConstraintKind::Joint { kind, .. } => Some((c, *kind)),
                    _ => None,
                },
            }
        };
    let mut seen = HashMap::new();
    for cp in &ds.couplers {
        let name = &cp.header.name;
        if seen.insert(cp.header.id, ()).is_some() {
            cx.error(
                cp.header.span,
                format!("duplicate COUPLER id {}", cp.header.id),
            );
            continue;
        }
        if cp.joints.len() < 2 || cp.joints.len() > 3 {
            cx.error(
                cp.header.span,
                format!("{name}: JOINTS must name 2 or 3 joints"),
            );
            continue;
        }
        if cp.scales.is_empty() {
            let what = if cp.function.as_ref().is_some_and(|f| f.value.user) {
                "a USER subroutine coupler cannot be run by linkage"
            } else {
                "SCALES is missing"
            };
            cx.error(cp.header.span, format!("{name}: {what}"));
            continue;
        }
        let n = cp.joints.len();
        let scales: Vec<f64> = match (n, cp.scales.len()) {
            (2, 1) => vec![1.0, cp.scales[0]],
            (3, 2) => vec![1.0, cp.scales[0], cp.scales[1]],
            (a, b) if a == b => cp.scales.clone(),
            _ => {
                cx.error(
                    cp.header.span,
                    format!("{name}: {} SCALES for {n} joints", cp.scales.len()),
                );
                continue;
            }
        };
        let mut terms = Vec::new();
        for (k, r) in cp.joints.iter().enumerate() {
            let Some((c, kind)) = joint_of(&mut cx, *r, name, &constraints) else {
                continue;
            };
            let dof = match (kind, cp.types.get(k)) {
                (JointType::Revolute, t) if t.is_none_or(|t| *t == CouplerDof::Rotation) => {
                    CouplerDof::Rotation
                }
                (JointType::Translational, t)
                    if t.is_none_or(|t| *t == CouplerDof::Translation) =>
                {
                    CouplerDof::Translation
                }
                (JointType::Cylindrical, Some(t)) => *t,
                (JointType::Cylindrical, None) => {
                    cx.error(
                        r.span,
                        format!(
                            "{name}: TYPE must say T or R for cylindrical JOINT {}",
                            r.id
                        ),
                    );
                    continue;
                }
                _ => {
                    cx.error(r.span, format!("{name}: JOINT {} is {}, a coupler needs a revolute, translational or cylindrical joint (with a matching TYPE)", r.id, kind.keyword()));
                    continue;
                }
            };
            terms.push((c, dof, scales[k]));
        }
        if terms.len() == n {
            constraints.push(Constraint {
                origin: origin("COUPLER", &cp.header),
                kind: ConstraintKind::Coupler {
                    terms,
                    function: cp.function.clone(),
                },
            });
        }
    }
    let mut seen = HashMap::new();
    for g in &ds.gears {
        let name = &g.header.name;
        if seen.insert(g.header.id, ()).is_some() {
            cx.error(g.header.span, format!("duplicate GEAR id {}", g.header.id));
            continue;
        }
        if g.joints.len() != 2 {
            cx.error(
                g.header.span,
                format!("{name}: JOINTS must name two joints"),
            );
            continue;
        }
        let Some(cv) = g.cv else {
            cx.error(
                g.header.span,
                format!("{name}: CV (common velocity marker) is missing"),
            );
            continue;
        };
        let cv = use_marker(&mut cx, cv, name);
        let a = joint_of(&mut cx, g.joints[0], name, &constraints);
        let b = joint_of(&mut cx, g.joints[1], name, &constraints);
        let (Some(cv), Some(a), Some(b)) = (cv, a, b) else {
            continue;
        };
        for (r, (_, kind)) in g.joints.iter().zip([a, b]) {
            if !matches!(
                kind,
                JointType::Revolute | JointType::Translational | JointType::Cylindrical
            ) {
                cx.error(r.span, format!("{name}: JOINT {} is {}, a gear needs revolute, translational or cylindrical joints", r.id, kind.keyword()));
            }
        }
        constraints.push(Constraint {
            origin: origin("GEAR", &g.header),
            kind: ConstraintKind::Gear {
                joints: [a.0, b.0],
                cv,
            },
        });
    }
    let mut seen = HashMap::new();
    for m in &ds.motions {
        let name = &m.header.name;
        if seen.insert(m.header.id, ()).is_some() {
            cx.error(
                m.header.span,
                format!("duplicate MOTION id {}", m.header.id),
            );
            continue;
        }
        if m.function.is_none() {
            cx.error(m.header.span, format!("{name}: FUNCTION is missing"));
            continue;
        }
        let (joint, i, j, coordinate) = match m.target {
            MotionTarget::Joint { joint, dof } => {
                let Some((c, kind)) = joint_of(&mut cx, joint, name, &constraints) else {
                    continue;
                };
                let Some((i, j)) = constraints[c].markers() else {
                    continue;
                };
                let coordinate = match (kind, dof) {
                    (JointType::Revolute, None | Some(MotionDof::Rotation)) => {
                        MotionCoordinate::RotationZ
                    }
                    (JointType::Translational, None | Some(MotionDof::Translation)) => {
                        MotionCoordinate::TranslationZ
                    }
                    (JointType::Cylindrical, Some(MotionDof::Rotation)) => {
                        MotionCoordinate::RotationZ
                    }
                    (JointType::Cylindrical, Some(MotionDof::Translation)) => {
                        MotionCoordinate::TranslationZ
                    }
                    (JointType::Cylindrical, None) => {
                        cx.error(m.header.span, format!("{name}: a motion on cylindrical JOINT {} must say TRANSLATION or ROTATION", joint.id));
                        continue;
                    }
                    (k, d) => {
                        cx.error(
                            joint.span,
                            format!(
                                "{name}: cannot drive {} of a {} joint (JOINT {})",
                                match d {
                                    Some(MotionDof::Translation) => "translation",
                                    _ => "rotation",
                                },
                                k.keyword(),
                                joint.id
                            ),
                        );
                        continue;
                    }
                };
                (Some(c), i, j, coordinate)
            }
            MotionTarget::Markers { i, j, axis } => {
                let mi = use_marker(&mut cx, i, name);
                let mj = use_marker(&mut cx, j, name);
                let Some((mi, mj)) = two_bodies(&mut cx, mi, mj, &m.header) else {
                    continue;
                };
                (None, mi, mj, MotionCoordinate::Marker(axis))
            }
        };
        constraints.push(Constraint {
            origin: origin("MOTION", &m.header),
            kind: ConstraintKind::Motion {
                joint,
                i,
                j,
                coordinate,
                level: m.level,
                function: m.function.clone(),
                icdisp: m.icdisp,
                icvel: m.icvel,
            },
        });
    }
    let mut seen = HashMap::new();
    for g in &ds.gcons {
        let name = &g.header.name;
        if seen.insert(g.header.id, ()).is_some() {
            cx.error(g.header.span, format!("duplicate GCON id {}", g.header.id));
            continue;
        }
        let Some(i) = g.i else {
            cx.error(g.header.span, format!("{name}: I marker is missing"));
            continue;
        };
        let Some(i) = use_marker(&mut cx, i, name) else {
            continue;
        };
        if g.function.is_none() {
            cx.error(g.header.span, format!("{name}: FUNCTION is missing"));
            continue;
        }
        constraints.push(Constraint {
            origin: origin("GCON", &g.header),
            kind: ConstraintKind::Gcon {
                i,
                function: g.function.clone(),
            },
        });
    }

    // --- force and data elements -----------------------------------------------------------
    let unsupported: Vec<Option<&'static str>> = raw.iter().map(|r| r.3).collect();
    let ground_name = ground.map_or("ground".to_string(), |g| g.header.name.clone());
    let force_data = crate::forces::build_forces(
        ds,
        &crate::forces::MarkerTable {
            index: &marker_index,
            markers: &markers,
            unsupported: &unsupported,
            parts: &parts,
            ground_name: &ground_name,
        },
        &mut cx.errors,
        &mut cx.warnings,
    );

    if !cx.errors.is_empty() {
        return Err(Diagnostics(cx.errors));
    }

    let mut model = Model {
        file: ds.file.clone(),
        title: ds.title.clone(),
        units,
        gravity,
        ground_name: ground.map_or("ground".into(), |g| g.header.name.clone()),
        parts,
        markers,
        constraints,
        forces: force_data.forces,
        variables: force_data.variables,
        arrays: force_data.arrays,
        splines: force_data.splines,
        characteristic_length: 1.0,
        ic: crate::settings::ic_settings(ds, &ds.file, &mut cx.warnings),
        equilibrium: crate::settings::equilibrium_settings(ds, &ds.file, &mut cx.warnings),
    };
    model.characteristic_length = characteristic_length(&model);
    Ok(Built {
        model,
        warnings: cx.warnings,
    })
}

/// Looks up a unit name: SI factor and canonical name.
type UnitLookup = fn(&str) -> Option<(f64, &'static str)>;

fn build_units(ds: &Dataset, cx: &mut Ctx) -> Units {
    let Some(u) = &ds.units else {
        return Units::default();
    };
    let mut names: [Option<(String, Span)>; 4] = [None, None, None, None];
    if let Some(sys) = &u.system {
        match units::system_units(&sys.value) {
            Some(n) => {
                for (slot, name) in names.iter_mut().zip(n) {
                    *slot = Some((name.to_string(), sys.span));
                }
            }
            None if sys.value == "NONE" => {}
            None => cx.error(sys.span, format!("unknown unit system '{}'", sys.value)),
        }
    }
    for (slot, given) in names
        .iter_mut()
        .zip([&u.force, &u.mass, &u.length, &u.time])
    {
        if let Some(g) = given {
            *slot = Some((g.value.clone(), g.span));
        }
    }
    let lookups: [UnitLookup; 4] = [
        units::force_unit,
        units::mass_unit,
        units::length_unit,
        units::time_unit,
    ];
    let defaults = ["NEWTON", "KILOGRAM", "MILLIMETER", "SECOND"];
    let mut out = Units {
        ucf_override: None,
        ..Units::default()
    };
    let mut factors = [1.0; 4];
    let mut all_none = true;
    for k in 0..4 {
        let (name, span) = match &names[k] {
            Some((n, s)) => {
                all_none = false;
                (n.as_str(), Some(*s))
            }
            None => (defaults[k], None),
        };
        match lookups[k](name) {
            Some((f, canon)) => {
                factors[k] = f;
                out.names[k] = canon;
            }
            None => cx.error(
                span.unwrap_or(u.header.span),
                format!("unknown unit '{name}'"),
            ),
        }
    }
    if all_none && u.ucf.is_none() {
        // `UNITS/` with nothing or SYSTEM=NONE: consistent, UCF 1.
        return Units::default();
    }
    out.force = factors[0];
    out.mass = factors[1];
    out.length = factors[2];
    out.time = factors[3];
    if let Some(ucf) = &u.ucf {
        if ucf.value <= 0.0 {
            cx.error(ucf.span, "UCF must be positive");
        }
        out.ucf_override = Some(ucf.value);
    }
    out
}

fn characteristic_length(m: &Model) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for k in 0..m.markers.len() {
        if m.markers[k].floating {
            continue;
        }
        let (p, _) = m.marker_in_ground(k);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    for p in &m.parts {
        lo = lo.min(p.p_gb);
        hi = hi.max(p.p_gb);
    }
    let d = (hi - lo).length();
    if d.is_finite() && d > 0.0 {
        d
    } else {
        1.0
    }
}
