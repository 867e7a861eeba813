//! Singular pose or structural redundancy: the rank at nearby admissible configurations.
//!
//! At a singular configuration (a four-bar with its links collinear, a chain of parallelograms
//! with horizontal cranks) the Jacobian loses rank only there: the DOF and redundancy reported
//! at the input are not those of the mechanism. The rank is lower semi-continuous, so the
//! generic rank near the input is the largest rank found at nearby admissible poses; the
//! generic DOF and redundancy follow from it, and the input is singular when its rank differs.
//!
//! Nearby poses are reached in two ways, each ending with a least-change assembly
//! ([`crate::pipeline::assemble::assemble`], tightened to 10⁻¹¹ so that the rank decisions are not
//! disturbed by the assembly error; motions are left free):
//!
//! * **Random moves** ([`TRIALS`]): every part is moved by a random step — components uniform
//!   in ±10⁻² of the part's size (the largest distance of its markers from its centre of mass,
//!   at least 10⁻³·L) and ±10⁻² rad, deterministic seeds — and assembled back by least change
//!   from there, which moves the mechanism along its free motions. Away from a singular pose by
//!   ε the extra singular value grows like ε (ε² at a tangency), so 10⁻² keeps it clear of the
//!   rank tolerance.
//! * **Driven moves** (at most [`DRIVES`], only when a random move found a higher rank than the
//!   input's or none reached an admissible pose): where several branches meet, the nearest
//!   admissible pose of a random move often lies on a branch that is rank-deficient along its
//!   whole length (a loop of equal-length links folded flat). A revolute, cylindrical or
//!   translational joint of a closed loop gets its coordinate moved by 10⁻² (rad, or of the
//!   part size) as a hard condition of the assembly; each further drive picks, at random, a
//!   joint whose coordinate has not moved from the input yet (driving one crank of a chain of
//!   parallelograms unfolds the loops on one side of it; the next drive those left folded).
//!
//! When the rank analysis at an assembled pose admits a row the assembly did not enforce and
//! that row is violated, the assembly is repeated with the new set (at most four rounds). A
//! pose counts only when every non-motion equation holds to 10⁻⁸ (relative to L for lengths).
//! Ranks are decided by [`super::dense::analyse`] (an SVD per loop where loops are small: the
//! poses reached are not axis-aligned).
//!
//! Only loops (biconnected blocks) of at most [`MAX_LOOP_PARTS`] parts are moved and
//! re-analysed; larger ones keep their input rank and are counted in
//! [`GenericMobility::unchecked_loops`]. Long chains folded flat at a bifurcation are the
//! known hard case (the assembly converges poorly there): a chain of 30 parallelograms is found
//! at DOF 1, one of 100 is not (its generic DOF is then over-estimated).

use super::dense::analyse;
use crate::constraints::drivers::NoDrivers;
use crate::constraints::graph::Topology;
use crate::constraints::rows::Quantity;
use crate::constraints::system::{RowUnit, System, Tier};
use crate::pipeline::assemble::{assemble, HardKind, HardRow};
use crate::pipeline::verify::rank_analysis;
use crate::state::State;
use crate::tolerances::Tolerances;
use crate::tolerances::{ADMISSIBLE_RESIDUAL, SMALLEST_PART_SIZE, TIGHT_ASSEMBLY};
use glam::DVec3;
use linkage_adm::JointType;
use linkage_model::{Body, ConstraintKind, Model};

/// Number of random moves.
pub const TRIALS: usize = 3;
/// Driven moves at most.
pub const DRIVES: usize = 8;
/// Move size (fraction of the part size; radians).
pub const STEP: f64 = 1e-2;
/// Loops with more parts keep their input rank.
pub const MAX_LOOP_PARTS: usize = 200;

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
    /// `None` when no nearby pose could be assembled (or no loop was small enough to check);
    /// the input's when no constraint touches a moving part.
    pub generic: Option<Mobility>,
    /// The input rank differs from the generic rank.
    pub singular: bool,
    /// Moves tried (random and driven).
    pub trials: usize,
    /// Moves that reached an admissible configuration.
    pub assembled_trials: usize,
    /// Loops too large to be checked (their input rank is kept).
    pub unchecked_loops: usize,
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
    /// Uniform index below `n` (`n > 0`).
    fn index(&mut self, n: usize) -> usize {
        (((self.next() + 1.0) * 0.5 * n as f64) as usize).min(n.saturating_sub(1))
    }
}

/// Whether every non-motion row holds at `s` to [`ADMISSIBLE_RESIDUAL`] (lengths relative to
/// `length`).
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
        v.is_finite() && v.abs() <= ADMISSIBLE_RESIDUAL * scale
    })
}

/// The coordinate of joint `e` (rotation about z_j, or translation along z_j).
fn coordinate(sys: &System, e: usize, rotation: bool) -> Option<Quantity> {
    let (fi, fj) = sys.frames.get(e).copied().flatten()?;
    Some(if rotation {
        Quantity::Angle {
            x: fi.axis(0),
            x_ref: fj.axis(0),
            y_ref: fj.axis(1),
        }
    } else {
        Quantity::Proj {
            i: fi.origin(),
            j: fj.origin(),
            e: fj.axis(2),
        }
    })
}

/// The rank of `sys` at configurations near `s` (see the module docs). `at_input` is the
/// mobility at `s` by [`super::dense::analyse`] over `topo`.
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
    let nrows = sys.rows.len();
    let mut out = GenericMobility {
        at_input,
        generic: None,
        singular: false,
        trials: 0,
        assembled_trials: 0,
        unchecked_loops: 0,
        regular_state: None,
    };
    // The loops that are moved and re-analysed.
    let (small, large): (Vec<_>, Vec<_>) = topo
        .blocks
        .iter()
        .filter(|b| !b.parts.is_empty())
        .partition(|b| b.parts.len() <= MAX_LOOP_PARTS);
    out.unchecked_loops = large.len();
    if small.is_empty() {
        if large.is_empty() {
            // No constraint between moving parts: nothing can be singular.
            out.generic = Some(at_input);
        }
        return out;
    }
    let sub = Topology {
        blocks: small.into_iter().cloned().collect(),
        ..Topology::default()
    };
    let mut checked_element = vec![false; model.constraints.len()];
    let mut moved_part = vec![false; n];
    for b in &sub.blocks {
        for &e in &b.elements {
            if let Some(x) = checked_element.get_mut(e) {
                *x = true;
            }
        }
        for &p in &b.parts {
            moved_part[p] = true;
        }
    }
    let sub_input_rank = analyse(sys, s, &sub, length, tol).rank;
    let other_rank = at_input.rank.saturating_sub(sub_input_rank);
    let input_admitted: Vec<usize> = rank_analysis(sys, s, topo, length, tol).admitted;
    // Rows of the large loops: as admitted at the input.
    let fixed_rows: Vec<usize> = input_admitted
        .iter()
        .copied()
        .filter(|&r| sys.rows[r].tier != Tier::Motion && !checked_element[sys.rows[r].element])
        .collect();
    let rows_at = |state: &State| -> Vec<usize> {
        let mut rows = fixed_rows.clone();
        rows.extend(
            rank_analysis(sys, state, &sub, length, tol)
                .admitted
                .into_iter()
                .filter(|&r| sys.rows[r].tier != Tier::Motion),
        );
        rows
    };
    let mut tight = model.clone();
    tight.ic.error = TIGHT_ASSEMBLY * length.clamp(1.0, 100.0);
    tight.ic.maxit = tight.ic.maxit.max(50);
    // Assemble from `from` towards `reference` with the hard rows `hard`, enforcing the rows
    // admitted at the admissible pose `origin`; re-analyse and assemble again while a newly
    // admitted row is violated.
    let settle = |origin: &State,
                  from: &State,
                  reference: &State,
                  hard: &[HardRow]|
     -> Option<(Mobility, State)> {
        let mut rows = rows_at(origin);
        let mut state = from.clone();
        for _round in 0..4 {
            let asm = assemble(&tight, sys, &rows, hard, &NoDrivers, &state, reference);
            if !asm.converged {
                return None;
            }
            state = asm.state;
            if admissible(sys, &state, length) {
                let rank = other_rank + analyse(sys, &state, &sub, length, tol).rank;
                return Some((Mobility::new(n, nrows, rank), state));
            }
            rows = rows_at(&state);
        }
        None
    };
    // Size of each part: the largest distance of its markers from its centre of mass.
    let mut size = vec![0.0f64; n];
    for mk in &model.markers {
        if let Body::Part(k) = mk.body {
            size[k] = size[k].max(mk.p_bm.length());
        }
    }
    let size: Vec<f64> = size
        .iter()
        .map(|x| x.max(SMALLEST_PART_SIZE * length))
        .collect();
    let mut results: Vec<(Mobility, State)> = Vec::new();
    // Random moves.
    for t in 0..TRIALS {
        let mut rng = Rng(0x5EED_0000_0000_0001 ^ ((t as u64 + 1) << 32));
        let mut start = s.clone();
        for k in (0..n).filter(|&k| moved_part[k]) {
            let dx = rng.vec() * (STEP * size[k]);
            let dth = rng.vec() * STEP;
            start.increment(k, dx, dth);
        }
        out.trials += 1;
        results.extend(settle(s, &start, &start, &[]));
    }
    // Driven moves, when the random ones suggest a singular pose.
    let suspicious = results.is_empty() || results.iter().any(|(m, _)| m.rank > at_input.rank);
    let drivable: Vec<(usize, bool, Quantity, f64)> = if suspicious {
        sub.blocks
            .iter()
            .filter(|b| b.elements.len() > 1)
            .flat_map(|b| b.elements.iter().copied())
            .filter_map(|e| {
                let rotation = match &model.constraints[e].kind {
                    ConstraintKind::Joint { kind, .. } => match kind {
                        JointType::Revolute | JointType::Cylindrical => true,
                        JointType::Translational => false,
                        _ => return None,
                    },
                    _ => return None,
                };
                let q = coordinate(sys, e, rotation)?;
                let step = if rotation {
                    STEP
                } else {
                    let (i, j) = model.constraints[e].markers()?;
                    let part = |m: usize| model.markers[m].body.part().map_or(0.0, |k| size[k]);
                    STEP * part(i).max(part(j)).max(SMALLEST_PART_SIZE * length)
                };
                Some((e, rotation, q, step))
            })
            .collect()
    } else {
        Vec::new()
    };
    let mut rng = Rng(0xD81F_E000_0000_0001);
    let mut cur = s.clone();
    let mut driven: Vec<usize> = Vec::new();
    for _ in 0..DRIVES.min(drivable.len()) {
        // Joints whose coordinate has not moved from the input yet (a loop still folded).
        let stuck: Vec<usize> = (0..drivable.len())
            .filter(|k| !driven.contains(k))
            .filter(|&k| {
                let (_, _, q, step) = &drivable[k];
                (q.value(&cur) - q.value(s)).abs() < 0.1 * step
            })
            .collect();
        if stuck.is_empty() {
            break;
        }
        let k = stuck[rng.index(stuck.len())];
        driven.push(k);
        let (e, rotation, quantity, step) = drivable[k].clone();
        let sign = if rng.next() < 0.0 { -1.0 } else { 1.0 };
        let target = quantity.value(&cur) + sign * step;
        let hard = HardRow {
            name: model.constraints[e].origin.name.clone(),
            kind: HardKind::Driven,
            label: HardKind::Driven.label().into(),
            quantity,
            target,
            unit: if rotation {
                RowUnit::Angle
            } else {
                RowUnit::Length
            },
        };
        out.trials += 1;
        if let Some((m, st)) = settle(&cur, &cur, &cur, &[hard]) {
            cur = st.clone();
            results.push((m, st));
        }
    }
    out.assembled_trials = results.len();
    let best = results
        .into_iter()
        .fold(None, |best: Option<(Mobility, State)>, x| match best {
            Some(b) if b.0.rank >= x.0.rank => Some(b),
            _ => Some(x),
        });
    if let Some((m, st)) = best {
        out.generic = Some(m);
        out.singular = m.rank != at_input.rank;
        out.regular_state = Some(st);
    }
    out
}
