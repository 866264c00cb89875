//! Dense 6×6 kernels of the block eliminations: Cholesky factor, triangular solves and the
//! symmetric products `XᵀX`, written out so that nothing allocates and nothing is inverted
//! where a factor will do.

use super::{MassBlocks, RateJacobians};
use crate::lanes::{arr3, arr6};
use nalgebra::{Matrix6, Vector6};
use std::ops::{Add, Mul};

// The kernels work on the column-major arrays behind `Matrix6` (`m.data.0[column][row]`)
// with constant loop bounds, so that nothing is bounds-checked and the compiler can unroll.

/// A lower Cholesky factor `L` of a 6×6 block (`A = L·Lᵀ`), stored with the **reciprocals**
/// of its diagonal (`1/l_ii` in place of `l_ii`): every triangular solve multiplies instead
/// of dividing.
pub(crate) type Factor = Matrix6<f64>;

/// Lower Cholesky factor `L` of a symmetric positive-definite `a` (`a = L·Lᵀ`), reading the
/// lower triangle only, stored as a [`Factor`]. `None` when a pivot is not positive (the
/// matrix is not positive definite, or not finite) or subnormal.
#[cfg(test)]
pub(crate) fn cholesky(a: &Matrix6<f64>) -> Option<Factor> {
    let mut l = *a;
    cholesky_in_place(&mut l).then_some(l)
}

/// [`cholesky`] in place: `a` becomes its [`Factor`] (its upper triangle is left as it
/// was and never read). `false` when a pivot is not positive (then `a` holds garbage).
///
/// The pivots are a chain, each one's square root and reciprocal before the next:
/// `d_j = a_jj − Σ_k<j l_jk²` waits for `l_j,j−1 = s_j,j−1·(√d_j−1·(1/d_j−1))` (`s` the
/// entry before its scaling). Its last term is taken as `s_j,j−1²·(1/d_j−1)` (the same
/// `l_j,j−1² = s²/d_j−1`), so that the chain runs through the reciprocal alone (a division,
/// a product, a difference) and the square roots, needed for the entries below, run beside
/// it. The squares `s²` are finite for a matrix whose diagonal entries are below 1e154
/// (`s² ≤ a_jj·a_j−1,j−1`; the solver's blocks are below `1/ε = 1e12` and the bodies'
/// inverse masses). Not the old arithmetic bit for bit (the test
/// `cholesky_equals_the_square_root_chain` holds both to the same backward error and their
/// solutions within `κ·1e-15` of each other).
// (index loops with constant bounds and masks: the compiler unrolls the whole factorisation)
#[allow(clippy::needless_range_loop)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn cholesky_in_place(a: &mut Matrix6<f64>) -> bool {
    // column j of L overwrites column j of a (l[j][i] is entry (i, j)); entry (i, j) of a is
    // read once, before it is overwritten
    let l = &mut a.data.0;
    // every pivot positive, normal and finite; tested once at the end (a failed factor is
    // never used, and the unrolled factorisation stays one straight run of arithmetic)
    let mut ok = true;
    // the previous column's unscaled entries s_i,j−1 (i ≥ j) and 1/d_j−1
    let mut s_prev = [0.0; 6];
    let mut r_prev = 0.0;
    for j in 0..6 {
        // d = a_jj − Σ_k<j−1 l_jk² − s_j,j−1²·(1/d_j−1)
        let mut d = l[j][j];
        // constant bounds with a mask: the compiler unrolls the whole 6×6 factorisation
        for k in 0..6 {
            if k + 1 < j {
                d -= l[k][j] * l[k][j];
            }
        }
        if j > 0 {
            let sq = s_prev[j] * s_prev[j];
            d -= sq * r_prev;
        }
        // a subnormal pivot is as singular as zero (and 1/d below would overflow); NaN fails
        // both comparisons
        ok &= (f64::MIN_POSITIVE..=f64::MAX).contains(&d);
        // 1/√d as √d·(1/d): the square root and the division run side by side
        let r = 1.0 / d;
        let inv = d.sqrt() * r;
        l[j][j] = inv;
        let mut s_col = [0.0; 6];
        for i in 0..6 {
            if i > j {
                // l_ij = (a_ij − Σ_k<j l_ik·l_jk) / l_jj
                let mut s = l[j][i];
                for k in 0..6 {
                    if k < j {
                        s -= l[k][i] * l[k][j];
                    }
                }
                s_col[i] = s;
                l[j][i] = s * inv;
            }
        }
        s_prev = s_col;
        r_prev = r;
    }
    ok
}

/// `x ← L⁻¹·x` for a factor `L`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn forward(l: &Factor, x: &mut Vector6<f64>) {
    let l = &l.data.0;
    let x = &mut x.data.0[0];
    // column-oriented: once x_k is final, remove its share from the rows below
    for k in 0..6 {
        let xk = x[k] * l[k][k];
        x[k] = xk;
        for i in 0..6 {
            if i > k {
                x[i] -= l[k][i] * xk;
            }
        }
    }
}

/// `x ← L⁻ᵀ·x` for a factor `L`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn backward(l: &Factor, x: &mut Vector6<f64>) {
    let l = &l.data.0;
    let x = &mut x.data.0[0];
    for i in (0..6).rev() {
        // row i of Lᵀ is column i of L
        let mut s = x[i];
        for k in 0..6 {
            if k > i {
                s -= l[i][k] * x[k];
            }
        }
        x[i] = s * l[i][i];
    }
}

/// `x ← (L·Lᵀ)⁻¹·x`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn chol_solve(l: &Factor, x: &mut Vector6<f64>) {
    forward(l, x);
    backward(l, x);
}

/// `A·B` of two 3×3 blocks stored by columns (`m[column][row]`, the layout of
/// `Matrix3::data.0`) as nalgebra's `Matrix3 * Matrix3` forms it (`gemm`, column by column
/// through `gemv`): `C_ij = (A_i0·B_0j + A_i1·B_1j) + A_i2·B_2j`, each term added to the sum
/// so far. Generic over the number, `f64` here and four lanes of them in `tree_x4`: the
/// same operations in the same order, so the lanes give the scalar solve's bits. (nalgebra's
/// product was compiled out of line in the AVX2 copy of the substep, a call per product.)
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn mat3_mul<T: Copy + Add<Output = T> + Mul<Output = T>>(
    a: &[[T; 3]; 3],
    b: &[[T; 3]; 3],
) -> [[T; 3]; 3] {
    let mut c = *b;
    for (cj, bj) in c.iter_mut().zip(b) {
        let mut y = [a[0][0] * bj[0], a[0][1] * bj[0], a[0][2] * bj[0]];
        for k in 1..3 {
            for i in 0..3 {
                y[i] = a[k][i] * bj[k] + y[i];
            }
        }
        *cj = y;
    }
    c
}

/// A 6×6 block stored by rows (`x[row][column]`): the layout of the right-hand sides of
/// [`forward_rows`], whose every operation is then a 6-wide row update.
pub(crate) type Rows = [[f64; 6]; 6];

/// The rows of `B`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn rows_of(b: &Matrix6<f64>) -> Rows {
    let b = &b.data.0;
    arr6(|r| arr6(|c| b[c][r]))
}

/// The rows of `Bᵀ` (the columns of `B`).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn rows_of_transpose(b: &Matrix6<f64>) -> Rows {
    b.data.0
}

/// `X ← L⁻¹·X` for a factor `L` and `X` stored by rows (six right-hand sides at once):
/// once row `k` is final, its multiples are removed from the rows below.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn forward_rows(l: &Factor, x: &mut Rows) {
    let l = &l.data.0;
    for k in 0..6 {
        let d = l[k][k];
        let xk = arr6(|c| x[k][c] * d);
        x[k] = xk;
        for i in 0..6 {
            if i > k {
                let f = l[k][i];
                for c in 0..6 {
                    x[i][c] -= f * xk[c];
                }
            }
        }
    }
}

/// `a += Xᵀ·X = Σ_i x_iᵀ·x_i` for `X` stored by rows (`x_i` its rows). Each entry is the
/// same sum in the same order as its mirror, so the result is exactly symmetric.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn add_gram(a: &mut Matrix6<f64>, x: &Rows) {
    let a = &mut a.data.0;
    for xi in x {
        for c in 0..6 {
            for r in 0..6 {
                a[c][r] += xi[r] * xi[c];
            }
        }
    }
}

/// `a −= Xᵀ·X` on and below the diagonal for `X` stored by rows (a Schur complement whose
/// only reader is [`cholesky_in_place`]; [`add_lower`]).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn sub_lower_gram(a: &mut Matrix6<f64>, x: &Rows) {
    // the rows of X are the columns of Xᵀ: Xᵀ·X = C·Cᵀ with C = Xᵀ
    add_lower::<true, false>(a, x, x);
}

/// `a −= Xᵀ·Y` for `X`, `Y` and `a` stored by rows: row `i` of `a` loses
/// `Σ_r X_ri·y_r` (`y_r` the rows of `Y`), 6-wide row updates. The off-diagonal Schur
/// complement of a block elimination ([`super::loops`]).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn sub_tr_mul_rows(a: &mut Rows, x: &Rows, y: &Rows) {
    for (xr, yr) in x.iter().zip(y) {
        for (ai, &f) in a.iter_mut().zip(xr) {
            for c in 0..6 {
                ai[c] -= f * yr[c];
            }
        }
    }
}

/// `X·v` for `X` stored by rows.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn rows_mul(x: &Rows, v: &Vector6<f64>) -> Vector6<f64> {
    Vector6::from(arr6(|i| {
        let xi = &x[i];
        let mut s = 0.0;
        for c in 0..6 {
            s += xi[c] * v[c];
        }
        s
    }))
}

/// `Xᵀ·z = Σ_i z_i·x_i` for `X` stored by rows.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn transpose_mul(x: &Rows, z: &Vector6<f64>) -> Vector6<f64> {
    let mut out = [0.0; 6];
    for (xi, zi) in x.iter().zip(z.iter()) {
        for c in 0..6 {
            out[c] += zi * xi[c];
        }
    }
    Vector6::from(out)
}

/// `a += B·N·Bᵀ` for a symmetric `N` (the result is exactly symmetric).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn add_congruence(a: &mut Matrix6<f64>, b: &Matrix6<f64>, n: &Matrix6<f64>) {
    let bn = b * n;
    for c in 0..6 {
        for r in 0..=c {
            let s = bn.row(r).dot(&b.row(c));
            a[(r, c)] += s;
            if r != c {
                a[(c, r)] += s;
            }
        }
    }
}

/// A 6×6 block stored by columns (`c[column][row]`, the layout of `Matrix6`'s array).
pub(crate) type Columns = [[f64; 6]; 6];

/// Whether `b` has the structure of a joint's rates Jacobian
/// ([`super::SolverJoint::jac`]): zero in its rotation rows × linear-velocity columns (the
/// lower-left 3×3 block), which the products with `M⁻¹` below rely on.
#[cfg(test)]
pub(crate) fn is_jacobian(b: &Matrix6<f64>) -> bool {
    b.fixed_view::<3, 3>(3, 0).iter().all(|v| *v == 0.0)
}

/// `B·M⁻¹` by columns for a joint's Jacobian `B` (lower-left 3×3 block zero,
/// [`is_jacobian`]) and a body's generalised inverse mass `M⁻¹ = diag(m⁻¹) ⊕ I⁻¹`
/// ([`MassBlocks`], as [`super::SolverBody::inv_mass`] is built): with
///
/// ```text
/// B = ⎡B_vv B_vω⎤,   B·M⁻¹ = ⎡B_vv·diag(m⁻¹)  B_vω·I⁻¹⎤
///     ⎣ 0   B_ωω⎦            ⎣      0         B_ωω·I⁻¹⎦
/// ```
///
/// 63 products instead of 216, and `B·M⁻¹` has the same zero block.
#[cfg(test)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn times_inv_mass(b: &Matrix6<f64>, m: &MassBlocks) -> Columns {
    debug_assert!(is_jacobian(b), "not a joint's Jacobian: {b}");
    let bd = &b.data.0; // bd[column][row]
    let id = &m.angular.data.0; // id[column][row]
    let mut c = [[0.0; 6]; 6];
    for k in 0..3 {
        for r in 0..3 {
            c[k][r] = m.linear[k] * bd[k][r];
        }
    }
    for l in 0..3 {
        for k in 0..3 {
            let i_kl = id[l][k];
            for r in 0..6 {
                c[3 + l][r] += bd[3 + k][r] * i_kl;
            }
        }
    }
    c
}

/// `col ± Σ_q B_jq·c_q` from row `S` down (`C` by columns, `B` as the array behind a
/// `Matrix6`, `bd[q][j] = B_jq`): column `j` of `±C·Bᵀ`, six 6-wide updates. `S` is a
/// constant so that the compiler unrolls it whole. With `JAC`, `C` and `B` both have a zero
/// lower-left 3×3 block (a Jacobian and its [`times_inv_mass`]): the terms `q < 3` are zero
/// below row 3 (`C_rq = 0` for `r ≥ 3`) and in the columns `j ≥ 3` (`B_jq = 0`), so they are
/// skipped there (`j` is a constant at every call).
#[cfg_attr(not(debug_assertions), inline(always))]
fn add_column_t<const S: usize, const NEG: bool, const JAC: bool>(
    col: &mut [f64; 6],
    c: &Columns,
    bd: &Columns,
    j: usize,
) {
    for q in 0..6 {
        let f = if NEG { -bd[q][j] } else { bd[q][j] };
        if JAC && q < 3 {
            if j < 3 {
                for r in S..3 {
                    col[r] += f * c[q][r];
                }
            }
        } else {
            for r in S..6 {
                col[r] += f * c[q][r];
            }
        }
    }
}

/// `a ± C·Bᵀ` from row 0 in columns 0 and 1, from row `S2` in columns 2 and 3, from row
/// `S4` in columns 4 and 5 (`bd` as in [`add_column_t`]).
#[cfg_attr(not(debug_assertions), inline(always))]
fn add_columns<const S2: usize, const S4: usize, const NEG: bool, const JAC: bool>(
    ad: &mut Columns,
    c: &Columns,
    bd: &Columns,
) {
    // written out column by column: a loop over the columns is not unrolled
    add_column_t::<0, NEG, JAC>(&mut ad[0], c, bd, 0);
    add_column_t::<0, NEG, JAC>(&mut ad[1], c, bd, 1);
    add_column_t::<S2, NEG, JAC>(&mut ad[2], c, bd, 2);
    add_column_t::<S2, NEG, JAC>(&mut ad[3], c, bd, 3);
    add_column_t::<S4, NEG, JAC>(&mut ad[4], c, bd, 4);
    add_column_t::<S4, NEG, JAC>(&mut ad[5], c, bd, 5);
}

/// `a ± C·Bᵀ` on and below the diagonal (`bd` as in [`add_column_t`]), by whole pairs of
/// rows: the entries above the diagonal, which [`cholesky_in_place`] never reads, are
/// updated in the pairs that hold a diagonal entry and left as they were elsewhere.
#[cfg_attr(not(debug_assertions), inline(always))]
fn add_lower<const NEG: bool, const JAC: bool>(a: &mut Matrix6<f64>, c: &Columns, bd: &Columns) {
    add_columns::<2, 4, NEG, JAC>(&mut a.data.0, c, bd);
}

/// `C·Bᵀ` by columns for a joint's Jacobian `B` and `C = A·M⁻¹` ([`times_inv_mass`] of
/// another Jacobian `A`): `A·M⁻¹·Bᵀ`, the zero blocks skipped ([`add_column_t`]).
#[cfg(test)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn product_t(c: &Columns, b: &Matrix6<f64>) -> Columns {
    debug_assert!(is_jacobian(b), "not a joint's Jacobian: {b}");
    let mut out = [[0.0; 6]; 6];
    add_columns::<0, 0, false, true>(&mut out, c, &b.data.0);
    out
}

/// `a += C·Bᵀ` on and below the diagonal for a joint's Jacobian `B` and `C = B·M⁻¹`
/// ([`times_inv_mass`], [`add_lower`]): the symmetric `B·M⁻¹·Bᵀ` (tests: the tree takes
/// [`add_jacobian_congruence`], [`add_two_sided_congruence`] and [`add_link_products`] of the
/// blocks).
#[cfg(test)]
pub(crate) fn add_lower_product_t(a: &mut Matrix6<f64>, c: &Columns, b: &Matrix6<f64>) {
    debug_assert!(is_jacobian(b), "not a joint's Jacobian: {b}");
    add_lower::<false, true>(a, c, &b.data.0);
}

/// `a += B·M⁻¹·Bᵀ` on and below the diagonal for a joint's Jacobian and a body's
/// generalised inverse mass ([`times_inv_mass`], [`add_lower_product_t`]): a leaf body of a
/// tree (tests: the tree takes [`add_jacobian_congruence`] of the blocks).
#[cfg(test)]
pub(crate) fn add_congruence_inv_mass(a: &mut Matrix6<f64>, b: &Matrix6<f64>, m: &MassBlocks) {
    add_lower_product_t(a, &times_inv_mass(b, m), b);
}

/// `a += J_s·M⁻¹·J_sᵀ` on and below the diagonal for side `s` of a joint's Jacobians
/// ([`RateJacobians`]) and a body's generalised inverse mass, from the 3×3 blocks without
/// the 6×6 expansion: with `J_s = σ_s·[T L; 0 R]` (`σ_s² = 1`, `L = L_s`) and
/// `M⁻¹ = diag(m⁻¹) ⊕ I⁻¹`,
///
/// ```text
/// J·M⁻¹·Jᵀ = ⎡T·diag(m⁻¹)·Tᵀ + (L·I⁻¹)·Lᵀ   (L·I⁻¹)·Rᵀ⎤
///            ⎣(R·I⁻¹)·Lᵀ                   (R·I⁻¹)·Rᵀ⎦
/// ```
///
/// (the lower triangle of the diagonal blocks and the whole lower-left block are written; the
/// upper triangle is left as it was, never read by [`cholesky_in_place`]). The same products
/// as [`add_congruence_inv_mass`] of `J_s.matrix()`, summed in another order.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn add_jacobian_congruence(
    a: &mut Matrix6<f64>,
    jac: &RateJacobians,
    s: usize,
    m: &MassBlocks,
) {
    let side = JacobianSide::new(jac, s, m);
    side.add_congruence(a, m);
}

/// `a += J_1·M_1⁻¹·J_1ᵀ + J_2·M_2⁻¹·J_2ᵀ` on and below the diagonal for both sides of a
/// joint's Jacobians, each against its body's generalised inverse mass: the two sides share
/// `T` and `R` (`J_s = σ_s·[T L_s; 0 R]`, `σ_s² = 1`), so with `M_s⁻¹ = diag(m⁻¹_s) ⊕ I⁻¹_s`
///
/// ```text
/// Σ_s J_s·M_s⁻¹·J_sᵀ = ⎡T·diag(m⁻¹_1 + m⁻¹_2)·Tᵀ + A_1·L_1ᵀ + A_2·L_2ᵀ   W·Rᵀ⎤
///                     ⎣R·Wᵀ                                            B·Rᵀ⎦
///
/// A_s = L_s·I⁻¹_s,   W = A_1 + A_2,   B = R·(I⁻¹_1 + I⁻¹_2)
/// ```
///
/// (`I⁻¹_s` symmetric: `R·I⁻¹_s·L_sᵀ = R·A_sᵀ`): three 3×3 products where the sides one by
/// one ([`add_jacobian_congruence`] twice) take four, and the linear, lower-left and
/// rotation blocks summed once where they were summed per side. Written as
/// [`add_jacobian_congruence`] writes (columns `0, 1` from row 0, `2` from row 2, `3` from
/// row 3, `4, 5` from row 4; the upper triangle is never read by [`cholesky_in_place`]).
/// Not the sides' sums bit for bit: the masses and inverse inertias of the two bodies are
/// added before the products (test `two_sided_congruence_equals_the_sides_one_by_one`,
/// within 1e-14 of the largest entry of either side's term).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn add_two_sided_congruence(
    a: &mut Matrix6<f64>,
    jac: &RateJacobians,
    m1: &MassBlocks,
    m2: &MassBlocks,
) {
    let ml = m1.linear + m2.linear;
    // x[k][r] = X_rk (the layout of Matrix3's array)
    let (l1, l2) = (jac.lever(0), jac.lever(1));
    let a1 = (l1 * m1.angular).data.0;
    let a2 = (l2 * m2.angular).data.0;
    let b = (jac.r * (m1.angular + m2.angular)).data.0;
    let (t, r) = (&jac.t.data.0, &jac.r.data.0);
    let (l1, l2) = (&l1.data.0, &l2.data.0);
    let ad = &mut a.data.0; // ad[column][row]
    shared_column::<0>(&mut ad[0], 0, &ml, t, l1, l2, r, &a1, &a2);
    shared_column::<0>(&mut ad[1], 1, &ml, t, l1, l2, r, &a1, &a2);
    shared_column::<2>(&mut ad[2], 2, &ml, t, l1, l2, r, &a1, &a2);
    rotation_column::<3>(&mut ad[3], 0, r, &b);
    rotation_column::<4>(&mut ad[4], 1, r, &b);
    rotation_column::<4>(&mut ad[5], 2, r, &b);
}

/// Column `c < 3` of [`add_two_sided_congruence`] from row `S` down: rows `S..3` take
/// `Σ_k (m⁻¹_k·T_ck·T_·k + L_1,ck·A_1,·k + L_2,ck·A_2,·k)`, rows `3..6` take
/// `Σ_k W_ck·R_·k` (`W_ck = A_1,ck + A_2,ck`).
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn shared_column<const S: usize>(
    col: &mut [f64; 6],
    c: usize,
    ml: &nalgebra::Vector3<f64>,
    t: &[[f64; 3]; 3],
    l1: &[[f64; 3]; 3],
    l2: &[[f64; 3]; 3],
    r: &[[f64; 3]; 3],
    a1: &[[f64; 3]; 3],
    a2: &[[f64; 3]; 3],
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

/// Column `3 + c` of [`add_two_sided_congruence`] from row `S ≥ 3` down: `Σ_k R_ck·B_·k`.
#[cfg_attr(not(debug_assertions), inline(always))]
fn rotation_column<const S: usize>(
    col: &mut [f64; 6],
    c: usize,
    r: &[[f64; 3]; 3],
    b: &[[f64; 3]; 3],
) {
    for k in 0..3 {
        let w = r[k][c];
        for i in S - 3..3 {
            col[3 + i] += w * b[k][i];
        }
    }
}

/// One side of a joint's Jacobians against one body's `M⁻¹` ([`add_jacobian_congruence`]):
/// its blocks `T`, `L = L_s`, `R` (without the sign `σ_s`) and the columns
/// `u_k = ((L·I⁻¹)_{·k}, (R·I⁻¹)_{·k})` of the angular half of `J·M⁻¹`, made once and shared
/// by the congruence and the coupling of a link ([`add_link_products`]).
///
/// Every product is then a sum of 6-long columns with scalar weights (a `q ≥ 3` column of
/// `J·M⁻¹·Bᵀ` for any Jacobian `B = [T' L'; 0 R']` is `Σ_k B_·k·u_k`; with `I⁻¹`
/// symmetric, `(L·I⁻¹·L'ᵀ)_{rj} = Σ_k L'_jk·(L·I⁻¹)_rk`), which the compiler makes
/// two-wide vector updates of whole columns, as in [`add_columns`].
struct JacobianSide<'a> {
    /// `t[k][r] = T_rk`, `l`, `r` alike (the layout of `Matrix3`'s array).
    t: &'a [[f64; 3]; 3],
    /// `L_s`, formed from the side's lever arm ([`RateJacobians::lever`]).
    l: [[f64; 3]; 3],
    r: &'a [[f64; 3]; 3],
    /// `u[k] = ((L·I⁻¹)_{0..3,k}, (R·I⁻¹)_{0..3,k})`.
    u: [[f64; 6]; 3],
}

/// `col += Σ_k a_k·(T_{·k}, 0) + Σ_k b_k·u_k` from row `S` down (the first sum only with
/// `LIN`; `tt[k][r] = T_rk`): one column of a product of [`JacobianSide`]s.
#[cfg_attr(not(debug_assertions), inline(always))]
fn add_weighted<const S: usize, const LIN: bool>(
    col: &mut [f64; 6],
    a: [f64; 3],
    b: [f64; 3],
    tt: &[[f64; 3]; 3],
    u: &[[f64; 6]; 3],
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

impl<'a> JacobianSide<'a> {
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn new(jac: &'a RateJacobians, s: usize, m: &MassBlocks) -> Self {
        let (l, r) = (jac.lever(s), &jac.r);
        // I⁻¹ symmetric: (X·I⁻¹)_rk = Σ_q X_rq·I⁻¹_qk
        let ia = &m.angular.data.0;
        let (li, ri) = (mat3_mul(&l.data.0, ia), mat3_mul(&r.data.0, ia));
        JacobianSide {
            t: &jac.t.data.0,
            l: l.data.0,
            r: &r.data.0,
            u: arr3(|k| [li[k][0], li[k][1], li[k][2], ri[k][0], ri[k][1], ri[k][2]]),
        }
    }

    /// The blocks of side `s` without the columns `u` (zero): the weights of a product
    /// whose columns are another side's ([`add_link_products`]).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn blocks(jac: &'a RateJacobians, s: usize) -> Self {
        JacobianSide {
            t: &jac.t.data.0,
            l: jac.lever(s).data.0,
            r: &jac.r.data.0,
            u: [[0.0; 6]; 3],
        }
    }

    /// The weights of column `c` (`c < 3`) of `J·M⁻¹·Jᵀ`: `a_k = m⁻¹_k·T_ck`, `b_k = L_ck`,
    /// times `sign`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn weights(&self, c: usize, m: &MassBlocks, sign: f64) -> ([f64; 3], [f64; 3]) {
        // written out: closures here were compiled out of line in the AVX2 copy
        let (t, l, ml) = (self.t, self.l, &m.linear);
        (
            [
                sign * (ml[0] * t[0][c]),
                sign * (ml[1] * t[1][c]),
                sign * (ml[2] * t[2][c]),
            ],
            [sign * l[0][c], sign * l[1][c], sign * l[2][c]],
        )
    }

    /// `b_k = R_ck` times `sign`: column `3 + c` of `J·M⁻¹·Jᵀ`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn rotation_weights(&self, c: usize, sign: f64) -> [f64; 3] {
        let r = self.r;
        [sign * r[0][c], sign * r[1][c], sign * r[2][c]]
    }

    /// `a += J·M⁻¹·Jᵀ` on and below the diagonal ([`add_jacobian_congruence`]; by pairs of
    /// rows as in [`add_lower`]: entries above the diagonal in a pair that holds a diagonal
    /// entry are updated too, and never read).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn add_congruence(&self, a: &mut Matrix6<f64>, m: &MassBlocks) {
        let ad = &mut a.data.0; // ad[column][row]
        let (t, u) = (self.t, &self.u);
        let (a0, b0) = self.weights(0, m, 1.0);
        add_weighted::<0, true>(&mut ad[0], a0, b0, t, u);
        let (a1, b1) = self.weights(1, m, 1.0);
        add_weighted::<0, true>(&mut ad[1], a1, b1, t, u);
        let (a2, b2) = self.weights(2, m, 1.0);
        add_weighted::<2, true>(&mut ad[2], a2, b2, t, u);
        let no = [0.0; 3];
        add_weighted::<2, false>(&mut ad[3], no, self.rotation_weights(0, 1.0), t, u);
        add_weighted::<4, false>(&mut ad[4], no, self.rotation_weights(1, 1.0), t, u);
        add_weighted::<4, false>(&mut ad[5], no, self.rotation_weights(2, 1.0), t, u);
    }
}

/// The products a link body of a tree ([`super::tree`], *Links*) makes between its child
/// joint `c` (side `sc` of `jc`) and its parent joint `p` (side `sp` of `jp`), from the
/// Jacobians' 3×3 blocks: `D_c += J_c·M⁻¹·J_cᵀ`, `D_p += J_p·M⁻¹·J_pᵀ` (lower triangles,
/// [`add_jacobian_congruence`]; each only where given: the tree adds them with the joint's
/// other side's where it can, [`add_two_sided_congruence`]) and the coupling
/// `E = J_c·M⁻¹·J_pᵀ` written by rows into `e`. With `J_c = σ_c·[T_c L_c; 0 R_c]`,
/// `J_p = σ_p·[T_p L_p; 0 R_p]` and `M⁻¹ = diag(m⁻¹) ⊕ I⁻¹`,
///
/// ```text
/// E = σ_c·σ_p·⎡T_c·diag(m⁻¹)·T_pᵀ + L_c·(L_p·I⁻¹)ᵀ   L_c·(R_p·I⁻¹)ᵀ⎤
///             ⎣R_c·(L_p·I⁻¹)ᵀ                       R_c·(R_p·I⁻¹)ᵀ⎦
/// ```
///
/// so row `r < 3` of `E` is `σ_c·σ_p·(Σ_k m⁻¹_k·T_c,rk·(T_p,·k, 0) + Σ_k L_c,rk·u_k)` and row
/// `3 + r` is `σ_c·σ_p·Σ_k R_c,rk·u_k`, with the columns `u_k` of side `p`
/// ([`JacobianSide`]); `σ_c·σ_p = ±1` is applied exactly, to the weights. `L·I⁻¹` and
/// `R·I⁻¹` of each side are made once for its congruence and for `E` (side `c`'s not at all
/// without its congruence), where the 6×6 forms ([`times_inv_mass`], [`product_t`],
/// `add_lower_product_t`) built both 6×6 Jacobians and both `J·M⁻¹`. The same products,
/// summed in another order.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn add_link_products(
    d_c: Option<&mut Matrix6<f64>>,
    d_p: Option<&mut Matrix6<f64>>,
    e: &mut Rows,
    jc: &RateJacobians,
    sc: usize,
    jp: &RateJacobians,
    sp: usize,
    m: &MassBlocks,
) {
    let p = JacobianSide::new(jp, sp, m);
    if let Some(d_p) = d_p {
        p.add_congruence(d_p, m);
    }
    // side c's blocks; its columns u only for its congruence (its `L_c` formed once)
    let c = match d_c {
        Some(d_c) => {
            let c = JacobianSide::new(jc, sc, m);
            c.add_congruence(d_c, m);
            c
        }
        None => JacobianSide::blocks(jc, sc),
    };
    let sign = RateJacobians::sign(sc) * RateJacobians::sign(sp);
    let (t, u) = (p.t, &p.u);
    *e = [[0.0; 6]; 6];
    let no = [0.0; 3];
    for r in 0..3 {
        let (a, b) = c.weights(r, m, sign);
        add_weighted::<0, true>(&mut e[r], a, b, t, u);
        add_weighted::<0, false>(&mut e[3 + r], no, c.rotation_weights(r, sign), t, u);
    }
}

/// `M⁻¹·v` for a body's generalised inverse mass ([`MassBlocks`]): 12 products instead of
/// 36, the same sums (the skipped entries are zeros).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn inv_mass_mul(m: &MassBlocks, v: &Vector6<f64>) -> Vector6<f64> {
    let id = &m.angular.data.0;
    let mut out = [0.0; 6];
    for k in 0..3 {
        out[k] = m.linear[k] * v[k];
    }
    for l in 0..3 {
        for r in 0..3 {
            out[3 + r] += id[l][r] * v[3 + l];
        }
    }
    Vector6::from(out)
}

/// `inv = (diag(g) + ε·I)⁻¹` of a diagonal `G` given by its diagonal `g` (`None` when an
/// entry is singular or not finite).
///
/// Inlined: out of line it was compiled without the substep's AVX2 and cleared its 288
/// bytes through a `memset` call (1.1 % of the 1000-link chain's frame in a profile, and a
/// share of the `memset`'s 1.2 %; the frame 0.4 % shorter inlined, within the spread).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn regularised_diagonal_inverse(
    g: &Vector6<f64>,
    eps: f64,
    inv: &mut Matrix6<f64>,
) -> Option<()> {
    *inv = Matrix6::zeros();
    // tested once at the end, as in cholesky_in_place
    let mut ok = true;
    for i in 0..6 {
        let d = g[i] + eps;
        ok &= d != 0.0 && d.abs() <= f64::MAX;
        inv.data.0[i][i] = 1.0 / d;
    }
    ok.then_some(())
}

/// Inverse of the regularised `G + ε·I` (symmetrised) into `inv`, by its diagonal when `G`
/// is diagonal (the common case: no coupled stops, no cross terms in the law's tangent).
/// `None` when it is singular, else whether `G` (and so `inv`) is diagonal.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn regularised_inverse(
    g: &Matrix6<f64>,
    eps: f64,
    inv: &mut Matrix6<f64>,
) -> Option<bool> {
    if is_diagonal(g) {
        regularised_diagonal_inverse(&g.diagonal(), eps, inv)?;
        return Some(true);
    }
    let full = (g + Matrix6::identity() * eps).try_inverse()?;
    *inv = 0.5 * (full + full.transpose());
    Some(false)
}

/// Whether every entry of `m` off its diagonal is ±0: their bits without the sign or-ed
/// together, without a branch (a NaN is not zero).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn is_diagonal(m: &Matrix6<f64>) -> bool {
    // the 36 entries in column order, the diagonal at every 7th: the 5 runs of 6 entries
    // between two diagonal entries
    let a = m.as_slice();
    let mut off = 0u64;
    for run in 0..5 {
        for v in &a[7 * run + 1..7 * run + 7] {
            off |= v.to_bits() << 1;
        }
    }
    off == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd() -> Matrix6<f64> {
        let b = Matrix6::from_fn(|i, j| ((i * 7 + j * 3) % 11) as f64 - 5.0);
        b * b.transpose() + Matrix6::identity() * 3.0
    }

    #[test]
    fn cholesky_reproduces_the_matrix_and_solves() {
        let a = spd();
        let l = cholesky(&a).unwrap();
        // the factor: reciprocal diagonal, upper triangle left as it was
        let mut full = l;
        for i in 0..6 {
            full[(i, i)] = 1.0 / l[(i, i)];
            for j in i + 1..6 {
                full[(i, j)] = 0.0;
            }
        }
        assert!((full * full.transpose() - a).abs().max() < 1e-12 * a.abs().max());
        let x0 = Vector6::new(1.0, -2.0, 3.0, 0.5, -0.25, 4.0);
        let mut x = a * x0;
        chol_solve(&l, &mut x);
        assert!((x - x0).abs().max() < 1e-10);
        let m = Matrix6::from_fn(|i, j| (i + 2 * j) as f64);
        let from_rows = |x: &Rows| Matrix6::from_fn(|r, c| x[r][c]);
        let mut x = rows_of(&m);
        forward_rows(&l, &mut x);
        assert!((full * from_rows(&x) - m).abs().max() < 1e-10);
        let mut x = rows_of_transpose(&m);
        forward_rows(&l, &mut x);
        assert!((full * from_rows(&x) - m.transpose()).abs().max() < 1e-10);
        let z = Vector6::new(0.5, 1.0, -1.0, 2.0, 0.0, 3.0);
        assert!(
            (transpose_mul(&x, &z) - from_rows(&x).transpose() * z)
                .abs()
                .max()
                < 1e-12
        );
    }

    /// The factorisation with the pivots' chain through the square roots (every
    /// `l_j,j−1²` from the scaled entry): the reference of [`cholesky_in_place`].
    fn square_root_chain_cholesky(a: &Matrix6<f64>) -> Option<Factor> {
        let mut a = *a;
        let l = &mut a.data.0;
        for j in 0..6 {
            let mut d = l[j][j];
            for lk in &l[..j] {
                d -= lk[j] * lk[j];
            }
            if !(f64::MIN_POSITIVE..=f64::MAX).contains(&d) {
                return None;
            }
            let inv = d.sqrt() * (1.0 / d);
            l[j][j] = inv;
            for i in j + 1..6 {
                let mut s = l[j][i];
                for lk in &l[..j] {
                    s -= lk[i] * lk[j];
                }
                l[j][i] = s * inv;
            }
        }
        Some(a)
    }

    /// [`cholesky_in_place`] against the square-root chain on pseudo-random positive
    /// definite blocks over ±12 decades of scale and up to 1e12 of condition (a blocked
    /// DOF's `G⁻¹` beside a free one's): the same backward error `‖L·Lᵀ − A‖ ≤ 1e-15·‖A‖`
    /// (the largest entry), and solutions within `1e-15·κ` of each other.
    #[test]
    fn cholesky_equals_the_square_root_chain() {
        let mut rand = crate::dynamics::solve::tests::uniform(4711);
        let full = |l: &Factor| {
            let mut f = *l;
            for i in 0..6 {
                f[(i, i)] = 1.0 / l[(i, i)];
                for j in i + 1..6 {
                    f[(i, j)] = 0.0;
                }
            }
            f
        };
        let (mut worst_back, mut worst_solve) = (0.0f64, 0.0f64);
        for n in 0..20000 {
            let b = Matrix6::from_fn(|_, _| rand() * 2.0 - 1.0);
            let spread = Vector6::from_fn(|_, _| 10f64.powf(12.0 * rand() - 6.0));
            let scale = 10f64.powf(24.0 * rand() - 12.0);
            let d = Matrix6::from_diagonal(&spread);
            let mut a =
                (d * b * b.transpose() * d + Matrix6::from_diagonal(&spread) * 1e-3) * scale;
            if n % 3 == 0 {
                // the upper triangle is never read
                a[(0, 5)] = f64::NAN;
            }
            let sym = a.lower_triangle() + a.lower_triangle().transpose()
                - Matrix6::from_diagonal(&a.diagonal());
            let eig = sym.symmetric_eigen().eigenvalues;
            let kappa = eig.max() / eig.min();
            let old = square_root_chain_cholesky(&a);
            let new = cholesky(&a);
            let (Some(old), Some(new)) = (old, new) else {
                // not positive definite to round-off: both fail or κ beyond 1e15
                assert!(
                    old.is_none() == new.is_none() || kappa.is_nan() || kappa >= 1e15,
                    "{n}: κ {kappa:e}"
                );
                continue;
            };
            let back = (full(&new) * full(&new).transpose() - sym).amax() / sym.amax();
            worst_back = worst_back.max(back);
            assert!(back <= 1e-15, "{n}: backward error {back:e}");
            let x0 = Vector6::from_fn(|_, _| rand() - 0.5);
            let rhs = sym * x0;
            let (mut xo, mut xn) = (rhs, rhs);
            chol_solve(&old, &mut xo);
            chol_solve(&new, &mut xn);
            let e = (xn - xo).amax() / xo.amax() / kappa;
            worst_solve = worst_solve.max(e);
            assert!(e <= 1e-15, "{n}: solutions {e:e}·κ apart (κ {kappa:e})");
        }
        println!("backward error {worst_back:e}, solutions {worst_solve:e}·κ apart");
    }

    #[test]
    fn products_equal_nalgebra() {
        let x = Matrix6::from_fn(|i, j| (i as f64 - j as f64) * 0.3 + 1.0);
        let n = spd();
        let mut a = Matrix6::identity();
        add_gram(&mut a, &rows_of(&x));
        assert_eq!(a, a.transpose());
        assert!((a - (Matrix6::identity() + x.transpose() * x)).abs().max() < 1e-12);
        let mut c = Matrix6::zeros();
        add_congruence(&mut c, &x, &n);
        assert!((c - x * n * x.transpose()).abs().max() < 1e-9);
        // a body's inverse mass: inverse masses (one locked: 0), then a full inverse inertia
        let mb = MassBlocks {
            linear: nalgebra::Vector3::new(0.5, 0.0, 2.0),
            angular: spd().fixed_view::<3, 3>(1, 1).into_owned(),
        };
        let m = mb.matrix();
        assert_eq!(m[(0, 0)], 0.5);
        assert_eq!(m[(2, 2)], 2.0);
        assert_eq!(m[(4, 3)], spd()[(2, 1)]);
        assert_eq!(m.fixed_view::<3, 3>(0, 3), nalgebra::Matrix3::zeros());
        // joints' Jacobians: rotation rates independent of the linear velocities
        let jacobian = |mut b: Matrix6<f64>| {
            b.fixed_view_mut::<3, 3>(3, 0).fill(0.0);
            assert!(is_jacobian(&b));
            b
        };
        assert!(!is_jacobian(&x));
        let xj = jacobian(x);
        let mut c = Matrix6::identity();
        add_congruence_inv_mass(&mut c, &xj, &mb);
        let expected = Matrix6::identity() + xj * m * xj.transpose();
        // on and below the diagonal (the upper triangle is never read)
        assert!((c - expected).lower_triangle().abs().max() < 1e-12 * expected.abs().max());
        let y = jacobian(Matrix6::from_fn(|i, j| {
            ((i * 5 + j) % 7) as f64 * 0.2 - 0.6
        }));
        // columns of Y·M⁻¹·Xᵀ: the rows of X·M⁻¹·Yᵀ
        let e = product_t(&times_inv_mass(&y, &mb), &xj);
        let expected = xj * m * y.transpose();
        assert!(
            (Matrix6::from_fn(|r, c| e[r][c]) - expected).abs().max()
                < 1e-12 * expected.abs().max()
        );
        let v = Vector6::new(1.0, -2.0, 0.5, 3.0, -1.0, 0.25);
        assert!((inv_mass_mul(&mb, &v) - m * v).abs().max() < 1e-12 * (m * v).abs().max());
        assert!((rows_mul(&rows_of(&x), &v) - x * v).abs().max() < 1e-12);
        let mut a = Matrix6::identity();
        sub_lower_gram(&mut a, &rows_of(&x));
        let expected = Matrix6::identity() - x.transpose() * x;
        assert!((a - expected).lower_triangle().abs().max() < 1e-12 * expected.abs().max());
        assert!(cholesky(&-spd()).is_none());
    }

    /// The congruence from the Jacobians' 3×3 blocks against the 6×6 product, both sides,
    /// on pseudo-random Jacobians and masses (one translation locked) over 12 decades.
    #[test]
    fn jacobian_congruence_equals_the_dense_product() {
        use crate::dynamics::solve::tests::{random_jacobians, random_mass, uniform};
        let mut rand = uniform(77);
        for n in 0..500 {
            let jac = random_jacobians(&mut rand);
            let other = random_jacobians(&mut rand);
            let mb = random_mass(&mut rand, n);
            for s in 0..2 {
                let start = Matrix6::from_fn(|i, j| (i + 7 * j) as f64);
                let mut fast = start;
                add_jacobian_congruence(&mut fast, &jac, s, &mb);
                let j = jac.matrix(s);
                let expected = start + j * mb.matrix() * j.transpose();
                let mut dense = start;
                add_congruence_inv_mass(&mut dense, &j, &mb);
                for c in 0..6 {
                    for r in c..6 {
                        let tol = 1e-12 * expected.amax();
                        assert!(
                            (fast[(r, c)] - expected[(r, c)]).abs() <= tol,
                            "{n} {s} ({r}, {c})"
                        );
                        assert!((fast[(r, c)] - dense[(r, c)]).abs() <= tol);
                    }
                }
            }
            // a link's products: both congruences as above, and the coupling E by rows
            // with a second joint (`other`), for every pair of sides; E alone too
            for (sc, sp) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let start = Matrix6::from_fn(|i, j| (i + 7 * j) as f64);
                let (mut d_c, mut d_p, mut e) = (start, start * 2.0, [[7.0; 6]; 6]);
                let mut e_alone = [[7.0; 6]; 6];
                let (dc, dp) = (Some(&mut d_c), Some(&mut d_p));
                add_link_products(dc, dp, &mut e, &jac, sc, &other, sp, &mb);
                add_link_products(None, None, &mut e_alone, &jac, sc, &other, sp, &mb);
                assert_eq!(e, e_alone);
                let (jc, jp, m) = (jac.matrix(sc), other.matrix(sp), mb.matrix());
                let exp_c = start + jc * m * jc.transpose();
                let exp_p = start * 2.0 + jp * m * jp.transpose();
                let exp_e = jc * m * jp.transpose();
                let tol = 1e-12 * exp_c.amax().max(exp_p.amax()).max(exp_e.amax());
                for c in 0..6 {
                    for r in 0..6 {
                        if r >= c {
                            assert!((d_c[(r, c)] - exp_c[(r, c)]).abs() <= tol, "{n} c");
                            assert!((d_p[(r, c)] - exp_p[(r, c)]).abs() <= tol, "{n} p");
                        }
                        assert!((e[r][c] - exp_e[(r, c)]).abs() <= tol, "{n} e ({r}, {c})");
                    }
                }
            }
        }
    }

    /// [`add_two_sided_congruence`] against the sides one by one
    /// ([`add_jacobian_congruence`] twice, the old arithmetic), on pseudo-random Jacobians
    /// and masses over 12 decades (one translation locked in some): within 1e-14 of the
    /// largest entry of the two sides' terms, entry by entry on and below the diagonal (the
    /// sums of two positive semi-definite terms: no cancellation beyond their size), and
    /// against the dense 6×6 products within 1e-12.
    #[test]
    fn two_sided_congruence_equals_the_sides_one_by_one() {
        use crate::dynamics::solve::tests::{random_jacobians, random_mass, uniform};
        let mut rand = uniform(4242);
        let mut worst = 0.0f64;
        for n in 0..20000 {
            let jac = random_jacobians(&mut rand);
            let (m1, m2) = (random_mass(&mut rand, n), random_mass(&mut rand, n / 3));
            let start = Matrix6::from_fn(|i, j| (i + 7 * j) as f64 * rand());
            let mut fast = start;
            add_two_sided_congruence(&mut fast, &jac, &m1, &m2);
            let mut old = start;
            add_jacobian_congruence(&mut old, &jac, 0, &m1);
            add_jacobian_congruence(&mut old, &jac, 1, &m2);
            let (j1, j2) = (jac.matrix(0), jac.matrix(1));
            let (t1, t2) = (
                j1 * m1.matrix() * j1.transpose(),
                j2 * m2.matrix() * j2.transpose(),
            );
            let scale = t1.amax().max(t2.amax()).max(start.amax());
            let dense = start + t1 + t2;
            for c in 0..6 {
                for r in c..6 {
                    let e = (fast[(r, c)] - old[(r, c)]).abs() / scale;
                    worst = worst.max(e);
                    assert!(e <= 1e-14, "{n} ({r}, {c}): {e:e}");
                    assert!((fast[(r, c)] - dense[(r, c)]).abs() <= 1e-12 * scale);
                }
            }
        }
        println!("two-sided congruence: {worst:e} of the largest term from the sides' sums");
    }

    #[test]
    fn diagonal_inverse_equals_general() {
        let g = Matrix6::from_diagonal(&Vector6::new(1.0, 2.0, 0.0, 4.0, 5.0, 6.0));
        let mut fast = Matrix6::zeros();
        assert_eq!(regularised_inverse(&g, 1e-12, &mut fast), Some(true));
        let general = (g + Matrix6::identity() * 1e-12).try_inverse().unwrap();
        assert!(
            ((fast - general).component_div(&general.map(|v| v.abs().max(1.0))))
                .abs()
                .max()
                < 1e-12
        );
        // coupled: the general inverse, said not diagonal
        let mut coupled = g;
        coupled[(0, 1)] = 0.5;
        coupled[(1, 0)] = 0.5;
        assert_eq!(regularised_inverse(&coupled, 1e-12, &mut fast), Some(false));
        let regularised = coupled + Matrix6::identity() * 1e-12;
        assert!((fast * regularised - Matrix6::identity()).abs().max() < 1e-9);
        // ε cancelled by a negative tangent: singular
        let cancelled = Matrix6::from_diagonal(&Vector6::new(1.0, -1e-12, 1.0, 1.0, 1.0, 1.0));
        assert_eq!(regularised_inverse(&cancelled, 1e-12, &mut fast), None);
    }

    #[test]
    fn is_diagonal_reads_every_entry_off_the_diagonal_and_only_those() {
        let mut m = Matrix6::from_diagonal(&Vector6::new(1.0, f64::NAN, -3.0, 0.0, 5.0, 6.0));
        assert!(is_diagonal(&m));
        m[(2, 4)] = -0.0;
        assert!(is_diagonal(&m), "−0 is zero");
        for r in 0..6 {
            for c in 0..6 {
                for v in [1e-320, f64::NAN, -2.0] {
                    let mut k = m;
                    k[(r, c)] = v;
                    assert_eq!(is_diagonal(&k), r == c, "({r}, {c}) = {v}");
                }
            }
        }
    }
}
