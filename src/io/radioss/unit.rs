//! The `/UNIT` block: a title, then the mass, length and time unit names (`kg mm ms`); a
//! blank name is the SI base unit (with a notice).

use super::blocks::Block;
use super::reader::{Heading, HeadingForm, Reader};
use super::{DeckError, DeckErrorKind, UnitEntry};
use crate::io::diagnostic::BaseQuantity;
use crate::io::units::UnitSystem;

/// `/UNIT/unit_ID`, then its title.
const UNIT: HeadingForm = HeadingForm {
    at: 1,
    id_field: "unit_ID",
    title_field: "unit_title",
    what: "unit system",
    unit: false,
};

impl Reader<'_> {
    pub(super) fn unit(&mut self, b: &Block) -> Result<(), DeckError> {
        let fields = self.fields;
        let Heading {
            id,
            unit_id: _,
            title,
        } = self.heading(b, &UNIT, |r, id| r.units.get(&id).map(|e| e.line))?;
        let card = b
            .body
            .get(1)
            .ok_or_else(|| fields.missing(b, "M_unit", "M_unit L_unit T_unit"))?;
        type Lookup = fn(&str) -> Option<f64>;
        let specs: [(&str, BaseQuantity, &'static str, Lookup); 3] = [
            (
                "M_unit",
                BaseQuantity::Mass,
                "kg, g, mg, Mg, t, lb, or the unit's size in kg",
                crate::io::units::mass_unit,
            ),
            (
                "L_unit",
                BaseQuantity::Length,
                "m, dm, cm, mm, um, km, in, ft, or the unit's size in m",
                crate::io::units::length_unit,
            ),
            (
                "T_unit",
                BaseQuantity::Time,
                "s, ms, us, ns, min, h, or the unit's size in s",
                crate::io::units::time_unit,
            ),
        ];
        let mut names: [String; 3] = Default::default();
        let mut sizes = [1.0; 3];
        for (k, (field, quantity, expected, lookup)) in specs.into_iter().enumerate() {
            let name = fields.text(card, 20 * k, 20);
            if name.is_empty() {
                self.notice(
                    card.no,
                    format!("/UNIT/{id}: blank {field}, the SI base unit is used"),
                );
            } else {
                sizes[k] = lookup(&name).ok_or_else(|| {
                    fields.error(
                        card.no,
                        field,
                        DeckErrorKind::UnknownUnit {
                            text: name.clone(),
                            quantity,
                            expected,
                        },
                    )
                })?;
            }
            names[k] = name;
        }
        // Sizes come from the tables or are checked positive and finite.
        let system = UnitSystem::new(sizes[0], sizes[1], sizes[2]).unwrap_or(UnitSystem::SI);
        self.extra_cards(b, 2);
        self.units.insert(
            id,
            UnitEntry {
                id,
                title,
                line: b.line,
                names,
                system,
            },
        );
        Ok(())
    }
}
