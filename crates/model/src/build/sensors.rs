//! `SENSOR/`: the watched function and EVALUATE parsed once, defaults filled in (ERROR 0.001).
//! Errors: a syntax error in FUNCTION or EVALUATE (at its place). A `USER(…)` call is left to
//! the coverage check, which names it with every other USER call.

use super::context::{origin, Ctx};
use crate::functions::parse_function;
use crate::sensors::{Sensor, DEFAULT_SENSOR_ERROR};
use linkage_adm::{Dataset, Located};
use std::sync::Arc;

pub(crate) fn sensors(ds: &Dataset, cx: &mut Ctx) -> Vec<Sensor> {
    let mut out = Vec::with_capacity(ds.sensors.len());
    for s in &ds.sensors {
        let origin = origin("SENSOR", &s.header);
        let mut parse = |f: &Option<Located<linkage_adm::Function>>, what: &str| {
            let f = f.as_ref()?;
            if f.value.user && !cx.user.given() {
                return None;
            }
            match parse_function(&ds.file, f, &origin, what, &cx.user) {
                Ok(e) if e.contains_user() => None,
                Ok(e) => Some(Arc::new(e)),
                Err(d) => {
                    cx.errors.push(d);
                    None
                }
            }
        };
        let function = parse(&s.function, "FUNCTION");
        let evaluate = parse(&s.evaluate, "EVALUATE");
        out.push(Sensor {
            origin,
            function,
            value: s.value.as_ref().map_or(0.0, |v| v.value),
            compare: s.compare,
            error: s.error.as_ref().map_or(DEFAULT_SENSOR_ERROR, |e| e.value),
            actions: s.actions,
            stepsize: s.stepsize.as_ref().map(|v| v.value),
            dt: s.dt.as_ref().map(|v| v.value),
            bisection: s.bisection,
            evaluate,
        });
    }
    out
}
