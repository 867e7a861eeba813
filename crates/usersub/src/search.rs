//! Where libraries are looked for, and the trust rule: only in the places the user chose.
//!
//! A library named in `ROUTINE = lib::name` is looked for, as `lib`, `lib.so` and
//! `liblib.so`, among the files given with `--user-lib` (by file name), then in the folders
//! given with `--user-lib`, the dataset's own folder and the folders of `LD_LIBRARY_PATH`, in
//! that order. A path spelled in the dataset (`ROUTINE = /opt/x/libf.so::f`) is used only when
//! the user gave that very file with `--user-lib`: a dataset from someone else never chooses
//! the code that runs. Without a library in ROUTINE, the subroutine is looked for in the
//! libraries the user gave: the files, then the `.so` files of the folders (in name order).

use crate::error::{LinkError, UserError};
use std::path::{Path, PathBuf};

/// The places the user chose.
#[derive(Clone, Debug, Default)]
pub struct Search {
    /// `--user-lib` files (canonical paths).
    files: Vec<PathBuf>,
    /// `--user-lib` folders, then the dataset's folder, then `LD_LIBRARY_PATH`.
    folders: Vec<PathBuf>,
    /// How many of `folders` the user gave with `--user-lib`.
    given_folders: usize,
}

impl Search {
    /// The search for the `--user-lib` entries `given` (files or folders) and a dataset (or
    /// command file) at `dataset`.
    pub fn new(given: &[PathBuf], dataset: Option<&Path>) -> Result<Search, UserError> {
        let mut s = Search::default();
        for p in given {
            let c = p
                .canonicalize()
                .map_err(|_| UserError::NoSuchPath(p.clone()))?;
            if c.is_dir() {
                s.folders.push(c);
            } else {
                s.files.push(c);
            }
        }
        s.given_folders = s.folders.len();
        if let Some(dir) = dataset
            .and_then(|d| d.canonicalize().ok())
            .and_then(|d| d.parent().map(Path::to_path_buf))
        {
            s.folders.push(dir);
        }
        if let Some(paths) = std::env::var_os("LD_LIBRARY_PATH") {
            s.folders.extend(
                std::env::split_paths(&paths)
                    .filter(|p| !p.as_os_str().is_empty())
                    .filter_map(|p| p.canonicalize().ok()),
            );
        }
        Ok(s)
    }

    /// The file of library `lib` (as ROUTINE spells it), or why there is none.
    pub fn library(&self, lib: &str) -> Result<PathBuf, LinkError> {
        if lib.contains('/') {
            let wanted = Path::new(lib).canonicalize().ok();
            return match wanted.filter(|w| self.files.contains(w)) {
                Some(w) => Ok(w),
                None => Err(LinkError::SpelledPath(lib.to_string())),
            };
        }
        let names = if lib.ends_with(".so") {
            vec![lib.to_string()]
        } else {
            vec![format!("lib{lib}.so"), format!("{lib}.so"), lib.to_string()]
        };
        let by_name = self.files.iter().find(|f| {
            f.file_name()
                .is_some_and(|n| names.iter().any(|w| n == w.as_str()))
        });
        if let Some(f) = by_name {
            return Ok(f.clone());
        }
        for dir in &self.folders {
            for n in &names {
                let p = dir.join(n);
                if p.is_file() {
                    return Ok(p);
                }
            }
        }
        Err(LinkError::NoLibrary {
            lib: lib.to_string(),
            names,
            folders: self.folders.clone(),
        })
    }

    /// The libraries the user gave, for a subroutine without a library in ROUTINE.
    pub fn given(&self) -> Vec<PathBuf> {
        let mut out = self.files.clone();
        for dir in &self.folders[..self.given_folders] {
            let mut in_dir: Vec<PathBuf> = std::fs::read_dir(dir)
                .into_iter()
                .flatten()
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "so") && p.is_file())
                .collect();
            in_dir.sort();
            out.extend(in_dir);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_spelled_in_the_dataset_loads_only_when_the_user_gave_that_file() {
        let dir = std::env::temp_dir().join(format!("linkage-search-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let lib = dir.join("libforces.so");
        std::fs::write(&lib, b"").unwrap();
        let spelled = lib.display().to_string();
        let none = Search::new(&[], None).unwrap();
        assert!(matches!(
            none.library(&spelled),
            Err(LinkError::SpelledPath(_))
        ));
        let given = Search::new(std::slice::from_ref(&lib), None).unwrap();
        assert_eq!(
            given.library(&spelled).unwrap(),
            lib.canonicalize().unwrap()
        );
        // By name: liblib.so in a given folder; the folder's .so files are the defaults.
        let folder = Search::new(std::slice::from_ref(&dir), None).unwrap();
        assert_eq!(
            folder.library("forces").unwrap(),
            lib.canonicalize().unwrap()
        );
        assert!(folder.given().contains(&lib.canonicalize().unwrap()));
        assert!(matches!(
            folder.library("absent"),
            Err(LinkError::NoLibrary { .. })
        ));
        assert!(matches!(
            Search::new(&[dir.join("nothing")], None),
            Err(UserError::NoSuchPath(_))
        ));
    }
}
