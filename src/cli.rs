//! The `kjoint` command line (clap derive).
//!
//! Everything it prints goes through one handle on standard output ([`say!`]), never
//! `println!`, so that a closed or full output is an error, not a panic: when the reader of
//! a pipe has gone (`kjoint check deck.rad | head -1`), the command ends quietly with exit
//! code 0, like a command killed by SIGPIPE but without the signal; any other write error
//! (`> /dev/full`: no space left) is reported on standard error with exit code 1. Errors go
//! to standard error, and a failure to write them there is ignored.
//!
//! Every option is checked ([`scene::check_run_options`]) before any output (CSV
//! directory, recording) is created.

use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rapier_kjoint::error::fmt_num;
use rapier_kjoint::io::{radioss, riser};
use rapier_kjoint::law::flexjoint::FlexMode;
use rapier_kjoint::law::{ConnectorLaw, Dof, FlexJointConnector, Kjoint2Property};
use rapier_kjoint::output::history::HistoryCsv;
use rapier_kjoint::output::summary::{format_figure, plural, Summary};
use rapier_kjoint::output::Observer;
use rapier_kjoint::rapier::dynamics::JointAxis;
use rapier_kjoint::scene::build::{free_names, MotionKind, PropertyOrigin};
use rapier_kjoint::scene::schema::LogEvery;
use rapier_kjoint::scene::{self, BuiltScene, Format, RunOptions, Source};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The bundled demo scene, run by `kjoint` without arguments.
const DEMO: &str = include_str!("../assets/scenes/demo.toml");

/// The URDF arm scene, run after the demo when the source tree is there.
const ARM_SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/urdf_arm.toml");

#[derive(Parser)]
#[command(
    name = "kjoint",
    version,
    about = "Radioss KJOINT2 penalty joints for rapier: run scenes, check scenes and decks",
    long_about = "Radioss KJOINT2 penalty joints for rapier.\n\nWithout a command, runs the \
                  bundled demo scene (assets/scenes/demo.toml), then the URDF arm \
                  (assets/scenes/urdf_arm.toml), and prints their summaries."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Runs a scene (.toml or .json) and prints the summary table.
    Run {
        /// The scene file.
        scene: PathBuf,
        /// Writes the CSV time histories (one file per joint) into this directory.
        #[arg(long, value_name = "DIR")]
        csv: Option<PathBuf>,
        /// Writes a rerun recording (needs the `rerun` cargo feature).
        #[arg(long, value_name = "FILE")]
        rrd: Option<PathBuf>,
        /// Draws pictures of the run into this directory (PNG and SVG): one per joint
        /// (forces by part, q and its stops, stick/slip/lock, energies) and the energy
        /// balance with the events (needs the `plot` cargo feature).
        #[arg(long, value_name = "DIR")]
        plot: Option<PathBuf>,
        /// Substeps per frame (overrides the scene's `substeps`).
        #[arg(long, value_name = "N")]
        substeps: Option<usize>,
        /// Simulated time \[s\] (overrides the scene's `duration`).
        #[arg(long, value_name = "SECONDS")]
        duration: Option<f64>,
        /// Logs after every frame or every substep (overrides the scene's `output.log`).
        #[arg(long, value_enum)]
        log: Option<LogArg>,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Checks a scene (.toml, .json) or a Radioss deck (.rad): prints every resolved
    /// property (defaults applied, SI units), or the errors.
    Check {
        /// The file.
        file: PathBuf,
    },
}

/// Why a command failed.
enum Failure {
    /// The input is wrong (the message names the file, line and field) or the run failed.
    Input(String),
    /// Standard output could not be written.
    Output(std::io::Error),
}

impl From<String> for Failure {
    fn from(s: String) -> Self {
        Failure::Input(s)
    }
}

/// `writeln!` on the output handle; a write error ends the command ([`Failure::Output`]).
macro_rules! say {
    ($out:expr) => {
        writeln!($out).map_err(Failure::Output)?
    };
    ($out:expr, $($arg:tt)*) => {
        writeln!($out, $($arg)*).map_err(Failure::Output)?
    };
}

/// `write!` on the output handle (no newline).
macro_rules! say_raw {
    ($out:expr, $($arg:tt)*) => {
        write!($out, $($arg)*).map_err(Failure::Output)?
    };
}

/// The output handle.
type Out<'a> = &'a mut dyn Write;

#[derive(Clone, Copy, ValueEnum)]
enum LogArg {
    Frame,
    Substep,
}

/// Entry point of the binary.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let mut stdout = std::io::stdout().lock();
    let out: Out = &mut stdout;
    let result = match cli.command {
        None => run_demo(out),
        Some(Command::Run {
            scene,
            csv,
            rrd,
            plot,
            substeps,
            duration,
            log,
            quiet,
        }) => run_file(
            out,
            &scene,
            Outputs { csv, rrd, plot },
            substeps,
            duration,
            log,
            quiet,
        ),
        Some(Command::Check { file }) => check(out, &file),
    };
    let result = result.and_then(|()| out.flush().map_err(Failure::Output));
    let message = match result {
        Ok(()) => return ExitCode::SUCCESS,
        // the reader has gone (`| head`): nothing more to say, and nobody to say it to
        Err(Failure::Output(e)) if e.kind() == std::io::ErrorKind::BrokenPipe => {
            return ExitCode::SUCCESS
        }
        Err(Failure::Output(e)) => format!("cannot write to standard output: {e}"),
        Err(Failure::Input(e)) => e,
    };
    let _ = writeln!(std::io::stderr(), "kjoint: error: {message}");
    ExitCode::FAILURE
}

fn run_demo(out: Out) -> Result<(), Failure> {
    let src = Source {
        file: PathBuf::from("assets/scenes/demo.toml"),
        text: DEMO.to_string(),
        format: Format::Toml,
    };
    let sc = scene::parse(&src).map_err(|e| e.to_string())?;
    let mut built = scene::build(&sc, &src).map_err(|e| e.to_string())?;
    say!(out, "rapier-kjoint demo: {}", src.file.display());
    simulate_demo(out, &mut built)?;
    // part 2: the URDF arm, read from the source tree (its URDF and mesh are files)
    let arm = Path::new(ARM_SCENE);
    if !arm.is_file() {
        say!(
            out,
            "\n(the URDF arm scene {ARM_SCENE} is not on this machine: skipped)"
        );
        return Ok(());
    }
    say!(out, "\nrapier-kjoint demo, the URDF arm: {ARM_SCENE}");
    let (sc, src) = scene::load(arm).map_err(|e| e.to_string())?;
    let mut built = scene::build(&sc, &src).map_err(|e| e.to_string())?;
    simulate_demo(out, &mut built)
}

/// A scene of the demo: the scene's settings, no outputs, no progress bar.
fn simulate_demo(out: Out, built: &mut BuiltScene) -> Result<(), Failure> {
    simulate(out, built, &RunOptions::default(), Outputs::default(), true)
}

/// The files and directories a run writes besides its summary.
#[derive(Default)]
struct Outputs {
    /// CSV histories (`--csv`).
    csv: Option<PathBuf>,
    /// Rerun recording (`--rrd`).
    rrd: Option<PathBuf>,
    /// Pictures (`--plot`).
    plot: Option<PathBuf>,
}

#[allow(clippy::too_many_arguments)]
fn run_file(
    out: Out,
    path: &Path,
    outputs: Outputs,
    substeps: Option<usize>,
    duration: Option<f64>,
    log: Option<LogArg>,
    quiet: bool,
) -> Result<(), Failure> {
    let (sc, src) = scene::load(path).map_err(|e| e.to_string())?;
    let mut built = scene::build(&sc, &src).map_err(|e| e.to_string())?;
    let options = RunOptions {
        duration,
        substeps,
        log: log.map(|l| match l {
            LogArg::Frame => LogEvery::Frame,
            LogArg::Substep => LogEvery::Substep,
        }),
    };
    let outputs = Outputs {
        csv: outputs.csv.or_else(|| built.csv.clone()),
        rrd: outputs.rrd.or_else(|| built.rrd.clone()),
        plot: outputs.plot,
    };
    // every option checked before the first line and before any output is created
    scene::check_run_options(&built, &options).map_err(|e| e.to_string())?;
    say!(out, "scene: {}", path.display());
    if !built.notices.is_empty() {
        say!(
            out,
            "  {} from the inputs (approximations, skipped items): `kjoint check {}` lists them",
            plural(built.notices.len(), "notice"),
            path.display()
        );
    }
    simulate(out, &mut built, &options, outputs, quiet)
}

/// The rerun logger of `--rrd`: bodies named as in the scene, URDF visual meshes drawn.
#[cfg(feature = "rerun")]
fn rerun_observer(path: &Path, built: &BuiltScene) -> Result<Box<dyn Observer>, String> {
    let names = built.bodies.iter().map(|(n, h)| (*h, n.clone())).collect();
    rapier_kjoint::output::rerun_log::RerunLogger::save(path)
        .map(|l| {
            Box::new(
                l.with_body_names(names)
                    .with_visual_meshes(&built.visual_meshes),
            ) as Box<dyn Observer>
        })
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The rerun logger of `--rrd`: refused without the `rerun` feature.
#[cfg(not(feature = "rerun"))]
fn rerun_observer(_path: &Path, _built: &BuiltScene) -> Result<Box<dyn Observer>, String> {
    Err("--rrd: built without the `rerun` feature; rebuild with --features rerun".into())
}

/// The pictures of `--plot`.
#[cfg(feature = "plot")]
fn plot_observer(dir: &Path) -> Result<Box<dyn PlotObserver>, String> {
    Ok(Box::new(rapier_kjoint::output::plot::Plotter::new(dir)))
}

/// The pictures of `--plot`: refused without the `plot` feature.
#[cfg(not(feature = "plot"))]
fn plot_observer(_dir: &Path) -> Result<Box<dyn PlotObserver>, String> {
    Err("--plot: built without the `plot` feature; rebuild with --features plot".into())
}

/// An observer that names the files it wrote.
trait PlotObserver: Observer {
    /// The files written, and the joints without a picture.
    fn written(&self) -> (&[PathBuf], usize);
    fn observer(&mut self) -> &mut dyn Observer;
}

#[cfg(feature = "plot")]
impl PlotObserver for rapier_kjoint::output::plot::Plotter {
    fn written(&self) -> (&[PathBuf], usize) {
        (self.files(), self.joints_left_out())
    }
    fn observer(&mut self) -> &mut dyn Observer {
        self
    }
}

fn simulate(
    out: Out,
    built: &mut BuiltScene,
    options: &RunOptions,
    outputs: Outputs,
    quiet: bool,
) -> Result<(), Failure> {
    let Outputs { csv, rrd, plot } = outputs;
    scene::check_run_options(built, options).map_err(|e| e.to_string())?;
    let mut rerun = match &rrd {
        Some(p) => Some(rerun_observer(p, built)?),
        None => None,
    };
    let mut plotter = match &plot {
        Some(dir) => Some(plot_observer(dir)?),
        None => None,
    };
    let mut history = match &csv {
        Some(dir) => Some(HistoryCsv::new(dir).map_err(|e| e.to_string())?),
        None => None,
    };
    let mut summary = Summary::new();
    let duration = options.duration.unwrap_or(built.duration);
    let frames = (duration / built.frame_dt - 1e-9).ceil().max(1.0) as u64;
    let bar = if quiet || !std::io::stderr().is_terminal() {
        ProgressBar::with_draw_target(Some(frames), ProgressDrawTarget::hidden())
    } else {
        let b = ProgressBar::new(frames);
        if let Ok(style) =
            ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {elapsed_precise} {msg}")
        {
            b.set_style(style);
        }
        b
    };
    let stats = {
        let mut observers: Vec<&mut dyn Observer> = vec![&mut summary];
        if let Some(h) = history.as_mut() {
            observers.push(h);
        }
        if let Some(r) = rerun.as_mut() {
            observers.push(r.as_mut());
        }
        if let Some(p) = plotter.as_mut() {
            observers.push(p.observer());
        }
        let mut progress = |i: u64, _n: u64| bar.set_position(i);
        scene::run(built, options, &mut observers, &mut progress)
    };
    bar.finish_and_clear();
    let stats = match stats {
        Ok(stats) => stats,
        Err(e) => {
            // what was written up to the failure is flushed and named as partial
            let mut partial = Vec::new();
            if let (Some(dir), Some(h)) = (&csv, history.as_mut()) {
                let _ = h.finish();
                partial.push(dir.display().to_string());
            }
            if let (Some(p), Some(r)) = (&rrd, rerun.as_mut()) {
                let _ = r.finish();
                partial.push(p.display().to_string());
            }
            // the pictures of what was recorded up to the failure
            if let (Some(dir), Some(p)) = (&plot, plotter.as_mut()) {
                if p.finish().is_ok() && !p.written().0.is_empty() {
                    partial.push(dir.display().to_string());
                }
            }
            let mut msg = e.to_string();
            if !partial.is_empty() {
                msg += &format!(
                    "\npartial outputs, up to t = {:.6} s: {}",
                    built.joints.time(),
                    partial.join(", ")
                );
            }
            return Err(msg.into());
        }
    };
    let rapier = match built.rapier_joints.len() {
        0 => String::new(),
        n => format!(", {}", plural(n, "rapier joint")),
    };
    say!(
        out,
        "{:.4} s simulated: {} of {} s, {} each, {}{rapier}\n",
        stats.time,
        plural(stats.frames as usize, "frame"),
        format_figure(built.frame_dt),
        plural(built.joints.settings().substeps, "substep"),
        plural(built.joints.len(), "joint")
    );
    say_raw!(out, "{}", summary.table(stats.external_work()));
    if let (Some(dir), Some(h)) = (csv, &history) {
        say!(
            out,
            "time histories: {} (index.csv names the file of each joint)",
            dir.display()
        );
        for (joint, file) in h.renamed(&built.joints) {
            say!(
                out,
                "  joint `{joint}`: {} (its name gives a file name already taken)",
                file.display()
            );
        }
    }
    if let (Some(dir), Some(p)) = (plot, &plotter) {
        let (files, left_out) = p.written();
        let names: Vec<String> = files
            .iter()
            .filter(|f| f.extension().is_some_and(|e| e == "png"))
            .filter_map(|f| f.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect();
        say!(
            out,
            "pictures (PNG and SVG): {}: {}",
            dir.display(),
            names.join(", ")
        );
        if left_out > 0 {
            say!(
                out,
                "  the first {} joints only: {left_out} more have no picture",
                names.len() - 1
            );
        }
    }
    Ok(())
}

fn check(out: Out, path: &Path) -> Result<(), Failure> {
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
        let deck = radioss::read_file(path).map_err(|e| e.to_string())?;
        say!(out, "deck: {}", path.display());
        for n in &deck.notices {
            say!(out, "  notice, line {}: {}", n.line, n.message);
        }
        if deck.properties.is_empty() {
            say!(out, "  no /PROP/TYPE45 (KJOINT2) property");
        }
        for e in deck.properties.values() {
            let unit = match &e.unit {
                Some(u) => format!(
                    "unit_ID {} (mass {} kg, length {} m, time {} s), converted to SI",
                    e.unit_id.unwrap_or(0),
                    u.mass,
                    u.length,
                    u.time
                ),
                None => "no unit_ID: values taken as SI".into(),
            };
            say!(
                out,
                "\nproperty {} `{}` (line {}, {}; {unit})",
                e.id,
                e.title,
                e.line,
                e.keyword
            );
            say_raw!(out, "{}", describe(&e.property_si, "  "));
            for (k, s) in [("Skew_ID1", e.skew1), ("Skew_ID2", e.skew2)] {
                if let Some(s) = s {
                    say!(out, "  {k} = {s}");
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
        return Ok(());
    }
    let (sc, src) = scene::load(path).map_err(|e| e.to_string())?;
    let mut built = scene::build(&sc, &src).map_err(|e| e.to_string())?;
    // mass properties (URDF inertias included), computed by a step that moves nothing
    built.joints.prepare(&mut built.world);
    say!(out, "scene: {}", path.display());
    for n in &built.notices {
        say!(out, "  notice, {n}");
    }
    let u = &built.units;
    say!(
        out,
        "units: {} (mass {} kg, length {} m, time {} s); values below in SI",
        sc.units,
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
    for (name, h) in &built.bodies {
        let b = &built.world.bodies[*h];
        let mass = b.mass();
        let at = b.translation();
        if b.is_dynamic() {
            say!(
                out,
                "body `{name}`: dynamic, mass {mass} kg, at [{}, {}, {}] m",
                at.x,
                at.y,
                at.z
            );
        } else if b.is_kinematic() {
            say!(
                out,
                "body `{name}`: kinematic (a prescribed motion), at [{}, {}, {}] m",
                at.x,
                at.y,
                at.z
            );
        } else {
            say!(
                out,
                "body `{name}`: fixed, at [{}, {}, {}] m",
                at.x,
                at.y,
                at.z
            );
        }
    }
    for ((_, j), origin) in built.joints.iter().zip(&built.origins) {
        let from = match origin {
            PropertyOrigin::Inline => "inline".to_string(),
            PropertyOrigin::Urdf { file } => format!("URDF {}", file.display()),
            PropertyOrigin::Deck { file, id, title } => {
                format!("deck {} prop_ID {id} `{title}`", file.display())
            }
        };
        say!(
            out,
            "\njoint `{}` ({from}), L0 = {} m",
            j.name,
            j.initial_length()
        );
        say_raw!(out, "{}", describe(&j.property, "  "));
        say_raw!(out, "{}", describe_connector(j.connector_law(), "  "));
    }
    for (name, h) in &built.rapier_joints {
        say_raw!(out, "{}", describe_rapier_joint(name, &built.world, *h));
    }
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
            if m.axis == JointAxis::AngX {
                "rad"
            } else {
                "m"
            },
            m.function
        );
    }
    say!(out, "\nok");
    Ok(())
}

/// A rapier impulse joint of a URDF robot: its bodies, free axes, limits and motors (SI).
fn describe_rapier_joint(
    name: &str,
    world: &rapier_kjoint::rapier::pipeline::PhysicsWorld,
    h: rapier_kjoint::rapier::dynamics::ImpulseJointHandle,
) -> String {
    let Some(j) = world.impulse_joints.get(h) else {
        return String::new();
    };
    let d = &j.data;
    let mut s = format!("\nrapier joint `{name}` (impulse joint, solved by rapier)\n");
    for (axis, label, unit, force) in [
        (JointAxis::LinX, "x", "m", "N"),
        (JointAxis::LinY, "y", "m", "N"),
        (JointAxis::LinZ, "z", "m", "N"),
        (JointAxis::AngX, "rx", "rad", "N·m"),
        (JointAxis::AngY, "ry", "rad", "N·m"),
        (JointAxis::AngZ, "rz", "rad", "N·m"),
    ] {
        if d.locked_axes.contains(axis.into()) {
            continue;
        }
        s += &format!("  {label} free");
        if let Some(l) = d.limits(axis) {
            s += &format!(
                ", limits [{}, {}] {unit}",
                fmt_num(l.min as f64),
                fmt_num(l.max as f64)
            );
        }
        if let Some(m) = d.motor(axis) {
            s += &format!(
                ", motor ({:?}) target {} {unit}, stiffness {} {force}/{unit}, damping {} \
                 {force}·s/{unit}, max force {} {force}",
                m.model,
                fmt_num(m.target_pos as f64),
                fmt_num(m.stiffness as f64),
                fmt_num(m.damping as f64),
                fmt_num(m.max_force as f64)
            );
        }
        s += "\n";
    }
    s
}

/// Every field of a property with its default applied and its unit (SI). Numbers in
/// exponent form when they are very large or small ([`fmt_num`]); curves with their points.
fn describe(p: &Kjoint2Property, indent: &str) -> String {
    let n = fmt_num;
    let mut s = String::new();
    let jt = p.joint_type;
    s += &format!(
        "{indent}type {} ({}), free DOFs: {}\n",
        jt.number(),
        jt.name(),
        free_names(jt)
    );
    let default = |v: f64| if v == 0.0 { " (default)" } else { "" };
    if p.automatic_stiffness() {
        s += &format!("{indent}Kn = 0 N/m: automatic blocked stiffness from the substep\n");
        s += &format!(
            "{indent}ScF = {}{} (scales both automatic stiffnesses)\n",
            n(p.resolved_scale_factor()),
            default(p.scale_factor)
        );
    } else {
        s += &format!("{indent}Kn = {} N/m\n", n(p.kn));
        s += &format!(
            "{indent}ScF = {} m²{} (KR = Kn·max(ScF, L0²))\n",
            n(p.resolved_scale_factor()),
            default(p.scale_factor)
        );
    }
    s += &format!(
        "{indent}Cr = {}{}\n",
        n(p.resolved_critical_damping()),
        default(p.critical_damping)
    );
    s += &format!(
        "{indent}sensor: {}\n",
        p.sensor.map_or("none".to_string(), |id| id.to_string())
    );
    for d in Dof::ALL.iter().filter(|d| jt.is_free(**d)) {
        let law = p.dof(*d);
        let (k, l, v, c, f, sm, sp, ff) = if d.is_rotation() {
            (
                "N·m/rad",
                "rad",
                "rad/s",
                "N·m·s/rad",
                "N·m",
                "SA-",
                "SA+",
                "FM",
            )
        } else {
            ("N/m", "m", "m/s", "N·s/m", "N", "SD-", "SD+", "FF")
        };
        // a curve's points, abscissa unit and ordinate unit (the ordinate is scaled)
        let curve = |c: &Option<rapier_kjoint::Curve>, x: &str, y: &str| match c {
            Some(c) => format!(
                " x curve [{}] ({x}, {y})",
                c.points()
                    .map(|(px, py)| format!("({}, {})", n(px), n(py)))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            None => String::new(),
        };
        let stop = |v: f64| {
            if v == 0.0 {
                "none".to_string()
            } else {
                format!("{} {l}", n(v))
            }
        };
        if law.has_stops() {
            let by = if law.friction_active() {
                format!(
                    "the friction spring Kf = {} {k} (friction active: its cap is lifted \
                     beyond a stop)",
                    n(law.friction_stiffness)
                )
            } else if law.friction_stiffness > 0.0 {
                format!("Kf = {} {k}", n(law.friction_stiffness))
            } else if p.automatic_stiffness() {
                "the automatic blocked stiffness".to_string()
            } else if d.is_rotation() {
                "KR = Kn·max(ScF, L0²)".to_string()
            } else {
                format!("Kn = {} N/m", n(p.kn))
            };
            s += &format!("{indent}{} stop stiffness: {by}\n", d.name());
        }
        let (curve_k, curve_c, curve_f) = (
            curve(&law.stiffness_curve, l, f),
            curve(&law.viscosity_curve, v, f),
            curve(&law.friction_curve, l, f),
        );
        s += &format!(
            "{indent}{}: K = {} {k}{curve_k}; {sm} = {}, {sp} = {}, Icomb = {}; C = {} {c}{curve_c}; \
             Kf = {} {k}, {ff} = {} {f}{curve_f}{}\n",
            d.name(),
            n(law.stiffness_scale()),
            stop(law.stop_min),
            stop(law.stop_max),
            u8::from(law.coupled_stops),
            n(law.viscosity_scale()),
            n(law.friction_stiffness),
            n(law.friction_scale()),
            if law.friction_active() {
                ""
            } else {
                " (friction inactive: needs Kf > 0 and FF > 0 or a curve)"
            }
        );
    }
    s
}

fn check_riser_deck(out: Out, path: &Path) -> Result<(), Failure> {
    let deck = riser::read_riser_deck(path).map_err(|e| e.to_string())?;
    say!(out, "riser deck: {}", path.display());
    for n in &deck.notices {
        say!(out, "  notice, {n}");
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
        say_raw!(out, "{}", describe_connector(&law, "  "));
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

/// The connector law of a joint, in SI (nothing for none).
fn describe_connector(law: &ConnectorLaw, indent: &str) -> String {
    let pts = |c: &rapier_kjoint::Curve| {
        c.points()
            .map(|(x, y)| format!("({} rad, {} N·m)", fmt_num(x), fmt_num(y)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    match law {
        ConnectorLaw::None => String::new(),
        ConnectorLaw::PlanarFriction(p) => {
            let auto = |k: f64, unit: &str, blocked: &str| {
                if k > 0.0 {
                    format!("{} {unit}", fmt_num(k))
                } else {
                    format!("automatic ({blocked})")
                }
            };
            format!(
                "{indent}planar friction: mu = {}, R = {} m, F_int = {} N, M_int = {} N·m, \
                 Kf = {}, Kr = {}\n",
                fmt_num(p.mu),
                fmt_num(p.radius),
                fmt_num(p.internal_force),
                fmt_num(p.internal_moment),
                auto(p.stick_stiffness, "N/m", "the automatic KX of the substep"),
                auto(
                    p.stick_rotational_stiffness,
                    "N·m/rad",
                    "the automatic KR of the substep"
                ),
            )
        }
        ConnectorLaw::FlexJoint(f) => {
            let mode = match f.law.mode() {
                FlexMode::Classical => "classical (law of the total angle)",
                FlexMode::Decoupled => "decoupled bending and torsion",
                FlexMode::Dynamic => "quasi-static bending, then dynamic bilinear hysteretic",
            };
            let mut s = format!("{indent}flex joint: {mode}\n");
            if let Some(c) = &f.law.bending {
                s += &format!("{indent}  bending law (IPRO): {}\n", pts(c));
            }
            if let Some(c) = &f.law.torsion {
                s += &format!("{indent}  torsion law (IPROT): {}\n", pts(c));
            }
            if let Some(d) = &f.law.dynamic {
                s += &format!(
                    "{indent}  *FLEXPROADD: Ktor = {} N·m/rad, Kdyn_ini = {} N·m/rad, \
                     Kdyn_lim = {} N·m/rad, Angle_lim = {} rad, CP = {} N·m·s/rad \
                     (yield moment {} N·m)\n",
                    fmt_num(d.torsion_stiffness),
                    fmt_num(d.kdyn_ini),
                    fmt_num(d.kdyn_lim),
                    fmt_num(d.angle_lim),
                    fmt_num(d.torsion_damping),
                    fmt_num(d.yield_moment())
                );
            }
            s += &format!(
                "{indent}  switch to dynamic: {}\n",
                f.switch_time
                    .map_or("none (only by an explicit call)".to_string(), |t| format!(
                        "at {t} s"
                    ))
            );
            s
        }
    }
}
