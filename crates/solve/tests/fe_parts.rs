//! FE_PART (nonlinear finite-element beams, issue 17) in every analysis, against closed forms:
//! the Gruebler count of Adams' chapter (equivalent linear flexible body), small-load
//! cantilever deflection `P·L³/(3·E·I)`, the first bending frequencies of a cantilever
//! (`1.875104²·√(EI/(ρAL⁴))/2π`) and of a free-free beam (`4.730041²·…`, with six zero
//! modes), a pure end moment bending the cantilever into a circle of radius `EI/M` (exact
//! elastica), a tip load's large deflection against Mattiasson's elastica, Rayleigh damping ratios, a hanging 3DCABLE's stretch `ρ·g·L²/(2E)`, and the
//! corpus dataset with its six-node 3DBEAM through verify, ic, static and simulate.
//!
//! Beam: steel, L = 1 m, 10 mm square section: E = 2.1e11 Pa, ρ = 7800 kg/m³,
//! A = 1e-4 m², I = b⁴/12, J = 0.1406·b⁴ (Roark's square-section torsion constant).

mod common;

use common::analyses::{equilibrium, linear, load};
use common::corpus;
use glam::DVec3;
use linkage_model::fe_parts::ChapterCount;
use linkage_model::Model;
use linkage_solve::physics::fe_modes::fe_modes;
use linkage_solve::pipeline::verify::verify;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Start};
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::{PI, TAU};
use std::path::PathBuf;
use std::sync::Arc;

const E: f64 = 2.1e11;
const RHO: f64 = 7800.0;
const B: f64 = 0.01;
const L: f64 = 1.0;
const G: f64 = 9.80665;

fn area() -> f64 {
    B * B
}

fn second_moment() -> f64 {
    B.powi(4) / 12.0
}

/// A straight beam along x from the origin, `n` nodes; `extra` statements appended (markers,
/// joints, loads). Markers 10 (node 1) and 11 (node n, at the tip) are on the beam.
fn beam(n: usize, kind: &str, damping: &str, extra: &str) -> String {
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
    format!(
        "beam\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1\nMARKER/12, PART = 1, FLOATING\n\
         FE_PART/3, TYPE = {kind}, NODE_LABELS = {}\n, COORDINATES = {}\n, SECTION = {}\n\
         , MATERIAL = 1{damping}\n\
         MATERIAL/1, DENSITY = {RHO}, YOUNGS_MODULUS = {E}, POISSONS_RATIO = 0.3\n\
         MARKER/10, FE_PART = 3, NODE_LABEL = 1\nMARKER/11, FE_PART = 3, NODE_LABEL = {n}, QP = {L}, 0, 0\n\
         {extra}\nEND\n",
        labels.join(", "),
        coords.join("\n, "),
        sections.join("\n, "),
    )
}

/// A cantilever clamped at node 1 (FIXED joint to ground), `extra` appended.
fn cantilever(n: usize, damping: &str, extra: &str) -> String {
    beam(
        n,
        "3DBEAM",
        damping,
        &format!("JOINT/1, FIXED, I = 10, J = 1\n{extra}"),
    )
}

fn node(m: &Model, label: u64) -> usize {
    let p = &m.fe_parts[0];
    p.nodes.iter().find(|n| n.label == label).unwrap().part
}

/// `√(EI/(ρAL⁴))`, the frequency scale of a uniform beam (rad/s per unit eigenvalue).
fn beam_scale() -> f64 {
    (E * second_moment() / (RHO * area() * L.powi(4))).sqrt()
}

#[test]
fn cantilever_counts_as_an_equivalent_flexible_body_per_the_chapter() {
    let (m, d, _) = load(&cantilever(21, "", ""));
    // Markers on nodes 1 and 21: 20 normal modes + 2·6 constraint modes + 6 rigid-body
    // modes − 6 for the fixed joint.
    let modes = fe_modes(&m, 0, 20);
    assert_eq!(modes.boundary_labels, [1, 21]);
    assert_eq!(modes.count, ChapterCount::new(21, 2, 6, 20));
    assert_eq!(modes.count.total() as i64 - 6, 20 + 12 + 6 - 6);
    // The environment variable's value, passed as a parameter: 8 normal modes.
    assert_eq!(fe_modes(&m, 0, 8).count.total() as i64 - 6, 8 + 12 + 6 - 6);
    // 114 interior DOF: 200 requested gives 114.
    assert_eq!(fe_modes(&m, 0, 200).count.normal_modes, 19 * 6);
    let v = verify(&m, &d, &Tolerances::default());
    if std::env::var_os(linkage_model::fe_parts::NORMAL_MODES_VARIABLE).is_none() {
        assert_eq!(v.gruebler, 32);
    }
    // The true DOF: 21 node bodies less the clamp.
    assert_eq!(v.dof, 21 * 6 - 6);
    assert_eq!(v.moving_parts - v.fe_nodes, 0);
    // Clamped–clamped (both marker nodes fixed) first mode, 4.730041²·√(EI/ρAL⁴)/2π, as the
    // fixed-boundary normal modes of the Craig–Bampton reduction (lumped mass: within 1 %).
    let f1 = 4.730041f64.powi(2) * beam_scale() / TAU;
    let got = modes.normal_frequencies[0];
    assert!((got / f1 - 1.0).abs() < 0.01, "{got} vs {f1}");
    assert_eq!(modes.normal_frequencies.len(), 20);
}

#[test]
fn small_tip_load_deflects_the_cantilever_by_pl3_over_3ei() {
    let p = 0.01;
    let (m, eq) = equilibrium(&cantilever(
        21,
        "",
        &format!(
            "VFORCE/1, I = 11, JFLOAT = 12, RM = 1, FX = 0, FY = {}, FZ = 0",
            -p
        ),
    ));
    let tip = eq.state.poses[node(&m, 21)].p;
    let expected = p * L.powi(3) / (3.0 * E * second_moment());
    assert!(
        (-tip.y / expected - 1.0).abs() < 0.01,
        "{} vs {expected}",
        -tip.y
    );
    assert_eq!(eq.stability.map(|s| s.0), Some(true));
}

#[test]
fn distributed_fe_load_deflects_the_cantilever_by_wl4_over_8ei() {
    // FE_LOAD: w per unit length along ground −y, lumped on the nodes by their tributary
    // lengths; the tip deflects w·L⁴/(8·E·I) (lumped instead of consistent nodal loads:
    // h²/(3L²) = 0.08 % off with 20 elements).
    let w = 0.02;
    let (m, eq) = equilibrium(&cantilever(
        21,
        "",
        &format!("FE_LOAD/1, FE_PART = 3, RM = 1, FY = -{w}"),
    ));
    let tip = eq.state.poses[node(&m, 21)].p;
    let expected = w * L.powi(4) / (8.0 * E * second_moment());
    assert!(
        (-tip.y / expected - 1.0).abs() < 0.01,
        "{} vs {expected}",
        -tip.y
    );
}

#[test]
fn cantilever_first_bending_frequency_is_1_875_squared_times_the_beam_scale() {
    let lin = linear(&cantilever(21, "", ""));
    let f1 = 1.875104f64.powi(2) * beam_scale() / TAU;
    // Two bending planes (square section): the two lowest modes.
    for m in &lin.modes[..2] {
        assert!(
            (m.frequency / f1 - 1.0).abs() < 0.01,
            "{} vs {f1}",
            m.frequency
        );
    }
    assert_eq!(lin.zero_eigenvalues, 0);
}

#[test]
fn end_moment_bends_the_cantilever_into_a_circle_of_radius_ei_over_m() {
    // M = (π/2)·EI/L: a quarter circle of radius R = EI/M = 2L/π, the tip at (R, R) turned
    // 90° (the elastica of a pure moment is exactly a circle).
    let ei = E * second_moment();
    let moment = PI / 2.0 * ei / L;
    let (m, eq) = equilibrium(&cantilever(
        21,
        "",
        &format!("EQUILIBRIUM/MAXIT = 100\nVTORQUE/1, I = 11, JFLOAT = 12, RM = 1, TX = 0, TY = 0, TZ = {moment}"),
    ));
    let k = node(&m, 21);
    let tip = eq.state.poses[k].p;
    let r = ei / moment;
    assert!(
        (tip - DVec3::new(r, r, 0.0)).length() < 1e-3 * L,
        "{tip:?} vs ({r}, {r}, 0)"
    );
    let x_axis = eq.state.poses[k].r.x_axis;
    assert!((x_axis - DVec3::Y).length() < 1e-3, "{x_axis:?}");
}

/// The elastica of a cantilever under a tip load of fixed direction (normal to the undeformed
/// beam): tip displacements `(u/L, v/L)` by `k = P·L²/(E·I)`, from K. Mattiasson, "Numerical
/// results from large deflection beam and frame problems analysed by means of elliptic
/// integrals", IJNME 17 (1981) 145–153, Table I (checked to 5 digits by shooting on
/// `θ'' = −k·cos θ`, `θ(0) = 0`, `θ'(1) = 0`).
const MATTIASSON: [(f64, f64, f64); 4] = [
    (1.0, 0.05643, 0.30172),
    (2.0, 0.16064, 0.49346),
    (5.0, 0.38763, 0.71379),
    (10.0, 0.55500, 0.81061),
];

#[test]
fn tip_loaded_cantilever_follows_mattiassons_elastica() {
    // 20 elements; the load keeps its ground direction (RM = ground marker 1). The beam's
    // stretch (P/EA ≤ 1e-4) and the discretisation stay within 1e-3 of the inextensible
    // elastica's tip displacements (measured: at most 6.3e-4, v/L at PL²/EI = 10).
    let ei = E * second_moment();
    for (k, u, v) in MATTIASSON {
        let p = k * ei / (L * L);
        let (m, eq) = equilibrium(&cantilever(
            21,
            "",
            &format!(
                "EQUILIBRIUM/MAXIT = 200\n\
                 VFORCE/1, I = 11, JFLOAT = 12, RM = 1, FX = 0, FY = {}, FZ = 0",
                -p
            ),
        ));
        let tip = eq.state.poses[node(&m, 21)].p;
        let (got_u, got_v) = ((L - tip.x) / L, -tip.y / L);
        assert!(
            (got_u / u - 1.0).abs() < 1e-3 && (got_v / v - 1.0).abs() < 1e-3,
            "PL²/EI = {k}: (u/L, v/L) = ({got_u}, {got_v}) vs ({u}, {v})"
        );
        assert!(tip.z.abs() < 1e-9 * L, "out of plane: {}", tip.z);
    }
}

#[test]
fn free_free_beam_has_six_zero_frequency_modes() {
    let lin = linear(&beam(21, "3DBEAM", "", ""));
    assert_eq!(lin.dof, 21 * 6);
    assert_eq!(lin.zero_eigenvalues, 12, "a zero pair per rigid-body mode");
    assert_eq!(lin.expected_zero_eigenvalues, 12);
    let mut f: Vec<f64> = lin.modes.iter().map(|m| m.frequency).collect();
    f.sort_by(f64::total_cmp);
    // The six rigid-body modes are the 12 zero eigenvalues of the first-order system (above);
    // the first mode above them is the first free-free bending mode, twice (square section).
    let f1 = 4.730041f64.powi(2) * beam_scale() / TAU;
    let elastic: Vec<f64> = f.into_iter().filter(|x| *x > 1e-4 * f1).collect();
    for x in &elastic[..2] {
        assert!((x / f1 - 1.0).abs() < 0.01, "{x} vs {f1}");
    }
}

#[test]
fn rayleigh_damping_gives_the_mode_its_damping_ratio() {
    // C = β·K: ζ = β·ω/2; C = α·M: ζ = α/(2ω).
    let omega = 1.875104f64.powi(2) * beam_scale();
    let lin = linear(&cantilever(21, ", CRATIOK = 1E-4", ""));
    let m = &lin.modes[0];
    let zeta = 1e-4 * TAU * m.frequency / 2.0;
    assert!(
        (m.damping_ratio / zeta - 1.0).abs() < 0.01,
        "{} vs {zeta}",
        m.damping_ratio
    );
    let lin = linear(&cantilever(21, ", CRATIOM = 2", ""));
    let m = &lin.modes[0];
    let zeta = 2.0 / (2.0 * TAU * m.frequency);
    assert!(
        (m.damping_ratio / zeta - 1.0).abs() < 0.01,
        "{} vs {zeta}",
        m.damping_ratio
    );
    assert!((TAU * m.frequency / omega - 1.0).abs() < 0.01);
}

#[test]
fn hanging_cable_stretches_by_rho_g_l_squared_over_2e() {
    // A vertical 3DCABLE hung from its top node by a SPHERICAL joint, under its own weight:
    // the tip moves down ρ·g·L²/(2E) (exact for the lumped masses too).
    let text = beam(
        11,
        "3DCABLE",
        "",
        "JOINT/1, SPHERICAL, I = 10, J = 1\nACCGRAV/, JGRAV = -9.80665",
    )
    .replace("ACCGRAV/, JGRAV = -9.80665", "ACCGRAV/, IGRAV = 9.80665");
    let (m, eq) = equilibrium(&text);
    let tip = eq.state.poses[node(&m, 11)].p;
    let expected = L + RHO * G * L * L / (2.0 * E);
    assert!(
        (tip.x / expected - 1.0).abs() < 1e-9,
        "{} vs {expected}",
        tip.x
    );
}

#[test]
fn suddenly_loaded_cantilever_swings_about_its_static_deflection() {
    // Undamped, from rest, six nodes: the tip swings about the static deflection δ (its mean
    // over a first-mode period is δ) and is farthest, about 2δ, half a period in (the first
    // mode carries 97 % of δ; the BDF's numerical damping at ERROR = 1e-4 takes ~10 % off the
    // peak, hence the peak's wider bound).
    let p = 0.01;
    let (m, d, f) = load(&cantilever(
        6,
        "",
        &format!(
            "VFORCE/1, I = 11, JFLOAT = 12, RM = 1, FX = 0, FY = {}, FZ = 0",
            -p
        ),
    ));
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    let period = TAU / (1.875104f64.powi(2) * beam_scale());
    let times: Vec<f64> = (0..=40).map(|k| period * k as f64 / 40.0).collect();
    let settings = IntegratorSettings {
        error: 1e-4,
        ..Default::default()
    };
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    let sim = r.simulation.unwrap_or_else(|| panic!("{:?}", r.error));
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let k = node(&m, 6);
    let y: Vec<f64> = sim.outputs.iter().map(|o| -o.state.poses[k].p.y).collect();
    let statics = p * L.powi(3) / (3.0 * E * second_moment());
    let (imax, ymax) = y.iter().enumerate().fold(
        (0, 0.0),
        |acc, (i, v)| if *v > acc.1 { (i, *v) } else { acc },
    );
    let peak = ymax / (2.0 * statics);
    assert!((0.85..1.02).contains(&peak), "peak {ymax} = {peak} × 2δ");
    assert!((19..=21).contains(&imax), "largest at output {imax} of 40");
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    assert!((mean / statics - 1.0).abs() < 0.02, "{mean} vs {statics}");
}

fn corpus_file() -> Option<PathBuf> {
    Some(corpus()?.join("bthornton191__adams_vscode__test__files__test.adm"))
}

/// The corpus dataset plus `extra` before END (its CONTACTs, which the model builder leaves
/// to the analyses' coverage check, play no part here).
fn corpus_text(extra: &str) -> Option<String> {
    let mut text = std::fs::read_to_string(corpus_file()?).unwrap();
    let end = text.rfind("END").unwrap();
    text.insert_str(end, extra);
    Some(text)
}

#[test]
fn corpus_beam_counts_as_the_chapter_says_and_runs() {
    let Some(text) = corpus_text("") else { return };
    let (m, d, f) = load(&text);
    // Six nodes; markers on nodes 1, 4 and 6: 18 constraint modes, 18 interior DOF (so 18 of
    // the 20 normal modes exist), 6 rigid-body modes.
    let modes = fe_modes(&m, 0, 20);
    assert_eq!(modes.boundary_labels, [1, 4, 6]);
    assert_eq!(
        (
            modes.count.normal_modes,
            modes.count.constraint_modes,
            modes.count.total()
        ),
        (18, 18, 42)
    );
    assert_eq!(fe_modes(&m, 0, 10).count.total(), 34);
    let v = verify(&m, &d, &Tolerances::default());
    if std::env::var_os(linkage_model::fe_parts::NORMAL_MODES_VARIABLE).is_none() {
        // PART_3 (6) + the FE part (42), no constraints.
        assert_eq!(v.gruebler, 48);
    }
    assert_eq!(v.dof, 6 + 36);
    // Free fall: every node drops g·t²/2 (g = 9806.65 mm/s²) and the beam stays unstressed.
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    assert!(a.failure().is_none());
    let times = [0.0, 0.05, 0.1];
    let r = run(
        &a,
        &times,
        &IntegratorSettings::default(),
        Start::InitialConditions,
        |_| {},
    );
    let sim = r.simulation.unwrap_or_else(|| panic!("{:?}", r.error));
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let drop = 0.5 * 9806.65 * 0.1 * 0.1;
    let at_end = &sim.outputs[2].state.poses;
    for n in &m.fe_parts[0].nodes {
        let y0 = m.parts[n.part].p_gb.y;
        let y = at_end[n.part].p.y;
        // The integrator's default ERROR (1e-3 over the run).
        assert!(
            (y0 - y - drop).abs() < 1e-3 * drop,
            "node {}: {}",
            n.label,
            y0 - y
        );
    }
    for e in &m.fe_parts[0].elements {
        let (a, b) = (m.fe_parts[0].nodes[e.a].part, m.fe_parts[0].nodes[e.b].part);
        let l = (at_end[b].p - at_end[a].p).length();
        assert!(
            (l / e.length - 1.0).abs() < 1e-9,
            "element stretched: {l} vs {}",
            e.length
        );
    }
}

#[test]
fn corpus_beam_clamped_at_node_1_sags_under_gravity() {
    // Clamp node 1 (marker 2, on node 1 at ground marker 1's place) and fix PART_3 to a new
    // ground marker at its marker 5: a curved cantilever under its weight.
    let Some(text) = corpus_text(
        "MARKER/900, PART = 1, QP = -25, 275, -100\nJOINT/900, FIXED, I = 2, J = 1\n\
         JOINT/901, FIXED, I = 5, J = 900\n",
    ) else {
        return;
    };
    let (m, d, _) = load(&text);
    let v = verify(&m, &d, &Tolerances::default());
    assert_eq!(v.dof, 36 - 6);
    assert!(v.redundant.is_empty() && v.misaligned.is_empty());
    let (m, eq) = equilibrium(&text);
    assert_eq!(eq.stability.map(|s| s.0), Some(true));
    // The tip sags; the clamped node stays.
    let k1 = node(&m, 1);
    assert!((eq.state.poses[k1].p - m.parts[k1].p_gb).length() < 1e-9);
    let k6 = node(&m, 6);
    let sag = m.parts[k6].p_gb.y - eq.state.poses[k6].p.y;
    // Order of magnitude of a straight cantilever of the span (1300 mm) under its weight,
    // w·L⁴/(8·E·Iyy… Izz): bending about z uses Izz = 1.302e5 mm⁴.
    let w = 7.801e-6 * 2500.0 * 9806.65 / 1000.0; // N/mm
    let straight = w * 1300f64.powi(4) / (8.0 * 20700.0 * 1.302083333e5);
    assert!(
        sag > 0.3 * straight && sag < 3.0 * straight,
        "{sag} vs {straight}"
    );
}

#[test]
fn saved_deflected_fe_part_reads_back_at_its_equilibrium() {
    // `static --save`: COORDINATES with the deflected nodes (places and 3-1-3 angles in the
    // BCS) and the markers on nodes at their new places (QP/REULER, or XP/ZP as given); the
    // saved dataset assembles with every node where the equilibrium left it.
    let ei = E * second_moment();
    let text = cantilever(
        6,
        "",
        &format!(
            "MARKER/13, FE_PART = 3, NODE_LABEL = 4, QP = 0.6, 0.01, 0, XP = 0.7, 0.01, 0, \
             ZP = 0.6, 0.01, 1\nEQUILIBRIUM/MAXIT = 100\n\
             VFORCE/1, I = 11, JFLOAT = 12, RM = 1, FX = 0, FY = {}, FZ = 0",
            -2.0 * ei / (L * L)
        ),
    )
    .replace(
        "FE_PART/3,",
        "FE_PART/3, QG = 0.5, 0.2, 0, REULER = 20D, 10D, 0,",
    );
    let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), &text).unwrap();
    let (m, eq) = equilibrium(&text);
    let poses: Vec<_> = eq.state.poses.iter().map(|p| (p.p, p.r)).collect();
    let changes = linkage_model::saved::saved_changes(&ds, &m, &poses);
    let saved = linkage_adm::writer::write_changes(&ds, &changes.parts, &changes.arguments)
        .unwrap_or_else(|e| panic!("{e}"));
    let (m2, d2, f2) = load(&saved);
    let a = Assembled::new(&m2, &d2, &f2, &Tolerances::default());
    assert!(a.failure().is_none(), "{:?}", a.failure());
    for (k, (want, got)) in eq.state.poses.iter().zip(&a.state().poses).enumerate() {
        let turn = largest_difference(want.r.transpose() * got.r, glam::DMat3::IDENTITY);
        assert!(
            (want.p - got.p).length() < 1e-9 && turn < 1e-9,
            "{}: {got:?} vs {want:?}",
            m.parts[k].origin.name
        );
    }
    // The markers on nodes are where they were on the deflected beam.
    for id in [10, 11, 13] {
        let (k1, k2) = (
            m.markers.iter().position(|x| x.id == id).unwrap(),
            m2.markers.iter().position(|x| x.id == id).unwrap(),
        );
        let place = |m: &Model, k: usize, poses: &[linkage_solve::state::Pose]| {
            let mk = &m.markers[k];
            let linkage_model::bodies::Body::Part(b) = mk.body else {
                panic!("on ground")
            };
            (poses[b].p + poses[b].r * mk.p_bm, poses[b].r * mk.r_bm)
        };
        let (p1, r1) = place(&m, k1, &eq.state.poses);
        let (p2, r2) = place(&m2, k2, &a.state().poses);
        assert!((p1 - p2).length() < 1e-9, "marker {id}: {p2:?} vs {p1:?}");
        assert!(largest_difference(r1, r2) < 1e-9, "marker {id}");
    }
    // The tip moved by the elastica's order (PL²/EI = 2: v/L ≈ 0.49), so the test is not
    // passed by an unmoved beam.
    let tip = node(&m, 6);
    assert!((eq.state.poses[tip].p - m.parts[tip].p_gb).length() > 0.3 * L);
}

/// The largest entry of `a − b`.
fn largest_difference(a: glam::DMat3, b: glam::DMat3) -> f64 {
    (a - b)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()))
}
