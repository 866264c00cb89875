//! A DOF sensor fires in the substep whose kinematics first show the DOF past its value, and
//! the lock it drives engages in that same substep (spec §4.5), not one substep later.

use rapier_kjoint::dynamics::{EventSource, KjointEventKind, SensorCause, Severity};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, JointType, KjointBuilder, KjointHandle, KjointProperty, KjointSet, SensorCondition,
};

/// A rod spinning at 1 rad/s about a hinge to the ground whose property names sensor 7, and
/// sensor 7 watching the hinge's θx pass `value`; the world stepped by substeps of `h`.
fn spinning_rod(value: f64, h: f64) -> (PhysicsWorld, KjointSet, KjointHandle) {
    let mut w = PhysicsWorld {
        gravity: Vector::ZERO,
        ..Default::default()
    };
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
    set.add_sensor(
        7,
        SensorCondition::DofPasses {
            joint: hinge,
            dof: Dof::Rx,
            value,
        },
    )
    .unwrap();
    w.integration_parameters.dt = h as _;
    set.prepare(&mut w);
    (w, set, hinge)
}

#[test]
fn the_lock_engages_in_the_crossing_substep() {
    let (value, h) = (0.0502, 1.0 / 240.0);
    let (mut w, mut set, hinge) = spinning_rod(value, h);
    let mut crossing = None;
    for n in 0..40 {
        set.apply_substep(&mut w.bodies, w.gravity, h).unwrap();
        w.step();
        set.advance_time(h).unwrap();
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

/// The activation of a DOF sensor is a typed event: the sensor, the joint, the DOF, the
/// threshold and the value measured past it are fields, the time is the start of the
/// crossing substep, and its text is the one the command line prints.
#[test]
fn a_dof_sensor_reports_its_joint_dof_and_time() {
    let (value, h) = (0.0502, 1.0 / 240.0);
    let (mut w, mut set, hinge) = spinning_rod(value, h);
    let mut events = Vec::new();
    for _ in 0..20 {
        set.apply_substep(&mut w.bodies, w.gravity, h).unwrap();
        w.step();
        set.advance_time(h).unwrap();
        events.extend(set.drain_events());
    }
    let sensor: Vec<_> = events.iter().filter(|e| e.sensor().is_some()).collect();
    assert_eq!(sensor.len(), 1, "{events:?}");
    let e = sensor[0];
    assert_eq!(e.source, EventSource::Sensor(7));
    assert_eq!(e.severity(), Severity::Info);
    // measured at the start of substep 13 (see the test above)
    assert!((e.time - 13.0 * h).abs() < 1e-12, "t = {}", e.time);
    let KjointEventKind::SensorActivated {
        cause:
            SensorCause::DofPassed {
                joint,
                ref joint_name,
                dof,
                value: threshold,
                measured,
            },
    } = e.kind
    else {
        panic!("not a DOF sensor activation: {e:?}")
    };
    assert_eq!(joint, hinge);
    assert_eq!(joint_name, "joint1");
    assert_eq!(dof, Dof::Rx);
    assert_eq!(threshold, value);
    // 13 substeps at 1 rad/s: 0.0542 rad, past the value
    assert!(
        measured > value && (measured - 13.0 * h).abs() < 2e-3,
        "θx = {measured}"
    );
    assert_eq!(
        e.to_string(),
        "sensor 7 at t = 0.054167 s: joint `joint1` rx passed 0.0502 rad"
    );
}
