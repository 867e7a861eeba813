//! Every FRICTION of a model, read-only: the laws, and the state each starts with at the
//! dataset's input configuration. The state a run carries is data of its [`State`]
//! (`State::elements.frictions`, [`FrictionState`] per friction in model order), started by
//! [`FrictionSet::start`] and moved by [`FrictionSet::accept`]; a state without it (one the
//! initial conditions did not start) reads as [`FrictionSet::initial`].

use super::{FrictionLaw, FrictionState, FrictionValue};
use crate::constraints::rows::Velocities;
use crate::physics::applied::Regime;
use crate::physics::forces::algebra::Real;
use crate::physics::forces::{marker_frame, Context, Loads};
use crate::physics::reactions::Reaction;
use crate::state::State;
use linkage_model::Model;

/// The model's frictions.
#[derive(Clone, Debug, Default)]
pub struct FrictionSet {
    laws: Vec<FrictionLaw>,
    /// Each friction anchored at the input configuration with the normal load of its preload.
    initial: Vec<FrictionState>,
}

impl FrictionSet {
    /// The frictions of `model`, with their states anchored at its input configuration with
    /// the normal load of their preloads.
    pub fn new(model: &Model) -> FrictionSet {
        let laws: Vec<FrictionLaw> = model
            .frictions
            .iter()
            .map(|f| FrictionLaw::new(f, marker_frame(model, f.i), marker_frame(model, f.j)))
            .collect();
        let input = State::input(model);
        let initial = laws.iter().map(|l| l.start(&input)).collect();
        FrictionSet { laws, initial }
    }

    pub fn is_empty(&self) -> bool {
        self.laws.is_empty()
    }

    /// The laws, in model order.
    pub fn laws(&self) -> &[FrictionLaw] {
        &self.laws
    }

    /// The states at the input configuration, with the preloads' normal loads.
    pub fn initial(&self) -> &[FrictionState] {
        &self.initial
    }

    /// The state of every friction at `s`: the run's, or [`FrictionSet::initial`] when `s`
    /// carries none.
    pub fn states<'a>(&'a self, s: &'a State) -> &'a [FrictionState] {
        let carried = &s.elements.frictions;
        if carried.len() == self.laws.len() {
            carried
        } else {
            &self.initial
        }
    }

    /// The state of friction `k` at `s`.
    pub fn state(&self, s: &State, k: usize) -> FrictionState {
        self.states(s)[k]
    }

    /// The states `s` carries, started from [`FrictionSet::initial`] when it carries none.
    fn states_mut<'a>(&self, s: &'a mut State) -> &'a mut [FrictionState] {
        let carried = &mut s.elements.frictions;
        if carried.len() != self.laws.len() {
            carried.clear();
            carried.extend_from_slice(&self.initial);
        }
        carried
    }

    /// Whether friction `k` acts in `regime` (not in statics when INACTIVE_DURING=STATIC).
    pub fn acts(&self, regime: Regime, k: usize) -> bool {
        !(regime == Regime::Static && self.laws[k].friction.inactive_static)
    }

    /// The largest stiction deformation of the frictions active in `regime` at `(s, v)` from
    /// their anchors, as a fraction of each one's MAX_STICTION_DEFORMATION (0 without any).
    pub fn stiction_fraction(&self, regime: Regime, s: &State, v: &Velocities) -> f64 {
        let states = self.states(s);
        let kin = crate::physics::forces::algebra::Kinematics {
            state: s,
            velocities: v,
        };
        let mut largest: f64 = 0.0;
        for (k, law) in self.laws.iter().enumerate() {
            if !self.acts(regime, k) {
                continue;
            }
            let slip = law.slip::<f64>(&kin, &states[k]);
            let size = slip.deformation[..slip.dims]
                .iter()
                .map(|c| c * c)
                .sum::<f64>()
                .sqrt();
            largest = largest.max(size / law.regime.max_deformation);
        }
        largest
    }

    /// Sets the normal load of friction `k` in `s` (its anchor unchanged): statics takes it
    /// from the Newton iterate's multipliers.
    pub fn set_normal(&self, s: &mut State, k: usize, normal: f64) {
        self.states_mut(s)[k].normal = normal;
    }

    /// Calls `sink` with the loads of every friction active in `regime` at `cx` (with the
    /// states its state carries).
    pub fn each_load<R: Real>(&self, regime: Regime, cx: &Context, mut sink: impl FnMut(Loads<R>)) {
        if self.laws.is_empty() {
            return;
        }
        let states = self.states(cx.kin.state);
        for (k, law) in self.laws.iter().enumerate() {
            if self.acts(regime, k) {
                sink(law.loads::<R>(cx, &states[k]));
            }
        }
    }

    /// Anchors every friction at `s` (the normal loads of the preloads alone), in `s`.
    pub fn start(&self, s: &mut State) {
        let started: Vec<FrictionState> = self.laws.iter().map(|l| l.start(s)).collect();
        s.elements.frictions = started;
    }

    /// Takes the normal loads from `reactions` and moves the anchors in `s` (see
    /// [`FrictionLaw::accept`]); returns the largest change of a normal load.
    pub fn accept(&self, s: &mut State, v: &Velocities, reactions: &[Reaction]) -> f64 {
        // Taken out of `s` while the laws read its positions (no allocation once started).
        let mut states = std::mem::take(&mut s.elements.frictions);
        if states.len() != self.laws.len() {
            states.clear();
            states.extend_from_slice(&self.initial);
        }
        let mut change: f64 = 0.0;
        for (law, st) in self.laws.iter().zip(states.iter_mut()) {
            let next = law.accept(s, v, reactions, st);
            change = change.max((next.normal - st.normal).abs());
            *st = next;
        }
        s.elements.frictions = states;
        change
    }

    /// The value of each friction at `(s, v)` in `regime` (zero when it is off there).
    pub fn values(&self, regime: Regime, s: &State, v: &Velocities) -> Vec<FrictionValue> {
        let states = self.states(s);
        self.laws
            .iter()
            .enumerate()
            .map(|(k, l)| l.value(s, v, &states[k], self.acts(regime, k)))
            .collect()
    }
}
