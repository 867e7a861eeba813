//! The streamed verify JSON report (`linkage verify --format json`) equals, byte for byte, the
//! value-tree document every other report prints (`serde_json::to_value`, `schema_version`,
//! `to_string_pretty`): on every corpus dataset (with and without `--explain`'s part), on a
//! generated chain with thousands of redundant equations, and as a list of several reports.
//!
//! The corpus is read by relative path; without it the test fails when `CI` is set and skips
//! with a notice otherwise.

mod common;

use linkage_report::verify::VerifyJson;
use linkage_report::verify_stream::{write_documents, StreamedVerify, VerifyDocument};
use linkage_solve::stages::explain::explain;
use linkage_solve::tolerances::Tolerances;
use std::path::Path;

/// The report of `linkage verify` on `path` (with `--explain`'s part when `explained`).
fn report(path: &Path, explained: bool) -> Option<VerifyJson> {
    let loaded = linkage_api::load_model(path, &[], None).ok()?;
    let tol = Tolerances::default();
    let v = linkage_api::verify::verification(&loaded, &tol);
    let mut r = linkage_api::verify::report(&loaded, &v);
    if explained {
        let ex = explain(&loaded.model, &loaded.drivers, &tol, &v);
        r.explain = Some(linkage_report::explain::to_json(&loaded.model, &ex));
    }
    Some(r)
}

/// The value-tree writer the streamed one replaces.
fn value_tree(reports: &[VerifyJson]) -> String {
    let doc = match reports {
        [one] => serde_json::to_value(one).unwrap(),
        many => serde_json::to_value(many).unwrap(),
    };
    serde_json::to_string_pretty(&linkage_report::with_schema_version(doc)).unwrap() + "\n"
}

fn streamed(reports: Vec<VerifyJson>) -> String {
    let docs: Vec<VerifyDocument> = reports
        .into_iter()
        .map(|r| VerifyDocument::Report(Box::new(StreamedVerify::new(r).unwrap())))
        .collect();
    let mut out = Vec::new();
    write_documents(&mut out, &docs).unwrap();
    String::from_utf8(out).unwrap()
}

fn assert_same(name: &str, reports: Vec<VerifyJson>) {
    let want = value_tree(&reports);
    let got = streamed(reports);
    if got != want {
        let at = got
            .bytes()
            .zip(want.bytes())
            .position(|(a, b)| a != b)
            .unwrap_or(got.len().min(want.len()));
        let lo = at.saturating_sub(200);
        panic!(
            "{name}: streamed JSON differs at byte {at}:\n--- streamed\n{}\n--- value tree\n{}",
            &got[lo..(at + 200).min(got.len())],
            &want[lo..(at + 200).min(want.len())]
        );
    }
}

#[test]
fn streamed_verify_json_equals_the_value_tree_on_the_corpus() {
    let Some(dir) = common::corpus() else { return };
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "adm"))
        .collect();
    files.sort();
    let mut compared = 0;
    for (k, f) in files.iter().enumerate() {
        let name = f.display().to_string();
        let Some(r) = report(f, false) else { continue };
        assert_same(&name, vec![r]);
        // The explanation's keys join the document's top level (one in four models).
        if k % 4 == 0 {
            if let Some(r) = report(f, true) {
                assert_same(&format!("{name} --explain"), vec![r]);
            }
        }
        compared += 1;
    }
    assert!(compared >= 60, "only {compared} corpus datasets were read");
}

#[test]
fn streamed_verify_json_equals_the_value_tree_on_a_redundant_chain_and_a_list() {
    let dir = std::env::temp_dir().join(format!("linkage-verify-stream-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let chain = dir.join("chain.adm");
    std::fs::write(
        &chain,
        linkage_solve::generate::parallelogram_chain(1000, 60.0),
    )
    .unwrap();
    let pendulum = dir.join("pendulum.adm");
    std::fs::write(&pendulum, linkage_solve::generate::pendulum_chain(3)).unwrap();
    let r = report(&chain, false).unwrap();
    // 3000 redundant equations, and near ties (rank decisions close to the tolerance).
    assert_eq!(r.redundant.len(), 3000);
    assert!(!r.near_ties.is_empty());
    assert_same("chain", vec![r.clone()]);
    assert_same("two reports", vec![r, report(&pendulum, false).unwrap()]);
    let _ = std::fs::remove_dir_all(&dir);
}
