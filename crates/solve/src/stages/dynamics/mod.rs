//! Dynamic simulation (DESIGN §8, ADM-REFERENCE §8.5): the index-3 DAE integrated with the
//! HHT-α method (Negrut, Rampalli, Ottarsson, Sajdak 2007) on the part configuration manifold.
//!
//! Per step the unknowns are the accelerations `a` (CM acceleration and angular acceleration of
//! every part, ground axes) and the multipliers `λ` of the independent constraint rows:
//!
//! ```text
//! M a_{n+1} + UCF·[(1+α)(Jᵀλ − Q)_{n+1} − α (Jᵀλ − Q)_n] = 0
//! Φ(q_{n+1}, t_{n+1}) / (β h²) = 0
//! q_{n+1} = q_n ⊕ (h v_n + h²/2 ((1−2β) a_n + 2β a_{n+1})),   v_{n+1} = v_n + h((1−γ) a_n + γ a_{n+1})
//! ```
//!
//! with `β = (1−α)²/4`, `γ = 1/2 − α`, `α ∈ [−1/3, 0]` (⊕: translation added, rotation applied
//! with the exponential map). Newton uses the scaled iteration matrix
//! `[M + (1+α)(βh² K_T + γh C_T), (1+α)Jᵀ; J, 0]` (K_T with the geometric stiffness), kept
//! across iterations and steps while it converges well (modified Newton: refreshed when a
//! correction contracts by less than `MATRIX_REFRESH_RATE` (0.05), when the step size moved by
//! more than a factor 2, or after three iterations with a matrix from an earlier step). The
//! scaling makes the matrix nearly independent of h, which is what allows keeping it across
//! step-size changes. The iteration starts from accelerations and multipliers extrapolated
//! linearly from the last two steps. The step size is controlled with the local error
//! estimate `h²|β − 1/6|·‖a_{n+1} − a_n‖` against the INTEGRATOR ERROR. Output times are hit
//! exactly; at each output the velocities and accelerations are made consistent with the
//! constraints (projection and the acceleration/force solve), which also gives the reactions.
//! Redundant rows (removed as in verify) are checked every step; one that becomes violated
//! stops the run.
//!
//! Cost: [`Integrator`] holds every buffer a step needs (MuJoCo's "model read-only, data
//! preallocated"): a step allocates nothing once the iteration matrix's sparsity pattern is
//! known (a test counts the allocations). The matrix lives in a
//! [`crate::linalg::linear::FixedPatternLu`]: its pattern (the entries nonzero when first assembled,
//! grown if another becomes nonzero) gets its column ordering and symbolic analysis once;
//! each refresh is a numeric refactorisation into the same storage. Per iteration: the rows'
//! residuals and gradients, the generalised forces, one sparse solve — O(rows + parts) for a
//! chain; per refresh additionally the assembly (row second derivatives) and the numeric LU.

mod run;
pub use linkage_model::settings::IntegratorSettings;
pub use run::{run, DynamicRun, RunError, RunProgress, Start, StartingEquilibrium};

use crate::constraints::hessian::HessianBlocks;
use crate::constraints::rows::{RowGradient, Velocities};
use crate::constraints::system::{RowUnit, System};
use crate::linalg::linear::FixedPatternLu;
use crate::physics::applied::AppliedForces;
use crate::stages::ic::{element_reactions, Reaction};
use crate::stages::verify::{report_residual, report_unit_suffix, within_tolerance, Drivers};
use crate::state::State;
use crate::tolerances::{
    CORRECTOR_CONSTRAINT, CORRECTOR_ERROR_FRACTION, CORRECTOR_NOISE, CORRECTOR_RELATIVE,
    CORRECTOR_ROUNDING,
};
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
    /// Kinetic energy `Σ ½ m v² + ½ ωᵀ I ω` over the moving parts, in the model's force ×
    /// length (divided by the UCF).
    pub fn kinetic_energy(&self, model: &Model) -> f64 {
        model
            .parts
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let r = self.state.poses[k].r;
                let ig = r * p.inertia * r.transpose();
                let (v, w) = self.velocities[k];
                0.5 * p.mass * v.length_squared() + 0.5 * w.dot(ig * w)
            })
            .sum::<f64>()
            / model.ucf()
    }
}

/// Why a simulation stopped early.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    pub time: f64,
    pub message: String,
}

/// Result of a simulation.
#[derive(Clone, Debug)]
pub struct Simulation {
    pub outputs: Vec<Output>,
    pub failure: Option<Failure>,
    pub steps: usize,
    pub rejected: usize,
    /// The model has no degrees of freedom: it was run kinematically.
    pub kinematic: bool,
}

/// Per-part damping added for dynamic settling: force `−c m v`, torque `−c I ω`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtraDamping(pub f64);

/// Everything the step needs that does not change.
pub struct Problem<'a> {
    pub model: &'a Model,
    pub sys: &'a System,
    /// Independent rows.
    pub rows: &'a [usize],
    /// Redundant rows, checked every step.
    pub redundant: &'a [usize],
    pub drivers: &'a dyn Drivers,
    pub forces: &'a dyn AppliedForces,
    pub damping: Option<ExtraDamping>,
    /// Freeze time at this value (dynamic settling): motions and forces see it.
    pub frozen_time: Option<f64>,
}

impl Problem<'_> {
    fn n(&self) -> usize {
        self.model.parts.len()
    }

    pub(crate) fn time(&self, t: f64) -> f64 {
        self.frozen_time.unwrap_or(t)
    }

    /// How fast the constraints' TIME advances: 0 when it is frozen.
    fn time_rate(&self) -> f64 {
        if self.frozen_time.is_some() {
            0.0
        } else {
            1.0
        }
    }

    /// An expression of row `r` that cannot be evaluated, with its element's name.
    fn row_error(&self, r: usize, e: &linkage_expr::EvalError) -> String {
        let c = &self.model.constraints[self.sys.rows[r].element];
        format!(
            "{}: the constraint's time derivatives cannot be evaluated: {e}",
            c.origin.name
        )
    }

    /// The state the force elements see: `s` itself, or (frozen time) a copy in `buf` with
    /// the frozen time. The copy reuses `buf`'s storage.
    fn force_state<'s>(&self, s: &'s State, buf: &'s mut State) -> &'s State {
        match self.frozen_time {
            None => s,
            Some(t) => {
                buf.poses.clone_from(&s.poses);
                buf.time = t;
                buf
            }
        }
    }

    /// `UCF·Q` into `q` (length 6n; mass × acceleration units): gravity, applied forces,
    /// gyroscopic terms `−ω × (I ω)`, extra damping. `buf` holds the force state when time
    /// is frozen.
    fn generalized_into(
        &self,
        s: &State,
        v: &Velocities,
        buf: &mut State,
        q: &mut [f64],
    ) -> Result<(), String> {
        let ucf = self.model.ucf();
        q.fill(0.0);
        self.forces.add_forces(self.force_state(s, buf), v, q)?;
        for x in q.iter_mut() {
            *x *= ucf;
        }
        for (k, p) in self.model.parts.iter().enumerate() {
            let ig = s.poses[k].r * p.inertia * s.poses[k].r.transpose();
            let w = v[k].1;
            let gyro = -w.cross(ig * w);
            for c in 0..3 {
                q[6 * k + c] += p.mass * self.model.gravity[c];
                q[6 * k + 3 + c] += gyro[c];
            }
            if let Some(ExtraDamping(c)) = self.damping {
                let dv = v[k].0 * (-c * p.mass);
                let dw = ig * w * (-c);
                for i in 0..3 {
                    q[6 * k + i] += dv[i];
                    q[6 * k + 3 + i] += dw[i];
                }
            }
        }
        Ok(())
    }

    /// Drive values of the rows (motions at time t) into `out` (length m).
    pub(crate) fn drives_into(&self, t: f64, out: &mut [f64]) -> Result<(), String> {
        for (o, &r) in out.iter_mut().zip(self.rows) {
            let row = &self.sys.rows[r];
            *o = if row.driven {
                self.drivers
                    .value(row.element, self.time(t))
                    .ok_or_else(|| {
                        crate::stages::verify::motion_error(
                            self.model,
                            self.drivers,
                            row.element,
                            self.time(t),
                        )
                    })?
            } else {
                0.0
            };
        }
        Ok(())
    }

    /// Gradients of the independent rows at `s` into `grads` (one per row, storage reused).
    fn gradients(&self, s: &State, grads: &mut [RowGradient]) {
        for (g, &r) in grads.iter_mut().zip(self.rows) {
            self.sys.gradient(r, s, g);
        }
    }
}

pub(crate) fn flat(v: &[(DVec3, DVec3)]) -> Vec<f64> {
    v.iter()
        .flat_map(|(a, b)| [a.x, a.y, a.z, b.x, b.y, b.z])
        .collect()
}

fn unflat(x: &[f64]) -> Vec<(DVec3, DVec3)> {
    let mut out = vec![(DVec3::ZERO, DVec3::ZERO); x.len() / 6];
    unflat_into(x, &mut out);
    out
}

fn unflat_into(x: &[f64], out: &mut [(DVec3, DVec3)]) {
    for (o, c) in out.iter_mut().zip(x.chunks_exact(6)) {
        *o = (DVec3::new(c[0], c[1], c[2]), DVec3::new(c[3], c[4], c[5]));
    }
}

/// Translations scaled by the characteristic length, rotations as they are (radians): the
/// weights of the convergence test and of the error estimate.
#[inline]
fn scale(i: usize, length: f64) -> f64 {
    if i % 6 < 3 {
        1.0 / length
    } else {
        1.0
    }
}

/// HHT-α coefficients: `β = (1−α)²/4`, `γ = 1/2 − α`.
#[derive(Clone, Copy, Debug)]
struct Hht {
    alpha: f64,
    beta: f64,
    gamma: f64,
}

impl Hht {
    fn new(alpha: f64) -> Hht {
        let alpha = alpha.clamp(-1.0 / 3.0, 0.0);
        Hht {
            alpha,
            beta: (1.0 - alpha).powi(2) / 4.0,
            gamma: 0.5 - alpha,
        }
    }
}

/// Integrator state at one time.
#[derive(Clone, Debug)]
struct Step {
    /// Positions and the time.
    s: State,
    /// Velocities and accelerations, 6 per part (CM then angular, ground axes).
    v: Vec<f64>,
    a: Vec<f64>,
    /// `Jᵀλ − Q` at the step (mass × acceleration units), for the HHT α term.
    force_term: Vec<f64>,
    lambda: Vec<f64>,
}

impl Step {
    /// Positions and velocities of the step of size `h` from `from` with accelerations
    /// `self.a`:
    /// `q = q_n ⊕ (h v_n + h²/2 ((1−2β) a_n + 2β a))`, `v = v_n + h((1−γ) a_n + γ a)`.
    fn place(&mut self, from: &Step, h: f64, hht: Hht) {
        let Hht { beta, gamma, .. } = hht;
        self.s.poses.copy_from_slice(&from.s.poses);
        self.s.time = from.s.time + h;
        for k in 0..self.s.poses.len() {
            let d = |i: usize| {
                let i = 6 * k + i;
                h * from.v[i]
                    + h * h / 2.0 * ((1.0 - 2.0 * beta) * from.a[i] + 2.0 * beta * self.a[i])
            };
            self.s.increment(
                k,
                DVec3::new(d(0), d(1), d(2)),
                DVec3::new(d(3), d(4), d(5)),
            );
        }
        for ((v, (v0, a0)), a) in self
            .v
            .iter_mut()
            .zip(from.v.iter().zip(&from.a))
            .zip(&self.a)
        {
            *v = v0 + h * ((1.0 - gamma) * a0 + gamma * a);
        }
    }

    /// `Jᵀλ − Q` (mass × acceleration units) at this step's positions, velocities and
    /// multipliers, into `force_term`. Leaves the velocities as pairs in `w.twists` and the
    /// rows' gradients at `s` in `w.grads`.
    fn evaluate(&mut self, p: &Problem, w: &mut Workspace) -> Result<(), String> {
        unflat_into(&self.v, &mut w.twists);
        p.gradients(&self.s, &mut w.grads);
        p.generalized_into(&self.s, &w.twists, &mut w.force_state, &mut w.q)?;
        let ucf = p.model.ucf();
        for (o, q) in self.force_term.iter_mut().zip(&w.q) {
            *o = -q;
        }
        for (g, l) in w.grads.iter().zip(&self.lambda) {
            for (body, b) in &g.blocks {
                let out = &mut self.force_term[6 * body..6 * body + 6];
                for (o, x) in out.iter_mut().zip(b) {
                    *o += ucf * l * x;
                }
            }
        }
        Ok(())
    }
}

/// Buffers of the corrector and of the consistent outputs, sized once per problem: a step
/// allocates nothing itself (see [`Integrator`] for what the force elements may allocate).
struct Workspace {
    /// Drive values of the rows at the step's time (m).
    drives: Vec<f64>,
    /// Residual `[r₁; r₂]`, then the Newton correction (6n + m).
    rhs: Vec<f64>,
    /// Velocities as (CM, angular) pairs for the force elements (n).
    twists: Vec<(DVec3, DVec3)>,
    /// `UCF·Q` (6n).
    q: Vec<f64>,
    /// Gradients of the independent rows at the current iterate (m).
    grads: Vec<RowGradient>,
    hessian: HessianBlocks,
    /// Force Jacobians `∂Q/∂q`, `∂Q/∂v` as triplets.
    dq: Vec<(usize, usize, f64)>,
    dv: Vec<(usize, usize, f64)>,
    /// The state force elements see when time is frozen.
    force_state: State,
    /// The scaled iteration matrix and the step size it was factorised for (`None`: no
    /// valid factorisation).
    matrix: FixedPatternLu,
    matrix_h: Option<f64>,
    /// Counts the changes of the iteration matrix's pattern.
    matrix_pattern: u64,
    /// `[M, Jᵀ; J, 0]` of the consistent velocity and acceleration solves: its pattern is a
    /// copy of the iteration matrix's (which holds every entry it needs), taken again when
    /// that one changes (`projection_pattern` is the `matrix_pattern` it copied).
    projection: FixedPatternLu,
    projection_pattern: u64,
}

impl Workspace {
    /// Buffers for `p`, and the iteration matrix's pattern found by assembling it at `start`
    /// with velocities `v0` (n of them; see [`assemble_iteration_matrix`]).
    fn new(p: &Problem, start: &State, v0: &Velocities, hht: Hht) -> Result<Workspace, String> {
        let (n, m) = (p.n(), p.rows.len());
        let dim = 6 * n + m;
        let mut grads = vec![RowGradient::default(); m];
        p.gradients(start, &mut grads);
        let diagonal = || {
            FixedPatternLu::new(dim, (0..dim).map(|i| (i, i)))
                .map_err(|e| format!("the integrator's matrices cannot be set up: {e}"))
        };
        let mut w = Workspace {
            drives: vec![0.0; m],
            rhs: vec![0.0; dim],
            twists: v0.to_vec(),
            q: vec![0.0; 6 * n],
            grads,
            hessian: HessianBlocks::default(),
            dq: Vec::new(),
            dv: Vec::new(),
            force_state: start.clone(),
            matrix: diagonal()?,
            matrix_h: None,
            matrix_pattern: 0,
            projection: diagonal()?,
            projection_pattern: 0,
        };
        // Only which entries are nonzero matters here: any step size, zero multipliers (the
        // rows' second derivatives claim their places all the same).
        let lambda = vec![0.0; m];
        assemble_iteration_matrix(p, start, &lambda, 1e-3, hht, &mut w)?;
        Ok(w)
    }
}

/// Assembles `a` with `fill` until no entry falls outside its pattern: the pattern starts
/// as the diagonal, the first assembly grows it to the entries that are nonzero there, and
/// an entry that becomes nonzero later grows it once more ([`FixedPatternLu::grow`]); a
/// planar mechanism thus keeps a planar pattern. Returns whether the pattern grew.
fn assemble_growing(
    a: &mut FixedPatternLu,
    what: &str,
    mut fill: impl FnMut(&mut FixedPatternLu),
) -> Result<bool, String> {
    let mut grew = false;
    // The values do not change between passes, so the second one finds every entry.
    for _ in 0..3 {
        a.clear();
        fill(a);
        if !a.has_missing() {
            return Ok(grew);
        }
        a.grow()
            .map_err(|e| format!("{what} cannot be set up: {e}"))?;
        grew = true;
    }
    Err(format!(
        "{what} cannot be set up: its sparsity pattern does not settle"
    ))
}

/// Adds the mass blocks `m·1` and `I_g = R I Rᵀ` of every part to `matrix`; `rotational(k)`
/// is added to the diagonal of part k's rotational block (regularisation of the projection).
fn add_mass(
    p: &Problem,
    s: &State,
    matrix: &mut FixedPatternLu,
    rotational: impl Fn(usize) -> f64,
) {
    for (k, part) in p.model.parts.iter().enumerate() {
        let ig = s.poses[k].r * part.inertia * s.poses[k].r.transpose();
        let reg = rotational(k);
        let diagonal = |x: f64| move |i: usize, j: usize| if i == j { x } else { 0.0 };
        matrix.add_block((6 * k, 6 * k), (3, 3), 1.0, diagonal(part.mass));
        matrix.add_block((6 * k + 3, 6 * k + 3), (3, 3), 1.0, |i, j| {
            ig.col(j)[i] + diagonal(reg)(i, j)
        });
    }
}

/// Assembles the values of the scaled iteration matrix (its pattern grows on first use,
/// see [`assemble_growing`])
///
/// ```text
/// [M + (1+α)(βh² K_T + γh C_T)    (1+α)·UCF·Jᵀ]
/// [J                              0           ]
/// ```
///
/// with `K_T = −UCF·∂Q/∂q + UCF·Σλ ∂²Φ/∂q²` (geometric stiffness of the kept rows' terms),
/// `C_T = −UCF·∂Q/∂v` (+ the extra damping), at the iterate `s`, `λ` with the velocities in
/// `w.twists` and the rows' gradients in `w.grads`. A row's second derivatives claim their
/// places in the pattern even while its multiplier is zero.
fn assemble_iteration_matrix(
    p: &Problem,
    s: &State,
    lambda: &[f64],
    h: f64,
    hht: Hht,
    w: &mut Workspace,
) -> Result<(), String> {
    let n = p.n();
    let ucf = p.model.ucf();
    let Hht { alpha, beta, gamma } = hht;
    let kq = (1.0 + alpha) * beta * h * h;
    let kv = (1.0 + alpha) * gamma * h;
    w.dq.clear();
    w.dv.clear();
    p.forces.add_jacobians(
        p.force_state(s, &mut w.force_state),
        &w.twists,
        &mut w.dq,
        Some(&mut w.dv),
    )?;
    let (dq, dv, hessian, grads) = (&w.dq, &w.dv, &mut w.hessian, &w.grads);
    let grew = assemble_growing(&mut w.matrix, "the integrator's Newton matrix", |a| {
        add_mass(p, s, a, |_| 0.0);
        for &(i, j, x) in dq {
            a.add(i, j, -ucf * x * kq);
        }
        for &(i, j, x) in dv {
            a.add(i, j, -ucf * x * kv);
        }
        if let Some(ExtraDamping(c)) = p.damping {
            for (k, part) in p.model.parts.iter().enumerate() {
                let ig = s.poses[k].r * part.inertia * s.poses[k].r.transpose();
                let mass = |i: usize, j: usize| if i == j { part.mass } else { 0.0 };
                a.add_block((6 * k, 6 * k), (3, 3), c * kv, mass);
                a.add_block((6 * k + 3, 6 * k + 3), (3, 3), c * kv, |i, j| ig.col(j)[i]);
            }
        }
        for (k, &r) in p.rows.iter().enumerate() {
            hessian.clear();
            p.sys.hessian(r, s, 1.0, hessian);
            let f = ucf * lambda[k] * kq;
            for &(br, rs, bc, cs, m) in &hessian.blocks {
                a.add_block((6 * br + 3 * rs, 6 * bc + 3 * cs), (3, 3), f, |i, j| {
                    m.col(j)[i]
                });
            }
            for (body, b) in &grads[k].blocks {
                a.add_block(
                    (6 * body, 6 * n + k),
                    (6, 1),
                    (1.0 + alpha) * ucf,
                    |i, _| b[i],
                );
                a.add_block((6 * n + k, 6 * body), (1, 6), 1.0, |_, j| b[j]);
            }
        }
    })?;
    if grew {
        w.matrix_pattern += 1;
    }
    Ok(())
}

/// The HHT-α integrator of a [`Problem`]: the current step, a trial step and every buffer
/// the corrector needs, allocated once ([`Integrator::new`]).
///
/// Allocation: [`Integrator::try_step`] and [`Integrator::accept`] allocate nothing
/// themselves once the iteration matrix's pattern has been found (the first factorisation,
/// and again only if a new nonzero appears). What they call may:
/// - faer's numeric LU grows its L and U storage if partial pivoting ever produces more fill
///   than any earlier factorisation (amortised doubling);
/// - force elements: the generalised forces of elements without expressions (SPRINGDAMPER,
///   BUSHING, FIELD, BEAM) allocate nothing; expressions (SFORCE, VFORCE, VTORQUE, GFORCE,
///   VARIABLEs) allocate in the evaluator at every evaluation; force Jacobians, evaluated at
///   each matrix refresh only, use dual numbers whose gradients are heap vectors;
/// - motions given by expressions allocate in the evaluator.
///
/// Models without expressions and force elements (e.g. the generated chains) step without a
/// single allocation; `tests/allocations.rs` counts them.
pub struct Integrator<'p, 'a> {
    p: &'p Problem<'a>,
    settings: IntegratorSettings,
    hht: Hht,
    cur: Step,
    trial: Step,
    /// Accelerations and multipliers of the step before `cur`, and the size of the step from
    /// there to `cur` (`None` before the first step): the corrector's predictor.
    prev_a: Vec<f64>,
    prev_lambda: Vec<f64>,
    prev_h: Option<f64>,
    work: Workspace,
}

impl<'p, 'a> Integrator<'p, 'a> {
    /// Starts at `start` (assembled) with velocities `v0` (one per part; missing ones are
    /// zero), projected onto the velocity constraints; accelerations and multipliers from the
    /// constraint-consistent solve. Returns the integrator and the output at the start.
    pub fn new(
        p: &'p Problem<'a>,
        start: &State,
        v0: &Velocities,
        settings: &IntegratorSettings,
    ) -> Result<(Integrator<'p, 'a>, Output), String> {
        if start.poses.len() != p.n() {
            return Err(format!(
                "the start state has {} parts, the model {}",
                start.poses.len(),
                p.n()
            ));
        }
        let v0: Vec<(DVec3, DVec3)> = (0..p.n())
            .map(|k| v0.get(k).copied().unwrap_or((DVec3::ZERO, DVec3::ZERO)))
            .collect();
        let hht = Hht::new(settings.alpha);
        let mut work = Workspace::new(p, start, &v0, hht)?;
        let first = consistent_output(p, start, &flat(&v0), &mut work)?;
        let mut cur = Step {
            s: start.clone(),
            v: flat(&first.velocities),
            a: flat(&first.accelerations),
            force_term: vec![0.0; 6 * p.n()],
            lambda: first.lambda,
        };
        cur.evaluate(p, &mut work)?;
        let trial = cur.clone();
        Ok((
            Integrator {
                p,
                settings: settings.clone(),
                hht,
                prev_a: cur.a.clone(),
                prev_lambda: cur.lambda.clone(),
                prev_h: None,
                cur,
                trial,
                work,
            },
            first.output,
        ))
    }

    /// Time of the current step.
    pub fn time(&self) -> f64 {
        self.cur.s.time
    }

    /// Positions at the current step.
    pub fn state(&self) -> &State {
        &self.cur.s
    }

    /// Velocities at the current step, 6 per part (CM velocity, angular velocity; ground).
    pub fn velocities(&self) -> &[f64] {
        &self.cur.v
    }

    /// Computes the step of size `h` from the current one (kept as the trial; see
    /// [`Integrator::accept`]) and returns its local error estimate
    /// `max_i h²|β − 1/6|·|a_{n+1} − a_n|_i` (translations over the characteristic length).
    /// An error (corrector not converged, singular matrix, a force or motion that cannot be
    /// evaluated) leaves the current step as it was and drops the iteration matrix.
    pub fn try_step(&mut self, h: f64) -> Result<f64, String> {
        let r = self.corrector(h);
        if r.is_err() {
            self.work.matrix_h = None;
        }
        r
    }

    /// Makes the trial step (from the last successful [`Integrator::try_step`]) current.
    pub fn accept(&mut self) {
        self.prev_a.copy_from_slice(&self.cur.a);
        self.prev_lambda.copy_from_slice(&self.cur.lambda);
        self.prev_h = Some(self.trial.s.time - self.cur.s.time);
        std::mem::swap(&mut self.cur, &mut self.trial);
    }

    /// The output at the current step: velocities and accelerations made consistent with the
    /// constraints, reactions.
    pub fn output(&mut self) -> Result<Output, String> {
        consistent_output(self.p, &self.cur.s, &self.cur.v, &mut self.work).map(|c| c.output)
    }

    /// Newton iteration of the HHT step (module docs) on the trial step.
    fn corrector(&mut self, h: f64) -> Result<f64, String> {
        let Integrator {
            p,
            settings,
            hht,
            cur,
            trial,
            prev_a,
            prev_lambda,
            prev_h,
            work: w,
        } = self;
        let p: &Problem = p;
        let Hht { alpha, beta, .. } = *hht;
        let n6 = 6 * p.n();
        let ucf = p.model.ucf();
        let length = p.model.characteristic_length;
        let t1 = cur.s.time + h;
        p.drives_into(t1, &mut w.drives)?;
        // Predictor: accelerations and multipliers extrapolated linearly from the last two
        // steps (the ratio of step sizes capped at 2), or the current ones.
        let r = prev_h
            .filter(|hp| *hp > 0.0)
            .map_or(0.0, |hp| (h / hp).min(2.0));
        for ((x, now), before) in trial.a.iter_mut().zip(&cur.a).zip(prev_a.iter()) {
            *x = now + r * (now - before);
        }
        for ((x, now), before) in trial
            .lambda
            .iter_mut()
            .zip(&cur.lambda)
            .zip(prev_lambda.iter())
        {
            *x = now + r * (now - before);
        }
        let mut converged = false;
        let mut da_prev = f64::INFINITY;
        // Contraction of the last correction relative to the one before (0: none yet).
        let mut rate = 0.0f64;
        // Whether the matrix was factorised during this step.
        let mut fresh = false;
        for it in 0..settings.maxit {
            trial.place(cur, h, *hht);
            trial.evaluate(p, w)?;
            // Residuals: r₁ = M a + (1+α)(Jᵀλ − Q) − α(Jᵀλ − Q)_n, r₂ = Φ/(βh²).
            let (r1, r2) = w.rhs.split_at_mut(n6);
            for (k, part) in p.model.parts.iter().enumerate() {
                let pose = &trial.s.poses[k];
                let ig = pose.r * part.inertia * pose.r.transpose();
                let a = &trial.a[6 * k..6 * k + 6];
                let ang = ig * DVec3::new(a[3], a[4], a[5]);
                for c in 0..3 {
                    r1[6 * k + c] = part.mass * a[c];
                    r1[6 * k + 3 + c] = ang[c];
                }
            }
            for ((r, ft), ft0) in r1.iter_mut().zip(&trial.force_term).zip(&cur.force_term) {
                *r += (1.0 + alpha) * ft - alpha * ft0;
            }
            // Position constraints to the assembly accuracy.
            let mut phi_ok = true;
            // The constraints see the analysis time (frozen when settling).
            let constrained = p.force_state(&trial.s, &mut w.force_state);
            for ((r, &row), &drive) in r2.iter_mut().zip(p.rows).zip(&w.drives) {
                let raw = p.sys.residual(row, constrained, drive);
                *r = raw / (beta * h * h);
                let limit = match p.sys.rows[row].unit {
                    RowUnit::Length | RowUnit::Mixed => CORRECTOR_CONSTRAINT * length,
                    _ => CORRECTOR_CONSTRAINT,
                };
                phi_ok &= raw.abs() <= limit;
            }
            // Modified Newton: the matrix is kept across iterations and steps, and refreshed
            // when there is none, when the step size is more than a factor 2 away from the
            // one it was built for, when the last correction contracted by less than
            // `MATRIX_REFRESH_RATE` (the matrix no longer describes the iterate well), or
            // when three iterations with a matrix from an earlier step did not converge.
            let stale = w.matrix_h.is_none_or(|hh| h > 2.0 * hh || h < 0.5 * hh)
                || rate > MATRIX_REFRESH_RATE
                || (it >= 3 && !fresh);
            if stale {
                w.matrix_h = None;
                assemble_iteration_matrix(p, &trial.s, &trial.lambda, h, *hht, w)?;
                w.matrix.factor().map_err(|err| {
                    format!("the integrator's Newton matrix cannot be factorised: {err}")
                })?;
                w.matrix_h = Some(h);
                fresh = true;
            }
            for x in w.rhs.iter_mut() {
                *x = -*x;
            }
            w.matrix
                .solve_in_place(&mut w.rhs)
                .map_err(|_| "the integrator's Newton matrix is singular".to_string())?;
            let amax = (0..n6)
                .map(|i| trial.a[i].abs() * scale(i, length))
                .fold(0.0, f64::max)
                .max(1.0 / (h * h) * 1e-12);
            let mut da = 0.0f64;
            for i in 0..n6 {
                trial.a[i] += w.rhs[i];
                da = da.max(w.rhs[i].abs() * scale(i, length));
            }
            for (l, d) in trial.lambda.iter_mut().zip(&w.rhs[n6..]) {
                *l += d / ucf;
            }
            // Converged when the constraints hold and the correction is negligible relative
            // to the accelerations, or its effect on positions is at rounding level.
            // Coordinates far from the origin (a 1000-loop chain reaches x = 1000 m) resolve
            // positions to ε·|x| only, so the residuals carry noise that the scaled matrix
            // turns into corrections of ε·|x|/(βh²) in the accelerations: a correction that
            // no longer contracts (at least halving) with a matrix built during this step,
            // while moving positions by less than a tenth of the constraint tolerance, is
            // that noise, and the iterate is as converged as the arithmetic allows.
            let moved = beta * h * h * da;
            let stagnant = fresh && da >= 0.5 * da_prev && moved <= CORRECTOR_NOISE;
            // Parts with tiny inertia about some axis leave corrections at noise level too:
            // a correction whose effect on positions and velocities (velocities times the
            // step) is a negligible fraction of the integration ERROR is accepted.
            let negligible =
                beta.max(hht.gamma) * h * h * da <= CORRECTOR_ERROR_FRACTION * settings.error;
            if phi_ok
                && (da <= CORRECTOR_RELATIVE * amax.max(1e-8)
                    || moved <= CORRECTOR_ROUNDING
                    || stagnant
                    || negligible)
            {
                converged = true;
                break;
            }
            // The rate compares two corrections made with the same matrix.
            rate = if !stale && da_prev.is_finite() && da_prev > 0.0 {
                da / da_prev
            } else {
                0.0
            };
            da_prev = da;
        }
        if !converged {
            return Err(format!(
                "the corrector did not converge in {} iterations at time {t1}",
                settings.maxit
            ));
        }
        // Final positions, velocities and force term from the converged accelerations.
        trial.place(cur, h, *hht);
        trial.evaluate(p, w)?;
        // Local error estimate (scaled: translations over the characteristic length).
        let err = (0..n6)
            .map(|i| {
                h * h * (beta - 1.0 / 6.0).abs() * (trial.a[i] - cur.a[i]).abs() * scale(i, length)
            })
            .fold(0.0, f64::max);
        Ok(err)
    }
}

/// Consistent outputs (velocities, accelerations, reactions) at given positions with one
/// reused workspace: the output solve of the kinematic analysis.
pub(crate) struct OutputSolver {
    work: Workspace,
}

impl OutputSolver {
    pub(crate) fn new(p: &Problem, start: &State, v0: &Velocities) -> Result<Self, String> {
        let v0: Vec<(DVec3, DVec3)> = (0..p.n())
            .map(|k| v0.get(k).copied().unwrap_or((DVec3::ZERO, DVec3::ZERO)))
            .collect();
        Ok(OutputSolver {
            work: Workspace::new(p, start, &v0, Hht::new(0.0))?,
        })
    }

    /// The output at positions `s` (time `s.time`) from the velocity guess `v` (6 per part).
    pub(crate) fn output(&mut self, p: &Problem, s: &State, v: &[f64]) -> Result<Output, String> {
        consistent_output(p, s, v, &mut self.work).map(|c| c.output)
    }
}

/// The corrector refreshes its matrix when a correction is more than this fraction of the one
/// before (modified Newton converging too slowly).
const MATRIX_REFRESH_RATE: f64 = 0.05;

/// Simulates from `start` (assembled, with consistent velocities `v0`) to `end`, with output at
/// `times` (ascending, within [start.time, end]).
pub fn simulate(
    p: &Problem,
    start: &State,
    v0: &[(DVec3, DVec3)],
    times: &[f64],
    settings: &IntegratorSettings,
    progress: impl FnMut(f64),
) -> Simulation {
    let mut outputs = Vec::new();
    let mut sim = simulate_with(p, start, v0, times, settings, progress, |o| {
        outputs.push(o);
        AfterOutput::Continue
    });
    sim.outputs = outputs;
    sim
}

/// What the caller of [`simulate_with`] wants after an output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AfterOutput {
    Continue,
    /// End the run at this output (dynamic settling met its limits).
    Stop,
}

/// [`simulate`], handing each output to `on_output` instead of keeping it (the returned
/// simulation's `outputs` is empty): one integrator, one symbolic analysis and no stored
/// history for a run that only watches its outputs (dynamic settling).
pub fn simulate_with(
    p: &Problem,
    start: &State,
    v0: &[(DVec3, DVec3)],
    times: &[f64],
    settings: &IntegratorSettings,
    mut progress: impl FnMut(f64),
    mut on_output: impl FnMut(Output) -> AfterOutput,
) -> Simulation {
    let n = p.n();
    let m = p.rows.len();
    let mut sim = Simulation {
        outputs: Vec::new(),
        failure: None,
        steps: 0,
        rejected: 0,
        kinematic: m >= 6 * n && n > 0,
    };
    if sim.kinematic {
        let mut run = crate::stages::kinematics::run(p, start, v0, times, progress);
        for o in std::mem::take(&mut run.outputs) {
            if on_output(o) == AfterOutput::Stop {
                break;
            }
        }
        return run;
    }
    let length = p.model.characteristic_length;
    let t_end = times.last().copied().unwrap_or(start.time);
    // Consistent accelerations at the start.
    let (mut integ, first) = match Integrator::new(p, start, v0, settings) {
        Ok(x) => x,
        Err(e) => {
            sim.failure = Some(Failure {
                time: start.time,
                message: e,
            });
            return sim;
        }
    };
    let mut next_output = 0;
    if times
        .first()
        .is_some_and(|t| (*t - start.time).abs() <= 1e-12 * t_end.abs().max(1.0))
    {
        if on_output(first) == AfterOutput::Stop {
            return sim;
        }
        next_output = 1;
    }
    let span = (t_end - start.time).max(1e-300);
    let hmax = settings.hmax.unwrap_or(span / 10.0).min(span);
    let mut h = settings
        .hinit
        .unwrap_or((span / 1000.0).min(hmax))
        .min(hmax);
    while next_output < times.len() {
        let target = times[next_output];
        let t = integ.time();
        let remaining = target - t;
        // Take the rest when it fits; split it in two rather than leave a sliver.
        let mut hs = if remaining <= h * (1.0 + 1e-9) {
            remaining
        } else if remaining < 2.0 * h {
            remaining / 2.0
        } else {
            h
        };
        let hit = hs >= remaining - 1e-12 * span;
        if hit {
            hs = remaining;
        }
        if hs <= 0.0 {
            next_output += 1;
            continue;
        }
        match integ.try_step(hs) {
            Ok(err) => {
                let tol = settings.error;
                if err > tol && hs > settings.hmin * 1.0001 {
                    sim.rejected += 1;
                    h = (hs * (0.9 * (tol / err).powf(1.0 / 3.0)).clamp(0.2, 0.9))
                        .max(settings.hmin);
                    continue;
                }
                sim.steps += 1;
                integ.accept();
                let now = integ.time();
                progress(now);
                if let Some(f) = redundant_violation(p, integ.state(), length) {
                    sim.failure = Some(f);
                    return sim;
                }
                let grow = if err > 0.0 {
                    (0.9 * (tol / err).powf(1.0 / 3.0)).clamp(0.2, 2.0)
                } else {
                    2.0
                };
                // A step shortened to hit an output does not shrink the step size.
                h = (hs * grow)
                    .max(if hit { h } else { 0.0 })
                    .min(hmax)
                    .max(settings.hmin);
                if hit {
                    match integ.output() {
                        Ok(o) => {
                            if on_output(o) == AfterOutput::Stop {
                                return sim;
                            }
                        }
                        Err(e) => {
                            sim.failure = Some(Failure {
                                time: now,
                                message: e,
                            });
                            return sim;
                        }
                    }
                    next_output += 1;
                }
            }
            Err(e) => {
                if hs <= settings.hmin * 1.0001 {
                    sim.failure = Some(Failure {
                        time: t,
                        message: format!("{e} (step size {hs:.3e} at its minimum)"),
                    });
                    return sim;
                }
                sim.rejected += 1;
                h = (hs * 0.25).max(settings.hmin);
            }
        }
    }
    sim
}

/// The first redundant row (removed as consistent) that no longer holds at `s`: Adams'
/// "consistent redundant constraint that becomes inconsistent", with element, equation, time
/// and value.
pub(crate) fn redundant_violation(p: &Problem, s: &State, length: f64) -> Option<Failure> {
    let tol = crate::tolerances::Tolerances {
        length: 1e-6,
        angle: 1e-6,
        ..Default::default()
    };
    for &r in p.redundant {
        let row = &p.sys.rows[r];
        let drive = if row.driven {
            p.drivers.value(row.element, p.time(s.time))
        } else {
            Some(0.0)
        };
        let Some(drive) = drive else { continue };
        let val = p.sys.residual(r, s, drive);
        if !within_tolerance(row.unit, val, &tol, length) {
            let c = &p.model.constraints[row.element];
            return Some(Failure {
                time: s.time,
                message: format!(
                    "the redundant equation {} of {} (removed as consistent) became inconsistent: residual {:.6e}{}",
                    row.label,
                    c.origin.name,
                    report_residual(row.unit, val),
                    report_unit_suffix(row.unit)
                ),
            });
        }
    }
    None
}

/// Output values made consistent with the constraints at `s`.
struct Consistent {
    output: Output,
    velocities: Vec<(DVec3, DVec3)>,
    accelerations: Vec<(DVec3, DVec3)>,
    lambda: Vec<f64>,
}

/// Projects velocities onto `J v = ḟ − ∂Φ/∂t` (least change, mass-weighted) and solves the
/// accelerations and multipliers (`M a + UCF·Jᵀλ = UCF·Q`, `J a = f̈ − γ`, with the exact
/// velocity-product terms γ of every row, general constraints included:
/// [`System::acceleration_bias`]). `M` is regularised by `1e-12·m·L²` on the rotational
/// diagonal only for parts whose inertia is singular (point masses, massless parts; `1e-12`
/// for a massless part's mass): elsewhere the equations are exact, so that a constraint wrench
/// recovered from them (FORCE requests) vanishes to rounding where it should. The matrix
/// `[M, Jᵀ; J, 0]` keeps its pattern in `w.projection`.
fn consistent_output(
    p: &Problem,
    s: &State,
    v: &[f64],
    w: &mut Workspace,
) -> Result<Consistent, String> {
    let n = p.n();
    let m = p.rows.len();
    let dim = 6 * n + m;
    let ucf = p.model.ucf();
    let length = p.model.characteristic_length;
    // The constraint expressions see the analysis time (frozen when settling).
    let mut frozen = s.clone();
    let se: &State = p.force_state(s, &mut frozen);
    p.gradients(se, &mut w.grads);
    let grads = &w.grads;
    let reg = |k: usize| {
        let part = &p.model.parts[k];
        let inertia = &part.inertia;
        let trace = inertia.x_axis.x + inertia.y_axis.y + inertia.z_axis.z;
        let singular = trace <= 0.0 || inertia.determinant() <= 1e-10 * (trace / 3.0).powi(3);
        let mass = if part.mass > 0.0 { part.mass } else { 1e-12 };
        if singular {
            1e-12 * mass * length * length
        } else {
            0.0
        }
    };
    if w.projection_pattern != w.matrix_pattern {
        w.projection = w.matrix.same_pattern().map_err(|e| {
            format!("the consistent velocity/acceleration solve cannot be set up: {e}")
        })?;
        w.projection_pattern = w.matrix_pattern;
    }
    let lu = &mut w.projection;
    assemble_growing(lu, "the consistent velocity/acceleration solve", |a| {
        add_mass(p, s, a, reg);
        for (k, g) in grads.iter().enumerate() {
            for (body, b) in &g.blocks {
                a.add_block((6 * body, 6 * n + k), (6, 1), 1.0, |i, _| b[i]);
                a.add_block((6 * n + k, 6 * body), (1, 6), 1.0, |_, j| b[j]);
            }
        }
    })?;
    lu.factor()
        .map_err(|e| format!("the consistent velocity/acceleration solve failed: {e}"))?;
    // Velocities: rhs = [M v; ḟ] (ḟ = J v for rows without a drive rate).
    let mut rhs = vec![0.0; dim];
    for (k, part) in p.model.parts.iter().enumerate() {
        let ig = s.poses[k].r * part.inertia * s.poses[k].r.transpose();
        let w_k = DVec3::new(v[6 * k + 3], v[6 * k + 4], v[6 * k + 5]);
        let hw = ig * w_k + w_k * reg(k);
        for c in 0..3 {
            rhs[6 * k + c] = part.mass * v[6 * k + c];
            rhs[6 * k + 3 + c] = hw[c];
        }
    }
    let time_rate = p.time_rate();
    for (k, &r) in p.rows.iter().enumerate() {
        let row = &p.sys.rows[r];
        rhs[6 * n + k] = if row.driven {
            match drive_series(p, row.element, s.time) {
                Some(f) => f[1],
                None => rate_of(&grads[k], v),
            }
        } else {
            -p.sys
                .explicit_rate(r, se, time_rate)
                .map_err(|e| p.row_error(r, &e))?
        };
    }
    lu.solve_in_place(&mut rhs)
        .map_err(|_| "the velocity projection is singular".to_string())?;
    let velocities = unflat(&rhs[..6 * n]);
    // Accelerations and multipliers.
    let mut q = vec![0.0; 6 * n];
    p.generalized_into(s, &velocities, &mut w.force_state, &mut q)?;
    let mut rhs = vec![0.0; dim];
    rhs[..6 * n].copy_from_slice(&q);
    for (k, &r) in p.rows.iter().enumerate() {
        let row = &p.sys.rows[r];
        let bias = p
            .sys
            .acceleration_bias(r, se, &velocities, time_rate)
            .map_err(|e| p.row_error(r, &e))?;
        let fdd = if row.driven {
            drive_series(p, row.element, s.time).map_or(0.0, |f| f[2])
        } else {
            0.0
        };
        rhs[6 * n + k] = fdd - bias;
    }
    lu.solve_in_place(&mut rhs)
        .map_err(|_| "the acceleration solve is singular".to_string())?;
    let accelerations = unflat(&rhs[..6 * n]);
    // Multipliers in force units (M a + Jᵀμ = UCF·Q → λ = μ/UCF).
    let lambda: Vec<f64> = rhs[6 * n..].iter().map(|x| x / ucf).collect();
    let rg: Vec<(usize, &RowGradient)> = p.rows.iter().copied().zip(grads.iter()).collect();
    let reactions = element_reactions(p.model, p.sys, &rg, &lambda, s);
    Ok(Consistent {
        output: Output {
            time: s.time,
            state: s.clone(),
            velocities: velocities.clone(),
            accelerations: accelerations.clone(),
            reactions,
        },
        velocities,
        accelerations,
        lambda,
    })
}

fn rate_of(g: &RowGradient, v: &[f64]) -> f64 {
    g.blocks
        .iter()
        .map(|(k, b)| (0..6).map(|c| b[c] * v[6 * k + c]).sum::<f64>())
        .sum()
}

/// `[f, ḟ, f̈]` of a motion at time t (frozen time gives zero rates).
fn drive_series(p: &Problem, element: usize, t: f64) -> Option<[f64; 3]> {
    if let Some(t0) = p.frozen_time {
        return p.drivers.value(element, t0).map(|f| [f, 0.0, 0.0]);
    }
    p.drivers.rates(element, t)
}
