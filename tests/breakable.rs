//! Breakable joints (docs/breakable.md): a joint under a ramped load fails in the substep
//! whose transmitted force first reaches its limit, the event names it, the model energy
//! balance closes through the break, and a row of bolts sharing a load fails in the order
//! the load path predicts.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;

use common::{add, joints, point_body, world};
use rapier_kjoint::dynamics::energy::mechanical_energy;
use rapier_kjoint::dynamics::{EventSource, KjointEvent, KjointEventKind};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    BreakCause, BreakCriterion, JointType, KjointHandle, KjointProperty, KjointSet, SimError,
    SubstepPhase,
};

const FRAME: f64 = 1.0 / 60.0;
const SUBSTEPS: usize = 4;
const H: f64 = FRAME / SUBSTEPS as f64;

/// A user force `dir·rate·t` on `body` (t the substep's start), set before every substep,
/// and its work `F·Δx` over each substep (the force is constant over the substep) \[J\].
struct Ramp {
    body: RigidBodyHandle,
    dir: Vector,
    rate: f64,
    /// The load stops once this is set (time \[s\]).
    off_after: Option<f64>,
    work: f64,
    start: Vector,
    force: Vector,
}

impl Ramp {
    fn new(body: RigidBodyHandle, dir: Vector, rate: f64) -> Self {
        Ramp {
            body,
            dir,
            rate,
            off_after: None,
            work: 0.0,
            start: Vector::ZERO,
            force: Vector::ZERO,
        }
    }

    fn hook(&mut self, phase: SubstepPhase, w: &mut PhysicsWorld, set: &KjointSet) {
        let b = &mut w.bodies[self.body];
        match phase {
            SubstepPhase::Before => {
                let t = set.time();
                let on = self.off_after.is_none_or(|t0| t < t0);
                self.force = if on {
                    self.dir * (self.rate * t) as Real
                } else {
                    Vector::ZERO
                };
                b.reset_forces(true);
                b.add_force(self.force, true);
                self.start = b.center_of_mass();
            }
            SubstepPhase::After => {
                self.work += self.force.dot(b.center_of_mass() - self.start) as f64;
            }
        }
    }
}

/// Bodies' energy + every joint's energy (present and removed) − work of the ramp \[J\].
fn balance(w: &PhysicsWorld, set: &KjointSet, ramp: &Ramp) -> f64 {
    let total = |e: rapier_kjoint::JointEnergy| e.elastic + e.dissipated();
    mechanical_energy(&w.bodies, w.gravity)
        + set.iter().map(|(_, j)| total(j.energy())).sum::<f64>()
        + total(set.removed_energy())
        - ramp.work
}

/// The break events among `events`: (handle, name, time, cause).
fn breaks(events: &[KjointEvent]) -> Vec<(KjointHandle, String, f64, BreakCause)> {
    events
        .iter()
        .filter_map(|e| match (&e.source, &e.kind) {
            (EventSource::Joint { handle, name }, KjointEventKind::JointBroke { cause, .. }) => {
                Some((*handle, name.clone(), e.time, *cause))
            }
            _ => None,
        })
        .collect()
}

#[test]
fn a_ramped_load_breaks_the_joint_in_the_substep_its_transmitted_force_reaches_the_limit() {
    // a 1 kg body held at the world origin by a spherical joint, pulled down by F = 1000·t N
    // (no gravity): the joint carries the load, F_max = 101 N. The load of substep k
    // (starting at k·h) is 1000·k·h: the first substep at or over the limit is
    // k* = ⌈101/(1000·h)⌉ = ⌈24.24⌉ = 25 (h = 1/240 s), t* = 0.104167 s.
    let (mut w, ground) = world(Vector::ZERO);
    let body = point_body(&mut w, 1.0, Vector::splat(0.01), Vector::ZERO);
    let mut set = joints(SUBSTEPS);
    let limit = 101.0;
    let j = add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Spherical),
        ground,
        body,
        |b| b.name("hanger").break_when(BreakCriterion::force(limit)),
    );
    let rate = 1000.0;
    let mut ramp = Ramp::new(body, -Vector::Y, rate);
    let mut events = Vec::new();
    let mut last_applied = 0.0;
    for _ in 0..12 {
        set.step_with(&mut w, FRAME, |phase, w, set| {
            ramp.hook(phase, w, set);
            if phase == SubstepPhase::After {
                if let Some(s) = set.get(j).and_then(|j| j.state()) {
                    last_applied = s.applied[1];
                }
            }
            Ok::<(), SimError>(())
        })
        .unwrap();
        events.extend(set.drain_events());
    }
    let broke = breaks(&events);
    assert_eq!(broke.len(), 1, "{events:?}");
    let (h, name, t, cause) = &broke[0];
    assert_eq!((*h, name.as_str()), (j, "hanger"));
    let k_star = (limit / (rate * H)).ceil();
    assert_eq!(k_star, 25.0);
    let k = t / H;
    assert!(
        (k - k_star).abs() <= 1.0 + 1e-9,
        "broke in substep {k}, expected {k_star}"
    );
    let BreakCause::Force { force, limit: l } = *cause else {
        panic!("{cause:?}")
    };
    assert_eq!(l, limit);
    eprintln!("broke in substep {k} (t = {t} s), F = {force} N, before {last_applied} N");
    // it carried the load of its substep (1000·k·h N, within 2 %), at or over the limit
    let load = rate * t;
    assert!(
        force >= limit && (force - load).abs() < 0.02 * load,
        "F = {force} N, load {load} N"
    );
    // the event carries the joint's readout of the breaking substep (the force it broke at)
    // and its final energies (those the set added to its removed energy)
    let event = events
        .iter()
        .find(|e| matches!(e.kind, KjointEventKind::JointBroke { .. }))
        .unwrap();
    let KjointEventKind::JointBroke { energy, last, .. } = &event.kind else {
        unreachable!()
    };
    let last = last.as_ref().expect("a readout of the breaking substep");
    assert_eq!(last.time, *t);
    let a = last.applied;
    assert_eq!((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt(), force);
    assert_eq!(*energy, set.removed_energy());
    // the substep before it held: its transmitted force was under the limit
    assert!(
        last_applied.abs() < limit,
        "last stored force {last_applied} N"
    );
    // the event names the joint; the joint is gone, the body flies off under the load
    let text = events
        .iter()
        .find(|e| {
            e.kind.severity() == rapier_kjoint::dynamics::Severity::Info
                && matches!(e.kind, KjointEventKind::JointBroke { .. })
        })
        .unwrap()
        .to_string();
    assert!(
        text.starts_with("joint hanger at t = ") && text.contains("broke: transmitted force"),
        "{text}"
    );
    assert!(set.get(j).is_none() && set.is_empty());
    let v = w.bodies[body].linvel().y as f64;
    // after the break: v = −∫ 1000·t dt from t* to 0.2 s (within 5 %)
    let t_end = 12.0 * FRAME;
    let expected = -0.5 * rate * (t_end * t_end - t * t);
    assert!(
        (v - expected).abs() < 0.05 * expected.abs(),
        "v = {v}, expected {expected}"
    );
}

#[test]
fn the_model_energy_balance_closes_through_the_break() {
    // a 2 kg pendulum bob 1 m below its pivot, under gravity, pushed sideways by a ramp of
    // 60·t N: the spherical joint (an automatic blocked stiffness, elastic energy stored in
    // it) breaks at 40 N, the load stops at the break, the bob flies off. 16 substeps per
    // frame: rapier's own integration of the free bodies (semi-implicit Euler) drifts by
    // m·g·h·Δv/2 a substep, which is not the joints' and is kept small beside the 1 %.
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let bob = point_body(
        &mut w,
        2.0,
        Vector::splat(0.02),
        Vector::new(0.0, -1.0, 0.0),
    );
    let mut set = joints(16);
    let j = add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Spherical),
        ground,
        bob,
        |b| {
            b.local_anchor2(Vector::new(0.0, 1.0, 0.0))
                .break_when(BreakCriterion::force(40.0))
        },
    );
    let mut ramp = Ramp::new(bob, Vector::X, 60.0);
    set.prepare(&mut w);
    let e0 = balance(&w, &set, &ramp);
    let mut worst: f64 = 0.0;
    let mut broke_at = None;
    // the balance error (J) at the end of the frame before the break and of the frame of it
    let (mut before, mut jump) = (0.0, f64::NAN);
    let mut frames_after = 0;
    while frames_after < 15 {
        set.step_with(&mut w, FRAME, |phase, w, set| {
            ramp.hook(phase, w, set);
            Ok::<(), SimError>(())
        })
        .unwrap();
        let err = balance(&w, &set, &ramp) - e0;
        worst = worst.max(err.abs());
        match broke_at {
            Some(_) => frames_after += 1,
            None => {
                if let Some((_, _, t, _)) = breaks(&set.drain_events()).first() {
                    broke_at = Some(*t);
                    ramp.off_after = Some(*t);
                    jump = err - before;
                }
                before = err;
            }
        }
        assert!(set.time() < 2.0, "the joint never broke");
    }
    let t = broke_at.unwrap();
    assert!(set.get(j).is_none());
    let work = ramp.work;
    eprintln!(
        "broke at {t} s; balance off by at most {worst} J, {jump} J over the frame of the \
         break, of a load work {work} J; removed {:?}",
        set.removed_energy()
    );
    // it held the swinging bob (its weight 19.6 N and the centripetal force) a while
    assert!(t > 0.3 && t < 1.2, "broke at {t} s");
    let removed = set.removed_energy();
    assert!(
        removed.elastic > 0.0,
        "the joint stored energy when it broke: {removed:?}"
    );
    assert!(worst < 0.01 * work, "balance off by {worst} J of {work} J");
    // the frame of the break adds no more than a frame's share of that drift
    assert!(
        jump.abs() < 0.001 * work,
        "the break moved the balance by {jump} J"
    );
}

#[test]
fn a_bolt_row_fails_in_the_order_of_its_load_path() {
    // a 1 kg plate held to the world by three bolts (spherical joints, the same user
    // Kn = 1e6 N/m) at x = −1, 0, 1 m, pulled down at its centre (x = 0) by F = 200·t N, no
    // gravity. The rigid plate shares the load equally, F/3 each: the middle bolt (limit
    // 20 N) fails first, at F = 60 N (t = 0.3 s). The two outer ones then carry F/2 each,
    // symmetric about the load: the left one (limit 45 N) fails at F = 90 N (t = 0.45 s);
    // the right one (50 N) is then a pivot 1 m from the load: the plate (inertia
    // I = 10 kg·m² about its centre) starts to turn about it with α = F·d/(I + m·d²) and the
    // pivot carries F − m·α·d = F·I/(I + m·d²) = 90·10/11 = 81.8 N > 50 N: it fails at once.
    let (mut w, ground) = world(Vector::ZERO);
    let plate = point_body(&mut w, 1.0, Vector::new(0.1, 10.0, 10.0), Vector::ZERO);
    let mut set = joints(SUBSTEPS);
    let bolt = KjointProperty::new(JointType::Spherical).with_kn(1e6);
    let mut row = Vec::new();
    for (name, x, limit) in [
        ("left", -1.0, 45.0),
        ("middle", 0.0, 20.0),
        ("right", 1.0, 50.0),
    ] {
        let at = Vector::new(x, 0.0, 0.0);
        row.push(add(&mut set, &w, bolt.clone(), ground, plate, |b| {
            b.name(name)
                .local_anchor1(at)
                .local_anchor2(at)
                .break_when(BreakCriterion::force(limit))
        }));
    }
    let rate = 200.0;
    let mut ramp = Ramp::new(plate, -Vector::Y, rate);
    let mut events = Vec::new();
    while !set.is_empty() {
        set.step_with(&mut w, FRAME, |phase, w, set| {
            ramp.hook(phase, w, set);
            Ok::<(), SimError>(())
        })
        .unwrap();
        events.extend(set.drain_events());
        assert!(set.time() < 1.0, "bolts left at 1 s: {}", set.len());
    }
    let broke = breaks(&events);
    let order: Vec<&str> = broke.iter().map(|b| b.1.as_str()).collect();
    assert_eq!(order, ["middle", "left", "right"]);
    let force = |c: &BreakCause| match c {
        BreakCause::Force { force, .. } => *force,
        other => panic!("{other:?}"),
    };
    for (handle, name, t, cause) in &broke {
        eprintln!(
            "{name} broke at t = {t:.6} s, load {:.2} N, carrying {:.2} N",
            rate * t,
            force(cause)
        );
        assert_eq!(
            *handle,
            row[["left", "middle", "right"]
                .iter()
                .position(|n| n == name)
                .unwrap()]
        );
    }
    // the middle bolt: in the substep whose load first reaches 3·20 = 60 N (±1 substep),
    // carrying its share F/3 (within 2 %)
    let (_, _, t1, c1) = &broke[0];
    assert!(
        (t1 / H - 60.0 / (rate * H)).abs() <= 1.0 + 1e-9,
        "middle broke at {t1} s"
    );
    assert!((force(c1) - rate * t1 / 3.0).abs() < 0.02 * rate * t1 / 3.0);
    // the left bolt: where F/2 first reaches 45 N, F = 90 N, carrying F/2
    let (_, _, t2, c2) = &broke[1];
    assert!(
        (t2 / H - 90.0 / (rate * H)).abs() <= 1.0 + 1e-9,
        "left broke at {t2} s"
    );
    assert!((force(c2) - rate * t2 / 2.0).abs() < 0.02 * rate * t2 / 2.0);
    // the right bolt: in the next substep, carrying F·I/(I + m·d²) (within 5 %)
    let (_, _, t3, c3) = &broke[2];
    let pivot = rate * t3 * 10.0 / 11.0;
    assert!((t3 - t2 - H).abs() < 1e-9, "right broke at {t3} s");
    assert!(
        (force(c3) - pivot).abs() < 0.05 * pivot,
        "{} N, not {pivot} N",
        force(c3)
    );
}
