//! Second derivatives of constraint quantities: the geometric stiffness `Σ λ_r ∂²Φ_r/∂q²`
//! (DESIGN §3, §6).
//!
//! Derivatives are of the gradient field of [`crate::rows`] with respect to the same tangent
//! perturbation (`δx`, `δθ` in ground), so `H[a][b] = ∂(∂Q/∂q_a)/∂q_b`. With `[v]×` the cross
//! matrix and, for body-fixed vectors, `d(u) = δθ × u = −[u]× δθ`:
//!
//! * `a·b`: `H[θA,θA] = a bᵀ − (a·b)1`, `H[θA,θB] = (a·b)1 − b aᵀ`, `H[θB,·] = −H[θA,·]`
//!   with A and B exchanged accordingly.
//! * `(P_i − P_j)·e`: from `∂/∂x_i = e`, `∂/∂θ_i = u_i × e`, `∂/∂θ_E = e × d` (and the
//!   negatives for j) — see [`Quantity::hessian`].
//! * `atan2(s, c)`: `H = (∇s∇cᵀ − ∇c∇sᵀ + c H_s − s H_c)/ρ − 2(c∇s − s∇c)(s∇s + c∇c)ᵀ/ρ²`.
//!
//! Body 1-2-3 (and other Euler) angle quantities have no second derivative here; analyses that
//! use this module say so (their Newton iteration then converges linearly on those rows).

use crate::rows::{BodyDir, BodyPoint, Quantity, RowGradient};
use crate::state::State;
use glam::{DMat3, DVec3};
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

impl Quantity {
    /// Adds `c · ∂²Q/∂q²` to `h`. Returns false for quantities without second derivatives
    /// here (Euler angles).
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
                if rho <= 1e-300 {
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
            Quantity::Euler { .. } => false,
        }
    }
}
