//! Steps the chain of the solver bench (`benches/scenes.rs`) for a number of frames and
//! prints the mean frame time: a harness for profilers (`perf record`, callgrind).
//!
//! `cargo run --release --example chain_frames -- [links=1000] [frames=300]
//! [kjoint2|rapier|unjointed] [chain|chains|pendulums|contacts|tree|trees|four_bar|ring]
//! [rounds=1]` (`tree`: `links` is the depth of the leaves-first binary tree, 9 = 511
//! joints; `trees`: 8 such trees of that depth, [`scenes::trees`]; `four_bar`: the free
//! four-bar loop, `links` ignored; `ring`: a closed ring of `links` rods pinned to the
//! world, [`scenes::ring`]; `rapier`: rapier's
//! own joints; `unjointed`: the same bodies without joints, stepped with the joint set's
//! substeps, the contact scene's reference; chains: `links / 1000` chains of 1000
//! links, [`scenes::chains`]; contacts: `links` is the number of groups, and 60 frames are
//! run first so that the capsules land; the chain, the chains and the pendulums run
//! [`scenes::SETTLE_FRAMES`] first, as the bench's interleaved exponents do). Each round
//! builds the scene again, settles it untimed and times `frames` frames; the mean over the
//! rounds is printed.
//!
//! With `PERF_CTL` set to the path of a FIFO, the timed frames alone are profiled: the
//! harness writes `enable` before them and `disable` after them, as `perf record
//! --delay=-1 --control=fifo:<path>` reads them. The bench's contact window (frames 60–120
//! of a fresh scene) is then, for example:
//!
//! ```sh
//! mkfifo /tmp/ctl
//! PERF_CTL=/tmp/ctl perf record --delay=-1 --control=fifo:/tmp/ctl \
//!     target/release/examples/chain_frames 50 60 kjoint2 contacts 150
//! ```
//!
//! (profiles over long runs are of another scene: 600 frames after landing, a quarter of
//! the hinges' groups of four have a hinge whose swing is beyond the four-lane measure's
//! series, and the four take the scalar path, which none does in the bench's window).

#[path = "../benches/scenes.rs"]
mod scenes;

use std::io::Write;

/// The `perf` control FIFO named by `PERF_CTL`, if any.
struct PerfControl(Option<std::fs::File>);

impl PerfControl {
    fn from_env() -> Self {
        let fifo = std::env::var_os("PERF_CTL").map(|path| {
            std::fs::OpenOptions::new()
                .write(true)
                .open(&path)
                .unwrap_or_else(|e| panic!("PERF_CTL {}: {e}", path.to_string_lossy()))
        });
        PerfControl(fifo)
    }

    fn send(&mut self, command: &str) {
        if let Some(f) = self.0.as_mut() {
            f.write_all(command.as_bytes())
                .and_then(|()| f.flush())
                .unwrap_or_else(|e| panic!("PERF_CTL: {e}"));
        }
    }
}

/// Steps `settle` frames untimed, then `frames` frames timed (and alone profiled, `perf`).
fn time_frames(
    mut frame: impl FnMut(),
    settle: usize,
    frames: usize,
    perf: &mut PerfControl,
) -> std::time::Duration {
    for _ in 0..settle {
        frame();
    }
    perf.send("enable\n");
    let t = std::time::Instant::now();
    for _ in 0..frames {
        frame();
    }
    let elapsed = t.elapsed();
    perf.send("disable\n");
    elapsed
}

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1000);
    let frames: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(300);
    let side = args.next().unwrap_or_default();
    let scene_name = args.next();
    let rounds: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1).max(1);
    let mut perf = PerfControl::from_env();
    let mut timed = std::time::Duration::ZERO;
    for _ in 0..rounds {
        let (scene, settle) = match scene_name.as_deref() {
            Some("pendulums") => (scenes::pendulums(n), scenes::SETTLE_FRAMES),
            Some("contacts") => (scenes::capsules_on_ground(n), 60),
            Some("chains") => (scenes::chains(n / 1000, 1000), scenes::SETTLE_FRAMES),
            Some("four_bar") => (scenes::four_bar(false), scenes::SETTLE_FRAMES),
            Some("ring") => (scenes::ring(n), scenes::SETTLE_FRAMES),
            Some("trees") => (scenes::trees(8, n as u32), scenes::SETTLE_FRAMES),
            Some("tree") => (
                scenes::tree(n as u32, scenes::TreeOrder::LeavesFirst),
                scenes::SETTLE_FRAMES,
            ),
            _ => (scenes::chain(n), scenes::SETTLE_FRAMES),
        };
        timed += if side == "rapier" {
            let mut w = scene.rapier();
            time_frames(|| w.frame(), settle, frames, &mut perf)
        } else if side == "unjointed" {
            let mut w = scene.rapier_unjointed();
            time_frames(|| w.frame(), settle, frames, &mut perf)
        } else {
            let mut w = scene.kjoint();
            time_frames(|| w.frame(), settle, frames, &mut perf)
        };
    }
    let per = timed.as_secs_f64() * 1e3 / (frames * rounds).max(1) as f64;
    eprintln!("{per:.3} ms/frame");
}
