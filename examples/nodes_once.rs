//! Cost per step of one straight sling with N segments (bench_rope part b), for profiling:
//! `cargo run --release --example nodes_once -- [segments] [seconds] [rtol]` (default rtol: the
//! scene's).
use mbcosim::math::Vec3;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};
use std::time::Instant;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let seg: usize = args.first().and_then(|s| s.parse().ok()).unwrap_or(5000);
    let dur: f64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(0.5);
    let mut p = RopeBlockParams::single_sling(seg);
    if let Some(rtol) = args.get(2).and_then(|s| s.parse().ok()) {
        p.rtol = rtol;
    }
    let t0 = Instant::now();
    let mut scene = RopeBlockScene::new(p)?;
    let setup = t0.elapsed().as_secs_f64();
    scene.set_hook(0, Vec3::new(0.0, 0.0, 0.2), 0.0)?;
    let s0 = scene.sim.sim.stats();
    let start = Instant::now();
    for _ in 0..(dur / 0.05).round() as usize {
        scene.step(0.05)?;
    }
    let wall = start.elapsed().as_secs_f64();
    let st = scene.sim.sim.stats();
    println!(
        "{seg} segments: set-up {setup:.3} s, {} steps, {:.3} ms per step, newton {}, factorizations {}",
        st.steps - s0.steps,
        1e3 * wall / (st.steps - s0.steps) as f64,
        st.newton_iterations - s0.newton_iterations,
        st.factorizations - s0.factorizations
    );
    Ok(())
}
