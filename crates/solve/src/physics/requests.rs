//! REQUEST outputs (ADM-REFERENCE §2.12) evaluated at the outputs of an analysis.
//!
//! The model resolves every REQUEST once ([`linkage_model::requests`]: markers checked,
//! `F1`…`F8` parsed, problems kept for the analyses that write REQUEST columns);
//! [`RequestSet::new`] makes them ready to evaluate or reports those problems.
//! [`RequestSet::columns`] names the values and [`RequestSet::evaluate`] computes them at one
//! [`Output`].
//!
//! Standard requests, six values each, I relative to J (J omitted = ground origin), vectors
//! resolved in RM's axes (RM omitted = ground):
//!
//! | request | columns | values |
//! |---|---|---|
//! | DISPLACEMENT | `.x .y .z .psi .theta .phi` | `P_I − P_J` in RM; body 3-1-3 angles of `R_Jᵀ R_I` in degrees (I's orientation relative to J's axes, not RM's), ψ and φ at θ ≈ 0 split as at the previous output ([`RequestSet::evaluate_continuing`]) |
//! | VELOCITY | `.vx .vy .vz .wx .wy .wz` | `v_I − v_J` (time derivative in ground) and `ω_I − ω_J`, in RM |
//! | ACCELERATION | `.ax .ay .az .wdx .wdy .wdz` | `a_I − a_J` (second derivative in ground) and `α_I − α_J`, in RM |
//! | FORCE | `.fx .fy .fz .tx .ty .tz` | net force on I's part from the elements *between I's part and J's part*, and its torque about I's origin, in RM |
//!
//! The FORCE definition (shared with the `FX`…`TM` measures): an element is between parts A
//! and B when one of its two markers is on A and the other on B (either way round). Its
//! contribution is the force and torque it exerts on A: for a joint, primitive or motion the
//! output's reaction on its I marker (or minus it, with the torque moved, when its I marker is
//! on B); for a force element (SFORCE, SPRINGDAMPER, BUSHING, FIELD, BEAM, VFORCE, VTORQUE,
//! GFORCE) its load on A. Torques are taken about I's origin. A and B the same part: zero.
//! Joint FRICTION is left out (decided; the reference does not say whether Adams' joint force
//! includes it): a joint's FORCE is its constraint reaction, and the reports give each
//! friction on its own.
//!
//! The outputs carry no reactions of COUPLER and GEAR elements, and a GCON's only on its I
//! marker's part (none when that is ground, as for a distance constraint from a ground
//! marker), so the wrench of these three is recovered from the equations of motion at the
//! output instead: on each moving part, the constraint wrench
//! `(m a − m g)/UCF − F_applied`, `(I_g α + ω × I_g ω)/UCF − T_applied` minus the joint,
//! primitive and motion reactions is what those elements exert. Such an element is between A
//! and B when the moving parts its rows act on are exactly the moving ones of A and B; its
//! wrench on A is that remainder on A (A moving), or minus the remainder on B, moved to the
//! same point (A ground: the element's load on ground balances its load on B, as for any
//! constraint written with relative measures). When two such elements act on the part used,
//! their shares cannot be told apart and the request is an error.
//!
//! Function requests give `.f1`…`.f8`, one column per expression written. Expressions see an
//! [`OutputEnv`].

use crate::constraints::rows::{BodyFrame, RowGradient};
use crate::constraints::system::System;
use crate::kernel::Output;
use crate::physics::applied::{AppliedForces, Regime};
use crate::physics::forces::data::DataElements;
use crate::physics::forces::ForceSet;
use crate::physics::mass::{ground_inertia, gyroscopic};
use crate::physics::measures::{MarkerFrames, StateEnv};
use glam::{DMat3, DVec3};
use linkage_adm::{Diagnostics, RequestKind};
use linkage_expr::{
    evaluate, Dual, ElementForce, ElementForceArgs, Env, EvalError, EvalErrorKind, ForceComponent,
    MarkerArgs, MeasureKind, SplineData, StateRef,
};
use linkage_model::forces::ForceKind;
use linkage_model::frames::EulerHistory;
use linkage_model::requests::{RequestDef, RequestWhat};
use linkage_model::{Body, ConstraintKind, Model};
use std::cell::RefCell;
use std::collections::HashMap;

/// The body 3-1-3 angles a run's REQUEST outputs gave, per pair of marker ids (I, J; 0 for
/// ground): the state its writer carries from output to output
/// ([`RequestSet::evaluate_continuing`]).
pub type RequestAngles = EulerHistory<(u32, u32)>;

/// Column suffixes of the standard requests.
const DISPLACEMENT: [&str; 6] = ["x", "y", "z", "psi", "theta", "phi"];
const VELOCITY: [&str; 6] = ["vx", "vy", "vz", "wx", "wy", "wz"];
const ACCELERATION: [&str; 6] = ["ax", "ay", "az", "wdx", "wdy", "wdz"];
const FORCE: [&str; 6] = ["fx", "fy", "fz", "tx", "ty", "tz"];

/// A REQUEST that cannot be evaluated at an output.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RequestError {
    /// A standard request's quantity (displacement, velocity, acceleration, force).
    #[error("{request} at time {}: {cause}", linkage_adm::num::time_text(*.time))]
    Quantity {
        /// The request's label (`REQUEST_9 (REQUEST/9, line 6)`).
        request: String,
        time: f64,
        cause: EvalError,
    },
    /// A function request's expression `F{component} = {text}`.
    #[error("{request} at time {}: F{component} = {text}: {cause}", linkage_adm::num::time_text(*.time))]
    Function {
        request: String,
        time: f64,
        component: usize,
        text: String,
        cause: EvalError,
    },
}

/// Why the model's force elements cannot be evaluated by requests: the first input error of
/// the force set.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("the model's force elements cannot be evaluated ({first})")]
struct ForcesUnavailable {
    first: String,
}

/// The REQUESTs of a dataset, ready to evaluate at outputs.
#[derive(Clone, Debug)]
pub struct RequestSet {
    requests: Vec<RequestDef>,
    frames: MarkerFrames,
    data: DataElements,
    /// The model's applied force elements (`None` when it has none), or why they cannot be
    /// evaluated.
    forces: Option<Result<ForceSet, ForcesUnavailable>>,
}

impl RequestSet {
    /// The REQUESTs of `model`, ready to evaluate: `Err` with every problem the model found
    /// resolving them ([`linkage_model::requests::Requests::issues`]).
    pub fn new(model: &Model) -> Result<RequestSet, Diagnostics> {
        if !model.requests.issues.is_empty() {
            return Err(Diagnostics(model.requests.issues.clone()));
        }
        let frames = MarkerFrames::new(model);
        let requests = model.requests.defs.clone();
        let forces = (!model.forces.is_empty()).then(|| {
            ForceSet::new(model).map_err(|d| ForcesUnavailable {
                first: d.0.first().map_or(String::new(), |e| e.message.clone()),
            })
        });
        // Data elements that cannot be built (bad SPLINE data, …) are the force set's input
        // errors; a request that reads one reports it when evaluated.
        let (data, _) = DataElements::new(model);
        Ok(RequestSet {
            requests,
            frames,
            data,
            forces,
        })
    }

    /// Whether there is nothing to output.
    pub fn is_empty(&self) -> bool {
        self.columns().is_empty()
    }

    /// Column names, in the order of [`RequestSet::evaluate`]'s values: `<name>.<component>`
    /// with the components of the module table, `<name>.f1` … for function requests.
    pub fn columns(&self) -> Vec<String> {
        let mut out = Vec::new();
        for r in &self.requests {
            match &r.what {
                RequestWhat::Standard { kind, .. } => {
                    let names = match kind {
                        RequestKind::Displacement => DISPLACEMENT,
                        RequestKind::Velocity => VELOCITY,
                        RequestKind::Acceleration => ACCELERATION,
                        RequestKind::Force => FORCE,
                    };
                    out.extend(names.iter().map(|c| format!("{}.{c}", r.name)));
                }
                RequestWhat::Functions(list) => {
                    out.extend(list.iter().map(|f| format!("{}.f{}", r.name, f.component)));
                }
            }
        }
        out
    }

    /// [`RequestSet::evaluate`]'s values as a request file stores them: six per request, in
    /// request order. A standard request's six components as they are; a function request's
    /// F2, F3, F4, F6, F7, F8 (F1 and F5, the magnitudes of Adams' eight-component layout, are
    /// not stored; a component not given is 0).
    pub fn stored_values(&self, values: &[f64]) -> Vec<[f64; 6]> {
        let mut at = 0;
        let mut out = Vec::with_capacity(self.requests.len());
        for r in &self.requests {
            let mut six = [0.0; 6];
            match &r.what {
                RequestWhat::Standard { .. } => {
                    for (slot, v) in six.iter_mut().zip(values.iter().skip(at)) {
                        *slot = *v;
                    }
                    at += 6;
                }
                RequestWhat::Functions(list) => {
                    for f in list {
                        let slot = match f.component {
                            2 => Some(0),
                            3 => Some(1),
                            4 => Some(2),
                            6 => Some(3),
                            7 => Some(4),
                            8 => Some(5),
                            _ => None,
                        };
                        if let (Some(k), Some(v)) = (slot, values.get(at)) {
                            six[k] = *v;
                        }
                        at += 1;
                    }
                }
            }
            out.push(six);
        }
        out
    }

    /// The values of every column at `output` of a run of `model`, whose compiled constraint
    /// rows are `sys` (the run's: GCON, COUPLER and GEAR rows tell which parts those elements
    /// act on). An error names the request, the time and the function (or quantity) that
    /// failed.
    pub fn evaluate(
        &self,
        model: &Model,
        sys: &System,
        output: &Output,
    ) -> Result<Vec<f64>, RequestError> {
        self.evaluate_continuing(model, sys, output, &mut RequestAngles::new())
    }

    /// [`RequestSet::evaluate`] at one output of a run whose earlier outputs left `angles`:
    /// the body 3-1-3 angles of DISPLACEMENT requests and of `ORIENT` (PSI, THETA, PHI and the
    /// Euler parameters' sign) continue the split of ψ and φ at θ ≈ 0 from them
    /// ([`EulerHistory`]), which are then this output's. A run's writer passes the same
    /// `angles` from its first output to its last.
    pub fn evaluate_continuing(
        &self,
        model: &Model,
        sys: &System,
        output: &Output,
        angles: &mut RequestAngles,
    ) -> Result<Vec<f64>, RequestError> {
        // The curve constraints' floating markers sit at their contacts at this output.
        let placed =
            crate::constraints::curve_contacts::floating_placements(model, sys, &output.state);
        let moved;
        let frames = if placed.is_empty() {
            &self.frames
        } else {
            moved = self.frames.with_placed(&placed);
            &moved
        };
        let env = OutputEnv::new(self, frames, model, sys, output);
        env.angles.replace(std::mem::take(angles));
        let result = self.evaluate_in(&env);
        *angles = env.angles.take();
        result
    }

    /// Every column's value in `env`.
    fn evaluate_in(&self, env: &OutputEnv<'_>) -> Result<Vec<f64>, RequestError> {
        let t = env.output.time;
        let mut out = Vec::new();
        for r in &self.requests {
            match &r.what {
                RequestWhat::Standard { kind, i, j, rm } => {
                    let six = env.standard(*kind, *i, *j, *rm).map_err(|cause| {
                        RequestError::Quantity {
                            request: r.label.clone(),
                            time: t,
                            cause,
                        }
                    })?;
                    out.extend(six);
                }
                RequestWhat::Functions(list) => {
                    for f in list {
                        let v = evaluate(&f.expr, env).map_err(|cause| RequestError::Function {
                            request: r.label.clone(),
                            time: t,
                            component: f.component,
                            text: f.text.clone(),
                            cause,
                        })?;
                        out.push(v);
                    }
                }
            }
        }
        Ok(out)
    }
}

/// The I marker, the other marker (`None`: a floating marker coincident with I) and the body
/// receiving the reaction, of a force element.
fn force_markers(model: &Model, kind: &ForceKind) -> (usize, Option<usize>, Body) {
    let pair = |i: usize, j: usize| (i, Some(j), model.markers[j].body);
    match kind {
        ForceKind::Sforce(s) => pair(s.i, s.j),
        ForceKind::SpringDamper(s) => pair(s.i, s.j),
        ForceKind::Bushing(b) => pair(b.i, b.j),
        ForceKind::Field(f) => pair(f.i, f.j),
        ForceKind::Beam(b) => pair(b.i, b.j),
        ForceKind::Vector(v) => (v.i, None, v.reaction),
        ForceKind::Contact(c) => pair(c.i, c.j),
    }
}

/// The statement of an element force function (`SPDP` is SPRINGDAMPER, `BUSH` BUSHING).
fn statement_of(kind: ElementForce) -> &'static str {
    kind.statement()
}

/// A force and a torque (ground axes).
type Wrench = (DVec3, DVec3);

/// A load of a force element: point of application, force, torque (ground).
type PointLoad = (DVec3, DVec3, DVec3);

/// Memory of VARVAL evaluations in one [`OutputEnv`]: a pure cache of values at its one
/// output (and the guard against cycles), dropped with the environment.
#[derive(Default)]
struct Memo {
    active: Vec<u32>,
    values: HashMap<u32, f64>,
}

/// What expressions see at an output: everything a [`StateEnv`] sees (positions, velocities,
/// `TIME`, VARIABLE/ARRAY/SPLINE data) plus
///
/// - accelerations, with the marker roles of ADM-REFERENCE §5.3 (`j` reference point, `k`
///   result axes, `l` the frame the derivatives are taken in; 0 = ground):
///   `ACCX/ACCY/ACCZ(i,j,k,l) = e_k·(d²/dt²)_l (P_i − P_j)` where, with `d = P_i − P_j` and
///   frame l turning at `ω_l`, `α_l`: `(d²d)_l = a_i − a_j − 2ω_l×(ḋ)_l − α_l×d − ω_l×(ω_l×d)`,
///   `(ḋ)_l = v_i − v_j − ω_l×d`; `ACCM(i,j,l)` its length;
///   `WDTX/WDTY/WDTZ(i,j,k,l) = e_k·((α_i − α_j) − ω_l×(ω_i − ω_j))`, `WDTM(i,j,l)` its length;
/// - net force measures `FX/FY/FZ(i,j,k)`, `TX/TY/TZ(i,j,k)`, `FM(i,j)`, `TM(i,j)`: the
///   FORCE-request wrench of the module docs (elements between i's part and j's part, force
///   on i's part, torque about i's origin), components along k's axes;
/// - element forces `JOINT/JPRIM/MOTION(id, jflag, comp, rm)` from the output's reactions and
///   `SFORCE/SPDP/BUSH/FIELD/BEAM/VFORCE/VTORQUE/GFORCE/CONTACT(id, jflag, comp, rm)` from the
///   force elements (a CONTACT's I and J markers are those of its first IGEOM and JGEOM
///   geometries; its force is the sum over its incidents): jflag 0 the force on the I marker and the torque about its origin, jflag 1 the
///   force on the J marker (minus the I force for constraints) and the torque about J's origin
///   (about I's point for VFORCE/VTORQUE/GFORCE, whose floating J marker sits there); comp 1
///   FM, 2–4 FX–FZ, 5 TM, 6–8 TX–TZ, resolved in rm's axes (0 = ground);
/// - `VARVAL` evaluated in this environment (so a VARIABLE may use accelerations and forces).
///
/// Values only: every result is a [`Dual::constant`] (requests need no derivatives).
/// `MODE` is 0, as for the force elements during the simulation.
pub struct OutputEnv<'a> {
    set: &'a RequestSet,
    /// The markers' frames at this output (floating markers placed).
    frames: &'a MarkerFrames,
    model: &'a Model,
    output: &'a Output,
    /// The run's compiled constraint rows.
    sys: &'a System,
    inner: StateEnv<'a>,
    memo: RefCell<Memo>,
    /// Per moving part, the constraint wrench the output's reactions do not explain (force at
    /// the CM, torque about it), computed on first use: a cache of a function of the output.
    remainder: RefCell<Option<Result<Vec<Wrench>, EvalError>>>,
    /// The body 3-1-3 angles of every pair of markers whose orientation the outputs so far
    /// gave, continued at this output as its requests read them.
    angles: RefCell<RequestAngles>,
}

fn resolve(r: &DMat3, v: DVec3) -> DVec3 {
    r.transpose() * v
}

fn pick(v: DVec3, axis: usize) -> f64 {
    match axis {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

impl<'a> OutputEnv<'a> {
    pub fn new(
        set: &'a RequestSet,
        frames: &'a MarkerFrames,
        model: &'a Model,
        sys: &'a System,
        output: &'a Output,
    ) -> OutputEnv<'a> {
        OutputEnv {
            set,
            frames,
            model,
            sys,
            output,
            inner: StateEnv::new(frames, &output.state, &output.velocities, &set.data),
            memo: RefCell::new(Memo::default()),
            remainder: RefCell::new(None),
            angles: RefCell::new(RequestAngles::new()),
        }
    }

    /// The body 3-1-3 angles (radians) of marker `i` relative to marker `j` at this output,
    /// continued from the previous output's ([`EulerHistory`]).
    fn continued_angles(&self, i: u32, j: u32) -> Result<[f64; 3], EvalError> {
        let (ri, rj) = (self.axes(i)?, self.axes(j)?);
        Ok(self
            .angles
            .borrow_mut()
            .angles((i, j), &(rj.transpose() * ri)))
    }

    fn applied_forces(&self) -> Result<Option<&'a ForceSet>, EvalError> {
        match &self.set.forces {
            Some(Ok(fs)) => Ok(Some(fs)),
            Some(Err(why)) => Err(EvalError::unavailable(why.to_string())),
            None => Ok(None),
        }
    }

    /// The constraint wrench on every moving part from the equations of motion, minus the
    /// joint, primitive and motion reactions of the output (module docs).
    fn compute_remainder(&self) -> Result<Vec<Wrench>, EvalError> {
        let (model, o) = (self.model, self.output);
        let n = model.parts.len();
        let mut applied = vec![0.0; 6 * n];
        if let Some(fs) = self.applied_forces()? {
            fs.add_forces(Regime::Dynamic, &o.state, &o.velocities, &mut applied)
                .map_err(|m| EvalError::new(EvalErrorKind::Domain, m.to_string()))?;
        }
        let ucf = model.ucf();
        // The flex bodies' inertia coupling `ΔM·a` (mass × acceleration units).
        let mut coupled = vec![0.0; 6 * n];
        let coupling = crate::physics::flex_inertia::FlexCoupling::new(model);
        if !coupling.is_empty() && o.accelerations.len() == n {
            let a: Vec<f64> = o
                .accelerations
                .iter()
                .flat_map(|(a, b)| [a.x, a.y, a.z, b.x, b.y, b.z])
                .collect();
            coupling.add_product(&o.state, &a, 1.0, &mut coupled);
        }
        let mut out = Vec::with_capacity(n);
        for (k, part) in model.parts.iter().enumerate() {
            let pose = o.state.poses[k];
            let (_, w) = self.twist(Body::Part(k))?;
            let (a, al) = self.acceleration(Body::Part(k))?;
            let ig = ground_inertia(part, &pose);
            let q = &applied[6 * k..6 * k + 6];
            let c = &coupled[6 * k..6 * k + 6];
            let f = (part.mass * (a - model.gravity) + DVec3::new(c[0], c[1], c[2])) / ucf
                - DVec3::new(q[0], q[1], q[2]);
            let t = (ig * al - gyroscopic(&ig, w) + DVec3::new(c[3], c[4], c[5])) / ucf
                - DVec3::new(q[3], q[4], q[5]);
            out.push((f, t));
        }
        for r in &o.reactions {
            let Some((i, j)) = self.model.constraints[r.element].markers() else {
                continue;
            };
            let pi = self.pose(&self.marker_frame(i)).0;
            for (body, sign) in [(model.markers[i].body, 1.0), (model.markers[j].body, -1.0)] {
                if let Body::Part(k) = body {
                    let arm = pi - o.state.poses[k].p;
                    out[k].0 -= sign * r.force;
                    out[k].1 -= sign * (r.torque + arm.cross(r.force));
                }
            }
        }
        Ok(out)
    }

    fn remainder(&self, k: usize) -> Result<Wrench, EvalError> {
        let mut cache = self.remainder.borrow_mut();
        let all = cache.get_or_insert_with(|| self.compute_remainder());
        match all {
            Ok(v) => v
                .get(k)
                .copied()
                .ok_or_else(|| EvalError::unavailable(format!("the output has no part {k}"))),
            Err(e) => Err(e.clone()),
        }
    }

    /// GCON, COUPLER and GEAR elements with the moving parts their rows act on (sorted).
    fn other_constraints(&self) -> Vec<(usize, Vec<usize>)> {
        let sys = self.sys;
        let mut g = RowGradient::default();
        let mut out = Vec::new();
        for (c, con) in self.model.constraints.iter().enumerate() {
            if con.markers().is_some() {
                continue;
            }
            let mut parts = Vec::new();
            for r in sys.element_rows[c].clone() {
                sys.gradient(r, &self.output.state, &mut g);
                for (k, block) in &g.blocks {
                    if block.iter().any(|x| *x != 0.0) && !parts.contains(k) {
                        parts.push(*k);
                    }
                }
            }
            parts.sort_unstable();
            out.push((c, parts));
        }
        out
    }

    /// Wrench on `a` (torque about `p`) of the GCON/COUPLER/GEAR elements between `a` and `b`.
    fn other_wrench(&self, a: Body, b: Body, p: DVec3) -> Result<Wrench, EvalError> {
        let others = self.other_constraints();
        let mut wanted: Vec<usize> = [a, b].iter().filter_map(|x| x.part()).collect();
        wanted.sort_unstable();
        let (mut f, mut t) = (DVec3::ZERO, DVec3::ZERO);
        for (_, parts) in &others {
            if parts.is_empty() || *parts != wanted {
                continue;
            }
            let (k, sign) = match (a, b) {
                (Body::Part(k), _) => (k, 1.0),
                (Body::Ground, Body::Part(k)) => (k, -1.0),
                (Body::Ground, Body::Ground) => continue,
            };
            let sharing: Vec<String> = others
                .iter()
                .filter(|(_, ps)| ps.contains(&k))
                .map(|(x, _)| self.model.constraints[*x].origin.name.clone())
                .collect();
            if sharing.len() > 1 {
                return Err(EvalError::unavailable(format!(
                    "the reactions of {} on {} cannot be told apart (linkage's outputs carry \
                     joint, primitive and motion reactions only)",
                    sharing.join(" and "),
                    self.model.parts[k].origin.name
                )));
            }
            let (rf, rt) = self.remainder(k)?;
            let cm = self.output.state.poses[k].p;
            f += sign * rf;
            t += sign * (rt + (cm - p).cross(rf));
        }
        Ok((f, t))
    }

    fn frame(&self, id: u32) -> Result<BodyFrame, EvalError> {
        self.frames.get(id)
    }

    fn marker_frame(&self, m: usize) -> BodyFrame {
        let mk = &self.model.markers[m];
        BodyFrame {
            body: mk.body,
            p_b: mk.p_bm,
            r_b: mk.r_bm,
        }
    }

    /// `(v, ω)` of a body's centre of mass.
    fn twist(&self, b: Body) -> Result<Wrench, EvalError> {
        match b {
            Body::Ground => Ok((DVec3::ZERO, DVec3::ZERO)),
            Body::Part(k) => self.output.velocities.get(k).copied().ok_or_else(|| {
                EvalError::unavailable(format!("the output has no velocity of part {k}"))
            }),
        }
    }

    /// `(a, α)` of a body's centre of mass.
    fn acceleration(&self, b: Body) -> Result<Wrench, EvalError> {
        match b {
            Body::Ground => Ok((DVec3::ZERO, DVec3::ZERO)),
            Body::Part(k) => self.output.accelerations.get(k).copied().ok_or_else(|| {
                EvalError::unavailable(format!("the output has no acceleration of part {k}"))
            }),
        }
    }

    /// Origin and axes of a frame in ground.
    fn pose(&self, f: &BodyFrame) -> (DVec3, DMat3) {
        f.eval(&self.output.state)
    }

    /// Position, velocity and acceleration of a frame's origin (ground).
    fn point_motion(&self, f: &BodyFrame) -> Result<[DVec3; 3], EvalError> {
        let pose = self.output.state.pose(f.body);
        let u = pose.r * f.p_b;
        let (v, w) = self.twist(f.body)?;
        let (a, al) = self.acceleration(f.body)?;
        Ok([
            pose.p + u,
            v + w.cross(u),
            a + al.cross(u) + w.cross(w.cross(u)),
        ])
    }

    /// Axes of marker `id` in ground (identity for 0).
    fn axes(&self, id: u32) -> Result<DMat3, EvalError> {
        let f = self.frame(id)?;
        Ok(self.pose(&f).1)
    }

    /// `(d²/dt²)_l (P_i − P_j)` and `(d/dt)_l (ω_i − ω_j)` in ground axes.
    fn relative_accelerations(&self, m: MarkerArgs) -> Result<Wrench, EvalError> {
        let (fi, fj, fl) = (self.frame(m.i)?, self.frame(m.j)?, self.frame(m.l)?);
        let [pi, vi, ai] = self.point_motion(&fi)?;
        let [pj, vj, aj] = self.point_motion(&fj)?;
        let (wl, all) = (self.twist(fl.body)?.1, self.acceleration(fl.body)?.1);
        let d = pi - pj;
        let d_dot = vi - vj - wl.cross(d);
        let acc = ai - aj - 2.0 * wl.cross(d_dot) - all.cross(d) - wl.cross(wl.cross(d));
        let (wi, wj) = (self.twist(fi.body)?.1, self.twist(fj.body)?.1);
        let (ali, alj) = (self.acceleration(fi.body)?.1, self.acceleration(fj.body)?.1);
        Ok((acc, ali - alj - wl.cross(wi - wj)))
    }

    /// Reaction of constraint `c` on its I marker: force and torque about I's origin.
    fn reaction(&self, c: usize) -> Result<Wrench, EvalError> {
        self.output
            .reactions
            .iter()
            .find(|r| r.element == c)
            .map(|r| (r.force, r.torque))
            .ok_or_else(|| {
                EvalError::unavailable(format!(
                    "{} has no reaction in the output",
                    self.model.constraints[c].origin.element()
                ))
            })
    }

    /// Loads of force element `e`: `[on I's body, on the reaction body]`, each `(point,
    /// force, torque)`.
    fn loads(&self, e: usize) -> Result<[Option<PointLoad>; 2], EvalError> {
        let fs = self
            .applied_forces()?
            .ok_or_else(|| EvalError::unavailable("the model has no force elements".to_string()))?;
        let loads = fs
            .loads::<f64>(e, &self.output.state, &self.output.velocities)
            .map_err(|m| EvalError::new(EvalErrorKind::Domain, m.to_string()))?;
        Ok(loads.map(|l| l.map(|l| (l.point.value(), l.force.value(), l.torque.value()))))
    }

    /// The FORCE-request wrench (module docs): force on body `a` from the elements between
    /// `a` and `b`, and its torque about `p`, in ground axes.
    fn net_wrench(&self, a: Body, b: Body, p: DVec3) -> Result<Wrench, EvalError> {
        let (mut f, mut t) = (DVec3::ZERO, DVec3::ZERO);
        if a == b {
            return Ok((f, t));
        }
        let between = |x: Body, y: Body| (x, y) == (a, b) || (x, y) == (b, a);
        for (c, con) in self.model.constraints.iter().enumerate() {
            match &con.kind {
                ConstraintKind::Joint { i, j, .. }
                | ConstraintKind::Jprim { i, j, .. }
                | ConstraintKind::Motion { i, j, .. } => {
                    let (bi, bj) = (self.model.markers[*i].body, self.model.markers[*j].body);
                    if !between(bi, bj) {
                        continue;
                    }
                    let (force, torque) = self.reaction(c)?;
                    let (sign, pi) = (
                        if bi == a { 1.0 } else { -1.0 },
                        self.pose(&self.marker_frame(*i)).0,
                    );
                    f += sign * force;
                    t += sign * (torque + (pi - p).cross(force));
                }
                _ => {}
            }
        }
        let (of, ot) = self.other_wrench(a, b, p)?;
        f += of;
        t += ot;
        for (e, el) in self.model.forces.iter().enumerate() {
            let (i, _, reaction_body) = force_markers(self.model, &el.kind);
            let bi = self.model.markers[i].body;
            if !between(bi, reaction_body) {
                continue;
            }
            let [on_i, on_j] = self.loads(e)?;
            if let Some((point, force, torque)) = if bi == a { on_i } else { on_j } {
                f += force;
                t += torque + (point - p).cross(force);
            }
        }
        Ok((f, t))
    }

    /// Force and torque of an element force function, in ground axes.
    fn element_wrench(&self, kind: ElementForce, id: u32, on_j: bool) -> Result<Wrench, EvalError> {
        let statement = statement_of(kind);
        let missing = || EvalError::unknown_reference(format!("{statement}/{id} does not exist"));
        if matches!(
            kind,
            ElementForce::Joint | ElementForce::Jprim | ElementForce::Motion
        ) {
            let c = self
                .model
                .constraints
                .iter()
                .position(|c| c.origin.statement == statement && c.origin.id == u64::from(id))
                .ok_or_else(missing)?;
            let (i, j) = self.model.constraints[c].markers().ok_or_else(missing)?;
            let (force, torque) = self.reaction(c)?;
            if !on_j {
                return Ok((force, torque));
            }
            let pi = self.pose(&self.marker_frame(i)).0;
            let pj = self.pose(&self.marker_frame(j)).0;
            return Ok((-force, -torque - (pi - pj).cross(force)));
        }
        let e = self
            .model
            .forces
            .iter()
            .position(|f| f.origin.statement == statement && f.origin.id == u64::from(id))
            .ok_or_else(missing)?;
        let (i, j, _) = force_markers(self.model, &self.model.forces[e].kind);
        let pi = self.pose(&self.marker_frame(i)).0;
        let about = match (on_j, j) {
            (true, Some(j)) => self.pose(&self.marker_frame(j)).0,
            _ => pi,
        };
        let [on_i, on_jm] = self.loads(e)?;
        Ok(match if on_j { on_jm } else { on_i } {
            Some((point, force, torque)) => (force, torque + (point - about).cross(force)),
            None => (DVec3::ZERO, DVec3::ZERO),
        })
    }

    /// The six values of a standard request.
    fn standard(&self, kind: RequestKind, i: u32, j: u32, rm: u32) -> Result<[f64; 6], EvalError> {
        let (fi, fj) = (self.frame(i)?, self.frame(j)?);
        let r_rm = self.axes(rm)?;
        let (lin, ang) = match kind {
            RequestKind::Displacement => {
                let (pi, pj) = (self.pose(&fi).0, self.pose(&fj).0);
                let d = resolve(&r_rm, pi - pj);
                let e = self.continued_angles(i, j)?.map(f64::to_degrees);
                return Ok([d.x, d.y, d.z, e[0], e[1], e[2]]);
            }
            RequestKind::Velocity => {
                let ([_, vi, _], [_, vj, _]) = (self.point_motion(&fi)?, self.point_motion(&fj)?);
                let (wi, wj) = (self.twist(fi.body)?.1, self.twist(fj.body)?.1);
                (vi - vj, wi - wj)
            }
            RequestKind::Acceleration => {
                self.relative_accelerations(MarkerArgs { i, j, k: 0, l: 0 })?
            }
            RequestKind::Force => {
                let pi = self.pose(&fi).0;
                self.net_wrench(fi.body, fj.body, pi)?
            }
        };
        let (l, a) = (resolve(&r_rm, lin), resolve(&r_rm, ang));
        Ok([l.x, l.y, l.z, a.x, a.y, a.z])
    }

    /// `VARVAL(id)` evaluated in this environment, once.
    fn varval(&self, id: u32) -> Result<f64, EvalError> {
        {
            let memo = self.memo.borrow();
            if let Some(v) = memo.values.get(&id) {
                return Ok(*v);
            }
            if let Some(start) = memo.active.iter().position(|a| *a == id) {
                let cycle: Vec<String> = memo.active[start..]
                    .iter()
                    .chain([&id])
                    .map(u32::to_string)
                    .collect();
                return Err(EvalError::invalid_argument(format!(
                    "VARVAL cycle: VARIABLE {} refer to each other",
                    cycle.join(" → ")
                )));
            }
        }
        let expr = self.set.data.variable_expr(id)?;
        self.memo.borrow_mut().active.push(id);
        let result = evaluate(expr, self);
        self.memo.borrow_mut().active.pop();
        let v = result.map_err(|e| {
            if e.message.starts_with("VARVAL cycle") || e.message.starts_with("in VARIABLE/") {
                e
            } else {
                EvalError::new(
                    e.kind,
                    format!(
                        "in VARIABLE/{id} ({}): {}",
                        self.set
                            .data
                            .variables
                            .get(&id)
                            .map_or("", |v| v.name.as_str()),
                        e.message
                    ),
                )
            }
        })?;
        self.memo.borrow_mut().values.insert(id, v);
        Ok(v)
    }
}

impl Env for OutputEnv<'_> {
    fn time(&self) -> f64 {
        self.output.time
    }

    fn measure(
        &self,
        kind: MeasureKind,
        m: MarkerArgs,
        _gradient: bool,
    ) -> Result<Dual, EvalError> {
        use MeasureKind::*;
        let value = match kind {
            Accx | Accy | Accz | Accm | Wdtx | Wdty | Wdtz | Wdtm => {
                let (acc, wdt) = self.relative_accelerations(m)?;
                match kind {
                    Accx | Accy | Accz => {
                        let axis = match kind {
                            Accx => 0,
                            Accy => 1,
                            _ => 2,
                        };
                        pick(resolve(&self.axes(m.k)?, acc), axis)
                    }
                    Accm => acc.length(),
                    Wdtm => wdt.length(),
                    _ => {
                        let axis = match kind {
                            Wdtx => 0,
                            Wdty => 1,
                            _ => 2,
                        };
                        pick(resolve(&self.axes(m.k)?, wdt), axis)
                    }
                }
            }
            Fx | Fy | Fz | Fm | Tx | Ty | Tz | Tm => {
                let (fi, fj) = (self.frame(m.i)?, self.frame(m.j)?);
                let p = self.pose(&fi).0;
                let (f, t) = self.net_wrench(fi.body, fj.body, p)?;
                match kind {
                    Fm => f.length(),
                    Tm => t.length(),
                    Fx | Fy | Fz => {
                        let axis = match kind {
                            Fx => 0,
                            Fy => 1,
                            _ => 2,
                        };
                        pick(resolve(&self.axes(m.k)?, f), axis)
                    }
                    _ => {
                        let axis = match kind {
                            Tx => 0,
                            Ty => 1,
                            _ => 2,
                        };
                        pick(resolve(&self.axes(m.k)?, t), axis)
                    }
                }
            }
            Psi | Theta | Phi => {
                let k = match kind {
                    Psi => 0,
                    Theta => 1,
                    _ => 2,
                };
                self.continued_angles(m.i, m.j)?[k]
            }
            _ => return Ok(Dual::constant(self.inner.measure(kind, m, false)?.value())),
        };
        Ok(Dual::constant(value))
    }

    fn rotation(&self, i: u32, j: u32, _gradient: bool) -> Result<[Dual; 9], EvalError> {
        self.inner.rotation(i, j, false)
    }

    /// The angles of the previous output; this output's, continued from them, are kept for
    /// the next (an unknown marker is left to `rotation` to report).
    fn euler313_previous(&self, i: u32, j: u32) -> Option<[f64; 3]> {
        let previous = self.angles.borrow().previous((i, j));
        let _ = self.continued_angles(i, j);
        previous
    }

    fn element_force(
        &self,
        kind: ElementForce,
        args: ElementForceArgs,
        _gradient: bool,
    ) -> Result<Dual, EvalError> {
        let (f, t) = self.element_wrench(kind, args.id, args.on_j)?;
        let r = self.axes(args.rm)?;
        let (f, t) = (resolve(&r, f), resolve(&r, t));
        Ok(Dual::constant(match args.component {
            ForceComponent::Fm => f.length(),
            ForceComponent::Fx => f.x,
            ForceComponent::Fy => f.y,
            ForceComponent::Fz => f.z,
            ForceComponent::Tm => t.length(),
            ForceComponent::Tx => t.x,
            ForceComponent::Ty => t.y,
            ForceComponent::Tz => t.z,
        }))
    }

    fn state(&self, state: StateRef, _gradient: bool) -> Result<Dual, EvalError> {
        crate::physics::control_states::read_state(
            &self.set.data,
            &self.output.state,
            state,
            false,
            &|id, _| self.varval(id).map(Dual::constant),
        )
    }

    fn spline(&self, id: u32) -> Option<&SplineData> {
        self.set.data.splines.get(&id)
    }
}
