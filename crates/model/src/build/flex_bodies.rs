//! FLEX_BODY, its MATRIX data and the markers on it → the model's [`FlexBody`]s and their
//! bodies (see [`crate::flex_bodies`] for the representation).
//!
//! **The modal data** [decided: the names are those Adams View gives the matrices it writes
//! from an MNF; their layouts are unconfirmed and chosen here]. The MATRIX statements the
//! FLEX_BODY lists are found by name: a FILE matrix's `NAME=`, else the MATRIX's
//! `adams_view_name` (its last `.`-separated part), compared without case. With `m` selected
//! modes and `N` nodes:
//!
//! | name | size | meaning |
//! |---|---|---|
//! | `SELMOD` | m × 1 or m × 2 | mode numbers (column 1; an optional column 2, the frequency, is not read). Optional: modes 1 … m |
//! | `SELNOD` | N × 4 | node id, then its undeformed x, y, z in the BCS |
//! | `GENSTIFF` | m × m | modal stiffness, symmetric (diagonal for orthogonal modes) |
//! | `INVAR1` | 1 × 1 | mass |
//! | `INVAR2` | 3 × 1 | first moment of mass `Σ m_p s_p` (BCS) |
//! | `INVAR3` | 3 × m | `Σ m_p Φ_p` (BCS): column j is mode j's first moment of mass. Optional: zero (a warning under gravity) |
//! | `INVAR6` | m × m | generalized mass, symmetric positive definite (diagonal for orthogonal modes) |
//! | `INVAR7` | 3 × 3 | inertia tensor about the BCS origin, BCS axes |
//! | `T_MODES` | 3N × m | translational mode shapes: rows 3k … 3k+2 are node k's x, y, z (SELNOD order) |
//! | `R_MODES` | 3N × m | rotational mode shapes (small rotations), same rows. Optional: zero |
//!
//! INVAR3 gives the modal load of the weight and, with INVAR4, 5, 8 and 9 ([`invariants`]),
//! the inertia coupling of the rigid and modal coordinates (module doc of
//! [`crate::flex_bodies`]); `INVARIANTS` switches each off.
//!
//! GENSTIFF and INVAR6 may be full symmetric matrices (INVAR6 positive definite): then the
//! modes linkage integrates are those of the principal basis `q = V·η` with `K·V = M·V·Λ`,
//! `Vᵀ·M·V = 1` ([`crate::modal_basis`]): shapes and INVAR3 times V, DMODE/VMODE as
//! `η = Vᵀ·M·q`, the mode bodies `<name>.mode_<k>` numbered 1 … m by ascending frequency,
//! CRATIO's FXFREQ and FXMODE theirs; reports and `--save` give the dataset's q = V·η
//! ([`FlexBody::coordinates`]).
//!
//! - A FLEX_BODY whose data is an MNF or MD DB file, or whose MATRIX file is missing or
//!   unreadable, is left out of the model (its markers stay unmodelled); `coverage` names
//!   the file and the analyses refuse the model.
//! - `DMODE` / `VMODE`: one value per selected mode (an error otherwise).
//! - `CRATIO`: an expression of `FXFREQ` (the mode's natural frequency, cycles per model
//!   time unit) and `FXMODE` (the mode number), evaluated once per mode [decided]; without
//!   it Adams' default by frequency in Hz ([`default_damping_ratio`]).
//! - Markers: `NODE_ID` → on that node's body (an id not in SELNOD is an error), their offset
//!   from the node's undeformed place and their axes (QP/REULER in the BCS) kept in the node's
//!   axes; without NODE_ID, on the reference body [decided].

mod invariants;

use super::context::{origin, Ctx};
use super::markers::MarkerStatements;
use crate::bodies::{Body, Marker, Part};
use crate::controls::{DenseMatrix, Matrix};
use crate::flex_bodies::{
    default_damping_ratio, FlexBody, FlexMode, FlexNode, FLEX_BODY_STATEMENT,
};
use crate::forces::{Bushing, ForceElement, ForceKind};
use crate::frames::{euler313_to_matrix, exp_so3};
use crate::modal_basis::principal_basis;
use crate::model::{Constraint, ConstraintKind, JointInitial};
use crate::units::Units;
use glam::{DMat3, DVec3};
use linkage_adm::flex_body::{type_flex_bodies, FlexBodyStatement};
use linkage_adm::{Dataset, JointType, MarkerCarrier, MatrixData, Severity, Span};
use std::collections::HashMap;

/// Relative size of an off-diagonal term of GENSTIFF or INVAR6 below which it is diagonal.
const OFF_DIAGONAL_TOLERANCE: f64 = 1e-9;

/// Builds every FLEX_BODY: appends its reference, mode and node bodies to `parts` and
/// re-places the markers on it (in `markers` and `ms.placed`).
pub(crate) fn flex_bodies(
    ds: &Dataset,
    units: &Units,
    gravity: DVec3,
    parts: &mut Vec<Part>,
    markers: &mut [Marker],
    ms: &mut MarkerStatements,
    cx: &mut Ctx,
) -> Vec<FlexBody> {
    let has_flex = ds
        .statements
        .iter()
        .any(|s| s.keyword == FLEX_BODY_STATEMENT);
    if !has_flex {
        return Vec::new();
    }
    let (data, diagnostics) = type_flex_bodies(ds);
    for d in diagnostics {
        match d.severity {
            Severity::Error => cx.errors.push(d),
            _ => cx.warnings.push(d),
        }
    }
    // The MATRIX values (controls reports their own errors; a scratch context here).
    let mut scratch = Ctx {
        file: cx.file.clone(),
        user: cx.user.clone(),
        errors: Vec::new(),
        warnings: Vec::new(),
    };
    let (matrices, unreadable) = super::controls::matrices(ds, &mut scratch);
    let names: HashMap<u64, String> = ds
        .controls
        .matrices
        .iter()
        .map(|m| {
            let name = match &m.data {
                MatrixData::File {
                    matrix: Some(n), ..
                } => n.clone(),
                _ => m.header.name.rsplit('.').next().unwrap_or("").to_string(),
            };
            (m.header.id, name.to_ascii_uppercase())
        })
        .collect();
    let mut out: Vec<FlexBody> = Vec::with_capacity(data.bodies.len());
    for st in &data.bodies {
        if out.iter().any(|b| b.origin.id == st.header.id) {
            cx.error(
                st.header.span,
                format!("duplicate FLEX_BODY id {}", st.header.id),
            );
            continue;
        }
        // Data the builder cannot read: left out, named by coverage.
        if st.matrices.is_empty() || st.matrices.iter().any(|r| unreadable.contains_key(&r.id)) {
            continue;
        }
        let source = Source {
            st,
            matrices: &matrices,
            names: &names,
        };
        let node_ids: Vec<u64> = data
            .marker_nodes
            .iter()
            .filter(|(id, _)| {
                ms.index.get(id).is_some_and(|&k| {
                    matches!(ms.statements[k].carrier, Some(MarkerCarrier::FlexBody(r)) if r.id == st.header.id)
                })
            })
            .filter_map(|(_, n)| n.as_ref().map(|n| n.value))
            .collect();
        if let Some(b) = flex_body(&source, &node_ids, units, gravity, parts, cx) {
            out.push(b);
        }
    }
    place_markers(
        &data.marker_nodes,
        &data.bodies,
        &out,
        parts,
        markers,
        ms,
        cx,
    );
    out
}

struct Source<'a> {
    st: &'a FlexBodyStatement,
    matrices: &'a [Matrix],
    names: &'a HashMap<u64, String>,
}

impl Source<'_> {
    fn span(&self) -> Span {
        self.st
            .matrices
            .first()
            .map_or(self.st.header.span, |r| r.span)
    }

    /// The listed MATRIX called `name`.
    fn find(&self, name: &str) -> Option<&DenseMatrix> {
        let r = self
            .st
            .matrices
            .iter()
            .find(|r| self.names.get(&r.id).is_some_and(|n| n == name))?;
        self.matrices
            .iter()
            .find(|m| m.origin.id == r.id)
            .map(|m| &m.matrix)
    }

    /// The listed MATRIX called `name`, of size `rows × columns` (an error otherwise).
    fn sized(&self, name: &str, rows: usize, columns: usize, cx: &mut Ctx) -> Option<DenseMatrix> {
        let label = &self.st.header.name;
        let Some(m) = self.find(name) else {
            cx.error(
                self.span(),
                format!("{label}: MATRICES has no matrix named {name}"),
            );
            return None;
        };
        if m.rows != rows || m.columns != columns {
            cx.error(
                self.span(),
                format!(
                    "{label}: {name} is {} × {}, expected {rows} × {columns}",
                    m.rows, m.columns
                ),
            );
            return None;
        }
        Some(m.clone())
    }
}

fn flex_body(
    src: &Source,
    node_ids: &[u64],
    units: &Units,
    gravity: DVec3,
    parts: &mut Vec<Part>,
    cx: &mut Ctx,
) -> Option<FlexBody> {
    let st = src.st;
    let name = st.header.name.clone();
    let Some(stiffness) = src.find("GENSTIFF").map(|k| k.rows) else {
        cx.error(
            src.span(),
            format!("{name}: MATRICES has no matrix named GENSTIFF"),
        );
        return None;
    };
    let m = stiffness;
    let (k, gm, basis) = modal_matrices(src, m, cx)?;
    let mass = src.sized("INVAR1", 1, 1, cx)?.get(0, 0);
    let first = src.sized("INVAR2", 3, 1, cx)?;
    let i7 = src.sized("INVAR7", 3, 3, cx)?;
    let Some(selnod) = src.find("SELNOD").cloned() else {
        cx.error(
            src.span(),
            format!("{name}: MATRICES has no matrix named SELNOD"),
        );
        return None;
    };
    if selnod.columns != 4 {
        cx.error(
            src.span(),
            format!(
                "{name}: SELNOD needs 4 columns (node id, x, y, z), found {}",
                selnod.columns
            ),
        );
        return None;
    }
    let n_nodes = selnod.rows;
    let mut t_modes = src.sized("T_MODES", 3 * n_nodes, m, cx)?;
    let mut r_modes = match src.find("R_MODES") {
        Some(_) => Some(src.sized("R_MODES", 3 * n_nodes, m, cx)?),
        None => None,
    };
    let dataset_labels: Vec<u64> = match src.find("SELMOD") {
        Some(s) if s.rows == m && (s.columns == 1 || s.columns == 2) => {
            (0..m).map(|i| s.get(i, 0) as u64).collect()
        }
        Some(s) => {
            cx.error(
                src.span(),
                format!(
                    "{name}: SELMOD is {} × {}, expected {m} × 1 or {m} × 2",
                    s.rows, s.columns
                ),
            );
            return None;
        }
        None => (1..=m as u64).collect(),
    };
    let positive = |x: f64| x.is_finite() && x > 0.0;
    let not_negative = |x: f64| x.is_finite() && x >= 0.0;
    if !positive(mass) || !gm.iter().all(|g| positive(*g)) || !k.iter().all(|x| not_negative(*x)) {
        cx.error(
            src.span(),
            format!(
                "{name}: INVAR1 and the generalized masses (INVAR6) must be positive, the modal \
                 stiffnesses (GENSTIFF) not negative"
            ),
        );
        return None;
    }
    let per_mode = |v: &Option<linkage_adm::Located<Vec<f64>>>, key: &str, cx: &mut Ctx| match v {
        None => Some(vec![0.0; m]),
        Some(l) if l.value.len() == m => Some(l.value.clone()),
        Some(l) => {
            cx.error(
                l.span,
                format!(
                    "{name}: {key} needs {m} values (one per mode), found {}",
                    l.value.len()
                ),
            );
            None
        }
    };
    let mut dmode = per_mode(&st.dmode, "DMODE", cx)?;
    let mut vmode = per_mode(&st.vmode, "VMODE", cx)?;
    // In a principal basis (q = V·η): shapes Φ·V, coordinates η = Vᵀ·M·q; the modes are
    // numbered 1 … m in ascending frequency.
    let labels: Vec<u64> = match &basis {
        None => dataset_labels.clone(),
        Some(b) => {
            t_modes = times(&t_modes, &b.v, m);
            r_modes = r_modes.map(|r| times(&r, &b.v, m));
            dmode = b.coordinates(&dmode);
            vmode = b.coordinates(&vmode);
            (1..=m as u64).collect()
        }
    };
    let ratios = damping_ratios(st, &labels, &k, &gm, units, cx)?;
    let inertia = invariants::modal_inertia(src, m, basis.as_ref().map(|b| b.v.as_slice()), cx)?;
    // INVAR3 (Σ m_p Φ_p, 3 × m in the BCS): the modal load of the weight.
    let first_moments: Vec<DVec3> = if !st.invariants[2] {
        vec![DVec3::ZERO; m]
    } else if src.find("INVAR3").is_some() {
        let mut i3 = src.sized("INVAR3", 3, m, cx)?;
        if let Some(b) = &basis {
            i3 = times(&i3, &b.v, m);
        }
        (0..m)
            .map(|j| DVec3::new(i3.get(0, j), i3.get(1, j), i3.get(2, j)))
            .collect()
    } else {
        if gravity != DVec3::ZERO {
            cx.warn(
                src.span(),
                format!("{name}: MATRICES has no INVAR3 (Σ m_p Φ_p), so the weight loads no mode"),
            );
        }
        vec![DVec3::ZERO; m]
    };
    // The BCS, the reference body at the centre of mass.
    let bcs_p = st
        .qg
        .as_ref()
        .map_or(DVec3::ZERO, |q| cx.point(&name, "QG", q));
    let a = st
        .reuler
        .as_ref()
        .map_or(DMat3::IDENTITY, |r| euler313_to_matrix(r.value));
    let cm = DVec3::new(first.get(0, 0), first.get(1, 0), first.get(2, 0)) / mass;
    let i_o = DMat3::from_cols(
        DVec3::new(i7.get(0, 0), i7.get(1, 0), i7.get(2, 0)),
        DVec3::new(i7.get(0, 1), i7.get(1, 1), i7.get(2, 1)),
        DVec3::new(i7.get(0, 2), i7.get(1, 2), i7.get(2, 2)),
    );
    // Parallel axes: I_cm = I_O − m (|c|² 1 − c cᵀ).
    let shift = DMat3::from_diagonal(DVec3::splat(cm.length_squared()))
        - DMat3::from_cols(cm * cm.x, cm * cm.y, cm * cm.z);
    let i_cm = i_o - shift * mass;
    let reference = parts.len();
    parts.push(Part {
        origin: origin(FLEX_BODY_STATEMENT, &st.header),
        mass,
        inertia: i_cm,
        p_gb: bcs_p + a * cm,
        r_gb: a,
        p_b_bcs: -cm,
        velocity: st.velocity,
        r_b_cm: DMat3::IDENTITY,
        exact: st.exact.clone(),
        point_mass: false,
    });
    // Mode bodies along a ground direction normal to gravity.
    let axis = mode_axis(gravity);
    let gyration = (i_cm.x_axis.x + i_cm.y_axis.y + i_cm.z_axis.z) / (2.0 * mass);
    let gyration = if gyration > 0.0 && gyration.is_finite() {
        gyration
    } else {
        1.0
    };
    let mut modes = Vec::with_capacity(m);
    for j in 0..m {
        let mut o = origin(FLEX_BODY_STATEMENT, &st.header);
        o.name = format!("{name}.mode_{}", labels[j]);
        let given = st.vmode.is_some();
        let v = axis * vmode[j];
        modes.push(FlexMode {
            label: labels[j],
            part: parts.len(),
            mass: gm[j],
            stiffness: k[j],
            damping_ratio: ratios[j],
            frequency: (k[j] / gm[j]).sqrt() / std::f64::consts::TAU,
            first_moment: first_moments[j],
        });
        parts.push(Part {
            origin: o,
            mass: gm[j],
            inertia: DMat3::from_diagonal(DVec3::splat(gm[j] * gyration)),
            p_gb: bcs_p + axis * dmode[j],
            r_gb: DMat3::IDENTITY,
            p_b_bcs: DVec3::ZERO,
            velocity: if given {
                [
                    Some(v.x),
                    Some(v.y),
                    Some(v.z),
                    Some(0.0),
                    Some(0.0),
                    Some(0.0),
                ]
            } else {
                [None; 6]
            },
            r_b_cm: DMat3::IDENTITY,
            exact: Vec::new(),
            point_mass: false,
        });
    }
    // Node bodies of the nodes markers use, in SELNOD order.
    let mut nodes = Vec::new();
    for row in 0..n_nodes {
        let id = selnod.get(row, 0) as u64;
        if !node_ids.contains(&id) || nodes.iter().any(|n: &FlexNode| n.id == id) {
            continue;
        }
        let shape = |d: &DenseMatrix, j: usize| {
            DVec3::new(
                d.get(3 * row, j),
                d.get(3 * row + 1, j),
                d.get(3 * row + 2, j),
            )
        };
        let translation: Vec<DVec3> = (0..m).map(|j| shape(&t_modes, j)).collect();
        let rotation: Vec<DVec3> = (0..m)
            .map(|j| r_modes.as_ref().map_or(DVec3::ZERO, |r| shape(r, j)))
            .collect();
        let position = DVec3::new(selnod.get(row, 1), selnod.get(row, 2), selnod.get(row, 3));
        let u: DVec3 = (0..m).map(|j| translation[j] * dmode[j]).sum();
        let theta: DVec3 = (0..m).map(|j| rotation[j] * dmode[j]).sum();
        let mut o = origin(FLEX_BODY_STATEMENT, &st.header);
        o.name = format!("{name}.node_{id}");
        let p = bcs_p + a * (position + u);
        nodes.push(FlexNode {
            id,
            part: parts.len(),
            position,
            translation,
            rotation,
        });
        parts.push(Part {
            origin: o,
            mass: 0.0,
            inertia: DMat3::ZERO,
            p_gb: p,
            r_gb: exp_so3(a * theta) * a,
            p_b_bcs: DVec3::ZERO,
            velocity: [None; 6],
            r_b_cm: DMat3::IDENTITY,
            exact: Vec::new(),
            point_mass: false,
        });
    }
    Some(FlexBody {
        origin: origin(FLEX_BODY_STATEMENT, &st.header),
        reference,
        bcs_in_body: -cm,
        modes,
        nodes,
        axis,
        rest: bcs_p,
        first_node_constraint: 0,
        inertia,
        labels: dataset_labels,
        basis: basis.map(|b| b.v),
    })
}

/// GENSTIFF and INVAR6 → the modal stiffnesses and generalized masses of the coordinates
/// linkage integrates: the dataset's own when both are diagonal, else those of the principal
/// basis ([`principal_basis`]: stiffness `ω_j²`, mass 1) with the basis.
fn modal_matrices(
    src: &Source,
    m: usize,
    cx: &mut Ctx,
) -> Option<(Vec<f64>, Vec<f64>, Option<Basis>)> {
    let k = src.sized("GENSTIFF", m, m, cx)?;
    let mass = src.sized("INVAR6", m, m, cx)?;
    let diagonal = |d: &DenseMatrix| {
        let scale = (0..m).fold(0.0f64, |a, i| a.max(d.get(i, i).abs()));
        (0..m)
            .all(|i| (0..m).all(|j| i == j || d.get(i, j).abs() <= OFF_DIAGONAL_TOLERANCE * scale))
    };
    if diagonal(&k) && diagonal(&mass) {
        let diag = |d: &DenseMatrix| (0..m).map(|i| d.get(i, i)).collect();
        return Some((diag(&k), diag(&mass), None));
    }
    match principal_basis(&k.values, &mass.values, m) {
        Ok((lambda, v)) => {
            let largest = lambda.iter().fold(0.0f64, |a, l| a.max(l.abs()));
            // Rounding below zero of a rigid-body mode's ω² is zero.
            let lambda = lambda
                .into_iter()
                .map(|l| {
                    if l < 0.0 && l > -1e-12 * largest {
                        0.0
                    } else {
                        l
                    }
                })
                .collect();
            Some((
                lambda,
                vec![1.0; m],
                Some(Basis {
                    v,
                    mass: mass.values,
                    m,
                }),
            ))
        }
        Err(e) => {
            cx.error(src.span(), format!("{}: {e}", src.st.header.name));
            None
        }
    }
}

/// A principal basis `q = V·η` with the generalized mass it is orthonormal in.
struct Basis {
    /// `V`, row-major m × m.
    v: Vec<f64>,
    /// INVAR6, row-major.
    mass: Vec<f64>,
    m: usize,
}

impl Basis {
    /// `η = Vᵀ·M·q`.
    fn coordinates(&self, q: &[f64]) -> Vec<f64> {
        let m = self.m;
        let mq: Vec<f64> = (0..m)
            .map(|i| (0..m).map(|j| self.mass[i * m + j] * q[j]).sum())
            .collect();
        (0..m)
            .map(|j| (0..m).map(|i| self.v[i * m + j] * mq[i]).sum())
            .collect()
    }
}

/// `a·V` for an `r × m` matrix `a` and the m × m row-major `v`.
fn times(a: &DenseMatrix, v: &[f64], m: usize) -> DenseMatrix {
    let mut out = DenseMatrix::zeros(a.rows, m);
    for r in 0..a.rows {
        for j in 0..m {
            out.values[r * m + j] = (0..m).map(|i| a.get(r, i) * v[i * m + j]).sum();
        }
    }
    out
}

/// A ground direction normal to gravity (ground z without gravity): the ground axis least
/// aligned with gravity, made normal to it.
fn mode_axis(gravity: DVec3) -> DVec3 {
    let g = gravity.normalize_or_zero();
    if g == DVec3::ZERO {
        return DVec3::Z;
    }
    let e = [DVec3::Z, DVec3::X, DVec3::Y]
        .into_iter()
        .min_by(|a, b| a.dot(g).abs().total_cmp(&b.dot(g).abs()))
        .unwrap_or(DVec3::Z);
    (e - g * e.dot(g)).normalize()
}

/// ζ per mode: CRATIO with FXFREQ and FXMODE replaced by the mode's values, or Adams'
/// default by frequency in Hz.
fn damping_ratios(
    st: &FlexBodyStatement,
    labels: &[u64],
    k: &[f64],
    gm: &[f64],
    units: &Units,
    cx: &mut Ctx,
) -> Option<Vec<f64>> {
    let freq: Vec<f64> = k
        .iter()
        .zip(gm)
        .map(|(k, m)| (k / m).sqrt() / std::f64::consts::TAU)
        .collect();
    let Some(c) = &st.cratio else {
        return Some(
            freq.iter()
                .map(|f| default_damping_ratio(f / units.time))
                .collect(),
        );
    };
    let name = &st.header.name;
    if c.value.user {
        cx.error(
            c.span,
            format!(
                "{name}: CRATIO = USER(…) needs a DMPSUB subroutine, which linkage cannot call"
            ),
        );
        return None;
    }
    let mut out = Vec::with_capacity(freq.len());
    for (j, f) in freq.iter().enumerate() {
        let text = substitute(
            &c.value.expr.text,
            &[("FXFREQ", *f), ("FXMODE", labels[j] as f64)],
        );
        let value = linkage_expr::parse(&text)
            .map_err(|e| e.message.clone())
            .and_then(|e| {
                linkage_expr::evaluate(&e, &linkage_expr::TimeEnv::default())
                    .map_err(|e| e.to_string())
            });
        match value {
            Ok(v) if v >= 0.0 && v.is_finite() => out.push(v),
            Ok(v) => {
                cx.error(
                    c.span,
                    format!("{name}: CRATIO is {v} for mode {}", labels[j]),
                );
                return None;
            }
            Err(e) => {
                cx.error(
                    c.span,
                    format!("{name}: CRATIO (a function of FXFREQ, FXMODE and constants): {e}"),
                );
                return None;
            }
        }
    }
    Some(out)
}

/// `text` with every whole word `names[i].0` (any case) replaced by the number `names[i].1`.
fn substitute(text: &str, names: &[(&str, f64)]) -> String {
    let mut out = String::with_capacity(text.len());
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < text.len() {
        let c = bytes[i];
        if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < text.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            let word = &text[start..i];
            match names.iter().find(|(n, _)| n.eq_ignore_ascii_case(word)) {
                Some((_, v)) => out.push_str(&format!("({v:e})")),
                None => out.push_str(word),
            }
        } else {
            let ch = text[i..].chars().next().unwrap_or(' ');
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

/// Markers on flex bodies: on their node's body (NODE_ID) or the reference body, pose kept.
fn place_markers(
    marker_nodes: &[(u64, Option<linkage_adm::Located<u64>>)],
    statements: &[FlexBodyStatement],
    bodies: &[FlexBody],
    parts: &[Part],
    markers: &mut [Marker],
    ms: &mut MarkerStatements,
    cx: &mut Ctx,
) {
    for (k, st) in ms.statements.iter().enumerate() {
        let Some(MarkerCarrier::FlexBody(r)) = st.carrier else {
            continue;
        };
        let name = &st.header.name;
        let Some(b) = bodies.iter().find(|b| b.origin.id == r.id) else {
            if !statements.iter().any(|s| s.header.id == r.id) {
                cx.error(r.span, format!("{name}: FLEX_BODY {} does not exist", r.id));
            }
            continue;
        };
        let node = marker_nodes
            .iter()
            .find(|(id, _)| *id == st.header.id)
            .and_then(|(_, n)| n.clone());
        // A node body's axes are the BCS axes when undeformed: a marker keeps its offset
        // from the node's undeformed place (so it rides with the DMODE deformation too).
        let (part, node_at) = match node {
            Some(l) => match b.nodes.iter().find(|n| n.id == l.value) {
                Some(n) => (n.part, Some(n.position)),
                None => {
                    cx.error(
                        l.span,
                        format!("{name}: {} has no node {} (SELNOD)", b.origin.name, l.value),
                    );
                    continue;
                }
            },
            None => (b.reference, None),
        };
        let placed = &mut ms.placed[k];
        if let Some(s_p) = node_at {
            placed.body = Body::Part(part);
            placed.p -= s_p;
            placed.unsupported = None;
            let mk = &mut markers[k];
            mk.body = Body::Part(part);
            mk.p_bm = placed.p;
            mk.r_bm = placed.r;
            continue;
        }
        let reference = &parts[b.reference];
        let (bcs_p, a) = (
            reference.p_gb + reference.r_gb * b.bcs_in_body,
            reference.r_gb,
        );
        let p_g = bcs_p + a * placed.p;
        let r_g = a * placed.r;
        let body = &parts[part];
        let r_t = body.r_gb.transpose();
        placed.body = Body::Part(part);
        placed.p = r_t * (p_g - body.p_gb);
        placed.r = r_t * r_g;
        placed.unsupported = None;
        let mk = &mut markers[k];
        mk.body = Body::Part(part);
        mk.p_bm = placed.p;
        mk.r_bm = placed.r;
    }
}

/// Appends each flex body's hidden elements after every dataset element: per mode a guide
/// (a TRANSLATIONAL joint to ground along `axis`, two markers of id 0) and a bushing (the
/// modal stiffness and damping along it); per node its FLEX_NODE equations.
pub(crate) fn attach(
    bodies: &mut [FlexBody],
    parts: &[Part],
    markers: &mut Vec<Marker>,
    constraints: &mut Vec<Constraint>,
    forces: &mut Vec<ForceElement>,
) {
    for (f, b) in bodies.iter_mut().enumerate() {
        let axes = axes_along(b.axis);
        for mode in &b.modes {
            let part = &parts[mode.part];
            let i = markers.len();
            markers.push(Marker {
                id: 0,
                name: format!("{}.coordinate", part.origin.name),
                span: part.origin.span,
                body: Body::Part(mode.part),
                p_bm: DVec3::ZERO,
                r_bm: axes,
                floating: false,
            });
            markers.push(Marker {
                id: 0,
                name: format!("{}.rest", part.origin.name),
                span: part.origin.span,
                body: Body::Ground,
                p_bm: b.rest,
                r_bm: axes,
                floating: false,
            });
            constraints.push(Constraint {
                origin: part.origin.clone(),
                kind: ConstraintKind::Joint {
                    kind: JointType::Translational,
                    i,
                    j: i + 1,
                    initial: JointInitial::default(),
                    pd: None,
                    pitch: None,
                },
            });
            let omega = (mode.stiffness / mode.mass).sqrt();
            forces.push(ForceElement {
                origin: part.origin.clone(),
                kind: ForceKind::Bushing(Bushing {
                    i,
                    j: i + 1,
                    stiffness: [0.0, 0.0, mode.stiffness],
                    damping: [0.0, 0.0, 2.0 * mode.damping_ratio * omega * mode.mass],
                    rotational_stiffness: [0.0; 3],
                    rotational_damping: [0.0; 3],
                    force: [0.0; 3],
                    torque: [0.0; 3],
                }),
            });
        }
        b.first_node_constraint = constraints.len();
        for node in 0..b.nodes.len() {
            let mut o = b.origin.clone();
            o.name = parts[b.nodes[node].part].origin.name.clone();
            constraints.push(Constraint {
                origin: o,
                kind: ConstraintKind::FlexNode { body: f, node },
            });
        }
    }
}

/// Axes whose z is `axis`.
fn axes_along(axis: DVec3) -> DMat3 {
    let x = axis.any_orthonormal_vector();
    DMat3::from_cols(x, axis.cross(x), axis)
}

#[cfg(test)]
mod tests {
    use super::{mode_axis, substitute};
    use glam::DVec3;

    #[test]
    fn fxfreq_and_fxmode_are_replaced_as_whole_words() {
        let s = substitute(
            "STEP(FXFREQ, 0, .01, 100, .1) + fxmode*0 + FXFREQX",
            &[("FXFREQ", 2.0), ("FXMODE", 3.0)],
        );
        assert_eq!(s, "STEP((2e0), 0, .01, 100, .1) + (3e0)*0 + FXFREQX");
    }

    #[test]
    fn modal_axis_is_normal_to_gravity() {
        assert_eq!(mode_axis(DVec3::ZERO), DVec3::Z);
        let a = mode_axis(DVec3::new(0.0, 0.0, -9.81));
        assert!(a.dot(DVec3::Z).abs() < 1e-15 && (a.length() - 1.0).abs() < 1e-15);
        let a = mode_axis(DVec3::new(1.0, -2.0, 0.5));
        assert!(a.dot(DVec3::new(1.0, -2.0, 0.5)).abs() < 1e-12);
    }
}
