//! Time functions of loads, motions and motors (scene `function = { ... }`): [`TimeFn`]
//! and its reading from the scene, in SI.

use super::checks::{finite, finite_array, non_negative};
use crate::error::PropertyError;
use crate::law::Curve;
use crate::scene::schema::TimeFunction;
use crate::scene::{FieldPath, SceneError, Source};

/// A dimensionless function of time `t` \[s\], in SI.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeFn {
    /// A constant.
    Constant(f64),
    /// Piecewise linear through `(t \[s\], value)` points, constant outside.
    Curve(ClampedCurve),
    /// `offset + amplitude·sin(2π·frequency·(t − start) + phase)` for `t ≥ start`, 0
    /// before; frequency \[Hz\], phase \[rad\], start \[s\].
    Sine {
        /// Amplitude.
        amplitude: f64,
        /// Frequency \[Hz\].
        frequency: f64,
        /// Phase \[rad\].
        phase: f64,
        /// Offset.
        offset: f64,
        /// Start time \[s\].
        start: f64,
    },
}

/// A [`Curve`] held constant outside its points: the curve of a time function.
#[derive(Clone, PartialEq)]
pub struct ClampedCurve {
    /// The curve (extrapolated linearly by itself).
    curve: Curve,
    /// Its first point.
    first: (f64, f64),
    /// Its last point.
    last: (f64, f64),
}

impl ClampedCurve {
    /// A curve through `points` (strictly increasing, finite; at least two, as
    /// [`Curve::new`] asks), constant outside them.
    pub fn new(points: impl IntoIterator<Item = (f64, f64)>) -> Result<Self, PropertyError> {
        let curve = Curve::new(points)?;
        let first = curve.points().next().unwrap_or_default();
        let last = curve.points().last().unwrap_or_default();
        Ok(ClampedCurve { curve, first, last })
    }

    /// The curve inside its points.
    pub fn curve(&self) -> &Curve {
        &self.curve
    }

    /// The value at `t`: the curve's between its first and last points, the value of the
    /// nearest end outside.
    pub fn value(&self, t: f64) -> f64 {
        if t <= self.first.0 {
            self.first.1
        } else if t >= self.last.0 {
            self.last.1
        } else {
            self.curve.value(t)
        }
    }
}

/// The points, `[(t, value), ...]`, as `kjoint check` prints them.
impl std::fmt::Debug for ClampedCurve {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.curve.points()).finish()
    }
}

impl TimeFn {
    /// The value at time `t` \[s\].
    pub fn value(&self, t: f64) -> f64 {
        match self {
            TimeFn::Constant(c) => *c,
            TimeFn::Curve(c) => c.value(t),
            TimeFn::Sine {
                amplitude,
                frequency,
                phase,
                offset,
                start,
            } => {
                if t < *start {
                    0.0
                } else {
                    offset
                        + amplitude
                            * (2.0 * std::f64::consts::PI * frequency * (t - start) + phase).sin()
                }
            }
        }
    }
}

/// A scene's time function at `fp` in SI (`t` the factor of the scene's time unit): times
/// of a curve strictly increasing, a sine's frequency and start >= 0, every value finite;
/// none is the constant 1.
pub(super) fn time_function(
    src: &Source,
    fp: &FieldPath,
    function: &Option<TimeFunction>,
    t: f64,
) -> Result<TimeFn, SceneError> {
    Ok(match function {
        None => TimeFn::Constant(1.0),
        Some(TimeFunction::Constant(c)) => TimeFn::Constant(finite(src, &fp.key("constant"), *c)?),
        Some(TimeFunction::Curve(pts)) => {
            let cp = fp.key("curve");
            if pts.len() < Curve::MIN_POINTS {
                let n = match pts.len() {
                    0 => "no point",
                    _ => "1 point",
                };
                return Err(src.error(
                    &cp,
                    format!(
                        "{n}: expected at least {} points [t, value] (a constant is two points \
                         with the same value, or `function = {{ constant = c }}`)",
                        Curve::MIN_POINTS
                    ),
                ));
            }
            let mut out: Vec<(f64, f64)> = Vec::with_capacity(pts.len());
            for (k, pt) in pts.iter().enumerate() {
                let pt = finite_array(src, &cp.index(k), *pt)?;
                if k > 0 && pt[0] * t <= out[k - 1].0 {
                    return Err(src.error(
                        &cp.index(k),
                        format!("time {} does not increase strictly", pt[0]),
                    ));
                }
                out.push((pt[0] * t, pt[1]));
            }
            TimeFn::Curve(ClampedCurve::new(out).map_err(|e| src.error(&cp, e.to_string()))?)
        }
        Some(TimeFunction::Sine(s)) => {
            let sp = fp.key("sine");
            let frequency = non_negative(src, &sp.key("frequency"), s.frequency)?;
            TimeFn::Sine {
                amplitude: finite(src, &sp.key("amplitude"), s.amplitude)?,
                frequency: frequency / t,
                phase: finite(src, &sp.key("phase"), s.phase)?,
                offset: finite(src, &sp.key("offset"), s.offset)?,
                start: non_negative(src, &sp.key("start"), s.start)? * t,
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_curve_is_linear_between_its_points_and_constant_outside() {
        let c = ClampedCurve::new([(1.0, 2.0), (3.0, 6.0), (4.0, 0.0)]).unwrap();
        let f = TimeFn::Curve(c);
        assert_eq!(f.value(0.0), 2.0);
        assert_eq!(f.value(1.0), 2.0);
        assert_eq!(f.value(2.0), 4.0);
        assert_eq!(f.value(3.5), 3.0);
        assert_eq!(f.value(4.0), 0.0);
        assert_eq!(f.value(10.0), 0.0);
        // a single point is refused: a constant is two points with the same value
        let e = ClampedCurve::new([(0.5, 7.0)]).unwrap_err().to_string();
        assert!(e.contains("1 point: expected at least 2 points"), "{e}");
        let flat = TimeFn::Curve(ClampedCurve::new([(0.5, 7.0), (1.0, 7.0)]).unwrap());
        assert_eq!(
            [flat.value(0.0), flat.value(0.7), flat.value(9.0)],
            [7.0; 3]
        );
    }

    #[test]
    fn a_curve_prints_as_its_points() {
        let c = ClampedCurve::new([(0.0, 0.0), (1.0, 2.5)]).unwrap();
        assert_eq!(
            format!("{:?}", TimeFn::Curve(c)),
            "Curve([(0.0, 0.0), (1.0, 2.5)])"
        );
    }
}
