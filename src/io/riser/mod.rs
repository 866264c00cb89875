//! Reader of riser-analysis flex joint decks: the keywords `*FLEXJOINT`, `*SPRINGPRO` and
//! `*FLEXPROADD` (spec `flex_joint.md`).
//!
//! # Format
//!
//! - Free format: values separated by whitespace, one record per line.
//! - A line whose first non-blank character is `*` starts a keyword block; the keyword is
//!   the first word of the line (case-insensitive), the rest of the line is ignored.
//!   Keywords other than the three below are skipped with a [`Notice`], together with
//!   their data lines (a riser-analysis deck has many keywords this reader does not read).
//!   A keyword close to one of the three is an error at its line naming it
//!   ([`DeckErrorKind::UnknownKeyword`]): within one edit (two for words of 5 characters or
//!   more, `*FLEXPROAD`, `*SPIRNGPRO`) or one of them with more after it (`*FLEXJOINTS`).
//!   Skipped, its records went missing without a word. An error of a missing law or record
//!   names the keywords skipped as unknown, the likely cause (`*SPRING` at line 3: a
//!   misspelt `*SPRINGPRO`?).
//! - A line whose first non-blank character is `c` or `C` is a comment; blank lines are
//!   ignored.
//! - Numbers are Rust/Fortran reals (`1e9`, `0.`, `1.5D+3`); integer fields also accept an
//!   integral real (`3.`). NaN and infinities are rejected.
//!
//! | keyword | record | units |
//! |---|---|---|
//! | `*SPRINGPRO` | `INDEX NPAIRS x1 y1 … xN yN` | angle \[rad\], moment \[N·m\] |
//! | `*FLEXPROADD` | `IMAT Ktor IFLAG Kdyn_ini Kdyn_lim Angle_lim Teta CP` | N·m/rad, rad, N·m·s/rad |
//! | `*FLEXJOINT` | `NEL JO JE IPRO IMAT LENGTH [IPROT]` | LENGTH \[m\] is read and unused |
//!
//! `IPROT` may be omitted (0). The index 0 means "none" for IPRO, IMAT and IPROT. The
//! blocks may come in any order: the indices of `*FLEXJOINT` are resolved once the whole
//! deck is read. Only `IFLAG = 1` is accepted. A non-zero `Teta` is read, kept and
//! ignored, with a warning notice; `Ktor` given together with IPROT ≠ 0 is ignored, with a
//! notice.
//!
//! Every error names the file, the line (1-based), the keyword, the field and what was
//! expected ([`DeckError`], shared with the Radioss reader in [`super::diagnostic`]). The
//! reader never panics, whatever the input.
//!
//! # Files
//!
//! - `mod.rs`: this documentation and the entry points [`RiserDeck::from_file`] and
//!   [`RiserDeck::from_str`].
//! - `deck.rs`: what a deck reads into ([`RiserDeck`] and its records).
//! - `record.rs`: the values of one record line, and the errors naming them.
//! - `reader.rs`: the line loop: comments, keywords, skipped blocks, dispatch of a record.
//! - `springpro.rs`, `flexproadd.rs`, `flex_joint.rs`: one keyword each (`flex_joint.rs`
//!   also resolves the elements' indices once the deck is read).

mod deck;
mod flex_joint;
mod flexproadd;
mod reader;
mod record;
mod springpro;

use std::path::Path;

pub use super::diagnostic::{DeckError, DeckErrorKind, Notice};
pub use deck::{FlexJointElement, FlexProAddRecord, RiserDeck, SpringPro};

impl RiserDeck {
    /// Reads (within the size cap [`super::MAX_INPUT_BYTES`]) and resolves a deck file;
    /// errors and notices name the file by `path` as given. See the module documentation
    /// for the format.
    pub fn from_file(path: impl AsRef<Path>) -> Result<RiserDeck, DeckError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text =
            super::input::read_input_text(path).map_err(|e| DeckError::io(file.as_str(), &e))?;
        RiserDeck::from_str(&text, &file)
    }

    /// Parses and resolves the text of a deck; `file` names it in errors and notices. See
    /// the module documentation for the format.
    pub fn from_str(text: &str, file: &str) -> Result<RiserDeck, DeckError> {
        reader::Reader::read(text, file)
    }
}
