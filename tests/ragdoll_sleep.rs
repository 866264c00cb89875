//! Ragdolls on KJOINT2 joints at rest fall asleep (`dynamics::sleep`), also when they rest
//! on each other: the pair of a user trial's 50-ragdoll scene that never slept. The ragdoll
//! (72 kg, 11 capsules, spherical joints with cone and twist stops, revolute elbows and
//! knees, a viscosity on every free rotation so that it comes to rest) is the trial's.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;

/// The bodies, standing, pelvis centre at the origin (y up): name, centre, collider, mass
/// \[kg\].
fn parts() -> [(&'static str, [Real; 3], ColliderBuilder, Real); 11] {
    let cap = ColliderBuilder::capsule_y;
    [
        (
            "pelvis",
            [0.0, 0.0, 0.0],
            ColliderBuilder::capsule_x(0.08, 0.1),
            11.0,
        ),
        ("torso", [0.0, 0.38, 0.0], cap(0.14, 0.13), 20.0),
        ("head", [0.0, 0.80, 0.0], ColliderBuilder::ball(0.11), 5.0),
        ("uarm_l", [-0.24, 0.40, 0.0], cap(0.12, 0.05), 2.5),
        ("larm_l", [-0.24, 0.03, 0.0], cap(0.13, 0.045), 2.0),
        ("uarm_r", [0.24, 0.40, 0.0], cap(0.12, 0.05), 2.5),
        ("larm_r", [0.24, 0.03, 0.0], cap(0.13, 0.045), 2.0),
        ("thigh_l", [-0.1, -0.30, 0.0], cap(0.15, 0.07), 9.0),
        ("shin_l", [-0.1, -0.75, 0.0], cap(0.15, 0.055), 4.5),
        ("thigh_r", [0.1, -0.30, 0.0], cap(0.15, 0.07), 9.0),
        ("shin_r", [0.1, -0.75, 0.0], cap(0.15, 0.055), 4.5),
    ]
}

/// The joints: name, bodies, anchor (standing frame), axis (the twist axis of a spherical
/// joint, the hinge of a revolute one), and its stops: `Some(cone)` with a twist of
/// ±`range.1` for a spherical joint, `None` with `range` for a revolute one.
#[allow(clippy::type_complexity)]
fn joints() -> [(
    &'static str,
    [usize; 2],
    [Real; 3],
    [Real; 3],
    Option<Real>,
    [Real; 2],
); 10] {
    let (up, down, x) = ([0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]);
    [
        (
            "spine",
            [0, 1],
            [0.0, 0.105, 0.0],
            up,
            Some(0.4),
            [-0.3, 0.3],
        ),
        (
            "neck",
            [1, 2],
            [0.0, 0.675, 0.0],
            up,
            Some(0.6),
            [-0.6, 0.6],
        ),
        (
            "shoulder_l",
            [1, 3],
            [-0.24, 0.585, 0.0],
            down,
            Some(1.2),
            [-0.8, 0.8],
        ),
        (
            "elbow_l",
            [3, 4],
            [-0.24, 0.2125, 0.0],
            x,
            None,
            [-2.4, 0.05],
        ),
        (
            "shoulder_r",
            [1, 5],
            [0.24, 0.585, 0.0],
            down,
            Some(1.2),
            [-0.8, 0.8],
        ),
        (
            "elbow_r",
            [5, 6],
            [0.24, 0.2125, 0.0],
            x,
            None,
            [-2.4, 0.05],
        ),
        (
            "hip_l",
            [0, 7],
            [-0.1, -0.09, 0.0],
            down,
            Some(1.2),
            [-0.5, 0.5],
        ),
        (
            "knee_l",
            [7, 8],
            [-0.1, -0.5325, 0.0],
            x,
            None,
            [-0.05, 2.4],
        ),
        (
            "hip_r",
            [0, 9],
            [0.1, -0.09, 0.0],
            down,
            Some(1.2),
            [-0.5, 0.5],
        ),
        (
            "knee_r",
            [9, 10],
            [0.1, -0.5325, 0.0],
            x,
            None,
            [-0.05, 2.4],
        ),
    ]
}

/// A ragdoll of the trial's scene, number `k` of 50: 25 lying on the ground in a 5 × 5
/// grid, 25 dropped across them, turned 1.4 rad. Its bodies do not collide with their
/// joint neighbours; a viscosity of 2 N·m·s/rad on every free rotation.
fn ragdoll(w: &mut PhysicsWorld, set: &mut KjointSet, k: usize) -> Vec<RigidBodyHandle> {
    let (cell, layer) = (k % 25, k / 25);
    let jit = ((k * 37) % 17) as Real / 16.0 - 0.5;
    let yaw = if layer == 0 {
        0.3 * jit
    } else {
        1.4 + 0.3 * jit
    };
    let rot = Rotation::from_rotation_y(yaw)
        * Rotation::from_rotation_x(std::f64::consts::FRAC_PI_2 as Real + 0.4 * jit);
    let height = if layer == 0 {
        1.0 + 0.5 * (jit + 0.5)
    } else {
        2.3 + 0.7 * (jit + 0.5)
    };
    let pos = Vector::new(
        (cell % 5) as Real * 2.4 - 4.8,
        height,
        (cell / 5) as Real * 2.4,
    );
    let js = joints();
    let neighbours = |i: usize| -> u32 {
        (js.iter())
            .filter_map(|j| match j.1 {
                [a, b] if a == i => Some(1 << b),
                [a, b] if b == i => Some(1 << a),
                _ => None,
            })
            .fold(0, |m, b| m | b)
    };
    let v = |a: [Real; 3]| Vector::new(a[0], a[1], a[2]);
    let parts = parts();
    let bodies: Vec<RigidBodyHandle> = (parts.iter().enumerate())
        .map(|(i, (_, c, shape, mass))| {
            let groups = InteractionGroups::new(
                Group::from_bits_truncate(1 << i),
                Group::from_bits_truncate(!neighbours(i)),
                InteractionTestMode::And,
            );
            let body = RigidBodyBuilder::dynamic()
                .translation(pos + rot * v(*c))
                .rotation(rot.to_scaled_axis());
            let collider = shape.clone().mass(*mass).collision_groups(groups);
            w.insert(body, collider.friction(0.7)).0
        })
        .collect();
    for (name, [b1, b2], anchor, axis, cone, range) in js {
        let law = |lo: Real, hi: Real| {
            DofLaw::default()
                .with_stops(lo as f64, hi as f64)
                .with_viscosity(2.0)
        };
        let rx = law(range[0], range[1]);
        let prop = match cone {
            Some(c) => {
                let swing = law(-c, c).with_coupled_stops();
                KjointProperty::new(JointType::Spherical)
                    .with_dof(Dof::Rx, rx)
                    .with_dof(Dof::Ry, swing.clone())
                    .with_dof(Dof::Rz, swing)
            }
            None => KjointProperty::new(JointType::Revolute).with_dof(Dof::Rx, rx),
        };
        let j = KjointBuilder::new(prop)
            .name(format!("r{k}_{name}"))
            .world_frame1(rot * Rotation::from_rotation_arc(Vector::X, v(axis)))
            .local_anchor1(v(anchor) - v(parts[b1].1))
            .local_anchor2(v(anchor) - v(parts[b2].1));
        set.insert(j, bodies[b1], bodies[b2], &w.bodies).unwrap();
    }
    bodies
}

/// Ragdolls 11 and 36 of the trial's scene: the second dropped across the first. Every
/// body's rest measure `(|v| + |ω|·r)/2` stayed at or below 0.014 m/s from 2.5 to 10 s and
/// no body slept: rapier's step reset the sleep timer of two of their bodies (0.4 mm/s)
/// at every step, which the set read as the user's wake, starting the pair's rest over.
/// They sleep now within 5 s (rapier's own joints put such a pair to sleep).
#[test]
fn two_ragdolls_resting_on_each_other_fall_asleep() {
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81, 0.0),
        ..Default::default()
    };
    let g = w.insert_body(RigidBodyBuilder::fixed());
    let ground = ColliderBuilder::cuboid(20.0, 0.5, 20.0)
        .translation(Vector::new(0.0, -0.5, 4.8))
        .friction(0.7);
    w.insert_collider(ground, Some(g));
    let mut set = KjointSet::new();
    let mut bodies = ragdoll(&mut w, &mut set, 11);
    bodies.extend(ragdoll(&mut w, &mut set, 36));
    let mut asleep_at = None;
    for f in 1..=600 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        if asleep_at.is_none() && bodies.iter().all(|h| w.bodies[*h].is_sleeping()) {
            asleep_at = Some(f as f64 / 60.0);
        }
    }
    let t = asleep_at.expect("the two ragdolls never slept in 10 s");
    assert!(t < 5.0, "asleep at {t} s");
    assert!(
        bodies.iter().all(|h| w.bodies[*h].is_sleeping()),
        "woke again"
    );
}
