//! `--html` pages and `linkage plot` images, end to end; the page loaded in headless
//! Chromium (scripts run without error, the 3-D view draws, a screenshot is not blank).

mod common;
use common::*;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh folder under the target directory for one test's outputs.
fn scratch(name: &str) -> PathBuf {
    let dir = root().join("target/test-html").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Point counts of every `<polyline points="…">` of a page.
fn polyline_points(page: &str) -> Vec<usize> {
    page.split("points=\"")
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

/// No script, style, font or image from anywhere: nothing names a network address, and no
/// element loads a file (`src=`, `<link`).
fn assert_self_contained(page: &str) {
    for bad in ["http://", "https://", " src=", "<link", "@import", "url("] {
        assert!(!page.contains(bad), "the page contains {bad:?}");
    }
}

fn example() -> String {
    root().join("examples/fourbar.adm").display().to_string()
}

#[test]
fn a_simulate_page_holds_the_report_tables_and_plots_thinned_to_its_frames() {
    let dir = scratch("simulate");
    let page = dir.join("fourbar.html");
    let (code, out, err) = run(&[
        "simulate",
        &example(),
        "--end",
        "1",
        "--steps",
        "1000",
        "--html",
        page.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let html = read(&page);
    assert_self_contained(&html);
    // 1001 outputs, at most 400 frames: every 3rd output (0, 3, …, 999) and the last.
    assert!(
        html.contains("335 of 1001 outputs are plotted and animated (one in 3, and the last)"),
        "{}",
        &html[..2000.min(html.len())]
    );
    // Position and velocity of 3 parts, the reaction force of 4 joints and the motion:
    // every series has the 335 kept points.
    let counts = polyline_points(&html);
    assert_eq!(counts.len(), (3 * 2 + 5) * 3, "{counts:?}");
    assert!(counts.iter().all(|&n| n == 335), "{counts:?}");
    // The report's final state: the crank driven at 30°/s from 60° is at 90° after 1 s,
    // turning at 30°/s = 0.5235988 rad/s.
    assert!(
        html.contains("<th>reuler [degree]</th>"),
        "units in the headers"
    );
    let crank = html
        .split("<tr><td>crank</td>")
        .nth(1)
        .and_then(|r| r.split("</tr>").next())
        .expect("a crank row in the final state table");
    assert!(crank.contains("<td>90, 0, 0</td>"), "crank at 90°: {crank}");
    assert!(
        crank.contains("<td>0, 0, 0.5235988</td>"),
        "crank at 30°/s: {crank}"
    );
    // The scene: 5 GRAPHICS (box, 3 cylinders, ellipsoid) and 4 joint symbols.
    assert!(html.contains("\"n\":\"crank_rod\""), "crank rod drawn");
    assert_eq!(html.matches("(REVOLUTE)").count(), 4);
}

#[test]
fn a_verify_page_draws_the_misaligned_hinge_in_red() {
    let dir = scratch("verify");
    let page = dir.join("door.html");
    let door = root().join("mechanisms/door_tilted_hinge.adm");
    let (code, _, _) = run(&[
        "verify",
        door.to_str().unwrap(),
        "--html",
        page.to_str().unwrap(),
    ]);
    // An inconsistent redundancy: verify fails, and the page says where.
    assert_eq!(code, 1);
    let html = read(&page);
    assert_self_contained(&html);
    assert!(
        html.contains("(redundant or misaligned equations)"),
        "highlight note"
    );
    assert!(html.contains("\"c\":[220,0,0]"), "a red joint symbol");
    assert!(html.contains("<h3>Redundant ("), "redundant table");
}

#[test]
fn ic_static_series_and_linear_pages_are_written() {
    let dir = scratch("others");
    let ex = example();
    let ic = dir.join("ic.html");
    assert_eq!(run(&["ic", &ex, "--html", ic.to_str().unwrap()]).0, 0);
    assert!(read(&ic).contains("input → assembled"));
    let st = dir.join("static.html");
    let (code, out, err) = run(&[
        "static",
        &ex,
        "--end",
        "1",
        "--steps",
        "4",
        "--html",
        st.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let html = read(&st);
    assert_self_contained(&html);
    // 5 equilibria: each part's position and each joint's reaction, 5 points per series.
    let counts = polyline_points(&html);
    assert!(
        !counts.is_empty() && counts.iter().all(|&n| n == 5),
        "{counts:?}"
    );
    // One equilibrium by Newton: the imbalance of every iteration (5 iterations, so 6
    // residuals: the start and after each correction) on a log scale, falling.
    let offset = root().join("mechanisms/pendulum_offset.adm");
    let eq = dir.join("equilibrium.html");
    let (code, v) = json(&["static", offset.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    let iterations = v["iterations"].as_u64().unwrap() as usize;
    assert_eq!(
        run(&[
            "static",
            offset.to_str().unwrap(),
            "--html",
            eq.to_str().unwrap()
        ])
        .0,
        0
    );
    let html = read(&eq);
    assert!(html.contains("largest imbalance per Newton iteration"));
    assert_eq!(polyline_points(&html), [iterations + 1]);
    let pendulum = root().join("mechanisms/pendulum.adm");
    let lin = dir.join("linear.html");
    let (code, out, err) = run(&[
        "linear",
        pendulum.to_str().unwrap(),
        "--html",
        lin.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let html = read(&lin);
    assert!(html.contains("mode 1 ("), "a mode-shape animation");
    assert!(html.contains("<h3>Modes (1 row)</h3>"), "the mode table");
}

#[test]
fn an_html_page_never_overwrites_its_input() {
    let dir = scratch("refuse");
    let model = dir.join("m.adm");
    std::fs::copy(root().join("examples/fourbar.adm"), &model).unwrap();
    let (code, _, err) = run(&[
        "verify",
        model.to_str().unwrap(),
        "--html",
        model.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("refusing to write"), "{err}");
    assert!(read(&model).starts_with("Adams View model name"));
}

#[test]
fn a_command_file_run_writes_its_page() {
    let dir = scratch("run");
    let page = dir.join("run.html");
    let acf = root().join("examples/fourbar.acf");
    let (code, out, err) = run(&[
        "run",
        acf.to_str().unwrap(),
        "--out-dir",
        dir.to_str().unwrap(),
        "--html",
        page.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let html = read(&page);
    assert_self_contained(&html);
    // 22 outputs (IC, 21 over the second; the static one at its end repeats t = 1).
    assert!(
        html.contains("crank: CM position"),
        "plots from the run's CSV"
    );
    assert!(
        html.contains("\"anims\":[{\"label\":\"time\""),
        "an animation"
    );
}

/// PNG signature, width and height from the IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |k: usize| u32::from_be_bytes([bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]]);
    (be(16), be(20))
}

/// The text of every `<text>` element of an SVG.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| t.split_once('>').map(|(_, rest)| rest))
        .map(|rest| {
            rest.split("</text>")
                .next()
                .unwrap_or("")
                .trim()
                .to_string()
        })
        .collect()
}

#[test]
fn linkage_plot_labels_its_axes_with_units_and_draws_a_smooth_png_of_the_size_asked() {
    let dir = scratch("plot-labels");
    let csv = dir.join("fourbar.csv");
    let (code, _, err) = run(&[
        "simulate",
        &example(),
        "--end",
        "1",
        "--steps",
        "50",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let svg = dir.join("forces.svg");
    let (code, _, err) = run(&[
        "plot",
        csv.to_str().unwrap(),
        "--columns",
        "crank_pivot.fx,crank_pivot.fy",
        "--out",
        svg.to_str().unwrap(),
        "--width",
        "640",
        "--height",
        "400",
        "--line-width",
        "3",
    ]);
    assert_eq!(code, 0, "{err}");
    let text = read(&svg);
    assert!(text.contains("width=\"640\" height=\"400\""), "{text:.300}");
    let labels = svg_texts(&text);
    assert!(labels.iter().any(|t| t == "time [s]"), "{labels:?}");
    assert!(
        labels
            .iter()
            .any(|t| t == "crank_pivot.fx, crank_pivot.fy [N]"),
        "{labels:?}"
    );
    assert!(text.contains("stroke-width=\"3\""), "line width");
    // The PNG: the size asked, and anti-aliased: the lines' edges are blends of the line
    // colour and the white background, so far more colours than the six lines, the grid and
    // the text would have without it.
    let png = dir.join("forces.png");
    let (code, _, err) = run(&[
        "plot",
        csv.to_str().unwrap(),
        "--columns",
        "crank_pivot.fx,crank_pivot.fy",
        "--out",
        png.to_str().unwrap(),
        "--width",
        "640",
        "--height",
        "400",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(png_size(&std::fs::read(&png).unwrap()), (640, 400));
    let colours = decode_png_colours(&png);
    assert!(colours > 300, "{colours} colours");
    // A .req column by the name `compare` gives it, and by its short form: the spring-mass
    // example's REQUEST/1 written by a command file.
    std::fs::copy(
        root().join("examples/spring_mass.adm"),
        dir.join("spring_mass.adm"),
    )
    .unwrap();
    let acf = dir.join("sm.acf");
    std::fs::write(
        &acf,
        "spring_mass\nsm\nSIMULATE/DYNAMIC, END = 1, STEPS = 10\nSTOP\n",
    )
    .unwrap();
    let (code, out, err) = run(&[
        "run",
        acf.to_str().unwrap(),
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let req = dir.join("sm.req");
    for column in ["REQUEST_1.x", "1.x"] {
        let (code, _, err) = run(&[
            "plot",
            req.to_str().unwrap(),
            "--columns",
            column,
            "--out",
            svg.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{column}: {err}");
        let labels = svg_texts(&read(&svg));
        assert!(
            labels
                .iter()
                .any(|t| t == "REQUEST_1.x [no unit in the file]"),
            "{labels:?}"
        );
    }
}

#[test]
fn linkage_plot_writes_an_svg_and_a_png_of_csv_columns() {
    let dir = scratch("plot");
    let csv = dir.join("fourbar.csv");
    let (code, _, err) = run(&[
        "simulate",
        &example(),
        "--end",
        "1",
        "--steps",
        "50",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let svg = dir.join("plot.svg");
    let (code, _, err) = run(&[
        "plot",
        csv.to_str().unwrap(),
        "--columns",
        "crank.x,crank.y",
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = read(&svg);
    assert!(
        text.starts_with("<svg") && text.trim_end().ends_with("</svg>"),
        "{text:.200}"
    );
    assert!(
        text.contains("crank.x") && text.contains("crank.y"),
        "legend"
    );
    // A line per column.
    assert!(text.matches("<polyline").count() >= 2);
    let png = dir.join("plot.png");
    let (code, _, err) = run(&[
        "plot",
        csv.to_str().unwrap(),
        "--columns",
        "crank.psi",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(png_size(&bytes), (960, 540));
    // Not one colour: the decoded image has the white background and the drawn line.
    let decoded = decode_png_colours(&png);
    assert!(decoded > 2, "{decoded} colours");
    // A column the file does not have is an input error naming it.
    let (code, _, err) = run(&[
        "plot",
        csv.to_str().unwrap(),
        "--columns",
        "nope.x",
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("no column 'nope.x'"), "{err}");
    // Columns of different units are refused, naming each column's unit.
    let (code, _, err) = run(&[
        "plot",
        csv.to_str().unwrap(),
        "--columns",
        "crank_pivot.fy,crank.wz",
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("crank_pivot.fy [N], crank.wz [rad/s]: the columns have different units"),
        "{err}"
    );
    // The input is never the output.
    let (code, _, _) = run(&[
        "plot",
        csv.to_str().unwrap(),
        "--columns",
        "crank.x",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
}

/// Distinct RGB colours of a PNG (decoded; 8-bit RGB or RGBA).
fn decode_png_colours(path: &Path) -> usize {
    let decoder = png::Decoder::new(std::fs::File::open(path).expect("png"));
    let mut reader = decoder.read_info().expect("png header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("png data");
    let channels = info.color_type.samples();
    assert!(
        channels >= 3 && info.bit_depth == png::BitDepth::Eight,
        "{info:?}"
    );
    let colours: std::collections::HashSet<[u8; 3]> = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    colours.len()
}

/// `/usr/bin/chromium`, or `None` with a notice (a failure under `CI`, which installs it).
fn chromium() -> Option<PathBuf> {
    let path = PathBuf::from("/usr/bin/chromium");
    if path.exists() {
        return Some(path);
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "/usr/bin/chromium is missing under CI (.ci/run installs it)"
    );
    eprintln!("notice: /usr/bin/chromium is absent; browser test skipped");
    None
}

/// Chromium headless on `page` with `extra` arguments; its standard output.
fn headless(browser: &Path, profile: &Path, extra: &[&str], page: &Path) -> String {
    headless_at(browser, profile, extra, page, "")
}

/// [`headless`] on `page` with the address fragment `fragment` (`#paused&frame=3`).
fn headless_at(
    browser: &Path,
    profile: &Path,
    extra: &[&str],
    page: &Path,
    fragment: &str,
) -> String {
    let url = format!(
        "file://{}{fragment}",
        page.canonicalize().unwrap().display()
    );
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-dev-shm-usage",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(url)
        .output()
        .expect("chromium runs");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The text of the page's hidden `#status` element in a DOM dump.
fn status_of(dom: &str) -> String {
    dom.split("<div id=\"status\" hidden=\"\">")
        .nth(1)
        .and_then(|s| s.split("</div>").next())
        .unwrap_or_else(|| panic!("no status element in the DOM: {dom:.500}"))
        .to_string()
}

/// The number after `key=` in a status text.
fn status_number(status: &str, key: &str) -> Option<f64> {
    status
        .split_whitespace()
        .find_map(|w| w.strip_prefix(&format!("{key}=")))
        .and_then(|v| v.parse().ok())
}

/// The x of the first plot's time cursor and whether it is shown, in a DOM dump.
fn first_cursor(dom: &str) -> (f64, bool) {
    let line = dom
        .split("<line class=\"cursor\"")
        .nth(1)
        .and_then(|s| s.split('>').next())
        .unwrap_or_else(|| panic!("no time cursor in the DOM"));
    let attr = |name: &str| {
        line.split(&format!(" {name}=\""))
            .nth(1)
            .and_then(|v| v.split('"').next())
            .unwrap_or_else(|| panic!("no {name} in {line}"))
            .to_string()
    };
    (attr("x1").parse().unwrap(), attr("visibility") == "visible")
}

#[test]
fn every_page_kind_opens_with_its_verdict_and_its_plots_follow_the_time_slider() {
    let Some(browser) = chromium() else {
        return;
    };
    let dir = scratch("kinds");
    let ex = example();
    let pendulum = root().join("mechanisms/pendulum.adm");
    // The pendulum with gravity reversed: it hangs in an unstable equilibrium, so the
    // quasi-static series fails with its error (exit 1) and still has its plots.
    let inverted = dir.join("inverted.adm");
    let text = read(&pendulum);
    assert!(text.contains("JGRAV = -9.80665"));
    std::fs::write(
        &inverted,
        text.replace("JGRAV = -9.80665", "JGRAV = 9.80665"),
    )
    .unwrap();
    let acf = root().join("examples/fourbar.acf");
    let out_dir = dir.display().to_string();
    // (name, arguments, exit code, verdict class, whether the page has plots against time)
    let kinds: Vec<(&str, Vec<String>, u8, &str, bool)> = vec![
        ("verify", vec!["verify".into(), ex.clone()], 0, "ok", false),
        ("ic", vec!["ic".into(), ex.clone()], 0, "ok", false),
        (
            "linear",
            vec!["linear".into(), pendulum.display().to_string()],
            0,
            "ok",
            false,
        ),
        (
            "simulate",
            vec![
                "simulate".into(),
                ex.clone(),
                "--end".into(),
                "1".into(),
                "--steps".into(),
                "20".into(),
            ],
            0,
            "ok",
            true,
        ),
        (
            "series",
            vec![
                "static".into(),
                ex.clone(),
                "--end".into(),
                "1".into(),
                "--steps".into(),
                "4".into(),
            ],
            0,
            "ok",
            true,
        ),
        (
            "unstable",
            vec![
                "static".into(),
                inverted.display().to_string(),
                "--end".into(),
                "1".into(),
                "--steps".into(),
                "4".into(),
            ],
            1,
            "failed",
            true,
        ),
        (
            "run",
            vec![
                "run".into(),
                acf.display().to_string(),
                "--out-dir".into(),
                out_dir.clone(),
            ],
            0,
            "ok",
            true,
        ),
    ];
    for (name, mut args, code, class, timed) in kinds {
        let page = dir.join(format!("{name}.html"));
        args.push("--html".into());
        args.push(page.display().to_string());
        let argv: Vec<&str> = args.iter().map(String::as_str).collect();
        let (got, out, err) = run(&argv);
        assert_eq!(got, i32::from(code), "{name}: {out}{err}");
        let html = read(&page);
        // The verdict comes first, in words, with the errors; no debug line is shown.
        let verdict = html
            .find("<section id=\"verdict\"")
            .unwrap_or_else(|| panic!("{name}: no verdict"));
        assert!(
            html[verdict..].starts_with(&format!(
                "<section id=\"verdict\" class=\"verdict {class}\">"
            )),
            "{name}: {}",
            &html[verdict..verdict + 200]
        );
        assert!(verdict < html.find("<canvas").unwrap(), "{name}");
        if class == "failed" {
            let errors = &html[verdict..html[verdict..].find("</section>").unwrap() + verdict];
            assert!(errors.contains("FAILED"), "{name}: {errors}");
            assert!(
                errors.contains("<li>the equilibrium at time 0 is UNSTABLE"),
                "{name}: {errors}"
            );
        }
        let profile = dir.join(format!("profile-{name}"));
        let first = headless_at(
            &browser,
            &profile,
            &["--dump-dom"],
            &page,
            "#paused&frame=0",
        );
        let status = status_of(&first);
        assert!(status.starts_with("ok frames="), "{name}: {status}");
        // Laid out by the browser: the verdict's box ends above the first plot.
        let bottom = status_number(&status, "verdict_bottom").expect("verdict_bottom");
        match status_number(&status, "first_plot_top") {
            Some(top) => assert!(bottom < top, "{name}: {status}"),
            None => assert!(!timed, "{name}: no plot: {status}"),
        }
        if !timed {
            continue;
        }
        // The slider at the first output puts the cursor on the plots' left edge, at the
        // last output on their right edge (every plot spans the run's times: x from 70 to
        // 70 + 438 in the SVG's units).
        let frames = status_number(&status, "frames").unwrap() as usize;
        assert_eq!(first_cursor(&first), (70.0, true), "{name}");
        let last = headless_at(
            &browser,
            &profile,
            &["--dump-dom"],
            &page,
            &format!("#paused&frame={}", frames - 1),
        );
        assert_eq!(first_cursor(&last), (508.0, true), "{name}");
        assert_eq!(
            status_number(&status_of(&last), "cursor"),
            Some(508.0),
            "{name}"
        );
        // Half-way through the run (the simulate page: 21 outputs over a second, frame 10 at
        // t = 0.5) the cursor is half-way along the axis.
        if name == "simulate" {
            let mid = headless_at(
                &browser,
                &profile,
                &["--dump-dom"],
                &page,
                "#paused&frame=10",
            );
            assert_eq!(first_cursor(&mid), (289.0, true), "{name}");
        }
    }
}

#[test]
fn the_page_runs_in_a_browser_and_its_3d_view_draws_the_mechanism() {
    let Some(browser) = chromium() else {
        return;
    };
    let dir = scratch("browser");
    let page = dir.join("fourbar.html");
    let (code, _, err) = run(&[
        "simulate",
        &example(),
        "--end",
        "1",
        "--steps",
        "100",
        "--html",
        page.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let dom = headless_at(
        &browser,
        &dir.join("profile"),
        &["--dump-dom"],
        &page,
        "#paused",
    );
    let status = status_of(&dom);
    let status = status.as_str();
    // "ok frames=101 items=9 triangles=… drawn_pixels=N": the scripts ran without error.
    assert!(status.starts_with("ok frames=101 items=9 "), "{status}");
    let pixels =
        status_number(status, "drawn_pixels").unwrap_or_else(|| panic!("{status}")) as usize;
    // The four-bar spans a good part of the 900 × 520 canvas: thousands of pixels, far
    // from all of them.
    assert!((2_000..200_000).contains(&pixels), "{status}");
    // The screenshot of the page is a real image, not a blank one.
    let shot = dir.join("shot.png");
    headless(
        &browser,
        &dir.join("profile"),
        &[
            "--window-size=1000,800",
            &format!("--screenshot={}", shot.display()),
        ],
        &page,
    );
    let bytes = std::fs::read(&shot).expect("a screenshot");
    assert_eq!(png_size(&bytes), (1000, 800));
    assert!(
        decode_png_colours(&shot) > 16,
        "the screenshot is not uniform"
    );
}

#[test]
fn a_graphic_on_an_unknown_marker_is_a_warning_and_changes_no_result() {
    let dir = scratch("bad-graphic");
    let text = read(&root().join("examples/fourbar.adm")).replace(", CM = 304", ", CM = 9304");
    let bad = dir.join("bad.adm");
    std::fs::write(&bad, &text).unwrap();
    let line = text
        .lines()
        .position(|l| l.contains("CM = 9304"))
        .expect("the edited line")
        + 1;
    let (code, out, err) = run(&["verify", bad.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    let all = format!("{out}{err}");
    assert!(
        all.contains(&format!(
            "bad.adm:{line}:8: warning: GRAPHICS/3 refers to MARKER/9304"
        )),
        "{all}"
    );
    // The same run as the bundled example: the crank ends at 90°.
    let (code, v) = json(&[
        "simulate",
        bad.to_str().unwrap(),
        "--end",
        "1",
        "--steps",
        "10",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    let crank = &v["final_state"][0];
    assert!(
        (crank["reuler"][0].as_f64().unwrap() - 90.0).abs() < 1e-9,
        "{crank}"
    );
}

#[test]
fn corpus_graphics_are_all_drawn() {
    let Some(corpus) = corpus() else {
        return;
    };
    // A two-robot formation: 118 GRAPHICS (1 BOX, 108 EXTERNAL, 9 dynamic FORCE graphics);
    // every one is typed and attached, none is warned about.
    let model = corpus.join(
        "baqumau__Mechatronics-baqumau__Robotics__Mobile_Robots__3WD_OMR_Formations__\
         Dynamics_and_Control-ADAMS_and_MATLAB__twoRobotsPlant_1_v2020.adm",
    );
    let dir = scratch("corpus");
    let page = dir.join("robots.html");
    let (_, out, err) = run(&[
        "verify",
        model.to_str().unwrap(),
        "--html",
        page.to_str().unwrap(),
    ]);
    // (The CONTACTs on its Parasolid files name their GRAPHICS; nothing else does.)
    let all = format!("{out}{err}");
    assert!(
        !all.lines()
            .any(|l| l.contains("GRAPHICS") && !l.contains("CONTACT")),
        "{all}"
    );
    let html = read(&page);
    assert_self_contained(&html);
    // Each EXTERNAL is its marker's triad (its x axis in red), the box a solid of 12
    // triangles.
    assert_eq!(html.matches("\"c\":[220,40,40]").count(), 108);
    assert!(html.contains("\"n\":\"BOX_360\""));
    assert!(html.contains("EXTERNAL geometry drawn as its marker's triad"));
}

#[test]
fn plot_picks_the_columns_of_a_simulate_page() {
    let dir = scratch("pick");
    let page = dir.join("picked.html");
    let (code, _, err) = run(&[
        "simulate",
        &example(),
        "--end",
        "1",
        "--steps",
        "20",
        "--html",
        page.to_str().unwrap(),
        "--plot",
        "crank.x,crank_pivot.fy",
    ]);
    assert_eq!(code, 0, "{err}");
    let html = read(&page);
    assert!(
        html.contains("class=\"pt\">crank.x<") && html.contains("class=\"pt\">crank_pivot.fy<")
    );
    assert_eq!(polyline_points(&html), [21, 21]);
    // An unknown column is an input error before the run.
    let (code, _, err) = run(&[
        "simulate",
        &example(),
        "--end",
        "1",
        "--html",
        page.to_str().unwrap(),
        "--plot",
        "crank.q",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--plot crank.q: no such column"), "{err}");
}

#[test]
fn a_windshield_over_the_wiper_starts_transparent_and_the_view_frames_the_mechanism() {
    let (Some(browser), Some(corpus)) = (chromium(), corpus()) else {
        return;
    };
    let dir = scratch("framing");
    // The wiper: a 2.5 m × 1.7 m windshield BOX over the linkage; the four-bar example: no
    // solid as large as its scene.
    let wiper = corpus
        .join("Dinh-Hao-Nguyen__MSCAdams_Wiper_Project__ControlSimulink__Controls_Plant_5.adm");
    let fast = corpus.join("old-NWTC__FAST__CertTest__Old_Adams_files__Test02_ADAMS.adm");
    for (name, model, transparent) in [
        ("wiper", wiper, 1),
        ("turbine", fast, 0),
        ("fourbar", root().join("examples/fourbar.adm"), 0),
    ] {
        let page = dir.join(format!("{name}.html"));
        run(&[
            "verify",
            model.to_str().unwrap(),
            "--html",
            page.to_str().unwrap(),
        ]);
        let dom = headless_at(
            &browser,
            &dir.join(format!("profile-{name}")),
            &["--dump-dom"],
            &page,
            "#paused",
        );
        let status = status_of(&dom);
        assert_eq!(
            status_number(&status, "transparent"),
            Some(transparent as f64),
            "{name}: {status}"
        );
        // Framed: the mechanism fills a good part of the 900 × 520 canvas.
        let pixels = status_number(&status, "drawn_pixels").unwrap();
        assert!(pixels > 5_000.0, "{name}: {status}");
    }
}

#[test]
fn clicking_a_part_s_entry_in_the_list_hides_it_in_the_3d_view() {
    let Some(browser) = chromium() else {
        return;
    };
    let dir = scratch("hide");
    let page = dir.join("fourbar.html");
    let (code, _, err) = run(&[
        "verify",
        root().join("examples/fourbar.adm").to_str().unwrap(),
        "--html",
        page.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let status = |fragment: &str, profile: &str| {
        let dom = headless_at(
            &browser,
            &dir.join(profile),
            &["--dump-dom"],
            &page,
            fragment,
        );
        status_of(&dom)
    };
    let all = status("#paused", "profile-all");
    let drawn = status_number(&all, "drawn_pixels").unwrap_or_else(|| panic!("{all}"));
    assert_eq!(status_number(&all, "hidden"), None, "{all}");
    // The crank's entry clicked: its graphics are hidden, the view draws fewer pixels.
    let hidden = status("#paused&hide=crank", "profile-hide");
    assert!(hidden.starts_with("ok "), "{hidden}");
    let items = status_number(&hidden, "hidden").unwrap_or_else(|| panic!("{hidden}"));
    assert!(items >= 1.0, "{hidden}");
    let left = status_number(&hidden, "drawn_pixels").unwrap();
    assert!(
        left < drawn - 100.0,
        "{drawn} pixels before, {left} after: {hidden}"
    );
    // An entry that is not a part hides nothing.
    let none = status("#paused&hide=no_such_part", "profile-none");
    assert_eq!(status_number(&none, "hidden"), Some(0.0), "{none}");
    assert_eq!(status_number(&none, "drawn_pixels"), Some(drawn), "{none}");
}
