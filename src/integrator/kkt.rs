//! Solves with the augmented matrix `[M G^T; G 0]` (initial accelerations, projections, explicit
//! integration).

use crate::dae::System;
use crate::dae::linear::LinearSolver;

/// Assembles and factorizes `[M G^T; G 0]` at `(q, t)`; the constraint rows must be evaluated.
pub fn factor(
    sys: &mut System,
    lin: &mut LinearSolver,
    t: f64,
    q: &[f64],
    v: &[f64],
) -> Result<(), String> {
    let (nv, nc) = (sys.n_v(), sys.n_c());
    lin.begin(nv + nc);
    sys.add_dynamics_matrix(t, q, v, 1.0, 0.0, 0.0, lin, 0);
    sys.add_constraint_blocks(lin, nv, 0, 1.0, Some((0, nv, 1.0)));
    lin.factor()
}

/// As [`factor`], with the compliance `-c I` in the constraint block: `[M G^T; G -c I]`.
pub fn factor_compliant(
    sys: &mut System,
    lin: &mut LinearSolver,
    t: f64,
    q: &[f64],
    v: &[f64],
    c: f64,
) -> Result<(), String> {
    let (nv, nc) = (sys.n_v(), sys.n_c());
    lin.begin(nv + nc);
    sys.add_dynamics_matrix(t, q, v, 1.0, 0.0, 0.0, lin, 0);
    sys.add_constraint_blocks(lin, nv, 0, 1.0, Some((0, nv, 1.0)));
    for r in 0..nc {
        lin.push(nv + r, nv + r, -c);
    }
    lin.factor()
}

/// Solves `[M G^T; G 0] [x; y] = [top; bottom]`, result in `rhs` (length `n_v + n_c`).
pub fn solve(lin: &mut LinearSolver, rhs: &mut [f64]) -> Result<(), String> {
    lin.solve(rhs)
}
