//! Solves with the augmented matrix `[M G^T; G -c I]` (initial accelerations, projections,
//! explicit integration; `c = 0` outside a passage through a singular configuration).
//!
//! Two factorizations, chosen per model structure by the envelope of `S = G M^-1 G^T`:
//! - the range-space method ([`RangeSpace`]): Cholesky factors of the body mass blocks and an
//!   envelope Cholesky of `S + c I`, `O(n)` in the bodies of a chain or tree whose rows come in
//!   joint order;
//! - the LU of the full matrix ([`LinearSolver`]), for small systems (up to
//!   [`DENSE_LIMIT`] unknowns its dense LU costs less: the double pendulum's 22 unknowns took
//!   9 % more instructions by the range-space method), where `S` is dense in many rows (a block
//!   shared by the contact joints of many rope nodes), where the joints close a loop (near a
//!   singular configuration forming `S` squares the conditioning the LU sees), or where the
//!   range-space factorization fails (a massless body, dependent rows).

use crate::dae::linear::{DENSE_LIMIT, LinearSolver};
use crate::dae::{RangeSpace, System};

/// Envelope entries of `S` per constraint row up to which the range-space method is used: a
/// chain's rows (five per revolute joint) couple with about ten rows before them.
pub const ENVELOPE_PER_ROW: usize = 40;

/// Which factorization holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Method {
    Lu,
    RangeSpace,
}

/// Factorization of `[M G^T; G -c I]` and its solves.
#[derive(Debug, Clone)]
pub struct Kkt {
    lu: LinearSolver,
    rs: RangeSpace,
    method: Method,
    /// The structure `(n_v, n_c)` for which the range-space method was found too costly.
    lu_for: Option<(usize, usize)>,
    n_v: usize,
}

impl Default for Kkt {
    fn default() -> Self {
        Kkt {
            lu: LinearSolver::new(),
            rs: RangeSpace::default(),
            method: Method::Lu,
            lu_for: None,
            n_v: 0,
        }
    }
}

impl Kkt {
    /// A new solver.
    pub fn new() -> Self {
        Self::default()
    }

    /// The LU of the full matrix (its history for serialized states: [`LinearSolver::whole_lu`]).
    pub fn lu(&self) -> &LinearSolver {
        &self.lu
    }

    /// The LU of the full matrix, to restore its history.
    pub fn lu_mut(&mut self) -> &mut LinearSolver {
        &mut self.lu
    }

    /// Factorizes `[M G^T; G -c I]` at `(t, q, v)`; the constraint rows must be evaluated there.
    pub fn factor(
        &mut self,
        sys: &mut System,
        t: f64,
        q: &[f64],
        v: &[f64],
        c: f64,
    ) -> Result<(), String> {
        let (nv, nc) = (sys.n_v(), sys.n_c());
        self.n_v = nv;
        // closed loops pass singular configurations, where forming S squares the
        // conditioning that the LU of the full matrix sees (round-off amplified by 1 / d^2
        // instead of 1 / d at a distance d from it): they keep the LU
        if self.lu_for != Some((nv, nc)) && !sys.has_loops() && nv + nc > DENSE_LIMIT {
            match sys.factor_range_space(q, v, c, &mut self.rs) {
                Ok(()) if self.rs.envelope_len() <= ENVELOPE_PER_ROW * nc.max(1) => {
                    self.method = Method::RangeSpace;
                    return Ok(());
                }
                // too costly for this structure: the LU from now on
                Ok(()) => self.lu_for = Some((nv, nc)),
                // a singular block or S here: the LU for this factorization
                Err(_) => {}
            }
        }
        self.method = Method::Lu;
        self.lu.begin(nv + nc);
        sys.add_dynamics_matrix(t, q, v, 1.0, 0.0, 0.0, &mut self.lu, 0);
        sys.add_constraint_blocks(&mut self.lu, nv, 0, 1.0, Some((0, nv, 1.0)));
        if c != 0.0 {
            for r in 0..nc {
                self.lu.push(nv + r, nv + r, -c);
            }
        }
        self.lu.factor()
    }

    /// Solves with the last factorization: `rhs = [top; bottom]` (length `n_v + n_c`) becomes
    /// `[x; y]` with `M x + G^T y = top`, `G x - c y = bottom`.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), String> {
        match self.method {
            Method::RangeSpace => {
                self.rs.solve(rhs);
                if rhs.iter().all(|x| x.is_finite()) {
                    Ok(())
                } else {
                    Err("non-finite solution of the augmented system".into())
                }
            }
            Method::Lu => self.lu.solve(rhs),
        }
    }

    /// Pivot of column `col` of the full matrix in the last factorization, where it shows one:
    /// a constraint column's is the Cholesky pivot of its row of `S` (range space) or the dense
    /// LU's pivot; `None` for the sparse LU and for speed columns of the range-space method.
    pub fn pivot(&self, col: usize) -> Option<f64> {
        match self.method {
            Method::RangeSpace => col
                .checked_sub(self.n_v)
                .and_then(|r| (r < self.rs.n_rows()).then(|| self.rs.pivot(r))?),
            Method::Lu => self.lu.dense_pivot(col),
        }
    }

    /// Whether the last factorization was by the range-space method.
    pub fn is_range_space(&self) -> bool {
        self.method == Method::RangeSpace
    }
}
