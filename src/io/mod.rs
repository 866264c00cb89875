//! Input readers: parsing of solver input files into the crate's property types, and of
//! robot descriptions into bodies and joint definitions.
//!
//! Nothing here steps the simulation. The robot readers [`urdf`] and [`mjcf`] describe a
//! robot without touching any world; [`robot`] inserts a description into one.
//!
//! - [`radioss`]: Radioss 2019+ fixed-width decks (`/PROP/TYPE45` = `/PROP/KJOINT2`,
//!   `/FUNCT`, `/UNIT`, `/SKEW/FIX`, `/SENSOR/TIME`).
//! - [`riser`]: riser-analysis decks (`*FLEXJOINT`, `*SPRINGPRO`, `*FLEXPROADD`).
//! - [`urdf`]: URDF robots with KJOINT2 joints (`rapier3d-urdf` for bodies and colliders).
//! - [`mjcf`]: MuJoCo MJCF robots with KJOINT2 joints (`rapier3d-mjcf`), with the URDF
//!   reader's options, handles and errors.
//! - [`robot`]: the robot description both readers produce, its insertion into a world and a
//!   joint set, and the handles of an inserted robot.
//! - [`visual`]: meshes for drawing (a link's `<visual>` meshes), shared with [`crate::output`].
//! - [`diagnostic`]: what both deck readers report: [`DeckError`] (file, line, field,
//!   what was expected), [`Notice`], and the number parsers of the deck formats.
//! - [`units`]: unit systems and the explicit conversion of a property into SI.
//! - [`input`]: the one function that reads every input file, within the size cap
//!   [`MAX_INPUT_BYTES`] (256 MiB).

pub mod diagnostic;
mod fuse;
pub mod input;
mod loaded;
pub mod mjcf;
pub mod radioss;
pub mod riser;
pub mod robot;
pub mod units;
pub mod urdf;
pub mod visual;

pub use input::{
    read_input, read_input_text, read_input_with_cap, InputError, InputErrorKind, MAX_INPUT_BYTES,
};
pub use radioss::{
    DeckError, DeckErrorKind, DofFunctionIds, Function, InputUnits, Notice, PropertyEntry,
    RadiossDeck, SkewFix, TimeSensor, UnitEntry,
};
pub use units::{property_to_si, Quantity, UnitSystem};
