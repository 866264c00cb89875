//! MuJoCo (MJCF) robots with KJOINT2 joints.
//!
//! [`MjcfRobot::from_file`] / [`MjcfRobot::from_str`] read an MJCF model with
//! `rapier3d-mjcf` (parsed by `mjcf-rs`, which resolves `<default>` classes, `<include>`,
//! `<compiler angle>` and `autolimits`): bodies with their MJCF (or geom-derived) inertia,
//! geoms → colliders, and each joint with its frames. Instead of rapier's joints, every MJCF
//! joint is described as one KJOINT2 joint. The description ([`MjcfRobot`], a
//! [`RobotDescription`]) touches no world; its [`insert`](RobotDescription::insert) puts it
//! into a world and a [`KjointSet`], on the same footing as URDF robots
//! ([`crate::io::urdf`]): the same options ([`UrdfOptions`]), the same handles
//! ([`UrdfRobotHandles`]: bodies and joints by name, notices) and the same typed errors
//! ([`UrdfError`], naming the file, the element and the field). Nothing is stepped.
//!
//! # Files
//!
//! `check.rs` (what is refused, with the element and its line; a number mjcf-rs could not
//! read, an orientation that is not finite or that it would read as none, named by the
//! attribute written),
//! `option.rs` (`<option>`: the model's gravity, notices for what is not used),
//! `files.rs` (the files the model reads besides itself, held to the input cap, and the
//! one walk over its mesh geoms and their files that the checks and the notices share),
//! `unread.rs` (notices for what mjcf-rs drops from the body tree: `<replicate>`,
//! `<composite>`, `<flexcomp>`, an `<attach>` it cannot splice),
//! `describe.rs` (phase 1); phase 2 is [`crate::io::robot`], shared with URDF.
//!
//! # Mapping
//!
//! | MJCF `<joint type>` | KJOINT2 type | free DOFs |
//! |---|---|---|
//! | `hinge` | [`JointType::Revolute`] (2) | rx |
//! | `slide` | [`JointType::Translational`] (6) | dx |
//! | `ball` | [`JointType::Spherical`] (1) | rx, ry, rz |
//! | `free` | none: a floating body | all |
//! | (no joint) | fused into the parent's body ([`UrdfOptions::fuse_fixed_joints`], as for URDF: [`crate::io::urdf`] "Fixed joints"), else [`JointType::Fixed`] (8) to the parent; a fixed body on the world | – |
//!
//! * **Frames.** The joint frame sits at the joint's `pos`, its x along `axis` (hinge,
//!   slide), as `rapier3d-mjcf` builds them; the loaded pose (MuJoCo's `qpos0`, joint
//!   coordinate `ref`) is the unloaded one, `q = 0`. [`UrdfOptions::initial_positions`]
//!   (by joint name, the joint's value with `ref` included, in rad or m whatever the
//!   compiler's angle unit) starts hinges and slides elsewhere, as a keyframe would: the
//!   bodies beyond are moved there, the KJOINT2 joint measures from there, its range is
//!   taken from there, and [`crate::io::urdf::UrdfRobotHandles::joint_position`] gives
//!   the joint's value (`ref` included, as MuJoCo's `qpos`); a spring then rests there
//!   (notice). [`UrdfOptions::keyframe`] takes them from a `<keyframe><key>`'s `qpos` (the
//!   named hinges and slides; a free joint's pose and a ball's orientation are not applied,
//!   with a notice), the entries of `initial_positions` winning, and its `ctrl` starts the
//!   actuators (their servos hold the keyframe's pose).
//! * **Several joints in one body** are, as in MuJoCo, joints in series: `rapier3d-mjcf`
//!   puts a spacer body between each two of them (at the body's pose), and so does this
//!   loader, one KJOINT2 joint each. The spacers have no mass in MJCF; they get
//!   [`UrdfOptions::min_link_mass`] with the inertia of a ball of radius
//!   [`crate::io::urdf::BALL_RADIUS`] (with a notice naming the body), which the automatic
//!   stiffness needs. They are not merged into universal or spherical joints: the series is
//!   exact for any axes and positions, and a merged joint is not.
//! * **Stops.** `range` of a limited hinge \[rad, read in degrees unless `<compiler
//!   angle="radian">`\] or slide \[m\] (`limited="true"`, or `auto` with `autolimits`), minus
//!   the joint's value at insertion (`ref`, or its initial position), becomes `SA-`/`SA+` (`SD-`/`SD+`) exactly as URDF limits do
//!   ([`crate::io::urdf`]): a bound at 0 is `∓1e-9`, `0 0` is none, a range that excludes the
//!   initial position is widened (with a notice). A ball's `range` (a cone) is not mapped
//!   (notice).
//! * **Spring.** `stiffness` → the linear stiffness `K` of the free DOF, resting at
//!   `springref` (MuJoCo's `qpos_spring`): measured from the pose at insertion `q0` (`ref`,
//!   or the initial position), `F = K·(q − c)` with `c = springref − q0`, the curve
//!   `f(δ) = δ − c` (extrapolated linearly), so a joint inserted away from its spring's rest
//!   starts preloaded by `−K·c` (the `SpringCurvePreload` notice says so). `springdamper="timeconst dampratio"` sets both the spring and the
//!   damping as MuJoCo's compiler does, in place of `stiffness` and `damping`:
//!   `K = I/(timeconst·dampratio)²`, `C = 2·I/timeconst`, with `I = 1/(M⁻¹)_ii` the joint's
//!   inertia in the joint-space inertia `M` of the whole model as inserted (a base the
//!   options leave floating with its six degrees of freedom in it, the joints' armature on
//!   its diagonal), taken at the pose the robot is inserted in (MuJoCo's at `qpos0`: the same unless a keyframe or
//!   `initial_positions` moves the joints). A ball joint takes the damping only (its
//!   stiffness noticed).
//! * **Damping.** `damping` → the viscosity `C` (all three rotations of a ball).
//! * **Armature.** Noticed, not mapped by default (it opened a collapsing walker2d's light
//!   feet beyond 1 cm at a landing, README): the override's `armature`
//!   ([`UrdfOptions::joints`]) gives the axis DOF the rotor ([`crate::law::DofLaw::armature`])
//!   as MuJoCo adds it to the mass matrix's diagonal: the DOF resists a change of its rate as
//!   if `a` were added to its inertia, and the rotor's kinetic energy `½·a·q̇²` is the
//!   joint's ([`crate::law::JointEnergy::kinetic`]).
//! * **Actuators.** A `<position>` or `<velocity>` actuator on a hinge or slide →
//!   its [`crate::KjointMotor`] at the control the model starts with (the keyframe's
//!   `ctrl`, else 0, clamped into a limited `ctrlrange`): stiffness `gear²·kp`, damping
//!   `gear²·kv`, target `ctrl/gear`, capped at `|gear|·forcerange` where the force is
//!   limited (`actuators.rs` derives it);
//!   [`crate::io::urdf::UrdfRobotHandles::set_motor_target`] moves the target (a `q` of the
//!   file, `ctrl/gear`). `<motor>` → a motor of constant force `gear·ctrl`
//!   ([`crate::io::urdf::UrdfRobotHandles::set_motor_force`]); `<general>` of a fixed gain
//!   and an affine or no bias → one of the three (Menagerie's servos). Other `<general>`s,
//!   `<damper>`, `<intvelocity>`, actuators of tendons, sites or bodies and a second one on
//!   a joint are named in a notice, not mapped.
//! * **Friction.** `frictionloss` of a hinge or slide → the friction `FM`/`FF`, with the
//!   friction spring stiffness of the URDF loader ([`crate::io::urdf::friction_stiffness`],
//!   from the load beyond the joint); on a ball it is not mapped (notice).
//! * **Stiffness, bodies, collisions.** As for URDF: `Kn` = [`UrdfOptions::kn`] (0 =
//!   automatic), `Cr` = [`UrdfOptions::critical_damping`], per-joint `options.joints` by MJCF
//!   joint name (KJOINT2 fields only: `engine = "rapier"` is refused for MJCF). Bodies never
//!   sleep unless [`UrdfOptions::can_sleep`]. With [`UrdfOptions::fixed_base`] (the default, as for URDF) a body with a `free`
//!   joint is fixed where it is; `fixed_base = false` lets it float as in MuJoCo. Bodies
//!   without a joint whose parent is the world are fixed. Geoms that collide (`contype` or
//!   `conaffinity` ≠ 0) become colliders of density 0 (the MJCF inertia is the mass); mesh
//!   geoms their convex hull ([`UrdfOptions::collision_meshes`]); a `plane` geom (a floor) a
//!   half-space whose normal is the geom's z, through its `pos` (MuJoCo allows planes on
//!   static bodies only; its `size` only draws it; one on a moving body is not loaded, with
//!   a notice). The model's **environment**, the world
//!   body and the static bodies welded to it (MuJoCo's: no joint, not `mocap`, the parent
//!   the world or a static body) from which no moving body hangs (a table, not a fixed
//!   arm's base), is not the robot: its geoms touch the robot's links whatever
//!   [`UrdfOptions::self_collisions`], by MuJoCo's rule of `contype` and `conaffinity` (a
//!   pair none of whose geoms collide by it is left apart, as below), so a model run with
//!   `fixed_base = false` lands on its floor; a link joined to it does not touch it (the
//!   joint's contacts are off: a first link overlapping its mount; MuJoCo exempts the world
//!   from its parent filter). Unless [`UrdfOptions::self_collisions`], the
//!   robot's colliders do not collide
//!   with each other; with it, a body and its parent across a joint still do not (MuJoCo's
//!   default, `contacts_enabled(false)` on the KJOINT2 joint; across joints in series, an
//!   exclude of the pair past their spacer bodies), nor two bodies of a
//!   `<contact><exclude>` or none of whose geoms collide by their `contype` and
//!   `conaffinity` ([`crate::io::robot::RobotDescription::contact_excludes`]).
//! * **`<option>`** (`option.rs`). Its `gravity` is the model's,
//!   [`RobotDescription::gravity`] (zero with `<flag gravity="disable"/>`, as in MuJoCo;
//!   `None` where the model gives none: MuJoCo's [`MUJOCO_GRAVITY`]). A model run as a scene
//!   of its own runs under it ([`crate::scene::robot_scene`], `kjoint run robot.xml`: a
//!   MuJoCo user expects the model's gravity); in a scene file the scene's `gravity` applies
//!   (a notice says so when the model's differs); inserting a description leaves the
//!   world's gravity alone (a world may hold several robots): a program sets it. Its
//!   `timestep` is not used (the run steps at its own substeps), nor are its other
//!   attributes (integrator, solver, fluid and contact settings) and flags: a notice names
//!   each, with what the run uses instead. The notices and the flags are read from the
//!   model's own text, not from an `<include>`d file.

mod actuators;
mod check;
mod describe;
mod files;
mod option;
mod unread;

pub use crate::io::robot::{MjcfFormat, RobotDescription};
use crate::io::urdf::{UrdfError, UrdfOptions};

use crate::io::robot::RobotFormat;
#[cfg(doc)]
use crate::{dynamics::KjointSet, io::robot::UrdfRobotHandles, law::JointType};
use std::path::Path;

/// The gravity the MJCF model at `path` gives \[m/s²\] ([`RobotDescription::gravity`]: its
/// `<option gravity>`, zero with `<flag gravity="disable"/>`; `None` where it gives none),
/// read without building the model, for a robot file run as a scene of its own
/// ([`crate::scene::robot_scene`]). `None` too where the file cannot be read or parsed, or
/// its gravity is not finite within ±1e12: the loader reports those when the scene is built.
pub(crate) fn model_gravity(path: &Path) -> Option<[f64; 3]> {
    let (text, file, base) = crate::io::robot::read_robot_file(path).ok()?;
    files::check_includes(&file, &text, base).ok()?;
    let model = rapier3d_mjcf::mjcf_rs::model::Model::from_str(&text, base).ok()?;
    let doc = roxmltree::Document::parse(&text).ok();
    let context = crate::io::urdf::ErrorContext { file: &file };
    option::check(&context, &model, doc.as_ref()).ok()?;
    option::gravity(&model, doc.as_ref())
}

/// MuJoCo's gravity where a model's `<option>` gives none \[m/s²\].
pub const MUJOCO_GRAVITY: [f64; 3] = option::MUJOCO_GRAVITY;

/// An MJCF model read but not inserted: its bodies and colliders, its joints' KJOINT2
/// builders and notices ([`RobotDescription`]). Made by [`MjcfRobot::from_file`] or
/// [`MjcfRobot::from_str`]; put into a world with [`RobotDescription::insert`].
pub type MjcfRobot = RobotDescription<MjcfFormat>;

impl RobotFormat for MjcfFormat {
    fn describe(
        text: &str,
        file: &str,
        base: &Path,
        options: &UrdfOptions,
    ) -> Result<MjcfRobot, UrdfError> {
        describe::describe(text, file, base, options)
    }
}
