use mbcosim::effect::{EvalCtx, ForceEffect, JacobianSink};
use mbcosim::math::{Matrix6, Vec3};
use mbcosim::model::kinematics::{BodyKin, evaluate};
use mbcosim::scene::rope_block::{RopeBlockParams, RopeBlockScene};
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

fn main() {
    let mut p = RopeBlockParams::default();
    p.segments = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(20);
    let t_end: f64 = std::env::args()
        .nth(2)
        .map(|s| s.parse().unwrap())
        .unwrap_or(0.46);
    let mut scene = RopeBlockScene::new(p).unwrap();
    scene.set_hook(0, Vec3::new(0.0, 0.0, 0.2), 0.0).unwrap();
    let _ = scene.sim.advance_to(t_end);
    println!("t {} modes {:?}", scene.sim.time(), scene.sim.slip_modes());
    let sim = &scene.sim;
    let model = sim.sim.system.model.clone();
    let e = sim.map.rope.clone();
    let st = &sim.sim.state;
    let mem = st.memory[sim.map.rope_memory..].to_vec();
    let n = model.n_v;
    let forces = |q: &[f64], v: &[f64]| {
        let mut kins = Vec::new();
        evaluate(&model, q, v, &mut kins);
        let ctx = EvalCtx {
            t: st.t,
            kins: &kins,
            inputs: &[],
            memory: &mem,
        };
        let mut f = vec![0.0; n];
        e.add_forces(&ctx, &mut f);
        f
    };
    let mut kins = Vec::new();
    evaluate(&model, &st.q, &st.v, &mut kins);
    let ctx = EvalCtx {
        t: st.t,
        kins: &kins,
        inputs: &[],
        memory: &mem,
    };
    let mut sink = Dense {
        k: DMatrix::zeros(n, n),
        d: DMatrix::zeros(n, n),
    };
    e.add_jacobian(&ctx, &mut sink);
    let mut worst = (0.0, 0, 0);
    let h = 1e-7;
    let mut qp = st.q.clone();
    let mut qm = st.q.clone();
    for c in 0..n {
        let mut dx = vec![0.0; n];
        dx[c] = h;
        model.retract(&st.q, &dx, &mut qp);
        dx[c] = -h;
        model.retract(&st.q, &dx, &mut qm);
        let fp = forces(&qp, &st.v);
        let fm = forces(&qm, &st.v);
        for r in 0..n {
            let fd = -(fp[r] - fm[r]) / (2.0 * h);
            let err = (fd - sink.k[(r, c)]).abs();
            if err > worst.0 {
                worst = (err, r, c);
            }
        }
    }
    let (err, r, c) = worst;
    println!(
        "max |K - K_fd| = {err:.3e} at ({r}, {c}), K = {:.3e}, max |K| = {:.3e}",
        sink.k[(r, c)],
        sink.k.amax()
    );
    // which bodies
    for b in &model.bodies {
        if (b.v_offset..b.v_offset + b.kind.n_v()).contains(&r)
            || (b.v_offset..b.v_offset + b.kind.n_v()).contains(&c)
        {
            println!("  body {} at {}", b.name, b.v_offset);
        }
    }
}
