//! Shared scene helpers for the integration tests.
#![allow(dead_code)]

pub mod cli;
pub mod fuzz;
pub mod robot;
pub mod scene;

use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{KjointBuilder, KjointHandle, KjointProperty, KjointSet, SubstepSettings};

/// A world with the given gravity and a fixed ground body at the origin.
pub fn world(gravity: Vector) -> (PhysicsWorld, RigidBodyHandle) {
    let mut w = PhysicsWorld {
        gravity,
        ..Default::default()
    };
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    (w, ground)
}

/// A dynamic ball of mass `m` and radius `r` at `pos`, which never sleeps.
pub fn ball(w: &mut PhysicsWorld, m: Real, r: Real, pos: Vector) -> RigidBodyHandle {
    let (h, _) = w.insert(
        RigidBodyBuilder::dynamic()
            .translation(pos)
            .can_sleep(false),
        ColliderBuilder::ball(r).mass(m),
    );
    h
}

/// A dynamic box of mass `m` with half extents `he` at `pos`, never sleeping.
pub fn cuboid(w: &mut PhysicsWorld, m: Real, he: Vector, pos: Vector) -> RigidBodyHandle {
    let (h, _) = w.insert(
        RigidBodyBuilder::dynamic()
            .translation(pos)
            .can_sleep(false),
        ColliderBuilder::cuboid(he.x, he.y, he.z).mass(m),
    );
    h
}

/// A joint set with `n` substeps.
pub fn joints(n: usize) -> KjointSet {
    KjointSet::with_settings(SubstepSettings {
        substeps: n,
        ..Default::default()
    })
}

/// A builder of the rod hinges of the tests: the joint's x along world z (the hinge axis),
/// anchor 2 at the end of a 1 m rod whose centre is at (0.5, 0, 0), `(−0.5, 0, 0)` in the
/// rod's frame (anchor 1 at the world origin).
pub fn rod_end_hinge_about_z(property: KjointProperty) -> KjointBuilder {
    KjointBuilder::new(property)
        .world_frame1(Rotation::from_rotation_arc(Vector::X, Vector::Z))
        .local_anchor2(Vector::new(-0.5, 0.0, 0.0))
}

/// Inserts a joint and unwraps.
pub fn add(
    set: &mut KjointSet,
    w: &PhysicsWorld,
    prop: KjointProperty,
    b1: RigidBodyHandle,
    b2: RigidBodyHandle,
    f: impl FnOnce(KjointBuilder) -> KjointBuilder,
) -> KjointHandle {
    set.insert(f(KjointBuilder::new(prop)), b1, b2, &w.bodies)
        .expect("valid joint")
}

/// A dynamic body without collider, with mass `m` and principal inertia `inertia` at its
/// origin, placed at `pos`, never sleeping.
pub fn point_body(w: &mut PhysicsWorld, m: Real, inertia: Vector, pos: Vector) -> RigidBodyHandle {
    w.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(pos)
            .can_sleep(false)
            .additional_mass_properties(MassProperties::new(Vector::ZERO, m, inertia)),
    )
}

/// Kinetic + potential energy of the bodies plus the joints' stored elastic energy [J].
pub fn total_energy(w: &PhysicsWorld, set: &KjointSet) -> f64 {
    rapier_kjoint::dynamics::energy::mechanical_energy(&w.bodies, w.gravity)
        + set.iter().map(|(_, j)| j.energy().stored()).sum::<f64>()
}

/// Dissipated work of all joints [J].
pub fn dissipated(set: &KjointSet) -> f64 {
    set.iter().map(|(_, j)| j.energy().dissipated()).sum()
}

/// A joint's anchor gap \[m\]: the anchors' separation along its blocked translations (a
/// prismatic joint's travel along its axis is its motion, not a gap). NaN when its state is.
pub fn anchor_gap(j: &rapier_kjoint::Kjoint) -> f64 {
    let s = j.state().unwrap();
    rapier_kjoint::Dof::ALL[..3]
        .iter()
        .filter(|d| !j.property().joint_type.is_free(**d))
        .map(|d| s.q[d.index()].powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The magnitude of the force a joint transmitted over its last substep \[N\].
pub fn applied_force(j: &rapier_kjoint::Kjoint) -> f64 {
    let a = &j.state().unwrap().applied;
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The distance between the joint's anchors in the world \[m\].
pub fn world_gap(j: &rapier_kjoint::Kjoint) -> f64 {
    let s = j.state().unwrap();
    (0..3)
        .map(|i| (s.anchor1[i] - s.anchor2[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// A 1 kg ball (radius 0.1 m) hanging 1 m below the ground under gravity −y, and what
/// `set.insert` answers for a joint named `hinge` of property `prop` between them,
/// anchored at the origin: the world, the ground, the ball and that answer.
pub fn hanging_ball(
    set: &mut KjointSet,
    prop: KjointProperty,
) -> (
    PhysicsWorld,
    RigidBodyHandle,
    RigidBodyHandle,
    Result<KjointHandle, rapier_kjoint::SimError>,
) {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let ball = ball(&mut w, 1.0, 0.1, Vector::new(0.0, -1.0, 0.0));
    let builder = KjointBuilder::new(prop)
        .name("hinge")
        .local_anchor2(Vector::new(0.0, 1.0, 0.0));
    let r = set.insert(builder, ground, ball, &w.bodies);
    (w, ground, ball, r)
}

/// A 1 kg rod of 1 m (0.04 m square) hanging under gravity −y from the ground by a joint of
/// property `prop` at its top (the origin), in a set of 4 substeps: the world, the set and
/// the joint.
pub fn hanging_rod(prop: KjointProperty) -> (PhysicsWorld, KjointSet, KjointHandle) {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let rod = cuboid(
        &mut w,
        1.0,
        Vector::new(0.02, 0.5, 0.02),
        Vector::new(0.0, -0.5, 0.0),
    );
    let mut set = joints(4);
    let j = add(&mut set, &w, prop, ground, rod, |b| {
        b.local_anchor2(Vector::new(0.0, 0.5, 0.0))
    });
    (w, set, j)
}

/// The centre of the world's one ball collider (asserted to be the only one).
#[allow(dead_code)] // (each test binary compiles this module; not all use it)
pub fn the_ball_centre(w: &PhysicsWorld) -> Vector {
    let balls: Vec<Vector> = (w.colliders.iter())
        .filter(|(_, c)| c.shape().as_ball().is_some())
        .map(|(_, c)| c.translation())
        .collect();
    assert_eq!(balls.len(), 1, "one ball collider: {balls:?}");
    balls[0]
}
