//! Singular pose or structural redundancy: the rank at nearby admissible configurations.
//!
//! At a singular configuration (a four-bar with its links collinear, a chain of parallelograms
//! with horizontal cranks) the Jacobian loses rank only there: the DOF and redundancy reported
//! at the input are not those of the mechanism. Each trial moves every part by a random
//! step (components uniform in ±10⁻²·L for the centre of mass and ±10⁻² rad for the
//! orientation, deterministic seeds; away from a singular pose by ε the extra singular value
//! grows like ε, or ε² at a tangency, so 10⁻² keeps it clear of the rank tolerance 10⁻⁶), then assembles onto the constraints by least change from
//! that perturbed configuration ([`crate::assemble::assemble`], tightened to 10⁻¹¹ (of L, at least 1,
//! at most 100) so that the rank decisions are not disturbed by the assembly error), which moves the mechanism
//! along its free motions. Motions are left free. When the rank analysis at the new
//! configuration admits a row the assembly did not enforce and that row is not satisfied, the
//! assembly is repeated with the new set (at most four rounds). A trial counts only when every
//! non-motion equation holds to 10⁻⁸ (relative to L for lengths), far below the rank tolerance.
//!
//! Ranks are decided by [`super::dense::analyse`] (an SVD per loop where loops are small: the
//! random poses are not axis-aligned). The rank is lower semi-continuous, so the generic rank near the input is the largest rank
//! found; the generic DOF and redundancy follow from it, and the configuration is singular
//! when the input rank differs.

use super::dense::analyse;
use crate::assemble::assemble;
use crate::graph::Topology;
use crate::state::State;
use crate::system::{RowUnit, System, Tier};
use crate::tolerances::Tolerances;
use crate::verify::{rank_analysis, NoDrivers};
use glam::DVec3;
use linkage_model::Model;

/// Number of random trials.
pub const TRIALS: usize = 3;
/// Perturbation size (fraction of the characteristic length; radians).
pub const STEP: f64 = 1e-2;

/// Rank, DOF and redundancy at one configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mobility {
    pub rank: usize,
    pub dof: i64,
    pub redundant: usize,
}

impl Mobility {
    pub fn new(moving_parts: usize, rows: usize, rank: usize) -> Mobility {
        Mobility {
            rank,
            dof: 6 * moving_parts as i64 - rank as i64,
            redundant: rows.saturating_sub(rank),
        }
    }
}

/// Mobility at the input and at nearby regular configurations.
#[derive(Clone, Debug)]
pub struct GenericMobility {
    pub at_input: Mobility,
    /// `None` when no trial could be assembled.
    pub generic: Option<Mobility>,
    /// The input rank differs from the generic rank.
    pub singular: bool,
    pub trials: usize,
    /// Trials that reached an admissible configuration.
    pub assembled_trials: usize,
    /// An admissible configuration with the generic rank (when found).
    pub regular_state: Option<State>,
}

/// splitmix64.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        // Uniform in [-1, 1).
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    fn vec(&mut self) -> DVec3 {
        DVec3::new(self.next(), self.next(), self.next())
    }
}

/// Whether every non-motion row holds at `s` to 10⁻⁸ (lengths relative to `length`).
fn admissible(sys: &System, s: &State, length: f64) -> bool {
    sys.rows.iter().enumerate().all(|(r, row)| {
        if row.tier == Tier::Motion {
            return true;
        }
        let v = sys.residual(r, s, 0.0);
        let scale = match row.unit {
            RowUnit::Length | RowUnit::Mixed => length,
            RowUnit::Direction | RowUnit::Angle => 1.0,
        };
        v.is_finite() && v.abs() <= 1e-8 * scale
    })
}

/// The rank of `sys` at configurations near `s` (see the module docs).
pub fn generic_mobility(
    model: &Model,
    sys: &System,
    topo: &Topology,
    s: &State,
    tol: &Tolerances,
    at_input: Mobility,
) -> GenericMobility {
    let n = model.parts.len();
    let length = model.characteristic_length;
    let mut tight = model.clone();
    tight.ic.error = 1e-11 * length.clamp(1.0, 100.0);
    tight.ic.maxit = tight.ic.maxit.max(50);
    let non_motion = |admitted: &[usize]| -> Vec<usize> {
        admitted
            .iter()
            .copied()
            .filter(|&r| sys.rows[r].tier != Tier::Motion)
            .collect()
    };
    let base = rank_analysis(sys, s, topo, length, tol);
    let mut best: Option<(Mobility, State)> = None;
    let mut assembled = 0;
    for t in 0..TRIALS {
        let mut rng = Rng(0x5EED_0000_0000_0001 ^ ((t as u64 + 1) << 32));
        let mut start = s.clone();
        for k in 0..n {
            let dx = rng.vec() * (STEP * length);
            let dth = rng.vec() * STEP;
            start.increment(k, dx, dth);
        }
        let mut rows = non_motion(&base.admitted);
        let mut state = start.clone();
        let mut found = None;
        for _round in 0..4 {
            let asm = assemble(&tight, sys, &rows, &[], &NoDrivers, &state, &start);
            if !asm.converged {
                break;
            }
            state = asm.state;
            if admissible(sys, &state, length) {
                let rank = analyse(sys, &state, topo, length, tol).rank;
                found = Some(Mobility::new(n, sys.rows.len(), rank));
                break;
            }
            let ra = rank_analysis(sys, &state, topo, length, tol);
            rows = non_motion(&ra.admitted);
        }
        if let Some(m) = found {
            assembled += 1;
            if best.as_ref().is_none_or(|(b, _)| m.rank > b.rank) {
                best = Some((m, state));
            }
        }
    }
    let (generic, regular_state) = match best {
        Some((m, st)) => (Some(m), Some(st)),
        None => (None, None),
    };
    GenericMobility {
        at_input,
        generic,
        singular: generic.is_some_and(|g| g.rank != at_input.rank),
        trials: TRIALS,
        assembled_trials: assembled,
        regular_state,
    }
}
