//! The summary of a run: per joint the peaks, slip and dissipation; for the model the
//! energy balance.
//!
//! Energy balance: `residual = (K + V + S + D − W) − (K₀ + V₀)`, with `K` the kinetic and
//! `V` the gravitational potential energy of the bodies ([`crate::dynamics::energy`]), `S`
//! the elastic energy stored in the joints, `D` the work they dissipated (damping,
//! friction, stops) and `W` the work of the applied loads. It is 0 for an exact
//! integration; the relative residual divides it by the largest of the peak `K + S`, `|W|`
//! and `D`.

use super::{Observer, OutputError};
use crate::dynamics::{energy, KjointEvent, KjointSet, Severity};
use crate::law::{Dof, StopContact};
use rapier3d::pipeline::PhysicsWorld;
use std::fmt;

/// Per-joint figures of a run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointSummary {
    /// Joint name.
    pub name: String,
    /// Peak magnitude of a force component (FX, FY, FZ) \[N\].
    pub peak_force: f64,
    /// Peak magnitude of a moment component (MX, MY, MZ) [N·m].
    pub peak_moment: f64,
    /// Peak penetration beyond a translational stop \[m\].
    pub peak_stop_penetration: f64,
    /// Peak penetration beyond a rotational stop \[rad\].
    pub peak_stop_angle: f64,
    /// Distance slipped by friction (sum of `|Δq|` between records while slipping),
    /// translations \[m\].
    pub slip_distance: f64,
    /// Angle slipped by friction, rotations \[rad\].
    pub slip_angle: f64,
    /// Elastic energy stored at the end \[J\].
    pub stored: f64,
    /// Work dissipated by damping, friction and stops \[J\].
    pub dissipated: f64,
}

/// Collects the summary of a run.
#[derive(Debug, Clone, Default)]
pub struct Summary {
    joints: Vec<JointSummary>,
    prev_q: Vec<Option<[f64; 6]>>,
    initial_energy: Option<f64>,
    mechanical: f64,
    peak_kinetic_stored: f64,
    time: f64,
    events: Vec<KjointEvent>,
}

/// The energy balance of a run \[J\].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyBalance {
    /// Kinetic + potential energy at the start.
    pub initial: f64,
    /// Kinetic + potential energy at the end.
    pub mechanical: f64,
    /// Elastic energy stored in the joints at the end.
    pub stored: f64,
    /// Work dissipated by the joints.
    pub dissipated: f64,
    /// Work of the applied loads.
    pub load_work: f64,
    /// `mechanical + stored + dissipated − load_work − initial`.
    pub residual: f64,
    /// `residual` over the energy scale of the run.
    pub relative: f64,
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

    /// The energy balance, given the work of the applied loads \[J\] (from
    /// [`crate::scene::RunStats::load_work`]).
    pub fn balance(&self, load_work: f64) -> EnergyBalance {
        let stored: f64 = self.joints.iter().map(|j| j.stored).sum();
        let dissipated: f64 = self.joints.iter().map(|j| j.dissipated).sum();
        let initial = self.initial_energy.unwrap_or(0.0);
        let residual = self.mechanical + stored + dissipated - load_work - initial;
        let scale = self
            .peak_kinetic_stored
            .max(load_work.abs())
            .max(dissipated)
            .max(1e-12);
        EnergyBalance {
            initial,
            mechanical: self.mechanical,
            stored,
            dissipated,
            load_work,
            residual,
            relative: residual / scale,
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
        writeln!(
            f,
            "{:<16} {:>11} {:>11} {:>11} {:>11} {:>11} {:>11} {:>11}",
            "joint",
            "peak|F| N",
            "peak|M| Nm",
            "stop pen m",
            "stop pen r",
            "slip m",
            "slip rad",
            "dissip. J"
        )?;
        for j in &self.joints {
            writeln!(
                f,
                "{:<16} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e}",
                j.name,
                j.peak_force,
                j.peak_moment,
                j.peak_stop_penetration,
                j.peak_stop_angle,
                j.slip_distance,
                j.slip_angle,
                j.dissipated
            )?;
        }
        for e in self.events.iter().filter(|e| e.severity == Severity::Info) {
            writeln!(f, "{e}")?;
        }
        let b = self.balance(load_work);
        writeln!(
            f,
            "energy [J]: initial {:.6e}, final kinetic+potential {:.6e}, stored {:.6e}, \
             dissipated {:.6e}, work of loads {:.6e}",
            b.initial, b.mechanical, b.stored, b.dissipated, b.load_work
        )?;
        writeln!(
            f,
            "energy balance residual: {:.4e} J ({:.3} % of the energy scale)",
            b.residual,
            100.0 * b.relative
        )?;
        // the health of the run, gathered at the end (`dynamics::health`)
        let health: Vec<&KjointEvent> = self
            .events
            .iter()
            .filter(|e| e.severity != Severity::Info)
            .collect();
        if !health.is_empty() {
            writeln!(f, "health of the run:")?;
            for e in health {
                writeln!(f, "  {e}")?;
            }
        }
        Ok(())
    }
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
        if self.initial_energy.is_none() {
            self.initial_energy = Some(mech);
        }
        self.mechanical = mech;
        self.time = time;
        self.events.extend_from_slice(events);
        if self.joints.len() < joints.len() {
            self.joints.resize_with(joints.len(), Default::default);
            self.prev_q.resize(joints.len(), None);
        }
        let kinetic: f64 = world
            .bodies
            .iter()
            .map(|(_, b)| energy::kinetic_energy(b))
            .sum();
        let mut stored = 0.0;
        for (h, j) in joints.iter() {
            let js = &mut self.joints[h.0];
            js.name = j.name.clone();
            let e = j.energy();
            js.stored = e.elastic;
            js.dissipated = e.dissipated();
            stored += e.elastic;
            let Some(s) = j.state() else { continue };
            for d in Dof::ALL {
                let i = d.index();
                let f = s.force[i].abs();
                let law = j.property.dof(d);
                let pen = match s.status[i].stop {
                    StopContact::None => 0.0,
                    StopContact::Min => law.stop_min - s.q[i],
                    StopContact::Max => s.q[i] - law.stop_max,
                    StopContact::Coupled => {
                        // Distance beyond the radius of the coupled family.
                        let fam = if d.is_rotation() { 3..6 } else { 0..3 };
                        let c = 0.5 * (law.stop_min + law.stop_max);
                        let r = 0.5 * (law.stop_max - law.stop_min);
                        let dist: f64 = fam
                            .filter(|k| s.status[*k].stop == StopContact::Coupled)
                            .map(|k| (s.q[k] - c).powi(2))
                            .sum::<f64>()
                            .sqrt();
                        dist - r
                    }
                }
                .max(0.0);
                let slipped = match (self.prev_q[h.0], s.status[i].friction) {
                    (Some(p), crate::law::FrictionStatus::Slip) => (s.q[i] - p[i]).abs(),
                    _ => 0.0,
                };
                if d.is_rotation() {
                    js.peak_moment = js.peak_moment.max(f);
                    js.peak_stop_angle = js.peak_stop_angle.max(pen);
                    js.slip_angle += slipped;
                } else {
                    js.peak_force = js.peak_force.max(f);
                    js.peak_stop_penetration = js.peak_stop_penetration.max(pen);
                    js.slip_distance += slipped;
                }
            }
            self.prev_q[h.0] = Some(s.q);
        }
        self.peak_kinetic_stored = self.peak_kinetic_stored.max(kinetic + stored);
        Ok(())
    }
}
