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
//! (one 6×6 block per joint, coupled through shared bodies), solved exactly by a sparse
//! Cholesky factorisation (nalgebra-sparse). A DOF with no stiffness and no damping has
//! `G = 0`, regularised as `G + ε` so that its impulse is the explicit `h·Q` up to `ε`.
//! Because the system is solved globally, a long stiff chain neither stretches nor becomes
//! unstable: the penalty update is unconditionally stable for the whole linearised system.

use crate::error::SimError;
use nalgebra::{DVector, Matrix3, Matrix6, Vector6};
use nalgebra_sparse::{factorization::CscCholesky, CooMatrix, CscMatrix};

/// The stiff-limit bound `β` of `h²ω̃²` (see the module docs).
pub const BETA: f64 = 3.0;

/// Regularisation of `G` [kg or kg·m²] for DOFs with neither stiffness nor damping.
pub const G_EPSILON: f64 = 1e-12;

/// Ratio `γ` of the numerical damping of an unresolved DOF to `h·K`.
pub const UNRESOLVED_DAMPING: f64 = 1.0;

/// Numerical damping [N·s/m or N·m·s/rad] of the DOFs the substep cannot resolve.
///
/// A DOF of tangent stiffness `K_ii` whose own effective inverse mass is `W_ii` (the
/// diagonal of `J·M⁻¹·Jᵀ` of the joint) oscillates at `ω = √(K_ii·W_ii)`. With `ω·h ≫ 1` the
/// update keeps its eigenvalues on the unit circle (`e^{±2πi/3}`), so every error the
/// linearisation makes (the anchors' curvature over a substep, f32 rounding of the poses)
/// stays in the mode and accumulates. Those DOFs get a damper `c = γ·h·K_ii·s(ω·h)` (force
/// `−c·q̇`, implicit like the physical damping), with `s` rising smoothly from 0 at `ω·h = 1`
/// to 1 at `ω·h = 2`: resolved modes (`ω·h < 1`, every mode a user can observe) are
/// untouched, and the stiff limit has `|λ| = ½` per substep instead of 1. Its work is
/// reported as [`crate::law::JointEnergy::numerical`].
pub fn unresolved_damping(kt: &Matrix6<f64>, w: &Matrix6<f64>, h: f64) -> Vector6<f64> {
    Vector6::from_fn(|i, _| {
        let k = kt[(i, i)];
        let wh = h * (k * w[(i, i)]).max(0.0).sqrt();
        let x = (wh - 1.0).clamp(0.0, 1.0);
        let s = x * x * (3.0 - 2.0 * x);
        UNRESOLVED_DAMPING * h * k.max(0.0) * s
    })
}

/// Stiffness [N/m or N·m/rad] that the update realises for a linear DOF of stiffness `k`
/// and own effective inverse mass `w`: `K̃ = K/(1 + h²·K·w/β)` (the `ω̃²` of the module
/// docs times the mass). The update conserves `½·m·v² + ½·K̃·q²` (up to an O(h) term), so
/// the energy stored in a blocked DOF is reported as `½·K̃·q²`: equal to the law's `½·K·q²`
/// when the DOF is resolved, and bounded by `β/(h²·w)` however large `Kn` is (an f32 pose
/// error of 1 µm would otherwise store 0.5 J at `Kn = 1e12`).
pub fn realised_stiffness(k: f64, w: f64, h: f64) -> f64 {
    if !(k > 0.0) {
        return k;
    }
    k / (1.0 + h * h * k * w.max(0.0) / BETA)
}

/// One body as the solver sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverBody {
    /// Generalised inverse mass (3 inverse masses on the diagonal, then the world inverse
    /// inertia tensor).
    pub inv_mass: Matrix6<f64>,
    /// Velocity change over the substep from gravity and user forces, `(Δv, Δω)`.
    pub dv_ext: Vector6<f64>,
}

impl SolverBody {
    /// Makes the geometric stiffness `K_g` of the forces acting on the body implicit like the
    /// joint stiffness: the angular momentum equation becomes
    /// `(I + s·K_g⁺)·Δω = Σ Jᵀ·P + h·τ_ext` with `s = h²/β` and `K_g⁺` the positive
    /// (restoring) part of `K_g`, so `inv_mass` and `dv_ext` become those of the augmented
    /// inertia. The negative part (a compressive, buckling load) stays explicit.
    pub fn add_implicit_rotational_stiffness(&mut self, kg: &Matrix3<f64>, s: f64) {
        let sym = 0.5 * (kg + kg.transpose());
        let eig = sym.symmetric_eigen();
        let pos = eig.eigenvalues.map(|l| l.max(0.0));
        if !(pos.max() > 0.0) || !(s > 0.0) {
            return;
        }
        let kp = eig.eigenvectors * Matrix3::from_diagonal(&pos) * eig.eigenvectors.transpose();
        let inv_i = self.inv_mass.fixed_view::<3, 3>(3, 3).into_owned();
        // (I + s·K)⁻¹ = (1 + s·I⁻¹·K)⁻¹·I⁻¹, valid for a singular I⁻¹ (locked rotations)
        let a = Matrix3::identity() + s * inv_i * kp;
        let Some(a_inv) = a.try_inverse() else {
            return;
        };
        let new_inv = a_inv * inv_i;
        let new_inv = 0.5 * (new_inv + new_inv.transpose());
        let dw = self.dv_ext.fixed_rows::<3>(3).into_owned();
        self.dv_ext.fixed_rows_mut::<3>(3).copy_from(&(a_inv * dw));
        self.inv_mass
            .fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&new_inv);
    }
}

/// One joint as the solver sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverJoint {
    /// Index of body 1 in the solver's bodies (`None`: fixed or kinematic).
    pub body1: Option<usize>,
    /// Index of body 2.
    pub body2: Option<usize>,
    /// Rates Jacobian of body 1.
    pub jac1: Matrix6<f64>,
    /// Rates Jacobian of body 2.
    pub jac2: Matrix6<f64>,
    /// `G = h·(h·K_t/β + C_t)`.
    pub g: Matrix6<f64>,
    /// `h·Q`: the explicit impulse.
    pub explicit: Vector6<f64>,
}

impl SolverJoint {
    fn jac(&self, which: usize) -> (&Option<usize>, &Matrix6<f64>) {
        if which == 0 {
            (&self.body1, &self.jac1)
        } else {
            (&self.body2, &self.jac2)
        }
    }
}

/// Solves the global implicit system and returns one impulse `P` per joint.
pub fn solve(joints: &[SolverJoint], bodies: &[SolverBody]) -> Result<Vec<Vector6<f64>>, SimError> {
    let n = joints.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    // joints attached to each body, with the side (0 = body 1, 1 = body 2)
    let mut on_body: Vec<Vec<(usize, usize)>> = vec![Vec::new(); bodies.len()];
    for (j, joint) in joints.iter().enumerate() {
        for side in 0..2 {
            if let Some(b) = *joint.jac(side).0 {
                on_body[b].push((j, side));
            }
        }
    }
    let mut coo = CooMatrix::new(6 * n, 6 * n);
    let mut rhs = DVector::zeros(6 * n);
    for (j, joint) in joints.iter().enumerate() {
        let g = joint.g + Matrix6::identity() * G_EPSILON;
        let g_inv = g.try_inverse().ok_or_else(|| SimError::Unstable {
            time: f64::NAN,
            reason: format!("joint #{j}: singular implicit matrix G"),
        })?;
        let g_inv = 0.5 * (g_inv + g_inv.transpose());
        let mut r = g_inv * joint.explicit;
        for side in 0..2 {
            let (b, jac) = joint.jac(side);
            if let Some(b) = *b {
                r -= jac * bodies[b].dv_ext;
            }
        }
        rhs.fixed_rows_mut::<6>(6 * j).copy_from(&r);
        push_block(&mut coo, j, j, &g_inv);
    }
    // W = J M⁻¹ Jᵀ: every pair of joint sides on the same body contributes a block.
    for (b, list) in on_body.iter().enumerate() {
        let minv = &bodies[b].inv_mass;
        for &(j, sj) in list {
            let jm = joints[j].jac(sj).1 * minv;
            for &(k, sk) in list {
                if k < j {
                    continue;
                }
                let mut block = jm * joints[k].jac(sk).1.transpose();
                if k == j {
                    block = 0.5 * (block + block.transpose());
                }
                push_block(&mut coo, j, k, &block);
                if k != j {
                    push_block(&mut coo, k, j, &block.transpose());
                }
            }
        }
    }
    let csc = CscMatrix::from(&coo);
    let chol = CscCholesky::factor(&csc).map_err(|e| SimError::Unstable {
        time: f64::NAN,
        reason: format!("the joint system is not positive definite ({e:?})"),
    })?;
    let sol = chol.solve(&rhs);
    let p: Vec<Vector6<f64>> = (0..n)
        .map(|j| Vector6::from_iterator((0..6).map(|i| sol[(6 * j + i, 0)])))
        .collect();
    if p.iter().any(|v| !v.iter().all(|x| x.is_finite())) {
        return Err(SimError::Unstable {
            time: f64::NAN,
            reason: "non-finite joint impulse".into(),
        });
    }
    Ok(p)
}

fn push_block(coo: &mut CooMatrix<f64>, bi: usize, bj: usize, m: &Matrix6<f64>) {
    for r in 0..6 {
        for c in 0..6 {
            // zeros are pushed too, so that the pattern stays symmetric
            coo.push(6 * bi + r, 6 * bj + c, m[(r, c)]);
        }
    }
}
