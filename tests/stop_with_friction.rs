//! A stop on a DOF with friction is the friction spring (docs/kjoint2.md §4.2): its stiffness
//! is `Kf`, not the blocked `KR`. A ragdoll given a little joint friction (`Kf` = 100 N·m/rad,
//! 1 N·m) saw its hips' cone stops overrun by 0.51 rad at 4 substeps (1.0 rad at 8), against
//! 0.006–0.017 rad without friction (user trial, 2026-12-02); the builder's documentation now
//! says so. This pins the number a user reads: a rod resting on its stop overruns it by
//! `(M − FF)/Kf` with friction, by almost nothing without.

mod common;
use rapier_kjoint::dynamics::StopRemedy;
use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;

/// A 1 kg, 1 m rod hinged at one end about world z, released horizontal onto a stop at
/// −0.1 rad; returns the hinge's angle after 5 s and the moment gravity puts on the stop.
fn rest_on_stop(law: DofLaw) -> (f64, f64) {
    let mut world = PhysicsWorld::default();
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let (rod, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.5, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.02, 0.02).mass(1.0),
    );
    // the stop's critical damping is `Cr·√(K·I)` with `I` the rod's mean inertia about its
    // centre (§4.6): at the default Cr = 0.05 the rod bounces on its stop for seconds; a
    // viscosity settles it
    let hinge = KjointProperty::new(JointType::Revolute).with_dof(Dof::Rx, law.with_viscosity(3.0));
    let mut joints = KjointSet::new();
    let h = joints
        .insert(
            common::rod_end_hinge_about_z(hinge),
            ground,
            rod,
            &world.bodies,
        )
        .unwrap();
    for _ in 0..300 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
    let st = joints.get(h).unwrap().state().unwrap();
    // at rest: asleep (its readout that of the step it fell asleep at) or still
    assert!(
        world.bodies[rod].is_sleeping() || st.rate[Dof::Rx].abs() < 1e-3,
        "not at rest: {} rad/s",
        st.rate[Dof::Rx]
    );
    let q = st.q[Dof::Rx];
    // gravity's moment about the hinge, m·g·(L/2)·cos(q)
    (q, 1.0 * 9.81 * 0.5 * q.cos())
}

#[test]
fn a_stop_with_friction_is_as_stiff_as_the_friction_spring() {
    let (kf, ff) = (500.0, 0.05);
    let (q, m) = rest_on_stop(
        DofLaw::default()
            .with_stops(-0.1, 0.1)
            .with_friction(kf, ff),
    );
    let overrun = -0.1 - q;
    // (M − FF)/Kf = (4.88 − 0.05)/500 = 9.7 mm·rad
    let expected = (m - ff) / kf;
    assert!(
        (overrun - expected).abs() < 0.1 * expected,
        "overrun {overrun} rad, expected (M − FF)/Kf = {expected} rad"
    );
    // without friction the stop is the blocked rotational stiffness: it holds
    let (q0, _) = rest_on_stop(DofLaw::default().with_stops(-0.1, 0.1));
    assert!(
        (-0.1 - q0).abs() < 1e-3,
        "frictionless stop overrun {}",
        -0.1 - q0
    );
}

/// The rod of [`rest_on_stop`] on a joint of property `joint` whose frame 1 is `frame`, `x`
/// m along world x from the origin, at `substeps` a frame, released horizontal and stepped
/// 2 s: the stop overrun warnings, with their text.
fn overrun_warnings(
    joint: KjointProperty,
    frame: Rotation,
    x: Real,
    substeps: usize,
) -> Vec<(StopRemedy, String)> {
    let mut world = PhysicsWorld::default();
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let (rod, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(x + 0.5, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.02, 0.02).mass(1.0),
    );
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    joints
        .insert(
            KjointBuilder::new(joint)
                .world_frame1(frame)
                .local_anchor1(Vector::new(x, 0.0, 0.0))
                .local_anchor2(Vector::new(-0.5, 0.0, 0.0)),
            ground,
            rod,
            &world.bodies,
        )
        .unwrap();
    let mut found = Vec::new();
    for _ in 0..120 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
        for e in joints.drain_events() {
            if let KjointEventKind::StopOverrun { remedy, .. } = e.kind {
                found.push((remedy, e.to_string()));
            }
        }
    }
    found
}

/// The stop overrun warning names what makes the stop soft, so that its remedy is one that
/// works: a stop on a DOF with friction is its friction spring `Kf`, and a larger `Kf`
/// stiffens it. A ball joint's cone 1000 m from the origin, whose automatic stiffness the
/// f32 rounding of the poses there lowers, overran (a game developer's ragdoll overran its
/// limits further at 16 substeps than at 4; a trial, 2026-12-04): its coupled stops are now
/// predicted and held as rigid limits, and it no longer overruns.
#[test]
fn a_stop_overrun_warning_names_what_makes_the_stop_soft() {
    let about_z = Rotation::from_rotation_arc(Vector::X, Vector::Z);
    let hinge = |law: DofLaw| KjointProperty::new(JointType::Revolute).with_dof(Dof::Rx, law);
    let law = DofLaw::default()
        .with_stops(-0.1, 0.1)
        .with_friction(20.0, 0.05);
    let with_friction = overrun_warnings(hinge(law), about_z, 0.0, 4);
    let (remedy, text) = with_friction.first().expect("an overrun warning");
    assert_eq!(*remedy, StopRemedy::FrictionSpring { stiffness: 20.0 });
    assert!(
        text.contains("friction spring Kf = 20.00 N·m/rad"),
        "{text}"
    );
    // a ball joint's cone (coupled stops at 0.1 rad), the rod swinging down onto it
    let cone = DofLaw::default().with_stops(-0.1, 0.1).with_coupled_stops();
    let ball = KjointProperty::new(JointType::Spherical)
        .with_dof(Dof::Ry, cone.clone())
        .with_dof(Dof::Rz, cone);
    // at the origin the cone holds: no warning
    let near = overrun_warnings(ball.clone(), Rotation::IDENTITY, 0.0, 16);
    assert!(near.is_empty(), "{near:?}");
    // 1000 m out, where the f32 noise bound lowers the automatic stiffness more than a
    // hundredfold, the cone overran at 16 substeps and the warning named the bound
    // (`StopRemedy::NoiseBounded`); the coupled stops are now held rigidly by the stop
    // prediction, as a hinge's are, whatever the stiffness: no overrun, in f32 as in f64
    let far = overrun_warnings(ball, Rotation::IDENTITY, 1000.0, 16);
    assert!(far.is_empty(), "{far:?}");
}
