//! A 10 kg block pulled across a plate by a constant force while the normal load varies:
//! planar KJOINT2 joint (type 4) with the load-dependent friction law (spec
//! `planar_friction.md`). The pull `P = 0.3·m·g` equals `μ·m·g`: the block sticks while the
//! extra downward load is positive and slides while it is negative.
//!
//! Run with `cargo run --release --example planar_block`.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

use rapier_kjoint::law::{ConnectorReport, PlanarFriction};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{JointType, KjointBuilder, KjointProperty, KjointSet, SubstepSettings};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (m, mu, g) = (10.0f64, 0.3f64, 9.81f64);
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, -g as Real, 0.0),
        ..Default::default()
    };
    let plate = world.insert_body(RigidBodyBuilder::fixed());
    let block = world.insert_body(
        RigidBodyBuilder::dynamic()
            .can_sleep(false)
            .additional_mass_properties(MassProperties::new(
                Vector::ZERO,
                m as Real,
                Vector::splat(1.0),
            )),
    );
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps: 4,
        ..Default::default()
    });
    // Joint x axis (the plate normal) = world +y; automatic stick stiffness (0, 0).
    let friction = PlanarFriction::new(mu, 0.0, 0.0, 0.0, 0.0, 0.0)?;
    let j = joints.insert(
        KjointBuilder::new(KjointProperty::new(JointType::Planar).with_critical_damping(0.3))
            .name("block")
            .world_frame1(Rotation::from_rotation_z(
                std::f64::consts::FRAC_PI_2 as Real,
            ))
            .planar_friction(friction),
        plate,
        block,
        &world.bodies,
    )?;
    let pull = mu * m * g;
    let dt = 1.0 / 60.0;
    let mut expected_dissipation = 0.0;
    let mut last_slip = 0.0;
    println!("   t [s]   F_N [N]  friction [N]  state   x [m]    dissipated [J]");
    for frame in 0..(6.0 / dt) as usize {
        let t = frame as f64 * dt;
        // Extra normal load: ±40 % of the weight, period 2 s, after 0.5 s of settling.
        let extra = if t < 0.5 {
            0.0
        } else {
            -0.4 * m * g * (std::f64::consts::TAU * (t - 0.5) / 2.0).sin()
        };
        let b = &mut world.bodies[block];
        b.reset_forces(true);
        let px = if t < 0.5 { 0.0 } else { -pull };
        b.add_force(Vector::new(px as Real, extra as Real, 0.0), true);
        joints.step(&mut world, dt)?;
        let s = joints.get(j).expect("inserted").state().expect("stepped");
        if let Some(ConnectorReport::PlanarFriction(r)) = s.connector {
            expected_dissipation += mu * r.normal_force * (r.slip_total - last_slip);
            last_slip = r.slip_total;
            if frame % 15 == 0 {
                println!(
                    "{t:8.2} {:9.2} {:12.2}  {:6} {:8.4} {:12.4}",
                    r.normal_force,
                    r.friction_force[0].hypot(r.friction_force[1]),
                    format!("{:?}", r.sliding),
                    s.q[1],
                    r.dissipated
                );
            }
        }
    }
    let e = joints.get(j).expect("inserted").energy();
    println!(
        "friction work {:.3} J, Σ μ·F_N·Δslip {:.3} J, stored in the stick spring {:.2e} J",
        e.friction, expected_dissipation, e.elastic
    );
    Ok(())
}
