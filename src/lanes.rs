//! Four `f64` in the lanes of one vector ([`F4`]): what the solver's four-island tree solve
//! (`dynamics::solve::tree_x4`) and the four-joint rotation measure
//! (`kinematics::twist_x4`) compute with. Each lane's operation is the scalar IEEE
//! operation, so a lane gives the bits the scalar code gives when it runs the same
//! operations in the same order.

use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// Four `f64`, one per lane, with element-wise arithmetic (IEEE, each lane exactly the
/// scalar operation): the compiler makes the four one AVX2 instruction inside
/// `substep_avx2`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(C, align(32))]
pub(crate) struct F4(pub [f64; 4]);

impl F4 {
    pub(crate) const ZERO: F4 = F4([0.0; 4]);

    #[inline(always)]
    pub(crate) fn splat(v: f64) -> F4 {
        F4([v; 4])
    }

    #[inline(always)]
    pub(crate) fn sqrt(self) -> F4 {
        F4([
            self.0[0].sqrt(),
            self.0[1].sqrt(),
            self.0[2].sqrt(),
            self.0[3].sqrt(),
        ])
    }

    /// The four lanes of `f(lane)`.
    #[inline(always)]
    pub(crate) fn gather(f: impl Fn(usize) -> f64) -> F4 {
        F4([f(0), f(1), f(2), f(3)])
    }
}

macro_rules! lane_op {
    ($tr:ident, $f:ident, $tra:ident, $fa:ident, $op:tt) => {
        impl $tr for F4 {
            type Output = F4;
            #[inline(always)]
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
            #[inline(always)]
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
    #[inline(always)]
    fn neg(self) -> F4 {
        F4([-self.0[0], -self.0[1], -self.0[2], -self.0[3]])
    }
}
