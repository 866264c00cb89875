//! Reader of riser-analysis flex joint decks: the keywords `*FLEXJOINT`, `*SPRINGPRO` and
//! `*FLEXPROADD` (spec `flexjoint.md`).
//!
//! # Format
//!
//! - Free format: values separated by whitespace, one record per line.
//! - A line whose first non-blank character is `*` starts a keyword block; the keyword is
//!   the first word of the line (case-insensitive), the rest of the line is ignored.
//!   Keywords other than the three below are skipped with a [`DeckNotice`], together with
//!   their data lines.
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
//! expected ([`RiserDeckError`]). The reader never panics, whatever the input.

use crate::dynamics::Kjoint2Builder;
use crate::error::PropertyError;
use crate::law::curve::Curve;
use crate::law::flexjoint::{FlexJointLaw, FlexProAdd};
use crate::law::Kjoint2Property;
use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;
use thiserror::Error;

/// A `*SPRINGPRO` record: a multilinear moment-angle law.
#[derive(Debug, Clone, PartialEq)]
pub struct SpringPro {
    /// `INDEX` of the law.
    pub index: u64,
    /// The `NPAIRS` (angle \[rad\], moment \[N·m\]) pairs as a curve.
    pub curve: Curve,
    /// Line of the record (1-based).
    pub line: usize,
}

/// A `*FLEXPROADD` record.
#[derive(Debug, Clone, PartialEq)]
pub struct FlexProAddRecord {
    /// `IMAT`: record id.
    pub id: u64,
    /// The validated settings.
    pub props: FlexProAdd,
    /// Line of the record (1-based).
    pub line: usize,
}

/// A `*FLEXJOINT` element with its resolved law.
#[derive(Debug, Clone, PartialEq)]
pub struct FlexJointElement {
    /// `NEL`: element id.
    pub id: u64,
    /// `JO`: origin node.
    pub origin_node: u64,
    /// `JE`: end node.
    pub end_node: u64,
    /// `IPRO`: bending (or classical) law index in `*SPRINGPRO` (0 = none).
    pub ipro: u64,
    /// `IMAT`: `*FLEXPROADD` record index (0 = none).
    pub imat: u64,
    /// `IPROT`: torsion law index in `*SPRINGPRO` (0 = none).
    pub iprot: u64,
    /// `LENGTH`: reference length \[m\] (read, unused).
    pub length: f64,
    /// The resolved and validated law.
    pub law: FlexJointLaw,
    /// Line of the record (1-based).
    pub line: usize,
}

impl FlexJointElement {
    /// The KJOINT2 joint of this element: a builder named `FLEXJOINT {NEL}` carrying the
    /// resolved law ([`Kjoint2Builder::flexjoint`]) on `property`, which must be a spherical
    /// joint (type 1; checked when the joint is inserted). The nodes `JO`, `JE` are the
    /// caller's to map onto bodies (body 1 = `JO`, body 2 = `JE`), and the joint's x axis must
    /// be the riser axis: give it with [`Kjoint2Builder::frame`], or let the anchors define it.
    pub fn joint_builder(&self, property: Kjoint2Property) -> Kjoint2Builder {
        Kjoint2Builder::new(property)
            .name(format!("FLEXJOINT {}", self.id))
            .flexjoint(self.law.clone())
    }
}

/// A non-fatal remark of the reader (skipped keyword, ignored field).
#[derive(Debug, Clone, PartialEq)]
pub struct DeckNotice {
    /// Line (1-based).
    pub line: usize,
    /// What happened.
    pub message: String,
}

impl fmt::Display for DeckNotice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

/// The content of a riser deck.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RiserDeck {
    /// `*SPRINGPRO` laws by index.
    pub spring_laws: BTreeMap<u64, SpringPro>,
    /// `*FLEXPROADD` records by id.
    pub flex_props: BTreeMap<u64, FlexProAddRecord>,
    /// `*FLEXJOINT` elements, in file order.
    pub joints: Vec<FlexJointElement>,
    /// Notices (skipped keywords, ignored fields), in file order.
    pub notices: Vec<DeckNotice>,
}

/// What is wrong with a field of a deck.
#[derive(Debug, Clone, PartialEq)]
pub enum DeckErrorKind {
    /// The text is not a number of the expected kind.
    NotANumber {
        /// The text found.
        text: String,
        /// What was expected (e.g. "a non-negative integer").
        expected: &'static str,
    },
    /// The number is NaN or infinite.
    NotFinite {
        /// The text found.
        text: String,
    },
    /// The record ends before this field.
    MissingField,
    /// The record has more values than the keyword allows.
    TooManyFields {
        /// Number of values found.
        found: usize,
        /// Maximum number of values.
        max: usize,
    },
    /// `*SPRINGPRO`: the number of pair values does not match `NPAIRS` (or is odd).
    PairCount {
        /// `NPAIRS` given.
        npairs: u64,
        /// Number of values found after `NPAIRS`.
        values: usize,
    },
    /// An index refers to a record that does not exist.
    UnknownIndex {
        /// The index.
        index: u64,
        /// The keyword whose records it should refer to.
        table: &'static str,
    },
    /// `IFLAG` other than 1.
    UnsupportedIflag(i64),
    /// The same id is defined twice.
    DuplicateId {
        /// The id.
        id: u64,
        /// Line of the first definition.
        first_line: usize,
    },
    /// A value is out of its range or the law is inconsistent.
    InvalidValue(String),
}

impl fmt::Display for DeckErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DeckErrorKind::NotANumber { text, expected } => {
                write!(f, "`{text}` is not a number: expected {expected}")
            }
            DeckErrorKind::NotFinite { text } => {
                write!(f, "`{text}` is not finite: expected a finite number")
            }
            DeckErrorKind::MissingField => write!(f, "missing: the record ends before it"),
            DeckErrorKind::TooManyFields { found, max } => {
                write!(f, "{found} values found: expected at most {max}")
            }
            DeckErrorKind::PairCount { npairs, values } => write!(
                f,
                "NPAIRS = {npairs} but {values} values follow: expected {} values (x y pairs)",
                npairs.saturating_mul(2)
            ),
            DeckErrorKind::UnknownIndex { index, table } => {
                write!(f, "index {index} does not exist: expected the index of a {table} record (or 0 = none)")
            }
            DeckErrorKind::UnsupportedIflag(v) => write!(
                f,
                "IFLAG = {v} is not supported: expected 1 (bilinear elasto-plastic)"
            ),
            DeckErrorKind::DuplicateId { id, first_line } => {
                write!(
                    f,
                    "id {id} already defined at line {first_line}: expected a unique id"
                )
            }
            DeckErrorKind::InvalidValue(m) => write!(f, "{m}"),
        }
    }
}

/// An error reading a riser deck.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RiserDeckError {
    /// The file cannot be read.
    #[error("{file}: cannot read: {message}")]
    Io {
        /// The file.
        file: String,
        /// The system's message.
        message: String,
    },
    /// A field of a record is wrong.
    #[error("{file}:{line}: {keyword} field {field}: {kind}")]
    Input {
        /// The file (or the name given to [`parse_riser_deck`]).
        file: String,
        /// Line (1-based).
        line: usize,
        /// The keyword of the block (`*FLEXJOINT`, ...).
        keyword: String,
        /// The field (`IPRO`, `NPAIRS`, `x2`, ...).
        field: String,
        /// What is wrong and what was expected.
        kind: DeckErrorKind,
    },
}

impl RiserDeckError {
    /// The line of the error (`None` for I/O errors).
    pub fn line(&self) -> Option<usize> {
        match self {
            RiserDeckError::Io { .. } => None,
            RiserDeckError::Input { line, .. } => Some(*line),
        }
    }

    /// The field of the error (`None` for I/O errors).
    pub fn field(&self) -> Option<&str> {
        match self {
            RiserDeckError::Io { .. } => None,
            RiserDeckError::Input { field, .. } => Some(field),
        }
    }

    /// What is wrong (`None` for I/O errors).
    pub fn kind(&self) -> Option<&DeckErrorKind> {
        match self {
            RiserDeckError::Io { .. } => None,
            RiserDeckError::Input { kind, .. } => Some(kind),
        }
    }
}

/// Reads (within the size cap [`super::MAX_INPUT_BYTES`]) and resolves a deck file. See the
/// module documentation for the format.
pub fn read_riser_deck(path: impl AsRef<Path>) -> Result<RiserDeck, RiserDeckError> {
    let path = path.as_ref();
    let file = path.display().to_string();
    let text = super::input::read_input_text(path).map_err(|e| RiserDeckError::Io {
        file: file.clone(),
        message: e.kind.reason(),
    })?;
    parse_riser_deck(&text, &file)
}

#[derive(Clone, Copy, PartialEq)]
enum Block {
    None,
    Skip,
    SpringPro,
    FlexProAdd,
    FlexJoint,
}

impl Block {
    fn keyword(self) -> &'static str {
        match self {
            Block::SpringPro => "*SPRINGPRO",
            Block::FlexProAdd => "*FLEXPROADD",
            Block::FlexJoint => "*FLEXJOINT",
            Block::None | Block::Skip => "",
        }
    }
}

/// A raw `*FLEXJOINT` record before resolution.
struct RawJoint {
    id: u64,
    origin_node: u64,
    end_node: u64,
    ipro: u64,
    imat: u64,
    length: f64,
    iprot: u64,
    line: usize,
}

/// Parsing context of one record line.
struct Rec<'a> {
    file: &'a str,
    line: usize,
    keyword: &'static str,
    tokens: Vec<&'a str>,
}

impl<'a> Rec<'a> {
    fn err(&self, field: &str, kind: DeckErrorKind) -> RiserDeckError {
        RiserDeckError::Input {
            file: self.file.to_string(),
            line: self.line,
            keyword: self.keyword.to_string(),
            field: field.to_string(),
            kind,
        }
    }

    fn token(&self, i: usize, field: &str) -> Result<&'a str, RiserDeckError> {
        self.tokens
            .get(i)
            .copied()
            .ok_or_else(|| self.err(field, DeckErrorKind::MissingField))
    }

    fn real(&self, i: usize, field: &str) -> Result<f64, RiserDeckError> {
        let t = self.token(i, field)?;
        parse_real(t).map_err(|k| self.err(field, k))
    }

    fn int(&self, i: usize, field: &str) -> Result<i64, RiserDeckError> {
        let t = self.token(i, field)?;
        let v = parse_real(t).map_err(|k| {
            self.err(
                field,
                match k {
                    DeckErrorKind::NotANumber { text, .. } => DeckErrorKind::NotANumber {
                        text,
                        expected: "an integer",
                    },
                    k => k,
                },
            )
        })?;
        // Integral and within the exactly representable range.
        if v.fract() == 0.0 && v.abs() <= 9.007_199_254_740_992e15 {
            Ok(v as i64)
        } else {
            Err(self.err(
                field,
                DeckErrorKind::NotANumber {
                    text: t.to_string(),
                    expected: "an integer",
                },
            ))
        }
    }

    fn uint(&self, i: usize, field: &str) -> Result<u64, RiserDeckError> {
        let v = self.int(i, field)?;
        u64::try_from(v).map_err(|_| {
            self.err(
                field,
                DeckErrorKind::NotANumber {
                    text: self.tokens.get(i).copied().unwrap_or("").to_string(),
                    expected: "a non-negative integer",
                },
            )
        })
    }

    fn at_most(&self, max: usize) -> Result<(), RiserDeckError> {
        if self.tokens.len() > max {
            Err(self.err(
                "(end of record)",
                DeckErrorKind::TooManyFields {
                    found: self.tokens.len(),
                    max,
                },
            ))
        } else {
            Ok(())
        }
    }
}

/// Parses a real (Rust or Fortran `D` exponent syntax), rejecting NaN and infinities.
fn parse_real(t: &str) -> Result<f64, DeckErrorKind> {
    let normalized: String = t
        .chars()
        .map(|c| if c == 'd' || c == 'D' { 'e' } else { c })
        .collect();
    match normalized.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(DeckErrorKind::NotFinite {
            text: t.to_string(),
        }),
        Err(_) => Err(DeckErrorKind::NotANumber {
            text: t.to_string(),
            expected: "a real number",
        }),
    }
}

fn invalid(e: PropertyError) -> DeckErrorKind {
    DeckErrorKind::InvalidValue(e.to_string())
}

/// Parses and resolves the text of a deck; `file` names it in errors. See the module
/// documentation for the format.
pub fn parse_riser_deck(text: &str, file: &str) -> Result<RiserDeck, RiserDeckError> {
    let mut deck = RiserDeck::default();
    let mut raw_joints: Vec<RawJoint> = Vec::new();
    let mut joint_lines: BTreeMap<u64, usize> = BTreeMap::new();
    let mut block = Block::None;

    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.trim();
        let Some(first) = content.chars().next() else {
            continue;
        };
        if first == '*' {
            let kw = content
                .split_whitespace()
                .next()
                .unwrap_or("")
                .to_ascii_uppercase();
            block = match kw.as_str() {
                "*SPRINGPRO" => Block::SpringPro,
                "*FLEXPROADD" => Block::FlexProAdd,
                "*FLEXJOINT" => Block::FlexJoint,
                _ => {
                    deck.notices.push(DeckNotice {
                        line,
                        message: format!("keyword {kw} is not read by this reader: block skipped"),
                    });
                    Block::Skip
                }
            };
            continue;
        }
        if first == 'c' || first == 'C' {
            continue;
        }
        let rec = Rec {
            file,
            line,
            keyword: block.keyword(),
            tokens: content.split_whitespace().collect(),
        };
        match block {
            Block::Skip => {}
            Block::None => deck.notices.push(DeckNotice {
                line,
                message: "data line before any keyword: skipped".into(),
            }),
            Block::SpringPro => {
                let index = rec.uint(0, "INDEX")?;
                let npairs = rec.uint(1, "NPAIRS")?;
                let values = rec.tokens.len() - 2;
                if npairs == 0 {
                    return Err(rec.err(
                        "NPAIRS",
                        DeckErrorKind::InvalidValue(
                            "NPAIRS = 0: expected at least one (angle, moment) pair".into(),
                        ),
                    ));
                }
                if values % 2 != 0 || (values / 2) as u64 != npairs {
                    return Err(rec.err("NPAIRS", DeckErrorKind::PairCount { npairs, values }));
                }
                let mut pts = Vec::with_capacity(values / 2);
                for k in 0..values / 2 {
                    let x = rec.real(2 + 2 * k, &format!("x{}", k + 1))?;
                    let y = rec.real(3 + 2 * k, &format!("y{}", k + 1))?;
                    pts.push((x, y));
                }
                let curve = Curve::new(pts).map_err(|e| rec.err("pairs", invalid(e)))?;
                if let Some(prev) = deck.spring_laws.get(&index) {
                    return Err(rec.err(
                        "INDEX",
                        DeckErrorKind::DuplicateId {
                            id: index,
                            first_line: prev.line,
                        },
                    ));
                }
                deck.spring_laws
                    .insert(index, SpringPro { index, curve, line });
            }
            Block::FlexProAdd => {
                rec.at_most(8)?;
                let id = rec.uint(0, "IMAT")?;
                let torsion_stiffness = rec.real(1, "Ktor")?;
                let iflag = rec.int(2, "IFLAG")?;
                if iflag != 1 {
                    return Err(rec.err("IFLAG", DeckErrorKind::UnsupportedIflag(iflag)));
                }
                let props = FlexProAdd {
                    torsion_stiffness,
                    iflag,
                    kdyn_ini: rec.real(3, "Kdyn_ini")?,
                    kdyn_lim: rec.real(4, "Kdyn_lim")?,
                    angle_lim: rec.real(5, "Angle_lim")?,
                    teta: rec.real(6, "Teta")?,
                    torsion_damping: rec.real(7, "CP")?,
                };
                props.validate().map_err(|e| {
                    let field = match &e {
                        PropertyError::InvalidField { field, .. } => field.clone(),
                        _ => "IMAT".into(),
                    };
                    rec.err(&field, invalid(e))
                })?;
                if let Some(prev) = deck.flex_props.get(&id) {
                    return Err(rec.err(
                        "IMAT",
                        DeckErrorKind::DuplicateId {
                            id,
                            first_line: prev.line,
                        },
                    ));
                }
                if props.teta != 0.0 {
                    deck.notices.push(DeckNotice {
                        line,
                        message: format!(
                            "warning: *FLEXPROADD {id}: Teta = {} is read and ignored (its meaning is not documented)",
                            props.teta
                        ),
                    });
                }
                deck.flex_props
                    .insert(id, FlexProAddRecord { id, props, line });
            }
            Block::FlexJoint => {
                rec.at_most(7)?;
                let j = RawJoint {
                    id: rec.uint(0, "NEL")?,
                    origin_node: rec.uint(1, "JO")?,
                    end_node: rec.uint(2, "JE")?,
                    ipro: rec.uint(3, "IPRO")?,
                    imat: rec.uint(4, "IMAT")?,
                    length: rec.real(5, "LENGTH")?,
                    iprot: if rec.tokens.len() > 6 {
                        rec.uint(6, "IPROT")?
                    } else {
                        0
                    },
                    line,
                };
                if let Some(&first_line) = joint_lines.get(&j.id) {
                    return Err(rec.err(
                        "NEL",
                        DeckErrorKind::DuplicateId {
                            id: j.id,
                            first_line,
                        },
                    ));
                }
                joint_lines.insert(j.id, line);
                raw_joints.push(j);
            }
        }
    }

    for j in raw_joints {
        let rec = Rec {
            file,
            line: j.line,
            keyword: "*FLEXJOINT",
            tokens: Vec::new(),
        };
        let spring = |index: u64, field: &str| -> Result<Option<Curve>, RiserDeckError> {
            if index == 0 {
                return Ok(None);
            }
            deck.spring_laws
                .get(&index)
                .map(|s| Some(s.curve.clone()))
                .ok_or_else(|| {
                    rec.err(
                        field,
                        DeckErrorKind::UnknownIndex {
                            index,
                            table: "*SPRINGPRO",
                        },
                    )
                })
        };
        let bending = spring(j.ipro, "IPRO")?;
        let torsion = spring(j.iprot, "IPROT")?;
        let dynamic = if j.imat == 0 {
            None
        } else {
            Some(
                deck.flex_props
                    .get(&j.imat)
                    .map(|r| r.props)
                    .ok_or_else(|| {
                        rec.err(
                            "IMAT",
                            DeckErrorKind::UnknownIndex {
                                index: j.imat,
                                table: "*FLEXPROADD",
                            },
                        )
                    })?,
            )
        };
        if let (Some(d), true) = (&dynamic, torsion.is_some()) {
            if d.torsion_stiffness != 0.0 {
                deck.notices.push(DeckNotice {
                    line: j.line,
                    message: format!(
                        "*FLEXJOINT {}: IPROT = {} is given, so Ktor = {} of *FLEXPROADD {} is ignored",
                        j.id, j.iprot, d.torsion_stiffness, j.imat
                    ),
                });
            }
        }
        let law = FlexJointLaw::new(bending, torsion, dynamic).map_err(|e| {
            let field = match &e {
                PropertyError::InvalidField { field, .. } => field.clone(),
                _ => "IPRO".into(),
            };
            rec.err(&field, invalid(e))
        })?;
        deck.joints.push(FlexJointElement {
            id: j.id,
            origin_node: j.origin_node,
            end_node: j.end_node,
            ipro: j.ipro,
            imat: j.imat,
            iprot: j.iprot,
            length: j.length,
            law,
            line: j.line,
        });
    }
    deck.notices.sort_by_key(|n| n.line);
    Ok(deck)
}
