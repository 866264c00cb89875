//! [`UrdfError`], the errors of the URDF and MJCF readers (each names the file, the element,
//! the field and what was expected), and `ErrorContext`, which makes them for one file.

use crate::error::SimError;
use crate::figure::fmt_num;
use crate::scene::build::MAX_VALUE;
use std::path::PathBuf;

/// Errors of the URDF loader. Each names the file (or `<string>`).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum UrdfError {
    /// The file could not be read (or is larger than [`crate::io::MAX_INPUT_BYTES`]).
    #[error("{file}: {source}")]
    Read {
        /// The file.
        file: PathBuf,
        /// The cause.
        #[source]
        source: crate::io::InputErrorKind,
    },
    /// The text is not a URDF document urdf-rs accepts.
    #[error("{file}: not a valid URDF document: {message}")]
    Parse {
        /// The file.
        file: String,
        /// The parser's message.
        message: String,
    },
    /// The text is not an MJCF model mjcf-rs accepts (its message names the element and the
    /// attribute).
    #[error("{file}: not a valid MJCF model: {message}")]
    Mjcf {
        /// The file.
        file: String,
        /// The parser's message.
        message: String,
    },
    /// A value is invalid.
    #[error("{file}: {element}: invalid {field} = {value}: expected {expected}")]
    Field {
        /// The file.
        file: String,
        /// The element, e.g. ``joint `elbow` `` or ``options.joints.`elbow` ``.
        element: String,
        /// The field, e.g. `limit.lower`.
        field: String,
        /// The value given.
        value: String,
        /// What is accepted.
        expected: String,
    },
    /// A per-joint override gives an invalid property.
    #[error("{file}: options.joints.`{joint}`: {source}")]
    Override {
        /// The file.
        file: String,
        /// The URDF joint.
        joint: String,
        /// What is wrong with the resulting property.
        #[source]
        source: crate::error::PropertyError,
    },
    /// The joints form a closed loop (URDF describes a tree: every link but the root is the
    /// child of one joint).
    #[error(
        "{file}: the joints {} form a closed loop (links {}): a URDF robot is a tree from \
         one root link; close the loop with a KJOINT2 joint of its own (a scene's [[joints]])",
        joints.iter().map(|j| format!("`{j}`")).collect::<Vec<_>>().join(", "),
        links.iter().map(|l| format!("`{l}`")).collect::<Vec<_>>().join(" → ")
    )]
    Loop {
        /// The file.
        file: String,
        /// The joints of the loop, in order from parent to child.
        joints: Vec<String>,
        /// The links of the loop, from parent to child, the first repeated at the end.
        links: Vec<String>,
    },
    /// A KJOINT2 joint could not be built.
    #[error("{file}: {}", joint_error(joint, source))]
    Joint {
        /// The file.
        file: String,
        /// The URDF joint.
        joint: String,
        /// The cause.
        #[source]
        source: Box<SimError>,
    },
}

/// `source` naming the joint once: the joint set's errors start with ``joint `name`: ``
/// (the KJOINT2 joint is named after the robot's), and were named twice.
fn joint_error(joint: &str, source: &SimError) -> String {
    let s = source.to_string();
    if s.starts_with(&format!("joint `{joint}`")) {
        s
    } else {
        format!("joint `{joint}`: {s}")
    }
}

/// The file errors are reported against, and the constructors of its field errors.
pub(crate) struct ErrorContext<'a> {
    /// The file's name as errors give it (`<string>` for text).
    pub(crate) file: &'a str,
}

impl ErrorContext<'_> {
    /// A [`UrdfError::Field`]: `element`'s `field` is `value`, `expected` was expected.
    pub(crate) fn field(
        &self,
        element: impl Into<String>,
        field: impl Into<String>,
        value: impl ToString,
        expected: impl Into<String>,
    ) -> UrdfError {
        UrdfError::Field {
            file: self.file.to_string(),
            element: element.into(),
            field: field.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }

    /// `v`, or an error when it is not finite or beyond ±1e12 ([`in_range`]).
    pub(crate) fn finite(&self, element: &str, field: &str, v: f64) -> Result<f64, UrdfError> {
        if in_range(v) {
            Ok(v)
        } else if v.is_finite() {
            Err(self.field(element, field, fmt_num(v), RANGE))
        } else {
            Err(self.field(element, field, v, "a finite number"))
        }
    }

    /// An error when one of `v` is not finite or beyond ±1e12 ([`in_range`]).
    pub(crate) fn finite3(
        &self,
        element: &str,
        field: &str,
        v: &[f64; 3],
    ) -> Result<(), UrdfError> {
        if v.iter().all(|x| in_range(*x)) {
            Ok(())
        } else if v.iter().all(|x| x.is_finite()) {
            Err(self.field(element, field, format!("{v:?}"), RANGE))
        } else {
            Err(self.field(element, field, format!("{v:?}"), "finite numbers"))
        }
    }
}

/// Why values are held to ±1e12 ([`in_range`]), as errors say it.
macro_rules! range_reason {
    () => {
        "the bound of a robot file's values and of the overrides that replace them: rapier \
         works in f32, where larger sizes, masses and positions overflow"
    };
}

/// What [`in_range`] asks of a value, as errors say it.
pub(crate) const RANGE: &str = concat!("a finite number within ±1e12 (", range_reason!(), ")");

/// What [`in_range`] asks of each of a list of values (an MJCF `euler`), as errors say it.
pub(crate) const RANGES: &str = concat!("finite numbers within ±1e12 (", range_reason!(), ")");

/// Whether `v` is finite and within ±[`MAX_VALUE`] (1e12), as scene values are: the robot
/// loaders build f32 bodies and colliders, where `1e300` is an infinity (NaN poses and
/// energies) and sizes beyond ~1e19 overflow parry's contact queries (a panic).
pub(crate) fn in_range(v: f64) -> bool {
    v.is_finite() && v.abs() <= MAX_VALUE
}

/// `element` with its `line`: ``joint `j` (body `b`, line 12)``, ``link `a` (line 3)``
/// (unchanged without a line). The URDF and MJCF errors about an element they name write
/// its line so.
pub(crate) fn with_line(element: String, line: Option<u32>) -> String {
    match line {
        None => element,
        Some(n) => match element.strip_suffix(')') {
            Some(head) if head.contains(" (") => format!("{head}, line {n})"),
            _ => format!("{element} (line {n})"),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_joint_error_names_the_joint_once() {
        let joint = |source: SimError| UrdfError::Joint {
            file: "arm.urdf".into(),
            joint: "knee".into(),
            source: Box::new(source),
        };
        let named = SimError::InvalidJoint {
            joint: "knee".into(),
            reason: "both bodies are fixed".into(),
        };
        assert_eq!(
            joint(named).to_string(),
            "arm.urdf: joint `knee`: both bodies are fixed"
        );
        let other = SimError::InvalidJoint {
            joint: "knee_2".into(),
            reason: "both bodies are fixed".into(),
        };
        assert_eq!(
            joint(other).to_string(),
            "arm.urdf: joint `knee`: joint `knee_2`: both bodies are fixed"
        );
    }
}
