//! `simulate`: one native run of a registered model, outputs as CSV.
//!
//! Call sequence (the same as fmpy's `simulate_fmu`, so results agree bit for bit with the FMU):
//! scene file, `--set` values and the schedule's rows at `t = 0` before initialization; then at
//! every communication point of [`Grid`] the schedule's inputs, one `do_step`, one CSV row.
//! Rows are written as the run goes: a run that fails leaves every row up to the failure.
//! `--replay` takes a 3D snapshot at every row and writes the replay page at the end (also after
//! a failure, with the frames up to it).

use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use mbcosim::scene::CoSimModel;
use mbcosim::scene::native::Grid;
use mbcosim::scene::port::{Causality, ModelInfo, PortSpec, PortType};
use mbcosim::scene::scene_file;

use crate::models;
use crate::progress::Progress;
use crate::replay::Recorder;
use crate::schedule::Schedule;
use crate::values;

/// How the CSV header names the columns.
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Header {
    /// `time [s]`, `name [unit]` (no brackets for dimensionless variables).
    Units,
    /// Bare variable names, as in the model description.
    Names,
}

#[derive(clap::Args)]
#[command(after_help = "\
Values (--set, --inputs) follow each variable's declared type: Real a finite number within its \
min/max; Integer a whole number (10 or 10.0, not 10.5); Boolean true/false/1/0; Enumeration an \
item name (case ignored) or its number; String the text as is. `mbcosim variables <MODEL>` lists \
the names, types, units and ranges.

CSV: one row per communication point; reals in shortest round-trip form, integers and \
enumerations as integers, booleans as 0/1. Paths are relative to the current directory.

Examples:
  mbcosim simulate PidController --stop 2 --step 0.01 --set setpoint=1 --set kp=2
  mbcosim simulate PanelLock --set contact_law=hertz --outputs hinge0_angle,tip_normal_velocity --out run.csv
  mbcosim simulate PidController --inputs schedule.csv --stop 5   # schedule.csv: time,setpoint
  mbcosim simulate RopeBlock --stop 4 --set hook0_vz=0.5 --out lift.csv --replay lift.html   # 3D page")]
pub struct SimulateArgs {
    /// Model identifier, case ignored (`mbcosim models` lists them).
    #[arg(value_parser = models::parser(), ignore_case = true)]
    model: String,
    /// Stop time [s] (default: the model's default stop time).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    stop: Option<f64>,
    /// Communication step [s] (default: the model's default step); the last step is shortened to
    /// land on the stop time.
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    step: Option<f64>,
    /// Scene file (TOML, see resources/scenes/) applied before the --set values.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Set a parameter or input before initialization, typed by the variable table; repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
    /// Input schedule: CSV with a `time` column [s] and one column per input; each input takes
    /// the value of the last row with time <= t at every communication point t.
    #[arg(long, value_name = "FILE")]
    inputs: Option<PathBuf>,
    /// Output columns to write, comma-separated, in this order (default: every output).
    #[arg(long, value_name = "NAME,...", value_delimiter = ',')]
    outputs: Vec<String>,
    /// CSV file to write (parent folders are created); default: standard output.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Header style of the CSV.
    #[arg(long, value_enum, default_value_t = Header::Units)]
    header: Header,
    /// Also write a self-contained HTML page that animates the run in 3D (one frame per CSV
    /// row; play/pause, scrub, `#t=SECONDS` in the URL shows a time); PanelLock and RopeBlock.
    #[arg(long, value_name = "FILE.html")]
    replay: Option<PathBuf>,
    /// Print the wall time of the run to stderr.
    #[arg(long)]
    timing: bool,
    /// Show progress from the start, also when stderr is not a terminal (one line a second);
    /// without it progress appears after a second, on a terminal only.
    #[arg(long)]
    progress: bool,
}

/// The output columns: `--outputs` in its order, or every non-string output in table order.
fn select_outputs(
    info: &'static ModelInfo,
    wanted: &[String],
) -> Result<Vec<&'static PortSpec>, String> {
    let all: Vec<&'static PortSpec> = info
        .ports
        .iter()
        .filter(|p| p.causality == Causality::Output && !matches!(p.ty, PortType::String { .. }))
        .collect();
    if wanted.is_empty() {
        return Ok(all);
    }
    let names: Vec<&str> = all.iter().map(|p| p.name.as_str()).collect();
    let mut chosen: Vec<&'static PortSpec> = Vec::new();
    for w in wanted.iter().map(|w| w.trim()) {
        if w == "time" {
            continue; // always the first column
        }
        if w.is_empty() {
            return Err("--outputs: an empty name (two commas in a row?)".into());
        }
        let p = all.iter().find(|p| p.name == w).ok_or_else(|| {
            let why = match info.port_by_name(w) {
                Some(p) => format!(
                    "is {} of {}, not an output",
                    p.causality.name(),
                    info.identifier
                ),
                None => format!("is not an output of {}", info.identifier),
            };
            let list = if names.len() <= 12 {
                format!(" (outputs: {})", names.join(", "))
            } else {
                format!(
                    " (`mbcosim variables {} --causality output` lists all {})",
                    info.identifier,
                    names.len()
                )
            };
            format!(
                "--outputs: `{w}` {why}{}{list}",
                values::did_you_mean(w, &names)
            )
        })?;
        if chosen.iter().any(|c| c.name == p.name) {
            return Err(format!("--outputs: `{w}` is named twice"));
        }
        chosen.push(p);
    }
    if chosen.is_empty() {
        return Err("--outputs names no output".into());
    }
    Ok(chosen)
}

fn header_line(columns: &[&PortSpec], style: Header) -> String {
    let cell = |name: &str, unit: Option<&str>| match (style, unit) {
        (Header::Units, Some(u)) => format!("{name} [{u}]"),
        _ => name.to_string(),
    };
    let mut cells = vec![cell("time", Some("s"))];
    cells.extend(columns.iter().map(|p| cell(&p.name, p.unit)));
    cells.join(",")
}

/// Why a run stopped early.
enum Stop {
    /// The model (or the schedule's value) refused: its message.
    Model(String),
    /// The CSV could not be written.
    Io(std::io::Error),
    /// The replay snapshot could not be taken (a model that draws nothing).
    Replay(String),
}

impl From<String> for Stop {
    fn from(e: String) -> Self {
        Stop::Model(e)
    }
}

/// One CSV row at time `t`: reals shortest round-trip, integers bare, booleans 0/1.
fn write_row(
    out: &mut dyn Write,
    t: f64,
    m: &dyn CoSimModel,
    columns: &[&PortSpec],
) -> Result<(), Stop> {
    let mut line = format!("{t:?}");
    for p in columns {
        let cell = match &p.ty {
            PortType::Real { .. } => format!(
                "{:?}",
                m.get_real(p.vr).map_err(|e| Stop::Model(e.to_string()))?
            ),
            PortType::Integer { .. } | PortType::Enumeration { .. } => m
                .get_integer(p.vr)
                .map_err(|e| Stop::Model(e.to_string()))?
                .to_string(),
            PortType::Boolean { .. } => u8::from(
                m.get_boolean(p.vr)
                    .map_err(|e| Stop::Model(e.to_string()))?,
            )
            .to_string(),
            PortType::String { .. } => continue,
        };
        line.push(',');
        line.push_str(&cell);
    }
    line.push('\n');
    out.write_all(line.as_bytes()).map_err(Stop::Io)
}

/// Where the run got to.
#[derive(Default)]
struct Reached {
    /// Time of the last row written [s].
    t: f64,
    /// Rows written.
    rows: u64,
    /// Communication steps done.
    steps: u64,
    initialized: bool,
}

struct Run<'a> {
    model: &'a mut dyn CoSimModel,
    schedule: Option<Schedule>,
    columns: Vec<&'static PortSpec>,
    out: Box<dyn Write + 'a>,
    progress: Progress,
    replay: Option<Recorder>,
}

impl Run<'_> {
    /// The replay frame of the row just written.
    fn record(&mut self) -> Result<(), Stop> {
        match &mut self.replay {
            Some(r) => r.record(self.model).map_err(Stop::Replay),
            None => Ok(()),
        }
    }

    fn go(&mut self, grid: Grid, at: &mut Reached) -> Result<(), Stop> {
        let mut last_flush = Instant::now();
        let mut points = grid;
        let t0 = points.next().unwrap_or(0.0);
        if let Some(s) = &mut self.schedule {
            s.apply_at(t0, self.model)?;
        }
        self.model.initialize(t0).map_err(|e| e.to_string())?;
        at.initialized = true;
        write_row(&mut self.out, t0, self.model, &self.columns)?;
        at.rows = 1;
        at.t = t0;
        self.record()?;
        for next in points {
            let t = at.t;
            if let Some(s) = &mut self.schedule {
                s.apply_at(t, self.model)?;
            }
            self.model
                .do_step(t, next - t)
                .map_err(|e| format!("in the step from t = {t} s to {next} s: {e}"))?;
            at.steps += 1;
            write_row(&mut self.out, next, self.model, &self.columns)?;
            at.rows += 1;
            at.t = next;
            self.record()?;
            self.progress.update(next, at.steps);
            if last_flush.elapsed() >= Duration::from_secs(1) {
                self.out.flush().map_err(Stop::Io)?;
                last_flush = Instant::now();
            }
        }
        Ok(())
    }
}

pub fn simulate(a: &SimulateArgs) -> Result<(), String> {
    let entry = models::entry(&a.model)?;
    let info = (entry.info)();
    let id = info.identifier;
    let stop = a.stop.unwrap_or(info.default_stop_time);
    let step = a.step.unwrap_or(info.default_step);
    let grid = Grid::new(stop, step).map_err(|e| e.to_string())?;
    let mut sets = Vec::new();
    for kv in &a.sets {
        let (port, value) = values::parse_set(info, kv)?;
        sets.push((kv, port, value));
    }
    let schedule = a
        .inputs
        .as_deref()
        .map(|p| Schedule::load(p, info))
        .transpose()?;
    let columns = select_outputs(info, &a.outputs)?;
    let replay = a.replay.as_deref().map(Recorder::new).transpose()?;

    let mut m = (entry.create)();
    if let Some(path) = &a.scene {
        scene_file::apply_file(m.as_mut(), path)?;
    }
    for (kv, port, value) in &sets {
        values::apply(m.as_mut(), port, value).map_err(|e| format!("--set {kv}: {e}"))?;
    }

    let (out, target): (Box<dyn Write>, String) = match &a.out {
        Some(p) => {
            if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir)
                    .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
            }
            let f = std::fs::File::create(p)
                .map_err(|e| format!("cannot write {}: {e}", p.display()))?;
            (Box::new(BufWriter::new(f)), p.display().to_string())
        }
        None => (
            Box::new(BufWriter::new(std::io::stdout().lock())),
            "standard output".to_string(),
        ),
    };
    let total = grid.steps_estimate();
    let mut run = Run {
        model: m.as_mut(),
        schedule,
        columns,
        out,
        progress: Progress::new(a.progress, stop, total),
        replay,
    };
    let header = header_line(&run.columns, a.header);
    writeln!(run.out, "{header}").map_err(|e| format!("cannot write {target}: {e}"))?;

    let wall = Instant::now();
    let mut at = Reached::default();
    let result = run.go(grid, &mut at);
    run.progress.finish(at.t, at.steps, result.is_ok());
    let flushed = run.out.flush();
    let wall = wall.elapsed();
    // the page of what ran, also after a failure (like the CSV's rows)
    let page = match &run.replay {
        Some(r) if r.len() > 0 => Some(r.write(id)),
        _ => None,
    };
    if a.timing {
        eprintln!(
            "timing: {} s wall for {} communication steps (initialization included)",
            wall.as_secs_f64(),
            at.steps
        );
        if let (Some(r), Some(Ok(bytes))) = (&run.replay, &page) {
            eprintln!(
                "timing: replay {} s for {} snapshots ({:.1} % of the run), page {bytes} bytes",
                r.spent().as_secs_f64(),
                r.len(),
                100.0 * r.spent().as_secs_f64() / wall.as_secs_f64().max(1e-12)
            );
        }
    }
    let page_error = match page {
        Some(Err(e)) => Some(e),
        _ => None,
    };
    // a reader that closed standard output (`| head`) has all it wanted: stop quietly
    let closed = |e: &std::io::Error| a.out.is_none() && e.kind() == std::io::ErrorKind::BrokenPipe;
    let outcome = match result {
        Ok(()) => match flushed {
            Err(e) if !closed(&e) => Err(format!("cannot write {target}: {e}")),
            _ => Ok(()),
        },
        Err(Stop::Io(e)) if closed(&e) => Ok(()),
        Err(Stop::Io(e)) => Err(format!(
            "cannot write {target}: {e} (the run stopped at t = {} s)",
            at.t
        )),
        Err(Stop::Replay(e)) => Err(format!(
            "{e}\n(the CSV on {target} holds the {} rows up to t = {} s)",
            at.rows, at.t
        )),
        Err(Stop::Model(e)) if !at.initialized => Err(format!(
            "{id} failed to initialize: {e}\n(the CSV on {target} has its header only)"
        )),
        Err(Stop::Model(e)) => Err(format!(
            "{id} stopped at t = {} s after {} of about {total} communication steps: {e}\n(the CSV on {target} holds the {} rows up to t = {} s)",
            at.t, at.steps, at.rows, at.t
        )),
    };
    match (outcome, page_error) {
        (outcome, None) => outcome,
        (Ok(()), Some(e)) => Err(e),
        (Err(m), Some(e)) => Err(format!("{m}\n{e}")),
    }
}
