//! Trial (riser engineer): is the flex joint's bending moment / bending plane true in world
//! coordinates when the riser is also twisted? Fixed vessel, dynamic riser (no gravity),
//! world torques: bending Mb about world z, torsion Mt about world y (the riser axis).
//! At static equilibrium the joint must carry exactly the applied torque, and the bending
//! angle must be the angle between the vessel axis and the riser axis.
use rapier_kjoint::law::ConnectorReport;
use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;

fn run(torsion_k: f64, mb: f64, mt: f64) -> Result<(), Box<dyn std::error::Error>> {
    let (len, m) = (10.0f64, 2000.0f64);
    let mut world = PhysicsWorld {
        gravity: Vector::ZERO,
        ..Default::default()
    };
    let vessel = world.insert_body(RigidBodyBuilder::fixed());
    let (riser, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, -5.0, 0.0))
            .can_sleep(false),
        ColliderBuilder::cylinder(5.0, 0.25).mass(m as Real),
    );
    let bending = Curve::new([
        (0.0, 0.0),
        (0.01, 20000.0),
        (0.02, 30000.0),
        (0.04, 40000.0),
    ])?;
    let torsion = Curve::new([(0.0, 0.0), (1.0, torsion_k)])?;
    let law = FlexJointLaw::new(Some(bending), Some(torsion), None)?;
    let prop = KjointProperty::new(JointType::Spherical)
        .with_dof(
            Dof::Rx,
            DofLaw::default().with_viscosity(0.2 * torsion_k.sqrt() * 8.0),
        )
        .with_dof(Dof::Ry, DofLaw::default().with_viscosity(3e5))
        .with_dof(Dof::Rz, DofLaw::default().with_viscosity(3e5));
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps: 16,
        ..Default::default()
    });
    let _ = len;
    let h = joints.insert(
        KjointBuilder::new(prop)
            .flex_joint(law)
            .world_frame1(Rotation::from_rotation_z(
                -std::f64::consts::FRAC_PI_2 as Real,
            ))
            .local_anchor2(Vector::new(0.0, 5.0, 0.0)),
        vessel,
        riser,
        &world.bodies,
    )?;
    let dt = 1.0 / 60.0;
    for frame in 0..(40.0 / dt) as usize {
        let t = frame as f64 * dt;
        let s = (t / 10.0).min(1.0);
        let b = &mut world.bodies[riser];
        b.reset_torques(true);
        b.add_torque(Vector::new(0.0, (mt * s) as Real, (mb * s) as Real), true);
        joints.step(&mut world, dt)?;
    }
    let st = joints.get(h).unwrap().state().unwrap().clone();
    let b = &world.bodies[riser];
    let axis = b.rotation() * Vector::new(0.0, -1.0, 0.0);
    let true_bend = (axis.dot(Vector::new(0.0, -1.0, 0.0)) as f64)
        .clamp(-1.0, 1.0)
        .acos();
    // direction the riser's lower end swung to (world x,z)
    println!("--- torsion law {torsion_k:.3e} N·m/rad, applied Mb = {mb} N·m about world z, Mt = {mt} about world y");
    println!("riser axis in world: ({:.6}, {:.6}, {:.6}); true bending angle {:.6e} rad; tilt direction atan2(z,x) = {:.5} rad",
        axis.x, axis.y, axis.z, true_bend, (axis.z as f64).atan2(axis.x as f64));
    let e = Rotation::from_xyzw(
        st.frame[0] as Real,
        st.frame[1] as Real,
        st.frame[2] as Real,
        st.frame[3] as Real,
    );
    let am = Vector::new(
        st.applied[Dof::Rx] as Real,
        st.applied[Dof::Ry] as Real,
        st.applied[Dof::Rz] as Real,
    );
    let amw = e * am;
    println!(
        "transmitted moment in E: ({:.2}, {:.2}, {:.2}); in world (E·AM): ({:.2}, {:.2}, {:.2})",
        am.x, am.y, am.z, amw.x, amw.y, amw.z
    );
    println!("applied torque (world):   (0, {mt}, {mb})");
    if let Some(ConnectorReport::FlexJoint(r)) = st.connector {
        let mbw = e * Vector::new(
            0.0,
            r.bending_moment[0] as Real,
            r.bending_moment[1] as Real,
        );
        let tilt = e * Vector::new(
            0.0,
            r.tilt_direction[0] as Real,
            r.tilt_direction[1] as Real,
        );
        println!(
            "report: bending angle {:.6e}, |Mb| {:.2}, torsion {:.6} rad {:.2} N·m",
            r.bending_angle,
            r.bending_moment[0].hypot(r.bending_moment[1]),
            r.torsion_angle,
            r.torsion_moment
        );
        println!("report bending moment rotated to world by E: ({:.2}, {:.2}, {:.2}); tilt direction in world by E: ({:.5}, {:.5}, {:.5})",
            mbw.x, mbw.y, mbw.z, tilt.x, tilt.y, tilt.z);
        println!("expected law: f_b(true angle) = {:.2} N·m", {
            let c = Curve::new([
                (0.0, 0.0),
                (0.01, 20000.0),
                (0.02, 30000.0),
                (0.04, 40000.0),
            ])?;
            c.value(true_bend)
        });
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    run(1e7, 10000.0, 50000.0)?;
    run(1e5, 10000.0, 50000.0)?;
    run(1e5, 25000.0, 0.0)?;
    Ok(())
}
