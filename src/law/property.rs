//! The KJOINT2 property (Radioss `/PROP/TYPE45`): joint type, blocked-DOF penalty settings
//! and the per-DOF law of every free DOF, with the defaults and validation rules of the
//! Radioss manual (docs/kjoint2.md §1).
//!
//! Units are whatever system the model uses (SI by default): stiffness in N/m or N·m/rad,
//! viscosity in N·s/m or N·m·s/rad, forces in N, moments in N·m, stops in m or rad.

use super::curve::Curve;
use crate::error::{finite, PropertyError};
use serde::{Deserialize, Serialize};

/// One of the six relative DOFs of a joint, in the joint's working frame E.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(rename_all = "lowercase")]
pub enum Dof {
    /// Translation along x.
    Dx = 0,
    /// Translation along y.
    Dy = 1,
    /// Translation along z.
    Dz = 2,
    /// Rotation about x.
    Rx = 3,
    /// Rotation about y.
    Ry = 4,
    /// Rotation about z.
    Rz = 5,
}

impl Dof {
    /// All six DOFs in the order dx, dy, dz, rx, ry, rz.
    pub const ALL: [Dof; 6] = [Dof::Dx, Dof::Dy, Dof::Dz, Dof::Rx, Dof::Ry, Dof::Rz];
    /// Index 0..6.
    pub fn index(self) -> usize {
        self as usize
    }
    /// `true` for rx, ry, rz.
    pub fn is_rotation(self) -> bool {
        self.index() >= 3
    }
    /// Short name (`dx` .. `rz`).
    pub fn name(self) -> &'static str {
        ["dx", "dy", "dz", "rx", "ry", "rz"][self.index()]
    }
    /// The SI unit of its displacement: `m` or `rad`.
    pub fn unit(self) -> &'static str {
        if self.is_rotation() {
            "rad"
        } else {
            "m"
        }
    }
    /// What acts along it, `force` or `moment`, and that quantity's SI unit, `N` or `N·m`.
    pub fn load(self) -> (&'static str, &'static str) {
        if self.is_rotation() {
            ("moment", "N·m")
        } else {
            ("force", "N")
        }
    }
    /// The DOF from its index 0..6.
    pub fn from_index(i: usize) -> Option<Dof> {
        Dof::ALL.get(i).copied()
    }
}

/// The nine KJOINT2 joint types (docs/kjoint2.md §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointType {
    /// 1: translations blocked, three free rotations.
    Spherical = 1,
    /// 2: one free rotation about x.
    Revolute = 2,
    /// 3: free translation along and rotation about x.
    Cylindrical = 3,
    /// 4: free translations in the y-z plane and rotation about its normal x.
    Planar = 4,
    /// 5: free rotations about y and z, x translation and rotation blocked.
    Universal = 5,
    /// 6: one free translation along x (prismatic; `"prismatic"` is read as this type in
    /// scene files and serialized data, the name rapier gives it).
    #[serde(alias = "prismatic")]
    Translational = 6,
    /// 7: free translations in the y-z plane, no rotation.
    Oldham = 7,
    /// 8: everything blocked.
    Fixed = 8,
    /// 9: everything free.
    Free = 9,
}

/// How far below 1 the cosine between the x axes of a joint's two initial frames may be on
/// a type whose only free rotation is about x ([`JointType::single_free_rotation`]): 1e-6,
/// 0.08° (a skew written with four or five digits).
pub(crate) const SKEW_X_PARALLEL: f64 = 1e-6;

impl JointType {
    /// The type from its Radioss number 1..=9.
    pub fn from_number(n: i64) -> Result<JointType, PropertyError> {
        use JointType::*;
        Ok(match n {
            1 => Spherical,
            2 => Revolute,
            3 => Cylindrical,
            4 => Planar,
            5 => Universal,
            6 => Translational,
            7 => Oldham,
            8 => Fixed,
            9 => Free,
            _ => return Err(PropertyError::UnknownJointType(n)),
        })
    }

    /// The Radioss number 1..=9.
    pub fn number(self) -> i64 {
        self as i64
    }

    /// `free[i]` is true when DOF `i` (dx, dy, dz, rx, ry, rz) is free (docs/kjoint2.md §2 table).
    pub fn free_dofs(self) -> [bool; 6] {
        use JointType::*;
        const F: bool = true;
        const B: bool = false;
        match self {
            Spherical => [B, B, B, F, F, F],
            Revolute => [B, B, B, F, B, B],
            Cylindrical => [F, B, B, F, B, B],
            Planar => [B, F, F, F, B, B],
            Universal => [B, B, B, B, F, F],
            Translational => [F, B, B, B, B, B],
            Oldham => [B, F, F, B, B, B],
            Fixed => [B, B, B, B, B, B],
            Free => [F, F, F, F, F, F],
        }
    }

    /// `true` when DOF `dof` is free for this type.
    pub fn is_free(self, dof: Dof) -> bool {
        self.free_dofs()[dof.index()]
    }

    /// Types whose only free rotation is about x: their angle is unwrapped over many turns
    /// and an initial angle from Skew2 may only be about x (the x axes of the two frames
    /// parallel: the cosine between them at least `1 − 1e-6`).
    pub fn single_free_rotation(self) -> bool {
        matches!(
            self,
            JointType::Revolute | JointType::Cylindrical | JointType::Planar
        )
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        use JointType::*;
        match self {
            Spherical => "spherical",
            Revolute => "revolute",
            Cylindrical => "cylindrical",
            Planar => "planar",
            Universal => "universal",
            Translational => "translational",
            Oldham => "oldham",
            Fixed => "fixed",
            Free => "free",
        }
    }
}

/// How far \[m or rad\] a limit at exactly 0 is moved ([`DofLaw::with_limits`], URDF and
/// MJCF limits): a stop of 0 means "no stop" in a KJOINT2 law, as in Radioss.
pub const ZERO_LIMIT: f64 = 1e-9;

/// The law of one free DOF: the three Radioss cards `K fct_K SD- SD+ Icomb`, `C fct_C`,
/// `Kf FF fct_FF` (or their rotational counterparts with `SA-`, `SA+`, `FM`).
///
/// Zero means "not set" everywhere, as in Radioss (docs/kjoint2.md §1). For a rotational DOF
/// read N·m/rad for N/m, rad for m, N·m for N.
///
/// ```
/// use rapier_kjoint::DofLaw;
/// // a drawer slide: 500 N/m spring, 20 N·s/m viscosity, stops at −0.1 m and +0.4 m,
/// // a friction spring of 1e4 N/m slipping at 5 N
/// let slide = DofLaw::spring(500.0)
///     .with_viscosity(20.0)
///     .with_stops(-0.1, 0.4)
///     .with_friction(1e4, 5.0);
/// assert!(slide.has_stops() && slide.friction_active());
/// assert_eq!(slide.stiffness_scale(), 500.0);
/// // friction needs both Kf > 0 and a friction force (or curve)
/// assert!(!DofLaw::default().with_friction(1e4, 0.0).friction_active());
/// ```
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DofLaw {
    /// `K` [N/m] (≥ 0): linear stiffness, or scale of [`Self::stiffness_curve`] (0 → 1 with
    /// a curve). A negative value is refused (a softening law is a curve whose slope falls).
    pub stiffness: f64,
    /// `fct_K`: force \[N\] vs displacement \[m\]; the force is `K·f(δ)`.
    pub stiffness_curve: Option<Curve>,
    /// `SD-` \[m\] (≤ 0): negative stop; 0 = no stop on that side.
    pub stop_min: f64,
    /// `SD+` \[m\] (≥ 0): positive stop; 0 = no stop on that side.
    pub stop_max: f64,
    /// `Icomb`: couple this DOF's stops with the other coupled DOFs of the same family
    /// (translations or rotations) into one circular/spherical stop (docs/kjoint2.md §4.3). It
    /// needs two or three coupled DOFs in the family, all with the same stops and all with
    /// friction or none (validated).
    pub coupled_stops: bool,
    /// `C` [N·s/m] (≥ 0): linear viscosity, or scale of [`Self::viscosity_curve`] (0 → 1 with
    /// a curve). A negative value is refused.
    pub viscosity: f64,
    /// `fct_C`: force \[N\] vs velocity [m/s]; the force is `C·h(δ̇)`.
    pub viscosity_curve: Option<Curve>,
    /// `Kf` [N/m]: stiffness of the friction spring, and of the stops when > 0.
    pub friction_stiffness: f64,
    /// `FF` \[N\]: friction force, or scale of [`Self::friction_curve`] (0 → 1 with a curve).
    pub friction: f64,
    /// `fct_FF`: friction force \[N\] vs displacement \[m\].
    pub friction_curve: Option<Curve>,
    /// `a` [kg or kg·m²] (≥ 0): the inertia of a rotor geared to this DOF (MuJoCo's joint
    /// `armature`, a motor's reflected inertia `I_rotor·n²`); 0 = none. Not a KJOINT2 field
    /// (Radioss has no card for it). Its force `F = a·q̈` (internal sign) resists every
    /// change of the DOF's rate: implicit over a substep, the impulse `−a·(q̇⁺ − q̇⁻)`, so
    /// the solve's `G = h·(h·K_t/β + C_t)` gains `a` on the DOF
    /// ([`crate::dynamics`]'s solve) and the DOF's effective inverse mass `w` becomes
    /// `w/(1 + a·w)`. Its kinetic energy `½·a·q̇²` is stored in the joint
    /// ([`crate::law::JointEnergy::kinetic`]). The critical damping of this DOF's stop,
    /// sticking friction spring or lock (`Cr·√(K·m)`, §4.6) takes `m = m_r + a`, the
    /// bodies' reduced mass or inertia and the rotor it moves with (Radioss' `m_r` alone
    /// left a geared DOF's stop damped at `Cr/2·√(m_r/(m_r + a))` of critical: a slider
    /// with a rotor nine times its mass bounced off its stop at 3.7 times the speed).
    pub armature: f64,
}

impl DofLaw {
    /// A linear spring of stiffness `k`.
    pub fn spring(k: f64) -> Self {
        DofLaw {
            stiffness: k,
            ..Default::default()
        }
    }
    /// Sets the stops `SD-` (≤ 0) and `SD+` (≥ 0); 0 means no stop on that side, as in
    /// Radioss (for rapier's limits, where 0 is a limit, see [`Self::with_limits`]).
    ///
    /// The stop's stiffness is the blocked one (`Kn`, or `KR` on a rotation), or, on a DOF
    /// with friction ([`Self::with_friction`]), the friction spring `Kf` (docs/kjoint2.md
    /// §4.2): a soft `Kf` makes a soft stop. Its damping is the property's `Cr` on
    /// `√(K·m)` (§4.6), light by default (`Cr` = 0.05): a stop the substep resolves (a
    /// `Kf` of a few hundred) bounces; a viscosity ([`Self::with_viscosity`]) settles it.
    ///
    /// At the blocked stiffness a stop is rigid: sized from the substep, its peak force in
    /// an impact grows as the substep shrinks (a car's suspension bottoming out on a 0.5 m
    /// drop: 50, 84 and 147 kN at 4, 8 and 16 substeps; a game developer's trial,
    /// 2026-12-06). For a bump stop whose force means something, give it a stiffness of its
    /// own ([`Self::with_stop_stiffness`]): its peak is then about `v·√(K·m)` at any
    /// substep. A stop in contact raises no event: the joint's state reads it
    /// ([`crate::JointState::status`], its `stop`); an overrun beyond the health bound is
    /// warned of ([`crate::dynamics::KjointEventKind::StopOverrun`]).
    #[must_use]
    pub fn with_stops(mut self, min: f64, max: f64) -> Self {
        self.stop_min = min;
        self.stop_max = max;
        self
    }
    /// Limits as rapier's joint limits (`limits([lower, upper])`) and URDF's: stops at
    /// `lower` ≤ 0 and `upper` ≥ 0 \[m or rad\] from the pose at insertion, **both acting**,
    /// a limit at 0 included (the DOF may not leave its initial value that way).
    ///
    /// [`Self::with_stops`] takes the Radioss convention, where 0 means no stop on that
    /// side: `with_stops(0.0, 1.0)` is a door with no stop when it closes. Here a limit of
    /// 0 is moved to ±[`ZERO_LIMIT`] (1e-9), a stop at the initial pose, as the URDF loader
    /// does. The values must bracket the pose at insertion (`lower ≤ 0 ≤ upper`, checked at
    /// insertion as the stops are); give a DOF without limits no call.
    ///
    /// ```
    /// use rapier_kjoint::{DofLaw, ZERO_LIMIT};
    /// let door = DofLaw::default().with_limits(0.0, 1.5);
    /// assert_eq!((door.stop_min, door.stop_max), (-ZERO_LIMIT, 1.5));
    /// // the Radioss form of the same numbers has no closing stop
    /// assert_eq!(DofLaw::default().with_stops(0.0, 1.5).stop_min, 0.0);
    /// ```
    #[must_use]
    pub fn with_limits(self, lower: f64, upper: f64) -> Self {
        let at_zero = |v: f64, side: f64| if v == 0.0 { side * ZERO_LIMIT } else { v };
        self.with_stops(at_zero(lower, -1.0), at_zero(upper, 1.0))
    }
    /// Couples the stops (`Icomb = 1`).
    #[must_use]
    pub fn with_coupled_stops(mut self) -> Self {
        self.coupled_stops = true;
        self
    }
    /// Sets a linear viscosity `C`.
    #[must_use]
    pub fn with_viscosity(mut self, c: f64) -> Self {
        self.viscosity = c;
        self
    }
    /// Sets the inertia `a` [kg or kg·m²] of a rotor geared to this DOF (MuJoCo's
    /// `armature`; [`Self::armature`]): a pendulum of inertia `I` about its pivot swings
    /// with the period `2π·√((I + a)/(m·g·l))`.
    #[must_use]
    pub fn with_armature(mut self, a: f64) -> Self {
        self.armature = a;
        self
    }
    /// A stiffness of its own for this DOF's stops, `k` \[N/m or N·m/rad\] (> 0): `Kf` of
    /// the friction spring, which is the stop (docs/kjoint2.md §4.2), leaving the friction
    /// force `FF` as it is (0 by default: no friction). A compliant stop, a bump stop or a
    /// door's buffer, whose peak force in an impact at speed `v` of a body of mass `m` is
    /// about `v·√(k·m)` at any substep that resolves it, where a stop at the blocked
    /// stiffness ([`Self::with_stops`]) is rigid.
    ///
    /// ```
    /// use rapier_kjoint::DofLaw;
    /// let bump = DofLaw::spring(3e4).with_stops(-0.1, 0.1).with_stop_stiffness(2e5);
    /// assert_eq!((bump.friction_stiffness, bump.friction), (2e5, 0.0));
    /// ```
    #[must_use]
    pub fn with_stop_stiffness(mut self, k: f64) -> Self {
        self.friction_stiffness = k;
        self
    }
    /// Sets the friction spring stiffness `Kf` and the friction force `FF`.
    ///
    /// `Kf` is also the stiffness of this DOF's stops (docs/kjoint2.md §4.2: beyond a stop
    /// the friction spring is the stop, its cap lifted), in place of the blocked `Kn`/`KR`
    /// the stops have without friction. A rod resting on its stop under a moment `M`
    /// overruns it by about `M/Kf` (`tests/stop_with_friction.rs`); a ragdoll's hips with
    /// `Kf` = 100 N·m/rad went 0.5 rad beyond their cone (a user trial, 2026-12-02): give
    /// a DOF with stops a `Kf` as stiff as the stop should be (at 1e4 N·m/rad those hips
    /// went 0.049 rad beyond it at 4 substeps).
    #[must_use]
    pub fn with_friction(mut self, kf: f64, ff: f64) -> Self {
        self.friction_stiffness = kf;
        self.friction = ff;
        self
    }

    /// The spring's force at `q = 0` \[N or N·m\] where its stiffness curve `fct_K` does not
    /// pass through (0, 0): `K·f(0)`, beyond 1e-9 of the curve's largest value (the joint
    /// starts preloaded, [`crate::KjointEventKind::SpringCurvePreload`]); `None` for a
    /// linear spring or a curve through (0, 0).
    pub fn spring_preload(&self) -> Option<f64> {
        let c = self.stiffness_curve.as_ref()?;
        let largest = c.points().fold(0.0f64, |m, (_, y)| m.max(y.abs()));
        let at_zero = c.value(0.0);
        (at_zero.abs() > 1e-9 * largest).then(|| self.stiffness_scale() * at_zero)
    }
    /// Scale of the stiffness: `K`, or 1 when a curve is given with `K = 0`.
    pub fn stiffness_scale(&self) -> f64 {
        scale(self.stiffness, self.stiffness_curve.is_some())
    }
    /// Scale of the viscosity: `C`, or 1 when a curve is given with `C = 0`.
    pub fn viscosity_scale(&self) -> f64 {
        scale(self.viscosity, self.viscosity_curve.is_some())
    }
    /// Scale of the friction: `FF`, or 1 when a curve is given with `FF = 0`.
    pub fn friction_scale(&self) -> f64 {
        scale(self.friction, self.friction_curve.is_some())
    }
    /// Friction is active only when `Kf > 0` and (`FF > 0` or a friction curve is given).
    pub fn friction_active(&self) -> bool {
        self.friction_stiffness > 0.0 && (self.friction > 0.0 || self.friction_curve.is_some())
    }
    /// `true` when at least one stop is set.
    pub fn has_stops(&self) -> bool {
        self.stop_min != 0.0 || self.stop_max != 0.0
    }

    /// `true` when the law of this DOF, free, is a linear spring and dashpot
    /// `F = K·q + C·q̇` and nothing else: no curve, no stop the law acts on
    /// (`SD+ > 0` or `SD- < 0`), no coupled stop, no active friction. When every free DOF's
    /// law is, and no lock acts, the law takes its short path ([`crate::law::evaluate`]: the
    /// same arithmetic without the tests of the mechanisms that are absent).
    pub(crate) fn is_linear(&self) -> bool {
        self.stiffness_curve.is_none()
            && self.viscosity_curve.is_none()
            && !self.coupled_stops
            && self.stop_max <= 0.0
            && self.stop_min >= 0.0
            && !self.friction_active()
    }

    /// The first field that differs from the default (no law), with its value as text.
    fn first_set_field(&self) -> Option<(&'static str, String)> {
        let d = DofLaw::default();
        let curve = |c: &Option<Curve>| {
            format!(
                "a curve of {} points",
                c.as_ref().map_or(0, |c| c.points().count())
            )
        };
        [
            (
                "stiffness",
                self.stiffness != d.stiffness,
                self.stiffness.to_string(),
            ),
            (
                "stiffness_curve",
                self.stiffness_curve.is_some(),
                curve(&self.stiffness_curve),
            ),
            (
                "stop_min",
                self.stop_min != d.stop_min,
                self.stop_min.to_string(),
            ),
            (
                "stop_max",
                self.stop_max != d.stop_max,
                self.stop_max.to_string(),
            ),
            ("coupled_stops", self.coupled_stops, "true".to_string()),
            (
                "viscosity",
                self.viscosity != d.viscosity,
                self.viscosity.to_string(),
            ),
            (
                "viscosity_curve",
                self.viscosity_curve.is_some(),
                curve(&self.viscosity_curve),
            ),
            (
                "friction_stiffness",
                self.friction_stiffness != d.friction_stiffness,
                self.friction_stiffness.to_string(),
            ),
            (
                "friction",
                self.friction != d.friction,
                self.friction.to_string(),
            ),
            (
                "friction_curve",
                self.friction_curve.is_some(),
                curve(&self.friction_curve),
            ),
            (
                "armature",
                self.armature != d.armature,
                self.armature.to_string(),
            ),
        ]
        .into_iter()
        .find(|(_, set, _)| *set)
        .map(|(f, _, v)| (f, v))
    }

    fn validate(&self, dof: Dof) -> Result<(), PropertyError> {
        let (sm, sp) = if dof.is_rotation() {
            ("SA-", "SA+")
        } else {
            ("SD-", "SD+")
        };
        let n = dof.name();
        let f = |name: &str, v: f64| finite(&format!("{n}.{name}"), v);
        f("stiffness (K)", self.stiffness)?;
        f(&format!("stop_min ({sm})"), self.stop_min)?;
        f(&format!("stop_max ({sp})"), self.stop_max)?;
        f("viscosity (C)", self.viscosity)?;
        f("friction_stiffness (Kf)", self.friction_stiffness)?;
        f("friction (FF/FM)", self.friction)?;
        f("armature", self.armature)?;
        if self.armature < 0.0 {
            return Err(PropertyError::field(
                format!("{n}.armature"),
                self.armature,
                format!(
                    "a value >= 0 [{}] (a rotor's inertia; 0 = none)",
                    if dof.is_rotation() { "kg·m²" } else { "kg" }
                ),
            ));
        }
        // a negative spring pushes the DOF away from q = 0 at every q (an unstable
        // equilibrium: the run diverges and its error blames the substep), a negative
        // viscosity feeds energy in; a softening law is a curve's falling slope instead
        let unit = if dof.is_rotation() { "N·m/rad" } else { "N/m" };
        if self.stiffness < 0.0 {
            return Err(PropertyError::field(
                format!("{n}.stiffness (K)"),
                self.stiffness,
                format!(
                    "a value >= 0 [{unit}, or the scale of the curve fct_K] (a negative spring \
                     pushes the joint away from q = 0 and the run diverges; give a softening \
                     law as a curve whose slope falls)"
                ),
            ));
        }
        if self.viscosity < 0.0 {
            return Err(PropertyError::field(
                format!("{n}.viscosity (C)"),
                self.viscosity,
                format!(
                    "a value >= 0 [{}, or the scale of the curve fct_C] (a negative \
                     viscosity feeds energy into the joint)",
                    if dof.is_rotation() {
                        "N·m·s/rad"
                    } else {
                        "N·s/m"
                    }
                ),
            ));
        }
        if let Some(c) = &self.viscosity_curve {
            dissipative(&format!("{n}.viscosity_curve (fct_C)"), c)?;
        }
        // a friction force is a capacity: its sign was dropped (`[[0, -0.337], …]` slipped
        // at +0.337 times `FF`, with no word; a Radioss analyst's trial, 2026-12-06)
        if let Some((x, y)) =
            (self.friction_curve.as_ref()).and_then(|c| c.points().find(|&(_, y)| y < 0.0))
        {
            return Err(PropertyError::field(
                format!("{n}.friction_curve (fct_FF)"),
                format!(
                    "{} at {}",
                    crate::figure::format_figure(y),
                    crate::figure::format_figure(x)
                ),
                "values >= 0: the friction force the DOF sticks up to, as a function of its \
                 displacement (its direction is the motion's)",
            ));
        }
        if self.stop_min > 0.0 {
            return Err(PropertyError::field(
                format!("{n}.stop_min ({sm})"),
                self.stop_min,
                "a value <= 0: the lower stop, the first value of `with_stops(min, max)` or \
                 `with_limits(lower, upper)` (0 = no negative stop with `with_stops`)",
            ));
        }
        if self.stop_max < 0.0 {
            return Err(PropertyError::field(
                format!("{n}.stop_max ({sp})"),
                self.stop_max,
                "a value >= 0: the upper stop, the second value of `with_stops(min, max)` or \
                 `with_limits(lower, upper)` (0 = no positive stop with `with_stops`)",
            ));
        }
        if self.friction_stiffness < 0.0 {
            return Err(PropertyError::field(
                format!("{n}.friction_stiffness (Kf)"),
                self.friction_stiffness,
                "a value >= 0",
            ));
        }
        if self.friction < 0.0 {
            return Err(PropertyError::field(
                format!("{n}.friction (FF/FM)"),
                self.friction,
                "a value >= 0",
            ));
        }
        if self.coupled_stops && (self.stop_min == 0.0 || self.stop_max == 0.0) {
            return Err(PropertyError::field(
                format!("{n}.coupled_stops (Icomb)"),
                1,
                format!("both {sm} and {sp} set (non-zero) on a coupled DOF"),
            ));
        }
        Ok(())
    }
}

fn scale(v: f64, has_curve: bool) -> f64 {
    if has_curve && v == 0.0 {
        1.0
    } else {
        v
    }
}

/// Which rule gives the blocked stiffness when `Kn = 0` (docs/kjoint2.md §5, see
/// [`crate::law::stiffness`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AutomaticStiffness {
    /// The crate's rule for its implicit update (default: builder, scene files, URDF robots):
    /// from the load each joint carries and the substep, stiff enough that joints hold their
    /// shape, bounded so that f32 pose noise stays small against the load
    /// ([`crate::law::stiffness::implicit_blocked_stiffness`]).
    #[default]
    Implicit,
    /// Radioss' rule for its explicit scheme (set by the Radioss deck reader, so that deck
    /// users compare with Radioss): the smaller of the two bodies' budgets `2m/(α·h²)`, shared
    /// among the automatic joints on a body
    /// ([`crate::law::stiffness::automatic_blocked_stiffness`]).
    Radioss,
}

/// A KJOINT2 property: the first card `Type Kn ScF Cr sens_ID` and the laws of the free
/// DOFs. Skew frames are geometry and belong to the joint, not to the property.
///
/// Zero means "default" for `kn`, `scale_factor` and `critical_damping`, as in Radioss
/// (docs/kjoint2.md §1).
///
/// ```
/// use rapier_kjoint::{Dof, DofLaw, JointType, KjointProperty};
/// let door = KjointProperty::new(JointType::Revolute)
///     .with_kn(1e6)                                           // blocked translations [N/m]
///     // closed at insertion, opening to 1.5 rad (`with_limits`: a limit at 0 acts)
///     .with_dof(Dof::Rx, DofLaw::default().with_limits(0.0, 1.5).with_friction(50.0, 0.5));
/// assert!(door.validate().is_ok());
/// // the defaults of 0: ScF → 10 with Kn > 0 (KR = Kn·max(ScF, L0²)), Cr → 0.05
/// assert_eq!(door.resolved_scale_factor(), 10.0);
/// assert_eq!(door.resolved_critical_damping(), 0.05);
/// assert!(!door.automatic_stiffness());
/// // a law on a blocked DOF is refused, naming it
/// let wrong = KjointProperty::new(JointType::Revolute).with_dof(Dof::Ry, DofLaw::spring(1.0));
/// assert!(wrong.validate().unwrap_err().to_string().contains("ry"));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KjointProperty {
    /// Joint type (which DOFs are blocked).
    #[serde(rename = "type")]
    pub joint_type: JointType,
    /// `Kn` [N/m]: penalty stiffness of the blocked translations; 0 = automatic from the
    /// substep (docs/kjoint2.md §5), by the rule [`Self::automatic`].
    #[serde(default)]
    pub kn: f64,
    /// The rule of the automatic stiffness (`Kn = 0`): [`AutomaticStiffness::Implicit`]
    /// (default) or [`AutomaticStiffness::Radioss`] (properties read from a Radioss deck).
    #[serde(default)]
    pub automatic: AutomaticStiffness,
    /// `ScF`: with `Kn = 0` scales both automatic stiffnesses (0 → 1), whatever the rule;
    /// with `Kn > 0` it is the rotational factor, `KR = Kn·max(ScF, L0²)` (0 → 10).
    #[serde(default)]
    pub scale_factor: f64,
    /// `Cr`: critical damping ratio in [0, 1] on blocked DOFs and on free DOFs while a stop,
    /// friction stick or lock acts (0 → 0.05).
    #[serde(default)]
    pub critical_damping: f64,
    /// `sens_ID`: the sensor that locks every DOF once active (`None` = no sensor).
    #[serde(default)]
    pub sensor: Option<u32>,
    /// Laws of the DOFs in the order dx, dy, dz, rx, ry, rz; only free DOFs use theirs.
    #[serde(default)]
    pub dofs: [DofLaw; 6],
}

impl KjointProperty {
    /// A property of the given type with every field at its default.
    pub fn new(joint_type: JointType) -> Self {
        KjointProperty {
            joint_type,
            kn: 0.0,
            automatic: AutomaticStiffness::Implicit,
            scale_factor: 0.0,
            critical_damping: 0.0,
            sensor: None,
            dofs: Default::default(),
        }
    }
    /// Sets `Kn` \[N/m\], the penalty stiffness of the blocked translations (and, times
    /// `max(ScF, L0²)` \[m²\], of the blocked rotations in N·m/rad); 0 = automatic from the
    /// substep by the rule [`Self::automatic`] (docs/kjoint2.md §5).
    #[must_use]
    pub fn with_kn(mut self, kn: f64) -> Self {
        self.kn = kn;
        self
    }
    /// Sets the rule of the automatic stiffness (`Kn = 0`).
    #[must_use]
    pub fn with_automatic(mut self, rule: AutomaticStiffness) -> Self {
        self.automatic = rule;
        self
    }
    /// Sets `ScF`: with `Kn = 0` a factor on both automatic stiffnesses (0 → 1); with
    /// `Kn > 0` the rotational factor \[m²\] of `KR = Kn·max(ScF, L0²)` (0 → 10).
    #[must_use]
    pub fn with_scale_factor(mut self, scf: f64) -> Self {
        self.scale_factor = scf;
        self
    }
    /// Sets `Cr`, the critical damping ratio in \[0, 1\] (no unit; 0 → 0.05): a damper
    /// `Cr·√(K_t·m_r)` on the blocked DOFs, and on a free DOF while a stop, friction stick
    /// or the sensor lock acts on it (docs/kjoint2.md §4.6).
    #[must_use]
    pub fn with_critical_damping(mut self, cr: f64) -> Self {
        self.critical_damping = cr;
        self
    }
    /// Sets the sensor id.
    #[must_use]
    pub fn with_sensor(mut self, sensor: u32) -> Self {
        self.sensor = Some(sensor);
        self
    }
    /// Sets the law of one DOF.
    #[must_use]
    pub fn with_dof(mut self, dof: Dof, law: DofLaw) -> Self {
        self.dofs[dof.index()] = law;
        self
    }
    /// The law of one DOF.
    pub fn dof(&self, dof: Dof) -> &DofLaw {
        &self.dofs[dof.index()]
    }

    /// The free DOFs whose spring curve does not pass through (0, 0), with the force it
    /// gives at `q = 0` ([`DofLaw::spring_preload`]): the joint starts preloaded by it.
    pub fn spring_preloads(&self) -> impl Iterator<Item = (Dof, f64)> + '_ {
        (Dof::ALL.into_iter())
            .filter(|&d| self.joint_type.is_free(d))
            .filter_map(|d| self.dof(d).spring_preload().map(|f| (d, f)))
    }

    /// Checks that the sensor this property names (if any) exists: `exists(id)` says whether
    /// a sensor of that id was added. A joint may be inserted before its sensor, so the
    /// joint set calls it when it starts stepping, for every joint
    /// ([`crate::error::SimError::UnknownSensor`] names the joint and the sensor).
    pub fn check_sensor_reference(
        &self,
        joint: &str,
        exists: impl Fn(u32) -> bool,
    ) -> Result<(), crate::error::SimError> {
        match self.sensor {
            Some(id) if !exists(id) => Err(crate::error::SimError::UnknownSensor {
                joint: joint.to_string(),
                sensor: id,
            }),
            _ => Ok(()),
        }
    }

    /// `Cr` with its default applied (0 → 0.05).
    pub fn resolved_critical_damping(&self) -> f64 {
        if self.critical_damping == 0.0 {
            0.05
        } else {
            self.critical_damping
        }
    }

    /// `ScF` with its default applied: 0 → 1.0 when `Kn = 0`, 0 → 10.0 when `Kn > 0`.
    pub fn resolved_scale_factor(&self) -> f64 {
        match (self.scale_factor == 0.0, self.kn > 0.0) {
            (false, _) => self.scale_factor,
            (true, false) => 1.0,
            (true, true) => 10.0,
        }
    }

    /// `true` when a free DOF has an independent stop (`SD+ > 0` or `SD- < 0` without
    /// `Icomb`): the only DOFs [`crate::law::predicted_stops`] acts on.
    pub(crate) fn has_independent_stops(&self) -> bool {
        let free = self.joint_type.free_dofs();
        (0..6).any(|i| {
            let law = &self.dofs[i];
            free[i] && !law.coupled_stops && (law.stop_max > 0.0 || law.stop_min < 0.0)
        })
    }

    /// `true` when a DOF has coupled stops (`Icomb`): the only part of the KJOINT2 law that
    /// writes its tangent stiffness off the diagonal (docs/kjoint2.md §4.3). Without them the
    /// law's stiffness and damping are diagonal by construction.
    pub(crate) fn has_coupled_stops(&self) -> bool {
        self.dofs.iter().any(|law| law.coupled_stops)
    }

    /// `true` when every free DOF's law is a linear spring and dashpot and nothing else
    /// ([`DofLaw::is_linear`]): no curve, stop, coupled stop or friction anywhere.
    pub(crate) fn linear_free_dofs(&self) -> bool {
        let free = self.joint_type.free_dofs();
        (0..6).all(|i| !free[i] || self.dofs[i].is_linear())
    }

    /// What the substep's stages ask of the property for every joint at every substep
    /// ([`PropertyShape`]), found once.
    pub(crate) fn shape(&self) -> PropertyShape {
        PropertyShape {
            independent_stops: self.has_independent_stops(),
            coupled_stops: self.has_coupled_stops(),
            linear_free_dofs: self.linear_free_dofs(),
        }
    }

    /// The free DOFs' armatures ([`DofLaw::armature`]), `None` where every one is 0 (kept
    /// by the joint, `Kjoint::armature`).
    pub(crate) fn armature(&self) -> Option<[f64; 6]> {
        // (a blocked DOF takes none: validated)
        if self.dofs.iter().all(|d| d.armature == 0.0) {
            return None;
        }
        Some(std::array::from_fn(|i| self.dofs[i].armature))
    }

    /// `true` when the blocked stiffness is computed from the substep (`Kn = 0`).
    pub fn automatic_stiffness(&self) -> bool {
        self.kn == 0.0
    }

    /// Checks every rule of docs/kjoint2.md §1 and returns the first violation. A blocked DOF takes
    /// no law (any field of its [`DofLaw`] set is refused, naming it): Radioss has no card for
    /// it, and the law would be silently ignored. [`crate::KjointSet::insert`] calls it.
    pub fn validate(&self) -> Result<(), PropertyError> {
        self.validate_stiffness_and_damping()?;
        self.validate_dofs()?;
        self.validate_coupled_stops()
    }

    /// `Kn`, `ScF` (and the `KR = Kn·ScF` they give) and `Cr`.
    fn validate_stiffness_and_damping(&self) -> Result<(), PropertyError> {
        finite("kn (Kn)", self.kn)?;
        finite("scale_factor (ScF)", self.scale_factor)?;
        finite("critical_damping (Cr)", self.critical_damping)?;
        if self.kn > 0.0 {
            // KR = Kn·ScF (the L0² term is checked when the joint is built)
            let scf = self.resolved_scale_factor();
            let kr = self.kn * scf;
            if !kr.is_finite() {
                let (field, value) = if self.scale_factor > self.kn {
                    ("scale_factor (ScF)", self.scale_factor)
                } else {
                    ("kn (Kn)", self.kn)
                };
                return Err(PropertyError::field(
                    field,
                    value,
                    format!(
                        "a value whose rotational stiffness KR = Kn·ScF = {:e}·{scf:e} is finite",
                        self.kn
                    ),
                ));
            }
        }
        if self.kn < 0.0 {
            return Err(PropertyError::field(
                "kn (Kn)",
                self.kn,
                "a value >= 0 (0 = automatic)",
            ));
        }
        if self.scale_factor < 0.0 {
            return Err(PropertyError::field(
                "scale_factor (ScF)",
                self.scale_factor,
                "a value >= 0 (0 = default)",
            ));
        }
        if !(0.0..=1.0).contains(&self.critical_damping) {
            return Err(PropertyError::field(
                "critical_damping (Cr)",
                self.critical_damping,
                "a value in [0, 1] (0 = default 0.05)",
            ));
        }
        Ok(())
    }

    /// The law of each free DOF; no law on a blocked DOF.
    fn validate_dofs(&self) -> Result<(), PropertyError> {
        let free = self.joint_type.free_dofs();
        for dof in Dof::ALL {
            if free[dof.index()] {
                self.dofs[dof.index()].validate(dof)?;
            } else if let Some((field, value)) = self.dofs[dof.index()].first_set_field() {
                // a blocked DOF takes no law: it would be silently ignored
                let free: Vec<&str> = Dof::ALL
                    .iter()
                    .filter(|d| self.joint_type.is_free(**d))
                    .map(|d| d.name())
                    .collect();
                return Err(PropertyError::field(
                    format!("{}.{field}", dof.name()),
                    value,
                    format!(
                        "no law: {} is blocked for a {} joint (free DOFs: {})",
                        dof.name(),
                        self.joint_type.name(),
                        if free.is_empty() {
                            "none".to_string()
                        } else {
                            free.join(", ")
                        }
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Coupled stops (`Icomb = 1`): at least two coupled DOFs in a family, friction on all
    /// of them or on none, and the same stop values on each.
    fn validate_coupled_stops(&self) -> Result<(), PropertyError> {
        let free = self.joint_type.free_dofs();
        for family in [[Dof::Dx, Dof::Dy, Dof::Dz], [Dof::Rx, Dof::Ry, Dof::Rz]] {
            let coupled: Vec<Dof> = family
                .into_iter()
                .filter(|d| free[d.index()] && self.dofs[d.index()].coupled_stops)
                .collect();
            if let [only] = coupled.as_slice() {
                return Err(PropertyError::field(
                    format!("{}.coupled_stops (Icomb)", only.name()),
                    1,
                    "Icomb = 1 on two or three free DOFs of the same family (translations or \
                     rotations): coupling needs at least two; 0 gives an independent stop",
                ));
            }
            if let Some((first, rest)) = coupled.split_first() {
                let a = &self.dofs[first.index()];
                // Friction on all coupled DOFs or on none: with friction the friction springs,
                // their caps lifted, are the stop (§4.2), without it the coupled stop spring.
                if let Some(d) = rest
                    .iter()
                    .find(|d| self.dofs[d.index()].friction_active() != a.friction_active())
                {
                    return Err(PropertyError::field(
                        format!("{}.friction (FF/FM)", d.name()),
                        self.dofs[d.index()].friction,
                        format!(
                            "friction on all coupled DOFs or on none (it is {} on {}): with \
                             friction the friction springs are the coupled stop",
                            if a.friction_active() {
                                "active"
                            } else {
                                "not active"
                            },
                            first.name()
                        ),
                    ));
                }
                for d in rest {
                    let b = &self.dofs[d.index()];
                    if a.stop_min != b.stop_min || a.stop_max != b.stop_max {
                        return Err(PropertyError::field(
                            format!("{}.stops (Icomb = 1)", d.name()),
                            format!("[{}, {}]", b.stop_min, b.stop_max),
                            format!(
                                "the same stops as the coupled DOF {} ([{}, {}])",
                                first.name(),
                                a.stop_min,
                                a.stop_max
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

/// `Ok` for a viscosity curve whose ends take energy out: beyond its first and last points
/// the curve is extrapolated with the first and last slopes (docs/kjoint2.md §4.1), and a
/// slope < 0 there is a negative viscosity at every rate beyond it, which feeds energy into
/// the joint without bound as a negative `C` does (refused alike): a body on
/// `[[-1, 10], [1, -10]]` runs away as `e^(10·t)`. Between the ends a curve may have either
/// sign (an offset `h(0) ≠ 0`, a curve digitised from a test crossing zero near the origin,
/// a constant): what that feeds is bounded by the curve's largest value times the rate
/// where it ends.
fn dissipative(field: &str, c: &Curve) -> Result<(), PropertyError> {
    let points: Vec<(f64, f64)> = c.points().collect();
    // a curve has at least two points (`Curve::new`)
    let n = points.len();
    let slope = |(xa, ya): (f64, f64), (xb, yb): (f64, f64)| (yb - ya) / (xb - xa);
    let ends = [
        ("first", slope(points[0], points[1])),
        ("last", slope(points[n - 2], points[n - 1])),
    ];
    for (end, s) in ends {
        if s < 0.0 {
            return Err(PropertyError::field(
                field,
                format!("a {end} slope {}", crate::figure::format_figure(s)),
                "first and last slopes >= 0: the curve is extrapolated with them, and a \
                 falling end is a negative viscosity at every rate beyond it, which feeds \
                 energy in without bound (give a last point where the force levels off)",
            ));
        }
    }
    Ok(())
}

/// What the substep's stages ask of a joint's property at every substep, found once per
/// analysis of the set ([`KjointProperty::shape`]; a property changes only through
/// `KjointSet::get_mut`, which brings an analysis): the questions cost the contact scene's
/// hinges, which have no stop and plain free DOFs, about 1 % of its instructions when each
/// stage asked the six DOF laws again. [`Default`]: [`Self::GENERAL`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct PropertyShape {
    /// [`KjointProperty::has_independent_stops`].
    pub independent_stops: bool,
    /// [`KjointProperty::has_coupled_stops`].
    pub coupled_stops: bool,
    /// [`KjointProperty::linear_free_dofs`].
    pub linear_free_dofs: bool,
}

impl PropertyShape {
    /// Any property: the stages look for stops and take the law's general path (the same
    /// results, found again at every substep), where nothing was found yet (a snapshot
    /// restored without it).
    pub(crate) const GENERAL: PropertyShape = PropertyShape {
        independent_stops: true,
        coupled_stops: true,
        linear_free_dofs: false,
    };
}

impl Default for PropertyShape {
    fn default() -> Self {
        Self::GENERAL
    }
}
