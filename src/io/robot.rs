//! Robot descriptions and their insertion, shared by the URDF ([`crate::io::urdf`]) and MJCF
//! ([`crate::io::mjcf`]) readers.
//!
//! Like `rapier3d-urdf`, reading a robot is two phases:
//!
//! 1. **Describe**: [`crate::io::urdf::UrdfRobot::from_file`] (or `from_str`, and the same on
//!    [`crate::io::mjcf::MjcfRobot`]) parses and validates the file and returns a
//!    [`RobotDescription`]: the rigid bodies and colliders of its links ([`RobotLink`]), the
//!    joints to create between them ([`RobotJoint`]: a KJOINT2 builder or a rapier joint),
//!    the visual meshes and the notices. No world is touched.
//! 2. **Insert**: [`RobotDescription::insert`] puts the bodies and colliders into the caller's
//!    [`PhysicsWorld`], the KJOINT2 joints into its [`KjointSet`] and the rapier joints into
//!    `world.impulse_joints`, and returns where they went ([`UrdfRobotHandles`]).
//!
//! This file also holds what the phases share: `read_robot_file` (a description file's
//! text, within the input size cap).

use crate::dynamics::{KjointHandle, KjointSet};
use crate::io::urdf::{UrdfError, UrdfOptions};
use crate::io::visual::{LinkMesh, VisualMesh};
use crate::rapier::dynamics::{GenericJoint, ImpulseJointHandle, RigidBody, RigidBodyHandle};
use crate::rapier::geometry::{Collider, ColliderHandle};
use crate::rapier::math::{Pose, Real, Rotation, Vector};
use crate::rapier::pipeline::PhysicsWorld;
use crate::KjointDescription;
use std::collections::BTreeMap;
use std::marker::PhantomData;
use std::path::Path;

/// The format a [`RobotDescription`] was read from: URDF ([`crate::io::urdf::UrdfRobot`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UrdfFormat {}

/// The format a [`RobotDescription`] was read from: MJCF ([`crate::io::mjcf::MjcfRobot`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MjcfFormat {}

/// A description file format the crate reads: [`UrdfFormat`] or [`MjcfFormat`] (sealed).
pub trait RobotFormat: sealed::Sealed + Sized {
    /// Describes the text `text` of a file of this format; `file` names it in errors,
    /// relative files (meshes, MJCF `<include>`) are taken from `base`.
    #[doc(hidden)]
    fn describe(
        text: &str,
        file: &str,
        base: &Path,
        options: &UrdfOptions,
    ) -> Result<RobotDescription<Self>, UrdfError>;
}

mod sealed {
    /// Only the crate's formats are [`super::RobotFormat`]s.
    pub trait Sealed {}
    impl Sealed for super::UrdfFormat {}
    impl Sealed for super::MjcfFormat {}
}

impl<Format: RobotFormat> RobotDescription<Format> {
    /// Reads and describes the file `path` (within [`crate::io::MAX_INPUT_BYTES`]); relative
    /// files (meshes, MJCF `<include>`) are taken from its directory. See
    /// [`crate::io::urdf`] and [`crate::io::mjcf`] for what is read and how.
    pub fn from_file(path: impl AsRef<Path>, options: &UrdfOptions) -> Result<Self, UrdfError> {
        let (text, file, base) = read_robot_file(path.as_ref())?;
        Format::describe(&text, &file, base, options)
    }

    /// Describes the text `text`; `file` names it in errors (e.g. `<string>`), relative
    /// files (meshes, MJCF `<include>`) are taken from `base_dir`.
    pub fn from_str(
        text: &str,
        file: &str,
        base_dir: impl AsRef<Path>,
        options: &UrdfOptions,
    ) -> Result<Self, UrdfError> {
        Format::describe(text, file, base_dir.as_ref(), options)
    }
}

/// A robot read from a description file, not yet in any world: its links as rapier bodies
/// and colliders, and the joints to create between them (see the module docs). `Format`
/// ([`UrdfFormat`] or [`MjcfFormat`]) only tells which reader made it.
#[derive(Debug, Clone)]
pub struct RobotDescription<Format> {
    /// The file the robot was read from, as errors name it (`<string>` for text).
    pub file: String,
    /// The robot's name (URDF `<robot name>`, MJCF `<mujoco model>`).
    pub name: String,
    /// The links, in the order they are inserted; joints refer to them by index.
    pub links: Vec<RobotLink>,
    /// The joints, in the order they are inserted.
    pub joints: Vec<RobotJoint>,
    /// What was approximated or skipped while reading (meshes not found or unreadable,
    /// massless links, widened limits, ignored dynamics, removed links).
    pub notices: Vec<String>,
    /// The gravity the file gives \[m/s²\]: an MJCF model's `<option gravity>` (zero with
    /// `<flag gravity="disable"/>`); `None` where it gives none (URDF has none; an MJCF
    /// model without it runs in MuJoCo under [`crate::io::mjcf::MUJOCO_GRAVITY`]). Inserting
    /// the robot leaves the world's gravity alone (a world may hold several robots and
    /// bodies): set `world.gravity` from it. A robot file run as a scene of its own runs
    /// under it ([`crate::scene::robot_scene`]); a scene file under its own `gravity`.
    pub gravity: Option<[f64; 3]>,
    /// The links fused into another link's body through fixed joints
    /// ([`UrdfOptions::fuse_fixed_joints`]): no longer in [`Self::links`] nor their joints in
    /// [`Self::joints`].
    pub fused: Vec<FusedLink>,
    /// Pairs of links, by name (a fused link's name finds the body it is part of), whose
    /// colliders do not touch each other though the robot's links collide: with
    /// [`UrdfOptions::self_collisions`] (without it no link touches another), an MJCF
    /// `<contact><exclude>`, or two MJCF bodies none of whose geoms collide by MuJoCo's
    /// `contype`/`conaffinity` rule; either way for an MJCF model's environment (its world
    /// and static bodies, which touch the links: [`crate::io::mjcf`], "Mapping") and a link. Inserted as rapier joints that only leave the pair's contacts out
    /// ([`crate::is_contact_filter`]), as [`crate::KjointBuilder::contacts_enabled`] does for a
    /// joint's own bodies; a name that finds no link is a notice of the inserted robot.
    pub contact_excludes: Vec<[String; 2]>,
    pub(crate) format: PhantomData<Format>,
}

/// One link of a [`RobotDescription`]: a rigid body with its colliders.
#[derive(Debug, Clone)]
pub struct RobotLink {
    /// The link's (MJCF: body's) name.
    pub name: String,
    /// Its rigid body, at its pose in the robot's loaded configuration.
    pub body: RigidBody,
    /// Its colliders, positioned relative to the body.
    pub colliders: Vec<Collider>,
    /// Its `<visual>` meshes, in the body frame (URDF only; drawing, never simulated).
    pub visual_meshes: Vec<LinkMesh>,
    /// A body that is not a link of the file (the spacer bodies between MJCF joints in
    /// series): inserted, but not listed by name in [`UrdfRobotHandles`].
    pub spacer: bool,
}

/// A link fused into another link's body through a fixed joint
/// ([`UrdfOptions::fuse_fixed_joints`], [`crate::io::urdf`] "Fixed joints").
#[derive(Debug, Clone, PartialEq)]
pub struct FusedLink {
    /// The names of the fixed joint (merged names too, as [`RobotJoint::names`]).
    pub joints: Vec<String>,
    /// The fused link's name.
    pub link: String,
    /// Index in [`RobotDescription::links`] of the link whose body it is part of.
    pub into: usize,
    /// The fused link's frame in that body's frame.
    pub pose: Pose,
    /// Its colliders: these indices of that link's [`RobotLink::colliders`].
    pub colliders: std::ops::Range<usize>,
}

/// Where a fixed joint went when its child link was fused ([`UrdfRobotHandles::fused_joints`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FusedJoint {
    /// The child link that was fused.
    pub link: String,
    /// The link whose body it is part of (the end of a chain of fused joints).
    pub into: String,
    /// That body.
    pub body: RigidBodyHandle,
    /// The fused link's frame in the body's frame (a point `p` of the link is `pose * p` on
    /// the body).
    pub pose: Pose,
}

/// The joint a [`RobotJoint`] creates.
#[derive(Debug, Clone)]
pub enum RobotJointKind {
    /// A KJOINT2 joint, inserted into the [`KjointSet`].
    Kjoint(Box<KjointDescription>),
    /// A rapier impulse joint, inserted into the world's `impulse_joints` (URDF joints with
    /// `engine = "rapier"`).
    Rapier(Box<GenericJoint>),
}

/// One joint of a [`RobotDescription`], between two of its links.
#[derive(Debug, Clone)]
pub struct RobotJoint {
    /// The names the joint answers to in [`UrdfRobotHandles`]: its own first, then those of
    /// the URDF joints merged into it when empty links were removed.
    pub names: Vec<String>,
    /// Index in [`RobotDescription::links`] of the first (parent) link.
    pub link1: usize,
    /// Index in [`RobotDescription::links`] of the second (child) link.
    pub link2: usize,
    /// What is created.
    pub kind: RobotJointKind,
    /// The joint's position at insertion in its file's convention \[rad or m\] (URDF: the
    /// [`UrdfOptions::initial_positions`] entry or 0; MJCF: that entry or the joint's
    /// `ref`), from which a KJOINT2 joint measures its axis DOF
    /// ([`UrdfRobotHandles::joint_position`]). 0 for joints without one axis.
    pub initial_position: f64,
}

/// An inserted robot: where its links and joints went ([`RobotDescription::insert`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct UrdfRobotHandles {
    /// The URDF `<robot name>` (MJCF: the model's name).
    pub name: String,
    /// Link name → rigid body (links removed as empty have no entry).
    pub links: BTreeMap<String, RigidBodyHandle>,
    /// Link name → its colliders.
    pub colliders: BTreeMap<String, Vec<ColliderHandle>>,
    /// URDF joint name → KJOINT2 joint. Joints merged by the removal of an empty link map to
    /// the joint they were merged into; the KJOINT2 joint is named after the URDF joint whose
    /// type and axis it carries.
    pub joints: BTreeMap<String, KjointHandle>,
    /// Fixed joint name → where it went, for the fixed joints whose child link was fused into
    /// its parent's body ([`UrdfOptions::fuse_fixed_joints`]): they have no entry in
    /// [`Self::joints`]; their links map to the body they are part of in [`Self::links`].
    pub fused_joints: BTreeMap<String, FusedJoint>,
    /// URDF joint name → rapier impulse joint, for the joints built by rapier
    /// ([`crate::io::urdf::JointOverride::engine`]); merged names as in [`Self::joints`].
    pub rapier_joints: BTreeMap<String, ImpulseJointHandle>,
    /// The `<visual>` meshes that were found and read (with
    /// [`crate::io::urdf::UrdfOptions::visual_meshes`]), on their bodies.
    pub visual_meshes: Vec<VisualMesh>,
    /// What was approximated or skipped (meshes not found or unreadable, massless links,
    /// widened limits, ignored dynamics, removed links).
    pub notices: Vec<String>,
    /// Joint name → its position at insertion \[rad or m\] ([`RobotJoint::initial_position`]),
    /// for the KJOINT2 joints of one axis (revolute, continuous, prismatic; MJCF hinge and
    /// slide) whose position there is not 0: the KJOINT2 joint measures its DOF from it.
    pub initial_positions: BTreeMap<String, f64>,
}

impl UrdfRobotHandles {
    /// The position `q` of the joint `name` as its file counts it \[rad or m\]: the value
    /// of the KJOINT2 joint's axis DOF ([`crate::Kjoint::dof_value`], measured from its pose
    /// at insertion) plus its position there ([`Self::initial_positions`],
    /// [`UrdfOptions::initial_positions`]). `None` for a name that is not a KJOINT2 joint of
    /// one axis of this robot, or before the first step.
    ///
    /// ```no_run
    /// # use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
    /// # use rapier_kjoint::rapier::pipeline::PhysicsWorld;
    /// # use rapier_kjoint::KjointSet;
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// let mut options = UrdfOptions::default();
    /// options.initial_positions.insert("panda_joint4".into(), -2.356);
    /// let robot = UrdfRobot::from_file("panda.urdf", &options)?;
    /// let (mut world, mut joints) = (PhysicsWorld::default(), KjointSet::new());
    /// let handles = robot.insert(&mut world, &mut joints)?;
    /// joints.step(&mut world, 1.0 / 60.0)?;
    /// let q4 = handles.joint_position(&joints, "panda_joint4"); // ≈ −2.356, not ≈ 0
    /// # let _ = q4; Ok(()) }
    /// ```
    pub fn joint_position(&self, joints: &KjointSet, name: &str) -> Option<f64> {
        let joint = joints.get(*self.joints.get(name)?)?;
        let dof = crate::io::urdf::axis_dof(joint.property().joint_type)?;
        let q0 = self.initial_positions.get(name).copied().unwrap_or(0.0);
        Some(q0 + joint.dof_value(dof)?)
    }

    /// Moves the targets of the motor of the KJOINT2 joint `name` (given by its override's
    /// `motor`, [`crate::io::urdf::JointOverride::motor`], or by
    /// [`KjointSet::set_motor`]): `target` a position `q` as the file counts it [rad or m]
    /// (the joint's `q − q0` is driven to `target − q0`, as [`Self::joint_position`]
    /// reads), `target_vel` its rate; its stiffness, damping and cap kept. Through
    /// [`KjointSet::set_motor`]: no analysis of the set, so it may be called at every frame
    /// or substep. `Ok(false)` where `name` is not a KJOINT2 joint of one axis of this
    /// robot with a motor; an error naming the joint for a non-finite target.
    pub fn set_motor_target(
        &self,
        joints: &mut KjointSet,
        name: &str,
        target: f64,
        target_vel: f64,
    ) -> Result<bool, crate::SimError> {
        let Some((h, dof, Some(motor))) = self.axis_motor(joints, name) else {
            return Ok(false);
        };
        let q0 = self.initial_positions.get(name).copied().unwrap_or(0.0);
        let moved = crate::KjointMotor {
            target_pos: target - q0,
            target_vel,
            ..motor
        };
        joints.set_motor(h, dof, Some(moved))
    }

    /// Sets the constant force (torque on a hinge) [N or N·m] of the motor of the KJOINT2
    /// joint `name` ([`crate::KjointMotor::force`]: an effort command, or the feed-forward
    /// term of a servo, as a gravity-compensating controller adds a model's torques); its
    /// targets, stiffness, damping and cap kept (an MJCF `<motor>` actuator's `forcerange`
    /// and `ctrlrange` are its cap), a motor of that force alone where the joint has none.
    /// Positive drives `q` up, as the file counts it. Through [`KjointSet::set_motor`]: no
    /// analysis of the set, so it may be called at every frame or substep. `Ok(false)` where
    /// `name` is not a KJOINT2 joint of one axis of this robot; an error naming the joint
    /// for a force that is not finite.
    pub fn set_motor_force(
        &self,
        joints: &mut KjointSet,
        name: &str,
        force: f64,
    ) -> Result<bool, crate::SimError> {
        let Some((h, dof, motor)) = self.axis_motor(joints, name) else {
            return Ok(false);
        };
        let motor = motor.unwrap_or_default().with_force(force);
        joints.set_motor(h, dof, Some(motor))
    }

    /// The KJOINT2 joint `name` of this robot if it has one axis (revolute, continuous,
    /// prismatic): its handle, its axis DOF and its motor, if any.
    fn axis_motor(
        &self,
        joints: &KjointSet,
        name: &str,
    ) -> Option<(
        crate::KjointHandle,
        crate::law::Dof,
        Option<crate::KjointMotor>,
    )> {
        let h = *self.joints.get(name)?;
        let joint = joints.get(h)?;
        let dof = crate::io::urdf::axis_dof(joint.property().joint_type)?;
        Some((h, dof, joint.motor(dof).copied()))
    }

    /// Body handle → link name (for outputs); a body with links fused into it is named after
    /// the link it was (not a fused one).
    pub fn body_names(&self) -> std::collections::HashMap<RigidBodyHandle, String> {
        let fused: std::collections::HashSet<&str> = self
            .fused_joints
            .values()
            .map(|f| f.link.as_str())
            .collect();
        self.links
            .iter()
            .filter(|(n, _)| !fused.contains(n.as_str()))
            .map(|(n, h)| (*h, n.clone()))
            .collect()
    }

    /// Whether the link `name` was fused into another link's body.
    pub fn is_fused_link(&self, name: &str) -> bool {
        self.fused_joints.values().any(|f| f.link == name)
    }
}

/// What joins a robot's name to the names of its links and joints
/// ([`RobotDescription::prefix_names`]): `left/elbow`, as ROS namespaces its frames. The
/// outputs that make file or entity names of joints map it (CSV histories `left_elbow.csv`,
/// pictures, rerun entities), as any character but `A-Za-z0-9_-.`.
pub const NAME_SEPARATOR: char = '/';

/// `body` moved by `pose` (the robot's [`UrdfOptions::base_pose`]): its pose and its
/// velocities, which the loaders leave at zero, turned with it.
pub(crate) fn place_body(body: &mut RigidBody, pose: &Pose) {
    if *pose == Pose::IDENTITY {
        return;
    }
    let placed = *pose * *body.position();
    let (v, w) = (pose.rotation * body.linvel(), pose.rotation * body.angvel());
    body.set_position(placed, false);
    body.set_linvel(v, false);
    body.set_angvel(w, false);
}

impl<Format> RobotDescription<Format> {
    /// Puts `prefix` and [`NAME_SEPARATOR`] before the name of every link (spacers and a
    /// `world` link too) and joint (merged names too, and the KJOINT2 joint's own name, which
    /// the outputs show): `elbow` becomes `left/elbow`. For two copies of one robot in a
    /// world, whose names would clash; do it after reading (the options' per-joint
    /// overrides name the file's joints) and before inserting.
    pub fn prefix_names(&mut self, prefix: &str) {
        let named = |n: &str| format!("{prefix}{NAME_SEPARATOR}{n}");
        for link in &mut self.links {
            link.name = named(&link.name);
        }
        for joint in &mut self.joints {
            for n in &mut joint.names {
                *n = named(n);
            }
            if let RobotJointKind::Kjoint(k) = &mut joint.kind {
                k.name = named(&k.name);
            }
        }
        for f in &mut self.fused {
            f.link = named(&f.link);
            for n in &mut f.joints {
                *n = named(n);
            }
        }
    }

    /// A description read from `file`, without links, joints or notices yet.
    pub(crate) fn new(file: &str, name: String) -> Self {
        RobotDescription {
            file: file.to_string(),
            name,
            links: Vec::new(),
            joints: Vec::new(),
            notices: Vec::new(),
            fused: Vec::new(),
            contact_excludes: Vec::new(),
            gravity: None,
            format: PhantomData,
        }
    }

    /// Inserts the robot: its bodies and colliders into `world`, its KJOINT2 joints into
    /// `joints`, its rapier joints into `world.impulse_joints` (woken up), and returns their
    /// handles with the description's notices and visual meshes. Fails when a joint names a
    /// link the description does not have or a KJOINT2 joint cannot be built (the error
    /// names the file and the joint); what was inserted before stays in the world.
    pub fn insert(
        self,
        world: &mut PhysicsWorld,
        joints: &mut KjointSet,
    ) -> Result<UrdfRobotHandles, UrdfError> {
        let mut out = UrdfRobotHandles {
            name: self.name,
            notices: self.notices,
            ..Default::default()
        };
        let mut bodies = Vec::with_capacity(self.links.len());
        let mut link_names = Vec::with_capacity(self.links.len());
        let mut all_colliders = Vec::with_capacity(self.links.len());
        // The pairs of links whose contacts the description switches off (a joint's
        // contacts, a contact exclude). A floor shared with another copy is on that copy's
        // body: this copy's exclusions of the link that would carry it are carried over to
        // that body, else a cart on a slide to its world body (its contacts off with it)
        // touches the shared floor where it does not touch its own (a review, 2026-12-04).
        let mut off_pairs: Vec<[usize; 2]> = (self.joints.iter())
            .filter(|joint| match &joint.kind {
                RobotJointKind::Kjoint(d) => !d.contacts_enabled,
                RobotJointKind::Rapier(g) => !g.contacts_enabled,
            })
            .map(|joint| [joint.link1, joint.link2])
            .collect();
        let index_of = |name: &str| self.links.iter().position(|l| l.name == name);
        off_pairs.extend(
            (self.contact_excludes.iter()).filter_map(|[a, b]| Some([index_of(a)?, index_of(b)?])),
        );
        // (link, the body of the floor it shares)
        let mut shared_on: Vec<(usize, RigidBodyHandle)> = Vec::new();
        for (l, link) in self.links.into_iter().enumerate() {
            let excluding = off_pairs.iter().any(|pair| pair.contains(&l));
            let fixed = link.body.is_fixed();
            let pose = *link.body.position();
            let body = world.bodies.insert(link.body);
            let mut colliders: Vec<ColliderHandle> = Vec::with_capacity(link.colliders.len());
            for c in link.colliders {
                // a floor the world has already (another copy of the model): one floor
                let same = fixed.then(|| same_floor(world, &pose, &c)).flatten();
                // (a floor without a body takes no exclusion: not shared by a link that has
                // some)
                let parent = same.map(|h| world.colliders[h].parent());
                if let (Some(same), Some(parent)) =
                    (same, parent.filter(|p| p.is_some() || !excluding))
                {
                    if let Some(p) = parent {
                        shared_on.push((l, p));
                    }
                    out.notices.push(format!(
                        "link `{}`: its floor (a half-space) is the one collider {:?} already \
                         puts in the world (the same plane, friction, restitution and \
                         groups): not inserted again, so that copies of the model stand on \
                         one floor (it stays on the body that carries it: removing that \
                         body removes it; the link's contact exclusions are carried over to \
                         it)",
                        link.name,
                        same.into_raw_parts()
                    ));
                    continue;
                }
                colliders.push(
                    world
                        .colliders
                        .insert_with_parent(c, body, &mut world.bodies),
                );
            }
            // the mass properties rapier would give the body from its colliders at its first
            // step, given now: a program reads the robot's masses before stepping it
            // (gravity compensation; a URDF robot read 0 kg until then, an MJCF one its
            // mass: a robotics user's trial, 2026-12-05), and the MJCF reader measured the
            // loads from them
            if let Some(rb) = world.bodies.get_mut(body) {
                rb.recompute_mass_properties_from_colliders(&world.colliders);
            }
            let meshes = link.visual_meshes.into_iter();
            out.visual_meshes
                .extend(meshes.map(|m| VisualMesh::on_body(&link.name, body, m)));
            if !link.spacer {
                out.links.insert(link.name.clone(), body);
                out.colliders.insert(link.name.clone(), colliders.clone());
            }
            bodies.push(body);
            link_names.push(link.name);
            all_colliders.push(colliders);
        }
        // the exclusions of the links that share a floor, carried over to its body
        let mut filtered = std::collections::HashSet::new();
        for (l, floor_body) in shared_on {
            for pair in off_pairs.iter().filter(|pair| pair.contains(&l)) {
                let other = if pair[0] == l { pair[1] } else { pair[0] };
                let Some(&ob) = bodies.get(other) else {
                    continue;
                };
                if ob != floor_body && filtered.insert((ob, floor_body)) {
                    let filter = crate::dynamics::contact_filter_joint();
                    world.impulse_joints.insert(ob, floor_body, filter, true);
                }
            }
        }
        for f in self.fused {
            let (Some(&body), Some(into)) = (bodies.get(f.into), link_names.get(f.into)) else {
                continue;
            };
            let cols = all_colliders[f.into].get(f.colliders.clone());
            // the fused link's own colliders, now on the body
            if let Some(into_list) = out.colliders.get_mut(into) {
                into_list.retain(|c| !cols.is_some_and(|cs| cs.contains(c)));
            }
            out.colliders
                .insert(f.link.clone(), cols.map(<[_]>::to_vec).unwrap_or_default());
            out.links.insert(f.link.clone(), body);
            for name in f.joints {
                out.fused_joints.insert(
                    name,
                    FusedJoint {
                        link: f.link.clone(),
                        into: into.clone(),
                        body,
                        pose: f.pose,
                    },
                );
            }
        }
        for joint in self.joints {
            let name = joint.names.first().cloned().unwrap_or_default();
            let body = |field: &str, link: usize| {
                bodies.get(link).copied().ok_or_else(|| UrdfError::Field {
                    file: self.file.clone(),
                    element: format!("joint `{name}`"),
                    field: field.to_string(),
                    value: link.to_string(),
                    expected: format!(
                        "the index of a link of the description (< {})",
                        bodies.len()
                    ),
                })
            };
            let (b1, b2) = (body("link1", joint.link1)?, body("link2", joint.link2)?);
            match joint.kind {
                RobotJointKind::Kjoint(description) => {
                    let one_axis = crate::io::urdf::axis_dof(description.property.joint_type);
                    if joint.initial_position != 0.0 && one_axis.is_some() {
                        out.initial_positions.extend(
                            (joint.names.iter()).map(|n| (n.clone(), joint.initial_position)),
                        );
                    }
                    let h =
                        joints
                            .insert(*description, b1, b2, &world.bodies)
                            .map_err(|source| UrdfError::Joint {
                                file: self.file.clone(),
                                joint: name,
                                source: Box::new(source),
                            })?;
                    out.joints.extend(joint.names.into_iter().map(|n| (n, h)));
                }
                RobotJointKind::Rapier(generic) => {
                    let h = world.impulse_joints.insert(b1, b2, *generic, true);
                    out.rapier_joints
                        .extend(joint.names.into_iter().map(|n| (n, h)));
                }
            }
        }
        for [a, b] in self.contact_excludes {
            match (out.links.get(&a), out.links.get(&b)) {
                (Some(&ba), Some(&bb)) if ba != bb => {
                    let filter = crate::dynamics::contact_filter_joint();
                    world.impulse_joints.insert(ba, bb, filter, true);
                }
                // (one body: its colliders never touch each other)
                (Some(_), Some(_)) => {}
                _ => out.notices.push(format!(
                    "contact exclude of `{a}` and `{b}` not applied: no link of that name"
                )),
            }
        }
        Ok(out)
    }
}

/// A joint of a description moved from its file's zero pose to an initial position
/// ([`UrdfOptions::initial_positions`]).
pub(crate) struct InitialMotion {
    /// Index of the parent link in the description's links.
    pub link1: usize,
    /// Index of the child link.
    pub link2: usize,
    /// The joint frame on the parent link, in its body frame (x: the joint axis).
    pub frame1: Pose,
    /// The joint slides along its axis (prismatic, slide) rather than turns about it.
    pub slide: bool,
    /// How far from the zero pose \[rad or m\].
    pub by: f64,
}

/// The child's joint frame `frame2` (in its body frame) moved back by `slide` along its x
/// axis: where the point of the child that stood at the parent's joint frame in the zero pose
/// is, once the joint has slid by `slide` to its initial position. A prismatic KJOINT2
/// joint anchored there starts with its anchors together, as at the zero pose (a joint whose
/// anchors start apart keeps them apart at rest, kjoint2.md §3 `δ0`).
pub(crate) fn at_zero_offset(frame2: &Pose, slide: f64) -> Pose {
    let back = frame2.rotation * (Vector::X * -(slide as Real));
    Pose::from_parts(frame2.translation + back, frame2.rotation)
}

/// Places `links` at their joints' initial positions, as forward kinematics does: for each
/// motion, its child link and every link beyond it (`edges`: parent → child, every joint of
/// the description) are moved by
///
/// ```text
/// T = X·M·X⁻¹,   X = P_parent·F_1 (the joint frame in the world),   M = R_x(by) or a slide by x·by
/// ```
///
/// Each `X` is taken from the parent's pose at the time, so the order of the motions does not
/// matter: a motion of an ancestor applied after carries this one's links with it
/// (`T_a·T_b` either way). The bodies' velocities are the loaders' zeros.
pub(crate) fn move_to_initial_positions(
    links: &mut [RobotLink],
    edges: &[(usize, usize)],
    motions: &[InitialMotion],
) {
    let n = links.len();
    let mut children = vec![Vec::new(); n];
    for &(a, b) in edges.iter().filter(|(a, b)| *a < n && *b < n) {
        children[a].push(b);
    }
    for m in motions.iter().filter(|m| m.by != 0.0) {
        let Some(parent) = links.get(m.link1) else {
            continue;
        };
        let x = *parent.body.position() * m.frame1;
        let local = if m.slide {
            Pose::from_translation(Vector::X * m.by as Real)
        } else {
            Pose::from_rotation(Rotation::from_rotation_x(m.by as Real))
        };
        let t = x * local * x.inverse();
        let mut seen = vec![false; n];
        let mut stack = vec![m.link2];
        while let Some(l) = stack.pop() {
            if l >= n || std::mem::replace(&mut seen[l], true) {
                continue;
            }
            let moved = t * *links[l].body.position();
            links[l].body.set_position(moved, false);
            stack.extend_from_slice(&children[l]);
        }
    }
}

/// A robot description file's text (within [`crate::io::MAX_INPUT_BYTES`]), its name for
/// errors, and its directory (relative files are taken from there); URDF and MJCF alike.
pub(crate) fn read_robot_file(path: &Path) -> Result<(String, String, &Path), UrdfError> {
    let text = crate::io::read_input_text(path).map_err(|e| UrdfError::Read {
        file: path.to_path_buf(),
        source: e.kind,
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    Ok((text, path.display().to_string(), base))
}

/// The half-space collider already in the world that `c` (a half-space on a fixed body at
/// `pose`) would duplicate: on a fixed body (or none), enabled, the same plane in the world
/// (normals within 1e-6, offsets within 1e-6 of 1 + the offset), friction, restitution,
/// their combine rules, collision and solver groups, sensor or not. A model inserted N
/// times (a reinforcement-learning batch) brought N floors, each touching every copy: 16
/// ants made 768 contact pairs with their floors where one floor makes 48, and rapier's
/// time grew as N² (a user trial, 2026-12-04). `None` for any other shape.
fn same_floor(world: &PhysicsWorld, pose: &Pose, c: &Collider) -> Option<ColliderHandle> {
    let h = c.shape().as_halfspace()?;
    // (a collider's `position` before its insertion is its pose on its body)
    let plane = |at: &Pose, n: Vector| {
        let n = at.rotation * n;
        (n, n.dot(at.translation) as f64)
    };
    let (n, d) = plane(&(*pose * *c.position()), h.normal);
    world.colliders.iter().find_map(|(handle, o)| {
        let oh = o.shape().as_halfspace()?;
        let fixed = o
            .parent()
            .is_none_or(|p| world.bodies.get(p).is_some_and(|b| b.is_fixed()));
        let (on, od) = plane(o.position(), oh.normal);
        let same = fixed
            && o.is_enabled()
            && on.dot(n) as f64 > 1.0 - 1e-6
            && (od - d).abs() <= 1e-6 * (1.0 + d.abs())
            && o.friction() == c.friction()
            && o.restitution() == c.restitution()
            && o.friction_combine_rule() == c.friction_combine_rule()
            && o.restitution_combine_rule() == c.restitution_combine_rule()
            && o.collision_groups() == c.collision_groups()
            && o.solver_groups() == c.solver_groups()
            && o.is_sensor() == c.is_sensor();
        same.then_some(handle)
    })
}
