//! User trial (game developer): a 4-wheel car on KJOINT2 joints.
//! Suspension: translational joint chassis -> hub (spring + damper + bump stops).
//! Wheels: revolute joint hub -> wheel (motor for driving / braking).
//!
//! `cargo run --release --example trial_car_ride [scenario]`
//! scenarios: rest, bottom, drop, park, slope, drive, bump (default: all)

use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;

const M_CHASSIS: f32 = 800.0;
const M_HUB: f32 = 5.0;
const M_WHEEL: f32 = 20.0;
const R_WHEEL: f32 = 0.35;
const K_SUSP: f64 = 40_000.0;
const C_SUSP: f64 = 3_000.0;
const STOP: f64 = 0.08;
const WHEEL_X: f32 = 1.0;
const WHEEL_Z: f32 = 1.0;
const SUSP_LEN: f32 = 0.3;
const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

struct Car {
    chassis: RigidBodyHandle,
    hubs: [RigidBodyHandle; 4],
    wheels: [RigidBodyHandle; 4],
    susp: [KjointHandle; 4],
    axles: [KjointHandle; 4],
}

fn corners() -> [(f32, f32); 4] {
    [
        (WHEEL_X, WHEEL_Z),
        (WHEEL_X, -WHEEL_Z),
        (-WHEEL_X, WHEEL_Z),
        (-WHEEL_X, -WHEEL_Z),
    ]
}

fn ground(world: &mut PhysicsWorld) -> RigidBodyHandle {
    let (g, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(200.0, 0.5, 50.0).friction(1.0),
    );
    g
}

/// A car whose chassis centre is at `pos` (wheels touching y = 0 if pos.y = R + SUSP_LEN).
fn build_car(
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    pos: Vector,
    chassis_mass: f32,
    susp_law: DofLaw,
) -> Car {
    let (chassis, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(pos),
        ColliderBuilder::cuboid(1.2, 0.15, 0.6).mass(chassis_mass),
    );
    let mut hubs = [RigidBodyHandle::invalid(); 4];
    let mut wheels = [RigidBodyHandle::invalid(); 4];
    let mut susp = [KjointHandle::invalid(); 4];
    let mut axles = [KjointHandle::invalid(); 4];
    let susp_prop = KjointProperty::new(JointType::Translational).with_dof(Dof::Dx, susp_law);
    let axle_prop = KjointProperty::new(JointType::Revolute);
    for (i, (x, z)) in corners().into_iter().enumerate() {
        let c = pos + Vector::new(x, -SUSP_LEN, z);
        let hub = world.insert_body(
            RigidBodyBuilder::dynamic()
                .translation(c)
                .additional_mass_properties(MassProperties::new(
                    Vector::ZERO,
                    M_HUB,
                    Vector::splat(0.02),
                )),
        );
        let (wheel, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(c),
            ColliderBuilder::ball(R_WHEEL).mass(M_WHEEL).friction(1.0),
        );
        susp[i] = joints
            .insert(
                KjointBuilder::new(susp_prop.clone())
                    .name(format!("susp{i}"))
                    .world_axis(Vector::Y)
                    .local_anchor1(Vector::new(x, -SUSP_LEN, z)),
                chassis,
                hub,
                &world.bodies,
            )
            .unwrap();
        axles[i] = joints
            .insert(
                KjointBuilder::new(axle_prop.clone())
                    .name(format!("axle{i}"))
                    .world_axis(Vector::Z)
                    .contacts_enabled(false),
                hub,
                wheel,
                &world.bodies,
            )
            .unwrap();
        hubs[i] = hub;
        wheels[i] = wheel;
    }
    Car {
        chassis,
        hubs,
        wheels,
        susp,
        axles,
    }
}

fn default_susp() -> DofLaw {
    DofLaw::spring(K_SUSP)
        .with_viscosity(C_SUSP)
        .with_stops(-STOP, STOP)
}

fn st(joints: &KjointSet, h: KjointHandle) -> &JointState {
    joints.get(h).unwrap().state().unwrap()
}

/// Kinetic + gravitational potential energy of every dynamic body (gravity along -y scaled by g).
fn body_energy(world: &PhysicsWorld) -> f64 {
    let mut e = 0.0;
    for (_, b) in world.bodies.iter() {
        if !b.is_dynamic() {
            continue;
        }
        let com = b.center_of_mass();
        e += b.kinetic_energy() as f64 - (b.mass() as f64) * (world.gravity.dot(com) as f64);
    }
    e
}

/// Sum of joints' closed energies: (elastic, dissipated incl. numerical, motor).
fn joint_energy(world: &PhysicsWorld, joints: &KjointSet) -> (f64, f64, f64) {
    let (mut el, mut dis, mut mo) = (0.0, 0.0, 0.0);
    for (_, j) in joints.iter() {
        let e = j.closed_energy(&world.bodies);
        el += e.elastic;
        dis += e.damping + e.friction + e.stop + e.numerical;
        mo += e.motor;
    }
    let r = joints.removed_energy();
    el += r.elastic;
    dis += r.damping + r.friction + r.stop + r.numerical;
    mo += r.motor;
    (el, dis, mo)
}

fn print_susp(joints: &KjointSet, car: &Car) {
    for i in 0..4 {
        let s = st(joints, car.susp[i]);
        let p = &s.parts[Dof::Dx];
        println!(
            "  susp{i}: q = {:+.5} m, rate = {:+.2e}, law F = {:+.1} N (elastic {:+.1}, damping {:+.1}, stop {:+.1}), applied = {:+.1} N, stop = {:?}, blocked applied (dy,dz,rx,ry,rz) = ({:+.1}, {:+.1}, {:+.1}, {:+.1}, {:+.1})",
            s.q[Dof::Dx],
            s.rate[Dof::Dx],
            s.force[Dof::Dx],
            p.elastic,
            p.damping,
            p.stop,
            s.applied[Dof::Dx],
            s.status[Dof::Dx].stop,
            s.applied[1],
            s.applied[2],
            s.applied[3],
            s.applied[4],
            s.applied[5],
        );
    }
}

fn no_sleep(world: &mut PhysicsWorld) {
    for (_, b) in world.bodies.iter_mut() {
        *b.activation_mut() = RigidBodyActivation::cannot_sleep();
    }
}

fn rest(sleep: bool, substeps: usize) {
    println!("== rest: 800 kg chassis on 4 springs of {K_SUSP} N/m (sleep {sleep}, {substeps} substeps) ==");
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let y0 = R_WHEEL + SUSP_LEN;
    let car = build_car(
        &mut world,
        &mut joints,
        Vector::new(0.0, y0, 0.0),
        M_CHASSIS,
        default_susp(),
    );
    if !sleep {
        no_sleep(&mut world);
    }
    let sag = M_CHASSIS as f64 * G / 4.0 / K_SUSP;
    println!(
        "  expected: sag m*g/(4k) = {:.5} m, spring force {:.1} N per corner, chassis y = {:.5} (minus contact penetration)",
        sag,
        M_CHASSIS as f64 * G / 4.0,
        y0 as f64 - sag
    );
    let mut ys = vec![];
    let mut max_v: f32 = 0.0;
    let mut max_w: f32 = 0.0;
    let mut p_at_5 = Vector::ZERO;
    for frame in 1..=900 {
        joints.step(&mut world, DT).unwrap();
        let b = &world.bodies[car.chassis];
        if frame == 300 {
            p_at_5 = b.translation();
            print_susp(&joints, &car);
        }
        if frame > 300 {
            ys.push(b.translation().y);
            max_v = max_v.max(b.linvel().length());
            max_w = max_w.max(b.angvel().length());
        }
        if frame % 60 == 0 && frame <= 180 {
            println!(
                "  t={:.1} chassis y = {:.5}, q0 = {:+.5}",
                joints.time(),
                b.translation().y,
                st(&joints, car.susp[0]).q[0]
            );
        }
    }
    let b = &world.bodies[car.chassis];
    let p = b.translation();
    let ymin = ys.iter().cloned().fold(f32::MAX, f32::min);
    let ymax = ys.iter().cloned().fold(f32::MIN, f32::max);
    println!(
        "  t=5..15 s: chassis y in [{ymin:.6}, {ymax:.6}], drift {:?} (x,z) = ({:+.2e}, {:+.2e}) m, max |v| = {:.2e} m/s, max |w| = {:.2e} rad/s, sleeping = {}",
        p - p_at_5,
        p.x - p_at_5.x,
        p.z - p_at_5.z,
        max_v,
        max_w,
        b.is_sleeping()
    );
    for i in 0..4 {
        let w = &world.bodies[car.wheels[i]];
        println!(
            "  wheel{i}: y = {:.5} (penetration {:.2e}), hub-wheel offset = {:.2e} m",
            w.translation().y,
            R_WHEEL - w.translation().y,
            (world.bodies[car.hubs[i]].translation() - w.translation()).length()
        );
        let a = st(&joints, car.axles[i]);
        println!(
            "  axle{i}: applied (dx,dy,dz) = ({:+.1}, {:+.1}, {:+.1}) N, expected |F| = {:.1} N",
            a.applied[0],
            a.applied[1],
            a.applied[2],
            (M_CHASSIS as f64 / 4.0 + M_HUB as f64) * G
        );
    }
    print_susp(&joints, &car);
    let (el, dis, mo) = joint_energy(&world, &joints);
    println!(
        "  energy: joint elastic {el:.3} J (expected 4*0.5*k*sag^2 = {:.3} J), dissipated {dis:.3} J, motor {mo:.3}",
        4.0 * 0.5 * K_SUSP * sag * sag
    );
    let ev = joints.drain_events();
    println!("  events: {}", ev.len());
    for e in ev.iter().take(5) {
        println!("    {e:?}");
    }
}

fn bottom(sleep: bool) {
    let m = 2800.0f32;
    println!(
        "== bottom: {m} kg chassis, sag would be {:.4} m > stop {STOP} m ==",
        m as f64 * G / 4.0 / K_SUSP
    );
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let mut joints = KjointSet::new();
    let car = build_car(
        &mut world,
        &mut joints,
        Vector::new(0.0, R_WHEEL + SUSP_LEN, 0.0),
        m,
        default_susp(),
    );
    if !sleep {
        no_sleep(&mut world);
    }
    let mut qmax: f64 = 0.0;
    for frame in 1..=600 {
        joints.step(&mut world, DT).unwrap();
        for i in 0..4 {
            qmax = qmax.max(st(&joints, car.susp[i]).q[0]);
        }
        if frame % 120 == 0 {
            println!(
                "  t={:.1} chassis y = {:.5} q0 = {:+.6}",
                joints.time(),
                world.bodies[car.chassis].translation().y,
                st(&joints, car.susp[0]).q[0]
            );
        }
    }
    println!(
        "  expected: q = {STOP} on the stop; applied = m*g/4 = {:.1} N, spring part k*stop = {:.1} N",
        m as f64 * G / 4.0,
        K_SUSP * STOP
    );
    println!("  max q over run = {qmax:.6}");
    print_susp(&joints, &car);
    let (el, dis, _) = joint_energy(&world, &joints);
    println!("  energy: elastic {el:.3} J (spring alone at stop 4*0.5*k*s^2 = {:.3}), dissipated {dis:.3} J", 4.0 * 0.5 * K_SUSP * STOP * STOP);
}

fn drop_test() {
    println!("== drop: 800 kg car dropped from 1.0 m above the ground ==");
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let mut joints = KjointSet::new();
    let car = build_car(
        &mut world,
        &mut joints,
        Vector::new(0.0, R_WHEEL + SUSP_LEN + 1.0, 0.0),
        M_CHASSIS,
        default_susp(),
    );
    let mut qmax: f64 = -1.0;
    let mut qmin: f64 = 1.0;
    let mut max_applied: f64 = 0.0;
    let mut frames_on_stop = 0;
    let mut ymax_after_land = 0.0f32;
    let mut landed = false;
    for _ in 1..=300 {
        joints.step(&mut world, DT).unwrap();
        for i in 0..4 {
            let s = st(&joints, car.susp[i]);
            qmax = qmax.max(s.q[0]);
            qmin = qmin.min(s.q[0]);
            max_applied = max_applied.max(s.applied[0].abs());
            if i == 0 && s.status[0].stop != StopContact::None {
                frames_on_stop += 1;
            }
        }
        let y = world.bodies[car.chassis].translation().y;
        if qmax > 0.02 {
            landed = true;
        }
        if landed {
            ymax_after_land = ymax_after_land.max(y);
        }
    }
    println!(
        "  q range [{qmin:+.5}, {qmax:+.5}] (stops ±{STOP}); overrun beyond stop {:.2e} m; peak applied {max_applied:.0} N; frames on a stop (susp0) {frames_on_stop}; chassis y max after landing {ymax_after_land:.4} (start {:.3})",
        qmax - STOP,
        R_WHEEL + SUSP_LEN + 1.0
    );
    print_susp(&joints, &car);
    println!(
        "  final chassis y = {:.5} (expected rest {:.5})",
        world.bodies[car.chassis].translation().y,
        (R_WHEEL + SUSP_LEN) as f64 - M_CHASSIS as f64 * G / 4.0 / K_SUSP
    );
}

fn park(slope_deg: f64, brake: Option<KjointMotor>) {
    println!("== park: slope {slope_deg} deg, brake {brake:?} ==");
    let mut world = PhysicsWorld::default();
    let th = slope_deg.to_radians();
    // slope via tilted gravity: downhill = +x
    world.gravity = Vector::new((G * th.sin()) as f32, (-G * th.cos()) as f32, 0.0);
    ground(&mut world);
    let mut joints = KjointSet::new();
    let car = build_car(
        &mut world,
        &mut joints,
        Vector::new(0.0, R_WHEEL + SUSP_LEN, 0.0),
        M_CHASSIS,
        default_susp(),
    );
    if let Some(m) = brake {
        for i in 0..4 {
            joints.set_motor(car.axles[i], Dof::Rx, Some(m)).unwrap();
        }
    }
    let mut x_at = vec![];
    for frame in 1..=900 {
        joints.step(&mut world, DT).unwrap();
        if frame % 150 == 0 {
            let b = &world.bodies[car.chassis];
            x_at.push((joints.time(), b.translation(), b.linvel()));
        }
    }
    for (t, p, v) in &x_at {
        println!(
            "  t={t:.1} chassis pos = ({:+.6}, {:.6}, {:+.2e}) v = ({:+.3e}, {:+.2e}, {:+.2e})",
            p.x, p.y, p.z, v.x, v.y, v.z
        );
    }
    if let Some(m) = brake {
        let total_m = (M_CHASSIS + 4.0 * (M_HUB + M_WHEEL)) as f64;
        let f_wheel = total_m * G * th.sin() / 4.0;
        let tau = f_wheel * R_WHEEL as f64;
        let v = tau / m.damping * R_WHEEL as f64;
        println!(
            "  expected creep with velocity-brake k_d={}: torque/wheel {:.1} N*m -> wheel rate {:.3e} rad/s -> v = {:.3e} m/s",
            m.damping, tau, tau / m.damping, v
        );
        for i in 0..4 {
            let s = st(&joints, car.axles[i]);
            println!(
                "  axle{i}: rate = {:+.4e} rad/s, motor part = {:+.2} N*m, applied Rx = {:+.2}",
                s.rate[Dof::Rx],
                s.parts[Dof::Rx].motor,
                s.applied[Dof::Rx]
            );
        }
    }
}

fn drive(with_bump: bool) {
    println!(
        "== drive{}: rear wheel velocity motors to 10 rad/s for 4 s, then coast 6 s ==",
        if with_bump { " over a 6 cm bump" } else { "" }
    );
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    if with_bump {
        // a bump 6 cm high, 40 cm long, across the road at x = 12 m
        world.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(12.0, 0.0, 0.0)),
            ColliderBuilder::cuboid(0.2, 0.06, 5.0).friction(1.0),
        );
    }
    let mut joints = KjointSet::new();
    let car = build_car(
        &mut world,
        &mut joints,
        Vector::new(0.0, R_WHEEL + SUSP_LEN, 0.0),
        M_CHASSIS,
        default_susp(),
    );
    // settle
    for _ in 0..120 {
        joints.step(&mut world, DT).unwrap();
    }
    // wheel rotation about world z: rolling in +x means angvel.z < 0; joint x = world z,
    // so drive with a negative target.
    let motor = KjointMotor::velocity(-10.0, 500.0).max_force(600.0);
    for i in [2, 3] {
        joints
            .set_motor(car.axles[i], Dof::Rx, Some(motor))
            .unwrap();
    }
    let (el0, dis0, mo0) = joint_energy(&world, &joints);
    let e0 = body_energy(&world) + el0 + dis0 + mo0;
    let mut coast_start = None;
    let mut prev_total_mech: Option<f64> = None;
    let mut max_gain = 0.0f64;
    let mut max_gain_t = 0.0;
    let mut max_pitch = 0.0f32;
    let mut qmax = -1.0f64;
    let mut qmin = 1.0f64;
    let mut stop_frames = 0;
    let mut max_zdrift = 0.0f32;
    for frame in 1..=600 {
        if frame == 241 {
            for i in [2, 3] {
                joints.set_motor(car.axles[i], Dof::Rx, None).unwrap();
            }
        }
        joints.step(&mut world, DT).unwrap();
        let b = &world.bodies[car.chassis];
        let (el, dis, mo) = joint_energy(&world, &joints);
        let eb = body_energy(&world);
        let mech = eb + el; // what the model holds
        let balance = eb + el + dis + mo - e0;
        for i in 0..4 {
            let s = st(&joints, car.susp[i]);
            qmax = qmax.max(s.q[0]);
            qmin = qmin.min(s.q[0]);
            if s.status[0].stop != StopContact::None {
                stop_frames += 1;
            }
        }
        let (ax, ang) = b.rotation().to_axis_angle();
        max_pitch = max_pitch.max((ax.z * ang).abs());
        max_zdrift = max_zdrift.max(b.translation().z.abs());
        if frame > 240 {
            if coast_start.is_none() {
                coast_start = Some(mech);
            }
            if let Some(p) = prev_total_mech {
                let gain = mech - p;
                if gain > max_gain {
                    max_gain = gain;
                    max_gain_t = joints.time();
                }
            }
            prev_total_mech = Some(mech);
        }
        if frame % 60 == 0 {
            println!(
                "  t={:.1} x = {:7.3} vx = {:6.3} y = {:.4} pitch = {:+.4} | KE+PE(bodies) {:10.2} J elastic {:7.2} dissipated {:8.2} motor {:8.2} | balance residual {:+.3} J",
                joints.time(),
                b.translation().x,
                b.linvel().x,
                b.translation().y,
                ang * ax.z,
                eb,
                el,
                dis,
                mo,
                balance
            );
        }
    }
    let cs = coast_start.unwrap();
    let (el, _, _) = joint_energy(&world, &joints);
    let mech_end = body_energy(&world) + el;
    println!(
        "  coasting: bodies+elastic {cs:.2} -> {mech_end:.2} J; largest frame-to-frame gain while coasting {max_gain:+.4} J at t={max_gain_t:.3}"
    );
    println!(
        "  susp q range [{qmin:+.4}, {qmax:+.4}] (stops ±{STOP}), frames*joints on a stop {stop_frames}, max |pitch| {max_pitch:.4} rad, max |z| drift {max_zdrift:.2e} m"
    );
    let ev = joints.drain_events();
    println!("  events: {}", ev.len());
    for e in ev.iter().take(8) {
        println!("    {e}");
    }
}

fn main() {
    let arg = std::env::args().nth(1).unwrap_or_else(|| "all".into());
    let all = arg == "all";
    if all || arg == "rest" {
        rest(true, 4);
    }
    if all || arg == "rest_nosleep" {
        for n in [4, 8, 16] {
            rest(false, n);
        }
    }
    if all || arg == "bottom" {
        bottom(true);
    }
    if all || arg == "bottom_nosleep" {
        bottom(false);
    }
    if all || arg == "drop" {
        drop_test();
    }
    if all || arg == "park" {
        park(0.0, None);
    }
    if all || arg == "slope" {
        park(5.0, None);
        park(5.0, Some(KjointMotor::velocity(0.0, 1e4)));
    }
    if all || arg == "drive" {
        drive(false);
    }
    if all || arg == "bump" {
        drive(true);
    }
}
