//! No statement of a real dataset is dropped silently: in every corpus dataset
//! (`../shared/corpus/*.adm`) each statement is modelled, settings or outputs, bookkeeping, or
//! named by [`linkage_solve::coverage::findings`]; every `USER(…)` call is named; a dataset that
//! does not read says why.
//!
//! The corpus is read by relative path; without it the test fails when `CI` is set and skips
//! with a notice elsewhere.

mod common;
use common::corpus;
use linkage_adm::Value;
use linkage_solve::coverage::{findings, statement_use, Reason, Use};
use std::path::PathBuf;
#[test]
fn every_statement_of_every_corpus_dataset_is_modelled_or_named() {
    let Some(dir) = corpus() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "adm"))
        .collect();
    files.sort();
    assert!(files.len() >= 76, "{} datasets", files.len());
    let (mut read, mut statements, mut named) = (0, 0, 0);
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy();
        let ds = match linkage_adm::read_dataset(f) {
            Ok(ds) => ds,
            Err(d) => {
                // Not silent either: the input errors say what is wrong.
                assert!(
                    !d.0.is_empty() && d.0.iter().any(|e| e.is_error()),
                    "{name}"
                );
                continue;
            }
        };
        read += 1;
        let found = findings(&ds);
        for (k, st) in ds.statements.iter().enumerate() {
            statements += 1;
            let of_it: Vec<_> = found.iter().filter(|f| f.statement == k).collect();
            let place = format!("{name}:{}: {}", st.span.line, st.keyword);
            match statement_use(&st.keyword) {
                Use::Named => assert!(!of_it.is_empty(), "{place} is neither modelled nor named"),
                Use::Bookkeeping => assert!(of_it.is_empty(), "{place}"),
                Use::Modelled | Use::Settings => {}
            }
            named += usize::from(!of_it.is_empty());
            let user = st.args.iter().any(|a| {
                a.values.iter().any(|v| {
                    matches!(v, Value::Expr(e) if e.text.to_ascii_uppercase().replace(' ', "").contains("USER("))
                })
            });
            if user && statement_use(&st.keyword) != Use::Bookkeeping {
                assert!(
                    of_it.iter().any(|f| f.reason == Reason::UserSubroutine
                        || f.detail.contains("USER subroutine")),
                    "{place}: its USER call is not named"
                );
            }
            for f in &of_it {
                assert_eq!(f.file, ds.file);
                assert!(
                    f.span.line >= st.lines.0 && f.span.line <= st.lines.1,
                    "{place}"
                );
            }
        }
    }
    eprintln!(
        "{read} of {} datasets read: {statements} statements, {named} named",
        files.len()
    );
    assert!(read >= 60, "{read}");
}
