//! The `*SPRINGPRO` record `INDEX NPAIRS x1 y1 … xN yN`: a multilinear moment-angle law
//! (angle \[rad\], moment \[N·m\]).

use super::reader::Reader;
use super::record::Record;
use super::{DeckError, DeckErrorKind, SpringPro};
use crate::law::curve::Curve;

impl Reader<'_> {
    pub(super) fn springpro(&mut self, rec: &Record) -> Result<(), DeckError> {
        let index = rec.uint(0, "INDEX")?;
        let npairs = rec.uint(1, "NPAIRS")?;
        let values = rec.tokens.len() - 2;
        if npairs == 0 {
            let kind = DeckErrorKind::InvalidValue {
                value: "0".into(),
                expected: "at least one (angle, moment) pair".into(),
            };
            return Err(rec.error("NPAIRS", kind));
        }
        if values % 2 != 0 || (values / 2) as u64 != npairs {
            return Err(rec.error("NPAIRS", DeckErrorKind::PairCount { npairs, values }));
        }
        let mut pts = Vec::with_capacity(values / 2);
        for k in 0..values / 2 {
            let x = rec.real(2 + 2 * k, &format!("x{}", k + 1))?;
            let y = rec.real(3 + 2 * k, &format!("y{}", k + 1))?;
            pts.push((x, y));
        }
        let curve = Curve::new(pts).map_err(|e| rec.error("pairs", DeckErrorKind::Property(e)))?;
        if let Some(prev) = self.deck.spring_laws.get(&index) {
            let kind = DeckErrorKind::DuplicateId {
                what: "*SPRINGPRO law",
                id: index,
                first_line: prev.line,
            };
            return Err(rec.error("INDEX", kind));
        }
        let line = rec.line;
        self.deck
            .spring_laws
            .insert(index, SpringPro { index, curve, line });
        Ok(())
    }
}
