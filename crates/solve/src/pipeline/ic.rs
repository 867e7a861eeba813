//! Initial conditions (Adams "assemble model", ADM-REFERENCE §8.1): displacement, velocity,
//! acceleration and force, with the redundancy classified at the assembled configuration.
//!
//! 1. Displacement: rank analysis at the input (broken joints as intended), least-change
//!    assembly of the independent rows and hard conditions ([`crate::pipeline::assemble`]), then the rank
//!    analysis again at the assembled configuration; if it admits a row the assembly did not
//!    satisfy, assemble once more with the new set.
//! 2. Velocity: `min ½(v − v₀)ᵀW(v − v₀)` subject to `J v = ḟ(t) − ∂Φ/∂t` (motions, and
//!    general constraints that depend on TIME), the joints' initial velocities and the curve
//!    constraints' initial sliding speeds (PTCV VEL, CVCV IVEL/JVEL).
//! 3. Acceleration and force: `M a + Jᵀμ = Q` (gravity and gyroscopic terms),
//!    `J a = f̈ − γ` with the exact velocity-product terms γ of every row, general constraints
//!    included ([`System::acceleration_bias`]); reactions `−Jᵀμ / UCF` on each element's I
//!    marker. Redundant rows are not in J, so their reactions are zero, as in Adams.

use super::assemble::{assemble, hard_rows, Assembly, HardKind, HardRow};
use super::verify::{verify_at, Verification};
use crate::constraints::drivers::{Drivers, ExpressionDrivers, MotionError};
use crate::constraints::residuals::{report_residual, residuals};
use crate::constraints::rows::RowGradient;
use crate::constraints::system::System;
use crate::kernel::{flat, IntegrationError, OutputSolver, Problem, SingularSolve};
use crate::linalg::kkt::{SaddlePoint, Zeros};
use crate::physics::applied::{AppliedForces, ForceError, Regime};
use crate::physics::reactions::Reaction;
use crate::state::{ElementState, State};
use crate::tolerances::{Tolerances, ACCELERATION_IC_FLOOR, UNGIVEN_VELOCITY_WEIGHT};
use glam::DVec3;
use linkage_model::{ConstraintKind, Model};

/// A part the assembly moved.
#[derive(Clone, Debug, PartialEq)]
pub struct MovedPart {
    pub part: usize,
    /// Translation of the centre of mass (ground axes, length units).
    pub translation: DVec3,
    /// Rotation angle in degrees.
    pub rotation_deg: f64,
}

/// A constraint equation that was violated at the input and its residual after assembly
/// (length units or degrees).
#[derive(Clone, Debug, PartialEq)]
pub struct Repair {
    pub row: usize,
    pub before: f64,
    pub after: f64,
}

/// Velocity IC result.
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityIc {
    /// CM velocity and angular velocity of every part (ground axes).
    pub velocities: Vec<(DVec3, DVec3)>,
    /// Largest violation of the velocity equations.
    pub max_error: f64,
    pub converged: bool,
    /// Motions whose velocity could not be evaluated (element, time and cause); their
    /// equations are left out.
    pub motion_errors: Vec<String>,
}

/// Acceleration and force IC result.
#[derive(Clone, Debug, PartialEq)]
pub struct AccelerationIc {
    /// CM acceleration and angular acceleration of every part (ground axes).
    pub accelerations: Vec<(DVec3, DVec3)>,
    pub reactions: Vec<Reaction>,
    /// Rows in the solve and their multipliers (model force units).
    pub multipliers: Vec<(usize, f64)>,
    pub max_error: f64,
    pub converged: bool,
}

/// Everything the `ic` analysis finds.
#[derive(Clone, Debug)]
pub struct InitialConditions {
    pub assembly: Assembly,
    /// Verification at the assembled configuration (redundancy and its consistency).
    pub analysis: Verification,
    pub hard: Vec<HardRow>,
    pub moved: Vec<MovedPart>,
    pub repaired: Vec<Repair>,
    pub velocity: Option<VelocityIc>,
    /// `Err` with the reason when the acceleration/force solve could not be done.
    pub acceleration: Option<Result<AccelerationIc, AccelerationError>>,
    /// Motions whose displacement at the start time cannot be evaluated (left out of the
    /// assembly): element, time and cause. Velocity and acceleration motions without ICDISP
    /// are not listed (the assembly decides their start displacement).
    pub motion_errors: Vec<String>,
}

impl InitialConditions {
    /// The constraint rows every later analysis enforces (the independent ones at the
    /// assembled pose) and the removed (redundant) rows it monitors.
    pub fn kept_and_removed_rows(&self) -> (Vec<usize>, Vec<usize>) {
        (
            admitted_rows(&self.analysis),
            self.analysis.redundant.iter().map(|r| r.row).collect(),
        )
    }

    /// Whether some redundant equation cannot be satisfied (the model cannot be assembled as
    /// built).
    pub fn inconsistent(&self) -> bool {
        self.analysis
            .redundant
            .iter()
            .any(|r| r.consistent == Some(false))
    }
}

/// Rows not reported redundant by a verification (the independent set).
pub fn admitted_rows(v: &Verification) -> Vec<usize> {
    let mut redundant = vec![false; v.system.rows.len()];
    for r in &v.redundant {
        redundant[r.row] = true;
    }
    (0..v.system.rows.len())
        .filter(|&r| !redundant[r])
        .collect()
}

/// Runs the displacement, velocity and acceleration/force initial conditions of `model`, whose
/// compiled rows are `sys` (see [`crate::pipeline::Assembled`], which calls this).
pub fn initial_conditions(
    model: &Model,
    sys: &System,
    drivers: &ExpressionDrivers,
    forces: &dyn AppliedForces,
    tol: &Tolerances,
) -> InitialConditions {
    initial_conditions_at(
        model,
        sys,
        drivers,
        forces,
        tol,
        0.0,
        &ElementState::default(),
    )
}

/// [`initial_conditions`] at time `time` (motions and time-dependent constraints are
/// evaluated there): a command file's analysis that continues a run assembles the model at
/// the time the previous analysis left it, with the values its sensors stored (`carried`'s
/// `sensors`, which `SENVAL` reads; the frictions are started again at the assembled pose).
pub fn initial_conditions_at(
    model: &Model,
    sys: &System,
    drivers: &ExpressionDrivers,
    forces: &dyn AppliedForces,
    tol: &Tolerances,
    time: f64,
    carried: &ElementState,
) -> InitialConditions {
    let mut input = State::input(model);
    input.time = time;
    if carried.sensors.len() == model.sensors.len() {
        input.elements.sensors.clone_from(&carried.sensors);
    }
    let hard = hard_rows(model);
    let mut analysis = verify_at(model, sys, &input, drivers, tol);
    let before = residuals(sys, &input, drivers);
    let mut asm = assemble(
        model,
        sys,
        &admitted_rows(&analysis),
        &hard,
        drivers,
        &input,
        &input,
    );
    for _ in 0..3 {
        if !asm.converged {
            break;
        }
        let next = verify_at(model, sys, &asm.state, drivers, tol);
        let again = !next.assembled;
        analysis = next;
        if !again {
            break;
        }
        asm = assemble(
            model,
            sys,
            &admitted_rows(&analysis),
            &hard,
            drivers,
            &asm.state,
            &input,
        );
    }
    let motion_errors = admitted_rows(&analysis)
        .into_iter()
        .filter(|&r| sys.rows[r].driven)
        .map(|r| sys.rows[r].element)
        .filter(|&e| Drivers::value(drivers, e, input.time).is_none() && !drivers.free_start(e))
        .map(|e| MotionError::at(model, drivers, e, input.time).to_string())
        .collect();
    let after = residuals(sys, &asm.state, drivers);
    let repaired = analysis_repairs(sys, &before, &after, model, tol);
    let moved = (0..model.parts.len())
        .filter_map(|k| {
            let (a, b) = (asm.state.poses[k], input.poses[k]);
            let translation = a.p - b.p;
            let rotation_deg = linkage_model::frames::log_so3(&(a.r * b.r.transpose()))
                .length()
                .to_degrees();
            let moved = translation.length() > tol.length * model.characteristic_length
                || rotation_deg.to_radians() > tol.angle;
            moved.then_some(MovedPart {
                part: k,
                translation,
                rotation_deg,
            })
        })
        .collect();
    let (velocity, acceleration) = if asm.converged {
        let rows = admitted_rows(&analysis);
        let vel = velocity_ic(model, sys, &rows, &hard, drivers, &asm.state);
        let solve =
            |s: &State| acceleration_ic(model, sys, &rows, drivers, forces, s, &vel.velocities);
        // Elements with a state (joint friction): anchored at the assembled pose; their
        // normal loads from the reactions of a first solve, then solved again with them.
        let acc = if forces.has_state() {
            forces.start_state(&mut asm.state);
            let first = solve(&asm.state);
            match &first {
                Ok(a) => {
                    forces.accept_state(&mut asm.state, &vel.velocities, &a.reactions);
                    solve(&asm.state)
                }
                Err(_) => first,
            }
        } else {
            solve(&asm.state)
        };
        let acc = acc.map_err(|e| match e {
            AccelerationError::Singular { free } if free.is_empty() => {
                AccelerationError::Singular {
                    free: analysis
                        .massless_free
                        .iter()
                        .map(|f| {
                            format!(
                                "{} ({})",
                                model.parts[f.part].origin.name,
                                f.coordinates.join(", ")
                            )
                        })
                        .collect(),
                }
            }
            other => other,
        });
        (Some(vel), Some(acc))
    } else {
        (None, None)
    };
    InitialConditions {
        motion_errors,
        assembly: asm,
        analysis,
        hard,
        moved,
        repaired,
        velocity,
        acceleration,
    }
}

fn analysis_repairs(
    sys: &System,
    before: &[Option<f64>],
    after: &[Option<f64>],
    model: &Model,
    tol: &Tolerances,
) -> Vec<Repair> {
    let mut out = Vec::new();
    for r in 0..sys.rows.len() {
        let (Some(b), Some(a)) = (before[r], after[r]) else {
            continue;
        };
        let unit = sys.rows[r].unit;
        let holds = |x| {
            crate::constraints::residuals::within_tolerance(
                unit,
                x,
                tol,
                model.characteristic_length,
            )
        };
        // Only real repairs: broken at the input and holding after the assembly (a redundant
        // equation that still does not hold is reported as inconsistent, not as repaired).
        if !holds(b) && holds(a) {
            out.push(Repair {
                row: r,
                before: report_residual(unit, b),
                after: report_residual(unit, a),
            });
        }
    }
    out
}

/// Input velocity targets: PART VX, VY, VZ (ground) and WX, WY, WZ (CM marker axes).
fn velocity_targets(model: &Model, s: &State) -> Vec<(DVec3, DVec3)> {
    model
        .parts
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let v = |i: usize| p.velocity[i].unwrap_or(0.0);
            let w_cm = DVec3::new(v(3), v(4), v(5));
            (DVec3::new(v(0), v(1), v(2)), s.poses[k].r * p.r_b_cm * w_cm)
        })
        .collect()
}

/// Velocity IC: one least-change linear solve.
pub fn velocity_ic(
    model: &Model,
    sys: &System,
    rows: &[usize],
    hard: &[HardRow],
    drivers: &ExpressionDrivers,
    s: &State,
) -> VelocityIc {
    let n = model.parts.len();
    let l = model.characteristic_length;
    let w_t = 1.0 / (l * l);
    let target = velocity_targets(model, s);
    let mut g = RowGradient::default();
    let mut eqs: Vec<(RowGradient, f64)> = Vec::new();
    let mut motion_errors = Vec::new();
    for &r in rows {
        let row = &sys.rows[r];
        let drive = if row.driven {
            match drivers.motion_rates(row.element, s.time) {
                Some(Ok((vel, _))) => vel,
                Some(Err(e)) => {
                    motion_errors.push(format!(
                        "{}: the motion's velocity at time {}: {e}",
                        model.constraints[row.element].origin.label(),
                        linkage_adm::num::time_text(s.time)
                    ));
                    continue;
                }
                None => continue,
            }
        } else {
            0.0
        };
        // A general constraint that depends on TIME: ∇Φ·v = −∂Φ/∂t (0 if it cannot be
        // evaluated here, which the acceleration solve then reports).
        let rhs = drive - sys.explicit_rate(r, s, 1.0).unwrap_or(0.0);
        sys.gradient(r, s, &mut g);
        eqs.push((g.clone(), rhs));
    }
    // Joints' initial velocities (IC = disp, vel).
    for con in &model.constraints {
        let ConstraintKind::Joint { initial, .. } = &con.kind else {
            continue;
        };
        for (want, kind) in [
            (initial.rotation.1, HardKind::IcRotation),
            (initial.translation.1, HardKind::IcTranslation),
        ] {
            let Some(vel) = want else { continue };
            let q = hard
                .iter()
                .find(|h| h.name == con.origin.name && h.kind == kind)
                .map(|h| h.quantity.clone())
                .or_else(|| {
                    let (i, j) = con.markers()?;
                    let f = |m: usize| crate::constraints::rows::BodyFrame {
                        body: model.markers[m].body,
                        p_b: model.markers[m].p_bm,
                        r_b: model.markers[m].r_bm,
                    };
                    let (fi, fj) = (f(i), f(j));
                    Some(if kind == HardKind::IcRotation {
                        crate::constraints::rows::Quantity::Angle {
                            x: fi.axis(0),
                            x_ref: fj.axis(0),
                            y_ref: fj.axis(1),
                        }
                    } else {
                        crate::constraints::rows::Quantity::Proj {
                            i: fi.origin(),
                            j: fj.origin(),
                            e: fj.axis(2),
                        }
                    })
                });
            if let Some(q) = q {
                g.clear();
                q.gradient(s, 1.0, &mut g);
                eqs.push((g.clone(), vel));
            }
        }
    }
    // Curve constraints' initial sliding speeds (PTCV VEL, CVCV IVEL and JVEL).
    eqs.extend(crate::constraints::curve_contacts::speed_equations(
        model, sys, s,
    ));
    // `[W Jᵀ; J 0] [v; μ] = [W v₀; ḟ]`: given velocities are targets; the others are "inexact
    // zeros" the solve may change freely (weight UNGIVEN_VELOCITY_WEIGHT keeps the problem
    // well posed). WX, WY, WZ are in the CM marker's axes.
    let mut kkt = SaddlePoint::new(6 * n, eqs.len());
    let mut rhs = vec![0.0; kkt.dim()];
    let weight = |given: Option<f64>| {
        if given.is_some() {
            1.0
        } else {
            UNGIVEN_VELOCITY_WEIGHT
        }
    };
    for (k, p) in model.parts.iter().enumerate() {
        for c in 0..3 {
            let w = w_t * weight(p.velocity[c]);
            kkt.add(6 * k + c, 6 * k + c, w);
            rhs[6 * k + c] = w * target[k].0[c];
        }
        let r_cm = s.poses[k].r * p.r_b_cm;
        let d =
            glam::DMat3::from_diagonal(DVec3::from_array([3, 4, 5].map(|i| weight(p.velocity[i]))));
        let w_rot = r_cm * d * r_cm.transpose();
        let b = w_rot * target[k].1;
        kkt.add_rotational_block(k, &w_rot, Zeros::Keep);
        for c in 0..3 {
            rhs[6 * k + 3 + c] = b[c];
        }
    }
    for (e, (grad, b)) in eqs.iter().enumerate() {
        kkt.add_constraint_row(e, grad);
        rhs[kkt.multiplier(e)] = *b;
    }
    let solved = kkt.solve(&mut rhs);
    let velocities: Vec<(DVec3, DVec3)> = if solved.is_ok() {
        (0..n)
            .map(|k| {
                (
                    DVec3::new(rhs[6 * k], rhs[6 * k + 1], rhs[6 * k + 2]),
                    DVec3::new(rhs[6 * k + 3], rhs[6 * k + 4], rhs[6 * k + 5]),
                )
            })
            .collect()
    } else {
        vec![(DVec3::ZERO, DVec3::ZERO); n]
    };
    let max_error = eqs
        .iter()
        .map(|(grad, b)| (grad.rate(&velocities) - b).abs())
        .fold(0.0, f64::max);
    VelocityIc {
        converged: solved.is_ok() && max_error <= model.ic.verror && motion_errors.is_empty(),
        velocities,
        max_error,
        motion_errors,
    }
}

/// Why the acceleration/force IC could not be solved.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AccelerationError {
    /// An applied force cannot be evaluated at the assembled configuration.
    #[error(transparent)]
    Force(#[from] ForceError),
    /// A motion's acceleration cannot be evaluated (`element` is its label with the line).
    #[error("{element}: the motion's acceleration at time {}: {cause}", linkage_adm::num::time_text(*.time))]
    MotionAcceleration {
        element: String,
        time: f64,
        cause: String,
    },
    /// A general constraint's second time derivative cannot be evaluated.
    #[error(
        "{element}: the second time derivative of the constraint cannot be evaluated: {cause}"
    )]
    ConstraintBias { element: String, cause: String },
    /// The shared consistent solve failed otherwise (its matrix could not be set up or
    /// factorised, the velocity projection is singular, a row cannot be evaluated).
    #[error(transparent)]
    Solve(Box<IntegrationError>),
    /// The matrix is singular: a massless part or a part without inertia is free to move.
    /// `free` names such parts and their free coordinates when the IC's analysis found them
    /// (`PART_4 (rx, ry, rz)`), empty otherwise.
    #[error(
        "the acceleration equations are singular: {}",
        if free.is_empty() {
            "a massless part or a part without inertia has motion the constraints leave free"
                .to_string()
        } else {
            format!("the constraints leave massless {} free", free.join(", "))
        }
    )]
    Singular { free: Vec<String> },
}

/// Acceleration and force IC: `M a + UCF·Jᵀμ = M g + UCF·Q` (gravity, applied forces,
/// gyroscopic terms) with `J a = f̈ − γ` (the exact velocity-product terms γ of every kept row,
/// general constraints included) at the assembled positions `s` with the IC velocities `v`,
/// by the consistent-output solve every analysis shares ([`OutputSolver`]), with the exact
/// mass matrix: a massless part or a part without inertia that the constraints leave free is
/// reported ([`AccelerationError::Singular`]), as Adams does before a dynamic run. Reactions
/// `−Jᵀλ` on each element's I marker (λ = μ/UCF). Before solving, the IC names in its own
/// words what cannot be evaluated there: a force element, a motion's acceleration, a general
/// constraint's second time derivative.
pub fn acceleration_ic(
    model: &Model,
    sys: &System,
    rows: &[usize],
    drivers: &ExpressionDrivers,
    forces: &dyn AppliedForces,
    s: &State,
    v: &[(DVec3, DVec3)],
) -> Result<AccelerationIc, AccelerationError> {
    let n = model.parts.len();
    let mut applied = vec![0.0; 6 * n];
    forces.add_forces(Regime::Dynamic, s, v, &mut applied)?;
    // The acceleration equations `∇Φ·a = f̈ − γ` of the rows, to measure the solution by.
    let mut g = RowGradient::default();
    let mut eqs: Vec<(RowGradient, f64)> = Vec::with_capacity(rows.len());
    for &r in rows {
        let row = &sys.rows[r];
        let fdd = if row.driven {
            match drivers.motion_rates(row.element, s.time) {
                Some(Ok((_, acc))) => acc,
                Some(Err(e)) => {
                    return Err(AccelerationError::MotionAcceleration {
                        element: model.constraints[row.element].origin.label(),
                        time: s.time,
                        cause: e.to_string(),
                    })
                }
                None => 0.0,
            }
        } else {
            0.0
        };
        let bias =
            sys.acceleration_bias(r, s, v, 1.0)
                .map_err(|e| AccelerationError::ConstraintBias {
                    element: model.constraints[row.element].origin.name.clone(),
                    cause: e.to_string(),
                })?;
        sys.gradient(r, s, &mut g);
        eqs.push((g.clone(), fdd - bias));
    }
    // Velocity and acceleration motions without ICDISP take their displacement from the
    // assembled configuration, as in every later stage.
    let anchored = drivers.anchored(sys, rows, s);
    let problem = Problem {
        model,
        sys,
        rows,
        redundant: &[],
        drivers: &anchored,
        forces,
        damping: None,
        frozen_time: None,
        regime: Regime::Dynamic,
        coupling: crate::physics::flex_inertia::FlexCoupling::new(model),
    };
    let solved = OutputSolver::exact(&problem, s, v)
        .and_then(|mut solver| solver.solve(&problem, s, &flat(v)))
        .map_err(|e| match e {
            // The velocity projection and the acceleration solve share the mass matrix on
            // the constraints' null space: either is singular exactly when a part without
            // mass or inertia is free.
            IntegrationError::Singular(
                SingularSolve::Acceleration | SingularSolve::VelocityProjection,
            ) => AccelerationError::Singular { free: Vec::new() },
            other => AccelerationError::Solve(Box::new(other)),
        })?;
    let acc = solved.output.accelerations;
    let max_error = eqs
        .iter()
        .map(|(grad, b)| (grad.rate(&acc) - b).abs())
        .fold(0.0, f64::max);
    let multipliers = rows.iter().copied().zip(solved.lambda).collect();
    Ok(AccelerationIc {
        accelerations: acc,
        reactions: solved.output.reactions,
        multipliers,
        max_error,
        converged: max_error <= model.ic.aerror.max(ACCELERATION_IC_FLOOR),
    })
}
