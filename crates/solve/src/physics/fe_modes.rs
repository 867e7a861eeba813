//! The equivalent linear flexible body of an FE_PART, as Adams counts it (issue 17): the
//! Craig–Bampton reduction of the beam's own linear mass and stiffness at the input
//! configuration (Craig & Bampton, AIAA J. 6(7), 1968).
//!
//! Boundary nodes are the nodes markers use; every other node is interior. With the linear
//! stiffness `K` (the exact Euler–Bernoulli element, rotated from each element's frame E₀ to
//! ground, `K = Σ Tᵀ K_e T`) and the lumped mass `M` of the node bodies, partitioned into
//! interior (i) and boundary (b) degrees of freedom:
//!
//! ```text
//! constraint modes  Ψ = −K_ii⁻¹ K_ib           (6 per boundary node; 3 for a cable node)
//! normal modes      K_ii φ = ω² M_ii φ          (fixed boundary; the lowest `requested`)
//! ```
//!
//! The Gruebler count of the part is `normal modes + constraint modes + 6`
//! ([`ChapterCount`]); at most `dim K_ii` normal modes exist. ω² is in the model's units:
//! `M·ẍ = UCF·F`, so `ω² = UCF·λ` with λ the eigenvalue of the pencil `(K_ii, M_ii)`. The
//! product of inertia Iyz is left out of this reduction (it only shifts the reported
//! frequencies of unsymmetric sections; the analyses use it).

use faer::Mat;
use linkage_model::fe_parts::{ChapterCount, FeKind};
use linkage_model::Model;

/// The Craig–Bampton reduction of one FE part.
#[derive(Clone, Debug, PartialEq)]
pub struct FeModes {
    /// Index into [`Model::fe_parts`].
    pub fe: usize,
    pub count: ChapterCount,
    /// Labels of the boundary nodes (those markers use), ascending by node order.
    pub boundary_labels: Vec<u64>,
    /// Nodes and elements.
    pub nodes: usize,
    pub elements: usize,
    /// Degrees of freedom of the node bodies (6 per node; 3 per cable node).
    pub nodal_dof: usize,
    /// The lowest fixed-boundary natural frequencies, cycles per time unit, ascending
    /// (`count.normal_modes` of them when the eigensolution succeeds).
    pub normal_frequencies: Vec<f64>,
    /// Columns of Ψ (equal to `count.constraint_modes`).
    pub constraint_modes: usize,
}

/// The 12×12 Euler–Bernoulli stiffness in the element frame, DOFs per node (u, v, w, θx, θy, θz).
fn local_stiffness(ea: f64, gj: f64, eiy: f64, eiz: f64, l: f64) -> [[f64; 12]; 12] {
    let mut k = [[0.0; 12]; 12];
    let mut put = |dofs: [usize; 2], m: [[f64; 2]; 2]| {
        for r in 0..2 {
            for c in 0..2 {
                k[dofs[r]][dofs[c]] += m[r][c];
            }
        }
    };
    put([0, 6], [[ea / l, -ea / l], [-ea / l, ea / l]]);
    put([3, 9], [[gj / l, -gj / l], [-gj / l, gj / l]]);
    // x–y plane: (v_a, θz_a, v_b, θz_b); x–z plane: (w_a, θy_a, w_b, θy_b), 6L terms negated.
    for (dofs, ei, s) in [([1, 5, 7, 11], eiz, 1.0), ([2, 4, 8, 10], eiy, -1.0)] {
        let (l2, l3) = (l * l, l * l * l);
        let m = [
            [12.0, s * 6.0 * l, -12.0, s * 6.0 * l],
            [s * 6.0 * l, 4.0 * l2, -s * 6.0 * l, 2.0 * l2],
            [-12.0, -s * 6.0 * l, 12.0, -s * 6.0 * l],
            [s * 6.0 * l, 2.0 * l2, -s * 6.0 * l, 4.0 * l2],
        ];
        for r in 0..4 {
            for c in 0..4 {
                k[dofs[r]][dofs[c]] += ei / l3 * m[r][c];
            }
        }
    }
    k
}

/// The linear stiffness and lumped mass of FE part `fe` in its nodal coordinates (per node
/// δx then δθ in ground axes; a cable's nodes δx only).
pub fn matrices(model: &Model, fe: usize) -> (Mat<f64>, Mat<f64>, usize) {
    let p = &model.fe_parts[fe];
    let cable = p.kind == FeKind::Cable3d;
    let per = if cable { 3 } else { 6 };
    let n = per * p.nodes.len();
    let mut k = Mat::<f64>::zeros(n, n);
    let mut m = Mat::<f64>::zeros(n, n);
    for e in &p.elements {
        let s = &e.section;
        let (ey, g) = (p.youngs_modulus, p.shear_modulus);
        let kl = if cable {
            local_stiffness(ey * s.area, 0.0, 0.0, 0.0, e.length)
        } else {
            local_stiffness(ey * s.area, g * s.jxx, ey * s.iyy, ey * s.izz, e.length)
        };
        // E₀ in ground from node a's pose: R_a·(R_aᵀE₀).
        let r_a = model.parts[p.nodes[e.a].part].r_gb;
        let e0 = r_a * e.r_a_e;
        // Global → local per 3-block: d_local = E₀ᵀ d_global.
        let t = |r: usize, c: usize| e0.col(r)[c];
        let nodes = [e.a, e.b];
        for (bi, &na) in nodes.iter().enumerate() {
            for (bj, &nb) in nodes.iter().enumerate() {
                for blk_r in 0..per / 3 {
                    for blk_c in 0..per / 3 {
                        let lr = 6 * bi + 3 * blk_r;
                        let lc = 6 * bj + 3 * blk_c;
                        // Tᵀ K T on a 3×3 block: Σ t(a,r)·K[a][b]·t(b,c).
                        for r in 0..3 {
                            for c in 0..3 {
                                let mut v = 0.0;
                                for a in 0..3 {
                                    for b in 0..3 {
                                        v += t(a, r) * kl[lr + a][lc + b] * t(b, c);
                                    }
                                }
                                k[(per * na + 3 * blk_r + r, per * nb + 3 * blk_c + c)] += v;
                            }
                        }
                    }
                }
            }
        }
    }
    for (i, node) in p.nodes.iter().enumerate() {
        let part = &model.parts[node.part];
        for c in 0..3 {
            m[(per * i + c, per * i + c)] = part.mass;
        }
        if !cable {
            let ig = part.r_gb * part.inertia * part.r_gb.transpose();
            for r in 0..3 {
                for c in 0..3 {
                    m[(per * i + 3 + r, per * i + 3 + c)] = ig.col(c)[r];
                }
            }
        }
    }
    (k, m, per)
}

/// The Craig–Bampton reduction of FE part `fe` with `requested` normal modes asked for.
pub fn fe_modes(model: &Model, fe: usize, requested: usize) -> FeModes {
    let p = &model.fe_parts[fe];
    let boundary = model.fe_marker_nodes(fe);
    let (k, m, per) = matrices(model, fe);
    let count = ChapterCount::new(p.nodes.len(), boundary.len(), per, requested);
    let interior: Vec<usize> = (0..p.nodes.len())
        .filter(|n| !boundary.contains(n))
        .flat_map(|n| (0..per).map(move |c| per * n + c))
        .collect();
    let normal_frequencies = fixed_boundary_frequencies(&k, &m, &interior, model.ucf())
        .into_iter()
        .take(count.normal_modes)
        .collect();
    FeModes {
        fe,
        count,
        boundary_labels: boundary.iter().map(|&n| p.nodes[n].label).collect(),
        nodes: p.nodes.len(),
        elements: p.elements.len(),
        nodal_dof: per * p.nodes.len(),
        normal_frequencies,
        constraint_modes: count.constraint_modes,
    }
}

/// Natural frequencies (cycles per time unit, ascending) of `(K_ii, M_ii)` on the
/// coordinates `dofs`: `M^{-1/2} K M^{-1/2}` by a symmetric eigensolution (M is positive
/// definite for a beam: masses and rotary inertias). Empty when the eigensolution fails.
pub fn fixed_boundary_frequencies(
    k: &Mat<f64>,
    m: &Mat<f64>,
    dofs: &[usize],
    ucf: f64,
) -> Vec<f64> {
    let n = dofs.len();
    if n == 0 {
        return Vec::new();
    }
    let mii = Mat::<f64>::from_fn(n, n, |i, j| m[(dofs[i], dofs[j])]);
    let kii = Mat::<f64>::from_fn(n, n, |i, j| k[(dofs[i], dofs[j])]);
    let Ok(me) = mii.self_adjoint_eigen(faer::Side::Lower) else {
        return Vec::new();
    };
    let (s, u) = (me.S(), me.U());
    if (0..n).any(|i| s[i] <= 0.0) {
        return Vec::new();
    }
    let w = Mat::<f64>::from_fn(n, n, |i, j| u[(i, j)] / s[j].sqrt());
    let a = w.transpose() * &kii * &w;
    let a = Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let Ok(ae) = a.self_adjoint_eigen(faer::Side::Lower) else {
        return Vec::new();
    };
    let l = ae.S();
    let mut f: Vec<f64> = (0..n)
        .map(|i| (ucf * l[i].max(0.0)).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    f
}
