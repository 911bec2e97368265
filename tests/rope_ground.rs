//! Block-ground contact: the default 200 t block set down on a level ground by lowering the hook,
//! and dragged along the ground by the hook. Checked against the static balance of the whole
//! rigging, Coulomb's law through the whole model, and the energy balance.
//! `cargo test --release --test rope_ground -- --nocapture` prints the figures.

mod common;

use common::force_effect_names;
use common::outputs::energy_balance;
use mbcosim::integrator::IntegratorKind;
use mbcosim::math::Vec3;
use mbcosim::scene::rope_block::params::GroundParams;
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};

/// The default lift with 20 segments per sling over a ground at `height` [m] (the block's
/// bottom starts at 0).
fn scene(height: f64) -> RopeBlockScene {
    scene_with(height, IntegratorKind::GenAlpha)
}

fn scene_with(height: f64, integrator: IntegratorKind) -> RopeBlockScene {
    let p = RopeBlockParams {
        segments: 20,
        integrator,
        ground: Some(GroundParams {
            height,
            ..GroundParams::default()
        }),
        ..RopeBlockParams::default()
    };
    RopeBlockScene::new(p).unwrap()
}

struct Probe {
    names: Vec<String>,
}

impl Probe {
    fn new(s: &RopeBlockScene) -> Self {
        Probe {
            names: s.output_names().to_vec(),
        }
    }
    fn get(&self, row: &[f64], name: &str) -> f64 {
        row[self.names.iter().position(|n| n == name).unwrap()]
    }
    /// Kinetic + potential + dissipated - input - events [J].
    fn balance(&self, row: &[f64]) -> f64 {
        energy_balance(&self.names)(row)
    }
}

/// Weight of everything [N]: block, rope nodes, contact nodes.
fn weight(s: &RopeBlockScene) -> f64 {
    s.sim.total_mass() * 9.81
}

#[test]
fn block_partly_set_down_balances_hook_and_ground() {
    // ground 5 cm below the block's bottom: the slings stretch by about 7.6 cm under the full
    // weight, so the block settles on the ground; lowering the hook by 2 cm moves more of the
    // weight onto the ground (gen-alpha and BDF)
    for integrator in [IntegratorKind::GenAlpha, IntegratorKind::Bdf] {
        partly_set_down(integrator);
    }
}

fn partly_set_down(integrator: IntegratorKind) {
    let mut s = scene_with(-0.05, integrator);
    let probe = Probe::new(&s);
    let b0 = probe.balance(&s.outputs());
    let w = weight(&s);
    let mut drift: f64 = 0.0;
    for k in 0..160 {
        let v = if k < 4 { -0.1 } else { 0.0 };
        s.set_hook(0, Vec3::new(0.0, 0.0, v), 0.0).unwrap();
        s.step(0.05).unwrap();
        drift = drift.max((probe.balance(&s.outputs()) - b0).abs());
    }
    let row = s.outputs();
    let normal = probe.get(&row, "ground.normal");
    let hook = -probe.get(&row, "hook0.fz");
    let friction = probe.get(&row, "ground.friction");
    let steps = s.sim.sim.stats().steps;
    println!(
        "{integrator:?}: ground {normal:.1} N, hook {hook:.1} N, sum {:.1} N, weight {w:.1} N, friction {friction:.3} N, balance drift {drift:.1} J, {steps} steps",
        normal + hook,
    );
    // at rest the ground and the hook carry everything
    assert!(
        ((normal + hook) / w - 1.0).abs() < 1e-3,
        "ground {normal} N + hook {hook} N against a weight of {w} N"
    );
    assert!(
        normal > 0.3 * w && hook > 0.3 * w,
        "both must carry: ground {normal} N, hook {hook} N"
    );
    // symmetric slings: no net horizontal load, no friction to speak of
    assert!(friction < 1e-3 * w, "friction {friction} N at rest");
    assert!(drift < 1e-3 * w, "energy balance drifted by {drift} J");
    assert!(
        steps < 4000,
        "{integrator:?}: {steps} steps for 8 s at rest"
    );
}

#[test]
fn block_set_down_until_the_slings_hang_slack() {
    // the default lift (100 segments per sling) over a ground at the block's bottom: the block
    // settles onto it, then the hook is lowered by 0.5 m, so the slings hang slack from the hook
    // over their deck edges with a few kN each, and held for 3 s. Until the rope's damping
    // stopped switching on the speeds (src/rope/segment.rs) this run fell to steps of tens of
    // microseconds and the energy guard stopped it within 0.7 s (1.1e5 J of spurious damping
    // work).
    let p = RopeBlockParams {
        ground: Some(GroundParams::default()),
        ..RopeBlockParams::default()
    };
    let mut s = RopeBlockScene::new(p).unwrap();
    let probe = Probe::new(&s);
    let b0 = probe.balance(&s.outputs());
    let w = weight(&s);
    let mut drift: f64 = 0.0;
    for k in 0..160 {
        // commanded where it changes, as an FMU importer's input does (each command restarts
        // the hook's 0.5 s ramp from where it is)
        if k == 0 || k == 100 {
            let v = if k < 100 { -0.1 } else { 0.0 };
            s.set_hook(0, Vec3::new(0.0, 0.0, v), 0.0).unwrap();
        }
        s.step(0.05)
            .unwrap_or_else(|e| panic!("stopped at t = {} s: {e}", s.sim.time()));
        drift = drift.max((probe.balance(&s.outputs()) - b0).abs());
    }
    let row = s.outputs();
    let normal = probe.get(&row, "ground.normal");
    let hook = -probe.get(&row, "hook0.fz");
    let steps = s.sim.sim.stats().steps;
    println!(
        "slack slings: ground {normal:.1} N, hook {hook:.1} N, sum {:.1} N, weight {w:.1} N, balance drift {drift:.1} J, {steps} steps for 8 s, {} contact nodes",
        normal + hook,
        probe.get(&row, "contact.count")
    );
    // the ground carries the block, the hook only what the slack slings pass on (their own
    // weight is 4 x 330 kg = 13 kN; a few kN more through their catenaries)
    assert!(
        ((normal + hook) / w - 1.0).abs() < 1e-3,
        "ground {normal} N + hook {hook} N against a weight of {w} N"
    );
    assert!(hook < 0.02 * w, "the slings must hang slack: hook {hook} N");
    assert!(drift < 5e-5 * w, "energy balance drifted by {drift} J");
    // the slings keep their contact nodes on the deck edges
    assert_eq!(probe.get(&row, "contact.count"), 4.0);
    // a step-count bound, not a timing (1,146 steps; the clamped damping took 25,000 steps for
    // the first 0.7 s)
    assert!(steps < 3000, "{steps} steps for 8 s");
}

#[test]
fn block_dragged_along_the_ground_slides_at_the_friction_limit() {
    // the partly set-down block (as above) dragged along its length by the hook at 0.2 m/s:
    // while it slides, the ground's friction is mu times its normal force, and over the run the
    // hook's horizontal pull balances the friction on average (the block ends at the hook's
    // speed, so its momentum hardly changed)
    let mut s = scene(-0.05);
    let probe = Probe::new(&s);
    let b0 = probe.balance(&s.outputs());
    let w = weight(&s);
    let mu = GroundParams::default().mu;
    let (mut pull, mut fric, mut n_avg) = (0.0, 0.0, 0);
    let mut worst_ratio: f64 = 0.0;
    let mut drift: f64 = 0.0;
    for k in 0..300 {
        let vz = if k < 4 { -0.1 } else { 0.0 };
        let vx = if k >= 40 { 0.2 } else { 0.0 };
        s.set_hook(0, Vec3::new(vx, 0.0, vz), 0.0).unwrap();
        s.step(0.05).unwrap();
        let row = s.outputs();
        drift = drift.max((probe.balance(&row) - b0).abs());
        if k >= 100 {
            let h = (probe.get(&row, "hook0.load").powi(2) - probe.get(&row, "hook0.fz").powi(2))
                .sqrt();
            let (f, n) = (
                probe.get(&row, "ground.friction"),
                probe.get(&row, "ground.normal"),
            );
            pull += h;
            fric += f;
            n_avg += 1;
            if probe.get(&row, "block.vx").abs() > 0.1 {
                worst_ratio = worst_ratio.max((f / n / mu - 1.0).abs());
            }
        }
    }
    let (pull, fric) = (pull / n_avg as f64, fric / n_avg as f64);
    let dissipated = probe.get(&s.outputs(), "energy.dissipated");
    println!(
        "mean pull {pull:.0} N, mean friction {fric:.0} N, friction/normal off mu by {worst_ratio:.2e} while sliding, balance drift {drift:.0} J of {dissipated:.0} J dissipated, {} steps",
        s.sim.sim.stats().steps
    );
    assert!(
        worst_ratio < 1e-2,
        "friction/normal off mu by {worst_ratio}"
    );
    assert!(
        fric > 0.05 * w,
        "the block must be dragged: mean friction {fric} N"
    );
    assert!(
        (pull / fric - 1.0).abs() < 0.03,
        "mean pull {pull} N against mean friction {fric} N"
    );
    assert!(
        drift < 1e-2 * dissipated,
        "energy balance drifted by {drift} J ({dissipated} J dissipated)"
    );
}

#[test]
fn the_ground_is_assembled_only_when_switched_on() {
    let names = |s: &RopeBlockScene| force_effect_names(&s.sim.sim.system.model);
    let off = RopeBlockScene::new(RopeBlockParams {
        segments: 4,
        ..RopeBlockParams::default()
    })
    .unwrap();
    let on = scene(-0.05);
    assert!(!names(&off).iter().any(|n| n == "ground-contact"));
    assert_eq!(
        names(&on).iter().filter(|n| *n == "ground-contact").count(),
        1
    );
    assert!(!off.output_names().iter().any(|n| n.starts_with("ground.")));
    // the block touches the ground with the vertices of its hull (the parametric block: the
    // bottom corners, the bilge facets and the deck corners)
    let points = on.sim.structure.ground.as_ref().unwrap().points.len();
    assert!((8..=64).contains(&points), "{points} hull vertices");
}
