//! Command files (`.acf`, ADM-REFERENCE §7.1): read into generic statements.
//!
//! Contract:
//! - Line 1 names the dataset to load, unless it is blank or a `!` comment. When it names one,
//!   line 2 is the output-file prefix (blank = same as the dataset) and commands start on line 3;
//!   otherwise commands start on line 2 (or on line 1 when it is a comment).
//! - Commands follow the dataset's lexical rules (continuations, `&`, comments, abbreviations:
//!   `sim/dyn`, `equil/stab=…`) and are matched against the command table; reading stops at
//!   `STOP`. Unknown commands are warnings, malformed ones errors.
//! - [`parse_commands`] / [`read_commands`] give the generic statements; [`type_commands`]
//!   turns them into [`Command`]s ([`typed`]), every unknown or malformed command an error.
//!   [`read_typed_commands`] / [`parse_typed_commands`] do both.

mod args;
mod settings;
mod tables;
pub mod typed;
mod typing;

pub use typed::*;
pub use typing::type_commands;

use crate::diagnostic::{Diagnostic, Diagnostics, Span};
use crate::lexer::split_lines;
use crate::parse::{self, Language};
use crate::statement::Statement;
use std::path::Path;
use std::sync::Arc;

/// A command file: the dataset it loads and its commands in generic form.
#[derive(Clone, Debug, PartialEq)]
pub struct CommandFile {
    /// File name used in diagnostics.
    pub file: Arc<str>,
    /// Line 1 when it names the dataset (trimmed), else `None`.
    pub model: Option<String>,
    /// Line 2 when line 1 names the dataset and line 2 is not blank (trimmed).
    pub output_prefix: Option<String>,
    /// Every command before `STOP`, in order (`keyword` canonical, e.g. `SIMULATE`).
    pub commands: Vec<Statement>,
    /// Line of the `STOP` command, if any.
    pub stop_line: Option<u32>,
    /// Non-fatal findings (unknown commands, …).
    pub warnings: Vec<Diagnostic>,
}

/// Reads a command file. I/O failures become a diagnostic naming the file.
pub fn read_commands(path: &Path) -> Result<CommandFile, Diagnostics> {
    let file: Arc<str> = Arc::from(path.display().to_string());
    match crate::input::read_input(path) {
        Ok(bytes) => parse_commands(file, &String::from_utf8_lossy(&bytes)),
        Err(e) => Err(Diagnostics(vec![Diagnostic::error(
            file,
            None,
            format!("cannot read command file: {e}"),
        )])),
    }
}

/// Reads and types a command file: every error of reading or typing ([`type_commands`]).
pub fn read_typed_commands(path: &Path) -> Result<TypedCommandFile, Diagnostics> {
    type_commands(&read_commands(path)?)
}

/// Parses and types command-file text. `file` is the name used in diagnostics.
pub fn parse_typed_commands(file: Arc<str>, text: &str) -> Result<TypedCommandFile, Diagnostics> {
    type_commands(&parse_commands(file, text)?)
}

/// Parses command-file text. `file` is the name used in diagnostics.
pub fn parse_commands(file: Arc<str>, text: &str) -> Result<CommandFile, Diagnostics> {
    let lines = split_lines(text);
    let line = |k: usize| {
        lines
            .get(k)
            .map(|l| l.trim_start_matches('\u{feff}').trim())
            .unwrap_or("")
    };
    let first = line(0);
    let (model, output_prefix, start) = if first.is_empty() {
        (None, None, 1)
    } else if first.starts_with('!') {
        (None, None, 0)
    } else {
        let prefix = Some(line(1).to_string()).filter(|p| !p.is_empty());
        (Some(first.to_string()), prefix, 2)
    };
    if let Some(cut) = cut_short(&file, &lines, start) {
        return Err(Diagnostics(vec![cut]));
    }
    let parsed = parse::parse(file.clone(), text, start, Language::Commands, true);
    let (errors, warnings): (Vec<_>, Vec<_>) = parsed
        .diagnostics
        .into_iter()
        .partition(Diagnostic::is_error);
    if !errors.is_empty() {
        return Err(Diagnostics(errors));
    }
    Ok(CommandFile {
        file,
        model,
        output_prefix,
        commands: parsed.statements,
        stop_line: parsed.stop_line,
        warnings,
    })
}

/// The error of a command file whose last command ends with a continuation (`,` or `&`):
/// the rest of it is missing (a truncated file), so the command is not run with what is left.
/// Lines before `start` are the header; comments (`!` on) are not code.
fn cut_short(file: &Arc<str>, lines: &[&str], start: usize) -> Option<Diagnostic> {
    let (k, code) = lines
        .iter()
        .enumerate()
        .skip(start)
        .map(|(k, l)| (k, l.split('!').next().unwrap_or("").trim_end()))
        .rfind(|(_, code)| !code.trim().is_empty())?;
    let last = code.chars().last()?;
    (last == ',' || last == '&').then(|| {
        Diagnostic::error(
            file.clone(),
            Some(Span::new(k as u32 + 1, code.chars().count() as u32)),
            format!(
                "the command file ends inside a command (its last line ends with '{last}'): \
                 the rest of the command is missing"
            ),
        )
    })
}

#[cfg(test)]
#[path = "commands/tests/typing.rs"]
mod typing_tests;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statement::Value;

    fn parse(text: &str) -> CommandFile {
        parse_commands(Arc::from("t.acf"), text).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn a_file_cut_after_a_dangling_comma_is_an_error_at_that_comma() {
        let e = parse_commands(
            Arc::from("t.acf"),
            "in\nout\nSIMULATE/DYNAMIC, END=1,\n! comment\n\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("t.acf:3:24"), "{e}");
        assert!(e.contains("ends inside a command"), "{e}");
        assert!(parse_commands(Arc::from("t.acf"), "in\nout\nSIMULATE/DYNAMIC, END=1\n").is_ok());
    }

    #[test]
    fn classic_header_names_model_and_output_prefix() {
        let acf = parse("model.adm\r\nout_ADAMS\r\noutput/noseparator\r\nintegrator/gstiff, &\r\n\terror = 1.0e-4, hmax=1e-5\r\nsimulate/transient, &\r\n\tend=5.0, dtout=1.0E-002\r\nstop");
        assert_eq!(acf.model.as_deref(), Some("model.adm"));
        assert_eq!(acf.output_prefix.as_deref(), Some("out_ADAMS"));
        let names: Vec<&str> = acf.commands.iter().map(|c| c.keyword.as_str()).collect();
        assert_eq!(names, ["OUTPUT", "INTEGRATOR", "SIMULATE"]);
        assert_eq!(acf.stop_line, Some(8));
        let sim = &acf.commands[2];
        assert!(sim.arg("TRANSIENT").is_some());
        assert!(matches!(sim.arg("END").map(|a| a.values.as_slice()),
            Some([Value::Number { value, .. }]) if *value == 5.0));
        assert!(acf.commands[1].arg("GSTIFF").is_some());
        assert!(acf.commands[1].arg("HMAX").is_some());
    }

    #[test]
    fn blank_first_line_then_file_model_and_abbreviations() {
        let acf = parse("\nfile/model=C:\\models\\test\n! comment\nequil/stab=10, err=1, imb=1, tlim=2, alim=2D, maxit=500\nsim/stat\nVARIABLE/9105 &\n, FUNCTION=STEP(TIME,15.0,0.0,15.0+15.0,60.0*PI/30)\nDEACTIVATE/JOINT, RANGE = 1301, 1321\nSTOP\nsim/dyn\n");
        assert_eq!(acf.model, None);
        let file = &acf.commands[0];
        assert_eq!(file.keyword, "FILE");
        match file.arg("MODEL").map(|a| a.values.as_slice()) {
            Some([Value::Expr(e)]) => assert_eq!(e.text, "C:\\models\\test"),
            other => panic!("{other:?}"),
        }
        let equil = &acf.commands[1];
        let keys: Vec<&str> = equil.args.iter().map(|a| a.key.as_str()).collect();
        assert_eq!(
            keys,
            [
                "STABILITY",
                "ERROR",
                "IMBALANCE",
                "TLIMIT",
                "ALIMIT",
                "MAXIT"
            ]
        );
        assert!(matches!(
            equil.arg("ALIMIT").map(|a| a.values.as_slice()),
            Some([Value::Number { degrees: true, .. }])
        ));
        assert_eq!(acf.commands[2].keyword, "SIMULATE");
        assert_eq!(acf.commands[3].id, Some(9105));
        assert!(matches!(
            acf.commands[3].arg("FUNCTION").map(|a| a.values.as_slice()),
            Some([Value::Expr(_)])
        ));
        assert_eq!(
            acf.commands[4].arg("RANGE").map(|a| a.values.len()),
            Some(2)
        );
        assert_eq!(acf.commands.len(), 5, "nothing after STOP is read");
    }

    #[test]
    fn comment_on_line_one_is_a_comment() {
        let acf = parse("! script.acf\nDEBUG/EPRINT\nSIMULATE/DYNAMIC, END=0.5, STEPS=50\n");
        assert_eq!(acf.model, None);
        assert_eq!(acf.commands.len(), 2);
        assert_eq!(acf.stop_line, None);
    }

    #[test]
    fn unknown_command_is_a_warning_and_bad_one_an_error() {
        let acf = parse("\nFROBNICATE/1\nstop\n");
        assert_eq!(acf.warnings.len(), 1);
        assert_eq!(acf.warnings[0].span, Some(crate::Span::new(2, 1)));
        let err = parse_commands(Arc::from("t.acf"), "\nMOTION/x, VELOCITY\n").unwrap_err();
        assert_eq!(err.0[0].span, Some(crate::Span::new(2, 8)));
    }
}
