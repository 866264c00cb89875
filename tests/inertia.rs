//! Inertia tensors of URDF links and MJCF bodies: what rapier simulates is the tensor the
//! file gives (turned into the link's frame), for tensors with equal principal moments and
//! tiny CAD-exported ones, which parry's f32 diagonalisation got wrong; a wheel spun up by a
//! known torque turns at `ω = T·t/I`.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobotHandles};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::KjointSet;

/// A symmetric tensor from `[ixx, iyy, izz, ixy, ixz, iyz]`.
fn tensor(t: [f64; 6]) -> Matrix3<f64> {
    let [xx, yy, zz, xy, xz, yz] = t;
    Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
}

/// The world inertia tensor of a body about its centre of mass, as rapier simulates it.
fn world_inertia(b: &RigidBody) -> Matrix3<f64> {
    let i = b
        .mass_properties()
        .local_mprops
        .reconstruct_inertia_matrix();
    let local = Matrix3::from_fn(|r, k| i.col(k)[r] as f64);
    let q = b.position().rotation;
    let rot = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        q.w as f64, q.x as f64, q.y as f64, q.z as f64,
    ))
    .to_rotation_matrix();
    rot.matrix() * local * rot.matrix().transpose()
}

/// `|a − b|` over the largest term of `b`.
fn relative(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    (a - b).abs().max() / b.abs().max()
}

/// A URDF wheel on a continuous joint about x at (0, 0, 1) of a fixed base, its inertia
/// `inertia` (`ixx iyy izz ixy ixz iyz`) at `rpy`, with `collisions` on it.
fn wheel_urdf(inertia: [f64; 6], rpy: &str, collisions: &str) -> String {
    let [xx, yy, zz, xy, xz, yz] = inertia;
    format!(
        r#"<robot name="wheel">
  <link name="base"><inertial><mass value="10"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="wheel"><inertial><origin xyz="0 0 0" rpy="{rpy}"/><mass value="2"/>
    <inertia ixx="{xx:e}" iyy="{yy:e}" izz="{zz:e}" ixy="{xy:e}" ixz="{xz:e}" iyz="{yz:e}"/></inertial>
    {collisions}</link>
  <joint name="axle" type="continuous">
    <parent link="base"/><child link="wheel"/>
    <origin xyz="0 0 1" rpy="0.3 -0.2 0.1"/>
    <axis xyz="1 0 0"/>
  </joint>
</robot>"#
    )
}

/// A rotated cylinder (along the wheel's x) and a box beside it: the wheel's colliders,
/// massless, away from its origin.
const WHEEL_COLLISIONS: &str = r#"
    <collision><origin xyz="0.01 0 0" rpy="0 1.5707963267948966 0"/><geometry><cylinder radius="0.3" length="0.05"/></geometry></collision>
    <collision><origin xyz="0 0.2 0.1"/><geometry><box size="0.02 0.02 0.02"/></geometry></collision>"#;

fn load_urdf(text: &str) -> (PhysicsWorld, KjointSet, UrdfRobotHandles) {
    let (mut world, _) = common::world(Vector::ZERO);
    let mut joints = common::joints(4);
    let robot = common::robot::insert_urdf_str(
        text,
        "wheel.urdf",
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    )
    .expect("loads");
    (world, joints, robot)
}

/// Spins the body `wheel` up under the torque `torque` N·m about the (world) axis `axis` for
/// `secs` s; its angular speed about that axis.
fn spin_up(
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    wheel: RigidBodyHandle,
    axis: Vector3<f64>,
    torque: f64,
    secs: f64,
) -> f64 {
    let dt = 1.0 / 60.0;
    let t = axis * torque;
    for _ in 0..(secs / dt).round() as usize {
        let b = &mut world.bodies[wheel];
        b.reset_torques(true);
        b.add_torque(Vector::new(t.x as Real, t.y as Real, t.z as Real), true);
        joints.step(world, dt).unwrap();
    }
    let w = world.bodies[wheel].angvel();
    Vector3::new(w.x as f64, w.y as f64, w.z as f64).dot(&axis)
}

/// The world direction of the joint `axle`'s axis (its frame's x).
fn axle_axis(world: &PhysicsWorld, wheel: RigidBodyHandle) -> Vector3<f64> {
    // the joint frame is the wheel's frame at load (URDF: the child link's frame)
    let q = world.bodies[wheel].position().rotation;
    let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        q.w as f64, q.x as f64, q.y as f64, q.z as f64,
    ));
    q * Vector3::x()
}

#[test]
fn a_urdf_wheel_spins_up_at_torque_times_time_over_its_axial_inertia() {
    // ixx = 0.1, iyy = izz = 0.05 (a wheel about x): ω = T·t/Ixx = 1 · 3 / 0.1 = 30 rad/s
    for (collisions, what) in [("", "no collider"), (WHEEL_COLLISIONS, "colliders")] {
        let text = wheel_urdf([0.1, 0.05, 0.05, 0.0, 0.0, 0.0], "0 0 0", collisions);
        let (mut world, mut joints, robot) = load_urdf(&text);
        let wheel = robot.links["wheel"];
        let axis = axle_axis(&world, wheel);
        let w = spin_up(&mut world, &mut joints, wheel, axis, 1.0, 3.0);
        println!("URDF wheel ({what}): ω = {w:.3} rad/s (T·t/I = 30)");
        assert!(
            (w / 30.0 - 1.0).abs() < 0.01,
            "{what}: ω = {w} rad/s, not 30"
        );
        assert!(
            !robot.notices.iter().any(|n| n.contains("diagonalise")),
            "{:?}",
            robot.notices
        );
    }
}

#[test]
fn an_mjcf_fullinertia_wheel_spins_up_at_torque_times_time_over_its_axial_inertia() {
    // the same wheel in MJCF, its tensor as `fullinertia` (off-diagonal terms about a tilted
    // axis too); with geoms away from its origin
    let geoms = r#"<geom type="cylinder" size="0.3 0.025" pos="0.01 0 0" euler="0 90 0"/>
           <geom type="box" size="0.01 0.01 0.01" pos="0 0.2 0.1"/>"#;
    for (tilt, geoms) in [
        ([0.0, 0.0, 0.0], ""),
        ([0.0, 0.0, 0.0], geoms),
        ([0.4, -0.3, 0.2], ""),
        ([0.4, -0.3, 0.2], geoms),
    ] {
        let tilt = Rotation3::from_euler_angles(tilt[0], tilt[1], tilt[2]);
        let t =
            tilt.matrix() * tensor([0.1, 0.05, 0.05, 0.0, 0.0, 0.0]) * tilt.matrix().transpose();
        let axis = tilt * Vector3::x();
        let text = format!(
            r#"<mujoco model="wheel"><worldbody><body name="wheel" pos="0 0 1">
  <joint name="axle" type="hinge" axis="{} {} {}"/>
  <inertial pos="0 0 0" mass="2" fullinertia="{} {} {} {} {} {}"/>{geoms}
</body></worldbody></mujoco>"#,
            axis.x,
            axis.y,
            axis.z,
            t[(0, 0)],
            t[(1, 1)],
            t[(2, 2)],
            t[(0, 1)],
            t[(0, 2)],
            t[(1, 2)]
        );
        let (mut world, _) = common::world(Vector::ZERO);
        let mut joints = common::joints(4);
        let robot = common::robot::insert_mjcf_str(
            &text,
            "wheel.xml",
            ".",
            &mut world,
            &mut joints,
            &UrdfOptions::default(),
        )
        .expect("loads");
        let wheel = robot.links["wheel"];
        let w = spin_up(&mut world, &mut joints, wheel, axis, 1.0, 3.0);
        println!(
            "MJCF fullinertia wheel (axis [{:.3}, {:.3}, {:.3}], geoms: {}): ω = {w:.3} rad/s \
             (T·t/I = 30)",
            axis.x,
            axis.y,
            axis.z,
            !geoms.is_empty()
        );
        assert!((w / 30.0 - 1.0).abs() < 0.01, "ω = {w} rad/s, not 30");
        // the body has turned about the axis since: the file's tensor turned with it
        let got = world_inertia(&world.bodies[wheel]);
        let q = world.bodies[wheel].position().rotation;
        let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            q.w as f64, q.x as f64, q.y as f64, q.z as f64,
        ))
        .to_rotation_matrix();
        let want = q.matrix() * t * q.matrix().transpose();
        assert!(relative(&got, &want) < 1e-5, "{got} vs {want}");
    }
}

#[test]
fn the_simulated_inertia_tensor_is_the_urdf_s_turned_into_the_world() {
    // CAD-like tensors (a Robotiq knuckle's, 1e-6 kg·m², with products of inertia), a wheel's
    // (two equal moments) with and without a tilt of the inertial frame, and a general one
    let cases: [([f64; 6], &str); 5] = [
        ([2.9e-6, 1.9e-6, 1.2e-6, 1.1e-7, -2.3e-7, 0.7e-7], "0 0 0"),
        ([1.2e-6, 1.2e-6, 2.0e-6, 0.0, 0.0, 0.0], "0.2 0.5 -0.4"),
        ([0.1, 0.05, 0.05, 0.0, 0.0, 0.0], "0 0 0"),
        ([0.05, 0.05, 0.1, 0.0, 0.0, 0.0], "1.1 -0.7 0.3"),
        ([0.3, 0.2, 0.15, 0.02, -0.01, 0.03], "0.4 0.1 -0.2"),
    ];
    let mut worst = 0.0f64;
    for (inertia, rpy) in cases {
        for collisions in ["", WHEEL_COLLISIONS] {
            let text = wheel_urdf(inertia, rpy, collisions);
            let (mut world, mut joints, robot) = load_urdf(&text);
            // one step: rapier sums the colliders' mass properties with the link's then
            joints.step(&mut world, 1.0 / 600.0).unwrap();
            let b = &world.bodies[robot.links["wheel"]];
            let r: Vec<f64> = rpy.split(' ').map(|v| v.parse().unwrap()).collect();
            let turn = Rotation3::from_euler_angles(r[0], r[1], r[2]);
            let q = b.position().rotation;
            let link = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                q.w as f64, q.x as f64, q.y as f64, q.z as f64,
            ))
            .to_rotation_matrix()
                * turn;
            let want = link.matrix() * tensor(inertia) * link.matrix().transpose();
            let got = world_inertia(b);
            let err = relative(&got, &want);
            println!(
                "{inertia:?} rpy {rpy} colliders {}: {err:.2e}",
                !collisions.is_empty()
            );
            worst = worst.max(err);
            assert!(
                err < 1e-6,
                "{inertia:?} at rpy {rpy}: {got} vs {want} ({err:e})"
            );
        }
    }
    println!("worst relative error {worst:.2e}");
}

/// A body of two geoms without `<inertial>` (its mass from theirs), on a hinge about `axis`
/// at (0, 0, 1) of the world.
fn two_geom_body(axis: Vector3<f64>, geoms: &str) -> String {
    format!(
        r#"<mujoco model="geoms"><worldbody><body name="pair" pos="0 0 1">
  <joint name="axle" type="hinge" axis="{} {} {}"/>{geoms}
</body></worldbody></mujoco>"#,
        axis.x, axis.y, axis.z
    )
}

#[test]
fn an_mjcf_body_of_two_geoms_has_their_summed_tensor_and_spins_up_at_torque_times_time_over_it() {
    // the tensor the crate sums in f64, computed here by hand (about the centre of mass, at
    // the body's origin: the geoms are symmetric about it)
    let ball = |m: f64, r: f64, d: Vector3<f64>| {
        // two balls of mass m, radius r at ±d
        let own = 0.4 * m * r * r;
        2.0 * (Matrix3::identity() * (own + m * d.norm_squared()) - m * d * d.transpose())
    };
    let plate = |m: f64, [a, b, c]: [f64; 3], d: f64| {
        // two boxes of mass m, half extents a, b, c at y = ±d
        let (xx, yy, zz) = (
            (b * b + c * c) / 3.0,
            (a * a + c * c) / 3.0,
            (a * a + b * b) / 3.0,
        );
        tensor([
            2.0 * m * (xx + d * d),
            2.0 * m * yy,
            2.0 * m * (zz + d * d),
            0.0,
            0.0,
            0.0,
        ])
    };
    let rho = 1000.0;
    let ball_mass = |r: f64| rho * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    let balls = |r: f64, d: Vector3<f64>, mass: &str| {
        format!(
            r#"<geom type="sphere" size="{r}"{mass} pos="{} {} {}"/>
  <geom type="sphere" size="{r}"{mass} pos="{} {} {}"/>"#,
            d.x, d.y, d.z, -d.x, -d.y, -d.z
        )
    };
    let plate_geoms = |[a, b, c]: [f64; 3], d: f64, mass: &str| {
        format!(
            r#"<geom type="box" size="{a} {b} {c}"{mass} pos="0 {d} 0"/>
  <geom type="box" size="{a} {b} {c}"{mass} pos="0 -{d} 0"/>"#
        )
    };
    let diagonal = Vector3::new(1.0, 1.0, 0.0).normalize();
    let cases: [(&str, String, Matrix3<f64>, Vector3<f64>); 8] = [
        (
            // Ixx < Iyy = Izz, the two equal moments the largest
            "two balls along x",
            balls(0.05, Vector3::x() * 0.1, ""),
            ball(ball_mass(0.05), 0.05, Vector3::x() * 0.1),
            Vector3::y(),
        ),
        (
            // a plate across x: Iyy = Izz the smallest moments (c² = b² + 3d²)
            "two boxes, a plate across x",
            plate_geoms([0.01, 0.1, 0.2], 0.1, ""),
            plate(rho * 8.0 * 0.01 * 0.1 * 0.2, [0.01, 0.1, 0.2], 0.1),
            Vector3::y(),
        ),
        (
            "two balls along (1, 1, 0)",
            balls(0.05, diagonal * 0.1, ""),
            ball(ball_mass(0.05), 0.05, diagonal * 0.1),
            diagonal,
        ),
        // CAD scale: 10 g balls of 5 mm, 1 cm off (2e-7 and 2.2e-6 kg·m²), and a plate of
        // 10 g boxes
        (
            "two small balls along x (geom mass)",
            balls(0.005, Vector3::x() * 0.01, r#" mass="0.01""#),
            ball(0.01, 0.005, Vector3::x() * 0.01),
            Vector3::x(),
        ),
        (
            "two small balls along y (geom mass)",
            balls(0.005, Vector3::y() * 0.01, r#" mass="0.01""#),
            ball(0.01, 0.005, Vector3::y() * 0.01),
            Vector3::y(),
        ),
        (
            "two small balls along (1, 1, 0) (geom mass)",
            balls(0.005, diagonal * 0.01, r#" mass="0.01""#),
            ball(0.01, 0.005, diagonal * 0.01),
            diagonal,
        ),
        (
            // a visual geom: no collider, its mass counted (as rapier3d-mjcf counts it)
            "two small balls along y, one visual (geom mass)",
            r#"<geom type="sphere" size="0.005" mass="0.01" pos="0 0.01 0"/>
  <geom type="sphere" size="0.005" mass="0.01" pos="0 -0.01 0" contype="0" conaffinity="0"/>"#
                .into(),
            ball(0.01, 0.005, Vector3::y() * 0.01),
            Vector3::y(),
        ),
        (
            "two small boxes, a plate across x (geom mass)",
            plate_geoms([0.001, 0.01, 0.02], 0.01, r#" mass="0.01""#),
            plate(0.01, [0.001, 0.01, 0.02], 0.01),
            Vector3::y(),
        ),
    ];
    let mut failed = Vec::new();
    for (what, geoms, want, axis) in cases {
        let text = two_geom_body(axis, &geoms);
        let load = || {
            let (mut world, _) = common::world(Vector::ZERO);
            let mut joints = common::joints(4);
            let robot = common::robot::insert_mjcf_str(
                &text,
                "geoms.xml",
                ".",
                &mut world,
                &mut joints,
                &UrdfOptions::default(),
            )
            .expect("loads");
            (world, joints, robot.links["pair"])
        };
        // the world tensor after one step (rapier sums the colliders with the body then); the
        // body has not turned
        let (mut world, mut joints, pair) = load();
        joints.step(&mut world, 1.0 / 600.0).unwrap();
        let got = world_inertia(&world.bodies[pair]);
        let err = relative(&got, &want);
        // spun up by a torque that makes 30 rad/s in 3 s
        let i = axis.dot(&(want * axis));
        let (mut world, mut joints, pair) = load();
        let w = spin_up(&mut world, &mut joints, pair, axis, 10.0 * i, 3.0);
        println!("{what}: tensor off by {err:.2e}, ω = {w:.3} rad/s (T·t/I = 30)");
        if err >= 1e-5 || (w / 30.0 - 1.0).abs() >= 0.01 {
            failed.push(format!(
                "{what}: {got} vs {want} ({err:e}), ω = {w} rad/s, not 30"
            ));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
