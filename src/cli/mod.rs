//! The `kjoint` command line (clap derive): its arguments and [`main`].
//!
//! Everything it prints goes through one handle on standard output (`say!`, below), never
//! `println!`, so that a closed or full output is an error, not a panic: when the reader of
//! a pipe has gone (`kjoint check deck.rad | head -1`), the command ends quietly with exit
//! code 0, like a command killed by SIGPIPE but without the signal; any other write error
//! (`> /dev/full`: no space left) is reported on standard error with exit code 1. Errors go
//! to standard error, and a failure to write them there is ignored.
//!
//! Every option is checked ([`rapier_kjoint::scene::check_run_options`]) before any output
//! (CSV directory, recording) is created.
//!
//! The commands, one file each: `run` (`kjoint run`), `check` (`kjoint check`: a scene, a
//! Radioss deck or a riser deck), `demo` (`kjoint` alone); `describe` writes the
//! properties, connector laws and rapier joints that `check` prints.

use clap::{Parser, Subcommand, ValueEnum};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// `writeln!` on the output handle; a write error ends the command ([`Failure::Output`]).
macro_rules! say {
    ($out:expr) => {
        writeln!($out).map_err($crate::cli::Failure::Output)?
    };
    ($out:expr, $($arg:tt)*) => {
        writeln!($out, $($arg)*).map_err($crate::cli::Failure::Output)?
    };
}

/// `write!` on the output handle (no newline).
macro_rules! say_raw {
    ($out:expr, $($arg:tt)*) => {
        write!($out, $($arg)*).map_err($crate::cli::Failure::Output)?
    };
}

mod check;
mod demo;
mod describe;
mod run;

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
    /// Runs a scene (.toml or .json) and prints the summary table. A robot file (.urdf, or
    /// MJCF .xml) runs as a scene of its own: the robot alone on its fixed base under
    /// gravity along -z (or an MJCF model's own gravity option) for 2 s, at 4 substeps a
    /// 1/60 s frame.
    Run {
        /// The scene file (or a robot file).
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
        #[arg(long, value_name = "N", allow_negative_numbers = true)]
        substeps: Option<usize>,
        /// Simulated time in seconds (overrides the scene's `duration`); runs whole frames,
        /// the last one ending at or after it.
        // (a negative value reaches the option's own check, which names what is expected,
        // rather than clap's "unexpected argument '-1'")
        #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
        duration: Option<f64>,
        /// Logs after every frame or every substep (overrides the scene's `output.log`).
        #[arg(long, value_enum)]
        log: Option<LogArg>,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Checks a scene (.toml, .json), a robot (.urdf, MJCF .xml; as `run` makes a scene
    /// of it), a Radioss deck (.rad, .dat, .inc) or a riser deck (*FLEXJOINT, *SPRINGPRO,
    /// *FLEXPROADD): prints every resolved property or flex joint law (defaults applied,
    /// SI units), or the errors.
    Check {
        /// The file.
        file: PathBuf,
    },
}

/// Why a command failed.
enum Failure {
    /// The input is wrong (the message names the file, line and field) or the run failed.
    Input(String),
    /// A command-line option's value is out of its range (exit code 2, as clap's own
    /// refusals of the command line).
    Usage(String),
    /// Standard output could not be written.
    Output(std::io::Error),
}

impl From<String> for Failure {
    fn from(s: String) -> Self {
        Failure::Input(s)
    }
}

/// The output handle.
type Out<'a> = &'a mut dyn Write;

/// The scene at `path`: a scene file, or a robot file run as a scene of its own
/// ([`rapier_kjoint::scene::robot_scene`]: `.urdf`, `.xml`, `.mjcf`; then `true`).
fn load_scene(
    path: &std::path::Path,
) -> Result<
    (
        rapier_kjoint::scene::Scene,
        rapier_kjoint::scene::Source,
        bool,
    ),
    Failure,
> {
    match rapier_kjoint::scene::robot_scene(path) {
        Some(r) => r
            .map(|(sc, src)| (sc, src, true))
            .map_err(|e| e.to_string().into()),
        None => rapier_kjoint::scene::load(path)
            .map(|(sc, src)| (sc, src, false))
            .map_err(|e| e.to_string().into()),
    }
}

/// [`rapier_kjoint::scene::build()`], its error as the command prints it: a robot file's
/// (`robot_file`, from [`load_scene`]) own error as the robot's loader gives it (file,
/// element, field), without the scene field (`robots[0].urdf`) of the scene made for it.
///
/// A robot file that gives no joint (an empty model, bodies without joints, free joints
/// only, joints between fixed bodies) is refused naming the file: as a scene of its own it
/// would run nothing but rapier's bodies, and `kjoint run` summed up 0 joints with exit
/// code 0. The loaders still describe such a file (a scene may hold it as a fixed prop or
/// a free body beside its own joints).
fn build_scene(
    sc: &rapier_kjoint::scene::Scene,
    src: &rapier_kjoint::scene::Source,
    robot_file: bool,
) -> Result<rapier_kjoint::scene::BuiltScene, Failure> {
    let built = rapier_kjoint::scene::build(sc, src).map_err(|e| {
        if robot_file && e.field.starts_with("robots[0]") {
            Failure::from(e.message)
        } else {
            Failure::from(e.to_string())
        }
    })?;
    if robot_file && built.joints.is_empty() && built.rapier_joints.is_empty() {
        return Err(format!(
            "{}: no joints to simulate: a robot file run as a scene of its own needs at least \
             one joint that holds a moving body (its bodies alone are not a mechanism for \
             KJOINT2 joints; free joints and joints between fixed bodies make none); a scene's \
             [[robots]] still loads it beside joints of its own",
            src.file.display()
        )
        .into());
    }
    Ok(built)
}

/// `--log`: when the observers are called.
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
        None => demo::run_demo(out),
        Some(Command::Run {
            scene,
            csv,
            rrd,
            plot,
            substeps,
            duration,
            log,
            quiet,
        }) => run::run_file(
            out,
            &scene,
            run::Outputs { csv, rrd, plot },
            run::Overrides {
                substeps,
                duration,
                log,
            },
            quiet,
        ),
        Some(Command::Check { file }) => check::check(out, &file),
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
        Err(Failure::Usage(e)) => {
            let _ = writeln!(std::io::stderr(), "kjoint: error: {e}");
            return ExitCode::from(2);
        }
    };
    let _ = writeln!(std::io::stderr(), "kjoint: error: {message}");
    ExitCode::FAILURE
}
