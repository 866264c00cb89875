//! The scene's `[[bodies]]`: rigid bodies with one collider each (shape, mass or density),
//! and the bodies' names.

use super::checks::{finite_array, listed, positive, rotation, vec3};
use super::Assembly;
use crate::io::units::{Quantity, UnitSystem};
use crate::rapier::prelude::*;
use crate::scene::schema::{BodyKind, BodySpec, Scene, ShapeSpec};
use crate::scene::{FieldPath, SceneError, Source};

impl Assembly {
    /// Adds the scene's bodies to the world, under their names.
    pub(super) fn add_bodies(
        &mut self,
        scene: &Scene,
        src: &Source,
        units: &UnitSystem,
    ) -> Result<(), SceneError> {
        let l = units.factor(Quantity::Length);
        let t = units.factor(Quantity::Time);
        for (i, b) in scene.bodies.iter().enumerate() {
            let p = FieldPath::root("bodies").index(i);
            if b.name == "world" || b.name.is_empty() {
                return Err(src.error(
                    &p.key("name"),
                    format!("`{}` is reserved: give the body another name", b.name),
                ));
            }
            if self.body_names.contains_key(&b.name) {
                return Err(src.error(&p.key("name"), format!("duplicate body name `{}`", b.name)));
            }
            let tr = finite_array(src, &p.key("translation"), b.translation)?;
            let v = finite_array(src, &p.key("linvel"), b.linvel)?;
            let w = finite_array(src, &p.key("angvel"), b.angvel)?;
            let rot = match &b.rotation {
                Some(r) => rotation(src, &p.key("rotation"), r)?,
                None => Rotation::IDENTITY,
            };
            let collider = body_collider(src, &p, b, units)?;
            let rb = match b.kind {
                BodyKind::Dynamic => RigidBodyBuilder::dynamic(),
                BodyKind::Fixed => RigidBodyBuilder::fixed(),
            }
            .pose(Pose::from_parts(vec3(tr, l), rot))
            .linvel(vec3(v, l / t))
            .angvel(vec3(w, 1.0 / t))
            .can_sleep(false);
            let (h, _) = self.world.insert(rb, collider);
            self.body_names.insert(b.name.clone(), h);
            self.bodies.push((b.name.clone(), h));
        }
        Ok(())
    }

    /// The body named `name` (at `path` in the scene); `"world"` is the fixed ground, added
    /// on its first use.
    pub(super) fn body(
        &mut self,
        src: &Source,
        path: &FieldPath,
        name: &str,
    ) -> Result<RigidBodyHandle, SceneError> {
        if name == "world" {
            return Ok(*self.ground.get_or_insert_with(|| {
                let h = self.world.insert_body(RigidBodyBuilder::fixed());
                self.bodies.insert(0, ("world".to_string(), h));
                h
            }));
        }
        self.body_names.get(name).copied().ok_or_else(|| {
            let known: Vec<&str> = self.body_names.keys().map(|s| s.as_str()).collect();
            src.error(
                path,
                format!(
                    "no body named `{name}` (bodies: {}; or \"world\")",
                    listed(known)
                ),
            )
        })
    }
}

/// The collider of a scene body: its shape, and its mass or density (1000 kg/m³ when
/// neither is given), with a mass and inertia rapier can use.
fn body_collider(
    src: &Source,
    path: &FieldPath,
    b: &BodySpec,
    u: &UnitSystem,
) -> Result<Collider, SceneError> {
    let l = u.factor(Quantity::Length);
    let sp = path.key("shape");
    let c = match &b.shape {
        ShapeSpec::Ball { radius } => {
            ColliderBuilder::ball((positive(src, &sp.key("radius"), *radius)? * l) as _)
        }
        ShapeSpec::Cuboid { half_extents } => {
            let he = finite_array(src, &sp.key("half_extents"), *half_extents)?;
            for (i, v) in he.iter().enumerate() {
                positive(src, &sp.key("half_extents").index(i), *v)?;
            }
            ColliderBuilder::cuboid((he[0] * l) as _, (he[1] * l) as _, (he[2] * l) as _)
        }
        ShapeSpec::Capsule {
            half_height,
            radius,
        }
        | ShapeSpec::Cylinder {
            half_height,
            radius,
        } => {
            let h = (positive(src, &sp.key("half_height"), *half_height)? * l) as _;
            let r = (positive(src, &sp.key("radius"), *radius)? * l) as _;
            if matches!(b.shape, ShapeSpec::Capsule { .. }) {
                ColliderBuilder::capsule_y(h, r)
            } else {
                ColliderBuilder::cylinder(h, r)
            }
        }
    };
    let c = match (b.mass, b.density) {
        (Some(_), Some(_)) => {
            return Err(src.error(&path.key("density"), "give `mass` or `density`, not both"))
        }
        (Some(m), None) => c.mass((positive(src, &path.key("mass"), m)? * u.mass) as _),
        (None, Some(d)) => {
            c.density((positive(src, &path.key("density"), d)? * u.mass / (l * l * l)) as _)
        }
        (None, None) => c.density(1000.0),
    };
    let c = if b.collide {
        c
    } else {
        c.collision_groups(InteractionGroups::none())
    };
    let collider = c.build();
    let mp = collider.mass_properties();
    let ok = mp.mass().is_finite()
        && mp.mass() > 0.0
        && mp.principal_inertia().is_finite()
        && mp.principal_inertia().min_element() > 0.0;
    if !ok {
        return Err(src.error(
            path,
            format!(
                "mass {} kg and inertia {:?} kg·m² are out of range (check the shape, mass and \
                 density)",
                mp.mass(),
                mp.principal_inertia()
            ),
        ));
    }
    Ok(collider)
}
