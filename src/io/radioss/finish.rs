//! Once the whole deck is read: every reference (functions, skews, sensors, unit systems)
//! resolved, each property validated ([`crate::law::KjointProperty::validate`]) and
//! converted into SI, and a property's [`PropertyError`] placed on the card and field that
//! hold the value.

use std::collections::BTreeMap;

use super::fields::Fields;
use super::kjoint2::RawProperty;
use super::reader::{Reader, RefKind};
use super::{DeckError, DeckErrorKind, Notice, PropertyEntry, RadiossDeck, SkewFix, TimeSensor};
use crate::error::PropertyError;
use crate::io::units::{property_to_si, Quantity};
use crate::law::Dof;

impl Reader<'_> {
    /// Resolves every reference and converts the properties into SI.
    pub(super) fn finish(mut self) -> Result<RadiossDeck, DeckError> {
        for f in self.functions.values() {
            self.unit_of(f.line, f.unit_id)?;
        }
        let mut skews = std::mem::take(&mut self.skews);
        for s in skews.values_mut() {
            s.unit = self.unit_of(s.line, s.unit_id)?;
        }
        let mut sensors = std::mem::take(&mut self.sensors);
        for s in sensors.values_mut() {
            s.unit = self.unit_of(s.line, s.unit_id)?;
        }
        let mut properties = BTreeMap::new();
        let mut notes = Vec::new();
        for raw in std::mem::take(&mut self.props) {
            // (an error names the property's block, as one found while reading it does)
            let e = self
                .resolve(&raw, &skews, &sensors, &mut notes)
                .map_err(|e| e.in_block(raw.entry.keyword.clone()))?;
            properties.insert(e.id, e);
        }
        self.notices.extend(notes);
        self.notices.sort_by_key(|n| n.line);
        Ok(RadiossDeck {
            file: self.fields.file.to_string(),
            properties,
            functions: self.functions,
            skews,
            sensors,
            units: self.units,
            input_units: self.input_units,
            notices: self.notices,
        })
    }

    /// One property with its references resolved, validated and converted into SI.
    fn resolve(
        &self,
        raw: &RawProperty,
        skews: &BTreeMap<u32, SkewFix>,
        sensors: &BTreeMap<u32, TimeSensor>,
        notes: &mut Vec<Notice>,
    ) -> Result<PropertyEntry, DeckError> {
        let mut e = raw.entry.clone();
        e.unit = self.unit_of(e.line, e.unit_id)?;
        let c1 = raw.first_card;
        if let Some(id) = e.property.sensor {
            if !sensors.contains_key(&id) {
                return Err(self.unknown(c1, "sens_ID", RefKind::Sensor, id));
            }
        }
        for (field, skew) in [("Skew_ID1", e.skew1), ("Skew_ID2", e.skew2)] {
            if let Some(id) = skew.filter(|id| !skews.contains_key(id)) {
                return Err(self.unknown(c1, field, RefKind::Skew, id));
            }
        }
        // Types 5 to 8 (universal, translational, Oldham, fixed) take no initial rotation:
        // Radioss ignores their Skew_ID2 (rini45.F: warning 1134, IDSK2 = 0, θ0 = 0) once
        // it has checked that the skew exists; so does the reader, with a notice.
        if let Some(id) = e.skew2 {
            let ty = e.property.joint_type;
            if (5..=8).contains(&ty.number()) {
                e.skew2 = None;
                let message = format!(
                    "{}: Skew_ID2 = {id} is ignored on Type {} ({}), as Radioss ignores it \
                     on types 5 to 8 (warning 1134): no initial rotation",
                    e.keyword,
                    ty.number(),
                    ty.name()
                );
                notes.push(Notice::new(self.fields.file, c1, message));
            }
        }
        // a type free about x alone takes an initial angle about x only: Skew_ID2's X'
        // parallel to Skew_ID1's (the global X for Skew_ID1 = 0), as the joint's builder
        // checks (refused there naming `world_frame2`, not the deck's field and line)
        if let Some(id2) = e.skew2 {
            let ty = e.property.joint_type;
            let x1 = e.skew1.map_or([1.0, 0.0, 0.0], |id| skews[&id].axes()[0]);
            let x2 = skews[&id2].axes()[0];
            let c: f64 = (0..3).map(|i| x1[i] * x2[i]).sum();
            if ty.single_free_rotation() && c < 1.0 - crate::law::property::SKEW_X_PARALLEL {
                let expected = format!(
                    "a skew whose X' is parallel to {}'s (Type {}, {}, takes an initial angle \
                     about X' only; the angle between them is {:.4}°)",
                    e.skew1
                        .map_or("the global X (Skew_ID1 = 0)".to_string(), |id| format!(
                            "Skew_ID1 = {id}"
                        )),
                    ty.number(),
                    ty.name(),
                    c.clamp(-1.0, 1.0).acos().to_degrees()
                );
                return Err(self.fields.invalid_value(c1, "Skew_ID2", id2, expected));
            }
        }
        for dof in Dof::ALL {
            self.attach_functions(raw, &mut e, dof, notes)?;
        }
        let fields = self.fields;
        e.property
            .validate()
            .map_err(|err| property_error(fields, raw, err))?;
        e.property_si = match &e.unit {
            Some(u) => {
                property_to_si(&e.property, u).map_err(|err| property_error(fields, raw, err))?
            }
            None => e.property.clone(),
        };
        // ScF with Kn > 0 is an area (KR = Kn·max(ScF, L0²)) that Radioss takes in the deck's
        // WORK units whatever the property's units: the cfg gives SCALE no dimension
        // (prop_p45_kjoint2.cfg), hm_read_prop45.F converts Kn alone (by the property's
        // unit_ID) and resolves ScF's default 0 → 10 unconverted, and rini45.F forms
        // KNN·MAX(SCF, LEN2) with LEN2 in work units. So ScF (or its default 10) is so many
        // squared work lengths: 10 mm² in a deck working in mm, even when its input units
        // or the property's unit_ID are in m. A scene's default stays 10 m² whatever its
        // units, so that a scene reads the same in mm as in m.
        if e.property.kn > 0.0 {
            let area = self.work_units.factor(Quantity::Area);
            e.property_si.scale_factor = e.property.resolved_scale_factor() * area;
            e.property_si
                .validate()
                .map_err(|err| property_error(fields, raw, err))?;
        }
        Ok(e)
    }

    /// The curves of the functions `fct_K`, `fct_C`, `fct_FF` (`fct_FM`) of `dof`, set on
    /// the property of `e`.
    fn attach_functions(
        &self,
        raw: &RawProperty,
        e: &mut PropertyEntry,
        dof: Dof,
        notes: &mut Vec<Notice>,
    ) -> Result<(), DeckError> {
        let i = dof.index();
        let ids = e.function_ids[i];
        let ff = if dof.is_rotation() {
            "fct_FM"
        } else {
            "fct_FF"
        };
        let slots = [
            (ids.stiffness, 0, "fct_K"),
            (ids.viscosity, 1, "fct_C"),
            (ids.friction, 2, ff),
        ];
        for (id, card, name) in slots {
            let Some(id) = id else { continue };
            let line = raw.card_lines[i][card].unwrap_or(e.line);
            let field = format!("{}.{name}", dof.name());
            let Some(f) = self.functions.get(&id) else {
                return Err(self.unknown(line, &field, RefKind::Function, id));
            };
            if f.unit_id.is_some() && f.unit_id != e.unit_id {
                let message = format!(
                    "{field} = {id}: the unit_ID of /FUNCT/{id} is ignored, its values are read \
                     in the unit system of {}",
                    e.keyword
                );
                notes.push(Notice::new(self.fields.file, line, message));
            }
            let law = &mut e.property.dofs[i];
            let curve = Some(f.curve.clone());
            match card {
                0 => law.stiffness_curve = curve,
                1 => law.viscosity_curve = curve,
                _ => law.friction_curve = curve,
            }
        }
        Ok(())
    }
}

/// Wraps a [`PropertyError`] from `validate()` with the line and Radioss name of the field.
///
/// The property's field names end with the Radioss name in parentheses
/// (`rx.stop_max (SA+)`, `kn (Kn)`, `dy.stops (Icomb = 1)`): that name selects the card.
fn property_error(fields: Fields, raw: &RawProperty, err: PropertyError) -> DeckError {
    let (line, field) = match &err {
        PropertyError::InvalidField { field, .. } => {
            let (dof, rest) = match field.split_once('.') {
                Some((d, rest)) => match Dof::ALL.into_iter().find(|x| x.name() == d) {
                    Some(dof) => (Some(dof), rest),
                    None => (None, field.as_str()),
                },
                None => (None, field.as_str()),
            };
            let name = match (rest.find('('), rest.rfind(')')) {
                (Some(a), Some(b)) if a < b => &rest[a + 1..b],
                _ => rest,
            };
            let name = name.split(' ').next().unwrap_or(name);
            match dof {
                Some(d) => {
                    let name = match name {
                        "FF/FM" if d.is_rotation() => "FM",
                        "FF/FM" => "FF",
                        "fct_FF" if d.is_rotation() => "fct_FM",
                        other => other,
                    };
                    // (the curves on their cards too: a negative `fct_FF` was named on the K
                    // card's line; a review, 2026-12-06)
                    let card = match name {
                        "C" | "fct_C" => 1,
                        "Kf" | "FF" | "FM" | "fct_FF" | "fct_FM" => 2,
                        _ => 0,
                    };
                    let line = raw.card_lines[d.index()][card].unwrap_or(raw.entry.line);
                    (line, format!("{}.{name}", d.name()))
                }
                None => (raw.first_card, name.to_string()),
            }
        }
        PropertyError::UnknownJointType(_) => (raw.first_card, "Type".to_string()),
        PropertyError::InvalidCurve(_) => (raw.entry.line, "fct_ID".to_string()),
    };
    fields.error(line, field, DeckErrorKind::Property(err))
}
