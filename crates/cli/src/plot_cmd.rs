//! `linkage plot FILE.csv|FILE.req --columns A,B --out plot.svg|plot.png`: columns of a time
//! history against time, drawn with `plotters`. The PNG's text uses DejaVu Sans embedded in
//! the binary (the `dejavu` crate), registered with plotters' `ab_glyph` text renderer: no
//! system font is read. The image is written to a temporary file and renamed into place.

use crate::compare_cmd::{load, Series};
use plotters::prelude::*;
use std::path::Path;
use std::process::ExitCode;

/// Image size in pixels.
pub const WIDTH: u32 = 960;
pub const HEIGHT: u32 = 540;

/// Line colours, in order of columns.
const COLOURS: [RGBColor; 6] = [
    RGBColor(76, 120, 168),
    RGBColor(245, 133, 24),
    RGBColor(84, 162, 75),
    RGBColor(228, 87, 86),
    RGBColor(178, 121, 162),
    RGBColor(114, 183, 178),
];

/// The font family name the embedded font is registered under.
const FONT: &str = "linkage-sans";

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    Svg,
    Png,
}

pub fn run(file: &Path, columns: &[String], out: &Path) -> ExitCode {
    let kind = match out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .as_deref()
    {
        Some("svg") => Kind::Svg,
        Some("png") => Kind::Png,
        _ => {
            eprintln!(
                "error: --out {}: the image must end in .svg or .png",
                out.display()
            );
            return ExitCode::from(2);
        }
    };
    let series = match load(file) {
        Ok(s) => s,
        Err(d) => {
            eprintln!("{d}");
            return ExitCode::from(2);
        }
    };
    let mut picked = Vec::with_capacity(columns.len());
    for c in columns {
        match series
            .signals
            .iter()
            .position(|s| s.name.eq_ignore_ascii_case(c.trim()))
        {
            Some(k) => picked.push(k),
            None => {
                let names: Vec<&str> = series.signals.iter().map(|s| s.name.as_str()).collect();
                let shown = names
                    .iter()
                    .take(12)
                    .copied()
                    .collect::<Vec<_>>()
                    .join(", ");
                eprintln!(
                    "error: {}: no column '{c}' (it has {}{})",
                    file.display(),
                    shown,
                    if names.len() > 12 { ", …" } else { "" }
                );
                return ExitCode::from(2);
            }
        }
    }
    if series.times.is_empty() {
        eprintln!("error: {}: no output times to plot", file.display());
        return ExitCode::from(1);
    }
    match render(&series, &picked, out, kind) {
        Ok(()) => {
            println!("{}", out.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: cannot write {}: {e}", out.display());
            ExitCode::from(1)
        }
    }
}

/// The x and y ranges of the picked signals (finite values only; a flat range widened).
fn ranges(series: &Series, picked: &[usize]) -> ((f64, f64), (f64, f64)) {
    let fold = |v: &mut (f64, f64), x: f64| {
        if x.is_finite() {
            *v = (v.0.min(x), v.1.max(x));
        }
    };
    let mut x = (f64::INFINITY, f64::NEG_INFINITY);
    let mut y = x;
    for &t in &series.times {
        fold(&mut x, t);
    }
    for &k in picked {
        for &v in &series.signals[k].values {
            fold(&mut y, v);
        }
    }
    let widen = |(lo, hi): (f64, f64)| {
        if lo > hi {
            (0.0, 1.0)
        } else if hi - lo <= 1e-12 * lo.abs().max(hi.abs()) {
            let pad = lo.abs().max(1.0) * 0.05;
            (lo - pad, hi + pad)
        } else {
            (lo, hi)
        }
    };
    (widen(x), widen(y))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    series: &Series,
    picked: &[usize],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let ((x0, x1), (y0, y1)) = ranges(series, picked);
    let title = picked
        .iter()
        .map(|&k| series.signals[k].name.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 22))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("time")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .draw()
        .map_err(err)?;
    for (n, &k) in picked.iter().enumerate() {
        let colour = COLOURS[n % COLOURS.len()];
        let points = series
            .times
            .iter()
            .zip(&series.signals[k].values)
            .filter(|(t, v)| t.is_finite() && v.is_finite())
            .map(|(t, v)| (*t, *v));
        chart
            .draw_series(LineSeries::new(points, colour.stroke_width(2)))
            .map_err(err)?
            .label(series.signals[k].name.clone())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)
}

/// Draws the plot into `out` by a temporary file beside it and a rename.
fn render(series: &Series, picked: &[usize], out: &Path, kind: Kind) -> Result<(), String> {
    plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| "the embedded font cannot be read".to_string())?;
    match kind {
        Kind::Svg => {
            let mut text = String::new();
            draw(
                SVGBackend::with_string(&mut text, (WIDTH, HEIGHT)).into_drawing_area(),
                series,
                picked,
            )?;
            linkage_html::write_atomically(out, text.as_bytes()).map_err(|e| e.to_string())
        }
        Kind::Png => {
            // The encoder picks PNG from the extension: the temporary file keeps it.
            let dir = match out.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            let name = out
                .file_name()
                .map_or_else(|| "plot".into(), |n| n.to_string_lossy().into_owned());
            let tmp = dir.join(format!(".{name}.{}.tmp.png", std::process::id()));
            let drawn = draw(
                BitMapBackend::new(&tmp, (WIDTH, HEIGHT)).into_drawing_area(),
                series,
                picked,
            )
            .and_then(|()| std::fs::rename(&tmp, out).map_err(|e| e.to_string()));
            if drawn.is_err() {
                let _ = std::fs::remove_file(&tmp);
            }
            drawn
        }
    }
}
