//! Time histories gathered for a page while a run streams its outputs, and the plots made of
//! them: each part's CM position and velocity, each constraint element's reaction force, and
//! the REQUEST columns, over time.
//!
//! Memory is bounded whatever the number of outputs: with `n` outputs expected, every
//! `k`-th is kept (`k = ceil(n / MAX_FRAMES)`) and the last one, so a page holds at most
//! [`crate::page::MAX_FRAMES`] + 1 frames and as many points per plotted series.

use crate::page::MAX_FRAMES;
use crate::scene::Frames;
use crate::svg::{stride, Plot, Series};
use linkage_model::Model;
use linkage_report::units::{units_json, Angle};
use linkage_solve::stages::dynamics::Output;

/// Most plots of each kind (parts, reactions, requests) on a page.
pub const MAX_PLOTS_PER_KIND: usize = 12;

/// One kept output: time, each part's CM position and velocity, each element's reaction
/// force, the request values.
#[derive(Clone, Debug, PartialEq)]
struct Row {
    time: f64,
    positions: Vec<[f64; 3]>,
    velocities: Vec<[f64; 3]>,
    forces: Vec<(usize, [f64; 3])>,
    requests: Vec<f64>,
}

/// The outputs of a run kept for a page.
#[derive(Clone, Debug)]
pub struct History {
    stride: usize,
    seen: usize,
    /// The last output seen when it was not kept (kept at [`History::finish`]).
    pending: Option<(Row, Vec<(glam::DVec3, glam::DMat3)>)>,
    rows: Vec<Row>,
    pub frames: Frames,
    request_names: Vec<String>,
    /// Columns picked for plotting (`--plot`); empty: the default plots.
    picked: Vec<String>,
}

/// A column of the time history, as the CSV names it (without its unit).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Column {
    Position(usize, usize),
    Velocity(usize, usize),
    Force(usize, usize),
    Request(usize),
}

impl Column {
    /// The column's value in a kept output.
    fn value(self, r: &Row) -> Option<f64> {
        match self {
            Column::Position(k, a) => r.positions.get(k).map(|v| v[a]),
            Column::Velocity(k, a) => r.velocities.get(k).map(|v| v[a]),
            Column::Force(e, a) => r.forces.iter().find(|f| f.0 == e).map(|f| f.1[a]),
            Column::Request(k) => r.requests.get(k).copied(),
        }
    }
}

/// The column `name` stands for: `PART.x|y|z|vx|vy|vz`, `ELEMENT.fx|fy|fz`, or a REQUEST
/// column of `requests`.
fn column(model: &Model, requests: &[String], name: &str) -> Option<Column> {
    if let Some(k) = requests.iter().position(|r| r == name) {
        return Some(Column::Request(k));
    }
    let (owner, component) = name.rsplit_once('.')?;
    let axis = |c: &str| ["x", "y", "z"].iter().position(|a| *a == c);
    if let Some(k) = model.parts.iter().position(|p| p.origin.name == owner) {
        if let Some(a) = axis(component) {
            return Some(Column::Position(k, a));
        }
        return component
            .strip_prefix('v')
            .and_then(axis)
            .map(|a| Column::Velocity(k, a));
    }
    let e = model
        .constraints
        .iter()
        .position(|c| c.origin.name == owner)?;
    component
        .strip_prefix('f')
        .and_then(axis)
        .map(|a| Column::Force(e, a))
}

/// A `--plot` name that is no column of the run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "--plot {0}: no such column (PART.x|y|z|vx|vy|vz, ELEMENT.fx|fy|fz or a REQUEST column such \
     as REQUEST_1.x)"
)]
pub struct UnknownColumn(pub String);

/// Checks the `--plot` names against the columns a run of `model` writes: the first unknown
/// one is the error.
pub fn check_columns(
    model: &Model,
    requests: &[String],
    names: &[String],
) -> Result<(), UnknownColumn> {
    match names.iter().find(|n| column(model, requests, n).is_none()) {
        Some(n) => Err(UnknownColumn(n.clone())),
        None => Ok(()),
    }
}

impl History {
    /// A history for a run of about `expected` outputs with request columns `request_names`.
    pub fn new(expected: usize, request_names: Vec<String>) -> History {
        History {
            stride: stride(expected, MAX_FRAMES),
            seen: 0,
            pending: None,
            rows: Vec::new(),
            frames: Frames {
                label: "time".into(),
                ..Frames::default()
            },
            request_names,
            picked: Vec::new(),
        }
    }

    /// Plots these columns (one plot each) instead of the default plots.
    pub fn with_columns(mut self, names: Vec<String>) -> History {
        self.picked = names;
        self
    }

    /// Records an output of the run (kept when its number is a multiple of the stride).
    pub fn record(&mut self, o: &Output, requests: &[f64]) {
        let row = Row {
            time: o.time,
            positions: o.state.poses.iter().map(|p| p.p.to_array()).collect(),
            velocities: o.velocities.iter().map(|v| v.0.to_array()).collect(),
            forces: o
                .reactions
                .iter()
                .map(|r| (r.element, r.force.to_array()))
                .collect(),
            requests: requests.to_vec(),
        };
        let poses: Vec<_> = o.state.poses.iter().map(|p| (p.p, p.r)).collect();
        if self.seen.is_multiple_of(self.stride) {
            self.keep(row, poses);
            self.pending = None;
        } else {
            self.pending = Some((row, poses));
        }
        self.seen += 1;
    }

    fn keep(&mut self, row: Row, poses: Vec<(glam::DVec3, glam::DMat3)>) {
        self.frames.push(row.time, poses.into_iter());
        self.rows.push(row);
    }

    /// Keeps the last output when the stride skipped it; the frames' total is the number of
    /// outputs seen.
    pub fn finish(&mut self) {
        if let Some((row, poses)) = self.pending.take() {
            self.keep(row, poses);
        }
        self.frames.total = self.seen;
    }

    /// Outputs seen and outputs kept.
    pub fn counts(&self) -> (usize, usize) {
        (self.seen, self.rows.len())
    }

    /// The sentence saying how the outputs were thinned (None when all are kept).
    pub fn note(&self) -> Option<String> {
        let (seen, kept) = self.counts();
        (kept < seen).then(|| {
            format!(
                "{kept} of {seen} outputs are plotted and animated (one in {}, and the last).",
                self.stride
            )
        })
    }

    /// Position and velocity plots of the first parts, reaction-force plots of the first
    /// elements, and one plot per REQUEST (its columns grouped by the name before the dot).
    pub fn plots(&self, model: &Model) -> Vec<Plot> {
        if !self.picked.is_empty() {
            return self.picked_plots(model);
        }
        let u = units_json(model, Angle::Degree, false);
        let mut plots = Vec::new();
        let xyz = |label: &str| ["x", "y", "z"].map(|c| format!("{label}{c}"));
        let series3 = |names: [String; 3], get: &dyn Fn(&Row) -> Option<[f64; 3]>| {
            (0..3)
                .map(|c| Series {
                    name: names[c].clone(),
                    points: self
                        .rows
                        .iter()
                        .filter_map(|r| get(r).map(|v| (r.time, v[c])))
                        .collect(),
                })
                .collect::<Vec<_>>()
        };
        let x_label = format!("time [{}]", u.time);
        for (k, part) in model.parts.iter().enumerate().take(MAX_PLOTS_PER_KIND) {
            plots.push(Plot {
                title: format!("{}: CM position", part.origin.name),
                x_label: x_label.clone(),
                y_label: format!("position [{}]", u.length),
                series: series3(xyz(""), &|r| r.positions.get(k).copied()),
            });
            plots.push(Plot {
                title: format!("{}: CM velocity", part.origin.name),
                x_label: x_label.clone(),
                y_label: format!("velocity [{}]", u.velocity),
                series: series3(xyz("v"), &|r| r.velocities.get(k).copied()),
            });
        }
        let elements: Vec<usize> = self
            .rows
            .first()
            .map(|r| r.forces.iter().map(|f| f.0).collect())
            .unwrap_or_default();
        for &e in elements.iter().take(MAX_PLOTS_PER_KIND) {
            let Some(c) = model.constraints.get(e) else {
                continue;
            };
            plots.push(Plot {
                title: format!("{}: reaction force on I", c.origin.name),
                x_label: x_label.clone(),
                y_label: format!("force [{}]", u.force),
                series: series3(xyz("f"), &|r| {
                    r.forces.iter().find(|f| f.0 == e).map(|f| f.1)
                }),
            });
        }
        plots.extend(self.request_plots(&x_label));
        plots
    }

    /// One plot per picked column (unknown names, refused by [`check_columns`], are
    /// skipped).
    fn picked_plots(&self, model: &Model) -> Vec<Plot> {
        let u = units_json(model, Angle::Degree, false);
        self.picked
            .iter()
            .filter_map(|name| {
                let c = column(model, &self.request_names, name)?;
                let y_label = match c {
                    Column::Position(..) => format!("position [{}]", u.length),
                    Column::Velocity(..) => format!("velocity [{}]", u.velocity),
                    Column::Force(..) => format!("force [{}]", u.force),
                    Column::Request(_) => "value".into(),
                };
                Some(Plot {
                    title: name.clone(),
                    x_label: format!("time [{}]", u.time),
                    y_label,
                    series: vec![Series {
                        name: name.clone(),
                        points: self
                            .rows
                            .iter()
                            .filter_map(|r| c.value(r).map(|v| (r.time, v)))
                            .collect(),
                    }],
                })
            })
            .collect()
    }

    fn request_plots(&self, x_label: &str) -> Vec<Plot> {
        let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
        for (k, name) in self.request_names.iter().enumerate() {
            let group = name.split('.').next().unwrap_or(name).to_string();
            match groups.iter_mut().find(|g| g.0 == group) {
                Some(g) => g.1.push(k),
                None => groups.push((group, vec![k])),
            }
        }
        groups
            .into_iter()
            .take(MAX_PLOTS_PER_KIND)
            .map(|(group, columns)| Plot {
                title: format!("REQUEST {group}"),
                x_label: x_label.to_string(),
                y_label: "value".into(),
                series: columns
                    .iter()
                    .map(|&c| Series {
                        name: self.request_names[c].clone(),
                        points: self
                            .rows
                            .iter()
                            .filter_map(|r| r.requests.get(c).map(|v| (r.time, *v)))
                            .collect(),
                    })
                    .collect(),
            })
            .collect()
    }

    /// The sentence saying which plots were left out (None when every part, element and
    /// request has its plot).
    pub fn plots_note(&self, model: &Model) -> Option<String> {
        let elements = self.rows.first().map_or(0, |r| r.forces.len());
        let parts = model.parts.len();
        (parts > MAX_PLOTS_PER_KIND || elements > MAX_PLOTS_PER_KIND).then(|| {
            format!(
                "Plots of the first {MAX_PLOTS_PER_KIND} of {parts} parts and of {elements} \
                 reaction elements; the CSV (--out) has every column."
            )
        })
    }
}
