//! Progress of a run on stderr: communication steps, simulated time / stop time, real-time
//! factor (simulated time / wall time), time left.
//!
//! Shown once a run has taken longer than [`DELAY`], and only when stderr is a terminal (an
//! indicatif bar), so pipes, tests and CI logs stay clean. `--progress` shows it from the start,
//! and where stderr is not a terminal as one plain line a second and a last line at the end.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long a run stays silent before the bar appears.
pub const DELAY: Duration = Duration::from_secs(1);

/// Update interval of the bar's message.
const TICK: Duration = Duration::from_millis(100);

/// Interval of the plain lines.
const LINE_EVERY: Duration = Duration::from_secs(1);

enum Shown {
    Nothing,
    Bar(ProgressBar),
    /// Plain lines; when the last one was written.
    Lines(Instant),
}

pub struct Progress {
    shown: Shown,
    force: bool,
    /// The delayed check for a terminal was made.
    looked: bool,
    start: Instant,
    last: Instant,
    stop: f64,
    total: u64,
}

impl Progress {
    /// A run to `stop` [s] of about `total` communication steps; `force` is `--progress`.
    pub fn new(force: bool, stop: f64, total: u64) -> Self {
        let now = Instant::now();
        let mut p = Self {
            shown: Shown::Nothing,
            force,
            looked: force,
            start: now,
            last: now,
            stop,
            total,
        };
        if force {
            p.show(0.0, 0);
        }
        p
    }

    fn show(&mut self, t: f64, steps: u64) {
        if std::io::stderr().is_terminal() {
            let style = ProgressStyle::with_template("[{elapsed_precise}] {wide_bar} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar());
            let bar = ProgressBar::hidden()
                .with_style(style)
                .with_elapsed(self.start.elapsed())
                .with_position(steps)
                .with_message(self.message(t, steps));
            bar.set_length(self.total.max(1));
            bar.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = Shown::Bar(bar);
        } else if self.force {
            eprintln!("progress: {}", self.message(t, steps));
            self.shown = Shown::Lines(Instant::now());
        }
    }

    fn message(&self, t: f64, steps: u64) -> String {
        let wall = self.start.elapsed().as_secs_f64();
        let rtf = if wall > 0.0 { t / wall } else { 0.0 };
        let left = if rtf > 0.0 && t < self.stop {
            format!(", ~{:.0} s left", (self.stop - t) / rtf)
        } else {
            String::new()
        };
        format!(
            "{steps}/{} steps, t = {t:.2}/{} s, {rtf:.3}x real time{left}",
            self.total, self.stop
        )
    }

    /// After communication step `steps` ending at `t` [s]. Cheap when nothing is shown.
    pub fn update(&mut self, t: f64, steps: u64) {
        let now = Instant::now();
        if now.duration_since(self.last) < TICK {
            return;
        }
        self.last = now;
        if !self.looked && now.duration_since(self.start) >= DELAY {
            self.looked = true;
            self.show(t, steps);
        }
        if matches!(self.shown, Shown::Nothing) {
            return;
        }
        let msg = self.message(t, steps);
        match &mut self.shown {
            Shown::Nothing => {}
            Shown::Bar(bar) => {
                bar.set_position(steps);
                bar.set_message(msg);
            }
            Shown::Lines(at) => {
                if now.duration_since(*at) >= LINE_EVERY {
                    *at = now;
                    eprintln!("progress: {msg}");
                }
            }
        }
    }

    /// The final state: left on screen after a success, frozen at the failure otherwise.
    pub fn finish(&mut self, t: f64, steps: u64, ok: bool) {
        self.total = if ok { steps } else { self.total };
        let msg = self.message(t, steps);
        let msg = if ok { msg } else { format!("{msg}, stopped") };
        match std::mem::replace(&mut self.shown, Shown::Nothing) {
            Shown::Nothing => {}
            Shown::Bar(bar) => {
                bar.set_length(self.total.max(1));
                bar.set_position(steps);
                if ok {
                    bar.finish_with_message(msg);
                } else {
                    bar.abandon_with_message(msg);
                }
                eprintln!(); // the bar stays; what follows starts on a line of its own
            }
            Shown::Lines(_) => eprintln!("progress: {msg}"),
        }
    }
}
