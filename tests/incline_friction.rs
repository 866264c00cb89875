//! A prismatic KJOINT2 on a 30° incline with friction: it sticks while the slope component of
//! gravity (m·g·sin 30° = 4.905 N) is below the friction force, and slides with acceleration
//! `g·sin 30° − FF/m` above it.

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
