//! A cart on a straight rail with an inverted pendulum on it, released 5° from upright (the
//! shape of corpus `yriyazi…validation__Matlab.adm`, in SI units), and its reference solution
//! from the Lagrange equations integrated by RK4.
//!
//! Cart mass `M` along global x, pendulum mass `m` with its CM at `l` from the pivot and
//! moment of inertia `I` about its CM (axis z), angle `θ` from upright (counterclockwise):
//!
//! ```text
//! (M + m) ẍ − m l cos θ θ̈ + m l sin θ θ̇² = 0
//! −m l cos θ ẍ + (I + m l²) θ̈ = m g l sin θ
//! ```
//!
//! The pendulum falls, swings through the bottom and climbs back almost to upright on the
//! other side, near its separatrix: the period depends on the energy logarithmically, so the
//! run shows every energy error of an integrator as a phase error of the cart's velocity.

pub const CART_MASS: f64 = 124.816;
pub const BOB_MASS: f64 = 36.61408371;
pub const BOB_ARM: f64 = 0.6;
pub const BOB_INERTIA: f64 = 0.5781627155;
pub const GRAVITY: f64 = 9.80665;
pub const START_DEG: f64 = 5.0;

/// The dataset in metres: cart PART/2 (its CM at the origin), pendulum PART/3; TRANSLATIONAL
/// joint along x to ground, REVOLUTE about z at the cart's CM.
pub fn dataset() -> String {
    dataset_in(false)
}

/// [`dataset`], in millimetres when `mm` (as the corpus model is written).
pub fn dataset_in(mm: bool) -> String {
    let (unit, k) = if mm {
        ("MILLIMETER", 1e3)
    } else {
        ("METER", 1.0)
    };
    let (s, c) = START_DEG.to_radians().sin_cos();
    let (x, y) = (-BOB_ARM * s * k, BOB_ARM * c * k);
    let i = BOB_INERTIA * k * k;
    let (ci, g, ri) = (
        [7.07 * k * k, 6.76 * k * k, 0.52 * k * k],
        GRAVITY * k,
        0.13 * k * k,
    );
    format!(
        "cart pendulum\n\
UNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = {unit}, TIME = SECOND\n\
ACCGRAV/, JGRAV = -{g}\n\
PART/1, GROUND\n\
MARKER/8, PART = 1, REULER = 90D, 90D, 0D\n\
PART/2, MASS = {CART_MASS}, CM = 9, IP = {}, {}, {}\n\
MARKER/9, PART = 2\n\
MARKER/7, PART = 2, REULER = 90D, 90D, 0D\n\
MARKER/6, PART = 2\n\
PART/3, MASS = {BOB_MASS}, CM = 10, IP = {i}, {ri}, {i}\n\
MARKER/5, PART = 3\n\
MARKER/10, PART = 3, QP = {x}, {y}, 0\n\
JOINT/1, REVOLUTE, I = 5, J = 6\n\
JOINT/2, TRANSLATIONAL, I = 7, J = 8\n\
END\n",
        ci[0], ci[1], ci[2]
    )
}

/// Cart position and velocity at `outputs + 1` equal times over `[0, end]` (RK4, 2000 steps
/// per output: steps of 5e-6 s over 10 s; its error is far below what the tests ask).
pub fn reference(end: f64, outputs: usize) -> Vec<(f64, f64)> {
    let (big, m, l, i, g) = (CART_MASS, BOB_MASS, BOB_ARM, BOB_INERTIA, GRAVITY);
    // State [x, θ, ẋ, θ̇].
    let rate = |y: [f64; 4]| {
        let (s, c) = y[1].sin_cos();
        // [[M+m, −m l c], [−m l c, I + m l²]] [ẍ, θ̈] = [−m l s θ̇², m g l s]
        let (a, b, d) = (big + m, -m * l * c, i + m * l * l);
        let (r1, r2) = (-m * l * s * y[3] * y[3], m * g * l * s);
        let det = a * d - b * b;
        [y[2], y[3], (d * r1 - b * r2) / det, (a * r2 - b * r1) / det]
    };
    let every = 2000;
    let h = end / (outputs * every) as f64;
    let mut y = [0.0, START_DEG.to_radians(), 0.0, 0.0];
    let mut out = vec![(y[0], y[2])];
    let add = |y: [f64; 4], k: [f64; 4], f: f64| std::array::from_fn(|j| y[j] + f * k[j]);
    for step in 0..outputs * every {
        let k1 = rate(y);
        let k2 = rate(add(y, k1, h / 2.0));
        let k3 = rate(add(y, k2, h / 2.0));
        let k4 = rate(add(y, k3, h));
        y = std::array::from_fn(|j| y[j] + h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]));
        if (step + 1) % every == 0 {
            out.push((y[0], y[2]));
        }
    }
    out
}
