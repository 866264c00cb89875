//! The unit systems: the `/UNIT` block (a title, then the mass, length and time unit names,
//! `kg mm ms`; a blank name is the SI base unit, with a notice) and the input units of
//! `/BEGIN`.

use super::blocks::Block;
use super::fields::Line;
use super::reader::{Heading, HeadingForm, Reader};
use super::{DeckError, DeckErrorKind, InputUnits, UnitEntry};
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

/// The fields of a `/UNIT` card.
const UNIT_FIELDS: [&str; 3] = ["M_unit", "L_unit", "T_unit"];
/// The fields of `/BEGIN`'s input and work unit cards.
const INPUT_FIELDS: [&str; 3] = ["Input_mass_unit", "Input_length_unit", "Input_time_unit"];
const WORK_FIELDS: [&str; 3] = ["Work_mass_unit", "Work_length_unit", "Work_time_unit"];

impl Reader<'_> {
    /// A card of a mass, a length and a time unit (20 columns each, named `field`): the
    /// names as written and each unit's size in SI (`None` for a blank name).
    fn unit_card(
        &self,
        card: &Line,
        field: [&str; 3],
    ) -> Result<([String; 3], [Option<f64>; 3]), DeckError> {
        type Lookup = fn(&str) -> Option<f64>;
        let specs: [(BaseQuantity, &'static str, Lookup); 3] = [
            (
                BaseQuantity::Mass,
                "kg, g, mg, Mg, t, lb, or the unit's size in kg",
                crate::io::units::mass_unit,
            ),
            (
                BaseQuantity::Length,
                "m, dm, cm, mm, um, km, in, ft, or the unit's size in m",
                crate::io::units::length_unit,
            ),
            (
                BaseQuantity::Time,
                "s, ms, us, ns, min, h, or the unit's size in s",
                crate::io::units::time_unit,
            ),
        ];
        let mut names: [String; 3] = Default::default();
        let mut sizes = [None; 3];
        for (k, (quantity, expected, lookup)) in specs.into_iter().enumerate() {
            let name = self.fields.text(card, 20 * k, 20);
            if !name.is_empty() {
                let size = lookup(&name).ok_or_else(|| {
                    let text = name.clone();
                    let kind = DeckErrorKind::UnknownUnit {
                        text,
                        quantity,
                        expected,
                    };
                    self.fields.error(card.no, field[k], kind)
                })?;
                sizes[k] = Some(size);
            }
            names[k] = name;
        }
        Ok((names, sizes))
    }

    /// `/BEGIN`: the run name, `Invers Irun`, then the input and the work unit systems
    /// (mass, length, time). The input system is the unit of every value whose keyword
    /// has no `/unit_ID`; a blank input unit is the work unit, a blank work unit the SI
    /// base unit (Radioss' defaults). The work system serves those defaults and is the
    /// unit of `ScF` when `Kn > 0` (Radioss does not convert it): the crate converts into SI.
    pub(super) fn begin(&mut self, b: &Block) -> Result<(), DeckError> {
        if let Some(first) = &self.input_units {
            let kind = DeckErrorKind::InvalidKeyword {
                text: b.name(),
                expected: format!("one /BEGIN block (the first is at line {})", first.line),
            };
            return Err(self.fields.error(b.line, "keyword", kind));
        }
        let blank = Line {
            no: b.line,
            text: "",
        };
        let card = |k: usize| {
            b.body.get(k).map_or(blank, |l| Line {
                no: l.no,
                text: l.text,
            })
        };
        let (mut names, input) = self.unit_card(&card(2), INPUT_FIELDS)?;
        let (work_names, work) = self.unit_card(&card(3), WORK_FIELDS)?;
        let mut sizes = [1.0; 3];
        for k in 0..3 {
            sizes[k] = input[k].or(work[k]).unwrap_or(1.0);
            if names[k].is_empty() {
                names[k].clone_from(&work_names[k]);
            }
        }
        let system = UnitSystem::new(sizes[0], sizes[1], sizes[2]).unwrap_or(UnitSystem::SI);
        let work = work.map(|s| s.unwrap_or(1.0));
        self.work_units = UnitSystem::new(work[0], work[1], work[2]).unwrap_or(UnitSystem::SI);
        if system != UnitSystem::SI {
            self.notice(
                b.line,
                format!(
                    "/BEGIN: values on keywords without a /unit_ID are in its input units \
                     ({}) and are converted into SI",
                    names
                        .iter()
                        .zip(["kg", "m", "s"])
                        .map(|(n, si)| if n.is_empty() { si } else { n })
                        .collect::<Vec<_>>()
                        .join(" ")
                ),
            );
        }
        self.extra_cards(b, 4);
        self.input_units = Some(InputUnits {
            line: b.line,
            names,
            system,
        });
        Ok(())
    }

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
        let (names, sizes) = self.unit_card(card, UNIT_FIELDS)?;
        for (name, field) in names.iter().zip(UNIT_FIELDS) {
            if name.is_empty() {
                self.notice(
                    card.no,
                    format!("/UNIT/{id}: blank {field}, the SI base unit is used"),
                );
            }
        }
        let sizes = sizes.map(|s| s.unwrap_or(1.0));
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
