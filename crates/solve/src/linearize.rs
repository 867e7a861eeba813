//! Linearization about an operating point (DESIGN §7, ADM-REFERENCE §8.6): eigenvalues,
//! undamped natural frequencies, damping ratios and mode shapes.
//!
//! Equations of motion `M q̈ = UCF·(Q(q, v) − Jᵀλ)` with `J δq = 0` are linearised exactly:
//!
//! ```text
//! M δq̈ + C δq̇ + K δq = 0,   K = UCF·(−∂Q/∂q + Σ λ_r ∂²Φ_r/∂q²),   C = −UCF·∂Q/∂v + G(ω)
//! ```
//!
//! (G the gyroscopic term, zero at rest), then reduced to the free motions with an orthonormal
//! basis N of the null space of J (dense QR of Jᵀ, coordinates scaled so that translations are
//! in characteristic lengths): `M_r = NᵀMN`, `C_r`, `K_r`. The first-order system
//! `ẋ = A x`, `A = [0 1; −M_r⁻¹K_r −M_r⁻¹C_r]`, is solved densely. Massless parts get
//! 1e-8 × the smallest non-zero mass, as Adams does.

use crate::applied::AppliedForces;
use crate::hessian::HessianBlocks;
use crate::rows::{RowGradient, Velocities};
use crate::state::State;
use crate::system::System;
use faer::linalg::solvers::DenseSolveCore;
use faer::Mat;
use linkage_model::Model;

/// Options of the eigen solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LinearOptions {
    /// Keep damping (Adams NODAMPIN clears it).
    pub damping: bool,
    /// Compute mode shapes (Adams NOVECTOR clears it).
    pub vectors: bool,
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

/// Result of a linearization.
#[derive(Clone, Debug, PartialEq)]
pub struct Linearization {
    /// Independent motions (the DOF) and states (2 × DOF).
    pub dof: usize,
    pub modes: Vec<Mode>,
    /// Eigenvalues at zero (rigid-body modes) found.
    pub zero_eigenvalues: usize,
    /// Zero eigenvalues expected from the free motions that carry no stiffness.
    pub expected_zero_eigenvalues: usize,
    /// Parts given a small artificial mass (zero-mass parts).
    pub massless_parts: usize,
}

fn cplx_abs(re: f64, im: f64) -> f64 {
    re.hypot(im)
}

/// Orthonormal basis of the null space of `a` (rows × cols), via QR of `aᵀ`.
fn null_space(a: &Mat<f64>) -> Mat<f64> {
    let (rows, cols) = (a.nrows(), a.ncols());
    if rows == 0 {
        return Mat::<f64>::identity(cols, cols);
    }
    let at = a.transpose().to_owned();
    let qr = at.qr();
    let q = qr.compute_Q();
    let r = qr.R();
    let d = rows.min(cols);
    let rmax = (0..d).map(|i| r[(i, i)].abs()).fold(0.0, f64::max);
    let rank = (0..d)
        .filter(|&i| r[(i, i)].abs() > 1e-9 * rmax.max(1e-300))
        .count();
    q.subcols(rank, cols - rank).to_owned()
}

/// Linearises at positions `s`, velocities `v`, with constraint multipliers `lambda` (row,
/// value in model force units) on the independent rows `rows`.
#[allow(clippy::too_many_arguments)]
pub fn linearize(
    model: &Model,
    sys: &System,
    rows: &[usize],
    forces: &dyn AppliedForces,
    s: &State,
    v: &Velocities,
    lambda: &[(usize, f64)],
    opts: LinearOptions,
) -> Result<Linearization, String> {
    let n = model.parts.len();
    let dim = 6 * n;
    let l = model.characteristic_length;
    let ucf = model.ucf();
    let sc = |c: usize| if c % 6 < 3 { l } else { 1.0 };

    // Mass matrix (scaled), with Adams' small mass for massless parts.
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
    let small_mass = if min_mass.is_finite() {
        1e-8 * min_mass
    } else {
        1e-8
    };
    let small_inertia = if min_inertia.is_finite() {
        1e-8 * min_inertia
    } else {
        small_mass * l * l
    };
    let mut massless_parts = 0;
    let mut m = Mat::<f64>::zeros(dim, dim);
    for (k, p) in model.parts.iter().enumerate() {
        let mass = if p.mass > 0.0 { p.mass } else { small_mass };
        if p.mass <= 0.0 {
            massless_parts += 1;
        }
        let r = s.poses[k].r;
        let mut ig = r * p.inertia * r.transpose();
        if linkage_model::inertia::symmetric_eigenvalues(&ig)[0] <= 0.0 {
            ig += glam::DMat3::IDENTITY * small_inertia;
        }
        for c in 0..3 {
            m[(6 * k + c, 6 * k + c)] = mass * l * l;
            for d in 0..3 {
                m[(6 * k + 3 + c, 6 * k + 3 + d)] = ig.col(d)[c];
            }
        }
    }
    // Stiffness and damping (scaled).
    let mut kmat = Mat::<f64>::zeros(dim, dim);
    let mut cmat = Mat::<f64>::zeros(dim, dim);
    let mut dq = Vec::new();
    let mut dv = Vec::new();
    forces.add_jacobians(s, v, &mut dq, Some(&mut dv))?;
    for (i, j, x) in dq {
        kmat[(i, j)] -= ucf * x * sc(i) * sc(j);
    }
    if opts.damping {
        for (i, j, x) in dv {
            cmat[(i, j)] -= ucf * x * sc(i) * sc(j);
        }
        // Gyroscopic term of −ω × (I ω): ∂/∂ω = −([ω]× I − [Iω]×).
        for (k, p) in model.parts.iter().enumerate() {
            let w = v[k].1;
            if w == glam::DVec3::ZERO {
                continue;
            }
            let r = s.poses[k].r;
            let ig = r * p.inertia * r.transpose();
            let gmat = linkage_model::frames::skew(w) * ig - linkage_model::frames::skew(ig * w);
            for c in 0..3 {
                for d in 0..3 {
                    cmat[(6 * k + 3 + c, 6 * k + 3 + d)] += gmat.col(d)[c];
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
            kmat[(i, j)] += x * sc(i) * sc(j);
        }
    }
    // Constraint Jacobian (scaled columns) and its null space.
    let mut jm = Mat::<f64>::zeros(rows.len(), dim);
    let mut g = RowGradient::default();
    for (k, &r) in rows.iter().enumerate() {
        sys.gradient(r, s, &mut g);
        for (body, b) in &g.blocks {
            for c in 0..6 {
                jm[(k, 6 * body + c)] = b[c] * sc(c);
            }
        }
    }
    let nb = null_space(&jm);
    let f = nb.ncols();
    if f == 0 {
        return Ok(Linearization {
            dof: 0,
            modes: Vec::new(),
            zero_eigenvalues: 0,
            expected_zero_eigenvalues: 0,
            massless_parts,
        });
    }
    let mr = nb.transpose() * &m * &nb;
    let kr = nb.transpose() * &kmat * &nb;
    let cr = nb.transpose() * &cmat * &nb;
    let lu = mr.partial_piv_lu();
    let minv = lu.inverse();
    let mk = &minv * &kr;
    let mc = &minv * &cr;
    let mut a = Mat::<f64>::zeros(2 * f, 2 * f);
    for i in 0..f {
        a[(i, f + i)] = 1.0;
        for j in 0..f {
            a[(f + i, j)] = -mk[(i, j)];
            a[(f + i, f + j)] = -mc[(i, j)];
        }
    }
    if (0..2 * f).any(|i| (0..2 * f).any(|j| !a[(i, j)].is_finite())) {
        return Err("the reduced mass matrix is singular".into());
    }
    let eig = a
        .eigen()
        .map_err(|e| format!("the eigen solution failed: {e:?}"))?;
    let vals = eig.S();
    let vecs = eig.U();
    let lmax = (0..2 * f)
        .map(|i| cplx_abs(vals[i].re, vals[i].im))
        .fold(0.0, f64::max);
    // Zero eigenvalues are judged against the model's own frequency scale √(‖K‖/‖M‖) (and
    // ‖C‖/‖M‖), not against the other eigenvalues (a one-DOF model has no others).
    let norm_max = |x: &Mat<f64>| {
        (0..dim)
            .flat_map(|i| (0..dim).map(move |j| (i, j)))
            .map(|(i, j)| x[(i, j)].abs())
            .fold(0.0, f64::max)
    };
    let (kn, cn, mn) = (norm_max(&kmat), norm_max(&cmat), norm_max(&m).max(1e-300));
    let omega_ref = (kn / mn).sqrt().max(cn / mn).max(1e-300);
    let zero_tol = 1e-6 * omega_ref;
    let zero_eigenvalues = (0..2 * f)
        .filter(|&i| cplx_abs(vals[i].re, vals[i].im) <= zero_tol)
        .count();
    // Expected zeros: 2 per free motion without stiffness, minus those damping takes away.
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
                .filter(|&i| s_vals[i].abs() <= 1e-10 * kmax.max(kn).max(1e-300))
                .collect();
            let p = Mat::<f64>::from_fn(f, free.len(), |i, j| u[(i, free[j])]);
            let pc = p.transpose() * &cr * &p;
            let cmax = (0..free.len())
                .flat_map(|i| (0..free.len()).map(move |j| (i, j)))
                .map(|(i, j)| pc[(i, j)].abs())
                .fold(0.0, f64::max);
            let damped = if free.is_empty() || cmax == 0.0 {
                0
            } else {
                let inner = null_space(&pc);
                free.len() - inner.ncols()
            };
            2 * free.len() - damped
        }
        Err(_) => zero_eigenvalues,
    };
    let mut modes = Vec::new();
    for i in 0..2 * f {
        let (re, im) = (vals[i].re, vals[i].im);
        if im < -1e-12 * lmax.max(1.0) {
            continue;
        }
        let mag = cplx_abs(re, im);
        let shape = opts.vectors.then(|| {
            // Positions: top half of the eigenvector, mapped back to part coordinates.
            let mut coords = vec![(0.0f64, 0.0f64); dim];
            for (row, c) in coords.iter_mut().enumerate() {
                let (mut sr, mut si) = (0.0, 0.0);
                for j in 0..f {
                    let z = vecs[(j, i)];
                    sr += nb[(row, j)] * z.re;
                    si += nb[(row, j)] * z.im;
                }
                *c = (sr * sc(row), si * sc(row));
            }
            let biggest = coords
                .iter()
                .map(|(r, i)| r.hypot(*i))
                .fold(0.0, f64::max)
                .max(1e-300);
            (0..n)
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
        });
        modes.push(Mode {
            real: re,
            imag: im.max(0.0),
            frequency: mag / std::f64::consts::TAU,
            damping_ratio: if mag > 0.0 { -re / mag } else { 0.0 },
            shape,
        });
    }
    modes.sort_by(|a, b| {
        a.frequency
            .total_cmp(&b.frequency)
            .then(a.real.total_cmp(&b.real))
    });
    Ok(Linearization {
        dof: f,
        modes,
        zero_eigenvalues,
        expected_zero_eigenvalues,
        massless_parts,
    })
}

/// A linear analysis: initial conditions, optionally static equilibrium, then the eigen
/// solution about that operating point.
#[derive(Clone, Debug)]
pub struct LinearRun {
    pub ic: crate::ic::InitialConditions,
    /// The static equilibrium used as operating point (with `--static-first`).
    pub equilibrium: Option<Result<crate::statics::Equilibrium, String>>,
    pub result: Result<Linearization, String>,
}

/// Runs the initial conditions, then (with `static_first`) static equilibrium, then the
/// linearization about the resulting operating point. Without static equilibrium the operating
/// point is the assembled configuration with the IC velocities and the constraint forces of the
/// acceleration/force IC.
pub fn run(
    model: &Model,
    drivers: &crate::drivers::ExpressionDrivers,
    forces: &dyn AppliedForces,
    tol: &crate::tolerances::Tolerances,
    static_first: bool,
    opts: LinearOptions,
) -> LinearRun {
    let sys = System::new(model);
    if static_first {
        let st = crate::statics::run(model, drivers, forces, tol, &[0.0]);
        let eq = st.steps.into_iter().next().map(|(_, e)| e);
        let ic = st.ic;
        let rows = crate::ic::admitted_rows(&ic.analysis);
        let result = match &eq {
            Some(Ok(e)) if e.converged => {
                let v = vec![(glam::DVec3::ZERO, glam::DVec3::ZERO); model.parts.len()];
                linearize(
                    model,
                    &sys,
                    &rows,
                    forces,
                    &e.state,
                    &v,
                    &e.multipliers,
                    opts,
                )
            }
            Some(Ok(_)) => Err("static equilibrium did not converge; no operating point".into()),
            Some(Err(e)) => Err(e.clone()),
            None => Err("the model could not be assembled; no operating point".into()),
        };
        return LinearRun {
            ic,
            equilibrium: eq,
            result,
        };
    }
    let ic = crate::ic::initial_conditions(model, drivers, forces, tol);
    let rows = crate::ic::admitted_rows(&ic.analysis);
    let result = match (&ic.velocity, &ic.acceleration) {
        (Some(v), Some(Ok(a))) => linearize(
            model,
            &sys,
            &rows,
            forces,
            &ic.assembly.state,
            &v.velocities,
            &a.multipliers,
            opts,
        ),
        (_, Some(Err(e))) => Err(e.clone()),
        _ => Err("the model could not be assembled; no operating point".into()),
    };
    LinearRun {
        ic,
        equilibrium: None,
        result,
    }
}
