use mbcosim::math::Vec3;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};

fn main() {
    let mut p = RopeBlockParams::default();
    p.settle = true;
    p.segments = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(20);
    if let Ok(mu) = std::env::var("MU") {
        p.rope.friction = mu.parse().unwrap();
    }
    if let Ok(c) = std::env::var("DAMP") {
        p.rope.axial_damping = c.parse().unwrap();
    }
    let mut scene = RopeBlockScene::new(p).unwrap();
    if std::env::var("NOREL").is_ok() {}
    let dt: f64 = std::env::var("DT")
        .map(|s| s.parse().unwrap())
        .unwrap_or(0.005);
    scene.set_hook(0, Vec3::new(0.0, 0.0, 0.2), 0.0).unwrap();
    for b in &scene.sim.sim.system.model.bodies {
        if (590..610).contains(&b.v_offset) {
            println!("{} at {}", b.name, b.v_offset);
        }
    }
    println!(
        "sling1 nodes {}, contact at {:?}",
        scene.sim.structure.ropes[1].nodes.len(),
        scene.sim.structure.ropes[1]
            .nodes
            .iter()
            .position(|n| n.contact.is_some())
    );
    let mut last = scene.sim.sim.stats();
    for k in 0..(2.0 / dt) as usize {
        let r = scene.step(dt);
        let s = scene.sim.sim.stats();
        let reps = scene.sim.contact_reports();
        let modes = scene.sim.slip_modes();
        if s.newton_failures > last.newton_failures || k < 20 {
            println!(
                "t {:.3} fails +{} steps +{} h {:.2e} modes {:?} counters {:?} T {:.0}/{:.0} N {:.0} Fe {:.0} Fr {:.0} turn {:.4} {:?}",
                scene.sim.time(),
                s.newton_failures - last.newton_failures,
                s.steps - last.steps,
                s.last_step,
                modes,
                scene.sim.counters,
                reps[0].segments.t_prev,
                reps[0].segments.t_next,
                reps[0].reaction.normal,
                reps[0].reaction.along_edge,
                reps[0].reaction.along_rope,
                reps[0].turn,
                r.err()
            );
        }
        last = s;
    }
}
#[allow(dead_code)]
fn _unused() {}
