//! The `*FLEXPROADD` record `IMAT Ktor IFLAG Kdyn_ini Kdyn_lim Angle_lim Teta CP`: the
//! torsion stiffness \[N·m/rad\] and the dynamic bilinear law (stiffnesses \[N·m/rad\],
//! angle \[rad\], torsion damping \[N·m·s/rad\]). Only `IFLAG = 1` is accepted; a non-zero
//! `Teta` is kept and ignored, with a warning notice.

use super::reader::Reader;
use super::record::Record;
use super::{DeckError, DeckErrorKind, FlexProAddRecord};
use crate::law::flex_joint::FlexProAdd;

impl Reader<'_> {
    pub(super) fn flexproadd(&mut self, rec: &Record) -> Result<(), DeckError> {
        rec.at_most(8)?;
        let id = rec.uint(0, "IMAT")?;
        let torsion_stiffness = rec.real(1, "Ktor")?;
        let iflag = rec.int(2, "IFLAG")?;
        if iflag != 1 {
            return Err(rec.error("IFLAG", DeckErrorKind::UnsupportedIflag(iflag)));
        }
        let props = FlexProAdd {
            torsion_stiffness,
            iflag,
            kdyn_ini: rec.real(3, "Kdyn_ini")?,
            kdyn_lim: rec.real(4, "Kdyn_lim")?,
            angle_lim: rec.real(5, "Angle_lim")?,
            teta: rec.real(6, "Teta")?,
            torsion_damping: rec.real(7, "CP")?,
        };
        props
            .validate()
            .map_err(|e| rec.property_error("IMAT", e))?;
        if let Some(prev) = self.deck.flex_props.get(&id) {
            let kind = DeckErrorKind::DuplicateId {
                what: "*FLEXPROADD record",
                id,
                first_line: prev.line,
            };
            return Err(rec.error("IMAT", kind));
        }
        if props.teta != 0.0 {
            let message = format!(
                "*FLEXPROADD {id}: Teta = {} is read and ignored (its meaning is not \
                 documented)",
                props.teta
            );
            self.notice(rec.line, message);
        }
        let line = rec.line;
        self.deck
            .flex_props
            .insert(id, FlexProAddRecord { id, props, line });
        Ok(())
    }
}
