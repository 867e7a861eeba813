//! The rigid–modal inertia coupling of FLEX_BODY (INVAR3, 4, 5, 8, 9 in the mass matrix and
//! the quadratic velocity terms, issue 17) against closed forms and conservation laws.
//!
//! The modal data are the cantilever modes of the uniform beam of `common::beam_modes` (first
//! bending modes in the y and z planes), and every invariant is the sum over particles: the
//! beam as point masses `ρA·w` at the 80 Gauss–Legendre points of `[0, L]`, plus the sections'
//! rotary inertia `ρL·diag(2I, I, I)` in INVAR7 only. The same particles give the tests'
//! momenta and kinetic energy, independently of linkage's invariant algebra.

mod common;

use common::analyses::{built, linear, load};

use common::beam_modes::{
    area, beam_scale, gauss_legendre, matrix, mode, second_moment, CANTILEVER, E, FREE_FREE, L, RHO,
};
use glam::{DMat3, DVec3};
use linkage_model::frames::skew;
use linkage_model::Model;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Output, Start};
use linkage_solve::stages::linearize::Linearization;
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::TAU;
use std::fmt::Write;

/// A point mass of the beam: mass, undeformed position (BCS) and translational shape of
/// every mode.
type Particle = (f64, DVec3, Vec<DVec3>);

/// The particle model of the beam with `bls.len()` cantilever modes per bending plane (mode
/// order: y plane, z plane, alternating).
struct Beam {
    /// Mass, undeformed position (BCS) and translational shape of every mode.
    particles: Vec<Particle>,
    /// The sections' rotary inertia (BCS), constant.
    rotary: DMat3,
    bls: Vec<f64>,
}

impl Beam {
    fn new(bls: &[f64]) -> Beam {
        let particles = gauss_legendre(80, L)
            .into_iter()
            .map(|(x, w)| {
                let shapes = bls
                    .iter()
                    .flat_map(|bl| {
                        let phi = mode(*bl, false, x).0;
                        [DVec3::new(0.0, phi, 0.0), DVec3::new(0.0, 0.0, phi)]
                    })
                    .collect();
                (RHO * area() * w, DVec3::new(x, 0.0, 0.0), shapes)
            })
            .collect();
        let i = second_moment();
        Beam {
            particles,
            rotary: DMat3::from_diagonal(DVec3::new(2.0 * i, i, i)) * (RHO * L),
            bls: bls.to_vec(),
        }
    }

    fn modes(&self) -> usize {
        2 * self.bls.len()
    }

    fn mass(&self) -> f64 {
        self.particles.iter().map(|p| p.0).sum()
    }

    /// The undeformed centre of mass (BCS).
    fn centre(&self) -> DVec3 {
        self.particles.iter().map(|p| p.1 * p.0).sum::<DVec3>() / self.mass()
    }

    fn stiffness(&self) -> Vec<f64> {
        self.bls
            .iter()
            .flat_map(|bl| {
                let k = bl.powi(4) * E * second_moment() / L.powi(3);
                [k, k]
            })
            .collect()
    }

    /// `Σ_p f(particle)` of 3 × 3 matrices.
    fn sum3(&self, f: impl Fn(&Particle) -> DMat3) -> DMat3 {
        self.particles
            .iter()
            .fold(DMat3::ZERO, |acc, p| acc + f(p) * p.0)
    }

    /// The dataset: FLEX_BODY/1 from the origin along x with every invariant, markers 10, 13
    /// and 11 on nodes 1 (x = 0), 2 (x = L/2) and 3 (x = L); `flex` appended to the
    /// FLEX_BODY, `extra` statements before END.
    fn dataset(&self, flex: &str, extra: &str) -> String {
        let nm = self.modes();
        let mut s = String::from(
            "coupled flex beam\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, \
             TIME = SECOND\nPART/1, GROUND\nMARKER/1, PART = 1\n",
        );
        let _ = writeln!(
            s,
            "FLEX_BODY/1, MATRICES = 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14{flex}"
        );
        let selmod: Vec<f64> = (1..=nm).map(|x| x as f64).collect();
        matrix(&mut s, 1, "SELMOD", nm, 1, &selmod);
        matrix(
            &mut s,
            2,
            "SELNOD",
            3,
            4,
            &[1.0, 0.0, 0.0, 0.0, 2.0, 0.5 * L, 0.0, 0.0, 3.0, L, 0.0, 0.0],
        );
        let k = self.stiffness();
        let mut genstiff = vec![0.0; nm * nm];
        for j in 0..nm {
            genstiff[j * nm + j] = k[j];
        }
        matrix(&mut s, 3, "GENSTIFF", nm, nm, &genstiff);
        matrix(&mut s, 4, "INVAR1", 1, 1, &[self.mass()]);
        let first = self.centre() * self.mass();
        matrix(&mut s, 5, "INVAR2", 3, 1, &first.to_array());
        let gm: Vec<f64> = (0..nm * nm)
            .map(|x| {
                let (j, k) = (x / nm, x % nm);
                self.particles
                    .iter()
                    .map(|p| p.0 * p.2[j].dot(p.2[k]))
                    .sum()
            })
            .collect();
        matrix(&mut s, 6, "INVAR6", nm, nm, &gm);
        let i7 = self.sum3(|p| {
            DMat3::from_diagonal(DVec3::splat(p.1.length_squared()))
                - DMat3::from_cols(p.1 * p.1.x, p.1 * p.1.y, p.1 * p.1.z)
        }) + self.rotary;
        matrix(&mut s, 7, "INVAR7", 3, 3, &rows(&[i7]));
        // Node shapes: T_MODES and R_MODES (9 × nm).
        let (mut t, mut r) = (vec![0.0; 9 * nm], vec![0.0; 9 * nm]);
        for (n, x) in [0.0, 0.5 * L, L].iter().enumerate() {
            for (p, bl) in self.bls.iter().enumerate() {
                let (phi, slope) = mode(*bl, false, *x);
                t[(3 * n + 1) * nm + 2 * p] = phi;
                r[(3 * n + 2) * nm + 2 * p] = slope;
                t[(3 * n + 2) * nm + 2 * p + 1] = phi;
                r[(3 * n + 1) * nm + 2 * p + 1] = -slope;
            }
        }
        matrix(&mut s, 8, "T_MODES", 9, nm, &t);
        matrix(&mut s, 9, "R_MODES", 9, nm, &r);
        // INVAR3 and INVAR4: 3 × nm, column j.
        let column = |f: &dyn Fn(&Particle, usize) -> DVec3| -> Vec<f64> {
            let cols: Vec<DVec3> = (0..nm)
                .map(|j| self.particles.iter().map(|p| f(p, j) * p.0).sum())
                .collect();
            (0..3)
                .flat_map(|c| cols.iter().map(move |v| v[c]))
                .collect()
        };
        matrix(&mut s, 10, "INVAR3", 3, nm, &column(&|p, j| p.2[j]));
        matrix(
            &mut s,
            11,
            "INVAR4",
            3,
            nm,
            &column(&|p, j| p.1.cross(p.2[j])),
        );
        // INVAR5: rows 3k…3k+2, column j: Σ m Φ_k × Φ_j.
        let mut i5 = vec![0.0; 3 * nm * nm];
        for k in 0..nm {
            for j in 0..nm {
                let v: DVec3 = self
                    .particles
                    .iter()
                    .map(|p| p.2[k].cross(p.2[j]) * p.0)
                    .sum();
                for c in 0..3 {
                    i5[(3 * k + c) * nm + j] = v[c];
                }
            }
        }
        matrix(&mut s, 12, "INVAR5", 3 * nm, nm, &i5);
        let i8: Vec<DMat3> = (0..nm)
            .map(|j| self.sum3(|p| skew(p.1) * skew(p.2[j])))
            .collect();
        matrix(&mut s, 13, "INVAR8", 3 * nm, 3, &rows(&i8));
        let i9: Vec<DMat3> = (0..nm * nm)
            .map(|x| self.sum3(|p| skew(p.2[x / nm]) * skew(p.2[x % nm])))
            .collect();
        matrix(&mut s, 14, "INVAR9", 3 * nm * nm, 3, &rows(&i9));
        let _ = write!(
            s,
            "MARKER/10, FLEX_BODY = 1, NODE_ID = 1\nMARKER/11, FLEX_BODY = 1, NODE_ID = 3, \
             QP = {L}, 0, 0\nMARKER/13, FLEX_BODY = 1, NODE_ID = 2, QP = {}, 0, 0\n{extra}\nEND\n",
            0.5 * L
        );
        s
    }

    /// Linear momentum, angular momentum about the ground origin and total energy (kinetic
    /// plus modal strain) of the particles at an output.
    fn momenta(&self, m: &Model, o: &Output) -> (DVec3, DVec3, f64) {
        let b = &m.flex_bodies[0];
        let (pose, (v, w)) = (o.state.poses[b.reference], o.velocities[b.reference]);
        let a = pose.r;
        let q = coordinates(m, o);
        let eta_rate: Vec<f64> = b
            .modes
            .iter()
            .map(|x| o.velocities[x.part].0.dot(b.axis))
            .collect();
        let qd = b.coordinates(&eta_rate);
        let c = self.centre();
        let (mut lin, mut ang, mut kinetic) = (DVec3::ZERO, DVec3::ZERO, 0.0);
        for (mass, s, phi) in &self.particles {
            let u: DVec3 = *s - c + phi.iter().zip(&q).map(|(f, x)| *f * *x).sum::<DVec3>();
            let ud: DVec3 = phi.iter().zip(&qd).map(|(f, x)| *f * *x).sum();
            let r = pose.p + a * u;
            let rd = v + w.cross(a * u) + a * ud;
            lin += rd * *mass;
            ang += r.cross(rd) * *mass;
            kinetic += 0.5 * mass * rd.length_squared();
        }
        let rotary = a * self.rotary * a.transpose();
        ang += rotary * w;
        kinetic += 0.5 * w.dot(rotary * w);
        let strain: f64 = self
            .stiffness()
            .iter()
            .zip(&q)
            .map(|(k, x)| 0.5 * k * x * x)
            .sum();
        (lin, ang, kinetic + strain)
    }
}

/// 3 × 3 blocks stacked as rows (row-major).
fn rows(blocks: &[DMat3]) -> Vec<f64> {
    blocks
        .iter()
        .flat_map(|b| (0..3).flat_map(move |r| (0..3).map(move |c| b.col(c)[r])))
        .collect()
}

/// Outputs of a dynamic run at `times` with ERROR `error`.
fn simulate(text: &str, times: &[f64], error: f64) -> (Model, Vec<Output>) {
    let (m, d, f) = load(text);
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    assert!(a.failure().is_none());
    let settings = IntegratorSettings {
        error,
        ..Default::default()
    };
    let r = run(&a, times, &settings, Start::InitialConditions, |_| {});
    let sim = r.simulation.unwrap_or_else(|| panic!("{:?}", r.error));
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let outputs = sim.outputs;
    (m, outputs)
}

/// The dataset's modal coordinates q at an output (`q = V·η` when linkage integrates the
/// principal modes η: the beam constants' six digits leave INVAR6 off-diagonal by 1e-7).
fn coordinates(m: &Model, o: &Output) -> Vec<f64> {
    let b = &m.flex_bodies[0];
    let eta: Vec<f64> = b
        .modes
        .iter()
        .map(|x| (o.state.poses[x.part].p - b.rest).dot(b.axis))
        .collect();
    b.coordinates(&eta)
}

/// Coordinate `j` of the modes linkage integrates (the principal modes η, if any).
fn principal(m: &Model, o: &Output, j: usize) -> f64 {
    let b = &m.flex_bodies[0];
    (o.state.poses[b.modes[j].part].p - b.rest).dot(b.axis)
}

#[test]
fn free_flex_body_of_cantilever_modes_vibrates_at_the_free_free_frequencies() {
    // Rayleigh–Ritz: the rigid motions and five cantilever modes per plane span the free
    // beam's lowest modes, so the coupled body has the free-free beam's frequencies
    // (βL = 4.730041, 7.853205) to the accuracy of the basis (the sections' rotary inertia,
    // which INVAR7 alone carries, and the six-digit βL of the modes move them by 3e-4);
    // without the coupling (INVARIANTS 3, 4, 5, 8, 9 off) the modes stay the cantilever's,
    // whatever the reference frame does.
    let beam = Beam::new(&CANTILEVER);
    let first = FREE_FREE[0].powi(2) * beam_scale() / TAU;
    let elastic = |lin: &Linearization| {
        let mut f: Vec<f64> = lin
            .modes
            .iter()
            .map(|m| m.frequency)
            .filter(|f| *f > 1e-4 * first)
            .collect();
        f.sort_by(f64::total_cmp);
        f
    };
    let text = beam.dataset(", CRATIO = 0", "");
    // Every invariant is listed: no warning about the coupling.
    for w in &built(&text).warnings {
        assert!(!w.message.contains("coupling"), "{}", w.message);
    }
    let coupled = linear(&text);
    // Sixteen degrees of freedom: ten elastic modes, and the six rigid-body motions at zero
    // (counted as zero, or left at the rounding level of the 60 coordinates, below 1e-4 of
    // the first elastic frequency).
    assert!(
        coupled.zero_eigenvalues >= 6,
        "{}",
        coupled.zero_eigenvalues
    );
    assert_eq!(elastic(&coupled).len(), 10);
    let f = elastic(&coupled);
    for (k, bl) in FREE_FREE[..2].iter().enumerate() {
        let exact = bl * bl * beam_scale() / TAU;
        for x in &f[2 * k..2 * k + 2] {
            assert!((x / exact - 1.0).abs() < 1e-3, "{x} vs {exact}");
        }
    }
    let uncoupled = linear(&beam.dataset(", INVARIANTS = T:T:F:F:F:T:T:F:F, CRATIO = 0", ""));
    let f = elastic(&uncoupled);
    assert_eq!(f.len(), 10);
    let cantilever = CANTILEVER[0].powi(2) * beam_scale() / TAU;
    for x in &f[..2] {
        assert!((x / cantilever - 1.0).abs() < 1e-6, "{x} vs {cantilever}");
    }
}

#[test]
fn free_flex_body_keeps_its_momenta_and_energy() {
    // No gravity, no damping, tumbling and vibrating: the particles' linear and angular
    // momentum and the energy stay at their start values. Without the coupling the modal
    // velocity would carry momentum the reference body never feels.
    let beam = Beam::new(&CANTILEVER[..2]);
    let text = beam.dataset(
        ", CRATIO = 0, DMODE = 1e-3, 0, 0, -5e-4, VMODE = 0.2, 0.1, 0, 0.05\
         , VX = 0.1, VY = 0, VZ = 0, WX = 0, WY = 0.5, WZ = 1",
        "",
    );
    let times: Vec<f64> = (0..=20).map(|k| 0.005 * k as f64).collect();
    // The largest relative drift of each over 0.1 s (about five periods of the first mode).
    let drift = |error: f64| {
        let (m, outputs) = simulate(&text, &times, error);
        let (p0, h0, e0) = beam.momenta(&m, &outputs[0]);
        // The start is not trivial: momentum from the modes, spin, strain and kinetic energy.
        assert!(
            p0.y.abs() > 1e-3 && h0.length() > 1e-2 && e0 > 1e-3,
            "{p0} {h0} {e0}"
        );
        let mut worst = [0.0f64; 3];
        for o in &outputs {
            let (p, h, e) = beam.momenta(&m, o);
            worst[0] = worst[0].max((p - p0).length() / p0.length());
            worst[1] = worst[1].max((h - h0).length() / h0.length());
            worst[2] = worst[2].max((e - e0).abs() / e0);
        }
        worst
    };
    // Measured: 6.3e-5, 2.2e-6, 1.2e-5 at ERROR 1e-8; five times less at 1e-10: the drift is
    // the integrator's, and it goes with the ERROR.
    let coarse = drift(1e-8);
    assert!(
        coarse[0] < 2e-4,
        "linear momentum drifts by {:e}",
        coarse[0]
    );
    assert!(
        coarse[1] < 1e-5,
        "angular momentum drifts by {:e}",
        coarse[1]
    );
    assert!(coarse[2] < 5e-5, "energy drifts by {:e}", coarse[2]);
    let fine = drift(1e-10);
    for k in 0..3 {
        assert!(fine[k] < coarse[k] / 3.0, "{fine:?} vs {coarse:?}");
    }
}

#[test]
fn spinning_cantilever_softens_in_plane_to_the_root_of_w2_minus_spin2() {
    // Root clamped to a hub turning at Ω about z: the in-plane (y) mode obeys
    // m q̈ + (k − m Ω²) q = 0 (spin softening from INVAR9), the out-of-plane (z) mode keeps ω₁.
    let spin = 30.0;
    let beam = Beam::new(&CANTILEVER[..1]);
    let text = beam.dataset(
        ", CRATIO = 0, DMODE = 1e-3, 1e-3",
        &format!(
            "PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
             JOINT/2, REVOLUTE, I = 20, J = 1\n\
             MOTION/1, JOINT = 2, ROTATION, FUNCTION = {spin} * TIME\n\
             JOINT/1, FIXED, I = 10, J = 20"
        ),
    );
    let dt = 2e-4;
    let times: Vec<f64> = (0..=2500).map(|k| dt * k as f64).collect();
    let (m, outputs) = simulate(&text, &times, 1e-8);
    let omega = CANTILEVER[0].powi(2) * beam_scale();
    // Mean period from the first and last upward zero crossings.
    let period = |j: usize| {
        let q: Vec<f64> = outputs.iter().map(|o| coordinates(&m, o)[j]).collect();
        let crossings: Vec<f64> = (1..q.len())
            .filter(|&k| q[k - 1] < 0.0 && q[k] >= 0.0)
            .map(|k| times[k - 1] + dt * q[k - 1] / (q[k - 1] - q[k]))
            .collect();
        let n = crossings.len() - 1;
        (crossings[n] - crossings[0]) / n as f64
    };
    let in_plane = TAU / (omega * omega - spin * spin).sqrt();
    let out_of_plane = TAU / omega;
    let (ty, tz) = (period(0), period(1));
    assert!((ty / in_plane - 1.0).abs() < 1e-4, "{ty} vs {in_plane}");
    assert!(
        (tz / out_of_plane - 1.0).abs() < 1e-4,
        "{tz} vs {out_of_plane}"
    );
}

#[test]
fn base_accelerated_cantilever_follows_the_modal_step_response() {
    // Root clamped to a sled accelerating at a₀ along y: each (principal) y mode is a
    // step-loaded oscillator, η_j = −(I3_j,y·a₀/k_j)(1 − cos ω_j t) with the mode's first
    // moment I3_j, stiffness k_j and generalized mass m_j (INVAR3 in the mass matrix); the z
    // modes stay at rest.
    let a0 = 5.0;
    let beam = Beam::new(&CANTILEVER[..2]);
    let text = beam.dataset(
        ", CRATIO = 0",
        &format!(
            "PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
             MARKER/21, PART = 1, REULER = 0, -90D, 0\n\
             MARKER/22, PART = 2, REULER = 0, -90D, 0\n\
             JOINT/2, TRANSLATIONAL, I = 22, J = 21\n\
             MOTION/1, JOINT = 2, TRANSLATION, FUNCTION = {} * TIME**2\n\
             JOINT/1, FIXED, I = 10, J = 20",
            0.5 * a0
        ),
    );
    let times: Vec<f64> = (0..=40).map(|k| 0.0025 * k as f64).collect();
    let (m, outputs) = simulate(&text, &times, 1e-8);
    let b = &m.flex_bodies[0];
    for j in [0, 2] {
        let mode = &b.modes[j];
        let w = (mode.stiffness / mode.mass).sqrt();
        let amplitude = mode.first_moment.y * a0 / mode.stiffness;
        let mut worst = 0.0f64;
        for (o, t) in outputs.iter().zip(&times) {
            let expected = -amplitude * (1.0 - (w * t).cos());
            worst = worst.max((principal(&m, o, j) - expected).abs());
        }
        assert!(
            worst < 1e-4 * amplitude.abs(),
            "mode {j}: error {worst:e} of {amplitude:e}"
        );
    }
    for o in &outputs {
        let q = coordinates(&m, o);
        assert!(q[1].abs() < 1e-12 && q[3].abs() < 1e-12, "{q:?}");
    }
}
