//! The tests' pseudo-random numbers: reproducible, without a dependency.

/// Uniform numbers in [0, 1) from Marsaglia's xorshift (13, 7, 17) on a 64-bit state
/// `seed` (not 0), the top 53 bits of each state.
pub(crate) fn xorshift(seed: u64) -> impl FnMut() -> f64 {
    let mut seed = seed;
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}
