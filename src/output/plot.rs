//! Pictures of a run (cargo feature `plot`): `kjoint run SCENE --plot DIR`, or a
//! [`Plotter`] among the observers of [`crate::scene::run()`].
//!
//! # Files
//!
//! At the end of the run (its [`Observer::finish`]) the plotter writes into `DIR`:
//!
//! - one picture per joint, `DIR/<joint>.png` (and `.svg`), the file name made from the
//!   joint's name as the CSV histories make theirs ([`super::history`]: unsafe characters
//!   replaced by `_`, `-2`, `-3`, … when taken); the first [`MAX_JOINTS`] joints only, in
//!   handle order;
//! - the energy balance of the model, `DIR/energy.png` (and `.svg`).
//!
//! [`Plotter::files`] names them. The directory is created at the first record, so that a
//! run refused for its options creates nothing; a run that fails draws what it recorded up
//! to the failure when its caller calls [`Observer::finish`] (the `kjoint` command does).
//!
//! # A joint's picture
//!
//! [`WIDTH`] × [`joint_picture_height`]`(n)` pixels, `n` the joint type's free DOFs: a title
//! strip of [`TITLE_HEIGHT`], then rows of [`ROW_HEIGHT`], each of two panels of half the
//! width, the last row one panel of the whole width:
//!
//! | row | left panel | right panel |
//! |---|---|---|
//! | 0 | force the joint **transmitted** to its bodies, `AFX AFY AFZ` \[N\] ([`crate::JointState::applied`]) | moment transmitted, `AMX AMY AMZ` [N·m] |
//! | 1 … n, a free DOF each | the law's force on the DOF by part (elastic, damping, friction, stop, lock: [`crate::law::ForceParts`]), their sum (law total, [`crate::JointState::force`]) and the transmitted force; background bands: friction sticking, slipping, the sensor lock on | `q` \[m or rad\] with its stops (dashed lines at `SD-`, `SD+` when set); background band: beyond a stop |
//! | n + 1 | the joint's energies \[J\]: stored (elastic, and kinetic in the rotors of its armatures), and the work dissipated so far by damping, friction, stops and the numerical damping of unresolved DOFs ([`crate::law::JointEnergy`]) | |
//!
//! The x, y, z components of the transmitted force and moment are blue, orange and green
//! ([`COMPONENT_COLORS`]). A part that stays 0 over the run is not drawn (its name is left
//! out of the legend). The events that concern the joint (its own, and its sensor's
//! activation) are vertical lines.
//!
//! # The energy balance
//!
//! [`WIDTH`] × [`ENERGY_HEIGHT`] pixels: a title strip, then two panels of the whole width
//! and [`ROW_HEIGHT`] each, then the list of events:
//!
//! - kinetic `K` and gravitational potential `V` energy of the bodies, the elastic energy
//!   `S` stored in the joints, the work `D` they dissipated, their sum `K + V + S + D`, and
//!   the initial energy plus the work done from outside, `E₀ + W` (the loads' and the
//!   prescribed motions', given by the run loop through [`Observer::external_work`]); the
//!   same quantities as the summary's energy balance ([`super::summary`]);
//! - the residual `(K + V + S + D) − (E₀ + W)`, 0 for an exact integration;
//! - events (sensor activations and connector phase switches in purple, health notices in
//!   olive, warnings in red) as numbered vertical lines in both panels, listed below them
//!   (the first [`EVENT_LINES`]).
//!
//! # Axes
//!
//! Time on x, from the first to the last record. Each panel's y axis spans its curves, 0
//! and the drawn stops, widened by 5 % of that span on each side ([`y_range`]); a span
//! below 1e-12 is shown as −1 … 1.
//!
//! # Memory
//!
//! Every record is kept until a history holds [`MAX_SAMPLES`] samples; then two neighbouring
//! samples are merged into one, and each sample from then on covers twice as many records.
//! A sample keeps per curve the minimum and the maximum of its records (drawn in the order
//! they came), so a peak between two drawn points is never lost, and per band whether the
//! state occurred in any of its records (slip drawn over stick). A run of any length holds
//! at most `MAX_SAMPLES` samples per curve: the 6 + 8·n + 7 curves of a joint of `n` free
//! DOFs take at most 12 bytes each per sample (0.7 MB for `n` = 6), the energy balance 7.
//!
//! # Text
//!
//! Text is drawn with a subset of DejaVu Sans (Latin-1, Greek and a few symbols, 32 kB,
//! `assets/fonts/`, the Bitstream Vera and Arev licence beside it) compiled into the crate:
//! the pictures do not depend on the fonts a machine has installed.

use super::history::Names;
use super::{Observer, OutputError};
use crate::dynamics::{energy, EventSource, KjointEvent, KjointHandle, KjointSet, Severity};
use crate::law::JointEnergy;
use crate::law::{Dof, FrictionStatus, JointType, StopContact};
use crate::rapier::pipeline::PhysicsWorld;
use crate::JointState;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::error::Error;
use std::path::{Path, PathBuf};

mod draw;
use draw::*;
pub use draw::{axis_label, COMPONENT_COLORS};

/// Width of every picture \[px\].
pub const WIDTH: u32 = 1200;
/// Height of the title strip at the top of a picture \[px\].
pub const TITLE_HEIGHT: u32 = 40;
/// Height of a row of panels \[px\].
pub const ROW_HEIGHT: u32 = 260;
/// Events listed below the energy balance (the lines mark all of them).
pub const EVENT_LINES: usize = 8;
/// Height of a line of the event list \[px\].
pub const EVENT_LINE_HEIGHT: u32 = 18;
/// Height of the energy balance picture \[px\]: title, two rows, the event list.
pub const ENERGY_HEIGHT: u32 =
    TITLE_HEIGHT + 2 * ROW_HEIGHT + (EVENT_LINES as u32 + 1) * EVENT_LINE_HEIGHT;
/// Most samples a history keeps (module docs, "Memory").
pub const MAX_SAMPLES: usize = 1024;
/// Most joints drawn (the first in handle order): a picture each.
pub const MAX_JOINTS: usize = 64;
/// Most events kept (marked and listed); later ones are counted only.
pub const MAX_EVENTS: usize = 1000;
/// File stem of the energy balance picture.
pub const ENERGY_STEM: &str = "energy";

/// Height of the picture of a joint with `free` free DOFs \[px\]: the title strip and
/// `free + 2` rows.
pub fn joint_picture_height(free: usize) -> u32 {
    TITLE_HEIGHT + ROW_HEIGHT * (free as u32 + 2)
}

/// The y range of a panel whose curves span `lo ..= hi` (0 and the drawn stops included
/// by the caller): widened by 5 % of the span on each side, −1 … 1 for a span below 1e-12.
pub fn y_range(lo: f64, hi: f64) -> (f64, f64) {
    let span = hi - lo;
    if !span.is_finite() || span <= 1e-12 {
        return (-1.0, 1.0);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

/// Minimum and maximum of one curve over the records of a sample.
#[derive(Debug, Clone, Copy)]
struct Span {
    min: f32,
    max: f32,
    /// The minimum came before the maximum.
    min_first: bool,
}

impl Span {
    fn point(v: f64) -> Self {
        Span {
            min: v as f32,
            max: v as f32,
            min_first: true,
        }
    }

    /// The span of `a` followed by `b`.
    fn then(a: Span, b: Span) -> Span {
        let (min, min_late) = if b.min < a.min {
            (b.min, true)
        } else {
            (a.min, false)
        };
        let (max, max_late) = if b.max > a.max {
            (b.max, true)
        } else {
            (a.max, false)
        };
        let min_first = match (min_late, max_late) {
            (false, true) => true,
            (true, false) => false,
            (false, false) => a.min_first,
            (true, true) => b.min_first,
        };
        Span {
            min,
            max,
            min_first,
        }
    }
}

/// A decimated history of several curves and state flags sharing their records (module
/// docs, "Memory").
#[derive(Debug, Clone)]
struct Track {
    curves: usize,
    flags: usize,
    /// Records per sample.
    width: u64,
    /// Records in the last sample.
    open: u64,
    /// First and last time of each sample \[s\].
    times: Vec<[f64; 2]>,
    /// `samples × curves`.
    spans: Vec<Span>,
    /// `samples × flags`: the union of the records' flags.
    states: Vec<u8>,
}

impl Track {
    fn new(curves: usize, flags: usize) -> Self {
        Track {
            curves,
            flags,
            width: 1,
            open: 0,
            times: Vec::new(),
            spans: Vec::new(),
            states: Vec::new(),
        }
    }

    fn len(&self) -> usize {
        self.times.len()
    }

    fn push(&mut self, time: f64, values: &[f64], flags: &[u8]) {
        debug_assert_eq!((values.len(), flags.len()), (self.curves, self.flags));
        if self.open > 0 && self.open < self.width {
            let n = self.len() - 1;
            self.times[n][1] = time;
            for (s, v) in self.spans[n * self.curves..].iter_mut().zip(values) {
                *s = Span::then(*s, Span::point(*v));
            }
            for (s, f) in self.states[n * self.flags..].iter_mut().zip(flags) {
                *s |= f;
            }
            self.open += 1;
            return;
        }
        if self.len() == MAX_SAMPLES {
            self.halve();
        }
        self.times.push([time, time]);
        self.spans.extend(values.iter().map(|v| Span::point(*v)));
        self.states.extend_from_slice(flags);
        self.open = 1;
    }

    /// Merges neighbouring samples in pairs (all full when called).
    fn halve(&mut self) {
        let (c, f) = (self.curves, self.flags);
        let n = self.len() / 2;
        for i in 0..n {
            let (a, b) = (2 * i, 2 * i + 1);
            self.times[i] = [self.times[a][0], self.times[b][1]];
            for k in 0..c {
                self.spans[i * c + k] = Span::then(self.spans[a * c + k], self.spans[b * c + k]);
            }
            for k in 0..f {
                self.states[i * f + k] = self.states[a * f + k] | self.states[b * f + k];
            }
        }
        self.times.truncate(n);
        self.spans.truncate(n * c);
        self.states.truncate(n * f);
        self.width *= 2;
    }

    /// The points of curve `k`: a point per sample of one record, the minimum and the
    /// maximum in their order (at the sample's first and last time) for a longer one.
    fn points(&self, k: usize) -> Vec<(f64, f64)> {
        let mut p = Vec::with_capacity(2 * self.len());
        for (i, [t0, t1]) in self.times.iter().enumerate() {
            let s = self.spans[i * self.curves + k];
            if s.min == s.max {
                p.push((0.5 * (t0 + t1), s.min as f64));
            } else if s.min_first {
                p.extend([(*t0, s.min as f64), (*t1, s.max as f64)]);
            } else {
                p.extend([(*t0, s.max as f64), (*t1, s.min as f64)]);
            }
        }
        p
    }

    /// Lowest and highest value of curve `k`.
    fn extent(&self, k: usize) -> (f64, f64) {
        (0..self.len())
            .map(|i| self.spans[i * self.curves + k])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(s.min as f64), hi.max(s.max as f64))
            })
    }

    /// The time intervals where `flag(state of flag word k)` holds, neighbours merged.
    fn intervals(&self, k: usize, flag: impl Fn(u8) -> bool) -> Vec<(f64, f64)> {
        let mut out: Vec<(f64, f64)> = Vec::new();
        for i in 0..self.len() {
            if !flag(self.states[i * self.flags + k]) {
                continue;
            }
            let t0 = self.times[i][0];
            // to the next sample's start, so that neighbouring samples join
            let t1 = self.times.get(i + 1).map_or(self.times[i][1], |t| t[0]);
            match out.last_mut() {
                Some(last) if last.1 >= t0 => last.1 = t1,
                _ => out.push((t0, t1)),
            }
        }
        out
    }
}

/// Flags of a free DOF in a record.
const STICK: u8 = 1;
const SLIP: u8 = 2;
const AT_STOP: u8 = 4;
const LOCKED: u8 = 8;

/// The parts of the law's force, in [`crate::law::ForceParts`] order.
const PARTS: [&str; 6] = ["elastic", "damping", "friction", "stop", "lock", "motor"];
/// The joint's energies: stored, then dissipated.
const ENERGIES: [&str; 7] = [
    "stored (elastic)",
    "stored (rotors)",
    "damping",
    "friction",
    "stop",
    "numerical",
    "taken by the motors",
];

/// What is kept of a joint.
#[derive(Debug, Clone)]
struct JointPlot {
    handle: KjointHandle,
    name: String,
    joint_type: JointType,
    free: Vec<Dof>,
    /// `(SD-, SD+)` of each free DOF (0 = none).
    stops: Vec<(f64, f64)>,
    sensor: Option<crate::dynamics::SensorId>,
    /// Curves: transmitted 0..6; per free DOF `k` at `6 + 8k`: 6 parts, law total, q; then
    /// 7 energies. A flag word per free DOF.
    track: Track,
}

impl JointPlot {
    /// One record of the joint: its readout `s` and its energies `e`.
    fn push(&mut self, s: &JointState, e: &JointEnergy) {
        let p = self;
        // the transmitted force, then per free DOF its law's parts, force and value, and
        // the energies
        let mut values = Vec::with_capacity(p.track.curves);
        values.extend(s.applied);
        let mut flags = Vec::with_capacity(p.free.len());
        for d in &p.free {
            let i = d.index();
            let parts = &s.parts[i];
            values.extend([
                parts.elastic,
                parts.damping,
                parts.friction,
                parts.stop,
                parts.sensor,
                parts.motor,
                s.force[i],
                s.q[i],
            ]);
            let st = &s.status[i];
            let mut f = match st.friction {
                FrictionStatus::None => 0,
                FrictionStatus::Stick => STICK,
                FrictionStatus::Slip => SLIP,
            };
            if st.stop != StopContact::None {
                f |= AT_STOP;
            }
            if st.locked || s.locked {
                f |= LOCKED;
            }
            flags.push(f);
        }
        values.extend(e.columns());
        p.track.push(s.time, &values, &flags);
    }

    fn dof_curve(&self, k: usize) -> usize {
        6 + 8 * k
    }
    fn energy_curve(&self) -> usize {
        6 + 8 * self.free.len()
    }
}

/// Curves of the energy balance.
const K: usize = 0;
const V: usize = 1;
const S: usize = 2;
const D: usize = 3;
const TOTAL: usize = 4;
const REFERENCE: usize = 5;
const RESIDUAL: usize = 6;

/// Draws the pictures of a run (module docs).
#[derive(Debug)]
pub struct Plotter {
    dir: PathBuf,
    svg: bool,
    joints: std::collections::BTreeMap<KjointHandle, JointPlot>,
    joints_seen: usize,
    balance: Track,
    initial: Option<f64>,
    work: f64,
    events: Vec<KjointEvent>,
    events_dropped: usize,
    created: bool,
    files: Vec<PathBuf>,
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

impl Plotter {
    /// A plotter into `dir`, PNG and SVG. Nothing is created before the first record.
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Plotter {
            dir: dir.into(),
            svg: true,
            joints: Default::default(),
            joints_seen: 0,
            balance: Track::new(7, 0),
            initial: None,
            work: 0.0,
            events: Vec::new(),
            events_dropped: 0,
            created: false,
            files: Vec::new(),
        }
    }

    /// Whether to write an SVG beside each PNG (default: yes).
    #[must_use]
    pub fn with_svg(mut self, svg: bool) -> Self {
        self.svg = svg;
        self
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The pictures written by [`Observer::finish`]: the joints' in handle order, then the
    /// energy balance (PNG, each followed by its SVG when written).
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// Keeps `events` for the list, the first [`MAX_EVENTS`] of the run; counts the rest.
    fn keep_events(&mut self, events: &[KjointEvent]) {
        for e in events {
            if self.events.len() < MAX_EVENTS {
                self.events.push(e.clone());
            } else {
                self.events_dropped += 1;
            }
        }
    }

    /// Joints seen in the run that have no picture (beyond [`MAX_JOINTS`]).
    pub fn joints_left_out(&self) -> usize {
        self.joints_seen.saturating_sub(MAX_JOINTS)
    }

    fn record_joints(&mut self, world: &PhysicsWorld, joints: &KjointSet, events: &[KjointEvent]) {
        self.joints_seen = self.joints_seen.max(joints.len());
        // a joint removed in this record's substeps (broken, detached) is no longer in the
        // set: the readout its event carries is its last sample (a broken joint's is the
        // substep it broke in, the force that broke it), as in its CSV history
        for (handle, energy, last) in events.iter().filter_map(KjointEvent::removed_joint) {
            let (Some(last), Some(p)) = (last, self.joints.get_mut(&handle)) else {
                continue;
            };
            if p.track.times.last().is_none_or(|t| last.time > t[1]) {
                p.push(last, energy);
            }
        }
        for (h, j) in joints.iter().take(MAX_JOINTS) {
            let Some(s) = j.state() else { continue };
            let p = self.joints.entry(h).or_insert_with(|| {
                let jt = j.property.joint_type;
                let free: Vec<Dof> = Dof::ALL.into_iter().filter(|d| jt.is_free(*d)).collect();
                let stops = free
                    .iter()
                    .map(|d| (j.property.dof(*d).stop_min, j.property.dof(*d).stop_max))
                    .collect();
                JointPlot {
                    handle: h,
                    name: j.name.clone(),
                    joint_type: jt,
                    track: Track::new(6 + 8 * free.len() + ENERGIES.len(), free.len()),
                    free,
                    stops,
                    sensor: j.property.sensor,
                }
            });
            p.push(s, &j.closed_energy(&world.bodies));
        }
    }

    fn record_balance(&mut self, time: f64, world: &PhysicsWorld, joints: &KjointSet) {
        let mech = energy::mechanical_energy(&world.bodies, world.gravity);
        let kinetic: f64 = world
            .bodies
            .iter()
            .map(|(_, b)| energy::kinetic_energy(b))
            .sum();
        let initial = *self.initial.get_or_insert(mech);
        // the joints removed so far (broken, detached) keep their energies in the balance,
        // as in the summary's: a broken friction joint's dissipation stays dissipated
        let removed = joints.removed_energy();
        let (mut stored, mut dissipated) = (removed.stored(), removed.dissipated());
        // and the work the joints' motors did on the bodies (`−motor`): put in from outside
        let mut motor_work = -removed.motor;
        for (_, j) in joints.iter() {
            let e = j.closed_energy(&world.bodies);
            stored += e.stored();
            dissipated += e.dissipated();
            motor_work -= e.motor;
        }
        let total = mech + stored + dissipated;
        let reference = initial + self.work + motor_work;
        self.balance.push(
            time,
            &[
                kinetic,
                mech - kinetic,
                stored,
                dissipated,
                total,
                reference,
                total - reference,
            ],
            &[],
        );
    }

    /// Writes every picture (called by [`Observer::finish`]).
    fn draw_all(&mut self) -> Result<(), OutputError> {
        if !self.created {
            // nothing recorded: nothing to draw
            return Ok(());
        }
        register_font();
        let t = match (self.balance.times.first(), self.balance.times.last()) {
            (Some(a), Some(b)) if b[1] > a[0] => (a[0], b[1]),
            (Some(a), _) => (a[0], a[0] + 1e-9),
            _ => return Ok(()),
        };
        let mut names = Names::new(&[&format!("{ENERGY_STEM}.png")], "png");
        let mut files = Vec::new();
        for p in self.joints.values() {
            let file = names.claim(&p.name);
            let events: Vec<&KjointEvent> = self.events.iter().filter(|e| concerns(e, p)).collect();
            let size = (WIDTH, joint_picture_height(p.free.len()));
            write_picture(&self.dir, self.svg, &mut files, &file, size, |root| {
                draw_joint(root, p, t, &events)
            })?;
        }
        let file = format!("{ENERGY_STEM}.png");
        let size = (WIDTH, ENERGY_HEIGHT);
        write_picture(&self.dir, self.svg, &mut files, &file, size, |root| {
            draw_balance(root, &self.balance, t, &self.events, self.events_dropped)
        })?;
        self.files = files;
        Ok(())
    }
}

/// The root area of a picture, on either backend.
enum Root<'a> {
    Png(DrawingArea<BitMapBackend<'a>, Shift>),
    Svg(DrawingArea<SVGBackend<'a>, Shift>),
}

type Drawn = Result<(), Box<dyn Error>>;

/// Draws a picture as `dir/file` (PNG) and, with `svg`, beside it as SVG.
fn write_picture(
    dir: &Path,
    svg: bool,
    files: &mut Vec<PathBuf>,
    file: &str,
    size: (u32, u32),
    draw: impl Fn(Root<'_>) -> Drawn,
) -> Result<(), OutputError> {
    let png = dir.join(file);
    let failed = |path: &Path, e: Box<dyn Error>| OutputError::Picture {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let mut pixels = vec![0u8; 3 * size.0 as usize * size.1 as usize];
    draw(Root::Png(
        BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area(),
    ))
    .map_err(|e| failed(&png, e))?;
    write_png(&png, size, &pixels).map_err(|e| failed(&png, e))?;
    files.push(png.clone());
    if svg {
        let path = png.with_extension("svg");
        draw(Root::Svg(SVGBackend::new(&path, size).into_drawing_area()))
            .map_err(|e| failed(&path, e))?;
        files.push(path);
    }
    Ok(())
}

/// Encodes 8-bit RGB pixels as a PNG file.
fn write_png(path: &Path, (w, h): (u32, u32), pixels: &[u8]) -> Drawn {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut enc = png::Encoder::new(file, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header()?;
    w.write_image_data(pixels)?;
    w.finish()?;
    Ok(())
}

/// Whether an event concerns a joint: its own, or its sensor's (its activation, a warning).
fn concerns(e: &KjointEvent, p: &JointPlot) -> bool {
    match &e.source {
        EventSource::Joint { handle, .. } => *handle == p.handle,
        EventSource::Sensor(id) => p.sensor == Some(*id),
    }
}

impl Observer for Plotter {
    fn record(
        &mut self,
        time: f64,
        world: &PhysicsWorld,
        joints: &KjointSet,
        events: &[KjointEvent],
    ) -> Result<(), OutputError> {
        if !self.created {
            std::fs::create_dir_all(&self.dir).map_err(io(&self.dir))?;
            self.created = true;
        }
        self.keep_events(events);
        self.record_balance(time, world, joints);
        self.record_joints(world, joints, events);
        Ok(())
    }

    /// The events since the last record, the failing substep's included: listed (and
    /// marked) with the others; the curves end at the last record.
    fn failed(&mut self, events: &[KjointEvent]) -> Result<(), OutputError> {
        self.keep_events(events);
        Ok(())
    }

    fn external_work(&mut self, work: f64) {
        self.work = work;
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        self.draw_all()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_history_keeps_its_extremes_within_the_sample_cap() {
        let mut t = Track::new(1, 1);
        let n = 10 * MAX_SAMPLES + 7;
        for i in 0..n {
            // a spike of 5 at one record, a slip flag at another, 0 elsewhere
            let v = if i == 4321 {
                5.0
            } else {
                (i as f64 * 1e-3).sin()
            };
            let f = if i == 777 { SLIP } else { STICK };
            t.push(i as f64, &[v], &[f]);
        }
        assert!(t.len() <= MAX_SAMPLES && t.len() > MAX_SAMPLES / 2);
        assert_eq!(t.width, 16);
        let (lo, hi) = t.extent(0);
        assert_eq!(hi, 5.0);
        let exact_lo = (0..n)
            .map(|i| (i as f64 * 1e-3).sin())
            .fold(f64::INFINITY, f64::min);
        assert!((lo - exact_lo).abs() < 1e-6, "{lo} {exact_lo}");
        // the spike is drawn at a time within its sample
        let p = t.points(0);
        let spike = p.iter().find(|q| q.1 == 5.0).unwrap();
        assert!((spike.0 - 4321.0).abs() <= 16.0, "{spike:?}");
        // the slip record's sample is the only slip interval
        let slips = t.intervals(0, |f| f & SLIP != 0);
        assert_eq!(slips.len(), 1);
        assert!(slips[0].0 <= 777.0 && slips[0].1 >= 777.0, "{slips:?}");
        // points in time order
        assert!(p.windows(2).all(|w| w[0].0 <= w[1].0));
    }

    #[test]
    fn y_range_pads_and_survives_flat_curves() {
        assert_eq!(y_range(0.0, 10.0), (-0.5, 10.5));
        assert_eq!(y_range(0.0, 0.0), (-1.0, 1.0));
        assert_eq!(y_range(f64::NAN, 1.0), (-1.0, 1.0));
    }
}
