//! The model a command file works on: the dataset as read, its statements as the commands have
//! amended them (redefinitions, deactivated elements), the model built from them, and the state
//! the last analysis left.
//!
//! Contract:
//! - [`Session::open`] reads and builds the dataset; every input error comes back at once.
//! - [`Session::redefine`], [`Session::deactivate`] and [`Session::activate`] change the
//!   statements and rebuild the model right away, so that an error names the command that
//!   caused it; the state the last analysis left is kept.
//! - [`Session::input_model`] is the model every analysis assembles: before the first analysis
//!   the dataset's own input (joint IC, EXACT, part velocities as given); afterwards the
//!   parts placed and moving as the last analysis left them (all velocities given, joint ICs
//!   and EXACT spent, as in Adams, where they apply to the first assembly only).

use crate::error::RunError;
use glam::DVec3;
use linkage_adm::amend::{self, Redefined};
use linkage_adm::{Dataset, Diagnostic, Diagnostics, Statement};
use linkage_model::{ConstraintKind, Model};
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::coverage::{self, Analysis, Finding};
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::state::State;
use std::collections::BTreeSet;
use std::path::Path;

/// Velocities of every part: CM velocity and angular velocity, ground axes.
pub type Velocities = Vec<(DVec3, DVec3)>;

/// A model built from the session's statements, with what every analysis needs.
pub struct Built {
    pub model: Model,
    pub drivers: ExpressionDrivers,
    /// `None` when some statement makes every force analysis refuse the model (the
    /// analyses then say which, [`Session::refusals`]).
    pub forces: Option<ForceSet>,
    /// Every statement some analysis refuses or runs without (of the active statements).
    pub findings: Vec<Finding>,
    pub requests: RequestSet,
    /// Dataset, model and function warnings.
    pub warnings: Vec<Diagnostic>,
}

/// Where the last analysis left the model.
#[derive(Clone, Debug)]
pub struct Left {
    pub state: State,
    pub velocities: Velocities,
}

/// The dataset, its amendments and the model built from them.
pub struct Session {
    dataset: Dataset,
    statements: Vec<Statement>,
    inactive: BTreeSet<(String, u64)>,
    pub built: Built,
    /// `None` before the first analysis.
    pub left: Option<Left>,
    /// A SENSOR's HALT ended the last simulation: the command file ends there (`SENSOR_1 at
    /// time 1.0`).
    pub halted: Option<String>,
}

/// Builds the model of a typed dataset with its drivers, forces and requests.
fn build(ds: &Dataset) -> Result<Built, Diagnostics> {
    let built = linkage_model::build_model(ds)?;
    let drivers = ExpressionDrivers::new(&built.model)?;
    let findings = coverage::findings(ds);
    let forces = if findings.iter().any(|f| f.refuses(Analysis::Ic)) {
        None
    } else {
        Some(ForceSet::new(&built.model)?)
    };
    let requests = RequestSet::new(&built.model)?;
    let mut warnings = built.warnings;
    warnings.extend(drivers.warnings().iter().cloned());
    Ok(Built {
        model: built.model,
        drivers,
        forces,
        findings,
        requests,
        warnings,
    })
}

impl Session {
    /// Reads the dataset at `path` and builds it without the statements `deactivate` names
    /// (see [`linkage_adm::amend::select`]), read with `read`.
    pub fn open(
        path: &Path,
        deactivate: &[String],
        read: linkage_adm::ReadOptions,
    ) -> Result<Session, RunError> {
        let dataset = linkage_adm::read_dataset_with(path, read).map_err(RunError::Input)?;
        let left_out =
            linkage_adm::amend::select(&dataset.statements, deactivate).map_err(|e| {
                RunError::Input(Diagnostics(vec![Diagnostic::error(
                    dataset.file.clone(),
                    None,
                    e,
                )]))
            })?;
        let inactive: BTreeSet<(String, u64)> =
            left_out.into_iter().map(|s| (s.keyword, s.id)).collect();
        let active = if inactive.is_empty() {
            dataset.clone()
        } else {
            amend::retype(&dataset, &dataset.statements, &inactive).map_err(RunError::Input)?
        };
        let built = build(&active).map_err(RunError::Input)?;
        Ok(Session {
            statements: dataset.statements.clone(),
            dataset,
            inactive,
            built,
            left: None,
            halted: None,
        })
    }

    /// The dataset's file name.
    pub fn file(&self) -> &str {
        &self.dataset.file
    }

    /// The time the last analysis left the model at (0 before the first).
    pub fn time(&self) -> f64 {
        self.left.as_ref().map_or(0.0, |l| l.state.time)
    }

    /// Rebuilds the model from the amended statements, keeping the old one when that fails.
    fn rebuild(
        &mut self,
        statements: Vec<Statement>,
        inactive: BTreeSet<(String, u64)>,
    ) -> Result<(), Diagnostics> {
        let ds = amend::retype(&self.dataset, &statements, &inactive)?;
        let built = build(&ds)?;
        if built.model.parts.len() != self.built.model.parts.len() {
            return Err(Diagnostics(vec![Diagnostic::error(
                self.dataset.file.clone(),
                None,
                "a command may not add or remove parts".to_string(),
            )]));
        }
        self.statements = statements;
        self.inactive = inactive;
        self.built = built;
        Ok(())
    }

    /// Applies a statement given as a command (`VARIABLE/9105, FUNCTION = …`,
    /// `EQUILIBRIUM/STABILITY = 1e-3`) and rebuilds the model.
    pub fn redefine(&mut self, change: &Statement) -> Result<Redefined, Diagnostics> {
        let mut statements = self.statements.clone();
        let done = amend::redefine(&mut statements, change).map_err(|e| {
            Diagnostics(vec![Diagnostic::error(
                self.dataset.file.clone(),
                None,
                e.to_string(),
            )])
        })?;
        self.rebuild(statements, self.inactive.clone())?;
        Ok(done)
    }

    /// Deactivates (or with `active`, activates again) the `keyword` statements whose ids
    /// `selects` accepts, and rebuilds the model. Selecting none is an error.
    pub fn set_active(
        &mut self,
        keyword: &str,
        selects: impl Fn(u64) -> bool,
        active: bool,
    ) -> Result<(), Diagnostics> {
        let mut inactive = self.inactive.clone();
        let mut found = 0;
        for id in self
            .statements
            .iter()
            .filter(|s| s.keyword == keyword)
            .filter_map(|s| s.id)
            .filter(|&id| selects(id))
        {
            found += 1;
            if active {
                inactive.remove(&(keyword.to_string(), id));
            } else {
                inactive.insert((keyword.to_string(), id));
            }
        }
        if found == 0 {
            return Err(Diagnostics(vec![Diagnostic::error(
                self.dataset.file.clone(),
                None,
                format!("the dataset has no {keyword} with the ids given"),
            )]));
        }
        self.rebuild(self.statements.clone(), inactive)
    }

    /// The amended statement `keyword/id` (active or not).
    pub fn statement(&self, keyword: &str, id: u64) -> Option<&Statement> {
        self.statements
            .iter()
            .find(|s| s.keyword == keyword && s.id == Some(id))
    }

    /// The statements of the model that analysis `a` refuses, one line each (`file:line:col:
    /// error: …`) with the command that leaves it out; empty when `a` can run.
    pub fn refusals(&self, a: Analysis) -> Vec<String> {
        self.built
            .findings
            .iter()
            .filter(|f| f.refuses(a))
            .map(|f| {
                let command = linkage_adm::commands::ElementType::ALL
                    .iter()
                    .any(|e| e.keyword() == f.keyword);
                let hint = match f.id {
                    Some(id) if command => format!(
                        "DEACTIVATE/{}, ID = {id} (or `linkage run --deactivate {}`) runs the \
                         rest of the model",
                        f.keyword, f.element
                    ),
                    _ => format!(
                        "`linkage run --deactivate {}` runs the rest of the model",
                        f.element
                    ),
                };
                f.error().with_hint(hint).to_string()
            })
            .collect()
    }

    /// The dataset as read.
    pub fn dataset(&self) -> &Dataset {
        &self.dataset
    }

    /// The inactive statements, in dataset order (DEACTIVATE).
    pub fn left_out(&self) -> Vec<linkage_adm::amend::Selected> {
        self.statements
            .iter()
            .filter_map(|st| {
                let id = st.id?;
                self.inactive.contains(&(st.keyword.clone(), id)).then(|| {
                    linkage_adm::amend::Selected {
                        keyword: st.keyword.clone(),
                        id,
                        name: st
                            .view_name
                            .clone()
                            .unwrap_or_else(|| format!("{}_{id}", st.keyword)),
                        line: st.span.line,
                    }
                })
            })
            .collect()
    }

    /// How many statements are inactive.
    pub fn inactive(&self) -> usize {
        self.inactive.len()
    }

    /// The model the next analysis assembles (see the module documentation).
    pub fn input_model(&self) -> Model {
        match &self.left {
            None => self.built.model.clone(),
            Some(left) => placed(&self.built.model, left),
        }
    }
}

/// `model` with its parts where `left` has them and moving as it has them, every velocity
/// given, and the joint initial conditions and EXACT coordinates spent.
pub fn placed(model: &Model, left: &Left) -> Model {
    let mut m = model.clone();
    for (k, p) in m.parts.iter_mut().enumerate() {
        let pose = left.state.poses[k];
        p.p_gb = pose.p;
        p.r_gb = pose.r;
        let (v, w) = left.velocities[k];
        let w_cm = (pose.r * p.r_b_cm).transpose() * w;
        p.velocity = [v.x, v.y, v.z, w_cm.x, w_cm.y, w_cm.z].map(Some);
        p.exact.clear();
    }
    for c in &mut m.constraints {
        if let ConstraintKind::Joint { initial, .. } = &mut c.kind {
            initial.translation = (None, None);
            initial.rotation = (None, None);
        }
    }
    m
}
