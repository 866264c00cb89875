//! The run loop of a built scene: substeps with the time-dependent loads applied at each
//! one, then the observers.
//!
//! Each substep of length `h = dt / substeps` at time `t`: the loads are evaluated at `t`
//! and set as the bodies' user forces and torques (so the joints' implicit update sees
//! them), the kinematic bodies of the motions get their velocity over the substep, the
//! motors of rapier joints their target at `t`, then [`crate::KjointSet::step_with`]
//! applies the joint impulses and advances rapier by `h` (contacts and rapier joints
//! included), and the work of the loads over the substep is added up (`F·Δx` of the centre
//! of mass, `τ·ω̄·h` with the mean angular velocity). The work of the motions is what the
//! moving bodies did through the KJOINT2 joints ([`crate::KjointSet::driven_work`]).
//!
//! After every frame, every body of the scene is checked for a finite pose and velocity
//! (`check_bodies`): the joint set checks the bodies of its own joints at every substep,
//! but a body that only rapier moves (a free body, a URDF robot's link on rapier joints, a
//! body in contact) would otherwise turn the summary's energies into NaN with the run
//! ending as if it had succeeded.

use super::build::{BuiltScene, Load, Motion, Motor, MotorJoint, Switch};
use super::schema::LogEvery;
use crate::dynamics::energy;
use crate::dynamics::KjointEvent;
use crate::error::SimError;
use crate::output::{Observer, OutputError};
use crate::rapier::prelude::*;
use crate::{KjointSet, SubstepPhase, SubstepSettings};

/// Overrides of the scene's settings for one run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RunOptions {
    /// Simulated time \[s\] instead of the scene's.
    pub duration: Option<f64>,
    /// Substeps per frame instead of the scene's. A robot's friction and stop stiffnesses
    /// were sized from the scene's substep when it was built
    /// ([`crate::io::urdf::UrdfOptions::substep`]): to run a robot at other substeps, set
    /// the scene's `substeps` before building it, as `kjoint run --substeps` does.
    pub substeps: Option<usize>,
    /// When to call the observers instead of the scene's `output.log`.
    pub log: Option<LogEvery>,
}

/// What a run measured besides the observers.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RunStats {
    /// Frames simulated.
    pub frames: u64,
    /// Substeps simulated.
    pub substeps: u64,
    /// Simulation time at the end \[s\].
    pub time: f64,
    /// Work of the applied loads \[J\].
    pub load_work: f64,
    /// Work of the prescribed motions through the KJOINT2 joints \[J\]
    /// ([`crate::KjointSet::driven_work`] over the run).
    pub motion_work: f64,
    /// Kinetic + potential energy of the bodies at the start \[J\].
    pub initial_mechanical: f64,
    /// Kinetic + potential energy of the bodies at the end \[J\].
    pub final_mechanical: f64,
}

impl RunStats {
    /// The work done on the model from outside \[J\]: the loads' and the motions'.
    pub fn external_work(&self) -> f64 {
        self.load_work + self.motion_work
    }
}

/// Error of a run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunError {
    /// The simulation failed (unstable, invalid joint).
    #[error(transparent)]
    Sim(#[from] SimError),
    /// An output could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// An option is invalid.
    #[error("invalid option {option} = {value}: expected {expected}")]
    Option {
        /// The option.
        option: &'static str,
        /// Its value.
        value: String,
        /// What is accepted.
        expected: &'static str,
    },
}

/// Runs a built scene for its duration, calling every observer at time 0 and then after
/// every frame (or substep), and `progress(frame, frames)` after every frame. Calls
/// [`Observer::finish`] at the end.
pub fn run(
    scene: &mut BuiltScene,
    options: &RunOptions,
    observers: &mut [&mut dyn Observer],
    progress: &mut dyn FnMut(u64, u64),
) -> Result<RunStats, RunError> {
    super::check_run_options(scene, options)?;
    let duration = options.duration.unwrap_or(scene.duration);
    let n = options.substeps.unwrap_or(scene.joints.settings().substeps);
    let settings = SubstepSettings {
        substeps: n,
        ..*scene.joints.settings()
    };
    scene.joints.set_settings(settings);
    let log = options.log.unwrap_or(scene.log);
    let frames = (duration / scene.frame_dt - 1e-9).ceil().max(1.0) as u64;
    let h = scene.frame_dt / n as f64;

    let world = &mut scene.world;
    let joints = &mut scene.joints;
    world.integration_parameters.dt = h as _;
    world.integration_parameters.num_solver_iterations = settings.rapier_iterations.max(1);
    joints.prepare(world);

    let mut stats = RunStats {
        initial_mechanical: energy::mechanical_energy(&world.bodies, world.gravity),
        ..Default::default()
    };
    let driven_at_start = joints.driven_work();
    for o in observers.iter_mut() {
        o.external_work(0.0);
        o.record(joints.time(), world, joints, &[])?;
    }

    let loaded = loaded_bodies(&scene.loads);
    let mut events: Vec<KjointEvent> = Vec::new();
    let mut before: Vec<SubstepStart> = Vec::with_capacity(loaded.len());
    let loads = &scene.loads;
    let (motions, motors) = (&scene.motions, &scene.motors);
    let switches = &scene.switches;
    // the switches already made (they are in time order)
    let mut switched = 0;
    let mut frames_run = || -> Result<(), RunError> {
        for frame in 0..frames {
            joints.step_with(world, scene.frame_dt, |phase, world, joints| {
                match phase {
                    SubstepPhase::Before => {
                        let t = joints.time();
                        apply_loads(world, loads, &loaded, t, &mut before);
                        drive(world, joints, motions, motors, t, h)?;
                        switch(joints, switches, &mut switched, t, h);
                    }
                    SubstepPhase::After => {
                        stats.substeps += 1;
                        add_load_work(world, &loaded, &before, h, &mut stats.load_work);
                        let raised = joints.drain_events();
                        for o in observers.iter_mut() {
                            o.substep(world, joints, &raised)?;
                        }
                        events.extend(raised);
                        if log == LogEvery::Substep {
                            let work = stats.load_work + (joints.driven_work() - driven_at_start);
                            record(observers, work, world, joints, &mut events)?;
                        }
                    }
                }
                Ok::<(), RunError>(())
            })?;
            check_bodies(world, &scene.bodies, joints.time())?;
            if log == LogEvery::Frame {
                let work = stats.load_work + (joints.driven_work() - driven_at_start);
                record(observers, work, world, joints, &mut events)?;
            }
            stats.frames += 1;
            progress(frame + 1, frames);
        }
        Ok(())
    };
    if let Err(e) = frames_run() {
        // the events no record carried, the failing substep's included (often the cause:
        // a warning raised just before), given to the observers before the error; an
        // output that cannot be written has nothing more to say
        if matches!(e, RunError::Sim(_)) {
            events.extend(joints.drain_events());
            for o in observers.iter_mut() {
                let _ = o.failed(&events);
            }
        }
        return Err(e);
    }
    for o in observers.iter_mut() {
        o.finish()?;
    }
    stats.time = joints.time();
    stats.motion_work = joints.driven_work() - driven_at_start;
    stats.final_mechanical = energy::mechanical_energy(&world.bodies, world.gravity);
    Ok(stats)
}

/// An error naming the first body, in scene order, whose pose or velocity is not finite
/// (position, rotation, centre of mass, linear or angular velocity), at time `time` \[s\].
fn check_bodies(
    world: &PhysicsWorld,
    bodies: &[(String, RigidBodyHandle)],
    time: f64,
) -> Result<(), SimError> {
    let bad = bodies.iter().find(|(_, h)| {
        let b = world.bodies.get(*h);
        b.is_some_and(|b| b.is_dynamic_or_kinematic() && !crate::dynamics::pose_is_finite(b))
    });
    match bad {
        None => Ok(()),
        Some((name, _)) => Err(SimError::Unstable {
            time,
            reason: format!(
                "body `{name}` has a non-finite position or velocity: what moves it \
                 diverged (its joints, contacts or loads); check its mass and inertia and \
                 the loads on it, or run with a smaller dt or more substeps"
            ),
        }),
    }
}

/// The loaded bodies, each with the indices of its loads.
type LoadedBodies = Vec<(RigidBodyHandle, Vec<usize>)>;

/// A loaded body's force and torque over a substep \[N, N·m\], and its linear and angular
/// velocity at the substep's start (before the joints' impulses).
type SubstepStart = ([f64; 3], [f64; 3], Vector, Vector);

/// The bodies of `loads`, in the order of their first load.
fn loaded_bodies(loads: &[Load]) -> LoadedBodies {
    let mut loaded: LoadedBodies = Vec::new();
    for (i, l) in loads.iter().enumerate() {
        match loaded.iter_mut().find(|(h, _)| *h == l.body) {
            Some((_, ids)) => ids.push(i),
            None => loaded.push((l.body, vec![i])),
        }
    }
    loaded
}

/// Sets the loads at time `t` (the substep's start) as the bodies' user forces and
/// torques; `before` receives each loaded body's [`SubstepStart`].
fn apply_loads(
    world: &mut PhysicsWorld,
    loads: &[Load],
    loaded: &LoadedBodies,
    t: f64,
    before: &mut Vec<SubstepStart>,
) {
    before.clear();
    for (hb, ids) in loaded {
        let (mut f, mut tau) = ([0.0f64; 3], [0.0f64; 3]);
        for &i in ids {
            let l = &loads[i];
            let v = l.at(t);
            let acc = if l.torque { &mut tau } else { &mut f };
            for k in 0..3 {
                acc[k] += v[k];
            }
        }
        let b = &mut world.bodies[*hb];
        b.reset_forces(true);
        b.reset_torques(true);
        b.add_force(Vector::new(f[0] as _, f[1] as _, f[2] as _), true);
        b.add_torque(Vector::new(tau[0] as _, tau[1] as _, tau[2] as _), true);
        before.push((f, tau, b.linvel(), b.angvel()));
    }
}

/// Gives the kinematic bodies of the motions their velocity over the substep from `t` to
/// Makes the switches of the substep starting at `t` (length `h`): those due at `t` or
/// before, within half a substep, beyond the `done` ones already made.
fn switch(joints: &mut KjointSet, switches: &[Switch], done: &mut usize, t: f64, h: f64) {
    for s in &switches[*done..] {
        if s.time > t + 0.5 * h {
            break;
        }
        joints.set_enabled(s.joint, s.enabled);
        *done += 1;
    }
}

/// `t + h`, and the motors their target (or force) at `t`.
fn drive(
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    motions: &[Motion],
    motors: &[Motor],
    t: f64,
    h: f64,
) -> Result<(), SimError> {
    for m in motions {
        let b = &mut world.bodies[m.body];
        let x = b.translation();
        let v = m.velocity(t, h, [x.x, x.y, x.z].map(f64::from));
        b.set_linvel(Vector::new(v[0] as _, v[1] as _, v[2] as _), true);
    }
    for m in motors {
        match m.joint {
            MotorJoint::Rapier { joint, axis } => {
                let target = m.at(t) as Real;
                let same = world
                    .impulse_joints
                    .get(joint)
                    .is_some_and(|j| j.data.motor(axis).is_some_and(|mo| mo.target_pos == target));
                // get_mut marks the joint modified: only when the target changes
                if !same {
                    if let Some(j) = world.impulse_joints.get_mut(joint, true) {
                        j.data.motors[axis as usize].target_pos = target;
                    }
                }
            }
            MotorJoint::Kjoint { dof, joint, .. } if m.force => {
                let motor = joints.get(joint).and_then(|j| j.motor(dof)).copied();
                let driven = motor.unwrap_or_default().with_force(m.at(t));
                joints.set_motor(joint, dof, Some(driven))?;
            }
            MotorJoint::Kjoint { joint, dof, q0 } => {
                let target = m.at(t) - q0;
                let Some(&motor) = joints.get(joint).and_then(|j| j.motor(dof)) else {
                    continue;
                };
                // (set_motor does not analyse the set again; unchanged, it does nothing)
                let moved = crate::KjointMotor {
                    target_pos: target,
                    ..motor
                };
                joints.set_motor(joint, dof, Some(moved))?;
            }
        }
    }
    Ok(())
}

/// Adds to `work` the work of the loads over the substep of length `h` just done on the
/// dynamic loaded bodies, `F·v̄·h + τ·ω̄·h` with the mean of the velocities at the substep's
/// start and end.
///
/// That is the kinetic energy the load gives the body in rapier's update: with
/// `v⁺ = v⁻ + (F·h + P)/m` (`P` the joints' impulse, booked by the joints on the same mean)
/// the change `½m(v⁺² − v⁻²) = (F·h + P)·(v⁻ + v⁺)/2`. The centre of mass moves by
/// `Δx = h·v⁺` (semi-implicit Euler), so `F·Δx` booked `F·h·(v⁺ − v⁻)/2 = F²·h²/(2m)` more
/// each substep: `(h/2)·∫F²/m dt` over a run, which grows with time for a varying load (a
/// free 1 kg cart under 10·sin(2πt) N read a work of 0.104 J over one period where it is 0;
/// a constant force's telescopes to `F·h·(v_end − v_start)/2`, as gravity's potential
/// energy read from the positions does).
fn add_load_work(
    world: &PhysicsWorld,
    loaded: &LoadedBodies,
    before: &[SubstepStart],
    h: f64,
    work: &mut f64,
) {
    for ((hb, _), (f, tau, v0, w0)) in loaded.iter().zip(before) {
        let b = &world.bodies[*hb];
        if !b.is_dynamic() {
            continue;
        }
        let v = (b.linvel() + *v0) * 0.5;
        let w = (b.angvel() + *w0) * 0.5;
        for k in 0..3 {
            *work += (f[k] * v[k] as f64 + tau[k] * w[k] as f64) * h;
        }
    }
}

/// Calls every observer with the external work so far and the events since the last
/// call, which are then cleared.
fn record(
    observers: &mut [&mut dyn Observer],
    work: f64,
    world: &PhysicsWorld,
    joints: &KjointSet,
    events: &mut Vec<KjointEvent>,
) -> Result<(), RunError> {
    for o in observers.iter_mut() {
        o.external_work(work);
        o.record(joints.time(), world, joints, events)?;
    }
    events.clear();
    Ok(())
}
