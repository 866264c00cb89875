//! Trial (riser engineer): hysteresis loop of the dynamic flex joint law (deck example 2,
//! element 3), moment-controlled, quasi-static. Fixed vessel, dynamic riser (no gravity).
//! 0-10 s ramp a static bending moment M0 about world z, hold to 20 s, switch to the
//! dynamic phase at 20 s, then a cyclic moment M0 + dM·sin(2π(t−20)/T).
//! Hand: variation amplitude a = φy + (dM − My)/Kdyn_lim, loop area 4·φy·(a−φy)·(Kini−Klim).
//! Also: torsion moment Mt about the riser axis → θx = Mt/Ktor.
use rapier_kjoint::law::ConnectorReport;
use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let deck_path = args.get(1).cloned().unwrap_or_else(|| {
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/assets/decks/flexjoint_example2.dat"
        )
        .into()
    });
    let m0: f64 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(20000.0);
    let dm: f64 = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(12000.0);
    let substeps: usize = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(16);
    let deck = RiserDeck::from_file(&deck_path)?;
    let el = &deck.joints[0];
    let dynp = el.law.dynamic.expect("a *FLEXPROADD record");
    let mut world = PhysicsWorld {
        gravity: Vector::ZERO,
        ..Default::default()
    };
    let vessel = world.insert_body(RigidBodyBuilder::fixed());
    let (riser, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, -5.0, 0.0))
            .can_sleep(false),
        ColliderBuilder::cylinder(5.0, 0.25).mass(2000.0),
    );
    let prop = KjointProperty::new(JointType::Spherical)
        .with_dof(Dof::Ry, DofLaw::default().with_viscosity(2e5))
        .with_dof(Dof::Rz, DofLaw::default().with_viscosity(2e5));
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let t_switch = 20.0;
    let h = joints.insert(
        el.joint_builder(prop)
            .world_frame1(Rotation::from_rotation_z(
                -std::f64::consts::FRAC_PI_2 as Real,
            ))
            .local_anchor2(Vector::new(0.0, 5.0, 0.0))
            .flex_joint_switch_time(t_switch),
        vessel,
        riser,
        &world.bodies,
    )?;
    for e in joints.drain_events() {
        println!("event: {e}");
    }
    let period = 20.0;
    let mt = 1e5; // torsion moment about world y
    let dt = 1.0 / 60.0;
    let n_cycles = 4;
    let t_end = t_switch + period * n_cycles as f64;
    let mut prev: Option<(f64, f64, f64)> = None; // (phi, M, ...) along the z bending
    let mut loop_area = vec![0.0; n_cycles];
    let mut diss_start = vec![f64::NAN; n_cycles + 1];
    let mut fric_start = vec![f64::NAN; n_cycles + 1];
    let mut amin = vec![f64::MAX; n_cycles];
    let mut amax = vec![f64::MIN; n_cycles];
    let mut bs = 0.0;
    let mut ms = 0.0;
    for frame in 0..(t_end / dt).round() as usize + 1 {
        let t = frame as f64 * dt;
        let mz = if t < 10.0 {
            m0 * t / 10.0
        } else if t < t_switch {
            m0
        } else {
            m0 + dm * (std::f64::consts::TAU * (t - t_switch) / period).sin()
        };
        let mty = mt * (t / 10.0).min(1.0);
        let b = &mut world.bodies[riser];
        b.reset_torques(true);
        b.add_torque(Vector::new(0.0, mty as Real, mz as Real), true);
        joints.step(&mut world, dt)?;
        for e in joints.drain_events() {
            println!("event: {e}");
        }
        let st = joints.get(h).unwrap().state().unwrap();
        let Some(ConnectorReport::FlexJoint(r)) = st.connector else {
            continue;
        };
        // signed bending about joint z (= world z, the moment's axis), law moment about z
        let phi = st.q[Dof::Rz];
        let mlaw = r.bending_moment[1];
        if (t - (t_switch - dt)).abs() < 0.5 * dt {
            bs = phi;
            ms = mlaw;
            println!(
                "at switch (t = {:.3}): β = {:.6e} rad, law moment {:.2} N·m, applied {:.2}; torsion θx = {:.6e} rad, M_x = {:.2} (Mt/Ktor = {:.6e})",
                t, r.bending_angle, r.bending_moment[0].hypot(r.bending_moment[1]), m0, r.torsion_angle, r.torsion_moment, mt / dynp.torsion_stiffness
            );
        }
        let tc = t + dt - t_switch;
        if tc > 0.0 {
            let k = (tc / period).floor() as usize;
            if k <= n_cycles && diss_start[k].is_nan() {
                diss_start[k] = r.dissipated_hysteresis;
                fric_start[k] = st.energy.friction;
            }
            if k < n_cycles {
                amin[k] = amin[k].min(phi - bs);
                amax[k] = amax[k].max(phi - bs);
                if let Some((p0, m0_, _)) = prev {
                    loop_area[k] += 0.5 * (mlaw + m0_) * (phi - p0);
                }
            }
        }
        prev = Some((phi, mlaw, t));
        if frame % 300 == 0 || (tc > 0.0 && tc < 0.05) {
            println!(
                "t={:7.3} phase {:?} β={:.5e} Mlaw=({:.1},{:.1}) yielding={} diss_hyst={:.3} E_fric={:.3}",
                t, r.phase, r.bending_angle, r.bending_moment[0], r.bending_moment[1], r.yielding, r.dissipated_hysteresis, st.energy.friction
            );
        }
    }
    let my = dynp.yield_moment();
    let a_hand = dynp.angle_lim + (dm - my) / dynp.kdyn_lim;
    println!(
        "static at switch: b_s = {bs:.6e} rad, M_s = {ms:.2} N·m; My = {my:.2}; hand amplitude a = {a_hand:.6e} rad, hand loop area {:.3} J",
        dynp.loop_area(a_hand)
    );
    for k in 0..n_cycles {
        let a = 0.5 * (amax[k] - amin[k]);
        println!(
            "cycle {}: variation [{:.6e}, {:.6e}] → a = {:.6e} rad; dissipated_hysteresis {:.3} J; joint E_friction {:.3} J; ∮M dφ {:.3} J; loop_area(a) {:.3} J",
            k + 1,
            amin[k],
            amax[k],
            a,
            diss_start[k + 1] - diss_start[k],
            fric_start[k + 1] - fric_start[k],
            loop_area[k],
            dynp.loop_area(a)
        );
    }
    let j = joints.get(h).unwrap();
    let e = j.closed_energy(&world.bodies);
    println!("joint energies: {e:?}");
    Ok(())
}
