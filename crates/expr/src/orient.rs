//! `ORIENT(system, component, i [, j])`: a component of the orientation of marker `i`
//! relative to marker `j` (default: ground) in one of 29 orientation systems.
//!
//! Everything is computed from the direction cosines `R = A_jᵀ·A_i` (the columns of `R` are
//! i's axes resolved in j's axes; `R[r][c] = x_j,r · x_i,c`), which the environment supplies
//! through [`crate::Env::rotation`] (values and gradients) or [`crate::Env::rotation_series`]
//! (series along a motion). The formulas below are differentiated exactly by the number type
//! of the evaluation, so ORIENT has exact first derivatives and second-order series like every
//! other function. Angles are in radians.
//!
//! | system | components | value |
//! |---|---|---|
//! | 1 … 12 | 1, 2, 3 | the first, second or third angle of a **body-fixed** Euler sequence: 1-2-3, 2-3-1, 3-1-2, 1-3-2, 2-1-3, 3-2-1, 1-2-1, 1-3-1, 2-1-2, 2-3-2, 3-1-3, 3-2-3 |
//! | 13 … 24 | 1, 2, 3 | the same twelve sequences **space-fixed** |
//! | 25 | 1, 2, 3 | the projection angles `AX`, `AY`, `AZ` |
//! | 26 | 1, 2, 3 | `YAW`, `PITCH`, `ROLL` (body 3-2-1) |
//! | 27 | 1 … 4 | the Euler parameters `P0` (scalar part), `P1`, `P2`, `P3` |
//! | 28 | 1, 2, 3 | the Rodrigues parameters `P1/P0`, `P2/P0`, `P3/P0` |
//! | 29 | 1 … 9 | direction cosines: 1-3 of `x_i` with `x_j`, `y_j`, `z_j`; 4-6 of `y_i`; 7-9 of `z_i` (column-major `R`) |
//!
//! Sources: the Adams Solver (C++) ORIENT page (systems 1-11 as quoted in the repository's
//! research notes) and a third-party re-implementation of the Adams function set that lists
//! the whole table (12-29, including the direction-cosine order); the Euler-parameter sign was
//! checked against Adams' own output (next paragraph).
//!
//! **Conventions.**
//! * Body-fixed sequence `(a, b, c)` with angles `(θ1, θ2, θ3)`: `R = R_a(θ1)·R_b(θ2)·R_c(θ3)`.
//!   Space-fixed sequence `(a, b, c)`: rotations about the fixed axes a, then b, then c, so
//!   `R = R_c(θ3)·R_b(θ2)·R_a(θ1)`, i.e. the body-fixed sequence `(c, b, a)` read backwards.
//! * Ranges: the first and third angles in (−π, π]; the middle angle in [−π/2, π/2] for
//!   sequences of three different axes (Tait–Bryan) and in [0, π] for repeated-axis (proper
//!   Euler) sequences, as `PSI`/`THETA`/`PHI` (system 11) and `YAW`/`PITCH`/`ROLL`
//!   (system 6). At a singular pose (middle angle ±π/2, resp. 0 or π) the third angle is set
//!   to 0 and the first carries the whole rotation about its axis; derivatives there are those
//!   of that branch (the angles are not differentiable at such a pose).
//! * Euler parameters: `P = (cos(α/2), sin(α/2)·u)` for the rotation by α about the unit
//!   axis u taking j's axes to i's. `P` and `−P` are the same orientation; the sign is
//!   Adams' own: that of `P0 = cos(θ/2)·cos((ψ+φ)/2)`, `P1 = sin(θ/2)·cos((ψ−φ)/2)`,
//!   `P2 = sin(θ/2)·sin((ψ−φ)/2)`, `P3 = cos(θ/2)·sin((ψ+φ)/2)` with the body 3-1-3 angles
//!   (ψ, θ, φ) of system 11 in their ranges above (the Adams .req files of the Chrono test
//!   models match this to their 6 printed digits, sign flips included). The value is
//!   computed with Shepperd's method (smooth in R) and given that sign.
//! * Rodrigues parameters are undefined for a rotation by 180° (`P0 = 0`): a domain error.

use crate::error::EvalError;
use crate::functions;
use crate::num::Num;

/// The body 3-1-3 sequence (system 11: PSI, THETA, PHI).
const BODY_313: [usize; 3] = [2, 0, 2];

/// Below this, a pair of direction cosines that fixes an Euler angle is taken as zero (a
/// singular pose of the sequence).
const SINGULAR: f64 = 1e-12;

/// The orientation systems of `ORIENT`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrientSystem {
    /// Body-fixed Euler sequence (axes 0, 1, 2 = x, y, z).
    BodyFixed([usize; 3]),
    /// Space-fixed Euler sequence.
    SpaceFixed([usize; 3]),
    /// `AX`, `AY`, `AZ`.
    Projection,
    /// `YAW`, `PITCH`, `ROLL`.
    YawPitchRoll,
    /// `P0`, `P1`, `P2`, `P3`.
    EulerParameters,
    /// `P1/P0`, `P2/P0`, `P3/P0`.
    Rodrigues,
    /// The nine entries of `R`, column-major.
    DirectionCosines,
}

/// The twelve sequences of systems 1-12 (and 13-24), 0-based axes.
const SEQUENCES: [[usize; 3]; 12] = [
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

impl OrientSystem {
    /// The system with Adams code `code` (1..=29).
    pub fn from_code(code: u32) -> Option<OrientSystem> {
        let k = usize::try_from(code).ok()?;
        Some(match k {
            1..=12 => OrientSystem::BodyFixed(SEQUENCES[k - 1]),
            13..=24 => OrientSystem::SpaceFixed(SEQUENCES[k - 13]),
            25 => OrientSystem::Projection,
            26 => OrientSystem::YawPitchRoll,
            27 => OrientSystem::EulerParameters,
            28 => OrientSystem::Rodrigues,
            29 => OrientSystem::DirectionCosines,
            _ => return None,
        })
    }

    /// How many components the system has (3, 4 or 9).
    pub fn components(self) -> u32 {
        match self {
            OrientSystem::EulerParameters => 4,
            OrientSystem::DirectionCosines => 9,
            _ => 3,
        }
    }
}

/// One `ORIENT(system, component, …)` value: the system and the 0-based component.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct OrientValue {
    system: OrientSystem,
    component: usize,
}

impl OrientValue {
    /// Checks the codes of `ORIENT(system, component, …)`.
    pub(crate) fn new(system: u32, component: u32) -> Result<OrientValue, EvalError> {
        let Some(sys) = OrientSystem::from_code(system) else {
            return Err(EvalError::invalid_argument(format!(
                "ORIENT: the orientation system (argument 1) must be 1..29, got {system}"
            )));
        };
        let n = sys.components();
        if component == 0 || component > n {
            return Err(EvalError::invalid_argument(format!(
                "ORIENT: orientation system {system} has components 1..{n}, got {component}"
            )));
        }
        Ok(OrientValue {
            system: sys,
            component: (component - 1) as usize,
        })
    }

    /// The value from the direction cosines `r` (column-major); `previous` the body 3-1-3
    /// angles of the same markers at the previous output, which the 3-1-3 angles and the
    /// Euler parameters' sign continue at θ ≈ 0 ([`euler313_continued`]).
    pub(crate) fn evaluate<N: Num>(
        &self,
        r: &[N; 9],
        previous: Option<[f64; 3]>,
    ) -> Result<N, EvalError> {
        let m = Matrix(r);
        let k = self.component;
        match self.system {
            OrientSystem::BodyFixed(seq) if seq == BODY_313 && k != 1 => {
                let values: [f64; 9] = std::array::from_fn(|i| r[i].val());
                if values[6].hypot(values[7]) < EULER_SPLIT_SINE {
                    // ψ and φ of a split, constant (not differentiable at this pose).
                    Ok(N::cst(euler313_continued(&values, previous)[k]))
                } else {
                    Ok(body_fixed_angle(&m, seq, k))
                }
            }
            OrientSystem::BodyFixed(seq) => Ok(body_fixed_angle(&m, seq, k)),
            OrientSystem::SpaceFixed([a, b, c]) => Ok(body_fixed_angle(&m, [c, b, a], 2 - k)),
            OrientSystem::Projection => {
                // AX = atan2(−z_i·y_j, z_i·z_j), AY = atan2(z_i·x_j, z_i·z_j),
                // AZ = atan2(x_i·y_j, x_i·x_j).
                Ok(match k {
                    0 => atan2(&m.at(1, 2).negate(), m.at(2, 2)),
                    1 => atan2(m.at(0, 2), m.at(2, 2)),
                    _ => atan2(m.at(1, 0), m.at(0, 0)),
                })
            }
            OrientSystem::YawPitchRoll => Ok(body_fixed_angle(&m, [2, 1, 0], k)),
            OrientSystem::EulerParameters => Ok(euler_parameters(&m, previous)[k].clone()),
            OrientSystem::Rodrigues => {
                let p = euler_parameters(&m, previous);
                if p[0].val() == 0.0 {
                    return Err(EvalError::domain(
                        "ORIENT: Rodrigues parameters are undefined for a rotation of 180 degrees \
                         (P0 = 0)",
                    ));
                }
                Ok(p[k + 1].over(&p[0]))
            }
            OrientSystem::DirectionCosines => Ok(r[k].clone()),
        }
    }
}

/// Direction cosines with `(row, column)` access.
struct Matrix<'a, N>(&'a [N; 9]);

impl<N: Num> Matrix<'_, N> {
    fn at(&self, row: usize, col: usize) -> &N {
        &self.0[3 * col + row]
    }
    fn value(&self, row: usize, col: usize) -> f64 {
        self.at(row, col).val()
    }
}

/// `atan2(y, x)` with its exact derivatives; 0 (a constant) when both are zero.
fn atan2<N: Num>(y: &N, x: &N) -> N {
    if y.val() == 0.0 && x.val() == 0.0 {
        return N::cst(0.0);
    }
    functions::atan2(y, x).unwrap_or_else(|_| N::cst(0.0))
}

/// `√(x² + y²)` (a constant 0 at the origin, where it is not differentiable).
fn hypot<N: Num>(x: &N, y: &N) -> N {
    let v = x.val().hypot(y.val());
    if v == 0.0 {
        return N::cst(0.0);
    }
    let sq = x.times(x).plus(&y.times(y));
    let s = sq.val();
    sq.chain(v, 0.5 / v, -0.25 / (v * s))
}

/// +1 if `(i, j, k)` is a cyclic permutation of (0, 1, 2), −1 otherwise.
fn parity(i: usize, j: usize, k: usize) -> f64 {
    if (i + 1) % 3 == j && (j + 1) % 3 == k {
        1.0
    } else {
        -1.0
    }
}

/// Angle `k` (0, 1, 2) of the body-fixed sequence `seq`: `R = R_a(θ1)·R_b(θ2)·R_c(θ3)`.
///
/// With ε the parity of the axes `(a, b, e)` (e the axis not among a, b for a repeated-axis
/// sequence, e = c otherwise):
/// * three different axes: `θ2 = atan2(ε R[a][c], √(R[a][a]² + R[a][b]²))`,
///   `θ1 = atan2(−ε R[b][c], R[c][c])`, `θ3 = atan2(−ε R[a][b], R[a][a])`;
/// * repeated axis (c = a): `θ2 = atan2(√(R[b][a]² + R[e][a]²), R[a][a])`,
///   `θ1 = atan2(R[b][a], −ε R[e][a])`, `θ3 = atan2(R[a][b], ε R[a][e])`;
/// * singular pose (the pair fixing θ1 is zero): `θ3 = 0`, `θ1 = atan2(ε R[e][b], R[b][b])`.
fn body_fixed_angle<N: Num>(m: &Matrix<'_, N>, [a, b, c]: [usize; 3], k: usize) -> N {
    let proper = a == c;
    let e = if proper { 3 - a - b } else { c };
    let eps = parity(a, b, e);
    let singular = if proper {
        m.value(b, a).hypot(m.value(e, a)) < SINGULAR
            || m.value(a, b).hypot(m.value(a, e)) < SINGULAR
    } else {
        m.value(b, c).hypot(m.value(c, c)) < SINGULAR
            || m.value(a, b).hypot(m.value(a, a)) < SINGULAR
    };
    if singular {
        return match k {
            0 => atan2(&m.at(e, b).scale(eps), m.at(b, b)),
            1 => {
                // ±π/2 (Tait–Bryan) or 0, π (proper Euler), as a constant.
                let v = if proper {
                    m.value(b, a).hypot(m.value(e, a)).atan2(m.value(a, a))
                } else {
                    (eps * m.value(a, c)).clamp(-1.0, 1.0).asin()
                };
                N::cst(v)
            }
            _ => N::cst(0.0),
        };
    }
    if proper {
        match k {
            0 => atan2(m.at(b, a), &m.at(e, a).scale(-eps)),
            1 => atan2(&hypot(m.at(b, a), m.at(e, a)), m.at(a, a)),
            _ => atan2(m.at(a, b), &m.at(a, e).scale(eps)),
        }
    } else {
        match k {
            0 => atan2(&m.at(b, c).scale(-eps), m.at(c, c)),
            1 => atan2(&m.at(a, c).scale(eps), &hypot(m.at(a, a), m.at(a, b))),
            _ => atan2(&m.at(a, b).scale(-eps), m.at(a, a)),
        }
    }
}

/// Angles of the Euler-parameter sign rule closer than this (radians) to −π are taken as +π.
const ANGLE_WRAP_SLACK: f64 = 1e-9;

/// Euler parameters `[P0, P1, P2, P3]` of `R` with Adams' sign (module docs), the 3-1-3
/// angles of the sign rule continued from `previous` ([`euler313_continued`]).
fn euler_parameters<N: Num>(m: &Matrix<'_, N>, previous: Option<[f64; 3]>) -> [N; 4] {
    let d = [m.at(0, 0), m.at(1, 1), m.at(2, 2)];
    let trace = d[0].plus(d[1]).plus(d[2]);
    // Shepperd: start from the largest of 4·P0², 4·P1², 4·P2², 4·P3² (1 + trace, 1 + 2R00 −
    // trace, …), then the others from the off-diagonal sums and differences:
    // R21 − R12 = 4 P0 P1, R02 − R20 = 4 P0 P2, R10 − R01 = 4 P0 P3,
    // R01 + R10 = 4 P1 P2, R02 + R20 = 4 P1 P3, R12 + R21 = 4 P2 P3.
    let diff = |r: usize, c: usize| m.at(r, c).minus(m.at(c, r));
    let sum = |r: usize, c: usize| m.at(r, c).plus(m.at(c, r));
    let squares = [
        trace.add_cst(1.0),
        d[0].scale(2.0).minus(&trace).add_cst(1.0),
        d[1].scale(2.0).minus(&trace).add_cst(1.0),
        d[2].scale(2.0).minus(&trace).add_cst(1.0),
    ];
    let big = (0..4)
        .max_by(|&x, &y| squares[x].val().total_cmp(&squares[y].val()))
        .unwrap_or(0);
    let s = squares[big].val().max(0.0).sqrt();
    // p_big = √(square)/2; the others are (4 p_big p_other)/(4 p_big).
    let p_big = if s > 0.0 {
        squares[big].chain(0.5 * s, 0.25 / s, -0.125 / (s * s * s))
    } else {
        N::cst(0.0)
    };
    let four_p = p_big.scale(4.0);
    let other = |x: N| {
        if four_p.val() == 0.0 {
            N::cst(0.0)
        } else {
            x.over(&four_p)
        }
    };
    let mut p: [N; 4] = match big {
        0 => [
            p_big.clone(),
            other(diff(2, 1)),
            other(diff(0, 2)),
            other(diff(1, 0)),
        ],
        1 => [
            other(diff(2, 1)),
            p_big.clone(),
            other(sum(0, 1)),
            other(sum(0, 2)),
        ],
        2 => [
            other(diff(0, 2)),
            other(sum(0, 1)),
            p_big.clone(),
            other(sum(1, 2)),
        ],
        _ => [
            other(diff(1, 0)),
            other(sum(0, 2)),
            other(sum(1, 2)),
            p_big.clone(),
        ],
    };
    // Adams' sign: that of the parameters written with the body 3-1-3 angles.
    let values: [f64; 9] = std::array::from_fn(|i| m.0[i].val());
    // Angles in (−π, π]: a rounding-level negative numerator must not turn +π into −π, which
    // would flip the sign (Adams prints ψ = 180, not −180, for such poses).
    let lift = |a: f64| {
        if a < -std::f64::consts::PI + ANGLE_WRAP_SLACK {
            a + 2.0 * std::f64::consts::PI
        } else {
            a
        }
    };
    let [psi, theta, phi] = euler313_continued(&values, previous);
    let (psi, phi) = (lift(psi), lift(phi));
    let (sh, ch) = (0.5 * theta).sin_cos();
    let (sp, cp) = (0.5 * (psi + phi)).sin_cos();
    let (sm, cm) = (0.5 * (psi - phi)).sin_cos();
    let adams = [ch * cp, sh * cm, sh * sm, ch * sp];
    let dot: f64 = adams.iter().zip(&p).map(|(a, q)| a * q.val()).sum();
    if dot < 0.0 {
        for x in &mut p {
            *x = x.negate();
        }
    }
    p
}

/// `ORIENT(system, component, …)` of the direction cosines `r` (column-major, as
/// [`crate::Env::rotation`]), as a plain value.
pub fn orient(system: u32, component: u32, r: &[f64; 9]) -> Result<f64, EvalError> {
    OrientValue::new(system, component)?.evaluate(r, None)
}

/// `sin θ` below which the body 3-1-3 angles of an output are taken at θ ≈ 0 (or π), where
/// only `ψ + φ` (resp. `ψ − φ`) is determined by the pose and the split between ψ and φ is
/// continued from the previous output ([`euler313_continued`]).
///
/// Chosen between two Adams runs of the Chrono test models: Adams splits a pose with
/// θ = 2.2e-5 rad by the general formula (Distance_Case02 at t = 0.14 s: ψ = −90.04°,
/// θ = 0.00124°, φ = 89.97°), and keeps the split of its previous output for a body whose θ
/// is still at rounding level after a hundredth of a second (Distance_Case03 at t = 0.01 s:
/// ψ = −90°, φ = 0° as at t = 0, where the general formula gives ψ = 180°, φ = 90° for
/// θ ~ 1e-9 rad).
pub const EULER_SPLIT_SINE: f64 = 1e-6;

/// The body 3-1-3 angles `[ψ, θ, φ]` (radians; ψ, φ in (−π, π], θ in [0, π]) of the direction
/// cosines `r` (column-major, `R = Rz(ψ)·Rx(θ)·Rz(φ)`), continued from the angles `previous`
/// of the same pair of frames at the previous output.
///
/// Away from θ = 0 and π (`sin θ ≥` [`EULER_SPLIT_SINE`]) the angles are unique and given by
/// the general formula. Nearer, only `σ = ψ + φ` (θ ≈ 0) or `δ = ψ − φ` (θ ≈ π) is
/// determined, exactly, by `σ = atan2(R21 − R12, R11 + R22)` and
/// `δ = atan2(R21 + R12, R11 − R22)` (both numerators and denominators carry the factor
/// `1 ± cos θ`); φ then keeps its previous value and ψ takes the rest, so that ψ, φ and the
/// Euler parameters written with them do not jump between outputs. Without a previous output
/// φ = 0 and ψ carries the whole rotation, as at an exactly singular pose. This is what
/// Adams writes: in its Distance_Case02 run the rod spins about z at θ = 0 for 0.13 s with
/// φ = 0 and ψ following the spin, and Distance_Case03 keeps ψ = −90°, φ = 0° of its first
/// output. The pose `Rz(ψ)·Rx(θ)·Rz(φ)` of the continued angles differs from `r` by less
/// than θ (< 1e-6 rad).
pub fn euler313_continued(r: &[f64; 9], previous: Option<[f64; 3]>) -> [f64; 3] {
    let at = |row: usize, col: usize| r[3 * col + row];
    let s = at(0, 2).hypot(at(1, 2));
    let theta = s.atan2(at(2, 2));
    if s >= EULER_SPLIT_SINE {
        let psi = at(0, 2).atan2(-at(1, 2));
        let phi = at(2, 0).atan2(at(2, 1));
        return [psi, theta, phi];
    }
    let wrap = |a: f64| {
        let w = a - std::f64::consts::TAU * (a / std::f64::consts::TAU).round();
        if w <= -std::f64::consts::PI + ANGLE_WRAP_SLACK {
            w + std::f64::consts::TAU
        } else {
            w
        }
    };
    let phi = previous.map_or(0.0, |p| p[2]);
    if at(2, 2) > 0.0 {
        let sigma = (at(1, 0) - at(0, 1)).atan2(at(0, 0) + at(1, 1));
        [wrap(sigma - phi), theta, wrap(phi)]
    } else {
        let delta = (at(1, 0) + at(0, 1)).atan2(at(0, 0) - at(1, 1));
        [wrap(delta + phi), theta, wrap(phi)]
    }
}
