//! The user's switch of a KJOINT2 joint (`KjointSet::set_enabled`, `KjointBuilder::enabled`),
//! as rapier's `GenericJoint::set_enabled` for its impulse joints (0.36:
//! `JointEnabled::Disabled`): a joint switched off acts on nothing, as one of a disabled
//! body does (tests/disabled_bodies.rs), keeps its state and energies, and takes up from
//! there when switched on again.

mod common;

use common::*;
use rapier_kjoint::law::JointEnergy;
use rapier_kjoint::output::{summary::Summary, Observer};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, JointType, KjointEvent, KjointEventKind, KjointHandle, KjointProperty, KjointSet,
};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

/// A 1 kg bob (a ball) 1 m below the fixed ground's origin, hung there by a KJOINT2 joint of
/// type `ty` named `rod` (a revolute one about z, with a spring and friction on its free
/// rotation), moving at `v` m/s along x: world, set, ground, bob, joint.
fn hung_bob(
    ty: JointType,
    v: Real,
) -> (
    PhysicsWorld,
    KjointSet,
    RigidBodyHandle,
    RigidBodyHandle,
    KjointHandle,
) {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let bob = ball(&mut w, 1.0, 0.1, Vector::new(0.0, -1.0, 0.0));
    w.bodies[bob].set_linvel(Vector::new(v, 0.0, 0.0), true);
    let mut set = joints(4);
    let mut prop = KjointProperty::new(ty);
    if ty == JointType::Revolute {
        prop = prop.with_dof(Dof::Rx, DofLaw::spring(20.0).with_friction(200.0, 0.2));
    }
    let j = add(&mut set, &w, prop, ground, bob, |b| {
        let b = b.name("rod").local_anchor2(Vector::new(0.0, 1.0, 0.0));
        if ty == JointType::Revolute {
            b.world_axis(Vector::Z)
        } else {
            b
        }
    });
    (w, set, ground, bob, j)
}

fn run(w: &mut PhysicsWorld, set: &mut KjointSet, frames: usize) {
    for _ in 0..frames {
        set.step(w, DT).unwrap();
    }
}

fn vy(w: &PhysicsWorld, b: RigidBodyHandle) -> f64 {
    w.bodies[b].linvel().y as f64
}

/// The bob's pose and velocities put back as they were in `saved`.
fn put_back(w: &mut PhysicsWorld, bob: RigidBodyHandle, saved: &RigidBody) {
    let b = &mut w.bodies[bob];
    b.set_position(*saved.position(), true);
    b.set_linvel(saved.linvel(), true);
    b.set_angvel(saved.angvel(), true);
}

/// The events of the user's switch among `events` (off, on).
fn switch_events(events: &[KjointEvent]) -> (usize, usize) {
    let off = events
        .iter()
        .filter(|e| e.kind == KjointEventKind::DisabledByUser)
        .count();
    let on = events
        .iter()
        .filter(|e| e.kind == KjointEventKind::EnabledAgain)
        .count();
    (off, on)
}

/// A bob hanging at rest on its rod: switched off, it falls at g and the rod reports that it
/// transmits nothing; put back where it hung and switched on again, the rod holds it again
/// at once, its anchors together within a millimetre and its force the bob's weight.
#[test]
fn a_bob_whose_rod_is_switched_off_falls_at_g_and_is_held_again_when_switched_on() {
    for ty in [JointType::Spherical, JointType::Revolute] {
        let (mut w, mut set, _, bob, j) = hung_bob(ty, 0.0);
        run(&mut w, &mut set, 60);
        let held = applied_force(set.get(j).unwrap());
        assert!(
            (held - G).abs() < 0.01 * G,
            "{ty:?}: the rod carries {held} N"
        );
        set.drain_events();
        let saved = w.bodies[bob].clone();
        assert!(set.set_enabled(j, false));
        let joint = set.get(j).unwrap();
        assert!(!joint.is_enabled() && !joint.is_switched_on());
        let (v0, t0) = (vy(&w, bob), set.time());
        run(&mut w, &mut set, 15);
        let a = (vy(&w, bob) - v0) / (set.time() - t0);
        let joint = set.get(j).unwrap();
        let s = joint.state().unwrap();
        println!(
            "{ty:?}: rod force {held} N held; switched off, the bob falls at {a} m/s², the \
             rod transmits {} N",
            applied_force(joint)
        );
        assert!((a + G).abs() < 1e-4, "{ty:?}: a = {a} m/s²");
        assert_eq!(s.applied, Default::default(), "{ty:?}");
        assert_eq!(s.force, Default::default(), "{ty:?}");
        assert_eq!(s.parts, Default::default(), "{ty:?}");
        assert!(!joint.is_enabled());
        let events = set.drain_events();
        assert_eq!(switch_events(&events), (1, 0), "{ty:?}: {events:?}");
        let text = events[0].to_string();
        assert!(
            text.contains("joint rod") && text.contains("switched off"),
            "{text}"
        );
        put_back(&mut w, bob, &saved);
        assert!(set.set_enabled(j, true));
        assert!(set.get(j).unwrap().is_enabled());
        run(&mut w, &mut set, 1);
        let (gap, force) = {
            let joint = set.get(j).unwrap();
            (world_gap(joint), applied_force(joint))
        };
        run(&mut w, &mut set, 59);
        let joint = set.get(j).unwrap();
        let (gap_later, force_later) = (world_gap(joint), applied_force(joint));
        println!(
            "{ty:?}: switched on again, gap {gap} m and force {force} N after a frame, \
             {gap_later} m and {force_later} N after a second"
        );
        for (g, f) in [(gap, force), (gap_later, force_later)] {
            assert!(g < 1e-3, "{ty:?}: gap {g} m");
            assert!((f - G).abs() < 0.01 * G, "{ty:?}: force {f} N");
        }
        let events = set.drain_events();
        assert_eq!(switch_events(&events), (0, 1), "{ty:?}: {events:?}");
        assert!(events[0].to_string().contains("enabled again"));
    }
}

/// A swinging hinge with a spring and friction switched off, its bob put back as it was
/// and switched on again, resumes with the same bits as the same hinge whose bob was
/// disabled and enabled again instead (the disabled-body path), and as the same hinge never
/// disabled (analysed again at the same moment): the same spring and friction moments,
/// energies and path. Meanwhile its energies keep their values.
#[test]
fn switched_on_again_it_resumes_as_a_joint_whose_body_is_enabled_again() {
    let (mut w, mut set, _, bob, j) = hung_bob(JointType::Revolute, 1.0);
    let (mut w_body, mut set_body, _, bob_body, j_body) = hung_bob(JointType::Revolute, 1.0);
    let (mut w_ref, mut set_ref, _, bob_ref, j_ref) = hung_bob(JointType::Revolute, 1.0);
    run(&mut w, &mut set, 20);
    run(&mut w_body, &mut set_body, 20);
    run(&mut w_ref, &mut set_ref, 20);
    // (any change of the set starts its substep data over: `get_mut`)
    set_ref.get_mut(j_ref).unwrap();
    let energy = set.get(j).unwrap().energy();
    let saved = w.bodies[bob].clone();
    set.set_enabled(j, false);
    w_body.bodies[bob_body].set_enabled(false);
    run(&mut w, &mut set, 30);
    run(&mut w_body, &mut set_body, 30);
    assert_eq!(set.get(j).unwrap().energy(), energy);
    assert_eq!(set_body.get(j_body).unwrap().energy(), energy);
    assert!(saved.translation().y - w.bodies[bob].translation().y > 0.5);
    put_back(&mut w, bob, &saved);
    put_back(&mut w_body, bob_body, &saved);
    set.set_enabled(j, true);
    w_body.bodies[bob_body].set_enabled(true);
    let mut apart = 0.0f64;
    for _ in 0..60 {
        set.step(&mut w, DT).unwrap();
        set_body.step(&mut w_body, DT).unwrap();
        set_ref.step(&mut w_ref, DT).unwrap();
        let s = set.get(j).unwrap().state().unwrap();
        let s_body = set_body.get(j_body).unwrap().state().unwrap();
        let s_ref = set_ref.get(j_ref).unwrap().state().unwrap();
        assert_eq!(s, s_body, "the same readout as the disabled-body path");
        assert_eq!(w.bodies[bob].position(), w_body.bodies[bob_body].position());
        assert_eq!(w.bodies[bob].linvel(), w_body.bodies[bob_body].linvel());
        let (p, p_ref) = (&s.parts[3], &s_ref.parts[3]);
        assert!((p.elastic - p_ref.elastic).abs() < 1e-9, "{p:?} {p_ref:?}");
        assert!(
            (p.friction - p_ref.friction).abs() < 1e-9,
            "{p:?} {p_ref:?}"
        );
        assert_eq!(s.energy, s_ref.energy);
        let d = w.bodies[bob].translation() - w_ref.bodies[bob_ref].translation();
        apart = apart.max(d.abs().max_element() as f64);
    }
    println!("switched on again: {apart} m at most from the path never disabled");
    assert!(apart < 1e-5, "{apart} m");
}

/// One event per change of the switch: none for a call that changes nothing, none for a
/// switch turned off and on again between two steps; and a call that changes nothing
/// leaves the set as it was (no new analysis: the same bits as a set never called).
#[test]
fn the_switch_gives_one_event_per_change_and_nothing_when_unchanged() {
    let (mut w, mut set, _, bob, j) = hung_bob(JointType::Revolute, 1.0);
    let (mut w_ref, mut set_ref, _, bob_ref, _) = hung_bob(JointType::Revolute, 1.0);
    for _ in 0..30 {
        assert!(set.set_enabled(j, true)); // on already: at every frame, as a game might
        set.step(&mut w, DT).unwrap();
        set_ref.step(&mut w_ref, DT).unwrap();
    }
    assert_eq!(w.bodies[bob].position(), w_ref.bodies[bob_ref].position());
    assert_eq!(switch_events(&set.drain_events()), (0, 0));
    // off and on again before the next step: nothing to report
    set.set_enabled(j, false);
    set.set_enabled(j, true);
    run(&mut w, &mut set, 2);
    assert_eq!(switch_events(&set.drain_events()), (0, 0));
    // off twice, then on: one event each way
    set.set_enabled(j, false);
    run(&mut w, &mut set, 1);
    set.set_enabled(j, false);
    run(&mut w, &mut set, 3);
    let events = set.drain_events();
    assert_eq!(switch_events(&events), (1, 0), "{events:?}");
    set.set_enabled(j, true);
    run(&mut w, &mut set, 3);
    assert_eq!(switch_events(&set.drain_events()), (0, 1));
}

/// The switch and a disabled body together: the switch wins (off while its body is
/// disabled, the joint stays off when the body is enabled again), and each change of what
/// keeps the joint off is reported once.
#[test]
fn the_users_switch_wins_over_a_disabled_body() {
    let (mut w, mut set, _, bob, j) = hung_bob(JointType::Spherical, 0.0);
    run(&mut w, &mut set, 10);
    set.drain_events();
    w.bodies[bob].set_enabled(false);
    run(&mut w, &mut set, 1);
    // (the events of the joint's state: the bob enabled again where it fell is far from
    // its anchor, and a warning says so)
    let kinds = |set: &mut KjointSet| -> Vec<KjointEventKind> {
        let events = set.drain_events().into_iter().map(|e| e.kind);
        events
            .filter(|k| {
                matches!(
                    k,
                    KjointEventKind::DisabledByBody { .. }
                        | KjointEventKind::DisabledByUser
                        | KjointEventKind::EnabledAgain
                )
            })
            .collect()
    };
    assert_eq!(
        kinds(&mut set),
        [KjointEventKind::DisabledByBody { body: 2 }]
    );
    set.set_enabled(j, false);
    run(&mut w, &mut set, 1);
    assert_eq!(kinds(&mut set), [KjointEventKind::DisabledByUser]);
    w.bodies[bob].set_enabled(true);
    run(&mut w, &mut set, 10);
    assert!(kinds(&mut set).is_empty());
    assert!(!set.get(j).unwrap().is_enabled(), "still switched off");
    let v0 = vy(&w, bob);
    run(&mut w, &mut set, 6);
    let a = (vy(&w, bob) - v0) / (6.0 * DT);
    assert!((a + G).abs() < 1e-4, "a = {a} m/s²: the bob falls");
    // switched on while the body is disabled: the body keeps it off
    w.bodies[bob].set_enabled(false);
    run(&mut w, &mut set, 1);
    assert!(kinds(&mut set).is_empty());
    set.set_enabled(j, true);
    run(&mut w, &mut set, 1);
    assert_eq!(
        kinds(&mut set),
        [KjointEventKind::DisabledByBody { body: 2 }]
    );
    assert!(!set.get(j).unwrap().is_enabled() && set.get(j).unwrap().is_switched_on());
    w.bodies[bob].set_enabled(true);
    run(&mut w, &mut set, 1);
    assert_eq!(kinds(&mut set), [KjointEventKind::EnabledAgain]);
    assert!(set.get(j).unwrap().is_enabled());
}

/// A handle that finds no joint (removed): `false`, nothing changes, no panic.
#[test]
fn an_unknown_handle_is_answered_false() {
    let (mut w, mut set, _, bob, j) = hung_bob(JointType::Spherical, 0.0);
    let other = add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Spherical),
        w.bodies.iter().next().unwrap().0,
        bob,
        |b| b.local_anchor2(Vector::new(0.0, 1.0, 0.0)),
    );
    set.remove(other).unwrap();
    run(&mut w, &mut set, 5);
    set.drain_events();
    assert!(!set.set_enabled(other, false));
    assert!(!set.set_enabled(other, true));
    assert!(set.get(other).is_none());
    run(&mut w, &mut set, 5);
    assert!(set.drain_events().is_empty());
    assert!(set.get(j).unwrap().is_enabled());
}

/// A joint inserted switched off (`KjointBuilder::enabled(false)`) holds nothing until it
/// is switched on: the bob falls at g from the start, with one event at the first step.
#[test]
fn a_joint_built_switched_off_acts_only_once_switched_on() {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let bob = ball(&mut w, 1.0, 0.1, Vector::new(0.0, -1.0, 0.0));
    let mut set = joints(4);
    let j = add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Spherical),
        ground,
        bob,
        |b| b.local_anchor2(Vector::new(0.0, 1.0, 0.0)).enabled(false),
    );
    assert!(!set.get(j).unwrap().is_enabled());
    run(&mut w, &mut set, 6);
    let a = vy(&w, bob) / (6.0 * DT);
    println!("built switched off: the bob falls at {a} m/s²");
    assert!((a + G).abs() < 1e-4, "a = {a} m/s²");
    assert_eq!(switch_events(&set.drain_events()), (1, 0));
    assert_eq!(set.get(j).unwrap().energy(), Default::default());
    w.bodies[bob].set_translation(Vector::new(0.0, -1.0, 0.0), true);
    w.bodies[bob].set_linvel(Vector::ZERO, true);
    set.set_enabled(j, true);
    run(&mut w, &mut set, 30);
    let joint = set.get(j).unwrap();
    let (gap, force) = (world_gap(joint), applied_force(joint));
    println!("switched on: gap {gap} m, force {force} N");
    assert!(
        gap < 1e-3 && (force - G).abs() < 0.01 * G,
        "{gap} m, {force} N"
    );
}

/// Two rods hanging a 1 kg bob from the ground's origin (two ball joints at the same
/// anchors, each holding the bob alone as well), the bob swinging at 1 m/s along x, with
/// the second rod switched off at frame `off` and on again at frame `on` (never when
/// `None`): per frame end, the residual of the run's energy balance (the summary's: the
/// bodies' mechanical energy, the joints' stored and dissipated energies, against the
/// initial energy) \[J\], its scale \[J\], and the second rod's energies booked and at the
/// end of the last substep.
fn two_rods_balance(switch: Option<(usize, usize)>) -> Vec<(f64, f64, JointEnergy, JointEnergy)> {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let bob = ball(&mut w, 1.0, 0.1, Vector::new(0.0, -1.0, 0.0));
    w.bodies[bob].set_linvel(Vector::new(1.0, 0.0, 0.0), true);
    let mut set = joints(4);
    let mut rods = Vec::new();
    for _ in 0..2 {
        rods.push(add(
            &mut set,
            &w,
            KjointProperty::new(JointType::Spherical),
            ground,
            bob,
            |b| b.local_anchor2(Vector::new(0.0, 1.0, 0.0)),
        ));
    }
    set.prepare(&mut w);
    let mut summary = Summary::new();
    summary.record(set.time(), &w, &set, &[]).unwrap();
    let mut out = Vec::new();
    for frame in 0..120 {
        if let Some((off, on)) = switch {
            if frame == off {
                set.set_enabled(rods[1], false);
            }
            if frame == on {
                set.set_enabled(rods[1], true);
            }
        }
        set.step(&mut w, DT).unwrap();
        let events = set.drain_events();
        summary.record(set.time(), &w, &set, &events).unwrap();
        let b = summary.balance(0.0);
        let rod = set.get(rods[1]).unwrap();
        out.push((
            b.residual,
            b.scale,
            rod.energy(),
            rod.closed_energy(&w.bodies),
        ));
    }
    out
}

/// The energy balance of a run closes at every frame end with one of two rods hanging a
/// bob switched off for half a second and on again, as it does with the two rods never
/// switched; meanwhile the rod's energies, booked and at the end of the last substep, keep
/// the values they had when it was switched off.
#[test]
fn the_energy_balance_closes_across_the_switch() {
    let never = two_rods_balance(None);
    let switched = two_rods_balance(Some((30, 60)));
    let worst = |r: &[(f64, f64, JointEnergy, JointEnergy)]| {
        r.iter()
            .map(|(res, scale, ..)| (res / scale).abs())
            .fold(0.0, f64::max)
    };
    let (worst_never, worst_switched) = (worst(&never), worst(&switched));
    println!(
        "the energy balance's residual at most {worst_switched} of its scale ({worst_never} \
         never switched)"
    );
    // the residual of a swinging pendulum swings with it, by ±3.3e-4 of the bob's weight
    // scale (rapier's f32 integration): the switched run's is the same within a 1e-5th
    let apart = (never.iter().zip(&switched))
        .map(|(a, b)| ((a.0 - b.0) / a.1).abs())
        .fold(0.0, f64::max);
    println!("{apart} of the scale at most from the residual of the run never switched");
    assert!(worst_switched < 4e-4, "{worst_switched}");
    assert!(apart < 1e-5, "{apart}");
    let off = &switched[30..60];
    println!(
        "switched off: {:?}, at the end of the last substep {:?}",
        off[0].2, off[0].3
    );
    assert!(
        off.windows(2).all(|p| p[0].2 == p[1].2 && p[0].3 == p[1].3),
        "{off:?}"
    );
    assert!(off[0].3.dissipated() < 0.01, "{:?}", off[0].3);
}

/// A ball of 1 kg (radius 0.1 m) at `pos` that may sleep (rapier's default thresholds).
fn sleepy_ball(w: &mut PhysicsWorld, pos: Vector) -> RigidBodyHandle {
    w.insert(
        RigidBodyBuilder::dynamic().translation(pos),
        ColliderBuilder::ball(0.1).mass(1.0),
    )
    .0
}

/// A chain of two balls at rest (the ground, A 0.5 m below, B 0.5 m below A) sleeps; its
/// lower joint switched off wakes it at the next step (B falls), and A, alone on its
/// joint, sleeps again while B still falls: the joint switched off left the island. Switched
/// on again (B put back), it wakes A.
#[test]
fn a_joint_switched_off_wakes_its_island_and_leaves_it() {
    let (mut w, ground) = world(Vector::new(0.0, -G as Real, 0.0));
    let a = sleepy_ball(&mut w, Vector::new(0.0, -0.5, 0.0));
    let b = sleepy_ball(&mut w, Vector::new(0.0, -1.0, 0.0));
    let mut set = joints(4);
    let prop = || KjointProperty::new(JointType::Spherical);
    let half = Vector::new(0.0, 0.5, 0.0);
    add(&mut set, &w, prop(), ground, a, |j| j.local_anchor2(half));
    let lower = add(&mut set, &w, prop(), a, b, |j| j.local_anchor2(half));
    run(&mut w, &mut set, 60);
    let asleep = |w: &PhysicsWorld| [a, b].map(|h| w.bodies[h].is_sleeping());
    assert_eq!(asleep(&w), [true, true], "the chain at rest sleeps");
    set.set_enabled(lower, false);
    run(&mut w, &mut set, 1);
    assert_eq!(asleep(&w), [false, false], "woken by the switch");
    assert!(vy(&w, b) < -0.1, "B falls: {} m/s", vy(&w, b));
    let mut slept_at = None;
    for frame in 1..60 {
        run(&mut w, &mut set, 1);
        if slept_at.is_none() && w.bodies[a].is_sleeping() {
            slept_at = Some(frame);
        }
    }
    println!("A alone asleep again {slept_at:?} frames after the switch");
    assert!(slept_at.is_some() && !w.bodies[b].is_sleeping());
    assert!(w.bodies[a].is_sleeping());
    // B put back under A, at rest, and the joint switched on: A is woken with it
    w.bodies[b].set_translation(Vector::new(0.0, -1.0, 0.0), true);
    w.bodies[b].set_linvel(Vector::ZERO, true);
    set.set_enabled(lower, true);
    run(&mut w, &mut set, 1);
    assert!(!w.bodies[a].is_sleeping(), "A woken by the switch");
}

/// A scene's `[[switches]]` release a 2 kg payload hung 1 m below the world at t = 0.5 s:
/// it hangs still until then and falls freely after (its speed `g·(1 − 0.5)` at t = 1 s),
/// the joint off; the summary's energy balance closes across the release, but for rapier's
/// integration of the free fall. A joint given
/// `enabled = false` and no switch never holds its payload.
#[test]
fn a_scene_releases_a_payload_at_its_switch_time() {
    let scene = |joint: &str, switches: &str| {
        format!(
            r#"duration = 1.0
substeps = 4
gravity = [0.0, -9.81, 0.0]

[[bodies]]
name = "payload"
shape = {{ type = "ball", radius = 0.1 }}
mass = 2.0
translation = [0.0, -1.0, 0.0]

[[joints]]
name = "hook"
body1 = "world"
body2 = "payload"
anchor2 = [0.0, 1.0, 0.0]
property = {{ type = "spherical" }}
{joint}
{switches}
"#
        )
    };
    let run = |text: &str| {
        let (built, summary, stats) =
            common::scene::run_with_summary("switch-scene", "release.toml", text);
        let payload = built.bodies.iter().find(|(n, _)| n == "payload").unwrap().1;
        let b = &built.world.bodies[payload];
        let hook = built
            .joints
            .get(built.joints.find("hook").unwrap())
            .unwrap();
        let balance = summary.balance(stats.external_work());
        (
            b.linvel().y as f64,
            b.translation().y as f64,
            hook.is_switched_on(),
            balance.residual,
        )
    };
    let released = scene(
        "",
        "[[switches]]\njoint = \"hook\"\ntime = 0.5\nenabled = false\n",
    );
    let (vy, y, on, residual) = run(&released);
    println!("released: vy = {vy} m/s, y = {y} m, balance residual {residual}");
    assert!(
        (vy - -G * 0.5).abs() < 1e-4,
        "vy = {vy}, expected {}",
        -G * 0.5
    );
    // (semi-implicit Euler over 120 substeps of 1/240 s: ½·g·t·(t + h))
    let h = 1.0 / 240.0;
    let drop = 0.5 * G * 0.5 * (0.5 + h);
    assert!(
        (y - (-1.0 - drop)).abs() < 1e-3,
        "y = {y}, expected {}",
        -1.0 - drop
    );
    assert!(!on);
    // rapier's semi-implicit Euler: over n substeps of free fall the drop `½·g·h²·n(n + 1)`
    // outruns the speed's `g·h·n` by `m·g²·h²·n/2` of energy (0.2005 J here), the balance's
    // whole residual: the joint's release adds nothing to it
    let n = 120.0;
    let integrator = -2.0 * G * G * h * h * n / 2.0;
    assert!(
        (residual - integrator).abs() < 1e-3,
        "balance residual {residual} J, rapier's free fall {integrator} J"
    );
    // built switched off, never switched on
    let (vy, _, on, _) = run(&scene("enabled = false", ""));
    assert!((vy - -G).abs() < 1e-4, "vy = {vy}");
    assert!(!on);
}
