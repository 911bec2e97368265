//! Every shipped rig starts at rest (issue #42): the lift (`scenario = 0`) and the turn-over
//! (`scenario = 1`) are settled into static equilibrium with the rope free to slide through and
//! along every edge, then every node sticks where it came to rest. So at t = 0 each node is
//! inside its Coulomb cone (it carries no friction but round-off, below 1e-6 mu N), and with no input the
//! scene stays at rest: kinetic energy below 1e-9 J at t = 0 and over 5 s (0.1 s communication
//! steps), against the zero of a static equilibrium. Before, the settlement held each node on
//! its edge by the hold's spring at the rigging point: the turn-over started with a sticking node
//! carrying 104,557 N of friction against mu N = 81,794 N (1.278 mu N), slid within 0.01 s and
//! had 35 J of kinetic energy after 5 s.

use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};

#[test]
fn shipped_rigs_start_at_rest_inside_their_cones() {
    let mut failures = Vec::new();
    for (name, p) in [
        ("lift", RopeBlockParams::default()),
        ("turn-over", RopeBlockParams::turnover()),
    ] {
        let mu = p.rope.friction;
        let mut scene = RopeBlockScene::new(p).unwrap();
        let names = scene.output_names().to_vec();
        let col = |n: &str| names.iter().position(|x| x == n).unwrap();
        let out = scene.outputs();
        let count = out[col("contact.count")] as usize;
        let mut worst_cone = 0.0f64;
        for i in 0..count.min(scene.params.contact_outputs) {
            let (n, f) = (
                out[col(&format!("contact{i}.normal"))],
                out[col(&format!("contact{i}.friction"))],
            );
            worst_cone = worst_cone.max(f / (mu * n));
            // no friction but the hold's round-off (stiffness 10 EA / L0 times the last bits of
            // the node's coordinate along the edge: 2e-6 N here)
            if !(n > 0.0 && f <= 1e-6 * mu * n) {
                failures.push(format!(
                    "{name}: contact {i} starts with friction {f:.6e} N at N {n:.6e} N"
                ));
            }
        }
        let mut kinetic = out[col("energy.kinetic")];
        for _ in 0..50 {
            scene.step(0.1).unwrap();
            kinetic = kinetic.max(scene.outputs()[col("energy.kinetic")]);
        }
        println!(
            "{name}: {count} contact nodes, friction / (mu N) at t = 0 at most {worst_cone:.3e}, kinetic energy over 5 s at most {kinetic:.3e} J"
        );
        if count == 0 {
            failures.push(format!("{name}: no contact nodes"));
        }
        if kinetic >= 1e-9 {
            failures.push(format!(
                "{name}: kinetic energy {kinetic:.3e} J with no input"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
