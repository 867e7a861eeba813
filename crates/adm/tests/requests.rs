//! REQUEST statements (typing) and Adams request files (`.req`).
//!
//! The corpus part reads the request files of the shared corpus (`/work/shared/corpus`,
//! third-party files that are not part of this repository); it is skipped, with a notice, when
//! the corpus folder is absent.

use linkage_adm::reqfile::{parse_request_file, read_request_file};
use linkage_adm::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn dataset(body: &str) -> Result<Dataset, Diagnostics> {
    parse_dataset(Arc::from("t.adm"), &format!("title\n{body}\nEND\n"))
}

fn ok(body: &str) -> Dataset {
    dataset(body).unwrap_or_else(|e| panic!("{e}"))
}

fn errors(body: &str) -> Vec<(u32, u32, String)> {
    match dataset(body) {
        Ok(_) => panic!("no error for {body:?}"),
        Err(d) => {
            d.0.iter()
                .map(|e| {
                    let s = e.span.unwrap_or_default();
                    (s.line, s.col, e.message.clone())
                })
                .collect()
        }
    }
}

#[test]
fn standard_requests_with_abbreviations() {
    let ds = ok(
        "REQUEST/01, D,I=0201,J=0101,C=DISPLACEMENT: X Y Z PSI THETA PHI (body-fixed-3-1-3)\n\
         REQUEST/02, V,I=0201,J=0101\n\
         REQUEST/3\n, ACCELERATION\n, I = 201\n\
         REQUEST/05, F,I=0102,J=0202,RM=0101,C=RForce X Y Z RTorque X Y Z",
    );
    let r = &ds.requests;
    assert_eq!(r.len(), 4);
    assert_eq!(r[0].header.name, "REQUEST_1");
    assert_eq!(r[0].kind, Some(RequestKind::Displacement));
    assert_eq!(
        (r[0].i.map(|i| i.id), r[0].j.map(|j| j.id), r[0].rm),
        (Some(201), Some(101), None)
    );
    assert_eq!(
        r[0].comment.as_ref().map(|c| c.value.as_str()),
        Some("DISPLACEMENT: X Y Z PSI THETA PHI (body-fixed-3-1-3)")
    );
    assert_eq!(r[1].kind, Some(RequestKind::Velocity));
    assert_eq!(r[2].kind, Some(RequestKind::Acceleration));
    assert_eq!((r[2].i.map(|i| i.id), r[2].j), (Some(201), None));
    assert_eq!(r[3].kind, Some(RequestKind::Force));
    assert_eq!(r[3].rm.map(|m| m.id), Some(101));
    assert!(r.iter().all(|q| q.functions.iter().all(Option::is_none)));
    // The I id is located where it was written.
    assert_eq!(r[2].i.map(|i| (i.span.line, i.span.col)), Some((6, 7)));
}

#[test]
fn function_requests_keep_their_expressions_and_texts() {
    let ds = ok("!                     adams_view_name='forces_on_ground'\n\
         REQUEST/05, F2=JOINT(1,0,2,0)\\F3=JOINT(1,0,3,0)\\F8=JOINT(1,0,8,0),C=RForce X Y Z\n\
         REQUEST/6\n, CNAMES = \"a\", \"\", \"c\"\n, RESULTS_NAME = motor\n, TITLE = A:B\n\
         , F1 = DX(9000005,9000001,9000001)\\\n, F4 = DIF(9000012)-\n, DIF(9000011)\n\
         REQUEST/7, FUNCTION = USER(-1, 9.0E+06)\\, ROUTINE = lib::fn");
    let r = &ds.requests;
    assert_eq!(r[0].header.name, "forces_on_ground");
    assert_eq!(r[0].kind, None);
    let text = |q: &Request, k: usize| q.functions[k].as_ref().map(|f| f.value.expr.text.clone());
    assert_eq!(text(&r[0], 0), None);
    assert_eq!(text(&r[0], 1).as_deref(), Some("JOINT(1,0,2,0)"));
    assert_eq!(text(&r[0], 2).as_deref(), Some("JOINT(1,0,3,0)"));
    assert_eq!(text(&r[0], 7).as_deref(), Some("JOINT(1,0,8,0)"));
    assert_eq!(
        r[0].functions[1]
            .as_ref()
            .map(|f| (f.span.line, f.span.col)),
        Some((3, 16))
    );
    assert_eq!(r[1].cnames, ["a", "", "c"]);
    assert_eq!(
        r[1].results_name.as_ref().map(|t| t.value.as_str()),
        Some("MOTOR")
    );
    assert_eq!(r[1].title.as_ref().map(|t| t.value.as_str()), Some("A:B"));
    assert_eq!(
        text(&r[1], 0).as_deref(),
        Some("DX(9000005,9000001,9000001)")
    );
    assert_eq!(
        text(&r[1], 3).as_deref(),
        Some("DIF(9000012)- DIF(9000011)")
    );
    let user = r[2].function.as_ref().map(|f| f.value.user);
    assert_eq!(user, Some(true));
    assert_eq!(r[2].header.name, "REQUEST_7");
}

#[test]
fn malformed_requests_are_errors_and_empty_ones_warnings() {
    let e = errors("REQUEST/1, DISPLACEMENT, J=3");
    assert_eq!(e.len(), 1);
    assert!(e[0].2.contains("needs I = <marker id>"), "{e:?}");
    let e = errors("REQUEST/1, D, I=2, F1=DX(2)");
    assert_eq!((e[0].0, e[0].1), (2, 20));
    assert!(
        e[0].2.contains("DISPLACEMENT request and also gives 'F1'"),
        "{e:?}"
    );
    let e = errors("REQUEST/1, F3=DX(2)\\FUNCTION=USER(1)");
    assert!(e[0].2.contains("both 'F3' and FUNCTION"), "{e:?}");
    let e = errors("REQUEST/1, D, V, I=2");
    assert!(e[0].2.contains("more than one quantity"), "{e:?}");
    let e = errors("REQUEST/1, D, I=2:3");
    assert_eq!(e.len(), 1, "{e:?}");
    let ds = ok("REQUEST/9, COMMENT = nothing here");
    assert_eq!(ds.requests.len(), 1);
    assert!(ds
        .warnings
        .iter()
        .any(|w| w.message.contains("defines no output")));
    // An argument REQUEST does not have is an input error naming the one meant, or read
    // leniently, ignored with a warning.
    let e = errors("REQUEST/1,ACCELERATION,I=1,J=2,COMMENTS=L01");
    assert_eq!(
        e[0].2,
        "unknown argument 'COMMENTS' of REQUEST (did you mean COMMENT?)"
    );
    let ds = parse_dataset_with(
        Arc::from("t.adm"),
        "title\nREQUEST/1,ACCELERATION,I=1,J=2,COMMENTS=L01\nEND\n",
        ReadOptions {
            lenient_arguments: true,
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ds.requests[0].kind, Some(RequestKind::Acceleration));
    assert!(ds
        .warnings
        .iter()
        .any(|w| w.message.contains("unknown argument 'COMMENTS'")));
}

fn corpus_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    if dir.is_dir() {
        Some(dir)
    } else {
        assert!(
            std::env::var_os("CI").is_none(),
            "corpus folder {} absent (required when CI is set)",
            dir.display()
        );
        println!(
            "note: corpus folder {} absent; request-file corpus test skipped",
            dir.display()
        );
        None
    }
}

#[test]
fn every_corpus_request_file_reads() {
    let Some(dir) = corpus_dir() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.extension().is_some_and(|e| e == "req"));
    files.sort();
    assert!(files.len() >= 8, "{} request files", files.len());
    for p in &files {
        let f = read_request_file(p).unwrap_or_else(|e| panic!("{e}"));
        assert!(!f.times.is_empty(), "{}", p.display());
        for r in &f.requests {
            assert_eq!(r.values.len(), f.times.len(), "{}", p.display());
        }
    }
}

#[test]
fn chrono_revolute_request_file() {
    let Some(dir) = corpus_dir() else { return };
    let path = dir.join("projectchrono__chrono__data__adams__test_Revolute_Case01_ADAMS.req");
    let f = read_request_file(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(f.title, "ADAMS/View model name: test_Revolute_Case01");
    assert_eq!((f.units.as_str(), f.scale), ("M_KGS_N_RACA", 1.0));
    // END=5.0, DTOUT=0.01: 501 outputs.
    assert_eq!(f.times.len(), 501);
    assert_eq!(f.times.first(), Some(&0.0));
    assert_eq!(f.times.last(), Some(&5.0));
    assert!((f.times[250] - 2.5).abs() < 1e-12);
    let ids: Vec<(u64, u32, u64, u64)> = f
        .requests
        .iter()
        .map(|r| (r.id, r.type_code, r.i, r.j))
        .collect();
    assert_eq!(
        ids,
        [
            (1, 1, 201, 101),
            (2, 2, 201, 101),
            (3, 3, 201, 101),
            (4, 5, 0, 0),
            (5, 5, 0, 0)
        ]
    );
    let r = |id: u64| f.request(id).unwrap_or_else(|| panic!("request {id}"));
    assert_eq!(r(2).comment, "VELOCITY X Y Z WX WY WZ");
    // Displacement at t = 0: the pendulum CM at x = 2, REULER 180D, 90D, 180D.
    assert_eq!(r(1).values[0], [2.0, 0.0, 0.0, 180.0, 90.0, 180.0]);
    // At t = 0.01 it has fallen by g·α-consistent 4.78373E-04.
    assert_eq!(r(1).values[1][2], -4.78373e-4);
    // JOINT(1,0,4,0) at t = 0 (F4 is the third stored value).
    assert_eq!(r(5).values[0][2], -2.39187e-1);
    // Last block.
    assert_eq!(r(5).values[500][0], -5.10225e-1);
    assert_eq!(r(3).component(4)[0], 4.78373);
}

#[test]
fn request_file_text_round_trip_of_counts() {
    // A file whose request count says 1 but that describes none is an error, located.
    let text = " A.R3\nmodel\n    1     M_KGS_N_RACA 1.0E+00\n   0.00000E+00\n";
    let e = parse_request_file(Arc::from("x.req"), text).unwrap_err();
    assert_eq!(e.0[0].span.map(|s| s.line), Some(4));
    assert!(e.0[0].message.contains("5 integers"), "{}", e.0[0].message);
}
