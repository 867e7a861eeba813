//! `linkage run FILE.acf`: an Adams command file, with its message, request and CSV files.

use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The files of `linkage run` besides the command file.
pub struct Paths<'p> {
    /// `--out-dir`.
    pub out_dir: Option<&'p Path>,
    /// `--model`: the dataset in place of the one the command file names.
    pub model: Option<&'p Path>,
    /// `--html`.
    pub html: Option<&'p Path>,
}

/// How `linkage run` runs besides its files.
pub struct Options<'o> {
    /// `--deactivate`.
    pub deactivate: &'o [String],
    /// `--allow-unstable`.
    pub allow_unstable: bool,
    /// `--time-limit`: wall-clock seconds for each SIMULATE/DYNAMIC.
    pub time_limit: Option<f64>,
}

/// Runs the command file and prints where its outputs are; exit 0 when every command was
/// carried out or a SENSOR's HALT ended the file (a complete run: Adams' HALT terminates the
/// solver; the line `ended by the HALT of SENSOR_1 at time …` says where), 1 when an analysis
/// failed or was interrupted (Ctrl-C stops the run at its next output; the files keep every
/// output written and the message file says where it stopped), 2 for input errors, commands
/// linkage refuses and command files with no dataset or no analysis.
pub fn run(command_file: &Path, paths: Paths, options: Options) -> ExitCode {
    let Options {
        deactivate,
        allow_unstable,
        time_limit,
    } = options;
    if let Err(e) = linkage_api::budget::check_time_limit(time_limit) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    let Paths {
        out_dir,
        model,
        html,
    } = paths;
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&interrupt);
    // Without a handler (another one is installed) Ctrl-C ends the process as usual.
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    // The bar of `linkage simulate`, on a terminal only, for each dynamic simulation.
    let bar = Arc::new(crate::common::Progress::on_terminal());
    let shown = Arc::clone(&bar);
    let watch = linkage_run::watch::Watch::new(move |e| match *e {
        linkage_run::watch::Event::Integrating {
            command,
            start,
            end,
            time,
        } => shown.show(
            (time - start) / (end - start),
            format!("{command}: t = {time:.4} of {end}"),
        ),
        linkage_run::watch::Event::Done => shown.clear(),
    });
    let options = linkage_run::RunOptions {
        out_dir: out_dir.map(Path::to_path_buf),
        model: model.map(Path::to_path_buf),
        interrupt: Some(interrupt),
        deactivate: deactivate.to_vec(),
        allow_unstable,
        read: crate::common::read_options(),
        user_libraries: crate::common::user_libraries().to_vec(),
        also_writes: html.map(Path::to_path_buf).into_iter().collect(),
        time_limit,
        watch,
    };
    let (summary, error) = match linkage_run::run_command_file(command_file, &options) {
        Ok(s) => (Some(s), None),
        Err(stopped) => (stopped.summary, Some(stopped.error)),
    };
    bar.finish();
    if let Some(s) = &summary {
        println!(
            "{} command(s) carried out, {} output(s)",
            s.commands, s.outputs
        );
        if let Some(by) = &s.halted {
            println!("ended by the HALT of {by}; the commands after it were not run");
        }
        println!("message file: {}", s.msg.display());
        if let (Some(req), Some(csv)) = (&s.req, &s.csv) {
            println!("request file: {}", req.display());
            println!("time histories: {}", csv.display());
        }
    }
    let mut code: u8 = match &error {
        None => 0,
        Some(e) => {
            eprintln!("error: {e}");
            e.exit_code()
        }
    };
    // A page that cannot be made fails a run that succeeded; a failed run keeps its code.
    let page_failed = |code: u8| if code == 0 { 1 } else { code };
    // A run that stopped before it opened its dataset has its error above and no page.
    if let (Some(out), Some(_)) = (html, &summary) {
        let errors: Vec<String> = error.iter().map(|e| e.to_string()).collect();
        match run_page(command_file, summary.as_ref(), deactivate, errors) {
            Ok(page) => match crate::html_out::write(&page, out) {
                Ok(()) => println!("html page: {}", out.display()),
                Err(e) => {
                    eprintln!("error: {e}");
                    code = page_failed(code);
                }
            },
            Err(e) => {
                eprintln!("error: no html page: {e}");
                code = page_failed(code);
            }
        }
    }
    ExitCode::from(code)
}

/// Why a command-file run has no page.
#[derive(Debug, thiserror::Error)]
enum RunPageError {
    #[error("the run stopped before it opened its dataset")]
    NotOpened,
    #[error("the run opened no dataset")]
    NoDataset,
    /// The run's dataset could not be read or built (its errors are printed above).
    #[error("the dataset of the command file could not be opened (the error above)")]
    DatasetFailed,
    /// The dataset or the run's CSV does not read.
    #[error("{0}")]
    Input(linkage_adm::Diagnostics),
}

/// The page of a command-file run: the model of its dataset, animated and plotted from the
/// time histories the run wrote (its `.csv`: `PART.x … PART.phi`, reactions, REQUESTs).
fn run_page(
    command_file: &Path,
    summary: Option<&linkage_run::RunSummary>,
    deactivate: &[String],
    errors: Vec<String>,
) -> Result<linkage_html::Page, RunPageError> {
    let summary = summary.ok_or(RunPageError::NotOpened)?;
    let dataset = summary.dataset.as_ref().ok_or(if errors.is_empty() {
        RunPageError::NoDataset
    } else {
        RunPageError::DatasetFailed
    })?;
    let loaded = crate::common::load(dataset, deactivate, None).map_err(RunPageError::Input)?;
    let report = serde_json::json!({
        "file": command_file.display().to_string(),
        "title": loaded.model.title,
        "dataset": dataset.display().to_string(),
        "commands": summary.commands,
        "outputs": summary.outputs,
        "halted": summary.halted,
        "message_file": summary.msg.display().to_string(),
        "request_file": summary.req.as_ref().map(|p| p.display().to_string()),
        "time_histories": summary.csv.as_ref().map(|p| p.display().to_string()),
        "units": linkage_report::units::units_json(
            &loaded.model,
            linkage_report::units::Angle::Degree,
            false
        ),
        "errors": errors,
    });
    let mut page = crate::html_out::page(&loaded.model, "run", &report, &[]);
    let history = match &summary.csv {
        Some(csv) if summary.outputs > 0 => {
            Some(crate::compare_cmd::load(csv).map_err(RunPageError::Input)?)
        }
        _ => None,
    };
    if let Some(h) = history {
        let (frames, plots) = csv_series(&loaded.model, &h);
        page.animations.push(frames);
        page.plots = plots;
    }
    Ok(page)
}

/// Frames (each part's `x y z` and 3-1-3 angles in degrees) and plots (each part's
/// position, each element's reaction force, each REQUEST's columns) from a time-history CSV.
fn csv_series(
    model: &linkage_model::Model,
    h: &crate::compare_cmd::Series,
) -> (linkage_html::scene::Frames, Vec<linkage_html::svg::Plot>) {
    use linkage_html::svg::{Plot, Series};
    let column = |name: &str| h.signals.iter().find(|s| s.name == name);
    let mut frames = linkage_html::scene::Frames {
        label: "time".into(),
        total: h.times.len(),
        ..Default::default()
    };
    let part_columns: Vec<Option<[&crate::compare_cmd::Signal; 6]>> = model
        .parts
        .iter()
        .map(|p| {
            let n = &p.origin.name;
            let [x, y, z, psi, theta, phi] =
                ["x", "y", "z", "psi", "theta", "phi"].map(|c| column(&format!("{n}.{c}")));
            Some([x?, y?, z?, psi?, theta?, phi?])
        })
        .collect();
    for (k, &t) in h.times.iter().enumerate() {
        frames.push(
            t,
            model.parts.iter().zip(&part_columns).map(|(p, c)| match c {
                Some(c) => {
                    let v = |i: usize| c[i].values.get(k).copied().unwrap_or(0.0);
                    (
                        glam::DVec3::new(v(0), v(1), v(2)),
                        linkage_model::frames::euler313_to_matrix(
                            [v(3), v(4), v(5)].map(f64::to_radians),
                        ),
                    )
                }
                None => (p.p_gb, p.r_gb),
            }),
        );
    }
    let units =
        linkage_report::units::units_json(model, linkage_report::units::Angle::Degree, false);
    let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
    for (k, s) in h.signals.iter().enumerate() {
        let Some((group, component)) = s.name.rsplit_once('.') else {
            continue;
        };
        if !matches!(component, "x" | "y" | "z" | "fx" | "fy" | "fz") && !group.contains("REQUEST_")
        {
            continue;
        }
        let key = if matches!(component, "fx" | "fy" | "fz") {
            format!("{group}: reaction force on I")
        } else if group.contains("REQUEST_") {
            group.to_string()
        } else {
            format!("{group}: CM position")
        };
        match groups.iter_mut().find(|g| g.0 == key) {
            Some(g) => g.1.push(k),
            None => groups.push((key, vec![k])),
        }
    }
    let plots = groups
        .into_iter()
        .take(3 * linkage_html::history::MAX_PLOTS_PER_KIND)
        .map(|(title, cols)| Plot {
            y_label: if title.ends_with("force on I") {
                format!("force [{}]", units.force)
            } else if title.ends_with("position") {
                format!("position [{}]", units.length)
            } else {
                "value".into()
            },
            title,
            x_label: format!("time [{}]", units.time),
            series: cols
                .iter()
                .map(|&c| Series {
                    name: h.signals[c].name.clone(),
                    points: h
                        .times
                        .iter()
                        .copied()
                        .zip(h.signals[c].values.iter().copied())
                        .collect(),
                })
                .collect(),
        })
        .collect();
    (frames, plots)
}
