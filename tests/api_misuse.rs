//! Misuse of the public API: bad values (NaN, infinities, out of range, huge), stale or
//! foreign handles, bodies removed under a joint. Each call either refuses the value with a
//! typed error naming the field (and leaves the set as it was), or runs without panicking
//! and without leaving non-finite state behind; a run that goes wrong names the joint.

// `as Real` is the identity with the `f64` feature and needed with either precision
#![allow(clippy::unnecessary_cast)]
// the crate's `UrdfError` returned as its API returns it (128 bytes, clippy's bound)
#![allow(clippy::result_large_err)]

mod common;

use proptest::prelude::*;
use rapier_kjoint::law::{FlexJointLaw, PlanarFriction};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    BreakCriterion, Curve, Dof, DofLaw, JointFriction, JointType, KjointBuilder, KjointEventKind,
    KjointHandle, KjointProperty, KjointSet, PropertyError, SensorCondition, Severity, SimError,
    SubstepSettings, MAX_RAPIER_ITERATIONS,
};

const G: Vector = Vector::new(0.0, -9.81, 0.0);

/// A 1 kg ball hanging 1 m below the ground on a joint named `hinge` of property `prop`.
fn pendulum(
    prop: KjointProperty,
) -> (
    PhysicsWorld,
    KjointSet,
    RigidBodyHandle,
    RigidBodyHandle,
    KjointHandle,
) {
    let mut set = KjointSet::new();
    let (w, ground, ball, h) = common::hanging_ball(&mut set, prop);
    (w, set, ground, ball, h.expect("valid joint"))
}

fn spherical() -> KjointProperty {
    KjointProperty::new(JointType::Spherical)
}

/// Non-finite values and values far out of any range.
fn non_finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(-f64::NAN),
    ]
}

/// Every body of the world has a finite pose and velocity.
fn bodies_finite(w: &PhysicsWorld) -> bool {
    w.bodies.iter().all(|(_, b)| {
        b.translation().is_finite()
            && b.rotation().is_finite()
            && b.linvel().is_finite()
            && b.angvel().is_finite()
    })
}

/// Steps `frames` frames of 1/60 s up to the first error, each either failing naming the
/// joint or leaving the bodies and readouts finite ([`failed_cleanly`]).
fn steps_fail_cleanly(w: &mut PhysicsWorld, set: &mut KjointSet, frames: usize) {
    for _ in 0..frames {
        let r = set.step(w, 1.0 / 60.0);
        let failed = r.is_err();
        failed_cleanly(w, set, r);
        if failed {
            break;
        }
    }
}

/// After a step that may fail: the error names the joint (`hinge`), or the run is finite.
fn failed_cleanly(w: &PhysicsWorld, set: &KjointSet, r: Result<(), SimError>) {
    match r {
        Ok(()) => {
            assert!(
                bodies_finite(w),
                "a step returned Ok with non-finite bodies"
            );
            for (_, j) in set.iter() {
                if let Some(s) = j.state() {
                    assert!(
                        s.q.0.iter().chain(&s.force.0).all(|v| v.is_finite()),
                        "Ok with a non-finite readout: {s:?}"
                    );
                }
            }
        }
        Err(e) => {
            let text = e.to_string();
            assert!(
                text.contains("hinge"),
                "the error does not name the joint: {text}"
            );
        }
    }
}

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 64,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

// ---------------------------------------------------------------------------------------
// stepping

/// Limits given the wrong way round name the call they come from: the error named
/// `rx.stop_min (SA-)` alone, a field a rapier user who wrote `with_limits` never saw (a
/// mechanism designer's trial, 2026-12-05).
#[test]
fn limits_the_wrong_way_round_name_with_limits() {
    let mut set = KjointSet::new();
    let hinge = KjointProperty::new(JointType::Revolute)
        .with_dof(Dof::Rx, DofLaw::default().with_limits(1.0, -1.0));
    let (_, _, _, r) = common::hanging_ball(&mut set, hinge);
    let e = r.unwrap_err().to_string();
    assert!(
        e.contains("rx.stop_min (SA-)") && e.contains("with_limits(lower, upper)"),
        "{e}"
    );
}

/// A frame of 0 s (a paused game's) is rapier's zero-length step: it returns `Ok`, no time
/// passes, the swinging ball and its joint's readout stay as they were, and rapier applies
/// the user's changes (a ball moved by the user has its collider moved with it). It was
/// refused as a time step that is not > 0.
#[test]
fn a_frame_of_zero_seconds_passes_no_time_and_applies_the_users_changes() {
    let (mut w, mut set, _, ball, h) = pendulum(spherical());
    set.step(&mut w, 1.0 / 60.0).unwrap();
    let (t, pos, vel, state) = (
        set.time(),
        w.bodies[ball].translation(),
        w.bodies[ball].linvel(),
        set.get(h).unwrap().state().cloned(),
    );
    for dt in [0.0, -0.0] {
        set.step(&mut w, dt).unwrap();
        assert_eq!(set.time(), t);
        assert_eq!(w.bodies[ball].translation(), pos);
        assert_eq!(w.bodies[ball].linvel(), vel);
        assert_eq!(set.get(h).unwrap().state().cloned(), state);
    }
    let mut called = false;
    set.step_with(&mut w, 0.0, |_, _, _| {
        called = true;
        Ok::<(), SimError>(())
    })
    .unwrap();
    assert!(!called);
    // the user moves the ball 1 cm: a zero step moves its collider with it
    let collider = w.bodies[ball].colliders()[0];
    let moved = pos + Vector::new(0.01, 0.0, 0.0);
    w.bodies[ball].set_translation(moved, true);
    set.step(&mut w, 0.0).unwrap();
    let at = w.colliders[collider].translation();
    assert!((at - moved).length() < 1e-6, "{at:?} {moved:?}");
    assert_eq!(set.time(), t);
    // and the set goes on stepping
    set.step(&mut w, 1.0 / 60.0).unwrap();
    assert!(set.time() > t);
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn a_frame_dt_negative_or_not_finite_is_refused_and_changes_nothing(
        dt in prop_oneof![non_finite(), -1e300..-1e-300f64],
    ) {
        let (mut w, mut set, _, ball, h) = pendulum(spherical());
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let (t, pos, state) = (set.time(), w.bodies[ball].translation(), set.get(h).unwrap().state().cloned());
        let e = set.step(&mut w, dt).unwrap_err();
        prop_assert!(matches!(&e, SimError::InvalidArgument { field, .. } if field == "frame_dt"), "{e}");
        prop_assert!(e.to_string().len() < 120, "{}", e);
        prop_assert_eq!(set.time(), t);
        prop_assert_eq!(w.bodies[ball].translation(), pos);
        prop_assert_eq!(set.get(h).unwrap().state().cloned(), state);
        // the set still steps
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }

    #[test]
    fn a_frame_dt_whose_substep_rapier_cannot_represent_is_refused(
        below in 0.01..15.0f64,
        substeps in 1usize..64,
    ) {
        let (mut w, mut set, _, ball, _) = pendulum(spherical());
        set.set_settings(SubstepSettings { substeps, ..Default::default() });
        // a substep `below` decades under rapier's smallest normal number (f32's or f64's):
        // a frame still > 0 in f64
        let dt = Real::MIN_POSITIVE as f64 * 10f64.powf(-below) * substeps as f64;
        prop_assert!(dt > 0.0);
        let h = (dt / substeps as f64) as Real;
        prop_assert!(!h.is_normal());
        let v = w.bodies[ball].linvel();
        let e = set.step(&mut w, dt).unwrap_err();
        prop_assert!(matches!(&e, SimError::InvalidArgument { field, .. } if field == "frame_dt"), "{e}");
        prop_assert!(e.to_string().contains("substep"), "{}", e);
        prop_assert!(e.to_string().len() < 300, "{}", e);
        prop_assert_eq!(set.time(), 0.0);
        prop_assert_eq!(w.bodies[ball].linvel(), v);
    }

    #[test]
    fn a_huge_or_tiny_frame_dt_fails_naming_the_joint_or_stays_finite(
        exp in prop_oneof![-300.0..-20.0f64, 3.0..300.0f64],
    ) {
        let (mut w, mut set, _, _, _) = pendulum(spherical().with_dof(Dof::Rx, DofLaw::spring(10.0)));
        w.bodies.iter_mut().for_each(|(_, b)| b.set_angvel(Vector::new(1.0, 0.0, 0.0), true));
        let dt = 10f64.powf(exp);
        let r = set.step(&mut w, dt);
        if !((dt / 4.0) as Real).is_normal() || dt / 4.0 > rapier_kjoint::MAX_SUBSTEP {
            // a substep rapier cannot represent, or over a second, is refused at the door
            prop_assert!(matches!(&r, Err(SimError::InvalidArgument { field, .. }) if field == "frame_dt"), "{:?}", r);
        } else {
            failed_cleanly(&w, &set, r);
        }
    }

    #[test]
    fn every_call_taking_a_substep_refuses_one_not_finite_and_positive(
        h in prop_oneof![non_finite(), Just(0.0), -1e300..0.0f64, 1.000001..1e300f64],
    ) {
        let (mut w, mut set, _, ball, _) = pendulum(spherical());
        set.set_settings(SubstepSettings { radioss_start: true, ..Default::default() });
        set.prepare(&mut w);
        let v = w.bodies[ball].linvel();
        let named_h = |e: &SimError| matches!(e, SimError::InvalidArgument { field, .. } if field == "h");
        let e = set.apply_substep(&mut w.bodies, w.gravity, h).unwrap_err();
        prop_assert!(named_h(&e), "{e}");
        let e = set.radioss_start_kick(&mut w.bodies, w.gravity, h).unwrap_err();
        prop_assert!(named_h(&e), "{e}");
        let e = set.advance_time(h).unwrap_err();
        prop_assert!(named_h(&e), "{e}");
        prop_assert!(e.to_string().len() < 120, "{}", e);
        // nothing moved, the time stays
        prop_assert_eq!(w.bodies[ball].linvel(), v);
        prop_assert_eq!(set.time(), 0.0);
    }
}

#[test]
fn an_automatic_stiffness_too_large_for_the_substep_names_the_substep_not_scf() {
    // the substep alone (ScF at its default): the error says the substep is too small
    let (mut w, mut set, ground, ball, h) = pendulum(spherical());
    set.prepare(&mut w);
    let e = set
        .apply_substep(&mut w.bodies, w.gravity, 1e-200)
        .unwrap_err();
    assert!(
        matches!(&e, SimError::InvalidJoint { joint, reason } if joint == "hinge" && reason.contains("substep")),
        "{e}"
    );
    // a huge ScF at an ordinary substep: ScF is named
    set.remove(h).unwrap();
    set.insert(
        KjointBuilder::new(spherical().with_scale_factor(1e307))
            .name("scf")
            .local_anchor2(Vector::new(0.0, 1.0, 0.0)),
        ground,
        ball,
        &w.bodies,
    )
    .unwrap();
    let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
    assert!(
        matches!(&e, SimError::Property { joint, .. } if joint == "scf"),
        "{e}"
    );
    assert!(e.to_string().contains("scale_factor (ScF)"), "{e}");
}

#[test]
fn zero_rapier_iterations_are_refused_and_the_settings_can_be_fixed() {
    let (mut w, mut set, _, _, _) = pendulum(spherical());
    set.set_settings(SubstepSettings {
        rapier_iterations: 0,
        ..Default::default()
    });
    let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
    assert!(e.to_string().contains("rapier_iterations"), "{e}");
    assert_eq!(set.time(), 0.0);
    set.set_settings(SubstepSettings::default());
    set.step(&mut w, 1.0 / 60.0).unwrap();
}

/// rapier bounds its own substeps by nothing: `usize::MAX` of them and the step never
/// returned. One over the bound is refused before anything moves; the bound itself steps.
#[test]
fn too_many_rapier_iterations_are_refused_before_anything_moves() {
    let (mut w, mut set, _, ball, _) = pendulum(spherical());
    let y0 = w.bodies[ball].translation().y;
    for n in [MAX_RAPIER_ITERATIONS + 1, usize::MAX] {
        set.set_settings(SubstepSettings {
            rapier_iterations: n,
            ..Default::default()
        });
        let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
        assert!(
            matches!(&e, SimError::InvalidArgument { field, value, .. }
                if field == "SubstepSettings::rapier_iterations" && *value == n.to_string()),
            "{e}"
        );
        assert!(e.to_string().contains("1 ..= 1000"), "{e}");
        assert_eq!(set.time(), 0.0);
        assert_eq!(w.bodies[ball].translation().y, y0);
    }
    set.set_settings(SubstepSettings {
        rapier_iterations: MAX_RAPIER_ITERATIONS,
        substeps: 1,
        ..Default::default()
    });
    set.step(&mut w, 1.0 / 600.0).unwrap();
    assert!(set.time() > 0.0);
}

/// A NaN or infinite gravity is refused at the door, naming it, before anything moves: it
/// was reported as the first joint's non-finite impulse, naming a joint not at fault.
#[test]
fn a_non_finite_gravity_is_refused_naming_it_before_anything_moves() {
    for g in [f64::NAN, f64::INFINITY] {
        let (mut w, mut set, _, ball, _) = pendulum(spherical());
        let y0 = w.bodies[ball].translation().y;
        w.gravity = Vector::new(0.0, g as Real, 0.0);
        let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
        assert!(
            matches!(&e, SimError::InvalidArgument { field, .. } if field == "gravity"),
            "{e}"
        );
        assert!(e.to_string().contains("finite components"), "{e}");
        assert_eq!(set.time(), 0.0);
        assert_eq!(w.bodies[ball].translation().y, y0);
        assert_eq!(w.bodies[ball].linvel(), Vector::ZERO);
        // the substep by substep call too
        let e = set
            .apply_substep(&mut w.bodies, w.gravity, 1.0 / 240.0)
            .unwrap_err();
        assert!(
            matches!(&e, SimError::InvalidArgument { field, .. } if field == "gravity"),
            "{e}"
        );
        assert_eq!(w.bodies[ball].linvel(), Vector::ZERO);
        // fixed, it steps
        w.gravity = G;
        set.step(&mut w, 1.0 / 60.0).unwrap();
        assert!((set.time() - 1.0 / 60.0).abs() < 1e-12, "{}", set.time());
        assert!(w.bodies[ball].translation().is_finite());
    }
}

/// A body the user made non-finite fails naming the joint, the body and what is not
/// finite; before the first step too, where the stiffness rule read it as a body without
/// mass ("automatic stiffness is zero: a body has no mass", a mechanism designer's trial,
/// 2026-12-05), and after it, where the error named the joint alone.
#[test]
fn a_body_made_non_finite_by_the_user_fails_naming_the_joint() {
    for first in [true, false] {
        let (mut w, mut set, _, ball, _) = pendulum(spherical());
        if !first {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        w.bodies[ball].set_linvel(Vector::new(Real::NAN, 0.0, 0.0), true);
        let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
        if first {
            assert!(matches!(&e, SimError::InvalidJoint { .. }), "{e}");
        } else {
            assert!(matches!(&e, SimError::Unstable { .. }), "{e}");
        }
        let text = e.to_string();
        assert!(
            text.contains("hinge")
                && text.contains("body 2")
                && text.contains("non-finite linear velocity [NaN, 0.0, 0.0]")
                && !text.contains("mass"),
            "{e}"
        );
    }
    // a translation set to infinity before the first step
    let (mut w, mut set, _, ball, _) = pendulum(spherical());
    w.bodies[ball].set_translation(Vector::new(0.0, Real::INFINITY, 0.0), true);
    let e = set.step(&mut w, 1.0 / 60.0).unwrap_err().to_string();
    assert!(e.contains("body 2 has a non-finite translation"), "{e}");
}

/// A NaN or infinite force or torque the user adds to a jointed body (rapier's `add_force`)
/// fails naming the body and what is not finite: it was reported as the joint's
/// "non-finite joint impulse", the joint taken for the culprit (a game developer's trial,
/// 2026-12-06).
#[test]
fn a_non_finite_user_force_fails_naming_the_body() {
    for (torque, first) in [(false, true), (false, false), (true, false)] {
        let (mut w, mut set, _, ball, _) = pendulum(spherical());
        if !first {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        if torque {
            w.bodies[ball].add_torque(Vector::new(0.0, 0.0, Real::INFINITY), true);
        } else {
            w.bodies[ball].add_force(Vector::new(Real::NAN, 0.0, 0.0), true);
        }
        let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
        let text = e.to_string();
        let what = if torque {
            "non-finite user torque [0.0, 0.0, inf]"
        } else {
            "non-finite user force [NaN, 0.0, 0.0]"
        };
        assert!(matches!(&e, SimError::Unstable { .. }), "{e}");
        assert!(
            text.contains("body 2 of joint `hinge`") && text.contains(what),
            "{e}"
        );
        assert!(!text.contains("impulse"), "{e}");
    }
    // a foot resting on the ground, which the solve takes as heavier along gravity's axis
    // (`held_axes`), given a NaN force along that axis: named as well, not hidden by the
    // hold (rapier would have quarantined the foot, told as a law feeding energy)
    let mut w = PhysicsWorld::default();
    w.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let (foot, _) = w.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.05, 0.0)),
        ColliderBuilder::cuboid(0.1, 0.05, 0.1).mass(1.0),
    );
    let (block, _) = w.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.35, 0.0)),
        (ColliderBuilder::cuboid(0.2, 0.2, 0.2).mass(10.0))
            .collision_groups(InteractionGroups::none()),
    );
    let mut set = KjointSet::new();
    let fixed = KjointBuilder::new(KjointProperty::new(JointType::Fixed))
        .local_anchor1(Vector::new(0.0, -0.25, 0.0))
        .name("ankle");
    set.insert(fixed, block, foot, &w.bodies).unwrap();
    for _ in 0..30 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    w.bodies[foot].add_force(Vector::new(0.0, Real::NAN, 0.0), true);
    let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("body 2 of joint `ankle`")
            && text.contains("non-finite user force [0.0, NaN, 0.0]"),
        "{e}"
    );
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn a_negative_or_nan_mass_or_inertia_fails_naming_the_joint_and_the_body(
        bad_mass in any::<bool>(),
        v in prop_oneof![Just(Real::NAN), Just(-Real::NAN), -1e30..-1e-6 as Real],
        which in 1u8..=2,
        kn in prop_oneof![Just(0.0), 1e2..1e8f64],
    ) {
        let (mut w, ground) = common::world(G);
        let (m, i) = if bad_mass { (v, 0.01) } else { (1.0, v) };
        let good = common::point_body(&mut w, 1.0, Vector::splat(0.01), Vector::new(0.0, -2.0, 0.0));
        let bad = common::point_body(&mut w, m, Vector::new(0.01, i, 0.01), Vector::new(0.0, -1.0, 0.0));
        let mut set = KjointSet::new();
        set.insert(KjointBuilder::new(spherical()).name("top"), ground, good, &w.bodies).unwrap();
        let (b1, b2) = if which == 1 { (bad, good) } else { (good, bad) };
        set.insert(KjointBuilder::new(spherical().with_kn(kn)).name("hinge"), b1, b2, &w.bodies).unwrap();
        let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
        let what = if bad_mass { "mass" } else { "inertia" };
        prop_assert!(
            matches!(&e, SimError::InvalidJoint { joint, reason }
                if joint == "hinge" && reason.contains(&format!("body {which}")) && reason.contains(what)),
            "{}", e
        );
        prop_assert!(bodies_finite(&w));
        prop_assert_eq!(set.time(), 0.0);
    }

    #[test]
    fn extreme_but_valid_masses_fail_naming_the_joint_or_stay_finite(
        m in prop_oneof![Just(0.0 as Real), 1e-30..1e-6 as Real, 1e6..1e30 as Real],
        i in prop_oneof![Just(0.0 as Real), 1e-30..1e-6 as Real, 1e6..1e30 as Real],
        kn in prop_oneof![Just(0.0), 1e2..1e8f64],
    ) {
        let (mut w, ground) = common::world(G);
        let ball = common::point_body(&mut w, m, Vector::splat(i), Vector::new(0.0, -1.0, 0.0));
        let mut set = KjointSet::new();
        set.insert(
            KjointBuilder::new(spherical().with_kn(kn)).name("hinge").local_anchor2(Vector::new(0.0, 1.0, 0.0)),
            ground,
            ball,
            &w.bodies,
        )
        .unwrap();
        w.bodies[ball].set_angvel(Vector::new(0.0, 0.0, 2.0), true);
        steps_fail_cleanly(&mut w, &mut set, 3);
    }
}

// ---------------------------------------------------------------------------------------
// insertion

#[test]
fn a_joint_between_a_body_and_itself_is_refused() {
    let (w, mut set, ground, ball, _) = pendulum(spherical());
    for b in [ball, ground] {
        let e = set
            .insert(
                KjointBuilder::new(spherical()).name("self"),
                b,
                b,
                &w.bodies,
            )
            .unwrap_err();
        assert!(
            matches!(&e, SimError::InvalidJoint { joint, .. } if joint == "self"),
            "{e}"
        );
    }
    assert_eq!(set.len(), 1);
}

#[test]
fn a_joint_between_two_fixed_bodies_is_refused() {
    let (mut w, mut set, ground, _, _) = pendulum(spherical());
    let other = w.insert_body(RigidBodyBuilder::fixed());
    let e = set
        .insert(
            KjointBuilder::new(spherical()).name("rigid"),
            ground,
            other,
            &w.bodies,
        )
        .unwrap_err();
    assert!(
        matches!(&e, SimError::InvalidJoint { joint, .. } if joint == "rigid"),
        "{e}"
    );
    assert_eq!(set.len(), 1);
    // a refused insertion does not use up a default name
    let ball = common::ball(&mut w, 1.0, 0.1, Vector::ZERO);
    let h = set
        .insert(KjointBuilder::new(spherical()), ground, ball, &w.bodies)
        .unwrap();
    assert_eq!(set.get(h).unwrap().name, "joint2");
}

#[test]
fn a_removed_or_foreign_body_handle_is_a_missing_body() {
    let (mut w, mut set, ground, ball, _) = pendulum(spherical());
    let gone = common::ball(&mut w, 1.0, 0.1, Vector::ZERO);
    w.remove_body(gone);
    let e = set
        .insert(
            KjointBuilder::new(spherical()).name("stale"),
            ground,
            gone,
            &w.bodies,
        )
        .unwrap_err();
    assert!(
        matches!(&e, SimError::MissingBody { joint, which: 2, body }
            if joint == "stale" && *body == gone),
        "{e}"
    );
    let (index, generation) = gone.into_raw_parts();
    assert_eq!(
        e.to_string(),
        format!(
            "joint `stale`: body 2 (RigidBodyHandle index {index}, generation {generation}) \
             is not in the rigid-body set"
        )
    );
    let e = set
        .insert(
            KjointBuilder::new(spherical()).name("stale"),
            gone,
            ball,
            &w.bodies,
        )
        .unwrap_err();
    assert!(
        matches!(&e, SimError::MissingBody { which: 1, body, .. } if *body == gone),
        "{e}"
    );
    // a handle of another world that this one does not have
    let (mut w2, _) = common::world(G);
    let mut far = ball;
    for _ in 0..5 {
        far = w2.insert_body(RigidBodyBuilder::dynamic());
    }
    let e = set
        .insert(
            KjointBuilder::new(spherical()).name("far"),
            ground,
            far,
            &w.bodies,
        )
        .unwrap_err();
    assert!(
        matches!(&e, SimError::MissingBody { which: 2, body, .. } if *body == far),
        "{e}"
    );
    // and an invalid handle
    let e = set
        .insert(
            KjointBuilder::new(spherical()).name("nil"),
            ground,
            RigidBodyHandle::invalid(),
            &w.bodies,
        )
        .unwrap_err();
    assert!(
        matches!(&e, SimError::MissingBody { which: 2, body, .. } if body.is_invalid()),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("body 2 (RigidBodyHandle::invalid())"),
        "{e}"
    );
    assert_eq!(set.len(), 1);
    set.step(&mut w, 1.0 / 60.0).unwrap();
}

#[test]
fn a_body_with_a_non_finite_pose_or_velocity_is_refused_at_insert() {
    let (mut w, mut set, ground, ball, _) = pendulum(spherical());
    let v = Real::NAN;
    let bad_bodies = [
        RigidBodyBuilder::dynamic().translation(Vector::new(v, 0.0, 0.0)),
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, Real::INFINITY, 0.0)),
        RigidBodyBuilder::dynamic().rotation(Vector::new(0.0, 0.0, v)),
        RigidBodyBuilder::dynamic().linvel(Vector::new(0.0, 0.0, v)),
        RigidBodyBuilder::dynamic().angvel(Vector::new(Real::NEG_INFINITY, 0.0, 0.0)),
    ];
    for (i, b) in bad_bodies.into_iter().enumerate() {
        let bad = w.insert_body(b.additional_mass(1.0));
        for (b1, b2, which) in [(ground, bad, "body 2"), (bad, ball, "body 1")] {
            let e = set
                .insert(
                    KjointBuilder::new(spherical()).name("nan"),
                    b1,
                    b2,
                    &w.bodies,
                )
                .unwrap_err();
            assert!(
                matches!(&e, SimError::InvalidJoint { joint, reason } if joint == "nan" && reason.contains(which)),
                "case {i}: {e}"
            );
        }
        w.remove_body(bad);
    }
    assert_eq!(set.len(), 1);
    set.step(&mut w, 1.0 / 60.0).unwrap();
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn a_non_finite_anchor_is_refused_naming_it(
        v in prop_oneof![Just(Real::NAN), Just(Real::INFINITY), Just(Real::NEG_INFINITY)],
        i in 0usize..3,
        second in any::<bool>(),
    ) {
        let (w, mut set, ground, ball, _) = pendulum(spherical());
        let mut a = [0.0 as Real; 3];
        a[i] = v;
        let a = Vector::new(a[0], a[1], a[2]);
        let b = KjointBuilder::new(spherical()).name("anchor");
        let b = if second { b.local_anchor2(a) } else { b.local_anchor1(a) };
        let e = set.insert(b, ground, ball, &w.bodies).unwrap_err();
        let field = if second { "local_anchor2" } else { "local_anchor1" };
        prop_assert!(
            matches!(&e, SimError::InvalidArgument { field: f, .. } if f.contains(field) && f.contains("anchor")),
            "{}", e
        );
        prop_assert_eq!(set.len(), 1);
    }

    #[test]
    fn a_frame_not_a_finite_unit_quaternion_is_refused(
        s in prop_oneof![Just(0.0 as Real), Just(2.0), Just(Real::NAN), Just(Real::INFINITY), 1.01..1e30 as Real],
        second in any::<bool>(),
    ) {
        let (w, mut set, ground, ball, _) = pendulum(spherical());
        let q = Rotation::from_xyzw(0.0, 0.0, 0.0, s);
        let b = KjointBuilder::new(spherical()).name("frame");
        let b = if second { b.world_frame2(q) } else { b.world_frame1(q) };
        let e = set.insert(b, ground, ball, &w.bodies).unwrap_err();
        let field = if second { "world_frame2" } else { "world_frame1" };
        prop_assert!(
            matches!(&e, SimError::InvalidArgument { field: f, .. } if f.contains(field)),
            "{}", e
        );
    }

    #[test]
    fn far_anchors_fail_naming_the_joint_or_stay_finite(exp in 3.0..38.0f64, kn in prop_oneof![Just(0.0), 1e3..1e8f64]) {
        let (mut w, ground) = common::world(G);
        let ball = common::ball(&mut w, 1.0, 0.1, Vector::new(0.0, -1.0, 0.0));
        let mut set = KjointSet::new();
        let far = 10f64.powf(exp) as Real;
        let r = set.insert(
            KjointBuilder::new(spherical().with_kn(kn)).name("hinge").local_anchor2(Vector::new(far, 0.0, 0.0)),
            ground,
            ball,
            &w.bodies,
        );
        match r {
            Err(e) => prop_assert!(e.to_string().contains("hinge"), "{}", e),
            Ok(_) => {
                let r = set.step(&mut w, 1.0 / 60.0);
                failed_cleanly(&w, &set, r);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// properties

/// The field names of KjointProperty's and DofLaw's numbers, and setters of each.
fn property_with(field: usize, v: f64) -> (KjointProperty, &'static str) {
    let p = KjointProperty::new(JointType::Free);
    let law = |f: fn(DofLaw, f64) -> DofLaw| p.clone().with_dof(Dof::Ry, f(DofLaw::default(), v));
    match field {
        0 => (p.with_kn(v), "kn (Kn)"),
        1 => (p.with_scale_factor(v), "scale_factor (ScF)"),
        2 => (p.with_critical_damping(v), "critical_damping (Cr)"),
        3 => (law(|l, v| DofLaw { stiffness: v, ..l }), "ry.stiffness (K)"),
        4 => (law(|l, v| DofLaw { viscosity: v, ..l }), "ry.viscosity (C)"),
        5 => (law(|l, v| DofLaw { stop_min: v, ..l }), "ry.stop_min (SA-)"),
        6 => (law(|l, v| DofLaw { stop_max: v, ..l }), "ry.stop_max (SA+)"),
        7 => (
            law(|l, v| DofLaw {
                friction_stiffness: v,
                ..l
            }),
            "ry.friction_stiffness (Kf)",
        ),
        _ => (
            law(|l, v| DofLaw { friction: v, ..l }),
            "ry.friction (FF/FM)",
        ),
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn a_non_finite_property_value_is_refused_naming_its_field(field in 0usize..9, v in non_finite()) {
        let (p, name) = property_with(field, v);
        let e = p.validate().unwrap_err();
        prop_assert!(
            matches!(&e, PropertyError::InvalidField { field: f, .. } if f == name),
            "{}: {}", name, e
        );
        // at insertion and through set_property, naming the joint; nothing changes
        let (mut w, mut set, ground, ball, h) = pendulum(KjointProperty::new(JointType::Free).with_kn(1e4));
        let e = set.insert(KjointBuilder::new(p.clone()).name("bad"), ground, ball, &w.bodies).unwrap_err();
        prop_assert!(matches!(&e, SimError::Property { joint, .. } if joint == "bad"), "{}", e);
        prop_assert!(e.to_string().contains(name), "{}", e);
        let before = set.get(h).unwrap().property().clone();
        let e = set.get_mut(h).unwrap().set_property(p).unwrap_err();
        prop_assert!(e.to_string().contains("hinge") && e.to_string().contains(name), "{}", e);
        prop_assert_eq!(set.get(h).unwrap().property(), &before);
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }

    #[test]
    fn a_property_value_out_of_range_is_refused_naming_its_field(
        (field, v) in prop_oneof![
            (Just(0usize), -1e300..-1e-300f64),
            (Just(1usize), -1e300..-1e-300f64),
            (Just(2usize), prop_oneof![-1e300..-1e-300f64, 1.0000001..1e300f64]),
            (Just(5usize), 1e-300..1e300f64),
            (Just(6usize), -1e300..-1e-300f64),
            (Just(7usize), -1e300..-1e-300f64),
            (Just(8usize), -1e300..-1e-300f64),
        ],
    ) {
        let (p, name) = property_with(field, v);
        let e = p.validate().unwrap_err();
        prop_assert!(
            matches!(&e, PropertyError::InvalidField { field: f, .. } if f == name),
            "{}: {}", name, e
        );
        prop_assert!(e.to_string().len() < 400, "message too long: {}", e);
    }

    #[test]
    fn a_huge_blocked_stiffness_fails_naming_the_joint_or_stays_finite(exp in 6.0..308.0f64) {
        let kn = 10f64.powf(exp);
        let prop = spherical().with_kn(kn);
        match prop.validate() {
            Err(e) => prop_assert!(e.to_string().contains("kn"), "{}", e),
            Ok(()) => {
                let (mut w, ground) = common::world(G);
                let ball = common::ball(&mut w, 1.0, 0.1, Vector::new(0.0, -1.0, 0.0));
                let mut set = KjointSet::new();
                let r = set.insert(
                    KjointBuilder::new(prop).name("hinge").local_anchor2(Vector::new(0.0, 1.0, 0.0)),
                    ground,
                    ball,
                    &w.bodies,
                );
                match r {
                    Err(e) => prop_assert!(e.to_string().contains("hinge"), "{}", e),
                    Ok(_) => {
                        w.bodies[ball].set_angvel(Vector::new(0.0, 0.0, 3.0), true);
                        steps_fail_cleanly(&mut w, &mut set, 3);
                    }
                }
            }
        }
    }

    #[test]
    fn huge_free_dof_laws_fail_naming_the_joint_or_stay_finite(
        exp in 6.0..308.0f64,
        which in 0usize..5,
        neg in any::<bool>(),
    ) {
        let v = 10f64.powf(exp);
        let law = match which {
            0 => DofLaw::spring(if neg { -v } else { v }),
            1 => DofLaw::default().with_viscosity(if neg { -v } else { v }),
            2 => DofLaw::default().with_friction(v, 1.0),
            3 => DofLaw::default().with_friction(1e3, v),
            _ => DofLaw::default().with_stops(-1e-3, 1e-3).with_friction(v, v),
        };
        let prop = spherical().with_dof(Dof::Rz, law);
        if neg && which < 2 {
            // a negative spring or viscosity is refused, naming the field
            let e = prop.validate().expect_err("a negative spring or viscosity is refused");
            let field = if which == 0 { "rz.stiffness (K)" } else { "rz.viscosity (C)" };
            prop_assert!(e.to_string().contains(field), "{}", e);
            // and `insert` refuses it, naming the joint's field
            let (.., r) = common::hanging_ball(&mut KjointSet::new(), prop);
            let e = r.expect_err("insert refuses a negative spring or viscosity");
            prop_assert!(e.to_string().contains(field), "{}", e);
            return Ok(());
        }
        let (mut w, mut set, _, ball, _) = pendulum(prop);
        w.bodies[ball].set_angvel(Vector::new(0.0, 0.0, 3.0), true);
        steps_fail_cleanly(&mut w, &mut set, 3);
    }
}

/// A viscosity curve whose end falls is a negative viscosity at every rate beyond it, as a
/// negative `C` is everywhere: refused alike, naming the DOF's field and the slope. A body
/// on `[[-1, 10], [1, -10]]` ran away as `e^(10·t)` (4e43 J fed in over 5 s, exit 0). A
/// curve that crosses zero between rising ends, and a constant, stay accepted.
#[test]
fn a_viscosity_curve_whose_end_falls_is_refused() {
    let with_curve = |points: &[(f64, f64)]| {
        let mut law = DofLaw::default().with_viscosity(1.0);
        law.viscosity_curve = Some(Curve::new(points.iter().copied()).unwrap());
        spherical().with_dof(Dof::Rz, law).validate()
    };
    for (points, slope) in [
        (&[(-1.0, 10.0), (1.0, -10.0)][..], "first slope -10.00"),
        (
            &[(-1.0, -10.0), (0.0, 0.0), (1.0, 10.0), (2.0, 5.0)][..],
            "last slope -5.000",
        ),
        (
            &[(-1.0, 3.0), (0.0, 0.0), (1.0, 1.0)][..],
            "first slope -3.000",
        ),
    ] {
        let e = with_curve(points).expect_err("a falling end feeds energy in");
        let text = e.to_string();
        assert!(text.contains("rz.viscosity_curve (fct_C)"), "{text}");
        assert!(text.contains(slope), "{text}");
    }
    with_curve(&[(-1.0, -12.0), (0.0, 2.0), (1.0, 10.0)]).unwrap();
    with_curve(&[(0.0, 5.0), (1.0, 5.0)]).unwrap();
}

/// A friction curve with a negative value is refused, naming the DOF's field, the value
/// and where: the friction force is a cap the DOF sticks up to, and a negative one slipped
/// at its size with its sign dropped (`[[-1, -5], [1, 5]]`, a Radioss analyst's trial,
/// 2026-12-06). A curve that grows either way from zero stays accepted, as does one that
/// falls to a lower positive value.
#[test]
fn a_friction_curve_with_a_negative_value_is_refused() {
    let with_curve = |points: &[(f64, f64)]| {
        let mut law = DofLaw::default().with_friction(1e4, 1.0);
        law.friction_curve = Some(Curve::new(points.iter().copied()).unwrap());
        spherical().with_dof(Dof::Rz, law).validate()
    };
    let e = with_curve(&[(-1.0, -5.0), (1.0, 5.0)]).expect_err("a negative friction force");
    let text = e.to_string();
    assert!(text.contains("rz.friction_curve (fct_FF)"), "{text}");
    assert!(text.contains("-5.000 at -1.000"), "{text}");
    with_curve(&[(-1.0, 5.0), (0.0, 0.0), (1.0, 5.0)]).unwrap();
    with_curve(&[(0.0, 1.0), (0.01, 1.0), (0.011, 0.1)]).unwrap();
}

#[test]
fn malformed_curves_are_refused() {
    let cases: Vec<Vec<(f64, f64)>> = vec![
        vec![],
        vec![(0.0, 0.0), (0.0, 1.0)],
        vec![(1.0, 0.0), (0.0, 1.0)],
        vec![(0.0, 0.0), (1.0, 1.0), (0.5, 2.0)],
        vec![(f64::NAN, 0.0)],
        vec![(0.0, f64::INFINITY)],
        vec![(0.0, 0.0), (1e-320, 1e300)],
        vec![(-1e308, -1.5e308), (1e308, 1.5e308)],
    ];
    for pts in cases {
        let r = Curve::new(pts.clone());
        assert!(
            matches!(r, Err(PropertyError::InvalidCurve(_))),
            "{pts:?} gave {r:?}"
        );
    }
    // the same through serde (a scene's or a program's JSON)
    let r: Result<Curve, _> = serde_json::from_str("[[1.0, 0.0], [0.0, 1.0]]");
    assert!(r.unwrap_err().to_string().contains("increase"));
}

/// A curve of one point has no segment, so no slope to extrapolate with: it was read as the
/// constant `y`, and a spring of `(0.1 rad, 5 N·m)` held 5 N·m at every angle (a body on it
/// with no load spun to −507 rad in 1 s). Refused by `Curve::new`, by serde (a scene's or a
/// program's JSON) and by a property's deserialisation alike, saying that a constant is two
/// points with the same value; none of them panics.
#[test]
fn a_curve_of_one_point_is_refused() {
    let want = "invalid curve: 1 point: expected at least 2 points (a constant is two points \
                with the same value)";
    let e = Curve::new([(0.1, 5.0)]).unwrap_err();
    assert!(matches!(e, PropertyError::InvalidCurve(_)), "{e:?}");
    assert_eq!(e.to_string(), want);
    let e = Curve::new(std::iter::empty()).unwrap_err().to_string();
    assert!(e.contains("no point: expected at least 2 points"), "{e}");
    let e = serde_json::from_str::<Curve>("[[0.1, 5.0]]")
        .unwrap_err()
        .to_string();
    assert!(e.contains(want), "{e}");
    // a constant is accepted
    let c = Curve::new([(0.0, 5.0), (1.0, 5.0)]).unwrap();
    assert_eq!((c.value(-3.0), c.value(7.0), c.slope(0.5)), (5.0, 5.0, 0.0));
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn a_curve_of_any_finite_points_evaluates_finite_or_is_refused(
        pts in proptest::collection::vec((-1e300..1e300f64, -1e300..1e300f64), 1..6),
        x in -1e3..1e3f64,
    ) {
        if let Ok(c) = Curve::new(pts) {
            // extrapolation may overflow only far out; at a joint's range it is finite
            let (v, s) = (c.value(x), c.slope(x));
            prop_assert!(!v.is_nan() && s.is_finite(), "{:?}: f({}) = {}, f' = {}", c, x, v, s);
        }
    }
}

// ---------------------------------------------------------------------------------------
// connector laws and break criteria

proptest! {
    #![proptest_config(config())]

    #[test]
    fn a_break_criterion_out_of_range_is_refused_at_insert_naming_its_field(
        field in 0usize..5,
        v in prop_oneof![non_finite(), -1e300..-1e-300f64],
    ) {
        let c = BreakCriterion::force(10.0);
        let (c, name) = match field {
            0 => (BreakCriterion { force: v, ..c }, "force"),
            1 => (BreakCriterion { moment: v, ..c }, "moment"),
            2 => (BreakCriterion { dissipated_energy: v, ..c }, "dissipated_energy"),
            3 => (BreakCriterion { force_exponent: v, ..c }, "force_exponent"),
            _ => (BreakCriterion { moment_exponent: v, ..c }, "moment_exponent"),
        };
        let (w, mut set, ground, ball, _) = pendulum(spherical());
        let e = set
            .insert(KjointBuilder::new(spherical()).name("brk").break_when(c), ground, ball, &w.bodies)
            .unwrap_err();
        let want = format!("joint `brk`: break_criterion.{name}");
        prop_assert!(matches!(&e, SimError::InvalidArgument { field, .. } if *field == want), "{}", e);
    }

    #[test]
    fn planar_friction_out_of_range_is_refused_naming_its_field(
        field in 0usize..6,
        v in prop_oneof![non_finite(), -1e300..-1e-300f64],
    ) {
        let mut a = [0.3, 0.1, 0.0, 0.0, 0.0, 0.0];
        a[field] = v;
        let r = PlanarFriction::new(a[0], a[1], a[2], a[3], a[4], a[5]);
        // F_int and M_int may have any sign
        if v.is_finite() && (field == 2 || field == 3) {
            prop_assert!(r.is_ok());
        } else {
            let e = r.unwrap_err();
            let names = ["mu", "radius", "internal_force", "internal_moment", "stick_stiffness (Kf)", "stick_rotational_stiffness"];
            prop_assert!(e.to_string().contains(names[field]), "{}", e);
        }
    }

    #[test]
    fn joint_friction_out_of_range_is_refused_at_insert(
        field in 0usize..5,
        v in prop_oneof![non_finite(), -1e300..-1e-300f64],
    ) {
        let mut f = JointFriction { mu: 0.2, pin_radius: 0.01, ..Default::default() };
        let name = match field {
            0 => { f.mu = v; "mu" }
            1 => { f.pin_radius = v; "pin_radius" }
            2 => { f.length = v; "length" }
            3 => { f.thrust_radius = v; "thrust_radius" }
            _ => { f.stick_rotational_stiffness = v; "stick_rotational_stiffness" }
        };
        let (w, mut set, ground, ball, _) = pendulum(spherical());
        let e = set
            .insert(
                KjointBuilder::new(KjointProperty::new(JointType::Revolute)).name("jf").joint_friction(f),
                ground,
                ball,
                &w.bodies,
            )
            .unwrap_err();
        prop_assert!(matches!(&e, SimError::Connector { joint, .. } if joint == "jf"), "{}", e);
        prop_assert!(e.to_string().contains(name), "{}", e);
    }

    #[test]
    fn a_flex_joint_switch_time_not_finite_is_refused(t in non_finite()) {
        let bending = Curve::new([(-1.0, -1e5), (0.0, 0.0), (1.0, 1e5)]).unwrap();
        let law = FlexJointLaw::new(Some(bending), None, None);
        let (w, mut set, ground, ball, _) = pendulum(spherical());
        {
            let law = law.unwrap();
            let e = set
                .insert(
                    KjointBuilder::new(spherical()).name("flex").flex_joint(law).flex_joint_switch_time(t),
                    ground,
                    ball,
                    &w.bodies,
                )
                .unwrap_err();
            prop_assert!(e.to_string().contains("switch_time"), "{}", e);
        }
    }
}

// ---------------------------------------------------------------------------------------
// handles and sensors

#[test]
fn a_stale_joint_handle_finds_nothing_anywhere() {
    let (mut w, mut set, ground, ball, h) = pendulum(spherical());
    set.step(&mut w, 1.0 / 60.0).unwrap();
    assert!(set.remove(h).is_some());
    let h2 = set
        .insert(KjointBuilder::new(spherical()), ground, ball, &w.bodies)
        .unwrap();
    for stale in [
        h,
        KjointHandle::invalid(),
        KjointHandle::from_raw_parts(7, 0),
    ] {
        assert!(!set.contains(stale));
        assert!(set.get(stale).is_none() && set.get_mut(stale).is_none());
        assert!(set.remove(stale).is_none());
        assert!(set.stable_dt(stale, &w.bodies).is_none());
        let e = set.switch_flex_joint(stale).unwrap_err();
        assert!(
            matches!(&e, SimError::InvalidArgument { field, .. } if field == "joint handle"),
            "{e}"
        );
    }
    assert_eq!(set.len(), 1);
    set.step(&mut w, 1.0 / 60.0).unwrap();
    assert!(set.get(h2).unwrap().state().is_some());
}

#[test]
fn switch_flex_joint_on_a_joint_without_one_is_refused() {
    let (_, mut set, _, _, h) = pendulum(spherical());
    let e = set.switch_flex_joint(h).unwrap_err();
    assert!(
        matches!(&e, SimError::InvalidJoint { joint, .. } if joint == "hinge"),
        "{e}"
    );
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn a_sensor_threshold_out_of_range_is_refused_and_not_added(
        kind in 0usize..3,
        v in prop_oneof![non_finite(), -1e300..=0.0f64],
    ) {
        let (_, mut set, _, _, h) = pendulum(spherical());
        let c = match kind {
            0 => SensorCondition::Time(if v.is_finite() { f64::NAN } else { v }),
            1 => SensorCondition::DofPasses { joint: h, dof: Dof::Rx, value: if v.is_finite() { f64::INFINITY } else { v } },
            _ => SensorCondition::ForceReaches { joint: h, dof: Dof::Dx, value: v },
        };
        let e = set.add_sensor(3, c).unwrap_err();
        let want = if kind == 0 { "sensor 3: time" } else { "sensor 3: value" };
        prop_assert!(matches!(&e, SimError::InvalidArgument { field, .. } if field == want), "{}", e);
        prop_assert!(e.to_string().len() < 120, "{}", e);
        prop_assert!(!set.trigger_sensor(3), "a refused sensor was added");
    }
}

#[test]
fn a_sensor_on_a_joint_not_in_the_set_is_refused() {
    let (w, mut set, ground, ball, h) = pendulum(spherical());
    let other = set
        .insert(KjointBuilder::new(spherical()), ground, ball, &w.bodies)
        .unwrap();
    set.remove(other).unwrap();
    for joint in [other, KjointHandle::invalid()] {
        for c in [
            SensorCondition::DofPasses {
                joint,
                dof: Dof::Rx,
                value: 0.1,
            },
            SensorCondition::ForceReaches {
                joint,
                dof: Dof::Dx,
                value: 10.0,
            },
        ] {
            let e = set.add_sensor(1, c).unwrap_err();
            assert!(
                matches!(&e, SimError::InvalidArgument { field, .. } if field == "sensor 1: joint"),
                "{e}"
            );
            assert!(!set.trigger_sensor(1));
        }
    }
    set.add_sensor(
        1,
        SensorCondition::DofPasses {
            joint: h,
            dof: Dof::Rx,
            value: 0.1,
        },
    )
    .unwrap();
}

// ---------------------------------------------------------------------------------------
// bodies removed from rapier under the joints

#[test]
fn removing_both_bodies_of_a_joint_and_stepping_is_clean() {
    let (mut w, mut set, ground, ball, h) =
        pendulum(spherical().with_dof(Dof::Rx, DofLaw::spring(5.0)));
    let ball2 = common::ball(&mut w, 1.0, 0.1, Vector::new(0.0, -2.0, 0.0));
    let h2 = set
        .insert(
            KjointBuilder::new(spherical()).local_anchor2(Vector::new(0.0, 1.0, 0.0)),
            ball,
            ball2,
            &w.bodies,
        )
        .unwrap();
    set.step(&mut w, 1.0 / 60.0).unwrap();
    w.remove_body(ball);
    set.step(&mut w, 1.0 / 60.0).unwrap();
    assert!(set.get(h).is_none() && set.get(h2).is_none() && set.is_empty());
    // the empty set keeps stepping, and takes new joints on the bodies left
    w.remove_body(ball2);
    set.step(&mut w, 1.0 / 60.0).unwrap();
    let b = common::ball(&mut w, 1.0, 0.1, Vector::new(0.0, -1.0, 0.0));
    set.insert(KjointBuilder::new(spherical()), ground, b, &w.bodies)
        .unwrap();
    set.step(&mut w, 1.0 / 60.0).unwrap();
}

#[test]
fn a_body_removed_between_apply_substep_calls_is_clean() {
    let (mut w, mut set, _, ball, h) = pendulum(spherical());
    set.prepare(&mut w);
    set.apply_substep(&mut w.bodies, w.gravity, 1.0 / 240.0)
        .unwrap();
    w.remove_body(ball);
    set.apply_substep(&mut w.bodies, w.gravity, 1.0 / 240.0)
        .unwrap();
    assert!(set.get(h).is_none());
    // the Radioss start kick and the body check read only the bodies left
    set.radioss_start_kick(&mut w.bodies, w.gravity, 1.0 / 240.0)
        .unwrap();
    set.check_bodies(&w.bodies).unwrap();
}

#[test]
fn a_body_switched_to_fixed_under_a_joint_is_clean() {
    let (mut w, mut set, _, ball, _) = pendulum(spherical());
    set.step(&mut w, 1.0 / 60.0).unwrap();
    w.bodies[ball].set_body_type(RigidBodyType::Fixed, true);
    let r = set.step(&mut w, 1.0 / 60.0);
    failed_cleanly(&w, &set, r);
}

#[test]
fn a_property_changed_to_name_a_missing_sensor_fails_at_the_next_step() {
    let (mut w, mut set, _, _, h) = pendulum(spherical());
    set.step(&mut w, 1.0 / 60.0).unwrap();
    set.get_mut(h)
        .unwrap()
        .set_property(spherical().with_sensor(9))
        .unwrap();
    let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
    assert!(
        matches!(&e, SimError::UnknownSensor { joint, sensor: 9 } if joint == "hinge"),
        "{e}"
    );
    set.add_sensor(9, SensorCondition::Manual).unwrap();
    set.step(&mut w, 1.0 / 60.0).unwrap();
}

#[test]
fn the_readers_of_a_set_whose_bodies_left_the_world_do_not_panic() {
    let (mut w, mut set, _, ball, h) = pendulum(spherical());
    // before any step, and after the body is gone
    assert!(set.joint_loads(&w.bodies).contains_key(&h));
    assert_eq!(set.island_count(), 0);
    assert!(set.loop_joints().is_empty());
    set.check_bodies(&w.bodies).unwrap();
    set.step(&mut w, 1.0 / 60.0).unwrap();
    w.remove_body(ball);
    assert_eq!(set.joint_loads(&w.bodies).get(&h), Some(&None));
    assert!(set.stable_dt(h, &w.bodies).is_none());
    set.check_bodies(&w.bodies).unwrap();
    let _ = set.island_count();
    set.step(&mut w, 1.0 / 60.0).unwrap();
    assert!(set.is_empty());
}

#[test]
fn apply_substep_without_prepare_fails_naming_the_joint_or_runs() {
    let (mut w, mut set, _, _, _) = pendulum(spherical());
    let r = set.apply_substep(&mut w.bodies, w.gravity, 1.0 / 240.0);
    failed_cleanly(&w, &set, r);
    let mut s = *set.settings();
    s.radioss_start = true;
    set.set_settings(s);
    set.radioss_start_kick(&mut w.bodies, w.gravity, 1.0 / 240.0)
        .unwrap();
    assert!(bodies_finite(&w));
}

/// What a `step_with` hook does to the set or the world in the middle of a step.
#[derive(Debug, Clone, Copy)]
enum HookMisuse {
    RemoveJoint,
    InsertJoint,
    RemoveBody,
    MakeBodyFixed,
    ZeroSubsteps,
    NestedStep,
    NewProperty,
    TimeBack,
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..config() })]

    #[test]
    fn a_step_with_hook_that_changes_the_set_or_the_world_does_not_panic(
        misuse in prop_oneof![
            Just(HookMisuse::RemoveJoint),
            Just(HookMisuse::InsertJoint),
            Just(HookMisuse::RemoveBody),
            Just(HookMisuse::MakeBodyFixed),
            Just(HookMisuse::ZeroSubsteps),
            Just(HookMisuse::NestedStep),
            Just(HookMisuse::NewProperty),
            Just(HookMisuse::TimeBack),
        ],
        after in any::<bool>(),
        at in 0usize..4,
    ) {
        let (mut w, mut set, ground, ball, h) = pendulum(spherical().with_kn(1e4));
        let ball2 = common::ball(&mut w, 1.0, 0.1, Vector::new(0.0, -2.0, 0.0));
        set.insert(
            KjointBuilder::new(spherical()).name("hinge2").local_anchor2(Vector::new(0.0, 1.0, 0.0)),
            ball,
            ball2,
            &w.bodies,
        )
        .unwrap();
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let mut calls = 0;
        let r = set.step_with(&mut w, 1.0 / 60.0, |phase, world, joints| {
            let here = (phase == rapier_kjoint::SubstepPhase::After) == after;
            if here {
                calls += 1;
            }
            if !(here && calls == at + 1) {
                return Ok::<(), SimError>(());
            }
            match misuse {
                HookMisuse::RemoveJoint => {
                    joints.remove(h);
                }
                HookMisuse::InsertJoint => {
                    let b = common::ball(world, 1.0, 0.1, Vector::new(1.0, 0.0, 0.0));
                    joints.insert(KjointBuilder::new(spherical()), ground, b, &world.bodies)?;
                }
                HookMisuse::RemoveBody => {
                    world.remove_body(ball);
                }
                HookMisuse::MakeBodyFixed => {
                    world.bodies[ball2].set_body_type(RigidBodyType::Fixed, true);
                }
                HookMisuse::ZeroSubsteps => {
                    joints.set_settings(SubstepSettings { substeps: 0, ..Default::default() });
                }
                HookMisuse::NestedStep => {
                    let _ = joints.step(world, 1.0 / 120.0);
                }
                HookMisuse::NewProperty => {
                    joints.get_mut(h).unwrap().set_property(spherical().with_kn(1e6))?;
                }
                HookMisuse::TimeBack => {
                    // refused: the time stays
                    let t = joints.time();
                    let e = joints.advance_time(-1.0).unwrap_err();
                    assert!(matches!(&e, SimError::InvalidArgument { field, .. } if field == "h"), "{e}");
                    assert_eq!(joints.time(), t);
                }
            }
            Ok(())
        });
        match r {
            Ok(()) => prop_assert!(bodies_finite(&w)),
            Err(e) => prop_assert!(e.to_string().contains("hinge"), "{:?}: {}", misuse, e),
        }
        // the set keeps working after it
        set.set_settings(SubstepSettings::default());
        let r = set.step(&mut w, 1.0 / 60.0);
        prop_assert!(r.is_ok(), "{:?}: {:?}", misuse, r);
    }
}

#[test]
fn a_hook_error_stops_the_step_and_the_set_keeps_working() {
    #[derive(Debug)]
    struct Stop;
    impl From<SimError> for Stop {
        fn from(_: SimError) -> Self {
            Stop
        }
    }
    let (mut w, mut set, _, ball, h) = pendulum(spherical().with_dof(Dof::Rx, DofLaw::spring(5.0)));
    set.step(&mut w, 1.0 / 60.0).unwrap();
    let t0 = set.time();
    let mut n = 0;
    let r = set.step_with(&mut w, 1.0 / 60.0, |phase, _, _| {
        n += 1;
        if phase == rapier_kjoint::SubstepPhase::Before && n > 3 {
            return Err(Stop);
        }
        Ok(())
    });
    assert!(r.is_err());
    // (calls: before, after, before, after, before) two substeps of four ran: the time
    // says so, the readout is of a substep that ran
    assert!(
        (set.time() - (t0 + 2.0 / 240.0)).abs() < 1e-12,
        "{}",
        set.time()
    );
    let s = set.get(h).unwrap().state().unwrap();
    assert!(s.time <= set.time() && s.q.0.iter().all(|v| v.is_finite()));
    set.step(&mut w, 1.0 / 60.0).unwrap();
    assert!(bodies_finite(&w) && w.bodies[ball].translation().is_finite());
}

// ---------------------------------------------------------------------------------------
// robot loader options

const ARM: &str = r#"<robot name="arm">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0.5 0 0"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="elbow" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"#;

proptest! {
    #![proptest_config(config())]

    #[test]
    fn urdf_options_out_of_range_are_refused_naming_the_field(
        field in 0usize..4,
        v in prop_oneof![non_finite(), -1e300..-1e-300f64, 1.0000001..1e300f64],
    ) {
        use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
        let mut o = UrdfOptions::default();
        let name = match field {
            0 => { o.kn = v; "kn" }
            1 => { o.critical_damping = v; "critical_damping" }
            2 => { o.substep = v; "substep" }
            _ => { o.min_link_mass = if v > 0.0 && v.is_finite() { -v } else { v }; "min_link_mass" }
        };
        // a large finite value is fine for Kn and the substep (the mass was made negative)
        let accepted = v.is_finite() && v >= 0.0 && (field == 0 || field == 2);
        let r = UrdfRobot::from_str(ARM, "arm.urdf", ".", &o);
        if accepted {
            prop_assert!(r.is_ok(), "{}", r.err().unwrap());
        } else {
            let e = r.expect_err("refused").to_string();
            prop_assert!(e.contains(&format!("invalid {name} =")), "{}", e);
        }
    }

    #[test]
    fn a_urdf_joint_override_out_of_range_is_refused_naming_the_joint_and_field(
        field in 0usize..7,
        v in prop_oneof![non_finite(), -1e300..-1e-300f64],
    ) {
        use rapier_kjoint::io::urdf::{JointOverride, UrdfOptions, UrdfRobot};
        let mut ov = JointOverride::default();
        let name = match field {
            0 => { ov.kn = Some(v); "kn" }
            1 => { ov.critical_damping = Some(v); "critical_damping" }
            2 => { ov.stiffness = Some(if v.is_finite() { f64::NAN } else { v }); "stiffness" }
            3 => { ov.viscosity = Some(if v.is_finite() { f64::NAN } else { v }); "viscosity" }
            4 => { ov.friction = Some(v); "friction" }
            5 => { ov.friction_stiffness = Some(v); "friction_stiffness" }
            _ => { ov.stop_max = Some(v); "stop_max" }
        };
        let mut o = UrdfOptions::default();
        o.joints.insert("elbow".into(), ov);
        let (mut w, _) = common::world(G);
        let mut set = KjointSet::new();
        let r = UrdfRobot::from_str(ARM, "arm.urdf", ".", &o).and_then(|r| r.insert(&mut w, &mut set));
        let e = r.expect_err("refused").to_string();
        prop_assert!(e.contains("elbow") && e.contains(name), "{}", e);
        prop_assert!(set.is_empty());
    }

    #[test]
    fn a_rapier_motor_out_of_range_is_refused_naming_the_joint(
        field in 0usize..4,
        v in prop_oneof![non_finite(), -1e300..-1e-300f64],
    ) {
        use rapier_kjoint::io::urdf::{JointEngine, JointOverride, RapierMotor, UrdfOptions, UrdfRobot};
        let mut m = RapierMotor { target: 0.1, stiffness: 100.0, damping: 1.0, max_force: Some(10.0) };
        let name = match field {
            0 => { m.target = if v.is_finite() { f64::NAN } else { v }; "target" }
            1 => { m.stiffness = v; "stiffness" }
            2 => { m.damping = v; "damping" }
            _ => { m.max_force = Some(v); "max_force" }
        };
        let mut o = UrdfOptions::default();
        o.joints.insert("elbow".into(), JointOverride { engine: Some(JointEngine::Rapier), motor: Some(m), ..Default::default() });
        let (mut w, _) = common::world(G);
        let mut set = KjointSet::new();
        let r = UrdfRobot::from_str(ARM, "arm.urdf", ".", &o).and_then(|r| r.insert(&mut w, &mut set));
        let e = r.expect_err("refused").to_string();
        prop_assert!(e.contains("elbow") && e.contains(name), "{}", e);
    }
}

/// A frame whose substep is over a second is refused, as a scene refuses it: at 2.5 s
/// substeps the automatic stiffness, sized from the substep, let a pendulum's anchors part
/// by 4.4 m while every step returned `Ok`. A substep of exactly 1 s still steps, and its
/// automatic stiffness (16 N/m) cannot hold the pendulum: the step stops, once the
/// substep on which the anchors part beyond half the joint's size is complete, naming
/// the load the stiffness lets them part under.
#[test]
fn a_substep_over_a_second_is_refused_as_in_scenes() {
    let (mut w, mut set, _, ball, _) = pendulum(spherical());
    let pos = w.bodies[ball].translation();
    let e = set.step(&mut w, 10.0).unwrap_err();
    assert!(
        matches!(&e, SimError::InvalidArgument { field, .. } if field == "frame_dt"),
        "{e}"
    );
    assert!(e.to_string().contains("at most 1 s"), "{e}");
    assert_eq!(w.bodies[ball].translation(), pos);
    assert_eq!(set.time(), 0.0);
    match set.step(&mut w, 4.0) {
        Ok(()) => assert_eq!(set.time(), 4.0),
        Err(SimError::Unstable { time, reason }) => {
            assert!(
                reason.contains("automatic blocked stiffness") && reason.contains("more substeps"),
                "{reason}"
            );
            // stopped once a whole substep of 1 s was complete
            assert!(time >= 1.0 && time.fract() == 0.0, "{time}");
            let t = set.time();
            assert!(t >= time && t < 4.0 && t.fract() == 0.0, "{t}");
        }
        Err(e) => panic!("{e}"),
    }
}

// A body switched out of `dynamic` before the first step, and an absurd number of
// substeps (found by a user trial).

/// A 1 kg ball hanging 1 m below the ground on a revolute joint named `hinge`.
fn revolute_hinge() -> (PhysicsWorld, KjointSet, RigidBodyHandle) {
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81, 0.0),
        ..Default::default()
    };
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    let (ball, _) = w.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, -1.0, 0.0)),
        ColliderBuilder::ball(0.1).mass(1.0),
    );
    let mut set = KjointSet::new();
    set.insert(
        KjointBuilder::new(KjointProperty::new(JointType::Revolute))
            .name("hinge")
            .local_anchor2(Vector::new(0.0, 1.0, 0.0)),
        ground,
        ball,
        &w.bodies,
    )
    .unwrap();
    (w, set, ball)
}

/// A joint whose only dynamic body is switched to fixed or kinematic before the first step
/// acts on nothing, as rapier's joints between such bodies, with a notice saying why (the
/// 1 kg ball keeps its mass: it is not called massless); made dynamic again, it acts.
/// Before, the step failed ("neither body is dynamic"), and every later step with it: a
/// game that froze a vehicle froze its whole world (a game developer's trial,
/// 2026-12-04).
#[test]
fn a_body_switched_out_of_dynamic_before_the_first_step_leaves_its_joint_inert_with_a_notice() {
    for ty in [RigidBodyType::Fixed, RigidBodyType::KinematicPositionBased] {
        let (mut w, mut set, ball) = revolute_hinge();
        w.bodies[ball].set_body_type(ty, true);
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let h = set.find("hinge").unwrap();
        assert!(!set[h].is_enabled());
        let events = set.drain_events();
        let notice = events
            .iter()
            .find(|e| matches!(e.kind, KjointEventKind::NoDynamicBody))
            .unwrap_or_else(|| panic!("{events:?}"));
        let text = notice.to_string();
        assert!(
            notice.severity() == Severity::Notice
                && text.contains("joint hinge")
                && text.contains("neither body is dynamic")
                && !text.contains("no mass"),
            "{text}"
        );
        // made dynamic again, it acts: the ball hangs on it 1 m below the ground
        w.bodies[ball].set_body_type(RigidBodyType::Dynamic, true);
        for _ in 0..30 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        assert!(set[h].is_enabled());
        let y = w.bodies[ball].translation().y;
        assert!((y + 1.0).abs() < 1e-3, "ball at y = {y}");
        assert!(set
            .drain_events()
            .iter()
            .any(|e| matches!(e.kind, KjointEventKind::EnabledAgain)));
    }
}

/// A joint of the user's `Kn` takes a dynamic body without mass as infinitely heavy, as
/// rapier's joints do, and acts: a 1 kg bob hung 0.5 m below a massless anchor that is
/// pinned to the ground swings on it (it fell freely, both joints turned off, when every
/// joint on a massless body was: a review, 2026-12-05), with no `MasslessBody` warning.
#[test]
fn a_joint_of_the_users_kn_on_a_massless_body_acts() {
    let mut w = PhysicsWorld {
        gravity: G,
        ..Default::default()
    };
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    let anchor = w.insert_body(RigidBodyBuilder::dynamic());
    let bob = w.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.5, 0.0, 0.0))
            .additional_mass(1.0),
    );
    let mut set = KjointSet::new();
    let pin = |kn: f64| KjointBuilder::new(KjointProperty::new(JointType::Spherical).with_kn(kn));
    let a = set.insert(pin(1e5), ground, anchor, &w.bodies).unwrap();
    let b = set
        .insert(
            pin(1e5).local_anchor2(Vector::new(-0.5, 0.0, 0.0)),
            anchor,
            bob,
            &w.bodies,
        )
        .unwrap();
    for _ in 0..30 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    assert!(set[a].is_enabled() && set[b].is_enabled());
    assert!(
        !set.drain_events()
            .iter()
            .any(|e| matches!(e.kind, KjointEventKind::MasslessBody { .. })),
        "a MasslessBody event"
    );
    // on its 0.5 m rod: within a millimetre of it from the pivot (a free fall's 1.2 m
    // below in 0.5 s)
    let r = w.bodies[bob].translation().length();
    assert!((r - 0.5).abs() < 1e-3, "the bob {r} m from the pivot");
    assert!(w.bodies[anchor].translation().length() < 1e-3);
}

/// A body and its joint inserted by a `step_with` hook in the middle of a step: its mass
/// properties are derived before the set's next substep with it (rapier derives them in
/// its step), so that the joint acts from there, with no `MasslessBody` warning (it had
/// one, and acted on nothing for a substep: a review, 2026-12-05).
#[test]
fn a_body_inserted_by_a_hook_is_not_taken_for_massless() {
    let mut w = PhysicsWorld {
        gravity: G,
        ..Default::default()
    };
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    let mut set = KjointSet::new();
    let mut inserted = None;
    set.step_with(&mut w, 1.0 / 60.0, |phase, w, set| {
        if phase == rapier_kjoint::SubstepPhase::Before && inserted.is_none() && set.time() > 0.0 {
            let ball = w.insert_body(
                RigidBodyBuilder::dynamic()
                    .translation(Vector::new(0.0, -1.0, 0.0))
                    .additional_mass(1.0),
            );
            let joint = KjointBuilder::new(KjointProperty::new(JointType::Spherical))
                .local_anchor2(Vector::new(0.0, 1.0, 0.0));
            inserted = Some((ball, set.insert(joint, ground, ball, &w.bodies).unwrap()));
        }
        Ok::<(), SimError>(())
    })
    .unwrap();
    let (ball, h) = inserted.expect("inserted in the step");
    for _ in 0..30 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    assert!(set[h].is_enabled());
    let events = set.drain_events();
    assert!(
        !events
            .iter()
            .any(|e| matches!(e.kind, KjointEventKind::MasslessBody { .. })),
        "{events:?}"
    );
    let y = w.bodies[ball].translation().y;
    assert!((y + 1.0).abs() < 1e-3, "the ball at y = {y}");
}

/// A joint on a dynamic body without mass (no collider, no additional mass) is told of as
/// such, by a warning naming the body and the remedies, and acts on nothing: the step goes
/// on (it failed, "automatic stiffness is zero: a body has no mass", at every step).
#[test]
fn a_massless_body_is_still_called_massless() {
    let mut w = PhysicsWorld::default();
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    let b = w.insert_body(RigidBodyBuilder::dynamic());
    let mut set = KjointSet::new();
    let h = set
        .insert(
            KjointBuilder::new(KjointProperty::new(JointType::Revolute)).name("hinge"),
            ground,
            b,
            &w.bodies,
        )
        .unwrap();
    set.step(&mut w, 1.0 / 60.0).unwrap();
    assert!(!set[h].is_enabled());
    let events = set.drain_events();
    let warning = events
        .iter()
        .find(|e| matches!(e.kind, KjointEventKind::MasslessBody { body: 2 }))
        .unwrap_or_else(|| panic!("{events:?}"));
    let text = warning.to_string();
    assert_eq!(warning.severity(), Severity::Warning);
    assert!(
        text.contains("joint hinge") && text.contains("body 2") && text.contains("no mass"),
        "{text}"
    );
    // given a mass, the body is held by the joint again, at its anchor under gravity
    w.gravity = Vector::new(0.0, -9.81, 0.0);
    w.bodies[b].set_additional_mass(1.0, true);
    for _ in 0..60 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    assert!(set[h].is_enabled());
    let events = set.drain_events();
    assert!(
        events
            .iter()
            .any(|e| matches!(e.kind, KjointEventKind::EnabledAgain)),
        "{events:?}"
    );
    let y = w.bodies[b].translation().y;
    assert!(y.abs() < 1e-3, "the body {y} m below its hinge");
}

#[test]
fn more_substeps_than_a_scene_accepts_are_refused_not_run_for_ever() {
    let (mut w, mut set, ball) = revolute_hinge();
    let before = w.bodies[ball].translation();
    for n in [usize::MAX, rapier_kjoint::scene::MAX_SUBSTEPS + 1] {
        set.set_settings(SubstepSettings {
            substeps: n,
            ..Default::default()
        });
        let start = std::time::Instant::now();
        let e = set.step(&mut w, 1.0 / 60.0).unwrap_err();
        assert!(start.elapsed().as_secs_f64() < 1.0);
        assert!(
            matches!(&e, SimError::InvalidArgument { field, .. } if field == "SubstepSettings::substeps"),
            "{e}"
        );
        assert!(e.to_string().contains("100000"), "{e}");
        assert_eq!(w.bodies[ball].translation(), before);
    }
    set.set_settings(SubstepSettings {
        substeps: 16,
        ..Default::default()
    });
    set.step(&mut w, 1.0 / 60.0).unwrap();
}

/// A sensor that has fired cannot be replaced: `add_sensor` with its id reset it to off
/// while the joint it locked stayed locked (q frozen at 0.0978 rad, `sensor_active` false).
/// A sensor that has not fired can be.
#[test]
fn a_fired_sensor_is_not_replaced_under_its_locked_joint() {
    let mut w = PhysicsWorld {
        gravity: G,
        ..Default::default()
    };
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    let (ball, _) = w.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(1.0, 0.0, 0.0)),
        ColliderBuilder::ball(0.1).mass(1.0),
    );
    let mut set = KjointSet::new();
    let prop = KjointProperty::new(JointType::Revolute)
        .with_kn(1e6)
        .with_sensor(1);
    // hinge about z at the origin: the ball swings down from the horizontal
    let h = set
        .insert(
            KjointBuilder::new(prop)
                .local_anchor2(Vector::new(-1.0, 0.0, 0.0))
                .world_frame1(Rotation::from_rotation_y(
                    -std::f32::consts::FRAC_PI_2 as Real,
                )),
            ground,
            ball,
            &w.bodies,
        )
        .unwrap();
    // not fired yet: replaced
    set.add_sensor(1, SensorCondition::Time(50.0)).unwrap();
    set.add_sensor(1, SensorCondition::Time(0.1)).unwrap();
    for _ in 0..12 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    assert!(set.sensor_active(1));
    let held = set.get(h).unwrap().state().unwrap().q[3];
    assert!(held.abs() > 0.01, "the ball swung before the lock: {held}");
    let e = set.add_sensor(1, SensorCondition::Time(100.0)).unwrap_err();
    assert!(
        matches!(&e, SimError::InvalidArgument { field, .. } if field == "sensor 1"),
        "{e}"
    );
    assert!(e.to_string().contains("fired at t = 0.1"), "{e}");
    for _ in 0..30 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    let state = set.get(h).unwrap().state().unwrap();
    assert!(set.sensor_active(1) && state.locked, "{state:?}");
    assert!(
        (state.q[3] - held).abs() < 1e-3,
        "{} against {held}",
        state.q[3]
    );
}

/// `world_axis` of a zero or non-finite axis is refused naming `world_axis` and the axis as
/// given (it named `world_frame1 = Quat(NaN, NaN, NaN, NaN)`, a method the user never
/// called, then `world_axis (or world_frame1)` with that quaternion; user trials,
/// 2026-12-04).
#[test]
fn a_zero_world_axis_is_refused_naming_world_axis() {
    for (axis, given) in [
        (Vector::ZERO, "world_axis = [0, 0, 0]"),
        (Vector::new(Real::NAN, 0.0, 1.0), "world_axis = [NaN, 0, 1]"),
    ] {
        let (w, mut set, ground, ball, _) = pendulum(spherical());
        let b = KjointBuilder::new(spherical())
            .name("axis")
            .world_axis(axis);
        let e = set.insert(b, ground, ball, &w.bodies).unwrap_err();
        let text = e.to_string();
        assert!(
            matches!(&e, SimError::InvalidArgument { field, .. } if field.contains("world_axis")),
            "{text}"
        );
        assert!(
            text.contains(given) && text.contains("non-zero axis") && !text.contains("Quat"),
            "{text}"
        );
    }
}
