//! CSV time histories: one file per joint, `DIR/<joint name>.csv`, and the events (sensor
//! activations, flex joint phase switches) in `DIR/events.csv` (`time,source,reason`).
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
//! | `IE` | internal energy `Σ ½·Δq·(F_new + F_old)` of the law's force \[J\] |
//! | `VX VY VZ WX WY WZ` | rates [m/s, rad/s] |
//! | `AFX AFY AFZ AMX AMY AMZ` | force \[N\] / moment [N·m] the joint **transmitted** to its bodies over the substep (`−P/h`, `P` the impulse of the implicit update, [`crate::JointState::applied`]): what holds the bodies. Equal to `FX .. MZ` on a resolved DOF in a steady state; the summary's peak force and moment are the peaks of these columns |
//! | `<part>_<DOF>` | the law's force split by source, `part` = `elastic`, `damping`, `friction`, `stop`, `sensor`, `DOF` = `FX .. MZ` [N, N·m] (their sum is `FX .. MZ`) |
//! | `slip_<DOF>` | friction: 0 none, 1 stick, 2 slip |
//! | `contact_<DOF>` | stop contact: 0 none, −1 beyond `SD-`, 1 beyond `SD+`, 2 outside coupled stops |
//! | `locked` | 1 once the sensor lock acts |
//! | `E_elastic` | elastic energy stored in the joint \[J\]: springs, stops, friction springs, lock, and blocked DOFs (these at the stiffness the update realises, `½·K̃·q²`, [`crate::law::JointEnergy::elastic`]) |
//! | `E_damping E_friction E_stop` | work dissipated so far by viscosity and critical damping, by friction slip, by stops \[J\] |
//! | `E_numerical` | work dissipated so far by the numerical damping of the DOFs the substep cannot resolve \[J\] ([`crate::law::JointEnergy::numerical`]) |
//! | `<law>.<channel>` | only for a joint with a connector law: its readout, `law` = `planar_friction` or `flex_joint` ([`crate::law::ConnectorReport::channels`]) |
//!
//! A joint that has not been evaluated yet (the record at time 0) has no row.

use super::{Observer, OutputError};
use crate::dynamics::{KjointEvent, KjointSet};
use crate::law::{FrictionStatus, StopContact};
use rapier3d::pipeline::PhysicsWorld;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

const DOFS: [&str; 6] = ["FX", "FY", "FZ", "MX", "MY", "MZ"];
const PARTS: [&str; 5] = ["elastic", "damping", "friction", "stop", "sensor"];

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
            "E_damping",
            "E_friction",
            "E_stop",
            "E_numerical",
        ]
        .map(String::from),
    );
    h.join(",")
}

/// File name of a joint's history: its name with anything but `[A-Za-z0-9_-.]` replaced
/// by `_`, plus `.csv`.
pub fn file_name(joint: &str) -> String {
    let s: String = joint
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "_-.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{s}.csv")
}

/// Writes the CSV time histories of every joint into a directory.
pub struct HistoryCsv {
    dir: PathBuf,
    files: Vec<Option<(PathBuf, BufWriter<File>)>>,
    events: Option<(PathBuf, BufWriter<File>)>,
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

impl HistoryCsv {
    /// Creates the directory (and its parents) if needed; the files are created at the
    /// first record.
    pub fn new(dir: impl Into<PathBuf>) -> Result<Self, OutputError> {
        let dir = dir.into();
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        Ok(HistoryCsv {
            dir,
            files: Vec::new(),
            events: None,
        })
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

impl Observer for HistoryCsv {
    fn record(
        &mut self,
        _time: f64,
        _world: &PhysicsWorld,
        joints: &KjointSet,
        events: &[KjointEvent],
    ) -> Result<(), OutputError> {
        if self.events.is_none() {
            let path = self.dir.join("events.csv");
            let mut w = BufWriter::new(File::create(&path).map_err(io(&path))?);
            writeln!(w, "time,source,reason").map_err(io(&path))?;
            self.events = Some((path, w));
        }
        if let Some((path, w)) = self.events.as_mut() {
            for e in events {
                writeln!(
                    w,
                    "{},\"{}\",\"{}\"",
                    e.time,
                    e.source.to_string().replace('"', "'"),
                    e.reason.replace('"', "'")
                )
                .map_err(io(path))?;
            }
        }
        if self.files.len() < joints.len() {
            self.files.resize_with(joints.len(), || None);
        }
        for (h, j) in joints.iter() {
            let Some(s) = j.state() else { continue };
            let slot = &mut self.files[h.0];
            if slot.is_none() {
                let path = self.dir.join(file_name(&j.name));
                let mut w = BufWriter::new(File::create(&path).map_err(io(&path))?);
                let mut head = header();
                if let Some(c) = &s.connector {
                    let (law, ch) = c.channels();
                    for (n, _) in ch {
                        head += &format!(",{law}.{n}");
                    }
                }
                writeln!(w, "{head}").map_err(io(&path))?;
                *slot = Some((path, w));
            }
            let (path, w) = slot.as_mut().expect("created above");
            let mut row: Vec<f64> = Vec::with_capacity(80);
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
            row.extend(s.status.iter().map(|st| match st.friction {
                FrictionStatus::None => 0.0,
                FrictionStatus::Stick => 1.0,
                FrictionStatus::Slip => 2.0,
            }));
            row.extend(s.status.iter().map(|st| match st.stop {
                StopContact::None => 0.0,
                StopContact::Min => -1.0,
                StopContact::Max => 1.0,
                StopContact::Coupled => 2.0,
            }));
            row.push(if s.locked { 1.0 } else { 0.0 });
            row.extend([
                s.energy.elastic,
                s.energy.damping,
                s.energy.friction,
                s.energy.stop,
                s.energy.numerical,
            ]);
            if let Some(c) = &s.connector {
                row.extend(c.channels().1.iter().map(|(_, v)| *v));
            }
            let line: Vec<String> = row.iter().map(|v| format!("{v:e}")).collect();
            writeln!(w, "{}", line.join(",")).map_err(io(path))?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        for (path, w) in self.files.iter_mut().flatten().chain(self.events.as_mut()) {
            w.flush().map_err(io(path))?;
        }
        Ok(())
    }
}
