//! The function utility routines a subroutine calls (STEP, POLY, IMPACT, BISTOP, AKISPL,
//! CUBSPL), answered by the expression language's own functions of the same names, so that a
//! subroutine and a function expression compute the same numbers.
//!
//! Each is `NAME(a₁, …, aₙ)` of numbers; the first `nvars` arguments are its variables (x; x
//! and ẋ for IMPACT and BISTOP; x and z for the splines). With IORD:
//! * 0: `out[0] = f`;
//! * 1: `out[k] = ∂f/∂a_{k+1}`, k < nvars (exact, by the evaluator's dual numbers);
//! * 2: one variable: `out[0] = ∂²f/∂x²`; two: `out = [∂²f/∂a₁², ∂²f/∂a₁∂a₂, ∂²f/∂a₂²]`, by
//!   central differences of the exact first partials.

use crate::callbacks::with_current_env;
use crate::error::ReadError;
use crate::routine::DIFFERENCE_STEP;
use linkage_expr::{evaluate_with_gradient, parse, Env, SplineData};
use std::ffi::{c_char, c_int, CStr};

/// The value of `name(args…)` with argument `var` the variable (TIME of [`At`]), and its
/// first derivative along it.
fn along(
    name: &str,
    args: &[f64],
    var: usize,
    env: Option<&dyn Env>,
) -> Result<[f64; 2], ReadError> {
    if args.iter().any(|a| !a.is_finite()) {
        return Err(arguments(name, "an argument is not a finite number".into()));
    }
    let text: Vec<String> = args
        .iter()
        .enumerate()
        .map(|(k, a)| {
            if k == var {
                "TIME".into()
            } else {
                format!("{a:e}")
            }
        })
        .collect();
    let call = format!("{name}({})", text.join(","));
    let expr = parse(&call).map_err(|e| ReadError::BadName {
        name: name.to_string(),
        why: Some(e.message),
    })?;
    let at = At {
        env,
        time: args[var],
    };
    let d = evaluate_with_gradient(&expr, &at).map_err(|e| ReadError::Evaluate {
        what: call,
        why: e.message,
    })?;
    let slope = d.gradient().iter().map(|&(_, g)| g).sum();
    Ok([d.value(), slope])
}

fn arguments(routine: &str, why: String) -> ReadError {
    ReadError::Arguments {
        routine: routine.to_string(),
        why,
    }
}

/// The environment of a utility call: TIME is the variable (index 0); splines are the model's.
struct At<'a> {
    env: Option<&'a dyn Env>,
    time: f64,
}

impl Env for At<'_> {
    fn time(&self) -> f64 {
        self.time
    }
    fn time_variable(&self) -> Option<u32> {
        Some(0)
    }
    fn spline(&self, id: u32) -> Option<&SplineData> {
        self.env?.spline(id)
    }
}

/// The IORD-th partials of `name(args…)` with respect to its first `nvars` arguments (see the
/// module's documentation), at most 3 values.
pub(crate) fn partials(
    name: &str,
    args: &[f64],
    nvars: usize,
    iord: i32,
    env: Option<&dyn Env>,
) -> Result<Vec<f64>, ReadError> {
    let nvars = nvars.clamp(1, 2).min(args.len());
    if nvars == 0 {
        return Err(arguments(name, "no arguments".into()));
    }
    let first = |args: &[f64], k: usize| along(name, args, k, env).map(|v| v[1]);
    match iord {
        0 => Ok(vec![along(name, args, 0, env)?[0]]),
        1 => (0..nvars).map(|k| first(args, k)).collect(),
        2 => {
            // ∂/∂a_j of ∂f/∂a_k by central differences.
            let second = |k: usize, j: usize| -> Result<f64, ReadError> {
                let h = DIFFERENCE_STEP * args[j].abs().max(1.0);
                let mut up = args.to_vec();
                let mut down = args.to_vec();
                up[j] += h;
                down[j] -= h;
                Ok((first(&up, k)? - first(&down, k)?) / (2.0 * h))
            };
            if nvars == 1 {
                Ok(vec![second(0, 0)?])
            } else {
                Ok(vec![second(0, 0)?, second(0, 1)?, second(1, 1)?])
            }
        }
        _ => Err(arguments(name, format!("IORD {iord} is not 0, 1 or 2"))),
    }
}

/// The shim's entry for every function utility routine: `name` (NUL-terminated, upper case),
/// `nargs` numbers, `nvars` of them variables, IORD; writes the partials to `out` (room for 3)
/// and ERRFLG (0 or 1; a failure is also reported on standard error with the routine's name).
pub(crate) unsafe extern "C" fn utility(
    name: *const c_char,
    args: *const f64,
    nargs: c_int,
    nvars: c_int,
    iord: c_int,
    out: *mut f64,
    errflg: *mut c_int,
) {
    let name = CStr::from_ptr(name).to_string_lossy().into_owned();
    let args = if args.is_null() || nargs <= 0 {
        &[][..]
    } else {
        std::slice::from_raw_parts(args, nargs as usize)
    };
    let r = std::panic::catch_unwind(|| {
        with_current_env(|env| partials(&name, args, nvars.max(0) as usize, iord, env))
    })
    .unwrap_or_else(|_| Err(ReadError::Panicked(name.clone())));
    match r {
        Ok(values) => {
            for (k, v) in values.iter().enumerate() {
                *out.add(k) = *v;
            }
            *errflg = 0;
        }
        Err(why) => {
            *out = 0.0;
            *errflg = 1;
            eprintln!("warning: user subroutine utility {why}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_and_its_derivatives_are_the_cubic_of_the_expression_language() {
        // STEP(x, 0, 0, 1, 1) = 3x² − 2x³: at x = 0.5, 0.5, 1.5 and 0.
        let a = [0.5, 0.0, 0.0, 1.0, 1.0];
        assert!((partials("STEP", &a, 1, 0, None).unwrap()[0] - 0.5).abs() < 1e-15);
        assert!((partials("STEP", &a, 1, 1, None).unwrap()[0] - 1.5).abs() < 1e-12);
        assert!(partials("STEP", &a, 1, 2, None).unwrap()[0].abs() < 1e-6);
        let a = [0.25, 0.0, 0.0, 1.0, 1.0];
        // d²/dx² = 6 − 12x = 3.
        assert!((partials("STEP", &a, 1, 2, None).unwrap()[0] - 3.0).abs() < 1e-6);
    }

    #[test]
    fn poly_and_impact_partials_are_closed_form() {
        // POLY(x, x0, a0, a1, a2) = a0 + a1(x−x0) + a2(x−x0)²; at x = 3, x0 = 1: 1 + 4 + 12.
        let p = [3.0, 1.0, 1.0, 2.0, 3.0];
        assert!((partials("POLY", &p, 1, 0, None).unwrap()[0] - 17.0).abs() < 1e-12);
        assert!((partials("POLY", &p, 1, 1, None).unwrap()[0] - 14.0).abs() < 1e-12);
        // IMPACT(x, ẋ, x1, k, e, cmax, d) inside the damping ramp: k(x1−x)^e − STEP(…)·ẋ.
        let i = [0.9, -2.0, 1.0, 1e3, 1.5, 10.0, 0.5];
        let pen: f64 = 0.1;
        let s = 0.8f64; // (x − (x1 − d))/d
        let c = 10.0 * (1.0 - s * s * (3.0 - 2.0 * s));
        let f = 1e3 * pen.powf(1.5) - c * -2.0;
        let v = partials("IMPACT", &i, 2, 0, None).unwrap();
        assert!((v[0] - f).abs() < 1e-9 * f.abs(), "{v:?} vs {f}");
        let d = partials("IMPACT", &i, 2, 1, None).unwrap();
        assert!((d[1] + c).abs() < 1e-9 * c, "∂F/∂ẋ {} vs {}", d[1], -c);
        assert_eq!(d.len(), 2);
        assert_eq!(partials("IMPACT", &i, 2, 2, None).unwrap().len(), 3);
        assert!(partials("IMPACT", &i, 2, 3, None).is_err());
    }
}
