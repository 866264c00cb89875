//! The sensor lock in a running world (docs/kjoint2.md §4.5): from its activation a locked
//! joint carries the force it carried then, held constant, plus the lock spring `K_b·(q − q_s)`.
//! What a user looks at: the joint stays where it was, the readout keeps the held force, the
//! moment it transmits balances the loads, and the stored energy goes on without a jump.

mod common;
use rapier_kjoint::dynamics::{KjointEventKind, SensorCause};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, DofLaw, JointType, KjointProperty, KjointSet, SensorCondition};

/// The hinge spring [N·m/rad]; `Kn` = 1e4 N/m gives `KR = Kn·ScF` = 1e5 N·m/rad (L0 = 0).
const K: f64 = 100.0;
const KR: f64 = 1e5;

/// A 1 kg rod of 1 m hinged at its end to the ground about world z, horizontal along +x under
/// gravity −y: the spring K with a viscosity of 5 N·m·s/rad holds it at θ ≈ −m·g·(L/2)/K =
/// −0.049 rad. Sensor 3 locks the hinge at t = 1.5 s, when it has settled; from t = 1.75 s a
/// load of 10 N pulls the tip down (10 N·m more about the hinge).
#[test]
fn a_locked_hinge_holds_its_angle_and_the_force_it_carried() {
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    let (rod, _) = w.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.5, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.01, 0.01).mass(1.0),
    );
    let mut set = KjointSet::new();
    let hinge = set
        .insert(
            common::rod_end_hinge_about_z(
                KjointProperty::new(JointType::Revolute)
                    .with_kn(1e4)
                    .with_sensor(3)
                    .with_dof(Dof::Rx, DofLaw::spring(K).with_viscosity(5.0)),
            ),
            ground,
            rod,
            &w.bodies,
        )
        .unwrap();
    set.add_sensor(3, SensorCondition::Time(1.5)).unwrap();

    let frame = 1.0 / 60.0;
    let mut before = None;
    let mut at_lock = None;
    // the last second's transmitted moment and angle, averaged: the lock rings at its own
    // frequency (√(KR/I) = 548 rad/s, past what the substep resolves), seen at the frames
    let (mut applied, mut angle, mut samples) = (0.0, 0.0, 0.0);
    for n in 0..240 {
        if n == 105 {
            // 10 N down at the tip: the force at the centre and its moment 0.5 m × 10 N
            let b = &mut w.bodies[rod];
            b.add_force(Vector::new(0.0, -10.0, 0.0), true);
            b.add_torque(Vector::new(0.0, 0.0, -5.0), true);
        }
        set.step(&mut w, frame).unwrap();
        let s = set.get(hinge).unwrap().state().unwrap().clone();
        if n >= 180 {
            applied += s.applied[Dof::Rx] / 60.0;
            angle += s.q[Dof::Rx] / 60.0;
            samples += 1.0;
        }
        if s.locked && at_lock.is_none() {
            at_lock = Some(s.clone());
        } else if !s.locked {
            before = Some(s.clone());
        }
    }
    let (before, at) = (before.unwrap(), at_lock.unwrap());
    let joint = set.get(hinge).unwrap();
    let s = joint.state().unwrap();
    let lock = joint.sensor_lock().expect("the sensor fired");
    let theta_s = lock.values[Dof::Rx.index()];
    assert!((theta_s - at.q[Dof::Rx]).abs() < 1e-3, "θs = {theta_s}");
    // settled before the lock, on the spring alone
    let m_gravity = 9.81 * 0.5 * theta_s.cos();
    assert!(
        (K * theta_s.abs() - m_gravity).abs() < 0.01 * m_gravity,
        "θs = {theta_s}"
    );
    // the lock does not jump: force and stored energy as in the frame before
    assert!(
        (at.force[Dof::Rx] - before.force[Dof::Rx]).abs() < 1e-3,
        "{at:?}"
    );
    assert!(
        (at.energy.elastic - before.energy.elastic).abs() < 1e-3 * before.energy.elastic.abs(),
        "stored energy {} → {}",
        before.energy.elastic,
        at.energy.elastic
    );

    // two seconds later, under the extra 10 N·m: the hinge has moved by ΔM/KR only (the
    // spring alone would have let it turn by 0.1 rad)
    assert_eq!(samples, 60.0);
    let theta = angle;
    let moved = theta - theta_s;
    assert!(s.locked);
    assert!(
        (moved.abs() - 10.0 * theta.cos() / KR).abs() < 0.1e-4,
        "moved {moved} rad"
    );
    // the readout holds the spring's force of the activation: K·θs, not K·θ
    assert_eq!(s.parts[Dof::Rx].elastic, at.parts[Dof::Rx].elastic);
    assert_eq!(s.parts[Dof::Rx].elastic, K * theta_s);
    assert_eq!(lock.held[Dof::Rx.index()].elastic, K * theta_s);
    // the lock's own part: KR·(θ − θs) at the last frame
    let last = s.q[Dof::Rx] - theta_s;
    assert!((s.parts[Dof::Rx].sensor - KR * last).abs() < 1e-6 * KR * last.abs() + 1e-9);
    // the moment transmitted balances gravity and the load: (4.905 + 10)·cos θ N·m
    let load = (9.81 * 0.5 + 10.0) * theta.cos();
    assert!(
        (applied.abs() - load).abs() < 0.01 * load,
        "transmitted {applied} N·m against {load}"
    );
    // stored energy: ½·K·θs² held, plus K·θs·e + ½·KR·e² on the rotation, plus what the
    // blocked DOFs store, between nothing and the law's ½·K_b·q² (the readout books the
    // stiffness the update realises)
    let rotation = 0.5 * K * theta_s * theta_s + K * theta_s * last + 0.5 * KR * last * last;
    let blocked: f64 = [Dof::Dx, Dof::Dy, Dof::Dz, Dof::Ry, Dof::Rz]
        .into_iter()
        .map(|d| 0.5 * if d.is_rotation() { KR } else { 1e4 } * s.q[d] * s.q[d])
        .sum();
    let e = s.energy.elastic;
    assert!(
        e > rotation - 1e-6 && e < rotation + blocked + 1e-6,
        "stored {e} against {rotation} + [0, {blocked}]"
    );
}

/// A lock engaging on a stop stiffer than the substep resolves moves no energy: a 1 kg rod
/// of 1 m hinged at its end (no gravity), pressed into its stop at 0.1 rad by 1000 N·m
/// (stop stiffness `KR` = 1e5 N·m/rad, `ω·h` = 2.3: the update realises 36 % of it), locked
/// at t = 1.5 s. The stored energy and `E_numerical`, averaged over the half second before
/// and after the lock, stay as they were. The energy book scaled the held energy with the
/// DOF's tangent stiffness including the lock's (`K_t + K_b`): a quarter joule of the 0.70 J
/// stored went from the stored energy into `E_numerical` at the lock (0.45 J stored after it).
#[test]
fn a_lock_on_an_unresolved_stop_moves_no_energy() {
    let (mut w, ground) = common::world(Vector::ZERO);
    let (rod, _) = w.insert(
        RigidBodyBuilder::dynamic()
            .can_sleep(false)
            .translation(Vector::new(0.5, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.01, 0.01).mass(1.0),
    );
    let mut set = KjointSet::new();
    let hinge = set
        .insert(
            common::rod_end_hinge_about_z(
                KjointProperty::new(JointType::Revolute)
                    .with_kn(1e4)
                    .with_sensor(3)
                    .with_dof(Dof::Rx, DofLaw::spring(10.0).with_stops(-1.0, 0.1)),
            ),
            ground,
            rod,
            &w.bodies,
        )
        .unwrap();
    set.add_sensor(3, SensorCondition::Time(1.5)).unwrap();
    // (stored, numerical) summed over the frames before and after the lock
    let mut sums = [[0.0; 2]; 2];
    for n in 0..120 {
        let b = &mut w.bodies[rod];
        b.reset_torques(true);
        b.add_torque(Vector::new(0.0, 0.0, 1000.0), true);
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let s = set.get(hinge).unwrap().state().unwrap();
        assert_eq!(s.locked, n >= 90, "frame {n}");
        if n >= 60 {
            let half = &mut sums[usize::from(s.locked)];
            half[0] += s.energy.elastic / 30.0;
            half[1] += s.energy.numerical / 30.0;
        }
    }
    let [[stored0, numerical0], [stored1, numerical1]] = sums;
    assert!(stored0 > 0.5, "stored {stored0} J");
    assert!(
        (stored1 - stored0).abs() < 0.1 * stored0,
        "stored {stored0} J before the lock, {stored1} J after"
    );
    assert!(
        // (the frames sample the ringing of the unresolved stop: ±0.05 J from frame to frame)
        (numerical1 - numerical0).abs() < 0.1,
        "numerical {numerical0} J before the lock, {numerical1} J after"
    );
}

/// A force sensor reads the force the joint transmits (docs/kjoint2.md §4.5): a 1 kg rod at
/// rest hanging from a spherical joint at `Kn` = 1e12 N/m, stiffer than the substep resolves,
/// whose law force `K·q` is a product of a separation near f32 resolution while the joint
/// carries the rod's weight, 9.81 N on `dy`. A sensor at 9 N fires in the first frame and
/// reports the weight; one at 11 N never fires.
#[test]
fn a_force_sensor_reads_the_load_a_stiff_pin_carries() {
    let prop = KjointProperty::new(JointType::Spherical).with_kn(1e12);
    let (mut w, mut set, pin) = common::hanging_rod(prop);
    for (id, value) in [(1, 9.0), (2, 11.0)] {
        let watch = SensorCondition::ForceReaches {
            joint: pin,
            dof: Dof::Dy,
            value,
        };
        set.add_sensor(id, watch).unwrap();
    }
    let mut fired = Vec::new();
    let mut law_dy = Vec::new();
    for _ in 0..60 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        law_dy.push(set.get(pin).unwrap().state().unwrap().force[Dof::Dy]);
        for e in set.drain_events() {
            if let KjointEventKind::SensorActivated {
                cause: SensorCause::ForceReached { measured, .. },
            } = e.kind
            {
                fired.push((e.sensor(), e.time, measured));
                // the threshold with its unit
                assert!(e.to_string().ends_with("dy force reached 9 N"), "{e}");
            }
        }
    }
    let law_peak = law_dy.iter().fold(0.0f64, |m, f| m.max(f.abs()));
    println!("fired {fired:?}; law force on dy: peak |K·q| {law_peak} N");
    assert_eq!(fired.len(), 1, "{fired:?}");
    let (sensor, time, measured) = fired[0];
    assert_eq!(sensor, Some(1));
    assert!(time < 1.0 / 60.0, "fired at {time} s");
    assert!((measured.abs() - 9.81).abs() < 0.02 * 9.81, "{measured} N");
    assert!(set.sensor_active(1) && !set.sensor_active(2));
}

/// A sensor waiting on a joint that leaves the set can never see its condition: the user is
/// told, once, naming the sensor and the joint, when the joint breaks or is removed; a
/// sensor that fired already is not warned about.
#[test]
fn a_sensor_whose_joint_breaks_or_is_removed_says_it_will_not_fire() {
    use rapier_kjoint::dynamics::{EventSource, Severity};
    use rapier_kjoint::law::BreakCriterion;
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    let mut set = common::joints(4);
    // two 1 kg rods hanging from pins: the first pin breaks at 5 N (it carries 9.81 N)
    let rod_on_pin = |w: &mut PhysicsWorld, set: &mut KjointSet, x: Real, name: &str, limit| {
        let rod = common::cuboid(
            w,
            1.0,
            Vector::new(0.02, 0.5, 0.02),
            Vector::new(x, -0.5, 0.0),
        );
        let prop = KjointProperty::new(JointType::Spherical).with_kn(1e8);
        common::add(set, w, prop, ground, rod, |b| {
            let b = b
                .local_anchor1(Vector::new(x, 0.0, 0.0))
                .local_anchor2(Vector::new(0.0, 0.5, 0.0))
                .name(name);
            match limit {
                Some(f) => b.break_when(BreakCriterion::force(f)),
                None => b,
            }
        })
    };
    let weak = rod_on_pin(&mut w, &mut set, 0.0, "weak", Some(5.0));
    let kept = rod_on_pin(&mut w, &mut set, 2.0, "kept", None);
    let removed = rod_on_pin(&mut w, &mut set, 4.0, "removed", None);
    let on = |joint| SensorCondition::ForceReaches {
        joint,
        dof: Dof::Dy,
        value: 50.0,
    };
    set.add_sensor(1, on(weak)).unwrap();
    set.add_sensor(2, on(removed)).unwrap();
    set.add_sensor(3, on(kept)).unwrap();
    // sensor 4 watches the removed joint too, but has fired already
    set.add_sensor(4, on(removed)).unwrap();
    set.trigger_sensor(4);
    set.step(&mut w, 1.0 / 60.0).unwrap();
    assert!(!set.contains(weak), "the weak pin did not break");
    set.remove(removed).unwrap();
    for _ in 0..10 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    let events = set.drain_events();
    // the warning follows the event of the removal it is about
    let at = |f: &dyn Fn(&KjointEventKind) -> bool| events.iter().position(|e| f(&e.kind));
    let broke = at(&|k| matches!(k, KjointEventKind::JointBroke { .. })).unwrap();
    let first_warning = at(&|k| matches!(k, KjointEventKind::SensorJointRemoved { .. })).unwrap();
    assert_eq!(first_warning, broke + 1, "{events:?}");
    let warned: Vec<_> = events
        .into_iter()
        .filter(|e| matches!(e.kind, KjointEventKind::SensorJointRemoved { .. }))
        .collect();
    let seen: Vec<_> = warned
        .iter()
        .map(|e| (e.source.clone(), e.to_string()))
        .collect();
    assert_eq!(warned.len(), 2, "{seen:?}");
    assert_eq!(warned[0].source, EventSource::Sensor(1));
    assert_eq!(warned[1].source, EventSource::Sensor(2));
    assert!(warned.iter().all(|e| e.severity() == Severity::Warning));
    assert_eq!(
        warned[0].kind,
        KjointEventKind::SensorJointRemoved {
            joint: weak,
            joint_name: "weak".into()
        }
    );
    assert!(
        warned[1].to_string().starts_with(
            "warning: sensor 2 at t = 0.016667 s: joint `removed`, whose DOF it watches, was \
             removed: it will not fire"
        ),
        "{}",
        warned[1]
    );
    assert!(!set.sensor_active(1) && !set.sensor_active(2) && !set.sensor_active(3));
}

/// A lock that stops a swinging rod transmits the momentum it removes, whatever the substep
/// (the README's "Decisions": a lock on the automatic stiffness is a rigid stop the substep
/// does not resolve, so its peak moment spreads over a substep and reads `≈ I·ω₀/h`-like
/// values that depend on the substep, while its impulse does not). A 1 kg rod of 1 m
/// hinged at its end about world z (no gravity, no spring: the hinge's free rotation carries
/// no moment before the lock) turns at ω₀ = 2 rad/s; sensor 1 locks it at t = 0.1 s. The
/// moment about the hinge is the only moment about that fixed point, so
/// `∫ M_x dt = I_O·(ω₀ − ω)` with `I_O = m·(L² + t²)/12 + m·(L/2)² = 0.33337 kg·m²` (the
/// cuboid's 1 m × 2 cm section) and ω the rod's spin at the end (0.3 s), at 4, 16 and 64
/// substeps: the transmitted moment the readout reports is the one that stopped the rod.
#[test]
fn a_lock_stopping_a_swinging_rod_transmits_the_momentum_it_removes() {
    use rapier_kjoint::SubstepPhase;
    let omega0 = 2.0;
    let i_o = (1.0 + 0.02 * 0.02) / 12.0 + 0.25;
    let mut peaks = Vec::new();
    for substeps in [4, 16, 64] {
        let (mut w, ground) = common::world(Vector::ZERO);
        let (rod, _) = w.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.5, 0.0, 0.0))
                .linvel(Vector::new(0.0, omega0 as Real * 0.5, 0.0))
                .angvel(Vector::new(0.0, 0.0, omega0 as Real))
                .can_sleep(false),
            ColliderBuilder::cuboid(0.5, 0.01, 0.01).mass(1.0),
        );
        let mut set = common::joints(substeps);
        let hinge = set
            .insert(
                common::rod_end_hinge_about_z(
                    KjointProperty::new(JointType::Revolute).with_sensor(1),
                ),
                ground,
                rod,
                &w.bodies,
            )
            .unwrap();
        set.add_sensor(1, SensorCondition::Time(0.1)).unwrap();
        let h = 1.0 / 60.0 / substeps as f64;
        let (mut impulse, mut peak) = (0.0_f64, 0.0_f64);
        for _ in 0..18 {
            set.step_with(&mut w, 1.0 / 60.0, |phase, _, set: &mut KjointSet| {
                if phase == SubstepPhase::After {
                    let m = set.get(hinge).unwrap().state().unwrap().applied[Dof::Rx];
                    impulse += m * h;
                    peak = peak.max(m.abs());
                }
                Ok::<(), rapier_kjoint::SimError>(())
            })
            .unwrap();
        }
        assert!(set.get(hinge).unwrap().state().unwrap().locked);
        // the rod stopped: rigidly where the lock is unresolved, with a rebound of a few per
        // cent where the substep resolves the lock spring (64 substeps: ω·h = 0.26)
        let spin = w.bodies[rod].angvel().z as f64;
        assert!(
            spin.abs() < 0.05 * omega0,
            "{substeps} substeps: ω = {spin}"
        );
        let removed = i_o * (omega0 - spin);
        assert!(
            (impulse - removed).abs() < 0.01 * i_o * omega0,
            "{substeps} substeps: ∫M dt = {impulse} N·m·s against I·(ω₀ − ω) = {removed}"
        );
        peaks.push(peak);
    }
    // the peak is the substep's: 109, 301 and 547 N·m at 4, 16 and 64 substeps (measured
    // 2026-12-04), growing with the substep count as long as the lock is unresolved
    assert!(
        peaks[0] < peaks[1] && peaks[1] < peaks[2],
        "peaks {peaks:?}"
    );
}
