//! CONTACT against closed forms: a sphere bouncing on a plane with the POISSON law's
//! restitution, a cube resting on a slab through IMPACT contact (rest height and total normal
//! force m·g, in statics and at the end of a simulation), a block sliding on a plane and
//! decelerating at μd·g, an STL mesh resting like the box it describes, and 2-D CURVE
//! contacts: a ball resting on an open straight curve and inside a flipped closed circle (a
//! ring) at the IMPACT penetration, with the solid sides' push when flipped.

use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::applied::{AppliedForces, Regime};
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Output, Start};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::sync::Arc;

const G: f64 = 9.81;

const HEADER: &str = "contact\n\
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\n\
MARKER/1, PART = 1\n\
ACCGRAV/KGRAV = -9.81\n";

fn load_text(file: &str, text: &str) -> (Model, ExpressionDrivers, ForceSet) {
    let ds = linkage_adm::parse_dataset(Arc::from(file), text).unwrap_or_else(|e| panic!("{e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let f = ForceSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    (m, d, f)
}

fn load(body: &str) -> (Model, ExpressionDrivers, ForceSet) {
    load_text("t.adm", &format!("{HEADER}{body}\nEND\n"))
}

/// The outputs of a simulation to `end` with outputs every `dt` and the step limited to
/// `hmax`.
fn simulate(m: &Model, d: &ExpressionDrivers, f: &ForceSet, end: f64, dt: f64) -> Vec<Output> {
    let n = (end / dt).round() as usize;
    let times: Vec<f64> = (0..=n).map(|k| k as f64 * dt).collect();
    let settings = IntegratorSettings {
        error: 1e-6,
        hmax: Some(dt),
        ..Default::default()
    };
    let a = Assembled::new(m, d, f, &Tolerances::default());
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    let sim = r
        .simulation
        .unwrap_or_else(|| panic!("no simulation: {:?}", r.error));
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    sim.outputs
}

/// The generalised force of the force set on part 0 (force at its CM) at an output.
fn contact_force(f: &ForceSet, o: &Output) -> glam::DVec3 {
    let mut q = vec![0.0; 6 * o.state.poses.len()];
    f.add_forces(Regime::Dynamic, &o.state, &o.velocities, &mut q)
        .unwrap();
    glam::DVec3::new(q[0], q[1], q[2])
}

/// A ball of radius 0.1 m and mass 1 kg with its centre at height `z0`, above the ground
/// plane z = 0, with the POISSON law (penalty 1e7 N/m, restitution `e`).
fn ball(z0: f64, e: f64) -> String {
    format!(
        "MARKER/2, PART = 1\n\
         PART/2, MASS = 1, CM = 20, IP = 0.004, 0.004, 0.004, QG = 0, 0, {z0}\n\
         MARKER/20, PART = 2\n\
         GRAPHICS/1, ELLIPSOID, CM = 20, XSCALE = 0.2, YSCALE = 0.2, ZSCALE = 0.2\n\
         GRAPHICS/2, PLANE, RM = 2, XMIN = -1, XMAX = 1, YMIN = -1, YMAX = 1\n\
         CONTACT/1, IGEOM = 1, JGEOM = 2, POISSON, PENALTY = 1E7, RESTITUTION_COEFFICIENT = {e}"
    )
}

#[test]
fn sphere_bounces_on_a_plane_with_the_restitution_coefficient() {
    // Dropped from 0.4 m above touching: it hits at v0 = √(2 g 0.4) and leaves at ε·v0, so
    // its next apex is ε² · 0.4 m above touching. Energy bookkeeping with gravity working
    // through the peak penetration g_max = v0·√(m/p) ≈ 0.9 mm shifts the ratio by
    // ≈ 2 g g_max / v0² ≈ 0.2 %: the tolerance is 1 %.
    let e = 0.5;
    let (m, d, f) = load(&ball(0.5, e));
    let out = simulate(&m, &d, &f, 0.52, 1e-3);
    let t_hit = (2.0 * 0.4 / G).sqrt();
    let apex = out
        .iter()
        .filter(|o| o.time > t_hit + 0.01)
        .map(|o| o.state.poses[0].p.z)
        .fold(f64::NEG_INFINITY, f64::max);
    let ratio = ((apex - 0.1) / 0.4).sqrt();
    assert!(
        (ratio - e).abs() < 0.01 * e,
        "rebound ratio {ratio}, want {e}"
    );
    // The contact only pushes, never pulls, and only while the ball touches.
    for o in &out {
        let fz = contact_force(&f, o).z;
        let z = o.state.poses[0].p.z;
        assert!(fz >= 0.0, "pull {fz} at {}", o.time);
        if z > 0.1 {
            assert_eq!(fz, 0.0, "force without touching at {}", o.time);
        }
    }
}

/// A cube of side 0.2 m and mass 10 kg whose centre starts at `z0` above a ground slab
/// (top face z = 0), IMPACT contact k = 1e6 N/m^1.5, e = 1.5, c = 2e3 N·s/m, dmax = 1e-4 m;
/// `guide`: the cube is kept on a vertical translational joint.
fn cube(z0: f64, guide: bool, friction: &str, extra: &str) -> String {
    let guide = if guide {
        "MARKER/3, PART = 1\nMARKER/21, PART = 2\nJOINT/1, TRANSLATIONAL, I = 21, J = 3\n"
    } else {
        ""
    };
    format!(
        "MARKER/2, PART = 1, QP = -1, -1, -0.1\n\
         PART/2, MASS = 10, CM = 20, IP = 0.0667, 0.0667, 0.0667, QG = 0, 0, {z0} {extra}\n\
         MARKER/20, PART = 2\n\
         MARKER/22, PART = 2, QP = -0.1, -0.1, -0.1\n\
         {guide}\
         GRAPHICS/1, BOX, CORNER = 22, X = 0.2, Y = 0.2, Z = 0.2\n\
         GRAPHICS/2, BOX, CORNER = 2, X = 2, Y = 2, Z = 0.1\n\
         CONTACT/1, IGEOM = 1, JGEOM = 2, IMPACT, STIFFNESS = 1E6, DAMPING = 2E3, \
         DMAX = 1E-4, EXPONENT = 1.5{friction}"
    )
}

/// Rest penetration of the cube: one incident carries the weight, k·g^e = m·g.
fn rest_penetration() -> f64 {
    (10.0 * G / 1e6_f64).powf(1.0 / 1.5)
}

#[test]
fn cube_rests_on_a_slab_at_the_impact_penetration_in_statics() {
    let (m, d, f) = load(&cube(0.099, true, "", ""));
    let r = linkage_solve::stages::statics::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        &[0.0],
    );
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(eq.converged, "{:?}", eq.worst);
    let z = eq.state.poses[0].p.z;
    let want = 0.1 - rest_penetration();
    assert!((z - want).abs() < 1e-9, "rest height {z}, want {want}");
    let v = vec![(glam::DVec3::ZERO, glam::DVec3::ZERO)];
    let mut q = vec![0.0; 6];
    f.add_forces(Regime::Dynamic, &eq.state, &v, &mut q)
        .unwrap();
    assert!(
        (q[2] - 10.0 * G).abs() < 1e-6 * 10.0 * G,
        "normal force {}",
        q[2]
    );
    // Flat on the slab: no moment about the CM.
    assert!(q[3].abs() < 1e-9 && q[4].abs() < 1e-9, "{q:?}");
}

#[test]
fn dropped_cube_comes_to_rest_on_the_slab_carrying_its_weight() {
    // A free cube (six degrees of freedom) dropped 5 mm; the damping settles it.
    let (m, d, f) = load(&cube(0.105, false, "", ""));
    let out = simulate(&m, &d, &f, 1.0, 2e-3);
    let last = out.last().unwrap();
    let z = last.state.poses[0].p.z;
    let want = 0.1 - rest_penetration();
    assert!(
        (z - want).abs() < 1e-3 * rest_penetration(),
        "{z} vs {want}"
    );
    let fc = contact_force(&f, last);
    assert!((fc.z - 10.0 * G).abs() < 1e-3 * 10.0 * G, "{fc}");
    assert!(fc.x.abs() < 1e-6 && fc.y.abs() < 1e-6, "{fc}");
}

#[test]
fn block_sliding_on_a_plane_decelerates_at_mu_dynamic_g() {
    // The cube starts resting at its rest height with vx = 2 m/s; above the friction
    // transition velocity the friction is μd·m·g, so vx(t) = 2 − μd·g·t. An ORIENTATION
    // primitive keeps it from rocking under the friction moment (free, it rocks on its front
    // edge and the normal force oscillates about m·g).
    let z0 = 0.1 - rest_penetration();
    let friction = ", COULOMB_FRICTION = ON, MU_STATIC = 0.4, MU_DYNAMIC = 0.3, \
                    STICTION_TRANSITION_VELOCITY = 0.01, FRICTION_TRANSITION_VELOCITY = 0.1";
    let body = cube(z0, false, friction, ", VX = 2") + "\nJPRIM/1, ORIENTATION, I = 20, J = 1";
    let (m, d, f) = load(&body);
    let out = simulate(&m, &d, &f, 0.5, 1e-3);
    let at = |t: f64| {
        out.iter()
            .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))
            .unwrap()
    };
    let (a, b) = (at(0.1), at(0.5));
    let decel = (a.velocities[0].0.x - b.velocities[0].0.x) / (b.time - a.time);
    let want = 0.3 * G;
    assert!(
        (decel - want).abs() < 1e-3 * want,
        "deceleration {decel}, want {want}"
    );
    // Sliding, not stuck: still faster than the friction transition velocity.
    assert!(b.velocities[0].0.x > 0.1);
}

/// An ascii STL of the axis-aligned cube [-h, h]³ (12 triangles, outward normals).
fn stl_cube(h: f64) -> String {
    let v = |i: usize| {
        let s = |b: usize| if i & b != 0 { h } else { -h };
        [s(1), s(2), s(4)]
    };
    // Faces as quads of vertex ids (bit 1 = x, 2 = y, 4 = z), counter-clockwise from outside.
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut s = String::from("solid cube\n");
    for q in quads {
        for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            s.push_str("facet normal 0 0 0\nouter loop\n");
            for k in t {
                let p = v(k);
                s.push_str(&format!("vertex {} {} {}\n", p[0], p[1], p[2]));
            }
            s.push_str("endloop\nendfacet\n");
        }
    }
    s.push_str("endsolid cube\n");
    s
}

#[test]
fn stl_mesh_cube_rests_like_the_box_it_describes() {
    let dir = std::env::temp_dir().join(format!("linkage-contact-stl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("cube.stl"), stl_cube(0.1)).unwrap();
    let body = cube(0.099, true, "", "").replace(
        "GRAPHICS/1, BOX, CORNER = 22, X = 0.2, Y = 0.2, Z = 0.2",
        "GRAPHICS/1, EXTERNAL, RM = 20, FILE = cube.stl",
    );
    let file = dir.join("stl.adm");
    let (m, d, f) = load_text(file.to_str().unwrap(), &format!("{HEADER}{body}\nEND\n"));
    assert!(Path::new(&dir.join("cube.stl")).exists());
    let r = linkage_solve::stages::statics::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        &[0.0],
    );
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(eq.converged, "{:?}", eq.worst);
    let z = eq.state.poses[0].p.z;
    let want = 0.1 - rest_penetration();
    // STL coordinates are f32: the half-side 0.1 is stored as 0.1 + 1.5e-9.
    assert!((z - want).abs() < 1e-8, "rest height {z}, want {want}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cube_on_the_slab_vibrates_at_the_contact_stiffness_frequency() {
    // About its rest penetration g the contact is a spring of stiffness dFn/dg = e·k·g^(e−1):
    // f = √(1.5·k·√g / m) / 2π on the vertical guide.
    use linkage_solve::stages::linearize::{EigenMethod, LinearOptions};
    let (m, d, f) = load(&cube(0.099, true, "", "").replace("DAMPING = 2E3", "DAMPING = 0"));
    let run = linkage_solve::stages::linearize::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        true,
        LinearOptions {
            damping: false,
            vectors: false,
            method: EigenMethod::Auto,
        },
    );
    let l = run.result.unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(l.dof, 1);
    let stiffness = 1.5 * 1e6 * rest_penetration().sqrt();
    let want = (stiffness / 10.0).sqrt() / std::f64::consts::TAU;
    let got = l.modes[0].frequency;
    assert!((got - want).abs() < 1e-6 * want, "{got} Hz, want {want}");
}

/// `∂Q/∂q` and `∂Q/∂v` of the force set (dense 6 × 6 for one part) against central
/// differences of `Q` at `(s, v)`.
fn check_jacobians(
    f: &ForceSet,
    s: &linkage_solve::state::State,
    v: &[(glam::DVec3, glam::DVec3)],
) {
    let q = |s: &linkage_solve::state::State, v: &[(glam::DVec3, glam::DVec3)]| {
        let mut out = vec![0.0; 6];
        f.add_forces(Regime::Dynamic, s, v, &mut out).unwrap();
        out
    };
    let (mut dq, mut dv) = (Vec::new(), Vec::new());
    f.add_jacobians(Regime::Dynamic, s, v, &mut dq, Some(&mut dv))
        .unwrap();
    let dense = |t: &[(usize, usize, f64)]| {
        let mut m = [[0.0; 6]; 6];
        for &(r, c, x) in t {
            m[r][c] += x;
        }
        m
    };
    let (aq, av) = (dense(&dq), dense(&dv));
    // Relative to the largest derivative.
    let scale = aq
        .iter()
        .chain(&av)
        .flatten()
        .fold(1.0_f64, |a, x| a.max(x.abs()));
    let h = 1e-7;
    for c in 0..6 {
        let unit = |x: f64| {
            let mut e = [0.0; 6];
            e[c] = x;
            (
                glam::DVec3::new(e[0], e[1], e[2]),
                glam::DVec3::new(e[3], e[4], e[5]),
            )
        };
        let shifted = |x: f64| {
            let mut t = s.clone();
            let (dx, dth) = unit(x);
            t.increment(0, dx, dth);
            q(&t, v)
        };
        let moved = |x: f64| {
            let (dv_, dw) = unit(x);
            q(s, &[(v[0].0 + dv_, v[0].1 + dw)])
        };
        let (qp, qm, vp, vm) = (shifted(h), shifted(-h), moved(h), moved(-h));
        for r in 0..6 {
            let nq = (qp[r] - qm[r]) / (2.0 * h);
            let nv = (vp[r] - vm[r]) / (2.0 * h);
            assert!(
                (aq[r][c] - nq).abs() < 1e-6 * scale,
                "∂Q{r}/∂q{c}: {} vs {nq}",
                aq[r][c]
            );
            assert!(
                (av[r][c] - nv).abs() < 1e-6 * scale,
                "∂Q{r}/∂v{c}: {} vs {nv}",
                av[r][c]
            );
        }
    }
}

#[test]
fn contact_jacobians_match_finite_differences() {
    // A tilted cube with one corner 1 mm into the slab, sliding and spinning (friction in
    // its transition band), and a rolling ball pressed into the plane.
    let friction = ", COULOMB_FRICTION = ON, MU_STATIC = 0.4, MU_DYNAMIC = 0.3, \
                    STICTION_TRANSITION_VELOCITY = 0.01, FRICTION_TRANSITION_VELOCITY = 1";
    let tilt = ", REULER = 10D, 20D, 5D";
    let (m, _, f) = load(&cube(0.1, false, friction, tilt));
    let mut s = linkage_solve::state::State::input(&m);
    // Put the lowest corner 1 mm below the slab's top.
    let r = s.poses[0].r;
    let lowest = (0..8)
        .map(|k| {
            let c = |b: usize| if k & b != 0 { 0.1 } else { -0.1 };
            (r * glam::DVec3::new(c(1), c(2), c(4))).z
        })
        .fold(f64::INFINITY, f64::min);
    s.poses[0].p.z = -lowest - 1e-3;
    let v = [(
        glam::DVec3::new(0.3, -0.2, -0.05),
        glam::DVec3::new(0.5, 1.0, 2.0),
    )];
    let mut q = vec![0.0; 6];
    f.add_forces(Regime::Dynamic, &s, &v, &mut q).unwrap();
    assert!(q[2] > 0.0, "the corner is in contact: {q:?}");
    check_jacobians(&f, &s, &v);

    let ball = ball(0.099, 0.5).replace(
        "RESTITUTION_COEFFICIENT = 0.5",
        &format!("RESTITUTION_COEFFICIENT = 0.5{friction}"),
    );
    let (m, _, f) = load(&ball);
    let s = linkage_solve::state::State::input(&m);
    let v = [(
        glam::DVec3::new(0.2, 0.1, -0.5),
        glam::DVec3::new(1.0, -2.0, 0.5),
    )];
    check_jacobians(&f, &s, &v);
}

/// A ball of radius 0.1 m and mass 1 kg (centre height `y0`) on a vertical slider, against the
/// ground CURVE `curve` (a GRAPHICS CURVE on MARKER/2, whose xy plane is the world's xy
/// plane), gravity −y, IMPACT k = 1e6 N/m^1.5, e = 1.5, c = 50 N·s/m, dmax = 1e-4 m.
fn ball_on_curve(y0: f64, curve: &str, flip: &str) -> String {
    format!(
        "curve contact\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\n\
         MARKER/1, PART = 1\n\
         MARKER/2, PART = 1\n\
         MARKER/3, PART = 1, REULER = 0D, -90D, 0D\n\
         ACCGRAV/JGRAV = -9.81\n\
         PART/2, MASS = 1, CM = 20, IP = 0.004, 0.004, 0.004, QG = 0, {y0}, 0\n\
         MARKER/20, PART = 2\n\
         MARKER/21, PART = 2, REULER = 0D, -90D, 0D\n\
         JOINT/1, TRANSLATIONAL, I = 21, J = 3\n\
         GRAPHICS/1, ELLIPSOID, CM = 20, XSCALE = 0.2, YSCALE = 0.2, ZSCALE = 0.2\n\
         {curve}\
         GRAPHICS/2, CURVE, CID = 5, CRM = 2\n\
         CONTACT/1, IGEOM = 1, JGEOM = 2, IMPACT, STIFFNESS = 1E6, DAMPING = 50, \
         DMAX = 1E-4, EXPONENT = 1.5{flip}\n\
         END\n"
    )
}

/// An open straight CURVE along +x through five points on y = 0: its solid side (right of
/// increasing α) is y < 0.
const LINE: &str = "MATRIX/4, FULL = RORDER, ROWS = 5, COLUMNS = 3, \
    VALUES = -1, 0, 0, -0.5, 0, 0, 0, 0, 0, 0.5, 0, 0, 1, 0, 0\n\
    CURVE/5, OPEN, CURVE_POINTS, MATRIX = 4\n";

/// A closed CURVE through 16 points of the circle of radius 1 about the origin (one of them
/// the bottom point (0, −1)); flipped, its outside is solid: a ring.
fn ring() -> String {
    circle(5, 4, 1.0)
}

/// CURVE/`id` (MATRIX/`matrix`): closed, through 16 points of the circle of `radius` about
/// the origin of its frame.
fn circle(id: u32, matrix: u32, radius: f64) -> String {
    let values: Vec<String> = (0..16)
        .map(|k| {
            let a = std::f64::consts::TAU * f64::from(k) / 16.0;
            format!("{:.17}, {:.17}, 0", radius * a.cos(), radius * a.sin())
        })
        .collect();
    format!(
        "MATRIX/{matrix}, FULL = RORDER, ROWS = 16, COLUMNS = 3, VALUES = {}\n\
         CURVE/{id}, CLOSED, CURVE_POINTS, MATRIX = {matrix}\n",
        values.join(", ")
    )
}

/// Rest penetration of the 1 kg ball: k·δ^e = m·g.
fn ball_rest_penetration() -> f64 {
    (G / 1e6_f64).powf(1.0 / 1.5)
}

/// Statics of a ball-on-curve model: the rest height of the ball's centre and the contact
/// force on it (x, y).
fn ball_statics(text: &str) -> (f64, glam::DVec3) {
    let (m, d, f) = load_text("c.adm", text);
    let r = linkage_solve::stages::statics::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        &[0.0],
    );
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(eq.converged, "{:?}", eq.worst);
    let v = vec![(glam::DVec3::ZERO, glam::DVec3::ZERO)];
    let mut q = vec![0.0; 6];
    f.add_forces(Regime::Dynamic, &eq.state, &v, &mut q)
        .unwrap();
    (eq.state.poses[0].p.y, glam::DVec3::new(q[0], q[1], q[2]))
}

#[test]
fn ball_rests_on_an_open_curve_at_the_impact_penetration() {
    // Straight line y = 0 (the interpolating spline of collinear points is the line): the
    // centre rests at r − δ, δ = (m g / k)^(1/e), the contact carrying m g along +y.
    let (y, fc) = ball_statics(&ball_on_curve(0.099, LINE, ""));
    let want = 0.1 - ball_rest_penetration();
    assert!((y - want).abs() < 1e-9, "rest height {y}, want {want}");
    assert!((fc.y - G).abs() < 1e-6 * G, "normal force {fc}");
    assert!(fc.x.abs() < 1e-9 && fc.z.abs() < 1e-9, "{fc}");
    // Flipped, the solid is above the line: the centre 0.099 above it is inside, the depth
    // r + 0.099 = 0.199 and the force k·0.199^1.5 pushes it down (no velocity, no damping).
    let (m, _, f) = load_text("c.adm", &ball_on_curve(0.099, LINE, ", JFLIP_GEOMETRY = 2"));
    let st = linkage_solve::state::State::input(&m);
    let mut q = vec![0.0; 6];
    f.add_forces(
        Regime::Dynamic,
        &st,
        &[(glam::DVec3::ZERO, glam::DVec3::ZERO)],
        &mut q,
    )
    .unwrap();
    let want = -1e6 * 0.199_f64.powf(1.5);
    assert!((q[1] - want).abs() < 1e-9 * want.abs(), "{q:?} vs {want}");
}

#[test]
fn ball_inside_a_ring_rests_at_its_bottom_at_the_impact_penetration() {
    // The flipped closed circle: the ball inside rests on the bottom point (0, −1), centre at
    // −1 + r − δ, the contact carrying m g.
    // The sampled polyline's chords lie within CHORD_TOLERANCE × size (the bounding box's
    // diagonal, 2√2 m) of the curve,
    // inside the circle: that is the tolerance on the height.
    let sag = linkage_model::contacts::CHORD_TOLERANCE * 8f64.sqrt();
    let text = ball_on_curve(-0.901, &ring(), ", JFLIP_GEOMETRY = 2");
    let (y, fc) = ball_statics(&text);
    let want = -1.0 + 0.1 - ball_rest_penetration();
    assert!((y - want).abs() < sag, "rest height {y}, want {want}");
    assert!((fc.y - G).abs() < 1e-6 * G, "normal force {fc}");
    // The normal is that of the chord under the ball, tilted from the circle's by at most
    // half a chord's angle θ/2 = √(2·sag/R) (sag = R θ²/8); the slider carries the x part.
    let tilt = (2.0 * sag / 1.0_f64).sqrt();
    assert!(fc.x.abs() <= G * tilt, "{fc}");
    // Dropped from the centre of the ring it falls 0.9 m, hits the bottom and stays inside
    // (centre above −1 + r − δ_max; the peak penetration at the 4.2 m/s impact is a few
    // mm), settling towards the rest height.
    let (m, d, f) = load_text(
        "c.adm",
        &ball_on_curve(0.0, &ring(), ", JFLIP_GEOMETRY = 2"),
    );
    let out = simulate(&m, &d, &f, 1.5, 2e-3);
    let mut lowest = f64::INFINITY;
    for o in &out {
        let y = o.state.poses[0].p.y;
        assert!(
            y > -1.0 + 0.1 - 0.02,
            "left the ring: y = {y} at {}",
            o.time
        );
        lowest = lowest.min(y);
    }
    // It did reach the ring (penetrating it).
    assert!(lowest < -0.9, "never touched: lowest {lowest}");
    // Unflipped, the disc of the circle is solid: the centre at (0, −0.5) is 0.5 inside it
    // (the nearest boundary point is the data point (0, −1)), the depth 0.6 and the force
    // k·0.6^1.5 pushes it down, out through the nearest boundary.
    let (m, _, f) = load_text("c.adm", &ball_on_curve(-0.5, &ring(), ""));
    let st = linkage_solve::state::State::input(&m);
    let mut q = vec![0.0; 6];
    f.add_forces(
        Regime::Dynamic,
        &st,
        &[(glam::DVec3::ZERO, glam::DVec3::ZERO)],
        &mut q,
    )
    .unwrap();
    // The depth is within the chord sag of 0.6: the force within 1.5 × sag / 0.6.
    let want = -1e6 * 0.6_f64.powf(1.5);
    assert!(
        (q[1] - want).abs() < 1.5 * sag / 0.6 * want.abs(),
        "{q:?} vs {want}"
    );
}

#[test]
fn wheel_curve_rests_on_a_plane_and_on_a_line_curve_at_the_impact_penetration() {
    // The ball's sphere replaced by a closed circular CURVE of radius 0.1 about its CM (the
    // I geometry): on the ground PLANE y = 0 (MARKER/3's z is +y), and on the open LINE
    // curve. The deepest vertex carries k·δ^e = m·g; the lowest vertex of the sampled
    // circle is within the chord sag (CHORD_TOLERANCE × 0.2√2 m) of the circle's bottom.
    let sag = linkage_model::contacts::CHORD_TOLERANCE * 0.08f64.sqrt();
    let want = 0.1 - ball_rest_penetration();
    let wheel = |j: &str| {
        ball_on_curve(0.099, &format!("{LINE}{}", circle(7, 6, 0.1)), "")
            .replace(
                "GRAPHICS/1, ELLIPSOID, CM = 20, XSCALE = 0.2, YSCALE = 0.2, ZSCALE = 0.2",
                "GRAPHICS/1, CURVE, CID = 7, CRM = 20\nGRAPHICS/3, PLANE, RM = 3\n",
            )
            .replace("JGEOM = 2", &format!("JGEOM = {j}"))
    };
    for j in ["3", "2"] {
        let (y, fc) = ball_statics(&wheel(j));
        assert!(
            (y - want).abs() <= sag,
            "JGEOM {j}: rest height {y}, want {want}"
        );
        assert!((fc.y - G).abs() < 1e-6 * G, "JGEOM {j}: normal force {fc}");
    }
}
