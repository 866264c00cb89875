//! The scene file format: pure serde data, no rapier.
//!
//! A scene is a TOML file (`.toml`) or a JSON file (`.json`) with the same structure. Every
//! table refuses unknown keys. All values are in the scene's unit system ([`Scene::units`],
//! SI by default) and converted explicitly into SI when the scene is built
//! ([`mod@super::build`]); angles are always radians. Rotations are given as an axis and an
//! angle or as a quaternion `[x, y, z, w]` ([`RotationSpec`]).
//!
//! ```toml
//! units = "SI"            # or e.g. "kg mm ms": every value below is in that system
//! gravity = [0, -9.81, 0] # [m/s²]
//! dt = 0.016666           # frame \[s\]
//! substeps = 16
//! duration = 2.0          # \[s\]
//!
//! [[bodies]]
//! name = "rod"
//! shape = { type = "cuboid", half_extents = [0.05, 0.5, 0.05] }
//! mass = 1.0
//! translation = [0, -0.5, 0]
//!
//! [[joints]]
//! name = "hinge"
//! body1 = "world"
//! body2 = "rod"
//! anchor2 = [0, 0.5, 0]
//! frame = { axis = [0, 1, 0], angle = -1.5707963 }  # joint x axis = world z
//! property = { type = "revolute", rx = { stop_max = 0.3, friction_stiffness = 50, friction = 0.05 } }
//! ```
//!
//! Beside the KJOINT2 joints, a scene holds rapier's own joints and contacts in the same
//! world: URDF joints built as rapier impulse joints (`engine = "rapier"` in a robot's
//! options, [`RobotSpec`]) with their motor targets over time ([`MotorSpec`],
//! `[[motors]]`), bodies that touch (`collide = true`), kinematic bodies with a prescribed
//! motion ([`MotionSpec`], `[[motions]]`), and the settings of rapier's solver
//! ([`RapierSpec`], `[rapier]`). `assets/scenes/arm_gripper.toml` uses them all: an arm on
//! KJOINT2 joints lifts a box gripped by fingers on rapier joints.

use crate::law::{DofLaw, FlexProAdd, JointFriction, JointType, PlanarFriction};
use serde::{Deserialize, Serialize};

/// A whole scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Unit system of every value of the scene: `"SI"` (default, when `units` is left out)
    /// or three unit names `"mass length time"`, e.g. `"kg mm ms"` (names of
    /// [`crate::io::units::mass_unit`] and friends); an empty or blank string is refused.
    /// Angles are radians in every system.
    #[serde(default = "default_units")]
    pub units: String,
    /// Gravity [length/time²], default `[0, -9.81, 0]` m/s² (given in the scene's units).
    #[serde(default, deserialize_with = "exact_opt")]
    pub gravity: Option<[f64; 3]>,
    /// Frame time step \[time\] (default 1/60 s): the interval of the loads' sampling for the
    /// per-frame log and of the progress bar. A substep `dt / substeps` is at most 1 s
    /// ([`crate::scene::MAX_SUBSTEP_TIME`]).
    #[serde(default)]
    pub dt: Option<f64>,
    /// Substeps per frame (default 16); the joints and loads are evaluated at every one.
    #[serde(default = "default_substeps")]
    pub substeps: usize,
    /// rapier's own solver, for contacts and rapier joints.
    #[serde(default)]
    pub rapier: RapierSpec,
    /// Radioss-compatible start (default false): the first substep is a half kick, as
    /// Radioss' central difference starts, so that time histories compare with a Radioss
    /// run at its own time step (with `dt` the deck's step and one substep). Off, a load
    /// applied at `t = 0` acts as if it started half a substep earlier
    /// ([`crate::SubstepSettings::radioss_start`]).
    #[serde(default)]
    pub radioss_start: bool,
    /// Simulated time \[time\] (> 0).
    pub duration: f64,
    /// The rigid bodies.
    #[serde(default)]
    pub bodies: Vec<BodySpec>,
    /// URDF and MJCF robots: their links become bodies (named after the links, or
    /// `"{name}/{link}"` for a robot with a `name`), their joints KJOINT2 joints (named after
    /// the file's joints, likewise), usable by the joints, sensors and loads below, or rapier
    /// impulse joints where the options ask for them (usable by the motors).
    #[serde(default)]
    pub robots: Vec<RobotSpec>,
    /// The KJOINT2 joints.
    #[serde(default)]
    pub joints: Vec<JointSpec>,
    /// The sensors that lock the joints whose property names them.
    #[serde(default)]
    pub sensors: Vec<SensorSpec>,
    /// Applied forces and torques.
    #[serde(default)]
    pub loads: Vec<LoadSpec>,
    /// Prescribed motions of bodies that are not dynamic (they become kinematic).
    #[serde(default)]
    pub motions: Vec<MotionSpec>,
    /// Time schedules of the motor targets of rapier joints (URDF joints built with
    /// `engine = "rapier"`).
    #[serde(default)]
    pub motors: Vec<MotorSpec>,
    /// Joints switched off (released) or on at given times.
    #[serde(default)]
    pub switches: Vec<SwitchSpec>,
    /// What is written during the run.
    #[serde(default)]
    pub output: OutputSpec,
}

fn default_units() -> String {
    "SI".into()
}

fn default_substeps() -> usize {
    16
}

fn default_pgs_iterations() -> usize {
    1
}

/// Settings of rapier's own solver, which solves the contacts and the rapier joints (URDF
/// joints with `engine = "rapier"`) inside every substep; the KJOINT2 joints do not depend
/// on them. A scene's world has no speed cap (rapier's `normalized_max_linear_velocity`,
/// 400 m/s by default, is lifted: it clipped a block at 500 m/s to 400 m/s silently), nor a
/// spin cap (every body allows fast rotation: rapier clamps a body's angular speed to π/4 a
/// step otherwise).
///
/// ```toml
/// [rapier]
/// pgs_iterations = 4            # default 1
/// friction_in_bias_pass = true  # default false
/// ```
///
/// A scene whose bodies are held by friction needs both: a box gripped by two fingers on
/// rapier joints was not lifted at the defaults (the fingers' motors and contacts do not
/// converge in one iteration), nor with friction in the bias pass alone; with 4 iterations
/// alone it was lifted 79 mm of 100 and dropped; with both it rose 98 mm and was held
/// (`assets/scenes/arm_gripper.toml`; the same with every joint a rapier one: not lifted,
/// sliding out at 7 mm/s, 94 mm and held). rapier's own substeps (`num_solver_iterations`,
/// [`crate::SubstepSettings::rapier_iterations`]) stay at 1: more of them change how rapier
/// advances the positions within the substep, which the stiff KJOINT2 joints see as a
/// deflection of the order of their sag under load (the URDF arm's energy balance went from
/// 0.001 % to 6 % at 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RapierSpec {
    /// Iterations of rapier's constraint solver in each substep (rapier's
    /// `IntegrationParameters::num_internal_pgs_iterations`, 1 ..= 1000, default 1 as in
    /// rapier).
    #[serde(default = "default_pgs_iterations")]
    pub pgs_iterations: usize,
    /// Friction is also solved in rapier's biased (position-correcting) pass (rapier's
    /// `IntegrationParameters::friction_in_bias_pass`, default false as in rapier).
    #[serde(default)]
    pub friction_in_bias_pass: bool,
}

impl Default for RapierSpec {
    fn default() -> Self {
        RapierSpec {
            pgs_iterations: default_pgs_iterations(),
            friction_in_bias_pass: false,
        }
    }
}

/// Whether a body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyKind {
    /// Moves under forces (default).
    #[default]
    Dynamic,
    /// Never moves.
    Fixed,
}

/// A rigid body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Unique name (`"world"` is reserved for the fixed ground).
    pub name: String,
    /// `"dynamic"` (default) or `"fixed"`.
    #[serde(default)]
    pub kind: BodyKind,
    /// Shape of its collider, which gives the inertia.
    pub shape: ShapeSpec,
    /// Mass \[mass\] (> 0); the inertia is the shape's scaled to this mass. Exclusive with
    /// `density`.
    pub mass: Option<f64>,
    /// Density [mass/length³] (> 0), exclusive with `mass`. Neither: density 1000 kg/m³.
    pub density: Option<f64>,
    /// Position of the body origin (the shape's centre) in the world \[length\].
    #[serde(default, deserialize_with = "exact")]
    pub translation: [f64; 3],
    /// Orientation in the world (default identity).
    pub rotation: Option<RotationSpec>,
    /// Initial linear velocity [length/time].
    #[serde(default, deserialize_with = "exact")]
    pub linvel: [f64; 3],
    /// Initial angular velocity [rad/time].
    #[serde(default, deserialize_with = "exact")]
    pub angvel: [f64; 3],
    /// Whether the body touches others (default `false`: only the joints connect bodies).
    #[serde(default)]
    pub collide: bool,
}

/// Shape of a body's collider, in the body's frame, centred on its origin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum ShapeSpec {
    /// A sphere.
    Ball {
        /// Radius \[length\] (> 0).
        radius: f64,
    },
    /// A box.
    Cuboid {
        /// Half sizes along x, y, z \[length\] (> 0).
        #[serde(deserialize_with = "exact")]
        half_extents: [f64; 3],
    },
    /// A capsule along the body's y axis.
    Capsule {
        /// Half length of the cylindrical part \[length\] (> 0).
        half_height: f64,
        /// Radius \[length\] (> 0).
        radius: f64,
    },
    /// A cylinder along the body's y axis.
    Cylinder {
        /// Half length \[length\] (> 0).
        half_height: f64,
        /// Radius \[length\] (> 0).
        radius: f64,
    },
}

/// A rotation: either `axis` and `angle` (right-hand rule, the axis need not be unit) or a
/// unit `quaternion = [x, y, z, w]` (normalised if within 1e-3 of unit length).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotationSpec {
    /// Rotation axis (non-zero).
    #[serde(default, deserialize_with = "exact_opt")]
    pub axis: Option<[f64; 3]>,
    /// Angle about `axis` \[rad\].
    pub angle: Option<f64>,
    /// Quaternion `[x, y, z, w]`.
    #[serde(default, deserialize_with = "exact_opt")]
    pub quaternion: Option<[f64; 4]>,
}

/// A URDF robot ([`crate::io::urdf`]) or a MuJoCo MJCF one ([`crate::io::mjcf`], `mjcf =
/// "robot.xml"` in place of `urdf`) loaded into the scene, where its description puts it or
/// placed by `position` and `rotation`, under its file's names or prefixed by `name`.
///
/// ```toml
/// [[robots]]
/// urdf = "../urdf/arm.urdf"   # relative to the scene file
/// name = "left"               # bodies and joints `left/base_link`, `left/elbow`, ...
/// position = [0.0, 0.5, 0.0]  # [m] the robot's frame in the world
/// rotation = { axis = [0, 0, 1], angle = 1.5707963267948966 }  # [rad]
/// [robots.options]            # crate::io::urdf::UrdfOptions, all optional
/// kn = 0.0                    # blocked stiffness of every joint [N/m] (0 = automatic)
/// [robots.options.joints.elbow]
/// friction = 2.0              # per-joint overrides by the file's joint name
/// ```
///
/// URDF is in SI, and so are these options: a scene with robots must be in SI units.
/// `options.substep` defaults to the scene's substep.
///
/// A joint can be a rapier impulse joint instead of a KJOINT2 one, with the URDF limits and
/// a motor (see [`crate::io::urdf`], "Rapier joints"); its motor target is scheduled by
/// `[[motors]]` ([`MotorSpec`]):
///
/// ```toml
/// [robots.options.joints.left_finger]
/// engine = "rapier"
/// motor = { stiffness = 1000.0, damping = 10.0, max_force = 20.0 }  # N/m, N·s/m, N
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// The URDF file, relative to the scene file (exactly one of `urdf` and `mjcf`).
    #[serde(default)]
    pub urdf: Option<String>,
    /// The MuJoCo MJCF file ([`crate::io::mjcf`]), relative to the scene file (exactly one
    /// of `urdf` and `mjcf`); the same `options`, joints named as in the MJCF.
    #[serde(default)]
    pub mjcf: Option<String>,
    /// A name for this copy of the robot (non-empty): every body and joint it makes is
    /// named `"{name}/{link}"`, `"{name}/{joint}"` (`left/elbow`,
    /// [`crate::io::urdf::NAME_SEPARATOR`]) in the scene, so that two copies of one file load
    /// side by side. The rest of the scene names them so (`[[joints]]` `body1`/`body2`,
    /// `[[sensors]]` `joint`, `[[loads]]` and `[[motions]]` `body`, `[[motors]]` `joint`),
    /// and so do the outputs (the CSV history of `left/elbow` is `left_elbow.csv`); the
    /// `options.joints` overrides keep the file's names (`joints.elbow`). Absent: the file's
    /// names as they are.
    #[serde(default)]
    pub name: Option<String>,
    /// Where the robot's own frame (a URDF's root link, an MJCF model's `<worldbody>`)
    /// stands in the world \[length\] (default `[0, 0, 0]`; robots are in SI scenes, so
    /// metres). Every link, collider and joint frame of the robot is placed with it, a fixed
    /// base too ([`crate::io::urdf::UrdfOptions::base_pose`]).
    #[serde(default, deserialize_with = "exact_opt")]
    pub position: Option<[f64; 3]>,
    /// The orientation of the robot's own frame in the world (default identity), as a
    /// body's `rotation`: `{ axis = [0, 0, 1], angle = 1.5707963267948966 }` or
    /// `{ quaternion = [x, y, z, w] }`. A placed robot's massless root link `world` (ROS) or
    /// MJCF world body is a fixed body where the robot stands, not the scene's `world`
    /// (named `"{name}/world"` when the robot has a name).
    #[serde(default)]
    pub rotation: Option<RotationSpec>,
    /// How the robot becomes bodies and KJOINT2 joints.
    #[serde(default)]
    pub options: crate::io::urdf::UrdfOptions,
}

/// A KJOINT2 joint between two bodies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// Unique name (used for messages and the CSV file name).
    pub name: String,
    /// Body 1: a body name, or `"world"` (a fixed body at the origin).
    pub body1: String,
    /// Body 2: a body name, or `"world"`.
    pub body2: String,
    /// Anchor on body 1 in its local frame \[length\] (for `"world"`: world coordinates).
    #[serde(default, deserialize_with = "exact")]
    pub anchor1: [f64; 3],
    /// Anchor on body 2 in its local frame \[length\].
    #[serde(default, deserialize_with = "exact")]
    pub anchor2: [f64; 3],
    /// Radioss `Skew_ID1`: the joint's axes in the world at creation (the columns of this
    /// rotation); default: the `Skew_ID1` of a deck property, else from the anchors'
    /// geometry (x from anchor 1 to anchor 2, or the world axes when they coincide). Refused
    /// when the deck property has a `Skew_ID1`.
    pub frame: Option<RotationSpec>,
    /// Radioss `Skew_ID2`: body 2's axes at creation (initial relative rotation); default:
    /// the `Skew_ID2` of a deck property. Refused when the deck property has a `Skew_ID2`.
    pub frame2: Option<RotationSpec>,
    /// The KJOINT2 property, inline or from a deck.
    pub property: PropertySpec,
    /// Load-dependent friction on the free DOFs of a planar joint (type 4), the PLANAR
    /// connector law (see [`crate::law::connector`]): friction limited by `μ·F_N` in the
    /// plane and `μ·M_N` about the normal, with `F_N = | |f1| + √(m2²+m3²)/R + F_int |` and
    /// `M_N = | (2/3)·R·|f1| + √(m2²+m3²) + M_int |` built from the joint's own blocked-DOF
    /// forces. The fields of [`PlanarFriction`], in the scene's units (`radius` a length,
    /// `internal_force` a force, `internal_moment` a moment, `stick_stiffness`
    /// force/length, `stick_rotational_stiffness` moment/rad); only `mu` is required:
    /// `planar_friction = { mu = 0.3, radius = 0.05 }`. Exclusive with `flex_joint`.
    pub planar_friction: Option<PlanarFriction>,
    /// Riser flex joint law on a spherical joint (type 1), x the riser axis (see
    /// [`crate::law::connector`]). Exclusive with `planar_friction`.
    pub flex_joint: Option<FlexJointSpec>,
    /// Load-dependent friction on a revolute, cylindrical or translational joint
    /// (docs/joint_friction.md): bounded by `μ` times `F_N = |F_r + M_b/L + F_pre|` built
    /// from the joint's own radial reaction and bending moment. The fields of
    /// [`JointFriction`] in the scene's units (`pin_radius`, `length`, `thrust_radius`
    /// lengths, `preload` a force, `stick_stiffness` force/length,
    /// `stick_rotational_stiffness` moment/rad); `mu` is required, and `pin_radius` on a
    /// revolute joint: `joint_friction = { mu = 0.2, pin_radius = 0.01, length = 0.05 }`.
    /// One connector law per joint.
    pub joint_friction: Option<JointFriction>,
    /// When the joint breaks (docs/breakable.md): the `break` table, the fields of
    /// [`crate::law::BreakCriterion`] in the scene's units (`force` a force, `moment` a
    /// moment, `dissipated_energy` an energy; 0 or absent: no such limit), e.g.
    /// `break = { force = 1e4, moment = 500.0, force_exponent = 2, moment_exponent = 2 }`.
    /// Absent: the joint never breaks.
    #[serde(rename = "break")]
    pub break_criterion: Option<crate::law::BreakCriterion>,
    /// Whether the two bodies touch each other where both `collide` (default `true`):
    /// `false` leaves this pair apart (links whose shapes overlap at the joint), each body
    /// still touching the others ([`crate::KjointBuilder::contacts_enabled`]).
    #[serde(default = "default_true")]
    pub contacts: bool,
    /// Whether the joint acts from the start (default `true`); `false` inserts it switched
    /// off, for a `[[switches]]` entry to switch on ([`crate::KjointBuilder::enabled`]).
    #[serde(default = "default_true")]
    pub enabled: bool,
}

fn default_true() -> bool {
    true
}

/// A riser flex joint (`flex_joint.md`): either a reference `{ deck = "riser.dat",
/// element = NEL }` to a `*FLEXJOINT` element of a riser deck (path relative to the scene
/// file; riser decks are in SI), or the law inline in the scene's units. `switch_time` may
/// be given with either.
///
/// ```toml
/// [joints.flex_joint]
/// switch_time = 2.0                                     # \[time\]
/// bending = [[0.0, 0.0], [0.01, 2.0e4], [0.02, 3.0e4]]  # IPRO: [rad, moment]
/// dynamic = { torsion_stiffness = 1e6, kdyn_ini = 4e6, kdyn_lim = 1.7e6, angle_lim = 1.7e-3 }
/// ```
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlexJointSpec {
    /// Riser deck holding the element (exclusive with the inline fields).
    pub deck: Option<String>,
    /// `NEL` of the `*FLEXJOINT` element in `deck`.
    pub element: Option<u64>,
    /// `IPRO`: bending law (classical mode: law of the total angle), pairs
    /// `[angle \[rad\], moment [moment]]`, angles strictly increasing.
    #[serde(default, deserialize_with = "exact_points_opt")]
    pub bending: Option<Vec<[f64; 2]>>,
    /// `IPROT`: torsion law, pairs `[angle \[rad\], moment [moment]]`.
    #[serde(default, deserialize_with = "exact_points_opt")]
    pub torsion: Option<Vec<[f64; 2]>>,
    /// `*FLEXPROADD`: dynamic bilinear hysteretic bending law, torsion stiffness and damping
    /// ([`FlexProAdd`]: `kdyn_ini`, `kdyn_lim`, `angle_lim` required; `torsion_stiffness`,
    /// `torsion_damping`, `teta` default to 0 and `iflag` to 1), stiffnesses in moment/rad,
    /// `torsion_damping` in moment·time/rad.
    pub dynamic: Option<FlexProAdd>,
    /// Time of the quasi-static → dynamic switch \[time\] (needs `dynamic`; none: the run
    /// stays quasi-static).
    pub switch_time: Option<f64>,
}

/// A KJOINT2 property: either inline (`type` and the fields below, in the scene's units),
/// or a reference `{ deck = "file.rad", id = N }` to a `/PROP/TYPE45` block of a Radioss
/// deck (path relative to the scene file; converted into SI with the deck's `/UNIT`, or its
/// `/BEGIN` input units).
///
/// For a rotational DOF read N·m/rad for N/m, rad for m and N·m for N in the DOF tables
/// ([`DofLaw`]). Zero means "default" or "not set", as in Radioss.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PropertySpec {
    /// Radioss deck that holds the property (exclusive with the inline fields).
    pub deck: Option<String>,
    /// `prop_ID` of the property in `deck`.
    pub id: Option<u32>,
    /// Joint type: `spherical`, `revolute`, `cylindrical`, `planar`, `universal`,
    /// `translational` (or `prismatic`, rapier's name), `oldham` (type 7, old revolute),
    /// `fixed` or `free`.
    #[serde(rename = "type")]
    pub joint_type: Option<JointType>,
    /// `Kn` [force/length]: penalty stiffness of the blocked DOFs; 0 = automatic.
    pub kn: Option<f64>,
    /// The rule of the automatic stiffness (`kn = 0`): `"implicit"` (default: from the load
    /// each joint carries and the substep, [`crate::law::stiffness`]) or `"radioss"` (spec
    /// §5, as OpenRadioss; properties of a deck reference always use it).
    pub automatic: Option<crate::law::AutomaticStiffness>,
    /// `ScF`: stiffness scale factor (0 = default: 1, or 10 m² whatever the scene's units when
    /// `kn > 0`; \[length²\] when `kn > 0`).
    pub scale_factor: Option<f64>,
    /// `Cr`: critical damping ratio in [0, 1] (0 = 0.05).
    pub critical_damping: Option<f64>,
    /// `sens_ID`: id of a sensor of [`Scene::sensors`] that locks the joint once active; 0
    /// (as in a Radioss deck) or absent: no sensor.
    pub sensor: Option<u32>,
    /// Law of the translation along x [force/length, length, force·time/length, force].
    pub dx: Option<DofLaw>,
    /// Law of the translation along y.
    pub dy: Option<DofLaw>,
    /// Law of the translation along z.
    pub dz: Option<DofLaw>,
    /// Law of the rotation about x [moment/rad, rad, moment·time/rad, moment].
    pub rx: Option<DofLaw>,
    /// Law of the rotation about y.
    pub ry: Option<DofLaw>,
    /// Law of the rotation about z.
    pub rz: Option<DofLaw>,
}

impl PropertySpec {
    /// The DOF tables in the order dx, dy, dz, rx, ry, rz.
    pub fn dof_laws(&self) -> [&Option<DofLaw>; 6] {
        [&self.dx, &self.dy, &self.dz, &self.rx, &self.ry, &self.rz]
    }
}

/// A sensor: exactly one of `time`, `passes` or `force_reaches`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// Id referenced by the properties' `sensor` (Radioss `sens_ID`): 1 or more (0 is "no
    /// sensor" in a property).
    pub id: u32,
    /// Activates at this time \[time\] (≥ 0).
    pub time: Option<f64>,
    /// The watched joint's name (with `passes` or `force_reaches`).
    pub joint: Option<String>,
    /// The watched DOF: `dx`, `dy`, `dz`, `rx`, `ry` or `rz`.
    pub dof: Option<crate::law::Dof>,
    /// Activates when the DOF passes this value [length or rad], from either side.
    pub passes: Option<f64>,
    /// Activates when the magnitude of the force (moment) the DOF transmitted over a
    /// substep reaches this value [force or moment] (> 0).
    pub force_reaches: Option<f64>,
}

/// A force or a torque applied to a body, `vector · function(t)`, in world axes at the
/// body's centre of mass. Exactly one of `force` and `torque`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// The loaded body.
    pub body: String,
    /// Force \[force\] (world axes).
    #[serde(default, deserialize_with = "exact_opt")]
    pub force: Option<[f64; 3]>,
    /// Torque [force·length] (world axes).
    #[serde(default, deserialize_with = "exact_opt")]
    pub torque: Option<[f64; 3]>,
    /// Dimensionless time function multiplying the vector (default: constant 1).
    pub function: Option<TimeFunction>,
}

/// A prescribed motion of a body that is not dynamic: a scene body of `kind = "fixed"` or
/// the fixed root link of a URDF robot (not `"world"`). The body becomes a kinematic body
/// (rapier's `KinematicVelocityBased`): it moves as prescribed whatever pushes on it, and
/// the joints and contacts it carries move with it. Translations only; exactly one of
/// `displacement` and `velocity`:
///
/// ```toml
/// [[motions]]                 # a lift: rises by 0.1 m between t = 1 s and t = 2 s
/// body = "base_link"
/// displacement = [0, 0, 0.1]  # [length], world axes: position = initial + displacement·f(t)
/// function = { curve = [[1.0, 0.0], [1.5, 0.5], [2.0, 1.0]] }
/// ```
///
/// With `displacement` the body is at `initial + displacement·f(t)` at the end of every
/// substep (its velocity over a substep is the difference of the positions at its ends, by
/// `h`); with `velocity` [length/time] it moves at `velocity·f(t)`, taken at the substep's
/// middle. The energy a motion gives the model through the KJOINT2 joints it carries is
/// counted with the work of the loads in the energy balance
/// ([`crate::KjointSet::driven_work`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSpec {
    /// The moving body.
    pub body: String,
    /// Displacement from the initial position \[length\] (world axes), times `function`.
    #[serde(default, deserialize_with = "exact_opt")]
    pub displacement: Option<[f64; 3]>,
    /// Velocity [length/time] (world axes), times `function`.
    #[serde(default, deserialize_with = "exact_opt")]
    pub velocity: Option<[f64; 3]>,
    /// Dimensionless time function multiplying the vector (default: constant 1).
    pub function: Option<TimeFunction>,
}

/// The position target of a robot joint's motor over time, `target·f(t)` [m or rad]: the
/// joint is a URDF joint with a `motor` (its stiffness, damping and largest force) in the
/// robot's options, a rapier joint (`engine = "rapier"`: rapier's motor) or a KJOINT2 one
/// (a [`crate::KjointMotor`] on its axis; the target a `q` of the file, as
/// `UrdfRobotHandles::joint_position` reads it). Or, instead of `target`, the constant
/// force of a KJOINT2 joint's motor over time, `force·f(t)` [N or N·m]
/// ([`crate::KjointMotor::force`]: an effort command, or the feed-forward of the motor its
/// options give it; a joint without one gets a motor of that force alone). Set at the start
/// of every substep.
///
/// ```toml
/// [[motors]]                  # close a finger by 30 mm between t = 0.3 s and t = 0.8 s
/// joint = "left_finger"
/// target = 0.03               # [m] (prismatic) or [rad] (revolute)
/// function = { curve = [[0.3, 0.0], [0.8, 1.0]] }
///
/// [[motors]]                  # a torque of 2 N·m on the elbow from t = 1 s
/// joint = "elbow"
/// force = 2.0                 # [N·m] (revolute) or [N] (prismatic)
/// function = { curve = [[1.0, 0.0], [1.01, 1.0]] }
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotorSpec {
    /// The joint, by its URDF name.
    pub joint: String,
    /// Target position [m or rad] (URDF robots are SI), times `function`; or `force`.
    #[serde(default)]
    pub target: Option<f64>,
    /// Constant force [N or N·m] of a KJOINT2 joint's motor, times `function`; or
    /// `target`.
    #[serde(default)]
    pub force: Option<f64>,
    /// Dimensionless time function multiplying the target (default: constant 1).
    pub function: Option<TimeFunction>,
}

/// A KJOINT2 joint (a scene's or a robot's, by name) switched off or on at a time
/// ([`crate::KjointSet::set_enabled`]): at the start of the first substep that begins at
/// `time` or after (within half a substep). Switched off, the joint acts on nothing (a
/// payload released, a stage separated); its state and energies are kept. Switched on, it
/// pulls its bodies back towards the configuration they had at its insertion (the joint's
/// frames are attached to the bodies then), as an event's lock would.
///
/// ```toml
/// [[switches]]               # release the payload at t = 0.5 s
/// joint = "hook"
/// time = 0.5                 # [time]
/// enabled = false
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwitchSpec {
    /// The joint, by its name (a robot's joint by the name the scene gives it).
    pub joint: String,
    /// When \[time\] (≥ 0).
    pub time: f64,
    /// `false` switches the joint off, `true` on.
    pub enabled: bool,
}

/// A dimensionless function of time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum TimeFunction {
    /// `{ constant = c }`.
    Constant(f64),
    /// `{ curve = [[t0, v0], [t1, v1], ...] }`: piecewise linear in time \[time\], constant
    /// beyond the first and last points.
    Curve(#[serde(deserialize_with = "exact_points")] Vec<[f64; 2]>),
    /// `{ sine = { amplitude = a, frequency = f, phase = p, offset = o, start = s } }`:
    /// `o + a·sin(2π·f·(t − s) + p)` from `t = s` on, 0 before (`s` defaults to 0).
    Sine(Sine),
}

/// Parameters of [`TimeFunction::Sine`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sine {
    /// Amplitude (dimensionless).
    pub amplitude: f64,
    /// Frequency [1/time] (≥ 0).
    pub frequency: f64,
    /// Phase \[rad\].
    #[serde(default)]
    pub phase: f64,
    /// Offset (dimensionless).
    #[serde(default)]
    pub offset: f64,
    /// Start time \[time\] (≥ 0): the function is 0 before it and its phase counts from it.
    #[serde(default)]
    pub start: f64,
}

/// When the observers are called.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LogEvery {
    /// After every frame (default).
    #[default]
    Frame,
    /// After every substep.
    Substep,
}

/// Outputs of a run (the command line overrides them).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Directory of the CSV time histories (one file per joint), relative to the scene file.
    pub csv: Option<String>,
    /// Rerun recording file (needs the `rerun` feature), relative to the scene file.
    pub rrd: Option<String>,
    /// `"frame"` (default) or `"substep"`.
    #[serde(default)]
    pub log: LogEvery,
}

/// A fixed-size array of numbers read in full: `[0, -9.81, 0, 5]` for a vector of 3 is
/// refused (TOML's reader dropped the numbers beyond the third without a word, JSON's said
/// `trailing characters`).
fn exact<'de, D: serde::Deserializer<'de>, const N: usize>(d: D) -> Result<[f64; N], D::Error> {
    Ok(Exact::<N>::deserialize(d)?.0)
}

/// [`exact`] of an optional array.
fn exact_opt<'de, D: serde::Deserializer<'de>, const N: usize>(
    d: D,
) -> Result<Option<[f64; N]>, D::Error> {
    Ok(Option::<Exact<N>>::deserialize(d)?.map(|e| e.0))
}

/// A list of `[x, y]` points, each read in full ([`exact`]).
fn exact_points<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<[f64; 2]>, D::Error> {
    Ok(Vec::<Exact<2>>::deserialize(d)?
        .into_iter()
        .map(|e| e.0)
        .collect())
}

/// [`exact_points`] of an optional list.
fn exact_points_opt<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<[f64; 2]>>, D::Error> {
    Ok(Option::<Vec<Exact<2>>>::deserialize(d)?
        .map(|points| points.into_iter().map(|e| e.0).collect()))
}

/// An array of exactly `N` numbers. Its length is checked while the array is read, so that
/// the reader places a wrong length at the array: JSON's reader placed an error raised once
/// the array was read after the end of the object holding it (`"position": [1, 2]` as the
/// last member of a robot was reported at the robot, `robots[0]`, not at `position`).
struct Exact<const N: usize>([f64; N]);

impl<'de, const N: usize> Deserialize<'de> for Exact<N> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Numbers<const N: usize>;
        impl<'de, const N: usize> serde::de::Visitor<'de> for Numbers<N> {
            type Value = Exact<N>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "an array of length {N}")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Exact<N>, A::Error> {
                let mut out = [0.0; N];
                let mut len = 0;
                // every element read, to say how many there are
                while let Some(v) = seq.next_element::<f64>()? {
                    if let Some(slot) = out.get_mut(len) {
                        *slot = v;
                    }
                    len += 1;
                }
                if len != N {
                    return Err(serde::de::Error::invalid_length(len, &self));
                }
                Ok(Exact(out))
            }
        }
        d.deserialize_seq(Numbers::<N>)
    }
}
