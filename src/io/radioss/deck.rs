//! What a Radioss deck reads into: [`RadiossDeck`] and its entries (KJOINT2 properties,
//! functions, fixed skews, time sensors, unit systems), with the values as written and the
//! conversions into SI.

use std::collections::BTreeMap;

use super::skew::{cross, normalize};
use super::Notice;
use crate::io::units::{Quantity, UnitSystem};
use crate::law::{Curve, KjointProperty};

/// The ids of the functions attached to one DOF (`None` = no function).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DofFunctionIds {
    /// `fct_K`: force (moment) vs displacement (angle).
    pub stiffness: Option<u32>,
    /// `fct_C`: force (moment) vs velocity (angular velocity).
    pub viscosity: Option<u32>,
    /// `fct_FF` / `fct_FM`: friction force (moment) vs displacement (angle).
    pub friction: Option<u32>,
}

/// One `/PROP/TYPE45` (`/PROP/KJOINT2`) block.
#[derive(Debug, Clone, PartialEq)]
pub struct PropertyEntry {
    /// `prop_ID`.
    pub id: u32,
    /// `prop_title` (trailing blanks removed).
    pub title: String,
    /// Line of the keyword.
    pub line: usize,
    /// The keyword as written, e.g. `/PROP/TYPE45/2/2`.
    pub keyword: String,
    /// `unit_ID` of the keyword (`None` = the values are in `/BEGIN`'s input units).
    pub unit_id: Option<u32>,
    /// The unit system of the values: `unit_id`'s, else `/BEGIN`'s input units (`None` =
    /// SI).
    pub unit: Option<UnitSystem>,
    /// The property with the values as written in the deck (functions resolved).
    pub property: KjointProperty,
    /// The property converted into SI (kg, m, s) with
    /// [`crate::io::units::property_to_si`]; equal to `property` without unit. `ScF` with
    /// `Kn > 0` (an area) is taken from `/BEGIN`'s work units, as Radioss reads it.
    pub property_si: KjointProperty,
    /// `Skew_ID1` (`None` = from the anchors' geometry).
    pub skew1: Option<u32>,
    /// `Skew_ID2` (`None` = no initial relative rotation). `None` on types 5 to 8
    /// (universal, translational, Oldham, fixed), which Radioss gives no initial rotation:
    /// it ignores their `Skew_ID2` (warning 1134), and so does the reader, with a notice.
    pub skew2: Option<u32>,
    /// The function ids of each DOF, indexed like [`KjointProperty::dofs`].
    pub function_ids: [DofFunctionIds; 6],
}

/// One `/FUNCT` block.
#[derive(Debug, Clone, PartialEq)]
pub struct Function {
    /// `fct_ID`.
    pub id: u32,
    /// Title.
    pub title: String,
    /// Line of the keyword.
    pub line: usize,
    /// `unit_ID` of the keyword (checked to exist; values are interpreted in the unit
    /// system of the referencing property).
    pub unit_id: Option<u32>,
    /// The points as written.
    pub curve: Curve,
}

/// One `/SKEW/FIX` block: a fixed frame given by its origin and its Y' and Z' axes.
#[derive(Debug, Clone, PartialEq)]
pub struct SkewFix {
    /// `skew_ID`.
    pub id: u32,
    /// Title.
    pub title: String,
    /// Line of the keyword.
    pub line: usize,
    /// `unit_ID` of the keyword.
    pub unit_id: Option<u32>,
    /// The unit system of the origin: `unit_id`'s, else `/BEGIN`'s input units (`None` =
    /// SI).
    pub unit: Option<UnitSystem>,
    /// Origin `Ox Oy Oz` in the deck's length unit.
    pub origin: [f64; 3],
    /// `X1 Y1 Z1`: direction of the Y' axis (any length).
    pub y_axis: [f64; 3],
    /// `X2 Y2 Z2`: direction of the Z' axis (any length, need not be orthogonal to Y').
    pub z_axis: [f64; 3],
}

impl SkewFix {
    /// The orthonormal axes `[X', Y', Z']` as Radioss builds them: `Y'` normalised,
    /// `X' = Y'×Z'` normalised, then `Z' = X'×Y'`.
    pub fn axes(&self) -> [[f64; 3]; 3] {
        // Checked non-degenerate when the deck is read.
        let y = normalize(self.y_axis).unwrap_or([0.0, 1.0, 0.0]);
        let z = normalize(self.z_axis).unwrap_or([0.0, 0.0, 1.0]);
        let x = normalize(cross(y, z)).unwrap_or([1.0, 0.0, 0.0]);
        [x, y, cross(x, y)]
    }

    /// The origin in metres.
    pub fn origin_si(&self) -> [f64; 3] {
        let f = self.unit.map_or(1.0, |u| u.factor(Quantity::Length));
        self.origin.map(|v| v * f)
    }
}

/// One `/SENSOR/TIME` block: active from `t = Tdelay` on.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeSensor {
    /// `sens_ID`.
    pub id: u32,
    /// Title.
    pub title: String,
    /// Line of the keyword.
    pub line: usize,
    /// `unit_ID` of the keyword.
    pub unit_id: Option<u32>,
    /// The unit system of `Tdelay`: `unit_id`'s, else `/BEGIN`'s input units (`None` = SI).
    pub unit: Option<UnitSystem>,
    /// `Tdelay` in the deck's time unit (≥ 0).
    pub tdelay: f64,
}

impl TimeSensor {
    /// `Tdelay` in seconds.
    pub fn tdelay_si(&self) -> f64 {
        self.tdelay * self.unit.map_or(1.0, |u| u.factor(Quantity::Time))
    }
}

/// One `/UNIT` block.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitEntry {
    /// `unit_ID`.
    pub id: u32,
    /// Title.
    pub title: String,
    /// Line of the keyword.
    pub line: usize,
    /// The mass, length and time names as written (blank = SI base unit).
    pub names: [String; 3],
    /// The unit system.
    pub system: UnitSystem,
}

/// The input unit system of the `/BEGIN` block: the unit of every value whose keyword has
/// no `/unit_ID`.
#[derive(Debug, Clone, PartialEq)]
pub struct InputUnits {
    /// Line of the `/BEGIN` keyword.
    pub line: usize,
    /// The mass, length and time names in force: the input unit as written, else the work
    /// unit (blank = SI base unit).
    pub names: [String; 3],
    /// The unit system.
    pub system: UnitSystem,
}

/// Everything read from a deck.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RadiossDeck {
    /// The file name given to the reader.
    pub file: String,
    /// KJOINT2 properties by `prop_ID`.
    pub properties: BTreeMap<u32, PropertyEntry>,
    /// Functions by `fct_ID`.
    pub functions: BTreeMap<u32, Function>,
    /// Fixed skews by `skew_ID`.
    pub skews: BTreeMap<u32, SkewFix>,
    /// Time sensors by `sens_ID`.
    pub sensors: BTreeMap<u32, TimeSensor>,
    /// Unit systems by `unit_ID`.
    pub units: BTreeMap<u32, UnitEntry>,
    /// The input units of `/BEGIN` (`None` without one: SI).
    pub input_units: Option<InputUnits>,
    /// Skipped blocks, defaulted cards and other remarks, in file order.
    pub notices: Vec<Notice>,
}

impl RadiossDeck {
    /// The property block `id`.
    pub fn property(&self, id: u32) -> Option<&PropertyEntry> {
        self.properties.get(&id)
    }

    /// The property `id` converted into SI (kg, m, s): see
    /// [`crate::io::units::property_to_si`] for the factors.
    pub fn property_si(&self, id: u32) -> Option<&KjointProperty> {
        self.properties.get(&id).map(|p| &p.property_si)
    }

    /// The unit system `id`.
    pub fn unit_system(&self, id: u32) -> Option<UnitSystem> {
        self.units.get(&id).map(|u| u.system)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skew_axes() {
        let s = SkewFix {
            id: 1,
            title: String::new(),
            line: 1,
            unit_id: None,
            unit: None,
            origin: [0.0; 3],
            y_axis: [0.0, 2.0, 0.0],
            z_axis: [0.0, 1.0, 3.0],
        };
        let [x, y, z] = s.axes();
        assert_eq!(x, [1.0, 0.0, 0.0]);
        assert_eq!(y, [0.0, 1.0, 0.0]);
        assert_eq!(z, [0.0, 0.0, 1.0]);
    }
}
