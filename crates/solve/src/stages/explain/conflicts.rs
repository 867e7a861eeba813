//! Drivers and initial conditions that fix the same DOF twice or conflict with a joint.
//!
//! Adams does not check these. The rows are ranked in priority order: the constraint rows
//! (as in verify), then the motions, then the hard initial conditions of the assembly (EXACT
//! part coordinates, then joint initial displacements, [`crate::pipeline::assemble::hard_rows`]). A
//! motion or initial condition whose row is redundant fixes a DOF that the rows before it
//! already fix: a *duplicate*. It *conflicts* when the values disagree: with the linearised
//! dependency `r = Σ c_k a_k` (scaled rows, norms `n`), `Δ = φ_r/n_r − Σ c_k φ_k/n_k` of the
//! residuals `φ` at the input must vanish (to the length or angle tolerance); the mismatch is
//! reported in the row's units (length, or degrees). When a motion cannot be evaluated the
//! kind is unknown.

use crate::constraints::drivers::Drivers;
use crate::constraints::rank::{greedy_rank, RankSettings, SparseRows};
use crate::constraints::residuals::report_residual;
use crate::constraints::rows::RowGradient;
use crate::constraints::system::{RowUnit, System, Tier};
use crate::linalg::kkt::scaled_row;
use crate::pipeline::assemble::hard_rows;
use crate::state::State;
use crate::tolerances::Tolerances;
use linkage_model::Model;

/// Whether a redundant driver agrees with what fixes the same DOF.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConflictKind {
    /// Fixes an already fixed DOF to the same value.
    Duplicate,
    /// Fixes an already fixed DOF to a different value.
    Conflict,
    /// A value involved cannot be evaluated.
    Unknown,
}

/// A motion or initial condition that fixes a DOF already fixed.
#[derive(Clone, Debug, PartialEq)]
pub struct DriverConflict {
    /// Element (motion, joint) or part name.
    pub name: String,
    /// `Rotational Motion`, `IC rotation`, `EXACT X`, …
    pub what: String,
    pub kind: ConflictKind,
    /// What fixes the DOF already: `name (type)` of constraints and motions, `name label` of
    /// initial conditions.
    pub with: Vec<String>,
    /// Whether only constraint equations (no other driver) fix it already.
    pub with_constraints_only: bool,
    /// The disagreement, in `unit` (report units: length or degrees).
    pub mismatch: Option<f64>,
    pub unit: RowUnit,
}

enum Source {
    Row(usize),
    Hard(usize),
}

/// The redundant motions and initial conditions of `model` at configuration `s`.
pub fn driver_conflicts(
    model: &Model,
    sys: &System,
    s: &State,
    drivers: &dyn Drivers,
    tol: &Tolerances,
) -> Vec<DriverConflict> {
    let hard = hard_rows(model);
    let motions: Vec<usize> = (0..sys.rows.len())
        .filter(|&r| sys.rows[r].tier == Tier::Motion)
        .collect();
    if hard.is_empty() && motions.is_empty() {
        return Vec::new();
    }
    let length = model.characteristic_length;
    let mut order: Vec<Source> = Vec::with_capacity(sys.rows.len() + hard.len());
    let mut constraint_rows: Vec<usize> = (0..sys.rows.len())
        .filter(|&r| sys.rows[r].tier != Tier::Motion)
        .collect();
    constraint_rows.sort_by_key(|&r| (sys.rows[r].tier, r));
    order.extend(constraint_rows.into_iter().map(Source::Row));
    order.extend(motions.into_iter().map(Source::Row));
    order.extend((0..hard.len()).map(Source::Hard));

    let mut m = SparseRows::new(6 * model.parts.len());
    let mut norms = Vec::with_capacity(order.len());
    let mut values: Vec<Option<f64>> = Vec::with_capacity(order.len());
    let mut g = RowGradient::default();
    let mut entries = Vec::new();
    for src in &order {
        match src {
            Source::Row(r) => {
                sys.gradient(*r, s, &mut g);
                let row = &sys.rows[*r];
                let drive = if row.driven {
                    drivers.value(row.element, s.time)
                } else {
                    Some(0.0)
                };
                values.push(drive.map(|d| sys.residual(*r, s, d)));
            }
            Source::Hard(h) => {
                g.clear();
                hard[*h].quantity.gradient(s, 1.0, &mut g);
                values.push(Some(hard[*h].residual(s)));
            }
        }
        let n = scaled_row(&g, length, &mut entries);
        let n = if n > 0.0 { n } else { 1.0 };
        norms.push(n);
        m.push_row(entries.iter().map(|&(c, x)| (c, x / n)));
    }
    let res = greedy_rank(
        &m,
        &RankSettings {
            tolerance: tol.rank,
            near_tie_factor: tol.near_tie_factor,
        },
    );
    let describe = |src: &Source| -> (String, String, RowUnit, bool) {
        match src {
            Source::Row(r) => {
                let row = &sys.rows[*r];
                let c = &model.constraints[row.element];
                (
                    c.origin.name.clone(),
                    c.description().to_string(),
                    row.unit,
                    row.tier == Tier::Motion,
                )
            }
            Source::Hard(h) => (
                hard[*h].name.clone(),
                hard[*h].label.clone(),
                hard[*h].unit,
                true,
            ),
        }
    };
    let first_driver = order
        .iter()
        .position(|src| match src {
            Source::Row(r) => sys.rows[*r].tier == Tier::Motion,
            Source::Hard(_) => true,
        })
        .unwrap_or(order.len());
    let mut out = Vec::new();
    for red in &res.redundant {
        if red.row < first_driver {
            continue;
        }
        let (name, what, unit, _) = describe(&order[red.row]);
        let mut with: Vec<String> = Vec::new();
        let mut only_constraints = true;
        for d in &red.depends_on {
            let (n, w, _, driver) = describe(&order[d.row]);
            only_constraints &= !driver;
            let label = match &order[d.row] {
                Source::Hard(_) => format!("{n} {w}"),
                Source::Row(_) => format!("{n} ({w})"),
            };
            if !with.contains(&label) {
                with.push(label);
            }
        }
        let delta = values[red.row].and_then(|v| {
            let mut d = v / norms[red.row];
            for dep in &red.depends_on {
                d -= dep.coefficient * values[dep.row]? / norms[dep.row];
            }
            Some(d)
        });
        let limit = match unit {
            RowUnit::Length | RowUnit::Mixed => tol.length,
            RowUnit::Direction | RowUnit::Angle => tol.angle,
        };
        let (kind, mismatch) = match delta {
            Some(d) if d.is_finite() => {
                let raw = d * norms[red.row];
                let shown = report_residual(unit, raw);
                if d.abs() > limit {
                    (ConflictKind::Conflict, Some(shown))
                } else {
                    (ConflictKind::Duplicate, Some(shown))
                }
            }
            _ => (ConflictKind::Unknown, None),
        };
        out.push(DriverConflict {
            name,
            what,
            kind,
            with,
            with_constraints_only: only_constraints,
            mismatch,
            unit,
        });
    }
    out
}
