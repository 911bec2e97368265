//! Accuracy suite (issue #17 item 7): problems with independent reference solutions, every
//! integrator across tolerances, the achieved error against the reference, error / rtol, CPU
//! time (best of a few runs), steps, rejected steps, failures.
//!
//! ```sh
//! cargo run --release --example accuracy_suite -- [--problem NAME ...] [--integrator NAME ...]
//!     [--rtol X ...] [--step H ...] [--repeats N] [--budget S] [--atol-ratio R] [--quick]
//!     [--csv] [--reference-out FILE] [--samples K] [--h-max H]
//! ```
//! Problems: chain2, chain8, chain32 (pendulum chains of uniform rods; chain100 when named),
//! fourbar (closed loop),
//! impact_hertz, impact_ln (ball on a half-space), panel_smooth (the PanelLock default scene
//! before its first lock). Integrators: gen_alpha, bdf, dopri5, dopri5_tree and
//! verner65_tree, verner87_tree (joint coordinates, chains only)
//! (adaptive, swept over rtol 1e-2 .. 1e-10, atol = rtol) and gen_alpha_fixed (fixed steps
//! 1e-2 .. 1e-5 s with the default Newton tolerances). `--quick`: chain2, chain8, fourbar,
//! impact_hertz at rtol 1e-2, 1e-4, 1e-6, 1e-8, steps 1e-2 and 1e-3, one run each. `--csv`
//! prints one CSV row per run on stdout (tables go to stderr); `--reference-out` writes the
//! reference values for `benches/exudyn_compare.py`. Each problem lives in its own module.
//!
//! Besides the end-time error (the timed run), each setting is run three more times, stopping at
//! the sample times of nested grids `t_k = k T / K'` for K' = K, K/2, K/4 (`--samples K`, default
//! 32; the impacts add three times inside the contact to every grid), each sample against an
//! independent reference value there: the trajectory error is the largest over all grids and
//! their samples, the end-time run counted as a grid of one sample (the error a user can meet
//! at that setting with any of those communication grids; one grid alone measures where its
//! cuts fall, see `suite::SAMPLES`; the table's "at t" names the grid that gave it). The summary checks, on both errors, that each decade
//! of rtol lowers the error at least 3x until it reaches the floor (1e-10, or 10x the
//! reference's own estimated error if larger), and prints the smallest per-decade factor.
//! `--h-max H` sets the adaptive runs' largest step (default: the library's, 0.1 s).

mod chain;
mod fourbar;
mod impact;
mod ode;
mod panel;
mod suite;

use suite::{Problem, Run, Series};

const ALL_PROBLEMS: [&str; 7] = [
    "chain2",
    "chain8",
    "chain32",
    "fourbar",
    "impact_hertz",
    "impact_ln",
    "panel_smooth",
];
/// Problems run only when named (their references and maximal-coordinate sweeps take minutes).
const ON_REQUEST: [&str; 1] = ["chain100"];
const QUICK_PROBLEMS: [&str; 4] = ["chain2", "chain8", "fourbar", "impact_hertz"];
/// Error levels of the per-level table.
const LEVELS: [f64; 7] = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];

struct Options {
    problems: Vec<String>,
    series: Vec<Series>,
    rtols: Vec<f64>,
    steps: Vec<f64>,
    repeats: usize,
    budget: f64,
    atol_ratio: f64,
    csv: bool,
    reference_out: Option<String>,
    samples: usize,
}

fn parse_args() -> Result<Options, String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "--quick");
    let mut o = Options {
        problems: Vec::new(),
        series: Vec::new(),
        rtols: Vec::new(),
        steps: Vec::new(),
        repeats: if quick { 1 } else { 3 },
        budget: if quick { 5.0 } else { 20.0 },
        atol_ratio: 1.0,
        csv: false,
        reference_out: None,
        samples: suite::SAMPLES,
    };
    let mut it = args.iter();
    let number = |flag: &str, v: Option<&String>| -> Result<f64, String> {
        let v = v.ok_or(format!("{flag} needs a value"))?;
        v.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite() && *x > 0.0)
            .ok_or(format!("{flag}: '{v}' is not a positive number"))
    };
    while let Some(a) = it.next() {
        match a.as_str() {
            "--quick" => {}
            "--csv" => o.csv = true,
            "--problem" => {
                for p in it.next().ok_or("--problem needs a name")?.split(',') {
                    if !ALL_PROBLEMS.contains(&p) && !ON_REQUEST.contains(&p) {
                        return Err(format!(
                            "unknown problem '{p}' (known: {}, {})",
                            ALL_PROBLEMS.join(", "),
                            ON_REQUEST.join(", ")
                        ));
                    }
                    o.problems.push(p.to_string());
                }
            }
            "--integrator" => {
                for s in it.next().ok_or("--integrator needs a name")?.split(',') {
                    o.series.push(Series::parse(s)?);
                }
            }
            "--rtol" => o.rtols.push(number(a, it.next())?),
            "--step" => o.steps.push(number(a, it.next())?),
            "--repeats" => o.repeats = number(a, it.next())?.round().max(1.0) as usize,
            "--budget" => o.budget = number(a, it.next())?,
            "--atol-ratio" => o.atol_ratio = number(a, it.next())?,
            "--samples" => o.samples = number(a, it.next())?.round().max(1.0) as usize,
            "--h-max" => {
                let h = number(a, it.next())?;
                suite::H_MAX
                    .set(h)
                    .map_err(|_| "--h-max given twice".to_string())?;
            }
            "--reference-out" => {
                o.reference_out = Some(it.next().ok_or("--reference-out needs a file")?.clone())
            }
            "-h" | "--help" => {
                return Err("usage: accuracy_suite [--problem NAME[,NAME]] [--integrator gen_alpha|bdf|dopri5|gen_alpha_fixed|dopri5_tree|verner65_tree|verner87_tree] [--rtol X ...] [--step H ...] [--repeats N] [--budget S] [--atol-ratio R] [--quick] [--csv] [--reference-out FILE] [--samples K] [--h-max H]".into());
            }
            other => return Err(format!("unknown argument '{other}' (try --help)")),
        }
    }
    if o.problems.is_empty() {
        let list: &[&str] = if quick {
            &QUICK_PROBLEMS
        } else {
            &ALL_PROBLEMS
        };
        o.problems = list.iter().map(|s| s.to_string()).collect();
    }
    if o.series.is_empty() {
        o.series = Series::ALL.to_vec();
    }
    if o.rtols.is_empty() {
        o.rtols = if quick {
            vec![1e-2, 1e-4, 1e-6, 1e-8]
        } else {
            (2..=10).map(|k| 10f64.powi(-k)).collect()
        };
    }
    if o.steps.is_empty() {
        o.steps = if quick {
            vec![1e-2, 1e-3]
        } else {
            vec![1e-2, 1e-3, 1e-4, 1e-5]
        };
    }
    // loose to tight, so that a run over the CPU budget skips the tighter ones
    o.rtols.sort_by(|a, b| b.total_cmp(a));
    o.steps.sort_by(|a, b| b.total_cmp(a));
    Ok(o)
}

fn build(name: &str, k: usize) -> Result<Problem, String> {
    match name {
        "chain2" => chain::problem(2, k),
        "chain8" => chain::problem(8, k),
        "chain32" => chain::problem(32, k),
        "chain100" => chain::problem(100, k),
        "fourbar" => fourbar::problem(k),
        "impact_hertz" => impact::problem(impact::Law::Hertz, k),
        "impact_ln" => impact::problem(impact::Law::LankaraniNikravesh(0.8), k),
        "panel_smooth" => panel::problem(k),
        _ => Err(format!("unknown problem {name}")),
    }
}

/// Prints to stdout, or to stderr in CSV mode (stdout then carries only CSV).
macro_rules! say {
    ($csv:expr, $($arg:tt)*) => {
        if $csv { eprintln!($($arg)*) } else { println!($($arg)*) }
    };
}

fn main() {
    if let Err(e) = run_suite() {
        eprintln!("accuracy_suite: {e}");
        std::process::exit(2);
    }
}

fn run_suite() -> Result<(), String> {
    let o = parse_args()?;
    let csv = o.csv;
    if csv {
        println!(
            "problem,integrator,parameter,value,error,aux_error,approach_speed_error,cpu_s,repeats,steps,rejected,newton_failures,status,message,traj_error,traj_time,traj_end_error,traj_steps,traj_status,traj_message,traj_samples"
        );
    }
    let mut reference_rows = vec!["problem,t_end,estimated_error,values".to_string()];
    let mut overview: Vec<(String, Series, Decades)> = Vec::new();
    for name in &o.problems {
        let t0 = suite::cpu_now();
        let p = build(name, o.samples)?;
        let t_ref = suite::cpu_now() - t0;
        say!(csv, "\n## {}: {}\n", p.name, p.title);
        say!(
            csv,
            "Reference: {} = [{}], estimated error {:.1e} ({}; {:.1} s CPU).\n",
            p.quantity.split(" error").next().unwrap_or(p.quantity),
            p.reference
                .value
                .iter()
                .map(|v| format!("{v:.12}"))
                .collect::<Vec<_>>()
                .join(", "),
            p.reference.estimated_error,
            p.reference.method,
            t_ref
        );
        say!(
            csv,
            "Trajectory reference: {} sample times [{}] s, estimated error {:.1e} ({}); at the end time it differs from the end-time reference by {:.1e}.\n",
            p.trajectory.times.len(),
            p.trajectory
                .times
                .iter()
                .map(|t| format!("{t:.4}"))
                .collect::<Vec<_>>()
                .join(", "),
            p.trajectory.estimated_error,
            p.trajectory.method,
            p.sample_error(p.trajectory.times.len() - 1, &p.reference.value)
        );
        reference_rows.push(format!(
            "{},{},{:e},{}",
            p.name,
            p.t_end,
            p.reference.estimated_error,
            p.reference
                .value
                .iter()
                .map(|v| format!("{v:.17e}"))
                .collect::<Vec<_>>()
                .join(";")
        ));
        let mut aux = p.aux_name.map(|a| format!(" {a} |")).unwrap_or_default();
        let mut aux_rule = if p.aux_name.is_some() { "---|" } else { "" }.to_string();
        if p.approach_speed.is_some() {
            aux.push_str(" recorded approach speed error [m/s] |");
            aux_rule.push_str("---|");
        }
        let n_extra = aux_rule.len() / 4;
        say!(
            csv,
            "| integrator | rtol or h | {} | error/rtol | trajectory error | at t [s] | traj. error/rtol |{aux} CPU [ms] | runs | steps | rejected | Newton failures | Newton it./step | status |",
            p.quantity
        );
        say!(
            csv,
            "|---|---|---|---|---|---|---|{aux_rule}---|---|---|---|---|---|---|"
        );
        let mut runs: Vec<Run> = Vec::new();
        for &series in &o.series {
            if !series.applies_to(&p.name) {
                continue;
            }
            let xs = match series {
                Series::Adaptive(_) => &o.rtols,
                Series::GenAlphaFixed => &o.steps,
            };
            let mut over_budget = false;
            for &x in xs {
                if over_budget {
                    say!(
                        csv,
                        "| {} | {x:.0e} | - | - | - | - | - |{} - | - | - | - | - | - | skipped: a looser setting used up the CPU budget |",
                        series.name(),
                        " - |".repeat(n_extra)
                    );
                    continue;
                }
                eprintln!(
                    "  {} {} {} {x:.0e}",
                    p.name,
                    series.name(),
                    series.parameter()
                );
                let r = suite::run(&p, series, x, o.atol_ratio, o.repeats, o.budget);
                over_budget = r.over_budget;
                let ratio = match series {
                    Series::Adaptive(_) if r.failure.is_none() => sig(r.error / x),
                    _ => "-".into(),
                };
                let mut aux_cell = match (p.aux_name, r.aux_error) {
                    (Some(_), Some(a)) => format!(" {a:.2e} |"),
                    (Some(_), None) => " - |".into(),
                    _ => String::new(),
                };
                if p.approach_speed.is_some() {
                    aux_cell.push_str(
                        &r.approach_error
                            .map(|a| format!(" {a:.2e} |"))
                            .unwrap_or(" - |".into()),
                    );
                }
                let mut status = r
                    .failure
                    .as_deref()
                    .map(|f| format!("FAILED: {f}"))
                    .unwrap_or_else(|| "ok".into());
                if let Some(f) = &r.traj_failure {
                    status.push_str(&format!("; sampled run FAILED: {f}"));
                }
                let (traj, traj_t, traj_ratio) = match (&r.traj_failure, series) {
                    (Some(_), _) => ("-".into(), "-".into(), "-".into()),
                    (None, Series::Adaptive(_)) => (
                        format!("{:.2e}", r.traj_error),
                        format!("{:.4} ({} samples)", r.traj_time, r.traj_grid),
                        sig(r.traj_error / x),
                    ),
                    (None, Series::GenAlphaFixed) => (
                        format!("{:.2e}", r.traj_error),
                        format!("{:.4}", r.traj_time),
                        "-".into(),
                    ),
                };
                say!(
                    csv,
                    "| {} | {x:.0e} | {} | {ratio} | {traj} | {traj_t} | {traj_ratio} |{aux_cell} {:.3} | {} | {} | {} | {} | {:.2} | {status} |",
                    series.name(),
                    if r.failure.is_none() {
                        format!("{:.2e}", r.error)
                    } else {
                        "-".into()
                    },
                    r.cpu * 1e3,
                    r.repeats,
                    r.steps,
                    r.rejected,
                    r.newton_failures,
                    r.newton_iterations as f64 / r.steps.max(1) as f64
                );
                if csv {
                    println!(
                        "{},{},{},{x:e},{:e},{},{},{:e},{},{},{},{},{},\"{}\",{:e},{},{:e},{},{},\"{}\",{}",
                        p.name,
                        series.name(),
                        series.parameter(),
                        r.error,
                        r.aux_error.map(|a| format!("{a:e}")).unwrap_or_default(),
                        r.approach_error
                            .map(|a| format!("{a:e}"))
                            .unwrap_or_default(),
                        r.cpu,
                        r.repeats,
                        r.steps,
                        r.rejected,
                        r.newton_failures,
                        if r.failure.is_none() { "ok" } else { "failed" },
                        r.failure.as_deref().unwrap_or("").replace('"', "'"),
                        r.traj_error,
                        r.traj_time,
                        r.traj_end_error,
                        r.traj_steps,
                        if r.traj_failure.is_none() {
                            "ok"
                        } else {
                            "failed"
                        },
                        r.traj_failure.as_deref().unwrap_or("").replace('"', "'"),
                        r.traj_grid
                    );
                }
                runs.push(r);
            }
        }
        overview.extend(summary(csv, &p, &o.series, &runs));
    }
    overview_table(csv, &o.series, &overview);
    if let Some(path) = &o.reference_out {
        std::fs::write(path, reference_rows.join("\n") + "\n")
            .map_err(|e| format!("cannot write {path}: {e}"))?;
        eprintln!("references written to {path}");
    }
    Ok(())
}

/// Per-decade factors of one adaptive series: consecutive settings a decade apart whose looser
/// error is above `floor` are judged; a decade fails when the error falls less than 3x and the
/// tighter error is still above `floor`. A decade whose tighter run failed is not judged.
#[derive(Debug, Clone, Default)]
struct Decades {
    judged: usize,
    /// Smallest factor of the judged decades whose tighter error is above the floor, and its
    /// looser rtol.
    smallest: Option<(f64, f64)>,
    /// Judged decades whose tighter error reached the floor (passed, factor not counted).
    at_floor: usize,
    failures: Vec<String>,
}

/// `points`: (rtol, error or None if the run failed), loose to tight.
fn decades(points: &[(f64, Option<f64>)], floor: f64) -> Decades {
    let mut d = Decades::default();
    for w in points.windows(2) {
        let ((x0, e0), (x1, e1)) = (w[0], w[1]);
        let (Some(e0), Some(e1)) = (e0, e1) else {
            continue;
        };
        if (x0 / x1 - 10.0).abs() > 1e-6 || e0 <= floor {
            continue;
        }
        d.judged += 1;
        if e1 <= floor {
            d.at_floor += 1;
            continue;
        }
        let f = e0 / e1;
        if d.smallest.is_none_or(|(s, _)| f < s) {
            d.smallest = Some((f, x0));
        }
        if f < 3.0 {
            d.failures.push(format!(
                "{x0:.0e} -> {x1:.0e}: {e0:.2e} -> {e1:.2e} ({f:.2}x; {} x rtol at {x0:.0e})",
                sig(e0 / x0)
            ));
        }
    }
    d
}

impl Decades {
    fn smallest_cell(&self) -> String {
        match self.smallest {
            Some((f, x0)) => format!("{}x ({x0:.0e} -> {:.0e})", sig(f), x0 / 10.0),
            None if self.judged > 0 => "all at floor".into(),
            None => "none judged".into(),
        }
    }

    fn failures_cell(&self) -> String {
        if self.failures.is_empty() {
            "none".into()
        } else {
            self.failures.join("; ")
        }
    }
}

/// Errors of a series, loose to tight (`x`: failed), and error/rtol.
fn error_cells(ok: &[Option<f64>], xs: &[f64], adaptive: bool) -> (String, String) {
    let errs = ok
        .iter()
        .map(|e| e.map(|e| format!("{e:.1e}")).unwrap_or("x".into()))
        .collect::<Vec<_>>()
        .join(" ");
    let ratios = if adaptive {
        ok.iter()
            .zip(xs)
            .filter_map(|(e, x)| e.map(|e| sig(e / x)))
            .collect::<Vec<_>>()
            .join(" ")
    } else {
        "-".into()
    };
    (errs, ratios)
}

/// Per series: monotonicity of the error in the swept parameter and the error/rtol range, the
/// per-decade factors of the end-time and the trajectory error; then the cheapest run per error
/// level. Returns the trajectory error's decades per adaptive series.
fn summary(
    csv: bool,
    p: &Problem,
    series: &[Series],
    runs: &[Run],
) -> Vec<(String, Series, Decades)> {
    // differences below this are noise (the reference's, round-off), not the integrator's
    let floor = (10.0 * p.reference.estimated_error).max(1e-11);
    say!(
        csv,
        "\n| integrator | error monotone as rtol or h shrinks | violations | error/rtol (min .. max) |"
    );
    say!(csv, "|---|---|---|---|");
    for &s in series {
        let ok: Vec<&Run> = runs
            .iter()
            .filter(|r| r.series == s && r.failure.is_none())
            .collect();
        let failed = runs
            .iter()
            .filter(|r| r.series == s && r.failure.is_some())
            .count();
        let mut violations = Vec::new();
        for w in ok.windows(2) {
            if w[1].error > w[0].error && w[1].error > floor {
                violations.push(format!(
                    "{:.0e} -> {:.0e}: {:.1e} -> {:.1e}",
                    w[0].x, w[1].x, w[0].error, w[1].error
                ));
            }
        }
        let ratios: Vec<f64> = ok
            .iter()
            .filter(|r| r.error > floor)
            .map(|r| r.error / r.x)
            .collect();
        let range = match s {
            Series::Adaptive(_) if !ratios.is_empty() => format!(
                "{} .. {}",
                sig(ratios.iter().copied().fold(f64::INFINITY, f64::min)),
                sig(ratios.iter().copied().fold(0.0, f64::max))
            ),
            _ => "-".into(),
        };
        let verdict = if ok.len() < 2 {
            "too few runs".to_string()
        } else if violations.is_empty() {
            "yes".to_string()
        } else {
            format!("no ({} of {})", violations.len(), ok.len() - 1)
        };
        let failed_note = if failed > 0 {
            format!("; {failed} failed")
        } else {
            String::new()
        };
        say!(
            csv,
            "| {} | {verdict}{failed_note} | {} | {range} |",
            s.name(),
            if violations.is_empty() {
                "-".to_string()
            } else {
                violations.join("; ")
            }
        );
    }
    // the per-decade check, on the end-time error and on the trajectory error
    let end_floor = (10.0 * p.reference.estimated_error).max(1e-10);
    let traj_floor = (10.0 * p.trajectory.estimated_error).max(1e-10);
    say!(
        csv,
        "\nPer decade of rtol (at least 3x until the error reaches the floor: 1e-10, or 10x the reference's estimated error if larger; end time {end_floor:.1e}, trajectory {traj_floor:.1e}; a decade whose tighter run failed is not judged).\n"
    );
    say!(
        csv,
        "| integrator | trajectory errors (loose -> tight; x = failed) | traj. error/rtol | smallest decade factor, trajectory | decades < 3x, trajectory | smallest decade factor, end time | decades < 3x, end time |"
    );
    say!(csv, "|---|---|---|---|---|---|---|");
    let mut out = Vec::new();
    for &s in series {
        let mine: Vec<&Run> = runs.iter().filter(|r| r.series == s).collect();
        let xs: Vec<f64> = mine.iter().map(|r| r.x).collect();
        let traj: Vec<Option<f64>> = mine
            .iter()
            .map(|r| r.traj_failure.is_none().then_some(r.traj_error))
            .collect();
        let end: Vec<Option<f64>> = mine
            .iter()
            .map(|r| r.failure.is_none().then_some(r.error))
            .collect();
        let adaptive = matches!(s, Series::Adaptive(_));
        let (errs, ratios) = error_cells(&traj, &xs, adaptive);
        if !adaptive {
            say!(csv, "| {} | {errs} | - | - | - | - | - |", s.name());
            continue;
        }
        let pts = |e: &[Option<f64>]| {
            xs.iter()
                .copied()
                .zip(e.iter().copied())
                .collect::<Vec<_>>()
        };
        let dt = decades(&pts(&traj), traj_floor);
        let de = decades(&pts(&end), end_floor);
        say!(
            csv,
            "| {} | {errs} | {ratios} | {} | {} | {} | {} |",
            s.name(),
            dt.smallest_cell(),
            dt.failures_cell(),
            de.smallest_cell(),
            de.failures_cell()
        );
        out.push((p.name.clone(), s, dt));
    }
    say!(
        csv,
        "\n| error level | cheapest run reaching it | CPU [ms] |\n|---|---|---|"
    );
    for level in LEVELS {
        let best = runs
            .iter()
            .filter(|r| r.failure.is_none() && r.error <= level)
            .min_by(|a, b| a.cpu.total_cmp(&b.cpu));
        match best {
            Some(r) => {
                // '*': a tighter setting of the same series misses the level (reached by luck)
                let lucky = runs.iter().any(|q| {
                    q.series == r.series && q.x < r.x && (q.failure.is_some() || q.error > level)
                });
                say!(
                    csv,
                    "| {level:.0e} | {} {} {:.0e}{} | {:.3} |",
                    r.series.name(),
                    r.series.parameter(),
                    r.x,
                    if lucky { " *" } else { "" },
                    r.cpu * 1e3
                );
            }
            None => say!(csv, "| {level:.0e} | none | - |"),
        }
    }
    out
}

/// All problems: the smallest per-decade factor of the trajectory error per problem and adaptive
/// integrator, and every decade below 3x.
fn overview_table(csv: bool, series: &[Series], all: &[(String, Series, Decades)]) {
    let adaptive: Vec<Series> = series
        .iter()
        .copied()
        .filter(|s| matches!(s, Series::Adaptive(_)))
        .collect();
    if all.is_empty() || adaptive.is_empty() {
        return;
    }
    say!(
        csv,
        "\n## Trajectory error: smallest factor per decade of rtol (decades < 3x in brackets)\n"
    );
    say!(
        csv,
        "| problem | {} |",
        adaptive
            .iter()
            .map(|s| s.name())
            .collect::<Vec<_>>()
            .join(" | ")
    );
    say!(csv, "|---|{}", "---|".repeat(adaptive.len()));
    let mut problems: Vec<&String> = Vec::new();
    for (p, _, _) in all {
        if !problems.contains(&p) {
            problems.push(p);
        }
    }
    let mut fails = Vec::new();
    for p in problems {
        let cells: Vec<String> = adaptive
            .iter()
            .map(|s| match all.iter().find(|(q, t, _)| q == p && t == s) {
                Some((_, _, d)) => {
                    for f in &d.failures {
                        fails.push(format!("{p} {}: {f}", s.name()));
                    }
                    let n = d.failures.len();
                    format!(
                        "{}{}",
                        d.smallest_cell(),
                        if n > 0 {
                            format!(" [{n}]")
                        } else {
                            String::new()
                        }
                    )
                }
                None => "-".into(),
            })
            .collect();
        say!(csv, "| {p} | {} |", cells.join(" | "));
    }
    if fails.is_empty() {
        say!(
            csv,
            "\nEvery judged decade lowers the trajectory error at least 3x."
        );
    } else {
        say!(csv, "\nDecades below 3x (trajectory error):");
        for f in fails {
            say!(csv, "- {f}");
        }
    }
}

/// Two significant digits for ratios (no decimals from 100 on; below 1, as many decimals as two
/// significant digits need).
fn sig(x: f64) -> String {
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 10.0 {
        format!("{x:.1}")
    } else if x >= 1.0 || x <= 0.0 || !x.is_finite() {
        format!("{x:.2}")
    } else {
        let decimals = (1.0 - x.log10().floor()) as usize;
        format!("{x:.decimals$}")
    }
}
