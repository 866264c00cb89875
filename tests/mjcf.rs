//! MJCF loading: joint kinds, ranges as stops, stiffness/damping/frictionloss, notices,
//! errors, and the MuJoCo models of gymnasium (from `KJOINT_MJCF_MODELS`, set by `.ci/run`).

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;

use rapier_kjoint::io::mjcf::MjcfRobot;
use rapier_kjoint::io::urdf::{JointOverride, UrdfError, UrdfOptions};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, JointType, KjointSet};

const KINDS: &str = r#"<mujoco model="kinds">
  <default><joint damping="0.5"/></default>
  <worldbody>
    <body name="base" pos="0 0 1">
      <inertial pos="0 0 0" mass="2" diaginertia="0.02 0.02 0.02"/>
      <body name="arm" pos="0 0 -0.2">
        <joint name="elbow" type="hinge" axis="0 1 0" limited="true" range="-30 60"
               stiffness="3" frictionloss="0.2" armature="0.01"/>
        <inertial pos="0 0 -0.1" mass="1" diaginertia="0.01 0.01 0.01"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02"/>
        <body name="slider" pos="0 0 -0.2">
          <joint name="rail" type="slide" axis="0 0 1" limited="true" range="-0.1 0"/>
          <inertial pos="0 0 0" mass="0.5" diaginertia="0.001 0.001 0.001"/>
          <body name="wrist" pos="0 0 -0.1">
            <joint name="wx" type="hinge" axis="1 0 0"/>
            <joint name="wy" type="hinge" axis="0 1 0"/>
            <inertial pos="0 0 0" mass="0.3" diaginertia="0.001 0.001 0.001"/>
            <body name="hand" pos="0 0 -0.1">
              <joint name="ball" type="ball"/>
              <inertial pos="0 0 0" mass="0.2" diaginertia="0.001 0.001 0.001"/>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="elbow" gear="10"/></actuator>
</mujoco>"#;

#[test]
fn each_mjcf_joint_kind_maps_to_its_kjoint2_type_stops_and_laws() {
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let robot = common::robot::insert_mjcf_str(
        KINDS,
        "kinds.xml",
        ".",
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    )
    .expect("loads");
    for n in &robot.notices {
        println!("notice: {n}");
    }
    let j = |n: &str| joints.get(robot.joints[n]).unwrap();
    // hinge: range in degrees (MuJoCo's default) → radians; stiffness, damping, frictionloss
    let elbow = &j("elbow").property();
    assert_eq!(elbow.joint_type, JointType::Revolute);
    let rx = elbow.dof(Dof::Rx);
    assert!((rx.stop_min + 30f64.to_radians()).abs() < 1e-6, "{rx:?}");
    assert!((rx.stop_max - 60f64.to_radians()).abs() < 1e-6, "{rx:?}");
    assert_eq!(rx.stiffness, 3.0);
    assert_eq!(rx.viscosity, 0.5, "damping from the default class");
    assert!((rx.friction - 0.2).abs() < 1e-6);
    assert!(rx.friction_stiffness > 0.0);
    // slide: a bound at exactly 0 is a stop just past it (0 means "no stop" in KJOINT2)
    let rail = &j("rail").property();
    assert_eq!(rail.joint_type, JointType::Translational);
    let dx = rail.dof(Dof::Dx);
    assert!((dx.stop_min + 0.1).abs() < 1e-6 && dx.stop_max > 0.0 && dx.stop_max < 1e-6);
    // two hinges in one body: two revolute joints in series through a spacer
    assert_eq!(j("wx").property().joint_type, JointType::Revolute);
    assert_eq!(j("wy").property().joint_type, JointType::Revolute);
    // ball → spherical, damping on its three rotations
    let ball = &j("ball").property();
    assert_eq!(ball.joint_type, JointType::Spherical);
    for d in [Dof::Rx, Dof::Ry, Dof::Rz] {
        assert_eq!(ball.dof(d).viscosity, 0.5);
    }
    // `base` has no joint under the world: fixed, with no KJOINT2 joint
    assert!(world.bodies[robot.links["base"]].is_fixed());
    assert_eq!(joints.len(), 5, "elbow, rail, wx, wy, ball (base is fixed)");
    let all = robot.notices.join("\n");
    // the elbow's `<motor>` (gear 10, control not limited): a motor of constant torque
    // `10·u`, 0 at the start, with no cap (`UrdfRobotHandles::set_motor_force` sets it)
    assert!(!all.contains("actuator(s) not mapped"), "{all}");
    let torque = j("elbow").motor(Dof::Rx).copied();
    assert_eq!(torque, Some(rapier_kjoint::KjointMotor::force(0.0)));
    assert!(
        all.contains("armature of 1 joint(s) not mapped") && all.contains("elbow"),
        "{all}"
    );
    assert!(
        all.contains("body `wrist`: 2 joints in series through 1 spacer"),
        "{all}"
    );
    // it runs: 2 s under gravity, every anchor within 1 mm
    for _ in 0..120 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    assert!(max_gap(&joints).0 < 1e-3, "{:?}", max_gap(&joints));
}

/// The largest anchor gap of the joints (the anchors' separation along the blocked
/// translations) and its joint.
fn max_gap(joints: &KjointSet) -> (f64, String) {
    let mut worst = (0.0f64, String::new());
    for (_, j) in joints.iter() {
        let gap = common::anchor_gap(j);
        if gap.is_nan() || gap > worst.0 {
            worst = (gap, j.name.clone());
        }
    }
    worst
}

/// A rotor on a vertical hinge with `frictionloss` 2 N·m (no gravity moment about it),
/// driven by a constant torque: the joint angle and the rotor's rate after `t` s.
fn rotor_angle(torque: Real, t: f64) -> (f64, f64) {
    let xml = r#"<mujoco model="rotor">
      <worldbody>
        <body name="rotor" pos="0 0 1">
          <joint name="spin" type="hinge" axis="0 0 1" frictionloss="2"/>
          <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/>
        </body>
      </worldbody>
    </mujoco>"#;
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let robot = common::robot::insert_mjcf_str(
        xml,
        "rotor.xml",
        ".",
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    )
    .expect("loads");
    let b = robot.links["rotor"];
    world.bodies[b].add_torque(Vector::new(0.0, 0.0, torque), true);
    let h = robot.joints["spin"];
    let frames = (t * 60.0).round() as usize;
    for _ in 0..frames {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    let q = joints.get(h).unwrap().dof_value(Dof::Rx).unwrap();
    (q, world.bodies[b].angvel().z as f64)
}

#[test]
fn a_hinge_with_frictionloss_sticks_below_its_friction_torque_and_slides_above() {
    // below: 1.5 N·m < 2 N·m: it sticks (within the friction spring's FM/Kf)
    let (stuck, stuck_rate) = rotor_angle(1.5, 1.0);
    // above: 3 N·m: it turns with α = (3 − 2)/0.1 = 10 rad/s²: ω = α·t = 5 rad/s at 0.5 s,
    // q = α·t²/2 = 1.25 rad (the joint's angle is measured at the last substep's start)
    let t = 0.5;
    let (slid, rate) = rotor_angle(3.0, t);
    let alpha = (3.0 - 2.0) / 0.1;
    let (q_exp, w_exp) = (0.5 * alpha * t * t, alpha * t);
    println!(
        "frictionloss 2 N·m: 1.5 N·m → {stuck:.3e} rad, {stuck_rate:.1e} rad/s after 1 s; \
         3 N·m → {rate:.4} rad/s ({:+.2} % of α·t = {w_exp}), {slid:.4} rad ({:+.2} % of \
         α·t²/2 = {q_exp}) after {t} s",
        100.0 * (rate / w_exp - 1.0),
        100.0 * (slid / q_exp - 1.0),
    );
    assert!(stuck.abs() < 1e-4, "sticks: {stuck} rad");
    assert!(stuck_rate.abs() < 1e-3, "sticks: {stuck_rate} rad/s");
    assert!(
        (rate / w_exp - 1.0).abs() < 0.01,
        "slides: {rate} rad/s vs {w_exp}"
    );
    assert!(
        (slid / q_exp - 1.0).abs() < 0.03,
        "slides: {slid} rad vs {q_exp}"
    );
}

#[test]
fn a_slide_with_stiffness_oscillates_at_sqrt_k_over_m() {
    let (k, m) = (100.0f64, 1.0f64);
    let xml = format!(
        r#"<mujoco model="spring">
      <worldbody>
        <body name="mass" pos="0 0 1">
          <joint name="spring" type="slide" axis="1 0 0" stiffness="{k}"/>
          <inertial pos="0 0 0" mass="{m}" diaginertia="0.01 0.01 0.01"/>
        </body>
      </worldbody>
    </mujoco>"#
    );
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let robot = common::robot::insert_mjcf_str(
        &xml,
        "spring.xml",
        ".",
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    )
    .expect("loads");
    let b = robot.links["mass"];
    world.bodies[b].set_linvel(Vector::new(0.1, 0.0, 0.0), true);
    let h = robot.joints["spring"];
    // 60 Hz frames × 4 substeps for 5 s: the zero crossings, interpolated between frames
    let dt = 1.0 / 60.0;
    let (mut prev, mut crossings) = (0.0f64, Vec::new());
    for i in 1..=5 * 60 {
        joints.step(&mut world, dt).unwrap();
        let q = joints.get(h).unwrap().dof_value(Dof::Dx).unwrap();
        if i > 1 && prev != 0.0 && (prev < 0.0) != (q < 0.0) {
            let t = dt * ((i - 1) as f64 + prev / (prev - q));
            crossings.push(t);
        }
        prev = q;
    }
    assert!(crossings.len() > 10, "{crossings:?}");
    let n = crossings.len() - 1;
    let half_period = (crossings[n] - crossings[0]) / n as f64;
    let omega = std::f64::consts::PI / half_period;
    let expected = (k / m).sqrt();
    let err = omega / expected - 1.0;
    println!(
        "slide k = {k} N/m, m = {m} kg: ω = {omega:.5} rad/s from {} zero crossings, √(k/m) = \
         {expected:.5} ({:+.3} %)",
        crossings.len(),
        100.0 * err
    );
    assert!(err.abs() < 0.005, "ω = {omega} vs {expected}");
}

/// `springdamper="timeconst dampratio"`: MuJoCo's compiler replaces the joint's stiffness
/// and damping by `K = I/(timeconst·dampratio)²` and `C = 2·I/timeconst`, with `I` the
/// joint's inertia `1/(M⁻¹)_ii` in the model's joint-space inertia. MuJoCo's own test
/// (`SetConstTest.SpringDamperFollowsInertia`): a slide on a 1 kg body, `springdamper=".5 1"`,
/// gets 4 N/m and 4 N·s/m, on a 4 kg body 16 and 16. A hinge between a free base (`m1`, `I1`
/// about the axis, centred on it) and a link (`m2` at `r`, `i2` about its centre) has, the
/// base free, `I = I1·(J·(m1 + m2) − m2²r²)/((m1 + m2)·(I1 + J) − m2²r²)` with `J = m2·r² + i2`
/// (the planar Lagrangian by hand), below the `J` it has on a fixed base.
#[test]
fn a_springdamper_gives_the_stiffness_and_damping_mujoco_sets_from_the_joint_s_inertia() {
    let slide = |mass: f64| {
        let xml = format!(
            r#"<mujoco model="sd">
          <worldbody>
            <body name="b">
              <joint name="s" type="slide" axis="1 0 0" springdamper=".5 1" damping="9"/>
              <inertial pos="0 0 0" mass="{mass}" diaginertia="1 1 1"/>
            </body>
          </worldbody>
        </mujoco>"#
        );
        let (mut world, _) = common::world(Vector::ZERO);
        let mut joints = common::joints(4);
        let robot = common::robot::insert_mjcf_str(
            &xml,
            "sd.xml",
            ".",
            &mut world,
            &mut joints,
            &UrdfOptions::default(),
        )
        .expect("loads");
        assert!(
            !robot.notices.iter().any(|n| n.contains("springdamper")),
            "{:?}",
            robot.notices
        );
        let law = joints
            .get(robot.joints["s"])
            .unwrap()
            .property()
            .dof(Dof::Dx)
            .clone();
        (law.stiffness, law.viscosity)
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-5 * b.abs();
    let (k, c) = slide(1.0);
    assert!(close(k, 4.0) && close(c, 4.0), "{k} {c}");
    let (k, c) = slide(4.0);
    assert!(close(k, 16.0) && close(c, 16.0), "{k} {c}");

    let (m1, i1, m2, r, i2) = (3.0, 0.4, 1.5, 0.6, 0.002);
    let xml = format!(
        r#"<mujoco model="sd">
      <worldbody>
        <body name="base" pos="0 0 1">
          <freejoint/>
          <inertial pos="0 0 0" mass="{m1}" diaginertia="{i1} {i1} {i1}"/>
          <body name="link">
            <joint name="h" type="hinge" axis="0 0 1" springdamper=".5 .2"/>
            <inertial pos="{r} 0 0" mass="{m2}" diaginertia="{i2} {i2} {i2}"/>
          </body>
        </body>
      </worldbody>
    </mujoco>"#
    );
    let hinge = |fixed_base: bool| {
        let (mut world, _) = common::world(Vector::ZERO);
        let mut joints = common::joints(4);
        let options = UrdfOptions {
            fixed_base,
            ..UrdfOptions::default()
        };
        let robot =
            common::robot::insert_mjcf_str(&xml, "sd.xml", ".", &mut world, &mut joints, &options)
                .expect("loads");
        assert_eq!(world.bodies[robot.links["base"]].is_dynamic(), !fixed_base);
        joints
            .get(robot.joints["h"])
            .unwrap()
            .property()
            .dof(Dof::Rx)
            .clone()
    };
    // the base fixed (the options' default): the link's own J about the axis
    let law = hinge(true);
    let j = m2 * r * r + i2;
    assert!(close(law.stiffness, j / (0.5 * 0.2f64).powi(2)), "{law:?}");
    assert!(close(law.viscosity, 2.0 * j / 0.5), "{law:?}");
    let law = hinge(false);
    let mt = m1 + m2;
    let inertia = i1 * (j * mt - m2 * m2 * r * r) / (mt * (i1 + j) - m2 * m2 * r * r);
    println!(
        "hinge on a free base: I = {inertia:.6} kg·m² (J = {j} on a fixed base), K = {} N·m/rad, \
         C = {} N·m·s/rad",
        law.stiffness, law.viscosity
    );
    assert!(inertia < 0.8 * j);
    assert!(
        close(law.stiffness, inertia / (0.5 * 0.2f64).powi(2)),
        "{law:?}"
    );
    assert!(close(law.viscosity, 2.0 * inertia / 0.5), "{law:?}");
}

/// A slide's spring rests at its `springref` (MuJoCo's `qpos_spring`), not where it is
/// inserted: a 1 kg body on a slide of `stiffness` 100 N/m and `damping` 20 N·s/m
/// (critically damped), `springref` 0.1 m, inserted at 0 without gravity, comes to rest at
/// 0.1 m within 0.1 mm; started at 0.25 m (`initial_positions`), at 0.1 m as well.
#[test]
fn a_slide_s_spring_rests_at_its_springref() {
    let xml = r#"<mujoco model="rest">
      <worldbody>
        <body name="b">
          <joint name="s" type="slide" axis="1 0 0" stiffness="100" damping="20" springref="0.1"/>
          <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>
        </body>
      </worldbody>
    </mujoco>"#;
    for start in [None, Some(0.25)] {
        let (mut world, _) = common::world(Vector::ZERO);
        let mut joints = common::joints(4);
        let mut options = UrdfOptions::default();
        if let Some(q) = start {
            options.initial_positions.insert("s".into(), q);
        }
        let robot =
            common::robot::insert_mjcf_str(xml, "rest.xml", ".", &mut world, &mut joints, &options)
                .expect("loads");
        let b = robot.links["b"];
        let x0 = world.bodies[b].translation().x as f64;
        for _ in 0..5 * 60 {
            joints.step(&mut world, 1.0 / 60.0).unwrap();
        }
        let x = world.bodies[b].translation().x as f64;
        // the body's travel from where it was inserted, plus where that was
        let at = x - x0 + start.unwrap_or(0.0);
        println!("started at {start:?}: rests at {at} m");
        assert!((at - 0.1).abs() < 1e-4, "{at}");
    }
}

#[test]
fn invalid_mjcf_input_gives_typed_errors_naming_file_element_and_field() {
    let err = |xml: &str, o: &UrdfOptions| {
        let (mut world, _) = common::world(Vector::ZERO);
        let mut joints = common::joints(4);
        common::robot::insert_mjcf_str(xml, "bad.xml", ".", &mut world, &mut joints, o).unwrap_err()
    };
    let d = UrdfOptions::default();
    let body = |joint: &str| {
        format!(
            r#"<mujoco><worldbody><body name="b" pos="0 0 1">{joint}
            <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/></body></worldbody></mujoco>"#
        )
    };
    // not XML
    let e = err("<mujoco><worldbody>", &d);
    assert!(matches!(e, UrdfError::Mjcf { .. }), "{e}");
    assert!(e.to_string().starts_with("bad.xml: "), "{e}");
    println!("{e}");
    // an attribute the parser refuses: it names the tag and the attribute
    let e = err(&body(r#"<joint name="j" type="hinge" damping="x"/>"#), &d);
    println!("{e}");
    let s = e.to_string();
    assert!(
        s.starts_with("bad.xml: <joint name=\"j\"> (line 1): invalid damping = x"),
        "{s}"
    );
    // negative damping, reversed range: the joint, its body and the field
    let e = err(&body(r#"<joint name="j" type="hinge" damping="-1"/>"#), &d);
    println!("{e}");
    let s = e.to_string();
    assert!(
        s.contains("bad.xml")
            && s.contains("joint `j` (body `b`, line 1)")
            && s.contains("damping"),
        "{s}"
    );
    let e = err(
        &body(r#"<joint name="j" type="slide" limited="true" range="0.2 0.1"/>"#),
        &d,
    );
    println!("{e}");
    assert!(
        e.to_string()
            .contains("joint `j` (body `b`, line 1): invalid range"),
        "{e}"
    );
    let e = err(&body(r#"<joint name="j" type="hinge" axis="0 0 0"/>"#), &d);
    assert!(e.to_string().contains("invalid axis"), "{e}");
    // an override naming no joint of the model
    let mut o = UrdfOptions::default();
    o.joints.insert("nope".into(), JointOverride::default());
    let e = err(&body(r#"<joint name="j" type="hinge"/>"#), &o);
    println!("{e}");
    assert!(
        e.to_string().contains("options.joints") && e.to_string().contains("nope"),
        "{e}"
    );
}

/// Found by fuzzing the shipped pendulum: a body's `pos` of 1e300 (an infinity in rapier's
/// f32) gave NaN poses in `kjoint check`, an `inertial` mass of NaN, -1 or inf loaded, and a
/// cylinder of size -1 or -0 panicked in parry (caught, but the panic was printed). Each is
/// refused naming the body (or geom) and the attribute.
#[test]
fn bodies_inertials_and_geoms_out_of_range_are_refused_naming_the_attribute() {
    let model = |body_pos: &str, inertial: &str, geom: &str| {
        format!(
            r#"<mujoco><worldbody><body name="b" pos="{body_pos}">
            <joint name="j" type="hinge" axis="0 1 0"/>{geom}
            <inertial pos="0 0 0" {inertial}/></body></worldbody></mujoco>"#
        )
    };
    let ok_inertial = r#"mass="1" diaginertia="0.1 0.1 0.1""#;
    let cases = [
        (
            model("0 0 1e300", ok_inertial, ""),
            "body `b` (line 1): invalid pos = [0.0, 0.0, 1e300]: expected a finite number within ±1e12",
        ),
        (
            model("0 0 1", r#"mass="nan" diaginertia="0.1 0.1 0.1""#, ""),
            "body `b` (line 1): invalid inertial.mass = NaN",
        ),
        (
            model("0 0 1", r#"mass="-1" diaginertia="0.1 0.1 0.1""#, ""),
            "body `b` (line 1): invalid inertial.mass = -1: expected a value >= 0",
        ),
        (
            model("0 0 1", r#"mass="1" diaginertia="0.1 -1 0.1""#, ""),
            "body `b` (line 1): invalid inertial.diaginertia = -1",
        ),
        (
            model(
                "0 0 1",
                ok_inertial,
                r#"<geom type="cylinder" size="-1 0.1"/>"#,
            ),
            "geom #0 (body `b`, line 2): invalid size = -1: expected a value >= 0",
        ),
        (
            model(
                "0 0 1",
                ok_inertial,
                r#"<geom name="g" type="cylinder" size="-0 0.1"/>"#,
            ),
            "geom `g` (body `b`, line 2): invalid size = -0",
        ),
        (
            model(
                "0 0 1",
                ok_inertial,
                r#"<geom type="box" size="1e25 1 1"/>"#,
            ),
            "geom #0 (body `b`, line 2): invalid size = 1e25",
        ),
    ];
    for (xml, message) in cases {
        let (mut world, _) = common::world(Vector::ZERO);
        let mut joints = common::joints(4);
        let d = UrdfOptions::default();
        let e = common::robot::insert_mjcf_str(&xml, "bad.xml", ".", &mut world, &mut joints, &d)
            .unwrap_err();
        println!("{e}");
        assert!(matches!(e, UrdfError::Field { .. }), "{e}");
        let s = e.to_string();
        assert!(
            s.starts_with(&format!("bad.xml: {message}")),
            "`{s}` should start with `bad.xml: {message}`"
        );
    }
}

#[test]
fn unmapped_elements_are_named_in_notices_and_overrides_apply_by_joint_name() {
    let xml = r#"<mujoco model="extras">
      <worldbody>
        <body name="a" pos="0 0 1">
          <joint name="j1" type="hinge" axis="0 1 0" springref="10" stiffness="1"/>
          <inertial pos="0 0 -0.1" mass="1" diaginertia="0.01 0.01 0.01"/>
          <geom name="ga" size="0.05"/>
          <body name="b" pos="0 0 -0.2">
            <joint name="j2" type="hinge" axis="0 1 0"/>
            <inertial pos="0 0 -0.1" mass="1" diaginertia="0.01 0.01 0.01"/>
            <body name="c" pos="0 0 -0.2">
              <joint type="hinge" axis="1 0 0" armature="0.1"/>
              <inertial pos="0 0 -0.1" mass="1" diaginertia="0.01 0.01 0.01"/>
              <geom name="gc" size="0.05"/>
            </body>
          </body>
        </body>
      </worldbody>
      <tendon><fixed name="t"><joint joint="j1" coef="1"/><joint joint="j2" coef="-1"/></fixed></tendon>
      <equality><joint joint1="j1" joint2="j2"/><connect name="loop" body1="a" body2="c" anchor="0 0 0"/><weld body1="b"/></equality>
      <sensor><jointpos joint="j1"/><touch name="tip" site="s"/></sensor>
      <contact><pair geom1="ga" geom2="gc" friction="2 2 0.005 0.0001 0.0001"/>
        <exclude body1="a" body2="b"/></contact>
      <deformable><flex name="cloth" dim="2" body="a b c" vertex="0 0 0 0 0 0 0 0 0"/></deformable>
    </mujoco>"#;
    let (mut world, _) = common::world(Vector::ZERO);
    let mut joints = common::joints(4);
    let mut o = UrdfOptions::default();
    o.joints.insert(
        "j2".into(),
        JointOverride {
            viscosity: Some(7.0),
            ..Default::default()
        },
    );
    let robot = common::robot::insert_mjcf_str(xml, "extras.xml", ".", &mut world, &mut joints, &o)
        .expect("loads");
    let all = robot.notices.join("\n");
    println!("{all}");
    // each by its name, or by what it ties (a robotics user read only counts: "1 equality
    // constraint(s) not mapped", where a <connect> closing a loop had left it open)
    assert!(
        all.contains("1 tendon(s) not mapped (ignored): `t`"),
        "{all}"
    );
    assert!(
        all.contains(
            "3 equality constraint(s) not mapped (ignored): joint coupling j1–j2, connect \
             `loop` (a loop it closes is left open), weld b–world"
        ),
        "{all}"
    );
    assert!(
        all.contains("2 sensor(s) not mapped (ignored): jointpos (unnamed) on j1, touch `tip`"),
        "{all}"
    );
    // rapier3d-mjcf applies contact pairs and excludes through physics hooks, which are not
    // installed; the links do not collide with each other (self_collisions = false), as an
    // exclude asks; MuJoCo's flexes are not read (all three were dropped without a word)
    assert!(
        all.contains(
            "1 <contact><pair>(s) not applied (their friction; the geoms collide as any others)"
        ),
        "{all}"
    );
    assert!(!all.contains("<exclude>"), "{all}");
    assert!(
        all.contains(
            "<deformable> (line 23): not loaded (no flex or skin in rapier): \
             <flex name=\"cloth\"> (line 23)"
        ),
        "{all}"
    );
    let mut with_collisions = o.clone();
    with_collisions.self_collisions = true;
    let (mut w2, _) = common::world(Vector::ZERO);
    let mut j2 = common::joints(4);
    let robot2 =
        common::robot::insert_mjcf_str(xml, "extras.xml", ".", &mut w2, &mut j2, &with_collisions)
            .expect("loads");
    // the exclude applied: a rapier joint that only leaves the pair's contacts out
    assert!(
        !robot2.notices.iter().any(|n| n.contains("<exclude>")),
        "{:?}",
        robot2.notices
    );
    let excludes: Vec<_> = w2.impulse_joints.iter().map(|(_, j)| j).collect();
    assert_eq!(excludes.len(), 1);
    assert!(rapier_kjoint::is_contact_filter(excludes[0]));
    assert_eq!(
        (excludes[0].body1(), excludes[0].body2()),
        (robot2.links["a"], robot2.links["b"])
    );
    // `springref` (10°, degrees by default) is where the spring rests: `K·(q − 10°)` from
    // the pose at insertion, preloaded by −K·10° there (it was noticed as not mapped)
    assert!(!all.contains("springref"), "{all}");
    let j1 = joints
        .get(robot.joints["j1"])
        .unwrap()
        .property()
        .dof(Dof::Rx)
        .clone();
    let f = j1.stiffness_curve.as_ref().expect("springref's curve");
    let rest = 10f64.to_radians();
    assert!((f.value(0.0) + rest).abs() < 1e-12 && (f.value(rest)).abs() < 1e-12);
    // an unnamed joint by its body (it read `(unnamed)`)
    assert!(
        all.contains(
            "armature of 1 joint(s) not mapped (a joint's rotor is its override's `armature`, \
             options.joints.<name>.armature): joint #0 (unnamed) (body `c`)"
        ),
        "{all}"
    );
    assert_eq!(
        joints
            .get(robot.joints["j2"])
            .unwrap()
            .property()
            .dof(Dof::Rx)
            .viscosity,
        7.0
    );
}

/// The error of loading the MJCF `xml`, read as the file `file` from the working directory
/// with the default options.
fn load_err(xml: &str, file: &str) -> UrdfError {
    MjcfRobot::from_str(xml, file, ".", &UrdfOptions::default()).unwrap_err()
}

/// Two joints of one name: the loader finds a joint's MJCF range and ref by its name, so the
/// first joint (range ±10°) was given the second's (±80°: SA± = ±1.396 rad) without a word;
/// two bodies of one name left one of them out of the scene's bodies. MuJoCo refuses both
/// (`repeated name`): refused, naming the element, as URDF's duplicate names are.
#[test]
fn repeated_joint_and_body_names_are_refused() {
    let xml = r#"<mujoco><worldbody>
      <body name="a"><joint name="j" type="hinge" range="-10 10" limited="true"/><geom size="0.1"/>
        <body name="b" pos="0 0 -1"><joint name="j" type="hinge" range="-80 80" limited="true"/>
          <geom size="0.1"/></body></body></worldbody></mujoco>"#;
    let e = load_err(xml, "dup.xml");
    println!("{e}");
    let s = e.to_string();
    assert!(matches!(e, UrdfError::Field { .. }), "{s}");
    assert!(
        s.starts_with("dup.xml: joint `j` (body `b`, line 3): invalid name = j")
            && s.contains("unique joint name (also in body `a`)"),
        "{s}"
    );
    let xml = r#"<mujoco><worldbody>
      <body name="a"><joint name="j1" type="hinge"/><geom size="0.1"/>
        <body name="a" pos="0 0 -1"><joint name="j2" type="hinge"/><geom size="0.1"/></body>
      </body></worldbody></mujoco>"#;
    let e = load_err(xml, "dup.xml");
    println!("{e}");
    assert!(
        e.to_string().starts_with(
            "dup.xml: body `a` (line 3): invalid name = a: expected a unique body name"
        ),
        "{e}"
    );
}

/// A mesh geom whose file is missing was skipped by rapier3d-mjcf with a log line only: the
/// body (no `<inertial>`: its mass from the mesh's density) loaded with the minimum 0.01 kg,
/// and the only notice said "no mass in the MJCF". The skipped mesh is now named in a notice.
#[test]
fn a_missing_mesh_file_is_named_in_a_notice() {
    let xml = r#"<mujoco><asset><mesh name="m" file="nothere.stl"/></asset><worldbody>
      <geom name="floor" type="mesh" mesh="m"/>
      <body name="a"><joint name="j" type="hinge"/><geom name="hull" type="mesh" mesh="m"/>
        <geom type="mesh" mesh="undeclared"/></body></worldbody></mujoco>"#;
    let robot = MjcfRobot::from_str(xml, "mesh.xml", "/nonexistent-dir", &UrdfOptions::default())
        .expect("loads");
    let all = robot.notices.join("\n");
    println!("{all}");
    assert!(
        all.contains(
            "geom `hull` (body `a`): mesh `m`: file `/nonexistent-dir/nothere.stl` not found: \
             skipped (no collider, and no mass from it)"
        ),
        "{all}"
    );
    assert!(
        all.contains("geom #1 (body `a`): mesh `undeclared` is not declared in <asset>"),
        "{all}"
    );
    // a geom of <worldbody> itself is one rapier3d-mjcf builds too (on the world)
    assert!(
        all.contains(
            "geom `floor` (<worldbody>): mesh `m`: file `/nonexistent-dir/nothere.stl` \
             not found"
        ),
        "{all}"
    );
    // the only moving body has no collider left: said once for the model
    assert!(
        all.contains(
            "no moving body of the model has a collider (mesh geoms were skipped, as the \
             notices above say): they collide with nothing"
        ),
        "{all}"
    );
    // with a box on the body, not
    let boxed = xml.replace(
        r#"<geom type="mesh" mesh="undeclared"/>"#,
        r#"<geom type="box" size="0.1 0.1 0.1"/>"#,
    );
    let robot = MjcfRobot::from_str(
        &boxed,
        "mesh.xml",
        "/nonexistent-dir",
        &UrdfOptions::default(),
    )
    .expect("loads");
    let all = robot.notices.join("\n");
    assert!(!all.contains("no moving body"), "{all}");
}

/// A jointless body's geoms stay where MJCF puts them once the body is fused into its
/// parent: a thigh at (0, 0, 1) turned 90° about z, its foot body at (0.1, 0, −0.4) in the
/// thigh's frame turned 90° about y, the foot's sphere at (0.05, 0, 0) in the foot's frame:
/// by hand (0, 0.1, 0.6) + R_z(90°)·R_y(90°)·(0.05, 0, 0) = (0, 0.1, 0.55). (The fused
/// links' colliders stayed at their parent's origin until 2026-12-06, rapier's
/// `set_position_wrt_parent` doing nothing before a collider is attached.)
#[test]
fn a_fused_body_s_geoms_stay_where_mjcf_puts_them() {
    let xml = r#"<mujoco><option gravity="0 0 0"/><worldbody>
        <body name="thigh" pos="0 0 1" euler="0 0 90">
          <joint name="hip" type="hinge" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.05"/>
          <body name="foot" pos="0.1 0 -0.4" euler="0 90 0">
            <geom type="sphere" size="0.03" pos="0.05 0 0"/>
          </body>
        </body></worldbody></mujoco>"#;
    let (mut world, _) = common::world(Vector::ZERO);
    let mut joints = KjointSet::new();
    let robot = common::robot::insert_mjcf_str(
        xml,
        "fuse.xml",
        ".",
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    )
    .unwrap();
    assert_eq!(robot.links["foot"], robot.links["thigh"], "the foot fused");
    let ball = common::the_ball_centre(&world);
    let want = [0.0, 0.1, 0.55];
    for k in 0..3 {
        assert!(
            (ball[k] as f64 - want[k]).abs() < 1e-6,
            "the foot's sphere at {:?}, want {want:?}",
            ball
        );
    }
}

/// An ellipsoid geom weighs what the ellipsoid does: 4/3·π·abc·ρ (0.1 × 0.05 × 0.05 m at
/// MuJoCo's 1000 kg/m³: 1.0472 kg), with `m·(b² + c²)/5`, … about its own axes (turned here
/// by 90° about z: the long axis along y), alone on a body and beside a box (1 kg more,
/// centred 0.2 m along x). `rapier3d-mjcf` builds it as the convex hull of an icosphere,
/// 60.5 % of its volume: it weighed 0.634 kg with nothing said (an MJCF user's trial,
/// 2026-12-06).
#[test]
fn an_ellipsoid_geom_weighs_what_the_ellipsoid_does() {
    let xml = |extra: &str| {
        format!(
            r#"<mujoco><worldbody><body name="a" pos="0 0 1"><joint name="j" type="hinge"/>
            <geom type="ellipsoid" size="0.1 0.05 0.05" euler="0 0 90"/>{extra}
            </body></worldbody></mujoco>"#
        )
    };
    let (a, b, c) = (0.1f64, 0.05f64, 0.05f64);
    let m = 4.0 / 3.0 * std::f64::consts::PI * a * b * c * 1000.0;
    // about the body's axes: the ellipsoid's a along y
    let own = [
        m * (a * a + c * c) / 5.0,
        m * (b * b + c * c) / 5.0,
        m * (a * a + b * b) / 5.0,
    ];
    for (extra, mass, com_x) in [
        ("", m, 0.0),
        (
            r#"<geom type="box" size="0.05 0.05 0.05" pos="0.2 0 0" mass="1"/>"#,
            m + 1.0,
            0.2 / (m + 1.0),
        ),
    ] {
        let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
        let mut joints = KjointSet::new();
        let robot = common::robot::insert_mjcf_str(
            &xml(extra),
            "e.xml",
            ".",
            &mut world,
            &mut joints,
            &UrdfOptions::default(),
        )
        .unwrap();
        let mp = world.bodies[robot.links["a"]]
            .mass_properties()
            .local_mprops;
        assert!(
            (mp.mass() as f64 - mass).abs() < 1e-5 * mass,
            "mass {} kg, want {mass} kg (extra {extra:?})",
            mp.mass()
        );
        assert!(
            (mp.local_com.x as f64 - com_x).abs() < 1e-5,
            "{:?}",
            mp.local_com
        );
        let i = mp.reconstruct_inertia_matrix();
        let d = com_x;
        // the box's own (1 kg, 0.1 m cube: 1/600 kg·m²) and both parallel axes
        let want = if extra.is_empty() {
            own
        } else {
            let cube = 1.0 / 600.0;
            let (mb, xb) = (1.0, 0.2);
            [
                own[0] + cube,
                own[1] + cube + m * d * d + mb * (xb - d) * (xb - d),
                own[2] + cube + m * d * d + mb * (xb - d) * (xb - d),
            ]
        };
        for (k, want) in want.iter().enumerate() {
            let got = i.col(k)[k] as f64;
            assert!(
                (got - want).abs() < 1e-4 * want,
                "I[{k}][{k}] = {got}, want {want} (extra {extra:?})"
            );
        }
    }
}

/// The files a model reads besides itself are held to the size cap of input files: an
/// `<include>` of `/dev/zero` was read by mjcf-rs until the memory ran out, and a mesh file
/// `/dev/zero` read whole by rapier3d-mjcf (2 GB) and then called "not found", and so was an
/// `<asset><model>` sub-model. An include that cannot be read or is not XML is named with
/// its line.
#[cfg(unix)]
#[test]
fn included_and_mesh_files_are_held_to_the_input_cap() {
    let body = r#"<worldbody><body name="a"><joint name="j" type="hinge"/><geom size="0.1"/>
        </body></worldbody>"#;
    let dir = std::env::temp_dir().join(format!("kjoint-mjcf-include-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = dir.join("notes.txt");
    std::fs::write(&text, "plain text, not a model").unwrap();
    let text = text.display();
    let not_xml = format!(
        "inc.xml: not a valid MJCF model: <include file=\"{text}\"> (line 2): `{text}` is not XML"
    );
    let cases = [
        (
            format!("<mujoco>\n<include file=\"/dev/zero\"/>\n{body}</mujoco>"),
            "inc.xml: not a valid MJCF model: <include file=\"/dev/zero\"> (line 2): larger \
             than 256 MiB, the size cap of input files",
        ),
        (
            format!("<mujoco>\n\n<include file=\"/\"/>\n{body}</mujoco>"),
            "inc.xml: not a valid MJCF model: <include file=\"/\"> (line 3): ",
        ),
        (
            format!("<mujoco>\n<include file=\"{text}\"/>\n{body}</mujoco>"),
            &not_xml,
        ),
        (
            r#"<mujoco><asset><mesh name="m" file="/dev/zero"/></asset><worldbody>
              <body name="a"><joint name="j" type="hinge"/><geom type="mesh" mesh="m"/>
              </body></worldbody></mujoco>"#
                .to_string(),
            "inc.xml: not a valid MJCF model: mesh `m`: file `/dev/zero` is not a regular file",
        ),
        // a mesh geom of <worldbody> itself (it ran out of memory: only the bodies' geoms
        // were checked)
        (
            r#"<mujoco><asset><mesh name="m" file="/dev/zero"/></asset><worldbody>
              <geom type="mesh" mesh="m"/><body name="a"><joint name="j" type="hinge"/>
              <geom size="0.1"/></body></worldbody></mujoco>"#
                .to_string(),
            "inc.xml: not a valid MJCF model: mesh `m`: file `/dev/zero` is not a regular file",
        ),
        // a sub-model for <attach> (mjcf-rs read it whole: the memory ran out)
        (
            format!(
                "<mujoco>\n<asset>\n<model name=\"arm\" file=\"/dev/zero\"/></asset>\n{body}</mujoco>"
            ),
            "inc.xml: not a valid MJCF model: <model file=\"/dev/zero\"> (line 3): larger \
             than 256 MiB, the size cap of input files",
        ),
    ];
    for (xml, expected) in cases {
        let start = std::time::Instant::now();
        let e = load_err(&xml, "inc.xml").to_string();
        println!("{e}");
        assert!(e.starts_with(expected), "{e}");
        // refused before anything is read beyond the cap
        assert!(start.elapsed().as_secs() < 60, "{e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `class="arms"` for a class defined as `arm`: MuJoCo refuses it; mjcf-rs applied the main
/// defaults, so the joint loaded without the class's range and damping (SA± none, C = 0).
#[test]
fn an_undefined_default_class_is_refused_naming_its_element_and_line() {
    let xml = r#"<mujoco>
      <default><default class="arm"><joint range="-10 10" limited="true" damping="2"/></default></default>
      <worldbody><body name="a">
        <joint name="j" class="arms" type="hinge"/><geom size="0.1"/></body></worldbody></mujoco>"#;
    let e = load_err(xml, "cls.xml");
    println!("{e}");
    assert_eq!(
        e.to_string(),
        "cls.xml: <joint name=\"j\"> (line 4): invalid class = arms: expected the class of a \
         <default>"
    );
    // the class written right loads, with its range and damping
    let ok = xml.replace("\"arms\"", "\"arm\"");
    MjcfRobot::from_str(&ok, "cls.xml", ".", &UrdfOptions::default()).expect("loads");
}

/// A reversed hinge range written in degrees (MuJoCo's default) was reported in radians
/// without a unit (`invalid range = 0.5235987755982988 -0.5235987755982988`): reported as
/// written, with its unit.
#[test]
fn a_reversed_hinge_range_is_reported_as_written_with_its_unit() {
    let model = |compiler: &str, range: &str| {
        format!(
            r#"<mujoco>{compiler}<worldbody><body name="b">
            <joint name="j" type="hinge" limited="true" range="{range}"/><geom size="0.1"/>
            </body></worldbody></mujoco>"#
        )
    };
    let err = |xml: String| load_err(&xml, "r.xml").to_string();
    assert_eq!(
        err(model("", "30 -30")),
        "r.xml: joint `j` (body `b`, line 2): invalid range = 30 -30 (degrees): expected lower <= upper"
    );
    assert_eq!(
        err(model(r#"<compiler angle="radian"/>"#, "0.5 -0.25")),
        "r.xml: joint `j` (body `b`, line 2): invalid range = 0.5 -0.25 (rad): expected lower <= upper"
    );
}

/// A model's floor holds it: a `plane` geom becomes a half-space through its `pos` (it was
/// skipped, and a model run with `fixed_base = false` fell through its floor), on the world
/// body or on a body welded to it, and it touches the robot's links without
/// `self_collisions` as with it, by MuJoCo's `contype`/`conaffinity` rule (a floor and geoms
/// of `conaffinity = 0` both ways do not touch: the dumbbell falls through). A floating
/// dumbbell (two 0.1 m balls 0.3 m apart, a hinge along its bar) dropped from 1 m onto a
/// floor 0.1 m up comes to rest with both balls on it, their centres at 0.2 m, the hinge
/// holding within 1.5 mm: the landing leaves a bending moment about the hinge's blocked
/// axis (0.44 N·m, 5 mrad at the automatic stiffness sized for the 1 kg balls) that the
/// balls' friction on the floor keeps, its anchors 1.08 mm apart at rest (1.00 mm before
/// the solve held the balls the floor carries, `held_axes` in src/dynamics/substep.rs).
#[test]
fn a_floor_plane_holds_a_floating_robot_by_mujoco_s_contact_rule() {
    let xml = |floor: &str, conaffinity: &str| {
        format!(
            r#"<mujoco model="dumbbell">
      <default><geom conaffinity="{conaffinity}"/></default>
      <worldbody>
        {floor}
        <body name="left" pos="0 0 1">
          <freejoint/>
          <geom type="sphere" size="0.1" mass="1"/>
          <body name="right" pos="0.3 0 0">
            <joint name="spin" type="hinge" axis="1 0 0" damping="0.1"/>
            <geom type="sphere" size="0.1" mass="1"/>
            <geom type="capsule" fromto="-0.3 0 0 0 0 0" size="0.02" mass="0.1"/>
          </body>
        </body>
      </worldbody>
    </mujoco>"#
        )
    };
    let on_world =
        r#"<geom name="floor" type="plane" size="5 5 0.1" pos="0 0 0.1" conaffinity="1"/>"#;
    let welded = r#"<body name="ground" pos="0 0 0.1">
          <geom name="floor" type="plane" size="5 5 0.1" conaffinity="1"/>
        </body>"#;
    let run = |xml: &str, self_collisions: bool| {
        let (mut w, _) = common::world(Vector::new(0.0, 0.0, -9.81));
        let mut set = common::joints(4);
        let o = UrdfOptions {
            fixed_base: false,
            self_collisions,
            ..Default::default()
        };
        let robot = common::robot::insert_mjcf_str(xml, "dumbbell.xml", ".", &mut w, &mut set, &o)
            .expect("loads");
        for _ in 0..3 * 60 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        let z = |name: &str| w.bodies[robot.links[name]].translation().z as f64;
        (z("left"), z("right"), max_gap(&set).0)
    };
    for floor in [on_world, welded] {
        for self_collisions in [false, true] {
            let (left, right, gap) = run(&xml(floor, "1"), self_collisions);
            let what = format!("{floor} self_collisions {self_collisions}: {left} {right} {gap}");
            assert!((left - 0.2).abs() < 2e-3, "{what}");
            assert!((right - 0.2).abs() < 2e-3, "{what}");
            assert!(gap < 1.5e-3, "{what}");
        }
    }
    // the floor's `conaffinity` 0 and the balls' 0: by MuJoCo's rule they never touch
    let apart = on_world.replace(r#"conaffinity="1""#, r#"conaffinity="0""#);
    for self_collisions in [false, true] {
        let (left, right, _) = run(&xml(&apart, "0"), self_collisions);
        assert!(left < -5.0 && right < -5.0, "{left} {right}");
    }
}

/// The environment is the world and the static bodies from which no moving body hangs: a
/// table declared after a floating robot (whose jointless `head` is fused into it) holds the
/// robot up without `self_collisions`; a fixed arm's mount is the robot's, in its collision
/// group, but a floor on it is a floor; a plane on a moving body is not loaded (a notice).
/// (The table was found by a link's index from before the fusion.)
#[test]
fn a_table_is_environment_and_an_arm_s_mount_is_not() {
    let xml = r#"<mujoco model="room">
      <worldbody>
        <body name="mount" pos="2 0 1">
          <geom type="box" size="0.1 0.1 0.1"/>
          <geom name="floor" type="plane" pos="0 0 -1" size="5 5 0.1"/>
          <body name="arm" pos="0 0 -0.15">
            <joint name="shoulder" type="hinge" axis="0 1 0"/>
            <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.03" mass="1"/>
            <geom type="plane" size="1 1 0.1"/>
          </body>
        </body>
        <body name="block" pos="0 0 1">
          <freejoint/>
          <geom type="box" size="0.1 0.1 0.1" mass="1"/>
          <body name="head" pos="0 0 0.15"><geom type="sphere" size="0.05" mass="0.1"/></body>
        </body>
        <body name="table" pos="0 0 0.5"><geom type="box" size="0.5 0.5 0.05"/></body>
      </worldbody>
    </mujoco>"#;
    let (mut w, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut set = common::joints(4);
    let o = UrdfOptions {
        fixed_base: false,
        ..Default::default()
    };
    let robot =
        common::robot::insert_mjcf_str(xml, "room.xml", ".", &mut w, &mut set, &o).expect("loads");
    assert!(
        robot
            .notices
            .iter()
            .any(|n| n.starts_with("body `arm`: its plane geom is not loaded")),
        "{:?}",
        robot.notices
    );
    assert!(!robot.notices.iter().any(|n| n.starts_with("body `mount`")));
    let groups = |name: &str, k: usize| w.colliders[robot.colliders[name][k]].collision_groups();
    assert_eq!(groups("table", 0), InteractionGroups::all());
    assert_ne!(groups("mount", 0), InteractionGroups::all());
    let floor = w.colliders[robot.colliders["mount"][1]]
        .shape()
        .as_halfspace();
    assert!(floor.is_some());
    assert_eq!(groups("mount", 1), InteractionGroups::all());
    for _ in 0..2 * 60 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    // the block's centre 0.1 m above the table's top (0.55 m); its head fused into it
    let block = w.bodies[robot.links["block"]].translation().z as f64;
    assert!((block - 0.65).abs() < 3e-3, "{block}");
    // MuJoCo's world body is `world`, and so is the loader's world link
    let s = load_err(
        &xml.replace(r#"name="table""#, r#"name="world""#),
        "room.xml",
    )
    .to_string();
    assert!(
        s.starts_with("room.xml: body `world` (line 17): invalid name = world: expected a name other than `world`"),
        "{s}"
    );
}

/// With `self_collisions`, a body of two joints in series does not touch its parent (MuJoCo's
/// parent filter): it hangs on it through a spacer body, and the joints' own contact
/// switches left the pair colliding (gymnasium's humanoid's thighs, 8.7 cm inside its
/// pelvis, were pushed out from the first substep: −33 % of its energy unbooked in 5 s).
#[test]
fn a_body_of_joints_in_series_does_not_touch_its_parent() {
    let xml = r#"<mujoco model="series">
      <worldbody>
        <body name="a" pos="0 0 1">
          <joint name="ja" type="hinge" axis="0 1 0"/>
          <geom type="box" size="0.1 0.1 0.1" mass="1"/>
          <body name="b" pos="0 0 -0.15">
            <joint name="b1" type="hinge" axis="1 0 0"/>
            <joint name="b2" type="hinge" axis="0 1 0"/>
            <geom type="box" size="0.1 0.1 0.1" mass="1"/>
          </body>
        </body>
      </worldbody>
    </mujoco>"#;
    let (mut w, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut set = common::joints(4);
    let o = UrdfOptions {
        self_collisions: true,
        ..Default::default()
    };
    let robot = common::robot::insert_mjcf_str(xml, "series.xml", ".", &mut w, &mut set, &o)
        .expect("loads");
    for _ in 0..3 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    let (a, b) = (robot.colliders["a"][0], robot.colliders["b"][0]);
    let touch = (w.narrow_phase.contact_pair(a, b)).is_some_and(|p| p.has_any_active_contact());
    assert!(!touch, "b overlaps a by 5 cm and must not touch it");
    assert!(max_gap(&set).0 < 1e-3, "{:?}", max_gap(&set));
}

/// The MuJoCo models of gymnasium (`.ci/run` downloads them, `KJOINT_MJCF_MODELS`): each
/// loads and runs 5 s under gravity at 60 Hz × 4 substeps with its free bodies fixed (the
/// default `fixed_base`), then floating (`fixed_base = false`) at 8 substeps: the walkers
/// land on their floors (a landing opens the joints by `O(h)`: the humanoid's 18 mm at 4
/// substeps, 4.5 mm at 8), and no body's centre of mass ends below its model's floor. Each
/// with no NaN and every KJOINT2 joint's anchor gap below 1 cm (1.5 cm for the floating
/// humanoid's fall onto its knees). (The hopper, whose hinge
/// at its torso's middle parted 5.9 mm for a few substeps as it landed, was stopped as
/// unstable while that joint's size was the 1 cm floor: `tests/health.rs`.)
#[test]
fn gymnasium_models_load_and_hold_their_joints_for_five_seconds() {
    let Some(dir) = std::env::var_os("KJOINT_MJCF_MODELS") else {
        eprintln!("NOTICE: KJOINT_MJCF_MODELS is not set: skipping the gymnasium models (.ci/run sets it)");
        return;
    };
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("KJOINT_MJCF_MODELS is a directory")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "xml"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no .xml in {dir:?}");
    let mut failures = Vec::new();
    for f in &files {
        for fixed_base in [true, false] {
            let o = UrdfOptions {
                fixed_base,
                ..Default::default()
            };
            let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
            let mut joints = common::joints(if fixed_base { 4 } else { 8 });
            let name = f.file_name().unwrap().to_string_lossy().to_string();
            let robot = match common::robot::insert_mjcf_file(f, &mut world, &mut joints, &o) {
                Ok(r) => r,
                Err(e) => {
                    failures.push(format!("{name}: {e}"));
                    continue;
                }
            };
            let mut worst = (0.0f64, String::new());
            let mut err = None;
            for _ in 0..5 * 60 {
                if let Err(e) = joints.step(&mut world, 1.0 / 60.0) {
                    err = Some(e.to_string());
                    break;
                }
                let g = max_gap(&joints);
                if g.0.is_nan() || g.0 > worst.0 {
                    worst = g;
                }
            }
            let nan = world
                .bodies
                .iter()
                .any(|(_, b)| !(b.translation().is_finite() && b.linvel().is_finite()));
            // the model's floor (a half-space of its world), and the lowest centre of mass
            // of the bodies that collide with it (pusher's arm has no collider: its geoms are
            // visual), at most 1 cm below it (point's ball slides on it at its centre)
            let floor = (world.colliders.iter())
                .filter(|(_, c)| c.shape().as_halfspace().is_some())
                .map(|(_, c)| (c.translation().z as f64, c.collision_groups()))
                .reduce(|a, b| if a.0 >= b.0 { a } else { b });
            let lowest = (world.bodies.iter())
                .filter(|(_, b)| {
                    b.is_dynamic()
                        && (b.colliders().iter()).any(|c| {
                            floor.is_some_and(|(_, g)| {
                                g.test(world.colliders[*c].collision_groups())
                            })
                        })
                })
                .map(|(_, b)| b.center_of_mass().z as f64)
                .fold(f64::INFINITY, f64::min);
            let floor = floor.map(|(z, _)| z);
            let through = floor.is_some_and(|f| lowest < f - 0.01);
            let line = format!(
                "{name} (fixed_base = {fixed_base}): {} bodies, {} KJOINT2 joints, {} notices, \
                 max gap {:.3e} m ({}), floor {floor:?} m, lowest centre of mass {lowest:.3} m",
                robot.links.len(),
                joints.len(),
                robot.notices.len(),
                worst.0,
                worst.1
            );
            println!("{line}");
            if fixed_base {
                for n in &robot.notices {
                    println!("    {n}");
                }
            }
            // the floating humanoid falls over and lands on its knees, a chaotic landing
            // whose worst opening moves with any change: 6.1 and 9.3 mm (f64, f32), 11.4
            // and 6.9 mm since the contact hold (2026-12-06); 1 cm for every other model
            let bound = if name == "humanoid.xml" && !fixed_base {
                0.015
            } else {
                0.01
            };
            if err.is_some()
                || nan
                || through
                || worst.0.partial_cmp(&bound) != Some(std::cmp::Ordering::Less)
            {
                failures.push(format!(
                    "{line}: error {err:?}, NaN {nan}, through {through}"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Describe, then insert: `MjcfRobot::from_str` then `insert` gives the same handles and
/// notices each time, with the spacer bodies not listed by name.
#[test]
fn describe_then_insert() {
    use rapier_kjoint::io::mjcf::MjcfRobot;
    let o = UrdfOptions::default();
    let robot = MjcfRobot::from_str(KINDS, "kinds.xml", ".", &o).expect("describes");
    assert!(
        robot.links.iter().any(|l| l.spacer),
        "the wrist's two hinges need a spacer"
    );
    let (n_links, n_joints) = (robot.links.len(), robot.joints.len());
    let mut by_parts = (PhysicsWorld::default(), common::joints(4));
    let inserted = robot.insert(&mut by_parts.0, &mut by_parts.1).unwrap();
    let mut at_once = (PhysicsWorld::default(), common::joints(4));
    let loaded =
        common::robot::insert_mjcf_str(KINDS, "kinds.xml", ".", &mut at_once.0, &mut at_once.1, &o);
    assert_eq!(Some(&inserted), loaded.as_ref().ok());
    assert_eq!(by_parts.0.bodies.len(), n_links);
    assert!(inserted.links.len() < n_links);
    assert_eq!(by_parts.1.len(), n_joints);
}

/// A free joint below another body: MuJoCo refuses it ("free joint can only be used on top
/// level"); it loaded, and the body floated off its parent without a word. On a body of
/// `<worldbody>` itself it stays a floating base.
#[test]
fn a_free_joint_below_another_body_is_refused() {
    let d = UrdfOptions::default();
    let xml = r#"<mujoco><worldbody>
      <body name="a"><joint type="hinge"/><geom size="0.1"/>
        <body name="b" pos="0 0 -1"><freejoint name="loose"/><geom size="0.1"/></body>
      </body></worldbody></mujoco>"#;
    let e = load_err(xml, "free.xml");
    let s = e.to_string();
    assert!(matches!(e, UrdfError::Field { .. }), "{s}");
    assert!(
        s.starts_with("free.xml: joint `loose` (body `b`, line 3): invalid type = free")
            && s.contains("<worldbody>"),
        "{s}"
    );
    let top = r#"<mujoco><worldbody>
      <body name="a"><freejoint name="base"/><geom size="0.1"/>
        <body name="b" pos="0 0 -1"><joint type="hinge"/><geom size="0.1"/></body>
      </body></worldbody></mujoco>"#;
    MjcfRobot::from_str(top, "free.xml", ".", &d).expect("a floating base loads");
}

/// The checks of the model name the element's line, found by walking `<worldbody>` as
/// mjcf-rs reads it: an unnamed joint by its place in its body (a `<freejoint>` counting as
/// one), a geom inside a `<frame>` as one of its body's, a body under a frame as the next
/// body; the joints a frame holds, which mjcf-rs does not read, not counted.
#[test]
fn model_errors_name_the_line_of_unnamed_elements_inside_frames() {
    let model = |bad_joint: &str, bad_geom: &str| {
        format!(
            r#"<mujoco>
  <worldbody>
    <geom type="plane" size="1 1 0.1"/>
    <frame pos="0 0 1">
      <joint type="hinge"/>
      <geom size="0.1"/>
      <body name="a">
        <joint type="hinge"/>
        <geom size="0.1"/>
        <frame pos="0 0 -0.5">
          <geom size="0.1"/>
          <body pos="0 0 -1">
            <joint type="hinge"/>
            {bad_joint}
            <geom size="0.1"/>
            {bad_geom}
          </body>
        </frame>
      </body>
    </frame>
  </worldbody>
</mujoco>"#
        )
    };
    let err = |xml: String| load_err(&xml, "lines.xml").to_string();
    // the second joint of the unnamed body (body #2), on line 14
    let s = err(model(r#"<joint type="hinge" damping="-1"/>"#, ""));
    assert!(
        s.starts_with("lines.xml: joint #1 (unnamed, line 14): invalid damping = -1"),
        "{s}"
    );
    // its second geom, on line 16 (line 15 is the first)
    let s = err(model("", r#"<geom type="cylinder" size="-1 0.1"/>"#));
    assert!(
        s.starts_with("lines.xml: geom #1 (body #2 (unnamed), line 16): invalid size = -1"),
        "{s}"
    );
    // the world's own geoms: the plane, then the frame's (line 6)
    let xml = model("", "").replace(
        r#"<frame pos="0 0 1">
      <joint type="hinge"/>
      <geom size="0.1"/>"#,
        r#"<frame pos="0 0 1">
      <joint type="hinge"/>
      <geom size="-2"/>"#,
    );
    let s = err(xml);
    assert!(
        s.starts_with("lines.xml: geom #1 (<worldbody>, line 6): invalid size = -2"),
        "{s}"
    );
}

/// A rotation written with no direction: mjcf-rs read each as the identity without a word,
/// so a body written `quat="0 0 0 0"` loaded unrotated. Refused, naming the element, its
/// line and the attribute; the same rotations written properly load.
#[test]
fn rotations_without_a_direction_are_refused_naming_element_line_and_attribute() {
    let model = |rotation: &str| {
        format!(
            "<mujoco><worldbody>\n<body name=\"b\" {rotation}>\n<joint name=\"j\" type=\"hinge\"/>\
             <geom size=\"0.1\"/></body></worldbody></mujoco>"
        )
    };
    for (rotation, expected) in [
        (
            r#"quat="0 0 0 0""#,
            "invalid quat = 0 0 0 0: expected a quaternion of non-zero norm",
        ),
        (
            r#"axisangle="0 0 0 30""#,
            "invalid axisangle = 0 0 0 30: expected a non-zero axis",
        ),
        (
            r#"zaxis="0 0 0""#,
            "invalid zaxis = 0 0 0: expected a non-zero axis",
        ),
        (
            r#"xyaxes="1 0 0 2 0 0""#,
            "invalid xyaxes = 1 0 0 2 0 0: expected a non-zero x axis and a y axis not parallel",
        ),
        (r#"xyaxes="0 0 0 0 1 0""#, "invalid xyaxes = 0 0 0 0 1 0"),
    ] {
        let e = load_err(&model(rotation), "rot.xml");
        assert!(matches!(e, UrdfError::Field { .. }), "{e}");
        let s = e.to_string();
        assert!(
            s.starts_with(&format!("rot.xml: <body name=\"b\"> (line 2): {expected}")),
            "{rotation}: {s}"
        );
    }
    for rotation in [
        r#"quat="0 0 0 2""#,
        r#"axisangle="0 0 1 30""#,
        r#"zaxis="0 0 1""#,
        r#"xyaxes="1 0 0 0 1 0""#,
    ] {
        let robot = MjcfRobot::from_str(&model(rotation), "rot.xml", ".", &UrdfOptions::default());
        assert!(robot.is_ok(), "{rotation}: {:?}", robot.err());
    }
}

/// An orientation that is not finite (or beyond ±1e12) is refused naming the attribute the
/// user wrote and its value, on a body, a geom and an inertial: `euler="inf 0 0"` on a body
/// was reported as `quat = NaN` (the quaternion mjcf-rs made of it), on a geom as a
/// non-finite pose of the joint's body, and on an inertial not at all (it loaded).
#[test]
fn non_finite_orientations_are_refused_naming_the_attribute_as_written() {
    let model = |body: &str, geom: &str, inertial: &str| {
        format!(
            "<mujoco><worldbody>\n<body name=\"b\" {body}>\n<joint name=\"j\" type=\"hinge\"/>\n\
             <geom name=\"g\" size=\"0.1\" {geom}/>\n<inertial pos=\"0 0 0\" mass=\"1\" \
             diaginertia=\"0.1 0.1 0.1\" {inertial}/>\n</body></worldbody></mujoco>"
        )
    };
    let cases = [
        (
            model(r#"euler="inf 0 0""#, "", ""),
            "<body name=\"b\"> (line 2): invalid euler = inf 0 0: expected finite numbers",
        ),
        (
            model(r#"euler="1e300 0 0""#, "", ""),
            "<body name=\"b\"> (line 2): invalid euler = 1e300 0 0: expected finite numbers \
             within ±1e12",
        ),
        (
            model(r#"axisangle="0 0 1 -inf""#, "", ""),
            "<body name=\"b\"> (line 2): invalid axisangle = 0 0 1 -inf",
        ),
        (
            model(r#"xyaxes="1 0 0 0 nan 0""#, "", ""),
            "<body name=\"b\"> (line 2): invalid xyaxes = 1 0 0 0 nan 0",
        ),
        (
            model(r#"zaxis="0 inf 1""#, "", ""),
            "<body name=\"b\"> (line 2): invalid zaxis = 0 inf 1",
        ),
        (
            model(r#"quat="inf 0 0 1""#, "", ""),
            "<body name=\"b\"> (line 2): invalid quat = inf 0 0 1",
        ),
        (
            model("", r#"euler="inf 0 0""#, ""),
            "<geom name=\"g\"> (line 4): invalid euler = inf 0 0",
        ),
        (
            model("", r#"quat="1 nan 0 0""#, ""),
            "<geom name=\"g\"> (line 4): invalid quat = 1 nan 0 0",
        ),
        (
            model("", "", r#"euler="0 -inf 0""#),
            "<inertial> (line 5): invalid euler = 0 -inf 0",
        ),
    ];
    for (xml, message) in cases {
        let e = load_err(&xml, "rot.xml");
        assert!(matches!(e, UrdfError::Field { .. }), "{e}");
        let s = e.to_string();
        assert!(
            s.starts_with(&format!("rot.xml: {message}")),
            "`{s}` should start with `rot.xml: {message}`"
        );
    }
    // in an `<include>`d file the text is not the model's: the rotation mjcf-rs made of it
    let inc = common::cli::temp_file(
        "mjcf-rotation",
        "part.xml",
        "<mujoco><worldbody><body name=\"b\" euler=\"inf 0 0\"><joint name=\"j\" \
         type=\"hinge\"/><geom size=\"0.1\"/></body></worldbody></mujoco>",
    );
    let xml = format!("<mujoco>\n<include file=\"{}\"/>\n</mujoco>", inc.display());
    let e = load_err(&xml, "inc.xml").to_string();
    assert!(
        e.starts_with("inc.xml: body `b`: invalid orientation = [NaN")
            && e.contains(
                "expected a finite rotation (the quaternion mjcf-rs made of its quat, euler"
            ),
        "{e}"
    );
    // finite orientations within the range load, and the one written is the one used
    let xml = model(r#"euler="0 0 90""#, "", "");
    let robot = MjcfRobot::from_str(&xml, "rot.xml", ".", &UrdfOptions::default()).unwrap();
    let b = robot.links.iter().find(|l| l.name == "b").unwrap();
    let z = b.body.rotation() * Vector::X;
    assert!((z - Vector::Y).length() < 1e-6, "{z:?}");
}

/// `<option>`: its `gravity` is the model's (`RobotDescription::gravity`, which a robot file
/// run as a scene of its own runs under; zero with `<flag gravity="disable"/>`), checked like
/// any number; its `timestep`, other attributes and flags are not used, each with a notice
/// that says so and what the run uses instead. They were ignored without a word.
#[test]
fn option_gravity_is_the_models_and_the_rest_of_option_is_noticed() {
    let model = |option: &str| {
        format!(
            "<mujoco>\n{option}\n<worldbody><body name=\"b\"><joint name=\"j\" type=\"hinge\"/>\
             <geom size=\"0.1\"/></body></worldbody></mujoco>"
        )
    };
    let load = |xml: &str| {
        MjcfRobot::from_str(xml, "opt.xml", ".", &UrdfOptions::default()).expect("loads")
    };
    let robot = load(&model(
        "<option gravity=\"0 0 -1.62\" timestep=\"0.005\" integrator=\"RK4\" iterations=\"50\">\n\
         <flag contact=\"disable\"/>\n</option>",
    ));
    assert_eq!(robot.gravity, Some([0.0, 0.0, -1.62]));
    let all = robot.notices.join("\n");
    println!("{all}");
    assert!(
        all.contains(
            "<option> (line 2): timestep = 0.005 s not used: the joints step at the run's \
             substep (a scene's dt / substeps; 1/60 s frames of 4 substeps when the file runs \
             as a scene of its own; 0.004167 s assumed for this model's friction stiffness)"
        ),
        "{all}"
    );
    assert!(
        all.contains("<option> (line 2): integrator=\"RK4\" iterations=\"50\" not used"),
        "{all}"
    );
    assert!(
        all.contains("<flag> (line 3): contact=\"disable\" not used"),
        "{all}"
    );
    assert!(!all.contains("-1.62"), "gravity is used: {all}");
    // none written: no gravity of the model's own, no notice about <option>
    let robot = load(&model(""));
    assert_eq!(robot.gravity, None);
    assert!(
        !robot.notices.join("\n").contains("<option>"),
        "{:?}",
        robot.notices
    );
    // gravity disabled as in MuJoCo
    let robot = load(&model(
        "<option gravity=\"0 0 -3\"><flag gravity=\"disable\"/></option>",
    ));
    assert_eq!(robot.gravity, Some([0.0; 3]));
    assert!(
        !robot.notices.join("\n").contains("<flag>"),
        "{:?}",
        robot.notices
    );
    // not finite, or beyond 1e12: refused naming <option>, its line and the attribute
    for (option, message) in [
        (
            "<option gravity=\"0 0 inf\"/>",
            "opt.xml: <option> (line 2): invalid gravity = 0 0 inf: expected finite numbers",
        ),
        (
            "<option gravity=\"0 0 -1e300\"/>",
            "opt.xml: <option> (line 2): invalid gravity = 0 0 -1e300: expected finite numbers \
             within ±1e12",
        ),
        (
            "<option timestep=\"nan\"/>",
            "opt.xml: <option> (line 2): invalid timestep = nan: expected finite numbers",
        ),
    ] {
        let e = load_err(&model(option), "opt.xml").to_string();
        assert!(
            e.starts_with(message),
            "`{e}` should start with `{message}`"
        );
    }
}

/// mjcf-rs reads no `<replicate>` (MuJoCo 3), `<composite>` or `<flexcomp>`, nor an
/// `<attach>` inside a `<frame>` or naming no `<asset><model>`: it dropped them without a
/// word, and the bodies and joints they carry were missing from `kjoint check` and the run
/// (exit 0). Each is now named in a notice with its line (and its file when `<include>`d) and
/// what is not loaded; the rest of the model loads.
#[test]
fn mjcf_elements_the_parser_drops_are_named_in_notices_with_their_line() {
    let dir = std::env::temp_dir().join(format!("kjoint-mjcf-unread-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("part.xml"),
        "<mujoco>\n<worldbody>\n<replicate count=\"3\" offset=\"1 0 0\">\n\
         <body name=\"p\"><joint name=\"pj\" type=\"hinge\"/><geom size=\"0.1\"/></body>\n\
         </replicate>\n</worldbody>\n</mujoco>\n",
    )
    .unwrap();
    let xml = r#"<mujoco model="fr">
  <include file="part.xml"/>
  <worldbody>
    <frame pos="0 0 1">
      <body name="a"><joint name="j" type="hinge" axis="0 1 0"/><geom size="0.1"/></body>
      <attach model="arm" body="hand" prefix="x"/>
    </frame>
    <replicate count="2" offset="0 1 0">
      <body name="r">
        <joint name="k" type="hinge" axis="0 1 0"/>
        <inertial pos="0.5 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>
      </body>
    </replicate>
    <body name="c" pos="0 0 2"><joint name="jc" type="hinge"/><geom size="0.1"/>
      <composite type="cable" count="5 1 1" size="1"><geom type="capsule" size=".005"/></composite>
      <attach model="gripper" body="palm" prefix="g"/>
    </body>
    <flexcomp name="cloth" type="grid" count="3 3 1" spacing=".1 .1 .1" dim="2"/>
  </worldbody>
</mujoco>"#;
    let robot = MjcfRobot::from_str(xml, "frame.xml", &dir, &UrdfOptions::default())
        .expect("loads without what mjcf-rs drops");
    std::fs::remove_dir_all(&dir).unwrap();
    let all = robot.notices.join("\n");
    println!("{all}");
    let names: Vec<&str> = robot.joints.iter().map(|j| j.names[0].as_str()).collect();
    assert_eq!(names, ["j", "jc"], "{all}");
    let part = dir.join("part.xml").display().to_string();
    for expected in [
        "<replicate> (line 8): not read by mjcf-rs (the MJCF parser; MuJoCo 3's <replicate>): \
         its 2 copies of 1 body(ies), 1 joint(s) and 0 geom(s) are not loaded"
            .to_string(),
        format!(
            "`{part}`: <replicate> (line 3): not read by mjcf-rs (the MJCF parser; MuJoCo 3's \
             <replicate>): its 3 copies of 1 body(ies), 1 joint(s) and 1 geom(s) are not loaded"
        ),
        "<composite> (line 15): not read by mjcf-rs (the MJCF parser): the bodies, joints and \
         geoms it generates are not loaded"
            .to_string(),
        "<flexcomp name=\"cloth\"> (line 18): not read by mjcf-rs (the MJCF parser): the \
         bodies, joints and geoms it generates are not loaded"
            .to_string(),
        "<attach> (line 6): not read by mjcf-rs (the MJCF parser) inside a <frame>: body `hand` \
         of model `arm` and what hangs on it (bodies, joints, geoms) are not loaded"
            .to_string(),
        "<attach> (line 16): no <asset><model name=\"gripper\"> declares its model: body `palm` \
         of model `gripper` and what hangs on it (bodies, joints, geoms) are not loaded"
            .to_string(),
    ] {
        assert!(all.contains(&expected), "`{expected}` not in:\n{all}");
    }
}

/// A mesh geom whose file is empty (an empty `.obj`, an STL with no facet) was skipped by
/// rapier3d-mjcf with a log line only: the body (no `<inertial>`) loaded with the minimum
/// 0.01 kg and the only notice was "body `a`: no mass in the MJCF". The geom and the file
/// are now named, read by the URDF loader's mesh reader.
#[test]
fn an_empty_mjcf_mesh_file_is_named_in_a_notice() {
    let dir = std::env::temp_dir().join(format!("kjoint-mjcf-empty-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("empty.obj"), "").unwrap();
    std::fs::write(dir.join("empty.stl"), "solid x\nendsolid x\n").unwrap();
    let xml = r#"<mujoco model="em">
      <asset><mesh name="e" file="empty.obj"/><mesh name="s" file="empty.stl"/></asset>
      <worldbody>
        <body name="a" pos="0 0 1"><joint name="j" type="hinge" axis="0 1 0"/>
          <geom name="hull" type="mesh" mesh="e" pos="0.5 0 0"/></body>
        <body name="b" pos="2 0 1"><joint name="k" type="hinge" axis="0 1 0"/>
          <geom type="mesh" mesh="s" pos="0.5 0 0"/></body>
      </worldbody></mujoco>"#;
    let robot =
        MjcfRobot::from_str(xml, "emptymesh.xml", &dir, &UrdfOptions::default()).expect("loads");
    let all = robot.notices.join("\n");
    println!("{all}");
    for (geom, mesh, file) in [
        ("geom `hull` (body `a`)", "e", "empty.obj"),
        ("geom #0 (body `b`)", "s", "empty.stl"),
    ] {
        let expected = format!(
            "{geom}: mesh `{mesh}`: file `{}` unreadable: no triangles: skipped (no collider, \
             and no mass from it)",
            dir.join(file).display()
        );
        assert!(all.contains(&expected), "`{expected}` not in:\n{all}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// With `self_collisions`, a `<contact><exclude>` leaves two links that are not joined
/// apart (here a link and its grandchild, folded onto it): without it their geoms touch,
/// with it not; the pairs joined by a joint do not touch either way. So does MuJoCo's rule
/// of `contype` and `conaffinity` (geoms of `conaffinity = 0`, gymnasium's walkers', touch
/// the floor and never each other), and each link still touches a collider of the user's.
#[test]
fn mjcf_excludes_and_contype_leave_two_links_apart_where_the_links_collide() {
    let xml = |defaults: &str, exclude: &str| {
        format!(
            r#"<mujoco model="folded">
      <default>{defaults}</default>
      <worldbody>
        <body name="a" pos="0 0 1">
          <joint name="j1" type="hinge" axis="0 1 0"/>
          <geom name="ga" type="box" size="0.1 0.1 0.1" mass="1"/>
          <body name="b" pos="0.5 0 0">
            <joint name="j2" type="hinge" axis="0 1 0"/>
            <geom name="gb" type="box" size="0.1 0.1 0.1" pos="0 0 0.3" mass="1"/>
            <body name="c" pos="-0.69 0 0">
              <joint name="j3" type="hinge" axis="0 1 0"/>
              <geom name="gc" type="box" size="0.1 0.1 0.1" mass="1"/>
            </body>
          </body>
        </body>
      </worldbody>
      <contact>{exclude}</contact>
    </mujoco>"#
        )
    };
    let touching = |defaults: &str, exclude: &str| {
        let (mut w, _) = common::world(Vector::ZERO);
        // a ground of the user's, 1 mm below link a's box
        let ground = w.insert_collider(
            ColliderBuilder::cuboid(2.0, 2.0, 0.1).translation(Vector::new(0.0, 0.0, 0.799)),
            None,
        );
        let mut set = common::joints(4);
        let o = UrdfOptions {
            self_collisions: true,
            ..Default::default()
        };
        let robot = common::robot::insert_mjcf_str(
            &xml(defaults, exclude),
            "folded.xml",
            ".",
            &mut w,
            &mut set,
            &o,
        )
        .expect("loads");
        for _ in 0..3 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        let touch = |x: ColliderHandle, y: ColliderHandle| {
            (w.narrow_phase.contact_pair(x, y)).is_some_and(|p| p.has_any_active_contact())
        };
        let c = |name: &str| robot.colliders[name][0];
        let pair = |x: &str, y: &str| touch(c(x), c(y));
        assert!(touch(c("a"), ground), "link a off the ground");
        (pair("a", "c"), pair("a", "b") || pair("b", "c"))
    };
    // a and c overlap by 1 cm; the joined pairs are apart either way
    assert_eq!(touching("", ""), (true, false));
    assert_eq!(
        touching("", r#"<exclude body1="a" body2="c"/>"#),
        (false, false)
    );
    assert_eq!(
        touching(r#"<geom contype="1" conaffinity="0"/>"#, ""),
        (false, false)
    );
}

/// Two copies of the MJCF model `xml` (named `file`) inserted into `w` and `set`, the
/// second `apart` from the first (`fixed_base` as given): their handles, and the number of
/// half-spaces in the world after them.
fn two_copies(
    xml: &str,
    file: &str,
    w: &mut PhysicsWorld,
    set: &mut KjointSet,
    fixed_base: bool,
    apart: Vector,
) -> (Vec<rapier_kjoint::io::urdf::UrdfRobotHandles>, usize) {
    let mut robots = Vec::new();
    for at in [Vector::ZERO, apart] {
        let o = UrdfOptions {
            fixed_base,
            base_pose: Pose::from_translation(at),
            ..Default::default()
        };
        robots.push(common::robot::insert_mjcf_str(xml, file, ".", w, set, &o).expect("loads"));
    }
    let planes = (w.colliders.iter())
        .filter(|(_, c)| c.shape().as_halfspace().is_some())
        .count();
    (robots, planes)
}

/// Copies of a model standing on one floor share it: a `plane` that is the same plane as a
/// half-space already in the world (with the same friction and groups) is not inserted
/// again, with a notice. A model inserted N times (a reinforcement-learning batch) brought
/// N floors, each touching every copy (16 ants: 768 contact pairs, rapier's time growing
/// as N²; a user trial, 2026-12-04). Two dumbbells placed 2 m apart land on the one floor;
/// the user's own ground at the same height, of rapier's default friction (0.5, the
/// model's floor MuJoCo's 1), is another floor.
#[test]
fn copies_of_a_model_share_its_floor() {
    let xml = r#"<mujoco model="dumbbell">
      <worldbody>
        <geom name="floor" type="plane" size="5 5 0.1" pos="0 0 0.1"/>
        <body name="left" pos="0 0 1">
          <freejoint/>
          <geom type="sphere" size="0.1" mass="1"/>
          <body name="right" pos="0.3 0 0">
            <joint name="spin" type="hinge" axis="1 0 0" damping="0.1"/>
            <geom type="sphere" size="0.1" mass="1"/>
          </body>
        </body>
      </worldbody>
    </mujoco>"#;
    let (mut w, ground) = common::world(Vector::new(0.0, 0.0, -9.81));
    w.colliders.insert_with_parent(
        ColliderBuilder::new(SharedShape::halfspace(Vector::Z))
            .translation(Vector::new(0.0, 0.0, 0.1)),
        ground,
        &mut w.bodies,
    );
    let mut set = common::joints(4);
    let (robots, planes) = two_copies(
        xml,
        "dumbbell.xml",
        &mut w,
        &mut set,
        false,
        Vector::X * 2.0,
    );
    assert_eq!(
        planes, 2,
        "the user's ground and one floor for the two copies"
    );
    let shared: Vec<bool> = robots
        .iter()
        .map(|r| {
            r.notices
                .iter()
                .any(|n| n.contains("its floor (a half-space)"))
        })
        .collect();
    assert_eq!(shared, [false, true], "{:?}", robots[1].notices);
    for _ in 0..3 * 60 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    for r in &robots {
        for link in ["left", "right"] {
            let z = w.bodies[r.links[link]].translation().z as f64;
            assert!((z - 0.2).abs() < 2e-3, "{link} at {z}");
        }
    }
}

/// A copy that shares another's floor takes its own contact exclusions with it: a cart on a
/// slide joint to the world body does not touch the world's geoms (the joint's contacts
/// are off), and the first copy's floor, on that copy's world body, touched the second
/// copy's cart (a review, 2026-12-04; two floors, one per copy, would each touch the other
/// copy's cart). Two copies of a cart sunk 5 cm into its floor: one floor, and each rail
/// carries its cart's weight alone, not a contact.
#[test]
fn a_copy_sharing_a_floor_keeps_its_contact_exclusions_with_it() {
    let xml = r#"<mujoco model="rail">
      <worldbody>
        <geom name="floor" type="plane" size="5 5 0.1"/>
        <body name="cart" pos="0 0 0.05">
          <joint name="rail" type="slide" axis="1 0 0"/>
          <geom type="sphere" size="0.1" mass="1"/>
        </body>
      </worldbody>
    </mujoco>"#;
    let (mut w, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut set = common::joints(4);
    let (robots, planes) = two_copies(xml, "rail.xml", &mut w, &mut set, true, Vector::Y * 2.0);
    assert_eq!(planes, 1, "{:?}", robots[1].notices);
    assert!(
        (robots[1].notices.iter()).any(|n| n.contains("its floor (a half-space)")),
        "{:?}",
        robots[1].notices
    );
    for _ in 0..60 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    for r in &robots {
        let s = set[r.joints["rail"]].state().expect("stepped");
        let across = s.applied[Dof::Dy].hypot(s.applied[Dof::Dz]);
        assert!(
            (across - 9.81).abs() < 0.02 * 9.81,
            "the rail carries {across} N"
        );
    }
}
