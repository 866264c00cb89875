//! URDF robots with KJOINT2 joints.
//!
//! [`load_urdf`] / [`load_urdf_str`] read a URDF description with `rapier3d-urdf` (links →
//! rigid bodies with the URDF inertia, `<collision>` primitives → colliders) and, instead of
//! rapier's joints, insert one KJOINT2 joint ([`Kjoint2Builder`] + [`Kjoint2Property`]) per
//! URDF joint into a [`KjointSet`], except the joints asked for as rapier impulse joints
//! ("Rapier joints" below). Nothing is stepped.
//!
//! # Mapping
//!
//! | URDF `type` | KJOINT2 type | free DOFs |
//! |---|---|---|
//! | `revolute`, `continuous` | [`JointType::Revolute`] (2) | rx |
//! | `prismatic` | [`JointType::Translational`] (6) | dx |
//! | `fixed` | [`JointType::Fixed`] (8) | – |
//! | `floating` | [`JointType::Free`] (9) | all |
//! | `planar` | [`JointType::Planar`] (4) | dy, dz, rx (x = plane normal) |
//! | `spherical` | [`JointType::Spherical`] (1) | rx, ry, rz |
//!
//! * **Frames.** The joint frame sits at the URDF joint origin; its local x is the URDF
//!   `<axis>` (the minimal rotation taking x to the axis, as rapier does), given to
//!   [`Kjoint2Builder::frame`] and [`Kjoint2Builder::frame2`] in world coordinates. The URDF
//!   places each child link at joint position 0, so the loaded configuration is the unloaded
//!   one (`q = 0`).
//! * **Limits.** `<limit lower upper>` of revolute \[rad\] and prismatic \[m\] joints become the
//!   stops `SA-`/`SA+` (`SD-`/`SD+`) of the free DOF; continuous joints have none. KJOINT2
//!   reads a stop of 0 as "no stop" and needs `SD- ≤ 0 ≤ SD+`, so a limit at exactly 0 becomes
//!   `∓1e-9`, an infinite limit means no stop on that side, `lower = upper = 0` (the URDF
//!   default when `<limit>` only carries effort/velocity) means no stops, and a limit range
//!   that excludes the initial position 0 is widened to include it (with a notice).
//! * **Dynamics.** `<dynamics damping friction>` of revolute, continuous and prismatic joints
//!   become the viscosity `C` [N·s/m, N·m·s/rad] and the friction `FF`/`FM` [N, N·m] of the
//!   free DOF. The friction needs a spring stiffness `Kf` that URDF does not give, and beyond
//!   a KJOINT2 stop that spring **is** the stop (kjoint2.md §4.2), so it must hold the limit
//!   like the blocked DOFs hold the joint. It gets the implicit rule of the blocked DOFs
//!   ([`crate::law::stiffness`]) for the load the joint's axis carries
//!   ([`friction_stiffness`]):
//!
//!   `Kf = κ_eff·m_eff/h²`, `κ_eff = min(16, η·a·h²/(ε·r))`, `h` = [`UrdfOptions::substep`],
//!
//!   with `m_eff` the mass (prismatic) or the moment of inertia about the joint axis through
//!   the joint origin (revolute, continuous) of the child link **and every link beyond it**,
//!   and `r` the joint origin's distance from the world origin plus the radius of gyration
//!   of those links. The friction spring then sticks within `FF/Kf` (micrometres), the stop it
//!   makes is beyond what the substep resolves (`ω·h ≥ 4`, held by the implicit update like a
//!   constraint), and the f32 noise of the measured angle stays below 1 % of the load. (The
//!   child link alone, or Radioss' budget `m/(α·h²)` used before, made the stop of a joint
//!   carrying a long arm soft: limits were overrun by tenths of a radian.) Dynamics on
//!   planar, floating and spherical joints are ignored (with a notice).
//! * **Stiffness.** Every joint gets `Kn` = [`UrdfOptions::kn`] (0, the default = automatic
//!   by the implicit rule: from the load each joint carries, [`crate::law::stiffness`]) and
//!   `Cr` = [`UrdfOptions::critical_damping`]; [`UrdfOptions::joints`] overrides single
//!   joints by URDF name. Without friction, a limit's stop has the blocked rotational (or
//!   translational) stiffness of its joint, so the same rule holds it.
//! * **Bodies.** Empty links (no inertial, visual or collision) are removed by
//!   `rapier3d-urdf` and the joints around them merged; a merged joint carries the name,
//!   type, axis, limits and dynamics of the URDF joint that moves (see
//!   [`UrdfRobot::joints`], which also lists the merged names). Root links are fixed when
//!   [`UrdfOptions::fixed_base`] is set (a root that is an empty `world` link with a fixed
//!   joint fixes its child in any case). A root link named `world` without mass is the
//!   fixed world (the ROS convention) whatever `fixed_base` says: when it is kept (it has a
//!   visual, or a moving joint to the base) it is a fixed body at the origin, and in a scene
//!   it is the scene's `world`. Dynamic links without mass get
//!   [`UrdfOptions::min_link_mass`] (with the inertia of a ball of radius [`BALL_RADIUS`]) so
//!   the automatic stiffness is defined. Bodies never sleep. The links must form a tree:
//!   joints that close a loop are refused ([`UrdfError::Loop`], naming them), since
//!   `rapier3d-urdf` would keep no root and the base would fall.
//! * **Inertia.** Diagonal terms and principal moments down to `−tol` are round-off (CAD
//!   exports write `-5e-20` for 0) and read as 0 with a notice, `tol` =
//!   [`INERTIA_ROUNDOFF`] × the largest inertia term of the link, at least
//!   [`INERTIA_ABS_ROUNDOFF`]; a more negative diagonal term is refused naming the link and
//!   the field. A dynamic link with mass and a zero principal moment (a point mass, a thin
//!   rod about its axis) would have its rotation about that axis locked by rapier (infinite
//!   inertia: a point-mass pendulum would hang in the air); so would a tensor that is not
//!   positive semi-definite (rapier reads its negative principal moments as 0; romeo and
//!   tiago of example-robot-data have such tensors, so they are not refused). Such a link
//!   gets the inertia of a solid ball of its mass and radius
//!   [`BALL_RADIUS`] (`0.4·m·r²`) about those axes, with a notice. That is what robotics
//!   users expect of a URDF point mass: it loads and swings, as in the other simulators,
//!   with an inertia small beside `m·d²` at any joint distance `d` of a few centimetres or
//!   more. Fixed roots are left as they are.
//! * **Geometry.** `<collision>` boxes, cylinders, capsules, spheres and meshes become
//!   colliders of density 0 (the URDF inertia is the mass); a mesh becomes its convex hull by
//!   default ([`UrdfOptions::collision_meshes`]: `convex_hull`, `tri_mesh` or `ignore`).
//!   Colliders of one robot do not collide with each other (adjacent links overlap in most
//!   descriptions) unless [`UrdfOptions::self_collisions`] is set; they do collide with
//!   everything else.
//! * **Meshes.** STL, COLLADA (`.dae`) and Wavefront (`.obj`) files. `package://PKG/path` is
//!   looked up in [`UrdfOptions::package_dirs`] (as `DIR/PKG/path`), then in the ancestors of
//!   the URDF file's directory (an ancestor named `PKG`, or one holding `PKG`); `file://`
//!   paths are absolute, others relative to the URDF file ([`resolve_mesh_path`]). A mesh
//!   that is not found, unreadable, degenerate or larger than the size cap of input files
//!   ([`crate::io::MAX_INPUT_BYTES`], which also holds for the URDF file) is skipped with a
//!   notice. `<visual>` meshes
//!   are read into [`UrdfRobot::visual_meshes`] (body-frame triangles, for drawing: the rerun
//!   logger shows them with [`crate::output`]'s `RerunLogger::with_urdf_robot`); they are
//!   never simulated. Materials and textures are not read; a `<texture>` without a
//!   `filename` (`<texture/>`, which urdf-rs refuses: icub and romeo of example-robot-data)
//!   is removed with a notice naming its line.
//!
//! * **Rapier joints.** A joint whose override says `engine = "rapier"`
//!   ([`JointOverride::engine`]) is not a KJOINT2 joint but a rapier impulse joint in
//!   `world.impulse_joints` ([`UrdfRobot::rapier_joints`]), solved by rapier with the
//!   contacts, inside the same substeps ([`crate::KjointSet::step`]): gripper fingers, whose
//!   grip is made of contacts. It is `rapier3d-urdf`'s own joint: frames at the URDF joint
//!   origin with the axis as x, on both links; the URDF `<limit>` of a revolute or prismatic
//!   joint as rapier limits on the axis (`lower = upper = 0` is no limit, as for KJOINT2; an
//!   infinite side is put [`FAR_LIMIT`] away, rapier's limits having two sides; a range
//!   that excludes 0 is kept, with a notice: rapier pulls the joint into it). Its
//!   `<dynamics>` are ignored (with a notice), and so are `kn`, `critical_damping` and the
//!   per-DOF fields of the override (refused). `motor = { target, stiffness, damping,
//!   max_force }` ([`RapierMotor`]) drives the axis of a revolute, continuous or prismatic
//!   joint with rapier's force-based position motor, `F = stiffness·(target − q) −
//!   damping·q̇` up to `max_force` (N/m, N·s/m, N; N·m/rad, N·m·s/rad, N·m about an axis);
//!   its target is changed during a run by the program (`ImpulseJoint::data`) or by a
//!   scene's `[[motors]]`. The automatic stiffness of the KJOINT2 joints counts the bodies
//!   linked to them by KJOINT2 joints only: a hand's wrist holds the hand, not the fingers
//!   hanging on rapier joints nor what they grip (it sags by `(m_hand + m_fingers +
//!   m_box)/m_hand` times more, a few micrometres).
//! * **Ignored**: `<limit effort velocity>`, `<mimic>` (with a notice), `<safety_controller>`,
//!   `<calibration>`, transmissions and simulator tags; `<visual>` boxes, cylinders and
//!   spheres (the rerun logger draws the colliders) and materials.
//!
//! Every error names the file, the link or joint and the field ([`UrdfError`]); NaN and
//! infinite values are refused (except infinite limits, read as "no stop"), and nothing
//! panics on user input.

use crate::dynamics::{from_quat, from_vec3, KjointHandle, KjointSet};
use crate::error::SimError;
use crate::io::loaded;
use crate::law::stiffness::implicit_kappa;
use crate::law::{Dof, DofLaw, JointType, Kjoint2Property};
use crate::rapier::dynamics::{
    GenericJoint, ImpulseJointHandle, JointAxesMask, JointAxis, MassProperties, MotorModel,
    RigidBodyHandle, RigidBodyType,
};
use crate::rapier::geometry::{ColliderHandle, Group, InteractionGroups, InteractionTestMode};
use crate::rapier::math::{Real, Vector};
use crate::rapier::pipeline::PhysicsWorld;
use crate::Kjoint2Builder;
use nalgebra::{Matrix3, Rotation3, Vector3};
use rapier3d_urdf::urdf_rs;
use rapier3d_urdf::{UrdfLoaderOptions, UrdfRobot as RapierUrdfRobot};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Limit values at exactly 0 are moved by this much [m or rad] (0 means "no stop").
pub const ZERO_LIMIT: f64 = 1e-9;

/// The name of the link that is the fixed world when it is a root without mass (ROS).
pub const WORLD_LINK: &str = "world";

/// Radius \[m\] of the solid ball whose inertia `0.4·m·r²` a link gets about the axes where
/// the URDF gives it none: every axis for a link without mass (given
/// [`UrdfOptions::min_link_mass`]), the zero principal axes for a link with mass.
pub const BALL_RADIUS: f64 = 0.05;

/// Relative round-off tolerance of inertia terms: a diagonal term or principal moment down
/// to `−INERTIA_ROUNDOFF × (the largest inertia term)` is round-off and read as 0.
pub const INERTIA_ROUNDOFF: f64 = 1e-9;

/// Absolute round-off tolerance of inertia terms \[kg·m²\], for links whose terms are all
/// tiny: far below any real part (a 1 g ball of 1 mm radius has 4e-10 kg·m²).
pub const INERTIA_ABS_ROUNDOFF: f64 = 1e-15;

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
    /// ([`friction_stiffness`]); use the substep the robot will run at. 0 (default) = automatic: the scene's substep in a
    /// scene file, 1/240 s (60 Hz frames × 4 substeps) when loading with [`load_urdf`].
    pub substep: f64,
    /// Make the root link(s) fixed (default `true`).
    pub fixed_base: bool,
    /// Let the robot's colliders collide with each other (default `false`).
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
    /// Load the `<visual>` meshes into [`UrdfRobot::visual_meshes`] for drawing (default
    /// `true`). They are never simulated.
    pub visual_meshes: bool,
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

/// A `<visual>` mesh of a link, for drawing (never simulated).
#[derive(Debug, Clone, PartialEq)]
pub struct VisualMesh {
    /// The link's name.
    pub link: String,
    /// The link's body.
    pub body: RigidBodyHandle,
    /// The mesh file, resolved.
    pub file: PathBuf,
    /// Vertices in the body (link) frame \[m\]: the URDF `<origin>` and `scale` applied.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles, as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
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
        }
    }
}

/// Changes to one joint's property. `property` replaces the whole property built from the
/// URDF (its type must then be given; the frames still come from the URDF); the other fields
/// replace single values, applied after it, on the joint's axis DOF (rx for revolute,
/// continuous and planar joints, dx for prismatic ones).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct JointOverride {
    /// A complete replacement property.
    pub property: Option<Kjoint2Property>,
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
    /// Axis DOF: negative stop [m or rad] (≤ 0; 0 = none).
    pub stop_min: Option<f64>,
    /// Axis DOF: positive stop [m or rad] (≥ 0; 0 = none).
    pub stop_max: Option<f64>,
    /// Which engine builds the joint: `"kjoint2"` (default) or `"rapier"`, a rapier impulse
    /// joint (see the module docs, "Rapier joints"). A rapier joint takes none of
    /// the KJOINT2 fields above, only `motor`.
    pub engine: Option<JointEngine>,
    /// The motor of a rapier joint's axis (needs `engine = "rapier"`, and a revolute,
    /// continuous or prismatic joint).
    pub motor: Option<RapierMotor>,
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
    /// A KJOINT2 penalty joint in the [`KjointSet`] (default).
    #[default]
    Kjoint2,
    /// A rapier impulse joint in the world's `impulse_joints`, solved by rapier's own
    /// constraint solver with the contacts.
    Rapier,
}

/// The motor of a rapier joint's axis: rapier's force-based position motor
/// (`MotorModel::ForceBased`), `F = stiffness·(target − q) − damping·q̇`, bounded by
/// `max_force`. Its target is set once here; a scene changes it over time with
/// `[[motors]]`, a program with `ImpulseJoint::data.set_motor_position`.
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

/// A loaded robot: where its links and joints went.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct UrdfRobot {
    /// The URDF `<robot name>`.
    pub name: String,
    /// Link name → rigid body (links removed as empty have no entry).
    pub links: BTreeMap<String, RigidBodyHandle>,
    /// Link name → its colliders.
    pub colliders: BTreeMap<String, Vec<ColliderHandle>>,
    /// URDF joint name → KJOINT2 joint. Joints merged by the removal of an empty link map to
    /// the joint they were merged into; the KJOINT2 joint is named after the URDF joint whose
    /// type and axis it carries.
    pub joints: BTreeMap<String, KjointHandle>,
    /// URDF joint name → rapier impulse joint, for the joints built by rapier
    /// ([`JointOverride::engine`]); merged names as in [`Self::joints`].
    pub rapier_joints: BTreeMap<String, ImpulseJointHandle>,
    /// The `<visual>` meshes that were found and read (with [`UrdfOptions::visual_meshes`]).
    pub visual_meshes: Vec<VisualMesh>,
    /// What was approximated or skipped (meshes not found or unreadable, massless links,
    /// widened limits, ignored dynamics, removed links).
    pub notices: Vec<String>,
}

impl UrdfRobot {
    /// Body handle → link name (for outputs).
    pub fn body_names(&self) -> std::collections::HashMap<RigidBodyHandle, String> {
        self.links.iter().map(|(n, h)| (*h, n.clone())).collect()
    }
}

/// Errors of the URDF loader. Each names the file (or `<string>`).
#[derive(Debug, thiserror::Error)]
pub enum UrdfError {
    /// The file could not be read (or is larger than [`crate::io::MAX_INPUT_BYTES`]).
    #[error("{file}: {source}")]
    Read {
        /// The file.
        file: PathBuf,
        /// The cause.
        #[source]
        source: crate::io::InputErrorKind,
    },
    /// The text is not a URDF document urdf-rs accepts.
    #[error("{file}: not a valid URDF document: {message}")]
    Parse {
        /// The file.
        file: String,
        /// The parser's message.
        message: String,
    },
    /// The text is not an MJCF model mjcf-rs accepts (its message names the element and the
    /// attribute).
    #[error("{file}: not a valid MJCF model: {message}")]
    Mjcf {
        /// The file.
        file: String,
        /// The parser's message.
        message: String,
    },
    /// A value is invalid.
    #[error("{file}: {element}: invalid {field} = {value}: expected {expected}")]
    Field {
        /// The file.
        file: String,
        /// The element, e.g. ``joint `elbow` `` or ``options.joints.`elbow` ``.
        element: String,
        /// The field, e.g. `limit.lower`.
        field: String,
        /// The value given.
        value: String,
        /// What is accepted.
        expected: String,
    },
    /// A per-joint override gives an invalid property.
    #[error("{file}: options.joints.`{joint}`: {source}")]
    Override {
        /// The file.
        file: String,
        /// The URDF joint.
        joint: String,
        /// What is wrong with the resulting property.
        #[source]
        source: crate::error::PropertyError,
    },
    /// The joints form a closed loop (URDF describes a tree: every link but the root is the
    /// child of one joint).
    #[error(
        "{file}: the joints {} form a closed loop (links {}): a URDF robot is a tree from \
         one root link; close the loop with a KJOINT2 joint of its own (a scene's [[joints]])",
        joints.iter().map(|j| format!("`{j}`")).collect::<Vec<_>>().join(", "),
        links.iter().map(|l| format!("`{l}`")).collect::<Vec<_>>().join(" → ")
    )]
    Loop {
        /// The file.
        file: String,
        /// The joints of the loop, in order from parent to child.
        joints: Vec<String>,
        /// The links of the loop, from parent to child, the first repeated at the end.
        links: Vec<String>,
    },
    /// A KJOINT2 joint could not be built.
    #[error("{file}: joint `{joint}`: {source}")]
    Joint {
        /// The file.
        file: String,
        /// The URDF joint.
        joint: String,
        /// The cause.
        #[source]
        source: Box<SimError>,
    },
}

/// Loads the URDF file `path` into `world` and `joints` (see the module docs).
pub fn load_urdf(
    path: impl AsRef<Path>,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    let (text, file, base) = read_robot_file(path.as_ref())?;
    load(&text, &file, base, world, joints, options)
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

/// Loads URDF text; `file` names it in errors (e.g. `<string>`). Relative mesh paths are
/// taken from the current directory.
pub fn load_urdf_str(
    text: &str,
    file: &str,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    load(text, file, Path::new("."), world, joints, options)
}

fn load(
    text: &str,
    file: &str,
    base: &Path,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    let mut notices = Vec::new();
    let text = sanitize_empty_geometry(&sanitize_empty_texture(text, &mut notices));
    let mut robot = urdf_rs::read_from_string(&text).map_err(|e| UrdfError::Parse {
        file: file.to_string(),
        message: e.to_string(),
    })?;
    let cx = Cx { file };
    cx.check_options(options)?;
    cx.check_robot(&robot)?;
    cx.check_inertias(&mut robot, options, &mut notices)?;
    build(&cx, &robot, base, world, joints, options, notices)
}

/// The file of a URDF mesh `filename`: `package://PKG/rest` is looked up as
/// `DIR/PKG/rest` in `package_dirs`, then in the ancestors of `base` (an ancestor named
/// `PKG`, or one holding a `PKG` directory); `file://path` is `path`; anything else is
/// relative to `base`. `None` when no candidate exists.
pub fn resolve_mesh_path(filename: &str, base: &Path, package_dirs: &[PathBuf]) -> Option<PathBuf> {
    if let Some(rest) = filename.strip_prefix("package://") {
        let (pkg, rel) = rest.split_once('/')?;
        let in_dirs = package_dirs.iter().map(|d| d.join(pkg).join(rel));
        let up = base.ancestors().flat_map(|a| {
            let named = (a.file_name().is_some_and(|n| n == pkg)).then(|| a.join(rel));
            named
                .into_iter()
                .chain(std::iter::once(a.join(pkg).join(rel)))
        });
        return in_dirs.chain(up).find(|p| p.is_file());
    }
    let p = match filename.strip_prefix("file://") {
        Some(abs) => PathBuf::from(abs),
        None => base.join(filename),
    };
    p.is_file().then_some(p)
}

/// Reads a mesh file into body-frame triangles: `origin · (scale ⊙ v)`.
fn read_visual_mesh(
    file: &Path,
    origin: &urdf_rs::Pose,
    scale: Option<urdf_rs::Vec3>,
) -> Result<(Vec<[f32; 3]>, Vec<[u32; 3]>), String> {
    let scene = rapier3d_meshloader::mesh_loader::Loader::default()
        .load(file)
        .map_err(|e| e.to_string())?;
    let sc = scale.map_or([1.0; 3], |s| s.0);
    let [r, p, y] = origin.rpy.0;
    let rot = Rotation3::from_euler_angles(r, p, y);
    let t = Vector3::from(origin.xyz.0);
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for m in scene.meshes {
        let off = vertices.len() as u32;
        let n = m.vertices.len() as u32;
        for v in &m.vertices {
            let w =
                rot * Vector3::new(
                    v[0] as f64 * sc[0],
                    v[1] as f64 * sc[1],
                    v[2] as f64 * sc[2],
                ) + t;
            vertices.push([w.x as f32, w.y as f32, w.z as f32]);
        }
        for f in &m.faces {
            if f.iter().all(|i| *i < n) {
                triangles.push([f[0] + off, f[1] + off, f[2] + off]);
            }
        }
    }
    if triangles.is_empty() {
        return Err("no triangles".into());
    }
    Ok((vertices, triangles))
}

pub(crate) struct Cx<'a> {
    pub(crate) file: &'a str,
}

impl Cx<'_> {
    pub(crate) fn field(
        &self,
        element: impl Into<String>,
        field: impl Into<String>,
        value: impl ToString,
        expected: impl Into<String>,
    ) -> UrdfError {
        UrdfError::Field {
            file: self.file.to_string(),
            element: element.into(),
            field: field.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }

    /// Inserts the KJOINT2 joint `name` of a description between `bodies`: anchors at the
    /// translations of the rapier joint frames `frames` (in each body), its frame the world
    /// rotation `frame` on both sides (the loaded pose is the unloaded one).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn insert_joint(
        &self,
        joints: &mut KjointSet,
        world: &PhysicsWorld,
        prop: Kjoint2Property,
        name: &str,
        bodies: (RigidBodyHandle, RigidBodyHandle),
        frames: (&crate::rapier::math::Pose, &crate::rapier::math::Pose),
        frame: crate::rapier::math::Rotation,
    ) -> Result<KjointHandle, UrdfError> {
        let builder = Kjoint2Builder::new(prop)
            .name(name.to_string())
            .local_anchor1(frames.0.translation)
            .local_anchor2(frames.1.translation)
            .frame(frame)
            .frame2(frame);
        joints
            .insert(builder, bodies.0, bodies.1, &world.bodies)
            .map_err(|source| UrdfError::Joint {
                file: self.file.to_string(),
                joint: name.to_string(),
                source: Box::new(source),
            })
    }

    pub(crate) fn finite(&self, element: &str, field: &str, v: f64) -> Result<f64, UrdfError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.field(element, field, v, "a finite number"))
        }
    }

    pub(crate) fn finite3(
        &self,
        element: &str,
        field: &str,
        v: &[f64; 3],
    ) -> Result<(), UrdfError> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(self.field(element, field, format!("{v:?}"), "finite numbers"))
        }
    }

    pub(crate) fn check_options(&self, o: &UrdfOptions) -> Result<(), UrdfError> {
        let e = "options";
        if !(o.kn.is_finite() && o.kn >= 0.0) {
            return Err(self.field(e, "kn", o.kn, "a finite value >= 0 (0 = automatic)"));
        }
        if !(0.0..=1.0).contains(&o.critical_damping) {
            return Err(self.field(
                e,
                "critical_damping",
                o.critical_damping,
                "a value in [0, 1]",
            ));
        }
        if !(o.substep.is_finite() && o.substep >= 0.0) {
            return Err(self.field(
                e,
                "substep",
                o.substep,
                "a finite time >= 0 [s] (0 = automatic)",
            ));
        }
        if !(o.min_link_mass.is_finite() && o.min_link_mass > 0.0) {
            return Err(self.field(
                e,
                "min_link_mass",
                o.min_link_mass,
                "a finite mass > 0 [kg]",
            ));
        }
        Ok(())
    }

    /// Checks everything rapier3d-urdf would panic on or turn into NaN.
    fn check_robot(&self, robot: &urdf_rs::Robot) -> Result<(), UrdfError> {
        let mut names = std::collections::HashSet::new();
        for link in &robot.links {
            let el = format!("link `{}`", link.name);
            if !names.insert(link.name.as_str()) {
                return Err(self.field(&el, "name", &link.name, "a unique link name"));
            }
            let i = &link.inertial;
            self.finite3(&el, "inertial.origin.xyz", &i.origin.xyz.0)?;
            self.finite3(&el, "inertial.origin.rpy", &i.origin.rpy.0)?;
            let m = self.finite(&el, "inertial.mass", i.mass.value)?;
            if m < 0.0 {
                return Err(self.field(&el, "inertial.mass", m, "a mass >= 0 [kg]"));
            }
            for (f, v) in [
                ("ixx", i.inertia.ixx),
                ("ixy", i.inertia.ixy),
                ("ixz", i.inertia.ixz),
                ("iyy", i.inertia.iyy),
                ("iyz", i.inertia.iyz),
                ("izz", i.inertia.izz),
            ] {
                self.finite(&el, &format!("inertial.inertia.{f}"), v)?;
            }
            let geoms = link
                .collision
                .iter()
                .map(|c| ("collision", &c.origin, &c.geometry))
                .chain(
                    link.visual
                        .iter()
                        .map(|v| ("visual", &v.origin, &v.geometry)),
                );
            for (kind, origin, g) in geoms {
                self.finite3(&el, &format!("{kind}.origin.xyz"), &origin.xyz.0)?;
                self.finite3(&el, &format!("{kind}.origin.rpy"), &origin.rpy.0)?;
                let sizes: Vec<(&str, f64)> = match g {
                    urdf_rs::Geometry::Box { size } => {
                        vec![
                            ("box.size", size[0]),
                            ("box.size", size[1]),
                            ("box.size", size[2]),
                        ]
                    }
                    urdf_rs::Geometry::Cylinder { radius, length } => {
                        vec![("cylinder.radius", *radius), ("cylinder.length", *length)]
                    }
                    urdf_rs::Geometry::Capsule { radius, length } => {
                        vec![("capsule.radius", *radius), ("capsule.length", *length)]
                    }
                    urdf_rs::Geometry::Sphere { radius } => vec![("sphere.radius", *radius)],
                    urdf_rs::Geometry::Mesh { scale, .. } => scale
                        .map(|s| s.0.iter().map(|v| ("mesh.scale", *v)).collect())
                        .unwrap_or_default(),
                };
                for (f, v) in sizes {
                    if !(v.is_finite() && (v >= 0.0 || f == "mesh.scale")) {
                        return Err(self.field(
                            &el,
                            format!("{kind}.geometry.{f}"),
                            v,
                            "a finite size >= 0 [m]",
                        ));
                    }
                }
            }
        }
        let mut jnames = std::collections::HashSet::new();
        for j in &robot.joints {
            let el = format!("joint `{}`", j.name);
            if !jnames.insert(j.name.as_str()) {
                return Err(self.field(&el, "name", &j.name, "a unique joint name"));
            }
            for (f, l) in [
                ("parent.link", &j.parent.link),
                ("child.link", &j.child.link),
            ] {
                if !names.contains(l.as_str()) {
                    return Err(self.field(&el, f, l, "the name of a link of the robot"));
                }
            }
            if j.parent.link == j.child.link {
                return Err(self.field(
                    &el,
                    "child.link",
                    &j.child.link,
                    "a link other than the parent",
                ));
            }
            self.finite3(&el, "origin.xyz", &j.origin.xyz.0)?;
            self.finite3(&el, "origin.rpy", &j.origin.rpy.0)?;
            self.finite3(&el, "axis.xyz", &j.axis.xyz.0)?;
            let a = j.axis.xyz.0;
            let moving = !matches!(
                j.joint_type,
                urdf_rs::JointType::Fixed
                    | urdf_rs::JointType::Floating
                    | urdf_rs::JointType::Spherical
            );
            if moving && a.iter().map(|v| v * v).sum::<f64>() < 1e-12 {
                return Err(self.field(&el, "axis.xyz", format!("{a:?}"), "a non-zero axis"));
            }
            for (f, v) in [
                ("limit.lower", j.limit.lower),
                ("limit.upper", j.limit.upper),
            ] {
                if v.is_nan() {
                    return Err(self.field(&el, f, v, "a number (±inf = no stop)"));
                }
            }
            if j.limit.lower > j.limit.upper {
                return Err(self.field(
                    &el,
                    "limit.lower",
                    j.limit.lower,
                    format!("a value <= limit.upper = {}", j.limit.upper),
                ));
            }
            if let Some(d) = &j.dynamics {
                for (f, v) in [
                    ("dynamics.damping", d.damping),
                    ("dynamics.friction", d.friction),
                ] {
                    if !(v.is_finite() && v >= 0.0) {
                        return Err(self.field(&el, f, v, "a finite value >= 0"));
                    }
                }
            }
        }
        // every link is the child of at most one joint (a tree)
        let mut children = std::collections::HashSet::new();
        for j in &robot.joints {
            if !children.insert(j.child.link.as_str()) {
                return Err(self.field(
                    format!("joint `{}`", j.name),
                    "child.link",
                    &j.child.link,
                    "a link that is the child of no other joint (URDF is a tree)",
                ));
            }
        }
        // and no closed loop (with one parent per link, a robot without root has one)
        if let Some((joints, links)) = closed_loop(robot) {
            return Err(UrdfError::Loop {
                file: self.file.to_string(),
                joints,
                links,
            });
        }
        Ok(())
    }

    /// Inertias: round-off below zero is read as zero, clearly negative diagonal terms are
    /// refused, and the zero (or negative) principal moments of a dynamic link with mass get
    /// the inertia of a ball ([`BALL_RADIUS`]); see the module docs.
    fn check_inertias(
        &self,
        robot: &mut urdf_rs::Robot,
        options: &UrdfOptions,
        notices: &mut Vec<String>,
    ) -> Result<(), UrdfError> {
        let roots: std::collections::HashSet<String> =
            root_links(robot).into_iter().map(String::from).collect();
        for link in robot.links.iter_mut() {
            let el = format!("link `{}`", link.name);
            let m = link.inertial.mass.value;
            let i = &mut link.inertial.inertia;
            let largest = [i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz]
                .iter()
                .fold(0.0f64, |a, v| a.max(v.abs()));
            let tol = (INERTIA_ROUNDOFF * largest).max(INERTIA_ABS_ROUNDOFF);
            for (f, v) in [
                ("ixx", &mut i.ixx),
                ("iyy", &mut i.iyy),
                ("izz", &mut i.izz),
            ] {
                if *v < -tol {
                    return Err(self.field(
                        &el,
                        format!("inertial.inertia.{f}"),
                        *v,
                        format!("a value >= 0 [kg·m²] (round-off down to -{tol:.1e} is read as 0)"),
                    ));
                }
                if *v < 0.0 {
                    notices.push(format!(
                        "{el}: inertial.inertia.{f} = {v:e} is round-off (within -{tol:.1e}): read \
                         as 0"
                    ));
                    *v = 0.0;
                }
            }
            let tensor = Matrix3::new(
                i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz,
            );
            let eig = nalgebra::SymmetricEigen::new(tensor);
            let p = eig.eigenvalues;
            let mut sorted = [p[0], p[1], p[2]];
            sorted.sort_by(f64::total_cmp);
            // a tensor that is not positive semi-definite (real descriptions have them:
            // romeo, tiago): rapier reads its negative principal moments as 0, like a zero
            // inertia, so it gets the same treatment, with a notice that says so
            let not_psd = if p.min() < -tol {
                format!(
                    "inertial.inertia is not positive semi-definite (principal moments [{:.3e}, \
                     {:.3e}, {:.3e}] kg·m²), ",
                    sorted[0], sorted[1], sorted[2]
                )
            } else {
                String::new()
            };
            // a dynamic link with mass and a zero principal moment: rapier would lock its
            // rotation about that axis (infinite inertia); give it a ball's inertia there
            let fixed = options.fixed_base && roots.contains(&link.name);
            let zero: Vec<usize> = (0..3).filter(|&k| p[k] <= tol).collect();
            if m > 0.0 && !fixed && !zero.is_empty() {
                let ball = 0.4 * m * BALL_RADIUS * BALL_RADIUS;
                let mut t = tensor;
                for &k in &zero {
                    let v = eig.eigenvectors.column(k);
                    t += (ball - p[k]) * v * v.transpose();
                }
                (i.ixx, i.iyy, i.izz) = (t[(0, 0)], t[(1, 1)], t[(2, 2)]);
                (i.ixy, i.ixz, i.iyz) = (t[(0, 1)], t[(0, 2)], t[(1, 2)]);
                notices.push(format!(
                    "{el}: {not_psd}mass {m} kg with {} zero principal moment{} of inertia \
                     (inertial.inertia): given {ball:.3e} kg·m² there, the inertia of a ball of \
                     its mass and radius {BALL_RADIUS} m",
                    zero.len(),
                    if zero.len() > 1 { "s" } else { "" }
                ));
            } else if !not_psd.is_empty() {
                notices.push(format!("{el}: {not_psd}its negative moments are read as 0"));
            }
        }
        Ok(())
    }
}

/// The links that are the child of no joint.
fn root_links(robot: &urdf_rs::Robot) -> std::collections::HashSet<&str> {
    let children: std::collections::HashSet<&str> =
        robot.joints.iter().map(|j| j.child.link.as_str()).collect();
    robot
        .links
        .iter()
        .map(|l| l.name.as_str())
        .filter(|l| !children.contains(l))
        .collect()
}

/// The first closed loop of parent links (in link order), as its joints and its links from
/// parent to child; `None` for a forest. Expects every link to be the child of at most one
/// joint.
fn closed_loop(robot: &urdf_rs::Robot) -> Option<(Vec<String>, Vec<String>)> {
    let parent: std::collections::HashMap<&str, (&str, &str)> = robot
        .joints
        .iter()
        .map(|j| {
            (
                j.child.link.as_str(),
                (j.name.as_str(), j.parent.link.as_str()),
            )
        })
        .collect();
    for start in &robot.links {
        let start = start.name.as_str();
        let (mut cur, mut joints, mut links) = (start, Vec::new(), vec![start]);
        for _ in 0..=robot.links.len() {
            let Some(&(j, p)) = parent.get(cur) else {
                break;
            };
            joints.push(j.to_string());
            links.push(p);
            cur = p;
            if cur == start {
                // walked up from `start` back to it: report it parent → child
                joints.reverse();
                links.reverse();
                return Some((joints, links.iter().map(|l| l.to_string()).collect()));
            }
        }
    }
    None
}

fn kjoint_type(t: &urdf_rs::JointType) -> JointType {
    match t {
        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => JointType::Revolute,
        urdf_rs::JointType::Prismatic => JointType::Translational,
        urdf_rs::JointType::Fixed => JointType::Fixed,
        urdf_rs::JointType::Floating => JointType::Free,
        urdf_rs::JointType::Planar => JointType::Planar,
        urdf_rs::JointType::Spherical => JointType::Spherical,
    }
}

/// The DOF that carries a joint's URDF axis data (limits, dynamics, overrides).
pub(crate) fn axis_dof(t: JointType) -> Option<Dof> {
    match t {
        JointType::Revolute | JointType::Planar => Some(Dof::Rx),
        JointType::Translational => Some(Dof::Dx),
        _ => None,
    }
}

/// URDF limits → KJOINT2 stops `(SD-, SD+)`, and a notice when they had to be changed.
pub(crate) fn stops_from_limits(lower: f64, upper: f64) -> ((f64, f64), Option<String>) {
    if lower == 0.0 && upper == 0.0 {
        return (
            (0.0, 0.0),
            Some("limit lower = upper = 0: read as no limits".into()),
        );
    }
    let mut note = None;
    let lo = if lower == f64::NEG_INFINITY {
        0.0
    } else if lower > 0.0 {
        note = Some(format!(
            "limit [{lower}, {upper}] excludes the initial position 0: widened to include it"
        ));
        -ZERO_LIMIT
    } else if lower == 0.0 {
        -ZERO_LIMIT
    } else {
        lower
    };
    let hi = if upper == f64::INFINITY {
        0.0
    } else if upper < 0.0 {
        note = Some(format!(
            "limit [{lower}, {upper}] excludes the initial position 0: widened to include it"
        ));
        ZERO_LIMIT
    } else if upper == 0.0 {
        ZERO_LIMIT
    } else {
        upper
    };
    ((lo, hi), note)
}

fn build(
    cx: &Cx,
    robot: &urdf_rs::Robot,
    base: &Path,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
    mut notices: Vec<String>,
) -> Result<UrdfRobot, UrdfError> {
    // overrides must name joints of the robot
    for name in options.joints.keys() {
        if !robot.joints.iter().any(|j| &j.name == name) {
            return Err(cx.field(
                "options.joints",
                "name",
                name,
                "the name of a joint of the robot",
            ));
        }
    }
    let group = Group::GROUP_32;
    let groups = if options.self_collisions {
        InteractionGroups::all()
    } else {
        InteractionGroups::new(group, Group::ALL ^ group, InteractionTestMode::And)
    };
    // mesh paths resolved to files (unresolved ones are dropped, with a notice)
    let mut robot = robot.clone();
    for link in robot.links.iter_mut() {
        let name = link.name.clone();
        let mut resolve = |kind: &str, g: &mut urdf_rs::Geometry| -> bool {
            let urdf_rs::Geometry::Mesh { filename, .. } = g else {
                return true;
            };
            match resolve_mesh_path(filename, base, &options.package_dirs) {
                Some(p)
                    if std::fs::metadata(&p)
                        .is_ok_and(|m| m.len() > crate::io::MAX_INPUT_BYTES) =>
                {
                    notices.push(format!(
                        "link `{name}`: {kind} mesh `{}` is larger than the size cap of input \
                         files ({} bytes, rapier_kjoint::io::MAX_INPUT_BYTES): skipped",
                        p.display(),
                        crate::io::MAX_INPUT_BYTES
                    ));
                    false
                }
                Some(p) => {
                    *filename = p.display().to_string();
                    true
                }
                None => {
                    notices.push(format!(
                        "link `{name}`: {kind} mesh `{filename}` not found (from {}): skipped",
                        base.display()
                    ));
                    false
                }
            }
        };
        link.collision
            .retain_mut(|c| resolve("collision", &mut c.geometry));
        link.visual
            .retain_mut(|v| resolve("visual", &mut v.geometry));
        if options.collision_meshes == CollisionMeshes::Ignore {
            link.collision
                .retain(|c| !matches!(c.geometry, urdf_rs::Geometry::Mesh { .. }));
        }
    }
    let robot = &robot;
    // rapier3d-urdf builds f32 objects (rapier3d), converted into the world's rapier below
    // (`loaded`); the collision groups are set on the converted colliders
    let loader = UrdfLoaderOptions {
        make_roots_fixed: options.fixed_base,
        mesh_converter: Some(options.collision_meshes.converter()),
        collider_blueprint: rapier3d::geometry::ColliderBuilder::default().density(0.0),
        rigid_body_blueprint: rapier3d::dynamics::RigidBodyBuilder::dynamic().can_sleep(false),
        ..Default::default()
    };
    let loaded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        RapierUrdfRobot::from_robot(robot, loader, Path::new("."))
    }))
    .map_err(|_| UrdfError::Parse {
        file: cx.file.to_string(),
        message: "rapier3d-urdf could not build the robot".into(),
    })?;

    let mut out = UrdfRobot {
        name: robot.name.clone(),
        notices,
        ..Default::default()
    };
    // notices for meshes and removed links
    let kept: std::collections::HashSet<usize> =
        loaded.links.iter().map(|l| l.urdf_link_index).collect();
    for (i, link) in robot.links.iter().enumerate() {
        if !kept.contains(&i) {
            out.notices.push(format!(
                "link `{}`: empty (no inertial, visual or collision): removed, its joints merged",
                link.name
            ));
        }
    }

    // bodies and colliders
    let mut handles = Vec::with_capacity(loaded.links.len());
    let mut poses = Vec::with_capacity(loaded.links.len());
    let roots = root_links(robot);
    for link in loaded.links.iter() {
        let ulink = &robot.links[link.urdf_link_index];
        let mut body = loaded::body(&link.body);
        let m = ulink.inertial.mass.value;
        if ulink.name == WORLD_LINK && m <= 0.0 && roots.contains(ulink.name.as_str()) {
            // the ROS convention: a massless root `world` is the fixed world
            body.set_body_type(RigidBodyType::Fixed, false);
        }
        if body.body_type() == RigidBodyType::Dynamic && m <= 0.0 {
            let mm = options.min_link_mass as Real;
            let i = 0.4 * mm * (BALL_RADIUS * BALL_RADIUS) as Real;
            body.set_additional_mass_properties(
                MassProperties::new(Vector::ZERO, mm, Vector::splat(i)),
                false,
            );
            out.notices.push(format!(
                "link `{}`: no mass in the URDF: given {} kg",
                ulink.name, options.min_link_mass
            ));
        }
        poses.push(*body.position());
        let h = world.bodies.insert(body);
        let mut cols: Vec<ColliderHandle> = Vec::with_capacity(link.colliders.len());
        for c in &link.colliders {
            let mut c = loaded::collider(&c.collider).map_err(|e| UrdfError::Parse {
                file: cx.file.to_string(),
                message: format!("link `{}`: {e}", ulink.name),
            })?;
            c.set_collision_groups(groups);
            cols.push(world.colliders.insert_with_parent(c, h, &mut world.bodies));
        }
        let meshes = ulink
            .collision
            .iter()
            .filter(|c| matches!(c.geometry, urdf_rs::Geometry::Mesh { .. }))
            .count();
        let made = link
            .colliders
            .iter()
            .filter(|c| {
                matches!(
                    c.collider.shape().as_typed_shape(),
                    rapier3d::geometry::TypedShape::ConvexPolyhedron(_)
                        | rapier3d::geometry::TypedShape::TriMesh(_)
                )
            })
            .count();
        if made < meshes {
            out.notices.push(format!(
                "link `{}`: {} of {meshes} collision meshes unreadable (or degenerate): no \
                 collider for them",
                ulink.name,
                meshes - made
            ));
        }
        if options.visual_meshes {
            for v in &ulink.visual {
                let urdf_rs::Geometry::Mesh { filename, scale } = &v.geometry else {
                    continue;
                };
                let file = PathBuf::from(filename);
                match read_visual_mesh(&file, &v.origin, *scale) {
                    Ok((vertices, triangles)) => out.visual_meshes.push(VisualMesh {
                        link: ulink.name.clone(),
                        body: h,
                        file,
                        vertices,
                        triangles,
                    }),
                    Err(e) => out.notices.push(format!(
                        "link `{}`: visual mesh `{filename}` unreadable: {e}",
                        ulink.name
                    )),
                }
            }
        }
        out.links.insert(ulink.name.clone(), h);
        out.colliders.insert(ulink.name.clone(), cols);
        handles.push(h);
    }

    // the links beyond each joint (their mass and inertia make its friction stiffness)
    let link_mass: Vec<LinkMass> = loaded
        .links
        .iter()
        .zip(&poses)
        .map(|(l, pose)| {
            LinkMass::of(
                &robot.links[l.urdf_link_index].inertial,
                pose,
                options.min_link_mass,
            )
        })
        .collect();
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); loaded.links.len()];
    for uj in &loaded.joints {
        children[uj.link1].push(uj.link2);
    }

    // joints
    for uj in &loaded.joints {
        let src = &robot.joints[uj.source_urdf_joint_index()];
        let joint = loaded::joint(&uj.joint);
        let name = src.name.clone();
        let el = format!("joint `{name}`");
        let (b1, b2) = (handles[uj.link1], handles[uj.link2]);
        let dyn1 = world.bodies.get(b1).is_some_and(|b| b.is_dynamic());
        let dyn2 = world.bodies.get(b2).is_some_and(|b| b.is_dynamic());
        if !dyn1 && !dyn2 {
            out.notices
                .push(format!("{el}: both links are fixed: no joint created"));
            continue;
        }
        if src.mimic.is_some() {
            out.notices
                .push(format!("{el}: <mimic> ignored: the joint moves freely"));
        }
        // the URDF names this joint answers to (merged ones too)
        let names: Vec<&str> = std::iter::once(name.as_str())
            .chain(
                std::iter::once(uj.urdf_joint_index)
                    .chain(uj.merged_urdf_joint_indices.iter().copied())
                    .map(|i| robot.joints[i].name.as_str()),
            )
            .collect();
        // an override may also name a joint merged into this one
        let ov = names.iter().find_map(|n| options.joints.get(*n));
        if let Some(ov) = ov.filter(|o| o.engine == Some(JointEngine::Rapier)) {
            let joint = rapier_joint(cx, &name, src, joint, ov, &mut out.notices)?;
            let h = world.impulse_joints.insert(b1, b2, joint, true);
            for n in names {
                out.rapier_joints.insert(n.to_string(), h);
            }
            continue;
        }
        if let Some(m) = ov.and_then(|o| o.motor.as_ref()) {
            return Err(cx.field(
                format!("options.joints.`{name}`"),
                "motor",
                m.to_string(),
                "no motor on a KJOINT2 joint: a motor drives a rapier joint (engine = \"rapier\")",
            ));
        }
        let lf1 = joint.local_frame1;
        let lf2 = joint.local_frame2;
        let frame = (poses[uj.link1].rotation * lf1.rotation).normalize();
        let jt = kjoint_type(&src.joint_type);
        let mut prop = Kjoint2Property::new(jt)
            .with_kn(options.kn)
            .with_critical_damping(options.critical_damping);
        if let Some(dof) = axis_dof(jt) {
            let mut law = DofLaw::default();
            let revolute_like = matches!(
                src.joint_type,
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Prismatic
            );
            if revolute_like {
                let ((lo, hi), note) = stops_from_limits(src.limit.lower, src.limit.upper);
                law = law.with_stops(lo, hi);
                if let Some(n) = note {
                    out.notices.push(format!("{el}: {n}"));
                }
            }
            if let Some(d) = &src.dynamics {
                if jt == JointType::Planar {
                    if d.damping > 0.0 || d.friction > 0.0 {
                        out.notices
                            .push(format!("{el}: dynamics of a planar joint ignored"));
                    }
                } else {
                    law.viscosity = d.damping;
                    if d.friction > 0.0 {
                        law.friction = d.friction;
                    }
                }
            }
            if law.friction > 0.0 {
                let pose2 = &poses[uj.link2];
                let anchor = from_vec3(pose2.translation)
                    + from_quat(pose2.rotation) * from_vec3(lf2.translation);
                let axis = from_quat(pose2.rotation * lf2.rotation) * Vector3::x();
                let (m_eff, scale) =
                    load_beyond(&link_mass, &children, uj.link2, dof, &anchor, &axis);
                law.friction_stiffness =
                    friction_stiffness(m_eff, scale, options.resolved_substep());
            }
            prop = prop.with_dof(dof, law);
        } else if let Some(d) = &src.dynamics {
            if d.damping > 0.0 || d.friction > 0.0 {
                out.notices
                    .push(format!("{el}: dynamics of a {} joint ignored", jt.name()));
            }
        }
        if let Some(ov) = ov {
            prop = apply_override(cx, &name, prop, ov)?;
        }
        let h = cx.insert_joint(joints, world, prop, &name, (b1, b2), (&lf1, &lf2), frame)?;
        for n in names {
            out.joints.insert(n.to_string(), h);
        }
    }
    Ok(out)
}

/// The rapier impulse joint of a URDF joint whose override says `engine = "rapier"`:
/// `rapier3d-urdf`'s joint (frames at the URDF joint origin, the axis as the joint's x, the
/// URDF limits on the axis), with the limits read as for the KJOINT2 stops where rapier
/// would read them otherwise and the override's motor (module docs, "Rapier joints").
fn rapier_joint(
    cx: &Cx,
    name: &str,
    src: &urdf_rs::Joint,
    mut joint: GenericJoint,
    ov: &JointOverride,
    notices: &mut Vec<String>,
) -> Result<GenericJoint, UrdfError> {
    let el = format!("options.joints.`{name}`");
    let kjoint_fields = [
        ("property", ov.property.is_some()),
        ("kn", ov.kn.is_some()),
        ("critical_damping", ov.critical_damping.is_some()),
        ("stiffness", ov.stiffness.is_some()),
        ("viscosity", ov.viscosity.is_some()),
        ("friction", ov.friction.is_some()),
        ("friction_stiffness", ov.friction_stiffness.is_some()),
        ("stop_min", ov.stop_min.is_some()),
        ("stop_max", ov.stop_max.is_some()),
    ];
    if let Some((f, _)) = kjoint_fields.iter().find(|(_, set)| *set) {
        return Err(cx.field(
            &el,
            *f,
            "(set)",
            "nothing: a rapier joint (engine = \"rapier\") takes no KJOINT2 field, only `motor` \
             (its limits are the URDF's)",
        ));
    }
    let axis = match src.joint_type {
        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => Some(JointAxis::AngX),
        urdf_rs::JointType::Prismatic => Some(JointAxis::LinX),
        _ => None,
    };
    if let Some(axis) = axis.filter(|_| src.joint_type != urdf_rs::JointType::Continuous) {
        let (lo, hi) = (src.limit.lower, src.limit.upper);
        if lo == 0.0 && hi == 0.0 {
            // the URDF default of a <limit> with effort and velocity only, as for KJOINT2
            joint.limit_axes.remove(JointAxesMask::from(axis));
            notices.push(format!(
                "joint `{name}`: limit lower = upper = 0: read as no limits"
            ));
        } else {
            // rapier's limits have two sides: an infinite one becomes a far one
            let side = |v: f64| v.clamp(-FAR_LIMIT, FAR_LIMIT) as Real;
            joint.set_limits(axis, [side(lo), side(hi)]);
            if lo > 0.0 || hi < 0.0 {
                notices.push(format!(
                    "joint `{name}`: limit [{lo}, {hi}] excludes the initial position 0: \
                     rapier pulls the joint into it at the first step"
                ));
            }
        }
    }
    if src
        .dynamics
        .as_ref()
        .is_some_and(|d| d.damping > 0.0 || d.friction > 0.0)
    {
        notices.push(format!(
            "joint `{name}`: <dynamics> ignored on a rapier joint (give the motor damping)"
        ));
    }
    if let Some(m) = &ov.motor {
        let Some(axis) = axis else {
            return Err(cx.field(
                &el,
                "motor",
                m.to_string(),
                format!(
                    "no motor on a {:?} joint: a motor drives the axis of a revolute, continuous \
                     or prismatic joint",
                    src.joint_type
                ),
            ));
        };
        let e = format!("{el}.motor");
        let target = cx.finite(&e, "target", m.target)?;
        for (f, v) in [("stiffness", m.stiffness), ("damping", m.damping)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(cx.field(&e, f, v, "a finite value >= 0"));
            }
        }
        if m.stiffness == 0.0 && m.damping == 0.0 {
            return Err(cx.field(
                &e,
                "stiffness",
                m.stiffness,
                "a value > 0 (or a damping > 0): a motor with neither does nothing",
            ));
        }
        joint.set_motor_model(axis, MotorModel::ForceBased);
        joint.set_motor_position(axis, target as Real, m.stiffness as Real, m.damping as Real);
        if let Some(f) = m.max_force {
            if !(f.is_finite() && f > 0.0) {
                return Err(cx.field(&e, "max_force", f, "a finite force > 0 [N or N·m]"));
            }
            joint.set_motor_max_force(axis, f as Real);
        }
    }
    Ok(joint)
}

/// How far \[m or rad\] the infinite side of a rapier joint's URDF limit is put (rapier's
/// limits have two sides).
pub const FAR_LIMIT: f64 = 1e6;

/// Friction spring stiffness rule `Kf = κ_eff·m_eff/h²` [N/m or N·m/rad] (module docs):
/// the implicit rule of the blocked DOFs ([`crate::law::stiffness::implicit_kappa`]) for a
/// load of mass or moment of inertia `m_eff` (the links the joint holds up, about its axis)
/// at pose scale `pose_scale` \[m\] (the anchor's distance from the origin plus the load's
/// radius of gyration), substep `h` \[s\].
pub fn friction_stiffness(m_eff: f64, pose_scale: f64, substep: f64) -> f64 {
    implicit_kappa(substep, pose_scale) * m_eff / (substep * substep)
}

/// Mass, world centre of mass and world inertia tensor (about that centre) of a link.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LinkMass {
    pub(crate) m: f64,
    pub(crate) c: Vector3<f64>,
    pub(crate) inertia: Matrix3<f64>,
}

impl LinkMass {
    /// From the URDF inertial at the link's world pose; a link without mass counts
    /// `min_mass` with the inertia of a 5 cm ball (as its body gets).
    fn of(inertial: &urdf_rs::Inertial, pose: &crate::rapier::math::Pose, min_mass: f64) -> Self {
        let i = &inertial.inertia;
        let (mut m, mut ic) = (
            inertial.mass.value,
            Matrix3::new(
                i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz,
            ),
        );
        if m <= 0.0 {
            m = min_mass;
            ic = Matrix3::identity() * (0.4 * m * 0.05 * 0.05);
        }
        let rpy = inertial.origin.rpy.0;
        let rot = from_quat(pose.rotation).to_rotation_matrix()
            * Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]);
        let c = from_vec3(pose.translation)
            + from_quat(pose.rotation) * Vector3::from(inertial.origin.xyz.0);
        LinkMass {
            m,
            c,
            inertia: rot.matrix() * ic * rot.matrix().transpose(),
        }
    }
}

/// The load a joint's free DOF `dof` holds up: the link `first` and every link beyond it
/// (`children`), as a mass \[kg\] (translation) or a moment of inertia about `axis` through
/// `anchor` [kg·m²] (rotation), and the pose scale `|anchor| + √(I/m)` \[m\] of the
/// implicit rule (world coordinates).
pub(crate) fn load_beyond(
    links: &[LinkMass],
    children: &[Vec<usize>],
    first: usize,
    dof: Dof,
    anchor: &Vector3<f64>,
    axis: &Vector3<f64>,
) -> (f64, f64) {
    let a = axis.normalize();
    let (mut m, mut i_axis, mut i_mean) = (0.0, 0.0, 0.0);
    let mut seen = vec![false; links.len()];
    let mut stack = vec![first];
    while let Some(l) = stack.pop() {
        if std::mem::replace(&mut seen[l], true) {
            continue;
        }
        let lm = &links[l];
        let d = lm.c - anchor;
        m += lm.m;
        i_axis += (a.transpose() * lm.inertia * a)[0] + lm.m * d.cross(&a).norm_squared();
        i_mean += lm.inertia.trace() / 3.0 + 2.0 / 3.0 * lm.m * d.norm_squared();
        stack.extend(children[l].iter().copied());
    }
    let gyration = if m > 0.0 { (i_mean / m).sqrt() } else { 0.0 };
    let scale = anchor.norm() + gyration;
    if dof.is_rotation() {
        (i_axis.max(0.0), scale)
    } else {
        (m, scale)
    }
}

/// Mass \[kg\] (translations) or moment of inertia about the axis `axis` through `anchor`
/// [kg·m²] (rotations) of a link, from its URDF inertial; `anchor` and `axis` in the link
/// frame. A link without mass counts `min_mass` with the inertia of a 5 cm ball.
pub fn effective_mass(
    inertial: &urdf_rs::Inertial,
    dof: Dof,
    anchor: &Vector3<f64>,
    axis: &Vector3<f64>,
    min_mass: f64,
) -> f64 {
    let mut m = inertial.mass.value;
    let i = &inertial.inertia;
    let mut ic = Matrix3::new(
        i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz,
    );
    if m <= 0.0 {
        m = min_mass;
        ic = Matrix3::identity() * (0.4 * m * BALL_RADIUS * BALL_RADIUS);
    }
    if !dof.is_rotation() {
        return m;
    }
    let rpy = inertial.origin.rpy.0;
    let r = Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]);
    let c = Vector3::from(inertial.origin.xyz.0);
    let a = axis.normalize();
    let i_axis = (a.transpose() * r.matrix() * ic * r.matrix().transpose() * a)[0];
    let d = (c - anchor).cross(&a);
    (i_axis + m * d.norm_squared()).max(0.0)
}

pub(crate) fn apply_override(
    cx: &Cx,
    joint: &str,
    prop: Kjoint2Property,
    ov: &JointOverride,
) -> Result<Kjoint2Property, UrdfError> {
    let el = format!("options.joints.`{joint}`");
    let mut p = ov.property.clone().unwrap_or(prop);
    if let Some(v) = ov.kn {
        p.kn = v;
    }
    if let Some(v) = ov.critical_damping {
        p.critical_damping = v;
    }
    let fields = [
        ("stiffness", ov.stiffness),
        ("viscosity", ov.viscosity),
        ("friction", ov.friction),
        ("friction_stiffness", ov.friction_stiffness),
        ("stop_min", ov.stop_min),
        ("stop_max", ov.stop_max),
    ];
    if fields.iter().any(|(_, v)| v.is_some()) {
        let Some(dof) = axis_dof(p.joint_type) else {
            let (f, v) = fields
                .iter()
                .find(|(_, v)| v.is_some())
                .copied()
                .unwrap_or(("", None));
            return Err(cx.field(
                el,
                f,
                v.unwrap_or_default(),
                format!(
                    "no per-DOF field on a {} joint (give a whole `property` instead)",
                    p.joint_type.name()
                ),
            ));
        };
        let law = &mut p.dofs[dof.index()];
        for (f, v) in fields {
            if let Some(v) = v {
                match f {
                    "stiffness" => law.stiffness = v,
                    "viscosity" => law.viscosity = v,
                    "friction" => law.friction = v,
                    "friction_stiffness" => law.friction_stiffness = v,
                    "stop_min" => law.stop_min = v,
                    _ => law.stop_max = v,
                }
            }
        }
    }
    p.validate().map_err(|source| UrdfError::Override {
        file: cx.file.to_string(),
        joint: joint.to_string(),
        source,
    })?;
    Ok(p)
}

/// `<texture>` elements without a `filename` (`<texture/>`, which urdf-rs refuses; icub and
/// romeo of example-robot-data have them) are removed, with a notice naming their line.
/// Textures are never read.
fn sanitize_empty_texture(input: &str, notices: &mut Vec<String>) -> String {
    const TAG: &str = "<texture";
    let mut out = String::with_capacity(input.len());
    let mut pos = 0;
    while let Some(found) = input[pos..].find(TAG) {
        let start = pos + found;
        let after = start + TAG.len();
        let is_tag =
            input[after..].starts_with(|c: char| c.is_whitespace() || c == '/' || c == '>');
        let Some(end) = input[after..].find('>').filter(|_| is_tag) else {
            out.push_str(&input[pos..after]);
            pos = after;
            continue;
        };
        let open_end = after + end + 1;
        let open = &input[start..open_end];
        let mut stop = open_end;
        if !open.contains("filename") && !open.ends_with("/>") {
            // <texture ...> ... </texture>
            match input[open_end..].find("</texture>") {
                Some(close) => stop = open_end + close + "</texture>".len(),
                None => stop = start,
            }
        }
        if open.contains("filename") || stop == start {
            out.push_str(&input[pos..open_end]);
            pos = open_end;
            continue;
        }
        notices.push(format!(
            "line {}: <texture> without a filename ignored (textures are not read)",
            crate::scene::line_at(input, start)
        ));
        out.push_str(&input[pos..start]);
        pos = stop;
    }
    out.push_str(&input[pos..]);
    out
}

/// `<geometry></geometry>` with nothing inside (which urdf-rs rejects) → a zero box, which
/// rapier3d-urdf skips (the same sanitising `rapier3d-urdf` does on its own entry points).
fn sanitize_empty_geometry(input: &str) -> String {
    let mut out = String::with_capacity(input.len());
    let mut rem = input;
    while let Some(start) = rem.find("<geometry") {
        let (before, tag) = rem.split_at(start);
        out.push_str(before);
        let Some(end) = tag.find('>') else {
            out.push_str(tag);
            return out;
        };
        let open = &tag[..=end];
        out.push_str(open);
        let body = &tag[end + 1..];
        if open.ends_with("/>") {
            rem = body;
            continue;
        }
        match body.find("</geometry>") {
            Some(close) if body[..close].trim().is_empty() => {
                out.push_str("<box size=\"0 0 0\"/>");
                rem = &body[close..];
            }
            _ => rem = body,
        }
    }
    out.push_str(rem);
    out
}
