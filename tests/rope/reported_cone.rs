//! The contact forces a user reads (issue #42): `contact{i}.normal`, `contact{i}.friction` and
//! `contact{i}.slip` from [`RopeBlockScene::outputs`] (what the FMU returns), checked against
//! Coulomb's law at every communication point: `friction <= mu N (1 + 1e-9)` at every node with
//! `N > 0`, `friction >= mu N (1 - 1e-9)` wherever the slip flag says the rope slides, and with
//! friction off exactly 0 friction and slip flag 0 (no friction element acts: the edge hold has
//! no stiffness and a frictionless node carries equal tensions). Before, the outputs were the line
//! joint's multipliers plus the hold: they carried the node's lumped rope mass (30.76 N across
//! the edge at rest with friction off, the slip flag flipping between 1 and -1) and
//! friction / (mu N) reached 1.952 in the default lift.

use mbcosim::math::Vec3;
use mbcosim::rope::friction::FrictionLaw;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};

/// Output columns of one contact slot.
struct Slot {
    normal: usize,
    friction: usize,
    slip: usize,
    sling: usize,
}

fn slots(scene: &RopeBlockScene) -> Vec<Slot> {
    let names = scene.output_names();
    let col = |n: String| names.iter().position(|x| *x == n).unwrap();
    (0..scene.params.contact_outputs)
        .map(|i| Slot {
            normal: col(format!("contact{i}.normal")),
            friction: col(format!("contact{i}.friction")),
            slip: col(format!("contact{i}.slip")),
            sling: col(format!("contact{i}.sling")),
        })
        .collect()
}

/// What the outputs showed over a run.
#[derive(Debug, Default)]
struct Cone {
    /// Node samples with `N > 0`, and those the slip flag reports sliding.
    samples: usize,
    sliding: usize,
    /// Largest friction / (mu N), and the least while sliding.
    worst: f64,
    least_sliding: f64,
    bad: Vec<String>,
}

impl Cone {
    fn check(&mut self, t: f64, out: &[f64], slots: &[Slot], mu: f64) {
        for (i, s) in slots.iter().enumerate() {
            if out[s.sling] < 0.0 {
                continue;
            }
            let (n, f, slip) = (out[s.normal], out[s.friction], out[s.slip]);
            if n <= 0.0 {
                continue;
            }
            self.samples += 1;
            let r = f / (mu * n);
            self.worst = self.worst.max(r);
            let sliding = slip != 0.0;
            if sliding {
                self.sliding += 1;
                self.least_sliding = self.least_sliding.min(r);
            }
            if (r > 1.0 + 1e-9 || (sliding && r < 1.0 - 1e-9)) && self.bad.len() < 6 {
                self.bad.push(format!(
                    "t = {t:.3} s, slot {i}: friction {f:.6e} N = {r:.12} mu N (N {n:.6e} N), slip {slip}"
                ));
            }
        }
    }
}

/// Runs `scene` over `steps` communication steps of `h` [s], `hooks(t)` setting the hook rates
/// before each step, and checks the contact outputs after each.
fn run(
    mut scene: RopeBlockScene,
    steps: usize,
    h: f64,
    hooks: impl Fn(&mut RopeBlockScene, f64),
) -> Cone {
    let mu = scene.params.rope.friction;
    let slots = slots(&scene);
    let mut cone = Cone {
        least_sliding: f64::INFINITY,
        ..Cone::default()
    };
    let out = scene.outputs();
    cone.check(0.0, &out, &slots, mu);
    for k in 0..steps {
        let t = k as f64 * h;
        hooks(&mut scene, t);
        scene.step(h).unwrap();
        cone.check(t + h, &scene.outputs(), &slots, mu);
    }
    cone
}

fn assert_inside(name: &str, cone: &Cone, min_samples: usize) {
    println!(
        "{name}: {} node samples ({} sliding), max reported friction / (mu N) {:.12}, least while sliding {:.12}",
        cone.samples, cone.sliding, cone.worst, cone.least_sliding
    );
    assert!(
        cone.samples >= min_samples,
        "{name}: {} samples",
        cone.samples
    );
    assert!(cone.bad.is_empty(), "{name}: {:#?}", cone.bad);
}

#[test]
fn lift_reports_contact_forces_inside_the_cone() {
    // the reviewer's lift: hoist at 0.2 m/s after 1 s, 0.05 s communication steps, 3 s
    let p = RopeBlockParams::default();
    let hoist = |scene: &mut RopeBlockScene, t: f64| {
        let vz = if t < 1.0 - 1e-9 { 0.0 } else { 0.2 };
        scene.set_hook(0, Vec3::new(0.0, 0.0, vz), 0.0).unwrap();
    };
    let cone = run(RopeBlockScene::new(p.clone()).unwrap(), 60, 0.05, hoist);
    assert_inside("lift", &cone, 200);
    assert!(cone.sliding > 0, "the lift never slid through a node");
    // the same lift with the hoist ramped in over 0.5 s
    let ramped = RopeBlockParams {
        hook_ramp: 0.5,
        ..p
    };
    let cone = run(RopeBlockScene::new(ramped).unwrap(), 60, 0.05, hoist);
    assert_inside("lift, hoist ramped", &cone, 200);
}

#[test]
fn lift_reports_contact_forces_inside_the_cone_under_the_pseudo_coefficient() {
    // the reviewer's lift under the rope paper's friction law (issue #45 item 4): the cone's
    // criteria do not depend on how it splits friction between edge and rope
    let mut p = RopeBlockParams::default();
    p.rope.friction_law = FrictionLaw::PseudoCoefficient;
    let hoist = |scene: &mut RopeBlockScene, t: f64| {
        let vz = if t < 1.0 - 1e-9 { 0.0 } else { 0.2 };
        scene.set_hook(0, Vec3::new(0.0, 0.0, vz), 0.0).unwrap();
    };
    let cone = run(RopeBlockScene::new(p).unwrap(), 60, 0.05, hoist);
    assert_inside("lift, pseudo coefficient", &cone, 200);
    assert!(cone.sliding > 0, "the lift never slid through a node");
}

#[test]
fn turnover_reports_contact_forces_inside_the_cone() {
    // crane B lowering its slings at 0.4 m/s, as the shipped turn-over scenario is driven
    let scene = RopeBlockScene::new(RopeBlockParams::turnover()).unwrap();
    let lower = |scene: &mut RopeBlockScene, t: f64| {
        if t == 0.0 {
            scene.set_hook(1, Vec3::new(0.0, 0.0, -0.4), 0.0).unwrap();
        }
    };
    let cone = run(scene, 40, 0.05, lower);
    assert_inside("turn-over", &cone, 60);
}

#[test]
fn friction_off_reports_exactly_zero_friction_and_no_slip() {
    // a block hanging at rest on frictionless slings (the reviewer's CLI case): the rope runs
    // freely through every node, so no friction acts; the normal force is the bisector's share of
    // the two equal tensions, checked against the reported tensions independently
    // under both friction laws (issue #45 item 4)
    for (integrator, law) in [
        (
            mbcosim::integrator::IntegratorKind::GenAlpha,
            FrictionLaw::EdgeFirst,
        ),
        (
            mbcosim::integrator::IntegratorKind::Bdf,
            FrictionLaw::EdgeFirst,
        ),
        (
            mbcosim::integrator::IntegratorKind::GenAlpha,
            FrictionLaw::PseudoCoefficient,
        ),
    ] {
        let mut p = RopeBlockParams {
            integrator,
            ..RopeBlockParams::default()
        };
        p.rope.friction = 0.0;
        p.rope.friction_law = law;
        let mut scene = RopeBlockScene::new(p).unwrap();
        let slots = slots(&scene);
        let mut seen = 0;
        for k in 0..=4 {
            if k > 0 {
                scene.step(0.5).unwrap();
            }
            let out = scene.outputs();
            for (i, s) in slots.iter().enumerate() {
                if out[s.sling] < 0.0 {
                    continue;
                }
                seen += 1;
                assert_eq!(
                    (out[s.friction], out[s.slip]),
                    (0.0, 0.0),
                    "{integrator:?}, {law:?}, t = {} s, slot {i}",
                    0.5 * k as f64
                );
            }
            for rep in scene.sim.contact_reports() {
                // N = |T_prev e_prev + T_next e_next| (the pull has no other component)
                let seg = rep.segments;
                let want = (rep.e_prev * seg.t_prev + rep.e_next * seg.t_next).norm();
                assert!(seg.t_prev == seg.t_next, "{seg:?}");
                let n = rep.reaction.normal;
                assert!((n - want).abs() <= 1e-12 * want, "N {n} against {want}");
            }
        }
        assert!(seen >= 20, "{integrator:?}: {seen} samples");
    }
}
