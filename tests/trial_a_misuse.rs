//! Misuse found by a user trial: a body switched out of `dynamic` before the first step,
//! and an absurd number of substeps.

use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    JointType, KjointBuilder, KjointProperty, KjointSet, SimError, SubstepSettings,
};

/// A 1 kg ball hanging 1 m below the ground on a revolute joint named `hinge`.
fn hinge() -> (PhysicsWorld, KjointSet, RigidBodyHandle) {
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81, 0.0),
        ..Default::default()
    };
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    let (ball, _) = w.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, -1.0, 0.0)),
        ColliderBuilder::ball(0.1).mass(1.0),
    );
    let mut set = KjointSet::new();
    set.insert(
        KjointBuilder::new(KjointProperty::new(JointType::Revolute))
            .name("hinge")
            .local_anchor2(Vector::new(0.0, 1.0, 0.0)),
        ground,
        ball,
        &w.bodies,
    )
    .unwrap();
    (w, set, ball)
}

#[test]
fn a_body_switched_out_of_dynamic_before_the_first_step_is_named_not_called_massless() {
    for (ty, kind) in [
        (RigidBodyType::Fixed, "fixed"),
        (RigidBodyType::KinematicPositionBased, "kinematic"),
    ] {
        let (mut w, mut set, ball) = hinge();
        // the 1 kg ball keeps its mass: the message said "a body has no mass"
        w.bodies[ball].set_body_type(ty, true);
        let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
        let text = e.to_string();
        assert!(
            matches!(&e, SimError::InvalidJoint { joint, .. } if joint == "hinge"),
            "{text}"
        );
        assert!(
            text.contains("neither body is dynamic") && text.contains(kind),
            "{text}"
        );
        assert!(!text.contains("no mass (give it"), "{text}");
        // made dynamic again, it runs
        w.bodies[ball].set_body_type(RigidBodyType::Dynamic, true);
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
}

#[test]
fn a_massless_body_is_still_called_massless() {
    let mut w = PhysicsWorld::default();
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    let b = w.insert_body(RigidBodyBuilder::dynamic());
    let mut set = KjointSet::new();
    set.insert(
        KjointBuilder::new(KjointProperty::new(JointType::Revolute)).name("hinge"),
        ground,
        b,
        &w.bodies,
    )
    .unwrap();
    let text = set.step(&mut w, 1.0 / 60.0).unwrap_err().to_string();
    assert!(text.contains("a body has no mass"), "{text}");
}

#[test]
fn more_substeps_than_a_scene_accepts_are_refused_not_run_for_ever() {
    let (mut w, mut set, ball) = hinge();
    let before = w.bodies[ball].translation();
    for n in [usize::MAX, rapier_kjoint::scene::MAX_SUBSTEPS + 1] {
        set.set_settings(SubstepSettings {
            substeps: n,
            ..Default::default()
        });
        let start = std::time::Instant::now();
        let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
        assert!(start.elapsed().as_secs_f64() < 1.0);
        assert!(
            matches!(&e, SimError::InvalidArgument { field, .. } if field == "SubstepSettings::substeps"),
            "{e}"
        );
        assert!(e.to_string().contains("100000"), "{e}");
        assert_eq!(w.bodies[ball].translation(), before);
    }
    set.set_settings(SubstepSettings {
        substeps: 16,
        ..Default::default()
    });
    set.step(&mut w, 1.0 / 60.0).unwrap();
}
