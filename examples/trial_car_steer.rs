//! User trial (game developer): steering, a trailer on a ball hitch, wheel spin-up on a
//! hoist, freezing / respawning the car.
//!
//! `cargo run --release --example trial_car_steer [steer|trailer|spin|freeze|teleport]`

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
    bodies: Vec<RigidBodyHandle>,
    hubs: [RigidBodyHandle; 4],
    wheels: [RigidBodyHandle; 4],
    susp: [KjointHandle; 4],
    steer: [Option<KjointHandle>; 4],
    axles: [KjointHandle; 4],
}

fn small_body(world: &mut PhysicsWorld, p: Vector, m: f32) -> RigidBodyHandle {
    world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(p)
            .additional_mass_properties(MassProperties::new(Vector::ZERO, m, Vector::splat(0.02))),
    )
}

/// Car with chassis at `pos`; front wheels (x > 0) on a steering knuckle (revolute about y
/// with a position motor) when `steering`.
fn build_car(world: &mut PhysicsWorld, joints: &mut KjointSet, pos: Vector, steering: bool) -> Car {
    let (chassis, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(pos),
        ColliderBuilder::cuboid(1.2, 0.15, 0.6).mass(M_CHASSIS),
    );
    let mut bodies = vec![chassis];
    let mut hubs = [RigidBodyHandle::invalid(); 4];
    let mut wheels = [RigidBodyHandle::invalid(); 4];
    let mut susp = [KjointHandle::invalid(); 4];
    let mut steer = [None; 4];
    let mut axles = [KjointHandle::invalid(); 4];
    let corners = [
        (WHEEL_X, WHEEL_Z),
        (WHEEL_X, -WHEEL_Z),
        (-WHEEL_X, WHEEL_Z),
        (-WHEEL_X, -WHEEL_Z),
    ];
    for (i, (x, z)) in corners.into_iter().enumerate() {
        let c = pos + Vector::new(x, -SUSP_LEN, z);
        let hub = small_body(world, c, M_HUB);
        bodies.push(hub);
        susp[i] = joints
            .insert(
                KjointBuilder::new(
                    KjointProperty::new(JointType::Translational).with_dof(
                        Dof::Dx,
                        DofLaw::spring(K_SUSP)
                            .with_viscosity(C_SUSP)
                            .with_stops(-STOP, STOP),
                    ),
                )
                .name(format!("susp{i}"))
                .world_axis(Vector::Y)
                .local_anchor1(Vector::new(x, -SUSP_LEN, z)),
                chassis,
                hub,
                &world.bodies,
            )
            .unwrap();
        let mut carrier = hub;
        if steering && x > 0.0 {
            let knuckle = small_body(world, c, 3.0);
            bodies.push(knuckle);
            steer[i] = Some(
                joints
                    .insert(
                        KjointBuilder::new(
                            KjointProperty::new(JointType::Revolute)
                                .with_dof(Dof::Rx, DofLaw::default().with_stops(-0.6, 0.6)),
                        )
                        .name(format!("steer{i}"))
                        .world_axis(Vector::Y)
                        .motor(Dof::Rx, KjointMotor::position(0.0, 2e4, 500.0)),
                        hub,
                        knuckle,
                        &world.bodies,
                    )
                    .unwrap(),
            );
            carrier = knuckle;
        }
        let (wheel, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(c),
            ColliderBuilder::ball(R_WHEEL).mass(M_WHEEL).friction(1.0),
        );
        bodies.push(wheel);
        axles[i] = joints
            .insert(
                KjointBuilder::new(KjointProperty::new(JointType::Revolute))
                    .name(format!("axle{i}"))
                    .world_axis(Vector::Z)
                    .contacts_enabled(false),
                carrier,
                wheel,
                &world.bodies,
            )
            .unwrap();
        hubs[i] = hub;
        wheels[i] = wheel;
    }
    Car {
        chassis,
        bodies,
        hubs,
        wheels,
        susp,
        steer,
        axles,
    }
}

fn ground(world: &mut PhysicsWorld) {
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(300.0, 0.5, 300.0).friction(1.0),
    );
}

fn yaw(b: &RigidBody) -> f32 {
    let f = b.rotation() * Vector::X;
    (-f.z).atan2(f.x)
}

fn steer() {
    println!("== steer: front knuckles to 0.3 rad at ~3.5 m/s ==");
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let mut joints = KjointSet::new();
    let car = build_car(
        &mut world,
        &mut joints,
        Vector::new(0.0, R_WHEEL + SUSP_LEN, 0.0),
        true,
    );
    for _ in 0..60 {
        joints.step(&mut world, DT).unwrap();
    }
    for i in [2, 3] {
        joints
            .set_motor(
                car.axles[i],
                Dof::Rx,
                Some(KjointMotor::velocity(-10.0, 500.0).max_force(600.0)),
            )
            .unwrap();
    }
    for _ in 0..180 {
        joints.step(&mut world, DT).unwrap();
    }
    let delta = 0.3;
    for i in [0, 1] {
        joints
            .set_motor(
                car.steer[i].unwrap(),
                Dof::Rx,
                Some(KjointMotor::position(delta, 2e4, 500.0)),
            )
            .unwrap();
    }
    let mut yaw_prev = yaw(&world.bodies[car.chassis]);
    let mut rates = vec![];
    for f in 0..360 {
        joints.step(&mut world, DT).unwrap();
        let b = &world.bodies[car.chassis];
        let y = yaw(b);
        let mut d = y - yaw_prev;
        if d > std::f32::consts::PI {
            d -= 2.0 * std::f32::consts::PI;
        }
        if d < -std::f32::consts::PI {
            d += 2.0 * std::f32::consts::PI;
        }
        yaw_prev = y;
        if f >= 120 {
            rates.push((d as f64 / DT, b.linvel().length() as f64));
        }
        if f % 60 == 59 {
            let s0 = joints.get(car.steer[0].unwrap()).unwrap().state().unwrap();
            println!(
                "  t={:.2} pos=({:.2},{:.2}) speed={:.3} yaw={:.3} steer q={:.4} (motor part {:.1} N*m) roll stop? susp q = [{:.4} {:.4} {:.4} {:.4}]",
                joints.time(),
                b.translation().x,
                b.translation().z,
                b.linvel().length(),
                y,
                s0.q[Dof::Rx],
                s0.parts[Dof::Rx].motor,
                joints.get(car.susp[0]).unwrap().state().unwrap().q[0],
                joints.get(car.susp[1]).unwrap().state().unwrap().q[0],
                joints.get(car.susp[2]).unwrap().state().unwrap().q[0],
                joints.get(car.susp[3]).unwrap().state().unwrap().q[0],
            );
        }
    }
    let n = rates.len() as f64;
    let w = rates.iter().map(|r| r.0).sum::<f64>() / n;
    let v = rates.iter().map(|r| r.1).sum::<f64>() / n;
    let wheelbase = 2.0 * WHEEL_X as f64;
    let r_kin = wheelbase / (delta as f64).tan();
    println!(
        "  measured yaw rate {w:.4} rad/s at {v:.3} m/s -> radius {:.2} m; kinematic (Ackermann-free, bicycle) radius L/tan(delta) = {r_kin:.2} m -> yaw rate {:.4}",
        v / w,
        v / r_kin
    );
    let ev = joints.drain_events();
    println!("  events: {}", ev.len());
    for e in ev.iter().take(5) {
        println!("    {e}");
    }
}

fn trailer() {
    println!("== trailer: 300 kg box on a ball hitch, axle 0.4 m behind its centre, hitch 1.4 m ahead ==");
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let mut joints = KjointSet::new();
    let y0 = R_WHEEL + SUSP_LEN;
    let car = build_car(&mut world, &mut joints, Vector::new(0.0, y0, 0.0), false);
    // hitch point: car rear at x = -1.6, y = y0 - 0.1
    let hitch = Vector::new(-1.6, y0 - 0.1, 0.0);
    let tc = hitch - Vector::new(1.4, 0.0, 0.0); // trailer centre
    let (trailer, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(tc),
        ColliderBuilder::cuboid(1.0, 0.1, 0.5).mass(300.0),
    );
    let hitch_h = joints
        .insert(
            KjointBuilder::new(KjointProperty::new(JointType::Spherical))
                .name("hitch")
                .local_anchor1(hitch - Vector::new(0.0, y0, 0.0))
                .local_anchor2(hitch - tc)
                .contacts_enabled(false),
            car.chassis,
            trailer,
            &world.bodies,
        )
        .unwrap();
    // trailer wheels: directly on the trailer body; axle 0.4 m behind the trailer centre,
    // wheel centres at y = R (touching), so the trailer's axle offset is y0 - 0.1 - R below.
    let mut twheels = vec![];
    for z in [0.8f32, -0.8] {
        let wc = Vector::new(tc.x - 0.4, R_WHEEL, z);
        let (w, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(wc),
            ColliderBuilder::ball(R_WHEEL).mass(15.0).friction(1.0),
        );
        twheels.push(
            joints
                .insert(
                    KjointBuilder::new(KjointProperty::new(JointType::Revolute))
                        .world_axis(Vector::Z)
                        .local_anchor1(wc - tc)
                        .contacts_enabled(false),
                    trailer,
                    w,
                    &world.bodies,
                )
                .unwrap(),
        );
    }
    for _ in 0..300 {
        joints.step(&mut world, DT).unwrap();
    }
    let s = joints.get(hitch_h).unwrap().state().unwrap();
    // moments about the trailer axle (horizontal distances): W*0.4 = F*1.8
    let f_exp = 300.0 * G * 0.4 / 1.8;
    println!(
        "  static: hitch applied (dx,dy,dz) = ({:+.1}, {:+.1}, {:+.1}) N, rotations q = ({:+.4},{:+.4},{:+.4}); expected vertical hitch load {f_exp:.1} N (body 1 = car receives it downward)",
        s.applied[0], s.applied[1], s.applied[2], s.q[3], s.q[4], s.q[5]
    );
    println!(
        "  hitch anchors apart: {:.2e} m",
        ((Vector::new(
            s.anchor1[0] as f32,
            s.anchor1[1] as f32,
            s.anchor1[2] as f32
        )) - Vector::new(
            s.anchor2[0] as f32,
            s.anchor2[1] as f32,
            s.anchor2[2] as f32
        ))
        .length()
    );
    for i in 0..4 {
        let q = joints.get(car.susp[i]).unwrap().state().unwrap().q[0];
        println!("  susp{i} q = {q:.5}");
    }
    // expected: the hitch load 654 N at x=-1.6: rear corners take more.
    // moments about front axle (x=+1): 800*g*1 + F*2.6 = R_rear*2  (chassis only; spring loads)
    let rear = (800.0 * G * 1.0 + f_exp * 2.6) / 2.0 / 2.0;
    let front = (800.0 * G + f_exp) / 2.0 - rear;
    println!(
        "  expected spring loads: front {front:.1} N -> q {:.5}, rear {rear:.1} N -> q {:.5}",
        front / K_SUSP,
        rear / K_SUSP
    );
    // tow: accelerate with rear-wheel motors
    for i in [2, 3] {
        joints
            .set_motor(
                car.axles[i],
                Dof::Rx,
                Some(KjointMotor::velocity(-10.0, 500.0).max_force(600.0)),
            )
            .unwrap();
    }
    let mut vprev = world.bodies[trailer].linvel().x as f64;
    for f in 0..240 {
        joints.step(&mut world, DT).unwrap();
        if f % 30 == 29 {
            let v = world.bodies[trailer].linvel().x as f64;
            let a = (v - vprev) / (30.0 * DT);
            vprev = v;
            let s = joints.get(hitch_h).unwrap().state().unwrap();
            // trailer + wheels mass with wheel inertia as rolling mass (balls: 2/5 m)
            let m_eff = 300.0 + 2.0 * 15.0 * 1.4;
            println!(
                "  t={:.2} trailer vx {v:.3} avg accel {a:.3} -> m_eff*a = {:.1} N; hitch applied dx {:+.1} dy {:+.1} dz {:+.1}",
                joints.time(),
                m_eff * a,
                s.applied[0],
                s.applied[1],
                s.applied[2]
            );
        }
    }
    let ev = joints.drain_events();
    println!("  events: {}", ev.len());
    for e in ev.iter().take(5) {
        println!("    {e}");
    }
    let _ = twheels;
}

fn spin() {
    println!("== spin: chassis on a hoist (fixed), rear wheels driven to 300 rad/s in the air ==");
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let mut joints = KjointSet::new();
    let car = build_car(&mut world, &mut joints, Vector::new(0.0, 2.0, 0.0), false);
    world.bodies[car.chassis].set_body_type(RigidBodyType::Fixed, true);
    for i in [2, 3] {
        joints
            .set_motor(
                car.axles[i],
                Dof::Rx,
                Some(KjointMotor::velocity(-300.0, 50.0).max_force(400.0)),
            )
            .unwrap();
    }
    let i_wheel = 0.4 * M_WHEEL as f64 * (R_WHEEL as f64).powi(2);
    let ke = |world: &PhysicsWorld| -> f64 {
        car.wheels
            .iter()
            .map(|w| world.bodies[*w].kinetic_energy() as f64)
            .sum::<f64>()
            + car
                .hubs
                .iter()
                .map(|w| world.bodies[*w].kinetic_energy() as f64)
                .sum::<f64>()
    };
    let mut gap: f32 = 0.0;
    let mut wobble: f32 = 0.0;
    for f in 0..600 {
        if f == 360 {
            for i in [2, 3] {
                joints.set_motor(car.axles[i], Dof::Rx, None).unwrap();
            }
        }
        joints.step(&mut world, DT).unwrap();
        for i in 0..4 {
            let w = &world.bodies[car.wheels[i]];
            gap = gap.max((w.translation() - world.bodies[car.hubs[i]].translation()).length());
            let av = w.angvel();
            wobble = wobble.max(av.x.hypot(av.y));
        }
        if f % 60 == 59 {
            let s = joints.get(car.axles[2]).unwrap().state().unwrap();
            let e = joints
                .get(car.axles[2])
                .unwrap()
                .closed_energy(&world.bodies);
            let es: f64 = car
                .axles
                .iter()
                .map(|h| {
                    let e = joints.get(*h).unwrap().closed_energy(&world.bodies);
                    e.elastic + e.damping + e.friction + e.stop + e.numerical + e.motor
                })
                .sum::<f64>()
                + car
                    .susp
                    .iter()
                    .map(|h| {
                        let e = joints.get(*h).unwrap().closed_energy(&world.bodies);
                        e.elastic + e.damping + e.friction + e.stop + e.numerical + e.motor
                    })
                    .sum::<f64>();
            let pe: f64 = car
                .wheels
                .iter()
                .chain(car.hubs.iter())
                .map(|h| {
                    let b = &world.bodies[*h];
                    b.mass() as f64 * G * b.center_of_mass().y as f64
                })
                .sum();
            println!(
                "  t={:.1} wheel2 w = {:+.2} rad/s (rate readout {:+.2}), KE(wheels+hubs) = {:.1} J (1/2 I w^2 x2 = {:.1}), motor work {:.1} J, balance KE+PE+joints = {:.2} J, max gap {gap:.2e} m, max off-axis w {wobble:.2e}, susp2 q {:.5}",
                joints.time(),
                world.bodies[car.wheels[2]].angvel().z,
                s.rate[Dof::Rx],
                ke(&world),
                2.0 * 0.5 * i_wheel * (world.bodies[car.wheels[2]].angvel().z as f64).powi(2),
                -e.motor,
                ke(&world) + pe + es,
                joints.get(car.susp[2]).unwrap().state().unwrap().q[0],
            );
        }
    }
    println!(
        "  expected hanging susp q = -(hub+wheel) g / k = {:.5} m",
        -((M_HUB + M_WHEEL) as f64) * G / K_SUSP
    );
    let ev = joints.drain_events();
    println!("  events: {}", ev.len());
    for e in ev.iter().take(5) {
        println!("    {e}");
    }
}

fn freeze() {
    for kind in [RigidBodyType::KinematicPositionBased, RigidBodyType::Fixed] {
        println!(
            "== freeze: whole parked car switched to {kind:?} for 1 s, then back to dynamic =="
        );
        let mut world = PhysicsWorld::default();
        ground(&mut world);
        let mut joints = KjointSet::new();
        let car = build_car(
            &mut world,
            &mut joints,
            Vector::new(0.0, R_WHEEL + SUSP_LEN, 0.0),
            false,
        );
        for _ in 0..120 {
            joints.step(&mut world, DT).unwrap();
        }
        let y_before = world.bodies[car.chassis].translation().y;
        for b in &car.bodies {
            world.bodies[*b].set_body_type(kind, true);
        }
        let mut errs = 0;
        let mut first_err = None;
        for _ in 0..60 {
            if let Err(e) = joints.step(&mut world, DT) {
                errs += 1;
                if first_err.is_none() {
                    first_err = Some(e.to_string());
                }
                world.step(); // what a game would do to keep going
            }
        }
        println!("  while frozen: {errs} of 60 steps failed; first: {first_err:?}");
        for b in &car.bodies {
            world.bodies[*b].set_body_type(RigidBodyType::Dynamic, true);
        }
        let mut errs2 = 0;
        let mut ymin = f32::MAX;
        let mut ymax = f32::MIN;
        let mut vwmax: f32 = 0.0;
        let mut gmax: f32 = 0.0;
        for _ in 0..120 {
            if joints.step(&mut world, DT).is_err() {
                errs2 += 1;
            }
            for i in 0..4 {
                vwmax = vwmax.max(world.bodies[car.wheels[i]].linvel().length());
                gmax = gmax.max(
                    (world.bodies[car.wheels[i]].translation()
                        - world.bodies[car.hubs[i]].translation())
                    .length(),
                );
            }
            let y = world.bodies[car.chassis].translation().y;
            ymin = ymin.min(y);
            ymax = ymax.max(y);
        }
        println!(
            "  after unfreeze: max wheel speed {vwmax:.3} m/s, max hub-wheel gap {gmax:.2e} m"
        );
        println!(
            "  after: {errs2} failed steps; chassis y {y_before:.5} before, range [{ymin:.5}, {ymax:.5}] after; susp0 q {:.5}",
            joints.get(car.susp[0]).unwrap().state().unwrap().q[0]
        );
        let ev = joints.drain_events();
        println!("  events: {}", ev.len());
        for e in ev.iter().take(40) {
            println!("    {e}");
        }
    }
}

fn teleport() {
    println!("== teleport (respawn) ==");
    for whole in [true, false] {
        let mut world = PhysicsWorld::default();
        ground(&mut world);
        let mut joints = KjointSet::new();
        let car = build_car(
            &mut world,
            &mut joints,
            Vector::new(0.0, R_WHEEL + SUSP_LEN, 0.0),
            false,
        );
        for _ in 0..60 {
            joints.step(&mut world, DT).unwrap();
        }
        let off = Vector::new(20.0, 0.5, 0.0);
        let movers: Vec<RigidBodyHandle> = if whole {
            car.bodies.clone()
        } else {
            vec![car.chassis]
        };
        for b in movers {
            let p = world.bodies[b].translation();
            world.bodies[b].set_translation(p + off, true);
        }
        let mut vmax: f32 = 0.0;
        let mut err = None;
        for k in 0..120 {
            if let Err(e) = joints.step(&mut world, DT) {
                err = Some(format!("step {k}: {e}"));
                break;
            }
            for b in &car.bodies {
                vmax = vmax.max(world.bodies[*b].linvel().length());
            }
        }
        println!(
            "  {}: max body speed afterwards {vmax:.2} m/s; error: {err:?}; chassis at {:?}",
            if whole {
                "all 13 bodies moved 20 m"
            } else {
                "chassis only moved 20 m"
            },
            world.bodies[car.chassis].translation()
        );
        // can the game recover after an error? move everything next to the chassis again
        if err.is_some() {
            let cp = world.bodies[car.chassis].translation();
            let corners = [(1.0f32, 1.0f32), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)];
            for i in 0..4 {
                let p = cp + Vector::new(corners[i].0, -SUSP_LEN, corners[i].1);
                for b in [car.hubs[i], car.wheels[i]] {
                    world.bodies[b].set_translation(p, true);
                    world.bodies[b].set_linvel(Vector::ZERO, true);
                    world.bodies[b].set_angvel(Vector::ZERO, true);
                }
            }
            world.bodies[car.chassis].set_linvel(Vector::ZERO, true);
            world.bodies[car.chassis].set_angvel(Vector::ZERO, true);
            let mut e2 = 0;
            let mut first = None;
            for _ in 0..60 {
                if let Err(e) = joints.step(&mut world, DT) {
                    e2 += 1;
                    first.get_or_insert(e.to_string());
                }
            }
            println!(
                "  recovery (bodies put back by hand, velocities zeroed): {e2} failed steps of 60, first {first:?}; joints left {}; chassis at {:?}",
                joints.len(),
                world.bodies[car.chassis].translation()
            );
        }
        let ev = joints.drain_events();
        println!("  events: {}", ev.len());
        for e in ev.iter().take(40) {
            println!("    {e}");
        }
    }
}

fn main() {
    let arg = std::env::args().nth(1).unwrap_or_else(|| "all".into());
    let all = arg == "all";
    if all || arg == "steer" {
        steer();
    }
    if all || arg == "trailer" {
        trailer();
    }
    if all || arg == "spin" {
        spin();
    }
    if all || arg == "freeze" {
        freeze();
    }
    if all || arg == "teleport" {
        teleport();
    }
}
