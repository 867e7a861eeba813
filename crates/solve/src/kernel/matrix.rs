//! Assembly of the corrector's scaled iteration matrix, and the pieces it shares with the
//! consistent-output matrix: the mass blocks and the growing sparsity pattern.

use super::error::{IntegrationError, MatrixRole};
use super::problem::{ExtraDamping, Problem};
use crate::constraints::hessian::HessianBlocks;
use crate::constraints::rows::{RowGradient, Velocities};
use crate::linalg::kkt::{self, PatternError};
use crate::linalg::linear::FixedPatternLu;
use crate::physics::mass;
use crate::state::State;

/// An empty `dim × dim` matrix whose pattern is the diagonal (it grows on first assembly).
pub(crate) fn diagonal(dim: usize) -> Result<FixedPatternLu, IntegrationError> {
    FixedPatternLu::new(dim, (0..dim).map(|i| (i, i))).map_err(|cause| IntegrationError::Setup {
        matrix: MatrixRole::Both,
        cause,
    })
}

/// Assembles `a` with `fill` until no entry falls outside its pattern
/// ([`kkt::assemble_growing`]): the pattern starts as the diagonal, the first assembly grows
/// it to the entries that are nonzero there, and an entry that becomes nonzero later grows it
/// once more; a planar mechanism thus keeps a planar pattern. Returns whether the pattern
/// grew; a failure names the matrix `what`.
pub(crate) fn assemble_growing(
    a: &mut FixedPatternLu,
    what: MatrixRole,
    fill: impl FnMut(&mut FixedPatternLu),
) -> Result<bool, IntegrationError> {
    kkt::assemble_growing(a, fill).map_err(|e| match e {
        PatternError::Grow(cause) => IntegrationError::Setup {
            matrix: what,
            cause,
        },
        PatternError::Unsettled => IntegrationError::PatternUnsettled(what),
    })
}

/// Adds the mass blocks `m·𝟙` and `I_g = R I Rᵀ` ([`mass::ground_inertia`]) of every part to
/// `matrix` ([`kkt::add_part_mass_blocks`]), and the flex bodies' inertia coupling
/// ([`crate::physics::flex_inertia`], each 3 × 3 block claiming its place even where it is
/// zero); `rotational(k)` is added to the diagonal of part k's rotational block
/// (regularisation of the projection).
pub(crate) fn add_mass(
    p: &Problem,
    s: &State,
    matrix: &mut FixedPatternLu,
    rotational: impl Fn(usize) -> f64,
) {
    for (k, part) in p.model.parts.iter().enumerate() {
        let ig = mass::ground_inertia(part, &s.poses[k]);
        kkt::add_part_mass_blocks(matrix, k, part.mass, &ig, rotational(k));
    }
    p.coupling.blocks(s, |r, c, b| {
        matrix.add_block((r, c), (3, 3), 0.0, |_, _| 1.0);
        matrix.add_block((r, c), (3, 3), 1.0, |i, j| b.col(j)[i]);
    });
}

/// Coefficients of the scaled iteration matrix
/// `[M + stiffness·K_T + damping·C_T, multiplier·UCF·Jᵀ; J, 0]`; for HHT-α with step h:
/// `(1+α)βh²`, `(1+α)γh` and `1+α`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MatrixCoefficients {
    pub stiffness: f64,
    pub damping: f64,
    pub multiplier: f64,
}

/// The iterate the matrix is assembled at: positions (and time), velocities, the kept rows'
/// gradients at `s` and their multipliers (force units).
pub(crate) struct Iterate<'i> {
    pub s: &'i State,
    pub v: &'i Velocities,
    pub grads: &'i [RowGradient],
    pub lambda: &'i [f64],
}

/// The corrector's iteration matrix in a [`FixedPatternLu`], with the buffers of its assembly
/// and the step size it was last factorised for.
pub(crate) struct IterationMatrix {
    pub lu: FixedPatternLu,
    /// The step size of the valid factorisation (`None`: none valid).
    pub h: Option<f64>,
    /// Counts the changes of the pattern (matrices copying it compare this).
    pub pattern: u64,
    hessian: HessianBlocks,
    /// Force Jacobians `∂Q/∂q`, `∂Q/∂v` as triplets.
    dq: Vec<(usize, usize, f64)>,
    dv: Vec<(usize, usize, f64)>,
    /// The control states' Jacobian `∂r/∂(q, v, x, ẋ)` and `∂Q/∂(x, ẋ)` as triplets.
    dr: Vec<(usize, usize, f64)>,
    dqx: Vec<(usize, usize, f64)>,
    /// The state force elements see when time is frozen.
    force_state: State,
}

impl IterationMatrix {
    /// An unassembled matrix for `p` (diagonal pattern); `like` sizes the frozen-time state.
    pub(crate) fn new(p: &Problem, like: &State) -> Result<IterationMatrix, IntegrationError> {
        Ok(IterationMatrix {
            lu: diagonal(6 * p.n() + p.rows.len() + p.controls())?,
            h: None,
            pattern: 0,
            hessian: HessianBlocks::default(),
            dq: Vec::new(),
            dv: Vec::new(),
            dr: Vec::new(),
            dqx: Vec::new(),
            force_state: like.clone(),
        })
    }

    /// Assembles the values of the scaled iteration matrix (its pattern grows on first use,
    /// see [`assemble_growing`])
    ///
    /// ```text
    /// [M + stiffness·K_T + damping·C_T    multiplier·UCF·Jᵀ]
    /// [J                                  0                ]
    /// ```
    ///
    /// with `K_T = −UCF·∂Q/∂q + UCF·Σλ ∂²Φ/∂q²` (geometric stiffness of the kept rows' terms),
    /// bordered by the control states' rows and columns (unknowns ẋ after the multipliers):
    /// `∂r/∂q·p + ∂r/∂v·d` in the acceleration columns, `∂r/∂x·d + ∂r/∂ẋ` in the rate
    /// columns (p = stiffness/multiplier = ∂q/∂a, d = damping/multiplier = ∂v/∂a = ∂x/∂ẋ),
    /// and `−multiplier·UCF·(∂Q/∂x·d + ∂Q/∂ẋ)` in the equations of motion,
    /// `C_T = −UCF·∂Q/∂v` (+ the extra damping), at the iterate `at`. A row's second
    /// derivatives claim their places in the pattern even while its multiplier is zero.
    /// Cost: the force Jacobians and the rows' Hessians, O(rows + parts) for a chain.
    pub(crate) fn assemble(
        &mut self,
        p: &Problem,
        at: &Iterate,
        c: MatrixCoefficients,
    ) -> Result<(), IntegrationError> {
        let n = p.n();
        let ucf = p.model.ucf();
        let s = at.s;
        let (kq, kv) = (c.stiffness, c.damping);
        self.dq.clear();
        self.dv.clear();
        p.forces.add_jacobians(
            p.regime,
            p.force_state(s, &mut self.force_state),
            at.v,
            &mut self.dq,
            Some(&mut self.dv),
        )?;
        let nx = p.controls();
        self.dr.clear();
        self.dqx.clear();
        if nx > 0 {
            let fs = p.force_state(s, &mut self.force_state);
            p.forces.control_jacobian(fs, at.v, &mut self.dr)?;
            p.forces
                .add_control_force_jacobian(p.regime, fs, at.v, &mut self.dqx)?;
        }
        let base = 6 * n + p.rows.len();
        let (to_q, to_v) = (kq / c.multiplier, kv / c.multiplier);
        let (dr, dqx) = (&self.dr, &self.dqx);
        let (dq, dv, hessian) = (&self.dq, &self.dv, &mut self.hessian);
        let grew = assemble_growing(&mut self.lu, MatrixRole::Newton, |a| {
            for &(i, var, d) in dr {
                let row = base + i;
                match var {
                    v if v < 6 * n => a.add(row, v, d * to_q),
                    v if v < 12 * n => a.add(row, v - 6 * n, d * to_v),
                    v if v < 12 * n + nx => a.add(row, base + v - 12 * n, d * to_v),
                    v => a.add(row, base + v - 12 * n - nx, d),
                }
            }
            for &(row, col, d) in dqx {
                let (col, f) = if col < nx {
                    (base + col, to_v)
                } else {
                    (base + col - nx, 1.0)
                };
                a.add(row, col, -ucf * c.multiplier * d * f);
            }
            add_mass(p, s, a, |_| 0.0);
            for &(i, j, x) in dq {
                a.add(i, j, -ucf * x * kq);
            }
            for &(i, j, x) in dv {
                a.add(i, j, -ucf * x * kv);
            }
            if let Some(ExtraDamping(damping)) = p.damping {
                for (k, part) in p.model.parts.iter().enumerate() {
                    let ig = mass::ground_inertia(part, &s.poses[k]);
                    let m = |i: usize, j: usize| if i == j { part.mass } else { 0.0 };
                    a.add_block((6 * k, 6 * k), (3, 3), damping * kv, m);
                    a.add_block((6 * k + 3, 6 * k + 3), (3, 3), damping * kv, |i, j| {
                        ig.col(j)[i]
                    });
                }
            }
            for (k, &r) in p.rows.iter().enumerate() {
                hessian.clear();
                p.sys.hessian(r, s, 1.0, hessian);
                let f = ucf * at.lambda[k] * kq;
                for &(br, rs, bc, cs, m) in &hessian.blocks {
                    a.add_block((6 * br + 3 * rs, 6 * bc + 3 * cs), (3, 3), f, |i, j| {
                        m.col(j)[i]
                    });
                }
                kkt::add_constraint_row_blocks(a, 6 * n, k, &at.grads[k], c.multiplier * ucf);
            }
        })?;
        if grew {
            self.pattern += 1;
        }
        Ok(())
    }

    /// Assembles and factorises at `at` for a step of coefficients `c`.
    pub(crate) fn refresh(
        &mut self,
        p: &Problem,
        at: &Iterate,
        c: MatrixCoefficients,
    ) -> Result<(), IntegrationError> {
        self.assemble(p, at, c)?;
        self.lu
            .factor()
            .map_err(IntegrationError::NewtonFactorisation)
    }
}

/// The step size the pattern-finding assembly uses: only which entries are nonzero matters
/// there, and any positive step size gives the same entries.
const PATTERN_PROBE_STEP: f64 = 1e-3;

impl IterationMatrix {
    /// A matrix for `p` whose pattern is found by assembling it at `start` with velocities
    /// `v0` (one per part) and zero multipliers (the rows' second derivatives claim their
    /// places all the same); `coefficients(h)` gives the matrix coefficients of step size h.
    pub(crate) fn with_pattern(
        p: &Problem,
        start: &State,
        v0: &Velocities,
        coefficients: impl Fn(f64) -> MatrixCoefficients,
    ) -> Result<IterationMatrix, IntegrationError> {
        let mut matrix = IterationMatrix::new(p, start)?;
        let mut grads = vec![RowGradient::default(); p.rows.len()];
        p.gradients(start, &mut grads);
        let lambda = vec![0.0; p.rows.len()];
        let at = Iterate {
            s: start,
            v: v0,
            grads: &grads,
            lambda: &lambda,
        };
        matrix.assemble(p, &at, coefficients(PATTERN_PROBE_STEP))?;
        Ok(matrix)
    }
}
