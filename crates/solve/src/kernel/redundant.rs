//! The check of the redundant rows during a run: a row removed as consistent must stay
//! satisfied.

use super::error::IntegrationError;
use super::problem::Problem;
use super::results::Failure;
use crate::constraints::residuals::{report_residual, report_unit_suffix, within_tolerance};
use crate::state::State;
use crate::tolerances::REDUNDANT_DRIFT;

/// The monitor's tolerance for a run with INTEGRATOR ERROR `error`: a removed row may drift
/// by the integrator's own accuracy, so the larger of [`REDUNDANT_DRIFT`] (verify's tolerance)
/// and `error` (× L for lengths, radians for angles and dot products).
pub(crate) fn redundant_tolerance(error: f64) -> f64 {
    REDUNDANT_DRIFT.max(error)
}

/// The first redundant row (removed as consistent) that no longer holds at `s` (residual above
/// `tolerance` × `length` or radians: [`redundant_tolerance`]): Adams' "consistent redundant
/// constraint that becomes inconsistent", with element, equation, time and value. Rows whose
/// motion cannot be evaluated are skipped. Cost: one residual per redundant row.
pub(crate) fn redundant_violation(
    p: &Problem,
    s: &State,
    length: f64,
    tolerance: f64,
) -> Option<Failure> {
    let tol = crate::tolerances::Tolerances {
        length: tolerance,
        angle: tolerance,
        ..Default::default()
    };
    for &r in p.redundant {
        let row = &p.sys.rows[r];
        let drive = if row.driven {
            p.drivers.value(row.element, p.time(s.time))
        } else {
            Some(0.0)
        };
        let Some(drive) = drive else { continue };
        let val = p.sys.residual(r, s, drive);
        if !within_tolerance(row.unit, val, &tol, length) {
            let c = &p.model.constraints[row.element];
            return Some(Failure::new(
                s.time,
                IntegrationError::RedundantViolated {
                    equation: row.label,
                    element: c.origin.name.clone(),
                    residual: report_residual(row.unit, val),
                    unit: report_unit_suffix(row.unit),
                },
            ));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The monitor's tolerance follows INTEGRATOR ERROR above verify's tolerance, and is
    /// verify's below it (a run at ERROR = 1e-3 may drift a removed row by 1e-3 × L).
    #[test]
    fn the_redundant_row_tolerance_is_the_integrator_error_or_verify_s() {
        assert_eq!(redundant_tolerance(1e-3), 1e-3);
        assert_eq!(redundant_tolerance(1e-4), 1e-4);
        assert_eq!(redundant_tolerance(1e-12), REDUNDANT_DRIFT);
    }
}
