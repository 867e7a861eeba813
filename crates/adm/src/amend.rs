//! Amending a dataset between analyses, as a command file does: redefine a statement's
//! arguments (`MOTION/3150, DISPLACEMENT, FUNCTION = …`, `EQUILIBRIUM/STABILITY = 1e-3`),
//! deactivate and activate statements, then type the amended statements again.
//!
//! Contract:
//! - [`redefine`] changes only the arguments the command gives. An argument replaces the
//!   statement's argument of the same keyword (the full keyword, or an unambiguous prefix of
//!   at least [`MIN_PREFIX`] letters on either side); a flag of an exclusive group (the
//!   integrator names, `I3`/`SI2`/`SI1`, a motion's `DISPLACEMENT`/`VELOCITY`/`ACCELERATION`, a
//!   request's kind, …: [`EXCLUSIVE_FLAGS`]) replaces the other flags of its group; `DEFAULT`
//!   first removes every argument (the settings return to Adams' defaults). Arguments the
//!   statement does not have are appended.
//! - A statement with an id must exist (a command cannot create an element: the error says
//!   so); an analysis-settings statement without an id (`EQUILIBRIUM/`, `INTEGRATOR/`, …) is
//!   added when the dataset has none.
//! - [`retype`] types the amended statements with the dataset's file name and text, leaving
//!   out the inactive ones, and returns every error found, as reading the dataset would.

use crate::diagnostic::Diagnostics;
use crate::parse::Parsed;
use crate::statement::{Argument, Statement};
use crate::typed::{Dataset, INTEGRATOR_FORMULATIONS, INTEGRATOR_METHODS};
use std::collections::BTreeSet;

/// The shortest prefix by which a redefinition's keyword may name a statement's argument
/// (`STAB` for `STABILITY`); shorter ones must match exactly (`I` is not `IP`).
pub const MIN_PREFIX: usize = 3;

/// Flags of which a statement holds at most one per group, per statement keyword.
pub const EXCLUSIVE_FLAGS: &[(&str, &[&str])] = &[
    ("INTEGRATOR", &INTEGRATOR_METHODS),
    ("INTEGRATOR", &INTEGRATOR_FORMULATIONS),
    ("EQUILIBRIUM", &["STATIC", "DYNAMIC"]),
    ("MOTION", &["DISPLACEMENT", "VELOCITY", "ACCELERATION"]),
    (
        "MOTION",
        &["TRANSLATION", "ROTATION", "B1", "B2", "B3", "X", "Y", "Z"],
    ),
    ("SFORCE", &["TRANSLATION", "ROTATION"]),
    (
        "REQUEST",
        &["DISPLACEMENT", "VELOCITY", "ACCELERATION", "FORCE"],
    ),
];

/// Keywords of statements that hold analysis settings: they have no id, and a redefinition
/// adds one when the dataset has none.
pub const SETTINGS_STATEMENTS: &[&str] = &[
    "ACCGRAV",
    "DEBUG",
    "EQUILIBRIUM",
    "IC",
    "INTEGRATOR",
    "KINEMATICS",
    "LSOLVER",
    "OUTPUT",
    "PREFERENCES",
    "RESULTS",
];

/// Why a redefinition cannot be applied.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AmendError {
    /// The statement the command redefines is not in the dataset.
    #[error("the dataset has no {keyword}/{id}: a command can change an element, not create one")]
    NoSuchStatement { keyword: String, id: u64 },
    /// A keyword names several of the statement's arguments.
    #[error("{key} is ambiguous in {keyword}: it could be {candidates}")]
    Ambiguous {
        keyword: String,
        key: String,
        candidates: String,
    },
    /// The statement needs an id and the command gives none.
    #[error("{keyword} needs an id (`{keyword}/id, …`)")]
    MissingId { keyword: String },
}

/// What a redefinition did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Redefined {
    /// The statement's arguments were changed.
    Changed,
    /// A settings statement was added.
    Added,
}

/// The keyword of `statement`'s argument that `key` names: the same keyword, or the only
/// argument of which one is a prefix of the other ([`MIN_PREFIX`] letters at least).
fn matching_argument(statement: &Statement, key: &str) -> Result<Option<usize>, AmendError> {
    if let Some(k) = statement.args.iter().position(|a| a.key == key) {
        return Ok(Some(k));
    }
    let prefix = |a: &str, b: &str| a.len() >= MIN_PREFIX && b.starts_with(a);
    let found: Vec<usize> = statement
        .args
        .iter()
        .enumerate()
        .filter(|(_, a)| prefix(key, &a.key) || prefix(&a.key, key))
        .map(|(k, _)| k)
        .collect();
    match found.as_slice() {
        [] => Ok(None),
        [k] => Ok(Some(*k)),
        many => Err(AmendError::Ambiguous {
            keyword: statement.keyword.clone(),
            key: key.to_string(),
            candidates: many
                .iter()
                .map(|&k| statement.args[k].key.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}

/// The other flags of `flag`'s exclusive group in statements of `keyword`.
fn rivals(keyword: &str, flag: &str) -> Vec<&'static str> {
    EXCLUSIVE_FLAGS
        .iter()
        .filter(|(k, group)| *k == keyword && group.contains(&flag))
        .flat_map(|(_, group)| group.iter().copied().filter(|g| *g != flag))
        .collect()
}

/// Applies `change` (a statement given as a command) to `statements` (see the module
/// documentation).
pub fn redefine(
    statements: &mut Vec<Statement>,
    change: &Statement,
) -> Result<Redefined, AmendError> {
    let keyword = change.keyword.as_str();
    let settings = SETTINGS_STATEMENTS.contains(&keyword);
    if change.id.is_none() && !settings {
        return Err(AmendError::MissingId {
            keyword: keyword.to_string(),
        });
    }
    let Some(target) = statements
        .iter_mut()
        .find(|s| s.keyword == keyword && (settings || s.id == change.id))
    else {
        if settings {
            let mut added = change.clone();
            added.args.retain(|a| a.key != "DEFAULT");
            statements.push(added);
            return Ok(Redefined::Added);
        }
        return Err(AmendError::NoSuchStatement {
            keyword: keyword.to_string(),
            id: change.id.unwrap_or(0),
        });
    };
    for arg in &change.args {
        apply_argument(target, arg)?;
    }
    Ok(Redefined::Changed)
}

fn apply_argument(target: &mut Statement, arg: &Argument) -> Result<(), AmendError> {
    if arg.key == "DEFAULT" && arg.values.is_empty() {
        target.args.clear();
        return Ok(());
    }
    if arg.values.is_empty() {
        let rivals = rivals(&target.keyword, &arg.key);
        target
            .args
            .retain(|a| !(a.values.is_empty() && rivals.contains(&a.key.as_str())));
    }
    match matching_argument(target, &arg.key)? {
        Some(k) => target.args[k] = arg.clone(),
        None => target.args.push(arg.clone()),
    }
    Ok(())
}

/// A statement chosen to be left out of the analyses (`--deactivate`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Selected {
    pub keyword: String,
    pub id: u64,
    /// The `adams_view_name`, else `KEYWORD_id`.
    pub name: String,
    /// Line of the statement's keyword.
    pub line: u32,
}

impl Selected {
    /// The statement `st` as a selected one (its view name, else `KEYWORD_id`).
    pub fn of(st: &Statement) -> Selected {
        let id = st.id.unwrap_or(0);
        Selected {
            keyword: st.keyword.clone(),
            id,
            name: st
                .view_name
                .clone()
                .unwrap_or_else(|| format!("{}_{id}", st.keyword)),
            line: st.span.line,
        }
    }

    /// `SENSOR/3`.
    pub fn element(&self) -> String {
        format!("{}/{}", self.keyword, self.id)
    }
}

/// The statements of `statements` that `names` choose: `KEYWORD/id` (`SENSOR/3`), a statement
/// kind (`SENSOR`: every one of that kind), or an element's name (its `adams_view_name`, or
/// `SENSOR_3`); case does not matter, and a kind may be abbreviated as in the dataset. In
/// statement order, each once. An error names the first name that chooses nothing (only
/// statements with an id can be left out).
pub fn select(statements: &[Statement], names: &[String]) -> Result<Vec<Selected>, String> {
    let mut chosen = BTreeSet::new();
    for raw in names {
        let word = raw.trim();
        let upper = word.to_ascii_uppercase();
        let (kind, id) = match upper.split_once('/') {
            Some((k, id)) => match id.trim().parse::<u64>() {
                Ok(id) => (Some(k.trim().to_string()), Some(id)),
                Err(_) => return Err(format!("--deactivate {word}: '{id}' is not an id")),
            },
            None => (Some(upper.clone()), None),
        };
        let kind = kind.map(|k| {
            match crate::keywords::lookup_statement(&k, crate::keywords::DATASET_STATEMENTS) {
                crate::keywords::Lookup::Found(d) => d.name.to_string(),
                _ => k,
            }
        });
        let before = chosen.len();
        let mut any = false;
        for (k, st) in statements.iter().enumerate() {
            let Some(sid) = st.id else { continue };
            let by_kind =
                kind.as_deref() == Some(st.keyword.as_str()) && id.is_none_or(|id| id == sid);
            let by_name = id.is_none()
                && (st
                    .view_name
                    .as_deref()
                    .is_some_and(|n| n.eq_ignore_ascii_case(word))
                    || format!("{}_{sid}", st.keyword) == upper);
            if by_kind || by_name {
                chosen.insert(k);
                any = true;
            }
        }
        if !any && chosen.len() == before {
            return Err(format!(
                "--deactivate {word}: the dataset has no element of that name (write KEYWORD/id \
                 as in SENSOR/3, a statement kind such as SENSOR, or an element's name)"
            ));
        }
    }
    Ok(chosen
        .into_iter()
        .map(|k| Selected::of(&statements[k]))
        .collect())
}

/// The dataset `ds` without the statements `left_out` (typed again).
pub fn without(ds: &Dataset, left_out: &[Selected]) -> Result<Dataset, Diagnostics> {
    let inactive: BTreeSet<(String, u64)> =
        left_out.iter().map(|s| (s.keyword.clone(), s.id)).collect();
    retype(ds, &ds.statements, &inactive)
}

/// Types `statements` (the dataset's, amended) as the dataset `ds` would be, leaving out the
/// statements listed in `inactive` (`(keyword, id)`).
pub fn retype(
    ds: &Dataset,
    statements: &[Statement],
    inactive: &BTreeSet<(String, u64)>,
) -> Result<Dataset, Diagnostics> {
    let active: Vec<Statement> = statements
        .iter()
        .filter(|s| {
            s.id.is_none_or(|id| !inactive.contains(&(s.keyword.clone(), id)))
        })
        .cloned()
        .collect();
    let parsed = Parsed {
        statements: active,
        stop_line: ds.end_line,
        diagnostics: Vec::new(),
    };
    crate::typing::type_dataset(ds.file.clone(), &ds.text, parsed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse_dataset;
    use std::sync::Arc;

    fn dataset(text: &str) -> Dataset {
        parse_dataset(Arc::from("m.adm"), text).expect("parses")
    }

    fn command(text: &str) -> Statement {
        let cf = crate::commands::parse_commands(Arc::from("c.acf"), &format!("\n{text}\n"))
            .expect("parses");
        cf.commands.into_iter().next().expect("one command")
    }

    const MODEL: &str = "m\nPART/1, GROUND\nPART/2, MASS = 2, CM = 3, IP = 1, 1, 1\n\
        MARKER/3, PART = 2\nMARKER/4, PART = 1\nJOINT/5, REVOLUTE, I = 3, J = 4\n\
        MOTION/6, JOINT = 5, ROTATION, VELOCITY, FUNCTION = 1\n\
        EQUILIBRIUM/, STABILITY = 1, ERROR = 1\nEND\n";

    #[test]
    fn a_redefinition_changes_only_the_arguments_it_gives() {
        let ds = dataset(MODEL);
        let mut st = ds.statements.clone();
        let r = redefine(
            &mut st,
            &command("MOTION/6, DISPLACEMENT, FUNCTION = 2*TIME"),
        )
        .expect("applies");
        assert_eq!(r, Redefined::Changed);
        let typed = retype(&ds, &st, &BTreeSet::new()).expect("types");
        let m = &typed.motions[0];
        assert_eq!(format!("{:?}", m.level), "Displacement");
        assert!(
            matches!(&m.target, crate::typed::MotionTarget::Joint { dof: Some(d), .. }
                if format!("{d:?}") == "Rotation"),
            "{:?}",
            m.target
        );
        let motion = st.iter().find(|s| s.keyword == "MOTION").unwrap();
        assert!(motion.args.iter().all(|a| a.key != "VELOCITY"));
        // An abbreviated keyword replaces the full one.
        redefine(&mut st, &command("EQUIL/STAB = 0.001")).expect("applies");
        let typed = retype(&ds, &st, &BTreeSet::new()).expect("types");
        let eq = typed
            .statements
            .iter()
            .find(|s| s.keyword == "EQUILIBRIUM")
            .unwrap();
        assert_eq!(eq.args.len(), 2, "{eq:?}");
    }

    #[test]
    fn settings_are_added_and_elements_are_not_created() {
        let ds = dataset(MODEL);
        let mut st = ds.statements.clone();
        assert_eq!(
            redefine(&mut st, &command("INTEGRATOR/GSTIFF, ERROR = 1e-4")),
            Ok(Redefined::Added)
        );
        redefine(&mut st, &command("INTEGRATOR/HHT")).expect("applies");
        let integ = st.iter().find(|s| s.keyword == "INTEGRATOR").unwrap();
        let keys: Vec<&str> = integ.args.iter().map(|a| a.key.as_str()).collect();
        assert_eq!(keys, ["ERROR", "HHT"]);
        let err = redefine(&mut st, &command("VARIABLE/99, FUNCTION = 1")).unwrap_err();
        assert_eq!(
            err.to_string(),
            "the dataset has no VARIABLE/99: a command can change an element, not create one"
        );
    }

    #[test]
    fn inactive_statements_are_left_out() {
        let ds = dataset(MODEL);
        let inactive = BTreeSet::from([("MOTION".to_string(), 6)]);
        let typed = retype(&ds, &ds.statements, &inactive).expect("types");
        assert!(typed.motions.is_empty());
        assert_eq!(typed.joints.len(), 1);
    }

    #[test]
    fn deactivate_names_choose_by_element_kind_or_name() {
        let ds = dataset(MODEL);
        let names = |n: &[&str]| -> Vec<String> {
            let chosen = select(
                &ds.statements,
                &n.iter().map(|s| s.to_string()).collect::<Vec<_>>(),
            )
            .expect("chosen");
            chosen.iter().map(Selected::element).collect()
        };
        assert_eq!(names(&["motion/6"]), ["MOTION/6"]);
        assert_eq!(names(&["MOT"]), ["MOTION/6"]);
        assert_eq!(
            names(&["JOINT_5", "MOTION/6", "motion"]),
            ["JOINT/5", "MOTION/6"]
        );
        let e = select(&ds.statements, &["EQUILIBRIUM".to_string()]).unwrap_err();
        assert!(e.contains("--deactivate EQUILIBRIUM"), "{e}");
        assert!(select(&ds.statements, &["JOINT/x".to_string()]).is_err());
        let left = select(&ds.statements, &["MOTION".to_string()]).expect("chosen");
        assert_eq!(left[0].line, 7);
        assert!(without(&ds, &left).expect("types").motions.is_empty());
    }
}
