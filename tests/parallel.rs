//! With the cargo feature `parallel`, islands are solved on rayon's threads: the results must
//! be bit-identical whatever the number of threads (`cargo test --features parallel`).
#![cfg(feature = "parallel")]

#[path = "../benches/scenes.rs"]
mod scenes;

use rapier_kjoint::rapier::math::Real;

/// Positions and velocities of every body after `frames` frames, bit for bit (in f64, which
/// holds an f32 exactly, so that the test reads the same in both precisions).
fn run(scene: &scenes::Scene, threads: usize, frames: usize) -> Vec<[u64; 13]> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut w = scene.kjoint();
        for _ in 0..frames {
            w.frame();
        }
        w.bodies
            .iter()
            .map(|h| {
                let b = &w.world.bodies[*h];
                let (t, r, v, a) = (b.translation(), b.rotation(), b.linvel(), b.angvel());
                [
                    t.x, t.y, t.z, r.x, r.y, r.z, r.w, v.x, v.y, v.z, a.x, a.y, a.z,
                ]
                .map(|x: Real| f64::from(x).to_bits())
            })
            .collect()
    })
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    for scene in [
        // 2500 pendulums: 5000 tree nodes, two batches of tree islands solved apart
        scenes::pendulums(2500),
        scenes::tree(5, scenes::TreeOrder::RootFirst),
        scenes::four_bar(false),
        scenes::capsules_on_ground(8),
    ] {
        let one = run(&scene, 1, 20);
        let three = run(&scene, 3, 20);
        assert_eq!(one, three, "{}", scene.name);
        // and the bodies moved (the comparison is not between two worlds at rest)
        let start = run(&scene, 1, 0);
        assert_ne!(one, start, "{}", scene.name);
    }
}
