//! The friction coefficient as a function of the stiction deformation and the slip velocity:
//! Adams' three regimes (ADM-ELEMENTS §4.3) written as one continuous law.
//!
//! Slip quantities are vectors of 1 to 3 components at the contact surface, in length units:
//! the stiction deformation `s` (`|s| ≤ Δmax` between steps) and the slip velocity `v`.
//!
//! ```text
//! u   = μs·(s/Δmax + v/vs)                 (EFFECT = ALL or STICTION)
//! u   = μs·v/vs                            (EFFECT = SLIDING: no stiction deformation)
//! cap = μs                                  |v| ≤ vs            (stiction)
//!     = STEP(|v|, vs, μs, β·vs, μ_end)      vs < |v| < β·vs     (transition)
//!     = μ_end                               |v| ≥ β·vs          (dynamic)
//! μ   = −u                  when |u| ≤ cap
//!     = −cap·u/|u|          otherwise
//! ```
//!
//! with `μ_end = μd`, or 0 for EFFECT = STICTION (that effect keeps only the stiction
//! regime; the fade to zero over the transition is decided here, the reference is silent).
//! In stiction the joint is a spring of stiffness `μs·N/Δmax` and a damper `μs·N/vs` capped
//! at `μs·N`: it holds any load below `μs·N` with a deformation below Δmax, and slips above.
//! Sliding at `|v| ≥ β·vs`, the stiction deformation trails at `|s| = Δmax` in the direction
//! of slip (the anchor follows, [`super::FrictionState::accept`]), so `|u| > μs ≥ cap` and the
//! coefficient is `μd` opposite the slip. EFFECT = SLIDING replaces the stiction spring by a
//! steep viscous ramp through zero (μs at vs), as CONTACT friction does (§1.3, linear instead of
//! cubic: decided). The law is continuous in `s` and `v`.

use crate::physics::forces::algebra::Real;
use linkage_adm::FrictionEffect;

/// The coefficients of one friction (model units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Regime {
    pub mu_static: f64,
    pub mu_dynamic: f64,
    /// vs.
    pub stiction_velocity: f64,
    /// β.
    pub transition_coefficient: f64,
    /// Δmax.
    pub max_deformation: f64,
    pub effect: FrictionEffect,
}

/// Adams' cubic STEP: `h0` for x ≤ x0, `h1` for x ≥ x1, `h0 + (h1 − h0)·Δ²(3 − 2Δ)` between.
fn step<R: Real>(x: &R, x0: f64, h0: f64, x1: f64, h1: f64) -> R {
    if x.value() <= x0 {
        return R::cst(h0);
    }
    if x.value() >= x1 {
        return R::cst(h1);
    }
    let d = x.shift(-x0).scale(1.0 / (x1 - x0));
    let shape = d.mul(&d).mul(&d.scale(-2.0).shift(3.0));
    shape.scale(h1 - h0).shift(h0)
}

fn norm<R: Real>(x: &[R]) -> R {
    x.iter()
        .fold(R::cst(0.0), |acc, c| acc.add(&c.mul(c)))
        .sqrt()
}

/// `|x|` of the values alone.
fn magnitude<R: Real>(x: &[R]) -> f64 {
    x.iter().map(|c| c.value() * c.value()).sum::<f64>().sqrt()
}

impl Regime {
    /// The largest coefficient at slip speed `speed` (see the module docs).
    pub fn cap<R: Real>(&self, speed: &R) -> R {
        let vs = self.stiction_velocity;
        let end = match self.effect {
            FrictionEffect::Stiction => 0.0,
            _ => self.mu_dynamic,
        };
        step(
            speed,
            vs,
            self.mu_static,
            self.transition_coefficient * vs,
            end,
        )
    }

    /// μ (as many components as `v`): the coefficient vector opposing the slip, from the
    /// stiction deformation `s` and the slip velocity `v` (module docs).
    pub fn coefficient<R: Real>(&self, s: &[R], v: &[R], out: &mut [R]) {
        let (ms, vs, dmax) = (self.mu_static, self.stiction_velocity, self.max_deformation);
        let spring = !matches!(self.effect, FrictionEffect::Sliding);
        for ((o, s), v) in out.iter_mut().zip(s).zip(v) {
            let damper = v.scale(ms / vs);
            *o = if spring {
                damper.add(&s.scale(ms / dmax))
            } else {
                damper
            };
        }
        let cap = if magnitude(v) <= vs {
            R::cst(self.cap(&R::cst(0.0)).value())
        } else {
            self.cap(&norm(v))
        };
        if magnitude(out) > cap.value() {
            let factor = cap.div(&norm(out));
            for o in out.iter_mut() {
                *o = o.mul(&factor);
            }
        }
        for o in out.iter_mut() {
            *o = o.neg();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use linkage_expr::Dual;

    const REGIME: Regime = Regime {
        mu_static: 0.5,
        mu_dynamic: 0.3,
        stiction_velocity: 0.1,
        transition_coefficient: 1.5,
        max_deformation: 0.01,
        effect: FrictionEffect::All,
    };

    fn mu(r: &Regime, s: f64, v: f64) -> f64 {
        let mut out = [0.0];
        r.coefficient(&[s], &[v], &mut out);
        out[0]
    }

    /// The three regimes: μs·s/Δmax in stiction at rest, μs at vs with the deformation
    /// trailing, the cubic STEP halfway through the transition, μd beyond β·vs.
    #[test]
    fn the_coefficient_follows_the_three_regimes() {
        assert!((mu(&REGIME, 0.004, 0.0) + 0.2).abs() < 1e-15);
        assert!((mu(&REGIME, -0.004, 0.0) - 0.2).abs() < 1e-15);
        assert!((mu(&REGIME, 0.01, 0.1) + 0.5).abs() < 1e-15);
        // Halfway: STEP = (μs + μd)/2.
        assert!((mu(&REGIME, 0.01, 0.125) + 0.4).abs() < 1e-12);
        assert!((mu(&REGIME, 0.01, 0.2) + 0.3).abs() < 1e-15);
        assert!((mu(&REGIME, -0.01, -3.0) - 0.3).abs() < 1e-15);
        let stiction = Regime {
            effect: FrictionEffect::Stiction,
            ..REGIME
        };
        assert_eq!(mu(&stiction, 0.01, 0.2), 0.0);
        assert!((mu(&stiction, 0.002, 0.0) + 0.1).abs() < 1e-15);
        let sliding = Regime {
            effect: FrictionEffect::Sliding,
            ..REGIME
        };
        assert_eq!(mu(&sliding, 0.01, 0.0), 0.0);
        assert!((mu(&sliding, 0.0, 0.05) + 0.25).abs() < 1e-15);
        assert!((mu(&sliding, 0.0, 1.0) + 0.3).abs() < 1e-15);
    }

    /// In 2-D the coefficient saturates on the magnitude, opposite the combined slip.
    #[test]
    fn a_vector_slip_saturates_on_its_magnitude() {
        let mut out = [0.0; 2];
        REGIME.coefficient(&[0.006, 0.008], &[3.0, 4.0], &mut out);
        assert!((out[0] + 0.3 * 0.6).abs() < 1e-3, "{out:?}");
        assert!((out[1] + 0.3 * 0.8).abs() < 1e-3, "{out:?}");
        assert!(((out[0] * out[0] + out[1] * out[1]).sqrt() - 0.3).abs() < 1e-15);
    }

    /// The derivative of the dual evaluation agrees with central differences in every regime.
    #[test]
    fn dual_derivatives_match_differences() {
        for (s, v) in [(0.003, 0.02), (0.01, 0.12), (0.01, 0.14), (-0.002, -0.03)] {
            let mut out = [Dual::cst(0.0)];
            REGIME.coefficient(&[Dual::variable(s, 0)], &[Dual::variable(v, 1)], &mut out);
            let h = 1e-7;
            let ds = (mu(&REGIME, s + h, v) - mu(&REGIME, s - h, v)) / (2.0 * h);
            let dv = (mu(&REGIME, s, v + h) - mu(&REGIME, s, v - h)) / (2.0 * h);
            assert!(
                (out[0].derivative(0) - ds).abs() < 1e-5 * ds.abs().max(1.0),
                "{s} {v}"
            );
            assert!(
                (out[0].derivative(1) - dv).abs() < 1e-5 * dv.abs().max(1.0),
                "{s} {v}"
            );
        }
    }
}
