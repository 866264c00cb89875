//! Motors on the free DOFs of KJOINT2 joints (`KjointMotor`, rapier's force-based joint
//! motor): what a user driving a joint looks at — where a servo holds a loaded arm, the
//! speed a velocity motor reaches against a damper, a capped motor that cannot hold its
//! load, the energy the motors put in, and the refusals.

mod common;

use common::*;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, JointType, KjointBuilder, KjointMotor, KjointProperty, KjointSet, SimError,
};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

/// A 1 kg rod of 1 m (0.04 m square) lying along +x from a hinge about world z at the
/// origin, under gravity −y: world, set (4 substeps), joint.
fn horizontal_arm(motor: KjointMotor) -> (PhysicsWorld, KjointSet, rapier_kjoint::KjointHandle) {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let rod = cuboid(
        &mut w,
        1.0,
        Vector::new(0.5, 0.02, 0.02),
        Vector::new(0.5, 0.0, 0.0),
    );
    let mut set = joints(4);
    let prop = KjointProperty::new(JointType::Revolute);
    let j = add(&mut set, &w, prop, ground, rod, |b| {
        b.name("shoulder")
            .world_axis(Vector::Z)
            .local_anchor2(Vector::new(-0.5, 0.0, 0.0))
            .motor(Dof::Rx, motor)
    });
    (w, set, j)
}

/// `mech + Σ (stored + dissipated + motor) − preload`: constant when the motors' work is
/// booked (no loads but gravity, which `mech` holds) [J].
fn book(w: &PhysicsWorld, set: &KjointSet) -> f64 {
    let mech = rapier_kjoint::dynamics::energy::mechanical_energy(&w.bodies, w.gravity);
    mech + set
        .iter()
        .map(|(_, j)| {
            let e = j.closed_energy(&w.bodies);
            e.elastic + e.dissipated() + e.motor - j.preload_energy()
        })
        .sum::<f64>()
}

/// Asserts that [`book`] moved from `e0` by less than 1e-3 of the motors' work `work` \[J\].
fn balance_closes(w: &PhysicsWorld, set: &KjointSet, e0: f64, work: f64) {
    let drift = book(w, set) - e0;
    assert!(
        drift.abs() < 1e-3 * work.abs(),
        "energy balance off by {drift} J of the motors' {work} J"
    );
}

/// A servo lifts a horizontal arm to 0.5 rad and holds it there against its weight: the
/// arm rests short of the target by the static error `τ_g/k_p`, `τ_g = m·g·(L/2)·cos θ`,
/// and the joint transmits `τ_g` about its axis, of which the motor is the source.
#[test]
fn a_servo_holds_a_loaded_arm_short_of_its_target_by_the_static_error() {
    let (kp, kd, target) = (1000.0, 60.0, 0.5);
    let (mut w, mut set, j) = horizontal_arm(KjointMotor::position(target, kp, kd));
    let e0 = book(&w, &set);
    for _ in 0..240 {
        set.step(&mut w, DT).unwrap();
    }
    let s = set.get(j).unwrap().state().unwrap();
    let q = s.q[Dof::Rx];
    // the static error, solved for θ: k_p·(θ* − θ) = m·g·(L/2)·cos θ
    let mut theta = target;
    for _ in 0..20 {
        theta = target - G * 0.5 * theta.cos() / kp;
    }
    assert!(
        (q - theta).abs() < 2e-5,
        "the arm rests at {q} rad, expected {theta} (target {target})"
    );
    assert!(
        s.rate[Dof::Rx].abs() < 1e-4,
        "still turning at {}",
        s.rate[Dof::Rx]
    );
    // the motor's force in the law's internal convention, −τ = k_p·(q − θ*), is the force
    // the joint transmits about its axis
    let tau_g = G * 0.5 * q.cos();
    assert!(
        (s.parts[Dof::Rx].motor + tau_g).abs() < 1e-3 * tau_g,
        "motor part {} N·m, the arm's weight {tau_g} N·m about the hinge",
        s.parts[Dof::Rx].motor
    );
    assert!(
        (s.applied[Dof::Rx].abs() - tau_g).abs() < 1e-3 * tau_g,
        "transmitted {} N·m about the axis, the weight's moment {tau_g}",
        s.applied[Dof::Rx]
    );
    // the anchors stay together
    assert!(anchor_gap(set.get(j).unwrap()) < 1e-4);
    // what the motor put in is the arm's potential energy and what damping took: booked as
    // the motor's work, not as numerical damping
    let e = set.get(j).unwrap().closed_energy(&w.bodies);
    let lift = G * 0.5 * q.sin();
    assert!(
        -e.motor > lift,
        "the motor did {} J, the arm gained {lift} J of height",
        -e.motor
    );
    assert!(
        e.numerical.abs() < 0.1 * -e.motor,
        "numerical {} J beside the motor's {} J",
        e.numerical,
        -e.motor
    );
    balance_closes(&w, &set, e0, -e.motor);
}

/// A velocity motor spins a free disc (no gravity) against the hinge's viscosity `C`: the
/// disc settles at `ω = k_d·ω*/(k_d + C)`, the motor's power into the damper; the energy
/// balance closes with the motor's work.
#[test]
fn a_velocity_motor_reaches_its_speed_less_what_the_damper_takes() {
    let (mut w, ground) = world(Vector::ZERO);
    let (disc, _) = w.insert(
        RigidBodyBuilder::dynamic().can_sleep(false),
        ColliderBuilder::cylinder(0.05, 0.5).mass(2.0),
    );
    let (kd, c, target) = (5.0, 1.0, 3.0);
    let prop = KjointProperty::new(JointType::Revolute)
        .with_dof(Dof::Rx, DofLaw::default().with_viscosity(c));
    let mut set = joints(4);
    let j = add(&mut set, &w, prop, ground, disc, |b| {
        b.world_axis(Vector::Y)
    });
    assert!(set
        .set_motor(j, Dof::Rx, Some(KjointMotor::velocity(target, kd)))
        .unwrap());
    let e0 = book(&w, &set);
    for _ in 0..300 {
        set.step(&mut w, DT).unwrap();
    }
    let s = set.get(j).unwrap().state().unwrap();
    let omega = kd * target / (kd + c);
    assert!(
        (s.rate[Dof::Rx] - omega).abs() < 1e-4 * omega,
        "the disc turns at {} rad/s, expected {omega}",
        s.rate[Dof::Rx]
    );
    let spin = w.bodies[disc].angvel().y as f64;
    assert!(
        (spin - omega).abs() < 1e-3 * omega,
        "the disc's own spin {spin}"
    );
    let e = set.get(j).unwrap().closed_energy(&w.bodies);
    // ½·I·ω² in the disc (I = m·r²/2 = 0.25 kg·m²) and the damper's share
    let kinetic = 0.5 * 0.25 * omega * omega;
    assert!(-e.motor > kinetic + e.damping * 0.99);
    balance_closes(&w, &set, e0, -e.motor);
}

/// A motor capped below the load it holds gives its cap and no more: a 2 kg carriage on a
/// vertical slide with a servo capped at 12 N falls at `g − 12/2` m/s².
#[test]
fn a_capped_motor_gives_its_cap_and_the_load_falls() {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let cart = cuboid(&mut w, 2.0, Vector::splat(0.05), Vector::ZERO);
    let mut set = joints(4);
    let prop = KjointProperty::new(JointType::Translational);
    let motor = KjointMotor::position(0.0, 1e5, 1e3).max_force(12.0);
    let j = add(&mut set, &w, prop, ground, cart, |b| {
        b.world_axis(Vector::Y).motor(Dof::Dx, motor)
    });
    for _ in 0..30 {
        set.step(&mut w, DT).unwrap();
    }
    let v0 = w.bodies[cart].linvel().y as f64;
    for _ in 0..30 {
        set.step(&mut w, DT).unwrap();
    }
    let a = (w.bodies[cart].linvel().y as f64 - v0) / 0.5;
    let expected = -(G - 12.0 / 2.0);
    assert!(
        (a - expected).abs() < 1e-3 * expected.abs(),
        "the carriage falls at {a} m/s², expected {expected}"
    );
    let s = set.get(j).unwrap().state().unwrap();
    // at its cap, pushing the carriage up (+y = +x of the slide): τ = 12, F_m = −12
    assert!(
        (s.parts[Dof::Dx].motor + 12.0).abs() < 1e-9,
        "motor part {}",
        s.parts[Dof::Dx].motor
    );
}

/// A servo with the arm's weight moment as its feed-forward force (`KjointMotor::with_force`,
/// as a robot's controller adds a model's gravity torque) rests on its target, where the
/// same servo alone rests short of it by `τ_g/k_p` (0.043 rad here).
#[test]
fn a_feed_forward_torque_puts_a_soft_servo_on_its_target() {
    let (kp, kd, target) = (100.0, 20.0, 0.5);
    let tau_g = G * 0.5 * target.cos();
    let rest = |motor: KjointMotor| {
        let (mut w, mut set, j) = horizontal_arm(motor);
        let e0 = book(&w, &set);
        for _ in 0..300 {
            set.step(&mut w, DT).unwrap();
        }
        let s = set.get(j).unwrap().state().unwrap();
        let e = set.get(j).unwrap().closed_energy(&w.bodies);
        balance_closes(&w, &set, e0, -e.motor);
        (s.q[Dof::Rx], s.parts[Dof::Rx].motor)
    };
    let servo = KjointMotor::position(target, kp, kd);
    let (q, part) = rest(servo.with_force(tau_g));
    assert!(
        (q - target).abs() < 1e-4,
        "rests at {q} rad, target {target}"
    );
    assert!(
        (part + tau_g).abs() < 1e-3 * tau_g,
        "motor part {part} N·m, the weight's moment {tau_g} N·m"
    );
    let (q_alone, _) = rest(servo);
    assert!(
        (target - q_alone - tau_g / kp).abs() < 0.1 * tau_g / kp,
        "without the feed-forward: {q_alone} rad, τ_g/k_p = {}",
        tau_g / kp
    );
}

/// An effort command (`KjointMotor::force`, MuJoCo's `<motor>`): 30 N up a vertical slide
/// lifts a 2 kg carriage at `30/2 − g` m/s² from rest (2.6 m in 1 s); the motor's work `F·x` is booked as
/// the motor's, and the carriage's kinetic energy is the net work.
#[test]
fn an_effort_command_lifts_a_carriage_at_f_over_m_less_g() {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let cart = cuboid(&mut w, 2.0, Vector::splat(0.05), Vector::ZERO);
    let mut set = joints(4);
    let prop = KjointProperty::new(JointType::Translational);
    let j = add(&mut set, &w, prop, ground, cart, |b| {
        b.world_axis(Vector::Y)
            .motor(Dof::Dx, KjointMotor::force(30.0))
    });
    for _ in 0..60 {
        set.step(&mut w, DT).unwrap();
    }
    // rapier's symplectic Euler over n = 240 substeps of h: x = a·h²·n(n+1)/2 = ½·a·t·(t + h)
    let (a, h) = (30.0 / 2.0 - G, DT / 4.0);
    let expected = 0.5 * a * (1.0 + h);
    let x = w.bodies[cart].translation().y as f64;
    assert!(
        (x - expected).abs() < 1e-4 * expected,
        "the carriage rose {x} m in 1 s, ½·a·t·(t + h) = {expected} m"
    );
    let e = set.get(j).unwrap().closed_energy(&w.bodies);
    assert!(
        (-e.motor - 30.0 * x).abs() < 2e-3 * 30.0 * x,
        "the motor's work {} J, F·x = {} J",
        -e.motor,
        30.0 * x
    );
    // the carriage's kinetic energy is the net work `(F − m·g)·x`, less what rapier's
    // symplectic Euler loses under a constant force, `h/t` of it (0.42 %)
    let v = w.bodies[cart].linvel().y as f64;
    let (kinetic, net) = (0.5 * 2.0 * v * v, (30.0 - 2.0 * G) * x);
    assert!(
        (kinetic - net * (1.0 - h)).abs() < 1e-3 * net,
        "kinetic {kinetic} J, (F − m·g)·x = {net} J"
    );
}

/// A target moved at every substep through `KjointSet::set_motor` in a `step_with` hook
/// (which does not analyse the set again) is tracked: a stiff servo follows a 0.5 Hz sine of
/// 0.4 rad within the static error of the arm's weight and its inertia (`(m·g·L/2 +
/// I·α_max)/k_p` = 3.1 mrad; measured 3.3 mrad: the target is held over each substep). A target set once a frame is held over the frame's substeps,
/// as rapier holds a motor's target over its step: the arm then lags up to `v·Δt` behind
/// the sine (21 mrad here).
#[test]
fn a_servo_tracks_a_target_moved_every_substep() {
    use std::f64::consts::PI;
    let (kp, kd) = (2000.0, 80.0);
    let (mut w, mut set, j) = horizontal_arm(KjointMotor::position(0.0, kp, kd));
    let target = |t: f64| (0.4 * (PI * t).sin(), 0.4 * PI * (PI * t).cos());
    let mut worst: f64 = 0.0;
    for frame in 0..180 {
        set.step_with(&mut w, DT, |phase, _, joints| {
            if phase == rapier_kjoint::SubstepPhase::Before {
                let (q, v) = target(joints.time());
                let m = KjointMotor::new(q, v, kp, kd);
                assert!(joints.set_motor(j, Dof::Rx, Some(m))?);
            }
            Ok::<(), SimError>(())
        })
        .unwrap();
        if frame >= 60 {
            let s = set.get(j).unwrap().state().unwrap();
            worst = worst.max((s.q[Dof::Rx] - target(s.time).0).abs());
        }
    }
    let bound = (G * 0.5 + (1.0 / 3.0) * 0.4 * PI * PI) / kp;
    assert!(
        worst < 1.25 * bound,
        "the arm strayed {worst} rad from the moving target (bound {bound})"
    );
    assert!(
        worst > 0.2 * bound,
        "{worst}: less than the weight's static error"
    );
}

/// Refusals: a motor on a blocked DOF, with a NaN or a negative setting, on a flex joint;
/// an unknown handle answers `false`; nothing changes on a refusal.
#[test]
fn motors_that_cannot_act_are_refused_naming_the_joint_the_dof_and_the_field() {
    let (mut w, ground) = world(Vector::ZERO);
    let b = ball(&mut w, 1.0, 0.1, Vector::new(0.0, -1.0, 0.0));
    let mut set = joints(4);
    let j = add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Revolute),
        ground,
        b,
        |b| b.name("elbow"),
    );
    let e = set
        .set_motor(j, Dof::Dy, Some(KjointMotor::velocity(1.0, 1.0)))
        .unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(e, SimError::Motor { dof: Dof::Dy, .. })
            && text.contains("elbow")
            && text.contains("dy")
            && text.contains("blocked")
            && text.contains("rx"),
        "{text}"
    );
    for (m, field) in [
        (KjointMotor::position(f64::NAN, 1.0, 1.0), "target_pos"),
        (KjointMotor::position(0.0, -1.0, 1.0), "stiffness"),
        (KjointMotor::velocity(0.0, f64::INFINITY), "damping"),
        (KjointMotor::velocity(1.0, 1.0).max_force(-2.0), "max_force"),
    ] {
        let text = set.set_motor(j, Dof::Rx, Some(m)).unwrap_err().to_string();
        assert!(
            text.contains("elbow") && text.contains(&format!("motor.{field}")),
            "{text}"
        );
    }
    assert!(set.get(j).unwrap().motor(Dof::Rx).is_none());
    // an unbounded cap is the default, and accepted
    assert!(set
        .set_motor(j, Dof::Rx, Some(KjointMotor::velocity(1.0, 1.0)))
        .unwrap());
    assert_eq!(
        set.get(j).unwrap().motor(Dof::Rx).unwrap().max_force,
        f64::INFINITY
    );
    // removed again
    assert!(set.set_motor(j, Dof::Rx, None).unwrap());
    assert!(set.get(j).unwrap().motor(Dof::Rx).is_none());
    // a handle of no joint
    let gone = set.remove(j).unwrap().handle();
    assert!(!set
        .set_motor(gone, Dof::Rx, Some(KjointMotor::velocity(1.0, 1.0)))
        .unwrap());
    // at insertion, through the builder
    let bad = KjointBuilder::new(KjointProperty::new(JointType::Revolute))
        .name("wrist")
        .motor(Dof::Dz, KjointMotor::velocity(1.0, 1.0));
    let text = set
        .insert(bad, ground, b, &w.bodies)
        .unwrap_err()
        .to_string();
    assert!(text.contains("wrist") && text.contains("dz"), "{text}");
}

/// The URDF arm of the demo scene with servos on its KJOINT2 shoulder and elbow (the robot's
/// options, `motor = { .. }`), their targets moved by the scene's `[[motors]]` from 0 to
/// (0.3, −0.5) rad over 1 s: the joints end at their targets within their static error
/// (the weight and the URDF friction over `k_p`), and the summary's energy balance closes
/// with the motors' work.
#[test]
fn a_scene_drives_a_urdf_arm_with_kjoint2_servos() {
    let urdf = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/urdf/arm.urdf");
    let text = format!(
        r#"
dt = 0.016666666666666666
substeps = 4
duration = 3.0
gravity = [0.0, 0.0, -9.81]
[[robots]]
urdf = "{}"
[robots.options.joints.shoulder]
motor = {{ stiffness = 400.0, damping = 40.0 }}
[robots.options.joints.elbow]
motor = {{ stiffness = 200.0, damping = 20.0, max_force = 30.0 }}
[[motors]]
joint = "shoulder"
target = 0.3
function = {{ curve = [[0.0, 0.0], [1.0, 1.0]] }}
[[motors]]
joint = "elbow"
target = -0.5
function = {{ curve = [[0.0, 0.0], [1.0, 1.0]] }}
"#,
        urdf.display().to_string().replace('\\', "/")
    );
    let (built, summary, stats) =
        common::scene::run_with_summary("motors-scene", "servo_arm.toml", &text);
    assert_eq!(built.motors.len(), 2);
    // the moment each holds: the shoulder the whole arm (2 kg at 0.2 m, 1 kg at 0.55 m,
    // 0.5 kg at 0.74 m: 12.3 N·m), the elbow the forearm and hand (3.1 N·m), with the
    // URDF friction (0.5, 0.3 N·m); bounds a tenth above
    for (name, target, kp, moment) in [("shoulder", 0.3, 400.0, 14.0), ("elbow", -0.5, 200.0, 3.7)]
    {
        let j = built.joints.get(built.joints.find(name).unwrap()).unwrap();
        let q = j.dof_value(Dof::Rx).unwrap();
        // gravity turns the arm down (+ about y): past the shoulder's target, short of the
        // elbow's
        assert!(
            (q - target).abs() < moment / kp && q > target,
            "{name} at {q} rad, its target {target}"
        );
        assert_eq!(j.motor(Dof::Rx).unwrap().target_pos, target);
    }
    let b = summary.balance(stats.external_work());
    // (the shoulder lowers the arm against its servo, which takes more than the elbow's
    // lift gives: −2.3 J)
    assert!(b.motor_work < -1.0, "the motors did {} J", b.motor_work);
    assert!(
        b.relative.abs() < 1e-3,
        "residual {} J, {} of the scale {} J",
        b.residual,
        b.relative,
        b.scale
    );
    assert!(summary
        .table(stats.external_work())
        .contains("work of the joints' motors"));
}

/// A target moved through `KjointSet::set_motor` wakes an island that had fallen asleep: a
/// rod hanging at rest on its hinge, its servo holding it there, sleeps; given a target of
/// 0.4 rad it swings up to it.
#[test]
fn a_new_target_wakes_a_sleeping_island() {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let (rod, _) = w.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(0.02, 0.5, 0.02).mass(1.0),
    );
    let mut set = joints(4);
    let (kp, kd) = (500.0, 30.0);
    let j = add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Revolute),
        ground,
        rod,
        |b| {
            b.world_axis(Vector::Z)
                .local_anchor2(Vector::new(0.0, 0.5, 0.0))
                .motor(Dof::Rx, KjointMotor::position(0.0, kp, kd))
        },
    );
    for _ in 0..240 {
        set.step(&mut w, DT).unwrap();
    }
    assert!(w.bodies[rod].is_sleeping(), "the resting rod did not sleep");
    set.set_motor(j, Dof::Rx, Some(KjointMotor::position(0.4, kp, kd)))
        .unwrap();
    for _ in 0..180 {
        set.step(&mut w, DT).unwrap();
    }
    let q = set.get(j).unwrap().state().unwrap().q[Dof::Rx];
    // k_p·(0.4 − θ) = m·g·(L/2)·sin θ
    let mut theta: f64 = 0.4;
    for _ in 0..30 {
        theta = 0.4 - G * 0.5 * theta.sin() / kp;
    }
    assert!(
        (q - theta).abs() < 1e-4,
        "the rod stands at {q} rad, expected {theta}"
    );
}

/// An MJCF `<position>` actuator on a hinge becomes its KJOINT2 motor: gear 2, `kp` 50, `kv` 5
/// give a servo of 200 N·m/rad damped at 20 N·m·s/rad, towards the control clamped into
/// `ctrlrange` (0 → 0.5, over the gear: 0.25 rad); a rod of 1 kg and 0.5 m hanging from it
/// rests at `θ = 0.25 − m·g·(L/2)·sin θ/200`, and moved to −0.3 rad by
/// `UrdfRobotHandles::set_motor_target` rests there likewise. A second actuator on the
/// joint (a `<motor>`) is named in a notice, not mapped.
#[test]
fn an_mjcf_position_actuator_is_the_hinge_motor() {
    let mjcf = rod_model(
        "",
        r#"<position name="servo" joint="hinge" gear="2" kp="50" kv="5" ctrlrange="0.5 1" forcerange="-3 3"/>
    <motor name="torque" joint="hinge"/>"#,
    );
    let (mut w, mut set, robot) = mjcf_robot(&mjcf, "servo.xml");
    let h = robot.joints["hinge"];
    let m = *set.get(h).unwrap().motor(Dof::Rx).unwrap();
    assert_eq!(
        (m.target_pos, m.stiffness, m.damping, m.max_force),
        (0.25, 200.0, 20.0, 6.0)
    );
    assert!(
        robot
            .notices
            .iter()
            .any(|n| n.contains("1 actuator(s) not mapped") && n.contains("torque")),
        "{:?}",
        robot.notices
    );
    for target in [0.25, -0.3] {
        rests_short_of(&mut w, &mut set, &robot, target);
    }
    // a name without a motor
    assert!(!robot.set_motor_target(&mut set, "elbow", 0.1, 0.0).unwrap());
}

/// An MJCF `<motor>` actuator on a hinge becomes a motor of constant torque `g·u`
/// (`KjointMotor::force`): 0 at the start (`u = 0`), capped at `|g|·max|ctrlrange|` (2 · 1.5
/// = 3 N·m, MuJoCo clamping the control); `UrdfRobotHandles::set_motor_force` sets the
/// torque: 1 N·m holds a hanging rod of 1 kg and 0.5 m at `m·g·(L/2)·sin θ = τ` (0.42 rad),
/// and 5 N·m gives the cap, 3.
#[test]
fn an_mjcf_motor_actuator_is_a_torque_the_program_sets() {
    let mjcf = r#"<mujoco model="torque">
  <worldbody>
    <body name="rod" pos="0 0 1">
      <joint name="hinge" type="hinge" axis="0 1 0" damping="0.5"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="torque" joint="hinge" gear="2" ctrlrange="-1.5 1.5"/>
  </actuator>
</mujoco>"#;
    let (mut w, mut set, robot) = mjcf_robot(mjcf, "torque.xml");
    assert!(
        !robot.notices.iter().any(|n| n.contains("not mapped")),
        "{:?}",
        robot.notices
    );
    let h = robot.joints["hinge"];
    let m = *set.get(h).unwrap().motor(Dof::Rx).unwrap();
    assert_eq!(
        (m.force, m.max_force, m.stiffness, m.damping),
        (0.0, 3.0, 0.0, 0.0)
    );
    assert!(robot.set_motor_force(&mut set, "hinge", 1.0).unwrap());
    for _ in 0..240 {
        set.step(&mut w, DT).unwrap();
    }
    let q = robot.joint_position(&set, "hinge").unwrap();
    // (the capsule's centre of mass is 0.25 m below the hinge)
    let theta = (1.0 / (G * 0.25)).asin();
    assert!(
        (q - theta).abs() < 1e-4,
        "the rod rests at {q} rad, expected {theta}"
    );
    assert!(robot.set_motor_force(&mut set, "hinge", 5.0).unwrap());
    set.step(&mut w, DT).unwrap();
    let s = set.get(h).unwrap().state().unwrap();
    assert_eq!(s.parts[Dof::Rx].motor, -3.0, "at the cap: τ = 3, F_m = −3");
    // a name that is not a joint of the robot; a torque that is not finite
    assert!(!robot.set_motor_force(&mut set, "elbow", 1.0).unwrap());
    assert!(robot.set_motor_force(&mut set, "hinge", f64::NAN).is_err());
}

/// A scene's `[[motors]]` `force` schedule on a URDF robot's KJOINT2 hinge with no motor in
/// its options (it gets one of that force alone): 1 N·m holds a 1 kg, 0.5 m link hanging
/// from a fixed base at `asin(τ/(m·g·L/2))` (0.42 rad, the file's positive turn), and the
/// summary's energy balance closes with the motor's work `τ·θ` (the lift's
/// `m·g·(L/2)·(1 − cos θ)` and what the damping took).
#[test]
fn a_scene_applies_a_joint_torque_to_a_urdf_robot() {
    let urdf = r#"<robot name="pendulum">
  <link name="base"/>
  <link name="rod">
    <inertial><origin xyz="0 0 -0.25"/><mass value="1.0"/>
      <inertia ixx="0.021" ixy="0" ixz="0" iyy="0.021" iyz="0" izz="0.001"/></inertial>
  </link>
  <joint name="hinge" type="continuous">
    <parent link="base"/><child link="rod"/><axis xyz="0 1 0"/>
    <dynamics damping="0.5"/>
  </joint>
</robot>"#;
    let urdf_path = common::cli::temp_file("motors-force", "pendulum.urdf", urdf);
    let text = format!(
        r#"
dt = 0.016666666666666666
substeps = 4
duration = 4.0
gravity = [0.0, 0.0, -9.81]
[[robots]]
urdf = "{}"
[[motors]]
joint = "hinge"
force = 1.0
"#,
        urdf_path.display().to_string().replace('\\', "/")
    );
    let (built, summary, stats) =
        common::scene::run_with_summary("motors-force", "torque.toml", &text);
    assert_eq!(built.motors[0].unit(), "N·m");
    let j = built
        .joints
        .get(built.joints.find("hinge").unwrap())
        .unwrap();
    let q = j.dof_value(Dof::Rx).unwrap();
    let theta = (1.0 / (G * 0.25)).asin();
    assert!(
        (q - theta).abs() < 1e-4,
        "the link rests at {q} rad, expected {theta}"
    );
    assert_eq!(j.motor(Dof::Rx).unwrap().force, 1.0);
    // the work a constant torque did is `τ·q`: the lift and what the damping took
    let b = summary.balance(stats.external_work());
    let lift = G * 0.25 * (1.0 - theta.cos());
    assert!(
        (b.motor_work - q).abs() < 1e-3 * q && b.motor_work > lift,
        "the motor did {} J, τ·q = {q} J, the lift {lift} J",
        b.motor_work
    );
    assert!(
        b.relative.abs() < 1e-3,
        "residual {} J, {} of the scale {} J",
        b.residual,
        b.relative,
        b.scale
    );
}

/// An MJCF model inserted as a robot (file name `name`) into a world of gravity −z and a
/// set of 4 substeps: world, set, handles.
fn mjcf_robot(
    mjcf: &str,
    name: &str,
) -> (
    PhysicsWorld,
    KjointSet,
    rapier_kjoint::io::urdf::UrdfRobotHandles,
) {
    let (mut w, _) = world(Vector::new(0.0, 0.0, -G as Real));
    let mut set = joints(4);
    let robot =
        common::robot::insert_mjcf_str(mjcf, name, ".", &mut w, &mut set, &Default::default())
            .unwrap();
    (w, set, robot)
}

/// The one-rod model of the MJCF tests with `actuator` on its hinge (and `defaults` in
/// `<default>`).
fn rod_model(defaults: &str, actuator: &str) -> String {
    format!(
        r#"<mujoco model="rod">
  <default>{defaults}</default>
  <worldbody>
    <body name="rod" pos="0 0 1">
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1"/>
    </body>
  </worldbody>
  <actuator>
    {actuator}
  </actuator>
</mujoco>"#
    )
}

/// A `<general>` servo as MuJoCo Menagerie writes its arms' (a class with an affine bias,
/// `gainprm="kp" biasprm="0 -kp -kv"`) is the `<position>` actuator of the same `kp`,
/// `kv`: the same motor, and the rod rests at the same static solution.
#[test]
fn an_mjcf_general_servo_is_the_position_actuator_it_writes() {
    let general = rod_model(
        r#"<default class="arm"><general dyntype="none" biastype="affine" ctrlrange="0.5 1" forcerange="-3 3"/></default>"#,
        r#"<general class="arm" name="servo" joint="hinge" gear="2" gainprm="50" biasprm="0 -50 -5"/>"#,
    );
    let (mut w, mut set, robot) = mjcf_robot(&general, "general.xml");
    assert!(
        !robot.notices.iter().any(|n| n.contains("not mapped")),
        "{:?}",
        robot.notices
    );
    let m = *set
        .get(robot.joints["hinge"])
        .unwrap()
        .motor(Dof::Rx)
        .unwrap();
    let position = rod_model(
        "",
        r#"<position name="servo" joint="hinge" gear="2" kp="50" kv="5" ctrlrange="0.5 1" forcerange="-3 3"/>"#,
    );
    let (_, set_p, robot_p) = mjcf_robot(&position, "position.xml");
    let mp = *set_p
        .get(robot_p.joints["hinge"])
        .unwrap()
        .motor(Dof::Rx)
        .unwrap();
    assert_eq!(m, mp);
    assert_eq!(
        (m.target_pos, m.stiffness, m.damping, m.max_force),
        (0.25, 200.0, 20.0, 6.0)
    );
    rests_short_of(&mut w, &mut set, &robot, -0.3);
}

/// The MJCF rod of [`rod_model`] on a servo of 200 N·m/rad, its target set to `target` and
/// stepped 3 s: it rests short of the target by the static error, at `θ = target −
/// m·g·(L/2)·sin θ/200` (1 kg, its centre of mass 0.25 m out), within 1e-4 rad.
#[track_caller]
fn rests_short_of(
    w: &mut PhysicsWorld,
    set: &mut KjointSet,
    robot: &rapier_kjoint::io::urdf::UrdfRobotHandles,
    target: f64,
) {
    let mut rest = target;
    for _ in 0..30 {
        rest = target - G * 0.25 * rest.sin() / 200.0;
    }
    assert!(robot.set_motor_target(set, "hinge", target, 0.0).unwrap());
    for _ in 0..180 {
        set.step(w, DT).unwrap();
    }
    let q = robot.joint_position(set, "hinge").unwrap();
    assert!(
        (q - rest).abs() < 1e-4,
        "the rod rests at {q} rad, expected {rest} for the target {target}"
    );
}

/// `<general>` with only a rate bias is a velocity servo, with no bias a constant torque
/// (capped over its control range); other gains and activation dynamics are named in a
/// notice; a bias that pushes away from its target is refused.
#[test]
fn mjcf_general_actuators_of_velocity_and_torque_and_the_ones_left_out() {
    let motor = |actuator: &str| {
        let (_, set, robot) = mjcf_robot(&rod_model("", actuator), "general.xml");
        let m = set
            .get(robot.joints["hinge"])
            .unwrap()
            .motor(Dof::Rx)
            .copied();
        (m, robot.notices)
    };
    let (m, _) =
        motor(r#"<general joint="hinge" gainprm="5" biastype="affine" biasprm="0 0 -5"/>"#);
    let m = m.unwrap();
    assert_eq!((m.target_vel, m.damping, m.stiffness), (0.0, 5.0, 0.0));
    let (m, _) = motor(r#"<general joint="hinge" gear="2" gainprm="3" ctrlrange="-1 0.5"/>"#);
    let m = m.unwrap();
    assert_eq!(
        (m.force, m.max_force, m.stiffness, m.damping),
        (0.0, 6.0, 0.0, 0.0)
    );
    for other in [
        r#"<general name="a" joint="hinge" gaintype="affine" gainprm="1 2"/>"#,
        r#"<general name="a" joint="hinge" dyntype="filter" dynprm="0.1" biastype="affine" biasprm="0 -1 0"/>"#,
    ] {
        let (m, notices) = motor(other);
        assert!(m.is_none());
        assert!(
            notices.iter().any(|n| n
                == "1 actuator(s) not mapped, a <general> of another gain, bias or activation \
                    dynamics than a fixed gain, an affine bias and none: a"),
            "{notices:?}"
        );
    }
    let (mut w, _) = world(Vector::new(0.0, 0.0, -G as Real));
    let mut set = joints(4);
    let pushing = rod_model(
        "",
        r#"<general joint="hinge" biastype="affine" biasprm="0 5 0"/>"#,
    );
    let e = common::robot::insert_mjcf_str(
        &pushing,
        "push.xml",
        ".",
        &mut w,
        &mut set,
        &Default::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("biasprm[1] and biasprm[2] <= 0 (here 5 and 0)"),
        "{e}"
    );
}

/// A servo stiffer than the substep resolves is noticed at the start, as a stiff spring
/// is: the update damps it (`h·k_p`), and its part of the readout then differs from the
/// moment the joint transmits. The 1 kg, 1 m rod (`W` = 12 rad/(N·m·s²) about its centre)
/// at 4 substeps of 1/60 s: `k_p` = 2e4 N·m/rad oscillates at `√(k_p·W)` = 490 rad/s,
/// `ω·h` = 2.04, which 9 substeps a frame resolve; `k_p` = 1000 (ω·h = 0.46) is not
/// noticed. No motor was noticed before (a UR5 shoulder of 1e4 N·m/rad read 80.9 N·m where
/// it transmitted 54.5; a robotics engineer's trial, 2026-12-04).
#[test]
fn a_servo_the_substep_cannot_resolve_is_noticed() {
    for (kp, noticed) in [(2e4, true), (1000.0, false)] {
        let (mut w, mut set, _) = horizontal_arm(KjointMotor::position(0.0, kp, 0.0));
        set.step(&mut w, DT).unwrap();
        let notices: Vec<_> = set
            .drain_events()
            .into_iter()
            .filter_map(|e| match e.kind {
                rapier_kjoint::KjointEventKind::StiffnessBeyondSubstep {
                    dof,
                    stiffness_of,
                    stiffness,
                    omega,
                    substeps_needed,
                    ..
                } => Some((
                    dof,
                    stiffness_of,
                    stiffness,
                    omega,
                    substeps_needed,
                    e.to_string(),
                )),
                _ => None,
            })
            .collect();
        if noticed {
            let [(dof, of, k, omega, needed, text)] = notices.as_slice() else {
                panic!("{notices:?}");
            };
            assert_eq!(
                (*dof, *of, *k, *needed),
                (
                    Dof::Rx,
                    rapier_kjoint::dynamics::DofStiffness::Motor,
                    kp,
                    9.0
                )
            );
            assert!(
                (omega - (kp * 12.0f64).sqrt()).abs() < 0.01 * omega,
                "{text}"
            );
            assert!(text.contains("rx motor"), "{text}");
        } else {
            assert!(notices.is_empty(), "{notices:?}");
        }
    }
}
