//! The request-file writer against the reader: what is written reads back the same, and the
//! Adams files of the shared corpus are reproduced character for character (line endings
//! aside). The corpus part is skipped with a notice when the corpus is absent, and fails then
//! when the environment variable `CI` is set.

use linkage_adm::reqfile::{parse_request_file, RequestFile};
use linkage_adm::reqwriter::{
    write_request_file, Precision, RequestDescription, RequestFileHeader, RequestFileWriter,
};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn corpus_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus");
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "corpus folder {} absent (required when CI is set)",
        dir.display()
    );
    println!(
        "note: corpus folder {} absent; corpus test skipped",
        dir.display()
    );
    None
}

fn read_back(bytes: Vec<u8>) -> RequestFile {
    let text = String::from_utf8(bytes).unwrap_or_else(|e| panic!("{e}"));
    parse_request_file(Arc::from("written.req"), &text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Requests of every type, comments of every length modulo 4 (and none), and values with
/// negative signs, tiny and huge magnitudes and three-digit exponents.
/// An output block: the time and six values per request.
type Block = (f64, Vec<[f64; 6]>);

fn sample() -> (Vec<RequestDescription>, Vec<Block>) {
    let comments = [
        "",
        "A",
        "AB C",
        "VELOCITY X Y Z WX WY WZ",
        "  lead",
        "x,y=z!",
    ];
    let requests: Vec<RequestDescription> = comments
        .iter()
        .enumerate()
        .map(|(k, c)| RequestDescription {
            id: 10 * k as u64 + 1,
            type_code: (k % 5) as u32 + 1,
            i: if k % 5 == 4 { 0 } else { 200 + k as u64 },
            j: if k % 5 == 4 { 0 } else { 100 },
            comment: c.to_string(),
        })
        .collect();
    let blocks = (0..4)
        .map(|step| {
            let t = [0.0, 0.0, 0.01, 1.23456789][step];
            let values = (0..requests.len())
                .map(|r| {
                    let s = (step * 7 + r) as f64;
                    [
                        -s * 1.5,
                        1e-100 * (s + 1.0),
                        -3.25e150,
                        (s * 0.37).sin() * 180.0,
                        -1e-7 / (s + 1.0),
                        1.0 / 3.0,
                    ]
                })
                .collect();
            (t, values)
        })
        .collect();
    (requests, blocks)
}

fn relative(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / a.abs().max(b.abs())
    }
}

#[test]
fn written_files_read_back_within_their_precision() {
    let (requests, blocks) = sample();
    for (precision, bound) in [(Precision::Adams, 5.0e-6), (Precision::Full, 0.0)] {
        let header = RequestFileHeader::now("round trip", "M_KGS_N_RACA", 1.0);
        let mut w = RequestFileWriter::new(Vec::new(), &header, &requests, precision)
            .unwrap_or_else(|e| panic!("{e}"));
        for (t, values) in &blocks {
            w.write_output(*t, values).unwrap_or_else(|e| panic!("{e}"));
        }
        let f = read_back(w.finish().unwrap_or_else(|e| panic!("{e}")));
        assert_eq!(f.title, "round trip");
        assert_eq!((f.units.as_str(), f.scale), ("M_KGS_N_RACA", 1.0));
        let times: Vec<f64> = blocks.iter().map(|b| b.0).collect();
        assert_eq!(f.times.len(), times.len());
        for (a, b) in f.times.iter().zip(&times) {
            assert!(relative(*a, *b) <= bound, "{a} vs {b}");
        }
        assert_eq!(f.requests.len(), requests.len());
        for (k, (read, written)) in f.requests.iter().zip(&requests).enumerate() {
            assert_eq!(RequestDescription::from(read), *written, "{precision:?}");
            for (step, (_, values)) in blocks.iter().enumerate() {
                for (a, b) in read.values[step].iter().zip(&values[k]) {
                    assert!(relative(*a, *b) <= bound, "{precision:?}: {a} vs {b}");
                }
            }
        }
    }
}

#[test]
fn a_file_without_requests_has_only_times() {
    let header = RequestFileHeader::now("SOLIDWORKS Motion Mechanism", "INLBS_PFRACA", 39.37);
    let mut w = RequestFileWriter::new(Vec::new(), &header, &[], Precision::Adams)
        .unwrap_or_else(|e| panic!("{e}"));
    for t in [0.0, 0.0, 0.005] {
        w.write_output(t, &[]).unwrap_or_else(|e| panic!("{e}"));
    }
    let bytes = w.finish().unwrap_or_else(|e| panic!("{e}"));
    let text = String::from_utf8(bytes.clone()).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        text.ends_with(
            "    0     INLBS_PFRACA 3.937000000000000E+01\n   0.00000E+00\n   0.00000E+00\n   5.00000E-03\n"
        ),
        "{text}"
    );
    let f = read_back(bytes);
    assert_eq!(f.times, [0.0, 0.0, 0.005]);
    assert!(f.requests.is_empty());
}

/// Every Adams request file of the corpus, read and written again, is the same text.
#[test]
fn corpus_adams_files_are_reproduced() {
    let Some(dir) = corpus_dir() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{e}"))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "req"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "{} request files", files.len());
    for path in files {
        let original = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{e}"))
            .replace("\r\n", "\n");
        let read = linkage_adm::reqfile::read_request_file(&path).unwrap_or_else(|e| panic!("{e}"));
        // The date of line 1: its second and third words.
        let words: Vec<&str> = read.header.split_whitespace().collect();
        let date = format!("{} {}", words[1], words[2]);
        let bytes = write_request_file(Vec::new(), &read, &date, Precision::Adams)
            .unwrap_or_else(|e| panic!("{e}"));
        let written = String::from_utf8(bytes).unwrap_or_else(|e| panic!("{e}"));
        for (k, (a, b)) in original.lines().zip(written.lines()).enumerate() {
            assert_eq!(a, b, "{}:{}", path.display(), k + 1);
        }
        assert_eq!(original.lines().count(), written.lines().count());
        // And at full precision the values read back bit for bit.
        let full = write_request_file(Vec::new(), &read, &date, Precision::Full)
            .unwrap_or_else(|e| panic!("{e}"));
        let again = read_back(full);
        assert_eq!(again.times, read.times);
        assert_eq!(again.requests, read.requests, "{}", path.display());
    }
}
