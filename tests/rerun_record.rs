//! A recording written by [`RerunLogger`] holds the logged entities and the values the Rust
//! side saw. The `.rrd` is read back with the rerun Python SDK (`tests/read_rrd.py`) run by
//! the interpreter in `KJOINT_RERUN_PYTHON` (a venv with `rerun-sdk==0.36.3`, set up by
//! `.ci/run`); without it the read-back is skipped with a notice.
//!
//! `cargo test --features rerun --test rerun_record`

mod common;

use rapier_kjoint::io::urdf::{load_urdf, UrdfOptions};
use rapier_kjoint::output::rerun_log::RerunLogger;
use rapier_kjoint::output::Observer;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, SensorCondition};

/// The strings of a JSON array.
fn strings(v: &serde_json::Value) -> Vec<&str> {
    v.as_array()
        .unwrap()
        .iter()
        .filter_map(|e| e.as_str())
        .collect()
}

/// Reads a recording back with `tests/read_rrd.py` (module docs); `None` with a notice when
/// `KJOINT_RERUN_PYTHON` is not set.
fn read_back(rrd: &std::path::Path, queried: &[&str]) -> Option<serde_json::Value> {
    let size = std::fs::metadata(rrd).unwrap().len();
    let Some(python) = std::env::var_os("KJOINT_RERUN_PYTHON") else {
        println!(
            "NOTICE: KJOINT_RERUN_PYTHON is not set: wrote {} ({size} bytes) but skipped reading \
             it back (.ci/run sets it to a venv with rerun-sdk==0.36.3)",
            rrd.display()
        );
        return None;
    };
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/read_rrd.py");
    let out = std::process::Command::new(&python)
        .arg(script)
        .arg(rrd)
        .args(queried)
        .output()
        .expect("runs the python reader");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "read_rrd.py failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(serde_json::from_str(&stdout).expect("JSON from read_rrd.py"))
}

#[test]
fn a_recorded_run_reads_back_with_its_entities_and_joint_values() {
    let dir = std::env::temp_dir().join(format!("kjoint-rerun-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rrd = dir.join("arm.rrd");

    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/urdf/arm.urdf");
    let robot = load_urdf(path, &mut world, &mut joints, &UrdfOptions::default()).unwrap();
    joints.add_sensor(7, SensorCondition::Time(0.25)).unwrap();
    let mut logger = RerunLogger::save(&rrd).unwrap().with_urdf_robot(&robot);
    let mut events_seen = 0;
    for _ in 0..45 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
        let ev = joints.drain_events();
        events_seen += ev.iter().filter(|e| e.sensor().is_some()).count();
        logger.record(joints.time(), &world, &joints, &ev).unwrap();
    }
    logger.finish().unwrap();
    drop(logger);
    assert_eq!(events_seen, 1, "the time sensor fired once");
    let size = std::fs::metadata(&rrd).unwrap().len();
    assert!(size > 10_000, "recording of {size} bytes");

    let shoulder = joints
        .get(robot.joints["shoulder"])
        .unwrap()
        .state()
        .unwrap()
        .clone();
    let wrist = joints
        .get(robot.joints["wrist"])
        .unwrap()
        .state()
        .unwrap()
        .clone();
    let t_end = joints.time();

    let queried = [
        "/joints/shoulder/rx/q",
        "/joints/shoulder/rx/force",
        "/joints/wrist/dx/q",
        "/joints/wrist/dx/force/friction",
    ];
    let Some(v) = read_back(&rrd, &queried) else {
        let _ = std::fs::remove_dir_all(&dir);
        return;
    };

    // entities
    let entities: Vec<&str> = strings(&v["entities"]);
    for e in [
        "/world/bodies/base_link",
        "/world/bodies/upper_arm",
        "/world/bodies/hand",
        "/world/joints/elbow/axes",
        "/world/joints/elbow/anchors",
        "/joints/elbow/rx/force/friction",
        "/joints/elbow/rx/slip",
        "/joints/elbow/rx/stop",
        "/joints/shoulder/energy/elastic",
        "/joints/wrist/locked",
        "/events",
    ] {
        assert!(entities.contains(&e), "{e} missing from {entities:?}");
    }
    let shapes = entities
        .iter()
        .filter(|e| e.starts_with("/world/bodies/forearm/collider"))
        .count();
    assert_eq!(shapes, 1, "the forearm's cylinder collider");
    // the hand's visual mesh (assets/urdf/meshes/hand.stl: palm and two fingers, 36 triangles)
    assert_eq!(robot.visual_meshes.len(), 1);
    assert_eq!(robot.visual_meshes[0].triangles.len(), 36);
    assert!(
        entities.contains(&"/world/bodies/hand/visual0"),
        "{entities:?}"
    );

    // values at the last logged time
    let last = &v["last"];
    let check = |path: &str, expected: f64| {
        let t = last[path]["time"]
            .as_f64()
            .unwrap_or_else(|| panic!("{path}: {last}"));
        let x = last[path]["value"].as_f64().unwrap();
        assert!((t - t_end).abs() < 1e-6, "{path}: last time {t} vs {t_end}");
        assert!(
            (x - expected).abs() <= 1e-12 * expected.abs().max(1.0),
            "{path}: recorded {x} vs JointState {expected}"
        );
        println!("{path}: t = {t} s, {x} (JointState {expected})");
    };
    check("/joints/shoulder/rx/q", shoulder.q[Dof::Rx.index()]);
    check("/joints/shoulder/rx/force", shoulder.force[Dof::Rx.index()]);
    check("/joints/wrist/dx/q", wrist.q[Dof::Dx.index()]);
    check(
        "/joints/wrist/dx/force/friction",
        wrist.parts[Dof::Dx.index()].friction,
    );
    assert!(shoulder.q[Dof::Rx.index()] > 0.05, "the arm has moved");
    let texts = strings(&v["events"]);
    assert_eq!(texts.len(), 1);
    assert!(texts[0].starts_with("sensor 7 at t = 0.2"), "{texts:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The two connector scenes, run through the scene loop into one recording each: their
/// connector readouts (`joints/<joint>/<law>/<channel>`) and the flex joint's phase-switch
/// event read back with the values the Rust side saw.
#[test]
fn connector_states_and_the_phase_switch_are_recorded() {
    use rapier_kjoint::scene::{self, RunOptions};
    let dir = std::env::temp_dir().join(format!("kjoint-rerun-conn-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for (name, joint, law, duration, channel) in [
        (
            "planar_friction_block",
            "contact",
            "planar_friction",
            1.0,
            "normal_force",
        ),
        (
            "riser_flexjoint",
            "flexjoint",
            "flex_joint",
            4.5,
            "bending_angle",
        ),
    ] {
        let (sc, src) = scene::load(&root.join(format!("assets/scenes/{name}.toml"))).unwrap();
        let mut built = scene::build(&sc, &src).unwrap();
        let rrd = dir.join(format!("{name}.rrd"));
        let mut logger = RerunLogger::save(&rrd).unwrap();
        let options = RunOptions {
            duration: Some(duration),
            ..Default::default()
        };
        {
            let mut observers: Vec<&mut dyn Observer> = vec![&mut logger];
            scene::run(&mut built, &options, &mut observers, &mut |_, _| {}).unwrap();
        }
        drop(logger);
        let (_, j) = built.joints.iter().next().unwrap();
        let report = j.state().unwrap().connector.expect("a connector readout");
        let (law_name, channels) = report.channels();
        assert_eq!(law_name, law);
        let expected = channels.iter().find(|(n, _)| *n == channel).unwrap().1;
        assert!(expected > 0.0, "{name}: {channel} = {expected}");
        let path = format!("/joints/{joint}/{law}/{channel}");
        let phase = format!("/joints/{joint}/{law}/phase");
        let Some(v) = read_back(&rrd, &[&path, &phase]) else {
            continue;
        };
        let entities: Vec<&str> = strings(&v["entities"]);
        for (n, _) in &channels {
            let e = format!("/joints/{joint}/{law}/{n}");
            assert!(
                entities.contains(&e.as_str()),
                "{e} missing from {entities:?}"
            );
        }
        let last = &v["last"][&path];
        let x = last["value"].as_f64().unwrap();
        assert!(
            (last["time"].as_f64().unwrap() - built.joints.time()).abs() < 1e-6,
            "{last}"
        );
        assert!(
            (x - expected).abs() <= 1e-12 * expected.abs(),
            "{path}: {x} vs {expected}"
        );
        let events: Vec<&str> = strings(&v["events"]);
        if law == "flex_joint" {
            assert_eq!(
                v["last"][&phase]["value"].as_f64(),
                Some(1.0),
                "dynamic at the end"
            );
            assert_eq!(events.len(), 1, "{events:?}");
            assert!(
                events[0].starts_with("joint flexjoint at t = 4.0")
                    && events[0].contains("dynamic phase"),
                "{events:?}"
            );
        } else {
            assert!(events.is_empty(), "{events:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
