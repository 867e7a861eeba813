//! The linker the model asks for each `USER(…)` call: ROUTINE parsed, the library found and
//! loaded (once), the entry point found in either convention.

use crate::error::{LinkError, UserError};
use crate::kind::{Kind, Shape};
use crate::routine::{Entry, Linked};
use crate::search::Search;
use libloading::os::unix::{Library, RTLD_LOCAL, RTLD_NOW};
use linkage_expr::Routine;
use linkage_model::functions::{UserLinker, UserRoutines, UserSite};
use std::collections::HashMap;
use std::error::Error;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

/// Links the USER calls of one dataset to the libraries the user gave.
pub struct Linker {
    search: Search,
    /// Libraries loaded so far (canonical path → library), in load order.
    loaded: Mutex<Vec<(PathBuf, Arc<Library>)>>,
    /// The IFLAG state of each statement's subroutine (`GFORCE/3 FUNCTION`), shared by the
    /// values it returns.
    initialised: Mutex<HashMap<String, Arc<AtomicBool>>>,
}

/// The linker for `--user-lib` entries `given` and the dataset (or command file) at
/// `dataset`, as the model takes it; no entries: none (USER calls stay refused).
pub fn user_routines(given: &[PathBuf], dataset: Option<&Path>) -> Result<UserRoutines, UserError> {
    if given.is_empty() {
        return Ok(UserRoutines::default());
    }
    crate::shim::ensure()?;
    Ok(UserRoutines(Some(Arc::new(Linker {
        search: Search::new(given, dataset)?,
        loaded: Mutex::new(Vec::new()),
        initialised: Mutex::new(HashMap::new()),
    }))))
}

/// `ROUTINE = lib::name` split: the library (if any) and the name (if any). `lib::` names the
/// library with the default name; a bare `name` is looked for in the libraries given.
pub fn split_routine(routine: Option<&str>) -> (Option<&str>, Option<&str>) {
    let Some(r) = routine.map(str::trim) else {
        return (None, None);
    };
    match r.rsplit_once("::") {
        Some((lib, name)) => (nonempty(lib), nonempty(name)),
        None => (None, nonempty(r)),
    }
}

/// `s` trimmed, `None` when empty.
fn nonempty(s: &str) -> Option<&str> {
    let s = s.trim();
    (!s.is_empty()).then_some(s)
}

/// The symbols tried for subroutine `name`, with whether each is the C-style interface.
/// Adams' rule: a mixed-case name (`Sfosub`, `StringForces`) is a C-style subroutine; the
/// default name is tried as C (`Sfosub`) and then as Fortran. Fortran names are tried as
/// gfortran and Intel Fortran on Linux spell them (lower case with a trailing underscore), then
/// plain lower case and upper case.
pub fn candidates(name: &str, default: bool) -> Vec<(String, bool)> {
    let lower = name.to_ascii_lowercase();
    let mixed = name.chars().any(|c| c.is_ascii_lowercase())
        && name.chars().any(|c| c.is_ascii_uppercase());
    let mut out = Vec::new();
    if default {
        let mut c = lower.clone();
        c[..1].make_ascii_uppercase();
        out.push((c, true));
    } else if mixed {
        out.push((name.to_string(), true));
    }
    out.push((format!("{lower}_"), false));
    out.push((lower.clone(), false));
    out.push((name.to_ascii_uppercase(), false));
    out.dedup();
    out
}

impl Linker {
    /// The library at `path`, loaded once.
    fn load(&self, path: &Path) -> Result<Arc<Library>, LinkError> {
        let mut loaded = self.loaded.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, l)) = loaded.iter().find(|(p, _)| p == path) {
            return Ok(l.clone());
        }
        // SAFETY: the user chose this library (--user-lib, the dataset's folder or
        // LD_LIBRARY_PATH); loading runs its initialisers. RTLD_NOW: a reference it cannot
        // resolve is an error here rather than a crash at its first call.
        let lib = unsafe { Library::open(Some(path), RTLD_NOW | RTLD_LOCAL) }.map_err(|e| {
            LinkError::Load {
                path: path.to_path_buf(),
                why: e.to_string(),
            }
        })?;
        let lib = Arc::new(lib);
        loaded.push((path.to_path_buf(), lib.clone()));
        Ok(lib)
    }

    /// The IFLAG state shared by every value of `site`'s statement and argument.
    fn initialised(&self, site: &UserSite<'_>) -> Arc<AtomicBool> {
        let key = format!("{} {}", site.origin.element(), site.what);
        let mut map = self.initialised.lock().unwrap_or_else(|e| e.into_inner());
        map.entry(key).or_default().clone()
    }

    /// The entry point `symbol` of `lib` in the convention of `kind`.
    fn entry(lib: &Library, symbol: &str, c_style: bool, kind: Kind) -> Option<Entry> {
        let name = format!("{symbol}\0");
        // SAFETY: only the address is taken here; the type is the convention Adams fixes for
        // this subroutine family and naming (see `candidates`).
        unsafe {
            Some(match (c_style, kind.shape()) {
                (false, Shape::Flagged) => Entry::FortranFlagged(*lib.get(name.as_bytes()).ok()?),
                (false, Shape::Plain) => Entry::FortranPlain(*lib.get(name.as_bytes()).ok()?),
                (true, Shape::Flagged) => Entry::CFlagged(*lib.get(name.as_bytes()).ok()?),
                (true, Shape::Plain) => Entry::CPlain(*lib.get(name.as_bytes()).ok()?),
            })
        }
    }
}

impl UserLinker for Linker {
    fn link(&self, site: &UserSite<'_>) -> Result<Routine, Box<dyn Error + Send + Sync>> {
        let statement = site.origin.statement;
        let kind = Kind::of_statement(statement)
            .ok_or_else(|| LinkError::Unsupported(statement.to_string()))?;
        let (lib, name) = split_routine(site.routine);
        let libraries = match lib {
            Some(lib) => vec![self.search.library(lib)?],
            None => self.search.given(),
        };
        if libraries.is_empty() {
            return Err(LinkError::NoLibraries(name.unwrap_or(kind.name()).to_string()).into());
        }
        let symbols = candidates(name.unwrap_or(kind.name()), name.is_none());
        for path in &libraries {
            let lib = self.load(path)?;
            for (symbol, c_style) in &symbols {
                if let Some(entry) = Self::entry(&lib, symbol, *c_style, kind) {
                    return Ok(Routine(Arc::new(Linked {
                        kind,
                        id: i32::try_from(site.origin.id).unwrap_or(i32::MAX),
                        component: site.component.min(kind.outputs() - 1),
                        entry,
                        symbol: symbol.clone(),
                        library: path.clone(),
                        _keep: lib,
                        element: site.origin.element(),
                        initialised: self.initialised(site),
                    })));
                }
            }
        }
        Err(LinkError::NoSymbol {
            tried: symbols.into_iter().map(|(s, _)| s).collect(),
            libraries,
        }
        .into())
    }

    fn calls(&self, keyword: &str, routine: Option<&str>) -> Option<String> {
        let kind = Kind::of_statement(keyword)?;
        Some(match routine.map(str::trim) {
            Some(r) => format!("{} as ROUTINE = {r}", kind.name()),
            None => format!("{} from the --user-lib libraries", kind.name()),
        })
    }

    fn loaded(&self) -> Vec<String> {
        let loaded = self.loaded.lock().unwrap_or_else(|e| e.into_inner());
        loaded
            .iter()
            .map(|(p, _)| p.display().to_string())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn routine_splits_into_library_and_name() {
        assert_eq!(split_routine(Some("tlmadams::")), (Some("tlmadams"), None));
        assert_eq!(
            split_routine(Some(" adrill_solver::StringForces ")),
            (Some("adrill_solver"), Some("StringForces"))
        );
        assert_eq!(split_routine(Some("myforce")), (None, Some("myforce")));
        assert_eq!(split_routine(Some("::f")), (None, Some("f")));
        assert_eq!(split_routine(None), (None, None));
    }

    #[test]
    fn mixed_case_names_are_c_style_and_the_default_is_tried_as_c_then_fortran() {
        let names = |n: &str, d: bool| candidates(n, d);
        assert_eq!(
            names("SFOSUB", true),
            [
                ("Sfosub".to_string(), true),
                ("sfosub_".to_string(), false),
                ("sfosub".to_string(), false),
                ("SFOSUB".to_string(), false)
            ]
        );
        assert_eq!(
            names("StringForces", false)[0],
            ("StringForces".into(), true)
        );
        assert!(names("myforce", false).iter().all(|(_, c)| !c));
    }
}
