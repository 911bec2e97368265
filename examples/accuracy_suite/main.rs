//! Accuracy suite (issue #17 item 7): problems with independent reference solutions, every
//! integrator across tolerances, the achieved error against the reference, error / rtol, CPU
//! time (best of a few runs), steps, rejected steps, failures.
//!
//! ```sh
//! cargo run --release --example accuracy_suite -- [--problem NAME ...] [--integrator NAME ...]
//!     [--rtol X ...] [--step H ...] [--repeats N] [--budget S] [--atol-ratio R] [--quick]
//!     [--csv] [--reference-out FILE]
//! ```
//! Problems: chain2, chain8, chain32 (pendulum chains of uniform rods), fourbar (closed loop),
//! impact_hertz, impact_ln (ball on a half-space), panel_smooth (the PanelLock default scene
//! before its first lock). Integrators: gen_alpha, bdf, dopri5
//! (adaptive, swept over rtol 1e-2 .. 1e-10, atol = rtol) and gen_alpha_fixed (fixed steps
//! 1e-2 .. 1e-5 s with the default Newton tolerances). `--quick`: chain2, chain8, fourbar,
//! impact_hertz at rtol 1e-2, 1e-4, 1e-6, 1e-8, steps 1e-2 and 1e-3, one run each. `--csv`
//! prints one CSV row per run on stdout (tables go to stderr); `--reference-out` writes the
//! reference values for `benches/exudyn_compare.py`. Each problem lives in its own module.

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
                    if !ALL_PROBLEMS.contains(&p) {
                        return Err(format!(
                            "unknown problem '{p}' (known: {})",
                            ALL_PROBLEMS.join(", ")
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
            "--reference-out" => {
                o.reference_out = Some(it.next().ok_or("--reference-out needs a file")?.clone())
            }
            "-h" | "--help" => {
                return Err("usage: accuracy_suite [--problem NAME[,NAME]] [--integrator gen_alpha|bdf|dopri5|gen_alpha_fixed] [--rtol X ...] [--step H ...] [--repeats N] [--budget S] [--atol-ratio R] [--quick] [--csv] [--reference-out FILE]".into());
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

fn build(name: &str) -> Result<Problem, String> {
    match name {
        "chain2" => chain::problem(2),
        "chain8" => chain::problem(8),
        "chain32" => chain::problem(32),
        "fourbar" => fourbar::problem(),
        "impact_hertz" => impact::problem(impact::Law::Hertz),
        "impact_ln" => impact::problem(impact::Law::LankaraniNikravesh(0.8)),
        "panel_smooth" => panel::problem(),
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
            "problem,integrator,parameter,value,error,aux_error,approach_speed_error,cpu_s,repeats,steps,rejected,newton_failures,status,message"
        );
    }
    let mut reference_rows = vec!["problem,t_end,estimated_error,values".to_string()];
    for name in &o.problems {
        let t0 = suite::cpu_now();
        let p = build(name)?;
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
            "| integrator | rtol or h | {} | error/rtol |{aux} CPU [ms] | runs | steps | rejected | Newton failures | Newton it./step | status |",
            p.quantity
        );
        say!(
            csv,
            "|---|---|---|---|{aux_rule}---|---|---|---|---|---|---|"
        );
        let mut runs: Vec<Run> = Vec::new();
        for &series in &o.series {
            let xs = match series {
                Series::Adaptive(_) => &o.rtols,
                Series::GenAlphaFixed => &o.steps,
            };
            let mut over_budget = false;
            for &x in xs {
                if over_budget {
                    say!(
                        csv,
                        "| {} | {x:.0e} | - | - |{} - | - | - | - | - | - | skipped: a looser setting used up the CPU budget |",
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
                let status = r
                    .failure
                    .as_deref()
                    .map(|f| format!("FAILED: {f}"))
                    .unwrap_or_else(|| "ok".into());
                say!(
                    csv,
                    "| {} | {x:.0e} | {} | {ratio} |{aux_cell} {:.3} | {} | {} | {} | {} | {:.2} | {status} |",
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
                        "{},{},{},{x:e},{:e},{},{},{:e},{},{},{},{},{},\"{}\"",
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
                        r.failure.as_deref().unwrap_or("").replace('"', "'")
                    );
                }
                runs.push(r);
            }
        }
        summary(csv, &p, &o.series, &runs);
    }
    if let Some(path) = &o.reference_out {
        std::fs::write(path, reference_rows.join("\n") + "\n")
            .map_err(|e| format!("cannot write {path}: {e}"))?;
        eprintln!("references written to {path}");
    }
    Ok(())
}

/// Per series: monotonicity of the error in the swept parameter and the error/rtol range; then
/// the cheapest run per error level.
fn summary(csv: bool, p: &Problem, series: &[Series], runs: &[Run]) {
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
}

/// Two significant digits for ratios (no decimals from 100 on).
fn sig(x: f64) -> String {
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 10.0 {
        format!("{x:.1}")
    } else {
        format!("{x:.2}")
    }
}
