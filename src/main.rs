//! `kjoint`: runs the bundled demo mechanism and prints a summary.
//!
//! With no arguments (`cargo run --release`) it runs the demo: a rod pendulum on a revolute
//! KJOINT2 (automatic stiffness, rotational stop) and a block on an inclined prismatic
//! KJOINT2 with elasto-plastic friction and a stop.

use rapier3d::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, JointType, Kjoint2Builder, Kjoint2Property, KjointSet, SubstepSettings,
};
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!(
            "kjoint: KJOINT2 penalty joints for rapier\n\nUSAGE: kjoint    (runs the bundled demo)"
        );
        return ExitCode::SUCCESS;
    }
    if !args.is_empty() {
        eprintln!("kjoint: unknown arguments {args:?}; run `kjoint --help`");
        return ExitCode::from(2);
    }
    match demo() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("kjoint: {e}");
            ExitCode::FAILURE
        }
    }
}

fn demo() -> Result<(), rapier_kjoint::SimError> {
    let mut world = PhysicsWorld::default();
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps: 16,
        ..Default::default()
    });

    // 1. A 1 m rod on a revolute joint about z, with a stop at +0.3 rad.
    let (rod, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, -0.5, 0.0))
            .can_sleep(false),
        ColliderBuilder::cuboid(0.05, 0.5, 0.05).mass(1.0),
    );
    let hinge = Kjoint2Property::new(JointType::Revolute).with_dof(
        Dof::Rx,
        DofLaw::default()
            .with_stops(0.0, 0.3)
            .with_friction(50.0, 0.05),
    );
    let axis_z = Rotation::from_rotation_arc(Vector::X, Vector::Z);
    let h_hinge = joints.insert(
        Kjoint2Builder::new(hinge)
            .name("hinge")
            .frame(axis_z)
            .local_anchor2(Vector::new(0.0, 0.5, 0.0)),
        ground,
        rod,
        &world.bodies,
    )?;
    world.bodies[rod].set_angvel(Vector::new(0.0, 0.0, 2.0), true);

    // 2. A 2 kg block on a 30° incline (prismatic), friction 5 N, stop 0.5 m down the slope.
    let slope = Rotation::from_rotation_z(-30f32.to_radians());
    let (block, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(3.0, 0.0, 0.0))
            .rotation(Vector::new(0.0, 0.0, -30f32.to_radians()))
            .can_sleep(false),
        ColliderBuilder::cuboid(0.1, 0.1, 0.1).mass(2.0),
    );
    let anchor =
        world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(3.0, 0.0, 0.0)));
    let slider = Kjoint2Property::new(JointType::Translational)
        .with_kn(1e6)
        .with_dof(
            Dof::Dx,
            DofLaw::default()
                .with_stops(0.0, 0.5)
                .with_friction(1e4, 5.0),
        );
    let h_slider = joints.insert(
        Kjoint2Builder::new(slider).name("slider").frame(slope),
        anchor,
        block,
        &world.bodies,
    )?;

    let frames = 5 * 60;
    let mut peak = [0.0f64; 2];
    for _ in 0..frames {
        joints.step(&mut world, 1.0 / 60.0)?;
        for (k, h) in [h_hinge, h_slider].into_iter().enumerate() {
            let s = joints.get(h).and_then(|j| j.state()).expect("stepped");
            peak[k] = peak[k].max(s.force.iter().take(3).fold(0.0f64, |a, f| a.max(f.abs())));
        }
    }
    println!(
        "rapier-kjoint demo: {:.1} s simulated, {} joints\n",
        joints.time(),
        joints.len()
    );
    println!(
        "{:<8} {:>10} {:>12} {:>12} {:>12} {:>12}",
        "joint", "free q", "peak |F| N", "elastic J", "friction J", "damping J"
    );
    for (k, h) in [h_hinge, h_slider].into_iter().enumerate() {
        let j = joints.get(h).expect("inserted");
        let s = j.state().expect("stepped");
        let free = if k == 0 { s.q[3] } else { s.q[0] };
        let e = j.energy();
        println!(
            "{:<8} {:>10.4} {:>12.2} {:>12.4} {:>12.4} {:>12.4}",
            j.name,
            free,
            peak[k],
            e.elastic,
            e.friction,
            e.damping + e.stop
        );
    }
    Ok(())
}
