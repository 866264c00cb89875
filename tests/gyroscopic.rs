//! The joint set integrates the gyroscopic term of the bodies it joins (rapier's own
//! correction acts after the joint impulses and destabilises stiff joints on slender bodies):
//! a body spinning freely about a non-principal axis keeps its world angular momentum.

mod common;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{JointType, KjointProperty};

fn world_momentum(b: &RigidBody) -> Vector {
    let mp = b.mass_properties().local_mprops;
    let r = *b.rotation() * mp.principal_inertia_local_frame;
    let w_local = r.inverse() * b.angvel();
    r * (mp.principal_inertia() * w_local)
}

#[test]
fn free_spinning_body_keeps_its_angular_momentum() {
    let (mut w, ground) = common::world(Vector::ZERO);
    let body = common::point_body(&mut w, 1.0, Vector::new(1.0, 2.0, 3.0), Vector::ZERO);
    w.bodies[body].set_angvel(Vector::new(0.2, 3.0, 0.3), true);
    // a free joint (type 9) with no law: it exerts nothing, but it puts the body in the set
    let mut set = common::joints(4);
    common::add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Free),
        ground,
        body,
        |b| b,
    );
    set.prepare(&mut w);
    let l0 = world_momentum(&w.bodies[body]);
    let mut worst: Real = 0.0;
    for _ in 0..120 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let l = world_momentum(&w.bodies[body]);
        worst = worst.max((l - l0).length() / l0.length());
    }
    let w_end = w.bodies[body].angvel();
    println!(
        "|L0| {}, worst relative change {worst:.3e}, ω end {w_end:?}",
        l0.length()
    );
    // without the gyroscopic term ω stays constant while the inertia turns with the body,
    // and L changes by tens of percent within the first second
    assert!(worst < 0.02, "angular momentum changed by {}", worst);
    // the spin about the intermediate axis is unstable: ω has left its initial direction
    assert!((w_end - Vector::new(0.2, 3.0, 0.3)).length() > 0.5);
}
