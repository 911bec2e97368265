//! Our side of the MuJoCo capstan benchmark (issue #19, benches/mujoco_capstan.sh): the sliding
//! drum of `tests/rope/rig.rs` (`sliding_drum(k)`: k edges of circumradius 0.52 m, 180 degrees of
//! wrap, steel rope EA 7.5e7 N, 6.4 kg/m, mu 0.2, undamped, pulled at 9.81 kN and 21.6 kN so it
//! slides), run to 0.3 s with the settings of `examples/rope_drum_cost.rs` (h_max 1 ms).
//!
//! Timed run: one `advance_to(0.3)` (as rope_drum_cost), CPU time of the process's threads
//! (sum of /proc/self/task/*/schedstat) and wall time, from after building the simulation.
//! Untimed run: the same simulation with output points every 1 ms from 0.15 s on, where the
//! tension ratio across the drum is read: tension of the last strand-1 segment (before the
//! first contact node) and of the first strand-2 segment (after the last), from
//! `rope_tensions` (what acts). Prints one line `key=value ...` for the benchmark script.
//! Run: `cargo run --release --example capstan_bench [-- k]` (default k = 32).

#[allow(dead_code)]
#[path = "../tests/rope/rig.rs"]
mod rig;

use mbcosim::rope::SlipMode;

/// CPU time [s] of all threads of this process (ns resolution, Linux).
fn cpu_time() -> f64 {
    let mut ns = 0u64;
    if let Ok(dir) = std::fs::read_dir("/proc/self/task") {
        for e in dir.flatten() {
            if let Ok(s) = std::fs::read_to_string(e.path().join("schedstat")) {
                ns += s
                    .split_whitespace()
                    .next()
                    .and_then(|v| v.parse::<u64>().ok())
                    .unwrap_or(0);
            }
        }
    }
    ns as f64 * 1e-9
}

/// The polygon law of the rig: product of the sharp-edge ratios over its turns.
fn polygon_law(w: &rig::Wrap, mu: f64) -> f64 {
    let mut dirs = vec![-w.e1];
    dirs.extend(w.vertices.windows(2).map(|v| (v[1] - v[0]).normalize()));
    dirs.push(w.e2);
    dirs.windows(2)
        .map(|d| {
            let x = mu * (0.5 * d[0].dot(&d[1]).clamp(-1.0, 1.0).acos()).tan();
            (1.0 + x) / (1.0 - x)
        })
        .product()
}

fn main() {
    let k: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(32);
    let t_end = 0.3;
    let w = rig::sliding_drum(k);
    let mu = w.props.friction;
    let capstan = (mu * std::f64::consts::PI).exp();
    let polygon = polygon_law(&w, mu);

    // timed run
    let mut sim = w.sim(rig::settings(1e-3));
    let (c0, w0) = (cpu_time(), std::time::Instant::now());
    if let Err(e) = sim.advance_to(t_end) {
        eprintln!("k = {k}: {e}");
        std::process::exit(1);
    }
    let (cpu, wall) = (cpu_time() - c0, w0.elapsed().as_secs_f64());
    let steps = sim.sim.stats().steps;

    // untimed run with output points: the ratio across the drum
    let mut sim = w.sim(rig::settings(1e-3));
    let (a, b) = (w.nodes, w.nodes + k);
    let mut ratios = Vec::new();
    let mut all_slide = true;
    for i in 150..=300 {
        let t = 1e-3 * i as f64;
        if let Err(e) = sim.advance_to(t) {
            eprintln!("k = {k}, output run: {e}");
            std::process::exit(1);
        }
        let ten = sim.rope_tensions(0);
        ratios.push(ten[b].0 / ten[a].0);
        all_slide &= sim.slip_modes().iter().all(|m| *m == SlipMode::SlipForward);
    }
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let end = *ratios.last().unwrap();
    let worst = ratios
        .iter()
        .map(|r| (r / polygon - 1.0).abs())
        .fold(0.0, f64::max);
    println!(
        "side=ours k={k} t_end={t_end} steps={steps} cpu_s={cpu:.6} wall_s={wall:.6} \
         ms_per_step={:.6} ratio_end={end:.9} ratio_mean={mean:.9} \
         err_end_capstan={:+.3e} err_end_polygon={:+.3e} worst_err_polygon_0.15_0.3={worst:.3e} \
         capstan_law={capstan:.9} polygon_law={polygon:.9} all_sliding={all_slide}",
        1e3 * cpu / steps as f64,
        end / capstan - 1.0,
        end / polygon - 1.0,
    );
}
