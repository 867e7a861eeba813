//! Displacement initial conditions: least-change assembly (DESIGN §5, ADM-REFERENCE §8.1).
//!
//! Minimise `½ eᵀ W e` (e: tangent displacement of every part from the input configuration,
//! `W = diag(1/L², 1/L², 1/L², 1, 1, 1)`) subject to the independent constraint rows, the
//! motions at the start time, and the hard initial conditions (parts' EXACT coordinates,
//! joints' IC displacements). Newton on the KKT system
//!
//! ```text
//! [ W   Jᵀ ] [δ]   [ −W e ]
//! [ J  −μI ] [λ] = [ −Φ   ]
//! ```
//!
//! (assembled and factorised by [`crate::linalg::kkt::SaddlePoint`]) with the step limited
//! per iteration (TLIMIT, ALIMIT), the Jacobian refreshed by PATTERN,
//! backtracking when the residual grows, and `μ` (Levenberg–Marquardt) raised when a step fails.
//! It stops when the constraints hold to ERROR *and* the last full step was within ERROR: the
//! first point where Φ = 0 is not yet the least change (on the exploded four-bar it leaves the
//! crank 0.07° away from it); from there the steps move along the constraints to the minimum,
//! with `μ` at least `ASSEMBLY_POLISH_REGULARISATION` since rows independent at the input may
//! be dependent there. MAXIT bounds both phases; a run out of iterations after reaching the
//! constraints keeps its last feasible point.

use crate::constraints::drivers::Drivers;
use crate::constraints::rank::{greedy_rank, RankSettings, SparseRows};
use crate::constraints::rows::{BodyDir, BodyFrame, BodyPoint, EulerSeq, Quantity, RowGradient};
use crate::constraints::system::{wrap_angle, RowUnit, System};
use crate::linalg::kkt::{scaled_row, SaddlePoint};
use crate::linalg::linear::SparseLu;
use crate::state::State;
use crate::tolerances::{
    ASSEMBLY_BACKTRACK_SLACK, ASSEMBLY_POLISH_REGULARISATION, ASSEMBLY_ROUNDING,
    ASSEMBLY_SATISFIED, ASSEMBLY_SINGULAR_REGULARISATION, ASSEMBLY_STEP_REGULARISATION,
};
use glam::{DMat3, DVec3};
use linkage_adm::ExactCoord;
use linkage_model::settings::refresh_at;
use linkage_model::{Body, ConstraintKind, JointInitial, Model};

/// What a hard equation holds. Hard rows are not rows of the [`System`]: EXACT conditions
/// belong to parts, while a system row's `element` indexes the model's constraints (reports
/// read `model.constraints[row.element]`), so they keep their own type; this names them
/// without comparing label strings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HardKind {
    /// One of the three dot products holding a part's orientation when all of PSI, THETA, PHI
    /// are EXACT: `Zb·X0`, `Zb·Y0`, `Xb·Y0` (0, 1, 2).
    ExactOrientation(usize),
    /// One EXACT coordinate of a part.
    Exact(ExactCoord),
    /// A joint's initial rotation (IC, ICROT).
    IcRotation,
    /// A joint's initial translation (IC, ICTRAN).
    IcTranslation,
    /// A joint coordinate driven to a target by the explanations' moves.
    Driven,
}

impl HardKind {
    /// The label reports print.
    pub fn label(self) -> &'static str {
        match self {
            HardKind::ExactOrientation(k) => [
                "EXACT orientation (Zb·X0)",
                "EXACT orientation (Zb·Y0)",
                "EXACT orientation (Xb·Y0)",
            ][k.min(2)],
            HardKind::Exact(c) => match c {
                ExactCoord::X => "EXACT X",
                ExactCoord::Y => "EXACT Y",
                ExactCoord::Z => "EXACT Z",
                ExactCoord::Psi => "EXACT PSI",
                ExactCoord::Theta => "EXACT THETA",
                ExactCoord::Phi => "EXACT PHI",
            },
            HardKind::IcRotation => "IC rotation",
            HardKind::IcTranslation => "IC translation",
            HardKind::Driven => "explain: driven",
        }
    }
}

/// A hard equation of the initial conditions: `Q(q) = target`.
#[derive(Clone, Debug, PartialEq)]
pub struct HardRow {
    /// Element the condition belongs to (`PART_2`, `JOINT_1`).
    pub name: String,
    pub kind: HardKind,
    /// `kind.label()`: `EXACT X`, `IC rotation`, …
    pub label: String,
    pub quantity: Quantity,
    pub target: f64,
    pub unit: RowUnit,
}

impl HardRow {
    pub fn residual(&self, s: &State) -> f64 {
        let v = self.quantity.value(s) - self.target;
        if self.quantity.is_angle() {
            wrap_angle(v)
        } else {
            v
        }
    }
}

fn joint_frames(model: &Model, c: usize) -> Option<(BodyFrame, BodyFrame)> {
    let (i, j) = model.constraints[c].markers()?;
    let f = |m: usize| {
        let mk = &model.markers[m];
        BodyFrame {
            body: mk.body,
            p_b: mk.p_bm,
            r_b: mk.r_bm,
        }
    };
    Some((f(i), f(j)))
}

/// The hard rows of a model: EXACT part coordinates (held at their input values) and joint
/// initial displacements (IC, ICTRAN, ICROT).
pub fn hard_rows(model: &Model) -> Vec<HardRow> {
    let input = State::input(model);
    let mut out = Vec::new();
    for (k, p) in model.parts.iter().enumerate() {
        let all_angles = [ExactCoord::Psi, ExactCoord::Theta, ExactCoord::Phi]
            .iter()
            .all(|c| p.exact.contains(c));
        if all_angles {
            // Hold the orientation itself (Euler angles are singular at θ = 0): z·x₀, z·y₀, x·y₀.
            let r0 = p.r_gb;
            let body = |v: DVec3| BodyDir {
                body: Body::Part(k),
                v_b: v,
            };
            let fixed = |v: DVec3| BodyDir {
                body: Body::Ground,
                v_b: v,
            };
            for (i, (a, b)) in [
                (body(DVec3::Z), fixed(r0.x_axis)),
                (body(DVec3::Z), fixed(r0.y_axis)),
                (body(DVec3::X), fixed(r0.y_axis)),
            ]
            .into_iter()
            .enumerate()
            {
                let kind = HardKind::ExactOrientation(i);
                out.push(HardRow {
                    name: p.origin.name.clone(),
                    kind,
                    label: kind.label().into(),
                    quantity: Quantity::Dot(a, b),
                    target: 0.0,
                    unit: RowUnit::Direction,
                });
            }
        }
        let bcs = BodyFrame {
            body: Body::Part(k),
            p_b: p.p_b_bcs,
            r_b: DMat3::IDENTITY,
        };
        let ground = BodyFrame {
            body: Body::Ground,
            p_b: DVec3::ZERO,
            r_b: DMat3::IDENTITY,
        };
        for e in &p.exact {
            if all_angles && matches!(e, ExactCoord::Psi | ExactCoord::Theta | ExactCoord::Phi) {
                continue;
            }
            let (quantity, unit) = match e {
                ExactCoord::X | ExactCoord::Y | ExactCoord::Z => {
                    let axis = match e {
                        ExactCoord::X => 0,
                        ExactCoord::Y => 1,
                        _ => 2,
                    };
                    let q = Quantity::Proj {
                        i: BodyPoint {
                            body: Body::Part(k),
                            p_b: p.p_b_bcs,
                        },
                        j: BodyPoint {
                            body: Body::Ground,
                            p_b: DVec3::ZERO,
                        },
                        e: BodyDir {
                            body: Body::Ground,
                            v_b: DMat3::IDENTITY.col(axis),
                        },
                    };
                    (q, RowUnit::Length)
                }
                ExactCoord::Psi | ExactCoord::Theta | ExactCoord::Phi => {
                    let k3 = match e {
                        ExactCoord::Psi => 0,
                        ExactCoord::Theta => 1,
                        _ => 2,
                    };
                    let q = Quantity::euler(bcs, ground, EulerSeq::Body313, k3);
                    (q, RowUnit::Angle)
                }
            };
            let target = quantity.value(&input);
            let kind = HardKind::Exact(*e);
            out.push(HardRow {
                name: p.origin.name.clone(),
                kind,
                label: kind.label().into(),
                quantity,
                target,
                unit,
            });
        }
    }
    for (c, con) in model.constraints.iter().enumerate() {
        let ConstraintKind::Joint { initial, .. } = &con.kind else {
            continue;
        };
        let JointInitial {
            translation,
            rotation,
            ..
        } = initial;
        let Some((fi, fj)) = joint_frames(model, c) else {
            continue;
        };
        if let Some(d) = rotation.0 {
            let q = Quantity::Angle {
                x: fi.axis(0),
                x_ref: fj.axis(0),
                y_ref: fj.axis(1),
            };
            out.push(HardRow {
                name: con.origin.name.clone(),
                kind: HardKind::IcRotation,
                label: HardKind::IcRotation.label().into(),
                quantity: q,
                target: d,
                unit: RowUnit::Angle,
            });
        }
        if let Some(d) = translation.0 {
            let q = Quantity::Proj {
                i: fi.origin(),
                j: fj.origin(),
                e: fj.axis(2),
            };
            out.push(HardRow {
                name: con.origin.name.clone(),
                kind: HardKind::IcTranslation,
                label: HardKind::IcTranslation.label().into(),
                quantity: q,
                target: d,
                unit: RowUnit::Length,
            });
        }
    }
    out
}

/// One equation the assembly enforces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Equation {
    /// A constraint row of the system.
    Row(usize),
    /// A hard initial condition (index into the hard rows).
    Hard(usize),
}

/// Result of the displacement IC.
#[derive(Clone, Debug)]
pub struct Assembly {
    pub state: State,
    pub converged: bool,
    pub iterations: usize,
    /// Largest remaining residual (length units or radians).
    pub max_residual: f64,
    /// The enforced equations with their final residuals, largest first.
    pub residuals: Vec<(Equation, f64)>,
}

/// Tangent displacement of part k from the reference configuration.
fn displacement(s: &State, r: &State, k: usize) -> (DVec3, DVec3) {
    let a = s.poses[k];
    let b = r.poses[k];
    (
        a.p - b.p,
        linkage_model::frames::log_so3(&(a.r * b.r.transpose())),
    )
}

struct Problem<'a> {
    sys: &'a System,
    rows: Vec<(usize, f64)>,
    hard: &'a [HardRow],
}

impl Problem<'_> {
    fn m(&self) -> usize {
        self.rows.len() + self.hard.len()
    }
    fn residual(&self, s: &State, out: &mut Vec<f64>) {
        out.clear();
        for &(r, drive) in &self.rows {
            out.push(self.sys.residual(r, s, drive));
        }
        for h in self.hard {
            out.push(h.residual(s));
        }
    }
    fn jacobian(&self, s: &State, g: &mut RowGradient, mut put: impl FnMut(usize, &RowGradient)) {
        for (k, &(r, _)) in self.rows.iter().enumerate() {
            self.sys.gradient(r, s, g);
            put(k, g);
        }
        for (k, h) in self.hard.iter().enumerate() {
            g.clear();
            h.quantity.gradient(s, 1.0, g);
            put(self.rows.len() + k, g);
        }
    }
    fn equation(&self, k: usize) -> Equation {
        if k < self.rows.len() {
            Equation::Row(self.rows[k].0)
        } else {
            Equation::Hard(k - self.rows.len())
        }
    }
}

/// Least-change assembly of the rows `rows` (constraint rows of `sys`; motion rows whose
/// function cannot be evaluated at the start time are left free) and the hard rows, starting
/// from `start`, pulling towards `reference`, with the model's IC settings.
pub fn assemble(
    model: &Model,
    sys: &System,
    rows: &[usize],
    hard: &[HardRow],
    drivers: &dyn Drivers,
    start: &State,
    reference: &State,
) -> Assembly {
    let settings = &model.ic;
    let n = model.parts.len();
    let length = model.characteristic_length;
    let mut used = Vec::with_capacity(rows.len());
    for &r in rows {
        let row = &sys.rows[r];
        if row.driven {
            if let Some(f) = drivers.value(row.element, start.time) {
                used.push((r, f));
            }
        } else {
            used.push((r, 0.0));
        }
    }
    let (hard_kept, used) = independent_equations(sys, used, hard, start, length);
    let hard_owned: Vec<HardRow> = hard_kept.iter().map(|&h| hard[h].clone()).collect();
    let prob = Problem {
        sys,
        rows: used,
        hard: &hard_owned,
    };
    let m = prob.m();
    let dim = 6 * n + m;
    let w_t = 1.0 / (length * length);
    let tol_len = settings.error.max(ASSEMBLY_ROUNDING * length);
    let tol_ang = settings.error.max(ASSEMBLY_ROUNDING);
    let is_len = |k: usize| -> bool {
        match prob.equation(k) {
            Equation::Row(r) => matches!(sys.rows[r].unit, RowUnit::Length | RowUnit::Mixed),
            Equation::Hard(h) => hard_owned[h].unit == RowUnit::Length,
        }
    };
    let scaled_max = |phi: &[f64]| -> f64 {
        phi.iter()
            .enumerate()
            .map(|(k, v)| {
                if is_len(k) {
                    v.abs() / tol_len
                } else {
                    v.abs() / tol_ang
                }
            })
            .fold(0.0, f64::max)
    };

    let mut s = start.clone();
    let mut phi = Vec::with_capacity(m);
    prob.residual(&s, &mut phi);
    let mut g = RowGradient::default();
    let mut lu: Option<SparseLu> = None;
    let mut mu = 0.0;
    let mut iterations = 0;
    // Feasible: every equation within ERROR. Stationary: the last full KKT step was within
    // ERROR, so the point is the least change to that precision. A feasible input is its own
    // least change (e = 0). Once feasible, the iteration goes on until it is stationary too
    // (the minimum of ½ eᵀ W e on Φ = 0, not merely the first point where Φ = 0), within MAXIT;
    // if the budget ends between a step and its correction, the last feasible point is kept.
    // From the first feasible point on, the multipliers are regularised
    // (ASSEMBLY_POLISH_REGULARISATION): rows may be dependent there.
    let mut feasible = scaled_max(&phi) <= 1.0;
    let mut stationary = feasible;
    let mut last_feasible: Option<State> = None;
    let mut kkt = SaddlePoint::new(6 * n, m);
    while !(feasible && stationary) && iterations < settings.maxit {
        let refresh = lu.is_none() || refresh_at(&settings.pattern, iterations);
        if refresh {
            kkt.clear();
            kkt.add_coordinate_weights(|c| if c % 6 < 3 { w_t } else { 1.0 });
            prob.jacobian(&s, &mut g, |row, grad| kkt.add_constraint_row(row, grad));
            kkt.add_multiplier_regularisation(mu);
            lu = kkt.factor().ok();
        }
        let Some(f) = &lu else { break };
        let mut rhs = vec![0.0; dim];
        for k in 0..n {
            let (dx, dth) = displacement(&s, reference, k);
            for c in 0..3 {
                rhs[6 * k + c] = -w_t * dx[c];
                rhs[6 * k + 3 + c] = -dth[c];
            }
        }
        for (k, v) in phi.iter().enumerate() {
            rhs[6 * n + k] = -v;
        }
        if f.solve(&mut rhs).is_err() {
            // Singular: regularise and retry with a fresh factorisation.
            mu = if mu == 0.0 {
                ASSEMBLY_SINGULAR_REGULARISATION
            } else {
                mu * 100.0
            };
            lu = None;
            iterations += 1;
            continue;
        }
        // Step limits, and the size of the full step against ERROR.
        let mut scale: f64 = 1.0;
        let mut step_size: f64 = 0.0;
        for k in 0..n {
            let dx = DVec3::new(rhs[6 * k], rhs[6 * k + 1], rhs[6 * k + 2]).length();
            let dth = DVec3::new(rhs[6 * k + 3], rhs[6 * k + 4], rhs[6 * k + 5]).length();
            step_size = step_size.max(dx / tol_len).max(dth / tol_ang);
            if dx > settings.tlimit {
                scale = scale.min(settings.tlimit / dx);
            }
            if dth > settings.alimit {
                scale = scale.min(settings.alimit / dth);
            }
        }
        // Backtracking on the residual norm.
        let norm = |p: &[f64]| {
            p.iter()
                .enumerate()
                .map(|(k, v)| {
                    if is_len(k) {
                        (v / length).powi(2)
                    } else {
                        v * v
                    }
                })
                .sum::<f64>()
        };
        let before = norm(&phi);
        let before_step = s.clone();
        let mut accepted = false;
        let mut trial_phi = Vec::with_capacity(m);
        for _ in 0..8 {
            let mut t = s.clone();
            for k in 0..n {
                let dx = DVec3::new(rhs[6 * k], rhs[6 * k + 1], rhs[6 * k + 2]) * scale;
                let dth = DVec3::new(rhs[6 * k + 3], rhs[6 * k + 4], rhs[6 * k + 5]) * scale;
                t.increment(k, dx, dth);
            }
            prob.residual(&t, &mut trial_phi);
            // From a feasible point the step moves along the constraints towards the least
            // change; the residual it leaves is of second order in the step and the next
            // step corrects it, so it is taken whole.
            if norm(&trial_phi) <= before * (1.0 + ASSEMBLY_BACKTRACK_SLACK)
                || before < ASSEMBLY_SATISFIED
                || !refresh
                || feasible
            {
                s = t;
                std::mem::swap(&mut phi, &mut trial_phi);
                accepted = true;
                break;
            }
            scale *= 0.5;
        }
        iterations += 1;
        if !accepted {
            mu = if mu == 0.0 {
                ASSEMBLY_STEP_REGULARISATION
            } else {
                mu * 10.0
            };
            lu = None;
            continue;
        }
        if feasible {
            last_feasible = Some(before_step);
        }
        feasible = scaled_max(&phi) <= 1.0;
        stationary = step_size * scale <= 1.0;
        if feasible && mu < ASSEMBLY_POLISH_REGULARISATION {
            mu = ASSEMBLY_POLISH_REGULARISATION;
            lu = None;
        }
    }
    if !feasible {
        if let Some(kept) = last_feasible {
            s = kept;
            prob.residual(&s, &mut phi);
            feasible = true;
        }
    }
    let converged = feasible;
    let mut residuals: Vec<(Equation, f64)> = phi
        .iter()
        .enumerate()
        .map(|(k, v)| match prob.equation(k) {
            Equation::Hard(h) => (Equation::Hard(hard_kept[h]), *v),
            e => (e, *v),
        })
        .collect();
    let max_residual = phi.iter().map(|v| v.abs()).fold(0.0, f64::max);
    residuals.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
    Assembly {
        state: s,
        converged,
        iterations,
        max_residual,
        residuals,
    }
}

/// The equations the Newton system can hold at once: hard conditions first (they are exact by
/// definition), then the constraint rows that are independent of them and of each other. A
/// constraint row left out here is checked after assembly like any redundant equation.
fn independent_equations(
    sys: &System,
    rows: Vec<(usize, f64)>,
    hard: &[HardRow],
    s: &State,
    length: f64,
) -> (Vec<usize>, Vec<(usize, f64)>) {
    if hard.is_empty() {
        return (Vec::new(), rows);
    }
    let ncols = 6 * sys.nparts;
    let mut m = SparseRows::new(ncols);
    let mut g = RowGradient::default();
    let push = |g: &RowGradient, m: &mut SparseRows| {
        let mut e: Vec<(usize, f64)> = Vec::with_capacity(12);
        let norm = scaled_row(g, length, &mut e);
        m.push_row(
            e.into_iter()
                .map(|(c, x)| (c, if norm > 0.0 { x / norm } else { 0.0 })),
        );
    };
    for h in hard {
        g.clear();
        h.quantity.gradient(s, 1.0, &mut g);
        push(&g, &mut m);
    }
    for &(r, _) in &rows {
        sys.gradient(r, s, &mut g);
        push(&g, &mut m);
    }
    let res = greedy_rank(&m, &RankSettings::default());
    let nh = hard.len();
    let admitted = |k: usize| res.decisions.get(k).is_some_and(|d| d.admitted);
    let kept_hard = (0..nh).filter(|&k| admitted(k)).collect();
    let kept_rows = rows
        .into_iter()
        .enumerate()
        .filter(|(k, _)| admitted(nh + k))
        .map(|(_, r)| r)
        .collect();
    (kept_hard, kept_rows)
}
