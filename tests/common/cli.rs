//! Temporary files and `kjoint` runs shared by the tests of the command line and scenes.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `kjoint-{tag}-{pid}` under the system's temporary directory, created if need be.
fn temp_dir(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("kjoint-{tag}-{}", std::process::id()))
}

/// A fresh, empty directory `kjoint-{tag}-{pid}` (emptied if it was there).
pub fn fresh_temp_dir(tag: &str) -> PathBuf {
    let d = temp_dir(tag);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `text` into `name` in the directory `kjoint-{tag}-{pid}` and returns its path.
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
