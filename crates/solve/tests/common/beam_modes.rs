//! The uniform Euler–Bernoulli beam the FLEX_BODY tests build their modal data from:
//! cantilever modes `φ = cosh βx − cos βx − σ(sinh βx − sin βx)`, free-free modes
//! `φ = cosh βx + cos βx − σ(sinh βx + sin βx)`, both normalised to `∫₀ᴸ φ² dx = L`, so the
//! generalized mass is `ρAL` and the modal stiffness `(βL)⁴·EI/L³`.
//!
//! Beam (as the FE_PART tests): steel, L = 1 m, 10 mm square: E = 2.1e11 Pa,
//! ρ = 7800 kg/m³, A = 1e-4 m², I = b⁴/12.
//! βL of the cantilever: 1.875104, 4.694091, 7.854757, 10.995541, 14.137168; of the free-free
//! beam: 4.730041, 7.853205, 10.995608 (Blevins, Formulas for Natural Frequency and Mode
//! Shape, table 8-1).
#![allow(dead_code)]

use std::fmt::Write;

pub const E: f64 = 2.1e11;
pub const RHO: f64 = 7800.0;
pub const B: f64 = 0.01;
pub const L: f64 = 1.0;

pub const CANTILEVER: [f64; 5] = [1.875104, 4.694091, 7.854757, 10.995541, 14.137168];
pub const FREE_FREE: [f64; 3] = [4.730041, 7.853205, 10.995608];

pub fn area() -> f64 {
    B * B
}

pub fn second_moment() -> f64 {
    B.powi(4) / 12.0
}

/// `√(EI/(ρAL⁴))` (rad/s per unit (βL)²).
pub fn beam_scale() -> f64 {
    (E * second_moment() / (RHO * area() * L.powi(4))).sqrt()
}

/// `∫₀ᴸ φ dx` of a beam mode (cantilever or free-free; zero for a free-free elastic mode).
pub fn mode_integral(bl: f64, free: bool) -> f64 {
    let b = bl / L;
    let (ch, c, sh, s) = (bl.cosh(), bl.cos(), bl.sinh(), bl.sin());
    if free {
        let sigma = (ch - c) / (sh - s);
        (sh + s - sigma * (ch - c)) / b
    } else {
        let sigma = (ch + c) / (sh + s);
        (sh - s - sigma * (ch + c - 2.0)) / b
    }
}

/// A beam mode: `φ(x)` and `φ'(x)` for `βL` (cantilever or free-free).
pub fn mode(bl: f64, free: bool, x: f64) -> (f64, f64) {
    let b = bl / L;
    let (ch, c, sh, s) = (bl.cosh(), bl.cos(), bl.sinh(), bl.sin());
    let bx = b * x;
    if free {
        let sigma = (ch - c) / (sh - s);
        (
            bx.cosh() + bx.cos() - sigma * (bx.sinh() + bx.sin()),
            b * (bx.sinh() - bx.sin() - sigma * (bx.cosh() + bx.cos())),
        )
    } else {
        let sigma = (ch + c) / (sh + s);
        (
            bx.cosh() - bx.cos() - sigma * (bx.sinh() - bx.sin()),
            b * (bx.sinh() + bx.sin() - sigma * (bx.cosh() - bx.cos())),
        )
    }
}

/// A MATRIX statement named `FLEX_BODY_1.<name>` (row-major values).
pub fn matrix(out: &mut String, id: u64, name: &str, rows: usize, cols: usize, values: &[f64]) {
    let v: Vec<String> = values.iter().map(|x| format!("{x:e}")).collect();
    let _ = writeln!(
        out,
        "!adams_view_name='FLEX_BODY_1.{name}'\nMATRIX/{id}, FULL = RORDER, ROWS = {rows}, \
         COLUMNS = {cols}\n, VALUES = {}",
        v.join(", ")
    );
}

/// Gauss–Legendre points and weights on `[0, len]` (`n` points; Newton on `P_n`).
pub fn gauss_legendre(n: usize, len: f64) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_n'(x) by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / dp;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            (0.5 * len * (x + 1.0), 0.5 * len * w)
        })
        .collect()
}
