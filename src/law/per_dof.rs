//! Per-DOF data of a joint, indexed by [`Dof`] (as rapier and Jolt index per-axis data by an
//! axis enum) and still usable as the `[T; 6]` array it wraps (`q[Dof::Rx]`, `q[3]`,
//! `q.iter()`, `for v in q`), in the order dx, dy, dz, rx, ry, rz.

use super::property::Dof;
use serde::Serialize;
use std::ops::{Deref, DerefMut, Index, IndexMut};
use std::slice::SliceIndex;

/// Six values, one per [`Dof`] of the joint's working frame, in the order of [`Dof::ALL`].
///
/// ```
/// use rapier_kjoint::law::{Dof, PerDof};
/// let mut q = PerDof([0.0; 6]);
/// q[Dof::Rx] = 0.25;
/// assert_eq!(q[3], 0.25);
/// assert_eq!(q.iter().sum::<f64>(), 0.25);
/// assert_eq!(q.with_dof().find(|(_, v)| **v != 0.0).map(|(d, _)| d), Some(Dof::Rx));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[serde(transparent)]
pub struct PerDof<T>(pub [T; 6]);

impl<T> PerDof<T> {
    /// Each DOF with its value.
    pub fn with_dof(&self) -> impl Iterator<Item = (Dof, &T)> {
        Dof::ALL.into_iter().zip(self.0.iter())
    }
}

impl<T> From<[T; 6]> for PerDof<T> {
    fn from(a: [T; 6]) -> Self {
        PerDof(a)
    }
}

impl<T> From<PerDof<T>> for [T; 6] {
    fn from(p: PerDof<T>) -> Self {
        p.0
    }
}

impl<T> Deref for PerDof<T> {
    type Target = [T; 6];
    fn deref(&self) -> &[T; 6] {
        &self.0
    }
}

impl<T> DerefMut for PerDof<T> {
    fn deref_mut(&mut self) -> &mut [T; 6] {
        &mut self.0
    }
}

impl<T> Index<Dof> for PerDof<T> {
    type Output = T;
    fn index(&self, d: Dof) -> &T {
        &self.0[d.index()]
    }
}

impl<T> IndexMut<Dof> for PerDof<T> {
    fn index_mut(&mut self, d: Dof) -> &mut T {
        &mut self.0[d.index()]
    }
}

impl<T, I: SliceIndex<[T]>> Index<I> for PerDof<T> {
    type Output = I::Output;
    fn index(&self, i: I) -> &I::Output {
        &self.0[i]
    }
}

impl<T, I: SliceIndex<[T]>> IndexMut<I> for PerDof<T> {
    fn index_mut(&mut self, i: I) -> &mut I::Output {
        &mut self.0[i]
    }
}

impl<T> IntoIterator for PerDof<T> {
    type Item = T;
    type IntoIter = std::array::IntoIter<T, 6>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.into_iter()
    }
}

impl<'a, T> IntoIterator for &'a PerDof<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.iter()
    }
}
