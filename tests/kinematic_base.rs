//! A body under a joint moved as rapier users move one: a kinematic position-based base
//! (`RigidBodyBuilder::kinematic_position_based`) given its pose for the frame with
//! `set_next_kinematic_translation` before each `KjointSet::step`. The set steps rapier once
//! a substep, where a target set for the frame was reached in the first substep (the base
//! at rest in the others), and the joints read the velocity of the base's last step, not the
//! one rapier gives it in the substep: the joint's anchors parted at every frame's start and
//! the pendulum below was jerked. The set now spreads the frame's motion over its substeps
//! and reads the base's velocity from its next pose.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{JointType, KjointProperty, KjointSet, SubstepPhase};

const DT: f64 = 1.0 / 60.0;

/// A kinematic base at (0, 1, 0) and a 1 kg bob hung 0.5 m below it on a joint of type
/// `joint` (anchored at the base's origin), in a set of 4 substeps: the world, the set, the
/// base and the bob.
fn hung_below_a_base(
    joint: JointType,
) -> (PhysicsWorld, KjointSet, RigidBodyHandle, RigidBodyHandle) {
    let (mut w, _) = common::world(Vector::new(0.0, -9.81, 0.0));
    let base = w.insert_body(
        RigidBodyBuilder::kinematic_position_based().translation(Vector::new(0.0, 1.0, 0.0)),
    );
    let bob = common::point_body(&mut w, 1.0, Vector::splat(0.01), Vector::new(0.0, 0.5, 0.0));
    let mut set = common::joints(4);
    common::add(&mut set, &w, KjointProperty::new(joint), base, bob, |b| {
        b.local_anchor2(Vector::new(0.0, 0.5, 0.0))
    });
    (w, set, base, bob)
}

/// A 1 kg bob hung 0.5 m below a kinematic base at (0, 1, 0) on a joint of type `joint`; the
/// base's translation at time `t` is `(x(t), 1, 0)`, set before each frame. Returns the
/// largest anchor gap \[m\] and the world, the set and the bob after `frames`.
fn run(
    joint: JointType,
    x: impl Fn(f64) -> f64,
    frames: usize,
) -> (f64, PhysicsWorld, KjointSet, RigidBodyHandle) {
    let (mut w, mut set, base, bob) = hung_below_a_base(joint);
    let below = Vector::new(0.0, 0.5, 0.0);
    let mut max_gap = 0.0f64;
    for f in 1..=frames {
        let t = f as f64 * DT;
        w.bodies[base].set_next_kinematic_translation(Vector::new(x(t) as Real, 1.0, 0.0));
        set.step(&mut w, DT).unwrap();
        let gap = w.bodies[base].translation() - w.bodies[bob].position() * below;
        max_gap = max_gap.max(gap.length() as f64);
    }
    (max_gap, w, set, bob)
}

#[test]
fn a_base_moved_at_a_steady_speed_carries_what_it_holds_at_that_speed() {
    // 1 m/s along x for 1 s, the bob on a fixed joint
    let (gap, w, _, bob) = run(JointType::Fixed, |t| t, 60);
    let v = w.bodies[bob].linvel();
    println!("max gap {gap:.3e} m, bob velocity {v:?}");
    // measured 0.16 mm (at the start from rest) and 1.000 m/s; before, the base jumped 4
    // times as fast in the first substep and stood in the others: 3.4 mm, and the bob moved
    // at −0.79 m/s at the end of the last frame
    assert!(gap < 5e-4, "gap {gap} m");
    assert!(
        (v.x as f64 - 1.0).abs() < 0.01 && (v.y as f64).abs() < 0.01,
        "bob velocity {v:?}"
    );
}

#[test]
fn a_base_shaken_frame_by_frame_keeps_its_joint_closed_and_books_its_work() {
    // 5 cm at 5 Hz for 5 s: the base's acceleration reaches 49 m/s²
    let omega = 2.0 * std::f64::consts::PI * 5.0;
    let (gap, w, set, bob) = run(JointType::Spherical, |t| 0.05 * (omega * t).sin(), 300);
    // the bob's energy, from its start at rest 0.5 m up (m·g·y of 4.905 J then)
    let energy = rapier_kjoint::dynamics::energy::mechanical_energy(&w.bodies, w.gravity) - 4.905;
    let _ = bob;
    let booked = set.driven_work()
        - common::dissipated(&set)
        - set.iter().map(|(_, j)| j.energy().elastic).sum::<f64>();
    println!(
        "max gap {gap:.3e} m, bob energy {energy:.4} J, driven work less the joint's {booked:.4} J"
    );
    // measured 0.21 mm, about the base's `a·h²/β` (β = 3): 0.28 mm (before: 4.5 mm)
    assert!(gap < 5e-4, "gap {gap} m");
    // what the base's motion did through the joint is what the bob holds: 0.0414 J booked,
    // 0.0433 J held (before: −10.97 J booked for a bob of 0.24 J)
    assert!(
        (energy - booked).abs() < 0.01 + 0.02 * energy.abs(),
        "bob {energy} J, work {booked} J"
    );
}

/// A program that moves the base substep by substep from a `step_with` hook (its next pose
/// set at each substep's `After` for the next one, as a controller does): the set leaves
/// the base to it, and the load moves at the base's speed (a target set for one substep
/// must not be spread over a frame).
#[test]
fn a_base_a_hook_moves_substep_by_substep_is_left_to_it() {
    let (mut w, mut set, base, bob) = hung_below_a_base(JointType::Fixed);
    let h = DT / 4.0;
    // 1 m/s along x: the first substep's target, then each next one from the hook
    w.bodies[base].set_next_kinematic_translation(Vector::new(h as Real, 1.0, 0.0));
    for _ in 0..60 {
        set.step_with(&mut w, DT, |phase, w, set| {
            if phase == SubstepPhase::After {
                let x = set.time() + h;
                w.bodies[base].set_next_kinematic_translation(Vector::new(x as Real, 1.0, 0.0));
            }
            Ok::<(), rapier_kjoint::SimError>(())
        })
        .unwrap();
    }
    let (vb, x) = (w.bodies[bob].linvel(), w.bodies[base].translation().x);
    println!("bob velocity {vb:?}, base at x = {x}");
    // measured 1.000 m/s and x = 1.000 m
    assert!((x as f64 - 1.0).abs() < 1e-3, "base at {x}");
    assert!((vb.x as f64 - 1.0).abs() < 0.01, "bob velocity {vb:?}");
}
