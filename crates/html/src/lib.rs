//! # linkage-html — one self-contained HTML page per analysis
//!
//! A page opens with the verdict of the analysis in words and every error ([`verdict`]),
//! then holds the analysis report as tables (the JSON structures of `linkage-report`,
//! serialised, with units), inline SVG plots of the run, and a 3-D view of the mechanism
//! drawn by a small canvas renderer of its own (`viewer.js`, inline): the GRAPHICS of the
//! dataset tessellated here in Rust ([`mesh`], [`scene`]), joint symbols, part poses animated
//! over the run with play/pause, a time slider and orbit/zoom. Every script, style and datum
//! is inline: the page opens offline and refers to nothing on a network.
//!
//! ```text
//! Model ──scene──▶ meshes on bodies ─┐
//! run outputs ──history──▶ frames ───┼──page──▶ HTML (tables · SVG · canvas viewer)
//! report JSON ──tables───────────────┘
//! ```
//!
//! Nothing here computes physics: poses, reactions and values come from the analyses.

pub mod history;
pub mod mesh;
pub mod page;
pub mod scene;
pub mod series;
pub mod svg;
pub mod tables;
pub mod text;
pub mod verdict;

pub use page::{render, Page};

use std::io::Write;
use std::path::Path;

/// Writes `page` to `path` through a temporary file in the same folder and a rename, so that
/// a reader never sees half a page and a failed write leaves any older file whole.
pub fn write_page(page: &Page, path: &Path) -> std::io::Result<()> {
    write_atomically(path, render(page).as_bytes())
}

/// Writes `bytes` to `path` by a temporary file beside it and a rename.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "page".into());
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
