//! The `property` of a scene joint: inline (in the scene's units, converted by
//! [`property_to_si`]) or a `{ deck, id }` reference to a Radioss `/PROP/TYPE45`, read by
//! [`radioss::RadiossDeck::from_file`] in SI with the deck's own `/UNIT` (or its `/BEGIN`
//! input units); and where each came from.

use super::checks::listed;
use super::files::{not_in_file, read_once, ReadOnce};
use crate::error::PropertyError;
use crate::io::radioss;
use crate::io::units::{property_to_si, UnitSystem};
use crate::law::{Dof, KjointProperty};
use crate::rapier::prelude::Rotation;
use crate::scene::schema::PropertySpec;
use crate::scene::{FieldPath, SceneError, Source};
use std::path::PathBuf;

/// Where a joint's property comes from, for reports.
#[derive(Debug, Clone, PartialEq)]
pub enum PropertyOrigin {
    /// Written inline in the scene (with its unit system).
    Inline,
    /// Built from a URDF joint (`robots` of the scene).
    Urdf {
        /// The URDF file (resolved path).
        file: PathBuf,
    },
    /// Built from an MJCF joint (`robots` of the scene, `mjcf = ...`).
    Mjcf {
        /// The MJCF file (resolved path).
        file: PathBuf,
    },
    /// Read from a Radioss deck.
    Deck {
        /// The deck file (resolved path).
        file: PathBuf,
        /// `prop_ID`.
        id: u32,
        /// The deck's title of the property.
        title: String,
    },
}

/// The frames a deck property's `Skew_ID1` and `Skew_ID2` give (world axes, the skews'
/// `[X', Y', Z']` as columns); `None` where the property has no skew.
pub(super) type DeckSkews = [Option<Rotation>; 2];

/// A joint's property in SI and checked, with what else it brings.
pub(super) struct ResolvedProperty {
    /// The property, in SI.
    pub property: KjointProperty,
    /// Where it comes from.
    pub origin: PropertyOrigin,
    /// The delay of its deck's time sensor \[s\] (deck properties with a sensor).
    pub sensor_delay: Option<f64>,
    /// The frames its deck's skews give.
    pub skews: DeckSkews,
}

/// The Radioss decks a scene refers to, each read once, by resolved path.
pub(super) type Decks = ReadOnce<radioss::RadiossDeck>;

/// A property of the scene at `path`, in SI and checked.
pub(super) fn resolve_property(
    src: &Source,
    path: &FieldPath,
    spec: &PropertySpec,
    units: &UnitSystem,
    decks: &mut Decks,
) -> Result<ResolvedProperty, SceneError> {
    if let Some(deck) = &spec.deck {
        return deck_property(src, path, spec, deck, decks);
    }
    if spec.id.is_some() {
        return Err(src.error(&path.key("id"), "`id` needs `deck` (the Radioss file)"));
    }
    let Some(jt) = spec.joint_type else {
        return Err(src.error(
            path,
            "missing `type` (an inline property) or `deck` and `id` (a deck reference)",
        ));
    };
    let mut p = KjointProperty::new(jt);
    p.kn = spec.kn.unwrap_or(0.0);
    p.automatic = spec.automatic.unwrap_or_default();
    p.scale_factor = spec.scale_factor.unwrap_or(0.0);
    p.critical_damping = spec.critical_damping.unwrap_or(0.0);
    // 0 is "no sensor", as a deck's sens_ID
    p.sensor = spec.sensor.filter(|&id| id != 0);
    for (dof, law) in Dof::ALL.iter().zip(spec.dof_laws()) {
        if let Some(law) = law {
            if !jt.is_free(*dof) {
                return Err(src.error(
                    &path.key(dof.name()),
                    format!(
                        "DOF {} is blocked for a {} joint: it takes no law (free DOFs: {})",
                        dof.name(),
                        jt.name(),
                        free_names(jt)
                    ),
                ));
            }
            p.dofs[dof.index()] = law.clone();
        }
    }
    p.validate().map_err(|e| property_error(src, path, e))?;
    let si = property_to_si(&p, units).map_err(|e| property_error(src, path, e))?;
    si.validate().map_err(|e| property_error(src, path, e))?;
    Ok(ResolvedProperty {
        property: si,
        origin: PropertyOrigin::Inline,
        sensor_delay: None,
        skews: [None, None],
    })
}

/// A `{ deck, id }` reference: the deck's `/PROP/TYPE45` with that `prop_ID`, its sensor's
/// delay and its skews (the deck read once per file).
fn deck_property(
    src: &Source,
    path: &FieldPath,
    spec: &PropertySpec,
    deck: &str,
    decks: &mut Decks,
) -> Result<ResolvedProperty, SceneError> {
    let inline = spec.joint_type.is_some()
        || spec.kn.is_some()
        || spec.automatic.is_some()
        || spec.scale_factor.is_some()
        || spec.critical_damping.is_some()
        || spec.sensor.is_some()
        || spec.dof_laws().iter().any(|d| d.is_some());
    if inline {
        return Err(src.error(
            path,
            "a deck reference `{ deck, id }` takes no inline property fields",
        ));
    }
    let Some(id) = spec.id else {
        return Err(src.error(&path.key("deck"), "a deck reference needs `id` (prop_ID)"));
    };
    let (file, d) = read_once(src, &path.key("deck"), deck, decks, |f| {
        radioss::RadiossDeck::from_file(f).map_err(|e| e.to_string())
    })?;
    let Some(entry) = d.property(id) else {
        let missing = format!("no /PROP/TYPE45 with prop_ID {id}");
        let ids = d.properties.keys();
        return Err(not_in_file(src, &path.key("id"), missing, &file, ids));
    };
    let sensor_delay = entry
        .property_si
        .sensor
        .and_then(|s| d.sensors.get(&s))
        .map(|s| s.tdelay_si());
    // the reader checked that the skews exist
    let skews =
        [entry.skew1, entry.skew2].map(|id| id.and_then(|id| d.skews.get(&id)).map(skew_rotation));
    Ok(ResolvedProperty {
        property: entry.property_si.clone(),
        origin: PropertyOrigin::Deck {
            file,
            id,
            title: entry.title.clone(),
        },
        sensor_delay,
        skews,
    })
}

/// A `/SKEW/FIX` frame as a rotation whose columns are its axes.
fn skew_rotation(s: &radioss::SkewFix) -> Rotation {
    let [x, y, z] = s.axes().map(nalgebra::Vector3::from);
    let m = nalgebra::Matrix3::from_columns(&[x, y, z]);
    let q = nalgebra::UnitQuaternion::from_rotation_matrix(
        &nalgebra::Rotation3::from_matrix_unchecked(m),
    );
    crate::dynamics::to_quat(&q)
}

/// Names of the free DOFs of a type, e.g. `rx` or `none`.
fn free_names(jt: crate::JointType) -> String {
    let v: Vec<&str> = Dof::ALL
        .iter()
        .filter(|d| jt.is_free(**d))
        .map(|d| d.name())
        .collect();
    listed(v)
}

/// A [`PropertyError`] at its field under `base`, e.g. `rx.stop_min (SA-)` →
/// `base.rx.stop_min`.
pub(super) fn property_error(src: &Source, base: &FieldPath, e: PropertyError) -> SceneError {
    match &e {
        PropertyError::InvalidField { field, .. } => {
            let name = field.split(" (").next().unwrap_or(field);
            let mut p = base.clone();
            for k in name.split('.') {
                p = p.key(k);
            }
            let mut err = src.error(&p, e.to_string());
            err.field = p.to_string();
            err
        }
        _ => src.error(base, e.to_string()),
    }
}
