//! Turns a parsed [`Scene`] into a rapier world, a [`KjointSet`] and the applied loads,
//! after checking every value and converting it into SI (kg, m, s).
//!
//! Nothing is simulated here. Unit conversion is explicit: every scene value is multiplied
//! by the factor of its dimension ([`UnitSystem::factor`]); inline properties go through
//! [`crate::io::units::property_to_si`]; deck properties are taken in SI as the deck reader
//! converted them with the deck's own `/UNIT` (or its `/BEGIN` input units).
//!
//! [`build`] reads the scene's sections in order, one file each:
//! - `settings`: `units`, `gravity`, `dt`, `substeps`, `duration`, `[rapier]`;
//! - `bodies`: `[[bodies]]`;
//! - `robots`: `[[robots]]` (URDF and MJCF);
//! - `joints`: `[[joints]]`, with their `property` (`properties`) and their connector law
//!   (`connectors`);
//! - `sensors`: `[[sensors]]`;
//! - `loads`, `motions`, `motors`: `[[loads]]`, `[[motions]]`, `[[motors]]`, with their
//!   time functions (`time`);
//! - `checks`: the checks of single values every section uses (finite, positive, ...);
//!   `files`: the files the scene names, found next to it and read once.

mod bodies;
mod checks;
mod connectors;
mod files;
mod free_fall;
mod joints;
mod loads;
mod motions;
mod motors;
mod overlap;
mod properties;
mod robots;
mod sensors;
mod settings;
mod switches;
mod time;

pub use loads::Load;
pub use motions::{Motion, MotionKind};
pub use motors::{Motor, MotorJoint};
pub use properties::PropertyOrigin;
pub use settings::parse_units;
pub use switches::Switch;
pub use time::{ClampedCurve, TimeFn};

use super::schema::{LogEvery, Scene};
use super::{SceneError, Source};
use crate::io::units::UnitSystem;
use crate::rapier::dynamics::ImpulseJointHandle;
use crate::rapier::prelude::*;
use crate::{KjointHandle, KjointSet, SubstepSettings};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A scene ready to run: everything in SI.
pub struct BuiltScene {
    /// The rapier world (bodies, colliders, gravity).
    pub world: PhysicsWorld,
    /// The joints and sensors.
    pub joints: KjointSet,
    /// Applied loads.
    pub loads: Vec<Load>,
    /// Prescribed motions of kinematic bodies.
    pub motions: Vec<Motion>,
    /// Motor target schedules of the robots' joints.
    pub motors: Vec<Motor>,
    /// The joints' switches, in time order.
    pub switches: Vec<Switch>,
    /// The rapier impulse joints of the scene's URDF robots (`engine = "rapier"`), by name,
    /// in name order (a merged joint under each of its names).
    pub rapier_joints: Vec<(String, ImpulseJointHandle)>,
    /// Body names and handles, in scene order (`"world"` first when used).
    pub bodies: Vec<(String, RigidBodyHandle)>,
    /// Where each joint's property comes from, in joint order.
    pub origins: Vec<PropertyOrigin>,
    /// Frame time step \[s\].
    pub frame_dt: f64,
    /// Simulated time \[s\].
    pub duration: f64,
    /// When the observers are called.
    pub log: LogEvery,
    /// CSV directory from the scene (resolved against the scene's directory).
    pub csv: Option<PathBuf>,
    /// Rerun file from the scene (resolved against the scene's directory).
    pub rrd: Option<PathBuf>,
    /// The scene's unit system.
    pub units: UnitSystem,
    /// The `<visual>` meshes of the scene's URDF robots (for drawing).
    pub visual_meshes: Vec<crate::io::urdf::VisualMesh>,
    /// What the readers approximated or skipped (a URDF's meshes not found, massless
    /// links, zero inertias, widened limits, ...; a deck property that ends before its
    /// cards, the units a deck's values were converted from, not the blocks a deck reader
    /// skips), each prefixed by its file.
    pub notices: Vec<String>,
    /// What will go wrong as the scene stands (bodies that nothing can stop falling:
    /// `free_fall.rs`; bodies that start deep inside the ground: `overlap.rs`), printed by
    /// `kjoint run` and `kjoint check`.
    pub warnings: Vec<String>,
}

/// The most rapier solver iterations per substep a scene accepts (`[rapier]
/// pgs_iterations`).
pub const MAX_PGS_ITERATIONS: usize = 1000;

/// Largest magnitude accepted for a scene value (rapier works in f32).
pub const MAX_VALUE: f64 = 1e12;

/// The world, the joints and the names the sections have built so far; each section's
/// file adds its part.
#[derive(Default)]
struct Assembly {
    /// The rapier world.
    world: PhysicsWorld,
    /// The KJOINT2 joints and sensors.
    joints: KjointSet,
    /// Bodies by name (scene bodies and robot links; not `"world"`).
    body_names: BTreeMap<String, RigidBodyHandle>,
    /// Body names and handles in scene order, `"world"` first when used.
    bodies: Vec<(String, RigidBodyHandle)>,
    /// The fixed ground `"world"`, once used.
    ground: Option<RigidBodyHandle>,
    /// KJOINT2 joints by name.
    joint_names: BTreeMap<String, KjointHandle>,
    /// The robots' rapier impulse joints by name.
    rapier_joints: BTreeMap<String, ImpulseJointHandle>,
    /// The robots' KJOINT2 joints inserted away from their zero pose, by name: their
    /// position there `q0` [rad or m] (`UrdfRobotHandles::initial_positions`).
    joint_q0: BTreeMap<String, f64>,
    /// Each KJOINT2 joint's property origin, with the joint's index.
    origins: Vec<(KjointHandle, PropertyOrigin)>,
    /// The notices of the decks the joints read ([`BuiltScene::notices`]).
    deck_notices: Vec<String>,
}

/// Checks every value of `scene`, converts it into SI and builds the world, the joints,
/// the sensors and the loads. Deck references are read relative to `src.file`.
pub fn build(scene: &Scene, src: &Source) -> Result<BuiltScene, SceneError> {
    let settings = settings::settings(scene, src)?;
    let units = settings.units;
    let mut parts = Assembly {
        world: PhysicsWorld {
            gravity: checks::vec3(settings.gravity, 1.0),
            ..Default::default()
        },
        joints: KjointSet::with_settings(SubstepSettings {
            substeps: scene.substeps,
            radioss_start: scene.radioss_start,
            ..Default::default()
        }),
        ..Default::default()
    };
    parts.add_bodies(scene, src, &units)?;
    settings::solver(scene, src, &mut parts.world)?;
    let robots = parts.add_robots(scene, src, &settings)?;
    let mut sensor_refs = parts.add_joints(scene, src, &units)?;
    sensor_refs.used.extend(robots.sensor_refs.iter().cloned());
    parts.add_sensors(scene, src, &units, sensor_refs)?;
    let loads = loads::loads(scene, src, &units, &parts.body_names)?;
    let motions = motions::motions(scene, src, &units, &parts.body_names, &mut parts.world)?;
    let motors = parts.motors(scene, src)?;
    let switches = parts.switches(scene, src, &units)?;
    let mut warnings =
        free_fall::free_fall_warnings(&parts.world, &parts.joints, &loads, &parts.bodies);
    // (the set's contact filters in the world first: a link on its mount does not touch it)
    let world = &mut parts.world;
    (parts.joints).update_contact_filters(&world.bodies, &mut world.impulse_joints);
    warnings.extend(overlap::start_overlap_warnings(&parts.world, &parts.bodies));
    // no spin cap either: rapier clamps a body's angular speed to π/4 a step unless the body
    // allows fast rotation (its safety net for CCD, which a scene's bodies do not use): a
    // flywheel at 500 rad/s, 8 substeps a frame, was clipped to 377 rad/s (π/4 / h) from
    // its first substep, 43 % of its energy gone
    for (_, b) in parts.world.bodies.iter_mut() {
        b.set_allow_fast_rotation(true);
    }

    let mut origins = parts.origins;
    // in the set's joint order (`KjointSet::iter`)
    origins.sort_by_key(|(h, _)| parts.joints.slot(*h));
    let dir = files::scene_dir(src);
    Ok(BuiltScene {
        world: parts.world,
        joints: parts.joints,
        loads,
        motions,
        motors,
        switches,
        rapier_joints: parts.rapier_joints.into_iter().collect(),
        bodies: parts.bodies,
        origins: origins.into_iter().map(|(_, o)| o).collect(),
        frame_dt: settings.frame_dt,
        duration: settings.duration,
        log: scene.output.log,
        csv: scene.output.csv.as_ref().map(|c| dir.join(c)),
        rrd: scene.output.rrd.as_ref().map(|c| dir.join(c)),
        units,
        visual_meshes: robots.visual_meshes,
        notices: robots
            .notices
            .into_iter()
            .chain(parts.deck_notices)
            .collect(),
        warnings,
    })
}
