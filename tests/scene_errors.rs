//! Malformed scenes: every error names the file, the line and the field, and is found
//! before anything is simulated. Plus a no-panic property test over arbitrary and mutated
//! scene files (`PROPTEST_CASES=100000 cargo test --release --test scene_errors` runs it
//! longer).

use proptest::prelude::*;
use rapier_kjoint::scene::{self, Format, SceneError, Source};
use std::path::{Path, PathBuf};
use std::process::Command;

const BASE: &str = r#"duration = 0.1

[[bodies]]
name = "ball"
shape = { type = "ball", radius = 0.1 }
mass = 1.0

[[joints]]
name = "j"
body1 = "world"
body2 = "ball"
[joints.property]
type = "revolute"
rx = { stop_min = -0.2, stop_max = 0.3 }
"#;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

mod common;

fn tmp_file(name: &str, text: &str) -> PathBuf {
    common::cli::temp_file("scene-errors", name, text)
}

/// Loads and builds a scene text written to `name`; returns its error.
fn error(name: &str, text: &str) -> SceneError {
    let path = tmp_file(name, text);
    let (sc, src) = match scene::load(&path) {
        Ok(x) => x,
        Err(e) => return e,
    };
    match scene::build(&sc, &src) {
        Ok(_) => panic!("{name}: accepted:\n{text}"),
        Err(e) => e,
    }
}

/// 1-based line of the first line containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("`{needle}` not in the text"))
        + 1
}

fn replaced(a: &str, b: &str) -> String {
    assert!(BASE.contains(a), "{a}");
    BASE.replace(a, b)
}

#[track_caller]
fn check(e: &SceneError, file: &str, line: usize, field: &str, message: &str) {
    assert!(e.file.ends_with(file), "file {}", e.file.display());
    assert_eq!(e.line, line, "line of {e}");
    assert_eq!(e.field, field, "field of {e}");
    assert!(
        e.message.contains(message),
        "message of {e}: expected `{message}`"
    );
    let shown = e.to_string();
    assert!(
        shown.contains(&format!("{file}:{line}: field `{field}`: ")),
        "display: {shown}"
    );
}

#[test]
fn base_scene_is_valid() {
    let path = tmp_file("base.toml", BASE);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    assert_eq!(built.joints.len(), 1);
    assert_eq!(built.bodies.len(), 2, "ball and the world");
}

/// A joint between a body and itself is refused at its `body2`, the line to change (it
/// named the `[[joints]]` header; a mechanism designer's trial, 2026-12-05).
#[test]
fn a_joint_between_a_body_and_itself_names_body2() {
    let t = replaced("body1 = \"world\"", "body1 = \"ball\"");
    let e = error("self_joint.toml", &t);
    check(
        &e,
        "self_joint.toml",
        line_of(&t, "body2 ="),
        "joints[0].body2",
        "body 1 and body 2 are the same body",
    );
}

/// An array with more numbers than its field holds is refused naming the field: TOML's
/// reader took the first three of `gravity = [0, -9.81, 0, 5]` (and the first two of a curve
/// point `[1, 1, 5]`) without a word.
#[test]
fn arrays_longer_than_their_field_are_refused() {
    let t = replaced(
        "duration = 0.1",
        "duration = 0.1\ngravity = [0, -9.81, 0, 5]",
    );
    let e = error("gravity4.toml", &t);
    check(
        &e,
        "gravity4.toml",
        2,
        "gravity",
        "invalid length 4, expected an array of length 3",
    );
    let t = replaced(
        "body2 = \"ball\"",
        "body2 = \"ball\"\nanchor2 = [0, 0.5, 0, 0]",
    );
    let e = error("anchor4.toml", &t);
    check(
        &e,
        "anchor4.toml",
        12,
        "joints[0].anchor2",
        "invalid length 4",
    );
    let t = replaced(
        "rx = { stop_min = -0.2, stop_max = 0.3 }",
        "rx = { stiffness_curve = [[0, 0], [1, 1, 5]] }",
    );
    let e = error("curve3.toml", &t);
    check(
        &e,
        "curve3.toml",
        14,
        "joints[0].property.rx.stiffness_curve",
        "point 2 has 3 numbers: expected [x, y]",
    );
}

#[test]
fn unknown_key_at_the_top() {
    let t = replaced("duration = 0.1", "duration = 0.1\ngravty = [0, 0, 0]");
    let e = error("unknown_top.toml", &t);
    check(
        &e,
        "unknown_top.toml",
        2,
        "gravty",
        "unknown field `gravty`",
    );
}

#[test]
fn unknown_key_in_a_dof_law() {
    let t = replaced("stop_max = 0.3 }", "stop_max = 0.3, stifness = 3.0 }");
    let e = error("unknown_dof.toml", &t);
    check(
        &e,
        "unknown_dof.toml",
        14,
        "joints[0].property.rx.stifness",
        "unknown field `stifness`",
    );
}

#[test]
fn unknown_key_in_a_body_and_a_shape() {
    let t = replaced("mass = 1.0", "mass = 1.0\ncolour = \"red\"");
    let e = error("unknown_body.toml", &t);
    check(
        &e,
        "unknown_body.toml",
        7,
        "bodies[0].colour",
        "unknown field `colour`",
    );
    let t = replaced("radius = 0.1 }", "radius = 0.1, height = 2 }");
    let e = error("unknown_shape.toml", &t);
    assert_eq!(e.line, 5, "{e}");
    assert!(e.message.contains("unknown field `height`"), "{e}");
}

#[test]
fn unknown_joint_type() {
    let t = replaced("type = \"revolute\"", "type = \"hinge\"");
    let e = error("unknown_type.toml", &t);
    check(
        &e,
        "unknown_type.toml",
        13,
        "joints[0].property.type",
        "unknown variant `hinge`",
    );
    assert!(e.message.contains("revolute"), "lists the types: {e}");
}

/// `prismatic`, rapier's name for a joint of one free translation, is the translational
/// type (a vehicle developer wrote it from docs/kjoint2.md's "translational, prismatic" and
/// was refused): its x is free, its rotations blocked.
#[test]
fn prismatic_is_the_translational_type() {
    let t = BASE
        .replace("type = \"revolute\"", "type = \"prismatic\"")
        .replace(
            "rx = { stop_min = -0.2, stop_max = 0.3 }",
            "dx = { stiffness = 10.0 }",
        );
    let path = tmp_file("prismatic.toml", &t);
    let (sc, src) = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let built = scene::build(&sc, &src).unwrap_or_else(|e| panic!("{e}"));
    let (_, j) = built.joints.iter().next().expect("one joint");
    let ty = j.property().joint_type;
    assert_eq!(ty, rapier_kjoint::JointType::Translational);
    assert_eq!(ty.free_dofs(), [true, false, false, false, false, false]);
    assert_eq!(j.property().dof(rapier_kjoint::Dof::Dx).stiffness, 10.0);
}

#[test]
fn unknown_shape_type() {
    let t = replaced("type = \"ball\"", "type = \"cone\"");
    let e = error("unknown_shape_type.toml", &t);
    assert_eq!(e.line, 5, "{e}");
    assert!(e.message.contains("unknown variant `cone`"), "{e}");
}

#[test]
fn number_that_does_not_parse() {
    let t = replaced("mass = 1.0", "mass = 1.0.0");
    let e = error("bad_number.toml", &t);
    assert_eq!(e.line, 6, "{e}");
    assert!(e.to_string().contains("bad_number.toml:6"), "{e}");
    let t = replaced("mass = 1.0", "mass = \"heavy\"");
    let e = error("string_number.toml", &t);
    check(
        &e,
        "string_number.toml",
        6,
        "bodies[0].mass",
        "invalid type: string \"heavy\"",
    );
}

/// Found by fuzzing arm_gripper.toml: `dt = 4294967296` (and any substep of thousands of
/// seconds) was accepted and the run hung in rapier's continuous collision detection
/// (parry's shape cast), `kjoint check` printed NaN positions. A substep `dt / substeps`
/// over 1 s is refused, in the scene at `dt` and for `--substeps`.
#[test]
fn substep_longer_than_a_second() {
    let t = replaced(
        "duration = 0.1",
        "dt = 4294967296\nsubsteps = 4\nduration = 0.1",
    );
    let e = error("long_dt.toml", &t);
    check(
        &e,
        "long_dt.toml",
        1,
        "dt",
        "a substep dt / substeps = 1073741824 s: expected at most 1 s",
    );
    // 2 s frames in 4 substeps are accepted, but not in one (`kjoint run --substeps 1`)
    let t = replaced("duration = 0.1", "dt = 2.0\nsubsteps = 4\nduration = 4.0");
    let path = tmp_file("two_second_frames.toml", &t);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    let mut options = scene::RunOptions::default();
    scene::check_run_options(&built, &options).unwrap();
    options.substeps = Some(1);
    let e = scene::check_run_options(&built, &options).unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid option substeps = 1: expected enough substeps for a substep dt / substeps <= 1 s"
    );
}

#[test]
fn stop_of_the_wrong_sign() {
    let t = replaced("stop_min = -0.2", "stop_min = 0.2");
    let e = error("stop_sign.toml", &t);
    check(
        &e,
        "stop_sign.toml",
        14,
        "joints[0].property.rx.stop_min",
        "expected a value <= 0",
    );
    let t = replaced("stop_max = 0.3", "stop_max = -0.3");
    let e = error("stop_sign2.toml", &t);
    check(
        &e,
        "stop_sign2.toml",
        14,
        "joints[0].property.rx.stop_max",
        "expected a value >= 0",
    );
}

/// A negative spring or viscosity is refused at the door (it was accepted: the run diverged
/// and its error blamed the substep).
#[test]
fn negative_spring_or_viscosity() {
    for (field, text, unit) in [
        (
            "stiffness",
            "rx = { stop_min = -0.2, stop_max = 0.3, stiffness = -1e4 }",
            "N·m/rad",
        ),
        (
            "viscosity",
            "rx = { stop_min = -0.2, stop_max = 0.3, viscosity = -2.0 }",
            "N·m·s/rad",
        ),
    ] {
        let t = replaced("rx = { stop_min = -0.2, stop_max = 0.3 }", text);
        let name = format!("negative_{field}.toml");
        let e = error(&name, &t);
        check(
            &e,
            &name,
            14,
            &format!("joints[0].property.rx.{field}"),
            &format!("expected a value >= 0 [{unit}"),
        );
    }
}

#[test]
fn coupled_stops_unequal() {
    let t = replaced("type = \"revolute\"", "type = \"spherical\"").replace(
        "rx = { stop_min = -0.2, stop_max = 0.3 }",
        "rx = { stop_min = -0.2, stop_max = 0.3, coupled_stops = true }\n\
         ry = { stop_min = -0.1, stop_max = 0.3, coupled_stops = true }",
    );
    let e = error("coupled.toml", &t);
    check(
        &e,
        "coupled.toml",
        15,
        "joints[0].property.ry.stops",
        "the same stops as the coupled DOF rx",
    );
}

#[test]
fn law_on_a_blocked_dof() {
    let t = replaced("rx = {", "ry = { stiffness = 1.0 }\nrx = {");
    let e = error("blocked_law.toml", &t);
    check(
        &e,
        "blocked_law.toml",
        14,
        "joints[0].property.ry",
        "blocked for a revolute joint",
    );
}

#[test]
fn reference_to_a_missing_body() {
    let t = replaced("body2 = \"ball\"", "body2 = \"bal\"");
    let e = error("missing_body.toml", &t);
    check(
        &e,
        "missing_body.toml",
        11,
        "joints[0].body2",
        "no body named `bal`",
    );
    let t = format!("{BASE}\n[[loads]]\nbody = \"rod\"\nforce = [1, 0, 0]\n");
    let e = error("missing_load_body.toml", &t);
    check(
        &e,
        "missing_load_body.toml",
        line_of(&t, "body = \"rod\""),
        "loads[0].body",
        "no body named `rod`",
    );
}

#[test]
fn reference_to_a_missing_deck_or_property() {
    let t = replaced(
        "[joints.property]\ntype = \"revolute\"\nrx = { stop_min = -0.2, stop_max = 0.3 }",
        "property = { deck = \"nothere.rad\", id = 2 }",
    );
    let e = error("missing_deck.toml", &t);
    check(
        &e,
        "missing_deck.toml",
        12,
        "joints[0].property.deck",
        "cannot read the file",
    );
    assert!(e.message.contains("nothere.rad"), "{e}");

    let deck = root().join("assets/decks/revolute_stop.rad");
    let t = replaced(
        "[joints.property]\ntype = \"revolute\"\nrx = { stop_min = -0.2, stop_max = 0.3 }",
        &format!(
            "property = {{ deck = {:?}, id = 3 }}",
            deck.to_str().unwrap()
        ),
    );
    let e = error("missing_prop.toml", &t);
    check(
        &e,
        "missing_prop.toml",
        12,
        "joints[0].property.id",
        "no /PROP/TYPE45 with prop_ID 3",
    );
    assert!(e.message.contains("it has: 2"), "{e}");
}

#[test]
fn error_inside_a_referenced_deck_names_both_files() {
    let deck = tmp_file(
        "bad.rad",
        "/PROP/TYPE45/2\nbad\n         2                 abc\n",
    );
    let t = replaced(
        "[joints.property]\ntype = \"revolute\"\nrx = { stop_min = -0.2, stop_max = 0.3 }",
        &format!(
            "property = {{ deck = {:?}, id = 2 }}",
            deck.to_str().unwrap()
        ),
    );
    let e = error("bad_deck_ref.toml", &t);
    assert_eq!(
        (e.line, e.field.as_str()),
        (12, "joints[0].property.deck"),
        "{e}"
    );
    assert!(e.message.contains("bad.rad:3: field `Kn`"), "{e}");
}

#[test]
fn reference_to_a_missing_sensor_or_joint() {
    let t = replaced("type = \"revolute\"", "type = \"revolute\"\nsensor = 7");
    let e = error("missing_sensor.toml", &t);
    check(
        &e,
        "missing_sensor.toml",
        14,
        "joints[0].property.sensor",
        "no sensor with id 7",
    );
    let t = format!("{BASE}\n[[sensors]]\nid = 1\njoint = \"k\"\ndof = \"rx\"\npasses = 0.1\n");
    let e = error("missing_sensor_joint.toml", &t);
    check(
        &e,
        "missing_sensor_joint.toml",
        line_of(&t, "joint = \"k\""),
        "sensors[0].joint",
        "no joint named `k`",
    );
}

#[test]
fn nan_and_infinity_are_refused() {
    let e = error("nan_mass.toml", &replaced("mass = 1.0", "mass = nan"));
    check(
        &e,
        "nan_mass.toml",
        6,
        "bodies[0].mass",
        "not a finite number",
    );
    let e = error(
        "inf_kn.toml",
        &replaced("type = \"revolute\"", "type = \"revolute\"\nkn = inf"),
    );
    check(
        &e,
        "inf_kn.toml",
        14,
        "joints[0].property.kn",
        "expected a finite number",
    );
    let e = error(
        "nan_gravity.toml",
        &replaced("duration = 0.1", "duration = 0.1\ngravity = [0, nan, 0]"),
    );
    check(
        &e,
        "nan_gravity.toml",
        2,
        "gravity[1]",
        "not a finite number",
    );
    // beyond the range, the value in a few digits (it was printed with its 301 digits)
    let e = error(
        "huge_gravity.toml",
        &replaced("duration = 0.1", "duration = 0.1\ngravity = [0, 1e300, 0]"),
    );
    check(
        &e,
        "huge_gravity.toml",
        2,
        "gravity[1]",
        "1e300 is out of range: expected |value| <= 1e12",
    );
    let e = error(
        "inf_stop.toml",
        &replaced("stop_max = 0.3", "stop_max = -inf"),
    );
    check(
        &e,
        "inf_stop.toml",
        14,
        "joints[0].property.rx.stop_max",
        "finite",
    );
    let e = error(
        "nan_curve.toml",
        &replaced(
            "stop_max = 0.3",
            "stop_max = 0.3, stiffness_curve = [[0, 0], [nan, 1]]",
        ),
    );
    assert_eq!(e.line, 14, "{e}");
    assert!(e.message.contains("not finite"), "{e}");
}

#[test]
fn other_invalid_values() {
    let e = error(
        "both_mass.toml",
        &replaced("mass = 1.0", "mass = 1.0\ndensity = 1000.0"),
    );
    check(&e, "both_mass.toml", 7, "bodies[0].density", "not both");
    let e = error(
        "neg_radius.toml",
        &replaced("radius = 0.1", "radius = -0.1"),
    );
    check(
        &e,
        "neg_radius.toml",
        5,
        "bodies[0].shape.radius",
        "expected a value > 0",
    );
    let e = error(
        "units.toml",
        &replaced(
            "duration = 0.1",
            "units = \"kg furlong ms\"\nduration = 0.1",
        ),
    );
    check(&e, "units.toml", 1, "units", "unknown unit system");
    // the name not understood, with the names its place takes
    assert!(
        e.message
            .contains("the length unit `furlong` is none of m, dm, cm, mm, um, km, in, ft"),
        "{e}"
    );
    let e = error(
        "units_sec.toml",
        &replaced("duration = 0.1", "units = \"kg mm sec\"\nduration = 0.1"),
    );
    assert!(
        e.message
            .contains("the time unit `sec` is none of s, ms, us, ns, min, h"),
        "{e}"
    );
    let e = error(
        "dup.toml",
        &format!(
            "{BASE}\n[[bodies]]\nname = \"ball\"\nshape = {{ type = \"ball\", radius = 1 }}\n"
        ),
    );
    assert!(e.message.contains("duplicate body name `ball`"), "{e}");
    let e = error(
        "cr.toml",
        &replaced(
            "type = \"revolute\"",
            "type = \"revolute\"\ncritical_damping = 2",
        ),
    );
    check(
        &e,
        "cr.toml",
        14,
        "joints[0].property.critical_damping",
        "[0, 1]",
    );
    let e = error(
        "rot.toml",
        &replaced("mass = 1.0", "mass = 1.0\nrotation = { axis = [0, 0, 1] }"),
    );
    check(
        &e,
        "rot.toml",
        7,
        "bodies[0].rotation",
        "`axis` and `angle`",
    );
    let e = error("load.toml", &format!("{BASE}\n[[loads]]\nbody = \"ball\"\nforce = [1, 0, 0]\nfunction = {{ curve = [[0, 0], [0, 1]] }}\n"));
    assert_eq!(e.field, "loads[0].function.curve[1]", "{e}");
    let e = error("scene.yaml", BASE);
    assert!(e.message.contains("`.toml` or `.json`"), "{e}");
}

/// `units = ""` (or blank) was read as SI without a word: a unit system left empty by
/// mistake (a template's placeholder) is refused, naming the field and what it takes.
#[test]
fn an_empty_unit_system_is_refused() {
    for blank in ["", "   "] {
        let t = replaced(
            "duration = 0.1",
            &format!("units = \"{blank}\"\nduration = 0.1"),
        );
        let e = error("units_blank.toml", &t);
        check(
            &e,
            "units_blank.toml",
            1,
            "units",
            "an empty unit system: expected \"SI\" or three unit names \"mass length time\"",
        );
    }
    let json = "{\n  \"units\": \"\",\n  \"duration\": 0.1\n}\n";
    let e = error("units_blank.json", json);
    assert_eq!(e.field, "units", "{e}");
    assert!(e.message.contains("an empty unit system"), "{e}");
    // SI as written, or left out, is SI
    for units in ["units = \"SI\"\n", "units = \"si\"\n", ""] {
        let t = format!("{units}{BASE}");
        let path = tmp_file("units_si.toml", &t);
        let (sc, src) = scene::load(&path).unwrap();
        let built = scene::build(&sc, &src).unwrap();
        assert_eq!(
            built.units,
            rapier_kjoint::io::units::UnitSystem::SI,
            "{units}"
        );
    }
    assert!(scene::build::parse_units("").is_none());
}

/// Sensor ids are Radioss `sens_ID`s: positive, 0 being "no sensor" in a property's
/// `sensor` (as in a deck's `/PROP/TYPE45`, and as the README says of scenes). `[[sensors]]
/// id = 0` was accepted and a property's `sensor = 0` looked for it (and locked on it):
/// the id is refused, the property's 0 is no sensor.
#[test]
fn sensor_id_0_is_refused_and_a_property_sensor_0_is_none() {
    let t = format!("{BASE}\n[[sensors]]\nid = 0\ntime = 0.05\n");
    let e = error("sensor_0.toml", &t);
    check(
        &e,
        "sensor_0.toml",
        line_of(&t, "id = 0"),
        "sensors[0].id",
        "0: expected a sensor id >= 1",
    );
    // a property's `sensor = 0`: no sensor (no `[[sensors]]` needed, nothing locks)
    let t = replaced("type = \"revolute\"", "type = \"revolute\"\nsensor = 0");
    let path = tmp_file("property_sensor_0.toml", &t);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    let (_, j) = built.joints.iter().next().unwrap();
    assert_eq!(j.property().sensor, None);
    // and a sensor 1 is what it names
    let t = replaced("type = \"revolute\"", "type = \"revolute\"\nsensor = 1")
        + "\n[[sensors]]\nid = 1\ntime = 0.05\n";
    let path = tmp_file("property_sensor_1.toml", &t);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    let (_, j) = built.joints.iter().next().unwrap();
    assert_eq!(j.property().sensor, Some(1));
}

/// A robot override's whole `property` naming a sensor: the scene checks that the sensor
/// exists before anything runs, at the override's line (it failed at the first substep,
/// without the scene's line or field), and its `sensor = 0` is no sensor as in a scene
/// property.
#[test]
fn a_robot_property_override_names_an_existing_sensor_or_none() {
    let urdf = root().join("assets/urdf/arm.urdf");
    let robot = |sensor: &str, extra: &str| {
        format!(
            "duration = 0.1\n\n[[robots]]\nurdf = {:?}\n[robots.options.joints.elbow.property]\n\
             type = \"revolute\"\n{sensor}\n{extra}",
            urdf.display().to_string()
        )
    };
    let t = robot("sensor = 5", "");
    let e = error("robot_sensor_5.toml", &t);
    check(
        &e,
        "robot_sensor_5.toml",
        line_of(&t, "sensor = 5"),
        "robots[0].options.joints.elbow.property.sensor",
        "no sensor with id 5 (sensors: none)",
    );
    let build = |name: &str, t: &str| {
        let path = tmp_file(name, t);
        let (sc, src) = scene::load(&path).unwrap();
        scene::build(&sc, &src).unwrap()
    };
    let sensor_of = |built: &scene::BuiltScene| {
        let (_, j) = built
            .joints
            .iter()
            .find(|(_, j)| j.name == "elbow")
            .unwrap();
        j.property().sensor
    };
    let built = build(
        "robot_sensor_5_ok.toml",
        &robot("sensor = 5", "\n[[sensors]]\nid = 5\ntime = 0.05\n"),
    );
    assert_eq!(sensor_of(&built), Some(5));
    let built = build("robot_sensor_0.toml", &robot("sensor = 0", ""));
    assert_eq!(sensor_of(&built), None);
}

#[test]
fn json_errors_give_the_line() {
    let json = "{\n  \"duration\": 0.1,\n  \"bodies\": [],\n  \"gravty\": [0, 0, 0]\n}\n";
    let e = error("bad.json", json);
    assert_eq!(e.line, 4, "{e}");
    assert!(e.message.contains("unknown field `gravty`"), "{e}");
    assert!(
        e.to_string()
            .starts_with(&format!("{}:4: ", e.file.display())),
        "{e}"
    );
}

/// A JSON scene's errors name the field and its line as a TOML scene's do: those of the
/// parser (a string in an array of numbers, a curve point, an unknown key, a missing one)
/// gave the line without the field, those of the checks the field without the line.
#[test]
fn json_errors_name_the_field_and_its_line_as_toml_ones_do() {
    let body = r#"{"name": "b", "shape": {"type": "ball", "radius": 0.1}, "mass": 1.0}"#;
    let scene = |gravity: &str, bodies: &str, loads: &str| {
        format!(
            "{{\n  \"duration\": 0.1,\n  \"gravity\": {gravity},\n  \"bodies\": [\n    \
             {bodies}\n  ],\n  \"loads\": [\n    {{\"body\": \"b\", \"force\": [1, 0, 0],\n     \
             \"function\": {loads}}}\n  ]\n}}\n"
        )
    };
    let ok_load = r#"{"curve": [[0, 1], [1, 2]]}"#;
    let cases = [
        // the parser's
        (
            scene("[0, \"a\", 0]", body, ok_load),
            3,
            "gravity[1]",
            "invalid type: string \"a\", expected f64",
        ),
        (
            scene("[0, 0, -9.81]", body, r#"{"curve": [[0, 1], [1, "x"]]}"#),
            9,
            "loads[0].function.curve[1][1]",
            "invalid type: string \"x\", expected f64",
        ),
        (
            scene(
                "[0, 0, -9.81]",
                &body.replace("\"mass\"", "\"mas\""),
                ok_load,
            ),
            5,
            "bodies[0].mas",
            "unknown field `mas`",
        ),
        (
            scene(
                "[0, 0, -9.81]",
                &body.replace("\"ball\"", "\"blob\""),
                ok_load,
            ),
            5,
            "bodies[0].shape.type",
            "unknown variant `blob`",
        ),
        (
            scene("[0, 0]", body, ok_load),
            3,
            "gravity",
            "invalid length 2",
        ),
        // the checks'
        (
            scene("[0, 0, 1e300]", body, ok_load),
            3,
            "gravity[2]",
            "out of range",
        ),
        (
            scene("[0, 0, -9.81]", &body.replace("0.1}", "-0.1}"), ok_load),
            5,
            "bodies[0].shape.radius",
            "expected a value > 0",
        ),
        (
            scene("[0, 0, -9.81]", body, r#"{"curve": [[0, 1], [0, 2]]}"#),
            9,
            "loads[0].function.curve[1]",
            "",
        ),
    ];
    for (text, line, field, message) in cases {
        let e = error("json_field.json", &text);
        check(&e, "json_field.json", line, field, message);
        // the same scene in TOML names the same field
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        let toml_text = toml::to_string(&value).unwrap();
        let t = error("json_field.toml", &toml_text);
        assert_eq!(t.field, field, "{t}\n{toml_text}");
    }
    // a missing key: the object that misses it
    let text = "{\n  \"duration\": 0.1,\n  \"bodies\": [\n    {\"name\": \"b\"}\n  ]\n}\n";
    let e = error("missing.json", text);
    check(&e, "missing.json", 4, "bodies[0]", "missing field `shape`");
}

#[test]
fn the_command_reports_errors_with_a_non_zero_exit() {
    let path = tmp_file(
        "cli_bad.toml",
        &replaced("stop_min = -0.2", "stop_min = 0.2"),
    );
    for cmd in ["check", "run"] {
        let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
            .arg(cmd)
            .arg(&path)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{cmd}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("cli_bad.toml:14: field `joints[0].property.rx.stop_min`"),
            "{cmd}: {err}"
        );
        assert!(
            out.stdout.is_empty() || !String::from_utf8_lossy(&out.stdout).contains("simulated")
        );
    }
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .args(["run", "/nonexistent/x.toml"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent/x.toml: cannot read"));
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .args(["frobnicate"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "usage error");
}

// ---------------------------------------------------------------------------------------
// No panic on any input
// ---------------------------------------------------------------------------------------

fn seeds() -> Vec<(PathBuf, String)> {
    let dir = root().join("assets/scenes");
    let mut v: Vec<(PathBuf, String)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| {
            let t = std::fs::read_to_string(&p).unwrap();
            (p, t)
        })
        .collect();
    v.sort();
    v.push((dir.join("base.toml"), BASE.to_string()));
    v
}

/// Parses and builds; never simulates. Must not panic.
fn no_panic(file: &Path, text: &str, format: Format) {
    let src = Source {
        file: file.to_path_buf(),
        text: text.to_string(),
        format,
    };
    if let Ok(sc) = scene::parse(&src) {
        let _ = scene::build(&sc, &src);
    }
}

#[derive(Debug, Clone)]
enum Edit {
    /// Replaces the n-th number of the text.
    Number(usize, String),
    /// Deletes a line.
    DeleteLine(usize),
    /// Inserts text at a character position.
    Insert(usize, String),
    /// Replaces a quoted word.
    Word(usize, String),
}

fn edit() -> impl Strategy<Value = Edit> {
    let number = prop_oneof![
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("1e308".to_string()),
        Just("1e-320".to_string()),
        Just("1e13".to_string()),
        Just("\"x\"".to_string()),
        Just("[]".to_string()),
        any::<f64>().prop_map(|f| format!("{f:?}")),
        any::<i64>().prop_map(|i| i.to_string()),
    ];
    let word = prop_oneof![
        Just("\"world\"".to_string()),
        Just("\"\"".to_string()),
        Just("\"fixed\"".to_string()),
        Just("\"rx\"".to_string()),
        "\"[a-z]{0,8}\"",
    ];
    prop_oneof![
        (0usize..200, number).prop_map(|(n, s)| Edit::Number(n, s)),
        (0usize..60).prop_map(Edit::DeleteLine),
        (0usize..3000, "(?s).{0,12}").prop_map(|(p, s)| Edit::Insert(p, s)),
        (0usize..40, word).prop_map(|(n, s)| Edit::Word(n, s)),
    ]
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut t = text.to_string();
    for e in edits {
        match e {
            Edit::Number(n, s) => {
                let re: Vec<(usize, usize)> = number_spans(&t);
                if !re.is_empty() {
                    let (a, b) = re[n % re.len()];
                    t.replace_range(a..b, s);
                }
            }
            Edit::DeleteLine(n) => {
                let mut lines: Vec<&str> = t.lines().collect();
                if !lines.is_empty() {
                    let i = n % lines.len();
                    lines.remove(i);
                }
                t = lines.join("\n");
            }
            Edit::Insert(p, s) => {
                let mut p = (*p).min(t.len());
                while !t.is_char_boundary(p) {
                    p -= 1;
                }
                t.insert_str(p, s);
            }
            Edit::Word(n, s) => {
                let quotes: Vec<usize> = t.match_indices('"').map(|(i, _)| i).collect();
                if quotes.len() >= 2 {
                    let k = (n % (quotes.len() / 2)) * 2;
                    t.replace_range(quotes[k]..=quotes[k + 1], s);
                }
            }
        }
    }
    t
}

/// Byte spans of the numbers (digits, signs, dots, exponents) of a text.
fn number_spans(t: &str) -> Vec<(usize, usize)> {
    let b = t.as_bytes();
    let mut v = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() {
            let mut s = i;
            if s > 0 && b[s - 1] == b'-' {
                s -= 1;
            }
            let mut e = i;
            while e < b.len() && (b[e].is_ascii_alphanumeric() || b"+-.".contains(&b[e])) {
                e += 1;
            }
            v.push((s, e));
            i = e;
        } else {
            i += 1;
        }
    }
    v
}

proptest! {
    #[test]
    fn no_panic_on_arbitrary_text(text in any::<String>(), toml_like in "(?s)[a-z_=\\[\\]{}\",. 0-9\n-]{0,300}") {
        for t in [&text, &toml_like] {
            no_panic(Path::new("arbitrary.toml"), t, Format::Toml);
            no_panic(Path::new("arbitrary.json"), t, Format::Json);
        }
    }

    #[test]
    fn no_panic_on_mutated_scenes(seed in 0usize..64, edits in proptest::collection::vec(edit(), 1..5)) {
        let seeds = seeds();
        let (file, text) = &seeds[seed % seeds.len()];
        let t = apply(text, &edits);
        no_panic(file, &t, Format::Toml);
        // The same scene as JSON, mutated the same way.
        if let Ok(sc) = scene::parse(&Source { file: file.clone(), text: text.clone(), format: Format::Toml }) {
            let json = serde_json::to_string_pretty(&sc).unwrap();
            no_panic(&file.with_extension("json"), &apply(&json, &edits), Format::Json);
        }
    }
}

/// The TOML example of the README is a valid scene.
#[test]
fn readme_example_is_a_valid_scene() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let section = readme
        .split("## Scenes and the `kjoint` command")
        .nth(1)
        .unwrap();
    let block = section
        .split("```toml\n")
        .nth(1)
        .unwrap()
        .split("```")
        .next()
        .unwrap();
    // the URDF path is relative to assets/scenes/
    let urdf = root().join("assets/urdf/arm.urdf");
    let block = block.replace(
        "\"../urdf/arm.urdf\"",
        &format!("{:?}", urdf.display().to_string()),
    );
    // a body touches nothing unless `collide = true`: a ground written from the example
    // without it let a floating-base robot fall through it, silently
    assert!(
        block.contains("\ncollide = "),
        "the example shows `collide`"
    );
    let path = tmp_file("readme.toml", &block);
    let (sc, src) = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let built = scene::build(&sc, &src).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        built.joints.len(),
        1 + 2,
        "the hinge and the arm's shoulder and elbow"
    );
    let rapier: Vec<&str> = built
        .rapier_joints
        .iter()
        .map(|(n, _)| n.as_str())
        .collect();
    // the robot is named `left`: its parts are `left/...` for the scene
    assert_eq!(rapier, ["left/wrist"]);
    assert!(built.bodies.iter().any(|(n, _)| n == "left/forearm"));
    assert_eq!(built.loads.len(), 1);
    assert_eq!((built.motions.len(), built.motors.len()), (1, 1));
    assert_eq!(
        built
            .world
            .integration_parameters
            .num_internal_pgs_iterations,
        4
    );
    assert!(built.csv.unwrap().ends_with("out"));
}

// ---- connector laws (planar friction, flex joint) ----

/// A planar joint with planar friction, and a spherical one with an inline flex joint.
const CONNECTORS: &str = r#"duration = 0.1

[[bodies]]
name = "block"
shape = { type = "cuboid", half_extents = [0.1, 0.1, 0.1] }
mass = 1.0

[[bodies]]
name = "riser"
shape = { type = "cylinder", half_height = 1.0, radius = 0.1 }
mass = 10.0

[[joints]]
name = "slide"
body1 = "world"
body2 = "block"
property = { type = "planar" }
planar_friction = { mu = 0.3, radius = 0.05 }

[[joints]]
name = "flex"
body1 = "world"
body2 = "riser"
property = { type = "spherical" }
[joints.flex_joint]
switch_time = 1.0
bending = [[0.0, 0.0], [0.01, 2000.0], [0.02, 3000.0]]
dynamic = { torsion_stiffness = 1e5, kdyn_ini = 4e5, kdyn_lim = 2e5, angle_lim = 1e-3 }
"#;

fn connectors(a: &str, b: &str) -> String {
    assert!(CONNECTORS.contains(a), "{a}");
    CONNECTORS.replace(a, b)
}

#[test]
fn connector_scene_is_valid_and_in_si() {
    let path = tmp_file("connectors.toml", CONNECTORS);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    let laws: Vec<_> = built
        .joints
        .iter()
        .map(|(_, j)| j.connector_law().clone())
        .collect();
    let rapier_kjoint::law::ConnectorLaw::PlanarFriction(p) = &laws[0] else {
        panic!("{laws:?}")
    };
    assert_eq!((p.mu, p.radius), (0.3, 0.05));
    let rapier_kjoint::law::ConnectorLaw::FlexJoint(f) = &laws[1] else {
        panic!("{laws:?}")
    };
    assert_eq!(f.switch_time, Some(1.0));
    assert_eq!(f.law.dynamic.unwrap().kdyn_ini, 4e5);
    // The same scene in kg, mm, ms: lengths ×1e-3, moments (kN·mm = N·m) ×1, times ×1e-3.
    let t = connectors("duration = 0.1", "units = \"kg mm ms\"\nduration = 100")
        .replace("radius = 0.05 }", "radius = 50.0 }")
        .replace("switch_time = 1.0", "switch_time = 1000.0")
        .replace(
            "half_extents = [0.1, 0.1, 0.1]",
            "half_extents = [100, 100, 100]",
        )
        .replace(
            "half_height = 1.0, radius = 0.1",
            "half_height = 1000, radius = 100",
        );
    let path = tmp_file("connectors_mm.toml", &t);
    let (sc, src) = scene::load(&path).unwrap();
    let built_mm = scene::build(&sc, &src).unwrap();
    let laws_mm: Vec<_> = built_mm
        .joints
        .iter()
        .map(|(_, j)| j.connector_law().clone())
        .collect();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
    let rapier_kjoint::law::ConnectorLaw::PlanarFriction(q) = &laws_mm[0] else {
        panic!("{laws_mm:?}")
    };
    assert!(close(q.radius, p.radius) && q.mu == p.mu, "{q:?}");
    let rapier_kjoint::law::ConnectorLaw::FlexJoint(g) = &laws_mm[1] else {
        panic!("{laws_mm:?}")
    };
    assert!(close(g.switch_time.unwrap(), 1.0));
    assert_eq!(
        g.law, f.law,
        "moments in kN·mm = N·m and angles in rad are unchanged"
    );
}

#[test]
fn planar_friction_on_a_wrong_joint_type_names_the_field() {
    let t = connectors(
        "property = { type = \"planar\" }",
        "property = { type = \"revolute\" }",
    );
    let e = error("pf_type.toml", &t);
    check(
        &e,
        "pf_type.toml",
        line_of(&t, "planar_friction ="),
        "joints[0].planar_friction",
        "the planar friction law needs a planar joint (type 4), not a revolute joint (type 2)",
    );
}

#[test]
fn planar_friction_values_are_checked() {
    let t = connectors("mu = 0.3", "mu = -0.3");
    let e = error("pf_mu.toml", &t);
    check(
        &e,
        "pf_mu.toml",
        line_of(&t, "planar_friction ="),
        "joints[0].planar_friction.mu",
        "invalid mu = -0.3: expected a value >= 0",
    );
    let t = connectors("radius = 0.05 }", "radius = 0.05, stick_stiffnes = 1e4 }");
    let e = error("pf_unknown.toml", &t);
    assert_eq!(e.line, line_of(&t, "planar_friction ="), "{e}");
    assert!(e.message.contains("unknown field `stick_stiffnes`"), "{e}");
    let t = connectors("mu = 0.3, radius = 0.05", "radius = 0.05");
    let e = error("pf_no_mu.toml", &t);
    assert!(e.message.contains("missing field `mu`"), "{e}");
}

#[test]
fn flex_joint_errors_name_the_field() {
    // on a planar joint
    let t = connectors(
        "property = { type = \"spherical\" }",
        "property = { type = \"planar\" }",
    );
    let e = error("fj_type.toml", &t);
    check(
        &e,
        "fj_type.toml",
        line_of(&t, "[joints.flex_joint]"),
        "joints[1].flex_joint",
        "needs a spherical joint (type 1)",
    );
    // Kdyn_lim above Kdyn_ini
    let t = connectors("kdyn_lim = 2e5", "kdyn_lim = 5e5");
    let e = error("fj_kdyn.toml", &t);
    check(
        &e,
        "fj_kdyn.toml",
        line_of(&t, "dynamic = {"),
        "joints[1].flex_joint.dynamic.kdyn_lim",
        "invalid dynamic.kdyn_lim = 500000: expected a stiffness in [0, Kdyn_ini = 400000]",
    );
    // a law not through the origin
    let t = connectors(
        "[[0.0, 0.0], [0.01, 2000.0]",
        "[[0.0, 10.0], [0.01, 2000.0]",
    );
    let e = error("fj_origin.toml", &t);
    check(
        &e,
        "fj_origin.toml",
        line_of(&t, "bending ="),
        "joints[1].flex_joint.bending",
        "a moment-angle law passing through (0, 0)",
    );
    // ... the message in the scene's words, and where the law starts when it is not at
    // angle 0 (it gave `M(0) = -1111.1` alone, the first segment extended: a riser
    // engineer's trial, 2026-12-04)
    assert!(
        e.message
            .starts_with("invalid bending = M(0) = 10: expected"),
        "{e}"
    );
    let t = connectors(
        "[[0.0, 0.0], [0.01, 2000.0]",
        "[[0.001, 0.0], [0.01, 2000.0]",
    );
    let e = error("fj_start.toml", &t);
    assert!(
        e.message
            .contains("the law starts at (0.001, 0); its first segment extended to angle 0"),
        "{e}"
    );
    // neither a bending nor a dynamic law: the scene's keys, not the deck's IPRO and IMAT
    let t = connectors(
        "bending = [[0.0, 0.0], [0.01, 2000.0], [0.02, 3000.0]]\ndynamic = { torsion_stiffness = 1e5, kdyn_ini = 4e5, kdyn_lim = 2e5, angle_lim = 1e-3 }\n",
        "torsion = [[0.0, 0.0], [0.01, 2000.0]]\n",
    );
    let t = t.replace("switch_time = 1.0\n", "");
    let e = error("fj_none.toml", &t);
    assert!(
        e.message
            .contains("a flex joint needs a `bending` law or a `dynamic` law"),
        "{e}"
    );
    assert!(
        !e.message.contains("IPRO") && !e.message.contains("IMAT"),
        "{e}"
    );
    // angles not increasing
    let t = connectors("[0.02, 3000.0]", "[0.005, 3000.0]");
    let e = error("fj_curve.toml", &t);
    check(
        &e,
        "fj_curve.toml",
        line_of(&t, "bending ="),
        "joints[1].flex_joint.bending",
        "x must increase strictly",
    );
    // a switch time without the dynamic law
    let t = connectors(
        "dynamic = { torsion_stiffness = 1e5, kdyn_ini = 4e5, kdyn_lim = 2e5, angle_lim = 1e-3 }\n",
        "",
    );
    let e = error("fj_switch.toml", &t);
    check(
        &e,
        "fj_switch.toml",
        line_of(&t, "switch_time"),
        "joints[1].flex_joint.switch_time",
        "needs the dynamic law",
    );
    // both laws on one joint
    let t = connectors(
        "property = { type = \"spherical\" }",
        "property = { type = \"spherical\" }\nplanar_friction = { mu = 0.1 }",
    );
    let e = error("fj_both.toml", &t);
    assert!(e.message.contains("one connector law"), "{e}");
}

#[test]
fn flex_joint_deck_references_are_checked() {
    let deck = root().join("assets/decks/flexjoint_example2.dat");
    let inline = "switch_time = 1.0\nbending = [[0.0, 0.0], [0.01, 2000.0], [0.02, 3000.0]]\n\
        dynamic = { torsion_stiffness = 1e5, kdyn_ini = 4e5, kdyn_lim = 2e5, angle_lim = 1e-3 }\n";
    let with = |s: &str| connectors(inline, s);
    // a valid reference: element 3 of the deck, IPRO 3 and IMAT 2
    let t = with(&format!(
        "deck = {:?}\nelement = 3\nswitch_time = 2.0\n",
        deck
    ));
    let path = tmp_file("fj_deck.toml", &t);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    let (_, j) = built.joints.iter().nth(1).unwrap();
    let rapier_kjoint::law::ConnectorLaw::FlexJoint(f) = j.connector_law() else {
        panic!()
    };
    assert_eq!(f.switch_time, Some(2.0));
    let d = f.law.dynamic.unwrap();
    assert_eq!(
        (d.kdyn_ini, d.kdyn_lim, d.angle_lim),
        (4.0107e6, 1.718873e6, 1.74533e-3)
    );
    // an unknown element
    let t = with(&format!("deck = {:?}\nelement = 7\n", deck));
    let e = error("fj_nel.toml", &t);
    check(
        &e,
        "fj_nel.toml",
        line_of(&t, "element = 7"),
        "joints[1].flex_joint.element",
        "no *FLEXJOINT element 7",
    );
    // a missing deck file
    let t = with("deck = \"nowhere.dat\"\nelement = 3\n");
    let e = error("fj_nodeck.toml", &t);
    assert_eq!(e.field, "joints[1].flex_joint.deck", "{e}");
    assert!(e.message.contains("nowhere.dat"), "{e}");
    // a broken deck: the deck's own line is named
    let bad = tmp_file(
        "bad_riser.dat",
        "*SPRINGPRO\n3 3 0 0 0.01 25000\n*FLEXJOINT\n3 1 3 3 0 0.\n",
    );
    let t = with(&format!("deck = {:?}\nelement = 3\n", bad));
    let e = error("fj_baddeck.toml", &t);
    assert_eq!(e.field, "joints[1].flex_joint.deck", "{e}");
    assert!(e.message.contains("bad_riser.dat:2:"), "{e}");
    // inline fields with a reference
    let t = with(&format!(
        "deck = {:?}\nelement = 3\nbending = [[0.0, 0.0], [0.01, 1.0]]\n",
        deck
    ));
    let e = error("fj_mixed.toml", &t);
    assert!(e.message.contains("takes no inline"), "{e}");
}

#[test]
fn sine_start_is_checked() {
    let t = format!(
        "{BASE}\n[[loads]]\nbody = \"ball\"\nforce = [1, 0, 0]\nfunction = {{ sine = {{ amplitude = 1, frequency = 1, start = -1 }} }}\n"
    );
    let e = error("sine_start.toml", &t);
    check(
        &e,
        "sine_start.toml",
        line_of(&t, "start = -1"),
        "loads[0].function.sine.start",
        "-1: expected >= 0",
    );
}

#[test]
fn robot_errors_name_the_field() {
    let urdf = root().join("assets/urdf/arm.urdf");
    let robot = |extra: &str| {
        format!(
            "duration = 0.1\n\n[[robots]]\nurdf = {:?}\n{extra}",
            urdf.display().to_string()
        )
    };
    // a valid robot with a robot-wide Kn: its links are bodies, its joints can be watched by
    // sensors
    let t = robot("options = { kn = 2e6 }\n")
        + "\n[[sensors]]\nid = 1\njoint = \"elbow\"\ndof = \"rx\"\npasses = 0.1\n";
    let path = tmp_file("robot_ok.toml", &t);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    assert_eq!(built.joints.len(), 3);
    assert!(built.joints.iter().all(|(_, j)| j.property().kn == 2e6));
    assert!(built.bodies.iter().any(|(n, _)| n == "forearm"));
    // a missing file
    let t = "duration = 0.1\n\n[[robots]]\nurdf = \"nowhere.urdf\"\n";
    let e = error("robot_missing.toml", t);
    check(
        &e,
        "robot_missing.toml",
        4,
        "robots[0].urdf",
        "nowhere.urdf",
    );
    // an unknown option
    let t = robot("[robots.options]\nkn = 1e6\nstifness = 3\n");
    let e = error("robot_option.toml", &t);
    assert_eq!(e.line, line_of(&t, "stifness"), "{e}");
    assert!(e.message.contains("unknown field `stifness`"), "{e}");
    // an override of a joint the robot does not have: at the override's own line (the
    // `urdf` key's before)
    let t = robot("[robots.options.joints.knee]\nfriction = 1.0\n");
    let e = error("robot_override.toml", &t);
    assert_eq!(e.field, "robots[0].options.joints.knee", "{e}");
    assert_eq!(e.line, line_of(&t, "[robots.options.joints.knee]"), "{e}");
    assert!(e.message.contains("knee"), "{e}");
    // not SI
    let t = robot("").replace("duration = 0.1", "units = \"kg mm ms\"\nduration = 100");
    let e = error("robot_units.toml", &t);
    check(
        &e,
        "robot_units.toml",
        line_of(&t, "[[robots]]"),
        "robots[0]",
        "need an SI scene",
    );
    // a body named like a link
    let t =
        robot("") + "\n[[bodies]]\nname = \"hand\"\nshape = { type = \"ball\", radius = 0.1 }\n";
    let e = error("robot_name.toml", &t);
    assert!(e.message.contains("link `hand`"), "{e}");
}

/// Every numeric robot override is held to ±1e12, as the same URDF attributes are
/// (`<dynamics friction>` beyond it is refused): `friction = 1e308` was accepted and ran.
/// The error names the scene's line and the override's field.
#[test]
fn robot_overrides_beyond_1e12_are_refused_naming_the_field() {
    let urdf = root().join("assets/urdf/arm.urdf");
    let robot = |table: &str, line: &str| {
        format!(
            "duration = 0.1\n\n[[robots]]\nurdf = {:?}\n[robots.options.joints.elbow]\n{table}\n\
             {line}\n",
            urdf.display().to_string()
        )
    };
    let cases = [
        ("", "kn = 1e308", "kn"),
        ("", "critical_damping = 1e13", "critical_damping"),
        ("", "stiffness = 1e308", "stiffness"),
        ("", "viscosity = 1e308", "viscosity"),
        ("", "friction = 1e308", "friction"),
        ("", "friction_stiffness = 1e308", "friction_stiffness"),
        ("", "stop_min = -1e308", "stop_min"),
        ("", "stop_max = 1e308", "stop_max"),
        ("", "break = { force = 1e308 }", "break.force"),
        (
            "",
            "joint_friction = { mu = 0.1, pin_radius = 0.01, stick_stiffness = 1e300 }",
            "joint_friction.stick_stiffness",
        ),
        (
            "[robots.options.joints.elbow.property]",
            "type = \"revolute\"\nkn = 1e308",
            "property.kn",
        ),
        (
            "[robots.options.joints.elbow.property]",
            "type = \"revolute\"\nscale_factor = 1e300",
            "property.scale_factor",
        ),
    ];
    for (table, line, field) in cases {
        let t = robot(table, line);
        let e = error("override_huge.toml", &t);
        let written = line.lines().last().unwrap();
        check(
            &e,
            "override_huge.toml",
            line_of(&t, written),
            &format!("robots[0].options.joints.elbow.{field}"),
            "expected a finite number within ±1e12",
        );
        assert!(e.message.contains("arm.urdf"), "{e}");
    }
    // a whole property's DOF law and curve points, by index
    let t = robot(
        "[robots.options.joints.elbow.property]",
        "type = \"revolute\"\ndofs = [{}, {}, {}, { stiffness = 1e300 }, {}, {}]",
    );
    let e = error("override_dof.toml", &t);
    check(
        &e,
        "override_dof.toml",
        line_of(&t, "dofs = "),
        "robots[0].options.joints.elbow.property.dofs[3].stiffness",
        "invalid property.dofs[3].stiffness = 1e300: expected a finite number within ±1e12",
    );
    let t = robot(
        "[robots.options.joints.elbow.property]",
        "type = \"revolute\"\ndofs = [{}, {}, {}, { friction_stiffness = 10, friction_curve = \
         [[0, 0], [1, 1e300]] }, {}, {}]",
    );
    let e = error("override_curve.toml", &t);
    assert_eq!(
        e.field, "robots[0].options.joints.elbow.property.dofs[3].friction_curve",
        "{e}"
    );
    assert!(e.message.contains("1e300"), "{e}");
    // at the bound the value is taken as given
    let t = robot("", "friction = 1e12");
    let path = tmp_file("override_bound.toml", &t);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    let elbow = built
        .joints
        .iter()
        .find(|(_, j)| j.name == "elbow")
        .unwrap()
        .1;
    assert_eq!(elbow.property().dofs[3].friction, 1e12);
    // the same for an MJCF robot
    let mjcf = root().join("assets/mjcf/pendulum.xml");
    let t = format!(
        "duration = 0.1\n\n[[robots]]\nmjcf = {:?}\n[robots.options.joints.elbow]\nviscosity = \
         -1e300\n",
        mjcf.display().to_string()
    );
    let e = error("override_mjcf.toml", &t);
    check(
        &e,
        "override_mjcf.toml",
        line_of(&t, "viscosity"),
        "robots[0].options.joints.elbow.viscosity",
        "invalid viscosity = -1e300: expected a finite number within ±1e12",
    );
}

#[test]
fn mjcf_robots_load_in_scenes_beside_urdf_ones() {
    let mjcf = root().join("assets/mjcf/pendulum.xml");
    let t = format!(
        "duration = 0.1\n\n[[robots]]\nmjcf = {:?}\noptions = {{ kn = 2e6 }}\n\n[[sensors]]\nid = 1\njoint = \"elbow\"\ndof = \"rx\"\npasses = 0.1\n",
        mjcf.display().to_string()
    );
    let path = tmp_file("mjcf_ok.toml", &t);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    assert_eq!(
        built.joints.len(),
        2,
        "shoulder and elbow (base is fixed on the world)"
    );
    assert!(built.joints.iter().all(|(_, j)| j.property().kn == 2e6));
    assert!(built.bodies.iter().any(|(n, _)| n == "lower"));
    // the joints come from an MJCF file, and `kjoint check` says so (it said "URDF")
    assert!(
        built
            .origins
            .iter()
            .all(|o| *o == scene::build::PropertyOrigin::Mjcf { file: mjcf.clone() }),
        "{:?}",
        built.origins
    );
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .args(["check".as_ref(), path.as_os_str()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains(&format!("joint `elbow` (MJCF {})", mjcf.display())),
        "{text}"
    );
    assert!(!text.contains("(URDF "), "{text}");
    // both files, or neither
    let urdf = root().join("assets/urdf/arm.urdf");
    let t = format!(
        "duration = 0.1\n\n[[robots]]\nurdf = {:?}\nmjcf = {:?}\n",
        urdf.display().to_string(),
        mjcf.display().to_string()
    );
    let e = error("robot_both.toml", &t);
    check(
        &e,
        "robot_both.toml",
        line_of(&t, "[[robots]]"),
        "robots[0]",
        "exactly one of `urdf` and `mjcf`",
    );
    // an MJCF error is at `robots[0].mjcf`, naming the file
    let t = "duration = 0.1\n\n[[robots]]\nmjcf = \"nowhere.xml\"\n";
    let e = error("robot_mjcf_missing.toml", t);
    check(
        &e,
        "robot_mjcf_missing.toml",
        4,
        "robots[0].mjcf",
        "nowhere.xml",
    );
}

// ---------------------------------------------------------------------------------------
// Input size cap
// ---------------------------------------------------------------------------------------

/// Every reader (scene, Radioss deck, riser deck, URDF, and `kjoint check`) refuses a file
/// that never ends after a bounded read, naming the file and the cap.
#[cfg(unix)]
#[test]
fn input_files_beyond_the_size_cap_are_refused_naming_file_and_cap() {
    use rapier_kjoint::io::{radioss, riser, urdf};
    let cap = "larger than 256 MiB, the size cap of input files";
    let zero = Path::new("/dev/zero");
    // a scene: a `.toml` name for /dev/zero
    let dir = common::cli::temp_dir("size-cap");
    std::fs::create_dir_all(&dir).unwrap();
    let scene_path = dir.join("zero.toml");
    let _ = std::fs::remove_file(&scene_path);
    std::os::unix::fs::symlink(zero, &scene_path).unwrap();
    let e = scene::load(&scene_path).unwrap_err();
    assert!(e.file.ends_with("zero.toml"), "{e}");
    assert!(e.to_string().contains(cap), "{e}");
    // a Radioss deck
    let e = radioss::RadiossDeck::from_file(zero).unwrap_err();
    assert_eq!(e.file, "/dev/zero");
    assert!(e.to_string().contains(cap), "{e}");
    // a riser deck
    let e = riser::RiserDeck::from_file(zero).unwrap_err();
    assert!(e.to_string().starts_with("/dev/zero: "), "{e}");
    assert!(e.to_string().contains(cap), "{e}");
    // a URDF
    let e = urdf::UrdfRobot::from_file(zero, &Default::default()).unwrap_err();
    assert!(e.to_string().starts_with("/dev/zero: "), "{e}");
    assert!(e.to_string().contains(cap), "{e}");
    // the command line
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .args(["check", "/dev/zero"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("/dev/zero: ") && err.contains(cap), "{err}");
}

// ---------------------------------------------------------------------------------------
// Rapier joints, motors, motions (the arm with a gripper)
// ---------------------------------------------------------------------------------------

/// A scene of the gripper arm with `options` for its robot and `extra` after it.
fn gripper(options: &str, extra: &str) -> String {
    let urdf = root().join("assets/urdf/arm_gripper.urdf");
    format!(
        "duration = 0.1\n\n[[robots]]\nurdf = {:?}\n[robots.options.joints.left_finger]\n\
         engine = \"rapier\"\n{options}\n{extra}",
        urdf.display().to_string()
    )
}

const MOTOR: &str = "motor = { stiffness = 1000.0, damping = 10.0 }";

#[test]
fn gripper_scene_errors_name_the_field() {
    // valid: a rapier finger with a motor, its schedule, a lift and rapier's settings
    let ok = gripper(
        MOTOR,
        "[[motors]]\njoint = \"left_finger\"\ntarget = 0.02\n\n[[motions]]\nbody = \
         \"base_link\"\nvelocity = [0, 0, 0.1]\n\n[rapier]\npgs_iterations = 3\n",
    );
    let path = tmp_file("gripper_ok.toml", &ok);
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    assert_eq!(
        built.joints.len(),
        4,
        "shoulder, elbow, wrist, right_finger"
    );
    let names: Vec<&str> = built
        .rapier_joints
        .iter()
        .map(|(n, _)| n.as_str())
        .collect();
    assert_eq!(names, ["left_finger"]);
    assert_eq!(built.motors[0].at(5.0), 0.02);
    assert_eq!(
        built.motions[0].velocity(0.0, 0.01, [0.0; 3]),
        [0.0, 0.0, 0.1]
    );
    assert!(
        built
            .world
            .integration_parameters
            .num_internal_pgs_iterations
            == 3
    );

    let cases: Vec<(&str, String, &str, &str, &str)> = vec![
        // (file, text, the line's text, field, message)
        (
            "motion_dynamic.toml",
            gripper(
                MOTOR,
                "[[motions]]\nbody = \"hand\"\ndisplacement = [0, 0, 0.1]\n",
            ),
            "body = \"hand\"",
            "motions[0].body",
            "body `hand` is dynamic",
        ),
        (
            "motion_unknown.toml",
            gripper(
                MOTOR,
                "[[motions]]\nbody = \"lift\"\ndisplacement = [0, 0, 0.1]\n",
            ),
            "body = \"lift\"",
            "motions[0].body",
            "no body named `lift`",
        ),
        (
            "motion_world.toml",
            gripper(
                MOTOR,
                "[[motions]]\nbody = \"world\"\nvelocity = [0, 0, 0.1]\n",
            ),
            "body = \"world\"",
            "motions[0].body",
            "`world` is the ground and does not move",
        ),
        (
            "motion_both.toml",
            gripper(
                MOTOR,
                "[[motions]]\nbody = \"base_link\"\ndisplacement = [0, 0, 0.1]\nvelocity = \
                 [0, 0, 1]\n",
            ),
            "[[motions]]",
            "motions[0]",
            "exactly one of `displacement` and `velocity`",
        ),
        (
            "motion_nan.toml",
            gripper(
                MOTOR,
                "[[motions]]\nbody = \"base_link\"\ndisplacement = [0, 0, nan]\n",
            ),
            "displacement",
            "motions[0].displacement[2]",
            "not a finite number",
        ),
        (
            "motion_curve.toml",
            gripper(
                MOTOR,
                "[[motions]]\nbody = \"base_link\"\ndisplacement = [0, 0, 0.1]\nfunction = { \
                 curve = [[1.0, 0.0], [1.0, 1.0]] }\n",
            ),
            "curve",
            "motions[0].function.curve[1]",
            "does not increase strictly",
        ),
        (
            "motion_twice.toml",
            gripper(
                MOTOR,
                "[[motions]]\nbody = \"base_link\"\nvelocity = [0, 0, 0.1]\n[[motions]]\nbody \
                 = \"base_link\" # again\nvelocity = [0, 0, -0.1]\n",
            ),
            "# again",
            "motions[1].body",
            "has a motion already",
        ),
        (
            "motor_kjoint.toml",
            gripper(MOTOR, "[[motors]]\njoint = \"elbow\"\ntarget = 0.1\n"),
            "joint = \"elbow\"",
            "motors[0].joint",
            "joint `elbow` has no motor: give it one in the robot's options",
        ),
        (
            "motor_unknown.toml",
            gripper(MOTOR, "[[motors]]\njoint = \"thumb\"\ntarget = 0.1\n"),
            "joint = \"thumb\"",
            "motors[0].joint",
            "no robot joint named `thumb` (rapier joints: left_finger; or a KJOINT2 joint",
        ),
        (
            "motor_without.toml",
            gripper("", "[[motors]]\njoint = \"left_finger\"\ntarget = 0.01\n"),
            "joint = \"left_finger\"",
            "motors[0].joint",
            "has no motor",
        ),
        (
            "motor_inf.toml",
            gripper(MOTOR, "[[motors]]\njoint = \"left_finger\"\ntarget = inf\n"),
            "target = inf",
            "motors[0].target",
            "not a finite number",
        ),
        (
            "motor_both.toml",
            gripper(
                MOTOR,
                "[[motors]]\njoint = \"elbow\"\ntarget = 0.1\nforce = 1.0\n",
            ),
            "force = 1.0",
            "motors[0].force",
            "expected one of `target` (a position [m or rad]) and `force`",
        ),
        (
            "motor_force_rapier.toml",
            gripper(MOTOR, "[[motors]]\njoint = \"left_finger\"\nforce = 1.0\n"),
            "joint = \"left_finger\"",
            "motors[0].joint",
            "rapier's motors have no constant force",
        ),
        (
            "rapier_pgs.toml",
            gripper(MOTOR, "[rapier]\npgs_iterations = 0\n"),
            "pgs_iterations",
            "rapier.pgs_iterations",
            "0: expected 1 ..= 1000",
        ),
        (
            "motor_nan.toml",
            gripper("motor = { stiffness = nan }", ""),
            "motor = ",
            "robots[0].options.joints.left_finger.motor.stiffness",
            "options.joints.`left_finger`.motor: invalid stiffness = NaN",
        ),
        (
            "motor_force.toml",
            gripper("motor = { stiffness = 10.0, max_force = 0.0 }", ""),
            "motor = ",
            "robots[0].options.joints.left_finger.motor.max_force",
            "expected a finite force > 0",
        ),
        // found by fuzzing arm_gripper.toml: 1e300 is finite as f64 but infinite as rapier's
        // f32 (`kjoint check` printed `max force inf N` and exited 0)
        (
            "motor_huge.toml",
            gripper("motor = { stiffness = 10.0, max_force = 1e300 }", ""),
            "motor = ",
            "robots[0].options.joints.left_finger.motor.max_force",
            "invalid max_force = 1e300: expected a finite force > 0 [N or N·m] (within ±1e12)",
        ),
        (
            "motor_empty.toml",
            gripper("motor = { target = 0.01 }", ""),
            "motor = ",
            "robots[0].options.joints.left_finger.motor.stiffness",
            "a motor with neither does nothing",
        ),
        (
            "rapier_friction.toml",
            gripper("friction = 1.0", ""),
            "friction = 1.0",
            "robots[0].options.joints.left_finger.friction",
            "takes no KJOINT2 field",
        ),
        (
            "kjoint_motor.toml",
            gripper(
                "",
                "[robots.options.joints.elbow]\nmotor = { stiffness = -5.0 }\n",
            ),
            "motor = { stiffness = -5.0 }",
            "robots[0].options.joints.elbow.motor.stiffness",
            "invalid stiffness = -5: expected a finite value >= 0",
        ),
    ];
    for (file, text, line, field, message) in cases {
        let e = error(file, &text);
        check(&e, file, line_of(&text, line), field, message);
        // the message names the URDF file where the URDF loader found it
        if field.starts_with("robots") {
            assert!(e.message.contains("arm_gripper.urdf"), "{e}");
        }
    }
    // an unknown engine is a parse error at its line
    let t = gripper("", "").replace("engine = \"rapier\"", "engine = \"bullet\"");
    let e = error("engine.toml", &t);
    assert_eq!(e.line, line_of(&t, "bullet"), "{e}");
    assert!(e.message.contains("unknown variant `bullet`"), "{e}");
}

/// `kjoint check` of a file it cannot tell (a `.txt`) names every kind it reads, and of a
/// deck without a KJOINT2 property (empty, or only other blocks) or of a riser deck without a
/// flex joint fails: they passed with exit 0, so a truncated or wrong deck went unnoticed.
#[test]
fn check_refuses_an_unknown_kind_of_file_and_a_deck_without_a_kjoint2_property() {
    let check = |path: &std::path::Path| {
        let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
            .arg("check")
            .arg(path)
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let txt = common::cli::temp_file("check-kinds", "deck.txt", "/PROP/TYPE45/1\nhinge\n");
    let (code, err) = check(&txt);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("deck.txt: unknown kind of file")
            && err.contains("`.toml`, `.json`")
            && err.contains("`.rad`, `.dat`, `.inc`")
            && err.contains("*FLEXJOINT"),
        "{err}"
    );
    for (name, text) in [
        ("empty.rad", ""),
        ("shell.rad", "/PROP/SHELL/1\nshell\n#ENDDATA\n"),
    ] {
        let deck = common::cli::temp_file("check-kinds", name, text);
        let (code, err) = check(&deck);
        assert_eq!(code, Some(1), "{name}: {err}");
        assert!(
            err.contains(&format!("{name}: no /PROP/TYPE45 (KJOINT2) property")),
            "{name}: {err}"
        );
    }
    // a riser deck of laws that no *FLEXJOINT reads: it printed `ok` with nothing listed
    let laws = common::cli::temp_file("check-kinds", "laws.dat", "*SPRINGPRO\n3 2 0 0 1 10\n");
    let (code, err) = check(&laws);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("laws.dat: no *FLEXJOINT element"), "{err}");
}

/// `--csv` naming a file that is not a directory fails before the run starts, saying what
/// was expected: it failed once the run had started, calling the user's own file "partial
/// outputs".
#[test]
fn csv_to_a_file_fails_before_the_run() {
    let file = common::cli::temp_file("csv-file", "not_a_dir", "mine");
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("run")
        .arg(root().join("assets/scenes/seed_translational_stops.toml"))
        .arg("--csv")
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let (stdout, err) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(stdout.is_empty(), "{stdout}");
    assert!(
        err.contains("--csv ")
            && err.contains("not_a_dir: ")
            && err.contains("expected a directory"),
        "{err}"
    );
    assert!(!err.contains("partial"), "{err}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
}

/// A scene whose deck property ends before its cards (a file cut short: the friction cards
/// lost) says so in `kjoint check` and counts it in `kjoint run`: the deck's notice stayed
/// with the deck, and the joint ran without friction, silently.
#[test]
fn a_deck_cut_short_is_noticed_in_the_scene_that_reads_it() {
    let deck = "/PROP/TYPE45/1\nfriction SI\n         6                   0                   0                  .2         0\n                   0         0\n";
    common::cli::temp_file("deck-cut-short", "cut.rad", deck);
    let scene = common::cli::temp_file(
        "deck-cut-short",
        "cut.toml",
        r#"dt = 0.016666666666666666
duration = 0.1

[[bodies]]
name = "block"
shape = { type = "cuboid", half_extents = [0.05, 0.05, 0.05] }
mass = 1.0

[[joints]]
name = "j"
body1 = "world"
body2 = "block"
property = { deck = "cut.rad", id = 1 }
"#,
    );
    let kjoint = |cmd: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
            .args(if cmd == "run" {
                &["run", "--quiet"][..]
            } else {
                &["check"][..]
            })
            .arg(&scene)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(0), "{cmd}");
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    let check = kjoint("check");
    assert!(
        check.contains("cut.rad:4: /PROP/TYPE45/1 ends before the cards dx.C, dx.Kf"),
        "{check}"
    );
    let run = kjoint("run");
    assert!(run.contains("1 notice from the inputs"), "{run}");
}

/// An override naming no joint of the robot (`[robots.options.joints.axel]`, a typo of
/// `axle`) was reported at the line of `urdf =` (`robots[0].urdf`), one line above the
/// override the user has to fix; it is now at the override's own table, for URDF and MJCF
/// robots alike.
#[test]
fn an_override_of_a_missing_joint_is_reported_at_its_own_line_urdf_and_mjcf() {
    for (key, file, expected) in [
        (
            "urdf",
            "assets/urdf/arm.urdf",
            "the name of a joint of the robot",
        ),
        (
            "mjcf",
            "assets/mjcf/pendulum.xml",
            "the name of a joint of the model",
        ),
    ] {
        let path = root().join(file);
        let t = format!(
            "duration = 0.1\n[[robots]]\n{key} = {:?}\n[robots.options.joints.axel]\n\
             friction = 0.3\n",
            path.display().to_string()
        );
        let name = format!("override_missing_{key}.toml");
        let e = error(&name, &t);
        check(
            &e,
            &name,
            line_of(&t, "[robots.options.joints.axel]"),
            "robots[0].options.joints.axel",
            &format!("options.joints: invalid name = axel: expected {expected}"),
        );
    }
}

/// A curve of one point has no segment, so no slope to extrapolate with: it was read as the
/// constant `y` everywhere (a flex joint's `bending = [[0.0, 0.0]]`, a spring of one
/// `/FUNCT` point that spun a body with no load to −507 rad, a load's time curve of one
/// point held from t = 0). Every reader of a curve refuses it at the file, line and field
/// where it is written, saying that a constant is two points with the same value.
#[test]
fn a_curve_of_one_point_is_refused_where_it_is_written() {
    const WANT: &str = "1 point: expected at least 2 points";
    const CONSTANT: &str = "a constant is two points with the same value";
    // a DOF's stiffness curve
    let t = replaced(
        "rx = { stop_min = -0.2, stop_max = 0.3 }",
        "rx = { stop_min = -0.2, stop_max = 0.3, stiffness_curve = [[0.1, 5.0]] }",
    );
    let e = error("one_point_k.toml", &t);
    check(
        &e,
        "one_point_k.toml",
        line_of(&t, "stiffness_curve"),
        "joints[0].property.rx.stiffness_curve",
        WANT,
    );
    assert!(e.message.contains(CONSTANT), "{e}");
    // a flex joint's bending and torsion laws
    for (key, law) in [
        ("bending", "bending = [[0.0, 0.0]]"),
        (
            "torsion",
            "bending = [[0.0, 0.0], [0.01, 2000.0], [0.02, 3000.0]]\ntorsion = [[0.0, 0.0]]",
        ),
    ] {
        let t = connectors(
            "bending = [[0.0, 0.0], [0.01, 2000.0], [0.02, 3000.0]]",
            law,
        );
        let e = error("one_point_flex.toml", &t);
        check(
            &e,
            "one_point_flex.toml",
            line_of(&t, &format!("{key} = [[0.0, 0.0]]")),
            &format!("joints[1].flex_joint.{key}"),
            WANT,
        );
    }
    // a load's time function
    let t = format!(
        "{BASE}\n[[loads]]\nbody = \"ball\"\nforce = [1, 0, 0]\nfunction = {{ curve = [[5.0, \
         1.0]] }}\n"
    );
    let e = error("one_point_load.toml", &t);
    check(
        &e,
        "one_point_load.toml",
        line_of(&t, "function ="),
        "loads[0].function.curve",
        WANT,
    );
    assert!(e.message.contains("`function = { constant = c }`"), "{e}");
    // a Radioss /FUNCT: the scene names the deck's line
    let deck = tmp_file(
        "funct_1pt.rad",
        "/PROP/TYPE45/2\nrev\n         2                   0                   0                   \
         0         0\n                   1         7                   0                   0         \
         0\n                   0         0\n                   0                   0         0\n\
         /FUNCT/7\none point\n                 0.1                 5.0\n/END\n",
    );
    let t = replaced(
        "[joints.property]\ntype = \"revolute\"\nrx = { stop_min = -0.2, stop_max = 0.3 }",
        &format!(
            "property = {{ deck = {:?}, id = 2 }}",
            deck.to_str().unwrap()
        ),
    );
    let e = error("one_point_funct.toml", &t);
    assert_eq!(e.field, "joints[0].property.deck", "{e}");
    assert!(
        e.message.contains(
            "funct_1pt.rad:9: field `X` of /FUNCT/7: invalid curve: 1 point: expected \
                       at least 2 points"
        ),
        "{e}"
    );
    // a riser deck's *SPRINGPRO
    let riser = tmp_file(
        "riser_1pair.dat",
        "*SPRINGPRO\n3 1 0 0\n*FLEXJOINT\n3 1 3 3 0 0.\n",
    );
    let t = connectors(
        "switch_time = 1.0\nbending = [[0.0, 0.0], [0.01, 2000.0], [0.02, 3000.0]]\n\
         dynamic = { torsion_stiffness = 1e5, kdyn_ini = 4e5, kdyn_lim = 2e5, angle_lim = 1e-3 }\n",
        &format!("deck = {:?}\nelement = 3\n", riser),
    );
    let e = error("one_point_riser.toml", &t);
    assert_eq!(e.field, "joints[1].flex_joint.deck", "{e}");
    assert!(
        e.message.contains(
            "riser_1pair.dat:2: field `NPAIRS` of *SPRINGPRO: invalid value 1: expected at least \
             2 (angle, moment) pairs (a constant is two pairs with the same moment)"
        ),
        "{e}"
    );
    // a robot's property override
    let urdf = root().join("assets/urdf/arm.urdf");
    let t = format!(
        "duration = 0.1\n\n[[robots]]\nurdf = {:?}\n[robots.options.joints.elbow.property]\n\
         type = \"revolute\"\ndofs = [{{}}, {{}}, {{}}, {{ stiffness_curve = [[0.1, 5.0]] }}, {{}}, \
         {{}}]\n",
        urdf.display().to_string()
    );
    let e = error("one_point_override.toml", &t);
    assert_eq!(e.line, line_of(&t, "dofs = "), "{e}");
    assert!(e.message.contains(WANT), "{e}");
}

/// `[[switches]]` name a KJOINT2 joint and a time ≥ 0; an unknown key is refused at its line.
#[test]
fn switches_name_a_joint_and_a_time() {
    for (name, switch, needle, field, message) in [
        (
            "switch_unknown.toml",
            "[[switches]]\njoint = \"k\"\ntime = 0.5\nenabled = false\n",
            "joint = \"k\"",
            "switches[0].joint",
            "no KJOINT2 joint named `k`: j",
        ),
        (
            "switch_negative.toml",
            "[[switches]]\njoint = \"j\"\ntime = -0.5\nenabled = false\n",
            "time = -0.5",
            "switches[0].time",
            "-0.5: expected >= 0",
        ),
        (
            "switch_key.toml",
            "[[switches]]\njoint = \"j\"\nat = 0.5\nenabled = false\n",
            "at = 0.5",
            "switches[0].at",
            "unknown field `at`",
        ),
    ] {
        let text = format!("{BASE}\n{switch}");
        let e = error(name, &text);
        check(&e, name, line_of(&text, needle), field, message);
    }
}

/// A deck given where a scene is expected (`kjoint run ex2.dat`) said only "expected a
/// `.toml` or `.json` extension"; it now says a deck is read by `kjoint check` and run from
/// a scene, with the keys that reference one. Other extensions keep the short message.
#[test]
fn a_deck_given_as_a_scene_is_told_how_a_scene_runs_it() {
    for name in ["riser.dat", "model.rad", "part.INC"] {
        let path = tmp_file(name, "*FLEXJOINT\n");
        let e = scene::load(&path).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("a Radioss or riser deck is not a scene; `kjoint check` reads it")
                && text.contains("flex_joint = { deck = \"...\", element = N }")
                && text.contains("property = { deck = \"...\", id = N }"),
            "{text}"
        );
    }
    let e = scene::load(&tmp_file("notes.txt", "x")).unwrap_err();
    assert!(
        e.to_string()
            .ends_with("expected a `.toml` or `.json` extension"),
        "{e}"
    );
}
