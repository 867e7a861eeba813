//! Generated datasets of growing size, for benchmarks and scaling tests.
//!
//! Each generator returns dataset text (`.adm`) so that benchmarks and tests exercise the whole
//! path a user's file takes.

use std::fmt::Write;

/// A chain of `n` planar parallelogram four-bars sharing their cranks: ground pivots at
/// x = 0, 1, …, n (metres), n + 1 cranks of length 1 at `crank_deg` from the x axis, and n
/// couplers joining neighbouring crank tips; every joint a revolute about global z.
///
/// 2n + 1 moving parts, 3n + 1 revolutes (15n + 5 rows): Gruebler 1 − 3n, DOF 1, and 3n
/// redundant equations (three per planar loop); the whole chain is one closed-loop block.
pub fn parallelogram_chain(n: usize, crank_deg: f64) -> String {
    let (s, c) = crank_deg.to_radians().sin_cos();
    let mut t = String::with_capacity(600 * (2 * n + 1));
    let _ = writeln!(t, "Adams View model name: parallelogram_chain_{n}");
    t.push_str("UNITS/\n, FORCE = NEWTON\n, MASS = KILOGRAM\n, LENGTH = METER\n, TIME = SECOND\n");
    t.push_str("ACCGRAV/\n, JGRAV = -9.80665\n");
    t.push_str("PART/1\n, GROUND\n");
    // Ground pivots: markers 1 + k.
    for k in 0..=n {
        let _ = writeln!(t, "MARKER/{}, PART = 1, QP = {k}, 0, 0", 1 + k);
    }
    // Cranks: part 2 + k; markers 10_000 + 10k + {0: base, 1: tip, 2: cm}.
    for k in 0..=n {
        let (p, m) = (2 + k, 100_000 + 10 * k);
        let x = k as f64;
        let _ = writeln!(t, "!                  adams_view_name='crank_{k}'");
        let _ = writeln!(
            t,
            "PART/{p}, MASS = 1, CM = {}, IP = 0.0833333333333, 0.0833333333333, 0.001",
            m + 2
        );
        let _ = writeln!(t, "MARKER/{m}, PART = {p}, QP = {x}, 0, 0");
        let _ = writeln!(t, "MARKER/{}, PART = {p}, QP = {}, {s}, 0", m + 1, x + c);
        // CM marker z along the rod (IP's third value is the axial moment).
        let _ = writeln!(
            t,
            "MARKER/{}, PART = {p}, QP = {}, {}, 0, REULER = {}D, 90D, 0D",
            m + 2,
            x + c / 2.0,
            s / 2.0,
            crank_deg - 90.0
        );
    }
    // Couplers: part 2 + (n + 1) + k; markers 500_000 + 10k + {0: left, 1: right, 2: cm}.
    for k in 0..n {
        let (p, m) = (3 + n + k, 500_000 + 10 * k);
        let x = k as f64 + c;
        let _ = writeln!(t, "!                  adams_view_name='coupler_{k}'");
        let _ = writeln!(
            t,
            "PART/{p}, MASS = 1, CM = {}, IP = 0.001, 0.0833333333333, 0.0833333333333",
            m + 2
        );
        let _ = writeln!(t, "MARKER/{m}, PART = {p}, QP = {x}, {s}, 0");
        let _ = writeln!(t, "MARKER/{}, PART = {p}, QP = {}, {s}, 0", m + 1, x + 1.0);
        let _ = writeln!(t, "MARKER/{}, PART = {p}, QP = {}, {s}, 0", m + 2, x + 0.5);
    }
    // Joints: crank pivots 1 + k; coupler ends.
    for k in 0..=n {
        let _ = writeln!(
            t,
            "JOINT/{}, REVOLUTE, I = {}, J = {}",
            1 + k,
            100_000 + 10 * k,
            1 + k
        );
    }
    for k in 0..n {
        let (left, right) = (500_000 + 10 * k, 500_000 + 10 * k + 1);
        let _ = writeln!(
            t,
            "JOINT/{}, REVOLUTE, I = {left}, J = {}",
            100_000 + 2 * k,
            100_000 + 10 * k + 1
        );
        let _ = writeln!(
            t,
            "JOINT/{}, REVOLUTE, I = {right}, J = {}",
            100_001 + 2 * k,
            100_000 + 10 * (k + 1) + 1
        );
    }
    t.push_str("END\n");
    t
}

/// A chain of `n` pendulum links hanging from ground, each a unit rod joined to the previous by
/// a revolute about global z (a tree: DOF n, no redundancy).
pub fn pendulum_chain(n: usize) -> String {
    let mut t = String::with_capacity(400 * n);
    let _ = writeln!(t, "Adams View model name: pendulum_chain_{n}");
    t.push_str("UNITS/\n, FORCE = NEWTON\n, MASS = KILOGRAM\n, LENGTH = METER\n, TIME = SECOND\n");
    t.push_str("ACCGRAV/\n, JGRAV = -9.80665\n");
    t.push_str("PART/1\n, GROUND\nMARKER/1, PART = 1\n");
    for k in 0..n {
        let (p, m) = (2 + k, 100 + 10 * k);
        let y = -(k as f64);
        let _ = writeln!(
            t,
            "PART/{p}, MASS = 1, CM = {}, IP = 0.0833333333333, 0.001, 0.0833333333333",
            m + 2
        );
        let _ = writeln!(t, "MARKER/{m}, PART = {p}, QP = 0, {y}, 0");
        let _ = writeln!(t, "MARKER/{}, PART = {p}, QP = 0, {}, 0", m + 1, y - 1.0);
        let _ = writeln!(t, "MARKER/{}, PART = {p}, QP = 0, {}, 0", m + 2, y - 0.5);
        let j = if k == 0 { 1 } else { 100 + 10 * (k - 1) + 1 };
        let _ = writeln!(t, "JOINT/{}, REVOLUTE, I = {m}, J = {j}", 1 + k);
    }
    t.push_str("END\n");
    t
}
