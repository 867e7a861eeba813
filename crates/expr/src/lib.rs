//! # linkage-expr: the Adams function-expression language
//!
//! Parses and evaluates the expressions found in `FUNCTION=`, `FX=`, `VARIABLE`, `REQUEST`
//! ... arguments of MSC Adams datasets, with exact derivatives.
//!
//! This crate knows nothing about parts or markers: measures (`DX`, `VR`, `JOINT`, `VARVAL`,
//! ...) are evaluated through the [`Env`] trait, which the solver implements.
//!
//! ## Quick start
//!
//! ```
//! use linkage_expr::{parse, evaluate, evaluate_time_series, TimeEnv};
//!
//! let motion = parse("30.0d * time").unwrap();          // 30 degrees per unit time
//! let env = TimeEnv { time: 2.0, mode: 0 };
//! let [f, df, d2f] = evaluate_time_series(&motion, &env).unwrap();
//! assert!((f - 60f64.to_radians()).abs() < 1e-15);
//! assert!((df - 30f64.to_radians()).abs() < 1e-15 && d2f == 0.0);
//!
//! let e = parse("STEP(TIME, 0, 0, 1, 1)").unwrap();
//! let env = TimeEnv { time: 0.25, mode: 0 };
//! assert_eq!(evaluate(&e, &env).unwrap(), 0.15625);
//! ```
//!
//! Implementing an environment (the solver does this with its real kinematics):
//!
//! ```
//! use linkage_expr::{parse, evaluate_with_gradient, Dual, Env, EvalError, MarkerArgs, MeasureKind};
//!
//! /// One part sliding along x: variable 0 is its x coordinate, variable 1 its x velocity.
//! struct Slider { x: f64, vx: f64 }
//!
//! impl Env for Slider {
//!     fn time(&self) -> f64 { 0.0 }
//!     fn measure(&self, kind: MeasureKind, m: MarkerArgs, _gradient: bool)
//!         -> Result<Dual, EvalError> {
//!         match (kind, m.i) {
//!             (MeasureKind::Dx, 2) => Ok(Dual::variable(self.x, 0)),
//!             (MeasureKind::Vx, 2) => Ok(Dual::variable(self.vx, 1)),
//!             _ => Err(EvalError::unknown_reference(format!("MARKER/{} does not exist", m.i))),
//!         }
//!     }
//! }
//!
//! // A spring-damper force: -k·(x - 0.1) - c·vx
//! let f = parse("-100*(DX(2) - 0.1) - 2*VX(2)").unwrap();
//! let d = evaluate_with_gradient(&f, &Slider { x: 0.3, vx: 1.0 }).unwrap();
//! assert!((d.value() + 22.0).abs() < 1e-12);
//! assert_eq!(d.gradient(), &[(0, -100.0), (1, -2.0)]);
//! ```
//!
//! ## Syntax ([`parse`])
//!
//! * Numbers in FORTRAN style: `1`, `.4`, `1.`, `1.0E-04`, `5.0E-002`, `4.32E+09`. A `D`/`d`
//!   suffix means **degrees**: `30.0d` is 30·π/180. (`1.0D0`, a FORTRAN double exponent, is
//!   rejected.) Literals are never negative; `-1` is unary minus applied to `1`.
//! * Names are case-insensitive. Constants/system values: `PI`, `DTOR` (π/180), `RTOD`
//!   (180/π), `TIME`, `MODE`.
//! * Operators, lowest to highest precedence: binary `+ -`; `* / %`; unary `+ -` and `**`.
//!   All are left-associative except `**`, which is right-associative and binds tighter than a
//!   unary operator on its left but looser than one on its right:
//!   `2**3**2 = 512`, `-2**2 = -4`, `2*-3 = -6`, `-A**-B = -(A**(-B))`.
//! * Function calls `NAME(arg, ...)`; arithmetic `IF(test: lt, eq, gt)` (only the selected
//!   branch is evaluated); `USER(...)` parses into [`Expr::User`] and cannot be evaluated
//!   (check [`Expr::contains_user`] and report "user subroutine cannot be run") until it is
//!   linked to a subroutine ([`Expr::link_user`] → [`Expr::Linked`], [`user`]).
//! * Vectors `[x, y, z]` with `v+v`, `v-v`, `s*v`, `v*s`, `v/s`, `-v`, `v*v` (dot product →
//!   scalar) and `v%v` (cross product). Shapes are checked by the parser; the whole expression
//!   and every function argument must be scalar.
//! * Unknown names, wrong argument counts and shape errors are [`ParseError`]s at the byte
//!   offset of the name/operator. Trees deeper than [`MAX_DEPTH`] (256) or nested more than
//!   [`MAX_NESTING`] (64) levels are rejected, so that no input can overflow the stack.
//! * [`Expr`] implements `Display`, printing re-parseable text with minimal parentheses.
//!
//! ## Functions
//!
//! * Intrinsics ([`Intrinsic`]): `ABS ACOS AINT ANINT ASIN ATAN ATAN2 COS COSH DIM EXP LOG
//!   LOG10 MAX MIN MOD SIGN SIN SINH SQRT TAN TANH` with FORTRAN semantics.
//! * Special functions ([`Special`]): `STEP STEP5 HAVSIN SHF POLY CHEBY FORCOS FORSIN IMPACT
//!   BISTOP AKISPL CUBSPL`; exact formulas in [`functions`] and [`spline`].
//! * Measures ([`MeasureKind`]): `DX DY DZ DM VX VY VZ VM VR WX WY WZ WM ACCX ACCY ACCZ ACCM
//!   WDTX WDTY WDTZ WDTM AX AY AZ PSI THETA PHI YAW PITCH ROLL FX FY FZ FM TX TY TZ TM`
//!   → [`Env::measure`] with a [`MarkerArgs`] (roles per [`MeasureKind::marker_roles`]).
//! * Element forces ([`ElementForce`]): `JOINT JPRIM MOTION SFORCE SPDP BUSH FIELD BEAM VFORCE
//!   VTORQUE GFORCE` as `NAME(id, jflag, comp [, rm])` → [`Env::element_force`]; `jflag`
//!   must be 0/1 and `comp` 1..8 ([`ForceComponent`]).
//! * States ([`StateKind`]): `VARVAL(id) DIF(id) DIF1(id) ARYVAL(id, n) PINVAL(id, n) POUVAL(id, n) SENVAL(id)` → [`Env::state`].
//! * `ORIENT(system, component, i [, j])` ([`Function::Orient`]): Euler angles of the 12
//!   body-fixed and 12 space-fixed sequences, projection angles, yaw/pitch/roll, Euler and
//!   Rodrigues parameters, direction cosines ([`orient`] has the table), computed from the
//!   direction cosines that [`Env::rotation`] supplies.
//! * Splines: `AKISPL(x, z, id [, iord])`, `CUBSPL(...)` read [`SplineData`] from
//!   [`Env::spline`]; `z` is evaluated but ignored (1-D splines only); `iord` ∈ {0, 1, 2}.
//!   Build the data once with [`SplineData::new`]`(x, y, linear_extrapolate)`, which validates
//!   it and precomputes the Akima and natural-cubic coefficients.
//!
//! **Id arguments** (markers, element/VARIABLE/ARRAY/SPLINE ids, jflag, comp, rm, iord) are
//! expressions that must evaluate to non-negative integers (usually literals); anything else
//! is an [`EvalErrorKind::InvalidArgument`] error. **Omitted optional id arguments are passed
//! as 0**, which means ground/default: `DX(5)` is `DX(5, 0, 0)` = displacement of marker 5
//! from the ground origin in ground axes, `JOINT(1, 0, 2)` resolves in ground (`rm = 0`).
//!
//! ## Evaluation
//!
//! * [`evaluate`] → `f64` (fast; measures requested without gradient).
//! * [`evaluate_with_gradient`] → [`Dual`]: value and exact sparse gradient with respect to
//!   the environment's variables (forward-mode AD; the environment returns each measure's
//!   value and partial derivatives). `TIME` carries the derivative 1 for
//!   [`Env::time_variable`] if the environment defines one.
//! * [`evaluate_path_series`] → `[f, df/dt, d²f/dt²]` along the environment's current
//!   motion, exact via truncated Taylor arithmetic: TIME advances at [`Env::time_rate`],
//!   measures and direction cosines are the series of [`Env::measure_series`] and
//!   [`Env::rotation_series`] (the solver uses this for the second derivatives of general
//!   constraints). Element forces and states have no series
//!   ([`EvalErrorKind::NotTimeOnly`]).
//! * [`evaluate_time_series`] → the same for expressions of TIME only (MOTION functions):
//!   with an environment that supplies no series, any measure or state reference is an
//!   [`EvalErrorKind::NotTimeOnly`] error.
//!
//! Non-smooth functions (ABS, MIN, MAX, SIGN, DIM, MOD, AINT, ANINT, IF, the flat parts of
//! the steps, IMPACT/BISTOP switching) use the derivative of the branch active at the current
//! value. For `a**b` with a varying exponent and a base ≤ 0 the exponent's derivative
//! contribution is dropped (it is undefined there).
//!
//! Domain problems return an [`EvalError`] whose message names the function (`SQRT of
//! negative number -4`, `division by zero (1 / 0)`, `LOG of non-positive number 0`,
//! `ACOS of 2, outside [-1, 1]`, `AKISPL: SPLINE/7 does not exist`, overflow to a non-finite
//! value, non-finite derivative); the caller adds the element name and time. No input makes
//! the parser or evaluator panic.

#![warn(missing_docs)]

pub mod ast;
pub mod catalog;
pub mod dual;
pub mod env;
pub mod error;
mod eval;
pub mod functions;
mod lexer;
mod num;
pub mod orient;
pub mod parser;
pub mod spline;
mod taylor;
pub mod user;

pub use ast::{BinOp, Expr};
pub use catalog::{
    Constant, ElementForce, ForceComponent, Function, Intrinsic, MarkerRole, MeasureKind, Special,
    StateKind,
};
pub use dual::Dual;
pub use env::{ElementForceArgs, Env, MarkerArgs, StateRef, TimeEnv};
pub use error::{EvalError, EvalErrorKind, ParseError};
pub use eval::{evaluate, evaluate_path_series, evaluate_time_series, evaluate_with_gradient};
pub use orient::{orient, OrientSystem};
pub use parser::{parse, MAX_DEPTH, MAX_NESTING};
pub use spline::{SplineData, SplineError, SplineMethod};
pub use user::{Routine, UserRoutine};
