//! The positive (restoring) part of a symmetric 3×3 stiffness, which the solve makes
//! implicit on a body ([`super::SolverBody::add_implicit_rotational_stiffness`]).

use nalgebra::{Matrix3, Vector3};

/// The positive part `Σ max(λ, 0)·v·vᵀ` of a symmetric 3×3 matrix (`None` when it is zero),
/// from its eigenvalues in closed form (Smith 1961): a semi-definite matrix (a chain link
/// under tension; up to 1e-13 of its trace) is its own positive part; with one negative eigenvalue `λ₀` the part is
/// `K − λ₀·v₀·v₀ᵀ`, with two it is `λ₂·v₂·v₂ᵀ`, each eigenvector being the cross product
/// of two rows of `K − λ·I`.
///
/// Inlined into its caller (the closed form with its arc-cosine apart, cold): a 3×3 returned
/// through memory is written as scalars and read back as pairs, a stalled store forwarding
/// on the body's chain.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn positive_part(k: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let (a, b, c) = (k[(0, 0)], k[(1, 1)], k[(2, 2)]);
    let (d, e, f) = (k[(0, 1)], k[(1, 2)], k[(0, 2)]);
    // semi-definite already up to round-off: its own positive part, without the eigenvalues.
    // The common case is a link hanging from its joints, `K = α·(|r|²·I − r·rᵀ)`, whose
    // eigenvalue along `r` is zero and comes out of the products at ±1e-16·tr K: an exact
    // test (Sylvester's minors ≥ 0) failed on 79 000 of 80 000 pendulum substeps and paid for
    // the eigenvalues. `K + δ·I ≻ 0` with `δ = 1e-13·tr K` (its LDLᵀ pivots all positive)
    // proves `λ_min(K) > −δ`; the part of `K` below zero that is then kept is below δ.
    let t = a + b + c;
    if t > 0.0 {
        let delta = 1e-13 * t;
        let d1 = a + delta;
        if d1 > 0.0 {
            let (l21, l31) = (d / d1, f / d1);
            let d2 = b + delta - l21 * d;
            if d2 > 0.0 {
                let l32 = (e - l31 * d) / d2;
                let d3 = c + delta - l31 * f - l32 * l32 * d2;
                if d3 > 0.0 {
                    return Some(*k);
                }
            }
        }
    }
    // one eigenvalue of sign opposite to the other two (det ≠ 0, not all negative): the
    // lone one, by a bracketed Newton iteration on the characteristic polynomial, without
    // the arc-cosine and cosines of the closed form
    if let Some(part) = lone_eigenvalue_part::<true>(k) {
        return part;
    }
    trigonometric_positive_part(k)
}

/// [`positive_part`] from the three eigenvalues in closed form (Smith 1961), where neither
/// the screen nor the lone eigenvalue decided: a zero determinant, a multiple of the
/// identity, round-off against the signs.
#[cold]
#[inline(never)]
fn trigonometric_positive_part(k: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let (a, b, c) = (k[(0, 0)], k[(1, 1)], k[(2, 2)]);
    let (d, e, f) = (k[(0, 1)], k[(1, 2)], k[(0, 2)]);
    let p1 = d * d + e * e + f * f;
    let q = (a + b + c) / 3.0;
    let p2 = (a - q).powi(2) + (b - q).powi(2) + (c - q).powi(2) + 2.0 * p1;
    if !(p2 > 0.0) {
        // a multiple of the identity
        return (q > 0.0).then_some(*k);
    }
    let p = (p2 / 6.0).sqrt();
    let r = ((k - Matrix3::identity() * q) / p).determinant() / 2.0;
    let phi = r.clamp(-1.0, 1.0).acos() / 3.0;
    let l2 = q + 2.0 * p * phi.cos();
    let l0 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    let l1 = 3.0 * q - l0 - l2;
    if l2 <= 0.0 {
        return None;
    }
    if l0 >= 0.0 {
        return Some(*k);
    }
    let simple = if l1 >= 0.0 {
        eigenvector(k, l0).map(|v| k - v * v.transpose() * l0)
    } else {
        eigenvector(k, l2).map(|v| v * v.transpose() * l2)
    };
    simple.or_else(|| {
        // repeated eigenvalues: the general decomposition
        let eig = k.symmetric_eigen();
        let pos = eig.eigenvalues.map(|l| l.max(0.0));
        Some(eig.eigenvectors * Matrix3::from_diagonal(&pos) * eig.eigenvectors.transpose())
    })
}

/// The unit eigenvector of a simple eigenvalue `l` of the symmetric `k`: the largest cross
/// product of two rows of `K − l·I` (`None` when all vanish: `l` is repeated).
fn eigenvector(k: &Matrix3<f64>, l: f64) -> Option<Vector3<f64>> {
    eigen_direction(k, l).map(|(w, _)| w.normalize())
}

/// `l·v·vᵀ` for the unit eigenvector `v` of [`eigenvector`], as `(l/|w|²)·w·wᵀ` from the
/// cross product `w` itself (`v = w/|w|`): one division and no square root, where
/// normalising `w` took both, one after the other on the iteration's critical path; the
/// result exactly symmetric (its lower triangle mirrored).
#[cfg_attr(not(debug_assertions), inline(always))]
fn eigen_projection(k: &Matrix3<f64>, l: f64) -> Option<Matrix3<f64>> {
    let (w, n2) = eigen_direction(k, l)?;
    let sw = w * (l / n2);
    let e = |i: usize, j: usize| sw[i] * w[j];
    let (m10, m20, m21) = (e(1, 0), e(2, 0), e(2, 1));
    Some(Matrix3::new(
        e(0, 0),
        m10,
        m20,
        m10,
        e(1, 1),
        m21,
        m20,
        m21,
        e(2, 2),
    ))
}

/// The largest cross product `w` of two rows of `K − l·I` and `|w|²` (`None` when all
/// vanish).
#[cfg_attr(not(debug_assertions), inline(always))]
fn eigen_direction(k: &Matrix3<f64>, l: f64) -> Option<(Vector3<f64>, f64)> {
    let m = k - Matrix3::identity() * l;
    let (r0, r1, r2) = (
        m.row(0).transpose(),
        m.row(1).transpose(),
        m.row(2).transpose(),
    );
    // the largest of the three (the last of equal ones, as `Iterator::max_by`), by a loop:
    // the iterator's `reduce` was compiled out of line, without the substep's AVX2, once
    // the substep's function grew
    let crosses = [r0.cross(&r1), r0.cross(&r2), r1.cross(&r2)];
    let mut best = (crosses[0], crosses[0].norm_squared());
    for w in &crosses[1..] {
        let n2 = w.norm_squared();
        if best.1.total_cmp(&n2) != std::cmp::Ordering::Greater {
            best = (*w, n2);
        }
    }
    (best.1 > 0.0).then_some(best)
}

/// The positive part of an indefinite symmetric 3×3 whose determinant is not zero, from
/// its lone eigenvalue (the one whose sign the other two do not share), or `None` when
/// that does not apply (a zero determinant, all three negative, no convergence): the
/// caller's closed form then decides.
///
/// With `p(λ) = det(K − λ·I) = −λ³ + c₂·λ² − c₁·λ + c₀` (`c₂ = tr K`, `c₁` the sum of the
/// principal 2×2 minors, `c₀ = det K`) and eigenvalues `λ₀ ≤ λ₁ ≤ λ₂`:
///
/// ```text
/// c₀ < 0, c₂ > 0:  λ₀ < 0 < λ₁ ≤ λ₂   part = K − λ₀·v₀·v₀ᵀ,   λ₀ the only root in [g⁻, 0]
/// c₀ > 0:          λ₀ ≤ λ₁ < 0 < λ₂   part = λ₂·v₂·v₂ᵀ,        λ₂ the only root in [0, g⁺]
/// ```
///
/// (`g∓` the Gershgorin bounds; `c₀ > 0` with three positive eigenvalues is a definite
/// matrix, which the caller has already returned). The root is found by Halley steps from
/// 0, kept inside the bracket and halving it when a step leaves it; the lone eigenvalue is
/// simple, so Newton's steps converge quadratically and Halley's
/// (`λ ← λ − 2·p·p′/(2·p′² − p·p″)`, taken here) cubically, in 2–4 steps.
///
/// The iteration stops when a step is below `4ε·scale`, or (`RESIDUAL`) before the step
/// whose Newton size `|p/p′|` already is, tested as `|p| ≤ 4ε·scale·|p′|` (a product, no
/// division): the last Halley step, which only confirmed the root (its division on the
/// critical path), is not taken, and the root kept is within `4ε·scale` of the one it
/// would have given (the test `residual_stop_equals_the_step_stop` holds both parts to
/// 1e-14 of the matrix). `RESIDUAL = false` (tests) is the form without that stop.
#[cfg_attr(not(debug_assertions), inline(always))]
fn lone_eigenvalue_part<const RESIDUAL: bool>(k: &Matrix3<f64>) -> Option<Option<Matrix3<f64>>> {
    let (a, b, c) = (k[(0, 0)], k[(1, 1)], k[(2, 2)]);
    let (d, e, f) = (k[(0, 1)], k[(1, 2)], k[(0, 2)]);
    let c2 = a + b + c;
    let c1 = a * b + b * c + a * c - d * d - e * e - f * f;
    let c0 = a * (b * c - e * e) - d * (d * c - e * f) + f * (d * e - b * f);
    let (lower, upper) = (
        (a - d.abs() - f.abs())
            .min(b - d.abs() - e.abs())
            .min(c - f.abs() - e.abs()),
        (a + d.abs() + f.abs())
            .max(b + d.abs() + e.abs())
            .max(c + f.abs() + e.abs()),
    );
    // the bracket [lo, hi] with p(lo) and p(hi) of opposite signs
    let (mut lo, mut hi, lowest) = if c0 < 0.0 && c2 > 0.0 {
        (lower, 0.0, true)
    } else if c0 > 0.0 {
        (0.0, upper, false)
    } else {
        return None;
    };
    if !(lo < hi) || !lo.is_finite() || !hi.is_finite() {
        return None;
    }
    let poly = |l: f64| ((-l + c2) * l - c1) * l + c0;
    let slope = |l: f64| (-3.0 * l + 2.0 * c2) * l - c1;
    let p_lo = poly(lo);
    if p_lo == 0.0 {
        return None;
    }
    let scale = upper.abs().max(lower.abs());
    let mut l = 0.0;
    for _ in 0..100 {
        let p = poly(l);
        if p == 0.0 {
            break;
        }
        // keep the bracket: the root lies on the side where p changes sign
        let at_lo = (p > 0.0) == (p_lo > 0.0);
        if at_lo {
            lo = l;
        } else {
            hi = l;
        }
        // Halley's step (cubic convergence: ~2 steps fewer than Newton's from 0, each with
        // one division, the latency the iteration is bound by)
        let dp = slope(l);
        // l is an end of the bracket: the Newton step `−p/p′` into it (towards hi from lo,
        // towards lo from hi) and below 4ε·scale means the nearest root, a simple one, is the
        // bracketed one (`p′/p = Σ 1/(l − λ_i)`: its sign is that of the nearest root's term);
        // out of it, the nearest root is another one (a root just beyond 0)
        let inward = ((p > 0.0) == (dp > 0.0)) != at_lo;
        if RESIDUAL && inward && p.abs() <= 4.0 * f64::EPSILON * scale * dp.abs() {
            break;
        }
        let ddp = -6.0 * l + 2.0 * c2;
        let mut next = l - 2.0 * p * dp / (2.0 * dp * dp - p * ddp);
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        let step = (next - l).abs();
        l = next;
        if step <= 4.0 * f64::EPSILON * scale {
            break;
        }
        if hi - lo <= 4.0 * f64::EPSILON * scale {
            l = 0.5 * (lo + hi);
            break;
        }
    }
    // the other two eigenvalues, of sum c₂ − l and product c₀/l > 0, share a sign that is
    // not l's (else the signs were not as the determinant said: round-off, or a definite
    // matrix)
    if (c2 - l > 0.0) != lowest {
        return None;
    }
    let part = eigen_projection(k, l)?;
    Some(Some(if lowest { k - part } else { part }))
}

/// `count` pseudo-random symmetric 3×3 matrices from `seed` (a 64-bit LCG): random
/// rotations of diagonals of every sign pattern, scaled over twelve decades, with one
/// eigenvalue small beside the others in half of them (the common case). The tests'
/// shared fixture.
#[cfg(test)]
fn random_symmetric(seed: u64, count: usize) -> Vec<Matrix3<f64>> {
    let mut seed = seed;
    let mut rand = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    (0..count)
        .map(|n| {
            let q = nalgebra::UnitQuaternion::from_scaled_axis(nalgebra::Vector3::new(
                3.0 * rand(),
                3.0 * rand(),
                3.0 * rand(),
            ));
            let small = if n % 2 == 0 { 1e-6 * rand() } else { rand() };
            let l = nalgebra::Vector3::new(small, rand(), rand()) * 10f64.powf(12.0 * rand());
            let r = q.to_rotation_matrix().into_inner();
            r * Matrix3::from_diagonal(&l) * r.transpose()
        })
        .collect()
}

/// The iteration stopped on its residual against the one stopped on its step, on the
/// indefinite matrices of `positive_part_equals_the_eigen_decomposition`'s kind: the same
/// part to 1e-14 of the matrix.
#[cfg(test)]
#[test]
fn residual_stop_equals_the_step_stop() {
    let (mut worst, mut compared) = (0.0f64, 0);
    for k in random_symmetric(4242, 20000) {
        let (new, old) = (
            lone_eigenvalue_part::<true>(&k),
            lone_eigenvalue_part::<false>(&k),
        );
        assert_eq!(new.is_some(), old.is_some(), "{k}");
        if let (Some(new), Some(old)) = (new, old) {
            let zero = Matrix3::zeros;
            let e = (new.unwrap_or_else(zero) - old.unwrap_or_else(zero)).amax() / k.amax();
            worst = worst.max(e);
            compared += 1;
            assert!(e <= 1e-14, "{k}: {e:e}");
        }
    }
    assert!(compared > 10000);
    println!("worst {worst:e} of the matrix over {compared}");
}

#[cfg(test)]
#[test]
fn positive_part_equals_the_eigen_decomposition() {
    let cases = [
        Matrix3::new(2.0, 0.3, -0.1, 0.3, 1.0, 0.2, -0.1, 0.2, 0.5),
        Matrix3::new(1.0, 2.0, 0.0, 2.0, 1.0, 0.5, 0.0, 0.5, -0.3),
        Matrix3::new(-1.0, 0.2, 0.0, 0.2, -2.0, 0.1, 0.0, 0.1, 0.4),
        Matrix3::new(-1.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, -0.5),
        Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0),
        // a rod under tension: f ∥ r, eigenvalues (λ|r|², λ|r|², 0)
        {
            let r = nalgebra::Vector3::new(0.05, -0.02, 0.01);
            Matrix3::identity() * r.norm_squared() * 3.0 - r * r.transpose() * 3.0
        },
    ];
    // and 2000 pseudo-random ones (`random_symmetric`)
    let more = random_symmetric(12345, 2000);
    for k in cases.into_iter().chain(more) {
        let eig = k.symmetric_eigen();
        let pos = eig.eigenvalues.map(|l: f64| l.max(0.0));
        let expected =
            eig.eigenvectors * Matrix3::from_diagonal(&pos) * eig.eigenvectors.transpose();
        let got = positive_part(&k).unwrap_or_else(Matrix3::zeros);
        assert!(
            (got - expected).amax() < 1e-12 * k.amax(),
            "{k} → {got} vs {expected}"
        );
    }
}
