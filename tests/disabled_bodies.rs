//! A body disabled by the user (`RigidBody::set_enabled(false)`) with KJOINT2 joints: as
//! rapier does with its impulse joints (0.36: `JointEnabled::DisabledByAttachedBody`), the
//! joints of a disabled body act on nothing until it is enabled again; the other body moves
//! as if they were not there (a bob whose pivot is disabled falls at g), and the joints take
//! up again from their state at disabling when the body is enabled.

mod common;

use common::*;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, JointType, KjointEventKind, KjointHandle, KjointProperty, KjointSet,
};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

/// A world under gravity with a 5 kg pivot held to the ground by a rapier fixed joint
/// (no gravity of its own) and a 1 kg ball 1 m below it moving at 1 m/s along x: world,
/// ground, pivot, bob.
fn pivot_and_bob() -> (
    PhysicsWorld,
    RigidBodyHandle,
    RigidBodyHandle,
    RigidBodyHandle,
) {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let pivot = cuboid(&mut w, 5.0, Vector::new(0.05, 0.05, 0.05), Vector::ZERO);
    w.bodies[pivot].set_gravity_scale(0.0, true);
    w.impulse_joints
        .insert(ground, pivot, FixedJointBuilder::new(), true);
    let bob = ball(&mut w, 1.0, 0.1, Vector::new(0.0, -1.0, 0.0));
    w.bodies[bob].set_linvel(Vector::new(1.0, 0.0, 0.0), true);
    (w, ground, pivot, bob)
}

/// A pendulum: a 5 kg pivot block at the origin held to the fixed ground by a rapier fixed
/// joint, and a 1 kg bob (a ball) 1 m below it on a KJOINT2 joint of type `ty` at the pivot
/// (a revolute one about z), swinging at 1 m/s through the bottom at t = 0. World, set,
/// ground, pivot, bob, joint.
fn pendulum(
    ty: JointType,
) -> (
    PhysicsWorld,
    KjointSet,
    RigidBodyHandle,
    RigidBodyHandle,
    RigidBodyHandle,
    KjointHandle,
) {
    let (w, ground, pivot, bob) = pivot_and_bob();
    let mut set = joints(4);
    let prop = KjointProperty::new(ty);
    let j = add(&mut set, &w, prop, pivot, bob, |b| {
        let b = b.name("rod").local_anchor2(Vector::new(0.0, 1.0, 0.0));
        if ty == JointType::Revolute {
            b.world_axis(Vector::Z)
        } else {
            b
        }
    });
    (w, set, ground, pivot, bob, j)
}

fn run(w: &mut PhysicsWorld, set: &mut KjointSet, frames: usize) {
    for _ in 0..frames {
        set.step(w, DT).unwrap();
    }
}

fn vy(w: &PhysicsWorld, b: RigidBodyHandle) -> f64 {
    w.bodies[b].linvel().y as f64
}

fn pos(w: &PhysicsWorld, b: RigidBodyHandle) -> [f64; 3] {
    let p = w.bodies[b].translation();
    [p.x as f64, p.y as f64, p.z as f64]
}

/// The bob's swing energy: kinetic + potential (the pivot is held still) \[J\].
fn swing_energy(w: &PhysicsWorld, bob: RigidBodyHandle) -> f64 {
    let b = &w.bodies[bob];
    let v = b.linvel().length() as f64;
    let m = b.mass() as f64;
    0.5 * m * v * v + m * G * b.translation().y as f64
}

/// Whatever the joint's law and the body disabled: the bob falls at g, the joint reports
/// that it transmits nothing, and the disabled pivot stays where it was (rapier does not
/// simulate it). Its energies at the end of the last substep (`Kjoint::closed_energy`, what
/// the summary reports) stay what they were at disabling while the bob falls.
#[test]
fn a_bob_whose_pivot_is_disabled_falls_at_g() {
    for ty in [JointType::Spherical, JointType::Revolute] {
        let (mut w, mut set, _, pivot, bob, j) = pendulum(ty);
        run(&mut w, &mut set, 60);
        let held = applied_force(set.get(j).unwrap());
        assert!(held > 9.0, "{ty:?}: the rod carries the bob ({held} N)");
        let closed = set.get(j).unwrap().closed_energy(&w.bodies);
        w.bodies[pivot].set_enabled(false);
        let pivot_at = pos(&w, pivot);
        let v0 = vy(&w, bob);
        let t0 = set.time();
        run(&mut w, &mut set, 15);
        let a = (vy(&w, bob) - v0) / (set.time() - t0);
        println!("{ty:?}: the bob's acceleration {a} m/s² with its pivot disabled");
        assert!((a + G).abs() < 1e-3, "{ty:?}: a = {a} m/s²");
        let joint = set.get(j).unwrap();
        assert!(!joint.is_enabled());
        let s = joint.state().unwrap();
        assert_eq!(s.applied, Default::default(), "{ty:?}");
        assert_eq!(s.force, Default::default(), "{ty:?}");
        assert_eq!(pos(&w, pivot), pivot_at, "{ty:?}: the disabled pivot moved");
        assert_eq!(joint.closed_energy(&w.bodies), closed, "{ty:?}");
        let events = set.drain_events();
        let off: Vec<_> = events
            .iter()
            .filter(|e| matches!(e.kind, KjointEventKind::DisabledByBody { body: 1 }))
            .collect();
        assert_eq!(off.len(), 1, "{ty:?}: {events:?}");
        assert!(
            off[0].to_string().contains("body 1 was disabled"),
            "{}",
            off[0]
        );
    }
}

/// Disabled, the pivot lets the bob fall; the bob put back where and as it was and the pivot
/// enabled again, the rod holds it again at once (the anchors together within 1 mm, the rod's
/// force what it was) and the swing goes on as that of the same pendulum never disabled: no
/// energy gained, the same path.
#[test]
fn the_rod_holds_again_when_its_pivot_is_enabled_again() {
    for ty in [JointType::Spherical, JointType::Revolute] {
        let (mut w, mut set, _, pivot, bob, j) = pendulum(ty);
        let (mut w_ref, mut set_ref, _, _, bob_ref, _) = pendulum(ty);
        run(&mut w, &mut set, 60);
        run(&mut w_ref, &mut set_ref, 60);
        let before = applied_force(set.get(j).unwrap());
        let e0 = swing_energy(&w, bob);
        let saved = w.bodies[bob].clone();
        w.bodies[pivot].set_enabled(false);
        run(&mut w, &mut set, 15);
        let fell = saved.translation().y - w.bodies[bob].translation().y;
        assert!(fell > 0.2, "{ty:?}: the bob fell {fell} m");
        {
            let b = &mut w.bodies[bob];
            b.set_position(*saved.position(), true);
            b.set_linvel(saved.linvel(), true);
            b.set_angvel(saved.angvel(), true);
        }
        w.bodies[pivot].set_enabled(true);
        let (mut worst_gap, mut most, mut most_ref, mut apart) = (0.0f64, e0, e0, 0.0f64);
        let mut after = 0.0;
        for frame in 0..120 {
            set.step(&mut w, DT).unwrap();
            set_ref.step(&mut w_ref, DT).unwrap();
            let joint = set.get(j).unwrap();
            assert!(joint.is_enabled());
            if frame == 0 {
                after = applied_force(joint);
            }
            worst_gap = worst_gap.max(world_gap(joint));
            most = most.max(swing_energy(&w, bob));
            most_ref = most_ref.max(swing_energy(&w_ref, bob_ref));
            let (p, q) = (pos(&w, bob), pos(&w_ref, bob_ref));
            apart = apart.max((0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f64::max));
        }
        println!(
            "{ty:?}: rod force {before} N before, {after} N after; worst gap {worst_gap} m; \
             swing energy {e0} J at disabling, at most {most} J after ({most_ref} J never \
             disabled); {apart} m from the path never disabled"
        );
        assert!(
            (after - before).abs() < 0.02 * before,
            "{ty:?}: {before} N → {after} N"
        );
        assert!(worst_gap < 1e-3, "{ty:?}: gap {worst_gap} m");
        assert!(most <= most_ref + 1e-6, "{ty:?}: {most} J, {most_ref} J");
        assert!(
            apart < 1e-5,
            "{ty:?}: {apart} m from the path never disabled"
        );
        let events = set.drain_events();
        assert!(
            events
                .iter()
                .any(|e| matches!(e.kind, KjointEventKind::EnabledAgain)),
            "{ty:?}: {events:?}"
        );
    }
}

/// The bob disabled: it stays where it was (rapier does not simulate it), the rod transmits
/// nothing, and its pivot side is left alone. Enabled again, the swing goes on.
#[test]
fn a_disabled_bob_leaves_its_pivot_alone() {
    let (mut w, mut set, _, pivot, bob, j) = pendulum(JointType::Spherical);
    run(&mut w, &mut set, 60);
    let pivot_at = pos(&w, pivot);
    w.bodies[bob].set_enabled(false);
    let bob_at = pos(&w, bob);
    run(&mut w, &mut set, 30);
    assert_eq!(pos(&w, bob), bob_at);
    let moved = (0..3)
        .map(|i| (pos(&w, pivot)[i] - pivot_at[i]).abs())
        .fold(0.0, f64::max);
    assert!(moved < 1e-4, "the pivot moved {moved} m");
    assert_eq!(
        set.get(j).unwrap().state().unwrap().applied,
        Default::default()
    );
    assert!(set
        .drain_events()
        .iter()
        .any(|e| matches!(e.kind, KjointEventKind::DisabledByBody { body: 2 })));
    w.bodies[bob].set_enabled(true);
    run(&mut w, &mut set, 60);
    let joint = set.get(j).unwrap();
    assert!(joint.is_enabled() && world_gap(joint) < 1e-3);
    assert!(applied_force(joint) > 5.0);
}

/// A post welded (a KJOINT2 of type 8, every DOF blocked) on top of a base that a rapier
/// fixed joint holds: the base disabled, the post falls at g rather than stand on a body no
/// longer simulated. The disabled body is the joint's body 2 here.
#[test]
fn a_post_welded_on_a_disabled_base_falls_at_g() {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let base = cuboid(&mut w, 5.0, Vector::new(0.2, 0.05, 0.2), Vector::ZERO);
    w.impulse_joints
        .insert(ground, base, FixedJointBuilder::new(), true);
    let post = cuboid(
        &mut w,
        2.0,
        Vector::new(0.05, 0.5, 0.05),
        Vector::new(0.0, 0.6, 0.0),
    );
    let mut set = joints(4);
    let prop = KjointProperty::new(JointType::Fixed);
    let j = add(&mut set, &w, prop, post, base, |b| {
        b.local_anchor1(Vector::new(0.0, -0.55, 0.0))
            .local_anchor2(Vector::new(0.0, 0.05, 0.0))
    });
    run(&mut w, &mut set, 30);
    assert!(applied_force(set.get(j).unwrap()) > 15.0);
    w.bodies[base].set_enabled(false);
    let v0 = vy(&w, post);
    let t0 = set.time();
    run(&mut w, &mut set, 15);
    let a = (vy(&w, post) - v0) / (set.time() - t0);
    println!("the post's acceleration {a} m/s² with its base disabled");
    assert!((a + G).abs() < 1e-3, "a = {a} m/s²");
    assert!(set
        .drain_events()
        .iter()
        .any(|e| matches!(e.kind, KjointEventKind::DisabledByBody { body: 2 })));
}

/// A hinge with a spring and friction on its free DOF whose pivot is disabled: nothing of
/// its law moves while it is off (its energies keep their values), and, its bob put back as
/// it was and the pivot enabled again, it resumes as the same hinge never disabled: the same
/// spring and friction moments, the same energies, to the one substep in which the enabled
/// hinge has no prediction of what rapier's fixed joint on the pivot does (the never-disabled
/// hinge keeps its own: `ContactPrediction`), which the swing carries on: within 1e-3 of the
/// moments and energies over the next ten frames (1e-4 after one). A law that moved while
/// off would be off by the whole of it.
#[test]
fn a_disabled_joints_law_keeps_its_state() {
    let hinge = || {
        let (w, _, pivot, bob) = pivot_and_bob();
        let prop = KjointProperty::new(JointType::Revolute)
            .with_dof(Dof::Rx, DofLaw::spring(20.0).with_friction(200.0, 0.2));
        let mut set = joints(4);
        let j = add(&mut set, &w, prop, pivot, bob, |b| {
            b.local_anchor2(Vector::new(0.0, 1.0, 0.0))
                .world_axis(Vector::Z)
        });
        (w, set, pivot, bob, j)
    };
    let (mut w, mut set, pivot, bob, j) = hinge();
    let (mut w_ref, mut set_ref, _, _, j_ref) = hinge();
    run(&mut w, &mut set, 20);
    run(&mut w_ref, &mut set_ref, 20);
    // the set analyses its joints again when a body is disabled or enabled, as at any change
    // of the set (`get_mut`), which starts the substep's data over but the bodies' contact
    // prediction (the hinge's angle 2e-6 rad from the never-disabled one's a frame later
    // without the same change here)
    set_ref.get_mut(j_ref).unwrap();
    let energy = set.get(j).unwrap().energy();
    let saved = w.bodies[bob].clone();
    w.bodies[pivot].set_enabled(false);
    run(&mut w, &mut set, 30);
    assert_eq!(set.get(j).unwrap().energy(), energy);
    {
        let b = &mut w.bodies[bob];
        b.set_position(*saved.position(), true);
        b.set_linvel(saved.linvel(), true);
        b.set_angvel(saved.angvel(), true);
    }
    w.bodies[pivot].set_enabled(true);
    for _ in 0..10 {
        set.step(&mut w, DT).unwrap();
        set_ref.step(&mut w_ref, DT).unwrap();
        let (s, s_ref) = (
            set.get(j).unwrap().state().unwrap(),
            set_ref.get(j_ref).unwrap().state().unwrap(),
        );
        let (p, p_ref) = (&s.parts[3], &s_ref.parts[3]);
        println!(
            "spring {} N·m, friction {} N·m ({} and {} never disabled)",
            p.elastic, p.friction, p_ref.elastic, p_ref.friction
        );
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-3 * b.abs() + 1e-12;
        assert!(close(p.elastic, p_ref.elastic), "{p:?} {p_ref:?}");
        assert!(close(p.friction, p_ref.friction), "{p:?} {p_ref:?}");
        let (e, e_ref) = (&s.energy, &s_ref.energy);
        for (a, b) in [
            (e.elastic, e_ref.elastic),
            (e.damping, e_ref.damping),
            (e.friction, e_ref.friction),
        ] {
            assert!(close(a, b), "{e:?} {e_ref:?}");
        }
    }
}

/// A tumbling bar (a box of three different moments of inertia spun near its intermediate
/// axis) whose pivot is disabled turns as the same bar with no joint at all: rapier's
/// gyroscopic term, which the set takes over for the bodies it steps, is rapier's again
/// while the bar's only joint is out.
#[test]
fn a_free_bar_whose_joint_is_off_tumbles_as_one_without_joints() {
    let bar = |w: &mut PhysicsWorld| {
        let b = cuboid(
            w,
            2.0,
            Vector::new(0.3, 0.1, 0.05),
            Vector::new(0.0, -1.0, 0.0),
        );
        w.bodies[b].set_angvel(Vector::new(0.05, 6.0, 0.05), true);
        b
    };
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let pivot = cuboid(&mut w, 5.0, Vector::new(0.05, 0.05, 0.05), Vector::ZERO);
    w.bodies[pivot].set_gravity_scale(0.0, true);
    w.impulse_joints
        .insert(ground, pivot, FixedJointBuilder::new(), true);
    let b = bar(&mut w);
    let mut set = joints(4);
    let j = add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Spherical),
        pivot,
        b,
        |k| k.local_anchor2(Vector::new(0.0, 1.0, 0.0)),
    );
    set.step(&mut w, DT).unwrap();
    w.bodies[pivot].set_enabled(false);
    // the same bar, alone in a world stepped as the set steps it (4 substeps a frame)
    let (mut w2, _) = world(Vector::new(0.0, -G as Real, 0.0));
    let b2 = bar(&mut w2);
    {
        let (src, dst) = (w.bodies[b].clone(), &mut w2.bodies[b2]);
        dst.set_position(*src.position(), true);
        dst.set_linvel(src.linvel(), true);
        dst.set_angvel(src.angvel(), true);
    }
    let mut alone = joints(4);
    let mut worst = 0.0f64;
    for _ in 0..60 {
        set.step(&mut w, DT).unwrap();
        alone.step(&mut w2, DT).unwrap();
        let (q1, q2) = (w.bodies[b].rotation(), w2.bodies[b2].rotation());
        // (the angle of q1⁻¹·q2 from its vector part: `angle_between`'s acos reads f32 noise
        // as 1e-3 rad)
        let d = q1.inverse() * *q2;
        worst = worst.max(2.0 * (d.x * d.x + d.y * d.y + d.z * d.z).sqrt() as f64);
    }
    assert!(!set.get(j).unwrap().is_enabled());
    println!("the bar's orientation at most {worst} rad from the bar without joints");
    assert!(worst < 1e-6, "{worst} rad");
}

/// A pendulum swinging from the ground beside a pair of boxes hinged together and falling
/// freely; at frame `freeze` (if any) both boxes are made fixed (a vehicle frozen for a
/// cutscene), and at frame `thaw` the second is made dynamic again. Returns the set, the
/// pair's joint, the lowest the second box's centre went below the first's after the
/// thaw, and the bob's pose at every frame.
fn frozen_pair(
    freeze: Option<usize>,
    thaw: usize,
) -> (KjointSet, KjointHandle, Real, Vec<[Real; 3]>) {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let bob = ball(&mut w, 1.0, 0.1, Vector::new(1.0, 0.0, 0.0));
    add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Spherical),
        ground,
        bob,
        |b| b,
    );
    let a = cuboid(&mut w, 2.0, Vector::splat(0.1), Vector::new(5.0, 0.0, 0.0));
    let b = cuboid(&mut w, 1.0, Vector::splat(0.1), Vector::new(5.3, 0.0, 0.0));
    let hinge = add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Revolute),
        a,
        b,
        |k| {
            k.world_axis(Vector::Z)
                .local_anchor1(Vector::new(0.15, 0.0, 0.0))
                .local_anchor2(Vector::new(-0.15, 0.0, 0.0))
                .contacts_enabled(false)
        },
    );
    let (mut poses, mut lowest): (_, Real) = (Vec::new(), 0.0);
    for f in 0..thaw + 60 {
        if Some(f) == freeze {
            for hb in [a, b] {
                w.bodies[hb].set_body_type(RigidBodyType::Fixed, true);
            }
        }
        if freeze.is_some() && f == thaw {
            w.bodies[b].set_body_type(RigidBodyType::Dynamic, true);
        }
        set.step(&mut w, DT).expect("every step runs");
        let p = w.bodies[bob].translation();
        poses.push([p.x, p.y, p.z]);
        if f >= thaw {
            lowest = lowest.max(w.bodies[a].translation().y - w.bodies[b].translation().y);
        }
    }
    (set, hinge, lowest, poses)
}

/// A joint both of whose bodies are made fixed after its insertion acts on nothing (as
/// rapier's joints between such bodies), with an event, and acts again when one is
/// dynamic again; the rest of the world runs on unchanged. Every step failed before
/// ("automatic stiffness is zero: neither body is dynamic"), and the pendulum beside
/// stopped with it (a game developer's trial, 2026-12-04).
#[test]
fn a_joint_whose_bodies_are_both_made_fixed_rests_and_the_world_runs_on() {
    let (_, _, _, free) = frozen_pair(None, 60);
    let (mut set, hinge, lowest, frozen) = frozen_pair(Some(30), 60);
    // the pendulum beside is not touched by the pair's change
    assert_eq!(free, frozen);
    let kinds: Vec<_> = set
        .drain_events()
        .into_iter()
        .filter(|e| matches!(&e.source, rapier_kjoint::EventSource::Joint { handle, .. } if *handle == hinge))
        .map(|e| (e.kind, e.time))
        .collect();
    let t = |f: f64| f * DT;
    assert!(
        matches!(kinds.as_slice(), [(KjointEventKind::NoDynamicBody, t1), (KjointEventKind::EnabledAgain, t2)]
            if (*t1 - t(30.0)).abs() < 1e-9 && (*t2 - t(60.0)).abs() < 1e-9),
        "{kinds:?}"
    );
    // thawed, the second box swings from the first on the hinge: its centre, 0.15 m from
    // the hinge, goes down to 0.15 m below it, its anchor held (a free fall would have
    // taken it 4.9 m down in the second)
    let j = set.get(hinge).unwrap();
    assert!(j.is_enabled());
    assert!(anchor_gap(j) < 1e-3, "gap {}", anchor_gap(j));
    assert!((lowest - 0.15).abs() < 2e-3, "went {lowest} m below");
}
