//! `kjoint` without a command: runs the bundled demo scene, then the URDF arm when the
//! source tree is there, and prints their summaries.

use super::run::{simulate, Outputs};
use super::{Failure, Out};
use rapier_kjoint::scene::{self, BuiltScene, Format, RunOptions, Source};
use std::path::{Path, PathBuf};

/// The bundled demo scene, run by `kjoint` without arguments.
const DEMO: &str = include_str!("../../assets/scenes/demo.toml");

/// The URDF arm scene, run after the demo when the source tree is there.
const ARM_SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/urdf_arm.toml");

/// Runs the demo scene, then the URDF arm.
pub(super) fn run_demo(out: Out) -> Result<(), Failure> {
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
