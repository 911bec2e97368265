use mbcosim::math::Vec3;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};
use std::time::Instant;

fn main() {
    let p = RopeBlockParams::turnover();
    let t0 = Instant::now();
    let mut scene = RopeBlockScene::new(p).unwrap();
    println!("build+settle {:.3} s", t0.elapsed().as_secs_f64());
    let names = scene.output_names().to_vec();
    scene.set_hook(1, Vec3::new(0.0, 0.0, -0.4), 0.0).unwrap();
    let t1 = Instant::now();
    for _ in 0..30 {
        if let Err(e) = scene.step(1.0) {
            println!("error {e}");
            break;
        }
        let o = scene.outputs();
        let g = |n: &str| o[names.iter().position(|x| x == n).unwrap()];
        let q = mbcosim::math::Quat::from_quaternion(nalgebra::Quaternion::new(
            g("block.qw"),
            g("block.qx"),
            g("block.qy"),
            g("block.qz"),
        ));
        let (roll, _, _) = q.euler_angles();
        println!(
            "t {:.1} roll {:.1} deg hookA {:.0} kN hookB {:.0} kN contacts {} slings T {:.0} {:.0} {:.0} {:.0} counters {:?} steps {}",
            g("time"),
            roll.to_degrees(),
            g("hook0.load") / 1e3,
            g("hook1.load") / 1e3,
            g("contact.count"),
            g("sling0.tension_hook") / 1e3,
            g("sling1.tension_hook") / 1e3,
            g("sling2.tension_hook") / 1e3,
            g("sling3.tension_hook") / 1e3,
            scene.sim.counters,
            scene.sim.sim.stats().steps
        );
    }
    println!("wall {:.2} s", t1.elapsed().as_secs_f64());
}
