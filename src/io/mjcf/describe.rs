//! Phase 1 of reading an MJCF model: its text → an [`MjcfRobot`] description, without
//! touching any world. The steps, in order: parse (mjcf-rs), validate the options, the model
//! and the overrides, let `rapier3d-mjcf` build the bodies, colliders and joints, then
//! describe each body (with its colliders), notice what is not mapped, measure the loads the
//! joints carry, and describe each joint (its KJOINT2 builder).

use super::actuators::Actuators;
use super::check::{
    bad_rotation, check_actuators, check_model, check_overrides, joint_element,
    located_parse_error, mesh_notices, unknown_class, Lines,
};
use super::MjcfRobot;
use crate::dynamics::{from_quat, from_vec3};
use crate::figure::fmt_num;
use crate::io::loaded;
use crate::io::robot::{
    at_zero_offset, move_to_initial_positions, place_body, InitialMotion, RobotJoint,
    RobotJointKind, RobotLink,
};
use crate::io::urdf::{
    apply_override, axis_dof, check_options, friction_by_rule, friction_stiffness,
    inverse_inertia_diagonal, kjoint_builder, load_beyond, motor_dof, place_mass, principal_axes,
    principal_mass_properties, stops_from_limits, with_break, with_override_connector,
    ErrorContext, LinkMass, TreeDof, UrdfError, UrdfOptions, BALL_RADIUS, WORLD_LINK,
};
use crate::law::{Curve, Dof, DofLaw, JointType, KjointProperty};
use crate::rapier::dynamics::{
    GenericJoint, JointAxesMask, JointAxis, MassProperties, RigidBody,
    RigidBodyAdditionalMassProps, RigidBodyBuilder, RigidBodySet,
};
use crate::rapier::geometry::{ColliderSet, Group, InteractionGroups, InteractionTestMode};
use crate::rapier::math::{Pose, Real, Vector};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use rapier3d_mjcf::mjcf_rs::body::InertiaSpec;
use rapier3d_mjcf::mjcf_rs::body::{GeomType, Joint as MjcfJoint, JointType as MjcfJointType};
use rapier3d_mjcf::mjcf_rs::compiler::InertiaFromGeom;
use rapier3d_mjcf::mjcf_rs::equality::Equality;
use rapier3d_mjcf::mjcf_rs::model::Model;
use rapier3d_mjcf::{
    MjcfJoint as RapierMjcfJoint, MjcfLoaderOptions, MjcfRobot as RapierMjcfRobot,
};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::Path;

/// Describes the MJCF text `text` (read from `file`; `<include>` and meshes relative to
/// `base`).
pub(super) fn describe(
    text: &str,
    file: &str,
    base: &Path,
    options: &UrdfOptions,
) -> Result<MjcfRobot, UrdfError> {
    let context = ErrorContext { file };
    let included = super::files::check_includes(file, text, base)?;
    let model = Model::from_str(text, base).map_err(|e| {
        // mjcf-rs names no line, and neither the element nor the attribute of a number it
        // cannot read (`invalid attribute `_` on <_>`): find them
        located_parse_error(&context, text, &e).unwrap_or_else(|| UrdfError::Mjcf {
            file: file.to_string(),
            message: e.to_string(),
        })
    })?;
    check_options(&context, options)?;
    let mut keyframe_notices = Vec::new();
    let options = &with_keyframe(&context, &model, options, &mut keyframe_notices)?;
    // the text parsed once for the checks that read it as written (mjcf-rs has parsed it
    // too, and keeps no document)
    let doc = roxmltree::Document::parse(text).ok();
    if let Some(doc) = &doc {
        unknown_class(&context, doc)?;
        bad_rotation(&context, doc)?;
    }
    super::option::check(&context, &model, doc.as_ref())?;
    let lines = doc.as_ref().and_then(|d| Lines::of(d, &model));
    check_model(&context, &model, lines.as_ref())?;
    check_actuators(&context, &model, doc.as_ref())?;
    check_overrides(&context, &model, options)?;
    super::files::check_mesh_files(file, &model, base)?;
    let robot = build_with_rapier(&context, &model, base, options, false)?;
    // the visual geoms' shapes, for the bodies whose mass their geoms make with them:
    // `rapier3d-mjcf` counts them, but makes no colliders of them
    let with_visual = if model.bodies.iter().any(|e| {
        inertia_from_geoms(&model, &e.body)
            && e.body.geoms.len() > 1
            && e.body.geoms.iter().any(is_visual)
    }) {
        Some(build_with_rapier(&context, &model, base, options, true)?)
    } else {
        None
    };
    let name = robot.name.clone().or(model.name.clone());
    let mut out = MjcfRobot::new(file, name.unwrap_or_default());
    out.gravity = super::option::gravity(&model, doc.as_ref());
    let substep = options.resolved_substep();
    out.notices
        .extend(super::option::notices(&model, doc.as_ref(), substep));
    out.notices
        .extend(super::unread::notices(doc.as_ref(), base, &included));
    out.notices.extend(keyframe_notices);
    let fixed = static_bodies(&model);
    let describer = Describer {
        environment: environment(&model, &fixed),
        fixed,
        context,
        model: &model,
        robot: &robot,
        with_visual: with_visual.as_ref(),
        options,
    };
    // before the bodies' notices: a body whose mesh is skipped may be given the minimum mass
    let skipped = mesh_notices(&model, base);
    let meshes_skipped = !skipped.is_empty();
    out.notices.extend(skipped);
    let index = describer.bodies(&mut out)?;
    out.notices.extend(no_collider(&out.links, meshes_skipped));
    // before the joints' frames and loads are measured, as the base pose
    describer.move_to_initial_positions(&mut out.links, &index);
    describer.unmapped(&mut out.notices);
    let loads = Loads::of(&out.links, &index, &robot);
    out.joints = describer.joints(&out.links, &index, &loads, &mut out.notices)?;
    out.fuse_fixed_joints(options);
    // the pairs MuJoCo leaves apart, where the links collide at all: any two with
    // `self_collisions`, else the environment's with the robot's
    // (by name: `index` is the links' before the fusion)
    let environment: HashSet<String> = (0..robot.bodies.len())
        .filter(|&i| index[i].is_some() && describer.is_environment(i))
        .map(|i| describer.body_name(i))
        .collect();
    let collide = |a: &str, b: &str| {
        let (ea, eb) = (environment.contains(a), environment.contains(b));
        !(ea && eb) && (options.self_collisions || ea || eb)
    };
    out.contact_excludes = (model.contact.excludes.iter())
        .filter(|e| collide(&e.body1, &e.body2))
        .map(|e| [e.body1.clone(), e.body2.clone()])
        .collect();
    out.contact_excludes
        .extend(apart_by_contype(&model, &out, collide));
    // MuJoCo's parent filter across joints in series: a body of several joints hangs on
    // its parent through spacer bodies, which the joints' own contact switches skip (the
    // humanoid's thighs, 8.7 cm inside its pelvis, pushed out from the first substep)
    if options.self_collisions {
        for e in model.bodies.iter().skip(1) {
            let serial = (e.body.joints.iter())
                .filter(|j| j.type_ != MjcfJointType::Free)
                .count();
            let (Some(name), Some(parent)) = (&e.body.name, e.parent) else {
                continue;
            };
            let parent = match parent {
                0 => Some(WORLD_LINK.to_string()),
                p => model.bodies[p].body.name.clone(),
            };
            if let (true, Some(parent)) = (serial >= 2, parent) {
                out.contact_excludes.push([parent, name.clone()]);
            }
        }
    }
    Ok(out)
}

/// The pairs of the robot's links (of those `collide` admits: both the robot's with
/// `self_collisions`, else one the environment's) of which no two geoms collide by MuJoCo's rule, `(contype₁
/// & conaffinity₂) ≠ 0 or (contype₂ & conaffinity₁) ≠ 0` (gymnasium's walkers give their
/// geoms `conaffinity = 0`: they touch the floor, never each other). rapier3d-mjcf's collision
/// groups (`contype | conaffinity` both ways, which collide with the user's colliders as
/// any rapier collider) let them touch, so these pairs are left apart as an `<exclude>` is
/// ([`crate::io::robot::RobotDescription::contact_excludes`]). A link's geoms are its
/// body's and those of the bodies fused into it; where some geom pairs of two links
/// collide and others not, the pair collides whole.
fn apart_by_contype(
    model: &Model,
    out: &MjcfRobot,
    collide: impl Fn(&str, &str) -> bool,
) -> Vec<[String; 2]> {
    let geoms = |name: &str| -> Vec<(u32, u32)> {
        // (mjcf-rs finds no world body by name)
        let id = match name {
            WORLD_LINK => Some(0),
            _ => model.body_id_by_name(name),
        };
        let Some(id) = id else {
            return Vec::new();
        };
        (model.bodies[id].body.geoms.iter())
            .filter(|g| !is_visual(g))
            .map(|g| (g.contype, g.conaffinity))
            .collect()
    };
    let links: Vec<(&str, Vec<(u32, u32)>)> = (out.links.iter().enumerate())
        .filter(|(_, l)| !l.spacer && !l.colliders.is_empty())
        .map(|(k, l)| {
            let fused = (out.fused.iter()).filter(|f| f.into == k);
            let mut g = geoms(&l.name);
            g.extend(fused.flat_map(|f| geoms(&f.link)));
            (l.name.as_str(), g)
        })
        .collect();
    let touch = |a: &[(u32, u32)], b: &[(u32, u32)]| {
        (a.iter()).any(|(ct1, ca1)| (b.iter()).any(|(ct2, ca2)| ct1 & ca2 != 0 || ct2 & ca1 != 0))
    };
    let mut apart = Vec::new();
    for (i, (a, ga)) in links.iter().enumerate() {
        for (b, gb) in &links[i + 1..] {
            if collide(a, b) && !ga.is_empty() && !gb.is_empty() && !touch(ga, gb) {
                apart.push([a.to_string(), b.to_string()]);
            }
        }
    }
    apart
}

/// `options` with the positions of the keyframe [`UrdfOptions::keyframe`] names added to its
/// [`UrdfOptions::initial_positions`] (whose own entries win), by joint name: a keyframe's
/// `qpos` lists the joints' coordinates in MuJoCo's order, the bodies depth first as the
/// file writes them (mjcf-rs's body order) and each body's joints in order, a free joint 7
/// (position, quaternion), a ball 4, a hinge or slide 1 (MuJoCo stores keyframes as `qpos`:
/// radians whatever the compiler's angle unit).
fn with_keyframe(
    context: &ErrorContext,
    model: &Model,
    options: &UrdfOptions,
    notices: &mut Vec<String>,
) -> Result<UrdfOptions, UrdfError> {
    let mut options = options.clone();
    let Some(name) = options.keyframe.clone() else {
        return Ok(options);
    };
    let Some(key) = model
        .keyframes
        .iter()
        .find(|k| k.name.as_deref() == Some(&name))
    else {
        let names: Vec<&str> = model
            .keyframes
            .iter()
            .filter_map(|k| k.name.as_deref())
            .collect();
        return Err(context.field(
            "options",
            "keyframe",
            &name,
            format!("the name of a keyframe of the model (it has: {names:?})"),
        ));
    };
    let el = format!("keyframe `{name}`");
    let joints: Vec<&MjcfJoint> = (model.bodies_iter())
        .flat_map(|(_, e)| e.body.joints.iter())
        .collect();
    let size = |j: &MjcfJoint| match j.type_ {
        MjcfJointType::Free => 7,
        MjcfJointType::Ball => 4,
        _ => 1,
    };
    let nq: usize = joints.iter().map(|j| size(j)).sum();
    // the actuators' controls at the start (read by `Actuators::of`)
    let nu = model.actuators.len();
    if !key.ctrl.is_empty() && key.ctrl.len() != nu {
        return Err(context.field(
            &el,
            "ctrl",
            format!("{} values", key.ctrl.len()),
            format!("{nu} values, one per actuator of the model"),
        ));
    }
    for u in &key.ctrl {
        context.finite(&el, "ctrl", *u)?;
    }
    if key.qpos.is_empty() {
        return Ok(options);
    }
    if key.qpos.len() != nq {
        return Err(context.field(
            &el,
            "qpos",
            format!("{} values", key.qpos.len()),
            format!("{nq} values, one per coordinate of the model's joints"),
        ));
    }
    let mut at = 0;
    for j in joints {
        let q = &key.qpos[at..at + size(j)];
        at += size(j);
        let what = match j.type_ {
            MjcfJointType::Free => "the free joint's pose",
            MjcfJointType::Ball => "the ball joint's orientation",
            _ => "the position",
        };
        let moved = match j.type_ {
            MjcfJointType::Free | MjcfJointType::Ball => true,
            _ => q[0] != j.ref_,
        };
        match (&j.name, j.type_) {
            (Some(n), MjcfJointType::Hinge | MjcfJointType::Slide) => {
                context.finite(&el, "qpos", q[0])?;
                options.initial_positions.entry(n.clone()).or_insert(q[0]);
            }
            (n, _) if moved => notices.push(format!(
                "{el}: {what} of {} not applied",
                n.as_deref()
                    .map_or("an unnamed joint".into(), |n| format!("joint `{n}`"))
            )),
            _ => {}
        }
    }
    Ok(options)
}

/// The `ctrl` of the keyframe `options` names (checked by [`with_keyframe`]): the
/// actuators' controls at the start, empty without one.
fn keyframe_ctrl<'m>(model: &'m Model, options: &UrdfOptions) -> &'m [f64] {
    let name = options.keyframe.as_deref();
    (model.keyframes.iter())
        .find(|k| name.is_some() && k.name.as_deref() == name)
        .map_or(&[], |k| k.ctrl.as_slice())
}

/// `rapier3d-mjcf`'s bodies, colliders and joints of the (validated) model. They are f32
/// objects (rapier3d), converted into the world's rapier by [`loaded`]. `visual`: visual
/// geoms (`contype` = `conaffinity` = 0) made colliders too.
fn build_with_rapier(
    context: &ErrorContext,
    model: &Model,
    base: &Path,
    options: &UrdfOptions,
    visual: bool,
) -> Result<RapierMjcfRobot, UrdfError> {
    let loader = MjcfLoaderOptions {
        create_colliders_from_visual_shapes: visual,
        make_roots_fixed: options.fixed_base,
        mesh_converter: Some(options.collision_meshes.converter()),
        rigid_body_blueprint: rapier3d::dynamics::RigidBodyBuilder::dynamic()
            .can_sleep(options.can_sleep),
        collider_blueprint: rapier3d::geometry::ColliderBuilder::default().density(0.0),
        disable_joint_motors: true,
        // a floor: a half-space (its normal the geom's z) on the world or a body welded to it
        skip_plane_geoms: false,
        ..Default::default()
    };
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        RapierMjcfRobot::from_model(model, loader, base)
    }))
    .map_err(|_| UrdfError::Mjcf {
        file: context.file.to_string(),
        message: "rapier3d-mjcf could not build the model".into(),
    })
}

/// Whether `rapier3d-mjcf` gives the MJCF body `body` the mass of its geoms (when they have
/// one): the compiler's `inertiafromgeom="true"`, or `"auto"` and no `<inertial>`.
fn inertia_from_geoms(model: &Model, body: &rapier3d_mjcf::mjcf_rs::body::Body) -> bool {
    match model.compiler.inertia_from_geom {
        InertiaFromGeom::True => true,
        InertiaFromGeom::Auto => body.inertial.is_none(),
        _ => false,
    }
}

/// A notice when no moving body of the model has a collider: it collides with nothing, the
/// floor included (a floating one falls through it), which a notice per skipped mesh geom
/// did not say (a URDF robot whose meshes were all missing fell out of sight so; a user
/// trial, 2026-12-05). `meshes_skipped`: mesh geoms were skipped (named in notices).
fn no_collider(links: &[crate::io::robot::RobotLink], meshes_skipped: bool) -> Option<String> {
    let mut moving = links.iter().filter(|l| l.body.is_dynamic()).peekable();
    moving.peek()?;
    if moving.any(|l| !l.colliders.is_empty()) {
        return None;
    }
    let why = if meshes_skipped {
        " (mesh geoms were skipped, as the notices above say)"
    } else {
        ""
    };
    Some(format!(
        "no moving body of the model has a collider{why}: they collide with nothing, the \
         floor included (a floating base falls through it)"
    ))
}

/// A visual geom: `rapier3d-mjcf` makes no collider of it (by default), but counts its mass.
fn is_visual(g: &rapier3d_mjcf::mjcf_rs::body::Geom) -> bool {
    g.contype == 0 && g.conaffinity == 0
}

/// The loads the joints carry: per `rapier3d-mjcf` body, its mass ([`LinkMass`], zero for
/// fixed bodies and the world) and the bodies that hang on it.
struct Loads {
    masses: Vec<LinkMass>,
    children: Vec<Vec<usize>>,
    /// Per `rapier3d-mjcf` joint with a `springdamper`: the inertia MuJoCo's compiler sets
    /// its spring and damper from ([`springdamper_inertias`]); `None` elsewhere, or where
    /// the joint moves no mass.
    springdamper: Vec<Option<f64>>,
}

impl Loads {
    /// The loads of the described `links` (`index`: `rapier3d-mjcf` body → link), with the
    /// mass properties each body has once its colliders are attached.
    fn of(links: &[RobotLink], index: &[Option<usize>], robot: &RapierMjcfRobot) -> Self {
        let masses: Vec<LinkMass> = index
            .iter()
            .map(|l| match l.and_then(|l| links.get(l)) {
                Some(link) if link.body.is_dynamic() => mass_with_colliders(link),
                _ => LinkMass::ZERO,
            })
            .collect();
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); robot.bodies.len()];
        for j in &robot.joints {
            children[j.link1].push(j.link2);
        }
        let springdamper = springdamper_inertias(links, index, robot, &masses, &children);
        Loads {
            masses,
            children,
            springdamper,
        }
    }
}

/// The inertia of each joint with a `springdamper` as MuJoCo's compiler takes it
/// (`mjCModel::AutoSpringDamper`): `n / Σ (M⁻¹)_ii` over the joint's `n` degrees of freedom,
/// `M` the joint-space inertia of the whole model (a floating base's six degrees of freedom
/// with it, the armatures on its diagonal; [`inverse_inertia_diagonal`]), here at the pose
/// the robot is inserted in (MuJoCo's at `qpos0`: the same unless a keyframe or
/// `initial_positions` moves the joints). Empty where no joint has one.
fn springdamper_inertias(
    links: &[RobotLink],
    index: &[Option<usize>],
    robot: &RapierMjcfRobot,
    masses: &[LinkMass],
    children: &[Vec<usize>],
) -> Vec<Option<f64>> {
    if robot.joints.iter().all(|j| j.springdamper.is_none()) {
        return Vec::new();
    }
    // the degrees of freedom of every joint, then those of the floating bases
    let mut dofs = Vec::new();
    let mut of_joint = Vec::with_capacity(robot.joints.len());
    for uj in &robot.joints {
        let first = dofs.len();
        if let Some(link) = index[uj.link2].and_then(|l| links.get(l)) {
            let joint = loaded::joint(&uj.joint);
            let (anchor, axis) = anchor_and_axis(&joint, link.body.position());
            let mut moved = match joint_type(&joint) {
                JointType::Revolute => vec![TreeDof::hinge(uj.link2, &anchor, &axis)],
                JointType::Translational => vec![TreeDof::slide(uj.link2, &axis)],
                JointType::Spherical => (0..3)
                    .map(|k| TreeDof::hinge(uj.link2, &anchor, &Vector3::ith(k, 1.0)))
                    .collect(),
                _ => Vec::new(),
            };
            for d in &mut moved {
                d.armature = uj.armature_per_dof as f64;
            }
            dofs.extend(moved);
        }
        of_joint.push(first..dofs.len());
    }
    let jointed: HashSet<usize> = robot.joints.iter().map(|j| j.link2).collect();
    for (b, m) in masses.iter().enumerate() {
        if m.m > 0.0 && !jointed.contains(&b) {
            dofs.extend(TreeDof::free(b));
        }
    }
    let diagonal = inverse_inertia_diagonal(masses, children, &dofs);
    (robot.joints.iter().zip(of_joint))
        .map(|(uj, range)| {
            let d = diagonal.as_ref()?;
            let n = range.len() as f64;
            let sum: f64 = d[range].iter().sum();
            (uj.springdamper.is_some() && n > 0.0).then_some(n / sum)
        })
        .collect()
}

/// The mass of the link's body once its colliders are attached, measured in a scratch set
/// (no world is touched): what inserting it makes.
fn mass_with_colliders(link: &RobotLink) -> LinkMass {
    let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    let h = bodies.insert(link.body.clone());
    for c in &link.colliders {
        colliders.insert_with_parent(c.clone(), h, &mut bodies);
    }
    match bodies.get_mut(h) {
        Some(rb) => {
            rb.recompute_mass_properties_from_colliders(&colliders);
            link_mass(rb)
        }
        None => link_mass(&link.body),
    }
}

/// Mass, centre and world inertia of a body from its rapier mass properties.
fn link_mass(rb: &RigidBody) -> LinkMass {
    let mp = rb.mass_properties().local_mprops;
    let pose = rb.position();
    let c = from_vec3(pose * mp.local_com);
    let rot = from_quat(pose.rotation).to_rotation_matrix();
    let i = mp.reconstruct_inertia_matrix();
    let local = Matrix3::from_fn(|r, k| i.col(k)[r] as f64);
    LinkMass {
        m: mp.mass() as f64,
        c,
        inertia: rot.matrix() * local * rot.matrix().transpose(),
    }
}

/// The model's environment, by MJCF body id: the world body and the static bodies welded
/// to it (MuJoCo's: no joint, not `mocap`, the parent the world or a static body) from
/// which no moving body hangs (a fixed arm's base is the robot's, a table is not). Their
/// geoms (floors, walls, tables) touch the robot's links whether or not
/// [`UrdfOptions::self_collisions`], by MuJoCo's rule of `contype` and `conaffinity`
/// ([`apart_by_contype`]), but for a link joined to them (a joint to the environment keeps
/// its contacts off: MuJoCo exempts the world from its parent filter, so that a first link
/// overlapping its mount would be pushed off it). `fixed`: [`static_bodies`].
fn environment(model: &Model, fixed: &[bool]) -> Vec<bool> {
    let n = model.bodies.len();
    // bodies with a moving body below them
    let mut carries = vec![false; n];
    for (id, e) in model.bodies.iter().enumerate().skip(1).rev() {
        if let Some(p) = e.parent.filter(|&p| p < id) {
            carries[p] |= !fixed[id] || carries[id];
        }
    }
    (0..n)
        .map(|id| id == 0 || (fixed[id] && !carries[id]))
        .collect()
}

/// MuJoCo's static bodies, by MJCF body id: the world, and the bodies with no joint, not
/// `mocap`, whose parent is static (mjcf-rs lists a body after its parent).
fn static_bodies(model: &Model) -> Vec<bool> {
    let mut fixed = vec![true; model.bodies.len()];
    for (id, e) in model.bodies.iter().enumerate().skip(1) {
        fixed[id] = e.parent.is_some_and(|p| p < id && fixed[p])
            && e.body.joints.is_empty()
            && !e.body.mocap;
    }
    fixed
}

/// What the body and joint descriptions are made from.
struct Describer<'a> {
    /// [`static_bodies`]
    fixed: Vec<bool>,
    /// [`environment`]
    environment: Vec<bool>,
    context: ErrorContext<'a>,
    model: &'a Model,
    robot: &'a RapierMjcfRobot,
    /// The same built with visual geoms as colliders, when a body's mass counts them
    with_visual: Option<&'a RapierMjcfRobot>,
    options: &'a UrdfOptions,
}

impl Describer<'_> {
    /// The name of `rapier3d-mjcf`'s body `i`: `world` for the world body.
    fn body_name(&self, i: usize) -> String {
        let b = &self.robot.bodies[i];
        match (&b.name, i) {
            (_, 0) => WORLD_LINK.to_string(),
            (Some(n), _) => n.clone(),
            (None, _) => format!("body{}", b.mjcf_body_id),
        }
    }

    /// Whether `rapier3d-mjcf`'s body `i` is the model's environment ([`environment`]).
    fn is_environment(&self, i: usize) -> bool {
        i == 0
            || (self.robot.bodies.get(i)).is_some_and(|b| {
                !b.is_intermediate && self.environment.get(b.mjcf_body_id) == Some(&true)
            })
    }

    /// Describes the bodies into `out.links`: the world (body 0) as a fixed body when
    /// something hangs on it, the others with the minimum mass when they have none (spacers
    /// between joints in series too). Returns the link of each `rapier3d-mjcf` body.
    fn bodies(&self, out: &mut MjcfRobot) -> Result<Vec<Option<usize>>, UrdfError> {
        let robot = self.robot;
        let needs_world = !robot.bodies[0].colliders.is_empty()
            || robot.joints.iter().any(|j| j.link1 == 0 || j.link2 == 0);
        let group = Group::GROUP_32;
        let groups = InteractionGroups::new(group, Group::ALL ^ group, InteractionTestMode::And);
        let mut index = vec![None; robot.bodies.len()];
        let mut spacers: BTreeMap<String, usize> = BTreeMap::new();
        for (i, b) in robot.bodies.iter().enumerate() {
            let mut body = if i == 0 {
                if !needs_world {
                    continue;
                }
                RigidBodyBuilder::fixed().build()
            } else {
                loaded::body(&b.body)
            };
            // where the model stands (its world body too): before the loads are measured
            place_body(&mut body, &self.options.base_pose);
            if body.is_dynamic() && b.mass <= 0.0 {
                let mm = self.options.min_link_mass as Real;
                let inertia = 0.4 * mm * (BALL_RADIUS * BALL_RADIUS) as Real;
                body.set_additional_mass_properties(
                    MassProperties::new(Vector::ZERO, mm, Vector::splat(inertia)),
                    false,
                );
                if b.is_intermediate {
                    *spacers.entry(spacer_of(&self.body_name(i))).or_default() += 1;
                } else {
                    out.notices.push(format!(
                        "body `{}`: no mass in the MJCF: given {} kg",
                        self.body_name(i),
                        self.options.min_link_mass
                    ));
                }
            }
            let mut colliders = Vec::with_capacity(b.colliders.len());
            // a static body's (a plane on a mount that carries an arm is a floor too)
            let fixed =
                i == 0 || (!b.is_intermediate && self.fixed.get(b.mjcf_body_id) == Some(&true));
            for c in &b.colliders {
                let plane = c.shape().as_halfspace().is_some();
                if plane && !fixed {
                    out.notices.push(format!(
                        "body `{}`: its plane geom is not loaded (MuJoCo allows planes on \
                         static bodies only: the world and the bodies welded to it)",
                        self.body_name(i)
                    ));
                    continue;
                }
                let mut c = loaded::collider(c).map_err(|e| UrdfError::Mjcf {
                    file: self.context.file.to_string(),
                    message: format!("body `{}`: {e}", self.body_name(i)),
                })?;
                if self.is_environment(i) || plane {
                    // a floor touches the robot's links (with `self_collisions` by the
                    // groups `rapier3d-mjcf` gives, which let any two geoms touch)
                    if !self.options.self_collisions {
                        c.set_collision_groups(InteractionGroups::all());
                    }
                } else if !self.options.self_collisions {
                    c.set_collision_groups(groups);
                }
                colliders.push(c);
            }
            if i > 0 && body.is_dynamic() && b.mass > 0.0 && !b.is_intermediate {
                // rapier3d-mjcf's where it is right (diaginertia, one geom), kept through the
                // sum with the colliders too
                let own = match body.mass_properties().additional_local_mprops.as_deref() {
                    Some(RigidBodyAdditionalMassProps::MassProps(m)) => Some(*m),
                    _ => None,
                };
                let mp = self.full_inertia(b).or_else(|| self.geom_sum(i));
                if let Some(mp) = mp.or(own) {
                    if let Some(err) = place_mass(&mut body, &mut colliders, mp) {
                        out.notices.push(format!(
                            "body `{}`: its geoms make rapier diagonalise its inertia tensor \
                             again in f32: off by up to {:.1} % of its largest term",
                            self.body_name(i),
                            err * 100.0
                        ));
                    }
                }
            }
            index[i] = Some(out.links.len());
            out.links.push(RobotLink {
                name: self.body_name(i),
                body,
                colliders,
                visual_meshes: Vec::new(),
                spacer: b.is_intermediate,
            });
        }
        for (body, n) in &spacers {
            out.notices.push(format!(
                "body `{body}`: {} joints in series through {n} spacer body(ies) of {} kg each \
                 (no mass in MJCF)",
                n + 1,
                self.options.min_link_mass
            ));
        }
        Ok(index)
    }

    /// The mass properties of the body `b` where its `<inertial>` gives a `fullinertia`
    /// (and the compiler takes it, not the geoms'): the tensor turned by the inertial's frame
    /// and diagonalised in double precision (`rapier3d-mjcf` has parry do it in f32), then
    /// the compiler's `boundmass`, `boundinertia`, `balanceinertia` and `settotalmass` as
    /// `rapier3d-mjcf` applies them. `None` for other bodies: `rapier3d-mjcf`'s stand.
    fn full_inertia(&self, b: &rapier3d_mjcf::MjcfBody) -> Option<MassProperties> {
        let compiler = &self.model.compiler;
        if compiler.inertia_from_geom == InertiaFromGeom::True {
            return None;
        }
        let inertial = self
            .model
            .bodies
            .get(b.mjcf_body_id)?
            .body
            .inertial
            .as_ref()?;
        let InertiaSpec::Full([ixx, iyy, izz, ixy, ixz, iyz]) = inertial.inertia else {
            return None;
        };
        let tensor = Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
        let (t, q) = (inertial.pose.translation, inertial.pose.rotation);
        let turn = UnitQuaternion::from_quaternion(Quaternion::new(q.w, q.x, q.y, q.z));
        let turn = turn.to_rotation_matrix();
        let tensor = turn.matrix() * tensor * turn.matrix().transpose();
        let com = Vector3::new(t.x, t.y, t.z);
        Some(self.compiled(b, inertial.mass, &com, &tensor))
    }

    /// The mass properties of the body `i` (of `rapier3d-mjcf`'s) whose mass two geoms or
    /// more make: `rapier3d-mjcf` sums theirs with parry's `+` (diagonalised in f32), here in
    /// double precision. Each geom's in its own frame is parry's (exact for primitives): moved
    /// onto the body (parallel axes), summed and diagonalised in f64, then the compiler's
    /// bounds as for [`Self::full_inertia`]. The geoms counted and their densities are
    /// `rapier3d-mjcf`'s (`loader/mass.rs`: every geom whose shape it builds, its `mass` or
    /// `density`, else the compiler's); the shapes and their poses on the body are its
    /// colliders'. `None` where one geom or none has mass, or where the colliders are not
    /// the geoms one for one (a shape it cannot build): `rapier3d-mjcf`'s stand.
    ///
    /// An ellipsoid geom is `rapier3d-mjcf`'s convex hull of a scaled icosphere, 60.5 % of
    /// the ellipsoid's volume: its mass and inertia are the ellipsoid's here (`4/3·π·abc·ρ`,
    /// `m·(b² + c²)/5`, … about its axes), for a body of one geom too (a 0.1 × 0.05 × 0.05
    /// ellipsoid at 1000 kg/m³ weighed 0.634 kg for 1.047 kg, with nothing said; an MJCF
    /// user's trial, 2026-12-06). Its contact shape stays the hull.
    fn geom_sum(&self, i: usize) -> Option<MassProperties> {
        let b = &self.robot.bodies[i];
        let body = &self.model.bodies.get(b.mjcf_body_id)?.body;
        let ellipsoid = |g: &rapier3d_mjcf::mjcf_rs::body::Geom| g.type_ == GeomType::Ellipsoid;
        let any_ellipsoid = body.geoms.iter().any(ellipsoid);
        if !inertia_from_geoms(self.model, body) || (body.geoms.len() < 2 && !any_ellipsoid) {
            return None;
        }
        let colliders = match self.with_visual {
            Some(r) if body.geoms.iter().any(is_visual) => &r.bodies.get(i)?.colliders,
            _ => &b.colliders,
        };
        if colliders.len() != body.geoms.len() {
            return None;
        }
        let v3 = |v: rapier3d::math::Vector| Vector3::new(v.x as f64, v.y as f64, v.z as f64);
        let rot = |q: rapier3d::math::Rotation| {
            UnitQuaternion::from_quaternion(Quaternion::new(
                q.w as f64, q.x as f64, q.y as f64, q.z as f64,
            ))
            .to_rotation_matrix()
        };
        // per geom: mass, centre and tensor about it, on the body
        let mut parts = Vec::with_capacity(colliders.len());
        for (g, c) in body.geoms.iter().zip(colliders) {
            let unit = c.shape().mass_properties(1.0);
            let [ea, eb, ec] = g.size;
            let volume = if ellipsoid(g) {
                (4.0 / 3.0 * std::f64::consts::PI * ea * eb * ec) as f32
            } else {
                unit.mass()
            };
            // the loader's density, in f32 (then the mass it makes, in f64)
            let density = match g.mass {
                Some(m) if volume > 1e-30 => m as f32 / volume,
                Some(_) => 0.0,
                None => g.density.unwrap_or(self.model.compiler.inertia_density) as f32,
            };
            if density <= 0.0 {
                continue;
            }
            // the density as a mass (exact) over the volume, in f64
            let (mass, density) = match g.mass {
                Some(m) => (m, m / volume as f64),
                None => (density as f64 * volume as f64, density as f64),
            };
            let pose = c.position_wrt_parent().copied().unwrap_or(*c.position());
            let turn = rot(pose.rotation);
            let (com, tensor) = if ellipsoid(g) {
                // about its own axes, the geom's frame, centred on it
                let (a2, b2, c2) = (ea * ea, eb * eb, ec * ec);
                let moments = Vector3::new(b2 + c2, a2 + c2, a2 + b2) * (mass / 5.0);
                let tensor = turn.matrix() * Matrix3::from_diagonal(&moments);
                (v3(pose.translation), tensor * turn.matrix().transpose())
            } else {
                let axes = turn * rot(unit.principal_inertia_local_frame);
                let moments = Matrix3::from_diagonal(&(v3(unit.principal_inertia()) * density));
                let tensor = axes.matrix() * moments * axes.matrix().transpose();
                (turn * v3(unit.local_com) + v3(pose.translation), tensor)
            };
            parts.push((mass, com, tensor));
        }
        if parts.is_empty() || (parts.len() < 2 && !any_ellipsoid) {
            return None;
        }
        let mass: f64 = parts.iter().map(|p| p.0).sum();
        let com = parts.iter().map(|p| p.1 * p.0).sum::<Vector3<f64>>() / mass;
        let tensor = parts
            .iter()
            .map(|(m, c, t)| {
                let d = c - com;
                t + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * *m
            })
            .sum::<Matrix3<f64>>();
        Some(self.compiled(b, mass, &com, &tensor))
    }

    /// Rapier mass properties of mass `mass` at `com` with the tensor `tensor` about it (body
    /// frame), diagonalised in double precision, then the compiler's `boundmass`,
    /// `boundinertia`, `balanceinertia` and `settotalmass` as `rapier3d-mjcf` applies them to
    /// the body `b`.
    fn compiled(
        &self,
        b: &rapier3d_mjcf::MjcfBody,
        mut mass: f64,
        com: &Vector3<f64>,
        tensor: &Matrix3<f64>,
    ) -> MassProperties {
        let compiler = &self.model.compiler;
        let (mut moments, axes) = principal_axes(tensor);
        if compiler.bound_mass > 0.0 && mass < compiler.bound_mass {
            mass = compiler.bound_mass;
        }
        if compiler.bound_inertia > 0.0 {
            moments = moments.map(|m| m.max(compiler.bound_inertia));
        }
        if compiler.balance_inertia {
            for (k, a, c) in [(0, 1, 2), (1, 0, 2), (2, 0, 1)] {
                moments[k] = moments[k].max((moments[a] - moments[c]).abs());
            }
        }
        if compiler.set_total_mass > 0.0 && mass > 0.0 {
            // the loader's factor, read off the mass it gave the body
            let factor = b.mass as f64 / mass;
            mass *= factor;
            moments *= factor;
        }
        principal_mass_properties(com, mass, &moments, &axes)
    }

    /// A notice for each part of the model that is not mapped: free joints (fixed or
    /// floating bodies), armature, actuators, tendons, equality constraints, sensors,
    /// keyframes and contact pairs (contact excludes are applied where the links collide,
    /// [`crate::io::robot::RobotDescription::contact_excludes`]).
    fn unmapped(&self, notices: &mut Vec<String>) {
        let model = self.model;
        let free = model
            .bodies_iter()
            .filter(|(_, e)| e.body.joints.iter().any(|j| j.type_ == MjcfJointType::Free))
            .count();
        if free > 0 {
            notices.push(format!(
                "{free} body(ies) with a free joint: {} (no KJOINT2 joint)",
                if self.options.fixed_base {
                    "fixed where they are (fixed_base = true)"
                } else {
                    "floating"
                }
            ));
        }
        // (an unnamed joint by its body, as errors name it). Not mapped by default: with the
        // gymnasium models' armatures (walker2d's 0.01 kg·m²) the collapsing walker2d's
        // light capsule feet opened their joints 18 mm at a landing in double precision at 4
        // substeps (6.5 mm in single; 1 cm is the test's bound): the rotor makes the hinge
        // carry the foot's strike, and a blocked DOF opens by its load over the foot's mass
        // a substep (README, "MJCF robots")
        let armature: Vec<String> = (model.bodies_iter())
            .flat_map(|(_, e)| {
                let body = e.body.name.as_deref();
                let joints = e.body.joints.iter().enumerate();
                joints
                    .filter(|(_, j)| j.armature > 0.0)
                    .map(move |(k, j)| joint_element(j.name.as_deref(), body, k))
            })
            .collect();
        if !armature.is_empty() {
            notices.push(format!(
                "armature of {} joint(s) not mapped (a joint's rotor is its override's \
                 `armature`, options.joints.<name>.armature): {}",
                armature.len(),
                armature.join(", ")
            ));
        }
        notices.extend(Actuators::of(model, &[]).notices);
        // each by its name, or by what it ties where it has none (a user could not tell which
        // of a model's constraints the count was about; a `<connect>` that closes a loop
        // leaves it open)
        let named = |name: &Option<String>, or: String| match name {
            Some(n) => format!("`{n}`"),
            None => or,
        };
        let pair = |a: &str, b: &Option<String>| format!("{a}–{}", b.as_deref().unwrap_or("world"));
        let tendons: Vec<String> = (model.tendons.iter())
            .map(|t| {
                let on: Vec<&str> = t.joints.iter().map(|j| j.joint.as_str()).collect();
                named(&t.name, format!("on joints {}", on.join(", ")))
            })
            .collect();
        // (a coupling without its second joint or tendon holds the first at a constant)
        let coupling = |a: &str, b: &Option<String>| match b {
            Some(b) => format!("{a}–{b}"),
            None => format!("{a} held at a constant"),
        };
        let equality: Vec<String> = (model.equality.iter())
            .map(|e| match e {
                // between two bodies it closes a loop the joints leave open; to the world it
                // pins its body
                Equality::Connect(c) => format!(
                    "connect {} ({})",
                    named(&c.common.name, pair(&c.body1, &c.body2)),
                    if c.body2.is_some() {
                        "a loop it closes is left open"
                    } else {
                        "its body is not pinned to the world"
                    }
                ),
                Equality::Weld(w) => {
                    format!("weld {}", named(&w.common.name, pair(&w.body1, &w.body2)))
                }
                Equality::Joint(j) => format!(
                    "joint coupling {}",
                    named(&j.common.name, coupling(&j.joint1, &j.joint2))
                ),
                Equality::Tendon(t) => format!(
                    "tendon coupling {}",
                    named(&t.common.name, coupling(&t.tendon1, &t.tendon2))
                ),
            })
            .collect();
        let sensors: Vec<String> = (model.sensors.iter())
            .map(|s| {
                let on = s
                    .objname
                    .as_deref()
                    .map_or(String::new(), |o| format!(" on {o}"));
                format!("{} {}", s.kind, named(&s.name, format!("(unnamed){on}")))
            })
            .collect();
        let keyframes = model.keyframes.len() - usize::from(self.options.keyframe.is_some());
        for (what, list) in [
            ("tendon", tendons),
            ("equality constraint", equality),
            ("sensor", sensors),
        ] {
            if !list.is_empty() {
                notices.push(format!(
                    "{} {what}(s) not mapped (ignored): {}",
                    list.len(),
                    list.join(", ")
                ));
            }
        }
        if keyframes > 0 {
            notices.push(format!("{keyframes} keyframe(s) not mapped (ignored)"));
        }
        // rapier3d-mjcf applies them through physics hooks (`contact_hooks`), which neither
        // the joint set nor the scene runner installs
        let contact = &model.contact;
        if !contact.pairs.is_empty() {
            notices.push(format!(
                "{} <contact><pair>(s) not applied (their friction; the geoms collide as \
                 any others)",
                contact.pairs.len()
            ));
        }
    }

    /// The MJCF joint named `name`, if any.
    fn mjcf_joint(&self, name: Option<&str>) -> Option<&MjcfJoint> {
        let (b, i) = self.model.joint_by_name(name?)?;
        Some(&self.model.bodies[b].body.joints[i])
    }

    /// The joint `uj`'s value at insertion \[rad or m\], `ref` included (its
    /// [`UrdfOptions::initial_positions`] entry, else its `ref`), and how far that is from
    /// the loaded pose (`qpos0`, where it reads `ref`).
    fn initial_position(&self, uj: &RapierMjcfJoint, src: Option<&MjcfJoint>) -> (f64, f64) {
        let ref_ = src.map_or(0.0, |j| j.ref_);
        let given = uj
            .name
            .as_ref()
            .and_then(|n| self.options.initial_positions.get(n));
        given.map_or((ref_, 0.0), |q| (*q, q - ref_))
    }

    /// The links moved from the model's `qpos0` to the joints' initial positions
    /// ([`move_to_initial_positions`]).
    fn move_to_initial_positions(&self, links: &mut [RobotLink], index: &[Option<usize>]) {
        let link = |b: usize| index.get(b).copied().flatten();
        let mut edges = Vec::new();
        let mut motions = Vec::new();
        for uj in &self.robot.joints {
            let (Some(l1), Some(l2)) = (link(uj.link1), link(uj.link2)) else {
                continue;
            };
            edges.push((l1, l2));
            let src = self.mjcf_joint(uj.name.as_deref());
            let (_, by) = self.initial_position(uj, src);
            if by != 0.0 {
                motions.push(InitialMotion {
                    link1: l1,
                    link2: l2,
                    frame1: loaded::joint(&uj.joint).local_frame1,
                    slide: src.is_some_and(|j| j.type_ == MjcfJointType::Slide),
                    by,
                });
            }
        }
        move_to_initial_positions(links, &edges, &motions);
    }

    /// Every joint between described bodies of which one at least is dynamic, as KJOINT2
    /// joints named after the MJCF joint (unnamed ones after their body and type; a name
    /// taken twice gets the joint's index).
    fn joints(
        &self,
        links: &[RobotLink],
        index: &[Option<usize>],
        loads: &Loads,
        notices: &mut Vec<String>,
    ) -> Result<Vec<RobotJoint>, UrdfError> {
        // the MJCF joint of each rapier joint, by name (for its type and attributes)
        let mut by_name = HashMap::new();
        for (_, e) in self.model.bodies_iter() {
            for j in &e.body.joints {
                if let Some(n) = &j.name {
                    by_name.insert(n.as_str(), j);
                }
            }
        }
        let mut taken = HashSet::new();
        let actuators = Actuators::of(self.model, keyframe_ctrl(self.model, self.options));
        let mut joints = Vec::with_capacity(self.robot.joints.len());
        for (k, uj) in self.robot.joints.iter().enumerate() {
            let (Some(l1), Some(l2)) = (index[uj.link1], index[uj.link2]) else {
                continue;
            };
            let parent = spacer_of(&self.body_name(uj.link2));
            let el = joint_element(uj.name.as_deref(), Some(&parent), k);
            let dynamic = |l: usize| links.get(l).is_some_and(|l| l.body.is_dynamic());
            if !dynamic(l1) && !dynamic(l2) {
                notices.push(format!("{el}: both bodies are fixed: no joint created"));
                continue;
            }
            let joint = loaded::joint(&uj.joint);
            let jt = joint_type(&joint);
            let src = uj.name.as_deref().and_then(|n| by_name.get(n).copied());
            let mut name = uj
                .name
                .clone()
                .unwrap_or_else(|| format!("{parent}_{}", jt.name().to_lowercase()));
            if taken.contains(&name) {
                name = format!("{name}_{k}");
            }
            let (lf1, lf2) = (joint.local_frame1, joint.local_frame2);
            let (q0, by) = self.initial_position(uj, src);
            let pose1 = *links[l1].body.position();
            let pose2 = *links[l2].body.position();
            let frame = (pose1.rotation * lf1.rotation).normalize();
            let at = JointAt {
                uj,
                k,
                src,
                joint: &joint,
                pose2: &pose2,
                el: &el,
                q0,
            };
            let (mut prop, rule_kf) = self.property(jt, &at, loads, notices);
            let ov = self.options.joints.get(&name);
            if let Some(ov) = ov {
                prop = apply_override(&self.context, &name, prop, ov)?;
            }
            let by_rule = friction_by_rule(&mut prop, rule_kf, ov);
            let slide = jt == JointType::Translational;
            let lf2 = at_zero_offset(&lf2, if slide { by } else { 0.0 });
            // a body and its parent across a joint do not touch (MuJoCo's parent filter), by
            // the robot's groups without `self_collisions`, by the joint's contacts where
            // they collide: with it, and against the environment (a first link on its
            // mount welded to the world; MuJoCo exempts the world body from its filter, the
            // loader does not)
            let parent_filter = self.options.self_collisions
                || self.is_environment(uj.link1)
                || self.is_environment(uj.link2);
            let mut builder = kjoint_builder(prop, &name, (&lf1, &lf2), frame, parent_filter);
            builder.0.friction_by_rule = by_rule;
            let builder = with_override_connector(builder, ov);
            let mut builder = with_break(&self.context, &name, builder, ov)?;
            // the actuator of a hinge or slide as its motor ("Actuators", `actuators.rs`)
            if let Some(mjcf_name) = uj.name.as_deref().filter(|n| actuators.drives(n)) {
                let dof = motor_dof(jt);
                let motor = actuators.motor(self.model, mjcf_name, q0, notices);
                match (dof, motor) {
                    (Some(dof), Ok(Some(m))) => builder = builder.motor(dof, m),
                    (Some(_), Ok(None)) => {}
                    (Some(_), Err(expected)) => {
                        return Err(self.context.field(&el, "actuator", mjcf_name, expected))
                    }
                    (None, _) => notices.push(format!(
                        "{el}: its actuator not mapped: a motor drives a hinge or a slide"
                    )),
                }
            }
            taken.insert(name.clone());
            let one_axis = axis_dof(jt).is_some();
            joints.push(RobotJoint {
                names: vec![name],
                link1: l1,
                link2: l2,
                kind: RobotJointKind::Kjoint(Box::new(builder.build())),
                initial_position: if one_axis { q0 } else { 0.0 },
            });
        }
        Ok(joints)
    }

    /// The KJOINT2 property of the joint `at` of type `jt` (module docs, "Mapping"): the
    /// options' `Kn` and `Cr`; on a hinge or slide the stops of its range, its spring,
    /// damping and friction; on a ball the damping. With the friction spring stiffness of
    /// the load beyond its child body by the rule (0 without an axis DOF), which
    /// [`friction_by_rule`] gives the DOF once the override is applied.
    fn property(
        &self,
        jt: JointType,
        at: &JointAt,
        loads: &Loads,
        notices: &mut Vec<String>,
    ) -> (KjointProperty, f64) {
        let JointAt {
            uj,
            k,
            src,
            joint,
            pose2,
            el,
            q0,
        } = *at;
        let child = uj.link2;
        // the spring and damper: a `springdamper`'s (MuJoCo's compiler sets both from it and
        // the joint's inertia, in place of `stiffness` and `damping`:
        // `K = I/(timeconst·dampratio)²`, `C = 2·I/timeconst`), else the joint's own
        let derived = uj.springdamper.map(|(timeconst, dampratio)| {
            let (t, z) = (timeconst as f64, dampratio as f64);
            loads
                .springdamper
                .get(k)
                .copied()
                .flatten()
                .map(|i| (i / (t * z * t * z), 2.0 * i / t))
        });
        let (spring_k, damping) = match derived {
            Some(Some(kc)) => kc,
            Some(None) => (0.0, 0.0),
            None => (
                uj.spring_stiffness_per_dof as f64,
                uj.damping_per_dof as f64,
            ),
        };
        let mut prop = KjointProperty::new(jt)
            .with_kn(self.options.kn)
            .with_critical_damping(self.options.critical_damping);
        let mut rule_kf = 0.0;
        if let Some(dof) = axis_dof(jt) {
            let mut law = DofLaw::default();
            let ax = if dof.is_rotation() {
                JointAxis::AngX
            } else {
                JointAxis::LinX
            };
            if joint.limit_axes.contains(JointAxesMask::from(ax)) {
                if let Some(l) = joint.limits(ax) {
                    // the MJCF values (f64) where the joint is named, rapier's (f32) otherwise
                    // from the joint's value at insertion: `ref` or its initial position
                    let (lo, hi) = match src.and_then(|j| j.range) {
                        Some(r) => (r[0] - q0, r[1] - q0),
                        None => (l.min as f64, l.max as f64),
                    };
                    let ((lo, hi), note) = stops_from_limits(lo, hi);
                    law = law.with_stops(lo, hi);
                    if let Some(n) = note {
                        notices.push(format!("{el}: {}", n.replace("limit", "range")));
                    }
                }
            }
            law.stiffness = spring_k;
            law.viscosity = damping;
            // the spring rests at `springref` (MuJoCo's `qpos_spring`), `c` from the pose at
            // insertion (`q0`): `F = K·(q − c)`, the curve `f(δ) = δ − c` (extrapolated
            // linearly), the joint preloaded by `−K·c` at the start (its notice says so)
            let rest = match src {
                Some(j) => j.springref - q0,
                None => uj.spring_ref as f64,
            };
            if spring_k > 0.0 && rest != 0.0 {
                law.stiffness_curve = Curve::new([(-1.0, -1.0 - rest), (1.0, 1.0 - rest)]).ok();
            }
            if uj.frictionloss_per_dof > 0.0 {
                law.friction = uj.frictionloss_per_dof as f64;
            }
            let (anchor, axis) = anchor_and_axis(joint, pose2);
            let (m_eff, scale) =
                load_beyond(&loads.masses, &loads.children, child, dof, &anchor, &axis);
            rule_kf = friction_stiffness(m_eff, scale, self.options.resolved_substep());
            prop = prop.with_dof(dof, law);
        } else if jt == JointType::Spherical {
            for dof in [Dof::Rx, Dof::Ry, Dof::Rz] {
                let law = DofLaw::default().with_viscosity(damping);
                prop = prop.with_dof(dof, law);
            }
            if let Some(j) = src {
                ball_not_mapped(j, el, notices);
            }
            if spring_k > 0.0 && derived.is_some() {
                notices.push(format!(
                    "{el}: the stiffness {} N·m/rad its springdamper gives a ball joint not \
                     mapped (its damping is)",
                    fmt_num(spring_k)
                ));
            }
        }
        if derived == Some(None) {
            // (MuJoCo sets the joint's stiffness and damping from it, replacing the joint's
            // own: a user took a class's damping for kept, an MJCF user's trial, 2026-12-06)
            notices.push(format!(
                "{el}: springdamper not mapped: the model's joint-space inertia is singular \
                 (a degree of freedom that moves no mass), so the joint has neither a spring \
                 nor damping (MuJoCo sets both from it, in place of its `stiffness` and \
                 `damping`); give `stiffness` and `damping` instead"
            ));
        }
        (prop, rule_kf)
    }
}

/// A `rapier3d-mjcf` joint being described.
#[derive(Clone, Copy)]
struct JointAt<'a> {
    /// The joint.
    uj: &'a RapierMjcfJoint,
    /// Its index among `rapier3d-mjcf`'s joints.
    k: usize,
    /// Its MJCF joint, when it is named.
    src: Option<&'a MjcfJoint>,
    /// Its rapier joint, in the world's rapier.
    joint: &'a GenericJoint,
    /// The pose of its child body.
    pose2: &'a Pose,
    /// Its element in notices and errors.
    el: &'a str,
    /// Its value at insertion \[rad or m\] (`ref`, or its initial position).
    q0: f64,
}

/// The world anchor of `joint` (its frame on the child body at `pose2`) and its axis (the
/// frame's x: a hinge's or a slide's).
fn anchor_and_axis(joint: &GenericJoint, pose2: &Pose) -> (Vector3<f64>, Vector3<f64>) {
    let lf2 = joint.local_frame2;
    let anchor = from_vec3(pose2 * lf2.translation);
    (
        anchor,
        from_quat(pose2.rotation * lf2.rotation) * Vector3::x(),
    )
}

/// The KJOINT2 type of a `rapier3d-mjcf` joint, from its locked axes (hinge, slide, ball;
/// fixed otherwise).
fn joint_type(joint: &GenericJoint) -> JointType {
    let locked = joint.locked_axes;
    if locked == JointAxesMask::LOCKED_REVOLUTE_AXES {
        JointType::Revolute
    } else if locked == JointAxesMask::LOCKED_PRISMATIC_AXES {
        JointType::Translational
    } else if locked == JointAxesMask::LOCKED_SPHERICAL_AXES {
        JointType::Spherical
    } else {
        JointType::Fixed
    }
}

/// A notice for what a ball joint `j` gives that KJOINT2 does not map (stiffness, friction,
/// a cone range).
fn ball_not_mapped(j: &MjcfJoint, el: &str, notices: &mut Vec<String>) {
    let mut lost = Vec::new();
    if j.stiffness > 0.0 {
        lost.push("stiffness");
    }
    if j.frictionloss > 0.0 {
        lost.push("frictionloss");
    }
    if j.range.is_some() {
        lost.push("range (a cone)");
    }
    if !lost.is_empty() {
        notices.push(format!(
            "{el}: {} of a ball joint not mapped",
            lost.join(", ")
        ));
    }
}

/// The MJCF body a (spacer) body's name belongs to: the name before `__intermediate_`.
fn spacer_of(name: &str) -> String {
    name.split("__intermediate_")
        .next()
        .unwrap_or(name)
        .to_string()
}
