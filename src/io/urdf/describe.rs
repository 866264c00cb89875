//! Phase 1 of reading a URDF robot: its text → a [`UrdfRobot`] description, without touching
//! any world. The steps, in order: sanitize and parse (urdf-rs), validate the options and
//! the robot, repair the inertias, check the overrides' joint names, resolve the mesh files,
//! let `rapier3d-urdf` build the bodies, colliders and joints, then describe each link
//! (body, colliders, visual meshes) and each joint (its KJOINT2 builder or rapier joint).

use super::error::{ErrorContext, UrdfError};
use super::joint::{
    apply_override, axis_dof, friction_by_rule, kjoint_builder, kjoint_motor, kjoint_type,
    rapier_joint, stops_from_limits, with_break, with_override_connector,
};
use super::mass::{
    friction_stiffness, inertial_mass_properties, load_beyond, place_mass, repair_inertias,
    LinkMass, BALL_RADIUS,
};
use super::mesh::{read_visual_meshes, resolve_meshes};
use super::options::{CollisionMeshes, JointEngine, UrdfOptions};
use super::sanitize::sanitize;
use super::validate::{check_options, check_robot, root_links};
use super::UrdfRobot;
use crate::dynamics::{from_quat, from_vec3};
use crate::io::loaded;
use crate::io::robot::{
    at_zero_offset, move_to_initial_positions, place_body, InitialMotion, RobotJoint,
    RobotJointKind, RobotLink,
};
use crate::law::{DofLaw, JointType, KjointProperty};
use crate::rapier::dynamics::{MassProperties, RigidBodyType};
use crate::rapier::geometry::{Group, InteractionGroups, InteractionTestMode};
use crate::rapier::math::{Pose, Real, Vector};
use nalgebra::Vector3;
use rapier3d_urdf::urdf_rs;
use rapier3d_urdf::{UrdfJoint, UrdfLink, UrdfLoaderOptions, UrdfRobot as RapierUrdfRobot};
use std::collections::HashSet;
use std::path::Path;

/// The name of the link that is the fixed world when it is a root without mass (ROS).
pub const WORLD_LINK: &str = "world";

/// Describes the URDF text `text` (read from `file`, meshes relative to `base`); an error
/// about a link or joint names its line in `text`.
pub(super) fn describe(
    text: &str,
    file: &str,
    base: &Path,
    options: &UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    describe_text(text, file, base, options).map_err(|e| super::locate::with_element_line(e, text))
}

/// [`describe`], its errors without lines.
fn describe_text(
    text: &str,
    file: &str,
    base: &Path,
    options: &UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    let mut notices = Vec::new();
    let text = sanitize(text, &mut notices);
    let context = ErrorContext { file };
    // an MJCF file given to the URDF reader read "invalid link = (none): expected at least
    // one <link>" (a robotics user's trial, 2026-12-05): say what it is
    if root_element(&text) == Some("mujoco") {
        return Err(UrdfError::Parse {
            file: file.to_string(),
            message: "its root element is <mujoco>, an MJCF model, where a URDF file has \
                      <robot>: read it with the MJCF reader (`MjcfRobot`, a scene's \
                      `[[robots]] mjcf = ...`)"
                .to_string(),
        });
    }
    // urdf-rs names neither the element nor the line of a missing attribute or a bad
    // number: find them ourselves
    let mut robot = urdf_rs::read_from_string(&text).map_err(|e| {
        super::locate::locate(&context, &text).unwrap_or_else(|| UrdfError::Parse {
            file: file.to_string(),
            message: e.to_string(),
        })
    })?;
    check_options(&context, options)?;
    check_robot(&context, &robot)?;
    repair_inertias(&context, &mut robot, options, &mut notices)?;
    check_override_names(&context, &robot, options)?;
    check_initial_positions(&context, &robot, options)?;
    if let Some(k) = &options.keyframe {
        let expected = "none: keyframes are MJCF's (give the positions in initial_positions)";
        return Err(context.field("options", "keyframe", k, expected));
    }
    // per link, the collision elements the user meant to collide with, and the meshes left
    // out on purpose by `CollisionMeshes::Ignore`
    let collisions: std::collections::HashMap<String, (usize, usize)> = (robot.links.iter())
        .map(|l| {
            let meshes = (l.collision.iter())
                .filter(|c| matches!(c.geometry, urdf_rs::Geometry::Mesh { .. }))
                .count();
            let ignored = if options.collision_meshes == CollisionMeshes::Ignore {
                meshes
            } else {
                0
            };
            (l.name.clone(), (l.collision.len() - ignored, ignored))
        })
        .collect();
    resolve_meshes(&mut robot, base, options, &mut notices);
    let loaded = build_with_rapier(&context, &robot, options)?;
    let describer = Describer {
        context,
        robot: &robot,
        options,
        loaded: &loaded,
    };
    let mut out = UrdfRobot::new(file, robot.name.clone());
    out.notices = notices;
    describer.removed_links(&mut out.notices);
    out.links = describer.links(&mut out.notices)?;
    // before the joints' frames and loads are measured, as the base pose
    describer.move_to_initial_positions(&mut out.links);
    out.joints = describer.joints(&out.links, &mut out.notices)?;
    out.notices
        .extend(no_collider(&out.links, &collisions, options));
    out.fuse_fixed_joints(options);
    Ok(out)
}

/// A notice when no moving link of the robot has a collider: its file meant some (every
/// mesh not found or unreadable, each named in its own notice), or its collision meshes are
/// ignored (`collision_meshes = "ignore"`), or, with a floating base, it has none: it passes
/// through the ground and every other body. `collisions`: per link name, the `<collision>`
/// elements meant and the meshes ignored. A robot whose meshes were all missing fell out of
/// sight with a notice per mesh and nothing that said the robot itself collides with nothing
/// (a user trial, 2026-12-05).
fn no_collider(
    links: &[crate::io::robot::RobotLink],
    collisions: &std::collections::HashMap<String, (usize, usize)>,
    options: &UrdfOptions,
) -> Option<String> {
    let moving: Vec<_> = links.iter().filter(|l| l.body.is_dynamic()).collect();
    if moving.is_empty() || moving.iter().any(|l| !l.colliders.is_empty()) {
        return None;
    }
    let (meant, ignored) = (moving.iter())
        .filter_map(|l| collisions.get(&l.name))
        .fold((0, 0), |(m, i), (lm, li)| (m + lm, i + li));
    let falls = if options.fixed_base {
        ""
    } else {
        ", and the robot, its base floating, falls through the ground under gravity"
    };
    if meant > 0 {
        Some(format!(
            "no moving link of the robot has a collider: none of the {meant} <collision> \
             elements of its moving links made one (their meshes not found or unreadable, as \
             the notices above say; `package://` paths are looked up in \
             `UrdfOptions::package_dirs`, a scene's `[robots.options] package_dirs`, other \
             relative paths from the file's directory): they collide with nothing{falls}"
        ))
    } else if ignored > 0 {
        Some(format!(
            "no moving link of the robot has a collider: their {ignored} collision meshes are \
             ignored (`collision_meshes = \"ignore\"`): they collide with nothing{falls}"
        ))
    } else if !options.fixed_base {
        Some(format!(
            "no moving link of the robot has a <collision> element: they collide with \
             nothing{falls}"
        ))
    } else {
        None
    }
}

/// The name of the first element of an XML text (after its declaration, comments and
/// doctype), if any.
fn root_element(text: &str) -> Option<&str> {
    let mut rest = text;
    loop {
        let at = rest.find('<')?;
        rest = &rest[at + 1..];
        if let Some(comment) = rest.strip_prefix("!--") {
            rest = &comment[comment.find("-->")? + 3..];
        } else if rest.starts_with('?') || rest.starts_with('!') {
            rest = &rest[rest.find('>')? + 1..];
        } else {
            let end = rest
                .find(|c: char| c.is_whitespace() || c == '>' || c == '/')
                .unwrap_or(rest.len());
            return Some(&rest[..end]);
        }
    }
}

/// Overrides must name joints of the robot.
fn check_override_names(
    context: &ErrorContext,
    robot: &urdf_rs::Robot,
    options: &UrdfOptions,
) -> Result<(), UrdfError> {
    for name in options.joints.keys() {
        if !robot.joints.iter().any(|j| &j.name == name) {
            return Err(context.field(
                "options.joints",
                "name",
                name,
                "the name of a joint of the robot",
            ));
        }
    }
    Ok(())
}

/// Initial positions must name joints of the robot that have one axis, within their limits.
fn check_initial_positions(
    context: &ErrorContext,
    robot: &urdf_rs::Robot,
    options: &UrdfOptions,
) -> Result<(), UrdfError> {
    use urdf_rs::JointType as T;
    let el = "options.initial_positions";
    for (name, &q0) in &options.initial_positions {
        let Some(j) = robot.joints.iter().find(|j| &j.name == name) else {
            return Err(context.field(el, name, q0, "the name of a joint of the robot"));
        };
        if !matches!(j.joint_type, T::Revolute | T::Continuous | T::Prismatic) {
            return Err(context.field(
                el,
                name,
                q0,
                "the name of a revolute, continuous or prismatic joint (this one is not)",
            ));
        }
        let (lo, hi) = (j.limit.lower, j.limit.upper);
        let limited = j.joint_type != T::Continuous && !(lo == 0.0 && hi == 0.0);
        if limited && !(lo <= q0 && q0 <= hi) {
            return Err(context.field(
                el,
                name,
                q0,
                format!("a position within the joint's limit [{lo}, {hi}]"),
            ));
        }
    }
    Ok(())
}

/// `rapier3d-urdf`'s bodies, colliders and joints of the (validated, mesh-resolved) robot.
/// They are f32 objects (rapier3d), converted into the world's rapier by [`loaded`].
fn build_with_rapier(
    context: &ErrorContext,
    robot: &urdf_rs::Robot,
    options: &UrdfOptions,
) -> Result<RapierUrdfRobot, UrdfError> {
    let loader = UrdfLoaderOptions {
        make_roots_fixed: options.fixed_base,
        mesh_converter: Some(options.collision_meshes.converter()),
        collider_blueprint: rapier3d::geometry::ColliderBuilder::default().density(0.0),
        rigid_body_blueprint: rapier3d::dynamics::RigidBodyBuilder::dynamic()
            .can_sleep(options.can_sleep),
        ..Default::default()
    };
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        RapierUrdfRobot::from_robot(robot, loader, Path::new("."))
    }))
    .map_err(|_| UrdfError::Parse {
        file: context.file.to_string(),
        message: "rapier3d-urdf could not build the robot".into(),
    })
}

/// The mass distribution the friction stiffnesses are computed from: per described link,
/// its pose, its mass ([`LinkMass`]) and the links that hang on it.
struct Loads {
    poses: Vec<Pose>,
    masses: Vec<LinkMass>,
    children: Vec<Vec<usize>>,
}

/// What the link and joint descriptions are made from.
struct Describer<'a> {
    context: ErrorContext<'a>,
    robot: &'a urdf_rs::Robot,
    options: &'a UrdfOptions,
    loaded: &'a RapierUrdfRobot,
}

impl Describer<'_> {
    /// A notice for each link `rapier3d-urdf` removed as empty.
    fn removed_links(&self, notices: &mut Vec<String>) {
        let kept: HashSet<usize> = self
            .loaded
            .links
            .iter()
            .map(|l| l.urdf_link_index)
            .collect();
        for (i, link) in self.robot.links.iter().enumerate() {
            if !kept.contains(&i) {
                notices.push(format!(
                    "link `{}`: empty (no inertial, visual or collision): removed, its joints \
                     merged",
                    link.name
                ));
            }
        }
    }

    /// Every kept link, in `rapier3d-urdf`'s order (its joints' link indices).
    fn links(&self, notices: &mut Vec<String>) -> Result<Vec<RobotLink>, UrdfError> {
        let group = Group::GROUP_32;
        let groups = if self.options.self_collisions {
            InteractionGroups::all()
        } else {
            InteractionGroups::new(group, Group::ALL ^ group, InteractionTestMode::And)
        };
        let roots = root_links(self.robot);
        let links = self.loaded.links.iter();
        links
            .map(|link| self.link(link, &roots, groups, notices))
            .collect()
    }

    /// A link's body (fixed for a massless root `world`, given the minimum mass when it has
    /// none), colliders (in the robot's collision groups) and visual meshes.
    fn link(
        &self,
        link: &UrdfLink,
        roots: &HashSet<&str>,
        groups: InteractionGroups,
        notices: &mut Vec<String>,
    ) -> Result<RobotLink, UrdfError> {
        let ulink = &self.robot.links[link.urdf_link_index];
        let mut body = loaded::body(&link.body);
        // where the robot stands: before the joints' frames and loads are measured
        place_body(&mut body, &self.options.base_pose);
        let m = ulink.inertial.mass.value;
        if ulink.name == WORLD_LINK && m <= 0.0 && roots.contains(ulink.name.as_str()) {
            // the ROS convention: a massless root `world` is the fixed world
            body.set_body_type(RigidBodyType::Fixed, false);
        }
        let mut colliders = Vec::with_capacity(link.colliders.len());
        for c in &link.colliders {
            let mut c = loaded::collider(&c.collider).map_err(|e| UrdfError::Parse {
                file: self.context.file.to_string(),
                message: format!("link `{}`: {e}", ulink.name),
            })?;
            c.set_collision_groups(groups);
            colliders.push(c);
        }
        if body.body_type() == RigidBodyType::Dynamic && m > 0.0 {
            // in place of rapier3d-urdf's, which parry diagonalised in f32 (module docs)
            let mp = inertial_mass_properties(&ulink.inertial);
            if let Some(err) = place_mass(&mut body, &mut colliders, mp) {
                notices.push(format!(
                    "link `{}`: its colliders make rapier diagonalise its inertia tensor again \
                     in f32: off by up to {:.1} % of its largest term",
                    ulink.name,
                    err * 100.0
                ));
            }
        }
        if body.body_type() == RigidBodyType::Dynamic && m <= 0.0 {
            let mm = self.options.min_link_mass as Real;
            let i = 0.4 * mm * (BALL_RADIUS * BALL_RADIUS) as Real;
            body.set_additional_mass_properties(
                MassProperties::new(Vector::ZERO, mm, Vector::splat(i)),
                false,
            );
            notices.push(format!(
                "link `{}`: no mass in the URDF: given {} kg",
                ulink.name, self.options.min_link_mass
            ));
        }
        unread_collision_meshes(ulink, link, notices);
        let visual_meshes = if self.options.visual_meshes {
            read_visual_meshes(ulink, notices)
        } else {
            Vec::new()
        };
        Ok(RobotLink {
            name: ulink.name.clone(),
            body,
            colliders,
            visual_meshes,
            spacer: false,
        })
    }

    /// The initial position [`UrdfOptions::initial_positions`] gives the joint `uj` (that
    /// of the URDF joint it carries the type and axis of), 0 without one.
    fn initial_position(&self, uj: &UrdfJoint) -> f64 {
        let src = &self.robot.joints[uj.source_urdf_joint_index()];
        (self.options.initial_positions.get(&src.name)).map_or(0.0, |q| *q)
    }

    /// The links moved from the URDF's zero pose to the joints' initial positions
    /// ([`move_to_initial_positions`]).
    fn move_to_initial_positions(&self, links: &mut [RobotLink]) {
        let edges: Vec<(usize, usize)> = (self.loaded.joints.iter())
            .map(|uj| (uj.link1, uj.link2))
            .collect();
        let motions: Vec<InitialMotion> = (self.loaded.joints.iter())
            .map(|uj| InitialMotion {
                link1: uj.link1,
                link2: uj.link2,
                frame1: loaded::joint(&uj.joint).local_frame1,
                slide: self.robot.joints[uj.source_urdf_joint_index()].joint_type
                    == urdf_rs::JointType::Prismatic,
                by: self.initial_position(uj),
            })
            .filter(|m| m.by != 0.0)
            .collect();
        move_to_initial_positions(links, &edges, &motions);
    }

    /// Every joint between links of which one at least is dynamic.
    fn joints(
        &self,
        links: &[RobotLink],
        notices: &mut Vec<String>,
    ) -> Result<Vec<RobotJoint>, UrdfError> {
        let poses: Vec<Pose> = links.iter().map(|l| *l.body.position()).collect();
        let masses = self
            .loaded
            .links
            .iter()
            .zip(&poses)
            .map(|(l, pose)| {
                let inertial = &self.robot.links[l.urdf_link_index].inertial;
                LinkMass::of(inertial, pose, self.options.min_link_mass)
            })
            .collect();
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); links.len()];
        for uj in &self.loaded.joints {
            children[uj.link1].push(uj.link2);
        }
        let loads = Loads {
            poses,
            masses,
            children,
        };
        let mut joints = Vec::with_capacity(self.loaded.joints.len());
        for uj in &self.loaded.joints {
            if let Some(j) = self.joint(uj, links, &loads, notices)? {
                joints.push(j);
            }
        }
        Ok(joints)
    }

    /// One joint: a rapier joint when its override says so, a KJOINT2 joint otherwise;
    /// `None` (with a notice) between two fixed links.
    fn joint(
        &self,
        uj: &UrdfJoint,
        links: &[RobotLink],
        loads: &Loads,
        notices: &mut Vec<String>,
    ) -> Result<Option<RobotJoint>, UrdfError> {
        let src = &self.robot.joints[uj.source_urdf_joint_index()];
        let joint = loaded::joint(&uj.joint);
        let name = src.name.clone();
        let el = format!("joint `{name}`");
        let dynamic = |l: usize| links.get(l).is_some_and(|l| l.body.is_dynamic());
        if !dynamic(uj.link1) && !dynamic(uj.link2) {
            notices.push(format!("{el}: both links are fixed: no joint created"));
            return Ok(None);
        }
        if src.mimic.is_some() {
            notices.push(format!("{el}: <mimic> ignored: the joint moves freely"));
        }
        // the URDF names this joint answers to (merged ones too)
        let names: Vec<String> = std::iter::once(name.clone())
            .chain(
                std::iter::once(uj.urdf_joint_index)
                    .chain(uj.merged_urdf_joint_indices.iter().copied())
                    .map(|i| self.robot.joints[i].name.clone()),
            )
            .collect();
        // an override may also name a joint merged into this one
        let ov = names.iter().find_map(|n| self.options.joints.get(n));
        let q0 = self.initial_position(uj);
        let described = |kind| RobotJoint {
            names: names.clone(),
            link1: uj.link1,
            link2: uj.link2,
            kind,
            initial_position: q0,
        };
        if let Some(ov) = ov.filter(|o| o.engine == Some(JointEngine::Rapier)) {
            let joint = rapier_joint(&self.context, &name, src, joint, ov, q0, notices)?;
            return Ok(Some(described(RobotJointKind::Rapier(Box::new(joint)))));
        }
        let (lf1, lf2) = (joint.local_frame1, joint.local_frame2);
        let frame = (loads.poses[uj.link1].rotation * lf1.rotation).normalize();
        let (mut prop, rule_kf) = self.property(src, q0, uj.link2, &lf2, loads, notices);
        if let Some(ov) = ov {
            prop = apply_override(&self.context, &name, prop, ov)?;
        }
        let by_rule = friction_by_rule(&mut prop, rule_kf, ov);
        let slide = src.joint_type == urdf_rs::JointType::Prismatic;
        let lf2 = at_zero_offset(&lf2, if slide { q0 } else { 0.0 });
        let collide = self.options.self_collisions;
        let mut builder = kjoint_builder(prop, &name, (&lf1, &lf2), frame, collide);
        builder.0.friction_by_rule = by_rule;
        let builder = with_override_connector(builder, ov);
        let mut builder = with_break(&self.context, &name, builder, ov)?;
        if let Some(m) = ov.and_then(|o| o.motor.as_ref()) {
            let el = format!("options.joints.`{name}`");
            let jt = builder.0.property.joint_type;
            let (dof, motor) = kjoint_motor(&self.context, &el, jt, m, q0)?;
            builder = builder.motor(dof, motor);
        }
        Ok(Some(described(RobotJointKind::Kjoint(Box::new(
            builder.build(),
        )))))
    }

    /// The KJOINT2 property of the URDF joint `src` (module docs, "Mapping"): its type, the
    /// options' `Kn` and `Cr`, and on the axis DOF the stops of its limits (measured from
    /// its initial position `q0`) and its dynamics;
    /// with the friction spring stiffness of the load beyond the child link `child` (joint
    /// frame `lf2` in it) by the rule (0 without an axis DOF), which [`friction_by_rule`]
    /// gives the DOF once the override is applied.
    fn property(
        &self,
        src: &urdf_rs::Joint,
        q0: f64,
        child: usize,
        lf2: &Pose,
        loads: &Loads,
        notices: &mut Vec<String>,
    ) -> (KjointProperty, f64) {
        let el = format!("joint `{}`", src.name);
        let jt = kjoint_type(&src.joint_type);
        let prop = KjointProperty::new(jt)
            .with_kn(self.options.kn)
            .with_critical_damping(self.options.critical_damping);
        let Some(dof) = axis_dof(jt) else {
            if src
                .dynamics
                .as_ref()
                .is_some_and(|d| d.damping > 0.0 || d.friction > 0.0)
            {
                notices.push(format!("{el}: dynamics of a {} joint ignored", jt.name()));
            }
            return (prop, 0.0);
        };
        let mut law = DofLaw::default();
        let limited = matches!(
            src.joint_type,
            urdf_rs::JointType::Revolute | urdf_rs::JointType::Prismatic
        );
        if limited {
            let (lower, upper) = (src.limit.lower, src.limit.upper);
            let ((lo, hi), note) = if lower == 0.0 && upper == 0.0 {
                stops_from_limits(lower, upper)
            } else {
                stops_from_limits(lower - q0, upper - q0)
            };
            law = law.with_stops(lo, hi);
            if let Some(n) = note {
                notices.push(format!("{el}: {n}"));
            }
        }
        if let Some(d) = &src.dynamics {
            if jt == JointType::Planar {
                if d.damping > 0.0 || d.friction > 0.0 {
                    notices.push(format!("{el}: dynamics of a planar joint ignored"));
                }
            } else {
                law.viscosity = d.damping;
                if d.friction > 0.0 {
                    law.friction = d.friction;
                }
            }
        }
        let pose2 = &loads.poses[child];
        let anchor =
            from_vec3(pose2.translation) + from_quat(pose2.rotation) * from_vec3(lf2.translation);
        let axis = from_quat(pose2.rotation * lf2.rotation) * Vector3::x();
        let (m_eff, scale) =
            load_beyond(&loads.masses, &loads.children, child, dof, &anchor, &axis);
        let rule_kf = friction_stiffness(m_eff, scale, self.options.resolved_substep());
        (prop.with_dof(dof, law), rule_kf)
    }
}

/// A notice when some of `ulink`'s collision meshes made no collider of `link` (unreadable
/// or degenerate files).
fn unread_collision_meshes(ulink: &urdf_rs::Link, link: &UrdfLink, notices: &mut Vec<String>) {
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
        // (which ones rapier3d-urdf could not read it does not say: the link's files, each
        // found, are named, a user's first place to look)
        let files: Vec<String> = (ulink.collision.iter())
            .filter_map(|c| match &c.geometry {
                urdf_rs::Geometry::Mesh { filename, .. } => Some(format!("`{filename}`")),
                _ => None,
            })
            .collect();
        notices.push(format!(
            "link `{}`: {} of {meshes} collision meshes unreadable (or degenerate): no \
             collider for them (the link's collision meshes: {})",
            ulink.name,
            meshes - made,
            files.join(", ")
        ));
    }
}
