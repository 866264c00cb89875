//! The failure criterion of a breakable joint (docs/breakable.md), as a pure function of
//! the force and moment the joint transmitted and the energy it dissipated.
//!
//! With `F` the transmitted force \[N\], `M` the transmitted moment \[N·m\] and `D` the
//! dissipated energy \[J\] (docs/breakable.md §1), a joint fails when
//!
//! ```text
//! (F/F_max)^a + (M/M_max)^b ≥ 1      (the terms of the limits that are given)
//! or  D ≥ D_max                      (when D_max is given)
//! ```
//!
//! A limit of 0 is "no such limit". A bolt of `F_max` = 10 kN and `M_max` = 500 N·m with
//! the elliptic interaction (`a = b = 2`) fails under 6 kN and 400 N·m (0.36 + 0.64 = 1):
//!
//! ```
//! use rapier_kjoint::law::{BreakCause, BreakCriterion};
//! let bolt = BreakCriterion::force_and_moment(1e4, 500.0);
//! assert!(bolt.validate().is_ok());
//! assert_eq!(bolt.check(5.0e3, 400.0, 0.0), None); // 0.25 + 0.64 < 1
//! match bolt.check(6.0e3, 400.0, 0.0) {
//!     Some(BreakCause::Interaction { value, .. }) => assert!((value - 1.0).abs() < 1e-12),
//!     other => panic!("{other:?}"),
//! }
//! ```

use crate::error::PropertyError;
use crate::figure::format_figure as fig;
use serde::{Deserialize, Serialize};
use std::fmt;

/// When a joint breaks (docs/breakable.md §2): limits on the transmitted force and moment,
/// combined by the interaction `(F/F_max)^a + (M/M_max)^b ≥ 1`, and on the dissipated
/// energy. A limit of 0 is "no such limit"; at least one limit must be given.
///
/// In a scene file the `break` table of a joint, in the scene's units:
/// `break = { force = 1e4, moment = 500.0, force_exponent = 2, moment_exponent = 2 }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BreakCriterion {
    /// `F_max`, the limit of the transmitted force \[N\] (0: none).
    pub force: f64,
    /// `M_max`, the limit of the transmitted moment \[N·m\] (0: none).
    pub moment: f64,
    /// `a`, the exponent of the force term of the interaction (> 0; default 2; without a
    /// moment limit it changes nothing: `(F/F_max)^a ≥ 1 ⇔ F ≥ F_max`).
    pub force_exponent: f64,
    /// `b`, the exponent of the moment term (> 0; default 2).
    pub moment_exponent: f64,
    /// `D_max`, the limit of the energy the joint's law dissipated, `damping + friction +
    /// stop` of its [`crate::law::JointEnergy`] \[J\] (0: none).
    pub dissipated_energy: f64,
}

impl Default for BreakCriterion {
    /// No limit (invalid until one is set), exponents 2.
    fn default() -> Self {
        BreakCriterion {
            force: 0.0,
            moment: 0.0,
            force_exponent: 2.0,
            moment_exponent: 2.0,
            dissipated_energy: 0.0,
        }
    }
}

/// Why a joint broke: which limit was met, with the measured value and the limit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
#[non_exhaustive]
pub enum BreakCause {
    /// The transmitted force reached the force limit (no moment limit given).
    Force {
        /// The transmitted force `F` \[N\].
        force: f64,
        /// `F_max` \[N\].
        limit: f64,
    },
    /// The transmitted moment reached the moment limit (no force limit given).
    Moment {
        /// The transmitted moment `M` \[N·m\].
        moment: f64,
        /// `M_max` \[N·m\].
        limit: f64,
    },
    /// The interaction of force and moment reached 1 (both limits given).
    Interaction {
        /// The transmitted force `F` \[N\].
        force: f64,
        /// The transmitted moment `M` \[N·m\].
        moment: f64,
        /// `(F/F_max)^a + (M/M_max)^b` (≥ 1; dimensionless).
        value: f64,
    },
    /// The dissipated energy reached its limit.
    DissipatedEnergy {
        /// The dissipated energy `D` \[J\].
        energy: f64,
        /// `D_max` \[J\].
        limit: f64,
    },
}

impl fmt::Display for BreakCause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BreakCause::Force { force, limit } => write!(
                f,
                "transmitted force {} N reached its limit {} N",
                fig(*force),
                fig(*limit)
            ),
            BreakCause::Moment { moment, limit } => write!(
                f,
                "transmitted moment {} N·m reached its limit {} N·m",
                fig(*moment),
                fig(*limit)
            ),
            BreakCause::Interaction {
                force,
                moment,
                value,
            } => write!(
                f,
                "force {} N and moment {} N·m: interaction {:.4} ≥ 1",
                fig(*force),
                fig(*moment),
                value
            ),
            BreakCause::DissipatedEnergy { energy, limit } => write!(
                f,
                "dissipated energy {} J reached its limit {} J",
                fig(*energy),
                fig(*limit)
            ),
        }
    }
}

impl BreakCriterion {
    /// Fails when the transmitted force reaches `limit` \[N\].
    pub fn force(limit: f64) -> Self {
        BreakCriterion {
            force: limit,
            ..Default::default()
        }
    }

    /// Fails when the transmitted moment reaches `limit` \[N·m\].
    pub fn moment(limit: f64) -> Self {
        BreakCriterion {
            moment: limit,
            ..Default::default()
        }
    }

    /// Fails when `(F/force)² + (M/moment)² ≥ 1` (set the exponents with
    /// [`Self::with_exponents`]).
    pub fn force_and_moment(force: f64, moment: f64) -> Self {
        BreakCriterion {
            force,
            moment,
            ..Default::default()
        }
    }

    /// Fails when the law has dissipated `limit` \[J\].
    pub fn dissipated_energy(limit: f64) -> Self {
        BreakCriterion {
            dissipated_energy: limit,
            ..Default::default()
        }
    }

    /// The interaction exponents `a` (force) and `b` (moment), both > 0.
    #[must_use]
    pub fn with_exponents(mut self, a: f64, b: f64) -> Self {
        self.force_exponent = a;
        self.moment_exponent = b;
        self
    }

    /// Adds (or replaces) the dissipated-energy limit \[J\].
    #[must_use]
    pub fn with_dissipated_energy(mut self, limit: f64) -> Self {
        self.dissipated_energy = limit;
        self
    }

    /// Every value finite, limits ≥ 0 (0: none) with at least one > 0, exponents > 0. The
    /// error names the field (`force`, `moment`, `force_exponent`, `moment_exponent`,
    /// `dissipated_energy`).
    pub fn validate(&self) -> Result<(), PropertyError> {
        for (field, v) in [
            ("force", self.force),
            ("moment", self.moment),
            ("dissipated_energy", self.dissipated_energy),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(PropertyError::field(
                    field,
                    v,
                    "a finite limit ≥ 0 (0: no such limit)",
                ));
            }
        }
        for (field, v) in [
            ("force_exponent", self.force_exponent),
            ("moment_exponent", self.moment_exponent),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(PropertyError::field(field, v, "a finite exponent > 0"));
            }
        }
        if self.force == 0.0 && self.moment == 0.0 && self.dissipated_energy == 0.0 {
            return Err(PropertyError::field(
                "force",
                0.0,
                "at least one limit > 0 among force, moment and dissipated_energy (a \
                 criterion without a limit is never met: give none for an unbreakable joint)",
            ));
        }
        Ok(())
    }

    /// Whether and why a joint that transmitted the force `force` \[N\] and the moment
    /// `moment` \[N·m\] (magnitudes) and dissipated `dissipated` \[J\] fails
    /// (docs/breakable.md §2); `None`: it holds. The interaction `Σ (x/x_max)^e` takes the
    /// terms of the limits that are given; its cause is [`BreakCause::Force`] or
    /// [`BreakCause::Moment`] when only one is, [`BreakCause::Interaction`] when both are.
    /// The dissipated energy is checked after the load.
    ///
    /// An infinite force, moment, interaction or energy (a magnitude whose components' squares
    /// overflowed f64: a joint with `Kn = 1e300`) is reported as `f64::MAX`, saturated as
    /// the law's values are, not as `inf`.
    pub fn check(&self, force: f64, moment: f64, dissipated: f64) -> Option<BreakCause> {
        let (f, m) = (saturated(force.abs()), saturated(moment.abs()));
        let dissipated = saturated(dissipated);
        let term = |x: f64, limit: f64, e: f64| (x / limit).powf(e);
        match (self.force > 0.0, self.moment > 0.0) {
            (true, false) if f >= self.force => {
                return Some(BreakCause::Force {
                    force: f,
                    limit: self.force,
                })
            }
            (false, true) if m >= self.moment => {
                return Some(BreakCause::Moment {
                    moment: m,
                    limit: self.moment,
                })
            }
            (true, true) => {
                let value = saturated(
                    term(f, self.force, self.force_exponent)
                        + term(m, self.moment, self.moment_exponent),
                );
                if value >= 1.0 {
                    return Some(BreakCause::Interaction {
                        force: f,
                        moment: m,
                        value,
                    });
                }
            }
            _ => {}
        }
        (self.dissipated_energy > 0.0 && dissipated >= self.dissipated_energy).then_some(
            BreakCause::DissipatedEnergy {
                energy: dissipated,
                limit: self.dissipated_energy,
            },
        )
    }
}

/// `x`, or `f64::MAX` for `+∞` (NaN unchanged: it breaks nothing).
fn saturated(x: f64) -> f64 {
    if x == f64::INFINITY {
        f64::MAX
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn force_limit_alone_whatever_the_exponent() {
        let c = BreakCriterion::force(1000.0).with_exponents(3.0, 2.0);
        assert_eq!(
            c.check(999.999, 1e9, 0.0),
            None,
            "no moment limit: M ignored"
        );
        assert_eq!(
            c.check(-1000.0, 0.0, 0.0),
            Some(BreakCause::Force {
                force: 1000.0,
                limit: 1000.0
            })
        );
    }

    #[test]
    fn moment_limit_alone() {
        let c = BreakCriterion::moment(50.0);
        assert_eq!(c.check(1e9, 49.9, 0.0), None);
        assert_eq!(
            c.check(0.0, 50.5, 0.0),
            Some(BreakCause::Moment {
                moment: 50.5,
                limit: 50.0
            })
        );
    }

    #[test]
    fn interaction_at_exactly_one() {
        // a = b = 2: (600/1000)² + (40/50)² = 0.36 + 0.64 = 1 (1.0 in f64 too)
        let c = BreakCriterion::force_and_moment(1000.0, 50.0);
        match c.check(600.0, 40.0, 0.0) {
            Some(BreakCause::Interaction { value, .. }) => {
                assert!((value - 1.0).abs() < 1e-15, "{value}")
            }
            other => panic!("{other:?}"),
        }
        // just below: (599.9/1000)² + 0.64 = 0.99988 holds
        assert_eq!(c.check(599.9, 40.0, 0.0), None);
        // exact binary fractions: (0.5)^1 + (0.25/0.5)^1 = 1 with a = b = 1
        let lin = BreakCriterion::force_and_moment(2.0, 0.5).with_exponents(1.0, 1.0);
        assert_eq!(
            lin.check(1.0, 0.25, 0.0),
            Some(BreakCause::Interaction {
                force: 1.0,
                moment: 0.25,
                value: 1.0
            })
        );
        assert_eq!(lin.check(1.0, 0.2499, 0.0), None);
        // a = 4, b = 1: (0.5)^4 + 0.9 = 0.9625 holds; (0.75)^4 + 0.9 = 1.216 fails
        let mixed = BreakCriterion::force_and_moment(1.0, 1.0).with_exponents(4.0, 1.0);
        assert_eq!(mixed.check(0.5, 0.9, 0.0), None);
        match mixed.check(0.75, 0.9, 0.0) {
            Some(BreakCause::Interaction { value, .. }) => {
                assert!((value - 1.21640625).abs() < 1e-12, "{value}")
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn dissipated_energy_limit() {
        let c = BreakCriterion::dissipated_energy(12.5);
        assert_eq!(c.check(1e9, 1e9, 12.4), None, "no load limit");
        assert_eq!(
            c.check(0.0, 0.0, 12.5),
            Some(BreakCause::DissipatedEnergy {
                energy: 12.5,
                limit: 12.5
            })
        );
        // a load limit met first is the cause given
        let both = BreakCriterion::force(10.0).with_dissipated_energy(1.0);
        assert!(matches!(
            both.check(10.0, 0.0, 5.0),
            Some(BreakCause::Force { .. })
        ));
        assert!(matches!(
            both.check(9.0, 0.0, 5.0),
            Some(BreakCause::DissipatedEnergy { .. })
        ));
    }

    #[test]
    fn validate_names_the_field() {
        let field_of = |c: BreakCriterion| match c.validate() {
            Err(PropertyError::InvalidField { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        assert_eq!(field_of(BreakCriterion::force(f64::NAN)), "force");
        assert_eq!(field_of(BreakCriterion::moment(-1.0)), "moment");
        assert_eq!(
            field_of(BreakCriterion::force(1.0).with_dissipated_energy(f64::INFINITY)),
            "dissipated_energy"
        );
        assert_eq!(
            field_of(BreakCriterion::force(1.0).with_exponents(0.0, 2.0)),
            "force_exponent"
        );
        assert_eq!(
            field_of(BreakCriterion::force(1.0).with_exponents(2.0, f64::NAN)),
            "moment_exponent"
        );
        assert_eq!(field_of(BreakCriterion::default()), "force");
        assert!(BreakCriterion::moment(3.0).validate().is_ok());
    }

    #[test]
    fn display_names_the_values() {
        let c = BreakCause::Force {
            force: 12000.0,
            limit: 10000.0,
        };
        assert_eq!(
            c.to_string(),
            format!(
                "transmitted force {} N reached its limit {} N",
                fig(12000.0),
                fig(10000.0)
            )
        );
    }
}
