//! The sliding chain's dense stiffness bordered by auxiliary unknowns (issue #19): the Newton
//! matrix `M + c_D D + c_K K` of a rope sliding round a drum, assembled with the dense part of
//! every sliding chain's Jacobian as auxiliary rows, gives the same Newton step as the same
//! matrix assembled with that part as dense blocks (the linear solver told to refuse auxiliary
//! unknowns, which the rope then emits as before). Round-off is the only difference: the
//! Schur complement of the auxiliary block is the dense block itself.

use crate::rig::*;
use mbcosim::dae::linear::LinearSolver;
use mbcosim::rope::SlipMode;

/// Solves `(M + cd D + ck K) x = b` at the simulation's state; returns `x` and the number of
/// auxiliary unknowns the assembly added.
fn newton_step(
    sim: &mut mbcosim::sim::Simulation,
    aux: bool,
    cd: f64,
    ck: f64,
    b: &[f64],
) -> (Vec<f64>, usize) {
    let (t, q, v) = (sim.state.t, sim.state.q.clone(), sim.state.v.clone());
    let nv = sim.system.n_v();
    let mut lin = LinearSolver::new();
    lin.set_aux_allowed(aux);
    lin.begin(nv);
    sim.system
        .add_dynamics_matrix(t, &q, &v, 1.0, cd, ck, &mut lin, 0);
    let n_aux = lin.n_aux();
    lin.factor().expect("Newton matrix factorizes");
    let mut x = b.to_vec();
    lin.solve(&mut x).expect("Newton step solves");
    (x, n_aux)
}

#[test]
fn bordered_newton_step_equals_the_dense_one_on_a_sliding_drum() {
    for k in [16usize, 64] {
        let mut rs = sliding_drum(k).sim(settings(1e-3));
        rs.sim.advance_to(0.3).unwrap();
        let modes = rs.slip_modes();
        let sliding = modes.iter().filter(|m| **m != SlipMode::Stick).count();
        assert!(
            sliding + 2 >= k,
            "drum {k}: only {sliding} of {} nodes slide",
            modes.len()
        );
        let nv = rs.sim.system.n_v();
        // a right-hand side of forces [N] with every entry non-zero
        let b: Vec<f64> = (0..nv)
            .map(|i| 1e3 * ((i as f64 * 0.7311).sin() + 0.1))
            .collect();
        // c_D, c_K of generalized-alpha at h = 1 ms and 0.1 s
        for (cd, ck) in [(5e-4, 2.5e-7), (5e-2, 2.5e-3)] {
            let (dense, n0) = newton_step(&mut rs.sim, false, cd, ck, &b);
            let (bordered, n1) = newton_step(&mut rs.sim, true, cd, ck, &b);
            assert_eq!(n0, 0);
            assert!(
                n1 >= sliding,
                "drum {k}: {n1} auxiliary unknowns for {sliding} sliding nodes"
            );
            let scale = dense.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            let diff = dense
                .iter()
                .zip(&bordered)
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            println!(
                "drum {k}, c_K {ck:.1e}: {n1} auxiliary unknowns, step difference {:.1e} of {scale:.3e}",
                diff / scale
            );
            assert!(
                diff <= 1e-10 * scale,
                "drum {k}, c_K {ck}: {:.2e}",
                diff / scale
            );
        }
    }
}
