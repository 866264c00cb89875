//! Islands with closed loops: the joint-space system `(G⁻¹ + J·M⁻¹·Jᵀ)·P = r` of
//! [`super::tree`] factorised by Cholesky, with no allocation per substep.
//!
//! - **Large islands** (more than [`DENSE_UP_TO`] joints): `faer`'s sparse Cholesky. The
//!   pattern (one 6×6 block per pair of joints sharing a body), its fill-reducing ordering
//!   (AMD) and the symbolic factorisation are computed once per topology; every substep
//!   only writes the values in place, refactorises numerically and solves.
//! - **Small islands** (a four-bar linkage, a closed gripper, a suspension: up to
//!   [`DENSE_UP_TO`] joints, a matrix of at most 42 × 42): the same matrix dense, its upper
//!   triangle factorised `A = Uᵀ·U` in the joints' order ([`dense_cholesky_upper`]). No
//!   ordering is needed: the matrix is positive definite (`G⁻¹ ≻ 0`), so the factorisation
//!   exists in any order, and at this size fill costs less than faer's machinery, which
//!   is built for large matrices (its dispatch, recursion and kernels).
//!
//! The threshold is where the two cross, counted in instructions per solve (callgrind,
//! everything [`LoopSolve::solve`] does: the blocks `J·M⁻¹·Jᵀ`, the factorisation, the
//! solve, the velocity changes), on rings of rods hinged at their corners and to the world
//! at one of them (`Kn = 1e8`, 40 substeps each):
//!
//! | joints in the island | 5 | 6 | 7 | 9 | 13 | 17 | 25 |
//! |---|---|---|---|---|---|---|---|
//! | dense | 62 700 | 90 500 | 125 000 | 220 000 | 574 000¹ | 1 126 000¹ | 3 108 000¹ |
//! | faer, sparse | 105 000 | 129 000 | 153 000 | 201 000 | 297 000 | 392 000 | 583 000 |
//!
//! ¹ with the whole matrix zeroed each substep (the upper triangle now: a little less).
//! The free four-bar of the solver bench (4 joints, 4 bodies) took 74 600 instructions a
//! substep in faer's factorisation and 40 800 dense; faer's supernodal mode, forced,
//! 62 000.

use super::{block, joint_block, SolveFailure, SolverBody, SolverJoints};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use nalgebra::{Matrix6, Vector6};

/// One pair of joint sides on a shared body: a contribution `J_a·M⁻¹·J_cᵀ` to block
/// `(a, c)` (local joints, `a ≤ c`), stored at `slot` among the blocks of column `c`.
#[derive(Debug, Clone, Copy)]
struct Pair {
    body: u32,
    a: u32,
    side_a: u8,
    c: u32,
    side_c: u8,
    slot: u32,
}

/// Most joints of an island factorised dense (the [module documentation](self)'s table:
/// the two factorisations cost the same at about 8 joints).
const DENSE_UP_TO: usize = 7;

/// faer's sparse Cholesky of an island: the upper triangle of its matrix in compressed
/// columns, the symbolic factorisation and their workspace.
struct SparseFactor {
    /// Upper triangle in compressed columns.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    mem: MemBuffer,
}

/// How an island's matrix is kept and factorised.
enum Factor {
    Sparse(Box<SparseFactor>),
    /// The `n × n` matrix by columns (`a[row + n·column]`), its upper triangle written, then
    /// factorised in place into `U` (`A = Uᵀ·U`).
    Dense(Vec<f64>),
}

/// The workspace of one island with loops.
pub(crate) struct LoopSolve {
    /// Global joint index of each local joint.
    joints: Vec<u32>,
    /// Global body indices, and for each the local joints on it with their side.
    bodies: Vec<u32>,
    body_start: Vec<usize>,
    body_sides: Vec<(u32, u8)>,
    pairs: Vec<Pair>,
    /// Number of blocks in each block column (the diagonal block is the last).
    col_blocks: Vec<u32>,
    factor: Factor,
    /// The right-hand side, then the impulses (`6·joints` numbers).
    rhs: Vec<f64>,
    /// Impulse of each local joint after [`Self::solve`].
    pub(crate) impulses: Vec<Vector6<f64>>,
    /// Velocity change of each body (same order as `bodies`) after [`Self::solve`].
    pub(crate) velocity: Vec<Vector6<f64>>,
}

impl std::fmt::Debug for LoopSolve {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("LoopSolve");
        d.field("joints", &self.joints.len());
        match &self.factor {
            Factor::Sparse(s) => d
                .field("nnz", &s.values.len())
                .field("factor", &s.l_values.len()),
            Factor::Dense(a) => d.field("dense", &a.len()),
        };
        d.finish()
    }
}

impl LoopSolve {
    /// Analyses the pattern of an island (`joints`, `bodies`: global indices, ascending;
    /// `sides[j]`: the solver bodies of joint `j`).
    pub(crate) fn new(joints: &[u32], bodies: &[u32], sides: &[[Option<u32>; 2]]) -> Self {
        let nj = joints.len();
        let local_body = |b: u32| bodies.binary_search(&b).expect("body of the island");
        // joint sides on each body
        let mut count = vec![0usize; bodies.len() + 1];
        for &j in joints {
            for b in sides[j as usize].iter().flatten() {
                count[local_body(*b) + 1] += 1;
            }
        }
        for i in 0..bodies.len() {
            count[i + 1] += count[i];
        }
        let body_start = count.clone();
        let mut fill = count;
        let mut body_sides = vec![(0u32, 0u8); body_start[bodies.len()]];
        for (lj, &j) in joints.iter().enumerate() {
            for (side, b) in sides[j as usize].iter().enumerate() {
                if let Some(b) = b {
                    let lb = local_body(*b);
                    body_sides[fill[lb]] = (lj as u32, side as u8);
                    fill[lb] += 1;
                }
            }
        }
        // block pattern: (a, c) with a ≤ c when a and c share a body
        let mut rows_of_col: Vec<Vec<u32>> = (0..nj as u32).map(|c| vec![c]).collect();
        for lb in 0..bodies.len() {
            let list = &body_sides[body_start[lb]..body_start[lb + 1]];
            for &(a, _) in list {
                for &(c, _) in list {
                    if a < c {
                        rows_of_col[c as usize].push(a);
                    }
                }
            }
        }
        for rows in &mut rows_of_col {
            rows.sort_unstable();
            rows.dedup();
        }
        let mut pairs = Vec::new();
        for (lb, &b) in bodies.iter().enumerate() {
            let list = &body_sides[body_start[lb]..body_start[lb + 1]];
            for &(a, sa) in list {
                for &(c, sc) in list {
                    if a <= c {
                        let slot = rows_of_col[c as usize]
                            .binary_search(&a)
                            .expect("in pattern");
                        pairs.push(Pair {
                            body: b,
                            a,
                            side_a: sa,
                            c,
                            side_c: sc,
                            slot: slot as u32,
                        });
                    }
                }
            }
        }
        // scalar compressed columns: column 6c + k holds, for every block row a < c, its six
        // rows, then rows 6c ..= 6c + k of the diagonal block
        let mut col_ptr = Vec::with_capacity(6 * nj + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for (c, rows) in rows_of_col.iter().enumerate() {
            for k in 0..6 {
                for &a in rows {
                    let top = if a as usize == c { k + 1 } else { 6 };
                    for r in 0..top {
                        row_idx.push(6 * a as usize + r);
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let n = 6 * nj;
        let factor = if nj <= DENSE_UP_TO {
            Factor::Dense(vec![0.0; n * n])
        } else {
            let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
            let symbolic = factorize_symbolic_cholesky(
                pattern,
                Side::Upper,
                SymmetricOrdering::Amd,
                Default::default(),
            )
            .expect("symbolic analysis of a valid pattern");
            let mem = MemBuffer::new(StackReq::any_of(&[
                symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
                symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
            ]));
            Factor::Sparse(Box::new(SparseFactor {
                values: vec![0.0; row_idx.len()],
                col_ptr,
                row_idx,
                l_values: vec![0.0; symbolic.len_val()],
                symbolic,
                mem,
            }))
        };
        LoopSolve {
            joints: joints.to_vec(),
            bodies: bodies.to_vec(),
            body_start,
            body_sides,
            pairs,
            col_blocks: rows_of_col.iter().map(|r| r.len() as u32).collect(),
            factor,
            rhs: vec![0.0; n],
            impulses: vec![Vector6::zeros(); nj],
            velocity: vec![Vector6::zeros(); bodies.len()],
        }
    }

    /// Whether the island is factorised dense ([`DENSE_UP_TO`]).
    #[cfg(test)]
    pub(crate) fn is_dense(&self) -> bool {
        matches!(self.factor, Factor::Dense(_))
    }

    /// Global joint indices, in local order.
    pub(crate) fn joints(&self) -> &[u32] {
        &self.joints
    }

    /// Global body indices, in local order.
    pub(crate) fn bodies(&self) -> &[u32] {
        &self.bodies
    }

    /// Adds `m` (upper triangle only when `a == c`) to block `(a, c)`, `a ≤ c`, which is
    /// block `slot` of column `c`.
    fn add_block(&mut self, a: u32, c: u32, slot: u32, m: &Matrix6<f64>) {
        let diagonal = a == c;
        match &mut self.factor {
            Factor::Sparse(f) => {
                let before = 6 * slot as usize;
                for k in 0..6 {
                    let start = f.col_ptr[6 * c as usize + k] + before;
                    let top = if diagonal { k + 1 } else { 6 };
                    for r in 0..top {
                        f.values[start + r] += m[(r, k)];
                    }
                }
            }
            Factor::Dense(d) => {
                let n = 6 * self.joints.len();
                for k in 0..6 {
                    let start = 6 * a as usize + n * (6 * c as usize + k);
                    let top = if diagonal { k + 1 } else { 6 };
                    for r in 0..top {
                        d[start + r] += m[(r, k)];
                    }
                }
            }
        }
    }

    pub(crate) fn solve(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        match &mut self.factor {
            Factor::Sparse(f) => f.values.fill(0.0),
            Factor::Dense(d) => {
                // the upper triangle, which is all the factorisation reads
                let n = 6 * self.joints.len();
                for (j, col) in d.chunks_exact_mut(n.max(1)).enumerate() {
                    col[..=j].fill(0.0);
                }
            }
        }
        for lj in 0..self.joints.len() {
            let (mut g_inv, mut r) = (Matrix6::zeros(), Vector6::zeros());
            joint_block(joints, bodies, self.joints[lj], &mut g_inv, &mut r)?;
            for i in 0..6 {
                self.rhs[6 * lj + i] = r[i];
            }
            let slot = self.col_blocks[lj] - 1;
            self.add_block(lj as u32, lj as u32, slot, &g_inv);
        }
        for p in 0..self.pairs.len() {
            let pair = self.pairs[p];
            let minv = &bodies[pair.body as usize].inv_mass;
            let ja = &joints[self.joints[pair.a as usize] as usize]
                .jac
                .matrix(pair.side_a as usize);
            let jc = &joints[self.joints[pair.c as usize] as usize]
                .jac
                .matrix(pair.side_c as usize);
            // J_a·M⁻¹·J_cᵀ from the blocks of M⁻¹
            let block = Matrix6::from_data(nalgebra::ArrayStorage(block::product_t(
                &block::times_inv_mass(ja, minv),
                jc,
            )));
            let block = if pair.a == pair.c {
                0.5 * (block + block.transpose())
            } else {
                block
            };
            self.add_block(pair.a, pair.c, pair.slot, &block);
        }
        let n = 6 * self.joints.len();
        match &mut self.factor {
            Factor::Sparse(f) => {
                let pattern =
                    SymbolicSparseColMatRef::new_checked(n, n, &f.col_ptr, None, &f.row_idx);
                let a = SparseColMatRef::new(pattern, &f.values);
                let stack = MemStack::new(&mut f.mem);
                let llt = f
                    .symbolic
                    .factorize_numeric_llt(
                        &mut f.l_values,
                        a,
                        Side::Upper,
                        Default::default(),
                        Par::Seq,
                        stack,
                        Default::default(),
                    )
                    .map_err(|_| SolveFailure::NotPositive(self.joints[0]))?;
                let rhs = MatMut::from_column_major_slice_mut(&mut self.rhs, n, 1);
                llt.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack);
            }
            Factor::Dense(d) => {
                if let Err(row) = dense_cholesky_upper(d, n) {
                    return Err(SolveFailure::NotPositive(self.joints[row / 6]));
                }
                dense_solve_upper(d, n, &mut self.rhs);
            }
        }
        for lj in 0..self.joints.len() {
            self.impulses[lj] = Vector6::from_fn(|i, _| self.rhs[6 * lj + i]);
        }
        // velocity changes u_b = M⁻¹·Σ Jᵀ·P
        for lb in 0..self.bodies.len() {
            let mut f = Vector6::zeros();
            for &(lj, side) in &self.body_sides[self.body_start[lb]..self.body_start[lb + 1]] {
                let sj = &joints[self.joints[lj as usize] as usize];
                f += sj.jac.tr_mul(side as usize, &self.impulses[lj as usize]);
            }
            self.velocity[lb] = block::inv_mass_mul(&bodies[self.bodies[lb] as usize].inv_mass, &f);
        }
        Ok(())
    }
}

/// `Σ x_k·y_k` over two slices of the same length, in four interleaved partial sums (the
/// order of a vector unit's lanes): `(s_0 + s_1) + (s_2 + s_3)`, then the tail.
#[inline]
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    let (x, y) = (&x[..n], &y[..n]);
    let mut s = [0.0f64; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let (xt, yt) = (xc.remainder(), yc.remainder());
    for (a, b) in xc.zip(yc) {
        for l in 0..4 {
            s[l] += a[l] * b[l];
        }
    }
    let mut sum = (s[0] + s[1]) + (s[2] + s[3]);
    for (a, b) in xt.iter().zip(yt) {
        sum += a * b;
    }
    sum
}

/// `A = Uᵀ·U` in place: `a` holds the `n × n` matrix by columns (`a[i + n·j]`, its upper
/// triangle read), and on return `U` (upper, the strict lower triangle untouched). Column by
/// column (Cholesky–Crout):
///
/// ```text
/// U_ij = (A_ij − Σ_{k<i} U_ki·U_kj) / U_ii   (i < j),    U_jj = √(A_jj − Σ_{k<j} U_kj²)
/// ```
///
/// every sum a dot product of two contiguous columns. `Err(j)`: the pivot of row `j` is
/// not positive and finite (the matrix is not positive definite).
fn dense_cholesky_upper(a: &mut [f64], n: usize) -> Result<(), usize> {
    for j in 0..n {
        let (before, from_j) = a.split_at_mut(n * j);
        let col_j = &mut from_j[..n];
        for i in 0..j {
            let col_i = &before[n * i..n * i + i + 1];
            let (done, rest) = col_j.split_at_mut(i);
            rest[0] = (rest[0] - dot(&col_i[..i], done)) / col_i[i];
        }
        let (done, rest) = col_j.split_at_mut(j);
        let d = rest[0] - dot(done, done);
        if !(d > 0.0 && d.is_finite()) {
            return Err(j);
        }
        rest[0] = d.sqrt();
    }
    Ok(())
}

/// Solves `Uᵀ·U·x = b` in place (`b` in, `x` out) with `U` from [`dense_cholesky_upper`]:
/// `Uᵀ·y = b` forwards (`y_i = (b_i − Σ_{k<i} U_ki·y_k)/U_ii`, column `i` of `U`), then
/// `U·x = y` backwards (`x_i = y_i/U_ii`, then `y_k −= U_ki·x_i` for `k < i`).
fn dense_solve_upper(u: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let col = &u[n * i..n * i + i + 1];
        let (done, rest) = b.split_at_mut(i);
        rest[0] = (rest[0] - dot(&col[..i], done)) / col[i];
    }
    for i in (0..n).rev() {
        let col = &u[n * i..n * i + i + 1];
        let (above, rest) = b.split_at_mut(i);
        let x = rest[0] / col[i];
        rest[0] = x;
        for (y, c) in above.iter_mut().zip(&col[..i]) {
            *y -= c * x;
        }
    }
}
