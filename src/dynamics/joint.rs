//! One KJOINT2 joint between two rapier bodies: its builder (the inputs of docs/kjoint2.md
//! §1: property, anchors, Skew1/Skew2 frames; a connector law of docs/planar_friction.md or
//! docs/flex_joint.md), its stored data and the state it reports after every substep
//! (docs/kjoint2.md §6).

use super::convert::{from_quat, from_vec3};
use crate::error::SimError;
use crate::kinematics::{
    self, BodyPose, JointFrames, MeasureState, RotationMeasure, TranslationMeasure,
};
use crate::law::{
    BlockedStiffness, Connector, ConnectorEvent, ConnectorLaw, ConnectorReport, Dof, DofStatus,
    FlexJointConnector, FlexJointLaw, ForceParts, JointEnergy, KjointProperty, LawState, PerDof,
    PlanarFriction,
};
use crate::rapier::dynamics::{RigidBodyHandle, RigidBodySet};
use crate::rapier::math::{Rotation, Vector};
use nalgebra::{UnitQuaternion, Vector3};
use serde::Serialize;

/// Builder of a KJOINT2 joint, in the style of rapier's joint builders: the property
/// (docs/kjoint2.md §1), the anchors, the Skew1/Skew2 frames and a connector law.
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
///     .frame(Rotation::from_rotation_arc(Vector::X, Vector::Z)) // joint x axis = world z
///     .local_anchor2(Vector::new(-0.5, 0.0, 0.0));             // the rod's end
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
pub struct KjointBuilder {
    pub(crate) name: String,
    pub(crate) property: KjointProperty,
    pub(crate) local_anchor1: Vector,
    pub(crate) local_anchor2: Vector,
    pub(crate) frame1: Option<Rotation>,
    pub(crate) frame2: Option<Rotation>,
    pub(crate) connector: ConnectorLaw,
}

impl KjointBuilder {
    /// A joint with the given property, anchors at both bodies' origins, axes from the
    /// geometry (x from anchor 1 to anchor 2, or the world axes when the anchors coincide).
    pub fn new(property: KjointProperty) -> Self {
        KjointBuilder {
            name: String::new(),
            property,
            local_anchor1: Vector::ZERO,
            local_anchor2: Vector::ZERO,
            frame1: None,
            frame2: None,
            connector: ConnectorLaw::None,
        }
    }
    /// A name for messages and outputs.
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }
    /// Anchor on body 1, in body 1's local coordinates \[m\].
    pub fn local_anchor1(mut self, p: Vector) -> Self {
        self.local_anchor1 = p;
        self
    }
    /// Anchor on body 2, in body 2's local coordinates \[m\].
    pub fn local_anchor2(mut self, p: Vector) -> Self {
        self.local_anchor2 = p;
        self
    }
    /// The joint's initial axes in world coordinates (Radioss `Skew_ID1`): the columns of
    /// this rotation are the joint's x, y, z axes at creation.
    pub fn frame(mut self, r: Rotation) -> Self {
        self.frame1 = Some(r);
        self
    }
    /// Body 2's initial axes in world coordinates (Radioss `Skew_ID2`): the initial relative
    /// rotation is the rotation from [`Self::frame`] to this one. For revolute, cylindrical
    /// and planar joints both x axes must be parallel (only an initial angle about x).
    pub fn frame2(mut self, r: Rotation) -> Self {
        self.frame2 = Some(r);
        self
    }
    /// Load-dependent friction on the free DOFs of a **planar** joint (type 4),
    /// docs/planar_friction.md (see [`crate::law::connector`]). Checked at insertion: another
    /// joint type, invalid parameters or KJOINT2 friction (`FF`) on `δy`, `δz`, `θx` give
    /// [`SimError::Connector`]. Stops on the free components are the property's KJOINT2
    /// stops ([`crate::DofLaw::with_stops`]).
    pub fn planar_friction(mut self, law: PlanarFriction) -> Self {
        self.connector = ConnectorLaw::PlanarFriction(law);
        self
    }
    /// Riser flex joint law on the rotations of a **spherical** joint (type 1),
    /// docs/flex_joint.md (see [`crate::law::connector`]); the joint's x axis is the riser axis.
    /// Checked at insertion ([`SimError::Connector`]). The quasi-static → dynamic switch
    /// happens at [`Self::flex_joint_switch_time`] or on
    /// [`crate::KjointSet::switch_flex_joint`].
    pub fn flex_joint(mut self, law: FlexJointLaw) -> Self {
        let switch_time = match &self.connector {
            ConnectorLaw::FlexJoint(f) => f.switch_time,
            _ => None,
        };
        self.connector = ConnectorLaw::FlexJoint(FlexJointConnector { law, switch_time });
        self
    }
    /// Time \[s\] of the flex joint's quasi-static → dynamic switch (call after
    /// [`Self::flex_joint`]; ignored without a flex joint law).
    pub fn flex_joint_switch_time(mut self, t: f64) -> Self {
        if let ConnectorLaw::FlexJoint(f) = &mut self.connector {
            f.switch_time = Some(t);
        }
        self
    }
    /// Any connector law (as read from a scene file).
    pub fn connector(mut self, law: ConnectorLaw) -> Self {
        self.connector = law;
        self
    }
}

/// Everything a joint reports after a substep (docs/kjoint2.md §6). Forces use the internal-force
/// convention of [`crate::law::kjoint2`]: body 1 receives `+E·F`, body 2 `−E·F`.
#[derive(Debug, Clone, PartialEq, Serialize)]
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
    /// state; the summary's peak force and moment, the CSV's `AFX .. AMZ`.
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

impl JointState {
    /// A record before the first evaluation (everything zero).
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

/// A KJOINT2 joint stored in a [`super::KjointSet`].
#[derive(Debug, Clone)]
pub struct Kjoint {
    /// Name.
    pub name: String,
    /// Property.
    pub property: KjointProperty,
    /// Body 1 (rapier handle).
    pub body1: RigidBodyHandle,
    /// Body 2 (rapier handle).
    pub body2: RigidBodyHandle,
    pub(crate) frames: JointFrames,
    pub(crate) measure: MeasureState,
    pub(crate) law: LawState,
    pub(crate) blocked: Option<BlockedStiffness>,
    pub(crate) initial_length: f64,
    pub(crate) state: Option<JointState>,
    pub(crate) connector: Connector,
    /// How many of the connector's events the set has already reported.
    pub(crate) connector_events_reported: usize,
    /// `false` once a body of the joint has left the world: the joint takes no further part.
    pub(crate) active: bool,
    /// Health warnings already given (bits of `substep::health`), each given once.
    pub(crate) warned: u8,
    /// The law's energy (stored + dissipated) already set against the update's work.
    pub(crate) booked_law: f64,
    /// Which stops acted over the previous substep ([`crate::law::stop_prediction`]).
    pub(crate) predicted_stops: crate::law::StopPredictionState,
}

/// Whether the connector is a flex joint whose bending and torsion are separate laws (the
/// decoupled and dynamic modes), measured by a swing-twist split about the riser axis x.
fn flex_bending(law: &ConnectorLaw) -> bool {
    matches!(law, ConnectorLaw::FlexJoint(f) if f.law.mode() != crate::law::flex_joint::FlexMode::Classical)
}

pub(crate) fn body_pose(bodies: &RigidBodySet, h: RigidBodyHandle) -> Option<BodyPose> {
    let b = bodies.get(h)?;
    Some(BodyPose {
        translation: from_vec3(b.translation()),
        rotation: from_quat(*b.rotation()),
        com: from_vec3(b.center_of_mass()),
        linvel: from_vec3(b.linvel()),
        angvel: from_vec3(b.angvel()),
    })
}

impl Kjoint {
    pub(crate) fn build(
        b: KjointBuilder,
        body1: RigidBodyHandle,
        body2: RigidBodyHandle,
        bodies: &RigidBodySet,
    ) -> Result<Kjoint, SimError> {
        let name = b.name.clone();
        b.property.validate().map_err(|source| SimError::Property {
            joint: name.clone(),
            source,
        })?;
        for (field, v) in [
            ("local_anchor1", b.local_anchor1),
            ("local_anchor2", b.local_anchor2),
        ] {
            if !v.is_finite() {
                return Err(SimError::InvalidArgument {
                    field: format!("joint `{name}`: {field}"),
                    value: format!("{v:?}"),
                    expected: "finite coordinates".into(),
                });
            }
        }
        for (field, r) in [("frame", b.frame1), ("frame2", b.frame2)] {
            if let Some(r) = r {
                if !r.is_finite() || (r.length() - 1.0).abs() > 1e-3 {
                    return Err(SimError::InvalidArgument {
                        field: format!("joint `{name}`: {field}"),
                        value: format!("{r:?}"),
                        expected: "a finite unit quaternion".into(),
                    });
                }
            }
        }
        let pose1 = body_pose(bodies, body1).ok_or(SimError::MissingBody {
            joint: name.clone(),
            which: 1,
        })?;
        let pose2 = body_pose(bodies, body2).ok_or(SimError::MissingBody {
            joint: name.clone(),
            which: 2,
        })?;
        if body1 == body2 {
            return Err(SimError::InvalidJoint {
                joint: name,
                reason: "body 1 and body 2 are the same body".into(),
            });
        }
        let a1 = from_vec3(b.local_anchor1);
        let a2 = from_vec3(b.local_anchor2);
        let p1 = pose1.point(&a1);
        let p2 = pose2.point(&a2);
        let f1: UnitQuaternion<f64> = match b.frame1 {
            Some(r) => from_quat(r),
            None => kinematics::frame_from_x(&(p2 - p1)),
        };
        let f2: UnitQuaternion<f64> = b.frame2.map(from_quat).unwrap_or(f1);
        let jt = b.property.joint_type;
        if jt.single_free_rotation() && b.frame2.is_some() {
            let c = (f1 * Vector3::x()).dot(&(f2 * Vector3::x()));
            if c < 1.0 - 1e-6 {
                return Err(SimError::InvalidJoint {
                    joint: name,
                    reason: format!(
                        "a {} joint allows an initial angle about x only: the x axes of frame \
                         (Skew1) and frame2 (Skew2) must be parallel (cos = {c:.6})",
                        jt.name()
                    ),
                });
            }
        }
        b.connector
            .validate(&b.property)
            .map_err(|source| SimError::Connector {
                joint: name.clone(),
                source,
            })?;
        let mut frames = JointFrames {
            local_anchor1: a1,
            local_anchor2: a2,
            local_frame1: pose1.rotation.inverse() * f1,
            local_frame2: pose2.rotation.inverse() * f2,
            delta0: Vector3::zeros(),
            // the flex joint's bending angle is the angle between the two axes (flex_joint.md):
            // the swing of a swing-twist split, the torsion its twist; only its classical mode
            // acts on the total rotation angle, the rotation vector's norm
            measure: if jt.single_free_rotation() || flex_bending(&b.connector) {
                RotationMeasure::TwistX
            } else if jt == crate::law::JointType::Universal {
                RotationMeasure::Cardan
            } else {
                RotationMeasure::RotationVector
            },
            // the planar-friction connector measures its translations as Abaqus's PLANAR
            // does, on body 1's plane at anchor 2 (kinematics, "Translation measure")
            translation: if matches!(b.connector, ConnectorLaw::PlanarFriction(_)) {
                TranslationMeasure::Body1Frame
            } else {
                TranslationMeasure::MidPoint
            },
        };
        let initial_length = (p2 - p1).norm();
        if !b.property.automatic_stiffness() {
            // KR = Kn·max(ScF, L0²) must be finite (validate() checked Kn·ScF)
            let l2 = initial_length * initial_length;
            let k = crate::law::stiffness::user_blocked_stiffness(&b.property, initial_length);
            if !k.rotational.is_finite() {
                return Err(SimError::Property {
                    joint: name,
                    source: crate::error::PropertyError::field(
                        "kn (Kn)",
                        b.property.kn,
                        format!(
                            "a value whose rotational stiffness KR = Kn·max(ScF, L0²) = Kn·{:e} \
                             is finite (L0 = {initial_length} m)",
                            b.property.resolved_scale_factor().max(l2)
                        ),
                    ),
                });
            }
        }
        let mut ms = MeasureState::default();
        let k0 = kinematics::measure(&frames, &pose1, &pose2, &mut ms);
        frames.delta0 = Vector3::new(k0.q[0], k0.q[1], k0.q[2]);
        Ok(Kjoint {
            name,
            property: b.property,
            body1,
            body2,
            frames,
            measure: MeasureState::default(),
            law: LawState::default(),
            blocked: None,
            initial_length,
            state: None,
            connector: Connector::new(b.connector),
            connector_events_reported: 0,
            active: true,
            warned: 0,
            booked_law: 0.0,
            predicted_stops: Default::default(),
        })
    }

    /// The state after the last substep (`None` before the first).
    pub fn state(&self) -> Option<&JointState> {
        self.state.as_ref()
    }

    /// Resolved blocked stiffness (`None` until the first step for automatic stiffness).
    pub fn blocked_stiffness(&self) -> Option<BlockedStiffness> {
        self.blocked
    }

    /// Distance between the anchors at creation, `L0` \[m\].
    pub fn initial_length(&self) -> f64 {
        self.initial_length
    }

    /// Energies accumulated so far.
    pub fn energy(&self) -> JointEnergy {
        self.law.energy
    }

    /// The connector law attached to the joint.
    pub fn connector_law(&self) -> &ConnectorLaw {
        &self.connector.law
    }

    /// Connector events so far (flex joint phase switches), oldest first.
    pub fn connector_events(&self) -> &[ConnectorEvent] {
        self.connector.events()
    }

    /// The DOF's value in the last state (m or rad).
    pub fn dof_value(&self, dof: Dof) -> Option<f64> {
        self.state.as_ref().map(|s| s.q[dof.index()])
    }
}
