//! SENSOR elements (ADM-ELEMENTS §5) as the model holds them: the watched function parsed
//! once, VALUE, the comparison and its tolerance ERROR (default 0.001), the actions.
//!
//! A sensor watches `g = FUNCTION − VALUE` during a dynamic run. It is *true* when
//! `|g| ≤ ERROR` (EQ), `g ≥ −ERROR` (GE) or `g ≤ ERROR` (LE); it *fires* when it becomes true
//! after a step (having been false before, or at the start of the run), at the time the run
//! locates to within ERROR of `g = 0` (see `linkage-solve`'s dynamics sensors).

use crate::bodies::Origin;
use linkage_adm::{SensorActions, SensorCompare};
use linkage_expr::Expr;
use std::sync::Arc;

/// Adams' default ERROR of a SENSOR.
pub const DEFAULT_SENSOR_ERROR: f64 = 1e-3;

/// A SENSOR, resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct Sensor {
    pub origin: Origin,
    /// The watched FUNCTION, parsed (a USER call is named by the coverage check instead).
    pub function: Option<Arc<Expr>>,
    pub value: f64,
    pub compare: SensorCompare,
    /// The tolerance of the comparison and of the event time's location (in units of
    /// FUNCTION).
    pub error: f64,
    pub actions: SensorActions,
    /// STEPSIZE: the integrator's next trial step after the sensor fires.
    pub stepsize: Option<f64>,
    /// DT: the output interval from the event on.
    pub dt: Option<f64>,
    /// BISECTION: locate the event by bisection instead of the secant method.
    pub bisection: bool,
    /// EVALUATE: evaluated when the sensor fires; `SENVAL(id)` returns it (FUNCTION's value
    /// when there is no EVALUATE).
    pub evaluate: Option<Arc<Expr>>,
}

impl Sensor {
    /// Whether the sensor's condition holds for `g = FUNCTION − VALUE`.
    pub fn holds(&self, g: f64) -> bool {
        match self.compare {
            SensorCompare::Eq => g.abs() <= self.error,
            SensorCompare::Ge => g >= -self.error,
            SensorCompare::Le => g <= self.error,
        }
    }

    /// The actions that fire, as Adams names them (`HALT`, `RETURN`, …).
    pub fn action_names(&self) -> Vec<&'static str> {
        let a = &self.actions;
        [
            (a.halt, "HALT"),
            (a.return_, "RETURN"),
            (a.print, "PRINT"),
            (a.restart, "RESTART"),
            (a.codgen, "CODGEN"),
            (a.yydump, "YYDUMP"),
            (self.stepsize.is_some(), "STEPSIZE"),
            (self.dt.is_some(), "DT"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use linkage_adm::Span;

    fn sensor(compare: SensorCompare) -> Sensor {
        Sensor {
            origin: Origin {
                statement: "SENSOR",
                id: 1,
                name: "SENSOR_1".into(),
                span: Span::new(1, 1),
                statement_index: 0,
            },
            function: None,
            value: 0.0,
            compare,
            error: 0.1,
            actions: SensorActions::default(),
            stepsize: None,
            dt: None,
            bisection: false,
            evaluate: None,
        }
    }

    #[test]
    fn comparisons_hold_within_error() {
        let eq = sensor(SensorCompare::Eq);
        assert!(eq.holds(0.1) && eq.holds(-0.1) && !eq.holds(0.11) && !eq.holds(-0.11));
        let ge = sensor(SensorCompare::Ge);
        assert!(ge.holds(-0.1) && ge.holds(5.0) && !ge.holds(-0.11));
        let le = sensor(SensorCompare::Le);
        assert!(le.holds(0.1) && le.holds(-5.0) && !le.holds(0.11));
    }
}
