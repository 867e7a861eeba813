//! Function-expression measures evaluated on the solver state (the `linkage-expr` [`Env`]).
//!
//! Position measures (DX, DY, DZ, DM, AX, AY, AZ, PSI, THETA, PHI, YAW, PITCH, ROLL) are
//! built from the same geometric [`Quantity`]s as the constraint rows, so their gradients are
//! exact. The gradient variable of part `k`'s tangent coordinate `c` is `6k + c`.
//!
//! `ORIENT` reads the direction cosines `R = A_jᵀ·A_i` of two markers, each entry a
//! [`Quantity::Dot`] of their axes (`R[r][c] = x_j,r · x_i,c`).
//!
//! [`PositionEnv`] sees positions only (constraint rows, motions); [`StateEnv`] adds
//! velocities, VARIABLE/ARRAY/SPLINE data and `MODE` (force expressions); [`PathEnv`] moves the
//! parts with given velocities and accelerations and supplies the position measures as
//! second-order series in time (second derivatives of general constraints).

use crate::constraints::rows::{
    dir_series, point_series, BodyDir, BodyFrame, BodyPoint, EulerSeq, Quantity, RowGradient,
    Velocities,
};
use crate::physics::forces::algebra::{Kinematics, Real, V3};
use crate::physics::forces::data::DataElements;
use crate::state::State;
use glam::{DMat3, DVec3};
use linkage_expr::{
    evaluate, evaluate_with_gradient, Dual, Env, EvalError, Expr, Function, MarkerArgs,
    MeasureKind, SplineData, StateRef,
};
use linkage_model::{Body, Model};
use std::cell::RefCell;
use std::collections::HashMap;

/// Marker frames by dataset id (ground frame for id 0).
#[derive(Clone, Debug, Default)]
pub struct MarkerFrames {
    frames: HashMap<u64, BodyFrame>,
}

impl MarkerFrames {
    pub fn new(model: &Model) -> MarkerFrames {
        let frames = model
            .markers
            .iter()
            .map(|m| {
                (
                    m.id,
                    BodyFrame {
                        body: m.body,
                        p_b: m.p_bm,
                        r_b: m.r_bm,
                    },
                )
            })
            .collect();
        MarkerFrames { frames }
    }

    /// These frames with markers `placed` (id, frame on its body) moved: the floating markers
    /// of curve constraints at their contacts, for one output
    /// ([`crate::constraints::curve_contacts::floating_placements`]).
    pub fn with_placed(&self, placed: &[(u64, BodyFrame)]) -> MarkerFrames {
        let mut frames = self.frames.clone();
        frames.extend(placed.iter().copied());
        MarkerFrames { frames }
    }

    /// The frame of marker `id`; id 0 is the ground frame.
    pub fn get(&self, id: u32) -> Result<BodyFrame, EvalError> {
        if id == 0 {
            return Ok(BodyFrame {
                body: Body::Ground,
                p_b: DVec3::ZERO,
                r_b: DMat3::IDENTITY,
            });
        }
        self.frames.get(&(id as u64)).copied().ok_or_else(|| {
            EvalError::new(
                linkage_expr::EvalErrorKind::UnknownReference,
                format!("marker {id} does not exist"),
            )
        })
    }
}

/// A position-level environment: time and part poses.
pub struct PositionEnv<'a> {
    pub frames: &'a MarkerFrames,
    pub state: &'a State,
}

thread_local! {
    /// The row gradient position measures build their gradients in, reused so that
    /// evaluating them does not allocate.
    static MEASURE_GRADIENT: RefCell<RowGradient> = RefCell::new(RowGradient::default());
    /// VARIABLE memories of dropped [`StateEnv`]s, cleared, for the next ones (storage only:
    /// nothing read from these buffers outlives one evaluation).
    static MEMOS: RefCell<Vec<VariableMemo>> = const { RefCell::new(Vec::new()) };
}

/// `q` at `state` (value `value`) with its gradient.
fn quantity_dual(q: &Quantity, value: f64, state: &State) -> Dual {
    let build = |g: &mut RowGradient| {
        g.clear();
        q.gradient(state, 1.0, g);
        dual(value, g)
    };
    MEASURE_GRADIENT
        .try_with(|g| g.try_borrow_mut().ok().map(|mut g| build(&mut g)))
        .ok()
        .flatten()
        .unwrap_or_else(|| build(&mut RowGradient::default()))
}

fn dual(value: f64, g: &RowGradient) -> Dual {
    Dual::new(
        value,
        g.blocks.iter().flat_map(|(k, v)| {
            v.iter()
                .enumerate()
                .map(move |(c, x)| ((6 * k + c) as u32, *x))
        }),
    )
}

fn negate(d: BodyDir) -> BodyDir {
    BodyDir {
        body: d.body,
        v_b: -d.v_b,
    }
}

impl PositionEnv<'_> {
    /// The geometric quantity a position measure is.
    fn quantity(&self, kind: MeasureKind, m: MarkerArgs) -> Result<Option<Quantity>, EvalError> {
        let (fi, fj) = (self.frames.get(m.i)?, self.frames.get(m.j)?);
        let point = |f: BodyFrame| BodyPoint {
            body: f.body,
            p_b: f.p_b,
        };
        let proj = |axis: usize| -> Result<Quantity, EvalError> {
            let fk = self.frames.get(m.k)?;
            Ok(Quantity::Proj {
                i: point(fi),
                j: point(fj),
                e: fk.axis(axis),
            })
        };
        let euler = |seq, k| Quantity::euler(fi, fj, seq, k);
        Ok(Some(match kind {
            MeasureKind::Dx => proj(0)?,
            MeasureKind::Dy => proj(1)?,
            MeasureKind::Dz => proj(2)?,
            MeasureKind::Dm => {
                let d = fi.eval(self.state).0 - fj.eval(self.state).0;
                let e = BodyDir {
                    body: Body::Ground,
                    v_b: d.try_normalize().unwrap_or(DVec3::X),
                };
                Quantity::Proj {
                    i: point(fi),
                    j: point(fj),
                    e,
                }
            }
            // AX = atan2(−z_i·y_j, z_i·z_j), AY = atan2(z_i·x_j, z_i·z_j), AZ = atan2(x_i·y_j, x_i·x_j).
            MeasureKind::Ax => Quantity::Angle {
                x: fi.axis(2),
                x_ref: fj.axis(2),
                y_ref: negate(fj.axis(1)),
            },
            MeasureKind::Ay => Quantity::Angle {
                x: fi.axis(2),
                x_ref: fj.axis(2),
                y_ref: fj.axis(0),
            },
            MeasureKind::Az => Quantity::Angle {
                x: fi.axis(0),
                x_ref: fj.axis(0),
                y_ref: fj.axis(1),
            },
            MeasureKind::Psi => euler(EulerSeq::Body313, 0),
            MeasureKind::Theta => euler(EulerSeq::Body313, 1),
            MeasureKind::Phi => euler(EulerSeq::Body313, 2),
            MeasureKind::Yaw => euler(EulerSeq::Body321, 0),
            MeasureKind::Pitch => euler(EulerSeq::Body321, 1),
            MeasureKind::Roll => euler(EulerSeq::Body321, 2),
            _ => return Ok(None),
        }))
    }
}

/// The direction cosine `R[r][c] = x_j,r · x_i,c` of frame `fi` relative to `fj`.
fn cosine(fi: BodyFrame, fj: BodyFrame, r: usize, c: usize) -> Quantity {
    Quantity::Dot(fj.axis(r), fi.axis(c))
}

impl PositionEnv<'_> {
    /// Direction cosines of marker `i` relative to marker `j`, column-major (entry `3c + r` is
    /// `R[r][c]`), with gradients if asked.
    fn rotation_entries(&self, i: u32, j: u32, gradient: bool) -> Result<[Dual; 9], EvalError> {
        let (fi, fj) = (self.frames.get(i)?, self.frames.get(j)?);
        Ok(std::array::from_fn(|e| {
            let q = cosine(fi, fj, e % 3, e / 3);
            let value = q.value(self.state);
            if gradient {
                quantity_dual(&q, value, self.state)
            } else {
                Dual::constant(value)
            }
        }))
    }
}

impl Env for PositionEnv<'_> {
    fn time(&self) -> f64 {
        self.state.time
    }

    fn rotation(&self, i: u32, j: u32, gradient: bool) -> Result<[Dual; 9], EvalError> {
        self.rotation_entries(i, j, gradient)
    }

    fn measure(
        &self,
        kind: MeasureKind,
        markers: MarkerArgs,
        gradient: bool,
    ) -> Result<Dual, EvalError> {
        let Some(q) = self.quantity(kind, markers)? else {
            return Err(EvalError::unavailable(format!(
                "{} needs velocities or forces, which a position-level analysis does not have",
                kind.name()
            )));
        };
        let value = q.value(self.state);
        if !gradient {
            return Ok(Dual::constant(value));
        }
        if kind == MeasureKind::Dm && value == 0.0 {
            // |d| has no derivative at d = 0.
            return Ok(Dual::constant(0.0));
        }
        Ok(quantity_dual(&q, value, self.state))
    }
}

/// The marker ids an expression's measures and `ORIENT` calls name (ground's 0 included),
/// or `None` when some id is computed rather than written as a literal (then any marker may
/// be meant).
pub fn referenced_markers(expr: &Expr) -> Option<Vec<u32>> {
    let mut ids = Vec::new();
    let mut computed = false;
    expr.walk(&mut |node| {
        let Expr::Call { func, args } = node else {
            return;
        };
        let markers = match func {
            Function::Measure(_) => args.as_slice(),
            // ORIENT(system, component, i [, j]).
            Function::Orient => args.get(2..).unwrap_or_default(),
            _ => return,
        };
        for a in markers {
            match a {
                Expr::Number(x) if *x >= 0.0 && x.fract() == 0.0 && *x <= f64::from(u32::MAX) => {
                    // Exact: a whole number in u32 range.
                    ids.push(*x as u32)
                }
                _ => computed = true,
            }
        }
    });
    if computed {
        return None;
    }
    ids.sort_unstable();
    ids.dedup();
    Some(ids)
}

/// Adds `c · ∂f/∂q` of an expression's gradient to a row gradient.
pub fn add_dual_gradient(d: &Dual, c: f64, g: &mut RowGradient) {
    for &(idx, v) in d.gradient() {
        let (k, comp) = (idx as usize / 6, idx as usize % 6);
        let mut block = [0.0; 6];
        block[comp] = v * c;
        g.add_block(k, block);
    }
}

/// Memory of one [`StateEnv`]: VARIABLEs being evaluated (cycle detection) and values already
/// computed (keyed by id and whether the gradient was requested).
///
/// Memories are recycled (cleared, with their storage kept) from one environment to the
/// next on the same thread, so that evaluating VARIABLEs does not allocate once warm.
#[derive(Default)]
struct VariableMemo {
    active: Vec<u32>,
    values: HashMap<(u32, bool), Dual>,
}

impl VariableMemo {
    /// A cleared memory, recycled if one is free.
    fn take() -> VariableMemo {
        MEMOS
            .try_with(|m| m.try_borrow_mut().ok().and_then(|mut m| m.pop()))
            .ok()
            .flatten()
            .unwrap_or_default()
    }

    /// Clears this memory and keeps it for the next environment.
    fn recycle(mut self) {
        if self.active.capacity() == 0 && self.values.capacity() == 0 {
            return; // nothing worth keeping
        }
        self.active.clear();
        self.values.clear();
        // At most a few environments are alive at once; a busy or full pool frees it.
        const KEPT: usize = 8;
        let _ = MEMOS.try_with(|m| {
            if let Ok(mut m) = m.try_borrow_mut() {
                if m.len() < KEPT {
                    m.push(self);
                }
            }
        });
    }
}

/// A position- and velocity-level environment: what force expressions see.
///
/// - Position measures (DX … ROLL) are those of [`PositionEnv`].
/// - Velocity measures, with the marker roles of ADM-REFERENCE §5.3 (`j` the reference
///   point, default ground origin; `k` the axes of the result, default ground; `l` the frame
///   in which the time derivative is taken, default ground):
///   - `VX/VY/VZ(i,j,k,l) = e_k·(v_Pi − v_Pj − ω_l × (P_i − P_j))`, `VM(i,j,l)` its length,
///   - `VR(i,j,l) = (v_Pi − v_Pj)·(P_i − P_j)/|P_i − P_j|` (separating > 0; independent of l;
///     0 when the points coincide),
///   - `WX/WY/WZ(i,j,k) = e_k·(ω_i − ω_j)`, `WM(i,j) = |ω_i − ω_j|`.
/// - `TIME` is the state's time, `MODE` the given mode.
/// - `VARVAL(id)` evaluates VARIABLE/id's expression in this environment (a cycle of VARVAL
///   references is an error); `ARYVAL(id, n)` reads ARRAY/id; `DIF`, `DIF1`, `PINVAL`,
///   `POUVAL` and the X and Y arrays read the control states
///   ([`crate::physics::control_states::read_state`]); `AKISPL`/`CUBSPL` read the 1-D SPLINEs.
/// - Accelerations (ACCX …, WDTX …), generic force measures (FX … TM) and element forces
///   (JOINT(…), SFORCE(…), …) are unavailable (an error naming them).
///
/// Gradient variables: `6k + c` for part k's tangent position coordinate c,
/// `6n + 6k + c` for its velocity coordinate c (v, then ω), n = number of parts, then the
/// control states and their rates ([`crate::physics::control_states::state_variable`]).
pub struct StateEnv<'a> {
    pub frames: &'a MarkerFrames,
    pub state: &'a State,
    pub velocities: &'a Velocities,
    pub data: &'a DataElements,
    pub mode: i32,
    /// VARIABLE values memoised at this environment's one state (and the guard against
    /// cycles): a pure cache of functions of the state, dropped with the environment, so no
    /// state outlives an evaluation.
    memo: RefCell<VariableMemo>,
}

impl<'a> StateEnv<'a> {
    /// An environment on `state` and `velocities` (one `(v, ω)` per part), mode 0.
    pub fn new(
        frames: &'a MarkerFrames,
        state: &'a State,
        velocities: &'a Velocities,
        data: &'a DataElements,
    ) -> StateEnv<'a> {
        StateEnv {
            frames,
            state,
            velocities,
            data,
            mode: 0,
            memo: RefCell::new(VariableMemo::take()),
        }
    }

    /// Sets the value of `MODE`.
    pub fn with_mode(mut self, mode: i32) -> Self {
        self.mode = mode;
        self
    }

    fn kinematics(&self) -> Kinematics<'a> {
        Kinematics {
            state: self.state,
            velocities: self.velocities,
        }
    }

    /// A velocity measure, generic over values / values with gradients.
    fn velocity_measure<R: Real>(
        &self,
        kind: MeasureKind,
        m: MarkerArgs,
    ) -> Result<Option<R>, EvalError> {
        let kin = self.kinematics();
        let (fi, fj) = (self.frames.get(m.i)?, self.frames.get(m.j)?);
        let along_k = |v: &V3<R>, axis: usize| -> Result<R, EvalError> {
            let fk = self.frames.get(m.k)?;
            Ok(v.dot(&kin.dir::<R>(&fk.axis(axis))))
        };
        let length = |v: &V3<R>| {
            let n2 = v.dot(v);
            if n2.value() > 0.0 {
                n2.sqrt()
            } else {
                R::cst(0.0)
            }
        };
        Ok(Some(match kind {
            MeasureKind::Vx
            | MeasureKind::Vy
            | MeasureKind::Vz
            | MeasureKind::Vm
            | MeasureKind::Vr => {
                let (oi, oj) = (fi.origin(), fj.origin());
                let d = kin.point::<R>(&oi).sub(&kin.point::<R>(&oj));
                let v = kin
                    .point_velocity::<R>(&oi)
                    .sub(&kin.point_velocity::<R>(&oj));
                if kind == MeasureKind::Vr {
                    let dist = length(&d);
                    if dist.value() == 0.0 {
                        return Ok(Some(R::cst(0.0)));
                    }
                    return Ok(Some(v.dot(&d).div(&dist)));
                }
                let fl = self.frames.get(m.l)?;
                let v = v.sub(&kin.omega::<R>(fl.body).cross(&d));
                match kind {
                    MeasureKind::Vx => along_k(&v, 0)?,
                    MeasureKind::Vy => along_k(&v, 1)?,
                    MeasureKind::Vz => along_k(&v, 2)?,
                    _ => length(&v),
                }
            }
            MeasureKind::Wx | MeasureKind::Wy | MeasureKind::Wz | MeasureKind::Wm => {
                let w = kin.omega::<R>(fi.body).sub(&kin.omega::<R>(fj.body));
                match kind {
                    MeasureKind::Wx => along_k(&w, 0)?,
                    MeasureKind::Wy => along_k(&w, 1)?,
                    MeasureKind::Wz => along_k(&w, 2)?,
                    _ => length(&w),
                }
            }
            _ => return Ok(None),
        }))
    }

    /// `VARVAL(id)`: the VARIABLE's expression, evaluated once per environment.
    fn varval(&self, id: u32, gradient: bool) -> Result<Dual, EvalError> {
        {
            let memo = self.memo.borrow();
            if let Some(d) = memo
                .values
                .get(&(id, gradient))
                .or_else(|| memo.values.get(&(id, true)))
            {
                return Ok(if gradient {
                    d.clone()
                } else {
                    Dual::constant(d.value())
                });
            }
            if let Some(start) = memo.active.iter().position(|a| *a == id) {
                let cycle: Vec<String> = memo.active[start..]
                    .iter()
                    .chain([&id])
                    .map(|v| v.to_string())
                    .collect();
                return Err(EvalError::invalid_argument(format!(
                    "VARVAL cycle: VARIABLE {} refer to each other",
                    cycle.join(" → ")
                )));
            }
        }
        let expr = self.data.variable_expr(id)?;
        self.memo.borrow_mut().active.push(id);
        let result = if gradient {
            evaluate_with_gradient(expr, self)
        } else {
            evaluate(expr, self).map(Dual::constant)
        };
        self.memo.borrow_mut().active.pop();
        let d = result.map_err(|e| {
            if e.message.starts_with("VARVAL cycle") || e.message.starts_with("in VARIABLE/") {
                e
            } else {
                EvalError::new(
                    e.kind,
                    format!(
                        "in VARIABLE/{id} ({}): {}",
                        self.data.variables.get(&id).map_or("", |v| v.name.as_str()),
                        e.message
                    ),
                )
            }
        })?;
        self.memo
            .borrow_mut()
            .values
            .insert((id, gradient), d.clone());
        Ok(d)
    }

    /// `VARVAL(id)` in this environment (what control laws read as inputs).
    pub fn varval_of(&self, id: u32, gradient: bool) -> Result<Dual, EvalError> {
        self.varval(id, gradient)
    }
}

impl Env for StateEnv<'_> {
    fn time(&self) -> f64 {
        self.state.time
    }

    fn mode(&self) -> i32 {
        self.mode
    }

    fn measure(
        &self,
        kind: MeasureKind,
        markers: MarkerArgs,
        gradient: bool,
    ) -> Result<Dual, EvalError> {
        use MeasureKind::*;
        match kind {
            Dx | Dy | Dz | Dm | Ax | Ay | Az | Psi | Theta | Phi | Yaw | Pitch | Roll => {
                PositionEnv {
                    frames: self.frames,
                    state: self.state,
                }
                .measure(kind, markers, gradient)
            }
            _ => {
                let value = if gradient {
                    self.velocity_measure::<Dual>(kind, markers)?
                } else {
                    self.velocity_measure::<f64>(kind, markers)?
                        .map(Dual::constant)
                };
                value.ok_or_else(|| {
                    EvalError::unavailable(format!(
                        "{} is not available: linkage evaluates force expressions on positions \
                         and velocities only (no accelerations or forces)",
                        kind.name()
                    ))
                })
            }
        }
    }

    fn rotation(&self, i: u32, j: u32, gradient: bool) -> Result<[Dual; 9], EvalError> {
        PositionEnv {
            frames: self.frames,
            state: self.state,
        }
        .rotation(i, j, gradient)
    }

    fn state(&self, state: StateRef, gradient: bool) -> Result<Dual, EvalError> {
        crate::physics::control_states::read_state(
            self.data,
            self.state,
            state,
            gradient,
            &|id, g| self.varval(id, g),
        )
    }

    fn spline(&self, id: u32) -> Option<&SplineData> {
        self.data.splines.get(&id)
    }
}

impl Drop for StateEnv<'_> {
    fn drop(&mut self) {
        std::mem::take(self.memo.get_mut()).recycle();
    }
}

/// Position measures along a motion of the model: the parts at `state`, moving with the twists
/// `velocities` (CM velocity and angular velocity, ground axes) and the accelerations
/// `accelerations` (CM acceleration and angular acceleration; zero when `None`), while TIME
/// advances at `time_rate` (1, or 0 to freeze it).
///
/// Values and gradients are those of [`PositionEnv`]. [`Env::measure_series`] gives
/// `[m, ṁ, m̈]` of every position measure and [`Env::rotation_series`] those of the direction
/// cosines, so that [`linkage_expr::evaluate_path_series`] returns a general constraint's
/// `[f, ḟ, f̈]` along that motion:
///
/// * `DX/DY/DZ(i, j, k) = (P_i − P_j)·e_k`, `AX/AY/AZ(i, j) = atan2(s, c)` of two dot
///   products, the direction cosines `x_j,r·x_i,c`: products of the point and direction
///   series `P̈ = a_c + α×u + ω×(ω×u)`, `ë = α×e + ω×(ω×e)` ([`Quantity::series`]);
/// * `DM(i, j) = |d|`, `d = P_i − P_j`: `ṙ = d·ḋ/r`, `r̈ = (ḋ·ḋ + d·d̈ − ṙ²)/r` (a domain error
///   where the markers coincide: |d| has no derivative there);
/// * `PSI … ROLL`: the Euler-angle rates from the relative angular velocity in J's axes and its
///   rate ([`Quantity::series`]).
///
/// With zero accelerations the second derivative is the velocity-product term of the
/// acceleration equations; with frozen time and the velocity set to a unit tangent direction
/// u it is `uᵀ ∇²f u` (the polarization of [`crate::constraints::hessian`]). Velocity measures would need
/// third derivatives of positions and are unavailable (a general constraint may not use them,
/// see [`crate::constraints::drivers::ExpressionDrivers::new`]).
pub struct PathEnv<'a> {
    pub frames: &'a MarkerFrames,
    pub state: &'a State,
    pub velocities: &'a Velocities,
    pub accelerations: Option<&'a Velocities>,
    pub time_rate: f64,
}

impl PathEnv<'_> {
    fn position(&self) -> PositionEnv<'_> {
        PositionEnv {
            frames: self.frames,
            state: self.state,
        }
    }
}

impl Env for PathEnv<'_> {
    fn time(&self) -> f64 {
        self.state.time
    }

    fn time_rate(&self) -> f64 {
        self.time_rate
    }

    fn measure(
        &self,
        kind: MeasureKind,
        markers: MarkerArgs,
        gradient: bool,
    ) -> Result<Dual, EvalError> {
        self.position().measure(kind, markers, gradient)
    }

    fn rotation(&self, i: u32, j: u32, gradient: bool) -> Result<[Dual; 9], EvalError> {
        self.position().rotation(i, j, gradient)
    }

    fn measure_series(&self, kind: MeasureKind, m: MarkerArgs) -> Result<[f64; 3], EvalError> {
        let (s, v, acc) = (self.state, self.velocities, self.accelerations);
        if kind == MeasureKind::Dm {
            let (fi, fj) = (self.frames.get(m.i)?, self.frames.get(m.j)?);
            let pi = point_series(&fi.origin(), s, v, acc);
            let pj = point_series(&fj.origin(), s, v, acc);
            let d = [pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]];
            let r = d[0].length();
            if r == 0.0 {
                return Err(EvalError::domain(format!(
                    "DM({}, {}): the markers coincide, where the distance has no derivative",
                    m.i, m.j
                )));
            }
            let rate = d[0].dot(d[1]) / r;
            let acc2 = (d[1].dot(d[1]) + d[0].dot(d[2]) - rate * rate) / r;
            return Ok([r, rate, acc2]);
        }
        match self.position().quantity(kind, m)? {
            Some(q) => Ok(q.series(s, v, acc)),
            None => Err(EvalError::unavailable(format!(
                "{} along a path would need third derivatives of the positions: only position \
                 measures have second-order series",
                kind.name()
            ))),
        }
    }

    fn rotation_series(&self, i: u32, j: u32) -> Result<[[f64; 3]; 9], EvalError> {
        let (fi, fj) = (self.frames.get(i)?, self.frames.get(j)?);
        let (s, v, acc) = (self.state, self.velocities, self.accelerations);
        let xi: [[DVec3; 3]; 3] = std::array::from_fn(|c| dir_series(&fi.axis(c), s, v, acc));
        let xj: [[DVec3; 3]; 3] = std::array::from_fn(|r| dir_series(&fj.axis(r), s, v, acc));
        Ok(std::array::from_fn(|e| {
            crate::constraints::rows::dot_series(&xj[e % 3], &xi[e / 3])
        }))
    }
}
