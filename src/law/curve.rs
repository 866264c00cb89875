//! Piecewise-linear functions (Radioss `/FUNCT`) with linear extrapolation
//! (docs/kjoint2.md §4.1).

use crate::error::PropertyError;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// A piecewise-linear function `y = f(x)` given by points with strictly increasing `x`.
///
/// Between points the function is linear; beyond the first and last point it is
/// **extrapolated linearly** with the slope of the first or last segment (as Radioss does).
/// A curve has at least two points: a constant `c` is two points with the same value,
/// `[(0, c), (1, c)]` (a single point has no segment, and so no slope to extrapolate with).
///
/// Used for stiffness (force vs displacement), viscosity (force vs velocity) and friction
/// (friction force vs displacement) laws; the property's scalar multiplies it
/// (docs/kjoint2.md §4.1).
///
/// ```
/// use rapier_kjoint::Curve;
/// // a spring that stiffens: 100 N at 1 cm, 300 N at 2 cm
/// let f = Curve::new([(0.0, 0.0), (0.01, 100.0), (0.02, 300.0)]).unwrap();
/// assert!((f.value(0.015) - 200.0).abs() < 1e-9);
/// assert!((f.value(0.03) - 500.0).abs() < 1e-9);   // extrapolated with the last slope
/// assert!((f.slope(0.03) - 20000.0).abs() < 1e-6); // [N/m]
/// ```
///
/// A curve keeps, besides its points, what every evaluation would otherwise recompute: the
/// segment used and its slope for each interval between points, the value at each point and
/// at 0, and where 0 falls among the points. A value, its slope and the integral from 0 then
/// take one search (none when the caller's hint still holds) and no division
/// (`CurveData::value_slope_integral`), with the same results, bit for bit, as the separate
/// [`CurveData::value`], [`CurveData::slope`] and [`CurveData::integral_from_zero`].
///
/// The points and what is kept of them live behind one shared pointer: a property holds up to
/// three optional curves per DOF, and joints built from one property (a chain, a robot's
/// repeated links) share them; a DOF without curves costs three null pointers.
#[derive(Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<Vec<f64>>", into = "Vec<[f64; 2]>")]
pub struct Curve(std::sync::Arc<CurveData>);

/// The data of a [`Curve`].
#[derive(Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct CurveData {
    x: Vec<f64>,
    y: Vec<f64>,
    /// One cell per count `k = #{x_i ≤ x}`, `k = 0..=n` (see [`Cell`]).
    cells: Vec<Cell>,
    /// `f(x_i)` as [`CurveData::value`] gives it (at the last point it comes from the last
    /// segment, `y_{n−2} + s·(x_{n−1} − x_{n−2})`, which may round away from `y_{n−1}`).
    at_point: Vec<f64>,
    /// `f(0)`.
    at_zero: f64,
    /// Number of points with `x_i ≤ 0`.
    zero_le: usize,
    /// Number of points with `x_i < 0`.
    zero_lt: usize,
}

/// Where `x` falls among the points, for the `k = #{x_i ≤ x}` of the cell: the interval
/// `lo ≤ x < hi` that has this count, `[x_{k−1}, x_k)` with `−∞`/`+∞` for the missing ends,
/// and the segment `i = clamp(k, 1, n − 1) − 1` used there (first/last beyond the ends):
/// its start `(x_i, y_i)` and slope `s_i = (y_{i+1} − y_i)/(x_{i+1} − x_i)`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
struct Cell {
    lo: f64,
    hi: f64,
    x: f64,
    y: f64,
    slope: f64,
}

/// The points only: the cached fields are functions of them.
impl std::fmt::Debug for Curve {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Curve")
            .field("x", &self.x)
            .field("y", &self.y)
            .finish()
    }
}

impl std::ops::Deref for Curve {
    type Target = CurveData;
    fn deref(&self) -> &CurveData {
        &self.0
    }
}

impl TryFrom<Vec<[f64; 2]>> for Curve {
    type Error = PropertyError;
    fn try_from(points: Vec<[f64; 2]>) -> Result<Self, Self::Error> {
        Curve::new(points.iter().map(|p| (p[0], p[1])))
    }
}

/// Points as a reader gives them, each read in full: a point of one or three numbers is
/// refused, where `[f64; 2]` read `[0, 0, 3]` as `[0, 0]` without a word.
impl TryFrom<Vec<Vec<f64>>> for Curve {
    type Error = PropertyError;
    fn try_from(points: Vec<Vec<f64>>) -> Result<Self, Self::Error> {
        if let Some((i, p)) = points.iter().enumerate().find(|(_, p)| p.len() != 2) {
            return Err(PropertyError::InvalidCurve(format!(
                "point {} has {} numbers: expected [x, y]",
                i + 1,
                p.len()
            )));
        }
        Curve::new(points.iter().map(|p| (p[0], p[1])))
    }
}

impl From<Curve> for Vec<[f64; 2]> {
    fn from(c: Curve) -> Self {
        c.x.iter().zip(&c.y).map(|(&x, &y)| [x, y]).collect()
    }
}

impl Curve {
    /// Builds a curve from `(x, y)` points. There must be at least two points
    /// ([`Curve::too_few_points`]: a constant is two points with the same value), the `x`
    /// finite and strictly increasing, the `y` finite and the slopes between points finite.
    pub fn new(points: impl IntoIterator<Item = (f64, f64)>) -> Result<Self, PropertyError> {
        let (x, y): (Vec<f64>, Vec<f64>) = points.into_iter().unzip();
        if x.len() < Self::MIN_POINTS {
            return Err(Self::too_few_points(x.len()));
        }
        for (i, (&xi, &yi)) in x.iter().zip(&y).enumerate() {
            if !xi.is_finite() || !yi.is_finite() {
                return Err(PropertyError::InvalidCurve(format!(
                    "point {} = ({xi}, {yi}) is not finite",
                    i + 1
                )));
            }
            if i > 0 && xi <= x[i - 1] {
                return Err(PropertyError::InvalidCurve(format!(
                    "x must increase strictly: point {} has x = {xi} after x = {}",
                    i + 1,
                    x[i - 1]
                )));
            }
            if i > 0 && !((yi - y[i - 1]) / (xi - x[i - 1])).is_finite() {
                return Err(PropertyError::InvalidCurve(format!(
                    "the slope from point {i} to point {} overflows (x too close for the \
                     change of y)",
                    i + 1
                )));
            }
        }
        let n = x.len();
        let cells = (0..=n)
            .map(|k| {
                let (lo, hi) = (
                    if k == 0 { f64::NEG_INFINITY } else { x[k - 1] },
                    x.get(k).copied().unwrap_or(f64::INFINITY),
                );
                let i = k.clamp(1, n - 1) - 1;
                Cell {
                    lo,
                    hi,
                    x: x[i],
                    y: y[i],
                    slope: (y[i + 1] - y[i]) / (x[i + 1] - x[i]),
                }
            })
            .collect();
        let mut d = CurveData {
            x,
            y,
            cells,
            at_point: Vec::new(),
            at_zero: 0.0,
            zero_le: 0,
            zero_lt: 0,
        };
        // the values at the points and at 0 as `value` gives them (its lookup only reads
        // the cells)
        let at_point = d.x.iter().map(|&xi| d.value(xi)).collect();
        d.at_point = at_point;
        d.at_zero = d.value(0.0);
        d.zero_le = d.x.partition_point(|&xi| xi <= 0.0);
        d.zero_lt = d.x.partition_point(|&xi| xi < 0.0);
        Ok(Curve(std::sync::Arc::new(d)))
    }

    /// The fewest points a curve has: two (one segment).
    pub const MIN_POINTS: usize = 2;

    /// The error [`Curve::new`] returns for `n` points, fewer than [`Curve::MIN_POINTS`]:
    /// `n point(s): expected at least 2 points (a constant is two points with the same
    /// value)`. The readers that count points themselves (a deck's `NPAIRS`, a scene's time
    /// curve) say the same.
    pub fn too_few_points(n: usize) -> PropertyError {
        PropertyError::InvalidCurve(format!(
            "{}: expected at least {} points (a constant is two points with the same value)",
            match n {
                0 => "no point".to_string(),
                1 => "1 point".to_string(),
                n => format!("{n} points"),
            },
            Self::MIN_POINTS
        ))
    }
}

impl CurveData {
    /// The points of the curve.
    pub fn points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.x.iter().copied().zip(self.y.iter().copied())
    }

    /// Where `x` falls: the number `k` of points with `x_i ≤ x`, and its [`Cell`].
    #[inline]
    fn locate(&self, x: f64) -> (usize, &Cell) {
        // a hint no lookup can hold: the search
        let mut none = u32::MAX;
        self.locate_from(x, &mut none)
    }

    /// [`Self::locate`] starting from the `k` of an earlier lookup, `hint`, which becomes
    /// this lookup's `k`. Any hint gives the same result; a law whose `x` moves little from
    /// one evaluation to the next keeps it right and skips the search.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn locate_from(&self, x: f64, hint: &mut u32) -> (usize, &Cell) {
        // the x_i increase: x_{k−1} ≤ x < x_k means exactly k points are ≤ x (false for a
        // NaN x, which counts none, as the search finds)
        if let Some(c) = self.cells.get(*hint as usize) {
            if c.lo <= x && x < c.hi {
                return (*hint as usize, c);
            }
        }
        // partition_point: number of points with x_i <= x (a hint kept in 32 bits, as the
        // laws' records hold it; past them it is no hint, and the next lookup searches)
        let k = self.x.partition_point(|&xi| xi <= x);
        *hint = u32::try_from(k).unwrap_or(u32::MAX);
        (k, &self.cells[k])
    }

    /// The number of points with `x_i < x`, from the number `k` with `x_i ≤ x` and its
    /// cell (the `x_i` increase strictly: at most one, `x_{k−1}`, equals `x`).
    #[inline]
    fn count_below(x: f64, (k, cell): (usize, &Cell)) -> usize {
        if k > 0 && cell.lo == x {
            k - 1
        } else {
            k
        }
    }

    /// `f(x)` in `cell`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn value_in(&self, cell: &Cell, x: f64) -> f64 {
        cell.y + cell.slope * (x - cell.x)
    }

    /// `f(x)`, linear between points and extrapolated linearly beyond the ends.
    #[inline]
    pub fn value(&self, x: f64) -> f64 {
        self.value_in(self.locate(x).1, x)
    }

    /// [`Self::value`], the search starting from `hint` ([`Self::locate_from`]).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn value_near(&self, x: f64, hint: &mut u32) -> f64 {
        self.value_in(self.locate_from(x, hint).1, x)
    }

    /// `f'(x)`: the slope of the segment containing `x` (right derivative at points).
    #[inline]
    pub fn slope(&self, x: f64) -> f64 {
        self.locate(x).1.slope
    }

    /// `(f(x), f'(x))` from one search: [`Self::value`] and [`Self::slope`], bit for bit;
    /// the search starts from `hint` ([`Self::locate_from`]).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn value_and_slope(&self, x: f64, hint: &mut u32) -> (f64, f64) {
        let cell = self.locate_from(x, hint).1;
        (self.value_in(cell, x), cell.slope)
    }

    /// `(f(x), f'(x), ∫₀ˣ f)` from one search: [`Self::value`], [`Self::slope`] and
    /// [`Self::integral_from_zero`], bit for bit (the same trapezoids summed in the same
    /// order, over the same break points); the search starts from `hint`
    /// ([`Self::locate_from`]).
    // always: out of line, the law around it spills and reloads its live registers
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn value_slope_integral(&self, x: f64, hint: &mut u32) -> (f64, f64, f64) {
        self.value_slope_integral_at(x, self.locate_from(x, hint))
    }

    /// [`Self::value_slope_integral`] with `x` located ([`Self::locate`]).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn value_slope_integral_at(&self, x: f64, (k, cell): (usize, &Cell)) -> (f64, f64, f64) {
        let fx = self.value_in(cell, x);
        // integral(0, x) for x ≥ 0 (and −0); −integral(x, 0) below, as `integral` does
        let area = if x < 0.0 {
            -self.trapezoids((x, fx), k..self.zero_lt, (0.0, self.at_zero))
        } else {
            self.trapezoids(
                (0.0, self.at_zero),
                self.zero_le..Self::count_below(x, (k, cell)),
                (x, fx),
            )
        };
        (fx, cell.slope, area)
    }

    /// The largest `|f'|` over the segments: the largest tangent stiffness a law `K·f` can
    /// reach is `|K|·max_abs_slope()` (the extrapolation uses the end segments' slopes).
    pub fn max_abs_slope(&self) -> f64 {
        // every segment has a cell (the end ones two)
        self.cells.iter().map(|c| c.slope.abs()).fold(0.0, f64::max)
    }

    /// The displacements `(lo, hi)` beyond which the curve's linear extrapolation pushes
    /// away from zero without bound (`−∞`, `+∞` where it does not). Past the last point a
    /// falling last segment `f(x) = y_i + s·(x − x_i)`, `s < 0`, reaches `f = 0` at
    /// `x_i − y_i/s` (a flat one that ends below zero pushes outwards from the last point
    /// with a constant force); from there on `f(x)·x < 0` and `|f|` grows with `x` (or
    /// stays), so a law
    /// `F = K·f(δ)` (`K ≥ 0`) pushes the DOF further out the further it goes. Below the first
    /// point likewise, where the first segment falls (`f > 0` for `x < 0`). `hi` is at least
    /// the last point and 0, `lo` at most the first point and 0: a softening curve whose
    /// force has changed sign inside its own points runs away from its end. `(−0.02, −5)`,
    /// `(−0.01, −10)`, `(0, 0)`, `(0.01, 10)`, `(0.02, 5)`: slopes −500 at both ends, so
    /// `(lo, hi) = (−0.03, 0.03)`.
    pub fn runaway_bounds(&self) -> (f64, f64) {
        let n = self.x.len();
        // the cells beyond the ends carry the end segments (start point and slope)
        // (a flat end that pushes outwards, `f < 0` past the last point or `f > 0` before
        // the first, pushes with a constant force: it runs away too)
        let (first, last) = (&self.cells[0], &self.cells[n]);
        let hi = if last.slope < 0.0 {
            (last.x - last.y / last.slope).max(self.x[n - 1]).max(0.0)
        } else if last.slope == 0.0 && last.y < 0.0 {
            self.x[n - 1].max(0.0)
        } else {
            f64::INFINITY
        };
        let lo = if first.slope < 0.0 {
            (first.x - first.y / first.slope).min(self.x[0]).min(0.0)
        } else if first.slope == 0.0 && first.y > 0.0 {
            self.x[0].min(0.0)
        } else {
            f64::NEG_INFINITY
        };
        (lo, hi)
    }

    /// `∫₀ˣ f(s) ds`, exact for the piecewise-linear function (the stored energy of a
    /// force-displacement curve).
    pub fn integral_from_zero(&self, x: f64) -> f64 {
        self.value_slope_integral_at(x, self.locate(x)).2
    }

    /// `∫ₐᵇ f(s) ds`, exact (trapezoids on each linear piece, extrapolation included).
    pub fn integral(&self, a: f64, b: f64) -> f64 {
        if a > b {
            return -self.integral(b, a);
        }
        // Break points strictly inside (a, b): those after the points ≤ a, before those ≥ b.
        let inside = self.locate(a).0..Self::count_below(b, self.locate(b));
        self.trapezoids((a, self.value(a)), inside, (b, self.value(b)))
    }

    /// `∫ₐᵇ f(s) ds` given `f(a)`, `f(b)` and the indices of the break points strictly
    /// inside `(a, b)` (increasing): the function is linear between them, so the sum of the
    /// trapezoids `½·(f(lo) + f(x_j))·(x_j − lo)` from `lo = a` over the break points, then
    /// to `b`, is exact.
    fn trapezoids(&self, (a, fa): (f64, f64), inside: Range<usize>, (b, fb): (f64, f64)) -> f64 {
        let mut total = 0.0;
        let (mut lo, mut f_lo) = (a, fa);
        for j in inside {
            let (xj, fj) = (self.x[j], self.at_point[j]);
            total += 0.5 * (f_lo + fj) * (xj - lo);
            (lo, f_lo) = (xj, fj);
        }
        total + 0.5 * (f_lo + fb) * (b - lo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// `runaway_bounds`: where the extrapolation's force has turned to push outwards (a
    /// falling end stays on the restoring side until `x_i − y_i/s`), and nowhere for a
    /// curve whose ends rise.
    #[test]
    fn runaway_bounds_are_where_the_extrapolation_pushes_outwards() {
        let soft = Curve::new([
            (-0.02, -5.0),
            (-0.01, -10.0),
            (0.0, 0.0),
            (0.01, 10.0),
            (0.02, 5.0),
        ])
        .unwrap();
        let (lo, hi) = soft.runaway_bounds();
        assert!(
            (lo + 0.03).abs() < 1e-15 && (hi - 0.03).abs() < 1e-15,
            "{lo} {hi}"
        );
        // just past them the force points outwards, just inside not yet
        assert!(soft.value(hi + 1e-6) < 0.0 && soft.value(hi - 1e-6) > 0.0);
        assert!(soft.value(lo - 1e-6) > 0.0 && soft.value(lo + 1e-6) < 0.0);
        // rising ends: none
        let stiff = Curve::new([(-1.0, -1.0), (0.0, 0.0), (1.0, 3.0)]).unwrap();
        assert_eq!(stiff.runaway_bounds(), (f64::NEG_INFINITY, f64::INFINITY));
        // a force that has already changed sign at the last point: from that point on
        let through = Curve::new([(0.0, 0.0), (1.0, 2.0), (2.0, -1.0)]).unwrap();
        assert_eq!(through.runaway_bounds(), (f64::NEG_INFINITY, 2.0));
        // a curve on the negative side only, pushing outwards all along it: from its first
        // point down, and from 0 up (where its extrapolation is negative)
        let negative = Curve::new([(-2.0, 1.0), (-1.0, 0.5)]).unwrap();
        assert_eq!(negative.runaway_bounds(), (-2.0, 0.0));
        // a single falling segment through the origin: a negative spring everywhere
        let falling = Curve::new([(-1.0, 2.0), (1.0, -2.0)]).unwrap();
        assert_eq!(falling.runaway_bounds(), (-1.0, 1.0));
        // flat ends that push outwards (a constant force), and flat ends that restore
        let flat_out = Curve::new([
            (-3.0, 1.0),
            (-2.0, 1.0),
            (0.0, 0.0),
            (2.0, -1.0),
            (3.0, -1.0),
        ])
        .unwrap();
        assert_eq!(flat_out.runaway_bounds(), (-3.0, 3.0));
        let flat_in = Curve::new([(-2.0, -1.0), (-1.0, -1.0), (1.0, 1.0), (2.0, 1.0)]).unwrap();
        assert_eq!(flat_in.runaway_bounds(), (f64::NEG_INFINITY, f64::INFINITY));
    }

    /// The plain lookups, as they were before the curve kept its slopes and values: a
    /// search and a division for every value and slope, the integral over a filter of all
    /// the points. The cached lookups must give the same bits.
    mod plain {
        fn segment(x: &[f64], v: f64) -> usize {
            let n = x.len();
            if n < 2 {
                return 0;
            }
            x.partition_point(|&xi| xi <= v).clamp(1, n - 1) - 1
        }
        fn slope_of(x: &[f64], y: &[f64], i: usize) -> f64 {
            (y[i + 1] - y[i]) / (x[i + 1] - x[i])
        }
        pub fn value(x: &[f64], y: &[f64], v: f64) -> f64 {
            if x.len() == 1 {
                return y[0];
            }
            let i = segment(x, v);
            y[i] + slope_of(x, y, i) * (v - x[i])
        }
        pub fn slope(x: &[f64], y: &[f64], v: f64) -> f64 {
            if x.len() == 1 {
                0.0
            } else {
                slope_of(x, y, segment(x, v))
            }
        }
        pub fn integral(x: &[f64], y: &[f64], a: f64, b: f64) -> f64 {
            if a > b {
                return -integral(x, y, b, a);
            }
            let mut total = 0.0;
            let mut lo = a;
            for &xi in x.iter().filter(|&&xi| xi > a && xi < b) {
                total += 0.5 * (value(x, y, lo) + value(x, y, xi)) * (xi - lo);
                lo = xi;
            }
            total + 0.5 * (value(x, y, lo) + value(x, y, b)) * (b - lo)
        }
    }

    /// 2 to 7 points with strictly increasing x around 0 (sometimes exactly at 0).
    fn any_points() -> impl Strategy<Value = Vec<(f64, f64)>> {
        (
            -5.0f64..5.0,
            any::<bool>(),
            proptest::collection::vec((0.01f64..3.0, -100.0f64..100.0), 2..8),
        )
            .prop_map(|(start, at_zero, steps)| {
                let mut x = if at_zero { 0.0 } else { start };
                steps
                    .into_iter()
                    .map(|(dx, y)| {
                        let p = (x, y);
                        x += dx;
                        p
                    })
                    .collect()
            })
    }

    /// Where to look a curve up: anywhere, far beyond the ends, on a point, at ±0.
    fn any_x(points: &[(f64, f64)]) -> impl Strategy<Value = f64> {
        let on: Vec<f64> = points.iter().map(|p| p.0).collect();
        prop_oneof![
            -20.0f64..20.0,
            -1e6f64..1e6,
            proptest::sample::select(on),
            Just(0.0),
            Just(-0.0),
        ]
    }

    fn same(a: f64, b: f64) -> bool {
        a.to_bits() == b.to_bits()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// The cached lookups (`value`, `slope`, `value_near`, `value_and_slope`,
        /// `value_slope_integral`, `integral_from_zero`, `integral`, `max_abs_slope`) equal
        /// the plain ones bit for bit, whatever hint they start from.
        #[test]
        fn cached_lookups_equal_the_plain_ones(
            (points, a, b) in any_points()
                .prop_flat_map(|p| (Just(p.clone()), any_x(&p), any_x(&p))),
            hint in prop_oneof![0u32..10, Just(u32::MAX)],
        ) {
            let c = Curve::new(points.iter().copied()).unwrap();
            let (x, y): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
            // any hint (even one past the points), then the hint the lookup at a left
            let mut h = hint;
            for v in [a, b] {
                let (f, s, i) = c.value_slope_integral(v, &mut h.clone());
                let want = (
                    plain::value(&x, &y, v),
                    plain::slope(&x, &y, v),
                    plain::integral(&x, &y, 0.0, v),
                );
                prop_assert!(same(f, want.0) && same(s, want.1) && same(i, want.2),
                    "at {v}: {:?} != {want:?}", (f, s, i));
                prop_assert!(same(c.value(v), want.0) && same(c.slope(v), want.1));
                prop_assert!(same(c.value_near(v, &mut h.clone()), want.0));
                let (f2, s2) = c.value_and_slope(v, &mut h);
                prop_assert!(same(f2, want.0) && same(s2, want.1));
                // the hint is the number of points <= v
                prop_assert_eq!(h as usize, x.iter().filter(|&&xi| xi <= v).count());
                prop_assert!(same(c.integral_from_zero(v), want.2));
            }
            prop_assert!(same(c.integral(a, b), plain::integral(&x, &y, a, b)));
            let max = (0..x.len().saturating_sub(1))
                .map(|i| ((y[i + 1] - y[i]) / (x[i + 1] - x[i])).abs())
                .fold(0.0, f64::max);
            prop_assert!(same(c.max_abs_slope(), max));
        }
    }

    /// A curve reads back as its points, in Debug and through serde, whatever it caches.
    #[test]
    fn debug_and_serde_show_the_points_only() {
        let c = Curve::new([(-1.0, -2.0), (0.0, 0.0), (2.0, 1.0)]).unwrap();
        assert_eq!(
            format!("{c:?}"),
            "Curve { x: [-1.0, 0.0, 2.0], y: [-2.0, 0.0, 1.0] }"
        );
        let json = serde_json::to_string(&c).unwrap();
        assert_eq!(json, "[[-1.0,-2.0],[0.0,0.0],[2.0,1.0]]");
        assert_eq!(serde_json::from_str::<Curve>(&json).unwrap(), c);
    }
}
