//! Linear solves for Newton iterations: triplet assembly into a recorded sparse pattern, then a
//! dense LU (small systems) or faer's sparse LU whose symbolic factorization is reused until the
//! pattern changes.
//!
//! Callers push the same sequence of `(row, col)` entries at every assembly for a given model
//! structure; values may be zero. A change of the sequence (e.g. a contact node inserted) is
//! detected by comparing with the recorded pattern and triggers a new symbolic analysis.

use super::dense_lu::DenseLu;
use faer::Par;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::mat::MatMut;
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

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
enum Backend {
    None,
    Dense,
    Sparse {
        symbolic: SymbolicLu<usize>,
        numeric: NumericLu<usize, f64>,
        mem: MemBuffer,
        req: StackReq,
    },
}

impl Clone for Backend {
    fn clone(&self) -> Self {
        match self {
            Backend::None => Backend::None,
            Backend::Dense => Backend::Dense,
            Backend::Sparse {
                symbolic,
                numeric,
                req,
                ..
            } => Backend::Sparse {
                symbolic: symbolic.clone(),
                numeric: numeric.clone(),
                mem: MemBuffer::new(*req),
                req: *req,
            },
        }
    }
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
    n: usize,
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
            stats: self.stats,
        }
    }
}

impl std::fmt::Debug for LinearSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LinearSolver(n={}, nnz={})", self.n, self.rows.len())
    }
}

impl LinearSolver {
    /// An empty solver.
    pub fn new() -> Self {
        LinearSolver {
            n: 0,
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
            stats: LinearStats::default(),
        }
    }

    /// Starts assembling an `n x n` matrix.
    pub fn begin(&mut self, n: usize) {
        self.n = n;
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

    /// Dimension of the current system.
    pub fn dim(&self) -> usize {
        self.n
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
        if n <= DENSE_LIMIT || (n <= DENSE_FILLED_LIMIT && fill >= DENSE_FILL) {
            self.backend = Backend::Dense;
        } else {
            let sym =
                SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
            let symbolic = factorize_symbolic_lu(sym, Default::default())
                .map_err(|e| format!("sparse LU symbolic analysis failed: {e:?}"))?;
            let req = StackReq::any_of(&[
                symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
                symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
            ]);
            self.backend = Backend::Sparse {
                symbolic,
                numeric: NumericLu::new(),
                mem: MemBuffer::new(req),
                req,
            };
        }
        Ok(())
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
        let Backend::Sparse {
            symbolic,
            numeric,
            mem,
            ..
        } = &mut self.backend
        else {
            return Err("sparse backend missing".into());
        };
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let a = SparseColMatRef::new(sym, &self.csc_vals);
        symbolic
            .factorize_numeric_lu(numeric, a, Par::Seq, MemStack::new(mem), Default::default())
            .map_err(|e| format!("Newton matrix is singular ({e:?})"))?;
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

    /// Solves `A x = rhs` in place with the last factorization.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), String> {
        if !self.factored {
            return Err("solve called without a valid factorization".into());
        }
        self.stats.solves += 1;
        match &mut self.backend {
            Backend::None => return Err("solve called before factor".into()),
            Backend::Dense => self.dense.solve(rhs),
            Backend::Sparse {
                symbolic,
                numeric,
                mem,
                ..
            } => {
                let n = self.n;
                let lu = lu_ref(symbolic, numeric);
                let rhs_mat = MatMut::from_column_major_slice_mut(rhs, n, 1);
                lu.solve_in_place_with_conj(faer::Conj::No, rhs_mat, Par::Seq, MemStack::new(mem));
            }
        }
        if rhs.iter().any(|x| !x.is_finite()) {
            return Err("linear solve produced non-finite values (singular Newton matrix)".into());
        }
        Ok(())
    }
}

/// The factorization as a `LuRef` (faer builds it from the symbolic and numeric parts).
fn lu_ref<'a>(
    symbolic: &'a SymbolicLu<usize>,
    numeric: &'a NumericLu<usize, f64>,
) -> faer::sparse::linalg::lu::LuRef<'a, usize, f64> {
    // `new_unchecked` is a safe fn in faer 0.24; `factored` guarantees the parts belong together.
    faer::sparse::linalg::lu::LuRef::new_unchecked(symbolic, numeric)
}
