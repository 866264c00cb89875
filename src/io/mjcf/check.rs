//! Validation of a parsed MJCF model: what `rapier3d-mjcf` would turn into NaN, nonsense or a
//! panic is refused naming the joint, body or geom and the attribute; the overrides must
//! name joints of the model and hold KJOINT2 fields only; and a number mjcf-rs could not read
//! is found again to name its element and attribute.

use crate::figure::fmt_num;
use crate::io::urdf::{ErrorContext, JointEngine, UrdfError, UrdfOptions};
use rapier3d_mjcf::mjcf_rs::body::{Body, GeomType, InertiaSpec, JointType as MjcfJointType};
use rapier3d_mjcf::mjcf_rs::model::Model;
use std::path::Path;

/// The element of an MJCF joint in errors and notices: ``joint `name` (body `b`)``.
pub(super) fn joint_element(name: Option<&str>, body: Option<&str>, index: usize) -> String {
    let j = match name {
        Some(n) => format!("joint `{n}`"),
        None => format!("joint #{index} (unnamed)"),
    };
    match body {
        Some(b) => format!("{j} (body `{b}`)"),
        None => j,
    }
}

/// The element of an MJCF body in errors: ``body `name` `` (the world body for index 0).
fn body_element(name: Option<&str>, index: usize) -> String {
    match (name, index) {
        (Some(n), _) => format!("body `{n}`"),
        (None, 0) => "<worldbody>".to_string(),
        (None, i) => format!("body #{i} (unnamed)"),
    }
}

/// What rapier3d-mjcf would turn into NaN or nonsense: refused, naming joint and attribute.
pub(super) fn check_model(context: &ErrorContext, model: &Model) -> Result<(), UrdfError> {
    check_unique_names(context, model)?;
    for (i, entry) in model.bodies.iter().enumerate() {
        check_body(context, &entry.body, i)?;
    }
    for (_, entry) in model.bodies_iter() {
        let b = &entry.body;
        for (k, j) in b.joints.iter().enumerate() {
            let el = joint_element(j.name.as_deref(), b.name.as_deref(), k);
            context.finite3(&el, "pos", &j.pos)?;
            context.finite3(&el, "axis", &j.axis)?;
            // MuJoCo refuses a free joint below another body ("free joint can only be used
            // on top level"); it would float here, off its parent without a word
            if j.type_ == MjcfJointType::Free && entry.parent.is_some_and(|p| p != 0) {
                return Err(context.field(
                    &el,
                    "type",
                    "free",
                    "a free joint in a body of <worldbody> itself (MuJoCo refuses it below \
                     another body)",
                ));
            }
            let moving = matches!(j.type_, MjcfJointType::Hinge | MjcfJointType::Slide);
            if moving && j.axis.iter().map(|v| v * v).sum::<f64>() < 1e-12 {
                return Err(context.field(&el, "axis", format!("{:?}", j.axis), "a non-zero axis"));
            }
            for (f, v) in [
                ("stiffness", j.stiffness),
                ("damping", j.damping),
                ("frictionloss", j.frictionloss),
                ("armature", j.armature),
            ] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(context.field(&el, f, v, "a finite value >= 0"));
                }
            }
            context.finite(&el, "springref", j.springref)?;
            context.finite(&el, "ref", j.ref_)?;
            if let Some([lo, hi]) = j.range {
                context.finite(&el, "range", lo)?;
                context.finite(&el, "range", hi)?;
                if lo > hi {
                    // as written: a hinge's range is read in degrees by default (mjcf-rs has
                    // converted it), a slide's in metres
                    let value = if j.type_ == MjcfJointType::Hinge {
                        let deg = model.compiler.angle_is_degree;
                        let (a, b) = if deg {
                            (lo.to_degrees(), hi.to_degrees())
                        } else {
                            (lo, hi)
                        };
                        let unit = if deg { "degrees" } else { "rad" };
                        format!("{} {} ({unit})", fmt_num(a), fmt_num(b))
                    } else {
                        format!("{} {}", fmt_num(lo), fmt_num(hi))
                    };
                    return Err(context.field(&el, "range", value, "lower <= upper"));
                }
            }
        }
    }
    Ok(())
}

/// Body and joint names are unique, as MuJoCo requires (`repeated name`): the loader finds
/// a joint's MJCF attributes (its range, ref) and the overrides by name, and a scene its
/// bodies, so a second joint of the same name would lend the first its range, and a second
/// body of the same name would hide the first.
fn check_unique_names(context: &ErrorContext, model: &Model) -> Result<(), UrdfError> {
    let mut bodies: std::collections::HashMap<&str, usize> = Default::default();
    let mut joints: std::collections::HashMap<&str, Option<&str>> = Default::default();
    for (i, entry) in model.bodies.iter().enumerate() {
        let b = &entry.body;
        if let Some(n) = b.name.as_deref() {
            if bodies.insert(n, i).is_some() {
                return Err(context.field(
                    body_element(Some(n), i),
                    "name",
                    n,
                    "a unique body name (MuJoCo refuses a repeated name)",
                ));
            }
        }
        for (k, j) in b.joints.iter().enumerate() {
            let Some(n) = j.name.as_deref() else { continue };
            if let Some(first) = joints.insert(n, b.name.as_deref()) {
                let also = match first {
                    Some(f) => format!(" (also in body `{f}`)"),
                    None => String::new(),
                };
                return Err(context.field(
                    joint_element(Some(n), b.name.as_deref(), k),
                    "name",
                    n,
                    format!("a unique joint name{also}: MuJoCo refuses a repeated name"),
                ));
            }
        }
    }
    Ok(())
}

/// A body's pose, inertial and geoms (index `i` in the model, 0 the world): what
/// rapier3d-mjcf would turn into NaN (a position beyond f32), a negative or NaN mass, or a
/// panic (parry asserts the sign of a cylinder's sizes).
fn check_body(context: &ErrorContext, b: &Body, i: usize) -> Result<(), UrdfError> {
    let el = body_element(b.name.as_deref(), i);
    context.finite3(&el, "pos", &b.pose.translation.to_array())?;
    for q in b.pose.rotation.to_array() {
        context.finite(&el, "quat", q)?;
    }
    if let Some(inertial) = &b.inertial {
        context.finite3(&el, "inertial.pos", &inertial.pose.translation.to_array())?;
        let (field, values) = match &inertial.inertia {
            InertiaSpec::Diagonal(d) => ("inertial.diaginertia", d.to_vec()),
            InertiaSpec::Full(f) => ("inertial.fullinertia", f.to_vec()),
        };
        non_negative(context, &el, "inertial.mass", inertial.mass)?;
        for (k, v) in values.into_iter().enumerate() {
            // the products of inertia (fullinertia's last three) may be negative
            if k < 3 {
                non_negative(context, &el, field, v)?;
            } else {
                context.finite(&el, field, v)?;
            }
        }
    }
    for (k, g) in b.geoms.iter().enumerate() {
        let gel = match &g.name {
            Some(n) => format!("geom `{n}` ({el})"),
            None => format!("geom #{k} ({el})"),
        };
        context.finite3(&gel, "pos", &g.pose.translation.to_array())?;
        if let Some(ft) = g.fromto {
            context.finite3(&gel, "fromto", &[ft[0], ft[1], ft[2]])?;
            context.finite3(&gel, "fromto", &[ft[3], ft[4], ft[5]])?;
        }
        let sized = matches!(
            g.type_,
            GeomType::Sphere
                | GeomType::Capsule
                | GeomType::Cylinder
                | GeomType::Box
                | GeomType::Ellipsoid
        );
        if sized {
            for v in g.size {
                non_negative(context, &gel, "size", v)?;
            }
        }
        if let Some(m) = g.mass {
            non_negative(context, &gel, "mass", m)?;
        }
        if let Some(d) = g.density {
            non_negative(context, &gel, "density", d)?;
        }
    }
    Ok(())
}

/// `v` if it is finite, within ±1e12 and >= 0 by its sign bit (parry asserts it: -0 is
/// refused), else an error naming `element` and `field`.
fn non_negative(
    context: &ErrorContext,
    element: &str,
    field: &str,
    v: f64,
) -> Result<f64, UrdfError> {
    let v = context.finite(element, field, v)?;
    if v.is_sign_negative() {
        let expected = if v == 0.0 {
            "a value >= 0 without a minus sign (parry refuses -0)"
        } else {
            "a value >= 0"
        };
        return Err(context.field(element, field, v, expected));
    }
    Ok(v)
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

/// An XML element as errors name it: its tag, its `name` and its line,
/// `<joint name="j"> (line 12)`.
fn element_at(doc: &roxmltree::Document, node: &roxmltree::Node) -> String {
    let tag = node.tag_name().name();
    let line = doc.text_pos_at(node.range().start).row;
    match node.attribute("name") {
        Some(n) => format!("<{tag} name=\"{n}\"> (line {line})"),
        None => format!("<{tag}> (line {line})"),
    }
}

/// The first numeric attribute of `text` that is not a list of numbers, as an error naming
/// its element (tag, `name`, line) and the attribute.
pub(super) fn bad_number(context: &ErrorContext, text: &str) -> Option<UrdfError> {
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
            let el = element_at(&doc, &node);
            return Some(context.field(el, a.name(), a.value(), "numbers"));
        }
    }
    None
}

/// The first `class` or `childclass` attribute of `text` that names no `<default>` class, as
/// an error naming its element (tag, `name`, line): MuJoCo refuses it (`unknown default
/// class name`), mjcf-rs applies the main defaults instead, so a joint's damping or range
/// written in the class was silently lost. A model with an `<include>` is not checked (its
/// classes may be defined in the included file).
pub(super) fn unknown_class(context: &ErrorContext, text: &str) -> Result<(), UrdfError> {
    let Ok(doc) = roxmltree::Document::parse(text) else {
        return Ok(());
    };
    let elements = || doc.descendants().filter(|n| n.is_element());
    if elements().any(|n| n.tag_name().name() == "include") {
        return Ok(());
    }
    let mut classes: std::collections::HashSet<&str> = ["main"].into_iter().collect();
    for n in elements().filter(|n| n.tag_name().name() == "default") {
        if let Some(c) = n.attribute("class") {
            classes.insert(c);
        }
    }
    for node in elements().filter(|n| n.tag_name().name() != "default") {
        for attr in ["class", "childclass"] {
            let Some(c) = node.attribute(attr) else {
                continue;
            };
            if classes.contains(c) {
                continue;
            }
            let el = element_at(&doc, &node);
            return Err(context.field(el, attr, c, "the class of a <default>"));
        }
    }
    Ok(())
}

/// The overrides of `options` name joints of `model` and give KJOINT2 fields only (no rapier
/// joints nor motors for MJCF).
pub(super) fn check_overrides(
    context: &ErrorContext,
    model: &Model,
    options: &UrdfOptions,
) -> Result<(), UrdfError> {
    let names: std::collections::HashSet<&str> = model
        .bodies_iter()
        .flat_map(|(_, e)| e.body.joints.iter().filter_map(|j| j.name.as_deref()))
        .collect();
    for (name, ov) in &options.joints {
        if !names.contains(name.as_str()) {
            return Err(context.field(
                "options.joints",
                "name",
                name,
                "the name of a joint of the model",
            ));
        }
        if ov.engine == Some(JointEngine::Rapier) || ov.motor.is_some() {
            return Err(context.field(
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
    Ok(())
}

/// A notice for each mesh geom that `rapier3d-mjcf` skips without a word (it only logs): no
/// `mesh=`, a mesh not declared in `<asset>`, without a file or inline data, a file that is
/// not there, or a `.msh` file. Such a geom gives neither a collider nor mass: a body whose
/// mass came from its mesh (no `<inertial>`) would otherwise load with the minimum mass.
pub(super) fn mesh_notices(model: &Model, base: &Path) -> Vec<String> {
    let mut notices = Vec::new();
    for (i, entry) in model.bodies_iter() {
        let b = &entry.body;
        for (k, g) in b.geoms.iter().enumerate() {
            if g.type_ != GeomType::Mesh {
                continue;
            }
            let el = body_element(b.name.as_deref(), i);
            let gel = match &g.name {
                Some(n) => format!("geom `{n}` ({el})"),
                None => format!("geom #{k} ({el})"),
            };
            let why = match g.mesh.as_deref() {
                None => Some("a mesh geom without `mesh=`".to_string()),
                Some(name) => match model.assets.mesh(name) {
                    None => Some(format!("mesh `{name}` is not declared in <asset>")),
                    Some(mesh) => match model.resolve_mesh_file(mesh, base) {
                        None if mesh.inline_vertices.is_none() => Some(format!(
                            "mesh `{name}` has neither a `file=` nor inline vertices"
                        )),
                        None => None,
                        Some(p) if !p.is_file() => {
                            Some(format!("mesh `{name}`: file `{}` not found", p.display()))
                        }
                        Some(p) if p.extension().is_some_and(|e| e.eq_ignore_ascii_case("msh")) => {
                            Some(format!(
                                "mesh `{name}`: file `{}` is a MuJoCo .msh (only .stl and .obj \
                                 are read)",
                                p.display()
                            ))
                        }
                        Some(_) => None,
                    },
                },
            };
            if let Some(why) = why {
                notices.push(format!(
                    "{gel}: {why}: skipped (no collider, and no mass from it)"
                ));
            }
        }
    }
    notices
}
