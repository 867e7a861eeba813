//! The mutable state analyses work on: part poses, time, the control states and what force
//! elements carry from one accepted state to the next ([`ElementState`]). A run owns its
//! states; the model and the force set are read-only (MuJoCo's mjModel/mjData split).

use glam::{DMat3, DVec3};
use linkage_model::{Body, Model};

/// Pose of a moving part's body frame: centre-of-mass position and axes, both in ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub p: DVec3,
    pub r: DMat3,
}

/// Positions of every moving part, the control states and the time.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    pub poses: Vec<Pose>,
    pub time: f64,
    /// The first-order states of DIFF, LSE and TFSISO elements and their rates
    /// (`linkage_model::controls`; empty without them).
    pub controls: ControlValues,
    /// The force elements' own state (joint friction), carried by the run from one accepted
    /// state to the next.
    pub elements: ElementState,
}

/// What elements carry from one accepted state to the next, owned by the run with the
/// positions (the model and the force set stay read-only).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ElementState {
    /// Each joint FRICTION's stiction anchor and normal load, in model order. Empty until
    /// the initial conditions start them (`AppliedForces::start_state`); empty reads as every
    /// friction anchored at the dataset's input configuration with its preload.
    pub frictions: Vec<FrictionState>,
    /// The value each SENSOR stored when it last fired, which `SENVAL` reads, in model order
    /// (written by the run's `kernel::sensors::SensorWatch`); a missing one reads 0.
    pub sensors: Vec<f64>,
}

/// What a friction carries from one accepted state to the next
/// (`crate::physics::forces::friction`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionState {
    /// The travel `(P_i − P_j)·z_j` where the axial deformation is zero.
    pub anchor_travel: f64,
    /// `R_jᵀR_i` where the rotational deformation is zero.
    pub anchor_rotation: DMat3,
    /// The normal load N (force at the slip surface, model force units).
    pub normal: f64,
}

/// Values `x` of the control states and their rates `ẋ` (the layout of
/// [`linkage_model::controls::Controls`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ControlValues {
    pub x: Vec<f64>,
    pub xdot: Vec<f64>,
}

impl ControlValues {
    /// Number of control states.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}

impl State {
    /// The configuration written in the dataset, at time 0.
    pub fn input(model: &Model) -> State {
        State {
            poses: model
                .parts
                .iter()
                .map(|p| Pose {
                    p: p.p_gb,
                    r: p.r_gb,
                })
                .collect(),
            time: 0.0,
            controls: {
                let (x, xdot) = model.controls.initial();
                ControlValues { x, xdot }
            },
            elements: ElementState::default(),
        }
    }

    /// Body pose (identity for ground).
    #[inline]
    pub fn pose(&self, b: Body) -> Pose {
        match b {
            Body::Ground => Pose {
                p: DVec3::ZERO,
                r: DMat3::IDENTITY,
            },
            Body::Part(k) => self.poses[k],
        }
    }

    /// Applies a tangent increment to part `k`: `p ← p + δx`, `R ← exp([δθ]×)·R` (δθ in ground).
    pub fn increment(&mut self, k: usize, dx: DVec3, dtheta: DVec3) {
        let pose = &mut self.poses[k];
        pose.p += dx;
        pose.r = linkage_model::frames::exp_so3(dtheta) * pose.r;
    }
}
