//! Steps the chain of the solver bench (`benches/scenes.rs`) for a number of frames and
//! prints the mean frame time: a harness for profilers (`perf record`, callgrind).
//!
//! `cargo run --release --example chain_frames -- [links=1000] [frames=300]`

#[path = "../benches/scenes.rs"]
mod scenes;
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000);
    let frames: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let mut s = scenes::chain(n).kjoint();
    let t = std::time::Instant::now();
    for _ in 0..frames {
        s.frame();
    }
    eprintln!(
        "{:.3} ms/frame",
        t.elapsed().as_secs_f64() * 1e3 / frames as f64
    );
}
