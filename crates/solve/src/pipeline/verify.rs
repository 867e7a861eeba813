//! Model verification (DESIGN §4): counts, Gruebler count, DOF, redundant equations (priority
//! policy), misaligned joints, consistency, unconstrained and massless parts.
//!
//! Cost: O(rows) to evaluate, plus one sparse rank-revealing elimination per closed-loop block
//! (tree joints form blocks of their own and are never redundant).

use crate::constraints::graph::{topology, Topology};
use crate::constraints::rank::{greedy_rank, RankSettings, SparseRows};
use crate::constraints::residuals::{report_residual, residuals, within_tolerance};
use crate::constraints::rows::RowGradient;
use crate::constraints::system::{System, Tier};
use crate::state::State;
use crate::tolerances::{Tolerances, DEPENDENCY_COEFFICIENT};
use linkage_model::{ConstraintKind, Model};
use std::borrow::Cow;

// The motion drivers live with the constraints; re-exported for the analyses' paths.
use crate::constraints::drivers::Drivers;

/// One equation another depends on, with its coefficient: `r ≈ Σ c_k a_k`.
#[derive(Clone, Debug, PartialEq)]
pub struct Dependency {
    pub row: usize,
    pub coefficient: f64,
}

/// A redundant constraint equation.
#[derive(Clone, Debug, PartialEq)]
pub struct RedundantEquation {
    pub row: usize,
    /// Residual at the analysed configuration in report units (length, or degrees for
    /// rotational rows); `None` when it cannot be evaluated (a motion function linkage cannot
    /// evaluate).
    pub residual: Option<f64>,
    /// `Some(true)` when the residual is within tolerance at an assembled configuration,
    /// `Some(false)` when not, `None` when unknown (the configuration is not assembled).
    pub consistent: Option<bool>,
    /// The admitted equations it is a combination of.
    pub depends_on: Vec<Dependency>,
    /// The rank decision was within the near-tie factor of the tolerance.
    pub near_tie: bool,
    /// Relative size of the row's component outside the admitted rows (the decision value).
    pub decision: f64,
}

/// A constraint equation violated at the input configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Misalignment {
    pub row: usize,
    /// In length units, or degrees for rotational equations.
    pub residual: f64,
}

/// A massless part whose motion the constraints leave free.
#[derive(Clone, Debug, PartialEq)]
pub struct MasslessFreedom {
    pub part: usize,
    /// Free coordinates of the part among `x, y, z, rx, ry, rz` (first dependent columns).
    pub coordinates: Vec<&'static str>,
}

/// Result of [`verify`].
#[derive(Clone, Debug)]
pub struct Verification {
    pub system: System,
    /// Moving bodies: parts, point masses and FE nodes.
    pub moving_parts: usize,
    /// Point masses among them (3 degrees of freedom each: their 3 held rotations are among
    /// `rows`, as a rotation hold each).
    pub point_masses: usize,
    /// FE nodes among them (their part counted as an equivalent linear flexible body in the
    /// Gruebler count, see `fe_parts`).
    pub fe_nodes: usize,
    /// Rotation-hold rows among `rows` (3 per point mass and per 3DCABLE node).
    pub hold_rows: usize,
    /// Parts of flex bodies among `moving_parts` (reference, mode and node bodies; each flex
    /// body counted as its modes + 6, see `linkage_model::flex_bodies`).
    pub flex_parts: usize,
    /// The flex bodies' hidden equations among `rows` (5 per mode guide, 6 per node).
    pub flex_rows: usize,
    /// Each FE part's Craig–Bampton reduction and chapter count
    /// ([`crate::physics::fe_modes`]).
    pub fe_parts: Vec<crate::physics::fe_modes::FeModes>,
    /// Parts with zero mass.
    pub massless_parts: Vec<usize>,
    /// Constraint elements counted by description (`Revolute Joint` → 2), in first-seen order.
    pub counts: Vec<(String, usize)>,
    pub rows: usize,
    pub gruebler: i64,
    pub rank: usize,
    pub dof: i64,
    pub redundant: Vec<RedundantEquation>,
    pub misaligned: Vec<Misalignment>,
    /// Elements analysed in their idealised (repaired) form because they are misaligned.
    pub idealized: Vec<usize>,
    /// Whether every admitted equation holds at the analysed configuration.
    pub assembled: bool,
    /// Parts no constraint touches.
    pub unconstrained_parts: Vec<usize>,
    /// Parts with constraints but no chain of constraints to ground.
    pub ungrounded_parts: Vec<usize>,
    pub massless_free: Vec<MasslessFreedom>,
    /// Admitted rows whose rank decision was a near-tie.
    pub near_tie_admitted: Vec<usize>,
    pub topology: Topology,
}

/// Outcome of the rank analysis of a whole system.
#[derive(Clone, Debug, Default)]
pub struct RankAnalysis {
    pub rank: usize,
    /// Admitted (independent) rows, ascending.
    pub admitted: Vec<usize>,
    /// (row, decision residual, dependencies, near tie) of each redundant row.
    pub redundant: Vec<(usize, f64, Vec<Dependency>, bool)>,
    pub near_tie_admitted: Vec<usize>,
}

/// Greedy priority-order rank analysis of `sys` at state `s`, block by block.
///
/// Priority: translational rows of joints and primitives, then their rotational rows, then
/// couplings, then motions; within a tier, definition order. The Jacobian is scaled
/// (translation columns × `length`) and each row normalised before the decision.
pub fn rank_analysis(
    sys: &System,
    s: &State,
    topo: &Topology,
    length: f64,
    tol: &Tolerances,
) -> RankAnalysis {
    let settings = RankSettings {
        tolerance: tol.rank,
        near_tie_factor: tol.near_tie_factor,
    };
    let mut out = RankAnalysis::default();
    let mut local = vec![usize::MAX; sys.nparts];
    let mut g = RowGradient::default();
    let mut order: Vec<usize> = Vec::new();
    let mut entries: Vec<(usize, f64)> = Vec::with_capacity(24);
    for blk in &topo.blocks {
        for (k, &p) in blk.parts.iter().enumerate() {
            local[p] = k;
        }
        order.clear();
        for &e in &blk.elements {
            order.extend(sys.element_rows[e].clone());
        }
        order.sort_by_key(|&r| (sys.rows[r].tier, r));
        let mut m = SparseRows::new(6 * blk.parts.len());
        for &r in &order {
            sys.gradient(r, s, &mut g);
            entries.clear();
            for (body, v) in &g.blocks {
                let base = 6 * local[*body];
                for (c, x) in v.iter().enumerate() {
                    let scaled = if c < 3 { x * length } else { *x };
                    if scaled != 0.0 {
                        entries.push((base + c, scaled));
                    }
                }
            }
            let norm = entries.iter().map(|(_, x)| x * x).sum::<f64>().sqrt();
            if norm > 0.0 {
                for e in entries.iter_mut() {
                    e.1 /= norm;
                }
            }
            m.push_row(entries.iter().copied());
        }
        let res = greedy_rank(&m, &settings);
        out.rank += res.rank;
        out.admitted.extend(res.admitted.iter().map(|&k| order[k]));
        for d in &res.decisions {
            if d.admitted && d.near_tie {
                out.near_tie_admitted.push(order[d.row]);
            }
        }
        for red in res.redundant {
            let near = res
                .decisions
                .get(red.row)
                .is_some_and(|d| d.row == red.row && d.near_tie);
            let deps = red
                .depends_on
                .iter()
                .map(|d| Dependency {
                    row: order[d.row],
                    coefficient: d.coefficient,
                })
                .collect();
            out.redundant
                .push((order[red.row], red.residual, deps, near));
        }
        for &p in &blk.parts {
            local[p] = usize::MAX;
        }
    }
    prefer_well_conditioned_rows(sys, &mut out);
    out.admitted.sort_unstable();
    out.redundant.sort_by_key(|r| r.0);
    out
}

/// Within one element, reports as redundant the row the redundancy leans on most.
///
/// When a redundant row `a` depends on an admitted row `m` of the same element and tier with
/// `|c_m| > 1`, the two are exchanged (`m = (a − Σ_{k≠m} c_k r_k)/c_m`): the kept set stays a
/// basis of the same span and is better conditioned. This only changes which equation of a
/// joint is named (e.g. `Zi.Xj` rather than `Zi.Yj` of a revolute) and matches Adams Solver's
/// choice on the corpus slider-crank (`generic_model.adm`). Skipped when `m` also appears in
/// another redundant row's dependencies.
fn prefer_well_conditioned_rows(sys: &System, ra: &mut RankAnalysis) {
    // How many redundant rows lean on each row, and where each admitted row sits.
    let mut uses = vec![0u32; sys.rows.len()];
    for r in &ra.redundant {
        for d in &r.2 {
            uses[d.row] += 1;
        }
    }
    let mut slot = vec![usize::MAX; sys.rows.len()];
    for (k, &r) in ra.admitted.iter().enumerate() {
        slot[r] = k;
    }
    for red in ra.redundant.iter_mut() {
        let a = red.0;
        let (el, tier) = (sys.rows[a].element, sys.rows[a].tier);
        let best = red
            .2
            .iter()
            .filter(|d| {
                sys.rows[d.row].element == el
                    && sys.rows[d.row].tier == tier
                    && d.coefficient.abs() > 1.0 + DEPENDENCY_COEFFICIENT
            })
            .max_by(|x, y| x.coefficient.abs().total_cmp(&y.coefficient.abs()))
            .cloned();
        let Some(m) = best else { continue };
        if uses[m.row] > 1 || slot[m.row] == usize::MAX {
            continue;
        }
        let mut deps: Vec<Dependency> = vec![Dependency {
            row: a,
            coefficient: 1.0 / m.coefficient,
        }];
        deps.extend(red.2.iter().filter(|d| d.row != m.row).map(|d| Dependency {
            row: d.row,
            coefficient: -d.coefficient / m.coefficient,
        }));
        deps.sort_by_key(|d| d.row);
        uses[m.row] = 0;
        uses[a] += 1;
        red.0 = m.row;
        red.2 = deps;
        let k = slot[m.row];
        ra.admitted[k] = a;
        slot[a] = k;
        slot[m.row] = usize::MAX;
    }
}

/// Compiles the constraint rows of a model for verification, with the joints `idealized`
/// analysed as intended at `s` (see [`System::idealized`]): the verify stage's compilation,
/// also used by explain for the candidate models it checks. (The analyses share the one
/// compiled in [`crate::pipeline::Assembled`].)
pub fn compile(model: &Model, s: &State, idealized: &[usize]) -> System {
    let sys = System::new(model);
    if idealized.is_empty() {
        sys
    } else {
        sys.idealized(model, s, idealized)
    }
}

/// Verifies `model` at its input configuration.
pub fn verify(model: &Model, drivers: &dyn Drivers, tol: &Tolerances) -> Verification {
    let input = State::input(model);
    let sys = Cow::Owned(compile(model, &input, &[]));
    analyse(model, sys, &input, drivers, tol)
}

/// Verifies `model`, whose compiled rows are `sys`, at configuration `state` (e.g. after
/// assembly). "Misaligned" rows are the rows violated at that configuration.
pub fn verify_at(
    model: &Model,
    sys: &System,
    state: &State,
    drivers: &dyn Drivers,
    tol: &Tolerances,
) -> Verification {
    analyse(model, Cow::Borrowed(sys), state, drivers, tol)
}

/// [`verify_at`] with the system owned or borrowed (the verification keeps a copy of the
/// system it analysed: the given one is moved in when owned).
fn analyse(
    model: &Model,
    sys: Cow<System>,
    state: &State,
    drivers: &dyn Drivers,
    tol: &Tolerances,
) -> Verification {
    let state = state.clone();
    let length = model.characteristic_length;
    let res = residuals(&sys, &state, drivers);

    // Misaligned (broken) joints and primitives: violated rows at the input configuration.
    let mut misaligned = Vec::new();
    let mut broken: Vec<usize> = Vec::new();
    for (r, row) in sys.rows.iter().enumerate() {
        if matches!(row.tier, Tier::Motion) {
            continue;
        }
        if let Some(v) = res[r] {
            if !within_tolerance(row.unit, v, tol, length) {
                misaligned.push(Misalignment {
                    row: r,
                    residual: report_residual(row.unit, v),
                });
                let is_joint = matches!(
                    model.constraints[row.element].kind,
                    ConstraintKind::Joint { .. } | ConstraintKind::Jprim { .. }
                );
                if is_joint && broken.last() != Some(&row.element) {
                    broken.push(row.element);
                }
            }
        }
    }
    let rank_sys = if broken.is_empty() {
        None
    } else {
        Some(sys.idealized(model, &state, &broken))
    };
    let all: Vec<usize> = (0..model.constraints.len()).collect();
    let topo = topology(model, &all);
    let ra = rank_analysis(
        rank_sys.as_ref().unwrap_or(&sys),
        &state,
        &topo,
        length,
        tol,
    );

    // Assembled when every admitted row with a known residual holds.
    let assembled = ra.admitted.iter().all(|&r| match res[r] {
        Some(v) => within_tolerance(sys.rows[r].unit, v, tol, length),
        None => true,
    });
    let redundant = ra
        .redundant
        .iter()
        .map(|(r, decision, deps, near)| {
            let unit = sys.rows[*r].unit;
            let residual = res[*r].map(|v| report_residual(unit, v));
            let consistent = match res[*r] {
                Some(v) if assembled => Some(within_tolerance(unit, v, tol, length)),
                _ => None,
            };
            RedundantEquation {
                row: *r,
                residual,
                consistent,
                depends_on: deps.clone(),
                near_tie: *near,
                decision: *decision,
            }
        })
        .collect();

    let n = model.parts.len();
    let rows = sys.rows.len();
    let massless_parts: Vec<usize> = (0..n).filter(|&k| model.parts[k].mass <= 0.0).collect();
    let massless_free = massless_freedom(model, &sys, &state, &massless_parts, length, tol);
    let mut counts: Vec<(String, usize)> = Vec::new();
    let mut hold_rows = 0;
    let mut flex_rows = 0;
    for c in &model.constraints {
        if linkage_model::build::point_masses::is_rotation_hold(c) {
            hold_rows += 3;
            continue;
        }
        if c.origin.statement == linkage_model::flex_bodies::FLEX_BODY_STATEMENT {
            flex_rows += match c.kind {
                linkage_model::ConstraintKind::FlexNode { .. } => 6,
                _ => 5,
            };
            continue;
        }
        let d = c.description();
        match counts.iter_mut().find(|(k, _)| *k == d) {
            Some((_, n)) => *n += 1,
            None => counts.push((d.to_string(), 1)),
        }
    }
    // FE parts: the Gruebler count takes the equivalent linear flexible body (Adams'
    // chapter) in place of the node bodies' 6 (cable: 3) columns each; the DOF by rank keeps
    // every nodal coordinate.
    let requested = linkage_model::fe_parts::requested_normal_modes();
    let fe_parts: Vec<_> = (0..model.fe_parts.len())
        .map(|f| crate::physics::fe_modes::fe_modes(model, f, requested))
        .collect();
    let fe_nodes: usize = model.fe_parts.iter().map(|p| p.nodes.len()).sum();
    let rigid = n - fe_nodes;
    let cable_holds: usize = fe_parts
        .iter()
        .filter(|m| m.nodal_dof == 3 * m.nodes)
        .map(|m| 3 * m.nodes)
        .sum();
    let chapter: usize = fe_parts.iter().map(|m| m.count.total()).sum();
    let is_fe = |k: usize| model.fe_node(k).is_some();
    let mut unconstrained_parts: Vec<usize> = (0..n)
        .filter(|&k| topo.degree[k] == 0 && !is_fe(k))
        .collect();
    // An FE part none of whose nodes is constrained: named by its first node.
    for p in &model.fe_parts {
        if p.nodes.iter().all(|nd| topo.degree[nd.part] == 0) {
            unconstrained_parts.extend(p.nodes.first().map(|nd| nd.part));
        }
    }
    Verification {
        moving_parts: n,
        point_masses: model.parts.iter().filter(|p| p.point_mass).count() - cable_holds / 3,
        fe_nodes,
        hold_rows,
        flex_parts: model.flex_bodies.iter().map(|b| b.parts().count()).sum(),
        flex_rows,
        fe_parts,
        massless_parts,
        counts,
        rows,
        gruebler: 6 * rigid as i64 + chapter as i64 - (rows - cable_holds) as i64,
        rank: ra.rank,
        dof: 6 * n as i64 - ra.rank as i64,
        redundant,
        misaligned,
        idealized: broken,
        assembled,
        unconstrained_parts,
        ungrounded_parts: (0..n)
            .filter(|&k| topo.degree[k] > 0 && !topo.grounded[k])
            .collect(),
        massless_free,
        near_tie_admitted: ra.near_tie_admitted,
        topology: topo,
        system: rank_sys.unwrap_or_else(|| sys.into_owned()),
    }
}

/// Massless parts need their motion fully determined by the constraints: the columns of the
/// Jacobian that belong to massless parts must be independent (a null-space motion that moves
/// only massless parts would have no inertia). Checked by a greedy rank analysis of the
/// transposed column block.
fn massless_freedom(
    model: &Model,
    sys: &System,
    s: &State,
    massless: &[usize],
    length: f64,
    tol: &Tolerances,
) -> Vec<MasslessFreedom> {
    if massless.is_empty() {
        return Vec::new();
    }
    let mut slot = vec![usize::MAX; model.parts.len()];
    for (k, &p) in massless.iter().enumerate() {
        slot[p] = k;
    }
    // Columns of massless parts, as sparse vectors over the rows that touch them.
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); 6 * massless.len()];
    let mut g = RowGradient::default();
    let mut nrows = 0usize;
    for r in 0..sys.rows.len() {
        sys.gradient(r, s, &mut g);
        let norm = g
            .blocks
            .iter()
            .flat_map(|(_, v)| {
                v.iter()
                    .enumerate()
                    .map(|(c, x)| if c < 3 { x * length } else { *x })
            })
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        let mut used = false;
        for (body, v) in &g.blocks {
            if slot[*body] == usize::MAX {
                continue;
            }
            for (c, x) in v.iter().enumerate() {
                let scaled = if c < 3 { x * length } else { *x };
                if scaled != 0.0 && norm > 0.0 {
                    cols[6 * slot[*body] + c].push((nrows, scaled / norm));
                    used = true;
                }
            }
        }
        if used {
            nrows += 1;
        }
    }
    let mut m = SparseRows::new(nrows);
    for col in &cols {
        let n = col.iter().map(|(_, x)| x * x).sum::<f64>().sqrt();
        m.push_row(
            col.iter()
                .map(|&(r, x)| (r, if n > 0.0 { x / n } else { 0.0 })),
        );
    }
    let res = greedy_rank(
        &m,
        &RankSettings {
            tolerance: tol.rank,
            near_tie_factor: tol.near_tie_factor,
        },
    );
    const NAMES: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];
    let mut out: Vec<MasslessFreedom> = Vec::new();
    for red in &res.redundant {
        let part = massless[red.row / 6];
        let coord = NAMES[red.row % 6];
        match out.iter_mut().find(|f| f.part == part) {
            Some(f) => f.coordinates.push(coord),
            None => out.push(MasslessFreedom {
                part,
                coordinates: vec![coord],
            }),
        }
    }
    out
}
