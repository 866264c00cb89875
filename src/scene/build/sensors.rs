//! The scene's `[[sensors]]` (a time, a DOF passing a value, a force reaching one), the
//! time sensors of deck properties, and the check that every sensor a property refers to
//! exists.

use super::checks::{finite, listed, non_negative, positive};
use super::joints::SensorRefs;
use super::Assembly;
use crate::dynamics::SensorCondition;
use crate::io::units::{Quantity, UnitSystem};
use crate::scene::schema::{Scene, SensorSpec};
use crate::scene::{FieldPath, SceneError, Source};
use std::collections::BTreeSet;

impl Assembly {
    /// Adds the scene's sensors, then the deck properties' time sensors the scene does not
    /// define; every sensor in `refs` must then exist.
    pub(super) fn add_sensors(
        &mut self,
        scene: &Scene,
        src: &Source,
        units: &UnitSystem,
        refs: SensorRefs,
    ) -> Result<(), SceneError> {
        let mut ids = BTreeSet::new();
        for (i, s) in scene.sensors.iter().enumerate() {
            let p = FieldPath::root("sensors").index(i);
            if s.id == 0 {
                return Err(src.error(
                    &p.key("id"),
                    "0: expected a sensor id >= 1 (a Radioss sens_ID; 0 means \"no sensor\" in a \
                     property's `sensor`)",
                ));
            }
            if !ids.insert(s.id) {
                return Err(src.error(&p.key("id"), format!("duplicate sensor id {}", s.id)));
            }
            let cond = self.sensor_condition(src, &p, s, units)?;
            self.joints
                .add_sensor(s.id, cond)
                .map_err(|e| src.error(&p, e.to_string()))?;
        }
        for (id, delay) in &refs.deck_delays {
            if ids.insert(*id) {
                self.joints
                    .add_sensor(*id, SensorCondition::Time(*delay))
                    .map_err(|e| src.file_error(e.to_string()))?;
            }
        }
        for (id, p) in &refs.used {
            if !ids.contains(id) {
                let known: Vec<String> = ids.iter().map(|k| k.to_string()).collect();
                return Err(src.error(
                    p,
                    format!("no sensor with id {id} (sensors: {})", listed(known)),
                ));
            }
        }
        Ok(())
    }

    /// The condition of sensor `s` at `p`, in SI: exactly one of `time`, `passes` and
    /// `force_reaches`, the last two on a named joint's DOF.
    fn sensor_condition(
        &self,
        src: &Source,
        p: &FieldPath,
        s: &SensorSpec,
        units: &UnitSystem,
    ) -> Result<SensorCondition, SceneError> {
        match (s.time, s.passes, s.force_reaches) {
            (Some(time), None, None) => {
                if s.joint.is_some() || s.dof.is_some() {
                    return Err(src.error(p, "a time sensor takes no `joint` or `dof`"));
                }
                let time = non_negative(src, &p.key("time"), time)?;
                Ok(SensorCondition::Time(time * units.factor(Quantity::Time)))
            }
            (None, Some(_), None) | (None, None, Some(_)) => {
                let Some(jn) = &s.joint else {
                    return Err(src.error(p, "missing `joint` (the watched joint's name)"));
                };
                let Some(&joint) = self.joint_names.get(jn) else {
                    let known: Vec<&str> = self.joint_names.keys().map(|s| s.as_str()).collect();
                    return Err(src.error(
                        &p.key("joint"),
                        format!("no joint named `{jn}` (joints: {})", listed(known)),
                    ));
                };
                let Some(dof) = s.dof else {
                    return Err(src.error(p, "missing `dof` (dx, dy, dz, rx, ry or rz)"));
                };
                if let Some(v) = s.passes {
                    let v = finite(src, &p.key("passes"), v)?;
                    let q = if dof.is_rotation() {
                        1.0
                    } else {
                        units.factor(Quantity::Length)
                    };
                    return Ok(SensorCondition::DofPasses {
                        joint,
                        dof,
                        value: v * q,
                    });
                }
                let v = positive(src, &p.key("force_reaches"), s.force_reaches.unwrap_or(0.0))?;
                let q = if dof.is_rotation() {
                    Quantity::Moment
                } else {
                    Quantity::Force
                };
                Ok(SensorCondition::ForceReaches {
                    joint,
                    dof,
                    value: v * units.factor(q),
                })
            }
            _ => Err(src.error(
                p,
                "expected exactly one of `time`, `passes` or `force_reaches`",
            )),
        }
    }
}
