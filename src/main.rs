//! `kjoint`: runs KJOINT2 scenes and checks scenes and Radioss decks.
//!
//! ```text
//! kjoint                                   # runs the bundled demo scene, prints the summary
//! kjoint run SCENE [--csv DIR] [--rrd FILE] [--substeps N] [--duration T] [--log frame|substep] [--quiet]
//! kjoint check FILE                        # a scene (.toml/.json) or a Radioss deck (.rad)
//! ```
//!
//! Every error is printed with the file, line and field, and the exit code is 1 (2 for a
//! command-line usage error: an unknown option, an option's value that is not a number or
//! is out of its range). Nothing is created before every option is checked. Output
//! that cannot be written is an error with exit code 1 (a full disk), except a pipe whose
//! reader has gone (`kjoint check deck.rad | head -1`), which ends the command quietly with
//! exit code 0.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
