//! Where a URDF document urdf-rs refused went wrong. urdf-rs (through serde) reports a
//! missing attribute or a number it cannot read without its element or line (`custom:
//! missing field `value``, `custom: invalid float literal`); this finds the first such
//! attribute itself, so that the error names the element, its line and the attribute.

use super::error::{ErrorContext, UrdfError};

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
