//! Control states as columns of the simulate CSV, named after their element: a DIFF decaying
//! as `y = e^{−t/τ}` (τ = 0.5, y(0) = 1) beside a free part.

mod common;
use common::json;

#[test]
fn simulate_csv_has_the_diff_state_decaying_as_exp_minus_t_over_tau() {
    let text = "diff decay\nUNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
                PART/1, GROUND\nPART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
                DIFF/3, FUNCTION = -DIF(3)/0.5, IC = 1\n\
                INTEGRATOR/GSTIFF, ERROR = 1E-8\nEND\n";
    let dir = std::env::temp_dir().join(format!("linkage-columns-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("diff.adm");
    std::fs::write(&f, text).unwrap();
    let csv = dir.join("diff.csv");
    let (code, v) = json(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        "2",
        "--steps",
        "4",
        "--format",
        "json",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{v}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    // No unit: a control state has whatever unit its equation gives it.
    let y = header.iter().position(|h| *h == "DIFF_3.state").unwrap();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 5);
    for r in &rows {
        let exact = (-r[0] / 0.5).exp();
        assert!(
            (r[y] - exact).abs() < 1e-5,
            "t {}: {} vs {exact}",
            r[0],
            r[y]
        );
    }
}
