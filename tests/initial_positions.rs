//! Robots inserted at initial joint positions (`UrdfOptions::initial_positions`): the links
//! where forward kinematics puts them, the joints reading the file's `q` through
//! `UrdfRobotHandles::joint_position`, the limits where the file puts them (a Panda's
//! `joint4` range [−3.07, −0.07] excludes the zero pose, and was widened to include it),
//! and the errors of a position the robot cannot take.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]
#![allow(clippy::result_large_err)]

mod common;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rapier_kjoint::io::urdf::{UrdfError, UrdfOptions, UrdfRobotHandles};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, KjointSet};

const ROD: &str = r#"<inertial><origin xyz="0 0 -0.25"/><mass value="1"/>
  <inertia ixx="0.021" ixy="0" ixz="0" iyy="0.021" iyz="0" izz="0.001"/></inertial>"#;

/// A fixed base, a shoulder about y at 1 m with a Panda `joint4`'s range, an elbow about y
/// 0.5 m below it, and a tip sliding along the forearm's z 0.5 m further.
fn arm_urdf() -> String {
    format!(
        r#"<robot name="arm">
  <link name="base"><inertial><mass value="5"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 1"/><axis xyz="0 1 0"/>
    <limit lower="-3.07" upper="-0.07" effort="87" velocity="2"/></joint>
  <link name="upper">{ROD}</link>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 -0.5"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="87" velocity="2"/></joint>
  <link name="fore">{ROD}</link>
  <joint name="slide" type="prismatic"><parent link="fore"/><child link="tip"/>
    <origin xyz="0 0 -0.5"/><axis xyz="0 0 1"/>
    <limit lower="-0.1" upper="0.2" effort="100" velocity="1"/></joint>
  <link name="tip"><inertial><mass value="0.5"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
</robot>"#
    )
}

fn options(positions: &[(&str, f64)]) -> UrdfOptions {
    let mut o = UrdfOptions::default();
    for (name, q) in positions {
        o.initial_positions.insert(name.to_string(), *q);
    }
    o
}

fn insert(
    urdf: &str,
    gravity: Vector,
    options: &UrdfOptions,
) -> Result<(PhysicsWorld, KjointSet, UrdfRobotHandles), UrdfError> {
    let (mut world, _) = common::world(gravity);
    let mut joints = common::joints(4);
    let robot = common::robot::insert_urdf_str(urdf, "arm.urdf", &mut world, &mut joints, options)?;
    Ok((world, joints, robot))
}

fn pose_of(world: &PhysicsWorld, h: RigidBodyHandle) -> Isometry3<f64> {
    let p = world.bodies[h].position();
    let (t, r) = (p.translation, p.rotation);
    Isometry3::from_parts(
        Translation3::new(t.x as f64, t.y as f64, t.z as f64),
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            r.w as f64, r.x as f64, r.y as f64, r.z as f64,
        )),
    )
}

/// How far apart two poses are: the distance of their origins and the angle between them.
fn apart(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    let d = (a.translation.vector - b.translation.vector).norm();
    (d, a.rotation.angle_to(&b.rotation))
}

#[test]
fn the_links_stand_where_forward_kinematics_puts_them_and_the_joints_read_q() {
    let (q1, q2, q3) = (-1.5, 0.5, 0.1);
    let o = options(&[("shoulder", q1), ("elbow", q2), ("slide", q3)]);
    let (mut world, mut joints, robot) = insert(&arm_urdf(), Vector::ZERO, &o).unwrap();
    // forward kinematics, written out: each link's frame is its parent's, moved to the
    // joint origin, turned about (slid along) the joint axis by q
    let y = Vector3::y_axis();
    let upper = Isometry3::translation(0.0, 0.0, 1.0) * UnitQuaternion::from_axis_angle(&y, q1);
    let fore =
        upper * Isometry3::translation(0.0, 0.0, -0.5) * UnitQuaternion::from_axis_angle(&y, q2);
    let tip = fore * Isometry3::translation(0.0, 0.0, -0.5 + q3);
    for (link, expected) in [("upper", upper), ("fore", fore), ("tip", tip)] {
        let (d, a) = apart(&pose_of(&world, robot.links[link]), &expected);
        assert!(
            d < 1e-6 && a < 1e-6,
            "{link}: {d} m and {a} rad from its pose"
        );
    }
    // the shoulder's limit excludes 0 but holds its initial position: not widened
    assert!(
        !robot.notices.iter().any(|n| n.contains("widened")),
        "{:?}",
        robot.notices
    );
    for _ in 0..30 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    for (name, q, dof) in [
        ("shoulder", q1, Dof::Rx),
        ("elbow", q2, Dof::Rx),
        ("slide", q3, Dof::Dx),
    ] {
        let read = robot.joint_position(&joints, name).unwrap();
        assert!((read - q).abs() < 1e-6, "{name} reads {read} for {q}");
        // the KJOINT2 joint measures from its pose at insertion
        let v = joints
            .get(robot.joints[name])
            .unwrap()
            .dof_value(dof)
            .unwrap();
        assert!(v.abs() < 1e-6, "{name}: DOF {v}");
        // the anchors together, as in the zero pose (a slide's too: its anchor on the tip is
        // the point that stood at the forearm's joint origin in the zero pose)
        let s = joints.get(robot.joints[name]).unwrap().state().unwrap();
        let gap = (0..3)
            .map(|i| (s.anchor2[i] - s.anchor1[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(gap < 1e-6, "{name}: anchors {gap} m apart");
    }
    assert_eq!(robot.initial_positions["shoulder"], q1);
    assert_eq!(robot.joint_position(&joints, "no_such_joint"), None);
}

#[test]
fn a_limit_that_excludes_zero_is_held_where_the_file_puts_it() {
    // one rod on the shoulder, from −1.5 rad (reaching out along x): gravity swings it down
    // towards hanging (q = 0), and the limit −0.07 stops it there
    let urdf = arm_urdf()
        .split("<joint name=\"elbow\"")
        .next()
        .unwrap()
        .to_string()
        + "</robot>";
    let (_, _, at_zero) = insert(&urdf, Vector::ZERO, &UrdfOptions::default()).unwrap();
    assert!(
        at_zero.notices.iter().any(|n| n.contains("widened")),
        "without an initial position the limit is widened: {:?}",
        at_zero.notices
    );
    let o = options(&[("shoulder", -1.5)]);
    let (mut world, mut joints, robot) = insert(&urdf, Vector::new(0.0, 0.0, -9.81), &o).unwrap();
    let mut q_max = f64::MIN;
    for _ in 0..180 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
        q_max = q_max.max(robot.joint_position(&joints, "shoulder").unwrap());
    }
    let q = robot.joint_position(&joints, "shoulder").unwrap();
    assert!(q_max > -0.07 - 1e-3, "the rod reached its limit: {q_max}");
    assert!(q_max < -0.07 + 0.02, "the rod overran its limit to {q_max}");
    assert!(
        (q + 0.07).abs() < 2e-3,
        "the rod rests at {q} rad, not on −0.07"
    );
    // where the user sees it: the rod's centre of mass below and beside the pivot
    let c = world.bodies[robot.links["upper"]].center_of_mass();
    let (x, z) = (-0.25 * (-0.07f64).sin(), 1.0 - 0.25 * (-0.07f64).cos());
    assert!(
        (c.x as f64 - x).abs() < 1e-3 && (c.z as f64 - z).abs() < 1e-3,
        "the rod's centre at ({}, {}) for ({x}, {z})",
        c.x,
        c.z
    );
}

#[test]
fn a_slide_set_out_comes_down_to_its_lower_limit() {
    let urdf = r#"<robot name="lift">
  <link name="base"><inertial><mass value="5"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <joint name="lift" type="prismatic"><parent link="base"/><child link="carriage"/>
    <origin xyz="0 0 1"/><axis xyz="0 0 1"/>
    <limit lower="-0.2" upper="0.3" effort="100" velocity="1"/></joint>
  <link name="carriage"><inertial><mass value="2"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
</robot>"#;
    let o = options(&[("lift", 0.25)]);
    let (mut world, mut joints, robot) = insert(urdf, Vector::new(0.0, 0.0, -9.81), &o).unwrap();
    let z0 = world.bodies[robot.links["carriage"]].translation().z as f64;
    assert!((z0 - 1.25).abs() < 1e-6, "the carriage starts at {z0} m");
    for _ in 0..120 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    let q = robot.joint_position(&joints, "lift").unwrap();
    let z = world.bodies[robot.links["carriage"]].translation().z as f64;
    assert!(
        (q + 0.2).abs() < 1e-3,
        "the carriage rests at q = {q}, not −0.2"
    );
    assert!(
        (z - 0.8).abs() < 1e-3,
        "the carriage rests at z = {z} m, not 0.8"
    );
}

#[test]
fn a_position_the_robot_cannot_take_is_refused_naming_the_joint() {
    let field =
        |positions: &[(&str, f64)]| match insert(&arm_urdf(), Vector::ZERO, &options(positions)) {
            Err(UrdfError::Field {
                element,
                field,
                expected,
                ..
            }) => (element, field, expected),
            Err(e) => panic!("another error: {e}"),
            Ok(_) => panic!("{positions:?} accepted"),
        };
    let (el, f, expected) = field(&[("wrist", 0.1)]);
    assert_eq!(
        (el.as_str(), f.as_str()),
        ("options.initial_positions", "wrist")
    );
    assert!(expected.contains("name of a joint"), "{expected}");
    let (_, f, expected) = field(&[("shoulder", 0.5)]);
    assert_eq!(f, "shoulder");
    assert!(expected.contains("[-3.07, -0.07]"), "{expected}");
    let (_, f, expected) = field(&[("slide", f64::NAN)]);
    assert_eq!(f, "slide");
    assert!(expected.contains("finite"), "{expected}");
    let fixed = arm_urdf().replace(r#""slide" type="prismatic""#, r#""slide" type="fixed""#);
    let mut o = options(&[("slide", 0.1)]);
    o.fuse_fixed_joints = false;
    match insert(&fixed, Vector::ZERO, &o) {
        Err(UrdfError::Field {
            field, expected, ..
        }) => {
            assert_eq!(field, "slide");
            assert!(
                expected.contains("revolute, continuous or prismatic"),
                "{expected}"
            );
        }
        other => panic!("a fixed joint's position: {:?}", other.map(|_| ())),
    }
    // and a scene file gives them as a table
    let o: UrdfOptions = toml::from_str("initial_positions = { shoulder = -1.5 }").unwrap();
    assert_eq!(o.initial_positions["shoulder"], -1.5);
}

#[test]
fn an_mjcf_hinge_starts_at_its_value_ref_included() {
    // the rod hangs (along −z) in the file's pose, where the hinge reads `ref` = 0.2; its
    // range [−3, −0.1] excludes that pose
    let mjcf = r#"<mujoco model="hinge">
  <compiler angle="radian"/>
  <worldbody>
    <body name="rod" pos="0 0 1">
      <joint name="hinge" type="hinge" axis="0 1 0" range="-3 -0.1" ref="0.2"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/>
    </body>
  </worldbody>
</mujoco>"#;
    let run = |o: &UrdfOptions| {
        let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
        let mut joints = common::joints(4);
        let robot =
            common::robot::insert_mjcf_str(mjcf, "hinge.xml", ".", &mut world, &mut joints, o)
                .unwrap();
        (world, joints, robot)
    };
    let (_, _, at_ref) = run(&UrdfOptions::default());
    assert!(
        at_ref.notices.iter().any(|n| n.contains("widened")),
        "{:?}",
        at_ref.notices
    );
    let (mut world, mut joints, robot) = run(&options(&[("hinge", -1.5)]));
    // turned by −1.5 − 0.2 from the file's pose
    let turned = Isometry3::translation(0.0, 0.0, 1.0)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -1.7);
    let (d, a) = apart(&pose_of(&world, robot.links["rod"]), &turned);
    assert!(
        d < 1e-6 && a < 1e-6,
        "the rod is {d} m and {a} rad from its pose"
    );
    joints.step(&mut world, 1.0 / 60.0).unwrap();
    let q = robot.joint_position(&joints, "hinge").unwrap();
    assert!((q + 1.5).abs() < 0.01, "the hinge reads {q} at the start");
    for _ in 0..180 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    let q = robot.joint_position(&joints, "hinge").unwrap();
    assert!(
        (q + 0.1).abs() < 2e-3,
        "the rod rests at {q}, not on its range's −0.1"
    );
}

/// The Panda of example-robot-data (`KJOINT_ROBOT_URDFS`, set by `.ci/run`) started at its
/// ready pose: held there without gravity, and under gravity (no controller: it folds) every
/// joint stays within its URDF range (0.05 rad, the real-robot test's bound), `joint4`'s
/// [−3.07, −0.07] included, which the zero pose had widened to include 0.
#[test]
fn the_panda_at_its_ready_pose_keeps_its_ranges() {
    let Some(dir) = std::env::var_os("KJOINT_ROBOT_URDFS") else {
        println!("NOTICE: KJOINT_ROBOT_URDFS is not set: skipping the Panda (.ci/run sets it)");
        return;
    };
    let path = std::path::Path::new(&dir)
        .join("example-robot-data/robots/panda_description/urdf/panda.urdf");
    let ready = [
        ("panda_joint1", 0.0),
        ("panda_joint2", -0.785),
        ("panda_joint3", 0.0),
        ("panda_joint4", -2.356),
        ("panda_joint5", 0.0),
        ("panda_joint6", 1.571),
        ("panda_joint7", 0.785),
    ];
    let limits = [
        (-2.8973, 2.8973),
        (-1.7628, 1.7628),
        (-2.8973, 2.8973),
        (-3.0718, -0.0698),
        (-2.8973, 2.8973),
        (-0.0175, 3.7525),
        (-2.8973, 2.8973),
    ];
    let o = options(&ready);
    for gravity in [0.0, -9.81] {
        let (mut world, _) = common::world(Vector::new(0.0, 0.0, gravity));
        let mut joints = common::joints(4);
        let robot = common::robot::insert_urdf_file(&path, &mut world, &mut joints, &o).unwrap();
        assert!(
            !robot.notices.iter().any(|n| n.contains("widened")),
            "{:?}",
            robot.notices
        );
        let mut worst = 0.0f64;
        let mut drift = 0.0f64;
        for _ in 0..300 {
            joints.step(&mut world, 1.0 / 60.0).unwrap();
            for ((name, q0), (lo, hi)) in ready.iter().zip(limits) {
                let q = robot.joint_position(&joints, name).unwrap();
                worst = worst.max(lo - q).max(q - hi);
                drift = drift.max((q - q0).abs());
            }
        }
        println!("gravity {gravity}: drift {drift:.3e} rad, worst beyond a range {worst:.4} rad");
        if gravity == 0.0 {
            assert!(
                drift < 1e-4,
                "without gravity the pose moved by {drift} rad"
            );
        } else {
            assert!(drift > 0.1, "under gravity the arm folds: {drift} rad");
            assert!(worst < 0.05, "a joint {worst} rad beyond its range");
        }
    }
}

/// An MJCF model started at its keyframe `home`: its hinges where the keyframe's `qpos` puts
/// them (radians, whatever the compiler's angle unit), an entry of `initial_positions`
/// winning over it, and the errors of a keyframe the model does not have or of the wrong
/// length.
#[test]
fn an_mjcf_model_starts_at_its_keyframe() {
    let mjcf = |qpos: &str| {
        mjcf_arm(
            "",
            &format!(r#"<keyframe><key name="home" qpos="{qpos}"/></keyframe>"#),
        )
    };
    let run = |text: &str, o: &UrdfOptions| {
        let (mut world, _) = common::world(Vector::ZERO);
        let mut joints = common::joints(4);
        let robot =
            common::robot::insert_mjcf_str(text, "arm.xml", ".", &mut world, &mut joints, o)?;
        joints.step(&mut world, 1.0 / 60.0).unwrap();
        Ok::<_, UrdfError>((world, joints, robot))
    };
    let mut o = UrdfOptions {
        keyframe: Some("home".into()),
        ..Default::default()
    };
    let (world, joints, robot) = run(&mjcf("0.5 -1.0"), &o).unwrap();
    for (name, q) in [("shoulder", 0.5), ("elbow", -1.0)] {
        let read = robot.joint_position(&joints, name).unwrap();
        assert!((read - q).abs() < 1e-6, "{name} reads {read} for {q}");
    }
    let y = Vector3::y_axis();
    let fore = Isometry3::translation(0.0, 0.0, 1.0)
        * UnitQuaternion::from_axis_angle(&y, 0.5)
        * Isometry3::translation(0.0, 0.0, -0.5)
        * UnitQuaternion::from_axis_angle(&y, -1.0);
    let (d, a) = apart(&pose_of(&world, robot.links["fore"]), &fore);
    assert!(
        d < 1e-5 && a < 1e-5,
        "the forearm is {d} m and {a} rad from its pose"
    );
    // an initial position given by name wins over the keyframe's
    o.initial_positions.insert("elbow".into(), 0.25);
    let (_, joints, robot) = run(&mjcf("0.5 -1.0"), &o).unwrap();
    let q = robot.joint_position(&joints, "elbow").unwrap();
    assert!((q - 0.25).abs() < 1e-6, "the elbow reads {q}");
    // errors, naming what is wrong
    let err = |text: &str, o: &UrdfOptions| match run(text, o) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("accepted"),
    };
    let e = err(&mjcf("0.5"), &o);
    assert!(
        e.contains("keyframe `home`") && e.contains("2 values"),
        "{e}"
    );
    o.keyframe = Some("away".into());
    let e = err(&mjcf("0.5 -1.0"), &o);
    assert!(e.contains("away") && e.contains("[\"home\"]"), "{e}");
    let urdf = UrdfOptions {
        keyframe: Some("home".into()),
        ..Default::default()
    };
    let e = insert(&arm_urdf(), Vector::ZERO, &urdf)
        .map(|_| ())
        .unwrap_err();
    assert!(e.to_string().contains("keyframe"), "{e}");
}

/// A keyframe's `ctrl` starts the actuators: servos of the Menagerie kind (`<general>`,
/// `gainprm="kp" biasprm="0 -kp -kv"`) whose control is the keyframe's hold the arm at the
/// keyframe's pose (under gravity, short of it by the static error `τ_g/k`); without it
/// they started at 0 and drove the arm there. A `ctrl` of the wrong length is refused.
#[test]
fn an_mjcf_keyframe_s_controls_hold_its_pose() {
    let mjcf = |ctrl: &str| {
        mjcf_arm(
            r#"<default><default class="servo"><general biastype="affine" gainprm="400" biasprm="0 -400 -40"/></default></default>"#,
            &format!(
                r#"<actuator>
    <general class="servo" joint="shoulder"/>
    <general class="servo" joint="elbow" gear="2"/>
  </actuator>
  <keyframe><key name="home" qpos="0.5 -1.0" {ctrl}/></keyframe>"#
            ),
        )
    };
    let o = UrdfOptions {
        keyframe: Some("home".into()),
        ..Default::default()
    };
    let run = |text: &str| {
        let (mut world, _) = common::world(Vector::ZERO);
        let mut joints = common::joints(4);
        let robot =
            common::robot::insert_mjcf_str(text, "arm.xml", ".", &mut world, &mut joints, &o)?;
        for _ in 0..60 {
            joints.step(&mut world, 1.0 / 60.0).unwrap();
        }
        let q = |name: &str| robot.joint_position(&joints, name).unwrap();
        Ok::<_, UrdfError>((q("shoulder"), q("elbow")))
    };
    // the elbow's gear 2: its control is 2·q
    let (shoulder, elbow) = run(&mjcf(r#"ctrl="0.5 -2.0""#)).unwrap();
    assert!(
        (shoulder - 0.5).abs() < 1e-6 && (elbow - -1.0).abs() < 1e-6,
        "held at ({shoulder}, {elbow}) for (0.5, -1.0)"
    );
    // without the controls: a control of 0 is a target of 0
    let (shoulder, elbow) = run(&mjcf("")).unwrap();
    assert!(
        shoulder.abs() < 1e-3 && elbow.abs() < 1e-3,
        "({shoulder}, {elbow}) without ctrl"
    );
    let e = run(&mjcf(r#"ctrl="0.5""#)).unwrap_err().to_string();
    assert!(
        e.contains("keyframe `home`")
            && e.contains("ctrl")
            && e.contains("2 values, one per actuator"),
        "{e}"
    );
}

/// A two-link MJCF arm hanging from hinges about y (upper link and forearm, 1 kg and 0.5 m
/// each), with `head` before its `<worldbody>` and `tail` after it.
fn mjcf_arm(head: &str, tail: &str) -> String {
    format!(
        r#"<mujoco model="arm">
  {head}
  <worldbody>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" type="hinge" axis="0 1 0" range="-90 90"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/>
      <body name="fore" pos="0 0 -0.5">
        <joint name="elbow" type="hinge" axis="0 1 0" range="-120 120"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/>
      </body>
    </body>
  </worldbody>
  {tail}
</mujoco>"#
    )
}
