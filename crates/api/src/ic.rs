//! The initial conditions of a loaded model and their report.

use crate::error::Error;
use crate::sink::{Feed, NoSink, OutputSink};
use crate::source::Loaded;
use crate::start::{assemble, input_model, Left, Start};
use linkage_report::ic::IcJson;
use linkage_solve::coverage::Analysis;
use linkage_solve::physics::applied::Regime;
use linkage_solve::pipeline::{Assembled, NotAssembled};
use linkage_solve::stages::dynamics::Output;
use linkage_solve::state::State;

/// What the initial conditions gave.
pub struct IcRun {
    /// `linkage ic --format json`.
    pub report: IcJson,
    /// The model could not be assembled (exit code 1).
    pub failed: bool,
    /// The assembled configuration (what `--save` writes).
    pub state: State,
    /// Where the initial conditions leave the model (`None` when they failed).
    pub left: Option<Left>,
}

/// The output of the initial conditions of `a`: the assembled configuration with its
/// velocities, accelerations and reactions (`None` when the acceleration solve failed).
pub fn initial_output(a: &Assembled) -> Option<Output> {
    let acc = a.ic.acceleration.as_ref()?.as_ref().ok()?;
    Some(Output {
        time: a.state().time,
        state: a.state().clone(),
        velocities: a.velocities(),
        accelerations: acc.accelerations.clone(),
        reactions: acc.reactions.clone(),
    })
}

/// Assembles `loaded` from its input and solves its velocities, accelerations and forces at
/// time 0 (`linkage ic`).
pub fn ic(loaded: &Loaded) -> Result<IcRun, Error> {
    run(loaded, Start::Input, &mut NoSink)
}

/// The initial conditions from `start` (always assembled anew: that is what they are), their
/// output handed to `sink`. An inconsistent redundant equation is the verdict's one line.
pub fn run(loaded: &Loaded, start: Start, sink: &mut dyn OutputSink) -> Result<IcRun, Error> {
    let mut start = start;
    if let Start::Left(left) = &mut start {
        left.assembly = None;
    }
    let mut feed = Feed::new(&loaded.model, sink)?;
    let model = input_model(loaded, &start);
    let begun = assemble(loaded, model.as_ref(), start, Analysis::Ic)?;
    let a = begun.assembled;
    let ic = &a.ic;
    let mut report = linkage_report::ic::to_json(a.model, ic, &loaded.warnings);
    if let Some(v) = &ic.velocity {
        let values = a
            .forces
            .friction_values(Regime::Dynamic, &ic.assembly.state, &v.velocities);
        report.frictions = linkage_report::friction::frictions_json(a.model, &values);
    }
    if !matches!(a.failure(), Some(NotAssembled::DidNotConverge { .. })) {
        let contacts = linkage_solve::constraints::curve_contacts::curve_contacts(
            a.model,
            &a.system,
            &ic.assembly.state,
        );
        report.curve_contacts =
            linkage_report::curve_contacts::curve_contacts_json(a.model, &contacts);
    }
    (report.left_out, report.runs_without) = loaded.coverage(Analysis::Ic);
    // An assembly that did not converge has its own error; an inconsistent redundancy is named
    // here, as the one line of the verdict.
    if let Some(why @ NotAssembled::Inconsistent { .. }) = a.failure() {
        report.errors.push(why.to_string());
    }
    let failed = a.failure().is_some() || !report.errors.is_empty();
    let state = ic.assembly.state.clone();
    let mut left = None;
    if !failed {
        feed.assembled(&a, true).map_err(Error::from)?;
        if let Some(o) = initial_output(&a) {
            feed.output(&a, &o).map_err(Error::from)?;
            left = Some(Left {
                state: o.state,
                velocities: o.velocities,
                assembly: None,
            });
        }
    }
    if let Some(l) = left.as_mut() {
        l.assembly = Some(a.into_assembly());
    }
    Ok(IcRun {
        report,
        failed,
        state,
        left,
    })
}
