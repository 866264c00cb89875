//! The `/SENSOR/TIME` block: a title, then `Tdelay` (the sensor activates at `t = Tdelay`,
//! ≥ 0).

use super::blocks::Block;
use super::reader::{Heading, HeadingForm, Reader};
use super::{DeckError, TimeSensor};

/// `/SENSOR/TIME/sens_ID[/unit_ID]`, then its title.
const SENSOR: HeadingForm = HeadingForm {
    at: 2,
    id_field: "sens_ID",
    title_field: "sens_title",
    what: "sensor",
    unit: true,
};

impl Reader<'_> {
    pub(super) fn sensor(&mut self, b: &Block) -> Result<(), DeckError> {
        let fields = self.fields;
        let Heading { id, unit_id, title } =
            self.heading(b, &SENSOR, |r, id| r.sensors.get(&id).map(|e| e.line))?;
        let l = b
            .body
            .get(1)
            .ok_or_else(|| fields.missing(b, "Tdelay", "Tdelay"))?;
        let tdelay = fields.real(l, 0, 20, "Tdelay")?;
        if tdelay < 0.0 {
            return Err(fields.invalid_value(l.no, "Tdelay", tdelay, "a time >= 0"));
        }
        self.extra_cards(b, 2);
        self.sensors.insert(
            id,
            TimeSensor {
                id,
                title,
                line: b.line,
                unit_id,
                unit: None,
                tdelay,
            },
        );
        Ok(())
    }
}
