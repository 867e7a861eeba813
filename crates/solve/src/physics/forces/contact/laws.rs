//! The force laws of a contact incident, generic over [`Real`] (exact Jacobians with `Dual`).
//!
//! With g the penetration (> 0) and ġ its rate (> 0 while the bodies approach), and the cubic
//! `STEP(x, x0, h0, x1, h1)` of ADM-ELEMENTS (the Adams STEP):
//!
//! - IMPACT (ADM-ELEMENTS §1.1): `Fn = k·g^e + STEP(g, 0, 0, dmax, c)·ġ`;
//! - POISSON (§1.2, no Adams text found: a decision, `[unconfirmed]`): a penalty spring fully
//!   active while the penetration grows and at `ε²` of its stiffness while it shrinks, blended
//!   over `|ġ| < vn`: `Fn = p·g·STEP(ġ, −vn, ε², vn, 1)`. Loading stores `½·p·g_max²`,
//!   unloading returns `ε²` of it, so the separation speed is ε times the approach speed
//!   (when the contact is short against gravity and `vn` small against the speeds);
//!
//! both clamped to `Fn ≥ 0` (no adhesion: the max(0, ·) of the IMPACT function).
//!
//! Coulomb friction (§1.3): the coefficient as a function of the slip speed `s ≥ 0`:
//! `μ(s) = STEP(s, −vs, −μs, vs, μs)` for `s < vs`, `STEP(s, vs, μs, vd, μd)` for
//! `vs ≤ s < vd`, `μd` beyond; the force on I is `−μ(s)·Fn·v_t/s` with `v_t` the slip velocity
//! of I on J. `μ(s)/s` is taken as its limit `1.5·μs/vs` (the slope of the STEP at 0) when
//! `s` is below [`SLIP_AT_REST`]·vs, so the law is smooth through rest.

use super::super::algebra::{Real, V3};
use linkage_adm::contact::{Friction, FrictionMode, NormalLaw};

/// Slip speeds below this fraction of the stiction transition velocity are rest for the
/// direction of the friction force (its limit `μ(s)/s → 1.5·μs/vs` is used).
pub const SLIP_AT_REST: f64 = 1e-9;

/// The Adams STEP function of a [`Real`] argument (constant ends).
pub fn step<R: Real>(x: &R, x0: f64, h0: f64, x1: f64, h1: f64) -> R {
    let v = x.value();
    if v <= x0 {
        return R::cst(h0);
    }
    if v >= x1 {
        return R::cst(h1);
    }
    let w = x1 - x0;
    let d = (v - x0) / w;
    let a = h1 - h0;
    let value = h0 + a * d * d * (3.0 - 2.0 * d);
    let slope = a * 6.0 * d * (1.0 - d) / w;
    x.chain(value, slope)
}

/// `x^e` for `x > 0`.
pub fn pow<R: Real>(x: &R, e: f64) -> R {
    let v = x.value();
    x.chain(v.powf(e), e * v.powf(e - 1.0))
}

/// The exponent that shares an incident's force among its points (`g_k^e`): the IMPACT
/// exponent, 1 for POISSON.
pub fn share_exponent(law: &NormalLaw) -> f64 {
    match law {
        NormalLaw::Impact { exponent, .. } => *exponent,
        _ => 1.0,
    }
}

/// The normal force of an incident with penetration `g > 0` and rate `gdot` (module docs).
pub fn normal_force<R: Real>(law: &NormalLaw, g: &R, gdot: &R) -> R {
    let f = match law {
        NormalLaw::Impact {
            stiffness,
            damping,
            dmax,
            exponent,
        } => pow(g, *exponent)
            .scale(*stiffness)
            .add(&step(g, 0.0, 0.0, *dmax, *damping).mul(gdot)),
        NormalLaw::Poisson {
            penalty,
            restitution,
            transition_velocity: vn,
        } => g
            .scale(*penalty)
            .mul(&step(gdot, -vn, restitution * restitution, *vn, 1.0)),
        NormalLaw::User { .. } => R::cst(0.0),
    };
    if f.value() > 0.0 {
        f
    } else {
        R::cst(0.0)
    }
}

/// The magnitude of the friction coefficient at slip speed `s ≥ 0`.
pub fn mu<R: Real>(f: &Friction, s: &R) -> R {
    let (vs, vd) = (f.stiction_velocity, f.friction_velocity);
    let v = s.value();
    if v < vs {
        step(s, -vs, -f.mu_static, vs, f.mu_static)
    } else if v < vd {
        step(s, vs, f.mu_static, vd, f.mu_dynamic)
    } else {
        R::cst(f.mu_dynamic)
    }
}

/// The friction force on I for normal force `fn_` and slip velocity `v_t` of I on J
/// (tangential), or `None` without friction.
pub fn friction_force<R: Real>(f: &Friction, fn_: &R, v_t: &V3<R>) -> Option<V3<R>> {
    if f.mode == FrictionMode::Off {
        return None;
    }
    let s2 = v_t.dot(v_t);
    let ratio = if s2.value().sqrt() < SLIP_AT_REST * f.stiction_velocity {
        R::cst(1.5 * f.mu_static / f.stiction_velocity)
    } else {
        let s = s2.sqrt();
        mu(f, &s).div(&s)
    };
    Some(v_t.times(&ratio.mul(fn_)).neg())
}

#[cfg(test)]
mod tests {
    use super::*;
    use linkage_expr::Dual;

    fn coulomb() -> Friction {
        Friction {
            mode: FrictionMode::On,
            mu_static: 0.5,
            mu_dynamic: 0.3,
            stiction_velocity: 0.1,
            friction_velocity: 1.0,
            user: None,
        }
    }

    #[test]
    fn step_matches_the_documented_values_and_slope() {
        // STEP(x, 3, 0, 4, 1) at x = 2, 3, 3.5, 4, 5 → 0, 0, 0.5, 1, 1 (ADM-ELEMENTS).
        let got: Vec<f64> = [2.0, 3.0, 3.5, 4.0, 5.0]
            .iter()
            .map(|x| step(x, 3.0, 0.0, 4.0, 1.0))
            .collect();
        assert_eq!(got, [0.0, 0.0, 0.5, 1.0, 1.0]);
        let d = step(&Dual::variable(3.5, 0), 3.0, 0.0, 4.0, 1.0);
        assert!((d.derivative(0) - 1.5).abs() < 1e-15);
    }

    #[test]
    fn impact_law_has_its_spring_and_ramped_damping() {
        let law = NormalLaw::Impact {
            stiffness: 1e5,
            damping: 10.0,
            dmax: 0.1,
            exponent: 2.0,
        };
        // Below DMAX the damping is ramped: at g = dmax/2, STEP = c/2.
        let f: f64 = normal_force(&law, &0.05, &2.0);
        assert!((f - (1e5 * 0.0025 + 5.0 * 2.0)).abs() < 1e-9, "{f}");
        // Full damping beyond DMAX; never pulling.
        let f: f64 = normal_force(&law, &0.2, &1.0);
        assert!((f - (1e5 * 0.04 + 10.0)).abs() < 1e-9);
        let f: f64 = normal_force(&law, &0.2, &-1e4);
        assert_eq!(f, 0.0);
    }

    #[test]
    fn poisson_law_unloads_at_restitution_squared() {
        let law = NormalLaw::Poisson {
            penalty: 100.0,
            restitution: 0.5,
            transition_velocity: 1e-3,
        };
        let load: f64 = normal_force(&law, &0.01, &1.0);
        let unload: f64 = normal_force(&law, &0.01, &-1.0);
        assert!((load - 1.0).abs() < 1e-12);
        assert!((unload - 0.25).abs() < 1e-12);
    }

    #[test]
    fn friction_coefficient_passes_through_its_documented_points() {
        let f = coulomb();
        for (s, want) in [(0.0, 0.0), (0.1, 0.5), (0.55, 0.4), (1.0, 0.3), (5.0, 0.3)] {
            let got: f64 = mu(&f, &s);
            assert!((got - want).abs() < 1e-12, "μ({s}) = {got}, want {want}");
        }
        // Opposes the slip, proportional to the normal force.
        let v = V3::<f64>::constant(glam::DVec3::new(3.0, 4.0, 0.0));
        let ft = friction_force(&f, &10.0, &v).expect("on");
        assert!((ft.value() - glam::DVec3::new(-1.8, -2.4, 0.0)).length() < 1e-12);
        // At rest the direction is the slope's limit: zero force, finite derivative.
        let z = V3::<f64>::constant(glam::DVec3::ZERO);
        assert_eq!(
            friction_force(&f, &10.0, &z).expect("on").value(),
            glam::DVec3::ZERO
        );
    }
}
