//! MuJoCo (MJCF) robots with KJOINT2 joints.
//!
//! [`load_mjcf`] / [`load_mjcf_str`] read an MJCF model with `rapier3d-mjcf` (parsed by
//! `mjcf-rs`, which resolves `<default>` classes, `<include>`, `<compiler angle>` and
//! `autolimits`): bodies with their MJCF (or geom-derived) inertia, geoms → colliders, and
//! each joint with its frames. Instead of rapier's joints, every MJCF joint becomes one
//! KJOINT2 joint in a [`KjointSet`], on the same footing as URDF robots
//! ([`crate::io::urdf`]): the same options ([`UrdfOptions`]), the same robot record
//! ([`UrdfRobot`]: bodies and joints by name, notices) and the same typed errors
//! ([`UrdfError`], naming the file, the element and the field). Nothing is stepped.
//!
//! # Mapping
//!
//! | MJCF `<joint type>` | KJOINT2 type | free DOFs |
//! |---|---|---|
//! | `hinge` | [`JointType::Revolute`] (2) | rx |
//! | `slide` | [`JointType::Translational`] (6) | dx |
//! | `ball` | [`JointType::Spherical`] (1) | rx, ry, rz |
//! | `free` | none: a floating body | all |
//! | (no joint) | [`JointType::Fixed`] (8) to the parent, or a fixed body on the world | – |
//!
//! * **Frames.** The joint frame sits at the joint's `pos`, its x along `axis` (hinge,
//!   slide), as `rapier3d-mjcf` builds them; the loaded pose (MuJoCo's `qpos0`, joint
//!   coordinate `ref`) is the unloaded one, `q = 0`.
//! * **Several joints in one body** are, as in MuJoCo, joints in series: `rapier3d-mjcf`
//!   puts a spacer body between each two of them (at the body's pose), and so does this
//!   loader, one KJOINT2 joint each. The spacers have no mass in MJCF; they get
//!   [`UrdfOptions::min_link_mass`] with the inertia of a ball of radius
//!   [`crate::io::urdf::BALL_RADIUS`] (with a notice naming the body), which the automatic
//!   stiffness needs. They are not merged into universal or spherical joints: the series is
//!   exact for any axes and positions, and a merged joint is not.
//! * **Stops.** `range` of a limited hinge \[rad, read in degrees unless `<compiler
//!   angle="radian">`\] or slide \[m\] (`limited="true"`, or `auto` with `autolimits`), minus
//!   `ref`, becomes `SA-`/`SA+` (`SD-`/`SD+`) exactly as URDF limits do
//!   ([`crate::io::urdf`]): a bound at 0 is `∓1e-9`, `0 0` is none, a range that excludes the
//!   initial position is widened (with a notice). A ball's `range` (a cone) is not mapped
//!   (notice).
//! * **Spring.** `stiffness` → the linear stiffness `K` of the free DOF. KJOINT2 springs
//!   rest at the initial pose: a `springref` other than `ref` is not mapped (notice; the
//!   spring rests at `ref`). `springdamper` is not mapped (notice).
//! * **Damping.** `damping` → the viscosity `C` (all three rotations of a ball).
//! * **Friction.** `frictionloss` of a hinge or slide → the friction `FM`/`FF`, with the
//!   friction spring stiffness of the URDF loader ([`crate::io::urdf::friction_stiffness`],
//!   from the load beyond the joint); on a ball it is not mapped (notice).
//! * **Stiffness, bodies, collisions.** As for URDF: `Kn` = [`UrdfOptions::kn`] (0 =
//!   automatic), `Cr` = [`UrdfOptions::critical_damping`], per-joint `options.joints` by MJCF
//!   joint name (KJOINT2 fields only: `engine = "rapier"` is refused for MJCF). Bodies never
//!   sleep. With [`UrdfOptions::fixed_base`] (the default, as for URDF) a body with a `free`
//!   joint is fixed where it is; `fixed_base = false` lets it float as in MuJoCo. Bodies
//!   without a joint whose parent is the world are fixed. Geoms that collide (`contype` or
//!   `conaffinity` ≠ 0) become colliders of density 0 (the MJCF inertia is the mass); mesh
//!   geoms their convex hull ([`UrdfOptions::collision_meshes`]); `plane` geoms (floors) are
//!   skipped. Unless [`UrdfOptions::self_collisions`], the robot's colliders do not collide
//!   with each other (`contype`/`conaffinity` are then not read); geoms of the `worldbody`
//!   are colliders of a fixed body `world`.
//! * **Not mapped** (one notice each, with what the model holds): `armature`, actuators,
//!   tendons, equality constraints, sensors, keyframes. `package_dirs` and `visual_meshes`
//!   of the options are URDF-only.
//!
//! Every error names the file, the element and the field ([`UrdfError`]): the parser's
//! messages name the tag and attribute; NaN, infinite, negative coefficients and reversed
//! ranges are refused naming the joint (and its body) and the attribute.

use crate::dynamics::{from_quat, from_vec3, KjointSet};
use crate::io::loaded;
use crate::io::urdf::{
    apply_override, axis_dof, friction_stiffness, load_beyond, read_robot_file, stops_from_limits,
    Cx, JointEngine, LinkMass, UrdfError, UrdfOptions, UrdfRobot, BALL_RADIUS, WORLD_LINK,
};
use crate::law::{Dof, DofLaw, JointType, Kjoint2Property};
use crate::rapier::dynamics::{
    JointAxesMask, JointAxis, MassProperties, RigidBody, RigidBodyBuilder, RigidBodyHandle,
};
use crate::rapier::geometry::{ColliderHandle, Group, InteractionGroups, InteractionTestMode};
use crate::rapier::math::{Real, Vector};
use crate::rapier::pipeline::PhysicsWorld;
use nalgebra::{Matrix3, Vector3};
use rapier3d_mjcf::mjcf_rs::body::JointType as MjcfJointType;
use rapier3d_mjcf::mjcf_rs::model::Model;
use rapier3d_mjcf::{MjcfLoaderOptions, MjcfRobot};
use std::path::Path;

/// Loads the MJCF file `path` into `world` and `joints` (see the module docs);
/// `<include>` and mesh files are relative to its directory.
pub fn load_mjcf(
    path: impl AsRef<Path>,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    let (text, file, base) = read_robot_file(path.as_ref())?;
    load(&text, &file, base, world, joints, options)
}

/// Loads MJCF text; `file` names it in errors (e.g. `<string>`); `<include>` and mesh files
/// are relative to `base_dir`.
pub fn load_mjcf_str(
    text: &str,
    file: &str,
    base_dir: impl AsRef<Path>,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    load(text, file, base_dir.as_ref(), world, joints, options)
}

/// The element of an MJCF joint in errors and notices: ``joint `name` (body `b`)``.
fn joint_element(name: Option<&str>, body: Option<&str>, index: usize) -> String {
    let j = match name {
        Some(n) => format!("joint `{n}`"),
        None => format!("joint #{index} (unnamed)"),
    };
    match body {
        Some(b) => format!("{j} (body `{b}`)"),
        None => j,
    }
}

/// What rapier3d-mjcf would turn into NaN or nonsense: refused, naming joint and attribute.
fn check_model(cx: &Cx, model: &Model) -> Result<(), UrdfError> {
    for (_, entry) in model.bodies_iter() {
        let b = &entry.body;
        for (k, j) in b.joints.iter().enumerate() {
            let el = joint_element(j.name.as_deref(), b.name.as_deref(), k);
            cx.finite3(&el, "pos", &j.pos)?;
            cx.finite3(&el, "axis", &j.axis)?;
            let moving = matches!(j.type_, MjcfJointType::Hinge | MjcfJointType::Slide);
            if moving && j.axis.iter().map(|v| v * v).sum::<f64>() < 1e-12 {
                return Err(cx.field(&el, "axis", format!("{:?}", j.axis), "a non-zero axis"));
            }
            for (f, v) in [
                ("stiffness", j.stiffness),
                ("damping", j.damping),
                ("frictionloss", j.frictionloss),
                ("armature", j.armature),
            ] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(cx.field(&el, f, v, "a finite value >= 0"));
                }
            }
            cx.finite(&el, "springref", j.springref)?;
            cx.finite(&el, "ref", j.ref_)?;
            if let Some([lo, hi]) = j.range {
                cx.finite(&el, "range", lo)?;
                cx.finite(&el, "range", hi)?;
                if lo > hi {
                    return Err(cx.field(&el, "range", format!("{lo} {hi}"), "lower <= upper"));
                }
            }
        }
    }
    Ok(())
}

fn load(
    text: &str,
    file: &str,
    base: &Path,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    let cx = Cx { file };
    let model = Model::from_str(text, base).map_err(|e| {
        // mjcf-rs names neither the element nor the attribute of a number it cannot read
        // (`invalid attribute `_` on <_>`): find them
        bad_number(&cx, text).unwrap_or_else(|| UrdfError::Mjcf {
            file: file.to_string(),
            message: e.to_string(),
        })
    })?;
    cx.check_options(options)?;
    check_model(&cx, &model)?;
    let names: std::collections::HashSet<&str> = model
        .bodies_iter()
        .flat_map(|(_, e)| e.body.joints.iter().filter_map(|j| j.name.as_deref()))
        .collect();
    for (name, ov) in &options.joints {
        if !names.contains(name.as_str()) {
            return Err(cx.field(
                "options.joints",
                "name",
                name,
                "the name of a joint of the model",
            ));
        }
        if ov.engine == Some(JointEngine::Rapier) || ov.motor.is_some() {
            return Err(cx.field(
                format!("options.joints.`{name}`"),
                if ov.motor.is_some() {
                    "motor"
                } else {
                    "engine"
                },
                "(set)",
                "KJOINT2 fields only: rapier joints and motors are for URDF robots",
            ));
        }
    }
    // rapier3d-mjcf builds f32 objects (rapier3d), converted into the world's rapier in
    // `build` (`loaded`)
    let loader = MjcfLoaderOptions {
        make_roots_fixed: options.fixed_base,
        mesh_converter: Some(options.collision_meshes.converter()),
        rigid_body_blueprint: rapier3d::dynamics::RigidBodyBuilder::dynamic().can_sleep(false),
        collider_blueprint: rapier3d::geometry::ColliderBuilder::default().density(0.0),
        disable_joint_motors: true,
        ..Default::default()
    };
    let robot = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        MjcfRobot::from_model(&model, loader, base)
    }))
    .map_err(|_| UrdfError::Mjcf {
        file: file.to_string(),
        message: "rapier3d-mjcf could not build the model".into(),
    })?;
    build(&cx, &model, &robot, world, joints, options)
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

fn build(
    cx: &Cx,
    model: &Model,
    robot: &MjcfRobot,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    let mut out = UrdfRobot {
        name: robot
            .name
            .clone()
            .or(model.name.clone())
            .unwrap_or_default(),
        ..Default::default()
    };
    let group = Group::GROUP_32;
    let groups = InteractionGroups::new(group, Group::ALL ^ group, InteractionTestMode::And);
    let body_name = |i: usize| -> String {
        let b = &robot.bodies[i];
        match (&b.name, i) {
            (_, 0) => WORLD_LINK.to_string(),
            (Some(n), _) => n.clone(),
            (None, _) => format!("body{}", b.mjcf_body_id),
        }
    };
    // bodies: index 0 (the world) becomes a fixed body when something hangs on it
    let needs_world = !robot.bodies[0].colliders.is_empty()
        || robot.joints.iter().any(|j| j.link1 == 0 || j.link2 == 0);
    let mut handles: Vec<Option<RigidBodyHandle>> = vec![None; robot.bodies.len()];
    let mut spacers: std::collections::BTreeMap<String, usize> = Default::default();
    for (i, b) in robot.bodies.iter().enumerate() {
        let mut body = if i == 0 {
            if !needs_world {
                continue;
            }
            RigidBodyBuilder::fixed().build()
        } else {
            loaded::body(&b.body)
        };
        if body.is_dynamic() && b.mass <= 0.0 {
            let mm = options.min_link_mass as Real;
            let inertia = 0.4 * mm * (BALL_RADIUS * BALL_RADIUS) as Real;
            body.set_additional_mass_properties(
                MassProperties::new(Vector::ZERO, mm, Vector::splat(inertia)),
                false,
            );
            if b.is_intermediate {
                let name = body_name(i);
                let base = name.split("__intermediate_").next().unwrap_or(&name);
                *spacers.entry(base.to_string()).or_default() += 1;
            } else {
                out.notices.push(format!(
                    "body `{}`: no mass in the MJCF: given {} kg",
                    body_name(i),
                    options.min_link_mass
                ));
            }
        }
        let h = world.bodies.insert(body);
        let mut cols: Vec<ColliderHandle> = Vec::with_capacity(b.colliders.len());
        for c in &b.colliders {
            let mut c = loaded::collider(c).map_err(|e| UrdfError::Mjcf {
                file: cx.file.to_string(),
                message: format!("body `{}`: {e}", body_name(i)),
            })?;
            if !options.self_collisions {
                c.set_collision_groups(groups);
            }
            cols.push(world.colliders.insert_with_parent(c, h, &mut world.bodies));
        }
        if let Some(rb) = world.bodies.get_mut(h) {
            rb.recompute_mass_properties_from_colliders(&world.colliders);
        }
        handles[i] = Some(h);
        if !b.is_intermediate {
            out.links.insert(body_name(i), h);
            out.colliders.insert(body_name(i), cols);
        }
    }
    for (body, n) in &spacers {
        out.notices.push(format!(
            "body `{body}`: {} joints in series through {n} spacer body(ies) of {} kg each (no \
             mass in MJCF)",
            n + 1,
            options.min_link_mass
        ));
    }
    let free = model
        .bodies_iter()
        .filter(|(_, e)| e.body.joints.iter().any(|j| j.type_ == MjcfJointType::Free))
        .count();
    if free > 0 {
        out.notices.push(format!(
            "{free} body(ies) with a free joint: {} (no KJOINT2 joint)",
            if options.fixed_base {
                "fixed where they are (fixed_base = true)"
            } else {
                "floating"
            }
        ));
    }
    // what is not mapped
    let armature: Vec<&str> = model
        .bodies_iter()
        .flat_map(|(_, e)| e.body.joints.iter())
        .filter(|j| j.armature > 0.0)
        .map(|j| j.name.as_deref().unwrap_or("(unnamed)"))
        .collect();
    if !armature.is_empty() {
        out.notices.push(format!(
            "armature of {} joint(s) not mapped (no rotor inertia in KJOINT2): {}",
            armature.len(),
            armature.join(", ")
        ));
    }
    for (what, n) in [
        ("actuator", model.actuators.len()),
        ("tendon", model.tendons.len()),
        ("equality constraint", model.equality.len()),
        ("sensor", model.sensors.len()),
        ("keyframe", model.keyframes.len()),
    ] {
        if n > 0 {
            out.notices
                .push(format!("{n} {what}(s) not mapped (ignored)"));
        }
    }

    // the bodies beyond each joint (their load makes the friction stiffness)
    let masses: Vec<LinkMass> = handles
        .iter()
        .map(|h| match h.and_then(|h| world.bodies.get(h)) {
            Some(rb) if rb.is_dynamic() => link_mass(rb),
            _ => LinkMass {
                m: 0.0,
                c: Vector3::zeros(),
                inertia: Matrix3::zeros(),
            },
        })
        .collect();
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); robot.bodies.len()];
    for j in &robot.joints {
        children[j.link1].push(j.link2);
    }

    // the MJCF joint of each rapier joint, by name (for its type and attributes)
    let mut by_name = std::collections::HashMap::new();
    for (_, e) in model.bodies_iter() {
        for j in &e.body.joints {
            if let Some(n) = &j.name {
                by_name.insert(n.as_str(), j);
            }
        }
    }
    for (k, uj) in robot.joints.iter().enumerate() {
        let (Some(b1), Some(b2)) = (handles[uj.link1], handles[uj.link2]) else {
            continue;
        };
        let parent = body_name(uj.link2);
        let parent = parent.split("__intermediate_").next().unwrap_or(&parent);
        let el = joint_element(uj.name.as_deref(), Some(parent), k);
        let dyn1 = world.bodies.get(b1).is_some_and(|b| b.is_dynamic());
        let dyn2 = world.bodies.get(b2).is_some_and(|b| b.is_dynamic());
        if !dyn1 && !dyn2 {
            out.notices
                .push(format!("{el}: both bodies are fixed: no joint created"));
            continue;
        }
        let joint = loaded::joint(&uj.joint);
        let locked = joint.locked_axes;
        let jt = if locked == JointAxesMask::LOCKED_REVOLUTE_AXES {
            JointType::Revolute
        } else if locked == JointAxesMask::LOCKED_PRISMATIC_AXES {
            JointType::Translational
        } else if locked == JointAxesMask::LOCKED_SPHERICAL_AXES {
            JointType::Spherical
        } else {
            JointType::Fixed
        };
        let src = uj.name.as_deref().and_then(|n| by_name.get(n).copied());
        let mut name = uj
            .name
            .clone()
            .unwrap_or_else(|| format!("{parent}_{}", jt.name().to_lowercase()));
        if out.joints.contains_key(&name) {
            name = format!("{name}_{k}");
        }
        let lf1 = joint.local_frame1;
        let lf2 = joint.local_frame2;
        let pose1 = *world.bodies[b1].position();
        let pose2 = *world.bodies[b2].position();
        let frame = (pose1.rotation * lf1.rotation).normalize();
        let mut prop = Kjoint2Property::new(jt)
            .with_kn(options.kn)
            .with_critical_damping(options.critical_damping);
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
                    let (lo, hi) = match src.and_then(|j| j.range.map(|r| (r, j.ref_))) {
                        Some((r, rf)) => (r[0] - rf, r[1] - rf),
                        None => (l.min as f64, l.max as f64),
                    };
                    let ((lo, hi), note) = stops_from_limits(lo, hi);
                    law = law.with_stops(lo, hi);
                    if let Some(n) = note {
                        out.notices
                            .push(format!("{el}: {}", n.replace("limit", "range")));
                    }
                }
            }
            law.stiffness = uj.spring_stiffness_per_dof as f64;
            law.viscosity = uj.damping_per_dof as f64;
            if uj.frictionloss_per_dof > 0.0 {
                law.friction = uj.frictionloss_per_dof as f64;
                let anchor = from_vec3(pose2 * lf2.translation);
                let axis = from_quat(pose2.rotation * lf2.rotation) * Vector3::x();
                let (m_eff, scale) = load_beyond(&masses, &children, uj.link2, dof, &anchor, &axis);
                law.friction_stiffness =
                    friction_stiffness(m_eff, scale, options.resolved_substep());
            }
            prop = prop.with_dof(dof, law);
        } else if jt == JointType::Spherical {
            for dof in [Dof::Rx, Dof::Ry, Dof::Rz] {
                prop = prop.with_dof(
                    dof,
                    DofLaw::default().with_viscosity(uj.damping_per_dof as f64),
                );
            }
            if let Some(j) = src {
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
                    out.notices.push(format!(
                        "{el}: {} of a ball joint not mapped",
                        lost.join(", ")
                    ));
                }
            }
        }
        if uj.spring_stiffness_per_dof > 0.0 && uj.spring_ref != 0.0 {
            out.notices.push(format!(
                "{el}: springref − ref = {} not mapped: the spring rests at the initial pose",
                uj.spring_ref
            ));
        }
        if uj.springdamper.is_some() {
            out.notices
                .push(format!("{el}: springdamper not mapped (ignored)"));
        }
        if let Some(ov) = options.joints.get(&name) {
            prop = apply_override(cx, &name, prop, ov)?;
        }
        let h = cx.insert_joint(joints, world, prop, &name, (b1, b2), (&lf1, &lf2), frame)?;
        out.joints.insert(name, h);
    }
    Ok(out)
}

/// Attributes whose values are numbers (one or several) in MJCF.
const NUMERIC_ATTRIBUTES: &[&str] = &[
    "pos",
    "axis",
    "range",
    "damping",
    "stiffness",
    "frictionloss",
    "armature",
    "springref",
    "ref",
    "margin",
    "mass",
    "diaginertia",
    "fullinertia",
    "size",
    "fromto",
    "quat",
    "euler",
    "axisangle",
    "xyaxes",
    "zaxis",
    "gear",
    "density",
    "friction",
    "rgba",
    "gravity",
    "timestep",
    "ctrlrange",
    "forcerange",
    "kp",
    "kv",
    "solref",
    "solimp",
    "springdamper",
    "scale",
    "polycoef",
    "coef",
    "gravcomp",
];

/// The first numeric attribute of `text` that is not a list of numbers, as an error naming
/// its element (tag, `name`, line) and the attribute.
fn bad_number(cx: &Cx, text: &str) -> Option<UrdfError> {
    let doc = roxmltree::Document::parse(text).ok()?;
    for node in doc.descendants().filter(|n| n.is_element()) {
        for a in node.attributes() {
            if !NUMERIC_ATTRIBUTES.contains(&a.name()) {
                continue;
            }
            if a.value()
                .split_whitespace()
                .all(|t| t.parse::<f64>().is_ok())
            {
                continue;
            }
            let tag = node.tag_name().name();
            let line = doc.text_pos_at(node.range().start).row;
            let el = match node.attribute("name") {
                Some(n) => format!("<{tag} name=\"{n}\"> (line {line})"),
                None => format!("<{tag}> (line {line})"),
            };
            return Some(cx.field(el, a.name(), a.value(), "numbers"));
        }
    }
    None
}
