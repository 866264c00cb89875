//! The `/PROP/TYPE45` (`/PROP/KJOINT2`) block: the first card (type, Kn, ScF, Cr, sensor,
//! skews), then three cards (K, C, Kf) for each free DOF of the type. Missing DOF cards
//! take their defaults (zero) with a notice.

use super::blocks::Block;
use super::fields::{Fields, Line};
use super::reader::{Heading, HeadingForm, Reader};
use super::{DeckError, DeckErrorKind, DofFunctionIds, PropertyEntry};
use crate::law::{AutomaticStiffness, Dof, DofLaw, JointType, KjointProperty};

/// `/PROP/TYPE45/prop_ID[/unit_ID]` (or `/PROP/KJOINT2/...`), then its title.
const KJOINT2: HeadingForm = HeadingForm {
    at: 2,
    id_field: "prop_ID",
    title_field: "prop_title",
    what: "property",
    unit: true,
};

/// The fields of the first card.
const PROP_CARD1: &str = "Type Kn ScF Cr sens_ID Skew_ID1 Skew_ID2";

/// A KJOINT2 block before its references are resolved.
pub(super) struct RawProperty {
    pub(super) entry: PropertyEntry,
    /// Line of the first card (`Type Kn ...`).
    pub(super) first_card: usize,
    /// Line of the K, C and Kf cards of each DOF (`None` = missing, defaulted).
    pub(super) card_lines: [[Option<usize>; 3]; 6],
}

/// The per-DOF cards read so far.
struct DofCards {
    card_lines: [[Option<usize>; 3]; 6],
    function_ids: [DofFunctionIds; 6],
    /// The cards absent from the block (`rx.K`, ...).
    missing: Vec<String>,
    /// Index in the block's body of the card after the last DOF card.
    next: usize,
}

impl Reader<'_> {
    pub(super) fn kjoint2(&mut self, b: &Block) -> Result<(), DeckError> {
        let fields = self.fields;
        let Heading { id, unit_id, title } = self.heading(b, &KJOINT2, |r, id| {
            let first = r.props.iter().find(|p| p.entry.id == id);
            first.map(|p| p.entry.line)
        })?;
        let c1 = b
            .body
            .get(1)
            .ok_or_else(|| fields.missing(b, "Type", PROP_CARD1))?;
        let (mut p, skew1, skew2) = first_card(fields, c1, &b.body[0])?;
        let cards = dof_cards(fields, b, &mut p)?;
        if cards.missing.is_empty() {
            self.extra_cards(b, cards.next);
        } else {
            let last = b.body.last().map_or(b.line, |l| l.no);
            self.notice(
                last,
                format!(
                    "{} ends before the cards {}: their fields take the default 0",
                    b.name(),
                    cards.missing.join(", ")
                ),
            );
        }
        self.props.push(RawProperty {
            entry: PropertyEntry {
                id,
                title,
                line: b.line,
                keyword: b.name(),
                unit_id,
                unit: None,
                property_si: p.clone(),
                property: p,
                skew1,
                skew2,
                function_ids: cards.function_ids,
            },
            first_card: c1.no,
            card_lines: cards.card_lines,
        });
        Ok(())
    }
}

/// The first card: the property without DOF laws, and `Skew_ID1`, `Skew_ID2`.
fn first_card(
    fields: Fields,
    c1: &Line,
    title: &Line,
) -> Result<(KjointProperty, Option<u32>, Option<u32>), DeckError> {
    let type_number = fields.int(c1, 0, 10, "Type")?;
    let joint_type = JointType::from_number(type_number).map_err(|_| {
        let kind = DeckErrorKind::UnknownJointType {
            value: type_number,
            hint: type_hint(c1, title),
        };
        fields.error(c1.no, "Type", kind)
    })?;
    // Kn = 0 keeps Radioss' own automatic rule: deck users compare with Radioss
    let mut p = KjointProperty::new(joint_type).with_automatic(AutomaticStiffness::Radioss);
    p.kn = fields.real(c1, 10, 20, "Kn")?;
    p.scale_factor = fields.real(c1, 30, 20, "ScF")?;
    p.critical_damping = fields.real(c1, 50, 20, "Cr")?;
    p.sensor = fields.id(c1, 70, 10, "sens_ID")?;
    let skew1 = fields.id(c1, 80, 10, "Skew_ID1")?;
    let skew2 = fields.id(c1, 90, 10, "Skew_ID2")?;
    Ok((p, skew1, skew2))
}

/// What the layout of a first card whose `Type` is not 1..9 suggests (a Radioss analyst's
/// deck without its title line, and one shifted by a column, each read "unknown joint type
/// 0"): the line read as the title holds numbers only (the title missing, the first card
/// taken for it), or the card's columns 1–10 are blank while it has fields further on (the
/// card shifted). A genuine title of numbers only gets the first hint too (it is a
/// question); a `Type` that is not an integer fails before this, as a number that does not
/// parse.
fn type_hint(c1: &Line, title: &Line) -> String {
    let numbers_only = !title.text.trim().is_empty()
        && (title.text.split_whitespace()).all(|w| w.parse::<f64>().is_ok());
    if numbers_only {
        return format!(
            "; the line read as the property's title (line {}) holds numbers only: is the \
             title line missing? (the title is the line after the keyword, the first card \
             the line after it)",
            title.no
        );
    }
    let head: String = c1.text.chars().take(10).collect();
    if head.trim().is_empty() && !c1.text.trim().is_empty() {
        return "; columns 1-10 of the card are blank and it has fields further on: is the \
                card shifted? (each field is 10 or 20 columns wide, Type in columns 1-10)"
            .to_string();
    }
    String::new()
}

/// The K, C and Kf cards of each free DOF of `p`'s type, from the block's third card on.
fn dof_cards(fields: Fields, b: &Block, p: &mut KjointProperty) -> Result<DofCards, DeckError> {
    let mut cards = DofCards {
        card_lines: [[None; 3]; 6],
        function_ids: [DofFunctionIds::default(); 6],
        missing: Vec::new(),
        next: 2,
    };
    let joint_type = p.joint_type;
    for dof in Dof::ALL.into_iter().filter(|&d| joint_type.is_free(d)) {
        let i = dof.index();
        for card in 0..3 {
            let Some(l) = b.body.get(cards.next + card) else {
                let name = ["K", "C", "Kf"][card];
                cards.missing.push(format!("{}.{name}", dof.name()));
                continue;
            };
            cards.card_lines[i][card] = Some(l.no);
            let (law, ids) = (&mut p.dofs[i], &mut cards.function_ids[i]);
            dof_card(fields, l, dof, card, law, ids)?;
        }
        cards.next += 3;
    }
    Ok(cards)
}

/// Card `card` (0 = K, 1 = C, 2 = Kf) of `dof` into its law and function ids.
fn dof_card(
    fields: Fields,
    l: &Line,
    dof: Dof,
    card: usize,
    law: &mut DofLaw,
    ids: &mut DofFunctionIds,
) -> Result<(), DeckError> {
    let f = |name: &str| format!("{}.{name}", dof.name());
    let (sm, sp, ff, fct_ff) = if dof.is_rotation() {
        ("SA-", "SA+", "FM", "fct_FM")
    } else {
        ("SD-", "SD+", "FF", "fct_FF")
    };
    match card {
        0 => {
            law.stiffness = fields.real(l, 0, 20, &f("K"))?;
            ids.stiffness = fields.id(l, 20, 10, &f("fct_K"))?;
            law.stop_min = fields.real(l, 30, 20, &f(sm))?;
            law.stop_max = fields.real(l, 50, 20, &f(sp))?;
            law.coupled_stops = match fields.int(l, 70, 10, &f("Icomb"))? {
                0 => false,
                1 => true,
                v => {
                    let expected = "0 (independent stops) or 1 (coupled stops)";
                    return Err(fields.invalid_value(l.no, f("Icomb"), v, expected));
                }
            };
        }
        1 => {
            law.viscosity = fields.real(l, 0, 20, &f("C"))?;
            ids.viscosity = fields.id(l, 20, 10, &f("fct_C"))?;
        }
        _ => {
            law.friction_stiffness = fields.real(l, 0, 20, &f("Kf"))?;
            law.friction = fields.real(l, 20, 20, &f(ff))?;
            ids.friction = fields.id(l, 40, 10, &f(fct_ff))?;
        }
    }
    Ok(())
}
