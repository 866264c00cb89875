//! The line loop of the riser reader: blank and comment lines, keyword lines (a known
//! keyword opens its block, a keyword close to a known one is an error, another one is
//! skipped with a notice) and the dispatch of each record to the parser of its keyword; the
//! `*FLEXJOINT` elements are resolved at the end.

use std::collections::BTreeMap;

use super::flex_joint::RawJoint;
use super::record::Record;
use super::{DeckError, DeckErrorKind, Notice, RiserDeck};
use crate::io::diagnostic::{likely_keyword, Closeness};

/// The keywords the reader reads.
pub(super) const KEYWORDS: [&str; 3] = ["*SPRINGPRO", "*FLEXPROADD", "*FLEXJOINT"];

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
    /// The keywords skipped as unknown, `(line, keyword)` in file order: named by an error
    /// of a missing law or record, which one of them may have meant to define.
    pub(super) skipped: Vec<(usize, String)>,
    /// The first data line before any keyword, skipped (a deck whose first keyword line is
    /// missing): named by the same errors.
    pub(super) orphan_line: Option<usize>,
}

impl<'f> Reader<'f> {
    /// Reads and resolves the deck `text` of file `file`.
    pub(super) fn read(text: &str, file: &'f str) -> Result<RiserDeck, DeckError> {
        let mut reader = Reader {
            file,
            deck: RiserDeck::default(),
            raw_joints: Vec::new(),
            joint_lines: BTreeMap::new(),
            skipped: Vec::new(),
            orphan_line: None,
        };
        let mut keyword = Keyword::None;
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let content = raw.trim();
            let Some(first) = content.chars().next() else {
                continue;
            };
            if first == '*' {
                keyword = reader.keyword(line, content)?;
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

    /// The block a keyword line opens. A keyword close to one of the three the reader reads
    /// (within the edits of [`Closeness::Edits`], or one of them with more after it:
    /// `*FLEXPROAD`, `*FLEXJOINTS`) is an error naming it: skipped, its block's records went
    /// missing without a word (an element of `*FLEXJOINTS` disappeared, `check` said ok).
    /// Any other keyword belongs to the rest of a riser-analysis deck and is skipped with a
    /// notice (and named by the error of a missing law or record, [`Self::skipped_note`]).
    fn keyword(&mut self, line: usize, content: &str) -> Result<Keyword, DeckError> {
        let kw = content
            .split_whitespace()
            .next()
            .unwrap_or("")
            .to_ascii_uppercase();
        Ok(match kw.as_str() {
            "*SPRINGPRO" => Keyword::SpringPro,
            "*FLEXPROADD" => Keyword::FlexProAdd,
            "*FLEXJOINT" => Keyword::FlexJoint,
            _ => {
                if let Some((likely, Closeness::Edits(_) | Closeness::Extends)) =
                    likely_keyword(&kw, &KEYWORDS)
                {
                    let kind = DeckErrorKind::UnknownKeyword {
                        keyword: kw,
                        likely: Some(likely.into()),
                        reason: format!(
                            "refused rather than skipped: this close to a keyword the reader \
                             reads ({}), its records would go missing",
                            KEYWORDS.join(", ")
                        ),
                    };
                    return Err(DeckError::new(self.file, line, "keyword", kind));
                }
                let message = format!("keyword {kw} is not read by this reader: block skipped");
                self.notice(line, message);
                self.skipped.push((line, kw));
                Keyword::Skip
            }
        })
    }

    /// What to add to the error of a missing `wanted` law or record (`*SPRINGPRO`) when the
    /// deck skipped unknown keywords: they are the likely cause. Those that may be a
    /// misspelt `wanted` ([`likely_keyword`]) are named alone, with the question; else all
    /// (the first three). Empty when none was skipped.
    pub(super) fn skipped_note(&self, wanted: &str) -> String {
        let misspelt: Vec<&(usize, String)> = self
            .skipped
            .iter()
            .filter(|(_, kw)| likely_keyword(kw, &[wanted]).is_some())
            .collect();
        let (named, question) = if misspelt.is_empty() {
            (self.skipped.iter().collect::<Vec<_>>(), String::new())
        } else {
            (misspelt, format!(": a misspelt {wanted}?"))
        };
        // (data the deck skipped before its first keyword: a missing keyword line, most
        // likely the wanted one; a riser engineer's trial, 2026-12-04)
        let orphans = self.orphan_line.map_or(String::new(), |line| {
            format!("; the deck skipped its data from line {line}, before any keyword: a missing {wanted} line?")
        });
        let Some(&(first_line, first)) = named.first() else {
            return orphans;
        };
        if named.len() == 1 {
            return format!(
                "; the deck skipped {first} at line {first_line} as an unknown keyword{question}"
            );
        }
        let mut list: Vec<String> = named
            .iter()
            .take(3)
            .map(|(line, kw)| format!("{kw} at line {line}"))
            .collect();
        if named.len() > 3 {
            list.push(format!("{} more", named.len() - 3));
        }
        let last = list.pop().unwrap_or_default();
        format!(
            "; the deck skipped {} and {last} as unknown keywords{question}",
            list.join(", ")
        )
    }

    fn record(&mut self, keyword: Keyword, record: &Record) -> Result<(), DeckError> {
        match keyword {
            Keyword::Skip => Ok(()),
            Keyword::None => {
                self.notice(record.line, "data line before any keyword: skipped");
                self.orphan_line.get_or_insert(record.line);
                Ok(())
            }
            Keyword::SpringPro => self.springpro(record),
            Keyword::FlexProAdd => self.flexproadd(record),
            Keyword::FlexJoint => self.flex_joint(record),
        }
    }
}
