//! Peak resident memory of a hanging chain (the chain of `benches/scenes.rs`: rods of
//! 0.1 m and 0.1 kg, released at 30°) on KJOINT2 joints (Kn = 1e12, 4 substeps) or on rapier
//! revolute impulse joints (1/60 s, 4 solver iterations), built and stepped a few frames in
//! this process; prints `VmHWM` from `/proc/self/status` (Linux). Run each side in its own
//! process, since the peak never goes down:
//!
//! ```sh
//! cargo run --release --example peak_memory -- kjoint2            # 10 000 links, 3 frames
//! cargo run --release --example peak_memory -- rapier
//! cargo run --release --example peak_memory -- baseline           # the process alone
//! cargo run --release --example peak_memory -- kjoint2 1000 10    # 1000 links, 10 frames
//! ```
//!
//! `cargo bench --bench solver -- peak_memory` runs the three and prints the ratio.

#[path = "../benches/scenes.rs"]
mod scenes;

use scenes::MemorySide;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: peak_memory <kjoint2|rapier|baseline> [links = 10000] [frames = 3]";
    let side = match args.first().and_then(|s| MemorySide::parse(s)) {
        Some(s) => s,
        None => {
            eprintln!("{usage}");
            std::process::exit(2);
        }
    };
    let number = |i: usize, default: usize| match args.get(i) {
        None => default,
        Some(v) => v.parse().unwrap_or_else(|_| {
            eprintln!("`{v}` is not a count\n{usage}");
            std::process::exit(2);
        }),
    };
    let links = number(1, 10_000);
    let frames = number(2, 3);
    let t = std::time::Instant::now();
    match scenes::peak_memory_run(side, links, frames) {
        Some(kib) => println!(
            "{side:?}, chain of {links}, {frames} frame(s): peak resident memory (VmHWM) \
             {kib} KiB = {:.1} MiB ({:.1} s)",
            kib as f64 / 1024.0,
            t.elapsed().as_secs_f64()
        ),
        None => {
            eprintln!("no VmHWM in /proc/self/status (Linux only)");
            std::process::exit(1);
        }
    }
}
