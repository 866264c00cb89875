//! Benchmarks of issue 2: the cost of one joint evaluation with every mechanism on, and a
//! hanging chain of 1000 rods on KJOINT2 revolute joints against the same chain on rapier's
//! revolute impulse joints at the same substep count (frame time; the anchor drift of both
//! is printed before the timing). Figures and machine: README, "Benchmarks".
//!
//! `cargo bench --bench kjoint`

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rapier3d::prelude::*;
use rapier_kjoint::law::{self, BlockedStiffness, LawParams, LawState};
use rapier_kjoint::{
    Curve, Dof, DofLaw, JointType, Kjoint2Builder, Kjoint2Property, KjointSet, SubstepSettings,
};

/// A free joint (every DOF free) whose six laws use every mechanism: curve spring, curve
/// viscosity, friction with a curve, stops (coupled on the rotations).
fn every_mechanism() -> Kjoint2Property {
    let curve = Curve::new(vec![(-1.0, -2.0), (0.0, 0.0), (1.0, 1.0)]).unwrap();
    let mut p = Kjoint2Property::new(JointType::Free).with_kn(1e6);
    for d in Dof::ALL {
        let mut l = DofLaw::spring(1.0e3)
            .with_stops(-0.1, 0.1)
            .with_friction(1e4, 5.0);
        l.stiffness_curve = Some(curve.clone());
        l.viscosity = 1.0;
        l.viscosity_curve = Some(curve.clone());
        l.friction_curve = Some(curve.clone());
        if d.is_rotation() {
            l = l.with_coupled_stops();
        }
        p = p.with_dof(d, l);
    }
    p.with_sensor(1)
}

fn joint_evaluation(c: &mut Criterion) {
    let prop = every_mechanism();
    let params = LawParams {
        blocked: BlockedStiffness {
            translational: 1e6,
            rotational: 1e4,
        },
        reduced_mass: 1.0,
        reduced_inertia: 0.1,
    };
    let mut state = LawState::default();
    let mut t = 0.0f64;
    c.bench_function("law::evaluate, every mechanism on", |b| {
        b.iter(|| {
            // a slow sweep through the stops and the friction cycle
            t += 1e-3;
            let s = (t * 7.0).sin() * 0.15;
            let q = [s, -s, 0.5 * s, s, 0.3 * s, -0.2 * s];
            let rate = [1.0, -1.0, 0.5, 1.0, 0.3, -0.2];
            black_box(law::evaluate(
                &prop,
                &params,
                black_box(&q),
                black_box(&rate),
                false,
                &mut state,
            ))
        })
    });
}

const LINKS: usize = 1000;
const LINK: f32 = 0.1;
const MASS: f32 = 0.1;
const SUBSTEPS: usize = 4;
const FRAME: f64 = 1.0 / 60.0;

/// A chain of `LINKS` slender rods hanging from the world, released straight at 30° from the
/// vertical. Returns the world and the bodies.
fn chain_bodies() -> (PhysicsWorld, RigidBodyHandle, Vec<RigidBodyHandle>) {
    let mut w = PhysicsWorld::default();
    w.gravity = Vector::new(0.0, -9.81, 0.0);
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    let dir = Vector::new(0.5, -(3.0f32.sqrt()) / 2.0, 0.0);
    let rod = Rotation::from_rotation_arc(Vector::X, dir);
    let i = MASS * LINK * LINK / 12.0;
    let bodies = (0..LINKS)
        .map(|k| {
            w.insert_body(
                RigidBodyBuilder::dynamic()
                    .translation(dir * (LINK * (k as f32 + 0.5)))
                    .rotation(rod.to_scaled_axis())
                    .can_sleep(false)
                    .additional_mass_properties(MassProperties::new(
                        Vector::ZERO,
                        MASS,
                        Vector::new(0.1 * i, i, i),
                    )),
            )
        })
        .collect();
    (w, ground, bodies)
}

fn anchors(k: usize) -> (Vector, Vector) {
    let a1 = if k == 0 {
        Vector::ZERO
    } else {
        Vector::new(LINK / 2.0, 0.0, 0.0)
    };
    (a1, Vector::new(-LINK / 2.0, 0.0, 0.0))
}

fn kjoint_chain() -> (PhysicsWorld, KjointSet, Vec<RigidBodyHandle>) {
    let (mut w, ground, bodies) = chain_bodies();
    let mut set = KjointSet::with_settings(SubstepSettings {
        substeps: SUBSTEPS,
        ..Default::default()
    });
    let prop = Kjoint2Property::new(JointType::Revolute).with_kn(1e12);
    let axis_z = Rotation::from_rotation_arc(Vector::X, Vector::Z);
    let mut prev = ground;
    for (k, &b) in bodies.iter().enumerate() {
        let (a1, a2) = anchors(k);
        let j = Kjoint2Builder::new(prop.clone())
            .frame(axis_z)
            .local_anchor1(a1)
            .local_anchor2(a2);
        set.insert(j, prev, b, &w.bodies).unwrap();
        prev = b;
    }
    set.prepare(&mut w);
    (w, set, bodies)
}

fn rapier_chain() -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let (mut w, ground, bodies) = chain_bodies();
    w.integration_parameters.dt = FRAME as f32;
    w.integration_parameters.num_solver_iterations = SUBSTEPS;
    let mut prev = ground;
    for (k, &b) in bodies.iter().enumerate() {
        let (a1, a2) = anchors(k);
        // the hinge axis is world z: the rods' local z
        let j = RevoluteJointBuilder::new(Vector::Z)
            .local_anchor1(a1)
            .local_anchor2(a2);
        w.insert_impulse_joint(prev, b, j);
        prev = b;
    }
    (w, bodies)
}

/// Largest distance between the two anchors of any joint of the chain [m].
fn drift(w: &PhysicsWorld, bodies: &[RigidBodyHandle]) -> f32 {
    let mut prev_tip = Vector::ZERO; // the world anchor of the first joint
    let mut worst = 0.0f32;
    for (k, &b) in bodies.iter().enumerate() {
        let (_, a2) = anchors(k);
        let body = &w.bodies[b];
        let top = body.position() * a2;
        worst = worst.max((top - prev_tip).length());
        prev_tip = body.position() * Vector::new(LINK / 2.0, 0.0, 0.0);
    }
    worst
}

fn chain_1000(c: &mut Criterion) {
    // anchor drift over 10 s, printed once (not when `cargo test` runs the bench as a test)
    if std::env::args().any(|a| a == "--bench") {
        let (mut w, mut set, bodies) = kjoint_chain();
        let mut worst = 0.0f32;
        for _ in 0..600 {
            set.step(&mut w, FRAME).unwrap();
            worst = worst.max(drift(&w, &bodies));
        }
        println!("KJOINT2 chain ({LINKS} links, Kn = 1e12, {SUBSTEPS} substeps): max anchor drift over 10 s = {worst:.3e} m");
        let (mut w, bodies) = rapier_chain();
        let mut worst = 0.0f32;
        for _ in 0..600 {
            w.step();
            worst = worst.max(drift(&w, &bodies));
        }
        println!("rapier revolute impulse-joint chain ({LINKS} links, {SUBSTEPS} substeps): max anchor drift over 10 s = {worst:.3e} m");
    }
    let mut g = c.benchmark_group("chain of 1000, one 60 Hz frame");
    g.sample_size(20);
    let (mut w, mut set, _) = kjoint_chain();
    g.bench_function("KJOINT2 revolute (Kn = 1e12)", |b| {
        b.iter(|| set.step(&mut w, FRAME).unwrap())
    });
    let (mut w, _) = rapier_chain();
    g.bench_function("rapier revolute impulse joints", |b| b.iter(|| w.step()));
    g.finish();
}

criterion_group!(benches, joint_evaluation, chain_1000);
criterion_main!(benches);
