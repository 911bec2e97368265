use mbcosim::math::Vec3;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};
fn main() {
    let mut scene = RopeBlockScene::new(RopeBlockParams::default()).unwrap();
    let t0 = std::time::Instant::now();
    let mut last = (0u64, 0u64);
    for k in 0..200 {
        let t = scene.sim.time();
        let v = if (1.0..9.0).contains(&t) { 0.2 } else { 0.0 };
        if k == 0 || (t - 1.0).abs() < 1e-9 {
            scene.set_hook(0, Vec3::new(0.0, 0.0, v), 0.0).unwrap();
        }
        scene.step(0.05).unwrap();
        let s = scene.sim.sim.stats();
        if s.steps - last.0 > 20 || k % 10 == 0 {
            println!(
                "t {:.2} wall {:.2} steps +{} fails +{} h {:.2e} counters {:?} contacts {}",
                scene.sim.time(),
                t0.elapsed().as_secs_f64(),
                s.steps - last.0,
                s.newton_failures - last.1,
                s.last_step,
                scene.sim.counters,
                scene.sim.structure.n_contacts()
            );
        }
        last = (s.steps, s.newton_failures);
    }
}
