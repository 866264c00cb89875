//! Every scene of `assets/scenes/` run from the command line (`kjoint run SCENE --csv DIR
//! --quiet`), its CSV histories read back and checked against what the scene is about.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

mod common;

fn tmp(name: &str) -> PathBuf {
    common::cli::fresh_temp_dir(&format!("scene-run-{name}"))
}

/// Runs `kjoint run SCENE --csv DIR --quiet ARGS`; returns the CSV directory and stdout.
fn run(scene: &Path, name: &str, args: &[&str]) -> (PathBuf, String) {
    let dir = tmp(name);
    let stdout = common::cli::kjoint_run(scene, Some(&dir), args);
    (dir, stdout)
}

fn scene(name: &str) -> PathBuf {
    root().join("assets/scenes").join(format!("{name}.toml"))
}

/// The summary's "work of loads and motions" \[J\].
fn load_work(stdout: &str) -> f64 {
    stdout
        .split("work of loads and motions ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .unwrap_or_else(|| panic!("{stdout}"))
        .parse()
        .unwrap()
}

/// The percentages of the summaries' `residual` lines (of the energy balance), in order.
fn residuals(stdout: &str) -> Vec<f64> {
    stdout
        .lines()
        .filter(|l| l.starts_with("  residual "))
        .map(|l| {
            let pct = l
                .split('(')
                .nth(1)
                .and_then(|p| p.split_whitespace().next());
            pct.unwrap_or_else(|| panic!("{l}")).parse().unwrap()
        })
        .collect()
}

/// A CSV file as columns.
struct Table {
    cols: HashMap<String, Vec<f64>>,
}

impl Table {
    fn read(path: &Path) -> Table {
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut lines = text.lines();
        let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
        let mut cols: HashMap<String, Vec<f64>> =
            header.iter().map(|h| (h.clone(), Vec::new())).collect();
        for l in lines {
            for (h, v) in header.iter().zip(l.split(',')) {
                cols.get_mut(h).unwrap().push(v.parse().unwrap());
            }
        }
        Table { cols }
    }
    fn col(&self, c: &str) -> &[f64] {
        self.cols.get(c).unwrap_or_else(|| panic!("no column {c}"))
    }
    fn max_abs(&self, c: &str) -> f64 {
        self.col(c).iter().fold(0.0, |a, v| a.max(v.abs()))
    }
    fn last(&self, c: &str) -> f64 {
        *self.col(c).last().unwrap()
    }
}

#[test]
fn header_has_the_radioss_columns_then_ours() {
    let h = rapier_kjoint::output::history::header();
    assert!(h.starts_with("time,FX,FY,FZ,MX,MY,MZ,LX,LY,LZ,RX,RY,RZ,IE,VX,VY,VZ,WX,WY,WZ,AFX,"));
    assert!(
        h.ends_with("locked,E_elastic,E_kinetic,E_damping,E_friction,E_stop,E_numerical,E_motor")
    );
    assert!(h.contains(",stop_FX,") && h.contains(",contact_FX,"));
    assert!(h.contains(",sensor_MZ,motor_FX,"));
    assert_eq!(
        h.split(',').count(),
        1 + 6 + 6 + 1 + 6 + 6 + 36 + 6 + 6 + 1 + 7
    );
}

#[test]
fn seed_revolute_stop_holds_the_rod() {
    let (dir, out) = run(&scene("seed_revolute_stop"), "seed-rev", &[]);
    assert!(out.contains("hinge"), "{out}");
    let t = Table::read(&dir.join("hinge.csv"));
    let rx = t.col("RX");
    let stop = t.col("contact_MX");
    // The stop at SA+ = 0.52 rad (from the deck) is reached and holds the rod, driven by up
    // to 20 N·m, within 0.03 rad; without it the torque would spin the rod round.
    assert!(stop.contains(&1.0), "the stop is never reached");
    let max = rx.iter().cloned().fold(f64::MIN, f64::max);
    assert!(max > 0.52 && max < 0.55, "peak angle {max}");
    // Over the last 0.5 s it stays at the stop...
    let time = t.col("time");
    let late: Vec<usize> = (0..time.len()).filter(|&i| time[i] > 1.5).collect();
    for &i in &late {
        assert!(
            rx[i] > 0.45 && rx[i] < 0.55,
            "t = {}: rx = {}",
            time[i],
            rx[i]
        );
    }
    // ...and carries on average the torque minus the gravity moment: 20 − 4.905·sin(0.52).
    let mean: f64 = late.iter().map(|&i| t.col("MX")[i]).sum::<f64>() / late.len() as f64;
    let expected = 20.0 - 4.905 * 0.52f64.sin();
    assert!(
        (mean - expected).abs() < 0.2 * expected,
        "mean moment {mean} vs {expected}"
    );
    // No friction (Kf = 0 in the deck).
    assert_eq!(t.max_abs("slip_MX"), 0.0);
    // The blocked translations stay small: the automatic stiffness is stiff.
    assert!(t.max_abs("LX").max(t.max_abs("LY")).max(t.max_abs("LZ")) < 0.01);
}

/// A stop only pushes: at every substep the moment the seed's hinge transmits about its free
/// axis (its only law there is the stop at SA+) pushes the rod back from SA+ or is zero. The
/// rod bounces on the stop's spring (the Radioss rule's stiffness, which the substep
/// resolves, with 5 % critical damping); the stop held after a contact pulled the rebounding
/// rod back with −14.2 N·m in the substep it left.
#[test]
fn a_stop_never_pulls() {
    let (dir, _) = run(
        &scene("seed_revolute_stop"),
        "seed-rev-substeps",
        &["--log", "substep"],
    );
    let t = Table::read(&dir.join("hinge.csv"));
    let amx = t.col("AMX");
    let (time, rx) = (t.col("time"), t.col("RX"));
    let peak = amx.iter().cloned().fold(0.0, f64::max);
    assert!(peak > 50.0, "the rod hits the stop: {peak} N·m");
    for i in 0..amx.len() {
        assert!(
            amx[i] > -1e-6 * peak,
            "t = {}: rx = {}, transmitted {} N·m",
            time[i],
            rx[i],
            amx[i]
        );
    }
}

#[test]
fn seed_translational_stops_hold_the_block() {
    let (dir, _) = run(&scene("seed_translational_stops"), "seed-tr", &[]);
    let t = Table::read(&dir.join("slider.csv"));
    let lx = t.col("LX");
    let stop = t.col("contact_FX");
    // SD- = -100 mm, SD+ = 100 mm from the deck (kg-mm-ms → m); the stop stiffness is
    // Kf = 1e9 N/m. The force first drives the block into SD-.
    let first = stop
        .iter()
        .position(|s| *s != 0.0)
        .expect("a stop is reached");
    assert_eq!(stop[first], -1.0);
    let t_first = t.col("time")[first];
    // Free motion of the 1 kg block under −50·sin(2πt): x = (50/2π)(sin(2πt)/2π − t)
    // reaches −0.1 m at t_c ≈ 0.1254 s; the history is written once per frame (1/60 s) with
    // the status of the frame's last substep, which may fall in a rebound off the stop.
    let x = |t: f64| {
        let w = 2.0 * std::f64::consts::PI;
        50.0 / w * ((w * t).sin() / w - t)
    };
    let (mut lo, mut hi) = (0.0, 0.3);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if x(mid) > -0.1 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    assert!(
        t_first >= lo - 1e-3 && t_first <= lo + 2.0 / 60.0 + 1e-3,
        "first contact at {t_first}, free motion reaches the stop at {lo}"
    );
    for (i, x) in lx.iter().enumerate() {
        assert!(
            *x >= -0.1 - 2e-3 && *x <= 0.1 + 2e-3,
            "t = {}: LX = {x} beyond the stops",
            t.col("time")[i]
        );
    }
    // Inside the stops there is no force along dx at all (no spring, no friction).
    for (s, f) in stop.iter().zip(t.col("FX")) {
        if *s == 0.0 {
            assert!(f.abs() < 1e-9, "FX = {f}");
        }
    }
    // The stop's damper (Cr = 0.2 of a 1e9 N/m stop) books no more than the joint
    // dissipated at any frame, the rest being the update's numerical work on the impacts it
    // cannot resolve (≥ 0 here): with the critical damping also booked over the substep
    // before each contact, `E_stop` read 47.1 J of the 16.1 J dissipated at the end and
    // `E_numerical` −31.1 J (measured: 11.7 and 4.4 J now).
    let (e_stop, e_num) = (t.col("E_stop"), t.col("E_numerical"));
    let dissipated = |i: usize| e_stop[i] + e_num[i] + t.col("E_damping")[i];
    let end = e_stop.len() - 1;
    assert!(dissipated(end) > 15.0, "{}", dissipated(end));
    for i in 0..=end {
        assert!(
            e_stop[i] <= dissipated(i) + 1e-3 && e_num[i] >= -1e-3,
            "t = {}: E_stop {} J, E_numerical {} J",
            t.col("time")[i],
            e_stop[i],
            e_num[i]
        );
    }
}

#[test]
fn translational_friction_sticks_then_slips() {
    let (dir, out) = run(&scene("translational"), "tr-friction", &[]);
    let t = Table::read(&dir.join("translational.csv"));
    let (time, lx, slip) = (t.col("time"), t.col("LX"), t.col("slip_FX"));
    // Force 10·t N against friction FF = 5 N with Kf = 1e4 N/m: sticks until t = 0.5 s with
    // the friction spring stretched by F/Kf (≤ 0.5 mm), then slips.
    for i in 0..time.len() {
        if time[i] < 0.45 {
            assert_eq!(slip[i], 1.0, "t = {}: not sticking", time[i]);
            let f = 10.0 * time[i];
            assert!(
                (lx[i] - f / 1e4).abs() < 1e-4,
                "t = {}: LX = {} vs {}",
                time[i],
                lx[i],
                f / 1e4
            );
            assert!(lx[i].abs() <= 5.0 / 1e4);
        }
    }
    let first_slip = slip.iter().position(|s| *s == 2.0).expect("never slips");
    assert!(
        (time[first_slip] - 0.5).abs() < 0.03,
        "slips at {}",
        time[first_slip]
    );
    // Sliding: m·a = 10t − 5, x = FF/Kf + (5/3)(t − 0.5)³ = 0.2088 m at t = 1 s.
    let expected = 5.0 / 1e4 + 5.0 / 3.0 * 0.5f64.powi(3);
    assert!(
        (t.last("LX") - expected).abs() < 0.03 * expected,
        "LX(1) = {}",
        t.last("LX")
    );
    // Friction force at its cap while slipping; work dissipated FF·slip.
    assert!((t.last("friction_FX").abs() - 5.0).abs() < 1e-6);
    assert!((t.last("E_friction") - 5.0 * (expected - 5e-4)).abs() < 0.05 * 5.0 * expected);
    // Blocked dy under gravity: 9.81 N / Kn = 1e6 N/m, twice that at most dynamically.
    assert!(
        t.max_abs("LY") <= 2.0 * 9.81 / 1e6,
        "LY {}",
        t.max_abs("LY")
    );
    assert!(
        out.contains("\nenergy balance ") && out.contains("\n  residual "),
        "{out}"
    );
}

/// The scenes of the nine types: a ball pushed along and about every axis.
#[test]
fn every_joint_type_frees_and_blocks_its_dofs() {
    use rapier_kjoint::JointType::*;
    let norm = |v: &[f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    for jt in [
        Spherical,
        Revolute,
        Cylindrical,
        Planar,
        Universal,
        Translational,
        Oldham,
        Fixed,
        Free,
    ] {
        // Loads, Kn and KR = Kn·ScF (default ScF = 10) of the scene, and its duration. The
        // translational scene is the friction one: 10 N along x at the end plus gravity.
        let (force, torque, kn, duration) = if jt == Translational {
            ([10.0f64, -9.81, 0.0], [0.0f64; 3], 1e6, "1.0")
        } else {
            ([1.0f64, 0.5, -0.8], [0.01f64, -0.008, 0.006], 1e3, "0.5")
        };
        let kr = 10.0 * kn;
        let name = jt.name();
        let (dir, _) = run(&scene(name), name, &["--duration", duration]);
        let t = Table::read(&dir.join(format!("{name}.csv")));
        let end: f64 = duration.parse().unwrap();
        assert!(
            (t.last("time") - end).abs() < 0.02,
            "{name}: ends at {}",
            t.last("time")
        );
        let cols = ["LX", "LY", "LZ", "RX", "RY", "RZ"];
        let fcols = ["FX", "FY", "FZ", "MX", "MY", "MZ"];
        // Largest lever arm between the anchors (free translations move them apart).
        let lever = (0..t.col("LX").len())
            .map(|i| {
                (t.col("LX")[i].powi(2) + t.col("LY")[i].powi(2) + t.col("LZ")[i].powi(2)).sqrt()
            })
            .fold(0.0, f64::max);
        for (i, free) in jt.free_dofs().iter().enumerate() {
            let q = t.max_abs(cols[i]);
            if *free {
                // Free and unloaded by the joint: moves like the bare body (≥ 1 cm / 0.01 rad
                // in 0.5 s under these loads).
                assert!(q > 0.01, "{name}: free {} moved only {q}", cols[i]);
                assert_eq!(t.max_abs(&format!("elastic_{}", fcols[i])), 0.0, "{name}");
            } else {
                // Blocked: at most twice the static deflection under the whole load (step
                // load), the moment including the couple of the force over the lever.
                // Plus 2e-7 for the f32 poses of rapier.
                let tol = 2e-7
                    + if i < 3 {
                        2.2 * norm(&force) / kn
                    } else {
                        2.2 * (norm(&torque) + lever * norm(&force)) / kr
                    };
                assert!(q <= tol, "{name}: blocked {} = {q} > {tol}", cols[i]);
                // The penalty force is the blocked stiffness times the displacement.
                let k = if i < 3 { kn } else { kr };
                let (e, qc) = (t.col(&format!("elastic_{}", fcols[i])), t.col(cols[i]));
                for r in 0..e.len() {
                    assert!(
                        (e[r] - k * qc[r]).abs() <= 1e-6 * k * qc[r].abs() + 1e-12,
                        "{name}: {} elastic {} vs K·q {}",
                        fcols[i],
                        e[r],
                        k * qc[r]
                    );
                }
            }
        }
    }
}

#[test]
fn demo_runs_without_arguments() {
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .current_dir(std::env::temp_dir())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("5.0000 s simulated"), "{stdout}");
    // then the URDF arm
    assert!(stdout.contains("3.0000 s simulated"), "{stdout}");
    for joint in ["hinge", "slider", "shoulder", "elbow", "wrist"] {
        assert!(stdout.lines().any(|l| l.starts_with(joint)), "{stdout}");
    }
    // Both residual lines (the demo's, the arm's) report a percentage below 1 %.
    let pct = residuals(&stdout);
    assert_eq!(pct.len(), 2, "{stdout}");
    assert!(pct.iter().all(|p| p.abs() < 1.0), "{pct:?}");
    // the first thing a user runs warns of nothing: its stops hold (overruns within the
    // health bounds), its joints keep their anchors
    assert!(!stdout.contains("warning"), "{stdout}");
}

#[test]
fn demo_scene_hits_both_stops_and_slips() {
    let (dir, _) = run(&scene("demo"), "demo", &["--duration", "2"]);
    let hinge = Table::read(&dir.join("hinge.csv"));
    // Launched at 2 rad/s about the hinge: ½·(1/3)·2² = 0.667 J lifts it past 0.3 rad.
    assert!(hinge.col("contact_MX").contains(&1.0));
    let max = hinge.col("RX").iter().cloned().fold(f64::MIN, f64::max);
    assert!(max > 0.3 && max < 0.5, "peak {max}");
    let slider = Table::read(&dir.join("slider.csv"));
    // Down the 30° slope: 9.81 N > FF = 5 N, into the stop at 0.5 m, where it rests:
    // (m·g·sin30° − FF... the friction spring) within (9.81 N)/(Kf = 1e5 N/m) ≈ 0.1 mm.
    assert!(slider.col("slip_FX").contains(&2.0));
    assert!(slider.col("contact_FX").contains(&1.0));
    assert!(
        (slider.last("LX") - 0.5).abs() < 2e-3,
        "LX = {}",
        slider.last("LX")
    );
}

/// The histories' numbers: status codes and flags as integers (`2`, `-1`; they read
/// `2e0`, `-1e0`), every other value in the shortest form that reads back as the same
/// `f64`, in plain notation where Rust's `{:?}` uses it (`0.015624999999999998`, not
/// `1.5624999999999998e-2`; `1e-300` stays). The column set is unchanged.
#[test]
fn histories_write_codes_as_integers_and_reals_in_full() {
    let (dir, _) = run(&scene("demo"), "demo-numbers", &["--duration", "2"]);
    for joint in ["hinge", "slider"] {
        let text = std::fs::read_to_string(dir.join(format!("{joint}.csv"))).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(header.join(","), rapier_kjoint::output::history::header());
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert!(rows.len() > 100);
        for (k, name) in header.iter().enumerate() {
            let code =
                name.starts_with("slip_") || name.starts_with("contact_") || *name == "locked";
            for row in &rows {
                let text = row[k];
                let v: f64 = text.parse().unwrap();
                // the shortest text of the same f64, without a trailing `.0`
                let shortest = format!("{v:?}");
                assert_eq!(
                    text,
                    shortest.strip_suffix(".0").unwrap_or(&shortest),
                    "{name}"
                );
                if code {
                    assert!(["-1", "0", "1", "2"].contains(&text), "{name} = {text}");
                }
            }
        }
        // the codes the demo reaches: the hinge in its stop, the slider slipping
        let col = |name: &str| {
            let k = header.iter().position(|h| *h == name).unwrap();
            rows.iter().map(|r| r[k]).collect::<Vec<_>>()
        };
        let (column, code) = match joint {
            "hinge" => ("contact_MX", "1"),
            _ => ("slip_FX", "2"),
        };
        assert!(col(column).contains(&code), "{joint}: {:?}", col(column));
        // the first row's time, the start of the last substep of the first frame (15/960 s
        // summed in 15 substeps), in full: it read `1.5624999999999998e-2`
        assert_eq!(col("time")[0], "0.015624999999999998");
    }
}

#[test]
fn json_scene_gives_the_same_history_as_toml() {
    let path = scene("translational");
    let (sc, _) = rapier_kjoint::scene::load(&path).unwrap();
    let dir = tmp("json-src");
    let json = dir.join("translational.json");
    std::fs::write(&json, serde_json::to_string_pretty(&sc).unwrap()).unwrap();
    let (a, _) = run(&path, "json-a", &["--duration", "0.3"]);
    let (b, _) = run(&json, "json-b", &["--duration", "0.3"]);
    let ta = std::fs::read_to_string(a.join("translational.csv")).unwrap();
    let tb = std::fs::read_to_string(b.join("translational.csv")).unwrap();
    assert!(ta.lines().count() > 10);
    assert_eq!(ta, tb);
}

#[test]
fn per_substep_log_writes_every_substep() {
    let (dir, _) = run(
        &scene("translational"),
        "substep",
        &["--duration", "0.1", "--log", "substep", "--substeps", "4"],
    );
    let t = Table::read(&dir.join("translational.csv"));
    // 6 frames × 4 substeps, each row one substep (1/240 s) apart.
    assert_eq!(t.col("time").len(), 24);
    let dt = t.col("time")[1] - t.col("time")[0];
    assert!((dt - 1.0 / 240.0).abs() < 1e-9, "{dt}");
}

#[test]
fn rrd_without_the_feature_is_a_clear_error() {
    if cfg!(feature = "rerun") {
        return;
    }
    // with `--csv` beside it: refused before its directory is made
    let csv = tmp("rrd-refused").join("csv");
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .args(["run"])
        .arg(scene("fixed"))
        .args(["--rrd", "/tmp/x.rrd", "--quiet", "--csv"])
        .arg(&csv)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("built without the `rerun` feature; rebuild with --features rerun"),
        "{err}"
    );
    assert!(!csv.exists(), "{}", csv.display());
}

/// Seed example 2 at 64 substeps: the 1e9 N/m stop with Cr = 0.2 used to gain energy at
/// each impact (velocities of hundreds of m/s under a 50 N load) before unresolved DOFs
/// were damped in the implicit update; it must stay bounded at every substep count.
#[test]
fn seed_translational_stops_are_stable_at_64_substeps() {
    let (dir, _) = run(
        &scene("seed_translational_stops"),
        "seed-tr-64",
        &["--substeps", "64"],
    );
    let t = Table::read(&dir.join("slider.csv"));
    assert!(t.max_abs("VX") < 20.0, "max |VX| = {}", t.max_abs("VX"));
    assert!(
        t.max_abs("LX") < 0.1 + 2e-3,
        "max |LX| = {}",
        t.max_abs("LX")
    );
}

fn write_scene(name: &str, text: &str) -> PathBuf {
    let dir = tmp(&format!("src-{name}"));
    let p = dir.join(format!("{name}.toml"));
    std::fs::write(&p, text).unwrap();
    p
}

/// The translational scene written in kg-mm-ms gives the same history as in SI.
#[test]
fn scene_in_kg_mm_ms_matches_si() {
    let mm = write_scene(
        "mm",
        r#"units = "kg mm ms"
dt = 16.666666666666666        # [ms]
substeps = 16
duration = 1000.0              # [ms]
gravity = [0.0, -9.81e-3, 0.0] # [mm/ms²]

[[bodies]]
name = "block"
shape = { type = "cuboid", half_extents = [50.0, 50.0, 50.0] }  # [mm]
mass = 1.0                                                      # [kg]

[[joints]]
name = "translational"
body1 = "world"
body2 = "block"
[joints.property]
type = "translational"
kn = 1.0                                                # [kg/ms²] = 1e6 N/m
dx = { friction_stiffness = 0.01, friction = 0.005 }    # 1e4 N/m, 5 N

[[loads]]
body = "block"
force = [0.01, 0.0, 0.0]                          # [kg·mm/ms²] = 10 N
function = { curve = [[0.0, 0.0], [1000.0, 1.0]] }  # t [ms]
"#,
    );
    let (a, _) = run(&scene("translational"), "si", &[]);
    let (b, _) = run(&mm, "mm", &[]);
    let ta = Table::read(&a.join("translational.csv"));
    let tb = Table::read(&b.join("translational.csv"));
    assert_eq!(ta.col("time").len(), tb.col("time").len());
    for c in ["time", "LX", "FX", "friction_FX", "LY", "E_friction"] {
        let (x, y) = (ta.last(c), tb.last(c));
        assert!(
            (x - y).abs() <= 1e-6 * x.abs().max(1e-9),
            "{c}: SI {x} vs kg-mm-ms {y}"
        );
    }
    assert!(ta.last("LX") > 0.2, "{}", ta.last("LX"));
}

/// A time sensor locks the joint: the free DOFs stop where they were at activation.
#[test]
fn time_sensor_locks_a_free_joint() {
    let text = std::fs::read_to_string(scene("free")).unwrap().replace(
        "property = { type = \"free\", kn = 1e3 }",
        "property = { type = \"free\", kn = 1e3, sensor = 1 }",
    ) + "\n[[sensors]]\nid = 1\ntime = 0.25\n";
    let p = write_scene("sensor", &text);
    let (dir, out) = run(&p, "sensor", &["--duration", "0.5"]);
    assert!(out.contains("sensor 1 at t = 0.25"), "{out}");
    let t = Table::read(&dir.join("free.csv"));
    let time = t.col("time");
    let at = time.iter().position(|x| *x >= 0.25).unwrap();
    assert_eq!(t.col("locked")[at - 1], 0.0);
    assert_eq!(t.last("locked"), 1.0);
    // Before the lock dx moves freely (a = 1 m/s²: 0.031 m at 0.25 s); after it, the lock
    // spring Kn = 1e3 N/m (1 kg) holds it within the overshoot v/ω + 2·|F|/Kn of the value at
    // activation (ω = √(Kn/m)), while it would otherwise travel 0.094 m further.
    let lx = t.col("LX");
    assert!((lx[at] - 0.5 * 0.25f64.powi(2)).abs() < 0.005, "{}", lx[at]);
    let bound = t.col("VX")[at].abs() / 1e3f64.sqrt() + 2.0 * 1.375 / 1e3;
    assert!(bound < 0.012, "{bound}");
    for i in at..lx.len() {
        assert!(
            (lx[i] - lx[at]).abs() < bound,
            "t = {}: {} vs {}",
            time[i],
            lx[i],
            lx[at]
        );
    }
    assert!(t.max_abs("sensor_FX") > 1.0, "the lock spring acts");
    let events = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    let fired: f64 = events
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((fired - 0.25).abs() < 1e-9, "{events}");
}

/// Rows of a table as `(column → value)` lookups, for the connector scenes.
fn rows(t: &Table) -> Vec<HashMap<&str, f64>> {
    let n = t.col("time").len();
    (0..n)
        .map(|i| t.cols.iter().map(|(k, v)| (k.as_str(), v[i])).collect())
        .collect()
}

#[test]
fn planar_friction_block_slides_at_mu_times_its_varying_normal_force() {
    let (dir, stdout) = run(&scene("planar_friction_block"), "pf_block", &[]);
    let t = Table::read(&dir.join("contact.csv"));
    // The scene: N(t) = m·g + 100·(1 + 0.5·sin(π t)) N pressing the block on the plate, a
    // pull of 90·min(t/2, 1) N at the centre of mass h = 0.1 m above the contact, μ = 0.3,
    // R = 0.1 m. The joint carries the tipping moment |f|·h, so F_N = N + |f|·h/R.
    let (mu, h, r) = (0.3, 0.1, 0.1);
    let normal = |t: f64| 10.0 * 9.81 + 100.0 * (1.0 + 0.5 * (std::f64::consts::PI * t).sin());
    let pull = |t: f64| 90.0 * (t / 2.0).min(1.0);
    let mut first_slip = None;
    let mut restick = false;
    let mut slides = 0;
    for row in rows(&t) {
        let time = row["time"];
        let f_n = row["planar_friction.normal_force"];
        let f = row["planar_friction.friction_y"].hypot(row["planar_friction.friction_z"]);
        let sliding = row["planar_friction.sliding"] == 2.0;
        if sliding {
            slides += 1;
            first_slip.get_or_insert(time);
            // the sliding threshold is μ·F_N (1 %)
            assert!(
                (f - mu * f_n).abs() <= 0.01 * mu * f_n,
                "t = {time}: |f| = {f}, F_N = {f_n}"
            );
            // F_N is built from the joint's own normal force and tipping moment. 3 %: the
            // penalty normal force K·q of the automatic stiffness (~1e7 N/m) reads rapier's
            // f32 positions, whose resolution 0.5 µm at 4 m from the origin is ~5 N; the
            // error stays below 1 % over the first 2 m of travel.
            let expected = normal(time) + f * h / r;
            let tol = if row["LY"].abs() < 2.0 { 0.01 } else { 0.03 };
            assert!(
                (f_n - expected).abs() <= tol * expected,
                "t = {time}: F_N = {f_n}, N + |f|·h/R = {expected}"
            );
        } else {
            assert!(
                f <= mu * f_n * (1.0 + 1e-9),
                "t = {time}: sticking beyond the cap"
            );
            restick |= first_slip.is_some();
        }
    }
    // First slip where the pull reaches μ·N/(1 − μ·h/R) (analytic, 1.4240 s), within a frame.
    let mut onset = 0.0;
    while pull(onset) < mu * normal(onset) / (1.0 - mu * h / r) {
        onset += 1e-5;
    }
    let first = first_slip.expect("the block slides");
    assert!(
        (first - onset).abs() <= 1.0 / 60.0,
        "first slip at {first} s, analytic {onset} s"
    );
    assert!(restick, "the block sticks again when the normal load rises");
    assert!(slides > 100, "{slides} sliding records");
    assert!(
        t.last("planar_friction.slip_total") > 1.0,
        "the block has slid"
    );
    assert!(
        stdout.contains("\nenergy balance ") && stdout.contains("\n  residual "),
        "{stdout}"
    );
}

#[test]
fn riser_flexjoint_follows_the_static_law_then_closes_hysteresis_loops() {
    let (dir, stdout) = run(&scene("riser_flexjoint"), "riser", &[]);
    // (it switched at 4 s: no note that it did not)
    assert!(!stdout.contains("did not come within the run"), "{stdout}");
    let t = Table::read(&dir.join("flexjoint.csv"));
    let rows = rows(&t);
    // Quasi-static phase, just before the switch at 4 s: the joint moment is the *SPRINGPRO 3
    // table at the angle (first segment, 25000 N·m per 0.00872665 rad), and balances the
    // 5 kN current at the centre of mass 5 m down against gravity (2 t):
    // M(θ) = F·5·cos θ − m·g·5·sin θ.
    let before = rows.iter().rfind(|r| r["time"] < 4.0 - 1e-9).unwrap();
    let theta = before["flex_joint.bending_angle"];
    let m = before["flex_joint.bending_moment_z"].hypot(before["flex_joint.bending_moment_y"]);
    assert_eq!(before["flex_joint.phase"], 0.0);
    let table = 25000.0 / 0.00872665 * theta;
    assert!(
        (m - table).abs() <= 1e-6 * table,
        "M = {m} vs table {table}"
    );
    // The balance over the last second before the switch, not at one record: the
    // pendulum-flex mode (1.1 Hz, 5 % damped) still rings from the ramp, by ±3 % about it
    // (a riser engineer's trial, 2026-12-04: the test read the one record where it was
    // 0.1 % off); the mean over the second balances within 1 %.
    let relative = |r: &HashMap<&str, f64>| {
        let theta = r["flex_joint.bending_angle"];
        let m = r["flex_joint.bending_moment_z"].hypot(r["flex_joint.bending_moment_y"]);
        let balance = 5000.0 * 5.0 * theta.cos() - 2000.0 * 9.81 * 5.0 * theta.sin();
        m / balance - 1.0
    };
    let last_second: Vec<f64> = rows
        .iter()
        .filter(|r| r["time"] >= 3.0 && r["time"] < 4.0 - 1e-9)
        .map(relative)
        .collect();
    assert_eq!(last_second.len(), 60);
    let mean = last_second.iter().sum::<f64>() / 60.0;
    let swing = last_second.iter().fold(0.0_f64, |a, r| a.max(r.abs()));
    assert!(
        mean.abs() < 0.01,
        "M balances the loads within {mean} on average"
    );
    assert!(swing < 0.04, "M rings about the balance by {swing}");
    // The switch is an event at 4 s, logged once.
    let events = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    let lines: Vec<&str> = events.lines().skip(1).collect();
    assert_eq!(lines.len(), 1, "{events}");
    assert!(lines[0].contains("\"joint flexjoint\"") && lines[0].contains("dynamic phase"));
    let at: f64 = lines[0].split(',').next().unwrap().parse().unwrap();
    assert!((at - 4.0).abs() < 1e-9, "{events}");
    // Second load cycle (9 – 14 s): the dissipated hysteresis energy equals the loop area
    // 4·φy·(a − φy)·(Kdyn_ini − Kdyn_lim) of the law at the amplitude a the run reached
    // (2 %), a about three times the critical angle φy.
    let (phi_y, k_ini, k_lim) = (1.74533e-3, 4.0107e6, 1.718873e6);
    let cycle: Vec<_> = rows
        .iter()
        .filter(|r| r["time"] >= 9.0 - 1e-9 && r["time"] <= 14.0)
        .collect();
    let (lo, hi) = cycle.iter().fold((f64::MAX, f64::MIN), |(lo, hi), r| {
        (lo.min(r["RZ"]), hi.max(r["RZ"]))
    });
    let a = 0.5 * (hi - lo);
    assert!(
        (2.5..4.0).contains(&(a / phi_y)),
        "amplitude {} φy",
        a / phi_y
    );
    let dissipated = cycle.last().unwrap()["flex_joint.dissipated_hysteresis"]
        - cycle[0]["flex_joint.dissipated_hysteresis"];
    let area = 4.0 * phi_y * (a - phi_y) * (k_ini - k_lim);
    assert!(
        (dissipated - area).abs() <= 0.02 * area,
        "dissipated {dissipated} J vs loop area {area} J"
    );
    // The hysteresis is the joint's friction energy (nothing else dissipates by friction).
    assert!(
        (t.last("E_friction") - t.last("flex_joint.dissipated_hysteresis")).abs() < 1e-9,
        "E_friction = hysteresis"
    );
    // The bending plane and the hysteretic law's state (a riser engineer's trial,
    // 2026-12-04: the CSV had neither). The current pushes along world x, the joint's y
    // (its x is the riser axis, world −y): the riser tilts towards joint y, bending about z.
    let f = |r: &HashMap<&str, f64>, k: &str| r[format!("flex_joint.{k}").as_str()];
    for r in rows.iter().filter(|r| f(r, "bending_angle") > 1e-6) {
        let tilt = (f(r, "tilt_y"), f(r, "tilt_z"));
        assert!(
            (tilt.0 - 1.0).abs() < 1e-6 && tilt.1.abs() < 1e-6,
            "tilt {tilt:?} at {}",
            r["time"]
        );
    }
    // No plastic variation before the switch; after it, along z alone, with the back
    // moment `α = H·φp` (H = E·Kdyn_lim/(E − Kdyn_lim)), and wherever the law yields the
    // moment's variation from the switch `m = M − M_s` on the yield circle `|m − α| = My`
    // (`My = Kdyn_ini·φy`; M_s the moment of the last evaluation before the switch).
    let h = k_ini * k_lim / (k_ini - k_lim);
    let my = k_ini * phi_y;
    let m_s = f(before, "bending_moment_z");
    let mut yielding = 0;
    for r in &rows {
        let (pz, az) = (f(r, "plastic_z"), f(r, "back_moment_z"));
        assert_eq!((f(r, "plastic_y"), f(r, "back_moment_y")), (0.0, 0.0));
        if r["time"] < 4.0 - 1e-9 {
            assert_eq!((pz, az), (0.0, 0.0), "at {}", r["time"]);
            continue;
        }
        assert!(
            (az - h * pz).abs() <= 1e-9 * az.abs().max(1.0),
            "α {az} vs H·φp {}",
            h * pz
        );
        if f(r, "yielding") == 1.0 {
            yielding += 1;
            let xi = f(r, "bending_moment_z") - m_s - az;
            assert!(
                (xi.abs() - my).abs() <= 1e-6 * my,
                "|m − α| = {} vs My {my}",
                xi.abs()
            );
        }
    }
    assert!(yielding > 100, "{yielding} yielding records");
}

#[test]
fn check_prints_the_connector_laws() {
    for (name, expect) in [
        (
            "planar_friction_block",
            "planar friction: mu = 0.3, R = 0.1 m",
        ),
        (
            "riser_flexjoint",
            "*FLEXPROADD: Ktor = 572958000 N·m/rad, Kdyn_ini = 4010700",
        ),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
            .arg("check")
            .arg(scene(name))
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{stdout}");
        assert!(stdout.contains(expect), "{name}: {stdout}");
    }
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("check")
        .arg(root().join("assets/decks/flexjoint_example2.dat"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("*FLEXJOINT 3 (line 9): nodes 1 -> 3, IPRO 3, IMAT 2"),
        "{stdout}"
    );
    assert!(stdout.contains("yield moment 6999.99"), "{stdout}");
}

#[test]
fn urdf_arm_scene_applies_the_robot_options_and_hits_its_limits() {
    let (dir, stdout) = run(&scene("urdf_arm"), "urdf_arm", &[]);
    assert!(stdout.contains("3 joints"), "{stdout}");
    // The elbow's friction is the scene's override, 0.6 N·m (the URDF says 0.3): away from
    // the stops (beyond a stop the cap is lifted, kjoint2.md §4.4) the friction moment never
    // exceeds it and equals it while slipping.
    let elbow = Table::read(&dir.join("elbow.csv"));
    let mut slipping = 0;
    for row in rows(&elbow).iter().filter(|r| r["contact_MX"] == 0.0) {
        let f = row["friction_MX"].abs();
        assert!(
            f <= 0.6 * (1.0 + 1e-12),
            "t = {}: friction {f}",
            row["time"]
        );
        if row["slip_MX"] == 2.0 {
            slipping += 1;
            assert!(
                (f - 0.6).abs() < 1e-9,
                "t = {}: slipping at {f}",
                row["time"]
            );
        }
    }
    assert!(slipping > 5, "{slipping} slipping records");
    // The shoulder falls into its 0.6 rad URDF limit and rests on it.
    let shoulder = Table::read(&dir.join("shoulder.csv"));
    let rest = shoulder.last("RX");
    assert!(rest > 0.6 && rest < 0.65, "shoulder at {rest} rad");
    // The wrist slides into its 50 mm limit; the sensor watching it fired once, at 40 mm.
    let wrist = Table::read(&dir.join("wrist.csv"));
    assert!(wrist.max_abs("LX") > 0.05, "wrist {}", wrist.max_abs("LX"));
    let events = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    assert_eq!(events.lines().count(), 2, "{events}");
    assert!(
        events.contains("\"sensor 1\",\"joint `wrist` dx passed 0.04 m\""),
        "{events}"
    );
    // The robot-wide critical damping of the scene, and the automatic stiffness.
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("check")
        .arg(scene("urdf_arm"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.matches("Cr = 0.1\n").count(), 3, "{text}");
    assert_eq!(text.matches("Kn = 0 N/m: automatic").count(), 3, "{text}");
    // With the automatic (resolved) stiffness the energy balance closes within 1 %.
    assert!(residuals(&stdout)[0].abs() < 1.0, "{stdout}");
    assert!(
        text.contains("body `upper_arm`: dynamic, mass 2.000 kg, at [0, 0, 0.1500] m"),
        "{text}"
    );
    // the wrist's anchors coincide to f32 rounding: L0 as a figure, not 22 decimals
    assert!(text.contains("joint `wrist` (URDF"), "{text}");
    assert!(!text.contains("L0 = 0.0000"), "{text}");
    // and the scene's sensor, in SI with its unit
    assert!(
        text.contains("sensor 1: activates when joint `wrist` dx passes 0.04 m"),
        "{text}"
    );
}

/// Issue 12, item 6: a scene using a deck property applies the deck's skews. The property
/// (a revolute, free rx) has Skew_ID1 = joint x along world z and Skew_ID2 = Skew1 turned by
/// 0.3 rad about that axis: the joint reports the initial angle θx = 0.3 (it reported 0, the
/// skews dropped), and a torque about world z turns rx while the blocked rotations stay put.
/// A scene `frame` on top of the deck's Skew_ID1 is refused.
#[test]
fn deck_skews_give_the_joint_frames() {
    let r20 = |v: f64| format!("{v:>20}");
    let i10 = |v: i64| format!("{v:>10}");
    let card = |v: [f64; 3]| v.map(r20).concat();
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    let deck = [
        "/PROP/TYPE45/1".to_string(),
        "hinge with skews".into(),
        format!(
            "{}{}{}{}{}{}{}",
            i10(2),
            r20(1e4),
            r20(0.0),
            r20(0.0),
            i10(0),
            i10(1),
            i10(2)
        ),
        format!("{}{}{}{}{}", r20(0.0), i10(0), r20(0.0), r20(0.0), i10(0)),
        format!("{}{}", r20(0.0), i10(0)),
        format!("{}{}{}", r20(0.0), r20(0.0), i10(0)),
        // Y' = y, Z' = −x: X' = Y'×Z' = z
        "/SKEW/FIX/1".into(),
        "joint x = world z".into(),
        card([0.0; 3]),
        card([0.0, 1.0, 0.0]),
        card([-1.0, 0.0, 0.0]),
        // the same turned by 0.3 rad about world z
        "/SKEW/FIX/2".into(),
        "turned by 0.3".into(),
        card([0.0; 3]),
        card([-s, c, 0.0]),
        card([-c, -s, 0.0]),
    ]
    .join("\n")
        + "\n";
    let scene_text = |frame: &str| {
        format!(
            r#"dt = 0.01
substeps = 4
duration = 0.1
gravity = [0, 0, 0]

[[bodies]]
name = "disc"
shape = {{ type = "ball", radius = 0.1 }}
mass = 1.0

[[joints]]
name = "hinge"
body1 = "world"
body2 = "disc"
{frame}property = {{ deck = "skews.rad", id = 1 }}

[[loads]]
body = "disc"
torque = [0.0, 0.0, 0.01]
"#
        )
    };
    let path = write_scene("skews", &scene_text(""));
    std::fs::write(path.parent().unwrap().join("skews.rad"), &deck).unwrap();
    let (dir, _) = run(&path, "skews", &[]);
    let t = Table::read(&dir.join("hinge.csv"));
    let rx = t.col("RX");
    // I = 0.4·m·r² = 0.004, α = 2.5 rad/s²: 0.3 + 1.25·t² (+ at most 0.0125 by t = 0.1)
    assert!((rx[0] - 0.3).abs() < 2e-4, "initial RX = {}", rx[0]);
    assert!(t.last("RX") > 0.3 + 0.01, "RX = {}", t.last("RX"));
    for c in ["RY", "RZ"] {
        assert!(t.max_abs(c) < 1e-6, "{c} = {}", t.max_abs(c));
    }
    // a scene frame for the same joint as the deck's Skew_ID1 is an error naming `frame`
    let path = write_scene(
        "skews-frame",
        &scene_text("frame = { axis = [0, 0, 1], angle = 0.0 }\n"),
    );
    std::fs::write(path.parent().unwrap().join("skews.rad"), &deck).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("check")
        .arg(&path)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("frame") && err.contains("Skew_ID1"), "{err}");
}

// ---------------------------------------------------------------------------------------
// Output names, closed and full outputs, options checked before any output
// ---------------------------------------------------------------------------------------

/// Three balls on revolute joints named `events`, `a/b` and `a_b`: the first would write
/// over `events.csv`, the other two share `a_b.csv`.
const CLASHING_NAMES: &str = r#"duration = 0.05
gravity = [0, -9.81, 0]
[[bodies]]
name = "b1"
shape = { type = "ball", radius = 0.1 }
mass = 1.0
[[bodies]]
name = "b2"
shape = { type = "ball", radius = 0.1 }
mass = 2.0
[[bodies]]
name = "b3"
shape = { type = "ball", radius = 0.1 }
mass = 3.0
[[joints]]
name = "events"
body1 = "world"
body2 = "b1"
property = { type = "revolute", kn = 1e6, critical_damping = 1.0 }
[[joints]]
name = "a/b"
body1 = "world"
body2 = "b2"
property = { type = "revolute", kn = 1e6, critical_damping = 1.0 }
[[joints]]
name = "a_b"
body1 = "world"
body2 = "b3"
property = { type = "revolute", kn = 1e6, critical_damping = 1.0 }
[[sensors]]
id = 1
time = 0.02
"#;

#[test]
fn clashing_joint_names_get_their_own_files_listed_in_the_index() {
    let p = write_scene("clash", CLASHING_NAMES);
    let (dir, out) = run(&p, "clash", &[]);
    let index = std::fs::read_to_string(dir.join("index.csv")).unwrap();
    assert_eq!(
        index,
        "joint,file\n\"events\",\"events-2.csv\"\n\"a/b\",\"a_b.csv\"\n\"a_b\",\"a_b-2.csv\"\n"
    );
    // the events file is the events file; each joint's file has its own rows: the blocked
    // force on each ball is its weight, so the three files differ
    let events = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    assert!(events.starts_with("time,source,reason\n"), "{events}");
    assert!(events.contains("sensor 1"), "{events}");
    for (file, mass) in [("events-2.csv", 1.0), ("a_b.csv", 2.0), ("a_b-2.csv", 3.0)] {
        let t = Table::read(&dir.join(file));
        let fy = *t.col("FY").last().unwrap();
        assert!(
            (fy.abs() - 9.81 * mass).abs() < 0.05 * 9.81 * mass,
            "{file}: FY {fy}"
        );
    }
    // the command says which joints were renamed
    assert!(
        out.contains("index.csv names the file of each joint"),
        "{out}"
    );
    assert!(
        out.contains("joint `events`: ") && out.contains("events-2.csv"),
        "{out}"
    );
    assert!(
        out.contains("joint `a_b`: ") && out.contains("a_b-2.csv"),
        "{out}"
    );
    assert!(!out.contains("joint `a/b`: "), "{out}");
}

/// A pipe whose reader has already gone: the write end, for a child's stdout.
#[cfg(unix)]
fn pipe_without_reader() -> std::process::Stdio {
    let mut reader = Command::new("true")
        .stdin(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let w = reader.stdin.take().unwrap();
    reader.wait().unwrap();
    w.into()
}

#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_quietly_and_a_full_disk_is_an_error_not_a_panic() {
    let p = scene("revolute");
    for args in [vec!["check"], vec!["run", "--quiet"]] {
        // `kjoint check … | head -1` once head has gone: exit 0, nothing on stderr
        let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
            .args(&args)
            .arg(&p)
            .stdout(pipe_without_reader())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {err}");
        assert!(err.is_empty(), "{args:?}: {err}");
        // `> /dev/full`: one error line, exit 1
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
            .args(&args)
            .arg(&p)
            .stdout(full)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(
            err.trim_end(),
            "kjoint: error: cannot write to standard output: No space left on device (os error \
             28)",
            "{args:?}"
        );
    }
}

#[test]
fn invalid_options_are_refused_before_any_output_is_created() {
    let base = tmp("refused-options");
    for (i, (opt, value, message)) in [
        (
            "--substeps",
            "1000000000",
            "substeps = 1000000000: expected 1 ..= 100000",
        ),
        ("--substeps", "0", "substeps = 0: expected 1 ..= 100000"),
        (
            "--substeps",
            "-2",
            "invalid value '-2' for '--substeps <N>'",
        ),
        (
            "--duration",
            "-1",
            "duration = -1: expected a finite time > 0",
        ),
        ("--duration", "1e12", "expected at most 1e8 frames"),
        // the value as given, not spelt out in 301 digits
        (
            "--duration",
            "1e300",
            "duration = 1e300: expected at most 1e8 frames",
        ),
        (
            "--duration",
            "NaN",
            "duration = NaN: expected a finite time > 0",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        // the value joined to its option, then as the next argument (where a negative
        // value once read as an unknown option)
        for (k, value_args) in [
            vec![format!("{opt}={value}")],
            vec![opt.into(), value.into()],
        ]
        .into_iter()
        .enumerate()
        {
            let csv = base.join(format!("csv{i}-{k}"));
            let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
                .arg("run")
                .arg(scene("revolute"))
                .arg("--csv")
                .arg(&csv)
                .args(&value_args)
                .arg("--quiet")
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            // a command-line usage error, clap's own refusal of a value that is not a number
            // of the option's type or the option's range: exit code 2 (README "Scenes and
            // the `kjoint` command"; the range was exit code 1, a mechanism designer's trial
            // found the two told apart nowhere)
            let code = 2;
            assert_eq!(out.status.code(), Some(code), "{value_args:?}: {err}");
            assert!(err.contains(message), "{value_args:?}: {err}");
            assert!(!csv.exists(), "{value_args:?}: {} created", csv.display());
            assert!(out.stdout.is_empty(), "{value_args:?}");
        }
    }
}

/// A robot whose root link is `world` (the ROS convention) in a scene: the link is the fixed
/// world, the base hangs on it, and the scene's own joints on `world` use the same body.
#[test]
fn a_root_link_named_world_is_the_scene_s_world() {
    let dir = tmp("world-link");
    let unit = r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;
    // `world` has a visual (so it is kept as a body) and a revolute joint to the base:
    // even with fixed_base = false it must be fixed, not a falling 10 g link
    let urdf = format!(
        r#"<robot name="r">
  <link name="world"><visual><geometry><box size="1 1 0.01"/></geometry></visual></link>
  <link name="base">{unit}</link>
  <link name="arm"><inertial><origin xyz="0 0 -0.25"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="yaw" type="revolute"><parent link="world"/><child link="base"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="pitch" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"#
    );
    std::fs::write(dir.join("r.urdf"), urdf).unwrap();
    let scene_text = r#"duration = 1.0
gravity = [0, 0, -9.81]
substeps = 8
[[robots]]
urdf = "r.urdf"
options = { fixed_base = false, kn = 1e5 }
[[bodies]]
name = "ball"
shape = { type = "ball", radius = 0.05 }
mass = 1.0
translation = [1, 0, 0]
[[joints]]
name = "tether"
body1 = "world"
body2 = "ball"
anchor1 = [1, 0, 0]
property = { type = "spherical", kn = 1e5 }
"#;
    let p = dir.join("world.toml");
    std::fs::write(&p, scene_text).unwrap();
    // check: `world` is a fixed body, listed once
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("check")
        .arg(&p)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        stdout
            .matches("body `world`: fixed, at [0, 0, 0] m")
            .count(),
        1,
        "{stdout}"
    );
    // run: the base and the ball hang on the world; nothing falls
    let (csv, _) = run(&p, "world-link-csv", &[]);
    for (joint, tol) in [("yaw", 0.01), ("pitch", 0.01), ("tether", 0.01)] {
        let t = Table::read(&csv.join(format!("{joint}.csv")));
        for c in ["LX", "LY", "LZ"] {
            assert!(t.max_abs(c) < tol, "{joint} {c}: {}", t.max_abs(c));
        }
    }
    // a `world` link with mass that is not fixed cannot be the ground: refused clearly
    let heavy = std::fs::read_to_string(dir.join("r.urdf"))
        .unwrap()
        .replace(
            r#"<link name="world"><visual>"#,
            &format!(r#"<link name="world">{unit}<visual>"#),
        );
    std::fs::write(dir.join("r.urdf"), heavy).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("check")
        .arg(&p)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        err.contains("world.toml:5: field `robots[0].urdf`: link `world` of ")
            && err.contains("is dynamic"),
        "{err}"
    );
}

/// Issue 13: every scene in `assets/scenes` closes its energy balance within 1 % (the joint
/// set books the work its impulses actually did; the seed translational deck was at 87 %).
#[test]
fn every_shipped_scene_closes_its_energy_balance_within_one_percent() {
    let mut checked = 0;
    for entry in std::fs::read_dir(root().join("assets/scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let (_, stdout) = run(&path, &format!("balance-{name}"), &[]);
        for r in residuals(&stdout) {
            assert!(r.abs() < 1.0, "{name}: residual {r} %\n{stdout}");
        }
        checked += 1;
    }
    assert!(checked >= 15, "{checked} scenes");
}

/// A ball on a spherical joint whose `rx` spring curve softens and falls past 0.1 rad,
/// under a torque about x rising at 5.5 N·m/s: `ends` closes the curve (the trial's
/// `[0.2, 4.0]`, where the force falls on without bound, or a rising segment after it).
fn softening_ball(ends: &str) -> String {
    format!(
        r#"dt = 0.016666666666666666
substeps = 16
duration = 2.0
gravity = [0, 0, 0]

[[bodies]]
name = "ball"
shape = {{ type = "ball", radius = 0.1 }}
mass = 1.0

[[joints]]
name = "ball_joint"
body1 = "world"
body2 = "ball"
[joints.property]
type = "spherical"
kn = 1e5
rx = {{ stiffness_curve = [[-0.2, -4.0], [-0.1, -5.0], [0.0, 0.0], [0.1, 5.0], {ends}] }}
ry = {{ stiffness = 50.0, viscosity = 0.1 }}
rz = {{ stiffness = 50.0, viscosity = 0.1 }}

[[loads]]
body = "ball"
torque = [5.5, 0.0, 0.0]
function = {{ curve = [[0.0, 0.0], [1.0, 1.0]] }}
"#
    )
}

/// A run whose bodies gain energy that nothing gave them fails (exit code 1) naming the
/// joint, after its summary: the softening curve runs away past its end, the ball spins up
/// and its spherical joint's rotation vector jumps at each turn; the joint's update booked
/// −1.95e10 J of dissipation, where the curve released 3.75e7 J and the torque did 5.2e6 J,
/// and the run ended with exit code 0 and a residual of 2.3e-4 % of a scale the spin itself
/// had inflated (a Radioss analyst's trial, 2026-12-06). The same ball on a curve that
/// rises again runs to its end (exit code 0) with no such error.
#[test]
fn a_run_whose_bodies_gain_energy_nothing_gave_them_fails_naming_the_joint() {
    let dir = tmp("energy-created");
    let run = |ends: &str, name: &str| {
        let path = dir.join(name);
        std::fs::write(&path, softening_ball(ends)).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
            .arg("run")
            .arg(&path)
            .arg("--quiet")
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout).to_string();
        let stderr = String::from_utf8_lossy(&out.stderr).to_string();
        (out.status.code(), stdout, stderr)
    };
    let (code, stdout, stderr) = run("[0.2, 4.0]", "runaway.toml");
    assert_eq!(code, Some(1), "{stdout}\n{stderr}");
    // the summary is printed, with the error under the energy balance, and the error again
    // on standard error
    let line = (stdout.lines())
        .find(|l| l.trim_start().starts_with("error: the bodies gained"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        stderr.contains("the run is unstable") && stderr.contains("joint `ball_joint`"),
        "{stderr}"
    );
    // the gain is the bodies' kinetic energy at the end (nothing else moves: no gravity),
    // less what the torque did and the curve released: hundreds of times the sources
    let number = |after: &str| -> f64 {
        let tail = line.split(after).nth(1).unwrap_or_else(|| panic!("{line}"));
        tail.split_whitespace().next().unwrap().parse().unwrap()
    };
    let gain = number("the bodies gained ");
    let times = number("), ");
    let final_energy: f64 = (stdout.lines())
        .find(|l| l.trim_start().starts_with("final kinetic + potential"))
        .and_then(|l| l.split_whitespace().last())
        .unwrap()
        .parse()
        .unwrap();
    assert!(times > 100.0, "{line}");
    assert!(
        (gain - final_energy).abs() < 0.01 * final_energy,
        "gain {gain} J, final {final_energy} J"
    );
    // the curve rising again: the same load, no runaway, no error
    let (code, stdout, stderr) = run("[0.2, 4.0], [2.0, 100.0]", "rising.toml");
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(!stdout.contains("error:"), "{stdout}");
    // energy the joints did not give: a kinematic bat knocks a ball at 2 m/s through
    // rapier's contact, which books nothing (2 J that no work explains; it failed the run
    // before the joints' share was asked, a review, 2026-12-06): the residual's warning
    // names the contacts, and the run succeeds
    let bat = r#"dt = 0.016666666666666666
substeps = 4
duration = 1.0
gravity = [0, 0, 0]

[[bodies]]
name = "rod"
shape = { type = "cuboid", half_extents = [0.05, 0.5, 0.05] }
mass = 1.0
translation = [0, -0.5, 0]

[[joints]]
name = "hinge"
body1 = "world"
body2 = "rod"
anchor1 = [0, 0, 0]
anchor2 = [0, 0.5, 0]
[joints.property]
type = "revolute"

[[bodies]]
name = "bat"
kind = "fixed"
shape = { type = "cuboid", half_extents = [0.1, 0.1, 0.1] }
translation = [3.0, 0, 0]
collide = true

[[bodies]]
name = "ball"
shape = { type = "ball", radius = 0.1 }
mass = 1.0
translation = [3.5, 0, 0]
collide = true

[[motions]]
body = "bat"
velocity = [2.0, 0, 0]
function = { constant = 1.0 }
"#;
    let path = dir.join("bat.toml");
    std::fs::write(&path, bat).unwrap();
    let stdout = common::cli::kjoint_run(&path, None, &[] as &[&str]);
    assert!(!stdout.contains("error:"), "{stdout}");
    assert!(
        stdout.contains("arose while rapier's contacts touched"),
        "{stdout}"
    );
}

/// Issue 13, item 7: the arm with a gripper runs from the command line. Its three KJOINT2
/// joints get histories, its two rapier finger joints are counted and listed by `check`
/// with their limits and motors, and the energy balance, which counts the work of the lift
/// (a prescribed motion) and leaves rapier's contacts and joints in the residual, closes
/// within 1 % (the physics: `tests/gripper.rs`).
#[test]
fn arm_gripper_scene_runs_with_rapier_joints_beside_kjoint2_ones() {
    let (dir, stdout) = run(&scene("arm_gripper"), "arm_gripper", &[]);
    assert!(stdout.contains("3 joints, 2 rapier joints"), "{stdout}");
    for joint in ["shoulder", "elbow", "wrist"] {
        assert!(dir.join(format!("{joint}.csv")).is_file(), "{joint}");
    }
    assert!(!dir.join("left_finger.csv").exists());
    let work = load_work(&stdout);
    // the lift raised 3.8 kg by 10 cm
    assert!((work - 3.8 * 9.81 * 0.1).abs() < 0.05 * 3.73, "{stdout}");
    assert!(residuals(&stdout)[0].abs() < 1.0, "{stdout}");
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("check")
        .arg(scene("arm_gripper"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    // the URDF limit 0.04 m as rapier keeps it (0.03999999910593033 in f32), printed as
    // the decimal it came from (`figure::fmt_num`), in f32 and f64 alike
    let limit = "0.04";
    assert!(
        text.contains(&format!(
            "rapier joint `left_finger` (impulse joint, solved by rapier)\n  x free, limits \
             [0, {limit}] m, motor (ForceBased) target 0 m, stiffness 1000 N/m, damping 10 \
             N·s/m, max force 20 N"
        )),
        "{text}"
    );
    assert!(
        text.contains("body `base_link`: kinematic (a prescribed motion)"),
        "{text}"
    );
    assert!(
        text.contains("rapier's solver (contacts, rapier joints): 4 iterations a substep, friction in the bias pass"),
        "{text}"
    );
}

/// `--substeps N` runs the model a scene file with `substeps = N` describes: a robot's
/// friction and stop stiffnesses, sized from the substep when the robot is built, follow
/// it (they kept the scene's: the URDF arm's shoulder stop stayed at 637621 N·m/rad at 8
/// substeps, where the file with `substeps = 8` gives 1.11e6). The shoulder's row of the
/// summary (its peak moment, stop penetration and slip follow that stiffness) is the same
/// both ways, and differs from the run at 4 substeps.
#[test]
fn the_substeps_option_resizes_a_robots_stops() {
    let notice = |stdout: &str| -> String {
        stdout
            .lines()
            .find(|l| l.starts_with("shoulder "))
            .unwrap_or_else(|| panic!("{stdout}"))
            .to_string()
    };
    let by_option = notice(&run(&scene("urdf_arm"), "substeps-option", &["--substeps", "8"]).1);
    let at_4 = notice(&run(&scene("urdf_arm"), "substeps-4", &[]).1);
    assert_ne!(by_option, at_4);
    let text = std::fs::read_to_string(scene("urdf_arm")).unwrap();
    let urdf = root().join("assets/urdf/arm.urdf");
    let text = text.replace("substeps = 4", "substeps = 8").replace(
        "\"../urdf/arm.urdf\"",
        &format!("{:?}", urdf.display().to_string()),
    );
    let file = tmp("substeps-file").join("urdf_arm_8.toml");
    std::fs::write(&file, text).unwrap();
    let by_file = notice(&run(&file, "substeps-file-out", &[]).1);
    assert_eq!(by_option, by_file);
}

/// A chain of 5 rods (1 kg, 0.5 m) on spherical joints released horizontal and swinging
/// for 20 s: at 4 substeps a frame its energy balance misses by 6.8 % of the energy scale
/// (the joints book 38 J dissipated where the bodies lost 31 J), which the summary says
/// with its remedy; at 16 substeps it closes within 0.4 % (0.36 % since the noise bound's
/// floor, `κ = 4`, holds its blocked DOFs there; 0.3 % where they were springs at
/// `κ = 0.9`) and the summary says nothing.
#[test]
fn an_energy_balance_that_does_not_close_is_said_with_its_remedy() {
    let chain = write_scene("chain5", &chain5());
    let (_, coarse) = run(&chain, "chain5-4", &[]);
    let (_, fine) = run(&chain, "chain5-16", &["--substeps", "16"]);
    let (r4, r16) = (residuals(&coarse)[0], residuals(&fine)[0]);
    assert!(r4 > 5.0 && r16.abs() < 0.4, "residuals {r4} % and {r16} %");
    let warning = "warning: the balance does not close";
    assert!(
        coarse.contains(warning) && coarse.contains("more substeps"),
        "{coarse}"
    );
    assert!(!fine.contains(warning), "{fine}");
}

/// A 20 kg cube at rest on a stiff revolute joint to the world (`Kn = 1e7`, `Cr = 0.5`):
/// little moves (the energy scale is the joint's sag, about 4 mJ), and 10 m above the
/// origin the f32 poses round that sag at every substep, so that the balance misses by
/// several times the scale, more at more substeps. The warning names that cause and its
/// remedy, where it only said "more substeps", which made it worse; at the origin the
/// balance closes. (With the `f64` feature the poses do not round so.)
#[cfg(not(feature = "f64"))]
#[test]
fn a_balance_missed_by_f32_poses_far_from_the_origin_names_that_remedy() {
    let cube = |y: f64| {
        format!(
            "dt = 0.016666666666666666\nsubsteps = 16\nduration = 3.0\ngravity = [0, -9.81, 0]\n\
             \n[[bodies]]\nname = \"wheel\"\n\
             shape = {{ type = \"cuboid\", half_extents = [0.1, 0.1, 0.1] }}\n\
             mass = 20.0\ntranslation = [0, {y:?}, 0]\n\
             \n[[joints]]\nname = \"axle\"\nbody1 = \"world\"\nbody2 = \"wheel\"\n\
             anchor1 = [0, {y:?}, 0]\nanchor2 = [0, 0, 0]\n\
             frame = {{ axis = [0, 1, 0], angle = -1.5707963267948966 }}\n\
             property = {{ type = \"revolute\", kn = 1e7, critical_damping = 0.5 }}\n"
        )
    };
    let (_, far) = run(&write_scene("cube10", &cube(10.0)), "cube10", &[]);
    let (_, near) = run(&write_scene("cube0", &cube(0.0)), "cube0", &[]);
    let (r_far, r_near) = (residuals(&far)[0], residuals(&near)[0]);
    assert!(
        r_far.abs() > 100.0 && r_near.abs() < 0.01,
        "residuals {r_far} % and {r_near} %"
    );
    assert!(
        far.contains("f32 poses of bodies far from the origin")
            && far.contains("the crate's `f64` feature"),
        "{far}"
    );
    assert!(
        !near.contains("warning: the balance does not close"),
        "{near}"
    );
}

/// A 2 kg cube (0.1 m) hung at its joint's anchor on a spring of 1e15 N/m: it sags
/// `m·g/K = 2e-14 m`, and its energies are of 1e-13 J, which the f32 poses do not resolve.
/// The balance is judged against the energy the poses resolve, `M·|g|·L_b·ε =
/// 2·9.81·(0.1·√3)·2⁻²³ = 4.05e-7 J`, not a floor of 1e-12 J, where the residual of
/// 1.4e-13 J read 14 % and got a warning.
#[cfg(not(feature = "f64"))]
#[test]
fn a_balance_of_energies_the_poses_do_not_resolve_is_not_a_warning() {
    let text = "dt = 0.016666666666666666\nsubsteps = 1\nduration = 1.0\n\
                gravity = [0, -9.81, 0]\n\n[[bodies]]\nname = \"mass\"\n\
                shape = { type = \"cuboid\", half_extents = [0.05, 0.05, 0.05] }\n\
                mass = 2.0\n\n[[joints]]\nname = \"spring\"\nbody1 = \"world\"\n\
                body2 = \"mass\"\nframe = { axis = [0, 0, 1], angle = -1.5707963267948966 }\n\
                [joints.property]\ntype = \"translational\"\nkn = 1e6\n\
                dx = { stiffness = 1e15, viscosity = 100.0 }\n";
    let (_, out) = run(
        &write_scene("stiff_at_anchor", text),
        "stiff_at_anchor",
        &[],
    );
    let line = out
        .lines()
        .find(|l| l.starts_with("  residual "))
        .unwrap_or_else(|| panic!("{out}"));
    let scale = 2.0 * 9.81 * 0.1 * 3f64.sqrt() * f64::from(f32::EPSILON);
    assert!(
        line.contains(&format!("energy scale {scale:.2e} J")),
        "{line}"
    );
    assert!(residuals(&out)[0].abs() < 1.0, "{line}");
    assert!(!out.contains("the balance does not close"), "{out}");
}

/// The scene of [`an_energy_balance_that_does_not_close_is_said_with_its_remedy`]: rods
/// `rod0` .. `rod4` along x, each hung from the end of the one before by a spherical joint
/// (`j0` at the world's origin).
fn chain5() -> String {
    let mut s = String::from(
        "dt = 0.016666666666666666\nsubsteps = 4\nduration = 20.0\ngravity = [0, -9.81, 0]\n",
    );
    for i in 0..5 {
        let (above, anchor1) = match i {
            0 => ("world".to_string(), 0.0),
            _ => (format!("rod{}", i - 1), 0.25),
        };
        s += &format!(
            "\n[[bodies]]\nname = \"rod{i}\"\n\
             shape = {{ type = \"cuboid\", half_extents = [0.25, 0.02, 0.02] }}\n\
             mass = 1.0\ntranslation = [{}, 0, 0]\n\
             \n[[joints]]\nname = \"j{i}\"\nbody1 = \"{above}\"\nbody2 = \"rod{i}\"\n\
             anchor1 = [{anchor1}, 0, 0]\nanchor2 = [-0.25, 0, 0]\n\
             property = {{ type = \"spherical\" }}\n",
            0.25 + 0.5 * i as f64
        );
    }
    s
}

/// A scene without gravity at 60 Hz (`timing`: its substeps and duration): a 1 kg block of
/// 10 cm (`block`: more keys of it) held to the world by the joint `joint` of `property`,
/// pulled along x by a constant `force` \[N\] if any.
fn block_scene(
    timing: &str,
    block: &str,
    joint: &str,
    property: &str,
    force: Option<f64>,
) -> String {
    let mut s = format!(
        "gravity = [0, 0, 0]\ndt = 0.016666666666666666\n{timing}\n\n[[bodies]]\n\
         name = \"block\"\nshape = {{ type = \"cuboid\", half_extents = [0.05, 0.05, 0.05] }}\n\
         mass = 1.0\n{block}\n\n[[joints]]\nname = \"{joint}\"\nbody1 = \"world\"\n\
         body2 = \"block\"\nproperty = {property}\n"
    );
    if let Some(f) = force {
        s += &format!(
            "\n[[loads]]\nbody = \"block\"\nforce = [{f:?}, 0.0, 0.0]\n\
             function = {{ constant = 1.0 }}\n"
        );
    }
    s
}

/// A block at 500 m/s in free flight keeps its speed: rapier clips every body's speed to
/// 400 m/s by default, which a scene lifts (the block was slowed to 400 m/s, a fifth of its
/// kinetic energy gone, and the run said nothing).
#[test]
fn a_body_faster_than_rapiers_speed_cap_keeps_its_speed() {
    let fast = write_scene(
        "fast",
        &block_scene(
            "substeps = 4\nduration = 0.1",
            "linvel = [500.0, 0.0, 0.0]",
            "slider",
            r#"{ type = "translational", kn = 1e6 }"#,
            None,
        ),
    );
    let (dir, out) = run(&fast, "fast", &[]);
    let t = Table::read(&dir.join("slider.csv"));
    // x = v·t along the free DOF, v unchanged
    let (time, x) = (t.last("time"), t.last("LX"));
    assert!(
        (x - 500.0 * time).abs() < 1e-3 * x,
        "x = {x} m at t = {time} s"
    );
    assert!(residuals(&out)[0].abs() < 1e-3, "{out}");
}

/// The cells of `joint`'s row of the summary table, by heading: `gap` and the figures after
/// it (`stop pen.` m and rad, `slip` m and rad, `dissipated`).
fn summary_cells(stdout: &str, joint: &str) -> HashMap<&'static str, f64> {
    let row = stdout
        .lines()
        .find(|l| l.split_whitespace().next() == Some(joint))
        .unwrap_or_else(|| panic!("no row {joint}: {stdout}"));
    let cells: Vec<f64> = row
        .split_whitespace()
        .skip(1)
        .map(|c| c.parse().unwrap())
        .collect();
    let names = [
        "gap",
        "pen_m",
        "pen_rad",
        "slip_m",
        "slip_rad",
        "dissipated",
    ];
    // after peak |F|, peak |M|, law |F|, law |M|, end |F|, end |M|
    names.into_iter().zip(cells[6..].iter().copied()).collect()
}

/// A block on a translational joint with a friction spring (`Kf` = 1e4 N/m, `FF` = 5 N)
/// under a 3 N step load overshoots past the cap and slips a little: the summary's slip is
/// the plastic part, `E_friction / FF` (21.6 µm), not the whole motion of the substeps it
/// slipped in (31.8 µm).
#[test]
fn the_summarys_slip_is_the_plastic_motion() {
    let scene = write_scene(
        "stick",
        &block_scene(
            "substeps = 16\nduration = 2.0",
            "",
            "j",
            r#"{ type = "translational", critical_damping = 0.2, dx = { friction_stiffness = 1e4, friction = 5.0 } }"#,
            Some(3.0),
        ),
    );
    let (dir, out) = run(&scene, "stick", &[]);
    let plastic = Table::read(&dir.join("j.csv")).last("E_friction") / 5.0;
    let slip = summary_cells(&out, "j")["slip_m"];
    assert!(plastic > 1e-5, "it slips: {plastic} m");
    assert!(
        (slip - plastic).abs() < 0.01 * plastic,
        "slip {slip} m, plastic {plastic} m"
    );
}

/// A spherical joint of `Kn` = 100 N/m pulled by 1000 N comes metres apart: the summary's
/// `gap` is the worst distance between its anchors along the blocked translations (the
/// health warning names only the first crossing, 1 mm).
#[test]
fn the_summarys_gap_is_the_worst_anchor_distance() {
    let scene = write_scene(
        "apart",
        &block_scene(
            "substeps = 16\nduration = 1.0",
            "",
            "spring",
            r#"{ type = "spherical", kn = 100.0 }"#,
            Some(1000.0),
        ),
    );
    let (dir, out) = run(&scene, "apart", &["--log", "substep"]);
    let t = Table::read(&dir.join("spring.csv"));
    let worst = (0..t.col("LX").len())
        .map(|i| (t.col("LX")[i].powi(2) + t.col("LY")[i].powi(2) + t.col("LZ")[i].powi(2)).sqrt())
        .fold(0.0, f64::max);
    let gap = summary_cells(&out, "spring")["gap"];
    // an undamped 1000 N step on 100 N/m swings to 2·F/K = 20 m
    assert!(worst > 10.0, "{worst}");
    assert!(
        (gap - worst).abs() < 1e-3 * worst,
        "gap {gap} m, worst {worst} m"
    );
    // the warning, given at the first crossing, ends with the worst of the run
    let warning = out
        .lines()
        .find(|l| l.contains("warning: joint spring") && l.contains("anchors"))
        .unwrap_or_else(|| panic!("{out}"));
    let said: f64 = warning
        .split("worst over the run ")
        .nth(1)
        .and_then(|w| w.split(' ').next())
        .unwrap_or_else(|| panic!("{warning}"))
        .parse()
        .unwrap();
    assert!((said - gap).abs() < 1e-3 * gap, "{warning}");
}

/// A block on a planar joint with planar friction (`μ` = 0.5, stick spring 1e4 N/m) under a
/// 4 N step pull overshoots past its cap and slips a little: the summary's slip is the
/// connector's own accumulated plastic slip (`slip_total`, 1.21 mm), not the motion of the
/// records it slipped over (0.78 mm).
#[test]
fn the_summarys_slip_of_planar_friction_is_the_connectors() {
    let scene = write_scene("planar-stick", PLANAR_STICK);
    let (dir, out) = run(&scene, "planar-stick", &[]);
    let total = Table::read(&dir.join("j.csv")).last("planar_friction.slip_total");
    let slip = summary_cells(&out, "j")["slip_m"];
    assert!(total > 1e-3, "it slips: {total} m");
    assert!(
        (slip - total).abs() < 1e-3 * total,
        "slip {slip} m, slip_total {total} m"
    );
}

/// The scene of [`the_summarys_slip_of_planar_friction_is_the_connectors`].
const PLANAR_STICK: &str = r#"dt = 0.016666666666666666
substeps = 16
duration = 2.0
gravity = [0.0, -9.81, 0.0]

[[bodies]]
name = "block"
shape = { type = "cuboid", half_extents = [0.05, 0.05, 0.05] }
mass = 1.0
translation = [0.0, 0.05, 0.0]

[[joints]]
name = "j"
body1 = "world"
body2 = "block"
anchor1 = [0.0, 0.0, 0.0]
anchor2 = [0.0, -0.05, 0.0]
frame = { axis = [0, 0, 1], angle = 1.5707963267948966 }
property = { type = "planar", critical_damping = 0.2 }
planar_friction = { mu = 0.5, stick_stiffness = 1e4 }

[[loads]]
body = "block"
force = [4.0, 0.0, 0.0]
function = { constant = 1.0 }
"#;

/// A joint preloaded by its skew frames (`frame2` turned 0.3 rad about x from `frame`):
/// the summary counts its spring's `½·K·θ0² = 0.045 J` as energy the model starts with, and
/// the joints' dissipation is what the damper took (positive, nearly all of the preload
/// after 6 s); it read −3e-4 J, the preload charged to `numerical`, while the balance
/// closed and "initial kinetic + potential" read 0.
#[test]
fn a_preloaded_joint_is_counted_at_the_start_of_the_balance() {
    let p = write_scene(
        "preload",
        r#"dt = 0.01
substeps = 10
duration = 6.0
gravity = [0.0, 0.0, 0.0]

[[bodies]]
name = "ball"
shape = { type = "ball", radius = 0.1 }
mass = 1.0
translation = [0.0, -0.5, 0.0]

[[joints]]
name = "skewed"
body1 = "world"
body2 = "ball"
anchor1 = [0.0, 0.0, 0.0]
anchor2 = [0.0, 0.0, 0.0]
frame = { axis = [1, 0, 0], angle = 0.0 }
frame2 = { axis = [1, 0, 0], angle = 0.3 }
[joints.property]
type = "revolute"
kn = 1e6
rx = { stiffness = 1.0, viscosity = 0.1 }
"#,
    );
    let (_, out) = run(&p, "preload", &[]);
    let value = |label: &str| -> f64 {
        let line = out
            .lines()
            .find(|l| l.trim_start().starts_with(label))
            .unwrap_or_else(|| panic!("no `{label}` line in\n{out}"));
        line.trim_start()[label.len()..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let preload = value("stored in the joints at their start");
    assert!((preload - 0.045).abs() < 1e-6, "preload {preload} J\n{out}");
    let dissipated = value("dissipated by the joints");
    assert!(
        dissipated > 0.99 * 0.045 && dissipated < 0.045,
        "dissipated {dissipated} J\n{out}"
    );
    let r = residuals(&out);
    assert!(r.len() == 1 && r[0].abs() < 0.5, "residual {r:?} %\n{out}");
}

/// The joints' start is shown as a preload only when it is one: the URDF arm placed off the
/// origin and turned starts its joints at the f32 rounding of their anchors, which the
/// summary printed as "stored in the joints at their start 1.41e-33" J beside 40.64 J;
/// the balance still closes with it.
#[test]
fn a_placed_robot_s_rounding_is_no_preload() {
    let arm = root().join("assets/urdf/arm.urdf");
    let p = write_scene(
        "placed_arm",
        &format!(
            "dt = 0.016666666666666666\nsubsteps = 4\nduration = 0.5\ngravity = [0, 0, -9.81]\n\
             [[robots]]\nurdf = {:?}\nname = \"left\"\nposition = [3.3, 2.1, 1.06]\n\
             rotation = {{ axis = [0.3, 0.2, 1], angle = 0.7 }}\n",
            arm.display().to_string()
        ),
    );
    let (_, out) = run(&p, "placed_arm", &[]);
    assert!(out.contains("energy balance"), "{out}");
    assert!(!out.contains("at their start"), "{out}");
    let r = residuals(&out);
    assert!(r.len() == 1 && r[0].abs() < 0.1, "residual {r:?} %\n{out}");
}

/// A free part that nothing can stop falling is named before the run: a floating body
/// hinged to another over a ground written without `collide = true` fell 44 m in 3 s with
/// no word. Held by the ground through collisions, or with no gravity, nothing is said; a
/// part hung from the world is not named.
#[test]
fn a_part_that_nothing_stops_falling_is_named() {
    let text = |collide: bool, gravity: f64, hang: bool| {
        // bob hung from the world, or not
        let hang = if hang {
            "[[joints]]\nname = \"hang\"\nbody1 = \"world\"\nbody2 = \"bob\"\n\
             anchor1 = [3.0, 3.0, 0.0]\nanchor2 = [0.0, 0.0, 0.0]\n\
             property = { type = \"spherical\", kn = 1e6 }\n"
        } else {
            ""
        };
        format!(
            r#"dt = 0.01
substeps = 4
duration = 0.5
gravity = [0.0, {gravity}, 0.0]

[[bodies]]
name = "ground"
kind = "fixed"
shape = {{ type = "cuboid", half_extents = [5.0, 0.1, 5.0] }}
translation = [0.0, -1.0, 0.0]
collide = {collide}

[[bodies]]
name = "chassis"
shape = {{ type = "cuboid", half_extents = [0.5, 0.1, 0.3] }}
mass = 20.0
collide = true

[[bodies]]
name = "wheel"
shape = {{ type = "ball", radius = 0.2 }}
mass = 1.0
translation = [0.6, -0.6, 0.0]
collide = true

[[bodies]]
name = "bob"
shape = {{ type = "ball", radius = 0.1 }}
mass = 1.0
translation = [3.0, 2.0, 0.0]

[[joints]]
name = "axle"
body1 = "chassis"
body2 = "wheel"
anchor1 = [0.6, -0.6, 0.0]
anchor2 = [0.0, 0.0, 0.0]
property = {{ type = "revolute", kn = 1e6 }}

{hang}"#
        )
    };
    let warnings = |name: &str, collide: bool, gravity: f64, hang: bool| -> Vec<String> {
        let p = write_scene(name, &text(collide, gravity, hang));
        let (_, out) = run(&p, name, &[]);
        out.lines()
            .filter(|l| l.trim_start().starts_with("warning: ") && l.contains("freely"))
            .map(String::from)
            .collect()
    };
    let w = warnings("falls", false, -9.81, true);
    assert!(
        w.len() == 1
            && w[0].contains("bodies `chassis`, `wheel` fall freely under gravity")
            && w[0].contains("no joint holds them")
            && w[0].contains("`collide = true`")
            && !w[0].contains("bob"),
        "{w:?}"
    );
    // the bob on a free joint (which holds nothing) falls too, named by itself
    let w = warnings("falls-alone", false, -9.81, false);
    assert!(
        w.len() == 2
            && w[1].contains("body `bob` falls freely under gravity: no joint holds it ")
            && w[1].contains("the ground or table it should rest on"),
        "{w:?}"
    );
    assert!(warnings("rests", true, -9.81, true).is_empty());
    assert!(warnings("floats", false, 0.0, true).is_empty());
}

/// `kjoint run --help` documents every option in plain text: the `--duration` line read
/// `Simulated time \[s\]`, the doc comment's markdown escape printed as is.
#[test]
fn run_help_documents_every_option_without_markdown_escapes() {
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .args(["run", "--help"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout);
    for option in [
        "--csv <DIR>",
        "--rrd <FILE>",
        "--plot <DIR>",
        "--substeps <N>",
        "--duration <SECONDS>",
        "--log <LOG>",
        "--quiet",
    ] {
        assert!(help.contains(option), "{option} missing:\n{help}");
    }
    assert!(
        !help.contains('\\'),
        "a markdown escape in the help:\n{help}"
    );
    assert!(help.contains("Simulated time in seconds"), "{help}");
}

/// A robot file is run and checked as a scene of its own (`scene::robot_scene`): the robot
/// alone, hanging from its fixed base under gravity along −z for 2 s. The MJCF pendulum,
/// released with both arms horizontal, swings its upper arm into the shoulder's 90° stop
/// (MJCF `range="-90 90"` in degrees) with every joint's anchors held and the energy
/// balance closed, as a user running the file would read in the summary.
#[test]
fn a_robot_file_runs_and_checks_as_a_scene_of_its_own() {
    let (_dir, stdout) = run(&root().join("assets/mjcf/pendulum.xml"), "robot_file", &[]);
    assert!(
        stdout.contains("2.0000 s simulated: 120 frames of 0.01667 s, 4 substeps each, 2 joints"),
        "{stdout}"
    );
    let row = |name: &str| -> Vec<f64> {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("no row {name}: {stdout}"));
        line.split_whitespace()
            .skip(1)
            .map(|v| v.parse().unwrap())
            .collect()
    };
    for name in ["shoulder", "elbow"] {
        let gap = row(name)[6];
        assert!(gap < 1e-3, "{name}: gap {gap} m");
    }
    // the shoulder's rotation stop was hit, and held within a hundredth of a radian
    let pen = row("shoulder")[8];
    assert!(
        pen > 0.0 && pen < 0.01,
        "shoulder stop penetration {pen} rad"
    );
    let r = residuals(&stdout);
    assert!(r.len() == 1 && r[0].abs() < 1.0, "{stdout}");
    // the same file checked: z-up gravity, the robot's bodies and joints
    let text = common::cli::kjoint_check(&root().join("assets/urdf/arm.urdf"));
    assert!(text.contains("gravity [0, 0, -9.81] m/s²"), "{text}");
    for j in ["shoulder", "elbow", "wrist"] {
        assert!(text.contains(&format!("joint `{j}` (URDF")), "{j}: {text}");
    }
    // a URDF written as `.xml` is read as URDF (told by its `<robot>` root)
    let dir = tmp("robot_file_bad");
    let xml = dir.join("arm.xml");
    std::fs::copy(root().join("assets/urdf/arm.urdf"), &xml).unwrap();
    let text = common::cli::kjoint_check(&xml);
    assert!(text.contains("joint `wrist` (URDF"), "{text}");
    // a robot file with an error: the loader's message alone, naming the robot file
    let bad = dir.join("bad.xml");
    std::fs::write(
        &bad,
        "<mujoco><worldbody>\n<body name=\"b\" quat=\"0 0 0 0\">\n<joint name=\"j\"/>\
         <geom size=\"0.1\"/></body></worldbody></mujoco>",
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("run")
        .arg(&bad)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(
        stderr.trim(),
        format!(
            "kjoint: error: {}: <body name=\"b\"> (line 2): invalid quat = 0 0 0 0: expected a \
             quaternion of non-zero norm (w x y z)",
            bad.display()
        )
    );
}

/// An MJCF file run as a scene of its own runs under its `<option gravity>`, as MuJoCo runs
/// it (it ran under the default −9.81 m/s² along z whatever the model said), and its
/// `timestep` is noticed as not used; in a scene file the scene's gravity applies, with a
/// notice when the model's differs.
#[test]
fn an_mjcf_file_runs_under_its_own_option_gravity() {
    use rapier_kjoint::scene;
    let dir = tmp("mjcf_gravity");
    let model = dir.join("moon.xml");
    std::fs::write(
        &model,
        "<mujoco model=\"moon\">\n<option gravity=\"0 0 -1.62\" timestep=\"0.005\"/>\n\
         <worldbody><body name=\"b\" pos=\"0 0 1\"><joint name=\"j\" type=\"hinge\" \
         axis=\"0 1 0\"/><geom type=\"capsule\" fromto=\"0 0 0 0.3 0 0\" size=\"0.02\"/>\
         </body></worldbody></mujoco>",
    )
    .unwrap();
    let (sc, src) = scene::robot_scene(&model).unwrap().unwrap();
    let built = scene::build(&sc, &src).unwrap();
    assert_eq!(
        [
            built.world.gravity.x,
            built.world.gravity.y,
            built.world.gravity.z
        ],
        [0.0, 0.0, -1.62]
    );
    assert!(
        built
            .notices
            .iter()
            .any(|n| n.contains("timestep = 0.005 s not used")),
        "{:?}",
        built.notices
    );
    let text = common::cli::kjoint_check(&model);
    assert!(text.contains("gravity [0, 0, -1.62] m/s²"), "{text}");
    // the run: the arm released horizontal swings down under the moon's gravity, so its
    // hinge carries m·g of the moon, not the earth's (peak |F| ≥ m·1.62, well below m·9.81)
    let (_d, stdout) = run(&model, "mjcf_gravity_run", &[]);
    let line = stdout.lines().find(|l| l.starts_with("j ")).unwrap();
    let peak: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    let m = built
        .bodies
        .iter()
        .find(|(n, _)| n == "b")
        .map(|(_, h)| built.world.bodies[*h].mass() as f64)
        .unwrap();
    assert!(
        peak > m * 1.62 && peak < m * 9.81 * 0.5,
        "peak {peak} N for {m} kg: {stdout}"
    );
    // in a scene file, the scene's gravity, with a notice that the model's is not used
    let t = format!(
        "duration = 0.1\ngravity = [0, 0, -9.81]\n\n[[robots]]\nmjcf = {:?}\n",
        model.display().to_string()
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, t).unwrap();
    let (sc, src) = scene::load(&path).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    assert_eq!(built.world.gravity.z, -9.81);
    assert!(
        built.notices.iter().any(|n| n.contains(
            "<option gravity> = [0, 0, -1.62] m/s² not used: the scene's gravity [0, 0, -9.81] \
             m/s² applies"
        )),
        "{:?}",
        built.notices
    );
    // a model without <option gravity> is z-up in MuJoCo: a scene whose gravity is along
    // -y is told (the shipped pendulum gives none); along -z, nothing to tell
    let pendulum = format!("{}/assets/mjcf/pendulum.xml", env!("CARGO_MANIFEST_DIR"));
    for (gravity, told) in [("[0, -9.81, 0]", true), ("[0, 0, -9.81]", false)] {
        let t = format!("duration = 0.1\ngravity = {gravity}\n\n[[robots]]\nmjcf = {pendulum:?}\n");
        std::fs::write(&path, t).unwrap();
        let (sc, src) = scene::load(&path).unwrap();
        let built = scene::build(&sc, &src).unwrap();
        let notice = "MuJoCo's default gravity (the model gives no <option gravity>) = [0, 0, \
                      -9.81] m/s² not used: the scene's gravity [0, -9.81, 0] m/s² applies";
        assert_eq!(
            built.notices.iter().any(|n| n.contains(notice)),
            told,
            "{gravity}: {:?}",
            built.notices
        );
    }
}

/// A robot file without a joint to simulate (an empty `<mujoco>`, a `<worldbody>` alone,
/// bodies without joints, a free body that `fixed_base` fixes; a URDF of one link) run or
/// checked as a scene of its own is refused naming the file: it ran with 0 joints and
/// exited 0. The library still loads such a file (a fixed prop beside other joints in a
/// scene is legitimate).
#[test]
fn a_robot_file_without_joints_is_refused_as_a_scene_of_its_own() {
    use rapier_kjoint::io::mjcf::MjcfRobot;
    use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
    let dir = tmp("robot_no_joints");
    let inertial = "<inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" \
                    iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>";
    let files = [
        ("empty.xml", "<mujoco/>\n".to_string()),
        (
            "world.xml",
            "<mujoco model=\"m\">\n<worldbody/>\n</mujoco>\n".to_string(),
        ),
        (
            "bodies.xml",
            "<mujoco><worldbody><body name=\"b\" pos=\"0 0 1\"><geom type=\"sphere\" \
             size=\"0.1\"/></body></worldbody></mujoco>"
                .to_string(),
        ),
        (
            "free.xml",
            "<mujoco><worldbody><body name=\"b\" pos=\"0 0 1\"><freejoint/><geom \
             type=\"sphere\" size=\"0.1\"/></body></worldbody></mujoco>"
                .to_string(),
        ),
        (
            "link.urdf",
            format!("<robot name=\"r\"><link name=\"a\">{inertial}</link></robot>"),
        ),
    ];
    for (name, text) in &files {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        for args in [&["run", "--quiet"][..], &["check"]] {
            let command = args[0];
            let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
                .args(args)
                .arg(&path)
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{command} {name}: {stderr}");
            assert!(
                stderr.starts_with(&format!(
                    "kjoint: error: {}: no joints to simulate: ",
                    path.display()
                )),
                "{command} {name}: {stderr}"
            );
            assert!(out.stdout.is_empty(), "{command} {name}: nothing run");
        }
        // the library loads it, without joints
        let d = UrdfOptions::default();
        let joints = if name.ends_with(".urdf") {
            UrdfRobot::from_str(text, name, ".", &d)
                .unwrap()
                .joints
                .len()
        } else {
            MjcfRobot::from_str(text, name, ".", &d)
                .unwrap()
                .joints
                .len()
        };
        assert_eq!(joints, 0, "{name}");
    }
    // one joint is enough: a revolute joint holding a link on the fixed base (a fixed joint
    // is no longer one: its link is fused into the base, `UrdfOptions::fuse_fixed_joints`)
    let path = dir.join("two.urdf");
    std::fs::write(
        &path,
        format!(
            "<robot name=\"r\"><link name=\"a\">{inertial}</link><link name=\"b\">{inertial}\
             </link><joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child \
             link=\"b\"/></joint></robot>"
        ),
    )
    .unwrap();
    let text = common::cli::kjoint_check(&path);
    assert!(text.contains("joint `j` (URDF"), "{text}");
}

/// The work a varying load does is booked on the mean of the body's velocities at the
/// substep's start and end, the kinetic energy rapier's update gives it. A free 1 kg cart on
/// a rail (a translational joint), pushed by 10·sin(2πt) N from rest: after half a period it
/// moves at `2·F0/(m·ω)` = 3.183 m/s, the work is its kinetic energy 5.066 J; after a whole
/// period it is at rest again and the work is 0. Booked as `F·Δx` with `Δx = h·v⁺`, each
/// substep added `F²·h²/(2m)`: 0.104 J after the period, 2 % of the energy scale in the
/// residual.
#[test]
fn a_varying_load_s_work_is_the_kinetic_energy_it_gives() {
    let text = r#"
dt = 0.016666666666666666
substeps = 4
duration = 1.0
gravity = [0, 0, 0]
[[bodies]]
name = "cart"
shape = { type = "cuboid", half_extents = [0.05, 0.05, 0.05] }
mass = 1.0
[[joints]]
name = "rail"
body1 = "world"
body2 = "cart"
property = { type = "translational" }
[[loads]]
body = "cart"
force = [10, 0, 0]
function = { sine = { amplitude = 1, frequency = 1 } }
"#;
    let file = tmp("varying-load").join("cart.toml");
    std::fs::write(&file, text).unwrap();
    let (_, half) = run(&file, "varying-load-half", &["--duration", "0.5"]);
    let v = 2.0 * 10.0 / (2.0 * std::f64::consts::PI);
    approx::assert_relative_eq!(load_work(&half), 0.5 * v * v, max_relative = 5e-3);
    let (_, whole) = run(&file, "varying-load-whole", &[]);
    assert!(load_work(&whole).abs() < 1e-4, "{whole}");
    for stdout in [&half, &whole] {
        assert!(residuals(stdout)[0].abs() < 1e-3, "{stdout}");
    }
}

/// A flywheel on a revolute joint and a free one beside it, both spinning at 500 rad/s with
/// nothing acting, at 8 substeps a frame: a scene lifts rapier's spin cap (π/4 a step, 377
/// rad/s here) as it lifts its speed cap, so both keep their speed and the kinetic energy
/// 2·½·(0.45 kg·m²)·500² = 112 500 J (they read 377 rad/s and 63 955 J, a −43 % residual,
/// exit 0, before).
#[test]
fn a_scene_s_flywheels_keep_their_spin() {
    let path = write_scene(
        "flywheels",
        r#"dt = 0.016666666666666666
substeps = 8
duration = 1.0
gravity = [0.0, 0.0, 0.0]
[[bodies]]
name = "wheel"
shape = { type = "cylinder", half_height = 0.05, radius = 0.3 }
mass = 10.0
angvel = [0.0, 500.0, 0.0]
[[bodies]]
name = "free_wheel"
shape = { type = "cylinder", half_height = 0.05, radius = 0.3 }
mass = 10.0
translation = [2.0, 0.0, 0.0]
angvel = [0.0, 500.0, 0.0]
[[joints]]
name = "axle"
body1 = "world"
body2 = "wheel"
frame = { axis = [0, 0, 1], angle = 1.5707963267948966 }
property = { type = "revolute" }
"#,
    );
    let (dir, stdout) = run(&path, "flywheels", &[]);
    let axle = Table::read(&dir.join("axle.csv"));
    let last = rows(&axle).pop().unwrap();
    assert!((last["WX"] - 500.0).abs() < 1e-3, "{}", last["WX"]);
    let line = |key: &str| -> f64 {
        let l = stdout.lines().find(|l| l.contains(key)).unwrap();
        l.split_whitespace().last().unwrap().parse().unwrap()
    };
    let (e0, e1) = (
        line("initial kinetic + potential"),
        line("final kinetic + potential"),
    );
    assert!((e0 - 112_500.0).abs() < 1.0, "{stdout}");
    assert!((e1 - e0).abs() < 1e-4 * e0, "{stdout}");
    assert!(!stdout.contains("warning"), "{stdout}");
}

/// A load applied at once at `t = 0` rings in a joint's penalty spring: the summary's
/// `peak |F|` is what the joint transmitted then, and a note under the table says so and
/// gives the largest force from 0.1 s on. A 1 kg ball hung at rest on a ball joint of
/// `Kn` = 1e4 N/m (ω = 100 rad/s, resolved at 16 substeps) and `Cr` = 0.3, with gravity
/// switched on at the start, peaks at 1.64 times its weight at 28 ms; from 0.1 s on its
/// largest force is 1.17 times it, the ringing fading (an offshore engineer read the riser scene's 34 364 N
/// start-up peak as the design load of a 19 620 N riser; a trial, 2026-12-04). (A user
/// `Kn`: the automatic stiffness differs between precisions, the f32 one softened by its
/// noise bound. With it the same ball peaked at 17.11 N in f32 and 10.04 N in f64, no
/// overshoot, which the CI's f64 stage found.)
#[test]
fn the_summary_notes_a_start_up_peak_and_the_largest_force_after_it() {
    let path = common::cli::temp_file(
        "start-up-peak",
        "hang.toml",
        "duration = 0.5\ngravity = [0, -9.81, 0]\n[[bodies]]\nname = \"ball\"\n\
         shape = { type = \"ball\", radius = 0.1 }\nmass = 1.0\ntranslation = [0, -1, 0]\n\
         [[joints]]\nname = \"rod\"\nbody1 = \"world\"\nbody2 = \"ball\"\n\
         anchor1 = [0, 0, 0]\nanchor2 = [0, 1, 0]\n\
         property = { type = \"spherical\", kn = 1e4, critical_damping = 0.3 }\n",
    );
    let out = common::cli::kjoint_run(&path, None, &[] as &[&str]);
    let note = out
        .lines()
        .find(|l| l.contains("note: `rod`'s peak |F|"))
        .unwrap_or_else(|| panic!("{out}"));
    let number_after = |key: &str| -> f64 {
        let rest = &note[note.find(key).unwrap_or_else(|| panic!("{note}")) + key.len()..];
        rest.split_whitespace().next().unwrap().parse().unwrap()
    };
    let (peak, at, late) = (
        number_after("peak |F| "),
        number_after("came at t = "),
        number_after("its largest |F| is "),
    );
    // (16.09 N at 28 ms, 11.51 N from 0.1 s on: the ringing fades)
    assert!(peak > 1.4 * 9.81 && at < 0.1, "{note}");
    assert!((0.99 * 9.81..1.25 * 9.81).contains(&late), "{note}");
}

/// Seven balls hung as in the test above, 1 m apart: the summary notes five start-up peaks
/// one by one and counts the other two in one line (500 joints under gravity made 500
/// notes; a review, 2026-12-04).
#[test]
fn the_summary_notes_five_start_up_peaks_and_counts_the_rest() {
    let mut text = String::from("duration = 0.3\ngravity = [0, -9.81, 0]\n");
    for i in 0..7 {
        text += &format!(
            "[[bodies]]\nname = \"ball{i}\"\nshape = {{ type = \"ball\", radius = 0.1 }}\n\
             mass = 1.0\ntranslation = [{i}, -1, 0]\n\
             [[joints]]\nname = \"rod{i}\"\nbody1 = \"world\"\nbody2 = \"ball{i}\"\n\
             anchor1 = [{i}, 0, 0]\nanchor2 = [0, 1, 0]\n\
             property = {{ type = \"spherical\", kn = 1e4, critical_damping = 0.3 }}\n"
        );
    }
    let path = common::cli::temp_file("start-up-peaks", "hang7.toml", &text);
    let out = common::cli::kjoint_run(&path, None, &[] as &[&str]);
    let notes = out.lines().filter(|l| l.contains("'s peak |F|")).count();
    assert_eq!(notes, 5, "{out}");
    assert!(
        out.lines()
            .any(|l| l.contains("note: and 2 more joints whose peak |F| came before")),
        "{out}"
    );
}

/// The riser scene run 3 s where its flex joint switches to the dynamic law at 4 s: the
/// summary says the switch did not come and the joint stayed quasi-static (an offshore
/// engineer read such a run as one of the dynamic law: nothing said otherwise).
#[test]
fn a_flex_joint_switch_after_the_run_s_end_is_noted() {
    let (_, stdout) = run(
        &scene("riser_flexjoint"),
        "riser_short",
        &["--duration", "3"],
    );
    assert!(
        stdout.contains(
            "note: flex joint `flexjoint`'s switch to its dynamic bending law at 4.000 s did \
             not come within the run (it ended at 3.000 s): it stayed in its quasi-static \
             phase"
        ),
        "{stdout}"
    );
}

/// `kjoint check` prints each joint's axes in the world at the start: the riser scene's
/// flex joint has its x down the riser (its `frame` turns the world axes −90° about z), the
/// axis an offshore engineer could not see when a scene without `frame` gave the world's.
#[test]
fn check_prints_a_joint_s_axes_in_the_world() {
    let out = common::cli::kjoint_check(&scene("riser_flexjoint"));
    assert!(
        out.contains(
            "joint `flexjoint` (inline), L0 = 0 m\n  axes in the world at the start: x = [0, \
             -1.000, 0], y = [1.000, 0, 0], z = [0, 0, 1.000]"
        ),
        "{out}"
    );
}

/// An inline flex joint law gets the notices a riser deck's does: a bending law with points
/// at negative angles (never read), one of zero moment everywhere, a dynamic law with no
/// torsion stiffness (both accepted without a word in a scene; an offshore engineer's
/// trial, 2026-12-06). A law of positive points and `Ktor > 0` gets none.
#[test]
fn an_inline_flex_joint_law_gets_the_deck_s_notices() {
    let scene_with = |law: &str| {
        format!(
            r#"dt = 0.016666666666666666
duration = 0.1
gravity = [0.0, 0.0, 0.0]
[[bodies]]
name = "riser"
shape = {{ type = "cylinder", half_height = 5.0, radius = 0.25 }}
mass = 2000.0
translation = [0.0, -5.0, 0.0]
[[joints]]
name = "fj"
body1 = "world"
body2 = "riser"
anchor2 = [0.0, 5.0, 0.0]
frame = {{ axis = [0, 0, 1], angle = -1.5707963267948966 }}
[joints.property]
type = "spherical"
[joints.flex_joint]
{law}
"#
        )
    };
    let check = |name: &str, law: &str| {
        let path = common::cli::temp_file("flex-notices", name, &scene_with(law));
        common::cli::kjoint_check(&path)
    };
    let out = check(
        "neg.toml",
        "bending = [[-0.01, -30000.0], [0.0, 0.0], [0.01, 30000.0]]",
    );
    assert!(
        out.contains(
            "joints[0].flex_joint: the bending law has points at negative angles (from -0.01 \
             rad), which are not used"
        ),
        "{out}"
    );
    let out = check("zero.toml", "bending = [[0.0, 0.0], [0.01, 0.0]]");
    assert!(
        out.contains(
            "the bending law is zero at every angle: in the classical mode, on the total \
             rotation angle, the joint carries no moment at all"
        ),
        "{out}"
    );
    let free = "bending = [[0.0, 0.0], [0.01, 25000.0]]\ndynamic = { torsion_stiffness = 0.0, \
                kdyn_ini = 4.0107e6, kdyn_lim = 1.718873e6, angle_lim = 1.74533e-3, \
                torsion_damping = 3.008e6 }";
    let out = check("free.toml", free);
    assert!(
        out.contains("no torsion law and a torsion stiffness Ktor of 0"),
        "{out}"
    );
    let fine = free.replace("torsion_stiffness = 0.0", "torsion_stiffness = 5.72958e8");
    let out = check("fine.toml", &fine);
    assert!(!out.contains("flex_joint: "), "{out}");
}
