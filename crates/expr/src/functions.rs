//! Numerical definitions of the intrinsics and special functions, generic over the number
//! type so that values, gradients and time derivatives share one implementation.
//!
//! Non-smooth functions (ABS, MIN, MAX, SIGN, DIM, MOD, AINT, ANINT, the flat parts of the
//! steps, IMPACT/BISTOP switching) return the derivative of the branch that is active at the
//! current value.
//!
//! # Special functions
//!
//! With `Δ = (x − x0)/(x1 − x0)`:
//!
//! * `STEP(x, x0, h0, x1, h1)` = h0 for Δ ≤ 0, h1 for Δ ≥ 1, otherwise
//!   `h0 + (h1 − h0)·Δ²·(3 − 2Δ)`.
//! * `STEP5(x, x0, h0, x1, h1)` = h0 / h1 outside, otherwise `h0 + (h1 − h0)·Δ³·(10 − 15Δ + 6Δ²)`.
//! * `HAVSIN(x, x0, h0, x1, h1)` = h0 / h1 outside, otherwise
//!   `(h0 + h1)/2 + (h1 − h0)/2 · sin(π·Δ − π/2)`.
//!
//!   For the three steps `x0 = x1` is an error; with `x0 > x1` the step runs backwards
//!   (the formulas in Δ are applied unchanged).
//! * `SHF(x, x0, a, w, phi, b)` = `a·sin(w·(x − x0) − phi) + b`.
//! * `POLY(x, x0, a0, ..., a30)` = `Σ aj·(x − x0)^j`.
//! * `CHEBY(x, x0, a0, ..., a30)` = `Σ aj·Tj(x − x0)`, with `T0 = 1`, `T1 = u`,
//!   `Tj = 2u·T(j−1) − T(j−2)`.
//! * `FORCOS(x, x0, w, a0, ..., a30)` = `a0 + Σ_{j≥1} aj·cos(j·w·(x − x0))`.
//! * `FORSIN(x, x0, w, a0, ..., a30)` = `a0 + Σ_{j≥1} aj·sin(j·w·(x − x0))`.
//! * `IMPACT(x, xdot, x1, k, e, cmax, d)` = 0 for x ≥ x1, otherwise
//!   `max(0, k·(x1 − x)^e − STEP(x, x1 − d, cmax, x1, 0)·xdot)`.
//!   Requires k ≥ 0, e > 0, cmax ≥ 0, d > 0.
//! * `BISTOP(x, xdot, x1, x2, k, e, cmax, d)` =
//!   `max(k·(x1 − x)^e − STEP(x, x1 − d, cmax, x1, 0)·xdot, 0)` for x < x1;
//!   0 for x1 ≤ x ≤ x2;
//!   `min(−k·(x − x2)^e − STEP(x, x2, 0, x2 + d, cmax)·xdot, 0)` for x > x2.
//!   Requires x1 < x2 and the IMPACT parameter conditions.
//! * `AKISPL(x, z, id [, iord])`, `CUBSPL(x, z, id [, iord])`: see [`crate::spline`].

use std::f64::consts::{FRAC_PI_2, LN_10, PI};

use crate::catalog::{arity_message, Function, Intrinsic, Special};
use crate::error::EvalError;
use crate::num::Num;
use crate::spline::{SplineData, SplineMethod};

fn arity_error(f: Function, got: usize) -> EvalError {
    EvalError::invalid_argument(arity_message(f.name(), f.arity(), got))
}

/// `c · x^p` with an exact zero when `c` is zero.
fn coef_pow(c: f64, x: f64, p: f64) -> f64 {
    if c == 0.0 {
        0.0
    } else {
        c * x.powf(p)
    }
}

/// `b ** p` for a constant exponent `p`.
fn pow_const<N: Num>(b: &N, p: f64) -> N {
    let x = b.val();
    if p == 0.0 {
        return N::cst(1.0);
    }
    b.chain(
        x.powf(p),
        coef_pow(p, x, p - 1.0),
        coef_pow(p * (p - 1.0), x, p - 2.0),
    )
}

/// The `**` operator.
///
/// A negative base requires an integer exponent; a zero base requires a non-negative one.
/// When the base is not positive the exponent's own variation is ignored (its derivative is
/// undefined there).
pub(crate) fn pow<N: Num>(b: &N, e: &N) -> Result<N, EvalError> {
    let (x, p) = (b.val(), e.val());
    if x == 0.0 && p < 0.0 {
        return Err(EvalError::domain(format!(
            "division by zero in '**': 0 raised to the negative power {p}"
        )));
    }
    if x < 0.0 && p.fract() != 0.0 {
        return Err(EvalError::domain(format!(
            "'**' of negative number {x} to the non-integer power {p}"
        )));
    }
    if !e.varies() || x <= 0.0 {
        return Ok(pow_const(b, p));
    }
    // x > 0: x^p = exp(p·ln x); the value is taken from powf for accuracy.
    let ln = b.chain(x.ln(), 1.0 / x, -1.0 / (x * x));
    let arg = e.times(&ln);
    let v = arg.val().exp();
    Ok(arg.chain(v, v, v).with_value(x.powf(p)))
}

/// Checked division.
pub(crate) fn divide<N: Num>(a: &N, b: &N) -> Result<N, EvalError> {
    if b.val() == 0.0 {
        return Err(EvalError::domain(format!(
            "division by zero ({} / 0)",
            a.val()
        )));
    }
    Ok(a.over(b))
}

fn max_of<'a, N: Num>(a: &'a N, b: &'a N) -> &'a N {
    if b.val() > a.val() {
        b
    } else {
        a
    }
}

fn abs<N: Num>(x: &N) -> N {
    if x.val() < 0.0 {
        x.negate()
    } else {
        x.clone()
    }
}

fn atan<N: Num>(x: &N) -> N {
    let v = x.val();
    let q = 1.0 + v * v;
    x.chain(v.atan(), 1.0 / q, -2.0 * v / (q * q))
}

fn sin<N: Num>(x: &N) -> N {
    let (s, c) = x.val().sin_cos();
    x.chain(s, c, -s)
}

fn cos<N: Num>(x: &N) -> N {
    let (s, c) = x.val().sin_cos();
    x.chain(c, -s, -c)
}

/// `ATAN2(y, x)` with exact derivatives (an error when both are zero).
pub(crate) fn atan2<N: Num>(y: &N, x: &N) -> Result<N, EvalError> {
    let (yv, xv) = (y.val(), x.val());
    if yv == 0.0 && xv == 0.0 {
        return Err(EvalError::domain("ATAN2 with both arguments zero"));
    }
    let value = yv.atan2(xv);
    // Differentiate through atan(y/x) or π/2 − atan(x/y), whichever is well conditioned;
    // the branch offset is a constant, so only the value needs fixing.
    Ok(if xv.abs() >= yv.abs() {
        atan(&y.over(x)).with_value(value)
    } else {
        atan(&x.over(y)).negate().with_value(value)
    })
}

/// Evaluates a math intrinsic on already-evaluated arguments.
pub(crate) fn intrinsic<N: Num>(f: Intrinsic, args: &[N]) -> Result<N, EvalError> {
    use Intrinsic::*;
    match (f, args) {
        (Max | Min, [first, rest @ ..]) if !rest.is_empty() => {
            let mut best = first;
            for a in rest {
                best = match f {
                    Max => max_of(best, a),
                    _ => {
                        if a.val() < best.val() {
                            a
                        } else {
                            best
                        }
                    }
                };
            }
            Ok(best.clone())
        }
        (Atan2, [y, x]) => atan2(y, x),
        (Dim, [a, b]) => Ok(if a.val() > b.val() {
            a.minus(b)
        } else {
            N::cst(0.0)
        }),
        (Mod, [a, b]) => {
            if b.val() == 0.0 {
                return Err(EvalError::domain(format!(
                    "MOD with zero divisor (MOD({}, 0))",
                    a.val()
                )));
            }
            let q = (a.val() / b.val()).trunc();
            Ok(a.minus(&b.scale(q)))
        }
        (Sign, [a, b]) => Ok(if b.val() >= 0.0 {
            abs(a)
        } else {
            abs(a).negate()
        }),
        (_, [x]) => unary(f, x),
        _ => Err(arity_error(Function::Intrinsic(f), args.len())),
    }
}

fn unary<N: Num>(f: Intrinsic, x: &N) -> Result<N, EvalError> {
    use Intrinsic::*;
    let v = x.val();
    let out = match f {
        Abs => abs(x),
        Aint => N::cst(v.trunc()),
        Anint => N::cst(v.round()),
        Sin => sin(x),
        Cos => cos(x),
        Tan => {
            let t = v.tan();
            let d = 1.0 + t * t;
            x.chain(t, d, 2.0 * t * d)
        }
        Asin | Acos => {
            if !(-1.0..=1.0).contains(&v) {
                return Err(EvalError::domain(format!(
                    "{} of {v}, outside [-1, 1]",
                    f.name()
                )));
            }
            let r = 1.0 - v * v;
            let d1 = 1.0 / r.sqrt();
            let d2 = v / (r * r.sqrt());
            if f == Asin {
                x.chain(v.asin(), d1, d2)
            } else {
                x.chain(v.acos(), -d1, -d2)
            }
        }
        Atan => atan(x),
        Sinh => x.chain(v.sinh(), v.cosh(), v.sinh()),
        Cosh => x.chain(v.cosh(), v.sinh(), v.cosh()),
        Tanh => {
            let t = v.tanh();
            let d = 1.0 - t * t;
            x.chain(t, d, -2.0 * t * d)
        }
        Exp => {
            let e = v.exp();
            x.chain(e, e, e)
        }
        Log | Log10 => {
            if v <= 0.0 {
                return Err(EvalError::domain(format!(
                    "{} of non-positive number {v}",
                    f.name()
                )));
            }
            let k = if f == Log { 1.0 } else { 1.0 / LN_10 };
            x.chain(v.ln() * k, k / v, -k / (v * v))
        }
        Sqrt => {
            if v < 0.0 {
                return Err(EvalError::domain(format!("SQRT of negative number {v}")));
            }
            let s = v.sqrt();
            x.chain(s, 0.5 / s, -0.25 / (s * v))
        }
        Atan2 | Dim | Max | Min | Mod | Sign => {
            return Err(arity_error(Function::Intrinsic(f), 1));
        }
    };
    Ok(out)
}

/// The smooth transition shape of a step function at `d` = Δ in (0, 1).
fn step_shape<N: Num>(f: Special, d: &N) -> N {
    match f {
        Special::Step5 => {
            // Δ³·(10 − 15Δ + 6Δ²)
            let d3 = d.times(d).times(d);
            let poly = d.scale(6.0).add_cst(-15.0).times(d).add_cst(10.0);
            d3.times(&poly)
        }
        Special::Havsin => {
            // (1 + sin(πΔ − π/2)) / 2, so that the result is (h0+h1)/2 + (h1−h0)/2·sin(...)
            sin(&d.scale(PI).add_cst(-FRAC_PI_2))
                .add_cst(1.0)
                .scale(0.5)
        }
        _ => {
            // Δ²·(3 − 2Δ)
            d.times(d).times(&d.scale(-2.0).add_cst(3.0))
        }
    }
}

/// STEP, STEP5 and HAVSIN.
fn step_like<N: Num>(f: Special, x: &N, x0: &N, h0: &N, x1: &N, h1: &N) -> Result<N, EvalError> {
    let span = x1.minus(x0);
    if span.val() == 0.0 {
        return Err(EvalError::invalid_argument(format!(
            "{}: x0 and x1 must differ (both are {})",
            f.name(),
            x0.val()
        )));
    }
    let d = x.minus(x0).over(&span);
    Ok(if d.val() <= 0.0 {
        h0.clone()
    } else if d.val() >= 1.0 {
        h1.clone()
    } else {
        h0.plus(&h1.minus(h0).times(&step_shape(f, &d)))
    })
}

fn check_contact_parameters(
    name: &str,
    k: f64,
    e: f64,
    cmax: f64,
    d: f64,
) -> Result<(), EvalError> {
    let bad = |what: &str, v: f64| {
        Err(EvalError::invalid_argument(format!(
            "{name}: {what}, got {v}"
        )))
    };
    if k < 0.0 {
        return bad("stiffness k must not be negative", k);
    }
    if e <= 0.0 {
        return bad("exponent e must be positive", e);
    }
    if cmax < 0.0 {
        return bad("maximum damping cmax must not be negative", cmax);
    }
    if d <= 0.0 {
        return bad("penetration depth d must be positive", d);
    }
    Ok(())
}

/// `k·pen^e − damping` for the contact functions.
fn contact_force<N: Num>(k: &N, pen: &N, e: &N, step: &N, xdot: &N) -> Result<N, EvalError> {
    Ok(k.times(&pow(pen, e)?).minus(&step.times(xdot)))
}

fn impact<N: Num>(a: &[N; 7]) -> Result<N, EvalError> {
    let [x, xdot, x1, k, e, cmax, d] = a;
    check_contact_parameters("IMPACT", k.val(), e.val(), cmax.val(), d.val())?;
    if x.val() >= x1.val() {
        return Ok(N::cst(0.0));
    }
    let pen = x1.minus(x);
    let damp = step_like(Special::Step, x, &x1.minus(d), cmax, x1, &N::cst(0.0))?;
    let f = contact_force(k, &pen, e, &damp, xdot)?;
    Ok(if f.val() > 0.0 { f } else { N::cst(0.0) })
}

fn bistop<N: Num>(a: &[N; 8]) -> Result<N, EvalError> {
    let [x, xdot, x1, x2, k, e, cmax, d] = a;
    check_contact_parameters("BISTOP", k.val(), e.val(), cmax.val(), d.val())?;
    if x1.val() >= x2.val() {
        return Err(EvalError::invalid_argument(format!(
            "BISTOP: x1 must be less than x2, got x1 = {}, x2 = {}",
            x1.val(),
            x2.val()
        )));
    }
    let zero = N::cst(0.0);
    if x.val() < x1.val() {
        let damp = step_like(Special::Step, x, &x1.minus(d), cmax, x1, &zero)?;
        let f = contact_force(k, &x1.minus(x), e, &damp, xdot)?;
        Ok(if f.val() > 0.0 { f } else { zero })
    } else if x.val() > x2.val() {
        let damp = step_like(Special::Step, x, x2, &zero, &x2.plus(d), cmax)?;
        let spring = k.times(&pow(&x.minus(x2), e)?);
        let f = spring.negate().minus(&damp.times(xdot));
        Ok(if f.val() < 0.0 { f } else { zero })
    } else {
        Ok(zero)
    }
}

fn fixed<N: Num, const K: usize>(f: Special, args: &[N]) -> Result<[N; K], EvalError> {
    if args.len() != K {
        return Err(arity_error(Function::Special(f), args.len()));
    }
    let mut out: [N; K] = std::array::from_fn(|_| N::cst(0.0));
    for (slot, a) in out.iter_mut().zip(args) {
        *slot = a.clone();
    }
    Ok(out)
}

/// Evaluates a special function other than the splines on already-evaluated arguments.
pub(crate) fn special<N: Num>(f: Special, args: &[N]) -> Result<N, EvalError> {
    use Special::*;
    let (min, max) = Function::Special(f).arity();
    if args.len() < min || args.len() > max {
        return Err(arity_error(Function::Special(f), args.len()));
    }
    match f {
        Step | Step5 | Havsin => {
            let [x, x0, h0, x1, h1] = fixed::<N, 5>(f, args)?;
            step_like(f, &x, &x0, &h0, &x1, &h1)
        }
        Shf => {
            let [x, x0, a, w, phi, b] = fixed::<N, 6>(f, args)?;
            let arg = w.times(&x.minus(&x0)).minus(&phi);
            Ok(a.times(&sin(&arg)).plus(&b))
        }
        Poly => match args {
            [x, x0, coefs @ ..] => {
                let u = x.minus(x0);
                let mut acc = N::cst(0.0);
                for a in coefs.iter().rev() {
                    acc = acc.times(&u).plus(a);
                }
                Ok(acc)
            }
            _ => Err(arity_error(Function::Special(f), args.len())),
        },
        Cheby => match args {
            [x, x0, coefs @ ..] => {
                let u = x.minus(x0);
                let (mut t_prev, mut t) = (N::cst(1.0), u.clone());
                let mut acc = N::cst(0.0);
                for (j, a) in coefs.iter().enumerate() {
                    let tj = match j {
                        0 => N::cst(1.0),
                        1 => u.clone(),
                        _ => {
                            let next = u.times(&t).scale(2.0).minus(&t_prev);
                            t_prev = t;
                            t = next.clone();
                            next
                        }
                    };
                    acc = acc.plus(&a.times(&tj));
                }
                Ok(acc)
            }
            _ => Err(arity_error(Function::Special(f), args.len())),
        },
        Forcos | Forsin => match args {
            [x, x0, w, a0, coefs @ ..] => {
                let base = w.times(&x.minus(x0));
                let mut acc = a0.clone();
                for (j, a) in coefs.iter().enumerate() {
                    let arg = base.scale((j + 1) as f64);
                    let term = if f == Forcos { cos(&arg) } else { sin(&arg) };
                    acc = acc.plus(&a.times(&term));
                }
                Ok(acc)
            }
            _ => Err(arity_error(Function::Special(f), args.len())),
        },
        Impact => impact(&fixed::<N, 7>(f, args)?),
        Bistop => bistop(&fixed::<N, 8>(f, args)?),
        Akispl | Cubspl => Err(EvalError::invalid_argument(format!(
            "{} must be evaluated with its spline data",
            f.name()
        ))),
    }
}

/// Interpolates `data` at `(x, z)`, returning derivative order `iord` (0, 1 or 2) in x of the
/// spline, with the chain rule through `x` and `z`: for a 2-D spline the x-derivative of
/// `(1 − w)·y_k(x) + w·y_{k+1}(x)`, `w = (z − z_k)/(z_{k+1} − z_k)` ([`SplineData::bracket`]);
/// `z` is not read for a 1-D spline.
pub(crate) fn spline_surface<N: Num>(
    data: &SplineData,
    method: SplineMethod,
    x: &N,
    z: &N,
    iord: usize,
) -> N {
    let Some((lo, hi, z0, z1)) = data.bracket(z.val()) else {
        return spline(data, method, x, iord);
    };
    let s0 = spline(lo, method, x, iord);
    let s1 = spline(hi, method, x, iord);
    let w = z.add_cst(-z0).scale(1.0 / (z1 - z0));
    s0.plus(&w.times(&s1.minus(&s0)))
}

/// Interpolates a 1-D spline `data` at `x`, returning derivative order `iord` (0, 1 or 2),
/// with the chain rule through `x`.
pub(crate) fn spline<N: Num>(data: &SplineData, method: SplineMethod, x: &N, iord: usize) -> N {
    let [s0, s1, s2, s3] = data.evaluate(method, x.val());
    let d = [s0, s1, s2, s3, 0.0, 0.0];
    let g = |k: usize| d.get(iord + k).copied().unwrap_or(0.0);
    x.chain(g(0), g(1), g(2))
}

#[cfg(test)]
mod surface_tests {
    use super::*;

    /// Curves at z = 0 (y = x² at x = 0..3) and z = 1 (y = x + 1). Natural cubic of the first
    /// by hand: h = 1, M1 = M2 = 12/5, so on [1, 2] with u = x − 1:
    /// s = 1 + 1.8u + 1.2u² (b = m − (2M1 + M2)/6 = 3 − 1.2, c = M1/2, d = (M2 − M1)/6 = 0).
    /// The second curve is the straight line for either method.
    fn data() -> SplineData {
        SplineData::surface(
            vec![0.0, 1.0, 2.0, 3.0],
            vec![0.0, 1.0],
            vec![vec![0.0, 1.0, 4.0, 9.0], vec![1.0, 2.0, 3.0, 4.0]],
            false,
        )
        .unwrap()
    }

    #[test]
    fn a_surface_is_cubic_along_x_and_linear_between_curves() {
        let d = data();
        let at = |x: f64, z: f64, iord| spline_surface(&d, SplineMethod::Cubic, &x, &z, iord);
        // x = 1.5: s0 = 1 + 0.9 + 0.3 = 2.2, s1 = 2.5; z = 0.25: 0.75·2.2 + 0.25·2.5.
        assert!((at(1.5, 0.25, 0) - 2.275).abs() < 1e-12);
        // First x-derivative: s0' = 1.8 + 2.4u = 3.0, s1' = 1; second: s0'' = 2.4, s1'' = 0.
        assert!((at(1.5, 0.25, 1) - 2.5).abs() < 1e-12);
        assert!((at(1.5, 0.25, 2) - 1.8).abs() < 1e-12);
        // On a curve: that curve; beyond the last z, continued linearly (w = 2).
        assert!((at(1.5, 0.0, 0) - 2.2).abs() < 1e-12);
        assert!((at(1.5, 1.0, 0) - 2.5).abs() < 1e-12);
        assert!((at(1.5, 2.0, 0) - 2.8).abs() < 1e-12);
        assert!((at(1.5, -1.0, 0) - 1.9).abs() < 1e-12);
        // Akima on the straight line is the line too: at z = 1 both methods agree.
        let ak = spline_surface(&d, SplineMethod::Akima, &1.5, &1.0, 0);
        assert!((ak - 2.5).abs() < 1e-12);
    }

    #[test]
    fn surface_data_are_validated() {
        let x = vec![0.0, 1.0, 2.0];
        let bad_z =
            SplineData::surface(x.clone(), vec![1.0, 1.0], vec![x.clone(), x.clone()], false);
        assert!(bad_z.unwrap_err().message.contains("strictly increasing"));
        let one = SplineData::surface(x.clone(), vec![1.0], vec![x.clone()], false);
        assert!(one.unwrap_err().message.contains("at least two curves"));
        let short =
            SplineData::surface(x.clone(), vec![0.0, 1.0], vec![x.clone(), vec![1.0]], false);
        assert!(short.unwrap_err().message.contains("z = 1"));
    }
}
