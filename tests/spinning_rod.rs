//! Anchors turning about a joint: the curvature of their paths over a substep, which the
//! solve predicts (`prepare::curvature_rate`). Without it a stiff joint left the anchors of a
//! spinning rod 5/3 of a sagitta apart (the sagitta `r·(ω·h)²/2` of the anchor's arc over a
//! substep `h`, the stiff limit's fixed point): the rammed rod of `tests/health.rs`,
//! spinning at 56 rad/s, 2.1 cm.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{JointType, KjointBuilder, KjointProperty, KjointSet, SubstepSettings};

/// What a user sees of a spinning joint over the second second of a run: the largest
/// distance between its anchors \[m\] and the bodies' kinetic energy at the end over at the
/// start.
struct Spun {
    gap: f64,
    energy: f64,
}

/// Steps `w` two seconds at 60 Hz with `substeps`, measuring `gap` over the second one.
fn spin(
    mut w: PhysicsWorld,
    set: &mut KjointSet,
    substeps: usize,
    bodies: &[RigidBodyHandle],
    gap: impl Fn(&PhysicsWorld) -> f64,
) -> Spun {
    set.set_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let energy = |w: &PhysicsWorld| -> f64 {
        (bodies.iter())
            .map(|b| w.bodies[*b].kinetic_energy() as f64)
            .sum()
    };
    let start = energy(&w);
    let mut largest = 0.0f64;
    for frame in 0..120 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        if frame >= 60 {
            largest = largest.max(gap(&w));
        }
    }
    Spun {
        gap: largest,
        energy: energy(&w) / start,
    }
}

/// A 1 kg rod of 1 m without gravity, pinned at its end to the world by a joint of type
/// `joint_type` (axis z) of blocked stiffness `kn` (`None`: automatic) and spinning about the
/// pin at `omega`; with the joint's resolved `Kn` \[N/m\].
fn pinned_rod(joint_type: JointType, kn: Option<f64>, omega: f64, substeps: usize) -> (Spun, f64) {
    let (mut w, ground) = common::world(Vector::ZERO);
    let (rod, _) = w.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.5, 0.0, 0.0))
            .linvel(Vector::new(0.0, 0.5 * omega as Real, 0.0))
            .angvel(AngVector::new(0.0, 0.0, omega as Real))
            .can_sleep(false),
        ColliderBuilder::cuboid(0.5, 0.02, 0.02).density(625.0),
    );
    let mut set = KjointSet::new();
    let property = KjointProperty::new(joint_type);
    let pin = set
        .insert(
            common::rod_end_hinge_about_z(match kn {
                Some(kn) => property.with_kn(kn),
                None => property,
            }),
            ground,
            rod,
            &w.bodies,
        )
        .unwrap();
    let mut resolved = 0.0;
    let spun = spin(w, &mut set, substeps, &[rod], |w| {
        (w.bodies[rod].position() * Vector::new(-0.5, 0.0, 0.0)).length() as f64
    });
    if let Some(k) = set.get(pin).and_then(|j| j.blocked_stiffness()) {
        resolved = k.translational;
    }
    (spun, resolved)
}

/// The sagitta \[m\] of an anchor at `r` from the axis turning at `omega` over a substep.
fn sagitta(r: f64, omega: f64, substeps: usize) -> f64 {
    let h = 1.0 / 60.0 / substeps as f64;
    0.5 * r * (omega * h).powi(2)
}

/// A rod spinning about its pin on a stiff joint (`Kn` = 1e12, the stiff limit) holds it
/// within half a sagitta (a third, as `prepare::curvature_rate` derives; 1.44–1.67
/// sagittas before the curvature was predicted: 2.9 mm at 20 rad/s and 4 substeps, where
/// the sagitta is 1.7 mm), every joint type that blocks the pin's radial translations alike
/// (the cylindrical joint slides along the spin axis), and loses less energy to the update
/// than it did (1.0 % in 2 s at 20 rad/s and 4 substeps, now 0.33 %; 16 % at 56 rad/s, now
/// 14 %, where the rod turns 13° a substep).
#[test]
fn a_rod_spinning_about_a_stiff_pin_stays_on_it() {
    for jt in [
        JointType::Revolute,
        JointType::Spherical,
        JointType::Cylindrical,
    ] {
        for (omega, substeps, lost) in [
            (5.0, 4, 1e-4),
            (20.0, 4, 6e-3),
            (20.0, 16, 5e-4),
            (56.0, 4, 0.17),
        ] {
            let (spun, _) = pinned_rod(jt, Some(1e12), omega, substeps);
            let s = sagitta(0.5, omega, substeps);
            println!(
                "{jt:?} at {omega} rad/s, {substeps} substeps: anchors {:.3e} m apart \
                 ({:.2} sagittas), energy ×{:.5}",
                spun.gap,
                spun.gap / s,
                spun.energy
            );
            assert!(
                spun.gap < 0.5 * s,
                "{jt:?} {omega} {substeps}: {}",
                spun.gap
            );
            assert!(
                spun.energy <= 1.0,
                "{jt:?} {omega} {substeps}: {}",
                spun.energy
            );
            assert!(
                spun.energy > 1.0 - lost,
                "{jt:?} {omega} {substeps}: {}",
                spun.energy
            );
        }
    }
}

/// On the automatic stiffness (the default) the pin is a spring: the rod's end stands off it
/// by the stretch the centripetal load gives it, `F/Kn` with `F = m·ω²·r` (200 N at
/// 20 rad/s), and by at most 0.4 of a sagitta more (the stiff limit's third); before the
/// curvature was predicted, 1.4–1.7 sagittas more (3.1 mm at 20 rad/s and 4 substeps, where
/// `F/Kn` is 0.22 mm and the sagitta 1.7 mm).
#[test]
fn a_rod_spinning_about_a_pin_of_automatic_stiffness_stretches_it_by_its_load() {
    for (omega, substeps) in [(5.0, 4), (20.0, 4), (20.0, 16), (56.0, 4)] {
        let (spun, kn) = pinned_rod(JointType::Revolute, None, omega, substeps);
        let stretch = 1.0 * omega * omega * 0.5 / kn;
        let s = sagitta(0.5, omega, substeps);
        println!(
            "at {omega} rad/s, {substeps} substeps: anchors {:.3e} m apart, F/Kn {stretch:.3e} \
             (Kn {kn:.3e} N/m), {:.2} sagittas beyond, energy ×{:.5}",
            spun.gap,
            (spun.gap - stretch) / s,
            spun.energy
        );
        assert!(spun.gap > stretch, "{omega} {substeps}: {}", spun.gap);
        assert!(
            spun.gap < stretch + 0.4 * s,
            "{omega} {substeps}: {}",
            spun.gap
        );
    }
}

/// Two 1 kg rods of 1 m joined end to end by a spherical joint, without gravity, spinning
/// about their joint at 20 rad/s: both anchors turn, in opposite directions from their
/// bodies' centres; they stay within half the sagitta of their relative motion (the two
/// arcs' sum, 3.5 mm at 4 substeps; 6.0 mm apart before).
#[test]
fn two_rods_spinning_about_their_joint_stay_joined() {
    let omega = 20.0;
    let (mut w, _) = common::world(Vector::ZERO);
    let rod = |w: &mut PhysicsWorld, side: Real| {
        w.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.5 * side, 0.0, 0.0))
                .linvel(Vector::new(0.0, 0.5 * side * omega as Real, 0.0))
                .angvel(AngVector::new(0.0, 0.0, omega as Real))
                .can_sleep(false),
            ColliderBuilder::cuboid(0.5, 0.02, 0.02).density(625.0),
        )
        .0
    };
    let (a, b) = (rod(&mut w, -1.0), rod(&mut w, 1.0));
    let mut set = KjointSet::new();
    set.insert(
        KjointBuilder::new(KjointProperty::new(JointType::Spherical))
            .local_anchor1(Vector::new(0.5, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.5, 0.0, 0.0))
            .contacts_enabled(false),
        a,
        b,
        &w.bodies,
    )
    .unwrap();
    let spun = spin(w, &mut set, 4, &[a, b], |w| {
        let pa = w.bodies[a].position() * Vector::new(0.5, 0.0, 0.0);
        let pb = w.bodies[b].position() * Vector::new(-0.5, 0.0, 0.0);
        (pa - pb).length() as f64
    });
    let s = sagitta(1.0, omega, 4);
    println!(
        "anchors {:.3e} m apart ({:.2} sagittas), energy ×{:.5}",
        spun.gap,
        spun.gap / s,
        spun.energy
    );
    assert!(spun.gap < 0.5 * s, "{}", spun.gap);
    assert!(spun.energy <= 1.0 && spun.energy > 0.994, "{}", spun.energy);
}
