//! Leaves-first block elimination of a tree island in the body + joint form (Baraff 1996,
//! "Linear-time dynamics using Lagrange multipliers").
//!
//! # The system
//! With the impulse `P_j` of every joint and the velocity change `u_b = M_b⁻¹·Σ J_jbᵀ·P_j`
//! that the impulses give every body as unknowns, the implicit update of
//! [`super`] reads
//!
//! ```text
//! ⎡ G⁻¹   J ⎤ ⎡P⎤   ⎡ r ⎤        r_j = G_j⁻¹·h·Q_j − Σ_b J_jb·Δv_ext,b
//! ⎣ Jᵀ   −M ⎦ ⎣u⎦ = ⎣ 0 ⎦
//! ```
//!
//! whose first row is `(G⁻¹ + J·M⁻¹·Jᵀ)·P = r` once `u` is eliminated: the joint-space
//! system. This matrix is quasi-definite (`G⁻¹ ≻ 0`, `−M ≺ 0`), so a block `LDLᵀ` without
//! pivoting is stable in any order; its graph is the body–joint tree, so eliminating children
//! before parents makes no fill and costs O(n) for chains, trees and hubs alike (a body with
//! `d` joints costs O(d), not the O(d³) of the dense `6d × 6d` clique it makes in
//! `J·M⁻¹·Jᵀ`).
//!
//! # Elimination (children first)
//! A joint node accumulates `D_j = G_j⁻¹ + Σ_children J·N_b·Jᵀ` and `y_j = r_j + Σ J·N_b·y_b`;
//! its factor `D_j = L·Lᵀ` is kept. A body node accumulates `S_b = Σ_children Jᵀ·D_j⁻¹·J`
//! (as `XᵀX` with `X = L⁻¹·J`) and `y_b = −Σ Jᵀ·D_j⁻¹·y_j`, and keeps
//! `N_b = (M_b + S_b)⁻¹` as the Cholesky factor of `M_b + S_b` (or, when rapier locks a
//! rotation and `M⁻¹` is singular, explicitly as `(I + M_b⁻¹·S_b)⁻¹·M_b⁻¹`).
//! Back-substitution from the root:
//! `P_j = D_j⁻¹·(y_j − J·u_parent)`, `u_b = N_b·(Jᵀ·P_parent − y_b)`.

use super::block;
use super::topology::{NodeKind, TreeNode};
use super::{joint_block, SolveFailure, SolverBody, SolverJoint};
use nalgebra::{Matrix6, Vector6};

/// The workspace of one tree island, allocated once per topology.
#[derive(Debug, Clone)]
pub(crate) struct TreeSolve {
    pub(crate) nodes: Vec<TreeNode>,
    /// Per node: the accumulated `D_j` / `S_b`, then the factor `L_j` / `N_b`.
    mat: Vec<Matrix6<f64>>,
    /// Per node: the accumulated `y`, then the solution (`P_j` or `u_b`).
    pub(crate) x: Vec<Vector6<f64>>,
    /// Per node: whether a body node received a child's contribution (a leaf body has
    /// `N = M⁻¹` and needs no factorisation).
    loaded: Vec<bool>,
    /// Per body node: what `mat` holds.
    held: Vec<Held>,
}

/// What `mat` holds for a body node once it is eliminated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Held {
    /// Nothing: a leaf body, `N = M⁻¹` is the body's own `inv_mass` (block-diagonal).
    Leaf,
    /// The Cholesky factor of `M + S`.
    Factor,
    /// `N` itself.
    Explicit,
}

impl TreeSolve {
    pub(crate) fn new(nodes: Vec<TreeNode>) -> Self {
        let n = nodes.len();
        TreeSolve {
            nodes,
            mat: vec![Matrix6::zeros(); n],
            x: vec![Vector6::zeros(); n],
            loaded: vec![false; n],
            held: vec![Held::Leaf; n],
        }
    }

    pub(crate) fn solve(
        &mut self,
        joints: &[SolverJoint],
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        // 1. Right-hand sides and the joints' own blocks G⁻¹.
        for (i, node) in self.nodes.iter().enumerate() {
            self.loaded[i] = false;
            match node.kind {
                NodeKind::Joint(j) => {
                    joint_block(joints, bodies, j, &mut self.mat[i], &mut self.x[i])?;
                }
                NodeKind::Body(_) => {
                    self.mat[i] = Matrix6::zeros();
                    self.x[i] = Vector6::zeros();
                }
            }
        }
        // 2. Elimination, children before parents.
        for i in 0..self.nodes.len() {
            let node = self.nodes[i];
            let parent = node.parent as usize;
            match node.kind {
                NodeKind::Joint(j) => {
                    if !block::cholesky_in_place(&mut self.mat[i]) {
                        return Err(SolveFailure::NotPositive(j));
                    }
                    if node.parent != u32::MAX {
                        // parent body: S += Jᵀ·D⁻¹·J = XᵀX,  y_b −= Jᵀ·D⁻¹·y_j = Xᵀ·(L⁻¹·y_j)
                        let (done, rest) = self.mat.split_at_mut(parent);
                        let l = &done[i];
                        let mut x = block::rows_of(&joints[j as usize].jac[node.side as usize]);
                        block::forward_rows(l, &mut x);
                        block::add_gram(&mut rest[0], &x);
                        let mut z = self.x[i];
                        block::forward(l, &mut z);
                        self.x[parent] -= block::transpose_mul(&x, &z);
                        self.loaded[parent] = true;
                    }
                }
                NodeKind::Body(b) => {
                    let body = &bodies[b as usize];
                    let jac = if node.parent != u32::MAX {
                        let NodeKind::Joint(pj) = self.nodes[parent].kind else {
                            unreachable!("a body's parent is a joint")
                        };
                        Some(&joints[pj as usize].jac[node.side as usize])
                    } else {
                        None
                    };
                    if !self.loaded[i] {
                        // a leaf body: N = M⁻¹, read from the body where it is needed
                        self.held[i] = Held::Leaf;
                    } else if let Some(c) = body.mass.and_then(|m| {
                        let mut c = m + self.mat[i];
                        block::cholesky_in_place(&mut c).then_some(c)
                    }) {
                        // N = (M + S)⁻¹ kept as the factor C of M + S = C·Cᵀ: the stiff
                        // directions of N (≈ 1/G of the child joints, tiny) keep their relative
                        // accuracy, which an explicit inverse would bury under the round-off
                        // of its large free-direction entries
                        self.mat[i] = c;
                        self.held[i] = Held::Factor;
                    } else {
                        // M⁻¹ singular (rapier locks a rotation): N = (I + M⁻¹·S)⁻¹·M⁻¹
                        let minv = &body.inv_mass;
                        let a = Matrix6::identity() + minv * self.mat[i];
                        let n = a.lu().solve(minv).ok_or(SolveFailure::SingularBody(b))?;
                        self.mat[i] = 0.5 * (n + n.transpose());
                        self.held[i] = Held::Explicit;
                    }
                    if let Some(jac) = jac {
                        // parent joint: D += J·N·Jᵀ,  y += J·N·y_b
                        if self.held[i] == Held::Leaf {
                            // y_b = 0: no child gave the body anything
                            block::add_congruence_inv_mass(
                                &mut self.mat[parent],
                                jac,
                                &body.inv_mass,
                            );
                        } else if self.held[i] == Held::Factor {
                            let (done, rest) = self.mat.split_at_mut(parent);
                            let c = &done[i];
                            let mut y = block::rows_of_transpose(jac);
                            block::forward_rows(c, &mut y);
                            block::add_gram(&mut rest[0], &y);
                            let mut z = self.x[i];
                            block::forward(c, &mut z);
                            self.x[parent] += block::transpose_mul(&y, &z);
                        } else {
                            let (done, rest) = self.mat.split_at_mut(parent);
                            let n = &done[i];
                            block::add_congruence(&mut rest[0], jac, n);
                            let ny = n * self.x[i];
                            self.x[parent] += jac * ny;
                        }
                    }
                }
            }
        }
        // 3. Back-substitution, parents before children.
        for i in (0..self.nodes.len()).rev() {
            let node = self.nodes[i];
            let parent = node.parent as usize;
            match node.kind {
                NodeKind::Joint(j) => {
                    let mut w = self.x[i];
                    if node.parent != u32::MAX {
                        w -= joints[j as usize].jac[node.side as usize] * self.x[parent];
                    }
                    block::chol_solve(&self.mat[i], &mut w);
                    self.x[i] = w;
                }
                NodeKind::Body(b) => {
                    let mut w = -self.x[i];
                    if node.parent != u32::MAX {
                        let NodeKind::Joint(pj) = self.nodes[parent].kind else {
                            unreachable!("a body's parent is a joint")
                        };
                        w += joints[pj as usize].jac[node.side as usize].transpose()
                            * self.x[parent];
                    }
                    match self.held[i] {
                        Held::Leaf => self.x[i] = bodies[b as usize].inv_mass * w,
                        Held::Factor => {
                            block::chol_solve(&self.mat[i], &mut w);
                            self.x[i] = w;
                        }
                        Held::Explicit => self.x[i] = self.mat[i] * w,
                    }
                }
            }
        }
        Ok(())
    }
}
