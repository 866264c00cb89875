//! The scene's `[[loads]]`: forces and torques on named bodies, `vector · function(t)`.

use super::checks::{finite_array, listed};
use super::time::{time_function, TimeFn};
use crate::io::units::{Quantity, UnitSystem};
use crate::rapier::prelude::RigidBodyHandle;
use crate::scene::schema::Scene;
use crate::scene::{FieldPath, SceneError, Source};
use std::collections::BTreeMap;

/// A force or torque on a body, `vector · function(t)`, world axes, at the centre of mass.
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    /// The body's name.
    pub body_name: String,
    /// The body.
    pub body: RigidBodyHandle,
    /// `true` for a torque [N·m], `false` for a force \[N\].
    pub torque: bool,
    /// The vector [N or N·m].
    pub vector: [f64; 3],
    /// Its time function.
    pub function: TimeFn,
}

impl Load {
    /// The load vector at time `t` \[s\] [N or N·m].
    pub fn at(&self, t: f64) -> [f64; 3] {
        let s = self.function.value(t);
        self.vector.map(|v| v * s)
    }
}

/// The scene's loads in SI, on the bodies of `body_names`.
pub(super) fn loads(
    scene: &Scene,
    src: &Source,
    units: &UnitSystem,
    body_names: &BTreeMap<String, RigidBodyHandle>,
) -> Result<Vec<Load>, SceneError> {
    let mut out = Vec::new();
    for (i, ld) in scene.loads.iter().enumerate() {
        let p = FieldPath::root("loads").index(i);
        let Some(&body) = body_names.get(&ld.body) else {
            // (robots' links under their prefixed names among them: `left/hand`)
            let known: Vec<&str> = body_names.keys().map(|s| s.as_str()).collect();
            return Err(src.error(
                &p.key("body"),
                format!("no body named `{}` (bodies: {})", ld.body, listed(known)),
            ));
        };
        let (torque, v, key, q) = match (ld.force, ld.torque) {
            (Some(f), None) => (false, f, "force", Quantity::Force),
            (None, Some(m)) => (true, m, "torque", Quantity::Moment),
            _ => return Err(src.error(&p, "expected exactly one of `force` and `torque`")),
        };
        let v = finite_array(src, &p.key(key), v)?.map(|x| x * units.factor(q));
        let t = units.factor(Quantity::Time);
        let function = time_function(src, &p.key("function"), &ld.function, t)?;
        out.push(Load {
            body_name: ld.body.clone(),
            body,
            torque,
            vector: v,
            function,
        });
    }
    Ok(out)
}
