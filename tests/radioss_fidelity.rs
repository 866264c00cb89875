//! Fidelity to OpenRadioss (issue 12) through the joint set and rapier: the automatic
//! stiffness and the stable step of the KJOINT2 QA model (`qa-tests/miniqa/RESSORT/kjoint2`
//! of OpenRadioss: two 156 kg rigid bodies, I = 31200, the spring node 75 from the fixed
//! body's centre of mass, dt = 1.475e-3), and the figures of spec §5.

mod common;
use rapier3d::prelude::*;
use rapier_kjoint::{JointType, Kjoint2Property, KjointHandle, KjointSet, SubstepSettings};

/// Radioss' fixed time step of the QA deck (`/DTIX 0 1.475e-3`) \[s\].
const DT: f64 = 1.475e-3;

/// The QA model: body 1 fixed, its centre of mass at (−75, 0, 0) (the rigid body `rb1` of
/// the deck, spring node 1 at the origin); body 2 of 156 kg, I = 31200, its centre of mass
/// at the spring node; a spherical KJOINT2 with automatic stiffness between the two nodes.
struct Qa {
    w: PhysicsWorld,
    set: KjointSet,
    rb2: RigidBodyHandle,
    j: KjointHandle,
}

fn qa_model(prop: Kjoint2Property) -> Qa {
    let mut w = PhysicsWorld::default();
    w.gravity = Vector::ZERO;
    let rb1 = w.insert_body(RigidBodyBuilder::fixed().additional_mass_properties(
        MassProperties::new(Vector::new(-75.0, 0.0, 0.0), 156.0, Vector::splat(31200.0)),
    ));
    let rb2 = common::point_body(&mut w, 156.0, Vector::splat(31200.0), Vector::ZERO);
    let mut set = KjointSet::with_settings(SubstepSettings {
        substeps: 1,
        ..Default::default()
    });
    let j = common::add(&mut set, &w, prop, rb1, rb2, |b| b);
    Qa { w, set, rb2, j }
}

/// Issue 12, item 2: the fixed body's anchor offset (75) is part of r² although the fixed
/// body does not bound the minimum: KX = 0.8·I/(α·dt²·75²) = 4.97455e5 and
/// KR = I/(α·dt²) = 3.49773e9 as OpenRadioss (the crate gave KX = 3.4977e7 = 2m/(α·dt²)).
#[test]
fn qa_model_automatic_stiffness_counts_the_fixed_body_offset() {
    let mut qa = qa_model(Kjoint2Property::new(JointType::Spherical).with_critical_damping(0.01));
    qa.set.step(&mut qa.w, DT).unwrap();
    let k = qa.set.get(qa.j).unwrap().blocked_stiffness().unwrap();
    // the formulas (rapier keeps the inertia in f32: 1e-6 relative)
    let adt2 = 4.1 * DT * DT;
    let (kx, kr) = (0.8 * 31200.0 / (adt2 * 5625.0), 31200.0 / adt2);
    assert!(
        (k.translational / kx - 1.0).abs() < 1e-6,
        "KX = {}",
        k.translational
    );
    assert!(
        (k.rotational / kr - 1.0).abs() < 1e-6,
        "KR = {}",
        k.rotational
    );
    // the OpenRadioss figures, to their six printed digits
    assert!(
        (k.translational - 4.97455e5).abs() < 0.5,
        "KX = {}",
        k.translational
    );
    assert!(
        (k.rotational - 3.49773e9).abs() < 5e3,
        "KR = {}",
        k.rotational
    );
    let _ = qa.rb2;
}
