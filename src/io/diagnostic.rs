//! The diagnostics vocabulary shared by the deck readers ([`super::radioss`] and
//! [`super::riser`]): one error type ([`DeckError`], with its typed [`DeckErrorKind`]), one
//! notice type ([`Notice`]), and the one parser of numbers written in a deck
//! ([`parse_real`], [`parse_int`], with the [`NumberSyntax`] of each deck format) together
//! with the one check that a number is finite ([`finite`]).
//!
//! Nothing here reads a file or knows a keyword: the readers say where (file, line, block,
//! field) and these types say what was wrong and what was expected.

use std::fmt;

use thiserror::Error;

use super::input::InputError;
use crate::error::PropertyError;

/// An error in a deck: where it is (file, line, block, field) and what was expected.
///
/// Displayed as `file:line: field `F` of BLOCK: what is wrong` (without ` of BLOCK` when
/// `block` is empty), or `file: what is wrong` when `line` is 0.
#[derive(Debug, Clone, PartialEq, Error)]
pub struct DeckError {
    /// Name of the file: its path as given to `from_file`, or the name given to `from_str`.
    pub file: String,
    /// 1-based line number; 0 means the file as a whole (e.g. it cannot be read).
    pub line: usize,
    /// The block the field belongs to: its keyword as the deck writes it
    /// (`*FLEXJOINT` in a riser deck, `/PROP/TYPE45/2/2` in a Radioss deck), or empty when
    /// the error is not within one block (a reference between blocks, the file itself).
    pub block: String,
    /// The field, as the deck format names it: `Kn`, `rx.SA+`, `dx.fct_K`, `prop_ID` for
    /// Radioss (per-DOF fields prefixed by the DOF); `IPRO`, `NPAIRS`, `x2` for riser
    /// decks; `file` when the file cannot be read.
    pub field: String,
    /// What is wrong, and what was expected (boxed: the error stays small enough to be
    /// returned by every function of the readers).
    pub kind: Box<DeckErrorKind>,
}

impl DeckError {
    /// An error at `line` of `file` in `field` (no block named).
    pub fn new(
        file: impl Into<String>,
        line: usize,
        field: impl Into<String>,
        kind: DeckErrorKind,
    ) -> Self {
        DeckError {
            file: file.into(),
            line,
            block: String::new(),
            field: field.into(),
            kind: Box::new(kind),
        }
    }

    /// The same error, naming its block (`*FLEXJOINT`, `/PROP/TYPE45/2`).
    pub fn in_block(mut self, block: impl Into<String>) -> Self {
        self.block = block.into();
        self
    }

    /// The file `file` cannot be read (line 0, field `file`, kind [`DeckErrorKind::Io`]).
    pub fn io(file: impl Into<String>, e: &InputError) -> Self {
        DeckError::new(file, 0, "file", DeckErrorKind::Io(e.kind.reason()))
    }
}

impl fmt::Display for DeckError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            return write!(f, "{}: {}", self.file, self.kind);
        }
        write!(f, "{}:{}: field `{}`", self.file, self.line, self.field)?;
        if !self.block.is_empty() {
            write!(f, " of {}", self.block)?;
        }
        write!(f, ": {}", self.kind)
    }
}

/// What is wrong in a [`DeckError`]: each variant says what was expected.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DeckErrorKind {
    /// The file cannot be read (the system's reason, or the size cap).
    #[error("cannot read the file: {0}")]
    Io(String),
    /// A field does not hold a number of the expected kind.
    #[error("`{text}` is not {expected}")]
    InvalidNumber {
        /// The field's text.
        text: String,
        /// `"a real number"`, `"an integer"` or `"a non-negative integer"`.
        expected: &'static str,
    },
    /// A real field holds NaN, infinity, or a value that overflows.
    #[error("`{text}` is not a finite number (NaN and infinity are refused)")]
    NotFinite {
        /// The field's text.
        text: String,
    },
    /// A number is outside the values the field accepts.
    #[error("invalid value {value}: expected {expected}")]
    InvalidValue {
        /// The value given.
        value: String,
        /// What the field accepts.
        expected: String,
    },
    /// The Radioss joint type is not 1..=9.
    #[error("unknown joint type {value}: expected 1 (spherical) .. 9 (free){hint}")]
    UnknownJointType {
        /// The number given.
        value: i64,
        /// What the card's layout suggests went wrong, if anything (a title line missing,
        /// the card shifted): `"; ..."` or empty.
        hint: String,
    },
    /// `IFLAG` of a riser `*FLEXPROADD` record other than 1.
    #[error("IFLAG = {0} is not supported: expected 1 (bilinear elasto-plastic)")]
    UnsupportedIflag(i64),
    /// A fixed-width block ends before a required card (the error's line is the keyword
    /// line).
    #[error("missing card `{card}` in {block}")]
    MissingCard {
        /// The card's layout, e.g. `Type Kn ScF Cr sens_ID Skew_ID1 Skew_ID2`.
        card: String,
        /// The block, e.g. `/PROP/TYPE45/2`.
        block: String,
    },
    /// A free-format record ends before this field.
    #[error("missing: the record ends before it")]
    MissingField,
    /// A free-format record has more values than its keyword allows.
    #[error("{found} values found: expected at most {max}")]
    TooManyFields {
        /// Number of values found.
        found: usize,
        /// Maximum number of values.
        max: usize,
    },
    /// `*SPRINGPRO`: the number of values after `NPAIRS` is not `2 × NPAIRS`.
    #[error(
        "NPAIRS = {npairs} but {values} values follow: expected {} values (x y pairs)",
        npairs.saturating_mul(2)
    )]
    PairCount {
        /// `NPAIRS` given.
        npairs: u64,
        /// Number of values found after `NPAIRS`.
        values: usize,
    },
    /// A keyword line lacks its id or has too many parts.
    #[error("invalid keyword line `{text}`: expected {expected}")]
    InvalidKeyword {
        /// The keyword line.
        text: String,
        /// The expected form.
        expected: String,
    },
    /// Two blocks (records) of the same kind have the same id.
    #[error("{what} {id} is defined twice (first at line {first_line})")]
    DuplicateId {
        /// The kind of block: `property`, `function`, `unit system`, `skew`, `sensor` for
        /// Radioss; `*SPRINGPRO law`, `*FLEXPROADD record`, `*FLEXJOINT element` for riser
        /// decks.
        what: &'static str,
        /// The id.
        id: u64,
        /// Line of the first definition.
        first_line: usize,
    },
    /// A referenced block (record) is not defined in the deck.
    #[error("{what} {id} does not exist{note}")]
    UnknownReference {
        /// What was expected: `function` (`/FUNCT`), `skew` (`/SKEW/FIX`), `sensor`
        /// (`/SENSOR/TIME`), `unit system` (`/UNIT`); `*SPRINGPRO law`,
        /// `*FLEXPROADD record`.
        what: &'static str,
        /// The id referenced (never 0, which means "none").
        id: u64,
        /// Extra explanation (e.g. the id belongs to a block the reader skips), or empty.
        note: String,
    },
    /// A `/UNIT` name is not recognised.
    #[error("unknown {quantity} unit `{text}`: expected {expected}")]
    UnknownUnit {
        /// The name given.
        text: String,
        /// The quantity of the unit (its field: `M_unit`, `L_unit`, `T_unit`).
        quantity: BaseQuantity,
        /// The accepted names.
        expected: &'static str,
    },
    /// A keyword line whose keyword the deck format does not have: most likely a misspelt
    /// one ([`likely_keyword`]). The error's line is the keyword's, its field `keyword`.
    #[error(
        "unknown keyword {keyword}{}: {reason}",
        likely.as_ref().map(|k| format!(" (a misspelt {k}?)")).unwrap_or_default()
    )]
    UnknownKeyword {
        /// The keyword as written (upper case).
        keyword: String,
        /// The known keyword it most likely means, if one is close
        /// ([`likely_keyword`]).
        likely: Option<String>,
        /// Why the reader refuses it rather than skip it.
        reason: String,
    },
    /// The property, curve or law read breaks a rule of the spec, as reported by its own
    /// validation ([`crate::law::KjointProperty::validate`], [`crate::law::Curve::new`],
    /// the flex joint law's checks).
    #[error("{0}")]
    Property(PropertyError),
}

/// The quantity of a base unit: what a [`DeckErrorKind::UnknownUnit`] should have named.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BaseQuantity {
    /// Mass (SI unit: kg).
    Mass,
    /// Length (SI unit: m).
    Length,
    /// Time (SI unit: s).
    Time,
}

impl fmt::Display for BaseQuantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BaseQuantity::Mass => "mass",
            BaseQuantity::Length => "length",
            BaseQuantity::Time => "time",
        })
    }
}

/// Something a reader skipped, defaulted or ignored, with where it is.
///
/// Displayed as `file:line: message`, or `file: message` when `line` is 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Notice {
    /// Name of the file (as in [`DeckError::file`]).
    pub file: String,
    /// 1-based line number (0 = the whole file).
    pub line: usize,
    /// What happened.
    pub message: String,
}

impl Notice {
    /// A notice at `line` of `file`.
    pub fn new(file: impl Into<String>, line: usize, message: impl Into<String>) -> Self {
        Notice {
            file: file.into(),
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for Notice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            0 => write!(f, "{}: {}", self.file, self.message),
            line => write!(f, "{}:{line}: {}", self.file, self.message),
        }
    }
}

/// How close a keyword a reader does not know is to one it knows: [`likely_keyword`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Closeness {
    /// Within this many single-character edits (insertion, deletion, substitution or the
    /// swap of two neighbours): 1, or 2 for words of 5 characters or more (`/FUNC` for
    /// `/FUNCT`, `*FLEXPROAD` for `*FLEXPROADD`).
    Edits(usize),
    /// The word is the known keyword with more after it (`*FLEXJOINTS`, `*SPRINGPRO2`).
    Extends,
    /// The word is the start of the known keyword, 3 characters or more (`*SPRING` of
    /// `*SPRINGPRO`).
    Starts,
}

/// The keyword of `known` that `word` most likely means, and how close it is, or `None`
/// when none is close ([`Closeness`]; compared without case, the keywords' leading `/` or
/// `*` included). The fewest edits win, then a word that extends a keyword, then the start
/// of one; among equals the first of `known` (a reader lists the keywords it reads first).
pub fn likely_keyword<'k>(word: &str, known: &[&'k str]) -> Option<(&'k str, Closeness)> {
    let w: Vec<char> = word.to_uppercase().chars().collect();
    let body = |s: &[char]| s.iter().filter(|c| c.is_alphanumeric()).count();
    let rank = |c: Closeness| match c {
        Closeness::Edits(1) => 0,
        Closeness::Extends => 1,
        Closeness::Edits(_) => 2,
        Closeness::Starts => 3,
    };
    known
        .iter()
        .filter_map(|&k| {
            let kc: Vec<char> = k.to_uppercase().chars().collect();
            if kc == w {
                return None;
            }
            let limit = if body(&w) >= 5 { 2 } else { 1 };
            let ways = [
                edit_distance(&w, &kc, limit).map(Closeness::Edits),
                (w.starts_with(&kc) && body(&kc) >= 3).then_some(Closeness::Extends),
                (kc.starts_with(&w) && body(&w) >= 3).then_some(Closeness::Starts),
            ];
            let closest = ways.into_iter().flatten().min_by_key(|&c| rank(c))?;
            Some((k, closest))
        })
        .min_by_key(|&(_, c)| rank(c))
}

/// The optimal-string-alignment distance between `a` and `b` (insertions, deletions,
/// substitutions, swaps of neighbours), if at most `limit`.
fn edit_distance(a: &[char], b: &[char], limit: usize) -> Option<usize> {
    if a.len().abs_diff(b.len()) > limit {
        return None;
    }
    // rows i − 2, i − 1 and i of the table d[i][j] = distance(a[..i], b[..j])
    let mut before: Vec<usize> = Vec::new();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut row = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            row[j] = (prev[j] + 1).min(row[j - 1] + 1).min(prev[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                row[j] = row[j].min(before[j - 2] + 1);
            }
        }
        before = std::mem::replace(&mut prev, row);
    }
    let d = prev[b.len()];
    (d <= limit).then_some(d)
}

/// How numbers are written in a deck format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumberSyntax {
    /// Fixed-width fields (Radioss): a blank field is 0; reals may take a Fortran exponent
    /// with a letter (`1.5D3`, `1.5E+3`) or without (`1.5+3`, `1.5-3`); integers are plain
    /// (`+`/`-` and digits).
    FixedWidth,
    /// Whitespace-separated values (riser decks): a value is never blank; reals take an
    /// exponent only with a letter (`1e9`, `1.5D+3`; `1.5+3` is refused); integers may be
    /// written as an integral real (`3.`, `3e0`) within ±2^53.
    FreeFormat,
}

/// The one finiteness check: `value` (read from `text`) if finite, else
/// [`DeckErrorKind::NotFinite`] naming the text.
pub fn finite(value: f64, text: &str) -> Result<f64, DeckErrorKind> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(DeckErrorKind::NotFinite { text: text.into() })
    }
}

/// A real written in `syntax` (surrounding blanks ignored). NaN, infinities and values
/// that overflow are refused ([`DeckErrorKind::NotFinite`]).
pub fn parse_real(raw: &str, syntax: NumberSyntax) -> Result<f64, DeckErrorKind> {
    let t = raw.trim();
    let invalid = || DeckErrorKind::InvalidNumber {
        text: t.into(),
        expected: "a real number",
    };
    if t.is_empty() {
        return match syntax {
            NumberSyntax::FixedWidth => Ok(0.0),
            NumberSyntax::FreeFormat => Err(invalid()),
        };
    }
    let lower = t.to_lowercase();
    if lower.contains("nan") || lower.contains("inf") {
        return Err(DeckErrorKind::NotFinite { text: t.into() });
    }
    let allowed =
        |c: char| c.is_ascii_digit() || matches!(c, '+' | '-' | '.' | 'e' | 'E' | 'd' | 'D');
    if !t.chars().all(allowed) || !t.chars().any(|c| c.is_ascii_digit()) {
        return Err(invalid());
    }
    // Only ASCII from here on: byte indexing is safe.
    let mut s: String = t
        .chars()
        .map(|c| if c == 'd' || c == 'D' { 'e' } else { c })
        .collect();
    if syntax == NumberSyntax::FixedWidth && !s.contains(['e', 'E']) {
        // Fortran exponent without letter: `1.5+3` = 1.5e3.
        if let Some(p) = s[1..].find(['+', '-']) {
            s.insert(p + 1, 'e');
        }
    }
    match s.parse::<f64>() {
        Ok(v) => finite(v, t),
        Err(_) => Err(invalid()),
    }
}

/// An integer written in `syntax` (surrounding blanks ignored).
pub fn parse_int(raw: &str, syntax: NumberSyntax) -> Result<i64, DeckErrorKind> {
    let t = raw.trim();
    let invalid = || DeckErrorKind::InvalidNumber {
        text: t.into(),
        expected: "an integer",
    };
    match syntax {
        NumberSyntax::FixedWidth if t.is_empty() => Ok(0),
        NumberSyntax::FixedWidth => t.parse::<i64>().map_err(|_| invalid()),
        NumberSyntax::FreeFormat => {
            let v = parse_real(t, syntax).map_err(|k| match k {
                DeckErrorKind::InvalidNumber { .. } => invalid(),
                k => k,
            })?;
            // Integral and within the exactly representable range.
            if v.fract() == 0.0 && v.abs() <= 9.007_199_254_740_992e15 {
                Ok(v as i64)
            } else {
                Err(invalid())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FIXED: NumberSyntax = NumberSyntax::FixedWidth;
    const FREE: NumberSyntax = NumberSyntax::FreeFormat;

    fn is_invalid(r: Result<impl fmt::Debug, DeckErrorKind>) -> bool {
        matches!(r, Err(DeckErrorKind::InvalidNumber { .. }))
    }

    fn is_not_finite(r: Result<f64, DeckErrorKind>) -> bool {
        matches!(r, Err(DeckErrorKind::NotFinite { .. }))
    }

    #[test]
    fn fixed_width_reals() {
        assert_eq!(parse_real(".52", FIXED), Ok(0.52));
        assert_eq!(parse_real("  -100 ", FIXED), Ok(-100.0));
        assert_eq!(parse_real("1e3", FIXED), Ok(1e3));
        assert_eq!(parse_real("1.5E+02", FIXED), Ok(150.0));
        assert_eq!(parse_real("1.5d3", FIXED), Ok(1500.0));
        assert_eq!(parse_real("1.5D-3", FIXED), Ok(1.5e-3));
        assert_eq!(parse_real("-1.5+3", FIXED), Ok(-1500.0));
        assert_eq!(parse_real("1.5-3", FIXED), Ok(1.5e-3));
        assert_eq!(parse_real("5.", FIXED), Ok(5.0));
        assert_eq!(parse_real("", FIXED), Ok(0.0));
        for t in ["nan", "-Inf", "1e999"] {
            assert!(is_not_finite(parse_real(t, FIXED)), "{t}");
        }
        for t in ["1.2.3", ".", "-", "1-"] {
            assert!(is_invalid(parse_real(t, FIXED)), "{t}");
        }
    }

    #[test]
    fn free_format_reals() {
        assert_eq!(parse_real("1.0D-2", FREE), Ok(1e-2));
        assert_eq!(parse_real("12.5D0", FREE), Ok(12.5));
        assert_eq!(parse_real("0.", FREE), Ok(0.0));
        assert_eq!(parse_real("1e9", FREE), Ok(1e9));
        // the exponent needs its letter, and a value is never blank
        assert!(is_invalid(parse_real("1.5+3", FREE)));
        assert!(is_invalid(parse_real("", FREE)));
        assert!(is_invalid(parse_real("1.0x", FREE)));
        for t in ["NaN", "inf", "-infinity", "1e999"] {
            assert!(is_not_finite(parse_real(t, FREE)), "{t}");
        }
    }

    #[test]
    fn ints() {
        assert_eq!(parse_int("  +7", FIXED), Ok(7));
        assert_eq!(parse_int("", FIXED), Ok(0));
        assert!(is_invalid(parse_int("2.0", FIXED)));
        assert_eq!(parse_int("3.", FREE), Ok(3));
        assert_eq!(parse_int("-2e1", FREE), Ok(-20));
        assert!(is_invalid(parse_int("2.5", FREE)));
        assert!(is_invalid(parse_int("three", FREE)));
        assert!(is_invalid(parse_int("1e17", FREE)));
        assert!(matches!(
            parse_int("inf", FREE),
            Err(DeckErrorKind::NotFinite { .. })
        ));
    }

    #[test]
    fn likely_keywords() {
        let known = ["*SPRINGPRO", "*FLEXPROADD", "*FLEXJOINT"];
        let likely = |w: &str| likely_keyword(w, &known);
        assert_eq!(
            likely("*FLEXPROAD"),
            Some(("*FLEXPROADD", Closeness::Edits(1)))
        );
        assert_eq!(
            likely("*flexjoints"),
            Some(("*FLEXJOINT", Closeness::Edits(1)))
        );
        assert_eq!(
            likely("*FLEXJOINT2D"),
            Some(("*FLEXJOINT", Closeness::Extends))
        );
        assert_eq!(
            likely("*FLEXJIONT"),
            Some(("*FLEXJOINT", Closeness::Edits(1)))
        );
        assert_eq!(
            likely("*FLXJOINTT"),
            Some(("*FLEXJOINT", Closeness::Edits(2)))
        );
        assert_eq!(
            likely("*FLEXJOINTXYZ"),
            Some(("*FLEXJOINT", Closeness::Extends))
        );
        assert_eq!(
            likely("*SPIRNGPRO"),
            Some(("*SPRINGPRO", Closeness::Edits(1)))
        );
        assert_eq!(likely("*SPRING"), Some(("*SPRINGPRO", Closeness::Starts)));
        assert_eq!(likely("*NODE"), None);
        assert_eq!(likely("*FLEXJOINT"), None);
        // short words: one edit at most
        let known = ["/FUNCT", "/SPH", "/PROP"];
        assert_eq!(
            likely_keyword("/FUNC", &known),
            Some(("/FUNCT", Closeness::Edits(1)))
        );
        assert_eq!(
            likely_keyword("/SPA", &known),
            Some(("/SPH", Closeness::Edits(1)))
        );
        assert_eq!(likely_keyword("/SXA", &known), None);
    }

    #[test]
    fn an_error_stays_small_enough_to_return() {
        // clippy's `result_large_err` bound: every reader function returns it
        assert!(std::mem::size_of::<DeckError>() < 128);
    }

    #[test]
    fn messages_name_file_line_field_and_block() {
        let kind = DeckErrorKind::MissingField;
        let e = DeckError::new("a.dat", 3, "IPRO", kind.clone());
        assert_eq!(
            e.to_string(),
            "a.dat:3: field `IPRO`: missing: the record ends before it"
        );
        let e = e.in_block("*FLEXJOINT");
        assert!(e
            .to_string()
            .starts_with("a.dat:3: field `IPRO` of *FLEXJOINT: "));
        let e = DeckError::new("a.dat", 0, "file", DeckErrorKind::Io("gone".into()));
        assert_eq!(e.to_string(), "a.dat: cannot read the file: gone");
        assert_eq!(
            Notice::new("a.dat", 2, "skipped").to_string(),
            "a.dat:2: skipped"
        );
        assert_eq!(
            Notice::new("a.dat", 0, "skipped").to_string(),
            "a.dat: skipped"
        );
    }
}
