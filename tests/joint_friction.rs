//! Load-dependent friction of the revolute, cylindrical and translational joints (spec
//! `joint_friction.md`) through the joint set and rapier. A body hangs on the ground by a
//! joint whose axis x is world z; gravity (world −y) is its radial reaction, a torque about
//! world x its bending moment. The free DOF is driven by a slowly ramped force or torque
//! along world z, and the load at the first slipping substep is compared with the bound
//! computed by hand from the specified normal force.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;
use rapier_kjoint::law::{ConnectorError, ConnectorReport, JointFriction, JointFrictionReport};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, FrictionStatus, JointType, KjointHandle, KjointProperty, KjointSet, SimError,
};

const G: f64 = 9.81;
const H: f64 = 1.0 / 240.0;
/// Bearing length `L` [m] and pin radius `R_pin` [m] of every test.
const L: f64 = 0.05;
const R_PIN: f64 = 0.02;

/// What drives the free DOF: a force along the axis or a torque about it.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Drive {
    Force,
    Torque,
}

struct Rig {
    w: PhysicsWorld,
    set: KjointSet,
    body: RigidBodyHandle,
    j: KjointHandle,
    /// Bending torque about world x [N·m], held while driving.
    bend: f64,
}

fn law(joint: JointType, mu: f64) -> JointFriction {
    JointFriction {
        mu,
        pin_radius: if joint == JointType::Translational {
            0.0
        } else {
            R_PIN
        },
        length: L,
        ..Default::default()
    }
}

fn rig(joint: JointType, m: f64, law: JointFriction, bend: f64) -> Rig {
    let (mut w, ground) = common::world(Vector::new(0.0, -G as Real, 0.0));
    let body = common::point_body(
        &mut w,
        m as Real,
        Vector::splat(0.1 * m as Real),
        Vector::ZERO,
    );
    let mut set = common::joints(1);
    let prop = KjointProperty::new(joint).with_critical_damping(0.3);
    // joint x = world z
    let frame = Rotation::from_rotation_y(-std::f64::consts::FRAC_PI_2 as Real);
    let j = common::add(&mut set, &w, prop, ground, body, |b| {
        b.world_frame1(frame).joint_friction(law)
    });
    let mut r = Rig {
        w,
        set,
        body,
        j,
        bend,
    };
    r.load(Drive::Force, 0.0);
    r.settle(1.0);
    r
}

impl Rig {
    fn step(&mut self) {
        self.set.step(&mut self.w, H).unwrap();
    }
    fn settle(&mut self, seconds: f64) {
        for _ in 0..(seconds / H).round() as usize {
            self.step();
        }
    }
    fn report(&self) -> JointFrictionReport {
        match self.set.get(self.j).unwrap().state().unwrap().connector {
            Some(ConnectorReport::JointFriction(r)) => r,
            other => panic!("no joint friction report: {other:?}"),
        }
    }
    fn q(&self) -> [f64; 6] {
        self.set.get(self.j).unwrap().state().unwrap().q.0
    }
    fn rate(&self) -> [f64; 6] {
        self.set.get(self.j).unwrap().state().unwrap().rate.0
    }
    /// Applies the drive `p` along / about world z (the joint's axis) and the bending torque.
    fn load(&mut self, drive: Drive, p: f64) {
        let b = &mut self.w.bodies[self.body];
        b.reset_forces(true);
        b.reset_torques(true);
        let along = Vector::new(0.0, 0.0, p as Real);
        let bend = Vector::new(self.bend as Real, 0.0, 0.0);
        match drive {
            Drive::Force => {
                b.add_force(along, true);
                b.add_torque(bend, true);
            }
            Drive::Torque => b.add_torque(along + bend, true),
        }
    }
    /// Ramps the drive from 0 at `rate` per second until the joint slips; the drive then.
    fn ramp_until_slip(&mut self, drive: Drive, rate: f64) -> f64 {
        for i in 1..40_000 {
            let p = rate * i as f64 * H;
            self.load(drive, p);
            self.step();
            if self.report().sliding == FrictionStatus::Slip {
                return p;
            }
        }
        panic!("never slipped");
    }
    /// The driven DOF's value (`δx` or `θx`).
    fn driven(&self, drive: Drive) -> f64 {
        self.q()[if drive == Drive::Force { 0 } else { 3 }]
    }
}

/// The bound by hand: `F_N = m·g + M_b/L`, times μ, times `R_pin` for a moment.
fn bound(drive: Drive, mu: f64, m: f64, bend: f64) -> f64 {
    let f_n = m * G + bend / L;
    mu * f_n * if drive == Drive::Torque { R_PIN } else { 1.0 }
}

/// Threshold for three normal loads and with a bending moment; stick just below.
fn thresholds(joint: JointType, drive: Drive) {
    let mu = 0.3;
    for (m, bend) in [(1.0, 0.0), (3.0, 0.0), (10.0, 0.0), (3.0, 2.0)] {
        let mut r = rig(joint, m, law(joint, mu), bend);
        let rep = r.report();
        let f_n = m * G + bend / L;
        assert_eq!(rep.sliding, FrictionStatus::Stick);
        assert!(
            (rep.normal_force - f_n).abs() < 1e-3 * f_n,
            "{joint:?} m = {m}, M_b = {bend}: F_N = {}, expected {f_n}",
            rep.normal_force
        );
        let expected = bound(drive, mu, m, bend);
        // Ramped to the bound in 8 s: slow against the stick spring and its damping.
        let p = r.ramp_until_slip(drive, expected / 8.0);
        eprintln!(
            "MEASURED {joint:?} {drive:?} m = {m} kg, M_b = {bend} N·m: slipped at {p:.6}, \
             bound {expected:.6} ({:+.3} %)",
            100.0 * (p / expected - 1.0)
        );
        assert!(
            (p - expected).abs() < 0.01 * expected,
            "{joint:?} {drive:?} m = {m}, M_b = {bend}: slipped at {p}, expected {expected}"
        );
        // Below the bound it sticks: ramped to 95 % in 4 s and held 2 s, it never slips and
        // moves by the stick spring only.
        let mut r = rig(joint, m, law(joint, mu), bend);
        let q0 = r.driven(drive);
        for i in 1..=1440 {
            r.load(drive, 0.95 * expected * (i as f64 / 960.0).min(1.0));
            r.step();
            assert_eq!(
                r.report().sliding,
                FrictionStatus::Stick,
                "{joint:?} {drive:?}"
            );
        }
        assert_eq!(r.report().slip_total, 0.0);
        let k = r.report().stick_stiffness[if drive == Drive::Force { 0 } else { 1 }];
        let moved = (r.driven(drive) - q0).abs();
        assert!(
            moved < 1.01 * 0.95 * expected / k,
            "{joint:?} {drive:?}: moved {moved} while sticking (stick travel {})",
            0.95 * expected / k
        );
    }
}

#[test]
fn revolute_slips_at_mu_r_pin_normal_force() {
    thresholds(JointType::Revolute, Drive::Torque);
}

#[test]
fn translational_slips_at_mu_normal_force() {
    thresholds(JointType::Translational, Drive::Force);
}

#[test]
fn cylindrical_slips_at_mu_normal_force_sliding_and_turning() {
    thresholds(JointType::Cylindrical, Drive::Force);
    thresholds(JointType::Cylindrical, Drive::Torque);
}

/// Above the bound it slips with the acceleration `(P − bound)/m` (or `/I`), and the work of
/// the drive equals the change of kinetic + potential + stored energy plus the dissipated
/// work within 1 %.
fn slip_and_energy(joint: JointType, drive: Drive) {
    let (mu, m, bend) = (0.3, 3.0, 1.0);
    let mut r = rig(joint, m, law(joint, mu), bend);
    let cap = bound(drive, mu, m, bend);
    let e0 = common::total_energy(&r.w, &r.set) + common::dissipated(&r.set);
    let pull = 1.5 * cap;
    r.load(drive, pull);
    let mut work = 0.0;
    let mut x = r.driven(drive);
    let i = if drive == Drive::Force { 2 } else { 5 };
    let mut v0 = 0.0;
    for n in 0..240 {
        r.step();

        let xn = r.driven(drive);
        work += pull * (xn - x);
        x = xn;
        if n == 59 {
            v0 = r.rate()[if drive == Drive::Force { 0 } else { 3 }];
        }
    }
    assert_eq!(r.report().sliding, FrictionStatus::Slip);
    let v1 = r.rate()[if drive == Drive::Force { 0 } else { 3 }];
    let inertia = if drive == Drive::Force { m } else { 0.1 * m };
    let a = (v1 - v0) / (180.0 * H);
    let a_exp = (pull - cap) / inertia;
    eprintln!("MEASURED {joint:?} {drive:?}: a = {a:.5}, expected {a_exp:.5} (index {i})");
    assert!(
        (a.abs() - a_exp).abs() < 0.02 * a_exp,
        "{joint:?} {drive:?}: a = {a}, expected {a_exp}"
    );
    let e1 = common::total_energy(&r.w, &r.set) + common::dissipated(&r.set);
    let e = r.set.get(r.j).unwrap().energy();
    let rep = r.report();
    eprintln!(
        "MEASURED {joint:?} {drive:?}: work {work:.6} J, ΔE {:.6} J, friction {:.6} J, \
         cap·slip {:.6} J",
        e1 - e0,
        e.friction,
        rep.cap * rep.slip_total
    );
    assert!(e.friction > 0.4 * work, "friction {} of {work}", e.friction);
    assert!(
        ((e1 - e0) - work).abs() < 0.01 * work,
        "{joint:?} {drive:?}: ΔE = {}, work = {work}",
        e1 - e0
    );
    // The friction work is the bound times the slip (the bound is constant here).
    assert!(
        (rep.dissipated - rep.cap * rep.slip_total).abs() < 0.01 * rep.dissipated,
        "{} vs {}",
        rep.dissipated,
        rep.cap * rep.slip_total
    );
    let balance = e.elastic + e.dissipated();
    assert!(
        (e.internal - balance).abs() < 0.01 * balance,
        "internal {} vs stored + dissipated {balance}",
        e.internal
    );
}

#[test]
fn revolute_energy_balance_while_slipping() {
    slip_and_energy(JointType::Revolute, Drive::Torque);
}

#[test]
fn translational_energy_balance_while_slipping() {
    slip_and_energy(JointType::Translational, Drive::Force);
}

#[test]
fn cylindrical_energy_balance_while_slipping() {
    slip_and_energy(JointType::Cylindrical, Drive::Force);
    slip_and_energy(JointType::Cylindrical, Drive::Torque);
}

#[test]
fn wrong_joint_type_unused_parameter_or_double_friction_is_a_typed_error() {
    let (mut w, ground) = common::world(Vector::ZERO);
    let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
    let mut set = common::joints(1);
    let mut insert = |prop: KjointProperty, law: JointFriction| {
        set.insert(
            rapier_kjoint::KjointBuilder::new(prop)
                .name("pin")
                .joint_friction(law),
            ground,
            b,
            &w.bodies,
        )
        .unwrap_err()
    };
    let e = insert(
        KjointProperty::new(JointType::Spherical),
        law(JointType::Revolute, 0.2),
    );
    assert!(
        matches!(
            &e,
            SimError::Connector {
                source: ConnectorError::UnsupportedJointType {
                    found: JointType::Spherical,
                    ..
                },
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("pin"), "{e}");
    let e = insert(
        KjointProperty::new(JointType::Translational),
        law(JointType::Revolute, 0.2),
    );
    assert!(e.to_string().contains("pin_radius"), "{e}");
    let ff = KjointProperty::new(JointType::Revolute)
        .with_dof(Dof::Rx, DofLaw::default().with_friction(1e4, 2.0));
    let e = insert(ff, law(JointType::Revolute, 0.2));
    assert!(
        matches!(
            &e,
            SimError::Connector {
                source: ConnectorError::Conflict { .. },
                ..
            }
        ),
        "{e}"
    );
    let nan = JointFriction {
        length: f64::NAN,
        ..law(JointType::Cylindrical, 0.2)
    };
    let e = insert(KjointProperty::new(JointType::Cylindrical), nan);
    assert!(e.to_string().contains("length"), "{e}");
}

/// A hinge and a slider in a scene file, with the `joint_friction` key.
const SCENE: &str = r#"duration = 0.1

[[bodies]]
name = "door"
shape = { type = "cuboid", half_extents = [0.1, 0.1, 0.1] }
mass = 1.0

[[bodies]]
name = "carriage"
shape = { type = "cuboid", half_extents = [0.1, 0.1, 0.1] }
mass = 1.0

[[joints]]
name = "hinge"
body1 = "world"
body2 = "door"
property = { type = "revolute" }
joint_friction = { mu = 0.2, pin_radius = 0.01, length = 0.05, thrust_radius = 0.02 }

[[joints]]
name = "rail"
body1 = "world"
body2 = "carriage"
property = { type = "translational" }
joint_friction = { mu = 0.1, length = 0.3, preload = 5.0, stick_stiffness = 1e5 }
"#;

fn scene_file(name: &str, text: &str) -> std::path::PathBuf {
    common::cli::temp_file("joint-friction", name, text)
}

fn scene_laws(
    name: &str,
    text: &str,
) -> Result<Vec<JointFriction>, rapier_kjoint::scene::SceneError> {
    use rapier_kjoint::law::ConnectorLaw;
    let (sc, src) = rapier_kjoint::scene::load(&scene_file(name, text))?;
    let built = rapier_kjoint::scene::build(&sc, &src)?;
    Ok(built
        .joints
        .iter()
        .map(|(_, j)| match j.connector_law() {
            ConnectorLaw::JointFriction(l) => *l,
            other => panic!("{other:?}"),
        })
        .collect())
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn scene_key_reads_the_law_in_si() {
    let laws = scene_laws("jf.toml", SCENE).unwrap();
    assert_eq!(
        laws[0],
        JointFriction {
            mu: 0.2,
            pin_radius: 0.01,
            length: 0.05,
            thrust_radius: 0.02,
            ..Default::default()
        }
    );
    assert_eq!((laws[1].length, laws[1].preload), (0.3, 5.0));
    // In kg, mm, ms: lengths ×1e-3, forces (kg·mm/ms² = kN) ×1e3, N/mm... (kN/mm = 1e6 N/m).
    let mm = SCENE
        .replace("duration = 0.1", "units = \"kg mm ms\"\nduration = 100")
        .replace(
            "half_extents = [0.1, 0.1, 0.1]",
            "half_extents = [100, 100, 100]",
        )
        .replace(
            "pin_radius = 0.01, length = 0.05, thrust_radius = 0.02",
            "pin_radius = 10, length = 50, thrust_radius = 20",
        )
        .replace(
            "length = 0.3, preload = 5.0, stick_stiffness = 1e5",
            "length = 300, preload = 0.005, stick_stiffness = 0.1",
        );
    let si = scene_laws("jf_mm.toml", &mm).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
    assert!(
        close(si[0].pin_radius, 0.01) && close(si[0].length, 0.05),
        "{si:?}"
    );
    assert!(close(si[0].thrust_radius, 0.02), "{si:?}");
    assert!(
        close(si[1].preload, 5.0) && close(si[1].stick_stiffness, 1e5),
        "{si:?}"
    );
}

#[test]
fn scene_errors_name_the_field_and_line() {
    // A translational joint has no pin radius.
    let t = SCENE.replace(
        "mu = 0.1, length = 0.3",
        "mu = 0.1, pin_radius = 0.01, length = 0.3",
    );
    let e = scene_laws("jf_pin.toml", &t).unwrap_err();
    assert_eq!(e.field, "joints[1].joint_friction.pin_radius", "{e}");
    assert_eq!(e.line, line_of(&t, "mu = 0.1"), "{e}");
    assert!(e.message.contains("0 on a translational joint"), "{e}");
    // Negative, NaN-like and missing values.
    let t = SCENE.replace("mu = 0.2", "mu = -0.2");
    let e = scene_laws("jf_mu.toml", &t).unwrap_err();
    assert_eq!(e.field, "joints[0].joint_friction.mu", "{e}");
    assert!(e.message.contains("expected a value >= 0"), "{e}");
    let t = SCENE.replace("length = 0.05", "length = nan");
    let e = scene_laws("jf_nan.toml", &t).unwrap_err();
    assert_eq!(e.field, "joints[0].joint_friction.length", "{e}");
    let t = SCENE.replace("mu = 0.2, ", "");
    let e = scene_laws("jf_no_mu.toml", &t).unwrap_err();
    assert!(e.message.contains("missing field `mu`"), "{e}");
    // Wrong joint type: the key is named.
    let t = SCENE.replace("type = \"revolute\"", "type = \"spherical\"");
    let e = scene_laws("jf_type.toml", &t).unwrap_err();
    assert_eq!(e.field, "joints[0].joint_friction", "{e}");
    assert!(
        e.message
            .contains("revolute (type 2), cylindrical (type 3) or translational (type 6)"),
        "{e}"
    );
    // Two connector laws on one joint.
    let t = SCENE.replace(
        "joint_friction = { mu = 0.1,",
        "planar_friction = { mu = 0.1 }\njoint_friction = { mu = 0.1,",
    );
    let e = scene_laws("jf_two.toml", &t).unwrap_err();
    assert_eq!(e.field, "joints[1].joint_friction", "{e}");
    assert!(e.message.contains("one connector law"), "{e}");
}

/// The example scene `assets/scenes/joint_friction_axle.toml` through `kjoint run`: a 20 kg
/// wheel on an axle, a 5 N·m bending moment, a driving torque ramped at 1 N·m/s up to 2 N·m.
/// F_N = m·g + M_b/L = 196.2 + 100 = 296.2 N; bound μ·R_pin·F_N = 1.1848 N·m.
#[test]
fn axle_scene_slips_when_the_torque_reaches_the_bound() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes/joint_friction_axle.toml");
    let dir = common::cli::temp_dir("jf-axle");
    let stdout = common::cli::kjoint_run(&scene, Some(&dir), &[] as &[&str]);
    let text = std::fs::read_to_string(dir.join("axle.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let (t, f_n, cap) = (
        col("time"),
        col("joint_friction.normal_force"),
        col("joint_friction.cap"),
    );
    let (m, sliding, w) = (
        col("joint_friction.friction_moment"),
        col("joint_friction.sliding"),
        col("WX"),
    );
    let (f_n_exp, bound) = (20.0 * G + 5.0 / 0.05, 0.2 * 0.02 * (20.0 * G + 5.0 / 0.05));
    let mut first = None;
    for r in &rows {
        if r[t] > 0.6 {
            assert!(
                (r[f_n] - f_n_exp).abs() < 0.01 * f_n_exp,
                "t = {}: F_N = {}",
                r[t],
                r[f_n]
            );
        }
        if r[sliding] == 2.0 {
            first.get_or_insert(r[t]);
            assert!((r[m].abs() - r[cap]).abs() <= 1e-9 * r[cap], "t = {}", r[t]);
        } else {
            assert!(
                r[m].abs() <= r[cap] * (1.0 + 1e-9),
                "t = {}: sticking beyond the cap",
                r[t]
            );
        }
    }
    // T(t) = t N·m reaches the bound at t = 1.1848 s: the first slipping frame.
    let first = first.expect("the wheel turns");
    eprintln!("MEASURED axle: first slip at {first:.5} s, analytic {bound:.5} s");
    assert!(
        (first - bound).abs() <= 1.0 / 60.0,
        "first slip at {first} s, analytic {bound} s"
    );
    // Then it turns with (2 − bound)/I, I = m·(0.2² + 0.2²)/12 (between 2.1 s and 2.9 s).
    let at = |time: f64| rows.iter().find(|r| r[t] >= time).unwrap()[w];
    let a = (at(2.9) - at(2.1))
        / (rows.iter().find(|r| r[t] >= 2.9).unwrap()[t]
            - rows.iter().find(|r| r[t] >= 2.1).unwrap()[t]);
    let a_exp = (2.0 - bound) / (20.0 * 0.08 / 12.0);
    eprintln!("MEASURED axle: angular acceleration {a:.5} rad/s², analytic {a_exp:.5}");
    assert!(
        (a - a_exp).abs() < 0.01 * a_exp,
        "a = {a}, expected {a_exp}"
    );
    // The energy balance of the run closes.
    let residual = stdout
        .lines()
        .find(|l| l.starts_with("  residual "))
        .and_then(|l| l.split('(').nth(1))
        .and_then(|p| p.split_whitespace().next())
        .and_then(|p| p.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(residual.abs() < 1.0, "energy residual {residual} %");
}

/// A 2 kg wheel on a horizontal axle (URDF `continuous`, axis world z) whose URDF friction
/// is a constant 0.5 N·m (`<dynamics friction>`).
const URDF: &str = r#"<robot name="axle">
  <link name="base"/>
  <link name="wheel"><inertial><mass value="2"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="arm"><inertial><mass value="1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="axle" type="continuous"><parent link="base"/><child link="wheel"/>
    <origin xyz="0 1 0"/><axis xyz="0 0 1"/><dynamics friction="0.5"/></joint>
  <joint name="weld" type="fixed"><parent link="wheel"/><child link="arm"/>
    <origin xyz="0 0 0.5"/></joint>
</robot>"#;

fn urdf_options(
    ov: rapier_kjoint::io::urdf::JointOverride,
) -> rapier_kjoint::io::urdf::UrdfOptions {
    // A user Kn: the Radioss rule a friction law keeps for an automatic Kn (spec §4) shares
    // the light wheel's rotational budget (I = 0.01 kg·m²) and gives it only ~56 N/m.
    let mut o = rapier_kjoint::io::urdf::UrdfOptions {
        fixed_base: true,
        kn: 1e6,
        critical_damping: 0.3,
        ..Default::default()
    };
    o.joints.insert("axle".into(), ov);
    o
}

#[test]
fn urdf_option_replaces_the_constant_friction() {
    use rapier_kjoint::io::urdf::JointOverride;
    let law = JointFriction {
        mu: 0.2,
        pin_radius: 0.02,
        length: 0.1,
        ..Default::default()
    };
    let ov = JointOverride {
        joint_friction: Some(law),
        ..Default::default()
    };
    let (mut w, _) = common::world(Vector::new(0.0, -G as Real, 0.0));
    let mut set = common::joints(1);
    let h = common::robot::insert_urdf_str(URDF, "axle.urdf", &mut w, &mut set, &urdf_options(ov))
        .unwrap();
    let j = h.joints["axle"];
    let wheel = h.links["wheel"];
    // The URDF's constant 0.5 N·m is dropped: the law replaces it.
    assert_eq!(
        set.get(j).unwrap().property().dofs[Dof::Rx.index()].friction,
        0.0
    );
    for _ in 0..240 {
        set.step(&mut w, H).unwrap();
    }
    // F_N = weight of wheel and arm (the welded 1 kg arm 0.5 m along the axle bends the
    // pin by 1·g·0.5 N·m): 3·g + 4.905/0.1.
    let r = match set.get(j).unwrap().state().unwrap().connector {
        Some(ConnectorReport::JointFriction(r)) => r,

        other => panic!("{other:?}"),
    };
    let f_n = 3.0 * G + 1.0 * G * 0.5 / 0.1;
    assert!(
        (r.normal_force - f_n).abs() < 0.01 * f_n,
        "F_N = {}, expected {f_n}",
        r.normal_force
    );
    let bound = 0.2 * 0.02 * f_n;
    let mut slipped = None;
    for i in 1..20_000 {
        let t = bound / 8.0 * i as f64 * H;
        let b = &mut w.bodies[wheel];
        b.reset_torques(true);
        b.add_torque(Vector::new(0.0, 0.0, t as Real), true);
        set.step(&mut w, H).unwrap();
        if set.get(j).unwrap().state().unwrap().status[3].friction == FrictionStatus::Slip {
            slipped = Some(t);
            break;
        }
    }
    let t = slipped.expect("never slipped");
    eprintln!("MEASURED URDF axle: slipped at {t:.6} N·m, bound {bound:.6} N·m");
    assert!(
        (t - bound).abs() < 0.01 * bound,
        "slipped at {t}, bound {bound}"
    );
}

#[test]
fn urdf_option_errors_name_the_field() {
    use rapier_kjoint::io::urdf::JointOverride;
    let law = JointFriction {
        mu: 0.2,
        pin_radius: 0.02,
        ..Default::default()
    };
    let err = |ov: JointOverride| {
        let (mut w, _) = common::world(Vector::ZERO);
        let mut set = common::joints(1);
        common::robot::insert_urdf_str(URDF, "axle.urdf", &mut w, &mut set, &urdf_options(ov))
            .unwrap_err()
            .to_string()
    };
    let e = err(JointOverride {
        joint_friction: Some(JointFriction {
            pin_radius: 0.0,
            ..law
        }),
        ..Default::default()
    });
    assert!(
        e.contains("joint_friction.pin_radius") && e.contains("axle.urdf"),
        "{e}"
    );
    let e = err(JointOverride {
        joint_friction: Some(law),
        friction: Some(0.3),
        ..Default::default()
    });
    assert!(
        e.contains("joint_friction") && e.contains("no `friction` beside it"),
        "{e}"
    );
    let e = err(JointOverride {
        joint_friction: Some(JointFriction {
            mu: f64::NAN,
            ..law
        }),
        ..Default::default()
    });
    assert!(e.contains("joint_friction.mu"), "{e}");
}
