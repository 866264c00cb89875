//! The scene's `[[motions]]`: prescribed displacements or velocities of bodies that forces
//! do not move, which become kinematic.

use super::checks::{finite_array, listed};
use super::time::{time_function, TimeFn};
use crate::io::units::{Quantity, UnitSystem};
use crate::rapier::dynamics::RigidBodyType;
use crate::rapier::prelude::{PhysicsWorld, RigidBodyHandle};
use crate::scene::schema::Scene;
use crate::scene::{FieldPath, SceneError, Source};
use std::collections::BTreeMap;

/// How a [`Motion`] prescribes its body's translation.
#[derive(Debug, Clone, PartialEq)]
pub enum MotionKind {
    /// Position `initial + vector·f(t)` \[m\].
    Displacement {
        /// The body's initial position (its origin) \[m\].
        initial: [f64; 3],
    },
    /// Velocity `vector·f(t)` \[m/s\].
    Velocity,
}

/// A prescribed motion of a kinematic body, in SI (scene `[[motions]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// The body's name.
    pub body_name: String,
    /// The body (kinematic, velocity based).
    pub body: RigidBodyHandle,
    /// Displacement or velocity.
    pub kind: MotionKind,
    /// The vector \[m or m/s\].
    pub vector: [f64; 3],
    /// Its time function.
    pub function: TimeFn,
}

impl Motion {
    /// The body's velocity \[m/s\] over the substep from `t` to `t + h` \[s\], the body being at
    /// `position` \[m\] at `t`: for a displacement, the way to the prescribed position at
    /// `t + h` (so that f32 round-off does not accumulate); for a velocity, its value at the
    /// substep's middle.
    pub fn velocity(&self, t: f64, h: f64, position: [f64; 3]) -> [f64; 3] {
        match &self.kind {
            MotionKind::Displacement { initial } => {
                let s = self.function.value(t + h);
                std::array::from_fn(|k| (initial[k] + self.vector[k] * s - position[k]) / h)
            }
            MotionKind::Velocity => {
                let s = self.function.value(t + 0.5 * h);
                self.vector.map(|v| v * s)
            }
        }
    }
}

/// The scene's motions, in SI: each on a body that is not dynamic (not `"world"`), one per
/// body, which becomes kinematic (velocity based).
pub(super) fn motions(
    scene: &Scene,
    src: &Source,
    units: &UnitSystem,
    body_names: &BTreeMap<String, RigidBodyHandle>,
    world: &mut PhysicsWorld,
) -> Result<Vec<Motion>, SceneError> {
    let l = units.factor(Quantity::Length);
    let t = units.factor(Quantity::Time);
    let mut out: Vec<Motion> = Vec::new();
    for (i, m) in scene.motions.iter().enumerate() {
        let p = FieldPath::root("motions").index(i);
        let Some(&body) = body_names.get(&m.body) else {
            let known: Vec<&str> = body_names.keys().map(|s| s.as_str()).collect();
            let why = if m.body == "world" {
                "`world` is the ground and does not move: give the moving body a name \
                 (a body of kind = \"fixed\")"
                    .to_string()
            } else {
                format!("no body named `{}` (bodies: {})", m.body, listed(known))
            };
            return Err(src.error(&p.key("body"), why));
        };
        if world.bodies[body].is_dynamic() {
            return Err(src.error(
                &p.key("body"),
                format!(
                    "body `{}` is dynamic: a prescribed motion moves a body that forces do not \
                     (a scene body of kind = \"fixed\", or a URDF robot's fixed root link)",
                    m.body
                ),
            ));
        }
        if out.iter().any(|o| o.body == body) {
            return Err(src.error(
                &p.key("body"),
                format!(
                    "body `{}` has a motion already: one motion per body",
                    m.body
                ),
            ));
        }
        let (kind, vector) = match (m.displacement, m.velocity) {
            (Some(d), None) => {
                let d = finite_array(src, &p.key("displacement"), d)?.map(|x| x * l);
                let x = world.bodies[body].translation();
                let initial = [x.x, x.y, x.z].map(f64::from);
                (MotionKind::Displacement { initial }, d)
            }
            (None, Some(v)) => {
                let v = finite_array(src, &p.key("velocity"), v)?.map(|x| x * l / t);
                (MotionKind::Velocity, v)
            }
            _ => return Err(src.error(&p, "expected exactly one of `displacement` and `velocity`")),
        };
        let function = time_function(src, &p.key("function"), &m.function, t)?;
        world.bodies[body].set_body_type(RigidBodyType::KinematicVelocityBased, true);
        out.push(Motion {
            body_name: m.body.clone(),
            body,
            kind,
            vector,
            function,
        });
    }
    Ok(out)
}
