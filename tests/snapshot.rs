//! A snapshot of a world and its joints ([`Snapshot`]), restored, runs on with the same
//! bits: what a user resetting an episode or rolling a game back to a saved frame relies
//! on. It holds clones of rapier's sets and of the `KjointSet`, with its joints' law states
//! (friction, stops, sensor locks, energies) and the substep's carried state (the contact
//! prediction, the end-rate correction of the energy book).

mod common;

#[path = "../benches/scenes.rs"]
mod scenes;

use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, JointType, KjointMotor, KjointProperty, KjointSet, SensorCondition, Snapshot,
};

/// Hinged capsules (a hinge with friction and stops) falling onto a ground box and sliding
/// on it, a drawer on a slide with a spring, viscosity and stops, pushed by a motor, and a
/// pendulum on a ball joint whose sensor locks it when it swings past 0.2 rad.
fn scene() -> (PhysicsWorld, KjointSet) {
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    w.insert_collider(ColliderBuilder::cuboid(5.0, 0.1, 5.0), Some(ground));
    let mut set = common::joints(4);

    // two capsules hinged end to end, tilted, above the ground
    let capsule = |w: &mut PhysicsWorld, x: Real| {
        w.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(x, 0.6, 0.0))
                .rotation(Vector::new(0.0, 0.0, 0.3))
                .can_sleep(false),
            ColliderBuilder::capsule_x(0.25, 0.05).mass(1.5),
        )
        .0
    };
    let a = capsule(&mut w, 0.0);
    let b = capsule(&mut w, 0.6);
    let hinge = KjointProperty::new(JointType::Revolute).with_dof(
        Dof::Rx,
        DofLaw::default()
            .with_stops(-0.4, 0.4)
            .with_friction(200.0, 0.3),
    );
    common::add(&mut set, &w, hinge, a, b, |j| {
        j.world_axis(Vector::Z)
            .local_anchor1(Vector::new(0.3, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.3, 0.0, 0.0))
            .contacts_enabled(false)
    });

    // a drawer on a slide along x, sprung, damped, stopped, driven by a motor
    let drawer = w
        .insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(-2.0, 1.0, 0.0))
                .can_sleep(false),
            ColliderBuilder::cuboid(0.2, 0.1, 0.2).mass(5.0),
        )
        .0;
    let slide = KjointProperty::new(JointType::Translational).with_dof(
        Dof::Dx,
        DofLaw::spring(300.0)
            .with_viscosity(2.0)
            .with_stops(-0.3, 0.25),
    );
    let slider = common::add(&mut set, &w, slide, ground, drawer, |j| {
        j.world_axis(Vector::X)
            .local_anchor1(Vector::new(-2.0, 1.0, 0.0))
    });
    set.set_motor(slider, Dof::Dx, Some(KjointMotor::velocity(0.4, 60.0)))
        .unwrap();

    // a pendulum on a ball joint, started 0.29 rad out, locked by its sensor when it has
    // swung 0.2 rad (about x) towards the vertical
    let bob = common::ball(&mut w, 2.0, 0.1, Vector::new(2.0, 1.5, 0.3));
    let ball = KjointProperty::new(JointType::Spherical).with_sensor(1);
    let pendulum = common::add(&mut set, &w, ball, ground, bob, |j| {
        j.local_anchor1(Vector::new(2.0, 2.5, 0.0))
            .local_anchor2(Vector::new(0.0, 1.0, -0.3))
    });
    set.add_sensor(
        1,
        SensorCondition::DofPasses {
            joint: pendulum,
            dof: Dof::Rx,
            value: 0.2,
        },
    )
    .unwrap();
    (w, set)
}

/// The world's state a user sees and the joints carry: every body's pose and velocity, and
/// every joint's readout and energies, as text of their bits.
fn state(w: &PhysicsWorld, set: &KjointSet) -> String {
    let mut s = String::new();
    for (h, b) in w.bodies.iter() {
        s += &format!(
            "{h:?} {:?} {:?} {:?}\n",
            b.position(),
            b.linvel(),
            b.angvel()
        );
    }
    for (h, j) in set.iter() {
        s += &format!(
            "{h:?} {:?} {:?} {:?}\n",
            j.state(),
            j.energy(),
            j.sensor_lock()
        );
    }
    s
}

fn frames(w: &mut PhysicsWorld, set: &mut KjointSet, n: usize) {
    for _ in 0..n {
        set.step(w, 1.0 / 60.0).unwrap();
    }
}

#[test]
fn a_restored_snapshot_runs_on_with_the_same_bits() {
    let (mut w, mut set) = scene();
    // into the contacts, the friction's stick and slip, the stops and the lock
    frames(&mut w, &mut set, 45);
    let snapshot = Snapshot::take(&w, &set);
    let saved = state(&w, &set);
    // what a snapshot holds, printed (`{:?}`: in a user's struct that derives `Debug`)
    let shown = format!("{snapshot:?}");
    let expected = format!(
        "time: {:?}, gravity: {:?}, bodies: {}, colliders: {}, impulse_joints: {}, kjoints: {}",
        set.time(),
        w.gravity,
        w.bodies.len(),
        w.colliders.len(),
        w.impulse_joints.len(),
        set.len()
    );
    assert!(shown.contains(&expected), "{shown}");

    frames(&mut w, &mut set, 60);
    let ran = state(&w, &set);

    // the user rolls back to the saved frame and steps again, in a new world
    let (mut w2, mut set2) = snapshot.restore();
    assert_eq!(
        state(&w2, &set2),
        saved,
        "the snapshot is the state it was taken of"
    );
    frames(&mut w2, &mut set2, 60);
    assert_eq!(
        state(&w2, &set2),
        ran,
        "the restored run parts from the original"
    );

    // or in the world that ran on (its pipeline kept), twice
    for _ in 0..2 {
        snapshot.restore_into(&mut w, &mut set);
        assert_eq!(state(&w, &set), saved);
        frames(&mut w, &mut set, 60);
        assert_eq!(state(&w, &set), ran, "restored in place");
    }

    // the run did something: the sensor locked the ball joint, the capsules landed
    assert_ne!(ran, saved);
    assert!(set.sensor_active(1), "the pendulum's sensor did not fire");
    assert!(set.iter().any(|(_, j)| j.sensor_lock().is_some()));
}

/// The bench scenes that take the solver's other paths: many islands stepped in tiles that
/// share one solver (2100 pendulums), a loop factorised by blocks (a ring), a four-bar
/// whose loop is ungrounded, asleep pendulums, capsules landing on a box.
#[test]
fn tiles_loops_and_asleep_islands_restore_with_the_same_bits() {
    for scene in [
        scenes::pendulums(2100),
        scenes::ring(10),
        scenes::four_bar(false),
        scenes::resting_pendulums(5),
        scenes::capsules_on_ground(4),
    ] {
        let mut k = scene.kjoint();
        for _ in 0..20 {
            k.frame();
        }
        let snapshot = Snapshot::take(&k.world, &k.joints);
        for _ in 0..20 {
            k.frame();
        }
        let ran = state(&k.world, &k.joints);
        let (world, joints) = snapshot.restore();
        let mut restored = scenes::KjointWorld {
            world,
            joints,
            bodies: k.bodies.clone(),
            handles: k.handles.clone(),
        };
        for _ in 0..20 {
            restored.frame();
        }
        assert!(
            state(&restored.world, &restored.joints) == ran,
            "{}: the restored run parts from the original",
            scene.name
        );
    }
}

/// With the cargo feature `serde-serialize` a world and its joints go through serde (here
/// CBOR, as a file would hold them), as a [`Snapshot`] or as rapier's `PhysicsWorld` and the
/// `KjointSet` themselves, and step on with the same bits: the joint set's solver
/// workspace, not saved, is built again when the set is read back.
#[cfg(feature = "serde-serialize")]
#[test]
fn a_world_saved_with_serde_steps_on_with_the_same_bits() {
    let scenes = || {
        let k = scenes::pendulums(1100).kjoint();
        [scene(), (k.world, k.joints)]
    };
    for (mut w, mut set) in scenes() {
        frames(&mut w, &mut set, 45);
        let mut file = Vec::new();
        ciborium::into_writer(&Snapshot::take(&w, &set), &mut file).expect("serialized");
        frames(&mut w, &mut set, 60);
        let ran = state(&w, &set);
        let saved: Snapshot = ciborium::from_reader(file.as_slice()).expect("deserialized");
        let (mut w2, mut set2) = saved.restore();
        frames(&mut w2, &mut set2, 60);
        assert!(
            state(&w2, &set2) == ran,
            "a snapshot restored from CBOR parts from the original"
        );
    }
    // and in JSON, a text format whose map keys are strings (a body handle as a map key
    // made `serde_json` refuse the set: "key must be a string"; a user trial, 2026-12-04),
    // before the first step too (a joint's "no notice yet", NaN, was written `null`)
    for (k, (mut w, mut set)) in scenes().into_iter().enumerate() {
        frames(&mut w, &mut set, if k == 0 { 0 } else { 45 });
        let text = serde_json::to_string(&Snapshot::take(&w, &set)).expect("serialized to JSON");
        let set_before = set.clone();
        frames(&mut w, &mut set, 60);
        let ran = state(&w, &set);
        let saved: Snapshot = serde_json::from_str(&text).expect("deserialized from JSON");
        // the set read back is saved with the same bytes (its body maps and sets were
        // written in their hashers' order, which differs from map to map)
        let set_text = serde_json::to_string(&set_before).expect("the set to JSON");
        let again: KjointSet = serde_json::from_str(&set_text).expect("the set from JSON");
        assert!(
            serde_json::to_string(&again).unwrap() == set_text,
            "the set read back from JSON is saved with other bytes"
        );
        let (mut w2, mut set2) = saved.restore();
        frames(&mut w2, &mut set2, 60);
        assert!(
            state(&w2, &set2) == ran,
            "a snapshot restored from JSON parts from the original"
        );
    }
    for (mut w, mut set) in scenes() {
        frames(&mut w, &mut set, 45);
        let mut file = Vec::new();
        ciborium::into_writer(&(&w, &set), &mut file).expect("serialized");
        let structure = (set.island_count(), set.loop_joints());
        frames(&mut w, &mut set, 60);
        let ran = state(&w, &set);
        let (mut w2, mut set2): (PhysicsWorld, KjointSet) =
            ciborium::from_reader(file.as_slice()).expect("deserialized");
        // what the set says of its structure before it is stepped
        assert!(structure.0 > 0);
        assert_eq!((set2.island_count(), set2.loop_joints()), structure);
        frames(&mut w2, &mut set2, 60);
        assert!(
            state(&w2, &set2) == ran,
            "a world and set read from CBOR part from the original"
        );
    }
}

/// An event saved before a motor counted in a DOF's stiffness (`DofStiffness::Together`
/// without its `motor` flag) reads back, the motor not taking part.
#[cfg(feature = "serde-serialize")]
#[test]
fn a_together_stiffness_saved_without_its_motor_flag_reads_back() {
    let old = r#"{"Together":{"spring":true,"stop":false,"friction":true,"connector":false}}"#;
    use rapier_kjoint::dynamics::DofStiffness;
    let read: DofStiffness = serde_json::from_str(old).expect("an old event's stiffness");
    assert_eq!(
        read,
        DofStiffness::Together {
            spring: true,
            stop: false,
            friction: true,
            connector: false,
            motor: false,
        }
    );
}
