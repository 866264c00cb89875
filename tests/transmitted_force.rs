//! The summary reports the force and moment a joint transmitted (from the solve), not the
//! law's `K·q`: its peaks equal the peaks of the magnitudes of the CSV's transmitted-force
//! columns (`√(AFX² + AFY² + AFZ²)`, `√(AMX² + …)`) logged at every substep, through
//! `kjoint run SCENE --csv DIR --log substep` (the summary reads every substep whatever the
//! logging rate), on the cases where the two differ
//! most: a rod hanging at rest on a very stiff joint (`K·q` is 0 when `q` is below f32
//! resolution) and a rod hitting a stop stiffer than the substep resolves.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

mod common;

fn tmp(name: &str) -> PathBuf {
    common::cli::fresh_temp_dir(&format!("transmitted-{name}"))
}

/// Writes `scene` into a fresh directory, runs `kjoint run` on it with `--csv`, and returns
/// the CSV directory and stdout.
fn run(name: &str, scene: &str) -> (PathBuf, String) {
    let dir = tmp(name);
    let file = dir.join("scene.toml");
    std::fs::write(&file, scene).unwrap();
    let csv = dir.join("csv");
    let stdout = common::cli::kjoint_run(&file, Some(&csv), &["--log", "substep"]);
    (csv, stdout)
}

/// Largest magnitude `√(Σ x²)` of the given columns over the rows of a CSV file.
fn csv_peak(path: &Path, columns: &[&str]) -> f64 {
    let text = std::fs::read_to_string(path).unwrap();
    // a zero is written 0e0, never -0e0 (these rods' blocked DOFs carry signed zeros)
    assert!(
        !text.split([',', '\n']).any(|c| c == "-0e0"),
        "{}: a cell -0e0",
        path.display()
    );
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let idx: Vec<usize> = columns
        .iter()
        .map(|c| header.iter().position(|h| h == c).expect("column"))
        .collect();
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            idx.iter().map(|&i| v[i] * v[i]).sum::<f64>().sqrt()
        })
        .fold(0.0, f64::max)
}

/// The summary's figures of a joint by column heading.
fn summary_row(stdout: &str, joint: &str) -> HashMap<&'static str, f64> {
    let line = stdout
        .lines()
        .find(|l| l.split_whitespace().next() == Some(joint))
        .unwrap_or_else(|| panic!("no summary line for {joint}:\n{stdout}"));
    let v: Vec<f64> = line
        .split_whitespace()
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect();
    let heads = ["peak|F|", "peak|M|", "law|F|", "law|M|", "end|F|", "end|M|"];
    let header = stdout
        .lines()
        .find(|l| l.starts_with("joint "))
        .expect("summary header");
    // the headings are written `peak |F|` (a space before the bars)
    let header = header.replace(" |", "|");
    for h in heads {
        assert!(header.contains(h), "{header}");
    }
    heads.into_iter().zip(v).collect()
}

fn rod_at_rest(kn: f64) -> String {
    format!(
        r#"
dt = 0.016666666666666666
substeps = 4
duration = 1.0
gravity = [0, -9.81, 0]

[[bodies]]
name = "rod"
shape = {{ type = "cuboid", half_extents = [0.02, 0.5, 0.02] }}
mass = 1.0
translation = [0, -0.5, 0]

[[joints]]
name = "pivot"
body1 = "world"
body2 = "rod"
anchor2 = [0, 0.5, 0]
property = {{ type = "spherical", kn = {kn:e} }}
"#
    )
}

#[test]
fn summary_peak_force_is_the_transmitted_force_of_a_rod_at_rest_on_a_very_stiff_joint() {
    for kn in [1e12, 1e15] {
        let (csv, stdout) = run(&format!("rest-{kn:e}"), &rod_at_rest(kn));
        let row = summary_row(&stdout, "pivot");
        let peak_csv = csv_peak(&csv.join("pivot.csv"), &["AFX", "AFY", "AFZ"]);
        println!(
            "Kn = {kn:e}: summary peak|F| {} N, CSV max |AF| {peak_csv} N, law|F| {} N",
            row["peak|F|"], row["law|F|"]
        );
        assert!(
            (row["peak|F|"] - peak_csv).abs() <= 0.01 * peak_csv,
            "summary {} vs CSV {peak_csv}",
            row["peak|F|"]
        );
        // it is the rod's weight, which the joint carries, and so is the force at the end
        assert!(
            (peak_csv - 9.81).abs() < 0.02 * 9.81,
            "transmitted peak {peak_csv} N, weight 9.81 N"
        );
        assert!(
            (row["end|F|"] - 9.81).abs() < 0.01 * 9.81,
            "end |F| {} N, weight 9.81 N",
            row["end|F|"]
        );
    }
}

#[test]
fn summary_peak_moment_is_the_transmitted_moment_of_a_stop_hit() {
    // A 1 m, 1 kg rod along +x on a hinge about world z at its end, released horizontal:
    // gravity swings it down into the stop at rx = −0.3 rad. Kn = 1e6 N/m, so the stop has
    // KR = Kn·ScF = 1e7 N·m/rad, far beyond what the substep resolves for this rod.
    let scene = r#"
dt = 0.016666666666666666
substeps = 4
duration = 1.0
gravity = [0, -9.81, 0]

[[bodies]]
name = "rod"
shape = { type = "cuboid", half_extents = [0.5, 0.02, 0.02] }
mass = 1.0
translation = [0.5, 0, 0]

[[joints]]
name = "hinge"
body1 = "world"
body2 = "rod"
anchor2 = [-0.5, 0, 0]
frame = { axis = [0, 1, 0], angle = -1.5707963267948966 }
property = { type = "revolute", kn = 1e6, rx = { stop_min = -0.3 } }
"#;
    let (csv, stdout) = run("stop", scene);
    let row = summary_row(&stdout, "hinge");
    let path = csv.join("hinge.csv");
    let peak_csv = csv_peak(&path, &["AMX", "AMY", "AMZ"]);
    let law_csv = csv_peak(&path, &["MX", "MY", "MZ"]);
    println!(
        "stop: summary peak|M| {} N·m, CSV max |AM| {peak_csv} N·m; law|M| {} N·m (CSV {law_csv})",
        row["peak|M|"], row["law|M|"]
    );
    assert!(
        (row["peak|M|"] - peak_csv).abs() <= 0.01 * peak_csv,
        "summary {} vs CSV {peak_csv}",
        row["peak|M|"]
    );
    assert!((row["law|M|"] - law_csv).abs() <= 0.01 * law_csv);
    // the stop holds the rod: at rest on it the moment is m·g·(L/2)·cos(0.3) = 4.69 N·m, and
    // the impact (the rod arrives at 4.5 rad/s) transmits more, bounded by the momentum the
    // stop takes in one substep, I·ω/h with I = m·L²/3
    let rest = 9.81 * 0.5 * 0.3f64.cos();
    let bound = (1.0 / 3.0) * 4.6 * 240.0;
    assert!(
        peak_csv > rest && peak_csv < bound,
        "peak {peak_csv} N·m, rest {rest}, bound {bound}"
    );
    // at the end the rod rests on the stop: the summary's end moment is that load (what a
    // user compares with an actuator's rating; the peak is the impact's)
    assert!(
        (row["end|M|"] - rest).abs() < 0.01 * rest,
        "end |M| {} N·m, at rest {rest}",
        row["end|M|"]
    );
    // the law's moment there is the stop's K·q, far above what the joint carries, and a note
    // under the table says so, naming the joint
    assert!(row["law|M|"] > 2.0 * row["peak|M|"], "{stdout}");
    let note = stdout
        .lines()
        .find(|l| l.starts_with("  note: law |F| and |M| are the laws' K·q"))
        .unwrap_or_else(|| panic!("no note:\n{stdout}"));
    assert!(note.contains("`hinge`: law |M|"), "{note}");
}

/// No note on the law's force where it is what the joint carries: a soft spring resolved by
/// the substep (a 1 kg rod on a spherical joint of `Kn` = 200 N/m).
#[test]
fn no_law_note_where_the_law_is_what_the_joint_carries() {
    let scene = rod_at_rest(200.0);
    let (_, stdout) = run("soft", &scene);
    let row = summary_row(&stdout, "pivot");
    assert!(row["law|F|"] < 1.1 * row["peak|F|"], "{stdout}");
    assert!(!stdout.contains("note: law |F|"), "{stdout}");
}
