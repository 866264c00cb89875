//! Piecewise-linear functions (Radioss `/FUNCT`) with linear extrapolation.

use crate::error::PropertyError;
use serde::{Deserialize, Serialize};

/// A piecewise-linear function `y = f(x)` given by points with strictly increasing `x`.
///
/// Between points the function is linear; beyond the first and last point it is
/// **extrapolated linearly** with the slope of the first or last segment (as Radioss does).
/// A curve with a single point is the constant `y0`.
///
/// Used for stiffness (force vs displacement), viscosity (force vs velocity) and friction
/// (friction force vs displacement) laws; the property's scalar multiplies it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<[f64; 2]>", into = "Vec<[f64; 2]>")]
pub struct Curve {
    x: Vec<f64>,
    y: Vec<f64>,
}

impl TryFrom<Vec<[f64; 2]>> for Curve {
    type Error = PropertyError;
    fn try_from(points: Vec<[f64; 2]>) -> Result<Self, Self::Error> {
        Curve::new(points.iter().map(|p| (p[0], p[1])))
    }
}

impl From<Curve> for Vec<[f64; 2]> {
    fn from(c: Curve) -> Self {
        c.x.iter().zip(&c.y).map(|(&x, &y)| [x, y]).collect()
    }
}

impl Curve {
    /// Builds a curve from `(x, y)` points. The `x` must be finite and strictly increasing,
    /// the `y` finite, the slopes between points finite, and there must be at least one
    /// point.
    pub fn new(points: impl IntoIterator<Item = (f64, f64)>) -> Result<Self, PropertyError> {
        let (x, y): (Vec<f64>, Vec<f64>) = points.into_iter().unzip();
        if x.is_empty() {
            return Err(PropertyError::InvalidCurve(
                "a curve needs at least one point".into(),
            ));
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
        Ok(Curve { x, y })
    }

    /// The points of the curve.
    pub fn points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.x.iter().copied().zip(self.y.iter().copied())
    }

    /// Index `i` of the segment `[x_i, x_{i+1}]` used at `x` (first/last for extrapolation).
    fn segment(&self, x: f64) -> usize {
        let n = self.x.len();
        if n < 2 {
            return 0;
        }
        // partition_point: number of points with x_i <= x
        let k = self.x.partition_point(|&xi| xi <= x);
        k.clamp(1, n - 1) - 1
    }

    /// `f(x)`, linear between points and extrapolated linearly beyond the ends.
    pub fn value(&self, x: f64) -> f64 {
        if self.x.len() == 1 {
            return self.y[0];
        }
        let i = self.segment(x);
        self.y[i] + self.slope_of(i) * (x - self.x[i])
    }

    fn slope_of(&self, i: usize) -> f64 {
        (self.y[i + 1] - self.y[i]) / (self.x[i + 1] - self.x[i])
    }

    /// `f'(x)`: the slope of the segment containing `x` (right derivative at points).
    pub fn slope(&self, x: f64) -> f64 {
        if self.x.len() == 1 {
            0.0
        } else {
            self.slope_of(self.segment(x))
        }
    }

    /// The largest `|f'|` over the segments (0 for a single point): the largest tangent
    /// stiffness a law `K·f` can reach is `|K|·max_abs_slope()` (the extrapolation uses the
    /// end segments' slopes).
    pub fn max_abs_slope(&self) -> f64 {
        (0..self.x.len().saturating_sub(1))
            .map(|i| self.slope_of(i).abs())
            .fold(0.0, f64::max)
    }

    /// `∫₀ˣ f(s) ds`, exact for the piecewise-linear function (the stored energy of a
    /// force-displacement curve).
    pub fn integral_from_zero(&self, x: f64) -> f64 {
        self.integral(0.0, x)
    }

    /// `∫ₐᵇ f(s) ds`, exact (trapezoids on each linear piece, extrapolation included).
    pub fn integral(&self, a: f64, b: f64) -> f64 {
        if a > b {
            return -self.integral(b, a);
        }
        // Break points strictly inside (a, b); the function is linear between them.
        let mut total = 0.0;
        let mut lo = a;
        for &xi in self.x.iter().filter(|&&xi| xi > a && xi < b) {
            total += 0.5 * (self.value(lo) + self.value(xi)) * (xi - lo);
            lo = xi;
        }
        total + 0.5 * (self.value(lo) + self.value(b)) * (b - lo)
    }
}
