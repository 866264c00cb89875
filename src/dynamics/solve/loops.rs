//! Islands with closed loops: the joint-space system `(G⁻¹ + J·M⁻¹·Jᵀ)·P = r` of
//! [`super::tree`] factorised by `faer`'s sparse Cholesky. The pattern (one 6×6 block per
//! pair of joints sharing a body), its fill-reducing ordering (AMD) and the symbolic
//! factorisation are computed once per topology; every substep only writes the values in
//! place, refactorises numerically and solves, with no allocation.

use super::{block, joint_block, SolveFailure, SolverBody, SolverJoints};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, Par, Side};
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

/// The workspace of one island with loops.
pub(crate) struct LoopSolve {
    /// Global joint index of each local joint.
    joints: Vec<u32>,
    /// Global body indices, and for each the local joints on it with their side.
    bodies: Vec<u32>,
    body_start: Vec<usize>,
    body_sides: Vec<(u32, u8)>,
    pairs: Vec<Pair>,
    /// Upper triangle in compressed columns.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    /// Number of blocks in each block column (the diagonal block is the last).
    col_blocks: Vec<u32>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    mem: MemBuffer,
    rhs: Mat<f64>,
    /// Impulse of each local joint after [`Self::solve`].
    pub(crate) impulses: Vec<Vector6<f64>>,
    /// Velocity change of each body (same order as `bodies`) after [`Self::solve`].
    pub(crate) velocity: Vec<Vector6<f64>>,
}

impl std::fmt::Debug for LoopSolve {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoopSolve")
            .field("joints", &self.joints.len())
            .field("nnz", &self.values.len())
            .field("factor", &self.l_values.len())
            .finish()
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
        LoopSolve {
            joints: joints.to_vec(),
            bodies: bodies.to_vec(),
            body_start,
            body_sides,
            pairs,
            values: vec![0.0; row_idx.len()],
            col_blocks: rows_of_col.iter().map(|r| r.len() as u32).collect(),
            col_ptr,
            row_idx,
            l_values: vec![0.0; symbolic.len_val()],
            symbolic,
            mem,
            rhs: Mat::zeros(n, 1),
            impulses: vec![Vector6::zeros(); nj],
            velocity: vec![Vector6::zeros(); bodies.len()],
        }
    }

    /// Global joint indices, in local order.
    pub(crate) fn joints(&self) -> &[u32] {
        &self.joints
    }

    /// Global body indices, in local order.
    pub(crate) fn bodies(&self) -> &[u32] {
        &self.bodies
    }

    /// Adds `m` (upper triangle only when `a == c`) to block `(a, c)`, `a ≤ c`.
    fn add_block(&mut self, c: u32, slot: u32, diagonal: bool, m: &Matrix6<f64>) {
        let before = 6 * slot as usize;
        for k in 0..6 {
            let start = self.col_ptr[6 * c as usize + k] + before;
            let top = if diagonal { k + 1 } else { 6 };
            for r in 0..top {
                self.values[start + r] += m[(r, k)];
            }
        }
    }

    pub(crate) fn solve(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        self.values.iter_mut().for_each(|v| *v = 0.0);
        for lj in 0..self.joints.len() {
            let (mut g_inv, mut r) = (Matrix6::zeros(), Vector6::zeros());
            joint_block(joints, bodies, self.joints[lj], &mut g_inv, &mut r)?;
            for i in 0..6 {
                self.rhs[(6 * lj + i, 0)] = r[i];
            }
            let slot = self.col_blocks[lj] - 1;
            self.add_block(lj as u32, slot, true, &g_inv);
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
            self.add_block(pair.c, pair.slot, pair.a == pair.c, &block);
        }
        let n = 6 * self.joints.len();
        let pattern =
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let a = SparseColMatRef::new(pattern, &self.values);
        let stack = MemStack::new(&mut self.mem);
        let llt = self
            .symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                a,
                Side::Upper,
                Default::default(),
                Par::Seq,
                stack,
                Default::default(),
            )
            .map_err(|_| SolveFailure::NotPositive(self.joints[0]))?;
        llt.solve_in_place_with_conj(Conj::No, self.rhs.as_mut(), Par::Seq, stack);
        for lj in 0..self.joints.len() {
            self.impulses[lj] = Vector6::from_fn(|i, _| self.rhs[(6 * lj + i, 0)]);
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
