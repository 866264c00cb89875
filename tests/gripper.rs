//! KJOINT2 joints beside rapier's own joints and contacts in one world (issue 13, item 7):
//! the arm with a gripper of `assets/scenes/arm_gripper.toml` picks a box off a table. Its
//! shoulder, elbow and wrist are KJOINT2 joints, its fingers rapier impulse joints with
//! position motors, the box is held by the fingers' contacts alone, and the arm hangs from
//! a kinematic lift that rises by 10 cm between 1 s and 2 s.
//!
//! What a user sees, checked at every substep of the run through the library (the scene
//! as `kjoint run` builds it): the box rises by the commanded 10 cm within 1 cm and stays
//! up; every KJOINT2 joint's anchors stay within 1 cm and its URDF limit within 0.05 rad;
//! every rapier joint's anchors (from the bodies' poses and the joint's local frames) stay
//! within 1 cm across its locked axes and its travel within its limits.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

use rapier3d_urdf::urdf_rs;
use rapier_kjoint::dynamics::KjointEvent;
use rapier_kjoint::output::{Observer, OutputError};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::scene::{self, RunOptions};
use rapier_kjoint::KjointSet;
use std::collections::BTreeMap;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// What the run showed, over every substep.
#[derive(Default)]
struct Watch {
    /// Name and handle of the box, the kinematic base and the rapier joints.
    box_body: Option<RigidBodyHandle>,
    base: Option<RigidBodyHandle>,
    rapier: Vec<(String, ImpulseJointHandle)>,
    /// URDF limits by joint name [rad or m].
    limits: BTreeMap<String, (f64, f64)>,
    /// (time, box height, base height).
    heights: Vec<(f64, f64, f64)>,
    /// Largest KJOINT2 anchor gap [m] and the joint.
    kjoint_gap: (f64, String),
    /// Largest overrun of a KJOINT2 joint's URDF limit [rad] and the joint.
    kjoint_overrun: (f64, String),
    /// Largest anchor separation of a rapier joint across its locked axes [m] and the joint.
    rapier_gap: (f64, String),
    /// Largest overrun of a rapier joint's limits [m] and the joint.
    rapier_overrun: (f64, String),
    /// Finger travel [m] per rapier joint at the last record.
    travel: BTreeMap<String, f64>,
    records: usize,
}

fn worse(slot: &mut (f64, String), v: f64, name: &str) {
    // a NaN counts as the worst
    if v.is_nan() || v > slot.0 {
        *slot = (v, name.to_string());
    }
}

fn f64v(v: Vector) -> nalgebra::Vector3<f64> {
    nalgebra::Vector3::new(v.x as f64, v.y as f64, v.z as f64)
}

impl Observer for Watch {
    fn record(
        &mut self,
        time: f64,
        world: &PhysicsWorld,
        joints: &KjointSet,
        _events: &[KjointEvent],
    ) -> Result<(), OutputError> {
        self.records += 1;
        let b = &world.bodies[self.box_body.unwrap()];
        let base = &world.bodies[self.base.unwrap()];
        self.heights
            .push((time, b.translation().z as f64, base.translation().z as f64));
        for (_, j) in joints.iter() {
            let Some(s) = j.state() else { continue };
            let gap =
                (nalgebra::Vector3::from(s.anchor2) - nalgebra::Vector3::from(s.anchor1)).norm();
            worse(&mut self.kjoint_gap, gap, &j.name);
            let (lo, hi) = self.limits[&j.name];
            let q = s.q[3]; // rx: every KJOINT2 joint of the arm is revolute
            worse(
                &mut self.kjoint_overrun,
                (q - hi).max(lo - q).max(0.0),
                &j.name,
            );
        }
        for (name, h) in &self.rapier {
            let j = &world.impulse_joints.get(*h).unwrap();
            let (p1, p2) = (
                world.bodies[j.body1()].position(),
                world.bodies[j.body2()].position(),
            );
            let f1 = *p1 * j.data.local_frame1;
            let f2 = *p2 * j.data.local_frame2;
            let d = f64v(f2.translation - f1.translation);
            let axis = f64v(f1.rotation * Vector::X);
            let travel = d.dot(&axis);
            let across = (d - travel * axis).norm();
            worse(&mut self.rapier_gap, across, name);
            let (lo, hi) = self.limits[name];
            worse(
                &mut self.rapier_overrun,
                (travel - hi).max(lo - travel).max(0.0),
                name,
            );
            self.travel.insert(name.clone(), travel);
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(())
    }
}

#[test]
fn the_arm_lifts_the_box_in_its_rapier_fingers_with_every_joint_within_its_bound() {
    let path = root().join("assets/scenes/arm_gripper.toml");
    let (sc, src) = scene::load(&path).unwrap();
    let mut built = scene::build(&sc, &src).unwrap();
    let body = |name: &str| {
        built
            .bodies
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, h)| *h)
            .unwrap()
    };
    let urdf = urdf_rs::read_file(root().join("assets/urdf/arm_gripper.urdf")).unwrap();
    let mut watch = Watch {
        box_body: Some(body("box")),
        base: Some(body("base_link")),
        rapier: built.rapier_joints.clone(),
        limits: urdf
            .joints
            .iter()
            .map(|j| (j.name.clone(), (j.limit.lower, j.limit.upper)))
            .collect(),
        ..Default::default()
    };
    // the scene is what the test is about: three KJOINT2 joints, two rapier ones
    assert_eq!(built.joints.len(), 3);
    let names: Vec<&str> = watch.rapier.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["left_finger", "right_finger"]);
    assert!(!built.world.bodies[watch.base.unwrap()].is_dynamic());

    let started = std::time::Instant::now();
    let options = RunOptions {
        log: Some(scene::schema::LogEvery::Substep),
        ..Default::default()
    };
    let stats = scene::run(&mut built, &options, &mut [&mut watch], &mut |_, _| {}).unwrap();
    let elapsed = started.elapsed();

    // the commanded rise: the lift's displacement at the end of the run
    let lift = &built.motions[0];
    assert_eq!(lift.body_name, "base_link");
    let commanded = lift.vector[2] * lift.function.value(stats.time);
    assert!((commanded - 0.10).abs() < 1e-12, "{commanded}");

    let at = |t: f64| {
        watch
            .heights
            .iter()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .copied()
            .unwrap()
    };
    let (_, box0, base0) = at(0.95); // the fingers closed, before the lift
    let (_, box_end, base_end) = at(stats.time);
    let lowest_held = watch
        .heights
        .iter()
        .filter(|h| h.0 >= 2.0)
        .map(|h| h.1)
        .fold(f64::INFINITY, f64::min);
    println!(
        "run {elapsed:?} ({} records); box {box0:.5} -> {box_end:.5} m: rise {:.5} m \
         (commanded {commanded}), lowest after the lift {:.5}; base rise {:.5} m; KJOINT2 \
         anchors {:.3e} m apart ({}), URDF limit overrun {:.3e} rad ({}); rapier anchors \
         {:.3e} m apart ({}), travel overrun {:.3e} m ({}), travel at the end {:?}; work of \
         the lift {:.4} J",
        watch.records,
        box_end - box0,
        lowest_held - box0,
        base_end - base0,
        watch.kjoint_gap.0,
        watch.kjoint_gap.1,
        watch.kjoint_overrun.0,
        watch.kjoint_overrun.1,
        watch.rapier_gap.0,
        watch.rapier_gap.1,
        watch.rapier_overrun.0,
        watch.rapier_overrun.1,
        watch.travel,
        stats.motion_work,
    );
    assert_eq!(watch.records, 721, "every substep and the start");
    // The box stood still on the table until the lift (the grip did not push it around).
    assert!(
        (box0 - (-0.41)).abs() < 1e-3,
        "box at {box0} before the lift"
    );
    // The lift moved the base by exactly the commanded amount, and the box with it.
    assert!(
        (base_end - base0 - commanded).abs() < 1e-6,
        "base {base0} -> {base_end}"
    );
    let rise = box_end - box0;
    assert!(
        (rise - commanded).abs() < 0.01,
        "box rose {rise} m for {commanded}"
    );
    // Not dropped: held up over the whole second after the lift.
    assert!(
        lowest_held - box0 > commanded - 0.01,
        "box down to {lowest_held} after the lift"
    );
    // The fingers hold it: closed onto its sides (contact at 20 mm of travel, the motor
    // target at 30 mm), not through it.
    for (name, travel) in &watch.travel {
        assert!(*travel > 0.015 && *travel < 0.0275, "{name} at {travel} m");
    }
    // Every joint of both kinds within its bound, over every substep (a NaN fails).
    for ((worst, joint), bound, what) in [
        (&watch.kjoint_gap, 0.01, "KJOINT2 anchors apart [m]"),
        (&watch.kjoint_overrun, 0.05, "URDF limit overrun [rad]"),
        (&watch.rapier_gap, 0.01, "rapier anchors apart [m]"),
        (
            &watch.rapier_overrun,
            0.001,
            "finger travel beyond its limits [m]",
        ),
    ] {
        assert!(*worst < bound, "{what}: {worst} ({joint})");
    }
    // The lift's work went into the arm and the box through the KJOINT2 joints: the
    // potential energy they gained, m·g·Δz with the arm's 3.5 kg (upper arm, forearm, hand,
    // fingers) and the box's 0.3 kg, within 2 % (the joints and contacts dissipate a little).
    let mgh = 9.81 * (3.5 * (base_end - base0) + 0.3 * rise);
    assert!(
        (stats.motion_work - mgh).abs() < 0.02 * mgh,
        "work of the lift {} J for m·g·h = {mgh} J",
        stats.motion_work
    );
}
