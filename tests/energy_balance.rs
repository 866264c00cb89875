//! A damped, frictional slider hitting a stop: kinetic + potential + stored elastic energy +
//! all dissipated work (viscosity, friction, stop damping) equals the initial energy within 1 %.

mod common;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, DofLaw, JointType, KjointProperty, StopContact};

#[test]
fn energy_is_accounted_for_through_a_stop_impact() {
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
    // The energy bookkeeping (trapezoidal work of the law's forces) differs from the work of
    // the implicit impulses by O(h): 3.8 % at 8 substeps, 0.6 % at 32 (measured).
    let mut set = common::joints(32);
    let law = DofLaw::spring(20.0)
        .with_viscosity(0.5)
        .with_friction(1e4, 1.0)
        .with_stops(0.0, 0.3);
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e6)
        .with_critical_damping(0.1)
        .with_dof(Dof::Dx, law);
    let j = common::add(&mut set, &w, prop, ground, b, |bl| {
        bl.world_frame1(Rotation::IDENTITY)
    });
    w.bodies[b].set_linvel(Vector::new(2.0, 0.0, 0.0), true);
    set.prepare(&mut w);
    let e0 = common::total_energy(&w, &set);
    let mut hit = false;
    let mut worst = 0.0f64;
    for _ in 0..180 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let s = set.get(j).unwrap().state().unwrap();
        hit |= s.status[0].stop == StopContact::Max;
        let e = common::total_energy(&w, &set) + common::dissipated(&set);
        worst = worst.max((e - e0).abs());
    }
    let en = set.get(j).unwrap().energy();
    println!("E0 {e0}, worst residual {worst}, {en:?}");
    assert!(hit, "the slider never reached its stop");
    assert!(en.friction > 0.1 && en.damping > 0.01 && en.stop > 0.0);
    assert!(worst < 0.01 * e0, "energy residual {worst} J of {e0} J");
}

/// 1 kg on a slider at 2 m/s into a stop of `k` = 1000 N/m (the DOF's friction stiffness
/// `Kf`, no friction) at x = 0.3 m, 4 substeps of 1/240 s (`ω·h` = 0.13: resolved), the stop
/// damped at `Cr` (its damping `Cr·√(k·m)`, `ζ = Cr/2`): the contact starts at t = 0.15 s, a
/// substep's end. The work its damper has done by `t` is that of the continuous damped
/// oscillator, `E0 − ½·m·v² − ½·k·x²` (`None` once `x` < 0, the contact over).
fn stop_damper_work(cr: f64, t: f64) -> Option<f64> {
    let (m, k, v0) = (1.0, 1000.0, 2.0);
    let t = t - 0.15;
    if t <= 0.0 {
        return Some(0.0);
    }
    let omega = (k / m).sqrt();
    let zeta = cr / 2.0;
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    let decay = (-zeta * omega * t).exp();
    let x = v0 / wd * decay * (wd * t).sin();
    let v = v0 * decay * ((wd * t).cos() - zeta * omega / wd * (wd * t).sin());
    (x >= 0.0).then_some(0.5 * m * v0 * v0 - 0.5 * m * v * v - 0.5 * k * x * x)
}

/// The run's summary through a stop's contact, after every frame: the energy balance closes
/// (rapier's f32 poses) and the slider's dissipated energy is its stop damper's work
/// ([`stop_damper_work`], Cr = 0.05) within 0.01 J (0.5 % of E0 = 2 J) at every frame end of
/// the contact, the rebound included (measured: 0.0054 J at worst, at 0.2 s). The summary
/// reads the joint's energies at the end of the last substep (`Kjoint::closed_energy`): where
/// it read them as booked (`Kjoint::energy`), the law's share of the last substep was not in
/// yet and its stored energy was that of the substep's start, so that the dissipated energy
/// swung by ±F·v·h/2: 0.182 J where the damper had done 0.094 J (t = 0.1667 s), 0.059 J for
/// 0.159 J (t = 0.2167 s).
#[test]
fn the_summary_dissipates_what_a_stop_damper_does_at_every_frame_end() {
    use rapier_kjoint::output::{summary::Summary, Observer};
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
    let mut set = common::joints(4);
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e6)
        .with_critical_damping(0.05)
        .with_dof(
            Dof::Dx,
            DofLaw::default()
                .with_stops(-1.0, 0.3)
                .with_friction(1000.0, 0.0),
        );
    common::add(&mut set, &w, prop, ground, b, |bl| {
        bl.world_frame1(Rotation::IDENTITY)
    });
    w.bodies[b].set_linvel(Vector::new(2.0, 0.0, 0.0), true);
    set.prepare(&mut w);
    let mut summary = Summary::new();
    summary.record(set.time(), &w, &set, &[]).unwrap();
    let e0 = 2.0;
    let mut in_contact = 0;
    let mut worst = 0.0f64;
    for _ in 0..18 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let events = set.drain_events();
        summary.record(set.time(), &w, &set, &events).unwrap();
        let balance = summary.balance(0.0);
        assert!(
            balance.residual.abs() < 1e-5 * e0,
            "t = {}: residual {} J",
            set.time(),
            balance.residual
        );
        let dissipated = summary.joints()[0].dissipated;
        assert!(
            dissipated >= 0.0,
            "t = {}: dissipated {dissipated} J",
            set.time()
        );
        if let Some(want) = stop_damper_work(0.05, set.time()) {
            if set.time() > 0.151 {
                in_contact += 1;
            }
            let off = dissipated - want;
            println!(
                "t = {:.4} s: dissipated {dissipated:.5} J, the damper's work {want:.5} J",
                set.time()
            );
            worst = worst.max(off.abs());
            assert!(
                off.abs() < 0.01,
                "t = {} s: dissipated {dissipated} J, the damper did {want} J",
                set.time()
            );
        }
    }
    println!("worst {worst} J");
    assert!(in_contact >= 5, "{in_contact} frame ends in the contact");
}

/// `kjoint run` of the slider of [`stop_damper_work`] with little damping (Cr = 0.01), ending
/// within the stop's rebound (t = 0.2167 s, 13 frames): the summary prints a dissipated
/// energy that is the damper's work within 0.01 J, not below 0, and a residual below 1e-5 of
/// E0. Printed as booked (the law's share of the last substep outstanding, its stored
/// energy that of the substep's start) it read −0.074 J.
#[test]
fn a_run_ending_within_a_stop_contact_prints_what_the_damper_dissipated() {
    let scene = common::cli::temp_file(
        "energy-stop",
        "slider.toml",
        r#"dt = 0.016666666666666666
substeps = 4
duration = 0.21666666666666667
gravity = [0, -9.81, 0]

[[bodies]]
name = "block"
shape = { type = "cuboid", half_extents = [0.05, 0.05, 0.05] }
mass = 1.0
linvel = [2.0, 0.0, 0.0]

[[joints]]
name = "slider"
body1 = "world"
body2 = "block"
[joints.property]
type = "translational"
kn = 1e6
critical_damping = 0.01
dx = { stop_min = -1.0, stop_max = 0.3, friction_stiffness = 1000 }
"#,
    );
    let out = common::cli::kjoint_run(&scene, None, &[] as &[&str]);
    let value = |label: &str| -> f64 {
        let line = out
            .lines()
            .find(|l| l.trim_start().starts_with(label))
            .unwrap_or_else(|| panic!("no `{label}` line in\n{out}"));
        line.trim_start()[label.len()..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let dissipated = value("dissipated by the joints");
    let want = stop_damper_work(0.01, 13.0 / 60.0).expect("within the contact");
    println!("{out}\nthe damper's work {want} J");
    assert!(dissipated >= 0.0, "{out}");
    assert!(
        (dissipated - want).abs() < 0.01,
        "{dissipated} J for {want} J\n{out}"
    );
    assert!(value("residual").abs() < 2e-5, "{out}");
}

/// The slider of [`stop_damper_work`] into an undamped stop (Cr = 1e-9): the implicit
/// update conserves `½·m·v² + ½·K̃·q_n·q_{n+1}` through the contact (the symplectic
/// kick-drift of a linear spring, `K̃ = K/(1 + h²·K/(β·m))`), so that the joint's energies at
/// the end of each substep (`Kjoint::closed_energy`: the law's stored energy of the
/// substep's mid-point) keep `numerical` where it was before the contact, to 1e-5 J, at every
/// substep (`step_with`) in the contact, while as booked
/// (`Kjoint::energy`, the stored energy of the substep's start) it swings by ±F·v·h/2
/// (measured: 0.14 J of E0 = 2 J, closed 1.4e-6 J) and comes back. The fields of both add
/// up alike.
#[test]
fn an_undamped_stop_keeps_the_numerical_energy_at_the_end_of_every_substep() {
    use rapier_kjoint::SubstepPhase;
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
    let mut set = common::joints(4);
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e6)
        .with_critical_damping(1e-9)
        .with_dof(
            Dof::Dx,
            DofLaw::default()
                .with_stops(-1.0, 0.3)
                .with_friction(1000.0, 0.0),
        );
    let j = common::add(&mut set, &w, prop, ground, b, |bl| {
        bl.world_frame1(Rotation::IDENTITY)
    });
    w.bodies[b].set_linvel(Vector::new(2.0, 0.0, 0.0), true);
    set.prepare(&mut w);
    let total = |e: &rapier_kjoint::law::JointEnergy| e.elastic + e.dissipated();
    let (mut before, mut contact, mut swing, mut worst) = (None, 0, 0.0f64, 0.0f64);
    for _ in 0..15 {
        set.step_with(&mut w, 1.0 / 60.0, |phase, w, set| {
            if phase != SubstepPhase::After {
                return Ok::<(), rapier_kjoint::SimError>(());
            }
            let joint = set.get(j).unwrap();
            let (booked, closed) = (joint.energy(), joint.closed_energy(&w.bodies));
            assert!((total(&booked) - total(&closed)).abs() < 1e-12);
            // in the stop's contact over the whole substep: at its start and its end (where
            // the slider leaves the stop within a substep, the update pushed it for the whole
            // substep: 3.2 mJ given to it, which `numerical` books then)
            let s = joint.state().unwrap();
            let x = w.bodies[b].translation().x as f64;
            if s.status[0].stop == StopContact::None || x < 0.3 {
                if contact == 0 {
                    before = Some(closed.numerical);
                }
                return Ok(());
            }
            contact += 1;
            let before = before.unwrap();
            swing = swing.max((booked.numerical - before).abs());
            worst = worst.max((closed.numerical - before).abs());
            Ok(())
        })
        .unwrap();
    }
    println!("{contact} substeps in contact: numerical as booked ±{swing} J, closed ±{worst} J");
    assert!(contact > 20, "{contact} substeps in the stop's contact");
    assert!(worst < 1e-5, "closed: numerical moved by {worst} J");
    assert!(swing > 0.05, "as booked: numerical swung by {swing} J only");
}

/// A heavily damped stop (`Cr` = 1, `ζ` = 0.5): the 1 kg slider of [`stop_damper_work`]
/// (no gravity, the stop's own `k` = 1000 N/m) dissipates in the stop what it loses, and the
/// book's numerical work stays within 0.015 J of E0 = 2 J at every frame end, at 4 and at
/// 16 substeps (measured: 0.011 and 0.001 J). Booked with the law's damping at the end of
/// each interval, the stop's critical damping, which engages at the first evaluation in the
/// contact, was counted over the substep before it, where nothing touched the slider
/// (`½·c_c·v·Δq`, 0.26 J at 4 substeps): the stop dissipated 2.22 J of the 1.95 J the
/// slider lost, and numerical work read −0.27 J (−0.065 at 16 substeps: one substep's).
#[test]
fn a_heavily_damped_stop_dissipates_what_the_slider_loses() {
    for substeps in [4, 16] {
        let (mut w, ground) = common::world(Vector::ZERO);
        let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
        let mut set = common::joints(substeps);
        let prop = KjointProperty::new(JointType::Translational)
            .with_kn(1e6)
            .with_critical_damping(1.0)
            .with_dof(
                Dof::Dx,
                DofLaw::default()
                    .with_stops(-1.0, 0.3)
                    .with_stop_stiffness(1000.0),
            );
        let j = common::add(&mut set, &w, prop, ground, b, |bl| bl);
        w.bodies[b].set_linvel(Vector::new(2.0, 0.0, 0.0), true);
        set.prepare(&mut w);
        let mut worst = 0.0f64;
        for _ in 0..30 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
            let e = set.get(j).unwrap().closed_energy(&w.bodies);
            worst = worst.max(e.numerical.abs());
        }
        let e = set.get(j).unwrap().closed_energy(&w.bodies);
        let v = w.bodies[b].linvel().x as f64;
        let lost = 2.0 - 0.5 * v * v;
        println!(
            "{substeps} substeps: left at {v} m/s, lost {lost} J, the stop dissipated {} J, \
             numerical at worst {worst} J",
            e.stop
        );
        // (the contact over: the slider left the stop, as the damped oscillator, at
        // 0.326 m/s)
        assert!(v < -0.3 && v > -0.35, "{v}");
        assert!((e.stop - lost).abs() < 0.015, "{} {lost}", e.stop);
        assert!(worst < 0.015, "numerical work {worst} J");
    }
}

/// rapier's contacts book nothing, and the summary says where its residual arose: a
/// dumbbell (two 1 kg balls, a fixed joint between them) dropped 0.5 m flat onto the ground
/// loses its 9.8 J at the landing (rapier's contacts, restitution 0). Before it lands no
/// contact has touched (no share), and the residual is the free fall's integration error,
/// `−M·g²·h·t/2`; after it the residual is about −9.8 J, all of it but the fall's while
/// the contacts touched, and the warning names them rather than the substep.
#[test]
fn the_summary_names_the_residual_that_arose_while_contacts_touched() {
    use rapier_kjoint::output::{summary::Summary, Observer};
    let (mut w, _) = common::world(Vector::new(0.0, -9.81, 0.0));
    w.insert_collider(
        ColliderBuilder::cuboid(5.0, 0.5, 5.0).translation(Vector::new(0.0, -0.5, 0.0)),
        None,
    );
    let left = common::ball(&mut w, 1.0, 0.1, Vector::new(-0.15, 0.6, 0.0));
    let right = common::ball(&mut w, 1.0, 0.1, Vector::new(0.15, 0.6, 0.0));
    let mut set = common::joints(4);
    common::add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Fixed),
        left,
        right,
        |b| {
            b.local_anchor1(Vector::new(0.15, 0.0, 0.0))
                .local_anchor2(Vector::new(-0.15, 0.0, 0.0))
        },
    );
    set.prepare(&mut w);
    let mut summary = Summary::new();
    summary.record(set.time(), &w, &set, &[]).unwrap();
    let mut landed = false;
    // the residual before the first contact: the free fall's
    let mut before = 0.0;
    for _ in 0..60 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        let events = set.drain_events();
        summary.record(set.time(), &w, &set, &events).unwrap();
        let b = summary.balance(0.0);
        // 0.5 m of fall takes 0.319 s
        if set.time() < 0.3 {
            assert_eq!(b.while_contacts_touched, None, "t = {}", set.time());
            // the free fall's integration: the semi-implicit Euler step loses `M·g²·h²/2` a
            // substep (`v += g·h` then `x += v·h`), `M·g²·h·t/2` by `t`
            let drift = 2.0 * 9.81f64.powi(2) * (1.0 / 240.0) * set.time() / 2.0;
            assert!(
                (b.residual + drift).abs() < 1e-3,
                "t = {}: {b:?}",
                set.time()
            );
        }
        landed |= b.while_contacts_touched.is_some();
        if !landed {
            before = b.residual;
        }
    }
    assert!(landed);
    let b = summary.balance(0.0);
    let (r, touched, of) = b.while_contacts_touched.unwrap();
    println!("{b:?}");
    assert!((b.residual + 9.81).abs() < 0.5, "{b:?}");
    // all of it after the fall's own (−0.12 J in 0.3 s)
    assert!(before < -0.1, "{before}");
    assert!((r - (b.residual - before)).abs() < 0.01, "{b:?} {before}");
    assert!(touched > 30 && of == 60, "{touched} of {of}");
    let text = summary.table(0.0);
    assert!(
        text.contains("of it while contacts touched")
            && text.contains("arose while rapier's contacts touched"),
        "{text}"
    );
}
