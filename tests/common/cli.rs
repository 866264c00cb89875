//! Temporary files and `kjoint` runs shared by the tests of the command line and scenes.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `kjoint-{tag}` in cargo's directory for the integration tests' files
/// (`CARGO_TARGET_TMPDIR`, `target/tmp`): `cargo clean` removes it, and a run of the tests
/// writes over the last run's files instead of leaving a directory per process in the
/// system's temporary directory.
pub fn temp_dir(tag: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("kjoint-{tag}"))
}

/// A fresh, empty directory `kjoint-{tag}` (see [`temp_dir`]; emptied if it was there).
pub fn fresh_temp_dir(tag: &str) -> PathBuf {
    let d = temp_dir(tag);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `text` into `name` in the directory `kjoint-{tag}` (see [`temp_dir`]) and returns
/// its path.
pub fn temp_file(tag: &str, name: &str, text: &str) -> PathBuf {
    let d = temp_dir(tag);
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Runs `kjoint run SCENE [--csv CSV] --quiet ARGS`, asserts that it succeeded (printing its
/// stderr and stdout if not) and returns its stdout.
pub fn kjoint_run<S: AsRef<OsStr>>(scene: &Path, csv: Option<&Path>, args: &[S]) -> String {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_kjoint"));
    cmd.arg("run").arg(scene);
    if let Some(csv) = csv {
        cmd.arg("--csv").arg(csv);
    }
    let out = cmd.arg("--quiet").args(args).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{}: {}\n{stdout}",
        scene.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// `kjoint check FILE`: its stdout, asserting success.
pub fn kjoint_check(path: &Path) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("check")
        .arg(path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).to_string()
}
