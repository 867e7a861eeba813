//! `linkage verify A.adm B.adm …`: one report per model, the worst verdict as exit code.

mod common;
use common::{json, root, run};

fn mechanism(name: &str) -> String {
    root()
        .join("mechanisms")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

#[test]
fn several_models_give_one_report_each_and_the_worst_verdict() {
    let (good, bad) = (mechanism("fourbar.adm"), mechanism("door_tilted_hinge.adm"));
    // Text: both reports, in order; the inconsistent door makes the run fail.
    let (code, out, _) = run(&["verify", &good, &bad]);
    assert_eq!(code, 1, "{out}");
    let first = out
        .find("VERIFY MODEL: Adams View model name: fourbar")
        .expect("fourbar");
    let second = out.find("door").expect("door");
    assert!(first < second, "{out}");
    assert_eq!(out.matches("VERIFY MODEL").count(), 2, "{out}");
    // Both consistent: exit 0.
    let (code, _, err) = run(&["verify", &good, &mechanism("pendulum.adm")]);
    assert_eq!(code, 0, "{err}");
    // JSON: an array of the two documents, each with its verdict.
    let (code, v) = json(&["verify", &good, &bad, "--format", "json"]);
    assert_eq!(code, 1);
    let docs = v.as_array().expect("an array");
    assert_eq!(docs.len(), 2);
    assert_eq!(docs[0]["dof"], 1);
    assert!(docs[0]["errors"].as_array().unwrap().is_empty());
    assert!(!docs[1]["errors"].as_array().unwrap().is_empty());
    // A missing file is an input error (exit 2) and the others are still verified.
    let (code, out, err) = run(&["verify", &good, "/no/such.adm"]);
    assert_eq!(code, 2, "{err}");
    assert!(out.contains("VERIFY MODEL"), "{out}");
    assert!(err.contains("/no/such.adm"), "{err}");
    // One model gives one document, as before.
    let (_, v) = json(&["verify", &good, "--format", "json"]);
    assert!(v.is_object(), "{v}");
}
