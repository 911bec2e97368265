//! Speed of the flexible PanelLock scene (three panels, 10 Craig-Bampton modes each, the paper
//! configuration at k = 1e7, n = 1.5): real-time factor per integrator at the loosest tolerance
//! whose peak lock force and post-lock frequency are within 1 % of a tight reference (BDF,
//! rtol 1e-8). Prints a markdown table. Not a timed test: numbers depend on the machine.
//!
//! `cargo run --release --example bench_flex_panel [t_end]` (default 65 s of simulated time: the
//! last hinge locks near 27 s, and the post-lock window needs several 0.16 Hz periods; with
//! 35 s the window holds one period and the frequency is not resolved).

use mbcosim::integrator::{IntegratorKind, Settings};
use mbcosim::scene::panel_lock::PanelLockParams;
use mbcosim::scene::panel_lock::flex_panel::{compute, panel_spec};
use mbcosim::scene::panel_lock::study::{CaseResult, run_case};

fn params(kind: IntegratorKind, rtol: f64, max_order: usize) -> PanelLockParams {
    PanelLockParams {
        integrator: kind,
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
