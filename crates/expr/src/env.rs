//! The environment an expression is evaluated in: time, mode, measures, states, splines.

use crate::catalog::{ElementForce, ForceComponent, MeasureKind};
use crate::dual::Dual;
use crate::error::EvalError;
use crate::spline::SplineData;

/// Marker ids of a measure, by role. Omitted optional arguments are 0, meaning ground
/// (`j` = ground origin, `k` = ground axes, `l` = ground frame). Which positional argument
/// fills which role is given by [`MeasureKind::marker_roles`]; for example `VM(i, j, l)`
/// fills `l` from its third argument, `VX(i, j, k, l)` fills `k` from its third.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct MarkerArgs {
    /// The measured marker.
    pub i: u32,
    /// The reference marker (0 = ground origin).
    pub j: u32,
    /// The marker whose axes the result is resolved in (0 = ground axes).
    pub k: u32,
    /// The marker whose frame time derivatives are taken in (0 = ground frame).
    pub l: u32,
}

/// Arguments of an element force function `NAME(id, jflag, comp [, rm])`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ElementForceArgs {
    /// The element id (e.g. JOINT/id).
    pub id: u32,
    /// `jflag = 1`: the force acting on the J marker; `jflag = 0`: on the I marker.
    pub on_j: bool,
    /// The requested component (`comp` 1..=8).
    pub component: ForceComponent,
    /// Marker whose axes resolve the result (0 or omitted = ground).
    pub rm: u32,
}

/// A reference to a solver state, with its evaluated ids.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StateRef {
    /// `VARVAL(id)`: value of VARIABLE/id.
    Varval(u32),
    /// `DIF(id)`: state of DIFF/id.
    Dif(u32),
    /// `DIF1(id)`: time derivative of DIFF/id.
    Dif1(u32),
    /// `ARYVAL(id, index)`: value number `index` (1-based) of ARRAY/id.
    Aryval {
        /// The ARRAY id.
        id: u32,
        /// 1-based position in the array.
        index: u32,
    },
    /// `PINVAL(id, index)`: the VARIABLE at position `index` (1-based) of PINPUT/id.
    Pinval {
        /// The PINPUT id.
        id: u32,
        /// 1-based position in the list.
        index: u32,
    },
    /// `POUVAL(id, index)`: the VARIABLE at position `index` (1-based) of POUTPUT/id.
    Pouval {
        /// The POUTPUT id.
        id: u32,
        /// 1-based position in the list.
        index: u32,
    },
    /// `SENVAL(id)`: the value SENSOR/id stored when it last fired (0 before it fires).
    Senval(u32),
}

/// What an expression can observe. The solver implements this; the expression crate knows
/// nothing about parts or markers.
///
/// Every method returning a [`Dual`] receives `gradient`: when `false` (plain
/// [`crate::evaluate`]) only the value is used and the implementation may return
/// [`Dual::constant`]; when `true` ([`crate::evaluate_with_gradient`]) it must return the
/// partial derivatives with respect to its own variables (indices of its choosing, used
/// consistently across calls). An unknown id should be reported with
/// [`EvalError::unknown_reference`] naming it (e.g. `VARIABLE/12 does not exist`).
///
/// Only [`Env::time`] is required; the defaults of the other methods report the quantity as
/// unavailable (useful for contexts such as MOTION functions that only see time).
pub trait Env {
    /// Current simulation time.
    fn time(&self) -> f64;

    /// Analysis mode code returned by `MODE` (default 0).
    fn mode(&self) -> i32 {
        0
    }

    /// Variable index to attach to `TIME` in gradient evaluation, if the caller wants ∂/∂t
    /// (default: none, TIME is a constant for the gradient).
    fn time_variable(&self) -> Option<u32> {
        None
    }

    /// Value (and gradient) of a marker measure.
    fn measure(
        &self,
        kind: MeasureKind,
        markers: MarkerArgs,
        gradient: bool,
    ) -> Result<Dual, EvalError> {
        let _ = (markers, gradient);
        Err(EvalError::unavailable(format!(
            "{} is not available in this context",
            kind.name()
        )))
    }

    /// A marker measure as a truncated Taylor series along the environment's current motion:
    /// `[m, dm/dt, d²m/dt²]` (the value and its first two total time derivatives), used by
    /// [`crate::evaluate_path_series`]. What "the current motion" is belongs to the
    /// environment (for the solver: part poses moving with given velocities and
    /// accelerations).
    ///
    /// Default: an [`crate::EvalErrorKind::NotTimeOnly`] error (contexts such as MOTION
    /// functions, where only TIME may vary).
    fn measure_series(
        &self,
        kind: MeasureKind,
        markers: MarkerArgs,
    ) -> Result<[f64; 3], EvalError> {
        let _ = markers;
        Err(EvalError::not_time_only(kind.name()))
    }

    /// The direction cosines of marker `i` relative to marker `j` (0: ground), with their
    /// gradients, for `ORIENT` ([`crate::orient`]): the matrix `R = A_jᵀ·A_i` whose columns
    /// are i's axes resolved in j's axes, **column-major**: entry `3c + r` is
    /// `R[r][c] = x_j,r · x_i,c` (r, c = 0, 1, 2 for x, y, z). `gradient` as for
    /// [`Env::measure`].
    ///
    /// Default: unavailable.
    fn rotation(&self, i: u32, j: u32, gradient: bool) -> Result<[Dual; 9], EvalError> {
        let _ = (i, j, gradient);
        Err(EvalError::unavailable(
            "ORIENT is not available in this context",
        ))
    }

    /// The body 3-1-3 angles `[ψ, θ, φ]` (radians) of marker `i` relative to marker `j` at
    /// the previous output of the run being written, from which `ORIENT` continues the split
    /// of ψ and φ at θ ≈ 0 ([`crate::orient::euler313_continued`]).
    ///
    /// Default: none (no previous output).
    fn euler313_previous(&self, i: u32, j: u32) -> Option<[f64; 3]> {
        let _ = (i, j);
        None
    }

    /// The entries of [`Env::rotation`] as series along the current motion (as
    /// [`Env::measure_series`]): `[R, dR/dt, d²R/dt²]` per entry, same order.
    ///
    /// Default: an [`crate::EvalErrorKind::NotTimeOnly`] error.
    fn rotation_series(&self, i: u32, j: u32) -> Result<[[f64; 3]; 9], EvalError> {
        let _ = (i, j);
        Err(EvalError::not_time_only("ORIENT"))
    }

    /// The rate of TIME along the motion of [`crate::evaluate_path_series`]: 1 (default), or 0
    /// when the caller freezes time (e.g. for second derivatives with respect to positions
    /// only, or dynamic settling at a fixed time).
    fn time_rate(&self) -> f64 {
        1.0
    }

    /// Value (and gradient) of an element force function such as `JOINT(id, jflag, comp, rm)`.
    fn element_force(
        &self,
        kind: ElementForce,
        args: ElementForceArgs,
        gradient: bool,
    ) -> Result<Dual, EvalError> {
        let _ = (args, gradient);
        Err(EvalError::unavailable(format!(
            "{} is not available in this context",
            kind.name()
        )))
    }

    /// Value (and gradient) of a state reference (`VARVAL`, `DIF`, `DIF1`, `ARYVAL`).
    fn state(&self, state: StateRef, gradient: bool) -> Result<Dual, EvalError> {
        let _ = gradient;
        let name = match state {
            StateRef::Varval(_) => "VARVAL",
            StateRef::Dif(_) => "DIF",
            StateRef::Dif1(_) => "DIF1",
            StateRef::Aryval { .. } => "ARYVAL",
            StateRef::Pinval { .. } => "PINVAL",
            StateRef::Pouval { .. } => "POUVAL",
            StateRef::Senval(_) => "SENVAL",
        };
        Err(EvalError::unavailable(format!(
            "{name} is not available in this context"
        )))
    }

    /// The data of SPLINE/`id`, or `None` if there is no such spline.
    fn spline(&self, id: u32) -> Option<&SplineData> {
        let _ = id;
        None
    }
}

/// An environment with only a time value (and mode), e.g. for MOTION functions.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TimeEnv {
    /// The time.
    pub time: f64,
    /// The `MODE` code.
    pub mode: i32,
}

impl Env for TimeEnv {
    fn time(&self) -> f64 {
        self.time
    }
    fn mode(&self) -> i32 {
        self.mode
    }
}
