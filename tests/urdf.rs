//! URDF loading: joint kinds, axes, limits as stops, dynamics, overrides, errors, and real
//! robot descriptions (from `KJOINT_ROBOT_URDFS`, set by `.ci/run`).

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;

use approx::assert_relative_eq;
use rapier_kjoint::io::urdf::{
    friction_stiffness, JointOverride, UrdfError, UrdfOptions, UrdfRobot, ZERO_LIMIT,
};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, JointType, KjointSet};

const INERTIAL: &str = r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.02"/></inertial>"#;

fn kinds_urdf() -> String {
    let link = |n: &str| format!(r#"<link name="{n}">{INERTIAL}</link>"#);
    let mut s = String::from(r#"<robot name="kinds">"#);
    for n in [
        "base", "l_rev", "l_cont", "l_pri", "l_fix", "l_float", "l_planar",
    ] {
        s += &link(n);
    }
    s += r#"
      <joint name="rev" type="revolute"><parent link="base"/><child link="l_rev"/>
        <origin xyz="1 0 0" rpy="0 0 1.5707963267948966"/><axis xyz="1 0 0"/>
        <limit lower="-0.5" upper="0.7" effort="1" velocity="1"/>
        <dynamics damping="0.2" friction="0.3"/></joint>
      <joint name="cont" type="continuous"><parent link="base"/><child link="l_cont"/>
        <origin xyz="0 1 0"/><axis xyz="1 0 0"/><dynamics damping="0.1"/></joint>
      <joint name="pri" type="prismatic"><parent link="base"/><child link="l_pri"/>
        <origin xyz="0 0 1"/><axis xyz="0 1 0"/>
        <limit lower="0" upper="0.2" effort="1" velocity="1"/><dynamics damping="3"/></joint>
      <joint name="fix" type="fixed"><parent link="base"/><child link="l_fix"/>
        <origin xyz="-1 0 0"/></joint>
      <joint name="float" type="floating"><parent link="base"/><child link="l_float"/>
        <origin xyz="0 -1 0"/></joint>
      <joint name="planar" type="planar"><parent link="base"/><child link="l_planar"/>
        <origin xyz="0 0 -1"/><axis xyz="0 0 1"/></joint>
    </robot>"#;
    s
}

fn x_axis(frame: [f64; 4]) -> nalgebra::Vector3<f64> {
    let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        frame[3], frame[0], frame[1], frame[2],
    ));
    q * nalgebra::Vector3::x()
}

#[test]
fn each_urdf_joint_kind_maps_to_its_kjoint2_type_axis_stops_and_dynamics() {
    let (mut world, _) = common::world(Vector::ZERO);
    let mut joints = common::joints(4);
    // the fixed joint kept as a KJOINT2 joint (by default its link is fused into the base)
    let opts = UrdfOptions {
        fuse_fixed_joints: false,
        ..Default::default()
    };
    let robot =
        common::robot::insert_urdf_str(&kinds_urdf(), "kinds.urdf", &mut world, &mut joints, &opts)
            .expect("loads");
    assert_eq!(robot.name, "kinds");
    assert_eq!(robot.links.len(), 7);
    assert!(world.bodies[robot.links["base"]].is_fixed());
    let expect = [
        ("rev", JointType::Revolute, 2, [0.0, 1.0, 0.0]),
        ("cont", JointType::Revolute, 2, [1.0, 0.0, 0.0]),
        ("pri", JointType::Translational, 6, [0.0, 1.0, 0.0]),
        ("fix", JointType::Fixed, 8, [1.0, 0.0, 0.0]),
        ("float", JointType::Free, 9, [1.0, 0.0, 0.0]),
        ("planar", JointType::Planar, 4, [0.0, 0.0, 1.0]),
    ];
    joints.step(&mut world, 1.0 / 60.0).unwrap();
    for (name, jt, number, axis) in expect {
        let j = joints.get(robot.joints[name]).unwrap();
        assert_eq!(j.name, name);
        assert_eq!(j.property().joint_type, jt, "{name}");
        assert_eq!(j.property().joint_type.number(), number, "{name}");
        assert_eq!(j.body2(), robot.links[&format!("l_{name}")]);
        let x = x_axis(j.state().unwrap().frame);
        let err = (x - nalgebra::Vector3::from(axis)).norm();
        assert!(err < 1e-5, "{name}: joint x axis {x:?}, URDF axis {axis:?}");
    }
    // revolute: limits → stops on rx; damping → C; friction → FM with Kf = κ·I_axis/h²
    let rev = &joints.get(robot.joints["rev"]).unwrap().property();
    let rx = rev.dof(Dof::Rx);
    assert_eq!((rx.stop_min, rx.stop_max), (-0.5, 0.7));
    assert_eq!(rx.viscosity, 0.2);
    assert_eq!(rx.friction, 0.3);
    // the axis (x of the joint frame) is the link's x: I_axis = ixx = 0.01 kg·m², the link
    // alone beyond the joint, its centre of mass on the joint 1 m from the origin, radius
    // of gyration √((0.01 + 0.01 + 0.02)/3 / 1) = 0.1155 m: r = 1.1155 m, so the noise
    // bound κ = 0.01·9.81·h²/(1.192e-7·1.1155) = 12.81 < 16 (f32 poses; with f64 poses
    // the bound is 6.9e9 and κ = 16)
    let h = 1.0f64 / 240.0;
    let r = 1.0 + (0.04f64 / 3.0).sqrt();
    let kappa = 0.01 * 9.81 * h * h / (f32::EPSILON as f64 * r);
    assert_relative_eq!(kappa, 12.808, max_relative = 1e-4);
    #[cfg(feature = "f64")]
    let kappa = 16.0;
    let kf = kappa * 0.01 / (h * h);
    assert_relative_eq!(rx.friction_stiffness, kf, max_relative = 1e-5);
    #[cfg(not(feature = "f64"))]
    assert_relative_eq!(kf, 7377.4, max_relative = 1e-4);
    #[cfg(feature = "f64")]
    assert_relative_eq!(kf, 9216.0, max_relative = 1e-12);
    // continuous: no stops
    let cont = joints
        .get(robot.joints["cont"])
        .unwrap()
        .property()
        .dof(Dof::Rx)
        .clone();
    assert!(!cont.has_stops());
    assert_eq!(cont.viscosity, 0.1);
    assert_eq!(cont.friction_stiffness, 0.0);
    // prismatic: limit at 0 → -ZERO_LIMIT (0 means "no stop" in KJOINT2)
    let dx = joints
        .get(robot.joints["pri"])
        .unwrap()
        .property()
        .dof(Dof::Dx)
        .clone();
    assert_eq!((dx.stop_min, dx.stop_max), (-ZERO_LIMIT, 0.2));
    assert_eq!(dx.viscosity, 3.0);
    // the fixed joint holds its link in place (no gravity here, nothing moves)
    let p = world.bodies[robot.links["l_fix"]].translation();
    assert!((p - Vector::new(-1.0, 0.0, 0.0)).length() < 1e-5);
}

/// A 1 m, 1 kg rod on a revolute joint about y, lying along +x: gravity (−z) drives it into
/// its upper limit 0.3 rad. The stop stiffness is the blocked rotational stiffness `KR`
/// (no friction, so no `Kf`); the overshoot's bound follows from it; the stop is rigid
/// (`law::stop_prediction`): the rod rests on the limit, carrying its weight's moment.
#[test]
fn a_joint_driven_into_its_urdf_limit_is_held_by_the_stop() {
    let urdf = r#"<robot name="stop">
      <link name="base"/>
      <link name="rod">
        <inertial><origin xyz="0.5 0 0"/><mass value="1"/>
          <inertia ixx="0.0001" ixy="0" ixz="0" iyy="0.08333" iyz="0" izz="0.08333"/></inertial>
        <collision><origin xyz="0.5 0 0"/><geometry><box size="1 0.02 0.02"/></geometry></collision>
      </link>
      <joint name="world_fix" type="fixed"><parent link="base"/><child link="anchor"/></joint>
      <link name="anchor"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
      <joint name="hinge" type="revolute"><parent link="anchor"/><child link="rod"/>
        <axis xyz="0 1 0"/><limit lower="-0.3" upper="0.3" effort="10" velocity="1"/>
        <dynamics damping="0.5"/></joint>
    </robot>"#;
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let robot = common::robot::insert_urdf_str(
        urdf,
        "stop.urdf",
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    )
    .expect("loads");
    // the empty root `base` was removed and `anchor` fixed in its place
    assert!(!robot.links.contains_key("base"));
    assert!(world.bodies[robot.links["anchor"]].is_fixed());
    let h = robot.joints["hinge"];
    let (g, m, half) = (9.81, 1.0, 0.5);
    let limit = 0.3f64;
    let mut q_max = f64::MIN;
    let mut tail = Vec::new();
    let frames = 8 * 60;
    for f in 0..frames {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
        let q = joints.get(h).unwrap().dof_value(Dof::Rx).unwrap();
        assert!(q.is_finite());
        q_max = q_max.max(q);
        if f >= frames - 60 {
            tail.push(q);
        }
    }
    let kr = joints
        .get(h)
        .unwrap()
        .blocked_stiffness()
        .unwrap()
        .rotational;
    // impact: the rod falls from 0 to the limit, E = m·g·(L/2)·sin(0.3); with the gravity
    // moment M ≤ m·g·L/2 pushing on, ½·KR·δ² − M·δ ≤ E gives the largest overshoot
    let e = m * g * half * limit.sin();
    let m_max = m * g * half;
    let delta_max = (m_max + (m_max * m_max + 2.0 * kr * e).sqrt()) / kr;
    assert!(
        q_max <= limit + delta_max,
        "q_max = {q_max} rad beyond limit + {delta_max} (KR = {kr} N·m/rad)"
    );
    assert!(q_max > limit - 1e-6, "the rod reached its stop: {q_max}");
    // at rest on the stop, a rigid stop (automatic stiffness, no friction spring:
    // `law::stop_prediction`): on the limit, where the law's stop spring alone would rest
    // M/KR beyond it (M = m·g·(L/2)·cos(q)), and carrying M
    let q_end = tail.iter().sum::<f64>() / tail.len() as f64;
    let spread = tail.iter().fold(0.0f64, |a, q| a.max((q - q_end).abs()));
    let spring_pen = m * g * half * q_end.cos() / kr;
    assert!(spread < 0.01 * spring_pen, "settled: spread {spread} rad");
    assert!(
        (q_end - limit).abs() < 0.01 * spring_pen,
        "rests {} rad from the limit (the spring alone: {spring_pen})",
        q_end - limit
    );
    let moment = joints.get(h).unwrap().state().unwrap().applied[Dof::Rx];
    assert_relative_eq!(
        moment.abs(),
        m * g * half * q_end.cos(),
        max_relative = 1e-3
    );
    println!("KR = {kr:.1} N·m/rad, peak overshoot {:.4} rad (bound {delta_max:.4}), at rest {:.2e} rad from the limit (the spring alone M/KR = {spring_pen:.5}), moment {moment:.4} N·m", q_max - limit, q_end - limit);
}

fn arm_path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/urdf/arm.urdf")
}

/// The shipped arm inserted with the default options in a z-up world, its joints stepped
/// with `substeps` substeps a step.
fn shipped_arm(
    substeps: usize,
) -> (
    PhysicsWorld,
    KjointSet,
    rapier_kjoint::io::urdf::UrdfRobotHandles,
) {
    shipped_arm_with(substeps, &UrdfOptions::default())
}

/// [`shipped_arm`] loaded with `options`.
fn shipped_arm_with(
    substeps: usize,
    options: &UrdfOptions,
) -> (
    PhysicsWorld,
    KjointSet,
    rapier_kjoint::io::urdf::UrdfRobotHandles,
) {
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(substeps);
    let robot =
        common::robot::insert_urdf_file(arm_path(), &mut world, &mut joints, options).unwrap();
    (world, joints, robot)
}

/// The shipped arm: gravity drives the shoulder and elbow into their upper limits; the
/// frictional stops (stiffness `Kf`) hold them within `M/Kf` plus the impact overshoot.
#[test]
fn the_shipped_arm_settles_on_its_limits() {
    let (mut world, mut joints, robot) = shipped_arm(4);
    assert_eq!(robot.joints.len(), 3);
    for _ in 0..5 * 60 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    let q = |n: &str, d: Dof| joints.get(robot.joints[n]).unwrap().dof_value(d).unwrap();
    let kf = |n: &str, d: Dof| {
        joints
            .get(robot.joints[n])
            .unwrap()
            .property()
            .dof(d)
            .friction_stiffness
    };
    // shoulder: total gravity moment of the arm about the shoulder is below
    // 9.81·(2·0.2 + 1·0.55 + 0.5·0.78) ≈ 13.2 N·m
    let (s, e, w) = (
        q("shoulder", Dof::Rx),
        q("elbow", Dof::Rx),
        q("wrist", Dof::Dx),
    );
    println!("shoulder {s:.4} rad, elbow {e:.4} rad, wrist {w:.4} m");
    assert!(
        s > 0.6 && s < 0.6 + 13.2 / kf("shoulder", Dof::Rx) * 1.2,
        "shoulder {s}"
    );
    assert!(e > 0.8 - 0.05, "elbow {e}");
    assert!(
        e < 0.8 + 9.81 * (1.0 * 0.15 + 0.5 * 0.34) / kf("elbow", Dof::Rx) * 1.2,
        "elbow {e}"
    );
    assert!(
        w <= 0.05 + 9.81 * 0.5 / kf("wrist", Dof::Dx) * 1.2,
        "wrist {w}"
    );
}

#[test]
fn invalid_urdf_input_gives_typed_errors_naming_file_element_and_field() {
    let (mut world, _) = common::world(Vector::ZERO);
    let mut joints = KjointSet::new();
    let opts = UrdfOptions::default();
    let base = |joint: &str| {
        format!(
            r#"<robot name="r"><link name="a">{INERTIAL}</link><link name="b">{INERTIAL}</link>{joint}</robot>"#
        )
    };
    let cases = [
        (
            base(r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="NaN 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#),
            "bad.urdf: joint `j` (line 1): invalid origin.xyz",
        ),
        (
            base(r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><limit lower="nan" upper="1" effort="1" velocity="1"/></joint>"#),
            "bad.urdf: joint `j` (line 1): invalid limit.lower = NaN",
        ),
        (
            base(r#"<joint name="j" type="revolute"><parent link="a"/><child link="c"/></joint>"#),
            "bad.urdf: joint `j` (line 1): invalid child.link = c",
        ),
        (
            base(r#"<joint name="j" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="0 0 0"/></joint>"#),
            "bad.urdf: joint `j` (line 1): invalid axis.xyz",
        ),
        (
            base(r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><dynamics damping="-1"/></joint>"#),
            "bad.urdf: joint `j` (line 1): invalid dynamics.damping = -1",
        ),
        (
            r#"<robot name="r"><link name="a"><inertial><mass value="inf"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>"#.to_string(),
            "bad.urdf: link `a` (line 1): invalid inertial.mass = inf",
        ),
        ("<robot name=\"r\"><link>".to_string(), "bad.urdf: not a valid URDF document"),
        // no link at all (ROS refuses it; it loaded as nothing)
        (
            "<robot name=\"r\"></robot>".to_string(),
            "bad.urdf: robot `r` (line 1): invalid link = (none): expected at least one <link>",
        ),
        // what urdf-rs refuses without naming it (`custom: invalid float literal`, `custom:
        // missing field `value``): the element, its line and the attribute
        (
            "<robot name=\"r\">\n<link name=\"a\"><inertial>\n<mass value=\"six\"/>".to_string()
                + r#"<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>"#,
            "bad.urdf: <mass> (line 3, link `a`): invalid value = six: expected a number",
        ),
        (
            base(r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><limit lower="-1" upper="1" effort="1"/></joint>"#),
            "bad.urdf: <limit> (line 1, joint `j`): invalid velocity = (missing)",
        ),
    ];
    for (text, msg) in cases {
        let err = common::robot::insert_urdf_str(&text, "bad.urdf", &mut world, &mut joints, &opts)
            .unwrap_err();
        assert!(
            err.to_string().starts_with(msg),
            "`{err}` should start with `{msg}`"
        );
    }
    assert!(joints.is_empty(), "nothing inserted on error");
    // a missing file names the file
    let err =
        common::robot::insert_urdf_file("/nonexistent/x.urdf", &mut world, &mut joints, &opts)
            .unwrap_err();
    assert!(matches!(err, UrdfError::Read { .. }));
    assert!(err.to_string().starts_with("/nonexistent/x.urdf: "));
    // an override must name a joint of the robot; a NaN option is refused
    let mut o = UrdfOptions::default();
    o.joints.insert("nope".into(), JointOverride::default());
    let err = common::robot::insert_urdf_file(arm_path(), &mut world, &mut joints, &o).unwrap_err();
    assert!(
        err.to_string()
            .contains("options.joints: invalid name = nope"),
        "{err}"
    );
    let o = UrdfOptions {
        substep: f64::NAN,
        ..Default::default()
    };
    let err = common::robot::insert_urdf_file(arm_path(), &mut world, &mut joints, &o).unwrap_err();
    assert!(
        err.to_string().contains("options: invalid substep = NaN"),
        "{err}"
    );
    // an override with an invalid value names the joint
    let mut o = UrdfOptions::default();
    o.joints.insert(
        "elbow".into(),
        JointOverride {
            stop_min: Some(0.5),
            ..Default::default()
        },
    );
    let err = common::robot::insert_urdf_file(arm_path(), &mut world, &mut joints, &o).unwrap_err();
    assert!(err.to_string().contains("options.joints.`elbow`"), "{err}");
    assert!(err.to_string().contains("rx.stop_min (SA-)"), "{err}");
}

/// Errors about a link or a joint name the line of what they are about: the joint's
/// `<limit>`, the link's `<inertia>`, the joint itself for a wrong link name, the second of
/// two links of one name (they named the link or joint alone: a search through a
/// description of hundreds of lines).
#[test]
fn errors_name_the_line_of_the_link_or_joint_element() {
    let link = |name: &str, inertia: &str| {
        format!(
            "  <link name=\"{name}\">\n    <inertial>\n      <mass value=\"1\"/>\n      \
             <inertia {inertia}/>\n    </inertial>\n  </link>\n"
        )
    };
    let ok = r#"ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1""#;
    let joint = |limit: &str| {
        format!(
            "  <joint name=\"j\" type=\"revolute\">\n    <parent link=\"a\"/>\n    <child \
             link=\"b\"/>\n    <limit {limit} effort=\"1\" velocity=\"1\"/>\n  </joint>\n"
        )
    };
    let robot = |links: &str, joint: &str| format!("<robot name=\"r\">\n{links}{joint}</robot>\n");
    let cases = [
        // a bad joint attribute: the line of its <limit>
        (
            robot(
                &(link("a", ok) + &link("b", ok)),
                &joint(r#"lower="nan" upper="1""#),
            ),
            "lines.urdf: joint `j` (line 17): invalid limit.lower = NaN",
        ),
        (
            robot(
                &(link("a", ok) + &link("b", ok)),
                &joint(r#"lower="2" upper="1""#),
            ),
            "lines.urdf: joint `j` (line 17): invalid limit.lower = 2",
        ),
        // a bad link inertia: the line of its <inertia>, in the second link
        (
            robot(
                &(link("a", ok)
                    + &link("b", r#"ixx="-1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1""#)),
                &joint(r#"lower="-1" upper="1""#),
            ),
            "lines.urdf: link `b` (line 11): invalid inertial.inertia.ixx = -1",
        ),
        (
            robot(
                &(link("a", ok)
                    + &link("b", r#"ixx="inf" ixy="0" ixz="0" iyy="1" iyz="0" izz="1""#)),
                "",
            ),
            "lines.urdf: link `b` (line 11): invalid inertial.inertia.ixx = inf",
        ),
        // a link's mass: the line of its <mass>
        (
            robot(
                &(link("a", ok) + &link("b", ok).replace("value=\"1\"", "value=\"-2\"")),
                "",
            ),
            "lines.urdf: link `b` (line 10): invalid inertial.mass = -2",
        ),
        // a joint naming a link the robot does not have: its <child>
        (
            robot(&link("a", ok), &joint(r#"lower="-1" upper="1""#)),
            "lines.urdf: joint `j` (line 10): invalid child.link = b",
        ),
        // a repeated name: the second link of that name
        (
            robot(&(link("a", ok) + &link("a", ok)), ""),
            "lines.urdf: link `a` (line 8): invalid name = a: expected a unique link name",
        ),
    ];
    for (text, message) in cases {
        let e = UrdfRobot::from_str(&text, "lines.urdf", ".", &UrdfOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(message),
            "`{e}` should start with `{message}`\n{text}"
        );
    }
}

#[test]
fn options_deserialize_from_toml_and_overrides_apply_by_joint_name() {
    let text = r#"
        kn = 0.0
        substep = 0.001
        [joints.elbow]
        friction = 2.0
        friction_stiffness = 500.0
        [joints.wrist]
        property = { type = "fixed" }
    "#;
    let opts: UrdfOptions = toml::from_str(text).expect("options parse");
    assert_eq!(opts.substep, 0.001);
    assert!(opts.fixed_base, "defaults kept");
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = KjointSet::new();
    let robot =
        common::robot::insert_urdf_file(arm_path(), &mut world, &mut joints, &opts).unwrap();
    let p = |n: &str| joints.get(robot.joints[n]).unwrap().property().clone();
    assert_eq!(p("elbow").dof(Dof::Rx).friction, 2.0);
    assert_eq!(p("elbow").dof(Dof::Rx).friction_stiffness, 500.0);
    assert_eq!(
        p("elbow").dof(Dof::Rx).stop_max,
        0.8,
        "the rest stays from the URDF"
    );
    assert_eq!(p("wrist").joint_type, JointType::Fixed);
    // the shoulder keeps the Kf rule at the given substep, for the whole arm beyond it: its
    // moment of inertia about y through the joint, iyy + m·x² of each link, is
    // (0.0273 + 2·0.2²) + (0.00773 + 1·0.55²) + (0.000533 + 0.5·0.74²) = 0.691863 kg·m²; the
    // joint is 0.15 m from the origin and the arm's radius of gyration about it is
    // √(0.461967/3.5) = 0.363304 m (mean inertia: trace/3 + ⅔·m·d² of each link)
    let (i_axis, r) = (0.691863, 0.15 + (0.461967f64 / 3.5).sqrt());
    assert_relative_eq!(
        p("shoulder").dof(Dof::Rx).friction_stiffness,
        friction_stiffness(i_axis, r, 0.001),
        max_relative = 1e-5
    );
    // the noise bound governs at 1 ms: κ = 0.01·9.81·1e-6/(1.192e-7·0.5133) = 1.603, held at
    // the floor κ = 4 (f32 poses; with f64 poses the bound is 8.7e8 and κ = 16)
    #[cfg(not(feature = "f64"))]
    let kappa = rapier_kjoint::law::stiffness::IMPLICIT_KAPPA_FLOOR;
    #[cfg(feature = "f64")]
    let kappa = 16.0;
    assert_relative_eq!(
        friction_stiffness(i_axis, r, 0.001),
        kappa * i_axis / 1e-6,
        max_relative = 1e-3
    );
    assert!(toml::from_str::<UrdfOptions>("kn_typo = 1").is_err());
}

/// What a user sees of a robot simulated with default options: fixed base, gravity, 5 s at
/// 60 Hz × 4 substeps, read every frame.
#[derive(Debug, Clone, Default)]
struct RobotRun {
    /// At least one joint has a free DOF (the robot can move).
    moving: bool,
    /// Largest anchor gap (the anchors' separation along the blocked translations, `δ` of
    /// the blocked DOFs) over every joint and frame \[m\], and the joint.
    gap: (f64, String),
    /// Largest overrun of a revolute URDF limit (a stop) [rad], the joint, and the travel of
    /// one substep `|q̇|·h` at the fastest rate of that contact (the record before it
    /// included).
    overrun: (f64, String, f64),
    /// Largest overrun of a prismatic limit \[m\], the joint, and `|q̇|·h` there.
    overrun_m: (f64, String, f64),
    /// Every overrun is within its bound or within the travel of one substep `|q̇|·h` at
    /// the fastest rate of its contact: a stop evaluated at the start of a substep engages
    /// one substep after the crossing at the latest, so a joint arriving at `q̇` overruns by
    /// up to `q̇·h` before anything acts.
    within_travel: bool,
    /// Largest rise of the kinetic + potential energy `K + V` above its initial value, over
    /// `M·g·L`.
    energy_gain: f64,
    /// `M·g·L` \[J\]: total mass, gravity, the robot's extent.
    scale: f64,
    /// Mean wall time of a frame \[ms\].
    frame_ms: f64,
    links: usize,
    joints: usize,
}

impl RobotRun {
    /// Anchor gap bound \[m\].
    const GAP: f64 = 0.01;
    /// Revolute limit overrun bound \[rad\].
    const OVERRUN: f64 = 0.05;
    /// Prismatic limit overrun bound \[m\].
    const OVERRUN_M: f64 = 0.01;
    /// Energy gain bound, of `M·g·L`.
    const ENERGY_GAIN: f64 = 0.01;
    /// Every criterion of issue 13 holds.
    fn passes(&self) -> bool {
        self.passes_but_limits()
            && self.overrun.0 <= Self::OVERRUN
            && self.overrun_m.0 <= Self::OVERRUN_M
    }
    /// Every criterion holds, a limit overrun being allowed the travel of one substep.
    fn passes_within_travel(&self) -> bool {
        self.passes_but_limits() && self.within_travel
    }
    fn passes_but_limits(&self) -> bool {
        self.gap.0 <= Self::GAP && self.energy_gain <= Self::ENERGY_GAIN
    }
    fn line(&self, name: &str) -> String {
        format!(
            "{} {name}: {} links, {} joints, gap {:.3e} m ({}), limit overrun {:.3e} rad ({}, \
             one substep's travel {:.3e}), {:.3e} m ({}, {:.3e}), energy gain {:.2e} of M·g·L \
             = {:.3e} J, {:.2} ms/frame",
            if self.passes() {
                "ok    "
            } else if self.passes_within_travel() {
                "travel"
            } else {
                "FAILED"
            },
            self.links,
            self.joints,
            self.gap.0,
            self.gap.1,
            self.overrun.0,
            self.overrun.1,
            self.overrun.2,
            self.overrun_m.0,
            self.overrun_m.1,
            self.overrun_m.2,
            self.energy_gain,
            self.scale,
            self.frame_ms
        )
    }
}

/// Loads `path` with default options (or `options`) and simulates 5 s under gravity.
fn run_robot(path: &std::path::Path, options: &UrdfOptions) -> Result<RobotRun, String> {
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let robot = common::robot::insert_urdf_file(path, &mut world, &mut joints, options)
        .map_err(|e| e.to_string())?;
    let mut r = RobotRun {
        links: robot.links.len(),
        joints: joints.len(),
        moving: joints
            .iter()
            .any(|(_, j)| Dof::ALL.iter().any(|d| j.property().joint_type.is_free(*d))),
        within_travel: true,
        ..Default::default()
    };
    // what a user sees: the robot's kinetic + potential energy, which gravity alone can
    // never raise above its start (the joints' stored energy is at most what their
    // deflections hold, micro-joules here)
    let energy = |world: &PhysicsWorld| {
        rapier_kjoint::dynamics::energy::mechanical_energy(&world.bodies, world.gravity)
    };
    // rapier computes the bodies' mass properties at its first step (dt = 0 here)
    joints.prepare(&mut world);
    // M·g·L: the robot's mass, gravity and extent (its links' centres of mass)
    let (mut lo, mut hi) = (Vector::splat(Real::MAX), Vector::splat(Real::MIN));
    let mut mass = 0.0;
    for (_, b) in world.bodies.iter().filter(|(_, b)| b.is_dynamic()) {
        lo = lo.min(b.center_of_mass());
        hi = hi.max(b.center_of_mass());
        mass += b.mass() as f64;
    }
    let extent = if mass > 0.0 {
        ((hi - lo).length() as f64).max(0.1)
    } else {
        0.1
    };
    r.scale = mass * 9.81 * extent;
    let e0 = energy(&world);
    let mut elapsed = 0.0;
    // per (joint, DOF): one substep's travel at the last record out of contact, and the
    // largest of the contact episode under way
    let mut episodes: std::collections::HashMap<(rapier_kjoint::KjointHandle, usize), (f64, f64)> =
        Default::default();
    for _ in 0..5 * 60 {
        let t0 = std::time::Instant::now();
        joints
            .step(&mut world, 1.0 / 60.0)
            .map_err(|e| e.to_string())?;
        elapsed += t0.elapsed().as_secs_f64();
        let e = energy(&world);
        r.energy_gain = r.energy_gain.max((e - e0) / r.scale.max(1e-12));
        for (h, j) in joints.iter() {
            let s = j.state().unwrap();
            let gap = common::anchor_gap(j);
            // (a NaN counts as the worst)
            if gap.is_nan() || gap > r.gap.0 {
                r.gap = (gap, j.name.clone());
            }
            for d in Dof::ALL {
                let law = j.property().dof(d);
                if !j.property().joint_type.is_free(d) || !law.has_stops() {
                    continue;
                }
                let q = s.q[d.index()];
                let mut over = 0.0f64;
                if law.stop_max > 0.0 {
                    over = over.max(q - law.stop_max);
                }
                if law.stop_min < 0.0 {
                    over = over.max(law.stop_min - q);
                }
                // the travel of one substep at the fastest rate of this contact episode,
                // the record before it included (the rate at which the limit was crossed)
                let travel = s.rate[d.index()].abs() / 240.0;
                let episode = episodes.entry((h, d.index())).or_insert((0.0, 0.0));
                if over > 0.0 {
                    episode.1 = episode.1.max(episode.0).max(travel);
                } else {
                    *episode = (travel, 0.0);
                }
                let travel = episode.1;
                let (slot, bound) = if d.is_rotation() {
                    (&mut r.overrun, RobotRun::OVERRUN)
                } else {
                    (&mut r.overrun_m, RobotRun::OVERRUN_M)
                };
                if over.is_nan() || over > slot.0 {
                    *slot = (over, format!("{} {}", j.name, d.name()), travel);
                }
                if over.is_nan() || over > bound.max(travel) {
                    r.within_travel = false;
                }
            }
        }
    }
    r.frame_ms = 1e3 * elapsed / 300.0;
    if !(r.gap.0.is_finite() && r.energy_gain.is_finite()) {
        return Err(format!("non-finite: {r:?}"));
    }
    Ok(r)
}

/// The robots `.ci/run` downloads (example-robot-data 4.1.0, `KJOINT_ROBOT_URDFS`), tested for
/// what a user sees: with default options (fixed base, gravity, 5 s at 60 Hz × 4 substeps)
/// every joint stays within 1 cm (anchor gap), the bodies' kinetic + potential energy never
/// rises by more than 1 % of `M·g·L` above its start (no energy gain), and every URDF limit
/// holds within 0.05 rad (1 cm for a prismatic one). A joint crossing its limit at `q̇`
/// would travel `q̇·h` before a stop evaluated at the start of the substep acts (the
/// panda's joint 7 arrives at 22 rad/s, 0.09 rad per substep at 240 Hz): the stops engage
/// on the position predicted for the end of the substep (`law::stop_prediction`), which
/// this test holds to the strict bound. The lines printed say `ok` (every bound of issue 13
/// met), `travel` (a limit beyond 0.05 rad by no more than one substep's travel) or
/// `FAILED`.
///
/// `.ci/run` keeps the meshes of the UR5 (STL collision, COLLADA visual) and the double
/// pendulum (STL): their links get convex-hull colliders and visual meshes, found through
/// `package://example-robot-data/...`; the other robots' meshes are absent (inertia-only
/// links, with notices).
#[test]
fn real_robots_hold_their_joints_and_limits_for_five_seconds() {
    let Some(dir) = std::env::var_os("KJOINT_ROBOT_URDFS") else {
        println!(
            "NOTICE: KJOINT_ROBOT_URDFS is not set: skipping the real-robot test (.ci/run sets it)"
        );
        return;
    };
    let dir = std::path::PathBuf::from(dir);
    let mut files = Vec::new();
    find_urdfs(&dir, &mut files);
    let wanted = [
        "panda.urdf",
        "ur5_robot.urdf",
        "z1.urdf",
        "kinova.urdf",
        "double_pendulum.urdf",
        "solo12.urdf",
        "a1.urdf",
        "talos_left_arm.urdf",
    ];
    let mut failed = Vec::new();
    for name in wanted {
        let path = files
            .iter()
            .find(|p| p.file_name().is_some_and(|f| f == name))
            .unwrap_or_else(|| panic!("{name} not found under {}", dir.display()));
        // the meshes are found and read
        let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
        let mut joints = common::joints(4);
        let robot =
            common::robot::insert_urdf_file(path, &mut world, &mut joints, &UrdfOptions::default())
                .unwrap_or_else(|e| panic!("{e}"));
        assert!(!robot.joints.is_empty(), "{name}: joints");
        let hulls = world
            .colliders
            .iter()
            .filter(|(_, c)| c.shape().as_convex_polyhedron().is_some())
            .count();
        let (want_hulls, want_visuals) = match name {
            // base, shoulder, upper arm, forearm, wrists 1-3
            "ur5_robot.urdf" => (7, 7),
            // base, link 1, link 2
            "double_pendulum.urdf" => (3, 3),
            _ => (0, 0),
        };
        assert!(
            hulls >= want_hulls && robot.visual_meshes.len() >= want_visuals,
            "{name}: {hulls} hulls, {} visual meshes; notices {:?}",
            robot.visual_meshes.len(),
            robot.notices
        );
        let r = run_robot(path, &UrdfOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        println!("{}", r.line(name));
        if !r.passes() {
            failed.push(r.line(name));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

fn find_urdfs(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            find_urdfs(&p, out);
        } else if p.extension().is_some_and(|x| x == "urdf") {
            out.push(p);
        }
    }
}

/// Every URDF file under `KJOINT_SURVEY_URDFS` (`.ci/run` fetches every robot of
/// example-robot-data 6.0.0; else `KJOINT_ROBOT_URDFS`) on the criteria of
/// [`real_robots_hold_their_joints_and_limits_for_five_seconds`]; asserts issue 13's target,
/// at least 95 % of the robots that move meeting every bound (a robot that cannot be loaded
/// counts as a moving robot that fails), and prints how many meet them with a limit allowed
/// one substep's travel. `cargo test --release --test urdf -- --ignored --nocapture survey`
/// (a few seconds). `KJOINT_SURVEY_KN` sets a robot-wide `Kn` instead of the default (for
/// comparisons).
#[test]
#[ignore]
fn survey_every_robot_description() {
    let Some(dir) =
        std::env::var_os("KJOINT_SURVEY_URDFS").or_else(|| std::env::var_os("KJOINT_ROBOT_URDFS"))
    else {
        println!(
            "NOTICE: neither KJOINT_SURVEY_URDFS nor KJOINT_ROBOT_URDFS is set: nothing to survey"
        );
        return;
    };
    let mut options = UrdfOptions::default();
    if let Some(kn) = std::env::var("KJOINT_SURVEY_KN")
        .ok()
        .and_then(|s| s.parse().ok())
    {
        options.kn = kn;
    }
    let mut files = Vec::new();
    find_urdfs(std::path::Path::new(&dir), &mut files);
    files.sort();
    let (mut moving, mut passed, mut within_travel, mut errors) = (0, 0, 0, 0);
    let (mut gaps, mut frame_ms) = (Vec::new(), 0.0);
    let (mut worst_gap, mut worst_overrun) = ((0.0, String::new()), (0.0, String::new()));
    for path in &files {
        let name = path.file_name().unwrap().to_string_lossy();
        match run_robot(path, &options) {
            Ok(r) => {
                println!("{}", r.line(&name));
                if r.moving {
                    moving += 1;
                    passed += r.passes() as usize;
                    within_travel += r.passes_within_travel() as usize;
                    gaps.push(r.gap.0);
                    frame_ms += r.frame_ms;
                    if r.gap.0 > worst_gap.0 {
                        worst_gap = (r.gap.0, format!("{name} {}", r.gap.1));
                    }
                    if r.overrun.0 > worst_overrun.0 {
                        worst_overrun = (r.overrun.0, format!("{name} {}", r.overrun.1));
                    }
                }
            }
            Err(e) => {
                errors += 1;
                println!("ERROR  {name}: {e}");
            }
        }
    }
    gaps.sort_by(f64::total_cmp);
    let median = gaps.get(gaps.len() / 2).copied().unwrap_or(0.0);
    let total = moving + errors;
    println!(
        "{} files, {errors} not loaded; of {total} moving robots {passed} meet every bound, \
         {within_travel} with a limit allowed one substep's travel; median gap {median:.3e} m, \
         worst {:.3e} m ({}), worst limit overrun {:.3e} rad ({}); mean frame {:.2} ms",
        files.len(),
        worst_gap.0,
        worst_gap.1,
        worst_overrun.0,
        worst_overrun.1,
        frame_ms / moving.max(1) as f64
    );
    assert!(
        passed as f64 >= 0.95 * total as f64,
        "{passed} of {total} moving robots meet every bound (95 % wanted)"
    );
}

/// `fixed_base = false`: the arm falls 0.5 m onto a ground box. Its colliders hit the ground
/// (they collide with everything else) but not each other (adjacent links overlap at the
/// joints): the base comes to rest on the ground, no link sinks into it.
#[test]
fn a_floating_arm_lands_on_the_ground_without_self_collisions() {
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    world.insert_collider(
        ColliderBuilder::cuboid(5.0, 5.0, 0.5).translation(Vector::new(0.0, 0.0, -1.0)),
        None,
    );
    // the ground's top face is at z = -0.5; the base box (10 cm high) starts at z = 0
    let mut joints = common::joints(4);
    let opts = UrdfOptions {
        fixed_base: false,
        ..Default::default()
    };
    let robot =
        common::robot::insert_urdf_file(arm_path(), &mut world, &mut joints, &opts).unwrap();
    let base = robot.links["base_link"];
    assert!(world.bodies[base].is_dynamic());
    for _ in 0..3 * 60 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    let z = world.bodies[base].translation().z;
    let vz = world.bodies[base].linvel().z;
    println!("base at z = {z:.4} m, vz = {vz:.4} m/s");
    // resting on the ground: the base frame is at the bottom of its box
    assert!((z - -0.5).abs() < 0.01, "base z = {z}");
    assert!(vz.abs() < 0.05, "base vz = {vz}");
    for (name, h) in &robot.links {
        let b = &world.bodies[*h];
        assert!(
            b.translation().z > -0.6,
            "{name} sank: z = {}",
            b.translation().z
        );
    }
}

/// An ASCII STL of the cube [-1, 1]³ (12 triangles).
fn cube_stl() -> String {
    let mut s = String::from("solid cube\n");
    // for each axis and side: two triangles of the face
    for axis in 0..3 {
        for side in [-1.0f64, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |a: f64, b: f64| {
                let mut p = [0.0; 3];
                p[axis] = side;
                p[u] = a;
                p[v] = b;
                p
            };
            let quad = [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ];
            let mut n = [0.0; 3];
            n[axis] = side;
            for tri in [[0, 1, 2], [0, 2, 3]] {
                let tri = if side > 0.0 {
                    tri
                } else {
                    [tri[0], tri[2], tri[1]]
                };
                s += &format!(" facet normal {} {} {}\n  outer loop\n", n[0], n[1], n[2]);
                for k in tri {
                    let p = quad[k];
                    s += &format!("   vertex {} {} {}\n", p[0], p[1], p[2]);
                }
                s += "  endloop\n endfacet\n";
            }
        }
    }
    s + "endsolid cube\n"
}

/// A package tree `ROOT/meshbot/{urdf/meshbot.urdf, meshes/cube.stl, meshes/junk.stl}`.
fn mesh_package(tag: &str) -> std::path::PathBuf {
    let root = common::cli::temp_dir(&format!("urdf-mesh-{tag}"));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(root.join("meshbot/urdf")).unwrap();
    std::fs::create_dir_all(root.join("meshbot/meshes")).unwrap();
    std::fs::write(root.join("meshbot/meshes/cube.stl"), cube_stl()).unwrap();
    std::fs::write(
        root.join("meshbot/meshes/junk.stl"),
        "solid junk\n vertex 1 2\n",
    )
    .unwrap();
    let urdf = format!(
        r#"<robot name="meshbot">
  <link name="base">{INERTIAL}</link>
  <link name="arm">{INERTIAL}
    <collision><origin xyz="0 0 0.5"/>
      <geometry><mesh filename="package://meshbot/meshes/cube.stl" scale="0.1 0.2 0.3"/></geometry></collision>
    <visual><origin xyz="0 0 0.5" rpy="0 0 1.5707963267948966"/>
      <geometry><mesh filename="package://meshbot/meshes/cube.stl" scale="0.1 0.2 0.3"/></geometry></visual>
    <visual><geometry><mesh filename="package://meshbot/meshes/junk.stl"/></geometry></visual>
    <collision><geometry><mesh filename="package://meshbot/meshes/junk.stl"/></geometry></collision>
    <visual><geometry><mesh filename="package://meshbot/meshes/missing.stl"/></geometry></visual>
  </link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"#
    );
    std::fs::write(root.join("meshbot/urdf/meshbot.urdf"), urdf).unwrap();
    root
}

#[test]
fn urdf_meshes_become_convex_colliders_and_visual_meshes() {
    let root = mesh_package("load");
    let path = root.join("meshbot/urdf/meshbot.urdf");
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let robot =
        common::robot::insert_urdf_file(&path, &mut world, &mut joints, &UrdfOptions::default())
            .unwrap();
    // The collision mesh: the convex hull of the scaled cube, ±(0.1, 0.2, 0.3) m about the
    // collision origin 0.5 m up the link's z.
    let cols = &robot.colliders["arm"];
    assert_eq!(cols.len(), 1, "{:?}", robot.notices);
    let c = &world.colliders[cols[0]];
    assert!(c.shape().as_convex_polyhedron().is_some(), "a convex hull");
    let aabb = c.shape().compute_local_aabb();
    let local = c.position_wrt_parent().unwrap();
    for (k, h) in [0.1, 0.2, 0.3].into_iter().enumerate() {
        assert_relative_eq!(aabb.maxs[k], h, epsilon = 1e-6);
        assert_relative_eq!(aabb.mins[k], -h, epsilon = 1e-6);
    }
    assert_relative_eq!(local.translation.z, 0.5, epsilon = 1e-6);
    // The visual mesh in the link frame: scaled, turned 90° about z, lifted 0.5 m: the
    // corner (1, 1, 1) → Rz(90°)·(0.1, 0.2, 0.3) + (0, 0, 0.5) = (−0.2, 0.1, 0.8).
    assert_eq!(robot.visual_meshes.len(), 1, "{:?}", robot.notices);
    let v = &robot.visual_meshes[0];
    assert_eq!((v.link.as_str(), v.body), ("arm", robot.links["arm"]));
    assert_eq!(v.triangles.len(), 12);
    let max = |k: usize| v.vertices.iter().map(|p| p[k]).fold(f32::MIN, f32::max);
    let min = |k: usize| v.vertices.iter().map(|p| p[k]).fold(f32::MAX, f32::min);
    assert_relative_eq!(max(0), 0.2, epsilon = 1e-6);
    assert_relative_eq!(max(1), 0.1, epsilon = 1e-6);
    assert_relative_eq!(max(2), 0.8, epsilon = 1e-6);
    assert_relative_eq!(min(2), 0.2, epsilon = 1e-6);
    // The unreadable and the missing files are notices, not errors.
    let notes = robot.notices.join("\n");
    assert!(notes.contains("junk.stl` unreadable"), "{notes}");
    assert!(notes.contains("missing.stl` not found"), "{notes}");
    // (the collision mesh that made no collider: its file named)
    let unread = (robot.notices.iter())
        .find(|n| n.contains("1 of 2 collision meshes unreadable"))
        .unwrap_or_else(|| panic!("{notes}"));
    assert!(unread.contains("meshes/junk.stl`"), "{unread}");
    // It simulates (the mass sits on the hinge: the joint only sags by its penalty).
    for _ in 0..60 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    let q = joints
        .get(robot.joints["hinge"])
        .unwrap()
        .state()
        .unwrap()
        .q;
    assert!(q.iter().all(|x| x.is_finite() && x.abs() < 1e-2), "{q:?}");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn mesh_packages_are_found_in_package_dirs_and_collision_meshes_can_be_ignored() {
    let root = mesh_package("dirs");
    // The URDF moved away from its package: found only through package_dirs.
    let elsewhere = root.join("elsewhere.urdf");
    std::fs::copy(root.join("meshbot/urdf/meshbot.urdf"), &elsewhere).unwrap();
    let base = std::env::temp_dir();
    let cube = "package://meshbot/meshes/cube.stl";
    assert_eq!(
        rapier_kjoint::io::urdf::resolve_mesh_path(cube, &base, &[]),
        None,
        "not under the temp dir itself"
    );
    assert_eq!(
        rapier_kjoint::io::urdf::resolve_mesh_path(cube, &base, std::slice::from_ref(&root)),
        Some(root.join("meshbot/meshes/cube.stl"))
    );
    let load = |options: &UrdfOptions| {
        let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
        let mut joints = common::joints(4);
        let r =
            common::robot::insert_urdf_file(&elsewhere, &mut world, &mut joints, options).unwrap();
        (r.colliders["arm"].len(), r.visual_meshes.len())
    };
    // elsewhere.urdf sits in ROOT, which holds the package `meshbot`: found as ROOT/meshbot.
    assert_eq!(load(&UrdfOptions::default()), (1, 1));
    let options = UrdfOptions {
        collision_meshes: rapier_kjoint::io::urdf::CollisionMeshes::Ignore,
        visual_meshes: false,
        ..Default::default()
    };
    assert_eq!(load(&options), (0, 0));
    let options: UrdfOptions =
        toml::from_str("collision_meshes = \"tri_mesh\"\npackage_dirs = [\"/nowhere\"]\n").unwrap();
    assert_eq!(
        options.collision_meshes,
        rapier_kjoint::io::urdf::CollisionMeshes::TriMesh
    );
    assert_eq!(load(&options), (1, 1));
    let _ = std::fs::remove_dir_all(&root);
}

// ---------------------------------------------------------------------------------------
// Descriptions written by others: loops, textures, inertias
// ---------------------------------------------------------------------------------------

fn link_with(name: &str, inertial: &str) -> String {
    format!(r#"<link name="{name}"><inertial>{inertial}</inertial></link>"#)
}

fn revolute(name: &str, parent: &str, child: &str, origin: &str) -> String {
    format!(
        r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>
           <origin xyz="{origin}"/><axis xyz="1 0 0"/>
           <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>"#
    )
}

const UNIT: &str =
    r#"<mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>"#;

#[test]
fn a_closed_loop_of_links_is_refused_naming_its_joints() {
    // a → b → c → a: every link has a parent, none is the root
    let mut text = String::from(r#"<robot name="loop">"#);
    for l in ["a", "b", "c"] {
        text += &link_with(l, UNIT);
    }
    text += &revolute("ab", "a", "b", "0 0 -1");
    text += &revolute("bc", "b", "c", "0 0 -1");
    text += &revolute("ca", "c", "a", "0 0 2");
    text += "</robot>";
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = KjointSet::new();
    let opts = UrdfOptions::default();
    let err = common::robot::insert_urdf_str(&text, "loop.urdf", &mut world, &mut joints, &opts)
        .unwrap_err();
    let UrdfError::Loop {
        file,
        joints: js,
        links,
    } = &err
    else {
        panic!("{err}");
    };
    assert_eq!(file, "loop.urdf");
    assert_eq!(js, &["ab", "bc", "ca"]);
    assert_eq!(links, &["a", "b", "c", "a"]);
    assert_eq!(
        err.to_string(),
        "loop.urdf: the joints `ab`, `bc`, `ca` form a closed loop (links `a` → `b` → `c` → \
         `a`): a URDF robot is a tree from one root link; close the loop with a KJOINT2 joint \
         of its own (a scene's [[joints]])"
    );
    assert!(
        world.bodies.len() == 1 && joints.is_empty(),
        "nothing inserted"
    );
    // a loop beside a rooted tree is refused too
    let mut text = String::from(r#"<robot name="loop2">"#);
    for l in ["root", "arm", "b", "c"] {
        text += &link_with(l, UNIT);
    }
    text += &revolute("shoulder", "root", "arm", "0 0 -1");
    text += &revolute("bc", "b", "c", "0 0 -1");
    text += &revolute("cb", "c", "b", "0 0 1");
    text += "</robot>";
    let err = common::robot::insert_urdf_str(&text, "loop2.urdf", &mut world, &mut joints, &opts)
        .unwrap_err();
    assert!(
        err.to_string().starts_with(
            "loop2.urdf: the joints `bc`, `cb` form a closed loop (links `b` → `c` → `b`)"
        ),
        "{err}"
    );
}

#[test]
fn an_empty_texture_in_a_material_is_ignored_with_a_notice() {
    // as in icub and romeo (example-robot-data): <texture/> without a filename
    let text = format!(
        r#"<robot name="tex">
  <material name="shared"><color rgba="1 0 0 1"/><texture/></material>
  <link name="base">
    <inertial>{UNIT}</inertial>
    <visual><geometry><box size="0.1 0.1 0.1"/></geometry>
      <material name="skin"><color rgba="0 1 0 1"/><texture></texture></material></visual>
  </link>
  <link name="arm">
    <inertial>{UNIT}</inertial>
    <visual><geometry><box size="0.1 0.1 0.1"/></geometry>
      <material name="wood"><texture filename="wood.png"/></material></visual>
  </link>
  {}
</robot>"#,
        revolute("shoulder", "base", "arm", "0 0 -1")
    );
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = KjointSet::new();
    let robot = common::robot::insert_urdf_str(
        &text,
        "tex.urdf",
        &mut world,
        &mut joints,
        &Default::default(),
    )
    .expect("an empty texture does not refuse the robot");
    assert_eq!(robot.links.len(), 2);
    assert!(robot.joints.contains_key("shoulder"));
    let notes: Vec<&String> = robot
        .notices
        .iter()
        .filter(|n| n.contains("<texture> without a filename ignored"))
        .collect();
    assert_eq!(notes.len(), 2, "{:?}", robot.notices);
    assert!(notes[0].starts_with("line 2: "), "{}", notes[0]);
    assert!(notes[1].starts_with("line 6: "), "{}", notes[1]);
}

#[test]
fn inertia_round_off_is_read_as_zero_and_negative_inertia_is_refused() {
    let inertia = |ixx: &str, iyy: &str, ixy: &str| {
        format!(
            r#"<mass value="2"/><inertia ixx="{ixx}" ixy="{ixy}" ixz="0" iyy="{iyy}" iyz="0" izz="0.02"/>"#
        )
    };
    let robot_with = |arm: &str| {
        format!(
            r#"<robot name="r">{}{}{}</robot>"#,
            link_with("base", UNIT),
            link_with("arm", arm),
            revolute("shoulder", "base", "arm", "0 0 -1")
        )
    };
    let opts = UrdfOptions::default();
    // -5e-20 beside terms of 1e-2: round-off, read as 0 (with a notice)
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = KjointSet::new();
    let text = robot_with(&inertia("-5e-20", "0.02", "0"));
    let robot = common::robot::insert_urdf_str(&text, "r.urdf", &mut world, &mut joints, &opts)
        .expect("accepted");
    assert!(
        robot
            .notices
            .iter()
            .any(|n| n.starts_with("link `arm`: inertial.inertia.ixx = -5e-20 is round-off")),
        "{:?}",
        robot.notices
    );
    // clearly negative: refused, naming file, link and field
    let text = robot_with(&inertia("-1e-6", "0.02", "0"));
    let err = common::robot::insert_urdf_str(&text, "r.urdf", &mut world, &mut joints, &opts)
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "r.urdf: link `arm` (line 1): invalid inertial.inertia.ixx = -0.000001: expected a value >= 0 \
         [kg·m²] (round-off down to -2.0e-11 is read as 0)"
    );
    // positive diagonal, but not positive semi-definite (principal moments -0.08, 0.02,
    // 0.12): as rapier would read the negative one as 0, it gets the ball's inertia
    let text = robot_with(&inertia("0.02", "0.02", "0.1"));
    let robot = common::robot::insert_urdf_str(&text, "r.urdf", &mut world, &mut joints, &opts)
        .expect("accepted");
    assert!(
        robot.notices.iter().any(|n| n.starts_with(
            "link `arm`: inertial.inertia is not positive semi-definite (principal moments \
             [-8.000e-2, 2.000e-2, 1.200e-1] kg·m²), mass 2 kg with 1 zero principal moment"
        )),
        "{:?}",
        robot.notices
    );
    joints.prepare(&mut world);
    let pi = world.bodies[robot.links["arm"]]
        .mass_properties()
        .local_mprops
        .principal_inertia();
    let mut pi = [pi.x as f64, pi.y as f64, pi.z as f64];
    pi.sort_by(f64::total_cmp);
    for (got, want) in pi.iter().zip([0.4 * 2.0 * 0.05 * 0.05, 0.02, 0.12]) {
        assert_relative_eq!(*got, want, max_relative = 1e-4);
    }
}

#[test]
fn a_link_with_mass_and_no_inertia_gets_a_ball_s_inertia_and_swings() {
    // a horizontal point mass on a revolute joint: with zero inertia rapier would lock its
    // rotation and it would hang in the air; it gets the inertia of a 5 cm ball and falls
    let text = format!(
        r#"<robot name="point">{}{}{}</robot>"#,
        link_with("base", UNIT),
        link_with(
            "bob",
            r#"<origin xyz="0 0.5 0"/><mass value="2"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>"#
        ),
        revolute("hinge", "base", "bob", "0 0 0")
    );
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(8);
    let robot = common::robot::insert_urdf_str(
        &text,
        "point.urdf",
        &mut world,
        &mut joints,
        &Default::default(),
    )
    .expect("loads");
    let ball = 0.4 * 2.0 * 0.05 * 0.05;
    assert!(
        robot.notices.iter().any(|n| n.starts_with(
            "link `bob`: mass 2 kg with 3 zero principal moments of inertia (inertial.inertia): \
             given 2.000e-3 kg·m² there"
        )),
        "{:?}",
        robot.notices
    );
    joints.prepare(&mut world);
    let b = &world.bodies[robot.links["bob"]];
    let pi = b.mass_properties().local_mprops.principal_inertia();
    for k in 0..3 {
        assert_relative_eq!(pi[k] as f64, ball, max_relative = 1e-4);
    }
    for _ in 0..12 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    // 0.2 s of a point pendulum from the horizontal: it has fallen (z of the bob well below
    // the axis), not hung in the air
    let z = world.bodies[robot.links["bob"]].center_of_mass().z;
    assert!(z < -0.1, "bob at z = {z}");
}

/// A URDF joint without `<dynamics friction>` given a friction by a robot override
/// (`options.joints.hinge.friction`): the override's friction acts, with the friction spring
/// of the implicit rule that the file's friction would get. A 1 kg bob 0.5 m out on a
/// horizontal hinge pulls with m·g·r = 4.905 N·m: a friction of 10 N·m holds it, 2 N·m lets
/// it fall. (The override's friction was kept without a friction spring, `Kf = 0`, which
/// switches KJOINT2 friction off: the bob fell whatever the friction.) The friction spring
/// chosen by the rule, like the automatic `Kn`, is unresolved by the substep by design and
/// not named by a start notice; the same stiffness given by the override is the user's, and
/// is.
#[test]
fn an_override_s_friction_acts_on_a_joint_the_urdf_gives_none() {
    use rapier_kjoint::dynamics::KjointEventKind;
    let text = format!(
        r#"<robot name="bob">{}{}{}</robot>"#,
        link_with("base", UNIT),
        link_with(
            "bob",
            r#"<origin xyz="0 0.5 0"/><mass value="1"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/>"#
        ),
        revolute("hinge", "base", "bob", "0 0 0")
    );
    let run = |ov: JointOverride| {
        let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
        let mut joints = common::joints(4);
        let mut options = UrdfOptions::default();
        options.joints.insert("hinge".into(), ov);
        let robot =
            common::robot::insert_urdf_str(&text, "bob.urdf", &mut world, &mut joints, &options)
                .expect("loads");
        let h = robot.joints["hinge"];
        let kf = joints
            .get(h)
            .unwrap()
            .property()
            .dof(Dof::Rx)
            .friction_stiffness;
        let mut noticed = false;
        for _ in 0..60 {
            joints.step(&mut world, 1.0 / 60.0).unwrap();
            noticed |= joints
                .drain_events()
                .iter()
                .any(|e| matches!(e.kind, KjointEventKind::StiffnessBeyondSubstep { .. }));
        }
        let z = world.bodies[robot.links["bob"]].center_of_mass().z as f64;
        (z, kf, noticed)
    };
    let friction = |f: f64| JointOverride {
        friction: Some(f),
        ..Default::default()
    };
    // held: the spring of the rule deflects by 4.905 N·m / Kf, far below a millimetre at 0.5 m
    let (z, kf, noticed) = run(friction(10.0));
    // the rule's: the bob's moment of inertia about the hinge, I = m·r² + Ixx, at the pose
    // scale of its radius of gyration about the anchor, √((tr I_c/3 + ⅔·m·r²)/m)
    let rule = friction_stiffness(
        0.25 + 1e-4,
        (1e-4 + 0.25 * 2.0 / 3.0_f64).sqrt(),
        1.0 / 240.0,
    );
    assert!(kf > 1e4, "Kf = {kf}");
    assert_relative_eq!(kf, rule, max_relative = 1e-6);
    assert!(z.abs() < 1e-3, "the bob held by 10 N·m sank to z = {z} m");
    assert!(
        !noticed,
        "the friction spring of the rule was named at the start"
    );
    // falls: 2 N·m is less than the load's moment
    let (z, _, _) = run(friction(2.0));
    assert!(z < -0.2, "the bob held by 2 N·m is at z = {z} m");
    // the same stiffness as the user's own: named, for it does not follow the substep
    let (z, _, noticed) = run(JointOverride {
        friction_stiffness: Some(kf),
        ..friction(10.0)
    });
    assert!(z.abs() < 1e-3, "z = {z} m");
    assert!(
        noticed,
        "the user's unresolved friction spring was not named"
    );
}

/// Joints asked for as rapier impulse joints (`engine = "rapier"`): rapier3d-urdf's joint
/// with the URDF limits (none for `lower = upper = 0` or a continuous joint, far for an
/// infinite side) and the override's force-based motor; the other joints stay KJOINT2
/// joints. In one world, a rapier slider's motor reaches its target while a KJOINT2 hinge
/// holds its pendulum.
#[test]
fn joints_asked_for_as_rapier_joints_are_impulse_joints_with_limits_and_motors() {
    use rapier_kjoint::io::urdf::{JointEngine, RapierMotor, FAR_LIMIT};
    use rapier_kjoint::rapier::dynamics::{JointAxis, MotorModel};
    let link = |n: &str| format!(r#"<link name="{n}">{INERTIAL}</link>"#);
    let mut text = String::from(r#"<robot name="mixed">"#);
    for n in ["base", "slider", "wheel", "flap", "half", "arm"] {
        text += &link(n);
    }
    text += r#"
      <joint name="slide" type="prismatic"><parent link="base"/><child link="slider"/>
        <origin xyz="1 0 0"/><axis xyz="1 0 0"/>
        <limit lower="0" upper="0.04" effort="1" velocity="1"/><dynamics damping="3"/></joint>
      <joint name="spin" type="continuous"><parent link="base"/><child link="wheel"/>
        <origin xyz="0 1 0"/><axis xyz="0 1 0"/></joint>
      <joint name="flap" type="revolute"><parent link="base"/><child link="flap"/>
        <origin xyz="0 -1 0"/><axis xyz="0 1 0"/><limit effort="1" velocity="1"/></joint>
      <joint name="half" type="revolute"><parent link="base"/><child link="half"/>
        <origin xyz="0 0 1"/><axis xyz="0 1 0"/><limit lower="-inf" upper="0.5" effort="1" velocity="1"/></joint>
      <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/>
        <origin xyz="-1 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"#;
    let rapier = |motor: Option<RapierMotor>| JointOverride {
        engine: Some(JointEngine::Rapier),
        motor,
        ..Default::default()
    };
    let mut opts = UrdfOptions::default();
    let motor = RapierMotor {
        target: 0.02,
        stiffness: 200.0,
        damping: 20.0,
        max_force: Some(50.0),
    };
    opts.joints.insert("slide".into(), rapier(Some(motor)));
    for j in ["spin", "flap", "half"] {
        opts.joints.insert(j.into(), rapier(None));
    }
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let robot = common::robot::insert_urdf_str(&text, "mixed.urdf", &mut world, &mut joints, &opts)
        .unwrap();
    assert_eq!(robot.joints.keys().collect::<Vec<_>>(), ["hinge"]);
    assert_eq!(
        robot.rapier_joints.keys().collect::<Vec<_>>(),
        ["flap", "half", "slide", "spin"]
    );
    assert_eq!(world.impulse_joints.len(), 4);
    let data = |n: &str| {
        world
            .impulse_joints
            .get(robot.rapier_joints[n])
            .unwrap()
            .data
    };
    let slide = data("slide");
    let l = slide.limits(JointAxis::LinX).unwrap();
    assert_eq!((l.min, l.max), (0.0, 0.04));
    let m = slide.motor(JointAxis::LinX).unwrap();
    assert_eq!(m.model, MotorModel::ForceBased);
    assert_eq!(
        (m.target_pos, m.stiffness, m.damping, m.max_force),
        (0.02, 200.0, 20.0, 50.0)
    );
    assert!(data("spin").limits(JointAxis::AngX).is_none());
    assert!(
        data("flap").limits(JointAxis::AngX).is_none(),
        "lower = upper = 0"
    );
    let half = data("half").limits(JointAxis::AngX).copied().unwrap();
    assert_eq!((half.min, half.max), (-FAR_LIMIT as Real, 0.5));
    assert!(robot
        .notices
        .iter()
        .any(|n| n.contains("joint `flap`: limit lower = upper = 0")));
    assert!(robot
        .notices
        .iter()
        .any(|n| n.contains("joint `slide`: <dynamics> ignored on a rapier joint")));

    // one world: the motor drives the slider to its target, the KJOINT2 hinge holds the arm
    let slider = robot.links["slider"];
    let x0 = world.bodies[slider].translation().x;
    for _ in 0..120 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    let travel = world.bodies[slider].translation().x - x0;
    assert!((travel - 0.02).abs() < 1e-3, "slider travelled {travel} m");
    let arm = world.bodies[robot.links["arm"]].translation();
    assert!(
        (arm.x + 1.0).abs() < 1e-3 && arm.z.abs() < 1e-3,
        "arm at {arm:?}"
    );
}

/// What a rapier joint does not take is refused, naming the joint and the field.
#[test]
fn rapier_joint_overrides_are_checked() {
    use rapier_kjoint::io::urdf::{JointEngine, RapierMotor};
    let (mut world, _) = common::world(Vector::ZERO);
    let mut joints = common::joints(4);
    let cases = [
        (
            "fix",
            JointOverride {
                engine: Some(JointEngine::Rapier),
                motor: Some(RapierMotor {
                    stiffness: 1.0,
                    ..Default::default()
                }),
                ..Default::default()
            },
            "options.joints.`fix`: invalid motor = { target = 0, stiffness = 1, damping = 0 }: \
             expected no motor on a Fixed joint",
        ),
        (
            "pri",
            JointOverride {
                engine: Some(JointEngine::Rapier),
                kn: Some(1e6),
                ..Default::default()
            },
            "options.joints.`pri`: invalid kn = (set): expected nothing: a rapier joint",
        ),
        (
            "pri",
            JointOverride {
                engine: Some(JointEngine::Rapier),
                motor: Some(RapierMotor {
                    stiffness: 1.0,
                    damping: f64::INFINITY,
                    ..Default::default()
                }),
                ..Default::default()
            },
            "options.joints.`pri`.motor: invalid damping = inf: expected a finite value >= 0",
        ),
        (
            "planar",
            JointOverride {
                motor: Some(RapierMotor {
                    stiffness: 1.0,
                    ..Default::default()
                }),
                ..Default::default()
            },
            "options.joints.`planar`: invalid motor = { target = 0, stiffness = 1, damping = 0 }: \
             expected no motor on a planar joint: a motor drives the axis of a revolute",
        ),
        (
            "rev",
            JointOverride {
                motor: Some(RapierMotor {
                    stiffness: 1.0,
                    max_force: Some(0.0),
                    ..Default::default()
                }),
                ..Default::default()
            },
            "options.joints.`rev`.motor: invalid max_force = 0",
        ),
    ];
    for (joint, ov, message) in cases {
        let mut opts = UrdfOptions::default();
        opts.joints.insert(joint.into(), ov);
        let err = common::robot::insert_urdf_str(
            &kinds_urdf(),
            "kinds.urdf",
            &mut world,
            &mut joints,
            &opts,
        )
        .unwrap_err();
        assert!(
            matches!(err, UrdfError::Field { .. }) && err.to_string().contains(message),
            "{err}"
        );
        assert!(err.to_string().starts_with("kinds.urdf: "), "{err}");
    }
}

/// Describe, then insert: `UrdfRobot::from_file` touches no world and describes every
/// link and joint; its `insert` gives the same handles as the file described and inserted
/// again into another world, and a description whose joint names a link it does not have
/// is refused, not a panic.
#[test]
fn describe_then_insert() {
    use rapier_kjoint::io::urdf::{RobotJointKind, UrdfRobot};
    let opts = UrdfOptions::default();
    let robot = UrdfRobot::from_file(arm_path(), &opts).expect("describes");
    assert!(!robot.links.is_empty() && !robot.joints.is_empty());
    assert!(robot
        .joints
        .iter()
        .all(|j| matches!(j.kind, RobotJointKind::Kjoint(_))));
    let (mut world, mut joints) = (PhysicsWorld::default(), KjointSet::new());
    let inserted = robot
        .clone()
        .insert(&mut world, &mut joints)
        .expect("inserts");
    let (mut world2, mut joints2) = (PhysicsWorld::default(), KjointSet::new());
    let loaded =
        common::robot::insert_urdf_file(arm_path(), &mut world2, &mut joints2, &opts).unwrap();
    assert_eq!(inserted, loaded);
    assert_eq!(world.bodies.len(), world2.bodies.len());
    assert_eq!(joints.len(), joints2.len());
    assert_eq!(inserted.links.len(), robot.links.len());

    let mut bad = robot;
    bad.joints[0].link2 = 99;
    let (mut world3, mut joints3) = (PhysicsWorld::default(), KjointSet::new());
    let err = bad.insert(&mut world3, &mut joints3).unwrap_err();
    assert!(
        matches!(&err, UrdfError::Field { field, .. } if field == "link2"),
        "{err}"
    );
}

/// A URDF read from the working directory (`kjoint check robot.urdf`-style, base `""`)
/// named no directory in its missing-mesh notice: `not found (from ): skipped`.
#[test]
fn a_missing_mesh_notice_names_the_working_directory() {
    let urdf = r#"<robot name="r"><link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
      <collision><geometry><mesh filename="nothere.stl"/></geometry></collision></link></robot>"#;
    let robot =
        rapier_kjoint::io::urdf::UrdfRobot::from_str(urdf, "r.urdf", "", &UrdfOptions::default())
            .expect("loads");
    let all = robot.notices.join("\n");
    println!("{all}");
    assert!(
        all.contains("link `a`: collision mesh `nothere.stl` not found (from .): skipped"),
        "{all}"
    );
}

/// A floating robot whose collision meshes are all missing has no collider: besides the
/// notice of each missing mesh, one says that the robot collides with nothing and falls
/// through the ground, and under gravity it does (what a user saw: the robot gone, and only
/// the meshes' notices). A robot with one box, or a fixed arm without any `<collision>`,
/// gets no such notice; a floating one without any does.
#[test]
fn a_robot_whose_collision_meshes_are_all_missing_is_said_to_collide_with_nothing() {
    let link = |name: &str, collision: &str| {
        format!(
            r#"<link name="{name}"><inertial><mass value="1"/>
          <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>{collision}</link>"#
        )
    };
    let mesh =
        |f: &str| format!(r#"<collision><geometry><mesh filename="{f}"/></geometry></collision>"#);
    let robot = |a: &str, b: &str| {
        format!(
            r#"<robot name="r">{}{}<joint name="j" type="revolute"><parent link="a"/><child link="b"/>
          <origin xyz="0 0 -0.3"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#,
            link("a", a),
            link("b", b)
        )
    };
    let floating = UrdfOptions {
        fixed_base: false,
        ..Default::default()
    };
    let notices = |urdf: &str, options: &UrdfOptions| {
        rapier_kjoint::io::urdf::UrdfRobot::from_str(urdf, "r.urdf", "", options)
            .expect("loads")
            .notices
            .join("\n")
    };
    let lost = robot(&mesh("gone_a.stl"), &mesh("package://nopkg/gone_b.stl"));
    let all = notices(&lost, &floating);
    println!("{all}");
    assert!(
        all.contains("collision mesh `gone_a.stl` not found"),
        "{all}"
    );
    assert!(
        all.contains(
            "no moving link of the robot has a collider: none of the 2 <collision> elements \
             of its moving links made one"
        ) && all.contains("falls through the ground"),
        "{all}"
    );
    // the robot above a ground box falls through it, as the notice says
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..Default::default()
    };
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -1.0)),
        ColliderBuilder::cuboid(5.0, 5.0, 0.5),
    );
    let mut joints = KjointSet::new();
    let handles =
        common::robot::insert_urdf_str(&lost, "r", &mut world, &mut joints, &floating).unwrap();
    for _ in 0..120 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    let z = world.bodies[handles.links["a"]].translation().z as f64;
    assert!(z < -1.5, "the robot without colliders is at z = {z} m");
    // a box on one link: no such notice
    let boxed = robot(
        r#"<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>"#,
        &mesh("gone_b.stl"),
    );
    let all = notices(&boxed, &floating);
    assert!(!all.contains("no moving link of the robot"), "{all}");
    // a fixed arm whose base keeps its box but whose moving link lost its mesh: said too,
    // without the fall
    let all = notices(&boxed, &UrdfOptions::default());
    assert!(
        all.contains(
            "no moving link of the robot has a collider: none of the 1 <collision> elements"
        ) && !all.contains("falls through"),
        "{all}"
    );
    // meshes ignored on purpose: said as such
    let ignoring = UrdfOptions {
        collision_meshes: rapier_kjoint::io::urdf::CollisionMeshes::Ignore,
        ..floating.clone()
    };
    let all = notices(&lost, &ignoring);
    assert!(
        all.contains("their 2 collision meshes are ignored (`collision_meshes = \"ignore\"`)"),
        "{all}"
    );
    // no <collision> at all: said for a floating base, not for a fixed one
    let bare = robot("", "");
    let all = notices(&bare, &floating);
    assert!(
        all.contains("no moving link of the robot has a <collision> element"),
        "{all}"
    );
    let fixed = notices(&bare, &UrdfOptions::default());
    assert!(!fixed.contains("no moving link of the robot"), "{fixed}");
}

/// The largest blocked rotation \[rad\] of a translational joint's readout (its rotations
/// are all blocked).
#[cfg(not(feature = "f64"))]
fn blocked_rotation(q: &[f64]) -> f64 {
    q[3..6].iter().fold(0.0, |m: f64, r| m.max(r.abs()))
}

/// Stepped at 16 substeps a 60 Hz frame, the shipped arm's automatic stiffness was lowered
/// by the f32 noise bound (`law::stiffness`, κ = 1.17 of 16) and its wrist bent 0.037 rad
/// about a blocked axis when the shoulder hit its stop, carrying 38.7 N·m, 171 times the
/// moment of its 0.5 kg load's weight at its radius of gyration, which the rule sizes it
/// for; the warning named an explicit `Kn`. The bound now stops at the floor `κ = 4`
/// (`IMPLICIT_KAPPA_FLOOR`), where the update holds a blocked DOF as a constraint: the
/// wrist holds within the warning's 0.02 rad and nothing warns. (With the `f64` feature
/// the bound does not lower the stiffness.)
#[cfg(not(feature = "f64"))]
#[test]
fn at_many_substeps_the_noise_bound_leaves_the_arms_wrist_held() {
    use rapier_kjoint::dynamics::ROTATION_WARNING;
    use rapier_kjoint::law::stiffness::{IMPLICIT_KAPPA, IMPLICIT_KAPPA_FLOOR};
    use rapier_kjoint::{KjointEventKind, SimError, SubstepPhase};
    const DT: f64 = 1.0 / 60.0;
    // (events of the joints, the wrist's largest blocked rotation)
    let run = |substeps: usize, wrist_kn: Option<f64>| {
        let mut options = UrdfOptions::default();
        if let Some(kn) = wrist_kn {
            let wrist = rapier_kjoint::io::urdf::JointOverride {
                kn: Some(kn),
                ..Default::default()
            };
            options.joints.insert("wrist".into(), wrist);
        }
        let (mut world, mut joints, robot) = shipped_arm_with(substeps, &options);
        let wrist = robot.joints["wrist"];
        let (mut events, mut worst) = (Vec::new(), 0.0f64);
        for _ in 0..60 {
            // at every substep, as the warning reads it
            joints
                .step_with(&mut world, DT, |phase, _, set| {
                    if phase == SubstepPhase::After {
                        let q = &set.get(wrist).unwrap().state().unwrap().q;
                        worst = worst.max(blocked_rotation(&q[..]));
                    }
                    Ok::<(), SimError>(())
                })
                .unwrap();
            events.extend(joints.drain_events());
        }
        let k = joints.get(wrist).unwrap().blocked_stiffness().unwrap();
        (events, worst, k.rotational)
    };
    let (events, worst16, k16) = run(16, None);
    let (_, _, k1) = run(1, None);
    // the rule's κ = 16 at one substep a frame (h = 16.7 ms, beyond the noise bound's
    // full-κ substep), the floor's 4 at 16: K = κ·I_L/h² gives 4/16·16² = 64 times
    assert_relative_eq!(
        k16 / k1,
        IMPLICIT_KAPPA_FLOOR / IMPLICIT_KAPPA * 256.0,
        max_relative = 1e-9
    );
    let warned: Vec<_> = (events.iter())
        .filter(|e| {
            matches!(
                e.kind,
                KjointEventKind::BlockedRotation { .. } | KjointEventKind::AnchorsSeparating { .. }
            )
        })
        .collect();
    println!("wrist: {worst16:.4} rad at 16 substeps");
    assert!(warned.is_empty(), "{warned:?}");
    assert!(worst16 < ROTATION_WARNING, "{worst16}");
}

/// `self_collisions = true`: the links collide with each other but not across a joint (as
/// `rapier3d-urdf`'s joints by default), where the arm's boxes overlap: the arm hangs and
/// swings as without self-collisions, to the bit, and no adjacent pair touches. Before, the
/// overlapping links pushed each other apart against their joints.
#[test]
fn with_self_collisions_the_links_across_a_joint_stay_apart() {
    let run = |self_collisions: bool| {
        let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
        let mut joints = common::joints(4);
        let opts = UrdfOptions {
            self_collisions,
            ..Default::default()
        };
        let robot =
            common::robot::insert_urdf_file(arm_path(), &mut world, &mut joints, &opts).unwrap();
        let mut worst_gap = 0.0_f64;
        for _ in 0..60 {
            joints.step(&mut world, 1.0 / 60.0).unwrap();
            for (_, j) in joints.iter() {
                worst_gap = worst_gap.max(common::anchor_gap(j));
            }
        }
        let colliders: Vec<ColliderHandle> = (robot.links.values())
            .flat_map(|h| world.bodies[*h].colliders().to_vec())
            .collect();
        let touching = colliders.iter().any(|a| {
            colliders.iter().any(|b| {
                (world.narrow_phase.contact_pair(*a, *b))
                    .is_some_and(|p| p.has_any_active_contact())
            })
        });
        let poses: Vec<_> = robot
            .links
            .iter()
            .map(|(name, h)| (name.clone(), *world.bodies[*h].position()))
            .collect();
        let filters = world
            .impulse_joints
            .iter()
            .filter(|(_, j)| rapier_kjoint::is_contact_filter(j))
            .count();
        (poses, worst_gap, touching, filters, joints.len())
    };
    let (apart, gap_apart, touching_apart, filters_apart, _) = run(false);
    let (colliding, gap, touching, filters, n) = run(true);
    println!("worst gap {gap:.3e} m ({gap_apart:.3e} m without self-collisions)");
    assert!(!touching_apart && !touching);
    assert_eq!((filters_apart, filters), (0, n));
    assert_eq!(gap, gap_apart);
    assert_eq!(apart, colliding);
}

/// A URDF robot's bodies have their masses and inertias as soon as it is inserted, as an
/// MJCF robot's do: a program computing gravity compensation or an energy before the first
/// step read 0 kg for every URDF link (rapier gives a body its colliders' mass properties at
/// its first step; a robotics user's trial, 2026-12-05). `assets/urdf/arm.urdf`: 5, 2, 1
/// and 0.5 kg; each body's mass and inertia before the step are those after it.
#[test]
fn a_urdf_robot_has_its_masses_before_its_first_step() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/urdf/arm.urdf");
    let (mut w, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = rapier_kjoint::KjointSet::new();
    let options = UrdfOptions::default();
    let robot = common::robot::insert_urdf_file(path, &mut w, &mut joints, &options).unwrap();
    let mut names: Vec<&String> = robot.links.keys().collect();
    names.sort();
    let props = |w: &PhysicsWorld| -> Vec<(Real, Vector)> {
        names
            .iter()
            .map(|n| {
                let b = &w.bodies[robot.links[*n]];
                (
                    b.mass(),
                    b.mass_properties().local_mprops.principal_inertia(),
                )
            })
            .collect()
    };
    let before = props(&w);
    let total: Real = before.iter().map(|p| p.0).sum();
    assert!(
        (total - 8.5).abs() < 1e-5,
        "{total} kg before the first step"
    );
    joints.step(&mut w, 1.0 / 60.0).unwrap();
    assert_eq!(before, props(&w));
}

/// An MJCF model given to the URDF reader is named for what it is: its root is <mujoco>,
/// read it with the MJCF reader (it read "invalid link = (none): expected at least one
/// <link>"; a robotics user's trial, 2026-12-05). A comment and a declaration before the
/// root do not hide it; the file is named.
#[test]
fn an_mjcf_model_given_to_the_urdf_reader_says_so() {
    let text = r#"<?xml version="1.0"?>
<!-- a pendulum <robot> in MuJoCo's format -->
<mujoco model="p"><worldbody><body name="b"><joint type="hinge"/><geom size="0.1"/></body></worldbody></mujoco>"#;
    let e =
        rapier_kjoint::io::urdf::UrdfRobot::from_str(text, "p.xml", ".", &UrdfOptions::default())
            .unwrap_err()
            .to_string();
    assert!(
        e.starts_with("p.xml") && e.contains("<mujoco>, an MJCF model") && e.contains("MjcfRobot"),
        "{e}"
    );
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/mjcf/pendulum.xml");
    let e = rapier_kjoint::io::urdf::UrdfRobot::from_file(path, &UrdfOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("pendulum.xml") && e.contains("<mujoco>"), "{e}");
}
