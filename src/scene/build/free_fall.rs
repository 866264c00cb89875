//! The parts of a scene that nothing can stop falling: bodies that no joint links to a fixed
//! or kinematic body, under gravity and without a load, in a scene where no fixed or
//! kinematic body collides. A scene body touches nothing unless it says `collide = true`,
//! so a floating-base robot over a ground body written without it fell 44 m in 3 s, every
//! joint carrying 0.1 N, and the run said nothing ([`BuiltScene::warnings`](super::BuiltScene)).

use super::loads::Load;
use crate::rapier::geometry::InteractionGroups;
use crate::rapier::prelude::*;
use crate::KjointSet;
use std::collections::HashMap;

/// Bodies named in a warning before "and N more".
const NAMED: usize = 3;

/// One warning per part of the scene that falls freely: its bodies (KJOINT2 joints and
/// rapier's impulse joints linking them) hold no fixed or kinematic body, at least one of
/// them feels gravity, none carries a load, and no fixed or kinematic body of the scene
/// collides. `names`: the bodies' names (a body without one is named by its index).
pub(super) fn free_fall_warnings(
    world: &PhysicsWorld,
    joints: &KjointSet,
    loads: &[Load],
    names: &[(String, RigidBodyHandle)],
) -> Vec<String> {
    if world.gravity == Vector::ZERO || ground_collides(world) {
        return Vec::new();
    }
    let index: HashMap<RigidBodyHandle, usize> = world
        .bodies
        .iter()
        .enumerate()
        .map(|(i, (h, _))| (h, i))
        .collect();
    let mut parent: Vec<usize> = (0..index.len()).collect();
    let links = joints.iter().map(|(_, j)| (j.body1(), j.body2())).chain(
        world
            .impulse_joints
            .iter()
            .map(|(_, j)| (j.body1(), j.body2())),
    );
    for (a, b) in links {
        if let (Some(&a), Some(&b)) = (index.get(&a), index.get(&b)) {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            parent[ra] = rb;
        }
    }
    // per part (its root): whether it is held, loaded or feels gravity, and its bodies
    #[derive(Default)]
    struct Part {
        held: bool,
        weighed: bool,
        bodies: Vec<RigidBodyHandle>,
    }
    let loaded: Vec<RigidBodyHandle> = loads.iter().map(|l| l.body).collect();
    let mut parts: Vec<(usize, Part)> = Vec::new();
    for (h, b) in world.bodies.iter() {
        let r = root(&mut parent, index[&h]);
        let k = match parts.iter().position(|(root, _)| *root == r) {
            Some(k) => k,
            None => {
                parts.push((r, Part::default()));
                parts.len() - 1
            }
        };
        let part = &mut parts[k].1;
        part.held |= !b.is_dynamic() || loaded.contains(&h);
        part.weighed |= b.gravity_scale() != 0.0;
        part.bodies.push(h);
    }
    let name_of = |h: RigidBodyHandle| {
        names
            .iter()
            .find(|(_, n)| *n == h)
            .map_or_else(|| format!("#{}", index[&h]), |(n, _)| n.clone())
    };
    parts
        .into_iter()
        .filter(|(_, p)| !p.held && p.weighed)
        .map(|(_, p)| {
            let mut listed: Vec<String> = (p.bodies.iter().take(NAMED))
                .map(|h| format!("`{}`", name_of(*h)))
                .collect();
            if p.bodies.len() > NAMED {
                listed.push(format!("and {} more", p.bodies.len() - NAMED));
            }
            let (what, fall, them, they) = if p.bodies.len() == 1 {
                ("body", "falls", "it", "it")
            } else {
                ("bodies", "fall", "them", "they")
            };
            format!(
                "{what} {} {fall} freely under gravity: no joint holds {them} to a fixed or \
                 kinematic body, and nothing fixed in the scene collides (a scene body touches \
                 nothing unless it says `collide = true`: set it on the ground or table {they} \
                 should rest on)",
                listed.join(", ")
            )
        })
        .collect()
}

/// Whether a fixed or kinematic body (or a collider of no body) collides with anything.
fn ground_collides(world: &PhysicsWorld) -> bool {
    world.colliders.iter().any(|(_, c)| {
        let fixed = c
            .parent()
            .and_then(|b| world.bodies.get(b))
            .is_none_or(|b| !b.is_dynamic());
        fixed && c.collision_groups() != InteractionGroups::none()
    })
}

/// The root of `i` in the union-find forest `parent` (paths halved on the way).
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}
