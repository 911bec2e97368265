//! A block hanging at rest from slings over frictionless plate edges: every leg carries
//! T = W / (n cos beta), the same on both sides of its edge.

use mbcosim::math::Vec3;
use mbcosim::rope::RopeProps;
use mbcosim::rope::shell::parametric::BlockShape;
use mbcosim::scene::rope_block::{
    BlockGeometry, BlockRig, Lug, Rig, RigHook, RigSling, RopeBlockParams, RopeBlockScene,
};

#[test]
fn sling_legs_carry_weight_over_n_cos_beta() {
    let (l, b, h) = (18.0, 12.0, 7.0);
    let mass = 200e3;
    let g = 9.81;
    // two spreader hooks above x = +-6, four lugs on the side shell 1 m below the deck edges:
    // every sling lies in a plane normal to its edge
    let lug = |sx: f64, sy: f64| Lug {
        position: Vec3::new(sx * 6.0, sy * (0.5 * b + 0.3), h - 1.0),
    };
    let hook = |x: f64| RigHook {
        position: Vec3::new(x, 0.0, h + 15.0),
        crane: 0,
    };
    let params = RopeBlockParams {
        block_mass: mass,
        rig: Rig {
            block: BlockRig {
                geometry: BlockGeometry::Shape(BlockShape {
                    length: l,
                    breadth: b,
                    height: h,
                    bilge_radius: 0.0,
                    ..BlockShape::default()
                }),
                ..Rig::default().block
            },
            lugs: vec![
                lug(1.0, 1.0),
                lug(1.0, -1.0),
                lug(-1.0, 1.0),
                lug(-1.0, -1.0),
            ],
            slings: (0..4).map(|k| RigSling::new(k, k / 2)).collect(),
            hooks: vec![hook(6.0), hook(-6.0)],
        },
        rope: RopeProps {
            mass_per_length: 1e-3,
            friction: 0.0,
            ..RopeProps::default()
        },
        segments: 40,
        ..RopeBlockParams::default()
    };
    let mut scene = RopeBlockScene::new(params).unwrap();
    let names = scene.output_names().to_vec();
    let out = scene.outputs();
    let get = |n: &str| out[names.iter().position(|x| x == n).unwrap()];
    assert_eq!(get("contact.count"), 4.0, "one contact node per sling");
    let w = mass * g;
    let reports = scene.sim.contact_reports();
    for r in 0..4 {
        let rep = reports.iter().find(|x| x.rope == r).unwrap();
        let hook = scene.params.rig.hooks[scene.params.rig.slings[r].hook].position;
        // the leg from the edge to the hook, in the final (settled) geometry
        let pts = scene.sim.rope_points(r);
        let q = pts[1 + rep.node];
        let cos_beta = (hook - q).normalize().z;
        let t_ref = w / (4.0 * cos_beta);
        let (th, tl) = (
            get(&format!("sling{r}.tension_hook")),
            get(&format!("sling{r}.tension_lug")),
        );
        let rel = (th - t_ref) / t_ref;
        println!(
            "sling {r}: beta {:.3} deg, T hook {th:.1} N, T lug {tl:.1} N, reference W/(n cos beta) {t_ref:.1} N, rel err {rel:+.1e}",
            cos_beta.acos().to_degrees()
        );
        assert!(rel.abs() < 1e-4, "sling {r}: {th} vs {t_ref}");
        assert!(
            (th - tl).abs() < 1e-6 * th,
            "frictionless edge: equal tensions"
        );
    }
    // the hooks carry the weight
    let load = get("hook0.fz") + get("hook1.fz");
    assert!((-load / w - 1.0).abs() < 1e-4, "{load}");
}
