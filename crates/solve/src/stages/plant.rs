//! Plant inputs and outputs of a linearization (Adams' PINPUT and POUTPUT): the matrices B, C
//! and D of `ẋ = A x + B u`, `y = C x + D u` about an operating point, with the states of
//! [`StateMatrix`] (`x = [z; ż]`, `q = N z`).
//!
//! - An input `u_k` is the value of a VARIABLE: the VARIABLE is held at `u_k` (its FUNCTION
//!   replaced by the number), so that every force reading it (through `VARVAL`) follows.
//!   `B = [0; M_r⁻¹ Nᵀ F̂_u]`, where `F̂_u` is the change of the generalised forces per unit of
//!   `u_k` (in the scaled coordinates of the linear equations, times the UCF).
//! - An output `y_k` is the value of a VARIABLE at the state: `C = [∂y/∂z, ∂y/∂ż, ∂y/∂x_c]`,
//!   the state moved along each column of N (and each control state); `D = ∂y/∂u`.
//! - Control states follow an input through their equations: rows `−(∂r/∂ẋ)⁻¹ ∂r/∂u` of B.
//!
//! Derivatives are central differences with steps [`PLANT_STEP`] (relative to the size of the
//! input, and per unit of z or ż): exact for the linear laws plant models use, accurate to the
//! step squared otherwise.

use crate::constraints::rows::Velocities;
use crate::linalg::kkt::CoordinateScale;
use crate::physics::applied::{AppliedForces, ForceError, Regime};
use crate::physics::forces::ForceSet;
use crate::stages::linearize::{OperatingPoint, StateMatrix};
use crate::state::State;
use crate::tolerances::PLANT_STEP;
use glam::DVec3;
use linkage_expr::EvalError;
use linkage_model::Model;

/// B, C and D of a plant (row-major).
#[derive(Clone, Debug, PartialEq)]
pub struct Plant {
    pub inputs: usize,
    pub outputs: usize,
    /// `(2f + nx) × inputs`.
    pub b: Vec<f64>,
    /// `outputs × (2f + nx)`.
    pub c: Vec<f64>,
    /// `outputs × inputs`.
    pub d: Vec<f64>,
}

/// Why the plant matrices cannot be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlantError {
    /// A plant input or output names a VARIABLE the model does not have.
    #[error("VARIABLE/{id} does not exist")]
    NoVariable { id: u32 },
    /// A VARIABLE cannot be evaluated at the operating point.
    #[error("VARIABLE/{id}: {cause}")]
    Variable { id: u32, cause: EvalError },
    /// A force element cannot be evaluated with an input moved.
    #[error(transparent)]
    Force(#[from] ForceError),
}

/// VARIABLE/`id` of `set` at `(s, v)`.
fn value(set: &ForceSet, id: u32, s: &State, v: &Velocities) -> Result<f64, PlantError> {
    set.variable(id, s, v)
        .map_err(|cause| PlantError::Variable { id, cause })
}

/// The plant matrices of `inputs` and `outputs` (VARIABLE ids) at the operating point `at`
/// of `model`, whose force elements are `forces` and whose state matrix is `sm`.
pub fn plant(
    model: &Model,
    forces: &ForceSet,
    at: OperatingPoint,
    sm: &StateMatrix,
    inputs: &[u32],
    outputs: &[u32],
) -> Result<Plant, PlantError> {
    let f = sm.coordinates;
    let n6 = 6 * model.parts.len();
    let (s, v) = (at.state, at.velocities);
    let held = |id: u32, u: f64| {
        forces
            .with_variable(id, u)
            .ok_or(PlantError::NoVariable { id })
    };
    let scale = CoordinateScale::lengths(model.characteristic_length);
    let ucf = model.ucf();
    let (m, p) = (inputs.len(), outputs.len());
    let nx = sm.controls;
    let states = 2 * f + nx;
    let mut b = vec![0.0; states * m];
    let mut d = vec![0.0; p * m];
    for (k, &id) in inputs.iter().enumerate() {
        let u0 = value(forces, id, s, v)?;
        let du = PLANT_STEP * u0.abs().max(1.0);
        let (plus, minus) = (held(id, u0 + du)?, held(id, u0 - du)?);
        let (mut qp, mut qm) = (vec![0.0; n6], vec![0.0; n6]);
        plus.add_forces(Regime::Dynamic, s, v, &mut qp)?;
        minus.add_forces(Regime::Dynamic, s, v, &mut qm)?;
        // F̂ = UCF · s_i · ∂Q_i/∂u in the scaled coordinates; z̈ = M_r⁻¹ Nᵀ F̂.
        let fhat: Vec<f64> = (0..n6)
            .map(|i| ucf * scale.of(i) * (qp[i] - qm[i]) / (2.0 * du))
            .collect();
        for j in 0..f {
            let row = &sm.force_map[j * n6..(j + 1) * n6];
            b[(f + j) * m + k] = row.iter().zip(&fhat).map(|(a, x)| a * x).sum();
        }
        if nx > 0 {
            let (mut rp, mut rm) = (vec![0.0; nx], vec![0.0; nx]);
            plus.control_residuals(s, v, &mut rp)?;
            minus.control_residuals(s, v, &mut rm)?;
            for i in 0..nx {
                b[(2 * f + i) * m + k] = (0..nx)
                    .map(|j| sm.rate_map[i * nx + j] * (rp[j] - rm[j]) / (2.0 * du))
                    .sum();
            }
        }
        for (o, &out) in outputs.iter().enumerate() {
            d[o * m + k] = (value(&plus, out, s, v)? - value(&minus, out, s, v)?) / (2.0 * du);
        }
    }
    let mut c = vec![0.0; p * states];
    let column = |j: usize, k: usize| -> (DVec3, DVec3) {
        let at = |r: usize| sm.basis[r * f + j];
        (
            DVec3::new(at(6 * k), at(6 * k + 1), at(6 * k + 2)),
            DVec3::new(at(6 * k + 3), at(6 * k + 4), at(6 * k + 5)),
        )
    };
    for j in 0..f {
        // Positions moved by ±PLANT_STEP along column j of N.
        let moved = |sign: f64| {
            let mut st = s.clone();
            for k in 0..model.parts.len() {
                let (t, r) = column(j, k);
                st.increment(k, t * (sign * PLANT_STEP), r * (sign * PLANT_STEP));
            }
            st
        };
        let (sp, sm_) = (moved(1.0), moved(-1.0));
        // Velocities moved the same way.
        let sped = |sign: f64| -> Vec<(DVec3, DVec3)> {
            (0..model.parts.len())
                .map(|k| {
                    let (t, r) = column(j, k);
                    (
                        v[k].0 + t * (sign * PLANT_STEP),
                        v[k].1 + r * (sign * PLANT_STEP),
                    )
                })
                .collect()
        };
        let (vp, vm) = (sped(1.0), sped(-1.0));
        for (o, &out) in outputs.iter().enumerate() {
            let dz =
                (value(forces, out, &sp, v)? - value(forces, out, &sm_, v)?) / (2.0 * PLANT_STEP);
            let dzdot =
                (value(forces, out, s, &vp)? - value(forces, out, s, &vm)?) / (2.0 * PLANT_STEP);
            c[o * states + j] = dz;
            c[o * states + f + j] = dzdot;
        }
    }
    for i in 0..nx {
        let moved = |sign: f64| {
            let mut st = s.clone();
            st.controls.x[i] += sign * PLANT_STEP;
            st
        };
        let (sp, sm_) = (moved(1.0), moved(-1.0));
        for (o, &out) in outputs.iter().enumerate() {
            c[o * states + 2 * f + i] =
                (value(forces, out, &sp, v)? - value(forces, out, &sm_, v)?) / (2.0 * PLANT_STEP);
        }
    }
    Ok(Plant {
        inputs: m,
        outputs: p,
        b,
        c,
        d,
    })
}
