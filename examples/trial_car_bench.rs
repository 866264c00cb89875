//! User trial (game developer): the same car on KJOINT2 joints and on rapier's own joints,
//! in the same program: behaviour (rest, drop, bump) and frame cost.
//!
//! `cargo run --release --example trial_car_bench [rest|drop|bump|time]`

use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;
use std::time::Instant;

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
const DT: f64 = 1.0 / 60.0;

#[derive(Clone, Copy, PartialEq, Debug)]
enum Engine {
    Kjoint(usize),
    Rapier,
}

struct Car {
    chassis: RigidBodyHandle,
    hubs: [RigidBodyHandle; 4],
    wheels: [RigidBodyHandle; 4],
    kaxles: Vec<KjointHandle>,
    raxles: Vec<ImpulseJointHandle>,
}

struct Sim {
    world: PhysicsWorld,
    joints: KjointSet,
    engine: Engine,
    cars: Vec<Car>,
}

impl Sim {
    fn new(engine: Engine) -> Sim {
        let mut world = PhysicsWorld::default();
        world.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
            ColliderBuilder::cuboid(500.0, 0.5, 500.0).friction(1.0),
        );
        let n = match engine {
            Engine::Kjoint(n) => n,
            Engine::Rapier => 4,
        };
        Sim {
            world,
            joints: KjointSet::with_settings(SubstepSettings {
                substeps: n,
                ..Default::default()
            }),
            engine,
            cars: vec![],
        }
    }

    fn step(&mut self) {
        match self.engine {
            Engine::Kjoint(_) => self.joints.step(&mut self.world, DT).unwrap(),
            Engine::Rapier => self.world.step(),
        }
    }

    fn add_car(&mut self, pos: Vector, drive: Option<(f64, f64)>) {
        let world = &mut self.world;
        let (chassis, _) = world.insert(
            RigidBodyBuilder::dynamic()
                .translation(pos)
                .can_sleep(false),
            ColliderBuilder::cuboid(1.2, 0.15, 0.6).mass(M_CHASSIS),
        );
        let mut hubs = [RigidBodyHandle::invalid(); 4];
        let mut wheels = [RigidBodyHandle::invalid(); 4];
        let mut kaxles = vec![];
        let mut raxles = vec![];
        let corners = [
            (WHEEL_X, WHEEL_Z),
            (WHEEL_X, -WHEEL_Z),
            (-WHEEL_X, WHEEL_Z),
            (-WHEEL_X, -WHEEL_Z),
        ];
        for (i, (x, z)) in corners.into_iter().enumerate() {
            let c = pos + Vector::new(x, -SUSP_LEN, z);
            let hub = world.insert_body(
                RigidBodyBuilder::dynamic()
                    .translation(c)
                    .can_sleep(false)
                    .additional_mass_properties(MassProperties::new(
                        Vector::ZERO,
                        M_HUB,
                        Vector::splat(0.02),
                    )),
            );
            let (wheel, _) = world.insert(
                RigidBodyBuilder::dynamic().translation(c).can_sleep(false),
                ColliderBuilder::ball(R_WHEEL).mass(M_WHEEL).friction(1.0),
            );
            let driven = i >= 2;
            match self.engine {
                Engine::Kjoint(_) => {
                    let susp = KjointProperty::new(JointType::Translational).with_dof(
                        Dof::Dx,
                        DofLaw::spring(K_SUSP)
                            .with_viscosity(C_SUSP)
                            .with_stops(-STOP, STOP),
                    );
                    self.joints
                        .insert(
                            KjointBuilder::new(susp)
                                .world_axis(Vector::Y)
                                .local_anchor1(Vector::new(x, -SUSP_LEN, z)),
                            chassis,
                            hub,
                            &world.bodies,
                        )
                        .unwrap();
                    let mut axle = KjointBuilder::new(KjointProperty::new(JointType::Revolute))
                        .world_axis(Vector::Z)
                        .contacts_enabled(false);
                    if let (true, Some((w, f))) = (driven, drive) {
                        axle = axle.motor(Dof::Rx, KjointMotor::velocity(w, f).max_force(600.0));
                    }
                    kaxles.push(self.joints.insert(axle, hub, wheel, &world.bodies).unwrap());
                }
                Engine::Rapier => {
                    let susp = PrismaticJointBuilder::new(Vector::Y)
                        .local_anchor1(Vector::new(x, -SUSP_LEN, z))
                        .local_anchor2(Vector::ZERO)
                        .limits([-STOP as f32, STOP as f32])
                        .motor_model(MotorModel::ForceBased)
                        .motor_position(0.0, K_SUSP as f32, C_SUSP as f32);
                    world.insert_impulse_joint(chassis, hub, susp);
                    let mut axle = RevoluteJointBuilder::new(Vector::Z)
                        .local_anchor1(Vector::ZERO)
                        .local_anchor2(Vector::ZERO)
                        .contacts_enabled(false);
                    if let (true, Some((w, f))) = (driven, drive) {
                        axle = axle
                            .motor_model(MotorModel::ForceBased)
                            .motor_velocity(w as f32, f as f32)
                            .motor_max_force(600.0);
                    }
                    raxles.push(world.insert_impulse_joint(hub, wheel, axle));
                }
            }
            hubs[i] = hub;
            wheels[i] = wheel;
        }
        self.cars.push(Car {
            chassis,
            hubs,
            wheels,
            kaxles,
            raxles,
        });
    }

    /// Suspension compression of corner i, measured from the bodies (same for both engines).
    fn susp_q(&self, c: usize, i: usize) -> f32 {
        let car = &self.cars[c];
        let ch = &self.world.bodies[car.chassis];
        let corners = [
            (WHEEL_X, WHEEL_Z),
            (WHEEL_X, -WHEEL_Z),
            (-WHEEL_X, WHEEL_Z),
            (-WHEEL_X, -WHEEL_Z),
        ];
        let (x, z) = corners[i];
        let a1 = ch.position() * Vector::new(x, -SUSP_LEN, z);
        let up = ch.rotation() * Vector::Y;
        (self.world.bodies[car.hubs[i]].translation() - a1).dot(up)
    }
    fn axle_gap(&self, c: usize, i: usize) -> f32 {
        let car = &self.cars[c];
        (self.world.bodies[car.hubs[i]].translation()
            - self.world.bodies[car.wheels[i]].translation())
        .length()
    }
    fn chassis(&self, c: usize) -> &RigidBody {
        &self.world.bodies[self.cars[c].chassis]
    }
}

fn engines() -> [Engine; 3] {
    [Engine::Kjoint(4), Engine::Kjoint(8), Engine::Rapier]
}

fn rest() {
    println!("== rest 10 s; expected sag m*g/(4k) = {:.5} m, chassis y = 0.60095 - contact penetration ==", 800.0 * 9.81 / 4.0 / K_SUSP);
    for e in engines() {
        let mut s = Sim::new(e);
        s.add_car(Vector::new(0.0, R_WHEEL + SUSP_LEN, 0.0), None);
        let mut ymin = f32::MAX;
        let mut ymax = f32::MIN;
        for f in 0..600 {
            s.step();
            if f >= 300 {
                let y = s.chassis(0).translation().y;
                ymin = ymin.min(y);
                ymax = ymax.max(y);
            }
        }
        println!(
            "  {e:?}: chassis y = {:.5} (jitter {:.1e}), q = {:.5}, axle gap = {:.2e} m, wheel y = {:.5}, chassis x drift {:+.1e}",
            s.chassis(0).translation().y,
            ymax - ymin,
            s.susp_q(0, 0),
            s.axle_gap(0, 0),
            s.world.bodies[s.cars[0].wheels[0]].translation().y,
            s.chassis(0).translation().x
        );
    }
}

fn drop_test() {
    println!("== drop from 1 m ==");
    for e in engines() {
        let mut s = Sim::new(e);
        s.add_car(Vector::new(0.0, R_WHEEL + SUSP_LEN + 1.0, 0.0), None);
        let mut qmax = f32::MIN;
        let mut gmax: f32 = 0.0;
        let mut landed = false;
        let mut ymax_after: f32 = 0.0;
        for _ in 0..300 {
            s.step();
            for i in 0..4 {
                qmax = qmax.max(s.susp_q(0, i));
                gmax = gmax.max(s.axle_gap(0, i));
            }
            if qmax > 0.02 {
                landed = true;
            }
            if landed {
                ymax_after = ymax_after.max(s.chassis(0).translation().y);
            }
        }
        println!(
            "  {e:?}: max q = {qmax:.5} (stop {STOP}), max axle gap = {gmax:.2e} m, chassis max y after landing = {ymax_after:.4}, final y = {:.5}",
            s.chassis(0).translation().y
        );
    }
}

fn bump() {
    println!("== drive at 10 rad/s (3.5 m/s) over a 6 cm box bump at x = 12 ==");
    for e in engines() {
        let mut s = Sim::new(e);
        s.world.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(12.0, 0.0, 0.0)),
            ColliderBuilder::cuboid(0.2, 0.06, 5.0).friction(1.0),
        );
        s.add_car(
            Vector::new(0.0, R_WHEEL + SUSP_LEN, 0.0),
            Some((-10.0, 500.0)),
        );
        let mut qmax = f32::MIN;
        let mut qmin = f32::MAX;
        let mut gmax: f32 = 0.0;
        let mut pitch: f32 = 0.0;
        let mut vy: f32 = 0.0;
        for _ in 0..600 {
            s.step();
            for i in 0..4 {
                qmax = qmax.max(s.susp_q(0, i));
                qmin = qmin.min(s.susp_q(0, i));
                gmax = gmax.max(s.axle_gap(0, i));
            }
            let (ax, ang) = s.chassis(0).rotation().to_axis_angle();
            pitch = pitch.max((ax.z * ang).abs());
            vy = vy.max(s.chassis(0).linvel().y.abs());
        }
        let c = s.chassis(0);
        println!(
            "  {e:?}: q in [{qmin:.4}, {qmax:.4}], max axle gap {gmax:.2e} m, max pitch {pitch:.4} rad, max |vy| {vy:.3}, end x = {:.2} vx = {:.3}, z = {:.2e}",
            c.translation().x,
            c.linvel().x,
            c.translation().z
        );
    }
}

fn time() {
    println!("== frame cost: N cars driving (all awake), 1 thread, 300 frames after 60 warm-up ==");
    for n in [1usize, 16, 64] {
        for e in engines() {
            let mut s = Sim::new(e);
            let side = (n as f64).sqrt().ceil() as usize;
            for k in 0..n {
                let (ix, iz) = (k % side, k / side);
                s.add_car(
                    Vector::new(ix as f32 * 8.0, R_WHEEL + SUSP_LEN, iz as f32 * 5.0),
                    Some((-10.0, 500.0)),
                );
            }
            for _ in 0..60 {
                s.step();
            }
            let t0 = Instant::now();
            let frames = 300;
            for _ in 0..frames {
                s.step();
            }
            let dt = t0.elapsed().as_secs_f64() / frames as f64;
            println!(
                "  {n:3} cars ({:4} joints) {e:?}: {:.3} ms/frame ({:.1} us per car), car0 x = {:.2}",
                n * 8,
                dt * 1e3,
                dt * 1e6 / n as f64,
                s.chassis(0).translation().x
            );
        }
    }
}

fn main() {
    let arg = std::env::args().nth(1).unwrap_or_else(|| "all".into());
    let all = arg == "all";
    if all || arg == "rest" {
        rest();
    }
    if all || arg == "drop" {
        drop_test();
    }
    if all || arg == "bump" {
        bump();
    }
    if all || arg == "time" {
        time();
    }
    let _ = |c: &Car| (c.kaxles.len(), c.raxles.len());
}
