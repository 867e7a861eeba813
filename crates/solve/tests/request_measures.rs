//! REQUEST function values at a non-trivial pose against values derived by hand: the angle
//! measures AX/AY/AZ, PSI/THETA/PHI (body 3-1-3), YAW/PITCH/ROLL (body 3-2-1), and every
//! element force function (BUSH, FIELD, BEAM, SFORCE, SPDP, VFORCE, VTORQUE, GFORCE, JOINT,
//! JPRIM, MOTION) on I (jflag 0, resolved in a turned RM) and on J (jflag 1, in ground, torque
//! about J's origin) for all eight components FM, FX, FY, FZ, TM, TX, TY, TZ
//! (ADM-REFERENCE §5.3).
//!
//! The state is made by hand: part 2 placed so that its marker 21 sits at J marker 31's axes
//! shifted by d along them (so BUSHING and FIELD deflect by d only), part 3 so that the beam's
//! end 41 sits at 51's axes stretched by δ along x₅₁.

use glam::{DMat3, DVec3};
use linkage_model::Model;
use linkage_solve::constraints::system::System;
use linkage_solve::physics::reactions::Reaction;
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::stages::dynamics::Output;
use linkage_solve::state::{Pose, State};
use std::sync::Arc;

const ELEMENTS: &str = "request measures
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/1, PART = 1
MARKER/31, PART = 1, QP = 0.2, -0.1, 0.4, REULER = 25D, 40D, -60D
MARKER/32, PART = 1, FLOATING
MARKER/33, PART = 1, QP = -0.3, 0.5, 0.1, REULER = -70D, 20D, 15D
MARKER/51, PART = 1, QP = 1, 1, 0, REULER = 10D, 80D, 30D
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2
MARKER/21, PART = 2, QP = 0.1, 0.2, -0.1, REULER = 30D, 50D, 70D
MARKER/22, PART = 2, QP = -0.2, 0.1, 0.3, REULER = 5D, 60D, -30D
PART/3, MASS = 1, CM = 40, IP = 1, 1, 1
MARKER/40, PART = 3
MARKER/41, PART = 3, QP = 0.3, -0.2, 0.1, REULER = -40D, 30D, 100D
BUSHING/1, I = 21, J = 31, K = 100, 200, 300, KT = 10, 20, 30
, FORCE = 1, -2, 3, TORQUE = 0.1, 0.2, -0.3
FIELD/1, I = 21, J = 31
, KMATRIX = 100, 5, 6, 1, 2, 3, 5, 200, 7, 4, 5, 6, 6, 7, 300, 7, 8, 9
, 1, 4, 7, 10, 1, 2, 2, 5, 8, 1, 20, 3, 3, 6, 9, 2, 3, 30
, LENGTH = 0.01, 0, 0.02, 0, 0, 0, FORCE = 0.5, 0, 0, 0, 0.1, 0
SFORCE/1, TRANSLATIONAL, I = 21, J = 31, FUNCTION = 7
SPRINGDAMPER/1, TRANSLATIONAL, I = 21, J = 31, K = 50, LENGTH = 0.01
VFORCE/1, I = 21, JFLOAT = 32, RM = 33, FX = 1\\FY = 2\\FZ = 3
VTORQUE/1, I = 21, JFLOAT = 32, RM = 33, TX = 0.4\\TY = -0.5\\TZ = 0.6
GFORCE/1, I = 21, JFLOAT = 32, RM = 33, FX = -1\\FY = 0.5\\FZ = 2\\TX = 0.3\\TY = 0.2\\TZ = -0.1
BEAM/1, I = 41, J = 51, LENGTH = 0.5, IXX = 2E-5, IYY = 1E-5, IZZ = 2E-5, AREA = 0.01
, EMODULUS = 2E5, GMODULUS = 8E4
JOINT/1, SPHERICAL, I = 22, J = 33
JPRIM/1, INPLANE, I = 41, J = 51
MOTION/1, I = 22, J = 33, X, FUNCTION = 0
";

/// d: where 21 sits in 31's axes; δ: the beam's stretch.
const D: DVec3 = DVec3::new(0.03, -0.02, 0.05);
const STRETCH: f64 = 0.004;
/// Reactions set by hand on the constraints (force, torque on I about I, ground axes).
const JOINT_REACTION: (DVec3, DVec3) = (DVec3::new(1.5, -0.5, 2.0), DVec3::new(0.2, 0.1, -0.4));
const JPRIM_REACTION: (DVec3, DVec3) = (DVec3::new(-0.7, 0.3, 0.9), DVec3::new(-0.1, 0.6, 0.2));
const MOTION_REACTION: (DVec3, DVec3) = (DVec3::new(0.4, 1.1, -0.8), DVec3::new(0.3, -0.2, 0.5));

fn model_of(text: &str) -> Model {
    let ds = linkage_adm::parse_dataset(Arc::from("measures.adm"), text)
        .unwrap_or_else(|e| panic!("{e}"));
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

fn marker_index(m: &Model, id: u64) -> usize {
    m.markers.iter().position(|mk| mk.id == id).unwrap()
}

/// The pose of marker `id`'s part that puts the marker at (p, r) in ground.
fn place(m: &Model, id: u64, p: DVec3, r: DMat3) -> Pose {
    let mk = &m.markers[marker_index(m, id)];
    let r_part = r * mk.r_bm.transpose();
    Pose {
        p: p - r_part * mk.p_bm,
        r: r_part,
    }
}

fn element(m: &Model, name: &str) -> usize {
    m.constraints
        .iter()
        .position(|c| c.origin.name == name)
        .unwrap_or_else(|| panic!("no {name}"))
}

fn output(m: &Model) -> Output {
    let (p31, r31) = m.marker_in_ground(marker_index(m, 31));
    let (p51, r51) = m.marker_in_ground(marker_index(m, 51));
    let part2 = place(m, 21, p31 + r31 * D, r31);
    let part3 = place(m, 41, p51 + (0.5 + STRETCH) * r51.x_axis, r51);
    let reaction = |name: &str, (force, torque): (DVec3, DVec3)| Reaction {
        element: element(m, name),
        force,
        torque,
    };
    Output {
        time: 0.0,
        state: State {
            poses: vec![part2, part3],
            time: 0.0,
            controls: Default::default(),
            elements: Default::default(),
        },
        velocities: vec![(DVec3::ZERO, DVec3::ZERO); 2],
        accelerations: vec![(DVec3::ZERO, DVec3::ZERO); 2],
        reactions: vec![
            reaction("JOINT_1", JOINT_REACTION),
            reaction("JPRIM_1", JPRIM_REACTION),
            reaction("MOTION_1", MOTION_REACTION),
        ],
    }
}

/// Evaluates `functions` as function REQUESTs (eight to a statement) appended to the elements.
fn evaluate(functions: &[String]) -> (Model, Output, Vec<f64>) {
    let mut text = ELEMENTS.to_string();
    for (k, chunk) in functions.chunks(8).enumerate() {
        let fs: Vec<String> = chunk
            .iter()
            .enumerate()
            .map(|(n, f)| format!("F{} = {f}", n + 1))
            .collect();
        text.push_str(&format!("REQUEST/{}, {}\n", 100 + k, fs.join("\\")));
    }
    text.push_str("END\n");
    let m = model_of(&text);
    let set = RequestSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    let o = output(&m);
    let values = set
        .evaluate(&m, &System::new(&m), &o)
        .unwrap_or_else(|e| panic!("{e}"));
    let columns = set.columns();
    let picked = (0..functions.len())
        .map(|k| {
            let name = format!("REQUEST_{}.f{}", 100 + k / 8, k % 8 + 1);
            let at = columns
                .iter()
                .position(|c| *c == name)
                .unwrap_or_else(|| panic!("no column {name} in {columns:?}"));
            values[at]
        })
        .collect();
    (m, o, picked)
}

fn frame(m: &Model, o: &Output, id: u64) -> (DVec3, DMat3) {
    let mk = &m.markers[marker_index(m, id)];
    let pose = o.state.pose(mk.body);
    (pose.p + pose.r * mk.p_bm, pose.r * mk.r_bm)
}

/// Body 3-1-3 angles of `r` (= Rz(ψ) Rx(θ) Rz(φ), θ in (0, π)): R₁₃ = sin ψ sin θ,
/// R₂₃ = −cos ψ sin θ, R₃₁ = sin θ sin φ, R₃₂ = sin θ cos φ, R₃₃ = cos θ.
fn body313(r: DMat3) -> [f64; 3] {
    [
        r.z_axis.x.atan2(-r.z_axis.y),
        r.z_axis.z.acos(),
        r.x_axis.z.atan2(r.y_axis.z),
    ]
}

/// Body 3-2-1 angles of `r` (= Rz(yaw) Ry(pitch) Rx(roll)): R₃₁ = −sin pitch,
/// R₂₁ = sin yaw cos pitch, R₁₁ = cos yaw cos pitch, R₃₂ = cos pitch sin roll,
/// R₃₃ = cos pitch cos roll.
fn body321(r: DMat3) -> [f64; 3] {
    [
        r.x_axis.y.atan2(r.x_axis.x),
        (-r.x_axis.z).asin(),
        r.y_axis.z.atan2(r.z_axis.z),
    ]
}

#[test]
fn angle_measures_at_a_generic_pose_match_their_definitions() {
    let functions: Vec<String> = [
        "AX(22, 33)",
        "AY(22, 33)",
        "AZ(22, 33)",
        "PSI(22, 33)",
        "THETA(22, 33)",
        "PHI(22, 33)",
        "YAW(22, 33)",
        "PITCH(22, 33)",
        "ROLL(22, 33)",
        "PSI(22)",
        "THETA(22)",
        "PHI(22)",
        "YAW(22)",
        "PITCH(22)",
        "ROLL(22)",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let (m, o, v) = evaluate(&functions);
    let (_, ri) = frame(&m, &o, 22);
    let (_, rj) = frame(&m, &o, 33);
    let rel = rj.transpose() * ri;
    // ADM-REFERENCE §5.3: AX = atan2(−z_i·y_j, z_i·z_j), AY = atan2(z_i·x_j, z_i·z_j),
    // AZ = atan2(x_i·y_j, x_i·x_j).
    let (xi, zi) = (ri.x_axis, ri.z_axis);
    let expected_a = [
        (-zi.dot(rj.y_axis)).atan2(zi.dot(rj.z_axis)),
        zi.dot(rj.x_axis).atan2(zi.dot(rj.z_axis)),
        xi.dot(rj.y_axis).atan2(xi.dot(rj.x_axis)),
    ];
    let e313 = body313(rel);
    let e321 = body321(rel);
    let g313 = body313(ri);
    let g321 = body321(ri);
    // The angles reproduce the rotation (so the extraction above is right) and are not trivial.
    let rebuilt = DMat3::from_rotation_z(e313[0])
        * DMat3::from_rotation_x(e313[1])
        * DMat3::from_rotation_z(e313[2]);
    assert!((0..3).all(|c| (rebuilt.col(c) - rel.col(c)).length() < 1e-12));
    let rebuilt = DMat3::from_rotation_z(e321[0])
        * DMat3::from_rotation_y(e321[1])
        * DMat3::from_rotation_x(e321[2]);
    assert!((0..3).all(|c| (rebuilt.col(c) - rel.col(c)).length() < 1e-12));
    let expected: Vec<f64> = expected_a
        .into_iter()
        .chain(e313)
        .chain(e321)
        .chain(g313)
        .chain(g321)
        .collect();
    for ((f, got), want) in functions.iter().zip(&v).zip(&expected) {
        assert!(want.abs() > 0.05, "{f}: a trivial angle {want}");
        // Radians, to rounding.
        assert!((got - want).abs() < 1e-12, "{f}: {got} vs {want}");
    }
}

/// The eight components of a wrapper `(force, torque)` resolved in `r`: FM, FX, FY, FZ, TM,
/// TX, TY, TZ.
fn components(f: DVec3, t: DVec3, r: DMat3) -> [f64; 8] {
    let (fr, tr) = (r.transpose() * f, r.transpose() * t);
    [f.length(), fr.x, fr.y, fr.z, t.length(), tr.x, tr.y, tr.z]
}

#[test]
fn element_force_functions_give_the_loads_on_i_and_on_j_with_their_signs() {
    let m0 = model_of(&format!("{ELEMENTS}END\n"));
    let o0 = output(&m0);
    let (p21, r21) = frame(&m0, &o0, 21);
    let (p31, r31) = frame(&m0, &o0, 31);
    let (_, r33) = frame(&m0, &o0, 33);
    let (p41, _) = frame(&m0, &o0, 41);
    let (p51, r51) = frame(&m0, &o0, 51);
    let (p22, _) = frame(&m0, &o0, 22);
    assert!((0..3).all(|c| (r21.col(c) - r31.col(c)).length() < 1e-12));
    let to_ground = |v: [f64; 3]| r31 * DVec3::from_array(v);
    // The loads on I (ground axes), each from its law at q = (d, 0, 0, 0), q̇ = 0:
    // BUSHING: F = −K d + FORCE, T = TORQUE (along J's axes).
    let bush = (
        to_ground([1.0 - 100.0 * D.x, -2.0 - 200.0 * D.y, 3.0 - 300.0 * D.z]),
        to_ground([0.1, 0.2, -0.3]),
    );
    // FIELD: [F; T] = −K (q − LENGTH) + FORCE, K symmetric as written.
    let k: [[f64; 6]; 6] = [
        [100.0, 5.0, 6.0, 1.0, 2.0, 3.0],
        [5.0, 200.0, 7.0, 4.0, 5.0, 6.0],
        [6.0, 7.0, 300.0, 7.0, 8.0, 9.0],
        [1.0, 4.0, 7.0, 10.0, 1.0, 2.0],
        [2.0, 5.0, 8.0, 1.0, 20.0, 3.0],
        [3.0, 6.0, 9.0, 2.0, 3.0, 30.0],
    ];
    let dq = [D.x - 0.01, D.y, D.z - 0.02, 0.0, 0.0, 0.0];
    let preload = [0.5, 0.0, 0.0, 0.0, 0.1, 0.0];
    let load: Vec<f64> = (0..6)
        .map(|r| preload[r] - (0..6).map(|c| k[r][c] * dq[c]).sum::<f64>())
        .collect();
    let field = (
        to_ground([load[0], load[1], load[2]]),
        to_ground([load[3], load[4], load[5]]),
    );
    // SFORCE: 7 along J→I (repelling); SPRINGDAMPER: −50 (|d| − 0.01) along J→I.
    let u = (p21 - p31).normalize();
    let sforce = (7.0 * u, DVec3::ZERO);
    let spdp = (-50.0 * (D.length() - 0.01) * u, DVec3::ZERO);
    // VFORCE, VTORQUE, GFORCE: components along RM = 33.
    let vforce = (r33 * DVec3::new(1.0, 2.0, 3.0), DVec3::ZERO);
    let vtorque = (DVec3::ZERO, r33 * DVec3::new(0.4, -0.5, 0.6));
    let gforce = (
        r33 * DVec3::new(-1.0, 0.5, 2.0),
        r33 * DVec3::new(0.3, 0.2, -0.1),
    );
    // BEAM stretched by δ: −E A δ / L along x₅₁.
    let beam = (-2e5 * 0.01 * STRETCH / 0.5 * r51.x_axis, DVec3::ZERO);
    // (function name and id, load on I, I origin, J origin: the J marker's, or I's for JFLOAT)
    let cases = [
        ("BUSH(1", bush, p21, p31),
        ("FIELD(1", field, p21, p31),
        ("SFORCE(1", sforce, p21, p31),
        ("SPDP(1", spdp, p21, p31),
        ("VFORCE(1", vforce, p21, p21),
        ("VTORQUE(1", vtorque, p21, p21),
        ("GFORCE(1", gforce, p21, p21),
        ("BEAM(1", beam, p41, p51),
        ("JOINT(1", JOINT_REACTION, p22, frame(&m0, &o0, 33).0),
        ("JPRIM(1", JPRIM_REACTION, p41, p51),
        ("MOTION(1", MOTION_REACTION, p22, frame(&m0, &o0, 33).0),
    ];
    let mut functions = Vec::new();
    let mut expected = Vec::new();
    for (name, (f, t), pi, pj) in cases {
        // On I, resolved in RM = 33.
        for (c, want) in components(f, t, r33).into_iter().enumerate() {
            functions.push(format!("{name}, 0, {}, 33)", c + 1));
            expected.push(want);
        }
        // On J: −F, and the torque about J's origin −T − (P_i − P_j) × F; ground axes (rm 0).
        let (fj, tj) = (-f, -t - (pi - pj).cross(f));
        for (c, want) in components(fj, tj, DMat3::IDENTITY).into_iter().enumerate() {
            functions.push(format!("{name}, 1, {}, 0)", c + 1));
            expected.push(want);
        }
    }
    let (_, _, v) = evaluate(&functions);
    let mut wrong = Vec::new();
    for ((f, got), want) in functions.iter().zip(&v).zip(&expected) {
        // Loads of order 1–100 N: rounding only.
        if (got - want).abs() > 1e-10 * (1.0 + want.abs()) {
            wrong.push(format!("{f}: {got} vs {want}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
