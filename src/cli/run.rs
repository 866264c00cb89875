//! `kjoint run SCENE`: runs a scene with its observers (the summary, and the CSV histories,
//! rerun recording and pictures asked for) and prints the summary table.

use super::{Failure, LogArg, Out};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rapier_kjoint::figure::{format_figure, plural};
use rapier_kjoint::output::history::HistoryCsv;
use rapier_kjoint::output::summary::{health_counts, health_report, Summary};
use rapier_kjoint::output::Observer;
use rapier_kjoint::scene::schema::LogEvery;
use rapier_kjoint::scene::{self, BuiltScene, RunError, RunOptions, RunStats};
use rapier_kjoint::KjointEvent;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// The files and directories a run writes besides its summary.
#[derive(Default)]
pub(super) struct Outputs {
    /// CSV histories (`--csv`).
    pub csv: Option<PathBuf>,
    /// Rerun recording (`--rrd`).
    pub rrd: Option<PathBuf>,
    /// Pictures (`--plot`).
    pub plot: Option<PathBuf>,
}

/// What the command line overrides of the scene's settings.
pub(super) struct Overrides {
    /// `--substeps`.
    pub substeps: Option<usize>,
    /// `--duration` \[s\].
    pub duration: Option<f64>,
    /// `--log`.
    pub log: Option<LogArg>,
}

/// `kjoint run`: loads, builds and runs the scene at `path`.
pub(super) fn run_file(
    out: Out,
    path: &Path,
    outputs: Outputs,
    overrides: Overrides,
    quiet: bool,
) -> Result<(), Failure> {
    let (mut sc, src, robot_file) = super::load_scene(path)?;
    let mut built = super::build_scene(&sc, &src, robot_file)?;
    let options = RunOptions {
        duration: overrides.duration,
        substeps: overrides.substeps,
        log: overrides.log.map(|l| match l {
            LogArg::Frame => LogEvery::Frame,
            LogArg::Substep => LogEvery::Substep,
        }),
    };
    // every option checked before the first line and before any output is created; a value
    // given on the command line out of its range is a usage error (exit code 2)
    scene::check_run_options(&built, &options).map_err(|e| {
        let given = match &e {
            RunError::Option { option, .. } => match *option {
                "duration" => options.duration.is_some(),
                "substeps" => options.substeps.is_some(),
                _ => false,
            },
            _ => false,
        };
        if given {
            Failure::Usage(e.to_string())
        } else {
            Failure::Input(e.to_string())
        }
    })?;
    // a robot's friction and stop stiffnesses are sized from the substep when it is built
    // (`UrdfOptions::substep`): built again at the substeps the run takes
    if let Some(n) = options.substeps.filter(|n| *n != sc.substeps) {
        sc.substeps = n;
        built = super::build_scene(&sc, &src, robot_file)?;
    }
    let outputs = Outputs {
        csv: outputs.csv.or_else(|| built.csv.clone()),
        rrd: outputs.rrd.or_else(|| built.rrd.clone()),
        plot: outputs.plot,
    };
    // the outputs this build cannot write refused first (nothing is created for them), then
    // the output directories made (or found) before the first line: a path that is a file,
    // or where nothing can be created, fails here rather than once the run has started
    if outputs.rrd.is_some() && !cfg!(feature = "rerun") {
        return Err(RRD_WITHOUT_FEATURE.to_string().into());
    }
    if outputs.plot.is_some() && !cfg!(feature = "plot") {
        return Err(PLOT_WITHOUT_FEATURE.to_string().into());
    }
    for (what, dir) in [("--csv", &outputs.csv), ("--plot", &outputs.plot)] {
        if let Some(dir) = dir {
            std::fs::create_dir_all(dir).map_err(|e| {
                format!(
                    "{what} {}: {e}: expected a directory (created if missing)",
                    dir.display()
                )
            })?;
        }
    }
    say!(out, "scene: {}", path.display());
    for w in &built.warnings {
        say!(out, "  warning: {w}");
    }
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

/// Why `--rrd` is refused by a build without the `rerun` feature.
const RRD_WITHOUT_FEATURE: &str =
    "--rrd: built without the `rerun` feature; rebuild with --features rerun";

/// Why `--plot` is refused by a build without the `plot` feature.
const PLOT_WITHOUT_FEATURE: &str =
    "--plot: built without the `plot` feature; rebuild with --features plot";

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
    Err(RRD_WITHOUT_FEATURE.into())
}

/// The pictures of `--plot`.
#[cfg(feature = "plot")]
fn plot_observer(dir: &Path) -> Result<Box<dyn PlotObserver>, String> {
    Ok(Box::new(rapier_kjoint::output::plot::Plotter::new(dir)))
}

/// The pictures of `--plot`: refused without the `plot` feature.
#[cfg(not(feature = "plot"))]
fn plot_observer(_dir: &Path) -> Result<Box<dyn PlotObserver>, String> {
    Err(PLOT_WITHOUT_FEATURE.into())
}

/// An observer that names the files it wrote.
trait PlotObserver: Observer {
    /// The files written, and the joints without a picture.
    fn written(&self) -> (&[PathBuf], usize);
    /// The observer itself, to be called with the others.
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

/// The observers of a run besides the summary, created (files and directories included)
/// from its [`Outputs`].
struct Recorders {
    /// `--csv`.
    history: Option<HistoryCsv>,
    /// `--rrd`.
    rerun: Option<Box<dyn Observer>>,
    /// `--plot`.
    plotter: Option<Box<dyn PlotObserver>>,
    /// The time of the last record the observers made.
    last: LastRecord,
}

/// The time of the last record of a run (`None` before the first): what partial outputs
/// hold up to.
#[derive(Default)]
struct LastRecord(Option<f64>);

impl Observer for LastRecord {
    fn record(
        &mut self,
        time: f64,
        _world: &rapier_kjoint::rapier::pipeline::PhysicsWorld,
        _joints: &rapier_kjoint::KjointSet,
        _events: &[rapier_kjoint::KjointEvent],
    ) -> Result<(), rapier_kjoint::output::OutputError> {
        self.0 = Some(time);
        Ok(())
    }
}

impl Recorders {
    /// Creates the recorders `outputs` asks for.
    fn new(outputs: &Outputs, built: &BuiltScene) -> Result<Recorders, Failure> {
        let rerun = match &outputs.rrd {
            Some(p) => Some(rerun_observer(p, built)?),
            None => None,
        };
        let plotter = match &outputs.plot {
            Some(dir) => Some(plot_observer(dir)?),
            None => None,
        };
        let history = match &outputs.csv {
            Some(dir) => Some(HistoryCsv::new(dir).map_err(|e| e.to_string())?),
            None => None,
        };
        Ok(Recorders {
            history,
            rerun,
            plotter,
            last: LastRecord::default(),
        })
    }

    /// The error of a failed run, naming what was written up to the failure (flushed) as
    /// partial outputs, and the time of their last record: the end of the last frame the
    /// run completed (the failure's own time is in `e`), or the start when it failed in
    /// its first frame (the joints' histories then hold their headers alone: a joint has
    /// no row before its first evaluation).
    /// Then the health of the run up to the failure (`events`, the summary's, those of
    /// the failing substep included): a warning raised before the failure is often its
    /// cause (a body at rapier's spin cap, a joint stretching under a load it cannot
    /// carry), and the run prints no summary.
    fn failed(&mut self, outputs: &Outputs, e: impl ToString, events: &[KjointEvent]) -> Failure {
        let mut partial = Vec::new();
        if let (Some(dir), Some(h)) = (&outputs.csv, self.history.as_mut()) {
            let _ = h.finish();
            partial.push(dir.display().to_string());
        }
        if let (Some(p), Some(r)) = (&outputs.rrd, self.rerun.as_mut()) {
            let _ = r.finish();
            partial.push(p.display().to_string());
        }
        // the pictures of what was recorded up to the failure
        if let (Some(dir), Some(p)) = (&outputs.plot, self.plotter.as_mut()) {
            if p.finish().is_ok() && !p.written().0.is_empty() {
                partial.push(dir.display().to_string());
            }
        }
        let mut msg = e.to_string();
        let health = health_report(events);
        if !health.is_empty() {
            msg += &format!(
                "\nhealth of the run up to the failure ({}):",
                health_counts(&health)
            );
            for h in &health {
                msg += &format!("\n  {h}");
            }
        }
        if !partial.is_empty() {
            let upto = match self.last.0 {
                Some(t) if t > 0.0 => format!("up to t = {t:.6} s"),
                _ => "of t = 0 only (the run failed in its first frame; a joint's history \
                      has no row before its first evaluation)"
                    .to_string(),
            };
            msg += &format!("\npartial outputs, {upto}: {}", partial.join(", "));
        }
        msg.into()
    }
}

/// The progress bar of a run of `frames` frames (hidden when `quiet` or when standard
/// error is not a terminal).
fn progress_bar(frames: u64, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::with_draw_target(Some(frames), ProgressDrawTarget::hidden());
    }
    let b = ProgressBar::new(frames);
    if let Ok(style) =
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {elapsed_precise} {msg}")
    {
        b.set_style(style);
    }
    b
}

/// Runs a built scene with the summary and the recorders of `outputs`, then prints the
/// summary and what was written.
pub(super) fn simulate(
    out: Out,
    built: &mut BuiltScene,
    options: &RunOptions,
    outputs: Outputs,
    quiet: bool,
) -> Result<(), Failure> {
    scene::check_run_options(built, options).map_err(|e| e.to_string())?;
    let mut recorders = Recorders::new(&outputs, built)?;
    let mut summary = Summary::new();
    let duration = options.duration.unwrap_or(built.duration);
    let frames = (duration / built.frame_dt - 1e-9).ceil().max(1.0) as u64;
    let bar = progress_bar(frames, quiet);
    let stats = {
        let mut observers: Vec<&mut dyn Observer> = vec![&mut summary, &mut recorders.last];
        if let Some(h) = recorders.history.as_mut() {
            observers.push(h);
        }
        if let Some(r) = recorders.rerun.as_mut() {
            observers.push(r.as_mut());
        }
        if let Some(p) = recorders.plotter.as_mut() {
            observers.push(p.observer());
        }
        let mut progress = |i: u64, _n: u64| bar.set_position(i);
        scene::run(built, options, &mut observers, &mut progress)
    };
    bar.finish_and_clear();
    let stats = stats.map_err(|e| recorders.failed(&outputs, e, summary.events()))?;
    report(out, built, &stats, &summary)?;
    report_outputs(out, built, outputs, &recorders)?;
    // a run whose bodies gained energy nothing gave them went wrong: said, and exit code 1
    match summary.energy_created() {
        Some(c) => Err(Failure::Input(c.to_string())),
        None => Ok(()),
    }
}

/// The run's first line and the summary table.
fn report(
    out: Out,
    built: &BuiltScene,
    stats: &RunStats,
    summary: &Summary,
) -> Result<(), Failure> {
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
        joint_count(summary.joints().len(), built.joints.len())
    );
    say_raw!(out, "{}", summary.table(stats.external_work()));
    Ok(())
}

/// The joints of a run (the summary's rows), and how many of them left the set (broke, or
/// a body of theirs was removed): `3 joints (2 removed)`.
fn joint_count(run: usize, left: usize) -> String {
    match run.saturating_sub(left) {
        0 => plural(run, "joint"),
        removed => format!("{} ({removed} removed)", plural(run, "joint")),
    }
}

/// Where the CSV histories and the pictures were written.
fn report_outputs(
    out: Out,
    built: &BuiltScene,
    outputs: Outputs,
    recorders: &Recorders,
) -> Result<(), Failure> {
    if let (Some(dir), Some(h)) = (outputs.csv, &recorders.history) {
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
    if let (Some(dir), Some(p)) = (outputs.plot, &recorders.plotter) {
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
