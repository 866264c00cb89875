//! [`UrdfOptions`]: how a URDF (or MJCF) robot becomes rapier bodies and KJOINT2 joints, with
//! its per-joint overrides ([`JointOverride`], [`JointEngine`], [`RapierMotor`]) and what a
//! collision mesh becomes ([`CollisionMeshes`]). All are deserializable, so that a scene file
//! can carry them.

use crate::law::KjointProperty;
use crate::rapier::math::Pose;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// How a URDF robot becomes rapier bodies and KJOINT2 joints. Deserializable (all fields
/// optional) so that a scene file can carry it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct UrdfOptions {
    /// `Kn` [N/m] of every joint: 0 = automatic, by the implicit rule from the load each
    /// joint carries and the substep ([`crate::law::stiffness`]).
    pub kn: f64,
    /// `Cr` of every joint in [0, 1] (0 = the default 0.05).
    pub critical_damping: f64,
    /// Substep `h` \[s\] used for the friction stiffness rule `Kf = κ_eff·m_eff/h²`
    /// ([`super::friction_stiffness`]); use the substep the robot will run at. 0 (default) =
    /// automatic: the scene's substep in a scene file, 1/240 s (60 Hz frames × 4 substeps)
    /// when reading with [`super::UrdfRobot::from_file`] or [`super::UrdfRobot::from_str`].
    pub substep: f64,
    /// Make the root link(s) fixed (default `true`).
    pub fixed_base: bool,
    /// Let the robot's colliders collide with each other (default `false`), except two links
    /// joined by a joint: they overlap at it in most descriptions
    /// ([`crate::KjointBuilder::contacts_enabled`]`(false)` on the KJOINT2 joints, as
    /// `rapier3d-urdf` leaves its own joints' links apart and MuJoCo a body and its parent).
    pub self_collisions: bool,
    /// Mass \[kg\] given to dynamic links that have none in the URDF (default 0.01 kg, with the
    /// inertia of a 5 cm ball).
    pub min_link_mass: f64,
    /// Per-joint overrides, by URDF joint name.
    pub joints: BTreeMap<String, JointOverride>,
    /// Directories searched for the packages of `package://PKG/…` mesh paths, as
    /// `DIR/PKG/…` (like `ROS_PACKAGE_PATH`). Whatever they hold, the ancestors of the URDF
    /// file's directory are searched too: an ancestor named `PKG`, or one with a `PKG`
    /// subdirectory. Default none.
    pub package_dirs: Vec<PathBuf>,
    /// What a `<collision>` mesh becomes (default `"convex_hull"`).
    pub collision_meshes: CollisionMeshes,
    /// Read the `<visual>` meshes (into [`super::UrdfRobotHandles::visual_meshes`]) for
    /// drawing (default `true`). They are never simulated.
    pub visual_meshes: bool,
    /// Let the links sleep (default `false`: they never do): a robot at rest for rapier's
    /// `time_until_sleep` is then put to sleep as a whole with its joints, and woken as a
    /// whole (README, "Sleeping"). For a robot in a game; an analysis keeps it off.
    pub can_sleep: bool,
    /// Fuse the links joined by a fixed joint (URDF `fixed`, an MJCF body without a joint)
    /// into one rigid body (default `true`), as MuJoCo does for URDF (`fusestatic`) and
    /// PyBullet and Isaac offer ("merge fixed links"); see [`crate::io::urdf`],
    /// "Fixed joints". A fixed joint named in [`Self::joints`] is kept as a KJOINT2 (or
    /// rapier) joint; `false` keeps them all. A KJOINT2 fixed joint is a penalty joint: a
    /// light link on it (go1's 60 g feet) is turned by contact friction by `τ·h²/I` per
    /// substep, 0.3 rad at 240 Hz.
    pub fuse_fixed_joints: bool,
    /// Initial joint positions, by joint name (URDF joint, MJCF joint) [rad or m, SI]: the
    /// robot is described and inserted with these joints at these positions instead of its
    /// file's zero pose (URDF `q = 0`, MJCF `qpos0`): a Panda at its ready pose, whose
    /// `joint4` range \[−3.07, −0.07\] excludes 0. Revolute, continuous and prismatic joints
    /// (MJCF hinge and slide) only; a position must lie within the joint's limits (an MJCF
    /// position is the joint's value, `ref` included). Every link beyond the joint turns
    /// about its axis (slides along it), as forward kinematics places it. A KJOINT2 joint
    /// measures its DOF from its pose at insertion (kjoint2.md §3), so its
    /// [`crate::Kjoint::dof_value`] reads `q − q0` and its stops stand at `lower − q0`,
    /// `upper − q0`; [`super::UrdfRobotHandles::joint_position`] gives `q`. A joint built by
    /// rapier (`engine = "rapier"`) reads `q` itself. Default: none.
    pub initial_positions: BTreeMap<String, f64>,
    /// An MJCF model's keyframe (`<keyframe><key name="home" qpos="…">`) whose `qpos`
    /// starts the robot: each named hinge and slide at its value there, as
    /// [`Self::initial_positions`] would (whose entries win). A free joint's pose and a ball
    /// joint's orientation in it are not applied (notices: the robot stands at its
    /// [`Self::base_pose`]). Its `ctrl` is the actuators' control at the start: a servo's
    /// target where the keyframe holds the robot (without it, the control starts at 0 and
    /// the servos drive the robot away from the keyframe's pose). MJCF only (a URDF robot
    /// with one is refused). Default: none.
    pub keyframe: Option<String>,
    /// Where the robot stands in the world: the pose of the file's own frame (a URDF's
    /// root link, an MJCF model's `<worldbody>`) in world coordinates (default identity:
    /// the robot where its file puts it). Every link (and its colliders), a fixed base and
    /// the world frames of the KJOINT2 joints are placed with it, as `rapier3d-urdf`'s
    /// `UrdfLoaderOptions::shift` places its bodies; the loads the friction stiffnesses are
    /// sized from are measured where the robot stands (the f32 noise bound of the implicit
    /// rule grows with the distance from the origin, [`crate::law::stiffness`]). Its
    /// translation must be finite and within ±1e12 m, its rotation a unit quaternion. Not
    /// read from a file (a scene gives it as a robot's `position` and `rotation`,
    /// [`crate::scene::schema::RobotSpec`]).
    #[serde(skip)]
    pub base_pose: Pose,
}

impl UrdfOptions {
    /// The substep of the friction stiffness rule \[s\]: [`Self::substep`], or 1/240 s when
    /// it is 0.
    pub fn resolved_substep(&self) -> f64 {
        if self.substep > 0.0 {
            self.substep
        } else {
            DEFAULT_SUBSTEP
        }
    }
}

/// The substep assumed by [`UrdfOptions::resolved_substep`] when none is given \[s\].
pub const DEFAULT_SUBSTEP: f64 = 1.0 / 240.0;

/// What a URDF `<collision>` mesh becomes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CollisionMeshes {
    /// Its convex hull (default): cheap, and collides with everything, other links too.
    #[default]
    ConvexHull,
    /// The triangle mesh as is (rapier does not collide two triangle meshes).
    TriMesh,
    /// No collider (an inertia-only link when all its collision shapes are meshes).
    Ignore,
}

impl CollisionMeshes {
    /// The mesh converter of the description loaders (`ignore`: meshes are removed before).
    /// The loaders are built on rapier3d (f32) whatever the crate's precision.
    pub(crate) fn converter(self) -> rapier3d::geometry::MeshConverter {
        use rapier3d::geometry::MeshConverter;
        match self {
            CollisionMeshes::TriMesh => MeshConverter::TriMesh,
            _ => MeshConverter::ConvexHull,
        }
    }
}

impl Default for UrdfOptions {
    fn default() -> Self {
        UrdfOptions {
            kn: 0.0,
            critical_damping: 0.0,
            substep: 0.0,
            fixed_base: true,
            self_collisions: false,
            min_link_mass: 0.01,
            joints: BTreeMap::new(),
            package_dirs: Vec::new(),
            collision_meshes: CollisionMeshes::ConvexHull,
            visual_meshes: true,
            can_sleep: false,
            fuse_fixed_joints: true,
            initial_positions: BTreeMap::new(),
            keyframe: None,
            base_pose: Pose::IDENTITY,
        }
    }
}

/// Changes to one joint's property. `property` replaces the whole property built from the
/// URDF (its type must then be given; the frames still come from the URDF); the other fields
/// replace single values, applied after it, on the joint's axis DOF (rx for revolute,
/// continuous and planar joints, dx for prismatic ones).
///
/// Every number of an override (the single fields, `break`, `joint_friction`, a whole
/// `property`'s values and curve points, `motor`) must be finite and within ±1e12, as the
/// URDF attributes it replaces are: beyond that the error names the field
/// (``options.joints.`elbow`: invalid friction = 1e308``).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct JointOverride {
    /// A complete replacement property.
    pub property: Option<KjointProperty>,
    /// `Kn` [N/m] (0 = automatic).
    pub kn: Option<f64>,
    /// `Cr` in [0, 1].
    pub critical_damping: Option<f64>,
    /// Axis DOF: linear stiffness `K` [N/m or N·m/rad].
    pub stiffness: Option<f64>,
    /// Axis DOF: viscosity `C` [N·s/m or N·m·s/rad].
    pub viscosity: Option<f64>,
    /// Axis DOF: friction `FF` \[N\] or `FM` [N·m].
    pub friction: Option<f64>,
    /// Axis DOF: friction spring (and stop) stiffness `Kf` [N/m or N·m/rad].
    pub friction_stiffness: Option<f64>,
    /// Axis DOF: the inertia of a rotor geared to it [kg·m² or kg] (a motor's reflected
    /// inertia `I_rotor·n²`, MuJoCo's `armature`; [`crate::law::DofLaw::armature`]). URDF
    /// has no attribute for it.
    pub armature: Option<f64>,
    /// Load-dependent friction of a revolute, continuous or prismatic joint
    /// (docs/joint_friction.md): `joint_friction = { mu = 0.2, pin_radius = 0.01, length =
    /// 0.05 }`, bounded by `μ` times the joint's own radial reaction plus bending moment over
    /// `length`. It **replaces** the constant friction of the URDF's `<dynamics friction>` on
    /// that joint (the URDF's value is dropped); not together with `friction`.
    pub joint_friction: Option<crate::law::JointFriction>,
    /// Axis DOF: negative stop [m or rad] (≤ 0; 0 = none).
    pub stop_min: Option<f64>,
    /// Axis DOF: positive stop [m or rad] (≥ 0; 0 = none).
    pub stop_max: Option<f64>,
    /// Which engine builds the joint: `"kjoint2"` (default) or `"rapier"`, a rapier impulse
    /// joint (see the module docs, "Rapier joints"). A rapier joint takes none of
    /// the KJOINT2 fields above, only `motor`.
    pub engine: Option<JointEngine>,
    /// The motor of the joint's axis (a revolute, continuous or prismatic joint): rapier's
    /// on a rapier joint (`engine = "rapier"`), a [`crate::KjointMotor`] on a KJOINT2 joint
    /// (its target a `q` of the file, as here: the KJOINT2 joint's `q − q0` is driven to
    /// `target − q0`).
    pub motor: Option<RapierMotor>,
    /// When the KJOINT2 joint breaks (docs/breakable.md), SI: `break = { force = 2000.0 }`
    /// \[N, N·m, J\]; absent: never.
    #[serde(rename = "break")]
    pub break_criterion: Option<crate::law::BreakCriterion>,
}

impl std::fmt::Display for RapierMotor {
    /// As written in a scene: `{ target = 0, stiffness = 1000, damping = 10, max_force = 20 }`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{{ target = {}, stiffness = {}, damping = {}",
            self.target, self.stiffness, self.damping
        )?;
        if let Some(m) = self.max_force {
            write!(f, ", max_force = {m}")?;
        }
        write!(f, " }}")
    }
}

/// The engine that builds a URDF joint ([`JointOverride::engine`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointEngine {
    /// A KJOINT2 penalty joint in the [`crate::KjointSet`] (default).
    #[default]
    Kjoint,
    /// A rapier impulse joint in the world's `impulse_joints`, solved by rapier's own
    /// constraint solver with the contacts.
    Rapier,
}

/// The motor of a joint's axis: a force-based position motor, `F = stiffness·(target − q)
/// − damping·q̇`, bounded by `max_force`: rapier's (`MotorModel::ForceBased`) on a rapier
/// joint, a [`crate::KjointMotor`] on a KJOINT2 joint. Its target is set once here; a scene
/// changes it over time with `[[motors]]`, a program with
/// `ImpulseJoint::data.set_motor_position` or [`crate::KjointSet::set_motor`].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RapierMotor {
    /// Position target [m or rad] at the start (default 0, the URDF pose).
    pub target: f64,
    /// Stiffness [N/m or N·m/rad] (≥ 0).
    pub stiffness: f64,
    /// Damping [N·s/m or N·m·s/rad] (≥ 0; stiffness and damping not both 0).
    pub damping: f64,
    /// Largest force \[N\] or moment \[N·m\] the motor gives (> 0; default unbounded).
    pub max_force: Option<f64>,
}
