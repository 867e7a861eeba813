//! The immutable model: what every analysis reads.

pub use crate::bodies::{Body, Marker, Origin, Part};
use crate::units::Units;
use glam::{DMat3, DVec3};
use linkage_adm::{
    CouplerDof, Function, JointType, JprimType, Located, MotionAxis, MotionLevel, Span,
};
use std::sync::Arc;

/// Joint initial conditions: displacement and velocity of the joint coordinate(s).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointInitial {
    /// Translation along z_j: (displacement, velocity), each optional.
    pub translation: (Option<f64>, Option<f64>),
    /// Rotation about z_j in radians: (displacement, velocity).
    pub rotation: (Option<f64>, Option<f64>),
    pub span: Option<Span>,
}

/// The coordinate a motion drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionCoordinate {
    /// Angle of x_i about z_j measured from x_j (AZ(I,J)).
    RotationZ,
    /// Displacement of I's origin along z_j (DZ(I,J,J)).
    TranslationZ,
    /// Marker-form motions: translations of I along J's axes, or body 1-2-3 angles of I in J.
    Marker(MotionAxis),
}

/// Every constraint element.
#[derive(Clone, Debug, PartialEq)]
pub enum ConstraintKind {
    Joint {
        kind: JointType,
        i: usize,
        j: usize,
        initial: JointInitial,
        pd: Option<f64>,
        pitch: Option<f64>,
    },
    Jprim {
        kind: JprimType,
        i: usize,
        j: usize,
    },
    Motion {
        /// The joint it drives (index into [`Model::constraints`]), for joint-form motions.
        joint: Option<usize>,
        i: usize,
        j: usize,
        coordinate: MotionCoordinate,
        level: MotionLevel,
        function: Option<Located<Function>>,
        icdisp: Option<f64>,
        icvel: Option<f64>,
    },
    Coupler {
        /// (joint constraint index, coordinate used, scale r_k).
        terms: Vec<(usize, CouplerDof, f64)>,
        function: Option<Located<Function>>,
    },
    Gear {
        joints: [usize; 2],
        cv: usize,
    },
    /// The six node equations of a FLEX_BODY node ([`crate::flex_bodies`]): node body `node`
    /// of [`Model::flex_bodies`]`[body]` follows the reference body and the mode bodies.
    FlexNode {
        body: usize,
        node: usize,
    },
    Gcon {
        i: usize,
        function: Option<Located<Function>>,
        /// The FUNCTION parsed, once, for every analysis (the function check of the analyses
        /// reports a parse error with its place in the text).
        expr: Option<Result<Arc<linkage_expr::Expr>, linkage_expr::ParseError>>,
    },
    /// PTCV: the origin of fixed marker `i` kept on curve `curve` (index into
    /// [`Model::curves`]) carried by marker `rm` (the curve's frame) on another body
    /// ([`crate::curves`]). Removes 2 degrees of freedom.
    Ptcv(Box<PointOnCurve>),
    /// CVCV: planar curve `icurve` carried by marker `irm` kept in contact with, and tangent
    /// to, planar curve `jcurve` carried by marker `jrm` on another body ([`crate::curves`]).
    /// Removes 2 degrees of freedom.
    Cvcv(Box<CurveOnCurve>),
}

/// A CVCV's markers, curves and initial conditions (ADM-ELEMENTS §16). The I side is curve
/// `icurve` in the frame of marker `irm`, the J side curve `jcurve` in the frame of `jrm`.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveOnCurve {
    pub irm: usize,
    pub jrm: usize,
    /// The floating markers on IRM's and JRM's bodies that mark the contact point.
    pub ifloat: usize,
    pub jfloat: usize,
    /// Indices into [`Model::curves`].
    pub icurve: usize,
    pub jcurve: usize,
    /// IDISP, JDISP: initial contact point guesses, converted into the IRM and JRM frames.
    pub idisp: Option<DVec3>,
    pub jdisp: Option<DVec3>,
    /// IVEL, JVEL: the initial speeds of the contact point along each curve's tangent
    /// (dα/dt·|c_I'|, dβ/dt·|c_J'|).
    pub ivel: Option<f64>,
    pub jvel: Option<f64>,
}

/// A PTCV's markers, curve and initial conditions.
#[derive(Clone, Debug, PartialEq)]
pub struct PointOnCurve {
    /// The point (a fixed marker).
    pub i: usize,
    /// The marker whose frame the curve's coordinates are in.
    pub rm: usize,
    /// The floating marker on RM's body that marks the contact point.
    pub jfloat: usize,
    /// Index into [`Model::curves`].
    pub curve: usize,
    /// DISP: the initial contact point guess, converted into the RM frame (the curve point
    /// nearest to it starts the contact).
    pub disp: Option<DVec3>,
    /// VEL: the initial sliding speed along the tangent (dα/dt·|c'|).
    pub vel: Option<f64>,
}

/// A constraint element and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Constraint {
    pub origin: Origin,
    pub kind: ConstraintKind,
}

/// Statement keyword of a point mass's rotation hold (its origin is the POINT_MASS statement).
pub const POINT_MASS_STATEMENT: &str = "POINT_MASS";

impl Constraint {
    /// Human description in Adams View style: `Revolute Joint`, `Inline Primitive`,
    /// `Rotational Motion`, `Coupler`, `Gear`, `General Constraint`.
    pub fn description(&self) -> &'static str {
        if self.origin.statement == POINT_MASS_STATEMENT {
            return "Point Mass Rotation Hold";
        }
        if self.origin.statement == crate::fe_parts::FE_PART_STATEMENT {
            return "Cable Node Rotation Hold";
        }
        if self.origin.statement == crate::flex_bodies::FLEX_BODY_STATEMENT {
            return match self.kind {
                ConstraintKind::FlexNode { .. } => "Flex Body Node",
                _ => "Flex Body Mode Guide",
            };
        }
        match &self.kind {
            ConstraintKind::Joint { kind, .. } => joint_description(*kind),
            ConstraintKind::Jprim { kind, .. } => jprim_description(*kind),
            ConstraintKind::Motion { coordinate, .. } => match coordinate {
                MotionCoordinate::RotationZ => "Rotational Motion",
                MotionCoordinate::TranslationZ => "Translational Motion",
                MotionCoordinate::Marker(MotionAxis::X | MotionAxis::Y | MotionAxis::Z) => {
                    "Translational Motion"
                }
                MotionCoordinate::Marker(_) => "Rotational Motion",
            },
            ConstraintKind::Coupler { .. } => "Coupler",
            ConstraintKind::Gear { .. } => "Gear",
            ConstraintKind::Gcon { .. } => "General Constraint",
            ConstraintKind::Ptcv(_) => "Point-Curve Constraint",
            ConstraintKind::Cvcv(_) => "Curve-Curve Constraint",
            ConstraintKind::FlexNode { .. } => "Flex Body Node",
        }
    }

    /// The two markers of a joint, primitive or motion (a PTCV's I and RM, a CVCV's IRM and
    /// JRM).
    pub fn markers(&self) -> Option<(usize, usize)> {
        match &self.kind {
            ConstraintKind::Joint { i, j, .. }
            | ConstraintKind::Jprim { i, j, .. }
            | ConstraintKind::Motion { i, j, .. } => Some((*i, *j)),
            ConstraintKind::Ptcv(p) => Some((p.i, p.rm)),
            ConstraintKind::Cvcv(c) => Some((c.irm, c.jrm)),
            _ => None,
        }
    }
}

/// `Revolute Joint`: the joint type's keyword in title case (a table: verify names every
/// redundant row of a large model with it).
fn joint_description(kind: JointType) -> &'static str {
    match kind {
        JointType::Convel => "Convel Joint",
        JointType::Cylindrical => "Cylindrical Joint",
        JointType::Fixed => "Fixed Joint",
        JointType::Hooke => "Hooke Joint",
        JointType::Planar => "Planar Joint",
        JointType::Rackpin => "Rackpin Joint",
        JointType::Revolute => "Revolute Joint",
        JointType::Screw => "Screw Joint",
        JointType::Spherical => "Spherical Joint",
        JointType::Translational => "Translational Joint",
        JointType::Universal => "Universal Joint",
    }
}

/// `Parallel Axes Primitive`: the primitive's keyword in title case.
fn jprim_description(kind: JprimType) -> &'static str {
    match kind {
        JprimType::Atpoint => "Atpoint Primitive",
        JprimType::Inline => "Inline Primitive",
        JprimType::Inplane => "Inplane Primitive",
        JprimType::Orientation => "Orientation Primitive",
        JprimType::ParallelAxes => "Parallel Axes Primitive",
        JprimType::Perpendicular => "Perpendicular Primitive",
    }
}

/// The mechanical model.
#[derive(Clone, Debug)]
pub struct Model {
    pub file: Arc<str>,
    pub title: String,
    pub units: Units,
    /// Gravity in model length/time² (ground axes).
    pub gravity: DVec3,
    /// Display name of the ground part.
    pub ground_name: String,
    /// Moving parts (ground excluded).
    pub parts: Vec<Part>,
    pub markers: Vec<Marker>,
    /// Joints, primitives, motions, couplers, gears, general constraints, PTCVs and CVCVs, in that order of
    /// kinds and in definition order within each kind, then one rotation hold per point mass
    /// (an ORIENTATION primitive to ground whose origin is the POINT_MASS statement).
    pub constraints: Vec<Constraint>,
    /// SFORCE, SPRINGDAMPER, BUSHING, FIELD, BEAM, VFORCE, VTORQUE and GFORCE elements, in
    /// that order of kinds and in definition order within each kind ([`crate::forces`]).
    pub forces: Vec<crate::forces::ForceElement>,
    /// VARIABLE elements (referenced by `VARVAL(id)` and ARRAY `VARIABLES`).
    pub variables: Vec<crate::forces::Variable>,
    /// ARRAY elements (referenced by `ARYVAL(id, n)`).
    pub arrays: Vec<crate::forces::Array>,
    /// SPLINE elements (referenced by `AKISPL`/`CUBSPL`).
    pub splines: Vec<crate::forces::Spline>,
    /// SENSOR elements (evaluated by dynamic runs; `SENVAL(id)`).
    pub sensors: Vec<crate::sensors::Sensor>,
    /// FRICTION elements on joints ([`crate::friction`]).
    pub frictions: Vec<crate::friction::Friction>,
    /// DIFF, LSE, TFSISO states, MATRIX data and PINPUT/POUTPUT lists.
    pub controls: crate::controls::Controls,
    /// `IC/` settings (Adams defaults where not given).
    pub ic: crate::settings::IcSettings,
    /// `EQUILIBRIUM/` settings.
    pub equilibrium: crate::settings::EquilibriumSettings,
    /// `INTEGRATOR/` resolved: HHT's settings and what `simulate` notes and warns about.
    pub integrator: crate::settings::ResolvedIntegrator,
    /// Characteristic length: diagonal of the bounding box of markers and centres of mass
    /// (1 if that is zero). Tolerances on lengths are relative to it.
    pub characteristic_length: f64,
    /// The REQUESTs, resolved (their problems are reported by the analyses that write
    /// REQUEST columns).
    pub requests: crate::requests::Requests,
    /// Display geometry (GRAPHICS) on the markers; changes no result.
    pub graphics: Vec<crate::graphics::Graphic>,
    /// FE_PARTs: their nodes are parts (after the dataset's parts and point masses), their
    /// elements force elements ([`crate::fe_parts`]).
    pub fe_parts: Vec<crate::fe_parts::FePart>,
    /// CURVEs given by a MATRIX (read by PTCV and CVCV; [`crate::curves`]).
    pub curves: Vec<crate::curves::Curve>,
    /// FLEX_BODYs: their reference, mode and node bodies are parts (after the FE nodes),
    /// their node equations constraints, their modal stiffness and damping bushings
    /// ([`crate::flex_bodies`]).
    pub flex_bodies: Vec<crate::flex_bodies::FlexBody>,
    /// The linker of the `USER(…)` calls (none unless the user gave subroutine libraries).
    pub user: crate::functions::UserRoutines,
}

impl Model {
    /// Units consistency factor.
    pub fn ucf(&self) -> f64 {
        self.units.ucf()
    }

    /// Marker pose in ground at the input configuration.
    pub fn marker_in_ground(&self, m: usize) -> (DVec3, DMat3) {
        let mk = &self.markers[m];
        match mk.body {
            Body::Ground => (mk.p_bm, mk.r_bm),
            Body::Part(k) => {
                let p = &self.parts[k];
                (p.p_gb + p.r_gb * mk.p_bm, p.r_gb * mk.r_bm)
            }
        }
    }

    /// The FE part and node (indices into [`Model::fe_parts`] and its `nodes`) of part `k`,
    /// when part k is an FE node.
    pub fn fe_node(&self, k: usize) -> Option<(usize, usize)> {
        let first = self.fe_parts.first()?.nodes.first()?.part;
        if k < first {
            return None;
        }
        self.fe_parts
            .iter()
            .enumerate()
            .find_map(|(f, p)| p.node_of_part(k).map(|n| (f, n)))
    }

    /// The nodes of FE part `f` that markers of the dataset are on (indices into its
    /// `nodes`, ascending): the boundary of its Craig–Bampton partition.
    pub fn fe_marker_nodes(&self, f: usize) -> Vec<usize> {
        let p = &self.fe_parts[f];
        let mut out: Vec<usize> = self
            .markers
            .iter()
            .filter(|m| m.id != 0)
            .filter_map(|m| p.node_of_part(m.body.part()?))
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The flex body (index into [`Model::flex_bodies`]) part `k` belongs to (its reference,
    /// a mode body or a node body), if any.
    pub fn flex_body_of(&self, k: usize) -> Option<usize> {
        let first = self.flex_bodies.first()?.reference;
        if k < first {
            return None;
        }
        self.flex_bodies
            .iter()
            .position(|b| b.parts().any(|p| p == k))
    }

    /// Display name of a body.
    pub fn body_name(&self, b: Body) -> &str {
        match b {
            Body::Ground => &self.ground_name,
            Body::Part(k) => &self.parts[k].origin.name,
        }
    }

    /// Bodies an element connects (ground included as [`Body::Ground`]).
    pub fn constraint_bodies(&self, c: usize) -> Vec<Body> {
        let con = &self.constraints[c];
        let mut out = Vec::new();
        let mut add = |b: Body| {
            if !out.contains(&b) {
                out.push(b)
            }
        };
        match &con.kind {
            ConstraintKind::Joint { i, j, .. }
            | ConstraintKind::Jprim { i, j, .. }
            | ConstraintKind::Motion { i, j, .. } => {
                add(self.markers[*i].body);
                add(self.markers[*j].body);
            }
            ConstraintKind::Ptcv(p) => {
                add(self.markers[p.i].body);
                add(self.markers[p.rm].body);
            }
            ConstraintKind::Cvcv(c) => {
                add(self.markers[c.irm].body);
                add(self.markers[c.jrm].body);
            }
            ConstraintKind::Coupler { terms, .. } => {
                for (jt, _, _) in terms {
                    if let Some((i, j)) = self.constraints[*jt].markers() {
                        add(self.markers[i].body);
                        add(self.markers[j].body);
                    }
                }
            }
            ConstraintKind::Gear { joints, cv } => {
                for jt in joints {
                    if let Some((i, j)) = self.constraints[*jt].markers() {
                        add(self.markers[i].body);
                        add(self.markers[j].body);
                    }
                }
                add(self.markers[*cv].body);
            }
            ConstraintKind::Gcon { i, .. } => {
                add(self.markers[*i].body);
                add(Body::Ground);
            }
            ConstraintKind::FlexNode { body, node } => {
                let b = &self.flex_bodies[*body];
                add(Body::Part(b.nodes[*node].part));
                add(Body::Part(b.reference));
                for m in &b.modes {
                    add(Body::Part(m.part));
                }
            }
        }
        out
    }
}
