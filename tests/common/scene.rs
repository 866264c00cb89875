//! Scene texts run as `kjoint run` runs them, with the summary watching.

use rapier_kjoint::output::{summary::Summary, Observer};
use rapier_kjoint::scene::{self, BuiltScene, RunStats};

/// The scene `text`, written to `name` in the temporary directory `tag`, built and run for
/// its duration with a [`Summary`] watching: the scene as the run left it, the summary and
/// the run's statistics (`stats.external_work()` for the summary's balance).
pub fn run_with_summary(tag: &str, name: &str, text: &str) -> (BuiltScene, Summary, RunStats) {
    let path = super::cli::temp_file(tag, name, text);
    let (sc, src) = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let mut built = scene::build(&sc, &src).unwrap_or_else(|e| panic!("{e}"));
    let mut summary = Summary::new();
    let stats = scene::run(
        &mut built,
        &Default::default(),
        &mut [&mut summary as &mut dyn Observer],
        &mut |_, _| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    (built, summary, stats)
}
