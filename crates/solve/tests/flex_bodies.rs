//! FLEX_BODY (linear flexible bodies with modal coordinates, issue 17) in every analysis,
//! against closed forms. The modal data are the analytic modes of a uniform Euler–Bernoulli
//! beam written as MATRIX statements (the layout of `linkage_model::build::flex_bodies`):
//! cantilever modes `φ = cosh βx − cos βx − σ(sinh βx − sin βx)`, free-free modes
//! `φ = cosh βx + cos βx − σ(sinh βx + sin βx)`, both normalised to `∫₀ᴸ φ² dx = L`, so the
//! generalized mass is `ρAL` and the modal stiffness `(βL)⁴·EI/L³`; bending in the y and z
//! planes (square section).
//!
//! Beam (as the FE_PART tests): steel, L = 1 m, 10 mm square: E = 2.1e11 Pa,
//! ρ = 7800 kg/m³, A = 1e-4 m², I = b⁴/12.
//! βL of the cantilever: 1.875104, 4.694091, 7.854757, 10.995541, 14.137168; of the free-free
//! beam: 4.730041, 7.853205, 10.995608 (Blevins, Formulas for Natural Frequency and Mode
//! Shape, table 8-1).

mod common;

use common::analyses::{equilibrium, linear, load};

use common::beam_modes::{
    area, beam_scale, matrix, mode, mode_integral, second_moment, B, CANTILEVER, E, FREE_FREE, L,
    RHO,
};
use glam::DVec3;
use linkage_model::Model;
use linkage_solve::pipeline::verify::verify;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Start};
use linkage_solve::stages::statics::Equilibrium;
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::TAU;
use std::fmt::Write;
use std::sync::Arc;

/// A FLEX_BODY/1 along ground x from the origin with the beam's first `bls` modes in each
/// bending plane (mode order: y plane, z plane, alternating), nodes 1 (x = 0), 2 (x = L/2),
/// 3 (x = L); markers 10 (node 1), 11 (node 3), 13 (node 2), `flex` appended to the
/// FLEX_BODY statement, `extra` statements before END.
fn dataset(bls: &[f64], free: bool, flex: &str, extra: &str) -> String {
    dataset_in_basis(bls, free, flex, extra, None)
}

/// [`dataset`] with the modal coordinates of another basis `q = R·q'` (`R` row-major
/// `nm × nm`): shapes and INVAR3 `·R`, GENSTIFF and INVAR6 `Rᵀ·(·)·R`.
fn dataset_in_basis(
    bls: &[f64],
    free: bool,
    flex: &str,
    extra: &str,
    basis: Option<&[f64]>,
) -> String {
    let (a, i) = (area(), second_moment());
    let m = RHO * a * L;
    let nodes = [0.0, 0.5 * L, L];
    let nm = 2 * bls.len();
    let mut t = vec![0.0; 9 * nm];
    let mut r = vec![0.0; 9 * nm];
    let mut k = vec![0.0; nm * nm];
    let mut gm = vec![0.0; nm * nm];
    let mut i3 = vec![0.0; 3 * nm];
    for (p, bl) in bls.iter().enumerate() {
        for plane in 0..2 {
            let j = 2 * p + plane;
            i3[(1 + plane) * nm + j] = RHO * a * mode_integral(*bl, free);
            k[j * nm + j] = bl.powi(4) * E * i / L.powi(3);
            gm[j * nm + j] = m;
            for (n, x) in nodes.iter().enumerate() {
                let (phi, slope) = mode(*bl, free, *x);
                if plane == 0 {
                    // Bending in y: the x axis turns about +z.
                    t[(3 * n + 1) * nm + j] = phi;
                    r[(3 * n + 2) * nm + j] = slope;
                } else {
                    // Bending in z: the x axis turns about −y.
                    t[(3 * n + 2) * nm + j] = phi;
                    r[(3 * n + 1) * nm + j] = -slope;
                }
            }
        }
    }
    if let Some(rb) = basis {
        let right = |a: &[f64], rows: usize| -> Vec<f64> {
            (0..rows * nm)
                .map(|x| {
                    (0..nm)
                        .map(|i| a[(x / nm) * nm + i] * rb[i * nm + x % nm])
                        .sum()
                })
                .collect()
        };
        let congruent = |a: &[f64]| -> Vec<f64> {
            let ar = right(a, nm);
            (0..nm * nm)
                .map(|x| {
                    (0..nm)
                        .map(|i| rb[i * nm + x / nm] * ar[i * nm + x % nm])
                        .sum()
                })
                .collect()
        };
        t = right(&t, 9);
        r = right(&r, 9);
        i3 = right(&i3, 3);
        k = congruent(&k);
        gm = congruent(&gm);
    }
    let mut s = String::from(
        "flex beam\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1\nMARKER/12, PART = 1, FLOATING\n",
    );
    let _ = writeln!(
        s,
        "FLEX_BODY/1, MATRICES = 1, 2, 3, 4, 5, 6, 7, 8, 9, 10{flex}"
    );
    let selmod: Vec<f64> = (1..=nm).map(|x| x as f64).collect();
    matrix(&mut s, 1, "SELMOD", nm, 1, &selmod);
    matrix(
        &mut s,
        2,
        "SELNOD",
        3,
        4,
        &[1.0, 0.0, 0.0, 0.0, 2.0, 0.5 * L, 0.0, 0.0, 3.0, L, 0.0, 0.0],
    );
    matrix(&mut s, 3, "GENSTIFF", nm, nm, &k);
    matrix(&mut s, 4, "INVAR1", 1, 1, &[m]);
    matrix(&mut s, 5, "INVAR2", 3, 1, &[m * L / 2.0, 0.0, 0.0]);
    matrix(&mut s, 6, "INVAR6", nm, nm, &gm);
    let (ixx, iyy) = (RHO * 2.0 * i * L, m * L * L / 3.0 + RHO * i * L);
    matrix(
        &mut s,
        7,
        "INVAR7",
        3,
        3,
        &[ixx, 0.0, 0.0, 0.0, iyy, 0.0, 0.0, 0.0, iyy],
    );
    matrix(&mut s, 8, "T_MODES", 9, nm, &t);
    matrix(&mut s, 9, "R_MODES", 9, nm, &r);
    matrix(&mut s, 10, "INVAR3", 3, nm, &i3);
    let _ = write!(
        s,
        "MARKER/10, FLEX_BODY = 1, NODE_ID = 1\nMARKER/11, FLEX_BODY = 1, NODE_ID = 3, QP = {L}, 0, 0\n\
         MARKER/13, FLEX_BODY = 1, NODE_ID = 2, QP = {}, 0, 0\n{extra}\nEND\n",
        0.5 * L
    );
    s
}

/// The cantilever: node 1 clamped to ground (the cantilever modes are zero there, so the
/// clamp holds the reference frame).
fn cantilever(bls: &[f64], flex: &str, extra: &str) -> String {
    dataset(
        bls,
        false,
        flex,
        &format!("JOINT/1, FIXED, I = 10, J = 1\n{extra}"),
    )
}

fn node_part(m: &Model, id: u64) -> usize {
    m.flex_bodies[0]
        .nodes
        .iter()
        .find(|n| n.id == id)
        .unwrap()
        .part
}

#[test]
fn cantilever_flex_body_counts_its_modes_plus_six() {
    let (m, d, _) = load(&cantilever(&CANTILEVER[..3], "", ""));
    let b = &m.flex_bodies[0];
    assert_eq!(b.modes.len(), 6);
    assert_eq!(b.gruebler_dof(), 12);
    // Node bodies only for the nodes markers use (all three here).
    assert_eq!(b.nodes.len(), 3);
    let v = verify(&m, &d, &Tolerances::default());
    // 6 modes + 6 − 6 (the clamp).
    assert_eq!(v.gruebler, 6);
    // DOF by rank, with the modal columns in the node equations: the clamp leaves the modes.
    assert_eq!(v.dof, 6);
    assert!(v.redundant.is_empty());
    assert_eq!(v.flex_parts, 1 + 6 + 3);
    assert_eq!(v.flex_rows, 5 * 6 + 6 * 3);
    // Default damping: every frequency below 100 Hz has 1 %, above 10 %.
    for mode in &b.modes {
        let expected = if mode.frequency < 100.0 { 0.01 } else { 0.1 };
        assert_eq!(mode.damping_ratio, expected, "{}", mode.frequency);
    }
}

#[test]
fn cantilever_flex_body_has_the_beam_frequencies_of_the_fe_part() {
    // The FE_PART cantilever of the same beam (21 nodes) against the flex body: the four
    // lowest modes (two per bending plane) agree within 1 %, and both with 1.875², 4.694².
    let lin = linear(&cantilever(&CANTILEVER[..3], ", CRATIO = 0", ""));
    let mut f: Vec<f64> = lin.modes.iter().map(|m| m.frequency).collect();
    f.sort_by(f64::total_cmp);
    assert_eq!(f.len(), 6);
    for (k, bl) in CANTILEVER[..3].iter().enumerate() {
        let exact = bl * bl * beam_scale() / TAU;
        // Exact but for the linearization's stand-in mass of the massless node bodies
        // (1e-8 of the smallest mass).
        for x in &f[2 * k..2 * k + 2] {
            assert!((x / exact - 1.0).abs() < 1e-6, "{x} vs {exact}");
        }
    }
    let fe = fe_cantilever_frequencies();
    for k in 0..4 {
        assert!(
            (f[k] / fe[k] - 1.0).abs() < 0.01,
            "{} vs FE {}",
            f[k],
            fe[k]
        );
    }
    assert_eq!(lin.zero_eigenvalues, 0);
}

/// The four lowest frequencies of the 21-node FE_PART cantilever of the same beam.
fn fe_cantilever_frequencies() -> Vec<f64> {
    let n = 21;
    let (a, i, j) = (area(), second_moment(), 0.1406 * B.powi(4));
    let labels: Vec<String> = (1..=n).map(|k| k.to_string()).collect();
    let coords: Vec<String> = (0..n)
        .map(|k| {
            format!(
                "{}, {}, 0, 0, 0, 0, 0",
                k + 1,
                L * k as f64 / (n - 1) as f64
            )
        })
        .collect();
    let sections: Vec<String> = (0..n)
        .map(|k| format!("{}, {a}, {i}, {i}, 0, {j}", k + 1))
        .collect();
    let text = format!(
        "beam\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1\n\
         FE_PART/3, TYPE = 3DBEAM, NODE_LABELS = {}\n, COORDINATES = {}\n, SECTION = {}\n\
         , MATERIAL = 1\nMATERIAL/1, DENSITY = {RHO}, YOUNGS_MODULUS = {E}, POISSONS_RATIO = 0.3\n\
         MARKER/10, FE_PART = 3, NODE_LABEL = 1\nJOINT/1, FIXED, I = 10, J = 1\nEND\n",
        labels.join(", "),
        coords.join("\n, "),
        sections.join("\n, "),
    );
    let lin = linear(&text);
    let mut f: Vec<f64> = lin.modes.iter().map(|m| m.frequency).collect();
    f.sort_by(f64::total_cmp);
    f.truncate(4);
    f
}

#[test]
fn free_free_flex_body_has_six_zero_frequency_modes() {
    let lin = linear(&dataset(&FREE_FREE, true, ", CRATIO = 0", ""));
    assert_eq!(lin.zero_eigenvalues, 12, "a zero pair per rigid-body mode");
    assert_eq!(lin.expected_zero_eigenvalues, 12);
    let first = FREE_FREE[0].powi(2) * beam_scale() / TAU;
    let mut elastic: Vec<f64> = lin
        .modes
        .iter()
        .map(|m| m.frequency)
        .filter(|f| *f > 1e-4 * first)
        .collect();
    elastic.sort_by(f64::total_cmp);
    assert_eq!(elastic.len(), 6);
    for (k, bl) in FREE_FREE.iter().enumerate() {
        let exact = bl * bl * beam_scale() / TAU;
        for x in &elastic[2 * k..2 * k + 2] {
            assert!((x / exact - 1.0).abs() < 1e-6, "{x} vs {exact}");
        }
    }
}

#[test]
fn tip_load_deflects_the_cantilever_flex_body_by_pl3_over_3ei() {
    // Static tip load P along −y on node 3: Σ φ_i(L)²·P/k_i = 4PL³/EI·Σ 1/(β_iL)⁴, which with
    // the five modes is 0.99968 of P·L³/(3·E·I).
    let p = 0.01;
    let (m, eq) = equilibrium(&cantilever(
        &CANTILEVER,
        "",
        &format!(
            "VFORCE/1, I = 11, JFLOAT = 12, RM = 1, FX = 0, FY = {}, FZ = 0",
            -p
        ),
    ));
    let tip = eq.state.poses[node_part(&m, 3)].p;
    let expected = p * L.powi(3) / (3.0 * E * second_moment());
    assert!(
        (-tip.y / expected - 1.0).abs() < 0.001,
        "{} vs {expected}",
        -tip.y
    );
    // The tip turns by PL²/(2EI) about z (within the modal truncation, 1 %).
    let slope = eq.state.poses[node_part(&m, 3)].r.x_axis.y;
    let expected_slope = p * L * L / (2.0 * E * second_moment());
    assert!(
        (-slope / expected_slope - 1.0).abs() < 0.01,
        "{} vs {expected_slope}",
        -slope
    );
    // The first modal coordinate: φ₁(L)·P/k₁ = 2P/k₁ (mode 1 bends in y, φ₁(L) = 2).
    let b = &m.flex_bodies[0];
    let q1 = (eq.state.poses[b.modes[0].part].p - b.rest).dot(b.axis);
    let k1 = b.modes[0].stiffness;
    assert!((q1 / (-2.0 * p / k1) - 1.0).abs() < 1e-6, "{q1}");
}

#[test]
fn cantilever_flex_body_vibrates_at_its_first_frequency() {
    // Undamped free vibration from DMODE: q₁(t) = q₀·cos(ω₁t), the tip at 2·q₁.
    let q0 = 1e-3;
    let text = cantilever(
        &CANTILEVER[..2],
        &format!(", CRATIO = 0, DMODE = {q0}, 0, 0, 0"),
        "REQUEST/1, DISPLACEMENT, I = 11, J = 1\nREQUEST/2, F2 = DY(11, 1)",
    );
    let (m, d, f) = load(&text);
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    assert!(a.failure().is_none());
    let omega = CANTILEVER[0].powi(2) * beam_scale();
    let period = TAU / omega;
    let times: Vec<f64> = (0..=8).map(|k| period * k as f64 / 8.0).collect();
    let settings = IntegratorSettings {
        error: 1e-6,
        ..Default::default()
    };
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    let sim = r.simulation.unwrap_or_else(|| panic!("{:?}", r.error));
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let b = &m.flex_bodies[0];
    let tip = node_part(&m, 3);
    let requests = linkage_solve::physics::requests::RequestSet::new(&m).unwrap();
    for (k, o) in sim.outputs.iter().enumerate() {
        // REQUESTs on the node marker 11 (at the tip node) follow the node.
        let values = requests.evaluate(&m, &a.system, o).unwrap();
        assert!(
            (values[1] - o.state.poses[tip].p.y).abs() < 1e-15,
            "{values:?}"
        );
        assert!(
            (values[6] - o.state.poses[tip].p.y).abs() < 1e-15,
            "{values:?}"
        );
        let q = (o.state.poses[b.modes[0].part].p - b.rest).dot(b.axis);
        let expected = q0 * (omega * times[k]).cos();
        assert!(
            (q - expected).abs() < 0.02 * q0,
            "t = {}: q = {q} vs {expected}",
            times[k]
        );
        // The node equation holds along the run: y_tip = Σ φ_j(L)·q_j over the y-plane modes
        // (2·q₁ − 2·q₃, the second barely excited).
        let y = o.state.poses[tip].p.y;
        let q3 = (o.state.poses[b.modes[2].part].p - b.rest).dot(b.axis);
        assert!(q3.abs() < 1e-3 * q0, "q3 = {q3}");
        assert!(
            (y - 2.0 * q + 2.0 * q3).abs() < 1e-6 * q0,
            "tip {y} vs 2(q1 − q3) = {}",
            2.0 * (q - q3)
        );
    }
}

#[test]
fn missing_modal_data_file_refuses_naming_the_file() {
    let text = "t\nPART/1, GROUND\nMARKER/1, PART = 1\nFLEX_BODY/1, MNF_FILE = 'wing.mnf'\n\
                MARKER/2, FLEX_BODY = 1, NODE_ID = 4\nEND\n";
    let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap();
    let f = linkage_solve::coverage::findings(&ds);
    assert_eq!(f.len(), 1, "{f:?}");
    assert_eq!(f[0].element, "FLEX_BODY/1");
    assert!(f[0].detail.contains("'wing.mnf'"), "{}", f[0].detail);
    assert!(f[0].refuses(linkage_solve::coverage::Analysis::Ic));
    assert_eq!(f[0].span.line, 4);
    // A MATRIX FILE the flex body lists, missing: named too.
    let text = "t\nPART/1, GROUND\nFLEX_BODY/1, MATRICES = 5\nMATRIX/5, FILE = 'modes.mtx', NAME = GENSTIFF\nEND\n";
    let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap();
    let f = linkage_solve::coverage::findings(&ds);
    let flex: Vec<_> = f.iter().filter(|x| x.element == "FLEX_BODY/1").collect();
    assert_eq!(flex.len(), 1, "{f:?}");
    assert!(flex[0].detail.contains("'modes.mtx'"), "{}", flex[0].detail);
    assert!(flex[0].refuses(linkage_solve::coverage::Analysis::Simulate));
}

#[test]
fn cratio_expression_of_fxfreq_gives_each_mode_its_damping_ratio() {
    // CRATIO = STEP(FXFREQ, 10, 0.02, 100, 0.05): the cubic STEP between 10 and 100 Hz.
    let text = cantilever(
        &CANTILEVER[..2],
        ", CRATIO = STEP(FXFREQ, 10, 0.02, 100, 0.05) + 0*FXMODE",
        "",
    );
    let step = |f: f64| {
        let d = ((f - 10.0) / 90.0).clamp(0.0, 1.0);
        0.02 + 0.03 * d * d * (3.0 - 2.0 * d)
    };
    let (m, _, _) = load(&text);
    for mode in &m.flex_bodies[0].modes {
        let expected = step(mode.frequency);
        assert!((mode.damping_ratio - expected).abs() < 1e-12, "{mode:?}");
    }
    // The linearization sees them: ζ of each mode (c = 2ζωm on the modal coordinate).
    let lin = linear(&text);
    for mode in &lin.modes {
        let expected = step(mode.frequency);
        assert!(
            (mode.damping_ratio / expected - 1.0).abs() < 1e-3,
            "{} vs {expected}",
            mode.damping_ratio
        );
    }
}

#[test]
fn flex_body_input_errors_name_the_element() {
    let errors = |text: &str| {
        let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap();
        match linkage_model::build_model(&ds) {
            Ok(_) => panic!("built"),
            Err(e) => e.to_string(),
        }
    };
    let base = cantilever(&CANTILEVER[..1], "", "");
    let e = errors(&base.replace("NODE_ID = 3", "NODE_ID = 7"));
    assert!(e.contains("has no node 7"), "{e}");
    let e = errors(&base.replace("DMODE", "X").replace(
        "FLEX_BODY/1, MATRICES = 1, 2, 3, 4, 5, 6, 7, 8, 9, 10",
        "FLEX_BODY/1, MATRICES = 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, DMODE = 1, 2, 3",
    ));
    assert!(e.contains("DMODE needs 2 values"), "{e}");
    let e = errors(&base.replace("MATRICES = 1, 2, 3,", "MATRICES = 1, 2,"));
    assert!(e.contains("no matrix named GENSTIFF"), "{e}");
}

/// The equilibrium's changes written into the dataset (as `static --save` does), read back
/// and assembled: every body's pose within `1e-9` (length) and `1e-9` rad of the equilibrium.
fn assert_saved_pose_reads_back(text: &str) -> String {
    let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap();
    let (m, eq) = equilibrium(text);
    let poses: Vec<_> = eq.state.poses.iter().map(|p| (p.p, p.r)).collect();
    let changes = linkage_model::saved::saved_changes(&ds, &m, &poses);
    let saved = linkage_adm::writer::write_changes(&ds, &changes.parts, &changes.arguments)
        .unwrap_or_else(|e| panic!("{e}"));
    let (m2, d2, f2) = load(&saved);
    assert_eq!(m2.parts.len(), m.parts.len());
    let a = Assembled::new(&m2, &d2, &f2, &Tolerances::default());
    assert!(a.failure().is_none(), "{:?}", a.failure());
    // Modal coordinates: `(p − rest)·axis` of each mode body (its rest point is the BCS
    // origin as read, so the mode bodies themselves are elsewhere).
    let (b, b2) = (&m.flex_bodies[0], &m2.flex_bodies[0]);
    for (j, (mode, mode2)) in b.modes.iter().zip(&b2.modes).enumerate() {
        let q = (eq.state.poses[mode.part].p - b.rest).dot(b.axis);
        let q2 = (a.state().poses[mode2.part].p - b2.rest).dot(b2.axis);
        assert!(
            (q - q2).abs() < 1e-9 * q.abs().max(1e-9),
            "q{}: {q2} vs {q}",
            j + 1
        );
    }
    for (k, (want, got)) in eq.state.poses.iter().zip(&a.state().poses).enumerate() {
        if b.modes.iter().any(|mode| mode.part == k) {
            continue;
        }
        let turn = largest_difference(want.r.transpose() * got.r, glam::DMat3::IDENTITY);
        assert!(
            (want.p - got.p).length() < 1e-9 && turn < 1e-9,
            "{}: {:?} vs {:?}",
            m.parts[k].origin.name,
            got,
            want
        );
    }
    saved
}

#[test]
fn saved_flex_body_equilibrium_reads_back_with_its_pose_and_dmode() {
    // Clamped to a ground marker turned 30° about z and moved up 0.1 m: the assembly moves
    // the reference frame there; a tip load bends the modes. The saved dataset has the
    // reference frame's QG/REULER and DMODE, and assembles at the equilibrium pose.
    let text = dataset(
        &CANTILEVER[..2],
        false,
        ", CRATIO = 0",
        "MARKER/5, PART = 1, QP = 0, 0.1, 0, REULER = 30D, 0, 0\n\
         JOINT/1, FIXED, I = 10, J = 5\n\
         VFORCE/1, I = 11, JFLOAT = 12, RM = 1, FX = 0, FY = -0.05, FZ = 0",
    );
    let saved = assert_saved_pose_reads_back(&text);
    let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), &saved).unwrap();
    let flex = ds
        .statements
        .iter()
        .find(|s| s.keyword == "FLEX_BODY")
        .unwrap();
    for key in ["QG", "REULER", "DMODE"] {
        assert!(flex.arg(key).is_some(), "{key} not written:\n{saved}");
    }
}

/// The largest entry of `a − b`.
fn largest_difference(a: glam::DMat3, b: glam::DMat3) -> f64 {
    (a - b)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()))
}

#[test]
fn weight_bends_the_cantilever_flex_body_by_rho_a_g_l4_over_8ei() {
    // The weight's modal load gᵀ·A·I3_j (INVAR3 = ρA∫φ_j): the tip deflects
    // Σ φ_j(L)·ρAg∫φ_j/k_j, which with the five modes is 1.0000147 of ρ·A·g·L⁴/(8·E·I)
    // (the series in closed form; the z-plane modes stay unloaded).
    let g = 9.80665;
    let (m, eq) = equilibrium(&cantilever(&CANTILEVER, "", "ACCGRAV/, JGRAV = -9.80665"));
    let tip = eq.state.poses[node_part(&m, 3)].p;
    let closed = RHO * area() * g * L.powi(4) / (8.0 * E * second_moment());
    let series: f64 = CANTILEVER
        .iter()
        .map(|bl| {
            let k = bl.powi(4) * E * second_moment() / L.powi(3);
            mode(*bl, false, L).0 * RHO * area() * g * mode_integral(*bl, false) / k
        })
        .sum();
    assert!(
        (series / closed - 1.0000147).abs() < 1e-6,
        "{}",
        series / closed
    );
    assert!(
        (-tip.y / series - 1.0).abs() < 1e-6,
        "{} vs {series} ({} of ρAgL⁴/8EI)",
        -tip.y,
        -tip.y / closed
    );
    assert!(tip.z.abs() < 1e-9 * closed, "{}", tip.z);
    // Without INVAR3 (INVARIANTS switch 3 off) the weight loads no mode.
    let off = "T:T:F:T:T:T:T:T:T";
    let (m, eq) = equilibrium(&cantilever(
        &CANTILEVER,
        &format!(", INVARIANTS = {off}"),
        "ACCGRAV/, JGRAV = -9.80665",
    ));
    assert!(eq.state.poses[node_part(&m, 3)].p.y.abs() < 1e-12);
}

#[test]
fn full_modal_matrices_of_a_mixed_basis_give_the_same_frequencies_and_deflection() {
    // Four cantilever modes (y1, z1, y2, z2) written in the basis q = R·q' that mixes y1 with
    // y2 and z1 with z2 (not orthogonal): GENSTIFF and INVAR6 are full. linkage integrates
    // the principal basis of (K', M'): the frequencies and a tip deflection are those of the
    // orthonormal modes (to rounding, 1e-9), and the reported q' are R⁻¹·q.
    #[rustfmt::skip]
    let mix = [
        1.0, 0.0, 0.6, 0.0,
        0.0, 1.0, 0.0, -0.4,
        0.3, 0.0, 1.0, 0.0,
        0.0, 0.5, 0.0, 2.0,
    ];
    let plain = cantilever(&CANTILEVER[..2], ", CRATIO = 0", "");
    let mixed = dataset_in_basis(
        &CANTILEVER[..2],
        false,
        ", CRATIO = 0",
        "JOINT/1, FIXED, I = 10, J = 1\n",
        Some(&mix),
    );
    let (m, _, _) = load(&mixed);
    assert!(m.flex_bodies[0].basis.is_some());
    let freqs = |text: &str| {
        let mut f: Vec<f64> = linear(text).modes.iter().map(|m| m.frequency).collect();
        f.sort_by(f64::total_cmp);
        f
    };
    let (a, b) = (freqs(&plain), freqs(&mixed));
    assert_eq!(a.len(), 4);
    for (x, y) in a.iter().zip(&b) {
        assert!((x / y - 1.0).abs() < 1e-9, "{a:?} vs {b:?}");
    }
    let load_tip = "VFORCE/1, I = 11, JFLOAT = 12, RM = 1, FX = 0, FY = -0.01, FZ = 0.005";
    let (m1, e1) = equilibrium(&plain.replace("END\n", &format!("{load_tip}\nEND\n")));
    let (m2, e2) = equilibrium(&mixed.replace("END\n", &format!("{load_tip}\nEND\n")));
    let (t1, t2) = (
        e1.state.poses[node_part(&m1, 3)].p,
        e2.state.poses[node_part(&m2, 3)].p,
    );
    assert!(
        (t1 - t2).length() < 1e-9 * (t1 - DVec3::new(L, 0.0, 0.0)).length(),
        "{t1} vs {t2}"
    );
    // The dataset's coordinates: q = R·q', so q' = R⁻¹·q; check R·q' = q.
    let q_of = |m: &Model, e: &Equilibrium| {
        let b = &m.flex_bodies[0];
        let eta: Vec<f64> = b
            .modes
            .iter()
            .map(|x| (e.state.poses[x.part].p - b.rest).dot(b.axis))
            .collect();
        b.coordinates(&eta)
    };
    let (q, q_mixed) = (q_of(&m1, &e1), q_of(&m2, &e2));
    for i in 0..4 {
        let back: f64 = (0..4).map(|j| mix[i * 4 + j] * q_mixed[j]).sum();
        assert!(
            (back - q[i]).abs() < 1e-9 * q[i].abs().max(1e-12),
            "q{}: {back} vs {}",
            i + 1,
            q[i]
        );
    }
}
