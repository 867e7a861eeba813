//! REQUEST evaluation on hand-made outputs: every value against an independent computation.

use glam::{DMat3, DVec3};
use linkage_model::Model;
use linkage_solve::constraints::system::System;
use linkage_solve::physics::reactions::Reaction;
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::stages::dynamics::Output;
use linkage_solve::state::{Pose, State};
use std::sync::Arc;

const DATASET: &str = "requests test
UNITS/FORCE=NEWTON, MASS=KILOGRAM, LENGTH=METER, TIME=SECOND
ACCGRAV/KGRAV=-9.8
PART/1, GROUND
MARKER/1, PART=1
MARKER/2, PART=1, QP=1,0,0, REULER=90D,0,0
PART/2, MASS=2, CM=20, IP=1,1,1
MARKER/20, PART=2
MARKER/21, PART=2, QP=1,0,0
MARKER/22, PART=2, QP=0,1,0.5
PART/3, MASS=3, CM=30, IP=1,2,3
MARKER/30, PART=3, QP=0,0,-2
JOINT/5, REVOLUTE, I=21, J=2
SFORCE/7, TRANSLATIONAL, I=22, J=1, FUNCTION=10
GCON/9, I=30, FUNCTION=DM(30,1)-2
VARIABLE/3, FUNCTION=ACCY(21)
REQUEST/1, D, I=21, J=1
REQUEST/2, V, I=21, J=1, RM=2
REQUEST/3, A, I=21
REQUEST/4, F, I=21, J=2
REQUEST/6, FORCE, I=2, J=21, RM=2
!                       adams_view_name='measures'
REQUEST/8, F1=ACCX(30,20,0,20)\\F2=ACCY(30,20,0,20)\\F3=WDTY(30,0,0,20)\\F4=VARVAL(3)
, F5=JOINT(5,1,2,0)\\F6=JOINT(5,1,8,2)\\F7=SFORCE(7,0,4,0)\\F8=FX(21,2)+TM(21,2)
REQUEST/10, F, I=1, J=30
END
";

fn model_of(text: &str) -> Model {
    let ds =
        linkage_adm::parse_dataset(Arc::from("req.adm"), text).unwrap_or_else(|e| panic!("{e}"));
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

/// Part 2 turns about z (θ(t) = 0.3 + 1.5t + t²) about its CM at the origin; part 3's CM moves
/// along `p3(t)` without turning at this instant (ω3, α3 given).
fn theta(t: f64) -> [f64; 3] {
    [0.3 + 1.5 * t + t * t, 1.5 + 2.0 * t, 2.0]
}
fn p3(t: f64) -> [DVec3; 3] {
    [
        DVec3::new(1.0 + t * t, 2.0 * t, 0.5 * t * t * t),
        DVec3::new(2.0 * t, 2.0, 1.5 * t * t),
        DVec3::new(2.0, 0.0, 3.0 * t),
    ]
}
const T: f64 = 0.5;
const W3: DVec3 = DVec3::new(1.0, 0.0, 0.5);
const AL3: DVec3 = DVec3::new(0.0, 1.0, 0.25);
const F_JOINT: DVec3 = DVec3::new(1.0, -2.0, 3.0);
const T_JOINT: DVec3 = DVec3::new(0.5, 0.25, -1.0);

fn output(model: &Model) -> Output {
    let [th, w, al] = theta(T);
    let [p, v, a] = p3(T);
    let joint = model
        .constraints
        .iter()
        .position(|c| c.origin.statement == "JOINT" && c.origin.id == 5)
        .unwrap_or_else(|| panic!("no JOINT/5"));
    Output {
        time: T,
        state: State {
            poses: vec![
                Pose {
                    p: DVec3::ZERO,
                    r: DMat3::from_rotation_z(th),
                },
                Pose {
                    p,
                    r: DMat3::IDENTITY,
                },
            ],
            time: T,
            controls: Default::default(),
            elements: Default::default(),
        },
        velocities: vec![(DVec3::ZERO, DVec3::new(0.0, 0.0, w)), (v, W3)],
        accelerations: vec![(DVec3::ZERO, DVec3::new(0.0, 0.0, al)), (a, AL3)],
        reactions: vec![Reaction {
            element: joint,
            force: F_JOINT,
            torque: T_JOINT,
        }],
    }
}

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b}");
}

fn close3(a: DVec3, b: DVec3, tol: f64, what: &str) {
    assert!((a - b).abs().max_element() <= tol, "{what}: {a} vs {b}");
}

fn values(set: &RequestSet, model: &Model, o: &Output) -> Vec<(String, f64)> {
    let v = set
        .evaluate(model, &System::new(model), o)
        .unwrap_or_else(|e| panic!("{e}"));
    set.columns().into_iter().zip(v).collect()
}

fn get(vals: &[(String, f64)], name: &str) -> f64 {
    vals.iter()
        .find(|(n, _)| n == name)
        .map(|(_, v)| *v)
        .unwrap_or_else(|| panic!("no column {name}"))
}

fn vec_of(vals: &[(String, f64)], prefix: &str, names: [&str; 3]) -> DVec3 {
    DVec3::new(
        get(vals, &format!("{prefix}.{}", names[0])),
        get(vals, &format!("{prefix}.{}", names[1])),
        get(vals, &format!("{prefix}.{}", names[2])),
    )
}

#[test]
fn columns_name_every_component() {
    let model = model_of(DATASET);
    let set = RequestSet::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let cols = set.columns();
    assert_eq!(cols.len(), 6 * 6 + 8);
    assert_eq!(
        &cols[..6],
        [
            "REQUEST_1.x",
            "REQUEST_1.y",
            "REQUEST_1.z",
            "REQUEST_1.psi",
            "REQUEST_1.theta",
            "REQUEST_1.phi"
        ]
    );
    assert_eq!(cols[6], "REQUEST_2.vx");
    assert_eq!(cols[9], "REQUEST_2.wx");
    assert_eq!(cols[12], "REQUEST_3.ax");
    assert_eq!(cols[17], "REQUEST_3.wdz");
    assert_eq!(cols[18], "REQUEST_4.fx");
    assert_eq!(cols[23], "REQUEST_4.tz");
    assert_eq!(cols[30], "measures.f1");
    assert_eq!(cols[37], "measures.f8");
    assert_eq!(cols[38], "REQUEST_10.fx");
    assert!(!set.is_empty());
}

#[test]
fn standard_requests_are_relative_kinematics_in_rm() {
    let model = model_of(DATASET);
    let set = RequestSet::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let o = output(&model);
    let vals = values(&set, &model, &o);
    let [th, w, al] = theta(T);
    let u = DVec3::new(th.cos(), th.sin(), 0.0);
    let wv = DVec3::new(0.0, 0.0, w);
    // Displacement of marker 21 from the ground origin; orientation Rz(θ): ψ = θ, θ = φ = 0.
    close3(vec_of(&vals, "REQUEST_1", ["x", "y", "z"]), u, 1e-12, "D");
    close(get(&vals, "REQUEST_1.psi"), th.to_degrees(), 1e-9, "psi");
    close(get(&vals, "REQUEST_1.theta"), 0.0, 1e-9, "theta");
    close(get(&vals, "REQUEST_1.phi"), 0.0, 1e-9, "phi");
    // Velocity in RM = marker 2, whose axes are Rz(90°): (x, y) → (y, −x).
    let v = wv.cross(u);
    close3(
        vec_of(&vals, "REQUEST_2", ["vx", "vy", "vz"]),
        DVec3::new(v.y, -v.x, v.z),
        1e-12,
        "V",
    );
    close3(
        vec_of(&vals, "REQUEST_2", ["wx", "wy", "wz"]),
        wv,
        1e-12,
        "W",
    );
    // Acceleration of a point at radius 1: α × u + ω × (ω × u).
    let a = DVec3::new(0.0, 0.0, al).cross(u) + wv.cross(wv.cross(u));
    close3(
        vec_of(&vals, "REQUEST_3", ["ax", "ay", "az"]),
        a,
        1e-12,
        "A",
    );
    close3(
        vec_of(&vals, "REQUEST_3", ["wdx", "wdy", "wdz"]),
        DVec3::new(0.0, 0.0, al),
        1e-12,
        "WDT",
    );
    // VARVAL sees accelerations.
    close(
        get(&vals, "measures.f4"),
        a.y,
        1e-12,
        "VARVAL(3) = ACCY(21)",
    );
}

#[test]
fn accelerations_in_a_turning_frame_match_finite_differences() {
    let model = model_of(DATASET);
    let set = RequestSet::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let vals = values(&set, &model, &output(&model));
    // (d²/dt²)_l (P30 − P20) with l = part 2: differentiate the vector seen in part 2's axes,
    // then express it in ground.
    let seen = |t: f64| DMat3::from_rotation_z(-theta(t)[0]) * p3(t)[0];
    let h = 1e-4;
    let d2 = (seen(T + h) - 2.0 * seen(T) + seen(T - h)) / (h * h);
    let expected = DMat3::from_rotation_z(theta(T)[0]) * d2;
    close(
        get(&vals, "measures.f1"),
        expected.x,
        1e-6,
        "ACCX(30,20,0,20)",
    );
    close(
        get(&vals, "measures.f2"),
        expected.y,
        1e-6,
        "ACCY(30,20,0,20)",
    );
    // (d/dt)_l ω3 = α3 − ω_l × ω3.
    let wdt = AL3 - DVec3::new(0.0, 0.0, theta(T)[1]).cross(W3);
    close(get(&vals, "measures.f3"), wdt.y, 1e-12, "WDTY(30,0,0,20)");
}

#[test]
fn reactions_and_force_requests_follow_the_documented_conventions() {
    let model = model_of(DATASET);
    let set = RequestSet::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let o = output(&model);
    let vals = values(&set, &model, &o);
    let th = theta(T)[0];
    let r2 = DMat3::from_rotation_z(th);
    let p21 = r2 * DVec3::new(1.0, 0.0, 0.0);
    let p22 = r2 * DVec3::new(0.0, 1.0, 0.5);
    let p_j = DVec3::new(1.0, 0.0, 0.0);
    // JOINT(5, 1, …): on J, minus the force; torque about J's origin, resolved in rm.
    close(
        get(&vals, "measures.f5"),
        -F_JOINT.x,
        1e-12,
        "JOINT(5,1,2,0)",
    );
    let t_j = -T_JOINT - (p21 - p_j).cross(F_JOINT);
    let rm = DMat3::from_rotation_z(90f64.to_radians());
    close(
        get(&vals, "measures.f6"),
        (rm.transpose() * t_j).z,
        1e-12,
        "JOINT(5,1,8,2)",
    );
    // SFORCE: 10 N along J→I (repelling), on I.
    let f_s = 10.0 * p22.normalize();
    close(get(&vals, "measures.f7"), f_s.z, 1e-12, "SFORCE(7,0,4,0)");
    // FORCE I=21 J=2: the joint (I on 21's part) and the SFORCE (I on 21's part) on part 2,
    // torque about 21.
    let f = F_JOINT + f_s;
    let t = T_JOINT + (p22 - p21).cross(f_s);
    close3(
        vec_of(&vals, "REQUEST_4", ["fx", "fy", "fz"]),
        f,
        1e-12,
        "FORCE f",
    );
    close3(
        vec_of(&vals, "REQUEST_4", ["tx", "ty", "tz"]),
        t,
        1e-12,
        "FORCE t",
    );
    close(
        get(&vals, "measures.f8"),
        f.x + t.length(),
        1e-12,
        "FX + TM",
    );
    // FORCE I=2 J=21 in RM=2: the opposite wrench on ground, about marker 2's origin.
    let t_ground = -T_JOINT + (p21 - p_j).cross(-F_JOINT) + (p22 - p_j).cross(-f_s);
    close3(
        vec_of(&vals, "REQUEST_6", ["fx", "fy", "fz"]),
        rm.transpose() * -f,
        1e-12,
        "FORCE on ground f",
    );
    close3(
        vec_of(&vals, "REQUEST_6", ["tx", "ty", "tz"]),
        rm.transpose() * t_ground,
        1e-12,
        "FORCE on ground t",
    );
}

#[test]
fn general_constraint_force_comes_from_the_equations_of_motion() {
    let model = model_of(DATASET);
    let set = RequestSet::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let o = output(&model);
    let vals = values(&set, &model, &o);
    // Part 3 feels only GCON/9 (and gravity): its constraint wrench is m(a − g) and
    // I_g α + ω × I_g ω about the CM; the force on ground (I = 1) is the opposite, about 1.
    let [p, _, a] = p3(T);
    let f_c = 3.0 * (a - DVec3::new(0.0, 0.0, -9.8));
    let ig = DMat3::from_diagonal(DVec3::new(1.0, 2.0, 3.0));
    let t_c = ig * AL3 + W3.cross(ig * W3);
    close3(
        vec_of(&vals, "REQUEST_10", ["fx", "fy", "fz"]),
        -f_c,
        1e-12,
        "GCON f",
    );
    close3(
        vec_of(&vals, "REQUEST_10", ["tx", "ty", "tz"]),
        -(t_c + p.cross(f_c)),
        1e-12,
        "GCON t",
    );
}

fn errors(text: &str) -> Vec<(u32, u32, String)> {
    let model = model_of(text);
    match RequestSet::new(&model) {
        Ok(_) => panic!("no error"),
        Err(d) => {
            d.0.iter()
                .map(|e| {
                    let s = e.span.unwrap_or_default();
                    (s.line, s.col, e.message.clone())
                })
                .collect()
        }
    }
}

const SMALL: &str = "t
PART/1, GROUND
MARKER/1, PART=1
PART/2, MASS=1, CM=20, IP=1,1,1
MARKER/20, PART=2
";

#[test]
fn input_errors_are_located_and_name_the_request() {
    let e = errors(&format!("{SMALL}REQUEST/3, D, I=20, J=99\nEND\n"));
    assert_eq!(e.len(), 1);
    assert_eq!((e[0].0, e[0].1), (6, 23));
    assert!(
        e[0].2
            .contains("REQUEST_3 (REQUEST/3, line 6): J marker 99 does not exist"),
        "{e:?}"
    );
    let e = errors(&format!("{SMALL}REQUEST/4, F1=DX(20)\\F2=DX(20,+)\nEND\n"));
    assert_eq!(e.len(), 1);
    assert_eq!((e[0].0, e[0].1), (6, 32));
    assert!(e[0].2.contains("REQUEST_4: syntax error in F2"), "{e:?}");
    let e = errors(&format!(
        "{SMALL}REQUEST/5, FUNCTION=USER(1,2)\\, ROUTINE=lib::f\nEND\n"
    ));
    assert!(e[0].2.contains("REQUEST_5 (REQUEST/5, line 6): FUNCTION calls a USER subroutine, which linkage cannot run"), "{e:?}");
    let e = errors(&format!("{SMALL}REQUEST/5, F3=2*USER(1)\nEND\n"));
    assert!(e[0].2.contains("USER"), "{e:?}");
}

#[test]
fn evaluation_errors_name_request_time_and_function() {
    // A computed id: only evaluation finds that DIFF/4 does not exist (a literal one is an
    // input error of the REQUEST).
    let model = model_of(&format!("{SMALL}REQUEST/9, F1=TIME\\F2=DIF(2+2)\nEND\n"));
    let set = RequestSet::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let o = Output {
        time: 0.25,
        state: State::input(&model),
        velocities: vec![(DVec3::ZERO, DVec3::ZERO)],
        accelerations: vec![(DVec3::ZERO, DVec3::ZERO)],
        reactions: Vec::new(),
    };
    let e = set
        .evaluate(&model, &System::new(&model), &o)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("REQUEST_9 (REQUEST/9, line 6) at time 0.25: F2 = DIF(2+2): "),
        "{e}"
    );
    assert!(e.contains("DIFF"), "{e}");
    let model = model_of(&format!("{SMALL}REQUEST/9, F1=TIME*2\\F5=FZ(20)\nEND\n"));
    let set = RequestSet::new(&model).unwrap_or_else(|e| panic!("{e}"));
    // Nothing connects part 2 to ground: zero force.
    assert_eq!(
        set.evaluate(&model, &System::new(&model), &o),
        Ok(vec![0.5, 0.0])
    );
    assert_eq!(set.columns(), ["REQUEST_9.f1", "REQUEST_9.f5"]);
}
