//! The scene's top-level settings: `units`, `gravity`, `dt`, `substeps`, `duration` and
//! `[rapier]`, checked and in SI.

use super::checks::{finite_array, positive};
use super::MAX_PGS_ITERATIONS;
use crate::io::units::{Quantity, UnitSystem};
use crate::rapier::prelude::{PhysicsWorld, Real};
use crate::scene::schema::Scene;
use crate::scene::{FieldPath, SceneError, Source, MAX_FRAMES, MAX_SUBSTEPS, MAX_SUBSTEP_TIME};

/// The top-level settings of a scene, in SI.
pub(super) struct Settings {
    /// The scene's unit system.
    pub units: UnitSystem,
    /// Gravity \[m/s²\].
    pub gravity: [f64; 3],
    /// Frame time step \[s\].
    pub frame_dt: f64,
    /// Simulated time \[s\].
    pub duration: f64,
}

/// Parses a unit-system string: `"SI"` or three unit names `"mass length time"`; `None`
/// for anything else, an empty or blank string too (a scene without `units` is SI, but
/// `units = ""` is a value left out by mistake, not a choice of SI).
pub fn parse_units(s: &str) -> Option<UnitSystem> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("si") {
        return Some(UnitSystem::SI);
    }
    let parts: Vec<&str> = t.split_whitespace().collect();
    match parts.as_slice() {
        [m, l, ti] => UnitSystem::from_names(m, l, ti),
        _ => None,
    }
}

/// The units, gravity, frame time step, substeps and duration of `scene`, checked.
pub(super) fn settings(scene: &Scene, src: &Source) -> Result<Settings, SceneError> {
    let units = parse_units(&scene.units).ok_or_else(|| {
        let expected = "expected \"SI\" or three unit names \"mass length time\", e.g. \
                        \"kg mm ms\"";
        let parts: Vec<&str> = scene.units.split_whitespace().collect();
        // the name not understood, and what each of the three may be (`"kg mm sec"` said
        // only that the system was unknown; a Radioss analyst's trial, 2026-12-06)
        let wrong = match parts.as_slice() {
            [m, l, t] => {
                use crate::io::units as u;
                [
                    (m, u::mass_unit(m).is_none(), "mass", u::MASS_UNITS),
                    (l, u::length_unit(l).is_none(), "length", u::LENGTH_UNITS),
                    (t, u::time_unit(t).is_none(), "time", u::TIME_UNITS),
                ]
            }
            .into_iter()
            .filter(|w| w.1)
            .map(|(name, _, what, names)| {
                format!("the {what} unit `{name}` is none of {names} (or a size in SI)")
            })
            .collect::<Vec<_>>()
            .join(", "),
            _ => String::new(),
        };
        let message = if scene.units.trim().is_empty() {
            format!("an empty unit system: {expected} (leave `units` out for SI)")
        } else if !wrong.is_empty() {
            format!("unknown unit system `{}`: {wrong}; {expected}", scene.units)
        } else {
            format!("unknown unit system `{}`: {expected}", scene.units)
        };
        src.error(&FieldPath::root("units"), message)
    })?;
    let l = units.factor(Quantity::Length);
    let t = units.factor(Quantity::Time);
    let root = FieldPath::default();
    let gravity = match scene.gravity {
        Some(g) => finite_array(src, &root.key("gravity"), g)?.map(|x| x * l / (t * t)),
        None => [0.0, -9.81, 0.0],
    };
    let frame_dt = match scene.dt {
        Some(dt) => positive(src, &root.key("dt"), dt)? * t,
        None => 1.0 / 60.0,
    };
    if scene.substeps == 0 || scene.substeps > MAX_SUBSTEPS {
        return Err(src.error(
            &root.key("substeps"),
            format!("{}: expected 1 ..= 100000", scene.substeps),
        ));
    }
    let substep = frame_dt / scene.substeps as f64;
    if substep > MAX_SUBSTEP_TIME {
        return Err(src.error(
            &root.key("dt"),
            format!(
                "a substep dt / substeps = {} s: expected at most {MAX_SUBSTEP_TIME} s (rapier's \
                 contact queries do not end on longer ones): lower `dt` or raise `substeps`",
                crate::figure::fmt_num(substep)
            ),
        ));
    }
    let duration = positive(src, &root.key("duration"), scene.duration)? * t;
    if duration / frame_dt > MAX_FRAMES {
        return Err(src.error(&root.key("duration"), "more than 1e8 frames: raise `dt`"));
    }
    Ok(Settings {
        units,
        gravity,
        frame_dt,
        duration,
    })
}

/// Rapier's solver settings of the scene's `[rapier]` table, set on `world`.
pub(super) fn solver(
    scene: &Scene,
    src: &Source,
    world: &mut PhysicsWorld,
) -> Result<(), SceneError> {
    let pgs = scene.rapier.pgs_iterations;
    if pgs == 0 || pgs > MAX_PGS_ITERATIONS {
        return Err(src.error(
            &FieldPath::root("rapier").key("pgs_iterations"),
            format!("{pgs}: expected 1 ..= {MAX_PGS_ITERATIONS}"),
        ));
    }
    world.integration_parameters.num_internal_pgs_iterations = pgs;
    world.integration_parameters.friction_in_bias_pass = scene.rapier.friction_in_bias_pass;
    // no speed cap: rapier clips every body's speed to 400 m/s by default (a game's safety
    // net for its contacts), which a scene's physics does not have (a block at 500 m/s
    // slowed to 400 m/s, a fifth of its energy gone, and nothing said so)
    world.integration_parameters.normalized_max_linear_velocity = Real::MAX;
    Ok(())
}
