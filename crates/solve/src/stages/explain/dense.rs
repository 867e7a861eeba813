//! Rank and left null space block by block, by a dense SVD where the block is small.
//!
//! The sparse greedy elimination of [`crate::pipeline::verify::rank_analysis`] decides exactly on the
//! axis-aligned poses models are usually written in, but at a generic pose (e.g. after the
//! random moves of [`super::generic`]) its threshold pivoting can leave rounding of order
//! 10⁻⁹ in a long loop — at the rank tolerance. The explanations compare ranks across poses
//! and models, so every block with at most [`DENSE_LIMIT`] columns is analysed by an SVD of
//! its scaled, row-normalised Jacobian (the same matrix the greedy analysis sees): the rank is
//! the number of singular values above `tolerance·σ_max`, the left null space is spanned by
//! the remaining left singular vectors. Larger blocks use the greedy analysis (rank, and the
//! null vectors `e_r − Σ c_k e_k` of its redundant rows).

use crate::constraints::graph::{Block, Topology};
use crate::constraints::rows::RowGradient;
use crate::constraints::system::System;
use crate::linalg::kkt::scaled_row;
use crate::pipeline::verify::rank_analysis;
use crate::state::State;
use crate::tolerances::Tolerances;
use crate::tolerances::NULL_VECTOR_ENTRY;

/// Largest block (Jacobian columns, 6 per part) analysed densely.
pub const DENSE_LIMIT: usize = 150;

/// Rank analysis of the blocks of a topology.
#[derive(Clone, Debug, Default)]
pub struct Analysis {
    pub rank: usize,
    /// Rank of each block, in the topology's order.
    pub block_rank: Vec<usize>,
    /// A basis of the left null space, as `(row, coefficient)` entries on the scaled rows.
    pub null: Vec<Vec<(usize, f64)>>,
    /// Smallest `σ_rank/σ_max` over the densely analysed blocks (`None` when none was).
    pub conditioning: Option<f64>,
}

/// Analyses every block of `topo` at state `s`.
pub fn analyse(
    sys: &System,
    s: &State,
    topo: &Topology,
    length: f64,
    tol: &Tolerances,
) -> Analysis {
    let mut out = Analysis::default();
    for blk in &topo.blocks {
        let (rank, null, cond) = match dense_block(sys, s, blk, length, tol) {
            Some(x) => x,
            None => {
                let one = Topology {
                    blocks: vec![blk.clone()],
                    ..Topology::default()
                };
                let ra = rank_analysis(sys, s, &one, length, tol);
                let null = super::reactions::null_basis(
                    ra.redundant.iter().map(|(r, _, d, _)| (*r, d.as_slice())),
                );
                (ra.rank, null, None)
            }
        };
        out.rank += rank;
        out.block_rank.push(rank);
        out.null.extend(null);
        if let Some(c) = cond {
            out.conditioning = Some(out.conditioning.map_or(c, |x: f64| x.min(c)));
        }
    }
    out
}

type BlockResult = (usize, Vec<Vec<(usize, f64)>>, Option<f64>);

fn dense_block(
    sys: &System,
    s: &State,
    blk: &Block,
    length: f64,
    tol: &Tolerances,
) -> Option<BlockResult> {
    let ncols = 6 * blk.parts.len();
    let rows: Vec<usize> = blk
        .elements
        .iter()
        .flat_map(|&e| sys.element_rows.get(e).cloned().unwrap_or(0..0))
        .collect();
    let m = rows.len();
    if ncols > DENSE_LIMIT || m > 2 * DENSE_LIMIT {
        return None;
    }
    if m == 0 {
        return Some((0, Vec::new(), None));
    }
    let mut dense = vec![0.0; m * ncols.max(1)];
    let mut g = RowGradient::default();
    let mut entries = Vec::new();
    for (k, &r) in rows.iter().enumerate() {
        sys.gradient(r, s, &mut g);
        let norm = scaled_row(&g, length, &mut entries);
        if norm <= 0.0 || !norm.is_finite() {
            continue;
        }
        for &(c, x) in &entries {
            if let Ok(p) = blk.parts.binary_search(&(c / 6)) {
                dense[k * ncols + 6 * p + c % 6] = x / norm;
            }
        }
    }
    if ncols == 0 {
        let null = rows.iter().map(|&r| vec![(r, 1.0)]).collect();
        return Some((0, null, None));
    }
    let a = faer::Mat::<f64>::from_fn(m, ncols, |i, j| dense[i * ncols + j]);
    let svd = a.svd().ok()?;
    let sv: Vec<f64> = (0..m.min(ncols)).map(|k| svd.S()[k]).collect();
    let smax = sv.first().copied().unwrap_or(0.0);
    let threshold = tol.rank * smax;
    let rank = sv.iter().filter(|&&x| smax > 0.0 && x > threshold).count();
    let u = svd.U();
    let mut null = Vec::with_capacity(m - rank);
    for k in rank..m {
        let col: Vec<(usize, f64)> = (0..m)
            .map(|i| (rows[i], u[(i, k)]))
            .filter(|(_, x)| x.abs() > NULL_VECTOR_ENTRY)
            .collect();
        null.push(col);
    }
    let cond = (rank > 0 && smax > 0.0).then(|| sv[rank - 1] / smax);
    Some((rank, null, cond))
}
