//! A rig described as data (issue #21): the statics of user four-point lifts against hand
//! calculations, a user mesh with matching lugs getting its contact nodes, and every bad rig
//! refused with its named error.
//!
//! The closed forms: a rigid block hangs from one hook by four straight slings (contact off, rope
//! weight negligible) with the hook above the centre of gravity, so every sling's line passes
//! through the hook and the moments balance by themselves. With the lugs mirror-symmetric about
//! the `x z` plane through the centre of gravity, slings `+y` and `-y` carry the same tension and
//! the three force equations leave two unknowns: the problem is statically determinate. The test
//! chooses the hanging pose, derives the tensions by hand, and gives each sling the unstretched
//! length `L0 = L / (1 + T / EA)` that makes this pose the equilibrium; the product, started from
//! a displaced block, must find the same pose and tensions. A statically indeterminate lift is
//! checked against an elastic solution computed here, independently of the product's code.

use mbcosim::math::Vec3;
use mbcosim::rope::RopeProps;
use mbcosim::rope::shell::parametric::BlockShape;
use mbcosim::scene::rope_block::{
    BlockGeometry, BlockRig, Lug, Rig, RigHook, RigSling, RopeBlockParams, RopeBlockScene, Route,
};

const G: f64 = 9.81;
const MASS: f64 = 250e3;
/// Box length, breadth, height [m].
const L: f64 = 20.0;
const B: f64 = 14.0;
const H: f64 = 8.0;

fn box_block(cog: Vec3) -> BlockRig {
    BlockRig {
        geometry: BlockGeometry::Shape(BlockShape {
            length: L,
            breadth: B,
            height: H,
            bilge_radius: 0.0,
            ..BlockShape::default()
        }),
        mass: Some(MASS),
        plate: None,
        cog: Some(cog),
        inertia: None,
        pose: None,
    }
}

/// Scene parameters for a rig: straight slings, contact off, a light rope.
fn params(rig: Rig) -> RopeBlockParams {
    RopeBlockParams {
        rig,
        contact: false,
        rope: RopeProps {
            mass_per_length: 1e-5,
            friction: 0.0,
            ..RopeProps::default()
        },
        segments: 20,
        ..RopeBlockParams::default()
    }
}

struct Lift {
    /// Hand-calculated tension [N], stretched length [m] and angle to the vertical [rad] per sling.
    tension: [f64; 4],
    stretched: [f64; 4],
    angle: [f64; 4],
    scene: RopeBlockScene,
}

/// Four lugs on the deck at `(+-a, +-b, H)`, the centre of gravity at `(cx, 0, 3.5)`, the hook
/// `zd` above the deck over the centre of gravity; slings 0 and 3 on the `+x` lugs.
fn four_point_lift(cx: f64, ea: [f64; 4], mbl: [f64; 4]) -> Lift {
    let (a, b, zd) = (8.0, 5.0, 16.0);
    let cog = Vec3::new(cx, 0.0, 3.5);
    let hook = Vec3::new(cx, 0.0, H + zd);
    let lugs = [
        Vec3::new(a, b, H),
        Vec3::new(-a, b, H),
        Vec3::new(-a, -b, H),
        Vec3::new(a, -b, H),
    ];
    let w = MASS * G;
    // x: 2 Tp (cx - a) / Lp + 2 Tm (cx + a) / Lm = 0; z: 2 zd (Tp / Lp + Tm / Lm) = W
    let per_length_p = w * (a + cx) / (4.0 * zd * a);
    let per_length_m = w * (a - cx) / (4.0 * zd * a);
    let mut tension = [0.0; 4];
    let mut stretched = [0.0; 4];
    let mut angle = [0.0; 4];
    let mut slings = Vec::new();
    for (k, lug) in lugs.iter().enumerate() {
        let len = (hook - lug).norm();
        let t = len
            * if lug.x > 0.0 {
                per_length_p
            } else {
                per_length_m
            };
        tension[k] = t;
        stretched[k] = len;
        angle[k] = (zd / len).acos();
        slings.push(RigSling {
            length: Some(len / (1.0 + t / ea[k])),
            ea: Some(ea[k]),
            breaking_load: Some(mbl[k]),
            route: Route::Straight,
            ..RigSling::new(k, 0)
        });
    }
    let rig = Rig {
        block: box_block(cog),
        lugs: lugs.iter().map(|&position| Lug { position }).collect(),
        slings,
        hooks: vec![RigHook {
            position: hook,
            crane: 0,
        }],
    };
    let p = RopeBlockParams {
        // start displaced: 5 cm low, off to the side
        block_origin: Vec3::new(0.03, -0.02, -0.05),
        ..params(rig)
    };
    let scene = RopeBlockScene::new(p).expect("the rig hangs");
    Lift {
        tension,
        stretched,
        angle,
        scene,
    }
}

fn out(scene: &mut RopeBlockScene, name: &str) -> f64 {
    scene
        .output(name)
        .unwrap_or_else(|| panic!("no output {name}"))
}

fn check_lift(mut lift: Lift, mbl: [f64; 4], label: &str) {
    let s = &mut lift.scene;
    for (k, &strength) in mbl.iter().enumerate() {
        let t = out(s, &format!("sling{k}.tension_lug"));
        let th = out(s, &format!("sling{k}.tension_hook"));
        let u = out(s, &format!("sling{k}.utilisation"));
        let ang = out(s, &format!("sling{k}.angle"));
        let rel = (t - lift.tension[k]) / lift.tension[k];
        println!(
            "{label} sling {k}: T {t:.3} N (hook end {th:.3} N), hand {:.3} N, rel {rel:+.2e}; utilisation {u:.6}; angle {:.6} deg (hand {:.6}); stretched {:.4} m",
            lift.tension[k],
            ang.to_degrees(),
            lift.angle[k].to_degrees(),
            lift.stretched[k]
        );
        assert!(
            rel.abs() < 1e-6,
            "{label} sling {k}: tension off by {rel:e}"
        );
        assert!(((th - lift.tension[k]) / lift.tension[k]).abs() < 1e-6);
        let u_hand = lift.tension[k] / strength;
        assert!(
            ((u - u_hand) / u_hand).abs() < 1e-6,
            "{label} sling {k}: utilisation {u} against {u_hand}"
        );
        assert!(
            (ang - lift.angle[k]).abs() < 1e-6,
            "{label} sling {k}: angle"
        );
    }
    let daf = out(s, "daf");
    assert!((daf - 1.0).abs() < 1e-6, "{label}: daf at rest {daf}");
    // the centre of gravity under the hook, the block level at its design height
    let (x, y, z) = (out(s, "block.x"), out(s, "block.y"), out(s, "block.z"));
    let hook = s.params.rig.hooks[0].position;
    let cog = s.params.rig.block.cog.unwrap();
    println!("{label}: centre of gravity at ({x:.9}, {y:.9}, {z:.9}) m, daf {daf:.9}");
    assert!(
        (x - hook.x).abs() < 1e-6 && y.abs() < 1e-6,
        "{label}: not under the hook"
    );
    assert!((z - cog.z).abs() < 1e-6, "{label}: height {z}");
}

#[test]
fn symmetric_four_point_lift_matches_the_closed_form() {
    let ea = [1.6e8; 4];
    let mbl = [2.5e6; 4];
    let lift = four_point_lift(0.0, ea, mbl);
    // symmetric: T = W / (4 cos theta) for every sling
    let t = MASS * G / (4.0 * lift.angle[0].cos());
    for tk in lift.tension {
        assert!((tk - t).abs() < 1e-9 * t);
    }
    check_lift(lift, mbl, "symmetric");
}

#[test]
fn asymmetric_four_point_lift_matches_the_closed_form() {
    // centre of gravity 1.5 m towards +x; the slings differ in stiffness and strength
    let ea = [1.6e8, 1.0e8, 1.2e8, 2.0e8];
    let mbl = [2.5e6, 1.5e6, 2.0e6, 3.0e6];
    let lift = four_point_lift(1.5, ea, mbl);
    assert!(
        lift.tension[0] > 1.3 * lift.tension[1],
        "the +x slings carry more"
    );
    check_lift(lift, mbl, "asymmetric");
}

/// The hanging pose of a rigid block on straight elastic slings to one fixed hook, solved here
/// independently of the product: Newton with a finite-difference Jacobian on the block's
/// translation `c` and roll/pitch `(rx, ry)` (yaw about the vertical through the hook is neutral:
/// every sling's length is unchanged by it), for the three forces and the two horizontal moments
/// about the centre of gravity. Returns the tension [N] of each sling.
fn elastic_solution(
    hook: Vec3,
    lugs: &[Vec3],
    cog: Vec3,
    l0: &[f64],
    ea: &[f64],
    weight: f64,
) -> Vec<f64> {
    use mbcosim::math::Quat;
    let pose = |x: &[f64; 5]| {
        let rot = Quat::from_scaled_axis(Vec3::new(x[3], x[4], 0.0));
        (Vec3::new(x[0], x[1], x[2]), rot)
    };
    let tensions = |x: &[f64; 5]| -> (Vec<f64>, Vec<Vec3>, Vec<Vec3>) {
        let (c, rot) = pose(x);
        let mut t = Vec::new();
        let mut dir = Vec::new();
        let mut arm = Vec::new();
        for (k, l) in lugs.iter().enumerate() {
            let r = rot * (l - cog);
            let d = hook - (c + r);
            let len = d.norm();
            t.push(ea[k] * (len / l0[k] - 1.0));
            dir.push(d / len);
            arm.push(r);
        }
        (t, dir, arm)
    };
    let residual = |x: &[f64; 5]| -> [f64; 5] {
        let (t, dir, arm) = tensions(x);
        let mut f = Vec3::new(0.0, 0.0, -weight);
        let mut m = Vec3::zeros();
        for ((tk, d), a) in t.iter().zip(&dir).zip(&arm) {
            f += d * *tk;
            m += a.cross(&(d * *tk));
        }
        [f.x, f.y, f.z, m.x / 10.0, m.y / 10.0]
    };
    let mut x = [cog.x, cog.y, cog.z, 0.0, 0.0];
    for _ in 0..50 {
        let r0 = residual(&x);
        let mut jac = nalgebra::SMatrix::<f64, 5, 5>::zeros();
        for j in 0..5 {
            let mut xp = x;
            let h = 1e-7 * (1.0 + x[j].abs());
            xp[j] += h;
            let rp = residual(&xp);
            for i in 0..5 {
                jac[(i, j)] = (rp[i] - r0[i]) / h;
            }
        }
        let dx = jac
            .lu()
            .solve(&nalgebra::SVector::<f64, 5>::from_column_slice(&r0))
            .unwrap();
        for (xj, dj) in x.iter_mut().zip(dx.iter()) {
            *xj -= dj;
        }
        if dx.norm() < 1e-13 {
            break;
        }
    }
    tensions(&x).0
}

#[test]
fn indeterminate_four_point_lift_matches_an_independent_elastic_solution() {
    // centre of gravity off in x and y, lugs not symmetric, slings of different stiffness and
    // length: four tensions, three force equations; the elastic solution decides
    let cog = Vec3::new(1.3, -0.8, 3.2);
    let hook = Vec3::new(1.0, -0.5, H + 15.0);
    let lugs = [
        Vec3::new(8.5, 5.0, H),
        Vec3::new(-7.0, 6.0, H),
        Vec3::new(-8.0, -5.5, H),
        Vec3::new(7.5, -4.0, H),
    ];
    let ea = [1.6e8, 1.0e8, 1.3e8, 2.0e8];
    let l0: Vec<f64> = lugs
        .iter()
        .enumerate()
        .map(|(k, l)| (hook - l).norm() * (1.0 - 0.002 * (1 + k % 2) as f64))
        .collect();
    let weight = MASS * G;
    let hand = elastic_solution(hook, &lugs, cog, &l0, &ea, weight);
    let rig = Rig {
        block: box_block(cog),
        lugs: lugs.iter().map(|&position| Lug { position }).collect(),
        slings: (0..4)
            .map(|k| RigSling {
                length: Some(l0[k]),
                ea: Some(ea[k]),
                route: Route::Straight,
                ..RigSling::new(k, 0)
            })
            .collect(),
        hooks: vec![RigHook {
            position: hook,
            crane: 0,
        }],
    };
    let mut scene = RopeBlockScene::new(params(rig)).expect("the rig hangs");
    for (k, t_ref) in hand.iter().enumerate() {
        let t = out(&mut scene, &format!("sling{k}.tension_lug"));
        let rel = (t - t_ref) / t_ref;
        println!("indeterminate sling {k}: T {t:.3} N, independent {t_ref:.3} N, rel {rel:+.2e}");
        assert!(rel.abs() < 1e-6, "sling {k}: {rel:e}");
    }
}
