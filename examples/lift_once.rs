//! One run of the default lift (settled, hoisted at 0.2 m/s from 1 s to 9 s, held to 12 s) for
//! profiling: `cargo run --release --example lift_once -- [integrator] [rtol] [h_max] [seconds]`
//! `[segments]` with integrator `gen-alpha`, `bdf`, `dopri5` or `default`. Prints the set-up and stepping wall times,
//! the peak hook load and sling tension and the integrator counters.

use mbcosim::integrator::IntegratorKind;
use mbcosim::scene::rope_block::demo::hoist;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};
use std::time::Instant;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let base = RopeBlockParams::default();
    let kind = match args.first().map(String::as_str) {
        None | Some("default") => base.integrator,
        Some("gen-alpha") => IntegratorKind::GenAlpha,
        Some("bdf") => IntegratorKind::Bdf,
        Some("dopri5") => IntegratorKind::Dopri5,
        Some(o) => return Err(format!("unknown integrator {o}")),
    };
    let num = |i: usize, d: f64| -> Result<f64, String> {
        args.get(i)
            .map(|s| s.parse::<f64>().map_err(|e| format!("{s}: {e}")))
            .unwrap_or(Ok(d))
    };
    let params = RopeBlockParams {
        integrator: kind,
        rtol: num(1, base.rtol)?,
        h_max: num(2, base.h_max)?,
        segments: num(4, base.segments as f64)? as usize,
        ..base
    };
    let duration = num(3, 12.0)?;
    let trace = std::env::var_os("LIFT_TRACE").is_some();
    let start = Instant::now();
    let mut scene = RopeBlockScene::new(params)?;
    let setup = start.elapsed().as_secs_f64();
    let names = scene.output_names().to_vec();
    let peaks = hoist(&mut scene, duration, 0.05, |scene| {
        if std::env::var_os("LIFT_ROWS").is_some() {
            let row = scene.outputs();
            let pick: Vec<String> = names
                .iter()
                .zip(&row)
                .filter(|(n, _)| {
                    n.starts_with("sling0")
                        || n.starts_with("contact0.")
                        || n.starts_with("contact1.")
                        || n.as_str() == "hook0.load"
                        || n.as_str() == "contact.count"
                        || n.as_str() == "block.vz"
                })
                .map(|(n, x)| format!("{n}={x:.4e}"))
                .collect();
            eprintln!("t {:.2} {}", scene.sim.time(), pick.join(" "));
        }
        if trace {
            let st = scene.sim.sim.stats();
            eprintln!(
                "t {:.2} wall {:.3} steps {} rejected {} newton {} failures {} fact {} last_h {:.2e} {:?}",
                scene.sim.time(),
                start.elapsed().as_secs_f64(),
                st.steps,
                st.rejected,
                st.newton_iterations,
                st.newton_failures,
                st.factorizations,
                st.last_step,
                scene.sim.counters
            );
        }
        true
    })?;
    let (peak_load, peak_t) = (peaks.hook_load, peaks.sling_tension);
    let wall = start.elapsed().as_secs_f64();
    let st = scene.sim.sim.stats();
    println!(
        "{kind:?}: set-up {setup:.3} s, total {wall:.3} s wall ({:.1}x real time); peak load {:.3} kN, peak tension {:.3} kN",
        duration / wall,
        peak_load / 1e3,
        peak_t / 1e3
    );
    println!("{st:?}");
    println!("counters: {:?}", scene.sim.counters);
    Ok(())
}
