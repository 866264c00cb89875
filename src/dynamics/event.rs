//! Events of a joint set, reported once each by [`super::KjointSet::drain_events`].
//!
//! An event is a [`KjointEvent`]: what it comes from ([`EventSource`], a sensor or a joint),
//! when (`time`, s) and what happened, a typed [`KjointEventKind`] whose variants carry the
//! event's data as fields (units on each field), as rapier's collision and contact-force
//! events do. Match on the kind to act on an event:
//!
//! | kind | source | [`Severity`] | what happened |
//! |---|---|---|---|
//! | [`KjointEventKind::SensorActivated`] | sensor | info | a sensor switched on, with its [`SensorCause`] |
//! | [`KjointEventKind::FlexJointSwitched`] | joint | info | a flex joint entered its dynamic phase, with its [`FlexJointSwitchCause`] |
//! | [`KjointEventKind::JointDetached`] | joint | info | a body of the joint was removed from the world |
//! | [`KjointEventKind::NoDynamicBody`] | joint | notice | neither body of the joint is dynamic any more: it acts on nothing until one is |
//! | [`KjointEventKind::MasslessBody`] | joint | warning | a dynamic body of a joint of automatic stiffness has no mass: it acts on nothing until the body has one |
//! | [`KjointEventKind::JointBroke`] | joint | info | the joint met its failure criterion and was removed (docs/breakable.md) |
//! | [`KjointEventKind::StiffnessBeyondSubstep`] | joint | notice | a free DOF's spring, stop, friction spring or connector law, alone or together, oscillates faster than the substep resolves |
//! | [`KjointEventKind::StiffnessLoweredFarFromOrigin`] | joint | notice | the joint is so far from the world origin that the f32 rounding of the poses over a substep squared exceeds the load acceleration its automatic stiffness is sized for: the force it transmits carries it |
//! | [`KjointEventKind::AnchorsApartAtInsertion`] | joint | notice | the anchors were apart on the blocked translations at insertion: the joint holds them so |
//! | [`KjointEventKind::SensorLockSofterThanSpring`] | joint | notice | a sensor's lock on a free DOF is softer than the DOF's spring whose force it holds |
//! | [`KjointEventKind::SpringCurvePreload`] | joint | notice | a free DOF's spring curve does not pass through (0, 0): the joint starts preloaded by its value at 0 |
//! | [`KjointEventKind::FlexJointAxisAcross`] | joint | warning | a flex joint's axis (the riser's) points across its bodies: bending is read as torsion |
//! | [`KjointEventKind::AnchorsSeparating`] | joint | warning | the anchors separate along the blocked translations |
//! | [`KjointEventKind::BlockedRotation`] | joint | warning | a blocked rotation opens |
//! | [`KjointEventKind::StopOverrun`] | joint | warning | a free DOF overruns its stop |
//! | [`KjointEventKind::NoLongerHolds`] | joint | warning | the joint no longer holds (with [`super::OnUnstable::Warn`], or where rapier's contacts opened it; else the step's error) |
//! | [`KjointEventKind::SensorJointRemoved`] | sensor | warning | the joint a sensor waits on was removed: it can fire only when triggered |
//!
//! The severity follows from the kind ([`KjointEventKind::severity`]). The health checks
//! behind the notices and warnings are described in `super::health` and docs/kjoint2.md;
//! an unstable run is not an event but an error ([`crate::SimError::Unstable`]), unless
//! [`super::OnUnstable::Warn`] makes it the warning [`KjointEventKind::NoLongerHolds`], or
//! rapier's contacts opened the joint (the same warning).
//!
//! `Display` gives the one-line text the command line, the CSV files (`events.csv`,
//! `warnings.csv`), the summary, the plots and the rerun recording print:
//! `[notice: |warning: ]<source> at t = <t> s: <what happened>`.
//!
//! ```
//! use rapier_kjoint::dynamics::{KjointEventKind, SensorCause, Severity};
//! use rapier_kjoint::{KjointSet, SensorCondition};
//! # fn main() -> Result<(), rapier_kjoint::SimError> {
//! let mut joints = KjointSet::new();
//! joints.add_sensor(3, SensorCondition::Manual)?;
//! joints.trigger_sensor(3);
//! for e in joints.drain_events() {
//!     match &e.kind {
//!         KjointEventKind::SensorActivated { cause: SensorCause::Triggered } => {
//!             assert_eq!(e.sensor(), Some(3));
//!             assert_eq!(e.severity(), Severity::Info);
//!             assert_eq!(e.to_string(), "sensor 3 at t = 0.000000 s: triggered on demand");
//!         }
//!         KjointEventKind::StopOverrun { dof, overrun, .. } => println!("{dof:?} overran by {overrun}"),
//!         _ => println!("{e}"),
//!     }
//! }
//! # Ok(()) }
//! ```

use super::joint::JointState;
use super::joint_set::KjointHandle;
use super::sensor::SensorId;
use crate::figure::format_figure as fig;
pub use crate::law::FlexJointSwitchCause;
use crate::law::{BreakCause, Dof, JointEnergy};
use serde::Serialize;
use std::fmt;

/// What an event comes from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub enum EventSource {
    /// A sensor (Radioss `sens_ID`): its activation, or a warning that it cannot fire.
    Sensor(SensorId),
    /// A joint (its connector law, its bodies or its health).
    Joint {
        /// The joint.
        handle: KjointHandle,
        /// Its name.
        name: String,
    },
}

impl fmt::Display for EventSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EventSource::Sensor(id) => write!(f, "sensor {id}"),
            EventSource::Joint { name, .. } => write!(f, "joint {name}"),
        }
    }
}

/// How much an event matters to the user.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub enum Severity {
    /// Something that happened as modelled (a sensor fired, a phase switched).
    #[default]
    Info,
    /// Worth knowing about the model (a DOF the substep cannot resolve).
    Notice,
    /// The run may be wrong (anchors separating, a stop overrun): the text names the joint
    /// and a remedy.
    Warning,
}

/// Why a sensor activated: which of its [`super::SensorCondition`]s held.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[non_exhaustive]
pub enum SensorCause {
    /// The simulation time reached the sensor's time ([`super::SensorCondition::Time`]).
    TimeReached {
        /// The sensor's time \[s\] (the event's `time` is the substep's start, at or just
        /// after it).
        time: f64,
    },
    /// A DOF of a joint passed the sensor's value ([`super::SensorCondition::DofPasses`]).
    DofPassed {
        /// The watched joint.
        joint: KjointHandle,
        /// Its name.
        joint_name: String,
        /// The watched DOF.
        dof: Dof,
        /// The threshold \[m or rad\].
        value: f64,
        /// The DOF's value measured at the activation, past the threshold \[m or rad\].
        measured: f64,
    },
    /// The force or moment a DOF of a joint transmitted over a substep reached the sensor's
    /// value ([`super::SensorCondition::ForceReaches`]).
    ForceReached {
        /// The watched joint.
        joint: KjointHandle,
        /// Its name.
        joint_name: String,
        /// The watched DOF.
        dof: Dof,
        /// The threshold \[N or N·m\].
        value: f64,
        /// The force or moment the DOF transmitted over the substep before the activation
        /// \[N or N·m\].
        measured: f64,
    },
    /// [`super::KjointSet::trigger_sensor`] was called.
    Triggered,
}

impl fmt::Display for SensorCause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SensorCause::TimeReached { time } => write!(f, "time {time} s reached"),
            SensorCause::DofPassed {
                joint_name,
                dof,
                value,
                ..
            } => write!(
                f,
                "joint `{joint_name}` {} passed {value} {}",
                dof.name(),
                dof.unit()
            ),
            SensorCause::ForceReached {
                joint_name,
                dof,
                value,
                ..
            } => write!(
                f,
                "joint `{joint_name}` {} {} reached {value} {}",
                dof.name(),
                dof.load().0,
                dof.load().1
            ),
            SensorCause::Triggered => f.write_str("triggered on demand"),
        }
    }
}

/// Which stiffness of a free DOF a [`KjointEventKind::StiffnessBeyondSubstep`] notice is
/// about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[non_exhaustive]
pub enum DofStiffness {
    /// The DOF's spring (its stiffness scale, times a curve's steepest slope).
    Spring,
    /// The DOF's stops (the friction stiffness `Kf`, or the blocked stiffness `Kn`).
    Stop,
    /// The DOF's friction spring `Kf` while it sticks, on a DOF without stops.
    Friction,
    /// The stiffness the joint's connector law adds to the DOF
    /// ([`crate::law::ConnectorLaw::dof_stiffness`]: a flex joint's bending or torsion law).
    Connector,
    /// The DOF's motor ([`crate::KjointMotor::stiffness`] `k_p`): unresolved, the update
    /// damps it (`h·k_p` at most), and the motor's part of the readout, `k_p·(q* − q) +
    /// k_d·(q̇* − q̇)`, then differs from what the joint transmits by about that damping
    /// times the rate (`JointState::applied` is what it transmits; the difference is booked
    /// as `numerical`): a UR5 shoulder of `k_p` = 1e4 N·m/rad lifting the arm at 4 substeps
    /// read 80.9 N·m where it transmitted 54.5, with no notice (a robotics engineer's
    /// trial, 2026-12-04).
    Motor,
    /// Two or more of the above together, none of which the substep leaves unresolved
    /// alone: their sum is the DOF's tangent stiffness while they act at once (a spring and
    /// a sticking friction spring, a spring in stop contact), and the numerical damping
    /// judges that sum. The flags say which take part.
    Together {
        /// The DOF's spring.
        spring: bool,
        /// Its stops.
        stop: bool,
        /// Its friction spring (a DOF without stops).
        friction: bool,
        /// The connector law.
        connector: bool,
        /// The motor (`false` where absent: events saved before the motor counted).
        #[cfg_attr(feature = "serde-serialize", serde(default))]
        motor: bool,
    },
}

impl fmt::Display for DofStiffness {
    /// `spring`, `stop`, `friction spring`, `connector law`, `motor`, or those of
    /// [`Self::Together`] joined by ` + `.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let one = match self {
            DofStiffness::Spring => "spring",
            DofStiffness::Stop => "stop",
            DofStiffness::Friction => "friction spring",
            DofStiffness::Connector => "connector law",
            DofStiffness::Motor => "motor",
            DofStiffness::Together {
                spring,
                stop,
                friction,
                connector,
                motor,
            } => {
                let names = [
                    (*spring, "spring"),
                    (*stop, "stop"),
                    (*friction, "friction spring"),
                    (*connector, "connector law"),
                    (*motor, "motor"),
                ];
                let mut first = true;
                for (_, name) in names.into_iter().filter(|(on, _)| *on) {
                    if !first {
                        f.write_str(" + ")?;
                    }
                    f.write_str(name)?;
                    first = false;
                }
                return Ok(());
            }
        };
        f.write_str(one)
    }
}

/// What a health warning advises.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[non_exhaustive]
pub enum HealthRemedy {
    /// The blocked stiffness explains the separation under the joint's load (within a
    /// factor of 2): the joint is soft, a larger `Kn` holds it closer.
    LargerBlockedStiffness {
        /// The joint's blocked stiffness \[N/m for a separation, N·m/rad for a rotation\].
        stiffness: f64,
    },
    /// As [`Self::LargerBlockedStiffness`], where that stiffness is the automatic one of the
    /// implicit rule at its f32 noise bound ([`crate::law::stiffness`], "Do not turn f32
    /// noise into force"): the rule keeps the f32 rounding of rapier's poses at the joint's
    /// distance from the origin within 1 % of its load side's weight as force. That bound
    /// does not depend on the substep (`K = η·a·m_L/(ε·r)` at any substep shorter than
    /// `bound.full_substep` down to half of it, `16·m_L/h²` below it at a longer one): only
    /// a substep shorter than half `bound.full_substep`, where the rule's floor `κ = 4`
    /// takes over (`4·m_L/h²`), gives the joint a larger automatic stiffness. What does as
    /// well: an explicit `Kn`, the `f64` feature, a model nearer the origin. Where the joint carries more than twice the load the rule
    /// sizes it for (a contact's, an impact's, a grasped object's), the text names the `Kn`
    /// that keeps the rounding within 1 % of the load it carries
    /// ([`NoiseBound::stiffness_within`](crate::law::stiffness::NoiseBound::stiffness_within));
    /// where it does not and a substep within the frame gives the rule's full `κ`, it says
    /// that such a substep damps the joint's oscillation (it holds the DOF as the update's
    /// constraint, `ω·h = 4`) without making it stiffer. It never advises a substep longer
    /// than the frame.
    NoiseBoundedStiffness {
        /// The joint's blocked stiffness \[N/m for a separation, N·m/rad for a rotation\].
        stiffness: f64,
        /// The load the joint carries on the blocked DOFs \[N for a separation, N·m for a
        /// rotation\].
        load: f64,
        /// How far the bound lowered it, what the joint holds up and where.
        bound: crate::law::stiffness::NoiseBound,
    },
    /// The separation is dynamics the substep misses: more substeps (a shorter substep), a
    /// smaller frame time step, or lighter loads.
    ShorterSubstep,
    /// As [`Self::ShorterSubstep`], where rapier's contacts pushed body `body` (1 or 2) of
    /// the joint during the excursion: they act after the joints are solved in each
    /// substep, so a hard contact opens the joint before it answers (a robot's wrist
    /// against a table: the warning spoke of loads only; a robotics user's trial,
    /// 2026-12-05).
    ContactPushed {
        /// The joint's body the contacts pushed.
        body: u8,
        /// Substeps a frame that would keep the opening within its warning bound, as
        /// `[fewest, most]`: an opening a contact makes shrinks as the substep to a power
        /// between 2 (a standing robot's knees: 3.3, 0.85, 0.20 mm at 4, 8, 16 substeps)
        /// and 1 (a landing), so from `n·√r` to `n·r` for an opening `r` times its bound at
        /// `n` substeps (`[0, 0]`: not known, an event saved before it was recorded), each
        /// at most the [`crate::scene::MAX_SUBSTEPS`] a set takes: `[MAX, MAX]` where more
        /// would be needed, and the text then says what else must change (a smaller frame
        /// time step, a stiffer joint).
        #[cfg_attr(feature = "serde-serialize", serde(default))]
        substeps: [u32; 2],
    },
}

/// What makes an overrun stop as soft as it is ([`KjointEventKind::StopOverrun`]), and so
/// what stiffens it. A stop's stiffness is the DOF's friction spring `Kf` where it has
/// one, else the joint's blocked stiffness (`Kn`, `KR` on a rotation; docs/kjoint2.md
/// §4.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[non_exhaustive]
pub enum StopRemedy {
    /// The stop is as stiff as the DOF's friction spring `Kf`
    /// ([`crate::law::DofLaw::with_friction`]): a door with friction `Kf` = 1e4 N·m/rad
    /// slammed on its limit went 0.22 rad past it and bounced back (a game developer's
    /// trial, 2026-12-04). A larger `Kf` stiffens it (and the sticking friction with it).
    FrictionSpring {
        /// `Kf` \[N/m, or N·m/rad on a rotation\].
        stiffness: f64,
    },
    /// The stop is as stiff as the joint's automatic blocked stiffness, which the f32
    /// rounding of rapier's poses at the joint's distance from the world origin lowered
    /// more than twofold, above the bound's floor `κ = 4`
    /// ([`HealthRemedy::NoiseBoundedStiffness`]): more substeps do not stiffen it until
    /// the floor takes over (before the floor, more substeps overran a ragdoll's limits
    /// further 1000 m out); the `f64` feature, a model nearer the origin or an explicit
    /// `Kn` does. (Rare since the stop prediction holds the
    /// stops of the automatic stiffness as rigid limits, independent and, since 2026-12-04,
    /// coupled ones, wherever the joint is: that ragdoll's cones no longer overrun.)
    NoiseBounded {
        /// The stop's stiffness \[N/m, or N·m/rad on a rotation\].
        stiffness: f64,
        /// The joint anchor's distance from the world origin \[m\].
        distance: f64,
        /// How many times softer than the same joint at the origin.
        lowered: f64,
    },
    /// The stop is as stiff as the joint's blocked stiffness: the overrun is an impact the
    /// substep does not resolve. A stiffer stop (`Kn`, `KR`) or more substeps.
    ShorterSubstep {
        /// The stop's stiffness \[N/m, or N·m/rad on a rotation; 0 in events saved before
        /// the remedy was recorded\].
        stiffness: f64,
    },
}

impl Default for StopRemedy {
    /// [`Self::ShorterSubstep`] of unknown stiffness (0): what an event saved before the
    /// remedy was recorded said.
    fn default() -> Self {
        StopRemedy::ShorterSubstep { stiffness: 0.0 }
    }
}

/// The remedies of an unstable or separating joint.
pub(crate) const REMEDY: &str = "more substeps (a shorter substep), a smaller frame time step, \
     or lighter loads";
/// What a contact does to a joint that no longer holds, said of the body it pushed.
pub(crate) const CONTACT_OPENS: &str = "was pushed by rapier's contacts (or its own joints), \
     which act after the joints are solved in each substep: a hard contact (a landing, a foot \
     driven into the ground) opens the joint before it answers, the less the shorter the \
     substep";
/// What shortens an opening where the substeps a frame it needs are beyond the most a set
/// takes ([`crate::scene::MAX_SUBSTEPS`]).
pub(crate) const BEYOND_MAX_SUBSTEPS: &str = "a smaller frame time step (the substep is the \
     frame's over the substeps), a stiffer joint (a larger Kn, or scale factor ScF for one of \
     automatic stiffness) or lighter loads";
/// The blocked stiffness of an event saved before it was recorded: 0, not known.
#[cfg(feature = "serde-serialize")]
fn unknown_blocked_stiffness() -> crate::law::BlockedStiffness {
    crate::law::BlockedStiffness {
        translational: 0.0,
        rotational: 0.0,
    }
}
/// The remedy of a joint that no longer holds because a body was moved away.
pub(crate) const TELEPORT: &str = "where a body was moved (teleported) away from the body it is \
     jointed to, move the bodies a joint links together";

impl HealthRemedy {
    fn fmt_with_unit(&self, f: &mut fmt::Formatter<'_>, rotation: bool) -> fmt::Result {
        let unit = if rotation { "N·m/rad" } else { "N/m" };
        let stiffness = match self {
            HealthRemedy::LargerBlockedStiffness { stiffness }
            | HealthRemedy::NoiseBoundedStiffness { stiffness, .. } => stiffness,
            HealthRemedy::ShorterSubstep => return write!(f, "remedies: {REMEDY}"),
            HealthRemedy::ContactPushed { body, substeps } => {
                write!(f, "its body {body} {CONTACT_OPENS}; remedies: {REMEDY}")?;
                let [fewest, most] = *substeps;
                let about = if fewest == most {
                    format!("{fewest}")
                } else {
                    format!("{fewest} to {most}")
                };
                // (the advice is capped at the most a set takes: `health::contact_substeps`)
                let max = crate::scene::MAX_SUBSTEPS as u32;
                if fewest >= max {
                    write!(
                        f,
                        " (about {max} substeps a frame or more would keep this opening \
                         within the warning's bound, and {max} is the most a set takes: \
                         {BEYOND_MAX_SUBSTEPS} must do the rest)"
                    )?;
                } else if fewest > 0 {
                    write!(
                        f,
                        " (about {about} substeps a frame would keep this opening within \
                         the warning's bound: a contact's opening shrinks as the substep \
                         squared to as the substep"
                    )?;
                    if most >= max {
                        write!(
                            f,
                            "; {max} is the most a set takes: where it is not enough, \
                             {BEYOND_MAX_SUBSTEPS} must do the rest"
                        )?;
                    }
                    f.write_str(")")?;
                }
                return Ok(());
            }
        };
        let HealthRemedy::NoiseBoundedStiffness { load, bound, .. } = self else {
            write!(
                f,
                "the blocked stiffness {} {unit} gives it under the joint's load",
                fig(*stiffness)
            )?;
            return f.write_str(": set a larger Kn to hold the joint closer");
        };
        let load_unit = if rotation { "N·m" } else { "N" };
        let floor_substep = bound.floor_substep();
        // the fewest substeps a frame of that length or shorter
        let floor_substeps = (bound.frame / floor_substep).ceil().max(1.0) as usize;
        write!(
            f,
            "the blocked stiffness {} {unit} gives it under the joint's load of {} {load_unit}: \
             the automatic one, lowered to keep the f32 rounding of the poses {} m from the \
             origin out of the force (κ = {} of {} at this substep), the most the rule gives it \
             at any substep longer than {} s; from {} substeps a frame its floor κ = {} takes \
             over and grows as 1/h²; ",
            fig(*stiffness),
            fig(*load),
            fig(bound.load.anchor_distance),
            fig(bound.kappa),
            crate::law::stiffness::IMPLICIT_KAPPA,
            fig(floor_substep),
            floor_substeps,
            crate::law::stiffness::IMPLICIT_KAPPA_FLOOR,
        )?;
        let ratio = bound.load_ratio(*load, rotation);
        if ratio > 2.0 {
            write!(
                f,
                "it carries {} times the {} of the {} kg it holds up, which the rule sizes it \
                 for (a contact's, an impact's or a grasped object's load is not in it): an \
                 explicit Kn ",
                fig(ratio),
                if rotation {
                    "moment of the weight, at its radius of gyration,"
                } else {
                    "weight"
                },
                fig(bound.load.mass),
            )?;
            let within = bound.stiffness_within(*load, rotation);
            if rotation {
                write!(
                    f,
                    "whose KR = Kn·max(ScF, L0²) is up to {} N·m/rad",
                    fig(within)
                )?;
            } else {
                write!(f, "up to {} N/m", fig(within))?;
            }
            f.write_str(
                " (the f32 rounding within 1 % of that load) holds the joint closer, as do the \
                 `f64` feature and a model nearer the origin",
            )
        } else {
            f.write_str(
                "an explicit Kn, the `f64` feature or a model nearer the origin holds the joint \
                 closer",
            )?;
            if bound.substeps == 0 {
                return Ok(());
            }
            write!(
                f,
                "; {} substeps a frame of {} s or fewer (a substep of {} s or longer) give it the \
                 rule's full κ, which the update holds and damps rather than letting it ring, \
                 but no larger stiffness",
                bound.substeps,
                fig(bound.frame),
                fig(bound.full_substep)
            )
        }
    }
}

/// What happened: one variant per kind of event, its data as fields.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[non_exhaustive]
pub enum KjointEventKind {
    /// A sensor activated (the joints whose property names it lock all their DOFs).
    SensorActivated {
        /// Its condition that held.
        cause: SensorCause,
    },
    /// A flex joint switched from its quasi-static to its dynamic phase.
    FlexJointSwitched {
        /// Why.
        cause: FlexJointSwitchCause,
    },
    /// A body of the joint was removed from the world: the joint is removed from the set (its
    /// handle finds nothing), as rapier's `ImpulseJointSet` removes the joints of a removed
    /// body.
    JointDetached {
        /// Its energies when it was removed \[J\] (added to
        /// [`super::KjointSet::removed_energy`]).
        energy: JointEnergy,
        /// Its last readout (`None` if it never took a substep).
        last: Option<Box<JointState>>,
    },
    /// A body of the joint was disabled (`RigidBody::set_enabled(false)`): the joint acts
    /// on nothing until its bodies are all enabled again ([`super::Kjoint::is_enabled`]), as
    /// rapier's impulse joints attached to a disabled body do.
    DisabledByBody {
        /// Which body was found disabled: `1` or `2` (`1` when both are).
        body: u8,
    },
    /// Neither body of the joint is dynamic any more (each fixed or kinematic, switched so
    /// with `RigidBody::set_body_type` after the insertion: a vehicle frozen for a cutscene,
    /// a part held by a kinematic fixture): the joint acts on nothing until a body is
    /// dynamic again, as rapier's joints between such bodies, and is treated as a disabled
    /// one meanwhile ([`super::Kjoint::is_enabled`] is `false`). Every step failed on such a
    /// joint ("automatic stiffness is zero: neither body is dynamic"), and the whole world
    /// with it (a game developer's trial, 2026-12-04).
    NoDynamicBody,
    /// A dynamic body of the joint, whose stiffness is automatic, has no mass (its colliders
    /// removed, none with a density, no additional mass): the joint acts on nothing until
    /// it has one, as one of a disabled body ([`super::Kjoint::is_enabled`] is `false`); a
    /// joint of the user's `Kn` takes such a body as infinitely heavy, as rapier's do. (Its automatic stiffness had no mass
    /// to scale with, and every later step failed, "automatic stiffness is zero", stopping
    /// the whole world: an engine integrator's trial, 2026-12-05. rapier's own joints take
    /// such a body as infinitely heavy and drag what it is jointed to along at its constant
    /// velocity.) Remedies: a collider with a density, or `set_additional_mass`.
    MasslessBody {
        /// Which body has no mass: `1` or `2` (`1` when both have none).
        body: u8,
    },
    /// The joint has a sensor, and its lock on a free DOF (the blocked stiffness of the
    /// DOF's family: `Kn`, or `KR = Kn·max(ScF, L0²)` on a rotation) is softer than the
    /// DOF's own spring. The lock holds the force the DOF carries when the sensor fires and
    /// adds `K_lock·(q − q_s)` (docs/kjoint2.md §4.5): the spring no longer pulls the DOF
    /// back, so its held force drives the DOF on to about `q_s·(1 − K/K_lock)`. A Radioss
    /// deck in kg, mm, ms with `Kn` = 0.01 kN/mm and ScF left blank got `KR` = 0.1 N·m/rad
    /// under a 10 N·m/rad spring: its locked hinge ran to −3 rad where it swung ±0.1 rad
    /// unlocked, with no word (an analyst's trial, 2026-12-04). Once per joint and DOF, at
    /// its first substep.
    SensorLockSofterThanSpring {
        /// The DOF.
        dof: Dof,
        /// The lock's stiffness \[N/m, or N·m/rad on a rotation\].
        lock: f64,
        /// The DOF's spring stiffness (a curve's steepest slope times its scale) \[same
        /// units\].
        spring: f64,
    },
    /// A free DOF's spring curve (`fct_K`) does not pass through (0, 0): at `q = 0`, the pose
    /// at insertion, its force is `K·f(0)`, a preload the joint starts with, which moves its
    /// bodies until something balances it; the stored energy, the curve's integral from
    /// `q = 0`, is negative where the preload did work (a block on `[[-1, -99], [0, 1], [1,
    /// 101]]` N drifted to −0.01 m and the summary read −0.0046 J stored, with nothing said;
    /// a Radioss analyst's trial, 2026-12-06). Once per joint and DOF, at its first substep.
    SpringCurvePreload {
        /// The DOF.
        dof: Dof,
        /// `K·f(0)` \[N or N·m\].
        force: f64,
    },
    /// The joint was inserted with its anchors apart on its blocked translations (by more
    /// than [`super::GAP_WARNING`] of its size and [`super::GAP_FLOOR`]): the pose at
    /// insertion is its unloaded one (Radioss' `δ0`, docs/kjoint2.md §3), so it holds its
    /// bodies that far apart for good. A ragdoll's joint given anchors 0.1 m off by mistake
    /// was told of only by separation warnings; a ball re-attached 0.231 m off stayed
    /// there (a game developer's trial, 2026-12-04). Local anchors that meet join the
    /// bodies at one point; a joint meant as a rigid link of that length (a Radioss deck's
    /// nodes apart, its `L0`) is noticed too. Once per joint, at its first substep.
    AnchorsApartAtInsertion {
        /// The anchors' distance on the blocked translations at insertion \[m\].
        offset: f64,
        /// The joint's size \[m\] (the health checks' scale).
        size: f64,
    },
    /// A flex joint's axis, its working frame's x (the riser's axis: bending about y and z,
    /// torsion about x), points across both of its bodies: the line from the anchor to no
    /// dynamic body's centre of mass lies within 45° of it, so the riser's bending is read
    /// as torsion. A joint given no frame takes the world axes when its anchors meet (a
    /// riser hanging along −y with no `frame` read a 20 kN·m bending moment as torsion,
    /// 3.5e-5 rad on the torsion stiffness where the bending curve gives 0.4°, and the run
    /// ended with exit 0: an offshore engineer's trial, 2026-12-06). Once per joint, at its
    /// first substep; not for a classical law (a bending law alone), which acts on the total
    /// rotation angle whatever the axes.
    FlexJointAxisAcross {
        /// The axis in world coordinates at the first substep.
        axis: [f64; 3],
        /// The smallest angle between the axis line and the line from the anchor to a
        /// dynamic body's centre of mass \[rad\].
        angle: f64,
    },
    /// The user switched the joint off ([`super::KjointSet::set_enabled`],
    /// [`super::KjointBuilder::enabled`]): it acts on nothing until it is switched on again,
    /// as rapier's impulse joints disabled by `GenericJoint::set_enabled(false)` do. Given
    /// also to a joint already disabled by a body when the user switches it off (the
    /// switch wins; switched on again while the body is still disabled, it gives
    /// [`Self::DisabledByBody`]).
    DisabledByUser,
    /// A disabled joint acts again, from its state at disabling: its bodies are all enabled
    /// again, one of them dynamic, and its user's switch is on (whichever disabled it).
    EnabledAgain,
    /// The joint met its failure criterion ([`crate::law::BreakCriterion`],
    /// docs/breakable.md) on the force and moment it transmitted over the substep that
    /// started at the event's `time` (or on its dissipated energy): it was removed from the
    /// set at the end of that substep (its handle finds nothing), its energies added to
    /// [`super::KjointSet::removed_energy`].
    JointBroke {
        /// Which limit was met, the measured value and the limit.
        cause: BreakCause,
        /// Its energies when it was removed, the breaking substep's included \[J\].
        energy: JointEnergy,
        /// Its readout of the breaking substep: the force it transmitted then, its
        /// deflections (`None` if it never took a substep).
        last: Option<Box<JointState>>,
    },
    /// A free DOF's spring or stop oscillates faster than the substep resolves
    /// (`ω = √(K·W) > 1/h`, `W` the DOF's own effective inverse mass): it is held by the
    /// implicit update and its oscillation damped numerically. Given at the start and after
    /// every topology change.
    StiffnessBeyondSubstep {
        /// The DOF.
        dof: Dof,
        /// Its spring, its stop, its friction spring, its connector law, or several of
        /// them together.
        stiffness_of: DofStiffness,
        /// The stiffness \[N/m or N·m/rad\].
        stiffness: f64,
        /// Its angular frequency `ω` on the DOF's effective mass \[rad/s\].
        omega: f64,
        /// The substep `h` \[s\].
        substep: f64,
        /// Substeps per frame that would resolve it, `⌈ω·h·n⌉` with `n` the current count
        /// (a whole number).
        substeps_needed: f64,
    },
    /// The joint is so far from the world origin that the f32 rounding of rapier's poses
    /// there over a substep squared, `ε·r/h²`, exceeds the load acceleration its automatic
    /// stiffness (the implicit rule's, `Kn = 0`) is sized for ([`super::FAR_FROM_ORIGIN`]):
    /// the noise bound ([`crate::law::stiffness::NoiseBound`]) holds it at its floor
    /// `κ = 4`, where it still holds as near the origin (sagging `m_L·a/K` under its load's
    /// weight), and the force it transmits carries that rounding (a 1 kg ball swinging
    /// 1 km out at 16 substeps: 3.1 N s.d. on its 10 N; 3–7 % of `m·ε·r/h²`). Given at the
    /// start and after every topology change. Remedies: a model near the origin, the `f64`
    /// feature or fewer substeps (the rounding's acceleration goes as `1/h²`); a larger
    /// `Kn` does not take the noise out.
    StiffnessLoweredFarFromOrigin {
        /// The anchor's distance from the world origin \[m\].
        distance: f64,
        /// The blocked stiffness it got: translational \[N/m\], rotational \[N·m/rad\].
        stiffness: crate::law::BlockedStiffness,
        /// The translational stiffness the rule gives it at the origin, at this substep
        /// \[N/m\].
        origin_stiffness: f64,
        /// `κ_eff` here (the rule's own is 16, its floor 4).
        kappa: f64,
        /// `κ_eff` at the origin.
        origin_kappa: f64,
        /// The f32 rounding `ε·r` of its measured deflection \[m\].
        noise: f64,
        /// That rounding over a substep squared, `ε·r/h²` \[m/s²\] (0 when read from a
        /// file saved before 2026-12-05).
        #[cfg_attr(feature = "serde-serialize", serde(default))]
        rounding: f64,
        /// Its deflection under its load side's weight, `m_L·a/K` \[m\].
        sag: f64,
    },
    /// The anchors separate along the blocked translations by more than
    /// [`super::GAP_WARNING`] of the joint's size. Once per joint, at the first substep
    /// it is seen (`gap` is the separation then), and again whenever it has grown
    /// [`super::WARNING_GROWTH`]-fold over the last one given (the scene summary shows the
    /// worst of those, and its `gap` column the worst of the run; a program reads
    /// [`super::Kjoint::blocked_gap`], or [`super::JointState::anchor1`] and `anchor2`).
    AnchorsSeparating {
        /// The separation \[m\].
        gap: f64,
        /// The joint's size \[m\]: the lever arms from its dynamic bodies' centres of mass
        /// to their own anchors, each at least its body's radius of gyration, fixed in the
        /// bodies (it does not grow as the anchors part),
        /// at least the initial length and [`super::MIN_SIZE`] (`super::health`).
        size: f64,
        /// What to do.
        remedy: HealthRemedy,
    },
    /// A blocked rotation exceeds [`super::ROTATION_WARNING`]. Once per joint, and again
    /// whenever it has grown [`super::WARNING_GROWTH`]-fold over the last one given.
    BlockedRotation {
        /// The largest blocked rotation \[rad\].
        angle: f64,
        /// What to do.
        remedy: HealthRemedy,
    },
    /// The joint no longer holds: its anchors are more than [`super::GAP_ERROR`] of its size
    /// apart, or a blocked rotation is beyond [`super::ROTATION_ERROR`], each more than
    /// [`super::UNEXPLAINED`] times what the force it transmits explains (a body moved away
    /// from the body it is jointed to, a frame far too long for the joint, a hard contact).
    /// Given where [`super::SubstepSettings::on_unstable`] is [`super::OnUnstable::Warn`]
    /// (else the step returns [`crate::SimError::Unstable`]), and whatever that setting
    /// where rapier's contacts opened the joint (`contact`: they act after the joints are
    /// solved in each substep), until the joint is back within the bounds unless the
    /// opening grows fourfold or stays beyond them longer than a push's does
    /// ([`super::CONTACT_CREDIT_SUBSTEPS`] substeps, at least
    /// [`super::CONTACT_CREDIT_TIME`]); once per joint and again whenever it is fourfold further
    /// beyond those bounds. The joint pulls its bodies back at its blocked stiffness. The
    /// text names, for each opening beyond its bound, the load on it, the blocked
    /// stiffness it meets and the deflection they account for, in the error's words, and
    /// where that stiffness is automatic and explains the opening, the error's advice (more
    /// substeps, a larger scale factor `ScF` or an explicit `Kn`).
    NoLongerHolds {
        /// The anchors' separation along the blocked translations \[m\].
        gap: f64,
        /// The joint's size \[m\] (as in [`Self::AnchorsSeparating`]).
        size: f64,
        /// The largest blocked rotation \[rad\].
        rotation: f64,
        /// Its body (1 or 2) that rapier's contacts pushed over the substep before, if any:
        /// contacts act after the joints are solved, so that a hard one opens a joint before
        /// it answers (a quadruped's calf on the ground under strong torques at 4 substeps).
        #[cfg_attr(feature = "serde-serialize", serde(default))]
        contact: Option<u8>,
        /// The force the joint transmits along its blocked translations \[N\]: through
        /// `stiffness.translational` it explains `force/Kn` of the gap (0 in events saved
        /// before it was recorded).
        #[cfg_attr(feature = "serde-serialize", serde(default))]
        force: f64,
        /// The largest moment about its blocked rotations \[N·m\]: through
        /// `stiffness.rotational` it explains `moment/KR` of the rotation.
        #[cfg_attr(feature = "serde-serialize", serde(default))]
        moment: f64,
        /// The joint's blocked stiffness, `Kn` \[N/m\] and `KR` \[N·m/rad\] (0 in events
        /// saved before it was recorded).
        #[cfg_attr(
            feature = "serde-serialize",
            serde(default = "unknown_blocked_stiffness")
        )]
        stiffness: crate::law::BlockedStiffness,
        /// Whether that stiffness is automatic (`Kn = 0`): the set's rule chose it for this
        /// substep to hold the joint, so that an opening its load explains says the substep
        /// is too long for the load (the rule's stiffness grows as `1/h²`), where under an
        /// explicit `Kn` it is the user's penalty stretching.
        #[cfg_attr(feature = "serde-serialize", serde(default))]
        automatic: bool,
    },
    /// A free DOF is beyond one of its stops by more than [`super::STOP_WARNING`]
    /// (rad, or for a translation that fraction of the joint's size or of the stop's
    /// travel, the larger); for coupled stops, the members' distance beyond the stop's
    /// radius, named by the member farthest out. Once per joint, at the first substep it is
    /// seen, and again whenever the overrun has grown [`super::WARNING_GROWTH`]-fold (the
    /// scene summary gives the worst of the run; a program reads
    /// [`super::JointState::q`]). A stop on a DOF with friction is as stiff
    /// as its friction spring `Kf` ([`crate::law::DofLaw::with_friction`]).
    StopOverrun {
        /// The first such DOF.
        dof: Dof,
        /// By how much it was beyond its stop at that substep \[m or rad\].
        overrun: f64,
        /// What makes the stop as soft as it is, and so what stiffens it.
        #[cfg_attr(feature = "serde-serialize", serde(default))]
        remedy: StopRemedy,
    },
    /// A free DOF is beyond the end of its spring's curve where the curve's linear
    /// extrapolation pushes it further out without bound
    /// ([`crate::law::CurveData::runaway_bounds`]): past `edge` the force `K·f(δ)` of a
    /// softening curve whose end segment falls points away from the joint's zero and grows
    /// as the DOF goes, and the joint runs away (to kilometres, where the f32 poses no
    /// longer give its numbers: a Radioss analyst's trial, 2026-12-05). OpenRadioss
    /// extrapolates a curve the same way; the run goes on. Once per joint, and again
    /// whenever the DOF has gone [`super::WARNING_GROWTH`] times further; not on a side
    /// where the DOF has a stop.
    SpringRunsAway {
        /// The DOF.
        dof: Dof,
        /// Its value at that substep \[m or rad\].
        value: f64,
        /// Where the extrapolation turns to push outwards \[m or rad\].
        edge: f64,
        /// The spring's tangent stiffness there, `K·f'` (negative) \[N/m or N·m/rad\].
        stiffness: f64,
    },
    /// The joint's rotations are measured by the relative rotation vector (a spherical or
    /// free joint), which jumped by more than [`super::ROTATION_JUMP`] in a substep: the
    /// relative rotation completed a full turn while turning about another axis than the one
    /// it had turned about, where no measure that depends on the pose alone is continuous
    /// (`kinematics`, "rotation_vector"; OpenRadioss sums increments, which drift). The
    /// springs, stops and friction springs of the free rotations act on the jump (a cone
    /// stop read 5.9 rad of penetration and pushed with 584 N·m where 5 N·m was due: a
    /// Radioss analyst's trial, 2026-12-05). Given where a free rotation carries such a law
    /// (or a motor or connector law), once per joint.
    RotationVectorJumped {
        /// `|θ|` after the jump \[rad\].
        angle: f64,
        /// `|Δθ|` over the substep \[rad\].
        jump: f64,
    },
    /// A dynamic body of the joint spins at rapier's cap on a body's rotation per step,
    /// `π/4` over the substep `h` (`π/(4h)`: 377 rad/s at 60 Hz and 8 substeps): rapier
    /// clips its angular speed there (with the kinetic energy it carries) unless the body
    /// allows fast rotation (`RigidBodyBuilder::allow_fast_rotation(true)`,
    /// `RigidBody::set_allow_fast_rotation`; a scene's bodies all do). Once per body, after
    /// the frame in which it was seen.
    SpinCapped {
        /// Which body of the joint: 1 or 2.
        body: u8,
        /// Its angular speed \[rad/s\].
        speed: f64,
        /// rapier's cap `π/(4h)` \[rad/s\].
        cap: f64,
    },
    /// The joint that a sensor not yet activated watches
    /// ([`super::SensorCondition::DofPasses`] or [`super::SensorCondition::ForceReaches`])
    /// was removed from the set (it broke, a body of it was removed, or
    /// [`super::KjointSet::remove`]): its condition can no longer be measured, so the sensor
    /// stays off unless [`super::KjointSet::trigger_sensor`] is called, and the joints it
    /// would have locked do not lock.
    SensorJointRemoved {
        /// The removed joint (its handle finds nothing now).
        joint: KjointHandle,
        /// Its name.
        joint_name: String,
    },
}

impl KjointEventKind {
    /// How much an event of this kind matters.
    pub fn severity(&self) -> Severity {
        match self {
            KjointEventKind::SensorActivated { .. }
            | KjointEventKind::FlexJointSwitched { .. }
            | KjointEventKind::JointDetached { .. }
            | KjointEventKind::DisabledByBody { .. }
            | KjointEventKind::DisabledByUser
            | KjointEventKind::EnabledAgain
            | KjointEventKind::JointBroke { .. } => Severity::Info,
            KjointEventKind::StiffnessBeyondSubstep { .. }
            | KjointEventKind::StiffnessLoweredFarFromOrigin { .. }
            | KjointEventKind::NoDynamicBody
            | KjointEventKind::AnchorsApartAtInsertion { .. }
            | KjointEventKind::SensorLockSofterThanSpring { .. }
            | KjointEventKind::SpringCurvePreload { .. } => Severity::Notice,
            KjointEventKind::AnchorsSeparating { .. }
            | KjointEventKind::BlockedRotation { .. }
            | KjointEventKind::StopOverrun { .. }
            | KjointEventKind::SpringRunsAway { .. }
            | KjointEventKind::FlexJointAxisAcross { .. }
            | KjointEventKind::RotationVectorJumped { .. }
            | KjointEventKind::NoLongerHolds { .. }
            | KjointEventKind::MasslessBody { .. }
            | KjointEventKind::SpinCapped { .. }
            | KjointEventKind::SensorJointRemoved { .. } => Severity::Warning,
        }
    }
}

fn unit(dof: Dof, rotation: &'static str, translation: &'static str) -> &'static str {
    if dof.is_rotation() {
        rotation
    } else {
        translation
    }
}

impl fmt::Display for KjointEventKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            KjointEventKind::SensorActivated { cause } => write!(f, "{cause}"),
            KjointEventKind::FlexJointSwitched { cause } => {
                write!(f, "flex joint switched to the dynamic phase ({cause})")
            }
            KjointEventKind::JointDetached { .. } => {
                f.write_str("a body was removed from the world: joint detached")
            }
            KjointEventKind::DisabledByBody { body } => write!(
                f,
                "body {body} was disabled: the joint acts on nothing until it is enabled again"
            ),
            KjointEventKind::MasslessBody { body } => write!(
                f,
                "body {body} is dynamic and has no mass (its colliders removed or without a \
                 density): the joint's automatic stiffness has nothing to scale with, and it \
                 acts on nothing until the body has one; remedies: give the body a collider \
                 with a density, or `set_additional_mass`"
            ),
            KjointEventKind::NoDynamicBody => f.write_str(
                "neither body is dynamic (each fixed or kinematic): the joint acts on nothing \
                 until one is",
            ),
            KjointEventKind::SensorLockSofterThanSpring { dof, lock, spring } => {
                let unit = if dof.is_rotation() { "N·m/rad" } else { "N/m" };
                write!(
                    f,
                    "{}: its sensor lock ({} {unit}, the blocked stiffness{}) is softer than \
                     the DOF's spring ({} {unit}): once the sensor fires, the force the DOF \
                     carries then is held and only the lock resists its motion, which runs \
                     on to about q_s·(1 − K/K_lock); remedies: a larger Kn{}",
                    dof.name(),
                    fig(*lock),
                    if dof.is_rotation() {
                        " KR = Kn·max(ScF, L0²)"
                    } else {
                        " Kn"
                    },
                    fig(*spring),
                    if dof.is_rotation() {
                        " or ScF (in the deck's length unit squared)"
                    } else {
                        ""
                    }
                )
            }
            KjointEventKind::SpringCurvePreload { dof, force } => write!(
                f,
                "{}: its spring curve does not pass through (0, 0): it gives {} {} at {} = 0 \
                 (the pose at insertion, less an initial angle of skew frames), a preload the \
                 joint starts with (it moves its bodies \
                 until something balances it, and its stored energy, the curve's integral \
                 from 0, reads negative where the preload does work); a curve through (0, 0) \
                 leaves the joint unloaded at insertion",
                dof.name(),
                fig(*force),
                if dof.is_rotation() { "N·m" } else { "N" },
                dof.name()
            ),
            KjointEventKind::AnchorsApartAtInsertion { offset, size } => write!(
                f,
                "its anchors were {} m apart on its blocked DOFs when it was inserted ({} % \
                 of its size {} m): it holds its bodies that far apart, a rigid link of that \
                 length (the pose at insertion is its unloaded one); local anchors that meet \
                 join the bodies at one point instead",
                fig(*offset),
                fig(100.0 * offset / size),
                fig(*size)
            ),
            KjointEventKind::FlexJointAxisAcross { axis, angle } => write!(
                f,
                "its axis x (the riser's axis: bending about y and z, torsion about x) is \
                 [{}, {}, {}] in the world, {}° off the line from its anchor to each of its \
                 dynamic bodies' centres of mass: the riser's bending is read as torsion; \
                 give the joint's frame with x along the riser (`frame` in a scene, \
                 `KjointBuilder::world_frame1`; without one, the world axes where the anchors \
                 meet)",
                fig(axis[0]),
                fig(axis[1]),
                fig(axis[2]),
                fig(angle.to_degrees())
            ),
            KjointEventKind::DisabledByUser => f.write_str(
                "switched off by the user: the joint acts on nothing until it is switched on again",
            ),
            KjointEventKind::EnabledAgain => f.write_str("enabled again: the joint acts again"),
            KjointEventKind::JointBroke { cause, .. } => write!(f, "broke: {cause}"),
            KjointEventKind::StiffnessBeyondSubstep {
                dof,
                stiffness_of,
                stiffness,
                omega,
                substep,
                substeps_needed,
            } => {
                write!(
                    f,
                    "{} {} ({}{} {}) oscillates at {} rad/s, beyond the substep (ω·h = {}): \
                     it is held by the implicit update and its oscillation damped; ",
                    dof.name(),
                    stiffness_of,
                    if matches!(stiffness_of, DofStiffness::Together { .. }) {
                        "together "
                    } else {
                        ""
                    },
                    fig(*stiffness),
                    unit(*dof, "N·m/rad", "N/m"),
                    fig(*omega),
                    fig(omega * substep)
                )?;
                // ω·h < 1 at this substep: the stiffness reduced by (ω·h)²
                let resolved = stiffness / (omega * substep).powi(2);
                if *substeps_needed <= crate::scene::MAX_SUBSTEPS as f64 {
                    write!(
                        f,
                        "{substeps_needed:.0} substeps per frame would resolve it"
                    )
                } else {
                    write!(
                        f,
                        "{} substeps per frame would resolve it, beyond the {} a set takes; \
                         a stiffness of {} {} would at this substep",
                        fig(*substeps_needed),
                        fig(crate::scene::MAX_SUBSTEPS as f64),
                        fig(resolved),
                        unit(*dof, "N·m/rad", "N/m"),
                    )
                }
            }
            KjointEventKind::StiffnessLoweredFarFromOrigin {
                distance,
                stiffness,
                origin_stiffness,
                kappa,
                origin_kappa,
                noise,
                rounding,
                sag,
            } => {
                write!(
                    f,
                    "its anchor is {} m from the world origin, where the f32 rounding of the \
                     poses ({} m) over a substep squared is {} m/s², {} times the {} m/s² its \
                     stiffness is sized for: the force it transmits carries that rounding. Its \
                     automatic blocked stiffness {} N/m ({} N·m/rad, κ = {} of {}",
                    fig(*distance),
                    fig(*noise),
                    fig(*rounding),
                    fig(rounding / crate::law::stiffness::LOAD_ACCELERATION),
                    crate::law::stiffness::LOAD_ACCELERATION,
                    fig(stiffness.translational),
                    fig(stiffness.rotational),
                    fig(*kappa),
                    crate::law::stiffness::IMPLICIT_KAPPA,
                )?;
                if *origin_kappa > *kappa {
                    write!(
                        f,
                        ", {} times below the {} N/m it gets near the origin",
                        fig(origin_kappa / kappa),
                        fig(*origin_stiffness)
                    )?;
                }
                write!(
                    f,
                    ") holds it, sagging {} m under its load's weight; remedies: a model \
                     near the origin, the `f64` feature or fewer substeps (a larger Kn does not \
                     take the noise out)",
                    fig(*sag),
                )
            }
            KjointEventKind::AnchorsSeparating { gap, size, remedy } => {
                write!(
                    f,
                    "anchors {} m apart ({:.1} % of the joint's size {} m); ",
                    fig(*gap),
                    100.0 * gap / size,
                    fig(*size)
                )?;
                remedy.fmt_with_unit(f, false)
            }
            KjointEventKind::NoLongerHolds {
                gap,
                size,
                rotation,
                contact,
                force,
                moment,
                stiffness,
                automatic,
            } => {
                use super::health::{LoadExplains, GAP_ERROR, ROTATION_ERROR};
                write!(
                    f,
                    "the joint no longer holds: anchors {} m apart (its size {} m), a blocked \
                     rotation of {} rad, beyond half its size or {} rad, and beyond what its \
                     load explains unless its stiffness is automatic",
                    fig(*gap),
                    fig(*size),
                    fig(*rotation),
                    fig(ROTATION_ERROR)
                )?;
                // what its load explains of each opening beyond its bound, in the error's
                // words (`health::unstable`): the user judges the opening by them (none
                // where the stiffness was not recorded, an event saved before)
                let apart = (*gap > GAP_ERROR * size, *rotation > ROTATION_ERROR);
                let loads: Vec<LoadExplains> = LoadExplains::of_openings(
                    apart,
                    (*gap, *rotation),
                    (*force, *moment),
                    *stiffness,
                )
                .filter(|l| l.stiffness > 0.0 && l.stiffness.is_finite())
                .collect();
                let words: Vec<String> = loads.iter().map(|l| l.words(*automatic)).collect();
                if !words.is_empty() {
                    write!(f, ": {}", words.join(", and "))?;
                }
                f.write_str("; it pulls its bodies back at its blocked stiffness")?;
                match contact {
                    Some(body) => write!(
                        f,
                        "; its body {body} {CONTACT_OPENS}: the run goes on while it comes back \
                         (under `OnUnstable::Stop`, unless the opening grows fourfold or \
                         stays beyond the bounds longer than {} substeps, at least {} s); \
                         remedies: {REMEDY}",
                        super::CONTACT_CREDIT_SUBSTEPS,
                        super::CONTACT_CREDIT_TIME
                    )?,
                    None => write!(f, " (`OnUnstable::Warn`); remedies: {TELEPORT}, {REMEDY}")?,
                }
                // the stiffness the rule chose at this substep, which its load opens: as the
                // error advises
                if *automatic && loads.iter().any(LoadExplains::explains) {
                    f.write_str(super::health::AUTOMATIC_REMEDY)?;
                }
                Ok(())
            }
            KjointEventKind::BlockedRotation { angle, remedy } => {
                write!(f, "a blocked rotation of {} rad; ", fig(*angle))?;
                remedy.fmt_with_unit(f, true)
            }
            KjointEventKind::StopOverrun {
                dof,
                overrun,
                remedy,
            } => {
                write!(
                    f,
                    "{} overruns its stop by {} {}; ",
                    dof.name(),
                    fig(*overrun),
                    dof.unit()
                )?;
                let unit = if dof.is_rotation() { "N·m/rad" } else { "N/m" };
                match remedy {
                    StopRemedy::FrictionSpring { stiffness } => write!(
                        f,
                        "the stop is as stiff as the DOF's friction spring Kf = {} {unit}: \
                         remedies: a larger Kf, a viscosity to settle the rebound",
                        fig(*stiffness)
                    ),
                    StopRemedy::NoiseBounded {
                        stiffness,
                        distance,
                        lowered,
                    } => write!(
                        f,
                        "the stop's stiffness {} {unit} is the automatic one, lowered {}-fold \
                         by the f32 rounding of the poses {} m from the world origin (more \
                         substeps do not stiffen it until the rule's floor κ = 4): remedies: \
                         the `f64` feature, a model nearer the origin, or an explicit Kn",
                        fig(*stiffness),
                        fig(*lowered),
                        fig(*distance)
                    ),
                    StopRemedy::ShorterSubstep { .. } => {
                        write!(f, "remedies: a stiffer stop (Kn), more substeps")
                    }
                }
            }
            KjointEventKind::SpringRunsAway {
                dof,
                value,
                edge,
                stiffness,
            } => {
                let (unit, k_unit) = if dof.is_rotation() {
                    ("rad", "N·m/rad")
                } else {
                    ("m", "N/m")
                };
                write!(
                    f,
                    "{} = {} {unit} is beyond its spring curve's end, past {} {unit}, where the \
                     curve's linear extrapolation (tangent stiffness {} {k_unit}) pushes it \
                     further out the further it goes: the joint runs away; remedies: end the \
                     curve with a rising segment over the travel, or a stop",
                    dof.name(),
                    fig(*value),
                    fig(*edge),
                    fig(*stiffness)
                )
            }
            KjointEventKind::RotationVectorJumped { angle, jump } => write!(
                f,
                "the relative rotation completed a full turn about another axis than the one \
                 it had turned about, and the rotation vector that measures rx, ry, rz jumped \
                 by {} rad (to |θ| = {} rad): no measure of the pose alone is continuous \
                 there, and the springs, stops and friction of the rotations act on the jump; \
                 remedies: stops that keep the relative rotation within a turn, or a \
                 revolute or cylindrical joint for a shaft that spins (its turns accumulate)",
                fig(*jump),
                fig(*angle)
            ),
            KjointEventKind::SpinCapped { body, speed, cap } => write!(
                f,
                "body {body} spins at {} rad/s, rapier's cap on a body's rotation (π/4 a \
                 substep: {} rad/s): rapier clips its spin and the energy it carries; \
                 remedies: `allow_fast_rotation(true)` on the body (`RigidBodyBuilder`, \
                 `RigidBody::set_allow_fast_rotation`), more substeps",
                fig(*speed),
                fig(*cap)
            ),
            KjointEventKind::SensorJointRemoved { joint_name, .. } => write!(
                f,
                "joint `{joint_name}`, whose DOF it watches, was removed: it will not fire on \
                 its condition (the joints it locks stay free); remedies: a condition on a \
                 joint that stays, or trigger it from the application"
            ),
        }
    }
}

/// An event of the joint set, reported once.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub struct KjointEvent {
    /// What it comes from.
    pub source: EventSource,
    /// When it happened \[s\].
    pub time: f64,
    /// What happened.
    pub kind: KjointEventKind,
}

impl KjointEvent {
    /// How much it matters (from its kind).
    pub fn severity(&self) -> Severity {
        self.kind.severity()
    }

    /// The joint an event says was removed from the set (it broke, or a body of it was
    /// removed): its handle, its energies when it was removed and its last readout (`None`
    /// if it never took a substep); `None` for any other event. What observers read of a
    /// joint that is no longer in the set.
    pub fn removed_joint(&self) -> Option<(KjointHandle, &JointEnergy, Option<&JointState>)> {
        let EventSource::Joint { handle, .. } = &self.source else {
            return None;
        };
        match &self.kind {
            KjointEventKind::JointBroke { energy, last, .. }
            | KjointEventKind::JointDetached { energy, last } => {
                Some((*handle, energy, last.as_deref()))
            }
            _ => None,
        }
    }

    /// The sensor of an event from a sensor (its activation, or the warning that its joint
    /// was removed), `None` for an event from a joint.
    pub fn sensor(&self) -> Option<SensorId> {
        match self.source {
            EventSource::Sensor(id) => Some(id),
            EventSource::Joint { .. } => None,
        }
    }
}

impl fmt::Display for KjointEvent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let tag = match self.severity() {
            Severity::Info => "",
            Severity::Notice => "notice: ",
            Severity::Warning => "warning: ",
        };
        write!(
            f,
            "{tag}{} at t = {:.6} s: {}",
            self.source, self.time, self.kind
        )
    }
}
