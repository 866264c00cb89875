//! Scenes: a file describing bodies, KJOINT2 joints, sensors, loads and outputs, and the
//! run loop that simulates it.
//!
//! The data flow is one way: [`load`] parses the text into the pure data of [`schema`]
//! (no rapier); [`build::build`] validates everything, converts it into SI and builds a
//! rapier world, a [`crate::KjointSet`] and the applied loads; [`run::run`] steps it and
//! feeds the [`crate::output::Observer`]s. Nothing is simulated before every input has
//! been checked.
//!
//! Every error names the file, the line and the field, as a path such as
//! `joints[1].property.rx.stop_min`, in a TOML scene as in a JSON one (`json.rs` finds
//! the field of serde_json's errors and the line of a field).

pub mod build;
mod json;
pub mod run;
pub mod schema;

pub use build::{build, BuiltScene, Load};
pub use run::{run, RunError, RunOptions, RunStats};
pub use schema::Scene;

/// The most substeps per frame a scene or a run accepts.
pub const MAX_SUBSTEPS: usize = 100_000;

/// The most frames a scene or a run accepts (`duration / dt`).
pub const MAX_FRAMES: f64 = 1e8;

/// The longest substep (`dt / substeps`, \[s\]) a scene or a run accepts. Far beyond what a
/// joint needs; with substeps of thousands of seconds the bodies move so far in one substep
/// that rapier's f32 continuous collision detection no longer ends (a frame of 1e5 s in 4
/// substeps hung the gripper scene in parry's shape cast).
pub const MAX_SUBSTEP_TIME: f64 = crate::dynamics::MAX_SUBSTEP;

/// Checks the options of a run of `scene` (the duration, the substeps and the number of
/// frames they give) without running anything: call it before creating any output, so that
/// a refused run leaves nothing behind. [`run::run`] checks the duration and the substeps
/// again.
pub fn check_run_options(scene: &BuiltScene, options: &RunOptions) -> Result<(), RunError> {
    let duration = options.duration.unwrap_or(scene.duration);
    if !(duration.is_finite() && duration > 0.0) {
        return Err(RunError::Option {
            option: "duration",
            value: crate::error::compact_number(duration.to_string()),
            expected: "a finite time > 0 [s]",
        });
    }
    let n = options.substeps.unwrap_or(scene.joints.settings().substeps);
    if n == 0 || n > MAX_SUBSTEPS {
        return Err(RunError::Option {
            option: "substeps",
            value: n.to_string(),
            expected: "1 ..= 100000",
        });
    }
    if scene.frame_dt / n as f64 > MAX_SUBSTEP_TIME {
        return Err(RunError::Option {
            option: "substeps",
            value: n.to_string(),
            expected: "enough substeps for a substep dt / substeps <= 1 s",
        });
    }
    if duration / scene.frame_dt > MAX_FRAMES {
        return Err(RunError::Option {
            option: "duration",
            value: crate::error::compact_number(duration.to_string()),
            expected: "at most 1e8 frames of the scene's dt",
        });
    }
    Ok(())
}

use std::fmt;
use std::path::{Path, PathBuf};

/// The format of a scene file, chosen by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `.toml`.
    Toml,
    /// `.json`.
    Json,
}

impl Format {
    /// The format of a path's extension (`None` for anything but `.toml` / `.json`).
    pub fn of(path: &Path) -> Option<Format> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("toml") => Some(Format::Toml),
            Some("json") => Some(Format::Json),
            _ => None,
        }
    }
}

/// An error in a scene: where (file, line, field) and what.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct SceneError {
    /// The scene file.
    pub file: PathBuf,
    /// 1-based line (0 = unknown or the whole file).
    pub line: usize,
    /// The field as a path, e.g. `joints[1].property.rx.stop_min` (empty = the file).
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if self.line > 0 {
            write!(f, ":{}", self.line)?;
        }
        if !self.field.is_empty() {
            write!(f, ": field `{}`", self.field)?;
        }
        write!(f, ": {}", self.message)
    }
}

/// A scene's text and where it comes from, kept to locate fields in error messages.
#[derive(Debug, Clone)]
pub struct Source {
    /// The file (as given).
    pub file: PathBuf,
    /// Its text.
    pub text: String,
    /// Its format.
    pub format: Format,
}

/// One step of a field path: a key or an array index.
#[derive(Debug, Clone, PartialEq)]
pub enum Seg {
    /// A table key.
    Key(String),
    /// An array index (0-based).
    Index(usize),
}

/// A field path, written `a.b[2].c`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FieldPath(pub Vec<Seg>);

impl FieldPath {
    /// The path with one more key.
    pub fn key(&self, k: &str) -> FieldPath {
        let mut p = self.clone();
        p.0.push(Seg::Key(k.to_string()));
        p
    }
    /// The path with one more index.
    pub fn index(&self, i: usize) -> FieldPath {
        let mut p = self.clone();
        p.0.push(Seg::Index(i));
        p
    }
    /// A path from a root key.
    pub fn root(k: &str) -> FieldPath {
        FieldPath::default().key(k)
    }
}

impl fmt::Display for FieldPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, s) in self.0.iter().enumerate() {
            match s {
                Seg::Key(k) if i == 0 => write!(f, "{k}")?,
                Seg::Key(k) => write!(f, ".{k}")?,
                Seg::Index(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

impl Source {
    /// An error at `path` (its line found in the text when possible).
    pub fn error(&self, path: &FieldPath, message: impl Into<String>) -> SceneError {
        SceneError {
            file: self.file.clone(),
            line: self.line_of(path),
            field: path.to_string(),
            message: message.into(),
        }
    }

    /// An error about the file as a whole.
    pub fn file_error(&self, message: impl Into<String>) -> SceneError {
        SceneError {
            file: self.file.clone(),
            line: 0,
            field: String::new(),
            message: message.into(),
        }
    }

    /// The 1-based line of the deepest existing part of `path` (0 when unknown). A JSON
    /// source whose file is not a `.json` scene (the scene [`robot_scene`] makes of a robot
    /// file) has no lines: its text is not the file's.
    pub fn line_of(&self, path: &FieldPath) -> usize {
        let span = match self.format {
            Format::Toml => toml_span(&self.text, path),
            Format::Json if Format::of(&self.file) == Some(Format::Json) => {
                json::span_of(&self.text, path)
            }
            Format::Json => None,
        };
        span.map(|s| line_at(&self.text, s)).unwrap_or(0)
    }
}

/// 1-based line of a byte offset.
pub(crate) fn line_at(text: &str, offset: usize) -> usize {
    let offset = offset.min(text.len());
    text.as_bytes()[..offset]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// Start offset of the deepest part of `path` found in a TOML text.
fn toml_span(text: &str, path: &FieldPath) -> Option<usize> {
    let doc = toml_edit::ImDocument::parse(text).ok()?;
    descend_table(doc.as_table(), &path.0, None)
}

fn descend_table(t: &toml_edit::Table, rest: &[Seg], best: Option<usize>) -> Option<usize> {
    let Some((seg, rest)) = rest.split_first() else {
        return best;
    };
    let Seg::Key(k) = seg else { return best };
    let mut best = t.key(k).and_then(|k| k.span()).map(|s| s.start).or(best);
    match t.get(k) {
        Some(toml_edit::Item::Table(t2)) => {
            best = t2.span().map(|s| s.start).or(best);
            descend_table(t2, rest, best)
        }
        Some(toml_edit::Item::Value(v)) => {
            if rest.is_empty() {
                v.span().map(|s| s.start).or(best)
            } else {
                descend_value(v, rest, best)
            }
        }
        Some(toml_edit::Item::ArrayOfTables(a)) => match rest.split_first() {
            Some((Seg::Index(i), rest)) => match a.get(*i) {
                Some(t) => descend_table(t, rest, t.span().map(|s| s.start).or(best)),
                None => best,
            },
            _ => best,
        },
        _ => best,
    }
}

fn descend_value(v: &toml_edit::Value, rest: &[Seg], best: Option<usize>) -> Option<usize> {
    let best = v.span().map(|s| s.start).or(best);
    let Some((seg, rest)) = rest.split_first() else {
        return best;
    };
    match (seg, v) {
        (Seg::Key(k), toml_edit::Value::InlineTable(t)) => {
            let best = t.key(k).and_then(|k| k.span()).map(|s| s.start).or(best);
            match t.get(k) {
                Some(v2) => descend_value(v2, rest, best),
                None => best,
            }
        }
        (Seg::Index(i), toml_edit::Value::Array(a)) => match a.get(*i) {
            Some(v2) => descend_value(v2, rest, best),
            None => best,
        },
        _ => best,
    }
}

/// Reads and parses a scene file (`.toml` or `.json`): syntax, types and unknown keys are
/// checked here; the values are checked by [`build::build`].
pub fn load(path: &Path) -> Result<(Scene, Source), SceneError> {
    let err = |message: String| SceneError {
        file: path.to_path_buf(),
        line: 0,
        field: String::new(),
        message,
    };
    let format = Format::of(path).ok_or_else(|| {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        // a deck run as a scene said only the extension (an offshore engineer's trial,
        // 2026-12-06: `kjoint run ex2.dat`)
        let deck = if matches!(ext.as_deref(), Some("rad" | "dat" | "inc")) {
            ": a Radioss or riser deck is not a scene; `kjoint check` reads it, and a scene \
             runs it: `property = { deck = \"...\", id = N }` on a joint for a Radioss \
             property, `flex_joint = { deck = \"...\", element = N }` for a riser deck's flex \
             joint (README, \"Scenes and the `kjoint` command\")"
        } else {
            ""
        };
        err(format!(
            "unknown scene format: expected a `.toml` or `.json` extension{deck}"
        ))
    })?;
    let text = crate::io::read_input_text(path).map_err(|e| err(e.kind.to_string()))?;
    let source = Source {
        file: path.to_path_buf(),
        text,
        format,
    };
    let scene = parse(&source)?;
    Ok((scene, source))
}

/// How long a robot file run as a scene of its own ([`robot_scene`]) is simulated \[s\].
pub const ROBOT_SCENE_DURATION: f64 = 2.0;

/// The substeps of a 1/60 s frame of a robot file run as a scene of its own
/// ([`robot_scene`]): 240 Hz, where the implicit automatic stiffness has its full
/// `κ_eff = 16` near the origin (README, "Automatic stiffness"). At a scene's default 16
/// (960 Hz) the bound on f32 pose noise lowers it to its floor `κ = 4` (before that floor,
/// the shipped arm's wrist, bouncing off its stop, bent 0.024 rad under the stiffness the
/// bound left: a warning).
pub const ROBOT_SCENE_SUBSTEPS: usize = 4;

/// A robot file as a scene of its own, for `kjoint check` and `kjoint run`: `None` unless
/// `path` ends in `.urdf` (URDF), `.mjcf` (MJCF) or `.xml` (URDF if its root element is
/// `<robot>`, else MJCF). The scene holds the robot alone with the loader's default
/// options (a fixed base, the automatic stiffness), 1/60 s frames of
/// [`ROBOT_SCENE_SUBSTEPS`] substeps, under gravity along −z (URDF and MJCF robots are
/// z-up: `[0, 0, −9.81]` m/s², or an MJCF model's own `<option gravity>`, as MuJoCo runs
/// it; its `timestep` is not used, a notice says so), for [`ROBOT_SCENE_DURATION`]: the
/// robot hangs limp from its base, which shows
/// whether its joints hold (their gaps, the forces they transmit, the energy balance);
/// `kjoint run` and `kjoint check` refuse a robot file that gives no joint (nothing for
/// KJOINT2 joints to simulate), which this function and [`build()`] accept. The
/// source is written in JSON, its file the robot file, whose directory the robot is read
/// from as a scene's robots are.
pub fn robot_scene(path: &Path) -> Option<Result<(Scene, Source), SceneError>> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    let key = match ext.as_str() {
        "urdf" => "urdf",
        "mjcf" => "mjcf",
        // URDF files are often `.xml` too: told by the root element (`<robot>`)
        "xml" => {
            let urdf = crate::io::read_input_text(path).ok().is_some_and(|text| {
                roxmltree::Document::parse(&text)
                    .is_ok_and(|d| d.root_element().tag_name().name() == "robot")
            });
            if urdf {
                "urdf"
            } else {
                "mjcf"
            }
        }
        _ => return None,
    };
    let name = path.file_name()?.to_string_lossy().into_owned();
    // an MJCF model's own gravity, as MuJoCo runs it (`<option gravity>`)
    let gravity = match key {
        "mjcf" => crate::io::mjcf::model_gravity(path),
        _ => None,
    };
    let text = serde_json::json!({
        "substeps": ROBOT_SCENE_SUBSTEPS,
        "gravity": gravity.unwrap_or(crate::io::mjcf::MUJOCO_GRAVITY),
        "duration": ROBOT_SCENE_DURATION,
        "robots": [{ key: name }],
    })
    .to_string();
    let source = Source {
        file: path.to_path_buf(),
        text,
        format: Format::Json,
    };
    Some(parse(&source).map(|scene| (scene, source)))
}

/// Parses the text of a scene (no value checks; see [`build::build`]).
pub fn parse(source: &Source) -> Result<Scene, SceneError> {
    match source.format {
        Format::Toml => toml::from_str::<Scene>(&source.text).map_err(|e| {
            let offset = e.span().map(|s| s.start);
            let field = offset
                .map(|o| toml_path_at(&source.text, o))
                .unwrap_or_default();
            SceneError {
                file: source.file.clone(),
                line: offset.map(|o| line_at(&source.text, o)).unwrap_or(0),
                field,
                message: e.message().trim().to_string(),
            }
        }),
        Format::Json => serde_json::from_str::<Scene>(&source.text).map_err(|e| {
            let msg = e.to_string();
            // serde_json appends " at line L column C"; the line is reported separately.
            let msg = match msg.rfind(" at line ") {
                Some(p) => msg[..p].to_string(),
                None => msg,
            };
            // the column counts the bytes read on the line: the last one read is the
            // token the error is about (a value, a key, an object's `}`)
            let offset = json::offset_of(&source.text, e.line(), e.column());
            let field = match e.line() {
                0 => String::new(),
                _ => json::path_at(&source.text, offset.saturating_sub(1)).to_string(),
            };
            SceneError {
                file: source.file.clone(),
                line: e.line(),
                field,
                message: msg,
            }
        }),
    }
}

/// The path of the deepest key whose key or value contains byte `offset` of a TOML text.
fn toml_path_at(text: &str, offset: usize) -> String {
    let Ok(doc) = toml_edit::ImDocument::parse(text) else {
        return String::new();
    };
    let mut path = FieldPath::default();
    walk_table(doc.as_table(), offset, &mut path);
    path.to_string()
}

fn contains(span: Option<std::ops::Range<usize>>, offset: usize) -> bool {
    span.is_some_and(|s| s.start <= offset && offset < s.end.max(s.start + 1))
}

fn walk_table(t: &toml_edit::Table, offset: usize, path: &mut FieldPath) -> bool {
    for (k, item) in t.iter() {
        let key_span = t.key(k).and_then(|k| k.span());
        path.0.push(Seg::Key(k.to_string()));
        if contains(key_span.clone(), offset) {
            return true;
        }
        let found = match item {
            toml_edit::Item::Value(v) => {
                let hit = contains(v.span(), offset);
                if hit {
                    walk_value(v, offset, path);
                }
                hit
            }
            toml_edit::Item::Table(t2) => {
                walk_table(t2, offset, path) || contains(t2.span(), offset)
            }
            toml_edit::Item::ArrayOfTables(a) => {
                let mut hit = false;
                for (i, t2) in a.iter().enumerate() {
                    path.0.push(Seg::Index(i));
                    if walk_table(t2, offset, path) || contains(t2.span(), offset) {
                        hit = true;
                        break;
                    }
                    path.0.pop();
                }
                hit
            }
            toml_edit::Item::None => false,
        };
        if found {
            return true;
        }
        path.0.pop();
    }
    false
}

fn walk_value(v: &toml_edit::Value, offset: usize, path: &mut FieldPath) {
    match v {
        toml_edit::Value::InlineTable(t) => {
            for (k, v2) in t.iter() {
                let ks = t.key(k).and_then(|k| k.span());
                if contains(ks, offset) {
                    path.0.push(Seg::Key(k.to_string()));
                    return;
                }
                if contains(v2.span(), offset) {
                    path.0.push(Seg::Key(k.to_string()));
                    walk_value(v2, offset, path);
                    return;
                }
            }
        }
        toml_edit::Value::Array(a) => {
            for (i, v2) in a.iter().enumerate() {
                if contains(v2.span(), offset) {
                    path.0.push(Seg::Index(i));
                    walk_value(v2, offset, path);
                    return;
                }
            }
        }
        _ => {}
    }
}
