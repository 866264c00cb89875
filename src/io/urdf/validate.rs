//! Validation of the options and of a parsed URDF robot: everything `rapier3d-urdf` would
//! panic on or turn into NaN is refused, naming the link or joint and the field; so are
//! links that do not form a tree ([`UrdfError::Loop`]).

use super::error::{in_range, ErrorContext, UrdfError, RANGE};
use super::options::UrdfOptions;
use crate::figure::fmt_num;
use rapier3d_urdf::urdf_rs;
use std::collections::HashSet;

/// The options' global values (the per-joint overrides are checked with their joints).
pub(crate) fn check_options(context: &ErrorContext, o: &UrdfOptions) -> Result<(), UrdfError> {
    let e = "options";
    if !(o.kn.is_finite() && o.kn >= 0.0) {
        return Err(context.field(e, "kn", o.kn, "a finite value >= 0 (0 = automatic)"));
    }
    if !(0.0..=1.0).contains(&o.critical_damping) {
        return Err(context.field(
            e,
            "critical_damping",
            o.critical_damping,
            "a value in [0, 1]",
        ));
    }
    if !(o.substep.is_finite() && o.substep >= 0.0) {
        return Err(context.field(
            e,
            "substep",
            o.substep,
            "a finite time >= 0 [s] (0 = automatic)",
        ));
    }
    if !(o.min_link_mass.is_finite() && o.min_link_mass > 0.0) {
        return Err(context.field(
            e,
            "min_link_mass",
            o.min_link_mass,
            "a finite mass > 0 [kg]",
        ));
    }
    for (name, q0) in &o.initial_positions {
        if !in_range(*q0) {
            return Err(context.field(
                "options.initial_positions",
                name,
                q0,
                "a finite position within ±1e12 [rad or m]",
            ));
        }
    }
    let (t, q) = (o.base_pose.translation, o.base_pose.rotation);
    let t = [t.x, t.y, t.z].map(|v| v as f64);
    if !t.iter().all(|v| in_range(*v)) {
        return Err(context.field(
            e,
            "base_pose.translation",
            format!("{t:?}"),
            "finite numbers within ±1e12 [m]",
        ));
    }
    let q = [q.x, q.y, q.z, q.w].map(|v| v as f64);
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(norm - 1.0).abs().le(&1e-3) {
        return Err(context.field(
            e,
            "base_pose.rotation",
            format!("{q:?}"),
            "a unit quaternion",
        ));
    }
    Ok(())
}

/// Checks everything rapier3d-urdf would panic on or turn into NaN, and that the links form
/// a tree.
pub(super) fn check_robot(context: &ErrorContext, robot: &urdf_rs::Robot) -> Result<(), UrdfError> {
    // (ROS's parser refuses it too: "No link elements found in urdf file"; it loaded as
    // nothing, and `kjoint run` summed up an empty world)
    if robot.links.is_empty() {
        return Err(context.field(
            format!("robot `{}`", robot.name),
            "link",
            "(none)",
            "at least one <link>",
        ));
    }
    let mut names = HashSet::new();
    for link in &robot.links {
        if !names.insert(link.name.as_str()) {
            let el = format!("link `{}`", link.name);
            return Err(context.field(&el, "name", &link.name, "a unique link name"));
        }
        check_link(context, link)?;
    }
    let mut joint_names = HashSet::new();
    for j in &robot.joints {
        if !joint_names.insert(j.name.as_str()) {
            let el = format!("joint `{}`", j.name);
            return Err(context.field(&el, "name", &j.name, "a unique joint name"));
        }
        check_joint(context, j, &names)?;
    }
    check_tree(context, robot)
}

/// A link's inertial and the origins and sizes of its geometries.
fn check_link(context: &ErrorContext, link: &urdf_rs::Link) -> Result<(), UrdfError> {
    let el = format!("link `{}`", link.name);
    let i = &link.inertial;
    context.finite3(&el, "inertial.origin.xyz", &i.origin.xyz.0)?;
    context.finite3(&el, "inertial.origin.rpy", &i.origin.rpy.0)?;
    let m = context.finite(&el, "inertial.mass", i.mass.value)?;
    if m < 0.0 {
        return Err(context.field(&el, "inertial.mass", m, "a mass >= 0 [kg]"));
    }
    for (f, v) in [
        ("ixx", i.inertia.ixx),
        ("ixy", i.inertia.ixy),
        ("ixz", i.inertia.ixz),
        ("iyy", i.inertia.iyy),
        ("iyz", i.inertia.iyz),
        ("izz", i.inertia.izz),
    ] {
        context.finite(&el, &format!("inertial.inertia.{f}"), v)?;
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
        context.finite3(&el, &format!("{kind}.origin.xyz"), &origin.xyz.0)?;
        context.finite3(&el, &format!("{kind}.origin.rpy"), &origin.rpy.0)?;
        for (f, v) in geometry_sizes(g) {
            // the sign bit, not `v >= 0`: parry asserts it, and panics on a size of -0
            let signed = v.is_sign_positive() || f == "mesh.scale";
            if !(in_range(v) && signed) {
                let expected = if v == 0.0 {
                    "a size >= 0 [m] without a minus sign (parry refuses -0)"
                } else if v.is_finite() && signed {
                    RANGE
                } else {
                    "a finite size >= 0 [m]"
                };
                let field = format!("{kind}.geometry.{f}");
                return Err(context.field(&el, field, fmt_num(v), expected));
            }
        }
    }
    Ok(())
}

/// The sizes of a geometry, by field (`box.size` three times, `mesh.scale` three times or
/// none).
fn geometry_sizes(g: &urdf_rs::Geometry) -> Vec<(&'static str, f64)> {
    match g {
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
    }
}

/// A joint's links (`links`: the names of the robot's links), origin, axis, limits and
/// dynamics.
fn check_joint(
    context: &ErrorContext,
    j: &urdf_rs::Joint,
    links: &HashSet<&str>,
) -> Result<(), UrdfError> {
    let el = format!("joint `{}`", j.name);
    for (f, l) in [
        ("parent.link", &j.parent.link),
        ("child.link", &j.child.link),
    ] {
        if !links.contains(l.as_str()) {
            return Err(context.field(&el, f, l, "the name of a link of the robot"));
        }
    }
    if j.parent.link == j.child.link {
        return Err(context.field(
            &el,
            "child.link",
            &j.child.link,
            "a link other than the parent",
        ));
    }
    context.finite3(&el, "origin.xyz", &j.origin.xyz.0)?;
    context.finite3(&el, "origin.rpy", &j.origin.rpy.0)?;
    context.finite3(&el, "axis.xyz", &j.axis.xyz.0)?;
    let a = j.axis.xyz.0;
    let moving = !matches!(
        j.joint_type,
        urdf_rs::JointType::Fixed | urdf_rs::JointType::Floating | urdf_rs::JointType::Spherical
    );
    if moving && a.iter().map(|v| v * v).sum::<f64>() < 1e-12 {
        return Err(context.field(&el, "axis.xyz", format!("{a:?}"), "a non-zero axis"));
    }
    for (f, v) in [
        ("limit.lower", j.limit.lower),
        ("limit.upper", j.limit.upper),
    ] {
        if v.is_nan() {
            return Err(context.field(&el, f, v, "a number (±inf = no stop)"));
        }
    }
    if j.limit.lower > j.limit.upper {
        return Err(context.field(
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
            if !(in_range(v) && v >= 0.0) {
                return Err(context.field(
                    &el,
                    f,
                    fmt_num(v),
                    "a finite value >= 0 (within ±1e12)",
                ));
            }
        }
    }
    Ok(())
}

/// Every link is the child of at most one joint, and no joints close a loop.
fn check_tree(context: &ErrorContext, robot: &urdf_rs::Robot) -> Result<(), UrdfError> {
    let mut children = HashSet::new();
    for j in &robot.joints {
        if !children.insert(j.child.link.as_str()) {
            return Err(context.field(
                format!("joint `{}`", j.name),
                "child.link",
                &j.child.link,
                "a link that is the child of no other joint (URDF is a tree)",
            ));
        }
    }
    // with one parent per link, a robot without root has a closed loop
    if let Some((joints, links)) = closed_loop(robot) {
        return Err(UrdfError::Loop {
            file: context.file.to_string(),
            joints,
            links,
        });
    }
    Ok(())
}

/// The links that are the child of no joint.
pub(super) fn root_links(robot: &urdf_rs::Robot) -> std::collections::HashSet<&str> {
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
