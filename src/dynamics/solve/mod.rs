//! The linearised implicit penalty update, solved for all joints at once.
//!
//! # Scheme
//! rapier advances a substep `h` with semi-implicit Euler: `v⁺ = v + Δv`,
//! `x⁺ = x + h·v⁺`. At the start of the substep we give every joint a generalised impulse
//! `P` (6 components in its working frame, `P = −h·F_applied`) so that
//!
//! ```text
//! P = h·Q − G·(J·Δv),      G = h·(h·K_t/β + C_t),      Q = −F(q, q̇),    β = 3
//! ```
//!
//! where `F` is the law's force at the current state, `K_t`, `C_t` its tangent stiffness and
//! damping, and `J·Δv` the change of the joint's relative rates over the substep caused by
//! all impulses and by gravity/user forces. For a linear undamped spring on one body this is
//! the update `v⁺ = v − h·ω̃²·x`, `x⁺ = x + h·v⁺` with `ω̃² = ω²/(1 + h²ω²/β)`: a symplectic
//! map (determinant 1, so **no numerical damping**: the amplitude of an undamped spring is
//! kept for ever) with `cos(φ) = 1 − h²ω̃²/2` per substep. Since `h²ω̃² < β = 3 < 4` for
//! every stiffness, the map is stable for **any** stiffness, and even an infinitely stiff
//! DOF keeps its eigenvalues at `e^{±2πi/3}`, well away from the defective point `−1` that
//! the trapezoidal choice `β = 4` reaches in that limit (there a Jordan block makes the stiff
//! mode grow linearly). For a resolved mode the period error is `≈ (ωh)²/8`
//! (0.22 % for `ωh = 0.13`, a 1 kg / 1000 N/m spring at 240 Hz). The damping part is
//! backward Euler (dissipative, stable at any `C`). Statics are exact: with `Δv = 0` the
//! impulse is `h·Q`.
//!
//! # Unresolved DOFs
//! A DOF stiffer than the substep can resolve (`ω·h > 1`, e.g. a blocked DOF at
//! `Kn = 1e12`) sits at `e^{±2πi/3}` in the limit: undamped, so the errors of the
//! linearisation (the sagitta of a turning anchor, f32 rounding of rapier's poses) would
//! accumulate in it. [`unresolved_damping`] damps those DOFs only, and
//! [`realised_stiffness`] gives the energy they actually store. Resolved DOFs are untouched.
//!
//! # Global solve
//! With `Δv = M⁻¹(Jᵀ P) + Δv_ext` for every body, the impulses of all joints satisfy the
//! sparse symmetric positive-definite system
//!
//! ```text
//! (G⁻¹ + J M⁻¹ Jᵀ)·P = G⁻¹·h·Q − J·Δv_ext
//! ```
//!
//! (one 6×6 block per joint, coupled through shared bodies), solved exactly. A DOF with no
//! stiffness and no damping has `G = 0`, regularised as `G + ε` so that its impulse is the
//! explicit `h·Q` up to `ε`. Because the system is solved globally, a long stiff chain
//! neither stretches nor becomes unstable: the penalty update is unconditionally stable for
//! the whole linearised system.
//!
//! The structure is analysed once per topology ([`topology`]): each island (joints linked
//! through dynamic bodies) without loops is eliminated leaves first, a chain's bodies in the
//! joint-space form and hubs in the body + joint form ([`tree`], O(n) for chains, trees and
//! hubs), an island with loops is factorised by a sparse Cholesky whose ordering and
//! symbolic analysis are reused ([`loops`]). With the
//! cargo feature `parallel`, islands are solved on rayon's threads; each island's
//! arithmetic is the same whatever the thread count, so results are bit-identical.

mod block;
pub(crate) use block::is_diagonal;
mod loops;
mod positive_part;
pub(crate) mod topology;
mod tree;
mod tree_x4;

pub(crate) use crate::kinematics::RateJacobians;
use loops::LoopSolve;
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};
use positive_part::positive_part;
use topology::{NodeKind, Plan, TreeNode};
use tree::TreeSolve;
use tree_x4::TreeX4;

/// The stiff-limit bound `β` of `h²ω̃²` (see the module docs).
pub(crate) const BETA: f64 = 3.0;

/// Regularisation of `G` [kg or kg·m²] for DOFs with neither stiffness nor damping.
pub(crate) const G_EPSILON: f64 = 1e-12;

/// Ratio `γ` of the numerical damping of an unresolved DOF to `h·K`.
pub(crate) const UNRESOLVED_DAMPING: f64 = 1.0;
/// Numerical damping [N·s/m or N·m·s/rad] of the DOFs the substep cannot resolve.
///
/// A DOF of tangent stiffness `K_ii` whose own effective inverse mass is `W_ii` (the
/// diagonal `w` of `J·M⁻¹·Jᵀ` of the joint) oscillates at `ω = √(K_ii·W_ii)`. With `ω·h ≫ 1` the
/// update keeps its eigenvalues on the unit circle (`e^{±2πi/3}`), so every error the
/// linearisation makes (the anchors' curvature over a substep, f32 rounding of the poses)
/// stays in the mode and accumulates. Those DOFs get a damper `c = γ·h·K_ii·s(ω·h)` (force
/// `−c·q̇`, implicit like the physical damping), with `s` rising smoothly from 0 at `ω·h = 1`
/// to 1 at `ω·h = 2`: resolved modes (`ω·h < 1`, every mode a user can observe) are
/// untouched, and the stiff limit has `|λ| = ½` per substep instead of 1. Its work is
/// reported as [`crate::law::JointEnergy::numerical`]. `kt_diagonal`: the diagonal of the
/// tangent stiffness `K_t`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn unresolved_damping(
    kt_diagonal: &Vector6<f64>,
    extra: &Vector6<f64>,
    w: &Vector6<f64>,
    h: f64,
) -> Vector6<f64> {
    // built by `arr6`, not `Vector6::from_fn`, whose closure is called out of line in the
    // AVX2 copy of the substep
    Vector6::from(crate::lanes::arr6(|i| {
        let k = kt_diagonal[i] + extra[i];
        // `s` is 0 for `(ω·h)² ≤ 1` and 1 for `(ω·h)² ≥ 4`, which the square settles without
        // the root for every DOF of a usual joint (a blocked DOF far beyond 4, a free one
        // at 0); the margins of 1e-9 are far beyond the round-off of either form, so the
        // result is the root's, bit for bit (a NaN compares false and takes the root)
        let wh2 = h * h * (k * w[i]);
        let s = if wh2 >= 4.0 * (1.0 + 1e-9) {
            1.0
        } else if wh2 <= 1.0 - 1e-9 {
            0.0
        } else {
            let wh = h * (k * w[i]).max(0.0).sqrt();
            let x = (wh - 1.0).clamp(0.0, 1.0);
            x * x * (3.0 - 2.0 * x)
        };
        UNRESOLVED_DAMPING * h * k.max(0.0) * s
    }))
}

#[cfg(test)]
#[test]
fn unresolved_damping_equals_the_form_with_the_root_bit_for_bit() {
    let root = |k: f64, w: f64, h: f64| {
        let wh = h * (k * w).max(0.0).sqrt();
        let x = (wh - 1.0).clamp(0.0, 1.0);
        UNRESOLVED_DAMPING * h * k.max(0.0) * (x * x * (3.0 - 2.0 * x))
    };
    let mut seed = 977u64;
    let mut rand = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let specials = [0.0, -0.0, f64::INFINITY, f64::NAN, -1.0, 1e-320, 1e300];
    for n in 0..200_000 {
        let h = 10f64.powf(-1.0 - 4.0 * rand());
        let w = 10f64.powf(-6.0 + 12.0 * rand());
        // (ω·h)² spread over 1e-6…1e6, and crowded at the two thresholds
        let target = match n % 4 {
            0 => 10f64.powf(-6.0 + 12.0 * rand()),
            1 => 1.0 + (rand() - 0.5) * 1e-6,
            2 => 4.0 + (rand() - 0.5) * 1e-6,
            _ => 1.0 + 3.0 * rand(),
        };
        let mut k = target / (h * h * w);
        if n % 97 == 0 {
            k = specials[(n / 97) % specials.len()];
        }
        let extra = if n % 5 == 0 { 0.1 * k * rand() } else { 0.0 };
        let got = unresolved_damping(
            &Vector6::repeat(k),
            &Vector6::repeat(extra),
            &Vector6::repeat(w),
            h,
        )[0];
        let expected = root(k + extra, w, h);
        assert!(
            got.to_bits() == expected.to_bits() || (got.is_nan() && expected.is_nan()),
            "k {k}, w {w}, h {h}: {got} vs {expected}"
        );
    }
}

/// Rotational stiffness [N·m/rad] that the force `f` \[N\] a joint transmits gives its
/// relative rotations through the effective lever arms `levers` \[m\] of its two sides
/// ([`swing_lever`]): a kink of the joint swings both levers against the force,
/// `k ≈ |f|·(ℓ1 + ℓ2)`. A link of a stiff chain under tension swings between its
/// neighbours at `ω² ≈ k·W_θ`, far above what the substep resolves (≈ 4800 rad/s for a
/// 0.1 m, 0.1 kg rod under 10 kN): [`unresolved_damping`] damps that relative swing like any
/// other unresolved DOF, so that the errors of the linearisation do not pile up in it until
/// a long chain flies apart. It does not act on the chain's own, resolved swing (a rigid
/// rotation of the links has no relative rate) and is not a stiffness of the law.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn geometric_swing_stiffness(
    f: &nalgebra::Vector3<f64>,
    levers: [f64; 2],
) -> Vector6<f64> {
    let k = f.norm() * (levers[0] + levers[1]);
    Vector6::new(0.0, 0.0, 0.0, k, k, k)
}

/// The effective lever arm `ℓ` \[m\] of one side of a joint in
/// [`geometric_swing_stiffness`], for the side's body of mass `mass` \[kg\] and mean
/// inertia `inertia` \[kg·m²\] whose centre of mass is `r` \[m\] from the point the force
/// acts at; `None`: the side is not dynamic.
///
/// * A side that is not dynamic (the ground, a kinematic body) does not swing: `ℓ = 0`
///   (its centre of mass, wherever the ground's origin lies, is no lever of the joint).
/// * A body that carries other joints too (a chain's link) swings about its centre of mass
///   between them, the joints' anchors moving with it: `ℓ = r`, the kink's stiffness
///   `|f|·r` against its inertia `I`.
/// * A body that carries this joint alone (a pendulum's bob, a chain's free end) can only
///   swing about the joint's anchor, its centre of mass moving with it: its inertia there is
///   `I + m·r²`, and with `ω² = |f|·r/(I + m·r²) = |f|·ℓ/I` the lever is
///   `ℓ = r·I/(I + m·r²)` (a compact bob on a long rope: `ω² ≈ |f|/(m·r) = g/r`, the
///   pendulum's own frequency, which the substep resolves).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn swing_lever(r: f64, mass_inertia: Option<(f64, f64)>, alone: bool) -> f64 {
    let Some((mass, inertia)) = mass_inertia else {
        return 0.0;
    };
    if !alone {
        return r;
    }
    let about_anchor = inertia + mass * r * r;
    if about_anchor > 0.0 && about_anchor.is_finite() {
        r * (inertia / about_anchor)
    } else {
        0.0
    }
}

/// Stiffness [N/m or N·m/rad] that the update realises for a linear DOF of stiffness `k`
/// and own effective inverse mass `w`: `K̃ = K/(1 + h²·K·w/β)` (the `ω̃²` of the module
/// docs times the mass). The update conserves `½·m·v² + ½·K̃·q²` (up to an O(h) term), so
/// the energy stored in a blocked DOF is reported as `½·K̃·q²`: equal to the law's `½·K·q²`
/// when the DOF is resolved, and bounded by `β/(h²·w)` however large `Kn` is (an f32 pose
/// error of 1 µm would otherwise store 0.5 J at `Kn = 1e12`).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn realised_stiffness(k: f64, w: f64, h: f64) -> f64 {
    if !(k > 0.0) {
        return k;
    }
    k / (1.0 + h * h * k * w.max(0.0) / BETA)
}

/// The diagonal of `J·M⁻¹·Jᵀ` for one side `s` of a joint: with `M⁻¹` block-diagonal
/// (three inverse masses `m⁻¹_k`, then the world inverse inertia `I⁻¹`, [`MassBlocks`])
/// and `J_s = σ_s·[T L_s; 0 R]` ([`RateJacobians`], `σ_s² = 1`),
///
/// ```text
/// w_r = Σ_k m⁻¹_k·T_rk² + L_r·I⁻¹·L_rᵀ   (r < 3, L = L_s),     w_r = R_r·I⁻¹·R_rᵀ   (r ≥ 3)
/// ```
///
/// With `A = L·I⁻¹` and `B = R·I⁻¹` (two 3×3 products), `L_r·I⁻¹·L_rᵀ = Σ_k A_rk·L_rk`:
/// the three rows at once as sums of columns (`Σ_k A_·k ∘ L_·k`, two-wide vector
/// updates), where the row-by-row quadratic forms were scalar. The same products; the sums
/// of `A` in nalgebra's order (within an ulp of the row-by-row ones).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn jacobian_weighted_diagonal(
    jac: &RateJacobians,
    s: usize,
    inv_mass: &MassBlocks,
) -> Vector6<f64> {
    let (l, r) = (&jac.lever(s), &jac.r);
    let a = (l * inv_mass.angular).data.0; // a[k][r] = A_rk
    let b = (r * inv_mass.angular).data.0;
    let (t, l, r) = (&jac.t.data.0, &l.data.0, &r.data.0);
    let mut lin = [0.0; 3];
    let mut ang = [0.0; 3];
    for (mk, tk) in inv_mass.linear.iter().zip(t) {
        for (w, tr) in lin.iter_mut().zip(tk) {
            *w += mk * tr * tr;
        }
    }
    let mut quad = [0.0; 3];
    for ((ak, lk), (bk, rk)) in a.iter().zip(l).zip(b.iter().zip(r)) {
        for row in 0..3 {
            quad[row] += ak[row] * lk[row];
            ang[row] += bk[row] * rk[row];
        }
    }
    diagonal_of_parts(&lin, &quad, &ang)
}

/// The weighted diagonal from its parts: `(lin + quad, ang)` (the translation rows' terms of
/// `T·diag(m⁻¹)·Tᵀ` and `L·I⁻¹·Lᵀ`, the rotation rows').
#[cfg_attr(not(debug_assertions), inline(always))]
fn diagonal_of_parts(lin: &[f64; 3], quad: &[f64; 3], ang: &[f64; 3]) -> Vector6<f64> {
    Vector6::new(
        lin[0] + quad[0],
        lin[1] + quad[1],
        lin[2] + quad[2],
        ang[0],
        ang[1],
        ang[2],
    )
}

/// The diagonal of `Σ_s J_s·M_s⁻¹·J_sᵀ` over the dynamic sides of a joint (`m[s]` the
/// inverse mass of side `s`'s body, `None` for a fixed side): [`jacobian_weighted_diagonal`]
/// of the one side, or of both at once with the joint's `T` and `R` shared
/// (`J_s = σ_s·[T L_s; 0 R]`):
///
/// ```text
/// w_r = Σ_k (m⁻¹_1,k + m⁻¹_2,k)·T_rk² + Σ_s Σ_k A_s,rk·L_s,rk   (r < 3, A_s = L_s·I⁻¹_s),
/// w_r = Σ_k B_rk·R_rk   (r ≥ 3, B = R·(I⁻¹_1 + I⁻¹_2))
/// ```
///
/// three 3×3 products where the sides one by one take four. The same terms summed in
/// another order (the inverse masses and inertias of the two bodies added first): within a
/// few ulps of the sum of the terms' magnitudes of the sides one by one (test
/// `weighted_diagonal_of_both_sides_equals_the_sides_sum`).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn jacobian_weighted_diagonal_of_sides(
    jac: &RateJacobians,
    m: [Option<&MassBlocks>; 2],
) -> Vector6<f64> {
    let (m1, m2) = match m {
        [Some(m1), Some(m2)] => (m1, m2),
        [Some(m1), None] => return jacobian_weighted_diagonal(jac, 0, m1),
        [None, Some(m2)] => return jacobian_weighted_diagonal(jac, 1, m2),
        [None, None] => return Vector6::zeros(),
    };
    let (l1, l2, r) = (&jac.lever(0), &jac.lever(1), &jac.r);
    let a1 = (l1 * m1.angular).data.0; // a1[k][r] = A_1,rk
    let a2 = (l2 * m2.angular).data.0;
    let b = (r * (m1.angular + m2.angular)).data.0;
    let (t, l1, l2, r) = (&jac.t.data.0, &l1.data.0, &l2.data.0, &r.data.0);
    let ml = m1.linear + m2.linear;
    let mut lin = [0.0; 3];
    let mut quad = [0.0; 3];
    let mut ang = [0.0; 3];
    for k in 0..3 {
        for row in 0..3 {
            lin[row] += ml[k] * t[k][row] * t[k][row];
            quad[row] += a1[k][row] * l1[k][row] + a2[k][row] * l2[k][row];
            ang[row] += b[k][row] * r[k][row];
        }
    }
    diagonal_of_parts(&lin, &quad, &ang)
}

/// A body's generalised mass or inverse mass as it is built: block-diagonal,
/// `diag(linear) ⊕ angular`, with `linear` the three (inverse) masses along the world axes
/// (a locked translation: inverse mass 0) and `angular` the symmetric 3×3 world (inverse)
/// inertia. 96 bytes where the 6×6 takes 288; the kernels of [`block`] read the two blocks,
/// [`Self::matrix`] builds the 6×6 for the rare general paths.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct MassBlocks {
    pub linear: Vector3<f64>,
    pub angular: Matrix3<f64>,
}

impl MassBlocks {
    pub(crate) const ZERO: MassBlocks = MassBlocks {
        linear: Vector3::new(0.0, 0.0, 0.0),
        angular: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    };

    /// The 6×6 matrix (general paths only: a hub whose `M⁻¹` is singular, tests).
    pub(crate) fn matrix(&self) -> Matrix6<f64> {
        let mut m = Matrix6::zeros();
        self.add_to(&mut m);
        m
    }

    /// `a += diag(linear) ⊕ angular`.
    pub(crate) fn add_to(&self, a: &mut Matrix6<f64>) {
        for k in 0..3 {
            a[(k, k)] += self.linear[k];
        }
        let mut rot = a.fixed_view_mut::<3, 3>(3, 3);
        rot += self.angular;
    }
}

/// One body as the solver sees it (248 bytes: read by every joint of the body each
/// substep, so kept to what the solver uses).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct SolverBody {
    /// Generalised inverse mass `M⁻¹`: 3 inverse masses, then the world inverse inertia
    /// tensor.
    pub inv_mass: MassBlocks,
    /// Velocity change over the substep from gravity and user forces, `(Δv, Δω)`.
    pub dv_ext: Vector6<f64>,
    /// Generalised mass `M` (the inverse of `inv_mass`: the 3 masses, then the world
    /// inertia), when every direction has a finite mass (`None` when rapier locks a
    /// translation or a rotation).
    pub mass: Option<MassBlocks>,
}

impl SolverBody {
    /// A body before its first gather (overwritten by the gather stage).
    pub(crate) fn empty() -> Self {
        SolverBody {
            inv_mass: MassBlocks::ZERO,
            dv_ext: Vector6::zeros(),
            mass: None,
        }
    }

    /// Takes the body `heavier` times heavier along the world axes of `axes` (bit `a` for
    /// axis `a`), its velocity along them kept over the substep (`Δv_ext,a = 0`): the
    /// axes rapier's contacts hold (`substep::held_axes`).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn hold(&mut self, axes: u8, heavier: f64) {
        for a in 0..3 {
            if axes & (1 << a) != 0 {
                self.scale_mass_along(a, heavier);
                self.dv_ext[a] = 0.0;
            }
        }
    }

    /// Undoes [`Self::hold`] along world axis `a`: the mass `heavier` times lighter again
    /// and the external velocity change `dv_ext` back (exact: `heavier` a power of two).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn release(&mut self, a: usize, heavier: f64, dv_ext: f64) {
        self.scale_mass_along(a, 1.0 / heavier);
        self.dv_ext[a] = dv_ext;
    }

    /// The body's mass along world axis `a` times `factor` (its inverse divided).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn scale_mass_along(&mut self, a: usize, factor: f64) {
        self.inv_mass.linear[a] /= factor;
        if let Some(m) = self.mass.as_mut() {
            m.linear[a] *= factor;
        }
    }

    /// Makes the geometric stiffness `K_g` of the joint forces acting on the body implicit
    /// like the joint stiffness, given `s·K_g⁺` ([`GeometricLoad::implicit_part`], `None`:
    /// nothing to add): the angular momentum equation becomes `(I + s·K_g⁺)·Δω = Σ Jᵀ·P +
    /// h·τ_ext` with `s = h²/β` and `K_g⁺` the positive (restoring) part of `K_g`, so
    /// `inv_mass`, `mass` and `dv_ext` become those of the augmented inertia (the caller
    /// applies what this changes in `dv_ext`). The negative part (a compressive, buckling
    /// load) stays explicit. The swing this stiffness gives a link between its neighbours is
    /// damped where the substep cannot resolve it by the joints
    /// ([`geometric_swing_stiffness`]).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn add_implicit_rotational_stiffness(&mut self, part: &Option<Matrix3<f64>>) {
        if let Some(skp) = part {
            self.add_augmented_inertia(skp);
        }
    }

    /// `I ← I + s·K⁺` for a positive semi-definite `K⁺` (given as `s·K⁺`), with `I⁻¹` and
    /// the angular part of `dv_ext` to match.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn add_augmented_inertia(&mut self, skp: &Matrix3<f64>) {
        if let Some(m) = self.mass.as_mut() {
            // the inertia I is known: (I + s·K⁺)⁻¹ by the symmetric 3×3 inverse, and
            // Δω ← (I + s·K⁺)⁻¹·I·Δω; the same as the general form below (I·I⁻¹ = 1 up to
            // round-off) without the products with I⁻¹, and more accurate (within a few
            // κ·ε, κ the condition number of I + s·K⁺)
            let aug = m.angular + skp;
            if let Some(inv) = symmetric_inverse(&aug) {
                let dw = self.dv_ext.fixed_rows::<3>(3).into_owned();
                let dw = inv * (m.angular * dw);
                self.dv_ext.fixed_rows_mut::<3>(3).copy_from(&dw);
                self.inv_mass.angular = inv;
                m.angular = aug;
                return;
            }
        }
        self.add_augmented_inertia_general(skp);
    }

    /// [`Self::add_augmented_inertia`] from `I⁻¹` alone, valid for a singular `I⁻¹` (rapier
    /// locks a rotation; then `mass` is `None`).
    fn add_augmented_inertia_general(&mut self, skp: &Matrix3<f64>) {
        let inv_i = self.inv_mass.angular;
        // (I + s·K)⁻¹ = (1 + s·I⁻¹·K)⁻¹·I⁻¹
        let a = Matrix3::identity() + inv_i * skp;
        let Some(a_inv) = a.try_inverse() else {
            return;
        };
        let new_inv = a_inv * inv_i;
        let new_inv = 0.5 * (new_inv + new_inv.transpose());
        let dw = self.dv_ext.fixed_rows::<3>(3).into_owned();
        self.dv_ext.fixed_rows_mut::<3>(3).copy_from(&(a_inv * dw));
        self.inv_mass.angular = new_inv;
        if let Some(m) = self.mass.as_mut() {
            m.angular += skp;
        }
    }
}

/// The inverse of a symmetric 3×3 `a` by its cofactors, reading its lower triangle (the
/// result exactly symmetric; `None` when its determinant or the determinant's reciprocal is
/// not positive and finite: `a` is meant to be positive definite).
#[cfg_attr(not(debug_assertions), inline(always))]
fn symmetric_inverse(a: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let (m00, m11, m22) = (a[(0, 0)], a[(1, 1)], a[(2, 2)]);
    let (m01, m12, m02) = (a[(1, 0)], a[(2, 1)], a[(2, 0)]);
    let c00 = m11 * m22 - m12 * m12;
    let c11 = m00 * m22 - m02 * m02;
    let c22 = m00 * m11 - m01 * m01;
    let c01 = m12 * m02 - m01 * m22;
    let c02 = m01 * m12 - m11 * m02;
    let c12 = m01 * m02 - m00 * m12;
    let det = m00 * c00 + m01 * c01 + m02 * c02;
    let d = 1.0 / det;
    if !(det > 0.0 && det.is_finite() && d.is_finite()) {
        return None;
    }
    Some(Matrix3::new(
        c00 * d,
        c01 * d,
        c02 * d,
        c01 * d,
        c11 * d,
        c12 * d,
        c02 * d,
        c12 * d,
        c22 * d,
    ))
}

/// Geometric stiffness [N·m/rad] of a force `f` \[N\] (world, held fixed) applied at a point
/// attached to a body at lever arm `r` \[m\] from its centre of mass: the torque `τ = r×f`
/// changes under a small rotation `δθ` of the body by `δτ = [f]ₓ[r]ₓ·δθ = −K_g·δθ`, with the
/// symmetric part `K_g = (f·r)·I − ½(r·fᵀ + f·rᵀ)`. It is positive (restoring) when the body
/// hangs from the point (`f` along `r`: a chain link under tension) and indefinite for a
/// transverse force.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn geometric_stiffness(f: &Vector3<f64>, r: &Vector3<f64>) -> Matrix3<f64> {
    let rf = r * f.transpose();
    Matrix3::identity() * f.dot(r) - 0.5 * (rf + rf.transpose())
}

/// The joint forces acting on one body, whose geometric stiffness
/// ([`geometric_stiffness`]) the solve makes implicit
/// ([`SolverBody::add_implicit_rotational_stiffness`]). The prepare stage adds each force
/// with its lever arm; while there is one, the pair itself is kept (the closed form of
/// [`single_force_positive_part`] needs it), from the second on the sum of the stiffnesses.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct GeometricLoad {
    /// Number of forces added.
    count: u32,
    /// The first force \[N\] and its lever arm \[m\].
    f: Vector3<f64>,
    r: Vector3<f64>,
    /// `Σ K_g` once `count ≥ 2` (not read before).
    sum: Matrix3<f64>,
    /// `s·K_g⁺` as [`Self::implicit_part`] last found it (`None`: zero, or not found).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    part: Option<Matrix3<f64>>,
}

impl GeometricLoad {
    /// No force.
    pub(crate) const NONE: GeometricLoad = GeometricLoad {
        count: 0,
        f: Vector3::new(0.0, 0.0, 0.0),
        r: Vector3::new(0.0, 0.0, 0.0),
        sum: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        part: None,
    };

    /// Forgets every force (the start of a substep).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn clear(&mut self) {
        self.count = 0;
    }

    /// Adds the force `f` applied at lever arm `r`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn add(&mut self, f: &Vector3<f64>, r: &Vector3<f64>) {
        match self.count {
            0 => {
                self.f = *f;
                self.r = *r;
            }
            // the same sum, in the same order, as adding every stiffness to a zero matrix
            1 => self.sum = geometric_stiffness(&self.f, &self.r) + geometric_stiffness(f, r),
            _ => self.sum += geometric_stiffness(f, r),
        }
        self.count += 1;
    }

    /// `Σ K_g` of the forces added.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn stiffness(&self) -> Matrix3<f64> {
        match self.count {
            0 => Matrix3::zeros(),
            1 => geometric_stiffness(&self.f, &self.r),
            _ => self.sum,
        }
    }

    /// Finds `s·K_g⁺` of the forces added (`s = h²/β`), which
    /// [`SolverBody::add_implicit_rotational_stiffness`] adds to the body's inertia, and
    /// keeps it ([`Self::part`]): `None` where there is no force, `s` is not positive, or
    /// the part is zero. A body carrying one joint force (every pendulum, the ends of a
    /// chain) takes `K_g⁺` in closed form ([`single_force_positive_part`]), the others the
    /// general [`positive_part`] of the sum.
    ///
    /// A stage loop of its own, before the bodies take it: the part is a chain of roots and
    /// divisions (an iteration for a body between two joints), which the processor
    /// overlaps between bodies only when little else sits between them (it took 39 % of
    /// the solve stage's time in the contact scene inside the bodies' update).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn implicit_part(&mut self, s: f64) {
        self.part = if !(s > 0.0) || self.count == 0 {
            None
        } else {
            // s·K⁺: the closed form of one force takes s·f (K_g is linear in f and the
            // positive part positively homogeneous: (s·K)⁺ = s·K⁺ for s > 0)
            // (an `if`, not `bool::then` with a closure: the closure was compiled out of
            // line, outside the substep's AVX2 copy)
            let single = if self.count == 1 {
                single_force_positive_part(&(s * self.f), &self.r)
            } else {
                None
            };
            match single {
                Some(part) => part,
                None => positive_part(&self.stiffness()).map(|kp| s * kp),
            }
        };
    }

    /// `s·K_g⁺` as [`Self::implicit_part`] last found it.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn part(&self) -> &Option<Matrix3<f64>> {
        &self.part
    }
}

/// The positive part of the geometric stiffness `K = a·I − ½(r·fᵀ + f·rᵀ)` of one force
/// `f` at lever arm `r` ([`geometric_stiffness`], `a = f·r`) in closed form: `Some(None)`
/// when it is zero, `None` when the closed form does not apply (a non-finite force or lever),
/// then [`positive_part`] decides.
///
/// With `p = |f|·|r|`, `c = a/p` and the unit vectors `r̂`, `f̂`, let `v = r̂ + f̂` and
/// `u = r̂ − f̂`: `v·u = |r̂|² − |f̂|² = 0`, `|v|² = 2(1 + c)`, `|u|² = 2(1 − c)`, and
/// `r̂·f̂ᵀ + f̂·r̂ᵀ = ½(v·vᵀ − u·uᵀ)`, so
///
/// ```text
/// K = a·I − ¼p·v·vᵀ + ¼p·u·uᵀ
/// ```
///
/// whose eigenpairs are `(a, r×f)` (`r×f` is orthogonal to `v` and `u`),
/// `(a − ¼p·|v|², v) = (½(a − p), v)`, never positive, and `(a + ¼p·|u|², u) = (½(a + p), u)`,
/// never negative. Hence:
///
/// ```text
/// a ≥ 0:  K⁺ = K − ½(a − p)·v·vᵀ/|v|² = a·(I − v·vᵀ/|v|²) + ¼p·u·uᵀ
///         (the coefficient of v·vᵀ: −¼p − p(c − 1)/(4(1 + c)) = −½p·c/(1 + c) = −a/|v|²)
/// a < 0:  K⁺ = ½(a + p)·u·uᵀ/|u|² = ¼p·(1 + c)/(1 − c)·u·uᵀ
/// ```
///
/// Both divide by at least 2 (`|v|² ≥ 2` when `c ≥ 0`, `1 − c ≥ 1` when `c < 0`) and agree
/// at `a = 0`. The degenerate cases need nothing apart: `f ∥ r` in tension (`u = 0`) gives
/// `a·(I − r̂·r̂ᵀ)`, in compression (`1 + c = 0`) zero, and `f = 0` or `r = 0` zero.
///
/// Computed without the unit vectors: with `V = p·v = |f|·r + |r|·f`, `U = p·u =
/// |f|·r − |r|·f`, `|V|² = p²·|v|² = 2p·(p + a)` and `(1 + c)/(1 − c) = (p + a)/(p − a)`,
///
/// ```text
/// a ≥ 0:  K⁺ = a·I − 2a·s·V·Vᵀ + (p + a)·s·U·Uᵀ      s = 1/(4p·(p + |a|))
/// a < 0:  K⁺ = (p + a)·s·U·Uᵀ
/// ```
///
/// one reciprocal where the unit vectors took six divisions and `a/|v|²` a seventh, after
/// the square roots on the critical path (`p + |a| ≥ p`: the denominator is at least `4p²`).
/// Not the old arithmetic bit for bit: the test
/// `single_force_positive_part_equals_the_unit_vector_form` holds it to 1e-14 of `p`
/// against that form (kept there), and the closed form's test to 1e-12 of `p` against the
/// eigen-decomposition.
///
/// Inlined into its caller with the closed form (the rare rescaling apart): a 3×3 returned
/// through memory was written as scalars and read back as pairs, a stalled store
/// forwarding on the body's chain.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn single_force_positive_part(
    f: &Vector3<f64>,
    r: &Vector3<f64>,
) -> Option<Option<Matrix3<f64>>> {
    let (nf2, nr2) = (f.norm_squared(), r.norm_squared());
    // squares within 1e±100: p = |f|·|r| within 1e±100 and 4p·(p + |a|) ≤ 8p² normal and
    // finite
    let within = |n2: f64| (1e-100..=1e100).contains(&n2);
    if within(nf2) && within(nr2) {
        Some(single_force_closed_form(f, r, nf2, nr2))
    } else {
        single_force_rescaled(f, r)
    }
}

/// [`single_force_positive_part`] of a force or lever that is zero, not finite, or beyond
/// 1e±50: K⁺ is positively homogeneous in f and in r, so that of the force and lever scaled
/// to a largest component of 1 (x/x = 1 exactly, squares in [1, 3]: no second rescaling),
/// scaled back.
#[cold]
#[inline(never)]
fn single_force_rescaled(f: &Vector3<f64>, r: &Vector3<f64>) -> Option<Option<Matrix3<f64>>> {
    if !f.iter().chain(r.iter()).all(|v| v.is_finite()) {
        return None;
    }
    let (mf, mr) = (f.amax(), r.amax());
    if mf == 0.0 || mr == 0.0 {
        return Some(None);
    }
    let (f, r) = (f / mf, r / mr);
    let part = single_force_closed_form(&f, &r, f.norm_squared(), r.norm_squared());
    Some(part.map(|k| k * (mf * mr)))
}

/// The closed form of [`single_force_positive_part`] for `|f|² = nf2` and `|r|² = nr2`
/// within 1e±100.
#[cfg_attr(not(debug_assertions), inline(always))]
fn single_force_closed_form(
    f: &Vector3<f64>,
    r: &Vector3<f64>,
    nf2: f64,
    nr2: f64,
) -> Option<Matrix3<f64>> {
    let (nf, nr) = (nf2.sqrt(), nr2.sqrt());
    let p = nf * nr;
    let a = f.dot(r);
    let s = 1.0 / (4.0 * p * (p + a.abs()));
    let u = r * nf - f * nr;
    // the symmetric result from its lower triangle
    let sym = |m00: f64, m10: f64, m20: f64, m11: f64, m21: f64, m22: f64| {
        Matrix3::new(m00, m10, m20, m10, m11, m21, m20, m21, m22)
    };
    if a >= 0.0 {
        let v = r * nf + f * nr;
        let kv = 2.0 * a * s;
        let ku = (p + a) * s;
        let e = |i: usize, j: usize| ku * u[i] * u[j] - kv * v[i] * v[j];
        Some(sym(
            a + e(0, 0),
            e(1, 0),
            e(2, 0),
            a + e(1, 1),
            e(2, 1),
            a + e(2, 2),
        ))
    } else {
        let k = (p + a) * s;
        let e = |i: usize, j: usize| k * u[i] * u[j];
        (k > 0.0).then(|| sym(e(0, 0), e(1, 0), e(2, 0), e(1, 1), e(2, 1), e(2, 2)))
    }
}

/// One joint as the solver sees it (312 bytes).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct SolverJoint {
    /// Solver bodies of side 1 and side 2 (`None`: fixed or kinematic).
    pub bodies: [Option<u32>; 2],
    /// Rates Jacobians of side 1 and side 2 (rows: q̇ in the working frame; columns: the
    /// body's `(v, ω)`), by their blocks ([`RateJacobians`]): their rotation rows ×
    /// linear-velocity columns (lower-left 3×3 block) are zero and not stored, which the
    /// products with `M⁻¹` rely on.
    pub jac: RateJacobians,
    /// The diagonal of `G = h·(h·K_t/β + C_t)`.
    pub g_diagonal: Vector6<f64>,
    /// [`NOT_COUPLED`] when `G` is diagonal (every law but coupled stops, planar friction
    /// and the flex joint's tangents), else the index of the whole `G` in
    /// [`SolverJoints::coupled`]. Written with [`SolverJoints::set_g`].
    pub g_coupled: u32,
    /// `h·Q`: the explicit impulse.
    pub explicit: Vector6<f64>,
}

/// [`SolverJoint::g_coupled`] of a diagonal `G`.
pub(crate) const NOT_COUPLED: u32 = u32::MAX;

impl Default for SolverJoint {
    fn default() -> Self {
        SolverJoint {
            bodies: [None, None],
            jac: RateJacobians::default(),
            g_diagonal: Vector6::zeros(),
            g_coupled: NOT_COUPLED,
            explicit: Vector6::zeros(),
        }
    }
}

/// The joints of a set as the solver sees them (indexed like the set's joints through
/// `Deref`), with the side table of the `G` blocks that are not diagonal.
///
/// `G` is diagonal for almost every joint: storing the 6×6 in every joint (288 bytes, read
/// once a substep) made it a third of the joint's solver record. A joint keeps the diagonal
/// (48 bytes) and an index; the few coupled blocks are kept whole here, the table cleared
/// at the start of every prepare stage and refilled (its capacity kept: no allocation once
/// the number of coupled joints has been reached).
#[derive(Debug, Clone, Default, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct SolverJoints {
    pub list: Vec<SolverJoint>,
    /// The `G` of the joints whose `g_coupled` is not [`NOT_COUPLED`].
    pub coupled: Vec<Matrix6<f64>>,
}

impl std::ops::Deref for SolverJoints {
    type Target = [SolverJoint];
    fn deref(&self) -> &[SolverJoint] {
        &self.list
    }
}

impl std::ops::DerefMut for SolverJoints {
    fn deref_mut(&mut self) -> &mut [SolverJoint] {
        &mut self.list
    }
}

impl From<Vec<SolverJoint>> for SolverJoints {
    fn from(list: Vec<SolverJoint>) -> Self {
        SolverJoints {
            list,
            coupled: Vec::new(),
        }
    }
}

impl SolverJoints {
    /// Writes `G` of joint `j`: its diagonal, and the whole block into the side table when
    /// an entry off the diagonal is not exactly zero (the test [`block::regularised_inverse`]
    /// made on the whole block, so the same inverse is taken).
    pub(crate) fn set_g(&mut self, j: usize, g: &Matrix6<f64>) {
        if is_diagonal(g) {
            self.set_g_diagonal(j, &g.diagonal());
        } else {
            self.coupled.push(*g);
            let sj = &mut self.list[j];
            sj.g_diagonal = g.diagonal();
            sj.g_coupled = (self.coupled.len() - 1) as u32;
        }
    }

    /// Writes a diagonal `G` of joint `j` (what [`Self::set_g`] does with a block whose
    /// entries off the diagonal are all ±0, without forming the block).
    pub(crate) fn set_g_diagonal(&mut self, j: usize, g: &Vector6<f64>) {
        let sj = &mut self.list[j];
        sj.g_diagonal = *g;
        sj.g_coupled = NOT_COUPLED;
    }

    /// The whole `G` of joint `j` (tests and the dense reference).
    #[cfg(test)]
    pub(crate) fn g(&self, j: usize) -> Matrix6<f64> {
        let sj = &self.list[j];
        match sj.g_coupled {
            NOT_COUPLED => Matrix6::from_diagonal(&sj.g_diagonal),
            k => self.coupled[k as usize],
        }
    }
}

/// Why a solve failed (global joint or body index).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SolveFailure {
    /// `G + ε` of the joint is singular (a negative tangent stiffness cancelling `ε`).
    SingularJoint(u32),
    /// The system is not positive definite at this joint (a negative tangent stiffness
    /// larger than the bodies can carry, or non-finite values).
    NotPositive(u32),
    /// The augmented inertia of this body is singular.
    SingularBody(u32),
    /// An impulse came out non-finite at this joint.
    NonFinite(u32),
}

/// The joint's own block `G⁻¹` (of the regularised `G + ε`) and its right-hand side
/// `r = G⁻¹·h·Q − Σ J·Δv_ext`, written into `g_inv` and `r`.
#[cfg_attr(not(debug_assertions), inline(always))]
fn joint_block(
    joints: &SolverJoints,
    bodies: &[SolverBody],
    j: u32,
    g_inv: &mut Matrix6<f64>,
    r: &mut Vector6<f64>,
) -> Result<(), SolveFailure> {
    let sj = &joints[j as usize];
    // a diagonal G (the common case) from its diagonal, G⁻¹·h·Q by the same products
    *r = if sj.g_coupled == NOT_COUPLED {
        block::regularised_diagonal_inverse(&sj.g_diagonal, G_EPSILON, g_inv)
            .ok_or(SolveFailure::SingularJoint(j))?;
        sj.explicit.component_mul(&g_inv.diagonal())
    } else {
        let g = &joints.coupled[sj.g_coupled as usize];
        if block::regularised_inverse(g, G_EPSILON, g_inv).ok_or(SolveFailure::SingularJoint(j))? {
            sj.explicit.component_mul(&g_inv.diagonal())
        } else {
            *g_inv * sj.explicit
        }
    };
    for side in 0..2 {
        if let Some(b) = sj.bodies[side] {
            *r -= sj.jac.mul(side, &bodies[b as usize].dv_ext);
        }
    }
    Ok(())
}

/// The nodes of a forest (its trees one after the other, tree `i` from `starts[i]`) taken
/// round-robin: the first node of every tree, then the second of every tree, and so on,
/// parents renumbered. Each tree keeps its own order (children before parents) and its own
/// arithmetic, so the solution has the same bits; but consecutive nodes now belong to
/// different trees, whose eliminations do not wait on each other. A small tree's
/// elimination is a chain of dependent factorisations (three capsules: two 6×6 Choleskys
/// through `L⁻¹·E` and `XᵀX`, a few hundred cycles of latency) that the processor overlaps
/// with the next tree's only when that one's instructions come next.
fn interleave(forest: &[TreeNode], starts: &[usize]) -> Vec<TreeNode> {
    let ends: Vec<usize> = starts[1..]
        .iter()
        .copied()
        .chain(std::iter::once(forest.len()))
        .collect();
    let longest = starts
        .iter()
        .zip(&ends)
        .map(|(s, e)| e - s)
        .max()
        .unwrap_or(0);
    // old position → new position, then the nodes in their new order
    let mut order = Vec::with_capacity(forest.len());
    for k in 0..longest {
        for (s, e) in starts.iter().zip(&ends) {
            if s + k < *e {
                order.push(s + k);
            }
        }
    }
    let mut moved_to = vec![0u32; forest.len()];
    for (new, old) in order.iter().enumerate() {
        moved_to[*old] = new as u32;
    }
    order
        .iter()
        .map(|old| {
            let mut n = forest[*old];
            if n.parent != u32::MAX {
                n.parent = moved_to[n.parent as usize];
            }
            n
        })
        .collect()
}

/// Most nodes a batch of tree islands (a forest) shares one workspace with.
const FOREST_NODES: usize = 4096;

/// How one island (or a batch of tree islands) is solved, with its workspace.
// (built once per topology; the scalar tree and the loops unboxed, as the solve reads them
// at every substep)
#[allow(clippy::large_enum_variant)]
#[derive(Debug)]
enum IslandSolve {
    Tree(TreeSolve),
    /// Tree islands of one shape, four at a time in the lanes of a vector ([`tree_x4`]).
    TreeX4(Box<TreeX4>),
    Loops(LoopSolve),
}

impl IslandSolve {
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn solve(&mut self, joints: &SolverJoints, bodies: &[SolverBody]) -> Result<(), SolveFailure> {
        match self {
            IslandSolve::Tree(t) => t.solve(joints, bodies),
            IslandSolve::TreeX4(t) => t.solve(joints, bodies),
            IslandSolve::Loops(l) => l.solve(joints, bodies),
        }
    }
}

/// The solver of a joint set: one workspace per island, built once per topology.
#[derive(Debug, Default)]
pub(crate) struct Solver {
    islands: Vec<IslandSolve>,
    status: Vec<Result<(), SolveFailure>>,
    /// Joints that close loops (global indices), for diagnostics.
    loop_joints: Vec<u32>,
    /// Number of islands (tree islands are solved in batches).
    island_count: usize,
    /// Per solver body: the unit of `islands` that solves it and, in a unit of trees in
    /// lanes, the batch of four trees it is in (`[u32::MAX; 2]`: no active joint).
    body_unit: Vec<[u32; 2]>,
    /// The units and batches [`Self::solve_again`] solves (kept for its capacity).
    again: Vec<[u32; 2]>,
}

impl Solver {
    /// Analyses the topology: `sides[j]` are the solver bodies of joint `j`, joints with
    /// `active[j] == false` take no part.
    pub(crate) fn new(n_bodies: usize, sides: &[[Option<u32>; 2]], active: &[bool]) -> Self {
        let plans = topology::analyse(n_bodies, sides, active);
        let island_count = plans.len();
        let mut loop_joints = Vec::new();
        let mut islands: Vec<IslandSolve> = Vec::new();
        // tree islands of the same shape (tree_x4::shape), four at a time, are solved in the
        // lanes of a vector (all of each shape, in island order, but for one left over after
        // the batches of four: tree_x4::PAD_FROM), in groups of up to FOREST_NODES nodes;
        // each group is made where its last tree comes. The others go to the scalar forests
        // below.
        let mut by_shape: std::collections::HashMap<_, Vec<usize>> = Default::default();
        for (k, p) in plans.iter().enumerate() {
            if let Plan::Tree(nodes) = &p.plan {
                if tree_x4::supported(nodes) {
                    by_shape.entry(tree_x4::shape(nodes)).or_default().push(k);
                }
            }
        }
        // per island: the islands of its group (up to FOREST_NODES nodes, a multiple of
        // four but for a padded last batch) when it is the group's last
        let mut batch_at: Vec<Option<Vec<usize>>> = vec![None; plans.len()];
        let mut in_batch = vec![false; plans.len()];
        for (shape, group) in &by_shape {
            let per_group = (FOREST_NODES / shape.len() / 4).max(1) * 4;
            let whole = match group.len() % 4 {
                r if r >= tree_x4::PAD_FROM => group.len(),
                r => group.len() - r,
            };
            for trees in group[..whole].chunks(per_group) {
                batch_at[*trees.last().expect("a group has trees")] = Some(trees.to_vec());
                for &k in trees {
                    in_batch[k] = true;
                }
            }
        }
        // consecutive tree islands share one workspace of up to FOREST_NODES nodes (a forest
        // eliminates exactly like its trees one by one, from contiguous arrays): thousands of
        // pendulums are a few workspaces, not thousands. The batches depend on the topology
        // only, never on the thread count.
        let mut forest: Vec<TreeNode> = Vec::new();
        let mut starts: Vec<usize> = Vec::new();
        let flush = |forest: &mut Vec<TreeNode>,
                     starts: &mut Vec<usize>,
                     islands: &mut Vec<IslandSolve>| {
            if !forest.is_empty() {
                let nodes = interleave(forest, starts);
                islands.push(IslandSolve::Tree(TreeSolve::new(nodes)));
                forest.clear();
                starts.clear();
            }
        };
        let add_tree = |forest: &mut Vec<TreeNode>, starts: &mut Vec<usize>, nodes: &[TreeNode]| {
            starts.push(forest.len());
            let offset = forest.len() as u32;
            forest.extend(nodes.iter().map(|&n| {
                let mut n = n;
                if n.parent != u32::MAX {
                    n.parent += offset;
                }
                n
            }));
        };
        for k in 0..plans.len() {
            if let Some(group) = &batch_at[k] {
                let trees: Vec<&[TreeNode]> = group
                    .iter()
                    .map(|&t| match &plans[t].plan {
                        Plan::Tree(nodes) => nodes.as_slice(),
                        Plan::Loops { .. } => unreachable!("a batch holds trees"),
                    })
                    .collect();
                // the group's scalar forest for the substeps the lanes do not do
                let (mut f, mut s) = (Vec::new(), Vec::new());
                for t in &trees {
                    add_tree(&mut f, &mut s, t);
                }
                let fallback = TreeSolve::new(interleave(&f, &s));
                islands.push(IslandSolve::TreeX4(Box::new(TreeX4::new(&trees, fallback))));
                continue;
            }
            if in_batch[k] {
                continue;
            }
            let p = &plans[k];
            match &p.plan {
                Plan::Tree(nodes) => {
                    if forest.len() + nodes.len() > FOREST_NODES {
                        flush(&mut forest, &mut starts, &mut islands);
                    }
                    add_tree(&mut forest, &mut starts, nodes);
                }
                Plan::Loops { closing } => {
                    loop_joints.extend(closing.iter().copied());
                    islands.push(IslandSolve::Loops(LoopSolve::new(
                        &p.joints, &p.bodies, sides,
                    )));
                }
            }
        }
        flush(&mut forest, &mut starts, &mut islands);
        loop_joints.sort_unstable();
        let mut body_unit = vec![[u32::MAX; 2]; n_bodies];
        for (u, island) in islands.iter().enumerate() {
            let u = u as u32;
            match island {
                IslandSolve::Tree(t) => {
                    for node in &t.nodes {
                        if let NodeKind::Body(b) = node.kind {
                            body_unit[b as usize] = [u, 0];
                        }
                    }
                }
                IslandSolve::TreeX4(t) => {
                    t.for_each_body(|b, batch| body_unit[b as usize] = [u, batch as u32])
                }
                IslandSolve::Loops(l) => {
                    for &b in l.bodies() {
                        body_unit[b as usize] = [u, 0];
                    }
                }
            }
        }
        Solver {
            status: vec![Ok(()); islands.len()],
            islands,
            loop_joints,
            island_count,
            body_unit,
            again: Vec::new(),
        }
    }

    /// Number of islands.
    pub(crate) fn island_count(&self) -> usize {
        self.island_count
    }

    /// Numbers of loop islands factorised by blocks and by faer ([`loops`]).
    #[cfg(test)]
    pub(crate) fn loop_factorisations(&self) -> (usize, usize) {
        let loops = self.islands.iter().filter_map(|i| match i {
            IslandSolve::Loops(l) => Some(l.by_blocks()),
            _ => None,
        });
        loops.fold(
            (0, 0),
            |(b, s), blocks| if blocks { (b + 1, s) } else { (b, s + 1) },
        )
    }

    /// Joints that close a loop.
    pub(crate) fn loop_joints(&self) -> &[u32] {
        &self.loop_joints
    }

    /// Solves every island and writes the impulse of every active joint into `impulses` and
    /// the velocity change `M⁻¹·Σ Jᵀ·P` of every body into `velocity` (indexed like the
    /// inputs). On failure, the first failing island (in island order) is reported.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn solve(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
        impulses: &mut [Vector6<f64>],
        velocity: &mut [Vector6<f64>],
    ) -> Result<(), SolveFailure> {
        #[cfg(feature = "parallel")]
        {
            use rayon::prelude::*;
            self.islands
                .par_iter_mut()
                .zip(self.status.par_iter_mut())
                .for_each(|(island, status)| *status = island.solve(joints, bodies));
        }
        #[cfg(not(feature = "parallel"))]
        for (island, status) in self.islands.iter_mut().zip(self.status.iter_mut()) {
            *status = island.solve(joints, bodies);
        }
        for s in &self.status {
            (*s)?;
        }
        for island in &self.islands {
            scatter(island, None::<std::iter::Empty<usize>>, impulses, velocity);
        }
        finite(impulses)
    }

    /// Solves again, after [`Self::solve`], the islands of the solver bodies `changed`
    /// (whose inverse masses or external velocity changes were changed since: the bodies
    /// a held axis was released from, `substep::release_lifted`), and in a unit of trees
    /// in lanes only the batches of four trees they are in: the same bits as
    /// [`Self::solve`] again, the other islands' inputs being the same. One lifted foot in a
    /// world of many robots solved every island twice.
    pub(crate) fn solve_again(
        &mut self,
        joints: &SolverJoints,
        bodies: &[SolverBody],
        impulses: &mut [Vector6<f64>],
        velocity: &mut [Vector6<f64>],
        changed: &[u32],
    ) -> Result<(), SolveFailure> {
        self.again.clear();
        let units = changed.iter().map(|&b| self.body_unit[b as usize]);
        self.again.extend(units.filter(|u| u[0] != u32::MAX));
        // in island order, then batch order: the first failure is the one `solve` reports
        self.again.sort_unstable();
        self.again.dedup();
        // each unit once, with its batches (trees in lanes) or alone
        for unit in self.again.chunk_by(|a, b| a[0] == b[0]) {
            let u = unit[0][0] as usize;
            let batches = unit.iter().map(|a| a[1] as usize);
            self.status[u] = match &mut self.islands[u] {
                IslandSolve::TreeX4(t) => t.solve_batches(joints, bodies, batches),
                other => other.solve(joints, bodies),
            };
            self.status[u]?;
        }
        for unit in self.again.chunk_by(|a, b| a[0] == b[0]) {
            let batches = unit.iter().map(|a| a[1] as usize);
            scatter(
                &self.islands[unit[0][0] as usize],
                Some(batches),
                impulses,
                velocity,
            );
        }
        finite(impulses)
    }
}

/// Writes the solution of one unit of [`Solver`] into `impulses` and `velocity`: all of it,
/// or, for trees in lanes that did not fall back, only the batches `batches`.
#[cfg_attr(not(debug_assertions), inline(always))]
fn scatter(
    island: &IslandSolve,
    batches: Option<impl Iterator<Item = usize>>,
    impulses: &mut [Vector6<f64>],
    velocity: &mut [Vector6<f64>],
) {
    let mut write = |kind: NodeKind, x: &Vector6<f64>| match kind {
        NodeKind::Joint(j) => impulses[j as usize] = *x,
        NodeKind::Body(b) => velocity[b as usize] = *x,
    };
    match island {
        IslandSolve::Tree(t) => {
            for (node, x) in t.nodes.iter().zip(&t.x) {
                write(node.kind, x);
            }
        }
        IslandSolve::TreeX4(t) => match batches {
            Some(batches) if !t.fell_back() => {
                for b in batches {
                    t.for_each_solution_of(b, &mut write);
                }
            }
            _ => t.for_each_solution(write),
        },
        IslandSolve::Loops(l) => {
            for (j, p) in l.joints().iter().zip(&l.impulses) {
                impulses[*j as usize] = *p;
            }
            for (b, u) in l.bodies().iter().zip(&l.velocity) {
                velocity[*b as usize] = *u;
            }
        }
    }
}

/// The failure of the first joint whose impulse is not finite.
#[cfg_attr(not(debug_assertions), inline(always))]
fn finite(impulses: &[Vector6<f64>]) -> Result<(), SolveFailure> {
    for (j, p) in impulses.iter().enumerate() {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(SolveFailure::NonFinite(j as u32));
        }
    }
    Ok(())
}

/// The joint-space system solved densely: the reference the structured solve is tested
/// against (small systems only).
#[cfg(test)]
pub(crate) fn reference_solve(joints: &SolverJoints, bodies: &[SolverBody]) -> Vec<Vector6<f64>> {
    use nalgebra::{DMatrix, DVector};
    let n = joints.len();
    let mut a = DMatrix::<f64>::zeros(6 * n, 6 * n);
    let mut rhs = DVector::<f64>::zeros(6 * n);
    for (j, sj) in joints.iter().enumerate() {
        let g_inv = (joints.g(j) + Matrix6::identity() * G_EPSILON)
            .try_inverse()
            .unwrap();
        let g_inv = 0.5 * (g_inv + g_inv.transpose());
        let mut r = g_inv * sj.explicit;
        for s in 0..2 {
            if let Some(b) = sj.bodies[s] {
                r -= sj.jac.matrix(s) * bodies[b as usize].dv_ext;
            }
        }
        rhs.fixed_rows_mut::<6>(6 * j).copy_from(&r);
        a.fixed_view_mut::<6, 6>(6 * j, 6 * j).copy_from(&g_inv);
    }
    for (j, sj) in joints.iter().enumerate() {
        for (k, sk) in joints.iter().enumerate() {
            for s in 0..2 {
                for t in 0..2 {
                    if let (Some(b), Some(c)) = (sj.bodies[s], sk.bodies[t]) {
                        if b == c {
                            let blk = sj.jac.matrix(s)
                                * bodies[b as usize].inv_mass.matrix()
                                * sk.jac.matrix(t).transpose();
                            let mut v = a.fixed_view_mut::<6, 6>(6 * j, 6 * k);
                            v += blk;
                        }
                    }
                }
            }
        }
    }
    let a = 0.5 * (&a + a.transpose());
    let sol = a.cholesky().expect("positive definite").solve(&rhs);
    (0..n)
        .map(|j| sol.fixed_rows::<6>(6 * j).into_owned())
        .collect()
}

#[cfg(test)]
mod tests;
