//! Dense 6×6 kernels of the block eliminations: Cholesky factor, triangular solves and the
//! symmetric products `XᵀX`, written out so that nothing allocates and nothing is inverted
//! where a factor will do.

use nalgebra::{Matrix6, Vector6};

/// Lower Cholesky factor `L` of a symmetric positive-definite `a` (`a = L·Lᵀ`), reading the
/// lower triangle only. `None` when a pivot is not positive (the matrix is not positive
/// definite, or not finite).
#[inline]
pub(crate) fn cholesky(a: &Matrix6<f64>) -> Option<Matrix6<f64>> {
    let mut l = Matrix6::zeros();
    for j in 0..6 {
        // d = a_jj − Σ_k<j l_jk²
        let mut d = a[(j, j)];
        for k in 0..j {
            d -= l[(j, k)] * l[(j, k)];
        }
        if !(d > 0.0) || !d.is_finite() {
            return None;
        }
        let ljj = d.sqrt();
        l[(j, j)] = ljj;
        let inv = 1.0 / ljj;
        for i in j + 1..6 {
            // l_ij = (a_ij − Σ_k<j l_ik·l_jk) / l_jj
            let mut s = a[(i, j)];
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = s * inv;
        }
    }
    Some(l)
}

/// `x ← L⁻¹·x` for a lower-triangular `L`.
#[inline]
pub(crate) fn forward(l: &Matrix6<f64>, x: &mut Vector6<f64>) {
    for i in 0..6 {
        let mut s = x[i];
        for k in 0..i {
            s -= l[(i, k)] * x[k];
        }
        x[i] = s / l[(i, i)];
    }
}

/// `x ← L⁻ᵀ·x` for a lower-triangular `L`.
#[inline]
pub(crate) fn backward(l: &Matrix6<f64>, x: &mut Vector6<f64>) {
    for i in (0..6).rev() {
        let mut s = x[i];
        for k in i + 1..6 {
            s -= l[(k, i)] * x[k];
        }
        x[i] = s / l[(i, i)];
    }
}

/// `x ← (L·Lᵀ)⁻¹·x`.
#[inline]
pub(crate) fn chol_solve(l: &Matrix6<f64>, x: &mut Vector6<f64>) {
    forward(l, x);
    backward(l, x);
}

/// `L⁻¹·B` for a lower-triangular `L` (six right-hand sides at once).
#[inline]
pub(crate) fn forward_mat(l: &Matrix6<f64>, b: &Matrix6<f64>) -> Matrix6<f64> {
    let mut x = *b;
    for c in 0..6 {
        for i in 0..6 {
            let mut s = x[(i, c)];
            for k in 0..i {
                s -= l[(i, k)] * x[(k, c)];
            }
            x[(i, c)] = s / l[(i, i)];
        }
    }
    x
}

/// `a += Xᵀ·X` (symmetric: the upper triangle is computed and mirrored).
#[inline]
pub(crate) fn add_gram(a: &mut Matrix6<f64>, x: &Matrix6<f64>) {
    for c in 0..6 {
        for r in 0..=c {
            let s = x.column(r).dot(&x.column(c));
            a[(r, c)] += s;
            if r != c {
                a[(c, r)] += s;
            }
        }
    }
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

/// Inverse of the regularised `G + ε·I` (symmetrised), by its diagonal when `G` is
/// diagonal (the common case: no coupled stops, no cross terms in the law's tangent).
#[inline]
pub(crate) fn regularised_inverse(g: &Matrix6<f64>, eps: f64) -> Option<Matrix6<f64>> {
    let mut diagonal = true;
    'outer: for c in 0..6 {
        for r in 0..6 {
            if r != c && g[(r, c)] != 0.0 {
                diagonal = false;
                break 'outer;
            }
        }
    }
    if diagonal {
        let mut inv = Matrix6::zeros();
        for i in 0..6 {
            let d = g[(i, i)] + eps;
            if d == 0.0 || !d.is_finite() {
                return None;
            }
            inv[(i, i)] = 1.0 / d;
        }
        return Some(inv);
    }
    let inv = (g + Matrix6::identity() * eps).try_inverse()?;
    Some(0.5 * (inv + inv.transpose()))
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
        assert!((l * l.transpose() - a).abs().max() < 1e-12 * a.abs().max());
        let x0 = Vector6::new(1.0, -2.0, 3.0, 0.5, -0.25, 4.0);
        let mut x = a * x0;
        chol_solve(&l, &mut x);
        assert!((x - x0).abs().max() < 1e-10);
        let m = Matrix6::from_fn(|i, j| (i + 2 * j) as f64);
        assert!((l * forward_mat(&l, &m) - m).abs().max() < 1e-10);
    }

    #[test]
    fn products_equal_nalgebra() {
        let x = Matrix6::from_fn(|i, j| (i as f64 - j as f64) * 0.3 + 1.0);
        let n = spd();
        let mut a = Matrix6::identity();
        add_gram(&mut a, &x);
        assert!((a - (Matrix6::identity() + x.transpose() * x)).abs().max() < 1e-12);
        let mut c = Matrix6::zeros();
        add_congruence(&mut c, &x, &n);
        assert!((c - x * n * x.transpose()).abs().max() < 1e-9);
        assert!(cholesky(&-spd()).is_none());
    }

    #[test]
    fn diagonal_inverse_equals_general() {
        let g = Matrix6::from_diagonal(&Vector6::new(1.0, 2.0, 0.0, 4.0, 5.0, 6.0));
        let fast = regularised_inverse(&g, 1e-12).unwrap();
        let general = (g + Matrix6::identity() * 1e-12).try_inverse().unwrap();
        assert!(
            ((fast - general).component_div(&general.map(|v| v.abs().max(1.0))))
                .abs()
                .max()
                < 1e-12
        );
    }
}
