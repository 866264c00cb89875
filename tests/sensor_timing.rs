//! A DOF sensor fires in the substep whose kinematics first show the DOF past its value, and
//! the lock it drives engages in that same substep (spec §4.5), not one substep later.

use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, JointType, KjointBuilder, KjointProperty, KjointSet, SensorCondition};

#[test]
fn the_lock_engages_in_the_crossing_substep() {
    let mut w = PhysicsWorld::default();
    w.gravity = Vector::ZERO;
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    // a rod spinning at 1 rad/s about the hinge axis (world z) through its end
    let (rod, _) = w.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.5, 0.0, 0.0))
            .angvel(Vector::new(0.0, 0.0, 1.0))
            .linvel(Vector::new(0.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.02, 0.02).density(100.0),
    );
    let mut set = KjointSet::new();
    let axis_z = Rotation::from_rotation_arc(Vector::X, Vector::Z);
    let hinge = set
        .insert(
            KjointBuilder::new(
                KjointProperty::new(JointType::Revolute)
                    .with_kn(1e7)
                    .with_sensor(7),
            )
            .world_frame1(axis_z)
            .local_anchor2(Vector::new(-0.5, 0.0, 0.0)),
            ground,
            rod,
            &w.bodies,
        )
        .unwrap();
    let value = 0.0502;
    set.add_sensor(
        7,
        SensorCondition::DofPasses {
            joint: hinge,
            dof: Dof::Rx,
            value,
        },
    )
    .unwrap();
    let h = 1.0 / 240.0;
    w.integration_parameters.dt = h as _;
    set.prepare(&mut w);
    let mut crossing = None;
    for n in 0..40 {
        set.apply_substep(&mut w.bodies, w.gravity, h).unwrap();
        w.step();
        set.advance_time(h);
        let s = set.get(hinge).unwrap().state().unwrap();
        if crossing.is_none() && s.q[3].abs() >= value {
            crossing = Some(n);
            // the substep that first measures θx past the value is already locked
            assert!(
                s.locked,
                "substep {n}: θx = {} past {value} but not locked",
                s.q[3]
            );
        }
        if crossing.is_none() {
            assert!(
                !s.locked,
                "locked before the crossing (substep {n}, θx = {})",
                s.q[3]
            );
        }
    }
    // 0.0502 rad at 1 rad/s: measured at the start of substep 13 (13/240 = 0.0542 rad)
    assert_eq!(crossing, Some(13));
    assert!(set.sensor_active(7));
}
