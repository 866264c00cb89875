//! The set of KJOINT2 joints of a world, and the substep loop that drives them: the blocked
//! stiffness resolved from the substep (docs/kjoint2.md §5), sensors (§4.5), the implicit
//! update of the assembled forces (§4.7; README "How the penalty update stays stable").

use super::event::{EventSource, KjointEvent, KjointEventKind, SensorCause};
use super::health::OnUnstable;
use super::joint::{Kjoint, KjointDescription, Off};
use super::sensor::{Sensor, SensorCondition, SensorId};
use super::substep::{Readouts, SubstepData};
use crate::error::SimError;
use crate::law;
use crate::law::{Dof, JointEnergy, KjointMotor};
use crate::rapier::data::arena::{Arena, Index};
use crate::rapier::dynamics::{
    MassProperties, RigidBody, RigidBodyHandle, RigidBodySet, RigidBodyType,
};
use crate::rapier::math::{Pose, Real};
use crate::rapier::pipeline::PhysicsWorld;
use crate::rapier::pipeline::{EventHandler, PhysicsHooks};
use std::collections::{BTreeMap, HashMap};

mod contact_filters;
pub(crate) use contact_filters::contact_filter_joint;
pub use contact_filters::{is_contact_filter, CONTACT_FILTER_USER_DATA};
mod radioss_start;
mod stiffness_rules;

/// How many of the joints inserted last an inserted joint's property is compared with, to
/// share one copy with an equal one ([`KjointSet::insert`]): joints inserted in runs of one
/// property, or alternating among a few, share them, at most eight comparisons an insertion.
const PROPERTY_LOOKBACK: usize = 8;

/// Handle of a joint in a [`KjointSet`], like rapier's `ImpulseJointHandle`: a generational
/// index, so that the handle of a removed joint never finds another joint (not even one
/// inserted later in its place).
///
/// ```
/// use rapier_kjoint::KjointHandle;
/// let h = KjointHandle::from_raw_parts(3, 1);
/// assert_eq!(h.into_raw_parts(), (3, 1));
/// assert_ne!(h, KjointHandle::invalid());
/// ```
///
/// A handle is an index and a generation in its set's arena, as rapier's handles are: a
/// removed joint's handle finds nothing (its generation is gone), but a handle of another
/// set may find a joint of this one, which the set cannot tell from its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(transparent)]
pub struct KjointHandle(pub Index);

impl KjointHandle {
    /// Converts this handle into its (index, generation) components.
    pub fn into_raw_parts(self) -> (u32, u32) {
        self.0.into_raw_parts()
    }

    /// Reconstructs a handle from its (index, generation) components.
    pub fn from_raw_parts(index: u32, generation: u32) -> Self {
        KjointHandle(Index::from_raw_parts(index, generation))
    }

    /// An always-invalid joint handle.
    pub fn invalid() -> Self {
        Self::from_raw_parts(u32::MAX, u32::MAX)
    }
}

impl Default for KjointHandle {
    /// [`KjointHandle::invalid`].
    fn default() -> Self {
        Self::invalid()
    }
}

impl serde::Serialize for KjointHandle {
    /// As its raw parts `[index, generation]`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.into_raw_parts().serialize(s)
    }
}

#[cfg(feature = "serde-serialize")]
impl<'de> serde::Deserialize<'de> for KjointHandle {
    /// From its raw parts `[index, generation]`, as serialized.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (index, generation) = <(u32, u32)>::deserialize(d)?;
        Ok(Self::from_raw_parts(index, generation))
    }
}

/// Where a [`KjointSet::step_with`] callback is called within a substep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub enum SubstepPhase {
    /// Before the joints are evaluated, at the substep's start time.
    Before,
    /// After rapier advanced the substep; the set's time is the substep's end.
    After,
}

/// How a frame is split into substeps.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct SubstepSettings {
    /// Number of substeps per frame; the joints are evaluated at each one (default 4;
    /// 1 ..= [`crate::scene::MAX_SUBSTEPS`] (100 000), as in scenes: the step refuses others).
    pub substeps: usize,
    /// rapier's own substeps inside each substep (`num_solver_iterations`), for contacts and
    /// rapier's own joints (default 1: the substeps already play that role). Keep it at 1
    /// with stiff joints: more of them change how rapier advances the positions within the
    /// substep, where the implicit update predicts `x + h·v`, and the joints read the
    /// difference as a deflection of the order of their sag under load (the URDF arm's
    /// energy balance went from 0.001 % to 6 % at 4). For contacts and rapier joints that
    /// need more iterations, raise `IntegrationParameters::num_internal_pgs_iterations`
    /// (and set `friction_in_bias_pass` for a frictional grip), which the set leaves alone.
    /// 1 ..= [`MAX_RAPIER_ITERATIONS`] (1000): the step refuses others.
    pub rapier_iterations: usize,
    /// Radioss-compatible start (default off): the first substep of the simulation gives
    /// the bodies half its velocity change (joint impulses, gravity, loads), as the central
    /// difference scheme of Radioss starts with `v(h/2) = v(0) + ½·a(0)·h`; from then on
    /// rapier's semi-implicit Euler is that scheme, the velocities being those of the half
    /// steps. Off, rapier gives the full first kick `v(0) + a(0)·h`: a load applied at
    /// `t = 0` acts as if it started half a substep earlier, which shifts time histories by
    /// `h/2` (6 % on the displacement of the OpenRadioss KJOINT2 QA model at its own
    /// `dt = 1.475e-3`, 14 steps in; within 1 % with this start). Applied by
    /// [`KjointSet::radioss_start_kick`].
    pub radioss_start: bool,
    /// What a step does when a joint no longer holds ([`OnUnstable`]): stop the run with
    /// [`SimError::Unstable`] (default, as a crash code does), or warn and go on with the
    /// joint pulling its bodies back (a game's teleported body).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub on_unstable: OnUnstable,
}

impl Default for SubstepSettings {
    fn default() -> Self {
        SubstepSettings {
            substeps: 4,
            rapier_iterations: 1,
            radioss_start: false,
            on_unstable: OnUnstable::Stop,
        }
    }
}

/// All KJOINT2 joints of a world, their sensors, and the substep loop.
///
/// A 1 kg ball hanging from the ground on a prismatic joint whose free axis is vertical,
/// with a 1000 N/m spring and a 30 N·s/m damper (docs/kjoint2.md §4.1, §4.6): after two
/// seconds it rests `m·g/K` = 9.81 mm below its anchor, and the spring carries its weight
/// (internal-force sign: the joint is compressed, `δx < 0`, `F = K·δx < 0`).
///
/// ```
/// use rapier_kjoint::rapier::prelude::*;
/// use rapier_kjoint::{Dof, DofLaw, JointType, KjointBuilder, KjointProperty, KjointSet};
/// let mut world = PhysicsWorld::default();
/// world.gravity = Vector::new(0.0, -9.81, 0.0);
/// let ground = world.insert_body(RigidBodyBuilder::fixed());
/// let (ball, _) = world.insert(
///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, -1.0, 0.0)),
///     ColliderBuilder::ball(0.1).mass(1.0),
/// );
/// let prop = KjointProperty::new(JointType::Translational)
///     .with_dof(Dof::Dx, DofLaw::spring(1000.0).with_viscosity(30.0));
/// let mut joints = KjointSet::new(); // 4 substeps per frame
/// let h = joints
///     .insert(
///         KjointBuilder::new(prop)
///             .world_frame1(Rotation::from_rotation_arc(Vector::X, Vector::Y)) // joint x = world y
///             .local_anchor2(Vector::new(0.0, 1.0, 0.0)),               // at the ground's origin
///         ground,
///         ball,
///         &world.bodies,
///     )
///     .unwrap();
/// for _ in 0..120 {
///     joints.step(&mut world, 1.0 / 60.0).unwrap(); // replaces world.step()
/// }
/// let state = joints.get(h).unwrap().state().unwrap();
/// assert!((state.q[0] + 9.81e-3).abs() < 1e-4, "δx = {}", state.q[0]);
/// assert!((state.force[0] + 9.81).abs() < 0.1, "F = {}", state.force[0]);
/// assert!((state.parts[0].elastic - 1000.0 * state.q[0]).abs() < 1e-9); // the spring's part
/// ```
///
/// # Disabled bodies
///
/// A joint one of whose bodies is disabled (`RigidBody::set_enabled(false)`) acts on
/// nothing until that body is enabled again, as rapier (0.36) does with its impulse joints
/// (`JointEnabled::DisabledByAttachedBody`): the other body moves as if the joint were not
/// there (a bob whose pivot is disabled falls at g; rapier no longer simulates the disabled
/// body, which stays where it was), and the joint is left out of the solve, the islands and
/// sleeping. The set finds it at the next substep and gives a
/// [`KjointEventKind::DisabledByBody`] event; the joint's readout then reports no force
/// (its forces, parts and rates 0) and [`Kjoint::is_enabled`] is `false`. Its law is not
/// evaluated meanwhile: its state (displacements, friction, stops, the measured angles'
/// turn count) and energies keep their values at disabling, and the joint takes up from
/// there when the body is enabled again ([`KjointEventKind::EnabledAgain`]): a bob put
/// back where and as it was swings on with the same bits as one never disabled, while a
/// body enabled elsewhere is pulled back by the joint's stiffness within a few substeps,
/// far harder than rapier's joints pull (their correction is capped; a 1 kg ball 0.31 m
/// off was thrown at 7.6 m/s, where rapier's ball joint gave it 0.63 m/s): put it back
/// where the joint holds it first.
/// [`Self::iter`] lists the disabled joints after the others (each group in insertion
/// order); a joint inserted on a disabled body starts disabled. A joint neither of whose
/// bodies is dynamic any more (both made fixed or kinematic after its insertion: a vehicle
/// frozen for a cutscene) acts on nothing the same way, with a
/// [`KjointEventKind::NoDynamicBody`] notice, until one is dynamic again; its blocked
/// stiffness is then resolved for the bodies as they are. So does a joint of automatic
/// stiffness one of whose dynamic bodies has no mass (its only collider removed), with a
/// [`KjointEventKind::MasslessBody`] warning, until it has one again; a joint of the user's
/// `Kn` takes such a body as infinitely heavy, as rapier's joints do.
///
/// The user switches a joint off and on again the same way with [`Self::set_enabled`]
/// (rapier's `GenericJoint::set_enabled`, `JointEnabled::Disabled`), or inserts it off
/// with [`crate::KjointBuilder::enabled`]: [`KjointEventKind::DisabledByUser`], then
/// [`KjointEventKind::EnabledAgain`].
///
/// # Snapshots
///
/// A clone is a snapshot of the joints: with rapier's world saved alongside
/// ([`crate::Snapshot`] does both), the restored world and set step on with the same bits
/// as the originals would have. The joints' law states (friction, stops, sensor locks,
/// motors), the sensors, the energies and what a substep carries to the next (the contact
/// prediction, the energy book's pending correction, the islands' rest) are all cloned;
/// the solver's workspace is built again from the topology. With the cargo feature
/// `serde-serialize` the set is `Serialize` and `Deserialize` (its solver's workspace not
/// saved, built again when it is read back), to save a simulation to a file with rapier's
/// `PhysicsWorld`. (`tests/snapshot.rs`.)
#[derive(Debug, Clone, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct KjointSet {
    /// The joints, contiguous in insertion order: the position of a joint is its slot in
    /// the substep stages' per-joint arrays ([`SubstepData`]).
    pub(super) joints: Vec<Kjoint>,
    /// Handle → position in [`Self::joints`] (a generational arena: a removed joint's handle
    /// finds nothing).
    slots: Arena<u32>,
    /// Joints inserted so far (for the default names `joint<N>`).
    inserted: usize,
    /// The energies of the joints removed so far (their last state).
    removed_energy: JointEnergy,
    pub(super) sensors: BTreeMap<SensorId, Sensor>,
    pub(super) events: Vec<KjointEvent>,
    pub(super) settings: SubstepSettings,
    pub(super) time: f64,
    pub(super) auto_dt: Option<f64>,
    /// The substep length \[s\] the blocked stiffnesses were all resolved at (the first
    /// resolution, 0 before it, and each since for a change of length): a substep longer or
    /// shorter by more than `substep::RESOLVE_TOLERANCE` resolves them all again
    /// ([`Self::resolve_stiffness`]; the automatic rules scale as `1/h²`).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(super) resolved_h: f64,
    /// The length of the last substep stepped \[s\] (0 before the first): the contact
    /// prediction measured over it is rescaled to a substep of another length
    /// ([`super::substep::ContactPrediction`]).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(super) last_h: f64,
    /// `h / last_h` for the substep under way, 1 where the length did not change: the
    /// gather stage's factor on the predicted contact change.
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(super) contact_rescale: f64,
    /// The local mass properties of the jointed bodies when the blocked stiffness was last
    /// resolved ([`Self::check_masses`]). Saved as a list of pairs: a handle is no map key
    /// for JSON (`serde_json` refused the whole set: "key must be a string").
    #[cfg_attr(feature = "serde-serialize", serde(with = "pairs"))]
    pub(super) resolved_masses: HashMap<RigidBodyHandle, MassProperties>,
    /// The bodies of the joints removed since the last substep: the joints on those of them
    /// that are dynamic have their stiffness resolved again ([`Self::resolve_stiffness`]).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(super) removed_bodies: Vec<RigidBodyHandle>,
    /// The bodies of the joints reset since the last analysis ([`Self::reset_state`]):
    /// the analysis leaves them without the contact prediction they had.
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(super) forget_prediction: Vec<RigidBodyHandle>,
    /// A body's mass properties were derived again by the gather stage (after an analysis,
    /// or they changed): stage 3 compares them with [`Self::resolved_masses`].
    pub(super) mass_check: bool,
    /// The rapier joints that leave bodies' contacts out (`contact_filters`), as the set
    /// keeps them in the world.
    pub(super) contact_filters: contact_filters::ContactFilters,
    started: bool,
    /// Work done on the joints by the bodies that are not dynamic, since the start \[J\].
    pub(super) driven_work: f64,
    /// Jointed bodies whose gyroscopic term this set integrates (rapier's is switched off).
    #[cfg_attr(feature = "serde-serialize", serde(with = "sorted_handles"))]
    pub(super) gyroscopic: std::collections::HashSet<RigidBodyHandle>,
    /// The bodies found at rapier's spin cap in the last check (scratch of
    /// [`Self::check_bodies_and_spins`]), with their angular speed \[rad/s\].
    spin_capped: Vec<(RigidBodyHandle, f64)>,
    /// The bodies already warned of as at rapier's spin cap (once each).
    spin_warned: Vec<RigidBodyHandle>,
    /// Whether the world has rapier joints (impulse or multibody), which can change the
    /// jointed bodies' velocities in rapier's step (`substep::ContactPrediction`); set by
    /// each step, `true` for [`Self::apply_substep`], which does not see the world.
    pub(super) rapier_constraints: bool,
    /// Stage 3 found a joint of automatic stiffness acting on a body that has lost its
    /// mass: the next substep analyses the set again, which turns it off
    /// ([`KjointEventKind::MasslessBody`]).
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub(super) massless_found: bool,
    /// The error of the last substep's health check ([`super::health`]: a joint that no
    /// longer holds, [`OnUnstable::Stop`]), returned once that substep is complete: rapier
    /// stepped and the time moved on ([`Self::take_unstable`]).
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub(super) unstable: Option<SimError>,
    /// Topology and the contiguous arrays of the substep stages: of the whole set, or of
    /// its first tile when the set is tiled ([`super::tiles`]; during a substep, of the tile
    /// the stages run on).
    #[cfg_attr(
        feature = "serde-serialize",
        serde(deserialize_with = "super::substep::restored_tile")
    )]
    pub(super) data: SubstepData,
    /// The substep data of tiles 1, 2, … (empty when the set is one tile).
    #[cfg_attr(
        feature = "serde-serialize",
        serde(deserialize_with = "super::substep::restored_tiles")
    )]
    pub(super) tiles: Vec<SubstepData>,
    /// The joints of each tile, contiguous ranges of [`Self::joints`] in order (one range of
    /// every joint when the set is one tile; empty before the first analysis).
    pub(super) tile_joints: Vec<std::ops::Range<usize>>,
    /// The joints of the tile in [`Self::data`].
    pub(super) active: std::ops::Range<usize>,
    /// The per-substep arrays the tiles share (empty when the set is one tile).
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub(super) scratch: super::tiles::Scratch,
    /// How many joints the set had at its last analysis.
    pub(super) analysed: usize,
    /// How many of [`Self::joints`] are enabled at the last analysis: the first ones, the
    /// disabled ones after them ([`Kjoint::is_enabled`]).
    pub(super) enabled: usize,
    /// Bodies to wake at the next analysis: those of a joint inserted, removed or changed
    /// since the last (`super::sleep`).
    pub(super) wake: Vec<RigidBodyHandle>,
    /// The bodies of the asleep islands, whose joints the stages leave out; checked at every
    /// substep (`super::sleep`).
    pub(super) asleep: super::sleep::Asleep,
    /// What the next topology stage checks of [`Self::asleep`].
    pub(super) asleep_check: super::sleep::AsleepCheck,
    /// Joints a tile holds at least (tests only: [`super::tiles::TILE_JOINTS`] otherwise).
    #[cfg(test)]
    pub(crate) tile_joints_min: Option<usize>,
    /// Largest relative difference between the structured solve and the dense reference
    /// (tests only; `None`: not checked).
    #[cfg(test)]
    pub(crate) verify: Option<f64>,
    /// Runs the baseline compilation of the substep even where the processor has AVX2
    /// ([`super::isa`]; tests only: the two must give the same bits).
    #[cfg(test)]
    pub(crate) baseline_only: bool,
}

impl KjointSet {
    /// An empty set with default settings.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty set with the given substep settings.
    pub fn with_settings(settings: SubstepSettings) -> Self {
        KjointSet {
            settings,
            ..Default::default()
        }
    }

    /// The substep settings.
    pub fn settings(&self) -> &SubstepSettings {
        &self.settings
    }

    /// Changes the substep settings.
    pub fn set_settings(&mut self, settings: SubstepSettings) {
        self.settings = settings;
    }

    /// Simulation time \[s\].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Work \[J\] that the bodies which are not dynamic did on the bodies through the
    /// joints since the start: `−P·J·v` of every joint's impulse `P` on such a side moving at
    /// `v` (a kinematic body with a prescribed motion; a fixed body does none). It is the
    /// energy a prescribed motion gives a model through its KJOINT2 joints, to be counted
    /// with the work of the loads in an energy balance (the joints' own book,
    /// [`crate::law::JointEnergy`], already holds what they stored or dissipated of it).
    /// Contacts and rapier joints on a moving kinematic body are rapier's and not in it.
    pub fn driven_work(&self) -> f64 {
        self.driven_work
    }

    /// Adds a joint between `body1` and `body2` (use a fixed body for the world): a
    /// [`crate::KjointBuilder`] or the [`KjointDescription`] it builds. The joint's frames are
    /// attached to the bodies at their current poses. A joint without a name is named
    /// `joint<N>`, `N` counting the insertions into this set. Refused: an invalid
    /// description, a body not in `bodies` ([`SimError::MissingBody`]), the same body twice,
    /// a body with a non-finite pose or velocity, two bodies neither of which is dynamic
    /// ([`SimError::InvalidJoint`]).
    pub fn insert(
        &mut self,
        joint: impl Into<KjointDescription>,
        body1: RigidBodyHandle,
        body2: RigidBodyHandle,
        bodies: &RigidBodySet,
    ) -> Result<KjointHandle, SimError> {
        let mut d = joint.into();
        if d.name.is_empty() {
            d.name = format!("joint{}", self.inserted + 1);
        }
        let mut j = Kjoint::build(d, body1, body2, bodies)?;
        // one copy of a property that one of the last joints inserted has too (a chain, a
        // crowd, a deck's property referenced by many elements: `Kjoint::property`); equal
        // values, so the laws give the same results
        let recent = self.joints.iter().rev().take(PROPERTY_LOOKBACK);
        if let Some(same) = recent.map(|k| &k.property).find(|p| ***p == *j.property) {
            j.property = std::sync::Arc::clone(same);
        }
        let dyn1 = bodies.get(body1).is_some_and(|b| b.is_dynamic());
        let dyn2 = bodies.get(body2).is_some_and(|b| b.is_dynamic());
        if !dyn1 && !dyn2 {
            return Err(SimError::InvalidJoint {
                joint: j.name,
                reason: "neither body is dynamic: the joint could not move anything".into(),
            });
        }
        let handle = KjointHandle(self.slots.insert(self.joints.len() as u32));
        j.handle = handle;
        j.order = self.inserted;
        j.rest_since = self.time;
        self.wake.extend([body1, body2]);
        self.contact_filters.joint_inserted(&j);
        self.joints.push(j);
        self.inserted += 1;
        self.auto_dt = None;
        self.data.valid = false;
        Ok(handle)
    }

    /// Removes a joint and returns it, with its last state and energies (`None` when the
    /// handle finds no joint: removed already). Its handle finds nothing
    /// from then on; the other joints keep theirs.
    ///
    /// The energies the joint had stored and dissipated leave the joints' sums with it and
    /// are added to [`Self::removed_energy`], so that an energy balance of the joints stays
    /// closed (the elastic energy it stored is released from the model as the joint is cut:
    /// a balance of the bodies alone sees it as a jump). The automatic blocked stiffness of
    /// the joints that shared a body with it is resolved again at the next substep (their
    /// share of the body's budget grows, docs/kjoint2.md §5), as an insertion does.
    ///
    /// ```
    /// use rapier_kjoint::rapier::prelude::*;
    /// use rapier_kjoint::{JointType, KjointBuilder, KjointProperty, KjointSet};
    /// let mut world = PhysicsWorld::default();
    /// let ground = world.insert_body(RigidBodyBuilder::fixed());
    /// let ball = world.insert_body(RigidBodyBuilder::dynamic().additional_mass(1.0));
    /// let mut joints = KjointSet::new();
    /// let ball_joint = KjointBuilder::new(KjointProperty::new(JointType::Spherical));
    /// let a = joints.insert(ball_joint.clone(), ground, ball, &world.bodies).unwrap();
    /// let b = joints.insert(ball_joint.build(), ground, ball, &world.bodies).unwrap();
    /// let removed = joints.remove(a).unwrap();
    /// assert_eq!(removed.name, "joint1");
    /// assert!(joints.get(a).is_none() && joints.remove(a).is_none());
    /// assert_eq!((joints.len(), joints.get(b).unwrap().name.as_str()), (1, "joint2"));
    /// ```
    pub fn remove(&mut self, h: KjointHandle) -> Option<Kjoint> {
        let j = self.take(h)?;
        self.warn_sensors_of_removed(h, &j.name);
        Some(j)
    }

    /// Removes the joints attached to `body`, each with its
    /// [`KjointEventKind::JointDetached`] event, and returns their handles, as rapier's
    /// `ImpulseJointSet::remove_joints_attached_to_rigid_body` does. Call it where you remove
    /// a body from the world (`PhysicsWorld::remove_body`), for its joints' handles to find
    /// nothing at once: the set sees the body gone only at its next step, which detaches
    /// them the same way, and until then [`Self::get`] still finds them.
    ///
    /// ```
    /// use rapier_kjoint::prelude::*;
    /// use rapier_kjoint::rapier::prelude::*;
    /// let mut world = PhysicsWorld::default();
    /// let ground = world.insert_body(RigidBodyBuilder::fixed());
    /// let ball = world.insert_body(RigidBodyBuilder::dynamic().additional_mass(1.0));
    /// let mut joints = KjointSet::new();
    /// let pin = KjointBuilder::new(KjointProperty::new(JointType::Spherical));
    /// let h = joints.insert(pin, ground, ball, &world.bodies).unwrap();
    /// world.remove_body(ball);
    /// assert_eq!(joints.remove_joints_attached_to_rigid_body(ball), vec![h]);
    /// assert!(joints.get(h).is_none());
    /// let events = joints.drain_events();
    /// assert!(matches!(events[0].kind, KjointEventKind::JointDetached { .. }));
    /// joints.step(&mut world, 1.0 / 60.0).unwrap();
    /// ```
    pub fn remove_joints_attached_to_rigid_body(
        &mut self,
        body: RigidBodyHandle,
    ) -> Vec<KjointHandle> {
        let attached: Vec<KjointHandle> = (self.joints.iter())
            .filter(|j| j.body1 == body || j.body2 == body)
            .map(|j| j.handle)
            .collect();
        self.detach(&attached);
        attached
    }

    /// Removes joints `handles`, each with its [`KjointEventKind::JointDetached`] event (a
    /// body of theirs left the world).
    pub(super) fn detach(&mut self, handles: &[KjointHandle]) {
        for &h in handles {
            self.remove_with_event(h, |energy, last| KjointEventKind::JointDetached {
                energy,
                last,
            });
        }
    }

    /// [`Self::remove`] without the sensors' warnings (the caller gives them, after the
    /// event of the removal).
    pub(super) fn take(&mut self, h: KjointHandle) -> Option<Kjoint> {
        // the last substep's results into the records while they are in step with the data
        self.fold_stored_results();
        let slot = self.slot(h)?;
        self.fold_rest();
        self.slots.remove(h.0);
        let j = self.joints.remove(slot);
        self.wake.extend([j.body1, j.body2]);
        for k in &self.joints[slot..] {
            self.slots[k.handle.0] -= 1;
        }
        self.contact_filters.joint_removed(&j);
        self.book_removed_energy(&j.law.energy);
        // the joints on its dynamic bodies are resolved again at the next substep (stage 3,
        // which reads the bodies: a fixed ground shared by every robot of a world is no
        // link between their islands)
        self.removed_bodies.extend([j.body1, j.body2]);
        self.auto_dt = None;
        self.data.valid = false;
        Some(j)
    }

    /// Adds a joint's energies to [`Self::removed_energy`] (the joint removed, or its state
    /// reset).
    fn book_removed_energy(&mut self, r: &JointEnergy) {
        let e = &mut self.removed_energy;
        e.elastic += r.elastic;
        e.kinetic += r.kinetic;
        e.damping += r.damping;
        e.friction += r.friction;
        e.stop += r.stop;
        e.internal += r.internal;
        e.numerical += r.numerical;
        e.motor += r.motor;
    }

    /// Puts a joint back in the state it had when it was inserted, its definition kept: its
    /// property, frames and the pose its DOFs are measured from, its motors, name, handle
    /// and switches. What it had gathered since goes: its law's state (friction springs,
    /// plastic and hysteretic state, a flex joint's switch to dynamic, a sensor lock), the
    /// stop prediction, the motors' last forces, its readout and warnings, and the contact
    /// prediction of its bodies; its energies go to [`Self::removed_energy`], as those of
    /// a removed joint do (the elastic energy it stored is released from the model). Its
    /// island's automatic stiffness is resolved again at the next substep, at the bodies'
    /// poses then. Returns `false` (and changes nothing) where the handle finds no joint.
    ///
    /// For an episode reset that keeps the bodies: move them back to their first poses
    /// and velocities, then reset each of their joints; the episode then runs as the first
    /// did (without rapier's contacts, to the bit: `tests/independent_islands.rs`). Without
    /// it a robot moved back carried its friction springs, stop and contact predictions
    /// into the new episode (an A1 quadruped's calf 0.021 rad off its first episode in the
    /// first frame; a user trial, 2026-12-04). Removing the joints and inserting them again
    /// does the same, with new handles and from the poses of the new insertion. Not reset:
    /// the set's sensors (a joint whose sensor is active locks again at its next substep,
    /// at its pose then), the set's time (a flex joint's `switch_time` already past
    /// switches it to dynamic at once), and rapier's own state (its contacts' warm start).
    pub fn reset_state(&mut self, h: KjointHandle) -> bool {
        // the last substep's results into the records while they are in step with the data
        self.fold_stored_results();
        let Some(slot) = self.slot(h) else {
            return false;
        };
        self.fold_rest();
        let energy = self.joints[slot].law.energy;
        self.book_removed_energy(&energy);
        let time = self.time;
        let j = &mut self.joints[slot];
        j.reset_state(time);
        self.wake.extend([j.body1, j.body2]);
        self.forget_prediction.extend([j.body1, j.body2]);
        self.auto_dt = None;
        self.data.valid = false;
        true
    }

    /// Part of the analysis (stage 1): which joints are switched off by the user
    /// ([`Self::set_enabled`]), have a disabled body or no dynamic body any more
    /// ([`KjointEventKind::NoDynamicBody`]), and the joints in order, the enabled
    /// ones first ([`Self::enabled`]: only those are stepped), each in its order of
    /// insertion. A joint disabled since the last analysis reports no force from then on
    /// (its readout's forces and rates 0; its law's state and energies are kept, and
    /// [`Kjoint::closed_energy`] is held at its value of now) and gives an event, as one
    /// enabled again does, or one whose cause changed (the user's switch, or its bodies);
    /// the bodies of either are woken with their islands (`super::sleep`).
    pub(super) fn sort_out_disabled(&mut self, bodies: &RigidBodySet) {
        for j in &mut self.joints {
            // (a joint whose body left the world is removed before: none here)
            let Some(off) = Off::of_joint(j, bodies) else {
                continue;
            };
            if Off::same(off, j.disabled) {
                continue;
            }
            if off.is_none() && j.blocked.is_none() {
                // (inert since its insertion: its stiffness was never resolved)
                self.auto_dt = None;
            }
            let was_off = j.disabled.is_some();
            if !was_off {
                // what the joint reports while it is off (before the readout's rates, the
                // share's, are zeroed)
                j.closed_off = Some(Box::new(j.closed_energy(bodies)));
            }
            j.disabled = off;
            if off.is_none() {
                j.closed_off = None;
            }
            let kind = match off {
                Some(cause) => {
                    if !was_off {
                        if let Some(state) = &mut j.state {
                            state.force = Default::default();
                            state.applied = Default::default();
                            state.parts = Default::default();
                            state.rate = Default::default();
                        }
                    }
                    match cause {
                        Off::User => KjointEventKind::DisabledByUser,
                        Off::Body(body) => KjointEventKind::DisabledByBody { body },
                        Off::Inert => KjointEventKind::NoDynamicBody,
                        Off::Massless(body) => KjointEventKind::MasslessBody { body },
                    }
                }
                None => KjointEventKind::EnabledAgain,
            };
            j.rest_since = self.time;
            self.wake.extend([j.body1, j.body2]);
            self.events.push(KjointEvent {
                source: EventSource::Joint {
                    handle: j.handle,
                    name: j.name.clone(),
                },
                time: self.time,
                kind,
            });
        }
        let key = |j: &Kjoint| (j.disabled.is_some(), j.order);
        if !self.joints.is_sorted_by_key(key) {
            self.joints.sort_by_key(key);
            for (slot, j) in self.joints.iter().enumerate() {
                self.slots[j.handle.0] = slot as u32;
            }
        }
        self.enabled = self
            .joints
            .iter()
            .take_while(|j| j.disabled.is_none())
            .count();
    }

    /// Whether the joints disabled at the last analysis still are, for the same cause
    /// (every one has its bodies still in the world, and is switched off by the user, has
    /// a disabled body or has no dynamic body): part of stage 1's check that nothing
    /// changed. (A user's
    /// switch that changes marks the analysis out of date itself: [`Self::set_enabled`].)
    pub(super) fn disabled_unchanged(&self, bodies: &RigidBodySet) -> bool {
        (self.joints.get(self.enabled..).unwrap_or(&[]).iter())
            .all(|j| Off::of_joint(j, bodies).is_some_and(|off| Off::same(off, j.disabled)))
    }

    /// Switches joint `h` off (`enabled = false`) or on again, as rapier's
    /// `GenericJoint::set_enabled` does for an impulse joint (`JointEnabled::Disabled`):
    /// `false` when the handle finds no joint (removed already; nothing
    /// happens), `true` otherwise.
    ///
    /// A joint switched off acts on nothing, as one of a disabled body does (see
    /// [`KjointSet`], "Disabled bodies"): from the next substep it applies no force, is
    /// left out of the solve, the islands and sleeping, its readout reports no force (its
    /// forces, parts and rates 0), and its law is not evaluated: its state and its energies
    /// keep their values (they stay in the joints' sums, so that an energy balance closes
    /// as before). Switched on again, it takes up from there, as a joint whose body is
    /// enabled again. [`Kjoint::is_enabled`] is `false` from the call; the set finds the
    /// change at its next substep and gives a [`KjointEventKind::DisabledByUser`] or
    /// [`KjointEventKind::EnabledAgain`] event, once per change (none when the switch is
    /// turned and turned back before that substep), and wakes the joint's island if it
    /// sleeps. A call that does not change the switch changes nothing (no new analysis of
    /// the set): it may be made at every frame. The user's switch wins over the bodies: a
    /// joint switched on acts only while its bodies are enabled too, and one switched off
    /// stays off when its bodies are enabled.
    ///
    /// ```
    /// use rapier_kjoint::rapier::prelude::*;
    /// use rapier_kjoint::{JointType, KjointBuilder, KjointEventKind, KjointProperty, KjointSet};
    /// let mut world = PhysicsWorld::default();
    /// world.gravity = Vector::new(0.0, -9.81, 0.0);
    /// let ground = world.insert_body(RigidBodyBuilder::fixed());
    /// let bob = world.insert_body(
    ///     RigidBodyBuilder::dynamic()
    ///         .translation(Vector::new(0.0, -1.0, 0.0))
    ///         .additional_mass(1.0),
    /// );
    /// let rod = KjointBuilder::new(KjointProperty::new(JointType::Spherical))
    ///     .local_anchor2(Vector::new(0.0, 1.0, 0.0)); // at the ground's origin
    /// let mut joints = KjointSet::new();
    /// let h = joints.insert(rod, ground, bob, &world.bodies).unwrap();
    /// joints.step(&mut world, 1.0 / 60.0).unwrap();
    /// assert!(joints.set_enabled(h, false)); // switched off: the bob falls
    /// assert!(!joints.get(h).unwrap().is_enabled());
    /// for _ in 0..30 {
    ///     joints.step(&mut world, 1.0 / 60.0).unwrap();
    /// }
    /// assert!(world.bodies[bob].translation().y < -1.2);
    /// assert_eq!(joints.get(h).unwrap().state().unwrap().applied, Default::default());
    /// let events = joints.drain_events();
    /// assert!(matches!(events[..], [ref e] if e.kind == KjointEventKind::DisabledByUser));
    /// joints.set_enabled(h, true); // on again: it pulls the bob back
    /// assert!(joints.get(h).unwrap().is_enabled());
    /// ```
    pub fn set_enabled(&mut self, h: KjointHandle, enabled: bool) -> bool {
        let Some(s) = self.slot(h) else {
            return false;
        };
        let j = &mut self.joints[s];
        if j.switched_off != enabled {
            return true;
        }
        j.switched_off = !enabled;
        self.data.valid = false;
        true
    }

    /// A warning for each sensor not yet activated whose condition watches joint `h`, just
    /// removed: nothing would say otherwise that it can no longer fire.
    pub(super) fn warn_sensors_of_removed(&mut self, h: KjointHandle, name: &str) {
        for (id, s) in &self.sensors {
            if s.activated_at.is_none() && s.condition.joint() == Some(h) {
                self.events.push(KjointEvent {
                    source: EventSource::Sensor(*id),
                    time: self.time,
                    kind: KjointEventKind::SensorJointRemoved {
                        joint: h,
                        joint_name: name.to_owned(),
                    },
                });
            }
        }
    }

    /// The energies of the joints removed so far ([`Self::remove`], and the joints of a
    /// body removed from the world), each as it was when it was removed, and those a joint
    /// held when it was reset ([`Self::reset_state`]): with the joints' own sums, what every
    /// joint ever in the set stored and dissipated.
    pub fn removed_energy(&self) -> JointEnergy {
        self.removed_energy
    }

    /// Position of a joint in [`Self::joints`] (its slot in the substep stages).
    pub(crate) fn slot(&self, h: KjointHandle) -> Option<usize> {
        self.slots.get(h.0).map(|s| *s as usize)
    }

    /// Whether the handle finds a joint of this set.
    pub fn contains(&self, h: KjointHandle) -> bool {
        self.slots.contains(h.0)
    }

    /// The joint of a handle. (A joint whose body was removed from the world is found until
    /// the next step detaches it, or [`Self::remove_joints_attached_to_rigid_body`].)
    pub fn get(&self, h: KjointHandle) -> Option<&Kjoint> {
        self.slot(h).map(|s| &self.joints[s])
    }

    /// The joint of a handle, to change: its name, or its property with
    /// [`Kjoint::set_property`] (the bodies, anchors and frames are fixed at insertion). The
    /// set analyses its joints again at the next substep (as after an insertion: the
    /// topology, the start notices, and the blocked stiffness of a joint whose property
    /// changed) and wakes the joint's island if it sleeps, so call it when something
    /// changes, not at every frame.
    pub fn get_mut(&mut self, h: KjointHandle) -> Option<&mut Kjoint> {
        let s = self.slot(h)?;
        self.auto_dt = None;
        self.data.valid = false;
        let j = &mut self.joints[s];
        j.changes += 1;
        j.rest_since = self.time;
        self.wake.extend([j.body1, j.body2]);
        Some(j)
    }

    /// Sets (`Some`) or removes (`None`) the motor of a joint's free DOF
    /// ([`Kjoint::set_motor`]: the drive force `τ = clamp(k_p·(q* − q) + k_d·(q̇* − q̇),
    /// ±F_max)`), without analysing the set again as [`Self::get_mut`] does: made to move a
    /// target at every frame, as rapier's `set_motor_position` on an impulse joint. Wakes
    /// the joint's island if it sleeps. `Ok(false)` if the handle finds no joint; an error
    /// naming the joint, the DOF and the field for a blocked DOF or an invalid setting.
    ///
    /// A hinge driven by a servo of 200 N·m/rad (damped at 20 N·m·s/rad) to 0.5 rad turns
    /// a free disc there:
    ///
    /// ```
    /// use rapier_kjoint::rapier::prelude::*;
    /// use rapier_kjoint::{Dof, JointType, KjointBuilder, KjointMotor, KjointProperty, KjointSet};
    /// let mut world = PhysicsWorld::default();
    /// let ground = world.insert_body(RigidBodyBuilder::fixed());
    /// let (disc, _) = world.insert(
    ///     RigidBodyBuilder::dynamic(),
    ///     ColliderBuilder::cylinder(0.05, 0.5).mass(2.0),
    /// );
    /// let mut joints = KjointSet::new();
    /// let hinge = KjointBuilder::new(KjointProperty::new(JointType::Revolute))
    ///     .world_axis(Vector::Y); // the disc's axis
    /// let h = joints.insert(hinge, ground, disc, &world.bodies).unwrap();
    /// joints.set_motor(h, Dof::Rx, Some(KjointMotor::position(0.5, 200.0, 20.0))).unwrap();
    /// for _ in 0..120 {
    ///     joints.step(&mut world, 1.0 / 60.0).unwrap();
    /// }
    /// let q = joints.get(h).unwrap().state().unwrap().q[Dof::Rx];
    /// assert!((q - 0.5).abs() < 1e-3, "the disc turned to {q} rad");
    /// ```
    pub fn set_motor(
        &mut self,
        h: KjointHandle,
        dof: Dof,
        motor: Option<KjointMotor>,
    ) -> Result<bool, SimError> {
        let Some(s) = self.slot(h) else {
            return Ok(false);
        };
        let j = &mut self.joints[s];
        if j.motor(dof) == motor.as_ref() {
            return Ok(true);
        }
        j.set_motor(dof, motor)?;
        // an island asleep is taken up by the next analysis only
        if self.asleep.holds(j.body1) || self.asleep.holds(j.body2) {
            self.wake.extend([j.body1, j.body2]);
            self.data.valid = false;
        }
        Ok(true)
    }

    /// The joint named `name`.
    pub fn find(&self, name: &str) -> Option<KjointHandle> {
        self.joints
            .iter()
            .find(|j| j.name == name)
            .map(|j| j.handle)
    }

    /// All joints with their handles, in insertion order (the joints of a disabled body after
    /// the others: "Disabled bodies" above).
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (KjointHandle, &Kjoint)> {
        self.joints.iter().map(|j| (j.handle, j))
    }

    /// All joints with their handles, to change (as [`Self::get_mut`], for all of them: the
    /// set analyses its joints again at the next substep, and wakes every asleep island:
    /// not for every frame).
    pub fn iter_mut(&mut self) -> impl ExactSizeIterator<Item = (KjointHandle, &mut Kjoint)> {
        self.auto_dt = None;
        self.data.valid = false;
        let time = self.time;
        for j in &mut self.joints {
            j.changes += 1;
            j.rest_since = time;
            self.wake.extend([j.body1, j.body2]);
        }
        self.joints.iter_mut().map(|j| (j.handle, j))
    }

    /// The joints attached to `body` (as body 1 or body 2), like rapier's
    /// `ImpulseJointSet::attached_joints`. A linear pass over the joints.
    ///
    /// ```
    /// use rapier_kjoint::rapier::prelude::*;
    /// use rapier_kjoint::{JointType, KjointBuilder, KjointProperty, KjointSet};
    /// let mut world = PhysicsWorld::default();
    /// let ground = world.insert_body(RigidBodyBuilder::fixed());
    /// let a = world.insert_body(RigidBodyBuilder::dynamic().additional_mass(1.0));
    /// let b = world.insert_body(RigidBodyBuilder::dynamic().additional_mass(1.0));
    /// let ball = KjointBuilder::new(KjointProperty::new(JointType::Spherical));
    /// let mut joints = KjointSet::new();
    /// let j0 = joints.insert(ball.clone(), ground, a, &world.bodies).unwrap();
    /// let j1 = joints.insert(ball, a, b, &world.bodies).unwrap();
    /// let at_a: Vec<_> = joints.attached_joints(a).map(|(h, _)| h).collect();
    /// assert_eq!(at_a, [j0, j1]);
    /// assert_eq!(joints.attached_joints(b).count(), 1);
    /// assert_eq!(joints.joints_between(b, a).map(|(h, _)| h).collect::<Vec<_>>(), [j1]);
    /// assert_eq!(joints.joints_between(ground, b).count(), 0);
    /// ```
    pub fn attached_joints(
        &self,
        body: RigidBodyHandle,
    ) -> impl Iterator<Item = (KjointHandle, &Kjoint)> {
        self.iter()
            .filter(move |(_, j)| j.body1 == body || j.body2 == body)
    }

    /// The joints between `body1` and `body2`, in either order.
    pub fn joints_between(
        &self,
        body1: RigidBodyHandle,
        body2: RigidBodyHandle,
    ) -> impl Iterator<Item = (KjointHandle, &Kjoint)> {
        self.iter().filter(move |(_, j)| {
            (j.body1 == body1 && j.body2 == body2) || (j.body1 == body2 && j.body2 == body1)
        })
    }

    /// Number of joints.
    pub fn len(&self) -> usize {
        self.joints.len()
    }

    /// `true` when there is no joint.
    pub fn is_empty(&self) -> bool {
        self.joints.is_empty()
    }

    /// Number of islands (groups of joints linked through dynamic bodies, solved
    /// independently) found at the last topology analysis. A body asleep counts as a fixed
    /// one there: the islands whose bodies all sleep are left out (they count none), but a
    /// short run of asleep joints between awake ones, stepped within their tile
    /// (`dynamics::sleep`), counts one island per joint (8 ragdolls of 3 joints each read 8
    /// awake, up to 16 while some of them slept): it counts what the solver solves, not
    /// mechanisms.
    pub fn island_count(&self) -> usize {
        let tiles = std::iter::once(&self.data).chain(&self.tiles);
        tiles.map(|d| self.solver_of(d).island_count()).sum()
    }

    /// The solver of a tile's data (the first tile's, for a tile that shares it).
    fn solver_of<'a>(&'a self, data: &'a SubstepData) -> &'a super::solve::Solver {
        if data.shares_solver {
            &self.data.solver
        } else {
            &data.solver
        }
    }

    /// Numbers of loop islands factorised by blocks and by faer, over the tiles.
    #[cfg(test)]
    pub(crate) fn solver_factorisations(&self) -> (usize, usize) {
        let tiles = std::iter::once(&self.data).chain(&self.tiles);
        tiles
            .map(|d| self.solver_of(d).loop_factorisations())
            .fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
    }

    /// Joints that close a loop of jointed bodies, found at the last topology analysis: their
    /// islands are solved by a Cholesky factorisation (by 6×6 blocks in faer's fill-reducing
    /// order, or by faer's sparse one where the joints are densely coupled), the others by
    /// the linear-time tree elimination. A loop closed through a fixed or kinematic body is
    /// not one here: such a body is not part of an island (its joints end at the world), so
    /// a slider-crank whose crank and slider are both jointed to the ground has no loop
    /// joint, and its island is solved as a tree.
    pub fn loop_joints(&self) -> Vec<KjointHandle> {
        let tiles = std::iter::once(&self.data).chain(&self.tiles);
        let mut handles = Vec::new();
        for (data, range) in tiles.zip(&self.tile_joints) {
            let joints = self.joints.get(range.clone()).unwrap_or(&[]);
            let closing = self.solver_of(data).loop_joints().iter();
            handles.extend(
                closing
                    .filter_map(|&j| joints.get(j as usize))
                    .map(|j| j.handle),
            );
        }
        handles
    }

    /// Adds (or replaces) a sensor (docs/kjoint2.md §4.5). A threshold that is not finite (or
    /// a force threshold not > 0), or a watched joint whose handle finds none in this set
    /// (removed already), is refused ([`SimError::InvalidArgument`]) and nothing is added. So is
    /// the replacement of a sensor that has fired: a sensor switches on once and stays on, and
    /// the joints it locked stay locked (a replacement reset it to off under locked joints).
    ///
    /// A free body on a `free` joint (type 9, no law: it falls) whose property names sensor 1,
    /// which fires at t = 0.25 s: from then on the lock holds every DOF where it was, and the
    /// body stops falling.
    ///
    /// ```
    /// use rapier_kjoint::rapier::prelude::*;
    /// use rapier_kjoint::{JointType, KjointBuilder, KjointProperty, KjointSet, SensorCondition};
    /// let mut world = PhysicsWorld::default();
    /// world.gravity = Vector::new(0.0, -9.81, 0.0);
    /// let ground = world.insert_body(RigidBodyBuilder::fixed());
    /// let (body, _) = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.1).mass(1.0));
    /// let prop = KjointProperty::new(JointType::Free).with_kn(1e5).with_sensor(1);
    /// let mut joints = KjointSet::new();
    /// let h = joints.insert(KjointBuilder::new(prop), ground, body, &world.bodies).unwrap();
    /// joints.add_sensor(1, SensorCondition::Time(0.25)).unwrap();
    /// for _ in 0..30 {
    ///     joints.step(&mut world, 1.0 / 60.0).unwrap(); // 0.5 s
    /// }
    /// let held = joints.get(h).unwrap().state().unwrap().q[1];
    /// for _ in 0..30 {
    ///     joints.step(&mut world, 1.0 / 60.0).unwrap(); // 1 s
    /// }
    /// let state = joints.get(h).unwrap().state().unwrap();
    /// assert!(joints.sensor_active(1) && state.locked && state.status[1].locked);
    /// // it fell about g·t²/2 = 0.31 m before the lock caught it, and stays there
    /// assert!(held < -0.25, "fell by {held} m");
    /// assert!((state.q[1] - held).abs() < 1e-3 && state.rate[1].abs() < 0.01, "{:?}", state.q);
    /// ```
    pub fn add_sensor(&mut self, id: SensorId, condition: SensorCondition) -> Result<(), SimError> {
        let bad = |field: &str, v: f64, e: &str| SimError::InvalidArgument {
            field: format!("sensor {id}: {field}"),
            value: crate::error::compact_number(v.to_string()),
            expected: e.into(),
        };
        match &condition {
            SensorCondition::Time(t) if !t.is_finite() => {
                return Err(bad("time", *t, "a finite time"))
            }
            SensorCondition::DofPasses { value, .. } if !value.is_finite() => {
                return Err(bad("value", *value, "a finite value"))
            }
            SensorCondition::ForceReaches { value, .. } if !(value.is_finite() && *value > 0.0) => {
                return Err(bad("value", *value, "a finite force > 0"))
            }
            _ => {}
        }
        // a joint removed already would never be measured: the sensor
        // would silently never fire
        if let Some(joint) = condition.joint() {
            if !self.contains(joint) {
                return Err(SimError::InvalidArgument {
                    field: format!("sensor {id}: joint"),
                    value: format!("{:?}", joint.into_raw_parts()),
                    expected: "the handle of a joint of this set".into(),
                });
            }
        }
        if let Some(t) = self.sensors.get(&id).and_then(|s| s.activated_at) {
            return Err(SimError::InvalidArgument {
                field: format!("sensor {id}"),
                value: format!("fired at t = {} s", crate::figure::fmt_num(t)),
                expected: "the id of a sensor that has not fired: a sensor switches on once and \
                           stays on, with the joints it locked (docs/kjoint2.md §4.5)"
                    .into(),
            });
        }
        self.sensors.insert(
            id,
            Sensor {
                condition,
                activated_at: None,
                initial_side: None,
            },
        );
        Ok(())
    }

    /// Activates a sensor now (any condition). Returns `false` when it does not exist.
    pub fn trigger_sensor(&mut self, id: SensorId) -> bool {
        let t = self.time;
        match self.sensors.get_mut(&id) {
            Some(s) => {
                if s.activated_at.is_none() {
                    s.activated_at = Some(t);
                    self.events.push(KjointEvent {
                        source: EventSource::Sensor(id),
                        time: t,
                        kind: KjointEventKind::SensorActivated {
                            cause: SensorCause::Triggered,
                        },
                    });
                }
                true
            }
            None => false,
        }
    }

    /// The sensors, by id.
    pub fn sensors(&self) -> impl Iterator<Item = (SensorId, &Sensor)> {
        self.sensors.iter().map(|(id, s)| (*id, s))
    }

    /// Whether sensor `id` is active.
    pub fn sensor_active(&self, id: SensorId) -> bool {
        self.sensors
            .get(&id)
            .is_some_and(|s| s.activated_at.is_some())
    }

    /// Switches the flex joint of `h` to its dynamic phase now, around the bending state of
    /// its last evaluation; the switch is logged in [`Kjoint::connector_events`]. Returns
    /// `Ok(false)` when it is already dynamic, an error when `h` does not exist or has no
    /// flex joint law.
    pub fn switch_flex_joint(&mut self, h: KjointHandle) -> Result<bool, SimError> {
        let time = self.time;
        let slot = self.slot(h).ok_or(SimError::InvalidArgument {
            field: "joint handle".into(),
            value: format!("{:?}", h.into_raw_parts()),
            expected: "a joint of this set".into(),
        })?;
        let j = &mut self.joints[slot];
        if !matches!(j.connector.law(), law::ConnectorLaw::FlexJoint(_)) {
            return Err(SimError::InvalidJoint {
                joint: j.name.clone(),
                reason: "switch_flex_joint: the joint has no flex joint law".into(),
            });
        }
        let switched = j
            .connector
            .switch_to_dynamic(time, law::FlexJointSwitchCause::ExplicitCall);
        self.collect_connector_events();
        Ok(switched)
    }

    /// Events since the last call, oldest first: sensor activations and connector events
    /// (flex joint phase switches, also kept in [`Kjoint::connector_events`]).
    pub fn drain_events(&mut self) -> Vec<KjointEvent> {
        std::mem::take(&mut self.events)
    }

    /// Moves the connector events not yet reported into the set's event list.
    pub(super) fn collect_connector_events(&mut self) {
        for j in self.joints.iter_mut() {
            collect_connector_events_of(j, &mut self.events);
        }
    }

    /// Advances the world by one frame of `frame_dt` seconds split into
    /// [`SubstepSettings::substeps`] substeps: at each one the joints are evaluated and their
    /// impulses applied, then rapier advances one substep. Every joint's readout
    /// ([`Kjoint::state`]) and energies are those of the last substep when it returns; to
    /// read them after every substep, use [`Self::step_with`]. On an error, the joints'
    /// energies are those of the last substep, and each readout that of the last substep
    /// that wrote it, [`JointState::time`](crate::JointState::time) saying which: the
    /// substeps before the last of a step write only the readouts that their health
    /// checks, a failure criterion or a force sensor read (the joint an error names has
    /// the failing substep's). A `frame_dt` of 0 is rapier's zero-length step (a paused
    /// game's frame): rapier applies the user's changes and updates its contacts, no time
    /// passes and no joint is evaluated (nor, with [`Self::step_with`], a hook called). A
    /// `frame_dt` that is negative or not finite, or whose substep
    /// `frame_dt / substeps` is over [`MAX_SUBSTEP`](crate::MAX_SUBSTEP) (1 s) or is not a
    /// normal number in rapier's `Real`, is refused ([`SimError::InvalidArgument`]) before
    /// anything moves. rapier steps each substep with `integration_parameters.dt` set to
    /// the substep and `num_solver_iterations` to
    /// [`SubstepSettings::rapier_iterations`]; both are given back their values when the
    /// step returns. A joint that no longer holds ([`SubstepSettings::on_unstable`], README
    /// "Health of a run") ends the step with [`SimError::Unstable`] once its substep is
    /// complete: rapier advanced it, the time moved on and the step's end was done there (the
    /// bodies checked, sleep), so that a further step goes on from there.
    ///
    /// Everything short of that is a warning, and the step returns `Ok`: a stop overrun,
    /// anchors parting under a contact, a spring the substep does not resolve come as
    /// events ([`Self::drain_events`]), which a game loop reads or loses. The joints are as
    /// accurate as their substep, and a long frame makes a long one: a car on four
    /// 30 kN/m suspensions stepped in frames of 0.5 s (4 substeps of 0.125 s) overran its
    /// stops by 0.093 m and sat on the ground, each suspension warned, every step `Ok` (a
    /// game developer's trial, 2026-12-06). Clamp `frame_dt` (rapier itself steps a fixed
    /// `dt`, 1/60 s by default), or give a long frame more substeps.
    pub fn step(&mut self, world: &mut PhysicsWorld, frame_dt: f64) -> Result<(), SimError> {
        // no hook reads the joints between substeps: the store stage's results are written
        // into the records by the next substep, and by the end of the step
        self.step_inner(world, frame_dt, false, None, |_, _, _| {
            Ok::<(), SimError>(())
        })
    }

    /// [`Self::step`] with rapier's physics hooks and event handler, as rapier's
    /// `PhysicsWorld::step_with_events`: each of rapier's substeps reports its collision
    /// and contact-force events to `events` and asks `hooks` about contact pairs (a
    /// contact's events once per substep: its force events are those of one substep).
    ///
    /// ```
    /// use rapier_kjoint::prelude::*;
    /// use rapier_kjoint::rapier::prelude::*;
    /// let (collisions, _) = std::sync::mpsc::channel();
    /// let (forces, _) = std::sync::mpsc::channel();
    /// let (tears, _) = std::sync::mpsc::channel();
    /// let events = ChannelEventCollector::new(collisions, forces, tears);
    /// let mut world = PhysicsWorld::default();
    /// let mut joints = KjointSet::new();
    /// joints.step_with_events(&mut world, 1.0 / 60.0, &(), &events).unwrap();
    /// ```
    pub fn step_with_events(
        &mut self,
        world: &mut PhysicsWorld,
        frame_dt: f64,
        hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) -> Result<(), SimError> {
        self.step_inner(world, frame_dt, false, Some((hooks, events)), |_, _, _| {
            Ok::<(), SimError>(())
        })
    }

    /// [`Self::step`] with a callback at every substep: `hook(SubstepPhase::Before, ..)`
    /// before the joints are evaluated (set user forces there: the joints' implicit update
    /// sees them), `hook(SubstepPhase::After, ..)` once rapier has advanced and the time has
    /// moved on (read results, log). In both, every joint's readout is that of the last
    /// substep stepped.
    ///
    /// Kinematic position-based bodies are the hook's to move: where [`Self::step`]
    /// spreads a next pose set for the frame (`set_next_kinematic_position` before the
    /// step) over its substeps, `step_with` leaves them as the hook sets them, one
    /// substep ahead (a controller's target set at `After` for the next substep; spread
    /// over the frame, it would move the body at a quarter of its speed). A next pose set
    /// once for the frame and never by the hook is reached in the first substep, as rapier
    /// reaches it in one step, and the body then rests for the others.
    ///
    /// The hook returns `Result<(), E>` for any error type `E` that a [`SimError`] converts
    /// into (the step's own errors are returned as `E`); with `SimError` itself, the
    /// closure's `Ok` needs its type written out:
    ///
    /// ```
    /// use rapier_kjoint::prelude::*;
    /// use rapier_kjoint::rapier::prelude::*;
    /// let mut world = PhysicsWorld::default();
    /// world.gravity = Vector::new(0.0, -9.81, 0.0);
    /// let base = world.insert_body(RigidBodyBuilder::kinematic_position_based());
    /// let (bob, _) = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, -0.5, 0.0)),
    ///     ColliderBuilder::ball(0.05).mass(1.0),
    /// );
    /// let mut joints = KjointSet::new(); // 4 substeps a frame
    /// let prop = KjointProperty::new(JointType::Fixed);
    /// let builder = KjointBuilder::new(prop).local_anchor2(Vector::new(0.0, 0.5, 0.0));
    /// joints.insert(builder, base, bob, &world.bodies).unwrap();
    /// // the base carried along x at 1 m/s, its next pose set one substep ahead
    /// let h = 1.0 / 240.0;
    /// world.bodies[base].set_next_kinematic_translation(Vector::new(h as Real, 0.0, 0.0));
    /// for _ in 0..60 {
    ///     joints
    ///         .step_with(&mut world, 1.0 / 60.0, |phase, world, joints| {
    ///             if phase == SubstepPhase::After {
    ///                 let x = (joints.time() + h) as Real;
    ///                 world.bodies[base].set_next_kinematic_translation(Vector::new(x, 0.0, 0.0));
    ///             }
    ///             Ok::<(), SimError>(())
    ///         })
    ///         .unwrap();
    /// }
    /// // a second later the bob moves with its base, 1 m along
    /// let v = world.bodies[bob].linvel().x;
    /// assert!((v - 1.0).abs() < 0.01, "{v}");
    /// assert!((world.bodies[bob].translation().x - 1.0).abs() < 1e-3);
    /// ```
    pub fn step_with<E: From<SimError>>(
        &mut self,
        world: &mut PhysicsWorld,
        frame_dt: f64,
        hook: impl FnMut(SubstepPhase, &mut PhysicsWorld, &mut KjointSet) -> Result<(), E>,
    ) -> Result<(), E> {
        self.step_inner(world, frame_dt, true, None, hook)
    }

    /// [`Self::step_with`]; with `fold_each`, every substep's results are in the joints'
    /// records before the hook runs (else only at the end of the step).
    fn step_inner<E: From<SimError>>(
        &mut self,
        world: &mut PhysicsWorld,
        frame_dt: f64,
        fold_each: bool,
        rapier_events: RapierEvents,
        hook: impl FnMut(SubstepPhase, &mut PhysicsWorld, &mut KjointSet) -> Result<(), E>,
    ) -> Result<(), E> {
        self.contact_filters_in_line(&world.bodies, &mut world.impulse_joints);
        // (the set's own rapier joints, which only leave contacts out, change no velocity)
        self.rapier_constraints = world.impulse_joints.len() > self.contact_filters.count
            || world.multibody_joints.multibodies().next().is_some();
        // rapier steps each substep at `dt = h` with `rapier_iterations`; the world's own
        // values are the user's, given back at the end (a plain `world.step()` after a
        // frame advanced 1/240 s with one iteration instead of the 1/60 s set before it)
        let (dt, iterations) = (
            world.integration_parameters.dt,
            world.integration_parameters.num_solver_iterations,
        );
        let result = self.substeps(world, frame_dt, fold_each, rapier_events, hook);
        world.integration_parameters.dt = dt;
        world.integration_parameters.num_solver_iterations = iterations;
        self.fold_stored_results();
        result
    }

    /// The substeps of [`Self::step_inner`].
    fn substeps<E: From<SimError>>(
        &mut self,
        world: &mut PhysicsWorld,
        frame_dt: f64,
        fold_each: bool,
        rapier_events: RapierEvents,
        mut hook: impl FnMut(SubstepPhase, &mut PhysicsWorld, &mut KjointSet) -> Result<(), E>,
    ) -> Result<(), E> {
        if !(frame_dt.is_finite() && frame_dt >= 0.0) {
            return Err(SimError::InvalidArgument {
                field: "frame_dt".into(),
                value: crate::error::compact_number(frame_dt.to_string()),
                expected: "a finite time step ≥ 0".into(),
            }
            .into());
        }
        if self.settings.substeps == 0 || self.settings.rapier_iterations == 0 {
            return Err(SimError::InvalidArgument {
                field: "SubstepSettings::substeps, rapier_iterations".into(),
                value: format!(
                    "{}, {}",
                    self.settings.substeps, self.settings.rapier_iterations
                ),
                expected: "at least 1 each".into(),
            }
            .into());
        }
        // rapier runs `num_solver_iterations` substeps of its own inside each one, with no
        // bound of its own: `usize::MAX` of them and the step never returned
        if self.settings.rapier_iterations > MAX_RAPIER_ITERATIONS {
            return Err(SimError::InvalidArgument {
                field: "SubstepSettings::rapier_iterations".into(),
                value: self.settings.rapier_iterations.to_string(),
                expected: format!("1 ..= {MAX_RAPIER_ITERATIONS} of rapier's substeps a substep"),
            }
            .into());
        }
        // as a scene's `substeps` (`scene::MAX_SUBSTEPS`): `usize::MAX` substeps of a 1/60 s
        // frame passed every check on the substep (9e-22 s is a normal f32) and the step
        // never returned
        if self.settings.substeps > crate::scene::MAX_SUBSTEPS {
            return Err(SimError::InvalidArgument {
                field: "SubstepSettings::substeps".into(),
                value: self.settings.substeps.to_string(),
                expected: format!("1 ..= {} substeps a frame", crate::scene::MAX_SUBSTEPS),
            }
            .into());
        }
        // a frame of 0 s is rapier's zero-length step (a paused game's): the user's changes
        // applied and the contacts updated, no time passing, no joint evaluated, no hook
        // called (it has no substep)
        if frame_dt == 0.0 {
            world.integration_parameters.dt = 0.0;
            step_rapier(world, rapier_events);
            return Ok(());
        }
        if !self.data.valid {
            // once per topology change: every property's sensor exists
            for j in &self.joints {
                j.property
                    .check_sensor_reference(&j.name, |id| self.sensors.contains_key(&id))?;
            }
        }
        let n = self.settings.substeps;
        let h = frame_dt / n as f64;
        if h > MAX_SUBSTEP {
            return Err(SimError::InvalidArgument {
                field: "frame_dt".into(),
                value: crate::error::compact_number(frame_dt.to_string()),
                expected: format!(
                    "a time step whose substep frame_dt / substeps = {h:e} s is at most \
                     {MAX_SUBSTEP} s (`MAX_SUBSTEP`)"
                ),
            }
            .into());
        }
        // rapier steps with `h` at its own precision: below its smallest normal number the
        // substep is rounded to 0 (or loses its digits) and the bodies stop moving; above
        // its largest it is infinite
        if !(h as Real).is_normal() {
            return Err(SimError::InvalidArgument {
                field: "frame_dt".into(),
                value: crate::error::compact_number(frame_dt.to_string()),
                expected: format!(
                    "a time step whose substep frame_dt / substeps = {h:e} s rapier's {} \
                     represents (between {:e} and {:e} s)",
                    std::any::type_name::<Real>(),
                    Real::MIN_POSITIVE,
                    Real::MAX
                ),
            }
            .into());
        }
        world.integration_parameters.dt = h as _;
        world.integration_parameters.num_solver_iterations = self.settings.rapier_iterations;
        if !self.started {
            self.check_bodies_before_start(&world.bodies)?;
            self.prepare(world);
        }
        // (a hook may move kinematic bodies substep by substep: `step_with` leaves them to it)
        let glides = if fold_each {
            Vec::new()
        } else {
            self.kinematic_glides(&world.bodies)
        };
        for k in 0..n {
            glide(&mut world.bodies, &glides, k, n);
            hook(SubstepPhase::Before, world, self)?;
            // (at each substep: a hook may insert bodies and joints)
            if !self.data.valid {
                self.derive_new_masses(world);
            }
            // the asleep bodies rapier woke during the step (the user's changes between steps
            // are checked at its first substep, by the bodies' state)
            // (with a hook, which may have woken a body before this substep, every substep
            // checks them all: rapier's active set has it only after its next step)
            if k > 0 && !fold_each {
                self.woken_in_step(&world.bodies, &world.islands);
            }
            // the user's wakes of awake bodies restart their islands' rest
            if k == 0 || fold_each {
                self.rest_restarted_by_wakes(&world.bodies);
            }
            // a readout nothing reads before the next substep's is left out
            let readouts = if fold_each || k + 1 == n {
                Readouts::All
            } else {
                Readouts::Read
            };
            self.substep(&mut world.bodies, world.gravity, h, readouts)?;
            self.radioss_start_kick(&mut world.bodies, world.gravity, h)?;
            step_rapier(world, rapier_events);
            if fold_each || k + 1 == n {
                self.keep_rest_through_rapier(&mut world.bodies);
            }
            self.time += h;
            self.check_quarantine(world)?;
            // a joint that no longer holds stops the run once its substep is complete, the
            // step's end included (returned before rapier's step, every retry added the
            // impulses again with the time held)
            let unstable = self.unstable.take();
            // the next substep's gather stage checks the bodies as it reads them
            if k + 1 == n || unstable.is_some() {
                self.check_bodies_and_spins(&world.bodies, h)?;
                self.stage_sleep(world);
            }
            if fold_each {
                self.fold_stored_results();
            }
            hook(SubstepPhase::After, world, self)?;
            if let Some(e) = unstable {
                return Err(e.into());
            }
        }
        Ok(())
    }

    /// The health check's error of the last substep ([`Self::unstable`]), if any (for
    /// [`Self::apply_substep`]).
    pub(super) fn take_unstable(&mut self) -> Result<(), SimError> {
        self.unstable.take().map_or(Ok(()), Err)
    }

    /// The kinematic bodies moved by their next position (`KinematicPositionBased`) under a
    /// joint whose next position the user set for the frame: each with its pose and that
    /// target, which [`glide`] spreads over the substeps ([`Self::step`] and
    /// [`Self::step_with_events`]). The watched bodies of the last analysis, or every
    /// joint's bodies where the topology changed since.
    fn kinematic_glides(&self, bodies: &RigidBodySet) -> Vec<(RigidBodyHandle, Pose, Pose)> {
        let moved = |hb: &RigidBodyHandle| {
            let b = bodies.get(*hb)?;
            (b.body_type() == RigidBodyType::KinematicPositionBased
                && b.next_position() != b.position())
            .then(|| (*hb, *b.position(), *b.next_position()))
        };
        // (nothing allocated where no body moved, the usual frame)
        let mut out: Vec<_> = if self.data.valid && self.analysed == self.joints.len() {
            // every watched body, read as it is now (one made kinematic since the analysis
            // is re-analysed in the first substep, after the glides are taken)
            let tiles = std::iter::once(&self.data).chain(&self.tiles);
            tiles.flat_map(|d| &d.watched).filter_map(moved).collect()
        } else {
            let sides = self.joints.iter().flat_map(|j| [j.body1, j.body2]);
            sides.filter_map(|hb| moved(&hb)).collect()
        };
        out.sort_unstable_by_key(|g| g.0.into_raw_parts());
        out.dedup_by_key(|g| g.0);
        out
    }

    /// Lets rapier compute the mass properties of new bodies (it does so during a step) with a
    /// zero-dt step that moves nothing. [`Self::step`] calls it once by itself; call it
    /// before reading masses or energies of a world that has not been stepped yet. The
    /// rapier joints that leave a joint's contacts out are put in the world first
    /// ([`Self::update_contact_filters`]): rapier's step finds its contacts, and an arm
    /// whose box overlaps its base, prepared without them, was held in the base by a
    /// contact of 1956 N from then on (an engine integrator's trial, 2026-12-05).
    pub fn prepare(&mut self, world: &mut PhysicsWorld) {
        self.contact_filters_in_line(&world.bodies, &mut world.impulse_joints);
        let dt = world.integration_parameters.dt;
        world.integration_parameters.dt = 0.0;
        world.step();
        world.integration_parameters.dt = dt;
        self.started = true;
    }

    /// Derives the mass properties of the jointed bodies rapier has not stepped yet (inserted
    /// after the first step: rapier derives them in its step, after the set's first substep
    /// with them has read them), as rapier's step will: their effective inverse mass was
    /// zero, the set's first substep took them for bodies of no weight, and a quadruped
    /// inserted again at 2 s moved 1 cm off its first episode, its joints loaded by 6.6 N in
    /// free fall (a user trial, 2026-12-04). At an analysis of the set's structure only.
    fn derive_new_masses(&self, world: &mut PhysicsWorld) {
        for j in &self.joints {
            for hb in [j.body1, j.body2] {
                let fresh = world.bodies.get(hb).is_some_and(|b| {
                    b.is_dynamic()
                        && b.mass_properties().effective_inv_mass
                            == crate::rapier::math::Vector::ZERO
                });
                if fresh {
                    world.bodies[hb].recompute_mass_properties_from_colliders(&world.colliders);
                }
            }
        }
    }

    /// Adds the substep `h` \[s\] to the simulation time (when driving rapier yourself with
    /// [`Self::apply_substep`]). A substep that is not finite and > 0 is refused
    /// ([`SimError::InvalidArgument`]) and the time left as it was.
    pub fn advance_time(&mut self, h: f64) -> Result<(), SimError> {
        check_substep(h)?;
        self.time += h;
        Ok(())
    }

    /// Checks that every dynamic jointed body is finite after a substep.
    pub fn check_bodies(&self, bodies: &RigidBodySet) -> Result<(), SimError> {
        self.scan_bodies(bodies, |_, _| {})
    }

    /// [`Self::check_bodies`], and in the same pass over the bodies the ones whose spin
    /// rapier clips: a warning ([`KjointEventKind::SpinCapped`]) once per body, naming the
    /// first joint attached to it. rapier clamps the angular speed of a body that does not
    /// allow fast rotation (`RigidBodyBuilder::allow_fast_rotation`) to `π/4` a step, its
    /// step being the substep `h` here: a body at `|ω| ≥ 0.9999·π/(4h)` after it is taken as
    /// clipped (a flywheel at 500 rad/s read 376.99 rad/s after the first substep at 8 a
    /// frame, and the energy balance missed by 43 % with nothing said why). Once a frame:
    /// a clip that lasts less than a frame is not seen.
    fn check_bodies_and_spins(&mut self, bodies: &RigidBodySet, h: f64) -> Result<(), SimError> {
        use super::substep::{contact_change, ContactPrediction};
        let cap = 0.9999 * std::f64::consts::FRAC_PI_4 / h;
        let cap2 = (cap * cap) as Real;
        let mut capped = std::mem::take(&mut self.spin_capped);
        let warned = &self.spin_warned;
        // (the same pass as `scan_bodies`, with each tile's data written: the velocity change
        // of rapier's contacts and joints in the last substep, measured before the user can
        // change the bodies between steps, for the next step's first substep)
        let mut non_finite = None;
        let n_tiles = self.tile_joints.len();
        let tiles = std::iter::once(&mut self.data).chain(&mut self.tiles);
        'tiles: for (tile, data) in tiles.take(n_tiles).enumerate() {
            let measure = data.contact_pred == ContactPrediction::Measure;
            for (slot, hb) in data.handles.iter().enumerate() {
                let Some(b) = bodies.get(*hb) else { continue };
                if !super::substep::pose_is_finite(b) {
                    non_finite = Some((tile, slot as u32));
                    break 'tiles;
                }
                if b.angvel().length_squared() >= cap2
                    && !b.is_fast_rotation_allowed()
                    && !warned.contains(hb)
                {
                    capped.push((*hb, b.angvel().length() as f64));
                }
                if measure {
                    let (v, w) = (b.linvel(), b.angvel());
                    let v = nalgebra::Vector6::new(
                        v.x as f64, v.y as f64, v.z as f64, w.x as f64, w.y as f64, w.z as f64,
                    );
                    let (vp, scale) = (&data.v_pred[slot], &data.pred_scale[slot]);
                    data.dv_contact[slot] = contact_change(&v, vp, scale);
                }
            }
            if measure {
                data.contact_pred = ContactPrediction::Stored;
            }
        }
        if let Some((tile, slot)) = non_finite {
            let data = if tile == 0 {
                &self.data
            } else {
                &self.tiles[tile - 1]
            };
            return Err(self.non_finite_body_of(data, self.tile_joints[tile].start, slot, bodies));
        }
        for (hb, speed) in capped.drain(..) {
            let Some((handle, j)) = self.attached_joints(hb).next() else {
                continue;
            };
            let event = KjointEvent {
                source: EventSource::Joint {
                    handle,
                    name: j.name.clone(),
                },
                time: self.time,
                kind: KjointEventKind::SpinCapped {
                    body: if j.body1 == hb { 1 } else { 2 },
                    speed,
                    cap: std::f64::consts::FRAC_PI_4 / h,
                },
            };
            self.events.push(event);
            self.spin_warned.push(hb);
        }
        self.spin_capped = capped;
        Ok(())
    }

    /// Each dynamic jointed body after a substep, to `each`; the error of the first with a
    /// non-finite pose or velocity.
    fn scan_bodies(
        &self,
        bodies: &RigidBodySet,
        mut each: impl FnMut(RigidBodyHandle, &RigidBody),
    ) -> Result<(), SimError> {
        let tiles = std::iter::once(&self.data).chain(&self.tiles);
        for (data, range) in tiles.zip(&self.tile_joints) {
            for (slot, hb) in data.handles.iter().enumerate() {
                let Some(b) = bodies.get(*hb) else { continue };
                // the gather stage's check of the substeps before (`BodyPose::is_finite`)
                if !super::substep::pose_is_finite(b) {
                    return Err(self.non_finite_body_of(data, range.start, slot as u32, bodies));
                }
                each(*hb, b);
            }
        }
        Ok(())
    }

    /// The error of a solver body (`slot`, of the tile in [`Self::data`]) with a non-finite
    /// pose or velocity, naming the first joint attached to it.
    pub(super) fn non_finite_body(&self, slot: u32, bodies: &RigidBodySet) -> SimError {
        self.non_finite_body_of(&self.data, self.active.start, slot, bodies)
    }

    /// An error when rapier's last step quarantined a jointed body: its pose or velocity
    /// went non-finite inside rapier's step (a speed beyond f32's range, 3.4e38 m/s, put the
    /// body's next pose at infinity), and rapier rolled it back, zeroed its velocity and
    /// disabled it. The set would then hold it as fixed and the run go on with a frozen body
    /// (a stiffness curve falling through zero: the body ran away as `e^(ω·t)` and froze
    /// at 1e37 m, exit 0). The joint named is the first attached to the body. Nothing to do
    /// (one `is_empty`) when rapier quarantined nothing.
    ///
    /// A user driving rapier through [`Self::apply_substep`] checks `world.quarantine()`
    /// after each `world.step()` the same way.
    pub fn check_quarantine(&self, world: &PhysicsWorld) -> Result<(), SimError> {
        let quarantine = world.quarantine();
        if quarantine.is_empty() {
            return Ok(());
        }
        for hb in quarantine.bodies() {
            if let Some((_, j)) = self.attached_joints(*hb).next() {
                return Err(SimError::Unstable {
                    time: self.time,
                    reason: format!(
                        "rapier disabled a body of joint `{}` whose pose or velocity went \
                         non-finite in its step (rolled back, velocity zeroed); a law that \
                         feeds energy (a stiffness or viscosity curve whose slope falls below \
                         zero) or a substep too long for the joint's stiffness runs away so; \
                         remedies: curves whose slope stays positive, more substeps",
                        j.name
                    ),
                });
            }
        }
        Ok(())
    }

    /// The error naming the first body of the gathered tile ([`Self::data`]) whose user force
    /// or torque is not finite, if any: what a solve that failed on a non-finite impulse
    /// looks for first (the user's NaN force was reported as the first joint's
    /// "non-finite joint impulse"; a game developer's trial, 2026-12-06).
    pub(super) fn non_finite_user_force(&self, bodies: &RigidBodySet) -> Option<SimError> {
        let slot = self.data.handles.iter().position(|hb| {
            bodies
                .get(*hb)
                .is_some_and(|b| !(b.user_force().is_finite() && b.user_torque().is_finite()))
        })?;
        Some(self.non_finite_body(slot as u32, bodies))
    }

    /// [`Self::non_finite_body`] of the tile `data` whose joints start at `first`.
    fn non_finite_body_of(
        &self,
        data: &SubstepData,
        first: usize,
        slot: u32,
        bodies: &RigidBodySet,
    ) -> SimError {
        let at = Some(slot);
        let (j, side) = data
            .sides
            .iter()
            .enumerate()
            .find_map(|(k, s)| {
                s.iter()
                    .position(|x| *x == at)
                    .map(|side| (first + k, side))
            })
            .unwrap_or((first, 0));
        let state = data
            .handles
            .get(slot as usize)
            .and_then(|hb| bodies.get(*hb))
            .map_or_else(
                || "has a non-finite pose or velocity".to_string(),
                stiffness_rules::non_finite_state,
            );
        SimError::Unstable {
            time: self.time,
            reason: format!(
                "body {} of joint `{}` {state}",
                side + 1,
                self.joints.get(j).map_or("?", |j| j.name.as_str())
            ),
        }
    }

    /// Whether a sensor not yet activated waits for a joint's force
    /// ([`SensorCondition::ForceReaches`]): it reads the force the joint transmitted over the
    /// previous substep, which [`Self::update_sensors`] then folds first.
    pub(super) fn force_sensors(&self) -> bool {
        self.sensors.values().any(|s| {
            s.activated_at.is_none() && matches!(s.condition, SensorCondition::ForceReaches { .. })
        })
    }

    /// Activates the sensors whose condition holds at the start of the substep, on the
    /// current poses: a DOF sensor fires in the substep whose kinematics first show the DOF
    /// past its value, so the lock it drives engages in that same substep (docs/kjoint2.md §4.5).
    /// A force sensor compares the force its joint transmitted over the previous substep
    /// (`−P/h`, [`crate::JointState::applied`]), whose store stage's result this folds into
    /// the records first ([`Self::fold_stored_results`]; the prepare stage would fold it
    /// after the sensors, so they would read the substep before).
    pub(super) fn update_sensors(&mut self, bodies: &RigidBodySet) {
        if self.force_sensors() {
            self.fold_stored_results();
        }
        let t = self.time;
        for (id, s) in self.sensors.iter_mut() {
            if s.activated_at.is_some() {
                continue;
            }
            let fire: Option<SensorCause> = match &s.condition {
                SensorCondition::Time(t0) => {
                    (t >= *t0 - 1e-12).then_some(SensorCause::TimeReached { time: *t0 })
                }
                SensorCondition::DofPasses { joint, dof, value } => {
                    let slot = self.slots.get(joint.0).map(|s| *s as usize);
                    let q = slot.map(|s| &self.joints[s]).and_then(|j| {
                        let p1 = super::joint::body_pose(bodies, j.body1)?;
                        let p2 = super::joint::body_pose(bodies, j.body2)?;
                        // measured on a copy of the unwrapping state: the joint's own
                        // measurement of this substep comes next
                        let kin =
                            crate::kinematics::measure(&j.frames, &p1, &p2, &mut j.measure.clone());
                        Some(kin.q[dof.index()])
                    });
                    q.and_then(|q| {
                        let side = q >= *value;
                        match s.initial_side {
                            None => {
                                s.initial_side = Some(side);
                                None
                            }
                            Some(s0) => (s0 != side).then(|| SensorCause::DofPassed {
                                joint: *joint,
                                joint_name: self.joints[slot.expect("measured above")].name.clone(),
                                dof: *dof,
                                value: *value,
                                measured: q,
                            }),
                        }
                    })
                }
                SensorCondition::ForceReaches { joint, dof, value } => self
                    .slots
                    .get(joint.0)
                    .map(|s| &self.joints[*s as usize])
                    .and_then(|j| {
                        // the transmitted force, folded above (not the law's `K·q`, which
                        // on a DOF stiffer than the substep resolves is not what it carries)
                        let f = j.last_applied[dof.index()];
                        (f.abs() >= *value).then(|| SensorCause::ForceReached {
                            joint: *joint,
                            joint_name: j.name.clone(),
                            dof: *dof,
                            value: *value,
                            measured: f,
                        })
                    }),
                SensorCondition::Manual => None,
            };
            if let Some(cause) = fire {
                s.activated_at = Some(t);
                self.events.push(KjointEvent {
                    source: EventSource::Sensor(*id),
                    time: t,
                    kind: KjointEventKind::SensorActivated { cause },
                });
            }
        }
    }
}

/// Moves the connector events of joint `j` not yet reported into `events`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn collect_connector_events_of(j: &mut Kjoint, events: &mut Vec<KjointEvent>) {
    let all = j.connector.events();
    // (a connector's events only grow: none, none reported; the count is a cold field of
    // the record, not to be read and written for every joint at every substep)
    if all.is_empty() {
        return;
    }
    for e in &all[j.connector_events_reported.min(all.len())..] {
        let kind = match e.kind {
            law::ConnectorEventKind::FlexJointSwitched { cause } => {
                KjointEventKind::FlexJointSwitched { cause }
            }
        };
        events.push(KjointEvent {
            source: EventSource::Joint {
                handle: j.handle,
                name: j.name.clone(),
            },
            time: e.time,
            kind,
        });
    }
    j.connector_events_reported = all.len();
}

/// One rapier step (one substep of the set). A world without colliders has nothing for
/// rapier's continuous collision detection to hit, yet rapier 0.36 measures every dynamic
/// body's motion for it at each step (`pose_errors`, `is_moving_fast`: 13 % of a 1000-link
/// chain's frame, paid once per substep); it is switched off for that step
/// (`max_ccd_substeps = 0`) and the user's value restored. A world with colliders is stepped
/// as the user set it up: each substep is swept as rapier would sweep a frame.
pub(crate) fn step_rapier(world: &mut PhysicsWorld, events: RapierEvents) {
    let step = |world: &mut PhysicsWorld| match events {
        Some((hooks, events)) => world.step_with_events(hooks, events),
        None => world.step(),
    };
    if world.colliders.is_empty() && world.integration_parameters.max_ccd_substeps != 0 {
        let ccd = world.integration_parameters.max_ccd_substeps;
        world.integration_parameters.max_ccd_substeps = 0;
        step(world);
        world.integration_parameters.max_ccd_substeps = ccd;
    } else {
        step(world);
    }
}

/// rapier's physics hooks and event handler for its steps ([`KjointSet::step_with_events`]),
/// or none.
pub(crate) type RapierEvents<'a> = Option<(&'a dyn PhysicsHooks, &'a dyn EventHandler)>;

/// `Ok` for a substep `h` \[s\] that is finite and > 0, else the error naming `h` (the
/// calls that take a substep: [`KjointSet::apply_substep`], [`KjointSet::advance_time`],
/// [`KjointSet::radioss_start_kick`]).
pub(crate) fn check_substep(h: f64) -> Result<(), SimError> {
    if h.is_finite() && h > 0.0 && h <= MAX_SUBSTEP {
        return Ok(());
    }
    Err(SimError::InvalidArgument {
        field: "h".into(),
        value: crate::error::compact_number(h.to_string()),
        expected: format!("a finite substep > 0 and at most {MAX_SUBSTEP} s"),
    })
}

/// `Ok` for a gravity \[m/s²\] whose components are finite, else the error naming it: a
/// NaN gravity was reported as the first joint's non-finite impulse, naming a joint that
/// was not at fault (the calls that take one: [`KjointSet::step`] and its kin read
/// `PhysicsWorld::gravity`, [`KjointSet::apply_substep`] and
/// [`KjointSet::radioss_start_kick`] take it).
pub(crate) fn check_gravity(gravity: crate::rapier::math::Vector) -> Result<(), SimError> {
    if gravity.is_finite() {
        return Ok(());
    }
    Err(SimError::InvalidArgument {
        field: "gravity".into(),
        value: format!("{gravity:?}"),
        expected: "finite components".into(),
    })
}

/// The longest substep (`frame_dt / substeps`, \[s\]) the set steps, as a scene's
/// (`scene::MAX_SUBSTEP_TIME`). Far beyond what a joint needs: with substeps of thousands
/// of seconds rapier's f32 continuous collision detection no longer ended (a frame of 1e5 s
/// in 4 substeps hung a scene in parry's shape cast), and at 2.5 s the automatic stiffness,
/// sized from the substep, let a pendulum's anchors part by 4.4 m while each step returned
/// `Ok`.
pub const MAX_SUBSTEP: f64 = 1.0;

/// The most of rapier's own substeps a substep the set asks for
/// ([`SubstepSettings::rapier_iterations`], rapier's `num_solver_iterations`), as a scene's
/// `[rapier] pgs_iterations` (`scene::MAX_PGS_ITERATIONS`): rapier bounds neither.
pub const MAX_RAPIER_ITERATIONS: usize = 1000;

/// Moves each kinematic body of `glides` (its pose at the frame's start, its target for the
/// frame: [`KjointSet::kinematic_glides`]) by its next position to `(k + 1)/n` of the way
/// at substep `k` of `n`, its target at the last: rapier steps once a substep, and a
/// target set for the frame was reached in the first, the body at rest in the others (a
/// base shaken at 5 Hz jerked its pendulum's joint 0.86 mm open at every frame's start;
/// rapier's own joints, solved with the body in the same step, followed it). Not with a
/// hook ([`KjointSet::step_with`]), which may set the next pose substep by substep: a pose
/// set in the last substep's `After` for the next one could not be told from a frame's.
fn glide(bodies: &mut RigidBodySet, glides: &[(RigidBodyHandle, Pose, Pose)], k: usize, n: usize) {
    for (hb, start, target) in glides {
        if let Some(b) = bodies.get_mut(*hb) {
            let next = if k + 1 >= n {
                *target
            } else {
                start.lerp(target, (k + 1) as Real / n as Real)
            };
            b.set_next_kinematic_position(next);
        }
    }
}

impl std::ops::Index<KjointHandle> for KjointSet {
    type Output = Kjoint;

    /// The joint of a handle, to read, as `set[handle]` (as rapier's sets are read).
    ///
    /// # Panics
    ///
    /// Panics if the handle finds no joint of this set (removed already): use
    /// [`KjointSet::get`] where it may not. There is no `IndexMut`: a change goes through
    /// [`KjointSet::get_mut`], which tells the set to analyse its joints again.
    fn index(&self, h: KjointHandle) -> &Kjoint {
        self.get(h)
            .unwrap_or_else(|| panic!("no joint of this set has the handle {h:?}"))
    }
}

#[cfg(test)]
mod switch_tests {
    use crate::rapier::prelude::*;
    use crate::{JointType, KjointBuilder, KjointProperty, KjointSet};

    /// A call of [`KjointSet::set_enabled`] that does not change the switch leaves the
    /// set's analysis as it is (a game may call it at every frame); one that changes it
    /// marks it out of date, and the next step analyses it again, the joint switched off
    /// listed after the others.
    #[test]
    fn only_a_change_of_the_switch_analyses_the_set_again() {
        let mut w = PhysicsWorld::default();
        let ground = w.insert_body(RigidBodyBuilder::fixed());
        let mut set = KjointSet::new();
        let mut handles = Vec::new();
        for x in [0.0, 1.0] {
            let bob = w.insert_body(
                RigidBodyBuilder::dynamic()
                    .translation(Vector::new(x, -1.0, 0.0))
                    .additional_mass(1.0),
            );
            let rod = KjointBuilder::new(KjointProperty::new(JointType::Spherical))
                .local_anchor2(Vector::new(0.0, 1.0, 0.0));
            handles.push(set.insert(rod, ground, bob, &w.bodies).unwrap());
        }
        set.step(&mut w, 1.0 / 60.0).unwrap();
        assert!(set.data.valid);
        assert!(set.set_enabled(handles[0], true));
        assert!(set.data.valid, "unchanged: no new analysis");
        assert!(set.set_enabled(handles[0], false));
        assert!(!set.data.valid);
        set.step(&mut w, 1.0 / 60.0).unwrap();
        assert!(set.data.valid && set.enabled == 1);
        let order: Vec<_> = set.iter().map(|(h, _)| h).collect();
        assert_eq!(order, [handles[1], handles[0]]);
        assert!(set.set_enabled(handles[0], false));
        assert!(set.data.valid, "unchanged: no new analysis");
    }
}

/// A map saved as the list of its pairs (`#[serde(with = "pairs")]`): for keys a format
/// cannot take as map keys (JSON takes strings only).
#[cfg(feature = "serde-serialize")]
mod pairs {
    use crate::rapier::dynamics::RigidBodyHandle;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    use std::collections::HashMap;

    /// The pairs in the order of their handles: a map's own order is its hasher's, which
    /// differs from map to map, so that the same set saved twice (once read back) gave
    /// other bytes.
    pub fn serialize<V: Serialize, S: Serializer>(
        map: &HashMap<RigidBodyHandle, V>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        let mut pairs: Vec<_> = map.iter().collect();
        pairs.sort_unstable_by_key(|(h, _)| h.into_raw_parts());
        s.collect_seq(pairs)
    }

    pub fn deserialize<'de, V, D>(d: D) -> Result<HashMap<RigidBodyHandle, V>, D::Error>
    where
        V: Deserialize<'de>,
        D: Deserializer<'de>,
    {
        Ok(Vec::<(RigidBodyHandle, V)>::deserialize(d)?
            .into_iter()
            .collect())
    }
}

/// A set of body handles saved in the order of the handles ([`pairs`]).
#[cfg(feature = "serde-serialize")]
mod sorted_handles {
    use crate::rapier::dynamics::RigidBodyHandle;
    use serde::{Deserialize, Deserializer, Serializer};
    use std::collections::HashSet;

    pub fn serialize<S: Serializer>(
        set: &HashSet<RigidBodyHandle>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        let mut handles: Vec<_> = set.iter().collect();
        handles.sort_unstable_by_key(|h| h.into_raw_parts());
        s.collect_seq(handles)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<HashSet<RigidBodyHandle>, D::Error> {
        Ok(Vec::<RigidBodyHandle>::deserialize(d)?
            .into_iter()
            .collect())
    }
}
