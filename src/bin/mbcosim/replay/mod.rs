//! `simulate --replay`: a self-contained HTML page that animates the run in 3D (docs/replay.md).
//!
//! [`Recorder`] takes one [`mbcosim::scene::CoSimModel::snapshot`] per output point (the CSV's
//! rows) and encodes it at once ([`frames`]); at the end [`page`] writes the HTML with three.js
//! ([`three`], read at run time from the source tree's tools/replay) and the viewer inline.

mod frames;
mod json;
mod page;
mod three;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use mbcosim::scene::CoSimModel;

pub use three::{fetch as fetch_three, three};

/// Snapshots of a run, for its replay page.
pub struct Recorder {
    path: PathBuf,
    frames: frames::Frames,
    /// Time spent taking and encoding snapshots.
    spent: Duration,
}

impl Recorder {
    /// A recorder for the page `path`; `Err` (with what to do) when three.js is not installed,
    /// checked before the run starts.
    pub fn new(path: &Path) -> Result<Self, String> {
        three()?;
        Ok(Recorder {
            path: path.to_path_buf(),
            frames: frames::Frames::default(),
            spent: Duration::ZERO,
        })
    }

    /// Takes the model's snapshot now; `Err` if the model draws nothing.
    pub fn record(&mut self, m: &mut dyn CoSimModel) -> Result<(), String> {
        let start = Instant::now();
        let snap = m.snapshot().ok_or_else(|| {
            format!(
                "--replay: {} has no 3D scene to draw (PanelLock and RopeBlock have)",
                m.info().identifier
            )
        })?;
        self.frames.push(&snap);
        self.spent += start.elapsed();
        Ok(())
    }

    /// Number of frames recorded.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Wall time spent in snapshots and their encoding so far.
    pub fn spent(&self) -> Duration {
        self.spent
    }

    /// Writes the page (parent folders are created); returns its size [bytes].
    pub fn write(&self, model: &str) -> Result<usize, String> {
        let three = three()?;
        let title = format!("{model} replay: {} frames", self.frames.len());
        let html = page::page(&title, &self.frames.document(model, &three.version), three)?;
        let p = &self.path;
        if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
        std::fs::write(p, &html).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
        Ok(html.len())
    }
}
