use mbcosim::math::Vec3;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};
use std::time::Instant;

fn main() {
    let mut p = RopeBlockParams::default();
    p.settle = std::env::var("SETTLE").is_ok();
    if let Ok(mu) = std::env::var("MU") {
        p.rope.friction = mu.parse().unwrap();
    }
    if std::env::var("NOCONTACT").is_ok() {
        p.contact = false;
    }
    if let Ok(h) = std::env::var("HMAX") {
        p.h_max = h.parse().unwrap();
    }
    if let Some(n) = std::env::args().nth(1) {
        p.segments = n.parse().unwrap();
    }
    let t0 = Instant::now();
    let mut scene = RopeBlockScene::new(p).unwrap();
    println!(
        "build+settle {:.3} s, counters {:?}",
        t0.elapsed().as_secs_f64(),
        scene.sim.counters
    );
    let names = scene.output_names().to_vec();
    let show = |scene: &mut RopeBlockScene| {
        let o = scene.outputs();
        let g = |n: &str| o[names.iter().position(|x| x == n).unwrap()];
        println!(
            "t {:.2} hook load {:.1} kN, sling0 {:.1}/{:.1} kN, contacts {}, N0 {:.1} kN F0 {:.2} kN slip0 {}, block z {:.4}, stats {:?}",
            g("time"),
            g("hook0.load") / 1e3,
            g("sling0.tension_hook") / 1e3,
            g("sling0.tension_lug") / 1e3,
            g("contact.count"),
            g("contact0.normal") / 1e3,
            g("contact0.friction") / 1e3,
            g("contact0.slip"),
            g("block.z"),
            scene.sim.sim.stats()
        );
    };
    show(&mut scene);
    let t1 = Instant::now();
    scene.set_hook(0, Vec3::new(0.0, 0.0, 0.2), 0.0).unwrap();
    let n_out: usize = std::env::var("NOUT")
        .map(|s| s.parse().unwrap())
        .unwrap_or(4);
    for _ in 0..n_out {
        scene.step(0.5).unwrap();
        show(&mut scene);
    }
    println!(
        "5 s simulated in {:.3} s, steps {:?}",
        t1.elapsed().as_secs_f64(),
        scene.sim.sim.stats()
    );
}
