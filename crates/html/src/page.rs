//! The HTML document: one file, every style and script inline, no network reference.
//!
//! Layout: a header (analysis, file, title), the verdict in words with every error of the
//! report ([`crate::verdict`]), the 3-D view with its controls, parts list and notes, the
//! plots (each against time with a time cursor the view's slider moves), then the report
//! tables. The scene goes into the page as JSON
//! (`<script type="application/json" id="scene-data">`): meshes in body frames as flat `f32`
//! lists, and per animation one flat list per frame of `x y z qw qx qy qz` for each moving
//! part. A first inline script catches every script error into the hidden `#status`; the
//! viewer writes `ok frames=… drawn_pixels=…` and the layout facts a test reads there once it
//! has drawn its first frame (the element is never shown).
//!
//! The page's address may carry `#paused` (no autoplay) and `frame=K` (the slider moved to
//! output K, as a user would): `page.html#paused&frame=40`.

use crate::scene::{Frames, Scene};
use crate::svg::{self, Plot};
use crate::text::{escape, script_json};
use crate::verdict::{verdict, Level};
use glam::DVec3;
use serde::Serialize;
use std::fmt::Write;

/// Most animation frames kept in a page; longer runs are thinned ([`crate::svg::thin`]).
pub const MAX_FRAMES: usize = 400;

/// Most pose numbers (7 per part per frame) an animation puts in a page: a model of many
/// parts gets fewer frames (at least 2), so that the page stays tens of megabytes.
pub const MAX_POSE_VALUES: usize = 3_000_000;

/// The frames an animation of `parts` moving parts keeps at most.
pub fn frame_budget(parts: usize) -> usize {
    (MAX_POSE_VALUES / (7 * parts.max(1))).clamp(2, MAX_FRAMES)
}

/// Everything a page shows.
#[derive(Clone, Debug, Default)]
pub struct Page {
    /// `verify`, `simulate`, …
    pub analysis: String,
    /// The report of the analysis (a `linkage-report` JSON structure, serialised).
    pub report: serde_json::Value,
    pub scene: Scene,
    /// Gravity of the model (the view's up axis is against it; +y without gravity).
    pub gravity: DVec3,
    /// The animations the view offers (the first is shown first).
    pub animations: Vec<Frames>,
    pub plots: Vec<Plot>,
    /// Sentences shown under the view and the plots (what was thinned, and how).
    pub notes: Vec<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn many_parts_get_fewer_frames() {
        assert_eq!(frame_budget(3), MAX_FRAMES);
        // 20,001 parts: 3e6 / 140007 = 21 frames (about 3 million numbers).
        assert_eq!(frame_budget(20_001), 21);
        assert_eq!(frame_budget(1_000_000), 2);
    }

    #[test]
    fn a_page_refers_to_nothing_outside_it() {
        let html = render(&Page {
            analysis: "verify".into(),
            report: serde_json::json!({"title": "</script><script>alert(1)</script>"}),
            ..Page::default()
        });
        for bad in ["http://", "https://", " src=", "<link"] {
            assert!(!html.contains(bad), "{bad}");
        }
        // The title is text, not markup.
        assert!(!html.contains("<script>alert(1)"));
        assert_eq!(html.matches("<script").count(), 3);
    }
}

#[derive(Serialize)]
struct ItemJson<'a> {
    b: i64,
    #[serde(skip_serializing_if = "Option::is_none")]
    vb: Option<Vec<i64>>,
    c: [u8; 3],
    p: Vec<f32>,
    t: Vec<u32>,
    l: Vec<u32>,
    n: &'a str,
}

#[derive(Serialize)]
struct AnimJson<'a> {
    label: &'a str,
    times: Vec<f64>,
    poses: Vec<Vec<f32>>,
    total: usize,
}

#[derive(Serialize)]
struct SceneJson<'a> {
    items: Vec<ItemJson<'a>>,
    anims: Vec<AnimJson<'a>>,
    parts: &'a [String],
    up: [f64; 3],
    across: [f64; 3],
}

fn body(b: Option<usize>) -> i64 {
    b.map_or(-1, |k| k as i64)
}

/// The up axis (against gravity, +y without it) and a horizontal axis the view starts from.
fn axes(gravity: DVec3) -> (DVec3, DVec3) {
    let up = (-gravity).try_normalize().unwrap_or(DVec3::Y);
    let reference = if up.dot(DVec3::Z).abs() < 0.9 {
        DVec3::Z
    } else {
        -DVec3::Y
    };
    let across = (reference - up * reference.dot(up)).normalize();
    (up, across)
}

/// The scene and its animations as the viewer reads them; animations thinned to
/// [`MAX_FRAMES`].
fn scene_json(page: &Page) -> String {
    let items = page
        .scene
        .items
        .iter()
        .map(|it| ItemJson {
            b: body(it.body),
            vb: it
                .vertex_bodies
                .as_ref()
                .map(|v| v.iter().map(|b| body(*b)).collect()),
            c: it.colour,
            p: it
                .mesh
                .positions
                .iter()
                .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
                .collect(),
            t: it.mesh.triangles.iter().flatten().copied().collect(),
            l: it.mesh.lines.iter().flatten().copied().collect(),
            n: &it.label,
        })
        .collect();
    let anims = page
        .animations
        .iter()
        .map(|a| {
            let budget = frame_budget(page.scene.parts.len());
            let index: Vec<usize> = svg::thin(&(0..a.times.len()).collect::<Vec<_>>(), budget);
            AnimJson {
                label: &a.label,
                times: index.iter().map(|&k| a.times[k]).collect(),
                poses: index
                    .iter()
                    .map(|&k| {
                        a.poses[k]
                            .iter()
                            .flat_map(|(p, q)| {
                                [p.x, p.y, p.z, q.w, q.x, q.y, q.z].map(|v| v as f32)
                            })
                            .collect()
                    })
                    .collect(),
                total: a.total.max(a.times.len()),
            }
        })
        .collect();
    let (up, across) = axes(page.gravity);
    let json = SceneJson {
        items,
        anims,
        parts: &page.scene.parts,
        up: up.to_array(),
        across: across.to_array(),
    };
    script_json(&serde_json::to_string(&json).unwrap_or_else(|_| "{}".into()))
}

const STYLE: &str = "body{font:14px/1.4 system-ui,sans-serif;margin:0 auto;max-width:1100px;padding:12px;color:#222}\
h1{font-size:20px}h2{font-size:17px;margin-top:28px}h3,h4{font-size:15px}\
table{border-collapse:collapse;margin:6px 0 14px}td,th{border:1px solid #ccc;padding:2px 6px;text-align:left;font-variant-numeric:tabular-nums}\
th{background:#f3f3f6}.kv th{width:240px}canvas{border:1px solid #bbb;background:#fafafc;cursor:grab;max-width:100%}\
.controls{margin:6px 0}.plots svg{margin:4px;font-size:11px}.plots .pt{font-size:13px;font-weight:600}\
.errors{color:#b00}.warnings{color:#850}.note{color:#555}\
.verdict{border:2px solid;border-radius:6px;padding:8px 12px;margin:10px 0 16px}\
.verdict .headline{font-size:16px;font-weight:600;margin:2px 0}\
.verdict.ok{border-color:#4a4;background:#f2fbf2}.verdict.attention{border-color:#c80;background:#fff8ec}\
.verdict.failed{border-color:#c00;background:#fff1f1}.verdict.failed .headline{color:#b00}\
.view{display:flex;gap:10px;align-items:flex-start}#parts{max-height:520px;overflow:auto;font-size:12px;min-width:140px}\
#parts label{display:block;white-space:nowrap}";

/// The verdict box: the headline, every error, the warnings folded.
fn verdict_html(page: &Page) -> String {
    let v = verdict(&page.analysis, &page.report);
    let class = match v.level {
        Level::Ok => "ok",
        Level::Attention => "attention",
        Level::Failed => "failed",
    };
    let mut s = format!(
        "<section id=\"verdict\" class=\"verdict {class}\"><p class=\"headline\">{}</p>",
        escape(&v.headline)
    );
    if !v.errors.is_empty() {
        s.push_str("<ul class=\"errors\">");
        for e in &v.errors {
            let _ = write!(s, "<li>{}</li>", escape(e));
        }
        s.push_str("</ul>");
    }
    if !v.warnings.is_empty() {
        let _ = write!(
            s,
            "<details class=\"warnings\"><summary>{} warning{}</summary><ul>",
            v.warnings.len(),
            if v.warnings.len() == 1 { "" } else { "s" }
        );
        for w in &v.warnings {
            let _ = write!(s, "<li>{}</li>", escape(w));
        }
        s.push_str("</ul></details>");
    }
    s.push_str("</section>");
    s
}

/// The plots, each with its y noise judged against the largest magnitude of its quantity
/// (the plots of the same y label) on the page.
fn plots_html(plots: &[Plot]) -> String {
    let mut scale: std::collections::HashMap<&str, f64> = std::collections::HashMap::new();
    for p in plots {
        let m = scale.entry(p.y_label.as_str()).or_insert(0.0);
        *m = m.max(svg::magnitude(p));
    }
    plots
        .iter()
        .map(|p| svg::svg_scaled(p, scale.get(p.y_label.as_str()).copied().unwrap_or(0.0)))
        .collect()
}

/// The whole page.
pub fn render(page: &Page) -> String {
    let mut s = String::with_capacity(64 * 1024);
    let title = page
        .report
        .get("title")
        .and_then(|t| t.as_str())
        .unwrap_or("");
    let file = page
        .report
        .get("file")
        .and_then(|t| t.as_str())
        .unwrap_or("");
    let _ = write!(
        s,
        "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>linkage {} — {}</title><style>{STYLE}</style></head><body>\
         <h1>linkage {}: {}</h1><p>{}</p>\
         <div id=\"status\" hidden>loading</div>\
         <script>window.__linkageErrors=[];window.onerror=function(m,s,l,c){{\
         window.__linkageErrors.push(m+' at '+l+':'+c);\
         var e=document.getElementById('status');if(e)e.textContent='error: '+window.__linkageErrors.join('; ');}};</script>",
        escape(&page.analysis),
        escape(file),
        escape(&page.analysis),
        escape(file),
        escape(title),
    );
    s.push_str(&verdict_html(page));
    s.push_str("<h2>3-D view</h2><div class=\"view\"><canvas id=\"view\" width=\"900\" height=\"520\"></canvas><div id=\"parts\"></div></div><div class=\"controls\">");
    s.push_str("<button id=\"play\">play</button> <input id=\"frame\" type=\"range\" min=\"0\" max=\"0\" value=\"0\" style=\"width:55%\"> <span id=\"clock\"></span> <label><input id=\"autoplay\" type=\"checkbox\" checked> autoplay</label>");
    if page.animations.len() > 1 {
        s.push_str(" <select id=\"anim\">");
        for (k, a) in page.animations.iter().enumerate() {
            let _ = write!(s, "<option value=\"{k}\">{}</option>", escape(&a.label));
        }
        s.push_str("</select>");
    }
    s.push_str("</div><p class=\"note\">Drag to orbit, wheel to zoom; click a part to make it transparent, again to hide it (the list beside the view shows it again). A solid whose surface spans much of the scene (a windshield, a base plate) starts transparent.");
    let budget = frame_budget(page.scene.parts.len());
    for a in &page.animations {
        let total = a.total.max(a.times.len());
        let shown = svg::thin(&(0..a.times.len()).collect::<Vec<_>>(), budget).len();
        if shown < total {
            let _ = write!(
                s,
                " {}: {shown} of {total} outputs animated.",
                escape(&a.label)
            );
        }
    }
    if !page.scene.highlighted.is_empty() {
        let _ = write!(
            s,
            " In red: {} (redundant or misaligned equations).",
            escape(&page.scene.highlighted.join(", "))
        );
    }
    if !page.scene.externals.is_empty() {
        let _ = write!(
            s,
            " EXTERNAL geometry drawn as its marker's triad: {}.",
            escape(&page.scene.externals.join(", "))
        );
    }
    s.push_str("</p>");
    if !page.plots.is_empty() || !page.notes.is_empty() {
        s.push_str("<h2>Plots</h2>");
        for n in &page.notes {
            let _ = write!(s, "<p class=\"note\">{}</p>", escape(n));
        }
        s.push_str("<div class=\"plots\">");
        s.push_str(&plots_html(&page.plots));
        s.push_str("</div>");
    }
    s.push_str("<h2>Report</h2>");
    s.push_str(&crate::tables::report_tables(&page.report));
    let _ = writeln!(
        s,
        "<script type=\"application/json\" id=\"scene-data\">{}</script><script>{}</script></body></html>",
        scene_json(page),
        include_str!("viewer.js")
    );
    s
}
