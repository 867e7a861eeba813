//! The assembled problem: built once per dataset, consumed by every analysis. This layer owns
//! the initial-conditions solve: [`verify`] (rank analysis at the input), [`assemble`]
//! (least-change assembly) and [`ic`] (re-verification at the assembled pose, velocity and
//! acceleration/force IC), on the shared [`crate::kernel`]; it imports no stage.
//!
//! ```text
//! Model ──Assembled::new──▶ Assembled ──▶ statics::run      (equilibrium, quasi-statics)
//!   (compile the system,       │      ──▶ settle::settle    (damped dynamics, frozen time)
//!    initial conditions,       │      ──▶ linearize::run    (modes about an operating point)
//!    kept/removed rows,        │      ──▶ dynamics::run     (simulation, or kinematics at 0 DOF)
//!    anchored motions)         └──▶ failure(): the one definition of "could not be assembled"
//! ```
//!
//! The model is immutable; an [`Assembled`] holds what every stage shares and never changes
//! after assembly: the compiled [`System`], the initial conditions, the rows every stage
//! enforces (the independent set at the assembled pose) and the redundant rows it monitors,
//! the motion drivers anchored at the assembled configuration (velocity and acceleration
//! motions without ICDISP start from the displacement the assembly gave them, so
//! `q(t) = q(0) + ∫f`), and the applied forces. Each stage takes `&Assembled` (or the state a
//! previous stage left) and returns its own result type.

pub mod assemble;
pub mod ic;
pub mod verify;

use crate::constraints::drivers::ExpressionDrivers;
use crate::constraints::residuals::report_unit_suffix;
use crate::constraints::system::System;
use crate::kernel::{ExtraDamping, Problem};
use crate::physics::applied::{AppliedForces, Regime};
use crate::state::{ElementState, State};
use crate::tolerances::Tolerances;
use glam::DVec3;
use ic::{initial_conditions_at, InitialConditions};
use linkage_model::Model;

/// A redundant equation that the assembled configuration cannot satisfy.
#[derive(Clone, Debug, PartialEq)]
pub struct InconsistentEquation {
    /// The element's name (`JOINT_7` or its view name).
    pub element: String,
    /// The equation, as verify names it (`Rotation Between Zi & Xj`).
    pub label: &'static str,
    /// Its residual (length units or degrees) and the unit suffix used to print it.
    pub residual: Option<f64>,
    pub unit: &'static str,
}

impl std::fmt::Display for InconsistentEquation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.residual {
            Some(x) => write!(
                f,
                "{} of {} (residual {}{})",
                self.label,
                self.element,
                linkage_adm::num::sci(x, 5),
                self.unit
            ),
            None => write!(f, "{} of {}", self.label, self.element),
        }
    }
}

/// Why no analysis can start from the initial conditions.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NotAssembled {
    /// The displacement IC did not converge.
    #[error(
        "the model could not be assembled: the initial conditions did not converge (largest \
         residual {}); run `linkage ic` for the equations left unsatisfied",
        linkage_adm::num::sci(*.max_residual, 4)
    )]
    DidNotConverge { max_residual: f64 },
    /// The assembly converged but some redundant equation does not hold there.
    #[error(
        "the model cannot be assembled: redundant equation(s) inconsistent with the others: {}; \
         `linkage verify --explain` proposes joints without the redundancy",
        list(.equations)
    )]
    Inconsistent {
        equations: Vec<InconsistentEquation>,
    },
}

fn list(equations: &[InconsistentEquation]) -> String {
    equations
        .iter()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

impl NotAssembled {
    /// The judgement on initial conditions: `None` when the model is assembled (the displacement
    /// IC converged and every redundant equation holds at the assembled pose).
    pub fn judge(model: &Model, ic: &InitialConditions) -> Option<NotAssembled> {
        if !ic.assembly.converged {
            return Some(NotAssembled::DidNotConverge {
                max_residual: ic.assembly.max_residual,
            });
        }
        let sys = &ic.analysis.system;
        let equations: Vec<InconsistentEquation> = ic
            .analysis
            .redundant
            .iter()
            .filter(|r| r.consistent == Some(false))
            .map(|r| {
                let row = &sys.rows[r.row];
                InconsistentEquation {
                    element: model.constraints[row.element].origin.name.clone(),
                    label: row.label,
                    residual: r.residual,
                    unit: report_unit_suffix(row.unit),
                }
            })
            .collect();
        (!equations.is_empty()).then_some(NotAssembled::Inconsistent { equations })
    }
}

/// Whether `rows` kept constraint rows on `parts` moving parts with `controls` control states
/// leave no degree of freedom to integrate: a simulation of such a model is kinematic.
pub fn kinematic(rows: usize, parts: usize, controls: usize) -> bool {
    parts > 0 && rows >= 6 * parts && controls == 0
}

/// What an [`Assembled`] owns, without the model and forces it borrows (see
/// [`Assembled::into_assembly`]).
pub struct Assembly {
    system: System,
    ic: InitialConditions,
    kept: Vec<usize>,
    removed: Vec<usize>,
    drivers: ExpressionDrivers,
    failure: Option<NotAssembled>,
}

/// The assembled problem every analysis starts from (see the module documentation).
pub struct Assembled<'m> {
    pub model: &'m Model,
    pub forces: &'m dyn AppliedForces,
    /// The compiled constraint rows of the model (one compilation for every stage).
    pub system: System,
    /// Displacement, velocity and acceleration/force initial conditions.
    pub ic: InitialConditions,
    /// Rows every stage enforces: the independent set at the assembled configuration.
    pub kept: Vec<usize>,
    /// Redundant rows: left out of every solve (zero reactions), their consistency monitored.
    pub removed: Vec<usize>,
    /// Motion drivers anchored at the assembled configuration.
    pub drivers: ExpressionDrivers,
    failure: Option<NotAssembled>,
}

impl<'m> Assembled<'m> {
    /// Compiles the model's constraints and runs the initial conditions with `drivers` (the
    /// dataset's motions) and `forces`.
    pub fn new(
        model: &'m Model,
        drivers: &ExpressionDrivers,
        forces: &'m dyn AppliedForces,
        tol: &Tolerances,
    ) -> Assembled<'m> {
        Assembled::at_time(model, drivers, forces, tol, 0.0)
    }

    /// [`Assembled::new`] with the initial conditions at time `time` (the parts' input poses
    /// and velocities are the model's): how a command file continues after a change of the
    /// model.
    pub fn at_time(
        model: &'m Model,
        drivers: &ExpressionDrivers,
        forces: &'m dyn AppliedForces,
        tol: &Tolerances,
        time: f64,
    ) -> Assembled<'m> {
        Assembled::continuing(model, drivers, forces, tol, time, &ElementState::default())
    }

    /// [`Assembled::at_time`] continuing the element state `carried` the previous analysis
    /// left (a command file): the values its sensors stored carry on into `SENVAL`; the
    /// frictions are started again at the assembled pose, as every IC does.
    pub fn continuing(
        model: &'m Model,
        drivers: &ExpressionDrivers,
        forces: &'m dyn AppliedForces,
        tol: &Tolerances,
        time: f64,
        carried: &ElementState,
    ) -> Assembled<'m> {
        let system = System::new(model);
        let mut ic = initial_conditions_at(model, &system, drivers, forces, tol, time, carried);
        // The control states' rates consistent with their equations at the initial
        // conditions (a law that cannot be evaluated is reported by the analysis that needs
        // it).
        let v = ic.velocity.as_ref().map(|v| v.velocities.clone());
        let v = v.unwrap_or_else(|| vec![(DVec3::ZERO, DVec3::ZERO); model.parts.len()]);
        let _ = crate::physics::controls::consistent_rates(forces, &mut ic.assembly.state, &v);
        let (kept, removed) = ic.kept_and_removed_rows();
        let anchored = drivers.anchored(&system, &kept, &ic.assembly.state);
        let failure = NotAssembled::judge(model, &ic);
        Assembled {
            model,
            forces,
            system,
            ic,
            kept,
            removed,
            drivers: anchored,
            failure,
        }
    }

    /// The owned parts of this assembly, to keep between analyses of a command file while the
    /// model it borrows is amended in ways assembly does not depend on (an INTEGRATOR or
    /// EQUILIBRIUM setting): [`Assembled::from_assembly`] gives the same assembly back
    /// without compiling, ranking or assembling again.
    pub fn into_assembly(self) -> Assembly {
        Assembly {
            system: self.system,
            ic: self.ic,
            kept: self.kept,
            removed: self.removed,
            drivers: self.drivers,
            failure: self.failure,
        }
    }

    /// The assembly `parts` on `model` (the model it was assembled from, or one that differs
    /// from it only in settings assembly does not read) with the applied forces `forces`.
    pub fn from_assembly(
        model: &'m Model,
        forces: &'m dyn AppliedForces,
        parts: Assembly,
    ) -> Assembled<'m> {
        Assembled {
            model,
            forces,
            system: parts.system,
            ic: parts.ic,
            kept: parts.kept,
            removed: parts.removed,
            drivers: parts.drivers,
            failure: parts.failure,
        }
    }

    /// Whether the kept rows fix every coordinate, so that a simulation is a kinematic
    /// analysis (positions from the constraints at each output; no control states to
    /// integrate). The one definition of the rule, shared with the dynamic stage.
    pub fn is_kinematic(&self) -> bool {
        kinematic(
            self.kept.len(),
            self.model.parts.len(),
            self.forces.control_count(),
        )
    }

    /// Why no analysis can start from here (`None` when the model is assembled).
    pub fn failure(&self) -> Option<&NotAssembled> {
        self.failure.as_ref()
    }

    /// The assembled configuration, at the start time.
    pub fn state(&self) -> &State {
        &self.ic.assembly.state
    }

    /// The initial velocities (CM velocity and angular velocity, ground axes); at rest when the
    /// velocity IC was not run.
    pub fn velocities(&self) -> Vec<(DVec3, DVec3)> {
        self.ic
            .velocity
            .as_ref()
            .map(|v| v.velocities.clone())
            .unwrap_or_else(|| self.rest())
    }

    /// Every part at rest.
    pub fn rest(&self) -> Vec<(DVec3, DVec3)> {
        vec![(DVec3::ZERO, DVec3::ZERO); self.model.parts.len()]
    }

    /// The dynamic problem on the kept rows with the anchored drivers; `damping` and
    /// `frozen_time` for settling.
    pub fn problem(&self, damping: Option<ExtraDamping>, frozen_time: Option<f64>) -> Problem<'_> {
        Problem {
            model: self.model,
            sys: &self.system,
            rows: &self.kept,
            redundant: &self.removed,
            drivers: &self.drivers,
            forces: self.forces,
            damping,
            frozen_time,
            regime: Regime::Dynamic,
            coupling: crate::physics::flex_inertia::FlexCoupling::new(self.model),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::applied::NoForces;
    use std::sync::Arc;

    fn mechanism(name: &str) -> Model {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../mechanisms")
            .join(name);
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let ds = linkage_adm::parse_dataset(Arc::from(name), &text).expect("parses");
        linkage_model::build_model(&ds).expect("builds").model
    }

    /// The planar four-bar: assembled, its three redundant rows removed from every stage,
    /// the others kept, and nothing moved (it is built assembled).
    #[test]
    fn a_fourbar_assembles_and_removes_its_three_redundant_rows() {
        let m = mechanism("fourbar.adm");
        let d = ExpressionDrivers::new(&m).unwrap();
        let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
        assert!(a.failure().is_none());
        assert_eq!(a.removed.len(), 3);
        assert_eq!(a.kept.len() + a.removed.len(), a.system.rows.len());
        assert!(a.kept.iter().all(|r| !a.removed.contains(r)));
        assert!(a.ic.moved.is_empty());
        assert_eq!(a.velocities().len(), m.parts.len());
        let p = a.problem(None, None);
        assert_eq!(p.rows, a.kept.as_slice());
        assert_eq!(p.redundant, a.removed.as_slice());
    }

    /// A door on two hinges whose top hinge is tilted 2°: the assembly converges, but the
    /// redundant rotation of the top hinge cannot hold, and the judgement names it with its
    /// residual, in the words every analysis prints.
    #[test]
    fn a_tilted_hinge_is_not_assembled_and_names_the_inconsistent_equation() {
        let m = mechanism("door_tilted_hinge.adm");
        let d = ExpressionDrivers::new(&m).unwrap();
        let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
        let Some(NotAssembled::Inconsistent { equations }) = a.failure() else {
            panic!("{:?}", a.failure());
        };
        assert_eq!(equations.len(), 1);
        let e = &equations[0];
        assert_eq!(
            (e.element.as_str(), e.label, e.unit),
            ("hinge_top", "Rotation Between Zi & Yj", " deg")
        );
        assert!((e.residual.unwrap() - 2.0).abs() < 1e-9, "{e:?}");
        assert_eq!(
            a.failure().unwrap().to_string(),
            "the model cannot be assembled: redundant equation(s) inconsistent with the \
             others: Rotation Between Zi & Yj of hinge_top (residual 2.0000E+00 deg); \
             `linkage verify --explain` proposes joints without the redundancy"
        );
    }

    /// An assembly that does not converge is judged before any redundancy.
    #[test]
    fn an_unconverged_assembly_is_judged_by_its_largest_residual() {
        let m = mechanism("fourbar.adm");
        let d = ExpressionDrivers::new(&m).unwrap();
        let mut ic = Assembled::new(&m, &d, &NoForces, &Tolerances::default()).ic;
        ic.assembly.converged = false;
        ic.assembly.max_residual = 0.25;
        let why = NotAssembled::judge(&m, &ic).expect("not assembled");
        assert_eq!(why, NotAssembled::DidNotConverge { max_residual: 0.25 });
        assert!(
            why.to_string().contains("largest residual 2.500E-01"),
            "{why}"
        );
    }
}
