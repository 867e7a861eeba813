//! Control states as the analyses see them: what expressions read of them (`DIF`, `DIF1`,
//! `ARYVAL` of X and Y arrays, `PINVAL`, `POUVAL`) and the state equations of DIFF, LSE and
//! TFSISO elements with their exact Jacobians ([`ControlSet`]).
//!
//! Numbering of the gradient variables (what [`linkage_expr::Dual`]s carry), n parts and
//! nx control states: part k's tangent position coordinate c is `6k + c`, its velocity
//! coordinate c is `6n + 6k + c`, state i is `12n + i` and its rate `12n + nx + i`. The
//! states come after every part's columns, so force elements that index parts by their six
//! columns are unaffected.
//!
//! State equations, one residual per state (`r = 0` is the law):
//! - DIFF explicit: `r = ẏ − f(q, v, x, ẋ, t)`; IMPLICIT: `r = f(q, v, x, ẋ, t)` (ADM-ELEMENTS §6);
//! - LSE, TFSISO: `rᵢ = ẋᵢ − Σⱼ Aᵢⱼ xⱼ − Σⱼ Bᵢⱼ uⱼ`, `uⱼ = VARVAL` of the U array's VARIABLEs.

use crate::physics::applied::{ForceError, LawError};
use crate::physics::control_states::state_value;
pub use crate::physics::control_states::{read_state, state_variable};
use crate::physics::measures::StateEnv;
use crate::state::State;
use linkage_adm::{Function, Located};
use linkage_expr::{evaluate, evaluate_with_gradient, Dual, EvalError, Expr};
use linkage_model::controls::{DenseMatrix, StateLaw};
use linkage_model::{Model, Origin};

/// Parses and checks an expression argument of an element (`None`, its diagnostic recorded
/// by the caller, when it cannot be used).
pub type ParseArgument<'p> = dyn FnMut(&Located<Function>, &Origin, &str) -> Option<Expr> + 'p;

/// The law of one state element, ready to evaluate.
#[derive(Clone, Debug)]
enum Law {
    Diff {
        index: usize,
        expr: Expr,
        implicit: bool,
    },
    Linear {
        offset: usize,
        a: DenseMatrix,
        b: DenseMatrix,
        /// The U array's VARIABLE ids.
        inputs: Vec<u32>,
    },
}

/// A state element and how messages name it.
#[derive(Clone, Debug)]
struct Element {
    label: String,
    law: Law,
}

/// The state equations of a model's DIFF, LSE and TFSISO elements (module docs).
#[derive(Clone, Debug, Default)]
pub struct ControlSet {
    elements: Vec<Element>,
    count: usize,
}

impl ControlSet {
    /// The state equations of `model`; `parse` parses and checks an expression argument
    /// (`None`, with its diagnostic recorded by the caller, when it cannot be used).
    pub fn new(model: &Model, parse: &mut ParseArgument) -> ControlSet {
        let controls = &model.controls;
        let mut elements = Vec::with_capacity(controls.states.len());
        for e in &controls.states {
            let law = match &e.law {
                StateLaw::Diff { function, implicit } => {
                    let Some(expr) = parse(function, &e.origin, "FUNCTION") else {
                        continue;
                    };
                    Law::Diff {
                        index: e.offset,
                        expr,
                        implicit: *implicit,
                    }
                }
                StateLaw::Linear(l) => Law::Linear {
                    offset: e.offset,
                    a: l.a.clone(),
                    b: l.b.clone(),
                    inputs: l
                        .inputs
                        .iter()
                        .filter_map(|&k| u32::try_from(model.variables[k].origin.id).ok())
                        .collect(),
                },
            };
            elements.push(Element {
                label: e.origin.label(),
                law,
            });
        }
        ControlSet {
            elements,
            count: controls.count,
        }
    }

    /// Number of control states.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The error of element `label` at `s`.
    fn error(label: &str, s: &State, e: EvalError) -> ForceError {
        ForceError {
            element: label.to_string(),
            time: s.time,
            cause: LawError::Expression {
                argument: "FUNCTION",
                cause: e.message,
            },
        }
    }

    /// The residual of every element, generic over values (`f64` via `Dual::constant`) and
    /// values with gradients; `sink(i, rᵢ)` for state i.
    fn each(
        &self,
        env: &StateEnv,
        gradient: bool,
        mut sink: impl FnMut(usize, Dual),
    ) -> Result<(), ForceError> {
        let s = env.state;
        let x = |i: usize| state_value(s, i, false, gradient);
        let xd = |i: usize| state_value(s, i, true, gradient);
        for e in &self.elements {
            match &e.law {
                Law::Diff {
                    index,
                    expr,
                    implicit,
                } => {
                    let f = if gradient {
                        evaluate_with_gradient(expr, env)
                    } else {
                        evaluate(expr, env).map(Dual::constant)
                    }
                    .map_err(|err| Self::error(&e.label, s, err))?;
                    sink(*index, if *implicit { f } else { xd(*index) - f });
                }
                Law::Linear {
                    offset,
                    a,
                    b,
                    inputs,
                } => {
                    let mut u = Vec::with_capacity(inputs.len());
                    for &var in inputs {
                        u.push(
                            env.varval_of(var, gradient)
                                .map_err(|err| Self::error(&e.label, s, err))?,
                        );
                    }
                    for i in 0..a.rows {
                        let mut r = xd(offset + i);
                        for j in 0..a.columns {
                            let c = a.get(i, j);
                            if c != 0.0 {
                                r = r - x(offset + j) * c;
                            }
                        }
                        for (j, uj) in u.iter().enumerate() {
                            let c = b.get(i, j);
                            if c != 0.0 {
                                r = r - uj.clone() * c;
                            }
                        }
                        sink(offset + i, r);
                    }
                }
            }
        }
        Ok(())
    }

    /// The residuals `r(q, v, x, ẋ, t)` at `env`'s state into `out` (length [`Self::count`]).
    pub fn residuals(&self, env: &StateEnv, out: &mut [f64]) -> Result<(), ForceError> {
        out.fill(0.0);
        self.each(env, false, |i, r| out[i] = r.value())
    }

    /// `∂r/∂(q, v, x, ẋ)` at `env`'s state as `(state, variable, value)` triplets in the
    /// numbering of the module docs.
    pub fn jacobian(
        &self,
        env: &StateEnv,
        out: &mut Vec<(usize, usize, f64)>,
    ) -> Result<(), ForceError> {
        self.each(env, true, |i, r| {
            out.extend(r.gradient().iter().map(|&(var, d)| (i, var as usize, d)))
        })
    }
}

/// Solves `a·x = b` in place (`a` dense n × n, row-major; `b` becomes x) by Gaussian
/// elimination with partial pivoting; false when a pivot is below `tiny`.
pub fn solve_dense(a: &mut [f64], n: usize, b: &mut [f64], tiny: f64) -> bool {
    for k in 0..n {
        let Some(p) = (k..n).max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs()))
        else {
            return false;
        };
        if a[p * n + k].abs() <= tiny {
            return false;
        }
        if p != k {
            for j in 0..n {
                a.swap(p * n + j, k * n + j);
            }
            b.swap(p, k);
        }
        for i in k + 1..n {
            let f = a[i * n + k] / a[k * n + k];
            if f != 0.0 {
                for j in k..n {
                    a[i * n + j] -= f * a[k * n + j];
                }
                b[i] -= f * b[k];
            }
        }
    }
    for k in (0..n).rev() {
        let mut x = b[k];
        for j in k + 1..n {
            x -= a[k * n + j] * b[j];
        }
        b[k] = x / a[k * n + k];
    }
    true
}

/// Most Newton iterations of [`consistent_rates`].
const RATE_ITERATIONS: usize = 20;

/// The rates `ẋ` consistent with the state equations at positions, velocities and states
/// `s`, `v`: Newton on `r(ẋ) = 0` with `∂r/∂ẋ` (one iteration for explicit DIFFs and linear
/// elements, whose residuals are linear in ẋ). A state whose equation does not involve its
/// rate (an IMPLICIT DIFF that is an algebraic equation) keeps its rate from `s` (its IC
/// guess), as Adams' "approximate initial ẏ". Cost: O(nx³) per iteration (dense).
pub fn consistent_rates(
    forces: &dyn crate::physics::applied::AppliedForces,
    s: &mut State,
    v: &crate::constraints::rows::Velocities,
) -> Result<(), ForceError> {
    let nx = forces.control_count();
    if nx == 0 {
        return Ok(());
    }
    let n = s.poses.len();
    let mut r = vec![0.0; nx];
    let mut jac = Vec::new();
    let mut a = vec![0.0; nx * nx];
    for _ in 0..RATE_ITERATIONS {
        forces.control_residuals(s, v, &mut r)?;
        jac.clear();
        forces.control_jacobian(s, v, &mut jac)?;
        a.fill(0.0);
        for &(i, var, d) in &jac {
            if let Some(j) = var.checked_sub(12 * n + nx).filter(|j| *j < nx) {
                a[i * nx + j] += d;
            }
        }
        // Rows without a rate: the rate stays.
        for i in 0..nx {
            if a[i * nx..(i + 1) * nx].iter().all(|x| *x == 0.0) {
                a[i * nx + i] = 1.0;
                r[i] = 0.0;
            }
        }
        let scale = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if scale == 0.0 {
            return Ok(());
        }
        for x in r.iter_mut() {
            *x = -*x;
        }
        if !solve_dense(&mut a, nx, &mut r, 0.0) {
            return Ok(());
        }
        let mut moved = 0.0f64;
        for (xd, d) in s.controls.xdot.iter_mut().zip(&r) {
            *xd += d;
            moved = moved.max(d.abs() / xd.abs().max(1.0));
        }
        if moved <= 1e-14 {
            return Ok(());
        }
    }
    Ok(())
}
