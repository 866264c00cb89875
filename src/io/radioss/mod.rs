//! Reader for Radioss input decks (2019+ fixed-width format): KJOINT2 properties and the
//! functions, skews, time sensors and unit systems they reference.
//!
//! This is a pure parser: it builds [`KjointProperty`] values (as written and converted
//! into SI) and never simulates anything.
//!
//! # Deck format
//!
//! - A block starts with a keyword line beginning with `/` in column 1 and runs until the
//!   next such line. Its cards are its non-comment lines.
//! - Lines beginning with `#` or `$` are comments, except `#ENDDATA`, which ends the data
//!   like `/END` does (anything after is ignored). `#include` lines are not followed
//!   (a notice says so).
//! - Fields are fixed-width, counted in characters: integers in 10 columns, reals in 20.
//!   A blank field, or a field beyond the end of a short line, is 0. Columns after the
//!   last field of a card are ignored.
//! - Reals may be written `100`, `-100`, `.52`, `5.`, `1e3`, `1.5E+02`, `1.5d3` / `1.5D3`
//!   (Fortran double) or `1.5+3` (Fortran exponent without letter). `nan`, `inf` and
//!   values that overflow are refused. Integers are plain (`+`/`-` and digits).
//! - Keywords are matched case-insensitively.
//! - Any other block of Radioss (`/NODE`, `/PART`, other `/PROP` types, `/SKEW/MOV`, ...)
//!   is skipped with a [`Notice`]. A keyword that Radioss does not have (its first part,
//!   `/FUNC/7` for `/FUNCT/7`, is none of OpenRadioss' keywords) is an error at its line,
//!   as it is in OpenRadioss, naming the keyword it most likely means
//!   ([`DeckErrorKind::UnknownKeyword`]): skipped, the block's id went missing and the error
//!   came later, at the line that referenced it. A `//` keyword (`//SUBMODEL`) is skipped
//!   with a notice.
//!
//! # Blocks that are read
//!
//! `/PROP/TYPE45/prop_ID[/unit_ID]` or `/PROP/KJOINT2/prop_ID[/unit_ID]`:
//!
//! ```text
//! prop_title
//! Type(10) Kn(20) ScF(20) Cr(20) sens_ID(10) Skew_ID1(10) Skew_ID2(10)
//! then for each free DOF of the type, in the order dx, dy, dz, rx, ry, rz:
//! K(20) fct_K(10) SD-(20) SD+(20) Icomb(10)      (SA-, SA+ in rad for rotations)
//! C(20) fct_C(10)
//! Kf(20) FF(20) fct_FF(10)                        (FM, fct_FM for rotations)
//! ```
//!
//! When the block ends early, the missing DOF cards take their defaults (all zero) and a
//! notice says so; extra non-blank cards are ignored with a notice. `Icomb` must be 0 or 1.
//! Zero ids mean "none". The property is checked with [`KjointProperty::validate`].
//!
//! `/FUNCT/fct_ID[/unit_ID]`: a title, then lines of `X(20) Y(20)`, optionally a second
//! pair `X(20) Y(20)` on the same line (columns 41-80). Blank lines are skipped. Abscissas
//! must increase strictly, and there must be at least two points (a constant is two points
//! with the same `Y`; OpenRadioss reads one with a warning, docs/radioss_differences.md). A
//! function's values are interpreted in the unit system of the property that references it
//! (its own `unit_ID` is only checked to exist).
//!
//! `/BEGIN`: the run name, `Invers Irun`, then the input and the work unit systems, each
//! `M_unit(20) L_unit(20) T_unit(20)` as in `/UNIT`. The values of every keyword without a
//! `/unit_ID` are in the input units ([`InputUnits`]) and are converted into SI (with a
//! notice when they are not SI); a blank input unit is the work unit, a blank work unit the
//! SI base unit, as in Radioss. The work units serve those defaults and are the units of
//! `ScF` when `Kn > 0` (an area, `KR = Kn·max(ScF, L0²)`, which Radioss reads in its work
//! units whatever the property's units; its default 10 too); the crate computes in SI. A
//! second `/BEGIN` is an error.
//!
//! `/UNIT/unit_ID`: a title, then `M_unit(20) L_unit(20) T_unit(20)`, unit names such as
//! `kg mm ms` (see [`super::units::mass_unit`] and friends); a blank name is the SI base
//! unit (with a notice).
//!
//! `/SKEW/FIX/skew_ID[/unit_ID]`: a title, then three cards of three reals (20 columns):
//! the origin `Ox Oy Oz`, the **Y'** axis `X1 Y1 Z1` and the **Z'** axis `X2 Y2 Z2`
//! (Radioss computes `X' = Y'×Z'`, then `Z' = X'×Y'`; see [`SkewFix::axes`]). Y' must be
//! non-zero and Z' not parallel to it.
//!
//! `/SENSOR/TIME/sens_ID[/unit_ID]`: a title, then `Tdelay(20)`: the sensor activates at
//! `t = Tdelay` (≥ 0).
//!
//! References (`fct_*`, `sens_ID`, `Skew_ID1/2`, `unit_ID`) are resolved after the whole
//! deck is read, so blocks may come in any order. Ids must be unique per kind.
//!
//! Every error is a [`DeckError`] naming the file, the line, the field and what was
//! expected; every remark a [`Notice`] (both from [`super::diagnostic`], shared with the
//! riser reader).
//!
//! # Files
//!
//! - `mod.rs`: this documentation and the entry points [`RadiossDeck::from_file`] and
//!   [`RadiossDeck::from_str`].
//! - `deck.rs`: what a deck reads into ([`RadiossDeck`] and its entries).
//! - `fields.rs`: fixed-width columns, numbers and ids of a card, and the errors naming them.
//! - `blocks.rs`: splitting the text into keyword blocks (comments, `/END`, `#ENDDATA`).
//! - `keywords.rs`: the keywords of OpenRadioss, to tell a misspelt keyword from one the
//!   reader skips.
//! - `reader.rs`: the reader's state, the dispatch of a block to its parser, skipped blocks,
//!   and what every block opens with (the keyword line's ids, a unique id, the title).
//! - `kjoint2.rs`, `funct.rs`, `unit.rs`, `skew.rs`, `sensor.rs`: one block parser each.
//! - `finish.rs`: resolving references once the whole deck is read, validation and SI.
//!
//! [`KjointProperty`]: crate::law::KjointProperty
//! [`KjointProperty::validate`]: crate::law::KjointProperty::validate

mod blocks;
mod deck;
mod fields;
mod finish;
mod funct;
mod keywords;
mod kjoint2;
mod reader;
mod sensor;
mod skew;
mod unit;

use std::path::Path;

pub use super::diagnostic::{DeckError, DeckErrorKind, Notice};
pub use deck::{
    DofFunctionIds, Function, InputUnits, PropertyEntry, RadiossDeck, SkewFix, TimeSensor,
    UnitEntry,
};

impl RadiossDeck {
    /// Reads a deck file (within the size cap [`super::MAX_INPUT_BYTES`]); errors and
    /// notices name the file by `path` as given. Invalid UTF-8 is replaced (titles may be
    /// garbled) with a notice.
    pub fn from_file(path: impl AsRef<Path>) -> Result<RadiossDeck, DeckError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let bytes = super::input::read_input(path).map_err(|e| DeckError::io(name.as_str(), &e))?;
        match String::from_utf8(bytes) {
            Ok(text) => RadiossDeck::from_str(&text, &name),
            Err(e) => {
                let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
                let mut deck = RadiossDeck::from_str(&text, &name)?;
                let message = "the file is not valid UTF-8: invalid bytes were replaced by U+FFFD";
                deck.notices.insert(0, Notice::new(name, 0, message));
                Ok(deck)
            }
        }
    }

    /// Parses the text of a deck; `file` is the name used in errors and notices. Never
    /// panics.
    pub fn from_str(text: &str, file: &str) -> Result<RadiossDeck, DeckError> {
        reader::Reader::read(text, file)
    }
}
