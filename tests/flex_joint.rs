//! The riser flex joint (spec `flex_joint.md`) on a spherical KJOINT2 joint, through the joint
//! set and rapier: a rigid riser segment (1000 kg, 1000 kg·m²) hangs from the fixed ground
//! by a flex joint whose x axis (the riser axis) points down; torques applied to the segment
//! load the joint, with viscous damping on the rotations so that it settles.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;
use rapier_kjoint::io::riser::RiserDeck;
use rapier_kjoint::law::{ConnectorError, ConnectorReport, FlexJointReport, FlexPhase};
use rapier_kjoint::law::{ConnectorEventKind, FlexJointSwitchCause};
use rapier_kjoint::law::{Curve, FlexJointLaw, FlexProAdd};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, JointType, KjointBuilder, KjointHandle, KjointProperty, KjointSet, SimError,
};

const H: f64 = 1.0 / 240.0;
const INERTIA: Real = 1000.0;

/// `*SPRINGPRO 3 3 0 0 0.00872665 25000 0.0174533 35000`.
fn law3() -> Curve {
    Curve::new([(0.0, 0.0), (0.00872665, 25000.0), (0.0174533, 35000.0)]).unwrap()
}

/// Inverse of `law3` \[rad\] for a moment \[N·m\] below 35 kN·m.
fn law3_inverse(m: f64) -> f64 {
    if m <= 25000.0 {
        m / 25000.0 * 0.00872665
    } else {
        0.00872665 + (m - 25000.0) / 10000.0 * (0.0174533 - 0.00872665)
    }
}

/// `*FLEXPROADD 2 5.72958e8 1 4.0107e6 1.718873e6 1.74533e-3 0 3.008e6` (examples 2, 3).
fn proadd() -> FlexProAdd {
    FlexProAdd {
        torsion_stiffness: 5.72958e8,
        iflag: 1,
        kdyn_ini: 4.0107e6,
        kdyn_lim: 1.718873e6,
        angle_lim: 1.74533e-3,
        teta: 0.0,
        torsion_damping: 3.008e6,
    }
}

/// Joint frame: x (riser axis) = world −y, y = world +x, z = world z.
fn riser_frame() -> Rotation {
    Rotation::from_rotation_z(-std::f64::consts::FRAC_PI_2 as Real)
}

/// Local (x, y, z) joint-frame vector → world.
fn world(v: [f64; 3]) -> Vector {
    Vector::new(v[1] as Real, -v[0] as Real, v[2] as Real)
}

struct Scene {
    w: PhysicsWorld,
    set: KjointSet,
    riser: RigidBodyHandle,
    j: KjointHandle,
}

/// Viscosities `c` \[N·m·s/rad\] on (θx, θy, θz).
fn scene(law: FlexJointLaw, c: [f64; 3], f: impl FnOnce(KjointBuilder) -> KjointBuilder) -> Scene {
    let (mut w, ground) = common::world(Vector::ZERO);
    let riser = common::point_body(&mut w, 1000.0, Vector::splat(INERTIA), Vector::ZERO);
    let mut set = common::joints(1);
    let prop = KjointProperty::new(JointType::Spherical)
        .with_dof(Dof::Rx, DofLaw::default().with_viscosity(c[0]))
        .with_dof(Dof::Ry, DofLaw::default().with_viscosity(c[1]))
        .with_dof(Dof::Rz, DofLaw::default().with_viscosity(c[2]));
    let j = common::add(&mut set, &w, prop, ground, riser, |b| {
        f(b.world_frame1(riser_frame()).flex_joint(law))
    });
    Scene { w, set, riser, j }
}

impl Scene {
    fn step(&mut self) {
        self.set.step(&mut self.w, H).unwrap();
    }
    fn run(&mut self, seconds: f64) {
        for _ in 0..(seconds / H).round() as usize {
            self.step();
        }
    }
    fn torque(&mut self, local: [f64; 3]) {
        let b = &mut self.w.bodies[self.riser];
        b.reset_torques(true);
        b.add_torque(world(local), true);
    }
    fn theta(&self) -> [f64; 3] {
        let q = self.set.get(self.j).unwrap().state().unwrap().q;
        [q[3], q[4], q[5]]
    }
    fn report(&self) -> FlexJointReport {
        match self.set.get(self.j).unwrap().state().unwrap().connector {
            Some(ConnectorReport::FlexJoint(r)) => r,
            other => panic!("no flex joint report: {other:?}"),
        }
    }
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

#[test]
fn slow_bending_sweep_reproduces_the_springpro_table() {
    // Bending in the direction (0.6, −0.8) of the y-z plane, staircase of torques held
    // 1.5 s each (critical damping of the first slope: 2·√(2.9e6·1000) ≈ 1.1e5).
    let law = FlexJointLaw::new(Some(law3()), None, Some(proadd())).unwrap();
    let mut s = scene(law, [1e7, 1e5, 1e5], |b| b);
    let dir = [0.6, -0.8];
    for m in [12500.0, 25000.0, 30000.0, 35000.0] {
        s.torque([0.0, m * dir[0], m * dir[1]]);
        s.run(1.5);
        let r = s.report();
        assert_eq!(r.phase, FlexPhase::QuasiStatic);
        let th = s.theta();
        let beta = (th[1] * th[1] + th[2] * th[2]).sqrt();
        let expected = law3_inverse(m);
        eprintln!("MEASURED M = {m}: β = {beta:.7e}, table {expected:.7e}");
        assert!(
            (beta - expected).abs() < 0.005 * expected,
            "M = {m}: β = {beta}, table {expected}"
        );
        assert!((r.bending_angle - beta).abs() < 1e-12);
        let bm = (r.bending_moment[0].powi(2) + r.bending_moment[1].powi(2)).sqrt();
        assert!((bm - m).abs() < 0.005 * m, "moment {bm}");
        // Bending axis along the moment, tilt direction perpendicular to it.
        assert!((r.bending_axis[0] - dir[0]).abs() < 1e-3);
        assert!((r.bending_axis[1] - dir[1]).abs() < 1e-3);
        assert!((r.tilt_direction[0] * dir[0] + r.tilt_direction[1] * dir[1]).abs() < 1e-3);
        // The torsion does not move (linear Ktor, no torsion load).
        assert!(th[0].abs() < 1e-9);
    }
    // Static phase is elastic: stored energy = area under the table at β = 1°.
    let area = 0.5 * 0.00872665 * 25000.0 + 0.5 * 60000.0 * (0.0174533 - 0.00872665);
    assert!((s.report().stored - area).abs() < 0.01 * area);
}

#[test]
fn classical_mode_acts_on_the_total_angle() {
    let law = FlexJointLaw::new(Some(law3()), None, None).unwrap();
    let c = 1.2e5;
    let mut s = scene(law, [c, c, c], |b| b);
    // Torsion and bending together, |T| = 30 kN·m along (1, 1, 0)/√2, beyond the knee of the
    // law at 25 kN·m. On the total angle: |θ| = law3⁻¹(30 kN·m) = 0.01309 rad along T.
    // The same law applied to bending and torsion separately would give
    // √2·law3⁻¹(21.2 kN·m) = 0.01047 rad.
    let u = std::f64::consts::FRAC_1_SQRT_2;
    let t = 30000.0;
    s.torque([t * u, t * u, 0.0]);
    s.run(3.0);
    let th = s.theta();
    let expected = law3_inverse(t);
    let decoupled = law3_inverse(t * u) * 2f64.sqrt();
    assert!((expected - decoupled).abs() > 0.1 * expected);
    assert!(
        (norm(th) - expected).abs() < 0.005 * expected,
        "|θ| = {}",
        norm(th)
    );
    assert!((th[0] - th[1]).abs() < 1e-3 * expected && th[2].abs() < 1e-3 * expected);
    let r = s.report();
    assert!((r.torsion_moment - t * u).abs() < 0.005 * t);
}

#[test]
fn torsion_follows_its_own_law() {
    let tor = Curve::new([(0.0, 0.0), (0.01, 1000.0), (0.02, 1500.0)]).unwrap();
    let law = FlexJointLaw::new(Some(law3()), Some(tor), None).unwrap();
    // Torsion: 1.0e5 N·m/rad first slope, critical damping 2·√(1e5·1000) = 2e4.
    let mut s = scene(law, [2e4, 1.2e5, 1.2e5], |b| b);
    s.torque([1250.0, 25000.0, 0.0]);
    s.run(4.0);
    let th = s.theta();
    assert!((th[0] - 0.015).abs() < 0.005 * 0.015, "θx = {}", th[0]);
    assert!(
        (th[1] - 0.00872665).abs() < 0.005 * 0.00872665,
        "θy = {}",
        th[1]
    );
    // Reversed torsion: odd extension.
    s.torque([-500.0, 25000.0, 0.0]);
    s.run(4.0);
    let th = s.theta();
    assert!((th[0] + 0.005).abs() < 0.005 * 0.005, "θx = {}", th[0]);
    assert!((th[1] - 0.00872665).abs() < 0.005 * 0.00872665);
    let r = s.report();
    assert!((r.torsion_moment + 500.0).abs() < 5.0);
}

#[test]
fn linear_torsion_with_damping_cp() {
    // IMAT with IPROT = 0: M_x = Ktor·θx + CP·θ̇x (deck example 3: no IPRO).
    let law = FlexJointLaw::new(None, None, Some(proadd())).unwrap();
    let mut s = scene(law, [0.0, 1.3e5, 1.3e5], |b| b);
    let t = 2.0e5;
    s.torque([t, 0.0, 0.0]);
    s.step();
    s.step();
    let st = s.set.get(s.j).unwrap().state().unwrap();
    let (thx, w) = (st.q[3], st.rate[3]);
    let r = s.report();
    let expected = 5.72958e8 * thx + 3.008e6 * w;
    assert!((r.torsion_moment - expected).abs() < 1e-9 * expected.abs().max(1.0));
    assert!((st.parts[3].damping - 3.008e6 * w).abs() < 1e-9 * (3.008e6 * w).abs());
    s.run(2.0);
    let thx = s.theta()[0];
    assert!(
        (thx - t / 5.72958e8).abs() < 0.005 * t / 5.72958e8,
        "θx = {thx}"
    );
    let r = s.report();
    assert!(r.dissipated_damping > 0.0);
    let e = s.set.get(s.j).unwrap().energy();
    assert!((e.damping - r.dissipated_damping).abs() < 1e-9 * e.damping);
}

/// Runs the static phase at `static_moment`, switches at `t_switch`, then a cyclic bending
/// torque of amplitude `amp` about the joint's y axis with period `period`; returns the
/// report sequence of the second full cycle as (variation, report).
fn cyclic(
    law: FlexJointLaw,
    static_moment: f64,
    amp: f64,
    period: f64,
) -> (Scene, Vec<(f64, FlexJointReport)>) {
    let t_switch = 2.0;
    let mut s = scene(law, [1e7, 4e4, 4e4], |b| b.flex_joint_switch_time(t_switch));
    // Static ramp to the static moment over 1 s, hold until the switch.
    for i in 0..(1.0 / H) as usize {
        s.torque([0.0, static_moment * (i as f64 * H), 0.0]);
        s.step();
    }
    s.torque([0.0, static_moment, 0.0]);
    while s.set.time() < t_switch - 0.5 * H {
        s.step();
    }
    assert_eq!(s.report().phase, FlexPhase::QuasiStatic);
    s.step();
    let r = s.report();
    assert_eq!(r.phase, FlexPhase::Dynamic);
    assert!((r.switched_at.unwrap() - t_switch).abs() < 1e-9);
    let events = s.set.get(s.j).unwrap().connector_events().to_vec();
    assert_eq!(events.len(), 1);
    assert!((events[0].time - t_switch).abs() < 1e-9, "{events:?}");
    let b_s = s.theta()[1];
    let t0 = s.set.time();
    let n = (period / H).round() as usize;
    let mut second = Vec::new();
    for i in 0..2 * n {
        let t = s.set.time() - t0;
        let m = static_moment + amp * (std::f64::consts::TAU * t / period).sin();
        s.torque([0.0, m, 0.0]);
        s.step();
        if i >= n {
            second.push((s.theta()[1] - b_s, s.report()));
        }
    }
    (s, second)
}

#[test]
fn cyclic_bending_closes_a_loop_of_the_analytic_area() {
    let d = proadd();
    // Tip moment of a cycle of amplitude 3·φy: My + Kdyn_lim·2φy ≈ 13.0 kN·m.
    let amp = d.yield_moment() + d.kdyn_lim * 2.0 * d.angle_lim;
    for law in [
        FlexJointLaw::new(Some(law3()), None, Some(d)).unwrap(),
        FlexJointLaw::new(None, None, Some(d)).unwrap(),
    ] {
        let static_moment = if law.bending.is_some() {
            20000.0
        } else {
            5000.0
        };
        let (s, cycle) = cyclic(law, static_moment, amp, 4.0);
        let max = cycle.iter().map(|c| c.0).fold(f64::MIN, f64::max);
        let min = cycle.iter().map(|c| c.0).fold(f64::MAX, f64::min);
        let a = 0.5 * (max - min);
        assert!(
            (a - 3.0 * d.angle_lim).abs() < 0.05 * 3.0 * d.angle_lim,
            "a = {a}"
        );
        assert!(
            (max + min).abs() < 0.02 * a,
            "loop not centred: {max}, {min}"
        );
        let dissipated = cycle.last().unwrap().1.dissipated_hysteresis
            - cycle.first().unwrap().1.dissipated_hysteresis;
        let area = d.loop_area(a);
        eprintln!(
            "MEASURED a = {a:.6e} (3φy = {:.6e}), D = {dissipated:.4} J, area = {area:.4} J",
            3.0 * d.angle_lim
        );
        assert!(
            (dissipated - area).abs() < 0.02 * area,
            "dissipated {dissipated} J, loop area {area} J (a = {a})"
        );
        // The loop closes: same moment at the start and the end of the cycle.
        let (m0, m1) = (
            cycle.first().unwrap().1.bending_moment[0],
            cycle.last().unwrap().1.bending_moment[0],
        );
        assert!((m0 - m1).abs() < 0.01 * amp, "{m0} vs {m1}");
        assert!(cycle.iter().any(|c| c.1.yielding));
        // Booked as plastic work in the joint's energy.
        let e = s.set.get(s.j).unwrap().energy();
        let r = s.report();
        assert!((e.friction - r.dissipated_hysteresis).abs() < 1e-9 * e.friction);
        // Internal work ∫F·dq of the joint = stored + dissipated (trapezoidal: ≈).
        let balance = e.elastic + e.dissipated();
        assert!(
            (e.internal - balance).abs() < 0.01 * balance,
            "internal {} vs stored + dissipated {balance}",
            e.internal
        );
    }
}

#[test]
fn explicit_switch_and_wrong_joint_type() {
    let law = FlexJointLaw::new(Some(law3()), None, Some(proadd())).unwrap();
    let mut s = scene(law.clone(), [1e7, 1e5, 1e5], |b| b);
    s.torque([0.0, 10000.0, 0.0]);
    s.run(1.0);
    assert!(s.set.switch_flex_joint(s.j).unwrap());
    assert!(!s.set.switch_flex_joint(s.j).unwrap());
    s.run(0.5);
    let r = s.report();
    assert_eq!(r.phase, FlexPhase::Dynamic);
    assert!((r.switched_at.unwrap() - 1.0).abs() < 1e-9);
    // Same torque: the dynamic law keeps the static point (no jump).
    assert!((r.bending_moment[0] - 10000.0).abs() < 0.01 * 10000.0);
    let ev = s.set.get(s.j).unwrap().connector_events();
    assert_eq!(
        ev[0].kind,
        ConnectorEventKind::FlexJointSwitched {
            cause: FlexJointSwitchCause::ExplicitCall
        },
        "{ev:?}"
    );
    assert!((ev[0].time - 1.0).abs() < 1e-9, "{ev:?}");

    let (w, ground) = common::world(Vector::ZERO);
    let mut w = w;
    let b = common::point_body(&mut w, 1.0, Vector::splat(1.0), Vector::ZERO);
    let mut set = common::joints(1);
    let e = set
        .insert(
            KjointBuilder::new(KjointProperty::new(JointType::Planar)).flex_joint(law),
            ground,
            b,
            &w.bodies,
        )
        .unwrap_err();
    assert!(
        matches!(
            &e,
            SimError::Connector {
                source: ConnectorError::WrongJointType {
                    required: JointType::Spherical,
                    ..
                },
                ..
            }
        ),
        "{e}"
    );
    // A joint without a flex joint law cannot be switched.
    let j = set
        .insert(
            KjointBuilder::new(KjointProperty::new(JointType::Spherical)),
            ground,
            b,
            &w.bodies,
        )
        .unwrap();
    assert!(set.switch_flex_joint(j).is_err());
}

#[test]
fn riser_decks_build_flex_joints() {
    let dir = format!("{}/assets/decks", env!("CARGO_MANIFEST_DIR"));
    // (deck, bending moment applied, expected static bending angle)
    let cases = [
        ("flexjoint_example1.dat", 5.0e8, 0.0174533 * 0.5),
        ("flexjoint_example2.dat", 25000.0, 0.00872665),
        // IPRO = 0: bilinear in the static phase too; 5 kN·m < My = 7.0 kN·m is elastic.
        ("flexjoint_example3.dat", 5000.0, 5000.0 / 4.0107e6),
    ];
    let mut dts: Vec<f64> = Vec::new();
    for (name, m, expected) in cases {
        let deck = RiserDeck::from_file(format!("{dir}/{name}")).unwrap();
        let el = &deck.joints[0];
        let (mut w, ground) = common::world(Vector::ZERO);
        let riser = common::point_body(&mut w, 1000.0, Vector::splat(INERTIA), Vector::ZERO);
        let mut set = common::joints(1);
        let k0 = el.law.bending.as_ref().map_or(4.0107e6, |c| c.slope(0.0));
        let c = 2.0 * (k0 * INERTIA as f64).sqrt();
        let prop = KjointProperty::new(JointType::Spherical)
            .with_dof(Dof::Ry, DofLaw::default().with_viscosity(c));
        let b = el.joint_builder(prop).world_frame1(riser_frame());
        let j = set.insert(b, ground, riser, &w.bodies).unwrap();
        let mut s = Scene { w, set, riser, j };
        assert_eq!(s.set.get(j).unwrap().name, format!("FLEXJOINT {}", el.id));
        s.torque([0.0, m, 0.0]);
        s.run(1.5);
        let th = s.theta()[1];
        assert!(
            (th - expected).abs() < 0.005 * expected,
            "{name}: θy = {th}, expected {expected}"
        );
        dts.push(s.set.stable_dt(j, &s.w.bodies).unwrap().rotational);
    }
    // The explicit stable step sees the flex joint's stiffness: 1e9/0.0174533 N·m/rad for
    // example 1, Ktor = 5.73e8 for example 3 (the rotational bound √(2I/S_r)):
    // ratio √100 = 10.
    eprintln!("MEASURED stable dt {dts:?}");
    assert!((dts[2] / dts[0] - 10.0).abs() < 0.01 * 10.0, "{dts:?}");
}

/// Issue 12, item 9: the bending angle is the angle between the two bodies' axes
/// (flex_joint.md), in any direction and with any torsion. At the relative rotation whose
/// rotation vector is θ = (1, 0.1, 0) (1 rad of torsion about the riser axis x, 0.1 about y)
/// the riser axis is tilted by acos(x·R·x) = 0.0958812 rad; the rotation vector's
/// √(θy² + θz²) = 0.1 was 4 % too large. The torsion is the twist left after the swing.
#[test]
fn bending_angle_is_the_angle_between_the_axes() {
    let torsion = Curve::new([(0.0, 0.0), (1.0, 1e3)]).unwrap();
    let law = FlexJointLaw::new(Some(law3()), Some(torsion), None).unwrap();
    let mut s = scene(law, [0.0; 3], |b| b);
    // the relative rotation in the joint frame, turned into world by the joint frame
    let rel = nalgebra::UnitQuaternion::from_scaled_axis(nalgebra::Vector3::new(1.0, 0.1, 0.0));
    let f = riser_frame();
    let r = f * Rotation::from_scaled_axis(Vector::new(1.0, 0.1, 0.0)) * f.inverse();
    s.w.bodies[s.riser].set_rotation(r, true);
    s.set.step(&mut s.w, 1e-9).unwrap();
    let x = nalgebra::Vector3::x();
    let expected = (x.dot(&(rel * x))).clamp(-1.0, 1.0).acos();
    assert!((expected - 0.0958812).abs() < 1e-6, "{expected}");
    let b = s.report().bending_angle;
    assert!(
        (b - expected).abs() < 1e-6,
        "bending angle {b}, expected {expected}"
    );
    // the swing-twist split: the twist is what is left about x after the swing
    let swing = nalgebra::UnitQuaternion::rotation_between(&x, &(rel * x)).unwrap();
    let twist = swing.inverse() * rel;
    let tw = 2.0 * twist.i.atan2(twist.w);
    let t = s.report().torsion_angle;
    assert!((t - tw).abs() < 1e-6, "torsion {t}, expected {tw}");
}

/// A flex joint given no frame, its anchors meeting, takes the world axes: on a riser
/// segment hanging along −y (its centre of mass 5 m below the joint) the axis x points
/// across the riser, and a moment that bends it (about world x) is read as torsion (what an
/// offshore engineer saw: the bending angle 0, the torsion angle on `Ktor`, exit 0). That is
/// warned of at the first substep, naming the axis and the 90°; with the riser's frame (x
/// down the riser) the same moment bends the joint, and nothing is warned of.
/// A 1000 kg riser segment whose centre of mass hangs 5 m below the world origin, on a flex
/// joint of `law` at the origin (the anchors meeting there), with the riser's frame (x down
/// it) where `framed`, else none (the world axes).
fn hanging_riser(
    law: FlexJointLaw,
    prop: KjointProperty,
    framed: bool,
) -> (PhysicsWorld, KjointSet, RigidBodyHandle, KjointHandle) {
    let (mut w, ground) = common::world(Vector::ZERO);
    let riser = common::point_body(
        &mut w,
        1000.0,
        Vector::splat(INERTIA),
        Vector::new(0.0, -5.0, 0.0),
    );
    let mut set = common::joints(1);
    let j = common::add(&mut set, &w, prop, ground, riser, |b| {
        let b = b.local_anchor2(Vector::new(0.0, 5.0, 0.0)).flex_joint(law);
        if framed {
            b.world_frame1(riser_frame())
        } else {
            b
        }
    });
    (w, set, riser, j)
}

#[test]
fn a_flex_joint_whose_axis_points_across_its_riser_is_warned_of() {
    use rapier_kjoint::dynamics::{KjointEventKind, Severity};
    let law = FlexJointLaw::new(Some(law3()), None, Some(proadd())).unwrap();
    for framed in [false, true] {
        let prop = KjointProperty::new(JointType::Spherical)
            .with_dof(Dof::Rx, DofLaw::default().with_viscosity(1e6))
            .with_dof(Dof::Ry, DofLaw::default().with_viscosity(1e6))
            .with_dof(Dof::Rz, DofLaw::default().with_viscosity(1e6));
        let (mut w, mut set, riser, j) = hanging_riser(law.clone(), prop, framed);
        // 20 kN·m about world x: bending (0.4°, 6.98 mrad on law3) when x is down the riser,
        // torsion (20 kN·m / 5.73e8 N·m/rad = 3.5e-5 rad) when it is world x
        w.bodies[riser].add_torque(Vector::new(20000.0, 0.0, 0.0), true);
        let mut warned = Vec::new();
        for _ in 0..(2.0 / H) as usize {
            set.step(&mut w, H).unwrap();
            warned.extend(
                (set.drain_events().into_iter())
                    .filter(|e| matches!(e.kind, KjointEventKind::FlexJointAxisAcross { .. })),
            );
        }
        let s = set.get(j).unwrap().state().unwrap();
        let report = match &s.connector {
            Some(ConnectorReport::FlexJoint(r)) => *r,
            other => panic!("no flex joint report: {other:?}"),
        };
        println!(
            "framed {framed}: bending {:.6} rad, torsion {:.3e} rad, {warned:?}",
            report.bending_angle, report.torsion_angle
        );
        if framed {
            assert!(warned.is_empty(), "{warned:?}");
            assert!(
                (report.bending_angle - law3_inverse(20000.0)).abs() < 2e-5,
                "bending {} rad",
                report.bending_angle
            );
        } else {
            // what the warning is about: the bending moment went to the torsion stiffness
            assert!(
                report.bending_angle.abs() < 1e-6,
                "{}",
                report.bending_angle
            );
            assert!(
                report.torsion_angle.abs() > 1e-5,
                "{}",
                report.torsion_angle
            );
            assert_eq!(warned.len(), 1, "{warned:?}");
            assert_eq!(warned[0].kind.severity(), Severity::Warning);
            let KjointEventKind::FlexJointAxisAcross { axis, angle } = warned[0].kind else {
                unreachable!()
            };
            assert!((axis[0] - 1.0).abs() < 1e-9, "{axis:?}");
            assert!((angle.to_degrees() - 90.0).abs() < 1e-6, "{angle}");
            assert!(warned[0]
                .to_string()
                .contains("give the joint's frame with x along the riser"));
        }
    }
    // a classical law (the bending law alone) acts on the total rotation angle whatever the
    // axes: no warning without a frame
    let classical = FlexJointLaw::new(Some(law3()), None, None).unwrap();
    let prop = KjointProperty::new(JointType::Spherical);
    let (mut w, mut set, _, _) = hanging_riser(classical, prop, false);
    for _ in 0..10 {
        set.step(&mut w, H).unwrap();
    }
    let events = set.drain_events();
    assert!(
        !(events.iter()).any(|e| matches!(e.kind, KjointEventKind::FlexJointAxisAcross { .. })),
        "{events:?}"
    );
}
