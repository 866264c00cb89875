//! The `/SENSOR/TIME` block: a title, then `Tdelay` (the sensor activates at `t = Tdelay`,
//! ≥ 0).

use super::blocks::Block;
use super::reader::Reader;
use super::{DeckError, TimeSensor};

impl Reader<'_> {
    pub(super) fn sensor(&mut self, b: &Block) -> Result<(), DeckError> {
        let fields = self.fields;
        let (id, unit_id) = self.ids(b, 2, "sens_ID", true)?;
        if let Some(first) = self.sensors.get(&id) {
            return Err(fields.duplicate(b, "sens_ID", "sensor", id, first.line));
        }
        let title = self.title(b, "sens_title")?;
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
