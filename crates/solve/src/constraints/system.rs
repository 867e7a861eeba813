//! A model compiled into labelled constraint rows (DESIGN §3).
//!
//! One place defines the equations of every element: joints and primitives as unions of
//! primitive rows (translational rows first, rotational last), one row per motion, coupler,
//! gear, rack-and-pinion and screw. Every analysis uses these rows.
//!
//! # Sign conventions of the couplings (Adams Solver's JOINT, COUPLER and GEAR statements)
//!
//! Joint coordinates are those of Adams' CYLINDRICAL joint: the translation of I's origin along
//! z_j from J, and the rotation of x_i about the common z axis from x_j (AZ(I, J)).
//!
//! * **SCREW** (I the nut, J the screw; z_i, z_j co-directed): `(P_I − P_J)·z_j =
//!   PITCH·θ/2π` with θ the rotation of I about z_j — a positive PITCH is a right-hand thread:
//!   turning I anticlockwise about z_j advances it along +z_j.
//! * **RACKPIN** (I on the pinion at its centre, z_i its axis; J on the rack, z_j its direction
//!   of travel; x_i parallel to and co-directed with z_j, the rack's pitch line PD/2 from the
//!   pinion's axis on its −y_i side, per Adams View's rack-and-pinion description): the rack's
//!   travel `(P_J − P_I)·z_j = (PD/2)·θ` with θ the pinion's rotation about z_i relative to
//!   the rack — rolling without slip at the pitch point `P_I − (PD/2)·y_i`, whose velocity
//!   `θ̇ z_i × (−(PD/2) y_i) = (PD/2)·θ̇ x_i` is the rack's. It is the rack that travels (J
//!   relative to I): a falling rack turns the pinion positively about z_i. (Checked against
//!   an Adams run of the Chrono rack-and-pinion model: with I relative to J instead, the rack
//!   travels the same but the pinion turns the other way.)
//! * **COUPLER**: `r₁q₁ + r₂q₂ [+ r₃q₃] = 0`, q_k the displacement of joint k's I marker
//!   relative to its J marker (Adams' COUPLER statement: SCALES = 1, −2 makes q₁ = 2q₂, the
//!   same sign).
//! * **GEAR**: the velocities along z_cv of the two gears' material points at the CV marker
//!   are equal (Adams: CV's z axis points along the motion of the teeth in contact). Each
//!   joint's rate is turned into the velocity of its gear, the part of the joint that does
//!   not carry the CV marker (the carrier carries it), so either of its markers may be on the
//!   gear.
//! * **CONVEL** (z_i, z_j pointing down the shafts away from the centre; x_i ∥ x_j or
//!   y_i ∥ y_j at assembly): the spins about z_i and z_j are equal and opposite, written
//!   `x_i·y_j + y_i·x_j = 0`: for collinear shafts (z_i = −z_j, x_i = x_j) a spin α of I alone
//!   about z_i makes it `−2 sin α`, while the difference `x_i·y_j − y_i·x_j` stays 0 for every
//!   α and would constrain nothing.
//! * **UNIVERSAL**: the cross-pin axes are z_i and z_j (`z_i·z_j = 0`); **HOOKE**: x_i and
//!   y_j (`x_i·y_j = 0`). **JPRIM**: the rows of ADM-REFERENCE §4.1, I relative to J.

mod curve_pair;
mod flex_rows;

use crate::constraints::rows::curve_gap::{CurveGap, LastContact};
use crate::constraints::rows::{BodyDir, BodyFrame, EulerSeq, Quantity, RowGradient, Velocities};
use crate::physics::measures::{add_dual_gradient, MarkerFrames, PathEnv, PositionEnv};
use crate::state::State;
use crate::tolerances::ALIGNMENT_DIRECTION;
use curve_pair::curve_curve_rows;
use glam::{DMat3, DQuat, DVec3};
use linkage_adm::{CouplerDof, JointType, JprimType, MotionAxis};
use linkage_expr::{evaluate, evaluate_path_series, evaluate_with_gradient, EvalError, Expr};
use linkage_model::{Body, ConstraintKind, Model, MotionCoordinate};
use std::ops::Range;
use std::sync::{Arc, Mutex};

/// What a row's residual measures, to report it in length units or degrees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowUnit {
    /// A length (model units).
    Length,
    /// A dot product of unit axes (≈ sine of the misalignment angle).
    Direction,
    /// An angle in radians.
    Angle,
    /// A combination of joint coordinates (couplers, gears, rack-and-pinion, screw).
    Mixed,
}

/// Which group a row belongs to when rows are admitted for the rank analysis (lower first).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Tier {
    /// Translational rows of joints and primitives.
    Translation = 0,
    /// Rotational rows of joints and primitives.
    Rotation = 1,
    /// Couplings between joint coordinates: couplers, gears, rack-and-pinion, screw, GCON;
    /// and the curve-on-curve contacts (CVCV), so that in a planar mechanism the joints keep
    /// their rows and the CVCV's out-of-plane row is the one named redundant.
    Coupling = 2,
    /// Motions (drivers).
    Motion = 3,
}

/// One scalar constraint equation `Φ = Σ c_k Q_k − offset − f(t)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Index of the element in [`Model::constraints`].
    pub element: usize,
    /// Adams View label, e.g. `Rotation Between Zi & Xj`.
    pub label: &'static str,
    /// Adams Solver (C++) short label, e.g. `Zi.Xj`.
    pub short: &'static str,
    pub unit: RowUnit,
    pub tier: Tier,
    pub terms: Vec<(f64, Quantity)>,
    pub offset: f64,
    /// Whether `f(t)` of a motion is subtracted (the caller supplies it).
    pub driven: bool,
    /// The residual is defined modulo this period and wrapped to (−P/2, P/2]: the turns of its
    /// angle terms, which a pose cannot tell apart (2π for a rotational motion; the pitch of a
    /// SCREW, π·PD of a RACKPIN, 2π·gcd of the scales of a COUPLER or GEAR; see
    /// [`turn_period`]). `None`: no angle term, or angle terms whose turns are incommensurate.
    pub period: Option<f64>,
    /// A general constraint's expression `f(q, t)` (added to the terms).
    pub function: Option<Arc<Expr>>,
}

/// The rows of a model.
#[derive(Clone, Debug)]
pub struct System {
    pub nparts: usize,
    pub rows: Vec<Row>,
    /// Rows of each constraint element.
    pub element_rows: Vec<Range<usize>>,
    /// I and J frames used by each joint, primitive or motion.
    pub frames: Vec<Option<(BodyFrame, BodyFrame)>>,
    /// Marker frames by id, for expression measures.
    pub markers: Arc<MarkerFrames>,
}

fn marker_frame(model: &Model, m: usize) -> BodyFrame {
    let mk = &model.markers[m];
    BodyFrame {
        body: mk.body,
        p_b: mk.p_bm,
        r_b: mk.r_bm,
    }
}

fn ground_axis(k: usize) -> BodyDir {
    BodyDir {
        body: Body::Ground,
        v_b: DMat3::IDENTITY.col(k),
    }
}

const XG: [&str; 3] = [
    "Translation of I Marker Along Xg",
    "Translation of I Marker Along Yg",
    "Translation of I Marker Along Zg",
];
const XG_SHORT: [&str; 3] = ["Xg", "Yg", "Zg"];
const XJ: [&str; 3] = [
    "Translation of I Marker Along Xj",
    "Translation of I Marker Along Yj",
    "Translation of I Marker Along Zj",
];
const XJ_SHORT: [&str; 3] = ["Si.Xj", "Si.Yj", "Si.Zj"];

/// Primitive building blocks of joints (ADM-REFERENCE §4.1).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Prim {
    AtPoint,
    InLine,
    InPlane,
    Parallel,
    Perpendicular,
    Orientation,
    Hooke,
    Convel,
}

fn primitives(kind: ConstraintKindRef) -> &'static [Prim] {
    use Prim::*;
    match kind {
        ConstraintKindRef::Joint(j) => match j {
            JointType::Fixed => &[AtPoint, Orientation],
            JointType::Revolute => &[AtPoint, Parallel],
            JointType::Spherical => &[AtPoint],
            JointType::Translational => &[InLine, Orientation],
            JointType::Cylindrical => &[InLine, Parallel],
            JointType::Planar => &[InPlane, Parallel],
            JointType::Universal => &[AtPoint, Perpendicular],
            JointType::Hooke => &[AtPoint, Hooke],
            JointType::Convel => &[AtPoint, Convel],
            JointType::Rackpin | JointType::Screw => &[],
        },
        ConstraintKindRef::Jprim(p) => match p {
            JprimType::Atpoint => &[AtPoint],
            JprimType::Inline => &[InLine],
            JprimType::Inplane => &[InPlane],
            JprimType::Orientation => &[Orientation],
            JprimType::ParallelAxes => &[Parallel],
            JprimType::Perpendicular => &[Perpendicular],
        },
    }
}

#[derive(Clone, Copy)]
enum ConstraintKindRef {
    Joint(JointType),
    Jprim(JprimType),
}

struct Builder {
    input: State,
    rows: Vec<Row>,
}

impl Builder {
    fn push(
        &mut self,
        element: usize,
        label: &'static str,
        short: &'static str,
        unit: RowUnit,
        tier: Tier,
        terms: Vec<(f64, Quantity)>,
    ) {
        let period = turn_period(&terms);
        self.rows.push(Row {
            element,
            label,
            short,
            unit,
            tier,
            terms,
            offset: 0.0,
            driven: false,
            period,
            function: None,
        });
    }

    fn primitive_rows(&mut self, element: usize, prims: &[Prim], fi: BodyFrame, fj: BodyFrame) {
        let (oi, oj) = (fi.origin(), fj.origin());
        let proj = |e: BodyDir| vec![(1.0, Quantity::Proj { i: oi, j: oj, e })];
        let dot = |a: BodyDir, b: BodyDir| vec![(1.0, Quantity::Dot(a, b))];
        // Translational rows first.
        for p in prims {
            match p {
                Prim::AtPoint => {
                    for k in 0..3 {
                        self.push(
                            element,
                            XG[k],
                            XG_SHORT[k],
                            RowUnit::Length,
                            Tier::Translation,
                            proj(ground_axis(k)),
                        );
                    }
                }
                Prim::InLine => {
                    for k in 0..2 {
                        self.push(
                            element,
                            XJ[k],
                            XJ_SHORT[k],
                            RowUnit::Length,
                            Tier::Translation,
                            proj(fj.axis(k)),
                        );
                    }
                }
                Prim::InPlane => self.push(
                    element,
                    XJ[2],
                    XJ_SHORT[2],
                    RowUnit::Length,
                    Tier::Translation,
                    proj(fj.axis(2)),
                ),
                _ => {}
            }
        }
        let (xi, yi, zi) = (fi.axis(0), fi.axis(1), fi.axis(2));
        let (xj, yj, zj) = (fj.axis(0), fj.axis(1), fj.axis(2));
        let r = Tier::Rotation;
        let d = RowUnit::Direction;
        for p in prims {
            match p {
                Prim::Parallel | Prim::Orientation => {
                    self.push(
                        element,
                        "Rotation Between Zi & Xj",
                        "Zi.Xj",
                        d,
                        r,
                        dot(zi, xj),
                    );
                    self.push(
                        element,
                        "Rotation Between Zi & Yj",
                        "Zi.Yj",
                        d,
                        r,
                        dot(zi, yj),
                    );
                    if *p == Prim::Orientation {
                        self.push(
                            element,
                            "Rotation Between Xi & Yj",
                            "Xi.Yj",
                            d,
                            r,
                            dot(xi, yj),
                        );
                    }
                }
                Prim::Perpendicular => self.push(
                    element,
                    "Rotation Between Zi & Zj",
                    "Zi.Zj",
                    d,
                    r,
                    dot(zi, zj),
                ),
                Prim::Hooke => self.push(
                    element,
                    "Rotation Between Xi & Yj",
                    "Xi.Yj",
                    d,
                    r,
                    dot(xi, yj),
                ),
                Prim::Convel => self.push(
                    element,
                    "Equal Spin About Zi & Zj",
                    "Xi.Yj+Yi.Xj",
                    d,
                    r,
                    vec![(1.0, Quantity::Dot(xi, yj)), (1.0, Quantity::Dot(yi, xj))],
                ),
                _ => {}
            }
        }
    }

    /// Reference axes fixed on frame `fj`'s body that coincide with `fi`'s x and y axes at the
    /// input configuration (rotation of I relative to J measured from the input).
    fn input_refs(&self, fi: BodyFrame, fj: BodyFrame) -> (BodyDir, BodyDir) {
        let (_, ri) = fi.eval(&self.input);
        let rj_body = self.input.pose(fj.body).r;
        let to_body = |v: DVec3| BodyDir {
            body: fj.body,
            v_b: rj_body.transpose() * v,
        };
        (to_body(ri.x_axis), to_body(ri.y_axis))
    }

    /// The two rows of a PTCV ([`crate::constraints::rows::curve_gap`]), their contact started at
    /// the curve point nearest to DISP, or else to the I marker at the input.
    fn curve_rows(
        &mut self,
        element: usize,
        p: &linkage_model::PointOnCurve,
        fi: BodyFrame,
        fm: BodyFrame,
        curve: &Arc<linkage_model::curves::Curve>,
    ) {
        let start = p.disp.unwrap_or_else(|| {
            let (pi, _) = fi.eval(&self.input);
            let (pm, rm) = fm.eval(&self.input);
            rm.transpose() * (pi - pm)
        });
        let contact = Arc::new(Mutex::new(LastContact {
            key: DVec3::NAN,
            params: curve.nearest(start, None),
        }));
        for (axis, label, short) in [
            (0, "Translation of I Marker Normal to Curve", "Si.Nc"),
            (1, "Translation of I Marker Along Curve Binormal", "Si.Bc"),
        ] {
            let q = Quantity::CurveGap(Box::new(CurveGap {
                point: fi.origin(),
                frame: fm,
                curve: Arc::clone(curve),
                axis,
                contact: Arc::clone(&contact),
            }));
            self.push(
                element,
                label,
                short,
                RowUnit::Length,
                Tier::Translation,
                vec![(1.0, q)],
            );
        }
    }

    fn offset_at_input(&self, terms: &[(f64, Quantity)]) -> f64 {
        terms.iter().map(|(c, q)| c * q.value(&self.input)).sum()
    }
}

/// Joint coordinate of a revolute/translational/cylindrical joint: rotation of x_i about z_j
/// from x_j (AZ), or translation of I along z_j (DZ).
fn joint_coordinate(fi: BodyFrame, fj: BodyFrame, dof: CouplerDof) -> Quantity {
    match dof {
        CouplerDof::Rotation => Quantity::Angle {
            x: fi.axis(0),
            x_ref: fj.axis(0),
            y_ref: fj.axis(1),
        },
        CouplerDof::Translation => Quantity::Proj {
            i: fi.origin(),
            j: fj.origin(),
            e: fj.axis(2),
        },
    }
}

impl System {
    /// Compiles the model's constraints at their marker frames.
    pub fn new(model: &Model) -> System {
        let frames: Vec<Option<(BodyFrame, BodyFrame)>> = model
            .constraints
            .iter()
            .map(|c| {
                c.markers()
                    .map(|(i, j)| (marker_frame(model, i), marker_frame(model, j)))
            })
            .collect();
        Self::compile(model, frames)
    }

    /// This system recompiled with the J frames of `elements` replaced by their idealised
    /// frames at state `s` ([`ideal_j_frame`]): the broken joints are analysed as what they are
    /// meant to be.
    pub fn idealized(&self, model: &Model, s: &State, elements: &[usize]) -> System {
        let mut frames = self.frames.clone();
        for &e in elements {
            let kind = match &model.constraints[e].kind {
                ConstraintKind::Joint { kind, .. } => ConstraintKindRef::Joint(*kind),
                ConstraintKind::Jprim { kind, .. } => ConstraintKindRef::Jprim(*kind),
                _ => continue,
            };
            if let Some((fi, fj)) = frames[e] {
                let prims = primitives(kind);
                let (pi, ri) = fi.eval(s);
                let (pj, rj) = fj.eval(s);
                let (pj2, rj2) = ideal_j_frame(prims_mask(prims), (pi, ri), (pj, rj));
                let pose = s.pose(fj.body);
                let rt = pose.r.transpose();
                frames[e] = Some((
                    fi,
                    BodyFrame {
                        body: fj.body,
                        p_b: rt * (pj2 - pose.p),
                        r_b: rt * rj2,
                    },
                ));
            }
        }
        Self::compile(model, frames)
    }

    fn compile(model: &Model, frames: Vec<Option<(BodyFrame, BodyFrame)>>) -> System {
        let mut b = Builder {
            input: State::input(model),
            rows: Vec::with_capacity(model.constraints.len() * 5),
        };
        let mut element_rows = Vec::with_capacity(model.constraints.len());
        let curves: Vec<Arc<linkage_model::curves::Curve>> =
            model.curves.iter().cloned().map(Arc::new).collect();
        for (e, con) in model.constraints.iter().enumerate() {
            let start = b.rows.len();
            match &con.kind {
                ConstraintKind::Joint {
                    kind, pd, pitch, ..
                } => {
                    let Some((fi, fj)) = frames[e] else { continue };
                    b.primitive_rows(e, primitives(ConstraintKindRef::Joint(*kind)), fi, fj);
                    // The translation is measured along z_j from the marker that does not
                    // translate with it: a SCREW's nut (I) moves relative to its screw (J),
                    // a RACKPIN's rack (J) relative to its pinion (I) (module docs).
                    let coupling = match kind {
                        JointType::Rackpin => Some((
                            "Rack Translation = Pinion Rotation × PD/2",
                            "Rackpin",
                            pd.unwrap_or(0.0) / 2.0,
                            Quantity::Proj {
                                i: fj.origin(),
                                j: fi.origin(),
                                e: fj.axis(2),
                            },
                        )),
                        JointType::Screw => Some((
                            "Translation = Rotation × PITCH/2π",
                            "Screw",
                            pitch.unwrap_or(0.0) / std::f64::consts::TAU,
                            Quantity::Proj {
                                i: fi.origin(),
                                j: fj.origin(),
                                e: fj.axis(2),
                            },
                        )),
                        _ => None,
                    };
                    if let Some((label, short, ratio, travel)) = coupling {
                        let (x_ref, y_ref) = b.input_refs(fi, fj);
                        let terms = vec![
                            (1.0, travel),
                            (
                                -ratio,
                                Quantity::Angle {
                                    x: fi.axis(0),
                                    x_ref,
                                    y_ref,
                                },
                            ),
                        ];
                        let offset = b.offset_at_input(&terms);
                        b.push(e, label, short, RowUnit::Length, Tier::Coupling, terms);
                        if let Some(r) = b.rows.last_mut() {
                            r.offset = offset;
                        }
                    }
                }
                ConstraintKind::Jprim { kind, .. } => {
                    let Some((fi, fj)) = frames[e] else { continue };
                    b.primitive_rows(e, primitives(ConstraintKindRef::Jprim(*kind)), fi, fj);
                }
                ConstraintKind::Motion { coordinate, .. } => {
                    let Some((fi, fj)) = frames[e] else { continue };
                    let (label, short, unit, q) = match coordinate {
                        MotionCoordinate::RotationZ => (
                            "Rotation About Zj",
                            "AZ",
                            RowUnit::Angle,
                            joint_coordinate(fi, fj, CouplerDof::Rotation),
                        ),
                        MotionCoordinate::TranslationZ => (
                            "Translation Along Zj",
                            "DZ",
                            RowUnit::Length,
                            joint_coordinate(fi, fj, CouplerDof::Translation),
                        ),
                        MotionCoordinate::Marker(axis) => {
                            let proj = |k: usize| Quantity::Proj {
                                i: fi.origin(),
                                j: fj.origin(),
                                e: fj.axis(k),
                            };
                            let ang = |k: usize| Quantity::euler(fi, fj, EulerSeq::Body123, k);
                            match axis {
                                MotionAxis::X => {
                                    ("Translation Along Xj", "DX", RowUnit::Length, proj(0))
                                }
                                MotionAxis::Y => {
                                    ("Translation Along Yj", "DY", RowUnit::Length, proj(1))
                                }
                                MotionAxis::Z => {
                                    ("Translation Along Zj", "DZ", RowUnit::Length, proj(2))
                                }
                                MotionAxis::B1 => {
                                    ("Body 1-2-3 Angle B1", "B1", RowUnit::Angle, ang(0))
                                }
                                MotionAxis::B2 => {
                                    ("Body 1-2-3 Angle B2", "B2", RowUnit::Angle, ang(1))
                                }
                                MotionAxis::B3 => {
                                    ("Body 1-2-3 Angle B3", "B3", RowUnit::Angle, ang(2))
                                }
                            }
                        }
                    };
                    b.push(e, label, short, unit, Tier::Motion, vec![(1.0, q)]);
                    if let Some(r) = b.rows.last_mut() {
                        r.driven = true;
                        // A rotational motion's single angle (AZ, or an Euler angle): 2π.
                        r.period = (unit == RowUnit::Angle).then_some(std::f64::consts::TAU);
                    }
                }
                ConstraintKind::Coupler { terms, .. } => {
                    let mut qs = Vec::new();
                    for (jt, dof, scale) in terms {
                        if let Some((fi, fj)) = frames[*jt] {
                            qs.push((*scale, joint_coordinate(fi, fj, *dof)));
                        }
                    }
                    let offset = b.offset_at_input(&qs);
                    b.push(
                        e,
                        "Coupled Joint Displacements",
                        "Coupler",
                        RowUnit::Mixed,
                        Tier::Coupling,
                        qs,
                    );
                    if let Some(r) = b.rows.last_mut() {
                        r.offset = offset;
                    }
                }
                ConstraintKind::Gear { joints, cv } => {
                    let (p_cv, r_cv) = model.marker_in_ground(*cv);
                    let z_cv = r_cv.z_axis;
                    let mut qs = Vec::new();
                    for (k, jt) in joints.iter().enumerate() {
                        let Some((fi, fj)) = frames[*jt] else {
                            continue;
                        };
                        let (pj, rj) = fj.eval(&b.input);
                        let is_rev = matches!(
                            model.constraints[*jt].kind,
                            ConstraintKind::Joint {
                                kind: JointType::Revolute,
                                ..
                            }
                        );
                        // Velocity of the gear's material point at CV along z_cv per unit joint
                        // rate: the joint's rate moves I relative to J, so the gear is I unless
                        // I is on the carrier (the CV marker's part), where the gear (J) moves
                        // the other way.
                        let gear_is_j = fi.body == model.markers[*cv].body
                            && fj.body != model.markers[*cv].body;
                        let sense = if gear_is_j { -1.0 } else { 1.0 };
                        let (coef, dof) = if is_rev {
                            (
                                sense * rj.z_axis.cross(p_cv - pj).dot(z_cv),
                                CouplerDof::Rotation,
                            )
                        } else {
                            (sense * rj.z_axis.dot(z_cv), CouplerDof::Translation)
                        };
                        qs.push((
                            if k == 0 { coef } else { -coef },
                            joint_coordinate(fi, fj, dof),
                        ));
                    }
                    let offset = b.offset_at_input(&qs);
                    b.push(
                        e,
                        "Equal Velocity at Contact Point",
                        "Gear",
                        RowUnit::Mixed,
                        Tier::Coupling,
                        qs,
                    );
                    if let Some(r) = b.rows.last_mut() {
                        r.offset = offset;
                    }
                }
                ConstraintKind::Ptcv(p) => {
                    let Some((fi, fm)) = frames[e] else { continue };
                    b.curve_rows(e, p, fi, fm, &curves[p.curve]);
                }
                ConstraintKind::Cvcv(c) => {
                    let Some((fa, fb)) = frames[e] else { continue };
                    let pair = [Arc::clone(&curves[c.icurve]), Arc::clone(&curves[c.jcurve])];
                    for (label, short, q) in curve_curve_rows(c, [fa, fb], pair, &b.input) {
                        b.push(
                            e,
                            label,
                            short,
                            RowUnit::Length,
                            Tier::Coupling,
                            vec![(1.0, q)],
                        );
                    }
                }
                ConstraintKind::FlexNode { body, node } => {
                    for r in flex_rows::node_rows(model, *body, *node) {
                        b.push(e, r.label, r.short, r.unit, r.tier, r.terms);
                    }
                }
                ConstraintKind::Gcon { expr, .. } => {
                    // Unparseable or USER functions are input errors reported by
                    // `drivers::ExpressionDrivers::new`; such a GCON gets no row here.
                    let parsed = expr.as_ref().and_then(|e| e.as_ref().ok());
                    if let Some(expr) = parsed.filter(|e| !e.contains_user()) {
                        b.push(
                            e,
                            "General Constraint Function",
                            "GCON",
                            RowUnit::Mixed,
                            Tier::Coupling,
                            Vec::new(),
                        );
                        if let Some(r) = b.rows.last_mut() {
                            r.function = Some(Arc::clone(expr));
                        }
                    }
                }
            }
            element_rows.push(start..b.rows.len());
        }
        System {
            nparts: model.parts.len(),
            rows: b.rows,
            element_rows,
            frames,
            markers: Arc::new(MarkerFrames::new(model)),
        }
    }

    /// `Φ_r` at state `s`; `drive` is `f(t)` for motion rows (ignored otherwise).
    pub fn residual(&self, r: usize, s: &State, drive: f64) -> f64 {
        let row = &self.rows[r];
        let mut v: f64 = row.terms.iter().map(|(c, q)| c * q.value(s)).sum::<f64>() - row.offset;
        if let Some(f) = &row.function {
            v += evaluate(
                f,
                &PositionEnv {
                    frames: &self.markers,
                    state: s,
                },
            )
            .unwrap_or(f64::NAN);
        }
        if row.driven {
            v -= drive;
        }
        if let Some(p) = row.period {
            v = wrap_period(v, p);
        }
        v
    }

    /// `∂Φ_r/∂q` at state `s`, written into `g` (cleared first).
    pub fn gradient(&self, r: usize, s: &State, g: &mut RowGradient) {
        g.clear();
        for (c, q) in &self.rows[r].terms {
            q.gradient(s, *c, g);
        }
        if let Some(f) = &self.rows[r].function {
            if let Ok(d) = evaluate_with_gradient(
                f,
                &PositionEnv {
                    frames: &self.markers,
                    state: s,
                },
            ) {
                add_dual_gradient(&d, 1.0, g);
            }
        }
    }
}

impl System {
    /// `∂Φ_r/∂t` at fixed positions, without a motion's drive (the caller adds `ḟ(t)`): the
    /// explicit time dependence of a general constraint's expression, TIME advancing at
    /// `time_rate` (0 freezes it); 0 for every other row. The velocity equations are
    /// `∇Φ_r·v = ḟ(t) − explicit_rate`.
    pub fn explicit_rate(&self, r: usize, s: &State, time_rate: f64) -> Result<f64, EvalError> {
        let Some(f) = &self.rows[r].function else {
            return Ok(0.0);
        };
        if time_rate == 0.0 || !f.uses_time() {
            return Ok(0.0);
        }
        let still = vec![(DVec3::ZERO, DVec3::ZERO); self.nparts];
        let env = PathEnv {
            frames: &self.markers,
            state: s,
            velocities: &still,
            accelerations: None,
            time_rate,
        };
        Ok(evaluate_path_series(f, &env)?[1])
    }

    /// The velocity-product term `γ_r` of `Φ̈_r = ∇Φ_r·a + γ_r − f̈(t)` (a motion's `f̈` is the
    /// caller's): `Σ c_k Q̈_k` of the geometric terms at zero accelerations
    /// ([`Quantity::rates`]) plus, for a general constraint, the second derivative of its
    /// expression along the twists `v` with zero accelerations and TIME advancing at
    /// `time_rate` (`vᵀ∇²f v + 2 ṫ ∇f_t·v + ṫ² f_tt`, [`PathEnv`]). Exact: with it the
    /// acceleration equations `∇Φ·a = f̈ − γ` hold to rounding.
    pub fn acceleration_bias(
        &self,
        r: usize,
        s: &State,
        v: &Velocities,
        time_rate: f64,
    ) -> Result<f64, EvalError> {
        let row = &self.rows[r];
        let mut bias: f64 = row.terms.iter().map(|(c, q)| c * q.rates(s, v).1).sum();
        if let Some(f) = &row.function {
            let env = PathEnv {
                frames: &self.markers,
                state: s,
                velocities: v,
                accelerations: None,
                time_rate,
            };
            bias += evaluate_path_series(f, &env)?[2];
        }
        Ok(bias)
    }
}

/// Wraps `v` to (−P/2, P/2] modulo the period `P`.
pub fn wrap_period(v: f64, period: f64) -> f64 {
    let w = v - period * (v / period).round();
    if w <= -0.5 * period {
        w + period
    } else {
        w
    }
}

/// Largest ratio between an angle coefficient of a row and the gcd of them all for which the
/// row's turns are resolved ([`turn_period`]): gear and coupler ratios are ratios of small
/// tooth counts. The residual then wraps at ±P/2, which the faster joint reaches only
/// π/MAX_TURN_RATIO (1.8°) away from the solution: a Newton iterate straying further would
/// land on another mesh of the gears, so the period is not allowed to shrink below that.
pub const MAX_TURN_RATIO: f64 = 100.0;

/// The period of a row's residual `Σ c_k Q_k` due to the turns of its angle terms
/// ([`Quantity::Angle`]: a joint's rotation, measured by atan2 and so known only modulo 2π).
/// Adding a turn to term k changes the residual by 2π·c_k, so the residual is defined modulo
/// the lattice {2π Σ c_k n_k} = 2π·gcd(|c_k|)·ℤ when the coefficients are commensurate. That
/// lattice is exactly the set of poses the coupled joints reach by turning: a SCREW's nut is at
/// any whole number of pitches along its rotation, gears with ratio 2 mesh again every half
/// turn of the larger one. With one angle term (SCREW, RACKPIN, a rotation coupled to a
/// translation) the period is 2π·|c|. Coefficients whose ratio is not a ratio of integers up to
/// [`MAX_TURN_RATIO`] (to 1e-9) have no period: their turns cannot be told from a pose (the
/// state carries no turn count), and such a coupling holds only while its angles stay within
/// ±180°.
pub fn turn_period(terms: &[(f64, Quantity)]) -> Option<f64> {
    let mut g: Option<f64> = None;
    for (c, q) in terms {
        if matches!(q, Quantity::Angle { .. }) && *c != 0.0 {
            g = Some(match g {
                None => c.abs(),
                Some(g) => commensurate_gcd(g, c.abs())?,
            });
        }
    }
    g.map(|g| std::f64::consts::TAU * g)
}

/// The greatest common divisor of two positive reals by Euclid's algorithm, remainders within
/// 1e-9 of the larger taken as zero; `None` when it falls below 1/[`MAX_TURN_RATIO`] of it.
fn commensurate_gcd(a: f64, b: f64) -> Option<f64> {
    let (mut a, mut b) = (a.max(b), a.min(b));
    let tol = 1e-9 * a;
    let floor = a / MAX_TURN_RATIO;
    while b > tol {
        if b < floor {
            return None;
        }
        let r = a % b;
        a = b;
        b = if r <= tol || b - r <= tol { 0.0 } else { r };
    }
    Some(a)
}

/// Wraps an angle to (−π, π].
pub fn wrap_angle(a: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let w = a - tau * (a / tau).round();
    if w <= -std::f64::consts::PI {
        w + tau
    } else {
        w
    }
}

/// Which primitive groups constrain position and orientation.
#[derive(Clone, Copy, Default)]
pub struct PrimMask {
    at_point: bool,
    in_line: bool,
    in_plane: bool,
    parallel: bool,
    perpendicular: bool,
    orientation: bool,
    hooke: bool,
}

fn prims_mask(prims: &[Prim]) -> PrimMask {
    let mut m = PrimMask::default();
    for p in prims {
        match p {
            Prim::AtPoint => m.at_point = true,
            Prim::InLine => m.in_line = true,
            Prim::InPlane => m.in_plane = true,
            Prim::Parallel => m.parallel = true,
            Prim::Perpendicular => m.perpendicular = true,
            Prim::Orientation => m.orientation = true,
            Prim::Hooke => m.hooke = true,
            Prim::Convel => {}
        }
    }
    m
}

/// The J frame moved as little as possible so that the element's own equations hold relative
/// to the I frame (both in ground): position — the constrained components of `P_I − P_J`
/// are removed; orientation — the J axes are turned by the smallest rotation that satisfies
/// the rotational rows.
pub fn ideal_j_frame(
    m: PrimMask,
    (pi, ri): (DVec3, DMat3),
    (pj, rj): (DVec3, DMat3),
) -> (DVec3, DMat3) {
    let d = pi - pj;
    let zj = rj.z_axis;
    let p = if m.at_point {
        pi
    } else if m.in_line {
        pj + (d - zj * d.dot(zj))
    } else if m.in_plane {
        pj + zj * d.dot(zj)
    } else {
        pj
    };
    let turn = |from: DVec3, to: DVec3| {
        DMat3::from_quat(DQuat::from_rotation_arc(from.normalize(), to.normalize()))
    };
    let r = if m.orientation {
        ri
    } else if m.parallel {
        turn(zj, ri.z_axis) * rj
    } else if m.perpendicular {
        let zi = ri.z_axis;
        let target = zj - zi * zj.dot(zi);
        if target.length() > ALIGNMENT_DIRECTION {
            turn(zj, target) * rj
        } else {
            rj
        }
    } else if m.hooke {
        let xi = ri.x_axis;
        let yj = rj.y_axis;
        let target = yj - xi * yj.dot(xi);
        if target.length() > ALIGNMENT_DIRECTION {
            turn(yj, target) * rj
        } else {
            rj
        }
    } else {
        rj
    };
    (p, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_angle_range() {
        use std::f64::consts::PI;
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5) - 0.5).abs() < 1e-15);
        assert!((wrap_angle(2.0 * PI + 0.25) - 0.25).abs() < 1e-12);
    }

    #[test]
    fn turn_periods_are_the_lattice_of_the_angle_coefficients() {
        use std::f64::consts::TAU;
        let frame = BodyFrame {
            body: Body::Ground,
            p_b: DVec3::ZERO,
            r_b: DMat3::IDENTITY,
        };
        let a = || joint_coordinate(frame, frame, CouplerDof::Rotation);
        let proj = || joint_coordinate(frame, frame, CouplerDof::Translation);
        // SCREW: translation − PITCH/2π · angle: one pitch.
        let p = turn_period(&[(1.0, proj()), (-0.02 / TAU, a())]).unwrap();
        assert!((p - 0.02).abs() < 1e-15, "{p}");
        // Ratio 2 (and its rounding): half a turn of the first joint.
        let p = turn_period(&[(1.0, a()), (-0.5, a())]).unwrap();
        assert!((p - TAU / 2.0).abs() < 1e-15, "{p}");
        let p = turn_period(&[(0.1, a()), (-0.19999999999999998, a())]).unwrap();
        assert!((p - 0.1 * TAU).abs() < 1e-12, "{p}");
        // 3:2.
        let p = turn_period(&[(3.0, a()), (2.0, a())]).unwrap();
        assert!((p - TAU).abs() < 1e-12, "{p}");
        // Incommensurate, and no angle at all.
        assert_eq!(turn_period(&[(1.0, a()), (-0.333333, a())]), None);
        assert_eq!(
            turn_period(&[(1.0, a()), (std::f64::consts::SQRT_2, a())]),
            None
        );
        assert_eq!(turn_period(&[(1.0, proj())]), None);
        // Wrapping into (−P/2, P/2].
        assert!((wrap_period(0.75, 1.0) + 0.25).abs() < 1e-15);
        assert!((wrap_period(-0.5, 1.0) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn ideal_frame_satisfies_revolute_rows() {
        let ri = DMat3::from_rotation_x(0.3);
        let rj = DMat3::from_rotation_y(0.05) * DMat3::from_rotation_z(1.0);
        let m = PrimMask {
            at_point: true,
            parallel: true,
            ..Default::default()
        };
        let (p, r) = ideal_j_frame(m, (DVec3::new(1.0, 2.0, 3.0), ri), (DVec3::ZERO, rj));
        assert!((p - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-14);
        assert!(ri.z_axis.dot(r.x_axis).abs() < 1e-12 && ri.z_axis.dot(r.y_axis).abs() < 1e-12);
    }
}
