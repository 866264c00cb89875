//! Joint limits as a rapier user writes them: stops of the automatic stiffness stop a door
//! and a drawer as rapier's limits do (no rebound), `DofLaw::with_limits` takes a limit at
//! 0 as a limit, and `KjointBuilder::world_axis` gives a slide its axis.

use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, JointType, KjointBuilder, KjointHandle, KjointProperty, KjointSet, SimError,
    StopContact, SubstepSettings,
};

const DT: f64 = 1.0 / 60.0;

/// A 20 kg door (0.8 m × 2 m, hinged at its edge on the world's y axis through the origin)
/// swinging at `w0` rad/s, and a 5 kg drawer sliding along x at 1 m/s from x = 2 m, each on
/// the law `door` / `drawer`; no gravity, no collisions, no sleeping.
fn door_and_drawer(
    substeps: usize,
    w0: f64,
    door: DofLaw,
    drawer: DofLaw,
) -> (PhysicsWorld, KjointSet, KjointHandle, KjointHandle) {
    let mut world = PhysicsWorld::default();
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let (door_body, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.4, 0.0, 0.0))
            .angvel(Vector::new(0.0, w0 as Real, 0.0))
            .linvel(Vector::new(0.0, 0.0, -0.4 * w0 as Real))
            .can_sleep(false),
        ColliderBuilder::cuboid(0.4, 1.0, 0.02)
            .mass(20.0)
            .collision_groups(InteractionGroups::none()),
    );
    let (drawer_body, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(2.0, 0.5, 0.0))
            .linvel(Vector::new(1.0, 0.0, 0.0))
            .can_sleep(false),
        ColliderBuilder::cuboid(0.2, 0.1, 0.2)
            .mass(5.0)
            .collision_groups(InteractionGroups::none()),
    );
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let hinge = joints
        .insert(
            KjointBuilder::new(KjointProperty::new(JointType::Revolute).with_dof(Dof::Rx, door))
                .world_axis(Vector::Y)
                .local_anchor2(Vector::new(-0.4, 0.0, 0.0)),
            ground,
            door_body,
            &world.bodies,
        )
        .unwrap();
    // the slide's anchors apart (anchor 1 at the world's origin): its axis is given
    let slide = joints
        .insert(
            KjointBuilder::new(
                KjointProperty::new(JointType::Translational).with_dof(Dof::Dx, drawer),
            )
            .world_axis(Vector::new(3.0, 0.0, 0.0)),
            ground,
            drawer_body,
            &world.bodies,
        )
        .unwrap();
    (world, joints, hinge, slide)
}

/// (largest value, value and rate `after` s past the first reach of `reach`, value at the
/// end) of `dof` of joint `h` over `frames` frames.
fn history(
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    h: KjointHandle,
    dof: Dof,
    reach: f64,
    frames: usize,
) -> (f64, f64, f64) {
    let (mut max, mut hit, mut rate_after) = (f64::MIN, None, f64::NAN);
    for _ in 0..frames {
        joints.step(world, DT).unwrap();
        let s = joints.get(h).unwrap().state().unwrap();
        max = max.max(s.q[dof]);
        if hit.is_none() && s.q[dof] >= reach {
            hit = Some(s.time);
        }
        if hit.is_some_and(|t| (s.time - t - 0.25).abs() < 0.5 * DT) {
            rate_after = s.rate[dof];
        }
    }
    let end = joints.get(h).unwrap().state().unwrap().q[dof];
    (max, rate_after, end)
}

/// rapier's limits stop a body dead (no restitution); the stops of the automatic stiffness
/// did not: the door swung into its 1 rad stop at 1 rad/s left it at 0.05 rad/s at 4
/// substeps and drifted back to 0.90 rad by 3 s; the drawer at 0.08 m/s (4 substeps) and
/// 0.94 m/s, nearly elastic, at 16. Now the update ends the substep on the stop and holds
/// it there: both stay on their stops.
#[test]
fn a_door_and_a_drawer_stop_on_their_limits_without_rebound() {
    for substeps in [4, 16] {
        let (mut world, mut joints, hinge, slide) = door_and_drawer(
            substeps,
            1.0,
            DofLaw::default().with_limits(0.0, 1.0),
            DofLaw::default().with_limits(-0.05, 0.3),
        );
        let (dmax, drate, dend) = history(&mut world, &mut joints, slide, Dof::Dx, 0.29, 180);
        assert!(dmax < 0.3 + 1e-3, "{substeps} substeps: drawer to {dmax} m");
        assert!(
            drate.abs() < 0.01,
            "{substeps}: drawer left its stop at {drate} m/s of 1"
        );
        // (at 16 substeps the blocked DOFs give back a little: 0.298 m at 3 s)
        assert!(
            (dend - 0.3).abs() < 0.02,
            "{substeps}: drawer at {dend} m at 3 s"
        );

        let q = joints.get(hinge).unwrap().state().unwrap().q[Dof::Rx];
        // 3 s at 1 rad/s: the door reached its stop at 1 s and stayed there, within what its
        // hinge's blocked DOFs give back (f32: 1.000 rad at 4 substeps, 0.986 at 16, where
        // the noise bound's floor κ = 4 holds them; f64, where the bound leaves κ = 16:
        // 0.988; the law's stop spring alone: 0.90). Before the floor the blocked DOFs were
        // springs at 16 substeps and the door left its stop at 0.36 rad/s.
        assert!((q - 1.0).abs() < 0.02, "{substeps}: door at {q} rad at 3 s");
    }
}

/// `with_stops(0.0, 1.0)` is the Radioss convention: no stop where the door closes; the
/// same numbers in `with_limits` are rapier's `limits([0.0, 1.0])`, a stop at the
/// insertion pose. A door pushed shut at 1 rad/s swung to −1 rad with the first (a user
/// trial) and stops at 0 with the second.
#[test]
fn a_limit_at_zero_is_a_limit_and_a_stop_at_zero_is_none() {
    for (law, closes) in [
        (DofLaw::default().with_limits(0.0, 1.0), true),
        (DofLaw::default().with_stops(0.0, 1.0), false),
    ] {
        let (mut world, mut joints, hinge, _) = door_and_drawer(4, -1.0, law, DofLaw::default());
        for _ in 0..60 {
            joints.step(&mut world, DT).unwrap();
        }
        let q = joints.get(hinge).unwrap().state().unwrap().q[Dof::Rx];
        if closes {
            // (the hinge's blocked DOFs give back a little of the impact: 0.006 rad by 1 s)
            assert!(
                q > -1e-3 && q < 0.02,
                "the door passed its closed limit: {q} rad"
            );
        } else {
            assert!(
                (q + 1.0).abs() < 0.02,
                "no closing stop: the door at {q} rad"
            );
        }
    }
}

/// `world_axis` is the slide's axis whatever the anchors: the drawer's anchors are 2 m
/// apart along x and 0.5 m along y (anchor 1 at the origin), which without it made the
/// slide run from one anchor to the other (a drawer pushed along x moved at (0.94, 0.235,
/// 0) m/s and ended 0.12 m higher). A zero axis is refused at insertion.
#[test]
fn world_axis_gives_the_slide_its_axis_and_a_zero_axis_is_refused() {
    let (mut world, mut joints, _, slide) = door_and_drawer(
        4,
        0.0,
        DofLaw::default(),
        DofLaw::default().with_limits(-0.05, 0.3),
    );
    let h = joints.get(slide).unwrap().body2();
    for _ in 0..30 {
        joints.step(&mut world, DT).unwrap();
    }
    let p = world.bodies[h].translation();
    // 0.5 s at 1 m/s along x, then on the stop at 0.3 m
    assert!((p.x as f64 - 2.3).abs() < 1e-3, "{p:?}");
    assert!((p.y as f64 - 0.5).abs() < 1e-4, "{p:?}");
    assert!((p.z as f64).abs() < 1e-4, "{p:?}");

    let body = world.insert_body(RigidBodyBuilder::dynamic());
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let e = joints
        .insert(
            KjointBuilder::new(KjointProperty::new(JointType::Translational))
                .world_axis(Vector::ZERO),
            ground,
            body,
            &world.bodies,
        )
        .unwrap_err();
    assert!(
        matches!(&e, SimError::InvalidArgument { field, value, .. }
            if field.contains("world_axis") && value == "[0, 0, 0]"),
        "{e}"
    );
}

/// The substep a rigid limit stops a DOF in reads the limit in contact, though the update
/// ends it on the limit, not beyond it: a game watching the status for a door's slam read
/// no contact at any substep (a user trial, 2026-12-04).
#[test]
fn a_rigid_limit_reads_in_contact_in_the_substep_it_stops_the_dof() {
    let (mut world, mut joints, _, slide) = door_and_drawer(
        4,
        0.0,
        DofLaw::default(),
        DofLaw::default().with_limits(-0.05, 0.3),
    );
    // (q, the limit's status) at every substep
    let mut seen = Vec::new();
    for _ in 0..30 {
        joints
            .step_with(&mut world, DT, |phase, _, set| {
                if phase == rapier_kjoint::SubstepPhase::After {
                    let s = set.get(slide).unwrap().state().unwrap();
                    seen.push((s.q[Dof::Dx], s.status[Dof::Dx].stop));
                }
                Ok::<(), SimError>(())
            })
            .unwrap();
    }
    let worst = seen.iter().fold(f64::MIN, |m, (q, _)| m.max(*q));
    assert!(worst <= 0.3 + 1e-6, "beyond its limit: {worst} m");
    let first = seen
        .iter()
        .position(|(_, st)| *st == StopContact::Max)
        .unwrap_or_else(|| panic!("never in contact: {seen:?}"));
    // at 1 m/s from 0 it reaches 0.3 m at 0.3 s, the 72nd substep
    assert!(
        (68..=73).contains(&first),
        "in contact from substep {first}"
    );
    assert!(seen[first].0 <= 0.3, "{:?}", seen[first]);
}

/// A 1 kg rod of 1 m on a ball joint at its end (no gravity), its swing held within a cone
/// of 0.5 rad by coupled stops of the automatic stiffness (`Icomb = 1` on ry and rz, a
/// ragdoll's or an MJCF ball joint's cone limit), swung into it about world z at `w0`.
/// Returns the largest swing `√(ry² + rz²)` and the rod's spin about z a tenth of a second
/// after it reached 0.48 rad (negative: a rebound).
fn rod_into_a_cone(substeps: usize, w0: f64) -> (f64, f64) {
    let mut world = PhysicsWorld {
        gravity: Vector::ZERO,
        ..Default::default()
    };
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let (rod, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.5, 0.0, 0.0))
            .linvel(Vector::new(0.0, 0.5 * w0 as Real, 0.0))
            .angvel(Vector::new(0.0, 0.0, w0 as Real))
            .can_sleep(false),
        ColliderBuilder::cuboid(0.5, 0.02, 0.02).mass(1.0),
    );
    let cone = DofLaw::default().with_stops(-0.5, 0.5).with_coupled_stops();
    let mut set = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let ball = set
        .insert(
            KjointBuilder::new(
                KjointProperty::new(JointType::Spherical)
                    .with_dof(Dof::Ry, cone.clone())
                    .with_dof(Dof::Rz, cone),
            )
            .local_anchor2(Vector::new(-0.5, 0.0, 0.0)),
            ground,
            rod,
            &world.bodies,
        )
        .unwrap();
    let (mut peak, mut reached, mut spin) = (0.0_f64, None, f64::NAN);
    for n in 0..60_usize {
        set.step(&mut world, DT).unwrap();
        let q = set.get(ball).unwrap().state().unwrap().q;
        let swing = q[Dof::Ry].hypot(q[Dof::Rz]);
        peak = peak.max(swing);
        if reached.is_none() && swing > 0.48 {
            reached = Some(n);
        }
        if reached == Some(n.saturating_sub(6)) {
            spin = world.bodies[rod].angvel().z as f64;
        }
    }
    (peak, spin)
}

/// Coupled stops of the automatic stiffness stop the rod on the cone as a hinge's stops
/// stop a door: no rebound. Before the substep predicted them (`law::stop_prediction`,
/// "Coupled stops") the rod came back off the cone at 0.48 rad/s of 2 and 2.4 of 10 at 4
/// substeps, 0.89 of 2 at 16; now as with a hinge's stops: 0.012 and 0.063 at 4, 0.11 at 16.
#[test]
fn a_cone_limit_stops_a_swinging_rod_without_rebound() {
    for substeps in [4, 16] {
        for w0 in [2.0, 10.0] {
            let (peak, spin) = rod_into_a_cone(substeps, w0);
            assert!(
                peak < 0.5 + 1e-3,
                "{substeps} substeps, {w0} rad/s: swung to {peak}"
            );
            // (at 16 substeps the f32 noise bound leaves the blocked DOFs soft enough to
            // give back part of the impact, as for the door above: 0.11 rad/s of 2)
            let bound = if substeps == 4 { 0.02 } else { 0.1 };
            assert!(
                spin.abs() < bound * w0,
                "{substeps} substeps, {w0} rad/s: {spin} rad/s after the cone"
            );
        }
    }
}

/// A drawer on a return spring whose weight acts across its slide (the drawer of
/// `examples/mechanism.rs`: 5 kg, 200 N/m, limits −0.05 and 0.25 m, launched at 2.5 m/s):
/// the rigid limit stops it at 0.25 m, and the spring then pulls it straight off it. From
/// rest at 0.25 m it swings as `q = 0.25·cos(ωt)`, `ω = √(K/m)`, and reaches the other
/// limit where `cos(ωt) = −0.2`: 0.280 s later. It stayed on its limit for good, at rest
/// under the spring's 50 N (a mechanism designer's trial, 2026-12-05): the limit was held
/// while the force the joint transmitted pushed the drawer off it, and the spring's pull
/// was taken for that push; now the hold reads the stop's share of it.
#[test]
fn a_return_spring_pulls_a_drawer_off_its_limit() {
    let (k, m, v0, lo, hi) = (200.0, 5.0, 2.5, -0.05, 0.25);
    let omega = (k / m).sqrt();
    let expected = (lo / hi).acos() / omega;
    for substeps in [4, 16] {
        let mut world = PhysicsWorld {
            gravity: Vector::new(0.0, -9.81, 0.0),
            ..Default::default()
        };
        let ground = world.insert_body(RigidBodyBuilder::fixed());
        let (drawer, _) = world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(2.0, 0.5, 0.0))
                .linvel(Vector::new(v0 as Real, 0.0, 0.0)),
            ColliderBuilder::cuboid(0.2, 0.1, 0.2).mass(m as Real),
        );
        let mut joints = KjointSet::with_settings(SubstepSettings {
            substeps,
            ..Default::default()
        });
        let slide = KjointProperty::new(JointType::Translational)
            .with_dof(Dof::Dx, DofLaw::spring(k).with_limits(lo, hi));
        let h = joints
            .insert(
                KjointBuilder::new(slide).local_anchor1(Vector::new(2.0, 0.5, 0.0)),
                ground,
                drawer,
                &world.bodies,
            )
            .unwrap();
        let (mut at_hi, mut at_lo, mut peak) = (None, None, f64::MIN);
        for _ in 0..90 {
            joints.step(&mut world, DT).unwrap();
            let s = joints.get(h).unwrap().state().unwrap();
            peak = peak.max(s.q[Dof::Dx]);
            if at_hi.is_none() && s.q[Dof::Dx] >= hi - 1e-3 {
                at_hi = Some(s.time);
            }
            if at_hi.is_some() && at_lo.is_none() && s.q[Dof::Dx] <= lo + 1e-3 {
                at_lo = Some(s.time);
            }
        }
        let at_hi = at_hi.expect("the drawer reaches its limit");
        let at_lo = at_lo.unwrap_or_else(|| {
            let q = joints.get(h).unwrap().state().unwrap().q[Dof::Dx];
            panic!("{substeps} substeps: the drawer stayed at {q} m after its limit at {at_hi} s")
        });
        assert!(peak < hi + 1e-3, "{substeps} substeps: to {peak} m");
        assert!(
            (at_lo - at_hi - expected).abs() < 2.0 * DT,
            "{substeps} substeps: from limit to limit in {} s, {expected} s by hand",
            at_lo - at_hi
        );
    }
}
