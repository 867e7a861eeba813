//! What every step of a dynamic (or kinematic) run needs and that does not change: the model,
//! the kept and removed rows, the drivers and force elements, extra damping and frozen time;
//! the generalized forces `Q` and the rows' drive values at a state.

use super::error::IntegrationError;
use crate::constraints::drivers::Drivers;
use crate::constraints::drivers::MotionError;
use crate::constraints::rows::{RowGradient, Velocities};
use crate::constraints::system::System;
use crate::physics::applied::{AppliedForces, Regime};
use crate::physics::flex_inertia::FlexCoupling;
use crate::physics::mass;
use crate::state::State;
use glam::DVec3;
use linkage_model::Model;

/// Per-part damping added for dynamic settling: force `−c m v`, torque `−c I ω`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtraDamping(pub f64);

/// Everything the step needs that does not change.
pub struct Problem<'a> {
    pub model: &'a Model,
    pub sys: &'a System,
    /// Independent rows.
    pub rows: &'a [usize],
    /// Redundant rows, checked every step.
    pub redundant: &'a [usize],
    pub drivers: &'a dyn Drivers,
    pub forces: &'a dyn AppliedForces,
    pub damping: Option<ExtraDamping>,
    /// Freeze time at this value (dynamic settling): motions and forces see it.
    pub frozen_time: Option<f64>,
    /// The regime the forces are evaluated in: static for dynamic settling.
    pub regime: Regime,
    /// The flex bodies' rigid–modal inertia coupling, added to every mass matrix.
    pub coupling: FlexCoupling,
}

impl Problem<'_> {
    /// Number of moving parts.
    pub(crate) fn n(&self) -> usize {
        self.model.parts.len()
    }

    /// Number of control states (DIFF, LSE, TFSISO), appended to the unknowns after the
    /// multipliers.
    pub(crate) fn controls(&self) -> usize {
        self.forces.control_count()
    }

    /// The time motions, forces and constraints see at run time `t`.
    pub(crate) fn time(&self, t: f64) -> f64 {
        self.frozen_time.unwrap_or(t)
    }

    /// How fast the constraints' TIME advances: 0 when it is frozen.
    pub(crate) fn time_rate(&self) -> f64 {
        if self.frozen_time.is_some() {
            0.0
        } else {
            1.0
        }
    }

    /// An expression of row `r` that cannot be evaluated, with its element's name.
    pub(crate) fn row_error(&self, r: usize, e: &linkage_expr::EvalError) -> IntegrationError {
        let c = &self.model.constraints[self.sys.rows[r].element];
        IntegrationError::ConstraintRate {
            element: c.origin.name.clone(),
            cause: e.clone(),
        }
    }

    /// The state the force elements see: `s` itself, or (frozen time) a copy in `buf` with
    /// the frozen time. The copy reuses `buf`'s storage.
    pub(crate) fn force_state<'s>(&self, s: &'s State, buf: &'s mut State) -> &'s State {
        match self.frozen_time {
            None => s,
            Some(t) => {
                buf.poses.clone_from(&s.poses);
                buf.controls.clone_from(&s.controls);
                buf.elements.clone_from(&s.elements);
                buf.time = t;
                buf
            }
        }
    }

    /// `UCF·Q` into `q` (length 6n; mass × acceleration units): gravity `m g`, applied
    /// forces, gyroscopic terms `−ω × (I_g ω)` ([`mass::gyroscopic`]), extra damping
    /// `−c (m v, I_g ω)`. `buf` holds the force state when time is frozen.
    pub(crate) fn generalized_into(
        &self,
        s: &State,
        v: &Velocities,
        buf: &mut State,
        q: &mut [f64],
    ) -> Result<(), IntegrationError> {
        let ucf = self.model.ucf();
        q.fill(0.0);
        self.forces
            .add_forces(self.regime, self.force_state(s, buf), v, q)?;
        for x in q.iter_mut() {
            *x *= ucf;
        }
        let damping = self.damping.map(|ExtraDamping(c)| c);
        mass::add_body_loads(self.model, s, v, damping, q);
        Ok(())
    }

    /// Drive values of the rows (motions at time t, 0 for joints) into `out` (length m).
    pub(crate) fn drives_into(&self, t: f64, out: &mut [f64]) -> Result<(), IntegrationError> {
        for (o, &r) in out.iter_mut().zip(self.rows) {
            let row = &self.sys.rows[r];
            *o = if row.driven {
                let t = self.time(t);
                self.drivers
                    .value(row.element, t)
                    .ok_or_else(|| self.motion_error(row.element, t))?
            } else {
                0.0
            };
        }
        Ok(())
    }

    /// The motion `element` cannot be evaluated at `t`: its label and the drivers' reason.
    fn motion_error(&self, element: usize, t: f64) -> IntegrationError {
        MotionError::at(self.model, self.drivers, element, t).into()
    }

    /// `[f, ḟ, f̈]` of a motion at time t (frozen time gives zero rates).
    pub(crate) fn drive_series(&self, element: usize, t: f64) -> Option<[f64; 3]> {
        if let Some(t0) = self.frozen_time {
            return self.drivers.value(element, t0).map(|f| [f, 0.0, 0.0]);
        }
        self.drivers.rates(element, t)
    }

    /// Gradients of the independent rows at `s` into `grads` (one per row, storage reused).
    pub(crate) fn gradients(&self, s: &State, grads: &mut [RowGradient]) {
        for (g, &r) in grads.iter_mut().zip(self.rows) {
            self.sys.gradient(r, s, g);
        }
    }
}

/// Velocities (or accelerations) as 6 numbers per part: CM then angular, ground axes.
pub fn flat(v: &[(DVec3, DVec3)]) -> Vec<f64> {
    v.iter()
        .flat_map(|(a, b)| [a.x, a.y, a.z, b.x, b.y, b.z])
        .collect()
}

/// The inverse of [`flat`]: (CM, angular) pairs.
pub(crate) fn unflat(x: &[f64]) -> Vec<(DVec3, DVec3)> {
    let mut out = vec![(DVec3::ZERO, DVec3::ZERO); x.len() / 6];
    unflat_into(x, &mut out);
    out
}

/// [`unflat`] into existing storage.
pub(crate) fn unflat_into(x: &[f64], out: &mut [(DVec3, DVec3)]) {
    for (o, c) in out.iter_mut().zip(x.chunks_exact(6)) {
        *o = (DVec3::new(c[0], c[1], c[2]), DVec3::new(c[3], c[4], c[5]));
    }
}

/// `v0` with one entry per part of `p` (missing ones at rest).
pub(crate) fn padded(p: &Problem, v0: &Velocities) -> Vec<(DVec3, DVec3)> {
    (0..p.n())
        .map(|k| v0.get(k).copied().unwrap_or((DVec3::ZERO, DVec3::ZERO)))
        .collect()
}
