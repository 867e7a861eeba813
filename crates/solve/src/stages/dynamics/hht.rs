//! The HHT-α method's coefficients (Negrut, Rampalli, Ottarsson, Sajdak 2007).

use crate::kernel::matrix::MatrixCoefficients;
use crate::tolerances::HHT_UNDAMPED_RADIUS;

/// HHT-α coefficients: `β = (1−α)²/4`, `γ = 1/2 − α`, with `α ∈ [−1/3, 0]`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Hht {
    pub alpha: f64,
    pub beta: f64,
    pub gamma: f64,
}

impl Hht {
    /// The coefficients of `alpha`, clamped to `[−1/3, 0]`.
    pub(super) fn new(alpha: f64) -> Hht {
        let alpha = alpha.clamp(-1.0 / 3.0, 0.0);
        Hht {
            alpha,
            beta: (1.0 - alpha).powi(2) / 4.0,
            gamma: 0.5 - alpha,
        }
    }

    /// Whether the alternating mode of the index-3 form is left (nearly) undamped: the
    /// spectral radius at infinity `ρ∞ = (1+α)/(1−α)` is above `HHT_UNDAMPED_RADIUS` (α
    /// above about −0.005). Such a step projects its velocities onto the velocity
    /// constraints ([`super::corrector::project_velocities`]).
    pub(super) fn undamped(self) -> bool {
        (1.0 + self.alpha) / (1.0 - self.alpha) > HHT_UNDAMPED_RADIUS
    }

    /// The iteration matrix's coefficients for step size `h`: `(1+α)βh²` on the stiffness,
    /// `(1+α)γh` on the damping, `1+α` on the multipliers.
    pub(super) fn matrix_coefficients(self, h: f64) -> MatrixCoefficients {
        let Hht { alpha, beta, gamma } = self;
        MatrixCoefficients {
            stiffness: (1.0 + alpha) * beta * h * h,
            damping: (1.0 + alpha) * gamma * h,
            multiplier: 1.0 + alpha,
        }
    }
}
