//! Leaves-first block elimination of a tree island: bodies with at most one child joint in
//! the joint-space form, bodies with several (hubs) in the body + joint form (Baraff 1996,
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
//! pivoting exists in any order; its graph is the body–joint tree (the root is a joint),
//! and eliminating children before parents makes no fill and costs O(n) for chains, trees
//! and hubs alike.
//!
//! # Three kinds of body
//! A body's children in the tree are joints. By their number:
//!
//! * **leaf** (none): its row `Σ Jᵀ·P − M·u = 0` gives `u_b = M_b⁻¹·J_pbᵀ·P_p` (`p` its
//!   parent joint), so it adds `J_pb·M_b⁻¹·J_pbᵀ` to `D_p` and nothing to `y_p`;
//! * **link** (one child joint `c`, a chain's interior body): eliminated the same way,
//!   *before* `c`, in the joint-space form (below);
//! * **hub** (two or more): eliminated after its child joints in the body + joint form, so
//!   that a body with `d` joints costs O(d), not the O(d³) of the dense `6d × 6d` clique
//!   that its `J·M⁻¹·Jᵀ` makes among its joints.
//!
//! [`super::topology`] tells links from the others once per topology.
//!
//! # Joint nodes
//! A joint node accumulates `D_j = G_j⁻¹ + …` and `y_j = r_j + …` from its children, is
//! factored `D_j = L·Lᵀ` (kept), and passes itself on to its parent:
//!
//! * parent a hub `b` (coupling `J = J_jb`): `S_b += Jᵀ·D_j⁻¹·J = XᵀX` with `X = L⁻¹·J`,
//!   `y_b −= Jᵀ·D_j⁻¹·y_j = Xᵀ·(L⁻¹·y_j)`;
//! * parent a link `b` (then `j = c`, the link's child joint): see below;
//! * no parent (the root).
//!
//! # Links (joint-space form)
//! Let `b` be a link between its child joint `c` and its parent joint `p`. Its row gives
//! `u_b = M_b⁻¹·(J_cbᵀ·P_c + J_pbᵀ·P_p)`, which in the rows of `c` and `p` adds
//!
//! ```text
//! D_c += J_cb·M_b⁻¹·J_cbᵀ,   D_p += J_pb·M_b⁻¹·J_pbᵀ,   E = J_cb·M_b⁻¹·J_pbᵀ   (c, p block)
//! ```
//!
//! and nothing to `y` (the body's right-hand side is zero). `E` is the only fill: in the
//! reduced graph `c` hangs from `p` directly. `M_b⁻¹` is the body's own
//! [`SolverBody::inv_mass`], block-diagonal (three inverse masses, the 3×3 world inverse
//! inertia: [`super::MassBlocks`]), so the three products exploit its structure
//! ([`block::add_link_products`], from the Jacobians' 3×3 blocks); it may be singular
//! when rapier locks an axis, which is harmless here: `D_c` and `D_p` stay positive definite
//! through `G⁻¹ ≻ 0`. None of this depends on another node's elimination, so it is done at
//! `c`, just before `c` is factored (same post-order as the other kinds). Then, with
//! `D_c = L·Lᵀ` complete (all of `c`'s children eliminated),
//!
//! ```text
//! X = L⁻¹·E,   z_c = L⁻¹·y_c,   D_p −= XᵀX,   y_p −= Xᵀ·z_c
//! ```
//!
//! and `L`, `z_c` (in `c`'s slot) and `X` (in the link's slot) are kept. A link with no
//! parent joint (not produced by [`super::topology`], whose roots are joints, but handled)
//! only adds `J_cb·M_b⁻¹·J_cbᵀ` to `D_c`.
//!
//! A chain of `n` links thus costs `n` 6×6 Cholesky factorisations instead of the `2n` of
//! the body + joint form (`D_j` and `M_b + S_b` for every link), and the serial dependency
//! of its elimination is one factorisation, one `L⁻¹·E` and one `XᵀX` per link: the
//! congruences of `M_b⁻¹` do not depend on it.
//!
//! # Both sides of a joint at once
//! A joint whose two bodies are both leaves, or a leaf and a link, gets both congruences
//! `J_s·M_s⁻¹·J_sᵀ` with `G⁻¹` in the load step, in one product that shares the joint's `T`
//! and `R` between its sides ([`block::add_two_sided_congruence`]: three 3×3 products
//! instead of four, each block summed once), where the leaf's and the link's eliminations
//! add them otherwise (a lone leaf or link side of a joint is added there too, by itself).
//! A joint with two links (a chain's interior joint) keeps them where the links add them:
//! each beside the Schur complement `−XᵀX` of the chain below, which nearly cancels it, and
//! before the other side's; both at once made the links' errors of the table below up to
//! 10× larger. The contact scene's three-body chains (a leaf, a link, a leaf) are all of
//! the first kind.
//!
//! # Hubs (body + joint form)
//! A hub keeps `N_b = (M_b + S_b)⁻¹` as the Cholesky factor of `M_b + S_b` (or, when rapier
//! locks a rotation and `M⁻¹` is singular, explicitly as `(I + M_b⁻¹·S_b)⁻¹·M_b⁻¹`) and
//! passes `D_p += J·N_b·Jᵀ`, `y_p += J·N_b·y_b` to its parent joint.
//!
//! # Back-substitution (parents first)
//! * joint `j` under a hub `b` (`u_b` known), or the root: `P_j = D_j⁻¹·(y_j − J_jb·u_b)`;
//! * link `b` and its child joint `c` (done together at `c`):
//!   `P_c = L⁻ᵀ·(z_c − X·P_p)`, then `u_b = M_b⁻¹·(J_cbᵀ·P_c + J_pbᵀ·P_p)`;
//! * hub or leaf `b`: `u_b = N_b·(J_pbᵀ·P_p − y_b)` (`N_b = M_b⁻¹`, `y_b = 0` for a leaf).
//!
//! # Accuracy
//! Nothing is inverted explicitly, but the two forms do not accumulate the same thing: the
//! body + joint form sums masses (`M_b + S_b`, positive terms), the joint-space form sums
//! effective *inverse* masses through Schur complements that cancel (the out-of-plane
//! inverse mass of a joint above `k` links held rigid by stiff hinges is ~`1/k³` of a
//! link's own). Against the exact solution (residuals in double-double, test
//! `links_stay_accurate_on_long_stiff_chains`), after 30 frames of swinging, impulses
//! relative to the largest one (the states after 30 frames, and with them these figures,
//! move by up to a factor 3 with any change of round-off: re-measured when the Cholesky
//! pivots went through their reciprocals, [`block::cholesky_in_place`]; the 10 000 links
//! earlier):
//!
//! | chain of rods, `Kn = 1e12` | links | all in the body + joint form |
//! |---|---|---|
//! | 30 links | 1.4e-14 | 5.5e-15 |
//! | 1000 links | 2.6e-12 | 7.1e-13 |
//! | 1000 links, `Kn = 1e8` | 6.7e-13 | 5.9e-14 |
//! | 1000 links, rotations locked but z | 2.5e-12 | 2.0e-12 |
//! | 1000 links, all rotations locked | 6.7e-12 | 1.5e-14 |
//! | 10 000 links | 5.0e-11 (2e-10 in another state) | 8.5e-12 |
//!
//! and the velocity changes alike. The components that carry no load (out of the swing's
//! plane, 1e-14 of the largest impulse) have errors up to 2e-4 of their own size (1e-8 in
//! the body + joint form): 1e-18 of the largest. So the joint-space form loses up to one to
//! two orders of magnitude on long stiff chains (2.5 with every rotation locked), to ~1e-11 at
//! 1000 links: four orders below the f32 rounding of the poses and velocities rapier keeps,
//! and two below the 1e-9 the structured solve is held to against the dense reference.
//! Links are used wherever a body has one child joint. Splitting long runs of links with a
//! body in the body + joint form (every 8 to 128 links) did not bring the body + joint
//! accuracy back, so it is not done.

use super::block;
use super::topology::{NodeKind, TreeNode};
use super::{joint_block, SolveFailure, SolverBody, SolverJoints};
use nalgebra::{Matrix6, Vector6};

/// The workspace of one tree island, allocated once per topology.
#[derive(Debug, Clone)]
pub(crate) struct TreeSolve {
    pub(crate) nodes: Vec<TreeNode>,
    /// Per node that needs one, in node order: the accumulated `D_j` / `S_b`, then the
    /// factor `L_j` / `N_b`; for a link, the rows of `X = L_c⁻¹·E` ([`block::Rows`] in the
    /// column array). A leaf body (no child joint: `N = M⁻¹`, read from the body) has none,
    /// which is half the nodes of a set of pendulums (288 bytes each, touched every
    /// substep when they had one).
    mat: Vec<Matrix6<f64>>,
    /// Per node: its index in `mat` ([`NO_MATRIX`] for a leaf body), increasing with the
    /// node's, so that a child's matrix comes before its parent's (`split_at_mut`).
    slot: Vec<u32>,
    /// Per node: the accumulated `y` (`z_c = L⁻¹·y_c` for a link's child joint once
    /// eliminated), then the solution (`P_j` or `u_b`).
    pub(crate) x: Vec<Vector6<f64>>,
    /// Per node: whether a body node received a child's contribution (a leaf body has
    /// `N = M⁻¹` and needs no factorisation).
    loaded: Vec<bool>,
    /// Per body node: what `mat` holds.
    held: Vec<Held>,
    /// Per joint node: the sides (bit `s` for side `s`) whose congruences `J_s·M_s⁻¹·J_sᵀ`
    /// [`Self::load_node`] adds to `D_j` with `G⁻¹`, both sides' at once where there are two
    /// ([`block::add_two_sided_congruence`]: the joint's `T` and `R` shared). Those of the
    /// bodies eliminated in the joint-space form (a child leaf or link, a parent link),
    /// except at a joint with two links (a chain's interior joint, or a root between two
    /// chains): there each link's congruence stays where its elimination adds it, beside the
    /// Schur complement `−XᵀX` of the chain below that nearly cancels it, before the other
    /// side's is added (adding both first made the links' errors of
    /// `links_stay_accurate_on_long_stiff_chains` up to 10× larger).
    plain: Vec<u8>,
    /// Per node: whether [`Self::load_node`] has run for it in this solve. The elimination
    /// loads a node just before it first touches it (its own turn, or a child adding to
    /// it), so that a node's data are read once while in the cache instead of in a pass of
    /// their own over the whole island ahead of the elimination (at 10 000 links the loads
    /// had left the cache before the elimination read them). The sums are the same, in the
    /// same order: a node's own blocks first, then its children's contributions.
    ready: Vec<bool>,
}

/// [`TreeSolve::slot`] of a node without a matrix.
const NO_MATRIX: u32 = u32::MAX;

/// What `mat` holds for a hub or leaf body node once it is eliminated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Held {
    /// Nothing: a leaf body, `N = M⁻¹` is the body's own `inv_mass` (block-diagonal).
    Leaf,
    /// The Cholesky factor of `M + S`.
    Factor,
    /// `N` itself.
    Explicit,
}

/// The body of a body node.
fn body_of(node: &TreeNode) -> u32 {
    match node.kind {
        NodeKind::Body(b) => b,
        NodeKind::Joint(_) => unreachable!("a joint's parent is a body"),
    }
}

/// The joint of a joint node.
fn joint_of(node: &TreeNode) -> u32 {
    match node.kind {
        NodeKind::Joint(j) => j,
        NodeKind::Body(_) => unreachable!("a body's parent is a joint"),
    }
}

/// The matrix slots of a tree's nodes ([`TreeSolve::slot`], and how many there are) and its
/// joints' `plain` sides ([`TreeSolve::plain`]), from its node list: shared by the scalar
/// solve and the lanes' ([`super::tree_x4`]), which must lay their trees out alike.
pub(super) fn layout(nodes: &[TreeNode]) -> (Vec<u32>, u32, Vec<u8>) {
    let n = nodes.len();
    // a body node without a child joint is a leaf: no matrix
    let mut parent_of_some = vec![false; n];
    for node in nodes {
        if node.parent != u32::MAX {
            parent_of_some[node.parent as usize] = true;
        }
    }
    let mut count = 0;
    let slot = nodes
        .iter()
        .zip(&parent_of_some)
        .map(|(node, &has_child)| match node.kind {
            NodeKind::Body(_) if !has_child => NO_MATRIX,
            _ => {
                count += 1;
                count - 1
            }
        })
        .collect();
    // per joint node: the sides whose bodies are in the joint-space form, and how many
    // of them are links
    let mut plain = vec![0u8; n];
    let mut links = vec![0u8; n];
    for (i, node) in nodes.iter().enumerate() {
        if node.parent == u32::MAX {
            continue;
        }
        let parent = node.parent as usize;
        match node.kind {
            // a joint under a link: the link's side
            NodeKind::Joint(_) if nodes[parent].link => {
                plain[i] |= 1 << node.side;
                links[i] += 1;
            }
            NodeKind::Joint(_) => {}
            // a leaf or a link under its parent joint
            NodeKind::Body(_) if node.link || !parent_of_some[i] => {
                plain[parent] |= 1 << node.side;
                links[parent] += u8::from(node.link);
            }
            NodeKind::Body(_) => {}
        }
    }
    for (p, l) in plain.iter_mut().zip(&links) {
        if *l > 1 {
            *p = 0;
        }
    }
    (slot, count, plain)
}

impl TreeSolve {
    pub(crate) fn new(nodes: Vec<TreeNode>) -> Self {
        let n = nodes.len();
        let (slot, count, plain) = layout(&nodes);
        TreeSolve {
            plain,
            nodes,
            mat: vec![Matrix6::zeros(); count as usize],
            slot,
            x: vec![Vector6::zeros(); n],
            loaded: vec![false; n],
            held: vec![Held::Leaf; n],
            ready: vec![false; n],
        }
    }

    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn solve(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        // every node is loaded by the elimination as it reaches it ([`Self::ready`])
        self.ready.fill(false);
        self.eliminate(joints, bodies)?;
        self.substitute(joints, bodies);
        Ok(())
    }

    /// The joint nodes' right-hand sides `r_j` (tests replace them before
    /// [`Self::eliminate`]).
    #[cfg(test)]
    pub(crate) fn rhs_mut(&mut self) -> impl Iterator<Item = (u32, &mut Vector6<f64>)> {
        self.nodes
            .iter()
            .zip(self.x.iter_mut())
            .filter_map(|(n, x)| match n.kind {
                NodeKind::Joint(j) => Some((j, x)),
                NodeKind::Body(_) => None,
            })
    }

    /// Step 1, all at once: the right-hand sides and the joints' own blocks `G⁻¹` of every
    /// node (tests replace the right-hand sides before [`Self::eliminate`]; the solve leaves
    /// the loads to the elimination, [`Self::ready`]).
    #[cfg(test)]
    pub(crate) fn load(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        self.ready.fill(false);
        for i in 0..self.nodes.len() {
            self.load_node(i, joints, bodies)?;
        }
        Ok(())
    }

    /// Step 1 for node `i` unless done ([`Self::ready`]): a joint's right-hand side and its
    /// own blocks, `G⁻¹` and the congruences of [`Self::plain`]; a hub or leaf body's zero
    /// accumulators (a link's slots are written before they are read).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn load_node(
        &mut self,
        i: usize,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        if self.ready[i] {
            return Ok(());
        }
        self.ready[i] = true;
        self.loaded[i] = false;
        let node = self.nodes[i];
        match node.kind {
            NodeKind::Joint(j) => {
                let m = self.slot[i] as usize;
                let d = &mut self.mat[m];
                joint_block(joints, bodies, j, d, &mut self.x[i])?;
                // the congruences J_s·M_s⁻¹·J_sᵀ of the sides whose bodies are leaves or
                // links, both at once where the joint has two ([`Self::plain`])
                let sj = &joints[j as usize];
                let inv_mass = |s: usize| sj.bodies[s].map(|b| &bodies[b as usize].inv_mass);
                match (self.plain[i], inv_mass(0), inv_mass(1)) {
                    (3, Some(m1), Some(m2)) => block::add_two_sided_congruence(d, &sj.jac, m1, m2),
                    (1, Some(m1), _) => block::add_jacobian_congruence(d, &sj.jac, 0, m1),
                    (2, _, Some(m2)) => block::add_jacobian_congruence(d, &sj.jac, 1, m2),
                    _ => {}
                }
            }
            NodeKind::Body(_) if !node.link => {
                if self.slot[i] != NO_MATRIX {
                    self.mat[self.slot[i] as usize] = Matrix6::zeros();
                }
                self.x[i] = Vector6::zeros();
            }
            NodeKind::Body(_) => {}
        }
        Ok(())
    }

    /// Step 2: elimination, children before parents.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn eliminate(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        for i in 0..self.nodes.len() {
            self.load_node(i, joints, bodies)?;
            let node = self.nodes[i];
            let parent = node.parent as usize;
            match node.kind {
                NodeKind::Joint(j) if node.parent != u32::MAX && self.nodes[parent].link => {
                    self.eliminate_link(i, j, joints, bodies)?;
                }
                NodeKind::Joint(j) => {
                    let m = self.slot[i] as usize;
                    if !block::cholesky_in_place(&mut self.mat[m]) {
                        return Err(SolveFailure::NotPositive(j));
                    }
                    if node.parent != u32::MAX {
                        self.load_node(parent, joints, bodies)?;
                        // parent hub: S += Jᵀ·D⁻¹·J = XᵀX,  y_b −= Jᵀ·D⁻¹·y_j = Xᵀ·(L⁻¹·y_j)
                        let (done, rest) = self.mat.split_at_mut(self.slot[parent] as usize);
                        let l = &done[m];
                        let mut x =
                            block::rows_of(&joints[j as usize].jac.matrix(node.side as usize));
                        block::forward_rows(l, &mut x);
                        block::add_gram(&mut rest[0], &x);
                        let mut z = self.x[i];
                        block::forward(l, &mut z);
                        self.x[parent] -= block::transpose_mul(&x, &z);
                        self.loaded[parent] = true;
                    }
                }
                // eliminated with its child joint
                NodeKind::Body(_) if node.link => {}
                NodeKind::Body(b) => {
                    let body = &bodies[b as usize];
                    let side = node.side as usize;
                    let jac = (node.parent != u32::MAX)
                        .then(|| &joints[joint_of(&self.nodes[parent]) as usize].jac);
                    if !self.loaded[i] {
                        // a leaf body: N = M⁻¹, read from the body where it is needed
                        self.held[i] = Held::Leaf;
                    } else if let Some(c) = match body.mass {
                        // (a `match`, not `Option::and_then` with a closure: the closure was
                        // compiled out of line in the AVX2 copy of the substep)
                        Some(m) => {
                            let mut c = self.mat[self.slot[i] as usize];
                            m.add_to(&mut c);
                            block::cholesky_in_place(&mut c).then_some(c)
                        }
                        None => None,
                    } {
                        // N = (M + S)⁻¹ kept as the factor C of M + S = C·Cᵀ: the stiff
                        // directions of N (≈ 1/G of the child joints, tiny) keep their relative
                        // accuracy, which an explicit inverse would bury under the round-off
                        // of its large free-direction entries
                        self.mat[self.slot[i] as usize] = c;
                        self.held[i] = Held::Factor;
                    } else {
                        // M⁻¹ singular (rapier locks a rotation): N = (I + M⁻¹·S)⁻¹·M⁻¹
                        let minv = body.inv_mass.matrix();
                        let m = self.slot[i] as usize;
                        let a = Matrix6::identity() + minv * self.mat[m];
                        let n = a.lu().solve(&minv).ok_or(SolveFailure::SingularBody(b))?;
                        self.mat[m] = 0.5 * (n + n.transpose());
                        self.held[i] = Held::Explicit;
                    }
                    if let Some(jac) = jac {
                        self.load_node(parent, joints, bodies)?;
                        // parent joint: D += J·N·Jᵀ,  y += J·N·y_b
                        if self.held[i] == Held::Leaf {
                            // y_b = 0: no child gave the body anything; J·M⁻¹·Jᵀ unless
                            // Self::load_node added it
                            if self.plain[parent] & (1 << side) == 0 {
                                block::add_jacobian_congruence(
                                    &mut self.mat[self.slot[parent] as usize],
                                    jac,
                                    side,
                                    &body.inv_mass,
                                );
                            }
                        } else if self.held[i] == Held::Factor {
                            let (done, rest) = self.mat.split_at_mut(self.slot[parent] as usize);
                            let c = &done[self.slot[i] as usize];
                            let mut y = block::rows_of_transpose(&jac.matrix(side));
                            block::forward_rows(c, &mut y);
                            block::add_gram(&mut rest[0], &y);
                            let mut z = self.x[i];
                            block::forward(c, &mut z);
                            self.x[parent] += block::transpose_mul(&y, &z);
                        } else {
                            let (done, rest) = self.mat.split_at_mut(self.slot[parent] as usize);
                            let n = &done[self.slot[i] as usize];
                            let jac = jac.matrix(side);
                            block::add_congruence(&mut rest[0], &jac, n);
                            let ny = n * self.x[i];
                            self.x[parent] += jac * ny;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Step 3: back-substitution, parents before children: `x` becomes the solution.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn substitute(&mut self, joints: &SolverJoints, bodies: &[SolverBody]) {
        for i in (0..self.nodes.len()).rev() {
            let node = self.nodes[i];
            let parent = node.parent as usize;
            match node.kind {
                NodeKind::Joint(j) if node.parent != u32::MAX && self.nodes[parent].link => {
                    self.substitute_link(i, j, joints, bodies);
                }
                NodeKind::Joint(j) => {
                    let mut w = self.x[i];
                    if node.parent != u32::MAX {
                        w -= joints[j as usize]
                            .jac
                            .mul(node.side as usize, &self.x[parent]);
                    }
                    block::chol_solve(&self.mat[self.slot[i] as usize], &mut w);
                    self.x[i] = w;
                }
                // solved with its child joint
                NodeKind::Body(_) if node.link => {}
                NodeKind::Body(b) => {
                    let mut w = -self.x[i];
                    if node.parent != u32::MAX {
                        let pj = joint_of(&self.nodes[parent]);
                        w += joints[pj as usize]
                            .jac
                            .tr_mul(node.side as usize, &self.x[parent]);
                    }
                    match self.held[i] {
                        Held::Leaf => {
                            self.x[i] = block::inv_mass_mul(&bodies[b as usize].inv_mass, &w)
                        }
                        Held::Factor => {
                            block::chol_solve(&self.mat[self.slot[i] as usize], &mut w);
                            self.x[i] = w;
                        }
                        Held::Explicit => self.x[i] = self.mat[self.slot[i] as usize] * w,
                    }
                }
            }
        }
    }

    /// Elimination of the link body `nodes[i].parent` and then of its child joint `j`
    /// (node `i`), in the joint-space form (module docs, *Links*).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn eliminate_link(
        &mut self,
        i: usize,
        j: u32,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        let node = self.nodes[i];
        let bi = node.parent as usize;
        let link = self.nodes[bi];
        let minv = &bodies[body_of(&link) as usize].inv_mass;
        let jc = &joints[j as usize].jac;
        let sc = node.side as usize;
        // matrices of the child joint, the link and the parent joint (mi < mb < mp)
        let (mi, mb) = (self.slot[i] as usize, self.slot[bi] as usize);
        if link.parent == u32::MAX {
            // a link at the root: D_c += J_cb·M⁻¹·J_cbᵀ (unless Self::load_node added it) and
            // nothing to pass on; z_c = L⁻¹·y_c for the back-substitution
            if self.plain[i] & (1 << sc) == 0 {
                block::add_jacobian_congruence(&mut self.mat[mi], jc, sc, minv);
            }
            if !block::cholesky_in_place(&mut self.mat[mi]) {
                return Err(SolveFailure::NotPositive(j));
            }
            block::forward(&self.mat[mi], &mut self.x[i]);
            return Ok(());
        }
        let pi = link.parent as usize;
        self.load_node(pi, joints, bodies)?;
        let jp = &joints[joint_of(&self.nodes[pi]) as usize].jac;
        // D_c += J_cb·M⁻¹·J_cbᵀ (then D_c is complete), D_p += J_pb·M⁻¹·J_pbᵀ (each unless
        // Self::load_node added it) and E = J_cb·M⁻¹·J_pbᵀ by rows: independent of the
        // factorisation of D_c
        // i < bi < pi (children first); X is made in the link's slot
        let mp = self.slot[pi] as usize;
        let (lower, upper) = self.mat.split_at_mut(mb);
        let l = &mut lower[mi];
        let (slot, upper) = upper.split_at_mut(1);
        let x = &mut slot[0].data.0;
        let d_p = &mut upper[mp - mb - 1];
        let sp = link.side as usize;
        let d_c = (self.plain[i] & (1 << sc) == 0).then_some(&mut *l);
        let add_p = (self.plain[pi] & (1 << sp) == 0).then_some(&mut *d_p);
        block::add_link_products(d_c, add_p, x, jc, sc, jp, sp, minv);
        if !block::cholesky_in_place(l) {
            return Err(SolveFailure::NotPositive(j));
        }
        // X = L⁻¹·E, D_p −= XᵀX;  z_c = L⁻¹·y_c, y_p −= Xᵀ·z_c
        block::forward_rows(l, x);
        block::sub_lower_gram(d_p, x);
        let mut z = self.x[i];
        block::forward(l, &mut z);
        self.x[pi] -= block::transpose_mul(x, &z);
        self.x[i] = z;
        Ok(())
    }

    /// Back-substitution of the child joint `j` (node `i`) of a link, then of the link:
    /// `P_c = L⁻ᵀ·(z_c − X·P_p)`, `u_b = M_b⁻¹·(J_cbᵀ·P_c + J_pbᵀ·P_p)`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn substitute_link(&mut self, i: usize, j: u32, joints: &SolverJoints, bodies: &[SolverBody]) {
        let node = self.nodes[i];
        let bi = node.parent as usize;
        let link = self.nodes[bi];
        let mut p_c = self.x[i];
        let mut jt_p = Vector6::zeros();
        if link.parent != u32::MAX {
            let pi = link.parent as usize;
            let p_p = &self.x[pi];
            p_c -= block::rows_mul(&self.mat[self.slot[bi] as usize].data.0, p_p);
            let jp = &joints[joint_of(&self.nodes[pi]) as usize].jac;
            jt_p = jp.tr_mul(link.side as usize, p_p);
        }
        block::backward(&self.mat[self.slot[i] as usize], &mut p_c);
        self.x[i] = p_c;
        let w = joints[j as usize].jac.tr_mul(node.side as usize, &p_c) + jt_p;
        self.x[bi] = block::inv_mass_mul(&bodies[body_of(&link) as usize].inv_mass, &w);
    }
}
