//! Which reactions are uniquely determined when some equations are redundant.
//!
//! The reaction of element `e` on its I marker is `F = Σ λ_r f_r` (translational rows, `f_r`
//! the direction of the row's force: the projection axis of `(P_I − P_J)·e`) and
//! `T = Σ λ_r t_r` (rotational rows: `a × b` for `a·b`, the rotation axis for an angle).
//! λ is unique up to the left null space of the Jacobian. For each null vector `n` (on the
//! scaled, row-normalised Jacobian, so that the multipliers change by `m_r = n_r/‖row_r‖`)
//! the change of each reaction is `ΔF = Σ m_r f_r`, `ΔT = Σ m_r t_r`. A component `u·F`
//! (`u` an axis of the J marker) is *determinate* when `|u·ΔF| ≤ 10⁻⁷·Σ |m_r|‖f_r‖` for every
//! basis vector (the contributions cancel to rounding; null-vector entries below 10⁻¹⁰ of the
//! largest are rounding and ignored); otherwise it depends on which
//! equations were removed. Scalar equations (body 1-2-3 motions, couplers, gears, general
//! constraints) are reported by their equation label.
//!
//! Only the directions an element actually constrains are listed: an axis `u` is constrained
//! when its projection onto the span of the element's force (torque) directions has squared
//! length above 10⁻⁶ (a revolute constrains the three forces and the torques about Xj and Yj,
//! not the torque about its axis).

use crate::constraints::rows::{Quantity, RowGradient};
use crate::constraints::system::System;
use crate::linalg::kkt::scaled_row;
use crate::pipeline::verify::Dependency;
use crate::state::State;
use crate::tolerances::UNDERFLOW_FLOOR;
use crate::tolerances::{
    CONSTRAINED_AXIS, DETERMINATE_CANCELLATION, NULL_VECTOR_ROUNDING, SPAN_INDEPENDENCE,
    ZERO_DIRECTION,
};
use glam::DVec3;
use std::collections::HashMap;

/// A reaction component of an element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Direction {
    /// Force along axis 0, 1, 2 (x, y, z) of the element's J marker.
    Force(usize),
    /// Torque about axis 0, 1, 2 of the element's J marker.
    Torque(usize),
    /// A scalar equation, by its label.
    Equation(&'static str),
}

impl Direction {
    /// `force along Zj`, `torque about Xj`, or the equation label.
    pub fn label(&self) -> String {
        const AX: [&str; 3] = ["Xj", "Yj", "Zj"];
        match self {
            Direction::Force(k) => format!("force along {}", AX[*k % 3]),
            Direction::Torque(k) => format!("torque about {}", AX[*k % 3]),
            Direction::Equation(l) => (*l).to_string(),
        }
    }
}

/// The reaction components of one element, split by determinacy (each list ordered).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ElementReactions {
    /// Index into the model's constraints.
    pub element: usize,
    /// Components that are uniquely determined (can be trusted).
    pub determinate: Vec<Direction>,
    /// Components that depend on which equations were removed.
    pub indeterminate: Vec<Direction>,
}

/// A basis of the left null space: one vector `e_r − Σ c_k e_k` per redundant row `r`, as
/// `(row, coefficient)` entries.
pub fn null_basis<'a>(
    redundant: impl IntoIterator<Item = (usize, &'a [Dependency])>,
) -> Vec<Vec<(usize, f64)>> {
    redundant
        .into_iter()
        .map(|(r, deps)| {
            std::iter::once((r, 1.0))
                .chain(deps.iter().map(|d| (d.row, -d.coefficient)))
                .collect()
        })
        .collect()
}

#[derive(Clone, Copy)]
enum RowKind {
    Force(DVec3),
    Torque(DVec3),
    Scalar(&'static str),
}

fn row_kind(sys: &System, r: usize, s: &State) -> RowKind {
    let row = &sys.rows[r];
    if row.function.is_some() || row.terms.is_empty() {
        return RowKind::Scalar(row.label);
    }
    let mut force = DVec3::ZERO;
    let mut torque = DVec3::ZERO;
    let (mut nf, mut nt) = (0, 0);
    for (c, q) in &row.terms {
        match q {
            Quantity::Proj { e, .. } => {
                force += *c * e.eval(s);
                nf += 1;
            }
            Quantity::Dot(a, b) => {
                torque += *c * a.eval(s).cross(b.eval(s));
                nt += 1;
            }
            Quantity::Angle { x_ref, y_ref, .. } => {
                torque += *c * x_ref.eval(s).cross(y_ref.eval(s));
                nt += 1;
            }
            Quantity::Euler(_) | Quantity::CurveGap(_) | Quantity::CurveContact(_) => {
                return RowKind::Scalar(row.label)
            }
        }
    }
    match (nf, nt) {
        (_, 0) if force.length() > ZERO_DIRECTION => RowKind::Force(force),
        (0, _) if torque.length() > ZERO_DIRECTION => RowKind::Torque(torque),
        _ => RowKind::Scalar(row.label),
    }
}

/// Orthonormal basis of the span of `v` (Gram–Schmidt, dropping dependent vectors).
fn span(v: &[DVec3]) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = Vec::with_capacity(3);
    for x in v {
        let mut w = *x;
        for b in &out {
            w -= *b * b.dot(w);
        }
        for b in &out {
            w -= *b * b.dot(w);
        }
        let n = w.length();
        if n > SPAN_INDEPENDENCE * x.length().max(UNDERFLOW_FLOOR) && out.len() < 3 {
            out.push(w / n);
        }
    }
    out
}

fn constrained(basis: &[DVec3], u: DVec3) -> bool {
    basis.iter().map(|b| b.dot(u).powi(2)).sum::<f64>() > CONSTRAINED_AXIS
}

#[derive(Default, Clone, Copy)]
struct Acc {
    force: DVec3,
    force_scale: f64,
    torque: DVec3,
    torque_scale: f64,
}

/// Determinacy of every element's reactions at state `s` given a basis `null` of the left null
/// space of `sys`'s scaled Jacobian. Elements without rows are left out.
pub fn determinacy(
    sys: &System,
    s: &State,
    length: f64,
    null: &[Vec<(usize, f64)>],
) -> Vec<ElementReactions> {
    let nrows = sys.rows.len();
    let mut kinds: Vec<RowKind> = Vec::with_capacity(nrows);
    let mut norms: Vec<f64> = Vec::with_capacity(nrows);
    let mut g = RowGradient::default();
    let mut scratch = Vec::new();
    for r in 0..nrows {
        kinds.push(row_kind(sys, r, s));
        sys.gradient(r, s, &mut g);
        let n = scaled_row(&g, length, &mut scratch);
        norms.push(if n > 0.0 { n } else { 1.0 });
    }
    // Indeterminate directions per element.
    let mut bad: HashMap<usize, Vec<Direction>> = HashMap::new();
    let axes_of = |e: usize| -> [DVec3; 3] {
        match sys.frames.get(e).copied().flatten() {
            Some((_, fj)) => {
                let (_, r) = fj.eval(s);
                [r.x_axis, r.y_axis, r.z_axis]
            }
            None => [DVec3::X, DVec3::Y, DVec3::Z],
        }
    };
    for vector in null {
        let max = vector.iter().map(|(_, c)| c.abs()).fold(0.0, f64::max);
        let mut acc: HashMap<usize, Acc> = HashMap::new();
        for &(r, c) in vector {
            if r >= nrows || c.abs() <= NULL_VECTOR_ROUNDING * max {
                continue;
            }
            let e = sys.rows[r].element;
            let m = c / norms[r];
            match kinds[r] {
                RowKind::Force(f) => {
                    let a = acc.entry(e).or_default();
                    a.force += m * f;
                    a.force_scale += m.abs() * f.length();
                }
                RowKind::Torque(t) => {
                    let a = acc.entry(e).or_default();
                    a.torque += m * t;
                    a.torque_scale += m.abs() * t.length();
                }
                RowKind::Scalar(label) => {
                    let list = bad.entry(e).or_default();
                    if !list.contains(&Direction::Equation(label)) {
                        list.push(Direction::Equation(label));
                    }
                }
            }
        }
        for (e, a) in acc {
            let axes = axes_of(e);
            let list = bad.entry(e).or_default();
            for (k, u) in axes.iter().enumerate() {
                if a.force_scale > 0.0
                    && u.dot(a.force).abs() > DETERMINATE_CANCELLATION * a.force_scale
                {
                    let d = Direction::Force(k);
                    if !list.contains(&d) {
                        list.push(d);
                    }
                }
                if a.torque_scale > 0.0
                    && u.dot(a.torque).abs() > DETERMINATE_CANCELLATION * a.torque_scale
                {
                    let d = Direction::Torque(k);
                    if !list.contains(&d) {
                        list.push(d);
                    }
                }
            }
        }
    }
    let mut out = Vec::with_capacity(sys.element_rows.len());
    for (e, rows) in sys.element_rows.iter().enumerate() {
        if rows.is_empty() {
            continue;
        }
        let axes = axes_of(e);
        let (mut fd, mut td) = (Vec::new(), Vec::new());
        let mut all: Vec<Direction> = Vec::new();
        for r in rows.clone() {
            match kinds[r] {
                RowKind::Force(f) => fd.push(f),
                RowKind::Torque(t) => td.push(t),
                RowKind::Scalar(l) => {
                    if !all.contains(&Direction::Equation(l)) {
                        all.push(Direction::Equation(l));
                    }
                }
            }
        }
        let (fb, tb) = (span(&fd), span(&td));
        for (k, u) in axes.iter().enumerate() {
            if constrained(&fb, *u) {
                all.push(Direction::Force(k));
            }
        }
        for (k, u) in axes.iter().enumerate() {
            if constrained(&tb, *u) {
                all.push(Direction::Torque(k));
            }
        }
        let worse = bad.remove(&e).unwrap_or_default();
        // Components a row barely touches (projection below 10⁻³) are not listed at all.
        let (mut indeterminate, mut determinate): (Vec<Direction>, Vec<Direction>) =
            all.into_iter().partition(|d| worse.contains(d));
        determinate.sort();
        indeterminate.sort();
        out.push(ElementReactions {
            element: e,
            determinate,
            indeterminate,
        });
    }
    out
}
