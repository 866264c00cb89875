//! The `/SKEW/FIX` block (a title, the origin, the Y' axis and the Z' axis), and the vector
//! helpers that build its orthonormal axes.

use super::blocks::Block;
use super::reader::{Heading, HeadingForm, Reader};
use super::{DeckError, SkewFix};

/// `/SKEW/FIX/skew_ID[/unit_ID]`, then its title.
const SKEW: HeadingForm = HeadingForm {
    at: 2,
    id_field: "skew_ID",
    title_field: "skew_title",
    what: "skew",
    unit: true,
};

impl Reader<'_> {
    pub(super) fn skew(&mut self, b: &Block) -> Result<(), DeckError> {
        let fields = self.fields;
        let Heading { id, unit_id, title } =
            self.heading(b, &SKEW, |r, id| r.skews.get(&id).map(|e| e.line))?;
        let names = [["Ox", "Oy", "Oz"], ["X1", "Y1", "Z1"], ["X2", "Y2", "Z2"]];
        let mut v = [[0.0; 3]; 3];
        let mut lines = [0; 3];
        for (k, card) in names.iter().enumerate() {
            let l = b
                .body
                .get(1 + k)
                .ok_or_else(|| fields.missing(b, card[0], &card.join(" ")))?;
            lines[k] = l.no;
            for (j, field) in card.iter().enumerate() {
                v[k][j] = fields.real(l, 20 * j, 20, field)?;
            }
        }
        let degenerate = |line: usize, field: &str, value: [f64; 3], expected: &str| {
            let value = format!("({}, {}, {})", value[0], value[1], value[2]);
            fields.invalid_value(line, field, value, expected)
        };
        let y = normalize(v[1])
            .ok_or_else(|| degenerate(lines[1], "X1", v[1], "a non-zero vector (the Y' axis)"))?;
        let z = normalize(v[2])
            .ok_or_else(|| degenerate(lines[2], "X2", v[2], "a non-zero vector (the Z' axis)"))?;
        let x = cross(y, z);
        if x.iter().map(|c| c * c).sum::<f64>() < 1e-20 {
            return Err(degenerate(
                lines[2],
                "X2",
                v[2],
                "a vector not parallel to the Y' axis (X1 Y1 Z1)",
            ));
        }
        self.extra_cards(b, 4);
        self.skews.insert(
            id,
            SkewFix {
                id,
                title,
                line: b.line,
                unit_id,
                unit: None,
                origin: v[0],
                y_axis: v[1],
                z_axis: v[2],
            },
        );
        Ok(())
    }
}

/// `a × b`.
pub(super) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `v / |v|`, robust to huge and tiny components; `None` for a zero or non-finite vector.
pub(super) fn normalize(v: [f64; 3]) -> Option<[f64; 3]> {
    let m = v.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    if !(m.is_finite() && m > 0.0) {
        return None;
    }
    let s = v.map(|c| c / m);
    let n = s.iter().map(|c| c * c).sum::<f64>().sqrt();
    Some(s.map(|c| c / n))
}
