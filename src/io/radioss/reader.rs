//! The reader's state while a deck is read ([`Reader`]), the dispatch of each block to its
//! parser, the notices of skipped blocks and the parts every block shares: the ids of the
//! keyword line, the title card and the cards left over.

use std::collections::{BTreeMap, HashMap};

use super::blocks::{split_blocks, Block};
use super::fields::Fields;
use super::keywords::{RADIOSS_KEYWORDS, READ_KEYWORDS};
use super::kjoint2::RawProperty;
use super::{DeckError, DeckErrorKind, Function, Notice, RadiossDeck, SkewFix, TimeSensor};
use super::{InputUnits, UnitEntry};
use crate::io::diagnostic::{likely_keyword, parse_int, NumberSyntax};
use crate::io::units::UnitSystem;

/// What has been read so far; [`Reader::finish`](super::finish) resolves it into a
/// [`RadiossDeck`].
pub(super) struct Reader<'f> {
    /// Reads the fields of the file's cards.
    pub(super) fields: Fields<'f>,
    pub(super) notices: Vec<Notice>,
    /// KJOINT2 blocks in file order.
    pub(super) props: Vec<RawProperty>,
    pub(super) functions: BTreeMap<u32, Function>,
    pub(super) skews: BTreeMap<u32, SkewFix>,
    pub(super) sensors: BTreeMap<u32, TimeSensor>,
    pub(super) units: BTreeMap<u32, UnitEntry>,
    /// The input units of `/BEGIN`, once read.
    pub(super) input_units: Option<InputUnits>,
    /// The work units of `/BEGIN` (SI without one, or where blank): the units of `ScF`
    /// when `Kn > 0`, which Radioss does not convert (see `finish.rs`).
    pub(super) work_units: UnitSystem,
    /// Ids of functions, skews and sensors defined by blocks this reader skips:
    /// `(kind, id) -> (keyword, line)`.
    pub(super) skipped: HashMap<(RefKind, u32), (String, usize)>,
}

/// A kind of referenced block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(super) enum RefKind {
    Function,
    Skew,
    Sensor,
    Unit,
}

impl RefKind {
    /// Its name in messages.
    fn what(self) -> &'static str {
        match self {
            RefKind::Function => "function",
            RefKind::Skew => "skew",
            RefKind::Sensor => "sensor",
            RefKind::Unit => "unit system",
        }
    }

    /// The keyword this reader accepts for it.
    fn keyword(self) -> &'static str {
        match self {
            RefKind::Function => "/FUNCT",
            RefKind::Skew => "/SKEW/FIX",
            RefKind::Sensor => "/SENSOR/TIME",
            RefKind::Unit => "/UNIT",
        }
    }
}

/// The keyword line and title of a block that defines an id: [`Reader::heading`].
pub(super) struct Heading {
    /// The block's id.
    pub(super) id: u32,
    /// Its `unit_ID` (`None` = none).
    pub(super) unit_id: Option<u32>,
    /// Its title card, trailing blanks removed.
    pub(super) title: String,
}

/// How a block names its id and title: [`Reader::heading`].
pub(super) struct HeadingForm {
    /// Index of the id among the keyword's parts (`/SKEW/FIX/id`: 2).
    pub(super) at: usize,
    /// The id's field name (`skew_ID`).
    pub(super) id_field: &'static str,
    /// The title's field name (`skew_title`).
    pub(super) title_field: &'static str,
    /// The kind of block in a duplicate-id error (`skew`).
    pub(super) what: &'static str,
    /// Whether a `/unit_ID` may follow the id.
    pub(super) unit: bool,
}

impl<'f> Reader<'f> {
    /// Reads the deck `text` of file `file`.
    pub(super) fn read(text: &str, file: &'f str) -> Result<RadiossDeck, DeckError> {
        let mut reader = Reader {
            fields: Fields { file },
            notices: Vec::new(),
            props: Vec::new(),
            functions: BTreeMap::new(),
            skews: BTreeMap::new(),
            sensors: BTreeMap::new(),
            units: BTreeMap::new(),
            input_units: None,
            work_units: UnitSystem::SI,
            skipped: HashMap::new(),
        };
        let blocks = split_blocks(text, file, &mut reader.notices);
        for block in &blocks {
            reader.block(block)?;
        }
        reader.finish()
    }

    pub(super) fn notice(&mut self, line: usize, message: impl Into<String>) {
        self.notices
            .push(Notice::new(self.fields.file, line, message));
    }

    /// Reads one block; an error in it names the block's keyword line.
    fn block(&mut self, b: &Block) -> Result<(), DeckError> {
        self.block_contents(b).map_err(|e| {
            if e.block.is_empty() && e.line > 0 {
                e.in_block(b.name())
            } else {
                e
            }
        })
    }

    fn block_contents(&mut self, b: &Block) -> Result<(), DeckError> {
        let (p0, p1) = (b.part(0), b.part(1));
        match (p0.as_str(), p1.as_str()) {
            ("PROP", "TYPE45" | "KJOINT2") => self.kjoint2(b),
            // `/PROP/TYP45`: no property type of Radioss (those are `TYPE<n>` or named), an
            // error at its line as a misspelt keyword is (it was skipped with a notice, and
            // the deck then had no KJOINT2 property, said without a line)
            ("PROP", sub) if sub.starts_with("TYP") && !is_property_type_number(sub) => {
                Err(self.fields.error(
                    b.line,
                    "keyword",
                    DeckErrorKind::UnknownKeyword {
                        keyword: format!("/PROP/{sub}"),
                        likely: Some("/PROP/TYPE45".into()),
                        reason: "not a property type of Radioss (`TYPE<n>`, or a name such as \
                                 KJOINT2)"
                            .into(),
                    },
                ))
            }
            ("FUNCT", _) => self.funct(b),
            ("UNIT", _) => self.unit(b),
            ("BEGIN", "") => self.begin(b),
            ("SKEW", "FIX") => self.skew(b),
            ("SENSOR", "TIME") => self.sensor(b),
            _ if !p0.is_empty() && !RADIOSS_KEYWORDS.contains(&p0.as_str()) => {
                Err(self.unknown_keyword(b, &p0))
            }
            _ => {
                self.skip(b, &p0);
                Ok(())
            }
        }
    }

    /// The error of a keyword `/p0/...` that Radioss does not have (module `keywords`), at
    /// its line, with the known keyword it most likely means.
    fn unknown_keyword(&self, b: &Block, p0: &str) -> DeckError {
        let known: Vec<&str> = READ_KEYWORDS
            .iter()
            .chain(
                RADIOSS_KEYWORDS
                    .iter()
                    .filter(|k| !READ_KEYWORDS.contains(k)),
            )
            .copied()
            .collect();
        let likely = likely_keyword(p0, &known).map(|(k, _)| format!("/{k}"));
        let kind = DeckErrorKind::UnknownKeyword {
            keyword: format!("/{p0}"),
            likely,
            reason: "not a keyword of Radioss (OpenRadioss refuses it too)".into(),
        };
        self.fields.error(b.line, "keyword", kind)
    }

    fn skip(&mut self, b: &Block, p0: &str) {
        // Where the id sits in keywords that define an id another block may reference.
        let kind_at = match p0 {
            "SKEW" => Some((RefKind::Skew, 2)),
            "SENSOR" => Some((RefKind::Sensor, 2)),
            "FUNCT_SMOOTH" => Some((RefKind::Function, 1)),
            "TABLE" => Some((RefKind::Function, 2)),
            _ => None,
        };
        if let Some((kind, at)) = kind_at {
            if let Some(id) = b.parts.get(at).and_then(|t| t.parse::<u32>().ok()) {
                self.skipped.entry((kind, id)).or_insert((b.name(), b.line));
            }
        }
        let message = if p0 == "PROP" {
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
    pub(super) fn ids(
        &self,
        b: &Block,
        at: usize,
        id_name: &str,
        allow_unit: bool,
    ) -> Result<(u32, Option<u32>), DeckError> {
        let fields = self.fields;
        let form = {
            let head: Vec<&str> = b.parts.iter().take(at).copied().collect();
            let unit = if allow_unit { "[/unit_ID]" } else { "" };
            format!("/{}/{id_name}{unit}", head.join("/"))
        };
        let bad = |field: &str| {
            let kind = DeckErrorKind::InvalidKeyword {
                text: b.name(),
                expected: form.clone(),
            };
            fields.error(b.line, field, kind)
        };
        let id_text = b.parts.get(at).copied().unwrap_or("");
        if id_text.is_empty() {
            return Err(bad(id_name));
        }
        let int = |t: &str, field: &str| {
            parse_int(t, NumberSyntax::FixedWidth).map_err(|k| fields.error(b.line, field, k))
        };
        let id = int(id_text, id_name)?;
        let id = match u32::try_from(id) {
            Ok(id) if id > 0 => id,
            _ => {
                let expected = format!("an id in 1..={}", u32::MAX);
                return Err(fields.invalid_value(b.line, id_name, id, expected));
            }
        };
        let mut unit = None;
        let mut next = at + 1;
        if allow_unit {
            if let Some(t) = b.parts.get(at + 1).filter(|t| !t.is_empty()) {
                let v = fields.id_value(b.line, "unit_ID", int(t, "unit_ID")?)?;
                unit = (v != 0).then_some(v);
            }
            next += 1;
        }
        if b.parts.iter().skip(next).any(|t| !t.is_empty()) {
            return Err(bad("keyword"));
        }
        Ok((id, unit))
    }

    /// The block's first line (its title), trailing blanks removed.
    pub(super) fn title(&self, b: &Block, field: &str) -> Result<String, DeckError> {
        b.body
            .first()
            .map(|l| l.text.trim_end().to_string())
            .ok_or_else(|| self.fields.missing(b, field, field))
    }

    /// The id, `unit_ID` and title of block `b`, written in `form`; `defined_at` gives the
    /// line of the block of this kind that already has an id (`None` = none has).
    pub(super) fn heading(
        &self,
        b: &Block,
        form: &HeadingForm,
        defined_at: impl Fn(&Self, u32) -> Option<usize>,
    ) -> Result<Heading, DeckError> {
        let (id, unit_id) = self.ids(b, form.at, form.id_field, form.unit)?;
        if let Some(first) = defined_at(self, id) {
            return Err(self
                .fields
                .duplicate(b, form.id_field, form.what, id, first));
        }
        let title = self.title(b, form.title_field)?;
        Ok(Heading { id, unit_id, title })
    }

    /// A notice if `b` has non-blank cards after its first `used` ones.
    pub(super) fn extra_cards(&mut self, b: &Block, used: usize) {
        if let Some(l) = b.body.iter().skip(used).find(|l| !l.is_blank()) {
            let (no, name) = (l.no, b.name());
            self.notice(
                no,
                format!("extra cards in {name} ignored (from this line on)"),
            );
        }
    }

    /// The unit system of a keyword's values: that of its `unit_ID` (an error at `line` if
    /// it is not defined), else `/BEGIN`'s input units (`None` = SI).
    pub(super) fn unit_of(
        &self,
        line: usize,
        id: Option<u32>,
    ) -> Result<Option<UnitSystem>, DeckError> {
        match id {
            None => Ok(self
                .input_units
                .as_ref()
                .map(|u| u.system)
                .filter(|s| *s != UnitSystem::SI)),
            Some(id) => match self.units.get(&id) {
                Some(u) => Ok(Some(u.system)),
                None => Err(self.unknown(line, "unit_ID", RefKind::Unit, id)),
            },
        }
    }

    /// Error for a reference to an id that no read block defines.
    pub(super) fn unknown(&self, line: usize, field: &str, r: RefKind, id: u32) -> DeckError {
        let keyword = r.keyword();
        let note = match self.skipped.get(&(r, id)) {
            Some((kw, at)) => {
                // `/SENSOR/TIM/3` for `/SENSOR/TIME/3`: the subtype the reader reads, if close
                let read = keyword.rsplit('/').next().unwrap_or_default();
                let written = kw.split('/').nth(2).unwrap_or_default().trim();
                let misspelt = match likely_keyword(written, &[read]) {
                    Some(_) => format!(": a misspelt {keyword}?"),
                    None => String::new(),
                };
                format!(
                    " as a {keyword} block (it is defined by {kw} at line {at}, which this \
                     reader does not support{misspelt})"
                )
            }
            None => format!(" (no {keyword} block with this id)"),
        };
        let kind = DeckErrorKind::UnknownReference {
            what: r.what(),
            id: id.into(),
            note,
        };
        self.fields.error(line, field, kind)
    }
}

/// `TYPE<n>`: a property type of Radioss by its number.
fn is_property_type_number(sub: &str) -> bool {
    sub.strip_prefix("TYPE")
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|c| c.is_ascii_digit()))
}
