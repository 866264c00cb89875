//! The scene's `[[switches]]`: KJOINT2 joints switched off or on at given times.

use super::checks::{listed, non_negative};
use super::Assembly;
use crate::dynamics::KjointHandle;
use crate::io::units::{Quantity, UnitSystem};
use crate::scene::schema::Scene;
use crate::scene::{FieldPath, SceneError, Source};

/// A joint switched off or on at a time, in SI (scene `[[switches]]`,
/// [`crate::scene::schema::SwitchSpec`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Switch {
    /// The joint's name.
    pub joint_name: String,
    /// The joint.
    pub joint: KjointHandle,
    /// When \[s\].
    pub time: f64,
    /// Switched on (`true`) or off.
    pub enabled: bool,
}

impl Assembly {
    /// The scene's switches, each on a KJOINT2 joint of the scene or of a robot, in time
    /// order (those of one time in the scene's order).
    pub(super) fn switches(
        &self,
        scene: &Scene,
        src: &Source,
        units: &UnitSystem,
    ) -> Result<Vec<Switch>, SceneError> {
        let mut out = Vec::with_capacity(scene.switches.len());
        for (i, s) in scene.switches.iter().enumerate() {
            let p = FieldPath::root("switches").index(i);
            let Some(&joint) = self.joint_names.get(&s.joint) else {
                let known: Vec<&str> = self.joint_names.keys().map(|s| s.as_str()).collect();
                return Err(src.error(
                    &p.key("joint"),
                    format!("no KJOINT2 joint named `{}`: {}", s.joint, listed(known)),
                ));
            };
            let time = non_negative(src, &p.key("time"), s.time)? * units.factor(Quantity::Time);
            out.push(Switch {
                joint_name: s.joint.clone(),
                joint,
                time,
                enabled: s.enabled,
            });
        }
        out.sort_by(|a, b| a.time.total_cmp(&b.time));
        Ok(out)
    }
}
