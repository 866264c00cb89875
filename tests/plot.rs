//! `kjoint run --plot DIR` (cargo feature `plot`): the pictures of the demo scene are PNG
//! files of the documented size with a curve in every panel, one per joint plus the energy
//! balance, and a constant transmitted force is drawn at the pixel row its value gives.

use rapier_kjoint::output::plot::{
    joint_picture_height, COMPONENT_COLORS, ENERGY_HEIGHT, ROW_HEIGHT, TITLE_HEIGHT, WIDTH,
};
use rapier_kjoint::output::{Observer, OutputError};
use rapier_kjoint::scene::{self, RunOptions};
use std::path::{Path, PathBuf};
use std::process::Command;

const DEMO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/demo.toml");

/// A decoded RGB picture.
struct Picture {
    w: usize,
    h: usize,
    rgb: Vec<u8>,
}

impl Picture {
    fn read(path: &Path) -> Picture {
        let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap_or_else(|e| panic!("{path:?} is not a PNG: {e}"));
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb, "{path:?}");
        assert_eq!(info.bit_depth, png::BitDepth::Eight, "{path:?}");
        buf.truncate(info.buffer_size());
        Picture {
            w: info.width as usize,
            h: info.height as usize,
            rgb: buf,
        }
    }

    fn at(&self, x: usize, y: usize) -> [u8; 3] {
        let i = 3 * (y * self.w + x);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }
}

/// Ink of a curve inside a plot area: darker than the white background, the pale grey
/// grid and the pale bands (their channels are all ≥ 190).
fn ink(c: [u8; 3]) -> bool {
    c.iter().any(|v| *v < 190)
}

fn dark(c: [u8; 3]) -> bool {
    c.iter().all(|v| *v < 60)
}

/// The panels of a picture of `rows` rows, the first `halves` of two panels, the others of
/// one (module docs of `output::plot`): `(x0, y0, x1, y1)` \[px\], the caption strip left out.
fn panels(rows: usize, halves: usize) -> Vec<(usize, usize, usize, usize)> {
    let (w, t, r) = (WIDTH as usize, TITLE_HEIGHT as usize, ROW_HEIGHT as usize);
    let mut p = Vec::new();
    for row in 0..rows {
        let y0 = t + row * r + 24;
        let y1 = t + (row + 1) * r;
        if row < halves {
            p.push((0, y0, w / 2, y1));
            p.push((w / 2, y0, w, y1));
        } else {
            p.push((0, y0, w, y1));
        }
    }
    p
}

/// The y axis of a panel: the column with the longest vertical run of dark pixels (plotters
/// draws it just left of the plot area), and the rows where that run starts and ends (the
/// top and the bottom of the plot area: the ends of the y range).
fn y_axis(pic: &Picture, (x0, y0, x1, y1): (usize, usize, usize, usize)) -> (usize, usize, usize) {
    let mut best = (0, 0, 0, 0);
    for x in x0..x1 {
        let mut run_start = None;
        for y in y0..=y1 {
            let d = y < y1 && dark(pic.at(x, y));
            match (d, run_start) {
                (true, None) => run_start = Some(y),
                (false, Some(s)) => {
                    if y - s > best.0 {
                        best = (y - s, x, s, y - 1);
                    }
                    run_start = None;
                }
                _ => {}
            }
        }
    }
    assert!(
        best.0 > ROW_HEIGHT as usize / 2,
        "no y axis in {x0},{y0}: {best:?}"
    );
    (best.1, best.2, best.3)
}

/// The x axis of a panel: the dark run along the row just below the plot area, from the
/// column right of the y axis; its first and last columns (the ends of the time range).
fn x_axis(pic: &Picture, y_axis_col: usize, bottom: usize, x1: usize) -> (usize, usize) {
    let (y, first) = (bottom + 1, y_axis_col + 1);
    assert!(dark(pic.at(first, y)), "no x axis at row {y}");
    let mut x = first;
    while x + 1 < x1 && dark(pic.at(x + 1, y)) {
        x += 1;
    }
    assert!(x - first > 200, "x axis {first}..{x}");
    (first, x)
}

/// A CSV history: header names and rows.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (head, rows)
}

fn column(head: &[String], rows: &[Vec<f64>], name: &str) -> Vec<f64> {
    let i = head.iter().position(|h| h == name).unwrap();
    rows.iter().map(|r| r[i]).collect()
}

fn run_kjoint(scene: &str, args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .args(["run", scene, "-q"])
        .args(args)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

fn temp(name: &str) -> PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("kjoint-plot-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Every panel of a picture has a curve across most of its plot area (right of its y axis,
/// above its x axis).
fn assert_curve_in_every_panel(pic: &Picture, rows: usize, halves: usize, name: &str) {
    for (i, rect) in panels(rows, halves).into_iter().enumerate() {
        let (axis, top, bottom) = y_axis(pic, rect);
        let (_, right) = x_axis(pic, axis, bottom, rect.2);
        let columns = (axis + 1..=right)
            .filter(|x| (top..=bottom).any(|y| ink(pic.at(*x, y))))
            .count();
        let plot_width = right - axis;
        assert!(
            columns as f64 > 0.9 * plot_width as f64,
            "{name}: panel {i} {rect:?}: a curve in {columns} of {plot_width} columns"
        );
    }
}

#[test]
fn plot_of_the_demo_scene_draws_every_joint_and_the_energy_balance() {
    let (dir, csv) = (temp("demo"), temp("demo-csv"));
    let stdout = run_kjoint(
        DEMO,
        &[
            "--plot",
            dir.to_str().unwrap(),
            "--csv",
            csv.to_str().unwrap(),
        ],
    );
    assert!(stdout.contains("pictures (PNG and SVG)"), "{stdout}");

    // the joints and their free DOFs, from the library
    let (sc, src) = scene::load(Path::new(DEMO)).unwrap();
    let built = scene::build(&sc, &src).unwrap();
    let joints: Vec<(String, usize)> = built
        .joints
        .iter()
        .map(|(_, j)| {
            let jt = j.property().joint_type;
            let free = rapier_kjoint::law::Dof::ALL
                .iter()
                .filter(|d| jt.is_free(**d))
                .count();
            (j.name.clone(), free)
        })
        .collect();
    assert_eq!(joints.len(), 2);

    // one PNG and one SVG per joint and the energy balance, nothing else
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    let mut expected: Vec<String> = joints
        .iter()
        .map(|(n, _)| n.clone())
        .chain(["energy".to_string()])
        .flat_map(|n| [format!("{n}.png"), format!("{n}.svg")])
        .collect();
    expected.sort();
    assert_eq!(files, expected);
    for f in files.iter().filter(|f| f.ends_with(".svg")) {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(
            text.contains("<svg") && text.trim_end().ends_with("</svg>"),
            "{f}"
        );
    }

    for (name, free) in &joints {
        let pic = Picture::read(&dir.join(format!("{name}.png")));
        assert_eq!(
            (pic.w, pic.h),
            (WIDTH as usize, joint_picture_height(*free) as usize)
        );
        assert_eq!(pic.h, 40 + 260 * (free + 2), "the documented size");
        assert_curve_in_every_panel(&pic, free + 2, free + 1, name);
    }
    let energy = Picture::read(&dir.join("energy.png"));
    assert_eq!((energy.w, energy.h), (1200, ENERGY_HEIGHT as usize));
    assert_eq!(energy.h, 722, "the documented size");
    // two full-width rows: the energies, the residual
    assert_curve_in_every_panel(&energy, 2, 0, "energy");

    // The block of the slider rests on its stop at the end: it transmits its weight's
    // components, m·g·sin 30° = 9.81 N along the slope (AFX) and m·g·cos 30° = 16.99 N
    // across it (AFY), with the signs of the CSV. Their curves lie at the rows these
    // values give on the axis the documented range rule sets from the CSV's extremes.
    let (head, rows) = read_csv(&csv.join("slider.csv"));
    let (m, g) = (2.0, 9.81);
    let pic = Picture::read(&dir.join("slider.png"));
    let rect = panels(3, 2)[0];
    let (axis_x, top, bottom) = y_axis(&pic, rect);
    let (left, right) = x_axis(&pic, axis_x, bottom, rect.2);
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for c in ["AFX", "AFY", "AFZ"] {
        for v in column(&head, &rows, c) {
            (lo, hi) = (lo.min(v), hi.max(v));
        }
    }
    // the documented rule: the curves' extremes and 0, widened by 5 % of the span
    let (lo, hi) = (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo));
    let time = column(&head, &rows, "time");
    let t_end = *time.last().unwrap();
    let row_of = |v: f64| top as f64 + (hi - v) / (hi - lo) * (bottom - top) as f64;
    let x_of = |t: f64| left as f64 + t / t_end * (right - left) as f64;
    for (c, analytic, color) in [
        ("AFX", m * g * 0.5, COMPONENT_COLORS[0]),
        ("AFY", m * g * (3.0f64).sqrt() / 2.0, COMPONENT_COLORS[1]),
    ] {
        let values = column(&head, &rows, c);
        let last = *values.last().unwrap();
        // the block sits on the friction spring that is its stop, a spring the substep
        // resolves (ω·h = 0.23) with 5 % critical damping, which keeps ringing by about a
        // micrometre (±0.11 N at the end of the run): the mean over the last 30 % of the run
        // is the weight's component, each value within the ringing
        let tail: Vec<f64> = time
            .iter()
            .zip(&values)
            .filter(|(t, _)| **t > 0.7 * t_end)
            .map(|(_, v)| *v)
            .collect();
        let mean = tail.iter().sum::<f64>() / tail.len() as f64;
        assert!(
            (mean.abs() - analytic).abs() < 0.005 * analytic,
            "{c} over the last 30 %: {mean} N, expected ±{analytic} N"
        );
        assert!(
            (last.abs() - analytic).abs() < 0.02 * analytic,
            "{c} at the end: {last} N, expected ±{analytic} N"
        );
        let expected = row_of(analytic.copysign(last));
        // over the last 30 % of the run, every pixel of the curve's colour
        let (mut found, mut worst) = (0, 0.0f64);
        for x in x_of(0.7 * t_end) as usize..x_of(0.98 * t_end) as usize {
            for y in top..=bottom {
                if pic.at(x, y) == color {
                    found += 1;
                    worst = worst.max((y as f64 - expected).abs());
                    assert!(
                        (y as f64 - expected).abs() <= 2.5,
                        "{c}: a pixel at row {y}, the value {} N is at row {expected:.1}",
                        analytic.copysign(last)
                    );
                }
            }
        }
        assert!(found > 100, "{c}: {found} pixels of its colour");
        eprintln!("{c}: {found} pixels within {worst:.1} px of row {expected:.1}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&csv);
}

/// Records what the run loop gives an observer as the work done from outside.
#[derive(Default)]
struct Work(Vec<f64>);

impl Observer for Work {
    fn record(
        &mut self,
        _: f64,
        _: &rapier_kjoint::rapier::pipeline::PhysicsWorld,
        _: &rapier_kjoint::KjointSet,
        _: &[rapier_kjoint::dynamics::KjointEvent],
    ) -> Result<(), OutputError> {
        Ok(())
    }
    fn external_work(&mut self, work: f64) {
        self.0.push(work);
    }
}

#[test]
fn the_energy_balance_gets_the_work_of_the_loads_as_the_run_goes() {
    // a ball on a fixed joint pushed by constant loads: the work grows, and the last value
    // the observers get is the run's work of loads and motions
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/fixed.toml");
    let (sc, src) = scene::load(Path::new(path)).unwrap();
    let mut built = scene::build(&sc, &src).unwrap();
    let mut work = Work::default();
    let stats = scene::run(
        &mut built,
        &RunOptions::default(),
        &mut [&mut work],
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(work.0.len() as u64, stats.frames + 1);
    assert_eq!(work.0[0], 0.0);
    assert!(stats.external_work() > 0.0);
    assert_eq!(*work.0.last().unwrap(), stats.external_work());

    // a joint without a free DOF: the transmitted row and the energy row
    let dir = temp("fixed");
    run_kjoint(path, &["--plot", dir.to_str().unwrap()]);
    let pic = Picture::read(&dir.join("fixed.png"));
    assert_eq!((pic.w, pic.h), (1200, 40 + 2 * 260));
    assert_curve_in_every_panel(&pic, 2, 1, "fixed");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The y tick labels of every panel read distinct values that fall as the label goes down,
/// on axes of any span: the door's bottom pin transmits moments of 1e-11 N·m, whose axis
/// plotters labelled `0.0` at every tick (and `-0.0` below and above them), and its rz
/// (3e-5 rad) had `-0.0` labels above `0.0`.
#[test]
fn tick_labels_read_the_values_of_their_ticks() {
    use rapier_kjoint::output::plot::axis_label;
    assert_eq!(axis_label(0.0, -1.0, 1.0), "0");
    assert_eq!(axis_label(-0.4, -1.0, 1.0), "-0.4");
    assert_eq!(axis_label(-150.0, -230.0, 10.0), "-150");
    assert_eq!(axis_label(0.0005, -1.7e-4, 3.6e-3), "0.0005");
    assert_eq!(axis_label(1e-11, -1.5e-11, 1.4e-11), "1.0e-11");
    assert_eq!(axis_label(-1e-5, -3.3e-5, 1.6e-6), "-1.0e-5");
    assert_eq!(axis_label(5.0e5, 0.0, 2.0e6), "5.0e5");
    assert_eq!(axis_label(1e-17, -1.0, 1.0), "0");

    let door = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/door_torn_off.toml"
    );
    let dir = temp("door");
    run_kjoint(door, &["--plot", dir.to_str().unwrap()]);
    let svg = std::fs::read_to_string(dir.join("bottom.svg")).unwrap();
    let groups = y_ticks(&svg);
    let mut axes = 0;
    for ((x, row), ticks) in groups {
        axes += 1;
        let values: Vec<f64> = ticks.iter().map(|t| t.1.parse().unwrap()).collect();
        assert!(
            values.windows(2).all(|w| w[1] < w[0]),
            "bottom.svg, row {row} at x = {x}: tick labels {ticks:?}"
        );
        assert!(
            ticks
                .iter()
                .all(|t| !t.1.starts_with("-0") || t.1.parse::<f64>().unwrap() != 0.0),
            "bottom.svg, row {row} at x = {x}: a negative zero in {ticks:?}"
        );
    }
    // transmitted force and moment, then force and q of rx, ry, rz, then the energies
    assert_eq!(axes, 9, "{svg}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The energy balance picture keeps the energies of the joints removed during the run, as
/// the summary does: a friction slider that breaks on its dissipated energy (0.5 J) drew its
/// dissipation falling to 0 at the break and a residual of −0.51 J, where the summary's is
/// −0.013 J.
#[test]
fn the_energy_picture_keeps_a_broken_joints_energies() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/translational.toml"
    ))
    .unwrap();
    let text = text.replacen(
        "body2 = \"block\"\n",
        "body2 = \"block\"\nbreak = { dissipated_energy = 0.5 }\n",
        1,
    );
    let dir = temp("broken-energy");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("slider.toml");
    std::fs::write(&scene, text).unwrap();
    let pictures = dir.join("pictures");
    let stdout = run_kjoint(
        scene.to_str().unwrap(),
        &["--plot", pictures.to_str().unwrap()],
    );
    assert!(stdout.contains("broke: dissipated energy"), "{stdout}");
    let residual: f64 = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("residual"))
        .unwrap()
        .split_whitespace()
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    assert!(residual.abs() < 0.03, "{stdout}");
    // the residual panel's y tick labels (second row, left of its axis) span its curve
    let svg = std::fs::read_to_string(pictures.join("energy.svg")).unwrap();
    let row = |y: f64| ((y - TITLE_HEIGHT as f64) / ROW_HEIGHT as f64).floor() as i64;
    let ticks: Vec<f64> = svg
        .split("<text ")
        .skip(1)
        .filter_map(|piece| {
            let y: f64 = piece
                .split("y=\"")
                .nth(1)?
                .split('"')
                .next()?
                .parse()
                .ok()?;
            let x: f64 = piece
                .split("x=\"")
                .nth(1)?
                .split('"')
                .next()?
                .parse()
                .ok()?;
            let text = piece.split('>').nth(1)?.split('<').next()?.trim();
            (row(y) == 1 && x < 70.0)
                .then(|| text.parse().ok())
                .flatten()
        })
        .collect();
    assert!(ticks.len() >= 3, "{ticks:?}");
    let lowest = ticks.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(
        lowest > -0.1,
        "the residual axis reaches {lowest} J; the summary's residual is {residual} J: {ticks:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The y axes' tick labels of an SVG picture, by axis (the labels' `x` and their row of
/// panels), each axis' `(y, text)` from the top down; only numeric labels, on axes of at
/// least three.
fn y_ticks(svg: &str) -> std::collections::BTreeMap<(String, i64), Vec<(f64, String)>> {
    let mut groups: std::collections::BTreeMap<(String, i64), Vec<(f64, String)>> =
        Default::default();
    for piece in svg.split("<text ").skip(1) {
        let attr = |name: &str| -> String {
            piece
                .split(&format!("{name}=\""))
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
                .to_string()
        };
        let text = piece
            .split('>')
            .nth(1)
            .unwrap()
            .split('<')
            .next()
            .unwrap()
            .trim();
        if text.parse::<f64>().is_ok() {
            let y: f64 = attr("y").parse().unwrap();
            let row = ((y - TITLE_HEIGHT as f64) / ROW_HEIGHT as f64).floor() as i64;
            groups
                .entry((attr("x"), row))
                .or_default()
                .push((y, text.to_string()));
        }
    }
    groups.retain(|_, t| t.len() >= 3);
    for ticks in groups.values_mut() {
        ticks.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    groups
}

/// A broken joint's picture ends with the substep it broke in, as its CSV history and the
/// summary do: the door's bottom pin broke transmitting 409 N (AFY −363 N at that substep),
/// and its picture ended at the last record before the break (AFY −223 N; its force axis
/// reached down to −200). The force axis must reach, within one tick, the most negative
/// component of the CSV's last row (the break's substep).
#[test]
fn a_broken_joints_picture_ends_with_the_force_that_broke_it() {
    let door = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/door_torn_off.toml"
    );
    let dir = temp("door-broken");
    let (pictures, csv) = (dir.join("pictures"), dir.join("csv"));
    let stdout = run_kjoint(
        door,
        &[
            "--plot",
            pictures.to_str().unwrap(),
            "--csv",
            csv.to_str().unwrap(),
        ],
    );
    assert!(
        stdout.contains("joint bottom at t = ") && stdout.contains("broke: transmitted force"),
        "{stdout}"
    );
    let (head, rows) = read_csv(&csv.join("bottom.csv"));
    let last = rows.len() - 1;
    let at_break = ["AFX", "AFY", "AFZ"]
        .map(|c| column(&head, &rows, c)[last])
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    assert!(at_break < -300.0, "AFY at the break {at_break} N\n{stdout}");
    let svg = std::fs::read_to_string(pictures.join("bottom.svg")).unwrap();
    // the first row of panels: the transmitted force, left of the moment
    let force_axis = y_ticks(&svg)
        .into_iter()
        .filter(|((_, row), _)| *row == 0)
        .min_by(|a, b| {
            let x = |k: &(String, i64)| k.0.parse::<f64>().unwrap();
            x(&a.0).total_cmp(&x(&b.0))
        })
        .unwrap()
        .1;
    let ticks: Vec<f64> = force_axis.iter().map(|t| t.1.parse().unwrap()).collect();
    let (lowest, spacing) = (ticks[ticks.len() - 1], ticks[0] - ticks[1]);
    assert!(
        lowest - spacing <= at_break,
        "the force axis {ticks:?} stops short of the break's {at_break} N"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
