//! CSV time histories: one file per joint, `DIR/<joint name>.csv`, the events (sensor
//! activations, flex joint phase switches, joints detached) in `DIR/events.csv`
//! (`time,source,reason`), and the health notices and warnings of the run
//! (`dynamics::health`) in `DIR/warnings.csv` (`time,severity,source,reason`).
//!
//! # File names
//!
//! A joint's file is its name with anything but `[A-Za-z0-9_-.]` replaced by `_` (a leading
//! `.` too, so that no file is hidden), cut to [`MAX_STEM`] characters, plus `.csv`
//! ([`file_name`]). Names are unique in the directory, compared without case (as on the
//! file systems of macOS and Windows): a joint whose name gives a file already taken — by
//! an earlier joint (`a/b` and `a_b` both give `a_b.csv`), or by `events.csv` and
//! `index.csv` — gets `-2`, `-3`, … before `.csv` (`a_b-2.csv`), in the order of the joint
//! handles. `DIR/index.csv` (`joint,file`) says which file belongs to which joint, for
//! every joint; [`HistoryCsv::file_of`] and [`HistoryCsv::renamed`] give the same in code,
//! and the `kjoint` command lists the renamed joints after the run.
//!
//! The directory and the files are created at the first record, so that a run refused for
//! its options creates nothing: every joint's file with its header (a run that fails before
//! a joint's first evaluation leaves its file with the header alone, as `index.csv` names
//! it), `events.csv`, `warnings.csv` and `index.csv`.
//!
//! Numbers are written in the shortest form that reads back as the same `f64`
//! ([`csv_number`]): integer values (status codes, flags) as integers (`2`, `-1`), the
//! others in full precision (`0.014583333333333332`, `1e-300`).
//!
//! Columns (SI units; forces use the law's internal-force convention, tension positive: body
//! 1 receives `+E·F`, body 2 `−E·F`, in the joint's working frame `E`):
//!
//! | columns | meaning |
//! |---|---|
//! | `time` | \[s\] time at which the joint was evaluated (start of the last substep before the record) |
//! | `FX FY FZ MX MY MZ` | the **law's** total force \[N\] / moment [N·m] per DOF at that time, `F(q, q̇)` (Radioss spring TH): the sum of the parts below. On a DOF stiffer than the substep resolves (`ω·h > 1`: a blocked DOF at a large `Kn`, a stiff stop) it is `K·q` on a `q` near f32 resolution, not the force the joint carries: read `AFX .. AMZ` |
//! | `LX LY LZ` | relative displacements `δ` \[m\] |
//! | `RX RY RZ` | relative rotations `θ` \[rad\] |
//! | `IE` | internal energy `Σ ½·Δq·(F_new + F_old)` of the law's force \[J\] (on a DOF stiffer than the substep resolves, of its `K·q`, not of what the joint transmits: the elastic and dissipated columns are the joint's energy) |
//! | `VX VY VZ WX WY WZ` | rates [m/s, rad/s] |
//! | `AFX AFY AFZ AMX AMY AMZ` | force \[N\] / moment [N·m] the joint **transmitted** to its bodies over the substep (`−P/h`, `P` the impulse of the implicit update, [`crate::JointState::applied`]): what holds the bodies. Equal to `FX .. MZ` on a resolved DOF in a steady state; the summary's peak force and moment are the peaks of their magnitudes `√(AFX² + AFY² + AFZ²)`, `√(AMX² + AMY² + AMZ²)` |
//! | `<part>_<DOF>` | the law's force split by source, `part` = `elastic`, `damping`, `friction`, `stop`, `sensor`, `motor` (a motor's `F_m = −τ`, [`crate::KjointMotor`]), `DOF` = `FX .. MZ` [N, N·m] (their sum is `FX .. MZ`) |
//! | `slip_<DOF>` | friction: 0 none, 1 stick, 2 slip |
//! | `contact_<DOF>` | stop contact: 0 none, −1 beyond `SD-`, 1 beyond `SD+`, 2 outside coupled stops |
//! | `locked` | 1 once the sensor lock acts |
//! | `E_elastic` | elastic energy stored in the joint \[J\] at the end of the last substep before the record (this and the next columns: [`crate::Kjoint::closed_energy`], the law's share of that substep, which it books at its next evaluation, predicted along the motion the bodies made): springs, stops, friction springs, lock, and blocked DOFs (these at the stiffness the update realises, `½·K̃·q²`, [`crate::law::JointEnergy::elastic`]) |
//! | `E_kinetic` | kinetic energy stored in the rotors of the joint's armatures, `Σ ½·a·q̇²` \[J\] ([`crate::law::JointEnergy::kinetic`]; 0 without one) |
//! | `E_damping E_friction E_stop` | work dissipated so far by viscosity and critical damping, by friction slip, by stops, as the law books it at its own force \[J\] |
//! | `E_numerical` | the work the implicit update took from the bodies beyond the law's booking \[J\] ([`crate::law::JointEnergy::numerical`]): the numerical damping of the DOFs the substep cannot resolve, on those DOFs the difference between the transmitted force and the law's, and the update's truncation, of either sign (README "Known limits"). On a stop stiffer than the substep resolves, the impact's inelastic part that the substep cannot resolve is numerical work, and the split between `E_stop` and `E_numerical` is the update's: only the sum `E_damping + E_friction + E_stop + E_numerical` is then the work the joint dissipated (the summary's `dissipated`; README "Known limits") |
//! | `E_motor` | the work the bodies did against the joint's motors \[J\] ([`crate::law::JointEnergy::motor`]): negative while the motors drive them, neither stored nor dissipated (the motors' work on the model is `−E_motor`) |
//! | `<law>.<channel>` | only for a joint with a connector law: its readout, `law` = `planar_friction`, `joint_friction` or `flex_joint` ([`crate::law::ConnectorReport::channels`]) |
//!
//! A joint that has not been evaluated yet (the record at time 0) has no row. A joint that
//! broke or was detached ends with the readout its event carries: a broken joint's last row
//! is the substep it broke in (the transmitted force that met its limit, the summary's
//! `peak |F|`), its energies those added to `KjointSet::removed_energy`. An asleep
//! joint (`dynamics::sleep`: bodies that can sleep, never those of a scene unless a robot's
//! `can_sleep` says so) repeats its last row, `time` the time it was last evaluated at.

use super::{Observer, OutputError};
use crate::dynamics::{KjointEvent, KjointHandle, KjointSet, Severity};
use crate::law::ConnectorLaw;
use crate::rapier::pipeline::PhysicsWorld;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

const DOFS: [&str; 6] = ["FX", "FY", "FZ", "MX", "MY", "MZ"];
const PARTS: [&str; 6] = ["elastic", "damping", "friction", "stop", "sensor", "motor"];

/// The header line of a joint's CSV file (no newline).
pub fn header() -> String {
    let mut h: Vec<String> = ["time", "FX", "FY", "FZ", "MX", "MY", "MZ"]
        .iter()
        .chain(&["LX", "LY", "LZ", "RX", "RY", "RZ", "IE"])
        .chain(&["VX", "VY", "VZ", "WX", "WY", "WZ"])
        .map(|s| s.to_string())
        .collect();
    h.extend(DOFS.iter().map(|d| format!("A{d}")));
    for p in PARTS {
        h.extend(DOFS.iter().map(|d| format!("{p}_{d}")));
    }
    h.extend(DOFS.iter().map(|d| format!("slip_{d}")));
    h.extend(DOFS.iter().map(|d| format!("contact_{d}")));
    h.push("locked".into());
    h.extend(
        [
            "E_elastic",
            "E_kinetic",
            "E_damping",
            "E_friction",
            "E_stop",
            "E_numerical",
            "E_motor",
        ]
        .map(String::from),
    );
    h.join(",")
}

/// Longest file stem of a joint's history, in characters (file systems take 255 bytes).
pub const MAX_STEM: usize = 120;

/// The files of the directory that are not joint histories.
pub const RESERVED: [&str; 3] = ["events.csv", "index.csv", "warnings.csv"];

/// File name of a joint's history before it is made unique (module docs): its name with
/// anything but `[A-Za-z0-9_-.]` (and a leading `.`) replaced by `_`, cut to [`MAX_STEM`]
/// characters, plus `.csv`; `_.csv` for an empty name.
pub fn file_name(joint: &str) -> String {
    format!("{}.csv", file_stem(joint))
}

/// [`file_name`] without its `.csv` (also the stem of a joint's picture, `output::plot`).
pub(crate) fn file_stem(joint: &str) -> String {
    let mut s: String = joint
        .chars()
        .take(MAX_STEM)
        .enumerate()
        .map(|(i, c)| {
            if c.is_ascii_alphanumeric() || "_-".contains(c) || (c == '.' && i > 0) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        s.push('_');
    }
    s
}

/// Unique file names in one directory, compared without case.
#[derive(Debug, Default)]
pub(crate) struct Names {
    taken: std::collections::HashSet<String>,
    /// The extension of the files (no dot).
    ext: &'static str,
}

impl Names {
    /// Names of `.ext` files in a directory that also holds the files `reserved`.
    pub(crate) fn new(reserved: &[&str], ext: &'static str) -> Self {
        let mut n = Names {
            ext,
            ..Names::default()
        };
        for r in reserved {
            n.taken.insert(r.to_ascii_lowercase());
        }
        n
    }

    /// `file_stem(joint).ext`, or with `-2`, `-3`, … before the extension when taken.
    pub(crate) fn claim(&mut self, joint: &str) -> String {
        let (stem, ext) = (file_stem(joint), self.ext);
        let mut name = format!("{stem}.{ext}");
        let mut k = 2;
        while !self.taken.insert(name.to_ascii_lowercase()) {
            name = format!("{stem}-{k}.{ext}");
            k += 1;
        }
        name
    }
}

/// The number as the CSV files write it: the shortest text that reads back as the same
/// `f64` (Rust's `{:?}`), without a trailing `.0`, so that an integer value (a status code,
/// a flag, a count) is written as an integer: `2`, `-1`, `500`, `0.014583333333333332`,
/// `1e-300`, `1e16`, `NaN`, `inf`. A negative zero is written `0`.
pub fn csv_number(v: f64) -> String {
    let text = format!("{:?}", v + 0.0);
    match text.strip_suffix(".0") {
        Some(integer) => integer.to_string(),
        None => text,
    }
}

/// A joint's history file, created with its header when the joint is named (so that
/// `index.csv` never names a file that does not exist), and its writer.
struct JointFile {
    name: String,
    path: PathBuf,
    writer: BufWriter<File>,
    /// Time of the last row written (`-inf` before the first).
    last_time: f64,
}

impl JointFile {
    /// Creates the file `name` in `dir` with its header: [`header`], then the channels of
    /// the joint's connector law, `<law>.<channel>`.
    fn create(dir: &Path, name: String, law: &ConnectorLaw) -> Result<Self, OutputError> {
        let path = dir.join(&name);
        let mut writer = BufWriter::new(File::create(&path).map_err(io(&path))?);
        let mut head = header();
        if let Some((law, channels)) = law.channel_names() {
            for n in channels {
                head += &format!(",{law}.{n}");
            }
        }
        writeln!(writer, "{head}").map_err(io(&path))?;
        Ok(JointFile {
            name,
            path,
            writer,
            last_time: f64::NEG_INFINITY,
        })
    }

    /// Writes the row of readout `s`.
    fn write_row(
        &mut self,
        s: &crate::JointState,
        e: &crate::law::JointEnergy,
    ) -> Result<(), OutputError> {
        let JointFile {
            path,
            writer: w,
            last_time,
            ..
        } = self;
        let mut row: Vec<f64> = Vec::with_capacity(88);
        row.push(s.time);
        row.extend(s.force);
        row.extend(s.q);
        row.push(s.energy.internal);
        row.extend(s.rate);
        row.extend(s.applied);
        row.extend(s.parts.iter().map(|p| p.elastic));
        row.extend(s.parts.iter().map(|p| p.damping));
        row.extend(s.parts.iter().map(|p| p.friction));
        row.extend(s.parts.iter().map(|p| p.stop));
        row.extend(s.parts.iter().map(|p| p.sensor));
        row.extend(s.parts.iter().map(|p| p.motor));
        row.extend(s.status.iter().map(|st| st.friction.code()));
        row.extend(s.status.iter().map(|st| st.stop.code()));
        row.push(if s.locked { 1.0 } else { 0.0 });
        row.extend(e.columns());
        if let Some(c) = &s.connector {
            row.extend(c.channels().1.iter().map(|(_, v)| *v));
        }
        let line: Vec<String> = row.iter().map(|&v| csv_number(v)).collect();
        writeln!(w, "{}", line.join(",")).map_err(io(path))?;
        *last_time = s.time;
        Ok(())
    }
}

/// Writes the CSV time histories of every joint into a directory.
pub struct HistoryCsv {
    dir: PathBuf,
    names: Names,
    /// The file of every joint seen, by handle (named once, when the joint is first seen).
    files: BTreeMap<KjointHandle, JointFile>,
    index: Option<(PathBuf, BufWriter<File>)>,
    events: Option<(PathBuf, BufWriter<File>)>,
    /// The health notices and warnings of the run (`warnings.csv`).
    warnings: Option<(PathBuf, BufWriter<File>)>,
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn csv_text(s: &str) -> String {
    format!("\"{}\"", s.replace('"', "\"\""))
}

impl HistoryCsv {
    /// A writer into `dir`. Nothing is created yet: the directory (and its parents) and the
    /// files are created at the first record.
    pub fn new(dir: impl Into<PathBuf>) -> Result<Self, OutputError> {
        Ok(HistoryCsv {
            dir: dir.into(),
            names: Names::new(&RESERVED, "csv"),
            files: BTreeMap::new(),
            index: None,
            events: None,
            warnings: None,
        })
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The history file of joint `h` (known from the first record on).
    pub fn file_of(&self, h: KjointHandle) -> Option<&Path> {
        self.files.get(&h).map(|f| f.path.as_path())
    }

    /// The joints whose file is not [`file_name`] of their name (it was taken): `(joint
    /// name, file)`.
    pub fn renamed<'a>(&'a self, joints: &'a KjointSet) -> Vec<(&'a str, &'a Path)> {
        joints
            .iter()
            .filter_map(|(h, j)| Some((j, self.files.get(&h)?)))
            .filter(|(j, f)| f.name != file_name(&j.name))
            .map(|(j, f)| (j.name.as_str(), f.path.as_path()))
            .collect()
    }

    /// Writes `events` into `events.csv`, and the notices and warnings among them into
    /// `warnings.csv` (both created, with the directory, at the first call).
    fn write_events(&mut self, events: &[KjointEvent]) -> Result<(), OutputError> {
        if self.events.is_none() {
            std::fs::create_dir_all(&self.dir).map_err(io(&self.dir))?;
            let path = self.dir.join("events.csv");
            let mut w = BufWriter::new(File::create(&path).map_err(io(&path))?);
            writeln!(w, "time,source,reason").map_err(io(&path))?;
            self.events = Some((path, w));
        }
        if self.warnings.is_none() {
            let path = self.dir.join("warnings.csv");
            let mut w = BufWriter::new(File::create(&path).map_err(io(&path))?);
            writeln!(w, "time,severity,source,reason").map_err(io(&path))?;
            self.warnings = Some((path, w));
        }
        if let (Some((path, w)), Some((wpath, ww))) = (self.events.as_mut(), self.warnings.as_mut())
        {
            for e in events {
                let severity = match e.severity() {
                    Severity::Info => None,
                    Severity::Notice => Some("notice"),
                    Severity::Warning => Some("warning"),
                };
                if let Some(severity) = severity {
                    writeln!(
                        ww,
                        "{},{severity},\"{}\",\"{}\"",
                        csv_number(e.time),
                        e.source.to_string().replace('"', "'"),
                        e.kind.to_string().replace('"', "'")
                    )
                    .map_err(io(wpath))?;
                    continue;
                }
                writeln!(
                    w,
                    "{},\"{}\",\"{}\"",
                    csv_number(e.time),
                    e.source.to_string().replace('"', "'"),
                    e.kind.to_string().replace('"', "'")
                )
                .map_err(io(path))?;
            }
        }
        Ok(())
    }

    /// Names the files of joints not seen yet (in the set's order) and lists them in
    /// `index.csv`.
    fn name_new_joints(&mut self, joints: &KjointSet) -> Result<(), OutputError> {
        if joints.iter().all(|(h, _)| self.files.contains_key(&h)) {
            return Ok(());
        }
        if self.index.is_none() {
            let path = self.dir.join("index.csv");
            let mut w = BufWriter::new(File::create(&path).map_err(io(&path))?);
            writeln!(w, "joint,file").map_err(io(&path))?;
            self.index = Some((path, w));
        }
        let (ipath, iw) = self.index.as_mut().expect("created above");
        for (h, j) in joints.iter() {
            if self.files.contains_key(&h) {
                continue;
            }
            let name = self.names.claim(&j.name);
            let file = JointFile::create(&self.dir, name, j.connector_law())?;
            writeln!(iw, "{},{}", csv_text(&j.name), csv_text(&file.name)).map_err(io(ipath))?;
            self.files.insert(h, file);
        }
        Ok(())
    }
}

impl Observer for HistoryCsv {
    fn record(
        &mut self,
        _time: f64,
        world: &PhysicsWorld,
        joints: &KjointSet,
        events: &[KjointEvent],
    ) -> Result<(), OutputError> {
        self.write_events(events)?;
        self.name_new_joints(joints)?;
        // a joint removed in this record's substeps (broken, detached) is no longer in the
        // set: its last readout, carried by its event, is its last row (a broken joint's is
        // the substep it broke in, the force that broke it), unless already written
        for (handle, energy, last) in events.iter().filter_map(KjointEvent::removed_joint) {
            let (Some(last), Some(f)) = (last, self.files.get_mut(&handle)) else {
                continue;
            };
            if last.time > f.last_time {
                f.write_row(last, energy)?;
            }
        }
        for (h, j) in joints.iter() {
            let Some(s) = j.state() else { continue };
            let f = self.files.get_mut(&h).expect("named above");
            f.write_row(s, &j.closed_energy(&world.bodies))?;
        }
        Ok(())
    }

    /// The events since the last record, the failing substep's included, into
    /// `events.csv` and `warnings.csv`; the histories keep their last row.
    fn failed(&mut self, events: &[KjointEvent]) -> Result<(), OutputError> {
        self.write_events(events)
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        for f in self.files.values_mut() {
            f.writer.flush().map_err(io(&f.path))?;
        }
        for (path, w) in self
            .events
            .iter_mut()
            .chain(self.warnings.as_mut())
            .chain(self.index.as_mut())
        {
            w.flush().map_err(io(path))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_the_shortest_round_trip_text_integers_as_integers() {
        for (v, text) in [
            (2.0, "2"),
            (-1.0, "-1"),
            (-0.0, "0"),
            (500.0, "500"),
            (499.99999999999994, "499.99999999999994"),
            (0.014583333333333332, "0.014583333333333332"),
            (1e-300, "1e-300"),
            (1e16, "1e16"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(csv_number(v), text);
            if v.is_finite() {
                assert_eq!(text.parse::<f64>().unwrap(), v);
            }
        }
    }

    #[test]
    fn file_names_are_safe_and_unique_without_case() {
        assert_eq!(file_name("a/b"), "a_b.csv");
        assert_eq!(file_name(".hidden"), "_hidden.csv");
        assert_eq!(file_name("v1.2"), "v1.2.csv");
        assert_eq!(file_name(""), "_.csv");
        assert_eq!(file_name("épaule"), "_paule.csv");
        assert_eq!(file_name(&"x".repeat(300)).len(), MAX_STEM + 4);
        let mut n = Names::new(&RESERVED, "csv");
        let got: Vec<String> = ["events", "index", "a/b", "a_b", "A_B", "a_b-2", "Events"]
            .iter()
            .map(|j| n.claim(j))
            .collect();
        assert_eq!(
            got,
            [
                "events-2.csv",
                "index-2.csv",
                "a_b.csv",
                "a_b-2.csv",
                "A_B-3.csv",
                "a_b-2-2.csv",
                "Events-3.csv"
            ]
        );
    }
}
