//! A rigid 20 m riser segment (2 t) hanging from a flex joint read from the seed deck
//! `assets/decks/flexjoint_example2.dat` (multilinear static law, bilinear hysteretic dynamic
//! law): a steady lateral current force first (quasi-static phase), then the switch to the
//! dynamic phase at t = 20 s and a cyclic wave force at the bottom.
//!
//! Run with `cargo run --release --example riser_flexjoint`.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

use rapier_kjoint::io::riser::RiserDeck;
use rapier_kjoint::law::ConnectorReport;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, DofLaw, JointType, KjointProperty, KjointSet, SubstepSettings};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let deck = RiserDeck::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/decks/flexjoint_example2.dat"
    ))?;
    let element = &deck.joints[0];
    let dynamic = element
        .law
        .dynamic
        .ok_or("example 2 has a *FLEXPROADD record")?;
    let (len, m, g) = (20.0f64, 2000.0f64, 9.81f64);
    let i_com = m * len * len / 12.0;
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, -g as Real, 0.0),
        ..Default::default()
    };
    let vessel = world.insert_body(RigidBodyBuilder::fixed());
    let riser = world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, -0.5 * len as Real, 0.0))
            .can_sleep(false)
            .additional_mass_properties(MassProperties::new(
                Vector::ZERO,
                m as Real,
                Vector::new(i_com as Real, 1.0, i_com as Real),
            )),
    );
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps: 4,
        ..Default::default()
    });
    // Light hydrodynamic damping on the bending rotations (20 % of critical at Kdyn_ini).
    let i_top = m * len * len / 3.0;
    let c = 0.4 * (dynamic.kdyn_ini * i_top).sqrt();
    let prop = KjointProperty::new(JointType::Spherical)
        .with_dof(Dof::Ry, DofLaw::default().with_viscosity(c))
        .with_dof(Dof::Rz, DofLaw::default().with_viscosity(c))
        .with_dof(Dof::Rx, DofLaw::default().with_viscosity(c));
    let t_switch = 20.0;
    let j = joints.insert(
        element
            .joint_builder(prop)
            // x (riser axis) = world −y
            .world_frame1(Rotation::from_rotation_z(
                -std::f64::consts::FRAC_PI_2 as Real,
            ))
            .local_anchor2(Vector::new(0.0, 0.5 * len as Real, 0.0))
            .flex_joint_switch_time(t_switch),
        vessel,
        riser,
        &world.bodies,
    )?;
    let (current, wave, period) = (1000.0f64, 650.0f64, 10.0f64);
    let dt = 1.0 / 60.0;
    let mut cycle_start = None;
    let (mut amin, mut amax) = (f64::MAX, f64::MIN);
    println!("   t [s]  phase        β [deg]  M_bend [kN·m]  dissipated [J]");
    for frame in 0..(60.0 / dt) as usize {
        let t = frame as f64 * dt;
        let f = if t < 5.0 {
            current * t / 5.0
        } else if t < t_switch {
            current
        } else {
            current + wave * (std::f64::consts::TAU * (t - t_switch) / period).sin()
        };
        let b = &mut world.bodies[riser];
        let bottom = b.translation() + b.rotation() * Vector::new(0.0, -0.5 * len as Real, 0.0);
        b.reset_forces(true);
        b.reset_torques(true);
        b.add_force_at_point(Vector::new(f as Real, 0.0, 0.0), bottom, true);
        joints.step(&mut world, dt)?;
        let s = joints.get(j).expect("inserted").state().expect("stepped");
        let Some(ConnectorReport::FlexJoint(r)) = s.connector else {
            continue;
        };
        let tc = t + dt - t_switch;
        // Second wave cycle: record the extremes and the dissipation.
        if tc >= period && tc < 2.0 * period {
            cycle_start.get_or_insert(r.dissipated_hysteresis);
            let sign = if r.bending_axis[1] >= 0.0 { 1.0 } else { -1.0 };
            amin = amin.min(sign * r.bending_angle);
            amax = amax.max(sign * r.bending_angle);
        }
        if frame % 300 == 0 {
            println!(
                "{t:8.1}  {:11} {:9.4} {:13.2} {:14.2}",
                format!("{:?}", r.phase),
                r.bending_angle.to_degrees(),
                r.bending_moment[0].hypot(r.bending_moment[1]) / 1e3,
                r.dissipated_hysteresis
            );
        }
        if tc >= 2.0 * period {
            if let Some(d0) = cycle_start.take() {
                let a = 0.5 * (amax - amin);
                println!(
                    "second wave cycle: variation amplitude {:.4}° ({:.2}·Angle_lim), \
                     dissipated {:.2} J, analytic loop area {:.2} J",
                    a.to_degrees(),
                    a / dynamic.angle_lim,
                    r.dissipated_hysteresis - d0,
                    dynamic.loop_area(a)
                );
            }
        }
    }
    for e in joints.get(j).expect("inserted").connector_events() {
        println!("event at t = {:.6} s: {}", e.time, e.kind);
    }
    Ok(())
}
