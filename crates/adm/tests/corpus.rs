//! Reads every real dataset and command file of the shared corpus (`/work/shared/corpus`,
//! third-party files that are not part of this repository). Skipped, with a notice, when the
//! corpus folder is absent.

use linkage_adm::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

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
            "note: corpus folder {} absent; corpus test skipped",
            dir.display()
        );
        None
    }
}

/// Files judged truly malformed, with the first error line expected and the reason.
const MALFORMED: &[(&str, u32, &str)] = &[
    (
        "alex-marinov__mbdyn__contrib__a2m__samples__bipendolo.adm",
        2,
        "the title line is missing: line 1 (the title) is a MATERIAL statement, so its \
         continuation on line 2 (', DENSITY = …') has nothing to continue",
    ),
    (
        "alex-marinov__mbdyn__contrib__a2m__samples__prova_beam01.adm",
        2,
        "converter torture test: 'IZ=30,5,1,4' gives four values to the single-valued IZZ \
         of a BEAM",
    ),
    (
        "alex-marinov__mbdyn__contrib__a2m__samples__prova.adm",
        3,
        "parser torture test: 'PART/2930, %&(MASS=2,) …', a JPRIM without type, a MARKER on \
         both a FLEX_BODY and a POINT_MASS",
    ),
];

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    v.retain(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("adm" | "acf")));
    v.sort();
    v
}

fn name_of(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Reads a corpus file: the errors, if any (`Err` when reading panicked).
fn read(p: &Path) -> Result<Option<Diagnostics>, String> {
    let is_adm = p.extension().is_some_and(|e| e == "adm");
    catch_unwind(AssertUnwindSafe(|| {
        if is_adm {
            read_dataset(p).err()
        } else {
            read_commands(p).err()
        }
    }))
    .map_err(|_| format!("{}: reading panicked", name_of(p)))
}

#[test]
fn every_corpus_file_reads_without_panic_and_only_malformed_ones_fail() {
    let Some(dir) = corpus_dir() else { return };
    let all = files(&dir);
    assert!(
        all.len() > 100,
        "corpus looks incomplete: {} files",
        all.len()
    );
    let mut problems = Vec::new();
    for p in &all {
        let name = name_of(p);
        let expected = MALFORMED.iter().find(|(n, _, _)| *n == name);
        match (read(p), expected) {
            (Err(panic), _) => problems.push(panic),
            (Ok(None), None) => {}
            (Ok(Some(errors)), None) => {
                problems.push(format!("{name}: unexpected errors:\n{errors}"))
            }
            (Ok(None), Some(_)) => problems.push(format!("{name}: listed as malformed but reads")),
            (Ok(Some(errors)), Some((_, line, _))) => {
                let first = errors.0.first().and_then(|d| d.span).map(|s| s.line);
                if first != Some(*line) {
                    problems.push(format!("{name}: first error not on line {line}:\n{errors}"));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

fn dataset(name: &str) -> Option<Dataset> {
    let dir = corpus_dir()?;
    Some(read_dataset(&dir.join(name)).unwrap_or_else(|e| panic!("{e}")))
}

#[test]
fn generic_model_slider_crank_types_completely() {
    let Some(ds) = dataset("bthornton191__adamspy__test__files__generic_model__generic_model.adm")
    else {
        return;
    };
    assert_eq!(ds.title, "Adams View model name: generic_model");
    let units = ds.units.as_ref().unwrap_or_else(|| panic!("no UNITS"));
    let unit =
        |u: &Option<Located<String>>| u.as_ref().map(|l| l.value.clone()).unwrap_or_default();
    assert_eq!(
        [
            unit(&units.force),
            unit(&units.mass),
            unit(&units.length),
            unit(&units.time)
        ],
        ["POUND_FORCE", "POUND_MASS", "INCH", "SECOND"]
    );
    assert_eq!(ds.parts.len(), 3);
    assert_eq!(ds.parts.iter().filter(|p| p.ground).count(), 1);
    assert_eq!(ds.parts[1].header.name, "PART_2");
    assert_eq!(ds.parts[1].cm.map(|r| r.id), Some(11));
    assert_eq!(ds.markers.len(), 12);
    assert!(ds.markers.iter().all(|m| m.carrier.is_some()));
    let revolute: Vec<&Joint> = ds
        .joints
        .iter()
        .filter(|j| j.kind == JointType::Revolute)
        .collect();
    assert_eq!((ds.joints.len(), revolute.len()), (2, 2));
    assert_eq!((revolute[1].i.id, revolute[1].j.id), (7, 8));
    assert_eq!(ds.jprims.len(), 1);
    assert_eq!(ds.jprims[0].kind, JprimType::Inline);
    assert_eq!(
        ds.jprims[0].header.name, "JOINT_3",
        "name from adams_view_name"
    );
    assert_eq!(ds.motions.len(), 1);
    let m = &ds.motions[0];
    assert!(matches!(
        m.target,
        MotionTarget::Joint {
            joint: IdRef { id: 1, .. },
            dof: Some(MotionDof::Rotation)
        }
    ));
    let f = m.function.as_ref().unwrap_or_else(|| panic!("no FUNCTION"));
    assert_eq!(f.value.expr.text, "30.0d * time");
    assert!(!f.value.user);
    assert!(ds.warnings.is_empty(), "{:?}", ds.warnings);
    assert_eq!(ds.end_line, Some(135));
}

#[test]
fn monster_stops_at_its_first_end() {
    let Some(ds) = dataset("alex-marinov__mbdyn__contrib__a2m__samples__monster.adm") else {
        return;
    };
    assert_eq!(ds.end_line, Some(388));
    assert!(ds.statements.iter().all(|s| s.lines.1 < 388));
    // Line 14 repeats a title inside the dataset: an unknown statement, a warning.
    assert_eq!(ds.warnings.len(), 1);
    assert_eq!(ds.warnings[0].span, Some(Span::new(14, 1)));
}

#[test]
fn chrono_revolute_reads_ids_with_leading_zeros_and_degrees() {
    let Some(ds) = dataset("projectchrono__chrono__data__adams__test_Revolute_Case01.adm") else {
        return;
    };
    let m = ds
        .markers
        .iter()
        .find(|m| m.header.id == 102)
        .unwrap_or_else(|| panic!("no MARKER/0102"));
    assert!(matches!(
        m.carrier,
        Some(MarkerCarrier::Part(IdRef { id: 1, .. }))
    ));
    let r = m.reuler.as_ref().map(|l| l.value).unwrap_or_default();
    let pi = std::f64::consts::PI;
    assert!((r[0] - pi).abs() < 1e-12 && (r[1] - pi / 2.0).abs() < 1e-12);
    assert_eq!(ds.joints.len(), 1);
    assert_eq!((ds.joints[0].i.id, ds.joints[0].j.id), (102, 202));
    assert_eq!(
        ds.accgrav.as_ref().map(|g| g.gravity),
        Some([0.0, 0.0, -9.80665])
    );
}

#[test]
fn generic_model_command_file() {
    let Some(dir) = corpus_dir() else { return };
    let acf = read_commands(
        &dir.join("bthornton191__adamspy__test__files__generic_model__generic_model.acf"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(acf.model, None);
    let names: Vec<&str> = acf.commands.iter().map(|c| c.keyword.as_str()).collect();
    assert_eq!(names, ["FILE", "SIMULATE"]);
    assert!(acf.commands[1].arg("DYNAMICS").is_some());
    assert!(acf.stop_line.is_some());
}
