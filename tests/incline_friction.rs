//! A prismatic KJOINT2 on a 30° incline with friction: it sticks while the slope component of
//! gravity (m·g·sin 30° = 4.905 N) is below the friction force, and slides with acceleration
//! `g·sin 30° − FF/m` above it; into a stop it comes to rest at its penetration.

mod common;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, DofLaw, FrictionStatus, JointType, KjointProperty};

fn run(ff: f64) -> (Vec<f64>, Vec<f64>, FrictionStatus) {
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
    let mut set = common::joints(4);
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e6)
        .with_dof(Dof::Dx, DofLaw::default().with_friction(1e4, ff));
    // joint x axis down the slope
    let slope = Rotation::from_rotation_z(Real::to_radians(-30.0));
    let j = common::add(&mut set, &w, prop, ground, b, |bl| bl.world_frame1(slope));
    let (mut q, mut v) = (Vec::new(), Vec::new());
    for _ in 0..120 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let s = set.get(j).unwrap().state().unwrap();
        q.push(s.q[0]);
        v.push(s.rate[0]);
    }
    let st = set.get(j).unwrap().state().unwrap().status[0].friction;
    (q, v, st)
}

#[test]
fn sticks_below_the_friction_force() {
    let (q, v, st) = run(6.0);
    // The load is applied suddenly: the friction spring (Kf = 1e4 N/m) overshoots its static
    // deflection m·g·sin30°/Kf = 0.49 mm and may slip briefly, then it holds: it only rings
    // elastically about a fixed position (no creep between the two halves of the 2nd second).
    let max = q.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    assert!(max < 2e-3, "moved {max} m");
    let mean = |r: std::ops::Range<usize>| q[r.clone()].iter().sum::<f64>() / r.len() as f64;
    let creep = (mean(90..120) - mean(60..90)).abs();
    assert!(creep < 1e-6, "crept {creep} m while sticking");
    assert!(v[119].abs() < 1e-3, "still moving at {} m/s", v[119]);
    assert_eq!(st, FrictionStatus::Stick);
}

#[test]
fn slides_with_the_expected_acceleration_above_it() {
    let (_, v, st) = run(2.0);
    // rate sampled once per frame; acceleration from 0.5 s to 1.5 s
    let a = (v[89] - v[29]) / 1.0;
    let expect = 9.81 * 0.5 - 2.0;
    assert!(
        (a - expect).abs() / expect < 0.01,
        "a = {a}, expected {expect}"
    );
    assert_eq!(st, FrictionStatus::Slip);
}

/// Sliding (FF = 2 N) 0.1 m down the incline into a stop: the friction spring, its cap lifted
/// beyond the stop, is the stop (docs/kjoint2.md §4.2, §4.4), so the slider comes to rest
/// at `SD + (m·g·sin 30° − FF)/Kf` = 0.1 + 2.905/1e4 m whatever the substep. The stop is
/// reached within a substep (at 0.76 m/s a substep of 1/240 s moves 3.2 mm, ten times the
/// penetration): loaded with the whole substep's motion, the spring moved the stop by the
/// part before it, and the slider rested short of its penetration by an amount that
/// changed with the substep count (0.10018 m at 1 substep: 38 % short).
#[test]
fn slides_into_its_stop_and_rests_at_its_penetration_whatever_the_substep() {
    let expected = 0.1 + (9.81 * 0.5 - 2.0) / 1e4;
    for substeps in [1, 4, 16] {
        let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
        let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
        let mut set = common::joints(substeps);
        let law = DofLaw::default()
            .with_friction(1e4, 2.0)
            .with_stops(-1.0, 0.1);
        let prop = KjointProperty::new(JointType::Translational)
            .with_kn(1e6)
            .with_dof(Dof::Dx, law);
        let slope = Rotation::from_rotation_z(Real::to_radians(-30.0));
        let j = common::add(&mut set, &w, prop, ground, b, |bl| bl.world_frame1(slope));
        for _ in 0..240 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        let s = set.get(j).unwrap().state().unwrap();
        // 1 % of the penetration (2.9e-4 m); f32 poses round at 1e-8 m here
        assert!(
            (s.q[0] - expected).abs() < 3e-6,
            "{substeps} substeps: rests at {} m, expected {expected} m",
            s.q[0]
        );
        assert!(s.rate[0].abs() < 1e-4, "still moving at {} m/s", s.rate[0]);
    }
}
