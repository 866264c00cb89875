//! Trial (robotics engineer): broken URDF files. Each must give a typed error or a notice
//! naming the file and the element, never a panic; the ones that load are stepped 1 s.
//!
//! cargo run --release --example trial_robot_misuse

use rapier_kjoint::io::urdf::{JointOverride, UrdfOptions, UrdfRobot};
use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;

const TEMPLATE: &str = r#"<?xml version="1.0"?>
<robot name="trial">
  <link name="base">
    <inertial><mass value="2.0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="AXIS"/>
    <limit lower="LOWER" upper="UPPER" effort="50" velocity="3"/>
  </joint>
  <link name="upper">
    <inertial><origin xyz="0.25 0 0"/><mass value="MASS"/><inertia ixx="IXX" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>
    <collision><geometry>GEOM</geometry></collision>
  </link>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="fore"/>
    <origin xyz="0.5 0 0" rpy="0 0 0"/>
    <axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="50" velocity="3"/>
  </joint>
  <link name="fore">
    <inertial><origin xyz="0.2 0 0"/><mass value="1.0"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
</robot>
"#;

fn urdf(subs: &[(&str, &str)]) -> String {
    let mut s = TEMPLATE.to_string();
    let defaults = [
        ("AXIS", "0 1 0"),
        ("LOWER", "-1.5"),
        ("UPPER", "1.5"),
        ("MASS", "3.0"),
        ("IXX", "0.002"),
        ("GEOM", r#"<box size="0.5 0.05 0.05"/>"#),
    ];
    for (k, v) in defaults {
        let v = subs.iter().find(|(kk, _)| *kk == k).map(|(_, v)| *v).unwrap_or(v);
        s = s.replace(k, v);
    }
    s
}

fn try_case(name: &str, text: Option<String>, path_override: Option<&str>, options: UrdfOptions) {
    let dir = std::path::Path::new("/tmp/trial_robot/misuse");
    std::fs::create_dir_all(dir).unwrap();
    let path = match path_override {
        Some(p) => std::path::PathBuf::from(p),
        None => {
            let p = dir.join(format!("{name}.urdf"));
            std::fs::write(&p, text.unwrap()).unwrap();
            p
        }
    };
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| -> Result<String, String> {
        let desc = UrdfRobot::from_file(&path, &options).map_err(|e| format!("from_file error: {e}"))?;
        let mut world = PhysicsWorld {
            gravity: Vector::new(0.0, 0.0, -9.81),
            ..Default::default()
        };
        let mut joints = KjointSet::new();
        let robot = desc.insert(&mut world, &mut joints).map_err(|e| format!("insert error: {e}"))?;
        let mut out = String::new();
        for n in &robot.notices {
            out.push_str(&format!("\n      notice: {n}"));
        }
        for _ in 0..60 {
            if let Err(e) = joints.step(&mut world, 1.0 / 60.0) {
                return Err(format!("step error: {e}{out}"));
            }
        }
        let mut worst: f64 = 0.0;
        for h in robot.joints.values() {
            if let Some(s) = joints.get(*h).and_then(|j| j.state()) {
                let g = ((s.anchor1[0] - s.anchor2[0]).powi(2) + (s.anchor1[1] - s.anchor2[1]).powi(2) + (s.anchor1[2] - s.anchor2[2]).powi(2)).sqrt();
                worst = worst.max(g);
            }
        }
        let finite = world.bodies.iter().all(|(_, b)| b.translation().is_finite());
        let mut ev = String::new();
        for e in joints.drain_events() {
            if e.severity() != Severity::Info {
                ev.push_str(&format!("\n      event: {e}"));
            }
        }
        Ok(format!("loaded and ran 1 s: worst gap {:.3} mm, finite {finite}{out}{ev}", worst * 1e3))
    }));
    match result {
        Ok(Ok(s)) => println!("[{name}] OK: {s}"),
        Ok(Err(e)) => println!("[{name}] ERR: {e}"),
        Err(_) => println!("[{name}] PANIC"),
    }
}

fn main() {
    std::panic::set_hook(Box::new(|info| eprintln!("panic: {info}")));
    let d = UrdfOptions::default;
    try_case("baseline", Some(urdf(&[])), None, d());
    try_case("missing_mesh", Some(urdf(&[("GEOM", r#"<mesh filename="meshes/nope.stl"/>"#)])), None, d());
    try_case("missing_package_mesh", Some(urdf(&[("GEOM", r#"<mesh filename="package://nopkg/meshes/nope.stl"/>"#)])), None, d());
    std::fs::create_dir_all("/tmp/trial_robot/misuse/meshes").unwrap();
    std::fs::write("/tmp/trial_robot/misuse/meshes/garbage.stl", b"this is not an stl file at all").unwrap();
    try_case("garbage_mesh", Some(urdf(&[("GEOM", r#"<mesh filename="meshes/garbage.stl"/>"#)])), None, d());
    std::fs::write("/tmp/trial_robot/misuse/meshes/empty.stl", b"").unwrap();
    try_case("empty_mesh", Some(urdf(&[("GEOM", r#"<mesh filename="meshes/empty.stl"/>"#)])), None, d());
    try_case("nan_inertia", Some(urdf(&[("IXX", "nan")])), None, d());
    try_case("NaN_inertia", Some(urdf(&[("IXX", "NaN")])), None, d());
    try_case("inf_inertia", Some(urdf(&[("IXX", "inf")])), None, d());
    try_case("negative_inertia", Some(urdf(&[("IXX", "-0.5")])), None, d());
    try_case("nan_mass", Some(urdf(&[("MASS", "NaN")])), None, d());
    try_case("zero_mass_link", Some(urdf(&[("MASS", "0"), ("IXX", "0")])), None, d());
    try_case("zero_mass_with_inertia", Some(urdf(&[("MASS", "0")])), None, d());
    try_case("negative_mass", Some(urdf(&[("MASS", "-3")])), None, d());
    try_case("huge_mass", Some(urdf(&[("MASS", "1e30")])), None, d());
    try_case("tiny_mass", Some(urdf(&[("MASS", "1e-12"), ("IXX", "1e-15")])), None, d());
    try_case("limits_inverted", Some(urdf(&[("LOWER", "1.0"), ("UPPER", "-1.0")])), None, d());
    try_case("limits_inverted_both_positive", Some(urdf(&[("LOWER", "1.0"), ("UPPER", "0.5")])), None, d());
    try_case("limits_nan", Some(urdf(&[("LOWER", "nan")])), None, d());
    try_case("zero_axis", Some(urdf(&[("AXIS", "0 0 0")])), None, d());
    try_case("nan_axis", Some(urdf(&[("AXIS", "nan 0 1")])), None, d());
    try_case("axis_two_numbers", Some(urdf(&[("AXIS", "0 1")])), None, d());
    try_case("missing_parent", Some(urdf(&[]).replace(r#"<parent link="upper"/>"#, r#"<parent link="ghost"/>"#)), None, d());
    try_case("truncated", Some(urdf(&[])[..700].to_string()), None, d());
    try_case("empty_file", Some(String::new()), None, d());
    try_case("nonexistent_path", None, Some("/tmp/trial_robot/misuse/does_not_exist.urdf"), d());
    try_case("directory_path", None, Some("/tmp/trial_robot/misuse"), d());
    // options misuse
    let mut o = d();
    o.initial_positions.insert("no_such_joint".into(), 0.3);
    try_case("initial_position_unknown_joint", Some(urdf(&[])), None, o);
    let mut o = d();
    o.initial_positions.insert("shoulder".into(), 3.0);
    try_case("initial_position_outside_limits", Some(urdf(&[])), None, o);
    let mut o = d();
    o.joints.insert("no_such_joint".into(), JointOverride { friction: Some(1.0), ..Default::default() });
    try_case("override_unknown_joint", Some(urdf(&[])), None, o);
    let mut o = d();
    o.substep = f64::NAN;
    try_case("substep_nan", Some(urdf(&[])), None, o);
    let mut o = d();
    o.min_link_mass = -1.0;
    try_case("min_link_mass_negative", Some(urdf(&[("MASS", "0"), ("IXX", "0")])), None, o);
    let mut o = d();
    o.joints.insert(
        "shoulder".into(),
        JointOverride { motor: Some(rapier_kjoint::io::urdf::RapierMotor { target: f64::NAN, stiffness: 100.0, damping: 1.0, max_force: None }), ..Default::default() },
    );
    try_case("motor_target_nan", Some(urdf(&[])), None, o);
    // API misuse on a loaded robot: motor target NaN at run time, force on a missing joint
    let p = "/tmp/trial_robot/misuse/baseline.urdf";
    let desc = UrdfRobot::from_file(p, &d()).unwrap();
    let mut world = PhysicsWorld::default();
    let mut joints = KjointSet::new();
    let robot = desc.insert(&mut world, &mut joints).unwrap();
    println!("set_motor_target on a joint without motor: {:?}", robot.set_motor_target(&mut joints, "shoulder", 0.1, 0.0));
    println!("set_motor_force NaN: {:?}", robot.set_motor_force(&mut joints, "shoulder", f64::NAN).map_err(|e| e.to_string()));
    println!("set_motor_force unknown joint: {:?}", robot.set_motor_force(&mut joints, "ghost", 1.0));
    let h = robot.joints["shoulder"];
    println!(
        "set_motor(Dof::Ry blocked): {:?}",
        joints.set_motor(h, Dof::Ry, Some(KjointMotor::position(0.0, 10.0, 1.0))).map_err(|e| e.to_string())
    );
    println!(
        "set_motor negative stiffness: {:?}",
        joints.set_motor(h, Dof::Rx, Some(KjointMotor::position(0.0, -10.0, 1.0))).map_err(|e| e.to_string())
    );
}
