//! The scene's `break` table (docs/breakable.md §4): read in the scene's units, and its
//! errors name the file, the line and the field.

use rapier_kjoint::scene::{self, SceneError};
use rapier_kjoint::BreakCriterion;
use std::path::PathBuf;

const BASE: &str = r#"duration = 0.1

[[bodies]]
name = "ball"
shape = { type = "ball", radius = 0.1 }
mass = 1.0

[[joints]]
name = "j"
body1 = "world"
body2 = "ball"
property = { type = "spherical" }
break = { force = 1e4, moment = 500.0 }
"#;

mod common;

fn tmp_file(name: &str, text: &str) -> PathBuf {
    common::cli::temp_file("break-scene", name, text)
}

fn built_criterion(name: &str, text: &str) -> BreakCriterion {
    let (sc, src) = scene::load(&tmp_file(name, text)).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    let (_, j) = built.joints.iter().next().unwrap();
    *j.break_criterion().expect("a criterion")
}

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

#[track_caller]
fn check(e: &SceneError, file: &str, field: &str, message: &str) {
    assert!(e.file.ends_with(file), "file {}", e.file.display());
    assert_eq!(e.line, 13, "line of {e}");
    assert_eq!(e.field, field, "field of {e}");
    assert!(
        e.message.contains(message),
        "message of {e}: expected `{message}`"
    );
    assert!(
        e.to_string()
            .contains(&format!("{file}:13: field `{field}`: ")),
        "{e}"
    );
}

#[test]
fn the_break_table_is_read_in_the_scenes_units() {
    let c = built_criterion("si.toml", BASE);
    assert_eq!(c, BreakCriterion::force_and_moment(1e4, 500.0));
    // in "kg mm s": a force unit of kg·mm/s² = 1e-3 N, a moment (and an energy) of
    // 1e-3 N × 1e-3 m = 1e-6 N·m (J)
    let t = BASE
        .replace("duration = 0.1", "units = \"kg mm s\"\nduration = 0.1")
        .replace("radius = 0.1", "radius = 100.0")
        .replace(
            "{ force = 1e4, moment = 500.0 }",
            "{ force = 2.0, moment = 3.0, moment_exponent = 1.5, dissipated_energy = 7.0 }",
        );
    let c = built_criterion("mm.toml", &t);
    assert_eq!((c.force_exponent, c.moment_exponent), (2.0, 1.5));
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12 * b;
    assert!(close(c.force, 2e-3), "{c:?}");
    assert!(
        close(c.moment, 3e-6) && close(c.dissipated_energy, 7e-6),
        "{c:?}"
    );
}

#[test]
fn errors_name_the_field_of_the_break_table() {
    let bad = |name: &str, table: &str| {
        error(
            name,
            &BASE.replace("{ force = 1e4, moment = 500.0 }", table),
        )
    };
    check(
        &bad("neg.toml", "{ force = -1e4 }"),
        "neg.toml",
        "joints[0].break.force",
        "expected a finite limit ≥ 0",
    );
    check(
        &bad("nan.toml", "{ moment = nan }"),
        "nan.toml",
        "joints[0].break.moment",
        "expected a finite limit ≥ 0",
    );
    check(
        &bad("exp.toml", "{ force = 1.0, force_exponent = 0.0 }"),
        "exp.toml",
        "joints[0].break.force_exponent",
        "expected a finite exponent > 0",
    );
    check(
        &bad("energy.toml", "{ dissipated_energy = inf }"),
        "energy.toml",
        "joints[0].break.dissipated_energy",
        "expected a finite limit ≥ 0",
    );
    check(
        &bad("none.toml", "{}"),
        "none.toml",
        "joints[0].break.force",
        "at least one limit > 0",
    );
    check(
        &bad("unknown.toml", "{ force = 1.0, momnet = 2.0 }"),
        "unknown.toml",
        "joints[0].break.momnet",
        "unknown field `momnet`",
    );
}

/// Runs `kjoint run <scene> --quiet [extra]` on a bundled scene and returns its stdout
/// (the command must succeed).
fn run_scene(scene: &str, extra: &[&std::ffi::OsStr]) -> String {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    common::cli::kjoint_run(&root.join("assets/scenes").join(scene), None, extra)
}

/// The breaks a summary lists, in order: (joint, time \[s\]).
fn breaks(stdout: &str) -> Vec<(String, f64)> {
    stdout
        .lines()
        .filter(|l| l.contains("broke"))
        .map(|l| {
            let l = l.trim_start().strip_prefix("joint ").unwrap();
            let name = l.split(' ').next().unwrap().to_string();
            let t = l.split("t = ").nth(1).unwrap().split(' ').next().unwrap();
            (name, t.parse().unwrap())
        })
        .collect()
}

/// The summary's energy residual, in % of its energy scale.
fn residual_percent(stdout: &str) -> f64 {
    stdout
        .lines()
        .find(|l| l.trim_start().starts_with("residual"))
        .and_then(|l| l.split('(').nth(1))
        .and_then(|l| l.split(' ').next())
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn the_chain_pulled_apart_breaks_at_its_weakest_link() {
    // the pull grows as 1000·t N: link3 (300 N) breaks at t = 0.3 s (±1 substep of
    // 1/960 s), the others (500 N) hold; the summary and events.csv show it, and the
    // balance closes within 1 %
    let dir = common::cli::temp_dir("chain-apart");
    let stdout = run_scene(
        "chain_pulled_apart.toml",
        &["--csv".as_ref(), dir.as_os_str()],
    );
    let broke = breaks(&stdout);
    assert_eq!(broke.len(), 1, "{stdout}");
    assert_eq!(broke[0].0, "link3", "{stdout}");
    let t = broke[0].1;
    // ±1 substep of 1/960 s; the time is printed to 1e-6 s (the pull reaches 300 N exactly at
    // 0.3 s, so the round-off of the build decides between the two substeps around it)
    assert!((t - 0.3).abs() <= 1.0 / 960.0 + 1e-6, "broke at {t} s");
    let residual = residual_percent(&stdout);
    assert!(residual.abs() < 1.0, "residual {residual} %");
    let events = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    assert!(
        events
            .lines()
            .any(|l| l.contains("joint link3") && l.contains("broke")),
        "{events}"
    );
}

#[test]
fn a_robot_joint_override_takes_a_break_table() {
    let urdf = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/urdf/arm.urdf");
    let text = format!(
        "duration = 0.1\n\n[[robots]]\nurdf = {:?}\n[robots.options]\n\
         joints.elbow = {{ friction = 0.6, break = {{ force = 2000.0, moment = 150.0 }} }}\n",
        urdf.display().to_string()
    );
    let (sc, src) = scene::load(&tmp_file("robot.toml", &text)).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    let with: Vec<(&str, Option<BreakCriterion>)> = built
        .joints
        .iter()
        .map(|(_, j)| (j.name.as_str(), j.break_criterion().copied()))
        .collect();
    assert!(
        with.iter().any(|(n, c)| n.contains("elbow")
            && *c == Some(BreakCriterion::force_and_moment(2000.0, 150.0))),
        "{with:?}"
    );
    assert_eq!(
        with.iter().filter(|(_, c)| c.is_some()).count(),
        1,
        "{with:?}"
    );
}

#[test]
fn the_bolt_row_scene_fails_middle_left_right() {
    // assets/scenes/bolt_row.toml: the load 200·t N, shared F/3 by three bolts, then F/2 by
    // two: the middle bolt (20 N) at t = 0.3 s, the left (45 N) at 0.45 s (±1 substep of
    // 1/960 s; the times are printed to 1e-6 s), the right one (a pivot carrying
    // 0.64·F > 50 N) right after
    let stdout = run_scene("bolt_row.toml", &[]);
    let broke = breaks(&stdout);
    let names: Vec<&str> = broke.iter().map(|b| b.0.as_str()).collect();
    assert_eq!(names, ["middle", "left", "right"], "{stdout}");
    let h = 1.0 / 960.0;
    assert!((broke[0].1 - 0.3).abs() <= h + 1e-6, "{broke:?}");
    assert!((broke[1].1 - 0.45).abs() <= h + 1e-6, "{broke:?}");
    assert!(broke[2].1 - broke[1].1 <= 2.0 * h + 1e-6, "{broke:?}");
}

/// Found by fuzzing bolt_row.toml: with `kn = 1e300` on the middle bolt, its transmitted
/// force (Kn times f32 pose noise, components near 1e277) overflowed in its magnitude and
/// the run exited 0 printing `broke: transmitted force inf N`. The break's values saturate
/// at f64::MAX, as the law's do: the summary holds no infinity.
#[test]
fn a_break_on_an_overflowing_force_prints_no_infinity() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("assets/scenes/bolt_row.toml")).unwrap();
    let middle = "name = \"middle\"\nbody1 = \"world\"\nbody2 = \"plate\"\nproperty = { type = \
                  \"spherical\", kn = 1e6 }";
    assert!(text.contains(middle));
    let text = text.replace(middle, &middle.replace("1e6", "1e300"));
    let path = tmp_file("bolt_row_huge_kn.toml", &text);
    let stdout = common::cli::kjoint_run(&path, None, &["--duration", "0.05"]);
    let line = stdout
        .lines()
        .find(|l| l.contains("broke"))
        .expect("the middle bolt breaks");
    assert!(
        line.contains("joint middle") && line.contains("transmitted force 1.80e308 N"),
        "{line}"
    );
    let words = stdout.split(|c: char| !c.is_ascii_alphanumeric());
    assert!(
        !words.into_iter().any(|w| w == "inf" || w == "NaN"),
        "{stdout}"
    );
}

#[test]
fn the_door_is_torn_off_its_top_hinge_first() {
    // assets/scenes/door_torn_off.toml: a 20 kg door on two hinge pins 1.6 m apart, loaded
    // at its free edge (0.9 m from the hinge line) by P = 1000·t N. Each pin carries
    // V = (m·g + P)/2 and H = (0.45·m·g + 0.9·P)/1.6: the top pin (300 N) fails when
    // √(V² + H²) reaches 300 N (±1 substep of 1/960 s), the bottom pin (400 N) then carries
    // m·g + P ≈ 450 N alone and fails within 0.02 s; the balance closes within 1 %
    let mg = 20.0 * 9.81;
    let load = |p: f64| ((mg + p) / 2.0).hypot((0.45 * mg + 0.9 * p) / 1.6);
    let (mut lo, mut hi) = (0.0, 1000.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if load(mid) > 300.0 {
            hi = mid
        } else {
            lo = mid
        }
    }
    let t_top = lo / 1000.0; // 0.2542 s
    let stdout = run_scene("door_torn_off.toml", &[]);
    let broke = breaks(&stdout);
    let names: Vec<&str> = broke.iter().map(|b| b.0.as_str()).collect();
    assert_eq!(names, ["top", "bottom"], "{stdout}");
    let h = 1.0 / 960.0;
    assert!(
        (broke[0].1 - t_top).abs() <= h + 1e-6,
        "{broke:?} vs {t_top}"
    );
    // the bottom pin's load rises from its share as the door starts to swing about it: 3 to
    // 8 substeps later depending on the build's round-off (opt-level 0 or 1)
    assert!(
        broke[1].1 > broke[0].1 && broke[1].1 - broke[0].1 <= 0.02,
        "{broke:?}"
    );
    let residual = residual_percent(&stdout);
    assert!(residual.abs() < 1.0, "residual {residual} %");
    // the summary's peak |F| is the magnitude of the force the pin transmitted, as the
    // criterion reads it: at the last frame before the break (t = 0.25 s) √(V² + H²) =
    // 296.8 N, not its largest component V = 223 N (what the column showed)
    let peak = |name: &str| -> f64 {
        let row = stdout
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("no row for {name}: {stdout}"));
        row.split_whitespace().nth(1).unwrap().parse().unwrap()
    };
    // and it includes the substep each pin broke in: the force its event reports
    let broke_at = |name: &str| -> f64 {
        let line = stdout
            .lines()
            .find(|l| l.contains(&format!("joint {name} at")) && l.contains("broke"))
            .unwrap();
        line.split("transmitted force ")
            .nth(1)
            .unwrap()
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    for name in ["top", "bottom"] {
        let (f, at_break) = (peak(name), broke_at(name));
        assert_eq!(f, at_break, "{name}: peak |F| {f} N, broke at {at_break} N");
    }
    assert!(broke_at("top") > load(250.0));
    // the header counts the joints of the run, both removed
    assert!(
        stdout.contains("16 substeps each, 2 joints (2 removed)"),
        "{stdout}"
    );
}

/// The summary reads every substep, whatever the logging rate: a frame of 16 substeps
/// (the default `log = "frame"`) hid the peak of a stop hit, and a joint's slip, within it
/// (the URDF arm's shoulder read 179.8 N where it transmitted 695.2 N).
#[test]
fn the_summary_does_not_depend_on_the_logging_rate() {
    for scene in ["urdf_arm.toml", "bolt_row.toml"] {
        let table = |extra: &[&std::ffi::OsStr]| -> String {
            let out = run_scene(scene, extra);
            out.lines()
                .skip_while(|l| !l.starts_with("joint "))
                .take_while(|l| !l.is_empty())
                .collect::<Vec<_>>()
                .join("\n")
        };
        let by_frame = table(&[]);
        let by_substep = table(&["--log".as_ref(), "substep".as_ref()]);
        assert!(by_frame.lines().count() >= 5, "{by_frame}");
        assert_eq!(by_frame, by_substep, "{scene}");
    }
}

/// A broken joint's history ends with the substep it broke in: the row the summary's
/// `peak |F|` and the break event read. The CSV used to stop one substep before (the door's
/// bottom pin: 351.2 N in its history, 409.0 N in the summary and the event; the middle bolt
/// 19.99 N in its history for a 20 N limit), and its energies then missed that substep's.
#[test]
fn a_broken_joints_history_ends_with_the_force_that_broke_it() {
    for (scene, log) in [
        ("door_torn_off.toml", "frame"),
        ("door_torn_off.toml", "substep"),
        ("bolt_row.toml", "substep"),
    ] {
        let dir = common::cli::fresh_temp_dir(&format!("broken-history-{log}"));
        let stdout = run_scene(
            scene,
            &[
                "--csv".as_ref(),
                dir.as_os_str(),
                "--log".as_ref(),
                log.as_ref(),
            ],
        );
        for line in stdout.lines().filter(|l| l.contains(": broke: ")) {
            let l = line.trim_start().strip_prefix("joint ").unwrap();
            let name = l.split(' ').next().unwrap();
            // the number after `marker` in the event's line
            let after = |marker: &str| -> f64 {
                let rest = l.split(marker).nth(1).unwrap();
                rest.split(' ').next().unwrap().parse().unwrap()
            };
            let (t, force) = (after("t = "), after("transmitted force "));
            let text = std::fs::read_to_string(dir.join(format!("{name}.csv"))).unwrap();
            let head: Vec<&str> = text.lines().next().unwrap().split(',').collect();
            let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
            let last: Vec<f64> = text
                .lines()
                .last()
                .unwrap()
                .split(',')
                .map(|v| v.parse().unwrap())
                .collect();
            let af =
                (last[col("AFX")].powi(2) + last[col("AFY")].powi(2) + last[col("AFZ")].powi(2))
                    .sqrt();
            assert!(
                (last[col("time")] - t).abs() < 1e-6,
                "{scene} {log} {name}: last row at {} s, broke at {t} s",
                last[col("time")]
            );
            assert!(
                (af - force).abs() <= 5e-4 * force,
                "{scene} {log} {name}: last row transmits {af} N, broke at {force} N"
            );
            let times: Vec<&str> = text
                .lines()
                .skip(1)
                .map(|l| l.split(',').next().unwrap())
                .collect();
            let mut unique = times.clone();
            unique.dedup();
            assert_eq!(
                unique.len(),
                times.len(),
                "{scene} {log} {name}: a row twice"
            );
        }
    }
}
