//! Linear solves for Newton iterations: triplet assembly into a recorded sparse pattern, then a
//! dense LU (small systems) or faer's sparse LU whose symbolic factorization is reused until the
//! pattern changes.
//!
//! Callers push the same sequence of `(row, col)` entries at every assembly for a given model
//! structure; values may be zero. A change of the sequence (e.g. a contact node inserted) is
//! detected by comparing with the recorded pattern and triggers a new symbolic analysis.
//!
//! Force effects may border the system with *auxiliary unknowns* ([`LinearSolver::add_aux`],
//! numbered after the caller's `n`): a dense coupling written as a product of sparse factors
//! (the sliding rope's `u c (G + T_0 h)^T`) then stays sparse, and the Schur complement of the
//! auxiliary block is exactly the dense coupling, so the caller's unknowns solve the same system.
//! Callers keep their own size: [`LinearSolver::solve`] takes their right-hand side, pads the
//! auxiliary rows with zeros and drops the auxiliary part of the solution.

use super::dense_lu::DenseLu;
use super::sparse_lu::SparseLu;
use super::split_lu::SplitLu;

/// Systems up to this size use the dense LU.
pub const DENSE_LIMIT: usize = 48;
/// Larger systems up to this size use the dense LU too when their pattern fills at least
/// [`DENSE_FILL`] of the matrix (e.g. flexible bodies with full modal blocks): the in-place LU,
/// which skips zero multipliers, then beats the sparse one's per-column graph searches.
pub const DENSE_FILLED_LIMIT: usize = 200;
/// Fraction of structural non-zeros above which a system up to [`DENSE_FILLED_LIMIT`] is dense.
pub const DENSE_FILL: f64 = 0.15;

// One backend per solver, never stored in bulk: the size difference of the variants is harmless.
#[allow(clippy::large_enum_variant)]
#[derive(Clone)]
enum Backend {
    None,
    Dense,
    Sparse(SparseLu),
    /// A few dense rows and columns split off by a Schur complement ([`SplitLu`]).
    Split(SplitLu),
}

/// Counters of the work done.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LinearStats {
    pub factorizations: u64,
    pub symbolic_analyses: u64,
    pub solves: u64,
}

/// A square linear system assembled from triplets.
pub struct LinearSolver {
    /// Size of the assembled system: the caller's unknowns and the auxiliary ones.
    n: usize,
    /// The caller's size (`begin`); unknowns `n_user..n` are auxiliary.
    n_user: usize,
    /// Whether effects may add auxiliary unknowns (see the module documentation).
    aux_allowed: bool,
    /// Right-hand side padded with the auxiliary rows (scratch).
    padded: Vec<f64>,
    rows: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
    pattern_rows: Vec<usize>,
    pattern_cols: Vec<usize>,
    pattern_n: usize,
    /// triplet k -> position in the CSC value array
    map: Vec<usize>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    csc_vals: Vec<f64>,
    dense: DenseLu,
    backend: Backend,
    factored: bool,
    /// The split LU of the current pattern failed once: the LU of the whole matrix serves this
    /// pattern from then on (what a serialized state must carry, [`LinearSolver::whole_lu`]).
    whole: bool,
    /// A restored state's solver served its pattern with the whole LU: the next pattern built
    /// does too.
    restored_whole: bool,
    pub stats: LinearStats,
}

impl Default for LinearSolver {
    fn default() -> Self {
        Self::new()
    }
}

impl Clone for LinearSolver {
    /// A deep copy, factorization included, so a cloned integrator continues bit for bit.
    fn clone(&self) -> Self {
        LinearSolver {
            n: self.n,
            n_user: self.n_user,
            aux_allowed: self.aux_allowed,
            padded: self.padded.clone(),
            rows: self.rows.clone(),
            cols: self.cols.clone(),
            vals: self.vals.clone(),
            pattern_rows: self.pattern_rows.clone(),
            pattern_cols: self.pattern_cols.clone(),
            pattern_n: self.pattern_n,
            map: self.map.clone(),
            col_ptr: self.col_ptr.clone(),
            row_idx: self.row_idx.clone(),
            csc_vals: self.csc_vals.clone(),
            dense: self.dense.clone(),
            backend: self.backend.clone(),
            factored: self.factored,
            whole: self.whole,
            restored_whole: self.restored_whole,
            stats: self.stats,
        }
    }
}

impl std::fmt::Debug for LinearSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "LinearSolver(n={}, nnz={}, split={})",
            self.n,
            self.rows.len(),
            self.split_unknowns()
        )
    }
}

impl LinearSolver {
    /// An empty solver.
    pub fn new() -> Self {
        LinearSolver {
            n: 0,
            n_user: 0,
            aux_allowed: true,
            padded: Vec::new(),
            rows: Vec::new(),
            cols: Vec::new(),
            vals: Vec::new(),
            pattern_rows: Vec::new(),
            pattern_cols: Vec::new(),
            pattern_n: usize::MAX,
            map: Vec::new(),
            col_ptr: Vec::new(),
            row_idx: Vec::new(),
            csc_vals: Vec::new(),
            dense: DenseLu::default(),
            backend: Backend::None,
            factored: false,
            whole: false,
            restored_whole: false,
            stats: LinearStats::default(),
        }
    }

    /// Whether the current pattern is solved by the LU of the whole matrix because its split
    /// LU failed once (a history the results depend on: the two round differently).
    pub fn whole_lu(&self) -> bool {
        self.whole
    }

    /// Restores [`LinearSolver::whole_lu`] of a saved solver: the pattern is analysed again at
    /// the next factorization, with the whole LU when `whole`.
    pub fn restore_whole_lu(&mut self, whole: bool) {
        self.restored_whole = whole;
        self.whole = false;
        self.pattern_n = usize::MAX;
    }

    /// Starts assembling an `n x n` matrix (auxiliary unknowns are added after it).
    pub fn begin(&mut self, n: usize) {
        self.n = n;
        self.n_user = n;
        self.rows.clear();
        self.cols.clear();
        self.vals.clear();
    }

    /// Adds `value` at `(row, col)` (duplicates are summed).
    #[inline]
    pub fn push(&mut self, row: usize, col: usize, value: f64) {
        debug_assert!(row < self.n && col < self.n);
        self.rows.push(row);
        self.cols.push(col);
        self.vals.push(value);
    }

    /// The entries assembled since [`LinearSolver::begin`] as `(row, col, value)` (duplicates
    /// not yet summed), for callers that need the matrix itself (e.g. a linearization).
    pub fn triplets(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.rows
            .iter()
            .zip(&self.cols)
            .zip(&self.vals)
            .map(|((&r, &c), &v)| (r, c, v))
    }

    /// Dimension of the current system as the caller sees it (without auxiliary unknowns).
    pub fn dim(&self) -> usize {
        self.n_user
    }

    /// Number of auxiliary unknowns of the current assembly.
    pub fn n_aux(&self) -> usize {
        self.n - self.n_user
    }

    /// Number of dense unknowns the last factorization split off by a Schur complement (0: the
    /// dense LU or faer's LU of the whole matrix).
    pub fn split_unknowns(&self) -> usize {
        match &self.backend {
            Backend::Split(s) if self.factored => s.n_dense(),
            _ => 0,
        }
    }

    /// Whether effects may add auxiliary unknowns (default `true`).
    pub fn aux_allowed(&self) -> bool {
        self.aux_allowed
    }

    /// Allows or forbids auxiliary unknowns: forbidden, effects emit their dense blocks (a
    /// reference for tests, and the same Newton step to round-off).
    pub fn set_aux_allowed(&mut self, allowed: bool) {
        self.aux_allowed = allowed;
    }

    /// Adds one auxiliary unknown (and its equation row) to the current assembly and returns
    /// its index; `None` when they are not allowed.
    pub fn add_aux(&mut self) -> Option<usize> {
        if !self.aux_allowed {
            return None;
        }
        self.n += 1;
        Some(self.n - 1)
    }

    fn rebuild_pattern(&mut self) -> Result<(), String> {
        let n = self.n;
        let nt = self.rows.len();
        let mut order: Vec<usize> = (0..nt).collect();
        order.sort_unstable_by_key(|&k| (self.cols[k], self.rows[k]));
        self.map = vec![0; nt];
        self.col_ptr = vec![0; n + 1];
        self.row_idx.clear();
        let mut last = (usize::MAX, usize::MAX);
        for &k in &order {
            let key = (self.cols[k], self.rows[k]);
            if key != last {
                self.row_idx.push(key.1);
                self.col_ptr[key.0 + 1] += 1;
                last = key;
            }
            self.map[k] = self.row_idx.len() - 1;
        }
        for c in 0..n {
            self.col_ptr[c + 1] += self.col_ptr[c];
        }
        self.csc_vals = vec![0.0; self.row_idx.len()];
        self.pattern_rows.clone_from(&self.rows);
        self.pattern_cols.clone_from(&self.cols);
        self.pattern_n = n;
        self.stats.symbolic_analyses += 1;
        let fill = self.row_idx.len() as f64 / (n * n).max(1) as f64;
        let whole = std::mem::take(&mut self.restored_whole);
        self.whole = false;
        if n <= DENSE_LIMIT || (n <= DENSE_FILLED_LIMIT && fill >= DENSE_FILL) {
            self.backend = Backend::Dense;
        } else {
            self.backend = self.sparse_backend(!whole)?;
            self.whole = whole;
        }
        Ok(())
    }

    /// The sparse backend of the current pattern: split when it has a few dense rows or
    /// columns (and `split`), else faer's LU of the whole matrix.
    fn sparse_backend(&self, split: bool) -> Result<Backend, String> {
        let n = self.n;
        if split && let Some(s) = SplitLu::analyse(n, &self.col_ptr, &self.row_idx) {
            return Ok(Backend::Split(s?));
        }
        let lu = SparseLu::analyse(n, self.col_ptr.clone(), self.row_idx.clone())?;
        Ok(Backend::Sparse(lu))
    }

    /// Whether the assembled matrix holds a non-finite entry: after a failed
    /// [`LinearSolver::factor`], tells a non-finite matrix from a singular one without reading
    /// the message.
    pub fn has_non_finite_entries(&self) -> bool {
        self.vals.iter().any(|v| !v.is_finite())
    }

    /// Factorizes the assembled matrix. `Err` names a singular or non-finite matrix.
    pub fn factor(&mut self) -> Result<(), String> {
        self.factored = false;
        if self.pattern_n != self.n
            || self.rows != self.pattern_rows
            || self.cols != self.pattern_cols
        {
            self.rebuild_pattern()?;
        }
        if self.vals.iter().any(|v| !v.is_finite()) {
            return Err("Newton matrix has non-finite entries".into());
        }
        self.stats.factorizations += 1;
        let n = self.n;
        if matches!(self.backend, Backend::Dense) {
            self.dense.reset(n);
            for k in 0..self.rows.len() {
                self.dense.add(self.rows[k], self.cols[k], self.vals[k]);
            }
            // Newton matrices of index-2/3 forms mix O(1/h) and O(1) blocks, so pivots are only
            // refused when exactly zero or non-finite; the solve checks its result.
            self.dense.factor()?;
            self.factored = true;
            return Ok(());
        }
        self.csc_vals.fill(0.0);
        for (k, &p) in self.map.iter().enumerate() {
            self.csc_vals[p] += self.vals[k];
        }
        let split_failed = match &mut self.backend {
            Backend::Sparse(lu) => {
                lu.factor(&self.csc_vals)?;
                false
            }
            Backend::Split(lu) => lu.factor(&self.csc_vals).is_err(),
            _ => return Err("sparse backend missing".into()),
        };
        if split_failed {
            // a singular remainder or Schur complement: the LU of the whole matrix decides
            // (kept for this pattern)
            let mut whole = self.sparse_backend(false)?;
            if let Backend::Sparse(lu) = &mut whole {
                lu.factor(&self.csc_vals)?;
            }
            self.backend = whole;
            self.whole = true;
        }
        self.factored = true;
        Ok(())
    }

    /// Magnitude of pivot `k` of the last factorization when the dense LU made it (`None` for
    /// the sparse LU, whose fill-reducing column order hides which column a pivot belongs to).
    /// Costs nothing: the pivots are the diagonal of `U`, already computed.
    pub fn dense_pivot(&self, k: usize) -> Option<f64> {
        match self.backend {
            Backend::Dense if self.factored && k < self.n => Some(self.dense.pivot(k)),
            _ => None,
        }
    }

    /// Solves `A x = rhs` in place with the last factorization; `rhs` has the caller's size
    /// ([`LinearSolver::dim`]; auxiliary rows have a zero right-hand side) or the full one.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), String> {
        if !self.factored {
            return Err("solve called without a valid factorization".into());
        }
        if rhs.len() == self.n_user && self.n > self.n_user {
            let mut padded = std::mem::take(&mut self.padded);
            padded.clear();
            padded.extend_from_slice(rhs);
            padded.resize(self.n, 0.0);
            let r = self.solve(&mut padded);
            rhs.copy_from_slice(&padded[..self.n_user]);
            self.padded = padded;
            return r;
        }
        if rhs.len() != self.n {
            return Err(format!(
                "right-hand side of length {} for a system of {} unknowns",
                rhs.len(),
                self.n_user
            ));
        }
        self.stats.solves += 1;
        match &mut self.backend {
            Backend::None => return Err("solve called before factor".into()),
            Backend::Dense => self.dense.solve(rhs),
            Backend::Sparse(lu) => lu.solve(rhs),
            Backend::Split(lu) => lu.solve(rhs),
        }
        if rhs.iter().any(|x| !x.is_finite()) {
            return Err("linear solve produced non-finite values (singular Newton matrix)".into());
        }
        Ok(())
    }
}
