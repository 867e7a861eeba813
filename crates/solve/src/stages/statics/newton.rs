//! The static Newton iteration's problem (read-only) and workspace (buffers and matrices sized
//! once per solve, like the integrator's): an iteration allocates nothing itself.
//!
//! Two sparse matrices, each a [`TripletLu`] refactorised in place:
//!
//! ```text
//! Newton matrix        [K_T + STABILITY·M   Jᵀ − ∂Q/∂λ   −∂Q/∂x]      K_T = −∂Q/∂q + Σ_r λ_r ∂²Φ_r/∂q²
//!                      [J                   0           0     ]
//!                      [∂r/∂q               0           ∂r/∂x ]  (rows of free control states)
//! constraint KKT       [W   Jᵀ]                     W diagonal (per-coordinate weights)
//!                      [J   0 ]
//! ```
//!
//! Each is assembled as triplets into a list whose capacity is kept; while the coordinates
//! repeat (the usual case), the column ordering and symbolic analysis are reused and a refresh
//! is a numeric refactorisation, giving the same bits as a fresh factorisation. The KKT matrix
//! serves the least-change projection onto the constraints and the least-squares multipliers.
//!
//! Control states (DIFF, LSE, TFSISO) join the Newton unknowns after the multipliers: a free
//! state solves its equation with zero rate, `r(q, 0, x, ẋ = 0, t) = 0` (explicit: `f = 0`),
//! a STATIC_HOLD state keeps its value (an identity row). The KKT matrix leaves them out.
//!
//! `∂Q/∂λ` is joint friction's: its normal load follows the joint's multipliers
//! ([`friction_load`]).

mod friction_load;

use super::StaticsError;
use crate::constraints::hessian::HessianBlocks;
use crate::constraints::rows::RowGradient;
use crate::constraints::system::System;
use crate::linalg::kkt::{push_constraint_row, ConstraintBlocks, CoordinateScale, Zeros};
use crate::linalg::linear::LinearError;
use crate::linalg::triplet_lu::TripletLu;
use crate::physics::applied::{AppliedForces, ForceError, Regime};
use crate::physics::mass::ground_inertia;
use crate::state::State;
use crate::tolerances::STATIC_MASS_FLOOR;
use friction_load::FrictionLoads;
use glam::DVec3;
use linkage_model::settings::EquilibriumSettings;
use linkage_model::Model;

/// What one equilibrium solve works on, read-only.
pub(super) struct Problem<'a> {
    pub model: &'a Model,
    pub sys: &'a System,
    /// The constraint rows in the solve with their drive values.
    pub used: Vec<(usize, f64)>,
    pub forces: &'a dyn AppliedForces,
    pub settings: &'a EquilibriumSettings,
}

impl Problem<'_> {
    /// Number of parts n.
    pub fn parts(&self) -> usize {
        self.model.parts.len()
    }

    /// Order of the KKT matrix, `6n + m`.
    pub fn dim(&self) -> usize {
        6 * self.parts() + self.used.len()
    }

    /// Number of control states (after the multipliers in the Newton matrix).
    pub fn controls(&self) -> usize {
        self.forces.control_count()
    }

    /// Whether control state `i` is held (STATIC_HOLD).
    pub fn held(&self, i: usize) -> bool {
        self.model.controls.held(i)
    }
}

/// Buffers of one static solve, sized once ([`Workspace::new`]).
pub(super) struct Workspace {
    /// Velocities the force elements see: the parts are at rest (n).
    pub rest: Vec<(DVec3, DVec3)>,
    /// Gradients of the rows in the solve at the current iterate (m).
    pub grads: Vec<RowGradient>,
    /// Force residual `F = Q + Q_gravity − Jᵀλ` (6n).
    pub force: Vec<f64>,
    /// Constraint residuals `Φ` (m).
    pub phi: Vec<f64>,
    /// Residuals of the control states' equations (0 for held ones) (nx).
    pub state_residual: Vec<f64>,
    /// Right-hand side `[F; −Φ; −r]`, then the Newton correction `[δ; δλ; δx]` (6n + m + nx).
    pub rhs: Vec<f64>,
    /// Each part's correction `(δx, δθ)` (n) and whether it runs away (n).
    pub steps: Vec<(DVec3, DVec3)>,
    pub runaway: Vec<bool>,
    /// Rows whose second derivatives could not be evaluated at the last Newton matrix (m).
    pub approximate: Vec<bool>,
    /// Applied load for the least-squares multipliers (6n).
    load: Vec<f64>,
    hessian: HessianBlocks,
    /// Force Jacobian `∂Q/∂q` as triplets.
    dq: Vec<(usize, usize, f64)>,
    /// The control states' `∂r/∂(q, v, x, ẋ)` and the forces' `∂Q/∂(x, ẋ)` as triplets.
    dr: Vec<(usize, usize, f64)>,
    dqx: Vec<(usize, usize, f64)>,
    /// Gradient scratch of the KKT assembly.
    gradient: RowGradient,
    /// The Newton matrix and whether it has been factorised.
    newton: TripletLu,
    newton_factored: bool,
    kkt: TripletLu,
    /// Right-hand side and solution of the KKT solves (6n + m).
    kkt_rhs: Vec<f64>,
    /// Joint frictions, their normal loads taken from the multipliers of the iterate.
    frictions: Option<FrictionLoads>,
}

impl Workspace {
    /// Buffers for `p`.
    pub fn new(p: &Problem, start: &State) -> Workspace {
        let (n, m, dim) = (p.parts(), p.used.len(), p.dim());
        let nx = p.controls();
        Workspace {
            rest: vec![(DVec3::ZERO, DVec3::ZERO); n],
            grads: vec![RowGradient::default(); m],
            force: vec![0.0; 6 * n],
            phi: vec![0.0; m],
            state_residual: vec![0.0; nx],
            rhs: vec![0.0; dim + nx],
            steps: vec![(DVec3::ZERO, DVec3::ZERO); n],
            runaway: vec![false; n],
            approximate: vec![false; m],
            load: vec![0.0; 6 * n],
            hessian: HessianBlocks::default(),
            dq: Vec::new(),
            dr: Vec::new(),
            dqx: Vec::new(),
            gradient: RowGradient::default(),
            newton: TripletLu::new(dim + nx),
            newton_factored: false,
            kkt: TripletLu::new(dim),
            kkt_rhs: vec![0.0; dim],
            frictions: FrictionLoads::new(p, start),
        }
    }

    /// The residuals at `s`, `λ`: the rows' gradients, the frictions' normal loads from `λ`
    /// (set in `s` by [`FrictionLoads::update`]), `F` and `Φ`. Returns the largest applied
    /// load component `max |Q + Q_gravity|`.
    pub fn residuals(
        &mut self,
        p: &Problem,
        s: &mut State,
        lambda: &[f64],
    ) -> Result<f64, ForceError> {
        for (k, (r, _)) in p.used.iter().enumerate() {
            p.sys.gradient(*r, s, &mut self.grads[k]);
        }
        if let Some(f) = self.frictions.as_mut() {
            f.update(p, s, &self.grads, lambda);
        }
        let s: &State = s;
        applied(p, s, &self.rest, &mut self.force)?;
        let load = self.force.iter().map(|x| x.abs()).fold(0.0, f64::max);
        for (k, g) in self.grads.iter().enumerate() {
            for (body, b) in &g.blocks {
                for (f, x) in self.force[6 * body..6 * body + 6].iter_mut().zip(b) {
                    *f -= lambda[k] * x;
                }
            }
        }
        for (phi, (r, d)) in self.phi.iter_mut().zip(&p.used) {
            *phi = p.sys.residual(*r, s, *d);
        }
        if !self.state_residual.is_empty() {
            p.forces
                .control_residuals(s, &self.rest, &mut self.state_residual)?;
            for (i, r) in self.state_residual.iter_mut().enumerate() {
                if p.held(i) {
                    *r = 0.0;
                }
            }
        }
        Ok(load)
    }

    /// The factor on the step `scale·steps` that keeps the frictions inside their stiction
    /// bands ([`FrictionLoads::stiction_scale`]); 1 without frictions.
    pub fn stiction_scale(&mut self, p: &Problem, s: &State, scale: f64) -> f64 {
        match self.frictions.as_mut() {
            Some(f) => f.stiction_scale(p, s, &self.steps, scale, &self.rest),
            None => 1.0,
        }
    }

    /// Whether a Newton matrix has been factorised.
    pub fn has_newton_matrix(&self) -> bool {
        self.newton_factored
    }

    /// Assembles and factorises the Newton matrix at `s`, `λ` (gradients from the last
    /// [`Workspace::residuals`]).
    pub fn refresh_newton_matrix(
        &mut self,
        p: &Problem,
        s: &State,
        lambda: &[f64],
    ) -> Result<(), StaticsError> {
        self.dq.clear();
        p.forces
            .add_jacobians(Regime::Static, s, &self.rest, &mut self.dq, None)?;
        self.dr.clear();
        self.dqx.clear();
        if p.controls() > 0 {
            p.forces.control_jacobian(s, &self.rest, &mut self.dr)?;
            p.forces
                .add_control_force_jacobian(Regime::Static, s, &self.rest, &mut self.dqx)?;
        }
        let mut second = SecondDerivatives {
            hessian: &mut self.hessian,
            approximate: &mut self.approximate,
        };
        self.newton.clear();
        fill_newton(
            p,
            s,
            lambda,
            &self.dq,
            &self.grads,
            &mut second,
            &mut self.newton.entries,
        );
        if let Some(f) = &self.frictions {
            f.fill(p, s, &self.rest, &mut self.newton.entries);
        }
        fill_control_blocks(p, &self.dr, &self.dqx, &mut self.newton.entries);
        let stability = p.settings.stability;
        self.newton
            .factor()
            .map_err(|cause| StaticsError::Factor { cause, stability })?;
        self.newton_factored = true;
        Ok(())
    }

    /// The Newton correction: `rhs = [F; −Φ; −r]` solved with the last Newton matrix
    /// (`stability`, EQUILIBRIUM/STABILITY, for the message of a singular one).
    pub fn newton_correction(&mut self, stability: f64) -> Result<(), StaticsError> {
        let n6 = self.force.len();
        let m = self.phi.len();
        self.rhs[..n6].copy_from_slice(&self.force);
        for (x, v) in self.rhs[n6..n6 + m].iter_mut().zip(&self.phi) {
            *x = -v;
        }
        for (x, v) in self.rhs[n6 + m..].iter_mut().zip(&self.state_residual) {
            *x = -v;
        }
        self.newton
            .solve_in_place(&mut self.rhs)
            .map_err(|_| StaticsError::Singular { stability })
    }

    /// A few minimum-change Gauss–Newton corrections of the positions onto `Φ = 0` (each row
    /// within `tolerance`): `[W Jᵀ; J 0][δ; μ] = [0; −Φ]`, `W = diag(1/L², 1)` per part. Stops
    /// quietly when the KKT matrix is singular.
    pub fn project_onto_constraints(&mut self, p: &Problem, s: &mut State, tolerance: f64) {
        let n = p.parts();
        let l2 = p.model.characteristic_length.powi(2);
        for _ in 0..4 {
            self.kkt_rhs[..6 * n].fill(0.0);
            let mut within = true;
            for (x, (r, d)) in self.kkt_rhs[6 * n..].iter_mut().zip(&p.used) {
                let phi = p.sys.residual(*r, s, *d);
                within &= phi.abs() <= tolerance;
                *x = -phi;
            }
            if within {
                return;
            }
            let weight = |k: usize| if k % 6 < 3 { 1.0 / l2 } else { 1.0 };
            if self.solve_kkt(p, s, weight).is_err() {
                return;
            }
            for k in 0..n {
                let x = &self.kkt_rhs[6 * k..6 * k + 6];
                s.increment(
                    k,
                    DVec3::new(x[0], x[1], x[2]),
                    DVec3::new(x[3], x[4], x[5]),
                );
            }
        }
    }

    /// Least-squares multipliers, `min |Q − Jᵀλ|_W` (torques weighted by 1/L²), written to
    /// `lambda` (zero when the KKT matrix is singular), so that the first Newton matrix already
    /// holds the geometric stiffness.
    pub fn initial_multipliers(
        &mut self,
        p: &Problem,
        s: &State,
        lambda: &mut [f64],
    ) -> Result<(), ForceError> {
        let n = p.parts();
        if p.used.is_empty() {
            return Ok(());
        }
        let l2 = p.model.characteristic_length.powi(2);
        let weight = |k: usize| if k % 6 < 3 { 1.0 } else { l2 };
        applied(p, s, &self.rest, &mut self.load)?;
        for (k, (x, q)) in self.kkt_rhs.iter_mut().zip(&self.load).enumerate() {
            *x = q * weight(k);
        }
        self.kkt_rhs[6 * n..].fill(0.0);
        match self.solve_kkt(p, s, weight) {
            Ok(()) => lambda.copy_from_slice(&self.kkt_rhs[6 * n..]),
            Err(_) => lambda.fill(0.0),
        }
        Ok(())
    }

    /// Solves `[W Jᵀ; J 0] x = kkt_rhs` in place, `W = diag(weight(k))`, J at `s`.
    fn solve_kkt(
        &mut self,
        p: &Problem,
        s: &State,
        weight: impl Fn(usize) -> f64,
    ) -> Result<(), LinearError> {
        let n = p.parts();
        self.kkt.clear();
        let e = &mut self.kkt.entries;
        for k in 0..6 * n {
            e.push((k, k, weight(k)));
        }
        for (k, (r, _)) in p.used.iter().enumerate() {
            p.sys.gradient(*r, s, &mut self.gradient);
            push_constraint_row(e, 6 * n, &UNIT_BLOCKS, k, &self.gradient);
        }
        self.kkt.factor()?;
        self.kkt.solve_in_place(&mut self.kkt_rhs)
    }
}

/// Scratch and bookkeeping of the rows' second derivatives.
struct SecondDerivatives<'w> {
    hessian: &'w mut HessianBlocks,
    approximate: &'w mut [bool],
}

/// The entries of the Newton matrix at `s`, `λ`, in a fixed order (the sums of duplicates are
/// those of a triplet assembly): `−∂Q/∂q`, the geometric stiffness `λ_r ∂²Φ_r/∂q²` of every
/// row with a nonzero multiplier (marking rows whose second derivatives cannot be evaluated),
/// `STABILITY·M` (mass in the model's force units, `R I Rᵀ` for rotations) with a floor of
/// [`STATIC_MASS_FLOOR`] on the translational diagonal, then `J` and `Jᵀ`.
fn fill_newton(
    p: &Problem,
    s: &State,
    lambda: &[f64],
    dq: &[(usize, usize, f64)],
    grads: &[RowGradient],
    second: &mut SecondDerivatives,
    out: &mut Vec<(usize, usize, f64)>,
) {
    let n = p.parts();
    for &(i, j, v) in dq {
        out.push((i, j, -v));
    }
    for (k, (r, _)) in p.used.iter().enumerate() {
        if lambda[k] == 0.0 {
            continue;
        }
        second.hessian.clear();
        second.approximate[k] = !p.sys.hessian(*r, s, 1.0, second.hessian);
        for &(br, rs, bc, cs, m) in &second.hessian.blocks {
            for i in 0..3 {
                for j in 0..3 {
                    let v = m.col(j)[i] * lambda[k];
                    if v != 0.0 {
                        out.push((6 * br + 3 * rs + i, 6 * bc + 3 * cs + j, v));
                    }
                }
            }
        }
    }
    let mass_scale = p.settings.stability / p.model.ucf();
    for (k, part) in p.model.parts.iter().enumerate() {
        let ig = ground_inertia(part, &s.poses[k]);
        for c in 0..3 {
            out.push((
                6 * k + c,
                6 * k + c,
                mass_scale * part.mass + STATIC_MASS_FLOOR * (1.0 + part.mass),
            ));
            for d in 0..3 {
                let x = ig.col(d)[c] * mass_scale;
                if x != 0.0 {
                    out.push((6 * k + 3 + c, 6 * k + 3 + d, x));
                }
            }
        }
    }
    for (k, g) in grads.iter().enumerate() {
        push_constraint_row(out, 6 * n, &UNIT_BLOCKS, k, g);
    }
}

/// The control states' rows and columns of the Newton matrix (module docs): `∂r/∂q` and
/// `∂r/∂x` in a free state's row (rates are zero in statics: their columns are left out), an
/// identity row for a held state, `−∂Q/∂x` in the equations of motion.
fn fill_control_blocks(
    p: &Problem,
    dr: &[(usize, usize, f64)],
    dqx: &[(usize, usize, f64)],
    out: &mut Vec<(usize, usize, f64)>,
) {
    let (n, nx) = (p.parts(), p.controls());
    let base = 6 * n + p.used.len();
    for &(i, var, d) in dr {
        if p.held(i) || d == 0.0 {
            continue;
        }
        if var < 6 * n {
            out.push((base + i, var, d));
        } else if (12 * n..12 * n + nx).contains(&var) {
            out.push((base + i, base + var - 12 * n, d));
        }
    }
    for i in 0..nx {
        if p.held(i) {
            out.push((base + i, base + i, 1.0));
        } else {
            // Claims the diagonal (a state whose equation does not hold it is singular,
            // which the factorisation reports).
            out.push((base + i, base + i, 0.0));
        }
    }
    for &(row, col, d) in dqx {
        if col < nx && d != 0.0 {
            out.push((row, base + col, -d));
        }
    }
}

/// The constraint blocks of both statics matrices: `J` and `Jᵀ` unscaled, zeros left out.
const UNIT_BLOCKS: ConstraintBlocks = ConstraintBlocks {
    scale: CoordinateScale::IDENTITY,
    row_factor: 1.0,
    transpose_factor: 1.0,
    zeros: Zeros::Skip,
};

/// Generalised applied forces including gravity (`m g / UCF` at each centre of mass) into
/// `out` (6n).
fn applied(
    p: &Problem,
    s: &State,
    rest: &[(DVec3, DVec3)],
    out: &mut [f64],
) -> Result<(), ForceError> {
    out.fill(0.0);
    let ucf = p.model.ucf();
    for (k, part) in p.model.parts.iter().enumerate() {
        for c in 0..3 {
            out[6 * k + c] = part.mass * p.model.gravity[c] / ucf;
        }
    }
    p.forces.add_forces(Regime::Static, s, rest, out)
}
