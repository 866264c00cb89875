//! Reader for Radioss input decks (2019+ fixed-width format): KJOINT2 properties and the
//! functions, skews, time sensors and unit systems they reference.
//!
//! This is a pure parser: it builds [`Kjoint2Property`] values (as written and converted
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
//! - Any block other than those below (`/BEGIN`, `/NODE`, `/PART`, other `/PROP` types,
//!   `/SKEW/MOV`, ...) is skipped with a [`Notice`]. In particular the unit system of
//!   `/BEGIN` is **not** applied: a property without its own `/unit_ID` is taken as SI.
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
//! Zero ids mean "none". The property is checked with [`Kjoint2Property::validate`].
//!
//! `/FUNCT/fct_ID[/unit_ID]`: a title, then lines of `X(20) Y(20)`, optionally a second
//! pair `X(20) Y(20)` on the same line (columns 41-80). Blank lines are skipped. Abscissas
//! must increase strictly. A function's values are interpreted in the unit system of the
//! property that references it (its own `unit_ID` is only checked to exist).
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

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use thiserror::Error;

use super::units::{property_to_si, Quantity, UnitSystem};
use crate::error::PropertyError;
use crate::law::{Curve, Dof, JointType, Kjoint2Property};

// ---------------------------------------------------------------------------------------
// Errors and notices
// ---------------------------------------------------------------------------------------

/// An error in a Radioss deck: where it is (file, line, field) and what was expected.
///
/// `line` is 1-based; 0 means the file as a whole (e.g. it cannot be read). `field` is the
/// Radioss field name, prefixed by the DOF for per-DOF fields (`rx.SA+`, `dx.Kf`), or the
/// keyword part for keyword lines (`prop_ID`, `unit_ID`).
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{file}:{line}: field `{field}`: {kind}")]
pub struct DeckError {
    /// Name of the file (its path as given, or the name passed to [`parse_str`]).
    pub file: String,
    /// 1-based line number (0 = the whole file).
    pub line: usize,
    /// The field, e.g. `Type`, `Kn`, `rx.SA+`, `dx.fct_K`, `prop_ID`.
    pub field: String,
    /// What is wrong.
    pub kind: DeckErrorKind,
}

/// What is wrong in a [`DeckError`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DeckErrorKind {
    /// The file cannot be read.
    #[error("cannot read the file: {0}")]
    Io(String),
    /// A field does not hold a number of the expected kind.
    #[error("`{text}` is not {expected}")]
    InvalidNumber {
        /// The field's text.
        text: String,
        /// `"a real number"` or `"an integer"`.
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
    /// The joint type is not 1..=9.
    #[error("unknown joint type {value}: expected 1 (spherical) .. 9 (free)")]
    UnknownJointType {
        /// The number given.
        value: i64,
    },
    /// A block ends before a required card (the error's line is the keyword line).
    #[error("missing card `{card}` in {block}")]
    MissingCard {
        /// The card's layout, e.g. `Type Kn ScF Cr sens_ID Skew_ID1 Skew_ID2`.
        card: String,
        /// The block, e.g. `/PROP/TYPE45/2`.
        block: String,
    },
    /// A keyword line lacks its id or has too many parts.
    #[error("invalid keyword line `{text}`: expected {expected}")]
    InvalidKeyword {
        /// The keyword line.
        text: String,
        /// The expected form.
        expected: String,
    },
    /// Two blocks of the same kind have the same id.
    #[error("{what} {id} is defined twice (first at line {first_line})")]
    DuplicateId {
        /// `property`, `function`, `unit`, `skew` or `sensor`.
        what: &'static str,
        /// The id.
        id: u32,
        /// Line of the first definition.
        first_line: usize,
    },
    /// A referenced function, skew, sensor or unit system is not defined in the deck.
    #[error("{what} {id} does not exist{note}")]
    UnknownReference {
        /// `function` (`/FUNCT`), `skew` (`/SKEW/FIX`), `sensor` (`/SENSOR/TIME`) or
        /// `unit system` (`/UNIT`).
        what: &'static str,
        /// The id referenced.
        id: u32,
        /// Extra explanation (e.g. the id belongs to a block this reader skips), or empty.
        note: String,
    },
    /// A `/UNIT` name is not recognised.
    #[error("unknown {quantity} unit `{text}`: expected {expected}")]
    UnknownUnit {
        /// The name given.
        text: String,
        /// `mass`, `length` or `time`.
        quantity: &'static str,
        /// The accepted names.
        expected: &'static str,
    },
    /// The property (or a function) breaks a rule of the spec (§1), as reported by
    /// [`Kjoint2Property::validate`] or [`Curve::new`].
    #[error("{0}")]
    Property(PropertyError),
}

/// Something the reader skipped or defaulted, with the line it concerns (0 = the file).
#[derive(Debug, Clone, PartialEq)]
pub struct Notice {
    /// 1-based line number (0 = the whole file).
    pub line: usize,
    /// What happened.
    pub message: String,
}

// ---------------------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------------------

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
    /// `unit_ID` of the keyword (`None` = the values are taken as SI).
    pub unit_id: Option<u32>,
    /// The unit system of `unit_id`.
    pub unit: Option<UnitSystem>,
    /// The property with the values as written in the deck (functions resolved).
    pub property: Kjoint2Property,
    /// The property converted into SI (kg, m, s) with
    /// [`super::units::property_to_si`]; equal to `property` without unit.
    pub property_si: Kjoint2Property,
    /// `Skew_ID1` (`None` = from the anchors' geometry).
    pub skew1: Option<u32>,
    /// `Skew_ID2` (`None` = no initial relative rotation).
    pub skew2: Option<u32>,
    /// The function ids of each DOF, indexed like [`Kjoint2Property::dofs`].
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
    /// Its unit system (for the origin).
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
    /// Its unit system.
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
    /// Skipped blocks, defaulted cards and other remarks, in file order.
    pub notices: Vec<Notice>,
}

impl RadiossDeck {
    /// The property block `id`.
    pub fn property(&self, id: u32) -> Option<&PropertyEntry> {
        self.properties.get(&id)
    }

    /// The property `id` converted into SI (kg, m, s): see
    /// [`super::units::property_to_si`] for the factors.
    pub fn property_si(&self, id: u32) -> Option<&Kjoint2Property> {
        self.properties.get(&id).map(|p| &p.property_si)
    }

    /// The unit system `id`.
    pub fn unit_system(&self, id: u32) -> Option<UnitSystem> {
        self.units.get(&id).map(|u| u.system)
    }
}

// ---------------------------------------------------------------------------------------
// Entry points
// ---------------------------------------------------------------------------------------

/// Reads a deck file (within the size cap [`super::MAX_INPUT_BYTES`]). Invalid UTF-8 is
/// replaced (titles may be garbled) with a notice.
pub fn read_file(path: &Path) -> Result<RadiossDeck, DeckError> {
    let name = path.display().to_string();
    let bytes = super::input::read_input(path).map_err(|e| DeckError {
        file: name.clone(),
        line: 0,
        field: "file".into(),
        kind: DeckErrorKind::Io(e.kind.reason()),
    })?;
    match String::from_utf8(bytes) {
        Ok(text) => parse_str(&text, &name),
        Err(e) => {
            let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
            let mut deck = parse_str(&text, &name)?;
            deck.notices.insert(
                0,
                Notice {
                    line: 0,
                    message: "the file is not valid UTF-8: invalid bytes were replaced by U+FFFD"
                        .into(),
                },
            );
            Ok(deck)
        }
    }
}

/// Parses the text of a deck; `file` is the name used in errors. Never panics.
pub fn parse_str(text: &str, file: &str) -> Result<RadiossDeck, DeckError> {
    let ctx = Ctx { file };
    let mut reader = Reader::default();
    let blocks = split_blocks(text, &mut reader.notices);
    for block in &blocks {
        reader.block(&ctx, block)?;
    }
    reader.finish(&ctx)
}

// ---------------------------------------------------------------------------------------
// Lines, fields and numbers
// ---------------------------------------------------------------------------------------

#[derive(Debug, Clone, Copy)]
struct Line<'a> {
    no: usize,
    text: &'a str,
}

impl Line<'_> {
    fn is_blank(&self) -> bool {
        self.text.trim().is_empty()
    }
}

/// `width` characters from character `start` (fewer, or none, on a short line).
fn column(text: &str, start: usize, width: usize) -> String {
    text.chars().skip(start).take(width).collect()
}

/// A Fortran-style real; blank = 0.
fn parse_real(raw: &str) -> Result<f64, DeckErrorKind> {
    let t = raw.trim();
    if t.is_empty() {
        return Ok(0.0);
    }
    let lower = t.to_lowercase();
    if lower.contains("nan") || lower.contains("inf") {
        return Err(DeckErrorKind::NotFinite { text: t.into() });
    }
    let invalid = || DeckErrorKind::InvalidNumber {
        text: t.into(),
        expected: "a real number",
    };
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
    if !s.contains(['e', 'E']) {
        // Fortran exponent without letter: `1.5+3` = 1.5e3.
        if let Some(p) = s[1..].find(['+', '-']) {
            s.insert(p + 1, 'e');
        }
    }
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(DeckErrorKind::NotFinite { text: t.into() }),
        Err(_) => Err(invalid()),
    }
}

/// An integer; blank = 0.
fn parse_int(raw: &str) -> Result<i64, DeckErrorKind> {
    let t = raw.trim();
    if t.is_empty() {
        return Ok(0);
    }
    t.parse::<i64>().map_err(|_| DeckErrorKind::InvalidNumber {
        text: t.into(),
        expected: "an integer",
    })
}

struct Ctx<'f> {
    file: &'f str,
}

impl Ctx<'_> {
    fn err(&self, line: usize, field: impl Into<String>, kind: DeckErrorKind) -> DeckError {
        DeckError {
            file: self.file.to_string(),
            line,
            field: field.into(),
            kind,
        }
    }

    fn real(&self, l: &Line, start: usize, width: usize, field: &str) -> Result<f64, DeckError> {
        parse_real(&column(l.text, start, width)).map_err(|k| self.err(l.no, field, k))
    }

    fn int(&self, l: &Line, start: usize, width: usize, field: &str) -> Result<i64, DeckError> {
        parse_int(&column(l.text, start, width)).map_err(|k| self.err(l.no, field, k))
    }

    /// An id field: 0 (or blank) = none.
    fn id(
        &self,
        l: &Line,
        start: usize,
        width: usize,
        field: &str,
    ) -> Result<Option<u32>, DeckError> {
        let v = self.int(l, start, width, field)?;
        id_value(v)
            .map_err(|expected| {
                self.err(
                    l.no,
                    field,
                    DeckErrorKind::InvalidValue {
                        value: v.to_string(),
                        expected,
                    },
                )
            })
            .map(|id| (id != 0).then_some(id))
    }

    fn text(&self, l: &Line, start: usize, width: usize) -> String {
        column(l.text, start, width).trim().to_string()
    }

    fn missing(&self, b: &Block, field: &str, card: &str) -> DeckError {
        self.err(
            b.line,
            field,
            DeckErrorKind::MissingCard {
                card: card.into(),
                block: b.name(),
            },
        )
    }
}

fn id_value(v: i64) -> Result<u32, String> {
    u32::try_from(v).map_err(|_| format!("an id in 0..={} (0 = none)", u32::MAX))
}

// ---------------------------------------------------------------------------------------
// Blocks
// ---------------------------------------------------------------------------------------

struct Block<'a> {
    line: usize,
    header: &'a str,
    /// Keyword parts after the leading `/`, trimmed (`["PROP", "TYPE45", "2", "2"]`).
    parts: Vec<&'a str>,
    /// Non-comment lines of the block.
    body: Vec<Line<'a>>,
}

impl Block<'_> {
    fn part(&self, i: usize) -> String {
        self.parts
            .get(i)
            .map(|s| s.to_ascii_uppercase())
            .unwrap_or_default()
    }
    /// The block's name for messages: its keyword line without trailing blanks.
    fn name(&self) -> String {
        self.header.trim_end().to_string()
    }
}

fn starts_with_ci(text: &str, prefix: &str) -> bool {
    text.get(..prefix.len())
        .is_some_and(|s| s.eq_ignore_ascii_case(prefix))
}

fn split_blocks<'a>(text: &'a str, notices: &mut Vec<Notice>) -> Vec<Block<'a>> {
    let mut blocks: Vec<Block<'a>> = Vec::new();
    for (i, text) in text.lines().enumerate() {
        let no = i + 1;
        if starts_with_ci(text, "#ENDDATA") {
            break;
        }
        if text.starts_with('#') || text.starts_with('$') {
            if starts_with_ci(text, "#include") {
                notices.push(Notice {
                    line: no,
                    message: "#include is not followed: the included file is not read".into(),
                });
            }
            continue;
        }
        if let Some(rest) = text.strip_prefix('/') {
            let parts: Vec<&str> = rest.trim_end().split('/').map(str::trim).collect();
            if parts.len() == 1 && parts[0].eq_ignore_ascii_case("END") {
                break;
            }
            blocks.push(Block {
                line: no,
                header: text,
                parts,
                body: Vec::new(),
            });
            continue;
        }
        match blocks.last_mut() {
            Some(b) => b.body.push(Line { no, text }),
            None if !text.trim().is_empty() => notices.push(Notice {
                line: no,
                message: "line outside any block ignored".into(),
            }),
            None => {}
        }
    }
    blocks
}

// ---------------------------------------------------------------------------------------
// Reader
// ---------------------------------------------------------------------------------------

/// A KJOINT2 block before its references are resolved.
struct RawProperty {
    entry: PropertyEntry,
    first_card: usize,
    /// Line of the K, C and Kf cards of each DOF (`None` = missing, defaulted).
    card_lines: [[Option<usize>; 3]; 6],
}

#[derive(Default)]
struct Reader {
    notices: Vec<Notice>,
    props: Vec<RawProperty>,
    functions: BTreeMap<u32, Function>,
    skews: BTreeMap<u32, SkewFix>,
    sensors: BTreeMap<u32, TimeSensor>,
    units: BTreeMap<u32, UnitEntry>,
    /// Ids of functions, skews and sensors defined by blocks this reader skips:
    /// `(kind, id) -> (keyword, line)`.
    skipped: HashMap<(&'static str, u32), (String, usize)>,
}

/// A kind of referenced block: its name in messages, its key in `Reader::skipped`, and the
/// keyword this reader accepts for it.
#[derive(Clone, Copy)]
struct RefKind {
    what: &'static str,
    key: &'static str,
    keyword: &'static str,
}

impl RefKind {
    const FUNCTION: RefKind = RefKind {
        what: "function",
        key: "function",
        keyword: "/FUNCT",
    };
    const SKEW: RefKind = RefKind {
        what: "skew",
        key: "skew",
        keyword: "/SKEW/FIX",
    };
    const SENSOR: RefKind = RefKind {
        what: "sensor",
        key: "sensor",
        keyword: "/SENSOR/TIME",
    };
    const UNIT: RefKind = RefKind {
        what: "unit system",
        key: "unit",
        keyword: "/UNIT",
    };
}

const PROP_CARD1: &str = "Type Kn ScF Cr sens_ID Skew_ID1 Skew_ID2";

impl Reader {
    fn notice(&mut self, line: usize, message: impl Into<String>) {
        self.notices.push(Notice {
            line,
            message: message.into(),
        });
    }

    fn block(&mut self, ctx: &Ctx, b: &Block) -> Result<(), DeckError> {
        let (p0, p1) = (b.part(0), b.part(1));
        match (p0.as_str(), p1.as_str()) {
            ("PROP", "TYPE45" | "KJOINT2") => self.kjoint2(ctx, b),
            ("FUNCT", _) => self.funct(ctx, b),
            ("UNIT", _) => self.unit(ctx, b),
            ("SKEW", "FIX") => self.skew(ctx, b),
            ("SENSOR", "TIME") => self.sensor(ctx, b),
            _ => {
                self.skip(b, &p0);
                Ok(())
            }
        }
    }

    fn skip(&mut self, b: &Block, p0: &str) {
        // Where the id sits in keywords that define an id another block may reference.
        let kind_at = match p0 {
            "SKEW" => Some(("skew", 2)),
            "SENSOR" => Some(("sensor", 2)),
            "FUNCT_SMOOTH" => Some(("function", 1)),
            "TABLE" => Some(("function", 2)),
            _ => None,
        };
        if let Some((kind, at)) = kind_at {
            if let Some(id) = b.parts.get(at).and_then(|t| t.parse::<u32>().ok()) {
                self.skipped.entry((kind, id)).or_insert((b.name(), b.line));
            }
        }
        let message = if p0 == "BEGIN" {
            "/BEGIN skipped: its unit system is not applied (values without a /unit_ID on \
             their keyword are read as SI)"
                .to_string()
        } else if p0 == "PROP" {
            format!("{} skipped: only /PROP/TYPE45 (KJOINT2) is read", b.name())
        } else if p0 == "SKEW" || p0 == "SENSOR" {
            format!(
                "{} skipped: only /{p0}/{} is read",
                b.name(),
                if p0 == "SKEW" { "FIX" } else { "TIME" }
            )
        } else {
            format!("{} skipped: not read by this reader", b.name())
        };
        self.notice(b.line, message);
    }

    /// Parses `id[/unit_ID]` from keyword part `at` on.
    fn ids(
        &self,
        ctx: &Ctx,
        b: &Block,
        at: usize,
        id_name: &str,
        allow_unit: bool,
    ) -> Result<(u32, Option<u32>), DeckError> {
        let form = {
            let head: Vec<&str> = b.parts.iter().take(at).copied().collect();
            let unit = if allow_unit { "[/unit_ID]" } else { "" };
            format!("/{}/{id_name}{unit}", head.join("/"))
        };
        let bad = |field: &str| {
            ctx.err(
                b.line,
                field,
                DeckErrorKind::InvalidKeyword {
                    text: b.name(),
                    expected: form.clone(),
                },
            )
        };
        let id_text = b.parts.get(at).copied().unwrap_or("");
        if id_text.is_empty() {
            return Err(bad(id_name));
        }
        let id = parse_int(id_text).map_err(|k| ctx.err(b.line, id_name, k))?;
        let id = match id_value(id) {
            Ok(id) if id > 0 => id,
            _ => {
                return Err(ctx.err(
                    b.line,
                    id_name,
                    DeckErrorKind::InvalidValue {
                        value: id.to_string(),
                        expected: format!("an id in 1..={}", u32::MAX),
                    },
                ))
            }
        };
        let mut unit = None;
        let mut next = at + 1;
        if allow_unit {
            if let Some(t) = b.parts.get(at + 1).filter(|t| !t.is_empty()) {
                let v = parse_int(t).map_err(|k| ctx.err(b.line, "unit_ID", k))?;
                let v = id_value(v).map_err(|expected| {
                    ctx.err(
                        b.line,
                        "unit_ID",
                        DeckErrorKind::InvalidValue {
                            value: v.to_string(),
                            expected,
                        },
                    )
                })?;
                unit = (v != 0).then_some(v);
            }
            next += 1;
        }
        if b.parts.iter().skip(next).any(|t| !t.is_empty()) {
            return Err(bad("keyword"));
        }
        Ok((id, unit))
    }

    fn title(&self, ctx: &Ctx, b: &Block, field: &str) -> Result<String, DeckError> {
        b.body
            .first()
            .map(|l| l.text.trim_end().to_string())
            .ok_or_else(|| ctx.missing(b, field, field))
    }

    fn extra_cards(&mut self, b: &Block, used: usize) {
        if let Some(l) = b.body.iter().skip(used).find(|l| !l.is_blank()) {
            let (no, name) = (l.no, b.name());
            self.notice(
                no,
                format!("extra cards in {name} ignored (from this line on)"),
            );
        }
    }

    fn kjoint2(&mut self, ctx: &Ctx, b: &Block) -> Result<(), DeckError> {
        let (id, unit_id) = self.ids(ctx, b, 2, "prop_ID", true)?;
        if let Some(first) = self.props.iter().find(|p| p.entry.id == id) {
            return Err(ctx.err(
                b.line,
                "prop_ID",
                DeckErrorKind::DuplicateId {
                    what: "property",
                    id,
                    first_line: first.entry.line,
                },
            ));
        }
        let title = self.title(ctx, b, "prop_title")?;
        let c1 = b
            .body
            .get(1)
            .ok_or_else(|| ctx.missing(b, "Type", PROP_CARD1))?;
        let type_number = ctx.int(c1, 0, 10, "Type")?;
        let joint_type = JointType::from_number(type_number).map_err(|_| {
            ctx.err(
                c1.no,
                "Type",
                DeckErrorKind::UnknownJointType { value: type_number },
            )
        })?;
        // Kn = 0 keeps Radioss' own automatic rule: deck users compare with Radioss
        let mut p = Kjoint2Property::new(joint_type)
            .with_automatic(crate::law::AutomaticStiffness::Radioss);
        p.kn = ctx.real(c1, 10, 20, "Kn")?;
        p.scale_factor = ctx.real(c1, 30, 20, "ScF")?;
        p.critical_damping = ctx.real(c1, 50, 20, "Cr")?;
        p.sensor = ctx.id(c1, 70, 10, "sens_ID")?;
        let skew1 = ctx.id(c1, 80, 10, "Skew_ID1")?;
        let skew2 = ctx.id(c1, 90, 10, "Skew_ID2")?;

        let mut card_lines = [[None; 3]; 6];
        let mut function_ids = [DofFunctionIds::default(); 6];
        let mut missing: Vec<String> = Vec::new();
        let mut next = 2;
        for dof in Dof::ALL.into_iter().filter(|&d| joint_type.is_free(d)) {
            let i = dof.index();
            let n = dof.name();
            let (sm, sp, ff, fct_ff) = if dof.is_rotation() {
                ("SA-", "SA+", "FM", "fct_FM")
            } else {
                ("SD-", "SD+", "FF", "fct_FF")
            };
            let law = &mut p.dofs[i];
            let ids = &mut function_ids[i];
            for card in 0..3 {
                let Some(l) = b.body.get(next + card) else {
                    missing.push(format!("{n}.{}", ["K", "C", "Kf"][card]));
                    continue;
                };
                card_lines[i][card] = Some(l.no);
                let f = |name: &str| format!("{n}.{name}");
                match card {
                    0 => {
                        law.stiffness = ctx.real(l, 0, 20, &f("K"))?;
                        ids.stiffness = ctx.id(l, 20, 10, &f("fct_K"))?;
                        law.stop_min = ctx.real(l, 30, 20, &f(sm))?;
                        law.stop_max = ctx.real(l, 50, 20, &f(sp))?;
                        law.coupled_stops = match ctx.int(l, 70, 10, &f("Icomb"))? {
                            0 => false,
                            1 => true,
                            v => {
                                return Err(ctx.err(
                                    l.no,
                                    f("Icomb"),
                                    DeckErrorKind::InvalidValue {
                                        value: v.to_string(),
                                        expected: "0 (independent stops) or 1 (coupled stops)"
                                            .into(),
                                    },
                                ))
                            }
                        };
                    }
                    1 => {
                        law.viscosity = ctx.real(l, 0, 20, &f("C"))?;
                        ids.viscosity = ctx.id(l, 20, 10, &f("fct_C"))?;
                    }
                    _ => {
                        law.friction_stiffness = ctx.real(l, 0, 20, &f("Kf"))?;
                        law.friction = ctx.real(l, 20, 20, &f(ff))?;
                        ids.friction = ctx.id(l, 40, 10, &f(fct_ff))?;
                    }
                }
            }
            next += 3;
        }
        if missing.is_empty() {
            self.extra_cards(b, next);
        } else {
            let last = b.body.last().map_or(b.line, |l| l.no);
            self.notice(
                last,
                format!(
                    "{} ends before the cards {}: their fields take the default 0",
                    b.name(),
                    missing.join(", ")
                ),
            );
        }
        self.props.push(RawProperty {
            entry: PropertyEntry {
                id,
                title,
                line: b.line,
                keyword: b.name(),
                unit_id,
                unit: None,
                property_si: p.clone(),
                property: p,
                skew1,
                skew2,
                function_ids,
            },
            first_card: c1.no,
            card_lines,
        });
        Ok(())
    }

    fn funct(&mut self, ctx: &Ctx, b: &Block) -> Result<(), DeckError> {
        let (id, unit_id) = self.ids(ctx, b, 1, "fct_ID", true)?;
        if let Some(first) = self.functions.get(&id) {
            return Err(duplicate(ctx, b, "fct_ID", "function", id, first.line));
        }
        let title = self.title(ctx, b, "fct_title")?;
        let mut points: Vec<(f64, f64)> = Vec::new();
        for l in b.body.iter().skip(1).filter(|l| !l.is_blank()) {
            let mut pairs = vec![(ctx.real(l, 0, 20, "X")?, ctx.real(l, 20, 20, "Y")?)];
            if !(ctx.text(l, 40, 20).is_empty() && ctx.text(l, 60, 20).is_empty()) {
                pairs.push((ctx.real(l, 40, 20, "X")?, ctx.real(l, 60, 20, "Y")?));
            }
            for (x, y) in pairs {
                if let Some(&(px, _)) = points.last() {
                    if x <= px {
                        return Err(ctx.err(
                            l.no,
                            "X",
                            DeckErrorKind::InvalidValue {
                                value: x.to_string(),
                                expected: format!(
                                    "an abscissa > {px} (abscissas must increase strictly)"
                                ),
                            },
                        ));
                    }
                }
                points.push((x, y));
            }
        }
        if points.is_empty() {
            return Err(ctx.missing(b, "X", "X Y"));
        }
        let curve =
            Curve::new(points).map_err(|e| ctx.err(b.line, "X", DeckErrorKind::Property(e)))?;
        self.functions.insert(
            id,
            Function {
                id,
                title,
                line: b.line,
                unit_id,
                curve,
            },
        );
        Ok(())
    }

    fn unit(&mut self, ctx: &Ctx, b: &Block) -> Result<(), DeckError> {
        let (id, _) = self.ids(ctx, b, 1, "unit_ID", false)?;
        if let Some(first) = self.units.get(&id) {
            return Err(duplicate(ctx, b, "unit_ID", "unit system", id, first.line));
        }
        let title = self.title(ctx, b, "unit_title")?;
        let card = b
            .body
            .get(1)
            .ok_or_else(|| ctx.missing(b, "M_unit", "M_unit L_unit T_unit"))?;
        type Lookup = fn(&str) -> Option<f64>;
        let specs: [(&str, &'static str, &'static str, Lookup); 3] = [
            (
                "M_unit",
                "mass",
                "kg, g, mg, Mg, t, lb, or the unit's size in kg",
                super::units::mass_unit,
            ),
            (
                "L_unit",
                "length",
                "m, dm, cm, mm, um, km, in, ft, or the unit's size in m",
                super::units::length_unit,
            ),
            (
                "T_unit",
                "time",
                "s, ms, us, ns, min, h, or the unit's size in s",
                super::units::time_unit,
            ),
        ];
        let mut names: [String; 3] = Default::default();
        let mut sizes = [1.0; 3];
        for (k, (field, quantity, expected, lookup)) in specs.into_iter().enumerate() {
            let name = ctx.text(card, 20 * k, 20);
            if name.is_empty() {
                self.notice(
                    card.no,
                    format!("/UNIT/{id}: blank {field}, the SI base unit is used"),
                );
            } else {
                sizes[k] = lookup(&name).ok_or_else(|| {
                    ctx.err(
                        card.no,
                        field,
                        DeckErrorKind::UnknownUnit {
                            text: name.clone(),
                            quantity,
                            expected,
                        },
                    )
                })?;
            }
            names[k] = name;
        }
        // Sizes come from the tables or are checked positive and finite.
        let system = UnitSystem::new(sizes[0], sizes[1], sizes[2]).unwrap_or(UnitSystem::SI);
        self.extra_cards(b, 2);
        self.units.insert(
            id,
            UnitEntry {
                id,
                title,
                line: b.line,
                names,
                system,
            },
        );
        Ok(())
    }

    fn skew(&mut self, ctx: &Ctx, b: &Block) -> Result<(), DeckError> {
        let (id, unit_id) = self.ids(ctx, b, 2, "skew_ID", true)?;
        if let Some(first) = self.skews.get(&id) {
            return Err(duplicate(ctx, b, "skew_ID", "skew", id, first.line));
        }
        let title = self.title(ctx, b, "skew_title")?;
        let names = [["Ox", "Oy", "Oz"], ["X1", "Y1", "Z1"], ["X2", "Y2", "Z2"]];
        let mut v = [[0.0; 3]; 3];
        let mut lines = [0; 3];
        for (k, fields) in names.iter().enumerate() {
            let l = b
                .body
                .get(1 + k)
                .ok_or_else(|| ctx.missing(b, fields[0], &fields.join(" ")))?;
            lines[k] = l.no;
            for (j, field) in fields.iter().enumerate() {
                v[k][j] = ctx.real(l, 20 * j, 20, field)?;
            }
        }
        let degenerate = |line: usize, field: &str, value: [f64; 3], expected: &str| {
            ctx.err(
                line,
                field,
                DeckErrorKind::InvalidValue {
                    value: format!("({}, {}, {})", value[0], value[1], value[2]),
                    expected: expected.into(),
                },
            )
        };
        let y = normalize(v[1])
            .ok_or_else(|| degenerate(lines[1], "X1", v[1], "a non-zero vector (the Y' axis)"))?;
        let z = normalize(v[2])
            .ok_or_else(|| degenerate(lines[2], "X2", v[2], "a non-zero vector (the Z' axis)"))?;
        let x = cross(y, z);
        if x.iter().map(|c| c * c).sum::<f64>() < 1e-20 {
            return Err(degenerate(
                lines[2],
                "X2",
                v[2],
                "a vector not parallel to the Y' axis (X1 Y1 Z1)",
            ));
        }
        self.extra_cards(b, 4);
        self.skews.insert(
            id,
            SkewFix {
                id,
                title,
                line: b.line,
                unit_id,
                unit: None,
                origin: v[0],
                y_axis: v[1],
                z_axis: v[2],
            },
        );
        Ok(())
    }

    fn sensor(&mut self, ctx: &Ctx, b: &Block) -> Result<(), DeckError> {
        let (id, unit_id) = self.ids(ctx, b, 2, "sens_ID", true)?;
        if let Some(first) = self.sensors.get(&id) {
            return Err(duplicate(ctx, b, "sens_ID", "sensor", id, first.line));
        }
        let title = self.title(ctx, b, "sens_title")?;
        let l = b
            .body
            .get(1)
            .ok_or_else(|| ctx.missing(b, "Tdelay", "Tdelay"))?;
        let tdelay = ctx.real(l, 0, 20, "Tdelay")?;
        if tdelay < 0.0 {
            return Err(ctx.err(
                l.no,
                "Tdelay",
                DeckErrorKind::InvalidValue {
                    value: tdelay.to_string(),
                    expected: "a time >= 0".into(),
                },
            ));
        }
        self.extra_cards(b, 2);
        self.sensors.insert(
            id,
            TimeSensor {
                id,
                title,
                line: b.line,
                unit_id,
                unit: None,
                tdelay,
            },
        );
        Ok(())
    }

    /// Error for a reference to an id that no read block defines.
    fn unknown(&self, ctx: &Ctx, line: usize, field: &str, r: RefKind, id: u32) -> DeckError {
        let keyword = r.keyword;
        let note = match self.skipped.get(&(r.key, id)) {
            Some((kw, at)) => format!(
                " as a {keyword} block (it is defined by {kw} at line {at}, which this reader \
                 does not support)"
            ),
            None => format!(" (no {keyword} block with this id)"),
        };
        ctx.err(
            line,
            field,
            DeckErrorKind::UnknownReference {
                what: r.what,
                id,
                note,
            },
        )
    }

    fn unit_of(
        &self,
        ctx: &Ctx,
        line: usize,
        id: Option<u32>,
    ) -> Result<Option<UnitSystem>, DeckError> {
        match id {
            None => Ok(None),
            Some(id) => match self.units.get(&id) {
                Some(u) => Ok(Some(u.system)),
                None => Err(self.unknown(ctx, line, "unit_ID", RefKind::UNIT, id)),
            },
        }
    }

    /// Resolves every reference and converts the properties into SI.
    fn finish(mut self, ctx: &Ctx) -> Result<RadiossDeck, DeckError> {
        for f in self.functions.values() {
            self.unit_of(ctx, f.line, f.unit_id)?;
        }
        let mut skews = std::mem::take(&mut self.skews);
        for s in skews.values_mut() {
            s.unit = self.unit_of(ctx, s.line, s.unit_id)?;
        }
        let mut sensors = std::mem::take(&mut self.sensors);
        for s in sensors.values_mut() {
            s.unit = self.unit_of(ctx, s.line, s.unit_id)?;
        }
        let mut properties = BTreeMap::new();
        let mut notes = Vec::new();
        for raw in std::mem::take(&mut self.props) {
            let mut e = raw.entry.clone();
            e.unit = self.unit_of(ctx, e.line, e.unit_id)?;
            let c1 = raw.first_card;
            if let Some(id) = e.property.sensor {
                if !sensors.contains_key(&id) {
                    return Err(self.unknown(ctx, c1, "sens_ID", RefKind::SENSOR, id));
                }
            }
            for (field, skew) in [("Skew_ID1", e.skew1), ("Skew_ID2", e.skew2)] {
                if let Some(id) = skew.filter(|id| !skews.contains_key(id)) {
                    return Err(self.unknown(ctx, c1, field, RefKind::SKEW, id));
                }
            }
            for dof in Dof::ALL {
                let i = dof.index();
                let ids = e.function_ids[i];
                let ff = if dof.is_rotation() {
                    "fct_FM"
                } else {
                    "fct_FF"
                };
                let slots = [
                    (ids.stiffness, 0, "fct_K"),
                    (ids.viscosity, 1, "fct_C"),
                    (ids.friction, 2, ff),
                ];
                for (id, card, name) in slots {
                    let Some(id) = id else { continue };
                    let line = raw.card_lines[i][card].unwrap_or(e.line);
                    let field = format!("{}.{name}", dof.name());
                    let Some(f) = self.functions.get(&id) else {
                        return Err(self.unknown(ctx, line, &field, RefKind::FUNCTION, id));
                    };
                    if f.unit_id.is_some() && f.unit_id != e.unit_id {
                        notes.push(Notice {
                            line,
                            message: format!(
                                "{field} = {id}: the unit_ID of /FUNCT/{id} is ignored, its values \
                                 are read in the unit system of {}",
                                e.keyword
                            ),
                        });
                    }
                    let law = &mut e.property.dofs[i];
                    let curve = Some(f.curve.clone());
                    match card {
                        0 => law.stiffness_curve = curve,
                        1 => law.viscosity_curve = curve,
                        _ => law.friction_curve = curve,
                    }
                }
            }
            e.property
                .validate()
                .map_err(|err| property_error(ctx, &raw, err))?;
            e.property_si = match &e.unit {
                Some(u) => {
                    property_to_si(&e.property, u).map_err(|err| property_error(ctx, &raw, err))?
                }
                None => e.property.clone(),
            };
            properties.insert(e.id, e);
        }
        self.notices.extend(notes);
        self.notices.sort_by_key(|n| n.line);
        Ok(RadiossDeck {
            file: ctx.file.to_string(),
            properties,
            functions: self.functions,
            skews,
            sensors,
            units: self.units,
            notices: self.notices,
        })
    }
}

fn duplicate(
    ctx: &Ctx,
    b: &Block,
    field: &str,
    what: &'static str,
    id: u32,
    first_line: usize,
) -> DeckError {
    ctx.err(
        b.line,
        field,
        DeckErrorKind::DuplicateId {
            what,
            id,
            first_line,
        },
    )
}

/// Wraps a [`PropertyError`] from `validate()` with the line and Radioss name of the field.
///
/// The property's field names end with the Radioss name in parentheses
/// (`rx.stop_max (SA+)`, `kn (Kn)`, `dy.stops (Icomb = 1)`): that name selects the card.
fn property_error(ctx: &Ctx, raw: &RawProperty, err: PropertyError) -> DeckError {
    let (line, field) = match &err {
        PropertyError::InvalidField { field, .. } => {
            let (dof, rest) = match field.split_once('.') {
                Some((d, rest)) => match Dof::ALL.into_iter().find(|x| x.name() == d) {
                    Some(dof) => (Some(dof), rest),
                    None => (None, field.as_str()),
                },
                None => (None, field.as_str()),
            };
            let name = match (rest.find('('), rest.rfind(')')) {
                (Some(a), Some(b)) if a < b => &rest[a + 1..b],
                _ => rest,
            };
            let name = name.split(' ').next().unwrap_or(name);
            match dof {
                Some(d) => {
                    let name = match name {
                        "FF/FM" if d.is_rotation() => "FM",
                        "FF/FM" => "FF",
                        other => other,
                    };
                    let card = match name {
                        "C" => 1,
                        "Kf" | "FF" | "FM" => 2,
                        _ => 0,
                    };
                    let line = raw.card_lines[d.index()][card].unwrap_or(raw.entry.line);
                    (line, format!("{}.{name}", d.name()))
                }
                None => (raw.first_card, name.to_string()),
            }
        }
        PropertyError::UnknownJointType(_) => (raw.first_card, "Type".to_string()),
        PropertyError::InvalidCurve(_) => (raw.entry.line, "fct_ID".to_string()),
    };
    ctx.err(line, field, DeckErrorKind::Property(err))
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `v / |v|`, robust to huge and tiny components; `None` for a zero or non-finite vector.
fn normalize(v: [f64; 3]) -> Option<[f64; 3]> {
    let m = v.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    if !(m.is_finite() && m > 0.0) {
        return None;
    }
    let s = v.map(|c| c / m);
    let n = s.iter().map(|c| c * c).sum::<f64>().sqrt();
    Some(s.map(|c| c / n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reals() {
        assert_eq!(parse_real(".52"), Ok(0.52));
        assert_eq!(parse_real("  -100 "), Ok(-100.0));
        assert_eq!(parse_real("1e3"), Ok(1e3));
        assert_eq!(parse_real("1.5E+02"), Ok(150.0));
        assert_eq!(parse_real("1.5d3"), Ok(1500.0));
        assert_eq!(parse_real("1.5D-3"), Ok(1.5e-3));
        assert_eq!(parse_real("-1.5+3"), Ok(-1500.0));
        assert_eq!(parse_real("5."), Ok(5.0));
        assert_eq!(parse_real(""), Ok(0.0));
        assert!(matches!(
            parse_real("nan"),
            Err(DeckErrorKind::NotFinite { .. })
        ));
        assert!(matches!(
            parse_real("-Inf"),
            Err(DeckErrorKind::NotFinite { .. })
        ));
        assert!(matches!(
            parse_real("1e999"),
            Err(DeckErrorKind::NotFinite { .. })
        ));
        assert!(matches!(
            parse_real("1.2.3"),
            Err(DeckErrorKind::InvalidNumber { .. })
        ));
        assert!(matches!(
            parse_real("."),
            Err(DeckErrorKind::InvalidNumber { .. })
        ));
        assert!(matches!(
            parse_real("-"),
            Err(DeckErrorKind::InvalidNumber { .. })
        ));
        assert!(matches!(
            parse_real("1-"),
            Err(DeckErrorKind::InvalidNumber { .. })
        ));
    }

    #[test]
    fn ints_and_columns() {
        assert_eq!(parse_int("  +7"), Ok(7));
        assert!(parse_int("2.0").is_err());
        assert_eq!(column("ab", 5, 10), "");
        assert_eq!(column("日本語テキスト", 2, 3), "語テキ");
    }

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
