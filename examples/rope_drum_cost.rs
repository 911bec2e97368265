//! Cost per step of a rope sliding around a polygonal drum against the number of contact nodes
//! (issue #19: the return mapping along the run). The drum of `tests/rope/reports.rs`: k edges of
//! circumradius 0.52 m, 180 degrees of wrap, pulled at 9.81 kN and 21.6 kN (gross slip), 0.3 s.
//! Run: `cargo run --release --example rope_drum_cost [-- k ...]` (default k = 8 16 32 64 128
//! 256). Prints steps, Newton work, CPU time of the thread (from `/proc/thread-self/schedstat`,
//! so other load on the machine counts less than in wall time; wall time where that file is
//! missing) and time per step, then the exponent of the cost per step between the smallest and
//! the largest k (least squares on log-log). Each k runs three times; the least time counts.

#[allow(dead_code)]
#[path = "../tests/rope/rig.rs"]
mod rig;

fn main() {
    let mut ks: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    if ks.is_empty() {
        ks = vec![8, 16, 32, 64, 128, 256];
    }
    let mut pts = Vec::new();
    for &k in &ks {
        let mut wall = f64::INFINITY;
        let mut s = Default::default();
        for _ in 0..3 {
            let mut sim = rig::sliding_drum(k).sim(rig::settings(1e-3));
            let start = cpu_seconds();
            if let Err(e) = sim.advance_to(0.3) {
                eprintln!("k = {k}: {e}");
                std::process::exit(1);
            }
            wall = wall.min(cpu_seconds() - start);
            s = sim.sim.stats();
        }
        let per_step = 1e3 * wall / s.steps as f64;
        println!(
            "k = {k:3}: {} steps, {} Newton iterations, {} Jacobians, {} factorizations, {} residuals in {wall:.3} s CPU, {per_step:.3} ms per step",
            s.steps, s.newton_iterations, s.jacobians, s.factorizations, s.rhs_evaluations
        );
        pts.push(((k as f64).ln(), per_step.ln()));
    }
    if pts.len() >= 2 {
        let n = pts.len() as f64;
        let (mx, my) = pts
            .iter()
            .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
        let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        println!(
            "cost per step ~ k^{:.2} (least squares), k^{:.2} (first to last)",
            sxy / sxx,
            (last.1 - first.1) / (last.0 - first.0)
        );
    }
}

/// CPU time of this thread [s] (wall time since the first call where the kernel does not tell).
fn cpu_seconds() -> f64 {
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|t| t.split_whitespace().next()?.parse::<f64>().ok())
        .map(|ns| ns * 1e-9)
        .unwrap_or_else(|| {
            START
                .get_or_init(std::time::Instant::now)
                .elapsed()
                .as_secs_f64()
        })
}
