//! The joint set as a rapier user handles it: generational handles, removal (by the user, and
//! of the joints of a body removed from rapier), and changes through `get_mut`.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;
use rapier_kjoint::dynamics::EventSource;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, FrictionStatus, JointType, KjointBuilder, KjointHandle, KjointProperty, KjointSet,
    SimError,
};

const LINK: Real = 0.5;

/// A chain of `n` rods hanging from the ground on spherical joints (`Kn = 1e6`), rod `i`
/// centred at `y = −(i + ½)·LINK`.
fn chain(
    n: usize,
) -> (
    PhysicsWorld,
    KjointSet,
    Vec<RigidBodyHandle>,
    Vec<KjointHandle>,
) {
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    let mut set = common::joints(8);
    let up = Vector::new(0.0, LINK / 2.0, 0.0);
    let (mut rods, mut joints) = (Vec::new(), Vec::new());
    let mut parent = ground;
    for i in 0..n {
        let y = -(i as Real + 0.5) * LINK;
        let rod = common::cuboid(
            &mut w,
            1.0,
            Vector::new(0.02, LINK / 2.0, 0.02),
            Vector::new(0.0, y, 0.0),
        );
        let prop = KjointProperty::new(JointType::Spherical).with_kn(1e6);
        let anchor1 = if i == 0 { Vector::ZERO } else { -up };
        joints.push(common::add(&mut set, &w, prop, parent, rod, |b| {
            b.local_anchor1(anchor1).local_anchor2(up)
        }));
        rods.push(rod);
        parent = rod;
    }
    (w, set, rods, joints)
}

fn gap(set: &KjointSet, h: KjointHandle) -> f64 {
    let s = set.get(h).unwrap().state().unwrap();
    (0..3)
        .map(|i| (s.anchor2[i] - s.anchor1[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn a_body_removed_from_rapier_takes_its_joints_out_of_the_set() {
    let (mut w, mut set, rods, j) = chain(4);
    // swing it a little so that the joints carry energy
    w.bodies[rods[3]].set_linvel(Vector::new(1.0, 0.0, 0.0), true);
    for _ in 0..10 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    set.drain_events();
    let before: f64 = [j[1], j[2]]
        .iter()
        .map(|h| set.get(*h).unwrap().energy().elastic)
        .sum();
    assert!(before > 0.0);
    // the second rod goes: the joints on both of its ends go with it
    w.remove_body(rods[1]);
    for _ in 0..30 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    assert_eq!(set.len(), 2);
    for h in [j[1], j[2]] {
        assert!(set.get(h).is_none() && !set.contains(h) && set.remove(h).is_none());
    }
    let events = set.drain_events();
    let detached: Vec<KjointHandle> = events
        .iter()
        .filter_map(|e| match e.source {
            EventSource::Joint { handle, .. } => Some(handle),
            EventSource::Sensor(_) => None,
        })
        .collect();
    assert_eq!(detached, [j[1], j[2]], "{events:?}");
    assert_eq!(set.removed_energy().elastic, before);
    // the others keep their handles and keep working: the first rod still hangs from the
    // ground, the last two (now falling freely) stay together
    assert_eq!(set.iter().map(|(h, _)| h).collect::<Vec<_>>(), [j[0], j[3]]);
    assert!(gap(&set, j[0]) < 1e-3 && gap(&set, j[3]) < 1e-3);
    assert!((w.bodies[rods[0]].translation().y + LINK / 2.0).abs() < 0.05);
    assert!(
        w.bodies[rods[2]].translation().y < -2.0 * LINK - 1.0,
        "falling"
    );
    assert_eq!(set.attached_joints(rods[3]).next().unwrap().0, j[3]);
    assert_eq!(set.joints_between(rods[3], rods[2]).count(), 1);
}

#[test]
fn a_removed_joint_leaves_its_bodies_and_its_handle_finds_nothing() {
    let (mut w, mut set, rods, j) = chain(2);
    for _ in 0..5 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    let removed = set.remove(j[1]).unwrap();
    assert_eq!((removed.body1(), removed.body2()), (rods[0], rods[1]));
    assert!(removed.state().is_some());
    assert_eq!(set.removed_energy(), removed.energy());
    // a joint inserted in its place gets another handle; the old one stays dead
    let again = set
        .insert(
            KjointBuilder::new(removed.property().clone())
                .local_anchor1(Vector::new(0.0, -LINK / 2.0, 0.0))
                .local_anchor2(Vector::new(0.0, LINK / 2.0, 0.0)),
            rods[0],
            rods[1],
            &w.bodies,
        )
        .unwrap();
    assert_ne!(again, j[1]);
    assert!(set.get(j[1]).is_none());
    assert_eq!(set.get(again).unwrap().name, "joint3");
    // a stale handle is refused with a typed error, not a panic
    assert!(matches!(
        set.switch_flex_joint(j[1]),
        Err(SimError::InvalidArgument { .. })
    ));
    assert!(set.stable_dt(j[1], &w.bodies).is_none());
    assert!(set.get_mut(KjointHandle::invalid()).is_none());
    for _ in 0..5 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    // the last rod hangs from the first again
    assert!(gap(&set, again) < 1e-3, "{}", gap(&set, again));
}

#[test]
fn a_property_changed_through_get_mut_takes_effect_at_the_next_substep() {
    let (mut w, mut set, _, j) = chain(1);
    set.step(&mut w, 1.0 / 60.0).unwrap();
    let k0 = set.get(j[0]).unwrap().blocked_stiffness().unwrap();
    assert_eq!(k0.translational, 1e6);
    let prop = set.get(j[0]).unwrap().property().clone().with_kn(4e6);
    let joint = set.get_mut(j[0]).unwrap();
    joint.name = "renamed".into();
    joint.set_property(prop).unwrap();
    set.step(&mut w, 1.0 / 60.0).unwrap();
    let k1 = set.get(j[0]).unwrap().blocked_stiffness().unwrap();
    assert_eq!(k1.translational, 4e6);
    assert_eq!(k1.rotational, 4.0 * k0.rotational);
    assert_eq!(set.find("renamed"), Some(j[0]));
}

#[test]
fn joints_of_equal_properties_share_one_copy_and_a_change_to_one_leaves_the_others() {
    let (mut w, mut set, _, j) = chain(3);
    let prop = |set: &KjointSet, h: KjointHandle| set.get(h).unwrap().property() as *const _;
    // one copy of the three equal properties (what the substep reads for every joint)
    assert!(std::ptr::eq(prop(&set, j[0]), prop(&set, j[1])));
    assert!(std::ptr::eq(prop(&set, j[1]), prop(&set, j[2])));
    let stiffer = set.get(j[1]).unwrap().property().clone().with_kn(4e6);
    set.get_mut(j[1]).unwrap().set_property(stiffer).unwrap();
    assert!(!std::ptr::eq(prop(&set, j[0]), prop(&set, j[1])));
    set.step(&mut w, 1.0 / 60.0).unwrap();
    let kn = |h: KjointHandle| {
        set.get(h)
            .unwrap()
            .blocked_stiffness()
            .unwrap()
            .translational
    };
    assert_eq!((kn(j[0]), kn(j[1]), kn(j[2])), (1e6, 4e6, 1e6));
    assert_eq!(set.get(j[2]).unwrap().property().kn, 1e6);
}

/// Friction storage is each joint's own (docs/kjoint2.md §4.4), also when joints share one
/// copy of their property: two equal sliders (friction spring Kf = 1e4 N/m, friction force
/// FF = 5 N, no gravity), one pushed along its axis with 20 N, which slips at 5 N, the other
/// with 2 N, which sticks (its friction spring ringing about 2 N, within 0.4 mm of where it
/// started).
#[test]
fn joints_sharing_a_property_keep_their_own_friction_state() {
    let (mut w, ground) = common::world(Vector::ZERO);
    let slider = KjointProperty::new(JointType::Translational)
        .with_kn(1e6)
        .with_dof(Dof::Dx, DofLaw::default().with_friction(1e4, 5.0));
    let mut set = KjointSet::new();
    let mut bodies = Vec::new();
    let mut handles = Vec::new();
    for (z, push) in [(0.0, 20.0), (1.0, 2.0)] {
        let (b, _) = w.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.0, z)),
            ColliderBuilder::ball(0.1).mass(1.0),
        );
        let h = set
            .insert(
                KjointBuilder::new(slider.clone()).local_anchor1(Vector::new(0.0, 0.0, z)),
                ground,
                b,
                &w.bodies,
            )
            .unwrap();
        w.bodies[b].add_force(Vector::new(push, 0.0, 0.0), true);
        bodies.push(b);
        handles.push(h);
    }
    let (a, b) = (set.get(handles[0]).unwrap(), set.get(handles[1]).unwrap());
    assert!(
        std::ptr::eq(a.property(), b.property()),
        "one copy of the property"
    );
    for _ in 0..60 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    let state = |h: KjointHandle| set.get(h).unwrap().state().unwrap().clone();
    let (pushed, held) = (state(handles[0]), state(handles[1]));
    // internal-force convention: the slider pulled along +x carries a negative force
    assert_eq!(pushed.status[Dof::Dx].friction, FrictionStatus::Slip);
    assert!((pushed.parts[Dof::Dx].friction.abs() - 5.0).abs() < 1e-9);
    assert_eq!(held.status[Dof::Dx].friction, FrictionStatus::Stick);
    // the held one sticks: its friction spring rings about 2 N (lightly damped, Cr = 0.05),
    // between 0 and 4 N, below the cap
    let s_held = held.parts[Dof::Dx].friction.abs();
    assert!(
        s_held > 0.0 && s_held < 4.0 + 1e-6,
        "{:?}",
        held.parts[Dof::Dx]
    );
    // the pushed body accelerates at (20 − 5)/1 m/s² for 1 s, the held one stays put
    let x = |b: RigidBodyHandle| w.bodies[b].translation().x as f64;
    assert!((x(bodies[0]) - 7.5).abs() < 0.2, "{}", x(bodies[0]));
    assert!(x(bodies[1]).abs() < 1e-3, "{}", x(bodies[1]));
}

/// `step` sets rapier's `dt` to the substep and its iterations to the settings' for its
/// substeps, and gives both back: a plain `world.step()` after a frame advanced 1/240 s
/// with one iteration where the user had set 1/60 s and 4 (a user trial).
#[test]
fn step_gives_back_rapier_s_integration_parameters() {
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81, 0.0),
        ..Default::default()
    };
    world.integration_parameters.dt = (1.0 / 60.0) as Real;
    world.integration_parameters.num_solver_iterations = 4;
    let mut joints = KjointSet::new();
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let (rod, _) = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.1));
    joints
        .insert(
            KjointBuilder::new(KjointProperty::new(JointType::Spherical)),
            ground,
            rod,
            &world.bodies,
        )
        .unwrap();
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(5.0, 0.0, 0.0)),
        ColliderBuilder::ball(0.1),
    );
    joints.step(&mut world, 1.0 / 60.0).unwrap();
    assert_eq!(world.integration_parameters.dt, (1.0 / 60.0) as Real);
    assert_eq!(world.integration_parameters.num_solver_iterations, 4);
    // the free ball falls for one more frame of 1/60 s in rapier's own step
    let v0 = world.bodies[ball].linvel().y as f64;
    world.step();
    let dv = world.bodies[ball].linvel().y as f64 - v0;
    assert!(
        (dv + 9.81 / 60.0).abs() < 1e-5,
        "Δv = {dv} m/s in one plain step"
    );
}

/// `step_with_events` passes rapier's event handler to each of rapier's substeps: a ball on
/// a KJOINT2 pendulum swinging into a wall reports its collision and its contact forces, and
/// moves as under `step` (the same bits). Without it the events needed the hand-written
/// loop of `apply_substep` and `world.step_with_events` (a user trial).
#[test]
fn step_with_events_reports_rapier_s_collisions() {
    let world_with = || {
        let mut world = PhysicsWorld {
            gravity: Vector::new(0.0, -9.81, 0.0),
            ..Default::default()
        };
        let mut joints = KjointSet::new();
        let ground = world.insert_body(RigidBodyBuilder::fixed());
        // the wall below the pivot, the ball swinging down into it from the horizontal
        world.insert_collider(
            ColliderBuilder::cuboid(0.05, 0.5, 0.5).translation(Vector::new(0.15, -1.0, 0.0)),
            Some(ground),
        );
        let (ball, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(1.0, 0.0, 0.0)),
            ColliderBuilder::ball(0.1)
                .mass(1.0)
                .active_events(ActiveEvents::COLLISION_EVENTS | ActiveEvents::CONTACT_FORCE_EVENTS),
        );
        let j = KjointBuilder::new(KjointProperty::new(JointType::Spherical))
            .local_anchor2(Vector::new(-1.0, 0.0, 0.0));
        joints.insert(j, ground, ball, &world.bodies).unwrap();
        (world, joints, ball)
    };
    let (mut w1, mut j1, ball) = world_with();
    let (mut w2, mut j2, _) = world_with();
    let (collisions, collision_rx) = std::sync::mpsc::channel();
    let (forces, force_rx) = std::sync::mpsc::channel();
    let (tears, _) = std::sync::mpsc::channel();
    let events = ChannelEventCollector::new(collisions, forces, tears);
    for _ in 0..60 {
        j1.step_with_events(&mut w1, 1.0 / 60.0, &(), &events)
            .unwrap();
        j2.step(&mut w2, 1.0 / 60.0).unwrap();
    }
    assert_eq!(w1.bodies[ball].translation(), w2.bodies[ball].translation());
    let started = collision_rx.try_iter().filter(|e| e.started()).count();
    assert!(started >= 1, "no collision reported");
    let peak = force_rx
        .try_iter()
        .map(|e| e.total_force_magnitude as f64)
        .fold(0.0, f64::max);
    assert!(peak > 1.0, "contact force {peak} N");
}
