//! POINT_MASS (ADM-ELEMENTS §13) in the model: a point mass is a moving body with three
//! translational degrees of freedom. It is built as a [`Part`] with zero inertia whose
//! orientation is held at the input by an ORIENTATION primitive to ground (three rotation
//! equations, `z_i·x_j = z_i·y_j = x_i·y_j = 0`), so every analysis treats it with the same
//! rows, Jacobians and mass matrix as any part: `6 − 3 = 3` degrees of freedom per point mass,
//! and no rotational inertia is ever needed (ω ≡ 0).
//!
//! A point mass carries translational loads only and can only be constrained in translation
//! (as in Adams: ACCGRAV, translational SFORCE and SPRINGDAMPER, VFORCE; SPHERICAL, ATPOINT,
//! INLINE, INPLANE, translational motions, GCON). An element that would turn or constrain the
//! rotation of a point mass is an error at its statement, naming it and the point mass.

use super::context::Ctx;
use crate::bodies::{Body, Marker, Part};
use crate::forces::{ForceElement, ForceKind, VectorKind};
use crate::model::{Constraint, ConstraintKind, MotionCoordinate};
use glam::{DMat3, DVec3};
use linkage_adm::{ForceDof, JointType, JprimType, MotionAxis};

/// Statement keyword of the rotation hold's origin (it is the POINT_MASS statement).
pub use crate::model::POINT_MASS_STATEMENT as POINT_MASS;

/// Whether constraint `c` is the rotation hold of a point mass (not a dataset element).
pub fn is_rotation_hold(c: &Constraint) -> bool {
    c.origin.statement == POINT_MASS || c.origin.statement == crate::fe_parts::FE_PART_STATEMENT
}

/// Appends, for every point mass, two markers (one at its centre of mass with its body axes,
/// one on ground with the same pose at the input; both id 0, which no dataset marker has) and
/// the ORIENTATION primitive between them. Called after every dataset constraint is built, so
/// dataset constraints keep their indices.
pub(crate) fn hold_rotations(
    parts: &[Part],
    markers: &mut Vec<Marker>,
    constraints: &mut Vec<Constraint>,
) {
    for (k, p) in parts.iter().enumerate() {
        if !p.point_mass {
            continue;
        }
        let i = markers.len();
        markers.push(Marker {
            id: 0,
            name: format!("{}.held_axes", p.origin.name),
            span: p.origin.span,
            body: Body::Part(k),
            p_bm: DVec3::ZERO,
            r_bm: DMat3::IDENTITY,
            floating: false,
        });
        markers.push(Marker {
            id: 0,
            name: format!("{}.ground_axes", p.origin.name),
            span: p.origin.span,
            body: Body::Ground,
            p_bm: p.p_gb,
            r_bm: p.r_gb,
            floating: false,
        });
        constraints.push(Constraint {
            origin: p.origin.clone(),
            kind: ConstraintKind::Jprim {
                kind: JprimType::Orientation,
                i,
                j: i + 1,
            },
        });
    }
}

/// Errors for every constraint that would constrain, and every force that would turn, a point
/// mass (at the element's statement, naming the element and the point mass).
pub(crate) fn check_translational_use(
    parts: &[Part],
    markers: &[Marker],
    constraints: &[Constraint],
    forces: &[ForceElement],
    cx: &mut Ctx,
) {
    if !parts.iter().any(|p| p.point_mass) {
        return;
    }
    let point_mass_of = |m: usize| -> Option<&str> {
        let k = markers.get(m)?.body.part()?;
        parts[k].point_mass.then(|| parts[k].origin.name.as_str())
    };
    for c in constraints {
        let Some((i, j)) = c.markers() else {
            continue;
        };
        let Some(pm) = point_mass_of(i).or_else(|| point_mass_of(j)) else {
            continue;
        };
        if constrains_rotation(&c.kind) {
            let msg = format!(
                "{}: a {} constrains rotations, but {pm} is a POINT_MASS, which has only \
                 translations (use SPHERICAL, ATPOINT, INLINE, INPLANE or a translational motion)",
                c.origin.name,
                c.description()
            );
            cx.error(c.origin.span, msg);
        }
    }
    for f in forces {
        let (markers_used, turns): (Vec<usize>, bool) = match &f.kind {
            ForceKind::Sforce(s) => (vec![s.i, s.j], s.dof == ForceDof::Rotational),
            ForceKind::SpringDamper(s) => (vec![s.i, s.j], s.dof == ForceDof::Rotational),
            ForceKind::Bushing(b) => (vec![b.i, b.j], true),
            ForceKind::Field(x) => (vec![x.i, x.j], true),
            ForceKind::Beam(b) => (vec![b.i, b.j], true),
            ForceKind::Vector(v) => (vec![v.i, v.jfloat], v.kind != VectorKind::Vforce),
            // Forces at contact points; a point mass's rotation hold takes their moments.
            ForceKind::Contact(c) => (vec![c.i, c.j], false),
        };
        if !turns {
            continue;
        }
        if let Some(pm) = markers_used.iter().find_map(|&m| point_mass_of(m)) {
            let msg = format!(
                "{}: applies torques, but {pm} is a POINT_MASS, which carries only forces \
                 (use a translational SFORCE or SPRINGDAMPER, or a VFORCE)",
                f.origin.name
            );
            cx.error(f.origin.span, msg);
        }
    }
}

/// Whether a two-marker constraint removes a rotational freedom between its bodies.
fn constrains_rotation(kind: &ConstraintKind) -> bool {
    match kind {
        ConstraintKind::Joint { kind, .. } => *kind != JointType::Spherical,
        ConstraintKind::Jprim { kind, .. } => matches!(
            kind,
            JprimType::Orientation | JprimType::ParallelAxes | JprimType::Perpendicular
        ),
        ConstraintKind::Motion { coordinate, .. } => match coordinate {
            MotionCoordinate::RotationZ => true,
            MotionCoordinate::TranslationZ => false,
            MotionCoordinate::Marker(a) => {
                !matches!(a, MotionAxis::X | MotionAxis::Y | MotionAxis::Z)
            }
        },
        _ => false,
    }
}
