//! The reader's state while a deck is read ([`Reader`]), the dispatch of each block to its
//! parser, the notices of skipped blocks and the parts every block shares: the ids of the
//! keyword line, the title card and the cards left over.

use std::collections::{BTreeMap, HashMap};

use super::blocks::{split_blocks, Block};
use super::fields::Fields;
use super::kjoint2::RawProperty;
use super::{DeckError, DeckErrorKind, Function, Notice, RadiossDeck, SkewFix, TimeSensor};
use super::UnitEntry;
use crate::io::units::UnitSystem;
use crate::io::diagnostic::{parse_int, NumberSyntax};

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
    /// Ids of functions, skews and sensors defined by blocks this reader skips:
    /// `(kind, id) -> (keyword, line)`.
    pub(super) skipped: HashMap<(&'static str, u32), (String, usize)>,
}

/// A kind of referenced block: its name in messages, its key in `Reader::skipped`, and the
/// keyword this reader accepts for it.
#[derive(Clone, Copy)]
pub(super) struct RefKind {
    pub(super) what: &'static str,
    pub(super) key: &'static str,
    pub(super) keyword: &'static str,
}

impl RefKind {
    pub(super) const FUNCTION: RefKind = RefKind {
        what: "function",
        key: "function",
        keyword: "/FUNCT",
    };
    pub(super) const SKEW: RefKind = RefKind {
        what: "skew",
        key: "skew",
        keyword: "/SKEW/FIX",
    };
    pub(super) const SENSOR: RefKind = RefKind {
        what: "sensor",
        key: "sensor",
        keyword: "/SENSOR/TIME",
    };
    pub(super) const UNIT: RefKind = RefKind {
        what: "unit system",
        key: "unit",
        keyword: "/UNIT",
    };
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

    fn block(&mut self, b: &Block) -> Result<(), DeckError> {
        let (p0, p1) = (b.part(0), b.part(1));
        match (p0.as_str(), p1.as_str()) {
            ("PROP", "TYPE45" | "KJOINT2") => self.kjoint2(b),
            ("FUNCT", _) => self.funct(b),
            ("UNIT", _) => self.unit(b),
            ("SKEW", "FIX") => self.skew(b),
            ("SENSOR", "TIME") => self.sensor(b),
            _ => {
                self.skip(b, &p0);
                Ok(())
            }
        }
    }

    fn skip(&mut self, b: &Block, p0: &str) {
        // Where the id sits in keywords that define an id another block may reference.
        let kind_at = match p0 {
            "SKEW" => Some((RefKind::SKEW.key, 2)),
            "SENSOR" => Some((RefKind::SENSOR.key, 2)),
            "FUNCT_SMOOTH" => Some((RefKind::FUNCTION.key, 1)),
            "TABLE" => Some((RefKind::FUNCTION.key, 2)),
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

    /// The unit system `id` (`None` = none), or an error at `line` if it is not defined.
    pub(super) fn unit_of(
        &self,
        line: usize,
        id: Option<u32>,
    ) -> Result<Option<UnitSystem>, DeckError> {
        match id {
            None => Ok(None),
            Some(id) => match self.units.get(&id) {
                Some(u) => Ok(Some(u.system)),
                None => Err(self.unknown(line, "unit_ID", RefKind::UNIT, id)),
            },
        }
    }

    /// Error for a reference to an id that no read block defines.
    pub(super) fn unknown(&self, line: usize, field: &str, r: RefKind, id: u32) -> DeckError {
        let keyword = r.keyword;
        let note = match self.skipped.get(&(r.key, id)) {
            Some((kw, at)) => format!(
                " as a {keyword} block (it is defined by {kw} at line {at}, which this reader \
                 does not support)"
            ),
            None => format!(" (no {keyword} block with this id)"),
        };
        let kind = DeckErrorKind::UnknownReference {
            what: r.what,
            id: id.into(),
            note,
        };
        self.fields.error(line, field, kind)
    }
}
