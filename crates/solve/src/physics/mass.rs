//! Mass properties of the parts in ground axes, and the one policy for parts whose mass matrix
//! is singular. Every analysis that needs `M`, `R I Rᵀ` or the gyroscopic load takes it from
//! here.
//!
//! A part's 6×6 mass matrix in the coordinates the analyses use (CM velocity and angular
//! velocity, both in ground axes) is `diag(m·𝟙, R I Rᵀ)`, where `I` is the inertia about the CM
//! in body axes and `R` the body's orientation.

use crate::constraints::rows::Velocities;
use crate::state::{Pose, State};
use crate::tolerances::{
    INERTIA_REGULARISATION, MASSLESS_FRACTION, MASSLESS_PART_MASS, SINGULAR_INERTIA_RATIO,
};
use glam::{DMat3, DVec3};
use linkage_model::{Model, Part};

/// The inertia about the CM in ground axes: `R I Rᵀ`.
#[inline]
pub fn ground_inertia(part: &Part, pose: &Pose) -> DMat3 {
    pose.r * part.inertia * pose.r.transpose()
}

/// The gyroscopic load `−ω × (I_g ω)` of a part turning at `w` (ground axes).
#[inline]
pub fn gyroscopic(inertia_ground: &DMat3, w: DVec3) -> DVec3 {
    -w.cross(*inertia_ground * w)
}

/// Kinetic energy `½ m v·v + ½ ω·(I_g ω)` (model mass × length² / time²).
#[inline]
pub fn kinetic_energy(part: &Part, pose: &Pose, v: DVec3, w: DVec3) -> f64 {
    0.5 * part.mass * v.length_squared() + 0.5 * w.dot(ground_inertia(part, pose) * w)
}

/// Whether a part's inertia about its CM is singular (a point mass, a massless part, a rod
/// with no moment about its axis): [`SINGULAR_INERTIA_RATIO`].
pub fn singular_inertia(part: &Part) -> bool {
    let i = &part.inertia;
    let trace = i.x_axis.x + i.y_axis.y + i.z_axis.z;
    trace <= 0.0 || i.determinant() <= SINGULAR_INERTIA_RATIO * (trace / 3.0).powi(3)
}

/// The regularisation added to every diagonal entry of a part's rotational mass block where the
/// analysis needs a regular mass matrix: `INERTIA_REGULARISATION · m · L²` for a part with
/// singular inertia (with `m` = [`MASSLESS_PART_MASS`] for a massless part), 0 otherwise.
/// Constrained directions are unaffected; a free direction without inertia gets a tiny one.
pub fn rotational_regularisation(part: &Part, length: f64) -> f64 {
    if !singular_inertia(part) {
        return 0.0;
    }
    let mass = if part.mass > 0.0 {
        part.mass
    } else {
        MASSLESS_PART_MASS
    };
    INERTIA_REGULARISATION * mass * length * length
}

/// What a solve of the equations of motion does with a part whose inertia is singular (a
/// massless part, a point mass, a rod): the one policy every stage follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SingularInertia {
    /// Solve with the exact mass matrix: a direction the constraints leave free and that has no
    /// inertia makes the solve singular, which the caller reports. The initial conditions do
    /// this, as Adams does before a dynamic run.
    Report,
    /// Add [`rotational_regularisation`] to the rotational diagonal, so that the run goes on:
    /// the integrator and its consistent outputs.
    Regularise,
}

impl SingularInertia {
    /// The amount added to each rotational diagonal entry of `part` (0 with
    /// [`SingularInertia::Report`] and for every part with regular inertia).
    pub fn rotational(self, part: &Part, length: f64) -> f64 {
        match self {
            SingularInertia::Report => 0.0,
            SingularInertia::Regularise => rotational_regularisation(part, length),
        }
    }
}

/// The mass and inertia given to parts that have none where a linearized model needs a regular
/// mass matrix (Adams' rule for LINEAR): [`MASSLESS_FRACTION`] × the smallest nonzero part
/// mass, and [`MASSLESS_FRACTION`] × the smallest nonzero principal moment (or the small mass ×
/// L² when no part has inertia). Unlike [`rotational_regularisation`] (the integrator's
/// consistent solve, which must not move the modes of a model it integrates), these are sized
/// from the model so that the eigenvalues of the massless directions sit far above the others.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MasslessSubstitute {
    pub mass: f64,
    pub inertia: f64,
}

impl MasslessSubstitute {
    /// The substitute for `model`, whose characteristic length is `length`.
    pub fn of(model: &Model, length: f64) -> MasslessSubstitute {
        let min_mass = model
            .parts
            .iter()
            .map(|p| p.mass)
            .filter(|m| *m > 0.0)
            .fold(f64::INFINITY, f64::min);
        let min_inertia = model
            .parts
            .iter()
            .flat_map(|p| linkage_model::inertia::symmetric_eigenvalues(&p.inertia))
            .filter(|x| *x > 0.0)
            .fold(f64::INFINITY, f64::min);
        let mass = if min_mass.is_finite() {
            MASSLESS_FRACTION * min_mass
        } else {
            MASSLESS_FRACTION
        };
        let inertia = if min_inertia.is_finite() {
            MASSLESS_FRACTION * min_inertia
        } else {
            mass * length * length
        };
        MasslessSubstitute { mass, inertia }
    }
}

/// Adds every part's body loads to `q` (6 per part, ground axes, model mass × acceleration
/// units): the weight `m·g` at the CM, the gyroscopic torque `−ω × (I_g ω)`, and with
/// `damping = Some(c)` (dynamic settling, per time unit) the damping `−c·m·v` and `−c·I_g·ω`.
/// With `q` holding `UCF·Q_applied` on entry, it leaves the right-hand side `UCF·Q` of the
/// equations of motion `M a + UCF·Jᵀλ = UCF·Q` that the integrator, the consistent outputs and
/// the acceleration IC solve.
pub fn add_body_loads(
    model: &Model,
    s: &State,
    v: &Velocities,
    damping: Option<f64>,
    q: &mut [f64],
) {
    for (k, p) in model.parts.iter().enumerate() {
        let ig = ground_inertia(p, &s.poses[k]);
        let w = v[k].1;
        let gyro = gyroscopic(&ig, w);
        for c in 0..3 {
            q[6 * k + c] += p.mass * model.gravity[c];
            q[6 * k + 3 + c] += gyro[c];
        }
        if let Some(c) = damping {
            let dv = v[k].0 * (-c * p.mass);
            let dw = ig * w * (-c);
            for i in 0..3 {
                q[6 * k + i] += dv[i];
                q[6 * k + 3 + i] += dw[i];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use linkage_model::Part;

    fn part(mass: f64, moments: DVec3) -> Part {
        Part {
            origin: linkage_model::Origin {
                statement: "PART",
                id: 2,
                name: "PART_2".into(),
                span: Default::default(),
                statement_index: 0,
            },
            mass,
            inertia: DMat3::from_diagonal(moments),
            p_gb: DVec3::ZERO,
            r_gb: DMat3::IDENTITY,
            p_b_bcs: DVec3::ZERO,
            velocity: [None; 6],
            r_b_cm: DMat3::IDENTITY,
            exact: Vec::new(),
            point_mass: false,
        }
    }

    #[test]
    fn ground_inertia_turns_with_the_body() {
        let p = part(2.0, DVec3::new(1.0, 2.0, 3.0));
        let pose = Pose {
            p: DVec3::ZERO,
            r: DMat3::from_rotation_z(std::f64::consts::FRAC_PI_2),
        };
        let ig = ground_inertia(&p, &pose);
        // The body x axis now points along ground y: I_yy(ground) = I_xx(body).
        assert!((ig.y_axis.y - 1.0).abs() < 1e-15);
        assert!((ig.x_axis.x - 2.0).abs() < 1e-15);
        assert!((ig.z_axis.z - 3.0).abs() < 1e-15);
    }

    #[test]
    fn only_singular_inertia_is_regularised() {
        let l = 10.0;
        assert_eq!(rotational_regularisation(&part(2.0, DVec3::ONE), l), 0.0);
        let rod = part(2.0, DVec3::new(0.0, 1.0, 1.0));
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-15 * b;
        assert!(close(rotational_regularisation(&rod, l), 2e-10));
        let massless = part(0.0, DVec3::ZERO);
        assert!(close(rotational_regularisation(&massless, l), 1e-22));
    }

    #[test]
    fn gyroscopic_load_vanishes_about_a_principal_axis() {
        let ig = DMat3::from_diagonal(DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(gyroscopic(&ig, DVec3::new(0.0, 0.0, 5.0)), DVec3::ZERO);
        // ω = (1,1,0): I ω = (1,2,0), −ω × Iω = −(0,0,1).
        assert_eq!(
            gyroscopic(&ig, DVec3::new(1.0, 1.0, 0.0)),
            DVec3::new(0.0, 0.0, -1.0)
        );
    }

    /// A 2 kg body with principal moments (1, 2, 3) about its CM, moving at v = (1, 0, 0) and
    /// ω = (1, 1, 0) under g = (0, −9.80665, 0) with settling damping c = 0.5: weight and
    /// damping −c m v on the CM; gyroscopic −ω × Iω = (0, 0, −1) and damping −c I ω on the
    /// rotation.
    #[test]
    fn body_loads_add_weight_gyroscopic_torque_and_damping() {
        let text = "body\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
                    PART/1, GROUND\nPART/2, MASS = 2, CM = 2, IP = 1, 2, 3\nMARKER/2, PART = 2\n\
                    ACCGRAV/, JGRAV = -9.80665\nEND\n";
        let ds = linkage_adm::parse_dataset(std::sync::Arc::from("b.adm"), text).expect("parses");
        let model = linkage_model::build_model(&ds).expect("builds").model;
        let s = State::input(&model);
        let v = [(DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.0, 1.0, 0.0))];
        let mut q = [0.0; 6];
        add_body_loads(&model, &s, &v, Some(0.5), &mut q);
        let want = [-1.0, -2.0 * 9.80665, 0.0, -0.5, -1.0, -1.0];
        for (got, want) in q.iter().zip(want) {
            assert!((got - want).abs() < 1e-12, "{q:?}");
        }
        let mut still = [0.0; 6];
        add_body_loads(&model, &s, &[(DVec3::ZERO, DVec3::ZERO)], None, &mut still);
        assert_eq!(still, [0.0, -2.0 * 9.80665, 0.0, 0.0, 0.0, 0.0]);
    }

    /// Adams' LINEAR rule: a massless part gets 1e-8 × the smallest part mass (2 kg) and 1e-8 ×
    /// the smallest principal moment (1 kg m²); with no inertia anywhere, the small mass × L².
    #[test]
    fn massless_parts_get_a_fraction_of_the_smallest_mass_and_moment() {
        let text = "two\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
                    PART/1, GROUND\nPART/2, MASS = 2, CM = 2, IP = 1, 2, 3\nMARKER/2, PART = 2\n\
                    PART/3\nMARKER/3, PART = 3, QP = 1, 0, 0\nEND\n";
        let ds = linkage_adm::parse_dataset(std::sync::Arc::from("t.adm"), text).expect("parses");
        let model = linkage_model::build_model(&ds).expect("builds").model;
        let sub = MasslessSubstitute::of(&model, 10.0);
        assert!((sub.mass - 2e-8).abs() < 1e-22, "{sub:?}");
        assert!((sub.inertia - 1e-8).abs() < 1e-22, "{sub:?}");
        let text = text.replace(", IP = 1, 2, 3", "");
        let ds = linkage_adm::parse_dataset(std::sync::Arc::from("t.adm"), &text).expect("parses");
        let model = linkage_model::build_model(&ds).expect("builds").model;
        let sub = MasslessSubstitute::of(&model, 10.0);
        assert!((sub.inertia - 2e-8 * 100.0).abs() < 1e-20, "{sub:?}");
    }
}
