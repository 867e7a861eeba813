//! Replacement advice: weaker joints or joint primitives that remove redundant equations while
//! keeping the DOF and the motion.
//!
//! # Candidates
//!
//! Only elements involved in the redundancy are changed: the owners of the redundant rows
//! (priority policy of verify) and every element the left null space of the Jacobian touches
//! (the rows a redundancy runs through), owners first, at most
//! [`RepairSettings::max_elements`]. Joints driven by a MOTION, used by a COUPLER or GEAR, or
//! carrying initial conditions are left alone (their statements would no longer be valid).
//! Each candidate element is replaced, at the same markers, by a weaker set of equations whose
//! span lies in the span of its own equations, so that the changed model admits every motion
//! of the original:
//!
//! | element | candidates |
//! |---|---|
//! | REVOLUTE | SPHERICAL, INLINE, CYLINDRICAL, PLANAR, INPLANE, PARALLEL_AXES, UNIVERSAL¹, INLINE + PERPENDICULAR¹ |
//! | TRANSLATIONAL | CYLINDRICAL, INLINE, ORIENTATION, PARALLEL_AXES |
//! | CYLINDRICAL | INLINE, PARALLEL_AXES |
//! | FIXED | REVOLUTE, TRANSLATIONAL, CYLINDRICAL, SPHERICAL, PLANAR, INLINE, INPLANE, ORIENTATION, PARALLEL_AXES, UNIVERSAL¹ |
//! | PLANAR | INPLANE, PARALLEL_AXES |
//! | SPHERICAL, JPRIM ATPOINT | INLINE, INPLANE |
//! | UNIVERSAL | SPHERICAL, INLINE + PERPENDICULAR, INLINE, INPLANE |
//! | HOOKE, CONVEL | SPHERICAL, INLINE (HOOKE also INPLANE) |
//! | JPRIM ORIENTATION | PARALLEL_AXES |
//!
//! ¹ The cross pin `z_i·z_j = 0` needs one marker's z axis perpendicular to the joint axis:
//! the I (or J) marker re-oriented, turned by 90° about its own y axis (z along the former x)
//! or its x axis (z along the former y); all four are tried, since which pin direction stops
//! the motion it must stop depends on the loop (a coupler pin along the coupler leaves the
//! coupler's spin free). The re-oriented marker is a new MARKER at the same point on the same
//! part (the original may be used by other statements — motions, forces, requests, function
//! expressions — that must not change); the joint is pointed at it.
//!
//! # Search
//!
//! Each candidate is applied to a copy of the model ([`realize`]), compiled, and the rank of
//! the biconnected blocks it touches is found again ([`super::dense::analyse`]; the other
//! blocks are unchanged). A change is kept when the DOF is unchanged and the redundancy
//! decreased (weaker equations whose span lies in the original span and the same DOF admit
//! exactly the original motions). Single changes of different elements are combined in pairs
//! when the rows they remove add up to the redundancy, and when neither a single change nor a
//! pair removes every redundant equation, the three best partial changes are completed
//! greedily, one further element at a time (the change that removes most, trying the largest
//! removals first). The number of rank analyses is bounded
//! ([`RepairSettings::evaluations`]). Every proposal shown has then been checked on the whole
//! changed model (rank of every block, and its reactions).
//!
//! # Ranking
//!
//! Proposals that remove all redundancy are shown when there are any (otherwise those that
//! remove most). They are ranked by the number of elements changed, then by how evenly the
//! reactions can be shared: fewer indeterminate reaction components first, then the larger
//! *reaction conditioning* — the smallest over the changed loops of `σ_r/σ_1`, the smallest
//! non-zero over the largest singular value of the loop's scaled, row-normalised Jacobian.
//! The reactions solve `J_kᵀλ = Q` on the kept equations, so `1/σ_r` bounds how much an
//! applied load is amplified into reactions: a poorly conditioned support carries some load by
//! large, opposing reactions in few elements (near 0 close to a singular pose; `null` for
//! loops too large for a dense SVD). Variants that differ only in which way a marker is
//! turned are merged (the better conditioned is kept), and at most
//! [`RepairSettings::per_signature`] proposals of the same kind of change (e.g. "REVOLUTE →
//! JPRIM INLINE" at different joints) are listed.

use super::dense::analyse;
use super::reactions::{determinacy, Direction, ElementReactions};
use crate::constraints::graph::{topology, Block, Topology};
use crate::pipeline::verify::{compile, rank_analysis, Verification};
use crate::state::State;
use crate::tolerances::Tolerances;
use crate::tolerances::NULL_VECTOR_ROUNDING;
use glam::{DMat3, DVec3};
use linkage_adm::edit::{Edit, MarkerKey};
use linkage_adm::{JointType, JprimType};
use linkage_model::{Body, Constraint, ConstraintKind, JointInitial, Marker, Model, Origin};
use std::cell::Cell;

/// A joint or primitive type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ElementType {
    Joint(JointType),
    Jprim(JprimType),
}

impl ElementType {
    /// The type of a constraint element (joints and primitives only).
    pub fn of(kind: &ConstraintKind) -> Option<ElementType> {
        match kind {
            ConstraintKind::Joint { kind, .. } => Some(ElementType::Joint(*kind)),
            ConstraintKind::Jprim { kind, .. } => Some(ElementType::Jprim(*kind)),
            _ => None,
        }
    }

    /// `REVOLUTE`, `JPRIM INLINE`.
    pub fn name(self) -> String {
        match self {
            ElementType::Joint(k) => k.keyword().to_string(),
            ElementType::Jprim(k) => format!("JPRIM {}", k.keyword()),
        }
    }
}

/// How a marker is turned to carry a cross pin.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Turn {
    /// +90° about the marker's y axis: the new z is the former x.
    ZToX,
    /// −90° about the marker's x axis: the new z is the former y.
    ZToY,
}

impl Turn {
    /// The new marker axes expressed in the old marker's axes.
    pub fn matrix(self) -> DMat3 {
        match self {
            Turn::ZToX => DMat3::from_cols(-DVec3::Z, DVec3::Y, DVec3::X),
            Turn::ZToY => DMat3::from_cols(DVec3::X, -DVec3::Z, DVec3::Y),
        }
    }

    fn axis(self) -> &'static str {
        match self {
            Turn::ZToX => "x",
            Turn::ZToY => "y",
        }
    }
}

/// One element of a replacement, at the changed element's I and J markers (possibly turned).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct NewElement {
    pub kind: ElementType,
    pub i_turn: Option<Turn>,
    pub j_turn: Option<Turn>,
}

impl NewElement {
    fn plain(kind: ElementType) -> NewElement {
        NewElement {
            kind,
            i_turn: None,
            j_turn: None,
        }
    }
}

/// Replace element `element` by `into` (the first takes its place, the others are new JPRIMs).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Change {
    pub element: usize,
    pub into: Vec<NewElement>,
}

impl Change {
    /// `(from, to)` in words: `("REVOLUTE", "UNIVERSAL (new I marker: coupler_pin_b turned
    /// 90° so that its z lies along its former y axis)")`.
    pub fn describe(&self, model: &Model) -> (String, String) {
        let con = &model.constraints[self.element];
        let from =
            ElementType::of(&con.kind).map_or_else(|| con.description().to_string(), |t| t.name());
        let mut to: Vec<String> = self.into.iter().map(|n| n.kind.name()).collect();
        to.dedup();
        let mut notes: Vec<String> = Vec::new();
        if let Some((mi, mj)) = con.markers() {
            for n in &self.into {
                for (turn, m, which) in [(n.i_turn, mi, "I"), (n.j_turn, mj, "J")] {
                    if let Some(t) = turn {
                        let note = format!(
                            "new {which} marker: {} turned 90° so that its z lies along its former {} axis",
                            model.markers[m].name,
                            t.axis()
                        );
                        if !notes.contains(&note) {
                            notes.push(note);
                        }
                    }
                }
            }
        }
        let mut to = to.join(" + ");
        if !notes.is_empty() {
            to = format!("{to} ({})", notes.join("; "));
        }
        (from, to)
    }

    /// Equations removed (rows of the element minus rows of its replacement).
    fn signature(&self, model: &Model) -> (Option<ElementType>, Vec<ElementType>) {
        (
            ElementType::of(&model.constraints[self.element].kind),
            self.into.iter().map(|n| n.kind).collect(),
        )
    }
}

/// A checked proposal.
#[derive(Clone, Debug, PartialEq)]
pub struct Proposal {
    pub changes: Vec<Change>,
    pub dof_after: i64,
    pub redundant_after: usize,
    /// `σ_min/σ_max` of the kept equations of the changed loops (`None` for very large loops).
    pub conditioning: Option<f64>,
    /// Elements of the changed model with indeterminate reactions.
    pub indeterminate_after: Vec<NamedReactions>,
    /// Reaction components indeterminate before that the change makes determinate.
    pub now_determinate: Vec<NamedReactions>,
}

/// Reaction components of a named element.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedReactions {
    pub name: String,
    /// `Revolute Joint`.
    pub kind: String,
    pub directions: Vec<Direction>,
}

/// Limits of the search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RepairSettings {
    /// Elements considered for a change.
    pub max_elements: usize,
    /// Proposals shown.
    pub max_proposals: usize,
    /// Proposals of one kind of change shown.
    pub per_signature: usize,
    /// Budget of rank analyses: `evaluations / rows`, clamped to `[60, 4000]`.
    pub evaluations: usize,
}

impl Default for RepairSettings {
    fn default() -> Self {
        RepairSettings {
            max_elements: 24,
            max_proposals: 12,
            per_signature: 3,
            evaluations: 2_000_000,
        }
    }
}

/// The changed model and the dataset edits that make the same change.
#[derive(Clone, Debug)]
pub struct Realized {
    pub model: Model,
    pub edits: Vec<Edit>,
    /// `(changed element, index of a new JPRIM)` for every appended element.
    pub appended: Vec<(usize, usize)>,
}

fn keyword_lower(t: ElementType) -> String {
    match t {
        ElementType::Joint(k) => k.keyword().to_lowercase(),
        ElementType::Jprim(k) => k.keyword().to_lowercase(),
    }
}

/// Applies `changes` to a copy of `model`; new JPRIMs and markers get ids not used in it.
pub fn realize(model: &Model, changes: &[Change]) -> Realized {
    let mut m = model.clone();
    let mut edits = Vec::new();
    let mut appended = Vec::new();
    let mut next_marker = model.markers.iter().map(|k| k.id).max().unwrap_or(0) + 1;
    let mut next_jprim = model
        .constraints
        .iter()
        .filter(|c| c.origin.statement == "JPRIM")
        .map(|c| c.origin.id)
        .max()
        .unwrap_or(0)
        + 1;
    for ch in changes {
        let Some(con) = model.constraints.get(ch.element) else {
            continue;
        };
        let Some((mi, mj)) = con.markers() else {
            continue;
        };
        let original = ElementType::of(&con.kind);
        let statement = con.origin.statement_index;
        // New (turned) markers of this change: (is I, turn) → (index, id).
        let mut turned: Vec<((bool, Turn), usize, u64)> = Vec::new();
        let mut marker = |m: &mut Model, edits: &mut Vec<Edit>, is_i: bool, t: Option<Turn>| {
            let base = if is_i { mi } else { mj };
            let Some(t) = t else {
                return (base, model.markers[base].id);
            };
            if let Some(&(_, idx, id)) = turned.iter().find(|(k, _, _)| *k == (is_i, t)) {
                return (idx, id);
            }
            let old = &model.markers[base];
            let id = next_marker;
            next_marker += 1;
            let r_bm = old.r_bm * t.matrix();
            let name = format!("{}_turned_{}", old.name, t.axis());
            let qp = match old.body {
                Body::Ground => old.p_bm,
                Body::Part(k) => old.p_bm - model.parts[k].p_b_bcs,
            };
            edits.push(Edit::AddMarker {
                id,
                like: old.id,
                qp: qp.to_array(),
                reuler: linkage_model::frames::matrix_to_euler313(&r_bm),
                name: Some(name.clone()),
            });
            m.markers.push(Marker {
                id,
                name,
                span: old.span,
                body: old.body,
                p_bm: old.p_bm,
                r_bm,
                floating: false,
            });
            let idx = m.markers.len() - 1;
            turned.push(((is_i, t), idx, id));
            (idx, id)
        };
        for (k, ne) in ch.into.iter().enumerate() {
            let (i, iid) = marker(&mut m, &mut edits, true, ne.i_turn);
            let (j, jid) = marker(&mut m, &mut edits, false, ne.j_turn);
            let kind = match ne.kind {
                ElementType::Joint(t) => ConstraintKind::Joint {
                    kind: t,
                    i,
                    j,
                    initial: JointInitial::default(),
                    pd: None,
                    pitch: None,
                },
                ElementType::Jprim(t) => ConstraintKind::Jprim { kind: t, i, j },
            };
            if k == 0 {
                let c = &mut m.constraints[ch.element];
                match (original, ne.kind) {
                    (Some(ElementType::Joint(_)), ElementType::Joint(t)) => {
                        edits.push(Edit::JointType { statement, kind: t });
                    }
                    (Some(ElementType::Joint(_)), ElementType::Jprim(t)) => {
                        let id = next_jprim;
                        next_jprim += 1;
                        edits.push(Edit::JointToJprim {
                            statement,
                            id,
                            kind: t,
                        });
                        c.origin.statement = "JPRIM";
                        c.origin.id = id;
                    }
                    (Some(ElementType::Jprim(_)), ElementType::Jprim(t)) => {
                        edits.push(Edit::JprimType { statement, kind: t });
                    }
                    _ => continue,
                }
                if i != mi {
                    edits.push(Edit::SetMarker {
                        statement,
                        key: MarkerKey::I,
                        marker: iid,
                    });
                }
                if j != mj {
                    edits.push(Edit::SetMarker {
                        statement,
                        key: MarkerKey::J,
                        marker: jid,
                    });
                }
                c.kind = kind;
            } else {
                let ElementType::Jprim(t) = ne.kind else {
                    continue;
                };
                let id = next_jprim;
                next_jprim += 1;
                let name = format!("{}_{}", con.origin.name, keyword_lower(ne.kind));
                m.constraints.push(Constraint {
                    origin: Origin {
                        statement: "JPRIM",
                        id,
                        name: name.clone(),
                        span: con.origin.span,
                        statement_index: con.origin.statement_index,
                    },
                    kind,
                });
                appended.push((ch.element, m.constraints.len() - 1));
                edits.push(Edit::AddJprim {
                    id,
                    kind: t,
                    i: iid,
                    j: jid,
                    name: Some(name),
                });
            }
        }
    }
    Realized {
        model: m,
        edits,
        appended,
    }
}

/// The candidate replacements of an element type (module table).
pub fn replacements(t: ElementType) -> Vec<Vec<NewElement>> {
    use ElementType::{Joint as J, Jprim as P};
    use JointType as T;
    use JprimType as Q;
    let single = |k: ElementType| vec![NewElement::plain(k)];
    let turns = [Turn::ZToX, Turn::ZToY];
    let universal = || {
        let mut v = Vec::new();
        for t in turns {
            v.push(vec![NewElement {
                kind: J(T::Universal),
                i_turn: Some(t),
                j_turn: None,
            }]);
        }
        for t in turns {
            v.push(vec![NewElement {
                kind: J(T::Universal),
                i_turn: None,
                j_turn: Some(t),
            }]);
        }
        v
    };
    let inline_perpendicular = || {
        let mut v = Vec::new();
        for (i_turn, j_turn) in turns
            .iter()
            .map(|t| (Some(*t), None))
            .chain(turns.iter().map(|t| (None, Some(*t))))
        {
            v.push(vec![
                NewElement::plain(P(Q::Inline)),
                NewElement {
                    kind: P(Q::Perpendicular),
                    i_turn,
                    j_turn,
                },
            ]);
        }
        v
    };
    let list = |ks: &[ElementType]| ks.iter().map(|k| single(*k)).collect::<Vec<_>>();
    match t {
        J(T::Revolute) => {
            let mut v = list(&[
                J(T::Spherical),
                P(Q::Inline),
                J(T::Cylindrical),
                J(T::Planar),
                P(Q::Inplane),
                P(Q::ParallelAxes),
            ]);
            v.extend(universal());
            v.extend(inline_perpendicular());
            v
        }
        J(T::Translational) => list(&[
            J(T::Cylindrical),
            P(Q::Inline),
            P(Q::Orientation),
            P(Q::ParallelAxes),
        ]),
        J(T::Cylindrical) => list(&[P(Q::Inline), P(Q::ParallelAxes)]),
        J(T::Fixed) => {
            let mut v = list(&[
                J(T::Revolute),
                J(T::Translational),
                J(T::Cylindrical),
                J(T::Spherical),
                J(T::Planar),
                P(Q::Inline),
                P(Q::Inplane),
                P(Q::Orientation),
                P(Q::ParallelAxes),
            ]);
            v.extend(universal());
            v
        }
        J(T::Planar) => list(&[P(Q::Inplane), P(Q::ParallelAxes)]),
        J(T::Spherical) | P(Q::Atpoint) => list(&[P(Q::Inline), P(Q::Inplane)]),
        J(T::Universal) => vec![
            single(J(T::Spherical)),
            vec![
                NewElement::plain(P(Q::Inline)),
                NewElement::plain(P(Q::Perpendicular)),
            ],
            single(P(Q::Inline)),
            single(P(Q::Inplane)),
        ],
        J(T::Hooke) => list(&[J(T::Spherical), P(Q::Inline), P(Q::Inplane)]),
        J(T::Convel) => list(&[J(T::Spherical), P(Q::Inline)]),
        P(Q::Orientation) => list(&[P(Q::ParallelAxes)]),
        _ => Vec::new(),
    }
}

/// Per element: whether a motion, coupler or gear refers to it (then it is not changed).
fn driven_joints(model: &Model) -> Vec<bool> {
    let mut used = vec![false; model.constraints.len()];
    let mut mark = |j: usize| {
        if let Some(u) = used.get_mut(j) {
            *u = true;
        }
    };
    for c in &model.constraints {
        match &c.kind {
            ConstraintKind::Motion { joint, .. } => joint.iter().for_each(|&j| mark(j)),
            ConstraintKind::Coupler { terms, .. } => terms.iter().for_each(|(j, _, _)| mark(*j)),
            ConstraintKind::Gear { joints, .. } => joints.iter().for_each(|&j| mark(j)),
            _ => {}
        }
    }
    used
}

/// Whether an element may be changed (see the module docs); `used` from [`driven_joints`].
fn eligible(model: &Model, e: usize, used: &[bool]) -> bool {
    let Some(con) = model.constraints.get(e) else {
        return false;
    };
    match &con.kind {
        ConstraintKind::Joint { kind, initial, .. } => {
            let has_ic = initial.translation.0.is_some()
                || initial.translation.1.is_some()
                || initial.rotation.0.is_some()
                || initial.rotation.1.is_some();
            if has_ic || matches!(kind, JointType::Rackpin | JointType::Screw) {
                return false;
            }
        }
        ConstraintKind::Jprim { kind, .. } => {
            if !matches!(kind, JprimType::Orientation | JprimType::Atpoint) {
                return false;
            }
        }
        _ => return false,
    }
    !used.get(e).copied().unwrap_or(false)
}

/// A candidate found by the search.
#[derive(Clone, Debug)]
struct Candidate {
    changes: Vec<Change>,
    red: usize,
    cond: Option<f64>,
}

impl Candidate {
    fn elements(&self) -> Vec<usize> {
        self.changes.iter().map(|c| c.element).collect()
    }
}

struct Search<'a> {
    model: &'a Model,
    input: State,
    state: &'a State,
    tol: &'a Tolerances,
    length: f64,
    topo: &'a Topology,
    idealized: &'a [usize],
    element_block: Vec<Option<usize>>,
    block_rank: Vec<usize>,
    base_rank: usize,
    base_dof: i64,
    budget: Cell<usize>,
}

struct Evaluation {
    dof: i64,
    red: usize,
    cond: Option<f64>,
}

impl Search<'_> {
    fn evaluate(&self, changes: &[Change]) -> Option<Evaluation> {
        let left = self.budget.get();
        if left == 0 {
            return None;
        }
        self.budget.set(left - 1);
        let real = realize(self.model, changes);
        let m2 = &real.model;
        let mut ideal: Vec<usize> = self.idealized.to_vec();
        for &(orig, new) in &real.appended {
            if self.idealized.contains(&orig) {
                ideal.push(new);
            }
        }
        let sys = compile(m2, &self.input, &ideal);
        let mut blocks: Vec<usize> = changes
            .iter()
            .filter_map(|c| self.element_block.get(c.element).copied().flatten())
            .collect();
        blocks.sort_unstable();
        blocks.dedup();
        if blocks.is_empty() {
            return None;
        }
        let mut topo = Topology::default();
        for &b in &blocks {
            let mut blk: Block = self.topo.blocks[b].clone();
            for &(orig, new) in &real.appended {
                if self.element_block.get(orig).copied().flatten() == Some(b) {
                    blk.elements.push(new);
                }
            }
            blk.elements.sort_unstable();
            topo.blocks.push(blk);
        }
        let an = analyse(&sys, self.state, &topo, self.length, self.tol);
        let before: usize = blocks.iter().map(|&b| self.block_rank[b]).sum();
        let rank = (self.base_rank + an.rank).checked_sub(before)?;
        let n = self.model.parts.len();
        let dof = 6 * n as i64 - rank as i64;
        let red = sys.rows.len().saturating_sub(rank);
        Some(Evaluation {
            dof,
            red,
            cond: an.conditioning,
        })
    }

    fn valid(&self, e: &Evaluation, below: usize) -> bool {
        e.dof == self.base_dof && e.red < below
    }
}

/// Proposals for the redundancy of `v` (the verification of `model`), checked at `state`.
pub fn propose(
    model: &Model,
    tol: &Tolerances,
    v: &Verification,
    state: &State,
    settings: &RepairSettings,
) -> Vec<Proposal> {
    let length = model.characteristic_length;
    let base = analyse(&v.system, state, &v.topology, length, tol);
    let rows = v.system.rows.len();
    let n = model.parts.len();
    let base_red = rows.saturating_sub(base.rank);
    if base_red == 0 {
        return Vec::new();
    }
    let mut element_block = vec![None; model.constraints.len()];
    for (b, blk) in v.topology.blocks.iter().enumerate() {
        for &e in &blk.elements {
            if let Some(slot) = element_block.get_mut(e) {
                *slot = Some(b);
            }
        }
    }
    let search = Search {
        model,
        input: State::input(model),
        state,
        tol,
        length,
        topo: &v.topology,
        idealized: &v.idealized,
        element_block,
        block_rank: base.block_rank.clone(),
        base_rank: base.rank,
        base_dof: 6 * n as i64 - base.rank as i64,
        budget: Cell::new((settings.evaluations / rows.max(1)).clamp(60, 4000)),
    };

    // Elements involved: owners of redundant rows (priority policy) first, then every element
    // the left null space touches, by how many null vectors touch it.
    // Scores indexed by element (O(1) per touch: a chain of 10,000 loops touches 30,000
    // elements); the order below is by score, then element, whatever the order of touches.
    let mut by_element = vec![0usize; model.constraints.len()];
    let mut bump = |e: usize, w: usize| {
        if let Some(s) = by_element.get_mut(e) {
            *s += w;
        }
    };
    let greedy = rank_analysis(&v.system, state, &v.topology, length, tol);
    for (r, _, _, _) in &greedy.redundant {
        bump(v.system.rows[*r].element, 1000);
    }
    for vector in &base.null {
        let max = vector.iter().map(|(_, c)| c.abs()).fold(0.0, f64::max);
        let mut touched: Vec<usize> = vector
            .iter()
            .filter(|(_, c)| c.abs() > NULL_VECTOR_ROUNDING * max)
            .map(|(r, _)| v.system.rows[*r].element)
            .collect();
        touched.sort_unstable();
        touched.dedup();
        for e in touched {
            bump(e, 1);
        }
    }
    let used = driven_joints(model);
    let mut score: Vec<(usize, usize)> = by_element
        .iter()
        .enumerate()
        .filter(|&(e, &w)| w > 0 && eligible(model, e, &used))
        .map(|(e, &w)| (e, w))
        .collect();
    score.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    score.truncate(settings.max_elements);

    // Single changes.
    let mut singles: Vec<Candidate> = Vec::new();
    for &(e, _) in &score {
        let Some(t) = ElementType::of(&model.constraints[e].kind) else {
            continue;
        };
        for into in replacements(t) {
            let changes = vec![Change { element: e, into }];
            if let Some(ev) = search.evaluate(&changes) {
                if search.valid(&ev, base_red) {
                    singles.push(Candidate {
                        changes,
                        red: ev.red,
                        cond: ev.cond,
                    });
                }
            }
        }
    }
    let mut found: Vec<Candidate> = singles.iter().filter(|c| c.red == 0).cloned().collect();
    // Partial single changes, those that remove most first.
    let mut partial: Vec<&Candidate> = singles.iter().filter(|c| c.red > 0).collect();
    partial.sort_by_key(|c| c.red);

    // Pairs that may remove everything (the rows two changes remove add up to the
    // redundancy).
    for a in 0..partial.len() {
        for b in a + 1..partial.len() {
            if partial[a].changes[0].element == partial[b].changes[0].element
                || 2 * base_red - partial[a].red - partial[b].red != base_red
            {
                continue;
            }
            let mut changes = partial[a].changes.clone();
            changes.extend(partial[b].changes.iter().cloned());
            if let Some(ev) = search.evaluate(&changes) {
                if search.valid(&ev, 1) {
                    found.push(Candidate {
                        changes,
                        red: 0,
                        cond: ev.cond,
                    });
                }
            }
        }
    }

    // Greedy completion when nothing removes everything: from the three best partial changes
    // (of different elements), add at each step the change of a further element that removes
    // most (the first whose rows all come off, trying the largest removals first).
    let mut pool: Vec<Candidate> = Vec::new();
    if found.is_empty() {
        let mut seeds: Vec<Candidate> = Vec::new();
        for s in &partial {
            if seeds.len() >= 3 {
                break;
            }
            if !seeds.iter().any(|x| x.elements() == s.elements()) {
                seeds.push((*s).clone());
            }
        }
        for mut cur in seeds {
            while cur.red > 0 && search.budget.get() > 0 {
                let used = cur.elements();
                let mut best: Option<Candidate> = None;
                for s in &partial {
                    let removes = base_red - s.red;
                    if used.contains(&s.changes[0].element) || removes > cur.red {
                        continue;
                    }
                    if best.as_ref().is_some_and(|b| cur.red - b.red >= removes) {
                        break;
                    }
                    let mut changes = cur.changes.clone();
                    changes.push(s.changes[0].clone());
                    if let Some(ev) = search.evaluate(&changes) {
                        if search.valid(&ev, cur.red)
                            && best.as_ref().is_none_or(|b| ev.red < b.red)
                        {
                            best = Some(Candidate {
                                changes,
                                red: ev.red,
                                cond: ev.cond,
                            });
                        }
                    }
                }
                match best {
                    Some(b) => cur = b,
                    None => break,
                }
            }
            if cur.red == 0 {
                found.push(cur);
            } else {
                pool.push(cur);
            }
        }
    }
    let mut list = if found.is_empty() {
        pool.extend(partial.iter().map(|c| (*c).clone()));
        pool
    } else {
        found
    };
    list.sort_by(|a, b| {
        (a.changes.len(), a.red)
            .cmp(&(b.changes.len(), b.red))
            .then(
                b.cond
                    .unwrap_or(0.0)
                    .partial_cmp(&a.cond.unwrap_or(0.0))
                    .unwrap_or(std::cmp::Ordering::Equal),
            )
    });
    // Merge marker-turn variants, limit each kind of change.
    let key = |c: &Candidate| -> Vec<(usize, Vec<ElementType>)> {
        let mut k: Vec<(usize, Vec<ElementType>)> = c
            .changes
            .iter()
            .map(|ch| (ch.element, ch.into.iter().map(|n| n.kind).collect()))
            .collect();
        k.sort_by_key(|x| x.0);
        k
    };
    let mut chosen: Vec<Candidate> = Vec::new();
    let mut signatures: Vec<(Vec<String>, usize)> = Vec::new();
    for c in list {
        if chosen.iter().any(|x| key(x) == key(&c)) {
            continue;
        }
        let mut sig: Vec<String> = c
            .changes
            .iter()
            .map(|ch| format!("{:?}", ch.signature(model)))
            .collect();
        sig.sort();
        match signatures.iter_mut().find(|(s, _)| *s == sig) {
            Some((_, count)) if *count >= settings.per_signature => continue,
            Some((_, count)) => *count += 1,
            None => signatures.push((sig, 1)),
        }
        chosen.push(c);
        if chosen.len() >= 2 * settings.max_proposals {
            break;
        }
    }

    // Every proposal is checked in full on the changed model.
    let before = determinacy(&v.system, state, length, &base.null);
    let input = State::input(model);
    let mut out: Vec<(Proposal, usize)> = Vec::new();
    for c in chosen {
        let Some((proposal, count)) = check(model, tol, v, state, &input, &before, &c) else {
            continue;
        };
        if proposal.dof_after == search.base_dof && proposal.redundant_after == c.red {
            out.push((proposal, count));
        }
    }
    out.sort_by(|(a, ca), (b, cb)| {
        (a.changes.len(), a.redundant_after, *ca)
            .cmp(&(b.changes.len(), b.redundant_after, *cb))
            .then(
                b.conditioning
                    .unwrap_or(0.0)
                    .partial_cmp(&a.conditioning.unwrap_or(0.0))
                    .unwrap_or(std::cmp::Ordering::Equal),
            )
    });
    out.truncate(settings.max_proposals);
    out.into_iter().map(|(p, _)| p).collect()
}

/// The changed model analysed in full at `state`: DOF, redundancy and reactions. Returns the
/// proposal and its number of indeterminate reaction components.
fn check(
    model: &Model,
    tol: &Tolerances,
    v: &Verification,
    state: &State,
    input: &State,
    before: &[ElementReactions],
    c: &Candidate,
) -> Option<(Proposal, usize)> {
    let length = model.characteristic_length;
    let real = realize(model, &c.changes);
    let m2 = &real.model;
    let mut ideal: Vec<usize> = v.idealized.clone();
    for &(orig, new) in &real.appended {
        if v.idealized.contains(&orig) {
            ideal.push(new);
        }
    }
    let sys = compile(m2, input, &ideal);
    let all: Vec<usize> = (0..m2.constraints.len()).collect();
    let topo = topology(m2, &all);
    let an = analyse(&sys, state, &topo, length, tol);
    let rank = an.rank;
    let dof = 6 * m2.parts.len() as i64 - rank as i64;
    let redundant = sys.rows.len().checked_sub(rank)?;
    let after = determinacy(&sys, state, length, &an.null);
    let named = |m: &Model, r: &ElementReactions, dirs: Vec<Direction>| NamedReactions {
        name: m.constraints[r.element].origin.name.clone(),
        kind: m.constraints[r.element].description().to_string(),
        directions: dirs,
    };
    let indeterminate_after: Vec<NamedReactions> = after
        .iter()
        .filter(|r| !r.indeterminate.is_empty())
        .map(|r| named(m2, r, r.indeterminate.clone()))
        .collect();
    // The reactions after the change of each element (the first listed), found in O(1).
    let mut after_of: Vec<Option<&ElementReactions>> = vec![None; m2.constraints.len()];
    for a in after.iter().rev() {
        if let Some(slot) = after_of.get_mut(a.element) {
            *slot = Some(a);
        }
    }
    let mut now_determinate = Vec::new();
    for b in before.iter().filter(|b| !b.indeterminate.is_empty()) {
        let Some(a) = after_of.get(b.element).copied().flatten() else {
            continue;
        };
        let dirs: Vec<Direction> = b
            .indeterminate
            .iter()
            .filter(|d| a.determinate.contains(d))
            .copied()
            .collect();
        if !dirs.is_empty() {
            now_determinate.push(named(model, b, dirs));
        }
    }
    let count = indeterminate_after.iter().map(|r| r.directions.len()).sum();
    Some((
        Proposal {
            changes: c.changes.clone(),
            dof_after: dof,
            redundant_after: redundant,
            conditioning: c.cond,
            indeterminate_after,
            now_determinate,
        },
        count,
    ))
}
