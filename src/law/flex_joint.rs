//! Rotational law of an offshore riser **flex joint** (docs/flex_joint.md; keywords
//! `*FLEXJOINT`, `*SPRINGPRO`, `*FLEXPROADD`).
//!
//! A flex joint is a KJOINT2 spherical joint (type 1): its translations are blocked by the
//! KJOINT2 penalty elsewhere, and this module gives the moment of the three free
//! rotations. Everything is in the joint frame, in f64, with no rapier type.
//!
//! # Conventions
//!
//! - The joint's local **x axis is the riser axis**. `θ = (θx, θy, θz)` \[rad\] is the
//!   joint's rotation measure. In the decoupled and dynamic modes the joint set measures it
//!   as a **swing-twist** split about x ([`crate::kinematics`]): `(θy, θz)` is the rotation
//!   vector of the swing, the smallest rotation taking one body's axis onto the other's, so
//!   `|(θy, θz)|` is exactly the angle between the two axes (docs/flex_joint.md), and `θx` is the
//!   twist left about the axis. (The rotation vector's `|(θy, θz)|` is not that angle once
//!   there is torsion: 0.1 instead of 0.09588 at θ = (1, 0.1, 0).) In the classical mode it
//!   is the rotation vector, whose norm is the total rotation angle.
//! - **Torsion** is `θx`. **Bending** is the rotation about an axis in the y-z plane: the
//!   bending vector `b = (θy, θz)`, the bending angle `β = |b|`, the bending axis
//!   `e = b/β` (unit, in (y, z) components) and the tilt direction of the riser axis
//!   `t = (e_z, −e_y)` (the swing turns x into `cos β·x + sin β·(0, e_z, −e_y)`).
//! - **Sign**: the moment is the joint's internal moment, `M = +law(θ)`; a restoring law is
//!   `M = K·θ`, like KJOINT2's `F = K·δ`. The tangent stiffness is `∂M/∂θ` and the tangent
//!   damping `∂M/∂θ̇` (both positive semi-definite for restoring laws).
//!
//! # Modes
//!
//! | IPRO (`bending`) | IMAT (`dynamic`) | IPROT (`torsion`) | mode |
//! |---|---|---|---|
//! | law | none | none | [`FlexMode::Classical`]: `M = f(|θ|)·θ/|θ|` on the **total** rotation |
//! | law | none | law | [`FlexMode::Decoupled`]: bending `f_b(β)·e`, torsion `f_t(θx)` |
//! | law or none | record | law or none | [`FlexMode::Dynamic`]: static/dynamic bending, torsion `f_t(θx)` or `Ktor·θx`, damping `CP·θ̇x` |
//!
//! Multilinear laws (`*SPRINGPRO`) are [`Curve`]s of moment \[N·m\] versus angle \[rad\],
//! passing through (0, 0), extrapolated linearly beyond their last point. Magnitude laws
//! (classical and bending) are evaluated at the non-negative angle `|θ|` or `β`. The
//! torsion law is evaluated as `sign(θx)·f_t(|θx|)` (odd extension) when the table has no
//! negative angle, and as `f_t(θx)` when it does.
//!
//! ## Classical (IMAT = 0, IPROT = 0)
//!
//! ```text
//! a = |θ|,  n = θ/a
//! M = f(a)·n
//! K = f'(a)·n nᵀ + (f(a)/a)·(I − n nᵀ)      (f'(0)·I at a = 0)
//! E_stored = ∫₀ᵃ f
//! ```
//!
//! ## Decoupled (IPROT ≠ 0)
//!
//! ```text
//! M_yz = f_b(β)·e,    K_yz = f_b'(β)·e eᵀ + (f_b(β)/β)·(I − e eᵀ)
//! M_x  = f_t(θx),     K_xx = f_t'(θx)
//! ```
//!
//! ## Dynamic (IMAT ≠ 0, `*FLEXPROADD`, IFLAG = 1)
//!
//! Torsion: `M_x = f_t(θx)` when IPROT ≠ 0 (Ktor ignored), else `M_x = Ktor·θx`; plus the
//! torsion damping `CP·θ̇x` in both phases (tangent damping `diag(CP, 0, 0)`; dissipated
//! energy per evaluation `CP·θ̇x·Δθx`).
//!
//! Bending has two phases ([`FlexPhase`]). The switch from the quasi-static to the dynamic
//! phase is an explicit call, [`FlexJointLaw::switch_to_dynamic`], made by the caller at
//! the time it chooses; it is recorded in the state ([`FlexSwitch`]).
//!
//! - Quasi-static phase: with IPRO ≠ 0, the elastic multilinear law `f_b(β)·e` as in the
//!   decoupled mode; with IPRO = 0, the bilinear hysteretic law below acting on the bending
//!   vector itself (reference 0).
//! - At the switch, the bending vector `b_s` and bending moment `M_s` reached are frozen,
//!   and the hysteretic spring restarts from a virgin state around `b_s`.
//! - Dynamic phase: `M_yz = M_s + h(b − b_s)`, where `h` is the hysteretic law of the angle
//!   **variation** `φ = b − b_s`.
//!
//! ### The 2-D bilinear kinematic-hardening law `h(φ)`
//!
//! A 2-D elasto-plastic spring in the y-z plane (a vector return mapping, isotropic in the
//! plane) with linear kinematic (Prager) hardening:
//!
//! ```text
//! E  = Kdyn_ini                       elastic stiffness [N·m/rad]
//! My = Kdyn_ini·Angle_lim             yield moment [N·m]
//! H  = E·Kdyn_lim/(E − Kdyn_lim)      hardening modulus, so that E·H/(E+H) = Kdyn_lim
//! m  = E·(φ − φp)                     moment; φp = plastic variation
//! α  = H·φp                           back moment (centre of the elastic circle)
//! yield:  |m − α| ≤ My
//! ```
//!
//! Return mapping (backward Euler, exact for this law): trial `m* = E(φ − φp)`,
//! `ξ* = m* − α`; if `|ξ*| > My`: `n = ξ*/|ξ*|`, `Δλ = (|ξ*| − My)/(E + H)`,
//! `φp += Δλ·n`, `α += H·Δλ·n`, `m = m* − E·Δλ·n`. The consistent tangent is
//!
//! ```text
//! ∂m/∂φ = E·[ I − E/(E+H)·n nᵀ − (E·Δλ/|ξ*|)·(I − n nᵀ) ]
//! ```
//!
//! i.e. `Kdyn_lim` along `n` while yielding and `E·(1 − E·Δλ/|ξ*|)` across it. The
//! dissipated energy of a step is `My·Δλ` and the stored energy `|m|²/(2E) + |α|²/(2H)`.
//! `Kdyn_lim = Kdyn_ini` is purely elastic (H = ∞), `Kdyn_lim = 0` perfectly plastic.
//!
//! **Loop area.** On a 1-D cycle of the variation between `−a` and `+a` with
//! `a > φy = Angle_lim`, the loop is a parallelogram with elastic sides of slope
//! `Kdyn_ini` and height `2·My`, plastic sides of slope `Kdyn_lim`; the tip moment is
//! `My + Kdyn_lim·(a − φy)` and the energy dissipated per cycle is the loop's area,
//! `D_cycle` of docs/flex_joint.md §4 ([`FlexProAdd::loop_area`]); for `a ≤ φy` the
//! response is elastic and `D_cycle = 0`.
//! With linear kinematic hardening the loop is stable from the first reversal on.
//!
//! ### `Teta`
//!
//! The meaning of the "bending coefficient" `Teta` is not given by the source. It is read,
//! kept in [`FlexProAdd::teta`] and **ignored** by the law; the deck reader emits a
//! warning when it is non-zero.
//!
//! ### `IFLAG`
//!
//! Only `IFLAG = 1` (bilinear elasto-plastic) is implemented; other values are rejected by
//! [`FlexProAdd::validate`].

use super::curve::Curve;
use crate::error::{finite, PropertyError};
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// A `*FLEXPROADD` record: dynamic bending law, torsion stiffness and damping.
///
/// Units: stiffnesses in N·m/rad, angles in rad, damping in N·m·s/rad.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlexProAdd {
    /// `Ktor`: linear torsion stiffness \[N·m/rad\] (≥ 0), used when no torsion law (IPROT)
    /// is given: `M_x = Ktor·θx`. Default 0.
    #[serde(default)]
    pub torsion_stiffness: f64,
    /// `IFLAG`: law flag; only 1 (bilinear elasto-plastic) is supported. Default 1.
    #[serde(default = "iflag_bilinear")]
    pub iflag: i64,
    /// `Kdyn_ini`: initial (elastic) dynamic bending stiffness \[N·m/rad\] (> 0).
    pub kdyn_ini: f64,
    /// `Kdyn_lim`: asymptotic (post-yield) dynamic bending stiffness \[N·m/rad\],
    /// `0 ≤ Kdyn_lim ≤ Kdyn_ini`.
    pub kdyn_lim: f64,
    /// `Angle_lim`: critical angle variation `φy` \[rad\] (> 0); yield moment
    /// `My = Kdyn_ini·Angle_lim`.
    pub angle_lim: f64,
    /// `Teta`: "bending coefficient" of the source; read and **ignored** (its meaning is
    /// not documented). Default 0.
    #[serde(default)]
    pub teta: f64,
    /// `CP`: torsion damping coefficient \[N·m·s/rad\] (≥ 0): `M_x += CP·θ̇x`. Default 0.
    #[serde(default)]
    pub torsion_damping: f64,
}

fn iflag_bilinear() -> i64 {
    1
}

impl FlexProAdd {
    /// Checks the record: all values finite, `IFLAG = 1`, `Ktor ≥ 0`, `Kdyn_ini > 0`,
    /// `0 ≤ Kdyn_lim ≤ Kdyn_ini`, `Angle_lim > 0` (with a finite yield moment
    /// `Kdyn_ini·Angle_lim`), `CP ≥ 0`.
    pub fn validate(&self) -> Result<(), PropertyError> {
        finite("Ktor", self.torsion_stiffness)?;
        finite("Kdyn_ini", self.kdyn_ini)?;
        finite("Kdyn_lim", self.kdyn_lim)?;
        finite("Angle_lim", self.angle_lim)?;
        finite("Teta", self.teta)?;
        finite("CP", self.torsion_damping)?;
        if self.iflag != 1 {
            return Err(PropertyError::field(
                "IFLAG",
                self.iflag,
                "1 (bilinear elasto-plastic, the only law implemented)",
            ));
        }
        if self.torsion_stiffness < 0.0 {
            return Err(PropertyError::field(
                "Ktor",
                self.torsion_stiffness,
                "a stiffness >= 0 [N·m/rad]",
            ));
        }
        if self.kdyn_ini <= 0.0 {
            return Err(PropertyError::field(
                "Kdyn_ini",
                self.kdyn_ini,
                "a stiffness > 0 [N·m/rad]",
            ));
        }
        if self.kdyn_lim < 0.0 || self.kdyn_lim > self.kdyn_ini {
            return Err(PropertyError::field(
                "Kdyn_lim",
                self.kdyn_lim,
                format!("a stiffness in [0, Kdyn_ini = {}] [N·m/rad]", self.kdyn_ini),
            ));
        }
        if self.angle_lim <= 0.0 {
            return Err(PropertyError::field(
                "Angle_lim",
                self.angle_lim,
                "an angle variation > 0 [rad]",
            ));
        }
        if !self.yield_moment().is_finite() {
            // both finite, their product is not: name the larger
            let (field, value) = if self.angle_lim > self.kdyn_ini {
                ("Angle_lim", self.angle_lim)
            } else {
                ("Kdyn_ini", self.kdyn_ini)
            };
            return Err(PropertyError::field(
                field,
                value,
                format!(
                    "a value whose yield moment My = Kdyn_ini·Angle_lim = {:e}·{:e} is finite",
                    self.kdyn_ini, self.angle_lim
                ),
            ));
        }
        if self.torsion_damping < 0.0 {
            return Err(PropertyError::field(
                "CP",
                self.torsion_damping,
                "a damping coefficient >= 0 [N·m·s/rad]",
            ));
        }
        Ok(())
    }

    /// Yield moment `My = Kdyn_ini·Angle_lim` \[N·m\].
    pub fn yield_moment(&self) -> f64 {
        self.kdyn_ini * self.angle_lim
    }

    /// Kinematic hardening modulus `H = Kdyn_ini·Kdyn_lim/(Kdyn_ini − Kdyn_lim)`
    /// \[N·m/rad\] (`+∞` when `Kdyn_lim = Kdyn_ini`, 0 when `Kdyn_lim = 0`).
    pub fn hardening_modulus(&self) -> f64 {
        let d = self.kdyn_ini - self.kdyn_lim;
        if d <= 0.0 {
            f64::INFINITY
        } else {
            self.kdyn_ini * self.kdyn_lim / d
        }
    }

    /// Analytic area of the stabilised 1-D hysteresis loop for a cycle of the variation
    /// between `−a` and `+a` \[J\]: `D_cycle` of docs/flex_joint.md §4 (0 when
    /// `a ≤ Angle_lim`).
    ///
    /// ```
    /// use rapier_kjoint::law::FlexProAdd;
    /// let record = FlexProAdd {
    ///     torsion_stiffness: 0.0,
    ///     iflag: 1,
    ///     kdyn_ini: 4e6,   // [N·m/rad]
    ///     kdyn_lim: 1e6,   // [N·m/rad]
    ///     angle_lim: 1e-3, // φy [rad]: yield moment My = 4000 N·m
    ///     teta: 0.0,
    ///     torsion_damping: 0.0,
    /// };
    /// assert!(record.validate().is_ok());
    /// assert_eq!(record.yield_moment(), 4000.0);
    /// // a cycle of the bending variation between ±3 mrad dissipates D_cycle = 24 J
    /// assert!((record.loop_area(3e-3) - 24.0).abs() < 1e-9);
    /// assert_eq!(record.loop_area(0.5e-3), 0.0); // elastic below φy
    /// ```
    pub fn loop_area(&self, amplitude: f64) -> f64 {
        let a = amplitude.abs();
        if a <= self.angle_lim {
            0.0
        } else {
            4.0 * self.angle_lim * (a - self.angle_lim) * (self.kdyn_ini - self.kdyn_lim)
        }
    }

    /// One return mapping of the 2-D kinematic-hardening spring at variation `phi`,
    /// updating the plastic variation and back moment.
    fn hysteretic(
        &self,
        phi: Vector2<f64>,
        plastic: &mut Vector2<f64>,
        back: &mut Vector2<f64>,
    ) -> Hysteretic {
        let e = self.kdyn_ini;
        let h = self.hardening_modulus();
        let my = self.yield_moment();
        let trial = (phi - *plastic) * e;
        let xi = trial - *back;
        let xi_norm = xi.norm();
        let (moment, tangent, dissipated, yielding) = if h.is_finite() && xi_norm > my {
            let n = xi / xi_norm;
            let dl = (xi_norm - my) / (e + h);
            *plastic += n * dl;
            *back += n * (h * dl);
            let nn = n * n.transpose();
            let i = Matrix2::identity();
            let tangent = (i - nn * (e / (e + h)) - (i - nn) * (e * dl / xi_norm)) * e;
            (trial - n * (e * dl), tangent, my * dl, true)
        } else {
            (trial, Matrix2::identity() * e, 0.0, false)
        };
        let stored_back = if h.is_finite() && h > 0.0 {
            back.norm_squared() / (2.0 * h)
        } else {
            0.0
        };
        Hysteretic {
            moment,
            tangent,
            dissipated,
            yielding,
            stored: moment.norm_squared() / (2.0 * e) + stored_back,
        }
    }
}

struct Hysteretic {
    moment: Vector2<f64>,
    tangent: Matrix2<f64>,
    dissipated: f64,
    yielding: bool,
    stored: f64,
}

/// Which combination of laws a flex joint uses (see the module table).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FlexMode {
    /// IMAT = 0, IPROT = 0: one multilinear law on the total rotation angle.
    Classical,
    /// IMAT = 0, IPROT ≠ 0: multilinear bending and torsion laws, decoupled.
    Decoupled,
    /// IMAT ≠ 0: decoupled, with the `*FLEXPROADD` dynamic bending law and torsion damping.
    Dynamic,
}

/// Phase of the bending law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum FlexPhase {
    /// Quasi-static (equilibrium) phase, from the start until the switch.
    #[default]
    QuasiStatic,
    /// Dynamic phase, after [`FlexJointLaw::switch_to_dynamic`].
    Dynamic,
}

/// The resolved law of one flex joint element (docs/flex_joint.md).
///
/// The classical flex joint of the `*SPRINGPRO` example (law 3: 25 kN·m at 0.5°, 35 kN·m at
/// 1°): bent by 0.75° in the x-y plane of the joint (x = the riser axis), it carries the
/// moment the multilinear law gives there, 30 kN·m, about the bending axis.
///
/// ```
/// use nalgebra::Vector3;
/// use rapier_kjoint::law::flex_joint::{FlexJointInput, FlexJointState, FlexMode};
/// use rapier_kjoint::law::{Curve, FlexJointLaw};
/// let ipro = Curve::new([(0.0, 0.0), (0.00872665, 25000.0), (0.0174533, 35000.0)]).unwrap();
/// let law = FlexJointLaw::new(Some(ipro), None, None).unwrap();
/// assert_eq!(law.mode(), FlexMode::Classical);
/// let mut state = FlexJointState::default();
/// let theta = Vector3::new(0.0, 0.0, 0.75_f64.to_radians()); // rotation about z
/// let out = law.evaluate(&mut state, &FlexJointInput { theta, ..Default::default() });
/// assert!((out.bending_moment - 30000.0).abs() < 1.0, "{} N·m", out.bending_moment);
/// assert!((out.moment.z - 30000.0).abs() < 1.0);
/// assert!((out.bending_angle - 0.75_f64.to_radians()).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FlexJointLaw {
    /// `IPRO` law: moment \[N·m\] vs angle \[rad\]; on the total angle in the classical mode,
    /// on the bending angle otherwise (quasi-static phase when `dynamic` is set).
    #[serde(default)]
    pub bending: Option<Curve>,
    /// `IPROT` law: torsion moment \[N·m\] vs torsion angle \[rad\].
    #[serde(default)]
    pub torsion: Option<Curve>,
    /// `IMAT` record (`*FLEXPROADD`).
    #[serde(default)]
    pub dynamic: Option<FlexProAdd>,
}

/// The recorded static-to-dynamic switch.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct FlexSwitch {
    /// Time given by the caller at the switch \[s\].
    pub time: f64,
    /// Static bending vector `b_s = (θy, θz)` at the switch \[rad\].
    pub bending: Vector2<f64>,
    /// Static bending moment `M_s = (My, Mz)` at the switch \[N·m\].
    pub moment: Vector2<f64>,
    /// Bending energy stored at the switch \[J\].
    pub stored_energy: f64,
}

/// State of a flex joint kept between evaluations.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct FlexJointState {
    /// Current phase.
    pub phase: FlexPhase,
    /// The switch, once it happened.
    pub switch: Option<FlexSwitch>,
    /// Plastic angle variation `φp` of the hysteretic spring \[rad\] (y, z).
    pub plastic_variation: Vector2<f64>,
    /// Back moment `α = H·φp` of the hysteretic spring \[N·m\] (y, z).
    pub back_moment: Vector2<f64>,
    /// Bending vector `(θy, θz)` at the last evaluation \[rad\].
    pub last_bending: Vector2<f64>,
    /// Bending moment `(My, Mz)` at the last evaluation \[N·m\].
    pub last_bending_moment: Vector2<f64>,
    /// Bending energy stored at the last evaluation \[J\].
    pub last_bending_energy: f64,
    /// Total energy dissipated by the hysteretic bending law \[J\].
    pub dissipated_hysteresis: f64,
    /// Total energy dissipated by the torsion damping \[J\].
    pub dissipated_damping: f64,
}

/// Input of one evaluation, in the joint frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct FlexJointInput {
    /// Rotation `θ` \[rad\]: swing-twist (decoupled, dynamic modes) or rotation vector
    /// (classical), see the module docs.
    pub theta: Vector3<f64>,
    /// Increment `Δθ` since the last evaluation \[rad\] (used for the damping energy).
    pub dtheta: Vector3<f64>,
    /// Rate `θ̇` (relative angular velocity in the joint frame) \[rad/s\].
    pub rate: Vector3<f64>,
}

/// Output of one evaluation, in the joint frame.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct FlexJointOutput {
    /// Moment transmitted by the joint, `M = +law(θ) + CP·θ̇x·x` \[N·m\].
    pub moment: Vector3<f64>,
    /// Tangent stiffness `∂M/∂θ` \[N·m/rad\].
    pub stiffness: Matrix3<f64>,
    /// Tangent damping `∂M/∂θ̇` \[N·m·s/rad\]: `diag(CP, 0, 0)` or zero.
    pub damping: Matrix3<f64>,
    /// Bending angle `β = √(θy² + θz²)` \[rad\]: the angle between the two axes with the
    /// swing-twist measure.
    pub bending_angle: f64,
    /// Unit bending axis `e = (θy, θz)/β` (zero when `β = 0`).
    pub bending_axis: Vector2<f64>,
    /// Unit direction in the (y, z) plane towards which the riser axis tilts,
    /// `(e_z, −e_y)` (zero when `β = 0`).
    pub tilt_direction: Vector2<f64>,
    /// Magnitude of the bending moment `√(My² + Mz²)` \[N·m\].
    pub bending_moment: f64,
    /// Torsion angle `θx` \[rad\].
    pub torsion_angle: f64,
    /// Torsion moment `Mx`, damping included \[N·m\].
    pub torsion_moment: f64,
    /// Phase of the bending law.
    pub phase: FlexPhase,
    /// `true` when the hysteretic bending law yields in this evaluation.
    pub yielding: bool,
    /// Plastic angle variation `φp` after the evaluation \[rad\].
    pub plastic_variation: Vector2<f64>,
    /// Back moment `α` after the evaluation \[N·m\].
    pub back_moment: Vector2<f64>,
    /// Energy dissipated in this evaluation (hysteresis `My·Δλ` + damping
    /// `CP·θ̇x·Δθx`) \[J\].
    pub dissipated: f64,
    /// Total energy dissipated since the start \[J\].
    pub dissipated_total: f64,
    /// Elastic energy stored in the joint after the evaluation \[J\].
    pub elastic_energy: f64,
}

/// Whether a law passes through (0, 0), within 1e-9 of its largest moment.
pub(crate) fn passes_through_origin(c: &Curve) -> bool {
    let scale = c.points().fold(1.0_f64, |s, (_, y)| s.max(y.abs()));
    c.value(0.0).abs() <= 1e-9 * scale
}

/// A point `(angle, moment)` of a law.
pub(crate) type Pair = (f64, f64);

/// The first segment of a law along which the moment decreases (a negative stiffness), as
/// the index `k` of its first point and its two points `(x, y)`, `None` when the law never
/// falls. The extrapolation continues the end segments.
pub(crate) fn falling_segment(c: &Curve) -> Option<(usize, Pair, Pair)> {
    let pts: Vec<(f64, f64)> = c.points().collect();
    pts.windows(2)
        .enumerate()
        .find(|(_, w)| w[1].1 < w[0].1)
        .map(|(k, w)| (k, w[0], w[1]))
}

/// Moment, tangent and energy of a magnitude law at angle `a ≥ 0`.
fn magnitude_law(c: &Curve, a: f64) -> (f64, f64, f64) {
    (c.value(a), c.slope(a), c.integral_from_zero(a))
}

/// Torsion law: odd extension when the table has no negative angle.
fn torsion_law(c: &Curve, x: f64) -> (f64, f64, f64) {
    let has_negative = c.points().next().is_some_and(|(x0, _)| x0 < 0.0);
    if has_negative || x >= 0.0 {
        (c.value(x), c.slope(x), c.integral_from_zero(x))
    } else {
        (-c.value(-x), c.slope(-x), c.integral_from_zero(-x))
    }
}

/// Tangent of a radial law `M = f(a)·n`, `a = |v|`, `n = v/a`, in `D` dimensions.
fn radial_tangent2(v: Vector2<f64>, f: f64, df: f64) -> Matrix2<f64> {
    let a = v.norm();
    if a > 0.0 {
        let n = v / a;
        let nn = n * n.transpose();
        nn * df + (Matrix2::identity() - nn) * (f / a)
    } else {
        Matrix2::identity() * df
    }
}

/// What a law that misses the origin gives at angle 0, for its error: `M(0) = …`, and
/// where the law starts when its first point is not at angle 0 (the value is then the first
/// segment extended to 0, not a point the user wrote).
pub(crate) fn origin_miss(c: &Curve) -> String {
    let m0 = c.value(0.0);
    match c.points().next() {
        Some((x0, y0)) if x0 != 0.0 => {
            format!("M(0) = {m0} (the law starts at ({x0}, {y0}); its first segment extended to angle 0)")
        }
        _ => format!("M(0) = {m0}"),
    }
}

impl FlexJointLaw {
    /// Builds and validates a law (see [`FlexJointLaw::validate`]).
    pub fn new(
        bending: Option<Curve>,
        torsion: Option<Curve>,
        dynamic: Option<FlexProAdd>,
    ) -> Result<Self, PropertyError> {
        let law = FlexJointLaw {
            bending,
            torsion,
            dynamic,
        };
        law.validate()?;
        Ok(law)
    }

    /// Checks the law: a bending law (IPRO) or a `*FLEXPROADD` record (IMAT) is required;
    /// the multilinear laws must pass through (0, 0) and never fall (no segment of negative
    /// stiffness, which the implicit update refuses at run time as a joint system that is
    /// not positive definite); the `*FLEXPROADD` record must be
    /// valid ([`FlexProAdd::validate`]).
    pub fn validate(&self) -> Result<(), PropertyError> {
        if self.bending.is_none() && self.dynamic.is_none() {
            return Err(PropertyError::field(
                "IPRO",
                0,
                "a *SPRINGPRO bending law (IPRO != 0) when there is no *FLEXPROADD record (IMAT = 0)",
            ));
        }
        for (name, c) in [("IPRO", &self.bending), ("IPROT", &self.torsion)] {
            if let Some(c) = c {
                if !passes_through_origin(c) {
                    return Err(PropertyError::field(
                        name,
                        origin_miss(c),
                        "a moment-angle law passing through (0, 0)",
                    ));
                }
                if let Some((_, (x0, y0), (x1, y1))) = falling_segment(c) {
                    return Err(PropertyError::field(
                        name,
                        format!("law falling from ({x0}, {y0}) to ({x1}, {y1})"),
                        "a moment-angle law whose moment never decreases (a falling segment is \
                         a negative stiffness)",
                    ));
                }
            }
        }
        if let Some(d) = &self.dynamic {
            d.validate()?;
        }
        Ok(())
    }

    /// What a valid law does that its input most likely did not mean, in words (for a
    /// notice; each from its reader: the riser deck's `*FLEXJOINT`, a scene's
    /// `flex_joint`): a bending law with points at negative angles, which are never read
    /// (the moment is a law of the bending angle's magnitude, `β ≥ 0`); a bending law of
    /// zero moment at every angle it reads (in the classical mode no moment at all); no
    /// torsion law and `Ktor = 0` in the dynamic mode (the flex joint puts no stiffness on
    /// the riser's turn about its axis, only `CP`). An offshore engineer's trial, 2026-12-06: the deck
    /// noticed the first only, a scene none.
    pub fn notices(&self) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(c) = &self.bending {
            if let Some((x0, _)) = c.points().next() {
                if x0 < 0.0 {
                    out.push(format!(
                        "the bending law has points at negative angles (from {x0} rad), which \
                         are not used: the bending moment is a law of the bending angle's \
                         magnitude, β ≥ 0"
                    ));
                }
            }
            // (the points it reads, β ≥ 0)
            if c.points().filter(|(x, _)| *x >= 0.0).all(|(_, m)| m == 0.0) {
                let what = match self.mode() {
                    FlexMode::Classical => {
                        "in the classical mode, on the total rotation angle, the joint carries \
                         no moment at all"
                    }
                    FlexMode::Decoupled => "the joint carries no bending moment",
                    FlexMode::Dynamic => {
                        "the joint carries no bending moment in its quasi-static phase"
                    }
                };
                out.push(format!("the bending law is zero at every angle: {what}"));
            }
        }
        if let (None, Some(d)) = (&self.torsion, &self.dynamic) {
            if d.torsion_stiffness == 0.0 {
                out.push(format!(
                    "no torsion law and a torsion stiffness Ktor of 0: the flex joint puts no \
                     stiffness on the riser's turn about its axis, only its torsion damping \
                     CP = {} N·m·s/rad (SI)",
                    d.torsion_damping
                ));
            }
        }
        out
    }

    /// The mode selected by the laws present.
    pub fn mode(&self) -> FlexMode {
        if self.dynamic.is_some() {
            FlexMode::Dynamic
        } else if self.torsion.is_some() {
            FlexMode::Decoupled
        } else {
            FlexMode::Classical
        }
    }

    /// Switches the bending law from the quasi-static to the dynamic phase at `time` \[s\],
    /// around the bending vector and moment of the **last evaluation** (stored in
    /// `state`). The hysteretic spring restarts from a virgin state around that point.
    /// Returns `false` (and changes nothing) when the joint is already dynamic. In the
    /// classical and decoupled modes the switch is recorded but does not change the law.
    pub fn switch_to_dynamic(&self, state: &mut FlexJointState, time: f64) -> bool {
        if state.phase == FlexPhase::Dynamic {
            return false;
        }
        state.phase = FlexPhase::Dynamic;
        state.switch = Some(FlexSwitch {
            time,
            bending: state.last_bending,
            moment: state.last_bending_moment,
            stored_energy: state.last_bending_energy,
        });
        state.plastic_variation = Vector2::zeros();
        state.back_moment = Vector2::zeros();
        true
    }

    /// One evaluation at the rotation `input.theta`: updates `state` and returns the
    /// moment, tangents and outputs. See the module documentation for the equations.
    pub fn evaluate(&self, state: &mut FlexJointState, input: &FlexJointInput) -> FlexJointOutput {
        let theta = input.theta;
        let b = Vector2::new(theta.y, theta.z);
        let beta = b.norm();
        let axis = if beta > 0.0 {
            b / beta
        } else {
            Vector2::zeros()
        };

        let mut moment = Vector3::zeros();
        let mut stiffness = Matrix3::zeros();
        let mut damping = Matrix3::zeros();
        let mut energy = 0.0;
        let mut dissipated = 0.0;
        let mut yielding = false;

        match self.mode() {
            FlexMode::Classical => {
                // validate() guarantees a bending law here.
                if let Some(c) = &self.bending {
                    let a = theta.norm();
                    let (f, df, e) = magnitude_law(c, a);
                    if a > 0.0 {
                        let n = theta / a;
                        let nn = n * n.transpose();
                        moment = n * f;
                        stiffness = nn * df + (Matrix3::identity() - nn) * (f / a);
                    } else {
                        stiffness = Matrix3::identity() * df;
                    }
                    energy = e;
                    state.last_bending = b;
                    state.last_bending_moment = Vector2::new(moment.y, moment.z);
                    state.last_bending_energy = e;
                }
            }
            FlexMode::Decoupled | FlexMode::Dynamic => {
                // Torsion.
                let (mx, kx, ex) = if let Some(c) = &self.torsion {
                    torsion_law(c, theta.x)
                } else if let Some(d) = &self.dynamic {
                    let k = d.torsion_stiffness;
                    (k * theta.x, k, 0.5 * k * theta.x * theta.x)
                } else {
                    (0.0, 0.0, 0.0)
                };
                moment.x = mx;
                stiffness[(0, 0)] = kx;
                energy += ex;
                if let Some(d) = &self.dynamic {
                    let cp = d.torsion_damping;
                    moment.x += cp * input.rate.x;
                    damping[(0, 0)] = cp;
                    let dd = cp * input.rate.x * input.dtheta.x;
                    dissipated += dd;
                    state.dissipated_damping += dd;
                }

                // Bending.
                let (mb, kb, eb) = match (&self.dynamic, state.phase, &self.bending) {
                    (Some(d), FlexPhase::Dynamic, _) => {
                        let sw = state.switch.unwrap_or(FlexSwitch {
                            time: 0.0,
                            bending: Vector2::zeros(),
                            moment: Vector2::zeros(),
                            stored_energy: 0.0,
                        });
                        let h = d.hysteretic(
                            b - sw.bending,
                            &mut state.plastic_variation,
                            &mut state.back_moment,
                        );
                        dissipated += h.dissipated;
                        state.dissipated_hysteresis += h.dissipated;
                        yielding = h.yielding;
                        (
                            sw.moment + h.moment,
                            h.tangent,
                            sw.stored_energy + sw.moment.dot(&(b - sw.bending)) + h.stored,
                        )
                    }
                    (_, _, Some(c)) => {
                        let (f, df, e) = magnitude_law(c, beta);
                        (axis * f, radial_tangent2(b, f, df), e)
                    }
                    (Some(d), _, None) => {
                        let h =
                            d.hysteretic(b, &mut state.plastic_variation, &mut state.back_moment);
                        dissipated += h.dissipated;
                        state.dissipated_hysteresis += h.dissipated;
                        yielding = h.yielding;
                        (h.moment, h.tangent, h.stored)
                    }
                    (None, _, None) => (Vector2::zeros(), Matrix2::zeros(), 0.0),
                };
                moment.y = mb.x;
                moment.z = mb.y;
                stiffness.fixed_view_mut::<2, 2>(1, 1).copy_from(&kb);
                energy += eb;
                state.last_bending = b;
                state.last_bending_moment = mb;
                state.last_bending_energy = eb;
            }
        }

        FlexJointOutput {
            moment,
            stiffness,
            damping,
            bending_angle: beta,
            bending_axis: axis,
            tilt_direction: Vector2::new(axis.y, -axis.x),
            bending_moment: Vector2::new(moment.y, moment.z).norm(),
            torsion_angle: theta.x,
            torsion_moment: moment.x,
            phase: state.phase,
            yielding,
            plastic_variation: state.plastic_variation,
            back_moment: state.back_moment,
            dissipated,
            dissipated_total: state.dissipated_hysteresis + state.dissipated_damping,
            elastic_energy: energy,
        }
    }
}

#[cfg(test)]
mod tests;
