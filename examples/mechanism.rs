//! A small mechanism to copy: a door on a hinge (revolute, type 2) with friction and a stop,
//! a drawer on a slide (translational, type 6) with a return spring, viscosity and stops,
//! and a lamp hanging from a ball joint (spherical, type 1) with coupled (conical) stops,
//! all stepped through a [`KjointSet`] next to rapier's own contacts.
//!
//! `cargo run --release --example mechanism`

use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, DofLaw, JointType, KjointBuilder, KjointProperty, KjointSet};

fn main() -> Result<(), rapier_kjoint::SimError> {
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81, 0.0),
        ..Default::default()
    };
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let mut joints = KjointSet::new(); // 4 substeps per frame

    // Door: 0.8 m × 2 m, 20 kg, hinged about the world y axis along its left edge. It is
    // pushed open at 1 rad/s (2.1 J); hinge friction 0.5 N·m; it stops at 1.5 rad (86°).
    let (door, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.4, 1.0, 0.0))
            // turning about the hinge: v = ω × r, r = 0.4 m from the hinge to the centre
            .angvel(Vector::new(0.0, 1.0, 0.0))
            .linvel(Vector::new(0.0, 0.0, -0.4)),
        ColliderBuilder::cuboid(0.4, 1.0, 0.02).mass(20.0),
    );
    // The stop's damping is the property's `Cr` of critical (docs/kjoint2.md §4.6): at
    // Radioss' default 0.05 the door comes back off its stop at about 0.9 of its speed; a
    // door stop's rubber takes most of it (0.7: it stays on the stop).
    let hinge = KjointProperty::new(JointType::Revolute)
        .with_dof(
            Dof::Rx,
            DofLaw::default()
                .with_friction(1e3, 0.5) // Kf [N·m/rad], also the stop's stiffness; friction moment [N·m]
                .with_stops(-0.01, 1.5), // [rad]
        )
        .with_critical_damping(0.7);
    let axis_y = Rotation::from_rotation_arc(Vector::X, Vector::Y); // joint x = world y
    let door_hinge = joints.insert(
        KjointBuilder::new(hinge)
            .name("door hinge")
            .world_frame1(axis_y)
            .local_anchor1(Vector::new(0.0, 1.0, 0.0)) // on the ground body, world (0, 1, 0)
            .local_anchor2(Vector::new(-0.4, 0.0, 0.0)), // the door's left edge
        ground,
        door,
        &world.bodies,
    )?;

    // Drawer: 5 kg, pulled out along world x at 2.5 m/s; a 200 N/m return spring, 5 N·s/m
    // of viscosity, stops at -0.05 m and +0.25 m of travel (it hits both; a stop of 0 means
    // "no stop", as in Radioss).
    let (drawer, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(2.0, 0.5, 0.0))
            .linvel(Vector::new(2.5, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.2, 0.1, 0.2).mass(5.0),
    );
    let slide = KjointProperty::new(JointType::Translational).with_dof(
        Dof::Dx,
        DofLaw::spring(200.0)
            .with_viscosity(5.0)
            .with_stops(-0.05, 0.25),
    );
    let drawer_slide = joints.insert(
        KjointBuilder::new(slide)
            .name("drawer slide")
            .local_anchor1(Vector::new(2.0, 0.5, 0.0)),
        ground,
        drawer,
        &world.bodies,
    )?;

    // Lamp: a 1 kg ball 0.5 m below a ball joint, kicked sideways; the joint's swing is
    // limited to a 0.4 rad cone (coupled stops on the two bending rotations).
    let (lamp, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-2.0, 1.5, 0.0))
            .linvel(Vector::new(3.0, 0.0, 2.0)),
        ColliderBuilder::ball(0.1).mass(1.0),
    );
    let cone = DofLaw::default().with_stops(-0.4, 0.4).with_coupled_stops();
    let ball_joint = KjointProperty::new(JointType::Spherical)
        .with_dof(Dof::Ry, cone.clone())
        .with_dof(Dof::Rz, cone);
    let lamp_joint = joints.insert(
        KjointBuilder::new(ball_joint)
            .name("lamp")
            .world_frame1(Rotation::from_rotation_arc(Vector::X, Vector::NEG_Y)) // x down the cord
            .local_anchor1(Vector::new(-2.0, 2.0, 0.0))
            .local_anchor2(Vector::new(0.0, 0.5, 0.0)),
        ground,
        lamp,
        &world.bodies,
    )?;

    for frame in 1..=180 {
        joints.step(&mut world, 1.0 / 60.0)?;
        if frame % 15 == 0 {
            let door = joints
                .get(door_hinge)
                .and_then(|j| j.state())
                .expect("stepped");
            let drawer = joints
                .get(drawer_slide)
                .and_then(|j| j.state())
                .expect("stepped");
            let lamp = joints
                .get(lamp_joint)
                .and_then(|j| j.state())
                .expect("stepped");
            let swing = lamp.q[4].hypot(lamp.q[5]);
            println!(
                "t = {:.2} s | door {:.3} rad ({:?}, stop {:?}) | drawer {:.3} m (stop {:?}) | lamp swing {:.3} rad",
                joints.time(),
                door.q[3],
                door.status[3].friction,
                door.status[3].stop,
                drawer.q[0],
                drawer.status[0].stop,
                swing,
            );
        }
    }
    for h in [door_hinge, drawer_slide, lamp_joint] {
        let j = joints.get(h).expect("inserted");
        let e = j.energy();
        println!(
            "{}: dissipated {:.3} J by friction, {:.3} J by damping, {:.3} J in the stops",
            j.name, e.friction, e.damping, e.stop
        );
    }
    Ok(())
}
