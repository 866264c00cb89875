//! A friction spring stiffer than the substep resolves holds its DOF to the friction force
//! when the DOF moves: a door turning at 3 rad/s on a hinge of `K_f` = 1e6 N·m/rad and a
//! friction moment of 5 N·m brakes at `M_f/I`, as Coulomb friction does (it took 2412 N·m
//! in the substep it started to move, and lost 11.5 J of its 19.2 J to `numerical`; a user
//! trial, 2026-12-04). `law::slip_prediction`.

mod common;
use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;

const MF: f64 = 5.0;

/// A 20 kg door (0.8 × 2 × 0.04 m) hinged at its edge about the world's y, no gravity,
/// turning at `omega` [rad/s] about its hinge, on a friction spring `kf` [N·m/rad], 8
/// substeps a frame. Its moment of inertia about the hinge.
fn door(kf: f64, omega: Real) -> (PhysicsWorld, KjointSet, KjointHandle, RigidBodyHandle, f64) {
    let (mut w, ground) = common::world(Vector::ZERO);
    let (door, _) = w.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.4, 1.0, 0.0))
            .angvel(Vector::new(0.0, omega, 0.0))
            .linvel(Vector::new(0.0, 0.0, -0.4 * omega)),
        ColliderBuilder::cuboid(0.4, 1.0, 0.02).mass(20.0),
    );
    let i_hinge = 20.0 * (0.8f64.powi(2) + 0.04f64.powi(2)) / 12.0 + 20.0 * 0.4 * 0.4;
    let hinge = KjointProperty::new(JointType::Revolute)
        .with_dof(Dof::Rx, DofLaw::default().with_friction(kf, MF));
    let mut set = common::joints(8);
    let h = set
        .insert(
            KjointBuilder::new(hinge)
                .world_axis(Vector::Y)
                .local_anchor1(Vector::new(0.0, 1.0, 0.0))
                .local_anchor2(Vector::new(-0.4, 0.0, 0.0))
                .contacts_enabled(false),
            ground,
            door,
            &w.bodies,
        )
        .unwrap();
    (w, set, h, door, i_hinge)
}

#[test]
fn a_door_turning_on_a_stiff_friction_hinge_brakes_at_the_friction_moment() {
    let (mut w, mut set, h, door, i) = door(1e6, 3.0);
    let mut applied = Vec::new();
    for _ in 0..30 {
        set.step_with(&mut w, 1.0 / 60.0, |phase, _, set| {
            if phase == SubstepPhase::After {
                applied.push(set.get(h).unwrap().state().unwrap().applied[Dof::Rx]);
            }
            Ok::<(), SimError>(())
        })
        .unwrap();
    }
    // every substep transmits the friction moment, none more (2412 N·m before)
    let worst = applied.iter().fold(0.0f64, |a, m| a.max(m.abs()));
    assert!(worst <= MF * (1.0 + 1e-9), "transmitted {worst} N·m");
    assert!(applied.iter().all(|m| (m - MF).abs() < 1e-6), "{applied:?}");
    // ω(t) = ω0 − M_f·t/I over the half second (2.415 rad/s)
    let omega = w.bodies[door].angvel().y as f64;
    let expect = 3.0 - MF * 0.5 / i;
    assert!(
        (omega - expect).abs() < 2e-3 * expect,
        "ω {omega} rad/s, expected {expect}"
    );
    // the kinetic energy lost is the friction's work, M_f·Δθ; nothing to `numerical`
    let e = set.get(h).unwrap().closed_energy(&w.bodies);
    // (the door's angle at the end of the run: the readout's `q` is the last substep's start)
    let theta = w.bodies[door].rotation().to_scaled_axis().y as f64;
    assert!(
        (e.friction - MF * theta).abs() < 2e-3 * MF * theta,
        "friction {} J, M_f·θ {} J",
        e.friction,
        MF * theta
    );
    let lost = 0.5 * i * (9.0 - omega * omega);
    assert!(
        (lost - e.friction).abs() < 5e-3 * lost,
        "kinetic energy lost {lost} J, friction {} J",
        e.friction
    );
    assert!(
        e.numerical.abs() < 1e-3 * lost,
        "numerical {} J",
        e.numerical
    );
}

/// Below its friction moment the stiff spring holds the door: a 2 N·m torque on it, at rest,
/// turns it by the spring's `M/K_f` only (no slip predicted where the spring holds). (Half
/// the friction moment: a load applied at once overshoots its static moment up to twice;
/// at 4 N·m the f64 build slipped 0.1 µrad at the onset, as friction would.)
#[test]
fn a_stiff_friction_hinge_holds_a_load_below_its_friction_moment() {
    let (mut w, mut set, h, door, _) = door(1e6, 0.0);
    for _ in 0..60 {
        w.bodies[door].reset_torques(false);
        w.bodies[door].add_torque(Vector::new(0.0, 2.0, 0.0), true);
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let s = set.get(h).unwrap().state().unwrap();
        assert_eq!(s.status[Dof::Rx].friction, FrictionStatus::Stick);
    }
    let s = set.get(h).unwrap().state().unwrap();
    assert!(
        s.q[Dof::Rx].abs() < 2.0 * 2.0 / 1e6,
        "turned {} rad",
        s.q[Dof::Rx]
    );
    let e = set.get(h).unwrap().closed_energy(&w.bodies);
    assert_eq!(e.friction, 0.0, "no slip work");
}

/// The door set turning later, at rest before (a game's `set_angvel`), brakes the same way.
#[test]
fn a_door_set_turning_after_a_rest_brakes_at_the_friction_moment() {
    let (mut w, mut set, h, door, i) = door(1e6, 0.0);
    for _ in 0..30 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    let b = &mut w.bodies[door];
    b.set_angvel(Vector::new(0.0, 3.0, 0.0), true);
    b.set_linvel(Vector::new(0.0, 0.0, -1.2), true);
    set.step(&mut w, 1.0 / 60.0).unwrap();
    let omega = w.bodies[door].angvel().y as f64;
    let expect = 3.0 - MF / 60.0 / i;
    assert!(
        (omega - expect).abs() < 1e-4 * expect,
        "ω {omega} rad/s after a frame, expected {expect}"
    );
    let s = set.get(h).unwrap().state().unwrap();
    assert!(
        (s.applied[Dof::Rx] - MF).abs() < 1e-6,
        "{}",
        s.applied[Dof::Rx]
    );
}
