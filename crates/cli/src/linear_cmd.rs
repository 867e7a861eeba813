//! `linkage linear`: eigenvalues and modes about an operating point.

use crate::common::{input_error, load, print_json, Format};
use linkage_solve::coverage::Analysis;
use linkage_solve::stages::linearize::LinearOptions;
use std::path::Path;
use std::process::ExitCode;

/// Options of `linkage linear`.
pub struct LinearArgs<'a> {
    pub model: &'a Path,
    pub format: Format,
    pub static_first: bool,
    pub damping: bool,
    pub vectors: bool,
    /// `--modes K`: the K modes nearest the shift, by shift-invert.
    pub modes: Option<usize>,
    /// `--shift F` in cycles per time unit.
    pub shift: Option<f64>,
    /// With `static_first`: accept an unstable equilibrium as the operating point.
    pub allow_unstable: bool,
    /// Statements to leave out (`--deactivate`).
    pub deactivate: &'a [String],
    /// Where to write the HTML page (`--html`).
    pub html: Option<&'a Path>,
}

/// Most mode shapes a page animates.
const MODES_ANIMATED: usize = 12;

pub fn run_linear(args: &LinearArgs) -> ExitCode {
    let loaded = match load(args.model, args.deactivate, Some(Analysis::Linear)) {
        Ok(l) => l,
        Err(d) => return input_error(&d, args.format),
    };
    let method = match linkage_api::linear::eigen_method(args.modes, args.shift) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let opts = LinearOptions {
        damping: args.damping,
        vectors: args.vectors,
        method,
    };
    let linear = linkage_api::linear::LinearArgs {
        static_first: args.static_first,
        options: opts,
        allow_unstable: args.allow_unstable,
    };
    let (mut report, at) = match linkage_api::linear::linear_at(&loaded, &linear) {
        Ok(r) => r,
        Err(e) => return crate::common::analysis_error(&e, args.format),
    };
    if let Some(out) = args.html {
        let mut page = crate::html_out::page(&loaded.model, "linear", &report, &[]);
        // The operating point: the static equilibrium, or the assembled configuration.
        let at = &at;
        let base: Vec<_> = at.poses.iter().map(|p| (p.p, p.r)).collect();
        page.animations.extend(
            report
                .modes
                .iter()
                .filter(|m| m.frequency > 0.0)
                .take(MODES_ANIMATED)
                .filter_map(|m| {
                    linkage_html::series::mode_frames(&base, m, loaded.model.characteristic_length)
                }),
        );
        if page.animations.is_empty() {
            page.animations.push(crate::html_out::frames_of_states(
                "operating point",
                [at].into_iter(),
            ));
        } else {
            page.notes.push(format!(
                "Mode shapes of the first {} modes of nonzero frequency are animated over one \
                 cycle, scaled to be seen (the table gives their magnitudes).",
                page.animations.len()
            ));
        }
        if let Err(e) = crate::html_out::write(&page, out) {
            report.errors.push(e.to_string());
        }
    }
    match args.format {
        Format::Text => print!("{}", linkage_report::linear::to_text(&report)),
        Format::Json => {
            print_json(&report);
        }
    }
    crate::common::errors_to_stderr(&report.errors, crate::common::stdout_is_terminal());
    if report.errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
