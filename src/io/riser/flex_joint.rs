//! The `*FLEXJOINT` record `NEL JO JE IPRO IMAT LENGTH [IPROT]` (LENGTH \[m\] is read and
//! unused; `IPROT` may be omitted), and the resolution of its indices into a
//! [`FlexJointLaw`] once the whole deck is read (the blocks may come in any order).

use super::reader::Reader;
use super::record::Record;
use super::{DeckError, DeckErrorKind, FlexJointElement};
use crate::law::curve::Curve;
use crate::law::flex_joint::{FlexJointLaw, FlexProAdd};

/// A `*FLEXJOINT` record before its indices are resolved.
pub(super) struct RawJoint {
    id: u64,
    origin_node: u64,
    end_node: u64,
    ipro: u64,
    imat: u64,
    length: f64,
    iprot: u64,
    line: usize,
}

impl Reader<'_> {
    pub(super) fn flex_joint(&mut self, rec: &Record) -> Result<(), DeckError> {
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
            line: rec.line,
        };
        if let Some(&first_line) = self.joint_lines.get(&j.id) {
            let kind = DeckErrorKind::DuplicateId {
                what: "*FLEXJOINT element",
                id: j.id,
                first_line,
            };
            return Err(rec.error("NEL", kind));
        }
        self.joint_lines.insert(j.id, rec.line);
        self.raw_joints.push(j);
        Ok(())
    }

    /// Every `*FLEXJOINT` record with its laws resolved, into the deck's joints.
    pub(super) fn resolve_joints(&mut self) -> Result<(), DeckError> {
        for j in std::mem::take(&mut self.raw_joints) {
            let rec = Record {
                file: self.file,
                line: j.line,
                keyword: "*FLEXJOINT",
                tokens: Vec::new(),
            };
            let bending = self.spring(&rec, j.ipro, "IPRO")?;
            let torsion = self.spring(&rec, j.iprot, "IPROT")?;
            let dynamic = self.flex_props(&rec, j.imat)?;
            if let (Some(d), true) = (&dynamic, torsion.is_some()) {
                if d.torsion_stiffness != 0.0 {
                    let message = format!(
                        "*FLEXJOINT {}: IPROT = {} is given, so Ktor = {} of *FLEXPROADD {} is \
                         ignored",
                        j.id, j.iprot, d.torsion_stiffness, j.imat
                    );
                    self.notice(j.line, message);
                }
            }
            let law = FlexJointLaw::new(bending, torsion, dynamic)
                .map_err(|e| rec.property_error("IPRO", e))?;
            // what the law does that the deck most likely did not mean (points at negative
            // angles, never read: a deck accepted without a word; a riser engineer's trial,
            // 2026-12-04)
            for n in law.notices() {
                let message = format!(
                    "*FLEXJOINT {} (IPRO = {}, IMAT = {}, IPROT = {}): {n}",
                    j.id, j.ipro, j.imat, j.iprot
                );
                self.notice(j.line, message);
            }
            self.deck.joints.push(FlexJointElement {
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
        Ok(())
    }

    /// The `*SPRINGPRO` law `index` (0 = none) named by `field` of `rec`.
    fn spring(&self, rec: &Record, index: u64, field: &str) -> Result<Option<Curve>, DeckError> {
        if index == 0 {
            return Ok(None);
        }
        match self.deck.spring_laws.get(&index) {
            Some(s) => Ok(Some(s.curve.clone())),
            None => Err(rec.error(field, self.unknown("*SPRINGPRO law", index))),
        }
    }

    /// The `*FLEXPROADD` record `imat` (0 = none) named by `IMAT` of `rec`.
    fn flex_props(&self, rec: &Record, imat: u64) -> Result<Option<FlexProAdd>, DeckError> {
        if imat == 0 {
            return Ok(None);
        }
        match self.deck.flex_props.get(&imat) {
            Some(r) => Ok(Some(r.props)),
            None => Err(rec.error("IMAT", self.unknown("*FLEXPROADD record", imat))),
        }
    }

    /// [`DeckErrorKind::UnknownReference`] to the record `id` of `what` (`*SPRINGPRO law`),
    /// naming the keywords the deck skipped as unknown ([`Reader::skipped_note`]).
    fn unknown(&self, what: &'static str, id: u64) -> DeckErrorKind {
        let keyword = what.split(' ').next().unwrap_or(what);
        DeckErrorKind::UnknownReference {
            what,
            id,
            note: format!(
                " (no such record in the deck; 0 = none{})",
                self.skipped_note(keyword)
            ),
        }
    }
}
