//! Inline SVG line plots: one or more series against a common x axis, with ticks, labels and
//! a legend. Non-finite points are left out (a gap is not drawn as a line through it).
//!
//! The y axis never magnifies rounding noise: its span is at least [`NOISE_SPAN`] of the
//! quantity's scale (the largest magnitude of that quantity on the page, [`svg_scaled`]), so a
//! coordinate that stays at 0 ± 1e-20 m among parts that move by metres is a flat line at 0.
//! A plot against time carries a time cursor (`<line class="cursor">`, hidden until the page's
//! view moves it) and the mapping of time to its x coordinate (`data-t0`, `data-t1`,
//! `data-left`, `data-width`).

use crate::text::escape;
use std::fmt::Write;

/// Most points of a series drawn on the page; longer series are thinned ([`thin`]).
pub const MAX_POINTS: usize = 500;

/// Plot size in SVG user units (pixels).
const WIDTH: f64 = 520.0;
const HEIGHT: f64 = 280.0;
const LEFT: f64 = 70.0;
const RIGHT: f64 = 12.0;
const TOP: f64 = 28.0;
const BOTTOM: f64 = 44.0;

/// A plot's y span is at least this fraction of its quantity's scale: below it a variation is
/// rounding noise (the solver resolves about 1e-10 of the model's size; a 280-pixel plot shows
/// 1e-3 of its span), drawn flat.
pub const NOISE_SPAN: f64 = 1e-6;

/// The half-height of the y range of a flat plot, as a fraction of the quantity's scale.
const FLAT_PAD: f64 = 0.05;

/// The y range extends this fraction of the values' range beyond them, on each side.
const EDGE_MARGIN: f64 = 0.04;

/// Line colours, in order of series.
const COLOURS: [&str; 6] = [
    "#4c78a8", "#f58518", "#54a24b", "#e45756", "#b279a2", "#72b7b2",
];

#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Plot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

/// Every `k`-th point, `k = ceil(n / max)`, and always the last one: at most `max + 1`
/// points, evenly spaced in output number. Returns the points kept.
pub fn thin<T: Copy>(points: &[T], max: usize) -> Vec<T> {
    let stride = stride(points.len(), max);
    let mut out: Vec<T> = points.iter().step_by(stride).copied().collect();
    if let Some(last) = points.last() {
        if !(points.len() - 1).is_multiple_of(stride) {
            out.push(*last);
        }
    }
    out
}

/// The stride [`thin`] uses for `n` points (1 when `n <= max`).
pub fn stride(n: usize, max: usize) -> usize {
    n.div_ceil(max.max(1)).max(1)
}

/// "Nice" tick values covering `lo..=hi` (about five).
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let span = hi - lo;
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| span / s <= 6.0)
        .unwrap_or(10.0 * mag);
    // Integer multiples of the step: a tick at zero is exactly zero.
    let first = (lo / step).ceil();
    (0..=12)
        .map(|k| (first + k as f64) * step)
        .take_while(|t| *t <= hi + step * 1e-9)
        .collect()
}

fn label(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e5 || v.abs() < 1e-3 {
        format!("{v:.2e}")
    } else {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    }
}

/// The plot as an `<svg>` element (thinned to [`MAX_POINTS`] per series), its noise judged
/// against its own largest magnitude.
pub fn svg(plot: &Plot) -> String {
    svg_scaled(plot, 0.0)
}

/// The largest finite magnitude of the y values of `plot`.
pub fn magnitude(plot: &Plot) -> f64 {
    plot.series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .fold(0.0, |m: f64, p| m.max(p.1.abs()))
}

/// The y range shown for values in `y0..=y1` of a quantity of scale `scale` (the largest
/// magnitude of that quantity among the plots it is shown with): the values' range, or when
/// it is narrower than [`NOISE_SPAN`] of the scale, a flat range about their middle (0 when
/// the middle itself is noise).
fn y_range(y0: f64, y1: f64, scale: f64) -> (f64, f64) {
    let scale = scale.max(y0.abs()).max(y1.abs());
    if y1 - y0 > NOISE_SPAN * scale && y1 > y0 {
        // A margin, so that a line along the range's edge is not drawn on the frame.
        let margin = EDGE_MARGIN * (y1 - y0);
        return (y0 - margin, y1 + margin);
    }
    let mid = 0.5 * (y0 + y1);
    let mid = if mid.abs() <= NOISE_SPAN * scale {
        0.0
    } else {
        mid
    };
    let pad = if scale > 0.0 { FLAT_PAD * scale } else { 1.0 };
    (mid - pad, mid + pad)
}

/// The plot as an `<svg>` element, its y noise judged against `scale` (or its own largest
/// magnitude when that is larger).
pub fn svg_scaled(plot: &Plot, scale: f64) -> String {
    let finite = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let all = plot
        .series
        .iter()
        .flat_map(|s| s.points.iter().filter(finite));
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, y) in all {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    // No finite point: a unit frame.
    if x0 > x1 {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    if x1 - x0 <= 0.0 {
        x1 = x0 + 1.0;
    }
    (y0, y1) = y_range(y0, y1, scale);
    let (pw, ph) = (WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM);
    let sx = |x: f64| LEFT + (x - x0) / (x1 - x0) * pw;
    let sy = |y: f64| TOP + (1.0 - (y - y0) / (y1 - y0)) * ph;
    let mut s = String::new();
    let timed = plot.x_label.starts_with("time");
    let cursor_data = if timed {
        format!(" data-t0=\"{x0}\" data-t1=\"{x1}\" data-left=\"{LEFT}\" data-width=\"{pw}\"")
    } else {
        String::new()
    };
    let _ = write!(
        s,
        "<svg class=\"plot\" viewBox=\"0 0 {WIDTH} {HEIGHT}\"{cursor_data} \
         width=\"{WIDTH}\" height=\"{HEIGHT}\" role=\"img\"><title>{}</title>\
         <rect x=\"{LEFT}\" y=\"{TOP}\" width=\"{pw}\" height=\"{ph}\" fill=\"#fff\" stroke=\"#999\"/>\
         <text x=\"{}\" y=\"16\" text-anchor=\"middle\" class=\"pt\">{}</text>",
        escape(&plot.title),
        WIDTH / 2.0,
        escape(&plot.title)
    );
    for t in ticks(x0, x1) {
        let x = sx(t);
        let _ = write!(
            s,
            "<line x1=\"{x:.1}\" y1=\"{TOP}\" x2=\"{x:.1}\" y2=\"{}\" stroke=\"#eee\"/>\
             <text x=\"{x:.1}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
            TOP + ph,
            TOP + ph + 14.0,
            label(t)
        );
    }
    for t in ticks(y0, y1) {
        let y = sy(t);
        let _ = write!(
            s,
            "<line x1=\"{LEFT}\" y1=\"{y:.1}\" x2=\"{}\" y2=\"{y:.1}\" stroke=\"#eee\"/>\
             <text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
            LEFT + pw,
            LEFT - 4.0,
            y + 4.0,
            label(t)
        );
    }
    let _ = write!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\
         <text x=\"14\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 14 {})\">{}</text>",
        LEFT + pw / 2.0,
        HEIGHT - 6.0,
        escape(&plot.x_label),
        TOP + ph / 2.0,
        TOP + ph / 2.0,
        escape(&plot.y_label)
    );
    for (k, series) in plot.series.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let kept = thin(&series.points, MAX_POINTS);
        let pts: Vec<String> = kept
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .map(|(x, y)| format!("{:.2},{:.2}", sx(*x), sy(*y)))
            .collect();
        let _ = write!(
            s,
            "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\" points=\"{}\"/>\
             <text x=\"{}\" y=\"{}\" fill=\"{colour}\">{}</text>",
            pts.join(" "),
            LEFT + 6.0 + (k % 3) as f64 * (pw / 3.0),
            TOP + 14.0 + (k / 3) as f64 * 13.0,
            escape(&series.name)
        );
    }
    if timed {
        let _ = write!(
            s,
            "<line class=\"cursor\" x1=\"{LEFT}\" y1=\"{TOP}\" x2=\"{LEFT}\" y2=\"{}\" \
             stroke=\"#c00\" stroke-width=\"1.5\" visibility=\"hidden\"/>",
            TOP + ph
        );
    }
    s.push_str("</svg>");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn polyline_points(svg: &str) -> Vec<usize> {
        svg.split("points=\"")
            .skip(1)
            .map(|rest| {
                rest.split('"')
                    .next()
                    .unwrap_or("")
                    .split_whitespace()
                    .count()
            })
            .collect()
    }

    #[test]
    fn a_long_series_is_thinned_to_every_kth_point_and_its_last() {
        let pts: Vec<(f64, f64)> = (0..=2000).map(|k| (k as f64, (k as f64).sin())).collect();
        // 2001 points, at most 500: every 5th (401 points, the last one included).
        assert_eq!(stride(2001, MAX_POINTS), 5);
        let kept = thin(&pts, MAX_POINTS);
        assert_eq!(kept.len(), 401);
        assert_eq!(kept.last(), pts.last());
        let s = svg(&Plot {
            title: "t".into(),
            x_label: "time [s]".into(),
            y_label: "y".into(),
            series: vec![Series {
                name: "sin".into(),
                points: pts,
            }],
        });
        assert_eq!(polyline_points(&s), [401]);
    }

    #[test]
    fn a_short_series_keeps_every_point_and_skips_non_finite_ones() {
        let pts = vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0)];
        let s = svg(&Plot {
            title: "a < b".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            series: vec![Series {
                name: "s".into(),
                points: pts,
            }],
        });
        assert_eq!(polyline_points(&s), [2]);
        assert!(s.contains("a &lt; b"));
        // x from 0 to 2 maps onto the plot's width.
        assert!(s.contains(&format!("{:.2},", LEFT)), "{s}");
        assert!(s.contains(&format!("{:.2},", WIDTH - RIGHT)), "{s}");
    }

    fn y_ticks(svg: &str) -> Vec<String> {
        svg.split("text-anchor=\"end\">")
            .skip(1)
            .map(|t| t.split('<').next().unwrap_or("").to_string())
            .collect()
    }

    #[test]
    fn rounding_noise_on_the_y_axis_is_a_flat_line_at_zero() {
        // z of a planar part: ±1e-20 m; the page's positions reach 0.5 m. The axis spans
        // ±5 % of 0.5 m about 0, not ±1e-20.
        let pts: Vec<(f64, f64)> = (0..50)
            .map(|k| (k as f64 * 0.02, if k % 2 == 0 { 1e-20 } else { -1e-20 }))
            .collect();
        let plot = Plot {
            title: "z".into(),
            x_label: "time [s]".into(),
            y_label: "position [m]".into(),
            series: vec![Series {
                name: "z".into(),
                points: pts,
            }],
        };
        let s = svg_scaled(&plot, 0.5);
        assert_eq!(y_ticks(&s), ["-0.02", "-0.01", "0", "0.01", "0.02"], "{s}");
        // Alone, its scale is its own: the noise is all there is to show.
        assert_eq!(y_ticks(&svg(&plot))[0], "-1.00e-20");
        // A real variation of 1 mm in 0.5 m is drawn as it is (with 4 % margins).
        let (lo, hi) = y_range(0.499, 0.5, 0.5);
        assert!((lo - 0.49896).abs() < 1e-12 && (hi - 0.50004).abs() < 1e-12);
        // A constant away from zero: centred on it, ±5 % of the scale.
        let (lo, hi) = y_range(0.3, 0.3, 0.5);
        assert!((lo - 0.275).abs() < 1e-12 && (hi - 0.325).abs() < 1e-12);
    }

    #[test]
    fn a_plot_against_time_carries_a_hidden_time_cursor() {
        let plot = |x_label: &str| Plot {
            title: "t".into(),
            x_label: x_label.into(),
            y_label: "y".into(),
            series: vec![Series {
                name: "s".into(),
                points: vec![(0.0, 0.0), (2.0, 1.0)],
            }],
        };
        let s = svg(&plot("time [s]"));
        assert!(s.contains("data-t0=\"0\" data-t1=\"2\""), "{s}");
        assert!(s.contains("<line class=\"cursor\""), "{s}");
        let s = svg(&plot("Newton iteration"));
        assert!(!s.contains("cursor"), "{s}");
    }

    #[test]
    fn thinning_nothing_gives_nothing() {
        assert!(thin::<f64>(&[], MAX_POINTS).is_empty());
        assert_eq!(thin(&[1, 2, 3], 2), [1, 3]);
    }

    #[test]
    fn ticks_are_round_numbers_inside_the_range() {
        assert_eq!(
            ticks(0.0, 1.0),
            [0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]
        );
        let t = ticks(-3.3, 7.9);
        assert_eq!((t[0], *t.last().unwrap()), (-2.0, 6.0));
    }
}
