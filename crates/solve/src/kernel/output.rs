//! The consistent-output solve: at given positions, velocities projected onto the velocity
//! constraints, then accelerations and multipliers from the equations of motion with the
//! acceleration constraints, then the reactions. One solve shared by the dynamic run (at every
//! output), the kinematic run and the acceleration IC ([`OutputSolver`]). The IC solves with
//! the exact mass matrix ([`SingularInertia::Report`]), so that a free massless part is
//! reported; the runs regularise ([`SingularInertia::Regularise`]).

use super::error::{IntegrationError, MatrixRole, SingularSolve};
use super::matrix::{add_mass, assemble_growing, diagonal, IterationMatrix, MatrixCoefficients};
use super::problem::{padded, unflat, Problem};
use crate::constraints::rows::{RowGradient, Velocities};
use crate::linalg::kkt;
use crate::linalg::linear::FixedPatternLu;
use crate::physics::mass::{self, SingularInertia};
use crate::physics::reactions::{element_reactions, Reaction};
use crate::state::State;
use glam::DVec3;
use linkage_model::Model;

/// Part state at an output time.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    pub time: f64,
    pub state: State,
    /// CM velocity and angular velocity (ground).
    pub velocities: Vec<(DVec3, DVec3)>,
    pub accelerations: Vec<(DVec3, DVec3)>,
    pub reactions: Vec<Reaction>,
}

impl Output {
    /// Kinetic energy `Σ ½ m v² + ½ ωᵀ I_g ω` ([`mass::kinetic_energy`]) over the moving
    /// parts, with the flex bodies' inertia coupling `½ vᵀ ΔM v`, in the model's
    /// force × length (divided by the UCF).
    pub fn kinetic_energy(&self, model: &Model) -> f64 {
        let coupling = crate::physics::flex_inertia::FlexCoupling::new(model);
        let coupled = if coupling.is_empty() {
            0.0
        } else {
            coupling.kinetic_energy(&self.state, &super::problem::flat(&self.velocities))
        };
        (coupled
            + model
                .parts
                .iter()
                .enumerate()
                .map(|(k, p)| {
                    let (v, w) = self.velocities[k];
                    mass::kinetic_energy(p, &self.state.poses[k], v, w)
                })
                .sum::<f64>())
            / model.ucf()
    }
}

/// Output values made consistent with the constraints at a state.
#[derive(Clone, Debug, PartialEq)]
pub struct Consistent {
    /// Positions, consistent velocities and accelerations, reactions.
    pub output: Output,
    /// Multipliers of the kept rows (in `Problem::rows` order), model force units.
    pub lambda: Vec<f64>,
}

/// The matrix `[M, Jᵀ; J, 0]` of the consistent solves and its buffers. Its pattern is a copy
/// of an [`IterationMatrix`]'s (which holds every entry it needs), taken again when that one
/// changes; the copy fixes the column ordering, so the outputs do not depend on who asks.
pub(crate) struct ConsistentSolve {
    lu: FixedPatternLu,
    /// The [`IterationMatrix::pattern`] the pattern was copied from (0: its own diagonal).
    pattern: u64,
    /// Gradients of the kept rows at the output state.
    grads: Vec<RowGradient>,
    /// The output state with the analysis time (frozen when settling), for the constraints.
    constrained: State,
    /// The same for the force elements.
    force_state: State,
    /// Parts with singular inertia: regularised, or left singular for the caller to report.
    singular: SingularInertia,
}

impl ConsistentSolve {
    /// Buffers for `p`; `like` sizes the state buffers.
    pub(crate) fn new(
        p: &Problem,
        like: &State,
        singular: SingularInertia,
    ) -> Result<ConsistentSolve, IntegrationError> {
        Ok(ConsistentSolve {
            singular,
            lu: diagonal(6 * p.n() + p.rows.len())?,
            pattern: 0,
            grads: vec![RowGradient::default(); p.rows.len()],
            constrained: like.clone(),
            force_state: like.clone(),
        })
    }

    /// Projects the velocities `v` (6 per part) onto `J v = ḟ − ∂Φ/∂t` (least change,
    /// mass-weighted) and solves the accelerations and multipliers (`M a + UCF·Jᵀλ = UCF·Q`,
    /// `J a = f̈ − γ`, with the exact velocity-product terms γ of every row, general
    /// constraints included: [`crate::constraints::system::System::acceleration_bias`]) at the
    /// positions `s`. With [`SingularInertia::Regularise`], `M` is regularised on the
    /// rotational diagonal by [`mass::rotational_regularisation`], which is zero except for
    /// parts with singular inertia: elsewhere the equations are exact, so that a constraint wrench recovered from
    /// them (FORCE requests) vanishes to rounding where it should. The matrix takes
    /// `pattern_of`'s pattern. Cost: one assembly, one numeric LU, two solves.
    pub(crate) fn solve(
        &mut self,
        p: &Problem,
        s: &State,
        v: &[f64],
        pattern_of: &IterationMatrix,
    ) -> Result<Consistent, IntegrationError> {
        let n = p.n();
        let m = p.rows.len();
        let ucf = p.model.ucf();
        let length = p.model.characteristic_length;
        // The constraint expressions see the analysis time (frozen when settling).
        let se: &State = p.force_state(s, &mut self.constrained);
        p.gradients(se, &mut self.grads);
        let grads = &self.grads;
        let singular = self.singular;
        let reg = |k: usize| singular.rotational(&p.model.parts[k], length);
        if self.pattern != pattern_of.pattern {
            self.lu = pattern_of
                .lu
                .same_pattern()
                .map_err(|cause| IntegrationError::Setup {
                    matrix: MatrixRole::Consistent,
                    cause,
                })?;
            self.pattern = pattern_of.pattern;
        }
        let lu = &mut self.lu;
        // The pattern of an iteration matrix with control states has their rows too: the
        // identity there leaves them out of these solves.
        let dim = lu.dim();
        assemble_growing(lu, MatrixRole::Consistent, |a| {
            add_mass(p, s, a, reg);
            for (k, g) in grads.iter().enumerate() {
                kkt::add_constraint_row_blocks(a, 6 * n, k, g, 1.0);
            }
            for i in 6 * n + m..dim {
                a.add(i, i, 1.0);
            }
        })?;
        lu.factor()
            .map_err(IntegrationError::ConsistentFactorisation)?;
        // Velocities: rhs = [M v; ḟ] (ḟ = J v for rows without a drive rate).
        let mut rhs = vec![0.0; dim];
        for (k, part) in p.model.parts.iter().enumerate() {
            let ig = mass::ground_inertia(part, &s.poses[k]);
            let w_k = DVec3::new(v[6 * k + 3], v[6 * k + 4], v[6 * k + 5]);
            let hw = ig * w_k + w_k * reg(k);
            for c in 0..3 {
                rhs[6 * k + c] = part.mass * v[6 * k + c];
                rhs[6 * k + 3 + c] = hw[c];
            }
        }
        p.coupling.add_product(s, v, 1.0, &mut rhs[..6 * n]);
        let time_rate = p.time_rate();
        let guess = unflat(v);
        for (k, &r) in p.rows.iter().enumerate() {
            let row = &p.sys.rows[r];
            rhs[6 * n + k] = if row.driven {
                match p.drive_series(row.element, s.time) {
                    Some(f) => f[1],
                    None => grads[k].rate(&guess),
                }
            } else {
                -p.sys
                    .explicit_rate(r, se, time_rate)
                    .map_err(|e| p.row_error(r, &e))?
            };
        }
        lu.solve_in_place(&mut rhs)
            .map_err(|_| IntegrationError::Singular(SingularSolve::VelocityProjection))?;
        let velocities = unflat(&rhs[..6 * n]);
        // Accelerations and multipliers.
        let mut q = vec![0.0; 6 * n];
        p.generalized_into(s, &velocities, &mut self.force_state, &mut q)?;
        let mut rhs = vec![0.0; dim];
        rhs[..6 * n].copy_from_slice(&q);
        for (k, &r) in p.rows.iter().enumerate() {
            let row = &p.sys.rows[r];
            let bias = p
                .sys
                .acceleration_bias(r, se, &velocities, time_rate)
                .map_err(|e| p.row_error(r, &e))?;
            let fdd = if row.driven {
                p.drive_series(row.element, s.time).map_or(0.0, |f| f[2])
            } else {
                0.0
            };
            rhs[6 * n + k] = fdd - bias;
        }
        lu.solve_in_place(&mut rhs)
            .map_err(|_| IntegrationError::Singular(SingularSolve::Acceleration))?;
        let accelerations = unflat(&rhs[..6 * n]);
        // Multipliers in force units (M a + Jᵀμ = UCF·Q → λ = μ/UCF).
        let lambda: Vec<f64> = rhs[6 * n..6 * n + m].iter().map(|x| x / ucf).collect();
        let rg: Vec<(usize, &RowGradient)> = p.rows.iter().copied().zip(grads.iter()).collect();
        let reactions = element_reactions(p.model, p.sys, &rg, &lambda, s);
        Ok(Consistent {
            output: Output {
                time: s.time,
                state: s.clone(),
                velocities,
                accelerations,
                reactions,
            },
            lambda,
        })
    }
}

/// The iteration matrix's coefficients of the trapezoidal rule (HHT with α = 0: `β = 1/4`,
/// `γ = 1/2`) for step size `h`: they only decide which entries the pattern an
/// [`OutputSolver`] copies holds.
fn trapezoidal(h: f64) -> MatrixCoefficients {
    MatrixCoefficients {
        stiffness: 0.25 * h * h,
        damping: 0.5 * h,
        multiplier: 1.0,
    }
}

/// The consistent-output solve on its own, without a running integrator: the output solve of
/// the kinematic analysis.
///
/// Give it a [`Problem`] with the kept rows (`redundant` may be empty: it is not read here),
/// the (anchored) drivers and the force elements; then [`OutputSolver::solve`] at any
/// positions of the same model. Set up once (the matrix pattern, from an assembly of the
/// integrator's iteration matrix at `start`), reused for every solve.
pub struct OutputSolver {
    pattern_of: IterationMatrix,
    solve: ConsistentSolve,
}

impl OutputSolver {
    /// Sets up the solve for `p` near `start` with velocities `v0` (one per part; missing
    /// ones at rest): they only decide which matrix entries exist.
    pub fn new(p: &Problem, start: &State, v0: &Velocities) -> Result<Self, IntegrationError> {
        let v0 = padded(p, v0);
        Ok(OutputSolver {
            pattern_of: IterationMatrix::with_pattern(p, start, &v0, trapezoidal)?,
            solve: ConsistentSolve::new(p, start, SingularInertia::Regularise)?,
        })
    }

    /// [`OutputSolver::new`] with the exact mass matrix ([`SingularInertia::Report`]): a
    /// direction without inertia that the constraints leave free makes the acceleration solve
    /// fail with [`SingularSolve::Acceleration`] (the acceleration IC).
    pub fn exact(p: &Problem, start: &State, v0: &Velocities) -> Result<Self, IntegrationError> {
        let mut solver = OutputSolver::new(p, start, v0)?;
        solver.solve.singular = SingularInertia::Report;
        Ok(solver)
    }

    /// Velocities, accelerations, reactions and multipliers at positions `s` (time `s.time`),
    /// the velocities projected from the guess `v` (6 per part: CM, angular; ground axes).
    pub fn solve(
        &mut self,
        p: &Problem,
        s: &State,
        v: &[f64],
    ) -> Result<Consistent, IntegrationError> {
        self.solve.solve(p, s, v, &self.pattern_of)
    }

    /// [`OutputSolver::solve`]'s output alone.
    pub fn output(
        &mut self,
        p: &Problem,
        s: &State,
        v: &[f64],
    ) -> Result<Output, IntegrationError> {
        self.solve(p, s, v).map(|c| c.output)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::drivers::NoDrivers;
    use crate::constraints::system::System;
    use crate::kernel::problem::flat;
    use crate::physics::applied::NoForces;

    /// A 2 kg link hanging from a revolute about ground's z at its end, held horizontal with
    /// its centre of mass 1 m along x; gravity −9.80665 along y; inertia 0.1 kg m² about z.
    fn horizontal_pendulum() -> Model {
        let text =
            "pendulum\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
                    PART/1, GROUND\nMARKER/1, PART = 1\n\
                    PART/2, MASS = 2, CM = 2, IP = 0.1, 0.1, 0.1\n\
                    MARKER/2, PART = 2, QP = 1, 0, 0\nMARKER/3, PART = 2\n\
                    JOINT/1, REVOLUTE, I = 3, J = 1\nACCGRAV/, JGRAV = -9.80665\nEND\n";
        let ds = linkage_adm::parse_dataset(std::sync::Arc::from("p.adm"), text).expect("parses");
        linkage_model::build_model(&ds).expect("builds").model
    }

    #[test]
    fn released_pendulum_gets_projected_velocities_and_the_rigid_body_acceleration() {
        let model = horizontal_pendulum();
        let sys = System::new(&model);
        let rows: Vec<usize> = (0..sys.rows.len()).collect();
        let p = Problem {
            model: &model,
            sys: &sys,
            rows: &rows,
            redundant: &[],
            drivers: &NoDrivers,
            forces: &NoForces,
            damping: None,
            frozen_time: None,
            regime: crate::physics::applied::Regime::Dynamic,
            coupling: crate::physics::flex_inertia::FlexCoupling::new(&model),
        };
        let s = State::input(&model);
        // A guess that slides the link off its hinge: the projection keeps only the swing.
        let guess = [(DVec3::new(0.3, 0.5, 0.1), DVec3::new(0.0, 0.2, 0.4))];
        let mut solver = OutputSolver::new(&p, &s, &guess).expect("sets up");
        let c = solver.solve(&p, &s, &flat(&guess)).expect("solves");
        let (v, w) = c.output.velocities[0];
        let mut g = RowGradient::default();
        for &r in &rows {
            sys.gradient(r, &s, &mut g);
            assert!(g.rate(&c.output.velocities).abs() < 1e-12, "row {r}");
        }
        assert!((v - w.cross(DVec3::new(1.0, 0.0, 0.0))).length() < 1e-12);
        // Released from rest: α_z = −m g L / (I_zz + m L²).
        let rest = solver.solve(&p, &s, &[0.0; 6]).expect("solves");
        let (a, alpha) = rest.output.accelerations[0];
        let expected = -2.0 * 9.80665 / (0.1 + 2.0);
        assert!((alpha.z - expected).abs() < 1e-12, "{alpha:?}");
        assert!((a.y - expected).abs() < 1e-12, "{a:?}");
        // The hinge carries the weight less m·a: 2·9.80665 + 2·α_z upward on the link.
        let hinge = &rest.output.reactions[0];
        let lift = 2.0 * 9.80665 + 2.0 * expected;
        assert!((hinge.force.y - lift).abs() < 1e-9, "{hinge:?}");
        // At rest, the kinetic energy is zero; swinging, ½ (I + m L²) ω².
        assert_eq!(rest.output.kinetic_energy(&model), 0.0);
        let ke = 0.5 * (0.1 + 2.0) * w.z * w.z;
        assert!((c.output.kinetic_energy(&model) - ke).abs() < 1e-12);
    }
}
