//! A controlled memory load for the bench's cost exponents: one thread copying between two
//! buffers of `mib` MiB each (default 128, far beyond any last-level cache), for `seconds`
//! seconds (default: until killed). What a busy neighbour on the host does to the cache and
//! the memory bus, made repeatable:
//!
//! ```sh
//! taskset -c 1 target/release/examples/memory_load 128 &
//! taskset -c 0 target/release/examples/chain_frames 10000 10 kjoint2 chain 1
//! taskset -c 0 target/release/examples/chain_frames 10000 10 rapier chain 1
//! kill %1
//! ```
//!
//! On the 2-core VM of the README's tables, the load slowed the 10 000-link chain's frame by
//! about 42 % and rapier's own by about 27 % in some placements of the two virtual cores by
//! the host, and changed nothing measurable in others: compare runs of the same minute only
//! (docs/performance_log.md, session 47).

use std::time::{Duration, Instant};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, name: &str| -> Option<u64> {
        args.get(i).map(|a| {
            a.parse().unwrap_or_else(|_| {
                eprintln!("memory_load: {name} must be a whole number, got `{a}`");
                std::process::exit(2)
            })
        })
    };
    let mib = arg(0, "mib").unwrap_or(128).max(1);
    // (two buffers of this size must fit the memory: 1 TiB each at most)
    if mib > 1 << 20 {
        eprintln!("memory_load: mib must be at most {}, got {mib}", 1u64 << 20);
        std::process::exit(2)
    }
    let until = arg(1, "seconds").map(|s| Instant::now() + Duration::from_secs(s));
    let n = (mib << 20) as usize;
    let mut a = vec![1u8; n];
    let mut b = vec![2u8; n];
    let mut rounds = 0u64;
    while until.is_none_or(|t| Instant::now() < t) {
        b.copy_from_slice(&a);
        a.copy_from_slice(&b);
        rounds += 1;
        std::hint::black_box((&a, &b));
    }
    println!(
        "{} MiB copied",
        rounds * 2 * mib // each round copies both buffers once
    );
}
