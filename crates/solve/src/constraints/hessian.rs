//! Second derivatives of constraint quantities: the geometric stiffness `Σ λ_r ∂²Φ_r/∂q²`
//! (DESIGN §3, §6).
//!
//! Derivatives are of the gradient field of [`crate::constraints::rows`] with respect to the same tangent
//! perturbation (`δx`, `δθ` in ground), so `H[a][b] = ∂(∂Q/∂q_a)/∂q_b`. With `[v]×` the cross
//! matrix and, for body-fixed vectors, `d(u) = δθ × u = −[u]× δθ`:
//!
//! * `a·b`: `H[θA,θA] = a bᵀ − (a·b)1`, `H[θA,θB] = (a·b)1 − b aᵀ`, `H[θB,·] = −H[θA,·]`
//!   with A and B exchanged accordingly.
//! * `(P_i − P_j)·e`: from `∂/∂x_i = e`, `∂/∂θ_i = u_i × e`, `∂/∂θ_E = e × d` (and the
//!   negatives for j) — see [`Quantity::hessian`].
//! * `atan2(s, c)`: `H = (∇s∇cᵀ − ∇c∇sᵀ + c H_s − s H_c)/ρ − 2(c∇s − s∇c)(s∇s + c∇c)ᵀ/ρ²`.
//! * Euler angles and general-constraint expressions: by polarization (below).
//!
//! **Symmetric and antisymmetric parts.** The rotation increments are applied on the left
//! (`R ← exp([δθ]×)·R`), whose generators do not commute: `[ê_a, ê_b] = (e_a × e_b)^`. So `H`
//! is not symmetric; its antisymmetric part is fixed by the gradient alone. On the θθ block of
//! each part, `H − Hᵀ = −[g_θ]×` (`g_θ` the part's rotational gradient), and every other
//! block of `H − Hᵀ` is zero (translations commute with everything). The symmetric part is
//! the second derivative along the motion with constant twist u (`p(t) = p + t u_x`,
//! `R(t) = exp(t [u_θ]×)·R`): `d²Q/dt² = uᵀ H u`, since `Q̇ = ∇Q·u` and `d/dt ∇Q = H u`.
//!
//! **Polarization.** For a quantity whose second derivative along such a motion is available
//! ([`Quantity::series`] with zero accelerations; a general constraint's expression through
//! [`crate::physics::measures::PathEnv`] with frozen time and [`linkage_expr::evaluate_path_series`]),
//! with `S(u) = uᵀ H u` over the tangent coordinates `e_a` of the parts it depends on:
//! `H_sym[a][a] = S(e_a)`, `H_sym[a][b] = (S(e_a + e_b) − S(e_a) − S(e_b))/2`, and
//! `H = H_sym − ½[g_θ]×` on each part's θθ block. Cost: `m(m + 1)/2` second derivatives for
//! `m = 6 × (parts)` coordinates (21 for one part, 78 for two).
//!
//! A general constraint's parts are those of the markers its expression names
//! ([`crate::physics::measures::referenced_markers`]); when an id is computed, those with a non-zero
//! gradient block at the pose.

use crate::constraints::rows::{BodyDir, BodyPoint, Quantity, RowGradient, Velocities};
use crate::constraints::system::System;
use crate::physics::measures::{add_dual_gradient, referenced_markers, PathEnv, PositionEnv};
use crate::state::State;
use crate::tolerances::UNDEFINED_ANGLE;
use glam::{DMat3, DVec3};
use linkage_expr::{evaluate_path_series, evaluate_with_gradient, Expr};
use linkage_model::frames::skew;
use linkage_model::Body;

/// Accumulates `c·H` as 3×3 blocks: `(part_row, sub_row (0 = x, 1 = θ), part_col, sub_col, M)`.
#[derive(Default, Debug, Clone)]
pub struct HessianBlocks {
    pub blocks: Vec<(usize, usize, usize, usize, DMat3)>,
}

impl HessianBlocks {
    pub fn clear(&mut self) {
        self.blocks.clear();
    }
    fn add(&mut self, rb: Body, rs: usize, cb: Body, cs: usize, m: DMat3) {
        if let (Body::Part(r), Body::Part(c)) = (rb, cb) {
            self.blocks.push((r, rs, c, cs, m));
        }
    }
    /// Writes `scale ·` every block as `(row, col, value)` triplets in 6n index space.
    pub fn triplets(&self, scale: f64, out: &mut Vec<(usize, usize, f64)>) {
        for &(r, rs, c, cs, m) in &self.blocks {
            for i in 0..3 {
                for j in 0..3 {
                    let v = m.col(j)[i] * scale;
                    if v != 0.0 {
                        out.push((6 * r + 3 * rs + i, 6 * c + 3 * cs + j, v));
                    }
                }
            }
        }
    }
}

const X: usize = 0;
const TH: usize = 1;

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Hessian blocks of `a·b` scaled by `c`.
fn dot_hessian(a: &BodyDir, b: &BodyDir, s: &State, c: f64, h: &mut HessianBlocks) {
    let (va, vb) = (a.eval(s), b.eval(s));
    let ab = va.dot(vb);
    let aa = (outer(va, vb) - DMat3::IDENTITY * ab) * c;
    let ab_m = (DMat3::IDENTITY * ab - outer(vb, va)) * c;
    h.add(a.body, TH, a.body, TH, aa);
    h.add(a.body, TH, b.body, TH, ab_m);
    h.add(b.body, TH, a.body, TH, -aa);
    h.add(b.body, TH, b.body, TH, -ab_m);
}

fn proj_hessian(
    i: &BodyPoint,
    j: &BodyPoint,
    e: &BodyDir,
    s: &State,
    c: f64,
    h: &mut HessianBlocks,
) {
    let (pi, ui) = i.eval(s);
    let (pj, uj) = j.eval(s);
    let ve = e.eval(s);
    let d = pi - pj;
    let ex = skew(ve);
    // ∂/∂x_i = e, ∂/∂x_j = −e.
    h.add(i.body, X, e.body, TH, -ex * c);
    h.add(j.body, X, e.body, TH, ex * c);
    // ∂/∂θ_i = u_i × e.
    h.add(
        i.body,
        TH,
        i.body,
        TH,
        (outer(ui, ve) - DMat3::IDENTITY * ui.dot(ve)) * c,
    );
    h.add(
        i.body,
        TH,
        e.body,
        TH,
        (DMat3::IDENTITY * ui.dot(ve) - outer(ve, ui)) * c,
    );
    // ∂/∂θ_j = −u_j × e.
    h.add(
        j.body,
        TH,
        j.body,
        TH,
        -(outer(uj, ve) - DMat3::IDENTITY * uj.dot(ve)) * c,
    );
    h.add(
        j.body,
        TH,
        e.body,
        TH,
        -(DMat3::IDENTITY * uj.dot(ve) - outer(ve, uj)) * c,
    );
    // ∂/∂θ_E = e × d.
    h.add(
        e.body,
        TH,
        e.body,
        TH,
        (outer(ve, d) - DMat3::IDENTITY * ve.dot(d)) * c,
    );
    h.add(e.body, TH, i.body, X, ex * c);
    h.add(e.body, TH, i.body, TH, -(ex * skew(ui)) * c);
    h.add(e.body, TH, j.body, X, -ex * c);
    h.add(e.body, TH, j.body, TH, (ex * skew(uj)) * c);
}

/// Dense gradient (over body blocks) of `x·y` for the angle formula.
fn dot_grad(a: &BodyDir, b: &BodyDir, s: &State, g: &mut RowGradient) {
    g.clear();
    Quantity::Dot(*a, *b).gradient(s, 1.0, g);
}

fn add_outer(h: &mut HessianBlocks, u: &RowGradient, v: &RowGradient, c: f64) {
    for (bu, gu) in &u.blocks {
        for (bv, gv) in &v.blocks {
            for (rs, cs) in [(X, X), (X, TH), (TH, X), (TH, TH)] {
                let a = DVec3::new(gu[3 * rs], gu[3 * rs + 1], gu[3 * rs + 2]);
                let b = DVec3::new(gv[3 * cs], gv[3 * cs + 1], gv[3 * cs + 2]);
                if a != DVec3::ZERO && b != DVec3::ZERO {
                    h.blocks.push((*bu, rs, *bv, cs, outer(a, b) * c));
                }
            }
        }
    }
}

/// Adds `c·H` by polarization (module docs) over the tangent coordinates of `parts`:
/// `second(u)` is `uᵀ H u` for the twists `u` (one per model part, zero outside `parts`),
/// `g` the gradient. Returns false (adding nothing) when `second` fails.
fn polarize(
    parts: &[usize],
    nparts: usize,
    g: &RowGradient,
    c: f64,
    mut second: impl FnMut(&Velocities) -> Option<f64>,
    h: &mut HessianBlocks,
) -> bool {
    let m = 6 * parts.len();
    if m == 0 {
        return true;
    }
    let mut u: Vec<(DVec3, DVec3)> = vec![(DVec3::ZERO, DVec3::ZERO); nparts];
    let set = |u: &mut Vec<(DVec3, DVec3)>, a: usize, x: f64| {
        let (k, comp) = (parts[a / 6], a % 6);
        if comp < 3 {
            u[k].0[comp] = x;
        } else {
            u[k].1[comp - 3] = x;
        }
    };
    let mut diag = vec![0.0; m];
    for (a, d) in diag.iter_mut().enumerate() {
        set(&mut u, a, 1.0);
        let Some(v) = second(&u) else { return false };
        *d = v;
        set(&mut u, a, 0.0);
    }
    let mut sym = vec![0.0; m * m];
    for a in 0..m {
        sym[a * m + a] = diag[a];
        for b in a + 1..m {
            set(&mut u, a, 1.0);
            set(&mut u, b, 1.0);
            let Some(v) = second(&u) else { return false };
            set(&mut u, a, 0.0);
            set(&mut u, b, 0.0);
            let x = 0.5 * (v - diag[a] - diag[b]);
            sym[a * m + b] = x;
            sym[b * m + a] = x;
        }
    }
    for (pa, &ka) in parts.iter().enumerate() {
        for (pb, &kb) in parts.iter().enumerate() {
            for rs in [X, TH] {
                for cs in [X, TH] {
                    let entry =
                        |i: usize, j: usize| sym[(6 * pa + 3 * rs + i) * m + 6 * pb + 3 * cs + j];
                    let mut block = DMat3::from_cols_array_2d(&[
                        [entry(0, 0), entry(1, 0), entry(2, 0)],
                        [entry(0, 1), entry(1, 1), entry(2, 1)],
                        [entry(0, 2), entry(1, 2), entry(2, 2)],
                    ]);
                    if ka == kb && rs == TH && cs == TH {
                        if let Some((_, gb)) = g.blocks.iter().find(|(k, _)| *k == ka) {
                            block -= skew(DVec3::new(gb[3], gb[4], gb[5])) * 0.5;
                        }
                    }
                    if block != DMat3::ZERO {
                        h.blocks.push((ka, rs, kb, cs, block * c));
                    }
                }
            }
        }
    }
    true
}

impl System {
    /// Adds `c · ∂²Φ_r/∂q²` of row `r` to `h`: its geometric terms' analytic Hessians and, for a
    /// general constraint, the Hessian of its expression (by polarization of second
    /// derivatives along the path, time frozen). Returns false when part of it is not
    /// available (the expression cannot be evaluated at `s`); the rest is added.
    pub fn hessian(&self, r: usize, s: &State, c: f64, h: &mut HessianBlocks) -> bool {
        let row = &self.rows[r];
        let mut ok = true;
        for (k, q) in &row.terms {
            ok &= q.hessian(s, c * k, h);
        }
        if let Some(f) = &row.function {
            ok &= self.expression_hessian(f, s, c, h);
        }
        ok
    }

    /// `c ·` the Hessian of a position expression `f(q)` (module docs).
    fn expression_hessian(&self, f: &Expr, s: &State, c: f64, h: &mut HessianBlocks) -> bool {
        let position = PositionEnv {
            frames: &self.markers,
            state: s,
        };
        let Ok(d) = evaluate_with_gradient(f, &position) else {
            return false;
        };
        let mut g = RowGradient::default();
        add_dual_gradient(&d, 1.0, &mut g);
        let mut parts: Vec<usize> = match referenced_markers(f) {
            Some(ids) => ids
                .iter()
                .filter_map(|&id| self.markers.get(id).ok()?.body.part())
                .collect(),
            None => g.blocks.iter().map(|(k, _)| *k).collect(),
        };
        parts.sort_unstable();
        parts.dedup();
        let second = |u: &Velocities| {
            let env = PathEnv {
                frames: &self.markers,
                state: s,
                velocities: u,
                accelerations: None,
                time_rate: 0.0,
            };
            evaluate_path_series(f, &env).ok().map(|x| x[2])
        };
        polarize(&parts, self.nparts, &g, c, second, h)
    }
}

impl Quantity {
    /// Adds `c · ∂²Q/∂q²` to `h` (Euler angles, PTCV and CVCV gaps by polarization of
    /// [`Quantity::series`]).
    /// Returns true (every quantity has its second derivatives).
    pub fn hessian(&self, s: &State, c: f64, h: &mut HessianBlocks) -> bool {
        match self {
            Quantity::Dot(a, b) => {
                dot_hessian(a, b, s, c, h);
                true
            }
            Quantity::Proj { i, j, e } => {
                proj_hessian(i, j, e, s, c, h);
                true
            }
            Quantity::Angle { x, x_ref, y_ref } => {
                let (vx, vxr, vyr) = (x.eval(s), x_ref.eval(s), y_ref.eval(s));
                let (sn, cs) = (vx.dot(vyr), vx.dot(vxr));
                let rho = sn * sn + cs * cs;
                if rho <= UNDEFINED_ANGLE {
                    return true;
                }
                let (mut gs, mut gc) = (RowGradient::default(), RowGradient::default());
                dot_grad(x, y_ref, s, &mut gs);
                dot_grad(x, x_ref, s, &mut gc);
                add_outer(h, &gs, &gc, c / rho);
                add_outer(h, &gc, &gs, -c / rho);
                dot_hessian(x, y_ref, s, c * cs / rho, h);
                dot_hessian(x, x_ref, s, -c * sn / rho, h);
                // −2 (c∇s − s∇c)(s∇s + c∇c)ᵀ/ρ²
                let k = -2.0 * c / (rho * rho);
                add_outer(h, &gs, &gs, k * cs * sn);
                add_outer(h, &gs, &gc, k * cs * cs);
                add_outer(h, &gc, &gs, -k * sn * sn);
                add_outer(h, &gc, &gc, -k * sn * cs);
                true
            }
            Quantity::Euler(_) | Quantity::CurveGap(_) | Quantity::CurveContact(_) => {
                let (bi, bj) = match self {
                    Quantity::Euler(e) => (e.i.body, e.j.body),
                    Quantity::CurveGap(q) => (q.point.body, q.frame.body),
                    Quantity::CurveContact(q) => (q.frames[0].body, q.frames[1].body),
                    _ => return true,
                };
                let mut parts: Vec<usize> = [bi, bj].iter().filter_map(|b| b.part()).collect();
                parts.dedup();
                let Some(nparts) = parts.iter().max().map(|k| k + 1) else {
                    return true;
                };
                let mut g = RowGradient::default();
                self.gradient(s, 1.0, &mut g);
                let second = |u: &Velocities| Some(self.series(s, u, None)[2]);
                polarize(&parts, nparts, &g, c, second, h)
            }
        }
    }
}
