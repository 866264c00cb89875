//! Mistakes made through the library (not a scene file) are refused with typed errors that
//! name the joint and the field, instead of being silently accepted.

mod common;

use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, JointType, KjointProperty, KjointSet, PropertyError, SensorCondition, SimError,
    SubstepSettings,
};

fn pendulum(set: &mut KjointSet, prop: KjointProperty) -> (PhysicsWorld, Result<(), SimError>) {
    let (world, _, _, r) = common::hanging_ball(set, prop);
    (world, r.map(|_| ()))
}

#[test]
fn a_law_on_a_blocked_dof_is_refused_at_insert() {
    let prop = KjointProperty::new(JointType::Revolute)
        .with_kn(1e4)
        .with_dof(Dof::Ry, DofLaw::spring(5.0));
    assert!(matches!(
        prop.validate(),
        Err(PropertyError::InvalidField { ref field, .. }) if field == "ry.stiffness"
    ));
    let mut set = KjointSet::new();
    let (_, r) = pendulum(&mut set, prop);
    let e = r.unwrap_err();
    assert!(matches!(e, SimError::Property { ref joint, .. } if joint == "hinge"));
    assert_eq!(
        e.to_string(),
        "joint `hinge`: invalid ry.stiffness = 5: expected no law: ry is blocked for a revolute \
         joint (free DOFs: rx)"
    );
    assert!(set.is_empty());
    // stops, curves and flags count as a law too; a fixed joint has no free DOF
    let prop = KjointProperty::new(JointType::Fixed).with_dof(
        Dof::Dz,
        DofLaw::default().with_stops(-0.1, 0.0).with_coupled_stops(),
    );
    let e = prop.validate().unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid dz.stop_min = -0.1: expected no law: dz is blocked for a fixed joint (free \
         DOFs: none)"
    );
    // a law on a free DOF is still fine
    let prop = KjointProperty::new(JointType::Revolute).with_dof(Dof::Rx, DofLaw::spring(5.0));
    assert!(prop.validate().is_ok());
}

#[test]
fn a_property_naming_a_missing_sensor_is_an_unknown_sensor_error() {
    let mut prop = KjointProperty::new(JointType::Revolute).with_kn(1e4);
    prop.sensor = Some(7);
    // the check the joint set runs when it starts stepping
    let e = prop
        .check_sensor_reference("hinge", |id| id == 3)
        .unwrap_err();
    assert_eq!(
        e,
        SimError::UnknownSensor {
            joint: "hinge".into(),
            sensor: 7
        }
    );
    assert_eq!(
        e.to_string(),
        "joint `hinge`: property.sensor = 7: no sensor with that id in the joint set (add it \
         with KjointSet::add_sensor)"
    );
    assert!(prop.check_sensor_reference("hinge", |id| id == 7).is_ok());
    prop.sensor = None;
    assert!(prop.check_sensor_reference("hinge", |_| false).is_ok());
}

/// Needs `KjointSet::step_with` (src/dynamics/joint_set.rs) to call
/// `KjointProperty::check_sensor_reference` for every joint before the first substep.
#[test]
fn a_joint_set_refuses_to_step_with_a_missing_sensor() {
    let mut prop = KjointProperty::new(JointType::Revolute).with_kn(1e4);
    prop.sensor = Some(7);
    let mut set = KjointSet::new();
    let (mut world, r) = pendulum(&mut set, prop);
    r.unwrap();
    // a sensor added after the joint is fine; a missing one is refused at the first step
    set.add_sensor(3, SensorCondition::Time(1.0)).unwrap();
    let e = set.step(&mut world, 1.0 / 60.0).unwrap_err();
    assert_eq!(
        e,
        SimError::UnknownSensor {
            joint: "hinge".into(),
            sensor: 7
        }
    );
    set.add_sensor(7, SensorCondition::Time(1.0)).unwrap();
    set.step(&mut world, 1.0 / 60.0).unwrap();
}

/// Needs `KjointSet::with_settings` / `set_settings` (or `step_with`) in
/// src/dynamics/joint_set.rs to refuse `substeps: 0` instead of running 1 substep.
#[test]
fn zero_substeps_are_refused() {
    let mut set = KjointSet::with_settings(SubstepSettings {
        substeps: 0,
        ..Default::default()
    });
    let (mut world, r) = pendulum(&mut set, KjointProperty::new(JointType::Revolute));
    r.unwrap();
    let e = set.step(&mut world, 1.0 / 60.0).unwrap_err();
    assert!(
        matches!(e, SimError::InvalidArgument { ref field, .. } if field.contains("substeps")),
        "{e}"
    );
}
