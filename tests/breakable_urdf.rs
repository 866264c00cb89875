//! A URDF joint made breakable by its override's `break` table (docs/breakable.md).

mod common;

use rapier_kjoint::dynamics::KjointEventKind;
use rapier_kjoint::io::urdf::{JointEngine, JointOverride, UrdfError, UrdfOptions};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::BreakCriterion;

/// A 2 kg link hanging from a fixed base on a fixed joint, its centre 0.5 m below it.
const URDF: &str = r#"<robot name="hang">
  <link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0 0 -0.5"/><mass value="2"/>
    <inertia ixx="0.05" ixy="0" ixz="0" iyy="0.05" iyz="0" izz="0.01"/></inertial></link>
  <joint name="weld" type="fixed"><parent link="base"/><child link="arm"/></joint>
</robot>"#;

fn options(ov: JointOverride) -> UrdfOptions {
    let mut o = UrdfOptions::default();
    o.joints.insert("weld".into(), ov);
    o
}

/// Runs 0.5 s under gravity (−z); returns the time of the weld's break, if it broke.
fn hang(limit: f64) -> Option<f64> {
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let ov = JointOverride {
        break_criterion: Some(BreakCriterion::force(limit)),
        ..Default::default()
    };
    let robot =
        common::robot::insert_urdf_str(URDF, "hang.urdf", &mut world, &mut joints, &options(ov))
            .unwrap();
    let weld = robot.joints["weld"];
    let c = joints.get(weld).unwrap().break_criterion().copied();
    assert_eq!(c, Some(BreakCriterion::force(limit)));
    let mut broke = None;
    for _ in 0..30 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
        for e in joints.drain_events() {
            if let KjointEventKind::JointBroke { .. } = e.kind {
                assert!(e.to_string().starts_with("joint weld at t = "), "{e}");
                broke.get_or_insert(e.time);
            }
        }
    }
    assert_eq!(joints.contains(weld), broke.is_none());
    broke
}

#[test]
fn a_weld_breaks_under_a_weight_over_its_limit_and_holds_under_its_limit() {
    // the weld carries the weight m·g = 19.62 N (plus the moment of the offset centre)
    assert_eq!(hang(25.0), None);
    let t = hang(15.0).expect("broke");
    // the load is there from the first substep; the automatic stiffness takes a few
    // substeps to carry it all: within the first frame
    assert!(t < 1.0 / 60.0, "broke at {t} s");
}

#[test]
fn a_bad_break_override_is_refused_naming_the_field() {
    let (mut world, _) = common::world(Vector::ZERO);
    let mut joints = common::joints(4);
    for (ov, message) in [
        (
            JointOverride {
                break_criterion: Some(BreakCriterion::force(-1.0)),
                ..Default::default()
            },
            "options.joints.`weld`: invalid break.force = -1: expected a finite limit ≥ 0",
        ),
        (
            JointOverride {
                break_criterion: Some(BreakCriterion::moment(1.0).with_exponents(1.0, f64::NAN)),
                ..Default::default()
            },
            "options.joints.`weld`: invalid break.moment_exponent = NaN",
        ),
        (
            JointOverride {
                engine: Some(JointEngine::Rapier),
                break_criterion: Some(BreakCriterion::force(1.0)),
                ..Default::default()
            },
            "invalid break = (set): expected nothing: a rapier joint",
        ),
    ] {
        let err = common::robot::insert_urdf_str(
            URDF,
            "hang.urdf",
            &mut world,
            &mut joints,
            &options(ov),
        )
        .unwrap_err();
        assert!(
            matches!(err, UrdfError::Field { .. }) && err.to_string().contains(message),
            "{err}"
        );
    }
}
