//! The analyses the FE_PART and FLEX_BODY tests run on a dataset text (named `t.adm`); an input
//! error or a failed analysis panics with its message.
#![allow(dead_code)]

use linkage_model::build::Built;
use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::linearize::{EigenMethod, LinearOptions, Linearization};
use linkage_solve::stages::statics::Equilibrium;
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;

/// The model built from `text`, with the builder's warnings.
pub fn built(text: &str) -> Built {
    let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap_or_else(|e| panic!("{e}"));
    linkage_model::build_model(&ds).unwrap_or_else(|e| panic!("{e}"))
}

/// The model of `text` with its drivers and force elements.
pub fn load(text: &str) -> (Model, ExpressionDrivers, ForceSet) {
    let m = built(text).model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let f = ForceSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    (m, d, f)
}

/// The linearization about the assembled configuration (dense, with damping).
pub fn linear(text: &str) -> Linearization {
    let (m, d, f) = load(text);
    let run = linkage_solve::stages::linearize::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        false,
        LinearOptions {
            damping: true,
            vectors: false,
            method: EigenMethod::Dense,
        },
    );
    run.result.unwrap_or_else(|e| panic!("{e}"))
}

/// The static equilibrium at time 0 (converged).
pub fn equilibrium(text: &str) -> (Model, Equilibrium) {
    let (m, d, f) = load(text);
    let r = linkage_solve::stages::statics::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        &[0.0],
    );
    let eq = r.steps[0].1.clone().unwrap_or_else(|e| panic!("{e}"));
    assert!(eq.converged, "{:?}", eq.worst);
    (m, eq)
}
