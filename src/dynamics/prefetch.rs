//! Cache hints for the stages' loops over large per-joint and per-body records.
//!
//! The prepare stage reads each joint's record (`Kjoint`, 1.5 KB: its first 648 bytes of
//! frames, law state and the rest every substep reads, the readout only where the substep
//! writes it; the property behind a pointer, one copy for the joints that have the same)
//! once per substep, in order. The
//! lines it reads are spread over the record, so the hardware's stream prefetcher does not
//! follow them, and at 10 000 joints (16 MB of
//! records, out of the last-level cache with the bodies and solver data) every record's
//! first read waited for memory: 8 % of the 10 000-link chain's frame was that one load
//! (measured with `perf`). Asking for the record two joints ahead hides the wait behind two
//! joints' work (~1.5 µs). The same holds for rapier's bodies in the gather and apply
//! stages, asked for at the address the gather stage last read each one from (looking a
//! body up by its handle reads the record itself, so that hint waited for the line it
//! asked for: 3.7 % of the 10 000 pendulums' frame was that lookup). The light loops over
//! the substep's own arrays (the store and apply stages, the measure stage's rotations, the
//! write of the results into the records after a step) ask for the fields they read or
//! write a few joints ahead too: each reads several arrays at once, little work a joint,
//! and at 10 000 joints they cost 20–50 times what they cost at 1000 without the hints.
//! Hints are no help where a loop is bound by the memory's throughput rather than its
//! latency: the prepare loop, asking for its substep arrays ahead as well, was 3–7 % slower.
//!
//! A prefetch is a hint: it never faults, whatever the address, and changes no result.
//! Where a loop's records fit the core's second-level cache (a scene of 50 capsule groups:
//! 100 joint records, 150 bodies), the hints only cost instructions (41 a joint record,
//! plus a handle lookup a body), so the stages ask [`worth`] once per loop.

/// Cache line size \[bytes\] of the x86-64 and aarch64 processors this is tuned on.
const LINE: usize = 64;

/// Records a loop reads beyond which it prefetches \[bytes\]: 512 KiB, the second-level
/// cache of the smaller cores this runs on (the records of 200 joints or 700 bodies).
const WORTH_FROM: usize = 512 * 1024;

/// Whether a loop over `count` records of type `T` prefetches them ([`WORTH_FROM`]).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn worth<T>(count: usize) -> bool {
    count.saturating_mul(std::mem::size_of::<T>()) > WORTH_FROM
}

/// Asks the cache for the `len` bytes from `p` (nothing on other architectures).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn bytes(p: *const u8, len: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let mut off = 0;
        while off < len {
            // SAFETY: `_mm_prefetch` is a hint that reads nothing into the program and does
            // not fault on any address; SSE is part of the x86-64 baseline.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(off) as *const i8) };
            off += LINE;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (p, len);
}

/// Asks the cache for every line of `*p`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn value<T>(p: *const T) {
    bytes(p as *const u8, std::mem::size_of::<T>());
}

/// Asks the cache for the field at byte `offset` (from `std::mem::offset_of!`) of `*p`,
/// `len` bytes long.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn field<T>(p: *const T, offset: usize, len: usize) {
    bytes((p as *const u8).wrapping_add(offset), len);
}

/// Asks the cache for the field `f` (a path: `pose.rotation`) of the `T` at `p`, a
/// `*const T` that may point past its slice's end (a hint reads nothing):
/// `prefetch::field_of!(p, T, f)`. By name, not by a range of offsets: a struct's fields
/// are laid out in an order the compiler chooses.
macro_rules! field_of {
    ($p:expr, $t:ty, $($f:tt).+) => {
        $crate::dynamics::prefetch::field(
            $p,
            ::std::mem::offset_of!($t, $($f).+),
            $crate::dynamics::prefetch::size_of_field(|t: &$t| &t.$($f).+),
        )
    };
}
pub(crate) use field_of;

/// The size of the field that `at` selects (never called: it names the field's type).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn size_of_field<T, F>(_at: impl Fn(&T) -> &F) -> usize {
    std::mem::size_of::<F>()
}
