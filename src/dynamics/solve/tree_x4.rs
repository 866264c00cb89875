//! Four tree islands of the same shape solved at once, one in each lane of a 4-wide vector
//! of `f64` (an AVX2 register).
//!
//! A small tree's elimination ([`super::tree`]) is a chain of dependent 6×6 operations (for
//! the contact scene's three hinged capsules: two Choleskys through `L⁻¹·E` and `XᵀX`, then
//! the back-substitution): latency-bound, one island's chain of square roots and divisions
//! at a time. Islands whose node lists are the same up to their joint and body indices
//! (the same kinds, parents, sides and links, hence the same [`TreeSolve`] slots and
//! `plain` flags) run the same sequence of operations on different numbers: four of them
//! are solved here as one, every scalar `f64` of [`TreeSolve`] a [`F4`] of the four
//! islands' values. The arithmetic of every lane is the scalar code's **operation for
//! operation, in the same order** (no fused multiply-add, nothing re-associated: the
//! kernels below are [`super::block`]'s written lane-wise, and nalgebra's 3×3 products as
//! nalgebra sums them), so each island's impulses and velocity changes have the bits the
//! scalar solve gives them (test `x4_trees_equal_the_scalar_solve_bit_for_bit`).
//!
//! # What the lanes do
//! Trees whose bodies are leaves (no child joint) or links (one child joint), with a joint
//! at the root: chains of any length from a fixed body or between free ends, pendulums, the
//! contact scene's three-body chains. A tree with a hub (a body with several child joints)
//! stays in the scalar forest ([`supported`]). The trees of one shape are kept in groups
//! (up to `FOREST_NODES` nodes, [`TreeX4`]) whose batches of four are solved one after the
//! other. Per substep, a group in which a joint of any lane has a coupled `G`
//! ([`super::SolverJoint::g_coupled`]) is solved by the scalar [`TreeSolve`] of its trees
//! (kept for that), and so is a group in which any lane fails (a singular `G + ε`, a pivot
//! not positive): the scalar solve then reports the failure exactly as the forest would
//! (the first failing joint in the trees' interleaved order), and the lanes never need to
//! tell which one failed.

// the lane kernels keep the index loops of the scalar kernels they mirror ([`super::block`]),
// so that the order of every operation can be read against them
#![allow(clippy::needless_range_loop)]

use super::block::mat3_mul;
use super::topology::{NodeKind, TreeNode};
use super::tree::TreeSolve;
use super::{SolveFailure, SolverBody, SolverJoints, G_EPSILON, NOT_COUPLED};
use crate::kinematics::RateJacobians;
use crate::lanes::{arr3, arr4, arr6, F4};
use nalgebra::{Matrix3, Vector6};

/// Most nodes a tree of a four-lane batch has (larger trees stay in the scalar forest).
pub(crate) const MAX_NODES: usize = 64;

/// Fewest trees of a shape left over after its batches of four that are solved in a batch
/// of their own (its other lanes repeating one of them) rather than in the scalar forest.
/// In the contact scene's three-body chains (callgrind, per substep): two trees left over
/// cost 11 700 instructions in the scalar forest and 12 900 in a batch, whose lanes run
/// side by side where the forest's chain of square roots and divisions runs one tree after
/// the other; one tree left over costs 5 900 in the forest.
pub(crate) const PAD_FROM: usize = 2;

/// A 6-vector of lanes.
type V4 = [F4; 6];
/// A 6×6 block of lanes, by columns (`m[column][row]`, the layout of `Matrix6::data.0`), or
/// by rows where [`super::block::Rows`] is meant.
type M4 = [[F4; 6]; 6];
/// A 3×3 block of lanes by columns (`m[column][row]`, the layout of `Matrix3::data.0`).
type M3 = [[F4; 3]; 3];

const V4_ZERO: V4 = [F4::ZERO; 6];
const M4_ZERO: M4 = [V4_ZERO; 6];

/// A joint's [`RateJacobians`] in lanes.
#[derive(Debug, Clone, Copy)]
struct JacX4 {
    t: M3,
    r: M3,
    /// `L_s` ([`RateJacobians::lever`]), for the congruences.
    lever: [M3; 2],
    /// `a_s` ([`RateJacobians::arm`]), for the products with vectors.
    arm: [[F4; 3]; 2],
}

/// A body's [`super::MassBlocks`] `inv_mass` in lanes, with its `dv_ext`.
#[derive(Debug, Clone, Copy)]
struct BodyX4 {
    linear: [F4; 3],
    angular: M3,
    dv_ext: V4,
}

/// The lanes of four 3×3 matrices into `dst`, by two 4×4 transpositions (the first eight
/// entries of each lane in column order, four at a time) and the last entry.
#[cfg_attr(not(debug_assertions), inline(always))]
fn gather3(m: [&Matrix3<f64>; 4], dst: &mut M3) {
    let m = arr4(|l| &m[l].data.0);
    for base in [0, 4] {
        let a: [[f64; 4]; 4] = arr4(|l| arr4(|k| m[l][(base + k) / 3][(base + k) % 3]));
        for k in 0..4 {
            let e = base + k;
            dst[e / 3][e % 3] = F4([a[0][k], a[1][k], a[2][k], a[3][k]]);
        }
    }
    dst[2][2] = F4::gather(|l| m[l][2][2]);
}

/// The lanes of four 6-vectors.
#[cfg_attr(not(debug_assertions), inline(always))]
fn gather6(v: [&Vector6<f64>; 4]) -> V4 {
    arr6(|r| F4::gather(|l| v[l].data.0[0][r]))
}

/// `A·x` as nalgebra forms it (`gemv`): the same sums as [`mat3_mul`] (of `block`).
#[cfg_attr(not(debug_assertions), inline(always))]
fn mat3_mul_vec(a: &M3, x: &[F4; 3]) -> [F4; 3] {
    let mut y: [F4; 3] = arr3(|i| a[0][i] * x[0]);
    for k in 1..3 {
        for i in 0..3 {
            y[i] = a[k][i] * x[k] + y[i];
        }
    }
    y
}

/// `Aᵀ·x` as nalgebra's `tr_mul` forms it: row `i` the dot product of column `i` with
/// `x`, `(a_0·x_0 + a_1·x_1) + a_2·x_2`.
#[cfg_attr(not(debug_assertions), inline(always))]
fn mat3_tr_mul_vec(a: &M3, x: &[F4; 3]) -> [F4; 3] {
    arr3(|i| a[i][0] * x[0] + a[i][1] * x[1] + a[i][2] * x[2])
}

/// [`RateJacobians::lever`] in lanes: `L = −T·[a]×`, row `r` the product `a × t_r` (the
/// same bits as the scalar form, lane by lane).
#[cfg_attr(not(debug_assertions), inline(always))]
fn lever(t: &M3, a: &[F4; 3]) -> M3 {
    // t[c][r] = T_rc: row r of T is (t[0][r], t[1][r], t[2][r])
    let rows: [[F4; 3]; 3] = arr3(|r| cross(a, &[t[0][r], t[1][r], t[2][r]]));
    arr3(|c| arr3(|r| rows[r][c]))
}

/// `a × b` as nalgebra's `cross` forms it.
#[cfg_attr(not(debug_assertions), inline(always))]
fn cross(a: &[F4; 3], b: &[F4; 3]) -> [F4; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg_attr(not(debug_assertions), inline(always))]
fn mat3_add(a: &M3, b: &M3) -> M3 {
    arr3(|c| arr3(|r| a[c][r] + b[c][r]))
}

/// `σ_s` in lanes.
#[cfg_attr(not(debug_assertions), inline(always))]
fn sign(s: usize) -> F4 {
    F4::splat(RateJacobians::sign(s))
}

impl JacX4 {
    /// [`RateJacobians::mul`]: `σ_s·(T·(v − a_s × ω), R·ω)`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn mul(&self, s: usize, u: &V4) -> V4 {
        let w = [u[3], u[4], u[5]];
        let aw = cross(&self.arm[s], &w);
        let v = [u[0] - aw[0], u[1] - aw[1], u[2] - aw[2]];
        let tv = mat3_mul_vec(&self.t, &v);
        let ang = mat3_mul_vec(&self.r, &w);
        let sg = sign(s);
        [
            tv[0] * sg,
            tv[1] * sg,
            tv[2] * sg,
            ang[0] * sg,
            ang[1] * sg,
            ang[2] * sg,
        ]
    }

    /// [`RateJacobians::tr_mul`]: `σ_s·(Tᵀ·p_t, a_s × (Tᵀ·p_t) + Rᵀ·p_r)`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn tr_mul(&self, s: usize, p: &V4) -> V4 {
        let pt = [p[0], p[1], p[2]];
        let pr = [p[3], p[4], p[5]];
        let lin = mat3_tr_mul_vec(&self.t, &pt);
        let (lp, rp) = (cross(&self.arm[s], &lin), mat3_tr_mul_vec(&self.r, &pr));
        let sg = sign(s);
        [
            lin[0] * sg,
            lin[1] * sg,
            lin[2] * sg,
            (lp[0] + rp[0]) * sg,
            (lp[1] + rp[1]) * sg,
            (lp[2] + rp[2]) * sg,
        ]
    }
}

/// [`super::block::add_two_sided_congruence`] in lanes.
#[cfg_attr(not(debug_assertions), inline(always))]
fn add_two_sided_congruence(a: &mut M4, jac: &JacX4, m1: &BodyX4, m2: &BodyX4) {
    let ml: [F4; 3] = arr3(|k| m1.linear[k] + m2.linear[k]);
    let a1 = mat3_mul(&jac.lever[0], &m1.angular);
    let a2 = mat3_mul(&jac.lever[1], &m2.angular);
    let b = mat3_mul(&jac.r, &mat3_add(&m1.angular, &m2.angular));
    let (t, r) = (&jac.t, &jac.r);
    let (l1, l2) = (&jac.lever[0], &jac.lever[1]);
    // on and below the diagonal only: the scalar kernel's pairs of rows keep a vector
    // whole where an entry above the diagonal (never read) shares it with one below; in
    // lanes every entry is a vector of its own, so those are skipped (the entries below are
    // the same operations)
    shared_column::<0>(&mut a[0], 0, &ml, t, l1, l2, r, &a1, &a2);
    shared_column::<1>(&mut a[1], 1, &ml, t, l1, l2, r, &a1, &a2);
    shared_column::<2>(&mut a[2], 2, &ml, t, l1, l2, r, &a1, &a2);
    rotation_column::<3>(&mut a[3], 0, r, &b);
    rotation_column::<4>(&mut a[4], 1, r, &b);
    rotation_column::<5>(&mut a[5], 2, r, &b);
}

/// [`super::block`]'s `shared_column` in lanes.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn shared_column<const S: usize>(
    col: &mut V4,
    c: usize,
    ml: &[F4; 3],
    t: &M3,
    l1: &M3,
    l2: &M3,
    r: &M3,
    a1: &M3,
    a2: &M3,
) {
    for k in 0..3 {
        let (wt, w1, w2) = (ml[k] * t[k][c], l1[k][c], l2[k][c]);
        let w = a1[k][c] + a2[k][c];
        for i in S..3 {
            col[i] += wt * t[k][i] + w1 * a1[k][i] + w2 * a2[k][i];
        }
        for i in 0..3 {
            col[3 + i] += w * r[k][i];
        }
    }
}

/// [`super::block`]'s `rotation_column` in lanes.
#[cfg_attr(not(debug_assertions), inline(always))]
fn rotation_column<const S: usize>(col: &mut V4, c: usize, r: &M3, b: &M3) {
    for k in 0..3 {
        let w = r[k][c];
        for i in S - 3..3 {
            col[3 + i] += w * b[k][i];
        }
    }
}

/// [`super::block`]'s `JacobianSide` in lanes.
struct SideX4<'a> {
    t: &'a M3,
    l: &'a M3,
    r: &'a M3,
    u: [V4; 3],
}

/// [`super::block`]'s `add_weighted` in lanes.
#[cfg_attr(not(debug_assertions), inline(always))]
fn add_weighted<const S: usize, const LIN: bool>(
    col: &mut V4,
    a: [F4; 3],
    b: [F4; 3],
    tt: &M3,
    u: &[V4; 3],
) {
    for k in 0..3 {
        if LIN {
            for r in S..3 {
                col[r] += a[k] * tt[k][r];
            }
        }
        for r in S..6 {
            col[r] += b[k] * u[k][r];
        }
    }
}

impl<'a> SideX4<'a> {
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn new(jac: &'a JacX4, s: usize, m: &BodyX4) -> Self {
        let (l, r) = (&jac.lever[s], &jac.r);
        let (li, ri) = (mat3_mul(l, &m.angular), mat3_mul(r, &m.angular));
        SideX4 {
            t: &jac.t,
            l,
            r,
            u: arr3(|k| [li[k][0], li[k][1], li[k][2], ri[k][0], ri[k][1], ri[k][2]]),
        }
    }

    #[cfg_attr(not(debug_assertions), inline(always))]
    fn blocks(jac: &'a JacX4, s: usize) -> Self {
        SideX4 {
            t: &jac.t,
            l: &jac.lever[s],
            r: &jac.r,
            u: [V4_ZERO; 3],
        }
    }

    #[cfg_attr(not(debug_assertions), inline(always))]
    fn weights(&self, c: usize, m: &BodyX4, sign: F4) -> ([F4; 3], [F4; 3]) {
        (
            arr3(|k| sign * (m.linear[k] * self.t[k][c])),
            arr3(|k| sign * self.l[k][c]),
        )
    }

    #[cfg_attr(not(debug_assertions), inline(always))]
    fn rotation_weights(&self, c: usize, sign: F4) -> [F4; 3] {
        arr3(|k| sign * self.r[k][c])
    }

    #[cfg_attr(not(debug_assertions), inline(always))]
    fn add_congruence(&self, a: &mut M4, m: &BodyX4) {
        let (t, u) = (self.t, &self.u);
        let one = F4::splat(1.0);
        // on and below the diagonal only (as add_two_sided_congruence)
        let (a0, b0) = self.weights(0, m, one);
        add_weighted::<0, true>(&mut a[0], a0, b0, t, u);
        let (a1, b1) = self.weights(1, m, one);
        add_weighted::<1, true>(&mut a[1], a1, b1, t, u);
        let (a2, b2) = self.weights(2, m, one);
        add_weighted::<2, true>(&mut a[2], a2, b2, t, u);
        let no = [F4::ZERO; 3];
        add_weighted::<3, false>(&mut a[3], no, self.rotation_weights(0, one), t, u);
        add_weighted::<4, false>(&mut a[4], no, self.rotation_weights(1, one), t, u);
        add_weighted::<5, false>(&mut a[5], no, self.rotation_weights(2, one), t, u);
    }
}

/// [`super::block::add_jacobian_congruence`] in lanes.
#[cfg_attr(not(debug_assertions), inline(always))]
fn add_jacobian_congruence(a: &mut M4, jac: &JacX4, s: usize, m: &BodyX4) {
    SideX4::new(jac, s, m).add_congruence(a, m);
}

/// [`super::block::add_link_products`] in lanes.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn add_link_products(
    d_c: Option<&mut M4>,
    d_p: Option<&mut M4>,
    e: &mut M4,
    jc: &JacX4,
    sc: usize,
    jp: &JacX4,
    sp: usize,
    m: &BodyX4,
) {
    let p = SideX4::new(jp, sp, m);
    if let Some(d_p) = d_p {
        p.add_congruence(d_p, m);
    }
    let c = SideX4::blocks(jc, sc);
    if let Some(d_c) = d_c {
        SideX4::new(jc, sc, m).add_congruence(d_c, m);
    }
    let sign = F4::splat(RateJacobians::sign(sc) * RateJacobians::sign(sp));
    let (t, u) = (p.t, &p.u);
    *e = M4_ZERO;
    let no = [F4::ZERO; 3];
    for r in 0..3 {
        let (a, b) = c.weights(r, m, sign);
        add_weighted::<0, true>(&mut e[r], a, b, t, u);
        add_weighted::<0, false>(&mut e[3 + r], no, c.rotation_weights(r, sign), t, u);
    }
}

/// [`super::block::cholesky_in_place`] in lanes: `false` when a pivot of any lane is not
/// positive, normal and finite. Written column by column with the column a constant
/// ([`cholesky_column`]), so that every loop has constant bounds and the compiler unrolls
/// the whole factorisation as it does the scalar one (the lanes' arithmetic looked four
/// times larger to the unroller, which left the loops with their masks).
#[cfg_attr(not(debug_assertions), inline(always))]
fn cholesky_in_place(l: &mut M4) -> bool {
    let mut ok = true;
    // s_j,j−1 (the entry below the previous pivot before its scaling) and 1/d_j−1
    let (mut s_prev, mut r_prev) = (F4::ZERO, F4::ZERO);
    cholesky_column::<0>(l, &mut ok, &mut s_prev, &mut r_prev);
    cholesky_column::<1>(l, &mut ok, &mut s_prev, &mut r_prev);
    cholesky_column::<2>(l, &mut ok, &mut s_prev, &mut r_prev);
    cholesky_column::<3>(l, &mut ok, &mut s_prev, &mut r_prev);
    cholesky_column::<4>(l, &mut ok, &mut s_prev, &mut r_prev);
    cholesky_column::<5>(l, &mut ok, &mut s_prev, &mut r_prev);
    ok
}

/// Column `J` of [`cholesky_in_place`]: the scalar loop's body for `j = J`, the same
/// operations in the same order (`s_prev` is the only entry of the scalar `s_prev` that
/// the next column reads, `s_J+1,J`).
#[cfg_attr(not(debug_assertions), inline(always))]
fn cholesky_column<const J: usize>(l: &mut M4, ok: &mut bool, s_prev: &mut F4, r_prev: &mut F4) {
    // d = a_jj − Σ_k<j−1 l_jk² − s_j,j−1²·(1/d_j−1)
    let mut d = l[J][J];
    for k in 0..J.saturating_sub(1) {
        d -= l[k][J] * l[k][J];
    }
    if J > 0 {
        let sq = *s_prev * *s_prev;
        d -= sq * *r_prev;
    }
    for v in d.0 {
        *ok &= (f64::MIN_POSITIVE..=f64::MAX).contains(&v);
    }
    let r = F4::splat(1.0) / d;
    let inv = d.sqrt() * r;
    l[J][J] = inv;
    for i in J + 1..6 {
        // l_ij = (a_ij − Σ_k<j l_ik·l_jk) / l_jj
        let mut s = l[J][i];
        for k in 0..J {
            s -= l[k][i] * l[k][J];
        }
        if i == J + 1 {
            *s_prev = s;
        }
        l[J][i] = s * inv;
    }
    *r_prev = r;
}

/// [`super::block::forward`] in lanes, unrolled ([`forward_step`]), so that the six lanes
/// of `x` stay in registers: as a loop (not unrolled) each step stored `x[k]` and loaded
/// `x[k + 1]` from the stack, where a load that shares a store's address modulo 4096 waits
/// for it (4K aliasing), which made the solve stage's time depend on the stack's position
/// (the contact scene's frame by ±3 % with the environment's size).
#[cfg_attr(not(debug_assertions), inline(always))]
fn forward(l: &M4, x: &mut V4) {
    forward_step::<0>(l, x);
    forward_step::<1>(l, x);
    forward_step::<2>(l, x);
    forward_step::<3>(l, x);
    forward_step::<4>(l, x);
    forward_step::<5>(l, x);
}

/// Step `K` of [`forward`]: the scalar loop's body for `k = K`, the same operations in the
/// same order.
#[cfg_attr(not(debug_assertions), inline(always))]
fn forward_step<const K: usize>(l: &M4, x: &mut V4) {
    let xk = x[K] * l[K][K];
    x[K] = xk;
    for i in K + 1..6 {
        x[i] -= l[K][i] * xk;
    }
}

/// [`super::block::backward`] in lanes, unrolled as [`forward`] ([`backward_step`]).
#[cfg_attr(not(debug_assertions), inline(always))]
fn backward(l: &M4, x: &mut V4) {
    backward_step::<5>(l, x);
    backward_step::<4>(l, x);
    backward_step::<3>(l, x);
    backward_step::<2>(l, x);
    backward_step::<1>(l, x);
    backward_step::<0>(l, x);
}

/// Step `I` of [`backward`]: the scalar loop's body for `i = I`, the same operations in the
/// same order.
#[cfg_attr(not(debug_assertions), inline(always))]
fn backward_step<const I: usize>(l: &M4, x: &mut V4) {
    let mut s = x[I];
    for k in I + 1..6 {
        s -= l[I][k] * x[k];
    }
    x[I] = s * l[I][I];
}

/// [`super::block::chol_solve`] in lanes.
#[cfg_attr(not(debug_assertions), inline(always))]
fn chol_solve(l: &M4, x: &mut V4) {
    forward(l, x);
    backward(l, x);
}

/// [`super::block::forward_rows`] in lanes (`x` by rows), row by row with the row a
/// constant ([`forward_rows_step`]: unrolled, as [`cholesky_in_place`]).
#[cfg_attr(not(debug_assertions), inline(always))]
fn forward_rows(l: &M4, x: &mut M4) {
    forward_rows_step::<0>(l, x);
    forward_rows_step::<1>(l, x);
    forward_rows_step::<2>(l, x);
    forward_rows_step::<3>(l, x);
    forward_rows_step::<4>(l, x);
    forward_rows_step::<5>(l, x);
}

/// Row `K` of [`forward_rows`]: once it is final, its multiples are removed from the rows
/// below.
#[cfg_attr(not(debug_assertions), inline(always))]
fn forward_rows_step<const K: usize>(l: &M4, x: &mut M4) {
    let d = l[K][K];
    let xk = arr6(|c| x[K][c] * d);
    x[K] = xk;
    for i in K + 1..6 {
        let f = l[K][i];
        for c in 0..6 {
            x[i][c] -= f * xk[c];
        }
    }
}

/// [`super::block::sub_lower_gram`] in lanes: `add_columns::<2, 4, true, false>` with the
/// rows of `X` as both `C` and `B`.
#[cfg_attr(not(debug_assertions), inline(always))]
fn sub_lower_gram(a: &mut M4, x: &M4) {
    // on and below the diagonal only (as add_two_sided_congruence)
    sub_column::<0>(&mut a[0], x, 0);
    sub_column::<1>(&mut a[1], x, 1);
    sub_column::<2>(&mut a[2], x, 2);
    sub_column::<3>(&mut a[3], x, 3);
    sub_column::<4>(&mut a[4], x, 4);
    sub_column::<5>(&mut a[5], x, 5);
}

/// [`super::block`]'s `add_column_t::<S, true, false>` in lanes, `C = B = X`.
#[cfg_attr(not(debug_assertions), inline(always))]
fn sub_column<const S: usize>(col: &mut V4, x: &M4, j: usize) {
    for q in 0..6 {
        let f = -x[q][j];
        for r in S..6 {
            col[r] += f * x[q][r];
        }
    }
}

/// [`super::block::transpose_mul`] in lanes.
#[cfg_attr(not(debug_assertions), inline(always))]
fn transpose_mul(x: &M4, z: &V4) -> V4 {
    let mut out = V4_ZERO;
    for (xi, zi) in x.iter().zip(z.iter()) {
        for c in 0..6 {
            out[c] += *zi * xi[c];
        }
    }
    out
}

/// [`super::block::rows_mul`] in lanes.
#[cfg_attr(not(debug_assertions), inline(always))]
fn rows_mul(x: &M4, v: &V4) -> V4 {
    arr6(|i| {
        let xi = &x[i];
        let mut s = F4::ZERO;
        for c in 0..6 {
            s += xi[c] * v[c];
        }
        s
    })
}

/// [`super::block::inv_mass_mul`] in lanes.
#[cfg_attr(not(debug_assertions), inline(always))]
fn inv_mass_mul(m: &BodyX4, v: &V4) -> V4 {
    let id = &m.angular;
    let mut out = V4_ZERO;
    for k in 0..3 {
        out[k] = m.linear[k] * v[k];
    }
    for l in 0..3 {
        for r in 0..3 {
            out[3 + r] += id[l][r] * v[3 + l];
        }
    }
    out
}

#[cfg_attr(not(debug_assertions), inline(always))]
fn sub_assign(a: &mut V4, b: &V4) {
    for (a, b) in a.iter_mut().zip(b) {
        *a -= *b;
    }
}

/// Whether a tree island's nodes (children before parents, the root last) have a shape
/// the lanes solve: a joint at the root, every body a leaf or a link, at most
/// [`MAX_NODES`] nodes.
pub(crate) fn supported(nodes: &[TreeNode]) -> bool {
    let n = nodes.len();
    if n == 0 || n > MAX_NODES {
        return false;
    }
    let mut children = vec![0u32; n];
    for (i, node) in nodes.iter().enumerate() {
        if node.parent == u32::MAX {
            if i != n - 1 {
                return false;
            }
        } else if node.parent as usize <= i || node.parent as usize >= n {
            return false;
        } else {
            children[node.parent as usize] += 1;
        }
    }
    nodes
        .iter()
        .zip(&children)
        .all(|(node, &c)| match node.kind {
            NodeKind::Joint(_) => !node.link,
            NodeKind::Body(_) => node.parent != u32::MAX && c <= 1 && node.link == (c == 1),
        })
}

/// The shape of a tree island: its node list without the joint and body indices. Islands
/// with the same shape are solved in the same lanes.
pub(crate) fn shape(nodes: &[TreeNode]) -> Vec<(bool, u32, u8, bool)> {
    nodes
        .iter()
        .map(|n| {
            (
                matches!(n.kind, NodeKind::Joint(_)),
                n.parent,
                n.side,
                n.link,
            )
        })
        .collect()
}

/// Tree islands of one shape ([`shape`], [`supported`]), four at a time (a batch), and
/// their workspace: the batches are solved one after the other in one batch's workspace
/// (the lanes' Jacobians, inverse masses, blocks and right-hand sides, a few kilobytes that
/// stay in the cache), and only the solutions are kept per batch. Ten thousand pendulums
/// in a workspace of their own per batch (3.3 kB for four, the gathered Jacobians
/// included) ran 20 % slower than the scalar forest, from memory.
#[derive(Debug, Clone)]
pub(crate) struct TreeX4 {
    /// The shared shape (the first tree's nodes: kinds, parents, sides, links).
    nodes: Vec<TreeNode>,
    /// Number of batches of four trees.
    batches: usize,
    /// Per batch, per node (`b·n + i`): each lane's joint or body index.
    index: Vec<[u32; 4]>,
    /// Per batch, per node: the lanes' solutions.
    out: Vec<V4>,
    /// Per node: its index in `mat`, as [`TreeSolve`]'s slots (`u32::MAX`: a leaf).
    slot: Vec<u32>,
    /// Per joint node: the sides whose congruences the load adds ([`TreeSolve`]'s `plain`).
    plain: Vec<u8>,
    /// Per joint node: the node of the body on each side (`u32::MAX`: none, a fixed side).
    side_node: Vec<[u32; 2]>,
    /// Per node: its index in `jac` (joints) or `body` (bodies).
    data: Vec<u32>,
    jac: Vec<JacX4>,
    body: Vec<BodyX4>,
    mat: Vec<M4>,
    x: Vec<V4>,
    /// The trees in the scalar forest's form, for the substeps the lanes do not do.
    fallback: TreeSolve,
    /// Whether the last solve was the fallback's.
    fell_back: bool,
}

impl TreeX4 {
    /// `trees`: node lists of one supported shape (lanes in this order); `fallback`: their
    /// scalar forest. When their number is not a multiple of four, the last batch's empty
    /// lanes repeat its last tree: they compute that tree's solution again, bit for bit,
    /// and write it where it writes it ([`Self::for_each_solution`]). Two or three trees
    /// left over run faster in lanes than in the scalar forest, for a few more
    /// instructions ([`PAD_FROM`]).
    pub(crate) fn new(trees: &[&[TreeNode]], fallback: TreeSolve) -> Self {
        let nodes = trees[0].to_vec();
        debug_assert!(supported(&nodes));
        debug_assert!(trees.iter().all(|t| shape(t) == shape(&nodes)));
        let n = nodes.len();
        let batches = trees.len().div_ceil(4);
        let index = (0..batches * n)
            .map(|k| {
                let (b, i) = (k / n, k % n);
                std::array::from_fn(|l| {
                    let t = (4 * b + l).min(trees.len() - 1);
                    match trees[t][i].kind {
                        NodeKind::Joint(j) | NodeKind::Body(j) => j,
                    }
                })
            })
            .collect();
        // the scalar solve's slots and plain sides (the lanes mirror its kernels)
        let (slot, count, plain) = super::tree::layout(&nodes);
        // per joint node: the node of the body on each side that is in the tree
        let mut side_node = vec![[u32::MAX; 2]; n];
        for (i, node) in nodes.iter().enumerate() {
            if node.parent == u32::MAX {
                continue;
            }
            let parent = node.parent as usize;
            match node.kind {
                NodeKind::Joint(_) => side_node[i][node.side as usize] = parent as u32,
                NodeKind::Body(_) => side_node[parent][node.side as usize] = i as u32,
            }
        }
        let (mut joints, mut bodies) = (0u32, 0u32);
        let data = nodes
            .iter()
            .map(|node| match node.kind {
                NodeKind::Joint(_) => {
                    joints += 1;
                    joints - 1
                }
                NodeKind::Body(_) => {
                    bodies += 1;
                    bodies - 1
                }
            })
            .collect();
        let zero_jac = JacX4 {
            t: [[F4::ZERO; 3]; 3],
            r: [[F4::ZERO; 3]; 3],
            lever: [[[F4::ZERO; 3]; 3]; 2],
            arm: [[F4::ZERO; 3]; 2],
        };
        let zero_body = BodyX4 {
            linear: [F4::ZERO; 3],
            angular: [[F4::ZERO; 3]; 3],
            dv_ext: V4_ZERO,
        };
        TreeX4 {
            nodes,
            batches,
            index,
            out: vec![V4_ZERO; batches * n],
            slot,
            plain,
            side_node,
            data,
            jac: vec![zero_jac; joints as usize],
            body: vec![zero_body; bodies as usize],
            mat: vec![M4_ZERO; count as usize],
            x: vec![V4_ZERO; n],
            fallback,
            fell_back: false,
        }
    }

    /// Solves the trees: in the lanes, or all of them by the scalar forest when a joint's
    /// `G` is coupled or a lane fails (then its failure is the forest's).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn solve(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<(), SolveFailure> {
        // `joints.coupled` holds every coupled `G` of the set: empty (the common case), no
        // lane can have one and the pass over the lanes' joints is skipped.
        let coupled = !joints.coupled.is_empty()
            && self
                .nodes
                .iter()
                .cycle()
                .zip(&self.index)
                .any(|(node, idx)| {
                    matches!(node.kind, NodeKind::Joint(_))
                        && idx
                            .iter()
                            .any(|&j| joints[j as usize].g_coupled != NOT_COUPLED)
                });
        self.fell_back = coupled || !self.solve_lanes(joints, bodies);
        if self.fell_back {
            return self.fallback.solve(joints, bodies);
        }
        Ok(())
    }

    /// Solves again the batches `batches` (ascending) after [`Self::solve`], whose other
    /// batches' inputs have not changed: the same
    /// bits as solving every batch again, each batch being solved on its own. Where the
    /// last solve fell back to the scalar forest, or a batch fails in the lanes, everything
    /// is solved again as [`Self::solve`] solves it.
    pub(crate) fn solve_batches(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
        batches: impl Iterator<Item = usize>,
    ) -> Result<(), SolveFailure> {
        if self.fell_back {
            return self.solve(joints, bodies);
        }
        for b in batches {
            if !self.solve_batch(b, joints, bodies) {
                return self.solve(joints, bodies);
            }
        }
        Ok(())
    }

    /// Every node's solution (lane by lane): `(joint or body, x)`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn for_each_solution(&self, mut f: impl FnMut(NodeKind, &Vector6<f64>)) {
        if self.fell_back {
            for (node, x) in self.fallback.nodes.iter().zip(&self.fallback.x) {
                f(node.kind, x);
            }
            return;
        }
        for b in 0..self.batches {
            self.for_each_solution_of(b, &mut f);
        }
    }

    /// The solutions of batch `b` ([`Self::for_each_solution`]; not for a solve that fell
    /// back).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn for_each_solution_of(
        &self,
        b: usize,
        mut f: impl FnMut(NodeKind, &Vector6<f64>),
    ) {
        let n = self.nodes.len();
        let batch = b * n..(b + 1) * n;
        let nodes = self.nodes.iter().zip(&self.index[batch.clone()]);
        for ((node, idx), x) in nodes.zip(&self.out[batch]) {
            for (l, &k) in idx.iter().enumerate() {
                let v = Vector6::from(arr6(|r| x[r].0[l]));
                match node.kind {
                    NodeKind::Joint(_) => f(NodeKind::Joint(k), &v),
                    NodeKind::Body(_) => f(NodeKind::Body(k), &v),
                }
            }
        }
    }

    /// Whether the last solve fell back to the scalar forest (then
    /// [`Self::for_each_solution`] reads the forest's solutions).
    pub(crate) fn fell_back(&self) -> bool {
        self.fell_back
    }

    /// Calls `f(body, batch)` for each body of the trees (its lanes' batch).
    pub(crate) fn for_each_body(&self, mut f: impl FnMut(u32, usize)) {
        let n = self.nodes.len();
        for (k, idx) in self.index.iter().enumerate() {
            if let NodeKind::Body(_) = self.nodes[k % n].kind {
                for &b in idx {
                    f(b, k / n);
                }
            }
        }
    }

    /// The lanes' solve ([`TreeSolve::solve`] for the supported shapes); `false` when a
    /// lane fails.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn solve_lanes(&mut self, joints: &SolverJoints, bodies: &[SolverBody]) -> bool {
        for b in 0..self.batches {
            if !self.solve_batch(b, joints, bodies) {
                return false;
            }
        }
        true
    }

    /// Batch `b` of the lanes' solve, its solutions kept; `false` when a lane fails.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn solve_batch(&mut self, b: usize, joints: &SolverJoints, bodies: &[SolverBody]) -> bool {
        let n = self.nodes.len();
        let batch = b * n..(b + 1) * n;
        self.gather(batch.clone(), joints, bodies);
        let mut ok = self.load(batch.clone(), joints);
        ok &= self.eliminate();
        if !ok {
            return false;
        }
        self.substitute();
        self.out[batch].copy_from_slice(&self.x);
        true
    }

    /// The lanes of every joint's Jacobians and every body's inverse mass and `dv_ext`,
    /// written in place entry by entry (a block built on the stack and copied was written
    /// as scalars and read back as vectors: a stalled store forwarding for every entry).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn gather(
        &mut self,
        batch: std::ops::Range<usize>,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) {
        let index = &self.index[batch];
        for (i, ((node, idx), &d)) in self.nodes.iter().zip(index).zip(&self.data).enumerate() {
            match node.kind {
                NodeKind::Joint(_) => {
                    let sj = arr4(|l| &joints[idx[l] as usize].jac);
                    let dst = &mut self.jac[d as usize];
                    gather3(arr4(|l| &sj[l].t), &mut dst.t);
                    gather3(arr4(|l| &sj[l].r), &mut dst.r);
                    // a lever of a side without a body (a fixed side) is never read
                    for s in 0..2 {
                        if self.side_node[i][s] != u32::MAX {
                            dst.arm[s] = arr3(|k| F4::gather(|l| sj[l].arm[s][k]));
                            dst.lever[s] = lever(&dst.t, &dst.arm[s]);
                        }
                    }
                }
                NodeKind::Body(_) => {
                    let b = arr4(|l| &bodies[idx[l] as usize]);
                    let dst = &mut self.body[d as usize];
                    for k in 0..3 {
                        dst.linear[k] = F4::gather(|l| b[l].inv_mass.linear.data.0[0][k]);
                    }
                    gather3(arr4(|l| &b[l].inv_mass.angular), &mut dst.angular);
                    for k in 0..6 {
                        dst.dv_ext[k] = F4::gather(|l| b[l].dv_ext.data.0[0][k]);
                    }
                }
            }
        }
    }

    /// [`TreeSolve::load_node`] of every node, in lanes and in a pass of its own: every
    /// joint's `G⁻¹` ([`super::joint_block`] of a diagonal `G`) and right-hand side, and the
    /// congruences of its plain sides; `false` when a `G + ε` of a lane is singular.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn load(&mut self, batch: std::ops::Range<usize>, joints: &SolverJoints) -> bool {
        let mut ok = true;
        let index = &self.index[batch];
        for i in 0..self.nodes.len() {
            match self.nodes[i].kind {
                NodeKind::Joint(_) => {
                    let idx = index[i];
                    let sj = arr4(|l| &joints[idx[l] as usize]);
                    let jac = &self.jac[self.data[i] as usize];
                    let d = &mut self.mat[self.slot[i] as usize];
                    *d = M4_ZERO;
                    // regularised_diagonal_inverse, then r = h·Q ∘ diag(G⁻¹)
                    let g = gather6(arr4(|l| &sj[l].g_diagonal));
                    let explicit = gather6(arr4(|l| &sj[l].explicit));
                    let mut r = V4_ZERO;
                    for k in 0..6 {
                        let dk = g[k] + F4::splat(G_EPSILON);
                        for v in dk.0 {
                            ok &= v != 0.0 && v.abs() <= f64::MAX;
                        }
                        d[k][k] = F4::splat(1.0) / dk;
                    }
                    for k in 0..6 {
                        r[k] = explicit[k] * d[k][k];
                    }
                    let sides = self.side_node[i];
                    for (s, &b) in sides.iter().enumerate() {
                        if b != u32::MAX {
                            let dv = &self.body[self.data[b as usize] as usize].dv_ext;
                            sub_assign(&mut r, &jac.mul(s, dv));
                        }
                    }
                    self.x[i] = r;
                    let m = |s: usize| &self.body[self.data[sides[s] as usize] as usize];
                    match self.plain[i] {
                        3 => add_two_sided_congruence(d, jac, m(0), m(1)),
                        1 => add_jacobian_congruence(d, jac, 0, m(0)),
                        2 => add_jacobian_congruence(d, jac, 1, m(1)),
                        _ => {}
                    }
                }
                NodeKind::Body(_) if !self.nodes[i].link => self.x[i] = V4_ZERO,
                NodeKind::Body(_) => {}
            }
        }
        ok
    }

    /// [`TreeSolve::eliminate`] in lanes (joints at the root or under a link, leaf and link
    /// bodies); `false` when a pivot of a lane is not positive.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn eliminate(&mut self) -> bool {
        let mut ok = true;
        for i in 0..self.nodes.len() {
            let node = self.nodes[i];
            match node.kind {
                NodeKind::Joint(_) if node.parent != u32::MAX => ok &= self.eliminate_link(i),
                NodeKind::Joint(_) => {
                    ok &= cholesky_in_place(&mut self.mat[self.slot[i] as usize]);
                }
                NodeKind::Body(_) if node.link => {}
                NodeKind::Body(_) => {
                    // a leaf: N = M⁻¹; J·M⁻¹·Jᵀ unless the load added it
                    let parent = node.parent as usize;
                    let side = node.side as usize;
                    if self.plain[parent] & (1 << side) == 0 {
                        let m = &self.body[self.data[i] as usize];
                        let jac = &self.jac[self.data[parent] as usize];
                        add_jacobian_congruence(
                            &mut self.mat[self.slot[parent] as usize],
                            jac,
                            side,
                            m,
                        );
                    }
                }
            }
        }
        ok
    }

    /// [`TreeSolve`]'s `eliminate_link` in lanes (the link has a parent joint).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn eliminate_link(&mut self, i: usize) -> bool {
        let node = self.nodes[i];
        let bi = node.parent as usize;
        let link = self.nodes[bi];
        let pi = link.parent as usize;
        let minv = &self.body[self.data[bi] as usize];
        let jc = &self.jac[self.data[i] as usize];
        let jp = &self.jac[self.data[pi] as usize];
        let sc = node.side as usize;
        let sp = link.side as usize;
        let (mi, mb, mp) = (
            self.slot[i] as usize,
            self.slot[bi] as usize,
            self.slot[pi] as usize,
        );
        let (lower, upper) = self.mat.split_at_mut(mb);
        let l = &mut lower[mi];
        let (slot, upper) = upper.split_at_mut(1);
        let x = &mut slot[0];
        let d_p = &mut upper[mp - mb - 1];
        let d_c = (self.plain[i] & (1 << sc) == 0).then_some(&mut *l);
        let add_p = (self.plain[pi] & (1 << sp) == 0).then_some(&mut *d_p);
        add_link_products(d_c, add_p, x, jc, sc, jp, sp, minv);
        let ok = cholesky_in_place(l);
        forward_rows(l, x);
        sub_lower_gram(d_p, x);
        let mut z = self.x[i];
        forward(l, &mut z);
        let xz = transpose_mul(x, &z);
        sub_assign(&mut self.x[pi], &xz);
        self.x[i] = z;
        ok
    }

    /// [`TreeSolve::substitute`] in lanes.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn substitute(&mut self) {
        for i in (0..self.nodes.len()).rev() {
            let node = self.nodes[i];
            let parent = node.parent as usize;
            match node.kind {
                NodeKind::Joint(_) if node.parent != u32::MAX => self.substitute_link(i),
                NodeKind::Joint(_) => {
                    let mut w = self.x[i];
                    chol_solve(&self.mat[self.slot[i] as usize], &mut w);
                    self.x[i] = w;
                }
                NodeKind::Body(_) if node.link => {}
                NodeKind::Body(_) => {
                    let xi = &self.x[i];
                    let mut w = arr6(|c| -xi[c]);
                    let jac = &self.jac[self.data[parent] as usize];
                    let jt = jac.tr_mul(node.side as usize, &self.x[parent]);
                    for (w, t) in w.iter_mut().zip(&jt) {
                        *w += *t;
                    }
                    self.x[i] = inv_mass_mul(&self.body[self.data[i] as usize], &w);
                }
            }
        }
    }

    /// [`TreeSolve`]'s `substitute_link` in lanes (the link has a parent joint).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn substitute_link(&mut self, i: usize) {
        let node = self.nodes[i];
        let bi = node.parent as usize;
        let link = self.nodes[bi];
        let pi = link.parent as usize;
        let mut p_c = self.x[i];
        let p_p = &self.x[pi];
        sub_assign(&mut p_c, &rows_mul(&self.mat[self.slot[bi] as usize], p_p));
        let jp = &self.jac[self.data[pi] as usize];
        let jt_p = jp.tr_mul(link.side as usize, p_p);
        backward(&self.mat[self.slot[i] as usize], &mut p_c);
        self.x[i] = p_c;
        let jc = &self.jac[self.data[i] as usize];
        let mut w = jc.tr_mul(node.side as usize, &p_c);
        for (w, t) in w.iter_mut().zip(&jt_p) {
            *w += *t;
        }
        self.x[bi] = inv_mass_mul(&self.body[self.data[bi] as usize], &w);
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{random_jacobians, random_mass, uniform};
    use super::super::topology::{self, Plan};
    use super::super::{
        IslandSolve, MassBlocks, SolveFailure, Solver, SolverBody, SolverJoint, SolverJoints,
        TreeSolve, NOT_COUPLED,
    };
    use nalgebra::{Matrix6, Vector6};

    /// `copies` copies of one tree: the sides of its joints (`template[j]`, bodies counted
    /// from 0 in each copy), and the number of bodies of a copy.
    fn forest(template: &[[Option<u32>; 2]], copies: usize) -> (Vec<[Option<u32>; 2]>, usize) {
        let per = template
            .iter()
            .flatten()
            .flatten()
            .map(|b| b + 1)
            .max()
            .unwrap_or(0) as usize;
        let sides = (0..copies)
            .flat_map(|c| {
                template
                    .iter()
                    .map(move |s| s.map(|b| b.map(|b| b + (c * per) as u32)))
            })
            .collect();
        (sides, per * copies)
    }

    /// Random well-conditioned joints and bodies for `sides`: Jacobians in [−1, 1), `G`
    /// over six decades, inverse masses over six decades (some with a locked translation).
    fn random_system(
        sides: &[[Option<u32>; 2]],
        n_bodies: usize,
        seed: u64,
    ) -> (SolverJoints, Vec<SolverBody>) {
        let mut rand = uniform(seed);
        let list = sides
            .iter()
            .map(|s| SolverJoint {
                bodies: *s,
                jac: random_jacobians(&mut rand),
                g_diagonal: Vector6::from_fn(|_, _| 10f64.powf(3.0 * rand() - 3.0)),
                g_coupled: NOT_COUPLED,
                explicit: Vector6::from_fn(|_, _| rand()),
            })
            .collect::<Vec<_>>();
        let bodies = (0..n_bodies)
            .map(|n| SolverBody {
                inv_mass: random_mass(&mut rand, n),
                dv_ext: Vector6::from_fn(|_, _| rand()),
                mass: None::<MassBlocks>,
            })
            .collect();
        (SolverJoints::from(list), bodies)
    }

    /// The impulses of the joints and the velocity changes of the bodies.
    type Solution = (Vec<Vector6<f64>>, Vec<Vector6<f64>>);

    /// Every tree island solved alone by the scalar [`TreeSolve`]: the impulses and velocity
    /// changes, or the island's failure (the first in island order).
    fn scalar_solve(
        sides: &[[Option<u32>; 2]],
        n_bodies: usize,
        joints: &SolverJoints,
        bodies: &[SolverBody],
    ) -> Result<Solution, SolveFailure> {
        let mut p = vec![Vector6::zeros(); joints.len()];
        let mut u = vec![Vector6::zeros(); n_bodies];
        for island in topology::analyse(n_bodies, sides, &vec![true; sides.len()]) {
            let Plan::Tree(nodes) = island.plan else {
                panic!("trees only")
            };
            let mut t = TreeSolve::new(nodes);
            t.solve(joints, bodies)?;
            for (node, x) in t.nodes.iter().zip(&t.x) {
                match node.kind {
                    super::NodeKind::Joint(j) => p[j as usize] = *x,
                    super::NodeKind::Body(b) => u[b as usize] = *x,
                }
            }
        }
        Ok((p, u))
    }

    /// Number of batches of four trees in the lanes.
    fn batches(solver: &Solver) -> usize {
        solver
            .islands
            .iter()
            .map(|i| match i {
                IslandSolve::TreeX4(t) => t.batches,
                _ => 0,
            })
            .sum()
    }

    fn bits(v: &[Vector6<f64>]) -> Vec<u64> {
        v.iter()
            .flat_map(|x| x.iter().map(|e| e.to_bits()))
            .collect()
    }

    /// The shapes the lanes solve: the contact scene's three bodies (leaf–joint–link–joint–
    /// leaf), a pendulum, a chain of three bodies from a fixed one (its interior joint
    /// between two links), the same with every joint's sides swapped, and a joint without a
    /// dynamic body.
    fn shapes() -> Vec<Vec<[Option<u32>; 2]>> {
        vec![
            vec![[Some(0), Some(1)], [Some(1), Some(2)]],
            vec![[None, Some(0)]],
            vec![[None, Some(0)], [Some(0), Some(1)], [Some(1), Some(2)]],
            vec![[Some(1), None], [Some(0), Some(1)], [Some(2), Some(0)]],
            vec![[None, None]],
        ]
    }

    /// Forests of identical trees of every supported shape with random blocks: the lanes'
    /// impulses and velocity changes equal the scalar solve's bit for bit, with one tree
    /// left over after the batches of four (it stays in the scalar forest) and with two or
    /// three (a batch of their own whose other lanes repeat one of them, [`PAD_FROM`]).
    #[test]
    fn x4_trees_equal_the_scalar_solve_bit_for_bit() {
        for (k, template) in shapes().iter().enumerate() {
            for (copies, expected_batches) in [(4, 1), (9, 2), (13, 3), (2, 1), (7, 2), (10, 3)] {
                let (sides, n_bodies) = forest(template, copies);
                let (joints, bodies) = random_system(&sides, n_bodies, 100 * k as u64 + 7);
                let (p, u) = scalar_solve(&sides, n_bodies, &joints, &bodies).unwrap();
                let mut solver = Solver::new(n_bodies, &sides, &vec![true; sides.len()]);
                assert_eq!(
                    batches(&solver),
                    expected_batches,
                    "shape {k}, {copies} copies"
                );
                let mut pp = vec![Vector6::repeat(f64::NAN); joints.len()];
                let mut uu = vec![Vector6::repeat(f64::NAN); n_bodies];
                solver.solve(&joints, &bodies, &mut pp, &mut uu).unwrap();
                assert_eq!(bits(&pp), bits(&p), "shape {k}, {copies} copies: impulses");
                assert_eq!(
                    bits(&uu),
                    bits(&u),
                    "shape {k}, {copies} copies: velocities"
                );
            }
        }
    }

    /// A joint with a coupled `G` in one lane: the batch is solved by its scalar forest,
    /// the same bits; and the next substep without it in the lanes again.
    #[test]
    fn a_coupled_joint_falls_back_to_the_scalar_forest() {
        let (sides, n_bodies) = forest(&shapes()[0], 8);
        let (mut joints, bodies) = random_system(&sides, n_bodies, 31);
        let mut g = Matrix6::from_diagonal(&joints[5].g_diagonal);
        g[(1, 0)] = 0.1 * g[(1, 1)].min(g[(0, 0)]);
        g[(0, 1)] = g[(1, 0)];
        joints.set_g(5, &g);
        let mut solver = Solver::new(n_bodies, &sides, &vec![true; sides.len()]);
        assert_eq!(batches(&solver), 2);
        for coupled in [true, false] {
            if !coupled {
                let d = joints[5].g_diagonal;
                joints.set_g_diagonal(5, &d);
            }
            let (p, u) = scalar_solve(&sides, n_bodies, &joints, &bodies).unwrap();
            let mut pp = vec![Vector6::zeros(); joints.len()];
            let mut uu = vec![Vector6::zeros(); n_bodies];
            solver.solve(&joints, &bodies, &mut pp, &mut uu).unwrap();
            let fell_back = solver.islands.iter().any(|i| match i {
                IslandSolve::TreeX4(t) => t.fell_back,
                _ => false,
            });
            assert_eq!(fell_back, coupled);
            assert_eq!(bits(&pp), bits(&p));
            assert_eq!(bits(&uu), bits(&u));
        }
    }

    /// A pivot that is not positive in one lane (a negative `G` larger than the bodies
    /// carry): the failure is the scalar solve's, at that joint.
    #[test]
    fn a_failing_lane_reports_the_scalar_failure() {
        // eight trees, two batches: a failure in the first batch and in the second
        let (sides, n_bodies) = forest(&shapes()[0], 8);
        let (mut joints, bodies) = random_system(&sides, n_bodies, 5);
        for (j, g) in [(6usize, -1e-6), (13, 0.0 - super::G_EPSILON)] {
            let mut d = joints[j].g_diagonal;
            d[2] = g;
            joints.set_g_diagonal(j, &d);
            let expected = scalar_solve(&sides, n_bodies, &joints, &bodies).unwrap_err();
            let mut solver = Solver::new(n_bodies, &sides, &vec![true; sides.len()]);
            assert_eq!(batches(&solver), 2);
            let mut pp = vec![Vector6::zeros(); joints.len()];
            let mut uu = vec![Vector6::zeros(); n_bodies];
            let got = solver
                .solve(&joints, &bodies, &mut pp, &mut uu)
                .unwrap_err();
            assert_eq!(got, expected);
            assert!(matches!(
                got,
                SolveFailure::NotPositive(k) | SolveFailure::SingularJoint(k) if k == j as u32
            ));
            let mut d = joints[j].g_diagonal;
            d[2] = 1.0;
            joints.set_g_diagonal(j, &d);
        }
    }

    /// Shapes the lanes do not solve stay scalar: a hub, a tree larger than
    /// [`super::MAX_NODES`].
    #[test]
    fn hubs_and_large_trees_stay_scalar() {
        let hub = vec![[None, Some(0)], [Some(0), Some(1)], [Some(0), Some(2)]];
        let (sides, n_bodies) = forest(&hub, 4);
        let solver = Solver::new(n_bodies, &sides, &vec![true; sides.len()]);
        assert_eq!(batches(&solver), 0);
        let long: Vec<_> = std::iter::once([None, Some(0)])
            .chain((0..40).map(|b| [Some(b), Some(b + 1)]))
            .collect();
        let (sides, n_bodies) = forest(&long, 4);
        let solver = Solver::new(n_bodies, &sides, &vec![true; sides.len()]);
        assert_eq!(batches(&solver), 0);
    }

    /// The islands of bodies whose inputs changed after a solve (a held axis released:
    /// `substep::release_lifted`), solved again alone ([`Solver::solve_again`]): the same
    /// bits as the whole solve again, in a batch of the lanes, in the scalar forest of the
    /// tree left over, and where a coupled joint made the lanes fall back; the islands of
    /// bodies not named keep the first solve's solution.
    #[test]
    fn solving_again_the_changed_islands_equals_solving_all_again() {
        // nine copies of the contact scene's shape: two batches in lanes, one tree left
        // over in the scalar forest
        let (sides, n_bodies) = forest(&shapes()[0], 9);
        for coupled in [false, true] {
            let (mut joints, mut bodies) = random_system(&sides, n_bodies, 57);
            if coupled {
                let mut g = Matrix6::from_diagonal(&joints[1].g_diagonal);
                g[(2, 1)] = 0.1 * g[(1, 1)].min(g[(2, 2)]);
                g[(1, 2)] = g[(2, 1)];
                joints.set_g(1, &g);
            }
            let mut solver = Solver::new(n_bodies, &sides, &vec![true; sides.len()]);
            assert_eq!(batches(&solver), 2);
            let mut p = vec![Vector6::zeros(); joints.len()];
            let mut u = vec![Vector6::zeros(); n_bodies];
            solver.solve(&joints, &bodies, &mut p, &mut u).unwrap();
            let (p_first, u_first) = (p.clone(), u.clone());
            // a body of the second batch (tree 5, its middle body), one of the tree left
            // over (tree 8) and one of the first batch that is not named (tree 0)
            for b in [5 * 3 + 1, 8 * 3, 0] {
                bodies[b].release(0, 64.0, 0.25);
            }
            solver
                .solve_again(&joints, &bodies, &mut p, &mut u, &[16, 24])
                .unwrap();
            // what solving all again gives, but for tree 0, whose change was not named
            let mut all = Solver::new(n_bodies, &sides, &vec![true; sides.len()]);
            let (mut pa, mut ua) = (vec![Vector6::zeros(); joints.len()], u.clone());
            all.solve(&joints, &bodies, &mut pa, &mut ua).unwrap();
            let (tree0_joints, tree0_bodies) = (0..2, 0..3);
            assert_eq!(bits(&p[2..]), bits(&pa[2..]), "coupled {coupled}: impulses");
            assert_eq!(
                bits(&u[3..]),
                bits(&ua[3..]),
                "coupled {coupled}: velocities"
            );
            if coupled {
                // the fallback solved the whole forest again: tree 0 as well
                assert_eq!(bits(&p[tree0_joints]), bits(&pa[0..2]));
            } else {
                assert_eq!(bits(&p[tree0_joints.clone()]), bits(&p_first[tree0_joints]));
                assert_eq!(bits(&u[tree0_bodies.clone()]), bits(&u_first[tree0_bodies]));
                assert_ne!(bits(&pa[0..2]), bits(&p_first[0..2]), "tree 0 did change");
            }
            // (tree k's joints are 2k and 2k + 1)
            assert_ne!(
                bits(&p[10..12]),
                bits(&p_first[10..12]),
                "tree 5 did change"
            );
            assert_ne!(
                bits(&p[16..18]),
                bits(&p_first[16..18]),
                "tree 8 did change"
            );
        }
    }
}
