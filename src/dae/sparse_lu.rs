//! faer's sparse LU on a fixed pattern: the symbolic analysis once per pattern, numeric
//! factorizations and solves without allocation after the first.

use faer::Par;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::mat::MatMut;
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

/// A sparse LU of an `n x n` matrix with a compressed-column pattern of its own.
pub struct SparseLu {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    mem: MemBuffer,
    req: StackReq,
}

impl Clone for SparseLu {
    fn clone(&self) -> Self {
        SparseLu {
            n: self.n,
            col_ptr: self.col_ptr.clone(),
            row_idx: self.row_idx.clone(),
            symbolic: self.symbolic.clone(),
            numeric: self.numeric.clone(),
            mem: MemBuffer::new(self.req),
            req: self.req,
        }
    }
}

impl SparseLu {
    /// Analyses the pattern (`col_ptr` of length `n + 1`, sorted row indices per column).
    pub fn analyse(n: usize, col_ptr: Vec<usize>, row_idx: Vec<usize>) -> Result<Self, String> {
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_lu(sym, Default::default())
            .map_err(|e| format!("sparse LU symbolic analysis failed: {e:?}"))?;
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        Ok(SparseLu {
            n,
            col_ptr,
            row_idx,
            symbolic,
            numeric: NumericLu::new(),
            mem: MemBuffer::new(req),
            req,
        })
    }

    /// Factorizes the values `vals` (one per pattern entry); `Err` names a singular matrix.
    pub fn factor(&mut self, vals: &[f64]) -> Result<(), String> {
        let n = self.n;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let a = SparseColMatRef::new(sym, vals);
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                a,
                Par::Seq,
                MemStack::new(&mut self.mem),
                Default::default(),
            )
            .map_err(|e| format!("Newton matrix is singular ({e:?})"))?;
        Ok(())
    }

    /// Solves in place with the last factorization (`rhs` of length `n`).
    pub fn solve(&mut self, rhs: &mut [f64]) {
        // `new_unchecked` is a safe fn in faer 0.24; a solve follows a successful `factor`
        let lu = faer::sparse::linalg::lu::LuRef::new_unchecked(&self.symbolic, &self.numeric);
        let rhs_mat = MatMut::from_column_major_slice_mut(rhs, self.n, 1);
        lu.solve_in_place_with_conj(
            faer::Conj::No,
            rhs_mat,
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
    }
}
