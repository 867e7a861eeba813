//! `linkage fmu`: a dataset, with the platform binary, as an FMU file.
//!
//! The FMU is assembled in memory and written in one go beside its final path, then renamed
//! onto it: a failed export leaves no half-written FMU.

use crate::config::{Config, Parameter, CONFIG_FILE};
use crate::description::{model_description, About, FmiVersion};
use crate::zip::{archive, Entry, ZipError};
use linkage_adm::statement::Value;
use linkage_adm::Diagnostics;
use linkage_api::cosim::{ports, CosimError, Ports};
use linkage_api::Source;
use linkage_solve::coverage::Analysis;
use std::path::{Component, Path, PathBuf};

/// The FMU binary's file name: this crate built as a shared library (`cargo build --release`
/// puts it beside the `linkage` executable).
pub const BINARY_NAME: &str = "liblinkage_fmu_binary.so";

/// The environment variable that may name the FMU binary (where it is not beside `linkage`).
pub const BINARY_ENV: &str = "LINKAGE_FMU_BINARY";

/// Where the FMU binary is taken from: `explicit` (`--binary`, Python's `binary=`), else
/// `$LINKAGE_FMU_BINARY`, else [`BINARY_NAME`] in the folder `beside` (the running `linkage`
/// executable's, or that of `linkage` on the PATH for Python), else in the working folder.
pub fn locate_binary(explicit: Option<&Path>, beside: Option<&Path>) -> PathBuf {
    if let Some(p) = explicit {
        return p.to_path_buf();
    }
    if let Some(p) = std::env::var_os(BINARY_ENV).filter(|p| !p.is_empty()) {
        return PathBuf::from(p);
    }
    beside.map_or_else(|| PathBuf::from(BINARY_NAME), |d| d.join(BINARY_NAME))
}

/// The folder of the `linkage` executable found on the PATH.
pub fn linkage_on_path() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path).find(|d| d.join("linkage").is_file())
}

/// What `linkage fmu` asks for besides the dataset.
#[derive(Clone, Debug)]
pub struct ExportOptions {
    pub version: FmiVersion,
    /// The PINPUT and POUTPUT the ports come from (`None`: the last in the dataset).
    pub pinput: Option<u64>,
    pub poutput: Option<u64>,
    /// Statement arguments exposed as parameters: `KEYWORD/id.ARGUMENT`.
    pub parameters: Vec<String>,
    /// The start value of `initial_static`.
    pub initial_static: bool,
}

/// Why no FMU was written.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// Errors in the dataset (file:line:column).
    #[error("{0}")]
    Input(Diagnostics),
    /// The model cannot be simulated (refused statements, …).
    #[error(transparent)]
    Analysis(#[from] linkage_api::Error),
    /// No PINPUT/POUTPUT, or not the ones asked for.
    #[error(transparent)]
    Ports(#[from] CosimError),
    /// A `--parameter` that names no numeric argument of the dataset.
    #[error("--parameter {name}: {why}")]
    Parameter { name: String, why: String },
    /// The platform binary is not where it is looked for.
    #[error(
        "the FMU binary {path} cannot be read ({cause}); it is built beside the linkage \
         executable by `cargo build --release` (crate linkage-fmu-binary), or named by --binary or \
         $LINKAGE_FMU_BINARY"
    )]
    Binary { path: String, cause: std::io::Error },
    /// A file the dataset names cannot be packed.
    #[error("{path}: {why}")]
    Resource { path: String, why: String },
    #[error(transparent)]
    Zip(#[from] ZipError),
    #[error("cannot write {path}: {cause}")]
    Write { path: String, cause: std::io::Error },
}

impl From<Diagnostics> for ExportError {
    fn from(d: Diagnostics) -> Self {
        ExportError::Input(d)
    }
}

/// What was written.
#[derive(Clone, Debug)]
pub struct Exported {
    pub model_identifier: String,
    pub ports: Ports,
    pub parameters: Vec<Parameter>,
    /// The files packed, as paths in the FMU.
    pub files: Vec<String>,
    pub bytes: usize,
}

/// The model identifier of a dataset at `path`: its file stem as a C identifier (what the
/// binary is named after).
pub fn model_identifier(path: &Path) -> String {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut id: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        id.insert(0, '_');
    }
    id
}

/// `KEYWORD/id.ARGUMENT` of `source` as a parameter with its value in the dataset.
fn parameter(source: &Source, spec: &str) -> Result<Parameter, ExportError> {
    let fail = |why: String| ExportError::Parameter {
        name: spec.to_string(),
        why,
    };
    let (statement, argument) = spec
        .rsplit_once('.')
        .ok_or_else(|| fail("expected KEYWORD/id.ARGUMENT (SPRINGDAMPER/1.K)".into()))?;
    let (keyword, id) = statement
        .split_once('/')
        .ok_or_else(|| fail("expected KEYWORD/id.ARGUMENT (SPRINGDAMPER/1.K)".into()))?;
    let keyword = keyword.trim().to_ascii_uppercase();
    let argument = argument.trim().to_ascii_uppercase();
    let id: u64 = id
        .trim()
        .parse()
        .map_err(|_| fail(format!("`{id}` is not a statement id")))?;
    let st = source
        .statement(&keyword, id)
        .ok_or_else(|| fail(format!("{keyword}/{id} is not in the dataset")))?;
    let arg = st
        .args
        .iter()
        .find(|a| a.key == argument)
        .ok_or_else(|| fail(format!("{keyword}/{id} has no argument {argument}")))?;
    match arg.values.as_slice() {
        [Value::Number { value, .. }] => Ok(Parameter {
            statement: format!("{keyword}/{id}"),
            argument,
            start: *value,
        }),
        _ => Err(fail(format!(
            "{keyword}/{id}, {argument} is not a single number"
        ))),
    }
}

/// A token naming this exact FMU: 128 bits of two FNV-1a hashes of what it contains, in the
/// GUID form FMI 2.0 asks for.
fn token(parts: &[&[u8]]) -> String {
    let fnv = |seed: u64| {
        let mut h = seed;
        for p in parts {
            for &b in *p {
                h ^= u64::from(b);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
            h ^= 0xff;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        h
    };
    let (a, b) = (fnv(0xcbf2_9ce4_8422_2325), fnv(0x8422_2325_cbf2_9ce4));
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}

/// A file the dataset names, as a path inside `resources/` (relative to the dataset's
/// folder, without `..`).
fn resource_path(folder: &Path, file: &Path) -> Result<String, ExportError> {
    let rel = file.strip_prefix(folder).unwrap_or(file);
    let mut parts = Vec::new();
    for c in rel.components() {
        match c {
            Component::Normal(s) => parts.push(s.to_string_lossy().into_owned()),
            Component::CurDir => {}
            _ => {
                return Err(ExportError::Resource {
                    path: file.display().to_string(),
                    why: "only files in the dataset's folder or below it can be packed into \
                          the FMU's resources"
                        .into(),
                })
            }
        }
    }
    Ok(parts.join("/"))
}

/// Writes the FMU of the dataset at `dataset` to `out`, with the platform binary `binary`.
pub fn export(
    dataset: &Path,
    binary: &Path,
    out: &Path,
    options: &ExportOptions,
) -> Result<Exported, ExportError> {
    let source = Source::read(dataset)?;
    let loaded = source.load(&[], Some(Analysis::Simulate))?;
    loaded.forces(Analysis::Simulate)?;
    let ports = ports(&loaded.model, options.pinput, options.poutput)?;
    let parameters = options
        .parameters
        .iter()
        .map(|p| parameter(&source, p))
        .collect::<Result<Vec<_>, _>>()?;
    let folder = dataset.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut resources: Vec<(String, PathBuf)> = Vec::new();
    for f in linkage_api::dataset_files(&loaded) {
        let name = if f == dataset {
            model_identifier(dataset) + ".adm"
        } else {
            resource_path(&folder, &f)?
        };
        if !resources.iter().any(|(n, _)| *n == name) {
            resources.push((name, f));
        }
    }
    let mut entries = Vec::new();
    for (name, path) in &resources {
        let data = std::fs::read(path).map_err(|e| ExportError::Resource {
            path: path.display().to_string(),
            why: e.to_string(),
        })?;
        entries.push(Entry {
            path: format!("resources/{name}"),
            data,
            mode: 0o644,
        });
    }
    let binary_bytes = std::fs::read(binary).map_err(|cause| ExportError::Binary {
        path: binary.display().to_string(),
        cause,
    })?;
    let id = model_identifier(dataset);
    let mut config = Config {
        dataset: resources[0].0.clone(),
        pinput: ports.pinput,
        poutput: ports.poutput,
        parameters: parameters.clone(),
        initial_static: options.initial_static,
        token: String::new(),
    };
    let config_json = serde_json::to_vec(&config).unwrap_or_default();
    let version_tag: &[u8] = match options.version {
        FmiVersion::V2 => b"2",
        FmiVersion::V3 => b"3",
    };
    config.token = token(&[&entries[0].data, &config_json, version_tag]);
    let description = format!(
        "{} (Adams dataset {}; units: {})",
        loaded.model.title.trim(),
        dataset
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        units(&loaded.model)
    );
    let tool = format!("linkage {}", env!("CARGO_PKG_VERSION"));
    let about = About {
        model_name: &id,
        model_identifier: &id,
        description: &description,
        generation_tool: &tool,
    };
    let xml = model_description(options.version, &about, &ports, &config);
    entries.insert(
        0,
        Entry {
            path: "modelDescription.xml".into(),
            data: xml.into_bytes(),
            mode: 0o644,
        },
    );
    entries.push(Entry {
        path: format!("resources/{CONFIG_FILE}"),
        data: serde_json::to_vec_pretty(&config).unwrap_or_default(),
        mode: 0o644,
    });
    entries.push(Entry {
        path: format!("binaries/{}/{id}.so", options.version.platform_folder()),
        data: binary_bytes,
        mode: 0o755,
    });
    let zipped = archive(&entries)?;
    write_whole(out, &zipped)?;
    Ok(Exported {
        model_identifier: id,
        ports,
        parameters,
        files: entries.iter().map(|e| e.path.clone()).collect(),
        bytes: zipped.len(),
    })
}

/// The model's units as UNITS names them.
fn units(model: &linkage_model::Model) -> String {
    model.units.names.join(" ")
}

/// `bytes` to `path`, through a file beside it renamed onto it.
fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    let fail = |cause| ExportError::Write {
        path: path.display().to_string(),
        cause,
    };
    let mut part = path.as_os_str().to_owned();
    part.push(".part");
    let part = PathBuf::from(part);
    std::fs::write(&part, bytes).map_err(fail)?;
    std::fs::rename(&part, path).map_err(|e| {
        let _ = std::fs::remove_file(&part);
        fail(e)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn model_identifier_is_the_file_stem_as_a_c_identifier() {
        assert_eq!(model_identifier(Path::new("a/smd plant.adm")), "smd_plant");
        assert_eq!(model_identifier(Path::new("3-RPR.adm")), "_3_RPR");
    }

    #[test]
    fn token_is_a_guid_that_changes_with_the_contents() {
        let a = token(&[b"x", b"y"]);
        assert_eq!(a.len(), 38);
        assert_ne!(a, token(&[b"xy"]));
        assert_ne!(a, token(&[b"x", b"z"]));
    }

    #[test]
    fn files_outside_the_dataset_folder_are_refused() {
        let folder = Path::new("/d");
        assert_eq!(
            resource_path(folder, Path::new("/d/mesh/a.stl")).unwrap(),
            "mesh/a.stl"
        );
        assert!(resource_path(folder, Path::new("/d/../e/a.stl")).is_err());
    }
}
