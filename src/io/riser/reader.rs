//! The line loop of the riser reader: blank and comment lines, keyword lines (a known
//! keyword opens its block, another one is skipped with a notice) and the dispatch of each
//! record to the parser of its keyword; the `*FLEXJOINT` elements are resolved at the end.

use std::collections::BTreeMap;

use super::flex_joint::RawJoint;
use super::record::Record;
use super::{DeckError, Notice, RiserDeck};

/// The block the reader is in.
#[derive(Clone, Copy, PartialEq)]
enum Keyword {
    /// Before any keyword.
    None,
    /// A keyword this reader does not read.
    Skip,
    SpringPro,
    FlexProAdd,
    FlexJoint,
}

impl Keyword {
    fn name(self) -> &'static str {
        match self {
            Keyword::SpringPro => "*SPRINGPRO",
            Keyword::FlexProAdd => "*FLEXPROADD",
            Keyword::FlexJoint => "*FLEXJOINT",
            Keyword::None | Keyword::Skip => "",
        }
    }
}

/// What has been read so far.
pub(super) struct Reader<'f> {
    /// The file name given to the reader.
    pub(super) file: &'f str,
    pub(super) deck: RiserDeck,
    /// `*FLEXJOINT` records before their indices are resolved, in file order.
    pub(super) raw_joints: Vec<RawJoint>,
    /// Line of each `*FLEXJOINT` element by `NEL`.
    pub(super) joint_lines: BTreeMap<u64, usize>,
}

impl<'f> Reader<'f> {
    /// Reads and resolves the deck `text` of file `file`.
    pub(super) fn read(text: &str, file: &'f str) -> Result<RiserDeck, DeckError> {
        let mut reader = Reader {
            file,
            deck: RiserDeck::default(),
            raw_joints: Vec::new(),
            joint_lines: BTreeMap::new(),
        };
        let mut keyword = Keyword::None;
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let content = raw.trim();
            let Some(first) = content.chars().next() else {
                continue;
            };
            if first == '*' {
                keyword = reader.keyword(line, content);
            } else if first != 'c' && first != 'C' {
                let record = Record {
                    file,
                    line,
                    keyword: keyword.name(),
                    tokens: content.split_whitespace().collect(),
                };
                reader.record(keyword, &record)?;
            }
        }
        reader.resolve_joints()?;
        reader.deck.notices.sort_by_key(|n| n.line);
        Ok(reader.deck)
    }

    pub(super) fn notice(&mut self, line: usize, message: impl Into<String>) {
        self.deck
            .notices
            .push(Notice::new(self.file, line, message));
    }

    /// The block a keyword line opens.
    fn keyword(&mut self, line: usize, content: &str) -> Keyword {
        let kw = content
            .split_whitespace()
            .next()
            .unwrap_or("")
            .to_ascii_uppercase();
        match kw.as_str() {
            "*SPRINGPRO" => Keyword::SpringPro,
            "*FLEXPROADD" => Keyword::FlexProAdd,
            "*FLEXJOINT" => Keyword::FlexJoint,
            _ => {
                let message = format!("keyword {kw} is not read by this reader: block skipped");
                self.notice(line, message);
                Keyword::Skip
            }
        }
    }

    fn record(&mut self, keyword: Keyword, record: &Record) -> Result<(), DeckError> {
        match keyword {
            Keyword::Skip => Ok(()),
            Keyword::None => {
                self.notice(record.line, "data line before any keyword: skipped");
                Ok(())
            }
            Keyword::SpringPro => self.springpro(record),
            Keyword::FlexProAdd => self.flexproadd(record),
            Keyword::FlexJoint => self.flex_joint(record),
        }
    }
}
