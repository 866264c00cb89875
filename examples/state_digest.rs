//! Prints a digest of the bench scenes' states (`benches/scenes.rs`): every body's pose and
//! velocity and every joint's readout and energies, every 10 frames over 90, hashed, one
//! line a scene. A change meant to give the same bits (a reordered loop, a stage compiled
//! differently, a copy no longer kept) gives the same lines before and after:
//!
//! ```sh
//! cargo run --release --example state_digest > before.txt   # at the old commit
//! cargo run --release --example state_digest | diff before.txt -
//! ```
//!
//! Compare builds of the same profile: the four-bar's loop solve gives other bits in a
//! `dev` build than in a release one (the other scenes agree).
#[path = "../benches/scenes.rs"]
mod scenes;
use std::hash::{Hash, Hasher};
fn main() {
    let list = vec![
        ("chain", scenes::chain(300)),
        ("pendulums", scenes::pendulums(300)),
        ("tree", scenes::tree(7, scenes::TreeOrder::RootFirst)),
        ("hub", scenes::hub(40)),
        ("contacts", scenes::capsules_on_ground(12)),
        ("four_bar", scenes::four_bar(true)),
        ("chains", scenes::chains(3, 1000)),
    ];
    for (name, scene) in list {
        let mut w = scene.kjoint();
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for f in 0..90 {
            w.frame();
            if f % 10 == 9 {
                for b in &w.bodies {
                    let b = &w.world.bodies[*b];
                    format!("{:?}{:?}{:?}", b.position(), b.linvel(), b.angvel()).hash(&mut h);
                }
                for j in &w.handles {
                    if let Some(j) = w.joints.get(*j) {
                        format!("{:?}{:?}", j.state(), j.energy()).hash(&mut h);
                    }
                }
            }
        }
        println!("{name} {:016x}", h.finish());
    }
}
