//! Unit systems of Radioss `/UNIT` blocks and the explicit conversion of a KJOINT2
//! property into SI (kg, m, s).
//!
//! A [`UnitSystem`] holds the size of the deck's mass, length and time units expressed in
//! kg, m and s (e.g. kg-mm-ms is `mass = 1`, `length = 1e-3`, `time = 1e-3`). Every
//! quantity of the joint law is a product `M^a·L^b·T^c` ([`Quantity::exponents`]), and a
//! value written in the deck is multiplied by `mass^a · length^b · time^c` to get SI.
//! Angles are radians in every system and are never converted.
//!
//! Conversion factors for kg-mm-ms (the unit system of the Radioss examples):
//!
//! | quantity | dimension | factor to SI |
//! |---|---|---|
//! | length, stop `SD±` | L | 1e-3 (mm → m) |
//! | force, friction `FF` | M·L·T⁻² | 1e3 (kg·mm/ms² = 1000 N) |
//! | moment, friction `FM` | M·L²·T⁻² | 1 (kg·mm²/ms² = 1 N·m) |
//! | stiffness `Kn`, `K`, `Kf` (translation) | M·T⁻² | 1e6 (N/mm·1000 = 1e6 N/m) |
//! | stiffness `K`, `Kf` (rotation) | M·L²·T⁻² | 1 (N·m/rad) |
//! | viscosity `C` (translation) | M·T⁻¹ | 1e3 (N·s/m) |
//! | viscosity `C` (rotation) | M·L²·T⁻¹ | 1e-3 (N·m·s/rad) |
//! | velocity (function abscissa) | L·T⁻¹ | 1 (mm/ms = m/s) |
//! | angular velocity (function abscissa) | T⁻¹ | 1e3 (rad/ms → rad/s) |
//! | `ScF` when `Kn > 0` | L² | 1e-6 (mm² → m²); in a Radioss deck, from `/BEGIN`'s work units |
//! | time (sensor delay) | T | 1e-3 |
//! | angle, stop `SA±`, `Cr`, `ScF` when `Kn = 0` | — | 1 |

use crate::error::PropertyError;
use crate::law::{
    ConnectorLaw, Curve, Dof, DofLaw, FlexJointConnector, FlexJointLaw, KjointProperty,
};

/// A mechanical unit system: the size of its mass, length and time units in kg, m and s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitSystem {
    /// Size of the mass unit in kg (`g` → 1e-3).
    pub mass: f64,
    /// Size of the length unit in m (`mm` → 1e-3).
    pub length: f64,
    /// Size of the time unit in s (`ms` → 1e-3).
    pub time: f64,
}

/// The physical quantities that appear in a KJOINT2 property, with their dimensions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Pure number (`Cr`, function scales, `ScF` with `Kn = 0`).
    Dimensionless,
    /// Angle in rad (rotational stops `SA±`, function abscissas of rotations): never converted.
    Angle,
    /// Length \[m\] (translational stops `SD±`, skew origins).
    Length,
    /// Area \[m²\] (`ScF` when `Kn > 0`, since `KR = Kn·max(ScF, L0²)`).
    Area,
    /// Time \[s\] (sensor delays).
    Time,
    /// Velocity [m/s] (abscissa of a translational viscosity function).
    Velocity,
    /// Angular velocity [rad/s] (abscissa of a rotational viscosity function).
    AngularVelocity,
    /// Force \[N\] (`FF`, ordinates of translational functions).
    Force,
    /// Moment [N·m] (`FM`, ordinates of rotational functions).
    Moment,
    /// Translational stiffness [N/m] (`Kn`, `K`, `Kf`).
    Stiffness,
    /// Rotational stiffness [N·m/rad] (`K`, `Kf` of a rotation).
    RotationalStiffness,
    /// Translational viscosity [N·s/m] (`C`).
    Viscosity,
    /// Rotational viscosity [N·m·s/rad] (`C` of a rotation).
    RotationalViscosity,
}

impl Quantity {
    /// Exponents `(a, b, c)` of the dimension `M^a·L^b·T^c`.
    pub fn exponents(self) -> (i32, i32, i32) {
        use Quantity::*;
        match self {
            Dimensionless | Angle => (0, 0, 0),
            Length => (0, 1, 0),
            Area => (0, 2, 0),
            Time => (0, 0, 1),
            Velocity => (0, 1, -1),
            AngularVelocity => (0, 0, -1),
            Force => (1, 1, -2),
            Moment | RotationalStiffness => (1, 2, -2),
            Stiffness => (1, 0, -2),
            Viscosity => (1, 0, -1),
            RotationalViscosity => (1, 2, -1),
        }
    }
}

impl UnitSystem {
    /// kg, m, s.
    pub const SI: UnitSystem = UnitSystem {
        mass: 1.0,
        length: 1.0,
        time: 1.0,
    };

    /// A unit system from the sizes of its units in kg, m and s; `None` unless all three
    /// are finite and > 0.
    pub fn new(mass: f64, length: f64, time: f64) -> Option<UnitSystem> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        (ok(mass) && ok(length) && ok(time)).then_some(UnitSystem { mass, length, time })
    }

    /// A unit system from Radioss unit names (see [`mass_unit`], [`length_unit`],
    /// [`time_unit`]); `None` when a name is not recognised.
    pub fn from_names(mass: &str, length: &str, time: &str) -> Option<UnitSystem> {
        UnitSystem::new(mass_unit(mass)?, length_unit(length)?, time_unit(time)?)
    }

    /// The factor that converts a value of quantity `q` from this system into SI.
    pub fn factor(&self, q: Quantity) -> f64 {
        let (a, b, c) = q.exponents();
        self.mass.powi(a) * self.length.powi(b) * self.time.powi(c)
    }

    /// `value` of quantity `q` converted into SI.
    pub fn to_si(&self, q: Quantity, value: f64) -> f64 {
        value * self.factor(q)
    }
}

/// Parses a positive finite number given in place of a unit name (the unit's size in SI).
fn numeric_unit(name: &str) -> Option<f64> {
    let v: f64 = name.parse().ok()?;
    (v.is_finite() && v > 0.0).then_some(v)
}

/// The names [`mass_unit`] reads, for messages.
pub const MASS_UNITS: &str = "kg, g, mg, Mg (t, ton, tonne), lb";

/// Size in kg of a Radioss mass unit: `kg`, `g`, `mg`, `Mg` / `t` / `ton` / `tonne`
/// (1000 kg), `lb` / `lbm` (0.45359237 kg), or a positive number (the size in kg).
/// Names are case-insensitive except `mg` (milligram) versus `Mg` (megagram).
pub fn mass_unit(name: &str) -> Option<f64> {
    let name = name.trim();
    if name == "Mg" {
        return Some(1e3);
    }
    Some(match name.to_ascii_lowercase().as_str() {
        "kg" => 1.0,
        "g" => 1e-3,
        "mg" => 1e-6,
        "t" | "ton" | "tonne" => 1e3,
        "lb" | "lbm" => 0.453_592_37,
        _ => return numeric_unit(name),
    })
}

/// The names [`length_unit`] reads, for messages.
pub const LENGTH_UNITS: &str = "m, dm, cm, mm, um, km, in, ft";

/// Size in m of a Radioss length unit: `m`, `dm`, `cm`, `mm`, `um` / `mum` (micrometre),
/// `km`, `in` (0.0254 m), `ft` (0.3048 m), or a positive number (the size in m).
/// Case-insensitive.
pub fn length_unit(name: &str) -> Option<f64> {
    let name = name.trim();
    Some(match name.to_ascii_lowercase().as_str() {
        "m" => 1.0,
        "dm" => 1e-1,
        "cm" => 1e-2,
        "mm" => 1e-3,
        "um" | "mum" | "µm" => 1e-6,
        "km" => 1e3,
        "in" => 0.0254,
        "ft" => 0.3048,
        _ => return numeric_unit(name),
    })
}

/// The names [`time_unit`] reads, for messages.
pub const TIME_UNITS: &str = "s, ms, us, ns, min, h";

/// Size in s of a Radioss time unit: `s`, `ms`, `us` / `mus` (microsecond), `ns`, `min`,
/// `h`, or a positive number (the size in s). Case-insensitive.
pub fn time_unit(name: &str) -> Option<f64> {
    let name = name.trim();
    Some(match name.to_ascii_lowercase().as_str() {
        "s" => 1.0,
        "ms" => 1e-3,
        "us" | "mus" | "µs" => 1e-6,
        "ns" => 1e-9,
        "min" => 60.0,
        "h" => 3600.0,
        _ => return numeric_unit(name),
    })
}

/// A copy of `curve` with every abscissa multiplied by `fx` and every ordinate by `fy`.
pub fn scale_curve(curve: &Curve, fx: f64, fy: f64) -> Result<Curve, PropertyError> {
    Curve::new(curve.points().map(|(x, y)| (x * fx, y * fy)))
}

/// Converts a KJOINT2 property written in `units` into SI, field by field:
///
/// - `Kn` is a translational stiffness (M·T⁻²); `Cr` is a pure number.
/// - `ScF` is a pure number when `Kn = 0`, and an area (L²) when `Kn > 0`, because the
///   rotational stiffness is then `KR = Kn·max(ScF, L0²)` with `L0` a length. Its zero
///   default stays 0 and is resolved by the crate in SI (10 m²), as Radioss resolves it in
///   its working unit system. (The Radioss deck reader does not take ScF from here: Radioss
///   reads it in `/BEGIN`'s *work* units whatever the property's units, and so does the
///   reader, [`crate::io::radioss`].)
/// - On a translational DOF: `K` and `Kf` are stiffnesses, `C` a viscosity, `FF` a force,
///   `SD±` lengths. On a rotational DOF: `K` and `Kf` are rotational stiffnesses (a
///   moment per rad), `C` a rotational viscosity, `FM` a moment; `SA±` are angles in rad
///   and are **not** converted.
/// - When a function is attached, the scalar in front of it (`K`, `C`, `FF`/`FM`) is a
///   dimensionless scale and is **not** converted; the function carries the units: its
///   abscissa is a displacement (stiffness, friction: length or angle) or a velocity
///   (viscosity: length/time or 1/time), its ordinate a force or a moment.
///
/// Only free DOFs carry laws; the laws of blocked DOFs are converted too (they are
/// normally all zero). Fails only when a converted value overflows (or a curve does).
pub fn property_to_si(
    p: &KjointProperty,
    units: &UnitSystem,
) -> Result<KjointProperty, PropertyError> {
    use Quantity::*;
    let f = |q: Quantity| units.factor(q);
    let mut out = p.clone();
    out.kn = p.kn * f(Stiffness);
    out.scale_factor = if p.kn > 0.0 {
        p.scale_factor * f(Area)
    } else {
        p.scale_factor
    };
    for dof in Dof::ALL {
        let law: &DofLaw = p.dof(dof);
        let (disp, vel, force, stiff, visc) = if dof.is_rotation() {
            (
                Angle,
                AngularVelocity,
                Moment,
                RotationalStiffness,
                RotationalViscosity,
            )
        } else {
            (Length, Velocity, Force, Stiffness, Viscosity)
        };
        let o = &mut out.dofs[dof.index()];
        match &law.stiffness_curve {
            Some(c) => o.stiffness_curve = Some(scale_curve(c, f(disp), f(force))?),
            None => o.stiffness = law.stiffness * f(stiff),
        }
        o.stop_min = law.stop_min * f(disp);
        o.stop_max = law.stop_max * f(disp);
        match &law.viscosity_curve {
            Some(c) => o.viscosity_curve = Some(scale_curve(c, f(vel), f(force))?),
            None => o.viscosity = law.viscosity * f(visc),
        }
        o.friction_stiffness = law.friction_stiffness * f(stiff);
        match &law.friction_curve {
            Some(c) => o.friction_curve = Some(scale_curve(c, f(disp), f(force))?),
            None => o.friction = law.friction * f(force),
        }
    }
    out.validate()?;
    Ok(out)
}

/// Converts a connector law written in `units` into SI:
///
/// - planar friction: `μ` is a pure number, `R` a length, `F_int` a force, `M_int` a
///   moment, `Kf` a stiffness (force/length), `Kr` a rotational stiffness (moment/rad);
/// - joint friction: `R_pin`, `L`, `R_thrust` lengths, the preload a force, `Kf`, `Kr`
///   stiffnesses (its check against the joint type is [`ConnectorLaw::validate`]'s);
/// - flex joint: the `*SPRINGPRO` laws have angles \[rad\] (not converted) and moments as
///   ordinates; `Ktor`, `Kdyn_ini`, `Kdyn_lim` are rotational stiffnesses, `Angle_lim` and
///   `Teta` angles, `CP` a rotational viscosity; the switch time is a time.
///
/// The result is validated ([`ConnectorLaw::validate`] still checks it against the joint).
pub fn connector_to_si(
    law: &ConnectorLaw,
    units: &UnitSystem,
) -> Result<ConnectorLaw, PropertyError> {
    use Quantity::*;
    let f = |q: Quantity| units.factor(q);
    Ok(match law {
        ConnectorLaw::None => ConnectorLaw::None,
        ConnectorLaw::PlanarFriction(p) => {
            let mut o = *p;
            o.radius = p.radius * f(Length);
            o.internal_force = p.internal_force * f(Force);
            o.internal_moment = p.internal_moment * f(Moment);
            o.stick_stiffness = p.stick_stiffness * f(Stiffness);
            o.stick_rotational_stiffness = p.stick_rotational_stiffness * f(RotationalStiffness);
            o.validate()?;
            ConnectorLaw::PlanarFriction(o)
        }
        ConnectorLaw::JointFriction(j) => {
            let mut o = *j;
            o.pin_radius = j.pin_radius * f(Length);
            o.length = j.length * f(Length);
            o.thrust_radius = j.thrust_radius * f(Length);
            o.preload = j.preload * f(Force);
            o.stick_stiffness = j.stick_stiffness * f(Stiffness);
            o.stick_rotational_stiffness = j.stick_rotational_stiffness * f(RotationalStiffness);
            ConnectorLaw::JointFriction(o)
        }
        ConnectorLaw::FlexJoint(fj) => {
            let curve = |c: &Option<Curve>| -> Result<Option<Curve>, PropertyError> {
                c.as_ref()
                    .map(|c| scale_curve(c, 1.0, f(Moment)))
                    .transpose()
            };
            let dynamic = fj.law.dynamic.map(|mut d| {
                d.torsion_stiffness *= f(RotationalStiffness);
                d.kdyn_ini *= f(RotationalStiffness);
                d.kdyn_lim *= f(RotationalStiffness);
                d.torsion_damping *= f(RotationalViscosity);
                d
            });
            ConnectorLaw::FlexJoint(FlexJointConnector {
                law: FlexJointLaw::new(curve(&fj.law.bending)?, curve(&fj.law.torsion)?, dynamic)?,
                switch_time: fj.switch_time.map(|t| t * f(Time)),
            })
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1.0)
    }

    #[test]
    fn connector_laws_convert_into_si() {
        use crate::law::{FlexProAdd, PlanarFriction};
        // kg, mm, ms: force kN, moment N·m (kN·mm), stiffness kN/mm = 1e6 N/m.
        let u = UnitSystem::from_names("kg", "mm", "ms").unwrap();
        let pf = ConnectorLaw::PlanarFriction(
            PlanarFriction::new(0.3, 50.0, 2.0, 4.0, 5.0, 6.0).unwrap(),
        );
        let ConnectorLaw::PlanarFriction(p) = connector_to_si(&pf, &u).unwrap() else {
            panic!()
        };
        assert_eq!(p.mu, 0.3);
        assert!(close(p.radius, 0.05));
        assert!(close(p.internal_force, 2000.0));
        assert!(close(p.internal_moment, 4.0));
        assert!(close(p.stick_stiffness, 5e6));
        assert!(close(p.stick_rotational_stiffness, 6.0));
        // Flex joint in kg m ms: moments ×1e6, damping N·m·ms/rad ×1e3, time ×1e-3.
        let u = UnitSystem::from_names("kg", "m", "ms").unwrap();
        let d = FlexProAdd {
            torsion_stiffness: 1.0,
            iflag: 1,
            kdyn_ini: 2.0,
            kdyn_lim: 1.0,
            angle_lim: 1e-3,
            teta: 0.0,
            torsion_damping: 3.0,
        };
        let bending = Curve::new([(0.0, 0.0), (0.01, 5.0)]).unwrap();
        let fj = ConnectorLaw::FlexJoint(FlexJointConnector {
            law: FlexJointLaw::new(Some(bending), None, Some(d)).unwrap(),
            switch_time: Some(2000.0),
        });
        let ConnectorLaw::FlexJoint(c) = connector_to_si(&fj, &u).unwrap() else {
            panic!()
        };
        let pts: Vec<_> = c.law.bending.as_ref().unwrap().points().collect();
        assert!(close(pts[1].0, 0.01) && close(pts[1].1, 5e6), "{pts:?}");
        let d = c.law.dynamic.unwrap();
        assert!(
            close(d.kdyn_ini, 2e6) && close(d.kdyn_lim, 1e6) && close(d.torsion_stiffness, 1e6)
        );
        assert!(close(d.angle_lim, 1e-3));
        assert!(close(d.torsion_damping, 3e3));
        assert!(close(c.switch_time.unwrap(), 2.0));
    }

    #[test]
    fn kg_mm_ms_factors() {
        let u = UnitSystem::from_names("kg", "mm", "ms").unwrap();
        assert!(close(u.factor(Quantity::Force), 1e3));
        assert!(close(u.factor(Quantity::Moment), 1.0));
        assert!(close(u.factor(Quantity::Stiffness), 1e6));
        assert!(close(u.factor(Quantity::RotationalStiffness), 1.0));
        assert!(close(u.factor(Quantity::Viscosity), 1e3));
        assert!(close(u.factor(Quantity::RotationalViscosity), 1e-3));
        assert!(close(u.factor(Quantity::Velocity), 1.0));
        assert!(close(u.factor(Quantity::AngularVelocity), 1e3));
        assert!(close(u.factor(Quantity::Length), 1e-3));
        assert!(close(u.factor(Quantity::Area), 1e-6));
        assert!(close(u.factor(Quantity::Time), 1e-3));
        assert_eq!(u.factor(Quantity::Angle), 1.0);
    }

    #[test]
    fn names() {
        assert_eq!(mass_unit("Mg"), Some(1e3));
        assert_eq!(mass_unit("mg"), Some(1e-6));
        assert_eq!(mass_unit("T"), Some(1e3));
        assert_eq!(length_unit("MM"), Some(1e-3));
        assert_eq!(time_unit("mus"), Some(1e-6));
        assert_eq!(time_unit("0.5"), Some(0.5));
        assert_eq!(time_unit("-1"), None);
        assert_eq!(time_unit("inf"), None);
        assert_eq!(length_unit("furlong"), None);
    }
}
