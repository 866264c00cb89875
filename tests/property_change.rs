//! A property changed through `KjointSet::get_mut` while the set runs acts from the next
//! substep on: what the stages found once of the old property (whether it has stops, whether
//! its free DOFs are plain springs) is found again.

mod common;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, DofLaw, JointType, KjointProperty, StopContact};

/// A 1 kg slider at 2 m/s along x with no stop; at 0.1 s (x = 0.2 m) it is given stops at
/// 0 and 0.3 m: it stops at 0.3 m (within 5 mm over the next second) where it ran on to
/// 2.2 m with the old property's answers (measured by keeping them) (a free DOF without stops takes the law's short
/// path, which has no stop).
#[test]
fn stops_given_through_get_mut_hold_from_the_next_substep() {
    let (mut w, ground) = common::world(Vector::ZERO);
    let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
    let mut set = common::joints(4);
    let plain = |law: DofLaw| {
        KjointProperty::new(JointType::Translational)
            .with_kn(1e6)
            .with_dof(Dof::Dx, law)
    };
    let j = common::add(&mut set, &w, plain(DofLaw::spring(0.0)), ground, b, |bl| {
        bl.world_frame1(Rotation::IDENTITY)
    });
    w.bodies[b].set_linvel(Vector::new(2.0, 0.0, 0.0), true);
    set.prepare(&mut w);
    for _ in 0..6 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    let x0 = w.bodies[b].translation().x;
    assert!((x0 - 0.2).abs() < 1e-3, "free slider at {x0} m after 0.1 s");
    set.get_mut(j)
        .unwrap()
        .set_property(plain(DofLaw::spring(0.0).with_stops(0.0, 0.3)))
        .unwrap();
    let (mut furthest, mut hit) = (0.0f64, false);
    for _ in 0..60 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        furthest = furthest.max(w.bodies[b].translation().x as f64);
        hit |= set.get(j).unwrap().state().unwrap().status[0].stop == StopContact::Max;
    }
    println!("furthest {furthest} m");
    assert!(hit, "the new stop never acted");
    assert!(
        furthest < 0.305,
        "the slider passed its new stop: {furthest} m"
    );
}
