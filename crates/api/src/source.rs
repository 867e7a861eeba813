//! A dataset as read, with the argument changes asked for before an analysis
//! (`Source::set`), and the model built from it (`Loaded`).
//!
//! Changes go through the command files' redefinition machinery
//! ([`linkage_adm::amend::redefine`], then [`linkage_adm::amend::retype`]), so `set("SPRINGDAMPER/1",
//! "K", 4000.0)` means exactly what `SPRINGDAMPER/1, K = 4000` means in a command file; an
//! error in the changed statement is reported at the statement's file:line:column.

use linkage_adm::amend::{Redefined, Selected};
use linkage_adm::statement::{Argument, ExprText, Statement, Value};
use linkage_adm::{Dataset, Diagnostic, Diagnostics, Span};
use linkage_model::functions::UserRoutines;
use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::coverage::{self, Analysis, Finding};
use linkage_solve::physics::forces::ForceSet;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// A dataset read, built and with its functions parsed: the one loaded-model type of every
/// front end (CLI, command files, Python, sweeps).
pub struct Loaded {
    /// The dataset without the statements left out on request.
    pub dataset: Dataset,
    pub model: Model,
    pub drivers: ExpressionDrivers,
    /// Dataset, model and function warnings.
    pub warnings: Vec<Diagnostic>,
    /// The statements left out on request (`--deactivate`, DEACTIVATE).
    pub left_out: Vec<Selected>,
    /// Every statement of the dataset some analysis refuses or runs without.
    pub findings: Vec<Finding>,
    /// The applied force elements, built once when the model is loaded for an analysis
    /// (`None` for verify, and when some statement makes every analysis refuse the model).
    forces: Option<ForceSet>,
    /// How a refusal tells the user to leave a statement out (the front end's way).
    pub refusal: Refusal,
}

impl Loaded {
    /// The applied force elements for `analysis` (gravity is applied by the analyses), or its
    /// input errors: every statement it refuses, all at once, each saying how to leave it out
    /// ([`Loaded::refusal`]).
    pub fn forces(&self, analysis: Analysis) -> Result<&ForceSet, crate::Error> {
        let refused = self.refusals(analysis);
        if !refused.is_empty() {
            return Err(crate::Error::Refused {
                analysis,
                diagnostics: Diagnostics(refused),
            });
        }
        match &self.forces {
            Some(f) => Ok(f),
            // Built on demand only for a model loaded for verify (no analysis named).
            None => Err(crate::Error::Input(Diagnostics(vec![Diagnostic::error(
                self.dataset.file.clone(),
                None,
                "the model was loaded for verify only: its forces were not built".to_string(),
            )]))),
        }
    }

    /// Holds VARIABLE/`id` at `value` in the forces every later analysis of this model runs
    /// with (its FUNCTION replaced by the number), without loading the model again: a plant
    /// input set between co-simulation steps ([`crate::cosim`]). `false` when the model has
    /// no such VARIABLE or its forces were not built.
    pub fn hold_variable(&mut self, id: u32, value: f64) -> bool {
        self.forces
            .as_mut()
            .is_some_and(|f| f.hold_variable(id, value))
    }

    /// Every statement `analysis` refuses, as an input error with the way of leaving it out;
    /// empty when `analysis` can run.
    pub fn refusals(&self, analysis: Analysis) -> Vec<Diagnostic> {
        self.findings
            .iter()
            .filter(|f| f.refuses(analysis))
            .map(|f| refusal(f, self.refusal))
            .collect()
    }

    /// What a report of `analysis` says about the statements left out and those it ran
    /// without.
    pub fn coverage(
        &self,
        analysis: Analysis,
    ) -> (
        Vec<linkage_report::coverage::LeftOutJson>,
        Vec<linkage_report::coverage::FindingJson>,
    ) {
        (
            linkage_report::coverage::left_out_json(&self.left_out),
            linkage_report::coverage::runs_without_json(&self.findings, analysis),
        )
    }
}

/// How a front end leaves a refused statement out, for the hint of a refusal.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Refusal {
    /// `--deactivate NAME` (the CLI, Python's `deactivate=`, a sweep's `deactivate`).
    #[default]
    Option,
    /// A command file: `DEACTIVATE/KEYWORD, ID = id` where the statement is one a command
    /// can deactivate, or `linkage run --deactivate NAME`.
    CommandFile,
}

/// The value given to a statement argument by [`Source::set`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum ArgValue {
    /// `K = 4000`.
    Number(f64),
    /// `QG = 0, 0, 1`.
    Numbers(Vec<f64>),
    /// `FUNCTION = 1000*TIME` (an expression, written as in a dataset).
    Expression(String),
}

impl std::fmt::Display for ArgValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ArgValue::Number(x) => write!(f, "{x}"),
            ArgValue::Numbers(xs) => {
                let parts: Vec<String> = xs.iter().map(f64::to_string).collect();
                write!(f, "{}", parts.join(", "))
            }
            ArgValue::Expression(e) => write!(f, "{e}"),
        }
    }
}

/// A dataset as read, and its statements with every change made by [`Source::set`].
#[derive(Clone)]
pub struct Source {
    read: Dataset,
    /// The statements with the changes made; `None` until [`Source::set`] changes one (the
    /// dataset's own statements then stand, without a second copy of them).
    amended: Option<Vec<Statement>>,
    /// Statements left out by a command (DEACTIVATE) or by [`Source::leave_out`], as
    /// `(keyword, id)`.
    inactive: BTreeSet<(String, u64)>,
    /// The linker of the dataset's `USER(…)` calls ([`Source::with_user_libraries`]).
    user: UserRoutines,
}

impl Source {
    /// Reads the dataset at `path` (syntax and typing errors come with file:line:column).
    pub fn read(path: &Path) -> Result<Source, Diagnostics> {
        Source::read_with(path, linkage_adm::ReadOptions::default())
    }

    /// [`Source::read`] with `options` (lenient arguments).
    pub fn read_with(
        path: &Path,
        options: linkage_adm::ReadOptions,
    ) -> Result<Source, Diagnostics> {
        Ok(Source::from_dataset(linkage_adm::read_dataset_with(
            path, options,
        )?))
    }

    pub fn from_dataset(read: Dataset) -> Source {
        Source {
            read,
            amended: None,
            inactive: BTreeSet::new(),
            user: UserRoutines::default(),
        }
    }

    /// Links the dataset's `USER(…)` calls to the subroutines of the libraries `paths` (files
    /// or folders: `--user-lib`), looked for as [`linkage_usersub::search`] says (those
    /// places, the dataset's folder, `LD_LIBRARY_PATH`). No paths: USER calls stay refused.
    /// Errors: a path that names nothing; the utility routines cannot be loaded.
    pub fn with_user_libraries(mut self, paths: &[PathBuf]) -> Result<Source, Diagnostics> {
        let dataset = Path::new(&*self.read.file);
        self.user = linkage_usersub::user_routines(paths, Some(dataset)).map_err(|e| {
            Diagnostics(vec![Diagnostic::error(
                self.read.file.clone(),
                None,
                e.to_string(),
            )])
        })?;
        Ok(self)
    }

    /// The library files the dataset's `USER(…)` calls loaded so far, with their full paths.
    pub fn user_libraries_loaded(&self) -> Vec<String> {
        self.user.0.as_ref().map_or_else(Vec::new, |l| l.loaded())
    }

    /// The dataset as read.
    pub fn dataset(&self) -> &Dataset {
        &self.read
    }

    /// The amended statement `keyword/id` (active or not).
    pub fn statement(&self, keyword: &str, id: u64) -> Option<&Statement> {
        self.statements()
            .iter()
            .find(|s| s.keyword == keyword && s.id == Some(id))
    }

    /// Leaves out the statements `names` selects ([`linkage_adm::amend::select`]: `SENSOR/3`,
    /// a statement kind, an element's name) from every model loaded from here on.
    pub fn leave_out(&mut self, names: &[String]) -> Result<(), Diagnostics> {
        if names.is_empty() {
            return Ok(());
        }
        let selected = linkage_adm::amend::select(self.statements(), names)
            .map_err(|e| Diagnostics(vec![Diagnostic::error(self.read.file.clone(), None, e)]))?;
        self.inactive
            .extend(selected.into_iter().map(|s| (s.keyword, s.id)));
        Ok(())
    }

    /// Applies a whole statement given as a command (`VARIABLE/9105, FUNCTION = …`,
    /// `EQUILIBRIUM/STABILITY = 1e-3`; [`linkage_adm::amend::redefine`]). The changed
    /// statements are typed again; on an error the source is left unchanged.
    pub fn redefine(&mut self, change: &Statement) -> Result<Redefined, Diagnostics> {
        let mut statements = self.statements().to_vec();
        let done = linkage_adm::amend::redefine(&mut statements, change).map_err(|e| {
            Diagnostics(vec![Diagnostic::error(
                self.read.file.clone(),
                None,
                e.to_string(),
            )])
        })?;
        linkage_adm::amend::retype(&self.read, &statements, &self.inactive)?;
        self.amended = Some(statements);
        Ok(done)
    }

    /// Deactivates (or with `active`, activates again) the `keyword` statements whose ids
    /// `selects` accepts (DEACTIVATE/ACTIVATE). Selecting none is an error.
    pub fn set_active(
        &mut self,
        keyword: &str,
        selects: impl Fn(u64) -> bool,
        active: bool,
    ) -> Result<(), Diagnostics> {
        let ids: Vec<u64> = self
            .statements()
            .iter()
            .filter(|s| s.keyword == keyword)
            .filter_map(|s| s.id)
            .filter(|&id| selects(id))
            .collect();
        if ids.is_empty() {
            return Err(Diagnostics(vec![Diagnostic::error(
                self.read.file.clone(),
                None,
                format!("the dataset has no {keyword} with the ids given"),
            )]));
        }
        for id in ids {
            if active {
                self.inactive.remove(&(keyword.to_string(), id));
            } else {
                self.inactive.insert((keyword.to_string(), id));
            }
        }
        Ok(())
    }

    /// How many statements are inactive.
    pub fn inactive_count(&self) -> usize {
        self.inactive.len()
    }

    /// The statements with every change made so far.
    fn statements(&self) -> &[Statement] {
        self.amended.as_deref().unwrap_or(&self.read.statements)
    }

    /// The dataset's file name, as diagnostics give it.
    pub fn file(&self) -> &str {
        &self.read.file
    }

    /// Sets argument `argument` of the statement `statement` (`KEYWORD/id`, the keyword as in
    /// a dataset, abbreviations included; a settings statement such as `EQUILIBRIUM` without
    /// id) to `value`, as a command-file redefinition does: the argument replaces the one of
    /// the same keyword (or unambiguous prefix), or is added. The change is checked by typing
    /// the dataset again; its errors are returned and the source is left unchanged.
    pub fn set(
        &mut self,
        statement: &str,
        argument: &str,
        value: &ArgValue,
    ) -> Result<(), Diagnostics> {
        let error = |message: String| {
            Diagnostics(vec![Diagnostic::error(
                self.read.file.clone(),
                None,
                message,
            )])
        };
        let (keyword, id) = parse_element(statement).map_err(|e| error(e.to_string()))?;
        let keyword = self
            .resolve_keyword(&keyword, id)
            .map_err(|e| error(e.to_string()))?;
        let key = argument.trim().to_ascii_uppercase();
        if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(error(format!("`{argument}` is not an argument keyword")));
        }
        // The new value is placed where the statement is, so that a typing error in it
        // points at the statement it changes.
        let at = self
            .statements()
            .iter()
            .find(|s| s.keyword == keyword && (id.is_none() || s.id == id))
            .map_or(Span::default(), |s| {
                s.args
                    .iter()
                    .find(|a| a.key == key)
                    .map_or(s.span, |a| a.span)
            });
        let values = match value {
            ArgValue::Number(x) => vec![number(*x, at)],
            ArgValue::Numbers(xs) => xs.iter().map(|x| number(*x, at)).collect(),
            ArgValue::Expression(text) => vec![Value::Expr(ExprText {
                text: text.clone(),
                origins: vec![(0, at)],
            })],
        };
        if values.is_empty() {
            return Err(error(format!(
                "{statement}, {key} = needs at least one value"
            )));
        }
        if let Some(bad) = values.iter().find_map(|v| match v {
            Value::Number { value, .. } if !value.is_finite() => Some(*value),
            _ => None,
        }) {
            return Err(error(format!(
                "{statement}, {key} = {bad}: a value must be a finite number"
            )));
        }
        let change = Statement {
            keyword: keyword.clone(),
            known: true,
            id,
            args: vec![Argument {
                key,
                values,
                span: at,
            }],
            span: at,
            lines: (at.line, at.line),
            view_name: None,
        };
        let mut statements = self.statements().to_vec();
        linkage_adm::amend::redefine(&mut statements, &change).map_err(|e| error(e.to_string()))?;
        // Typing the amended statements checks the new value now, not at the next analysis.
        linkage_adm::amend::retype(&self.read, &statements, &BTreeSet::new())?;
        self.amended = Some(statements);
        Ok(())
    }

    /// The statement keyword `keyword` stands for: one of the dataset's statement keywords
    /// that it names in full or abbreviates (at least three letters, as the language allows).
    fn resolve_keyword(&self, keyword: &str, id: Option<u64>) -> Result<String, ElementError> {
        let mut kinds: Vec<&str> = self
            .statements()
            .iter()
            .map(|s| s.keyword.as_str())
            .filter(|k| *k == keyword || (keyword.len() >= 3 && k.starts_with(keyword)))
            .collect();
        kinds.sort_unstable();
        kinds.dedup();
        match kinds.as_slice() {
            [k] => Ok((*k).to_string()),
            [] if id.is_none() => Ok(keyword.to_string()),
            [] => Err(ElementError::NoSuchStatement {
                keyword: keyword.to_string(),
                id: id.unwrap_or(0),
            }),
            many if many.contains(&keyword) => Ok(keyword.to_string()),
            many => Err(ElementError::Ambiguous {
                keyword: keyword.to_string(),
                candidates: many.iter().map(|k| k.to_string()).collect(),
            }),
        }
    }

    /// The dataset with the changes made, without the statements `deactivate` names, built and
    /// with its functions checked. `analysis` is the analysis the model is loaded for
    /// (`None`: verify). When the model does not build, the input errors also name every
    /// statement that `analysis` (verify: any analysis) would refuse, so that all of them
    /// come at once.
    pub fn load(
        &self,
        deactivate: &[String],
        analysis: Option<Analysis>,
    ) -> Result<Loaded, Diagnostics> {
        let (dataset, left_out) = match self.amended_dataset(deactivate)? {
            Some(amended) => amended,
            None => (self.read.clone(), Vec::new()),
        };
        build(dataset, left_out, analysis, &self.user)
    }

    /// [`Source::load`] for a source used once: the dataset as read is moved into the
    /// [`Loaded`] rather than copied, so that a large model is held once while it is built.
    pub fn into_loaded(
        self,
        deactivate: &[String],
        analysis: Option<Analysis>,
    ) -> Result<Loaded, Diagnostics> {
        let (dataset, left_out) = match self.amended_dataset(deactivate)? {
            Some(amended) => amended,
            None => (self.read, Vec::new()),
        };
        build(dataset, left_out, analysis, &self.user)
    }

    /// [`Source::into_loaded`] for a caller that needs only the model (verify without a
    /// change to save): the text and the raw statements the model builder reads only in
    /// their typed form ([`linkage_model::TYPED_ONLY`]) are freed before the model is built,
    /// and the returned [`Loaded::dataset`] is empty but for its file name.
    pub fn into_model(
        self,
        deactivate: &[String],
        analysis: Option<Analysis>,
    ) -> Result<Loaded, Diagnostics> {
        let (mut dataset, left_out) = match self.amended_dataset(deactivate)? {
            Some(amended) => amended,
            None => (self.read, Vec::new()),
        };
        let findings = coverage::findings_with(&dataset, &self.user);
        dataset.text = String::new();
        dataset
            .statements
            .retain(|s| !linkage_model::TYPED_ONLY.contains(&s.keyword.as_str()));
        dataset.statements.shrink_to_fit();
        let mut loaded = build_found(dataset, left_out, analysis, findings, &self.user)?;
        loaded.dataset = Dataset::empty(loaded.dataset.file.clone());
        Ok(loaded)
    }

    /// The dataset typed again from the changed statements without those `deactivate` names,
    /// with the statements left out; `None` when nothing is changed or left out (the dataset
    /// as read stands).
    fn amended_dataset(
        &self,
        deactivate: &[String],
    ) -> Result<Option<(Dataset, Vec<Selected>)>, Diagnostics> {
        let mut inactive = self.inactive.clone();
        if !deactivate.is_empty() {
            let named = linkage_adm::amend::select(self.statements(), deactivate).map_err(|e| {
                Diagnostics(vec![Diagnostic::error(self.read.file.clone(), None, e)])
            })?;
            inactive.extend(named.into_iter().map(|s| (s.keyword, s.id)));
        }
        if inactive.is_empty() && self.amended.is_none() {
            return Ok(None);
        }
        let dataset = linkage_adm::amend::retype(&self.read, self.statements(), &inactive)?;
        Ok(Some((dataset, self.selected(&inactive))))
    }
}

impl Source {
    /// The statements of `inactive`, in dataset order.
    fn selected(&self, inactive: &BTreeSet<(String, u64)>) -> Vec<Selected> {
        self.statements()
            .iter()
            .filter(|st| {
                st.id
                    .is_some_and(|id| inactive.contains(&(st.keyword.clone(), id)))
            })
            .map(Selected::of)
            .collect()
    }
}

fn number(value: f64, span: Span) -> Value {
    Value::Number {
        value,
        degrees: false,
        span,
    }
}

/// `KEYWORD/id` (or `KEYWORD` for a settings statement) upper-cased, or why it is not one.
fn parse_element(element: &str) -> Result<(String, Option<u64>), ElementError> {
    let text = element.trim();
    let (keyword, id) = match text.split_once('/') {
        Some((k, "")) => (k, None),
        Some((k, id)) => (
            k,
            Some(
                id.trim()
                    .parse::<u64>()
                    .map_err(|_| ElementError::IdNotWhole(element.to_string()))?,
            ),
        ),
        None => (text, None),
    };
    let keyword = keyword.trim().to_ascii_uppercase();
    if keyword.is_empty() || !keyword.chars().all(|c| c.is_ascii_alphabetic() || c == '_') {
        return Err(ElementError::NotAStatement(element.to_string()));
    }
    Ok((keyword, id))
}

/// Why [`Source::set`] cannot find the statement it names.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ElementError {
    #[error("`{0}`: the id after the slash must be a whole number")]
    IdNotWhole(String),
    #[error("`{0}` is not a statement (KEYWORD/id, e.g. SPRINGDAMPER/1)")]
    NotAStatement(String),
    #[error("the dataset has no {keyword}/{id}: only a statement of the dataset can be changed")]
    NoSuchStatement { keyword: String, id: u64 },
    #[error("{keyword} is ambiguous: it could be {}", .candidates.join(", "))]
    Ambiguous {
        keyword: String,
        candidates: Vec<String>,
    },
}

/// Reads the dataset at `path`, leaves out the statements `deactivate` names, builds it and
/// checks its functions (see [`Source::load`]).
pub fn load(
    path: &Path,
    deactivate: &[String],
    analysis: Option<Analysis>,
) -> Result<Loaded, Diagnostics> {
    Source::read(path)?.into_loaded(deactivate, analysis)
}

/// Reads the dataset at `path` and builds its model, keeping nothing of the dataset but its
/// file name (see [`Source::into_model`]).
pub fn load_model(
    path: &Path,
    deactivate: &[String],
    analysis: Option<Analysis>,
) -> Result<Loaded, Diagnostics> {
    Source::read(path)?.into_model(deactivate, analysis)
}

/// Builds `dataset` (the statements `left_out` already removed from it).
fn build(
    dataset: Dataset,
    left_out: Vec<Selected>,
    analysis: Option<Analysis>,
    user: &UserRoutines,
) -> Result<Loaded, Diagnostics> {
    let findings = coverage::findings_with(&dataset, user);
    build_found(dataset, left_out, analysis, findings, user)
}

/// [`build`] with the dataset's findings already made.
fn build_found(
    dataset: Dataset,
    left_out: Vec<Selected>,
    analysis: Option<Analysis>,
    findings: Vec<Finding>,
    user: &UserRoutines,
) -> Result<Loaded, Diagnostics> {
    let built = linkage_model::build_model_with(&dataset, user)
        .and_then(|b| ExpressionDrivers::new(&b.model).map(|d| (b, d)));
    let (built, drivers) = match built {
        Ok(b) => b,
        Err(mut d) => {
            d.0.extend(refused_as_diagnostics(&findings, analysis, &d.0));
            explain_left_out(&mut d, &left_out);
            return Err(d);
        }
    };
    let mut warnings = built.warnings;
    warnings.extend(drivers.warnings().iter().cloned());
    // The forces of a model some statement of which every analysis refuses are not built
    // (their elements may be what is refused); each analysis then names the statements.
    let forces = match analysis {
        Some(a) if !findings.iter().any(|f| f.refuses(a)) => {
            Some(ForceSet::new(&built.model).map_err(|mut d| {
                explain_left_out(&mut d, &left_out);
                d
            })?)
        }
        _ => None,
    };
    if let Some(linker) = &user.0 {
        // Every report names the foreign code the run loaded, with full paths.
        for lib in linker.loaded() {
            warnings.push(Diagnostic {
                severity: linkage_adm::Severity::Note,
                ..Diagnostic::error(
                    dataset.file.clone(),
                    None,
                    format!("user subroutines loaded from {lib}"),
                )
            });
        }
    }
    Ok(Loaded {
        dataset,
        model: built.model,
        drivers,
        warnings,
        left_out,
        findings,
        forces,
        refusal: Refusal::Option,
    })
}

/// Says, on each error about a reference to a statement that does not exist because it was
/// left out on request (`--deactivate`, DEACTIVATE), that it was left out and what to do:
/// the error itself names the element that uses it.
fn explain_left_out(d: &mut Diagnostics, left_out: &[Selected]) {
    for diagnostic in &mut d.0 {
        let missing = left_out.iter().find(|s| {
            let kw = s.keyword.to_ascii_uppercase();
            [
                format!("{kw}/{} does not exist", s.id),
                format!("{kw} {} does not exist", s.id),
                format!("{} {} does not exist", kw.to_ascii_lowercase(), s.id),
            ]
            .iter()
            .any(|p| diagnostic.message.contains(p.as_str()))
        });
        if let Some(s) = missing {
            diagnostic.hint = Some(format!(
                "{} ({}, line {}) is left out on request (--deactivate or DEACTIVATE): leave \
                 out what uses it too, or keep it",
                s.element(),
                s.name,
                s.line
            ));
        }
    }
}

/// The findings `analysis` refuses (verify, `None`: that any analysis refuses) as
/// diagnostics, leaving out those at a line some diagnostic of `already` is at: errors for an
/// analysis, notes for verify.
fn refused_as_diagnostics(
    findings: &[Finding],
    analysis: Option<Analysis>,
    already: &[Diagnostic],
) -> Vec<Diagnostic> {
    findings
        .iter()
        .filter(|f| match analysis {
            Some(a) => f.refuses(a),
            None => !f.refused_by.is_empty(),
        })
        .filter(|f| {
            !already
                .iter()
                .any(|d| d.span.is_some_and(|s| s.line == f.span.line))
        })
        .map(|f| {
            let mut d = refusal(f, Refusal::Option);
            if analysis.is_none() {
                d.severity = linkage_adm::Severity::Note;
            }
            d
        })
        .collect()
}

/// The input error of an analysis refusing `f`, with the way that runs without it.
fn refusal(f: &Finding, hint: Refusal) -> Diagnostic {
    let command = linkage_adm::commands::ElementType::ALL
        .iter()
        .any(|e| e.keyword() == f.keyword);
    let hint = match (hint, f.id) {
        (Refusal::CommandFile, Some(id)) if command => format!(
            "DEACTIVATE/{}, ID = {id} (or `linkage run --deactivate {}`) runs the rest of the \
             model",
            f.keyword, f.element
        ),
        (Refusal::CommandFile, _) => format!(
            "`linkage run --deactivate {}` runs the rest of the model",
            f.element
        ),
        (Refusal::Option, _) => format!(
            "--deactivate {} runs the rest of the model without it",
            f.element
        ),
    };
    f.error().with_hint(hint)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spring_mass() -> Source {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/spring_mass.adm");
        Source::read(&path).expect("the example reads")
    }

    /// The numbers of argument `key` of statement `keyword`/`id`.
    fn numbers(s: &Source, keyword: &str, id: Option<u64>, key: &str) -> Vec<f64> {
        let st = s
            .statements()
            .iter()
            .find(|st| st.keyword == keyword && st.id == id)
            .expect("statement");
        st.arg(key)
            .expect("argument")
            .values
            .iter()
            .filter_map(|v| match v {
                Value::Number { value, .. } => Some(*value),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn set_replaces_or_adds_an_argument_as_a_redefinition_does() {
        let mut s = spring_mass();
        s.set("spring/1", "k", &ArgValue::Number(400.0))
            .expect("K changes");
        assert_eq!(numbers(&s, "SPRINGDAMPER", Some(1), "K"), vec![400.0]);
        s.set("MARKER/101", "QP", &ArgValue::Numbers(vec![0.0, 0.0, 2.0]))
            .expect("QP changes");
        assert_eq!(numbers(&s, "MARKER", Some(101), "QP"), vec![0.0, 0.0, 2.0]);
        // A settings statement the dataset lacks is added.
        s.set("EQUILIBRIUM", "STABILITY", &ArgValue::Number(1e-3))
            .expect("added");
        assert_eq!(numbers(&s, "EQUILIBRIUM", None, "STABILITY"), vec![1e-3]);
        // The changed model builds, with the new spring rate in force.
        let loaded = s.load(&[], Some(Analysis::Linear)).expect("builds");
        let report = crate::job::Job::Linear {
            static_first: false,
            no_damping: false,
            no_vectors: false,
            modes: None,
            shift: None,
            allow_unstable: false,
        }
        .run(&loaded, None)
        .expect("runs")
        .report;
        // f = sqrt(k/m)/2π with k = 400 N/m, m = 2 kg (rounding only: 1e-12 relative).
        let f = report["modes"][0]["frequency"].as_f64().expect("a mode");
        let expected = (400.0f64 / 2.0).sqrt() / std::f64::consts::TAU;
        assert!((f - expected).abs() < 1e-12 * expected, "{f} vs {expected}");
    }

    #[test]
    fn a_change_that_cannot_be_is_refused_and_nothing_changes() {
        let mut s = spring_mass();
        let message = |r: Result<(), Diagnostics>| r.expect_err("refused").to_string();
        let none = message(s.set("SPRINGDAMPER/7", "K", &ArgValue::Number(1.0)));
        assert!(none.contains("no SPRINGDAMPER/7"), "{none}");
        let bad_id = message(s.set("SPRINGDAMPER/x", "K", &ArgValue::Number(1.0)));
        assert!(bad_id.contains("whole number"), "{bad_id}");
        let nan = message(s.set("SPRINGDAMPER/1", "K", &ArgValue::Number(f64::NAN)));
        assert!(nan.contains("finite"), "{nan}");
        // A value of the wrong kind is a typing error at the argument it replaces.
        let typed = message(s.set("SPRINGDAMPER/1", "K", &ArgValue::Expression("1 +".into())));
        assert!(typed.contains("spring_mass.adm:25:"), "{typed}");
        assert_eq!(numbers(&s, "SPRINGDAMPER", Some(1), "K"), vec![800.0]);
        assert!(s.amended.is_none());
    }

    #[test]
    fn a_model_built_without_the_raw_statements_is_the_same_model() {
        // The four-bar has GRAPHICS, which the builder types from their raw statements.
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fourbar.adm");
        let mut s = Source::read(&path).expect("the example reads");
        // Settings statements are raw statements the model builder reads.
        s.set("EQUILIBRIUM", "STABILITY", &ArgValue::Number(1e-3))
            .expect("added");
        s.set("INTEGRATOR", "ERROR", &ArgValue::Number(1e-5))
            .expect("added");
        s.set("IC", "ERROR", &ArgValue::Number(1e-7))
            .expect("added");
        let whole = s.load(&[], None).expect("builds");
        let lean = s.into_model(&[], None).expect("builds");
        assert_eq!(format!("{:?}", whole.model), format!("{:?}", lean.model));
        assert_eq!(lean.model.integrator.settings.error, 1e-5);
        assert_eq!(lean.model.ic.error, 1e-7);
        assert!(lean.dataset.statements.is_empty() && lean.dataset.text.is_empty());
        assert!(whole.dataset.statements.len() > 10);
        assert!(!whole.model.graphics.is_empty());
        assert_eq!(whole.findings.len(), lean.findings.len());
    }
}
