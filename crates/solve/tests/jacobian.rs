//! Every row type's analytic Jacobian against central finite differences on the 6 tangent
//! coordinates of each part, at a configuration far from assembled (so no term vanishes).

use linkage_solve::constraints::rows::RowGradient;
use linkage_solve::constraints::system::System;
use linkage_solve::state::State;
use std::path::Path;

fn model(name: &str) -> linkage_model::Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let ds = linkage_adm::read_dataset(&path).expect("dataset parses");
    linkage_model::build_model(&ds).expect("model builds").model
}

/// Central difference of row r along part k's coordinate c.
fn fd(sys: &System, s: &State, r: usize, k: usize, c: usize, h: f64) -> f64 {
    let mut e = [0.0; 6];
    e[c] = h;
    let step = |sign: f64| {
        let mut t = s.clone();
        let v = glam::DVec3::new(e[0], e[1], e[2]) * sign;
        let w = glam::DVec3::new(e[3], e[4], e[5]) * sign;
        t.increment(k, v, w);
        sys.residual(r, &t, 0.0)
    };
    (step(1.0) - step(-1.0)) / (2.0 * h)
}

#[test]
fn every_row_type_matches_finite_differences() {
    let m = model("every_row.adm");
    let sys = System::new(&m);
    let s = State::input(&m);
    let mut g = RowGradient::default();
    let mut labels = std::collections::BTreeSet::new();
    let h = 1e-6;
    for r in 0..sys.rows.len() {
        sys.gradient(r, &s, &mut g);
        for k in 0..m.parts.len() {
            let analytic = g
                .blocks
                .iter()
                .find(|(b, _)| *b == k)
                .map_or([0.0; 6], |(_, v)| *v);
            for (c, &a) in analytic.iter().enumerate() {
                let numeric = fd(&sys, &s, r, k, c, h);
                let err = (a - numeric).abs();
                assert!(
                    err < 1e-7 * (1.0 + numeric.abs()),
                    "row {r} ({} {}) part {k} coord {c}: analytic {} vs numeric {numeric}",
                    m.constraints[sys.rows[r].element].origin.name,
                    sys.rows[r].label,
                    a
                );
            }
        }
        labels.insert((
            m.constraints[sys.rows[r].element].description(),
            sys.rows[r].label,
        ));
    }
    // Every joint type, primitive, motion form, coupler and gear contributed rows.
    let kinds: std::collections::BTreeSet<String> =
        labels.iter().map(|(d, _)| d.to_string()).collect();
    for want in [
        "Revolute Joint",
        "Translational Joint",
        "Cylindrical Joint",
        "Spherical Joint",
        "Universal Joint",
        "Hooke Joint",
        "Fixed Joint",
        "Planar Joint",
        "Convel Joint",
        "Rackpin Joint",
        "Screw Joint",
        "Atpoint Primitive",
        "Inline Primitive",
        "Inplane Primitive",
        "Orientation Primitive",
        "Parallel Axes Primitive",
        "Perpendicular Primitive",
        "Rotational Motion",
        "Translational Motion",
        "Coupler",
        "Gear",
    ] {
        assert!(kinds.contains(want), "no rows from {want}: {kinds:?}");
    }
    assert!(labels.len() > 30, "{labels:?}");
}

/// Second derivatives (geometric stiffness) of every row — geometric quantities, Euler-angle
/// motions and general-constraint expressions (measures, ORIENT, TIME) — against central
/// differences of the analytic gradient along the tangent perturbations `(δx, δθ)`: the
/// convention `H[a][b] = ∂(∂Φ/∂q_a)/∂q_b` of `hessian.rs`, antisymmetric part included.
#[test]
fn row_hessians_match_finite_differences_of_gradients() {
    use linkage_solve::constraints::hessian::HessianBlocks;
    let m = model("every_row.adm");
    let sys = System::new(&m);
    let mut s = State::input(&m);
    s.time = 0.3;
    let n = m.parts.len();
    let h = 1e-6;
    let mut checked = 0;
    let mut functions = 0;
    for r in 0..sys.rows.len() {
        let row = &sys.rows[r];
        let mut hb = HessianBlocks::default();
        assert!(
            sys.hessian(r, &s, 1.0, &mut hb),
            "row {r} ({} {}) has no second derivatives",
            m.constraints[row.element].origin.name,
            row.label
        );
        functions += usize::from(row.function.is_some());
        let mut dense = vec![0.0; 36 * n * n];
        let mut trip = Vec::new();
        hb.triplets(1.0, &mut trip);
        for (i, j, v) in trip {
            dense[i * 6 * n + j] += v;
        }
        let grad = |st: &State| {
            let mut g = RowGradient::default();
            sys.gradient(r, st, &mut g);
            let mut full = vec![0.0; 6 * n];
            for (b, v) in &g.blocks {
                full[6 * b..6 * b + 6].copy_from_slice(v);
            }
            full
        };
        for k in 0..n {
            for c in 0..6 {
                let step = |sign: f64| {
                    let mut e = [0.0; 6];
                    e[c] = h * sign;
                    let mut t = s.clone();
                    t.increment(
                        k,
                        glam::DVec3::new(e[0], e[1], e[2]),
                        glam::DVec3::new(e[3], e[4], e[5]),
                    );
                    grad(&t)
                };
                let (gp, gm) = (step(1.0), step(-1.0));
                for i in 0..6 * n {
                    let numeric = (gp[i] - gm[i]) / (2.0 * h);
                    let analytic = dense[i * 6 * n + 6 * k + c];
                    assert!(
                        (analytic - numeric).abs() < 1e-6 * (1.0 + numeric.abs()),
                        "row {r} ({} {}) d(g[{i}])/d(q[{}]): analytic {analytic} vs numeric {numeric}",
                        m.constraints[row.element].origin.name,
                        row.label,
                        6 * k + c
                    );
                }
            }
        }
        checked += 1;
    }
    assert_eq!(checked, sys.rows.len());
    assert_eq!(functions, 3);
}
