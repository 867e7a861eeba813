//! Every FRICTION of a model with its state ([`FrictionState`]), behind a lock so that the
//! force interface (`&self`) can carry it from one accepted state to the next.

use super::{FrictionLaw, FrictionState, FrictionValue};
use crate::constraints::rows::Velocities;
use crate::physics::applied::Regime;
use crate::physics::forces::algebra::Real;
use crate::physics::forces::{marker_frame, Context, Loads};
use crate::physics::reactions::Reaction;
use crate::state::State;
use linkage_model::Model;
use std::sync::{Mutex, MutexGuard};

/// What the analyses change: the states.
#[derive(Clone, Debug, Default)]
struct Shared {
    states: Vec<FrictionState>,
}

/// The model's frictions and their states.
#[derive(Debug, Default)]
pub struct FrictionSet {
    laws: Vec<FrictionLaw>,
    shared: Mutex<Shared>,
}

impl Clone for FrictionSet {
    fn clone(&self) -> Self {
        FrictionSet {
            laws: self.laws.clone(),
            shared: Mutex::new(self.lock().clone()),
        }
    }
}

impl FrictionSet {
    /// The frictions of `model`, anchored at its input configuration, with the normal load of
    /// their preloads.
    pub fn new(model: &Model) -> FrictionSet {
        let laws: Vec<FrictionLaw> = model
            .frictions
            .iter()
            .map(|f| FrictionLaw::new(f, marker_frame(model, f.i), marker_frame(model, f.j)))
            .collect();
        let input = State::input(model);
        let states = laws.iter().map(|l| l.start(&input)).collect();
        FrictionSet {
            laws,
            shared: Mutex::new(Shared { states }),
        }
    }

    fn lock(&self) -> MutexGuard<'_, Shared> {
        // A panic elsewhere while the lock was held leaves plain data behind: keep using it.
        self.shared.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub fn is_empty(&self) -> bool {
        self.laws.is_empty()
    }

    /// The laws, in model order.
    pub fn laws(&self) -> &[FrictionLaw] {
        &self.laws
    }

    /// The current state of each friction.
    pub fn states(&self) -> Vec<FrictionState> {
        self.lock().states.clone()
    }

    /// Whether friction `k` acts in `regime` (not in statics when INACTIVE_DURING=STATIC).
    pub fn acts(&self, regime: Regime, k: usize) -> bool {
        !(regime == Regime::Static && self.laws[k].friction.inactive_static)
    }

    /// The state of friction `k`.
    pub fn state(&self, k: usize) -> FrictionState {
        self.lock().states[k]
    }

    /// The largest stiction deformation of the frictions active in `regime` at `(s, v)` from
    /// their anchors, as a fraction of each one's MAX_STICTION_DEFORMATION (0 without any).
    pub fn stiction_fraction(&self, regime: Regime, s: &State, v: &Velocities) -> f64 {
        let shared = self.lock();
        let kin = crate::physics::forces::algebra::Kinematics {
            state: s,
            velocities: v,
        };
        let mut largest: f64 = 0.0;
        for (k, law) in self.laws.iter().enumerate() {
            if !self.acts(regime, k) {
                continue;
            }
            let slip = law.slip::<f64>(&kin, &shared.states[k]);
            let size = slip.deformation[..slip.dims]
                .iter()
                .map(|c| c * c)
                .sum::<f64>()
                .sqrt();
            largest = largest.max(size / law.regime.max_deformation);
        }
        largest
    }

    /// Sets the normal load of friction `k` (its anchor unchanged): statics takes it from the
    /// Newton iterate's multipliers.
    pub fn set_normal(&self, k: usize, normal: f64) {
        self.lock().states[k].normal = normal;
    }

    /// Calls `sink` with the loads of every friction active in `regime` at `cx`.
    pub fn each_load<R: Real>(&self, regime: Regime, cx: &Context, mut sink: impl FnMut(Loads<R>)) {
        if self.laws.is_empty() {
            return;
        }
        let shared = self.lock();
        for (k, law) in self.laws.iter().enumerate() {
            if self.acts(regime, k) {
                sink(law.loads::<R>(cx, &shared.states[k]));
            }
        }
    }

    /// Anchors every friction at `s` (the normal loads of the preloads alone).
    pub fn start(&self, s: &State) {
        let mut shared = self.lock();
        shared.states = self.laws.iter().map(|l| l.start(s)).collect();
    }

    /// Takes the normal loads from `reactions` and moves the anchors (see
    /// [`FrictionLaw::accept`]); returns the largest change of a normal load.
    pub fn accept(&self, s: &State, v: &Velocities, reactions: &[Reaction]) -> f64 {
        let mut shared = self.lock();
        let mut change: f64 = 0.0;
        for (law, st) in self.laws.iter().zip(shared.states.iter_mut()) {
            let next = law.accept(s, v, reactions, st);
            change = change.max((next.normal - st.normal).abs());
            *st = next;
        }
        change
    }

    /// The value of each friction at `(s, v)` in `regime` (zero when it is off there).
    pub fn values(&self, regime: Regime, s: &State, v: &Velocities) -> Vec<FrictionValue> {
        let shared = self.lock();
        self.laws
            .iter()
            .enumerate()
            .map(|(k, l)| l.value(s, v, &shared.states[k], self.acts(regime, k)))
            .collect()
    }

    /// The largest normal load, for the scale of convergence tests.
    pub fn largest_normal(&self) -> f64 {
        self.lock()
            .states
            .iter()
            .map(|s| s.normal)
            .fold(0.0, f64::max)
    }
}
