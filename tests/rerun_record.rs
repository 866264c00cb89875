//! A recording written by [`RerunLogger`] holds the logged entities and the values the Rust
//! side saw. The `.rrd` is read back with the rerun Python SDK (`tests/read_rrd.py`) run by
//! the interpreter in `KJOINT_RERUN_PYTHON` (a venv with `rerun-sdk==0.36.3`, set up by
//! `.ci/run`); without it the read-back is skipped with a notice.
//!
//! `cargo test --features rerun --test rerun_record`

mod common;

use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobotHandles};
use rapier_kjoint::output::rerun_log::RerunLogger;
use rapier_kjoint::output::Observer;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, KjointSet, SensorCondition};
use serde_json::Value;

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

/// A new directory for the files of test `tag`.
fn fresh_dir(tag: &str) -> std::path::PathBuf {
    let dir = common::cli::temp_dir(&format!("rerun-{tag}"));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Records 45 frames (0.75 s) of the URDF arm (`assets/urdf/arm.urdf`: shoulder and elbow
/// revolute, wrist prismatic) into `rrd`, a time sensor (7) locking the wrist at 0.25 s;
/// returns the joints, the robot and how many sensor events the run gave.
fn record_arm(rrd: &std::path::Path) -> (KjointSet, UrdfRobotHandles, usize) {
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = common::joints(4);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/urdf/arm.urdf");
    let robot =
        common::robot::insert_urdf_file(path, &mut world, &mut joints, &UrdfOptions::default())
            .unwrap();
    joints.add_sensor(7, SensorCondition::Time(0.25)).unwrap();
    let mut logger = RerunLogger::save(rrd).unwrap().with_urdf_robot(&robot);
    let mut events_seen = 0;
    for _ in 0..45 {
        joints.step(&mut world, 1.0 / 60.0).unwrap();
        let ev = joints.drain_events();
        events_seen += ev.iter().filter(|e| e.sensor().is_some()).count();
        logger.record(joints.time(), &world, &joints, &ev).unwrap();
    }
    logger.finish().unwrap();
    (joints, robot, events_seen)
}

#[test]
fn a_recorded_run_reads_back_with_its_entities_and_joint_values() {
    let dir = fresh_dir("test");
    let rrd = dir.join("arm.rrd");
    let (joints, robot, events_seen) = record_arm(&rrd);
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
    let dir = fresh_dir("conn");
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

/// Whether entity `path` is in the contents of a view: rerun query expressions `+ /a/b`
/// (that entity) and `+ /a/b/**` (it and everything below), `- …` excluding, `$origin` the
/// view's origin.
fn in_view(origin: &str, queries: &[&str], path: &str) -> bool {
    let matches = |q: &str| match q.strip_suffix("/**") {
        Some(base) => path == base || path.starts_with(&format!("{base}/")),
        None => path == q,
    };
    let mut inside = false;
    for q in queries {
        let q = q.replace("$origin", origin);
        if let Some(q) = q.strip_prefix("- ") {
            if matches(q.trim()) {
                return false;
            }
        } else {
            inside |= matches(q.trim_start_matches("+ ").trim());
        }
    }
    inside
}

/// A view of the blueprint: its class, title, origin and query expressions.
#[derive(Debug)]
struct ViewRead {
    class: String,
    name: String,
    origin: String,
    queries: Vec<String>,
}

/// The first string of a blueprint cell (a list of one instance, or the value itself).
fn first_str(v: &Value) -> Option<&str> {
    v.as_str().or_else(|| {
        v.as_array()
            .and_then(|a| a.first())
            .and_then(|x| x.as_str())
    })
}

/// Walks the blueprint's container tree from the viewport's root: the views, each with the
/// display names of the containers above it (outermost first).
fn blueprint_views(bp: &serde_json::Map<String, Value>) -> Vec<(Vec<String>, ViewRead)> {
    let viewport = &bp["/viewport"];
    // the root container's id: a UUID as its 16 bytes
    let root: String = viewport["ViewportBlueprint:root_container"][0]
        .as_array()
        .unwrap_or_else(|| panic!("no root container: {viewport}"))
        .iter()
        .map(|b| format!("{:02x}", b.as_u64().unwrap()))
        .collect();
    assert_eq!(root.len(), 32, "{viewport}");
    let mut out = Vec::new();
    // (path in the blueprint, names of the containers above); paths compared without the
    // dashes of their UUIDs
    let mut stack = vec![(format!("/container/{root}"), Vec::new())];
    let norm = |p: &str| p.replace('-', "");
    let by_path: std::collections::HashMap<String, &Value> =
        bp.iter().map(|(k, v)| (norm(k), v)).collect();
    while let Some((path, above)) = stack.pop() {
        let cell = by_path
            .get(&norm(&path))
            .unwrap_or_else(|| panic!("{path} is not in the blueprint: {:?}", bp.keys()));
        if path.starts_with("/container/") {
            let name = first_str(&cell["ContainerBlueprint:display_name"])
                .unwrap_or("")
                .to_string();
            let mut inner = above.clone();
            inner.push(name);
            for child in cell["ContainerBlueprint:contents"].as_array().unwrap() {
                let child = child.as_str().unwrap();
                stack.push((format!("/{}", child.trim_start_matches('/')), inner.clone()));
            }
        } else {
            let contents = by_path[&norm(&format!("{path}/ViewContents"))];
            let queries = contents["ViewContents:query"]
                .as_array()
                .unwrap()
                .iter()
                .map(|q| q.as_str().unwrap().to_string())
                .collect();
            let s = |c: &str| first_str(&cell[c]).unwrap_or("").to_string();
            out.push((
                above,
                ViewRead {
                    class: s("ViewBlueprint:class_identifier"),
                    name: s("ViewBlueprint:display_name"),
                    origin: s("ViewBlueprint:space_origin"),
                    queries,
                },
            ));
        }
    }
    out
}

/// The recording opens on plots: its blueprint (read back from the `.rrd` with the rerun
/// SDK) holds the 3-D view of `/world` and, per joint, a container named after it whose
/// time-series views hold the joint's transmitted force, its `q` with the stop lines (whose
/// values are the URDF limits), and its energies, and nothing of another joint.
#[test]
fn the_recording_opens_on_a_view_per_joint() {
    let dir = fresh_dir("bp");
    let rrd = dir.join("arm.rrd");
    let (joints, robot, _) = record_arm(&rrd);
    // the URDF limits: shoulder [-1, 0.6] rad, elbow [-2, 0.8] rad, wrist [-0.02, 0.05] m
    let limits = [
        ("shoulder", "rx", -1.0, 0.6),
        ("elbow", "rx", -2.0, 0.8),
        ("wrist", "dx", -0.02, 0.05),
    ];
    let stop_paths: Vec<String> = limits
        .iter()
        .flat_map(|(j, d, _, _)| ["stop_min", "stop_max"].map(|s| format!("/joints/{j}/{d}/q/{s}")))
        .collect();
    let queried: Vec<&str> = stop_paths.iter().map(|s| s.as_str()).collect();
    let Some(v) = read_back(&rrd, &queried) else {
        let _ = std::fs::remove_dir_all(&dir);
        return;
    };
    let entities = strings(&v["entities"]);
    for (j, d, lo, hi) in limits {
        let h = robot.joints[j];
        let law = joints
            .get(h)
            .unwrap()
            .property()
            .dof(Dof::ALL.into_iter().find(|x| x.name() == d).unwrap())
            .clone();
        assert_eq!((law.stop_min, law.stop_max), (lo, hi), "{j}");
        for (s, x) in [("stop_min", lo), ("stop_max", hi)] {
            let p = format!("/joints/{j}/{d}/q/{s}");
            let got = v["last"][&p]["value"]
                .as_f64()
                .unwrap_or_else(|| panic!("{p}: {v}"));
            assert_eq!(got, x, "{p}");
        }
    }

    let bps = v["blueprints"].as_array().unwrap();
    assert_eq!(bps.len(), 1, "one blueprint store in the file");
    // the viewer is told to show it: the activation command follows the blueprint (printed
    // by the `rerun` command of the same venv; the Python reader does not list commands)
    let python = std::path::PathBuf::from(std::env::var_os("KJOINT_RERUN_PYTHON").unwrap());
    let out = std::process::Command::new(python.with_file_name("rerun"))
        .args(["rrd", "print", "-v"])
        .arg(&rrd)
        .output()
        .expect("runs `rerun rrd print` of the venv");
    let printed = String::from_utf8_lossy(&out.stdout);
    let activation: Vec<&str> = printed
        .lines()
        .filter(|l| l.starts_with("BlueprintActivationCommand("))
        .collect();
    assert_eq!(activation.len(), 1, "{printed}");
    assert!(
        activation[0].contains("make_active: true")
            && activation[0].contains("Blueprint, \"rapier_kjoint\""),
        "{activation:?}"
    );
    let views = blueprint_views(bps[0].as_object().unwrap());
    for (above, view) in &views {
        println!(
            "{above:?} {} `{}` origin {}: {:?}",
            view.class, view.name, view.origin, view.queries
        );
    }
    // the 3-D view shows every body and joint frame
    let spatial: Vec<_> = views.iter().filter(|(_, v)| v.class == "3D").collect();
    assert_eq!(spatial.len(), 1, "{views:?}");
    let world = &spatial[0].1;
    assert_eq!(world.origin, "/world");
    let q: Vec<&str> = world.queries.iter().map(|s| s.as_str()).collect();
    for e in &entities {
        assert_eq!(
            in_view(&world.origin, &q, e),
            e.starts_with("/world/"),
            "{e} {world:?}"
        );
    }

    // the time-series views, by the container (joint) they are in
    let series: Vec<_> = views
        .iter()
        .filter(|(_, v)| v.class == "TimeSeries")
        .collect();
    let mut containers: Vec<&str> = series
        .iter()
        .map(|(above, _)| above.last().unwrap().as_str())
        .collect();
    containers.dedup();
    let mut names: Vec<&str> = joints.iter().map(|(_, j)| j.name.as_str()).collect();
    assert_eq!(
        containers.len(),
        joints.len(),
        "a container per joint: {containers:?}"
    );
    containers.sort();
    names.sort();
    assert_eq!(containers, names);

    for (_, j) in joints.iter() {
        let own = format!("/joints/{}/", j.name);
        let mine: Vec<&ViewRead> = series
            .iter()
            .filter(|(above, _)| above.last().unwrap() == &j.name)
            .map(|(_, v)| v)
            .collect();
        let shows = |v: &ViewRead, e: &str| {
            let q: Vec<&str> = v.queries.iter().map(|s| s.as_str()).collect();
            in_view(&v.origin, &q, e)
        };
        // no view of this joint shows an entity of another one
        for v in &mine {
            for e in &entities {
                if shows(v, e) {
                    assert!(e.starts_with(&own), "`{}` shows {e}", v.name);
                }
            }
        }
        let has = |e: &str| entities.contains(&e);
        let all_in_one_view = |wanted: Vec<String>| -> Vec<&str> {
            for w in &wanted {
                assert!(has(w), "{w} is not in the recording");
            }
            mine.iter()
                .filter(|v| wanted.iter().all(|w| shows(v, w)))
                .map(|v| v.name.as_str())
                .collect()
        };
        let jt = j.property().joint_type;
        let free: Vec<Dof> = Dof::ALL.into_iter().filter(|d| jt.is_free(*d)).collect();
        // force: what each DOF transmitted, with the law's parts of the free DOFs
        let mut force: Vec<String> = Dof::ALL
            .iter()
            .map(|d| format!("{own}{}/applied", d.name()))
            .collect();
        force.extend(
            free.iter()
                .map(|d| format!("{own}{}/force/elastic", d.name())),
        );
        // q of every DOF, and the stops of the free ones
        let mut q: Vec<String> = Dof::ALL
            .iter()
            .map(|d| format!("{own}{}/q", d.name()))
            .collect();
        q.extend(
            free.iter()
                .flat_map(|d| ["stop_min", "stop_max"].map(|s| format!("{own}{}/q/{s}", d.name()))),
        );
        let energy: Vec<String> = entities
            .iter()
            .filter(|e| e.starts_with(&format!("{own}energy/")))
            .map(|e| e.to_string())
            .collect();
        assert_eq!(energy.len(), 6, "{energy:?}");
        let force_views = all_in_one_view(force);
        let q_views = all_in_one_view(q);
        let energy_views = all_in_one_view(energy);
        println!(
            "{}: force {force_views:?}, q {q_views:?}, energy {energy_views:?}",
            j.name
        );
        assert_eq!(force_views.len(), 1, "{}", j.name);
        assert_eq!(q_views.len(), 1, "{}", j.name);
        assert_eq!(energy_views.len(), 1, "{}", j.name);
        // three different views, each in one unit family
        assert!(force_views[0] != q_views[0] && q_views[0] != energy_views[0]);
        assert!(force_views[0].contains("[N]") && energy_views[0].contains("[J]"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
