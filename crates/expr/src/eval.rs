//! Tree-walking evaluator, generic over the number type.

use crate::ast::{BinOp, Expr};
use crate::catalog::{
    arity_message, Constant, ElementForce, ForceComponent, Function, MarkerRole, MeasureKind,
    Special, StateKind,
};
use crate::dual::Dual;
use crate::env::{ElementForceArgs, Env, MarkerArgs, StateRef};
use crate::error::{EvalError, EvalErrorKind};
use crate::functions;
use crate::num::Num;
use crate::orient::OrientValue;
use crate::spline::SplineMethod;
use crate::taylor::Taylor;

/// π/180.
pub(crate) const DTOR: f64 = std::f64::consts::PI / 180.0;

/// Evaluates `expr` to a plain value (no derivatives). Measures are requested from `env`
/// with `gradient = false`.
pub fn evaluate<E: Env + ?Sized>(expr: &Expr, env: &E) -> Result<f64, EvalError> {
    Evaluator { env }.scalar::<f64>(expr)
}

/// Evaluates `expr` with exact first derivatives with respect to the environment's variables
/// (forward-mode AD). Measures are requested with `gradient = true`.
///
/// Fails with [`EvalErrorKind::Domain`] if a derivative is not finite (e.g. `SQRT` at 0 of a
/// varying argument).
pub fn evaluate_with_gradient<E: Env + ?Sized>(expr: &Expr, env: &E) -> Result<Dual, EvalError> {
    let d = Evaluator { env }.scalar::<Dual>(expr)?;
    if !d.all_finite() {
        return Err(EvalError::domain(
            "derivative is not finite: the expression is not differentiable here \
             (e.g. SQRT or '**' of a varying quantity at 0)",
        ));
    }
    Ok(d)
}

/// Evaluates an expression of TIME only, returning `[f, df/dt, d²f/dt²]` exactly (truncated
/// Taylor arithmetic in t). A measure or state reference gives an
/// [`EvalErrorKind::NotTimeOnly`] error ("a MOTION function must depend on time only ...")
/// with environments that supply no series (such as [`crate::TimeEnv`]); it is
/// [`evaluate_path_series`] under the name MOTION functions use.
pub fn evaluate_time_series<E: Env + ?Sized>(expr: &Expr, env: &E) -> Result<[f64; 3], EvalError> {
    evaluate_path_series(expr, env)
}

/// Evaluates `expr` along the environment's current motion, returning
/// `[f, df/dt, d²f/dt²]` exactly (truncated Taylor arithmetic to second order).
///
/// `TIME` is the series `[t, ṫ, 0]` with `ṫ =` [`Env::time_rate`] (1 unless the environment
/// freezes time); measures and direction cosines (`ORIENT`) are the series the environment
/// returns from [`Env::measure_series`] and [`Env::rotation_series`]. With an expression
/// `f(m(t), t)` of measures `m` this is the total derivative
/// `ḟ = f_m·ṁ + f_t·ṫ`,
/// `f̈ = f_m·m̈ + ṁᵀ f_mm ṁ + 2 ṫ f_mt·ṁ + ṫ² f_tt`:
/// an environment that moves the model with given velocities and zero accelerations gets
/// the velocity-product ("bias") term of a constraint's acceleration equation, and one that
/// freezes time and moves along a unit tangent direction u gets `uᵀ ∇²f u`.
///
/// Element forces and states (`JOINT(…)`, `VARVAL`, …) have no series: an
/// [`EvalErrorKind::NotTimeOnly`] error. Non-finite results are a domain error.
pub fn evaluate_path_series<E: Env + ?Sized>(expr: &Expr, env: &E) -> Result<[f64; 3], EvalError> {
    let t = Evaluator { env }.scalar::<Taylor>(expr)?;
    // The series holds f''/2: the derivative itself can overflow where the coefficient did not.
    let d = t.derivatives();
    if !t.all_finite() || d.iter().any(|x| !x.is_finite()) {
        return Err(EvalError::domain(
            "time derivative is not finite: the expression is not differentiable here",
        ));
    }
    Ok(d)
}

/// A value during evaluation: scalar or 3-vector (inline: evaluation does not allocate).
enum Val<N> {
    S(N),
    V([N; 3]),
}

struct Evaluator<'a, E: ?Sized> {
    env: &'a E,
}

fn mismatch(what: &str) -> EvalError {
    EvalError::invalid_argument(format!("{what}: scalar/vector mismatch"))
}

fn finite<N: Num>(n: N, what: impl FnOnce() -> String) -> Result<N, EvalError> {
    if n.val().is_finite() {
        Ok(n)
    } else {
        Err(EvalError::domain(format!(
            "{} is not finite (overflow)",
            what()
        )))
    }
}

impl<E: Env + ?Sized> Evaluator<'_, E> {
    fn scalar<N: Num>(&self, e: &Expr) -> Result<N, EvalError> {
        match self.eval::<N>(e)? {
            Val::S(n) => Ok(n),
            Val::V(_) => Err(EvalError::invalid_argument(
                "vector expression used where a scalar is required",
            )),
        }
    }

    fn eval<N: Num>(&self, e: &Expr) -> Result<Val<N>, EvalError> {
        Ok(match e {
            Expr::Number(v) => Val::S(N::cst(*v)),
            Expr::Degrees(v) => Val::S(N::cst(v * DTOR)),
            Expr::Constant(c) => Val::S(match c {
                Constant::Pi => N::cst(std::f64::consts::PI),
                Constant::Dtor => N::cst(DTOR),
                Constant::Rtod => N::cst(180.0 / std::f64::consts::PI),
                Constant::Time => N::time(self.env),
                Constant::Mode => N::cst(f64::from(self.env.mode())),
            }),
            Expr::Neg(x) => match self.eval::<N>(x)? {
                Val::S(n) => Val::S(n.negate()),
                Val::V(v) => Val::V(v.map(|c| c.negate())),
            },
            Expr::Binary { op, lhs, rhs } => {
                let l = self.eval::<N>(lhs)?;
                let r = self.eval::<N>(rhs)?;
                binary(*op, l, r)?
            }
            Expr::Vector(items) => {
                let [x, y, z] = items.as_ref();
                Val::V([self.scalar(x)?, self.scalar(y)?, self.scalar(z)?])
            }
            Expr::If { test, lt, eq, gt } => {
                let t = self.scalar::<N>(test)?.val();
                let branch = if t < 0.0 {
                    lt
                } else if t > 0.0 {
                    gt
                } else {
                    eq
                };
                Val::S(self.scalar(branch)?)
            }
            Expr::Call { func, args } => Val::S(self.call::<N>(*func, args)?),
            Expr::User(_) => {
                return Err(EvalError::new(
                    EvalErrorKind::UserSubroutine,
                    "USER subroutine cannot be run",
                ))
            }
            Expr::Linked { routine, args } => {
                let params = args
                    .iter()
                    .map(|a| self.scalar::<f64>(a))
                    .collect::<Result<Vec<f64>, EvalError>>()?;
                let env = crate::user::Forward(self.env);
                Val::S(N::user(&*routine.0, &params, &env)?)
            }
        })
    }

    fn call<N: Num>(&self, func: Function, args: &[Expr]) -> Result<N, EvalError> {
        let (min, max) = func.arity();
        if args.len() < min || args.len() > max {
            return Err(EvalError::invalid_argument(arity_message(
                func.name(),
                (min, max),
                args.len(),
            )));
        }
        let result = match func {
            Function::Intrinsic(f) => {
                self.with_scalars::<N, _>(args, |vals| functions::intrinsic(f, vals))?
            }
            Function::Special(f @ (Special::Akispl | Special::Cubspl)) => {
                self.spline::<N>(f, args)?
            }
            Function::Special(f) => {
                self.with_scalars::<N, _>(args, |vals| functions::special(f, vals))?
            }
            Function::Measure(kind) => self.measure::<N>(kind, args)?,
            Function::ElementForce(kind) => self.element_force::<N>(kind, args)?,
            Function::State(kind) => self.state::<N>(kind, args)?,
            Function::Orient => self.orient::<N>(args)?,
        };
        finite(result, || format!("the result of {}", func.name()))
    }

    /// Evaluates `args` as scalars and passes them to `f` (on the stack for short lists).
    fn with_scalars<N: Num, R>(
        &self,
        args: &[Expr],
        f: impl FnOnce(&[N]) -> Result<R, EvalError>,
    ) -> Result<R, EvalError> {
        const SHORT: usize = 8;
        if args.len() <= SHORT {
            let mut buf: [N; SHORT] = std::array::from_fn(|_| N::cst(0.0));
            for (slot, a) in buf.iter_mut().zip(args) {
                *slot = self.scalar::<N>(a)?;
            }
            f(buf.get(..args.len()).unwrap_or_default())
        } else {
            let vals = args
                .iter()
                .map(|a| self.scalar::<N>(a))
                .collect::<Result<Vec<N>, _>>()?;
            f(&vals)
        }
    }

    /// Evaluates argument `pos` (0-based) of `name` as a non-negative integer.
    fn integer_arg(
        &self,
        name: &str,
        pos: usize,
        what: &str,
        arg: &Expr,
    ) -> Result<u32, EvalError> {
        let v = self.scalar::<f64>(arg)?;
        if v.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&v) {
            // Exact: v is a whole number in u32 range.
            Ok(v as u32)
        } else {
            Err(EvalError::invalid_argument(format!(
                "{name}: argument {} ({what}) must be a non-negative integer, got {v}",
                pos + 1
            )))
        }
    }

    fn optional_integer_arg(
        &self,
        name: &str,
        pos: usize,
        what: &str,
        args: &[Expr],
    ) -> Result<u32, EvalError> {
        match args.get(pos) {
            Some(a) => self.integer_arg(name, pos, what, a),
            None => Ok(0),
        }
    }

    fn measure<N: Num>(&self, kind: MeasureKind, args: &[Expr]) -> Result<N, EvalError> {
        let name = kind.name();
        let mut m = MarkerArgs::default();
        for (pos, (arg, role)) in args.iter().zip(kind.marker_roles()).enumerate() {
            let id = self.integer_arg(name, pos, "marker id", arg)?;
            match role {
                MarkerRole::I => m.i = id,
                MarkerRole::J => m.j = id,
                MarkerRole::K => m.k = id,
                MarkerRole::L => m.l = id,
            }
        }
        let value = N::measure(self.env, kind, m)?;
        if !value.val().is_finite() {
            return Err(EvalError::domain(format!(
                "{name} returned the non-finite value {}",
                value.val()
            )));
        }
        Ok(value)
    }

    /// `ORIENT(system, component, i [, j])`.
    fn orient<N: Num>(&self, args: &[Expr]) -> Result<N, EvalError> {
        const NAME: &str = "ORIENT";
        let arg = |pos: usize, what: &str| self.optional_integer_arg(NAME, pos, what, args);
        let system = arg(0, "orientation system")?;
        let component = arg(1, "component")?;
        let i = arg(2, "marker id")?;
        let j = arg(3, "marker id")?;
        let what = OrientValue::new(system, component)?;
        let r = N::rotation(self.env, i, j)?;
        if r.iter().any(|x| !x.val().is_finite()) {
            return Err(EvalError::domain(
                "ORIENT: the environment returned non-finite direction cosines",
            ));
        }
        what.evaluate(&r, self.env.euler313_previous(i, j))
    }

    fn element_force<N: Num>(&self, kind: ElementForce, args: &[Expr]) -> Result<N, EvalError> {
        let name = kind.name();
        let arg = |pos: usize, what: &str| self.optional_integer_arg(name, pos, what, args);
        let id = arg(0, "element id")?;
        let jflag = arg(1, "jflag")?;
        let comp = arg(2, "component")?;
        let rm = arg(3, "rm marker id")?;
        if jflag > 1 {
            return Err(EvalError::invalid_argument(format!(
                "{name}: jflag must be 0 (I marker) or 1 (J marker), got {jflag}"
            )));
        }
        let Some(component) = ForceComponent::from_code(comp) else {
            return Err(EvalError::invalid_argument(format!(
                "{name}: component must be 1..8 (FM, FX, FY, FZ, TM, TX, TY, TZ), got {comp}"
            )));
        };
        let a = ElementForceArgs {
            id,
            on_j: jflag == 1,
            component,
            rm,
        };
        let d = self.env.element_force(kind, a, N::GRADIENT)?;
        from_env::<N>(d, name)
    }

    fn state<N: Num>(&self, kind: StateKind, args: &[Expr]) -> Result<N, EvalError> {
        let name = kind.name();
        let id = self.optional_integer_arg(name, 0, "id", args)?;
        let s = match kind {
            StateKind::Varval => StateRef::Varval(id),
            StateKind::Dif => StateRef::Dif(id),
            StateKind::Dif1 => StateRef::Dif1(id),
            StateKind::Senval => StateRef::Senval(id),
            StateKind::Aryval | StateKind::Pinval | StateKind::Pouval => {
                let index = self.optional_integer_arg(name, 1, "index", args)?;
                if index == 0 {
                    return Err(EvalError::invalid_argument(format!(
                        "{name}: the index (argument 2) is 1-based and must be at least 1"
                    )));
                }
                match kind {
                    StateKind::Aryval => StateRef::Aryval { id, index },
                    StateKind::Pinval => StateRef::Pinval { id, index },
                    _ => StateRef::Pouval { id, index },
                }
            }
        };
        let d = self.env.state(s, N::GRADIENT)?;
        from_env::<N>(d, name)
    }

    fn spline<N: Num>(&self, f: Special, args: &[Expr]) -> Result<N, EvalError> {
        let name = f.name();
        let (Some(x_arg), Some(z_arg), Some(id_arg)) = (args.first(), args.get(1), args.get(2))
        else {
            return Err(EvalError::invalid_argument(arity_message(
                name,
                Function::Special(f).arity(),
                args.len(),
            )));
        };
        let x = self.scalar::<N>(x_arg)?;
        // z interpolates linearly between the curves of a 2-D spline; a 1-D spline ignores it.
        let z = self.scalar::<N>(z_arg)?;
        let id = self.integer_arg(name, 2, "SPLINE id", id_arg)?;
        let iord = self.optional_integer_arg(name, 3, "derivative order", args)?;
        if iord > 2 {
            return Err(EvalError::invalid_argument(format!(
                "{name}: derivative order (argument 4) must be 0, 1 or 2, got {iord}"
            )));
        }
        let Some(data) = self.env.spline(id) else {
            return Err(EvalError::unknown_reference(format!(
                "{name}: SPLINE/{id} does not exist"
            )));
        };
        let method = if f == Special::Akispl {
            SplineMethod::Akima
        } else {
            SplineMethod::Cubic
        };
        Ok(functions::spline_surface(
            data,
            method,
            &x,
            &z,
            iord as usize,
        ))
    }
}

fn from_env<N: Num>(d: Dual, name: &str) -> Result<N, EvalError> {
    if !d.value().is_finite() {
        return Err(EvalError::domain(format!(
            "{name} returned the non-finite value {}",
            d.value()
        )));
    }
    N::from_env(d, name)
}

fn binary<N: Num>(op: BinOp, l: Val<N>, r: Val<N>) -> Result<Val<N>, EvalError> {
    use Val::{S, V};
    let sym = op.symbol();
    let out = match (op, l, r) {
        (BinOp::Add, S(a), S(b)) => S(a.plus(&b)),
        (BinOp::Sub, S(a), S(b)) => S(a.minus(&b)),
        (BinOp::Mul, S(a), S(b)) => S(a.times(&b)),
        (BinOp::Div, S(a), S(b)) => S(functions::divide(&a, &b)?),
        (BinOp::Pow, S(a), S(b)) => S(functions::pow(&a, &b)?),
        (BinOp::Add, V(a), V(b)) => V([0, 1, 2].map(|i| a[i].plus(&b[i]))),
        (BinOp::Sub, V(a), V(b)) => V([0, 1, 2].map(|i| a[i].minus(&b[i]))),
        (BinOp::Mul, S(s), V(v)) | (BinOp::Mul, V(v), S(s)) => V(v.map(|c| c.times(&s))),
        (BinOp::Mul, V(a), V(b)) => S(a[0]
            .times(&b[0])
            .plus(&a[1].times(&b[1]))
            .plus(&a[2].times(&b[2]))),
        (BinOp::Div, V(v), S(s)) => {
            if s.val() == 0.0 {
                return Err(EvalError::domain("division of a vector by zero"));
            }
            V(v.map(|c| c.over(&s)))
        }
        (BinOp::Cross, V(a), V(b)) => V([
            a[1].times(&b[2]).minus(&a[2].times(&b[1])),
            a[2].times(&b[0]).minus(&a[0].times(&b[2])),
            a[0].times(&b[1]).minus(&a[1].times(&b[0])),
        ]),
        _ => return Err(mismatch(&format!("operator '{sym}'"))),
    };
    match out {
        S(n) => Ok(S(finite(n, || format!("the result of '{sym}'"))?)),
        V(v) => {
            if v.iter().all(|c| c.val().is_finite()) {
                Ok(V(v))
            } else {
                Err(EvalError::domain(format!(
                    "the result of '{sym}' is not finite (overflow)"
                )))
            }
        }
    }
}
