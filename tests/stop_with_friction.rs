//! A stop on a DOF with friction is the friction spring (docs/kjoint2.md §4.2): its stiffness
//! is `Kf`, not the blocked `KR`. A ragdoll given a little joint friction (`Kf` = 100 N·m/rad,
//! 1 N·m) saw its hips' cone stops overrun by 0.51 rad at 4 substeps (1.0 rad at 8), against
//! 0.006–0.017 rad without friction (user trial, 2026-12-02); the builder's documentation now
//! says so. This pins the number a user reads: a rod resting on its stop overruns it by
//! `(M − FF)/Kf` with friction, by almost nothing without; and a stop given a stiffness of
//! its own (`DofLaw::with_stop_stiffness`, `Kf` without friction) peaks as its oscillator
//! whatever the substep.

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

/// The peak force of a stop hit at `v` = 1 m/s by a 10 kg body on a translational joint (no
/// gravity), `substeps` a 1/60 s frame: with a stop stiffness of its own `k` = 1e5 N/m
/// ([`DofLaw::with_stop_stiffness`]), or at the blocked stiffness (`k` = 0); the stop's
/// damping the default `Cr = 0.05` of `√(k·m)` (docs/kjoint2.md §4.6).
fn stop_peak(k: f64, substeps: usize) -> f64 {
    let mut world = PhysicsWorld {
        gravity: Vector::ZERO,
        ..Default::default()
    };
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let (body, _) = world.insert(
        RigidBodyBuilder::dynamic().linvel(Vector::new(1.0, 0.0, 0.0)),
        ColliderBuilder::ball(0.05).mass(10.0),
    );
    let mut law = DofLaw::default().with_stops(-0.1, 0.1);
    if k > 0.0 {
        law = law.with_stop_stiffness(k);
    }
    let slider = (KjointProperty::new(JointType::Translational).with_dof(Dof::Dx, law))
        .with_critical_damping(0.05);
    let mut joints = KjointSet::with_settings(rapier_kjoint::SubstepSettings {
        substeps,
        ..Default::default()
    });
    let h = (joints.insert(KjointBuilder::new(slider), ground, body, &world.bodies)).unwrap();
    let mut peak = 0.0f64;
    for _ in 0..30 {
        joints
            .step_with(&mut world, 1.0 / 60.0, |phase, _, set| {
                if phase == rapier_kjoint::SubstepPhase::After {
                    let s = set[h].state().unwrap();
                    peak = peak.max(s.applied[Dof::Dx].abs());
                }
                Ok::<(), SimError>(())
            })
            .unwrap();
    }
    peak
}

/// A stop given a stiffness of its own is a compliant bump stop: hit at 1 m/s by 10 kg, its
/// peak force is that of the damped oscillator it makes, `max k·x + c·ẋ` with
/// `x = (v/ω_d)·e^(−ζωt)·sin(ω_d·t)`, `ω = √(k/m)` = 100 rad/s, `ζ = Cr/2` = 0.025: 963.3 N
/// (`v·√(k·m)` = 1000 N undamped), within 1 % at 16 substeps (`ω·h` = 0.10) and 8 % at 4
/// (`ω·h` = 0.42: 936 N in f32, 903 N in f64, where the contact starts at another phase of
/// the substep; the implicit update's damping and the peak read at substep ends); at the blocked
/// stiffness the stop is rigid and its peak grows with the substeps (a car's bump stops
/// read 50, 84 and 147 kN at 4, 8 and 16 substeps: a game developer's trial, 2026-12-06).
#[test]
fn a_stop_with_a_stiffness_of_its_own_peaks_as_its_oscillator_whatever_the_substep() {
    let (k, m, v, zeta) = (1e5f64, 10.0f64, 1.0f64, 0.025f64);
    let w = (k / m).sqrt();
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let c = 2.0 * zeta * (k * m).sqrt();
    let expected = (0..20_000)
        .map(|i| {
            let t = i as f64 * 1e-6;
            let e = (-zeta * w * t).exp();
            let x = v / wd * e * (wd * t).sin();
            let xd = v * e * ((wd * t).cos() - zeta * w / wd * (wd * t).sin());
            k * x + c * xd
        })
        .fold(0.0, f64::max);
    let (soft_4, soft_16) = (stop_peak(k, 4), stop_peak(k, 16));
    let (rigid_4, rigid_16) = (stop_peak(0.0, 4), stop_peak(0.0, 16));
    println!("expected {expected} N; soft {soft_4} / {soft_16} N, rigid {rigid_4} / {rigid_16} N");
    assert!((expected - 963.3).abs() < 0.5, "{expected}");
    assert!((soft_16 - expected).abs() < 0.01 * expected, "{soft_16} N");
    assert!((soft_4 - expected).abs() < 0.08 * expected, "{soft_4} N");
    assert!(
        rigid_16 > 1.5 * rigid_4 && rigid_4 > 2.0 * soft_4,
        "{rigid_4} {rigid_16}"
    );
}
