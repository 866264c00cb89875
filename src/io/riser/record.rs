//! One record line of a riser deck ([`Record`]): its whitespace-separated values read as
//! reals, integers or indices, and the errors naming the file, line, keyword and field.
//!
//! Numbers are parsed by [`crate::io::diagnostic::parse_real`] and
//! [`crate::io::diagnostic::parse_int`] in the free-format syntax.

use crate::error::PropertyError;
use crate::io::diagnostic::{parse_int, parse_real, DeckError, DeckErrorKind, NumberSyntax};

/// The values of one record line.
pub(super) struct Record<'a> {
    /// The file name given to the reader.
    pub(super) file: &'a str,
    /// 1-based line number.
    pub(super) line: usize,
    /// The keyword of the block (`*FLEXJOINT`).
    pub(super) keyword: &'static str,
    /// The values, in order.
    pub(super) tokens: Vec<&'a str>,
}

impl<'a> Record<'a> {
    /// An error in `field` of this record.
    pub(super) fn error(&self, field: &str, kind: DeckErrorKind) -> DeckError {
        DeckError::new(self.file, self.line, field, kind).in_block(self.keyword)
    }

    /// A [`PropertyError`] of the law read, on the field it names (else on `field`).
    pub(super) fn property_error(&self, field: &str, e: PropertyError) -> DeckError {
        let field = match &e {
            PropertyError::InvalidField { field, .. } => field.clone(),
            _ => field.to_string(),
        };
        self.error(&field, DeckErrorKind::Property(e))
    }

    fn token(&self, i: usize, field: &str) -> Result<&'a str, DeckError> {
        self.tokens
            .get(i)
            .copied()
            .ok_or_else(|| self.error(field, DeckErrorKind::MissingField))
    }

    /// Value `i` as a real.
    pub(super) fn real(&self, i: usize, field: &str) -> Result<f64, DeckError> {
        let t = self.token(i, field)?;
        parse_real(t, NumberSyntax::FreeFormat).map_err(|k| self.error(field, k))
    }

    /// Value `i` as an integer (an integral real such as `3.` is accepted).
    pub(super) fn int(&self, i: usize, field: &str) -> Result<i64, DeckError> {
        let t = self.token(i, field)?;
        parse_int(t, NumberSyntax::FreeFormat).map_err(|k| self.error(field, k))
    }

    /// Value `i` as a non-negative integer (an index or id; 0 = none where it refers).
    pub(super) fn uint(&self, i: usize, field: &str) -> Result<u64, DeckError> {
        let v = self.int(i, field)?;
        u64::try_from(v).map_err(|_| {
            let kind = DeckErrorKind::InvalidNumber {
                text: self.tokens.get(i).copied().unwrap_or("").to_string(),
                expected: "a non-negative integer",
            };
            self.error(field, kind)
        })
    }

    /// An error if the record has more than `max` values.
    pub(super) fn at_most(&self, max: usize) -> Result<(), DeckError> {
        if self.tokens.len() > max {
            let kind = DeckErrorKind::TooManyFields {
                found: self.tokens.len(),
                max,
            };
            Err(self.error("(end of record)", kind))
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_and_errors() {
        let r = Record {
            file: "r.dat",
            line: 4,
            keyword: "*FLEXJOINT",
            tokens: vec!["3.", "-1", "1.5D+3"],
        };
        assert_eq!(r.uint(0, "NEL"), Ok(3));
        assert_eq!(r.real(2, "LENGTH"), Ok(1500.0));
        let e = r.uint(1, "JO").unwrap_err();
        assert_eq!(
            (e.line, e.field.as_str(), e.block.as_str()),
            (4, "JO", "*FLEXJOINT")
        );
        assert_eq!(
            *r.real(3, "IPRO").unwrap_err().kind,
            DeckErrorKind::MissingField
        );
        assert!(r.at_most(2).is_err() && r.at_most(3).is_ok());
    }
}
