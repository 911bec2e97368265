//! Progress of a run on stderr (indicatif): simulated time / stop time, real-time factor, steps.
//!
//! Shown once a run has taken longer than [`DELAY`] and only when stderr is a terminal, so tests
//! and CI logs stay clean; `--progress` shows it from the start, and where stderr is not a
//! terminal as one plain line per second.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle, TermLike};

/// How long a run stays silent before the bar appears.
pub const DELAY: Duration = Duration::from_secs(1);

/// Redraw interval of the message (the bar itself rate-limits drawing).
const TICK: Duration = Duration::from_millis(100);

pub struct Progress {
    bar: Option<ProgressBar>,
    force: bool,
    /// The delayed check for a terminal was made.
    looked: bool,
    start: Instant,
    last: Instant,
    stop: f64,
    total: u64,
}

/// A [`TermLike`] for a stderr that is not a terminal: every drawn state becomes one line.
#[derive(Debug, Default)]
struct LineLog {
    pending: Mutex<String>,
}

impl LineLog {
    fn emit(&self, tail: &str) -> std::io::Result<()> {
        let mut p = self.pending.lock().unwrap_or_else(|e| e.into_inner());
        p.push_str(tail);
        let line = p.replace('\r', "");
        p.clear();
        if !line.trim().is_empty() {
            writeln!(std::io::stderr(), "{}", line.trim_end())?;
        }
        Ok(())
    }
}

impl TermLike for LineLog {
    fn width(&self) -> u16 {
        100
    }
    fn move_cursor_up(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_down(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_right(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_left(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn write_line(&self, s: &str) -> std::io::Result<()> {
        self.emit(s)
    }
    fn write_str(&self, s: &str) -> std::io::Result<()> {
        self.pending
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push_str(s);
        Ok(())
    }
    fn clear_line(&self) -> std::io::Result<()> {
        self.pending
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        Ok(())
    }
    fn flush(&self) -> std::io::Result<()> {
        self.emit("")
    }
}

impl Progress {
    /// A run to `stop` [s] of about `total` communication steps; `force` is `--progress`.
    pub fn new(force: bool, stop: f64, total: u64) -> Self {
        let now = Instant::now();
        let mut p = Self {
            bar: None,
            force,
            looked: force,
            start: now,
            last: now,
            stop,
            total,
        };
        if force {
            p.show();
        }
        p
    }

    fn show(&mut self) {
        let target = if std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr()
        } else if self.force {
            ProgressDrawTarget::term_like_with_hz(Box::<LineLog>::default(), 1)
        } else {
            return;
        };
        let bar = ProgressBar::with_draw_target(Some(self.total), target);
        let style = ProgressStyle::with_template(
            "[{elapsed_precise}] {wide_bar} {pos}/{len} steps, {msg}, ETA {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar());
        bar.set_style(style);
        bar.set_message(self.message(0.0));
        self.bar = Some(bar);
    }

    fn message(&self, t: f64) -> String {
        let wall = self.start.elapsed().as_secs_f64();
        let rtf = if wall > 0.0 { t / wall } else { 0.0 };
        format!("t = {t:.4}/{} s, real-time factor {rtf:.3}", self.stop)
    }

    /// After communication step `steps` ending at `t` [s]. Cheap when nothing is drawn.
    pub fn update(&mut self, t: f64, steps: u64) {
        let now = Instant::now();
        if now.duration_since(self.last) < TICK {
            return;
        }
        self.last = now;
        if !self.looked && now.duration_since(self.start) >= DELAY {
            self.looked = true;
            self.show();
        }
        if let Some(bar) = &self.bar {
            bar.set_position(steps);
            bar.set_message(self.message(t));
        }
    }

    /// The final state: left on screen after a success, frozen at the failure otherwise.
    pub fn finish(&mut self, t: f64, steps: u64, ok: bool) {
        if let Some(bar) = self.bar.take() {
            let msg = self.message(t);
            if ok {
                bar.set_length(steps);
                bar.set_position(steps);
                bar.finish_with_message(msg);
            } else {
                bar.set_position(steps);
                bar.abandon_with_message(format!("{msg}, stopped"));
            }
        }
    }
}
