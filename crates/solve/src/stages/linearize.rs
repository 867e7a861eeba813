//! Linearization about an operating point (DESIGN §7, ADM-REFERENCE §8.6): eigenvalues,
//! undamped natural frequencies, damping ratios and mode shapes.
//!
//! Equations of motion `M q̈ = UCF·(Q(q, v) − Jᵀλ)` with `J δq = 0` are linearised exactly:
//!
//! ```text
//! M δq̈ + C δq̇ + K δq = 0,   K = UCF·(−∂Q/∂q + Σ λ_r ∂²Φ_r/∂q²),   C = −UCF·∂Q/∂v + G(ω)
//! ```
//!
//! (G the gyroscopic term, zero at rest). [`assemble`] writes M, C, K and the Jacobian J of
//! the kept rows once, as sparse triplets in scaled tangent coordinates (6 per part,
//! translations in characteristic lengths); both solutions start from it:
//!
//! * **dense** ([`EigenMethod::Dense`]): an orthonormal basis N of the null space of J (dense
//!   QR of Jᵀ), `M_r = NᵀMN`, `C_r`, `K_r`, and every eigenvalue of the first-order system
//!   `ẋ = A x`, `A = [0 1; −M_r⁻¹K_r −M_r⁻¹C_r]`. Cost `O((6·parts)³)`.
//! * **shift-invert** ([`EigenMethod::ShiftInvert`]): the `K` modes nearest a shift (the
//!   lowest, or around a frequency) by Arnoldi on one sparse KKT factorisation
//!   ([`crate::linalg::eigs`]), without N: without damping on `K x + Jᵀμ = ν M x` (`ν = −λ²`), with
//!   damping on the first-order form. The free motions without stiffness are counted on the
//!   same kind of problem with the symmetric part of K. Free motions of single parts without
//!   stiffness or damping (a rod's spin between two spherical joints, a free-floating body)
//!   are found structurally and deflated first ([`crate::linalg::eigs::deflate`]): their zero
//!   eigenvalues are counted, not listed, so `K` modes are the `K` lowest others. Cost grows
//!   with `K` and the sparse factor (linear in the length of a chain), not with `n³`: the
//!   20 lowest modes of a chain of 1,000 rods on spherical joints (6,000 coordinates, 1,000
//!   free spins) take about 0.1 s.
//!
//! With [`EigenMethod::ShiftInvert`] the `K` modes nearest the shift are listed whichever
//! solution ran (a model with control states is solved densely).
//!
//! [`EigenMethod::Auto`] solves densely up to [`DENSE_MAX_DOF`] free motions and
//! [`DENSE_MAX_COORDINATES`] coordinates, and otherwise computes the [`DEFAULT_MODES`] lowest
//! modes by shift-invert. Massless parts get a small mass and inertia sized from the model
//! ([`crate::physics::mass::MasslessSubstitute`]), as Adams does.
//!
//! Control states (DIFF, LSE, TFSISO; [`ControlEquations`]) join the first-order form as
//! states after `[z; ż]`: their equations `r(q, v, x, ẋ) = 0` give
//! `δẋ = F_q δq + F_v δv + F_x δx` with `F_• = −(∂r/∂ẋ)⁻¹ ∂r/∂•`, and they act on the
//! mechanics through `G = UCF·(∂Q/∂x + ∂Q/∂ẋ F_x)` (with `∂Q/∂ẋ F_q`, `∂Q/∂ẋ F_v` in K and C).
//! A model with control states is solved densely whatever the method asked.

use crate::constraints::hessian::HessianBlocks;
use crate::constraints::rows::{RowGradient, Velocities};
use crate::constraints::system::System;
use crate::linalg::eigs::{zero_eigenvectors, ConstrainedPencil, EigenError, SparseMatrix, Wanted};
use crate::linalg::kkt::{jacobian_entries, null_space, CoordinateScale, Zeros};
use crate::physics::applied::{AppliedForces, ForceError, Regime};
use crate::physics::mass::{ground_inertia, MasslessSubstitute};
use crate::pipeline::ic::AccelerationError;
use crate::pipeline::{Assembled, NotAssembled};
use crate::stages::statics::{Equilibrium, StaticsError};
use crate::state::State;
use crate::tolerances::UNDERFLOW_FLOOR;
use crate::tolerances::{
    FREE_MOTION, REAL_PAIR, SHIFT_MOVE, SHIFT_OFFSET, SYMMETRIC_STIFFNESS, ZERO_EIGENVALUE,
};
use faer::linalg::solvers::DenseSolveCore;
use faer::Mat;
use linkage_model::Model;

/// Largest number of free motions (DOF) [`EigenMethod::Auto`] solves densely. Measured
/// (`benches/linearization.rs`, pendulum chains): dense 70 ms at 100 DOF, 0.5 s at 200, 1.3 s
/// at 300; shift-invert for the 10 lowest modes 9 ms at 100, 20 ms at 300, 0.23 s at 3000.
pub const DENSE_MAX_DOF: usize = 200;
/// Largest number of coordinates (6 per moving part) [`EigenMethod::Auto`] solves densely: the
/// dense path's null-space QR and projections cost `O(coordinates³)` even for few DOF.
pub const DENSE_MAX_COORDINATES: usize = 1200;
/// Modes the shift-invert path computes when none were asked for.
pub const DEFAULT_MODES: usize = 20;
pub use crate::tolerances::DEFAULT_SHIFT_FRACTION;

/// How the eigenvalues are computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EigenMethod {
    /// Dense for small models, else the [`DEFAULT_MODES`] lowest modes by shift-invert.
    Auto,
    /// Every eigenvalue, densely.
    Dense,
    /// The `modes` modes (a complex pair is one mode) nearest the frequency `shift` (radians
    /// per time unit; `None` or 0: the lowest modes, zero-frequency ones first). The shift is
    /// `σ = −ε + i·shift`, `ε = DEFAULT_SHIFT_FRACTION · ω_ref`.
    ShiftInvert { modes: usize, shift: Option<f64> },
}

/// Options of the eigen solution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearOptions {
    /// Keep damping (Adams NODAMPIN clears it).
    pub damping: bool,
    /// Compute mode shapes (Adams NOVECTOR clears it).
    pub vectors: bool,
    pub method: EigenMethod,
}

/// Magnitude and phase (degrees) of one coordinate of a mode shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Component {
    pub magnitude: f64,
    pub phase_deg: f64,
}

/// Motion of one part in a mode: translation of its centre of mass and rotation (ground axes),
/// normalised so that the largest component of the mode is 1.
#[derive(Clone, Debug, PartialEq)]
pub struct PartShape {
    pub part: usize,
    pub translation: [Component; 3],
    pub rotation: [Component; 3],
}

/// One eigenvalue (a complex pair counted once, with positive imaginary part).
#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    /// Eigenvalue in radians per time unit.
    pub real: f64,
    pub imag: f64,
    /// Undamped natural frequency `|λ|/2π` in cycles per time unit.
    pub frequency: f64,
    /// `−Re λ / |λ|` (0 for a zero eigenvalue).
    pub damping_ratio: f64,
    pub shape: Option<Vec<PartShape>>,
}

/// How a linearization's eigenvalues were computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Solution {
    /// All of them, densely.
    Dense,
    /// Those nearest the frequency `shift` (radians per time unit; 0: the lowest modes) by
    /// shift-invert Arnoldi.
    ShiftInvert {
        shift: f64,
        /// Sparse solves (applications of the shift-invert operator).
        solves: usize,
        /// Every zero eigenvalue is among the computed ones (default shift), so
        /// `zero_eigenvalues` can be compared with `expected_zero_eigenvalues`.
        zeros_complete: bool,
    },
}

/// Result of a linearization.
#[derive(Clone, Debug, PartialEq)]
pub struct Linearization {
    /// Independent motions (the DOF) and states (2 × DOF).
    pub dof: usize,
    pub modes: Vec<Mode>,
    /// Eigenvalues computed (a complex pair counts 2), out of `2 · dof`; on the shift-invert
    /// path including the zero eigenvalues of the deflated free motions of single parts, which
    /// are known without being computed one by one.
    pub computed_eigenvalues: usize,
    /// Eigenvalues at zero (rigid-body modes) found.
    pub zero_eigenvalues: usize,
    /// Zero eigenvalues expected from the free motions that carry no stiffness.
    pub expected_zero_eigenvalues: usize,
    /// Parts given a small artificial mass (zero-mass parts).
    pub massless_parts: usize,
    pub solution: Solution,
}

/// Why a linearization failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LinearizeError {
    /// A force element's Jacobian could not be evaluated.
    #[error(transparent)]
    Force(#[from] ForceError),
    /// The shift-invert eigen solution failed.
    #[error(transparent)]
    Eigen(#[from] EigenError),
    /// `NᵀMN` cannot be inverted (dense path).
    #[error("the reduced mass matrix is singular")]
    SingularReducedMass,
    /// The dense eigen decomposition failed (the solver's message).
    #[error("the eigen solution failed: {0}")]
    DenseEigen(String),
    /// `∂r/∂ẋ` of the control states cannot be inverted (an IMPLICIT DIFF that is an
    /// algebraic equation has no rate of its own).
    #[error(
        "the control states' equations do not determine their rates (∂r/∂ẋ is singular: an \
         IMPLICIT DIFF without DIF1 of its own state is an algebraic equation, which \
         linearization does not reduce)"
    )]
    SingularStateRates,
}

/// The control states' part of the linear equations (module docs), dense and row-major, in
/// the scaled coordinates of [`LinearEquations`].
#[derive(Clone, Debug, PartialEq)]
pub struct ControlEquations {
    /// Number of control states nx.
    pub count: usize,
    /// `∂r/∂q̂`, `∂r/∂v̂` (nx × 6n), `∂r/∂x`, `∂r/∂ẋ` (nx × nx).
    pub rq: Vec<f64>,
    pub rv: Vec<f64>,
    pub rx: Vec<f64>,
    pub rxd: Vec<f64>,
    /// `UCF·s_i·∂Q_i/∂x` and `UCF·s_i·∂Q_i/∂ẋ` (6n × nx).
    pub qx: Vec<f64>,
    pub qxd: Vec<f64>,
}

impl ControlEquations {
    /// The control states' equations of `forces` at `(s, v)`: Jacobians in the scaled
    /// coordinates (`scale` of each of the 6n coordinates).
    fn of(
        forces: &dyn AppliedForces,
        s: &State,
        v: &Velocities,
        ucf: f64,
        scale: impl Fn(usize) -> f64,
    ) -> Result<Option<ControlEquations>, ForceError> {
        let nx = forces.control_count();
        if nx == 0 {
            return Ok(None);
        }
        let n6 = 6 * s.poses.len();
        let mut c = ControlEquations {
            count: nx,
            rq: vec![0.0; nx * n6],
            rv: vec![0.0; nx * n6],
            rx: vec![0.0; nx * nx],
            rxd: vec![0.0; nx * nx],
            qx: vec![0.0; n6 * nx],
            qxd: vec![0.0; n6 * nx],
        };
        let mut t = Vec::new();
        forces.control_jacobian(s, v, &mut t)?;
        for &(i, var, d) in &t {
            match var {
                j if j < n6 => c.rq[i * n6 + j] += d * scale(j),
                j if j < 2 * n6 => c.rv[i * n6 + j - n6] += d * scale(j - n6),
                j if j < 2 * n6 + nx => c.rx[i * nx + j - 2 * n6] += d,
                j => c.rxd[i * nx + j - 2 * n6 - nx] += d,
            }
        }
        t.clear();
        forces.add_control_force_jacobian(Regime::Dynamic, s, v, &mut t)?;
        for &(row, col, d) in &t {
            let x = ucf * scale(row) * d;
            if col < nx {
                c.qx[row * nx + col] += x;
            } else {
                c.qxd[row * nx + col - nx] += x;
            }
        }
        Ok(Some(c))
    }

    /// `(F_q, F_v, F_x)` (dense) and `−(∂r/∂ẋ)⁻¹`.
    fn rates(&self, n6: usize) -> Result<[Mat<f64>; 4], LinearizeError> {
        let nx = self.count;
        let rxd = Mat::<f64>::from_fn(nx, nx, |i, j| self.rxd[i * nx + j]);
        let inv = -rxd.partial_piv_lu().inverse();
        if (0..nx).any(|i| (0..nx).any(|j| !inv[(i, j)].is_finite())) {
            return Err(LinearizeError::SingularStateRates);
        }
        let rq = Mat::<f64>::from_fn(nx, n6, |i, j| self.rq[i * n6 + j]);
        let rv = Mat::<f64>::from_fn(nx, n6, |i, j| self.rv[i * n6 + j]);
        let rx = Mat::<f64>::from_fn(nx, nx, |i, j| self.rx[i * nx + j]);
        Ok([&inv * &rq, &inv * &rv, &inv * &rx, inv])
    }
}

/// The operating point of a linearization: positions, velocities, and the constraint
/// multipliers `(row, value in model force units)` of the kept rows.
#[derive(Clone, Copy, Debug)]
pub struct OperatingPoint<'a> {
    pub state: &'a State,
    pub velocities: &'a Velocities,
    pub multipliers: &'a [(usize, f64)],
}

fn cplx_abs(re: f64, im: f64) -> f64 {
    re.hypot(im)
}

/// The linearised equations at an operating point, as sparse `(row, col, value)` triplets
/// (duplicates are summed, in the order given).
///
/// Coordinates: 6 per part, `6k + c` is `δx_c / L` for `c < 3` (centre-of-mass translation in
/// characteristic lengths `L`) and `δθ_{c−3}` (rotation about ground axes) otherwise; with
/// `s_i` = `L` or 1 accordingly, `M_ij = s_i s_j M̂_ij` (so `M = diag(m L² 1, I_ground)` per
/// part), likewise `C`, `K`, and `J_rj = s_j Ĵ_rj`. Rows of `J` are the kept rows in the order
/// given to [`assemble`].
#[derive(Clone, Debug, PartialEq)]
pub struct LinearEquations {
    /// `6 · parts`.
    pub coordinates: usize,
    pub mass: Vec<(usize, usize, f64)>,
    pub damping: Vec<(usize, usize, f64)>,
    pub stiffness: Vec<(usize, usize, f64)>,
    pub jacobian: Vec<(usize, usize, f64)>,
    /// Rows of `J`.
    pub constraints: usize,
    pub characteristic_length: f64,
    /// Parts given a small artificial mass.
    pub massless_parts: usize,
    /// The control states' equations (`None` without control states).
    pub controls: Option<ControlEquations>,
}

impl LinearEquations {
    /// `s_c`, the model units of one unit of scaled coordinate `c`: the characteristic length
    /// L for translations, 1 for rotations (a scaled translation times this is a length).
    pub fn coordinate_unit(&self, c: usize) -> f64 {
        CoordinateScale::lengths(self.characteristic_length).of(c)
    }

    fn pencil(&self) -> Result<ConstrainedPencil, EigenError> {
        let n = self.coordinates;
        Ok(ConstrainedPencil::new(
            SparseMatrix::from_triplets(n, n, &self.mass)?,
            SparseMatrix::from_triplets(n, n, &self.damping)?,
            SparseMatrix::from_triplets(n, n, &self.stiffness)?,
            SparseMatrix::from_triplets(self.constraints, n, &self.jacobian)?,
        ))
    }
}

/// Assembles M, C (zero without `damping`), K (with the geometric stiffness `Σλ∇²Φ`) and J at
/// the operating point `at` on the independent rows `rows`. Cost `O(parts + rows)`.
pub fn assemble(
    model: &Model,
    sys: &System,
    rows: &[usize],
    forces: &dyn AppliedForces,
    at: OperatingPoint,
    damping: bool,
) -> Result<LinearEquations, ForceError> {
    let OperatingPoint {
        state: s,
        velocities: v,
        multipliers: lambda,
    } = at;
    let l = model.characteristic_length;
    let ucf = model.ucf();
    let scale = CoordinateScale::lengths(l);
    let sc = |c: usize| scale.of(c);

    // Mass matrix (scaled), with Adams' small mass for massless parts.
    let MasslessSubstitute {
        mass: small_mass,
        inertia: small_inertia,
    } = MasslessSubstitute::of(model, l);
    let mut massless_parts = 0;
    let mut m = Vec::with_capacity(12 * model.parts.len());
    for (k, p) in model.parts.iter().enumerate() {
        let mass = if p.mass > 0.0 { p.mass } else { small_mass };
        if p.mass <= 0.0 {
            massless_parts += 1;
        }
        let mut ig = ground_inertia(p, &s.poses[k]);
        if linkage_model::inertia::symmetric_eigenvalues(&ig)[0] <= 0.0 {
            ig += glam::DMat3::IDENTITY * small_inertia;
        }
        for c in 0..3 {
            m.push((6 * k + c, 6 * k + c, mass * l * l));
            for d in 0..3 {
                m.push((6 * k + 3 + c, 6 * k + 3 + d, ig.col(d)[c]));
            }
        }
    }
    crate::physics::flex_inertia::FlexCoupling::new(model)
        .entries(s, |i, j, x| m.push((i, j, x * sc(i) * sc(j))));
    // Stiffness and damping (scaled).
    let mut kmat = Vec::new();
    let mut cmat = Vec::new();
    let mut dq = Vec::new();
    let mut dv = Vec::new();
    forces.add_jacobians(Regime::Dynamic, s, v, &mut dq, Some(&mut dv))?;
    for (i, j, x) in dq {
        kmat.push((i, j, -(ucf * x * sc(i) * sc(j))));
    }
    if damping {
        for (i, j, x) in dv {
            cmat.push((i, j, -(ucf * x * sc(i) * sc(j))));
        }
        // Gyroscopic term of −ω × (I ω): ∂/∂ω = −([ω]× I − [Iω]×).
        for (k, p) in model.parts.iter().enumerate() {
            let w = v[k].1;
            if w == glam::DVec3::ZERO {
                continue;
            }
            let ig = ground_inertia(p, &s.poses[k]);
            let gmat = linkage_model::frames::skew(w) * ig - linkage_model::frames::skew(ig * w);
            for c in 0..3 {
                for d in 0..3 {
                    cmat.push((6 * k + 3 + c, 6 * k + 3 + d, gmat.col(d)[c]));
                }
            }
        }
    }
    let mut hb = HessianBlocks::default();
    let mut trip = Vec::new();
    for &(r, lam) in lambda {
        hb.clear();
        sys.hessian(r, s, 1.0, &mut hb);
        trip.clear();
        hb.triplets(lam * ucf, &mut trip);
        for &(i, j, x) in &trip {
            kmat.push((i, j, x * sc(i) * sc(j)));
        }
    }
    // Constraint Jacobian (scaled columns).
    let mut jac = Vec::new();
    let mut g = RowGradient::default();
    for (k, &r) in rows.iter().enumerate() {
        sys.gradient(r, s, &mut g);
        jacobian_entries(&mut jac, k, &g, scale, Zeros::Keep);
    }
    let controls = ControlEquations::of(forces, s, v, ucf, sc)?;
    Ok(LinearEquations {
        coordinates: 6 * model.parts.len(),
        mass: m,
        damping: cmat,
        stiffness: kmat,
        jacobian: jac,
        constraints: rows.len(),
        characteristic_length: l,
        massless_parts,
        controls,
    })
}

/// Linearises at the operating point `at` on the independent rows `rows`, by the method `opts`
/// chooses.
pub fn linearize(
    model: &Model,
    sys: &System,
    rows: &[usize],
    forces: &dyn AppliedForces,
    at: OperatingPoint,
    opts: LinearOptions,
) -> Result<Linearization, LinearizeError> {
    let eq = assemble(model, sys, rows, forces, at, opts.damping)?;
    let dof = eq.coordinates.saturating_sub(eq.constraints);
    let mut l = match opts.method {
        EigenMethod::Dense => solve_dense(&eq, opts.vectors),
        _ if eq.controls.is_some() => solve_dense(&eq, opts.vectors),
        EigenMethod::Auto if dof <= DENSE_MAX_DOF && eq.coordinates <= DENSE_MAX_COORDINATES => {
            solve_dense(&eq, opts.vectors)
        }
        EigenMethod::Auto => solve_shift_invert(&eq, DEFAULT_MODES, None, opts.vectors),
        EigenMethod::ShiftInvert { modes, shift } => {
            solve_shift_invert(&eq, modes, shift, opts.vectors)
        }
    }?;
    // `modes` asked for is what is listed, whichever solution ran (the solutions may have
    // computed more: every zero eigenvalue, a converged neighbour, the dense spectrum).
    if let EigenMethod::ShiftInvert { modes, shift } = opts.method {
        keep_nearest(&mut l.modes, modes, shift.map_or(0.0, f64::abs));
    }
    Ok(l)
}

/// Keeps the `count` modes nearest the frequency `omega_f` (radians per time unit; 0: the
/// lowest, ties to the more negative real part as [`sort_modes`] orders them), in the order of
/// [`sort_modes`].
fn keep_nearest(modes: &mut Vec<Mode>, count: usize, omega_f: f64) {
    if modes.len() <= count {
        return;
    }
    if omega_f > 0.0 {
        let distance = |m: &Mode| cplx_abs(m.real, m.imag - omega_f);
        modes.sort_by(|a, b| distance(a).total_cmp(&distance(b)));
        modes.truncate(count);
        sort_modes(modes);
    } else {
        sort_modes(modes);
        modes.truncate(count);
    }
}

/// Sums triplets into a dense matrix, in order.
fn dense(rows: usize, cols: usize, entries: &[(usize, usize, f64)]) -> Mat<f64> {
    let mut a = Mat::<f64>::zeros(rows, cols);
    for &(i, j, x) in entries {
        a[(i, j)] += x;
    }
    a
}

/// Part shapes from the complex coordinates of a mode (unscaled: translations in length units),
/// normalised by the largest component.
fn part_shapes(coords: &[(f64, f64)]) -> Vec<PartShape> {
    let biggest = coords
        .iter()
        .map(|(r, i)| r.hypot(*i))
        .fold(0.0, f64::max)
        .max(UNDERFLOW_FLOOR);
    (0..coords.len() / 6)
        .map(|k| {
            let comp = |c: usize| {
                let (r, i) = coords[6 * k + c];
                Component {
                    magnitude: r.hypot(i) / biggest,
                    phase_deg: i.atan2(r).to_degrees(),
                }
            };
            PartShape {
                part: k,
                translation: [comp(0), comp(1), comp(2)],
                rotation: [comp(3), comp(4), comp(5)],
            }
        })
        .collect()
}

fn sort_modes(modes: &mut [Mode]) {
    modes.sort_by(|a, b| {
        a.frequency
            .total_cmp(&b.frequency)
            .then(a.real.total_cmp(&b.real))
    });
}

/// The model's frequency scale `ω_ref = max(√(‖K‖/‖M‖), ‖C‖/‖M‖)` (max-entry norms): zero
/// eigenvalues are judged against it (`|λ| ≤ 1e-6 ω_ref`), not against the other eigenvalues (a
/// one-DOF model has no others).
fn frequency_scale(kn: f64, cn: f64, mn: f64) -> f64 {
    let mn = mn.max(UNDERFLOW_FLOOR);
    (kn / mn).sqrt().max(cn / mn).max(UNDERFLOW_FLOOR)
}

/// Zero eigenvalues expected from the free motions without stiffness: two per free motion,
/// minus one for each independent direction damping acts in (`pc` = the damping matrix
/// projected on those motions).
fn expected_zeros(free: usize, pc: &Mat<f64>) -> usize {
    let p = pc.nrows();
    let cmax = (0..p)
        .flat_map(|i| (0..p).map(move |j| (i, j)))
        .map(|(i, j)| pc[(i, j)].abs())
        .fold(0.0, f64::max);
    let damped = if p == 0 || cmax == 0.0 {
        0
    } else {
        p - null_space(pc).ncols()
    };
    (2 * free).saturating_sub(damped)
}

/// `(A, K_r, C_r, F_x)` of [`first_order`] (`F_x` empty without control states).
type FirstOrder = (Mat<f64>, Mat<f64>, Mat<f64>, Mat<f64>);

/// The first-order form `ẋ = A x` of `M q̈ + C q̇ + K q = G x_c` reduced to the null space `nb`
/// of J (`q = N z`, states `[z; ż; x_c]`):
/// `A = [0, I, 0; −M_r⁻¹K_r, −M_r⁻¹C_r, M_r⁻¹NᵀG; F_q N, F_v N, F_x]` with `M_r = NᵀMN`, …
/// (module docs for the control states' blocks); also returns `K_r`, `C_r` and `F_x`.
fn first_order(
    m: &Mat<f64>,
    kmat: &Mat<f64>,
    cmat: &Mat<f64>,
    nb: &Mat<f64>,
    controls: Option<&ControlEquations>,
) -> Result<FirstOrder, LinearizeError> {
    let f = nb.ncols();
    let n6 = nb.nrows();
    let nx = controls.map_or(0, |c| c.count);
    let mut kmat = kmat.clone();
    let mut cmat = cmat.clone();
    let mut g = Mat::<f64>::zeros(n6, nx);
    let mut rates = None;
    if let Some(c) = controls {
        let [fq, fv, fx, _] = c.rates(n6)?;
        let qx = Mat::<f64>::from_fn(n6, nx, |i, j| c.qx[i * nx + j]);
        let qxd = Mat::<f64>::from_fn(n6, nx, |i, j| c.qxd[i * nx + j]);
        // M q̈ = F̂ − C q̇ − K q: the forces' dependence on the rates through F_q, F_v.
        kmat -= &qxd * &fq;
        cmat -= &qxd * &fv;
        g = &qx + &qxd * &fx;
        rates = Some((&fq * nb, &fv * nb, fx));
    }
    let mr = nb.transpose() * m * nb;
    let kr = nb.transpose() * &kmat * nb;
    let cr = nb.transpose() * &cmat * nb;
    let lu = mr.partial_piv_lu();
    let minv = lu.inverse();
    let mk = &minv * &kr;
    let mc = &minv * &cr;
    let mg = &minv * nb.transpose() * &g;
    let dim = 2 * f + nx;
    let mut a = Mat::<f64>::zeros(dim, dim);
    for i in 0..f {
        a[(i, f + i)] = 1.0;
        for j in 0..f {
            a[(f + i, j)] = -mk[(i, j)];
            a[(f + i, f + j)] = -mc[(i, j)];
        }
        for j in 0..nx {
            a[(f + i, 2 * f + j)] = mg[(i, j)];
        }
    }
    let mut fx_out = Mat::<f64>::zeros(nx, nx);
    if let Some((fqn, fvn, fx)) = rates {
        for i in 0..nx {
            for j in 0..f {
                a[(2 * f + i, j)] = fqn[(i, j)];
                a[(2 * f + i, f + j)] = fvn[(i, j)];
            }
            for j in 0..nx {
                a[(2 * f + i, 2 * f + j)] = fx[(i, j)];
            }
        }
        fx_out = fx;
    }
    if (0..dim).any(|i| (0..dim).any(|j| !a[(i, j)].is_finite())) {
        return Err(LinearizeError::SingularReducedMass);
    }
    Ok((a, kr, cr, fx_out))
}

/// The state matrix of a linearization: `ẋ = A x` with the states `x = [z; ż; x_c]`, where
/// the `f` independent coordinates `z` move the parts by `q = N z` (N: an orthonormal basis of
/// the null space of the constraint Jacobian at the operating point; `q` the 6 coordinates
/// per part of [`LinearEquations`], translations in characteristic lengths L), and `x_c` are
/// the control states (DIFF, LSE, TFSISO, in the model's order).
#[derive(Clone, Debug, PartialEq)]
pub struct StateMatrix {
    /// `(2f + nx) × (2f + nx)`, row-major.
    pub a: Vec<f64>,
    /// `f`.
    pub coordinates: usize,
    /// `nx`, the control states.
    pub controls: usize,
    /// `−(∂r/∂ẋ)⁻¹` (nx × nx, row-major): the control rates a change `δr` of their equations'
    /// residuals gives.
    pub rate_map: Vec<f64>,
    /// `N` (`6·parts × f`, row-major), with translation rows in model length units (times L).
    pub basis: Vec<f64>,
    /// `M_r⁻¹ Nᵀ` (`f × 6·parts`, row-major): the accelerations `z̈` a generalised force
    /// `F̂` (in the scaled coordinates of [`LinearEquations`]) gives.
    pub force_map: Vec<f64>,
}

/// M, K, C of the linear equations as dense matrices, and an orthonormal basis of the null
/// space of J.
struct DenseEquations {
    m: Mat<f64>,
    k: Mat<f64>,
    c: Mat<f64>,
    nb: Mat<f64>,
}

impl DenseEquations {
    fn of(eq: &LinearEquations) -> DenseEquations {
        let dim = eq.coordinates;
        DenseEquations {
            m: dense(dim, dim, &eq.mass),
            k: dense(dim, dim, &eq.stiffness),
            c: dense(dim, dim, &eq.damping),
            nb: null_space(&dense(eq.constraints, dim, &eq.jacobian)),
        }
    }
}

/// [`StateMatrix`] of the linear equations `eq` (dense).
pub fn state_matrix(eq: &LinearEquations) -> Result<StateMatrix, LinearizeError> {
    let dim = eq.coordinates;
    let DenseEquations {
        m,
        k: kmat,
        c: cmat,
        nb,
    } = DenseEquations::of(eq);
    let f = nb.ncols();
    let (a, _, _, _) = first_order(&m, &kmat, &cmat, &nb, eq.controls.as_ref())?;
    let states = a.nrows();
    let mr = nb.transpose() * &m * &nb;
    let map = mr.partial_piv_lu().inverse() * nb.transpose();
    let (controls, rate_map) = match &eq.controls {
        Some(c) => {
            let [_, _, _, inv] = c.rates(dim)?;
            let nx = c.count;
            let flat = (0..nx * nx).map(|k| inv[(k / nx, k % nx)]).collect();
            (nx, flat)
        }
        None => (0, Vec::new()),
    };
    Ok(StateMatrix {
        controls,
        rate_map,
        force_map: (0..f)
            .flat_map(|i| (0..dim).map(move |j| (i, j)))
            .map(|(i, j)| map[(i, j)])
            .collect(),
        a: (0..states)
            .flat_map(|i| (0..states).map(move |j| (i, j)))
            .map(|(i, j)| a[(i, j)])
            .collect(),
        coordinates: f,
        basis: (0..dim)
            .flat_map(|i| (0..f).map(move |j| (i, j)))
            .map(|(i, j)| nb[(i, j)] * eq.coordinate_unit(i))
            .collect(),
    })
}

/// The dense solution: every eigenvalue of the problem reduced to the null space of J.
fn solve_dense(eq: &LinearEquations, vectors: bool) -> Result<Linearization, LinearizeError> {
    let dim = eq.coordinates;
    let DenseEquations {
        m,
        k: kmat,
        c: cmat,
        nb,
    } = DenseEquations::of(eq);
    let f = nb.ncols();
    if f == 0 && eq.controls.is_none() {
        return Ok(Linearization {
            dof: 0,
            modes: Vec::new(),
            computed_eigenvalues: 0,
            zero_eigenvalues: 0,
            expected_zero_eigenvalues: 0,
            massless_parts: eq.massless_parts,
            solution: Solution::Dense,
        });
    }
    let (a, kr, cr, fx) = first_order(&m, &kmat, &cmat, &nb, eq.controls.as_ref())?;
    let states = a.nrows();
    let eig = a
        .eigen()
        .map_err(|e| LinearizeError::DenseEigen(format!("{e:?}")))?;
    let vals = eig.S();
    let vecs = eig.U();
    let lmax = (0..states)
        .map(|i| cplx_abs(vals[i].re, vals[i].im))
        .fold(0.0, f64::max);
    let norm_max = |x: &Mat<f64>| {
        (0..dim)
            .flat_map(|i| (0..dim).map(move |j| (i, j)))
            .map(|(i, j)| x[(i, j)].abs())
            .fold(0.0, f64::max)
    };
    let (kn, cn, mn) = (norm_max(&kmat), norm_max(&cmat), norm_max(&m));
    let zero_tol = ZERO_EIGENVALUE * frequency_scale(kn, cn, mn);
    let zero_eigenvalues = (0..states)
        .filter(|&i| cplx_abs(vals[i].re, vals[i].im) <= zero_tol)
        .count();
    // Free motions without stiffness: the null space of the symmetric part of K_r.
    let ksym = Mat::<f64>::from_fn(f, f, |i, j| 0.5 * (kr[(i, j)] + kr[(j, i)]));
    let kmax = (0..f)
        .flat_map(|i| (0..f).map(move |j| (i, j)))
        .map(|(i, j)| ksym[(i, j)].abs())
        .fold(0.0, f64::max);
    let expected_zero_eigenvalues = match ksym.self_adjoint_eigen(faer::Side::Lower) {
        Ok(e) => {
            let s_vals = e.S();
            let u = e.U();
            let free: Vec<usize> = (0..f)
                .filter(|&i| s_vals[i].abs() <= FREE_MOTION * kmax.max(kn).max(UNDERFLOW_FLOOR))
                .collect();
            let p = Mat::<f64>::from_fn(f, free.len(), |i, j| u[(i, free[j])]);
            let pc = p.transpose() * &cr * &p;
            expected_zeros(free.len(), &pc)
        }
        Err(_) => zero_eigenvalues,
    };
    // Control states without a restoring law of their own (integrators) add theirs.
    let expected_zero_eigenvalues = expected_zero_eigenvalues
        + match fx.nrows() {
            0 => 0,
            _ => fx.eigen().map_or(0, |e| {
                let v = e.S();
                (0..fx.nrows())
                    .filter(|&i| cplx_abs(v[i].re, v[i].im) <= zero_tol)
                    .count()
            }),
        };
    let mut modes = Vec::new();
    for i in 0..states {
        let (re, im) = (vals[i].re, vals[i].im);
        if im < -REAL_PAIR * lmax.max(1.0) {
            continue;
        }
        let shape = vectors.then(|| {
            // Positions: top half of the eigenvector, mapped back to part coordinates.
            let mut coords = vec![(0.0f64, 0.0f64); dim];
            for (row, c) in coords.iter_mut().enumerate() {
                let (mut sr, mut si) = (0.0, 0.0);
                for j in 0..f {
                    let z = vecs[(j, i)];
                    sr += nb[(row, j)] * z.re;
                    si += nb[(row, j)] * z.im;
                }
                *c = (sr * eq.coordinate_unit(row), si * eq.coordinate_unit(row));
            }
            part_shapes(&coords)
        });
        modes.push(mode(re, im, shape));
    }
    sort_modes(&mut modes);
    Ok(Linearization {
        dof: f,
        modes,
        computed_eigenvalues: states,
        zero_eigenvalues,
        expected_zero_eigenvalues,
        massless_parts: eq.massless_parts,
        solution: Solution::Dense,
    })
}

/// Complex coordinates of a mode shape in model units (translations times `L`), conjugated
/// with `conj`.
fn shape_coords(eq: &LinearEquations, x_re: &[f64], x_im: &[f64], conj: bool) -> Vec<(f64, f64)> {
    let sign = if conj { -1.0 } else { 1.0 };
    (0..eq.coordinates)
        .map(|i| {
            (
                x_re[i] * eq.coordinate_unit(i),
                sign * x_im[i] * eq.coordinate_unit(i),
            )
        })
        .collect()
}

fn mode(re: f64, im: f64, shape: Option<Vec<PartShape>>) -> Mode {
    let mag = cplx_abs(re, im);
    Mode {
        real: re,
        imag: im.max(0.0),
        frequency: mag / std::f64::consts::TAU,
        // `+ 0.0` turns the −0 of an undamped mode into 0.
        damping_ratio: if mag > 0.0 { -re / mag + 0.0 } else { 0.0 },
        shape,
    }
}

/// Principal square root of a complex number.
fn csqrt(re: f64, im: f64) -> (f64, f64) {
    let r = cplx_abs(re, im);
    let a = (0.5 * (r + re)).max(0.0).sqrt();
    let b = (0.5 * (r - re)).max(0.0).sqrt();
    (a, if im < 0.0 { -b } else { b })
}

/// What one shift-invert solution looks for, and the model's scales.
#[derive(Clone, Copy, Debug)]
struct Search {
    /// Modes wanted.
    modes: usize,
    /// The frequency scale `ω_ref` (1 when the model has none).
    omega: f64,
    /// The frequency searched around (0: the lowest modes).
    omega_f: f64,
    /// `|λ|` at or below this is a zero eigenvalue.
    zero_tol: f64,
    /// `|ν|` at or below this is a free motion without stiffness.
    free_tol: f64,
    /// Compute mode shapes.
    vectors: bool,
}

/// Modes, eigenvalue counts and solves of one shift-invert solution.
struct SparseModes {
    modes: Vec<Mode>,
    computed: usize,
    zeros: usize,
    solves: usize,
    /// Free motions without stiffness, when the main solution already found them.
    free: Option<(usize, Vec<Vec<f64>>)>,
}

/// Without damping (`C = 0`): the constrained problem `K x + Jᵀμ = ν M x` with `ν = −λ²`,
/// shifted at `τ = −ε²` (lowest modes) or `τ = ω_F²` (around `ω_F`). Each real `ν ≥ 0` is the
/// mode `λ = ±i√ν`, each `ν < 0` the two real modes `±√(−ν)`, each complex pair `(ν, ν̄)` the
/// four eigenvalues `±√(−ν)`, `±√(−ν̄)` (two modes with `Im λ ≥ 0`).
fn undamped_modes(
    eq: &LinearEquations,
    pencil: &ConstrainedPencil,
    search: Search,
) -> Result<SparseModes, EigenError> {
    let Search {
        modes,
        omega,
        omega_f,
        zero_tol,
        free_tol,
        vectors,
    } = search;
    let lowest = omega_f == 0.0;
    let eps = DEFAULT_SHIFT_FRACTION * omega;
    // Around a frequency, 0.1 % below it: a shift on an eigenvalue makes the KKT matrix
    // singular, and one near it makes its θ dwarf the others'.
    let mut tau = if lowest {
        -eps * eps
    } else {
        (omega_f * (1.0 - SHIFT_OFFSET)).powi(2)
    };
    // With the lowest modes, every ν in the zero window |ν| ≤ max(zero_tol², free_tol) too.
    let window = (zero_tol * zero_tol).max(free_tol);
    let mut tries = 0;
    let found = loop {
        let wanted = Wanted {
            count: modes.max(1),
            beyond: lowest.then(|| 1.0 / (tau.abs() + window)),
        };
        match pencil.nearest_linear(tau, wanted, false) {
            Ok(r) => break r,
            // The shift hit an eigenvalue: move it.
            Err(EigenError::Shift(_)) if tries < 3 => {
                tau -= 3.7 * tau.abs().max(eps * eps) * SHIFT_MOVE * (1 + tries) as f64;
                tries += 1;
            }
            Err(e) => return Err(e),
        }
    };
    let mut out = Vec::new();
    let (mut computed, mut zeros) = (0, 0);
    for p in &found.pairs {
        let (nr, ni) = p.nu;
        let shape =
            |conj: bool| vectors.then(|| part_shapes(&shape_coords(eq, &p.x_re, &p.x_im, conj)));
        if p.multiplicity == 1 {
            computed += 2;
            if nr.abs().sqrt() <= zero_tol {
                zeros += 2;
            }
            if nr >= 0.0 {
                out.push(mode(0.0, nr.sqrt(), shape(false)));
            } else {
                let a = (-nr).sqrt();
                out.push(mode(a, 0.0, shape(false)));
                out.push(mode(-a, 0.0, shape(false)));
            }
        } else {
            computed += 4;
            let (a, b) = csqrt(-nr, -ni);
            if cplx_abs(a, b) <= zero_tol {
                zeros += 4;
            }
            // λ = ±(a + ib) with x, ±(a − ib) with x̄: the two with Im λ ≥ 0.
            let conj = b < 0.0;
            out.push(mode(a, b.abs(), shape(conj)));
            out.push(mode(-a, b.abs(), shape(!conj)));
        }
    }
    // K symmetric: the free motions are the ν = 0 vectors found (all of them, with `window`).
    let n = eq.coordinates;
    let asym: Vec<(usize, usize, f64)> = pencil
        .stiffness
        .entries()
        .flat_map(|(i, j, v)| [(i, j, v), (j, i, -v)])
        .collect();
    let symmetric = SparseMatrix::from_triplets(n, n, &asym)
        .is_ok_and(|d| d.max_abs() <= SYMMETRIC_STIFFNESS * pencil.stiffness.max_abs());
    let free = (lowest && symmetric).then(|| zero_eigenvectors(&found.pairs, free_tol));
    Ok(SparseModes {
        modes: out,
        computed,
        zeros,
        solves: found.applications,
        free,
    })
}

/// With damping: the first-order problem shifted at `σ = −ε + iω_F`, in the balanced state
/// `(a·x, v)` with `a = ω_F` (around a frequency) or `a = √(ε ω_ref)` (lowest modes: between the
/// shift, where undamped free motions make Jordan blocks, and the model's frequencies).
fn damped_modes(
    eq: &LinearEquations,
    pencil: &ConstrainedPencil,
    search: Search,
) -> Result<SparseModes, EigenError> {
    let Search {
        modes,
        omega,
        omega_f,
        zero_tol,
        vectors,
        ..
    } = search;
    let lowest = omega_f == 0.0;
    let eps = DEFAULT_SHIFT_FRACTION * omega;
    let mut sigma_re = -eps;
    let scale = if lowest {
        (eps * omega).sqrt()
    } else {
        omega_f
    };
    let mut tries = 0;
    let found = loop {
        let wanted = Wanted {
            count: modes.max(1),
            // With the lowest modes, every zero eigenvalue too (|λ − σ| ≤ |σ| + zero_tol).
            beyond: lowest.then(|| 1.0 / (sigma_re.abs() + zero_tol)),
        };
        match pencil.nearest((sigma_re, omega_f), scale, wanted) {
            Ok(r) => break r,
            // The shift hit an eigenvalue: move it.
            Err(EigenError::Shift(_)) if tries < 3 => {
                sigma_re *= 3.7;
                tries += 1;
            }
            Err(e) => return Err(e),
        }
    };
    let lmax = found
        .pairs
        .iter()
        .map(|p| cplx_abs(p.lambda.0, p.lambda.1))
        .fold(0.0, f64::max);
    let mut out = Vec::new();
    let mut zeros = 0;
    for p in &found.pairs {
        let (re, im) = p.lambda;
        let count = if im == 0.0 { 1 } else { 2 };
        if cplx_abs(re, im) <= zero_tol {
            zeros += count;
        }
        let shape =
            |conj: bool| vectors.then(|| part_shapes(&shape_coords(eq, &p.x_re, &p.x_im, conj)));
        // As in the dense path, a pair whose imaginary part is round-off is two real modes.
        if count == 2 && im <= REAL_PAIR * lmax.max(1.0) {
            out.push(mode(re, 0.0, shape(true)));
        }
        out.push(mode(re, im, shape(false)));
    }
    Ok(SparseModes {
        modes: out,
        computed: found.eigenvalues,
        zeros,
        solves: found.applications,
        free: None,
    })
}

/// The shift-invert solution: the `modes` modes nearest the frequency `shift` (default: the
/// lowest, from just below zero, and then every zero eigenvalue as well), without damping on
/// the `n`-dimensional problem in `ν = −λ²`, with damping on the first-order one; and the
/// count of free motions without stiffness from the constrained symmetric problem
/// `K_s x + Jᵀμ = ν M x` near `ν = 0` (unless the undamped solution found them already).
fn solve_shift_invert(
    eq: &LinearEquations,
    modes: usize,
    shift: Option<f64>,
    vectors: bool,
) -> Result<Linearization, LinearizeError> {
    let pencil = eq.pencil()?;
    let f = pencil.free_motions();
    let (kn, cn, mn) = (
        pencil.stiffness.max_abs(),
        pencil.damping.max_abs(),
        pencil.mass.max_abs(),
    );
    let omega_ref = frequency_scale(kn, cn, mn);
    // Without stiffness or damping every eigenvalue is zero; any scale will do.
    let omega = if omega_ref > UNDERFLOW_FLOOR {
        omega_ref
    } else {
        1.0
    };
    let zero_tol = ZERO_EIGENVALUE * omega;
    let omega2 = omega * omega;
    // Free motions: |ν| ≤ FREE_MOTION ω_ref² (the dense path: FREE_MOTION ‖K‖ on K_r's
    // eigenvalues).
    let free_tol = FREE_MOTION * omega2;
    let omega_f = shift.map_or(0.0, f64::abs);
    let lowest = omega_f == 0.0;
    if f == 0 {
        return Ok(Linearization {
            dof: 0,
            modes: Vec::new(),
            computed_eigenvalues: 0,
            zero_eigenvalues: 0,
            expected_zero_eigenvalues: 0,
            massless_parts: eq.massless_parts,
            solution: Solution::ShiftInvert {
                shift: omega_f,
                solves: 0,
                zeros_complete: true,
            },
        });
    }
    let search = Search {
        modes,
        omega,
        omega_f,
        zero_tol,
        free_tol,
        vectors,
    };
    let mut sm = if cn == 0.0 {
        undamped_modes(eq, &pencil, search)?
    } else {
        damped_modes(eq, &pencil, search)?
    };
    sort_modes(&mut sm.modes);
    // The free motions of single parts were deflated: each is two zero eigenvalues, known
    // without being computed one by one.
    let local = pencil.local_free_motions();
    sm.computed += 2 * local;
    sm.zeros += 2 * local;
    let mut solves = sm.solves;
    let free = match sm.free.take() {
        Some(found) => Ok(found),
        None => pencil
            .stiffness_null_space(-DEFAULT_SHIFT_FRACTION * omega2, free_tol)
            .map(|(free, basis, applications)| {
                solves += applications;
                (free, basis)
            }),
    };
    let expected_zero_eigenvalues = match free {
        Ok((free, basis)) => {
            let cp: Vec<Vec<f64>> = basis
                .iter()
                .map(|b| {
                    let mut y = vec![0.0; b.len()];
                    pencil.damping.mul_add(1.0, b, &mut y);
                    y
                })
                .collect();
            let pc = Mat::<f64>::from_fn(basis.len(), basis.len(), |i, j| {
                basis[i].iter().zip(&cp[j]).map(|(a, b)| a * b).sum()
            });
            expected_zeros(free + local, &pc)
        }
        Err(_) => sm.zeros,
    };
    Ok(Linearization {
        dof: f,
        modes: sm.modes,
        computed_eigenvalues: sm.computed,
        zero_eigenvalues: sm.zeros,
        expected_zero_eigenvalues,
        massless_parts: eq.massless_parts,
        solution: Solution::ShiftInvert {
            shift: omega_f,
            solves,
            zeros_complete: lowest,
        },
    })
}

/// Why a linear analysis has no result.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LinearRunError {
    /// The model could not be assembled.
    #[error("{0}; no operating point")]
    NotAssembled(NotAssembled),
    /// The initial conditions left no operating point (no velocities or forces were solved).
    #[error("the model could not be assembled; no operating point")]
    NoOperatingPoint,
    /// `--static-first`: the Newton iteration did not converge.
    #[error("static equilibrium did not converge; no operating point")]
    EquilibriumNotConverged,
    /// `--static-first`: the equilibrium could not be computed.
    #[error(transparent)]
    Statics(#[from] StaticsError),
    /// The acceleration/force IC (the multipliers of the operating point) failed.
    #[error(transparent)]
    Acceleration(#[from] AccelerationError),
    /// The linearization or its eigen solution failed.
    #[error(transparent)]
    Linearize(#[from] LinearizeError),
}

/// A linear analysis of an assembled model: optionally static equilibrium, then the eigen
/// solution about that operating point.
#[derive(Clone, Debug)]
pub struct LinearRun {
    /// The static equilibrium used as operating point (with `--static-first`).
    pub equilibrium: Option<Result<Equilibrium, StaticsError>>,
    pub result: Result<Linearization, LinearRunError>,
}

/// Linearizes an assembled model about its operating point: with `static_first`, static
/// equilibrium at the start time (at rest, with its multipliers); otherwise the assembled
/// configuration with the IC velocities and the constraint forces of the acceleration/force IC.
pub fn run(a: &Assembled, static_first: bool, opts: LinearOptions) -> LinearRun {
    let model = a.model;
    if let Some(why) = a.failure() {
        return LinearRun {
            equilibrium: None,
            result: Err(LinearRunError::NotAssembled(why.clone())),
        };
    }
    let about = |at: OperatingPoint| {
        linearize(model, &a.system, &a.kept, a.forces, at, opts).map_err(LinearRunError::from)
    };
    if static_first {
        let eq = crate::stages::statics::run(a, &[0.0])
            .steps
            .into_iter()
            .next()
            .map(|(_, e)| e);
        let rest = a.rest();
        let result = match &eq {
            Some(Ok(e)) if e.converged => about(OperatingPoint {
                state: &e.state,
                velocities: &rest,
                multipliers: &e.multipliers,
            }),
            Some(Ok(_)) => Err(LinearRunError::EquilibriumNotConverged),
            Some(Err(e)) => Err(e.clone().into()),
            None => Err(LinearRunError::NoOperatingPoint),
        };
        return LinearRun {
            equilibrium: eq,
            result,
        };
    }
    let result = match (&a.ic.velocity, &a.ic.acceleration) {
        (Some(v), Some(Ok(acc))) => about(OperatingPoint {
            state: a.state(),
            velocities: &v.velocities,
            multipliers: &acc.multipliers,
        }),
        (_, Some(Err(e))) => Err(e.clone().into()),
        _ => Err(LinearRunError::NoOperatingPoint),
    };
    LinearRun {
        equilibrium: None,
        result,
    }
}
