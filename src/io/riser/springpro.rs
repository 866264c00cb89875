//! The `*SPRINGPRO` record `INDEX NPAIRS x1 y1 … xN yN`: a multilinear moment-angle law
//! (angle \[rad\], moment \[N·m\]) of at least two pairs (a constant is two pairs with the
//! same moment). The law must pass through (0, 0), and its moment must never decrease from
//! one pair to the next (a falling segment is a negative stiffness): refused naming the
//! law's line (and the `y` of the pair).

use super::reader::Reader;
use super::record::Record;
use super::{DeckError, DeckErrorKind, SpringPro};
use crate::law::curve::Curve;
use crate::law::flex_joint::{falling_segment, passes_through_origin};

impl Reader<'_> {
    pub(super) fn springpro(&mut self, rec: &Record) -> Result<(), DeckError> {
        let index = rec.uint(0, "INDEX")?;
        let npairs = rec.uint(1, "NPAIRS")?;
        let values = rec.tokens.len() - 2;
        if npairs < Curve::MIN_POINTS as u64 {
            let kind = DeckErrorKind::InvalidValue {
                value: npairs.to_string(),
                expected: format!(
                    "at least {} (angle, moment) pairs (a constant is two pairs with the same \
                     moment)",
                    Curve::MIN_POINTS
                ),
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
        // what a flex joint's law must be (`FlexJointLaw::validate`), named here at the
        // law's own line rather than at the *FLEXJOINT that reads it
        if !passes_through_origin(&curve) {
            let kind = DeckErrorKind::InvalidValue {
                value: crate::law::flex_joint::origin_miss(&curve),
                expected: "a moment-angle law passing through (0, 0)".into(),
            };
            return Err(rec.error("pairs", kind));
        }
        if let Some((k, (x0, y0), (x1, y1))) = falling_segment(&curve) {
            let kind = DeckErrorKind::InvalidValue {
                value: y1.to_string(),
                expected: format!(
                    "a moment >= y{} = {y0} (the law falls from ({x0}, {y0}) to ({x1}, {y1}): \
                     a negative stiffness)",
                    k + 1
                ),
            };
            return Err(rec.error(&format!("y{}", k + 2), kind));
        }
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
