//! The fields of a fixed-width card: a line of the deck ([`Line`]), the characters of a
//! column ([`column`]), and [`Fields`], which reads a column as a real, an integer, an id
//! or a text and turns what is wrong into a [`DeckError`] naming the file, line and field.
//!
//! Numbers are parsed by [`crate::io::diagnostic::parse_real`] and
//! [`crate::io::diagnostic::parse_int`] in the fixed-width syntax.

use super::blocks::Block;
use crate::io::diagnostic::{parse_int, parse_real, DeckError, DeckErrorKind, NumberSyntax};

/// One line of the deck.
#[derive(Debug, Clone, Copy)]
pub(super) struct Line<'a> {
    /// 1-based line number.
    pub(super) no: usize,
    /// The line's text (without its end of line).
    pub(super) text: &'a str,
}

impl Line<'_> {
    pub(super) fn is_blank(&self) -> bool {
        self.text.trim().is_empty()
    }
}

/// `width` characters from character `start` (fewer, or none, on a short line).
pub(super) fn column(text: &str, start: usize, width: usize) -> String {
    text.chars().skip(start).take(width).collect()
}

/// Reads the fields of the cards of one file: every error names this file.
#[derive(Debug, Clone, Copy)]
pub(super) struct Fields<'f> {
    /// The file name given to the reader.
    pub(super) file: &'f str,
}

impl Fields<'_> {
    /// An error at `line` in `field`.
    pub(super) fn error(
        &self,
        line: usize,
        field: impl Into<String>,
        kind: DeckErrorKind,
    ) -> DeckError {
        DeckError::new(self.file, line, field, kind)
    }

    /// The real in columns `start..start + width` of `l` (blank = 0).
    pub(super) fn real(
        &self,
        l: &Line,
        start: usize,
        width: usize,
        field: &str,
    ) -> Result<f64, DeckError> {
        self.number(parse_real, l, (start, width), field)
    }

    /// The integer in columns `start..start + width` of `l` (blank = 0).
    pub(super) fn int(
        &self,
        l: &Line,
        start: usize,
        width: usize,
        field: &str,
    ) -> Result<i64, DeckError> {
        self.number(parse_int, l, (start, width), field)
    }

    /// The number `parse` reads in the columns `(start, width)` of `l`.
    fn number<T>(
        &self,
        parse: fn(&str, NumberSyntax) -> Result<T, DeckErrorKind>,
        l: &Line,
        (start, width): (usize, usize),
        field: &str,
    ) -> Result<T, DeckError> {
        parse(&column(l.text, start, width), NumberSyntax::FixedWidth)
            .map_err(|k| self.error(l.no, field, k))
    }

    /// An id field: 0 (or blank) = none.
    pub(super) fn id(
        &self,
        l: &Line,
        start: usize,
        width: usize,
        field: &str,
    ) -> Result<Option<u32>, DeckError> {
        let v = self.int(l, start, width, field)?;
        let id = self.id_value(l.no, field, v)?;
        Ok((id != 0).then_some(id))
    }

    /// `v` as an id (0 = none), or an error at `line` in `field`.
    pub(super) fn id_value(&self, line: usize, field: &str, v: i64) -> Result<u32, DeckError> {
        u32::try_from(v).map_err(|_| {
            let expected = format!("an id in 0..={} (0 = none)", u32::MAX);
            self.invalid_value(line, field, v, expected)
        })
    }

    /// [`DeckErrorKind::InvalidValue`]: `value` is not what `field` accepts.
    pub(super) fn invalid_value(
        &self,
        line: usize,
        field: impl Into<String>,
        value: impl ToString,
        expected: impl Into<String>,
    ) -> DeckError {
        let kind = DeckErrorKind::InvalidValue {
            value: value.to_string(),
            expected: expected.into(),
        };
        self.error(line, field, kind)
    }

    /// The text in columns `start..start + width` of `l`, trimmed.
    pub(super) fn text(&self, l: &Line, start: usize, width: usize) -> String {
        column(l.text, start, width).trim().to_string()
    }

    /// Block `b` ends before its card `card`, whose first field is `field`.
    pub(super) fn missing(&self, b: &Block, field: &str, card: &str) -> DeckError {
        let kind = DeckErrorKind::MissingCard {
            card: card.into(),
            block: b.name(),
        };
        self.error(b.line, field, kind)
    }

    /// Block `b` defines the id `id` of a `what` defined at `first_line` already.
    pub(super) fn duplicate(
        &self,
        b: &Block,
        field: &str,
        what: &'static str,
        id: u32,
        first_line: usize,
    ) -> DeckError {
        let kind = DeckErrorKind::DuplicateId {
            what,
            id: id.into(),
            first_line,
        };
        self.error(b.line, field, kind)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns() {
        assert_eq!(column("ab", 5, 10), "");
        assert_eq!(column("日本語テキスト", 2, 3), "語テキ");
    }

    #[test]
    fn ids() {
        let fields = Fields { file: "t.rad" };
        let l = Line {
            no: 4,
            text: "         7        -1",
        };
        assert_eq!(fields.id(&l, 0, 10, "a"), Ok(Some(7)));
        assert_eq!(fields.id(&l, 20, 10, "b"), Ok(None));
        let e = fields.id(&l, 10, 10, "c").unwrap_err();
        assert_eq!((e.line, e.field.as_str()), (4, "c"));
        assert!(matches!(*e.kind, DeckErrorKind::InvalidValue { .. }));
    }
}
