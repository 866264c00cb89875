//! One KJOINT2 joint between two rapier bodies: its builder (the inputs of docs/kjoint2.md
//! §1: property, anchors, Skew1/Skew2 frames; a connector law of docs/planar_friction.md or
//! docs/flex_joint.md), its stored data and the state it reports after every substep
//! (docs/kjoint2.md §6).

use super::convert::{from_quat, from_vec3};
use super::joint_set::KjointHandle;
use crate::error::SimError;
use crate::kinematics::{
    self, BodyPose, JointFrames, MeasureState, RotationMeasure, TranslationMeasure,
};
use crate::law::{
    BlockedStiffness, BreakCriterion, Connector, ConnectorEvent, ConnectorLaw, ConnectorReport,
    Dof, DofStatus, FlexJointConnector, FlexJointLaw, ForceParts, JointEnergy, JointFriction,
    KjointMotor, KjointProperty, LawState, MotorDrive, PerDof, PlanarFriction,
};
use crate::rapier::dynamics::{RigidBodyHandle, RigidBodySet};
use crate::rapier::math::{Real, Rotation, Vector};
use nalgebra::{UnitQuaternion, Vector3};
use serde::Serialize;
use std::sync::Arc;

/// The definition of a KJOINT2 joint, what [`KjointBuilder::build`] gives and
/// [`crate::KjointSet::insert`] takes: the property (docs/kjoint2.md §1), the anchors, the
/// Skew1/Skew2 frames and a connector law. The counterpart of rapier's `GenericJoint`
/// (what `RevoluteJointBuilder::build` gives); the joint stored in the set, with its bodies
/// and state, is a [`Kjoint`]. Nothing is checked until it is inserted.
///
/// ```
/// use rapier_kjoint::{JointType, KjointBuilder, KjointDescription, KjointProperty};
/// let d: KjointDescription = KjointBuilder::new(KjointProperty::new(JointType::Spherical))
///     .name("ball")
///     .build();
/// assert_eq!(d.name, "ball");
/// assert!(d.world_frame1.is_none()); // axes from the geometry
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct KjointDescription {
    /// A name for messages and outputs (empty: `joint<N>` is given at insertion).
    pub name: String,
    /// The KJOINT2 property: joint type, blocked stiffness, laws of the free DOFs.
    pub property: KjointProperty,
    /// Anchor on body 1, in body 1's local coordinates \[m\].
    pub local_anchor1: Vector,
    /// Anchor on body 2, in body 2's local coordinates \[m\].
    pub local_anchor2: Vector,
    /// The joint's initial axes in **world** coordinates (Radioss `Skew_ID1`), `None`: from
    /// the geometry ([`KjointBuilder::world_frame1`]).
    pub world_frame1: Option<Rotation>,
    /// Body 2's initial axes in **world** coordinates (Radioss `Skew_ID2`), `None`: those of
    /// [`Self::world_frame1`] ([`KjointBuilder::world_frame2`]).
    pub world_frame2: Option<Rotation>,
    /// The connector law (planar friction, flex joint) or [`ConnectorLaw::None`].
    pub connector: ConnectorLaw,
    /// When the joint breaks (docs/breakable.md), `None`: never
    /// ([`KjointBuilder::break_when`]).
    pub break_criterion: Option<BreakCriterion>,
    /// The user's switch at insertion: `false` inserts the joint switched off
    /// ([`KjointBuilder::enabled`], [`crate::KjointSet::set_enabled`]); `true` by default.
    pub enabled: bool,
    /// The free DOF whose friction spring `Kf` a robot loader chose by the implicit rule of
    /// the substep (`Kf = κ_eff·m_eff/h²`, [`crate::io::urdf::friction_stiffness`]): like a
    /// blocked DOF's automatic `Kn`, unresolved by the substep by design, so the start
    /// notices do not name it ([`crate::KjointEventKind::StiffnessBeyondSubstep`]).
    pub(crate) friction_by_rule: Option<Dof>,
    /// The axis given to [`KjointBuilder::world_axis`] where it is zero or not finite
    /// (refused at insertion, naming it as given; [`Self::world_frame1`] is then NaN).
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub(crate) refused_axis: Option<Vector>,
    /// The motors of the free DOFs ([`KjointBuilder::motor`]; none by default).
    pub motors: PerDof<Option<KjointMotor>>,
    /// Whether rapier's contacts act between the colliders of the joint's two bodies
    /// (`true`, the default, as rapier's `GenericJoint::contacts_enabled`;
    /// [`KjointBuilder::contacts_enabled`]).
    pub contacts_enabled: bool,
}

impl KjointDescription {
    /// A joint with the given property, anchors at both bodies' origins, axes from the
    /// geometry (x from anchor 1 to anchor 2, or the world axes when the anchors coincide).
    pub fn new(property: KjointProperty) -> Self {
        KjointDescription {
            name: String::new(),
            property,
            local_anchor1: Vector::ZERO,
            local_anchor2: Vector::ZERO,
            world_frame1: None,
            world_frame2: None,
            connector: ConnectorLaw::None,
            break_criterion: None,
            enabled: true,
            friction_by_rule: None,
            refused_axis: None,
            motors: PerDof::default(),
            contacts_enabled: true,
        }
    }
}

impl From<KjointBuilder> for KjointDescription {
    fn from(b: KjointBuilder) -> Self {
        b.build()
    }
}

/// Builder of a KJOINT2 joint, in the style of rapier's joint builders: the property
/// (docs/kjoint2.md §1), the anchors, the Skew1/Skew2 frames and a connector law.
/// [`Self::build`] gives the [`KjointDescription`]; [`crate::KjointSet::insert`] takes either.
///
/// The anchors are given in each body's **local** coordinates, the frames in **world**
/// coordinates at insertion (as Radioss' skews are): the method names say which.
///
/// A 1 m rod hinged at the world origin about the world z axis, released horizontally: after
/// half a second of swinging the two anchors are still together (the blocked translations
/// hold) and the hinge has turned.
///
/// ```
/// use rapier_kjoint::rapier::prelude::*;
/// use rapier_kjoint::{JointType, KjointBuilder, KjointProperty, KjointSet};
/// let mut world = PhysicsWorld::default();
/// world.gravity = Vector::new(0.0, -9.81, 0.0);
/// let ground = world.insert_body(RigidBodyBuilder::fixed());
/// let (rod, _) = world.insert(
///     RigidBodyBuilder::dynamic().translation(Vector::new(0.5, 0.0, 0.0)),
///     ColliderBuilder::cuboid(0.5, 0.02, 0.02).mass(1.0),
/// );
/// let hinge = KjointBuilder::new(KjointProperty::new(JointType::Revolute)) // Kn = 0: automatic
///     .name("hinge")
///     .world_frame1(Rotation::from_rotation_arc(Vector::X, Vector::Z)) // joint x axis = world z
///     .local_anchor2(Vector::new(-0.5, 0.0, 0.0));                    // the rod's end
/// let mut joints = KjointSet::new();
/// joints.insert(hinge, ground, rod, &world.bodies).unwrap();
/// for _ in 0..30 {
///     joints.step(&mut world, 1.0 / 60.0).unwrap();
/// }
/// let h = joints.find("hinge").unwrap();
/// let state = joints.get(h).unwrap().state().unwrap();
/// let gap: f64 = (0..3).map(|i| (state.anchor2[i] - state.anchor1[i]).powi(2)).sum::<f64>().sqrt();
/// assert!(gap < 1e-3, "anchors {gap} m apart");
/// assert!(state.q[3].abs() > 0.5, "the hinge turned by {} rad", state.q[3]); // θx, the free rotation
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
#[must_use = "a builder does nothing until it is built or inserted"]
pub struct KjointBuilder(pub KjointDescription);

impl KjointBuilder {
    /// A joint with the given property, anchors at both bodies' origins, axes from the
    /// geometry (x from anchor 1 to anchor 2, or the world axes when the anchors coincide).
    pub fn new(property: KjointProperty) -> Self {
        KjointBuilder(KjointDescription::new(property))
    }
    /// The joint's definition.
    pub fn build(self) -> KjointDescription {
        self.0
    }
    /// A name for messages and outputs.
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.0.name = name.into();
        self
    }
    /// Anchor on body 1, in body 1's local coordinates \[m\].
    pub fn local_anchor1(mut self, p: Vector) -> Self {
        self.0.local_anchor1 = p;
        self
    }
    /// Anchor on body 2, in body 2's local coordinates \[m\].
    pub fn local_anchor2(mut self, p: Vector) -> Self {
        self.0.local_anchor2 = p;
        self
    }
    /// The joint's initial axes in **world** coordinates (Radioss `Skew_ID1`): the columns
    /// of this rotation are the joint's x, y, z axes at creation (attached to body 1 from
    /// then on). Without it, x goes from anchor 1 to anchor 2 (the world axes when the
    /// anchors coincide, or when [`Self::world_frame2`] is given).
    pub fn world_frame1(mut self, r: Rotation) -> Self {
        self.0.world_frame1 = Some(r);
        self.0.refused_axis = None;
        self
    }
    /// The joint's x axis in **world** coordinates, as rapier's
    /// `RevoluteJointBuilder::new(axis)` and `PrismaticJointBuilder::new(axis)` take it: the
    /// hinge axis of a revolute or cylindrical joint, the slide of a translational one, the
    /// normal of a planar one. [`Self::world_frame1`] with the shortest rotation from the
    /// world's x to `axis` (y and z follow from it); without either, x goes from anchor 1 to
    /// anchor 2. `axis` need not be a unit vector; a zero or non-finite one is refused at
    /// insertion ([`SimError::InvalidArgument`] naming `world_axis`).
    pub fn world_axis(self, axis: Vector) -> Self {
        let r = match axis.try_normalize() {
            Some(a) => Rotation::from_rotation_arc(Vector::X, a),
            None => Rotation::from_xyzw(Real::NAN, Real::NAN, Real::NAN, Real::NAN),
        };
        let mut b = self.world_frame1(r);
        if !r.is_finite() {
            b.0.refused_axis = Some(axis);
        }
        b
    }
    /// Body 2's initial axes in **world** coordinates (Radioss `Skew_ID2`): the initial
    /// relative rotation is the rotation from [`Self::world_frame1`] to this one; without
    /// [`Self::world_frame1`], from the world axes (as Radioss takes the global system for a
    /// `Skew_ID1 = 0` when `Skew_ID2` is given), not from the anchors' geometry. For
    /// revolute, cylindrical and planar joints both x axes must be parallel (only an initial
    /// angle about x).
    pub fn world_frame2(mut self, r: Rotation) -> Self {
        self.0.world_frame2 = Some(r);
        self
    }
    /// Load-dependent friction on the free DOFs of a **planar** joint (type 4),
    /// docs/planar_friction.md (see [`crate::law::connector`]). Checked at insertion: another
    /// joint type, invalid parameters or KJOINT2 friction (`FF`) on `δy`, `δz`, `θx` give
    /// [`SimError::Connector`]. Stops on the free components are the property's KJOINT2
    /// stops ([`crate::DofLaw::with_stops`]).
    pub fn planar_friction(mut self, law: PlanarFriction) -> Self {
        self.0.connector = ConnectorLaw::PlanarFriction(law);
        self
    }
    /// Load-dependent friction on a **revolute**, **cylindrical** or **translational**
    /// joint (types 2, 3, 6): a pin in its bushing, a slider in its guide, bounded by `μ`
    /// times a normal force built from the joint's own radial reaction and bending moment
    /// (docs/joint_friction.md, [`crate::law::JointFriction`]). Checked at insertion: another
    /// joint type, parameters the type does not use or KJOINT2 friction (`FF`) on the free
    /// DOF give [`SimError::Connector`].
    pub fn joint_friction(mut self, law: JointFriction) -> Self {
        self.0.connector = ConnectorLaw::JointFriction(law);
        self
    }
    /// Riser flex joint law on the rotations of a **spherical** joint (type 1),
    /// docs/flex_joint.md (see [`crate::law::connector`]); the joint's x axis is the riser axis.
    /// Checked at insertion ([`SimError::Connector`]). The quasi-static → dynamic switch
    /// happens at [`Self::flex_joint_switch_time`] or on
    /// [`crate::KjointSet::switch_flex_joint`].
    pub fn flex_joint(mut self, law: FlexJointLaw) -> Self {
        let switch_time = match &self.0.connector {
            ConnectorLaw::FlexJoint(f) => f.switch_time,
            _ => None,
        };
        self.0.connector = ConnectorLaw::FlexJoint(FlexJointConnector { law, switch_time });
        self
    }
    /// Time \[s\] of the flex joint's quasi-static → dynamic switch (call after
    /// [`Self::flex_joint`]; ignored without a flex joint law).
    pub fn flex_joint_switch_time(mut self, t: f64) -> Self {
        if let ConnectorLaw::FlexJoint(f) = &mut self.0.connector {
            f.switch_time = Some(t);
        }
        self
    }
    /// Any connector law (as read from a scene file).
    pub fn connector(mut self, law: ConnectorLaw) -> Self {
        self.0.connector = law;
        self
    }
    /// Makes the joint breakable (docs/breakable.md): after the solve of every substep, the
    /// force and moment it transmitted (`JointState::applied`) and the energy its law
    /// dissipated are checked against `criterion`; when it is met the joint is removed from
    /// its set at the end of that substep, with a
    /// [`crate::dynamics::KjointEventKind::JointBroke`] event and its energies added to
    /// [`crate::KjointSet::removed_energy`]. Checked at insertion
    /// ([`BreakCriterion::validate`]).
    pub fn break_when(mut self, criterion: BreakCriterion) -> Self {
        self.0.break_criterion = Some(criterion);
        self
    }

    /// A motor on a free DOF ([`Kjoint::set_motor`], checked at insertion).
    pub fn motor(mut self, dof: Dof, motor: KjointMotor) -> Self {
        self.0.motors[dof] = Some(motor);
        self
    }
    /// Whether the joint is inserted switched on (`true`, the default) or off (`false`):
    /// a joint switched off acts on nothing until [`crate::KjointSet::set_enabled`]
    /// switches it on, as rapier's `RigidBodyBuilder::enabled` and
    /// `ColliderBuilder::enabled` do for a body and a collider. It is found off at the
    /// set's first analysis, with a [`crate::dynamics::KjointEventKind::DisabledByUser`]
    /// event, as a joint inserted on a disabled body is (`DisabledByBody`).
    pub fn enabled(mut self, enabled: bool) -> Self {
        self.0.enabled = enabled;
        self
    }

    /// Whether rapier's contacts act between the colliders of the joint's two bodies:
    /// `true` (the default) lets them collide, as any two bodies of a rapier world; `false`
    /// leaves them apart, as rapier's `RevoluteJointBuilder::contacts_enabled(false)`
    /// does for its own joints. Links whose colliders overlap at the joint (a slider-crank,
    /// a robot's adjacent links) otherwise push each other apart against it. The set
    /// carries it out with a rapier joint of its own in the world
    /// ([`crate::KjointSet::set_contacts_enabled`] tells how); unlike collision groups,
    /// only this pair of bodies is left apart, and each body still collides with the rest.
    pub fn contacts_enabled(mut self, enabled: bool) -> Self {
        self.0.contacts_enabled = enabled;
        self
    }
}

/// Everything a joint reports after a substep (docs/kjoint2.md §6). Forces use the internal-force
/// convention of [`crate::law::kjoint2`]: body 1 receives `+E·F`, body 2 `−E·F`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub struct JointState {
    /// Simulation time \[s\] at which the joint was evaluated (start of the substep).
    pub time: f64,
    /// `(δx, δy, δz, θx, θy, θz)` [m, rad].
    pub q: PerDof<f64>,
    /// Rates [m/s, rad/s].
    pub rate: PerDof<f64>,
    /// Force/moment of the law per DOF, split by source [N, N·m] (their sum is
    /// [`Self::force`]).
    pub parts: PerDof<ForceParts>,
    /// Total force/moment of the law per DOF at [`Self::time`], `F(q, q̇)` [N, N·m]: what
    /// the law gives for the measured deflection. On a DOF stiffer than the substep resolves
    /// (`ω·h > 1`: a blocked DOF at a large `Kn`, a stiff stop) it is `K·q` on a `q` near f32
    /// resolution and is not what the joint carries: a rod at rest on a blocked DOF at
    /// `Kn = 1e12` reads 0 while the joint holds its weight. Read [`Self::applied`] for that.
    pub force: PerDof<f64>,
    /// Force/moment the joint actually transmitted to its bodies over the substep that
    /// started at [`Self::time`] (`−P/h`, `P` the impulse of the implicit update) [N, N·m]:
    /// the law's force made implicit, with its damping and the numerical damping of
    /// unresolved DOFs. Equal to [`Self::force`] for a DOF the substep resolves in a steady
    /// state; the CSV's `AFX .. AMZ`; the summary's peak force and moment are the peaks of
    /// their magnitudes.
    pub applied: PerDof<f64>,
    /// Stick/slip, stop contact, lock per DOF.
    pub status: PerDof<DofStatus>,
    /// Whether the sensor lock is on.
    pub locked: bool,
    /// Energies.
    pub energy: JointEnergy,
    /// World anchor of body 1 \[m\].
    pub anchor1: [f64; 3],
    /// World anchor of body 2 \[m\].
    pub anchor2: [f64; 3],
    /// Working frame E as a quaternion `[x, y, z, w]` (world).
    pub frame: [f64; 4],
    /// Readout of the connector law (planar friction or flex joint), if the joint has one.
    pub connector: Option<ConnectorReport>,
}

/// A readout of nothing evaluated yet: time 0, every displacement, rate, force and energy
/// 0, no stop in contact, no lock, the anchors at the origin and the working frame the
/// identity (`[0, 0, 0, 1]`, the only entry that is not zero: a quaternion of zeros is no
/// rotation). The readout of a joint that has not been stepped yet ([`Kjoint::state`] is then
/// `None`), for a user's own records of a joint (the last readout kept before a joint is
/// removed, a readout per frame):
///
/// ```
/// use rapier_kjoint::rapier::prelude::*;
/// use rapier_kjoint::{JointState, JointType, KjointBuilder, KjointProperty, KjointSet};
///
/// #[derive(Default)]
/// struct Probe {
///     last: JointState,
///     peak_force: f64,
/// }
///
/// let mut world = PhysicsWorld::default();
/// world.gravity = Vector::new(0.0, -9.81, 0.0);
/// let ground = world.insert_body(RigidBodyBuilder::fixed());
/// let ball = world.insert_body(
///     RigidBodyBuilder::dynamic()
///         .translation(Vector::new(0.0, -1.0, 0.0))
///         .additional_mass(1.0),
/// );
/// let mut joints = KjointSet::new();
/// let prop = KjointProperty::new(JointType::Spherical);
/// let h = joints.insert(KjointBuilder::new(prop), ground, ball, &world.bodies).unwrap();
///
/// let mut probe = Probe::default();
/// assert_eq!(probe.last.time, 0.0); // nothing evaluated yet
/// assert_eq!(probe.last.applied, Default::default());
/// for _ in 0..30 {
///     joints.step(&mut world, 1.0 / 60.0).unwrap();
///     probe.last = joints.get(h).unwrap().state().unwrap().clone();
///     let a = &probe.last.applied;
///     probe.peak_force = probe.peak_force.max((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt());
/// }
/// assert!(probe.last.time > 0.4);
/// assert!((probe.peak_force - 9.81).abs() < 0.5, "{}", probe.peak_force); // the ball's weight
/// ```
impl Default for JointState {
    fn default() -> Self {
        JointState::empty()
    }
}

impl JointState {
    /// A record before the first evaluation ([`JointState::default`]).
    pub(crate) fn empty() -> Self {
        JointState {
            time: 0.0,
            q: PerDof([0.0; 6]),
            rate: PerDof([0.0; 6]),
            parts: Default::default(),
            force: PerDof([0.0; 6]),
            applied: PerDof([0.0; 6]),
            status: Default::default(),
            locked: false,
            energy: Default::default(),
            anchor1: [0.0; 3],
            anchor2: [0.0; 3],
            frame: [0.0, 0.0, 0.0, 1.0],
            connector: None,
        }
    }
}

/// A KJOINT2 joint stored in a [`super::KjointSet`]: its definition attached to two bodies,
/// and its state. Read it with [`super::KjointSet::get`]; through
/// [`super::KjointSet::get_mut`] its name and its property ([`Self::set_property`]) may be
/// changed, not its bodies nor its frames (remove it and insert another joint).
#[derive(Debug, Clone)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
// Laid out in this order (`repr(C)`): the fields every substep reads or writes for every
// joint first, [`KJOINT_HOT_BYTES`] of them, which the prepare stage asks the cache for ahead
// of each joint; then the readout (`state`, written only at the substeps something reads
// it) and what only an event, a check, a breakable joint or a topology change reads. At
// 10 000 joints the records come from memory at every substep: the compiler's own order put
// cold fields among the hot ones (832 bytes in two spans asked for then, 648 now).
#[repr(C)]
pub struct Kjoint {
    pub(crate) measure: MeasureState,
    pub(crate) law: LawState,
    pub(crate) blocked: Option<BlockedStiffness>,
    pub(crate) frames: JointFrames,
    /// Property ([`Self::property`], [`Self::set_property`]), one copy shared by the joints
    /// of a set that have the same (a chain, a crowd, the elements of one deck property:
    /// `KjointSet::insert`). The substep reads it for every joint: 520 bytes a joint read
    /// from memory at 10 000 joints, where the shared copy stays in the cache.
    pub(crate) property: Arc<KjointProperty>,
    /// Body 1 (rapier handle).
    pub(crate) body1: RigidBodyHandle,
    /// Body 2 (rapier handle).
    pub(crate) body2: RigidBodyHandle,
    pub(crate) initial_length: f64,
    pub(crate) connector: Connector,
    /// The law's energy (stored + dissipated) already set against the update's work.
    pub(crate) booked_law: f64,
    /// What the law stored at its first evaluation \[J\] ([`Self::preload_energy`]).
    pub(crate) preload: f64,
    /// The force transmitted over the last substep, `−P/h` \[N, N·m\], as the store stage
    /// left it (0 from the prepare stage until the store stage's result is written): what
    /// the geometric stiffness and the Radioss start read. The readout's
    /// [`JointState::applied`] is its copy, where the readout was written.
    pub(crate) last_applied: [f64; 6],
    /// Which stops acted over the previous substep ([`crate::law::stop_prediction`]).
    pub(crate) predicted_stops: crate::law::StopPredictionState,
    /// The motors of the free DOFs, if any ([`Self::set_motor`]; boxed: 8 bytes of the hot
    /// record for a joint without one).
    pub(crate) motors: Option<Box<MotorDrive>>,
    /// The free DOFs' armatures ([`crate::law::DofLaw::armature`]) where the property has
    /// one, kept with it ([`Self::set_property`]): the prepare stage's test, one word of the
    /// hot record (reading the property's six DOF laws cost the contact scene 0.25 % of
    /// its frame).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(crate) armature: Option<Box<[f64; 6]>>,
    // (the cold fields from here on: KJOINT_HOT_BYTES)
    pub(crate) state: Option<JointState>,
    /// Name.
    pub name: String,
    /// The joint's handle in its set.
    pub(crate) handle: KjointHandle,
    /// How many of the connector's events the set has already reported.
    pub(crate) connector_events_reported: usize,
    /// The values at which the health warnings were last given, per kind (gap, blocked
    /// rotation, stop overrun; 0: not given), each given again once it grows
    /// [`super::health::WARNING_GROWTH`]-fold.
    pub(crate) warned: [f32; 3],
    /// How far beyond the unstable bounds the joint was when its
    /// [`super::KjointEventKind::NoLongerHolds`] warning was last given (0: not given).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(crate) warned_apart: f32,
    /// `|δ|` of the DOF when its [`super::KjointEventKind::SpringRunsAway`] warning was
    /// last given (0: not given), given again once it grows
    /// [`super::health::WARNING_GROWTH`]-fold.
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(crate) warned_runaway: f32,
    /// Whether its [`super::KjointEventKind::RotationVectorJumped`] warning was given.
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(crate) warned_jump: bool,
    /// How far beyond the unstable bounds the joint was when rapier's contacts opened it
    /// (0: not opened by contacts, or back within the bounds since): the run goes on while
    /// it stays within [`super::health::WARNING_GROWTH`] times that (`health::check`).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(crate) opened_by_contact: f32,
    /// The set's time at the joint's last health check \[s\] (none: any time more than a
    /// substep before, `f64::MIN` when built): the checks run at every substep where it is
    /// beyond its warning bounds (or past a stop's), so that a gap between two checks
    /// starts a new excursion beyond them (`health::check`).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(crate) checked_at: f64,
    /// The body of the joint (1, 2; 0: none) that rapier's contacts pushed during its
    /// current excursion beyond its warning bounds (a change of its linear velocity beyond
    /// the solve's prediction over a substep: rapier's own joints on it count too).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(crate) pushed_open: u8,
    /// The set's time \[s\] at which rapier's contacts' opening of the joint (its
    /// [`Self::opened_by_contact`]) was first beyond the unstable bounds: it may stay there
    /// [`super::health::contact_credit_span`] (`health::check`).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub(crate) opened_at: f64,
    /// When the joint breaks (docs/breakable.md), `None`: never.
    pub(crate) break_criterion: Option<BreakCriterion>,
    /// The set's time since which the joint's island has been at rest \[s\]
    /// (`dynamics::sleep`).
    pub(crate) rest_since: f64,
    /// The [`Self::notice_key`] and the substep of the last start notices
    /// (`health::start_notices`), given once for each (NaN: none yet; saved as nothing,
    /// JSON having no NaN).
    #[cfg_attr(feature = "serde-serialize", serde(with = "noticed_serde"))]
    pub(crate) noticed: (u64, f64),
    /// Changes of the joint by the user (`get_mut`, `iter_mut`) since its insertion.
    pub(crate) changes: u64,
    /// Where the automatic stiffness of the implicit rule was lowered by the f32 noise bound
    /// at the substep it was resolved for (`None`: not lowered, or not that rule): what the
    /// health warnings advise.
    pub(crate) noise_bound: Option<crate::law::stiffness::NoiseBound>,
    /// The free DOF whose friction spring a robot loader chose by the implicit rule of the
    /// substep ([`KjointDescription`]'s), kept while the property keeps that `Kf`.
    pub(crate) friction_by_rule: Option<Dof>,
    /// The law's share of the last substep, which it books only at its next evaluation,
    /// as predicted where the readout was written ([`Self::closed_energy`]).
    pub(crate) outstanding: OutstandingShare,
    /// Its place in the order of insertion into its set (the set keeps its enabled joints
    /// in that order, its disabled ones after them).
    pub(crate) order: usize,
    /// Why the joint was left out of the stages at the set's last analysis (`None`: it was
    /// not; [`Self::is_enabled`]).
    pub(crate) disabled: Option<Off>,
    /// The user's switch is off ([`crate::KjointSet::set_enabled`]), since the call: the
    /// set's next analysis takes the joint out of the stages.
    pub(crate) switched_off: bool,
    /// [`Self::closed_energy`] when the joint was disabled, which it reports while it is:
    /// its bodies no longer move it, and the share of its last substep stays what the
    /// motion of that substep made it.
    pub(crate) closed_off: Option<Box<JointEnergy>>,
    /// Whether rapier's contacts act between the two bodies
    /// ([`crate::KjointSet::set_contacts_enabled`]).
    pub(crate) contacts_enabled: bool,
    /// The rapier joint that leaves the bodies' contacts out where they are not enabled,
    /// once the set has put it in the world (`joint_set::contact_filters`).
    pub(crate) contact_filter: Option<crate::rapier::dynamics::ImpulseJointHandle>,
}

/// Why a joint is disabled ([`Kjoint::is_enabled`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) enum Off {
    /// Switched off by the user ([`crate::KjointSet::set_enabled`]; it wins over a disabled
    /// body, as rapier's `JointEnabled::Disabled` over `DisabledByAttachedBody`).
    User,
    /// Its body 1 or 2 (the first found) is disabled (`RigidBody::set_enabled(false)`).
    Body(u8),
    /// Neither body is dynamic (each fixed or kinematic, switched so after the insertion):
    /// there is nothing for the joint to move, as for rapier's joints between such bodies.
    Inert,
    /// Its dynamic body 1 or 2 (the first found) has no mass (its colliders removed, none
    /// with a density, no additional mass) and its stiffness is automatic: it has nothing
    /// to scale with.
    Massless(u8),
}

impl Off {
    /// The cause of a joint whose user's switch is off or not (`switched_off`), whose body
    /// 1 and 2 are disabled or not, which has a dynamic body or not, and whose body 1 and 2
    /// are dynamic without mass or not: `None` when the joint acts.
    pub(crate) fn of(
        switched_off: bool,
        body_off: [bool; 2],
        dynamic: bool,
        massless: [bool; 2],
    ) -> Option<Off> {
        if switched_off {
            Some(Off::User)
        } else if let Some(s) = body_off.iter().position(|b| *b) {
            Some(Off::Body(s as u8 + 1))
        } else if !dynamic {
            Some(Off::Inert)
        } else {
            let s = massless.iter().position(|b| *b)?;
            Some(Off::Massless(s as u8 + 1))
        }
    }

    /// [`Self::of`] joint `j` among `bodies` (`None` where a body of it left the world).
    /// A body without mass turns off only a joint of automatic stiffness, which has nothing
    /// to scale with: one of the user's `Kn` takes it as infinitely heavy, as rapier's
    /// joints do.
    pub(crate) fn of_joint(j: &Kjoint, bodies: &RigidBodySet) -> Option<Option<Off>> {
        let (b1, b2) = (bodies.get(j.body1)?, bodies.get(j.body2)?);
        let automatic = j.property.automatic_stiffness();
        Some(Off::of(
            j.switched_off,
            [!b1.is_enabled(), !b2.is_enabled()],
            b1.is_dynamic() || b2.is_dynamic(),
            [automatic && massless(b1), automatic && massless(b2)],
        ))
    }

    /// Whether `a` and `b` are the same cause, a body's whichever body (a joint disabled
    /// by its body 1 whose body 2 is disabled too before body 1 is enabled again stays
    /// disabled by its bodies, without a new event).
    pub(crate) fn same(a: Option<Off>, b: Option<Off>) -> bool {
        matches!(
            (a, b),
            (None, None)
                | (Some(Off::User), Some(Off::User))
                | (Some(Off::Body(_)), Some(Off::Body(_)))
                | (Some(Off::Inert), Some(Off::Inert))
                | (Some(Off::Massless(_)), Some(Off::Massless(_)))
        )
    }
}

/// Whether `b` is a dynamic body without mass ([`Off::Massless`]).
pub(crate) fn massless(b: &crate::rapier::dynamics::RigidBody) -> bool {
    // (a mass that is not a number is refused where the stiffness is resolved)
    b.is_dynamic() && b.mass() == 0.0
}

/// What the law's share of its last substep is predicted from ([`Kjoint::closed_energy`]):
/// the law books the change of its stored energy and its dissipation over a substep at its
/// next evaluation, from the motion the substep ends with (`substep::prepare::fold_stored`),
/// while the update's work over the substep is booked at once, so that between the two the
/// joint's `numerical` energy holds that share. Written by the prepare stage at the
/// substeps whose readout it writes (a step's last, every one of
/// [`crate::KjointSet::step_with`] and [`crate::KjointSet::apply_substep`]), from the law's
/// output at the substep's start.
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct OutstandingShare {
    /// The gradient `∂S/∂q` of the energy the joint stores, per DOF: the law's springs,
    /// stops, friction springs and lock, scaled as the stored energy is to the stiffness
    /// the update realises (`K̃/K`).
    pub stored_gradient: [f64; 6],
    /// The law's damping force per DOF.
    pub damping: [f64; 6],
    /// The law's tangent damping `∂F/∂q̇` per DOF (without the numerical damping).
    pub damping_tangent: [f64; 6],
    /// Whether the law books a DOF's damping work as the stop's (in a stop's contact).
    pub in_stop: [bool; 6],
    /// The friction force of a DOF that slips (0 elsewhere), whose work is plastic.
    pub slip: [f64; 6],
}

impl OutstandingShare {
    /// The law's share of a substep over which its DOFs moved by `dq`, their rates going
    /// from `rate0` to `rate1`: half the change of the stored energy, `½·∂S/∂q·Δq` (the
    /// implicit update conserves, for a linear spring, `½·m·v² + ½·K̃·q_n·q_{n+1}`: the
    /// stored energy of the substep's mid-point), at least `−stored` (a stop left within the
    /// substep, `q_{n+1}` past it: no energy is stored below zero); the damping work
    /// as the law books it, trapezoidal, `½·Δq·(F_d + F_d')` with `F_d' = F_d + C·Δq̇` (the
    /// stop's in a stop's contact); the plastic work of a slipping DOF, `F_f·Δq` (not below
    /// 0); `numerical` minus their sum. Zero where a force or the motion is not finite.
    pub fn predict(
        &self,
        dq: &[f64; 6],
        rate0: &[f64; 6],
        rate1: &[f64; 6],
        stored: f64,
        motors: Option<&MotorDrive>,
    ) -> JointEnergy {
        let mut e = JointEnergy::default();
        for i in 0..6 {
            e.elastic += 0.5 * self.stored_gradient[i] * dq[i];
            let end = self.damping[i] + self.damping_tangent[i] * (rate1[i] - rate0[i]);
            let damping = 0.5 * dq[i] * (self.damping[i] + end);
            if self.in_stop[i] {
                e.stop += damping;
            } else {
                e.damping += damping;
            }
            e.friction += (self.slip[i] * dq[i]).max(0.0);
            if let Some(d) = motors {
                let [f, k, c] = d.outstanding[i];
                let end = f + k * dq[i] + c * (rate1[i] - rate0[i]);
                e.motor += 0.5 * dq[i] * (f + end);
            }
        }
        e.elastic = e.elastic.max(-stored.max(0.0));
        e.numerical = -(e.elastic + e.damping + e.stop + e.friction + e.motor);
        if e.numerical.is_finite() {
            e
        } else {
            JointEnergy::default()
        }
    }
}

/// The bytes at the start of a [`Kjoint`] that every substep reads or writes for every joint
/// (its fields before the readout `state`).
pub(crate) const KJOINT_HOT_BYTES: usize = std::mem::offset_of!(Kjoint, state);

/// Whether the connector is a flex joint whose bending and torsion are separate laws (the
/// decoupled and dynamic modes), measured by a swing-twist split about the riser axis x.
fn flex_bending(law: &ConnectorLaw) -> bool {
    matches!(law, ConnectorLaw::FlexJoint(f) if f.law.mode() != crate::law::flex_joint::FlexMode::Classical)
}

pub(crate) fn body_pose(bodies: &RigidBodySet, h: RigidBodyHandle) -> Option<BodyPose> {
    bodies.get(h).map(super::substep::body_pose)
}

/// Step 1 of [`Kjoint::build`]: the property, the anchors and the frames are valid.
fn check_description(d: &KjointDescription) -> Result<(), SimError> {
    let name = &d.name;
    d.property.validate().map_err(|source| SimError::Property {
        joint: name.clone(),
        source,
    })?;
    for (field, v) in [
        ("local_anchor1", d.local_anchor1),
        ("local_anchor2", d.local_anchor2),
    ] {
        if !v.is_finite() {
            return Err(SimError::InvalidArgument {
                field: format!("joint `{name}`: {field}"),
                value: format!("{v:?}"),
                expected: "finite coordinates".into(),
            });
        }
    }
    for (field, r) in [
        ("world_frame1", d.world_frame1),
        ("world_frame2", d.world_frame2),
    ] {
        if let Some(r) = r {
            if !r.is_finite() || (r.length() - 1.0).abs() > 1e-3 {
                // (`world_axis` of a zero or non-finite axis leaves this NaN frame: named as
                // the user gave it, where no `world_frame1` came after it)
                let axis = d.refused_axis.filter(|_| field == "world_frame1");
                let from_axis = axis.is_some();
                return Err(SimError::InvalidArgument {
                    field: format!(
                        "joint `{name}`: {}",
                        if from_axis { "world_axis" } else { field }
                    ),
                    value: match axis {
                        Some(a) => format!("[{}, {}, {}]", a.x, a.y, a.z),
                        None => format!("{r:?}"),
                    },
                    expected: if from_axis {
                        "a finite, non-zero axis"
                    } else {
                        "a finite unit quaternion"
                    }
                    .into(),
                });
            }
        }
    }
    if let Some(c) = &d.break_criterion {
        c.validate().map_err(|e| match e {
            crate::error::PropertyError::InvalidField {
                field,
                value,
                expected,
            } => SimError::InvalidArgument {
                field: format!("joint `{name}`: break_criterion.{field}"),
                value,
                expected,
            },
            other => SimError::InvalidJoint {
                joint: name.clone(),
                reason: other.to_string(),
            },
        })?;
    }
    Ok(())
}

/// Step 2 of [`Kjoint::build`]: the initial world frames of both sides (from the geometry
/// when not given), checked against what the joint type allows.
fn initial_frames(
    d: &KjointDescription,
    p1: &Vector3<f64>,
    p2: &Vector3<f64>,
) -> Result<(UnitQuaternion<f64>, UnitQuaternion<f64>), SimError> {
    // Radioss (/PROP/TYPE45, Skew_ID1 = 0 with Skew_ID2 != 0): Skew_ID1 is then the global
    // system, not the anchors' geometry; the initial angles are measured from the world axes
    let f1: UnitQuaternion<f64> = match (d.world_frame1, d.world_frame2) {
        (Some(r), _) => from_quat(r),
        (None, Some(_)) => UnitQuaternion::identity(),
        (None, None) => kinematics::frame_from_x(&(p2 - p1)),
    };
    let f2: UnitQuaternion<f64> = d.world_frame2.map(from_quat).unwrap_or(f1);
    let jt = d.property.joint_type;
    if jt.single_free_rotation() && d.world_frame2.is_some() {
        let c = (f1 * Vector3::x()).dot(&(f2 * Vector3::x()));
        if c < 1.0 - crate::law::property::SKEW_X_PARALLEL {
            return Err(SimError::InvalidJoint {
                joint: d.name.clone(),
                reason: format!(
                    "a {} joint allows an initial angle about x only: the x axes of \
                     world_frame1 (Skew1) and world_frame2 (Skew2) must be parallel (cos = {c:.6})",
                    jt.name()
                ),
            });
        }
    }
    Ok((f1, f2))
}

/// How a joint of this type and connector measures its rotations and translations.
fn measures(
    jt: crate::law::JointType,
    connector: &ConnectorLaw,
) -> (RotationMeasure, TranslationMeasure) {
    // the flex joint's bending angle is the angle between the two axes (flex_joint.md):
    // the swing of a swing-twist split, the torsion its twist; only its classical mode
    // acts on the total rotation angle, the rotation vector's norm
    let rotation = if jt.single_free_rotation() || flex_bending(connector) {
        RotationMeasure::TwistX
    } else if jt == crate::law::JointType::Universal {
        RotationMeasure::Cardan
    } else {
        RotationMeasure::RotationVector
    };
    // the planar-friction connector measures its translations as Abaqus's PLANAR
    // does, on body 1's plane at anchor 2 (kinematics, "Translation measure")
    let translation = if matches!(connector, ConnectorLaw::PlanarFriction(_)) {
        TranslationMeasure::Body1Frame
    } else {
        TranslationMeasure::MidPoint
    };
    (rotation, translation)
}

/// Step 3 of [`Kjoint::build`]: a user blocked stiffness `Kn` gives a finite rotational
/// stiffness `KR = Kn·max(ScF, L0²)` (validate() checked `Kn·ScF`).
fn check_user_stiffness(
    name: &str,
    property: &KjointProperty,
    initial_length: f64,
) -> Result<(), SimError> {
    if property.automatic_stiffness() {
        return Ok(());
    }
    let l2 = initial_length * initial_length;
    let k = crate::law::stiffness::user_blocked_stiffness(property, initial_length);
    if k.rotational.is_finite() {
        return Ok(());
    }
    Err(SimError::Property {
        joint: name.to_string(),
        source: crate::error::PropertyError::field(
            "kn (Kn)",
            property.kn,
            format!(
                "a value whose rotational stiffness KR = Kn·max(ScF, L0²) = Kn·{:e} \
                 is finite (L0 = {initial_length} m)",
                property.resolved_scale_factor().max(l2)
            ),
        ),
    })
}

impl Kjoint {
    /// The joint of definition `d` between `body1` and `body2` at their current poses,
    /// checked; its handle is set by the set.
    pub(crate) fn build(
        d: KjointDescription,
        body1: RigidBodyHandle,
        body2: RigidBodyHandle,
        bodies: &RigidBodySet,
    ) -> Result<Kjoint, SimError> {
        check_description(&d)?;
        let name = d.name.clone();
        let pose1 = body_pose(bodies, body1).ok_or(SimError::MissingBody {
            joint: name.clone(),
            which: 1,
            body: body1,
        })?;
        let pose2 = body_pose(bodies, body2).ok_or(SimError::MissingBody {
            joint: name.clone(),
            which: 2,
            body: body2,
        })?;
        if body1 == body2 {
            return Err(SimError::InvalidJoint {
                joint: name,
                reason: "body 1 and body 2 are the same body".into(),
            });
        }
        // the frames and L0 are taken from the poses once: a NaN there stays in the joint
        for (which, h) in [(1, body1), (2, body2)] {
            if !bodies.get(h).is_some_and(super::substep::pose_is_finite) {
                return Err(SimError::InvalidJoint {
                    joint: name,
                    reason: format!("body {which} has a non-finite pose or velocity"),
                });
            }
        }
        let a1 = from_vec3(d.local_anchor1);
        let a2 = from_vec3(d.local_anchor2);
        let p1 = pose1.point(&a1);
        let p2 = pose2.point(&a2);
        let (f1, f2) = initial_frames(&d, &p1, &p2)?;
        d.connector
            .validate(&d.property)
            .map_err(|source| SimError::Connector {
                joint: name.clone(),
                source,
            })?;
        let (measure, translation) = measures(d.property.joint_type, &d.connector);
        let mut frames = JointFrames {
            local_anchor1: a1,
            local_anchor2: a2,
            local_frame1: pose1.rotation.inverse() * f1,
            local_frame2: pose2.rotation.inverse() * f2,
            delta0: Vector3::zeros(),
            measure,
            translation,
        };
        let initial_length = (p2 - p1).norm();
        check_user_stiffness(&name, &d.property, initial_length)?;
        let mut ms = MeasureState::default();
        let k0 = kinematics::measure(&frames, &pose1, &pose2, &mut ms);
        frames.delta0 = Vector3::new(k0.q[0], k0.q[1], k0.q[2]);
        let armature = d.property.armature().map(Box::new);
        Kjoint {
            name,
            property: Arc::new(d.property),
            body1,
            body2,
            handle: KjointHandle::invalid(),
            frames,
            measure: MeasureState::default(),
            law: LawState::default(),
            blocked: None,
            initial_length,
            state: None,
            connector: Connector::new(d.connector),
            connector_events_reported: 0,
            warned: [0.0; 3],
            warned_apart: 0.0,
            warned_runaway: 0.0,
            warned_jump: false,
            opened_by_contact: 0.0,
            checked_at: f64::MIN,
            pushed_open: 0,
            opened_at: 0.0,
            booked_law: 0.0,
            preload: 0.0,
            last_applied: [0.0; 6],
            predicted_stops: Default::default(),
            break_criterion: d.break_criterion,
            rest_since: 0.0,
            noticed: (u64::MAX, f64::NAN),
            changes: 0,
            noise_bound: None,
            friction_by_rule: d.friction_by_rule,
            outstanding: OutstandingShare::default(),
            order: 0,
            disabled: None,
            switched_off: !d.enabled,
            closed_off: None,
            motors: None,
            armature,
            contacts_enabled: d.contacts_enabled,
            contact_filter: None,
        }
        .with_motors(&d.motors)
    }

    /// The state of a joint just inserted, its definition kept (property, frames, the pose
    /// its DOFs are measured from, `L0`, motors, name, switches): the law's (friction
    /// springs, plastic and hysteretic state, sensor lock, energies), the stop prediction,
    /// the motors' last forces, the readout, the health warnings and the blocked stiffness
    /// (resolved again at the next substep). [`crate::KjointSet::reset_state`].
    pub(crate) fn reset_state(&mut self, time: f64) {
        self.measure = MeasureState::default();
        self.law = LawState::default();
        self.blocked = None;
        self.state = None;
        self.connector = Connector::new(self.connector.law().clone());
        self.connector_events_reported = 0;
        self.warned = [0.0; 3];
        self.warned_apart = 0.0;
        self.warned_runaway = 0.0;
        self.warned_jump = false;
        self.opened_by_contact = 0.0;
        self.checked_at = f64::MIN;
        self.pushed_open = 0;
        self.opened_at = 0.0;
        self.booked_law = 0.0;
        self.preload = 0.0;
        self.last_applied = [0.0; 6];
        self.predicted_stops = Default::default();
        self.rest_since = time;
        self.noise_bound = None;
        self.outstanding = OutstandingShare::default();
        if let Some(m) = self.motors.as_deref_mut() {
            m.prev_force = [0.0; 6];
            m.outstanding = [[0.0; 3]; 6];
        }
        if self.closed_off.is_some() {
            self.closed_off = Some(Box::default());
        }
    }

    /// The joint with the motors of its description, checked.
    fn with_motors(mut self, motors: &PerDof<Option<KjointMotor>>) -> Result<Self, SimError> {
        for (dof, m) in motors.with_dof() {
            if m.is_some() {
                self.set_motor(dof, *m)?;
            }
        }
        Ok(self)
    }

    /// The joint's handle in the set it was inserted into.
    pub fn handle(&self) -> KjointHandle {
        self.handle
    }

    /// Body 1 (rapier handle).
    pub fn body1(&self) -> RigidBodyHandle {
        self.body1
    }

    /// Body 2 (rapier handle).
    pub fn body2(&self) -> RigidBodyHandle {
        self.body2
    }

    /// The joint's axes at insertion in body 1's frame: its [`KjointBuilder::world_frame1`],
    /// or the frame the anchors' geometry gave it (docs/kjoint2.md §3), carried by body 1.
    /// `bodies[j.body1()].rotation() * j.local_frame1()` gives them in the world (`kjoint
    /// check` prints them): the x of a flex joint is the riser's axis, of a revolute joint
    /// its hinge.
    pub fn local_frame1(&self) -> Rotation {
        super::convert::to_quat(&self.frames.local_frame1)
    }

    /// Whether the joint acts: `false` while it is switched off by the user
    /// ([`super::KjointSet::set_enabled`], [`KjointBuilder::enabled`]), one of its bodies
    /// is disabled (`RigidBody::set_enabled(false)`), neither body is dynamic any more
    /// (both made fixed or kinematic: [`crate::KjointEventKind::NoDynamicBody`]), or a
    /// dynamic body has no mass ([`crate::KjointEventKind::MasslessBody`]), as rapier's
    /// `GenericJoint::is_enabled` is for an impulse joint disabled (`JointEnabled::Disabled`)
    /// or attached to a disabled body (`DisabledByAttachedBody`). A disabled joint applies
    /// nothing, is left out of the solve and of the islands, and its law is not evaluated:
    /// its state (the displacements, friction, stops, the measured angles' turn count) and
    /// its energies keep their values at disabling, and its readout reports no force. The
    /// user's switch counts from the call; a body's state is read by the set at each
    /// substep's analysis ([`super::KjointSet`], "Disabled bodies").
    pub fn is_enabled(&self) -> bool {
        !self.switched_off
            && !matches!(
                self.disabled,
                Some(Off::Body(_) | Off::Inert | Off::Massless(_))
            )
    }

    /// Whether the user's switch is on ([`super::KjointSet::set_enabled`],
    /// [`KjointBuilder::enabled`]): `true` unless the user switched the joint off, whatever
    /// its bodies ([`Self::is_enabled`] tells whether it acts).
    pub fn is_switched_on(&self) -> bool {
        !self.switched_off
    }

    /// Whether rapier's contacts act between the colliders of the joint's two bodies
    /// ([`KjointBuilder::contacts_enabled`], [`super::KjointSet::set_contacts_enabled`]).
    pub fn contacts_enabled(&self) -> bool {
        self.contacts_enabled
    }

    /// The motor of a DOF ([`Self::set_motor`]), `None` where it has none.
    pub fn motor(&self, dof: Dof) -> Option<&KjointMotor> {
        self.motors.as_ref()?.motors[dof].as_ref()
    }

    /// Sets (`Some`) or removes (`None`) the motor of a free DOF, as rapier's
    /// `GenericJoint::set_motor`: the drive force
    /// `τ = clamp(k_p·(q* − q) + k_d·(q̇* − q̇), ±F_max)` on body 2, `−τ` on body 1
    /// ([`KjointMotor`], `law::motor`), part of the law's force
    /// ([`crate::law::ForceParts::motor`]) and of its tangents, so that the implicit update
    /// holds a stiff servo as it holds a stiff spring. `q` is measured as the joint measures
    /// it ([`JointState::q`]: from the pose at insertion). Refused, changing nothing: a
    /// blocked DOF, a flex joint, a NaN, infinite (but `max_force`) or negative setting.
    /// Through [`super::KjointSet::get_mut`] the set analyses its joints again; to change a
    /// target at every frame, [`super::KjointSet::set_motor`] does not.
    ///
    /// ```
    /// use rapier_kjoint::rapier::prelude::*;
    /// use rapier_kjoint::{Dof, JointType, KjointBuilder, KjointMotor, KjointProperty, KjointSet};
    /// let mut world = PhysicsWorld::default();
    /// let ground = world.insert_body(RigidBodyBuilder::fixed());
    /// let arm = world.insert_body(RigidBodyBuilder::dynamic().additional_mass(1.0));
    /// let mut joints = KjointSet::new();
    /// let hinge = KjointBuilder::new(KjointProperty::new(JointType::Revolute));
    /// let h = joints.insert(hinge, ground, arm, &world.bodies).unwrap();
    /// let j = joints.get_mut(h).unwrap();
    /// j.set_motor(Dof::Rx, Some(KjointMotor::position(0.5, 100.0, 10.0))).unwrap();
    /// assert_eq!(j.motor(Dof::Rx).unwrap().target_pos, 0.5);
    /// // a hinge's translations are blocked; a negative stiffness is refused
    /// assert!(j.set_motor(Dof::Dx, Some(KjointMotor::velocity(1.0, 5.0))).is_err());
    /// assert!(j.set_motor(Dof::Rx, Some(KjointMotor::position(0.5, -1.0, 0.0))).is_err());
    /// assert_eq!(j.motor(Dof::Rx).unwrap().stiffness, 100.0);
    /// ```
    pub fn set_motor(&mut self, dof: Dof, motor: Option<KjointMotor>) -> Result<(), SimError> {
        let Some(m) = motor else {
            if let Some(d) = self.motors.as_deref_mut() {
                d.motors[dof] = None;
                if !d.any() {
                    // its last force's work was booked at the last evaluation
                    self.motors = None;
                }
            }
            return Ok(());
        };
        let flex = matches!(self.connector.law(), ConnectorLaw::FlexJoint(_));
        crate::law::motor::check_motor(self.property.joint_type, flex, dof, &m).map_err(
            |source| SimError::Motor {
                joint: self.name.clone(),
                dof,
                source,
            },
        )?;
        self.motors.get_or_insert_with(Default::default).motors[dof] = Some(m);
        Ok(())
    }

    /// The KJOINT2 property.
    pub fn property(&self) -> &KjointProperty {
        &self.property
    }

    /// Replaces the property (new laws, a new blocked stiffness `Kn`), checked as at
    /// insertion; the joint type must stay the same (its frames and measures were made for
    /// it) and the connector law must accept the new property. The blocked stiffness is
    /// resolved again at the next substep; the laws' internal states (plastic offsets,
    /// friction anchors, the sensor lock) and the energies are kept. Reach the joint
    /// through [`super::KjointSet::get_mut`], which makes the set analyse its joints again.
    ///
    /// ```
    /// use rapier_kjoint::rapier::prelude::*;
    /// use rapier_kjoint::{JointType, KjointBuilder, KjointProperty, KjointSet};
    /// let mut world = PhysicsWorld::default();
    /// let ground = world.insert_body(RigidBodyBuilder::fixed());
    /// let ball = world.insert_body(RigidBodyBuilder::dynamic().additional_mass(1.0));
    /// let mut joints = KjointSet::new();
    /// let prop = KjointProperty::new(JointType::Spherical);
    /// let h = joints.insert(KjointBuilder::new(prop.clone()), ground, ball, &world.bodies).unwrap();
    /// let j = joints.get_mut(h).unwrap();
    /// j.set_property(prop.clone().with_kn(1e6)).unwrap();
    /// assert_eq!(j.property().kn, 1e6);
    /// // another joint type, or an invalid value, is refused and changes nothing
    /// assert!(j.set_property(KjointProperty::new(JointType::Revolute)).is_err());
    /// assert!(j.set_property(prop.with_kn(f64::NAN)).is_err());
    /// assert_eq!(j.property().kn, 1e6);
    /// ```
    pub fn set_property(&mut self, property: KjointProperty) -> Result<(), SimError> {
        property.validate().map_err(|source| SimError::Property {
            joint: self.name.clone(),
            source,
        })?;
        if property.joint_type != self.property.joint_type {
            return Err(SimError::InvalidJoint {
                joint: self.name.clone(),
                reason: format!(
                    "set_property: the joint type cannot change ({} → {}); remove the joint \
                     and insert another",
                    self.property.joint_type.name(),
                    property.joint_type.name()
                ),
            });
        }
        self.connector
            .law()
            .validate(&property)
            .map_err(|source| SimError::Connector {
                joint: self.name.clone(),
                source,
            })?;
        check_user_stiffness(&self.name, &property, self.initial_length)?;
        // a friction spring the user changes is theirs
        if let Some(d) = self.friction_by_rule {
            if property.dof(d).friction_stiffness != self.property.dof(d).friction_stiffness {
                self.friction_by_rule = None;
            }
        }
        self.armature = property.armature().map(Box::new);
        if self.armature.is_none() {
            // (none stored from then on)
            self.law.energy.kinetic = 0.0;
        }
        self.property = Arc::new(property);
        self.blocked = None;
        Ok(())
    }

    /// The state after the last substep (`None` before the first). After an error inside
    /// [`KjointSet::step`](crate::KjointSet::step), that of the last substep that wrote it
    /// ([`JointState::time`]): the substeps before a step's last write only the readouts
    /// their checks read.
    pub fn state(&self) -> Option<&JointState> {
        self.state.as_ref()
    }

    /// How far the anchors are apart along the joint's blocked translations at its last
    /// readout, `|q_t|` \[m\] (what the health checks judge against the joint's size, README
    /// "Health of a run"); `None` before its first substep. A joint whose translations are
    /// all blocked (spherical, revolute, universal, fixed) reads the distance between its
    /// anchors.
    pub fn blocked_gap(&self) -> Option<f64> {
        let s = self.state.as_ref()?;
        Some(super::health::blocked_motion(self.property.joint_type, &s.q).0)
    }

    /// The largest of the joint's blocked rotations at its last readout, `max |q_r|`
    /// \[rad\] (the health checks' measure); `None` before its first substep.
    pub fn blocked_rotation(&self) -> Option<f64> {
        let s = self.state.as_ref()?;
        Some(super::health::blocked_motion(self.property.joint_type, &s.q).1)
    }

    /// Resolved blocked stiffness (`None` until the first step for automatic stiffness).
    pub fn blocked_stiffness(&self) -> Option<BlockedStiffness> {
        self.blocked
    }

    /// Distance between the anchors at creation, `L0` \[m\].
    pub fn initial_length(&self) -> f64 {
        self.initial_length
    }

    /// Energies accumulated so far, as booked: the law's through its last evaluation, at
    /// the start of the last substep ([`JointState::time`]), and the update's work through
    /// the end of that substep. The law's share of the last substep (the change of its
    /// stored energy and its dissipation over it) is booked at its next evaluation, and
    /// `numerical` holds it until then: through a stop's contact it swings by about
    /// `±F·v·h/2` and comes back, and the stored energy is that of the substep's start.
    /// [`Self::closed_energy`] adds that share.
    pub fn energy(&self) -> JointEnergy {
        self.law.energy
    }

    /// The joint's energies at the end of the last substep, for the bodies' poses and
    /// velocities in `bodies` at that end: [`Self::energy`] with the law's share of the
    /// substep, which the law books only at its next evaluation, added as the law's forces
    /// at the substep's start ([`Self::state`]) predict it along the motion the joint has
    /// made since (`Δq`, measured from `bodies`, and the change of its rates): half the
    /// change of the stored energy (the implicit update conserves, for a linear spring,
    /// `½·m·v² + ½·K̃·q_n·q_{n+1}`, the stored energy of the substep's mid-point), the whole
    /// of the damping and friction work, and `numerical` less their sum. The fields add up
    /// to [`Self::energy`]'s total, both the preload plus what the bodies gave the joint, so
    /// that an energy balance closes alike; what differs is the split between stored and
    /// dissipated. A 1 kg slider at 2 m/s into an undamped 1000 N/m stop at 240 Hz books
    /// `numerical` swinging by ±0.14 J through the contact in [`Self::energy`] and by
    /// 1.4e-6 J in this; damped (`Cr` = 0.05), the dissipated energy of this is the
    /// damper's work within 0.0054 J at every frame end, where [`Self::energy`]'s was off by
    /// up to 0.1 J (`tests/energy_balance.rs`). What the summary, the CSV histories, the
    /// figures and the recording of a run report (a joint removed within a step, broken or
    /// detached, keeps its energies as booked: [`crate::KjointEvent::removed_joint`]).
    ///
    /// Read it where a step, or a substep of
    /// [`KjointSet::step_with`](crate::KjointSet::step_with) or
    /// [`KjointSet::apply_substep`](crate::KjointSet::apply_substep), has ended, before
    /// the bodies are moved; it is [`Self::energy`] where the law has evaluated since its
    /// last readout (an error within a step), before the first substep and where a body is
    /// gone from `bodies`. It costs a measure of the joint's kinematics.
    ///
    /// A disabled joint ([`Self::is_enabled`], switched off, of a disabled body, with no
    /// dynamic body or of automatic stiffness on a body without mass, once the set has
    /// found it so at a substep) reports what this was when it was disabled: its
    /// bodies no longer move it (measured from them, the share grew with the fall of a bob
    /// whose joint was off: 20.35 J of damping a quarter second into the fall for a rod
    /// that had damped 0.030 J, offset by as much `numerical`).
    pub fn closed_energy(&self, bodies: &RigidBodySet) -> JointEnergy {
        if self.disabled.is_some() {
            return self
                .closed_off
                .as_deref()
                .copied()
                .unwrap_or(self.law.energy);
        }
        let e = self.law.energy;
        let Some(s) = self.state.as_ref() else {
            return e;
        };
        // the law's book and the forces are the readout's: its last evaluation there
        if self.law.prev_q != Some(s.q.0) {
            return e;
        }
        let (Some(p1), Some(p2)) = (body_pose(bodies, self.body1), body_pose(bodies, self.body2))
        else {
            return e;
        };
        let mut measure = self.measure;
        let now = kinematics::measure(&self.frames, &p1, &p2, &mut measure);
        let dq = std::array::from_fn(|i| now.q[i] - s.q.0[i]);
        let share =
            self.outstanding
                .predict(&dq, &s.rate.0, &now.rate, e.elastic, self.motors.as_deref());
        // the rotors' kinetic energy at the rates now (what the law books at its next
        // evaluation), its change taken from the update's share as the law's other shares are
        let kinetic: f64 = match self.armature.as_deref() {
            Some(a) => JointEnergy::rotor_energy(a, &now.rate),
            None => 0.0,
        };
        let kinetic_share = if kinetic.is_finite() {
            kinetic - e.kinetic
        } else {
            0.0
        };
        JointEnergy {
            elastic: e.elastic + share.elastic,
            kinetic: e.kinetic + kinetic_share,
            damping: e.damping + share.damping,
            friction: e.friction + share.friction,
            stop: e.stop + share.stop,
            internal: e.internal,
            numerical: e.numerical + share.numerical - kinetic_share,
            motor: e.motor + share.motor,
        }
    }

    /// The energy the joint stored at its first substep \[J\], before its bodies did any
    /// work on it: its preload, `½·K·θ0²` for an initial angle `θ0` between its skew frames
    /// (`Skew_ID2`, [`KjointBuilder::world_frame2`]) on a linear spring, or what its law
    /// stores where the bodies were not at the joint's rest position when it was inserted
    /// (0 before the first substep). The energy book starts from it: the joint's energies
    /// ([`Self::energy`], stored plus dissipated) add up to this plus the work its bodies
    /// did on it, and an energy balance counts it with the initial energy (the summary's
    /// "stored in the joints at their start").
    pub fn preload_energy(&self) -> f64 {
        self.preload
    }

    /// The sensor lock once its sensor has fired (docs/kjoint2.md §4.5): the values `q_s` it
    /// holds the DOFs at and the force each free DOF carried at activation, held since.
    /// `None` while the joint is not locked.
    pub fn sensor_lock(&self) -> Option<&crate::law::SensorLock> {
        self.law.lock.as_deref()
    }

    /// When the joint breaks (docs/breakable.md), `None`: never.
    pub fn break_criterion(&self) -> Option<&BreakCriterion> {
        self.break_criterion.as_ref()
    }

    /// The connector law attached to the joint.
    pub fn connector_law(&self) -> &ConnectorLaw {
        self.connector.law()
    }

    /// Connector events so far (flex joint phase switches), oldest first.
    pub fn connector_events(&self) -> &[ConnectorEvent] {
        self.connector.events()
    }

    /// What the start notices of the joint depend on besides the substep: its changes by
    /// the user and its blocked stiffness (which an analysis after another joint's
    /// insertion or removal may change, through its load side). The notices are given again
    /// when it changes, and not for every change of the set (a ragdoll removed from a game
    /// gave again the notices of every joint of the 29 others).
    ///
    /// The stiffness counts by its logarithm to 1 % (an analysis computes it again from
    /// the poses of the moment: a joint's load 100 m out, swinging by millimetres, changes
    /// its last bits, not its notices).
    pub(crate) fn notice_key(&self) -> u64 {
        let level = |k: f64| (k.max(f64::MIN_POSITIVE).ln() * 100.0).round() as i64 as u64;
        let (kt, kr) = self
            .blocked
            .map_or((0, 0), |k| (level(k.translational), level(k.rotational)));
        self.changes.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ kt ^ kr.rotate_left(32)
    }

    /// The DOF's value in the last state \[m or rad\]: measured at the start of the last
    /// substep, at [`JointState::time`] (after [`KjointSet::step`], one substep before
    /// [`KjointSet::time`]; the bodies' poses are the end's). `None` before the first step.
    ///
    /// [`KjointSet::step`]: crate::KjointSet::step
    /// [`KjointSet::time`]: crate::KjointSet::time
    pub fn dof_value(&self, dof: Dof) -> Option<f64> {
        self.state.as_ref().map(|s| s.q[dof.index()])
    }
}

/// [`Kjoint::noticed`] saved with its NaN substep ("no notice yet") as nothing: JSON has no
/// NaN (`serde_json` wrote `null` and refused it back: a set saved before its first step).
#[cfg(feature = "serde-serialize")]
mod noticed_serde {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(n: &(u64, f64), s: S) -> Result<S::Ok, S::Error> {
        (n.0, (!n.1.is_nan()).then_some(n.1)).serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<(u64, f64), D::Error> {
        let (key, h) = <(u64, Option<f64>)>::deserialize(d)?;
        Ok((key, h.unwrap_or(f64::NAN)))
    }
}
