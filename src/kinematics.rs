//! Joint kinematics (docs/kjoint2.md §3): the symmetric working frame, the relative displacement
//! and a path-independent rotation measure, and the Jacobian of the relative rates.
//!
//! Pure nalgebra in f64; the rapier layer converts its poses into [`BodyPose`].
//!
//! # Frames
//! Each body carries a frame attached to it (anchor point + axes): `F_i = R_i·F_i,local`.
//! At creation both coincide with the joint's initial frame (Skew1), except that Skew2 adds
//! an initial relative rotation `θ0` on body 2's frame. `Q = F_1ᵀ·F_2` is the relative
//! rotation.
//!
//! # Rotation measure
//! - Types with a single free rotation about x (revolute, cylindrical, planar): a
//!   **swing-twist** split. The swing `S` is the smallest rotation taking body 1's x axis onto
//!   body 2's; `θy, θz` are the components of its rotation vector, and `θx` is the twist
//!   angle left after the swing, **unwrapped** over full turns (a stop at 7 rad means 7 rad).
//!   The working frame is `E = S^{1/2}·F_1·R_x(θx/2)`, exactly half-way: its x axis bisects
//!   the two joint axes.
//! - Universal joint (type 5): **Cardan angles**. A universal joint is a cross whose y arm
//!   turns in body 1 and whose z arm turns in body 2 (OpenRadioss builds its frame from
//!   body 1's y axis and body 2's z axis, `rskew33.F`). With `Q = R_y(θy)·R_x(θx)·R_z(θz)`,
//!   `θy` and `θz` are the two free cross rotations and the blocked `θx` is the deviation of
//!   the arms from 90°: `θx ≡ 0` for any Cardan motion `R_y(a)·R_z(b)`, whose rotation vector
//!   has the x component `½·a·b` (0.045 rad at a = b = 0.3, which the rotation vector would
//!   penalise with `KR`). `θy`, `θz` are continued over full turns. The working frame is the
//!   cross's frame turned half-way between the arms, `E = F_1·R_y(θy)·R_x(θx/2)`; the
//!   rotation rates are the Cardan rates: with `ω_G = Gᵀ(ω_2 − ω_1)`, `G = F_1·R_y(θy)`,
//!   `θ̇x = ω_G,x`, `θ̇y = ω_G,y + tan θx·ω_G,z`, `θ̇z = ω_G,z/cos θx` (exactly OpenRadioss'
//!   increments in the basis of the two arms and their common normal).
//!   The arms belong to their bodies, so swapping the bodies gives another joint, not `−θ`.
//!   A body turning at a constant ω over a substep (as rapier integrates it) leaves a Cardan
//!   motion at second order (`Δθx = −½·θ̇y·θ̇z·h²`), which the penalty corrects at the next
//!   substep: the blocked `θx` carries a bias of that order (2e-5 rad at
//!   `θ̇y·θ̇z = 1.25 rad²/s²` and `h = 1/240 s`), where the rotation vector's `θx` was wrong by
//!   `½·θy·θz` at any step.
//! - Other types: `θ` is the rotation vector of `Q` (`Q = exp(θ)`), continued past π by
//!   choosing the equivalent vector `n·(a + 2πk)` closest to the previous one, and
//!   `E = F_1·exp(θ/2)`.
//!
//! All are functions of the current poses only (plus the turn count), so they do not drift,
//! and equal the rotation vector for small rotations; the swing-twist and rotation-vector
//! measures change sign when the bodies are swapped. The rates `q̇` are the relative
//! velocities in `E`: `δ̇ = Eᵀ[(v_2 + ω_2×(p_m − c_2)) − (v_1 + ω_1×(p_m − c_1))]`,
//! `θ̇ = Eᵀ(ω_2 − ω_1)` (the Cardan rates above for the universal joint), with `p_m` the
//! mid-point of the anchors: the work-conjugate rates of the moment-balanced assembly of
//! docs/kjoint2.md §4.7 (force at the anchors plus the couples `½ L×F`), which is the same as
//! applying the force at the mid-point. The Jacobians are those of these rates, so the moments the
//! joint set applies (`Jᵀ·P`) do work `M·θ̇`.
//!
//! # Translation measure of a connector joint ([`TranslationMeasure::Body1Frame`])
//! The planar-friction connector (Abaqus PLANAR) measures its translations as Abaqus does:
//! in body 1's joint frame (the plate's) and at anchor 2 (the puck, Abaqus's node b),
//! `δ = F_1ᵀ·(p_2 − p_1) − δ0`. Its exact rate is
//!
//! ```text
//! δ̇ = F_1ᵀ·(ṗ_2 − ṗ_1 − ω_1×(p_2 − p_1)) = F_1ᵀ·[(v_2 + ω_2×(p_2 − c_2)) − (v_1 + ω_1×(p_2 − c_1))]
//! ```
//!
//! the relative velocity of the two bodies' material points at anchor 2: the joint's
//! translational force acts at anchor 2 on both bodies (equal and opposite, so the moment
//! balance is exact), and its Jacobian rows use the lever arms `p_2 − c_i`. The rotations
//! are measured as above, in `E`. Why (docs/planar_friction.md §5): with KJOINT2's
//! mid-point, a puck that has slid a distance `d` from anchor 1 receives the couple
//! `½·d·f1` of the normal force, which its blocked rotational stiffness carries by tilting
//! it, and the mid-plane it then slides in tilts with it: a 10 kg block pulled 6 m sank
//! 6 cm into its plate and its normal force fell by 2.6 %. On body 1's plane it neither
//! tilts nor sinks.

use nalgebra::{Matrix3, Matrix6, Quaternion, Rotation3, UnitQuaternion, Vector3, Vector6};
use std::f64::consts::PI;

/// Pose and velocity of a body, in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct BodyPose {
    /// Position of the body's origin.
    pub translation: Vector3<f64>,
    /// Orientation.
    pub rotation: UnitQuaternion<f64>,
    /// World centre of mass.
    pub com: Vector3<f64>,
    /// Linear velocity of the centre of mass.
    pub linvel: Vector3<f64>,
    /// Angular velocity.
    pub angvel: Vector3<f64>,
}

/// 0 when every value is finite, NaN otherwise: `x·0` is 0 for a finite `x` and NaN for an
/// infinite or NaN one, and a sum of zeros and NaNs is NaN as soon as one term is. A test of
/// many values is then one comparison of the sum (`== 0.0`) instead of a branch each. The
/// terms go to four sums, added at the end: a chain of `n/4 + 2` additions, not `n`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn zero_unless_not_finite(values: &[f64]) -> f64 {
    let mut sums = [0.0; 4];
    for (i, v) in values.iter().enumerate() {
        sums[i % 4] += v * 0.0;
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3])
}

impl BodyPose {
    /// Whether every number of the pose and velocities is finite.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn is_finite(&self) -> bool {
        let q = &self.rotation.coords;
        let sum = (zero_unless_not_finite(self.translation.as_slice())
            + zero_unless_not_finite(self.com.as_slice()))
            + (zero_unless_not_finite(self.linvel.as_slice())
                + zero_unless_not_finite(self.angvel.as_slice()))
            + zero_unless_not_finite(q.as_slice());
        sum == 0.0
    }

    /// A body at rest at the identity pose.
    pub fn identity() -> Self {
        BodyPose {
            translation: Vector3::zeros(),
            rotation: UnitQuaternion::identity(),
            com: Vector3::zeros(),
            linvel: Vector3::zeros(),
            angvel: Vector3::zeros(),
        }
    }

    /// Transforms a body-local point to world.
    pub fn point(&self, local: &Vector3<f64>) -> Vector3<f64> {
        self.translation + self.rotation * local
    }
}

/// How the rotation is measured (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub enum RotationMeasure {
    /// Swing-twist with an unwrapped twist about x.
    TwistX,
    /// Rotation vector, continued past π.
    RotationVector,
    /// Cardan angles of a universal joint: `Q = R_y(θy)·R_x(θx)·R_z(θz)`, the cross's y arm
    /// on body 1 and its z arm on body 2 (θx is the deviation of the arms from 90°).
    Cardan,
}

/// Where and in which frame the translations are measured (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub enum TranslationMeasure {
    /// KJOINT2: in the working frame `E`, the force acting at the anchors' mid-point.
    #[default]
    MidPoint,
    /// Abaqus's connector: in body 1's joint frame `F_1`, the force acting at anchor 2.
    Body1Frame,
}

/// The joint's attachment to its two bodies, fixed at creation.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct JointFrames {
    /// Anchor in body 1's local coordinates.
    pub local_anchor1: Vector3<f64>,
    /// Anchor in body 2's local coordinates.
    pub local_anchor2: Vector3<f64>,
    /// Joint frame attached to body 1, relative to the body.
    pub local_frame1: UnitQuaternion<f64>,
    /// Joint frame attached to body 2, relative to the body.
    pub local_frame2: UnitQuaternion<f64>,
    /// Initial displacement `δ0` (in the initial working frame).
    pub delta0: Vector3<f64>,
    /// Rotation measure.
    pub measure: RotationMeasure,
    /// Translation measure.
    pub translation: TranslationMeasure,
}

/// Continuity data of the rotation measure (previous θ, for unwrapping).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct MeasureState {
    prev_theta: Option<Vector3<f64>>,
    /// How far the rotation-vector measure's `θ` moved at its last measure, squared,
    /// `|θ − θ_prev|²` \[rad²\] (0 for the other measures; no square root per substep): a
    /// full relative turn about another axis than the one turned about jumps it
    /// (`rotation_vector`; the health checks say so).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    jump: f64,
}

impl MeasureState {
    /// How far the rotation-vector measure's `θ` moved at its last measure, squared
    /// \[rad²\] (0 for the other measures).
    pub(crate) fn jump_squared(&self) -> f64 {
        self.jump
    }

    /// Keeps a measure's `θ` for the next one to unwrap from.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn record(&mut self, measured: &Measured) {
        self.prev_theta = Some(measured.0);
    }
}

mod atan2;
mod twist_x4;
pub(crate) use twist_x4::measure_twist_x4;

/// Kinematics of a joint at one instant.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct JointKinematics {
    /// Working frame E (columns = its axes in world).
    pub frame: Rotation3<f64>,
    /// Frame of the translations `δ` (`E`, or body 1's joint frame: [`TranslationMeasure`]).
    pub translation_frame: Rotation3<f64>,
    /// World point the translational force acts at (the anchors' mid-point, or anchor 2).
    pub force_point: Vector3<f64>,
    /// World anchor of body 1.
    pub p1: Vector3<f64>,
    /// World anchor of body 2.
    pub p2: Vector3<f64>,
    /// `(δx, δy, δz, θx, θy, θz)`.
    pub q: [f64; 6],
    /// Time derivative of `q` (relative velocities in E).
    pub rate: [f64; 6],
    /// Jacobian of the rates with respect to body 1's (v, ω) (rows: q̇, in E). Its rotation
    /// rows × linear-velocity columns are zero (for `jac2` too), which the solver relies on.
    pub jac1: Matrix6<f64>,
    /// Jacobian of the rates with respect to body 2's (v, ω).
    pub jac2: Matrix6<f64>,
}

/// Builds a right-handed frame whose x axis is `x` (normalised); y is taken from the global
/// axis least aligned with x. Returns identity for a zero vector.
pub fn frame_from_x(x: &Vector3<f64>) -> UnitQuaternion<f64> {
    let n = x.norm();
    if !(n > 1e-12) {
        return UnitQuaternion::identity();
    }
    let ex = x / n;
    let helper = if ex.x.abs() <= ex.y.abs() && ex.x.abs() <= ex.z.abs() {
        Vector3::x()
    } else if ex.y.abs() <= ex.z.abs() {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let ez = ex.cross(&helper).normalize();
    let ey = ez.cross(&ex);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(Matrix3::from_columns(
        &[ex, ey, ez],
    )))
}

#[cfg_attr(not(debug_assertions), inline(always))]
fn wrap_pi(a: f64) -> f64 {
    // the common case (every angle the measure produces is already within a turn) without
    // the `fmod` of `rem_euclid`, a hundred instructions on the measure's hot path
    if a > -PI && a <= PI {
        return a;
    }
    let mut a = (a + PI).rem_euclid(2.0 * PI) - PI;
    if a <= -PI {
        a += 2.0 * PI;
    }
    a
}

/// The half rotation `q^{1/2}` of a unit quaternion (as a rotation: the sign is free), from
/// the half-angle of the representative with `w ≥ 0`: `(1 + w, v)/√(2·(1 + w))`, without
/// the sine and cosine of `from_scaled_axis(scaled_axis/2)`.
fn half_rotation(q: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
    let (w, v) = if q.w < 0.0 {
        (-q.w, -q.imag())
    } else {
        (q.w, q.imag())
    };
    let k = (2.0 * (1.0 + w)).sqrt();
    UnitQuaternion::new_unchecked(Quaternion::from_parts((1.0 + w) / k, v / k))
}

/// `exp(n·π·k/2)`: `k` half turns about the unit axis `n` (as a rotation, `π·k`), exactly:
/// `(cos(π·k/2), sin(π·k/2)·n)` is one of `(±1, 0)`, `(0, ±n)`.
fn half_turns(n: &Vector3<f64>, k: f64) -> UnitQuaternion<f64> {
    let (c, s) = match (k as i64).rem_euclid(4) {
        0 => (1.0, 0.0),
        1 => (0.0, 1.0),
        2 => (-1.0, 0.0),
        _ => (0.0, -1.0),
    };
    UnitQuaternion::new_unchecked(Quaternion::from_parts(c, n * s))
}

/// `R_x(θ/2)` for the unwrapped twist `θ = raw + 2π·m` of `t = (cos(raw/2), sin(raw/2)·x)`
/// given as `(tw, ti)` with `tw ≥ 0` (`turns = θ − raw = 2π·m`), without a sine or cosine:
/// the half rotation of `t` times `m` half turns about x.
#[cfg(test)]
fn half_twist(tw: f64, ti: f64, turns: f64) -> UnitQuaternion<f64> {
    let (a, b) = half_twist_parts(tw, ti, turns);
    UnitQuaternion::new_unchecked(Quaternion::new(a, b, 0.0, 0.0))
}

/// [`half_twist`] as `(cos(θ/4), sin(θ/4))`, its only non-zero components: `t` normalised,
/// its half rotation `(1 + w, v)/√(2·(1 + w))` (`w ≥ 0`) and the product with the half turns
/// `(c, s, 0, 0)` about x, `(a·c − b·s, a·s + b·c)`, all with x-only quaternions.
#[cfg_attr(not(debug_assertions), inline(always))]
fn half_twist_parts(tw: f64, ti: f64, turns: f64) -> (f64, f64) {
    // with n = |t| and s = n + t_w (t normalised: w = t_w/n, i = t_i/n),
    //   (1 + w)/√(2·(1 + w)) = s/√(2·n·s),   i/√(2·(1 + w)) = t_i/√(2·n·s):
    // one root and one reciprocal where normalising, then halving, took two roots and four
    // divisions (the same to a few ulp: `half_twist_parts_by_division`, its test)
    let n = (tw * tw + ti * ti).sqrt();
    let s = n + tw;
    let r = 1.0 / (2.0 * n * s).sqrt();
    let (a, b) = (s * r, ti * r);
    with_half_turns(a, b, turns)
}

/// `(a, b)`, the half twist `(cos, sin)` of the raw angle, turned by the half turns of
/// `turns` (the unwrapping's multiple of 2π, whose half is a multiple of π): `(a, b)`
/// itself within half a turn of none, else its product `(a·c − b·s, a·s + b·c)` with the
/// half turns' `(c, s)` (the same bits as the product for every `turns`).
#[cfg_attr(not(debug_assertions), inline(always))]
fn with_half_turns(a: f64, b: f64, turns: f64) -> (f64, f64) {
    // within half a turn of none (the twist not unwrapped past ±π): no half turn
    if turns.abs() < PI {
        return (a, b);
    }
    let (c, s) = match ((turns / (2.0 * PI)).round() as i64).rem_euclid(4) {
        0 => (1.0, 0.0),
        1 => (0.0, 1.0),
        2 => (-1.0, 0.0),
        _ => (0.0, -1.0),
    };
    (a * c - b * s, a * s + b * c)
}

/// The rates Jacobians of a joint's two sides, kept by their distinct blocks.
///
/// With `T` the rows of the translations' frame, `R` the map from the relative angular
/// velocity to `θ̇` and `a_s` the lever arm from side `s`'s centre of mass to the point the
/// translational force acts at (`v + ω×a = v − [a]×·ω`):
///
/// ```text
/// q̇ = J₁·(v₁, ω₁) + J₂·(v₂, ω₂),   J_s = σ_s·⎡T  L_s⎤,   L_s = −T·[a_s]×,   σ₁ = −1, σ₂ = +1
///                                           ⎣0   R ⎦
/// ```
///
/// so the two 6×6 (576 bytes, a quarter of them zeros and a half the same numbers up to
/// sign) are `T`, `R` and the two lever arms `a_s`: 24 numbers (192 bytes), from which
/// [`Self::lever`] forms `L_s` where a congruence needs it (the products with a vector
/// use `a_s` directly). The solver reads them in four passes a substep, at 10 000 joints
/// from memory: 8 lines a joint and substep fewer for 30 instructions more (cachegrind,
/// docs/performance_log.md, session 43; no change of time shown beyond the machine's
/// drift).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct RateJacobians {
    /// `T`: the translation rows' linear-velocity block (side 2's; side 1's is `−T`).
    pub t: Matrix3<f64>,
    /// `R`: the rotation rows' angular-velocity block (side 2's; side 1's is `−R`).
    pub r: Matrix3<f64>,
    /// `a_s` \[m\]: the lever arm of side 1 and side 2, from the side's centre of mass
    /// to the point the translational force acts at.
    pub arm: [Vector3<f64>; 2],
}

impl Default for RateJacobians {
    fn default() -> Self {
        RateJacobians {
            t: Matrix3::zeros(),
            r: Matrix3::zeros(),
            arm: [Vector3::zeros(); 2],
        }
    }
}

impl RateJacobians {
    /// `σ_s`: −1 for side 1 (`s = 0`), +1 for side 2.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn sign(s: usize) -> f64 {
        if s == 0 {
            -1.0
        } else {
            1.0
        }
    }

    /// `L_s = −T·[a_s]×`: the translation rows' angular-velocity block of side `s` before
    /// the sign `σ_s` (the same bits wherever it is formed).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn lever(&self, s: usize) -> Matrix3<f64> {
        lever(&self.t, &self.arm[s])
    }

    /// `J_s` as a 6×6 (rows: `q̇`; columns: the body's `(v, ω)`).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn matrix(&self, s: usize) -> Matrix6<f64> {
        let sign = Self::sign(s);
        let mut j = Matrix6::zeros();
        j.fixed_view_mut::<3, 3>(0, 0).copy_from(&(self.t * sign));
        j.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(self.lever(s) * sign));
        j.fixed_view_mut::<3, 3>(3, 3).copy_from(&(self.r * sign));
        j
    }

    /// `J_s·u` for a body's `u = (v, ω)`: `σ_s·(T·v + L_s·ω, R·ω)`, where
    /// `T·v + L_s·ω = T·v − T·(a_s × ω) = T·(v − a_s × ω)` (no `L_s` formed).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn mul(&self, s: usize, u: &Vector6<f64>) -> Vector6<f64> {
        let v = u.fixed_rows::<3>(0);
        let w = u.fixed_rows::<3>(3);
        let lin = self.t * (v - self.arm[s].cross(&w));
        let ang = self.r * w;
        let sign = Self::sign(s);
        Vector6::new(lin.x, lin.y, lin.z, ang.x, ang.y, ang.z) * sign
    }

    /// `J_sᵀ·p` for a joint's `p = (p_t, p_r)`: `σ_s·(Tᵀ·p_t, L_sᵀ·p_t + Rᵀ·p_r)`, where
    /// `L_sᵀ = −[a_s]×ᵀ·Tᵀ = [a_s]×·Tᵀ`, so `L_sᵀ·p_t = a_s × (Tᵀ·p_t)` (no `L_s` formed).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn tr_mul(&self, s: usize, p: &Vector6<f64>) -> Vector6<f64> {
        let pt = p.fixed_rows::<3>(0);
        let pr = p.fixed_rows::<3>(3);
        let lin = self.t.tr_mul(&pt);
        let ang = self.arm[s].cross(&lin) + self.r.tr_mul(&pr);
        let sign = Self::sign(s);
        Vector6::new(lin.x, lin.y, lin.z, ang.x, ang.y, ang.z) * sign
    }
}

/// `−T·[a]×`, row by row: row `r` of `T·[a]×` is `t_rᵀ·[a]× = ([a]×ᵀ·t_r)ᵀ = (t_r × a)ᵀ`
/// (`[a]×` is antisymmetric), so row `r` of `−T·[a]×` is `(a × t_r)ᵀ`: six products and
/// three differences a row, where the 3×3 product took nine products (three by the zeros
/// of `[a]×`) and six sums, then a negation.
#[cfg_attr(not(debug_assertions), inline(always))]
fn lever(t: &Matrix3<f64>, a: &Vector3<f64>) -> Matrix3<f64> {
    let row = |r: usize| a.cross(&Vector3::new(t[(r, 0)], t[(r, 1)], t[(r, 2)]));
    let (r0, r1, r2) = (row(0), row(1), row(2));
    Matrix3::new(r0.x, r0.y, r0.z, r1.x, r1.y, r1.z, r2.x, r2.y, r2.z)
}

/// `q·x̂`, body-frame x axis of the unit quaternion `q = (w, v)` in world: the first column of
/// its rotation matrix, `(1 − 2(y² + z²), 2(xy + wz), 2(xz − wy))`, where the general
/// rotation of a vector (`v + 2w·(q_v × v) + 2·q_v × (q_v × v)`) multiplies by the zeros of x̂.
#[cfg(test)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn x_axis(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    Vector3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y + w * z),
        2.0 * (x * z - w * y),
    )
}

/// `q·(a + b·i)` for a unit quaternion `q = (w, x, y, z)` and a rotation about x
/// `(a, b, 0, 0)`: `q·i = (−x, w, z, −y)`, so `a·q + b·q·i` is
/// `(a·w − b·x, a·x + b·w, a·y + b·z, a·z − b·y)`: eight products where the general product
/// takes sixteen.
#[cfg(test)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn times_x_rotation(q: &UnitQuaternion<f64>, a: f64, b: f64) -> UnitQuaternion<f64> {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    UnitQuaternion::new_unchecked(Quaternion::new(
        a * w - b * x,
        a * x + b * w,
        a * y + b * z,
        a * z - b * y,
    ))
}

/// Measures the joint at the current poses and updates the unwrapping state.
pub fn measure(
    frames: &JointFrames,
    b1: &BodyPose,
    b2: &BodyPose,
    state: &mut MeasureState,
) -> JointKinematics {
    let mut jac = RateJacobians::default();
    let rotation = measure_rotation(frames, &b1.rotation, &b2.rotation, state);
    let m = measure_with_rotation(frames, b1, b2, &rotation, &mut jac);
    let (jac1, jac2) = (jac.matrix(0), jac.matrix(1));
    let (p1, p2) = anchors(frames, b1, b2);
    JointKinematics {
        frame: rotation.1.to_rotation_matrix(),
        translation_frame: Rotation3::from_matrix_unchecked(jac.t.transpose()),
        force_point: m.force_point,
        p1,
        p2,
        q: m.q,
        rate: m.rate,
        jac1,
        jac2,
    }
}

/// What [`measure_with_rotation`] gives the substep, which keeps it for every joint from
/// its measure stage to its prepare stage. Not kept (80 bytes a joint and substep less to
/// write and read): the working frame `E`, which the rotation measure gives
/// ([`Measured`]), and the world anchors, which [`anchors`] gives again where a readout or
/// a connector reads them.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct JointMotion {
    /// World point the translational force acts at (the anchors' mid-point, or anchor 2).
    pub force_point: Vector3<f64>,
    /// `(δx, δy, δz, θx, θy, θz)`.
    pub q: [f64; 6],
    /// Time derivative of `q`.
    pub rate: [f64; 6],
}

impl JointMotion {
    /// Whether every entry of `q` and `rate` is finite ([`zero_unless_not_finite`]: one
    /// comparison instead of twelve branches).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn is_finite(&self) -> bool {
        zero_unless_not_finite(&self.q) + zero_unless_not_finite(&self.rate) == 0.0
    }
}

/// The swing `S` taking the unit vector `a` onto the unit vector `b` (the smallest
/// rotation), its half `S^{1/2}` and its rotation vector `φ·n̂`; `None` when they are
/// antiparallel. With `c = a·b = cos φ` and `n = a×b = sin φ·n̂`:
///
/// ```text
/// S = (1 + c, n) / √(2·(1 + c))                 (w = cos(φ/2) ≥ 0)
/// S^{1/2} = (1 + S_w, S_v) / √(2·(1 + S_w))      (the half-angle of a unit quaternion)
/// φ·n̂ = n · atan2(|n|, c) / |n|                  (→ n as |n| → 0)
/// ```
///
/// Square roots and one `atan2`, where `rotation_between` + `scaled_axis` +
/// `from_scaled_axis` took an `acos`, an `atan2` and two sine–cosine pairs; and the `acos`
/// of `c` read swings below 1.5e-8 rad as 0 (`c` rounds to 1), which `atan2(|n|, c)` keeps
/// to full relative precision.
#[cfg(test)]
fn swing_between(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
) -> Option<(UnitQuaternion<f64>, UnitQuaternion<f64>, Vector3<f64>)> {
    let c = a.dot(b);
    if !(1.0 + c > 1e-12) {
        return None;
    }
    let n = a.cross(b);
    let k = (2.0 * (1.0 + c)).sqrt();
    let swing = UnitQuaternion::new_unchecked(Quaternion::from_parts((1.0 + c) / k, n / k));
    let half = half_rotation(&swing);
    let sn = n.norm();
    let s_vec = if sn > 0.0 {
        n * angle_over_sine(sn, c)
    } else {
        Vector3::zeros()
    };
    Some((swing, half, s_vec))
}

/// `atan2(s, c)/s` for `s > 0` (the swing's angle over its sine, `|n|`). A blocked swing
/// (a revolute joint's) is of the order of its penalty's deflection, far below 1e-3 rad:
/// there `c > 0` and with `x = s/c`, `atan2(s, c) = atan(x)` and
///
/// ```text
/// atan(x)/x = 1 − x²/3 + x⁴/5 − x⁶/7 + …   (alternating, terms decreasing for |x| < 1)
/// ```
///
/// so `(1 − x²/3 + x⁴/5)/c` is within `x⁶/7 < 1.5e-19` relative of it for `x < 1e-3`,
/// below the round-off of the `atan2` it replaces (a libm call of a hundred instructions).
#[cfg_attr(not(debug_assertions), inline(always))]
fn angle_over_sine(s: f64, c: f64) -> f64 {
    if c > 0.0 && s < 1e-3 * c {
        let x = s / c;
        let x2 = x * x;
        (1.0 - x2 * (1.0 / 3.0 - x2 * 0.2)) / c
    } else {
        s.atan2(c) / s
    }
}

/// The world anchors `(p1, p2)` of a joint at the bodies' poses.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn anchors(
    frames: &JointFrames,
    b1: &BodyPose,
    b2: &BodyPose,
) -> (Vector3<f64>, Vector3<f64>) {
    (
        b1.point(&frames.local_anchor1),
        b2.point(&frames.local_anchor2),
    )
}

/// The rotations of a joint (its relative rotation `θ` and working frame `E`) from the two
/// bodies' rotations, its measure state brought up to date: the first part of
/// [`measure`], a chain of square roots, divisions and an `atan2` (about 200 cycles
/// of latency for some 150 instructions) that a processor overlaps between joints only when
/// the loop it runs in holds little else (the substep's measure stage runs it over every
/// joint before the rest, [`measure_with_rotation`]).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn measure_rotation(
    frames: &JointFrames,
    r1: &UnitQuaternion<f64>,
    r2: &UnitQuaternion<f64>,
    state: &mut MeasureState,
) -> Measured {
    let f1 = r1 * frames.local_frame1;
    let f2 = r2 * frames.local_frame2;
    // (θ, working frame E, map from the relative angular velocity ω2 − ω1 (world) to θ̇;
    // `None` = Eᵀ)
    let measured = match frames.measure {
        RotationMeasure::TwistX => twist_x(&f1, &f2, state),
        RotationMeasure::RotationVector => {
            let m = rotation_vector(&f1, &f2, state);
            state.jump = state.prev_theta.map_or(0.0, |p| (m.0 - p).norm_squared());
            m
        }
        RotationMeasure::Cardan => cardan(&f1, &f2, state),
    };
    state.record(&measured);
    measured
}

/// The rest of [`measure`] once [`measure_rotation`] has measured the rotations:
/// translations, rates and the Jacobians, written into `jac` (by their blocks,
/// [`RateJacobians`]: the substep keeps them in its solver's joint block).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn measure_with_rotation(
    frames: &JointFrames,
    b1: &BodyPose,
    b2: &BodyPose,
    rotation: &Measured,
    jac: &mut RateJacobians,
) -> JointMotion {
    let (theta, _, er, rot_map) = *rotation;
    let (p1, p2) = anchors(frames, b1, b2);
    let et = er.matrix().transpose();
    // the translations' frame and the point their force acts at
    let (tf, point) = match frames.translation {
        TranslationMeasure::MidPoint => (er, 0.5 * (p1 + p2)),
        TranslationMeasure::Body1Frame => {
            ((b1.rotation * frames.local_frame1).to_rotation_matrix(), p2)
        }
    };
    let tt = tf.matrix().transpose();
    let l = p2 - p1;
    let delta = tt * l - frames.delta0;
    let a1 = point - b1.com;
    let a2 = point - b2.com;
    // rates
    let v1 = b1.linvel + b1.angvel.cross(&a1);
    let v2 = b2.linvel + b2.angvel.cross(&a2);
    let rot = rot_map.unwrap_or(et);
    let drate = tt * (v2 - v1);
    let wrate = rot * (b2.angvel - b1.angvel);
    // Jacobians: q̇ = J1·(v1, ω1) + J2·(v2, ω2);  v + ω×a = v − [a]×·ω
    //   J2 = ⎡ T   −T·[a2]×⎤     J1 = ⎡−T    T·[a1]×⎤
    //        ⎣ 0     R     ⎦          ⎣ 0     −R    ⎦
    // (T = tt, R = rot), kept by their blocks (RateJacobians): the rotation rates do not
    // depend on the linear velocities, and both sides share T and R up to sign
    jac.t = tt;
    jac.r = rot;
    jac.arm = [a1, a2];

    JointMotion {
        force_point: point,
        q: [delta.x, delta.y, delta.z, theta.x, theta.y, theta.z],
        rate: [drate.x, drate.y, drate.z, wrate.x, wrate.y, wrate.z],
    }
}

/// A rotation measure's result: `θ`, the working frame `E` (as a quaternion and as a
/// matrix), and the map from the relative angular velocity `ω2 − ω1` (world) to `θ̇`
/// (`None` = `Eᵀ`).
pub(crate) type Measured = (
    Vector3<f64>,
    UnitQuaternion<f64>,
    Rotation3<f64>,
    Option<Matrix3<f64>>,
);

/// [`RotationMeasure::TwistX`]: the swing of body 1's x axis onto body 2's, then the twist
/// about x left after it, computed in body 1's joint frame, where the swing has no x
/// component. With `Q = F1⁻¹·F2` and `u = Q·x̂` (body 2's x axis seen from body 1's frame,
/// the first column of Q's matrix), `c = u_x` and `n = x̂ × u = (0, −u_z, u_y)`:
///
/// ```text
/// S_l = (1 + c, 0, −u_z, u_y)/√(2·(1 + c))       the swing x̂ → u; in world S = F1·S_l·F1⁻¹
///     = (1 + c, 0, −u_z, u_y)/√((1 + c)² + |n|²)
/// t   = (S·F1)⁻¹·F2 = S_l⁻¹·Q                    the twist (w and x components only)
/// E   = S^{1/2}·F1·R_x(θx/2) = F1·S_l^{1/2}·R_x(θx/2)
/// Eᵀ·(F1·φ_l) = R_x(−θx/2)·S_l^{−1/2}·φ_l = R_x(−θx/2)·φ_l     (φ_l is S_l's own axis)
/// ```
///
/// with `φ_l = n·atan2(|n|, c)/|n| = (0, φ_y, φ_z)` the swing's rotation vector in body 1's
/// frame and `R_x(−θx/2)` from the half twist `(a, b) = ±(cos(θx/4), sin(θx/4))`:
/// `cos(θx/2) = a² − b²`, `sin(θx/2) = 2ab`. The same quantities as the world form
/// (`twist_x_world`, which the test compares it with): where it took both world x axes, the
/// world swing, the products `S·F1` and `S^{1/2}·F1` and a pass through E's matrix, this
/// takes the one product `Q` and products with quaternions that have zeros. Antiparallel
/// axes (`1 + c ≤ 1e-12`): half a turn about body 1's y axis, `S_l = (0, 0, 1, 0)`,
/// `φ_l = (0, π, 0)`.
#[cfg_attr(not(debug_assertions), inline(always))]
fn twist_x(f1: &UnitQuaternion<f64>, f2: &UnitQuaternion<f64>, state: &MeasureState) -> Measured {
    let f1 = *f1;
    let q = f1.inverse() * f2;
    let (qw, qx, qy, qz) = (q.w, q.i, q.j, q.k);
    let c = 1.0 - 2.0 * (qy * qy + qz * qz);
    // n = (0, n_y, n_z) = (0, −u_z, u_y)
    let (ny, nz) = (-2.0 * (qx * qz - qw * qy), 2.0 * (qx * qy + qw * qz));
    // the swing S_l = (s_w, 0, s_y, s_z) and its rotation vector (0, φ_y, φ_z)
    let (sw, sy, sz, py, pz) = if 1.0 + c > 1e-12 {
        // `|(1 + c, n)| = √(2·(1 + c))` for exact inputs; the norm itself keeps S_l unit
        // near a half turn, where `1 + c` has lost its relative precision
        let sn2 = ny * ny + nz * nz;
        // one reciprocal of the norm for the three components (a division each before)
        let ik = 1.0 / ((1.0 + c) * (1.0 + c) + sn2).sqrt();
        let sn = sn2.sqrt();
        let r = if sn > 0.0 {
            angle_over_sine(sn, c)
        } else {
            0.0
        };
        ((1.0 + c) * ik, ny * ik, nz * ik, ny * r, nz * r)
    } else {
        (0.0, 1.0, 0.0, PI, 0.0)
    };
    // its half (s_w ≥ 0): (1 + s_w, s_v)/√(2·(1 + s_w)), by one reciprocal
    let ikh = 1.0 / (2.0 * (1.0 + sw)).sqrt();
    let (hw, hy, hz) = ((1.0 + sw) * ikh, sy * ikh, sz * ikh);
    // t = conj(S_l)·Q: w = s_w·q_w + s_v·q_v, x = s_w·q_x − (s_v × q_v)_x
    let t_w = sw * qw + (sy * qy + sz * qz);
    let t_i = sw * qx - (sy * qz - sz * qy);
    // t = ±(cos(raw/2), sin(raw/2)·x): the sign with w ≥ 0 puts raw in [−π, π]
    let (tw, ti) = if t_w < 0.0 { (-t_w, -t_i) } else { (t_w, t_i) };
    let raw = 2.0 * atan2::atan2(ti, tw);
    let prev = state.prev_theta.map_or(raw, |p| p.x);
    let twist = prev + wrap_pi(raw - prev);
    let (a, b) = half_twist_parts(tw, ti, twist - raw);
    // S_l^{1/2}·(a + b·i) = (a·h_w, b·h_w, a·h_y + b·h_z, a·h_z − b·h_y)
    let local = Quaternion::new(a * hw, b * hw, a * hy + b * hz, a * hz - b * hy);
    let e = UnitQuaternion::new_unchecked(f1.into_inner() * local);
    let (cos_h, sin_h) = (a * a - b * b, 2.0 * a * b);
    let s_y = cos_h * py + sin_h * pz;
    let s_z = cos_h * pz - sin_h * py;
    (
        Vector3::new(twist, s_y, s_z),
        e,
        e.to_rotation_matrix(),
        None,
    )
}

/// [`twist_x`] as it was computed in world coordinates (the swing of the two world x axes,
/// then the twist, then E and the swing's rotation vector in E from E's matrix): the
/// reference its test compares it with.
#[cfg(test)]
fn twist_x_world(
    f1: &UnitQuaternion<f64>,
    f2: &UnitQuaternion<f64>,
    state: &MeasureState,
) -> Measured {
    let (f1, f2) = (*f1, *f2);
    let x1 = x_axis(&f1);
    let x2 = x_axis(&f2);
    let (swing, half_swing, s_vec) = swing_between(&x1, &x2).unwrap_or_else(|| {
        // antiparallel axes: half a turn about body 1's y axis
        let swing = UnitQuaternion::from_axis_angle(&(f1 * Vector3::y_axis()), PI);
        let s_vec = swing.scaled_axis();
        (swing, UnitQuaternion::from_scaled_axis(s_vec * 0.5), s_vec)
    });
    // twist left after the swing, about body 2's x axis: t = (S·F1)⁻¹·F2 = conj(g)·F2,
    // of which only w = g_w·f_w + g_v·f_v and the x component of
    // g_w·f_v − f_w·g_v − g_v × f_v are needed (t is a rotation about x)
    let g = swing * f1;
    let t_w = g.w * f2.w + (g.i * f2.i + g.j * f2.j + g.k * f2.k);
    let t_i = g.w * f2.i - f2.w * g.i - (g.j * f2.k - g.k * f2.j);
    // t = ±(cos(raw/2), sin(raw/2)·x): the sign with w ≥ 0 puts raw in [−π, π]
    let (tw, ti) = if t_w < 0.0 { (-t_w, -t_i) } else { (t_w, t_i) };
    let raw = 2.0 * atan2::atan2(ti, tw);
    let prev = state.prev_theta.map_or(raw, |p| p.x);
    let twist = prev + wrap_pi(raw - prev);
    let (a, b) = half_twist_parts(tw, ti, twist - raw);
    let e = times_x_rotation(&(half_swing * f1), a, b);
    // the swing's rotation vector in E: `Eᵀ·φ`, with E's y and z columns
    let er = e.to_rotation_matrix();
    let m = er.matrix();
    let s_y = m[(0, 1)] * s_vec.x + m[(1, 1)] * s_vec.y + m[(2, 1)] * s_vec.z;
    let s_z = m[(0, 2)] * s_vec.x + m[(1, 2)] * s_vec.y + m[(2, 2)] * s_vec.z;
    (Vector3::new(twist, s_y, s_z), e, er, None)
}

/// [`RotationMeasure::RotationVector`]: the rotation vector of the relative rotation,
/// continued over full turns.
///
/// The continuation is that of the pose alone (the spec's path independence), and it is
/// continuous through a full turn only about the axis already turned about: on the sphere
/// `|θ| = 2π` every vector is the identity (the exponential's differential there keeps the
/// radial part of a change alone), so a relative rotation that completes a turn while
/// turning about another axis (a body spinning about z on a ball joint and tilting about
/// y) comes back out of the sphere along that other axis, and `θ` jumps (by 11 rad in a
/// Radioss analyst's trial, 2026-12-05); OpenRadioss's summed increments do not, but drift.
/// `MeasureState::jump` keeps the size of the last change, for the health checks' warning
/// (`KjointEventKind::RotationVectorJumped`).
#[cfg_attr(not(debug_assertions), inline(always))]
fn rotation_vector(
    f1: &UnitQuaternion<f64>,
    f2: &UnitQuaternion<f64>,
    state: &MeasureState,
) -> Measured {
    let (f1, f2) = (*f1, *f2);
    let rel = f1.inverse() * f2;
    let mut v = rel.scaled_axis();
    // the turn count k and its axis n: θ = n·(a + 2πk)
    let mut turns = (Vector3::x(), 0.0);
    if let Some(prev) = state.prev_theta {
        let a = v.norm();
        let n = if a > 1e-12 {
            v / a
        } else if prev.norm() > 1e-12 {
            prev.normalize()
        } else {
            Vector3::x()
        };
        // equivalent vectors n·(a + 2πk): pick the one closest to the previous θ
        let k = ((prev.dot(&n) - a) / (2.0 * PI)).round();
        v = n * (a + 2.0 * PI * k);
        turns = (n, k);
    }
    // E = F1·R(θ/2), R(θ/2) = exp(n·a/4)·exp(n·πk/2) as quaternions: the half
    // rotation of `rel` and a half turn about n for every turn
    let e = f1 * half_rotation(&rel) * half_turns(&turns.0, turns.1);
    (v, e, e.to_rotation_matrix(), None)
}

/// [`RotationMeasure::Cardan`]: the Cardan angles of a universal joint's cross.
#[cfg_attr(not(debug_assertions), inline(always))]
fn cardan(f1: &UnitQuaternion<f64>, f2: &UnitQuaternion<f64>, state: &MeasureState) -> Measured {
    let (f1, f2) = (*f1, *f2);
    let q = (f1.inverse() * f2).to_rotation_matrix();
    let m = q.matrix();
    // Q = R_y(a)·R_x(c)·R_z(b): its second row is (cos c·sin b, cos c·cos b, −sin c),
    // its third column (sin a·cos c, −sin c, cos a·cos c)
    let c = (-m[(1, 2)]).clamp(-1.0, 1.0).asin();
    let (a, b) = (m[(0, 2)].atan2(m[(2, 2)]), m[(1, 0)].atan2(m[(1, 1)]));
    // the free rotations a, b are continued over full turns
    let (a, b) = match state.prev_theta {
        Some(p) => (p.y + wrap_pi(a - p.y), p.z + wrap_pi(b - p.z)),
        None => (a, b),
    };
    // the cross's frame G = F1·R_y(a): x = the common normal of the two arms, y = the
    // arm of body 1; E turns it half-way towards the arm of body 2
    let g = f1 * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), a);
    let e = g * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.5 * c);
    // ω_rel = ȧ·y₁ + ċ·x_G + ḃ·z₂: in G, ω_G = (ċ, ȧ − ḃ·sin c, ḃ·cos c), so
    // θ̇ = (ω_G.x, ω_G.y + tan c·ω_G.z, ω_G.z/cos c) (c is blocked: cos c ≈ 1)
    let cos_c = c.cos().max(1e-6);
    let inv = Matrix3::new(
        1.0,
        0.0,
        0.0,
        0.0,
        1.0,
        c.sin() / cos_c,
        0.0,
        0.0,
        1.0 / cos_c,
    );
    let map = inv * g.to_rotation_matrix().matrix().transpose();
    (Vector3::new(c, a, b), e, e.to_rotation_matrix(), Some(map))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form swing equals nalgebra's `rotation_between` (and its half and rotation
    /// vector) wherever the `acos` of the latter is accurate, and keeps a swing of 1e-10 rad
    /// that the `acos` reads as 0.
    /// The products of the blocks are the products of the 6×6 they stand for, for both
    /// sides, with the zero block where the solver expects it.
    #[test]
    fn rate_jacobian_products_match_their_matrices() {
        let m = |seed: f64| {
            Matrix3::from_fn(|r, c| ((r * 3 + c) as f64 * 0.37 + seed).sin() * (1.0 + seed))
        };
        let jac = RateJacobians {
            t: m(0.1),
            r: m(0.7),
            arm: [Vector3::new(1.3, -0.2, 0.5), Vector3::new(-2.9, 0.4, 1.1)],
        };
        let u = Vector6::new(0.3, -1.2, 0.8, 2.0, -0.4, 0.9);
        for s in 0..2 {
            let full = jac.matrix(s);
            assert!(full.fixed_view::<3, 3>(3, 0).iter().all(|v| *v == 0.0));
            assert!((jac.mul(s, &u) - full * u).amax() < 1e-14);
            assert!((jac.tr_mul(s, &u) - full.transpose() * u).amax() < 1e-14);
            let sign = if s == 0 { -1.0 } else { 1.0 };
            assert_eq!(full.fixed_view::<3, 3>(0, 0), jac.t * sign);
            assert_eq!(full.fixed_view::<3, 3>(0, 3), jac.lever(s) * sign);
            let general = -jac.t * jac.arm[s].cross_matrix();
            assert!((jac.lever(s) - general).amax() < 1e-14);
        }
    }

    #[test]
    fn swing_between_equals_rotation_between_and_keeps_tiny_swings() {
        let x = Vector3::x();
        for (axis, angle) in [
            (Vector3::new(0.0, 1.0, 0.0), 0.3),
            (Vector3::new(0.2, -0.5, 0.8), 1.2),
            (Vector3::new(0.0, 0.6, -0.8), 2.9),
            (Vector3::new(1.0, 1.0, 1.0), 1e-3),
        ] {
            let b =
                UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle) * x;
            let (s, half, v) = swing_between(&x, &b).unwrap();
            let reference = UnitQuaternion::rotation_between(&x, &b).unwrap();
            // components (both have w ≥ 0), not angle_to, whose acos is blind below 1e-8
            let close =
                |p: &UnitQuaternion<f64>, q: &UnitQuaternion<f64>| (p.coords - q.coords).norm();
            assert!(close(&s, &reference) < 1e-9 * angle, "{angle}");
            assert!(close(&(half * half), &s) < 1e-14, "{angle}");
            assert!(
                (v - reference.scaled_axis()).norm() < 1e-9 * angle,
                "{angle}"
            );
            assert!((s * x - b).norm() < 1e-13, "{}", (s * x - b).norm());
        }
        // 1e-10 rad about z: nalgebra's acos gives 0, the closed form the angle to 1e-15
        let b = Vector3::new((1e-10f64).cos(), (1e-10f64).sin(), 0.0);
        assert_eq!(
            UnitQuaternion::rotation_between(&x, &b).unwrap().angle(),
            0.0
        );
        let (_, _, v) = swing_between(&x, &b).unwrap();
        assert!((v.z - 1e-10).abs() < 1e-15 * 1e-10 * 1e5, "{v}");
        assert!(swing_between(&x, &-x).is_none());
    }

    /// The closed forms of the measure (`lever`, `x_axis`, `times_x_rotation`, the twist's
    /// two components, the swing in E from the matrix, `half_twist_parts`) equal the
    /// general products they replace, on pseudo-random rotations and vectors of magnitudes
    /// from 1e-150 to 1e150, zeros and parallel vectors included.
    #[test]
    fn closed_forms_equal_the_general_products() {
        let mut unit_interval = crate::test_rand::xorshift(0x9e37_79b9_7f4a_7c15u64);
        let mut next = move || unit_interval() * 2.0 - 1.0;
        for case in 0..2000 {
            let mut unit =
                || UnitQuaternion::new_normalize(Quaternion::new(next(), next(), next(), next()));
            let (q, r) = (unit(), unit());
            let scale = 10f64.powf(150.0 * next());
            let mut a = Vector3::new(next(), next(), next()) * scale;
            let t = *r.to_rotation_matrix().matrix();
            match case % 5 {
                0 => a = Vector3::zeros(),
                1 => a = Vector3::new(t[(1, 0)], t[(1, 1)], t[(1, 2)]) * scale, // ∥ a row
                _ => {}
            }
            let general = -t * a.cross_matrix();
            let d = (lever(&t, &a) - general).amax();
            assert!(d <= 1e-15 * scale, "{case}: {d}");
            assert!((x_axis(&q) - q * Vector3::x()).amax() < 1e-15, "{case}");
            let (ca, cb) = (next(), next());
            let x_rot = Quaternion::new(ca, cb, 0.0, 0.0);
            let d = (times_x_rotation(&q, ca, cb).coords - (q.quaternion() * x_rot).coords).amax();
            assert!(d < 1e-15, "{case}: {d}");
            // the twist's components: conj(g)·f2
            let full = r.inverse() * q;
            let t_w = r.w * q.w + (r.i * q.i + r.j * q.j + r.k * q.k);
            let t_i = r.w * q.i - q.w * r.i - (r.j * q.k - r.k * q.j);
            assert!((t_w - full.w).abs() < 1e-15 && (t_i - full.i).abs() < 1e-15);
            // the swing in E from E's matrix
            let s = a / scale;
            let m = *q.to_rotation_matrix().matrix();
            let local = q.inverse() * s;
            let s_y = m[(0, 1)] * s.x + m[(1, 1)] * s.y + m[(2, 1)] * s.z;
            let s_z = m[(0, 2)] * s.x + m[(1, 2)] * s.y + m[(2, 2)] * s.z;
            assert!((s_y - local.y).abs() < 1e-15 && (s_z - local.z).abs() < 1e-15);
            // the half twist against the quaternion products it replaces
            let theta = 20.0 * next();
            let tq = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), theta);
            let (tw, ti) = if tq.w < 0.0 {
                (-tq.w, -tq.i)
            } else {
                (tq.w, tq.i)
            };
            let raw = 2.0 * ti.atan2(tw);
            let t = UnitQuaternion::new_normalize(Quaternion::new(tw, ti, 0.0, 0.0));
            let reference =
                half_rotation(&t) * half_turns(&Vector3::x(), ((theta - raw) / (2.0 * PI)).round());
            let (ha, hb) = half_twist_parts(tw, ti, theta - raw);
            assert!((ha - reference.w).abs() < 1e-15 && (hb - reference.i).abs() < 1e-15);
        }
    }

    /// The twist-swing measure computed in body 1's frame is the swing-twist split of
    /// `F1⁻¹·F2 = R(n, φ)·R_x(τ)` (`n ⊥ x`) that built it, and equals the world form it
    /// replaced (`twist_x_world`), on random frames: swings from 1e-12 rad to π − 1e-3 rad
    /// about random axes, twists up to 20 rad, a previous θx a few turns away, and random
    /// pairs of frames. Tolerances: every quantity is a chain of a few dozen roundings of
    /// numbers of order one, so a few 1e-15 absolute (1e-14 with the twist's magnitude
    /// added), except near a half-turn swing, where the swing's axis is ill-conditioned: the
    /// split itself moves by `ε/sin φ` when an axis moves by `ε` (the factor `1 + 0.1/gap`,
    /// `gap = π − φ`, a tolerance of `1e-15/gap` more), and the world form, which takes `1 + c = 1 + x1·x2` from two axes
    /// rounded apart, is off by up to `π·ε/(1 + c) ≈ 2π·ε/gap² < 1e-14/gap²` (4e-12 at
    /// `gap` = 0.0076, where the local form is within 1e-16 of the construction: the factor
    /// `1 + 1/gap²` against the world form only). Exactly antiparallel axes take the same half turn about body
    /// 1's y axis.
    #[test]
    fn twist_x_equals_the_world_form() {
        let mut unit_interval = crate::test_rand::xorshift(0x2545_f491_4f6c_dd1du64);
        let mut next = move || unit_interval() * 2.0 - 1.0;
        let (mut worst_truth, mut worst_world) = (0.0f64, 0.0f64);
        for case in 0..5000 {
            let unit = |next: &mut dyn FnMut() -> f64| {
                UnitQuaternion::new_normalize(Quaternion::new(next(), next(), next(), next()))
            };
            let f1 = unit(&mut next);
            let axis = nalgebra::Unit::new_normalize(Vector3::new(0.0, next(), next()));
            let swing_angle = match case % 3 {
                0 => 10f64.powf(-12.0 + 11.0 * next().abs()),
                1 => (PI - 1e-3) * next(),
                _ => 1e-3 * next(),
            };
            let twist_angle = 20.0 * next();
            let constructed = case % 7 != 6;
            let f2 = if constructed {
                f1 * UnitQuaternion::from_axis_angle(&axis, swing_angle)
                    * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), twist_angle)
            } else {
                unit(&mut next)
            };
            let fresh = MeasureState::default();
            let (raw, ..) = twist_x_world(&f1, &f2, &fresh);
            let turns = (3.0 * next()).round();
            let prev = |x: f64| MeasureState {
                prev_theta: Some(Vector3::new(x, 0.0, 0.0)),
                jump: 0.0,
            };
            let near = prev(raw.x + 2.0 * PI * turns + 0.5 * next());
            for st in [fresh, near] {
                let (t_ref, e_ref, er_ref, _) = twist_x_world(&f1, &f2, &st);
                let (t, e, er, map) = twist_x(&f1, &f2, &st);
                assert!(map.is_none());
                let gap = PI - (t_ref.y * t_ref.y + t_ref.z * t_ref.z).sqrt();
                let scale = (1.0 + 0.1 / gap) * (1.0 + 1.0 / (gap * gap));
                let dt = (t - t_ref).amax() / (1.0 + t_ref.x.abs()) / scale;
                let de = (e.coords - e_ref.coords).amax() / scale;
                let dm = (er.matrix() - er_ref.matrix()).amax() / scale;
                assert!(dt < 1e-14, "{case}: {t} {t_ref} {dt:e}");
                assert!(de < 1e-14 && dm < 2e-14, "{case}: {de:e} {dm:e}");
                worst_world = worst_world.max(dt).max(de);
            }
            if constructed {
                // the construction, with the twist continued from half a turn away at most
                let (t, e, ..) = twist_x(&f1, &f2, &prev(twist_angle + 0.5 * next()));
                let truth = Vector3::new(twist_angle, 0.0, 0.0)
                    + UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -0.5 * twist_angle)
                        * (axis.into_inner() * swing_angle);
                let e_truth = f1
                    * UnitQuaternion::from_axis_angle(&axis, 0.5 * swing_angle)
                    * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.5 * twist_angle);
                let gap = PI - swing_angle.abs();
                let scale = 1.0 + 0.1 / gap;
                let dt = (t - truth).amax() / (1.0 + twist_angle.abs()) / scale;
                // E as a rotation (the construction's quaternion may have the other sign)
                let de = (e.coords - e_truth.coords)
                    .amax()
                    .min((e.coords + e_truth.coords).amax())
                    / scale;
                assert!(dt < 1e-14, "{case}: {t} {truth} {dt:e}");
                assert!(de < 1e-14, "{case}: {e:?} {e_truth:?} {de:e} {gap}");
                worst_truth = worst_truth.max(dt).max(de);
            }
        }
        eprintln!(
            "twist_x: against the construction {worst_truth:e}, the world form {worst_world:e}"
        );
        // antiparallel x axes: a half turn about body 1's y axis then the twist
        let f1 = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.9);
        for tw in [0.0, 0.7, -2.0] {
            let f2 = f1
                * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), PI)
                * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), tw);
            let fresh = MeasureState::default();
            let (t_ref, e_ref, _, _) = twist_x_world(&f1, &f2, &fresh);
            let (t, e, _, _) = twist_x(&f1, &f2, &fresh);
            assert!((t - t_ref).amax() < 1e-14, "{tw}: {t} {t_ref}");
            assert!(
                (e.coords - e_ref.coords).amax() < 1e-14,
                "{tw}: {e:?} {e_ref:?}"
            );
        }
    }

    /// `angle_over_sine` equals `atan2(s, c)/s` to 1e-15 relative on both sides of its
    /// series' bound, on unit `(c, s)` of angles from 1e-300 to π and on scaled ones.
    #[test]
    fn angle_over_sine_equals_atan2_over_sine() {
        let mut next = crate::test_rand::xorshift(0x1234_5678_9abc_def1u64);
        for case in 0..5000 {
            let angle = match case % 4 {
                0 => 10f64.powf(-300.0 + 297.0 * next()),
                1 => 1e-3 * (0.5 + next()), // around the bound
                2 => PI * next(),
                _ => 10f64.powf(-9.0 + 6.0 * next()),
            };
            let scale = 10f64.powf(-100.0 + 200.0 * next());
            let (s, c) = (angle.sin() * scale, angle.cos() * scale);
            if !(s > 0.0) {
                continue;
            }
            let exact = s.atan2(c) / s;
            let d = (angle_over_sine(s, c) - exact).abs() / exact;
            assert!(d < 1e-15, "{angle} {scale}: {d}");
        }
    }

    /// `half_rotation` is the rotation by half the angle about the same axis.
    #[test]
    fn half_rotation_halves_the_angle() {
        for (axis, angle) in [
            (Vector3::new(0.3, -0.2, 0.9), 0.7),
            (Vector3::new(1.0, 0.0, 0.0), 3.0),
            (Vector3::new(0.0, 1.0, 1.0), 3.1),
            (Vector3::new(0.1, 0.2, 0.3), 1e-9),
        ] {
            let n = nalgebra::Unit::new_normalize(axis);
            let h = half_rotation(&UnitQuaternion::from_axis_angle(&n, angle));
            let expected = UnitQuaternion::from_axis_angle(&n, 0.5 * angle);
            // as rotations (the sign is free)
            let d = (h.coords - expected.coords)
                .norm()
                .min((h.coords + expected.coords).norm());
            assert!(d < 1e-15, "{angle}: {d}");
        }
    }

    /// The rotation-vector measure's working frame is `F1·exp(θ/2)` for its continued `θ`,
    /// over several turns in both directions (what `from_scaled_axis(θ/2)` gave).
    #[test]
    fn rotation_vector_frame_is_half_the_continued_rotation() {
        let frames = JointFrames {
            local_anchor1: Vector3::zeros(),
            local_anchor2: Vector3::zeros(),
            local_frame1: UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
            local_frame2: UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
            delta0: Vector3::zeros(),
            measure: RotationMeasure::RotationVector,
            translation: TranslationMeasure::MidPoint,
        };
        let axis = nalgebra::Unit::new_normalize(Vector3::new(0.3, -0.4, 0.85));
        for dir in [1.0, -1.0] {
            let mut state = MeasureState::default();
            for i in 0..60 {
                let angle = dir * 0.3 * i as f64;
                let b2 = BodyPose {
                    rotation: UnitQuaternion::from_axis_angle(&axis, angle),
                    ..BodyPose::identity()
                };
                let k = measure(&frames, &BodyPose::identity(), &b2, &mut state);
                let theta = Vector3::new(k.q[3], k.q[4], k.q[5]);
                assert!(
                    (theta.norm() - angle.abs()).abs() < 1e-9,
                    "{angle}: {theta}"
                );
                let f1 = frames.local_frame1;
                let expected =
                    (f1 * UnitQuaternion::from_scaled_axis(theta * 0.5)).to_rotation_matrix();
                assert!(
                    (k.frame.matrix() - expected.matrix()).norm() < 1e-12,
                    "{angle}"
                );
            }
        }
    }

    /// [`half_twist_parts`] as it was computed: `t` normalised by two divisions, then
    /// halved by two more (`(1 + w)/k`, `i/k`, `k = √(2·(1 + w))`).
    fn half_twist_parts_by_division(tw: f64, ti: f64) -> (f64, f64) {
        let n = (tw * tw + ti * ti).sqrt();
        let (w, i) = (tw / n, ti / n);
        let k = (2.0 * (1.0 + w)).sqrt();
        ((1.0 + w) / k, i / k)
    }

    /// The one-reciprocal form of [`half_twist_parts`] equals the division form it replaced
    /// within 4 ulp of 1 (both are unit up to round-off), on 200 000 half twists `(t_w, t_i)`
    /// with `t_w ≥ 0` over the whole half circle (the twist from 0 to ±π, crowded at both
    /// ends), unit and scaled by 1e-3…1e3 (`t` is unit only up to round-off in use).
    #[test]
    fn half_twist_parts_equals_the_division_form() {
        let mut next = crate::test_rand::xorshift(0x5851_f42d_4c95_7f2du64);
        for case in 0..200_000 {
            let u = next();
            let angle = match case % 3 {
                0 => PI * (u - 0.5),
                1 => 1e-9 * (u - 0.5),
                _ => (0.5 * PI - 1e-9 * u).copysign(u - 0.5),
            };
            let scale = if case % 2 == 0 {
                1.0
            } else {
                10f64.powf(6.0 * next() - 3.0)
            };
            let (tw, ti) = (scale * angle.cos(), scale * angle.sin());
            let (a, b) = half_twist_parts(tw, ti, 0.0);
            let (ar, br) = half_twist_parts_by_division(tw, ti);
            let d = (a - ar).abs().max((b - br).abs());
            assert!(
                d <= 4.0 * f64::EPSILON,
                "{case}: ({tw}, {ti}) {a} {ar} {b} {br} {d:e}"
            );
        }
    }

    /// `half_twist` is `R_x(θ/2)` for unwrapped twists over several turns, both signs.
    #[test]
    fn half_twist_equals_the_axis_angle_quaternion() {
        for theta in [
            0.0,
            0.4,
            -2.5,
            3.1,
            3.2,
            -3.2,
            7.0,
            -7.0,
            12.9,
            -20.0,
            2.0 * PI,
        ] {
            let t = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), theta);
            let (tw, ti) = if t.w < 0.0 { (-t.w, -t.i) } else { (t.w, t.i) };
            let raw = 2.0 * ti.atan2(tw);
            let h = half_twist(tw, ti, theta - raw);
            let expected = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.5 * theta);
            assert!(
                (h.coords - expected.coords).norm() < 1e-14,
                "{theta}: {h:?} {expected:?}"
            );
        }
    }
}
