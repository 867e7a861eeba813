//! The corpus datasets with CONTACT statements: every contact geometry in an external file
//! linkage cannot use (the corpus holds no Parasolid file) is named by verify with the file,
//! the force analyses refuse the contact, and with the contacts deactivated
//! (`--deactivate CONTACT`) nothing about contacts stops the initial conditions.
//!
//! The corpus is read by relative path; without it the test fails when `CI` is set and skips
//! with a notice elsewhere.

mod common;
use common::{corpus, run};
use std::collections::BTreeSet;

/// The EXTERNAL files named by the GRAPHICS that CONTACT statements use (from the raw text:
/// statements joined over their `,` continuation lines).
fn contact_files(text: &str) -> BTreeSet<String> {
    let mut statements: Vec<String> = Vec::new();
    for line in text.lines() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('!') {
            continue;
        }
        // Blanks dropped: `, IGEOM = 7` becomes `,IGEOM=7`.
        let t: String = t.chars().filter(|c| !c.is_whitespace()).collect();
        match statements.last_mut() {
            Some(last) if t.starts_with(',') => last.push_str(&t),
            _ => statements.push(t),
        }
    }
    let upper: Vec<String> = statements.iter().map(|s| s.to_ascii_uppercase()).collect();
    let value = |s: &str, key: &str| -> Option<String> {
        let at = s.find(&format!("{key}="))?;
        Some(s[at + key.len() + 1..].to_string())
    };
    let ids = |s: &str, key: &str| -> Vec<String> {
        value(s, key)
            .map(|v| {
                v.split(',')
                    .map(str::trim)
                    .take_while(|x| !x.is_empty() && x.chars().all(|c| c.is_ascii_digit()))
                    .map(str::to_string)
                    .collect()
            })
            .unwrap_or_default()
    };
    let mut used = BTreeSet::new();
    for s in upper.iter().filter(|s| s.starts_with("CONTACT/")) {
        used.extend(ids(s, ",IGEOM"));
        used.extend(ids(s, ",JGEOM"));
    }
    let mut files = BTreeSet::new();
    for (s, raw) in upper.iter().zip(&statements) {
        let Some(rest) = s.strip_prefix("GRAPHICS/") else {
            continue;
        };
        let id: String = rest.chars().take_while(char::is_ascii_digit).collect();
        if !used.contains(&id) || !s.contains(",EXTERNAL") {
            continue;
        }
        if let Some(at) = s.find(",FILE=") {
            let f = &raw[at + 6..];
            files.insert(f.split(',').next().unwrap_or(f).to_string());
        }
    }
    files
}

#[test]
fn corpus_contacts_name_their_missing_files_and_the_rest_of_each_model_runs() {
    let Some(dir) = corpus() else { return };
    let mut datasets: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "adm"))
        .filter(|p| {
            std::fs::read_to_string(p)
                .map(|t| {
                    t.lines()
                        .any(|l| l.to_ascii_uppercase().starts_with("CONTACT/"))
                })
                .unwrap_or(false)
        })
        .collect();
    datasets.sort();
    assert!(
        datasets.len() >= 12,
        "{} datasets with CONTACT",
        datasets.len()
    );
    let (mut named, mut ran) = (0, 0);
    for f in &datasets {
        let path = f.to_str().unwrap();
        let text = std::fs::read_to_string(f).unwrap();
        let files = contact_files(&text);
        let (_, out, err) = run(&["verify", path]);
        let all = format!("{out}\n{err}");
        if all.contains("error:") && !all.contains("CONTACT") {
            // Does not read or build for other reasons (not this test's business).
            continue;
        }
        for file in &files {
            assert!(
                all.contains(file.as_str()),
                "{path}: verify does not name the contact file {file}:\n{all}"
            );
            named += 1;
        }
        // The force analyses refuse the contacts by name…
        let (code, _, err) = run(&["ic", path]);
        if !files.is_empty() {
            assert_eq!(code, 2, "{path}: {err}");
            assert!(err.contains("CONTACT"), "{path}: {err}");
        }
        // …and without them nothing about contacts stops the initial conditions.
        let (code, out, err) = run(&["ic", path, "--deactivate", "CONTACT"]);
        assert!(
            !err.contains("CONTACT/"),
            "{path}: a contact still refused after --deactivate CONTACT:\n{err}"
        );
        if code == 0 {
            assert!(out.contains("left out on request"), "{path}: {out}");
            ran += 1;
        }
    }
    eprintln!(
        "{} contact datasets: {named} contact files named, {ran} ran ic with their contacts \
         deactivated",
        datasets.len()
    );
    assert!(named >= 12, "{named} files named");
    assert!(
        ran >= 1,
        "no corpus contact model ran with its contacts deactivated"
    );
}
