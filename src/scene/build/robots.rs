//! The scene's `[[robots]]`: URDF and MJCF descriptions, described by
//! [`crate::io::urdf::UrdfRobot::from_file`] and [`crate::io::mjcf::MjcfRobot::from_file`]
//! then inserted; their links become named bodies, their joints named KJOINT2 joints or
//! rapier joints.

use super::checks::{finite_array, rotation, vec3};
use super::files::scene_dir;
use super::properties::PropertyOrigin;
use super::settings::Settings;
use super::Assembly;
use crate::io::robot::RobotDescription;
use crate::io::units::UnitSystem;
use crate::io::urdf::{UrdfError, UrdfRobotHandles, VisualMesh, NAME_SEPARATOR, WORLD_LINK};
use crate::rapier::math::{Pose, Rotation};
use crate::scene::schema::{RobotSpec, Scene};
use crate::scene::{FieldPath, SceneError, Source};
use std::path::PathBuf;

/// A robot's description as read, with its file.
struct LoadedRobot {
    /// Where a clash of its names is reported: `robots[i].name` for a named robot, else its
    /// description file's field, `robots[i].urdf` or `robots[i].mjcf`.
    at: FieldPath,
    /// Its description file's field, `robots[i].urdf` or `robots[i].mjcf`.
    file_at: FieldPath,
    /// The name of its massless root `world` link (`world`, or `{name}/world`).
    world_link: String,
    /// Whether it has a `name` (its names are prefixed).
    named: bool,
    /// Whether `position` or `rotation` moved it from where its file puts it.
    placed: bool,
    /// Whether it was read from MJCF (`mjcf = ...`) rather than URDF.
    mjcf: bool,
    /// The description file (resolved path).
    file: PathBuf,
    /// What the reader built.
    robot: UrdfRobotHandles,
}

/// What the robots bring besides bodies and joints.
#[derive(Default)]
pub(super) struct RobotExtras {
    /// The `<visual>` meshes, for drawing.
    pub visual_meshes: Vec<VisualMesh>,
    /// What the readers approximated or skipped, each prefixed by its file.
    pub notices: Vec<String>,
    /// The sensors the overrides' whole properties name, at their fields
    /// (`robots[i].options.joints.<joint>.property.sensor`): checked with the scene's.
    pub sensor_refs: Vec<(u32, FieldPath)>,
}

impl Assembly {
    /// Reads the scene's robots into the world and the joint set.
    pub(super) fn add_robots(
        &mut self,
        scene: &Scene,
        src: &Source,
        settings: &Settings,
    ) -> Result<RobotExtras, SceneError> {
        let mut extras = RobotExtras::default();
        for (i, r) in scene.robots.iter().enumerate() {
            let p = FieldPath::root("robots").index(i);
            if settings.units != UnitSystem::SI {
                return Err(src.error(
                    &p,
                    format!(
                        "URDF robots need an SI scene (URDF and its options are in SI), not \
                         units = \"{}\"",
                        scene.units
                    ),
                ));
            }
            for (joint, ov) in &r.options.joints {
                if let Some(id) = ov.property.as_ref().and_then(|p| p.sensor) {
                    let at = p.key("options").key("joints").key(joint);
                    // 0 is no sensor (load_robot), as in a scene's property
                    if id != 0 {
                        extras
                            .sensor_refs
                            .push((id, at.key("property").key("sensor")));
                    }
                }
            }
            let place = placement(src, &p, r)?;
            let loaded = self.load_robot(src, &p, r, &place, settings, scene.substeps)?;
            // two copies of one file tell their notices apart by the robot's name
            let whose = match &place.name {
                Some(n) => format!("{} (robot `{n}`)", loaded.file.display()),
                None => loaded.file.display().to_string(),
            };
            for note in &loaded.robot.notices {
                extras.notices.push(format!("{whose}: {note}"));
            }
            self.add_links(src, &loaded)?;
            self.add_robot_joints(src, &loaded)?;
            extras.visual_meshes.extend(loaded.robot.visual_meshes);
        }
        Ok(extras)
    }

    /// Reads one robot's description, placed and named as `place` says.
    fn load_robot(
        &mut self,
        src: &Source,
        p: &FieldPath,
        r: &RobotSpec,
        place: &Placement,
        settings: &Settings,
        substeps: usize,
    ) -> Result<LoadedRobot, SceneError> {
        let (key, path) = match (&r.urdf, &r.mjcf) {
            (Some(u), None) => ("urdf", u),
            (None, Some(m)) => ("mjcf", m),
            _ => {
                return Err(src.error(
                    p,
                    "a robot needs exactly one of `urdf` and `mjcf` (its description file)",
                ))
            }
        };
        let file = scene_dir(src).join(path);
        let mut options = r.options.clone();
        options.base_pose = place.pose;
        if options.substep == 0.0 {
            options.substep = settings.frame_dt / substeps as f64;
        }
        // a whole property's `sensor = 0` is no sensor, as in a scene's property
        for ov in options.joints.values_mut() {
            if let Some(p) = ov.property.as_mut().filter(|p| p.sensor == Some(0)) {
                p.sensor = None;
            }
        }
        // the overrides name the file's joints: prefixed after reading, before inserting
        let name = place.name.as_deref();
        let robot = if key == "urdf" {
            crate::io::urdf::UrdfRobot::from_file(&file, &options)
                .and_then(|r| prefixed(r, name).insert(&mut self.world, &mut self.joints))
        } else {
            crate::io::mjcf::MjcfRobot::from_file(&file, &options).and_then(|r| {
                let r = prefixed(r, name);
                // the model's gravity, or MuJoCo's z-up default where it gives none
                let (g, whose) = match r.gravity {
                    Some(g) => (g, "<option gravity>"),
                    None => (
                        crate::io::mjcf::MUJOCO_GRAVITY,
                        "MuJoCo's default gravity (the model gives no <option gravity>)",
                    ),
                };
                let mut robot = r.insert(&mut self.world, &mut self.joints)?;
                if g != settings.gravity {
                    robot.notices.push(format!(
                        "{whose} = {} m/s² not used: the scene's gravity {} m/s² applies (the \
                         model runs under its own as a scene of its own, `kjoint run {}`)",
                        vector(g),
                        vector(settings.gravity),
                        path
                    ));
                }
                Ok(robot)
            })
        }
        .map_err(|e| src.error(&error_path(p, key, &e), e.to_string()))?;
        let world_link = match &place.name {
            Some(n) => format!("{n}{NAME_SEPARATOR}{WORLD_LINK}"),
            None => WORLD_LINK.to_string(),
        };
        Ok(LoadedRobot {
            at: match place.name {
                Some(_) => p.key("name"),
                None => p.key(key),
            },
            file_at: p.key(key),
            world_link,
            named: place.name.is_some(),
            placed: place.pose != Pose::IDENTITY,
            mjcf: key == "mjcf",
            file,
            robot,
        })
    }

    /// A robot's links as named bodies; a massless root link `world` of a robot where its
    /// file puts it is the scene's ground, a placed one a fixed body where the robot stands
    /// (`{name}/world` for a named robot, else unnamed).
    fn add_links(&mut self, src: &Source, loaded: &LoadedRobot) -> Result<(), SceneError> {
        let LoadedRobot {
            at,
            file_at,
            world_link,
            named,
            placed,
            file,
            robot,
            ..
        } = loaded;
        for (link, h) in &robot.links {
            if link == world_link && !(*placed && *named) {
                // the ROS convention: a root link `world` without mass is the fixed world,
                // at the origin like the scene's `world`; the first one is the scene's
                if self.world.bodies[*h].is_dynamic() {
                    return Err(src.error(
                        file_at,
                        format!(
                            "link `world` of {} is dynamic (it has mass, or is not a root \
                             with fixed_base): in a scene `world` is the fixed ground; give \
                             the link no mass or another name",
                            file.display()
                        ),
                    ));
                }
                // placed, it stands where the robot does: not the scene's `world`
                if *placed {
                    continue;
                }
                if self.ground.is_none() {
                    self.ground = Some(*h);
                    self.bodies.insert(0, ("world".to_string(), *h));
                }
                continue;
            }
            if self.body_names.insert(link.clone(), *h).is_some() {
                return Err(src.error(
                    at,
                    format!(
                        "link `{link}` of {} has the name of another body",
                        file.display()
                    ),
                ));
            }
            // a link fused into another's body answers to its name, but the body is listed
            // (outputs) once, under the link it was
            if !robot.is_fused_link(link) {
                self.bodies.push((link.clone(), *h));
            }
        }
        Ok(())
    }

    /// A robot's joints under their names: KJOINT2 joints (one origin each, merged URDF
    /// joints sharing one) and rapier joints.
    fn add_robot_joints(&mut self, src: &Source, loaded: &LoadedRobot) -> Result<(), SceneError> {
        let LoadedRobot {
            at,
            mjcf,
            file,
            robot,
            ..
        } = loaded;
        let taken = |name: &str| {
            src.error(
                at,
                format!(
                    "joint `{name}` of {} has the name of another joint",
                    file.display()
                ),
            )
        };
        let mut seen = std::collections::HashSet::new();
        for (name, h) in &robot.joints {
            if self.joint_names.insert(name.clone(), *h).is_some() {
                return Err(taken(name));
            }
            if seen.insert(*h) {
                let file = file.clone();
                let origin = if *mjcf {
                    PropertyOrigin::Mjcf { file }
                } else {
                    PropertyOrigin::Urdf { file }
                };
                self.origins.push((*h, origin));
            }
        }
        for (name, q0) in &robot.initial_positions {
            self.joint_q0.insert(name.clone(), *q0);
        }
        for (name, h) in &robot.rapier_joints {
            if self.joint_names.contains_key(name)
                || self.rapier_joints.insert(name.clone(), *h).is_some()
            {
                return Err(taken(name));
            }
        }
        Ok(())
    }
}

/// `d` with its names prefixed by `name` (none: as it is).
fn prefixed<F>(mut d: RobotDescription<F>, name: Option<&str>) -> RobotDescription<F> {
    if let Some(n) = name {
        d.prefix_names(n);
    }
    d
}

/// How a `[[robots]]` entry stands in the scene: its name and pose, checked.
struct Placement {
    /// The prefix of its names (`name`), if any.
    name: Option<String>,
    /// The pose of its frame in the world (`position`, `rotation`) \[m\].
    pose: Pose,
}

/// The checked `name`, `position` and `rotation` of the robot `r` at `p` (SI: robots are
/// refused in other unit systems before), with the checks of a body's.
fn placement(src: &Source, p: &FieldPath, r: &RobotSpec) -> Result<Placement, SceneError> {
    if let Some(n) = &r.name {
        if n.trim().is_empty() {
            return Err(src.error(
                &p.key("name"),
                "an empty name: give the robot a name (its bodies and joints are named \
                 `name/link`), or leave `name` out",
            ));
        }
    }
    let position = match r.position {
        Some(v) => finite_array(src, &p.key("position"), v)?,
        None => [0.0; 3],
    };
    let rot = match &r.rotation {
        Some(spec) => rotation(src, &p.key("rotation"), spec)?,
        None => Rotation::IDENTITY,
    };
    Ok(Placement {
        name: r.name.clone(),
        pose: Pose::from_parts(vec3(position, 1.0), rot),
    })
}

/// Where a URDF robot's error belongs in the scene: an invalid option at its key under
/// `robots[i].options` (`options.joints.`elbow`.motor` + `stiffness` →
/// `robots[i].options.joints.elbow.motor.stiffness`, `options.joints.`elbow`` +
/// `property.dofs[3].stiffness` → `robots[i].options.joints.elbow.property.dofs[3].stiffness`),
/// an invalid override (or one naming no joint of the robot) at its joint's table, anything
/// else (the file, the description) at
/// `robots[i].urdf` (or `.mjcf`: `key`).
fn error_path(robot: &FieldPath, key: &str, e: &UrdfError) -> FieldPath {
    match e {
        UrdfError::Override { joint, .. } => robot.key("options").key("joints").key(joint),
        // an override naming no joint of the robot: at its own table (it was at the
        // description's key, the line above the override to fix)
        UrdfError::Field {
            element,
            field,
            value,
            ..
        } if element == "options.joints" && field == "name" => {
            robot.key("options").key("joints").key(value)
        }
        UrdfError::Field { element, field, .. } if field != "name" => {
            let Some(rest) = element.strip_prefix("options") else {
                return robot.key(key);
            };
            let p = keys(robot.key("options"), rest);
            keys(p, &format!(".{field}"))
        }
        _ => robot.key(key),
    }
}

/// `p` followed by the keys of `rest`: `.joints.`elbow`.motor` (a joint's name is between
/// backticks: it may hold dots), `.dofs[3].stiffness` (a key and an index).
fn keys(mut p: FieldPath, mut rest: &str) -> FieldPath {
    while let Some(r) = rest.strip_prefix('.') {
        if let Some((name, after)) = r.strip_prefix('`').and_then(|q| q.split_once('`')) {
            p = p.key(name);
            rest = after;
            continue;
        }
        let (key, after) = r.split_at(r.find('.').unwrap_or(r.len()));
        let indexed = key.strip_suffix(']').and_then(|k| k.split_once('['));
        p = match indexed.and_then(|(k, i)| Some((k, i.parse::<usize>().ok()?))) {
            Some((k, i)) => p.key(k).index(i),
            None => p.key(key),
        };
        rest = after;
    }
    p
}

/// A vector as notices write it: `[0, 0, -9.81]`.
fn vector(v: [f64; 3]) -> String {
    let [x, y, z] = v.map(crate::figure::fmt_num);
    format!("[{x}, {y}, {z}]")
}
