//! Consistent initialization: positions and speeds projected onto the constraints (minimum
//! mass-weighted change), then accelerations and multipliers from the index-1 equations.

use super::SolverError;
use super::kkt::Kkt;
use super::newton::{Ended, PROJECTION_ITERATIONS, solve_from_start};
use crate::dae::System;
use crate::state::State;

/// Reusable buffers of the projections (so a caller's step loop does not allocate).
#[derive(Debug, Clone, Default)]
pub struct ProjectionScratch {
    rhs: Vec<f64>,
    qn: Vec<f64>,
    gv: Vec<f64>,
}

/// Largest constraint residual and the index of its row (a non-finite residual wins).
fn worst_row(sys: &System) -> (f64, usize) {
    sys.rows
        .iter()
        .enumerate()
        .map(|(i, r)| (r.phi.abs(), i))
        .fold(
            (0.0, 0),
            |a, b| if a.0.is_nan() || b.0 <= a.0 { a } else { b },
        )
}

/// Projects `state.q` onto `Phi = 0` (Gauss-Newton, at most [`PROJECTION_ITERATIONS`]
/// corrections, to `tol` [m, rad]; on the shared driver [`solve_from_start`]).
pub fn project_positions(
    sys: &mut System,
    lin: &mut Kkt,
    state: &mut State,
    tol: f64,
) -> Result<(), SolverError> {
    project_positions_reusing(
        sys,
        lin,
        state,
        tol,
        false,
        &mut ProjectionScratch::default(),
    )
}

/// As [`project_positions`]; with `reuse` the first iteration uses the factorization already in
/// `lin` (the caller formed `[M G^T; G 0]` at `state.q`).
pub fn project_positions_reusing(
    sys: &mut System,
    lin: &mut Kkt,
    state: &mut State,
    tol: f64,
    reuse: bool,
    scratch: &mut ProjectionScratch,
) -> Result<(), SolverError> {
    let (nv, nc) = (sys.n_v(), sys.n_c());
    if nc == 0 {
        return Ok(());
    }
    // never ask for less than round-off allows: 1e-13 on coordinates of order one, 64 machine
    // epsilons of the largest coordinate on larger ones (panels of 7.5e5 m kept a residual of
    // 2.9e-11 m after 50 projections, the round-off of their positions)
    let scale = state.q.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let tol = tol.max(1e-13).max(64.0 * f64::EPSILON * scale);
    let ProjectionScratch { rhs, qn, .. } = scratch;
    rhs.resize(nv + nc, 0.0);
    qn.clone_from(&state.q);
    // the iterate, and its largest residual and that row
    let mut ctx = (sys, lin, state, (0.0, 0));
    let ended = solve_from_start(
        &mut ctx,
        PROJECTION_ITERATIONS,
        |(sys, _, state, worst), _| {
            sys.eval_constraints(state.t, &state.q, &state.v);
            *worst = worst_row(sys);
            worst.0 / tol
        },
        |(sys, lin, state, _), k| {
            if reuse && k == 0 {
                // the caller's factorization at this very point
            } else {
                lin.factor(sys, state.t, &state.q, &state.v, 0.0)
                    .map_err(|e| {
                        SolverError::other(format!(
                            "projection onto the joints failed: {e} (redundant or conflicting joints?)"
                        ))
                    })?;
            }
            rhs[..nv].fill(0.0);
            for (r, row) in sys.rows.iter().enumerate() {
                rhs[nv + r] = -row.phi;
            }
            lin.solve(rhs).map_err(SolverError::other)?;
            sys.model.retract(&state.q, &rhs[..nv], qn);
            state.q.copy_from_slice(qn);
            Ok(true)
        },
    )?;
    let (_, _, state, (worst, row)) = ctx;
    match ended {
        Ended::Converged { .. } => Ok(()),
        Ended::Diverged { .. } => Err(SolverError::other(format!(
            "projection onto the joints failed at t = {:.9e} s: constraint row {row} has the residual {worst} (non-finite positions or joint data)",
            state.t
        ))),
        Ended::Exhausted => Err(SolverError::other(format!(
            "positions cannot be made to satisfy the joints at t = {:.9e} s: constraint row {row} keeps a residual of {worst:.3e} after {PROJECTION_ITERATIONS} projection iterations (check joint frames and initial poses)",
            state.t
        ))),
    }
}

/// Projects `state.v` onto `G v + Phi_t = 0` (one linear solve).
pub fn project_velocities(
    sys: &mut System,
    lin: &mut Kkt,
    state: &mut State,
) -> Result<(), SolverError> {
    project_velocities_reusing(sys, lin, state, false, &mut ProjectionScratch::default())
}

/// As [`project_velocities`]; with `reuse` the factorization already in `lin` (formed at a point
/// within the projection tolerance of `state.q`) is used: the result then satisfies the velocity
/// constraints to the product of that distance and the correction, far below the tolerance.
pub fn project_velocities_reusing(
    sys: &mut System,
    lin: &mut Kkt,
    state: &mut State,
    reuse: bool,
    scratch: &mut ProjectionScratch,
) -> Result<(), SolverError> {
    let (nv, nc) = (sys.n_v(), sys.n_c());
    if nc == 0 {
        return Ok(());
    }
    sys.eval_constraints(state.t, &state.q, &state.v);
    if !reuse {
        lin.factor(sys, state.t, &state.q, &state.v, 0.0)
            .map_err(|e| SolverError::other(format!("velocity projection failed: {e}")))?;
    }
    let ProjectionScratch { rhs, gv, .. } = scratch;
    rhs.resize(nv + nc, 0.0);
    rhs[..nv].fill(0.0);
    gv.resize(nc, 0.0);
    sys.g_mul(&state.v, gv);
    for (r, row) in sys.rows.iter().enumerate() {
        rhs[nv + r] = -(gv[r] + row.phi_t);
    }
    lin.solve(rhs).map_err(SolverError::other)?;
    for (v, dv) in state.v.iter_mut().zip(&rhs[..nv]) {
        *v += dv;
    }
    Ok(())
}

/// Accelerations and multipliers from `[M G^T; G 0] [v_dot; lambda] = [f; gamma]`.
pub fn accelerations(
    sys: &mut System,
    lin: &mut Kkt,
    state: &mut State,
) -> Result<(), SolverError> {
    let nv = sys.n_v();
    let mut rhs = Vec::new();
    index1_solution(sys, lin, state.t, &state.q, &state.v, &mut rhs)?;
    state.vdot.copy_from_slice(&rhs[..nv]);
    state.lambda.resize(rhs.len() - nv, 0.0);
    state.lambda.copy_from_slice(&rhs[nv..]);
    Ok(())
}

/// `[v_dot; lambda]` of `[M G^T; G 0] [v_dot; lambda] = [f; gamma]` at `(t, q, v)` into
/// `out` (resized to `n_v + n_c`; no allocation once it has that length), factorized by `lin`.
pub fn index1_solution(
    sys: &mut System,
    lin: &mut Kkt,
    t: f64,
    q: &[f64],
    v: &[f64],
    out: &mut Vec<f64>,
) -> Result<(), SolverError> {
    let (nv, nc) = (sys.n_v(), sys.n_c());
    out.resize(nv + nc, 0.0);
    sys.forces(t, q, v, &mut out[..nv]);
    sys.eval_constraints(t, q, v);
    for (r, row) in sys.rows.iter().enumerate() {
        out[nv + r] = row.gamma;
    }
    lin.factor(sys, t, q, v, 0.0)
        .map_err(|e| SolverError::other(format!("initial accelerations: {e}")))?;
    lin.solve(out).map_err(SolverError::other)
}

/// `v_dot` and `lambda` of the index-1 system at `(t, q, v)` into `vdot` (length `n_v`) and
/// `lambda` (resized to `n_c`): by the range-space method with `ws`, and where that fails (a
/// massless body, dependent rows) by the LU of the full matrix with `lin`, `scratch` its
/// right-hand side. No allocation once the buffers have their lengths.
#[allow(clippy::too_many_arguments)]
pub fn index1_motion(
    sys: &mut System,
    ws: &mut crate::dae::RangeSpace,
    lin: &mut Kkt,
    t: f64,
    q: &[f64],
    v: &[f64],
    vdot: &mut [f64],
    lambda: &mut Vec<f64>,
    scratch: &mut Vec<f64>,
) -> Result<(), SolverError> {
    let (nv, nc) = (sys.n_v(), sys.n_c());
    lambda.resize(nc, 0.0);
    if sys.index1_range_space(t, q, v, ws, vdot, lambda).is_ok() {
        return Ok(());
    }
    index1_solution(sys, lin, t, q, v, scratch)?;
    vdot.copy_from_slice(&scratch[..nv]);
    lambda.copy_from_slice(&scratch[nv..]);
    Ok(())
}

/// Makes `state` consistent: positions, speeds, accelerations and multipliers.
pub fn make_consistent(
    sys: &mut System,
    state: &mut State,
    position_tol: f64,
) -> Result<(), SolverError> {
    let mut lin = Kkt::new();
    project_positions(sys, &mut lin, state, position_tol)?;
    sys.check_dropped_rows(state.t, &state.q, &state.v, 1e3 * position_tol.max(1e-13))
        .map_err(SolverError::other)?;
    project_velocities(sys, &mut lin, state)?;
    accelerations(sys, &mut lin, state)
}

/// The initial state of a system's model at time `t0` (not yet consistent).
pub fn initial_state(sys: &System, t0: f64) -> State {
    State {
        t: t0,
        q: sys.model.q0.clone(),
        v: sys.model.v0.clone(),
        vdot: vec![0.0; sys.n_v()],
        lambda: vec![0.0; sys.n_c()],
        energy_dissipated: 0.0,
        work_input: 0.0,
        memory: vec![0.0; sys.n_memory()],
    }
}
