//! Trial (robotics engineer): quadrupeds (A1, Go1) with a floating base on a ground box,
//! joints held by position motors at a crouched standing pose; placed on the ground and
//! dropped from 0.3 m, at 4, 8 and 16 substeps.
//!
//! cargo run --release --example trial_robot_legs

use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;
use std::time::Instant;

const ROOT: &str = "target/ci/robot-urdfs-6/example-robot-data/robots";

fn options(substeps: usize, crouch: bool) -> UrdfOptions {
    let mut o = UrdfOptions {
        substep: 1.0 / (60.0 * substeps as f64),
        fixed_base: false,
        ..Default::default()
    };
    if crouch {
        for leg in ["FR", "FL", "RR", "RL"] {
            o.initial_positions.insert(format!("{leg}_thigh_joint"), 0.8);
            o.initial_positions.insert(format!("{leg}_calf_joint"), -1.6);
        }
    }
    o
}

fn lowest_point(file: &str, o: &UrdfOptions) -> Result<f32, Box<dyn std::error::Error>> {
    let mut world = PhysicsWorld::default();
    let mut joints = KjointSet::new();
    let _ = UrdfRobot::from_file(file, o)?.insert(&mut world, &mut joints)?;
    let mut zmin = f32::INFINITY;
    for (_, c) in world.colliders.iter() {
        zmin = zmin.min(c.compute_aabb().mins.z);
    }
    Ok(zmin)
}

fn run(robot_file: &str, base_link: &str, substeps: usize, drop: f32, kp: f64, kd: f64, verbose: bool) -> Result<(), Box<dyn std::error::Error>> {
    let file = format!("{ROOT}/{robot_file}");
    let frame_dt = 1.0 / 60.0;
    let mut o = options(substeps, true);
    let zmin = lowest_point(&file, &o)?;
    o.base_pose = Pose::from_translation(Vector::new(0.0, 0.0, -zmin + 0.001 + drop));
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..Default::default()
    };
    let ground = world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.5)));
    world.insert_collider(ColliderBuilder::cuboid(20.0, 20.0, 0.5).friction(0.8), Some(ground));
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let robot = UrdfRobot::from_file(&file, &o)?.insert(&mut world, &mut joints)?;
    if verbose {
        for n in &robot.notices {
            println!("  notice: {n}");
        }
    }
    let mut motored = 0;
    for (name, h) in &robot.joints {
        if name.ends_with("_joint") && (name.contains("hip") || name.contains("thigh") || name.contains("calf")) {
            joints.set_motor(*h, Dof::Rx, Some(KjointMotor::position(0.0, kp, kd)))?;
            motored += 1;
        }
    }
    let base = robot.links[base_link];
    let z0 = world.bodies[base].translation().z;
    let frames = (5.0 / frame_dt) as usize;
    let (mut zmin_run, mut gap_max, mut gap_worst, mut rot_max) = (f32::INFINITY, 0.0f64, String::new(), 0.0f64);
    let mut n_events = 0;
    let mut cpu = 0.0;
    let mut failed = None;
    let mut z_at_1s = f32::NAN;
    for frame in 0..frames {
        let t0 = Instant::now();
        let r = joints.step(&mut world, frame_dt);
        cpu += t0.elapsed().as_secs_f64();
        for e in joints.drain_events() {
            if n_events < 0 && (e.severity() != Severity::Info) {
                println!("    event: {e}");
            }
            n_events += 1;
        }
        if let Err(e) = r {
            failed = Some(format!("t = {:.3} s: {e}", frame as f64 * frame_dt));
            break;
        }
        let z = world.bodies[base].translation().z;
        zmin_run = zmin_run.min(z);
        if frame == 59 {
            z_at_1s = z;
        }
        for (name, h) in &robot.joints {
            if let Some(s) = joints.get(*h).and_then(|j| j.state()) {
                let g = ((s.anchor1[0] - s.anchor2[0]).powi(2) + (s.anchor1[1] - s.anchor2[1]).powi(2) + (s.anchor1[2] - s.anchor2[2]).powi(2)).sqrt();
                if g > gap_max {
                    gap_max = g;
                    gap_worst = name.clone();
                }
                rot_max = rot_max.max(s.q[Dof::Ry].abs()).max(s.q[Dof::Rz].abs());
            }
        }
    }
    let (mut gap_end, mut rot_end) = (0.0f64, 0.0f64);
    for h in robot.joints.values() {
        if let Some(s) = joints.get(*h).and_then(|j| j.state()) {
            let g = ((s.anchor1[0] - s.anchor2[0]).powi(2) + (s.anchor1[1] - s.anchor2[1]).powi(2) + (s.anchor1[2] - s.anchor2[2]).powi(2)).sqrt();
            gap_end = gap_end.max(g);
            rot_end = rot_end.max(s.q[Dof::Ry].abs()).max(s.q[Dof::Rz].abs());
        }
    }
    println!("      at rest (5 s): worst gap {:.3} mm, worst blocked rotation {:.4} rad", gap_end * 1e3, rot_end);
    let b = &world.bodies[base];
    let up = b.rotation() * Vector::Z;
    println!(
        "{:<10} sub {:>2} drop {:.2} m kp {:>5} motors {:>2}: base z0 {:.4} -> min {:.4}, 1 s {:.4}, end {:.4} (sag {:+.2} mm); tilt {:.2}°; gap max {:.3} mm ({}); blocked rot max {:.4} rad; events {}; {:.3} ms/frame{}",
        robot_file.split('/').next_back().unwrap(),
        substeps,
        drop,
        kp,
        motored,
        z0,
        zmin_run,
        z_at_1s,
        b.translation().z,
        (z0 - drop - b.translation().z) * 1e3,
        up.z.clamp(-1.0, 1.0).acos().to_degrees(),
        gap_max * 1e3,
        gap_worst,
        rot_max,
        n_events,
        cpu / frames as f64 * 1e3,
        failed.map(|f| format!("  FAILED {f}")).unwrap_or_default()
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let robots = [("a1_description/urdf/a1.urdf", "trunk"), ("go1_description/urdf/go1.urdf", "trunk")];
    for (i, (f, base)) in robots.iter().enumerate() {
        for substeps in [4, 8, 16] {
            for drop in [0.0f32, 0.3] {
                if let Err(e) = run(f, base, substeps, drop, 150.0, 3.0, i == 0 && substeps == 4 && drop == 0.0) {
                    println!("{f} sub {substeps} drop {drop}: ERROR {e}");
                }
            }
        }
    }
    Ok(())
}
