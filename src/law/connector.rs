//! Connector laws hooked onto the free DOFs of a KJOINT2 joint: the load-dependent planar
//! friction ([`super::planar_friction`], docs/planar_friction.md) on the planar joint
//! (type 4) and the riser flex joint ([`super::flex_joint`], docs/flex_joint.md) on the
//! spherical joint (type 1).
//!
//! Pure: no rapier type. The joint set evaluates the KJOINT2 law ([`super::evaluate`]) and
//! then calls `Connector::apply`, which **adds** the connector's forces, tangents and
//! energies to that [`LawOutput`] and [`JointEnergy`]; the implicit update then treats them
//! like any other part of the law.
//!
//! # Planar friction (type 4)
//!
//! DOF mapping (joint frame, KJOINT2 order `δx, δy, δz, θx, θy, θz`):
//!
//! | spec | KJOINT2 DOF | role |
//! |---|---|---|
//! | `f1` | `δx` (index 0) | blocked normal: `f1 = F_total[0]` of this evaluation |
//! | `m2`, `m3` | `θy`, `θz` (4, 5) | blocked: `F_total[4]`, `F_total[5]` referred to anchor 2 (below) |
//! | `u2`, `u3` | `δy`, `δz` (1, 2) | free, in-plane friction force `s = (f2, f3)` |
//! | `ur1` | `θx` (3) | free, friction moment `m1` |
//!
//! `f1`, `m2`, `m3` are the **KJOINT2 totals of the blocked DOFs of the same evaluation**
//! (penalty plus its critical damping), i.e. the constraint forces the joint carries now.
//! **Body 2 carries the puck** (the sliding part) and body 1 the plate. A joint with this
//! connector measures its translations as Abaqus's PLANAR does, in body 1's joint frame
//! and at anchor 2, the puck, where its translational force then acts on both bodies
//! (`kinematics::TranslationMeasure::Body1Frame`, "Translation measure" in
//! [`crate::kinematics`]): the moments carried at the puck are the KJOINT2 moments `M`
//! themselves, `(m2, m3) = (M − l×F)_{y,z}` with `l` = anchor 2 from the force's point = 0
//! (`ConnectorInput::lever`; `l = ½·L` for a joint measured at the mid-point, docs/kjoint2.md
//! §4.7). This matches Abaqus, whose connector constraint forces and moments (from which
//! its predefined friction derives the contact forces) are those applied at node b, the
//! second node. At KJOINT2's mid-point a puck that has slid a distance `d` from anchor 1
//! would carry the couple `½·d·f1`, tilt under it through its blocked rotational
//! stiffness, and sink along the tilted mid-plane, its normal force falling with it.
//! With them, the normal force `F_N` and moment `M_N` (docs/planar_friction.md §2, §3:
//! [`PlanarFriction::normal_force`], [`PlanarFriction::normal_moment`]) and the 2-D / 1-D return
//! mappings of [`PlanarFriction::evaluate`] give the friction force and moment, added to `F[1],
//! F[2]` and `F[3]` (part `friction`; springs, viscosity or stops of the property on these DOFs
//! still act). Tangents:
//!
//! ```text
//! K[1..3, 1..3] += Kf·I (stick)  or  Kf·(c/|s*|)·(I − n nᵀ) (slide)
//! K[3, 3]       += Kr (stick)    or  0 (slip)
//! ```
//!
//! The dependence of the caps on `f1, m2, m3` is not linearised (the caps are frozen over a
//! substep), so the tangent stays symmetric.
//!
//! **Stick stiffness.** `Kf = 0` (resp. `Kr = 0`) means automatic, chosen from the substep
//! like the automatic penalty (docs/planar_friction.md): the joint's automatic blocked
//! stiffness `KX` (resp. `KR`) of docs/kjoint2.md §5 (`Kn = 0`, `ScF = 1`), which the joint set
//! resolves with the blocked stiffness (`Connector::set_automatic_stiffness`). For a joint
//! with `Kn = 0` it is its blocked stiffness; a joint with a user `Kn` (say 1e12 N/m, a rigid
//! contact) keeps a stick spring the substep resolves. Until it is resolved (a bare
//! `Connector::apply`) the blocked stiffness of the evaluation stands in.
//!
//! **Stick damping.** As KJOINT2's own friction (docs/kjoint2.md §4.4), a sticking mechanism gets
//! the critical damping `c = Cr·√(K·m)` (`Cr` the property's critical damping ratio, `m` the
//! reduced mass or inertia): `F += c·q̇`, `C += c`. Without it the stick spring would ring for
//! ever (the implicit update has no numerical damping).
//!
//! **Stops.** The optional stops on `u2`, `u3`, `ur1` are the KJOINT2 stops of the free DOFs
//! `δy`, `δz`, `θx` of the property ([`super::DofLaw::with_stops`], independent or coupled):
//! the stop law, its stiffness and its critical damping are KJOINT2's, the friction acts on
//! top of them (unlike KJOINT2's given friction, the friction cap is **not** suspended in
//! stop contact: Abaqus keeps friction on while a stop acts).
//!
//! **Energy.** `elastic += |s|²/(2Kf) + m1²/(2Kr)` (stick springs), `friction += cap·Δλ`
//! plus the spring energy a falling cap releases (the plastic work of the return,
//! [`PlanarFriction::evaluate`]), `damping +=` trapezoidal work of the stick damping as the
//! update applied it, `½·Δq·(F_d⁻ + F_d)`: at an evaluation where the mechanism starts to
//! stick, `F_d = 0` (it slid over the interval), where it starts to slide `F_d = c⁻·q̇`
//! (`c⁻` the previous evaluation's; `Connector::apply`), `c·q̇` otherwise; and `internal += ½·Δq·(F_c,new + F_c,old)` of the connector's
//! own forces `F_c`.
//!
//! # Joint friction (types 2, 3, 6)
//!
//! Load-dependent friction on the revolute, cylindrical and translational joints
//! (docs/joint_friction.md, [`JointFriction`]); how it is added: [`joint_friction`].
//!
//! # Flex joint (type 1)
//!
//! The rotation `θ = (θx, θy, θz)` of the spherical joint is the flex joint's `θ`, with **x
//! the riser axis**. With a flex joint in its decoupled or dynamic mode the joint set
//! measures it as a swing-twist split about x (as for the revolute joint): `(θy, θz)` is the
//! swing, so the bending angle `|(θy, θz)|` is the angle between the two bodies' axes, and
//! `θx` the twist (torsion). In the classical mode (one law of the total angle) it is the
//! rotation vector. [`FlexJointLaw::evaluate`]
//! gives the moment `M` (added to `F[3..6]`, part `elastic`; the torsion damping `CP·θ̇x` to
//! part `damping`), the tangent stiffness `∂M/∂θ` (added to `K[3..6, 3..6]`: in the classical
//! mode the full 3×3 radial tangent, otherwise the 2×2 bending tangent in the (θy, θz) plane
//! and the torsion slope on `K[3, 3]`) and the tangent damping `diag(CP, 0, 0)`. The
//! property's own laws on `θx, θy, θz` (springs, stops, viscosity, lock) still act and add
//! to the flex joint's moment; a plain spherical property leaves the flex joint alone.
//!
//! **Phase switch.** The quasi-static → dynamic switch is an event: either at a time given
//! with the law ([`FlexJointConnector::switch_time`]; it happens at the first evaluation with
//! `t ≥ switch_time`, around the bending state of the previous evaluation) or by an explicit
//! call (`Connector::switch_to_dynamic`). Each switch is logged as a [`ConnectorEvent`]
//! (time and [`FlexJointSwitchCause`]) and appears in the readout ([`FlexJointReport::switched_at`]).
//!
//! **Energy.** `elastic += E_stored` of the law, `friction +=` the hysteretic plastic work
//! `My·Δλ` (the loop area over a cycle), `damping += CP·θ̇x·Δθx`, and
//! `internal += ½·Δθ·(M_new + M_old)`.

//!
//! # Serialisation
//!
//! Scene files describe the laws with their own tables, in the scene's units
//! (`planar_friction`, a [`PlanarFriction`] in the scene's units, and
//! [`crate::scene::schema::FlexJointSpec`]). [`ConnectorLaw`] itself is (de)serialised with serde
//! (SI), externally tagged in snake case; in TOML:
//!
//! ```toml
//! [planar_friction]          # only mu is required; 0 = none / automatic for the rest
//! mu = 0.3
//! radius = 0.05              # R \[m\]
//! internal_force = 0.0       # F_int \[N\]
//!
//! # or
//! [flex_joint]
//! switch_time = 20.0         # \[s\], optional
//! [flex_joint.law]
//! bending = [[0.0, 0.0], [0.00872665, 25000.0], [0.0174533, 35000.0]]  # IPRO [rad, N·m]
//! # torsion = [[...]]        # IPROT, optional
//! [flex_joint.law.dynamic]   # *FLEXPROADD, optional
//! torsion_stiffness = 5.72958e8
//! iflag = 1
//! kdyn_ini = 4.0107e6
//! kdyn_lim = 1.718873e6
//! angle_lim = 1.74533e-3
//! teta = 0.0
//! torsion_damping = 3.008e6
//! ```
//!
//! A deserialised law is validated when the joint is inserted ([`ConnectorLaw::validate`]).

use super::flex_joint::{FlexJointInput, FlexJointLaw, FlexJointState, FlexPhase};
use super::joint_friction::{JointFriction, JointFrictionState};
use super::planar_friction::{PlanarFriction, PlanarFrictionState};
use super::{FrictionStatus, JointEnergy, JointType, KjointProperty, LawOutput, LawParams};
use crate::error::PropertyError;
use serde::{Deserialize, Serialize};
use thiserror::Error;

pub mod joint_friction;
mod planar;
mod report;
pub use joint_friction::JointFrictionReport;
pub use report::{FlexJointReport, PlanarFrictionReport};

/// The flex joint law with its phase-switch time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FlexJointConnector {
    /// The resolved law (bending, torsion, `*FLEXPROADD`).
    pub law: FlexJointLaw,
    /// Simulation time \[s\] of the quasi-static → dynamic switch (`None`: only by an
    /// explicit call).
    #[serde(default)]
    pub switch_time: Option<f64>,
}

/// The connector law of a joint, on top of its KJOINT2 law.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ConnectorLaw {
    /// No connector law: the KJOINT2 law alone.
    #[default]
    None,
    /// Load-dependent friction on a planar joint (type 4).
    PlanarFriction(PlanarFriction),
    /// Riser flex joint on a spherical joint (type 1).
    FlexJoint(FlexJointConnector),
    /// Load-dependent friction on a revolute, cylindrical or translational joint (types 2,
    /// 3, 6; docs/joint_friction.md).
    JointFriction(JointFriction),
}

/// Why a connector law cannot be attached to a joint.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ConnectorError {
    /// The law needs another joint type.
    #[error("the {law} law needs a {} joint (type {}), not a {} joint (type {})", required.name(), required.number(), found.name(), found.number())]
    WrongJointType {
        /// The connector law (`planar friction`, `flex joint`).
        law: &'static str,
        /// The joint type the law is defined for.
        required: JointType,
        /// The joint type of the property.
        found: JointType,
    },
    /// The law is defined for several joint types, not this one.
    #[error("the {law} law needs a {supported} joint, not a {} joint (type {})", found.name(), found.number())]
    UnsupportedJointType {
        /// The connector law.
        law: &'static str,
        /// The joint types it is defined for, in words.
        supported: &'static str,
        /// The joint type of the property.
        found: JointType,
    },
    /// A parameter of the law is invalid.
    #[error("{law} law: {source}")]
    Property {
        /// The connector law.
        law: &'static str,
        /// What is wrong.
        #[source]
        source: PropertyError,
    },
    /// The KJOINT2 property defines something on the same DOF that the law replaces.
    #[error("{law} law: {reason}")]
    Conflict {
        /// The connector law.
        law: &'static str,
        /// What conflicts and how to fix it.
        reason: String,
    },
}

impl ConnectorLaw {
    /// Checks the law against the joint's property: planar friction needs a planar joint
    /// (type 4) without KJOINT2 friction (`FF`) on `δy`, `δz`, `θx` (two friction laws on
    /// one DOF); the flex joint needs a spherical joint (type 1); the parameters must be
    /// valid (a stick stiffness of 0 is allowed and means automatic).
    pub fn validate(&self, prop: &KjointProperty) -> Result<(), ConnectorError> {
        match self {
            ConnectorLaw::None => Ok(()),
            ConnectorLaw::PlanarFriction(p) => {
                let law = "planar friction";
                if prop.joint_type != JointType::Planar {
                    return Err(ConnectorError::WrongJointType {
                        law,
                        required: JointType::Planar,
                        found: prop.joint_type,
                    });
                }
                p.validate()
                    .map_err(|source| ConnectorError::Property { law, source })?;
                for i in [1, 2, 3] {
                    if prop.dofs[i].friction_active() {
                        return Err(ConnectorError::Conflict {
                            law,
                            reason: format!(
                                "the property also has KJOINT2 friction (FF) on {}: remove it, \
                                 the planar friction law replaces it",
                                super::Dof::ALL[i].name()
                            ),
                        });
                    }
                }
                Ok(())
            }
            ConnectorLaw::JointFriction(j) => joint_friction::validate(j, prop),
            ConnectorLaw::FlexJoint(f) => {
                let law = "flex joint";
                if prop.joint_type != JointType::Spherical {
                    return Err(ConnectorError::WrongJointType {
                        law,
                        required: JointType::Spherical,
                        found: prop.joint_type,
                    });
                }
                f.law
                    .validate()
                    .map_err(|source| ConnectorError::Property { law, source })?;
                if let Some(t) = f.switch_time {
                    if !t.is_finite() {
                        return Err(ConnectorError::Property {
                            law,
                            source: PropertyError::InvalidField {
                                field: "switch_time".into(),
                                value: t.to_string(),
                                expected: "a finite time [s]".into(),
                            },
                        });
                    }
                }
                Ok(())
            }
        }
    }
}

impl ConnectorLaw {
    /// Largest stiffness the law can add `(translational [N/m], rotational [N·m/rad])`, for
    /// the explicit stable-step estimate: the stick stiffnesses (automatic ones resolved to
    /// `blocked`) for planar friction; for the flex joint the largest slope of its laws,
    /// `Kdyn_ini` and `Ktor` (a secant or consistent tangent never exceeds them).
    pub fn max_stiffness(&self, blocked: &super::BlockedStiffness) -> (f64, f64) {
        match self {
            ConnectorLaw::None => (0.0, 0.0),
            ConnectorLaw::PlanarFriction(p) => {
                let pick = |k: f64, auto: f64| if k > 0.0 { k } else { auto };
                (
                    pick(p.stick_stiffness, blocked.translational),
                    pick(p.stick_rotational_stiffness, blocked.rotational),
                )
            }
            ConnectorLaw::FlexJoint(f) => {
                let mut k = [&f.law.bending, &f.law.torsion]
                    .into_iter()
                    .flatten()
                    .map(|c| c.max_abs_slope())
                    .fold(0.0, f64::max);
                if let Some(d) = &f.law.dynamic {
                    k = k.max(d.kdyn_ini).max(d.torsion_stiffness);
                }
                (0.0, k)
            }
            ConnectorLaw::JointFriction(j) => {
                let k = joint_friction::resolved(j, blocked);
                (k.stick_stiffness, k.stick_rotational_stiffness)
            }
        }
    }

    /// Largest stiffness the law adds to each DOF `(δx, δy, δz, θx, θy, θz)`
    /// \[N/m, N·m/rad\], for the start notice of a free DOF the substep cannot resolve
    /// (`dynamics::health`). A flex joint: the bending law's steepest slope and `Kdyn_ini`
    /// on `θy`, `θz`; on `θx` the torsion law's steepest slope, else `Ktor` (the bending law's
    /// in the classical mode, which acts on the total rotation). The friction laws add
    /// nothing here: their automatic stick springs are the blocked penalty, unresolved by
    /// design.
    pub fn dof_stiffness(&self) -> [f64; 6] {
        match self {
            ConnectorLaw::FlexJoint(f) => {
                let slope =
                    |c: &Option<super::curve::Curve>| c.as_ref().map_or(0.0, |c| c.max_abs_slope());
                let dynamic = f.law.dynamic.as_ref();
                let bending = slope(&f.law.bending).max(dynamic.map_or(0.0, |d| d.kdyn_ini));
                let torsion = if f.law.torsion.is_some() {
                    slope(&f.law.torsion)
                } else if let Some(d) = dynamic {
                    d.torsion_stiffness
                } else {
                    bending
                };
                [0.0, 0.0, 0.0, torsion, bending, bending]
            }
            _ => [0.0; 6],
        }
    }

    /// `true` when the law reads the joint's blocked reactions (its friction's normal
    /// force): the joint set keeps the Radioss rule on them, so that they are the forces the
    /// joint transmits (docs/planar_friction.md §4, docs/joint_friction.md §4).
    pub fn reads_reactions(&self) -> bool {
        matches!(
            self,
            ConnectorLaw::PlanarFriction(_) | ConnectorLaw::JointFriction(_)
        )
    }
}

/// Kinematics of one evaluation, as the connector needs them (joint frame E).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct ConnectorInput {
    /// DOF values `(δx, δy, δz, θx, θy, θz)` \[m, rad\].
    pub q: [f64; 6],
    /// Their rates \[m/s, rad/s\].
    pub rate: [f64; 6],
    /// Anchor 2 relative to the point the joint's translational force acts at, in the frame
    /// of the translations \[m\]: `½·(p2 − p1)` for KJOINT2's mid-point, 0 for a joint that
    /// measures at anchor 2 (the planar-friction connector, `kinematics::TranslationMeasure`).
    pub lever: [f64; 3],
    /// Simulation time \[s\].
    pub time: f64,
}

/// A connector event (the flex joint's phase switch), logged like a sensor activation; the
/// joint set reports it as a `KjointEvent` (`dynamics::event`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub struct ConnectorEvent {
    /// Simulation time \[s\].
    pub time: f64,
    /// What happened.
    pub kind: ConnectorEventKind,
}

/// What a connector event is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[non_exhaustive]
pub enum ConnectorEventKind {
    /// The flex joint switched from its quasi-static to its dynamic phase.
    FlexJointSwitched {
        /// Why.
        cause: FlexJointSwitchCause,
    },
}

/// Why a flex joint switched to its dynamic phase.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[non_exhaustive]
pub enum FlexJointSwitchCause {
    /// The law's switch time was reached ([`FlexJointConnector::switch_time`]; the switch
    /// happens at the first evaluation at or after it).
    SwitchTime {
        /// The switch time \[s\].
        switch_time: f64,
    },
    /// An explicit call (`Connector::switch_to_dynamic`, the joint set's
    /// `switch_flex_joint`).
    ExplicitCall,
}

impl std::fmt::Display for FlexJointSwitchCause {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FlexJointSwitchCause::SwitchTime { switch_time } => {
                write!(f, "switch time {switch_time} s reached")
            }
            FlexJointSwitchCause::ExplicitCall => f.write_str("explicit call"),
        }
    }
}

impl std::fmt::Display for ConnectorEventKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ConnectorEventKind::FlexJointSwitched { cause } => {
                write!(f, "flex joint switched to the dynamic phase ({cause})")
            }
        }
    }
}

/// What a connector law reports after each evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum ConnectorReport {
    /// Planar friction readout.
    PlanarFriction(PlanarFrictionReport),
    /// Flex joint readout.
    FlexJoint(FlexJointReport),
    /// Joint friction readout.
    JointFriction(JointFrictionReport),
}

impl ConnectorReport {
    /// The readout as named scalars, in SI, for time histories and recordings: the CSV
    /// column names and the rerun entity names under `joints/<joint>/<law>/`.
    ///
    /// Planar friction (`planar_friction`): `normal_force` \[N\], `normal_moment` \[N·m\],
    /// `friction_y`, `friction_z` \[N\], `friction_moment` \[N·m\], `sliding`, `twist`
    /// (1 stick, 2 slip), `slip_total` \[m\], `twist_slip_total` \[rad\], `stored`,
    /// `dissipated` \[J\].
    ///
    /// Joint friction (`joint_friction`): [`JointFrictionReport`]'s channels (`normal_force`,
    /// `cap`, `friction_force`, `friction_moment`, `sliding`, `slip_total`, `stored`,
    /// `dissipated`).
    ///
    /// Flex joint (`flex_joint`): `bending_angle` \[rad\], `bending_moment_y`,
    /// `bending_moment_z` \[N·m\], `torsion_angle` \[rad\], `torsion_moment` \[N·m\], `phase`
    /// (0 quasi-static, 1 dynamic), `yielding` (0/1), `dissipated_hysteresis`,
    /// `dissipated_damping`, `stored` \[J\], then the bending plane and the hysteretic law's
    /// state: `tilt_y`, `tilt_z` (the unit direction the riser axis tilts towards, in the
    /// joint's y-z plane), `plastic_y`, `plastic_z` (the plastic variation `φp` \[rad\]) and
    /// `back_moment_y`, `back_moment_z` (`α = H·φp` \[N·m\]; both 0 outside the dynamic
    /// phase's hysteretic law).
    pub fn channels(&self) -> (&'static str, Vec<(&'static str, f64)>) {
        let code = joint_friction::status_code;
        let (law, names, values): (_, &[&'static str], Vec<f64>) = match self {
            ConnectorReport::PlanarFriction(r) => (
                "planar_friction",
                &PLANAR_FRICTION_CHANNELS,
                vec![
                    r.normal_force,
                    r.normal_moment,
                    r.friction_force[0],
                    r.friction_force[1],
                    r.friction_moment,
                    code(r.sliding),
                    code(r.twist),
                    r.slip_total,
                    r.twist_slip_total,
                    r.stored,
                    r.dissipated,
                ],
            ),
            ConnectorReport::JointFriction(r) => {
                ("joint_friction", &JOINT_FRICTION_CHANNELS, r.channels())
            }
            ConnectorReport::FlexJoint(r) => (
                "flex_joint",
                &FLEX_JOINT_CHANNELS,
                vec![
                    r.bending_angle,
                    r.bending_moment[0],
                    r.bending_moment[1],
                    r.torsion_angle,
                    r.torsion_moment,
                    match r.phase {
                        FlexPhase::QuasiStatic => 0.0,
                        FlexPhase::Dynamic => 1.0,
                    },
                    if r.yielding { 1.0 } else { 0.0 },
                    r.dissipated_hysteresis,
                    r.dissipated_damping,
                    r.stored,
                    r.tilt_direction[0],
                    r.tilt_direction[1],
                    r.plastic_variation[0],
                    r.plastic_variation[1],
                    r.back_moment[0],
                    r.back_moment[1],
                ],
            ),
        };
        debug_assert_eq!(names.len(), values.len());
        (law, names.iter().copied().zip(values).collect())
    }
}

/// The channels of planar friction's readout, in [`ConnectorReport::channels`]' order.
const PLANAR_FRICTION_CHANNELS: [&str; 11] = [
    "normal_force",
    "normal_moment",
    "friction_y",
    "friction_z",
    "friction_moment",
    "sliding",
    "twist",
    "slip_total",
    "twist_slip_total",
    "stored",
    "dissipated",
];

/// The channels of joint friction's readout, in [`ConnectorReport::channels`]' order.
const JOINT_FRICTION_CHANNELS: [&str; 8] = [
    "normal_force",
    "cap",
    "friction_force",
    "friction_moment",
    "sliding",
    "slip_total",
    "stored",
    "dissipated",
];

/// The channels of the flex joint's readout, in [`ConnectorReport::channels`]' order.
const FLEX_JOINT_CHANNELS: [&str; 16] = [
    "bending_angle",
    "bending_moment_y",
    "bending_moment_z",
    "torsion_angle",
    "torsion_moment",
    "phase",
    "yielding",
    "dissipated_hysteresis",
    "dissipated_damping",
    "stored",
    "tilt_y",
    "tilt_z",
    "plastic_y",
    "plastic_z",
    "back_moment_y",
    "back_moment_z",
];

impl ConnectorLaw {
    /// The law's name and the names of its readout's channels, as
    /// [`ConnectorReport::channels`] gives them for a joint with this law (`None` for
    /// [`ConnectorLaw::None`]): the columns a joint's history has before its first
    /// evaluation.
    pub fn channel_names(&self) -> Option<(&'static str, &'static [&'static str])> {
        match self {
            ConnectorLaw::None => None,
            ConnectorLaw::PlanarFriction(_) => Some(("planar_friction", &PLANAR_FRICTION_CHANNELS)),
            ConnectorLaw::JointFriction(_) => Some(("joint_friction", &JOINT_FRICTION_CHANNELS)),
            ConnectorLaw::FlexJoint(_) => Some(("flex_joint", &FLEX_JOINT_CHANNELS)),
        }
    }
}

/// State of a connector law between evaluations.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) enum ConnectorState {
    /// No connector.
    #[default]
    None,
    /// Planar friction springs.
    PlanarFriction(PlanarFrictionState),
    /// Flex joint state.
    FlexJoint(FlexJointState),
    /// Joint friction spring.
    JointFriction(JointFrictionState),
}

/// A joint's connector: nothing for a joint without one (most joints), else its law and
/// runtime state ([`ConnectorRuntime`]) behind one pointer. The runtime is about 600 bytes:
/// inline in every joint record it made the record that the prepare stage streams through
/// a quarter larger, for nothing on the joints that have no connector.
#[derive(Debug, Clone, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct Connector(Option<Box<ConnectorRuntime>>);

/// The law of a joint without a connector.
static NO_LAW: ConnectorLaw = ConnectorLaw::None;
/// The report of a joint without a connector.
static NO_REPORT: Option<ConnectorReport> = None;

impl Connector {
    /// A connector with a fresh state (validate the law first with
    /// [`ConnectorLaw::validate`]); nothing is allocated for [`ConnectorLaw::None`].
    pub fn new(law: ConnectorLaw) -> Self {
        match law {
            ConnectorLaw::None => Connector(None),
            law => Connector(Some(Box::new(ConnectorRuntime::new(law)))),
        }
    }

    /// Whether the joint has a connector law.
    #[inline]
    pub fn is_some(&self) -> bool {
        self.0.is_some()
    }

    /// The law ([`ConnectorLaw::None`] without a connector).
    pub fn law(&self) -> &ConnectorLaw {
        self.0.as_deref().map_or(&NO_LAW, |c| &c.law)
    }

    /// See [`ConnectorRuntime::set_automatic_stiffness`].
    pub fn set_automatic_stiffness(&mut self, k: super::BlockedStiffness) {
        if let Some(c) = self.0.as_deref_mut() {
            c.set_automatic_stiffness(k);
        }
    }

    /// See [`ConnectorRuntime::max_stiffness`].
    pub fn max_stiffness(&self, blocked: &super::BlockedStiffness) -> (f64, f64) {
        match self.0.as_deref() {
            Some(c) => c.max_stiffness(blocked),
            None => NO_LAW.max_stiffness(blocked),
        }
    }

    /// See [`ConnectorRuntime::report`].
    #[cfg(test)]
    pub fn report(&self) -> Option<ConnectorReport> {
        self.0.as_deref().and_then(|c| c.report())
    }

    /// [`Self::report`] by reference.
    #[inline]
    pub(crate) fn report_ref(&self) -> &Option<ConnectorReport> {
        self.0.as_deref().map_or(&NO_REPORT, |c| c.report_ref())
    }

    /// See [`ConnectorRuntime::events`].
    pub fn events(&self) -> &[ConnectorEvent] {
        self.0.as_deref().map_or(&[], |c| c.events())
    }

    /// See [`ConnectorRuntime::switch_to_dynamic`].
    pub fn switch_to_dynamic(&mut self, time: f64, cause: FlexJointSwitchCause) -> bool {
        self.0
            .as_deref_mut()
            .is_some_and(|c| c.switch_to_dynamic(time, cause))
    }

    /// See [`ConnectorRuntime::apply`] (nothing without a connector).
    #[inline]
    pub fn apply(
        &mut self,
        prop: &KjointProperty,
        params: &LawParams,
        input: &ConnectorInput,
        out: &mut LawOutput,
        energy: &mut JointEnergy,
    ) {
        if let Some(c) = self.0.as_deref_mut() {
            c.apply(prop, params, input, out, energy);
        }
    }
}

/// A connector law with its state, events and bookkeeping, owned by one joint.
#[derive(Debug, Clone, PartialEq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct ConnectorRuntime {
    /// The law.
    pub law: ConnectorLaw,
    state: ConnectorState,
    prev_q: Option<[f64; 6]>,
    prev_force: [f64; 6],
    prev_damping: [f64; 6],
    /// The stick damping coefficients `c` of the previous evaluation (0 where the mechanism
    /// slid or has none): what the update applied over the interval that starts there.
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    prev_stick_damping: [f64; 6],
    slip_total: [f64; 2],
    report: Option<ConnectorReport>,
    events: Vec<ConnectorEvent>,
    /// Automatic stick stiffness from the substep (`None` until resolved).
    automatic: Option<super::BlockedStiffness>,
}

impl ConnectorRuntime {
    /// A connector with a fresh state (validate the law first with
    /// [`ConnectorLaw::validate`]).
    pub fn new(law: ConnectorLaw) -> Self {
        let state = match &law {
            ConnectorLaw::None => ConnectorState::None,
            ConnectorLaw::PlanarFriction(_) => {
                ConnectorState::PlanarFriction(PlanarFrictionState::default())
            }
            ConnectorLaw::FlexJoint(_) => ConnectorState::FlexJoint(FlexJointState::default()),
            ConnectorLaw::JointFriction(_) => {
                ConnectorState::JointFriction(JointFrictionState::default())
            }
        };
        ConnectorRuntime {
            law,
            state,
            ..Default::default()
        }
    }

    /// Sets the automatic stick stiffness of a planar friction law (`Kf = 0`, `Kr = 0`): the
    /// joint's automatic blocked stiffness for the substep (docs/kjoint2.md §5), whatever its `Kn`.
    pub fn set_automatic_stiffness(&mut self, k: super::BlockedStiffness) {
        self.automatic = Some(k);
    }

    /// Largest stiffness the law can add (see [`ConnectorLaw::max_stiffness`]), the
    /// automatic stick stiffnesses resolved ([`Self::set_automatic_stiffness`], else
    /// `blocked`).
    pub fn max_stiffness(&self, blocked: &super::BlockedStiffness) -> (f64, f64) {
        self.law.max_stiffness(&self.automatic.unwrap_or(*blocked))
    }

    /// The readout of the last evaluation (`None` without a connector or before the first).
    #[cfg(test)]
    pub fn report(&self) -> Option<ConnectorReport> {
        self.report
    }

    /// [`Self::report`] by reference.
    pub(crate) fn report_ref(&self) -> &Option<ConnectorReport> {
        &self.report
    }

    /// The events logged so far (phase switches), oldest first.
    pub fn events(&self) -> &[ConnectorEvent] {
        &self.events
    }

    /// Switches a flex joint to its dynamic phase at `time` \[s\], around the bending state of
    /// the last evaluation, and logs the event with its `cause`. Returns `false` when there
    /// is no flex joint or it is already dynamic.
    pub fn switch_to_dynamic(&mut self, time: f64, cause: FlexJointSwitchCause) -> bool {
        if let (ConnectorLaw::FlexJoint(f), ConnectorState::FlexJoint(st)) =
            (&self.law, &mut self.state)
        {
            if f.law.switch_to_dynamic(st, time) {
                self.events.push(ConnectorEvent {
                    time,
                    kind: ConnectorEventKind::FlexJointSwitched { cause },
                });
                return true;
            }
        }
        false
    }

    /// Adds the connector law to the KJOINT2 output `out` of the same evaluation and its
    /// energies to `energy` (see the module documentation for the equations).
    ///
    /// `params`: the blocked stiffness (the automatic stick stiffness until
    /// [`Self::set_automatic_stiffness`] resolved it) and reduced masses (stick damping) of
    /// the evaluation.
    pub fn apply(
        &mut self,
        prop: &KjointProperty,
        params: &LawParams,
        input: &ConnectorInput,
        out: &mut LawOutput,
        energy: &mut JointEnergy,
    ) {
        let (q, rate, time) = (&input.q, &input.rate, input.time);
        if matches!(self.law, ConnectorLaw::None) {
            return;
        }
        let dq: [f64; 6] = match self.prev_q {
            Some(p) => std::array::from_fn(|i| q[i] - p[i]),
            None => [0.0; 6],
        };
        let mut force = [0.0; 6];
        let mut damp = [0.0; 6];
        // the stick damping coefficients of the friction laws (`damp = c·q̇` on their DOFs)
        let mut stick = [0.0; 6];
        let automatic = self.automatic.unwrap_or(params.blocked);
        if let ConnectorLaw::FlexJoint(f) = &self.law {
            if let Some(switch_time) = f.switch_time.filter(|ts| time >= ts - 1e-12) {
                self.switch_to_dynamic(time, FlexJointSwitchCause::SwitchTime { switch_time });
            }
        }
        let ev = joint_friction::Evaluation {
            prop,
            params,
            automatic,
            dq,
            lever: input.lever,
        };
        match (&self.law, &mut self.state) {
            (ConnectorLaw::PlanarFriction(p), ConnectorState::PlanarFriction(st)) => {
                let (f, c, r) = planar::apply(p, st, &ev, &mut self.slip_total, out, energy);
                (force, stick) = (f, c);
                self.report = Some(ConnectorReport::PlanarFriction(r));
            }
            (ConnectorLaw::JointFriction(j), ConnectorState::JointFriction(st)) => {
                let slip = &mut self.slip_total[0];
                let (f, c, r) = joint_friction::apply(j, st, &ev, slip, out, energy);
                (force, stick) = (f, c);
                self.report = Some(ConnectorReport::JointFriction(r));
            }
            (ConnectorLaw::FlexJoint(f), ConnectorState::FlexJoint(st)) => {
                let hyst0 = st.dissipated_hysteresis;
                let damp0 = st.dissipated_damping;
                let input = FlexJointInput {
                    theta: [q[3], q[4], q[5]].into(),
                    dtheta: [dq[3], dq[4], dq[5]].into(),
                    rate: [rate[3], rate[4], rate[5]].into(),
                };
                let o = f.law.evaluate(st, &input);
                let cp = o.damping[(0, 0)];
                damp[3] = cp * rate[3];
                for i in 0..3 {
                    force[3 + i] = o.moment[i] - if i == 0 { damp[3] } else { 0.0 };
                    for j in 0..3 {
                        out.stiffness[(3 + i, 3 + j)] += o.stiffness[(i, j)];
                        out.damping[(3 + i, 3 + j)] += o.damping[(i, j)];
                    }
                }
                energy.elastic += o.elastic_energy;
                energy.friction += st.dissipated_hysteresis - hyst0;
                // The law's own damping work CP·θ̇x·Δθx replaces the trapezoidal one below.
                energy.damping += st.dissipated_damping - damp0;
                self.report = Some(ConnectorReport::FlexJoint(FlexJointReport {
                    bending_angle: o.bending_angle,
                    bending_axis: o.bending_axis.into(),
                    tilt_direction: o.tilt_direction.into(),
                    bending_moment: [o.moment.y, o.moment.z],
                    torsion_angle: o.torsion_angle,
                    torsion_moment: o.torsion_moment,
                    phase: o.phase,
                    switched_at: st.switch.map(|s| s.time),
                    yielding: o.yielding,
                    plastic_variation: o.plastic_variation.into(),
                    back_moment: o.back_moment.into(),
                    dissipated_hysteresis: st.dissipated_hysteresis,
                    dissipated_damping: st.dissipated_damping,
                    stored: o.elastic_energy,
                }));
            }
            _ => {}
        }
        let flex = matches!(self.law, ConnectorLaw::FlexJoint(_));
        if !flex {
            damp = std::array::from_fn(|i| stick[i] * rate[i]);
        }
        for i in 0..6 {
            out.parts[i].friction += if flex { 0.0 } else { force[i] };
            out.parts[i].elastic += if flex { force[i] } else { 0.0 };
            out.parts[i].damping += damp[i];
            out.total[i] += force[i] + damp[i];
        }
        if self.prev_q.is_some() {
            for i in 0..6 {
                energy.internal +=
                    0.5 * dq[i] * (force[i] + damp[i] + self.prev_force[i] + self.prev_damping[i]);
                if !flex {
                    // The stick damping the update applied over the interval from the previous
                    // evaluation is the one that evaluation had: none where the mechanism
                    // sticks from now on (it slid over the interval), its `c⁻·q̇` where it
                    // slides from now on (KJOINT2's friction and stops alike:
                    // `kjoint2::damping_at_interval_end`).
                    let end = super::kjoint2::damping_at_interval_end(
                        damp[i],
                        stick[i],
                        self.prev_stick_damping[i],
                        rate[i],
                    );
                    energy.damping += 0.5 * dq[i] * (end + self.prev_damping[i]);
                }
            }
        }
        self.prev_q = Some(*q);
        self.prev_force = force;
        self.prev_damping = damp;
        self.prev_stick_damping = stick;
    }
}

#[cfg(test)]
mod tests;
