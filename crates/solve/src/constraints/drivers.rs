//! Motion functions `f(t)` from the dataset's expressions.
//!
//! Each MOTION's FUNCTION is parsed once. A syntax error is an input error located at the line
//! and column inside the expression; a `USER(...)` subroutine cannot be run by linkage, so its
//! value is unknown (a warning; analyses that need it report it as such).

use crate::physics::measures::{MarkerFrames, PositionEnv};
use crate::state::State;
use crate::tolerances::MOTION_QUADRATURE;
use crate::tolerances::UNDERFLOW_FLOOR;
use linkage_adm::{Diagnostic, Diagnostics, MotionLevel};
use linkage_expr::{evaluate, evaluate_time_series, parse, Expr, TimeEnv};
use linkage_model::functions::parse_function;
use linkage_model::{ConstraintKind, Model};

/// Supplies motion functions `f(t)` (and whether they can be evaluated) to the analyses.
pub trait Drivers {
    /// `f(t)` of the motion element `element`; `None` when it cannot be evaluated.
    fn value(&self, element: usize, t: f64) -> Option<f64>;

    /// Displacement and its first two time derivatives; `None` when unknown.
    fn rates(&self, element: usize, t: f64) -> Option<[f64; 3]> {
        let _ = (element, t);
        None
    }

    /// Why `value(element, t)` is `None`, for messages (e.g. the expression's domain error).
    fn why_unknown(&self, element: usize, t: f64) -> DriveError {
        let _ = (element, t);
        DriveError::Unknown
    }
}

/// Drivers that cannot evaluate anything (motion residuals unknown).
pub struct NoDrivers;
impl Drivers for NoDrivers {
    fn value(&self, _: usize, _: f64) -> Option<f64> {
        None
    }
}

/// Why a motion's value (or rate) is unknown at a time.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DriveError {
    /// Nothing says why (drivers that evaluate nothing).
    #[error("its value is unknown")]
    Unknown,
    /// A USER subroutine, or no FUNCTION at all.
    #[error("its FUNCTION is a USER subroutine (or absent), which linkage cannot run")]
    NotRunnable,
    /// A velocity or acceleration motion whose start displacement is free.
    #[error("a {} motion without ICDISP has no known displacement", level_name(.level))]
    NoStartDisplacement { level: MotionLevel },
    /// The expression cannot be evaluated at the requested time.
    #[error("FUNCTION: {cause}")]
    Function { cause: String },
    /// The expression cannot be evaluated at `time`, inside the quadrature of a velocity or
    /// acceleration motion.
    #[error("FUNCTION at time {}: {cause}", linkage_adm::num::time_text(*.time))]
    FunctionAt { time: f64, cause: String },
    /// The quadrature of a velocity or acceleration motion does not converge.
    #[error("the integral of FUNCTION does not converge")]
    IntegralDiverges,
}

fn level_name(level: &MotionLevel) -> &'static str {
    match level {
        MotionLevel::Displacement => "displacement",
        MotionLevel::Velocity => "velocity",
        MotionLevel::Acceleration => "acceleration",
    }
}

/// A motion whose displacement cannot be evaluated at a time:
/// `NAME (MOTION/id, line N): the motion's displacement cannot be evaluated at time t: why`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{element}: the motion's displacement cannot be evaluated at time {}: {cause}", linkage_adm::num::time_text(*.time))]
pub struct MotionError {
    /// The motion's label (name, statement and line).
    pub element: String,
    pub time: f64,
    pub cause: DriveError,
}

impl MotionError {
    /// Motion element `element` of `model` at time `t`, with the drivers' cause.
    pub fn at(model: &Model, drivers: &dyn Drivers, element: usize, t: f64) -> MotionError {
        MotionError {
            element: model.constraints[element].origin.label(),
            time: t,
            cause: drivers.why_unknown(element, t),
        }
    }
}

/// Parsed motion functions of a model.
#[derive(Clone)]
pub struct ExpressionDrivers {
    /// Per constraint element: the displacement-level function, if any.
    functions: Vec<Option<(Expr, MotionLevel, Option<f64>)>>,
    icvels: Vec<Option<f64>>,
    warnings: Vec<Diagnostic>,
}

/// `∫ₐᵇ f` by adaptive Simpson quadrature to a relative accuracy of about
/// [`MOTION_QUADRATURE`] (motion functions are smooth functions of time); `None` when `f`
/// cannot be evaluated.
pub fn integrate(f: &dyn Fn(f64) -> Option<f64>, a: f64, b: f64) -> Option<f64> {
    #[allow(clippy::too_many_arguments)]
    fn simpson(
        f: &dyn Fn(f64) -> Option<f64>,
        a: f64,
        fa: f64,
        b: f64,
        fb: f64,
        whole: f64,
        m: f64,
        fm: f64,
        tol: f64,
        depth: u32,
    ) -> Option<f64> {
        let (lm, rm) = ((a + m) / 2.0, (m + b) / 2.0);
        let (flm, frm) = (f(lm)?, f(rm)?);
        let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
        let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
        let delta = left + right - whole;
        if depth == 0 || delta.abs() <= 15.0 * tol {
            return Some(left + right + delta / 15.0);
        }
        Some(
            simpson(f, a, fa, m, fm, left, lm, flm, tol / 2.0, depth - 1)?
                + simpson(f, m, fm, b, fb, right, rm, frm, tol / 2.0, depth - 1)?,
        )
    }
    if a == b {
        return Some(0.0);
    }
    let (fa, fb) = (f(a)?, f(b)?);
    let m = (a + b) / 2.0;
    let fm = f(m)?;
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    let tol = MOTION_QUADRATURE
        * (whole.abs() + (b - a).abs() * (fa.abs() + fb.abs() + fm.abs()) / 3.0)
            .max(UNDERFLOW_FLOOR);
    simpson(f, a, fa, b, fb, whole, m, fm, tol, 40)
}

impl ExpressionDrivers {
    /// Parses every motion function of `model`.
    pub fn new(model: &Model) -> Result<ExpressionDrivers, Diagnostics> {
        let mut functions = Vec::with_capacity(model.constraints.len());
        let mut errors = Vec::new();
        let mut warnings = Vec::new();
        // Marker frames and the input state are needed only to check GCON functions.
        let needs_frames = model.constraints.iter().any(|c| {
            matches!(
                c.kind,
                ConstraintKind::Gcon {
                    expr: Some(Ok(_)),
                    ..
                }
            )
        });
        let frames = if needs_frames {
            MarkerFrames::new(model)
        } else {
            MarkerFrames::default()
        };
        let input = State::input(model);
        for c in &model.constraints {
            if let ConstraintKind::Gcon {
                function: Some(f),
                expr: Some(parsed),
                ..
            } = &c.kind
            {
                let text = &f.value.expr;
                let problem = match parsed {
                    Err(pe) => Some((
                        text.span_at(pe.offset),
                        format!("in FUNCTION: {}", pe.message),
                    )),
                    Ok(e) if e.contains_user() => Some((
                        f.span,
                        "FUNCTION is a USER subroutine, which linkage cannot run".to_string(),
                    )),
                    Ok(e) => evaluate(
                        e,
                        &PositionEnv {
                            frames: &frames,
                            state: &input,
                        },
                    )
                    .err()
                    .map(|err| {
                        (
                            f.span,
                            format!(
                                "FUNCTION cannot be evaluated at the input configuration: {}",
                                err.message
                            ),
                        )
                    }),
                };
                if let Some((span, msg)) = problem {
                    errors.push(Diagnostic::error(
                        model.file.clone(),
                        Some(span),
                        format!("{}: {msg}", c.origin.name),
                    ));
                }
            }
            let ConstraintKind::Motion {
                function: Some(f),
                level,
                icdisp,
                ..
            } = &c.kind
            else {
                functions.push(None);
                continue;
            };
            let text = &f.value.expr;
            // A USER call with libraries given: MOTSUB, linked (or an input error naming the
            // library or symbol that is missing).
            let parsed = match parse(&text.text) {
                Ok(e) if e.contains_user() && model.user.given() => {
                    match parse_function(&model.file, f, &c.origin, "FUNCTION", &model.user) {
                        Ok(linked) => Ok(linked),
                        Err(d) => {
                            errors.push(d);
                            functions.push(None);
                            continue;
                        }
                    }
                }
                other => other,
            };
            match parsed {
                Ok(e) if e.contains_user() => {
                    warnings.push(Diagnostic::warning(
                        model.file.clone(),
                        Some(f.span),
                        format!("{}: FUNCTION is a USER subroutine, which linkage cannot run; its value is unknown", c.origin.name),
                    ));
                    functions.push(None);
                }
                Ok(e) => match super::motion_data::inline_data(model, &e) {
                    Ok(e) => functions.push(Some((e, *level, *icdisp))),
                    Err(why) => {
                        errors.push(Diagnostic::error(
                            model.file.clone(),
                            Some(f.span),
                            format!("{}: FUNCTION: {why}", c.origin.name),
                        ));
                        functions.push(None);
                    }
                },
                Err(pe) => {
                    errors.push(Diagnostic::error(
                        model.file.clone(),
                        Some(text.span_at(pe.offset)),
                        format!("{}: in FUNCTION: {}", c.origin.name, pe.message),
                    ));
                    functions.push(None);
                }
            }
        }
        let icvels = model
            .constraints
            .iter()
            .map(|c| match &c.kind {
                ConstraintKind::Motion { icvel, .. } => *icvel,
                _ => None,
            })
            .collect();
        if errors.is_empty() {
            Ok(ExpressionDrivers {
                functions,
                icvels,
                warnings,
            })
        } else {
            Err(Diagnostics(errors))
        }
    }

    /// ICVEL of a motion.
    fn icvel(&self, element: usize) -> Option<f64> {
        self.icvels.get(element).copied().flatten()
    }

    /// Non-fatal findings (USER subroutines).
    pub fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }

    /// Velocity and acceleration `(q̇, q̈)` a motion prescribes at time `t`, at any level:
    /// displacement `(ḟ, f̈)`, velocity `(f, ḟ)`, acceleration `(ICVEL + ∫₀ᵗ f, f)`.
    /// `None` for a motion without a function linkage can run; `Some(Err)` with the cause when
    /// the expression cannot be evaluated.
    pub fn motion_rates(&self, element: usize, t: f64) -> Option<Result<(f64, f64), DriveError>> {
        let (e, level, _) = self.functions.get(element)?.as_ref()?;
        let series = match evaluate_time_series(e, &TimeEnv { time: t, mode: 0 }) {
            Ok(s) => s,
            Err(err) => return Some(Err(DriveError::Function { cause: err.message })),
        };
        Some(match level {
            MotionLevel::Displacement => Ok((series[1], series[2])),
            MotionLevel::Velocity => Ok((series[0], series[1])),
            MotionLevel::Acceleration => {
                let f = |x: f64| {
                    evaluate_time_series(e, &TimeEnv { time: x, mode: 0 })
                        .map(|s| s[0])
                        .ok()
                };
                match integrate(&f, 0.0, t) {
                    Some(i) => Ok((self.icvel(element).unwrap_or(0.0) + i, series[0])),
                    None => Err(self.why_unknown(element, t)),
                }
            }
        })
    }

    /// Whether the motion is a velocity or acceleration motion without ICDISP (its start
    /// displacement is free, decided by the assembly).
    pub fn free_start(&self, element: usize) -> bool {
        matches!(
            self.functions.get(element),
            Some(Some((_, level, None))) if *level != MotionLevel::Displacement
        )
    }

    /// A copy whose velocity and acceleration motions without ICDISP start from the
    /// displacement they have in the assembled configuration `s` (Adams: the assembly decides a
    /// free start displacement; the motion then integrates from it). `rows` are the constraint
    /// rows in use; a motion's driven row measures its displacement.
    pub fn anchored(
        &self,
        sys: &crate::constraints::system::System,
        rows: &[usize],
        s: &State,
    ) -> Self {
        let mut out = self.clone();
        for &r in rows {
            let row = &sys.rows[r];
            if !row.driven {
                continue;
            }
            if !out.free_start(row.element) {
                continue;
            }
            // ICDISP is the displacement at time 0: the measured displacement at s.time minus
            // what the motion adds between 0 and s.time.
            let set = |out: &mut Self, v: f64| {
                if let Some(Some((_, _, icdisp))) = out.functions.get_mut(row.element) {
                    *icdisp = Some(v);
                }
            };
            set(&mut out, 0.0);
            let travelled = out.value(row.element, s.time).unwrap_or(0.0);
            set(&mut out, sys.residual(r, s, 0.0) - travelled);
        }
        out
    }

    /// `[f, ḟ, f̈]` of a displacement-level motion at time `t`.
    pub fn series(&self, element: usize, t: f64) -> Option<Result<[f64; 3], DriveError>> {
        let (e, level, _) = self.functions.get(element)?.as_ref()?;
        if *level != MotionLevel::Displacement {
            return None;
        }
        Some(
            evaluate_time_series(e, &TimeEnv { time: t, mode: 0 })
                .map_err(|err| DriveError::Function { cause: err.message }),
        )
    }
}

impl Drivers for ExpressionDrivers {
    /// Displacement motions: the function's Taylor series in time. Velocity motions:
    /// `[q(t), f(t), ḟ(t)]`; acceleration motions: `[q(t), ICVEL + ∫f, f(t)]`.
    fn rates(&self, element: usize, t: f64) -> Option<[f64; 3]> {
        let (vel, acc) = self.motion_rates(element, t)?.ok()?;
        Some([self.value(element, t)?, vel, acc])
    }

    /// The cause of an unknown value: the USER subroutine, the missing ICDISP, or the
    /// expression's error at `t` (or inside the quadrature of a velocity/acceleration motion).
    fn why_unknown(&self, element: usize, t: f64) -> DriveError {
        let Some(Some((e, level, icdisp))) = self.functions.get(element) else {
            return DriveError::NotRunnable;
        };
        if *level != MotionLevel::Displacement && icdisp.is_none() {
            return DriveError::NoStartDisplacement { level: *level };
        }
        if let Err(err) = evaluate_time_series(e, &TimeEnv { time: t, mode: 0 }) {
            return DriveError::Function { cause: err.message };
        }
        // The quadrature failed somewhere in [0, t]: find the first failing sample.
        let samples = 64;
        (0..=samples)
            .map(|i| t * i as f64 / samples as f64)
            .find_map(|x| {
                evaluate_time_series(e, &TimeEnv { time: x, mode: 0 })
                    .err()
                    .map(|err| DriveError::FunctionAt {
                        time: x,
                        cause: err.message,
                    })
            })
            .unwrap_or(DriveError::IntegralDiverges)
    }

    /// Displacement motions: `f(t)`. Velocity and acceleration motions: their ICDISP at t = 0
    /// when given, otherwise unknown (the start displacement is free).
    fn value(&self, element: usize, t: f64) -> Option<f64> {
        let (e, level, icdisp) = self.functions.get(element)?.as_ref()?;
        let f = |x: f64| {
            evaluate_time_series(e, &TimeEnv { time: x, mode: 0 })
                .map(|s| s[0])
                .ok()
        };
        match level {
            MotionLevel::Displacement => self.series(element, t)?.ok().map(|s| s[0]),
            // q(t) = ICDISP + ∫₀ᵗ f: the start displacement must be given.
            MotionLevel::Velocity => Some(icdisp.as_ref()? + integrate(&f, 0.0, t)?),
            // q(t) = ICDISP + ICVEL·t + ∫₀ᵗ (t − τ) f(τ) dτ.
            MotionLevel::Acceleration => {
                let icvel = self.icvel(element).unwrap_or(0.0);
                let g = |x: f64| f(x).map(|v| (t - x) * v);
                Some(icdisp.as_ref()? + icvel * t + integrate(&g, 0.0, t)?)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_of_smooth_functions() {
        let f = |x: f64| Some(x.sin());
        assert!((integrate(&f, 0.0, std::f64::consts::PI).unwrap() - 2.0).abs() < 1e-10);
        let g = |x: f64| Some(3.0 * x * x);
        assert!((integrate(&g, 0.0, 2.0).unwrap() - 8.0).abs() < 1e-10);
        assert_eq!(integrate(&g, 1.0, 1.0), Some(0.0));
        assert_eq!(integrate(&|_| None, 0.0, 1.0), None);
    }
}
