//! ORIENT: hand-computed values of every orientation system, Adams' own Euler-parameter
//! values, exact derivatives and path series against finite differences, and errors.
// Index loops read as the matrix formulas they are.
#![allow(clippy::needless_range_loop)]
mod common;

use common::assert_close;
use linkage_expr::{
    evaluate, evaluate_path_series, evaluate_time_series, evaluate_with_gradient, orient, parse,
    Dual, Env, EvalError, EvalErrorKind, MarkerArgs, MeasureKind, TimeEnv,
};

type M3 = [[f64; 3]; 3];

fn mul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

/// Elementary rotation about axis `k` (0, 1, 2) by `t`, and its first and second derivatives
/// with respect to `t`.
fn elementary(k: usize, t: f64) -> [M3; 3] {
    let (s, c) = t.sin_cos();
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let mut r = [[0.0; 3]; 3];
    let mut d1 = [[0.0; 3]; 3];
    let mut d2 = [[0.0; 3]; 3];
    r[k][k] = 1.0;
    // Rotation in the (i, j) plane: i → c·i + s·j.
    r[i][i] = c;
    r[j][j] = c;
    r[j][i] = s;
    r[i][j] = -s;
    d1[i][i] = -s;
    d1[j][j] = -s;
    d1[j][i] = c;
    d1[i][j] = -c;
    d2[i][i] = -c;
    d2[j][j] = -c;
    d2[j][i] = -s;
    d2[i][j] = s;
    [r, d1, d2]
}

/// `R_a(q0)·R_b(q1)·R_c(q2)`.
fn sequence(axes: [usize; 3], q: [f64; 3]) -> M3 {
    let m: Vec<M3> = (0..3).map(|k| elementary(axes[k], q[k])[0]).collect();
    mul(&mul(&m[0], &m[1]), &m[2])
}

fn column_major(r: &M3) -> [f64; 9] {
    std::array::from_fn(|e| r[e % 3][e / 3])
}

/// An environment whose ORIENT(…, 1, 2) rotation is `R(q) = Rz(q0)·Rx(q1)·Ry(q2)` (marker 1
/// relative to marker 2), with exact derivatives in q (variables 0, 1, 2) and series along
/// `q(t) = q + q̇ t + q̈ t²/2`. Relative to ground (j = 0) it is `B·R(q)` with a fixed `B`.
#[derive(Clone)]
struct Rotating {
    q: [f64; 3],
    qd: [f64; 3],
    qdd: [f64; 3],
    time: f64,
}

const AXES: [usize; 3] = [2, 0, 1];

impl Rotating {
    fn base(&self, j: u32) -> M3 {
        if j == 2 {
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        } else {
            // Ground relative to marker 2: a fixed rotation.
            sequence([0, 1, 2], [0.4, -0.3, 1.1])
        }
    }

    /// R, ∂R/∂q_k and ∂²R/∂q_k∂q_l.
    fn derivatives(&self, j: u32) -> (M3, [M3; 3], [[M3; 3]; 3]) {
        let e: Vec<[M3; 3]> = (0..3).map(|k| elementary(AXES[k], self.q[k])).collect();
        let b = self.base(j);
        let product = |orders: [usize; 3]| -> M3 {
            let m = mul(&mul(&e[0][orders[0]], &e[1][orders[1]]), &e[2][orders[2]]);
            mul(&b, &m)
        };
        let r = product([0, 0, 0]);
        let d: [M3; 3] = std::array::from_fn(|k| {
            let mut o = [0; 3];
            o[k] = 1;
            product(o)
        });
        let dd: [[M3; 3]; 3] = std::array::from_fn(|k| {
            std::array::from_fn(|l| {
                let mut o = [0; 3];
                o[k] += 1;
                o[l] += 1;
                product(o)
            })
        });
        (r, d, dd)
    }
}

impl Env for Rotating {
    fn time(&self) -> f64 {
        self.time
    }
    fn rotation(&self, i: u32, j: u32, gradient: bool) -> Result<[Dual; 9], EvalError> {
        if i != 1 || (j != 2 && j != 0) {
            return Err(EvalError::unknown_reference(format!("marker {i} or {j}")));
        }
        let (r, d, _) = self.derivatives(j);
        Ok(std::array::from_fn(|e| {
            let (row, col) = (e % 3, e / 3);
            if gradient {
                Dual::new(r[row][col], (0..3).map(|k| (k as u32, d[k][row][col])))
            } else {
                Dual::constant(r[row][col])
            }
        }))
    }
    fn rotation_series(&self, i: u32, j: u32) -> Result<[[f64; 3]; 9], EvalError> {
        if i != 1 || (j != 2 && j != 0) {
            return Err(EvalError::unknown_reference(format!("marker {i} or {j}")));
        }
        let (r, d, dd) = self.derivatives(j);
        Ok(std::array::from_fn(|e| {
            let (row, col) = (e % 3, e / 3);
            let rate: f64 = (0..3).map(|k| d[k][row][col] * self.qd[k]).sum();
            let mut acc: f64 = (0..3).map(|k| d[k][row][col] * self.qdd[k]).sum();
            for k in 0..3 {
                for l in 0..3 {
                    acc += dd[k][l][row][col] * self.qd[k] * self.qd[l];
                }
            }
            [r[row][col], rate, acc]
        }))
    }
    fn measure(&self, kind: MeasureKind, m: MarkerArgs, _: bool) -> Result<Dual, EvalError> {
        if kind != MeasureKind::Dx || m.i != 1 {
            return Err(EvalError::unavailable("only DX(1)"));
        }
        Ok(Dual::new(self.q[0].sin(), [(0, self.q[0].cos())]))
    }
    fn measure_series(&self, kind: MeasureKind, m: MarkerArgs) -> Result<[f64; 3], EvalError> {
        // DX(1) = sin(q0(t)) along the path, for mixing measures with ORIENT and TIME.
        if kind != MeasureKind::Dx || m.i != 1 {
            return Err(EvalError::unavailable("only DX(1)"));
        }
        let (s, c) = self.q[0].sin_cos();
        Ok([
            s,
            c * self.qd[0],
            c * self.qdd[0] - s * self.qd[0] * self.qd[0],
        ])
    }
}

fn env_at(q: [f64; 3]) -> Rotating {
    Rotating {
        q,
        qd: [0.7, -1.3, 0.4],
        qdd: [0.2, 0.5, -0.9],
        time: 0.8,
    }
}

/// Every (system, component) pair.
fn all_components() -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for system in 1..=29u32 {
        let n = match system {
            27 => 4,
            29 => 9,
            _ => 3,
        };
        for c in 1..=n {
            out.push((system, c));
        }
    }
    out
}

const TWELVE: [[usize; 3]; 12] = [
    [0, 1, 2],
    [1, 2, 0],
    [2, 0, 1],
    [0, 2, 1],
    [1, 0, 2],
    [2, 1, 0],
    [0, 1, 0],
    [0, 2, 0],
    [1, 0, 1],
    [1, 2, 1],
    [2, 0, 2],
    [2, 1, 2],
];

#[test]
fn euler_angles_of_every_body_and_space_fixed_sequence_are_recovered() {
    for (n, seq) in TWELVE.iter().enumerate() {
        let proper = seq[0] == seq[2];
        // Middle angle inside its range: (0, π) for repeated axes, (−π/2, π/2) otherwise.
        let angles = if proper {
            [0.3, 0.9, -2.1]
        } else {
            [-2.4, 0.6, 1.2]
        };
        let r = column_major(&sequence(*seq, angles));
        for k in 0..3u32 {
            let got = orient(n as u32 + 1, k + 1, &r).unwrap();
            assert_close(got, angles[k as usize], 1e-12, &format!("body {seq:?} {k}"));
        }
        // Space-fixed a-b-c with angles (θ1, θ2, θ3): R = R_c(θ3)·R_b(θ2)·R_a(θ1).
        let space = mul(
            &mul(
                &elementary(seq[2], angles[2])[0],
                &elementary(seq[1], angles[1])[0],
            ),
            &elementary(seq[0], angles[0])[0],
        );
        let r = column_major(&space);
        for k in 0..3u32 {
            let got = orient(n as u32 + 13, k + 1, &r).unwrap();
            assert_close(
                got,
                angles[k as usize],
                1e-12,
                &format!("space {seq:?} {k}"),
            );
        }
    }
}

#[test]
fn quarter_turn_about_z_in_every_system() {
    // x_i = y_j, y_i = −x_j, z_i = z_j.
    let r: M3 = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
    let r = column_major(&r);
    let q = std::f64::consts::FRAC_PI_2;
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let expect: &[(u32, u32, f64)] = &[
        (1, 3, q),   // body 1-2-3: the last rotation is about z
        (1, 1, 0.0), // …the others are zero
        (6, 1, q),   // body 3-2-1: the first
        (11, 1, q),  // body 3-1-3 at θ = 0: ψ carries the turn, φ = 0
        (11, 2, 0.0),
        (11, 3, 0.0),
        (13, 3, q), // space 1-2-3: R = Rz(θ3)·Ry(θ2)·Rx(θ1)
        (18, 1, q), // space 3-2-1: R = Rx·Ry·Rz(θ1)
        (25, 3, q), // AZ
        (25, 1, 0.0),
        (26, 1, q), // YAW
        (27, 1, h), // P0 = cos 45°
        (27, 2, 0.0),
        (27, 3, 0.0),
        (27, 4, h), // P3 = sin 45°
        (28, 3, 1.0),
        (28, 1, 0.0),
        (29, 1, 0.0), // x_i·x_j
        (29, 2, 1.0), // x_i·y_j
        (29, 3, 0.0),
        (29, 4, -1.0), // y_i·x_j
        (29, 5, 0.0),
        (29, 9, 1.0), // z_i·z_j
    ];
    for &(system, component, want) in expect {
        let got = orient(system, component, &r).unwrap();
        assert_close(got, want, 1e-14, &format!("ORIENT({system},{component})"));
    }
}

/// The body 3-1-3 matrix `Rz(ψ)·Rx(θ)·Rz(φ)` of angles in degrees.
fn from_313_degrees(a: [f64; 3]) -> [f64; 9] {
    column_major(&sequence([2, 0, 2], a.map(f64::to_radians)))
}

#[test]
fn euler_parameters_match_adams_output_signs_included() {
    // Adams' REQUEST/1 (ψ, θ, φ in degrees) and REQUEST/4 (ORIENT(27, 1..4)) of the Chrono
    // test model Distance_Case02 at t = 2.0 and t = 4.75, and Universal_Case01 at t = 0.5
    // (printed to 6 digits).
    let cases: [([f64; 3], [f64; 4]); 3] = [
        (
            [147.397, 130.039, -6.65255],
            [0.14186, 0.20352, 0.88331, 0.39777],
        ),
        (
            [160.811, 59.36, 163.942],
            [-0.82803, 0.49497, -0.01353, 0.26304],
        ),
        ([0.0, 56.1402, 0.0], [0.88237, 0.47055, 0.0, 0.0]),
    ];
    for (angles, want) in cases {
        let r = from_313_degrees(angles);
        for c in 0..4 {
            let got = orient(27, c as u32 + 1, &r).unwrap();
            assert!(
                (got - want[c]).abs() < 2e-5,
                "{angles:?}: P{c} = {got}, Adams {}",
                want[c]
            );
        }
        // Rodrigues parameters are the ratios.
        for c in 1..4 {
            let got = orient(28, c as u32, &r).unwrap();
            assert_close(got, want[c] / want[0], 1e-3, "Rodrigues");
        }
    }
}

#[test]
fn euler_parameters_reproduce_the_rotation() {
    for angles in [
        [10.0, 20.0, 30.0],
        [-170.0, 100.0, 175.0],
        [90.0, 0.0, 45.0],
    ] {
        let r = from_313_degrees(angles);
        let p: Vec<f64> = (1..=4).map(|c| orient(27, c, &r).unwrap()).collect();
        let (p0, p1, p2, p3) = (p[0], p[1], p[2], p[3]);
        let q: M3 = [
            [
                p0 * p0 + p1 * p1 - p2 * p2 - p3 * p3,
                2.0 * (p1 * p2 - p0 * p3),
                2.0 * (p1 * p3 + p0 * p2),
            ],
            [
                2.0 * (p1 * p2 + p0 * p3),
                p0 * p0 - p1 * p1 + p2 * p2 - p3 * p3,
                2.0 * (p2 * p3 - p0 * p1),
            ],
            [
                2.0 * (p1 * p3 - p0 * p2),
                2.0 * (p2 * p3 + p0 * p1),
                p0 * p0 - p1 * p1 - p2 * p2 + p3 * p3,
            ],
        ];
        let q = column_major(&q);
        for e in 0..9 {
            assert!((q[e] - r[e]).abs() < 1e-14, "{angles:?}: entry {e}");
        }
    }
}

/// Central difference of `ORIENT(…)` along variable `k`.
fn fd_gradient(text: &str, env: &Rotating, k: usize) -> f64 {
    let e = parse(text).unwrap();
    let h = 1e-6;
    let at = |d: f64| {
        let mut q = env.q;
        q[k] += d;
        evaluate(&e, &Rotating { q, ..env.clone() }).unwrap()
    };
    (at(h) - at(-h)) / (2.0 * h)
}

#[test]
fn orient_gradients_match_finite_differences_in_every_system() {
    let env = env_at([0.4, 0.9, -0.6]);
    for (system, component) in all_components() {
        for j in [2, 0] {
            let text = format!("ORIENT({system}, {component}, 1, {j})");
            let e = parse(&text).unwrap();
            let d = evaluate_with_gradient(&e, &env).unwrap();
            assert_close(d.value(), evaluate(&e, &env).unwrap(), 1e-14, &text);
            let mut nonzero = false;
            for k in 0..3 {
                let fd = fd_gradient(&text, &env, k);
                let exact = d.derivative(k as u32);
                nonzero |= exact.abs() > 1e-3;
                assert!(
                    (fd - exact).abs() < 1e-7 * (1.0 + exact.abs()),
                    "{text}: d/dq{k} exact {exact}, finite difference {fd}"
                );
            }
            assert!(nonzero, "{text}: zero gradient (weak case)");
        }
    }
}

#[test]
fn orient_series_along_a_path_match_finite_differences() {
    let env = env_at([0.4, 0.9, -0.6]);
    let h = 1e-4;
    let along = |text: &str, t: f64| {
        let q: [f64; 3] =
            std::array::from_fn(|k| env.q[k] + env.qd[k] * t + 0.5 * env.qdd[k] * t * t);
        let e = parse(text).unwrap();
        evaluate(
            &e,
            &Rotating {
                q,
                time: env.time + t,
                ..env.clone()
            },
        )
        .unwrap()
    };
    let mut texts: Vec<String> = all_components()
        .into_iter()
        .map(|(s, c)| format!("ORIENT({s}, {c}, 1, 0)"))
        .collect();
    // Mixed with a measure and with explicit time.
    texts.push("ORIENT(27, 2, 1, 2) * DX(1) + TIME**2 * ORIENT(3, 1, 1, 2)".into());
    for text in texts {
        let e = parse(&text).unwrap();
        let [f, df, ddf] = evaluate_path_series(&e, &env).unwrap();
        let (fm, f0, fp) = (along(&text, -h), along(&text, 0.0), along(&text, h));
        assert_close(f, f0, 1e-14, &text);
        let fd1 = (fp - fm) / (2.0 * h);
        let fd2 = (fp - 2.0 * f0 + fm) / (h * h);
        assert!(
            (df - fd1).abs() < 1e-7 * (1.0 + df.abs()),
            "{text}: rate {df} vs {fd1}"
        );
        assert!(
            (ddf - fd2).abs() < 1e-5 * (1.0 + ddf.abs()),
            "{text}: second derivative {ddf} vs {fd2}"
        );
    }
}

/// Measures as given functions of time: DX(1) = sin t (series [sin, cos, −sin]).
struct Clock {
    t: f64,
    rate: f64,
}

impl Env for Clock {
    fn time(&self) -> f64 {
        self.t
    }
    fn time_rate(&self) -> f64 {
        self.rate
    }
    fn measure_series(&self, _: MeasureKind, _: MarkerArgs) -> Result<[f64; 3], EvalError> {
        let (s, c) = self.t.sin_cos();
        Ok([s, c, -s])
    }
}

#[test]
fn path_series_combine_measures_with_explicit_time() {
    // f = DX(1)·TIME² with DX(1) = sin t: f' = cos t·t² + 2t sin t,
    // f'' = −sin t·t² + 4t cos t + 2 sin t.
    let e = parse("DX(1) * TIME**2").unwrap();
    let t: f64 = 0.7;
    let [f, d1, d2] = evaluate_path_series(&e, &Clock { t, rate: 1.0 }).unwrap();
    let (s, c) = t.sin_cos();
    assert_close(f, s * t * t, 1e-15, "f");
    assert_close(d1, c * t * t + 2.0 * t * s, 1e-14, "f'");
    assert_close(d2, -s * t * t + 4.0 * t * c + 2.0 * s, 1e-14, "f''");
    // Frozen time: TIME is a constant, only the measure moves.
    let [_, d1, d2] = evaluate_path_series(&e, &Clock { t, rate: 0.0 }).unwrap();
    assert_close(d1, c * t * t, 1e-14, "f' (frozen time)");
    assert_close(d2, -s * t * t, 1e-14, "f'' (frozen time)");
}

#[test]
fn orient_errors() {
    let env = env_at([0.4, 0.9, -0.6]);
    let kind = |text: &str| {
        let e = parse(text).unwrap();
        evaluate(&e, &env).unwrap_err()
    };
    let err = kind("ORIENT(30, 1, 1)");
    assert_eq!(err.kind, EvalErrorKind::InvalidArgument);
    assert!(err.message.contains("1..29"), "{}", err.message);
    let err = kind("ORIENT(27, 5, 1)");
    assert_eq!(err.kind, EvalErrorKind::InvalidArgument);
    assert!(err.message.contains("1..4"), "{}", err.message);
    assert_eq!(
        kind("ORIENT(29, 0, 1)").kind,
        EvalErrorKind::InvalidArgument
    );
    assert_eq!(
        kind("ORIENT(1.5, 1, 1)").kind,
        EvalErrorKind::InvalidArgument
    );
    assert_eq!(
        kind("ORIENT(1, 1, 7)").kind,
        EvalErrorKind::UnknownReference
    );
    // Rodrigues parameters at a half turn about x.
    let half: M3 = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]];
    let err = orient(28, 1, &column_major(&half)).unwrap_err();
    assert_eq!(err.kind, EvalErrorKind::Domain);
    assert!(orient(27, 2, &column_major(&half)).unwrap().abs() > 0.999);
    // Too few / too many arguments are parse errors.
    assert!(parse("ORIENT(27, 1)").is_err());
    assert!(parse("ORIENT(27, 1, 2, 3, 4)").is_err());
    // Not in a MOTION function (time only), nor where no rotation is available.
    let e = parse("ORIENT(27, 1, 201, 101)").unwrap();
    let err = evaluate_time_series(&e, &TimeEnv::default()).unwrap_err();
    assert_eq!(err.kind, EvalErrorKind::NotTimeOnly);
    assert_eq!(
        evaluate(&e, &TimeEnv::default()).unwrap_err().kind,
        EvalErrorKind::Unavailable
    );
    assert!(e.uses_state());
    assert_eq!(e.to_string(), "ORIENT(27, 1, 201, 101)");
}

/// An environment whose ORIENT(…, 1, 0) rotation is the fixed matrix `r`, with `previous` the
/// 3-1-3 angles of the previous output.
struct Held {
    r: [f64; 9],
    previous: Option<[f64; 3]>,
}

impl Env for Held {
    fn time(&self) -> f64 {
        0.0
    }
    fn rotation(&self, _i: u32, _j: u32, _gradient: bool) -> Result<[Dual; 9], EvalError> {
        Ok(self.r.map(Dual::constant))
    }
    fn euler313_previous(&self, _i: u32, _j: u32) -> Option<[f64; 3]> {
        self.previous
    }
}

#[test]
fn psi_and_phi_near_theta_zero_continue_the_previous_split() {
    use linkage_expr::orient::euler313_continued;
    use std::f64::consts::PI;
    let deg = |a: [f64; 3]| a.map(f64::to_degrees);
    // Distance_Case03: the CM marker at REULER −90°, 0°, 0°, then tilted about ground x by
    // −2e-9 rad (θ ≈ 0, only ψ + φ = −90° fixed): Adams writes ψ = −90°, φ = 0° as at t = 0,
    // where the general formula gives ψ = 180°, φ = 90°.
    let tilt = -2e-9;
    let r = column_major(&mul(
        &elementary(0, tilt)[0],
        &elementary(2, (-90f64).to_radians())[0],
    ));
    let first = euler313_continued(&from_313_degrees([-90.0, 0.0, 0.0]), None);
    assert_close(
        deg(first)[0],
        -90.0,
        1e-12,
        "ψ at t = 0 (φ = 0 without a history)",
    );
    let next = deg(euler313_continued(&r, Some(first)));
    assert_close(next[0], -90.0, 1e-12, "ψ continued");
    assert_close(next[1], tilt.abs().to_degrees(), 1e-12, "θ");
    assert_close(next[2], 0.0, 1e-6, "φ continued");
    // Continued from another split, the same pose keeps its φ: ψ + φ is what the pose fixes.
    let other = deg(euler313_continued(&r, Some([0.5, 0.0, -0.5 - PI / 2.0])));
    assert_close(other[0], 0.5f64.to_degrees(), 1e-6, "ψ of the other split");
    assert_close(other[2], (-0.5 - PI / 2.0).to_degrees(), 1e-12, "φ kept");
    assert_close(other[0] + other[2], -90.0, 1e-6, "ψ + φ");
    // Near θ = π only ψ − φ is fixed: Rz(30°)·Rx(π − 1e-9)·Rz(−20°) continued from φ = −40°.
    let r = from_313_degrees([30.0, 180.0 - 1e-7, -20.0]);
    let a = deg(euler313_continued(
        &r,
        Some([10f64.to_radians(), PI, (-40f64).to_radians()]),
    ));
    assert_close(a[0], 10.0, 1e-6, "ψ at θ ≈ π");
    assert_close(a[2], -40.0, 1e-12, "φ kept at θ ≈ π");
    assert_close(a[0] - a[2], 50.0, 1e-6, "ψ − φ at θ ≈ π");
    // A spin about z at θ = 0 from a first output with φ = 0 (Adams' Distance_Case02 for its
    // first 0.13 s): ψ follows the spin, φ stays 0.
    let mut last = None;
    for spin in [0.0f64, -1e-3, -0.05, 120.0, 179.0, -179.0] {
        let a = euler313_continued(&from_313_degrees([spin, 0.0, 0.0]), last);
        assert_close(deg(a)[0], spin, 1e-9, "ψ follows the spin");
        assert_close(a[2], 0.0, 1e-15, "φ stays 0");
        last = Some(a);
    }
    // Away from the singular poses the split is the pose's own, whatever came before.
    let r = from_313_degrees([40.0, 1e-3, 20.0]);
    let a = deg(euler313_continued(&r, Some([-1.0, 0.0, 1.0])));
    assert_close(a[0], 40.0, 1e-6, "ψ");
    assert_close(a[2], 20.0, 1e-6, "φ");
    // ORIENT continues the same split, and the Euler parameters' sign follows it
    // (P0 = cos(θ/2)·cos((ψ + φ)/2) > 0 with ψ = −90°, φ = 0°; it is < 0 with 180°, 90°).
    let r = column_major(&mul(
        &elementary(0, tilt)[0],
        &elementary(2, (-90f64).to_radians())[0],
    ));
    let value =
        |text: &str, previous| evaluate(&parse(text).unwrap(), &Held { r, previous }).unwrap();
    let previous = Some([-PI / 2.0, 0.0, 0.0]);
    assert_close(
        value("ORIENT(11, 1, 1, 0)", previous).to_degrees(),
        -90.0,
        1e-9,
        "PSI",
    );
    assert_close(
        value("ORIENT(11, 3, 1, 0)", previous).to_degrees(),
        0.0,
        1e-6,
        "PHI",
    );
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert_close(value("ORIENT(27, 1, 1, 0)", previous), h, 1e-9, "P0");
    assert_close(value("ORIENT(27, 4, 1, 0)", previous), -h, 1e-9, "P3");
    // The parameters are the same orientation either way: only the sign is a convention.
    let unsplit = value("ORIENT(27, 1, 1, 0)", None);
    assert_close(unsplit.abs(), h, 1e-9, "|P0| without a history");
}
