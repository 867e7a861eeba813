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
    // Cranks: part 2 + k; markers 100_000 + 10k + {0: base, 1: tip, 2: cm} (distinct from the
    // couplers' up to 90,000 loops).
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
    // Couplers: part 2 + (n + 1) + k; markers 1_000_000 + 10k + {0: left, 1: right, 2: cm}.
    for k in 0..n {
        let (p, m) = (3 + n + k, 1_000_000 + 10 * k);
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
        let (left, right) = (1_000_000 + 10 * k, 1_000_000 + 10 * k + 1);
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
    rod_chain(n, "pendulum_chain", "REVOLUTE")
}

/// A chain of `n` unit rods (1 m, 1 kg) hanging straight down from ground along −y, each
/// joined to the one above by a spherical joint (a tree: 6n coordinates, 3n rows, DOF 2n
/// pendulum motions plus n free spins of the rods about their own axes).
///
/// As `n` grows its swinging frequencies tend to those of the heavy hanging chain of length
/// `ℓ = n`: `ω_k = (j₀ₖ/2)·√(g/ℓ)`, `j₀ₖ` the zeros of the Bessel function J₀, each twice
/// (two planes of swing).
pub fn hanging_chain(n: usize) -> String {
    rod_chain(n, "hanging_chain", "SPHERICAL")
}

/// `n` unit rods hanging along −y from ground, each joined to the one above by `joint` (its
/// axis, for a revolute, global z).
fn rod_chain(n: usize, title: &str, joint: &str) -> String {
    let mut t = String::with_capacity(400 * n);
    let _ = writeln!(t, "Adams View model name: {title}_{n}");
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
        let _ = writeln!(t, "JOINT/{}, {joint}, I = {m}, J = {j}", 1 + k);
    }
    t.push_str("END\n");
    t
}

/// The IFToMM A02 dataset for `n` loops: n + 1 cranks of length 1 m pinned to ground at
/// x = 0, 1, …, n (initially vertical, angle φ = π/2 from +x), n couplers of 1 m joining the
/// crank tips; every link 1 kg, uniform (transverse inertia m L²/12, axial m r²/2 with
/// r = 0.01 m); the first crank's tip B0 (MARKER/203) moving at 1 m/s along +x, which is
/// φ' = −1 rad/s for every crank and 1 m/s along +x for every coupler.
pub fn iftomm_a02(n: usize) -> String {
    let (it, ia) = (1.0 / 12.0, 0.5 * 1e-4);
    let mut t = String::new();
    let _ = writeln!(t, "Adams View model name: a02_fourbar_n{n}");
    t.push_str(&format!(
        "!
! linkage benchmark  a02_fourbar_n{n}.adm  (written by linkage_solve::generate::iftomm_a02)
!   IFToMM multibody benchmark library, problem A02 \"N four-bar mechanism\"
!   (M. Gonzalez, D. Dopico, U. Lugris, J. Cuadrado, \"A benchmarking system
!   for MBS simulation software\", Multibody System Dynamics 16 (2006) 179-190;
!   library of the IFToMM Technical Committee for Multibody Dynamics,
!   originally lim.ii.udc.es/mbsbenchmark, problem A02).
!   Published data: 2N+1 links of 1 m with a uniformly distributed mass of
!   1 kg; gravity 9.81 m/s^2 along -y; initially the square position (cranks
!   vertical), the x velocity of point B0 (tip of the first crank) 1 m/s;
!   dynamic simulation over 20 s; the benchmark checks the position and
!   velocity of B0 at 400 outputs (high-precision limit 1e-3); published for
!   N = 40, here N = {n}.  The chain passes the horizontal singular position
!   (the degrees of freedom jump from 1 to N+1 there) twice per turn.
!   Link inertia: transverse m L^2/12, axial m r^2/2 with r = 0.01 m.
!   Part frames = ground frame; markers given in ground; initial velocities
!   VX (ground) and WZ on every part, consistent with the constraints.
!
! Expected mobility (6 coordinates per moving part):
!   moving parts                {parts}
!   constraint rows             {rows}  ({joints} x REVOLUTE 5)
!   degrees of freedom          1
!   redundant equations         {redundant}  ({n} loops x 3 out-of-plane rows)
!
",
        parts = 2 * n + 1,
        rows = 5 * 3 * n + 5,
        joints = 3 * n + 1,
        redundant = 3 * n,
    ));
    t.push_str("UNITS/\n, FORCE = NEWTON\n, MASS = KILOGRAM\n, LENGTH = METER\n, TIME = SECOND\n");
    t.push_str("!\nPART/1\n, GROUND\n");
    for k in 0..=n {
        let _ = writeln!(t, "!\nMARKER/{}\n, PART = 1\n, QP = {k}.0, 0.0, 0.0", 1 + k);
    }
    for k in 0..=n {
        let p = 2 + k;
        let _ = writeln!(
            t,
            "!\n!                          adams_view_name='crank_{k}'\n\
             PART/{p}\n, MASS = 1.0\n, CM = {p}01\n, IP = {it:?}, {ia:?}, {it:?}\n, VX = 0.5\n, WZ = -1.0\n\
             MARKER/{p}01\n, PART = {p}\n, QP = {k}.0, 0.5, 0.0\n\
             MARKER/{p}02\n, PART = {p}\n, QP = {k}.0, 0.0, 0.0\n\
             MARKER/{p}03\n, PART = {p}\n, QP = {k}.0, 1.0, 0.0"
        );
    }
    for j in 1..=n {
        let p = 2 + n + j;
        let _ = writeln!(
            t,
            "!\n!                          adams_view_name='coupler_{j}'\n\
             PART/{p}\n, MASS = 1.0\n, CM = {p}01\n, IP = {ia:?}, {it:?}, {it:?}\n, VX = 1.0\n\
             MARKER/{p}01\n, PART = {p}\n, QP = {x:?}, 1.0, 0.0\n\
             MARKER/{p}02\n, PART = {p}\n, QP = {l}.0, 1.0, 0.0\n\
             MARKER/{p}03\n, PART = {p}\n, QP = {j}.0, 1.0, 0.0",
            x = j as f64 - 0.5,
            l = j - 1,
        );
    }
    t.push_str("!\n");
    for k in 0..=n {
        let _ = writeln!(
            t,
            "JOINT/{}\n, REVOLUTE\n, I = {}02\n, J = {}",
            1 + k,
            2 + k,
            1 + k
        );
    }
    for j in 1..=n {
        let p = 2 + n + j;
        let _ = writeln!(
            t,
            "JOINT/{}\n, REVOLUTE\n, I = {p}02\n, J = {}03\nJOINT/{}\n, REVOLUTE\n, I = {p}03\n, J = {}03",
            n + 2 * j,
            1 + j,
            n + 2 * j + 1,
            2 + j
        );
    }
    t.push_str("!\nACCGRAV/\n, JGRAV = -9.81\n!\nEND\n");
    t
}
