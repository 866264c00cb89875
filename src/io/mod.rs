//! Input readers: pure parsing of solver input files into the crate's property types.
//!
//! Nothing here simulates or touches rapier.
//!
//! - [`radioss`]: Radioss 2019+ fixed-width decks (`/PROP/TYPE45` = `/PROP/KJOINT2`,
//!   `/FUNCT`, `/UNIT`, `/SKEW/FIX`, `/SENSOR/TIME`).
//! - [`riser`]: riser-analysis decks (`*FLEXJOINT`, `*SPRINGPRO`, `*FLEXPROADD`).
//! - [`units`]: unit systems and the explicit conversion of a property into SI.

pub mod radioss;
pub mod riser;
pub mod units;

pub use radioss::{
    parse_str, read_file, DeckError, DeckErrorKind, DofFunctionIds, Function, Notice,
    PropertyEntry, RadiossDeck, SkewFix, TimeSensor, UnitEntry,
};
pub use units::{property_to_si, Quantity, UnitSystem};
