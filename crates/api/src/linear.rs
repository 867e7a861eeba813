//! Linearization of a loaded model and its report.

use crate::error::Error;
use crate::sink::OutputSink;
use crate::source::Loaded;
use crate::start::{assemble, input_model, Left, Start};
use linkage_report::linear::LinearJson;
use linkage_solve::coverage::Analysis;
use linkage_solve::stages::linearize::{
    self, EigenMethod, LinearOptions, LinearRun, StateMatrix, DEFAULT_MODES,
};
use linkage_solve::stages::plant::Plant;
use linkage_solve::state::State;

/// What `linkage linear` asks for.
#[derive(Clone, Copy, Debug)]
pub struct LinearArgs {
    /// Linearize about the static equilibrium rather than the assembled configuration.
    pub static_first: bool,
    /// Damping, mode shapes and the eigen method.
    pub options: LinearOptions,
    /// With `static_first`: accept an unstable equilibrium as the operating point.
    pub allow_unstable: bool,
}

/// The eigen method of `--modes K` and `--shift F` (F in cycles per time unit): every mode
/// (dense for small models) when neither is given, else the K (default [`DEFAULT_MODES`])
/// modes nearest F by shift-invert. An infinite or NaN shift is an input error.
pub fn eigen_method(
    modes: Option<usize>,
    shift: Option<f64>,
) -> Result<EigenMethod, crate::error::ArgumentError> {
    if shift.is_some_and(|f| !f.is_finite()) {
        return Err(crate::error::ArgumentError::ShiftNotFinite);
    }
    Ok(match (modes, shift) {
        (None, None) => EigenMethod::Auto,
        (modes, shift) => EigenMethod::ShiftInvert {
            modes: modes.unwrap_or(DEFAULT_MODES),
            shift: shift.map(|f| f * std::f64::consts::TAU),
        },
    })
}

/// The verdict on linearizing about an unstable static equilibrium, in one line with what to
/// try (`None` when the operating point is not a converged, unstable equilibrium).
fn unstable_operating_point(run: &LinearRun) -> Option<String> {
    let Some(Ok(eq)) = &run.equilibrium else {
        return None;
    };
    let (false, stiffness) = eq.stability? else {
        return None;
    };
    Some(format!(
        "the static equilibrium linearized about is UNSTABLE (negative stiffness {} along a \
         free motion): `linkage static --settle` finds a stable one by damped dynamics; \
         --allow-unstable accepts this one",
        linkage_adm::num::sci(stiffness, 4)
    ))
}

/// `linkage linear --format json` of `loaded`: eigenvalues, frequencies, damping ratios and
/// mode shapes; its `errors` are the verdict.
pub fn linear(loaded: &Loaded, args: &LinearArgs) -> Result<LinearJson, Error> {
    linear_at(loaded, args).map(|(report, _)| report)
}

/// [`linear`] and its operating point: the static equilibrium (with `static_first`, when
/// found) or the assembled configuration.
pub fn linear_at(loaded: &Loaded, args: &LinearArgs) -> Result<(LinearJson, State), Error> {
    let run = run(loaded, Start::Input, args, &mut crate::sink::NoSink)?;
    Ok((run.report, run.operating_point))
}

/// What a linearization gave.
pub struct Linearized {
    /// `linkage linear --format json`.
    pub report: LinearJson,
    /// The configuration linearized about.
    pub operating_point: State,
    /// Where the model is left: where it started (a linearization moves nothing), on the
    /// assembly made for it.
    pub left: Option<Left>,
}

/// Returns `start`'s state and velocities on the assembly `a` (a linearization leaves the
/// model where it found it).
fn left_as_found(
    found: Option<(State, crate::start::Velocities)>,
    a: linkage_solve::pipeline::Assembled,
) -> Option<Left> {
    found.map(|(state, velocities)| Left {
        state,
        velocities,
        assembly: Some(a.into_assembly()),
    })
}

/// The start's state and velocities, and the start with its assembly dropped: a
/// linearization assembles at the state it starts from, for the accelerations and forces
/// there.
fn reassembled(start: Start) -> (Start, Option<(State, crate::start::Velocities)>) {
    match start {
        Start::Input => (Start::Input, None),
        Start::Left(l) => {
            let found = (l.state.clone(), l.velocities.clone());
            (
                Start::Left(Box::new(Left {
                    assembly: None,
                    ..*l
                })),
                Some(found),
            )
        }
    }
}

/// The linearization of `loaded` from `start` (see [`linear`]); `sink` is told of the
/// assembly (a linearization has no outputs).
pub fn run(
    loaded: &Loaded,
    start: Start,
    args: &LinearArgs,
    sink: &mut dyn OutputSink,
) -> Result<Linearized, Error> {
    let (start, found) = reassembled(start);
    let time = start.time();
    let model = input_model(loaded, &start);
    let begun = assemble(loaded, model.as_ref(), start, Analysis::Linear)?;
    let assembled = begun.assembled;
    if assembled.failure().is_none() {
        sink.assembled(&assembled, true)?;
    }
    let result = linearize::run(&assembled, args.static_first, args.options);
    let mut report = linkage_report::linear::to_json(
        assembled.model,
        &result,
        args.static_first,
        &loaded.warnings,
    );
    (report.left_out, report.runs_without) = loaded.coverage(Analysis::Linear);
    report.time = time;
    if found.is_some() {
        report.operating_point = "the state the previous analysis left, assembled at its time";
    }
    report.errors.extend(non_finite(&report));
    if !args.allow_unstable && report.errors.is_empty() {
        report.errors.extend(unstable_operating_point(&result));
    }
    let operating_point = match &result.equilibrium {
        Some(Ok(eq)) => eq.state.clone(),
        _ => assembled.ic.assembly.state.clone(),
    };
    Ok(Linearized {
        report,
        operating_point,
        left: left_as_found(found, assembled),
    })
}

/// The state matrices `ẋ = A x + B u`, `y = C x + D u` of `loaded` about the configuration
/// `start` gives (assembled there), with the VARIABLE ids `inputs` as u and `outputs` as y
/// (`LINEAR/STATEMAT`; [`linkage_solve::stages::plant`]).
pub struct StateMatrices {
    pub matrix: StateMatrix,
    pub plant: Plant,
    /// The time of the operating point.
    pub time: f64,
    /// Where the model is left: where it started.
    pub left: Option<Left>,
}

/// [`StateMatrices`] of `loaded` from `start` (`sink` is told of the assembly). A failure of
/// the operating point or of the matrices is the analysis's failure ([`Error::Failed`]).
pub fn state_matrices(
    loaded: &Loaded,
    start: Start,
    inputs: &[u32],
    outputs: &[u32],
    sink: &mut dyn OutputSink,
) -> Result<StateMatrices, Error> {
    let (start, found) = reassembled(start);
    let time = start.time();
    let forces = loaded.forces(Analysis::Linear)?;
    let model = input_model(loaded, &start);
    let a = assemble(loaded, model.as_ref(), start, Analysis::Linear)?.assembled;
    if let Some(why) = a.failure() {
        return Err(Error::Failed(why.to_string()));
    }
    sink.assembled(&a, true)?;
    let (Some(v), Some(Ok(acc))) = (&a.ic.velocity, &a.ic.acceleration) else {
        return Err(Error::Failed(
            "the operating point has no accelerations and forces".into(),
        ));
    };
    let op = linearize::OperatingPoint {
        state: a.state(),
        velocities: &v.velocities,
        multipliers: &acc.multipliers,
    };
    let eq = linearize::assemble(a.model, &a.system, &a.kept, a.forces, op, true)
        .map_err(|e| Error::Failed(e.to_string()))?;
    let matrix = linearize::state_matrix(&eq).map_err(|e| Error::Failed(e.to_string()))?;
    let plant = linkage_solve::stages::plant::plant(a.model, forces, op, &matrix, inputs, outputs)
        .map_err(|e| Error::Failed(e.to_string()))?;
    Ok(StateMatrices {
        matrix,
        plant,
        time,
        left: left_as_found(found, a),
    })
}

/// The finite-value guard of a linear report: an error naming the first eigenvalue, frequency
/// or mode-shape component that is not a finite number (a model whose scale is beyond double
/// precision: an ACCGRAV of 1e200, an IP of 1e300), so that no NaN is reported as a result.
pub fn non_finite(report: &LinearJson) -> Option<String> {
    let eigen = report
        .eigenvalues
        .iter()
        .position(|e| !(e.real.is_finite() && e.imag.is_finite()));
    if let Some(k) = eigen {
        return Some(format!(
            "eigenvalue {} is not a finite number: the model's scale is beyond double \
             precision",
            k + 1
        ));
    }
    for m in &report.modes {
        let shape_ok = m.shape.iter().flatten().all(|p| {
            p.translation
                .iter()
                .chain(&p.rotation)
                .all(|c| c.magnitude.is_finite() && c.phase_deg.is_finite())
        });
        let values_ok = [m.frequency, m.damping_ratio, m.real, m.imag]
            .iter()
            .all(|v| v.is_finite());
        if !(shape_ok && values_ok) {
            return Some(format!(
                "mode {} is not a finite number: the model's scale is beyond double precision",
                m.number
            ));
        }
    }
    None
}
