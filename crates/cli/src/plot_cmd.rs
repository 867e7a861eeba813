//! `linkage plot FILE.csv|FILE.req --columns A,B --out plot.svg|plot.png`: columns of a time
//! history against time, drawn with `plotters`.
//!
//! - The axes carry their labels and units: x `time [s]`, y the columns with the unit their
//!   CSV header states (`crank.x, crank.y [m]`); a `.req` file states no units, and its axis
//!   says so. Columns of different units are refused (exit 2, naming each column's unit):
//!   one image, one y axis, one unit.
//! - `--width`, `--height` (pixels, default 960 × 540) and `--line-width` (pixels, default 2).
//! - The PNG is anti-aliased: drawn at [`SUPERSAMPLE`] times its size and each block of
//!   pixels averaged (text, lines and edges get intermediate shades), then encoded with the
//!   `png` crate. Its text uses DejaVu Sans embedded in the binary (the `dejavu` crate),
//!   registered with plotters' `ab_glyph` text renderer: no system font is read.
//! - The image is written to a temporary file and renamed into place.

use crate::compare_cmd::{load, Series};
use plotters::prelude::*;
use std::path::Path;
use std::process::ExitCode;

/// Default image size in pixels.
pub const WIDTH: u32 = 960;
pub const HEIGHT: u32 = 540;

/// Largest width or height accepted, in pixels.
pub const MAX_SIDE: u32 = 10_000;

/// A PNG is drawn at this many times its size, then averaged down (anti-aliasing).
pub const SUPERSAMPLE: u32 = 3;

/// Line colours, in order of columns.
const COLOURS: [RGBColor; 6] = [
    RGBColor(76, 120, 168),
    RGBColor(245, 133, 24),
    RGBColor(84, 162, 75),
    RGBColor(228, 87, 86),
    RGBColor(178, 121, 162),
    RGBColor(114, 183, 178),
];

/// Why an image could not be drawn or written.
#[derive(Debug, thiserror::Error)]
enum PlotError {
    /// plotters' drawing error, as it words it.
    #[error("{0}")]
    Draw(String),
    #[error("the embedded font cannot be read")]
    Font,
    #[error(transparent)]
    Io(#[from] std::io::Error),
    #[error(transparent)]
    Png(#[from] png::EncodingError),
}

/// The font family name the embedded font is registered under.
const FONT: &str = "linkage-sans";

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    Svg,
    Png,
}

/// What `linkage plot` was asked for.
pub struct PlotArgs<'a> {
    pub file: &'a Path,
    pub columns: &'a [String],
    pub out: &'a Path,
    pub width: u32,
    pub height: u32,
    pub line_width: u32,
}

/// The look of one image: its size and line width in pixels of the surface drawn on (a PNG's
/// is [`SUPERSAMPLE`] times the image's).
#[derive(Clone, Copy, Debug)]
struct Look {
    width: u32,
    height: u32,
    line_width: u32,
    /// Pixels of the surface per pixel of the image.
    scale: u32,
}

impl Look {
    fn px(&self, image_pixels: u32) -> u32 {
        image_pixels * self.scale
    }
}

/// The signal of a column name: as the file names it (any case), or for a `.req` file
/// `3.x` as `REQUEST_3.x`.
fn find(series: &Series, column: &str) -> Option<usize> {
    let c = column.trim();
    let by_name = |name: &str| {
        series
            .signals
            .iter()
            .position(|s| s.name.eq_ignore_ascii_case(name))
    };
    by_name(c).or_else(|| {
        c.split_once('.')
            .filter(|(id, _)| !id.is_empty() && id.chars().all(|ch| ch.is_ascii_digit()))
            .and_then(|_| by_name(&format!("REQUEST_{c}")))
    })
}

fn unit_words(unit: Option<&str>) -> String {
    unit.unwrap_or("no unit in the file").to_string()
}

pub fn run(args: &PlotArgs) -> ExitCode {
    let out = args.out;
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
    for (flag, v, max) in [
        ("--width", args.width, MAX_SIDE),
        ("--height", args.height, MAX_SIDE),
        ("--line-width", args.line_width, 50),
    ] {
        if v == 0 || v > max {
            eprintln!("error: {flag} {v}: expected 1 to {max} pixels");
            return ExitCode::from(2);
        }
    }
    if args.width < 200 || args.height < 150 {
        eprintln!(
            "error: --width {} --height {}: a plot needs at least 200 × 150 pixels",
            args.width, args.height
        );
        return ExitCode::from(2);
    }
    let series = match load(args.file) {
        Ok(s) => s,
        Err(d) => {
            eprintln!("{d}");
            return ExitCode::from(2);
        }
    };
    let mut picked = Vec::with_capacity(args.columns.len());
    for c in args.columns {
        match find(&series, c) {
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
                    args.file.display(),
                    shown,
                    if names.len() > 12 { ", …" } else { "" }
                );
                return ExitCode::from(2);
            }
        }
    }
    // One y axis, one unit.
    let units: Vec<Option<&str>> = picked
        .iter()
        .map(|&k| series.signals[k].unit.as_deref())
        .collect();
    if units.iter().any(|u| *u != units[0]) {
        let each: Vec<String> = picked
            .iter()
            .zip(&units)
            .map(|(&k, u)| format!("{} [{}]", series.signals[k].name, unit_words(*u)))
            .collect();
        eprintln!(
            "error: --columns {}: the columns have different units; plot one unit per image",
            each.join(", ")
        );
        return ExitCode::from(2);
    }
    if series.times.is_empty() {
        eprintln!("error: {}: no output times to plot", args.file.display());
        return ExitCode::from(1);
    }
    match render(&series, &picked, args, kind) {
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
        } else if hi - lo <= linkage_html::svg::NOISE_SPAN * lo.abs().max(hi.abs()) {
            // Rounding noise is not magnified: a flat line with ±5 % about its value (0 when
            // the value itself is noise next to nothing).
            let mid = 0.5 * (lo + hi);
            let pad = mid.abs().max(1.0) * 0.05;
            (mid - pad, mid + pad)
        } else {
            (lo, hi)
        }
    };
    (widen(x), widen(y))
}

/// The y axis label: the columns and their unit.
fn y_label(series: &Series, picked: &[usize]) -> String {
    let mut names = picked
        .iter()
        .map(|&k| series.signals[k].name.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    if names.chars().count() > 60 {
        names = names.chars().take(57).collect::<String>() + "…";
    }
    let unit = picked
        .first()
        .and_then(|&k| series.signals[k].unit.as_deref());
    format!("{names} [{}]", unit_words(unit))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    series: &Series,
    picked: &[usize],
    look: Look,
) -> Result<(), PlotError>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| PlotError::Draw(e.to_string());
    root.fill(&WHITE).map_err(err)?;
    let ((x0, x1), (y0, y1)) = ranges(series, picked);
    let title = picked
        .iter()
        .map(|&k| series.signals[k].name.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let px = |p: u32| look.px(p);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, px(20)))
        .margin(px(12))
        .x_label_area_size(px(48))
        .y_label_area_size(px(84))
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    let time_label = format!(
        "time [{}]",
        series.time_unit.as_deref().unwrap_or("no unit in the file")
    );
    chart
        .configure_mesh()
        .x_desc(time_label)
        .y_desc(y_label(series, picked))
        .label_style((FONT, px(14)))
        .axis_desc_style((FONT, px(15)))
        .bold_line_style(RGBColor(225, 225, 225).stroke_width(px(1)))
        .light_line_style(RGBColor(243, 243, 243).stroke_width(px(1)))
        .axis_style(BLACK.stroke_width(px(1)))
        .draw()
        .map_err(err)?;
    let width = px(look.line_width);
    for (n, &k) in picked.iter().enumerate() {
        let colour = COLOURS[n % COLOURS.len()];
        let points = series
            .times
            .iter()
            .zip(&series.signals[k].values)
            .filter(|(t, v)| t.is_finite() && v.is_finite())
            .map(|(t, v)| (*t, *v));
        let legend = px(18);
        chart
            .draw_series(LineSeries::new(points, colour.stroke_width(width)))
            .map_err(err)?
            .label(series.signals[k].name.clone())
            .legend(move |(x, y)| {
                PathElement::new([(x, y), (x + legend as i32, y)], colour.stroke_width(width))
            });
    }
    chart
        .configure_series_labels()
        .label_font((FONT, px(14)))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.stroke_width(px(1)))
        .draw()
        .map_err(err)?;
    root.present().map_err(err)
}

/// `pixels` (RGB, `width·k` × `height·k`) averaged over k × k blocks: `width` × `height`.
fn downsample(pixels: &[u8], width: u32, height: u32, k: u32) -> Vec<u8> {
    let (w, h, k) = (width as usize, height as usize, k as usize);
    let big_w = w * k;
    let mut out = vec![0u8; w * h * 3];
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0u32; 3];
            for dy in 0..k {
                let row = (y * k + dy) * big_w;
                for dx in 0..k {
                    let p = (row + x * k + dx) * 3;
                    for (c, total) in sum.iter_mut().enumerate() {
                        *total += u32::from(pixels[p + c]);
                    }
                }
            }
            let n = (k * k) as u32;
            for (c, total) in sum.iter().enumerate() {
                // Rounded mean of the block, always within 0..=255.
                out[(y * w + x) * 3 + c] = ((total + n / 2) / n).min(255) as u8;
            }
        }
    }
    out
}

/// An 8-bit RGB PNG of `pixels` at `path`.
fn write_png(path: &Path, pixels: &[u8], width: u32, height: u32) -> Result<(), PlotError> {
    let file = std::fs::File::create(path)?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(pixels)?;
    Ok(writer.finish()?)
}

/// Draws the plot into `out` by a temporary file beside it and a rename.
fn render(series: &Series, picked: &[usize], args: &PlotArgs, kind: Kind) -> Result<(), PlotError> {
    plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| PlotError::Font)?;
    let (width, height) = (args.width, args.height);
    match kind {
        Kind::Svg => {
            let look = Look {
                width,
                height,
                line_width: args.line_width,
                scale: 1,
            };
            let mut text = String::new();
            draw(
                SVGBackend::with_string(&mut text, (look.width, look.height)).into_drawing_area(),
                series,
                picked,
                look,
            )?;
            Ok(linkage_html::write_atomically(args.out, text.as_bytes())?)
        }
        Kind::Png => {
            // Large images are drawn at a lower supersampling, within about 100 MB.
            let k = (1..=SUPERSAMPLE)
                .rev()
                .find(|k| u64::from(width * k) * u64::from(height * k) * 3 <= 100_000_000)
                .unwrap_or(1);
            let look = Look {
                width: width * k,
                height: height * k,
                line_width: args.line_width,
                scale: k,
            };
            let mut big = vec![255u8; look.width as usize * look.height as usize * 3];
            draw(
                BitMapBackend::with_buffer(&mut big, (look.width, look.height)).into_drawing_area(),
                series,
                picked,
                look,
            )?;
            let small = downsample(&big, width, height, k);
            drop(big);
            let out = args.out;
            let dir = match out.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            let name = out
                .file_name()
                .map_or_else(|| "plot".into(), |n| n.to_string_lossy().into_owned());
            let tmp = dir.join(format!(".{name}.{}.tmp.png", std::process::id()));
            let written = write_png(&tmp, &small, width, height)
                .and_then(|()| Ok(std::fs::rename(&tmp, out)?));
            if written.is_err() {
                let _ = std::fs::remove_file(&tmp);
            }
            written
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_averages_each_block() {
        // 2 × 1 image from a 4 × 2 surface: a black and white block, a half-grey one.
        let mut big = vec![255u8; 4 * 2 * 3];
        for p in [0usize, 1, 4, 5] {
            big[p * 3..p * 3 + 3].copy_from_slice(&[0, 0, 0]);
        }
        // Second block: half its pixels black → 128.
        for p in [2usize, 7] {
            big[p * 3..p * 3 + 3].copy_from_slice(&[0, 0, 0]);
        }
        assert_eq!(downsample(&big, 2, 1, 2), [0, 0, 0, 128, 128, 128]);
    }
}
