//! `kjoint check FILE`: prints everything a scene, a robot, a Radioss deck or a riser deck
//! resolves to (defaults applied, in SI), or the errors. The kind of file is told by its
//! extension (`.toml`/`.json`: a scene; `.urdf`, `.xml`, `.mjcf`: a robot, as the scene
//! `scene::robot_scene` makes of it; `.rad`, `.dat`, `.inc`: a Radioss deck) and, for other
//! extensions, by its keywords (a riser deck's `*FLEXJOINT`, ...).

use super::{describe, Failure, Out};
use rapier_kjoint::dynamics::KjointEventKind;
use rapier_kjoint::figure::{fmt_num, format_figure};
use rapier_kjoint::io::{radioss, riser};
use rapier_kjoint::law::{ConnectorLaw, FlexJointConnector};
use rapier_kjoint::scene::build::{MotionKind, PropertyOrigin};
use rapier_kjoint::scene::{self, BuiltScene, Format};
use std::path::Path;

/// `kjoint check`: a riser deck, a Radioss deck or a scene, by the file's extension and
/// keywords.
pub(super) fn check(out: Out, path: &Path) -> Result<(), Failure> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    if Format::of(path).is_none() {
        // read once within the size cap, so that a huge file or a device is refused here
        let bytes = rapier_kjoint::io::read_input(path).map_err(|e| e.to_string())?;
        if is_riser_deck(&bytes) {
            return check_riser_deck(out, path);
        }
    }
    if matches!(ext.as_deref(), Some("rad") | Some("dat") | Some("inc"))
        && Format::of(path).is_none()
    {
        return check_radioss_deck(out, path);
    }
    if Format::of(path).is_none() && scene::robot_scene(path).is_none() {
        return Err(format!(
            "{}: unknown kind of file: expected a scene (`.toml`, `.json`), a robot \
             (`.urdf`, MJCF `.xml`), a Radioss deck (`.rad`, `.dat`, `.inc`) or a riser deck \
             (`*FLEXJOINT`, `*SPRINGPRO`, … keywords)",
            path.display()
        )
        .into());
    }
    check_scene(out, path)
}

/// A Radioss deck: its notices, its KJOINT2 properties in SI and its time sensors.
fn check_radioss_deck(out: Out, path: &Path) -> Result<(), Failure> {
    let deck = radioss::RadiossDeck::from_file(path).map_err(|e| e.to_string())?;
    say!(out, "deck: {}", path.display());
    for n in &deck.notices {
        say!(out, "  notice, line {}: {}", n.line, n.message);
    }
    if deck.properties.is_empty() {
        // (an empty or truncated file, or the wrong one: nothing a scene could use)
        return Err(format!(
            "{}: no /PROP/TYPE45 (KJOINT2) property: expected a Radioss deck with at least \
             one (or a riser deck with a *FLEXJOINT, which this file has not either)",
            path.display()
        )
        .into());
    }
    for e in deck.properties.values() {
        let unit = match (&e.unit, e.unit_id) {
            (Some(u), id) => format!(
                "{} (mass {} kg, length {} m, time {} s), converted to SI",
                id.map_or("/BEGIN's input units".into(), |id| format!("unit_ID {id}")),
                u.mass,
                u.length,
                u.time
            ),
            (None, _) => "values in SI".into(),
        };
        say!(
            out,
            "\nproperty {} `{}` (line {}, {}; {unit})",
            e.id,
            e.title,
            e.line,
            e.keyword
        );
        say_raw!(
            out,
            "{}",
            describe::property(&e.property_si, &e.property, "  ")
        );
        curve_preloads(out, &e.property_si)?;
        for (k, s) in [("Skew_ID1", e.skew1), ("Skew_ID2", e.skew2)] {
            if let Some(s) = s {
                let [x, y, z] = deck.skews[&s].axes();
                let v = |a: [f64; 3]| {
                    format!(
                        "[{}, {}, {}]",
                        format_figure(a[0]),
                        format_figure(a[1]),
                        format_figure(a[2])
                    )
                };
                say!(
                    out,
                    "  {k} = {s}: X' = {}, Y' = {}, Z' = {}",
                    v(x),
                    v(y),
                    v(z)
                );
            }
        }
        if let Some(theta0) = initial_angle(&deck, e) {
            say!(
                out,
                "  initial angle about X' (Skew_ID1 to Skew_ID2): θ0 = {} rad ({}°)",
                format_figure(theta0),
                format_figure(theta0.to_degrees())
            );
            let law = e.property_si.dof(rapier_kjoint::Dof::Rx);
            let beyond = (law.stop_max > 0.0 && theta0 > law.stop_max)
                || (law.stop_min < 0.0 && theta0 < law.stop_min);
            if beyond {
                say!(
                    out,
                    "  warning: θ0 is beyond the rx stops [{}, {}] rad: the stop pushes the \
                     joint back from the first substep (the stops, as the spring, read the \
                     angle θ0 included)",
                    fmt_num(law.stop_min),
                    fmt_num(law.stop_max)
                );
            }
        }
    }
    for s in deck.sensors.values() {
        say!(
            out,
            "\nsensor {} `{}`: time {} s",
            s.id,
            s.title,
            s.tdelay_si()
        );
    }
    say!(out, "\nok");
    Ok(())
}

/// A notice for each free DOF of `property` whose spring curve does not pass through (0, 0)
/// (the run gives it at its first substep, [`KjointEventKind::SpringCurvePreload`]).
fn curve_preloads(out: Out, property: &rapier_kjoint::KjointProperty) -> Result<(), Failure> {
    for (dof, force) in property.spring_preloads() {
        let kind = KjointEventKind::SpringCurvePreload { dof, force };
        say!(out, "  notice: {kind}");
    }
    Ok(())
}

/// The initial angle `θ0` \[rad\] about x of a property of a type free about x alone
/// (revolute, cylindrical, planar) with a `Skew_ID2`: the angle from Skew_ID1's `Y'` (the
/// global Y for `Skew_ID1 = 0`) to Skew_ID2's about Skew_ID1's `X'` (the reader checked the
/// two `X'` parallel), `atan2((y₁ × y₂)·x₁, y₁·y₂)`. `None` for another type or without
/// `Skew_ID2`.
fn initial_angle(deck: &radioss::RadiossDeck, e: &radioss::PropertyEntry) -> Option<f64> {
    let s2 = e.skew2?;
    if !e.property.joint_type.single_free_rotation() {
        return None;
    }
    let [x1, y1, _] = e
        .skew1
        .map_or([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], |s| {
            deck.skews[&s].axes()
        });
    let [_, y2, _] = deck.skews[&s2].axes();
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = [
        y1[1] * y2[2] - y1[2] * y2[1],
        y1[2] * y2[0] - y1[0] * y2[2],
        y1[0] * y2[1] - y1[1] * y2[0],
    ];
    Some(dot(cross, x1).atan2(dot(y1, y2)))
}

/// A scene (or a robot file as a scene of its own): its settings, bodies, joints, loads,
/// motions and motors, in SI.
fn check_scene(out: Out, path: &Path) -> Result<(), Failure> {
    let (sc, src, robot_file) = super::load_scene(path)?;
    let mut built = super::build_scene(&sc, &src, robot_file)?;
    // mass properties (URDF inertias included), computed by a step that moves nothing
    built.joints.prepare(&mut built.world);
    say!(out, "scene: {}", path.display());
    for n in &built.notices {
        say!(out, "  notice, {n}");
    }
    for w in &built.warnings {
        say!(out, "  warning: {w}");
    }
    scene_settings(out, &built, &sc.units)?;
    scene_robots(out, &built, &sc.robots)?;
    scene_bodies(out, &built)?;
    let resolved = resolved_copy(&sc, &src, robot_file, built.frame_dt);
    scene_joints(out, &built, &resolved)?;
    scene_sensors(out, &built)?;
    scene_schedules(out, &built)?;
    say!(out, "\nok");
    Ok(())
}

/// The scene's units (`units` as written), time steps, gravity and rapier's solver.
fn scene_settings(out: Out, built: &BuiltScene, units: &str) -> Result<(), Failure> {
    let u = &built.units;
    say!(
        out,
        "units: {} (mass {} kg, length {} m, time {} s); values below in SI",
        units,
        u.mass,
        u.length,
        u.time
    );
    say!(
        out,
        "frame dt {} s, {} substeps{}, duration {} s, gravity [{}, {}, {}] m/s²",
        built.frame_dt,
        built.joints.settings().substeps,
        if built.joints.settings().radioss_start {
            " (Radioss-compatible start: a half kick on the first)"
        } else {
            ""
        },
        built.duration,
        built.world.gravity.x,
        built.world.gravity.y,
        built.world.gravity.z
    );
    let ip = &built.world.integration_parameters;
    say!(
        out,
        "rapier's solver (contacts, rapier joints): {} iteration{} a substep, friction {}in \
         the bias pass",
        ip.num_internal_pgs_iterations,
        if ip.num_internal_pgs_iterations > 1 {
            "s"
        } else {
            ""
        },
        if ip.friction_in_bias_pass { "" } else { "not " }
    );
    Ok(())
}

/// Each robot of the scene: its file, its name, where it stands and how it is turned, as
/// written (scene units are SI for robots), and what it made when it has a name (its bodies
/// and joints are the scene's named `name/...`).
fn scene_robots(
    out: Out,
    built: &BuiltScene,
    robots: &[scene::schema::RobotSpec],
) -> Result<(), Failure> {
    for r in robots {
        let (kind, file) = match (&r.urdf, &r.mjcf) {
            (Some(f), _) => ("URDF", f.as_str()),
            (None, Some(f)) => ("MJCF", f.as_str()),
            (None, None) => ("robot", "?"),
        };
        let list = |v: &[f64]| {
            v.iter()
                .map(|x| format_figure(*x))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let at = list(&r.position.unwrap_or([0.0; 3]));
        let turned = match &r.rotation {
            None => "not turned".to_string(),
            Some(q) => match (&q.axis, q.angle, &q.quaternion) {
                (Some(axis), Some(angle), _) => format!(
                    "turned {} rad ({}°) about [{}]",
                    format_figure(angle),
                    format_figure(angle.to_degrees()),
                    list(axis)
                ),
                (_, _, Some(q)) => format!("turned by the quaternion [{}] (x, y, z, w)", list(q)),
                _ => "turned".to_string(),
            },
        };
        let name = match &r.name {
            None => "robot (its file's names)".to_string(),
            Some(n) => {
                let prefix = format!("{n}{}", rapier_kjoint::io::urdf::NAME_SEPARATOR);
                let mine = |s: &str| s.starts_with(&prefix);
                let bodies = built.bodies.iter().filter(|(b, _)| mine(b)).count();
                let joints = built.joints.iter().filter(|(_, j)| mine(&j.name)).count();
                let rapier = built.rapier_joints.iter().filter(|(j, _)| mine(j)).count();
                let count = |k: usize, one: &str, many: &str| {
                    format!("{k} {}", if k == 1 { one } else { many })
                };
                format!(
                    "robot `{n}` ({}, {}, {})",
                    count(bodies, "body", "bodies"),
                    count(joints, "KJOINT2 joint", "KJOINT2 joints"),
                    count(rapier, "rapier joint", "rapier joints")
                )
            }
        };
        say!(
            out,
            "{name}: {kind} {file}, its frame at [{at}] m, {turned}"
        );
    }
    Ok(())
}

/// Each body: its kind, mass and position, as figures (rapier keeps them in f32: a mass of
/// 2000 kg read back as 1999.9999, a position of 0.7 m as 0.70000005).
fn scene_bodies(out: Out, built: &BuiltScene) -> Result<(), Failure> {
    for (name, h) in &built.bodies {
        let b = &built.world.bodies[*h];
        let at = b.translation();
        let at = [at.x, at.y, at.z]
            .map(|v| format_figure(v as f64))
            .join(", ");
        if b.is_dynamic() {
            let mass = format_figure(b.mass() as f64);
            say!(out, "body `{name}`: dynamic, mass {mass} kg, at [{at}] m");
        } else if b.is_kinematic() {
            say!(
                out,
                "body `{name}`: kinematic (a prescribed motion), at [{at}] m"
            );
        } else {
            say!(out, "body `{name}`: fixed, at [{at}] m");
        }
    }
    Ok(())
}

/// Each sensor and its condition, in SI.
fn scene_sensors(out: Out, built: &BuiltScene) -> Result<(), Failure> {
    use rapier_kjoint::SensorCondition;
    let joints = &built.joints;
    let name = |h| joints.get(h).map_or("?", |j| j.name.as_str());
    for (id, s) in joints.sensors() {
        let when = match &s.condition {
            SensorCondition::Time(t) => format!("at t = {} s", fmt_num(*t)),
            SensorCondition::DofPasses { joint, dof, value } => format!(
                "when joint `{}` {} passes {} {}",
                name(*joint),
                dof.name(),
                fmt_num(*value),
                dof.unit()
            ),
            SensorCondition::ForceReaches { joint, dof, value } => {
                let (load, unit) = dof.load();
                format!(
                    "when joint `{}` transmits a {load} of {} {unit} or more on {}",
                    name(*joint),
                    fmt_num(*value),
                    dof.name()
                )
            }
            SensorCondition::Manual => "when triggered by the application".into(),
        };
        say!(
            out,
            "\nsensor {id}: activates {when}; locks the joints whose property names it"
        );
    }
    Ok(())
}

/// Each KJOINT2 joint (its property's origin, its property and connector law), then each
/// rapier joint.
fn scene_joints(
    out: Out,
    built: &BuiltScene,
    resolved: &Result<BuiltScene, String>,
) -> Result<(), Failure> {
    let mut decks: std::collections::HashMap<std::path::PathBuf, Option<radioss::RadiossDeck>> =
        std::collections::HashMap::new();
    for ((_, j), origin) in built.joints.iter().zip(&built.origins) {
        let from = match origin {
            PropertyOrigin::Inline => "inline".to_string(),
            PropertyOrigin::Urdf { file } => format!("URDF {}", file.display()),
            PropertyOrigin::Mjcf { file } => format!("MJCF {}", file.display()),
            PropertyOrigin::Deck { file, id, title } => {
                format!("deck {} prop_ID {id} `{title}`", file.display())
            }
        };
        say!(
            out,
            "\njoint `{}` ({from}), L0 = {} m",
            j.name,
            format_figure(j.initial_length())
        );
        // its axes (a flex joint's x is the riser's: an offshore engineer's riser without a
        // `frame` took the world axes, and nothing showed them)
        if let Some(b1) = built.world.bodies.get(j.body1()) {
            let r = b1.rotation() * j.local_frame1();
            // (the f32 rounding of a turned axis, below 1e-6, printed as 0)
            let c = |x: f64| format_figure(if x.abs() < 1e-6 { 0.0 } else { x });
            let v = |a: rapier_kjoint::rapier::math::Vector| {
                let a = r * a;
                format!("[{}, {}, {}]", c(a.x as f64), c(a.y as f64), c(a.z as f64))
            };
            use rapier_kjoint::rapier::math::Vector as V;
            say!(
                out,
                "  axes in the world at the start: x = {}, y = {}, z = {}",
                v(V::X),
                v(V::Y),
                v(V::Z)
            );
        }
        if !j.contacts_enabled() {
            say!(out, "  contacts between its two bodies: off");
        }
        if !j.is_switched_on() {
            say!(out, "  switched off at the start");
        }
        // a deck's property as written says which values are defaults (its blank ScF is
        // 10 of its work units in SI); each deck read again once
        let written = match origin {
            PropertyOrigin::Deck { file, id, .. } => decks
                .entry(file.clone())
                .or_insert_with(|| radioss::RadiossDeck::from_file(file).ok())
                .as_ref()
                .and_then(|d| d.property(*id))
                .map(|e| &e.property),
            _ => None,
        };
        let written = written.unwrap_or(j.property());
        say_raw!(out, "{}", describe::property(j.property(), written, "  "));
        curve_preloads(out, j.property())?;
        say_raw!(out, "{}", resolved_stiffness(built, resolved, &j.name));
        say_raw!(out, "{}", describe::connector(j.connector_law(), "  "));
    }
    for (name, h) in &built.rapier_joints {
        say_raw!(out, "{}", describe::rapier_joint(name, &built.world, *h));
    }
    Ok(())
}

/// A second copy of the scene, stepped one frame: its joints hold the blocked stiffness the
/// run resolves at its first substep (from the poses at the start, before anything moved), for
/// [`resolved_stiffness`]. The error of the frame, or of building it again, as text.
fn resolved_copy(
    sc: &scene::Scene,
    src: &scene::Source,
    robot_file: bool,
    frame_dt: f64,
) -> Result<BuiltScene, String> {
    // (built once already: the same files give the same scene)
    let mut copy = match super::build_scene(sc, src, robot_file) {
        Ok(copy) => copy,
        Err(Failure::Input(e) | Failure::Usage(e)) => return Err(e),
        Err(Failure::Output(e)) => return Err(e.to_string()),
    };
    copy.joints.prepare(&mut copy.world);
    copy.joints
        .step(&mut copy.world, frame_dt)
        .map_err(|e| e.to_string())?;
    Ok(copy)
}

/// The blocked stiffness a joint gets for the scene's substep `h` and the stable steps of an
/// explicit update at that stiffness (docs/kjoint2.md §5: "expose both so users can see
/// whether their substep is safe for an explicit update"), from the copy of the scene
/// [`resolved_copy`] stepped: `KX`, `KR`, `dt_trans`, `dt_rot`, and how many substeps of the
/// frame Radioss' explicit update would need (the crate's own update is stable at any).
fn resolved_stiffness(
    built: &BuiltScene,
    resolved: &Result<BuiltScene, String>,
    name: &str,
) -> String {
    let settings = built.joints.settings();
    let h = built.frame_dt / settings.substeps as f64;
    let copy = match resolved {
        Ok(copy) => copy,
        Err(e) => return format!("  blocked stiffness: not resolved (the first frame: {e})\n"),
    };
    let found = copy.joints.find(name).and_then(|jh| {
        let j = copy.joints.get(jh)?;
        Some((j, copy.joints.stable_dt(jh, &copy.world.bodies)))
    });
    let (j, dt) = match found {
        Some((j, dt)) => (j, dt),
        None => return String::new(),
    };
    let Some(k) = j.blocked_stiffness() else {
        return "  blocked stiffness: not resolved (the joint was not stepped: off, or \
                neither body dynamic)\n"
            .to_string();
    };
    let p = j.property();
    let rule = if !p.automatic_stiffness() {
        "from Kn"
    } else {
        match p.automatic {
            rapier_kjoint::law::AutomaticStiffness::Implicit => "automatic, the implicit rule",
            rapier_kjoint::law::AutomaticStiffness::Radioss => "automatic, the Radioss rule",
        }
    };
    let mut s = format!(
        "  blocked stiffness for the substep h = {} s: KX = {} N/m, KR = {} N·m/rad ({rule})\n",
        format_figure(h),
        format_figure(k.translational),
        format_figure(k.rotational)
    );
    if let Some(dt) = dt {
        let least = dt.min();
        let verdict = if !least.is_finite() {
            "no body bounds them".to_string()
        } else if h <= least {
            "the substep is within them".to_string()
        } else {
            format!(
                "the substep is {}× the smaller: Radioss' explicit update would need {} \
                 substeps a frame (this crate's implicit update is stable at any)",
                format_figure(h / least),
                (built.frame_dt / least).ceil()
            )
        };
        // (a step no body bounds: a rotation without inertia, a joint to a fixed body only)
        let step = |t: f64| {
            if t.is_finite() {
                format!("{} s", format_figure(t))
            } else {
                "unbounded".to_string()
            }
        };
        s += &format!(
            "  explicit stable steps (OpenRadioss' estimate): dt_trans = {}, dt_rot = {}: \
             {verdict}\n",
            step(dt.translational),
            step(dt.rotational)
        );
    }
    s
}

/// The loads, motions and motor targets with their time functions.
fn scene_schedules(out: Out, built: &BuiltScene) -> Result<(), Failure> {
    for l in &built.loads {
        say!(
            out,
            "load on `{}`: {} {:?} {} x {:?}",
            l.body_name,
            if l.torque { "torque" } else { "force" },
            l.vector,
            if l.torque { "N·m" } else { "N" },
            l.function
        );
    }
    for m in &built.motions {
        say!(
            out,
            "motion of `{}` (kinematic): {} {:?} {} x {:?}",
            m.body_name,
            match m.kind {
                MotionKind::Displacement { .. } => "displacement",
                MotionKind::Velocity => "velocity",
            },
            m.vector,
            match m.kind {
                MotionKind::Displacement { .. } => "m",
                MotionKind::Velocity => "m/s",
            },
            m.function
        );
    }
    for m in &built.motors {
        say!(
            out,
            "motor target of `{}`: {} {} x {:?}",
            m.joint_name,
            m.target,
            m.unit(),
            m.function
        );
    }
    for s in &built.switches {
        let what = if s.enabled { "on" } else { "off" };
        say!(
            out,
            "joint `{}` switched {what} at {} s",
            s.joint_name,
            s.time
        );
    }
    Ok(())
}

/// A riser deck: its notices and each `*FLEXJOINT` element's law, in SI.
fn check_riser_deck(out: Out, path: &Path) -> Result<(), Failure> {
    let deck = riser::RiserDeck::from_file(path).map_err(|e| e.to_string())?;
    say!(out, "riser deck: {}", path.display());
    for n in &deck.notices {
        say!(out, "  notice, {n}");
    }
    if deck.joints.is_empty() {
        // (laws without a joint that reads them: nothing a scene could use, as a Radioss
        // deck without a KJOINT2 property)
        return Err(format!(
            "{}: no *FLEXJOINT element: expected a riser deck with at least one",
            path.display()
        )
        .into());
    }
    for e in &deck.joints {
        say!(
            out,
            "\n*FLEXJOINT {} (line {}): nodes {} -> {}, IPRO {}, IMAT {}, IPROT {}",
            e.id,
            e.line,
            e.origin_node,
            e.end_node,
            e.ipro,
            e.imat,
            e.iprot
        );
        let law = ConnectorLaw::FlexJoint(FlexJointConnector {
            law: e.law.clone(),
            switch_time: None,
        });
        say_raw!(out, "{}", describe::connector(&law, "  "));
    }
    say!(out, "\nok");
    Ok(())
}

/// Whether a file's bytes are a riser deck: a line starting with `*FLEXJOINT`, `*SPRINGPRO`
/// or `*FLEXPROADD` (Radioss decks use `/` keywords).
fn is_riser_deck(bytes: &[u8]) -> bool {
    String::from_utf8_lossy(bytes).lines().any(|l| {
        let l = l.trim_start().to_ascii_uppercase();
        ["*FLEXJOINT", "*SPRINGPRO", "*FLEXPROADD"]
            .iter()
            .any(|k| l.starts_with(k))
    })
}
