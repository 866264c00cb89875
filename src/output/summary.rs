//! The summary of a run: per joint the peaks, slip and dissipation; for the model the
//! energy balance.
//!
//! # Per joint
//!
//! A table, one row per joint, the units under the headings. Figures in plain notation with
//! 4 significant digits where they fit, in exponent notation for magnitudes below 1e-3 or
//! from 1e6 on ([`format_figure`]).
//!
//! | heading \[unit\] | meaning |
//! |---|---|
//! | `peak \|F\|` \[N\], `peak \|M\|` [N·m] | peak magnitude `√(A_x² + A_y² + A_z²)` of the force / moment the joint **transmitted** to its bodies over a substep (`−P/h` of the implicit update, [`crate::JointState::applied`], the `AFX AFY AFZ` / `AMX AMY AMZ` columns of the CSV histories), the magnitude a failure criterion reads; a broken joint's includes the substep it broke in |
//! | `law \|F\|` \[N\], `law \|M\|` [N·m] | peak magnitude of the law's force / moment `F(q, q̇)` ([`crate::JointState::force`], the `FX .. MZ` columns). On a DOF the substep resolves the two agree; on a blocked DOF or a stop stiffer than the substep resolves (`ω·h > 1`) the law's `K·q` is not what the joint transmits (a rod at rest at `Kn = 1e12` transmits its weight with `q` below f32 resolution, so `K·q = 0`; a stop hit fast shows `K·q` far above the moment it transmits) |
//! | `gap` \[m\] | peak distance between the anchors along the blocked translations (the joint coming apart: the health warning `AnchorsSeparating` is given at its first crossing, this is its worst) |
//! | `stop pen.` \[m\], \[rad\] | peak penetration beyond a translational / rotational stop |
//! | `slip` \[m\], \[rad\] | distance / angle slipped by friction: the plastic part of the motion, `Σ |Δq − ΔF_f/K_f|` over the records where a DOF with a friction spring `K_f` of its own slips or slipped (the friction spring's elastic part left out: a block sticking then slipping by 21.6 µm read 31.8 µm when the whole motion of the substep it broke loose in was counted), plus a connector law's accumulated slip (planar friction's `slip_total` and `twist_slip_total`, joint friction's `slip_total`) |
//! | `dissipated` \[J\] | work dissipated by the joint: damping, friction, stops and what the update did beyond the law (the numerical damping of unresolved DOFs, its truncation: [`crate::law::JointEnergy::numerical`]), at the end of the last substep ([`crate::Kjoint::closed_energy`]) |
//!
//! In a scene's run the peaks, penetrations and slip are taken at every substep
//! ([`Observer::substep`]), whatever the logging rate, and a joint removed by an event
//! (broken, detached) is read from the event's last readout and energies; fed through
//! [`Observer::record`] alone, they are taken at the records.
//!
//! Then the events of the model (sensor activations, phase switches), the energy balance,
//! and last the health of the run ([`health_report`]): every notice and warning of
//! `dynamics::health` once, naming the joint and the remedy, warnings first, with how many
//! times it was reported when more than once (a warning given again as its value grew is
//! one line, showing the worst of them: [`HealthEntry`]).
//!
//! # Energy balance
//!
//! `residual = (K + V + S + D − W) − (K₀ + V₀)`, with `K` the kinetic and `V` the
//! gravitational potential energy of the bodies ([`crate::dynamics::energy`]), `S` the
//! elastic energy stored in the joints (a blocked DOF stores the energy of the stiffness
//! the update realises, `½·K̃·q²`, not the law's `½·K·q²`), `D` the work they dissipated (`S`
//! and `D` at the end of the last substep, [`crate::Kjoint::closed_energy`]: as booked, the
//! stored energy is that of its start and the law's share of it is not in `D` yet, which
//! printed a slider's `D` as −0.074 J in a stop's rebound where its damper had done
//! 0.033 J) and
//! `W` the work done from outside: the applied loads', the prescribed motions' (what the
//! kinematic bodies did through the KJOINT2 joints, [`crate::KjointSet::driven_work`]) and
//! the joints' motors' (`−`[`crate::law::JointEnergy::motor`], [`crate::KjointMotor`]). It
//! is 0 for an exact integration. rapier's own contacts and joints book nothing: what they
//! dissipate or do (a motor's work, a contact's friction and softness, a kinematic body
//! pushing through a contact) shows in the residual (0.04 % in the arm with a gripper,
//! `assets/scenes/arm_gripper.toml`, whose box is held by contacts). The summary gives the
//! part of the residual that arose between records in which one of rapier's contacts was
//! active (`of it while contacts touched`, [`EnergyBalance::while_contacts_touched`]), and
//! its warning names the contacts where that part is most of the residual: gymnasium's
//! hopper landing on its floor leaves −21.9 J (−11 %), −21.7 J of it while its foot
//! touched. A free fall leaves `−M·g²·h·t/2` (rapier's semi-implicit Euler step). The relative residual
//! divides it by an energy scale the joints' own book cannot inflate: the largest of the
//! peak kinetic energy, the range of the potential energy over the run, `|W|`, and
//! `M·|g|·L` (the dynamic bodies' mass, gravity, and the initial extent `L` of their centres
//! of mass and the joints' anchors), and, where nothing moves, the energy the bodies' poses
//! resolve, `M·|g|·L_b·ε` (`L_b` the extent of the bodies with their colliders, `ε` the
//! precision of rapier's `Real`, 1.2e-7 in f32): a 2 kg block hung at its joint's anchor on
//! 1e15 N/m moves 1.4e-13 J, which read 14 % of a floor of 1e-12 J and got a warning. It
//! includes neither `S` nor `D`: a stored or dissipated energy booked wrongly shows in the
//! residual instead of hiding it.

use super::{Observer, OutputError};
use crate::dynamics::{
    energy, EventSource, JointState, KjointEvent, KjointEventKind, KjointHandle, KjointSet,
    Severity,
};
use crate::figure::{format_figure, plural};
use crate::law::JointEnergy;
use crate::law::{Dof, StopContact};
use crate::rapier::pipeline::PhysicsWorld;
use std::fmt;

/// The relative residual of the energy balance beyond which the summary warns that the
/// balance does not close (every shipped scene closes within 1 %; a 5-link chain swinging
/// at 4 substeps a frame read 6.8 %, and 0.2 % at 16).
pub const RESIDUAL_WARNING: f64 = 0.05;

/// The start-up of a run \[s\]: a joint's peak force before it, above
/// [`START_UP_OVERSHOOT`] times its largest force after, is noted under the summary table
/// as the start-up transient of loads applied at once. A joint's penalty spring carries a
/// load switched on at `t = 0` (gravity on a body resting on it) with an overshoot of its
/// damping ratio's step response (`exp(−π·ζ/√(1 − ζ²))`: 73 % at `Cr` = 0.1), in the
/// period of that spring, a few milliseconds: the peak the table shows is what the joint
/// transmitted, not the design load an analyst reads in it (a riser scene's peak 34 364 N
/// for a 19 620 N weight and 22 190 N after; an offshore engineer's trial, 2026-12-04).
pub const START_UP: f64 = 0.1;
/// See [`START_UP`].
pub const START_UP_OVERSHOOT: f64 = 1.2;
/// How many times a joint's peak law force or moment must exceed its peak transmitted one
/// for the note under the summary table that says the law's `K·q` is not what a joint
/// carries.
pub const LAW_OVER_TRANSMITTED: f64 = 2.0;
/// How many joints' start-up peaks the summary notes one by one ([`START_UP`]), those
/// whose peak exceeds their largest force after by the largest ratio; one line counts the
/// others.
pub const START_UP_NOTES: usize = 5;

/// Per-joint figures of a run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointSummary {
    /// Joint name.
    pub name: String,
    /// Peak magnitude `√(AFX² + AFY² + AFZ²)` of the force transmitted over a substep
    /// ([`crate::JointState::applied`]; the force a failure criterion reads) \[N\].
    pub peak_force: f64,
    /// The time of [`Self::peak_force`] \[s\].
    pub peak_force_time: f64,
    /// The largest [`Self::peak_force`] from [`START_UP`] on \[N\]: without the start-up
    /// transient of loads applied at once at `t = 0` (gravity switched on a body resting
    /// on its joint's penalty spring, which rings before it settles).
    pub peak_force_after_start: f64,
    /// Peak magnitude `√(AMX² + AMY² + AMZ²)` of the moment transmitted over a substep
    /// [N·m].
    pub peak_moment: f64,
    /// Magnitude of the force transmitted over the run's last substep \[N\]: the static
    /// load of a mechanism at rest at the end, which the peaks (a stop hit, the start-up)
    /// do not show.
    pub end_force: f64,
    /// Magnitude of the moment transmitted over the run's last substep \[N·m\].
    pub end_moment: f64,
    /// Peak magnitude `√(FX² + FY² + FZ²)` of the law's force
    /// ([`crate::JointState::force`]) \[N\].
    pub peak_law_force: f64,
    /// Peak magnitude `√(MX² + MY² + MZ²)` of the law's moment [N·m].
    pub peak_law_moment: f64,
    /// Peak distance between the anchors along the blocked translations \[m\].
    pub peak_gap: f64,
    /// Peak penetration beyond a translational stop \[m\].
    pub peak_stop_penetration: f64,
    /// Peak penetration beyond a rotational stop \[rad\].
    pub peak_stop_angle: f64,
    /// Distance slipped by friction (the plastic part of the motion, `Σ |Δq − ΔF_f/K_f|`
    /// between records where a DOF with a friction spring of its own slips or slipped, plus
    /// a connector law's accumulated slip), translations \[m\].
    pub slip_distance: f64,
    /// Angle slipped by friction, rotations \[rad\].
    pub slip_angle: f64,
    /// Elastic energy stored at the end \[J\].
    pub stored: f64,
    /// Work dissipated by damping, friction, stops and the numerical damping of unresolved
    /// DOFs \[J\].
    pub dissipated: f64,
    /// Energy the joint stored at its first substep, its preload
    /// ([`crate::Kjoint::preload_energy`]) \[J\].
    pub preload: f64,
    /// Work the joint's motors did on its bodies, `−`[`JointEnergy::motor`] \[J\] (0 without
    /// a motor, [`crate::KjointMotor`]).
    pub motor_work: f64,
}

impl JointSummary {
    /// How far the law's peak exceeds the transmitted one, force or moment, whichever
    /// more: `(ratio, law peak, transmitted peak, unit, "|F|" or "|M|")`.
    /// `floor`: the laws' forces and moments at or below which a ratio is round-off's
    /// (`1e-6` of the largest transmitted over the run, of each kind), not compared: an
    /// axle's law moment of 2.66e-10 N·m over 4.05e-11 transmitted was named in the note
    /// where its force, 7479 N over 3256 N, was the point (a vehicle developer's trial).
    fn law_over_transmitted(&self, floor: [f64; 2]) -> (f64, f64, f64, &'static str, &'static str) {
        let ratio = |law: f64, peak: f64, floor: f64| {
            if law > floor {
                law / peak.max(1e-300)
            } else {
                0.0
            }
        };
        let force = ratio(self.peak_law_force, self.peak_force, floor[0]);
        let moment = ratio(self.peak_law_moment, self.peak_moment, floor[1]);
        if force >= moment {
            (force, self.peak_law_force, self.peak_force, "N", "|F|")
        } else {
            (moment, self.peak_law_moment, self.peak_moment, "N·m", "|M|")
        }
    }
}

/// Collects the summary of a run.
#[derive(Debug, Clone, Default)]
pub struct Summary {
    /// Every joint seen, in the order first seen (a removed joint keeps its last values).
    joints: Vec<JointSummary>,
    /// Handle → position in `joints`, `prev` and `laws`, extended when a joint is first
    /// seen.
    slot_of: std::collections::BTreeMap<KjointHandle, usize>,
    /// Each row's last record.
    prev: Vec<Option<Previous>>,
    /// What each row's figures read of its joint's property (a removed joint's are read
    /// from here).
    laws: Vec<RowLaw>,
    /// Each row's slip by its DOFs' own friction springs (translations \[m\], rotations
    /// \[rad\]), to which a connector law's accumulated slip is added.
    dof_slip: Vec<[f64; 2]>,
    initial_energy: Option<f64>,
    mechanical: f64,
    peak_kinetic: f64,
    potential_range: Option<(f64, f64)>,
    weight_scale: f64,
    /// The energy the bodies' f32 poses resolve, `M·|g|·L_b·ε` ([`pose_resolution`]).
    resolution: f64,
    time: f64,
    events: Vec<KjointEvent>,
    /// Where the residual arose ([`ContactShare`]).
    contacts: ContactShare,
    /// What the run could give its bodies and what they gained beyond it
    /// ([`Summary::energy_created`]).
    sources: EnergySources,
}

/// The energy a run's sources could give its bodies, and the largest gain beyond what they
/// gave, over the records ([`Summary::energy_created`]).
#[derive(Debug, Clone, Copy, Default)]
struct EnergySources {
    /// The bodies' kinetic energy at the first record \[J\].
    initial_kinetic: f64,
    /// The largest `|W|` of the applied loads and prescribed motions, and of the joints'
    /// motors, at a record \[J\].
    work: f64,
    motor: f64,
    /// Whether the run gave its external work ([`Observer::external_work`], as a scene's
    /// run does from its start): without it the loads' work is unknown, and no gain is
    /// judged.
    work_given: bool,
    /// The largest gain (`K + V + S − K₀ − V₀ − S₀ − W`, the residual less the
    /// dissipation) and the time of its record \[J, s\].
    gain: (f64, f64),
}

/// The share of the residual that arose while rapier's contacts touched: the residual's
/// change from one record to the next, summed over the intervals in which a contact was
/// active at some substep (or at the record). rapier's contacts book nothing, so what an
/// impact, a landing or a contact's friction takes from the bodies shows in the residual
/// of those intervals; the rest is the integration's (and rapier's own joints').
#[derive(Debug, Clone, Copy, Default)]
struct ContactShare {
    /// The external work given for the next record \[J\].
    work: f64,
    /// A contact was active since the last record.
    touched: bool,
    /// The residual at the last record \[J\].
    last: Option<f64>,
    /// The residual's change summed over the intervals with contacts \[J\].
    residual: f64,
    /// Intervals between records with contacts, and all of them.
    touched_intervals: usize,
    intervals: usize,
}

/// Whether one of rapier's contacts is active in `world`.
fn contacts_touch(world: &PhysicsWorld) -> bool {
    (world.narrow_phase.contact_pairs()).any(|p| p.has_any_active_contact())
}

/// What a row of the summary reads of its joint's property.
#[derive(Debug, Clone, Copy)]
struct RowLaw {
    /// The stops `(SD-, SD+)` per DOF.
    stops: [(f64, f64); 6],
    /// Which translations are blocked (x, y, z).
    blocked: [bool; 3],
    /// Whether a joint friction law's slip is an angle (a revolute joint's).
    rotational_joint_friction: bool,
    /// The friction spring's stiffness `K_f` per DOF.
    friction_stiffness: [f64; 6],
    /// A flex joint's time of switching to its dynamic bending law \[s\], if it has one
    /// and a dynamic law (`*FLEXPROADD`) to switch to.
    switch_time: Option<f64>,
}

impl RowLaw {
    fn of(p: &crate::law::KjointProperty, connector: &crate::law::ConnectorLaw) -> Self {
        RowLaw {
            stops: Dof::ALL.map(|d| (p.dof(d).stop_min, p.dof(d).stop_max)),
            blocked: [Dof::Dx, Dof::Dy, Dof::Dz].map(|d| !p.joint_type.is_free(d)),
            rotational_joint_friction: p.joint_type == crate::law::JointType::Revolute,
            friction_stiffness: Dof::ALL.map(|d| p.dof(d).friction_stiffness),
            // (a law without a dynamic part records a switch that changes nothing)
            switch_time: match connector {
                crate::law::ConnectorLaw::FlexJoint(f) if f.law.dynamic.is_some() => f.switch_time,
                _ => None,
            },
        }
    }
}

/// What a row keeps of its joint's last record.
#[derive(Debug, Clone, Copy)]
struct Previous {
    q: [f64; 6],
    /// The friction force per DOF.
    friction: [f64; 6],
    /// Whether each DOF slipped.
    slipping: [bool; 6],
}

/// The energy balance of a run \[J\].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyBalance {
    /// Kinetic + potential energy at the start.
    pub initial: f64,
    /// Energy the joints stored at their first substep, before their bodies did work on
    /// them (their preloads, [`crate::Kjoint::preload_energy`]): energy the model starts
    /// with, as `initial`.
    pub preload: f64,
    /// Kinetic + potential energy at the end.
    pub mechanical: f64,
    /// Elastic energy stored in the joints at the end.
    pub stored: f64,
    /// Work dissipated by the joints.
    pub dissipated: f64,
    /// Work of the applied loads and the prescribed motions.
    pub load_work: f64,
    /// Work the joints' motors did on the bodies ([`crate::KjointMotor`]).
    pub motor_work: f64,
    /// `mechanical + stored + dissipated − load_work − motor_work − initial − preload`.
    pub residual: f64,
    /// The energy scale of the run: the largest of the peak kinetic energy, the range of
    /// the potential energy, `|W|`, the joints' preload, `M·|g|·L` and the energy the
    /// bodies' poses resolve, `M·|g|·L_b·ε` (module docs).
    pub scale: f64,
    /// `residual / scale`.
    pub relative: f64,
    /// The part of `residual` that arose between records while rapier's contacts touched
    /// (a contact active at one of the interval's substeps or at its record: rapier's
    /// speculative contacts within its prediction distance count), with the number of such
    /// intervals and of all intervals between records; `None` where no contact touched.
    /// Each record's residual takes the external work given before it
    /// ([`Observer::external_work`], as a scene's run gives it; 0 if never given).
    pub while_contacts_touched: Option<(f64, usize, usize)>,
}

impl Summary {
    /// An empty summary.
    pub fn new() -> Self {
        Self::default()
    }

    /// Per-joint figures.
    pub fn joints(&self) -> &[JointSummary] {
        &self.joints
    }

    /// Sensor events seen.
    pub fn events(&self) -> &[KjointEvent] {
        &self.events
    }

    /// Simulation time of the last record \[s\].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The energy balance, given the work done on the model from outside \[J\]: the
    /// applied loads' and the prescribed motions' ([`crate::scene::RunStats::external_work`]).
    pub fn balance(&self, load_work: f64) -> EnergyBalance {
        let stored: f64 = self.joints.iter().map(|j| j.stored).sum();
        let dissipated: f64 = self.joints.iter().map(|j| j.dissipated).sum();
        let preload: f64 = self.joints.iter().map(|j| j.preload).sum();
        let motor_work: f64 = self.joints.iter().map(|j| j.motor_work).sum();
        let initial = self.initial_energy.unwrap_or(0.0);
        let residual =
            self.mechanical + stored + dissipated - load_work - motor_work - initial - preload;
        let range = self.potential_range.map_or(0.0, |(lo, hi)| hi - lo);
        let scale = self
            .peak_kinetic
            .max(range)
            .max(load_work.abs())
            .max(motor_work.abs())
            .max(preload.abs())
            .max(self.weight_scale)
            .max(self.resolution)
            .max(1e-12);
        let c = &self.contacts;
        EnergyBalance {
            initial,
            preload,
            mechanical: self.mechanical,
            stored,
            dissipated,
            load_work,
            motor_work,
            residual,
            scale,
            relative: residual / scale,
            while_contacts_touched: (c.touched_intervals > 0).then_some((
                c.residual,
                c.touched_intervals,
                c.intervals,
            )),
        }
    }

    /// The summary table with the energy balance, as text.
    pub fn table(&self, load_work: f64) -> String {
        let mut s = String::new();
        self.write_table(&mut s, load_work)
            .expect("writing to a String");
        s
    }

    fn write_table(&self, f: &mut impl fmt::Write, load_work: f64) -> fmt::Result {
        const HEADINGS: [(&str, &str); 12] = [
            ("peak |F|", "N"),
            ("peak |M|", "N·m"),
            ("law |F|", "N"),
            ("law |M|", "N·m"),
            ("end |F|", "N"),
            ("end |M|", "N·m"),
            ("gap", "m"),
            ("stop pen.", "m"),
            ("stop pen.", "rad"),
            ("slip", "m"),
            ("slip", "rad"),
            ("dissipated", "J"),
        ];
        let rows: Vec<(String, Vec<String>)> = self
            .joints
            .iter()
            .map(|j| {
                let figures = [
                    j.peak_force,
                    j.peak_moment,
                    j.peak_law_force,
                    j.peak_law_moment,
                    j.end_force,
                    j.end_moment,
                    j.peak_gap,
                    j.peak_stop_penetration,
                    j.peak_stop_angle,
                    j.slip_distance,
                    j.slip_angle,
                    j.dissipated,
                ];
                (j.name.clone(), figures.map(format_figure).to_vec())
            })
            .collect();
        let mut heading = vec![("joint".to_string(), String::new())];
        heading.extend(
            HEADINGS
                .iter()
                .map(|(h, u)| (h.to_string(), format!("[{u}]"))),
        );
        let mut table = vec![
            heading.iter().map(|(h, _)| h.clone()).collect::<Vec<_>>(),
            heading.into_iter().map(|(_, u)| u).collect(),
        ];
        table.extend(rows.into_iter().map(|(name, cells)| {
            let mut row = vec![name];
            row.extend(cells);
            row
        }));
        write_columns(f, &table)?;
        // the law's K·q where a DOF the substep does not resolve (a blocked DOF at Kn, a stiff
        // stop) reads far above what the joint carries: said once, with the worst joint (a
        // Radioss analyst read law |F| 588 322 N for a stop that transmitted 1664 N)
        // (not a joint whose forces are all round-off beside the others': a law of 1e-9 N
        // against 1e-12 transmitted would be named)
        let largest = (self.joints.iter())
            .map(|j| j.peak_force.max(j.peak_moment))
            .fold(0.0, f64::max);
        let floor = [
            1e-6 * (self.joints.iter().map(|j| j.peak_force)).fold(0.0, f64::max),
            1e-6 * (self.joints.iter().map(|j| j.peak_moment)).fold(0.0, f64::max),
        ];
        let worst = (self.joints.iter())
            .filter(|j| j.peak_law_force.max(j.peak_law_moment) > 1e-6 * largest)
            .map(|j| (j, j.law_over_transmitted(floor)))
            .filter(|(_, o)| o.0 > LAW_OVER_TRANSMITTED)
            .max_by(|a, b| a.1 .0.total_cmp(&b.1 .0));
        if let Some((j, (_, law, peak, unit, what))) = worst {
            writeln!(
                f,
                "  note: law |F| and |M| are the laws' K·q, which a DOF stiffer than the \
                 substep resolves (a blocked DOF, a stiff stop) does not transmit (`{}`: law \
                 {what} {} {unit}, peak {what} {} {unit}); what the joints carried is peak and \
                 end |F|, |M|",
                j.name,
                format_figure(law),
                format_figure(peak)
            )?;
        }
        // a flex joint's switch to its dynamic bending law that did not come within the run
        // (a switch time at or after its end): the run looked like one of the dynamic law
        // (an offshore engineer's trial, 2026-12-06: `switch_time = 4`, `--duration 3`, and
        // nothing said)
        for (slot, law) in self.laws.iter().enumerate() {
            let Some(t) = law.switch_time else {
                continue;
            };
            let switched = self.events.iter().any(|e| {
                matches!(e.kind, KjointEventKind::FlexJointSwitched { .. })
                    && matches!(&e.source, EventSource::Joint { handle, .. }
                        if self.slot_of.get(handle) == Some(&slot))
            });
            if !switched {
                writeln!(
                    f,
                    "  note: flex joint `{}`'s switch to its dynamic bending law at {} s did \
                     not come within the run (it ended at {} s): it stayed in its \
                     quasi-static phase",
                    self.joints[slot].name,
                    format_figure(t),
                    format_figure(self.time)
                )?;
            }
        }
        // (at most START_UP_NOTES of them, the largest overshoots first, and one line for
        // the rest: 500 joints under gravity made 500 notes)
        let mut start_up: Vec<&JointSummary> = (self.joints.iter())
            .filter(|j| {
                let late = j.peak_force_after_start;
                j.peak_force_time < START_UP
                    && late > 0.0
                    && j.peak_force > START_UP_OVERSHOOT * late
            })
            .collect();
        start_up.sort_by(|a, b| {
            let ratio = |j: &JointSummary| j.peak_force / j.peak_force_after_start;
            ratio(b).total_cmp(&ratio(a))
        });
        for j in start_up.iter().take(START_UP_NOTES) {
            writeln!(
                f,
                "  note: `{}`'s peak |F| {} N came at t = {} s, in the start-up (loads \
                 applied at once ring in a penalty spring before it settles; an initial \
                 velocity or an impact then reads alike); from t = {START_UP} s on, its \
                 largest |F| is {} N (ramp the loads in, or start the bodies at rest, to \
                 avoid the transient)",
                j.name,
                format_figure(j.peak_force),
                format_figure(j.peak_force_time),
                format_figure(j.peak_force_after_start)
            )?;
        }
        if start_up.len() > START_UP_NOTES {
            writeln!(
                f,
                "  note: and {} more joints whose peak |F| came before t = {START_UP} s, above \
                 {START_UP_OVERSHOOT} times their largest after",
                start_up.len() - START_UP_NOTES
            )?;
        }
        let infos: Vec<&KjointEvent> = self
            .events
            .iter()
            .filter(|e| e.severity() == Severity::Info)
            .collect();
        if !infos.is_empty() {
            writeln!(f, "\nevents")?;
            for e in infos {
                writeln!(f, "  {e}")?;
            }
        }
        let b = self.balance(load_work);
        writeln!(f)?;
        let mut energy = vec![
            ("initial kinetic + potential", b.initial),
            ("final kinetic + potential", b.mechanical),
            ("stored in the joints", b.stored),
            ("dissipated by the joints", b.dissipated),
            ("work of loads and motions", b.load_work),
            ("residual", b.residual),
        ];
        // the joints' preload (an initial angle between skew frames) on a line of its own
        // where there is one: energy the model starts with; not the f32 rounding of the
        // anchors of a robot placed off the origin (1.41e-33 J beside 40.64 J, read as a
        // preload), which the residual still counts
        if b.preload.abs() > PRELOAD_SHOWN * b.scale {
            energy.insert(1, ("stored in the joints at their start", b.preload));
        }
        // the joints' motors, where one worked
        if b.motor_work != 0.0 {
            let at = energy.len() - 1;
            energy.insert(at, ("work of the joints' motors", b.motor_work));
        }
        let mut lines: Vec<Vec<String>> = vec![vec!["energy balance".into(), "[J]".into()]];
        lines.extend(
            energy
                .iter()
                .map(|(what, v)| vec![format!("  {what}"), format_figure(*v)]),
        );
        let last = lines.len() - 1;
        lines[last].push(format!(
            "({} % of the energy scale {} J)",
            format_figure(100.0 * b.relative),
            format_figure(b.scale)
        ));
        if let Some((r, touched, of)) = b.while_contacts_touched {
            lines.push(vec![
                "    of it while contacts touched".into(),
                format_figure(r),
                format!("(in {touched} of the {of} intervals logged)"),
            ]);
        }
        write_columns(f, &lines)?;
        if b.relative.abs() > RESIDUAL_WARNING {
            // the residual mostly the contacts': named first (with the other causes, which
            // act in those intervals too: a contact held through the run takes them all)
            let contacts = (b.while_contacts_touched)
                .map(|(r, ..)| r)
                .filter(|r| r.abs() >= 0.5 * b.residual.abs() && r * b.residual > 0.0);
            let contacts = match contacts {
                Some(r) => format!(
                    "{} J of it arose while rapier's contacts touched, which book nothing \
                     (what an impact, a landing or a contact's friction takes from the \
                     bodies, or gives them); rapier's own joints book nothing either",
                    format_figure(r)
                ),
                None => "rapier's contacts and its own joints book nothing".to_string(),
            };
            writeln!(
                f,
                "  warning: the balance does not close ({} % of the energy scale, over {} %): \
                 what the joints booked and what the bodies hold differ; {contacts}, a \
                 substep too long for the motion \
                 leaves an error of the integration (remedy: more substeps, `--substeps`), \
                 and where little moves, the f32 poses of bodies far from the origin round \
                 the motion itself, more at more substeps (remedy: the model near the \
                 origin, or the crate's `f64` feature)",
                format_figure(100.0 * b.relative),
                100.0 * RESIDUAL_WARNING
            )?;
        }
        if let Some(c) = self.energy_created() {
            writeln!(f, "  error: {c}")?;
        }
        // the health of the run, gathered at the end (`dynamics::health`)
        let health = health_report(&self.events);
        if !health.is_empty() {
            writeln!(f, "\nhealth of the run ({})", health_counts(&health))?;
            for h in &health {
                write!(f, "  {h}")?;
                // a warning is given at its crossings (fourfold apart): the worst of the run,
                // between them and after the last, beside it
                if let Some(worst) = self.worst_of(&h.event) {
                    write!(f, "; {worst}")?;
                }
                writeln!(f)?;
            }
        }
        Ok(())
    }
}

/// The joints' energy at their start \[J\] that the balance shows on a line of its own, as a
/// fraction of the balance's energy scale: below it, the start is the rounding of the
/// poses (a millionth of the scale is below what the table's other lines resolve).
pub const PRELOAD_SHOWN: f64 = 1e-6;

/// Writes rows of cells as columns: the first left-aligned, the others right-aligned, two
/// spaces apart; a row may have a last cell beyond the columns of the first row, written
/// after them as it is.
fn write_columns(f: &mut impl fmt::Write, rows: &[Vec<String>]) -> fmt::Result {
    let n = rows.first().map_or(0, |r| r.len());
    let mut widths = vec![0; n];
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    // padded by hand: `format!`'s width is at most 65 535 (a longer name, as a joint's may
    // be, panicked)
    let pad = |w: usize, cell: &str| " ".repeat(w.saturating_sub(cell.chars().count()));
    for row in rows {
        let mut line = String::new();
        for (i, cell) in row.iter().enumerate() {
            match widths.get(i) {
                Some(&w) if i == 0 => {
                    line += cell;
                    line += &pad(w, cell);
                }
                Some(&w) => {
                    line += "  ";
                    line += &pad(w, cell);
                    line += cell;
                }
                None => {
                    line += "  ";
                    line += cell;
                }
            }
        }
        writeln!(f, "{}", line.trim_end())?;
    }
    Ok(())
}

/// A health event of the run (notice or warning) with its repeats.
#[derive(Debug, Clone, PartialEq)]
pub struct HealthEntry {
    /// Its first occurrence; for a warning given again as its value grew (a gap, a blocked
    /// rotation, a stop overrun, a spring running off its curve, a joint that no longer
    /// holds: `dynamics::health::WARNING_GROWTH`), the worst (largest) of them, whose text
    /// is what the run came to (the first was printed, a neck warned at 1.1 mm that opened
    /// to 73 mm read 1.1 mm).
    pub event: KjointEvent,
    /// How many times the same event (same severity, source and text; for a warning given
    /// again as it grew, the same kind) was reported.
    pub count: usize,
    /// Time of its first occurrence \[s\] (before `event`'s where the worst came later).
    pub first_time: f64,
    /// Time of its last occurrence \[s\].
    pub last_time: f64,
}

impl fmt::Display for HealthEntry {
    /// The event, and how many times it was given when more than once: `warning: joint
    /// `pin` at t = 0.1 s: … (3 times, the last at t = 0.5 s)`; where the event shown is
    /// the worst of a warning given again as it grew and not its first, `(3 times, the
    /// first at t = 0.1 s, the last at t = 0.5 s; the worst shown)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.event)?;
        if self.count > 1 {
            write!(f, " ({} times, ", self.count)?;
            if self.first_time < self.event.time {
                write!(f, "the first at t = {} s, ", format_figure(self.first_time))?;
            }
            write!(f, "the last at t = {} s", format_figure(self.last_time))?;
            if self.first_time < self.event.time {
                f.write_str("; the worst shown")?;
            }
            f.write_str(")")?;
        }
        Ok(())
    }
}

/// How large a warning of a kind given again as its value grows is
/// (`dynamics::health::WARNING_GROWTH`), as the health checks compare it (a stop overrun in
/// m or rad as they do; a joint that no longer holds by how far beyond its error bounds):
/// `None` for a kind not given again so.
fn grown_value(kind: &KjointEventKind) -> Option<f64> {
    use crate::dynamics::{GAP_ERROR, ROTATION_ERROR};
    match kind {
        KjointEventKind::AnchorsSeparating { gap, .. } => Some(*gap),
        KjointEventKind::BlockedRotation { angle, .. } => Some(*angle),
        KjointEventKind::StopOverrun { overrun, .. } => Some(*overrun),
        KjointEventKind::SpringRunsAway { value, .. } => Some(value.abs()),
        KjointEventKind::NoLongerHolds {
            gap,
            size,
            rotation,
            ..
        } => Some((gap / (GAP_ERROR * size)).max(rotation / ROTATION_ERROR)),
        _ => None,
    }
}

/// How many warnings and notices `health` holds, in words: `1 warning, 2 notices`.
pub fn health_counts(health: &[HealthEntry]) -> String {
    let count = |sev: Severity| health.iter().filter(|h| h.event.severity() == sev).count();
    let counts: Vec<String> = [(Severity::Warning, "warning"), (Severity::Notice, "notice")]
        .into_iter()
        .filter(|(sev, _)| count(*sev) > 0)
        .map(|(sev, what)| plural(count(sev), what))
        .collect();
    counts.join(", ")
}

/// The notices and warnings among `events`, each once (repeats counted), warnings first,
/// then notices, each in the order of their first occurrence.
pub fn health_report(events: &[KjointEvent]) -> Vec<HealthEntry> {
    let mut out: Vec<HealthEntry> = Vec::new();
    for e in events.iter().filter(|e| e.severity() != Severity::Info) {
        // the same text, not the same data: a notice given again after a topology change
        // carries an ω that may differ in its last bits, printed alike
        let text = e.kind.to_string();
        // a warning given again as its value grew (`dynamics::health::WARNING_GROWTH`)
        // counts with its first, and the worst of them is shown: a user reads the line as
        // the size of the trouble (the first was shown, the joint's worst opening beside
        // it at best)
        let grown = grown_value(&e.kind);
        let same = out.iter_mut().find(|h| {
            h.event.severity() == e.severity()
                && h.event.source == e.source
                && (h.event.kind.to_string() == text
                    || (grown.is_some()
                        && std::mem::discriminant(&h.event.kind)
                            == std::mem::discriminant(&e.kind)))
        });
        match same {
            Some(h) => {
                h.count += 1;
                h.last_time = e.time;
                // (a value not a number is no worse: it is not compared)
                if let (Some(new), Some(shown)) = (grown, grown_value(&h.event.kind)) {
                    if new > shown {
                        h.event = e.clone();
                    }
                }
            }
            None => out.push(HealthEntry {
                event: e.clone(),
                count: 1,
                first_time: e.time,
                last_time: e.time,
            }),
        }
    }
    // stable: the order of first occurrence within each severity
    out.sort_by_key(|h| h.event.severity() != Severity::Warning);
    out
}

impl Observer for Summary {
    fn record(
        &mut self,
        time: f64,
        world: &PhysicsWorld,
        joints: &KjointSet,
        events: &[KjointEvent],
    ) -> Result<(), OutputError> {
        let mech = energy::mechanical_energy(&world.bodies, world.gravity);
        let first = self.initial_energy.is_none();
        if first {
            self.initial_energy = Some(mech);
            self.weight_scale = weight_scale(world, joints);
            self.resolution = pose_resolution(world);
        }
        self.mechanical = mech;
        self.time = time;
        self.events.extend_from_slice(events);
        let kinetic: f64 = world
            .bodies
            .iter()
            .map(|(_, b)| energy::kinetic_energy(b))
            .sum();
        let potential = mech - kinetic;
        self.peak_kinetic = self.peak_kinetic.max(kinetic);
        self.potential_range = Some(match self.potential_range {
            None => (potential, potential),
            Some((lo, hi)) => (lo.min(potential), hi.max(potential)),
        });
        for (h, j) in joints.iter() {
            let k = self.row(h, &j.name, RowLaw::of(&j.property, j.connector.law()));
            self.update_row(k, j.closed_energy(&world.bodies), j.state());
            self.joints[k].preload = j.preload_energy();
        }
        self.update_removed(events);
        // the residual's change since the last record, the contacts' if one touched
        let b = self.balance(self.contacts.work);
        let residual = b.residual;
        let c = &mut self.contacts;
        c.touched |= contacts_touch(world);
        if let Some(last) = c.last {
            c.intervals += 1;
            if c.touched {
                c.residual += residual - last;
                c.touched_intervals += 1;
            }
        }
        c.last = Some(residual);
        c.touched = false;
        // what the bodies gained beyond their sources ([`Summary::energy_created`])
        let e = &mut self.sources;
        if first {
            e.initial_kinetic = kinetic;
        }
        e.work = e.work.max(b.load_work.abs());
        e.motor = e.motor.max(b.motor_work.abs());
        let gain = b.residual - b.dissipated;
        if gain > e.gain.0 {
            e.gain = (gain, time);
        }
        Ok(())
    }

    fn external_work(&mut self, work: f64) {
        self.contacts.work = work;
        self.sources.work_given = true;
    }

    /// After every substep of a scene's run: the peaks, penetrations and slip of every
    /// joint at every substep, not only at the records (a frame of 16 substeps hides the
    /// peak of a stop hit within it), and the last readout of a joint removed in it.
    fn substep(
        &mut self,
        world: &PhysicsWorld,
        joints: &KjointSet,
        events: &[KjointEvent],
    ) -> Result<(), OutputError> {
        self.contacts.touched |= !self.contacts.touched && contacts_touch(world);
        for (h, j) in joints.iter() {
            if let Some(&k) = self.slot_of.get(&h) {
                self.update_row(k, j.energy(), j.state());
                self.joints[k].preload = j.preload_energy();
            }
        }
        self.update_removed(events);
        Ok(())
    }

    /// The events no record carried, the failing substep's included: in
    /// [`Summary::events`] and the health report (the peaks keep the last substep that
    /// completed).
    fn failed(&mut self, events: &[KjointEvent]) -> Result<(), OutputError> {
        self.events.extend_from_slice(events);
        Ok(())
    }
}

/// How many times the energy a run's sources could give its bodies they must have gained
/// beyond what those sources gave for the run to be called unstable
/// ([`Summary::energy_created`]).
pub const CREATED_ERROR: f64 = 1.0;

/// The least energy \[J\] the bodies must have gained beyond their sources for the run to be
/// called unstable ([`Summary::energy_created`]): a world at rest without gravity, loads or
/// motors has sources of nothing but round-off (gymnasium's pusher, weightless, gained
/// 9.2e-12 J over its 1.4 times as large sources).
pub const CREATED_FLOOR: f64 = 1e-6;

/// Energy the bodies of a run gained that nothing gave them ([`Summary::energy_created`]).
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyCreated {
    /// The largest gain over the records \[J\]: `K + V + S − (K₀ + V₀ + S₀) − W`, the
    /// residual of the balance less the joints' dissipation.
    pub gain: f64,
    /// The time of its record \[s\].
    pub time: f64,
    /// What the run's sources could give the bodies \[J\]: the largest of their initial
    /// kinetic energy, `M·|g|·L`, the largest `|W|` of the loads, prescribed motions and
    /// motors at a record, the joints' preload and the energy the bodies' poses resolve.
    pub sources: f64,
    /// The joints' dissipation at the end, at least half the gain below zero \[J\].
    pub dissipated: f64,
    /// The joint that booked the most negative dissipation (energy its update gave the
    /// bodies), with it \[J\].
    pub joint: Option<(String, f64)>,
}

impl fmt::Display for EnergyCreated {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the bodies gained {} J that nothing gave them (at t = {} s: their kinetic and \
             potential energy and the joints' stored energy beyond the start, less the work \
             of the loads, prescribed motions and motors), {} times all that the run's \
             sources could give them ({} J)",
            format_figure(self.gain),
            format_figure(self.time),
            format_figure(self.gain / self.sources),
            format_figure(self.sources)
        )?;
        if let Some((name, d)) = &self.joint {
            write!(
                f,
                "; the joints' update gave it, booked as their dissipation (joint `{name}`: {} J)",
                format_figure(*d)
            )?;
        }
        write!(
            f,
            ": the run is unstable; the warnings of its health say where it began"
        )
    }
}

impl Summary {
    /// Energy the bodies gained beyond everything that could give it to them, when more
    /// than [`CREATED_ERROR`] times that and [`CREATED_FLOOR`], and the joints booked at
    /// least half of it as negative dissipation ([`EnergyCreated`]); `None` for a run whose
    /// bodies' energy its sources explain, one the joints did not give it to (rapier's
    /// contacts, joints and motors book nothing: a kinematic bat that hit a ball through a
    /// contact gave it 2 J that no work booked; the balance's residual warns of it), and
    /// one that never gave its external work (a summary fed by a program's own loop, not
    /// `scene::run`).
    ///
    /// The balance's residual is divided by a scale that includes the peak kinetic energy,
    /// which a run away inflates with what it created: a spherical joint whose softening
    /// curve ran off its end under a 5.5 N·m torque spun its ball to 3.1e6 rad/s in 2 s,
    /// the joint's update booking −1.95e10 J of dissipation where the curve released
    /// 3.75e7 J and the torque did 5.2e6 J, and the residual read 2.3e-4 % (a Radioss
    /// analyst's trial, 2026-12-06). The gain `K + V + S − (K₀ + V₀ + S₀) − W` is the
    /// residual less the joints' dissipation: energy the joints' law or update gave the
    /// bodies that neither the loads nor their stored energy did; a stable run keeps it
    /// at or below zero (its joints dissipate), but for rapier's contacts, which book
    /// nothing (an impact's restitution, bodies pushed apart where they start inside each
    /// other). The sources it is compared with are what the bodies could take from outside
    /// the joints' dissipation, none of them inflated by the gain itself.
    pub fn energy_created(&self) -> Option<EnergyCreated> {
        let e = &self.sources;
        let preload: f64 = self.joints.iter().map(|j| j.preload).sum();
        let dissipated: f64 = self.joints.iter().map(|j| j.dissipated).sum();
        // (the joints' stored energy is in the gain, `S − S₀`: not among the sources, where
        // a swing growing between it and the bodies' would grow the bound with it)
        let sources = e
            .initial_kinetic
            .max(self.weight_scale)
            .max(e.work)
            .max(e.motor)
            .max(preload.abs())
            .max(self.resolution)
            .max(1e-12);
        let (gain, time) = e.gain;
        let created = gain > CREATED_ERROR * sources && gain > CREATED_FLOOR;
        if !(e.work_given && created && -dissipated >= 0.5 * gain) {
            return None;
        }
        let joint = self
            .joints
            .iter()
            .filter(|j| j.dissipated < 0.0)
            .min_by(|a, b| a.dissipated.total_cmp(&b.dissipated))
            .map(|j| (j.name.clone(), j.dissipated));
        Some(EnergyCreated {
            gain,
            time,
            sources,
            dissipated,
            joint,
        })
    }

    /// The worst of the run that a joint's separation or stop overrun warning is about
    /// (the table's `gap` or `stop pen.`), in words; `None` for other events.
    fn worst_of(&self, event: &KjointEvent) -> Option<String> {
        let EventSource::Joint { handle, .. } = &event.source else {
            return None;
        };
        let j = &self.joints[*self.slot_of.get(handle)?];
        match &event.kind {
            KjointEventKind::AnchorsSeparating { .. } => Some(format!(
                "worst over the run {} m apart (`gap`)",
                format_figure(j.peak_gap)
            )),
            KjointEventKind::StopOverrun { dof, .. } => {
                let (worst, unit) = if dof.is_rotation() {
                    (j.peak_stop_angle, "rad")
                } else {
                    (j.peak_stop_penetration, "m")
                };
                Some(format!(
                    "worst over the run {} {unit} beyond a stop (`stop pen.`)",
                    format_figure(worst)
                ))
            }
            _ => None,
        }
    }

    /// The row of joint `h`, added (with its name and what it reads of its property) when
    /// first seen.
    fn row(&mut self, h: KjointHandle, name: &str, law: RowLaw) -> usize {
        let k = *self.slot_of.entry(h).or_insert_with(|| {
            self.joints.push(JointSummary::default());
            self.prev.push(None);
            self.laws.push(law);
            self.dof_slip.push([0.0; 2]);
            self.joints.len() - 1
        });
        name.clone_into(&mut self.joints[k].name);
        self.laws[k] = law;
        k
    }

    /// The rows of the joints `events` say were removed (broken, detached), from the
    /// energies and last readout the events carry: the force a joint broke at, and its
    /// energies with the breaking substep's.
    fn update_removed(&mut self, events: &[KjointEvent]) {
        for (handle, energy, last) in events.iter().filter_map(KjointEvent::removed_joint) {
            if let Some(&k) = self.slot_of.get(&handle) {
                self.update_row(k, *energy, last);
            }
        }
    }

    /// Row `k` from a joint's energies and readout.
    fn update_row(&mut self, k: usize, energy: JointEnergy, state: Option<&JointState>) {
        let js = &mut self.joints[k];
        js.stored = energy.stored();
        js.dissipated = energy.dissipated();
        js.motor_work = -energy.motor;
        let Some(s) = state else { return };
        // the transmitted force and moment as vectors (as the failure criterion reads
        // them, docs/breakable.md): a pin carrying 223 N up and 197 N sideways carries
        // 297 N, not its largest component
        let force = magnitude(&s.applied.0[..3]);
        if force > js.peak_force {
            (js.peak_force, js.peak_force_time) = (force, s.time);
        }
        if s.time >= START_UP {
            js.peak_force_after_start = js.peak_force_after_start.max(force);
        }
        let moment = magnitude(&s.applied.0[3..]);
        js.peak_moment = js.peak_moment.max(moment);
        (js.end_force, js.end_moment) = (force, moment);
        js.peak_law_force = js.peak_law_force.max(magnitude(&s.force.0[..3]));
        js.peak_law_moment = js.peak_law_moment.max(magnitude(&s.force.0[3..]));
        let law = self.laws[k];
        let stops = law.stops;
        let gap = (0..3)
            .filter(|i| law.blocked[*i])
            .map(|i| s.q[i] * s.q[i])
            .sum::<f64>()
            .sqrt();
        js.peak_gap = js.peak_gap.max(gap);
        let prev = self.prev[k];
        for d in Dof::ALL {
            let i = d.index();
            let (stop_min, stop_max) = stops[i];
            let pen = match s.status[i].stop {
                StopContact::None => 0.0,
                StopContact::Min => stop_min - s.q[i],
                StopContact::Max => s.q[i] - stop_max,
                StopContact::Coupled => {
                    // Distance beyond the radius of the coupled family.
                    let fam = if d.is_rotation() { 3..6 } else { 0..3 };
                    let c = 0.5 * (stop_min + stop_max);
                    let r = 0.5 * (stop_max - stop_min);
                    let dist: f64 = fam
                        .filter(|k| s.status[*k].stop == StopContact::Coupled)
                        .map(|k| (s.q[k] - c).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    dist - r
                }
            }
            .max(0.0);
            // the plastic part of the motion since the last record, where the DOF slips or
            // slipped over it: `Δq_p = Δq − ΔF_f/K_f`, the friction spring's `F_f = K_f·(q −
            // q_p)`
            let slipping = s.status[i].friction == crate::law::FrictionStatus::Slip;
            let kf = law.friction_stiffness[i];
            // (a DOF without a friction spring of its own slips by a connector law's
            // friction, whose stick stiffness is the connector's: its report's total is
            // taken below)
            let slipped = match prev {
                Some(p) if kf > 0.0 && (slipping || p.slipping[i]) => {
                    let dq = s.q[i] - p.q[i];
                    (dq - (s.parts[i].friction - p.friction[i]) / kf).abs()
                }
                _ => 0.0,
            };
            if d.is_rotation() {
                js.peak_stop_angle = js.peak_stop_angle.max(pen);
                self.dof_slip[k][1] += slipped;
            } else {
                js.peak_stop_penetration = js.peak_stop_penetration.max(pen);
                self.dof_slip[k][0] += slipped;
            }
        }
        // a connector law's friction: its own accumulated plastic slip
        use crate::law::ConnectorReport;
        let connector = match &s.connector {
            Some(ConnectorReport::PlanarFriction(r)) => [r.slip_total, r.twist_slip_total],
            Some(ConnectorReport::JointFriction(r)) if law.rotational_joint_friction => {
                [0.0, r.slip_total]
            }
            Some(ConnectorReport::JointFriction(r)) => [r.slip_total, 0.0],
            _ => [0.0; 2],
        };
        js.slip_distance = self.dof_slip[k][0] + connector[0];
        js.slip_angle = self.dof_slip[k][1] + connector[1];
        self.prev[k] = Some(Previous {
            q: s.q.0,
            friction: Dof::ALL.map(|d| s.parts[d].friction),
            slipping: Dof::ALL.map(|d| s.status[d].friction == crate::law::FrictionStatus::Slip),
        });
    }
}

/// `√(Σ x²)` without overflow: the components are scaled by the largest first (a force
/// saturated at `f64::MAX` has a magnitude of `f64::MAX`, not `inf`).
fn magnitude(x: &[f64]) -> f64 {
    if x.iter().any(|v| v.is_nan()) {
        return f64::NAN;
    }
    let m = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    let r = m * x.iter().map(|v| (v / m).powi(2)).sum::<f64>().sqrt();
    r.min(f64::MAX)
}

/// `M·|g|·L_b·ε` \[J\]: the energy a change of the dynamic bodies' height by the precision
/// of their poses (`ε` of rapier's `Real` times the extent `L_b` of the bodies with their
/// colliders) stands for: a residual below it is below what the poses resolve.
fn pose_resolution(world: &PhysicsWorld) -> f64 {
    use crate::dynamics::from_vec3;
    let mut mass = 0.0;
    let mut points: Vec<nalgebra::Vector3<f64>> = Vec::new();
    for (_, b) in world.bodies.iter().filter(|(_, b)| b.is_dynamic()) {
        mass += b.mass() as f64;
        points.push(from_vec3(b.center_of_mass()));
        for co in b.colliders().iter().filter_map(|h| world.colliders.get(*h)) {
            let aabb = co.compute_aabb();
            points.extend([from_vec3(aabb.mins), from_vec3(aabb.maxs)]);
        }
    }
    let extent = points
        .iter()
        .skip(1)
        .fold(points.first().map(|p| (*p, *p)), |b, p| {
            b.map(|(lo, hi)| (lo.inf(p), hi.sup(p)))
        });
    let extent = extent.map_or(0.0, |(lo, hi)| (hi - lo).norm());
    mass * (world.gravity.length() as f64) * extent * (crate::rapier::math::Real::EPSILON as f64)
}

/// `M·|g|·L` \[J\]: the dynamic bodies' mass, the gravity, and the extent `L` (the diagonal
/// of the bounding box) of their centres of mass and the joints' world anchors.
fn weight_scale(world: &PhysicsWorld, joints: &KjointSet) -> f64 {
    use crate::dynamics::from_vec3;
    let mut mass = 0.0;
    let mut points: Vec<nalgebra::Vector3<f64>> = Vec::new();
    for (_, b) in world.bodies.iter().filter(|(_, b)| b.is_dynamic()) {
        mass += b.mass() as f64;
        points.push(from_vec3(b.center_of_mass()));
    }
    for (_, j) in joints.iter() {
        for (hb, a) in [
            (j.body1, &j.frames.local_anchor1),
            (j.body2, &j.frames.local_anchor2),
        ] {
            if let Some(b) = world.bodies.get(hb) {
                let p = from_vec3(b.translation()) + crate::dynamics::from_quat(*b.rotation()) * a;
                points.push(p);
            }
        }
    }
    let Some(first) = points.first().copied() else {
        return 0.0;
    };
    let (lo, hi) = points
        .iter()
        .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    mass * (world.gravity.length() as f64) * (hi - lo).norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{
        DofStiffness, EventSource, FlexJointSwitchCause, HealthRemedy, KjointEventKind,
    };
    use crate::law::Dof;

    /// The note under the table compares a joint's law and transmitted force, or moment,
    /// whichever is further apart, but not a round-off moment: an axle of ball wheels
    /// (law |M| 2.66e-10 N·m over 4.05e-11 transmitted, a ratio of 6.6) is named by its
    /// force, 7479 N over 3256 N (the vehicle developer's run, the largest moment 126 N·m).
    #[test]
    fn the_law_note_compares_no_round_off() {
        let axle = JointSummary {
            peak_force: 3256.0,
            peak_law_force: 7479.0,
            peak_moment: 4.05e-11,
            peak_law_moment: 2.66e-10,
            ..Default::default()
        };
        let floor = [1e-6 * 92182.0, 1e-6 * 126.0];
        let (ratio, law, peak, unit, what) = axle.law_over_transmitted(floor);
        assert_eq!((law, peak, unit, what), (7479.0, 3256.0, "N", "|F|"));
        assert!((ratio - 7479.0 / 3256.0).abs() < 1e-12);
        // without a floor the round-off's ratio wins, as before
        assert_eq!(axle.law_over_transmitted([0.0; 2]).4, "|M|");
    }

    #[test]
    fn figures_are_plain_where_they_fit_and_exponents_outside() {
        for (v, s) in [
            (22.8312, "22.83"),
            (-22.8312, "-22.83"),
            (1.2e-9, "1.20e-9"),
            (-1.2e-9, "-1.20e-9"),
            (0.0, "0"),
            (-0.0, "0"),
            (9.81, "9.810"),
            (0.001234, "0.001234"),
            (0.0009, "9.00e-4"),
            (123456.7, "123457"),
            (1234567.0, "1.23e6"),
            (3.4e7, "3.40e7"),
            // rounding that carries into the next decade keeps 4 significant digits
            (9.99996, "10.00"),
            (999999.7, "1.00e6"),
            (0.00099996, "0.001000"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
        ] {
            assert_eq!(format_figure(v), s, "{v:e}");
        }
    }

    /// A cell wider than `format!`'s largest width (65 535) is written in full, padded like
    /// the others: a joint named by 70 000 characters panicked the summary after the run.
    #[test]
    fn columns_take_cells_wider_than_format_widths() {
        let long = "j".repeat(70_000);
        let rows = vec![
            vec!["joint".to_owned(), "[N]".to_owned()],
            vec![long.clone(), "1.5".to_owned()],
        ];
        let mut out = String::new();
        write_columns(&mut out, &rows).unwrap();
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0].len(), 70_000 + 2 + 3);
        assert!(lines[0].starts_with("joint "));
        assert!(lines[0].ends_with("  [N]"));
        assert_eq!(lines[1], format!("{long}  1.5"));
    }

    #[test]
    fn plurals() {
        assert_eq!(plural(1, "joint"), "1 joint");
        assert_eq!(plural(0, "joint"), "0 joints");
        assert_eq!(plural(3, "rapier joint"), "3 rapier joints");
    }

    fn joint(name: &str, peak_force: f64, dissipated: f64) -> JointSummary {
        JointSummary {
            name: name.into(),
            peak_force,
            peak_moment: -3.5e-12,
            dissipated,
            ..Default::default()
        }
    }

    /// Every column's cells end at the same character column, whatever the figures' and
    /// the names' lengths, and the units sit under the headings.
    #[test]
    fn the_table_columns_are_aligned() {
        let summary = Summary {
            joints: vec![
                joint("a", 22.8312, 0.0),
                joint("a_much_longer_name", -123456.7, 1.5e-9),
            ],
            ..Default::default()
        };
        let text = summary.table(0.0);
        let lines: Vec<&str> = text.lines().take(4).collect();
        assert!(
            lines[0].starts_with("joint ") && lines[0].contains("peak |F|"),
            "{text}"
        );
        assert!(lines[1].trim_start().starts_with("[N]"), "{text}");
        let cells = |l: &str| -> Vec<(usize, String)> {
            // (end column in characters, text) of each cell (two spaces or more between)
            let mut out = Vec::new();
            let chars: Vec<char> = l.chars().collect();
            let mut i = 0;
            while i < chars.len() {
                if chars[i] == ' ' {
                    i += 1;
                    continue;
                }
                let start = i;
                // a heading like `peak |F|` is one cell: single spaces inside, two between
                while i < chars.len()
                    && !(chars[i] == ' ' && (i + 1 == chars.len() || chars[i + 1] == ' '))
                {
                    i += 1;
                }
                out.push((i, chars[start..i].iter().collect::<String>()));
            }
            out
        };
        let header = cells(lines[0]);
        assert_eq!(header.len(), 13, "{:?}", header);
        for l in &lines[1..] {
            let c = cells(l);
            let ends: Vec<usize> = c.iter().map(|x| x.0).collect();
            let header_ends: Vec<usize> = header.iter().map(|x| x.0).collect();
            if l.starts_with(' ') {
                // the units row has no joint name
                assert_eq!(ends, header_ends[1..], "{text}");
            } else {
                assert_eq!(ends[1..], header_ends[1..], "{text}");
            }
        }
        let row = cells(lines[3]);
        assert_eq!(row[0].1, "a_much_longer_name");
        assert_eq!(row[1].1, "-123457");
        assert_eq!(row[2].1, "-3.50e-12");
        assert_eq!(row[12].1, "1.50e-9");
        assert_eq!(cells(lines[2])[1].1, "22.83");
        assert_eq!(cells(lines[2])[12].1, "0");
    }

    fn event(joint: usize, time: f64, kind: KjointEventKind) -> KjointEvent {
        KjointEvent {
            source: EventSource::Joint {
                handle: KjointHandle::from_raw_parts(joint as u32, 0),
                name: format!("j{joint}"),
            },
            time,
            kind,
        }
    }

    /// A notice: the spring of rx beyond the substep.
    fn rx_spring() -> KjointEventKind {
        KjointEventKind::StiffnessBeyondSubstep {
            dof: Dof::Rx,
            stiffness_of: DofStiffness::Spring,
            stiffness: 1e4,
            omega: 400.0,
            substep: 0.005,
            substeps_needed: 8.0,
        }
    }

    #[test]
    fn health_events_are_listed_once_warnings_first() {
        let events = vec![
            event(0, 0.0, rx_spring()),
            event(
                0,
                0.1,
                KjointEventKind::FlexJointSwitched {
                    cause: FlexJointSwitchCause::ExplicitCall,
                },
            ),
            event(
                1,
                0.5,
                KjointEventKind::AnchorsSeparating {
                    gap: 0.1,
                    size: 1.0,
                    remedy: HealthRemedy::ShorterSubstep,
                },
            ),
            event(0, 1.0, rx_spring()),
            // the same text on another joint is another entry
            event(1, 1.0, rx_spring()),
            event(0, 2.0, rx_spring()),
        ];
        let h = health_report(&events);
        let got: Vec<(Severity, String, usize, f64)> = h
            .iter()
            .map(|h| {
                (
                    h.event.severity(),
                    h.event.source.to_string(),
                    h.count,
                    h.last_time,
                )
            })
            .collect();
        assert_eq!(
            got,
            vec![
                (Severity::Warning, "joint j1".into(), 1, 0.5),
                (Severity::Notice, "joint j0".into(), 3, 2.0),
                (Severity::Notice, "joint j1".into(), 1, 1.0),
            ]
        );
        let summary = Summary {
            events,
            ..Default::default()
        };
        let text = summary.table(0.0);
        let tail = text.split("health of the run").nth(1).expect(&text);
        assert!(tail.starts_with(" (1 warning, 2 notices)\n"), "{text}");
        assert_eq!(
            tail.matches("rx spring (10000 N·m/rad) oscillates at 400.0 rad/s")
                .count(),
            2,
            "{text}"
        );
        assert!(
            tail.contains("(3 times, the last at t = 2.000 s)"),
            "{text}"
        );
        // the model's own events come before the balance, not among the health
        assert!(
            text.find("switched to the dynamic phase (explicit call)")
                .unwrap()
                < text.find("energy balance").unwrap()
        );
    }

    /// A warning given again as its value grew (`dynamics::health::WARNING_GROWTH`) is one
    /// line showing the worst of them, with the times of the first and the last: a soft
    /// joint stretched from 1 mm to 0.1 m, warned at 1.1, 4.5, 18 and 73 mm (and at 2 mm
    /// after its state was reset), read "anchors 0.001100 m apart (5 times, the last at
    /// t = 1.600 s)". A joint that no longer holds, warned again fourfold further beyond
    /// its bounds, is one line as well, at its worst (it was one line per warning).
    #[test]
    fn a_warning_given_again_as_it_grew_is_shown_at_its_worst() {
        let gap = |gap: f64| KjointEventKind::AnchorsSeparating {
            gap,
            size: 0.05,
            remedy: HealthRemedy::LargerBlockedStiffness { stiffness: 1000.0 },
        };
        let apart = |gap: f64| KjointEventKind::NoLongerHolds {
            gap,
            size: 0.5,
            rotation: 0.0,
            contact: None,
            force: 10.0,
            moment: 0.0,
            stiffness: crate::law::BlockedStiffness {
                translational: 1e4,
                rotational: 1e3,
            },
            automatic: false,
        };
        let events = vec![
            event(1, 0.2, gap(0.0011)),
            event(2, 0.3, apart(0.3)),
            event(1, 0.5, gap(0.0045)),
            event(1, 0.9, gap(0.018)),
            event(2, 1.0, apart(1.3)),
            event(1, 1.4, gap(0.073)),
            event(1, 1.6, gap(0.002)),
        ];
        let h = health_report(&events);
        let got: Vec<(String, usize, f64, f64, f64)> = (h.iter())
            .map(|h| {
                (
                    h.event.source.to_string(),
                    h.count,
                    h.first_time,
                    h.event.time,
                    h.last_time,
                )
            })
            .collect();
        assert_eq!(
            got,
            vec![
                ("joint j1".into(), 5, 0.2, 1.4, 1.6),
                ("joint j2".into(), 2, 0.3, 1.0, 1.0),
            ]
        );
        let summary = Summary {
            events,
            ..Default::default()
        };
        let text = summary.table(0.0);
        println!("{text}");
        let tail = text.split("health of the run").nth(1).expect(&text);
        assert!(tail.starts_with(" (2 warnings)\n"), "{text}");
        assert!(
            tail.contains(
                "  warning: joint j1 at t = 1.400000 s: anchors 0.07300 m apart (146.0 % of the \
                 joint's size 0.05000 m); "
            ),
            "{text}"
        );
        assert!(
            tail.contains(
                " (5 times, the first at t = 0.2000 s, the last at t = 1.600 s; the worst shown)"
            ),
            "{text}"
        );
        assert!(
            tail.contains(
                "  warning: joint j2 at t = 1.000000 s: the joint no longer holds: anchors \
                 1.300 m apart"
            ),
            "{text}"
        );
        assert!(
            tail.contains("(2 times, the first at t = 0.3000 s, the last at t = 1.000 s"),
            "{text}"
        );
        for first in ["0.001100 m apart", "0.3000 m apart", "0.002000 m apart"] {
            assert!(!tail.contains(first), "{first}: {text}");
        }
    }
}
