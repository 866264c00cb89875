//! Steps the chain of the solver bench (`benches/scenes.rs`) for a number of frames and
//! prints the mean frame time: a harness for profilers (`perf record`, callgrind).
//!
//! `cargo run --release --example chain_frames -- [links=1000] [frames=300] [kjoint2|rapier]
//! [chain|pendulums|contacts]` (contacts: `links` is the number of groups, and 60 frames are
//! run first so that the capsules land)

#[path = "../benches/scenes.rs"]
#[allow(dead_code)]
mod scenes;

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1000);
    let frames: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(300);
    let rapier = args.next().is_some_and(|s| s == "rapier");
    let (scene, settle) = match args.next().as_deref() {
        Some("pendulums") => (scenes::pendulums(n), 0),
        Some("contacts") => (scenes::capsules_on_ground(n), 60),
        _ => (scenes::chain(n), 0),
    };
    let t;
    if rapier {
        let mut w = scene.rapier();
        for _ in 0..settle {
            w.frame();
        }
        t = std::time::Instant::now();
        for _ in 0..frames {
            w.frame();
        }
    } else {
        let mut w = scene.kjoint();
        for _ in 0..settle {
            w.frame();
        }
        t = std::time::Instant::now();
        for _ in 0..frames {
            w.frame();
        }
    }
    let per = t.elapsed().as_secs_f64() * 1e3 / frames.max(1) as f64;
    eprintln!("{per:.3} ms/frame");
}
