//! Dynamic bodies that start deep inside a fixed or kinematic body they collide with (a
//! robot placed into the ground). rapier's contacts push them out within the first
//! substeps, as fast as they can, and the jointed bodies are thrown against their joints:
//! the Unitree Go1 of MuJoCo Menagerie placed on its side with its trunk 0.2 m inside a
//! ground box ended its run at 0.0375 s ("simulation unstable … a blocked rotation of
//! 0.701 rad", with remedies of substeps and loads), and the scene said nothing of where it
//! stood ([`BuiltScene::warnings`](super::BuiltScene)).

use crate::rapier::parry::query;
use crate::rapier::prelude::*;

/// The depth beyond which a dynamic collider starting inside a fixed or kinematic one is
/// warned of \[m\]: the same Go1 standing 1 cm inside the ground lands with its knees 7.6 mm
/// apart, as dropped onto it; 0.1 m inside, 29 mm; 0.2 m, the run ends.
pub(crate) const START_OVERLAP: f64 = 0.01;

/// Bodies named in a warning before "and N more".
const NAMED: usize = 3;

/// Whether a rapier joint between bodies `a` and `b` leaves their contacts out (a joint of
/// the world's with `contacts_enabled = false`, or the contact filter a [`crate::KjointSet`]
/// keeps for one of its joints: a robot's first link overlapping the mount it is hinged on).
fn contacts_off(
    world: &PhysicsWorld,
    a: Option<RigidBodyHandle>,
    b: Option<RigidBodyHandle>,
) -> bool {
    let (Some(a), Some(b)) = (a, b) else {
        return false;
    };
    (world.impulse_joints.joints_between(a, b)).any(|(_, j)| !j.data.contacts_enabled)
}

/// One warning per fixed or kinematic body that dynamic bodies start more than
/// [`START_OVERLAP`] inside (colliders that collide with each other, by their groups and
/// their joints' contacts; the set's contact filters are to be in the world),
/// naming the deepest of them and its depth. `names`: the bodies' names (a body without
/// one is named by its index).
pub(super) fn start_overlap_warnings(
    world: &PhysicsWorld,
    names: &[(String, RigidBodyHandle)],
) -> Vec<String> {
    let name_of = |h: Option<RigidBodyHandle>| match h {
        Some(h) => names.iter().find(|(_, n)| *n == h).map_or_else(
            || format!("#{}", h.into_raw_parts().0),
            |(n, _)| format!("`{n}`"),
        ),
        None => "a collider of no body".to_string(),
    };
    let dynamic = |c: &Collider| {
        c.parent()
            .and_then(|b| world.bodies.get(b))
            .is_some_and(|b| b.is_dynamic())
    };
    let grounds: Vec<&Collider> = (world.colliders.iter())
        .map(|(_, c)| c)
        .filter(|c| !dynamic(c) && c.collision_groups() != InteractionGroups::none())
        .collect();
    let movers: Vec<&Collider> = (world.colliders.iter())
        .map(|(_, c)| c)
        .filter(|c| dynamic(c))
        .collect();
    let mut warnings = Vec::new();
    for g in grounds {
        let aabb = g.compute_aabb();
        // the deepest overlap of each dynamic body, deepest first
        let mut deep: Vec<(Option<RigidBodyHandle>, f64)> = Vec::new();
        for m in &movers {
            if !g.collision_groups().test(m.collision_groups())
                || !aabb.intersects(&m.compute_aabb())
                || contacts_off(world, g.parent(), m.parent())
            {
                continue;
            }
            let Ok(Some(c)) = query::contact(g.position(), g.shape(), m.position(), m.shape(), 0.0)
            else {
                continue;
            };
            let depth = -(c.dist as f64);
            if depth <= START_OVERLAP {
                continue;
            }
            match deep.iter_mut().find(|(b, _)| *b == m.parent()) {
                Some((_, d)) => *d = d.max(depth),
                None => deep.push((m.parent(), depth)),
            }
        }
        if deep.is_empty() {
            continue;
        }
        deep.sort_by(|a, b| b.1.total_cmp(&a.1));
        let mut listed: Vec<String> = (deep.iter().take(NAMED))
            .map(|(b, d)| format!("{} ({} m)", name_of(*b), crate::figure::format_figure(*d)))
            .collect();
        if deep.len() > NAMED {
            listed.push(format!("and {} more", deep.len() - NAMED));
        }
        let (what, start) = if deep.len() == 1 {
            ("body", "starts")
        } else {
            ("bodies", "start")
        };
        warnings.push(format!(
            "{what} {} {start} inside {}, which {} with: rapier's contacts push them \
             out at once and throw them against their joints (a robot placed into the ground \
             can tear apart in the first substeps, whatever the substep); place them above it \
             (a robot's `position`, a body's `translation`)",
            listed.join(", "),
            name_of(g.parent()),
            if deep.len() == 1 {
                "it collides"
            } else {
                "they collide"
            },
        ));
    }
    warnings
}
