//! Dense 6×6 kernels of the block eliminations: Cholesky factor, triangular solves and the
//! symmetric products `XᵀX`, written out so that nothing allocates and nothing is inverted
//! where a factor will do.

use nalgebra::{Matrix6, Vector6};

// The kernels work on the column-major arrays behind `Matrix6` (`m.data.0[column][row]`)
// with constant loop bounds, so that nothing is bounds-checked and the compiler can unroll.

/// A lower Cholesky factor `L` of a 6×6 block (`A = L·Lᵀ`), stored with the **reciprocals**
/// of its diagonal (`1/l_ii` in place of `l_ii`): every triangular solve multiplies instead
/// of dividing.
pub(crate) type Factor = Matrix6<f64>;

/// Lower Cholesky factor `L` of a symmetric positive-definite `a` (`a = L·Lᵀ`), reading the
/// lower triangle only, stored as a [`Factor`]. `None` when a pivot is not positive (the
/// matrix is not positive definite, or not finite).
#[cfg(test)]
pub(crate) fn cholesky(a: &Matrix6<f64>) -> Option<Factor> {
    let mut l = *a;
    cholesky_in_place(&mut l).then_some(l)
}

/// [`cholesky`] in place: `a` becomes its [`Factor`] (its upper triangle is left as it
/// was and never read). `false` when a pivot is not positive.
#[inline]
pub(crate) fn cholesky_in_place(a: &mut Matrix6<f64>) -> bool {
    // column j of L overwrites column j of a (l[j][i] is entry (i, j)); entry (i, j) of a is
    // read once, before it is overwritten
    let l = &mut a.data.0;
    for j in 0..6 {
        // d = a_jj − Σ_k<j l_jk²
        let mut d = l[j][j];
        // constant bounds with a mask: the compiler unrolls the whole 6×6 factorisation
        for k in 0..6 {
            if k < j {
                d -= l[k][j] * l[k][j];
            }
        }
        if !(d > 0.0) || !d.is_finite() {
            return false;
        }
        let inv = 1.0 / d.sqrt();
        l[j][j] = inv;
        for i in 0..6 {
            if i > j {
                // l_ij = (a_ij − Σ_k<j l_ik·l_jk) / l_jj
                let mut s = l[j][i];
                for k in 0..6 {
                    if k < j {
                        s -= l[k][i] * l[k][j];
                    }
                }
                l[j][i] = s * inv;
            }
        }
    }
    true
}

/// `x ← L⁻¹·x` for a factor `L`.
#[inline]
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
#[inline]
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
#[inline]
pub(crate) fn chol_solve(l: &Factor, x: &mut Vector6<f64>) {
    forward(l, x);
    backward(l, x);
}

/// A 6×6 block stored by rows (`x[row][column]`): the layout of the right-hand sides of
/// [`forward_rows`], whose every operation is then a 6-wide row update.
pub(crate) type Rows = [[f64; 6]; 6];

/// The rows of `B`.
#[inline]
pub(crate) fn rows_of(b: &Matrix6<f64>) -> Rows {
    let b = &b.data.0;
    std::array::from_fn(|r| std::array::from_fn(|c| b[c][r]))
}

/// The rows of `Bᵀ` (the columns of `B`).
#[inline]
pub(crate) fn rows_of_transpose(b: &Matrix6<f64>) -> Rows {
    b.data.0
}

/// `X ← L⁻¹·X` for a factor `L` and `X` stored by rows (six right-hand sides at once):
/// once row `k` is final, its multiples are removed from the rows below.
#[inline]
pub(crate) fn forward_rows(l: &Factor, x: &mut Rows) {
    let l = &l.data.0;
    for k in 0..6 {
        let d = l[k][k];
        let xk = x[k].map(|v| v * d);
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
#[inline]
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

/// `Xᵀ·z = Σ_i z_i·x_i` for `X` stored by rows.
#[inline]
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
#[inline]
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

/// `a += B·M⁻¹·Bᵀ` for a body's generalised inverse mass `M⁻¹` (three inverse masses on the
/// diagonal of its first block, the 3×3 world inverse inertia `I⁻¹` in its last, zero
/// elsewhere, as [`super::SolverBody::inv_mass`] is built): with `B = [B_v B_ω]`,
///
/// ```text
/// B·M⁻¹·Bᵀ = Σ_k m⁻¹_k·b_k·b_kᵀ + (B_ω·I⁻¹)·B_ωᵀ      (b_k: column k of B_v)
/// ```
///
/// 180 products instead of the 430 of [`add_congruence`] (a leaf body of a tree, every
/// pendulum's body). Only the diagonal of the first block and the last block of `m` are
/// read. The result is exactly symmetric.
#[inline]
pub(crate) fn add_congruence_inv_mass(a: &mut Matrix6<f64>, b: &Matrix6<f64>, m: &Matrix6<f64>) {
    let bd = &b.data.0; // bd[column][row]
    let md = &m.data.0;
    // t = B_ω·I⁻¹ (6×3), by columns
    let mut t = [[0.0; 6]; 3];
    for (l, tl) in t.iter_mut().enumerate() {
        for k in 0..3 {
            let i_kl = md[3 + l][3 + k];
            for r in 0..6 {
                tl[r] += bd[3 + k][r] * i_kl;
            }
        }
    }
    let ad = &mut a.data.0;
    for c in 0..6 {
        for r in 0..6 {
            if r <= c {
                let mut s = 0.0;
                for k in 0..3 {
                    s += md[k][k] * bd[k][r] * bd[k][c];
                }
                for l in 0..3 {
                    s += t[l][r] * bd[3 + l][c];
                }
                ad[c][r] += s;
                if r != c {
                    ad[r][c] += s;
                }
            }
        }
    }
}

/// Inverse of the regularised `G + ε·I` (symmetrised) into `inv`, by its diagonal when `G`
/// is diagonal (the common case: no coupled stops, no cross terms in the law's tangent).
/// `false` when it is singular.
#[inline]
pub(crate) fn regularised_inverse(g: &Matrix6<f64>, eps: f64, inv: &mut Matrix6<f64>) -> bool {
    let gd = &g.data.0;
    let mut diagonal = true;
    for (c, col) in gd.iter().enumerate() {
        for (r, v) in col.iter().enumerate() {
            diagonal &= r == c || *v == 0.0;
        }
    }
    if diagonal {
        *inv = Matrix6::zeros();
        for i in 0..6 {
            let d = gd[i][i] + eps;
            if d == 0.0 || !d.is_finite() {
                return false;
            }
            inv.data.0[i][i] = 1.0 / d;
        }
        return true;
    }
    match (g + Matrix6::identity() * eps).try_inverse() {
        Some(full) => {
            *inv = 0.5 * (full + full.transpose());
            true
        }
        None => false,
    }
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
        let mut m = Matrix6::zeros();
        m[(0, 0)] = 0.5;
        m[(2, 2)] = 2.0;
        m.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&spd().fixed_view::<3, 3>(1, 1));
        let mut c = Matrix6::identity();
        add_congruence_inv_mass(&mut c, &x, &m);
        assert_eq!(c, c.transpose());
        let expected = Matrix6::identity() + x * m * x.transpose();
        assert!((c - expected).abs().max() < 1e-12 * expected.abs().max());
        assert!(cholesky(&-spd()).is_none());
    }

    #[test]
    fn diagonal_inverse_equals_general() {
        let g = Matrix6::from_diagonal(&Vector6::new(1.0, 2.0, 0.0, 4.0, 5.0, 6.0));
        let mut fast = Matrix6::zeros();
        assert!(regularised_inverse(&g, 1e-12, &mut fast));
        let general = (g + Matrix6::identity() * 1e-12).try_inverse().unwrap();
        assert!(
            ((fast - general).component_div(&general.map(|v| v.abs().max(1.0))))
                .abs()
                .max()
                < 1e-12
        );
    }
}
