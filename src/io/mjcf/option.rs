//! The model's `<option>`: MuJoCo's simulation settings. Its `gravity` is the one setting a
//! KJOINT2 run takes from it: checked here, it is the model's gravity
//! ([`RobotDescription::gravity`](crate::io::robot::RobotDescription::gravity)), which a
//! robot file run as a scene of its own runs under ([`crate::scene::robot_scene`]).
//! `<flag gravity="disable"/>` makes it zero, as in MuJoCo. Everything else of `<option>`
//! (its `timestep`, integrator, solver, fluid and contact settings, the other flags) is not
//! used: a notice names each, with what the run uses instead.

use super::check::element_at;
use crate::figure::{fmt_num, format_figure};
use crate::io::urdf::{in_range, ErrorContext, UrdfError, RANGES};
use rapier3d_mjcf::mjcf_rs::model::Model;

/// MuJoCo's gravity where a model's `<option>` gives none \[m/s²\].
pub(super) const MUJOCO_GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// MuJoCo's `timestep` where a model's `<option>` gives none \[s\].
const MUJOCO_TIMESTEP: f64 = 0.002;

/// The `<option>` elements of the model's own text (not those of an `<include>`d file).
fn options<'a, 'i>(
    doc: &'a roxmltree::Document<'i>,
) -> impl Iterator<Item = roxmltree::Node<'a, 'i>> + 'a {
    doc.root_element()
        .children()
        .filter(|n| n.is_element() && n.tag_name().name() == "option")
}

/// The gravity the model gives \[m/s²\]: its `<option gravity>` (mjcf-rs has read it, from
/// an `<include>`d file too), zero with a `<flag gravity="disable"/>` of its own text;
/// `None` where it gives neither (MuJoCo then runs under [`MUJOCO_GRAVITY`]).
pub(super) fn gravity(model: &Model, doc: Option<&roxmltree::Document>) -> Option<[f64; 3]> {
    let written = doc.is_some_and(|d| options(d).any(|o| o.has_attribute("gravity")));
    let disabled = doc.is_some_and(|d| {
        options(d)
            .flat_map(|o| o.children())
            .any(|f| f.has_tag_name("flag") && f.attribute("gravity") == Some("disable"))
    });
    if disabled {
        Some([0.0; 3])
    } else if written || model.option.gravity != MUJOCO_GRAVITY {
        Some(model.option.gravity)
    } else {
        None
    }
}

/// Checks the `<option>` values mjcf-rs has read, `gravity` and `timestep`: finite and
/// within ±1e12, the error naming `<option>`, its line and the attribute as written (NaN
/// gravity would make every body's pose NaN).
pub(super) fn check(
    context: &ErrorContext,
    model: &Model,
    doc: Option<&roxmltree::Document>,
) -> Result<(), UrdfError> {
    if let Some(doc) = doc {
        for node in options(doc) {
            for a in ["gravity", "timestep"] {
                let Some(value) = node.attribute(a) else {
                    continue;
                };
                let v: Vec<f64> = value
                    .split_whitespace()
                    .filter_map(|t| t.parse().ok())
                    .collect();
                let expected = if v.iter().any(|x| !x.is_finite()) {
                    "finite numbers"
                } else if v.iter().any(|x| !in_range(*x)) {
                    RANGES
                } else {
                    continue;
                };
                return Err(context.field(element_at(doc, &node), a, value, expected));
            }
        }
    }
    // what an <include>d file gave
    context.finite3("<option>", "gravity", &model.option.gravity)?;
    context.finite("<option>", "timestep", model.option.timestep)?;
    Ok(())
}

/// A notice for each part of `<option>` the run does not use: its `timestep` (the run steps
/// at its own substep; `substep` is the one the loader assumed, [`UrdfOptions::substep`]),
/// its other attributes and its flags (but `<flag gravity="disable"/>`, which [`gravity`]
/// reads).
///
/// [`UrdfOptions::substep`]: crate::io::urdf::UrdfOptions::substep
pub(super) fn notices(
    model: &Model,
    doc: Option<&roxmltree::Document>,
    substep: f64,
) -> Vec<String> {
    let mut notices = Vec::new();
    let timestep = |at: &str| {
        format!(
            "{at}timestep = {} s not used: the joints step at the run's substep (a scene's dt / \
             substeps; 1/60 s frames of 4 substeps when the file runs as a scene of its own; \
             {} s assumed for this model's friction stiffness)",
            fmt_num(model.option.timestep),
            format_figure(substep)
        )
    };
    let Some(doc) = doc else {
        if model.option.timestep != MUJOCO_TIMESTEP {
            notices.push(timestep("<option>: "));
        }
        return notices;
    };
    let mut timestep_written = false;
    for node in options(doc) {
        let el = element_at(doc, &node);
        let mut others = Vec::new();
        for a in node.attributes() {
            match a.name() {
                "gravity" => {}
                "timestep" => {
                    timestep_written = true;
                    notices.push(timestep(&format!("{el}: ")));
                }
                name => others.push(format!("{name}=\"{}\"", a.value())),
            }
        }
        if !others.is_empty() {
            notices.push(format!(
                "{el}: {} not used (rapier integrates the bodies and solves the contacts, the \
                 KJOINT2 joints are updated implicitly at each substep, with their own settings)",
                others.join(" ")
            ));
        }
        for flag in node.children().filter(|n| n.has_tag_name("flag")) {
            let unused: Vec<String> = flag
                .attributes()
                .filter(|a| !(a.name() == "gravity" && a.value() == "disable"))
                .map(|a| format!("{}=\"{}\"", a.name(), a.value()))
                .collect();
            if !unused.is_empty() {
                notices.push(format!(
                    "{}: {} not used (MuJoCo's simulation flags; only gravity=\"disable\" is read)",
                    element_at(doc, &flag),
                    unused.join(" ")
                ));
            }
        }
    }
    if !timestep_written && model.option.timestep != MUJOCO_TIMESTEP {
        notices.push(timestep("<option>: "));
    }
    notices
}
