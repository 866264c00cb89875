//! Where in a URDF document an error is. urdf-rs (through serde) reports a missing
//! attribute or a number it cannot read without its element or line (`custom: missing
//! field `value``, `custom: invalid float literal`); [`locate`] finds the first such
//! attribute itself, so that the error names the element, its line and the attribute. The
//! checks of the parsed robot name a link or joint and a field (``joint `elbow` ``,
//! `limit.lower`); [`with_element_line`] adds the line where that field is written.

use super::error::{with_line, ErrorContext, UrdfError};

/// An attribute of a URDF element that urdf-rs reads: how many numbers it holds (0: text),
/// and whether urdf-rs requires it.
struct Attribute {
    tag: &'static str,
    name: &'static str,
    numbers: usize,
    required: bool,
}

const fn attr(tag: &'static str, name: &'static str, numbers: usize, required: bool) -> Attribute {
    Attribute {
        tag,
        name,
        numbers,
        required,
    }
}

/// The attributes urdf-rs 0.9 reads, with what it requires of them.
const ATTRIBUTES: &[Attribute] = &[
    attr("link", "name", 0, true),
    attr("joint", "name", 0, true),
    attr("joint", "type", 0, true),
    attr("parent", "link", 0, true),
    attr("child", "link", 0, true),
    attr("mass", "value", 1, true),
    attr("inertia", "ixx", 1, true),
    attr("inertia", "ixy", 1, true),
    attr("inertia", "ixz", 1, true),
    attr("inertia", "iyy", 1, true),
    attr("inertia", "iyz", 1, true),
    attr("inertia", "izz", 1, true),
    attr("origin", "xyz", 3, false),
    attr("origin", "rpy", 3, false),
    attr("axis", "xyz", 3, false),
    attr("limit", "lower", 1, false),
    attr("limit", "upper", 1, false),
    attr("limit", "effort", 1, false),
    attr("limit", "velocity", 1, true),
    attr("dynamics", "damping", 1, false),
    attr("dynamics", "friction", 1, false),
    attr("mimic", "joint", 0, true),
    attr("mimic", "multiplier", 1, false),
    attr("mimic", "offset", 1, false),
    attr("box", "size", 3, true),
    attr("cylinder", "radius", 1, true),
    attr("cylinder", "length", 1, true),
    attr("capsule", "radius", 1, true),
    attr("capsule", "length", 1, true),
    attr("sphere", "radius", 1, true),
    attr("mesh", "filename", 0, true),
    attr("mesh", "scale", 3, false),
];

/// The URDF joint types.
const JOINT_TYPES: &[&str] = &[
    "revolute",
    "continuous",
    "prismatic",
    "fixed",
    "floating",
    "planar",
    "spherical",
];

/// Elements whose contents are not URDF (simulator extensions, transmissions).
const FOREIGN: &[&str] = &["gazebo", "transmission", "ros2_control"];

/// The first attribute of `text` that urdf-rs cannot read (missing where required, not
/// the right count of numbers, an unknown joint type), as an error naming its element (tag,
/// line, and the link or joint it belongs to) and the attribute; text that is not XML gets
/// the XML parser's error (with its line where it gives one); `None` when there is none.
pub(super) fn locate(context: &ErrorContext, text: &str) -> Option<UrdfError> {
    let doc = match roxmltree::Document::parse(text) {
        Ok(doc) => doc,
        // urdf-rs says `No elements found` or `Unexpected closing tag`, without a line
        Err(e) => {
            return Some(UrdfError::Parse {
                file: context.file.to_string(),
                message: format!("XML parse error: {e}"),
            })
        }
    };
    for node in doc.descendants().filter(|n| n.is_element()) {
        let tag = node.tag_name().name();
        if node
            .ancestors()
            .any(|a| FOREIGN.contains(&a.tag_name().name()))
        {
            continue;
        }
        let element = || {
            let line = doc.text_pos_at(node.range().start).row;
            let owner = node
                .ancestors()
                .find(|a| matches!(a.tag_name().name(), "link" | "joint"))
                .filter(|a| *a != node)
                .map(|a| match a.attribute("name") {
                    Some(n) => format!(", {} `{n}`", a.tag_name().name()),
                    None => format!(", {}", a.tag_name().name()),
                })
                .unwrap_or_default();
            match node
                .attribute("name")
                .filter(|_| matches!(tag, "link" | "joint"))
            {
                Some(n) => format!("<{tag} name=\"{n}\"> (line {line})"),
                None => format!("<{tag}> (line {line}{owner})"),
            }
        };
        for a in ATTRIBUTES.iter().filter(|a| a.tag == tag) {
            let Some(value) = node.attribute(a.name) else {
                if a.required {
                    return Some(context.field(
                        element(),
                        a.name,
                        "(missing)",
                        "the attribute: urdf-rs requires it",
                    ));
                }
                continue;
            };
            if a.numbers > 0 {
                let tokens: Vec<&str> = value.split_whitespace().collect();
                let numbers = tokens.iter().all(|t| t.parse::<f64>().is_ok());
                if !numbers || tokens.len() != a.numbers {
                    let expected = match a.numbers {
                        1 => "a number".to_string(),
                        n => format!("{n} numbers"),
                    };
                    return Some(context.field(element(), a.name, value, expected));
                }
            } else if tag == "joint" && a.name == "type" && !JOINT_TYPES.contains(&value) {
                return Some(context.field(
                    element(),
                    a.name,
                    value,
                    format!("one of {}", JOINT_TYPES.join(", ")),
                ));
            }
        }
    }
    None
}

/// `e` with the line of what it is about, when it is an error about a link, a joint or the
/// robot of `text` (``link `b` ``, `inertial.inertia.ixx` → ``link `b` (line 11)``, the line
/// of the link's `<inertia>`): found by [`line_of`]. Other errors are returned as they are.
pub(super) fn with_element_line(e: UrdfError, text: &str) -> UrdfError {
    match e {
        UrdfError::Field {
            file,
            element,
            field,
            value,
            expected,
        } => {
            let line = line_of(text, &element, &field);
            UrdfError::Field {
                file,
                element: with_line(element, line),
                field,
                value,
                expected,
            }
        }
        other => other,
    }
}

/// The line in `text` of the field `field` of `element` (``link `a` ``, ``joint `j` ``,
/// ``robot `r` ``), as the checks name them: the link or joint of that name (the second
/// one for a repeated `name`), then down its field's path as far as it goes through
/// elements, one of each (`limit.lower`: its `<limit>`; `inertial.inertia.ixx`: its
/// `<inertia>`; `collision.origin.xyz` of a link with two `<collision>`s: the link). `None`
/// for another element, or text that is not XML.
fn line_of(text: &str, element: &str, field: &str) -> Option<u32> {
    let (kind, rest) = element.split_once(" `")?;
    let name = rest.strip_suffix('`')?;
    let doc = roxmltree::Document::parse(text).ok()?;
    let root = doc.root_element();
    let line = |n: roxmltree::Node| doc.text_pos_at(n.range().start).row;
    if kind == "robot" {
        return Some(line(root));
    }
    if kind != "link" && kind != "joint" {
        return None;
    }
    let mut named = root
        .children()
        .filter(|n| n.has_tag_name(kind) && n.attribute("name") == Some(name));
    let first = named.next()?;
    let mut node = match named.next() {
        Some(second) if field == "name" => second,
        _ => first,
    };
    for step in field.split('.') {
        let mut children = node.children().filter(|n| n.has_tag_name(step));
        match (children.next(), children.next()) {
            (Some(only), None) => node = only,
            _ => break,
        }
    }
    Some(line(node))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        locate(&ErrorContext { file: "r.urdf" }, text)
            .map(|e| e.to_string())
            .unwrap_or_default()
    }

    #[test]
    fn names_the_element_its_line_and_the_attribute() {
        let text = "<robot name=\"r\">\n<link name=\"a\">\n<inertial>\n<mass value=\"six\"/>\n\
                    </inertial>\n</link>\n</robot>";
        assert_eq!(
            err(text),
            "r.urdf: <mass> (line 4, link `a`): invalid value = six: expected a number"
        );
        let text = "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n\
                    <joint name=\"j\" type=\"revolute\">\n<parent link=\"a\"/><child link=\"b\"/>\n\
                    <origin xyz=\"0.45 0\"/>\n</joint>\n</robot>";
        assert_eq!(
            err(text),
            "r.urdf: <origin> (line 6, joint `j`): invalid xyz = 0.45 0: expected 3 numbers"
        );
        let text =
            "<robot name=\"r\">\n<link name=\"a\"><inertial><mass/></inertial></link>\n</robot>";
        assert_eq!(
            err(text),
            "r.urdf: <mass> (line 2, link `a`): invalid value = (missing): expected the \
             attribute: urdf-rs requires it"
        );
        let text = "<robot name=\"r\">\n<joint name=\"j\" type=\"hinge\"/>\n</robot>";
        assert!(err(text).starts_with("r.urdf: <joint name=\"j\"> (line 2): invalid type = hinge"));
        // not XML: the parser's error, with the line and column
        let text = "<robot name=\"r\">\n<link name=\"a\">\n</joint>\n</robot>";
        assert!(
            err(text).starts_with("r.urdf: not a valid URDF document: XML parse error: ")
                && err(text).contains("3:"),
            "{}",
            err(text)
        );
        // gazebo extensions are not URDF
        let text = "<robot name=\"r\"><gazebo><origin xyz=\"a\"/></gazebo></robot>";
        assert_eq!(err(text), "");
    }
}
