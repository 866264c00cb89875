//! Turns a parsed [`Scene`] into a rapier world, a [`KjointSet`] and the applied loads,
//! after checking every value and converting it into SI (kg, m, s).
//!
//! Nothing is simulated here. Unit conversion is explicit: every scene value is multiplied
//! by the factor of its dimension ([`UnitSystem::factor`]); inline properties go through
//! [`property_to_si`]; deck properties are taken in SI as the deck reader converted them
//! with the deck's own `/UNIT`.

use super::schema::{
    BodyKind, BodySpec, FlexJointSpec, JointSpec, LogEvery, PropertySpec, RotationSpec, Scene,
    ShapeSpec, TimeFunction,
};
use super::{FieldPath, Source};
use crate::dynamics::SensorCondition;
use crate::error::{PropertyError, SimError};
use crate::io::units::{connector_to_si, property_to_si, Quantity, UnitSystem};
use crate::io::{radioss, riser};
use crate::law::{
    ConnectorLaw, Curve, Dof, DofLaw, FlexJointConnector, FlexJointLaw, Kjoint2Property,
    PlanarFriction,
};
use crate::rapier::dynamics::{ImpulseJointHandle, JointAxis, RigidBodyType};
use crate::rapier::prelude::*;
use crate::{Kjoint2Builder, KjointSet, SubstepSettings};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use super::SceneError;

/// A dimensionless function of time `t` \[s\], in SI.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeFn {
    /// A constant.
    Constant(f64),
    /// Piecewise linear through `(t \[s\], value)` points, constant outside.
    Curve(Vec<(f64, f64)>),
    /// `offset + amplitude·sin(2π·frequency·(t − start) + phase)` for `t ≥ start`, 0
    /// before; frequency \[Hz\], phase \[rad\], start \[s\].
    Sine {
        /// Amplitude.
        amplitude: f64,
        /// Frequency \[Hz\].
        frequency: f64,
        /// Phase \[rad\].
        phase: f64,
        /// Offset.
        offset: f64,
        /// Start time \[s\].
        start: f64,
    },
}

impl TimeFn {
    /// The value at time `t` \[s\].
    pub fn value(&self, t: f64) -> f64 {
        match self {
            TimeFn::Constant(c) => *c,
            TimeFn::Curve(p) => {
                let (first, last) = (p[0], p[p.len() - 1]);
                if t <= first.0 {
                    return first.1;
                }
                if t >= last.0 {
                    return last.1;
                }
                let i = p.partition_point(|q| q.0 <= t).clamp(1, p.len() - 1);
                let (a, b) = (p[i - 1], p[i]);
                a.1 + (b.1 - a.1) * (t - a.0) / (b.0 - a.0)
            }
            TimeFn::Sine {
                amplitude,
                frequency,
                phase,
                offset,
                start,
            } => {
                if t < *start {
                    0.0
                } else {
                    offset
                        + amplitude
                            * (2.0 * std::f64::consts::PI * frequency * (t - start) + phase).sin()
                }
            }
        }
    }
}

/// A force or torque on a body, `vector · function(t)`, world axes, at the centre of mass.
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    /// The body's name.
    pub body_name: String,
    /// The body.
    pub body: RigidBodyHandle,
    /// `true` for a torque [N·m], `false` for a force \[N\].
    pub torque: bool,
    /// The vector [N or N·m].
    pub vector: [f64; 3],
    /// Its time function.
    pub function: TimeFn,
}

impl Load {
    /// The load vector at time `t` \[s\] [N or N·m].
    pub fn at(&self, t: f64) -> [f64; 3] {
        let s = self.function.value(t);
        self.vector.map(|v| v * s)
    }
}

/// How a [`Motion`] prescribes its body's translation.
#[derive(Debug, Clone, PartialEq)]
pub enum MotionKind {
    /// Position `initial + vector·f(t)` \[m\].
    Displacement {
        /// The body's initial position (its origin) \[m\].
        initial: [f64; 3],
    },
    /// Velocity `vector·f(t)` \[m/s\].
    Velocity,
}

/// A prescribed motion of a kinematic body, in SI (scene `[[motions]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// The body's name.
    pub body_name: String,
    /// The body (kinematic, velocity based).
    pub body: RigidBodyHandle,
    /// Displacement or velocity.
    pub kind: MotionKind,
    /// The vector \[m or m/s\].
    pub vector: [f64; 3],
    /// Its time function.
    pub function: TimeFn,
}

impl Motion {
    /// The body's velocity \[m/s\] over the substep from `t` to `t + h` \[s\], the body being at
    /// `position` \[m\] at `t`: for a displacement, the way to the prescribed position at
    /// `t + h` (so that f32 round-off does not accumulate); for a velocity, its value at the
    /// substep's middle.
    pub fn velocity(&self, t: f64, h: f64, position: [f64; 3]) -> [f64; 3] {
        match &self.kind {
            MotionKind::Displacement { initial } => {
                let s = self.function.value(t + h);
                std::array::from_fn(|k| (initial[k] + self.vector[k] * s - position[k]) / h)
            }
            MotionKind::Velocity => {
                let s = self.function.value(t + 0.5 * h);
                self.vector.map(|v| v * s)
            }
        }
    }
}

/// A time schedule of a rapier joint's motor target, in SI (scene `[[motors]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Motor {
    /// The joint's (URDF) name.
    pub joint_name: String,
    /// The rapier impulse joint.
    pub joint: ImpulseJointHandle,
    /// Its motorised axis.
    pub axis: JointAxis,
    /// The target \[m or rad\].
    pub target: f64,
    /// Its time function.
    pub function: TimeFn,
}

impl Motor {
    /// The target at time `t` \[s\] [m or rad].
    pub fn at(&self, t: f64) -> f64 {
        self.target * self.function.value(t)
    }
}

/// Where a joint's property comes from, for reports.
#[derive(Debug, Clone, PartialEq)]
pub enum PropertyOrigin {
    /// Written inline in the scene (with its unit system).
    Inline,
    /// Built from a URDF joint (`robots` of the scene).
    Urdf {
        /// The URDF file (resolved path).
        file: PathBuf,
    },
    /// Read from a Radioss deck.
    Deck {
        /// The deck file (resolved path).
        file: PathBuf,
        /// `prop_ID`.
        id: u32,
        /// The deck's title of the property.
        title: String,
    },
}

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
    /// Motor target schedules of rapier joints.
    pub motors: Vec<Motor>,
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
    /// links, zero inertias, widened limits, ...), each prefixed by its file.
    pub notices: Vec<String>,
}

/// The most rapier solver iterations per substep a scene accepts (`[rapier]
/// pgs_iterations`).
pub const MAX_PGS_ITERATIONS: usize = 1000;

/// Largest magnitude accepted for a scene value (rapier works in f32).
pub const MAX_VALUE: f64 = 1e12;

fn fin(src: &Source, path: &FieldPath, v: f64) -> Result<f64, SceneError> {
    if !v.is_finite() {
        Err(src.error(
            path,
            format!("{v} is not a finite number (NaN and infinity are refused)"),
        ))
    } else if v.abs() > MAX_VALUE {
        Err(src.error(
            path,
            format!("{v} is out of range: expected |value| <= {MAX_VALUE:e}"),
        ))
    } else {
        Ok(v)
    }
}

fn fin_n<const N: usize>(
    src: &Source,
    path: &FieldPath,
    v: [f64; N],
) -> Result<[f64; N], SceneError> {
    for (i, x) in v.iter().enumerate() {
        fin(src, &path.index(i), *x)?;
    }
    Ok(v)
}

fn positive(src: &Source, path: &FieldPath, v: f64) -> Result<f64, SceneError> {
    fin(src, path, v)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(src.error(path, format!("{v}: expected a value > 0")))
    }
}

/// Parses a unit-system string: `"SI"` or three unit names `"mass length time"`.
pub fn parse_units(s: &str) -> Option<UnitSystem> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("si") || t.is_empty() {
        return Some(UnitSystem::SI);
    }
    let parts: Vec<&str> = t.split_whitespace().collect();
    match parts.as_slice() {
        [m, l, ti] => UnitSystem::from_names(m, l, ti),
        _ => None,
    }
}

fn rotation(src: &Source, path: &FieldPath, r: &RotationSpec) -> Result<Rotation, SceneError> {
    match (&r.axis, &r.angle, &r.quaternion) {
        (Some(axis), Some(angle), None) => {
            let axis = fin_n(src, &path.key("axis"), *axis)?;
            let angle = fin(src, &path.key("angle"), *angle)?;
            let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
            if n < 1e-12 {
                return Err(src.error(&path.key("axis"), "the rotation axis is zero"));
            }
            let q = nalgebra::UnitQuaternion::from_axis_angle(
                &nalgebra::Unit::new_normalize(nalgebra::Vector3::from(axis)),
                angle,
            );
            Ok(crate::dynamics::to_quat(&q))
        }
        (None, None, Some(q)) => {
            let q = fin_n(src, &path.key("quaternion"), *q)?;
            let n = (q.iter().map(|x| x * x).sum::<f64>()).sqrt();
            if (n - 1.0).abs() > 1e-3 {
                return Err(src.error(
                    &path.key("quaternion"),
                    format!("norm {n}: expected a unit quaternion [x, y, z, w]"),
                ));
            }
            let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                q[3], q[0], q[1], q[2],
            ));
            Ok(crate::dynamics::to_quat(&q))
        }
        _ => Err(src.error(
            path,
            "expected either `axis` and `angle` [rad], or `quaternion` = [x, y, z, w]",
        )),
    }
}

fn vec3(v: [f64; 3], f: f64) -> Vector {
    Vector::new((v[0] * f) as _, (v[1] * f) as _, (v[2] * f) as _)
}

/// The path of a [`PropertyError`]'s field under `base`, e.g. `rx.stop_min (SA-)` →
/// `base.rx.stop_min`.
fn property_error(src: &Source, base: &FieldPath, e: PropertyError) -> SceneError {
    match &e {
        PropertyError::InvalidField { field, .. } => {
            let name = field.split(" (").next().unwrap_or(field);
            let mut p = base.clone();
            for k in name.split('.') {
                p = p.key(k);
            }
            let mut err = src.error(&p, e.to_string());
            err.field = p.to_string();
            err
        }
        _ => src.error(base, e.to_string()),
    }
}

/// The frames a deck property's `Skew_ID1` and `Skew_ID2` give (world axes, the skews'
/// `[X', Y', Z']` as columns); `None` where the property has no skew.
type DeckSkews = [Option<Rotation>; 2];

/// A `/SKEW/FIX` frame as a rotation whose columns are its axes.
fn skew_rotation(s: &radioss::SkewFix) -> Rotation {
    let [x, y, z] = s.axes().map(nalgebra::Vector3::from);
    let m = nalgebra::Matrix3::from_columns(&[x, y, z]);
    let q = nalgebra::UnitQuaternion::from_rotation_matrix(
        &nalgebra::Rotation3::from_matrix_unchecked(m),
    );
    crate::dynamics::to_quat(&q)
}

/// A property of the scene in SI, checked, its origin, the delay of its deck's time sensor
/// and the frames its deck's skews give.
fn resolve_property(
    src: &Source,
    path: &FieldPath,
    spec: &PropertySpec,
    units: &UnitSystem,
    decks: &mut HashMap<PathBuf, radioss::RadiossDeck>,
) -> Result<(Kjoint2Property, PropertyOrigin, Option<f64>, DeckSkews), SceneError> {
    if let Some(deck) = &spec.deck {
        let inline = spec.joint_type.is_some()
            || spec.kn.is_some()
            || spec.automatic.is_some()
            || spec.scale_factor.is_some()
            || spec.critical_damping.is_some()
            || spec.sensor.is_some()
            || spec.dof_laws().iter().any(|d| d.is_some());
        if inline {
            return Err(src.error(
                path,
                "a deck reference `{ deck, id }` takes no inline property fields",
            ));
        }
        let Some(id) = spec.id else {
            return Err(src.error(&path.key("deck"), "a deck reference needs `id` (prop_ID)"));
        };
        let dir = src.file.parent().unwrap_or(Path::new(""));
        let file = dir.join(deck);
        if !decks.contains_key(&file) {
            let d = radioss::read_file(&file)
                .map_err(|e| src.error(&path.key("deck"), e.to_string()))?;
            decks.insert(file.clone(), d);
        }
        let d = &decks[&file];
        let Some(entry) = d.property(id) else {
            let known: Vec<String> = d.properties.keys().map(|k| k.to_string()).collect();
            return Err(src.error(
                &path.key("id"),
                format!(
                    "no /PROP/TYPE45 with prop_ID {id} in {} (it has: {})",
                    file.display(),
                    listed(known)
                ),
            ));
        };
        let sensor_delay = entry
            .property_si
            .sensor
            .and_then(|s| d.sensors.get(&s))
            .map(|s| s.tdelay_si());
        // the reader checked that the skews exist
        let skews = [entry.skew1, entry.skew2]
            .map(|id| id.and_then(|id| d.skews.get(&id)).map(skew_rotation));
        return Ok((
            entry.property_si.clone(),
            PropertyOrigin::Deck {
                file,
                id,
                title: entry.title.clone(),
            },
            sensor_delay,
            skews,
        ));
    }
    if spec.id.is_some() {
        return Err(src.error(&path.key("id"), "`id` needs `deck` (the Radioss file)"));
    }
    let Some(jt) = spec.joint_type else {
        return Err(src.error(
            path,
            "missing `type` (an inline property) or `deck` and `id` (a deck reference)",
        ));
    };
    let mut p = Kjoint2Property::new(jt);
    p.kn = spec.kn.unwrap_or(0.0);
    p.automatic = spec.automatic.unwrap_or_default();
    p.scale_factor = spec.scale_factor.unwrap_or(0.0);
    p.critical_damping = spec.critical_damping.unwrap_or(0.0);
    p.sensor = spec.sensor;
    for (dof, law) in Dof::ALL.iter().zip(spec.dof_laws()) {
        if let Some(law) = law {
            if !jt.is_free(*dof) {
                return Err(src.error(
                    &path.key(dof.name()),
                    format!(
                        "DOF {} is blocked for a {} joint: it takes no law (free DOFs: {})",
                        dof.name(),
                        jt.name(),
                        free_names(jt)
                    ),
                ));
            }
            p.dofs[dof.index()] = law.clone();
        }
    }
    p.validate().map_err(|e| property_error(src, path, e))?;
    let si = property_to_si(&p, units).map_err(|e| property_error(src, path, e))?;
    si.validate().map_err(|e| property_error(src, path, e))?;
    Ok((si, PropertyOrigin::Inline, None, [None, None]))
}

/// `items` joined by commas, or `none` (for messages listing what exists).
fn listed<T: AsRef<str>>(items: Vec<T>) -> String {
    if items.is_empty() {
        "none".into()
    } else {
        items
            .iter()
            .map(|i| i.as_ref())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Names of the free DOFs of a type, e.g. `rx` or `none`.
pub fn free_names(jt: crate::JointType) -> String {
    let v: Vec<&str> = Dof::ALL
        .iter()
        .filter(|d| jt.is_free(**d))
        .map(|d| d.name())
        .collect();
    listed(v)
}

fn body_collider(
    src: &Source,
    path: &FieldPath,
    b: &BodySpec,
    u: &UnitSystem,
) -> Result<Collider, SceneError> {
    let l = u.factor(Quantity::Length);
    let sp = path.key("shape");
    let c = match &b.shape {
        ShapeSpec::Ball { radius } => {
            ColliderBuilder::ball((positive(src, &sp.key("radius"), *radius)? * l) as _)
        }
        ShapeSpec::Cuboid { half_extents } => {
            let he = fin_n(src, &sp.key("half_extents"), *half_extents)?;
            for (i, v) in he.iter().enumerate() {
                positive(src, &sp.key("half_extents").index(i), *v)?;
            }
            ColliderBuilder::cuboid((he[0] * l) as _, (he[1] * l) as _, (he[2] * l) as _)
        }
        ShapeSpec::Capsule {
            half_height,
            radius,
        } => ColliderBuilder::capsule_y(
            (positive(src, &sp.key("half_height"), *half_height)? * l) as _,
            (positive(src, &sp.key("radius"), *radius)? * l) as _,
        ),
        ShapeSpec::Cylinder {
            half_height,
            radius,
        } => ColliderBuilder::cylinder(
            (positive(src, &sp.key("half_height"), *half_height)? * l) as _,
            (positive(src, &sp.key("radius"), *radius)? * l) as _,
        ),
    };
    let c = match (b.mass, b.density) {
        (Some(_), Some(_)) => {
            return Err(src.error(&path.key("density"), "give `mass` or `density`, not both"))
        }
        (Some(m), None) => c.mass((positive(src, &path.key("mass"), m)? * u.mass) as _),
        (None, Some(d)) => {
            c.density((positive(src, &path.key("density"), d)? * u.mass / (l * l * l)) as _)
        }
        (None, None) => c.density(1000.0),
    };
    let c = if b.collide {
        c
    } else {
        c.collision_groups(InteractionGroups::none())
    };
    let collider = c.build();
    let mp = collider.mass_properties();
    let ok = mp.mass().is_finite()
        && mp.mass() > 0.0
        && mp.principal_inertia().is_finite()
        && mp.principal_inertia().min_element() > 0.0;
    if !ok {
        return Err(src.error(
            path,
            format!(
                "mass {} kg and inertia {:?} kg·m² are out of range (check the shape, mass and \
                 density)",
                mp.mass(),
                mp.principal_inertia()
            ),
        ));
    }
    Ok(collider)
}

/// Checks every value of `scene`, converts it into SI and builds the world, the joints,
/// the sensors and the loads. Deck references are read relative to `src.file`.
pub fn build(scene: &Scene, src: &Source) -> Result<BuiltScene, SceneError> {
    let units = parse_units(&scene.units).ok_or_else(|| {
        src.error(
            &FieldPath::root("units"),
            format!(
                "unknown unit system `{}`: expected \"SI\" or three unit names \"mass length \
                 time\", e.g. \"kg mm ms\"",
                scene.units
            ),
        )
    })?;
    let l = units.factor(Quantity::Length);
    let t = units.factor(Quantity::Time);
    let root = FieldPath::default();
    let gravity = match scene.gravity {
        Some(g) => fin_n(src, &root.key("gravity"), g)?.map(|x| x * l / (t * t)),
        None => [0.0, -9.81, 0.0],
    };
    let frame_dt = match scene.dt {
        Some(dt) => positive(src, &root.key("dt"), dt)? * t,
        None => 1.0 / 60.0,
    };
    if scene.substeps == 0 || scene.substeps > super::MAX_SUBSTEPS {
        return Err(src.error(
            &root.key("substeps"),
            format!("{}: expected 1 ..= 100000", scene.substeps),
        ));
    }
    let duration = positive(src, &root.key("duration"), scene.duration)? * t;
    if duration / frame_dt > super::MAX_FRAMES {
        return Err(src.error(&root.key("duration"), "more than 1e8 frames: raise `dt`"));
    }

    let mut world = PhysicsWorld {
        gravity: vec3(gravity, 1.0),
        ..Default::default()
    };
    let mut names: BTreeMap<String, RigidBodyHandle> = BTreeMap::new();
    let mut bodies = Vec::new();
    let mut ground = None;
    for (i, b) in scene.bodies.iter().enumerate() {
        let p = root.key("bodies").index(i);
        if b.name == "world" || b.name.is_empty() {
            return Err(src.error(
                &p.key("name"),
                format!("`{}` is reserved: give the body another name", b.name),
            ));
        }
        if names.contains_key(&b.name) {
            return Err(src.error(&p.key("name"), format!("duplicate body name `{}`", b.name)));
        }
        let tr = fin_n(src, &p.key("translation"), b.translation)?;
        let v = fin_n(src, &p.key("linvel"), b.linvel)?;
        let w = fin_n(src, &p.key("angvel"), b.angvel)?;
        let rot = match &b.rotation {
            Some(r) => rotation(src, &p.key("rotation"), r)?,
            None => Rotation::IDENTITY,
        };
        let collider = body_collider(src, &p, b, &units)?;
        let rb = match b.kind {
            BodyKind::Dynamic => RigidBodyBuilder::dynamic(),
            BodyKind::Fixed => RigidBodyBuilder::fixed(),
        }
        .pose(Pose::from_parts(vec3(tr, l), rot))
        .linvel(vec3(v, l / t))
        .angvel(vec3(w, 1.0 / t))
        .can_sleep(false);
        let (h, _) = world.insert(rb, collider);
        names.insert(b.name.clone(), h);
        bodies.push((b.name.clone(), h));
    }

    let pgs = scene.rapier.pgs_iterations;
    if pgs == 0 || pgs > MAX_PGS_ITERATIONS {
        return Err(src.error(
            &root.key("rapier").key("pgs_iterations"),
            format!("{pgs}: expected 1 ..= {MAX_PGS_ITERATIONS}"),
        ));
    }
    world.integration_parameters.num_internal_pgs_iterations = pgs;
    world.integration_parameters.friction_in_bias_pass = scene.rapier.friction_in_bias_pass;
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps: scene.substeps,
        radioss_start: scene.radioss_start,
        ..Default::default()
    });
    let mut rapier_joints: BTreeMap<String, ImpulseJointHandle> = BTreeMap::new();
    let mut decks = HashMap::new();
    let mut riser_decks = HashMap::new();
    let mut origins = Vec::new();
    let mut deck_sensors: BTreeMap<u32, (f64, FieldPath)> = BTreeMap::new();
    let mut sensor_refs: Vec<(u32, FieldPath)> = Vec::new();
    let mut joint_names: BTreeMap<String, crate::KjointHandle> = BTreeMap::new();

    // URDF robots: links become named bodies, joints named KJOINT2 joints.
    let mut visual_meshes = Vec::new();
    let mut notices = Vec::new();
    for (i, r) in scene.robots.iter().enumerate() {
        let p = root.key("robots").index(i);
        if units != UnitSystem::SI {
            return Err(src.error(
                &p,
                format!(
                    "URDF robots need an SI scene (URDF and its options are in SI), not units \
                     = \"{}\"",
                    scene.units
                ),
            ));
        }
        let dir = src.file.parent().unwrap_or(Path::new(""));
        let (key, path) = match (&r.urdf, &r.mjcf) {
            (Some(u), None) => ("urdf", u),
            (None, Some(m)) => ("mjcf", m),
            _ => {
                return Err(src.error(
                    &p,
                    "a robot needs exactly one of `urdf` and `mjcf` (its description file)",
                ))
            }
        };
        let file = dir.join(path);
        let mut options = r.options.clone();
        if options.substep == 0.0 {
            options.substep = frame_dt / scene.substeps as f64;
        }
        let robot = if key == "urdf" {
            crate::io::urdf::load_urdf(&file, &mut world, &mut joints, &options)
        } else {
            crate::io::mjcf::load_mjcf(&file, &mut world, &mut joints, &options)
        }
        .map_err(|e| src.error(&urdf_error_path(&p, key, &e), e.to_string()))?;
        for note in &robot.notices {
            notices.push(format!("{}: {note}", file.display()));
        }
        for (link, h) in &robot.links {
            if link == crate::io::urdf::WORLD_LINK {
                // the ROS convention: a root link `world` without mass is the fixed world,
                // at the origin like the scene's `world`; the first one is the scene's
                if world.bodies[*h].is_dynamic() {
                    return Err(src.error(
                        &p.key(key),
                        format!(
                            "link `world` of {} is dynamic (it has mass, or is not a root \
                             with fixed_base): in a scene `world` is the fixed ground; give \
                             the link no mass or another name",
                            file.display()
                        ),
                    ));
                }
                if ground.is_none() {
                    ground = Some(*h);
                    bodies.insert(0, ("world".to_string(), *h));
                }
                continue;
            }
            if names.insert(link.clone(), *h).is_some() {
                return Err(src.error(
                    &p.key(key),
                    format!(
                        "link `{link}` of {} has the name of another body",
                        file.display()
                    ),
                ));
            }
            bodies.push((link.clone(), *h));
        }
        let mut seen = std::collections::HashSet::new();
        for (name, h) in &robot.joints {
            // merged URDF joints share a KJOINT2 joint: one origin per KJOINT2 joint
            if joint_names.insert(name.clone(), *h).is_some() {
                return Err(src.error(
                    &p.key(key),
                    format!(
                        "joint `{name}` of {} has the name of another joint",
                        file.display()
                    ),
                ));
            }
            if seen.insert(*h) {
                origins.push((h.0, PropertyOrigin::Urdf { file: file.clone() }));
            }
        }
        for (name, h) in &robot.rapier_joints {
            if joint_names.contains_key(name) || rapier_joints.insert(name.clone(), *h).is_some() {
                return Err(src.error(
                    &p.key(key),
                    format!(
                        "joint `{name}` of {} has the name of another joint",
                        file.display()
                    ),
                ));
            }
        }
        visual_meshes.extend(robot.visual_meshes);
    }
    for (i, j) in scene.joints.iter().enumerate() {
        let p = root.key("joints").index(i);
        if j.name.is_empty() {
            return Err(src.error(&p.key("name"), "a joint needs a non-empty name"));
        }
        if joint_names.contains_key(&j.name) || rapier_joints.contains_key(&j.name) {
            return Err(src.error(&p.key("name"), format!("duplicate joint name `{}`", j.name)));
        }
        let mut body = |key: &str, name: &str| -> Result<RigidBodyHandle, SceneError> {
            if name == "world" {
                return Ok(*ground.get_or_insert_with(|| {
                    let h = world.insert_body(RigidBodyBuilder::fixed());
                    bodies.insert(0, ("world".to_string(), h));
                    h
                }));
            }
            names.get(name).copied().ok_or_else(|| {
                let known: Vec<&str> = names.keys().map(|s| s.as_str()).collect();
                src.error(
                    &p.key(key),
                    format!(
                        "no body named `{name}` (bodies: {}; or \"world\")",
                        listed(known)
                    ),
                )
            })
        };
        let b1 = body("body1", &j.body1)?;
        let b2 = body("body2", &j.body2)?;
        let (prop, origin, delay, skews) =
            resolve_property(src, &p.key("property"), &j.property, &units, &mut decks)?;
        if let Some(s) = prop.sensor {
            sensor_refs.push((s, p.key("property").key("sensor")));
            if let Some(d) = delay {
                deck_sensors.insert(s, (d, p.key("property")));
            }
        }
        let connector = resolve_connector(src, &p, j, &prop, &units, &mut riser_decks)?;
        let jb = joint_builder(src, &p, j, prop, l, skews)?.connector(connector);
        let h = joints
            .insert(jb, b1, b2, &world.bodies)
            .map_err(|e| sim_error(src, &p, e))?;
        joint_names.insert(j.name.clone(), h);
        origins.push((h.0, origin));
    }
    origins.sort_by_key(|(h, _)| *h);
    let origins: Vec<PropertyOrigin> = origins.into_iter().map(|(_, o)| o).collect();

    // Sensors.
    let mut sensor_ids = BTreeMap::new();
    for (i, s) in scene.sensors.iter().enumerate() {
        let p = root.key("sensors").index(i);
        if sensor_ids.insert(s.id, ()).is_some() {
            return Err(src.error(&p.key("id"), format!("duplicate sensor id {}", s.id)));
        }
        let cond = match (s.time, s.passes, s.force_reaches) {
            (Some(time), None, None) => {
                if s.joint.is_some() || s.dof.is_some() {
                    return Err(src.error(&p, "a time sensor takes no `joint` or `dof`"));
                }
                let time = fin(src, &p.key("time"), time)?;
                if time < 0.0 {
                    return Err(src.error(&p.key("time"), format!("{time}: expected >= 0")));
                }
                SensorCondition::Time(time * t)
            }
            (None, Some(_), None) | (None, None, Some(_)) => {
                let Some(jn) = &s.joint else {
                    return Err(src.error(&p, "missing `joint` (the watched joint's name)"));
                };
                let Some(&joint) = joint_names.get(jn) else {
                    return Err(src.error(&p.key("joint"), format!("no joint named `{jn}`")));
                };
                let Some(dof) = s.dof else {
                    return Err(src.error(&p, "missing `dof` (dx, dy, dz, rx, ry or rz)"));
                };
                if let Some(v) = s.passes {
                    let v = fin(src, &p.key("passes"), v)?;
                    let f = if dof.is_rotation() { 1.0 } else { l };
                    SensorCondition::DofPasses {
                        joint,
                        dof,
                        value: v * f,
                    }
                } else {
                    let v = positive(src, &p.key("force_reaches"), s.force_reaches.unwrap_or(0.0))?;
                    let q = if dof.is_rotation() {
                        Quantity::Moment
                    } else {
                        Quantity::Force
                    };
                    SensorCondition::ForceReaches {
                        joint,
                        dof,
                        value: v * units.factor(q),
                    }
                }
            }
            _ => {
                return Err(src.error(
                    &p,
                    "expected exactly one of `time`, `passes` or `force_reaches`",
                ))
            }
        };
        joints
            .add_sensor(s.id, cond)
            .map_err(|e| src.error(&p, e.to_string()))?;
    }
    for (id, (delay, _)) in &deck_sensors {
        if !sensor_ids.contains_key(id) {
            joints
                .add_sensor(*id, SensorCondition::Time(*delay))
                .map_err(|e| src.file_error(e.to_string()))?;
            sensor_ids.insert(*id, ());
        }
    }
    for (id, p) in &sensor_refs {
        if !sensor_ids.contains_key(id) {
            let known: Vec<String> = sensor_ids.keys().map(|k| k.to_string()).collect();
            return Err(src.error(
                p,
                format!("no sensor with id {id} (sensors: {})", listed(known)),
            ));
        }
    }

    // Loads.
    let mut loads = Vec::new();
    for (i, ld) in scene.loads.iter().enumerate() {
        let p = root.key("loads").index(i);
        let Some(&body) = names.get(&ld.body) else {
            return Err(src.error(&p.key("body"), format!("no body named `{}`", ld.body)));
        };
        let (torque, v, key, q) = match (ld.force, ld.torque) {
            (Some(f), None) => (false, f, "force", Quantity::Force),
            (None, Some(m)) => (true, m, "torque", Quantity::Moment),
            _ => return Err(src.error(&p, "expected exactly one of `force` and `torque`")),
        };
        let v = fin_n(src, &p.key(key), v)?.map(|x| x * units.factor(q));
        let function = time_function(src, &p.key("function"), &ld.function, t)?;
        loads.push(Load {
            body_name: ld.body.clone(),
            body,
            torque,
            vector: v,
            function,
        });
    }

    let motions = motions(src, scene, &names, &mut world, &units)?;
    let motors = motors(src, scene, &joint_names, &rapier_joints, &world)?;

    let dir = src.file.parent().unwrap_or(Path::new(""));
    Ok(BuiltScene {
        world,
        joints,
        loads,
        motions,
        motors,
        rapier_joints: rapier_joints.into_iter().collect(),
        bodies,
        origins,
        frame_dt,
        duration,
        log: scene.output.log,
        csv: scene.output.csv.as_ref().map(|c| dir.join(c)),
        rrd: scene.output.rrd.as_ref().map(|c| dir.join(c)),
        units,
        visual_meshes,
        notices,
    })
}

/// Where a URDF robot's error belongs in the scene: an invalid option at its key under
/// `robots[i].options` (`options.joints.`elbow`.motor` + `stiffness` →
/// `robots[i].options.joints.elbow.motor.stiffness`), an invalid override at its joint's
/// table, anything else (the file, the description) at `robots[i].urdf` (or `.mjcf`: `key`).
fn urdf_error_path(robot: &FieldPath, key: &str, e: &crate::io::urdf::UrdfError) -> FieldPath {
    use crate::io::urdf::UrdfError;
    match e {
        UrdfError::Override { joint, .. } => robot.key("options").key("joints").key(joint),
        UrdfError::Field { element, field, .. } if field != "name" => {
            let Some(mut rest) = element.strip_prefix("options") else {
                return robot.key(key);
            };
            let mut p = robot.key("options");
            // `.joints.`elbow`.motor`: a joint's name is between backticks (it may hold dots)
            while let Some(r) = rest.strip_prefix('.') {
                let (key, after) = match r.strip_prefix('`').and_then(|q| q.split_once('`')) {
                    Some((name, after)) => (name, after),
                    None => r.split_at(r.find('.').unwrap_or(r.len())),
                };
                p = p.key(key);
                rest = after;
            }
            p.key(field)
        }
        _ => robot.key(key),
    }
}

/// The scene's `[[motions]]`, in SI: each on a body that is not dynamic (not `"world"`),
/// one per body, which becomes kinematic (velocity based).
fn motions(
    src: &Source,
    scene: &Scene,
    names: &BTreeMap<String, RigidBodyHandle>,
    world: &mut PhysicsWorld,
    units: &UnitSystem,
) -> Result<Vec<Motion>, SceneError> {
    let l = units.factor(Quantity::Length);
    let t = units.factor(Quantity::Time);
    let mut out: Vec<Motion> = Vec::new();
    for (i, m) in scene.motions.iter().enumerate() {
        let p = FieldPath::root("motions").index(i);
        let Some(&body) = names.get(&m.body) else {
            let known: Vec<&str> = names.keys().map(|s| s.as_str()).collect();
            let why = if m.body == "world" {
                "`world` is the ground and does not move: give the moving body a name \
                 (a body of kind = \"fixed\")"
                    .to_string()
            } else {
                format!("no body named `{}` (bodies: {})", m.body, listed(known))
            };
            return Err(src.error(&p.key("body"), why));
        };
        if world.bodies[body].is_dynamic() {
            return Err(src.error(
                &p.key("body"),
                format!(
                    "body `{}` is dynamic: a prescribed motion moves a body that forces do not \
                     (a scene body of kind = \"fixed\", or a URDF robot's fixed root link)",
                    m.body
                ),
            ));
        }
        if out.iter().any(|o| o.body == body) {
            return Err(src.error(
                &p.key("body"),
                format!(
                    "body `{}` has a motion already: one motion per body",
                    m.body
                ),
            ));
        }
        let (kind, vector) = match (m.displacement, m.velocity) {
            (Some(d), None) => {
                let d = fin_n(src, &p.key("displacement"), d)?.map(|x| x * l);
                let x = world.bodies[body].translation();
                let initial = [x.x, x.y, x.z].map(f64::from);
                (MotionKind::Displacement { initial }, d)
            }
            (None, Some(v)) => {
                let v = fin_n(src, &p.key("velocity"), v)?.map(|x| x * l / t);
                (MotionKind::Velocity, v)
            }
            _ => return Err(src.error(&p, "expected exactly one of `displacement` and `velocity`")),
        };
        let function = time_function(src, &p.key("function"), &m.function, t)?;
        world.bodies[body].set_body_type(RigidBodyType::KinematicVelocityBased, true);
        out.push(Motion {
            body_name: m.body.clone(),
            body,
            kind,
            vector,
            function,
        });
    }
    Ok(out)
}

/// The scene's `[[motors]]`: each on a rapier joint of a robot that has a motor, one per
/// joint. URDF robots are SI, so are the targets.
fn motors(
    src: &Source,
    scene: &Scene,
    kjoints: &BTreeMap<String, crate::KjointHandle>,
    rapier_joints: &BTreeMap<String, ImpulseJointHandle>,
    world: &PhysicsWorld,
) -> Result<Vec<Motor>, SceneError> {
    let mut out: Vec<Motor> = Vec::new();
    for (i, m) in scene.motors.iter().enumerate() {
        let p = FieldPath::root("motors").index(i);
        let Some(&joint) = rapier_joints.get(&m.joint) else {
            let why = if kjoints.contains_key(&m.joint) {
                format!(
                    "joint `{}` is a KJOINT2 joint: motors drive rapier joints (engine = \
                     \"rapier\" in the robot's options.joints)",
                    m.joint
                )
            } else {
                let known: Vec<&str> = rapier_joints.keys().map(|s| s.as_str()).collect();
                format!(
                    "no rapier joint named `{}` (rapier joints: {})",
                    m.joint,
                    listed(known)
                )
            };
            return Err(src.error(&p.key("joint"), why));
        };
        let Some(data) = world.impulse_joints.get(joint).map(|j| &j.data) else {
            return Err(src.error(&p.key("joint"), "the rapier joint is not in the world"));
        };
        let Some(axis) = [JointAxis::LinX, JointAxis::AngX]
            .into_iter()
            .find(|a| data.motor(*a).is_some())
        else {
            return Err(src.error(
                &p.key("joint"),
                format!(
                    "joint `{}` has no motor: give it one in the robot's options \
                     (options.joints.{}.motor = {{ stiffness, damping, max_force }})",
                    m.joint, m.joint
                ),
            ));
        };
        if out.iter().any(|o| o.joint == joint) {
            return Err(src.error(
                &p.key("joint"),
                format!(
                    "joint `{}` has a motor schedule already: one per joint",
                    m.joint
                ),
            ));
        }
        let target = fin(src, &p.key("target"), m.target)?;
        // rapier joints come from URDF robots, which need an SI scene: times in seconds
        let function = time_function(src, &p.key("function"), &m.function, 1.0)?;
        out.push(Motor {
            joint_name: m.joint.clone(),
            joint,
            axis,
            target,
            function,
        });
    }
    Ok(out)
}

/// A scene's time function at `fp` in SI (`t` the factor of the scene's time unit): times
/// of a curve strictly increasing, a sine's frequency and start >= 0, every value finite;
/// none is the constant 1.
fn time_function(
    src: &Source,
    fp: &FieldPath,
    function: &Option<TimeFunction>,
    t: f64,
) -> Result<TimeFn, SceneError> {
    Ok(match function {
        None => TimeFn::Constant(1.0),
        Some(TimeFunction::Constant(c)) => TimeFn::Constant(fin(src, &fp.key("constant"), *c)?),
        Some(TimeFunction::Curve(pts)) => {
            let cp = fp.key("curve");
            if pts.is_empty() {
                return Err(src.error(&cp, "a curve needs at least one point [t, value]"));
            }
            let mut out: Vec<(f64, f64)> = Vec::with_capacity(pts.len());
            for (k, pt) in pts.iter().enumerate() {
                let pt = fin_n(src, &cp.index(k), *pt)?;
                if k > 0 && pt[0] * t <= out[k - 1].0 {
                    return Err(src.error(
                        &cp.index(k),
                        format!("time {} does not increase strictly", pt[0]),
                    ));
                }
                out.push((pt[0] * t, pt[1]));
            }
            TimeFn::Curve(out)
        }
        Some(TimeFunction::Sine(s)) => {
            let sp = fp.key("sine");
            let frequency = fin(src, &sp.key("frequency"), s.frequency)?;
            if frequency < 0.0 {
                return Err(src.error(&sp.key("frequency"), format!("{frequency}: expected >= 0")));
            }
            TimeFn::Sine {
                amplitude: fin(src, &sp.key("amplitude"), s.amplitude)?,
                frequency: frequency / t,
                phase: fin(src, &sp.key("phase"), s.phase)?,
                offset: fin(src, &sp.key("offset"), s.offset)?,
                start: {
                    let start = fin(src, &sp.key("start"), s.start)?;
                    if start < 0.0 {
                        return Err(src.error(&sp.key("start"), format!("{start}: expected >= 0")));
                    }
                    start * t
                },
            }
        }
    })
}

/// The connector law of a joint (`planar_friction` or `flex_joint`), in SI and checked
/// against the joint's property.
fn resolve_connector(
    src: &Source,
    p: &FieldPath,
    j: &JointSpec,
    prop: &Kjoint2Property,
    units: &UnitSystem,
    riser_decks: &mut HashMap<PathBuf, riser::RiserDeck>,
) -> Result<ConnectorLaw, SceneError> {
    let (law, path) = match (&j.planar_friction, &j.flex_joint) {
        (None, None) => return Ok(ConnectorLaw::None),
        (Some(_), Some(_)) => {
            return Err(src.error(
                &p.key("flex_joint"),
                "a joint takes one connector law: `planar_friction` or `flex_joint`, not both",
            ))
        }
        (Some(pf), None) => {
            let path = p.key("planar_friction");
            (planar_friction(src, &path, pf, units)?, path)
        }
        (None, Some(fj)) => {
            let path = p.key("flex_joint");
            (flex_joint(src, &path, fj, units, riser_decks)?, path)
        }
    };
    law.validate(prop)
        .map_err(|e| src.error(&path, e.to_string()))?;
    Ok(law)
}

fn planar_friction(
    src: &Source,
    path: &FieldPath,
    pf: &PlanarFriction,
    units: &UnitSystem,
) -> Result<ConnectorLaw, SceneError> {
    pf.validate().map_err(|e| property_error(src, path, e))?;
    connector_to_si(&ConnectorLaw::PlanarFriction(*pf), units)
        .map_err(|e| property_error(src, path, e))
}

/// The scene key of a flex joint field named as in the riser deck (`Kdyn_ini`, `IPRO`, ...).
fn flex_key(path: &FieldPath, e: &PropertyError) -> FieldPath {
    let PropertyError::InvalidField { field, .. } = e else {
        return path.clone();
    };
    match field.as_str() {
        "IPRO" => path.key("bending"),
        "IPROT" => path.key("torsion"),
        "Ktor" => path.key("dynamic").key("torsion_stiffness"),
        "IFLAG" => path.key("dynamic").key("iflag"),
        "Kdyn_ini" => path.key("dynamic").key("kdyn_ini"),
        "Kdyn_lim" => path.key("dynamic").key("kdyn_lim"),
        "Angle_lim" => path.key("dynamic").key("angle_lim"),
        "Teta" => path.key("dynamic").key("teta"),
        "CP" => path.key("dynamic").key("torsion_damping"),
        _ => path.clone(),
    }
}

fn flex_joint(
    src: &Source,
    path: &FieldPath,
    fj: &FlexJointSpec,
    units: &UnitSystem,
    riser_decks: &mut HashMap<PathBuf, riser::RiserDeck>,
) -> Result<ConnectorLaw, SceneError> {
    let switch_time = match fj.switch_time {
        Some(t) => {
            let t = fin(src, &path.key("switch_time"), t)?;
            if t < 0.0 {
                return Err(src.error(&path.key("switch_time"), format!("{t}: expected >= 0")));
            }
            Some(t)
        }
        None => None,
    };
    let law = if let Some(deck) = &fj.deck {
        if fj.bending.is_some() || fj.torsion.is_some() || fj.dynamic.is_some() {
            return Err(src.error(
                path,
                "a deck reference `{ deck, element }` takes no inline `bending`, `torsion` or \
                 `dynamic`",
            ));
        }
        let Some(nel) = fj.element else {
            return Err(src.error(
                &path.key("deck"),
                "a deck reference needs `element` (NEL of the *FLEXJOINT element)",
            ));
        };
        let dir = src.file.parent().unwrap_or(Path::new(""));
        let file = dir.join(deck);
        if !riser_decks.contains_key(&file) {
            let d = riser::read_riser_deck(&file)
                .map_err(|e| src.error(&path.key("deck"), e.to_string()))?;
            riser_decks.insert(file.clone(), d);
        }
        let d = &riser_decks[&file];
        let Some(el) = d.joints.iter().find(|e| e.id == nel) else {
            let known: Vec<String> = d.joints.iter().map(|e| e.id.to_string()).collect();
            return Err(src.error(
                &path.key("element"),
                format!(
                    "no *FLEXJOINT element {nel} in {} (it has: {})",
                    file.display(),
                    listed(known)
                ),
            ));
        };
        // riser decks are in SI: only the switch time is in the scene's units
        let c = FlexJointConnector {
            law: el.law.clone(),
            switch_time: switch_time.map(|t| t * units.factor(Quantity::Time)),
        };
        check_switch(src, path, &c)?;
        return Ok(ConnectorLaw::FlexJoint(c));
    } else if fj.element.is_some() {
        return Err(src.error(
            &path.key("element"),
            "`element` needs `deck` (the riser deck)",
        ));
    } else {
        let curve = |key: &str, pts: &Option<Vec<[f64; 2]>>| -> Result<Option<Curve>, SceneError> {
            let Some(pts) = pts else { return Ok(None) };
            Curve::new(pts.iter().map(|p| (p[0], p[1])))
                .map(Some)
                .map_err(|e| src.error(&path.key(key), e.to_string()))
        };
        let law = FlexJointLaw::new(
            curve("bending", &fj.bending)?,
            curve("torsion", &fj.torsion)?,
            fj.dynamic,
        )
        .map_err(|e| src.error(&flex_key(path, &e), e.to_string()))?;
        ConnectorLaw::FlexJoint(FlexJointConnector { law, switch_time })
    };
    let law =
        connector_to_si(&law, units).map_err(|e| src.error(&flex_key(path, &e), e.to_string()))?;
    if let ConnectorLaw::FlexJoint(c) = &law {
        check_switch(src, path, c)?;
    }
    Ok(law)
}

/// A switch time needs the dynamic law to switch to.
fn check_switch(src: &Source, path: &FieldPath, c: &FlexJointConnector) -> Result<(), SceneError> {
    if c.switch_time.is_some() && c.law.dynamic.is_none() {
        return Err(src.error(
            &path.key("switch_time"),
            "a switch to the dynamic phase needs the dynamic law (`dynamic`, or IMAT != 0 in the deck)",
        ));
    }
    Ok(())
}

/// The joint's builder: anchors, and its frames from the scene's `frame`/`frame2` or from
/// the `Skew_ID1`/`Skew_ID2` of its deck property (both for the same frame is an error: the
/// scene would silently override the deck, or the reverse).
fn joint_builder(
    src: &Source,
    p: &FieldPath,
    j: &JointSpec,
    prop: Kjoint2Property,
    l: f64,
    skews: DeckSkews,
) -> Result<Kjoint2Builder, SceneError> {
    let a1 = fin_n(src, &p.key("anchor1"), j.anchor1)?;
    let a2 = fin_n(src, &p.key("anchor2"), j.anchor2)?;
    let mut jb = Kjoint2Builder::new(prop)
        .name(j.name.clone())
        .local_anchor1(vec3(a1, l))
        .local_anchor2(vec3(a2, l));
    for (k, (key, skew_id, scene_frame)) in [
        ("frame", "Skew_ID1", &j.frame),
        ("frame2", "Skew_ID2", &j.frame2),
    ]
    .into_iter()
    .enumerate()
    {
        let r = match (scene_frame, skews[k]) {
            (Some(_), Some(_)) => {
                return Err(src.error(
                    &p.key(key),
                    format!(
                        "the deck property's {skew_id} already gives this frame: remove `{key}` \
                         (or the skew from the deck)"
                    ),
                ))
            }
            (Some(r), None) => Some(rotation(src, &p.key(key), r)?),
            (None, skew) => skew,
        };
        if let Some(r) = r {
            jb = if k == 0 { jb.frame(r) } else { jb.frame2(r) };
        }
    }
    Ok(jb)
}

fn sim_error(src: &Source, p: &FieldPath, e: SimError) -> SceneError {
    match e {
        SimError::Property { source, .. } => property_error(src, &p.key("property"), source),
        SimError::InvalidArgument { ref field, .. } if field.ends_with("frame2") => {
            src.error(&p.key("frame2"), e.to_string())
        }
        SimError::InvalidJoint { ref reason, .. } if reason.contains("Skew2") => {
            src.error(&p.key("frame2"), e.to_string())
        }
        other => src.error(p, other.to_string()),
    }
}

/// The DOF laws of a property that differ from the default, for reports.
pub fn set_laws(p: &Kjoint2Property) -> Vec<(Dof, &DofLaw)> {
    Dof::ALL
        .iter()
        .filter(|d| p.joint_type.is_free(**d))
        .map(|d| (*d, p.dof(*d)))
        .collect()
}
