//! Trial (robotics engineer): a UR5 on a fixed base held at its zero pose by position
//! motors; end-effector sag over 10 s, joint torques against hand-computed gravity
//! torques, anchor gaps; then the same robot on rapier's own joints (multibody and
//! impulse) in the same program, one thread.
//!
//! cargo run --release --example trial_robot_arm

use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;
use std::time::Instant;

const UR5: &str = "target/ci/robot-urdfs-6/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf";
const JOINTS: [&str; 6] = [
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
];
const G: f64 = 9.81;
const EE_LOCAL: [f32; 3] = [0.0, 0.0823, 0.0]; // ee_fixed_joint origin in wrist_3_link

/// Hand computation from the URDF inertials at q = 0 (arm straight out along +x):
/// shoulder_lift axis at x = 0: upper arm 8.393 kg at 0.28, forearm 2.275 kg at
/// 0.425 + 0.25, wrists 1.219 + 1.219 + 0.1879 kg at 0.425 + 0.39225.
fn hand_torques() -> [f64; 6] {
    let x_w = 0.425 + 0.39225;
    let wrists = 1.219 + 1.219 + 0.1879;
    let t_lift = G * (8.393 * 0.28 + 2.275 * (0.425 + 0.25) + wrists * x_w);
    let t_elbow = G * (2.275 * 0.25 + wrists * 0.39225);
    [0.0, t_lift, t_elbow, 0.0, 0.0, 0.0]
}

fn gains(i: usize) -> (f64, f64) {
    if i < 3 {
        (1.0e4, 300.0)
    } else {
        (2.0e3, 20.0)
    }
}

struct Stats {
    label: String,
    ee_sag_final: f64,   // z drop of the EE point at the end [m]
    ee_drift_max: f64,   // max |Δp| over the run [m]
    ee_drift_final: f64, // |Δp| at the end
    q_final: [f64; 6],
    torque: [f64; 6],
    motor: [f64; 6],
    gap_max: f64,
    gap_worst: String,
    ms_per_frame: f64,
    events: usize,
}

fn v3(p: Vector) -> [f64; 3] {
    [p.x as f64, p.y as f64, p.z as f64]
}
fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn kjoint_hold(substeps: usize, ff: bool, seconds: f64, print_notices: bool) -> Result<Stats, Box<dyn std::error::Error>> {
    let frame_dt = 1.0 / 60.0;
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..Default::default()
    };
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let options = UrdfOptions {
        substep: frame_dt / substeps as f64,
        ..Default::default()
    };
    let desc = UrdfRobot::from_file(UR5, &options)?;
    let robot = desc.insert(&mut world, &mut joints)?;
    if print_notices {
        for n in &robot.notices {
            println!("  notice: {n}");
        }
        let total: f64 = world.bodies.iter().filter(|(_, b)| b.is_dynamic()).map(|(_, b)| b.mass() as f64).sum();
        println!("  dynamic mass in world before the first step: {total:.4} kg");
        println!("  joints: {:?}", robot.joints.keys().collect::<Vec<_>>());
        // gravity torque computed from the bodies as loaded (COM, mass)
    }
    let tau = hand_torques();
    for (i, name) in JOINTS.iter().enumerate() {
        let h = robot.joints[*name];
        let (kp, kd) = gains(i);
        let mut m = KjointMotor::position(0.0, kp, kd);
        if ff {
            m = m.with_force(-tau[i]);
        }
        joints.set_motor(h, Dof::Rx, Some(m))?;
    }
    let ee_body = robot.links["wrist_3_link"];
    let ee_local = Vector::new(EE_LOCAL[0], EE_LOCAL[1], EE_LOCAL[2]);
    let p0 = v3(world.bodies[ee_body].position() * ee_local);
    let frames = (seconds / frame_dt).round() as usize;
    let mut drift_max: f64 = 0.0;
    let mut gap_max: f64 = 0.0;
    let mut gap_worst = String::new();
    let mut step_time = 0.0;
    let mut events = 0;
    for _ in 0..frames {
        let t0 = Instant::now();
        joints.step(&mut world, frame_dt)?;
        step_time += t0.elapsed().as_secs_f64();
        for e in joints.drain_events() {
            if events < 8 {
                println!("  event: {e}");
            }
            events += 1;
        }
        let p = v3(world.bodies[ee_body].position() * ee_local);
        drift_max = drift_max.max(dist(p, p0));
        for (name, h) in &robot.joints {
            if let Some(s) = joints.get(*h).and_then(|j| j.state()) {
                let g = dist(s.anchor1, s.anchor2);
                if g > gap_max {
                    gap_max = g;
                    gap_worst = name.clone();
                }
            }
        }
    }
    if print_notices {
        let total: f64 = world.bodies.iter().filter(|(_, b)| b.is_dynamic()).map(|(_, b)| b.mass() as f64).sum();
        println!("  dynamic mass in world after the run: {total:.4} kg (URDF moving links: 3.7+8.393+2.275+1.219+1.219+0.1879 = 17.0 kg)");
    }
    let p = v3(world.bodies[ee_body].position() * ee_local);
    let mut q_final = [0.0; 6];
    let mut torque = [0.0; 6];
    let mut motor = [0.0; 6];
    for (i, name) in JOINTS.iter().enumerate() {
        let j = joints.get(robot.joints[*name]).unwrap();
        let s = j.state().unwrap();
        q_final[i] = robot.joint_position(&joints, name).unwrap();
        torque[i] = s.applied[Dof::Rx];
        motor[i] = s.parts[Dof::Rx].motor;
    }
    Ok(Stats {
        label: format!("kjoint  {substeps:>2} substeps{}", if ff { " +ff" } else { "" }),
        ee_sag_final: p0[2] - p[2],
        ee_drift_max: drift_max,
        ee_drift_final: dist(p, p0),
        q_final,
        torque,
        motor,
        gap_max,
        gap_worst,
        ms_per_frame: step_time / frames as f64 * 1e3,
        events,
    })
}

fn rapier_hold(multibody: bool, seconds: f64) -> Result<Stats, Box<dyn std::error::Error>> {
    use rapier3d_urdf::{UrdfLoaderOptions, UrdfMultibodyOptions};
    let frame_dt = 1.0 / 60.0;
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..Default::default()
    };
    world.integration_parameters.dt = frame_dt as f32;
    let opts = UrdfLoaderOptions {
        make_roots_fixed: true,
        collider_blueprint: ColliderBuilder::default()
            .density(0.0)
            .collision_groups(InteractionGroups::new(Group::GROUP_1, !Group::GROUP_1, InteractionTestMode::And)),
        rigid_body_blueprint: RigidBodyBuilder::dynamic().can_sleep(false),
        ..Default::default()
    };
    let (mut urdf, robot) = rapier3d_urdf::UrdfRobot::from_file(UR5, opts, None)?;
    // a massless link (ee_link) is an immovable dynamic body for rapier: give it the 0.01 kg
    // the kjoint loader gives it
    for l in &mut urdf.links {
        if robot.links[l.urdf_link_index].inertial.mass.value == 0.0 {
            l.body.set_additional_mass_properties(
                MassProperties::new(Vector::ZERO, 0.01, Vector::splat(1.0e-6)),
                false,
            );
        }
    }
    // link name -> index in urdf.links, joint name -> index in urdf.joints
    let link_names: Vec<String> = urdf.links.iter().map(|l| robot.links[l.urdf_link_index].name.clone()).collect();
    let joint_names: Vec<String> = urdf.joints.iter().map(|j| robot.joints[j.urdf_joint_index].name.clone()).collect();
    let frames_of: Vec<(Pose, Pose)> = urdf.joints.iter().map(|j| (j.joint.local_frame1, j.joint.local_frame2)).collect();
    let ee_idx = link_names.iter().position(|n| n == "wrist_3_link").ok_or("no wrist_3_link")?;
    let mut jidx = [usize::MAX; 6];
    for (i, name) in JOINTS.iter().enumerate() {
        jidx[i] = joint_names.iter().position(|n| n == name).ok_or(format!("no joint {name}"))?;
    }
    let (bodies, impulse_handles, mb_handles);
    if multibody {
        let h = urdf.insert_using_multibody_joints(
            &mut world.bodies,
            &mut world.colliders,
            &mut world.multibody_joints,
            UrdfMultibodyOptions::DISABLE_SELF_CONTACTS,
        );
        bodies = h.links.iter().map(|l| l.body).collect::<Vec<_>>();
        mb_handles = h.joints.iter().map(|j| (j.joint, j.link1, j.link2)).collect::<Vec<_>>();
        impulse_handles = vec![];
    } else {
        let h = urdf.insert_using_impulse_joints(&mut world.bodies, &mut world.colliders, &mut world.impulse_joints);
        bodies = h.links.iter().map(|l| l.body).collect::<Vec<_>>();
        impulse_handles = h.joints.iter().map(|j| (j.joint, j.link1, j.link2)).collect::<Vec<_>>();
        mb_handles = vec![];
    }
    for (i, &ji) in jidx.iter().enumerate() {
        let (kp, kd) = gains(i);
        if multibody {
            let jh = mb_handles[ji].0.ok_or("joint not in multibody")?;
            let (mb, link_id) = world.multibody_joints.get_mut(jh).unwrap();
            let link = mb.link_mut(link_id).unwrap();
            link.joint.data.set_motor_model(JointAxis::AngX, MotorModel::ForceBased);
            link.joint.data.set_motor_position(JointAxis::AngX, 0.0, kp as f32, kd as f32);
        } else {
            let j = world.impulse_joints.get_mut(impulse_handles[ji].0, true).unwrap();
            j.data.set_motor_model(JointAxis::AngX, MotorModel::ForceBased);
            j.data.set_motor_position(JointAxis::AngX, 0.0, kp as f32, kd as f32);
        }
    }
    let ee_body = bodies[ee_idx];
    let ee_local = Vector::new(EE_LOCAL[0], EE_LOCAL[1], EE_LOCAL[2]);
    let p0 = v3(world.bodies[ee_body].position() * ee_local);
    let frames = (seconds / frame_dt).round() as usize;
    let (mut drift_max, mut gap_max, mut gap_worst, mut step_time) = (0.0f64, 0.0f64, String::new(), 0.0);
    for _ in 0..frames {
        let t0 = Instant::now();
        world.step();
        step_time += t0.elapsed().as_secs_f64();
        let p = v3(world.bodies[ee_body].position() * ee_local);
        drift_max = drift_max.max(dist(p, p0));
        if !multibody {
            for (k, (_, b1, b2)) in impulse_handles.iter().enumerate() {
                let a1 = world.bodies[*b1].position() * frames_of[k].0.translation;
                let a2 = world.bodies[*b2].position() * frames_of[k].1.translation;
                let g = dist(v3(a1), v3(a2));
                if g > gap_max {
                    gap_max = g;
                    gap_worst = joint_names[k].clone();
                }
            }
        }
    }
    let p = v3(world.bodies[ee_body].position() * ee_local);
    Ok(Stats {
        label: format!("rapier {}", if multibody { "multibody" } else { "impulse  " }),
        ee_sag_final: p0[2] - p[2],
        ee_drift_max: drift_max,
        ee_drift_final: dist(p, p0),
        q_final: [f64::NAN; 6],
        torque: [f64::NAN; 6],
        motor: [f64::NAN; 6],
        gap_max,
        gap_worst,
        ms_per_frame: step_time / frames as f64 * 1e3,
        events: 0,
    })
}

fn mech(world: &PhysicsWorld) -> f64 {
    rapier_kjoint::dynamics::energy::mechanical_energy(&world.bodies, world.gravity)
}

/// Shoulder lift driven along q*(t) = -A(1 - cos(2πt/T))/2 (arm raised by A at T/2, back at T),
/// two periods then 2 s of hold; target set every frame or every substep.
fn trajectory(substeps: usize, per_substep: bool, ff: bool) -> Result<(), Box<dyn std::error::Error>> {
    let frame_dt = 1.0 / 60.0;
    let (a, period) = (0.8f64, 4.0f64);
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..Default::default()
    };
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let options = UrdfOptions {
        substep: frame_dt / substeps as f64,
        ..Default::default()
    };
    let robot = UrdfRobot::from_file(UR5, &options)?.insert(&mut world, &mut joints)?;
    let tau = hand_torques();
    for (i, name) in JOINTS.iter().enumerate() {
        let (kp, kd) = gains(i);
        let mut m = KjointMotor::position(0.0, kp, kd);
        if ff {
            m = m.with_force(-tau[i]);
        }
        joints.set_motor(robot.joints[*name], Dof::Rx, Some(m))?;
    }
    let target = |t: f64| -> (f64, f64) {
        if t >= 2.0 * period {
            return (0.0, 0.0);
        }
        let w = 2.0 * std::f64::consts::PI / period;
        (-a * (1.0 - (w * t).cos()) / 2.0, -a * w * (w * t).sin() / 2.0)
    };
    // one step first so the bodies have their mass properties for the energy
    let frames = (10.0 / frame_dt).round() as usize;
    let mut e0 = None;
    let (mut err_max, mut err_max_t) = (0.0f64, 0.0);
    let mut motor_at_peak = f64::NAN;
    let mut de_at_peak = f64::NAN;
    let mut q_at_peak = f64::NAN;
    let lift = robot.joints["shoulder_lift_joint"];
    for frame in 0..frames {
        let t_start = frame as f64 * frame_dt;
        if per_substep {
            let r = &robot;
            joints.step_with(&mut world, frame_dt, |phase, _w, set: &mut KjointSet| {
                if phase == SubstepPhase::Before {
                    let (q, qd) = target(set.time());
                    r.set_motor_target(set, "shoulder_lift_joint", q, qd)?;
                }
                Ok::<(), SimError>(())
            })?;
        } else {
            let (q, qd) = target(t_start);
            robot.set_motor_target(&mut joints, "shoulder_lift_joint", q, qd)?;
            joints.step(&mut world, frame_dt)?;
        }
        if e0.is_none() {
            // energy at t = 0 not available before the masses exist: take the start of the
            // first frame as the reference by adding back nothing (arm at rest, 1 frame in)
            e0 = Some(mech(&world));
        }
        let s = joints.get(lift).unwrap().state().unwrap();
        let q = robot.joint_position(&joints, "shoulder_lift_joint").unwrap();
        let (qs, _) = target(s.time);
        let err = (q - qs).abs();
        if t_start < 2.0 * period && err > err_max {
            err_max = err;
            err_max_t = s.time;
        }
        if std::env::var("TRAJ_DEBUG").is_ok() && (frame % 30 == 0) && frame < 300 {
            let e = joints.get(lift).unwrap().closed_energy(&world.bodies);
            println!(
                "   dbg t {:.4} q {:+.5} q* {:+.5} rate {:+.5} motor {:+9.3} applied {:+9.3} elastic {:+.3} damp {:+.3} | Dx {:+.2e} Dy {:+.2e} Dz {:+.2e} Ry {:+.2e} Rz {:+.2e} | Eint_motor {:.3} Enum {:.3}",
                s.time, q, qs, s.rate[Dof::Rx], s.parts[Dof::Rx].motor, s.applied[Dof::Rx], s.parts[Dof::Rx].elastic, s.parts[Dof::Rx].damping,
                s.q[Dof::Dx], s.q[Dof::Dy], s.q[Dof::Dz], s.q[Dof::Ry], s.q[Dof::Rz], -e.motor, e.numerical
            );
        }
        let t_end = joints.time();
        if (t_end - period / 2.0).abs() < frame_dt / 2.0 {
            let motor: f64 = robot.joints.values().map(|h| joints.get(*h).unwrap().closed_energy(&world.bodies).motor).sum();
            motor_at_peak = -motor;
            de_at_peak = mech(&world) - e0.unwrap();
            q_at_peak = q;
        }
    }
    let mut sums = JointEnergy::default();
    for h in robot.joints.values() {
        let e = joints.get(*h).unwrap().closed_energy(&world.bodies);
        sums.elastic += e.elastic;
        sums.damping += e.damping;
        sums.friction += e.friction;
        sums.stop += e.stop;
        sums.numerical += e.numerical;
        sums.motor += e.motor;
    }
    let per: Vec<String> = JOINTS
        .iter()
        .map(|n| {
            let e = joints.get(robot.joints[*n]).unwrap().closed_energy(&world.bodies);
            format!("{} num {:.3} motor {:.3}", &n[..n.len() - 6], e.numerical, -e.motor)
        })
        .collect();
    println!("     per joint: {}", per.join(" | "));
    let de = mech(&world) - e0.unwrap();
    let residual = -sums.motor - de - sums.elastic - sums.damping - sums.friction - sums.stop - sums.numerical;
    println!(
        "traj {substeps:>2} substeps, target per {}{}: max |q - q*| = {:.5} rad at t = {:.3} s; at T/2: q = {:.4}, motor work in {:.3} J, ΔE_mech {:.3} J (hand ΔPE = τ_lift·sin(A) = {:.3} J)",
        if per_substep { "substep" } else { "frame  " },
        if ff { " +ff" } else { "" },
        err_max,
        err_max_t,
        q_at_peak,
        motor_at_peak,
        de_at_peak,
        59.25 * a.sin()
    );
    println!(
        "     end (10 s): motor work in {:.4} J, ΔE_mech {:.4} J, elastic {:.4}, damping {:.4}, friction {:.4}, stop {:.4}, numerical {:.4}; residual {:.2e} J; q_lift {:.5}",
        -sums.motor, de, sums.elastic, sums.damping, sums.friction, sums.stop, sums.numerical, residual,
        robot.joint_position(&joints, "shoulder_lift_joint").unwrap()
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    if std::env::args().any(|a| a == "trajdbg") {
        trajectory(4, true, true)?;
        trajectory(16, true, true)?;
        return Ok(());
    }
    if std::env::args().any(|a| a == "traj") {
        trajectory(4, false, false)?;
        trajectory(4, true, false)?;
        trajectory(4, true, true)?;
        trajectory(8, true, true)?;
        trajectory(16, true, true)?;
        return Ok(());
    }
    let seconds = 10.0;
    let tau = hand_torques();
    println!("hand gravity torques at q = 0: shoulder_lift {:.3} N·m, elbow {:.3} N·m", tau[1], tau[2]);
    let (kp1, _) = gains(1);
    let e1 = tau[1] / kp1;
    let e2 = tau[2] / kp1;
    let sag = 0.425 * e1 + 0.39225 * (e1 + e2);
    println!(
        "expected static errors without feed-forward: lift {:.4} rad, elbow {:.4} rad -> EE sag ≈ {:.2} mm",
        e1,
        e2,
        sag * 1e3
    );
    let mut all = Vec::new();
    all.push(kjoint_hold(4, false, seconds, true)?);
    all.push(kjoint_hold(4, true, seconds, false)?);
    all.push(kjoint_hold(8, false, seconds, false)?);
    all.push(kjoint_hold(16, false, seconds, false)?);
    all.push(rapier_hold(true, seconds)?);
    all.push(rapier_hold(false, seconds)?);
    // again, to see the timing is repeatable
    all.push(kjoint_hold(4, false, seconds, false)?);
    all.push(rapier_hold(true, seconds)?);
    println!("\n{:<26} {:>9} {:>9} {:>9} {:>10} {:>18} {:>8} {:>6}", "run", "sag mm", "drift mm", "dmax mm", "gap mm", "worst gap", "ms/frm", "events");
    for s in &all {
        println!(
            "{:<26} {:>9.3} {:>9.3} {:>9.3} {:>10.4} {:>18} {:>8.4} {:>6}",
            s.label,
            s.ee_sag_final * 1e3,
            s.ee_drift_final * 1e3,
            s.ee_drift_max * 1e3,
            s.gap_max * 1e3,
            s.gap_worst,
            s.ms_per_frame,
            s.events
        );
    }
    println!("\nper joint (kjoint runs): q_final [rad], applied[Rx] [N·m], motor part [N·m]; hand τ_g");
    for s in all.iter().filter(|s| s.label.starts_with("kjoint")).take(4) {
        println!("{}", s.label);
        for (i, n) in JOINTS.iter().enumerate() {
            println!(
                "   {:<20} q {:+.5}  applied {:+9.3}  motor {:+9.3}  hand {:+8.3}  (expected q = τ/kp {:+.5} without ff)",
                n,
                s.q_final[i],
                s.torque[i],
                s.motor[i],
                tau[i],
                tau[i] / gains(i).0
            );
        }
    }
    Ok(())
}
