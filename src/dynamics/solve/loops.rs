//! Islands with closed loops: the joint-space system `(G⁻¹ + J·M⁻¹·Jᵀ)·P = r` of
//! [`super::tree`] factorised by Cholesky, with no allocation per substep. Once per
//! topology, faer orders the island's joints (AMD on the graph of joints sharing a body)
//! and analyses the fill of that order (its simplicial symbolic factorisation); then
//!
//! - **by blocks** (a four-bar linkage, a closed gripper, a suspension, a ring of rods, a
//!   track): the non-zero 6×6 blocks of the factor, one block row a joint in that order,
//!   factorised with the tree's 6×6 kernels ([`BlockFactor`]);
//! - **by faer's sparse Cholesky** when that would take more than
//!   [`BLOCK_OPERATIONS_PER_JOINT`] block operations a joint (a dense coupling, such as
//!   many joints on the same two bodies, where faer's supernodal kernels pay): the scalar
//!   upper triangle (one 6×6 block per pair of joints sharing a body) with its own ordering
//!   and symbolic factorisation, computed once; every substep writes the values in place,
//!   refactorises numerically and solves.
//!
//! Instructions of a whole run (callgrind, `chain_frames N 50 kjoint2 ring`: a ring of `N`
//! rods pinned to the world at a corner, `N + 1` joints, 53 frames of 4 substeps, building
//! included), the island by blocks and by faer:
//!
//! | rods in the ring | 8 | 12 | 16 | 24 | 48 | 100 |
//! |---|---|---|---|---|---|---|
//! | by blocks [million] | 21.4 | 29.9 | 38.2 | 55.0 | 105.1 | 213.4 |
//! | faer [million] | 56.3 | 81.4 | 106.5 | 156.7 | 307.8 | 634.2 |
//!
//! In faer's order a ring fills a block or two a joint (its joints cost about nine block
//! operations each); faer's numeric factorisation, scalar and simplicial at this sparsity,
//! spends its time in index bookkeeping and checks. A ring of 1000 rods by blocks takes
//! about the time of the open 1000-link chain (5.0–6.7 against 4.0–6.2 ms a frame, the
//! machine slow; faer 12–18 ms). A fully coupled island of `n` joints takes about `n³/6`
//! block products, over the bound from 9 joints on. The free four-bar of the solver bench
//! (4 joints, 4 bodies): 74 600 instructions a substep in faer's factorisation, 40 800
//! with a scalar dense Cholesky, about 12 000 by blocks (the run 228.0, 159.9 and 102.4
//! million instructions).

use super::block::{self, Rows};
use super::{joint_block, SolveFailure, SolverBody, SolverJoints};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use nalgebra::{Matrix6, Vector6};

/// One pair of joint sides on a shared body: a contribution `J_a·M⁻¹·J_cᵀ` to block
/// `(a, c)` of two joints (local, `a < c`; a joint's own congruences are in its diagonal
/// block), stored at `slot` among the blocks of column `c` (faer) or at `block` in
/// [`BlockFactor::off`] (by blocks).
#[derive(Debug, Clone, Copy)]
struct Pair {
    body: u32,
    a: u32,
    side_a: u8,
    c: u32,
    side_c: u8,
    slot: u32,
    block: u32,
}

/// Most 6×6 block operations a joint of an island factorised by blocks
/// ([`BlockFactor::operations`]): more, and faer's sparse factorisation takes the island.
const BLOCK_OPERATIONS_PER_JOINT: usize = 16;

/// faer's sparse Cholesky of an island: the upper triangle of its matrix in compressed
/// columns, the symbolic factorisation and their workspace.
struct SparseFactor {
    /// Upper triangle in compressed columns.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    /// Number of blocks in each block column (the diagonal block is the last).
    col_blocks: Vec<u32>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    mem: MemBuffer,
    /// The right-hand side, then the impulses (`6·joints` numbers).
    rhs: Vec<f64>,
}

impl SparseFactor {
    /// The scalar upper triangle of the island's block pattern (`rows_of_col` as in
    /// [`BlockFactor::new`]) and faer's symbolic factorisation of it (AMD ordering).
    fn new(nj: usize, rows_of_col: &[Vec<u32>]) -> Self {
        // column 6c + k holds, for every block row a < c, its six rows, then rows
        // 6c ..= 6c + k of the diagonal block
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
        SparseFactor {
            values: vec![0.0; row_idx.len()],
            col_ptr,
            row_idx,
            col_blocks: rows_of_col.iter().map(|r| r.len() as u32).collect(),
            l_values: vec![0.0; symbolic.len_val()],
            symbolic,
            mem,
            rhs: vec![0.0; n],
        }
    }
}

/// How an island's matrix is kept and factorised.
enum Factor {
    Sparse(Box<SparseFactor>),
    Blocks(Box<BlockFactor>),
}

/// An island's matrix as the non-zero 6×6 blocks of its lower triangle (one block row a
/// joint, in faer's fill-reducing order, the fill included), factorised in place by block
/// Cholesky ([`BlockFactor::factorise`]) with the tree's 6×6 kernels ([`block`]).
struct BlockFactor {
    /// Diagonal block of each joint: `D_k`, then its factor `L_k` (`D_k = L_k·L_kᵀ`, lower
    /// triangle, [`block::cholesky_in_place`]).
    diag: Vec<Matrix6<f64>>,
    /// The position of each local joint in the elimination order; the blocks, `x` and the
    /// lists below are in that order.
    pos: Vec<u32>,
    /// For each joint `k`, from `right_start[k]`: the joints `c > k` whose block `(k, c)`
    /// is non-zero in the factor (ascending), the pattern's blocks (the joints share a
    /// body) and the fill the elimination makes, found once per topology.
    right_start: Vec<usize>,
    right: Vec<u32>,
    /// The block `(k, c)` of each entry of `right`, by rows (row `i` of joint `k`, column
    /// `j` of joint `c`): `A_kc`, then `U_kc = L_k⁻¹·A_kc`.
    off: Vec<Rows>,
    /// Where each product `U_kcᵀ·U_kd` of [`Self::factorise`] goes (the index of block
    /// `(c, d)` in `off`), in the order the factorisation makes them.
    targets: Vec<u32>,
    /// The right-hand side, then the impulses.
    x: Vec<Vector6<f64>>,
}

impl BlockFactor {
    /// The joints' elimination order and the factor's block pattern, from faer's symbolic
    /// analysis of the joints' graph (`rows_of_col[c]`: the joints `a ≤ c` sharing a body
    /// with `c`, ascending: the upper triangle of the `nj × nj` block pattern by columns):
    /// its fill-reducing ordering (AMD) and the pattern of its simplicial factor, whose
    /// column `k` lists the joints `c > k` (in the new order) that eliminating joint `k`
    /// couples to it.
    fn new(nj: usize, rows_of_col: &[Vec<u32>]) -> Self {
        let mut col_ptr = vec![0usize];
        let mut row_idx = Vec::new();
        for rows in rows_of_col {
            row_idx.extend(rows.iter().map(|&a| a as usize));
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMatRef::new_checked(nj, nj, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .expect("symbolic analysis of a valid pattern");
        // new position of each joint: P·A·Pᵀ has entry (i, j) = A(fwd[i], fwd[j])
        let pos: Vec<u32> = match symbolic.perm() {
            Some(p) => p.arrays().1.iter().map(|&i| i as u32).collect(),
            None => (0..nj as u32).collect(),
        };
        let SymbolicCholeskyRaw::Simplicial(l) = symbolic.raw() else {
            unreachable!("simplicial forced")
        };
        // column k of L: its diagonal first, then the rows below it, ascending
        let mut right_start = vec![0];
        let mut right = Vec::new();
        for k in 0..nj {
            let rows = &l.row_idx()[l.col_ptr()[k]..l.col_ptr()[k + 1]];
            debug_assert_eq!(rows.first(), Some(&k));
            right.extend(rows.iter().skip(1).map(|&c| c as u32));
            right_start.push(right.len());
        }
        let mut f = BlockFactor {
            diag: vec![Matrix6::zeros(); nj],
            off: vec![[[0.0; 6]; 6]; right.len()],
            pos,
            right_start,
            right,
            targets: Vec::new(),
            x: vec![Vector6::zeros(); nj],
        };
        for k in 0..nj {
            let (start, end) = (f.right_start[k], f.right_start[k + 1]);
            for i in start..end {
                for j in i + 1..end {
                    let target = f.block(f.right[i] as usize, f.right[j] as usize);
                    f.targets.push(target as u32);
                }
            }
        }
        f
    }

    /// The index in `off` of block `(a, c)`, `a < c`, non-zero in the factor.
    fn block(&self, a: usize, c: usize) -> usize {
        let found = self.right_of(a).binary_search(&(c as u32));
        self.right_start[a] + found.expect("a block of the factor's pattern")
    }

    /// The joints `c > k` with a non-zero block `(k, c)`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn right_of(&self, k: usize) -> &[u32] {
        &self.right[self.right_start[k]..self.right_start[k + 1]]
    }

    /// Right-looking block Cholesky, joint `k` after joint `k − 1`:
    ///
    /// ```text
    /// D_k = L_k·L_kᵀ,   U_kc = L_k⁻¹·A_kc   (c > k),
    /// A_cd −= U_kcᵀ·U_kd   (k < c ≤ d; the lower triangle where c = d)
    /// ```
    ///
    /// over the non-zero blocks only. `Err(k)`: the pivot block of joint `k` is not
    /// positive definite.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn factorise(&mut self) -> Result<(), usize> {
        let mut targets = self.targets.iter();
        for k in 0..self.diag.len() {
            if !block::cholesky_in_place(&mut self.diag[k]) {
                return Err(k);
            }
            let l = self.diag[k];
            let (start, end) = (self.right_start[k], self.right_start[k + 1]);
            for u in &mut self.off[start..end] {
                block::forward_rows(&l, u);
            }
            for i in start..end {
                let u_kc = self.off[i];
                block::sub_lower_gram(&mut self.diag[self.right[i] as usize], &u_kc);
                for j in i + 1..end {
                    let u_kd = self.off[j];
                    let t = *targets.next().expect("a target for every product") as usize;
                    block::sub_tr_mul_rows(&mut self.off[t], &u_kc, &u_kd);
                }
            }
        }
        Ok(())
    }

    /// The 6×6 block operations of [`Self::factorise`]: for each joint `k` with `m`
    /// non-zero blocks right of its diagonal, `m` triangular solves and `m·(m + 1)/2`
    /// products.
    fn operations(&self) -> usize {
        (0..self.diag.len())
            .map(|k| {
                let m = self.right_of(k).len();
                m + m * (m + 1) / 2
            })
            .sum()
    }

    /// `x ← A⁻¹·x` with the factor: `y_k = L_k⁻¹·(x_k − Σ_{a<k} U_akᵀ·y_a)` forwards, then
    /// `x_k = L_k⁻ᵀ·(y_k − Σ_{c>k} U_kc·x_c)` backwards.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn solve(&mut self) {
        let nj = self.diag.len();
        for k in 0..nj {
            let mut y = self.x[k];
            block::forward(&self.diag[k], &mut y);
            self.x[k] = y;
            for i in self.right_start[k]..self.right_start[k + 1] {
                self.x[self.right[i] as usize] -= block::transpose_mul(&self.off[i], &y);
            }
        }
        for k in (0..nj).rev() {
            let mut w = self.x[k];
            for i in self.right_start[k]..self.right_start[k + 1] {
                w -= block::rows_mul(&self.off[i], &self.x[self.right[i] as usize]);
            }
            block::backward(&self.diag[k], &mut w);
            self.x[k] = w;
        }
    }
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
    factor: Factor,
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
            Factor::Blocks(b) => d.field("blocks", &(b.diag.len() + b.off.len())),
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
                    if a < c {
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
                            block: u32::MAX,
                        });
                    }
                }
            }
        }
        let blocks = Some(BlockFactor::new(nj, &rows_of_col))
            .filter(|b| b.operations() <= BLOCK_OPERATIONS_PER_JOINT * nj);
        let factor = if let Some(blocks) = blocks {
            for p in &mut pairs {
                let (pa, pc) = (blocks.pos[p.a as usize], blocks.pos[p.c as usize]);
                p.block = blocks.block(pa.min(pc) as usize, pa.max(pc) as usize) as u32;
            }
            Factor::Blocks(Box::new(blocks))
        } else {
            Factor::Sparse(Box::new(SparseFactor::new(nj, &rows_of_col)))
        };
        LoopSolve {
            joints: joints.to_vec(),
            bodies: bodies.to_vec(),
            body_start,
            body_sides,
            pairs,
            factor,
            impulses: vec![Vector6::zeros(); nj],
            velocity: vec![Vector6::zeros(); bodies.len()],
        }
    }

    /// Whether the island is factorised by blocks ([`BLOCK_OPERATIONS_PER_JOINT`]).
    #[cfg(test)]
    pub(crate) fn by_blocks(&self) -> bool {
        matches!(self.factor, Factor::Blocks(_))
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
    /// block `slot` of column `c` of the sparse upper triangle.
    fn add_block(f: &mut SparseFactor, c: u32, slot: u32, diagonal: bool, m: &Matrix6<f64>) {
        let before = 6 * slot as usize;
        for k in 0..6 {
            let start = f.col_ptr[6 * c as usize + k] + before;
            let top = if diagonal { k + 1 } else { 6 };
            for r in 0..top {
                f.values[start + r] += m[(r, k)];
            }
        }
    }

    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn solve(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        match &mut self.factor {
            Factor::Sparse(f) => {
                Self::solve_sparse(f, &self.joints, &self.pairs, joints, bodies)?;
                for (lj, p) in self.impulses.iter_mut().enumerate() {
                    *p = Vector6::from_column_slice(&f.rhs[6 * lj..6 * lj + 6]);
                }
            }
            Factor::Blocks(f) => {
                Self::solve_blocks(f, &self.joints, &self.pairs, joints, bodies)?;
                for (p, &k) in self.impulses.iter_mut().zip(&f.pos) {
                    *p = f.x[k as usize];
                }
            }
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

    /// Joint `j`'s diagonal block `D = G⁻¹ + Σ_s J_s·M_s⁻¹·J_sᵀ` (lower triangle:
    /// [`block::add_two_sided_congruence`], [`block::add_jacobian_congruence`]) and its
    /// right-hand side.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn diagonal_block(
        joints: &SolverJoints,
        bodies: &[SolverBody],
        j: u32,
        d: &mut Matrix6<f64>,
        r: &mut Vector6<f64>,
    ) -> Result<(), SolveFailure> {
        joint_block(joints, bodies, j, d, r)?;
        let sj = &joints[j as usize];
        let inv_mass = |s: usize| sj.bodies[s].map(|b| &bodies[b as usize].inv_mass);
        match (inv_mass(0), inv_mass(1)) {
            (Some(m1), Some(m2)) => block::add_two_sided_congruence(d, &sj.jac, m1, m2),
            (Some(m1), None) => block::add_jacobian_congruence(d, &sj.jac, 0, m1),
            (None, Some(m2)) => block::add_jacobian_congruence(d, &sj.jac, 1, m2),
            (None, None) => {}
        }
        Ok(())
    }

    /// The coupling `J_1·M⁻¹·J_2ᵀ` of two joints of the island on the body of `pair`, by
    /// rows (row `i` of joint `first`, column `j` of joint `second`; each a local joint and
    /// its side), from the Jacobians' 3×3 blocks ([`block::add_link_products`]).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn coupling_block(
        island: &[u32],
        pair: &Pair,
        first: (u32, u8),
        second: (u32, u8),
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Rows {
        let j1 = &joints[island[first.0 as usize] as usize].jac;
        let j2 = &joints[island[second.0 as usize] as usize].jac;
        let mut e = [[0.0; 6]; 6];
        block::add_link_products(
            None,
            None,
            &mut e,
            j1,
            first.1 as usize,
            j2,
            second.1 as usize,
            &bodies[pair.body as usize].inv_mass,
        );
        e
    }

    /// A small island by blocks: each joint's [`Self::diagonal_block`], each pair sharing a
    /// body its [`Self::coupling_block`], then [`BlockFactor::factorise`] and
    /// [`BlockFactor::solve`].
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn solve_blocks(
        f: &mut BlockFactor,
        island: &[u32],
        pairs: &[Pair],
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        for (lj, &j) in island.iter().enumerate() {
            let k = f.pos[lj] as usize;
            Self::diagonal_block(joints, bodies, j, &mut f.diag[k], &mut f.x[k])?;
        }
        f.off.fill([[0.0; 6]; 6]);
        for pair in pairs {
            // the joint first in the elimination order gives the block's rows
            let (a, c) = ((pair.a, pair.side_a), (pair.c, pair.side_c));
            let (first, second) = if f.pos[a.0 as usize] < f.pos[c.0 as usize] {
                (a, c)
            } else {
                (c, a)
            };
            let e = Self::coupling_block(island, pair, first, second, joints, bodies);
            let out = &mut f.off[pair.block as usize];
            for (o, e) in out.iter_mut().zip(&e) {
                for (o, e) in o.iter_mut().zip(e) {
                    *o += e;
                }
            }
        }
        if let Err(k) = f.factorise() {
            let lj = f.pos.iter().position(|&p| p as usize == k).unwrap_or(0);
            return Err(SolveFailure::NotPositive(island[lj]));
        }
        f.solve();
        Ok(())
    }

    /// A large island with faer: the upper triangle of `G⁻¹ + J·M⁻¹·Jᵀ` written in place
    /// from the same blocks as [`Self::solve_blocks`], factorised numerically with the symbolic analysis of [`Self::new`], and solved.
    fn solve_sparse(
        f: &mut SparseFactor,
        island: &[u32],
        pairs: &[Pair],
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        f.values.fill(0.0);
        for (lj, &j) in island.iter().enumerate() {
            let (mut d, mut r) = (Matrix6::zeros(), Vector6::zeros());
            Self::diagonal_block(joints, bodies, j, &mut d, &mut r)?;
            f.rhs[6 * lj..6 * lj + 6].copy_from_slice(r.as_slice());
            // the upper triangle from the lower one
            Self::add_block(f, lj as u32, f.col_blocks[lj] - 1, true, &d.transpose());
        }
        for pair in pairs {
            let (a, c) = ((pair.a, pair.side_a), (pair.c, pair.side_c));
            let e = Self::coupling_block(island, pair, a, c, joints, bodies);
            Self::add_block(
                f,
                pair.c,
                pair.slot,
                false,
                &Matrix6::from_row_slice(e.as_flattened()),
            );
        }
        let n = 6 * island.len();
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &f.col_ptr, None, &f.row_idx);
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
            .map_err(|_| SolveFailure::NotPositive(island[0]))?;
        let x = MatMut::from_column_major_slice_mut(&mut f.rhs, n, 1);
        llt.solve_in_place_with_conj(Conj::No, x, Par::Seq, stack);
        Ok(())
    }
}
