//! URDF robots with KJOINT2 joints.
//!
//! A URDF robot is read in two phases, as with `rapier3d-urdf`:
//!
//! ```no_run
//! use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
//! use rapier_kjoint::rapier::pipeline::PhysicsWorld;
//! use rapier_kjoint::KjointSet;
//! # fn main() -> Result<(), rapier_kjoint::io::urdf::UrdfError> {
//! let (mut world, mut joints) = (PhysicsWorld::default(), KjointSet::new());
//! // 1. describe: parse, validate, build bodies, colliders and joint builders (no world)
//! let robot = UrdfRobot::from_file("arm.urdf", &UrdfOptions::default())?;
//! // 2. insert: into the caller's world and joint set, returning the handles
//! let handles = robot.insert(&mut world, &mut joints)?;
//! # let _ = handles; Ok(()) }
//! ```
//!
//! [`UrdfRobot::from_file`] / [`UrdfRobot::from_str`] read the description with
//! `rapier3d-urdf` (links → rigid bodies with the URDF inertia, `<collision>` primitives →
//! colliders) and, instead of rapier's joints, describe one KJOINT2 joint
//! ([`KjointBuilder`] + [`KjointProperty`]) per URDF joint, except the joints asked for as
//! rapier impulse joints ("Rapier joints" below): a [`UrdfRobot`] ([`RobotDescription`]).
//! Its [`insert`](RobotDescription::insert) puts the bodies into a [`PhysicsWorld`] and the KJOINT2 joints into a [`KjointSet`] and
//! returns a [`UrdfRobotHandles`]. Nothing is stepped. There is no one-call loader: the
//! description can be inspected or changed (a joint's builder, a link's body) before it is
//! inserted, and inserted into several worlds.
//!
//! # Files
//!
//! `options.rs` ([`UrdfOptions`], [`JointOverride`]), `error.rs` ([`UrdfError`]),
//! `sanitize.rs` (the XML fixes before urdf-rs), `locate.rs` (the element and line of what
//! urdf-rs could not read, and the line of a link's or joint's field in the errors),
//! `validate.rs` (what is refused), `mass.rs` (inertia round-off, the load behind a joint,
//! [`friction_stiffness`]), `mesh.rs` (mesh
//! files, visual meshes), `joint.rs` (URDF joint → KJOINT2 property or rapier joint),
//! `describe.rs` (phase 1); phase 2 is [`crate::io::robot`], shared with MJCF.
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
//! * **Placement and names.** The robot stands where [`UrdfOptions::base_pose`] puts its
//!   root link's frame (default: the world origin); its links, colliders and joint frames
//!   are placed with it as they are described, so the loads measured below are where it
//!   stands. [`RobotDescription::prefix_names`] names a copy (`left/elbow`,
//!   [`NAME_SEPARATOR`]), after reading: the overrides name the file's joints. MJCF alike.
//! * **Frames.** The joint frame sits at the URDF joint origin; its local x is the URDF
//!   `<axis>` (the minimal rotation taking x to the axis, as rapier does), given to
//!   [`KjointBuilder::world_frame1`] and [`KjointBuilder::world_frame2`] in world coordinates. The URDF
//!   places each child link at joint position 0, so the loaded configuration is the unloaded
//!   one (`q = 0`). [`UrdfOptions::initial_positions`] starts revolute, continuous and
//!   prismatic joints elsewhere (a Panda at its ready pose): every link beyond such a joint
//!   is turned about its axis (slid along it) by `q0`, as forward kinematics places it,
//!   before the joint frames and loads are measured. KJOINT2 measures every DOF from the
//!   pose at insertion (kjoint2.md §3), so the joint's DOF reads `q − q0`, its stops stand
//!   at `lower − q0` and `upper − q0`, and [`UrdfRobotHandles::joint_position`] gives `q`
//!   ([`UrdfRobotHandles::initial_positions`] holds the `q0`). A prismatic joint's anchor
//!   on the child is the child's point that stood at the parent's anchor in the zero
//!   pose, so the anchors start together as they do there. A joint built by rapier reads
//!   `q` itself (its frames are those of the zero pose); its motor's `target` is a `q`.
//! * **Limits.** `<limit lower upper>` of revolute \[rad\] and prismatic \[m\] joints become the
//!   stops `SA-`/`SA+` (`SD-`/`SD+`) of the free DOF; continuous joints have none. KJOINT2
//!   reads a stop of 0 as "no stop" and needs `SD- ≤ 0 ≤ SD+`, so a limit at exactly 0 becomes
//!   `∓1e-9`, an infinite limit means no stop on that side, `lower = upper = 0` (the URDF
//!   default when `<limit>` only carries effort/velocity) means no stops, and a limit range
//!   that excludes the initial position is widened to include it (with a notice): give the
//!   joint an initial position within its range ([`UrdfOptions::initial_positions`], which
//!   refuses one outside it) and the range is kept.
//! * **Dynamics.** `<dynamics damping friction>` of revolute, continuous and prismatic joints
//!   become the viscosity `C` [N·s/m, N·m·s/rad] and the friction `FF`/`FM` [N, N·m] of the
//!   free DOF. The friction needs a spring stiffness `Kf` that URDF does not give, and beyond
//!   a KJOINT2 stop that spring **is** the stop (kjoint2.md §4.2), so it must hold the limit
//!   like the blocked DOFs hold the joint. It gets the implicit rule of the blocked DOFs
//!   ([`crate::law::stiffness`]) for the load the joint's axis carries
//!   ([`friction_stiffness`]):
//!
//!   `Kf = κ_eff·m_eff/h²`, `κ_eff = max(4, min(16, η·a·h²/(ε·r)))`, `h` = [`UrdfOptions::substep`],
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
//!   [`UrdfRobotHandles::joints`], which also lists the merged names). Root links are fixed when
//!   [`UrdfOptions::fixed_base`] is set (a root that is an empty `world` link with a fixed
//!   joint fixes its child in any case). A root link named `world` without mass is the
//!   fixed world (the ROS convention) whatever `fixed_base` says: when it is kept (it has a
//!   visual, or a moving joint to the base) it is a fixed body at the origin (where
//!   [`UrdfOptions::base_pose`] puts the robot), and in a scene it is the scene's `world`
//!   (unless the robot is placed there: a fixed body where it stands). Dynamic links without mass get
//!   [`UrdfOptions::min_link_mass`] (with the inertia of a ball of radius [`BALL_RADIUS`]) so
//!   the automatic stiffness is defined. Bodies never sleep unless
//!   [`UrdfOptions::can_sleep`]. The links must form a tree:
//!   joints that close a loop are refused ([`UrdfError::Loop`], naming them), since
//!   `rapier3d-urdf` would keep no root and the base would fall.
//! * **Fixed joints.** With [`UrdfOptions::fuse_fixed_joints`] (the default) the child link
//!   of a `fixed` joint is fused into its parent's body instead of being held by a KJOINT2
//!   fixed joint, as MuJoCo does for URDF (`fusestatic`) and PyBullet and Isaac offer
//!   ("merge fixed links"): a penalty joint lets a load that acts after the joint solve
//!   (rapier's contacts) turn a light link by `τ·h²/I` each substep (go1's 60 g feet: 0.3 rad
//!   at 240 Hz, the run stopped as unstable at 1.7 s). Done once on the
//!   [`RobotDescription`] for URDF and MJCF (`src/io/fuse.rs`): the child's colliders and
//!   visual meshes move to the parent's body (poses and triangles re-expressed in its
//!   frame), its mass properties (as rapier would sum them from its colliders and body) are
//!   added to the parent's in double precision by the parallel axis theorem and placed on
//!   the body as below ("Inertia"), chains fuse transitively, and every other joint on the
//!   child is attached to the parent with its anchors (a rapier joint's frames) re-expressed
//!   in the parent's frame (KJOINT2 frames are world frames). A child of a fixed body (a
//!   fixed root, `world`) becomes part of it: it was held there by a penalty joint, it is
//!   now exactly there. Not fused: a joint named in [`UrdfOptions::joints`] (the user wants
//!   it: its readout, a `break`, `engine = "rapier"`), one whose child is not dynamic, or
//!   all with the option off. [`UrdfRobotHandles::links`] keeps the fused link, mapped to
//!   the body it is part of; the joint has no entry in [`UrdfRobotHandles::joints`] but one
//!   in [`UrdfRobotHandles::fused_joints`] (with the link's frame in the body), and a notice
//!   `N fixed joints fused into their parent links: joint (child → parent), ...`. A
//!   scene joint's anchor on a fused link is in the frame of the body it is part of.
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
//!   descriptions) unless [`UrdfOptions::self_collisions`] is set, and then not across a
//!   joint (`contacts_enabled(false)`, as `rapier3d-urdf`'s joints); they do collide with
//!   everything else.
//! * **Meshes.** STL, COLLADA (`.dae`) and Wavefront (`.obj`) files. `package://PKG/path` is
//!   looked up in [`UrdfOptions::package_dirs`] (as `DIR/PKG/path`), then in the ancestors of
//!   the URDF file's directory (an ancestor named `PKG`, or one holding `PKG`); `file://`
//!   paths are absolute, others relative to the URDF file ([`resolve_mesh_path`]). A mesh
//!   that is not found, unreadable, degenerate or larger than the size cap of input files
//!   ([`crate::io::MAX_INPUT_BYTES`], which also holds for the URDF file) is skipped with a
//!   notice. `<visual>` meshes
//!   are read into [`UrdfRobotHandles::visual_meshes`] (body-frame triangles, for drawing: the rerun
//!   logger shows them with [`crate::output`]'s `RerunLogger::with_urdf_robot`); they are
//!   never simulated. Materials and textures are not read; a `<texture>` without a
//!   `filename` (`<texture/>`, which urdf-rs refuses: icub and romeo of example-robot-data)
//!   is removed with a notice naming its line.
//!
//! * **Rapier joints.** A joint whose override says `engine = "rapier"`
//!   ([`JointOverride::engine`]) is not a KJOINT2 joint but a rapier impulse joint in
//!   `world.impulse_joints` ([`UrdfRobotHandles::rapier_joints`]), solved by rapier with the
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
//! * **Motors on KJOINT2 joints**: the same `motor = { target, stiffness, damping,
//!   max_force }` on a revolute, continuous or prismatic KJOINT2 joint gives it a
//!   [`crate::KjointMotor`] on its axis DOF (`rx`, `dx`), driving `q` to `target` (the
//!   joint's `q − q0` to `target − q0`, [`UrdfOptions::initial_positions`]); a scene's
//!   `[[motors]]` moves its target, a program [`UrdfRobotHandles::set_motor_target`].
//! * **Ignored**: `<limit effort velocity>`, `<mimic>` (with a notice), `<safety_controller>`,
//!   `<calibration>`, transmissions and simulator tags; `<visual>` boxes, cylinders and
//!   spheres (the rerun logger draws the colliders) and materials.
//!
//! Every error names the file, the link or joint and the field ([`UrdfError`]), with the
//! line where the field is written (the joint's `<limit>`, the link's `<inertia>`, else the
//! link or joint: ``joint `elbow` (line 64): invalid limit.lower = NaN``); an
//! attribute urdf-rs cannot read (missing, not a number) is named with its element and line
//! (`locate.rs`); NaN and
//! infinite values are refused (except infinite limits, read as "no stop"), and so are
//! sizes, masses, inertias, origins, dynamics and every number of a
//! per-joint override (its single fields, `break`, `joint_friction`, a whole `property`, a
//! `motor`) beyond ±1e12 (the scene's
//! [`MAX_VALUE`](crate::scene::build::MAX_VALUE): rapier's f32 makes NaN or a panic of
//! them), and nothing panics on user input.

mod describe;
mod error;
mod joint;
mod joint_space;
mod locate;
mod mass;
mod mesh;
mod options;
mod sanitize;
mod validate;

pub use crate::io::robot::{
    FusedJoint, FusedLink, RobotDescription, RobotJoint, RobotJointKind, RobotLink, UrdfFormat,
    UrdfRobotHandles, NAME_SEPARATOR,
};
pub use crate::io::visual::VisualMesh;
pub use describe::WORLD_LINK;
pub use error::UrdfError;
pub(crate) use error::{in_range, with_line, ErrorContext, RANGES};
pub(crate) use joint::{
    apply_override, axis_dof, friction_by_rule, kjoint_builder, motor_dof, stops_from_limits,
    with_break, with_override_connector,
};
pub use joint::{FAR_LIMIT, ZERO_LIMIT};
pub(crate) use joint_space::{inverse_inertia_diagonal, TreeDof};
pub use mass::{friction_stiffness, BALL_RADIUS, INERTIA_ABS_ROUNDOFF, INERTIA_ROUNDOFF};
pub(crate) use mass::{
    load_beyond, mass_properties, place_mass, principal_axes, principal_mass_properties, LinkMass,
};
pub(crate) use mesh::read_mesh_file;
pub use mesh::resolve_mesh_path;
pub use options::{
    CollisionMeshes, JointEngine, JointOverride, RapierMotor, UrdfOptions, DEFAULT_SUBSTEP,
};
pub(crate) use validate::check_options;

use crate::io::robot::RobotFormat;
#[cfg(doc)]
use crate::{dynamics::KjointSet, law::JointType, rapier::pipeline::PhysicsWorld};
#[cfg(doc)]
use crate::{KjointBuilder, KjointProperty};
use std::path::Path;

/// A URDF robot read but not inserted: its links' bodies and colliders, its joints' KJOINT2
/// builders (or rapier joints), visual meshes and notices ([`RobotDescription`]). Made by
/// [`UrdfRobot::from_file`] or [`UrdfRobot::from_str`]; put into a world with
/// [`RobotDescription::insert`].
pub type UrdfRobot = RobotDescription<UrdfFormat>;

impl RobotFormat for UrdfFormat {
    fn describe(
        text: &str,
        file: &str,
        base: &Path,
        options: &UrdfOptions,
    ) -> Result<UrdfRobot, UrdfError> {
        describe::describe(text, file, base, options)
    }
}
