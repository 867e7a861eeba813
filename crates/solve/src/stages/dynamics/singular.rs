//! Whether a run that gave up at its smallest step stands at a singular configuration: the
//! independent constraint rows kept at the start have become (nearly) dependent, so the
//! multipliers that hold the motions grow like `1/σ_min` and no step size converges.
//!
//! The test is a dense SVD of the kept rows' Jacobian at the last accepted state, scaled and
//! row-normalised as in the rank analysis (translation columns × the characteristic length,
//! each row to unit norm: [`crate::linalg::kkt::scaled_row`]): the pose is singular when its
//! `σ_min/σ_max` fell below [`SINGULAR_POSE_CONDITIONING`] times the start's (a model's rows
//! may be poorly conditioned from the start without being singular: corpus
//! `ssernap…intento2.adm` starts at 3.7e-3, and its motions drive it to 8e-8 at 0.6964 s,
//! falling linearly in time towards zero; there the full Jacobian, the redundant rows
//! included, loses a rank too, so no other choice of kept rows avoids it). The left singular vector of
//! `σ_min` is the combination of rows that lost its independence; the elements whose rows
//! carry at least [`SINGULAR_POSE_SHARE`] of its largest entry are the ones named (Adams
//! reports a singular Jacobian with the constraints involved the same way). Cost: only at a
//! failure, `O(m·(6n)²)`; models with more than [`SINGULAR_POSE_DENSE_COLUMNS`] coordinates
//! are not diagnosed.

use crate::constraints::rows::RowGradient;
use crate::kernel::error::IntegrationError;
use crate::kernel::problem::Problem;
use crate::linalg::kkt::scaled_row;
use crate::state::State;
use crate::tolerances::{
    SINGULAR_POSE_CONDITIONING, SINGULAR_POSE_DENSE_COLUMNS, SINGULAR_POSE_SHARE,
};

/// A configuration where the kept constraint rows lost their independence.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct SingularPose {
    /// `σ_min/σ_max` of the scaled, row-normalised Jacobian of the kept rows.
    pub conditioning: f64,
    /// The elements (`JOINT/11 (name)`) whose rows make up the dependent combination, the
    /// largest share first.
    pub elements: Vec<String>,
}

/// `σ_min/σ_max` of the kept rows' Jacobian at `s` and the left singular vector of `σ_min`
/// as `(row, weight)`, or `None` when the model is too large to analyse densely or has no rows.
fn smallest_singular_value(p: &Problem, s: &State) -> Option<(f64, Vec<(usize, f64)>)> {
    let cols = 6 * p.n();
    let m = p.rows.len();
    if m == 0 || cols == 0 || cols > SINGULAR_POSE_DENSE_COLUMNS || m > cols {
        return None;
    }
    let length = p.model.characteristic_length;
    let mut g = RowGradient::default();
    let mut entries = Vec::new();
    let mut dense = vec![0.0; m * cols];
    for (k, &r) in p.rows.iter().enumerate() {
        p.sys.gradient(r, s, &mut g);
        let norm = scaled_row(&g, length, &mut entries);
        if norm > 0.0 && norm.is_finite() {
            for &(c, x) in &entries {
                dense[k * cols + c] = x / norm;
            }
        }
    }
    let a = faer::Mat::<f64>::from_fn(m, cols, |i, j| dense[i * cols + j]);
    let svd = a.svd().ok()?;
    let smax = svd.S()[0];
    let smin = svd.S()[m - 1];
    if smax.is_nan() || smax <= 0.0 || !smin.is_finite() {
        return None;
    }
    let u = svd.U();
    let vector = (0..m).map(|i| (p.rows[i], u[(i, m - 1)])).collect();
    Some((smin / smax, vector))
}

/// `failure` (the run gave up at `s`, started at `start`) as an
/// [`IntegrationError::SingularConfiguration`] when the kept rows are nearly dependent at `s`;
/// unchanged otherwise.
pub(super) fn diagnose(
    p: &Problem,
    start: &State,
    s: &State,
    failure: IntegrationError,
) -> IntegrationError {
    match singular_pose(p, start, s) {
        Some(pose) => IntegrationError::SingularConfiguration {
            time: s.time,
            conditioning: pose.conditioning,
            elements: pose.elements.join(", "),
            cause: Box::new(failure),
        },
        None => failure,
    }
}

/// The singular configuration at `s`, if the kept rows are nearly dependent there (against
/// their conditioning at `start`).
pub(super) fn singular_pose(p: &Problem, start: &State, s: &State) -> Option<SingularPose> {
    let (conditioning, vector) = smallest_singular_value(p, s)?;
    let (initial, _) = smallest_singular_value(p, start)?;
    if conditioning >= SINGULAR_POSE_CONDITIONING * initial {
        return None;
    }
    // Each element's share: the largest weight among its rows.
    let mut shares: Vec<(usize, f64)> = Vec::new();
    for (row, w) in vector {
        let e = p.sys.rows[row].element;
        match shares.iter_mut().find(|(x, _)| *x == e) {
            Some((_, s)) => *s = s.max(w.abs()),
            None => shares.push((e, w.abs())),
        }
    }
    let top = shares.iter().map(|x| x.1).fold(0.0, f64::max);
    shares.retain(|x| x.1 >= SINGULAR_POSE_SHARE * top);
    shares.sort_by(|a, b| b.1.total_cmp(&a.1));
    let elements = shares
        .iter()
        .map(|&(e, _)| {
            let o = &p.model.constraints[e].origin;
            let id = o.element();
            // A default name (`JOINT_7`) adds nothing to `JOINT/7`.
            if o.name.is_empty() || o.name == linkage_adm::keyword_id(o.statement, '_', o.id) {
                id
            } else {
                format!("{id} ({})", o.name)
            }
        })
        .collect();
    Some(SingularPose {
        conditioning,
        elements,
    })
}
