//! Typing of a command file: generic command statements → [`Command`]s.
//!
//! Contract:
//! - Every command is typed or rejected: an unknown command, an unknown or ambiguous argument,
//!   a missing or conflicting one, a value of the wrong shape is an error at its line:column
//!   naming the command. All errors of the file are returned at once.
//! - Commands that change nothing in a solver without the feature are typed all the same
//!   (their arguments kept as [`Options`]); the runner decides what to say about them.
//! - No Adams default is applied (see [`super::typed`]).

use super::args::{resolve, value_text, Args, Sink};
use super::typed::*;
use super::{settings, tables, CommandFile};
use crate::diagnostic::{Diagnostic, Diagnostics, Span};
use crate::keywords::{self, ArgDef, Lookup};
use crate::statement::Statement;

/// Types a command file read by [`super::parse_commands`].
///
/// Returns the typed file (with the reader's warnings, except those about unknown commands,
/// which become errors here) or every error found, sorted by position.
pub fn type_commands(cf: &CommandFile) -> Result<TypedCommandFile, Diagnostics> {
    let mut sink = Sink {
        file: cf.file.clone(),
        list: Vec::new(),
    };
    let mut commands = Vec::with_capacity(cf.commands.len() + 1);
    let mut unknown_spans = Vec::new();
    for st in &cf.commands {
        if !st.known {
            unknown_spans.push(st.span);
        }
        if let Some(command) = command(st, &mut sink) {
            commands.push(CommandEntry {
                span: st.span,
                lines: st.lines,
                command,
            });
        }
    }
    if let Some(line) = cf.stop_line {
        commands.push(CommandEntry {
            span: Span::new(line, 1),
            lines: (line, line),
            command: Command::Stop,
        });
    }
    let mut diagnostics = sink.list;
    diagnostics.extend(
        cf.warnings
            .iter()
            .filter(|w| !w.span.is_some_and(|s| unknown_spans.contains(&s)))
            .cloned(),
    );
    diagnostics.sort_by_key(|d| d.span);
    let (errors, warnings): (Vec<_>, Vec<_>) =
        diagnostics.into_iter().partition(Diagnostic::is_error);
    if !errors.is_empty() {
        return Err(Diagnostics(errors));
    }
    Ok(TypedCommandFile {
        file: cf.file.clone(),
        model: cf.model.clone(),
        output_prefix: cf.output_prefix.clone(),
        commands,
        warnings,
    })
}

/// Types one command; `None` when it has errors (reported to `sink`).
fn command(st: &Statement, sink: &mut Sink) -> Option<Command> {
    let before = sink.errors();
    let name = st.keyword.as_str();
    if !st.known {
        let msg = format!("unknown command '{name}'");
        let d = Diagnostic::error(sink.file.clone(), Some(st.span), msg)
            .with_hint("not an Adams Solver command (ADM-REFERENCE §7.2); check its spelling");
        sink.list.push(d);
        return None;
    }
    let cmd = match name {
        "SIMULATE" => simulate(&resolve(st, name, tables::SIMULATE, sink), st, sink),
        "LINEAR" => linear(&resolve(st, name, tables::LINEAR, sink), st, sink),
        "INTEGRATOR" => Some(Command::Integrator(settings::integrator(
            &resolve(st, name, tables::INTEGRATOR, sink),
            sink,
        ))),
        "EQUILIBRIUM" => Some(Command::Equilibrium(settings::equilibrium(
            &resolve(st, name, tables::EQUILIBRIUM, sink),
            sink,
        ))),
        "IC" => Some(Command::Ic(settings::ic(
            &resolve(st, name, tables::IC, sink),
            sink,
        ))),
        "KINEMATICS" => Some(Command::Kinematics(settings::kinematics(
            &resolve(st, name, tables::KINEMATICS, sink),
            sink,
        ))),
        "ACCGRAV" => Some(Command::Accgrav(settings::accgrav(
            &resolve(st, name, tables::ACCGRAV, sink),
            sink,
        ))),
        "ACTIVATE" | "DEACTIVATE" => {
            let a = resolve(st, name, tables::ACTIVATION, sink);
            activation(&a, st, sink).map(|act| match name {
                "ACTIVATE" => Command::Activate(act),
                _ => Command::Deactivate(act),
            })
        }
        "FILE" => file(&resolve(st, name, tables::FILE, sink), st, sink),
        "SAVE" => state_file(&resolve(st, name, tables::SAVE, sink), st, sink).map(Command::Save),
        "RELOAD" => {
            state_file(&resolve(st, name, tables::RELOAD, sink), st, sink).map(Command::Reload)
        }
        "ENVIRONMENT" => environment(&resolve(st, name, tables::ENVIRONMENT, sink), st, sink),
        "OUTPUT" => Some(Command::Output(options("OUTPUT", tables::OUTPUT, st, sink))),
        "DEBUG" => Some(Command::Debug(options("DEBUG", tables::DEBUG, st, sink))),
        "PREFERENCES" => Some(Command::Preferences(options(
            "PREFERENCES",
            tables::PREFERENCES,
            st,
            sink,
        ))),
        "LSOLVER" => Some(Command::Lsolver(options(
            "LSOLVER",
            tables::LSOLVER,
            st,
            sink,
        ))),
        "CONTROL" => Some(Command::Control(st.clone())),
        _ if tables::INFORMATION.contains(&name) => Some(Command::Information(st.clone())),
        _ => redefinition(st, sink).map(Command::Redefine),
    };
    (sink.errors() == before).then_some(cmd).flatten()
}

// ---- SIMULATE --------------------------------------------------------------------------------

fn simulate(a: &Args, st: &Statement, sink: &mut Sink) -> Option<Command> {
    let kinds = [
        "STATICS",
        "DYNAMICS",
        "KINEMATICS",
        "TRANSIENT",
        "INITIAL_CONDITIONS",
    ];
    let phase = a
        .one_of(
            &["DISPLACEMENT", "VELOCITY", "ACCELERATION"],
            "IC phase",
            sink,
        )
        .map(|p| match p {
            "DISPLACEMENT" => IcPhase::Displacement,
            "VELOCITY" => IcPhase::Velocity,
            _ => IcPhase::Acceleration,
        });
    let kind = match a.one_of(&kinds, "analysis", sink) {
        Some("STATICS") => SimulateKind::Static,
        Some("DYNAMICS") => SimulateKind::Dynamic,
        Some("KINEMATICS") => SimulateKind::Kinematic,
        Some("TRANSIENT") => SimulateKind::Transient,
        Some(_) => SimulateKind::InitialConditions(phase),
        None => {
            if a.lacks(&kinds) {
                let msg = format!("SIMULATE needs an analysis: one of {}", kinds.join(", "));
                sink.error(st.span, msg);
            }
            return None;
        }
    };
    if phase.is_some() && !matches!(kind, SimulateKind::InitialConditions(_)) {
        let key = ["DISPLACEMENT", "VELOCITY", "ACCELERATION"]
            .into_iter()
            .find(|k| a.has(k))
            .unwrap_or("DISPLACEMENT");
        let msg = format!("'{key}' of SIMULATE applies to INITIAL_CONDITIONS only");
        sink.error(a.span_of(key).unwrap_or(st.span), msg);
    }
    a.one_of(&["END", "DURATION"], "end time", sink);
    a.one_of(&["STEPS", "DTOUT"], "output spacing", sink);
    let sim = Simulate {
        kind,
        end: a.real("END", sink),
        duration: a.real("DURATION", sink),
        steps: a.count("STEPS", sink),
        dtout: a.real("DTOUT", sink),
    };
    let positive = |key: &str, v: Option<f64>, sink: &mut Sink| {
        if let Some(x) = v.filter(|x| *x <= 0.0) {
            let msg = format!("'{key}' of SIMULATE must be positive, found {x}");
            sink.error(a.span_of(key).unwrap_or(st.span), msg);
        }
    };
    positive("END", sim.end, sink);
    positive("DURATION", sim.duration, sink);
    positive("DTOUT", sim.dtout, sink);
    if sim.steps == Some(0) {
        let span = a.span_of("STEPS").unwrap_or(st.span);
        sink.error(span, "'STEPS' of SIMULATE must be at least 1");
    }
    let timed = a.has("END") || a.has("DURATION");
    let spaced = a.has("STEPS") || a.has("DTOUT");
    match kind {
        SimulateKind::InitialConditions(_) if timed || spaced => {
            let key = ["END", "DURATION", "STEPS", "DTOUT"]
                .into_iter()
                .find(|k| a.has(k))
                .unwrap_or("END");
            let msg = format!("'{key}' of SIMULATE does not apply to INITIAL_CONDITIONS");
            sink.error(a.span_of(key).unwrap_or(st.span), msg);
        }
        SimulateKind::Dynamic | SimulateKind::Kinematic | SimulateKind::Transient
            if a.lacks(&["END", "DURATION"]) =>
        {
            let what = match kind {
                SimulateKind::Dynamic => "DYNAMICS",
                SimulateKind::Kinematic => "KINEMATICS",
                _ => "TRANSIENT",
            };
            sink.error(
                st.span,
                format!("SIMULATE/{what} needs END = <time> or DURATION = <time>"),
            );
        }
        _ if spaced && !timed => {
            let key = if a.has("STEPS") { "STEPS" } else { "DTOUT" };
            let msg = format!("'{key}' of SIMULATE needs END or DURATION");
            sink.error(a.span_of(key).unwrap_or(st.span), msg);
        }
        _ => {}
    }
    Some(Command::Simulate(sim))
}

// ---- LINEAR ----------------------------------------------------------------------------------

fn linear(a: &Args, st: &Statement, sink: &mut Sink) -> Option<Command> {
    let Some(kind) = a.one_of(&["EIGENSOL", "STATEMAT", "MKB"], "linear analysis", sink) else {
        if a.lacks(&["EIGENSOL", "STATEMAT", "MKB"]) {
            sink.error(st.span, "LINEAR needs one of EIGENSOL, STATEMAT, MKB");
        }
        return None;
    };
    let wrong: &[&str] = if kind == "EIGENSOL" {
        tables::EXPORT_ONLY
    } else {
        tables::EIGENSOL_ONLY
    };
    for key in wrong.iter().filter(|k| a.has(k)) {
        let msg = format!("'{key}' is not an argument of LINEAR/{kind}");
        sink.error(a.span_of(key).unwrap_or(st.span), msg);
    }
    let rm = a.id("RM", sink);
    let pstate = a.id("PSTATE", sink);
    let original = a.has("ORIGINAL");
    if kind == "EIGENSOL" {
        return Some(Command::Linear(Linear::Eigensol(Eigensol {
            nodamping: a.has("NODAMPIN"),
            novector: a.has("NOVECTOR"),
            coordinates: mode_range(a, "COORDS", sink),
            energy: mode_range(a, "ENERGY", sink),
            kinetic: mode_range(a, "KINETIC", sink),
            strain: mode_range(a, "STRAIN", sink),
            dissipative: mode_range(a, "DISSIPAT", sink),
            rm,
            pstate,
            original,
        })));
    }
    let file = a.text("FILE", sink);
    if a.lacks(&["FILE"]) {
        sink.error(st.span, format!("LINEAR/{kind} needs FILE = <file name>"));
    }
    let export = MatrixExport {
        file: file.unwrap_or_default(),
        format: a
            .choice("FORMAT", &["MATRIXX", "MATLAB"], sink)
            .map(|f| match f {
                "MATRIXX" => MatrixFormat::Matrixx,
                _ => MatrixFormat::Matlab,
            }),
        pinput: a.id("PINPUT", sink),
        poutput: a.id("POUTPUT", sink),
        rm,
        pstate,
        original,
    };
    Some(Command::Linear(match kind {
        "STATEMAT" => Linear::Statemat(export),
        _ => Linear::Mkb(export),
    }))
}

/// `key = i1[, i2]` with 1 ≤ i1 ≤ i2.
fn mode_range(a: &Args, key: &str, sink: &mut Sink) -> Option<ModeRange> {
    let ids = a.ids(key, &[1, 2], sink)?;
    let (first, last) = match ids.as_slice() {
        [f] => (*f, *f),
        [f, l] => (*f, *l),
        _ => return None,
    };
    let (Ok(first), Ok(last)) = (u32::try_from(first), u32::try_from(last)) else {
        let span = a.span_of(key).unwrap_or_default();
        sink.error(span, format!("'{key}' of LINEAR: mode number too large"));
        return None;
    };
    if first > last {
        let span = a.span_of(key).unwrap_or_default();
        let msg = format!("'{key}' of LINEAR: first mode {first} is after last mode {last}");
        sink.error(span, msg);
        return None;
    }
    Some(ModeRange { first, last })
}

// ---- ACTIVATE / DEACTIVATE -------------------------------------------------------------------

fn activation(a: &Args, st: &Statement, sink: &mut Sink) -> Option<Activation> {
    let names: Vec<&'static str> = ElementType::ALL.iter().map(|e| e.keyword()).collect();
    let label = &a.label;
    let element = match a.one_of(&names, "element type", sink) {
        Some(n) => ElementType::ALL.into_iter().find(|e| e.keyword() == n)?,
        None => {
            if a.lacks(&names) {
                let msg = format!("{label} needs an element type (JOINT, MOTION, SFORCE, …)");
                sink.error(st.span, msg);
            }
            return None;
        }
    };
    let ids = a.ids("ID", &[], sink).unwrap_or_default();
    let mut ranges = Vec::new();
    if let Some(r) = a.ids("RANGE", &[2], sink) {
        if let [lo, hi] = r.as_slice() {
            if lo > hi {
                let span = a.span_of("RANGE").unwrap_or(st.span);
                sink.error(
                    span,
                    format!("RANGE of {label} is empty: {lo} is above {hi}"),
                );
            }
            ranges.push((*lo, *hi));
        }
    }
    if a.lacks(&["ID", "RANGE"]) {
        let msg = format!(
            "{label}/{} needs ID = id1, … or RANGE = lo, hi",
            element.keyword()
        );
        sink.error(st.span, msg);
    }
    Some(Activation {
        element,
        ids,
        ranges,
    })
}

// ---- FILE, SAVE, RELOAD, ENVIRONMENT ---------------------------------------------------------

fn file(a: &Args, st: &Statement, sink: &mut Sink) -> Option<Command> {
    let f = FileCommand {
        model: a.text("MODEL", sink),
        output_prefix: a.text("OUTPUT_PREFIX", sink),
        command: a.text("COMMAND", sink),
    };
    if a.has("MODEL") && a.has("COMMAND") {
        let span = a.span_of("COMMAND").unwrap_or(st.span);
        sink.error(
            span,
            "FILE names both MODEL and COMMAND: give one per FILE command",
        );
    } else if a.lacks(&["MODEL", "COMMAND"]) {
        sink.error(
            st.span,
            "FILE needs MODEL = <dataset> or COMMAND = <command file>",
        );
    } else if a.has("OUTPUT_PREFIX") && !a.has("MODEL") {
        let span = a.span_of("OUTPUT_PREFIX").unwrap_or(st.span);
        sink.error(span, "OUTPUT_PREFIX of FILE goes with MODEL");
    }
    Some(Command::File(f))
}

fn state_file(a: &Args, st: &Statement, sink: &mut Sink) -> Option<StateFile> {
    let label = &a.label;
    let what = match a.one_of(&["SYSTEM", "STATES"], "state kind", sink) {
        Some("SYSTEM") => SavedState::System,
        Some(_) => SavedState::States,
        None => {
            if a.lacks(&["SYSTEM", "STATES"]) {
                sink.error(st.span, format!("{label} needs SYSTEM or STATES"));
            }
            return None;
        }
    };
    let file = a.text("FILE", sink);
    if a.lacks(&["FILE"]) {
        sink.error(st.span, format!("{label} needs FILE = <file name>"));
    }
    Some(StateFile {
        what,
        file: file.unwrap_or_default(),
        output_prefix: a.text("OUTPUT_PREFIX", sink),
    })
}

fn environment(a: &Args, st: &Statement, sink: &mut Sink) -> Option<Command> {
    let env = Environment {
        name: a.text("NAME", sink),
        value: a.text("VALUE", sink),
        unset: a.has("UNSET"),
        list: a.has("LIST"),
    };
    if !env.list && a.lacks(&["NAME"]) {
        sink.error(st.span, "ENVIRONMENT needs NAME = <variable> (or LIST)");
    } else if a.has("VALUE") && env.unset {
        let span = a.span_of("UNSET").unwrap_or(st.span);
        sink.error(span, "ENVIRONMENT gives both VALUE and UNSET");
    } else if a.has("NAME") && a.lacks(&["VALUE", "UNSET"]) {
        sink.error(st.span, "ENVIRONMENT needs VALUE = <value> or UNSET");
    }
    Some(Command::Environment(env))
}

// ---- option commands, redefinitions ----------------------------------------------------------

fn options(
    name: &'static str,
    table: &'static [super::args::Spec],
    st: &Statement,
    sink: &mut Sink,
) -> Options {
    use super::args::Kind;
    let a = resolve(st, name, table, sink);
    let mut items = Vec::with_capacity(a.items.len());
    for (spec, arg) in &a.items {
        let key = spec.canonical;
        let value = match spec.kind {
            Kind::Flag => Some(OptionValue::Flag),
            Kind::Real | Kind::Angle => a.real(key, sink).map(OptionValue::Number),
            Kind::Count => a.count(key, sink).map(OptionValue::Count),
            Kind::Word => match arg.values.as_slice() {
                [v] => Some(OptionValue::Word(value_text(v).to_ascii_uppercase())),
                _ => {
                    sink.error(arg.span, format!("'{key}' of {name} needs one word"));
                    None
                }
            },
            Kind::Text | Kind::Ids | Kind::Pattern => a.text(key, sink).map(OptionValue::Text),
        };
        if let Some(value) = value {
            items.push(OptionItem {
                key,
                value,
                span: arg.span,
            });
        }
    }
    Options {
        command: name,
        items,
    }
}

/// An element statement given as a command: keys canonical where the dataset language types
/// the element (its complete table plus `LIST`), as written otherwise.
fn redefinition(st: &Statement, sink: &mut Sink) -> Option<Redefinition> {
    let Some(element) = tables::REDEFINABLE
        .iter()
        .copied()
        .find(|e| *e == st.keyword)
    else {
        // A command of the parser's table that linkage does not type: say so rather than drop it.
        let msg = format!("command '{}' is not supported", st.keyword);
        sink.error(st.span, msg);
        return None;
    };
    let Some(id) = st.id else {
        sink.error(
            st.span,
            format!("{element} needs an id ('{element}/id, …')"),
        );
        return None;
    };
    let mut statement = st.clone();
    let def = match keywords::lookup_statement(element, keywords::DATASET_STATEMENTS) {
        Lookup::Found(def) if def.complete => Some(def),
        _ => None,
    };
    const LIST: ArgDef = ArgDef {
        spelling: "LIST",
        canonical: "LIST",
        kind: keywords::ArgKind::Flag,
    };
    let mut table: Vec<ArgDef> = def.map(|d| d.args.to_vec()).unwrap_or_default();
    table.push(LIST);
    for arg in &mut statement.args {
        let label = format!("{element}/{id}");
        match keywords::lookup(&arg.key, &table, |a| a.spelling, |a| a.canonical) {
            Lookup::Found(a) => arg.key = a.canonical.to_string(),
            Lookup::Ambiguous(names) => {
                let msg = format!(
                    "ambiguous argument '{}' of {label}: could be {}",
                    arg.key,
                    names.join(", ")
                );
                sink.error(arg.span, msg);
            }
            Lookup::NotFound if def.is_some() => {
                let msg = format!("unknown argument '{}' of {label}", arg.key);
                sink.error(arg.span, msg);
            }
            Lookup::NotFound => {}
        }
    }
    Some(Redefinition {
        element,
        id,
        statement,
    })
}
