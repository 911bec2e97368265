//! Speed of the flexible PanelLock scene (three panels, 10 Craig-Bampton modes each, the paper
//! configuration at k = 1e7, n = 1.5): real-time factor per integrator at the loosest tolerance
//! whose peak lock force and post-lock frequency are within 1 % of a tight reference (BDF,
//! rtol 1e-8). Prints a markdown table. Not a timed test: numbers depend on the machine.
//!
//! `cargo run --release --example bench_flex_panel [t_end]` (default 65 s of simulated time: the
//! last hinge locks near 27 s, and the post-lock window needs several 0.16 Hz periods; with
//! 35 s the window holds one period and the frequency is not resolved).
//!
//! `cargo run --release --example bench_flex_panel [t_end] quick`: only gen-alpha at rtol 1e-3,
//! with its work counters, errors against the reference figures of the last full run
//! (docs/panel_lock_flex_bench.md; valid for t_end = 65 s only). For profiling.

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::scene::panel_lock::PanelLockParams;
use mbcosim::scene::panel_lock::flex_panel::{compute, panel_spec};
use mbcosim::scene::panel_lock::study::{CaseResult, run_case};

fn params(kind: IntegratorKind, rtol: f64, max_order: usize) -> PanelLockParams {
    PanelLockParams {
        integrator: Some(kind),
        settings: Settings {
            rtol,
            atol: rtol * 1e-2,
            h_max: 0.02,
            max_order,
            ..Settings::default()
        },
        ..PanelLockParams::flexible(10)
    }
}

fn errors(c: &CaseResult, r: &CaseResult) -> (f64, f64) {
    let ef = (c.peak_force - r.peak_force).abs() / r.peak_force;
    let eq = match (c.frequency, r.frequency) {
        (Some(a), Some(b)) => (a - b).abs() / b,
        _ => f64::INFINITY,
    };
    (ef, eq)
}

fn main() {
    let t_end: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(65.0);
    let dt = 0.01;
    if std::env::args().nth(2).as_deref() == Some("hist") {
        step_histogram(t_end, dt);
        return;
    }
    if std::env::args().nth(2).as_deref() == Some("quick") {
        quick(t_end, dt);
        return;
    }
    // cost of the FE model and reduction (what the cache saves per instantiation)
    let p = PanelLockParams::flexible(10);
    let t = std::time::Instant::now();
    let [nx, ny] = p.panel_mesh;
    for outer in [false, true] {
        compute(
            &panel_spec(&p),
            nx,
            ny,
            10,
            p.modal_damping_ratio,
            p.reduction,
            outer,
        )
        .unwrap();
    }
    println!(
        "FE + Craig-Bampton of one inner and one outer panel ({nx} x {ny} mesh, 10 modes): {:.1} ms",
        1e3 * t.elapsed().as_secs_f64()
    );
    let t = std::time::Instant::now();
    for outer in [false, true] {
        compute(
            &panel_spec(&p),
            20,
            10,
            10,
            p.modal_damping_ratio,
            p.reduction,
            outer,
        )
        .unwrap();
    }
    println!(
        "same at a 20 x 10 mesh: {:.1} ms\n",
        1e3 * t.elapsed().as_secs_f64()
    );

    let reference = run_case(params(IntegratorKind::Bdf, 1e-8, 5), t_end, dt).unwrap();
    println!(
        "reference (BDF rtol 1e-8, {t_end} s): peak {:.3} N, post-lock {:.5} Hz, {:.1} s CPU\n",
        reference.peak_force,
        reference.frequency.unwrap_or(f64::NAN),
        reference.cpu
    );
    println!(
        "| integrator | rtol | max order | steps | CPU [s] | real-time factor | peak force err | frequency err | within 1 % |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let sweeps: [(IntegratorKind, usize); 4] = [
        (IntegratorKind::GenAlpha, 5),
        (IntegratorKind::Bdf, 5),
        (IntegratorKind::Bdf, 2),
        (IntegratorKind::Dopri5, 5),
    ];
    for (kind, order) in sweeps {
        for rtol in [1e-3, 1e-4, 1e-5] {
            let c = match run_case(params(kind, rtol, order), t_end, dt) {
                Ok(c) => c,
                Err(e) => {
                    println!("| {} | {rtol:e} | {order} | failed: {e} |", kind.name());
                    continue;
                }
            };
            let (ef, eq) = errors(&c, &reference);
            let ok = ef < 0.01 && eq < 0.01;
            println!(
                "| {} | {rtol:e} | {order} | {} | {:.2} | {:.1} | {:.2e} | {:.2e} | {} |",
                kind.name(),
                c.steps,
                c.cpu,
                t_end / c.cpu,
                ef,
                eq,
                if ok { "yes" } else { "no" }
            );
            if ok {
                break;
            }
        }
    }
}

/// Reference of the last full run (BDF rtol 1e-8, 65 s): peak force [N], frequency [Hz].
const REFERENCE_65: (f64, f64) = (1307.217, 0.16324);

fn quick(t_end: f64, dt: f64) {
    let p = params(IntegratorKind::GenAlpha, 1e-3, 5);
    let cpu = std::time::Instant::now();
    let s = mbcosim::scene::panel_lock::PanelLock::new(p.clone()).unwrap();
    println!(
        "set-up {:.3} s, n_v {}, n_c {}",
        cpu.elapsed().as_secs_f64(),
        s.sim.system.n_v(),
        s.sim.system.n_c()
    );
    drop(s);
    let c = run_case(p, t_end, dt).unwrap();
    let ef = (c.peak_force - REFERENCE_65.0).abs() / REFERENCE_65.0;
    let eq = c.frequency.map_or(f64::INFINITY, |f| {
        (f - REFERENCE_65.1).abs() / REFERENCE_65.1
    });
    println!(
        "gen-alpha rtol 1e-3: {} steps, {:.2} s CPU ({:.1} us/step, {:.1}x real time), peak {:.3} N (err {:.2e}), frequency {:.5} Hz (err {:.2e}), lock times {:?}",
        c.steps,
        c.cpu,
        1e6 * c.cpu / c.steps as f64,
        t_end / c.cpu,
        c.peak_force,
        ef,
        c.frequency.unwrap_or(f64::NAN),
        eq,
        c.lock_times
    );
    println!("{:?}", c.stats);
}

/// Steps per second of simulated time (where the steps are spent).
#[allow(dead_code)]
fn step_histogram(t_end: f64, dt: f64) {
    let p = params(IntegratorKind::GenAlpha, 1e-3, 5);
    let mut s = mbcosim::scene::panel_lock::PanelLock::new(p).unwrap();
    let n = (t_end / dt).round() as usize;
    let mut last = (0u64, 0u64, 0u64);
    let mut line = String::new();
    for i in 1..=n {
        s.advance_to(i as f64 * dt).unwrap();
        if i % 100 == 0 {
            let st = s.sim.stats();
            line += &format!(
                "t={:>3.0}: {} steps {} rej {} jac | ",
                i as f64 * dt,
                st.steps - last.0,
                st.rejected - last.1,
                st.jacobians - last.2
            );
            last = (st.steps, st.rejected, st.jacobians);
            if i % 500 == 0 {
                println!("{line}");
                line.clear();
            }
        }
    }
}
