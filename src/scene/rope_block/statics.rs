//! Static equilibrium of a rope-and-block scene at the current time: the positions where the
//! forces balance the joint reactions, with all speeds zero.
//!
//! Newton's method on `f(q) - G^T lambda = 0`, `Phi(q) = 0` with the analytic stiffness
//! `K = -df/dx`: `[K + M/tau^2, G^T; G, 0] [dx; lambda] = [f; -Phi]`. The mass term is a pseudo-time
//! regularization (it keeps the matrix regular where a slack rope or a free body has no stiffness);
//! `tau` [s] grows tenfold after every step that lowers the residual and shrinks otherwise, so the
//! iteration turns into plain Newton near the solution. Contact nodes keep their current
//! stick/slip state (a sliding node slides without friction losses in statics).

use super::runner::RopeBlockSim;
use crate::dae::linear::LinearSolver;
use crate::integrator::newton::{Ended, solve_from_start};

/// Result of a static solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticReport {
    /// Newton iterations taken.
    pub iterations: usize,
    /// Largest remaining force imbalance [N] (generalized forces, torques in N m).
    pub residual: f64,
}

/// Moves `sim` to the static equilibrium near its current positions; `Err` when no equilibrium is
/// found within `max_iter` iterations (the message gives the remaining force imbalance). The
/// iteration runs on the solver's shared Newton driver ([`solve_from_start`], the force
/// imbalance over `force_tol` judged before every correction).
///
/// Slings laid out just taut carry no tension and have no stiffness, so the exact tangent only
/// lets the block fall (against the pseudo-mass) and the iteration crawls. The first iterations
/// therefore use the taut tangent of the rope effect ([`crate::rope::RopeEffect::set_taut_tangent`]:
/// slack segments count with their axial stiffness in the matrix, not in the forces), until the
/// force imbalance has dropped tenfold or after [`TAUT_TANGENT_ITERATIONS`]; then plain Newton on
/// the exact tangent. The equilibrium found is the same (the residual is always exact).
pub fn solve(
    sim: &mut RopeBlockSim,
    force_tol: f64,
    max_iter: usize,
) -> Result<StaticReport, String> {
    sim.map.rope.set_taut_tangent(true);
    let r = solve_inner(sim, force_tol, max_iter);
    sim.map.rope.set_taut_tangent(false);
    r
}

/// Most iterations with the taut tangent.
pub const TAUT_TANGENT_ITERATIONS: usize = 10;

fn solve_inner(
    sim: &mut RopeBlockSim,
    force_tol: f64,
    max_iter: usize,
) -> Result<StaticReport, String> {
    let rope = sim.map.rope.clone();
    let s = &mut sim.sim;
    let (nv, nc) = (s.system.n_v(), s.system.n_c());
    let t = s.state.t;
    s.state.v.fill(0.0);
    let mut lin = LinearSolver::new();
    let mut f = vec![0.0; nv];
    let mut rhs = vec![0.0; nv + nc];
    let mut qn = s.state.q.clone();
    let residual =
        |sys: &mut crate::dae::System, q: &[f64], v: &[f64], lam: &[f64], f: &mut [f64]| {
            sys.forces(t, q, v, f);
            sys.eval_constraints(t, q, v);
            let neg: Vec<f64> = lam.iter().map(|x| -x).collect();
            sys.gt_mul_add(&neg, f);
            // largest magnitudes; a NaN wins (f64::max would drop it)
            let largest = |a: f64, x: f64| {
                if a.is_nan() || x.abs() <= a {
                    a
                } else {
                    x.abs()
                }
            };
            let fmax = f.iter().copied().fold(0.0, largest);
            let pmax = sys.rows.iter().map(|r| r.phi).fold(0.0, largest);
            (fmax, pmax)
        };
    let lam = s.state.lambda.clone();
    let (fmax, _) = residual(&mut s.system, &s.state.q, &s.state.v, &lam, &mut f);
    let f_start = fmax;
    let mut it = Iterate {
        s,
        lam,
        fmax,
        tau: 1e-2,
    };
    let ended = solve_from_start(
        &mut it,
        max_iter,
        |it, k| {
            if k >= TAUT_TANGENT_ITERATIONS || it.fmax < 0.1 * f_start {
                rope.set_taut_tangent(false);
            }
            it.fmax / force_tol
        },
        |it, _| -> Result<bool, String> {
            let s = &mut *it.s;
            let q = s.state.q.clone();
            let v = s.state.v.clone();
            s.system.forces(t, &q, &v, &mut f);
            s.system.eval_constraints(t, &q, &v);
            lin.begin(nv + nc);
            let mass = 1.0 / (it.tau * it.tau);
            s.system
                .add_dynamics_matrix(t, &q, &v, mass, 0.0, 1.0, &mut lin, 0);
            s.system
                .add_constraint_blocks(&mut lin, nv, 0, 1.0, Some((0, nv, 1.0)));
            rhs[..nv].copy_from_slice(&f);
            for (r, row) in s.system.rows.iter().enumerate() {
                rhs[nv + r] = -row.phi;
            }
            if lin.factor().and_then(|_| lin.solve(&mut rhs)).is_err() {
                // singular without enough pseudo-mass (a slack rope): regularize more
                it.tau *= 0.1;
                return Ok(it.tau >= 1e-9);
            }
            // backtracking on the potential energy (the forces are conservative in statics) or
            // on the force imbalance, whichever improves first
            let e0 = s.system.energy(t, &q, &v).1;
            let mut accepted = false;
            let mut dx = rhs[..nv].to_vec();
            for _ in 0..30 {
                s.system.model.retract(&q, &dx, &mut qn);
                let lam_try = rhs[nv..].to_vec();
                let (fnew, _) = residual(&mut s.system, &qn, &v, &lam_try, &mut f);
                let e1 = s.system.energy(t, &qn, &v).1;
                if fnew.is_finite() && (fnew < it.fmax || e1 < e0) {
                    s.state.q.copy_from_slice(&qn);
                    it.lam = lam_try;
                    it.fmax = fnew;
                    accepted = true;
                    break;
                }
                dx.iter_mut().for_each(|x| *x *= 0.5);
            }
            if accepted {
                it.tau = (it.tau * 10.0).min(1e8);
                Ok(true)
            } else {
                it.tau *= 0.1;
                Ok(it.tau >= 1e-9)
            }
        },
    )?;
    let Iterate { s, lam, fmax, .. } = it;
    match ended {
        Ended::Converged { iterations } => {
            rope.set_taut_tangent(false);
            s.state.vdot.fill(0.0);
            s.state.lambda.copy_from_slice(&lam);
            s.restart().map_err(String::from)?;
            Ok(StaticReport {
                iterations,
                residual: fmax,
            })
        }
        Ended::Diverged { iterations, .. } => Err(format!(
            "static solve: the force imbalance is {fmax} N after {iterations} iterations (non-finite forces: check the scene's parameters)"
        )),
        Ended::Exhausted => Err(format!(
            "no static equilibrium found in {max_iter} iterations: largest force imbalance {fmax:.3e} N (is the scene statically stable? free bodies need supports; a load far beyond the slings' strength, e.g. block_mass against rope_ea, or too few segments, also ends here; with ground_contact on, so does a ground_stiffness or ground_height the slings cannot balance)"
        )),
    }
}

/// The statics' iterate: the scene (positions in its state), the multipliers, the largest force
/// imbalance [N] and the pseudo-time [s].
struct Iterate<'a> {
    s: &'a mut crate::sim::Simulation,
    lam: Vec<f64>,
    fmax: f64,
    tau: f64,
}
