//! Frame time of the URDF arm demo (`assets/urdf/arm.urdf`, 60 Hz frames × 4 substeps) with
//! rerun logging off, to memory, and to an `.rrd` file in a temporary directory.
//!
//! `cargo bench --features rerun --bench logging`

use criterion::{criterion_group, criterion_main, Criterion};
use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot, UrdfRobotHandles};
use rapier_kjoint::output::rerun_log::RerunLogger;
use rapier_kjoint::output::Observer;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::KjointSet;

const FRAME: f64 = 1.0 / 60.0;

fn arm() -> (PhysicsWorld, KjointSet, UrdfRobotHandles) {
    let mut world = PhysicsWorld::default();
    world.gravity = Vector::new(0.0, 0.0, -9.81);
    let mut joints = KjointSet::new();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/urdf/arm.urdf");
    let robot = UrdfRobot::from_file(path, &UrdfOptions::default())
        .and_then(|r| r.insert(&mut world, &mut joints))
        .unwrap();
    (world, joints, robot)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("arm_frame");
    {
        let (mut world, mut joints, _) = arm();
        g.bench_function("logging_off", |b| {
            b.iter(|| joints.step(&mut world, FRAME).unwrap())
        });
    }
    {
        let (mut world, mut joints, robot) = arm();
        let (logger, _storage) = RerunLogger::memory().unwrap();
        let mut logger = logger.with_urdf_robot(&robot);
        g.bench_function("logging_memory", |b| {
            b.iter(|| {
                joints.step(&mut world, FRAME).unwrap();
                let ev = joints.drain_events();
                logger.record(joints.time(), &world, &joints, &ev).unwrap();
            })
        });
        logger.finish().unwrap();
    }
    {
        let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("kjoint-bench");
        std::fs::create_dir_all(&dir).unwrap();
        let (mut world, mut joints, robot) = arm();
        let mut logger = RerunLogger::save(dir.join("arm.rrd"))
            .unwrap()
            .with_urdf_robot(&robot);
        g.bench_function("logging_file", |b| {
            b.iter(|| {
                joints.step(&mut world, FRAME).unwrap();
                let ev = joints.drain_events();
                logger.record(joints.time(), &world, &joints, &ev).unwrap();
            })
        });
        logger.finish().unwrap();
        let size = std::fs::metadata(dir.join("arm.rrd"))
            .map(|m| m.len())
            .unwrap_or(0);
        println!("recording: {size} bytes");
        let _ = std::fs::remove_dir_all(&dir);
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(5));
    targets = bench
}
criterion_main!(benches);
