//! Constraint residuals in the units the reports and tolerances use: a row's raw residual
//! (length, direction cosine, angle) → report units (length, or degrees for rotational rows),
//! the unit suffix printed with it, the tolerance test against [`Tolerances`] relative to the
//! model's size, and the raw residual of every row at a state. Shared by verify, the initial
//! conditions, the judgement of an assembly, the kinematic run and the redundant-row monitor.

use crate::constraints::drivers::Drivers;
use crate::constraints::system::{RowUnit, System};
use crate::state::State;
use crate::tolerances::Tolerances;

/// Residual in report units: length, or degrees for rotational rows.
pub fn report_residual(unit: RowUnit, value: f64) -> f64 {
    match unit {
        RowUnit::Length | RowUnit::Mixed => value,
        RowUnit::Direction => value.clamp(-1.0, 1.0).asin().to_degrees(),
        RowUnit::Angle => value.to_degrees(),
    }
}

/// The unit [`report_residual`] gives a row's residual in, as a suffix: `" deg"` for
/// rotational rows, nothing for lengths.
pub fn report_unit_suffix(unit: RowUnit) -> &'static str {
    match unit {
        RowUnit::Direction | RowUnit::Angle => " deg",
        RowUnit::Length | RowUnit::Mixed => "",
    }
}

/// Whether a raw residual is within tolerance.
pub fn within_tolerance(unit: RowUnit, value: f64, tol: &Tolerances, length: f64) -> bool {
    match unit {
        RowUnit::Length | RowUnit::Mixed => value.abs() <= tol.length * length,
        RowUnit::Direction | RowUnit::Angle => value.abs() <= tol.angle,
    }
}

/// Raw residuals of every row at `s` (`None` for motions whose function cannot be evaluated).
pub fn residuals(sys: &System, s: &State, drivers: &dyn Drivers) -> Vec<Option<f64>> {
    (0..sys.rows.len())
        .map(|r| {
            let row = &sys.rows[r];
            let drive = if row.driven {
                drivers.value(row.element, s.time)?
            } else {
                0.0
            };
            Some(sys.residual(r, s, drive))
        })
        .collect()
}
