//! Descent to a stable equilibrium, for the models where Adams' modified Newton–Raphson does not
//! converge or converges to an unstable equilibrium: a saddle-free Newton iteration on the
//! constraint manifold.
//!
//! At each step, with least-squares multipliers at the configuration, the stiffness reduced to
//! the free motions and its modes against the mass (`K_r y = μ M_r y`, shapes `Φ`
//! mass-normalised, see [`super::stability`]) give the step
//!
//! ```text
//! ξ = Σ_j φ_j (φ_jᵀ F) / max(|μ_j|, DESCENT_SOFT_MODE · max|μ|)
//! ```
//!
//! which is Newton's step along every stiff mode and the reverse of it along every mode of
//! negative stiffness: it always goes downhill in the potential, away from saddles. The step is
//! capped by TLIMIT/ALIMIT like Newton's and brought back onto the constraints. Where every mode
//! is stiff (the configuration is in a basin), Adams' Newton is tried from there (at most every
//! [`DESCENT_NEWTON_EVERY`] steps); it converges to that basin's stable equilibrium.
//!
//! From an unstable equilibrium (where every force balances and no step would move) the
//! descent starts one kick along its negative-curvature mode away ([`DESCENT_KICK`]), back on
//! the constraints.

use super::newton::{Problem, Workspace};
use super::stability::{modes, Modes};
use super::{drive_values, equilibrium, Equilibrium, StaticsError};
use crate::constraints::drivers::Drivers;
use crate::constraints::system::System;
use crate::physics::applied::AppliedForces;
use crate::state::State;
use crate::tolerances::{
    DESCENT_KICK, DESCENT_MAX_DIM, DESCENT_NEWTON_EVERY, DESCENT_SOFT_MODE, DESCENT_STEPS,
    STATIC_CUT_PROJECTION,
};
use glam::DVec3;
use linkage_model::settings::EquilibriumSettings;
use linkage_model::Model;

/// Where a descent ended.
#[derive(Clone, Debug)]
pub struct Descent {
    /// The last equilibrium solve: converged at a stable equilibrium, or where the descent
    /// stopped.
    pub equilibrium: Equilibrium,
    /// Continuation steps taken (each one Newton step).
    pub steps: usize,
    /// Kicks off unstable equilibria.
    pub kicks: usize,
}

/// What the solves of one model share.
pub struct Solver<'a> {
    pub model: &'a Model,
    pub sys: &'a System,
    pub rows: &'a [usize],
    pub drivers: &'a dyn Drivers,
    pub forces: &'a dyn AppliedForces,
    pub settings: &'a EquilibriumSettings,
}

impl Solver<'_> {
    /// Adams' modified Newton–Raphson from `start` ([`equilibrium`]).
    pub fn newton(&self, start: &State) -> Result<Equilibrium, StaticsError> {
        self.newton_with(start, self.settings)
    }

    fn newton_with(
        &self,
        start: &State,
        settings: &EquilibriumSettings,
    ) -> Result<Equilibrium, StaticsError> {
        equilibrium(
            self.model,
            self.sys,
            self.rows,
            self.drivers,
            self.forces,
            start,
            settings,
        )
    }

    /// The modes of the free motions at `s` with least-squares multipliers (`None` where
    /// [`modes`] has none).
    pub fn modes_at(&self, s: &State) -> Result<Option<Modes>, StaticsError> {
        let p = self.problem(s)?;
        let mut w = Workspace::new(&p, s);
        let mut lambda = vec![0.0; p.used.len()];
        w.initial_multipliers(&p, s, &mut lambda)?;
        Ok(modes(
            self.model,
            self.sys,
            &p.used,
            &lambda,
            self.forces,
            s,
            DESCENT_MAX_DIM,
        ))
    }

    /// The modes at an equilibrium, with its own multipliers.
    fn modes_of(&self, e: &Equilibrium) -> Option<Modes> {
        let lambda: Vec<f64> = e.multipliers.iter().map(|(_, l)| *l).collect();
        let used: Vec<(usize, f64)> = e.multipliers.iter().map(|(r, _)| (*r, 0.0)).collect();
        modes(
            self.model,
            self.sys,
            &used,
            &lambda,
            self.forces,
            &e.state,
            DESCENT_MAX_DIM,
        )
    }

    fn problem(&self, s: &State) -> Result<Problem<'_>, StaticsError> {
        Ok(Problem {
            model: self.model,
            sys: self.sys,
            used: drive_values(self.model, self.sys, self.rows, self.drivers, s.time)?,
            forces: self.forces,
            settings: self.settings,
        })
    }

    /// `s` moved by [`DESCENT_KICK`] along `mode` (largest component: that many radians or
    /// characteristic lengths), back onto the constraints.
    fn kicked(&self, s: &State, mode: &Modes) -> Result<State, StaticsError> {
        let mut k = s.clone();
        let l = self.model.characteristic_length;
        for (i, (dx, dth)) in mode.lowest.iter().enumerate() {
            k.increment(i, *dx * (DESCENT_KICK * l), *dth * DESCENT_KICK);
        }
        let p = self.problem(&k)?;
        let mut w = Workspace::new(&p, &k);
        let tolerance = STATIC_CUT_PROJECTION * l.max(1.0);
        w.project_onto_constraints(&p, &mut k, tolerance);
        Ok(k)
    }

    /// Descends from `start` to a stable equilibrium (module docs); `unstable`: `start` is an
    /// unstable equilibrium to leave first. `Ok(None)`: the model is too large for the dense
    /// modes the descent steers by ([`DESCENT_MAX_DIM`]).
    pub fn descend(
        &self,
        start: &State,
        unstable: Option<&Equilibrium>,
    ) -> Result<Option<Descent>, StaticsError> {
        let mut s = match unstable {
            Some(e) => {
                let Some(mode) = self.modes_of(e) else {
                    return Ok(None);
                };
                self.kicked(&e.state, &mode)?
            }
            None => start.clone(),
        };
        let mut kicks = usize::from(unstable.is_some());
        let p = self.problem(&s)?;
        let mut w = Workspace::new(&p, &s);
        let mut lambda = vec![0.0; p.used.len()];
        let n = p.parts();
        let l = self.model.characteristic_length;
        let scale = |i: usize| if i % 6 < 3 { l } else { 1.0 };
        let tolerance = STATIC_CUT_PROJECTION * l.max(1.0);
        let mut newton_tried: Option<usize> = None;
        let mut xi = vec![0.0; 6 * n];
        for step in 1..=DESCENT_STEPS {
            w.initial_multipliers(&p, &s, &mut lambda)?;
            w.residuals(&p, &mut s, &lambda)?;
            if w.force.iter().any(|x| !x.is_finite()) {
                return Err(StaticsError::NotFinite { iteration: step });
            }
            let Some(m) = modes(
                self.model,
                self.sys,
                &p.used,
                &lambda,
                self.forces,
                &s,
                DESCENT_MAX_DIM,
            ) else {
                return Ok(None);
            };
            // Where every free motion is stiff, Newton takes over (at most every
            // DESCENT_NEWTON_EVERY steps): it converges there to the stable equilibrium.
            let convex = m.lowest_squared_frequency() > 0.0;
            if convex && newton_tried.is_none_or(|k| step >= k + DESCENT_NEWTON_EVERY) {
                newton_tried = Some(step);
                let e = self.newton(&s)?;
                if e.converged {
                    match (e.stability, self.modes_of(&e)) {
                        (Some((false, _)), Some(mode)) if kicks < DESCENT_KICKS => {
                            s = self.kicked(&e.state, &mode)?;
                            kicks += 1;
                            continue;
                        }
                        _ => {
                            return Ok(Some(Descent {
                                equilibrium: e,
                                steps: step,
                                kicks,
                            }))
                        }
                    }
                }
            }
            // The saddle-free Newton step: every mode's Newton step with its stiffness taken
            // by its size, ξ = Σ φ_j (φ_jᵀ F)/|μ_j| (a mode without stiffness at the floor).
            let largest = m
                .squared_frequencies
                .iter()
                .map(|x| x.abs())
                .fold(0.0, f64::max);
            // Without any stiffness, steepest descent (any positive scale: the step is capped).
            let floor = if largest > 0.0 {
                DESCENT_SOFT_MODE * largest
            } else {
                1.0
            };
            xi.fill(0.0);
            for (j, mu) in m.squared_frequencies.iter().enumerate() {
                let phi = m.shapes.col(j);
                let g: f64 = (0..6 * n).map(|i| phi[i] * w.force[i] * scale(i)).sum();
                let c = g / mu.abs().max(floor);
                for (i, x) in xi.iter_mut().enumerate() {
                    *x += c * phi[i];
                }
            }
            if xi.iter().any(|x| !x.is_finite()) {
                break;
            }
            // TLIMIT/ALIMIT cap the step of every part alike.
            let mut cut: f64 = 1.0;
            for k in 0..n {
                let dx = DVec3::new(xi[6 * k], xi[6 * k + 1], xi[6 * k + 2]) * l;
                let dth = DVec3::new(xi[6 * k + 3], xi[6 * k + 4], xi[6 * k + 5]);
                cut = cut
                    .min(self.settings.tlimit / dx.length())
                    .min(self.settings.alimit / dth.length());
            }
            for k in 0..n {
                let dx = DVec3::new(xi[6 * k], xi[6 * k + 1], xi[6 * k + 2]) * (l * cut);
                let dth = DVec3::new(xi[6 * k + 3], xi[6 * k + 4], xi[6 * k + 5]) * cut;
                s.increment(k, dx, dth);
            }
            w.project_onto_constraints(&p, &mut s, tolerance);
        }
        // Out of steps: Newton from where the descent stopped says how far it is.
        let e = self.newton(&s)?;
        Ok(Some(Descent {
            equilibrium: e,
            steps: DESCENT_STEPS,
            kicks,
        }))
    }
}

/// Most kicks off unstable equilibria in one descent.
const DESCENT_KICKS: usize = 4;
