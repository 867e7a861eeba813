use linkage_model::Model;
use linkage_solve::drivers::ExpressionDrivers;
use linkage_solve::explain::{explain, Explanation};
use linkage_solve::tolerances::Tolerances;
use linkage_solve::verify::{verify, Verification};
use std::path::Path;

fn load_text(name: &str, text: &str) -> Model {
    let ds =
        linkage_adm::parse_dataset(name.into(), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model
}

fn load(name: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../mechanisms")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    load_text(name, &text)
}

fn run(m: &Model) -> (Verification, Explanation) {
    let d = ExpressionDrivers::new(m).unwrap();
    let tol = Tolerances::default();
    let v = verify(m, &d, &tol);
    let t = std::time::Instant::now();
    let e = explain(m, &d, &tol, &v);
    eprintln!("explain took {:?}", t.elapsed());
    (v, e)
}

fn dump(m: &Model, e: &Explanation) {
    eprintln!(
        "mobility {:?} generic {:?} singular {} trials {}/{}",
        e.mobility.at_input,
        e.mobility.generic,
        e.mobility.singular,
        e.mobility.assembled_trials,
        e.mobility.trials
    );
    for r in &e.reactions {
        eprintln!(
            "  {} det {:?} indet {:?}",
            m.constraints[r.element].origin.name,
            r.determinate.iter().map(|d| d.label()).collect::<Vec<_>>(),
            r.indeterminate
                .iter()
                .map(|d| d.label())
                .collect::<Vec<_>>()
        );
    }
    for (k, p) in e.suggestions.iter().enumerate() {
        let ch: Vec<String> = p
            .changes
            .iter()
            .map(|c| {
                let (f, t) = c.describe(m);
                format!("{}: {f} -> {t}", m.constraints[c.element].origin.name)
            })
            .collect();
        eprintln!(
            " {}. {} | dof {} red {} cond {:?} indet_after {} nowdet {}",
            k + 1,
            ch.join("; "),
            p.dof_after,
            p.redundant_after,
            p.conditioning,
            p.indeterminate_after.len(),
            p.now_determinate.len()
        );
    }
    for c in &e.conflicts {
        eprintln!(" conflict {:?}", c);
    }
}

#[test]
fn explore() {
    for f in [
        "fourbar.adm",
        "door_two_hinges.adm",
        "bricard.adm",
        "revolute_motion_ic_conflict.adm",
        "fourbar_parallelogram_chain3.adm",
        "fourbar_motion.adm",
        "slider_crank.adm",
        "door_tilted_hinge.adm",
    ] {
        eprintln!("=== {f}");
        let m = load(f);
        let (_, e) = run(&m);
        dump(&m, &e);
    }
    for deg in [0.0, 60.0] {
        eprintln!("=== chain {deg}");
        let m = load_text(
            "chain",
            &linkage_solve::generate::parallelogram_chain(3, deg),
        );
        let (_, e) = run(&m);
        dump(&m, &e);
    }
}

#[test]
fn debug_chain() {
    use linkage_solve::state::State;
    use linkage_solve::verify::rank_analysis;
    let m = load("fourbar_parallelogram_chain3.adm");
    let (v, e) = run(&m);
    let s = e.mobility.regular_state.clone().unwrap();
    let input = State::input(&m);
    for k in 0..m.parts.len() {
        eprintln!("part {k} dp {:?}", s.poses[k].p - input.poses[k].p);
    }
    let mut mx: f64 = 0.0;
    for r in 0..v.system.rows.len() {
        mx = mx.max(v.system.residual(r, &s, 0.0).abs());
    }
    eprintln!("max residual {mx:e}");
    let ra = rank_analysis(
        &v.system,
        &s,
        &v.topology,
        m.characteristic_length,
        &Tolerances::default(),
    );
    eprintln!(
        "rank {} redundant {:?}",
        ra.rank,
        ra.redundant.iter().map(|r| (r.0, r.1)).collect::<Vec<_>>()
    );
    eprintln!("near ties {:?}", ra.near_tie_admitted);
}

fn svals(v: &Verification, s: &linkage_solve::state::State, l: f64) -> Vec<f64> {
    use linkage_solve::rows::RowGradient;
    let n = 6 * v.moving_parts;
    let rows = v.system.rows.len();
    let mut a = faer::Mat::<f64>::zeros(rows, n);
    let mut g = RowGradient::default();
    for r in 0..rows {
        v.system.gradient(r, s, &mut g);
        let mut nn = 0.0;
        for (b, x) in &g.blocks {
            for c in 0..6 {
                let y = if c < 3 { x[c] * l } else { x[c] };
                nn += y * y;
                a[(r, 6 * b + c)] = y;
            }
        }
        let nn: f64 = nn.sqrt();
        for c in 0..n {
            a[(r, c)] /= nn;
        }
    }
    a.singular_values().unwrap()
}

#[test]
fn debug_chain_sv() {
    use linkage_solve::state::State;
    let m = load("fourbar_parallelogram_chain3.adm");
    let (v, e) = run(&m);
    let s = e.mobility.regular_state.clone().unwrap();
    let l = m.characteristic_length;
    let a = svals(&v, &State::input(&m), l);
    let b = svals(&v, &s, l);
    eprintln!("L {l}\ninput {:?}\ntrial {:?}", &a[30..], &b[30..]);
}
