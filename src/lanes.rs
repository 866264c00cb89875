//! Four `f64` in the lanes of one vector ([`F4`]): what the solver's four-island tree solve
//! (`dynamics::solve::tree_x4`) and the four-joint rotation measure
//! (`kinematics::twist_x4`) compute with. Each lane's operation is the scalar IEEE
//! operation, so a lane gives the bits the scalar code gives when it runs the same
//! operations in the same order. With them, the small arrays `arr3`, `arr4`, `arr6` that
//! the lane and scalar kernels build without a closure compiled out of line.

use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// `[f(0), f(1), f(2)]`, the array `std::array::from_fn(f)` builds, written out: `from_fn`
/// and `<[T; N]>::map` go through a closure adaptor of `core` that is compiled out of line
/// in the AVX2 copy of the substep (`dynamics::isa`), a call for every entry.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn arr3<T>(mut f: impl FnMut(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// [`arr3`] of four entries.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn arr4<T>(mut f: impl FnMut(usize) -> T) -> [T; 4] {
    [f(0), f(1), f(2), f(3)]
}

/// [`arr3`] of six entries.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn arr6<T>(mut f: impl FnMut(usize) -> T) -> [T; 6] {
    [f(0), f(1), f(2), f(3), f(4), f(5)]
}

/// Four `f64`, one per lane, with element-wise arithmetic (IEEE, each lane exactly the
/// scalar operation): the compiler makes the four one AVX2 instruction inside the
/// substep's AVX2 stages (`dynamics::isa`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
#[repr(C, align(32))]
pub(crate) struct F4(pub [f64; 4]);

impl F4 {
    pub(crate) const ZERO: F4 = F4([0.0; 4]);

    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn splat(v: f64) -> F4 {
        F4([v; 4])
    }

    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn sqrt(self) -> F4 {
        F4([
            self.0[0].sqrt(),
            self.0[1].sqrt(),
            self.0[2].sqrt(),
            self.0[3].sqrt(),
        ])
    }

    /// The four lanes of `f(lane)`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn gather(f: impl FnMut(usize) -> f64) -> F4 {
        F4(arr4(f))
    }
}

macro_rules! lane_op {
    ($tr:ident, $f:ident, $tra:ident, $fa:ident, $op:tt) => {
        impl $tr for F4 {
            type Output = F4;
            #[cfg_attr(not(debug_assertions), inline(always))]
            fn $f(self, o: F4) -> F4 {
                F4([
                    self.0[0] $op o.0[0],
                    self.0[1] $op o.0[1],
                    self.0[2] $op o.0[2],
                    self.0[3] $op o.0[3],
                ])
            }
        }
        impl $tra for F4 {
            #[cfg_attr(not(debug_assertions), inline(always))]
            fn $fa(&mut self, o: F4) {
                *self = *self $op o;
            }
        }
    };
}
lane_op!(Add, add, AddAssign, add_assign, +);
lane_op!(Sub, sub, SubAssign, sub_assign, -);
lane_op!(Mul, mul, MulAssign, mul_assign, *);
lane_op!(Div, div, DivAssign, div_assign, /);

impl Neg for F4 {
    type Output = F4;
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn neg(self) -> F4 {
        F4([-self.0[0], -self.0[1], -self.0[2], -self.0[3]])
    }
}
