//! Benchmarks of issue 2: the cost of one joint evaluation with every mechanism on, and a
//! hanging chain of 1000 rods on KJOINT2 revolute joints against the same chain on rapier's
//! revolute impulse joints at the same substep count (frame time; the anchor drift of both
//! is printed before the timing). Figures and machine: README, "Benchmarks".
//!
//! `cargo bench --bench kjoint`

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rapier_kjoint::law::{self, BlockedStiffness, LawParams, LawState};
use rapier_kjoint::{Curve, Dof, DofLaw, JointType, KjointProperty};
use scenes::SUBSTEPS;

/// A free joint (every DOF free) whose six laws use every mechanism: curve spring, curve
/// viscosity, friction with a curve, stops (coupled on the rotations).
fn every_mechanism() -> KjointProperty {
    let curve = Curve::new(vec![(-1.0, -2.0), (0.0, 0.0), (1.0, 1.0)]).unwrap();
    // (a friction curve's values are caps, refused negative)
    let cap = Curve::new(vec![(-1.0, 2.0), (0.0, 1.0), (1.0, 1.5)]).unwrap();
    let mut p = KjointProperty::new(JointType::Free).with_kn(1e6);
    for d in Dof::ALL {
        let mut l = DofLaw::spring(1.0e3)
            .with_stops(-0.1, 0.1)
            .with_friction(1e4, 5.0);
        l.stiffness_curve = Some(curve.clone());
        l.viscosity = 1.0;
        l.viscosity_curve = Some(curve.clone());
        l.friction_curve = Some(cap.clone());
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
    // a slow sweep through the stops and the friction cycle: one period of
    // `0.15·sin(2π·k/1024)`, tabulated (a `sin` per call was 4 % of the time measured)
    const SWEEP: usize = 1024;
    let sweep: Vec<f64> = (0..SWEEP)
        .map(|k| 0.15 * (2.0 * std::f64::consts::PI * k as f64 / SWEEP as f64).sin())
        .collect();
    let mut k = 0;
    c.bench_function("law::evaluate, every mechanism on", |b| {
        b.iter(|| {
            k = (k + 1) % SWEEP;
            let s = sweep[k];
            let q = [s, -s, 0.5 * s, s, 0.3 * s, -0.2 * s];
            let rate = [1.0, -1.0, 0.5, 1.0, 0.3, -0.2];
            let out = law::evaluate(
                &prop,
                &params,
                black_box(&q),
                black_box(&rate),
                false,
                &mut state,
            );
            // the output seen through a reference: returned by value, criterion's
            // `black_box` copied its 888 bytes (0.07–0.09 µs), which no caller of the law pays
            black_box(&out);
        })
    });
}

#[path = "scenes.rs"]
mod scenes;

const LINKS: usize = 1000;
fn chain_1000(c: &mut Criterion) {
    let scene = scenes::chain(LINKS);
    // anchor drift over 10 s, printed once (not when `cargo test` runs the bench as a test)
    if std::env::args().any(|a| a == "--bench") {
        let mut k = scene.kjoint();
        let mut worst: rapier_kjoint::rapier::math::Real = 0.0;
        for _ in 0..600 {
            k.frame();
            worst = worst.max(scene.anchor_gap(&k.world, &k.bodies));
        }
        println!("KJOINT2 chain ({LINKS} links, Kn = 1e12, {SUBSTEPS} substeps): max anchor drift over 10 s = {worst:.3e} m");
        let mut r = scene.rapier();
        let mut worst: rapier_kjoint::rapier::math::Real = 0.0;
        for _ in 0..600 {
            r.frame();
            worst = worst.max(scene.anchor_gap(&r.world, &r.bodies));
        }
        println!("rapier revolute impulse-joint chain ({LINKS} links, {SUBSTEPS} substeps): max anchor drift over 10 s = {worst:.3e} m");
    }
    let mut g = c.benchmark_group("chain of 1000, one 60 Hz frame");
    g.sample_size(20);
    let mut k = scene.kjoint();
    g.bench_function("KJOINT2 revolute (Kn = 1e12)", |b| b.iter(|| k.frame()));
    let mut r = scene.rapier();
    g.bench_function("rapier revolute impulse joints", |b| b.iter(|| r.frame()));
    g.finish();
}

criterion_group!(benches, joint_evaluation, chain_1000);
criterion_main!(benches);
