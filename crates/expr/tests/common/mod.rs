//! Shared test helpers: a mock environment whose measures are smooth functions of a few
//! variables, and finite-difference utilities.
#![allow(dead_code)]

use std::cell::RefCell;
use std::collections::HashMap;

use linkage_expr::{
    parse, Dual, ElementForce, ElementForceArgs, Env, EvalError, MarkerArgs, MeasureKind,
    SplineData, StateRef,
};

/// Index used for TIME in gradient evaluation.
pub const TIME_VAR: u32 = 100;

#[derive(Clone)]
pub struct MockEnv {
    pub q: Vec<f64>,
    pub time: f64,
    pub mode: i32,
    pub splines: HashMap<u32, SplineData>,
    pub last_markers: RefCell<Option<(MeasureKind, MarkerArgs)>>,
    pub last_force: RefCell<Option<(ElementForce, ElementForceArgs)>>,
    pub last_state: RefCell<Option<StateRef>>,
}

impl MockEnv {
    pub fn new() -> Self {
        let mut splines = HashMap::new();
        splines.insert(
            1,
            SplineData::new(
                vec![-2.0, -1.0, 0.0, 0.5, 1.5, 3.0, 4.0],
                vec![1.0, 0.5, 0.0, 0.3, 1.2, 0.7, -0.4],
                false,
            )
            .unwrap(),
        );
        MockEnv {
            q: vec![0.3, -0.7, 1.1, 0.45, -0.2, 0.8],
            time: 0.37,
            mode: 4,
            splines,
            last_markers: RefCell::new(None),
            last_force: RefCell::new(None),
            last_state: RefCell::new(None),
        }
    }

    fn var(&self, i: u32) -> Dual {
        let k = i as usize % self.q.len();
        Dual::variable(self.q[k], k as u32)
    }

    /// A smooth, nonlinear function of several variables selected by `a`, `b`, `c`.
    fn smooth(&self, a: u32, b: u32, c: u32, s: f64) -> Dual {
        let x = self.var(a);
        let y = self.var(b + 1);
        let z = self.var(c + 2);
        &x * (0.5 + 0.01 * s) + &y * &z * 0.7 + (&x * 0.3 + 0.1).sin() + 0.25 * s
    }
}

impl Env for MockEnv {
    fn time(&self) -> f64 {
        self.time
    }
    fn mode(&self) -> i32 {
        self.mode
    }
    fn time_variable(&self) -> Option<u32> {
        Some(TIME_VAR)
    }
    fn measure(&self, kind: MeasureKind, m: MarkerArgs, _g: bool) -> Result<Dual, EvalError> {
        *self.last_markers.borrow_mut() = Some((kind, m));
        if m.i == 999 {
            return Err(EvalError::unknown_reference("MARKER/999 does not exist"));
        }
        let s = MeasureKind::ALL.iter().position(|&k| k == kind).unwrap() as f64;
        Ok(self.smooth(m.i, m.j, m.k + m.l, s))
    }
    fn element_force(
        &self,
        kind: ElementForce,
        a: ElementForceArgs,
        _g: bool,
    ) -> Result<Dual, EvalError> {
        *self.last_force.borrow_mut() = Some((kind, a));
        Ok(self.smooth(a.id, a.component.code(), a.rm, 3.0))
    }
    fn state(&self, s: StateRef, _g: bool) -> Result<Dual, EvalError> {
        *self.last_state.borrow_mut() = Some(s);
        match s {
            StateRef::Varval(99) => Err(EvalError::unknown_reference("VARIABLE/99 does not exist")),
            StateRef::Varval(id) => Ok(self.smooth(id, 1, 2, 1.0)),
            StateRef::Dif(id) => Ok(self.smooth(id, 2, 3, 2.0)),
            StateRef::Dif1(id) => Ok(self.smooth(id, 3, 4, 3.0)),
            StateRef::Aryval { id, index } => Ok(self.smooth(id, index, 5, 4.0)),
            StateRef::Pinval { id, index } => Ok(self.smooth(id, index, 6, 5.0)),
            StateRef::Pouval { id, index } => Ok(self.smooth(id, index, 7, 6.0)),
            StateRef::Senval(id) => Ok(self.smooth(id, 1, 8, 7.0)),
        }
    }
    fn spline(&self, id: u32) -> Option<&SplineData> {
        self.splines.get(&id)
    }
}

pub fn eval_str(text: &str, env: &impl Env) -> f64 {
    let e = parse(text).unwrap_or_else(|err| panic!("parse {text:?}: {err}"));
    linkage_expr::evaluate(&e, env).unwrap_or_else(|err| panic!("eval {text:?}: {err}"))
}

pub fn assert_close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol * (1.0 + want.abs()),
        "{what}: got {got}, want {want}"
    );
}
