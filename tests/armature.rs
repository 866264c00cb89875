//! A rotor geared to a joint's free DOF (`DofLaw::armature`, MuJoCo's joint `armature`): the
//! DOF moves as if its inertia were `a` larger, and the rotor's kinetic energy `½·a·q̇²` is
//! stored in the joint, so that the energy balance closes.

mod common;
use rapier_kjoint::io::urdf::UrdfOptions;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, DofLaw, JointType, KjointBuilder, KjointProperty};

/// A 2 kg body on a vertical slide falls under gravity at `g·m/(m + a)`: with a rotor of
/// `a` = 2 kg at half `g` (4.905 m/s after 1 s, where 9.81 without it). The implicit update
/// gives it exactly (`m·Δv = m·g·h − a·Δv` each substep), up to rapier's f32 velocities. The
/// rotor then holds `½·a·v²` = 24.06 J, the work the joint's impulses took from the body: its
/// book's `numerical` (that work less what the law stored) stays at round-off (it would be
/// −24 J were the rotor's energy not booked).
#[test]
fn a_slide_with_a_rotor_falls_at_g_m_over_m_plus_a_and_its_rotor_stores_the_difference() {
    for a in [0.0, 2.0] {
        let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
        let b = common::point_body(&mut w, 2.0, Vector::splat(0.1), Vector::ZERO);
        let mut set = common::joints(4);
        let prop = KjointProperty::new(JointType::Translational)
            .with_dof(Dof::Dx, DofLaw::default().with_armature(a));
        let j = common::add(&mut set, &w, prop, ground, b, |bl| {
            bl.world_frame1(Rotation::from_rotation_arc(Vector::X, Vector::Y))
        });
        for _ in 0..60 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        let v = w.bodies[b].linvel().y as f64;
        let expected = -9.81 * 2.0 / (2.0 + a);
        let e = set.get(j).unwrap().closed_energy(&w.bodies);
        println!("a = {a} kg: v = {v} m/s (expected {expected}), {e:?}");
        assert!(
            (v - expected).abs() < 1e-5 * expected.abs(),
            "{v} {expected}"
        );
        let rotor = 0.5 * a * v * v;
        assert!(
            (e.kinetic - rotor).abs() < 1e-4 * rotor.max(1.0),
            "{} {rotor}",
            e.kinetic
        );
        assert!(e.numerical.abs() < 1e-3, "{}", e.numerical);
    }
}

/// Upward crossings of the bob's centre of mass `x` through 0 over `secs`, by linear
/// interpolation: the mean period.
fn mean_period(
    w: &mut PhysicsWorld,
    set: &mut rapier_kjoint::KjointSet,
    bob: RigidBodyHandle,
    secs: f64,
    mut each: impl FnMut(&PhysicsWorld, &rapier_kjoint::KjointSet),
) -> f64 {
    let dt = 1.0 / 60.0;
    let mut crossings = Vec::new();
    let mut x_before = w.bodies[bob].center_of_mass().x as f64;
    for n in 1..=(secs / dt) as usize {
        set.step(w, dt).unwrap();
        each(w, set);
        let x = w.bodies[bob].center_of_mass().x as f64;
        if x_before < 0.0 && x >= 0.0 {
            crossings.push((n - 1) as f64 * dt + dt * x_before / (x_before - x));
        }
        x_before = x;
    }
    assert!(crossings.len() >= 4, "{crossings:?}");
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

/// The period of a 1 kg bob 1 m below its hinge swinging a little, `2π·√(I/(m·g·l))` with
/// `I` about the hinge (the rotor's included), within 0.2 %.
fn assert_small_swing_period(period: f64, inertia: f64) {
    let expected = 2.0 * std::f64::consts::PI * (inertia / 9.81).sqrt();
    println!("period {period} s, expected {expected} s");
    assert!(
        (period - expected).abs() < 2e-3 * expected,
        "{period} {expected}"
    );
}

/// A 1 kg bob 1 m below a hinge (its own inertia 1e-3 kg·m²: 1.001 kg·m² about the pivot)
/// swinging by ±0.045 rad with a rotor of `a` = 1 kg·m² on the hinge: the period is
/// `2π·√((I + a)/(m·g·l))` = 2.8377 s (2.0071 s without the rotor), within 0.2 %; over 30 s
/// the bodies' energy, the rotor's and the joint's stored and dissipated energies sum to the
/// start's within 3 % of the swing's energy `½·(I + a)·ω0²` (0.010 J).
#[test]
fn a_pendulum_with_a_rotor_swings_at_the_period_of_its_inertia_plus_the_rotor_s() {
    for a in [0.0, 1.0] {
        let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
        let bob = common::point_body(
            &mut w,
            1.0,
            Vector::splat(1e-3),
            Vector::new(0.0, -1.0, 0.0),
        );
        let mut set = common::joints(4);
        let prop = KjointProperty::new(JointType::Revolute)
            .with_dof(Dof::Rx, DofLaw::default().with_armature(a));
        let j = set
            .insert(
                KjointBuilder::new(prop)
                    .world_frame1(Rotation::from_rotation_arc(Vector::X, Vector::Z))
                    .local_anchor2(Vector::new(0.0, 1.0, 0.0)),
                ground,
                bob,
                &w.bodies,
            )
            .unwrap();
        // turning about the pivot at ω0: the bob's centre moves at ω0·l along x
        let omega0 = 0.1;
        w.bodies[bob].set_linvel(Vector::new(omega0, 0.0, 0.0), true);
        w.bodies[bob].set_angvel(Vector::new(0.0, 0.0, omega0), true);
        let inertia = 1.001 + a;
        let swing = 0.5 * inertia * (omega0 as f64).powi(2);
        set.prepare(&mut w);
        let e0 = common::total_energy(&w, &set);
        let mut worst = 0.0f64;
        let period = mean_period(&mut w, &mut set, bob, 30.0, |w, set| {
            // (the rotor's `½·a·ω0²` at the start is the joint's preload: the bob was set
            // turning with its rotor, no body did work on it)
            let j = set.get(j).unwrap();
            let e = j.closed_energy(&w.bodies);
            let mech = rapier_kjoint::dynamics::energy::mechanical_energy(&w.bodies, w.gravity);
            let start = e0 + j.preload_energy();
            worst = worst.max((mech + e.stored() + e.dissipated() - start).abs());
        });
        let e = set.get(j).unwrap().closed_energy(&w.bodies);
        println!("a = {a}: worst balance {worst} J of a swing of {swing} J, {e:?}");
        assert_small_swing_period(period, inertia);
        // (rapier's semi-implicit Euler and f32 poses: 1.4 % without the rotor; the rotor's
        // energy left out of the book would be half the swing's)
        assert!(worst < 0.03 * swing, "{worst} J");
    }
}

/// A 1 kg slider geared to a rotor of `a` = 9 kg runs at 2 m/s into its stop of `k` =
/// 10 000 N/m at 0.3 m, the stop damped at `Cr` = 1 (`Cr·√(K_t·m)`, docs/kjoint2.md §4.6):
/// the DOF's inertia is the body's and the rotor's, `m` = 10 kg, so the stop acts as the
/// damped oscillator of `ω = √(k/m)` = 31.6 rad/s and `ζ = Cr/2` = 0.5, and the slider
/// leaves it at `v0·exp(−ζ·ω·π/ω_d)` = 0.326 m/s (`ω_d = ω·√(1 − ζ²)`), within 3 %
/// (measured 0.319). With the body's mass alone in the damping (what the law took before),
/// `ζ` was 0.16 and the slider bounced back at 1.19 m/s. Without the rotor (`a` = 0, `k` =
/// 1000 N/m: the same `ω` and `ζ`) the 1 kg slider leaves at the same speed, the check of
/// the measure itself.
#[test]
fn a_stop_s_critical_damping_counts_the_rotor_s_inertia() {
    for a in [0.0, 9.0] {
        let (mut w, ground) = common::world(Vector::ZERO);
        let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
        let mut set = common::joints(4);
        let k = 1000.0 * (1.0 + a);
        let prop = KjointProperty::new(JointType::Translational)
            .with_critical_damping(1.0)
            .with_dof(
                Dof::Dx,
                DofLaw::default()
                    .with_stops(-1.0, 0.3)
                    .with_stop_stiffness(k)
                    .with_armature(a),
            );
        let j = common::add(&mut set, &w, prop, ground, b, |bl| bl);
        w.bodies[b].set_linvel(Vector::new(2.0, 0.0, 0.0), true);
        set.prepare(&mut w);
        let mut deepest = 0.0f64;
        for _ in 0..60 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
            deepest = deepest.max(w.bodies[b].translation().x as f64 - 0.3);
        }
        let v = w.bodies[b].linvel().x as f64;
        let (m, v0, cr) = (1.0 + a, 2.0, 1.0);
        let omega = (k / m).sqrt();
        let zeta = cr / 2.0;
        let wd = omega * (1.0f64 - zeta * zeta).sqrt();
        let expected = -v0 * (-zeta * omega * std::f64::consts::PI / wd).exp();
        println!(
            "a = {a}: left the stop at {v} m/s (expected {expected}), deepest {deepest} m, {:?}",
            set.get(j).unwrap().closed_energy(&w.bodies)
        );
        assert!(
            (v - expected).abs() < 0.03 * expected.abs(),
            "{v} {expected}"
        );
    }
}

/// An armature is refused where it is negative or not finite, and on a blocked DOF (which
/// takes no law), naming the DOF and the field.
#[test]
fn a_negative_or_misplaced_armature_is_refused_naming_the_dof_and_the_field() {
    let (w, ground) = common::world(Vector::ZERO);
    let mut w = w;
    let b = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
    for (dof, a, says) in [
        (Dof::Rx, -1.0, "rx.armature"),
        (Dof::Rx, f64::NAN, "rx.armature"),
        (Dof::Dx, 1.0, "dx.armature"),
    ] {
        let mut set = common::joints(4);
        let prop = KjointProperty::new(JointType::Revolute)
            .with_dof(dof, DofLaw::default().with_armature(a));
        let e = set
            .insert(KjointBuilder::new(prop), ground, b, &w.bodies)
            .unwrap_err()
            .to_string();
        println!("{e}");
        assert!(e.contains(says), "{e}");
    }
}

/// An MJCF hinge's `armature` is noticed, not mapped (see `io::mjcf`'s describer: the
/// gymnasium walker's feet opened beyond 1 cm with it); its override gives the rotor, as
/// MuJoCo's mass matrix has it: a 1 kg bob 1 m below the hinge with `armature="1"` swings
/// with the period `2π·√((I + a)/(m·g·l))` once `options.joints.h.armature = 1`.
#[test]
fn an_mjcf_hinge_s_armature_is_noticed_and_its_override_swings_as_mujoco_s_mass_matrix_says() {
    let xml = r#"<mujoco model="rotor">
      <worldbody>
        <body name="bob" pos="0 0 -1">
          <joint name="h" type="hinge" axis="0 1 0" pos="0 0 1" armature="1"/>
          <inertial pos="0 0 0" mass="1" diaginertia="0.001 0.001 0.001"/>
        </body>
      </worldbody>
    </mujoco>"#;
    for (a, period_inertia) in [(None, 1.001), (Some(1.0), 2.001)] {
        let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
        let mut joints = common::joints(4);
        let mut options = UrdfOptions::default();
        if let Some(a) = a {
            options.joints.insert(
                "h".into(),
                rapier_kjoint::io::urdf::JointOverride {
                    armature: Some(a),
                    ..Default::default()
                },
            );
        }
        let robot = common::robot::insert_mjcf_str(
            xml,
            "rotor.xml",
            ".",
            &mut world,
            &mut joints,
            &options,
        )
        .expect("loads");
        println!("{:?}", robot.notices);
        assert!(
            robot
                .notices
                .iter()
                .any(|n| n.contains("armature of 1 joint(s) not mapped")),
            "{:?}",
            robot.notices
        );
        let bob = robot.links["bob"];
        // turning about the hinge (world y) at ω0, the bob 1 m below it moves at
        // ω × r = (0, ω0, 0) × (0, 0, −1) = (−ω0, 0, 0)
        let omega0 = 0.1;
        world.bodies[bob].set_linvel(Vector::new(-omega0, 0.0, 0.0), true);
        world.bodies[bob].set_angvel(Vector::new(0.0, omega0, 0.0), true);
        let period = mean_period(&mut world, &mut joints, bob, 30.0, |_, _| {});
        assert_small_swing_period(period, period_inertia);
    }
}

/// URDF cannot say a joint's rotor inertia: the override `armature` gives it. A URDF bob of
/// 1 kg hanging 1 m below a revolute joint (its own inertia 1e-3 kg·m²), given a rotor of
/// 1 kg·m² by `options.joints.hinge.armature`, swings with the period of 2.001 kg·m²; a
/// negative one is refused naming the override's field.
#[test]
fn a_urdf_joint_takes_its_rotor_from_the_override() {
    let urdf = r#"<robot name="rotor">
      <link name="base"/>
      <link name="anchor"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
      <joint name="fix" type="fixed"><parent link="base"/><child link="anchor"/></joint>
      <link name="bob">
        <inertial><origin xyz="0 0 -1"/><mass value="1"/>
          <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
      </link>
      <joint name="hinge" type="continuous"><parent link="anchor"/><child link="bob"/>
        <axis xyz="0 1 0"/></joint>
    </robot>"#;
    let options = |a: f64| {
        let mut o = UrdfOptions::default();
        o.joints.insert(
            "hinge".into(),
            rapier_kjoint::io::urdf::JointOverride {
                armature: Some(a),
                ..Default::default()
            },
        );
        o
    };
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let robot =
        common::robot::insert_urdf_str(urdf, "rotor.urdf", &mut world, &mut joints, &options(1.0))
            .expect("loads");
    let bob = robot.links["bob"];
    // the link's frame is at the hinge, its centre of mass 1 m below: turning about world y
    // at ω0, the centre moves at (0, ω0, 0) × (0, 0, −1) = (−ω0, 0, 0)
    let omega0 = 0.1;
    world.bodies[bob].set_angvel(Vector::new(0.0, omega0, 0.0), true);
    world.bodies[bob].set_linvel(Vector::new(-omega0, 0.0, 0.0), true);
    let period = mean_period(&mut world, &mut joints, bob, 30.0, |_, _| {});
    assert_small_swing_period(period, 2.001);
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let e =
        common::robot::insert_urdf_str(urdf, "rotor.urdf", &mut world, &mut joints, &options(-1.0))
            .unwrap_err()
            .to_string();
    println!("{e}");
    assert!(e.contains("hinge") && e.contains("armature"), "{e}");
}
