//! The connector law of a scene joint: `planar_friction`, `joint_friction`, or `flex_joint` (inline, or a
//! `{ deck, element }` reference to a riser deck's `*FLEXJOINT`, read by
//! [`riser::RiserDeck::from_file`]), in SI and checked against the joint's property.

use super::checks::non_negative;
use super::files::{not_in_file, read_once, ReadOnce};
use super::properties::property_error;
use crate::error::PropertyError;
use crate::io::riser;
use crate::io::units::{connector_to_si, Quantity, UnitSystem};
use crate::law::{
    ConnectorLaw, Curve, FlexJointConnector, FlexJointLaw, JointFriction, KjointProperty,
    PlanarFriction,
};
use crate::scene::schema::{FlexJointSpec, JointSpec};
use crate::scene::{FieldPath, SceneError, Source};

/// The riser decks a scene refers to, each read once, by resolved path.
pub(super) type RiserDecks = ReadOnce<riser::RiserDeck>;

/// The connector law of joint `j` at `p` (`planar_friction` or `flex_joint`), in SI and
/// checked against the joint's property.
pub(super) fn resolve_connector(
    src: &Source,
    p: &FieldPath,
    j: &JointSpec,
    prop: &KjointProperty,
    units: &UnitSystem,
    riser_decks: &mut RiserDecks,
) -> Result<ConnectorLaw, SceneError> {
    if let Some(jf) = &j.joint_friction {
        if j.planar_friction.is_some() || j.flex_joint.is_some() {
            return Err(src.error(
                &p.key("joint_friction"),
                "a joint takes one connector law: `joint_friction`, `planar_friction` or \
                 `flex_joint`, not two",
            ));
        }
        return joint_friction(src, &p.key("joint_friction"), jf, prop, units);
    }
    let (law, path) = match (&j.planar_friction, &j.flex_joint) {
        (None, None) => return Ok(ConnectorLaw::None),
        (Some(_), Some(_)) => {
            return Err(src.error(
                &p.key("flex_joint"),
                "a joint takes one connector law: `planar_friction` or `flex_joint`, not both",
            ))
        }
        (Some(pf), None) => {
            let path = p.key("planar_friction");
            (planar_friction(src, &path, pf, units)?, path)
        }
        (None, Some(fj)) => {
            let path = p.key("flex_joint");
            (flex_joint(src, &path, fj, units, riser_decks)?, path)
        }
    };
    law.validate(prop)
        .map_err(|e| src.error(&path, e.to_string()))?;
    Ok(law)
}

/// A planar friction law, checked, in SI.
fn planar_friction(
    src: &Source,
    path: &FieldPath,
    pf: &PlanarFriction,
    units: &UnitSystem,
) -> Result<ConnectorLaw, SceneError> {
    pf.validate().map_err(|e| property_error(src, path, e))?;
    connector_to_si(&ConnectorLaw::PlanarFriction(*pf), units)
        .map_err(|e| property_error(src, path, e))
}

/// A joint friction law, in SI, checked against the joint's type (a bad field is named:
/// `joints[i].joint_friction.pin_radius`) and property.
fn joint_friction(
    src: &Source,
    path: &FieldPath,
    jf: &JointFriction,
    prop: &KjointProperty,
    units: &UnitSystem,
) -> Result<ConnectorLaw, SceneError> {
    let law = ConnectorLaw::JointFriction(*jf);
    if JointFriction::JOINT_TYPES.contains(&prop.joint_type) {
        jf.validate_for(prop.joint_type)
            .map_err(|e| property_error(src, path, e))?;
    }
    let law = connector_to_si(&law, units).map_err(|e| property_error(src, path, e))?;
    law.validate(prop)
        .map_err(|e| src.error(path, e.to_string()))?;
    Ok(law)
}

/// The scene key of a flex joint field named as in the riser deck (`Kdyn_ini`, `IPRO`, ...).
fn flex_key(path: &FieldPath, e: &PropertyError) -> FieldPath {
    let PropertyError::InvalidField { field, .. } = e else {
        return path.clone();
    };
    match field.as_str() {
        "IPRO" => path.key("bending"),
        "IPROT" => path.key("torsion"),
        "Ktor" => path.key("dynamic").key("torsion_stiffness"),
        "IFLAG" => path.key("dynamic").key("iflag"),
        "Kdyn_ini" => path.key("dynamic").key("kdyn_ini"),
        "Kdyn_lim" => path.key("dynamic").key("kdyn_lim"),
        "Angle_lim" => path.key("dynamic").key("angle_lim"),
        "Teta" => path.key("dynamic").key("teta"),
        "CP" => path.key("dynamic").key("torsion_damping"),
        _ => path.clone(),
    }
}

/// A flex joint law's error in the scene's words: the deck's names (IPRO, IPROT, Ktor, …)
/// as the scene's keys, which the error's field path names too.
fn flex_message(e: &PropertyError) -> String {
    let PropertyError::InvalidField {
        field,
        value,
        expected,
    } = e
    else {
        return e.to_string();
    };
    if field == "IPRO" && value == "0" {
        return "a flex joint needs a `bending` law or a `dynamic` law (a `torsion` law alone \
                leaves the bending free)"
            .to_string();
    }
    let key = match field.as_str() {
        "IPRO" => "bending",
        "IPROT" => "torsion",
        "Ktor" => "dynamic.torsion_stiffness",
        "IFLAG" => "dynamic.iflag",
        "Kdyn_ini" => "dynamic.kdyn_ini",
        "Kdyn_lim" => "dynamic.kdyn_lim",
        "Angle_lim" => "dynamic.angle_lim",
        "Teta" => "dynamic.teta",
        "CP" => "dynamic.torsion_damping",
        other => other,
    };
    format!("invalid {key} = {value}: expected {expected}")
}

/// A flex joint law: from a riser deck (in SI, only the switch time in the scene's
/// units) or inline (converted into SI).
fn flex_joint(
    src: &Source,
    path: &FieldPath,
    fj: &FlexJointSpec,
    units: &UnitSystem,
    riser_decks: &mut RiserDecks,
) -> Result<ConnectorLaw, SceneError> {
    let switch_time = match fj.switch_time {
        Some(t) => Some(non_negative(src, &path.key("switch_time"), t)?),
        None => None,
    };
    if let Some(deck) = &fj.deck {
        let law = deck_flex_joint(src, path, fj, deck, riser_decks)?;
        let c = FlexJointConnector {
            law,
            switch_time: switch_time.map(|t| t * units.factor(Quantity::Time)),
        };
        check_switch(src, path, &c)?;
        return Ok(ConnectorLaw::FlexJoint(c));
    }
    if fj.element.is_some() {
        return Err(src.error(
            &path.key("element"),
            "`element` needs `deck` (the riser deck)",
        ));
    }
    let curve = |key: &str, pts: &Option<Vec<[f64; 2]>>| -> Result<Option<Curve>, SceneError> {
        let Some(pts) = pts else { return Ok(None) };
        Curve::new(pts.iter().map(|p| (p[0], p[1])))
            .map(Some)
            .map_err(|e| src.error(&path.key(key), e.to_string()))
    };
    let law = FlexJointLaw::new(
        curve("bending", &fj.bending)?,
        curve("torsion", &fj.torsion)?,
        fj.dynamic,
    )
    .map_err(|e| src.error(&flex_key(path, &e), flex_message(&e)))?;
    let law = ConnectorLaw::FlexJoint(FlexJointConnector { law, switch_time });
    let law = connector_to_si(&law, units)
        .map_err(|e| src.error(&flex_key(path, &e), flex_message(&e)))?;
    if let ConnectorLaw::FlexJoint(c) = &law {
        check_switch(src, path, c)?;
    }
    Ok(law)
}

/// The law of a `{ deck, element }` reference: the riser deck's `*FLEXJOINT` element
/// `element` (the deck read once per file).
fn deck_flex_joint(
    src: &Source,
    path: &FieldPath,
    fj: &FlexJointSpec,
    deck: &str,
    riser_decks: &mut RiserDecks,
) -> Result<FlexJointLaw, SceneError> {
    if fj.bending.is_some() || fj.torsion.is_some() || fj.dynamic.is_some() {
        return Err(src.error(
            path,
            "a deck reference `{ deck, element }` takes no inline `bending`, `torsion` or \
             `dynamic`",
        ));
    }
    let Some(nel) = fj.element else {
        return Err(src.error(
            &path.key("deck"),
            "a deck reference needs `element` (NEL of the *FLEXJOINT element)",
        ));
    };
    let (file, d) = read_once(src, &path.key("deck"), deck, riser_decks, |f| {
        riser::RiserDeck::from_file(f).map_err(|e| e.to_string())
    })?;
    let Some(el) = d.joints.iter().find(|e| e.id == nel) else {
        let missing = format!("no *FLEXJOINT element {nel}");
        let ids = d.joints.iter().map(|e| e.id);
        return Err(not_in_file(src, &path.key("element"), missing, &file, ids));
    };
    Ok(el.law.clone())
}

/// A switch time needs the dynamic law to switch to.
fn check_switch(src: &Source, path: &FieldPath, c: &FlexJointConnector) -> Result<(), SceneError> {
    if c.switch_time.is_some() && c.law.dynamic.is_none() {
        return Err(src.error(
            &path.key("switch_time"),
            "a switch to the dynamic phase needs the dynamic law (`dynamic`, or IMAT != 0 in \
             the deck)",
        ));
    }
    Ok(())
}
