//! The summary of a run: per joint the peaks, slip and dissipation; for the model the
//! energy balance.
//!
//! # Per joint
//!
//! | figure | meaning |
//! |---|---|
//! | `peak\|F\| N`, `peak\|M\| Nm` | peak magnitude of a component of the force / moment the joint **transmitted** to its bodies over a substep (`−P/h` of the implicit update, [`crate::JointState::applied`]), the `AFX AFY AFZ` / `AMX AMY AMZ` columns of the CSV histories |
//! | `law\|F\| N`, `law\|M\| Nm` | peak magnitude of a component of the law's force / moment `F(q, q̇)` ([`crate::JointState::force`], the `FX .. MZ` columns). On a DOF the substep resolves the two agree; on a blocked DOF or a stop stiffer than the substep resolves (`ω·h > 1`) the law's `K·q` is not what the joint transmits (a rod at rest at `Kn = 1e12` transmits its weight with `q` below f32 resolution, so `K·q = 0`; a stop hit fast shows `K·q` far above the moment it transmits) |
//! | `stop pen m`, `stop pen r` | peak penetration beyond a translational / rotational stop |
//! | `slip m`, `slip rad` | distance / angle slipped by friction |
//! | `dissip. J` | work dissipated by the joint: damping, friction, stops and the numerical damping of unresolved DOFs |
//!
//! # Energy balance
//!
//! `residual = (K + V + S + D − W) − (K₀ + V₀)`, with `K` the kinetic and `V` the
//! gravitational potential energy of the bodies ([`crate::dynamics::energy`]), `S` the
//! elastic energy stored in the joints (a blocked DOF stores the energy of the stiffness
//! the update realises, `½·K̃·q²`, not the law's `½·K·q²`), `D` the work they dissipated and
//! `W` the work done from outside: the applied loads' and the prescribed motions' (what the
//! kinematic bodies did through the KJOINT2 joints, [`crate::KjointSet::driven_work`]). It
//! is 0 for an exact integration. rapier's own contacts and joints book nothing: what they
//! dissipate or do (a motor's work, a contact's friction and softness, a kinematic body
//! pushing through a contact) shows in the residual (0.04 % in the arm with a gripper,
//! `assets/scenes/arm_gripper.toml`, whose box is held by contacts). The relative residual
//! divides it by an energy scale the joints' own book cannot inflate: the largest of the
//! peak kinetic energy, the range of the potential energy over the run, `|W|`, and
//! `M·|g|·L` (the dynamic bodies' mass, gravity, and the initial extent `L` of their centres
//! of mass and the joints' anchors). It includes neither `S` nor `D`: a stored or dissipated
//! energy booked wrongly shows in the residual instead of hiding it.

use super::{Observer, OutputError};
use crate::dynamics::{energy, KjointEvent, KjointSet, Severity};
use crate::law::{Dof, StopContact};
use crate::rapier::pipeline::PhysicsWorld;
use std::fmt;

/// Per-joint figures of a run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointSummary {
    /// Joint name.
    pub name: String,
    /// Peak magnitude of a component of the force transmitted over a substep (AFX, AFY,
    /// AFZ: [`crate::JointState::applied`]) \[N\].
    pub peak_force: f64,
    /// Peak magnitude of a component of the moment transmitted over a substep (AMX, AMY,
    /// AMZ) [N·m].
    pub peak_moment: f64,
    /// Peak magnitude of a component of the law's force (FX, FY, FZ:
    /// [`crate::JointState::force`]) \[N\].
    pub peak_law_force: f64,
    /// Peak magnitude of a component of the law's moment (MX, MY, MZ) [N·m].
    pub peak_law_moment: f64,
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
    /// Work dissipated by damping, friction, stops and the numerical damping of unresolved
    /// DOFs \[J\].
    pub dissipated: f64,
}

/// Collects the summary of a run.
#[derive(Debug, Clone, Default)]
pub struct Summary {
    joints: Vec<JointSummary>,
    prev_q: Vec<Option<[f64; 6]>>,
    initial_energy: Option<f64>,
    mechanical: f64,
    peak_kinetic: f64,
    potential_range: Option<(f64, f64)>,
    weight_scale: f64,
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
    /// Work of the applied loads and the prescribed motions.
    pub load_work: f64,
    /// `mechanical + stored + dissipated − load_work − initial`.
    pub residual: f64,
    /// The energy scale of the run: the largest of the peak kinetic energy, the range of
    /// the potential energy, `|W|` and `M·|g|·L` (module docs).
    pub scale: f64,
    /// `residual / scale`.
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

    /// The energy balance, given the work done on the model from outside \[J\]: the
    /// applied loads' and the prescribed motions' ([`crate::scene::RunStats::external_work`]).
    pub fn balance(&self, load_work: f64) -> EnergyBalance {
        let stored: f64 = self.joints.iter().map(|j| j.stored).sum();
        let dissipated: f64 = self.joints.iter().map(|j| j.dissipated).sum();
        let initial = self.initial_energy.unwrap_or(0.0);
        let residual = self.mechanical + stored + dissipated - load_work - initial;
        let range = self.potential_range.map_or(0.0, |(lo, hi)| hi - lo);
        let scale = self
            .peak_kinetic
            .max(range)
            .max(load_work.abs())
            .max(self.weight_scale)
            .max(1e-12);
        EnergyBalance {
            initial,
            mechanical: self.mechanical,
            stored,
            dissipated,
            load_work,
            residual,
            scale,
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
            "{:<16} {:>11} {:>11} {:>11} {:>11} {:>11} {:>11} {:>11} {:>11} {:>11}",
            "joint",
            "peak|F| N",
            "peak|M| Nm",
            "law|F| N",
            "law|M| Nm",
            "stop pen m",
            "stop pen r",
            "slip m",
            "slip rad",
            "dissip. J"
        )?;
        for j in &self.joints {
            writeln!(
                f,
                "{:<16} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} \
                 {:>11.4e} {:>11.4e}",
                j.name,
                j.peak_force,
                j.peak_moment,
                j.peak_law_force,
                j.peak_law_moment,
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
             dissipated {:.6e}, work of loads and motions {:.6e}",
            b.initial, b.mechanical, b.stored, b.dissipated, b.load_work
        )?;
        writeln!(
            f,
            "energy balance residual: {:.4e} J ({:.3} % of the energy scale {:.4e} J)",
            b.residual,
            100.0 * b.relative,
            b.scale
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
            self.weight_scale = weight_scale(world, joints);
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
        let potential = mech - kinetic;
        self.peak_kinetic = self.peak_kinetic.max(kinetic);
        self.potential_range = Some(match self.potential_range {
            None => (potential, potential),
            Some((lo, hi)) => (lo.min(potential), hi.max(potential)),
        });
        for (h, j) in joints.iter() {
            let js = &mut self.joints[h.0];
            js.name = j.name.clone();
            let e = j.energy();
            js.stored = e.elastic;
            js.dissipated = e.dissipated();
            let Some(s) = j.state() else { continue };
            for d in Dof::ALL {
                let i = d.index();
                let f = s.applied[i].abs();
                let f_law = s.force[i].abs();
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
                    js.peak_law_moment = js.peak_law_moment.max(f_law);
                    js.peak_stop_angle = js.peak_stop_angle.max(pen);
                    js.slip_angle += slipped;
                } else {
                    js.peak_force = js.peak_force.max(f);
                    js.peak_law_force = js.peak_law_force.max(f_law);
                    js.peak_stop_penetration = js.peak_stop_penetration.max(pen);
                    js.slip_distance += slipped;
                }
            }
            self.prev_q[h.0] = Some(s.q);
        }
        Ok(())
    }
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
