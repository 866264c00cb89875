//! Validation of a parsed MJCF model: what `rapier3d-mjcf` would turn into NaN, nonsense or a
//! panic is refused naming the joint, body or geom and the attribute; the overrides must
//! name joints of the model and hold KJOINT2 fields only; and a number mjcf-rs could not read
//! is found again to name its element and attribute.

use super::files::{mesh_geoms, MeshOf};
use crate::figure::fmt_num;
use crate::io::urdf::{
    in_range, read_mesh_file, with_line, ErrorContext, JointEngine, UrdfError, UrdfOptions, RANGES,
};
use rapier3d_mjcf::mjcf_rs::body::{Body, GeomType, InertiaSpec, JointType as MjcfJointType};
use rapier3d_mjcf::mjcf_rs::model::Model;
use rapier3d_mjcf::mjcf_rs::ParseError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

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

/// What rapier3d-mjcf would turn into NaN or nonsense: refused, naming joint and attribute,
/// with the element's line where `lines` has it.
pub(super) fn check_model(
    context: &ErrorContext,
    model: &Model,
    lines: Option<&Lines>,
) -> Result<(), UrdfError> {
    check_unique_names(context, model, lines)?;
    for (i, entry) in model.bodies.iter().enumerate() {
        check_body(context, &entry.body, i, lines)?;
    }
    for (i, entry) in model.bodies_iter() {
        let b = &entry.body;
        for (k, j) in b.joints.iter().enumerate() {
            let el = with_line(
                joint_element(j.name.as_deref(), b.name.as_deref(), k),
                lines.and_then(|l| l.joint(i, k)),
            );
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
                // a damping of 1e308 is finite, and its law's viscosity in N·m·s/rad an
                // infinity the joint's builder refused without a line
                context.finite(&el, f, v)?;
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
fn check_unique_names(
    context: &ErrorContext,
    model: &Model,
    lines: Option<&Lines>,
) -> Result<(), UrdfError> {
    let mut bodies: std::collections::HashMap<&str, usize> = Default::default();
    let mut joints: std::collections::HashMap<&str, Option<&str>> = Default::default();
    for (i, entry) in model.bodies.iter().enumerate() {
        let b = &entry.body;
        if let Some(n) = b.name.as_deref() {
            // (MuJoCo names its world body `world`; so do the loader's links)
            if i > 0 && n == crate::io::urdf::WORLD_LINK {
                return Err(context.field(
                    with_line(body_element(Some(n), i), lines.and_then(|l| l.body(i))),
                    "name",
                    n,
                    "a name other than `world` (MuJoCo's world body's)",
                ));
            }
            if bodies.insert(n, i).is_some() {
                return Err(context.field(
                    with_line(body_element(Some(n), i), lines.and_then(|l| l.body(i))),
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
                    with_line(
                        joint_element(Some(n), b.name.as_deref(), k),
                        lines.and_then(|l| l.joint(i, k)),
                    ),
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
fn check_body(
    context: &ErrorContext,
    b: &Body,
    i: usize,
    lines: Option<&Lines>,
) -> Result<(), UrdfError> {
    let el = with_line(
        body_element(b.name.as_deref(), i),
        lines.and_then(|l| l.body(i)),
    );
    context.finite3(&el, "pos", &b.pose.translation.to_array())?;
    orientation(context, &el, "orientation", b.pose.rotation.to_array())?;
    if let Some(inertial) = &b.inertial {
        context.finite3(&el, "inertial.pos", &inertial.pose.translation.to_array())?;
        let q = inertial.pose.rotation.to_array();
        orientation(context, &el, "inertial.orientation", q)?;
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
    let bel = body_element(b.name.as_deref(), i);
    for (k, g) in b.geoms.iter().enumerate() {
        let gel = match &g.name {
            Some(n) => format!("geom `{n}` ({bel})"),
            None => format!("geom #{k} ({bel})"),
        };
        let gel = with_line(gel, lines.and_then(|l| l.geom(i, k)));
        context.finite3(&gel, "pos", &g.pose.translation.to_array())?;
        orientation(context, &gel, "orientation", g.pose.rotation.to_array())?;
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

/// An error naming `field` of `element` when the quaternion `q` mjcf-rs made of its
/// orientation is not finite. The orientations written in the model's own text are checked
/// as written before ([`bad_rotation`], which names the attribute); this catches those of
/// an `<include>`d file.
fn orientation(
    context: &ErrorContext,
    element: &str,
    field: &str,
    q: [f64; 4],
) -> Result<(), UrdfError> {
    if q.iter().all(|x| x.is_finite()) {
        return Ok(());
    }
    Err(context.field(
        element,
        field,
        format!("{q:?}"),
        "a finite rotation (the quaternion mjcf-rs made of its quat, euler, axisangle, \
         xyaxes or zaxis, in an included file)",
    ))
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

/// Attributes mjcf-rs 0.36 reads as one number (`parse_f64`; `coef` of a `<fixed>` tendon's
/// joint).
const SCALAR_ATTRIBUTES: &[&str] = &[
    "armature",
    "boundinertia",
    "boundmass",
    "coef",
    "cutoff",
    "damping",
    "density",
    "emission",
    "frictionloss",
    "gap",
    "gravcomp",
    "inertiadensity",
    "kp",
    "kv",
    "margin",
    "mass",
    "metallic",
    "noise",
    "ref",
    "roughness",
    "settotalmass",
    "shininess",
    "smoothnormal",
    "specular",
    "springref",
    "stiffness",
    "time",
    "timestep",
    "torquescale",
];

/// Attributes mjcf-rs 0.36 reads as a list of numbers (each token a number; their count is
/// checked by mjcf-rs, which names the attribute then).
const LIST_ATTRIBUTES: &[&str] = &[
    "act",
    "anchor",
    "axis",
    "axisangle",
    "biasprm",
    "ctrl",
    "ctrlrange",
    "diaginertia",
    "dynprm",
    "elevation",
    "euler",
    "face",
    "forcerange",
    "friction",
    "fromto",
    "fullinertia",
    "gainprm",
    "gear",
    "gravity",
    "mpos",
    "mquat",
    "normal",
    "polycoef",
    "pos",
    "qpos",
    "quat",
    "qvel",
    "range",
    "refpos",
    "refquat",
    "relpose",
    "rgb1",
    "rgb2",
    "rgba",
    "scale",
    "size",
    "solimp",
    "solref",
    "springdamper",
    "user",
    "vertex",
    "xyaxes",
    "zaxis",
];

/// Attributes mjcf-rs 0.36 reads as unsigned integers (`parse_u32`).
const UNSIGNED_ATTRIBUTES: &[&str] = &[
    "conaffinity",
    "condim",
    "contype",
    "maxhullvert",
    "ncol",
    "nrow",
];

/// Attributes mjcf-rs 0.36 reads as integers (`parse_i32`).
const INTEGER_ATTRIBUTES: &[&str] = &["group", "priority"];

/// Attributes mjcf-rs 0.36 reads as `true`/`false` (`parse_bool`).
const BOOL_ATTRIBUTES: &[&str] = &[
    "active",
    "autolimits",
    "balanceinertia",
    "convexhull",
    "discardvisual",
    "exactmeshinertia",
    "mocap",
    "sleep",
    "strippath",
];

/// Attributes mjcf-rs 0.36 reads as `true`/`false`/`auto` (`parse_tristate`).
const TRISTATE_ATTRIBUTES: &[&str] = &["ctrllimited", "forcelimited", "limited"];

/// An XML element as errors name it: its tag, its `name` and its line,
/// `<joint name="j"> (line 12)`.
pub(super) fn element_at(doc: &roxmltree::Document, node: &roxmltree::Node) -> String {
    let tag = node.tag_name().name();
    let line = doc.text_pos_at(node.range().start).row;
    match node.attribute("name") {
        Some(n) => format!("<{tag} name=\"{n}\"> (line {line})"),
        None => format!("<{tag}> (line {line})"),
    }
}

/// The line of each body of a model and of its joints and geoms, by mjcf-rs's indices
/// (`model.bodies[i]`, its `joints[k]` and `geoms[k]`), found by walking `<worldbody>` as
/// mjcf-rs does: bodies in document order, depth first; a `<freejoint>` is a joint; the
/// geoms of a `<frame>` belong to its body. The walk gives up (no lines) where it cannot
/// follow mjcf-rs (`<include>`, `<attach>`) or where its counts differ from the model's.
pub(super) struct Lines {
    /// For each body: its line (`<worldbody>`'s for the world), its joints', its geoms'.
    bodies: Vec<(u32, Vec<u32>, Vec<u32>)>,
}

impl Lines {
    /// The lines of `model`, read from its parsed text `doc`, or `None` (above).
    pub(super) fn of(doc: &roxmltree::Document, model: &Model) -> Option<Lines> {
        let line = |n: &roxmltree::Node| doc.text_pos_at(n.range().start).row;
        let mut bodies: Vec<(u32, Vec<u32>, Vec<u32>)> = Vec::new();
        // the element children of `node`, whose joints and geoms belong to body `owner`
        // (its joints only where `node` is the body itself: mjcf-rs reads no joint of a
        // frame or of `<worldbody>`)
        fn walk(
            node: roxmltree::Node,
            owner: usize,
            bodies: &mut Vec<(u32, Vec<u32>, Vec<u32>)>,
            line: &dyn Fn(&roxmltree::Node) -> u32,
            in_body: bool,
        ) -> Option<()> {
            for child in node.children().filter(|n| n.is_element()) {
                match child.tag_name().name() {
                    "joint" | "freejoint" if in_body => bodies[owner].1.push(line(&child)),
                    "geom" => bodies[owner].2.push(line(&child)),
                    "body" => {
                        bodies.push((line(&child), Vec::new(), Vec::new()));
                        let id = bodies.len() - 1;
                        walk(child, id, bodies, line, true)?;
                    }
                    // a frame's joints are not read (mjcf-rs): only its geoms and bodies
                    "frame" => walk(child, owner, bodies, line, false)?,
                    "include" | "attach" => return None,
                    _ => {}
                }
            }
            Some(())
        }
        for wb in doc
            .root_element()
            .children()
            .filter(|n| n.is_element() && n.tag_name().name() == "worldbody")
        {
            if bodies.is_empty() {
                bodies.push((line(&wb), Vec::new(), Vec::new()));
            }
            walk(wb, 0, &mut bodies, &line, false)?;
        }
        let same = bodies.len() == model.bodies.len()
            && bodies.iter().zip(&model.bodies).all(|((_, j, g), e)| {
                j.len() == e.body.joints.len() && g.len() == e.body.geoms.len()
            });
        same.then_some(Lines { bodies })
    }

    fn body(&self, i: usize) -> Option<u32> {
        self.bodies.get(i).map(|b| b.0)
    }

    fn joint(&self, i: usize, k: usize) -> Option<u32> {
        self.bodies.get(i)?.1.get(k).copied()
    }

    fn geom(&self, i: usize, k: usize) -> Option<u32> {
        self.bodies.get(i)?.2.get(k).copied()
    }
}

/// The attributes that give an element an orientation.
const ORIENTATIONS: &[&str] = &["quat", "euler", "axisangle", "xyaxes", "zaxis"];

/// The first orientation of `text` that is not finite, beyond ±1e12 ([`in_range`]), or
/// written so that it has no direction (a `quat` of norm 0, an `axisangle` or `zaxis` of
/// length 0, `xyaxes` whose x axis is 0 or parallel to y), as an error naming its element
/// (tag, `name`, line) and the attribute as written, on any element (bodies, geoms,
/// inertials, sites, frames, defaults). mjcf-rs turns each into a quaternion: of
/// `euler="inf 0 0"` a NaN one, reported as `quat = NaN` on a body and not at all on a geom
/// or an inertial; and it reads a rotation without a direction as the identity without a
/// word (below 1e-15 for an axis, 1e-30 for a quaternion's squared norm), so a body written
/// `quat="0 0 0 0"` loaded unrotated; MuJoCo refuses them (`zero quaternion is not
/// allowed`, `axisangle too small`, `xaxis too small`, ...).
pub(super) fn bad_rotation(
    context: &ErrorContext,
    doc: &roxmltree::Document,
) -> Result<(), UrdfError> {
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    for node in doc.descendants().filter(|n| n.is_element()) {
        for a in node.attributes() {
            if !ORIENTATIONS.contains(&a.name()) {
                continue;
            }
            let v: Vec<f64> = a
                .value()
                .split_whitespace()
                .filter_map(|t| t.parse().ok())
                .collect();
            let expected = if v.iter().any(|x| !x.is_finite()) {
                "finite numbers".to_string()
            } else if v.iter().any(|x| !in_range(*x)) {
                RANGES.to_string()
            } else {
                match (a.name(), v.len()) {
                    ("quat", 4) if norm(&v) * norm(&v) <= 1e-30 => {
                        "a quaternion of non-zero norm (w x y z)".into()
                    }
                    ("axisangle", 4) if norm(&v[..3]) <= 1e-15 => {
                        "a non-zero axis, then the angle".into()
                    }
                    ("zaxis", 3) if norm(&v) <= 1e-15 => "a non-zero axis".into(),
                    ("xyaxes", 6) => {
                        let (x, y) = (&v[..3], &v[3..]);
                        let z = [
                            x[1] * y[2] - x[2] * y[1],
                            x[2] * y[0] - x[0] * y[2],
                            x[0] * y[1] - x[1] * y[0],
                        ];
                        if norm(x) <= 1e-15 || norm(&z) / norm(x) <= 1e-15 {
                            "a non-zero x axis and a y axis not parallel to it".into()
                        } else {
                            continue;
                        }
                    }
                    _ => continue,
                }
            };
            let el = element_at(doc, &node);
            return Err(context.field(el, a.name(), a.value(), expected));
        }
    }
    Ok(())
}

/// The attribute mjcf-rs could not read, found again in `text`, as an error naming its
/// element (tag, `name`, line), the attribute, its value and what was expected; `None` where
/// it is not found (in an included file, or an error of another kind). mjcf-rs names neither
/// element nor attribute of a number, integer or boolean it cannot read (`invalid attribute
/// `_` on <_>`), and no line for any attribute: the first attribute (in document order) of
/// that kind whose value fails mjcf-rs's parse is the one, or the first element of the tag
/// mjcf-rs names whose attribute holds the value it quotes.
pub(super) fn located_parse_error(
    context: &ErrorContext,
    text: &str,
    error: &ParseError,
) -> Option<UrdfError> {
    let doc = roxmltree::Document::parse(text).ok()?;
    let f64_ok = |t: &str| t.parse::<f64>().is_ok();
    // whether attribute `a` of an element `t` is of the kind the error is about (`t` not
    // asked where `any_tag`: mjcf-rs names an actuator's `ctrlrange` on <actuator>)
    let kind = |t: &str, a: &str, any_tag: bool| -> bool {
        let (tag, attr) = match error {
            ParseError::BadAttribute { tag, attr, .. }
            | ParseError::BadAttributeValue { tag, attr, .. } => (tag, attr),
            _ => return false,
        };
        if !(any_tag || tag == "_" || tag == t) || !(attr == "_" || attr == a) {
            return false;
        }
        match error {
            ParseError::BadAttribute { message, .. } if message.starts_with("not a float") => {
                SCALAR_ATTRIBUTES.contains(&a) || LIST_ATTRIBUTES.contains(&a)
            }
            ParseError::BadAttribute { message, .. } if message.starts_with("not an unsigned") => {
                UNSIGNED_ATTRIBUTES.contains(&a)
            }
            ParseError::BadAttribute { message, .. } if message.starts_with("not an integer") => {
                INTEGER_ATTRIBUTES.contains(&a)
            }
            ParseError::BadAttribute { .. } => false,
            _ if attr == "_" => BOOL_ATTRIBUTES.contains(&a) || TRISTATE_ATTRIBUTES.contains(&a),
            _ => true,
        }
    };
    // whether the value `v` of attribute `a` fails the parse the error comes from
    let fails = |a: &str, v: &str| -> bool {
        match error {
            ParseError::BadAttribute { message, .. } if message.starts_with("not a float") => {
                if SCALAR_ATTRIBUTES.contains(&a) {
                    !f64_ok(v.trim())
                } else {
                    !v.split_ascii_whitespace().all(f64_ok)
                }
            }
            ParseError::BadAttribute { message, .. } if message.starts_with("not an unsigned") => {
                v.trim().parse::<u32>().is_err()
            }
            ParseError::BadAttribute { .. } => v.trim().parse::<i32>().is_err(),
            ParseError::BadAttributeValue { value, .. } => v == value,
            _ => false,
        }
    };
    let expected = match error {
        ParseError::BadAttribute { message, .. } if message.starts_with("not a float") => {
            "numbers".to_string()
        }
        ParseError::BadAttribute { message, .. } if message.starts_with("not an unsigned") => {
            "an integer >= 0".to_string()
        }
        ParseError::BadAttribute { .. } => "an integer".to_string(),
        ParseError::BadAttributeValue { message, .. } => match message.strip_prefix("expected ") {
            Some(m) => m.to_string(),
            None if message == "unknown geom type" => {
                "a geom type: plane, hfield, sphere, capsule, ellipsoid, cylinder, box, mesh or \
                 sdf"
                .to_string()
            }
            None => format!("a value mjcf-rs reads ({message})"),
        },
        _ => return None,
    };
    for any_tag in [false, true] {
        for node in doc
            .descendants()
            .filter(|n| n.is_element() && read_by_mjcf_rs(n))
        {
            for a in node.attributes() {
                if kind(node.tag_name().name(), a.name(), any_tag) && fails(a.name(), a.value()) {
                    let el = element_at(&doc, &node);
                    return Some(context.field(el, a.name(), a.value(), expected));
                }
            }
        }
    }
    None
}

/// The first `class` or `childclass` attribute of `text` that names no `<default>` class, as
/// an error naming its element (tag, `name`, line): MuJoCo refuses it (`unknown default
/// class name`), mjcf-rs applies the main defaults instead, so a joint's damping or range
/// written in the class was silently lost. A model with an `<include>` is not checked (its
/// classes may be defined in the included file).
pub(super) fn unknown_class(
    context: &ErrorContext,
    doc: &roxmltree::Document,
) -> Result<(), UrdfError> {
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
            let el = element_at(doc, &node);
            return Err(context.field(el, attr, c, "the class of a <default>"));
        }
    }
    Ok(())
}

/// Whether mjcf-rs 0.36 reads the attributes of element `node`: not those of `<visual>`,
/// `<size>`, `<statistic>`, `<custom>`, `<extension>` and what they hold, of `<option>`'s
/// children (`<flag gravity="disable">`), of lights and cameras, nor of the elements it
/// drops (`<composite>`, `<flexcomp>`, `<plugin>`): a `<light specular=".1 .1 .1">` (three
/// numbers, which mjcf-rs never parses there) was named for a body's unreadable mass.
fn read_by_mjcf_rs(node: &roxmltree::Node) -> bool {
    const SKIPPED: &[&str] = &[
        "visual",
        "size",
        "statistic",
        "custom",
        "extension",
        "light",
        "camera",
        "composite",
        "flexcomp",
        "plugin",
    ];
    let under_option = node
        .parent_element()
        .is_some_and(|p| p.tag_name().name() == "option");
    !under_option
        && node
            .ancestors()
            .filter(|n| n.is_element())
            .all(|n| !SKIPPED.contains(&n.tag_name().name()))
}

/// The numbers of every actuator are finite and within ±1e12 ([`in_range`]): a `kp` of NaN
/// or a gear of 1e308 made a motor the joint's builder refused naming neither the actuator
/// nor its line. The actuator is named by its element and line where the `<actuator>`
/// children of `doc` are the model's actuators one for one (no `<include>` nor `<attach>`
/// in the model).
pub(super) fn check_actuators(
    context: &ErrorContext,
    model: &Model,
    doc: Option<&roxmltree::Document>,
) -> Result<(), UrdfError> {
    let nodes: Vec<roxmltree::Node> = doc
        .map(|d| {
            d.descendants()
                .filter(|n| {
                    n.is_element()
                        && n.parent_element()
                            .is_some_and(|p| p.tag_name().name() == "actuator")
                })
                .collect()
        })
        .unwrap_or_default();
    // an `<include>` or an `<attach>` brings actuators from elsewhere
    let elsewhere = doc.is_some_and(|d| {
        d.descendants()
            .any(|n| matches!(n.tag_name().name(), "include" | "attach"))
    });
    let by_line = !elsewhere && nodes.len() == model.actuators.len();
    for (k, act) in model.actuators.iter().enumerate() {
        let el = match (doc, by_line) {
            (Some(d), true) => element_at(d, &nodes[k]),
            _ => match act.name.as_deref() {
                Some(n) => format!("actuator `{n}`"),
                None => format!("actuator #{k} (unnamed)"),
            },
        };
        let pairs = |v: Option<[f64; 2]>| v.map(|p| p.to_vec()).unwrap_or_default();
        for (field, values) in [
            ("gear", act.gear.to_vec()),
            ("ctrlrange", pairs(act.ctrl_range)),
            ("forcerange", pairs(act.force_range)),
            ("gainprm", act.gainprm.clone()),
            ("biasprm", act.biasprm.clone()),
            ("dynprm", act.dynprm.clone()),
            ("kp", act.kp.into_iter().collect()),
            ("kv", act.kv.into_iter().collect()),
        ] {
            for v in values {
                context.finite(&el, field, v)?;
            }
        }
        for (field, v) in [("kp", act.kp), ("kv", act.kv)] {
            if let Some(v) = v.filter(|v| *v < 0.0) {
                return Err(context.field(
                    &el,
                    field,
                    fmt_num(v),
                    "a gain >= 0 (a negative one drives away from the target)",
                ));
            }
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
    let el = "options.initial_positions";
    for (name, &q) in &options.initial_positions {
        let joint = model.joint_by_name(name);
        let Some(j) = joint.map(|(b, i)| &model.bodies[b].body.joints[i]) else {
            return Err(context.field(el, name, q, "the name of a joint of the model"));
        };
        if !matches!(j.type_, MjcfJointType::Hinge | MjcfJointType::Slide) {
            return Err(context.field(
                el,
                name,
                q,
                "the name of a hinge or slide joint (this one is not)",
            ));
        }
        let limited = (j.limited).resolve(model.compiler.autolimits, j.range.is_some());
        if let Some([lo, hi]) = j.range.filter(|_| limited) {
            if !(lo <= q && q <= hi) {
                return Err(context.field(
                    el,
                    name,
                    q,
                    format!("a position within the joint's range [{lo}, {hi}] (rad or m)"),
                ));
            }
        }
    }
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
/// not there, a `.msh` file, or a file that cannot be read as a mesh (not parsed, or with no
/// triangle: an empty `.obj`), read by the URDF loader's reader ([`read_mesh_file`]). Such a geom gives neither a collider nor mass: a body whose
/// mass came from its mesh (no `<inertial>`) would otherwise load with the minimum mass.
pub(super) fn mesh_notices(model: &Model, base: &Path) -> Vec<String> {
    let mut notices = Vec::new();
    // why each file read cannot be (each read once, however many geoms use it)
    let mut unreadable: HashMap<PathBuf, Option<String>> = HashMap::new();
    for g in mesh_geoms(model, base) {
        let el = body_element(g.body.name.as_deref(), g.body_index);
        let gel = match &g.geom.name {
            Some(n) => format!("geom `{n}` ({el})"),
            None => format!("geom #{} ({el})", g.geom_index),
        };
        let why = match g.mesh {
            MeshOf::Unnamed => Some("a mesh geom without `mesh=`".to_string()),
            MeshOf::Undeclared(name) => Some(format!("mesh `{name}` is not declared in <asset>")),
            MeshOf::Declared { name, mesh, file } => match file {
                None if mesh.inline_vertices.is_none() => Some(format!(
                    "mesh `{name}` has neither a `file=` nor inline vertices"
                )),
                None => None,
                Some(p) if !p.is_file() => {
                    Some(format!("mesh `{name}`: file `{}` not found", p.display()))
                }
                Some(p) if p.extension().is_some_and(|e| e.eq_ignore_ascii_case("msh")) => {
                    Some(format!(
                        "mesh `{name}`: file `{}` is a MuJoCo .msh (only .stl and .obj are read)",
                        p.display()
                    ))
                }
                Some(p) => unreadable
                    .entry(p.clone())
                    .or_insert_with(|| read_mesh_file(&p, |v| v).err())
                    .as_ref()
                    .map(|e| format!("mesh `{name}`: file `{}` unreadable: {e}", p.display())),
            },
        };
        if let Some(why) = why {
            notices.push(format!(
                "{gel}: {why}: skipped (no collider, and no mass from it)"
            ));
        }
    }
    notices
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped pendulum: every body, joint and geom at the line it is written on.
    #[test]
    fn the_lines_of_the_shipped_pendulum() {
        let text = include_str!("../../../assets/mjcf/pendulum.xml");
        let model = Model::from_str(text, Path::new(".")).unwrap();
        let doc = roxmltree::Document::parse(text).unwrap();
        let lines = Lines::of(&doc, &model).expect("lines");
        let line_of = |needle: &str| {
            text.lines()
                .position(|l| l.contains(needle))
                .map(|i| i as u32 + 1)
        };
        let names: Vec<_> = model.bodies.iter().map(|e| e.body.name.clone()).collect();
        assert_eq!(
            names,
            [
                None,
                Some("base".into()),
                Some("upper".into()),
                Some("lower".into())
            ]
        );
        assert_eq!(lines.body(0), line_of("<worldbody>"));
        assert_eq!(lines.body(1), line_of("<body name=\"base\""));
        assert_eq!(lines.body(3), line_of("<body name=\"lower\""));
        assert_eq!(lines.joint(2, 0), line_of("name=\"shoulder\""));
        assert_eq!(lines.joint(3, 0), line_of("name=\"elbow\""));
        assert_eq!(lines.geom(1, 0), line_of("type=\"box\""));
        assert_eq!(lines.joint(1, 0), None);
        assert_eq!(lines.geom(3, 1), None);
        // the gymnasium models, where `.ci/run` downloads them: the walk follows mjcf-rs
        if let Ok(dir) = std::env::var("KJOINT_MJCF_MODELS") {
            let mut n = 0;
            for e in std::fs::read_dir(&dir).unwrap() {
                let p = e.unwrap().path();
                if p.extension().is_some_and(|x| x == "xml") {
                    let text = std::fs::read_to_string(&p).unwrap();
                    let model = Model::from_str(&text, Path::new(&dir)).unwrap();
                    let doc = roxmltree::Document::parse(&text).unwrap();
                    assert!(Lines::of(&doc, &model).is_some(), "{}", p.display());
                    n += 1;
                }
            }
            assert!(n > 0);
        }
    }
}
