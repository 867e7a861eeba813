//! The number abstraction the evaluator is generic over.
//!
//! Three implementations: `f64` (plain values), [`Dual`] (value + sparse gradient) and
//! [`Taylor`] (truncated Taylor series in time: MOTION functions, and expressions along a path
//! of the model through [`Env::measure_series`]). Every elementary
//! function is expressed through [`Num::chain`], which applies a scalar function given its
//! value and first two derivatives at the current point; this is exact to the order each
//! type carries.

use crate::catalog::MeasureKind;
use crate::dual::Dual;
use crate::env::{Env, MarkerArgs};
use crate::error::EvalError;
use crate::taylor::Taylor;

pub(crate) trait Num: Clone + Sized {
    /// Whether measures should be requested with gradients.
    const GRADIENT: bool;

    fn cst(v: f64) -> Self;
    fn val(&self) -> f64;
    fn plus(&self, o: &Self) -> Self;
    fn minus(&self, o: &Self) -> Self;
    fn times(&self, o: &Self) -> Self;
    /// Division; the caller has checked that the divisor is non-zero.
    fn over(&self, o: &Self) -> Self;
    fn negate(&self) -> Self;
    fn scale(&self, c: f64) -> Self;
    fn add_cst(&self, c: f64) -> Self;
    /// `g(self)` where `g(v) = g0`, `g'(v) = g1`, `g''(v) = g2` at the current value `v`.
    fn chain(&self, g0: f64, g1: f64, g2: f64) -> Self;
    /// True if the number carries a non-zero derivative.
    fn varies(&self) -> bool;
    /// Replaces the value, keeping the derivative part.
    fn with_value(self, v: f64) -> Self;
    /// True if the value and every derivative are finite.
    fn all_finite(&self) -> bool;

    /// The current time.
    fn time<E: Env + ?Sized>(env: &E) -> Self;
    /// A marker measure from the environment.
    fn measure<E: Env + ?Sized>(
        env: &E,
        kind: MeasureKind,
        m: MarkerArgs,
    ) -> Result<Self, EvalError>;
    /// The direction cosines of marker `i` relative to `j` ([`Env::rotation`]).
    fn rotation<E: Env + ?Sized>(env: &E, i: u32, j: u32) -> Result<[Self; 9], EvalError>;
    /// Converts a value supplied by the environment for `what` (an element force or a state).
    fn from_env(d: Dual, what: &str) -> Result<Self, EvalError>;
    /// The value of a linked user subroutine with parameters `params`.
    fn user(
        routine: &dyn crate::user::UserRoutine,
        params: &[f64],
        env: &dyn Env,
    ) -> Result<Self, EvalError>;
}

impl Num for f64 {
    const GRADIENT: bool = false;

    fn cst(v: f64) -> Self {
        v
    }
    fn val(&self) -> f64 {
        *self
    }
    fn plus(&self, o: &Self) -> Self {
        self + o
    }
    fn minus(&self, o: &Self) -> Self {
        self - o
    }
    fn times(&self, o: &Self) -> Self {
        self * o
    }
    fn over(&self, o: &Self) -> Self {
        self / o
    }
    fn negate(&self) -> Self {
        -self
    }
    fn scale(&self, c: f64) -> Self {
        self * c
    }
    fn add_cst(&self, c: f64) -> Self {
        self + c
    }
    fn chain(&self, g0: f64, _g1: f64, _g2: f64) -> Self {
        g0
    }
    fn varies(&self) -> bool {
        false
    }
    fn with_value(self, v: f64) -> Self {
        v
    }
    fn all_finite(&self) -> bool {
        self.is_finite()
    }
    fn time<E: Env + ?Sized>(env: &E) -> Self {
        env.time()
    }
    fn measure<E: Env + ?Sized>(
        env: &E,
        kind: MeasureKind,
        m: MarkerArgs,
    ) -> Result<Self, EvalError> {
        Ok(env.measure(kind, m, false)?.value())
    }
    fn rotation<E: Env + ?Sized>(env: &E, i: u32, j: u32) -> Result<[Self; 9], EvalError> {
        Ok(env.rotation(i, j, false)?.map(|d| d.value()))
    }
    fn from_env(d: Dual, _what: &str) -> Result<Self, EvalError> {
        Ok(d.value())
    }
    fn user(
        routine: &dyn crate::user::UserRoutine,
        params: &[f64],
        env: &dyn Env,
    ) -> Result<Self, EvalError> {
        routine.evaluate(params, env, false).map(|d| d.value())
    }
}

impl Num for Dual {
    const GRADIENT: bool = true;

    fn cst(v: f64) -> Self {
        Dual::constant(v)
    }
    fn val(&self) -> f64 {
        self.value()
    }
    fn plus(&self, o: &Self) -> Self {
        self.add_ref(o)
    }
    fn minus(&self, o: &Self) -> Self {
        self.sub_ref(o)
    }
    fn times(&self, o: &Self) -> Self {
        self.mul_ref(o)
    }
    fn over(&self, o: &Self) -> Self {
        self.div_ref(o)
    }
    fn negate(&self) -> Self {
        self.neg_ref()
    }
    fn scale(&self, c: f64) -> Self {
        Dual::scale(self, c)
    }
    fn add_cst(&self, c: f64) -> Self {
        self.clone().with_value(self.value() + c)
    }
    fn chain(&self, g0: f64, g1: f64, _g2: f64) -> Self {
        self.map(g0, g1)
    }
    fn varies(&self) -> bool {
        !self.is_constant()
    }
    fn with_value(self, v: f64) -> Self {
        Dual::with_value(self, v)
    }
    fn all_finite(&self) -> bool {
        self.value().is_finite() && self.gradient().iter().all(|&(_, d)| d.is_finite())
    }
    fn time<E: Env + ?Sized>(env: &E) -> Self {
        match env.time_variable() {
            Some(index) => Dual::variable(env.time(), index),
            None => Dual::constant(env.time()),
        }
    }
    fn measure<E: Env + ?Sized>(
        env: &E,
        kind: MeasureKind,
        m: MarkerArgs,
    ) -> Result<Self, EvalError> {
        env.measure(kind, m, true)
    }
    fn rotation<E: Env + ?Sized>(env: &E, i: u32, j: u32) -> Result<[Self; 9], EvalError> {
        env.rotation(i, j, true)
    }
    fn from_env(d: Dual, _what: &str) -> Result<Self, EvalError> {
        Ok(d)
    }
    fn user(
        routine: &dyn crate::user::UserRoutine,
        params: &[f64],
        env: &dyn Env,
    ) -> Result<Self, EvalError> {
        routine.evaluate(params, env, true)
    }
}

impl Num for Taylor {
    const GRADIENT: bool = false;

    fn cst(v: f64) -> Self {
        Taylor::constant(v)
    }
    fn val(&self) -> f64 {
        self.c[0]
    }
    fn plus(&self, o: &Self) -> Self {
        Taylor::add(self, o)
    }
    fn minus(&self, o: &Self) -> Self {
        Taylor::sub(self, o)
    }
    fn times(&self, o: &Self) -> Self {
        Taylor::mul(self, o)
    }
    fn over(&self, o: &Self) -> Self {
        Taylor::div(self, o)
    }
    fn negate(&self) -> Self {
        self.scale(-1.0)
    }
    fn scale(&self, c: f64) -> Self {
        Taylor::scale(self, c)
    }
    fn add_cst(&self, c: f64) -> Self {
        let mut t = *self;
        t.c[0] += c;
        t
    }
    fn chain(&self, g0: f64, g1: f64, g2: f64) -> Self {
        Taylor::chain(self, g0, g1, g2)
    }
    fn varies(&self) -> bool {
        self.c[1] != 0.0 || self.c[2] != 0.0
    }
    fn with_value(mut self, v: f64) -> Self {
        self.c[0] = v;
        self
    }
    fn all_finite(&self) -> bool {
        self.c.iter().all(|x| x.is_finite())
    }
    fn time<E: Env + ?Sized>(env: &E) -> Self {
        Taylor::from_derivatives([env.time(), env.time_rate(), 0.0])
    }
    fn measure<E: Env + ?Sized>(
        env: &E,
        kind: MeasureKind,
        m: MarkerArgs,
    ) -> Result<Self, EvalError> {
        Ok(Taylor::from_derivatives(env.measure_series(kind, m)?))
    }
    fn rotation<E: Env + ?Sized>(env: &E, i: u32, j: u32) -> Result<[Self; 9], EvalError> {
        Ok(env.rotation_series(i, j)?.map(Taylor::from_derivatives))
    }
    fn from_env(_d: Dual, what: &str) -> Result<Self, EvalError> {
        Err(EvalError::not_time_only(what))
    }
    fn user(
        routine: &dyn crate::user::UserRoutine,
        params: &[f64],
        env: &dyn Env,
    ) -> Result<Self, EvalError> {
        routine.series(params, env).map(Taylor::from_derivatives)
    }
}
