//! A quadruped on the ground under random joint torques, as a reinforcement-learning loop
//! drives it: rapier's contacts act after the joints are solved in each substep, so a foot
//! driven into the ground opens its joints before they answer. Such an opening is warned
//! of, naming the contacts, and the run goes on (it stopped every episode at the default 4
//! substeps under the A1's full effort, where rapier's own joints flex as far; now one in a
//! few, an opening where no contact pushed that substep, naming more substeps); more
//! substeps, as the warning and the error say, hold the joints. Standing, a body the contacts hold against
//! gravity is taken as heavier in the solve, which keeps the knees within 1.5 mm at 4
//! substeps. The A1 of example-robot-data (`KJOINT_ROBOT_URDFS`, set by `.ci/run`).

mod common;

use rapier_kjoint::dynamics::KjointEventKind;
use rapier_kjoint::io::urdf::UrdfOptions;
use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{KjointMotor, SubstepSettings};

/// xorshift: uniform in [−1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// The A1's URDF of example-robot-data under `KJOINT_ROBOT_URDFS`, or `None` with a notice
/// where it is not set.
fn a1_urdf() -> Option<std::path::PathBuf> {
    let Some(dir) = std::env::var_os("KJOINT_ROBOT_URDFS") else {
        println!("NOTICE: KJOINT_ROBOT_URDFS is not set: skipping the A1 (.ci/run sets it)");
        return None;
    };
    let a1 = "example-robot-data/robots/a1_description/urdf/a1.urdf";
    Some(std::path::Path::new(&dir).join(a1))
}

/// The A1 (floating base) on a ground box at 60 Hz × `substeps`: the world, the set and
/// its 12 hinges by name.
fn a1_on_ground(
    a1: &std::path::Path,
    substeps: usize,
) -> (PhysicsWorld, KjointSet, Vec<KjointHandle>) {
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..Default::default()
    };
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let options = UrdfOptions {
        fixed_base: false,
        ..Default::default()
    };
    let robot = common::robot::insert_urdf_file(a1, &mut world, &mut joints, &options).unwrap();
    let bottom = (world.colliders.iter())
        .map(|(_, c)| c.compute_aabb().mins.z)
        .fold(Real::MAX, Real::min);
    let ground = world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(
        0.0,
        0.0,
        bottom - 0.5,
    )));
    let groups = InteractionGroups::new(Group::GROUP_2, Group::ALL, InteractionTestMode::And);
    let collider = ColliderBuilder::cuboid(50.0, 50.0, 0.5).collision_groups(groups);
    (world.colliders).insert_with_parent(collider.build(), ground, &mut world.bodies);
    let mut hinges: Vec<KjointHandle> = (robot.joints.values())
        .copied()
        .filter(|h| joints[*h].property().joint_type == JointType::Revolute)
        .collect();
    hinges.sort_by_key(|h| joints[*h].name.clone());
    assert_eq!(hinges.len(), 12);
    (world, joints, hinges)
}

/// One episode of 3 s at 60 Hz × `substeps`: the A1 on a ground box ([`a1_on_ground`]) under
/// uniform random torques of ±`amp` N·m on every hinge, new each frame. Returns the error
/// that stopped it (if any), its `NoLongerHolds` warnings and the largest blocked rotation
/// of any joint over the frames \[rad\].
fn episode(
    a1: &std::path::Path,
    substeps: usize,
    amp: f64,
    seed: u64,
) -> (Option<SimError>, Vec<KjointEvent>, f64) {
    let (mut world, mut joints, hinges) = a1_on_ground(a1, substeps);
    let mut rng = Rng(seed.wrapping_mul(0x9E3779B97F4A7C15) | 1);
    let (mut warnings, mut worst) = (Vec::new(), 0.0f64);
    for _ in 0..180 {
        for &h in &hinges {
            let torque = KjointMotor::force(amp * rng.next());
            joints.set_motor(h, Dof::Rx, Some(torque)).unwrap();
        }
        let result = joints.step(&mut world, 1.0 / 60.0);
        warnings.extend(
            (joints.drain_events().into_iter())
                .filter(|e| matches!(e.kind, KjointEventKind::NoLongerHolds { .. })),
        );
        for (_, j) in joints.iter() {
            worst = worst.max(j.blocked_rotation().unwrap_or(0.0));
        }
        if let Err(e) = result {
            return (Some(e), warnings, worst);
        }
    }
    (None, warnings, worst)
}

/// At 4 substeps under random torques of ±33.5 N·m (the A1's effort limit) every episode
/// stopped with a calf 0.5–0.8 rad about a blocked axis, opened by its foot's contact
/// (rapier's impulse joints reach 0.72 rad in the same episodes: a reinforcement-learning
/// researcher's trial, 2026-12-05). A joint opened by rapier's contacts is now warned of
/// once, naming the contacts and more substeps, and the run goes on unless the opening
/// grows fourfold; one that opens where no contact pushed its bodies stops the run, naming
/// more substeps. Measured with the feet where the URDF puts them (their fixed joints
/// fused, 2026-12-06: before, the fused feet's spheres sat at the knees and the calves
/// stood on their boxes' ends): at 4 substeps the calves open 0.9–1.4 rad in the 4
/// episodes, 4–6 joints warned of in each, and one episode stops (a calf at 0.57 rad, no
/// contact pushing it then; in f64 the one that stops is another); at 16 substeps
/// 0.13–0.40 rad, one warning; at 32 substeps every joint stays within 0.06 rad (0.07–0.15
/// rad in f64, whose episodes take other paths), with no warning.
#[test]
fn a_quadruped_whose_feet_open_its_joints_is_warned_of_or_stopped_naming_more_substeps() {
    let Some(a1) = a1_urdf() else {
        return;
    };
    let mut opened = 0;
    for seed in 0..4 {
        let (error, warnings, worst) = episode(&a1, 4, 33.5, seed);
        println!(
            "seed {seed}, 4 substeps: worst blocked rotation {worst:.3} rad, {} warnings, \
             error {error:?}",
            warnings.len()
        );
        // a run that stops says why and what to do
        if let Some(e) = &error {
            let text = e.to_string();
            assert!(
                text.contains("no longer holds") && text.contains("more substeps"),
                "seed {seed}: {text}"
            );
        }
        assert!(worst < 2.0, "seed {seed}: {worst} rad");
        for w in &warnings {
            let text = w.to_string();
            assert!(
                text.contains("was pushed by rapier's contacts") && text.contains("more substeps"),
                "{text}"
            );
        }
        // once per joint: a second warning would mean fourfold, where the run stops
        let mut sources: Vec<String> = warnings.iter().map(|w| w.source.to_string()).collect();
        sources.sort();
        sources.dedup();
        assert_eq!(sources.len(), warnings.len(), "{warnings:?}");
        opened += usize::from(!warnings.is_empty());
        let (error, warnings, worst) = episode(&a1, 32, 33.5, seed);
        println!("seed {seed}, 32 substeps: worst blocked rotation {worst:.3} rad");
        assert!(
            error.is_none() && warnings.is_empty(),
            "{error:?} {warnings:?}"
        );
        assert!(worst < 0.25, "seed {seed}: {worst} rad at 32 substeps");
    }
    // (the episodes do open the joints beyond the bounds at 4 substeps, and the runs that
    // go on are most of them)
    assert!(opened >= 2, "{opened} of 4 episodes opened a joint");
}

/// The A1 standing on the ground under PD control of its 12 hinges (`kp` 100 N·m/rad, `kd`
/// 1 N·m·s/rad, about the pose it was loaded in) at the default 4 substeps: a calf carries
/// about 30 N from its foot's contact, which acts after the joint solve and moved the calf
/// by `F·h²/m` (0.226 kg: 2.3 mm) a substep before the knee answered: the knees stood 3.7 mm
/// open (README "Known limits"). The solve now takes a body the contact held against gravity
/// in the last substep as 4 times heavier along that axis (`held_axes` in
/// src/dynamics/substep.rs): over the 5th second no joint is more than 1.5 mm open (1.01 mm
/// at the end), the robot standing (its base within 2 cm of the height it reached at 1 s).
#[test]
fn a_standing_quadruped_s_knees_stay_within_a_millimetre_and_a_half() {
    let Some(a1) = a1_urdf() else {
        return;
    };
    let (mut world, mut joints, hinges) = a1_on_ground(&a1, 4);
    for &h in &hinges {
        let pd = KjointMotor::position(0.0, 100.0, 1.0);
        joints.set_motor(h, Dof::Rx, Some(pd)).unwrap();
    }
    let top = |w: &PhysicsWorld| {
        (w.bodies.iter())
            .map(|(_, b)| b.translation().z as f64)
            .fold(f64::MIN, f64::max)
    };
    let (mut worst, mut worst_joint, mut standing) = (0.0f64, String::new(), 0.0);
    for frame in 0..300 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
        if frame == 59 {
            standing = top(&world);
        }
        if frame >= 240 {
            for (_, j) in joints.iter() {
                let gap = j.blocked_gap().unwrap_or(0.0);
                if gap > worst {
                    (worst, worst_joint) = (gap, j.name.clone());
                }
            }
        }
    }
    let end = top(&world);
    println!("worst gap over the 5th second {worst} m ({worst_joint}); top {standing} -> {end} m");
    assert!(worst < 1.5e-3, "{worst} m ({worst_joint})");
    assert!((end - standing).abs() < 0.02, "{standing} -> {end} m");
}
