//! The `/FUNCT` block: a title, then lines of `X Y` pairs (one or two pairs per line)
//! with strictly increasing abscissas, at least two pairs (a constant is two pairs with the
//! same `Y`).

use super::blocks::Block;
use super::reader::{Heading, HeadingForm, Reader};
use super::{DeckError, DeckErrorKind, Function};
use crate::law::Curve;

/// `/FUNCT/fct_ID[/unit_ID]`, then its title.
const FUNCT: HeadingForm = HeadingForm {
    at: 1,
    id_field: "fct_ID",
    title_field: "fct_title",
    what: "function",
    unit: true,
};

impl Reader<'_> {
    pub(super) fn funct(&mut self, b: &Block) -> Result<(), DeckError> {
        let fields = self.fields;
        let Heading { id, unit_id, title } =
            self.heading(b, &FUNCT, |r, id| r.functions.get(&id).map(|e| e.line))?;
        let mut points: Vec<(f64, f64)> = Vec::new();
        for l in b.body.iter().skip(1).filter(|l| !l.is_blank()) {
            let mut pairs = vec![(fields.real(l, 0, 20, "X")?, fields.real(l, 20, 20, "Y")?)];
            if !(fields.text(l, 40, 20).is_empty() && fields.text(l, 60, 20).is_empty()) {
                pairs.push((fields.real(l, 40, 20, "X")?, fields.real(l, 60, 20, "Y")?));
            }
            for (x, y) in pairs {
                if let Some(&(px, _)) = points.last() {
                    if x <= px {
                        let expected =
                            format!("an abscissa > {px} (abscissas must increase strictly)");
                        return Err(fields.invalid_value(l.no, "X", x, expected));
                    }
                }
                points.push((x, y));
            }
        }
        if points.is_empty() {
            return Err(fields.missing(b, "X", "X Y"));
        }
        if points.len() < Curve::MIN_POINTS {
            // named at the point's card (the one non-blank card after the title)
            let line = b
                .body
                .iter()
                .skip(1)
                .find(|l| !l.is_blank())
                .map_or(b.line, |l| l.no);
            let kind = DeckErrorKind::Property(Curve::too_few_points(points.len()));
            return Err(fields.error(line, "X", kind));
        }
        let curve = Curve::new(points)
            .map_err(|e| fields.error(b.line, "X", DeckErrorKind::Property(e)))?;
        self.functions.insert(
            id,
            Function {
                id,
                title,
                line: b.line,
                unit_id,
                curve,
            },
        );
        Ok(())
    }
}
