//! Cost per step of a rope sliding around a polygonal drum against the number of contact nodes
//! (issue #19: the return mapping along the run). The drum of `tests/rope/reports.rs`: k edges of
//! circumradius 0.52 m, 180 degrees of wrap, pulled at 9.81 kN and 21.6 kN (gross slip), 0.3 s.
//! Run: `cargo run --release --example rope_drum_cost`. Prints steps, wall time and time per step.

#[allow(dead_code)]
#[path = "../tests/rope/rig.rs"]
mod rig;

fn main() {
    for k in [8, 16, 32, 64] {
        let mut sim = rig::sliding_drum(k).sim(rig::settings(1e-3));
        let start = std::time::Instant::now();
        if let Err(e) = sim.advance_to(0.3) {
            eprintln!("k = {k}: {e}");
            std::process::exit(1);
        }
        let wall = start.elapsed().as_secs_f64();
        let steps = sim.sim.stats().steps;
        println!(
            "k = {k:3}: {steps} steps in {wall:.3} s, {:.3} ms per step",
            1e3 * wall / steps as f64
        );
    }
}
