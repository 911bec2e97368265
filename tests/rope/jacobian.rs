//! Analytic K = -df/dx and D = -df/dv of the rope effect against central finite differences:
//! plain segments (taut, with damping, one end on a rotating block, one on a moving hook), a run
//! of contact nodes sticking and slipping (friction ratio with its angle dependence), bending
//! hinges and drag.

use mbcosim::effect::{EvalCtx, ForceEffect, JacobianSink};
use mbcosim::math::{Mat3, Matrix6, Quat, Vec3};
use mbcosim::model::kinematics::{BodyKin, evaluate};
use mbcosim::model::{BodyId, BodyInit, Model, ModelBuilder};
use mbcosim::rope::{
    ContactInit, EdgeHold, HookInit, LayoutPoint, LayoutRope, PointAt, RopeEffect, RopeProps,
    SlipMode,
};
use nalgebra::DMatrix;

struct Dense {
    k: DMatrix<f64>,
    d: DMatrix<f64>,
}

impl JacobianSink for Dense {
    fn add(&mut self, row: &BodyKin, col: &BodyKin, k: &Matrix6<f64>, d: &Matrix6<f64>) {
        if !row.is_free() || !col.is_free() {
            return;
        }
        let nr = if row.rotational { 6 } else { 3 };
        let nc = if col.rotational { 6 } else { 3 };
        for r in 0..nr {
            for c in 0..nc {
                self.k[(row.col + r, col.col + c)] += k[(r, c)];
                self.d[(row.col + r, col.col + c)] += d[(r, c)];
            }
        }
    }
}

fn forces(model: &Model, e: &RopeEffect, mem: &[f64], t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
    let mut kins = Vec::new();
    evaluate(model, q, v, &mut kins);
    let ctx = EvalCtx {
        t,
        kins: &kins,
        inputs: &[],
        memory: mem,
        frozen: &[],
    };
    let mut f = vec![0.0; model.n_v];
    e.add_forces(&ctx, &mut f);
    f
}

/// Checks K and D of `e` at the model's initial state; returns the worst relative errors.
fn check(model: &Model, e: &RopeEffect, mem: &[f64]) -> (f64, f64) {
    let (q, v) = (model.q0.clone(), model.v0.clone());
    let n = model.n_v;
    let mut kins = Vec::new();
    evaluate(model, &q, &v, &mut kins);
    let ctx = EvalCtx {
        t: 0.3,
        kins: &kins,
        inputs: &[],
        memory: mem,
        frozen: &[],
    };
    let mut sink = Dense {
        k: DMatrix::zeros(n, n),
        d: DMatrix::zeros(n, n),
    };
    e.add_jacobian(&ctx, &mut sink);
    let mut kfd = DMatrix::zeros(n, n);
    let mut dfd = DMatrix::zeros(n, n);
    let h = 1e-6;
    let mut qp = q.clone();
    let mut qm = q.clone();
    for c in 0..n {
        let mut dx = vec![0.0; n];
        dx[c] = h;
        model.retract(&q, &dx, &mut qp);
        dx[c] = -h;
        model.retract(&q, &dx, &mut qm);
        let fp = forces(model, e, mem, 0.3, &qp, &v);
        let fm = forces(model, e, mem, 0.3, &qm, &v);
        let mut vp = v.clone();
        let mut vm = v.clone();
        vp[c] += h;
        vm[c] -= h;
        let gp = forces(model, e, mem, 0.3, &q, &vp);
        let gm = forces(model, e, mem, 0.3, &q, &vm);
        for r in 0..n {
            kfd[(r, c)] = -(fp[r] - fm[r]) / (2.0 * h);
            dfd[(r, c)] = -(gp[r] - gm[r]) / (2.0 * h);
        }
    }
    let ek = (&sink.k - &kfd).amax() / kfd.amax().max(1e-300);
    let ed = (&sink.d - &dfd).amax() / dfd.amax().max(1e-300);
    if ek > 1e-6 {
        let diff = &sink.k - &kfd;
        let (mut bi, mut bv) = ((0, 0), 0.0);
        for r in 0..n {
            for c in 0..n {
                if diff[(r, c)].abs() > bv {
                    bv = diff[(r, c)].abs();
                    bi = (r, c);
                }
            }
        }
        println!(
            "worst at {bi:?}: analytic {:.4e}, fd {:.4e}",
            sink.k[bi], kfd[bi]
        );
    }
    (ek, ed)
}

/// A block (rotating), a hook, and a chain of particles forming a rope that wraps over three
/// contact nodes between a lug on the block and the hook.
fn setup(mode: SlipMode, props: RopeProps, contacts: bool) -> (Model, RopeEffect, Vec<f64>) {
    setup_with(mode, props, contacts, true)
}

/// `mode` selects the strain gradient along the rope (growing towards the hook for
/// `SlipForward`, towards the lug for `SlipBackward`, flat for `Stick`) and the friction
/// (0.05: the nodes slide; 5: they stick); `middle_sticks` gives the middle node mu = 0.9 so that
/// it sticks between two sliding ones.
fn setup_with(
    mode: SlipMode,
    props: RopeProps,
    contacts: bool,
    middle_sticks: bool,
) -> (Model, RopeEffect, Vec<f64>) {
    let mut b = ModelBuilder::new();
    let inertia = Mat3::from_diagonal(&Vec3::new(3.0, 4.0, 5.0));
    let blk = b
        .add_rigid_body(
            "block",
            50.0,
            inertia,
            BodyInit::at(Vec3::new(0.1, -0.2, 0.05))
                .oriented(Quat::from_scaled_axis(Vec3::new(0.3, -0.2, 0.5)))
                .moving(Vec3::new(0.2, 0.1, -0.3), Vec3::new(0.4, -0.7, 0.2)),
        )
        .unwrap();
    // a wrapped path: lug -> p1 -> c1 -> c2 -> c3 -> p2 -> p3 -> hook
    let pts = [
        Vec3::new(1.3, 0.2, 0.1),
        Vec3::new(1.9, 1.0, 0.3),
        Vec3::new(2.2, 1.9, 0.2),
        Vec3::new(2.0, 2.8, 0.4),
        Vec3::new(1.4, 3.3, 0.3),
        Vec3::new(0.9, 4.1, 0.6),
    ];
    let vels = [
        Vec3::new(0.3, -0.1, 0.2),
        Vec3::new(-0.2, 0.4, 0.1),
        Vec3::new(0.1, 0.2, -0.3),
        Vec3::new(0.5, -0.2, 0.1),
        Vec3::new(-0.1, -0.3, 0.2),
        Vec3::new(0.2, 0.1, 0.4),
    ];
    let mut ids = Vec::new();
    for (i, (p, v)) in pts.iter().zip(&vels).enumerate() {
        ids.push(
            b.add_particle(&format!("n{i}"), 1.0 + i as f64, *p, *v)
                .unwrap(),
        );
    }
    let model = b.build().unwrap();
    let lug_local = Vec3::new(0.8, 0.3, -0.2);
    let hook = HookInit {
        position: Vec3::new(0.5, 5.0, 0.2),
        velocity: Vec3::new(0.3, 0.5, -0.1),
        target_velocity: Vec3::new(0.3, 0.5, -0.1),
        t0: 0.1,
        payout: 0.02,
        payout_rate: 0.05,
        target_payout_rate: 0.08,
        ramp: 0.5,
        ..HookInit::at(Vec3::new(0.5, 5.0, 0.2))
    };
    // material coordinates slightly shorter than the geometry: every segment taut
    let mut sigma = 0.0;
    let mut points = Vec::new();
    let mut kins = Vec::new();
    evaluate(&model, &model.q0, &model.v0, &mut kins);
    let lug_world = kins[0].point(&lug_local);
    let hook_pos = hook.position + hook.velocity * (0.3 - hook.t0);
    let world: Vec<Vec3> = std::iter::once(lug_world)
        .chain(pts.iter().copied())
        .chain(std::iter::once(hook_pos))
        .collect();
    for (i, w) in world.iter().enumerate() {
        if i > 0 {
            let grad = match mode {
                SlipMode::SlipForward => i as f64,
                SlipMode::SlipBackward => (8 - i) as f64,
                SlipMode::Stick => 0.3 * i as f64,
            };
            sigma += (w - world[i - 1]).norm() * (1.0 - 0.003 * (1.0 + grad));
        }
        let at = if i == 0 {
            PointAt::Body {
                body: blk,
                local: lug_local,
            }
        } else if i == world.len() - 1 {
            PointAt::Hook(0)
        } else {
            PointAt::Body {
                body: ids[i - 1],
                local: Vec3::zeros(),
            }
        };
        let mu = match mode {
            SlipMode::Stick => 5.0,
            _ if i == 4 && middle_sticks => 0.9,
            _ => 0.05,
        };
        // edge hold on the block: a slanted edge, the anchor at the node (the spring unloaded:
        // the node's Coulomb cone takes the hold's force along the edge with the rope's friction,
        // so a loaded spring would make the rope slide; the hold's own derivatives with a loaded
        // spring are checked in `edge_hold_matches_finite_differences`)
        let dir = Vec3::new(0.3, -0.5, 0.8).normalize();
        let point = Vec3::new(0.2, 0.4, -0.3);
        let hold = EdgeHold {
            block: blk,
            point,
            dir,
            u0: dir.dot(&(kins[0].rot.transpose() * (w - kins[0].r) - point)),
            cap: 1e3,
        };
        // the run starts from the decisions in the memory (warm start): the middle node that is
        // to stick starts sticking
        let mode = if i == 4 && middle_sticks {
            SlipMode::Stick
        } else {
            mode
        };
        let contact = (contacts && (3..=5).contains(&i)).then_some(ContactInit {
            mode,
            mu,
            mu_rope: mu,
            hold: Some(hold),
        });
        points.push(LayoutPoint { at, sigma, contact });
    }
    let _ = BodyId::GROUND;
    let e = RopeEffect::new(
        &[LayoutRope {
            props,
            nominal_segment: 1.0,
            points,
        }],
        &[hook],
    )
    .unwrap();
    let mut mem = vec![0.0; e.n_memory()];
    let ctx = EvalCtx {
        t: 0.0,
        kins: &kins,
        inputs: &[],
        memory: &[],
        frozen: &[],
    };
    e.init_memory(&ctx, &mut mem);
    (model, e, mem)
}

fn props() -> RopeProps {
    RopeProps {
        ea: 1e5,
        axial_damping: 50.0,
        ..RopeProps::default()
    }
}

#[test]
fn plain_segments_match_finite_differences() {
    let (m, e, mem) = setup(SlipMode::Stick, props(), false);
    let (ek, ed) = check(&m, &e, &mem);
    println!("plain: K rel err {ek:.2e}, D rel err {ed:.2e}");
    assert!(ek < 1e-6 && ed < 1e-6, "K {ek:.3e}, D {ed:.3e}");
}

fn modes(model: &Model, e: &RopeEffect, mem: &[f64]) -> Vec<SlipMode> {
    let mut kins = Vec::new();
    evaluate(model, &model.q0, &model.v0, &mut kins);
    let ctx = EvalCtx {
        t: 0.3,
        kins: &kins,
        inputs: &[],
        memory: mem,
        frozen: &[],
    };
    e.contact_modes(&ctx)
}

#[test]
fn sticking_run_matches_finite_differences() {
    let (m, e, mem) = setup(SlipMode::Stick, props(), true);
    assert_eq!(modes(&m, &e, &mem), vec![SlipMode::Stick; 3]);
    let (ek, ed) = check(&m, &e, &mem);
    println!("stick run: K rel err {ek:.2e}, D rel err {ed:.2e}");
    assert!(ek < 1e-6 && ed < 1e-6, "K {ek:.3e}, D {ed:.3e}");
}

#[test]
fn slipping_run_matches_finite_differences() {
    for mode in [SlipMode::SlipForward, SlipMode::SlipBackward] {
        for middle_sticks in [true, false] {
            let (m, e, mem) = setup_with(mode, props(), true, middle_sticks);
            let modes = modes(&m, &e, &mem);
            let want = if middle_sticks {
                vec![mode, SlipMode::Stick, mode]
            } else {
                vec![mode; 3]
            };
            assert_eq!(modes, want);
            let (ek, ed) = check(&m, &e, &mem);
            println!("slip run {mode:?} (middle sticks {middle_sticks}): K {ek:.2e}, D {ed:.2e}");
            assert!(ek < 1e-6 && ed < 1e-6, "{mode:?}: K {ek:.3e}, D {ed:.3e}");
        }
    }
}

#[test]
fn bending_and_drag_match_finite_differences() {
    // a nearly limp rope, so that bending and drag dominate the matrices being checked
    let p = RopeProps {
        ea: 1e-3,
        axial_damping: 0.0,
        bending_stiffness: 30.0,
        drag_coefficient: 1.2,
        fluid_density: 1000.0,
        ..props()
    };
    for contacts in [false, true] {
        let (m, e, mem) = setup(SlipMode::SlipForward, p, contacts);
        let (ek, ed) = check(&m, &e, &mem);
        println!("bending+drag (contacts {contacts}): K {ek:.2e}, D {ed:.2e}");
        assert!(ek < 1e-6 && ed < 1e-6, "K {ek:.3e}, D {ed:.3e}");
    }
}

/// The edge hold alone (a particle against a rotating, moving block), two anchors.
#[test]
fn edge_hold_matches_finite_differences() {
    use mbcosim::rope::edge_hold;
    let mut b = ModelBuilder::new();
    let blk = b
        .add_rigid_body(
            "block",
            50.0,
            Mat3::from_diagonal(&Vec3::new(3.0, 4.0, 5.0)),
            BodyInit::at(Vec3::new(0.1, -0.2, 0.05))
                .oriented(Quat::from_scaled_axis(Vec3::new(0.3, -0.2, 0.5)))
                .moving(Vec3::new(0.2, 0.1, -0.3), Vec3::new(0.4, -0.7, 0.2)),
        )
        .unwrap();
    let node = b
        .add_particle(
            "q",
            2.0,
            Vec3::new(1.1, 0.7, -0.4),
            Vec3::new(0.3, -0.2, 0.5),
        )
        .unwrap();
    let model = b.build().unwrap();
    let (a, e) = (
        Vec3::new(0.2, 0.4, -0.3),
        Vec3::new(0.3, -0.5, 0.8).normalize(),
    );
    for u0 in [0.3, -2.0] {
        let f = |q: &[f64], v: &[f64]| {
            let mut kins = Vec::new();
            evaluate(&model, q, v, &mut kins);
            let (kn, kb) = (&kins[node.index().unwrap()], &kins[blk.index().unwrap()]);
            let h = edge_hold::eval(kn, kb, &a, &e, u0, 1e4, 30.0);
            let mut out = vec![0.0; model.n_v];
            edge_hold::add_forces(&h, kn, kb, &e, &mut out);
            (out, h)
        };
        let (q, v) = (model.q0.clone(), model.v0.clone());
        let n = model.n_v;
        let mut kins = Vec::new();
        evaluate(&model, &q, &v, &mut kins);
        let (kn, kb) = (&kins[node.index().unwrap()], &kins[blk.index().unwrap()]);
        let h = edge_hold::eval(kn, kb, &a, &e, u0, 1e4, 30.0);
        let mut sink = Dense {
            k: DMatrix::zeros(n, n),
            d: DMatrix::zeros(n, n),
        };
        edge_hold::add_jacobian(&h, kn, kb, &e, &mut sink);
        let (mut kfd, mut dfd) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
        let hh = 1e-7;
        let (mut qp, mut qm) = (q.clone(), q.clone());
        for c in 0..n {
            let mut dx = vec![0.0; n];
            dx[c] = hh;
            model.retract(&q, &dx, &mut qp);
            dx[c] = -hh;
            model.retract(&q, &dx, &mut qm);
            let (fp, _) = f(&qp, &v);
            let (fm, _) = f(&qm, &v);
            let (mut vp, mut vm) = (v.clone(), v.clone());
            vp[c] += hh;
            vm[c] -= hh;
            let (gp, _) = f(&q, &vp);
            let (gm, _) = f(&q, &vm);
            for r in 0..n {
                kfd[(r, c)] = -(fp[r] - fm[r]) / (2.0 * hh);
                dfd[(r, c)] = -(gp[r] - gm[r]) / (2.0 * hh);
            }
        }
        let ek = (&sink.k - &kfd).amax() / kfd.amax();
        let ed = (&sink.d - &dfd).amax() / dfd.amax().max(1e-300);
        println!(
            "edge hold (anchor {u0} m, force {:.1} N): K {ek:.2e}, D {ed:.2e}",
            h.force
        );
        if ek > 1e-5 {
            println!("analytic\n{:.3}\nfd\n{:.3}", sink.k, kfd);
        }
        assert!(
            ek < 1e-5 && (ed < 1e-5 || dfd.amax() == 0.0),
            "K {ek:.3e} D {ed:.3e}"
        );
    }
}
