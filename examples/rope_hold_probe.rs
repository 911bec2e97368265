use mbcosim::math::Vec3;
use mbcosim::scene::rope_block::build::rope_ctx;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};
fn main() {
    let mut scene = RopeBlockScene::new(RopeBlockParams::default()).unwrap();
    scene.set_hook(0, Vec3::new(0.0, 0.0, 0.2), 0.0).unwrap();
    for _ in 0..60 {
        if scene.step(0.01).is_err() {
            break;
        }
        let sim = &mut scene.sim;
        let st = sim.sim.state.clone();
        sim.sim.system.update_kinematics(&st.q, &st.v);
        let ctx = rope_ctx(&sim.map, sim.sim.system.kins(), &[], &st);
        let h = sim.map.rope.edge_hold(&ctx, 0).unwrap();
        let o = sim.map.rope_memory + sim.map.rope.contact_memory_offset(0);
        let reps = sim.contact_reports();
        println!(
            "t {:.3} steps {} fails {} u {:.6e} udot {:.3e} F {:.1} cap {:.1} state {} u0 {:.6e} N {:.0} Fe {:.1} Fr {:.1}",
            st.t,
            sim.sim.stats().steps,
            sim.sim.stats().newton_failures,
            h.u,
            h.u_dot,
            h.force,
            st.memory[o + 4],
            st.memory[o + 5],
            st.memory[o + 3],
            reps[0].reaction.normal,
            reps[0].reaction.along_edge,
            reps[0].reaction.along_rope
        );
    }
}
