//! The MJCF loader does not panic on user input: attribute values of a model that uses most
//! of what the loader maps (defaults and classes, a free body, hinge, slide and ball joints,
//! every geom type, full and diagonal inertias, actuators, a keyframe, contact excludes,
//! `<option>`) are replaced by arbitrary numbers and words, text is cut; every result is `Ok`
//! or a typed error, and a loaded robot steps a few frames (an error is allowed, a panic is
//! not). `PROPTEST_CASES=10000` runs it longer; `KJOINT_MJCF_MODELS` (the gymnasium models
//! CI downloads) adds their mutations.

mod common;

use proptest::prelude::*;
use rapier_kjoint::io::urdf::UrdfOptions;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::KjointSet;

const MODEL: &str = r#"<mujoco model="fuzz">
  <compiler angle="degree" autolimits="true"/>
  <option timestep="0.002" gravity="0 0 -9.81" integrator="implicitfast"/>
  <default>
    <joint damping="0.1" armature="0.01"/>
    <geom density="500" friction="0.8 0.005 0.0001"/>
    <default class="limb">
      <joint type="hinge" axis="0 1 0" range="-60 60" stiffness="2" springref="5"/>
      <geom type="capsule" size="0.03"/>
    </default>
  </default>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1" pos="0 0 0"/>
    <body name="torso" pos="0 0 1.2" quat="1 0 0 0">
      <freejoint name="root"/>
      <geom name="chest" type="box" size="0.15 0.1 0.2"/>
      <geom type="ellipsoid" size="0.05 0.06 0.07" pos="0 0 0.3"/>
      <site name="imu" pos="0 0 0.1"/>
      <body name="thigh" pos="0 0.08 -0.2" euler="0 10 0" childclass="limb">
        <joint name="hip" ref="3" frictionloss="0.2"/>
        <geom fromto="0 0 0 0 0 -0.4"/>
        <body name="shin" pos="0 0 -0.4">
          <joint name="knee" axis="0 -1 0" range="0 120" limited="true" damping="0.5"/>
          <geom fromto="0 0 0 0 0 -0.4" size="0.025"/>
          <inertial pos="0 0 -0.2" mass="1.5" fullinertia="0.02 0.02 0.002 0 0 0.001"/>
          <body name="foot" pos="0 0 -0.4" axisangle="0 0 1 15">
            <joint name="ankle" type="ball" range="0 30" damping="0.05"/>
            <geom type="cylinder" size="0.04 0.02" pos="0.03 0 0"/>
          </body>
        </body>
      </body>
      <body name="arm" pos="0.2 0 0.1" xyaxes="1 0 0 0 1 0">
        <joint name="reach" type="slide" axis="1 0 0" range="-0.1 0.2" stiffness="50"/>
        <geom type="sphere" size="0.05" mass="0.4"/>
        <inertial pos="0 0 0" mass="0.4" diaginertia="0.001 0.001 0.001"/>
      </body>
    </body>
  </worldbody>
  <contact>
    <exclude body1="torso" body2="arm"/>
  </contact>
  <actuator>
    <motor name="hip_motor" joint="hip" gear="20" ctrlrange="-1 1"/>
    <position joint="knee" kp="40" ctrlrange="0 2"/>
    <velocity joint="reach" kv="5"/>
    <general joint="ankle" gainprm="3" biasprm="0 0 0"/>
  </actuator>
  <keyframe>
    <key name="stand" qpos="0 0 1.2 1 0 0 0 0.1 0.5 1 0 0 0 0.05" ctrl="0.2 1 0 0"/>
  </keyframe>
</mujoco>
"#;

fn run(text: &str, base: &str) {
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = KjointSet::new();
    if common::robot::insert_mjcf_str(
        text,
        "fuzz.xml",
        base,
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    )
    .is_ok()
    {
        for _ in 0..3 {
            if joints.step(&mut world, 1.0 / 60.0).is_err() {
                break;
            }
        }
    }
}

fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<f64>().prop_map(|v| v.to_string()),
        (-1e3f64..1e3).prop_map(|v| v.to_string()),
        (-1e3f64..1e3, -1e3f64..1e3, -1e3f64..1e3).prop_map(|(a, b, c)| format!("{a} {b} {c}")),
        Just("nan".to_string()),
        Just("-inf".to_string()),
        Just("0".to_string()),
        Just("-0".to_string()),
        Just("0 0 0".to_string()),
        Just("0 0 0 0".to_string()),
        Just("1e308 1e308 1e308".to_string()),
        Just("1e39".to_string()),
        Just("-1 -1 -1".to_string()),
        Just("1 2".to_string()),
        Just("1 2 3 4 5 6 7 8 9 10 11".to_string()),
        Just("hinge".to_string()),
        Just("slide".to_string()),
        Just("ball".to_string()),
        Just("free".to_string()),
        Just("mesh".to_string()),
        Just("plane".to_string()),
        Just("hfield".to_string()),
        Just("sdf".to_string()),
        Just("true".to_string()),
        Just("false".to_string()),
        Just("auto".to_string()),
        Just("radian".to_string()),
        Just("limb".to_string()),
        Just("torso".to_string()),
        Just("foot".to_string()),
        Just("knee".to_string()),
        Just("world".to_string()),
        "[ a-z0-9.eE+-]{0,12}",
    ]
}

/// The gymnasium models (`KJOINT_MJCF_MODELS`), with their directory, when given.
fn gymnasium_models() -> Vec<(String, String)> {
    let Ok(dir) = std::env::var("KJOINT_MJCF_MODELS") else {
        return Vec::new();
    };
    let mut out = Vec::new();
    if let Ok(entries) = std::fs::read_dir(&dir) {
        for e in entries.flatten() {
            let p = e.path();
            if p.extension().is_some_and(|x| x == "xml") {
                if let Ok(t) = std::fs::read_to_string(&p) {
                    out.push((t, dir.clone()));
                }
            }
        }
    }
    out.sort();
    out
}

#[test]
fn the_fuzzed_model_loads_and_stands_unmutated() {
    // the mutations start from a model the loader takes whole: a model refused outright
    // would leave them testing its first error only
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = KjointSet::new();
    let robot = common::robot::insert_mjcf_str(
        MODEL,
        "fuzz.xml",
        ".",
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    )
    .unwrap();
    assert_eq!(joints.len(), 4, "hip, knee, ankle, reach");
    assert!(robot.links.len() >= 5);
    for _ in 0..30 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
    }
}

/// The error that loading `text` (as `fuzz.xml`) gives, as text; a panic naming the text
/// where it loads.
fn load_error(text: &str) -> String {
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = KjointSet::new();
    let loaded = common::robot::insert_mjcf_str(
        text,
        "fuzz.xml",
        ".",
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    );
    match loaded {
        Ok(_) => panic!("loaded, where an error was expected:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// Found by the fuzzing below: mjcf-rs names neither element nor attribute of a number,
/// integer or boolean it cannot read (`invalid attribute `_` on <_>`) and no line for any
/// attribute, and a finite but huge joint damping or an actuator's NaN gain reached the
/// joint's builder, refused there without a line. Each names its element, line and
/// attribute now.
#[test]
fn unreadable_and_unmappable_values_are_refused_naming_element_line_and_attribute() {
    let cases = [
        // (text replaced, by, the element as named, the attribute, value and expectation)
        (r#"biasprm="0 0 0""#, r#"biasprm="torso""#, "<general>", "biasprm = torso: expected numbers"),
        (r#"timestep="0.002""#, r#"timestep="-1 -1 -1""#, "<option>", "timestep = -1 -1 -1: expected numbers"),
        (
            r#"limited="true""#,
            r#"limited="-1 -1 -1""#,
            "<joint name=\"knee\">",
            "limited = -1 -1 -1: expected `true`/`false`/`auto`",
        ),
        (
            r#"type="plane""#,
            r#"type="0""#,
            "<geom name=\"floor\">",
            "type = 0: expected a geom type: plane, hfield, sphere, capsule, ellipsoid, cylinder, box, mesh or sdf",
        ),
        (
            r#"gear="20" ctrlrange="-1 1""#,
            r#"gear="20" ctrlrange="1""#,
            "<motor name=\"hip_motor\">",
            "ctrlrange = 1: expected 2 floats, got 1",
        ),
        (r#"kp="40""#, r#"kp="nan""#, "<position>", "kp = NaN: expected a finite number"),
        (r#"kp="40""#, r#"kp="-40""#, "<position>", "kp = -40: expected a gain >= 0"),
        (r#"gear="20""#, r#"gear="1e308""#, "<motor name=\"hip_motor\">", "gear = 1e308: expected a finite number within ±1e12"),
        (
            r#"damping="0.5""#,
            r#"damping="1e308""#,
            "joint `knee` (body `shin`",
            "damping = 1e308: expected a finite number within ±1e12",
        ),
        (
            r#"density="500""#,
            r#"density="500" contype="x""#,
            "<geom>",
            "contype = x: expected an integer >= 0",
        ),
        (
            r#"<geom name="chest""#,
            r#"<geom group="1.5" name="chest""#,
            "<geom name=\"chest\">",
            "group = 1.5: expected an integer",
        ),
    ];
    for (from, to, element, what) in cases {
        let line = 1 + MODEL.lines().position(|l| l.contains(from)).expect(from);
        let e = load_error(&MODEL.replacen(from, to, 1));
        let at = if element.ends_with('`') || element.contains("(body") {
            format!("fuzz.xml: {element}, line {line}): invalid {what}")
        } else {
            format!("fuzz.xml: {element} (line {line}): invalid {what}")
        };
        assert!(e.starts_with(&at), "`{e}` should start with `{at}`");
    }
}

/// mjcf-rs never reads a light's attributes (MuJoCo's `specular` is three numbers there, a
/// material's one): an unreadable mass further down is the one named, not the light's
/// `specular` before it.
#[test]
fn an_unreadable_number_is_not_confused_with_an_attribute_mjcf_rs_does_not_read() {
    let text = MODEL
        .replacen(
            r#"<geom name="floor""#,
            r#"<light pos="0 0 3" specular=".1 .1 .1"/><geom name="floor""#,
            1,
        )
        .replacen(r#"mass="1.5""#, r#"mass="x""#, 1);
    let line = 1 + MODEL
        .lines()
        .position(|l| l.contains(r#"mass="1.5""#))
        .unwrap();
    let e = load_error(&text);
    let at = format!("fuzz.xml: <inertial> (line {line}): invalid mass = x: expected numbers");
    assert!(e.starts_with(&at), "`{e}` should start with `{at}`");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn no_panic_on_mutated_attributes(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), value()), 1..6)
    ) {
        run(&common::fuzz::mutate(MODEL, edits), ".");
    }

    #[test]
    fn no_panic_on_cut_text(cut in 0usize..MODEL.len(), text in "(?s).{0,200}") {
        let mut c = cut;
        while !MODEL.is_char_boundary(c) {
            c -= 1;
        }
        run(&MODEL[..c], ".");
        run(&format!("{}{text}", &MODEL[..c]), ".");
        run(&text, ".");
    }

    #[test]
    fn no_panic_on_mutated_gymnasium_models(
        which in any::<prop::sample::Index>(),
        edits in proptest::collection::vec((any::<prop::sample::Index>(), value()), 1..4)
    ) {
        let models = gymnasium_models();
        if !models.is_empty() {
            let (text, dir) = &models[which.index(models.len())];
            run(&common::fuzz::mutate(text, edits), dir);
        }
    }
}
