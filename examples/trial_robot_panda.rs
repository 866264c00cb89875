//! Trial (robotics engineer): a Franka Panda at its ready pose held by position motors on
//! every arm joint (fingers left to the loader's defaults), 10 s: hand drift, joint errors,
//! torques and gaps at 4 and 16 substeps; gravity torques cross-checked from the loaded bodies.
//!
//! cargo run --release --example trial_robot_panda

use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;

const PANDA: &str = "target/ci/robot-urdfs-6/example-robot-data/robots/panda_description/urdf/panda.urdf";

fn run(substeps: usize, kp: f64, kd: f64) -> Result<(), Box<dyn std::error::Error>> {
    let frame_dt = 1.0 / 60.0;
    let mut o = UrdfOptions {
        substep: frame_dt / substeps as f64,
        ..Default::default()
    };
    for (j, q) in [("panda_joint2", -0.785), ("panda_joint4", -2.356), ("panda_joint6", 1.571), ("panda_joint7", 0.785)] {
        o.initial_positions.insert(j.into(), q);
    }
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..Default::default()
    };
    let mut joints = KjointSet::with_settings(SubstepSettings { substeps, ..Default::default() });
    let robot = UrdfRobot::from_file(PANDA, &o)?.insert(&mut world, &mut joints)?;
    if substeps == 4 {
        for n in robot.notices.iter().filter(|n| !n.contains("mesh")) {
            println!("  notice: {n}");
        }
        println!("  joints: {:?}", robot.joints.keys().collect::<Vec<_>>());
    }
    let arm: Vec<String> = (1..=7).map(|i| format!("panda_joint{i}")).collect();
    for n in &arm {
        joints.set_motor(robot.joints[n.as_str()], Dof::Rx, Some(KjointMotor::position(0.0, kp, kd)))?;
    }
    let hand_link = if robot.links.contains_key("panda_hand") { "panda_hand" } else { "panda_link7" };
    let hand = robot.links[hand_link];
    let p0 = world.bodies[hand].translation();
    let frames = (10.0 / frame_dt) as usize;
    let (mut dmax, mut gmax, mut gworst) = (0.0f32, 0.0f64, String::new());
    let mut nev = 0;
    for _ in 0..frames {
        joints.step(&mut world, frame_dt)?;
        for e in joints.drain_events() {
            if e.severity() != Severity::Info && nev < 4 {
                println!("    event: {e}");
            }
            nev += 1;
        }
        dmax = dmax.max((world.bodies[hand].translation() - p0).length());
        for (n, h) in &robot.joints {
            if let Some(s) = joints.get(*h).and_then(|j| j.state()) {
                let g = ((s.anchor1[0] - s.anchor2[0]).powi(2) + (s.anchor1[1] - s.anchor2[1]).powi(2) + (s.anchor1[2] - s.anchor2[2]).powi(2)).sqrt();
                if g > gmax {
                    gmax = g;
                    gworst = n.clone();
                }
            }
        }
    }
    let p = world.bodies[hand].translation();
    println!(
        "panda {substeps:>2} substeps kp {kp}: {hand_link} drift end {:.3} mm (z {:+.3} mm), max {:.3} mm; worst gap {:.4} mm ({gworst}); events {nev}",
        (p - p0).length() * 1e3,
        (p.z - p0.z) * 1e3,
        dmax * 1e3,
        gmax * 1e3
    );
    // gravity torque about each arm joint from the loaded bodies beyond it (subtree = bodies
    // whose joint chain passes through it: here the links after it in the serial chain)
    let chain: Vec<&str> = vec!["panda_link1", "panda_link2", "panda_link3", "panda_link4", "panda_link5", "panda_link6", "panda_link7", hand_link];
    for (k, n) in arm.iter().enumerate() {
        let j = joints.get(robot.joints[n.as_str()]).unwrap();
        let s = j.state().unwrap();
        // axis and anchor in world from the joint's frame
        let q = s.frame;
        let rot = Rotation::from_xyzw(q[0] as f32, q[1] as f32, q[2] as f32, q[3] as f32);
        let axis = rot * Vector::X;
        let a = Vector::new(s.anchor2[0] as f32, s.anchor2[1] as f32, s.anchor2[2] as f32);
        let mut tau = 0.0f64;
        let mut seen = std::collections::HashSet::new();
        for l in &chain[k..] {
            let b = robot.links[*l];
            if !seen.insert(b) {
                continue;
            }
            let body = &world.bodies[b];
            let r = body.center_of_mass() - a;
            let f = Vector::new(0.0, 0.0, -9.81 * body.mass());
            tau += r.cross(f).dot(axis) as f64;
        }
        // fingers ride on the hand
        for (ln, b) in &robot.links {
            if ln.contains("finger") && seen.insert(*b) {
                let body = &world.bodies[*b];
                let r = body.center_of_mass() - a;
                tau += r.cross(Vector::new(0.0, 0.0, -9.81 * body.mass())).dot(axis) as f64;
            }
        }
        println!(
            "   {n}: q−q0 {:+.5} rad (τ_g/kp {:+.5}), applied {:+8.3} N·m, gravity torque of the bodies beyond {:+8.3} N·m",
            s.q[Dof::Rx],
            tau / kp,
            s.applied[Dof::Rx],
            tau
        );
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    run(4, 1000.0, 30.0)?;
    run(16, 1000.0, 30.0)?;
    Ok(())
}
