//! The scene's `[[joints]]`: KJOINT2 joints between named bodies, with their property,
//! connector law, anchors and frames.

use super::checks::{finite_array, rotation, vec3};
use super::connectors::{resolve_connector, RiserDecks};
use super::properties::{property_error, resolve_property, DeckSkews, Decks};
use super::Assembly;
use crate::error::SimError;
use crate::io::units::{Quantity, UnitSystem};
use crate::law::{BreakCriterion, ConnectorLaw, KjointProperty};
use crate::scene::schema::{JointSpec, Scene};
use crate::scene::{FieldPath, SceneError, Source};
use crate::KjointBuilder;
use std::collections::BTreeMap;

/// The sensors the joints' properties refer to.
#[derive(Default)]
pub(super) struct SensorRefs {
    /// Each property's sensor id, at its field.
    pub used: Vec<(u32, FieldPath)>,
    /// The time sensors of deck properties: the delay \[s\] by id.
    pub deck_delays: BTreeMap<u32, f64>,
}

impl Assembly {
    /// Adds the scene's joints; returns the sensors their properties refer to.
    pub(super) fn add_joints(
        &mut self,
        scene: &Scene,
        src: &Source,
        units: &UnitSystem,
    ) -> Result<SensorRefs, SceneError> {
        let mut decks = Decks::new();
        let mut riser_decks = RiserDecks::new();
        let mut sensors = SensorRefs::default();
        for (i, j) in scene.joints.iter().enumerate() {
            let p = FieldPath::root("joints").index(i);
            if j.name.is_empty() {
                return Err(src.error(&p.key("name"), "a joint needs a non-empty name"));
            }
            if self.joint_names.contains_key(&j.name) || self.rapier_joints.contains_key(&j.name) {
                return Err(src.error(&p.key("name"), format!("duplicate joint name `{}`", j.name)));
            }
            let b1 = self.body(src, &p.key("body1"), &j.body1)?;
            let b2 = self.body(src, &p.key("body2"), &j.body2)?;
            let prop = resolve_property(src, &p.key("property"), &j.property, units, &mut decks)?;
            if let Some(s) = prop.property.sensor {
                sensors.used.push((s, p.key("property").key("sensor")));
                if let Some(d) = prop.sensor_delay {
                    sensors.deck_delays.insert(s, d);
                }
            }
            let connector = resolve_connector(src, &p, j, &prop.property, units, &mut riser_decks)?;
            // an inline flex joint law's notices (a deck's come with the deck's below)
            if let (ConnectorLaw::FlexJoint(c), Some(None)) =
                (&connector, j.flex_joint.as_ref().map(|f| f.deck.as_ref()))
            {
                let at = p.key("flex_joint");
                self.deck_notices.extend(
                    c.law
                        .notices()
                        .into_iter()
                        .map(|n| format!("{}: {at}: {n}", src.file.display())),
                );
            }
            let l = units.factor(Quantity::Length);
            let mut jb =
                joint_builder(src, &p, j, prop.property, l, prop.skews)?.connector(connector);
            if let Some(c) = &j.break_criterion {
                jb = jb.break_when(break_criterion(src, &p.key("break"), c, units)?);
            }
            jb = jb.contacts_enabled(j.contacts).enabled(j.enabled);
            let h = self
                .joints
                .insert(jb, b1, b2, &self.world.bodies)
                .map_err(|e| sim_error(src, &p, e))?;
            self.joint_names.insert(j.name.clone(), h);
            self.origins.push((h, prop.origin));
        }
        // what the decks said of what the joints read (a property that ends before its
        // cards, the units a deck's values were converted from), not the blocks they skip
        let mut files: Vec<_> = decks.iter().map(|(f, d)| (f, &d.notices)).collect();
        files.extend(riser_decks.iter().map(|(f, d)| (f, &d.notices)));
        files.sort_by(|a, b| a.0.cmp(b.0));
        for (_, notices) in files {
            let kept = notices.iter().filter(|n| !n.message.contains("skipped"));
            self.deck_notices.extend(kept.map(|n| n.to_string()));
        }
        Ok(sensors)
    }
}

/// The joint's builder: anchors, and its frames from the scene's `frame`/`frame2` or from
/// the `Skew_ID1`/`Skew_ID2` of its deck property (both for the same frame is an error: the
/// scene would silently override the deck, or the reverse).
fn joint_builder(
    src: &Source,
    p: &FieldPath,
    j: &JointSpec,
    prop: KjointProperty,
    l: f64,
    skews: DeckSkews,
) -> Result<KjointBuilder, SceneError> {
    let a1 = finite_array(src, &p.key("anchor1"), j.anchor1)?;
    let a2 = finite_array(src, &p.key("anchor2"), j.anchor2)?;
    let mut jb = KjointBuilder::new(prop)
        .name(j.name.clone())
        .local_anchor1(vec3(a1, l))
        .local_anchor2(vec3(a2, l));
    for (k, (key, skew_id, scene_frame)) in [
        ("frame", "Skew_ID1", &j.frame),
        ("frame2", "Skew_ID2", &j.frame2),
    ]
    .into_iter()
    .enumerate()
    {
        let r = match (scene_frame, skews[k]) {
            (Some(_), Some(_)) => {
                return Err(src.error(
                    &p.key(key),
                    format!(
                        "the deck property's {skew_id} already gives this frame: remove `{key}` \
                         (or the skew from the deck)"
                    ),
                ))
            }
            (Some(r), None) => Some(rotation(src, &p.key(key), r)?),
            (None, skew) => skew,
        };
        if let Some(r) = r {
            jb = if k == 0 {
                jb.world_frame1(r)
            } else {
                jb.world_frame2(r)
            };
        }
    }
    Ok(jb)
}

/// The joint's `break` table at `p`, checked (the error names its field) and in SI: the
/// force limit times the force unit, the moment's the moment unit, the energy's the force
/// unit times the length unit.
fn break_criterion(
    src: &Source,
    p: &FieldPath,
    c: &BreakCriterion,
    units: &UnitSystem,
) -> Result<BreakCriterion, SceneError> {
    c.validate().map_err(|e| property_error(src, p, e))?;
    Ok(BreakCriterion {
        force: c.force * units.factor(Quantity::Force),
        moment: c.moment * units.factor(Quantity::Moment),
        dissipated_energy: c.dissipated_energy
            * units.factor(Quantity::Force)
            * units.factor(Quantity::Length),
        ..*c
    })
}

/// An error of the joint set about joint `p`, at the field it names.
fn sim_error(src: &Source, p: &FieldPath, e: SimError) -> SceneError {
    match e {
        SimError::Property { source, .. } => property_error(src, &p.key("property"), source),
        SimError::InvalidArgument { ref field, .. } if field.ends_with("frame2") => {
            src.error(&p.key("frame2"), e.to_string())
        }
        SimError::InvalidJoint { ref reason, .. } if reason.contains("Skew2") => {
            src.error(&p.key("frame2"), e.to_string())
        }
        // (at `body2`, the line to change: it named the joint's table header)
        SimError::InvalidJoint { ref reason, .. } if reason.contains("are the same body") => {
            src.error(&p.key("body2"), e.to_string())
        }
        other => src.error(p, other.to_string()),
    }
}
