//! No output overwrites an input: files are compared by identity (device and inode on Unix,
//! volume and file index on Windows), so that another spelling of an input (`./in.adm`, a
//! symbolic link) and a hard link to it are both caught, whatever the path says.
//!
//! Every command that writes checks each file it writes against every file it read: the
//! dataset, its MATRIX files and GRAPHICS meshes ([`dataset_files`]), a command file and the
//! command files it reads.

use crate::Loaded;
use linkage_adm::MatrixData;
use std::path::{Path, PathBuf};

/// An output that is one of the inputs: the message names both as the user wrote them.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("refusing to write {output}: it is the input {input} (choose another output file)")]
pub struct OutputIsInput {
    pub output: String,
    pub input: String,
}

/// Whether `a` and `b` are the same existing file (false when either does not exist: a file
/// that is not there yet is no input).
pub fn same_file(a: &Path, b: &Path) -> bool {
    same_file::is_same_file(a, b).unwrap_or(false)
}

/// `Err` naming the first output of `outputs` that is one of `inputs` (by identity).
pub fn check_outputs<I, O>(inputs: I, outputs: O) -> Result<(), OutputIsInput>
where
    I: IntoIterator,
    I::Item: AsRef<Path>,
    O: IntoIterator,
    O::Item: AsRef<Path>,
{
    let inputs: Vec<I::Item> = inputs.into_iter().collect();
    for output in outputs {
        let output = output.as_ref();
        if let Some(input) = inputs.iter().find(|i| same_file(i.as_ref(), output)) {
            return Err(OutputIsInput {
                output: output.display().to_string(),
                input: input.as_ref().display().to_string(),
            });
        }
    }
    Ok(())
}

/// Every file a loaded dataset was read from: the dataset, each MATRIX's FILE and each
/// EXTERNAL GRAPHICS mesh (named relative to the dataset's folder).
pub fn dataset_files(loaded: &Loaded) -> Vec<PathBuf> {
    let file = loaded.dataset.file.to_string();
    let mut files = vec![PathBuf::from(&file)];
    for m in &loaded.dataset.controls.matrices {
        if let MatrixData::File { name, .. } = &m.data {
            files.push(linkage_model::controls::matrix_file_path(&file, name));
        }
    }
    for g in &loaded.model.graphics {
        if let linkage_adm::graphics::Shape::External { file: Some(f), .. } = &g.shape {
            files.push(linkage_model::contacts::external_path(&file, f));
        }
    }
    files
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hard_link_and_another_spelling_of_an_input_are_the_input() {
        let dir = std::env::temp_dir().join(format!("linkage-files-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let input = dir.join("in.adm");
        std::fs::write(&input, "x").unwrap();
        let hard = dir.join("hard.adm");
        std::fs::hard_link(&input, &hard).unwrap();
        let dotted = dir.join(".").join("in.adm");
        let copy = dir.join("copy.adm");
        std::fs::write(&copy, "x").unwrap();
        for output in [&hard, &dotted, &input] {
            let e = check_outputs([&input], [output]).unwrap_err();
            assert_eq!(e.input, input.display().to_string());
        }
        // A copy with the same text, and a file not yet written, are other files.
        assert!(check_outputs([&input], [&copy, &dir.join("new.csv")]).is_ok());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
