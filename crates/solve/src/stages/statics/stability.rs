//! The stiffness of an equilibrium along the free motions: the tangent stiffness reduced to the
//! null space of the constraint Jacobian, its lowest eigenvalue (the stability verdict) and its
//! lowest modes against the mass (the descent's shift, the settling's damping).
//!
//! Coordinates are scaled so that translations are measured in characteristic lengths `L`
//! (`ξ = δx/L`, rotations in radians): stiffness entries in force × length, mass entries in
//! mass × length². With `N` an orthonormal basis of the null space of `J` (scaled):
//!
//! ```text
//! K_r = Nᵀ K_T N,   M_r = Nᵀ M N,   K_r y = μ M_r y   (μ = ω², 1/time², negative: unstable)
//! ```

use crate::constraints::hessian::HessianBlocks;
use crate::constraints::rows::RowGradient;
use crate::constraints::system::System;
use crate::physics::applied::{AppliedForces, Regime};
use crate::physics::mass::ground_inertia;
use crate::state::State;
use crate::tolerances::{STABILITY_EIGENVALUE, STABILITY_RANK};
use faer::Mat;
use glam::DVec3;
use linkage_model::Model;

/// Largest dense reduced problem for which stability is evaluated.
pub const MAX_DENSE_DOF_COLUMNS: usize = 1800;

/// The tangent stiffness at a configuration, reduced to the free motions (scaled coordinates).
struct Reduced {
    /// Orthonormal basis of the free motions (6n × free).
    basis: Mat<f64>,
    /// `K_T` (6n × 6n, scaled).
    kt: Mat<f64>,
    /// `½(K_r + K_rᵀ)` (free × free).
    k: Mat<f64>,
}

/// The reduced stiffness at `s` with multipliers `lambda` on the rows `used` (`None`: no free
/// motion, too large for the dense solve, or a force Jacobian that cannot be evaluated).
fn reduced(
    model: &Model,
    sys: &System,
    used: &[(usize, f64)],
    lambda: &[f64],
    forces: &dyn AppliedForces,
    s: &State,
    max_dim: usize,
) -> Option<Reduced> {
    let n = model.parts.len();
    let dim = 6 * n;
    if dim > max_dim || dim == 0 {
        return None;
    }
    let l = model.characteristic_length;
    let scale = |c: usize| if c % 6 < 3 { l } else { 1.0 };
    // J (scaled columns), dense.
    let m = used.len();
    let mut jt = Mat::<f64>::zeros(dim, m.max(1));
    let mut g = RowGradient::default();
    for (k, (r, _)) in used.iter().enumerate() {
        sys.gradient(*r, s, &mut g);
        for (body, b) in &g.blocks {
            for c in 0..6 {
                jt[(6 * body + c, k)] = b[c] * scale(c);
            }
        }
    }
    // Null space of J: the trailing columns of Q in Jᵀ = Q R (full QR), rank by |R_ii|.
    let qr = jt.qr();
    let q = qr.compute_Q();
    let r = qr.R();
    let rmax = (0..r.nrows().min(r.ncols()))
        .map(|i| r[(i, i)].abs())
        .fold(0.0, f64::max);
    let rank = (0..r.nrows().min(r.ncols()))
        .filter(|&i| r[(i, i)].abs() > STABILITY_RANK * rmax.max(f64::MIN_POSITIVE))
        .count();
    let rank = if m == 0 { 0 } else { rank };
    let free = dim - rank;
    if free == 0 {
        return None;
    }
    // K_T (scaled), dense.
    let mut kt = Mat::<f64>::zeros(dim, dim);
    let mut dq = Vec::new();
    let rest = vec![(DVec3::ZERO, DVec3::ZERO); n];
    forces
        .add_jacobians(Regime::Static, s, &rest, &mut dq, None)
        .ok()?;
    for (i, j, v) in dq {
        kt[(i, j)] -= v * scale(i) * scale(j);
    }
    let mut hb = HessianBlocks::default();
    let mut trip = Vec::new();
    for (k, (r, _)) in used.iter().enumerate() {
        hb.clear();
        sys.hessian(*r, s, 1.0, &mut hb);
        trip.clear();
        hb.triplets(lambda[k], &mut trip);
        for &(i, j, v) in &trip {
            kt[(i, j)] += v * scale(i) * scale(j);
        }
    }
    let basis = q.subcols(rank, free).to_owned();
    let red = basis.transpose() * &kt * &basis;
    let k = Mat::<f64>::from_fn(free, free, |i, j| 0.5 * (red[(i, j)] + red[(j, i)]));
    Some(Reduced { basis, kt, k })
}

/// Smallest eigenvalue of the stiffness reduced to the free motions, coordinates scaled so
/// that translations are measured in characteristic lengths (entries in force × length), and
/// whether it is stable (not below rounding of the model's stiffness).
pub(super) fn reduced_stability(
    model: &Model,
    sys: &System,
    used: &[(usize, f64)],
    lambda: &[f64],
    forces: &dyn AppliedForces,
    s: &State,
) -> Option<(bool, f64)> {
    let r = reduced(model, sys, used, lambda, forces, s, MAX_DENSE_DOF_COLUMNS)?;
    let eig = r.k.self_adjoint_eigenvalues(faer::Side::Lower).ok()?;
    let min = eig.iter().copied().fold(f64::INFINITY, f64::min);
    // Rounding is judged against the stiffness of the whole model, not only of the free
    // motions: a model whose free motions carry no stiffness at all (a door on a vertical
    // hinge) has reduced eigenvalues of rounding size only, of either sign.
    let max = eig.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let dim = r.kt.nrows();
    let k_max = (0..dim)
        .flat_map(|i| (0..dim).map(move |j| (i, j)))
        .map(|(i, j)| r.kt[(i, j)].abs())
        .fold(0.0, f64::max);
    Some((
        min > -STABILITY_EIGENVALUE * max.max(k_max).max(f64::MIN_POSITIVE),
        min,
    ))
}

/// The modes of the free motions against the mass at a configuration.
#[derive(Clone, Debug)]
pub struct Modes {
    /// `μ = ω²` of every free motion, ascending (1/time²; negative along an unstable motion,
    /// about zero along a motion without stiffness).
    pub squared_frequencies: Vec<f64>,
    /// The lowest mode as a motion of every part `(δx, δθ)`, scaled so that its largest
    /// component is 1 (translations over the characteristic length, rotations in radians).
    pub lowest: Vec<(DVec3, DVec3)>,
    /// Every mode's shape in scaled part coordinates, mass-normalised (`Φᵀ M Φ = I`,
    /// `Φᵀ K_T Φ = diag(μ)`), in the order of `squared_frequencies` (6n × free).
    pub(super) shapes: Mat<f64>,
}

impl Modes {
    /// The lowest `μ` (negative: the configuration is unstable along [`Modes::lowest`]).
    pub fn lowest_squared_frequency(&self) -> f64 {
        self.squared_frequencies.first().copied().unwrap_or(0.0)
    }

    /// The lowest angular frequency `√|μ|` among the modes whose `|μ|` is above `floor`
    /// (a mode without stiffness neither needs damping nor sets a settling time).
    pub fn lowest_frequency_above(&self, floor: f64) -> Option<f64> {
        self.squared_frequencies
            .iter()
            .map(|m| m.abs())
            .filter(|m| *m > floor)
            .fold(None, |lo: Option<f64>, m| Some(lo.map_or(m, |l| l.min(m))))
            .map(f64::sqrt)
    }
}

/// The modes of `K_r y = μ M_r y` at `s` (module docs), the mass in the model's force units
/// (`m/UCF`), up to `max_dim` coordinates (`None`: larger, no free motion, a massless free
/// motion, no mass at all, or a force Jacobian that cannot be evaluated).
pub fn modes(
    model: &Model,
    sys: &System,
    used: &[(usize, f64)],
    lambda: &[f64],
    forces: &dyn AppliedForces,
    s: &State,
    max_dim: usize,
) -> Option<Modes> {
    let r = reduced(model, sys, used, lambda, forces, s, max_dim)?;
    let l = model.characteristic_length;
    let ucf = model.ucf();
    let dim = r.kt.nrows();
    let mut m = Mat::<f64>::zeros(dim, dim);
    for (k, part) in model.parts.iter().enumerate() {
        let ig = ground_inertia(part, &s.poses[k]);
        for c in 0..3 {
            m[(6 * k + c, 6 * k + c)] = part.mass * l * l / ucf;
            for d in 0..3 {
                m[(6 * k + 3 + c, 6 * k + 3 + d)] = ig.col(d)[c] / ucf;
            }
        }
    }
    let mr = r.basis.transpose() * &m * &r.basis;
    let free = mr.nrows();
    let mr = Mat::<f64>::from_fn(free, free, |i, j| 0.5 * (mr[(i, j)] + mr[(j, i)]));
    let me = mr.self_adjoint_eigen(faer::Side::Lower).ok()?;
    let (sm, um) = (me.S(), me.U());
    let smax = (0..free).map(|i| sm[i]).fold(0.0, f64::max);
    if smax <= 0.0 {
        return None;
    }
    // W = U S^-1/2: Wᵀ M_r W = I, and Wᵀ K_r W has the eigenvalues μ. A free motion without
    // inertia (a slender rod spinning about its axis) gets a floor of mass: its μ is then
    // large when it has stiffness, zero when not.
    let floor = STABILITY_RANK * smax;
    let w = Mat::<f64>::from_fn(free, free, |i, j| um[(i, j)] / sm[j].max(floor).sqrt());
    let a = w.transpose() * &r.k * &w;
    let a = Mat::<f64>::from_fn(free, free, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let ae = a.self_adjoint_eigen(faer::Side::Lower).ok()?;
    let (sa, ua) = (ae.S(), ae.U());
    let mut order: Vec<usize> = (0..free).collect();
    order.sort_by(|&i, &j| sa[i].total_cmp(&sa[j]));
    let squared_frequencies: Vec<f64> = order.iter().map(|&i| sa[i]).collect();
    let shapes_unordered = &r.basis * &w * ua;
    let shapes = Mat::<f64>::from_fn(dim, free, |i, j| shapes_unordered[(i, order[j])]);
    let xi = shapes.col(0);
    let largest = (0..dim).map(|i| xi[i].abs()).fold(0.0, f64::max);
    if largest == 0.0 || !largest.is_finite() {
        return None;
    }
    let lowest = (0..model.parts.len())
        .map(|k| {
            let c = |i: usize| xi[6 * k + i] / largest;
            (DVec3::new(c(0), c(1), c(2)), DVec3::new(c(3), c(4), c(5)))
        })
        .collect();
    Some(Modes {
        squared_frequencies,
        lowest,
        shapes,
    })
}
