//! Blocked-DOF stiffness (docs/kjoint2.md §5): user `Kn`, or automatic from the substep by one of
//! two rules, and the stable-step estimate of an explicit update.
//!
//! # The implicit rule (default for the builder, scene files and URDF robots)
//!
//! The crate's update is implicit (`G = h·(h·K/β + C)`, [`crate::dynamics`]): it is stable at
//! any stiffness, it solves statics exactly (a joint under a steady load `F` deflects by
//! `F/K`), and a DOF it cannot resolve (`ω·h > 1`) is held like a constraint, its
//! oscillation damped within a few substeps. Radioss' explicit rule (below) instead bounds
//! the stiffness by the lighter neighbour's stability budget, which makes real robots sag
//! (a UR5 opened 0.51 m at its shoulder under 650 N/m). The implicit rule asks three things
//! of a blocked DOF:
//!
//! 1. **Hold the load.** Each joint carries a load side ([`JointLoad`]): the bodies it holds
//!    up. In a tree with a fixed (or kinematic) body, it is everything beyond the joint away
//!    from the fixed body (the subtree a robot's joint carries); between two free parts, the
//!    lighter one; for a joint in a loop, the whole island. Its mass `m_L` and mean inertia
//!    `I_L` about the anchor scale the stiffness: `K = κ·m_L/h²`, `KR = κ·I_L/h²`. Under
//!    the weight of its load side at `a = 9.81 m/s²` the joint then deflects by at most
//!    `a·h²/κ` (12 µm at 240 Hz with `κ = 14`), and its rotation moves the load's centre of
//!    mass by at most `1.5·a·h²/κ`: the moment `m_L·a·d` of a centre of mass at `d` turns
//!    the joint by `m_L·a·d·h²/(κ·I_L)`, and the mean inertia is at least `⅔·m_L·d²` (a
//!    third of the trace `2·Σ m·r² ≥ 2·m_L·d²`; a point mass reaches it, a slender rod from
//!    the anchor moves `1.125·a·h²/κ`): whatever the robot, at any size.
//! 2. **Do not resolve it.** The joint's own mode has `ω² = K·W` with `W` its effective
//!    inverse mass, at least `1/m` of the load-side body next to the joint, so
//!    `(ω·h)² ≥ κ`: with `κ = 16` every blocked DOF has `ω·h ≥ 4`, beyond what the substep
//!    carries; the update holds it as a constraint and damps it (the unresolved damping
//!    starts at `ω·h = 1` and is full from 2), and it stores the realised `½·K̃·q²`. A
//!    stiffness near `ω·h ≈ 1` would instead ring at the substep's own frequency.
//! 3. **Do not turn f32 noise into force, as far as that helps.** rapier's poses are f32:
//!    the measured deflection carries a noise `ε·r` with `ε = 1.19e-7` ([`POSE_NOISE`];
//!    2.2e-16 with the `f64` feature, where this bound no longer lowers `κ`) and `r` the
//!    distance of the joint's bodies from the world origin (the anchor's distance plus the
//!    load's radius of gyration). The law's force `K·q` then carries `K·ε·r`; the rule keeps
//!    it below 1 % ([`NOISE_FRACTION`]) of the load `m_L·a`, i.e. `κ ≤ η·a·h²/(ε·r)`
//!    ([`noise_kappa`]), **but not below `κ = 4`** ([`IMPLICIT_KAPPA_FLOOR`], `ω·h = 2`).
//!    The force the joint *transmits* is the update's, not the law's `K·q`: a DOF the
//!    substep does not resolve passes on at most `κ/(1+κ)` of the rounding's `m·ε·r/h²`,
//!    so going from `κ = 16` to 4 takes 15 % off that noise, and going lower only turns the
//!    DOF into a spring the substep resolves, which sags `a·h²/κ` and rings. Before
//!    2026-12-05 the bound went on down: a 1 kg ball released 0.5 rad from the vertical on
//!    a 1 m spherical joint 1 km out (60 Hz × 4 substeps, 10 s) swung with its anchors up
//!    to 2.1 cm apart, a transmitted force 1.4 N (s.d.) off its tension and 9 % of its
//!    energy lost; 5 km out 11 cm and 58 %, where rapier's joint holds it within 0.065 mm
//!    and 0.49 mm; a car's wheel 5 km out hung 0.5 m below its hub; five ragdolls lying
//!    1 km out kept joints 5 cm open. With the floor the ball swings within 0.11 mm (1 km)
//!    and 0.50 mm (5 km), its force 0.3 N off at 1 km, 1.4 % of its energy lost (15 % at
//!    5 km), the car's wheels sit on their hubs as at the origin (4.4 mm, the contact's
//!    lag), the ragdolls within 4.6 mm (0.6 mm at 16 substeps, rapier's 0.3–1.5 mm). The
//!    noise that is left is the rounding's own: 3.1 N (s.d.) on the 1 km ball at 16
//!    substeps, 20 N at 5 km, which the `f64` feature or a model nearer the origin
//!    removes, and fewer substeps lessen (`1/h²`).
//!
//! Together: `κ_eff = max(4, min(κ, η·a·h²/(ε·r)))`, `K = κ_eff·m_L/h²·ScF`,
//! `KR = κ_eff·I_L/h²·ScF`. At 60 Hz × 4 substeps a robot 1 m from the origin gets
//! `κ_eff ≈ 14`, 3.6 m or more away the floor's 4 and a sag of `a·h²/4` = 43 µm under its
//! load's weight; with one substep per 60 Hz frame `κ_eff = 16`, a sag of 0.17 mm. At 60 Hz
//! × 16 substeps (the scene files' default) the floor holds every joint whose pose scale
//! is beyond 0.22 m (the bound's own `κ` is `0.89/r`), at `a·h²/4` = 2.7 µm. Between the floor and 16, `K = η·a·m_L/(ε·r)` whatever the substep: a joint
//! the bound lowered says so in its health warning ([`NoiseBound`]). The transmitted force
//! is never noisier than the rounding's `κ/(1+κ)·m·ε·r/h²` anyway.
//!
//! Loads the joints do not see (contacts, rapier's own joints, a grasped object) are not in
//! `m_L`: a joint carrying `n` times its load side sags `n` times more, still `n·12 µm`,
//! by this rule. A contact's load is applied by rapier after the joint solve of each
//! substep, though, and moves the body by `F·h²/m` before the next one sees it, whatever
//! the stiffness: a legged robot's knee on the ground (28.5 N on 0.226 kg) opened 3 mm at
//! 240 Hz, about 1 mm since the solve takes a body the contacts hold as four times heavier
//! (README, "Joints against rapier's contacts").
//!
//! # The Radioss rule (properties read from a Radioss deck)
//!
//! [`automatic_blocked_stiffness`]: docs/kjoint2.md §5, as OpenRadioss computes it, so that deck
//! users compare with Radioss ([`crate::law::AutomaticStiffness::Radioss`]).

use super::kjoint2::BlockedStiffness;
use super::property::KjointProperty;

/// `κ = (ω·h)²` the implicit rule gives a blocked DOF against the load side next to it
/// (`ω·h = 4`), before the noise bound (module docs).
pub const IMPLICIT_KAPPA: f64 = 16.0;

/// The least `κ_eff` the noise bound leaves a blocked DOF, `(ω·h)² = 4`: the update still
/// holds it as a constraint and damps it in full (module docs, requirement 3).
pub const IMPLICIT_KAPPA_FLOOR: f64 = 4.0;

/// Relative rounding of rapier's poses, `ε`: f32's machine epsilon (1.19e-7), or f64's
/// (2.2e-16) with the `f64` feature, where the bound below leaves `κ = 16` to any joint
/// closer than 4.8e8 m to the origin.
#[cfg(not(feature = "f64"))]
pub const POSE_NOISE: f64 = f32::EPSILON as f64;
/// Relative rounding of rapier's poses, `ε`: f32's machine epsilon (1.19e-7), or f64's
/// (2.2e-16) with the `f64` feature, where the bound below leaves `κ = 16` to any joint
/// closer than 4.8e8 m to the origin.
#[cfg(feature = "f64")]
pub const POSE_NOISE: f64 = f64::EPSILON;

/// Fraction `η` of a joint's load that the pose noise may give as force (1 %).
pub const NOISE_FRACTION: f64 = 0.01;

/// Acceleration `a` \[m/s²\] that turns a load side's mass into the joint's load
/// (standard gravity, whatever the world's gravity).
pub const LOAD_ACCELERATION: f64 = 9.81;

/// What a joint holds up, for the implicit rule (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub struct JointLoad {
    /// Mass of the load side `m_L` \[kg\].
    pub mass: f64,
    /// Mean moment of inertia of the load side about the anchor `I_L` [kg·m²] (a third of the
    /// trace of its inertia tensor there).
    pub inertia: f64,
    /// Distance of the anchor from the world origin \[m\].
    pub anchor_distance: f64,
}

impl JointLoad {
    /// Radius of gyration of the load side about the anchor, `√(I_L/m_L)` \[m\].
    pub fn radius_of_gyration(&self) -> f64 {
        if self.mass > 0.0 && self.inertia > 0.0 {
            (self.inertia / self.mass).sqrt()
        } else {
            0.0
        }
    }
    /// The scale `r` of the coordinates whose f32 rounding the joint measures: the anchor's
    /// distance from the origin plus the radius of gyration \[m\].
    pub fn pose_scale(&self) -> f64 {
        self.anchor_distance + self.radius_of_gyration()
    }
}

/// `κ_eff = max(κ_min, min(κ, η·a·h²/(ε·r)))` of the implicit rule for substep `h` \[s\] and
/// pose scale `r` \[m\] (module docs): the noise bound [`noise_kappa`] held at
/// [`IMPLICIT_KAPPA_FLOOR`].
pub fn implicit_kappa(h: f64, pose_scale: f64) -> f64 {
    noise_kappa(h, pose_scale).max(IMPLICIT_KAPPA_FLOOR)
}

/// `min(κ, η·a·h²/(ε·r))`: the noise bound alone, before the floor (module docs). Below
/// [`IMPLICIT_KAPPA_FLOOR`] it measures how far the f32 rounding at pose scale `r` \[m\]
/// is beyond the rule's 1 % of the load, which the floor no longer follows.
pub fn noise_kappa(h: f64, pose_scale: f64) -> f64 {
    let noise = NOISE_FRACTION * LOAD_ACCELERATION * h * h / (POSE_NOISE * pose_scale);
    if noise.is_finite() {
        IMPLICIT_KAPPA.min(noise)
    } else {
        IMPLICIT_KAPPA
    }
}

/// The shortest substep \[s\] at which the noise bound leaves a joint at pose scale `r` \[m\]
/// the rule's own `κ` ([`IMPLICIT_KAPPA`]): `η·a·h²/(ε·r) = κ` gives
/// `h_full = √(κ·ε·r/(η·a))` (module docs). A shorter substep lowers its stiffness as
/// `κ_eff = κ·(h/h_full)²`, down to [`IMPLICIT_KAPPA_FLOOR`] at `h_full/2`. Check: `r` = 1 m in f32, `h_full = √(16·1.19e-7/0.0981)`
/// = 4.41 ms, a little over the 4.17 ms of 60 Hz × 4 substeps (`κ_eff` 14.3).
pub fn full_kappa_substep(pose_scale: f64) -> f64 {
    (IMPLICIT_KAPPA * POSE_NOISE * pose_scale / (NOISE_FRACTION * LOAD_ACCELERATION)).sqrt()
}

/// A joint whose automatic stiffness the noise bound lowered at the substep it was resolved
/// for (the implicit rule, [`implicit_kappa`] under [`IMPLICIT_KAPPA`]): what a health
/// warning about its deflection tells the user ([`crate::dynamics::HealthRemedy`]), and the
/// start notice of a joint so far from the origin that its rounding over a substep squared
/// is more than [`crate::dynamics::FAR_FROM_ORIGIN`] times the load acceleration
/// ([`crate::dynamics::KjointEventKind::StiffnessLoweredFarFromOrigin`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub struct NoiseBound {
    /// `κ_eff` at the joint's substep (under [`IMPLICIT_KAPPA`], at least
    /// [`IMPLICIT_KAPPA_FLOOR`]).
    pub kappa: f64,
    /// The noise bound's `κ` before the floor, [`noise_kappa`]: under
    /// [`IMPLICIT_KAPPA_FLOOR`], the f32 rounding is more than the rule's 1 % of the load.
    /// (0 when read from a snapshot saved before 2026-12-05.)
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub noise_kappa: f64,
    /// [`full_kappa_substep`] of the joint's pose scale \[s\]: at this substep or a longer
    /// one the joint gets the full `κ`.
    pub full_substep: f64,
    /// The frame time step \[s\] the substep divides (substeps × substep).
    pub frame: f64,
    /// The most substeps a frame that give the full `κ`, `⌊frame/full_substep⌋` (0: not
    /// even one, the frame is shorter than [`Self::full_substep`]).
    pub substeps: usize,
    /// The substep `h` \[s\] the stiffness was resolved for.
    pub substep: f64,
    /// What the joint holds up, and where: its load side's mass and inertia, and its
    /// anchor's distance from the world origin.
    pub load: JointLoad,
    /// `κ_eff` the rule gives the same joint at the same substep with its anchor at the
    /// world origin (pose scale the radius of gyration alone): `origin_kappa/kappa` is
    /// what the joint's distance from the origin costs its stiffness.
    pub origin_kappa: f64,
}

impl NoiseBound {
    /// The bound of a joint of `load` at substep `h` \[s\] of a frame `frame` \[s\], `None`
    /// where it leaves the rule's own `κ`.
    pub fn of(load: &JointLoad, h: f64, frame: f64) -> Option<NoiseBound> {
        let r = load.pose_scale();
        let kappa = implicit_kappa(h, r);
        (kappa < IMPLICIT_KAPPA).then(|| {
            let full_substep = full_kappa_substep(r);
            NoiseBound {
                kappa,
                full_substep,
                frame,
                // (a float to integer cast saturates: a NaN or negative quotient gives 0)
                substeps: (frame / full_substep).floor() as usize,
                substep: h,
                load: *load,
                noise_kappa: noise_kappa(h, r),
                origin_kappa: implicit_kappa(h, load.radius_of_gyration()),
            }
        })
    }

    /// Whether the bound sets the joint's stiffness: `κ_eff` above the floor
    /// [`IMPLICIT_KAPPA_FLOOR`], where the same `K = η·a·m_L/(ε·r)` holds at any substep
    /// down to [`Self::floor_substep`] (at the floor a shorter substep gives more).
    pub fn sets_stiffness(&self) -> bool {
        self.kappa > IMPLICIT_KAPPA_FLOOR
    }

    /// The substep \[s\] below which the floor takes over: the bound's
    /// `κ = 16·(h/h_full)²` reaches [`IMPLICIT_KAPPA_FLOOR`] at `h_full·√(κ_min/16)`.
    pub fn floor_substep(&self) -> f64 {
        self.full_substep * (IMPLICIT_KAPPA_FLOOR / IMPLICIT_KAPPA).sqrt()
    }

    /// The noise `ε·r` \[m\] of the joint's measured deflection: f32's rounding of
    /// coordinates at its pose scale `r` ([`JointLoad::pose_scale`]). A blocked stiffness
    /// `K` turns it into a force `K·ε·r`.
    pub fn deflection_noise(&self) -> f64 {
        POSE_NOISE * self.load.pose_scale()
    }

    /// The weight `m_L·a` \[N\] of the joint's load side ([`LOAD_ACCELERATION`]): the load
    /// the rule sizes the stiffness for, and whose [`NOISE_FRACTION`] the noise may give.
    pub fn load_weight(&self) -> f64 {
        self.load.mass * LOAD_ACCELERATION
    }

    /// How many times the load the rule sizes the joint for it carries: a force `load`
    /// \[N\] over the load side's weight `m_L·a`, or for a rotation (`rotation`) a moment
    /// \[N·m\] over that weight at the load's radius of gyration, `m_L·a·√(I_L/m_L)`.
    pub fn load_ratio(&self, load: f64, rotation: bool) -> f64 {
        let sized = if rotation {
            self.load_weight() * self.load.radius_of_gyration()
        } else {
            self.load_weight()
        };
        load / sized
    }

    /// The largest blocked stiffness whose f32 noise stays within [`NOISE_FRACTION`] of a
    /// load `load` the joint carries: `η·F/(ε·r)` \[N/m\] for a force (the noise `ε·r` of
    /// the deflection, [`Self::deflection_noise`]; for the load side's weight, the rule's
    /// own stiffness at this bound), `η·M/ε` \[N·m/rad\] for a moment (`rotation`: the
    /// rounding of the rotations, `ε` rad).
    pub fn stiffness_within(&self, load: f64, rotation: bool) -> f64 {
        let noise = if rotation {
            POSE_NOISE
        } else {
            self.deflection_noise()
        };
        NOISE_FRACTION * load / noise
    }
}

/// Automatic blocked stiffness of the implicit rule (`Kn = 0`,
/// [`crate::law::AutomaticStiffness::Implicit`]): `K = κ_eff·m_L/h²·ScF`,
/// `KR = κ_eff·I_L/h²·ScF` with `κ_eff` from [`implicit_kappa`] (module docs).
///
/// Check: a 1 kg load with `I_L = 0.25 kg·m²` about an anchor 0.5 m from the origin, 60 Hz ×
/// 4 substeps: `r = 0.5 + 0.5 = 1 m`, `κ_eff = min(16, 0.01·9.81·h²/(1.19e-7·1)) = 14.29`,
/// `K = 14.29·57600 = 8.23e5 N/m`, `KR = 2.06e5 N·m/rad`.
pub fn implicit_blocked_stiffness(
    prop: &KjointProperty,
    load: &JointLoad,
    h: f64,
) -> BlockedStiffness {
    let k = implicit_kappa(h, load.pose_scale()) / (h * h) * prop.resolved_scale_factor();
    BlockedStiffness {
        translational: k * load.mass.max(0.0),
        rotational: k * load.inertia.max(0.0),
    }
}

/// Radioss' safety factor `α` in the automatic stiffness.
pub const ALPHA: f64 = 4.1;

/// Mass data of one body of a joint, as the stiffness formulas need it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct BodyMass {
    /// Mass \[kg\]; `f64::INFINITY` for a fixed body.
    pub mass: f64,
    /// Mean principal inertia [kg·m²]; `f64::INFINITY` for a fixed body.
    pub inertia: f64,
    /// Squared distance from the anchor to the body's centre of mass \[m²\].
    pub anchor_offset_sq: f64,
}

impl BodyMass {
    /// A fixed (world) body anchored at its centre of mass: infinite mass and inertia.
    pub const FIXED: BodyMass = BodyMass {
        mass: f64::INFINITY,
        inertia: f64::INFINITY,
        anchor_offset_sq: 0.0,
    };
    /// A fixed (world) body whose anchor is `√anchor_offset_sq` from its centre of mass: it
    /// does not bound the automatic stiffness, but its offset is part of `r²` (docs/kjoint2.md §5;
    /// the Radioss QA model's spring node is 75 from the fixed rigid body's centre of mass).
    pub fn fixed(anchor_offset_sq: f64) -> BodyMass {
        BodyMass {
            anchor_offset_sq,
            ..BodyMass::FIXED
        }
    }
    /// `true` for a fixed body (infinite mass).
    pub fn is_fixed(&self) -> bool {
        !self.mass.is_finite()
    }
}

/// Blocked stiffness for a joint with user `Kn > 0`: `KR = Kn·max(ScF, L0²)`.
pub fn user_blocked_stiffness(prop: &KjointProperty, initial_length: f64) -> BlockedStiffness {
    let kn = prop.kn;
    BlockedStiffness {
        translational: kn,
        rotational: kn
            * prop
                .resolved_scale_factor()
                .max(initial_length * initial_length),
    }
}

/// Automatic blocked stiffness of the Radioss rule (`Kn = 0`,
/// [`crate::law::AutomaticStiffness::Radioss`]), computed from the substep `dt`:
///
/// `r² = max_i |anchor_i − com_i|² + |anchor_1 − anchor_2|²`,
/// `Kx_i = min(2·m_i/(α·dt²), 0.8·I_i/(α·dt²·r²))` (second term only when `r² > 0`),
/// `KX = min(Kx_1, Kx_2)`, `KR = min_i I_i/(α·dt²)`, both times `ScF`.
///
/// `share[i]` (in (0, 1]) is the fraction of body `i`'s stiffness budget this joint may
/// take; the joint set passes `1/n_i` with `n_i` the number of automatic joints on body `i`
/// after the user-stiffness joints on it have taken theirs. A fixed body does not bound the
/// minimum, but its anchor offset counts in `r²` ([`BodyMass::fixed`]). A body with zero
/// inertia (a point mass) drops the inertia term instead of giving a zero translational
/// stiffness, and gives `KR = 0`.
///
/// Check (the OpenRadioss KJOINT2 QA model): a fixed body with the anchor 75 from its centre
/// of mass, a 156 kg body with `I = 31200` anchored at its centre, `dt = 1.475e-3`:
/// `KX = 0.8·31200/(4.1·dt²·75²) = 4.97455e5`, `KR = 31200/(4.1·dt²) = 3.49773e9`.
pub fn automatic_blocked_stiffness(
    prop: &KjointProperty,
    bodies: [BodyMass; 2],
    initial_length: f64,
    dt: f64,
    share: [f64; 2],
) -> BlockedStiffness {
    let adt2 = ALPHA * dt * dt;
    let r2 = bodies
        .iter()
        .map(|b| b.anchor_offset_sq)
        .fold(0.0, f64::max)
        + initial_length * initial_length;
    let mut kx = f64::INFINITY;
    let mut kr = f64::INFINITY;
    for (b, s) in bodies.iter().zip(share) {
        if b.is_fixed() {
            continue;
        }
        let mut k = 2.0 * b.mass / adt2;
        if r2 > 0.0 && b.inertia > 0.0 {
            k = k.min(0.8 * b.inertia / (adt2 * r2));
        }
        kx = kx.min(k * s);
        if b.inertia > 0.0 {
            kr = kr.min(b.inertia / adt2 * s);
        } else {
            kr = 0.0;
        }
    }
    let scf = prop.resolved_scale_factor();
    BlockedStiffness {
        translational: if kx.is_finite() { kx * scf } else { 0.0 },
        rotational: if kr.is_finite() { kr * scf } else { 0.0 },
    }
}

/// Stable time steps of an explicit (central difference) update of one joint, as
/// OpenRadioss estimates them (docs/kjoint2.md §5): translational and rotational separately.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub struct StableDt {
    /// `dt_trans = 0.9·min_i √(m_i/S)` \[s\] (`∞` when nothing bounds it).
    pub translational: f64,
    /// `dt_rot = 0.9·min_i √(2·I_i/(S_r + S·L²))` \[s\] (`∞` when nothing bounds it).
    pub rotational: f64,
}

impl StableDt {
    /// The smaller of the two \[s\].
    pub fn min(&self) -> f64 {
        self.translational.min(self.rotational)
    }
}

/// Stable time steps of an explicit update of this joint (docs/kjoint2.md §5), as OpenRadioss
/// computes them: the nodal translational stiffness receives `2·S` and the rotational one
/// `S_r + S·L²`, so
///
/// `dt_trans = 0.9·min_i √(m_i/S)`, `dt_rot = 0.9·min_i √(2·I_i/(S_r + S·L²))`,
///
/// with `S = K·(ξ + √(1+ξ²))²`, `S_r = K_r·(ξ + √(1+ξ²))²`, `ξ` the largest active damping
/// ratio, `K`/`K_r` the largest translational / rotational tangent stiffness, `L` the joint
/// length. Fixed bodies and bodies without inertia do not bound the step.
///
/// Check: a fixed joint between a fixed node and a body of `m = I = 1`, `L = 0`, `Kn = 1e4`,
/// `KR = 1e5` (ScF = 10), `ξ = 0.05`: `dt_trans = 8.561e-3`, `dt_rot = 3.829e-3`.
///
/// The crate's own update is unconditionally stable; this tells whether a substep would be
/// safe for Radioss' explicit scheme, and how far the joint is from the explicit regime.
pub fn stable_dt(
    bodies: [BodyMass; 2],
    k_trans: f64,
    k_rot: f64,
    xi: f64,
    length: f64,
) -> StableDt {
    let f = (xi + (1.0 + xi * xi).sqrt()).powi(2);
    let s = k_trans * f;
    let s_rot = k_rot * f + s * length * length;
    let mut dt = StableDt {
        translational: f64::INFINITY,
        rotational: f64::INFINITY,
    };
    for b in bodies.iter().filter(|b| !b.is_fixed()) {
        if s > 0.0 {
            dt.translational = dt.translational.min((b.mass / s).sqrt());
        }
        if s_rot > 0.0 && b.inertia > 0.0 {
            dt.rotational = dt.rotational.min((2.0 * b.inertia / s_rot).sqrt());
        }
    }
    StableDt {
        translational: 0.9 * dt.translational,
        rotational: 0.9 * dt.rotational,
    }
}
