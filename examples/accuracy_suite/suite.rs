//! What a suite problem is, how one run is made and timed, and the CPU clock.

use mbcosim::dae::System;
use mbcosim::integrator::{IntegratorKind, Settings, SolverError, StepAction, StepHook};
use mbcosim::model::Model;
use mbcosim::sim::Simulation;
use mbcosim::state::State;

/// The largest step of the adaptive runs when `--h-max` sets it (else the library default).
pub static H_MAX: std::sync::OnceLock<f64> = std::sync::OnceLock::new();

/// Gravity [m/s^2], along -y in every problem.
pub const G: f64 = 9.81;

/// Reads the measured components from a simulation at the end time.
pub type Measure = Box<dyn Fn(&Simulation) -> Vec<f64>>;

/// The reference solution of a problem's measured quantity.
pub struct Reference {
    /// Reference values of the measured components.
    pub value: Vec<f64>,
    /// The reference's own error estimate (same norm as the run errors).
    pub estimated_error: f64,
    /// How it was computed.
    pub method: String,
}

/// The reference at sample times along the run (the trajectory error).
pub struct Trajectory {
    /// Sample times [s], ascending, the last one the end time.
    pub times: Vec<f64>,
    /// Reference values of the measured components at each sample time.
    pub values: Vec<Vec<f64>>,
    /// The reference's own error estimate, the largest over the samples (primary components).
    pub estimated_error: f64,
    /// The number `K` of the uniform grid `k T / K` the times were made from (times off that
    /// grid, such as the impacts' samples inside the contact, belong to every coarser grid).
    pub uniform: usize,
    /// How it was computed.
    pub method: String,
}

impl Trajectory {
    /// Indices of the sample times on the grid of every `stride`-th uniform time (`stride` 1:
    /// all), with the off-grid times and the end time always included.
    pub fn subgrid(&self, t_end: f64, stride: usize) -> Vec<usize> {
        let k_max = self.uniform.max(1) as f64;
        self.times
            .iter()
            .enumerate()
            .filter(|&(k, &t)| {
                let r = t * k_max / t_end;
                let on_grid = (r - r.round()).abs() < 1e-9;
                k + 1 == self.times.len() || !on_grid || (r.round() as usize).is_multiple_of(stride)
            })
            .map(|(k, _)| k)
            .collect()
    }
}

/// Default number of equally spaced sample times `t_k = k T / K`, k = 1..K, of the finest
/// sampling grid. The trajectory error is the largest over [`GRID_STRIDES`] nested grids (every
/// sample, every second, every fourth: 32, 16 and 8 samples) and the end-time run (one sample),
/// each a separate run stopping at its own grid as an FMU importer's communication points would. One grid alone is a lottery at loose
/// tolerances: where the grid cuts the steps changes the error by up to 40x on the four-bar
/// (DOPRI5 rtol 1e-3: 3.3e-2, 9.9e-3, 7.9e-3 m on 8, 16, 32 samples), so a decade of rtol judged
/// on one grid measured where the cuts fell rather than the tolerance. The largest over grids is
/// the error a user can meet at that rtol on any of them.
pub const SAMPLES: usize = 32;

/// Strides of the nested sampling grids (1: every sample time of the finest grid).
pub const GRID_STRIDES: [usize; 3] = [1, 2, 4];

/// `t_k = k t_end / k_max`, k = 1..k_max (the last exactly `t_end`).
pub fn grid(t_end: f64, k_max: usize) -> Vec<f64> {
    (1..=k_max)
        .map(|k| {
            if k == k_max {
                t_end
            } else {
                k as f64 * t_end / k_max as f64
            }
        })
        .collect()
}

/// One problem of the suite.
pub struct Problem {
    pub name: String,
    pub title: String,
    /// Simulated time [s].
    pub t_end: f64,
    /// What the error measures.
    pub quantity: &'static str,
    /// What the auxiliary error measures (the measured components after the first `primary`).
    pub aux_name: Option<&'static str>,
    /// Contact problems: the exact approach speed at contact onset [m/s], to compare with the
    /// one the solver records (memory `[in contact, approach speed, ...]` of the only contact).
    pub approach_speed: Option<f64>,
    pub model: Model,
    /// The measured components at the end time.
    pub measure: Measure,
    /// The first `primary` components form the error (Euclidean norm); the rest the auxiliary
    /// error.
    pub primary: usize,
    pub reference: Reference,
    /// References at the sample times; `measure` is applied there too.
    pub trajectory: Trajectory,
    /// The adaptive runs' largest step [s] where the problem sets one (`None`: the library's
    /// 0.1 s).
    pub h_max: Option<f64>,
}

impl Problem {
    /// Error and auxiliary error of measured components `v`.
    pub fn errors(&self, v: &[f64]) -> (f64, Option<f64>) {
        let p = self.primary;
        let e = crate::ode::dist(&v[..p], &self.reference.value[..p]);
        let aux = (v.len() > p).then(|| crate::ode::dist(&v[p..], &self.reference.value[p..]));
        (e, aux)
    }

    /// Error of measured components `v` at sample `k` (the primary components).
    pub fn sample_error(&self, k: usize, v: &[f64]) -> f64 {
        let p = self.primary;
        crate::ode::dist(&v[..p], &self.trajectory.values[k][..p])
    }
}

/// A series of runs: an adaptive integrator swept over rtol, or fixed-step generalized-alpha
/// swept over the step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Series {
    Adaptive(IntegratorKind),
    GenAlphaFixed,
}

impl Series {
    pub const ALL: [Series; 7] = [
        Series::Adaptive(IntegratorKind::GenAlpha),
        Series::Adaptive(IntegratorKind::Bdf),
        Series::Adaptive(IntegratorKind::Dopri5),
        Series::GenAlphaFixed,
        Series::Adaptive(IntegratorKind::Dopri5Tree),
        Series::Adaptive(IntegratorKind::Verner65Tree),
        Series::Adaptive(IntegratorKind::Verner87Tree),
    ];

    /// Whether the series runs on problem `name`: the joint-coordinate integrator only on the
    /// chains (the other problems have a loop or contact events, which it refuses).
    pub fn applies_to(self, name: &str) -> bool {
        let tree = matches!(
            self,
            Series::Adaptive(
                IntegratorKind::Dopri5Tree
                    | IntegratorKind::Verner65Tree
                    | IntegratorKind::Verner87Tree
            )
        );
        !tree || name.starts_with("chain")
    }

    /// Command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Series::Adaptive(IntegratorKind::GenAlpha) => "gen_alpha",
            Series::Adaptive(IntegratorKind::Bdf) => "bdf",
            Series::Adaptive(IntegratorKind::Dopri5) => "dopri5",
            Series::Adaptive(IntegratorKind::Dopri5Tree) => "dopri5_tree",
            Series::Adaptive(IntegratorKind::Verner65Tree) => "verner65_tree",
            Series::Adaptive(IntegratorKind::Verner87Tree) => "verner87_tree",
            Series::GenAlphaFixed => "gen_alpha_fixed",
        }
    }

    /// What the swept parameter is.
    pub fn parameter(self) -> &'static str {
        match self {
            Series::Adaptive(_) => "rtol",
            Series::GenAlphaFixed => "h",
        }
    }

    pub fn parse(s: &str) -> Result<Series, String> {
        Series::ALL
            .into_iter()
            .find(|x| x.name() == s)
            .ok_or_else(|| {
                format!(
                    "unknown integrator '{s}' (known: {})",
                    Series::ALL.map(|x| x.name()).join(", ")
                )
            })
    }

    /// Settings for parameter `x` (rtol or step); atol = `atol_ratio` rtol for adaptive runs.
    /// Everything else is the library default (h_max 0.1 s, rho_inf 0.8, BDF order <= 5), except
    /// the bound on steps per call (raised to 1e8: 2 s at 1e-5 s are 200,000 steps, the
    /// default bound; the CPU budget bounds a run instead) and the largest step where the
    /// problem sets its own (`h_max`, see [`Problem::h_max`]; `--h-max` overrides both).
    pub fn settings(
        self,
        x: f64,
        atol_ratio: f64,
        h_max: Option<f64>,
    ) -> (IntegratorKind, Settings) {
        let max_steps = 100_000_000;
        match self {
            Series::Adaptive(kind) => (
                kind,
                Settings {
                    rtol: x,
                    atol: atol_ratio * x,
                    max_steps,
                    h_max: H_MAX
                        .get()
                        .copied()
                        .or(h_max)
                        .unwrap_or(Settings::default().h_max),
                    ..Settings::default()
                },
            ),
            // default rtol/atol (they set the Newton tolerance): what a user gets
            Series::GenAlphaFixed => (
                IntegratorKind::GenAlpha,
                Settings {
                    fixed_step: x,
                    h_max: x,
                    max_steps,
                    ..Settings::default()
                },
            ),
        }
    }
}

/// One measured run.
#[derive(Debug, Clone)]
pub struct Run {
    pub series: Series,
    pub x: f64,
    pub error: f64,
    pub aux_error: Option<f64>,
    /// Error of the approach speed the solver recorded at the first contact [m/s].
    pub approach_error: Option<f64>,
    /// Best CPU time of the repeats [s].
    pub cpu: f64,
    pub repeats: usize,
    pub steps: u64,
    /// Steps rejected by a check after a converged Newton iteration (error, energy).
    pub rejected: u64,
    /// Newton iterations that did not converge (the step was retried).
    pub newton_failures: u64,
    /// Newton iterations in all (converged or not).
    pub newton_iterations: u64,
    /// Why the run failed (`None`: it reached the end time).
    pub failure: Option<String>,
    /// The failure was the CPU budget.
    pub over_budget: bool,
    /// The sampled run (a second run stopping at every sample time): the largest error over the
    /// samples, the time it occurs, the error at the end time, steps, and why it failed.
    pub traj_error: f64,
    pub traj_time: f64,
    pub traj_end_error: f64,
    pub traj_steps: u64,
    pub traj_failure: Option<String>,
    /// The number of sample times of the grid that gave `traj_error`.
    pub traj_grid: usize,
}

/// Process CPU time [s] (all threads).
#[cfg(target_os = "linux")]
pub fn cpu_now() -> f64 {
    #[repr(C)]
    struct Timespec {
        tv_sec: std::ffi::c_long,
        tv_nsec: std::ffi::c_long,
    }
    unsafe extern "C" {
        fn clock_gettime(clock: std::ffi::c_int, ts: *mut Timespec) -> std::ffi::c_int;
    }
    const CLOCK_PROCESS_CPUTIME_ID: std::ffi::c_int = 2;
    let mut ts = Timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    let rc = unsafe { clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_PROCESS_CPUTIME_ID) failed");
    ts.tv_sec as f64 + 1e-9 * ts.tv_nsec as f64
}

/// Wall-clock time [s] where no process CPU clock is wired up.
#[cfg(not(target_os = "linux"))]
pub fn cpu_now() -> f64 {
    use std::sync::OnceLock;
    static START: OnceLock<std::time::Instant> = OnceLock::new();
    START
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_secs_f64()
}

/// Stops the integration once the run has used its CPU budget (checked every 16 steps), and
/// notes the first approach speed a contact records; otherwise changes nothing, so results
/// equal those of `advance_to`.
struct Budget {
    start: f64,
    limit: f64,
    count: u64,
    exceeded: bool,
    watch_contact: bool,
    approach: Option<f64>,
}

impl StepHook for Budget {
    fn after_step(&mut self, _: &mut System, st: &mut State) -> Result<StepAction, SolverError> {
        if self.watch_contact
            && self.approach.is_none()
            && st.memory.len() >= 2
            && st.memory[0] > 0.5
        {
            self.approach = Some(st.memory[1]);
        }
        self.count += 1;
        if self.count.is_multiple_of(16) && cpu_now() - self.start > self.limit {
            self.exceeded = true;
            return Ok(StepAction::Stop);
        }
        Ok(StepAction::Continue)
    }
}

/// One run (no repeats): CPU time from building the simulation (consistent initial conditions
/// included, model assembly excluded) to the end time.
fn run_once(p: &Problem, series: Series, x: f64, atol_ratio: f64, budget: f64) -> Run {
    let (kind, settings) = series.settings(x, atol_ratio, p.h_max);
    let model = p.model.clone();
    let t0 = cpu_now();
    let mut out = Run {
        series,
        x,
        error: f64::NAN,
        aux_error: None,
        approach_error: None,
        cpu: f64::NAN,
        repeats: 1,
        steps: 0,
        rejected: 0,
        newton_failures: 0,
        newton_iterations: 0,
        failure: None,
        over_budget: false,
        traj_error: f64::NAN,
        traj_time: f64::NAN,
        traj_end_error: f64::NAN,
        traj_steps: 0,
        traj_failure: None,
        traj_grid: 0,
    };
    let mut sim = match Simulation::new(model, kind, settings, 0.0) {
        Ok(s) => s,
        Err(e) => {
            out.cpu = cpu_now() - t0;
            out.failure = Some(format!("setup: {e}"));
            return out;
        }
    };
    let mut hook = Budget {
        start: t0,
        limit: budget,
        count: 0,
        exceeded: false,
        watch_contact: p.approach_speed.is_some(),
        approach: None,
    };
    let result = sim.advance_with(p.t_end, &mut hook);
    out.cpu = cpu_now() - t0;
    let stats = sim.stats();
    out.steps = stats.steps;
    out.rejected = stats.rejected;
    out.newton_failures = stats.newton_failures;
    out.newton_iterations = stats.newton_iterations;
    if let (Some(exact), Some(recorded)) = (p.approach_speed, hook.approach) {
        out.approach_error = Some((recorded - exact).abs());
    }
    match result {
        Err(e) => out.failure = Some(format!("at t = {:.6} s: {e}", sim.state.t)),
        Ok(()) if hook.exceeded => {
            out.over_budget = true;
            out.failure = Some(format!(
                "CPU budget of {budget} s used up at t = {:.4} s",
                sim.state.t
            ));
        }
        Ok(()) => {
            let (e, aux) = p.errors(&(p.measure)(&sim));
            out.error = e;
            out.aux_error = aux;
            if !e.is_finite() {
                out.failure = Some("non-finite result".into());
            }
        }
    }
    out
}

/// The sampled runs: one per nested grid ([`GRID_STRIDES`]), each `advance_with` to its sample
/// times in turn (like an FMU communication grid) and measured there. Fills the `traj_*` fields
/// of `out` from the grid with the largest error, the end-time run (`out.error`, one sample at
/// the end) counted as one more grid: where an integrator's steps are longer than a grid's
/// spacing, stopping at the grid shortens them as `h_max` would, and the tolerance then shows
/// only in the run that is not cut (DOPRI5 on panel_smooth at rtol 1e-2: 7 steps and 1.3e-2 rad
/// in 2 s uncut, 1.2e-4 rad cut at every 0.25 s). A failure on any grid is the run's failure.
/// Not timed; each grid has its own CPU budget.
fn run_sampled(p: &Problem, out: &mut Run, atol_ratio: f64, budget: f64) {
    let mut worst: Option<Sampled> = None;
    for stride in GRID_STRIDES {
        let indices = p.trajectory.subgrid(p.t_end, stride);
        match run_grid(p, out, &indices, atol_ratio, budget) {
            Err(message) => {
                out.traj_failure = Some(format!("{} samples: {message}", indices.len()));
                return;
            }
            Ok(s) => {
                if worst.as_ref().is_none_or(|w| s.worst > w.worst) {
                    worst = Some(s);
                }
            }
        }
    }
    if out.failure.is_none() && worst.as_ref().is_some_and(|w| out.error > w.worst) {
        worst = Some(Sampled {
            worst: out.error,
            at: p.t_end,
            last: out.error,
            steps: out.steps,
            samples: 1,
        });
    }
    if let Some(w) = worst {
        out.traj_error = w.worst;
        out.traj_time = w.at;
        out.traj_end_error = w.last;
        out.traj_steps = w.steps;
        out.traj_grid = w.samples;
    }
}

/// What one sampled run found: the largest error, when, the error at the end time, steps, and
/// the number of sample times.
struct Sampled {
    worst: f64,
    at: f64,
    last: f64,
    steps: u64,
    samples: usize,
}

/// One sampled run stopping at the trajectory's sample times `indices`.
fn run_grid(
    p: &Problem,
    out: &Run,
    indices: &[usize],
    atol_ratio: f64,
    budget: f64,
) -> Result<Sampled, String> {
    let (kind, settings) = out.series.settings(out.x, atol_ratio, p.h_max);
    let t0 = cpu_now();
    let mut sim =
        Simulation::new(p.model.clone(), kind, settings, 0.0).map_err(|e| format!("setup: {e}"))?;
    let mut hook = Budget {
        start: t0,
        limit: budget,
        count: 0,
        exceeded: false,
        watch_contact: false,
        approach: None,
    };
    let mut s = Sampled {
        worst: 0.0,
        at: f64::NAN,
        last: f64::NAN,
        steps: 0,
        samples: indices.len(),
    };
    for &k in indices {
        let t = p.trajectory.times[k];
        let result = sim.advance_with(t, &mut hook);
        s.steps = sim.stats().steps;
        if let Err(e) = result {
            return Err(format!("at t = {:.6} s: {e}", sim.state.t));
        }
        if hook.exceeded {
            return Err(format!(
                "CPU budget of {budget} s used up at t = {:.4} s",
                sim.state.t
            ));
        }
        let e = p.sample_error(k, &(p.measure)(&sim));
        if !e.is_finite() {
            return Err(format!("non-finite result at t = {t} s"));
        }
        if std::env::var_os("ACCURACY_SUITE_DEBUG").is_some() {
            eprintln!(
                "sampled ({} samples): {} {:.0e} t = {t:.4} s: error {e:.2e}, {} steps",
                indices.len(),
                out.series.name(),
                out.x,
                s.steps
            );
        }
        if e > s.worst || s.at.is_nan() {
            (s.worst, s.at) = (e, t);
        }
        s.last = e;
    }
    Ok(s)
}

/// Best-of-`repeats` CPU time; runs slower than 1 s are not repeated. Then one sampled run
/// (unless the timed run used up the CPU budget).
pub fn run(
    p: &Problem,
    series: Series,
    x: f64,
    atol_ratio: f64,
    repeats: usize,
    budget: f64,
) -> Run {
    let mut best = run_once(p, series, x, atol_ratio, budget);
    let mut n = 1;
    while n < repeats && best.failure.is_none() && best.cpu < 1.0 {
        let r = run_once(p, series, x, atol_ratio, budget);
        n += 1;
        if r.cpu < best.cpu {
            best.cpu = r.cpu;
        }
    }
    best.repeats = n;
    if best.over_budget {
        best.traj_failure = Some("skipped: the end-time run used up the CPU budget".into());
    } else {
        run_sampled(p, &mut best, atol_ratio, budget);
    }
    best
}
