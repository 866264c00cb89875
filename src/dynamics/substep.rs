//! One substep of the joint set as named stages, each a loop over contiguous data:
//!
//! 1. **topology**: the structure (which bodies are dynamic, which joints are attached) is
//!    checked against rapier's bodies and re-analysed only when it changed (the bodies that
//!    were not dynamic here, whose poses it reads, the dynamic ones by the gather stage as
//!    it reads them);
//! 2. **gather bodies**: pose, inverse mass, external velocity change and gyroscopic term of
//!    every dynamic jointed body, once per body;
//! 3. **sensors**: activations from the previous substep's readout;
//! 4. **prepare joints**, in two loops whose machine code each fits the instruction cache,
//!    over a run of joints at a time ([`PREPARE_RUN`], as the gather stage's first two
//!    loops over runs of bodies: what the first loop leaves of a run, the second finds in
//!    the cache):
//!    (a) **measure**: kinematics and Jacobians of every joint, and the correction of the
//!    last substep's work to the rates the bodies ended with; (b) the last substep's stored
//!    results written into the joint's record, law, connector (and its events), the
//!    implicit blocks `G` and `h·Q`, the numerical damping of unresolved DOFs, the readout
//!    record (where something reads it: [`Readouts`]) and the screen of
//!    the health checks ([`health::suspect`]), once per joint;
//! 5. **solve**: the implicit system, island by island ([`super::solve`]);
//! 6. **apply impulses**: the velocity change of every body, written to rapier;
//! 7. **store results** (6 and 7 in turns over a run of bodies and one of joints, first to
//!    last, as stage 4: the store stage finds the run's velocity changes in the cache): the transmitted force and the work of each joint's impulse, the
//!    one place where the solve's work is booked, kept in the substep's data
//!    ([`StoredJoint`]) for the next 4b to write into the record, or written into it at
//!    once at the substeps whose readouts are read ([`Readouts::All`]: a step's last, every
//!    one of `step_with`); in the same loop, the health
//!    checks ([`health`]) of the joints the screen flagged and the failure criterion of the
//!    breakable ones (docs/breakable.md), whose records are written at once; the joints that
//!    broke are removed after the loop.
//!
//! A large set of many islands runs stages 2 to 7 over one tile of whole islands after
//! another, the tiles sharing their per-substep arrays ([`super::tiles`]); the results are
//! the same bits.
//!
//! Nothing here allocates per substep once the topology is analysed.
//!
//! # Direction of the loops
//! At 10 000 joints a stage's data have left the second-level cache (1 MB) before the next
//! stage reads them, and much of them the last-level cache too (≈ 4 KB a joint a substep
//! with rapier's bodies), so what a loop finds in the caches is what the loops before it
//! touched last. Loops whose results do not depend on their order therefore run in the
//! direction that starts where the loop before them ended:
//!
//! * the gather stage's loop over the gyroscopic terms, last body of its run first: the
//!   loop before it ends on the run's last bodies' solver data;
//! * the measure stage's motion loop, last joint of its run first: the rotation loop before
//!   it ends on the run's last joints' frames and rotations, and the prepare loop after it
//!   starts on the run's first joints' motions, Jacobians and stored results, which the
//!   motion loop then wrote last;
//! * the write of the stored results into the records where a step ends
//!   ([`KjointSet::fold_stored_results`]), last joint first: the store stage ends on the
//!   last joints' stored results, and the next prepare loop starts on the first joints'
//!   records.
//!
//! Each loop still does the same operations on every joint and body: the same bits (state
//! hashes of the bench scenes), and an error found in a reversed loop names the first joint
//! in the set's order, as before. Left first to last: the loops whose order is in their
//! results (the prepare loop sums each body's geometric stiffness in joint order; the store
//! stage's events and energy book), the gather stage's first two (no gain measured) and
//! the store stage's (last joint first made the 10 000-link chain 4–7 % slower: the write
//! after the step then starts where the store stage started). The apply stage ran last
//! body first, where the solve's back-substitution ends (parents first: a chain inserted
//! from its root), until it went over runs with the store stage (2026-12-07: the
//! 10 000-link chain's frame 0.983 of the one before, the 1000-link chain's and the
//! contact scene's the same).

use super::convert::{from_vec3, to_vec3};
use super::event::{EventSource, KjointEvent, KjointEventKind};
use super::health;
#[cfg(target_arch = "x86_64")]
use super::isa;
use super::joint::{JointState, Kjoint, KJOINT_HOT_BYTES};
use super::joint_set::{KjointHandle, KjointSet};
use super::prefetch;
use super::sleep::is_awake_dynamic;
use super::solve::{
    self, GeometricLoad, SolveFailure, Solver, SolverBody, SolverJoint, SolverJoints,
};
use crate::error::SimError;
use crate::kinematics::{self, BodyPose};
use crate::law::{self, LawParams};
use crate::rapier::dynamics::{RigidBody, RigidBodyHandle, RigidBodySet};
use crate::rapier::math::Vector;
use nalgebra::{Matrix3, Vector3, Vector6};

mod bodies;
mod prepare;
use bodies::{
    add_gyroscopic_change, flush_velocity, reduced, solver_body, watched_pose, Gyroscopic,
    MassCache,
};
pub(crate) use bodies::{body_pose, mean_inertia, pose_is_finite};

/// What a dynamic jointed body contributes to a substep.
#[derive(Debug, Clone, Copy)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct GatheredBody {
    pub pose: BodyPose,
    pub mass: f64,
    pub mean_inertia: f64,
    /// Gyroscopic velocity change integrated by the set (zero when rapier does it).
    pub gyro: Vector3<f64>,
    /// External velocity change before the geometric stiffness augments it: what rapier
    /// (gravity, user forces) and the gyroscopic term give the body by themselves.
    pub dv_plain: Vector6<f64>,
    /// Whether the body has a user torque (`bodies::solver_body`).
    pub torque: bool,
    /// The body's principal axes in the world at its current rotation (columns), as
    /// `bodies::solver_body` found them for its inertia: the gyroscopic term's loop reads
    /// them (each took the rotation matrix again, 49 instructions a body).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub axes: Matrix3<f64>,
    /// Where rapier's contacts hold the body ([`SubstepData::held`]): the part of its
    /// contact change the rotation share takes, `min(1, W/P)` ([`CONTACT_ROTATION_SHARE`],
    /// the gate), found once a body by the gather stage (the prepare stage took it again at
    /// each joint side). Not read where the body is not held.
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub gate: f64,
}

impl GatheredBody {
    /// A body before its first gather (overwritten by the gather stage).
    pub(crate) fn empty() -> Self {
        GatheredBody {
            pose: BodyPose::identity(),
            mass: 0.0,
            mean_inertia: 0.0,
            gyro: Vector3::zeros(),
            dv_plain: Vector6::zeros(),
            torque: false,
            axes: Matrix3::identity(),
            gate: 1.0,
        }
    }
}

/// What the gather stage found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Gather {
    /// Every body gathered.
    Done,
    /// A body was removed from the world or is no longer dynamic.
    TopologyChanged,
    /// The body of this solver slot has a non-finite pose or velocity.
    NonFinite(u32),
}

/// Per-joint results of the prepare stage that the store stage needs. (The rates at the
/// substep's start the store stage reads from the joint's motion, and the part of them
/// that bodies which are not dynamic give it derives again from their poses: neither is
/// copied here, 96 bytes a joint less to write and read each substep.)
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct PreparedJoint {
    /// Size of the joint \[m\]: the lever arms from the dynamic bodies' centres of mass to
    /// their own anchors, each at least its body's radius of gyration (fixed in the
    /// bodies), at least the initial length and
    /// [`health::MIN_SIZE`]; written by the analysis of the topology.
    pub size: f64,
    /// The impulse `P` as each dynamic side's body takes it, `g_s = J_sᵀ·P` (zero for a side
    /// that is not dynamic), with the Jacobians of the substep's start. This and
    /// [`Self::end_power`] are written by the store stage, for the next substep's end-rate
    /// correction ([`end_rate_correction`]), which reads them only after a store stage ran.
    pub side_impulse: [Vector6<f64>; 2],
    /// `P·(q̇⁺ − q̇_driven)` \[W·s\]: the power of `P` along the rates the solve predicts for
    /// the substep's end (joint impulses, gravity, user forces, gyroscopic term), less the
    /// bodies that are not dynamic; `Σ_s g_s·v⁺_s`.
    pub end_power: f64,
    /// Whether the store stage runs the joint's health checks ([`health::suspect`]).
    pub suspect: bool,
    /// Whether [`health::suspect`] also screens the joint's curve springs
    /// and its rotation vector's jumps ([`health::Screens`]): written by the analysis of
    /// the topology (which a property changed through `get_mut` brings), all on where a
    /// snapshot taken before 2026-12-06 is restored without them.
    #[cfg_attr(feature = "serde-serialize", serde(default = "health::Screens::all"))]
    pub screens: health::Screens,
    /// What the prepare stage asks of the joint's property ([`law::PropertyShape`]):
    /// written by the analysis of the topology, the general shape where a snapshot taken
    /// before 2026-12-07 is restored without it.
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub shape: law::PropertyShape,
}

/// Which joints' readouts (`JointState`) a substep writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Readouts {
    /// Every joint's: the last substep of [`KjointSet::step`], every substep of
    /// [`KjointSet::step_with`] and [`KjointSet::apply_substep`].
    All,
    /// Those something reads before the next is written: the joints whose health checks
    /// or failure criterion run in the substep, or all while a sensor waits for a joint's
    /// force. The substeps before the last of a plain [`KjointSet::step`], whose readouts
    /// nothing else reads.
    Read,
}

/// What the store stage (stage 7) found for a joint and has not yet written into its record:
/// the next substep's prepare stage writes it while it has the record in cache (at 10 000
/// joints a second pass over the 2 KB records each substep waited for memory); the store
/// stage writes it itself at the substeps whose readouts are read, and
/// [`KjointSet::fold_stored_results`] for every joint where the set changes in between.
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct StoredJoint {
    /// Work `W = P·(q̇⁻ + q̇⁺)/2` \[J\] of the substep's impulse on the bodies.
    pub work: f64,
    /// Force transmitted over the substep, `−P/h`.
    pub applied: [f64; 6],
    /// `work` and `applied` are not yet booked on the joint.
    pub pending: bool,
    /// The prepare stage of the substep that stored this wrote the joint's readout: its
    /// `applied` and energies are written into it with the booking.
    pub readout: bool,
    /// End-rate correction \[J\] measured by stage 4a ([`end_rate_correction`]),
    /// to take from the joint's numerical energy (0 once taken).
    pub correction: f64,
}

/// The set's substep data: the topology and contiguous per-body and per-joint arrays, sized
/// once per topology.
#[derive(Debug, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct SubstepData {
    /// Whether the arrays below match the joints and bodies.
    pub valid: bool,
    /// rapier handle of every solver body.
    pub handles: Vec<RigidBodyHandle>,
    /// Where each solver body's rapier record was when the gather stage last read it: a
    /// cache hint only ([`prefetch_body`]), never dereferenced. Looking a body up by its
    /// handle reads its record (the handle's generation) so a hint through the handle
    /// waited for the very line it asked for.
    pub body_addr: Vec<usize>,
    /// Whether and how the set integrates the body's gyroscopic term.
    pub gyro_on: Vec<Gyroscopic>,
    /// Solver bodies of each joint (`None`: the side is fixed or kinematic).
    pub sides: Vec<[Option<u32>; 2]>,
    /// Per joint side: whether its body is dynamic and carries no other active joint (a
    /// pendulum's bob), which swings about the joint's anchor ([`solve::swing_lever`]).
    pub alone: Vec<[bool; 2]>,
    /// The rapier bodies of the active joints that were not dynamic at the last analysis
    /// (fixed, kinematic or disabled; each once): what the topology stage checks at every
    /// substep. The dynamic ones are [`Self::handles`], checked by the gather stage as it
    /// reads them (a second pass over 10 000 bodies cost as much as the gather).
    pub watched: Vec<RigidBodyHandle>,
    /// Pose of every watched body, read by the topology stage at every substep (a scene of
    /// pendulums hung from the ground converted the ground's pose once per joint).
    pub watched_pose: Vec<BodyPose>,
    /// Whether each watched body was kinematic at the analysis (else fixed, disabled or
    /// asleep).
    pub watched_kinematic: Vec<bool>,
    /// For each joint side that is not dynamic, its index in [`Self::watched`].
    pub watched_of: Vec<[u32; 2]>,
    /// (Not saved by serde: built again from the topology when a set is read back,
    /// [`restored_tile`].)
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub solver: Solver,
    /// The tile's topology is the first tile's, whose [`Self::solver`] it borrows at each
    /// substep (its own is empty): a set of many alike islands keeps one solver's
    /// workspace in the cache ([`super::tiles`]).
    pub shares_solver: bool,
    pub bodies: Vec<SolverBody>,
    /// What the gather stage derived from each body's mass properties ([`MassCache`]).
    pub mass_cache: Vec<MassCache>,
    pub gathered: Vec<GatheredBody>,
    /// The joint forces on each body, whose geometric stiffness the solve makes implicit.
    pub geo: Vec<GeometricLoad>,
    pub joints: SolverJoints,
    pub prepared: Vec<PreparedJoint>,
    /// What stage 7 left for each joint's record ([`StoredJoint`]).
    pub stored: Vec<StoredJoint>,
    /// For each joint with a kinematic side, the displacement `h·J·v` that side gave it
    /// over the last substep, and the time of the substep it is for, the next (NaN:
    /// none), for the booking of the work of its motion (stage 7).
    #[cfg_attr(feature = "serde-serialize", serde(with = "nan_as_none"))]
    pub driven_before: Vec<(f64, Vector6<f64>)>,
    /// Whether a joint can break ([`Kjoint::break_criterion`]): the store stage writes its
    /// record at once and checks it.
    pub breakable: Vec<bool>,
    /// Whether [`Self::stored`] holds anything not yet written into the records.
    pub unfolded: bool,
    /// Motion of every joint measured by stage 4a for the rest of stage 4.
    pub motion: Vec<kinematics::JointMotion>,
    /// The rotations of every joint, measured by the first loop of stage 4a for its second.
    pub rotation: Vec<kinematics::Measured>,
    pub impulses: Vec<Vector6<f64>>,
    pub velocity: Vec<Vector6<f64>>,
    /// The topology was just analysed: the next prepare stage gives the start notices.
    pub fresh: bool,
    /// The tile's islands, for the sleep stage ([`super::sleep`]).
    pub islands: super::sleep::Islands,
    /// The last substep's work was booked with the rates the solve predicted for its end
    /// (`PreparedJoint::end_power`): the next substep books the difference to the rates the
    /// bodies actually ended with (in the measure stage).
    pub book_pending: bool,
    /// Per body: `(v, ω)` as the solve predicts rapier ends the substep with it (what the
    /// apply stage wrote plus rapier's own gravity and user forces), for
    /// [`ContactPrediction`].
    pub v_pred: Vec<Vector6<f64>>,
    /// Per body: the velocity change rapier's constraints (contacts, rapier joints) gave it
    /// in the last substep beyond what the solve predicted, taken as recurring in this one
    /// ([`ContactPrediction`]; zero below round-off, [`contact_change`]).
    pub dv_contact: Vec<Vector6<f64>>,
    /// Per body: the world axes along which rapier's contacts hold it against gravity
    /// (bit `a` for axis `a`; [`held_axes`]), found by the gather stage from
    /// [`Self::dv_contact`]: the solve takes the body as [`HELD_MASS`] times heavier along
    /// them, and the apply stage gives it its real share of the impulses.
    /// (Not saved by serde: found again by the next gather stage; sized at the read,
    /// [`restored_tile`].)
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub held: Vec<u8>,
    /// Per island of the tile ([`Self::islands`]): its weight over the substep,
    /// `M·|g|·h` \[N·s\] with this substep's masses, written by the gather stage where a
    /// body is held, for the gate of [`CONTACT_ROTATION_SHARE`]. (Not saved by serde:
    /// written again, and sized, by the next gather stage that reads it.)
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub island_weight: Vec<f64>,
    /// The bodies the solve stage freed a held axis of in this substep
    /// ([`release_lifted`]), whose islands it solves again. (Not saved by serde: cleared
    /// and written where it is read.)
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub released: Vec<u32>,
    /// Per body: the scale of [`Self::v_pred`]'s round-off, linear and angular: the squared
    /// norms of the velocity written and of rapier's own change added to it.
    pub pred_scale: Vec<[f64; 2]>,
    /// What [`Self::v_pred`] and [`Self::dv_contact`] hold.
    pub contact_pred: ContactPrediction,
    /// Whether a body of the tile has a [`Self::dv_contact`] this substep (the prepare
    /// stage looks at the joints' bodies only then).
    pub any_contact: bool,
    /// Whether a body of the tile has a [`Self::held`] axis this substep.
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub any_held: bool,
    /// Whether rapier's step can change a body of the tile beyond gravity and user forces
    /// (found by the gather stage): the apply stage writes [`Self::v_pred`] only then.
    pub touchable: bool,
    /// Whether a body of the tile had a collider at the analysis (a collider attached to a
    /// jointed body later is seen at the next analysis, which the change of the body's mass
    /// properties brings: `KjointSet::check_masses`; a collider without mass, at the next
    /// analysis for another cause).
    pub colliders: bool,
}

/// The velocity change of rapier's contacts and joints, predicted from the last substep's.
///
/// The solve predicts the joints' rates at the substep's end from the impulses, gravity and
/// user forces (`P = h·Q − G·(J·Δv)`, [`super::solve`]); rapier's contacts and joints act
/// after it, in rapier's step. A joint whose body rests on a contact is then charged, every
/// substep, the implicit response `G·(J·Δv)` to a motion the contact cancels: at rest
/// `K·q = F·(1 + h·(h·K/β + C)·W)` instead of `K·q = F` (a car's spring of 5e4 N/m and
/// 3000 N·s/m on a 20 kg wheel on the ground, 4 substeps: 72 % too far down). So the
/// velocity change the bodies ended the last substep with beyond the prediction,
/// `δv = v − v_pred`, is taken as recurring in this one on the DOFs the substep resolves
/// (`h·Q −= G·(J·δv)`, [`prepare::predict_contacts`]): at rest it is what the contact does
/// again, and the impulse is `h·Q` as statics want; where the contact ends, it is wrong for
/// one substep. The DOFs the substep does not resolve (blocked ones) are left out: for
/// them the lag of one substep makes a slow oscillation with the contact's response to the
/// joint's own impulse (a block on a light foot went unstable); they keep part of the known
/// limit of `F·h²/m` a substep, the body the contact holds taken as heavier ([`held_axes`]);
/// the rotations among them take a share of it ([`CONTACT_ROTATION_SHARE`]).
/// Bodies nothing of rapier's touches get `δv` of f32 round-off, zeroed by
/// [`contact_change`], and no joint is touched: their results are the same bits.
///
/// A substep of another length than the last (the frame's `dt` changed) takes `δv` scaled
/// by the ratio of the lengths: a contact that holds a body does so with an impulse of its
/// load times the substep (a car body on its spring above a wheel on the ground, settled,
/// jumped to 3.9 cm/s when `dt` went from 1/60 to 1/30 s; a game developer's trial,
/// 2026-12-04).
///
/// At the first substep of a step, `δv` is the one the set measured after the last substep
/// of the step before ([`KjointSet::check_bodies_and_spins`]), before the user could change
/// the bodies between steps; with [`KjointSet::apply_substep`], a velocity the user writes
/// between substeps is taken for rapier's.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) enum ContactPrediction {
    /// Nothing to predict from (a fresh analysis, a Radioss-start kick).
    #[default]
    None,
    /// [`SubstepData::v_pred`] holds the last substep's prediction: the gather stage
    /// measures `δv` against the bodies' velocities.
    Measure,
    /// [`SubstepData::dv_contact`] holds the `δv` measured after the last step.
    Stored,
}

/// The part of `v − v_pred` beyond round-off: per half (linear, angular), zero where
/// `|δ|² ≤ 2e-10·scale` with `scale` the squared norms of the velocity the set wrote and of
/// rapier's own change to it ([`SubstepData::pred_scale`]): a relative 1.4e-5, a hundred
/// times f32's rounding of rapier's velocities and of its sum.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn contact_change(
    v: &Vector6<f64>,
    v_pred: &Vector6<f64>,
    scale: &[f64; 2],
) -> Vector6<f64> {
    let d = v - v_pred;
    let half = |k: usize| d.fixed_rows::<3>(3 * k).norm_squared() > 2e-10 * scale[k];
    let (lin, ang) = (half(0), half(1));
    Vector6::new(
        if lin { d[0] } else { 0.0 },
        if lin { d[1] } else { 0.0 },
        if lin { d[2] } else { 0.0 },
        if ang { d[3] } else { 0.0 },
        if ang { d[4] } else { 0.0 },
        if ang { d[5] } else { 0.0 },
    )
}

/// How many times heavier the solve takes a body along an axis its contacts hold
/// ([`held_axes`]). The blocked DOF's opening under a contact's load goes as the inverse of
/// the body's mass in the solve: 4 takes a light foot's joint from `F·h²/m` a substep to
/// about `0.4·F·h²/m` (a 30 kg block on a 1 kg foot: 7.4 → 2.04 mm at rest, 4 substeps).
/// A hold of 10⁶ (the contact taken as rigid) brought it to `F/K` (0.32 mm), but the stiff
/// blocked mode, unresolved by the substep, then rang with the contact one substep behind
/// it: a box foot at rapier's single PGS iteration hopped the block off the ground, an A1
/// under random torques opened a calf 0.58 rad at 16 substeps, resting ragdolls never slept
/// (2026-12-06, README "Known limits"). At 4 none of that: the suite's scenes are as stable
/// as without the hold.
pub(crate) const HELD_MASS: f64 = 4.0;

/// The share `ρ` of the velocity change rapier's contacts gave a joint's bodies in the last
/// substep (`δv`, [`ContactPrediction`]) that the solve takes as recurring on a *rotation*
/// the substep does not resolve (a blocked rotation, a servo beyond the substep,
/// [`prepare::predict_contacts`]): its impulse pre-applies `ρ` of what cancels `J·δv`,
/// whatever its `G`. Only the change of the bodies the contacts hold against gravity
/// ([`held_axes`]: a foot standing on the ground): a hand whose rapier fingers carry a box
/// took its share of the fingers' change, and the box slipped out of the grip
/// (`tests/gripper.rs`). And of a held body's change only as much as its island's weight
/// explains (the gate, below).
///
/// The hold ([`held_axes`]) is linear, and a rotation the substep does not resolve took
/// none of the contact's change: the solve saw a flat foot free to turn, so a joint's
/// impulse turned the light foot rather than the body it carries, the contact took the
/// foot's turn back, and the joint carried the contact's moment only through the foot's
/// own inertia: a rotational stiffness of about `β·I_foot/h²` whatever `Kn` or `k_p`, in
/// series with the ankle's servo. A standing humanoid's tipping stiffness `m·g·L` is above
/// that of its two feet at 4 substeps: example-robot-data's Talos (90 kg, `k_p` 3000
/// N·m/rad, 1.6 kg box feet), standing in the half-sitting pose, opened its ankle rolls'
/// blocked pitch by 128 mrad at 1 s (about 210 N·m/rad each for its 26 N·m) and fell
/// forward by 2 s, with `Kn` = 1e10 alike; at 8 substeps (`h²` a quarter) it stood, its
/// ankles 20 mrad open. With `ρ` the opening the contact leaves is about `(1 − ρ)` of it.
/// Not all of it: the contact's change is one substep late, and where the contact
/// answers the joint's own impulse (a block on a light box foot, rocking on its corners)
/// the joint and the contact then pass it back and forth, by `ρ` a substep: `ρ` = 1 rang
/// the block at 0.19 m/s, 0.9 at 6.7 mm/s and 0.85 at 16 substeps at 16 mm/s (under
/// 3e-5 m/s without); 3/4 leaves it as it was (5e-6 m/s). Talos at 4 substeps falls with
/// 0.5 and 2/3, stands with 3/4 (base within 3.4 cm over 6 s, ankles 30 mrad at the start,
/// joints within 20 mrad of their targets after 0.5 s). The linear axes keep the hold
/// alone: there the same prediction made the block on the foot come apart.
/// (Measured 2026-12-06, a humanoid-robotics trial.)
///
/// The gate (2026-12-06): the contact's linear impulse on the held body over the last
/// substep, `P = m·|δv_lin|`, is compared with the weight of the body's island (the bodies
/// the set's joints join to it) over the substep, `W = M·|g|·h`
/// ([`SubstepData::island_weight`]), and where `P > W` the body's change is taken in the
/// ratio `W/P`. In statics a robot's contacts carry its weight between them, so a standing
/// foot's impulse is at most `W` (Talos's two feet 0.58 and 0.42 of it: the share whole);
/// an impulse beyond the weight is a strike (a landing, a foot slapping the ground, a
/// fall), over in a substep or a few, which the share, one substep late, struck into the
/// joint again: the gymnasium walker2d at 4 substeps, collapsing, struck its capsule feet
/// at 1.2 to 8 times its weight a substep where its torso landed (1.05 s), and its feet's
/// hinges, on their stops, took the strikes as recurring (a foot's change 3, 9, 17, 24, 28
/// rad/s in successive substeps under the two-substep gate below, the share feeding the
/// contact's change back), a foot's joint 10.6 mm open ungated where 7.34 mm without the
/// share. Gated: 7.41 mm; walker2d_v5 on a floating base at 8 substeps 3.62 mm (22.2
/// ungated, 3.62 without), the hopper at 4 4.76 mm (4.90, 4.57), the floating humanoid 7.59
/// mm (8.16, 6.38), Talos at 4 substeps as ungated (base 11.3 mm down and 49 mm aside over
/// 4 s, its ankle rolls 8.41 mm and 30.2 mrad, servos within 19.8 mrad), at 8 1.45 mm and
/// 5.3 mrad, at 16 0.35 mm and 0.8 mrad. The weight itself is the bound, not a tuning:
/// taking `W/2` left Talos leaning 67 mm and 45.6 mrad (its feet's impulses are about `W/2`
/// each), `2·W` and `4·W` kept walker2d within 6.4 mm and walker2d_v5 within 8.6 mm (4
/// substeps). Tried before it, and worse: the smaller of the last two substeps' changes
/// where they agree in sign (walker2d 10.1 mm at its torso's landing), held for two
/// substeps running (14.0 mm), the part that took back the joints' own angular change (10.6
/// mm), a change opposing the joints' (13.4 mm; walker2d_v5 22.2). Left: the collapsed
/// walker's capsule feet, carrying less than its weight, still rock on their stops at about
/// ±1.5 rad/s from 1.3 to 3.5 s (gaps of 3 to 5 mm; ±4–6 rad/s and 4 to 10.6 mm ungated,
/// quiet without the share), a light rotation under a point contact that the share takes as
/// held. The weight is the island's, not what rests on the body through contacts: a robot
/// carrying a box on its arms gets a share cut by the box's part of its feet's impulses.
///
/// The anchor (2026-12-07): the share's impulse is a couple, and on the held side it
/// turns the body in the solve against the contact's own turn, about the body's centre of
/// mass. The joint's anchor on that body moves with the turn (`−a_s × δω`, the ankle
/// some centimetres above the foot's centre of mass), the unresolved translations took
/// that as the joint opening and pulled the carried side along, and then the contact took
/// the turn back, the anchor with it, leaving the carried side pulled: the share opened the
/// blocked translations. As the load came onto Talos's feet (the first 0.05 s) the contact
/// took back 13 rad/s a substep off a foot where it took 6.8 without the share (in double
/// precision, 8 substeps), and the ankle roll's anchors parted 2.28 mm along the foot where
/// 1.04 without it: 2.65 mm in all, 1.69 without the share. The turn the contact will take
/// back, `I⁻¹·(J_sᵀ·λ)_ω` for the share's impulse `λ` (the body's mean inertia), is now
/// taken as recurring on the unresolved translations as the contact's change is on the
/// resolved DOFs ([`prepare::predict_contacts`]), so they no longer answer it. Measured
/// (f32 / f64): Talos at 8 substeps 0.92 / 1.68 mm (1.45 / 2.65 before) and 5.9 / 10.5 mrad,
/// at 4 4.26 / 4.92 mm (8.41 / 8.53), 25.1 / 29.0 mrad and drifting 35.8 / 37.0 mm (49.0 /
/// 50.1: the ankles' blocked pitch, less open, lets the body lean less), at 16 0.24 / 0.42
/// mm; walker2d at 4 substeps 5.83 / 5.74 mm (7.41 / 6.16), walker2d_v5 at 4 6.74 / 8.50 mm
/// (5.86 / 9.61), floating at 8 3.62 / 3.10 mm (3.62 / 3.59), the hopper 4.65 / 4.89 mm
/// (4.76 / 4.88), the floating humanoid 8.11 / 6.55 mm (7.59 / 6.86). Taken the other way
/// (the anchor's motion added rather than taken back) Talos at 8 opened 3.46 mm and at 4
/// leaned 67.7 mm: the gap was the share's.
pub(crate) const CONTACT_ROTATION_SHARE: f64 = 0.75;

/// The world axes along which rapier's contacts held a body against gravity over the last
/// substep: its velocity change beyond the solve's prediction `δv` ([`contact_change`])
/// opposes gravity along the axis by more than a quarter of gravity's own change `|g_a|·h`,
/// and lies mostly along it (`δv_a² ≥ |δv_lin|²/2`: a body rammed sideways, whose `δv`
/// has a small upward part, is not held; bit `a` set for axis `a`).
///
/// rapier solves its contacts after the joints, so the solve sees a foot on the ground
/// free to fall with gravity and with the joint's impulse, and the body the joint carries
/// falls towards it until the next substep: a blocked DOF opened by `F·h²/m` a substep (the
/// load over the foot's mass; a Unitree A1 standing under PD control, 3.7 mm at its knees
/// at 4 substeps). Taking `δv` as recurring on those DOFs, as on the resolved ones
/// ([`prepare::predict_contacts`]), is one substep late on a contact that answers the
/// joint's own impulse: the stiff DOF and the contact rang (a block on a light foot
/// hopped off the ground). Along a held axis the contact will cancel whatever the joints
/// and gravity give the body, so the solve takes the body nearer to how it will end: its
/// velocity change from gravity and user forces along the axis taken out of `Δv_ext` and
/// its mass [`HELD_MASS`] times larger (`W_a → W_a/HELD_MASS`), so that the joint's impulse
/// moves the body it carries more and the foot less, and more of the contact's load
/// reaches the joint in the same substep. The apply stage gives the held body its real
/// share of the impulse (`u_a·HELD_MASS`), which the contact cancels as before; where the
/// solve's impulses would lift the body off its contact, the axis is released and the
/// substep solved again ([`release_lifted`]), and a foot that leaves the ground has no `δv`
/// along the axis at the next substep. The resolved DOFs take the part of the body's motion
/// in the solve that the contact will cancel as recurring ([`prepare::predict_contacts`]).
/// The gather stage finds the axes; the solve stage alone takes the bodies as heavier:
/// the prepare stage sizes the joints' numerical damping, stored energies and predictions
/// on the real masses (the blocked DOFs' `ω·h ≥ 2` of the stiffness rule holds), and an
/// axis a non-finite force acts along is not held (the solve's failure names the force).
/// Left as they are: one release pass (a body only the second solve lifts stays held for
/// that substep), and a support taken as rigid (a body resting on a lighter free body is
/// held as on the ground; a pile of bodies ends on the ground or falls, where `δv` no
/// longer opposes gravity: the 30 kg block on a 1 kg foot resting on a loose plate of
/// 0.01, 0.1, 1 or 10 kg on the ground rests as on the ground itself, 2.02–2.04 mm). Measured at 4 substeps (2026-12-06): the A1 standing under PD
/// 3.7 → 1.01 mm, go1 4.2 → 1.24 mm (re-measured with the fused feet where the URDF puts them), a car's axles carrying its chassis on 1 kg wheels
/// 86 → 24 mm, a 30 kg block on a 1 kg foot dropped 1 m onto the ground 106 → 46 mm,
/// rebounding 0.50 → 0.31 m. Only
/// the linear axes, at the body's centre of mass: a contact's hold on the body's rotation
/// (a flat foot's tilt, the friction that twists a light calf) keeps the lag. (Holding the
/// rotation about the centre of mass as well, where the contact took back the angular
/// change, was tried and was worse: a point contact lets the body pivot about the contact
/// point; README, "Known limits".)
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn held_axes(dv: &Vector6<f64>, g: &Vector3<f64>, h: f64) -> u8 {
    let mut mask = 0;
    let lin = dv.fixed_rows::<3>(0).norm_squared();
    for a in 0..3 {
        let along = dv[a] * dv[a] >= 0.5 * lin;
        if along && dv[a] * g[a] < 0.0 && dv[a].abs() > 0.25 * g[a].abs() * h {
            mask |= 1 << a;
        }
    }
    mask
}

/// Frees the held axes ([`held_axes`]) along which the solve's impulses would move the body
/// away from its contact: its velocity at the substep's end with its real share of the
/// impulses (`u_a·HELD_MASS`) and gravity's change, `v_a + u_a·HELD_MASS + Δv_plain,a`,
/// points the way the contact pushed (the sign of `δv_a`), so the contact would not act and
/// the solve's hold was wrong. The body's mass, inverse mass and external velocity change
/// are restored along those axes; whether any was freed (the caller solves their islands
/// again), the bodies freed in [`SubstepData::released`].
fn release_lifted(data: &mut SubstepData) -> bool {
    data.released.clear();
    let bodies = (data.bodies.iter_mut()).zip(data.held.iter_mut());
    let bodies = bodies.zip(data.gathered.iter().zip(&data.dv_contact));
    for (slot, (((sb, held), (g, dvc)), u)) in bodies.zip(&data.velocity).enumerate() {
        if *held == 0 {
            continue;
        }
        let v = [g.pose.linvel.x, g.pose.linvel.y, g.pose.linvel.z];
        let mut freed = false;
        for a in 0..3 {
            let bit = 1 << a;
            if *held & bit != 0 && (v[a] + u[a] * HELD_MASS + g.dv_plain[a]) * dvc[a] > 0.0 {
                sb.release(a, HELD_MASS, g.dv_plain[a]);
                *held &= !bit;
                freed = true;
            }
        }
        if freed {
            data.released.push(slot as u32);
        }
    }
    !data.released.is_empty()
}

/// The contact prediction's per-body state ([`ContactPrediction`]) of the tiles before an
/// analysis, by body, for the tiles after it: an analysis (a joint inserted or removed
/// anywhere, an island falling asleep or waking) left every body without it for a substep,
/// and the robots standing on the ground in one world moved differently when a joint was
/// inserted 28 m away (a calf by 6 mrad in that frame; a user trial, 2026-12-04).
pub(crate) struct CarriedPrediction {
    /// What the tiles held, where they all held the same; else [`ContactPrediction::None`].
    mode: ContactPrediction,
    /// Per body: `v_pred`, `pred_scale`, `dv_contact`.
    bodies: std::collections::HashMap<RigidBodyHandle, BodyPrediction>,
}

/// A body's `v_pred`, `pred_scale` and `dv_contact` ([`SubstepData`]).
type BodyPrediction = (Vector6<f64>, [f64; 2], Vector6<f64>);

impl CarriedPrediction {
    /// What `tiles` hold (the set's data before an analysis).
    pub(crate) fn take<'a>(tiles: impl Iterator<Item = &'a SubstepData>) -> Self {
        let mut mode = None;
        let mut bodies = std::collections::HashMap::new();
        for d in tiles.filter(|d| !d.handles.is_empty()) {
            mode = match mode {
                None => Some(d.contact_pred),
                Some(m) if m == d.contact_pred => Some(m),
                Some(_) => Some(ContactPrediction::None),
            };
            if d.contact_pred == ContactPrediction::None {
                continue;
            }
            for (slot, hb) in d.handles.iter().enumerate() {
                bodies.insert(
                    *hb,
                    (d.v_pred[slot], d.pred_scale[slot], d.dv_contact[slot]),
                );
            }
        }
        CarriedPrediction {
            mode: mode.unwrap_or(ContactPrediction::None),
            bodies,
        }
    }

    /// Puts it into a freshly analysed tile: each body's own where it had one; a body new to
    /// the stages predicts nothing (measured against its present velocity, or no `δv`).
    pub(crate) fn restore(&self, data: &mut SubstepData, bodies: &RigidBodySet) {
        if self.mode == ContactPrediction::None {
            return;
        }
        for (slot, hb) in data.handles.iter().enumerate() {
            if let Some((vp, scale, dv)) = self.bodies.get(hb) {
                (data.v_pred[slot], data.pred_scale[slot]) = (*vp, *scale);
                data.dv_contact[slot] = *dv;
            } else if let Some(b) = bodies.get(*hb) {
                let (v, w) = (b.linvel(), b.angvel());
                let v = Vector6::new(
                    v.x as f64, v.y as f64, v.z as f64, w.x as f64, w.y as f64, w.z as f64,
                );
                data.v_pred[slot] = v;
                data.pred_scale[slot] = [
                    v.fixed_rows::<3>(0).norm_squared(),
                    v.fixed_rows::<3>(3).norm_squared(),
                ];
            }
        }
        data.contact_pred = self.mode;
    }
}

impl Clone for SubstepData {
    /// The whole state, so that a clone steps on with the same bits as the original (a
    /// snapshot restored: `tests/snapshot.rs`): what a substep carries to the next (the
    /// contact prediction, the energy book's pending end-rate correction, the stored
    /// results, the islands' rest) as well as the arrays of the analysis. The solver's
    /// workspace is built again from the topology (`Solver::new`, a pure function of it):
    /// its numbers are written afresh by every substep's solve.
    fn clone(&self) -> Self {
        let solver = self.rebuilt_solver();
        SubstepData {
            solver,
            valid: self.valid,
            handles: self.handles.clone(),
            body_addr: self.body_addr.clone(),
            gyro_on: self.gyro_on.clone(),
            sides: self.sides.clone(),
            alone: self.alone.clone(),
            watched: self.watched.clone(),
            watched_pose: self.watched_pose.clone(),
            watched_kinematic: self.watched_kinematic.clone(),
            watched_of: self.watched_of.clone(),
            shares_solver: self.shares_solver,
            bodies: self.bodies.clone(),
            mass_cache: self.mass_cache.clone(),
            gathered: self.gathered.clone(),
            geo: self.geo.clone(),
            joints: self.joints.clone(),
            prepared: self.prepared.clone(),
            stored: self.stored.clone(),
            driven_before: self.driven_before.clone(),
            breakable: self.breakable.clone(),
            unfolded: self.unfolded,
            motion: self.motion.clone(),
            rotation: self.rotation.clone(),
            impulses: self.impulses.clone(),
            velocity: self.velocity.clone(),
            fresh: self.fresh,
            islands: self.islands.clone(),
            book_pending: self.book_pending,
            v_pred: self.v_pred.clone(),
            dv_contact: self.dv_contact.clone(),
            held: self.held.clone(),
            island_weight: self.island_weight.clone(),
            released: self.released.clone(),
            pred_scale: self.pred_scale.clone(),
            contact_pred: self.contact_pred,
            any_contact: self.any_contact,
            any_held: self.any_held,
            touchable: self.touchable,
            colliders: self.colliders,
        }
    }
}

impl SubstepData {
    /// The solver's workspace of this topology (`Solver::new`, a pure function of it).
    fn topology_solver(&self) -> Solver {
        Solver::new(
            self.handles.len(),
            &self.sides,
            &vec![true; self.sides.len()],
        )
    }

    /// The solver's workspace as the analysis left it, built again for a copy of the data:
    /// empty for a tile that borrows the first tile's or for data no analysis filled.
    fn rebuilt_solver(&self) -> Solver {
        if self.valid && !self.shares_solver {
            self.topology_solver()
        } else {
            Solver::default()
        }
    }
}

/// A tile's data read back by serde, its solver's workspace (not saved) built again from
/// the topology, as a clone builds it.
#[cfg(feature = "serde-serialize")]
pub(super) fn restored_tile<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<SubstepData, D::Error> {
    let mut data = <SubstepData as serde::Deserialize>::deserialize(d)?;
    data.solver = data.rebuilt_solver();
    data.held = vec![0; data.handles.len()];
    Ok(data)
}

/// [`restored_tile`] for the set's other tiles.
#[cfg(feature = "serde-serialize")]
pub(super) fn restored_tiles<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Vec<SubstepData>, D::Error> {
    let mut tiles = <Vec<SubstepData> as serde::Deserialize>::deserialize(d)?;
    for data in &mut tiles {
        data.solver = data.rebuilt_solver();
        data.held = vec![0; data.handles.len()];
    }
    Ok(tiles)
}

/// A joint's motion before its first measurement (overwritten by stage 4a).
pub(super) fn motion_at_rest() -> kinematics::JointMotion {
    kinematics::JointMotion {
        force_point: Vector3::zeros(),
        q: [0.0; 6],
        rate: [0.0; 6],
    }
}

pub(super) fn rotation_at_rest() -> kinematics::Measured {
    let e = nalgebra::UnitQuaternion::identity();
    (Vector3::zeros(), e, e.to_rotation_matrix(), None)
}

/// Asks the cache for the rapier body of solver slot `slot`, if there is one, at the
/// address the gather stage last read it from ([`SubstepData::body_addr`]; an address gone
/// stale since, when rapier's arena grew, only makes the hint useless: [`prefetch`]).
#[cfg_attr(not(debug_assertions), inline(always))]
fn prefetch_body(addr: &[usize], slot: usize) {
    if let Some(&a) = addr.get(slot) {
        prefetch::value(a as *const RigidBody);
    }
}

/// How many bodies ahead the short loops over rapier's bodies (the poses of the gather
/// stage, the apply stage: ~10 ns a body) ask for one: enough to cover a read from memory
/// (~100 ns) at 10 000 bodies. At 4 the apply stage of 10 000 pendulums took 270 µs a
/// substep, at 16 150–190 µs (130–330 µs without hints). The gather's pose loop at 32 was
/// about 1 % slower at the 10 000-link chain (two runs of 10 alternating rounds).
const BODY_AHEAD_SHORT: usize = 16;

/// The same for the apply stage, which reads and writes each body (its velocity, its
/// change flags, rapier's list of the bodies written): at 32 rather than
/// [`BODY_AHEAD_SHORT`] the 10 000-link chain's frame was 1.2 % shorter (medians of 10, 10
/// and 16 alternating rounds: 0.979, 0.992, 0.988) and 10 000 pendulums' 1.0 %; at 64 the
/// chain 1 % slower than at 32 (2026-12-07; an hour later, in another state of the
/// machine, 1.006 against the binary before, within that run's ±3 %). Below
/// [`prefetch::worth`] (1000 bodies) no hint is asked for.
const BODY_AHEAD_APPLY: usize = 32;

/// The same for the gather stage's loop over the bodies' mass properties (~30 ns a body).
const BODY_AHEAD: usize = 8;

/// The joints the prepare stage's two loops (measure, prepare) take at a time (stage 4):
/// about 3 KB a joint of records, rotations, motions, solver blocks and bodies, 0.4 MB a
/// run, within a second-level cache of 1 MB. On a 2 MB one (Intel Xeon VM, 2026-12-07,
/// alternated medians of the 10 000-link chain's frame) 128 was 0.99 of 256 and 64 0.98
/// of 128, within the spread; the tree of 4095 and the contact scene alike.
const PREPARE_RUN: usize = 128;

/// Run `k` of `count` bodies or joints taken `size` at a time (the stages' runs:
/// [`PREPARE_RUN`], [`GATHER_RUN`]); empty past the last.
fn run_of(k: usize, size: usize, count: usize) -> std::ops::Range<usize> {
    (k * size).min(count)..((k + 1) * size).min(count)
}

/// The bodies the gather stage's three loops take at a time (stage 2): about 1.5 KB a body
/// between rapier's record and the set's, 192 KB a run (chosen with [`PREPARE_RUN`]).
const GATHER_RUN: usize = 128;

/// How many joints ahead the measure stage's rotation loop starts asking for the joint
/// records (each once, up to four joints further: one pass of four hinges). At 2 the first
/// read of a record, the check of its frames' measure, still waited on memory at 10 000
/// joints (1.1 % of the chain's frame in a profile, 0.06 % at 1000); at 8 the 10 000-link
/// chain and pendulums were 0.4–2.3 % and 1.7–2.5 % faster in two measures of 6 to 10
/// alternating rounds, 1000 links the same; at 12 the chain 2.1 % slower than at 8.
const MEASURE_AHEAD: usize = 8;

/// How many joints ahead the store stage asks for the substep's data it reads (~25 ns a
/// joint at 10 000 pendulums without hints, from memory: 0.95 ms of a 25 ms frame; 0.7 ms
/// with them).
const STORE_AHEAD: usize = 8;

/// How many joints ahead [`KjointSet::fold_stored_results`] asks for the lines it writes in
/// the records (~30 ns a joint at 10 000 joints without hints; 1000 joints: 6 ns).
const FOLD_AHEAD: usize = 8;

/// `(offset, length)` in a [`Kjoint`] of what [`prepare::fold_stored`] writes: the law's
/// energies, the booked law energy, the transmitted force, the readout's transmitted
/// force and energies (inside an `Option`, which has no stable field offsets: measured on
/// one) and the readout's tag.
fn fold_offsets() -> [(usize, usize); 6] {
    use std::mem::{offset_of, size_of, size_of_val};
    let readout = Some(JointState::empty());
    let s = readout.as_ref().expect("built as Some");
    // (offset, length) of a field of the readout, in the record
    let in_record = |field: *const u8, len: usize| {
        let offset = field as usize - &readout as *const _ as usize;
        (offset_of!(Kjoint, state) + offset, len)
    };
    [
        (
            offset_of!(Kjoint, law.energy),
            size_of::<law::JointEnergy>(),
        ),
        (offset_of!(Kjoint, booked_law), size_of::<f64>()),
        (offset_of!(Kjoint, last_applied), size_of::<[f64; 6]>()),
        in_record(&s.applied as *const _ as *const u8, size_of_val(&s.applied)),
        in_record(&s.energy as *const _ as *const u8, size_of_val(&s.energy)),
        // the readout's `Some` or `None`, read before it is written: at the 10 000-link
        // chain's readout substeps its line was a quarter of the store stage's samples,
        // waiting for memory (`perf annotate`, 2026-12-05)
        (offset_of!(Kjoint, state), 1),
    ]
}

/// Asks the cache for what [`prepare::fold_stored`] writes in the record at `record`
/// ([`fold_offsets`]).
#[cfg_attr(not(debug_assertions), inline(always))]
fn prefetch_folded(record: *const Kjoint, offsets: [(usize, usize); 6]) {
    for (offset, len) in offsets {
        prefetch::field(record, offset, len);
    }
}

/// The work of the last substep's impulse `P`, booked with the rates the solve predicted
/// for its end, corrected to the rates the bodies actually ended with (the velocities
/// gathered for this substep), with the same Jacobians: `P·(q̇⁺ − q̇⁺_predicted)/2` more work
/// on the bodies, taken from the joint's numerical energy (kept in the substep's data, booked
/// on the joint by [`prepare::fold_stored`]). With `g_s = J_sᵀ·P` from the store stage,
/// `P·(q̇⁺ − q̇_driven) = Σ_s g_s·v⁺_s`, against [`PreparedJoint::end_power`]. Without other
/// forces the two agree up to f32 round-off; rapier's contacts and joints on a jointed body
/// (a gripper's fingers on its hand) act after the joint solve, and without this the joint
/// would book, every substep, the work of an impulse along a motion the bodies did not make
/// (a hand held still by a wrist drifted by −0.05 J a second). The work of rapier's contacts
/// and joints themselves is rapier's, booked by no joint.
#[cfg_attr(not(debug_assertions), inline(always))]
fn end_rate_correction(
    prep: &PreparedJoint,
    sides: &[Option<u32>; 2],
    gathered: &[GatheredBody],
) -> f64 {
    let mut actual = 0.0;
    for (g, slot) in prep.side_impulse.iter().zip(sides) {
        if let Some(bi) = slot {
            let pose = &gathered[*bi as usize].pose;
            let (v, w) = (pose.linvel, pose.angvel);
            actual += g.fixed_rows::<3>(0).dot(&v) + g.fixed_rows::<3>(3).dot(&w);
        }
    }
    0.5 * (actual - prep.end_power)
}

/// Reads the pose of every watched body of a tile over the substep `h` (stage 1,
/// [`watched_pose`]): `false` when one is gone or has become dynamic.
fn watched_unchanged(data: &mut SubstepData, bodies: &RigidBodySet, h: f64) -> bool {
    let watched = data.watched.iter().zip(&data.watched_kinematic);
    for ((hb, kinematic), pose) in watched.zip(&mut data.watched_pose) {
        // (a switch between fixed and kinematic changes whether the island may sleep)
        // (a disabled one leaves its joints: [`KjointSet::sort_out_disabled`])
        let same = |b: &&RigidBody| {
            !is_awake_dynamic(b) && b.is_kinematic() == *kinematic && b.is_enabled()
        };
        match bodies.get(*hb).filter(same) {
            Some(b) => *pose = watched_pose(b, h),
            None => return false,
        }
    }
    true
}

/// Whether every dynamic body of a tile still is (what the gather stage checks as it
/// reads them; a tiled set checks it before any tile is stepped).
fn dynamic_unchanged(data: &SubstepData, bodies: &RigidBodySet) -> bool {
    (data.handles.iter()).all(|hb| bodies.get(*hb).is_some_and(is_dynamic))
}

pub(super) fn is_dynamic(b: &RigidBody) -> bool {
    b.is_dynamic() && b.is_enabled()
}

/// For each stage given, `$run(avx2, …)`, which runs one of its two compilations
/// ([`isa`]): `$avx2`, with AVX2 enabled, where `avx2` says the processor has it, else
/// `$baseline`, for the target the crate is built for. Each is one function of its own,
/// into which the stage and the hot functions it calls are inlined (`#[inline(always)]` in
/// release builds): one function a stage rather than the whole substep in one keeps each
/// small enough for the optimiser's passes, whose time grows faster than a function's size.
macro_rules! compiled_twice {
    ($(
        $(#[$doc:meta])*
        fn $run:ident: $baseline:ident / $avx2:ident = $stage:ident($($arg:ident: $ty:ty),*)
            -> $ret:ty;
    )*) => {$(
        $(#[$doc])*
        /// `avx2`: the processor has AVX2 ([`isa::avx2`]).
        #[inline]
        fn $run(&mut self, avx2: bool, $($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            if avx2 {
                // SAFETY: `avx2` only where the processor has AVX2 (detected at run time)
                return unsafe { self.$avx2($($arg),*) };
            }
            let _ = avx2;
            self.$baseline($($arg),*)
        }

        $(#[$doc])*
        #[inline(never)]
        fn $baseline(&mut self, $($arg: $ty),*) -> $ret {
            self.$stage($($arg),*)
        }

        $(#[$doc])*
        /// Compiled with AVX2.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        #[inline(never)]
        unsafe fn $avx2(&mut self, $($arg: $ty),*) -> $ret {
            self.$stage($($arg),*)
        }
    )*};
}

/// The relative change of the substep length `h` beyond which every joint's blocked
/// stiffness is resolved again at the next substep (the automatic rules scale as `1/h²`):
/// a frame rate's jitter within it keeps them, within ±10 % of the rule's at the substep
/// stepped (a resolution is O(joints): 0.3 ms on a 1000-link chain).
pub const RESOLVE_TOLERANCE: f64 = 0.05;

impl KjointSet {
    /// The force generator of one substep of length `h`: updates the sensors, evaluates
    /// every joint on the current poses and velocities, solves the implicit update and
    /// applies the impulses to the bodies. The caller then advances rapier by `h` (with
    /// `integration_parameters.dt = h`), adds `h` to the time with [`Self::advance_time`]
    /// and checks what rapier's step quarantined with [`Self::check_quarantine`]. A joint
    /// that no longer holds ([`super::OnUnstable::Stop`]) gives [`SimError::Unstable`] with
    /// the substep's impulses applied, as at any substep: advance rapier on it all the
    /// same for the world to stay as the impulses left it. Where a
    /// joint's contacts are off ([`Self::set_contacts_enabled`]), it calls
    /// [`Self::update_contact_filters`] before rapier's step too (this does not see the
    /// world's joints).
    pub fn apply_substep(
        &mut self,
        bodies: &mut RigidBodySet,
        gravity: Vector,
        h: f64,
    ) -> Result<(), SimError> {
        // (the world's rapier joints are not seen here: taken as possible)
        self.rapier_constraints = true;
        let result = self.substep(bodies, gravity, h, Readouts::All);
        self.fold_stored_results();
        result?;
        self.take_unstable()
    }

    /// [`Self::apply_substep`] leaving the store stage's results in the substep's data
    /// ([`StoredJoint`]): the next substep writes them into the records while it prepares
    /// the joints. Whoever calls this calls [`Self::fold_stored_results`] before anything
    /// reads a joint's readout or energies, or changes the set. `readouts`: which joints'
    /// readouts the substep writes.
    pub(crate) fn substep(
        &mut self,
        bodies: &mut RigidBodySet,
        gravity: Vector,
        h: f64,
        readouts: Readouts,
    ) -> Result<(), SimError> {
        #[cfg(target_arch = "x86_64")]
        let avx2 = isa::avx2() && !self.baseline_only();
        #[cfg(not(target_arch = "x86_64"))]
        let avx2 = false;
        self.substep_stages(bodies, gravity, h, readouts, avx2)
    }

    /// Whether a test asked for the baseline compilation ([`KjointSet::baseline_only`]);
    /// never outside the tests.
    #[cfg(target_arch = "x86_64")]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn baseline_only(&self) -> bool {
        #[cfg(test)]
        return self.baseline_only;
        #[cfg(not(test))]
        false
    }

    /// The stages of [`Self::substep`], the hot ones each through its baseline or its AVX2
    /// compilation (`avx2`; module [`isa`]).
    fn substep_stages(
        &mut self,
        bodies: &mut RigidBodySet,
        gravity: Vector,
        h: f64,
        readouts: Readouts,
        avx2: bool,
    ) -> Result<(), SimError> {
        super::joint_set::check_substep(h)?;
        super::joint_set::check_gravity(gravity)?;
        // (a contact change measured over a substep of another length is rescaled to this
        // one: [`ContactPrediction`])
        self.contact_rescale = if self.last_h > 0.0 && self.last_h != h {
            h / self.last_h
        } else {
            1.0
        };
        self.stage_topology(bodies, h);
        // stages 2 to 7 over each tile in turn ([`super::tiles`]; once in a set of one tile),
        // each stage called in one place only: its compilations inline it whole, where a
        // second call made it outline small helpers (`Iterator::reduce`, nalgebra's
        // `from_iterator`: 1 % more instructions in the contact scene). A tiled
        // set resolves the blocked stiffness and updates the sensors for all its joints
        // first (its topology stage has checked every dynamic body); a set of one tile after
        // its gather stage, which analyses the topology again when a body changed.
        let mut one_tile = self.tiles.is_empty();
        let mut analysed = false;
        // (and a set whose joints are all asleep, which has no tile: its sensors still fire)
        if !one_tile || self.tile_joints.is_empty() {
            self.stage_stiffness_and_sensors(bodies, h)?;
            if self.massless_found {
                // a joint of automatic stiffness on a body that lost its mass (stage 3 left
                // it unresolved): analyse again, which turns it off
                one_tile = self.analyse_again(bodies, h)?;
                analysed = true;
            }
        }
        let mut broken = Vec::new();
        let mut failure = Ok(());
        let mut k = 0;
        while k < self.tile_joints.len() {
            self.enter_tile(k, true);
            let stored = match self.run_gather_bodies(avx2, bodies, gravity, h) {
                Gather::Done if one_tile => match self.stage_stiffness_and_sensors(bodies, h) {
                    Ok(()) if self.massless_found && !analysed => {
                        // as above: analyse again, then gather
                        self.leave_tile(k, true);
                        one_tile = self.analyse_again(bodies, h)?;
                        analysed = true;
                        continue;
                    }
                    Ok(()) => self.stages_after_gather(bodies, h, readouts, &mut broken, avx2),
                    Err(e) => Err(e),
                },
                Gather::Done => self.stages_after_gather(bodies, h, readouts, &mut broken, avx2),
                Gather::NonFinite(slot) => Err(self.non_finite_body(slot, bodies)),
                Gather::TopologyChanged if one_tile && !analysed => {
                    // a dynamic body was removed or switched: analyse again, then gather
                    self.leave_tile(k, true);
                    one_tile = self.analyse_again(bodies, h)?;
                    analysed = true;
                    continue;
                }
                Gather::TopologyChanged => {
                    // (a fresh analysis, or the topology stage of a tiled set, checked every
                    // body)
                    self.data.valid = false;
                    Err(SimError::Unstable {
                        time: self.time,
                        reason: "a jointed body changed during the substep".into(),
                    })
                }
            };
            self.leave_tile(k, true);
            // an error of the stages ends the substep at once (the tiles before are applied);
            // the first failed health check is returned once every tile is stored, as the
            // store stage returns it once every joint is
            let stored = stored?;
            if failure.is_ok() {
                failure = stored;
            }
            k += 1;
        }
        self.remove_broken_joints(broken);
        // (after the tiles were gathered, each rescaling its prediction to `h` once)
        self.last_h = h;
        // (returned by the caller once the substep is complete)
        self.unstable = failure.err();
        Ok(())
    }

    /// Stage 1 again within a substep (a dynamic body removed or switched, a joint of
    /// automatic stiffness on a body that lost its mass), with stage 3 where the set is
    /// tiled now (a set of one tile runs it after its gather stage): whether it is one tile.
    fn analyse_again(&mut self, bodies: &mut RigidBodySet, h: f64) -> Result<bool, SimError> {
        self.data.valid = false;
        self.stage_topology(bodies, h);
        let one_tile = self.tiles.is_empty();
        if !one_tile {
            self.stage_stiffness_and_sensors(bodies, h)?;
        }
        Ok(one_tile)
    }

    /// Stages 4 to 7 of the gathered joints and bodies in [`Self::data`]: an error of the
    /// stages (`Err`), else the store stage's result (the first failed health check); the
    /// joints that broke are pushed on `broken`, for their removal after the substep.
    fn stages_after_gather(
        &mut self,
        bodies: &mut RigidBodySet,
        h: f64,
        readouts: Readouts,
        broken: &mut Vec<(KjointHandle, law::BreakCause)>,
        avx2: bool,
    ) -> Result<Result<(), SimError>, SimError> {
        self.run_prepare_joints(avx2, h, readouts)?;
        if let Err(e) = self.run_solve(avx2, h) {
            // a NaN or an infinity the user put in a body's force or torque (rapier's
            // `add_force`) made the impulses non-finite: the body is named, not a joint
            return Err(self.non_finite_user_force(bodies).unwrap_or(e));
        }
        Ok(self.run_apply_and_store(avx2, bodies, h, readouts, broken))
    }

    /// Stages 6 and 7 over a run of [`GATHER_RUN`] bodies and one of [`PREPARE_RUN`] joints
    /// at a time, first to last: the store stage finds the run's velocity changes where the
    /// apply stage left them, in the cache. The store stage's result (the first failed
    /// health check, once every joint is stored).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn stage_apply_and_store(
        &mut self,
        bodies: &mut RigidBodySet,
        h: f64,
        readouts: Readouts,
        broken: &mut Vec<(KjointHandle, law::BreakCause)>,
    ) -> Result<(), SimError> {
        let (nb, nj) = (self.data.handles.len(), self.active.len());
        let mut failure = Ok(());
        self.data.book_pending = true;
        // at a substep whose readouts are read (a step's last, every one of `step_with`),
        // the results go into the records here, where [`Self::fold_stored_results`] would
        // write them after rapier's step: the same values (nothing in between reads or
        // changes them), and in a tiled set the records of the tile are still in the cache
        // from its prepare stage, where the fold's own pass brought them from memory
        // (10 000 pendulums: 2 lines a joint-substep)
        self.data.unfolded = readouts != Readouts::All;
        for k in 0..nb.div_ceil(GATHER_RUN).max(nj.div_ceil(PREPARE_RUN)) {
            self.stage_apply_impulses(bodies, run_of(k, GATHER_RUN, nb));
            let stored = self.stage_store_results(h, readouts, broken, run_of(k, PREPARE_RUN, nj));
            if failure.is_ok() {
                failure = stored;
            }
        }
        let data = &mut self.data;
        data.contact_pred = if data.touchable {
            ContactPrediction::Measure
        } else {
            ContactPrediction::None
        };
        failure
    }

    compiled_twice! {
        /// Stage 2 ([`Self::stage_gather_bodies`]).
        fn run_gather_bodies: gather_bodies_baseline / gather_bodies_avx2 = stage_gather_bodies(
            bodies: &RigidBodySet, gravity: Vector, h: f64) -> Gather;
        /// Stage 4 ([`Self::stage_prepare_joints`]).
        fn run_prepare_joints: prepare_joints_baseline / prepare_joints_avx2 = stage_prepare_joints(
            h: f64, readouts: Readouts) -> Result<(), SimError>;
        /// Stage 5 ([`Self::stage_solve`]).
        fn run_solve: solve_baseline / solve_avx2 = stage_solve(h: f64) -> Result<(), SimError>;
        /// Stages 6 and 7 ([`Self::stage_apply_and_store`]).
        fn run_apply_and_store: apply_and_store_baseline / apply_and_store_avx2 =
            stage_apply_and_store(bodies: &mut RigidBodySet, h: f64, readouts: Readouts,
            broken: &mut Vec<(KjointHandle, law::BreakCause)>) -> Result<(), SimError>;
    }

    /// Stage 3 (with the blocked stiffness of the joints whose automatic `Kn` this substep
    /// length has not resolved yet): the sensors' activations, for every joint of the set.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn stage_stiffness_and_sensors(
        &mut self,
        bodies: &mut RigidBodySet,
        h: f64,
    ) -> Result<(), SimError> {
        if std::mem::take(&mut self.mass_check) {
            self.check_masses(bodies);
        }
        if !self.removed_bodies.is_empty() {
            self.unresolve_beside_removed(bodies);
        }
        // the frame's `dt` (or the substep count) changed since the resolution: the
        // automatic stiffness `κ·m_L/h²` (Radioss' `2m/(α·h²)`) resolved at the old length
        // `h₀` is `(h/h₀)²` times the one the rule asks for at this one. A first frame of
        // 0.1 s left a 10-link chain stepped at 60 Hz afterwards with 36 times the rule's
        // sag for the whole run, and a later shorter `dt` rang (an engine integrator's
        // trial, 2026-12-05). Every joint is resolved again, at the poses of now: O(joints)
        // (a 1000-link chain: 0.3 ms, 11 % of its frame), so not for a frame rate's
        // jitter within [`RESOLVE_TOLERANCE`] (the stiffness then within ±10 % of the rule's)
        let changed =
            self.resolved_h > 0.0 && (h / self.resolved_h - 1.0).abs() > RESOLVE_TOLERANCE;
        if changed {
            for j in &mut self.joints {
                j.blocked = None;
            }
            self.auto_dt = None;
        }
        if self.auto_dt != Some(h) && self.joints.iter().any(|j| j.blocked.is_none()) {
            self.resolve_stiffness(bodies, h)?;
            if changed || self.resolved_h == 0.0 {
                self.resolved_h = h;
            }
        }
        self.update_sensors(bodies);
        Ok(())
    }

    /// Puts tile `k` ([`super::tiles`]) in place for the stages: its data in [`Self::data`],
    /// its joints in [`Self::active`] and, with `scratch`, the shared scratch in its data
    /// (and the first tile's solver, where it borrows it). [`Self::leave_tile`] undoes it.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn enter_tile(&mut self, k: usize, scratch: bool) {
        if k > 0 {
            std::mem::swap(&mut self.data, &mut self.tiles[k - 1]);
        }
        self.active = self.tile_joints.get(k).cloned().unwrap_or(0..0);
        if scratch && !self.tiles.is_empty() {
            let (nb, nj) = (self.data.handles.len(), self.data.sides.len());
            self.scratch.exchange(&mut self.data, nb, nj);
            if k > 0 && self.data.shares_solver {
                // (tile 0's data is in the slot tile k's came from)
                std::mem::swap(&mut self.data.solver, &mut self.tiles[k - 1].solver);
            }
        }
    }

    /// Puts tile `k` back after [`Self::enter_tile`]: tile 0's data is in [`Self::data`]
    /// again.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn leave_tile(&mut self, k: usize, scratch: bool) {
        if scratch && !self.tiles.is_empty() {
            if k > 0 && self.data.shares_solver {
                std::mem::swap(&mut self.data.solver, &mut self.tiles[k - 1].solver);
            }
            self.scratch.exchange(&mut self.data, 0, 0);
        }
        self.active = self.tile_joints.first().cloned().unwrap_or(0..0);
        if k > 0 {
            std::mem::swap(&mut self.data, &mut self.tiles[k - 1]);
        }
    }

    /// Stage 1: re-analyses the structure when a joint's bodies changed (removed from the
    /// world: the joint is removed from the set; switched between dynamic and fixed;
    /// disabled or enabled: the joint leaves the stages or comes back,
    /// [`KjointSet::sort_out_disabled`]) or a joint was inserted, removed, changed
    /// ([`KjointSet::get_mut`]) or switched off or on ([`KjointSet::set_enabled`]).
    fn stage_topology(&mut self, bodies: &mut RigidBodySet, h: f64) {
        let check = std::mem::take(&mut self.asleep_check);
        let covered = self.analysed == self.joints.len();
        // (a joint of automatic stiffness whose body lost its mass, found by stage 3, is
        // turned off by this analysis: `Off::Massless`)
        let massless = std::mem::take(&mut self.massless_found);
        if self.data.valid && covered && !massless {
            // the dynamic bodies are checked by the gather stage (in a tiled set here, before
            // any tile is stepped); the others are read here
            let tiled = !self.tiles.is_empty();
            let same = std::iter::once(&mut self.data)
                .chain(&mut self.tiles)
                .all(|data| {
                    watched_unchanged(data, bodies, h)
                        && (!tiled || dynamic_unchanged(data, bodies))
                });
            let asleep_same =
                check == super::sleep::AsleepCheck::Done || self.asleep.unchanged(bodies);
            if same && asleep_same && self.disabled_unchanged(bodies) {
                return;
            }
        }
        // the last substep's results into the records before the arrays are rebuilt, and
        // the islands' rest
        self.fold_stored_results();
        self.fold_rest();
        // joints whose body left the world leave the set, with an event (as rapier's
        // `ImpulseJointSet` removes the joints of a removed body)
        self.remove_detached_joints(bodies);
        // the joints of a disabled body leave the stages until it is enabled again, as
        // rapier's impulse joints do (`JointEnabled::DisabledByAttachedBody`)
        self.sort_out_disabled(bodies);
        let enabled = self.enabled;
        #[cfg(test)]
        let min = self.tile_joints_min.unwrap_or(super::tiles::TILE_JOINTS);
        #[cfg(not(test))]
        let min = super::tiles::TILE_JOINTS;
        // the islands with an awake body wholly awake; those asleep left out
        let asleep = super::sleep::settle(
            &mut self.joints[..enabled],
            bodies,
            &mut self.wake,
            &mut self.asleep,
            self.time,
        );
        let ranges = super::tiles::tile_joints(&self.joints[..enabled], bodies, min, &asleep);
        let mut carried = CarriedPrediction::take(std::iter::once(&self.data).chain(&self.tiles));
        for hb in std::mem::take(&mut self.forget_prediction) {
            carried.bodies.remove(&hb);
        }
        let mut tiles: Vec<SubstepData> = ranges
            .iter()
            .map(|r| {
                let mut data = self.analyse_tile(r.clone(), bodies, h);
                carried.restore(&mut data, bodies);
                data
            })
            .collect();
        if tiles.len() > 1 {
            let (first, rest) = tiles.split_at_mut(1);
            for data in rest {
                if data.sides == first[0].sides {
                    data.solver = Solver::default();
                    data.shares_solver = true;
                }
            }
            for data in &mut tiles {
                super::tiles::Scratch::strip(data);
            }
        }
        let mut tiles = tiles.into_iter();
        // (no tile when every joint is asleep: nothing to step)
        self.data = tiles.next().unwrap_or_else(|| SubstepData {
            valid: true,
            ..Default::default()
        });
        self.tiles = tiles.collect();
        self.active = ranges.first().cloned().unwrap_or(0..0);
        self.tile_joints = ranges;
        self.analysed = self.joints.len();
        self.give_back_gyroscopic(bodies);
    }

    /// Gives rapier back the gyroscopic term of the bodies whose term the set took over
    /// ([`Self::analyse_tile`]) and that no tile steps any more, awake (their joints
    /// disabled or removed): nothing else would integrate it (a bar whose only joint's pivot
    /// was disabled turned 0.008 rad a second off the same bar without joints). Part of
    /// stage 1's analysis; a tile that steps the body again takes it over again.
    fn give_back_gyroscopic(&mut self, bodies: &mut RigidBodySet) {
        if self.gyroscopic.is_empty() {
            return;
        }
        let stepped: std::collections::HashSet<RigidBodyHandle> = std::iter::once(&self.data)
            .chain(&self.tiles)
            .flat_map(|data| data.handles.iter().copied())
            .collect();
        // (an asleep body keeps it off: woken inside rapier's step, it is stepped once by
        // rapier before the set takes it over again, as before)
        self.gyroscopic.retain(|hb| {
            let Some(b) = bodies.get(*hb) else {
                return false;
            };
            if stepped.contains(hb) || b.is_sleeping() {
                return true;
            }
            bodies[*hb].enable_gyroscopic_forces(true);
            false
        });
    }

    /// The topology and arrays of the joints `range` (a tile, or every joint): stage 1's
    /// analysis, the watched bodies read over the substep `h` ([`watched_pose`]).
    fn analyse_tile(
        &mut self,
        range: std::ops::Range<usize>,
        bodies: &mut RigidBodySet,
        h: f64,
    ) -> SubstepData {
        let mut data = SubstepData::default();
        let joints = &self.joints[range];
        let mut slot_of = std::collections::HashMap::new();
        // the watched bodies, each once (a linear search per joint was quadratic in a scene of
        // joints to distinct kinematic bodies)
        let mut watched = std::collections::HashMap::new();
        for j in joints {
            let mut sides = [None, None];
            let mut watched_of = [u32::MAX; 2];
            for (side, hb) in [j.body1, j.body2].into_iter().enumerate() {
                let b = &mut bodies[hb];
                if !is_awake_dynamic(b) {
                    watched_of[side] = *watched.entry(hb).or_insert_with(|| {
                        data.watched.push(hb);
                        data.watched_pose.push(watched_pose(b, h));
                        data.watched_kinematic.push(b.is_kinematic());
                        data.watched.len() as u32 - 1
                    });
                    continue;
                }
                let slot = *slot_of.entry(hb).or_insert_with(|| {
                    // rapier applies its explicit gyroscopic correction after our
                    // impulses, where a stiff joint only sees it one substep late (and
                    // the feedback grows on slender bodies); take the term over and
                    // solve it with the joints
                    if b.gyroscopic_forces_enabled() {
                        b.enable_gyroscopic_forces(false);
                        self.gyroscopic.insert(hb);
                    }
                    data.handles.push(hb);
                    data.body_addr.push(b as *const RigidBody as usize);
                    data.gyro_on.push(if self.gyroscopic.contains(&hb) {
                        Gyroscopic::Free
                    } else {
                        Gyroscopic::Off
                    });
                    data.handles.len() as u32 - 1
                });
                sides[side] = Some(slot);
            }
            // a joint of one free rotation to a fixed body holds the other to its axis
            // (`bodies::gyroscopic_change`; a kinematic body may turn, and the axis with it)
            let free = j.property().joint_type.free_dofs();
            if free[3..].iter().filter(|f| **f).count() == 1 {
                let fixed = |side: usize| {
                    let w = watched_of[side] as usize;
                    w < data.watched.len() && !data.watched_kinematic[w]
                };
                let held = match sides {
                    [Some(s), None] if fixed(1) => Some(s),
                    [None, Some(s)] if fixed(0) => Some(s),
                    _ => None,
                };
                if let Some(s) = held {
                    if data.gyro_on[s as usize] == Gyroscopic::Free {
                        data.gyro_on[s as usize] = Gyroscopic::OneAxis;
                    }
                }
            }
            data.sides.push(sides);
            data.watched_of.push(watched_of);
        }
        let nb = data.handles.len();
        let nj = joints.len();
        let mut carried = vec![0u32; nb];
        for slot in data.sides.iter().flatten().flatten() {
            carried[*slot as usize] += 1;
        }
        data.alone = data
            .sides
            .iter()
            .map(|s| s.map(|slot| slot.is_some_and(|b| carried[b as usize] == 1)))
            .collect();
        data.solver = data.topology_solver();
        data.bodies = vec![SolverBody::empty(); nb];
        data.mass_cache = vec![MassCache::EMPTY; nb];
        data.gathered = vec![GatheredBody::empty(); nb];
        data.geo = vec![GeometricLoad::NONE; nb];
        data.velocity = vec![Vector6::zeros(); nb];
        data.joints = vec![SolverJoint::default(); nj].into();
        data.prepared = vec![PreparedJoint::default(); nj];
        // the joints' sizes, fixed in their bodies: once per analysis, not per substep
        for ((prep, j), sides) in data.prepared.iter_mut().zip(joints).zip(&data.sides) {
            let levers = [
                prepare::lever_arm(&bodies[j.body1], &j.frames.local_anchor1),
                prepare::lever_arm(&bodies[j.body2], &j.frames.local_anchor2),
            ];
            prep.size = prepare::size(sides, levers, j.initial_length);
            prep.screens = health::Screens::of(j);
            prep.shape = j.property.shape();
        }
        data.motion = vec![motion_at_rest(); nj];
        data.rotation = vec![rotation_at_rest(); nj];
        data.stored = vec![StoredJoint::default(); nj];
        data.driven_before = vec![(f64::NAN, Vector6::zeros()); nj];
        data.breakable = joints.iter().map(|j| j.break_criterion.is_some()).collect();
        data.islands = super::sleep::Islands::analyse(
            joints,
            &data.sides,
            &data.handles,
            &data.watched,
            &data.watched_of,
            bodies,
        );
        data.unfolded = false;
        data.impulses = vec![Vector6::zeros(); nj];
        data.valid = true;
        data.fresh = true;
        data.book_pending = false;
        data.v_pred = vec![Vector6::zeros(); nb];
        data.dv_contact = vec![Vector6::zeros(); nb];
        data.held = vec![0; nb];
        data.pred_scale = vec![[0.0; 2]; nb];
        data.colliders = (data.handles.iter())
            .any(|hb| bodies.get(*hb).is_some_and(|b| !b.colliders().is_empty()));
        data.contact_pred = ContactPrediction::None;
        data
    }

    /// Removes the joints of which a body left the world, each with an event (part of
    /// stage 1, when the structure changed).
    fn remove_detached_joints(&mut self, bodies: &RigidBodySet) {
        let gone: Vec<KjointHandle> = self
            .joints
            .iter()
            .filter(|j| bodies.get(j.body1).is_none() || bodies.get(j.body2).is_none())
            .map(|j| j.handle)
            .collect();
        self.detach(&gone);
    }

    /// Removes joint `h` from the set (if it is still in it) with an event of the kind
    /// `kind` makes of its energies and last readout, then the warnings of the sensors that
    /// watched it.
    pub(super) fn remove_with_event(
        &mut self,
        h: KjointHandle,
        kind: impl FnOnce(law::JointEnergy, Option<Box<JointState>>) -> KjointEventKind,
    ) {
        let Some(j) = self.take(h) else { return };
        let last = j.state().cloned().map(Box::new);
        self.events.push(KjointEvent {
            source: EventSource::Joint {
                handle: h,
                name: j.name.clone(),
            },
            time: self.time,
            kind: kind(j.energy(), last),
        });
        self.warn_sensors_of_removed(h, &j.name);
    }

    /// Stage 2: every dynamic jointed body, once, checked as it is read: removed from the
    /// world or no longer dynamic (the topology changed: the data is left half gathered),
    /// or with a non-finite pose or velocity (what [`KjointSet::check_bodies`] reports,
    /// which [`KjointSet::step`] runs after the last substep only: the substeps before are
    /// checked here, without a second pass over the bodies).
    #[must_use]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn stage_gather_bodies(&mut self, bodies: &RigidBodySet, gravity: Vector, h: f64) -> Gather {
        let g = from_vec3(gravity);
        let data = &mut self.data;
        let ahead = prefetch::worth::<RigidBody>(data.handles.len());
        // the poses first, alone in their loop: each rotation's conversion ends in a square
        // root and divisions (`UnitQuaternion::from_quaternion`) on which the rest of the
        // body's work waits, and the processor overlaps them between bodies only when
        // little else sits between them
        // whether rapier can change a body's velocity in its step beyond gravity and user
        // forces: a rapier joint in the world, or a body with a collider at the analysis
        // ([`ContactPrediction`]; a world of bodies without colliders or rapier joints, the
        // benchmarks', skips its bookkeeping)
        let touchable = self.rapier_constraints || data.colliders;
        let rescale = self.contact_rescale;
        let mut rederived = false;
        data.touchable = touchable;
        let pred = data.contact_pred;
        let (mut any_contact, mut any_held) = (false, false);
        // the three loops over a run of [`GATHER_RUN`] bodies, run after run: the second and
        // the third find the run's rapier bodies and records where the first left them, in
        // the cache
        let count = data.handles.len();
        for k in 0..count.div_ceil(GATHER_RUN) {
            let run = run_of(k, GATHER_RUN, count);
            let start = run.start;
            let slots = data.handles[run.clone()]
                .iter()
                .zip(&mut data.gathered[run.clone()]);
            for (i, (hb, gathered)) in slots.enumerate() {
                let i = start + i;
                if ahead {
                    prefetch_body(&data.body_addr, i + BODY_AHEAD_SHORT);
                }
                let Some(b) = bodies.get(*hb).filter(|b| is_dynamic(b)) else {
                    self.mass_check |= rederived;
                    return Gather::TopologyChanged;
                };
                data.body_addr[i] = b as *const RigidBody as usize;
                gathered.pose = body_pose(b);
                if !gathered.pose.is_finite() {
                    self.mass_check |= rederived;
                    return Gather::NonFinite(i as u32);
                }
            }
            let slots = (data.handles[run.clone()].iter())
                .zip(&mut data.gathered[run.clone()])
                .zip((data.mass_cache[run.clone()].iter_mut()).zip(&mut data.bodies[run.clone()]))
                .zip(&mut data.geo[run.clone()]);
            for (i, (((hb, gathered), (cache, sb)), geo)) in slots.enumerate() {
                let i = start + i;
                // (the run's bodies were asked for by the loop before; asked for again here
                // they cost nothing measurable: without, 1.004 and 1.03 of the frame)
                if ahead && i + BODY_AHEAD < run.end {
                    prefetch_body(&data.body_addr, i + BODY_AHEAD);
                }
                let Some(b) = bodies.get(*hb) else {
                    self.mass_check |= rederived;
                    return Gather::TopologyChanged;
                };
                let rotation = &gathered.pose.rotation;
                let axes = &mut gathered.axes;
                let torque = solver_body(b, rotation, &g, h, cache, sb, &mut rederived, axes);
                gathered.mass = b.mass() as f64;
                gathered.mean_inertia = cache.mean_inertia;
                gathered.torque = torque;
                geo.clear();
            }
            // the gyroscopic terms in a loop of their own (`bodies::add_gyroscopic_change`), and
            // the velocity change of rapier's contacts and joints ([`ContactPrediction`])
            let gathered = data.gathered[run.clone()]
                .iter_mut()
                .zip(&mut data.bodies[run.clone()]);
            let gathered = gathered.zip(
                data.mass_cache[run.clone()]
                    .iter()
                    .zip(&data.gyro_on[run.clone()]),
            );
            let pred_at = data.v_pred[run.clone()]
                .iter()
                .zip(&data.pred_scale[run.clone()]);
            let gathered = gathered.zip(
                pred_at.zip(
                    data.dv_contact[run.clone()]
                        .iter_mut()
                        .zip(&mut data.held[run.clone()]),
                ),
            );
            // last body of the run first ("Direction of the loops" in the module's
            // documentation)
            for (((gathered, sb), (cache, on)), ((vp, scale), (dvc, held))) in gathered.rev() {
                let torque = gathered.torque;
                let (pose, axes) = (&gathered.pose, &gathered.axes);
                gathered.gyro = add_gyroscopic_change(pose, axes, cache, h, *on, torque, sb);
                match pred {
                    ContactPrediction::Measure => {
                        let p = &gathered.pose;
                        let v = Vector6::new(
                            p.linvel.x, p.linvel.y, p.linvel.z, p.angvel.x, p.angvel.y, p.angvel.z,
                        );
                        *dvc = contact_change(&v, vp, scale);
                        // (measured over a substep of another length: rescaled to this one)
                        if rescale != 1.0 {
                            *dvc *= rescale;
                        }
                    }
                    ContactPrediction::Stored => {}
                    // (left as it is: nothing reads it while `any_contact` is false, and the
                    // next prediction overwrites it; no write a body a substep where rapier
                    // cannot act)
                    ContactPrediction::None => {}
                }
                // (stored over a substep of another length: rescaled to this one, and
                // written so once every run is gathered, below: a gather that a changed body
                // ends in a later run leaves it as it was for the gather after the analysis)
                let stored_rescaled;
                let dvc: &Vector6<f64> = if rescale != 1.0 && pred == ContactPrediction::Stored {
                    stored_rescaled = *dvc * rescale;
                    &stored_rescaled
                } else {
                    dvc
                };
                any_contact |= pred != ContactPrediction::None && *dvc != Vector6::zeros();
                gathered.dv_plain = sb.dv_ext;
                // the axes rapier's contacts hold, taken as heavy by the solve ([`held_axes`]),
                // but an axis a non-finite force acts along (named as the user's by the solve's
                // failure, [`KjointSet::non_finite_user_force`])
                *held = if pred == ContactPrediction::None {
                    0
                } else {
                    held_axes(dvc, &g, h)
                };
                if *held != 0 {
                    for a in 0..3 {
                        if !sb.dv_ext[a].is_finite() {
                            *held &= !(1 << a);
                        }
                    }
                    any_held |= *held != 0;
                }
            }
        }
        if rescale != 1.0 && pred == ContactPrediction::Stored {
            for dvc in &mut data.dv_contact {
                *dvc *= rescale;
            }
        }
        data.any_contact = any_contact;
        data.any_held = any_held;
        if any_held {
            // the islands' weights over the substep, for the rotation share's gate
            // ([`CONTACT_ROTATION_SHARE`]), from this substep's masses
            let weight = &mut data.island_weight;
            weight.clear();
            weight.resize(data.islands.count(), 0.0);
            for (slot, gathered) in data.gathered.iter().enumerate() {
                weight[data.islands.of(slot)] += gathered.mass;
            }
            let gh = g.norm() * h;
            weight.iter_mut().for_each(|m| *m *= gh);
            // the gate of each held body: its contact's linear impulse `P` against its
            // island's weight `W`
            let bodies = data
                .gathered
                .iter_mut()
                .zip(&data.dv_contact)
                .zip(&data.held);
            for (slot, ((gathered, dv), held)) in bodies.enumerate() {
                if *held != 0 {
                    let impulse = gathered.mass * dv.fixed_rows::<3>(0).norm();
                    let weight = weight[data.islands.of(slot)];
                    gathered.gate = if impulse > weight {
                        weight / impulse
                    } else {
                        1.0
                    };
                }
            }
        }
        // (a body's mass properties derived again: compared with those the blocked
        // stiffness was resolved from by stage 3, [`KjointSet::check_masses`])
        self.mass_check |= rederived;
        Gather::Done
    }

    /// Stage 4: kinematics, law and implicit blocks of every joint, and its readout, in two
    /// loops: [`Self::stage_measure_joints`] (book the last substep's end rates; measure),
    /// then named steps (`prepare`): evaluate the law and the connector; pass the transmitted
    /// force's geometric stiffness to the bodies; damp what the substep cannot resolve and
    /// scale the stored energies to what the update realises; engage the predicted stops;
    /// write the solver block and the readout.
    ///
    /// Two loops rather than one: the kinematics, the law and the rest of this stage are
    /// each about 10 KB of machine code, together more than the processor's 32 KB
    /// instruction cache, which then missed about 180 times per joint (cachegrind); the
    /// joints' motions pass from one loop to the next in a contiguous array.
    ///
    /// Both loops over a run of [`PREPARE_RUN`] joints, run after run: the second finds the
    /// run's motions, rotations, Jacobians and records where the first left them, in the
    /// cache (at 10 000 joints each loop over the whole set read them from memory). A
    /// non-finite motion ends the stage at once, the runs before it prepared (their laws
    /// evaluated: the substep fails, with the joint named).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn stage_prepare_joints(&mut self, h: f64, readouts: Readouts) -> Result<(), SimError> {
        let book_end_rates = std::mem::replace(&mut self.data.book_pending, false);
        // the coupled G blocks of this substep (SolverJoints::set_g)
        self.data.joints.coupled.clear();
        let count = self.active.len();
        for k in 0..count.div_ceil(PREPARE_RUN) {
            let run = run_of(k, PREPARE_RUN, count);
            self.stage_measure_joints(run.clone(), book_end_rates)?;
            self.prepare_joints_run(run, h, readouts);
        }
        Ok(())
    }

    /// The prepare loop of [`Self::stage_prepare_joints`] over the joints `run` of
    /// [`Self::active`] (indices from its start), measured.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn prepare_joints_run(&mut self, run: std::ops::Range<usize>, h: f64, readouts: Readouts) {
        let time = self.time;
        let substeps = self.settings().substeps;
        let readout_each = readouts == Readouts::All;
        let data = &mut self.data;
        let active = self.active.clone();
        let count = active.len();
        let base = self.joints[active.clone()].as_ptr();
        let ahead = prefetch::worth::<Kjoint>(count);
        let records = &mut self.joints[active.start + run.start..active.start + run.end];
        for (ji, j) in run.zip(records) {
            if ahead && ji + 2 < count {
                // the record's hot fields, and the readout only where it is written (750 of
                // the record's 1520 bytes: at 10 000 pendulums 2 % of the frame); not its
                // cold fields (`Kjoint`'s layout)
                let record = base.wrapping_add(ji + 2);
                prefetch::field(record, 0, KJOINT_HOT_BYTES);
                if readout_each {
                    prefetch::field_of!(record, Kjoint, state);
                }
            }
            let sides = data.sides[ji];
            let shape = data.prepared[ji].shape;
            prepare::fold_stored(j, &mut data.stored[ji]);
            // pose and (mass, inertia) of each side; a fixed side has infinite mass
            let side = |s: usize| match sides[s] {
                Some(slot) => {
                    let g = &data.gathered[slot as usize];
                    (&g.pose, Some((g.mass, g.mean_inertia)))
                }
                None => (&data.watched_pose[data.watched_of[ji][s] as usize], None),
            };
            let (p1, m1) = side(0);
            let (p2, m2) = side(1);
            let kin = &data.motion[ji];
            let jac = &data.joints[ji].jac;
            let params = LawParams {
                blocked: j.blocked.expect("resolved before the joints are prepared"),
                reduced_mass: reduced(m1.map(|m| m.0), m2.map(|m| m.0)),
                reduced_inertia: reduced(m1.map(|m| m.1), m2.map(|m| m.1)),
            };
            let lock = j.property.sensor.is_some_and(|s| {
                self.sensors
                    .get(&s)
                    .is_some_and(|s| s.activated_at.is_some())
            });
            // the law's output, in the same stack slot for every joint (hot in cache; it was a
            // 900-byte value returned and copied per joint)
            let mut out = law::LawOutput::zeroed();
            // the law's first evaluation stores the joint's preload (no work of the bodies)
            let first = j.law.prev_q.is_none();
            prepare::evaluate_law(j, &params, &shape, kin, &jac.t, p2, lock, time, &mut out);
            // the events the connector just logged (a flex joint's phase switch)
            super::joint_set::collect_connector_events_of(j, &mut self.events);
            // geometric stiffness of the force the joint transmitted over the previous
            // substep (the law's explicit force is meaningless for an unresolved DOF: K·q
            // with q at f32 noise), at the point it acts at (the anchors' mid-point, or
            // anchor 2 of a planar-friction joint)
            let fa = j.last_applied;
            let f_world = jac.t.transpose() * Vector3::new(fa[0], fa[1], fa[2]);
            let point = kin.force_point;
            for (slot, pose, sign) in [(sides[0], p1, 1.0), (sides[1], p2, -1.0)] {
                if let Some(bi) = slot {
                    data.geo[bi as usize].add(&(sign * f_world), &(point - pose.com));
                }
            }
            // the diagonal of the symmetric part of the tangent stiffness (the block itself
            // only where the law has entries off the diagonal: `prepare::write_g`)
            let mut kt =
                Vector6::from_fn(|i, _| 0.5 * (out.stiffness[(i, i)] + out.stiffness[(i, i)]));
            // diagonal of the joint's own J·M⁻¹·Jᵀ (before the geometric stiffness is added
            // to the bodies)
            let inv_mass = |s: usize| sides[s].map(|bi| &data.bodies[bi as usize].inv_mass);
            let w = solve::jacobian_weighted_diagonal_of_sides(jac, [inv_mass(0), inv_mass(1)]);
            // a rotor geared to a free DOF (its armature `a`, `law::DofLaw::armature`) adds
            // its inertia to the bodies': the DOF's inverse mass `1/(1/w + a)` = `w/(1 + a·w)`
            // for the numerical damping, the predictions and the stored energy's scale below
            let armature = j.armature.as_deref().copied();
            let w = match &armature {
                Some(a) => {
                    // and its kinetic energy `½·a·q̇²` at the substep's start is the joint's
                    // (`law::JointEnergy::kinetic`), booked as the law books its own
                    j.law.energy.kinetic = law::JointEnergy::rotor_energy(a, &kin.rate);
                    Vector6::from_fn(|i, _| w[i] / (1.0 + a[i] * w[i]))
                }
                None => w,
            };
            let alone = data.alone[ji];
            let swing = solve::geometric_swing_stiffness(
                &f_world,
                [
                    solve::swing_lever((point - p1.com).norm(), m1, alone[0]),
                    solve::swing_lever((point - p2.com).norm(), m2, alone[1]),
                ],
            );
            let mut c_num = solve::unresolved_damping(&kt, &swing, &w, h);
            // a sticking friction spring the substep would load beyond its cap slips from the
            // start of the substep (`law::slip_prediction`); its `K_f` then leaves the tangent
            // and the numerical damping
            let sticks = out
                .status
                .iter()
                .any(|s| s.friction == law::FrictionStatus::Stick);
            if sticks {
                let c_friction = prepare::friction_share_of_damping(
                    &j.property,
                    &out,
                    &kt,
                    &swing,
                    &w,
                    h,
                    &c_num,
                );
                if law::predict_slips(
                    &j.property,
                    &mut out,
                    &mut j.law,
                    &kin.rate,
                    &w.data.0[0],
                    &c_num.data.0[0],
                    &c_friction,
                    &mut kt.data.0[0],
                    h,
                    solve::BETA,
                ) {
                    c_num = solve::unresolved_damping(&kt, &swing, &w, h);
                }
            }
            let mut total = out.total;
            prepare::add_unresolved_damping(&mut out, &mut total, &c_num, &kin.rate);
            prepare::scale_stored_energy(j, &params, &shape, &kt, &out, &w, &kin.q, h);
            if first {
                prepare::book_preload(j);
            }
            // the law's own tangent, for the share of the substep it books at its next
            // evaluation (the predicted stops, below, are the update's)
            let kt_law = kt;
            // stops the DOFs will reach by the end of the substep engage now, and a DOF that
            // rests on its stop is held on it (`law::stop_prediction`); after the numerical
            // damping, which must not act on the approach
            if shape.independent_stops || shape.coupled_stops {
                prepare::engage_predicted_stops(
                    j,
                    &params,
                    kin,
                    &fa,
                    &w,
                    h,
                    &mut kt,
                    &out.parts,
                    &mut out.stiffness,
                    &mut total,
                );
            } else {
                // (what the prediction leaves where the property has no stop)
                j.predicted_stops = law::StopPredictionState::default();
            }
            // (`side_impulse` and `end_power` are the store stage's, written there for every
            // joint before anything reads them; `size` the analysis')
            let prep = &mut data.prepared[ji];
            prep.suspect = health::suspect(&j.property, &kin.q, prep.size, prep.screens, &shape)
                || (prep.screens.rotation_vector && health::rotation_jumped(j));
            // once per joint and change of the set or of `h` (not at the analyses that
            // islands falling asleep or waking make); the key (two logarithms) only at the
            // first substep after an analysis, where a notice can come
            if data.fresh {
                let noticed = (j.notice_key(), h);
                if j.noticed != noticed {
                    if j.noticed.1.is_nan() {
                        health::first_notices(j, ji, prep.size, time, &mut self.events);
                        let dynamic = |s: usize, p| sides[s].map(|_| p);
                        health::flex_axis_across(
                            j,
                            ji,
                            prep.size,
                            [dynamic(0, p1), dynamic(1, p2)],
                            &kin.force_point,
                            &data.rotation[ji].1,
                            time,
                            &mut self.events,
                        );
                    }
                    health::start_notices(j, ji, &w, h, substeps, time, &mut self.events);
                    j.noticed = noticed;
                }
            }
            // written in place: the record and the solver block are kilobytes per joint
            let diagonal = !j.connector.is_some() && !shape.coupled_stops;
            prepare::write_g(
                &mut data.joints,
                ji,
                &out,
                &kt,
                h,
                diagonal,
                armature.as_ref(),
            );
            let sj = &mut data.joints[ji];
            sj.bodies = sides;
            #[allow(clippy::needless_range_loop)] // (`explicit` a Vector6, `total` an array)
            for i in 0..6 {
                sj.explicit[i] = -h * total[i];
            }
            if data.any_contact && diagonal {
                prepare::predict_contacts(
                    sj,
                    &sides,
                    (&data.dv_contact, &data.held, &data.gathered),
                    (&kt, &swing, &w),
                    h,
                );
            }
            // the readout where anything reads it before the next is written: at the
            // substeps that end a step or meet a hook ([`Readouts`]), and
            // where this substep's checks or the failure criterion read it
            let readout = readout_each || prep.suspect || data.breakable[ji];
            if readout {
                let frame = &data.rotation[ji].1;
                prepare::write_readout(j, kin, frame, [p1, p2], &out, time);
                prepare::outstanding_forces(j, &params, &kt_law, &out, &c_num, &w, h);
            }
            data.stored[ji].readout = readout;
            // (the store stage's result replaces it; as the readout's `applied` was, before)
            j.last_applied = [0.0; 6];
        }
    }

    /// Stage 4a over the joints `run` of [`Self::active`] (indices from its start): measures
    /// the last substep's end-rate correction (with its Jacobians, where `book_end_rates`)
    /// and each joint (its Jacobians written into its solver block, its motion into
    /// [`SubstepData::motion`]); a non-finite motion is an error naming the first such
    /// joint. Reads the joint records' frames and measure states only.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn stage_measure_joints(
        &mut self,
        run: std::ops::Range<usize>,
        book_end_rates: bool,
    ) -> Result<(), SimError> {
        let data = &mut self.data;
        let active = self.active.clone();
        let count = active.len();
        let base = self.joints[active.clone()].as_ptr();
        let ahead = prefetch::worth::<Kjoint>(count);
        let rotations_ahead = prefetch::worth::<kinematics::Measured>(count);
        let bodies_ahead = prefetch::worth::<GatheredBody>(data.gathered.len());
        // the rotations first, alone in their loop: each joint's is a chain of roots,
        // divisions and an `atan2` (`kinematics::measure_rotation`) that the processor
        // overlaps with the next joints' only when little else sits between them; four
        // consecutive twist-measured joints (hinges) at once in vector lanes
        // (`kinematics::measure_twist_x4`: the same bits), the others one by one
        let records = &mut self.joints[active.clone()];
        let rotation_of = |ji: usize, s: usize| match data.sides[ji][s] {
            Some(slot) => &data.gathered[slot as usize].pose.rotation,
            None => &data.watched_pose[data.watched_of[ji][s] as usize].rotation,
        };
        // the records asked for so far (each once, at MEASURE_AHEAD to MEASURE_AHEAD + 4
        // joints ahead)
        let mut asked = 0;
        // the first joint (in the set's order) whose motion is not finite
        let mut non_finite = None;
        let mut ji = run.start;
        while ji < run.end {
            if ahead && ji + MEASURE_AHEAD < count {
                // what this loop reads of a joint record: its frames and measure state
                let upto = (ji + MEASURE_AHEAD + 4).min(count);
                for k in (ji + MEASURE_AHEAD).max(asked)..upto {
                    let ahead = base.wrapping_add(k);
                    prefetch::field_of!(ahead, Kjoint, frames);
                    prefetch::field_of!(ahead, Kjoint, measure);
                    // and, two joints later (ten to fourteen ahead), the rotation's slot this
                    // loop writes (208 bytes) and the bodies' orientations it reads: at
                    // 10 000 joints both come from memory, and this loop cost 60 % more a
                    // joint than at 1000 (10 000 pendulums' frame 1 % faster with them,
                    // medians of 7 and 10 alternating rounds)
                    let later = k + 2;
                    if rotations_ahead {
                        prefetch::value(data.rotation.as_ptr().wrapping_add(later));
                    }
                    if bodies_ahead {
                        for slot in data.sides.get(later).into_iter().flatten().flatten() {
                            let body = data.gathered.as_ptr().wrapping_add(*slot as usize);
                            prefetch::field_of!(body, GatheredBody, pose.rotation);
                        }
                    }
                }
                asked = upto;
            }
            let twist = kinematics::RotationMeasure::TwistX;
            // (no `Iterator::all` with a closure: compiled out of line in the AVX2 copy)
            let four = ji + 4 <= run.end
                && records[ji].frames.measure == twist
                && records[ji + 1].frames.measure == twist
                && records[ji + 2].frames.measure == twist
                && records[ji + 3].frames.measure == twist;
            // the joints of this pass, and whether the lanes measured them
            let (n, in_lanes) = if four {
                let four = &records[ji..ji + 4];
                let in_lanes = kinematics::measure_twist_x4(
                    [
                        &four[0].frames,
                        &four[1].frames,
                        &four[2].frames,
                        &four[3].frames,
                    ],
                    [
                        rotation_of(ji, 0),
                        rotation_of(ji + 1, 0),
                        rotation_of(ji + 2, 0),
                        rotation_of(ji + 3, 0),
                    ],
                    [
                        rotation_of(ji, 1),
                        rotation_of(ji + 1, 1),
                        rotation_of(ji + 2, 1),
                        rotation_of(ji + 3, 1),
                    ],
                    [
                        &four[0].measure,
                        &four[1].measure,
                        &four[2].measure,
                        &four[3].measure,
                    ],
                    &mut data.rotation[ji..ji + 4],
                );
                (4, in_lanes)
            } else {
                (1, false)
            };
            if in_lanes {
                for (j, m) in records[ji..ji + 4].iter_mut().zip(&data.rotation[ji..]) {
                    j.measure.record(m);
                }
            } else {
                // one by one: a single joint, or four with a lane off the lanes' common path
                // (all four, not the next four from ji + 1, which would try that lane again)
                for (k, j) in (ji..).zip(&mut records[ji..ji + n]) {
                    data.rotation[k] = kinematics::measure_rotation(
                        &j.frames,
                        rotation_of(k, 0),
                        rotation_of(k, 1),
                        &mut j.measure,
                    );
                }
            }
            ji += n;
        }
        let joints = (records[run.clone()]
            .iter()
            .zip(&data.sides[run.clone()])
            .zip(&data.rotation[run.clone()]))
        .zip((data.joints.list[run.clone()].iter_mut()).zip(&mut data.motion[run.clone()]))
        .zip((data.prepared[run.clone()].iter()).zip(&mut data.stored[run.clone()]));
        // last joint of the run first ("Direction of the loops" in the module's
        // documentation)
        for (ji, ((((j, sides), rotation), (sj, motion)), (prep, stored))) in
            joints.enumerate().rev()
        {
            let ji = run.start + ji;
            if book_end_rates {
                stored.correction = end_rate_correction(prep, sides, &data.gathered);
            }
            let pose = |s: usize| match sides[s] {
                Some(slot) => &data.gathered[slot as usize].pose,
                None => &data.watched_pose[data.watched_of[ji][s] as usize],
            };
            let kin = kinematics::measure_with_rotation(
                &j.frames,
                pose(0),
                pose(1),
                rotation,
                &mut sj.jac,
            );
            if !kin.is_finite() {
                non_finite = Some(ji);
            }
            *motion = kin;
        }
        match non_finite {
            Some(ji) => Err(SimError::Unstable {
                time: self.time,
                reason: format!(
                    "joint `{}`: non-finite kinematics",
                    self.joints[active.start + ji].name
                ),
            }),
            None => Ok(()),
        }
    }

    /// Stage 5: the geometric stiffness made implicit on the bodies, then the solve.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn stage_solve(&mut self, h: f64) -> Result<(), SimError> {
        let data = &mut self.data;
        data.fresh = false;
        // the geometric stiffness's positive parts first, alone in their loop
        // (`GeometricLoad::implicit_part`), then the bodies' inertias augmented by them
        let s = h * h / solve::BETA;
        for load in data.geo.iter_mut() {
            load.implicit_part(s);
        }
        for (sb, load) in data.bodies.iter_mut().zip(&data.geo) {
            sb.add_implicit_rotational_stiffness(load.part());
        }
        // the bodies rapier's contacts hold, heavier along the held axes ([`held_axes`]):
        // for the solve alone, after the prepare stage sized the joints' damping and
        // stored energies on the bodies' real masses
        if data.any_held {
            for (sb, held) in data.bodies.iter_mut().zip(&data.held) {
                if *held != 0 {
                    sb.hold(*held, HELD_MASS);
                }
            }
        }
        let mut result = data.solver.solve(
            &data.joints,
            &data.bodies,
            &mut data.impulses,
            &mut data.velocity,
        );
        // a held body the joints' impulses lift off its contact, which cannot pull it back:
        // solved again with its real mass ([`held_axes`])
        if result.is_ok() && data.any_held && release_lifted(data) {
            result = data.solver.solve_again(
                &data.joints,
                &data.bodies,
                &mut data.impulses,
                &mut data.velocity,
                &data.released,
            );
        }
        #[cfg(test)]
        if let Some(worst) = self.verify.as_mut() {
            let active: Vec<usize> = (0..self.active.len()).collect();
            let js = SolverJoints {
                list: active.iter().map(|&j| data.joints[j].clone()).collect(),
                coupled: data.joints.coupled.clone(),
            };
            let reference = solve::reference_solve(&js, &data.bodies);
            let scale = reference.iter().map(|p| p.amax()).fold(0.0, f64::max);
            for (k, &j) in active.iter().enumerate() {
                let e = (data.impulses[j] - reference[k]).amax() / scale.max(f64::MIN_POSITIVE);
                *worst = worst.max(e);
            }
        }
        result.map_err(|f| {
            let (j, what) = match f {
                SolveFailure::SingularJoint(j) => (j, "singular implicit matrix G"),
                SolveFailure::NotPositive(j) => {
                    let joint = self.active.start + j as usize;
                    let remedy = self.not_positive_remedy(j as usize, joint, h);
                    let name = self.joints.get(joint).map_or("?", |j| j.name.as_str());
                    return SimError::Unstable {
                        time: self.time,
                        reason: format!(
                            "joint `{name}`: the joint system is not positive definite; {remedy}"
                        ),
                    };
                }
                SolveFailure::NonFinite(j) => (j, "non-finite joint impulse"),
                SolveFailure::SingularBody(b) => {
                    let owner = self
                        .data
                        .sides
                        .iter()
                        .position(|s| s.contains(&Some(b)))
                        .unwrap_or(0);
                    (owner as u32, "singular augmented inertia of a body")
                }
            };
            let joint = self.active.start + j as usize;
            let name = self.joints.get(joint).map_or("?", |j| j.name.as_str());
            SimError::Unstable {
                time: self.time,
                reason: format!("joint `{name}`: {what}"),
            }
        })
    }

    /// Why the joints' system at `joint` (its index `j` in the stage data) is not positive
    /// definite, and what to do. Where joints hold the same DOFs twice (two pins on one
    /// hinge line: redundant), the system is positive definite only through the joints'
    /// compliance `β/(h²·Kn)`, which rounding loses beside the bodies' inverse mass `W`
    /// once `h²·Kn·W/β` nears `1/ε ≈ 1e16` (the forces the joints share lose the digits
    /// long before: a relative error of about `ε·h²·Kn·W/β`). Otherwise a free DOF's
    /// tangent stiffness is negative beyond what the bodies carry.
    #[cold]
    fn not_positive_remedy(&self, j: usize, joint: usize, h: f64) -> String {
        let w: f64 = self.data.sides.get(j).map_or(0.0, |sides| {
            sides
                .iter()
                .flatten()
                .map(|&b| self.data.bodies[b as usize].inv_mass.linear.max())
                .sum()
        });
        let kn = self
            .joints
            .get(joint)
            .and_then(|j| j.blocked)
            .map_or(0.0, |k| k.translational);
        let stiff = h * h * kn * w / solve::BETA;
        if stiff > 1e12 {
            format!(
                "its blocked stiffness Kn = {} N/m is {} times its bodies' inertia over a \
                 substep (h²·Kn/(β·m)), beyond what double precision resolves where joints \
                 hold the same DOFs twice (as two pins on one hinge line); remedies: a smaller \
                 Kn (Kn = 0: the automatic stiffness from the substep), or one joint where two \
                 hold the same DOFs (if none do, a free DOF's curve whose slope falls below \
                 zero: a slope that stays positive)",
                crate::figure::format_figure(kn),
                crate::figure::format_figure(stiff)
            )
        } else {
            "a free DOF's tangent stiffness (a curve's slope falling below zero, a connector \
             law) pulls harder than its bodies' inertia holds; remedies: curves whose slope \
             stays positive, more substeps"
                .to_owned()
        }
    }

    /// Stage 6: `Δv = M⁻¹·Jᵀ·P` (from the solve) plus the gyroscopic term, to rapier, and
    /// what the augmented inertia changes in the external velocity change (the damping of an
    /// unresolved swing; rapier applies gravity and user forces itself).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn stage_apply_impulses(&mut self, bodies: &mut RigidBodySet, run: std::ops::Range<usize>) {
        let data = &mut self.data;
        let touchable = data.touchable;
        let ahead = prefetch::worth::<RigidBody>(data.handles.len());
        let bodies_in_order = (data.handles[run.clone()].iter())
            .zip(&data.velocity[run.clone()])
            .zip(&data.gathered[run.clone()])
            .zip(&data.bodies[run.clone()])
            .zip((data.v_pred[run.clone()].iter_mut()).zip(&mut data.pred_scale[run.clone()]));
        for (i, ((((hb, u), g), sb), (vp, scale))) in run.clone().zip(bodies_in_order) {
            if ahead {
                prefetch_body(&data.body_addr, i + BODY_AHEAD_APPLY);
                // and the fields this loop reads of the substep's data (at 10 000 bodies
                // from memory too)
                let a = i + BODY_AHEAD;
                let gb = data.gathered.as_ptr().wrapping_add(a);
                prefetch::field_of!(gb, GatheredBody, gyro);
                prefetch::field_of!(gb, GatheredBody, dv_plain);
                let sb = data.bodies.as_ptr().wrapping_add(a);
                prefetch::field_of!(sb, SolverBody, dv_ext);
            }
            let mut d = u + (sb.dv_ext - g.dv_plain);
            // a held axis: the body's real share of the impulses, which rapier's contact
            // cancels ([`held_axes`]; the solve took it `HELD_MASS` times heavier)
            let held = data.held[i];
            if held != 0 {
                for a in 0..3 {
                    if held & (1 << a) != 0 {
                        d[a] = u[a] * HELD_MASS;
                    }
                }
            }
            let body = &mut bodies[*hb];
            let v = body.linvel() + to_vec3(&d.fixed_rows::<3>(0).into_owned());
            let w = body.angvel() + to_vec3(&(d.fixed_rows::<3>(3) + g.gyro));
            // (the round-off's components flushed: `bodies::VELOCITY_FLOOR`)
            let (v, w) = (flush_velocity(v), flush_velocity(w));
            body.set_linvel(v, true);
            body.set_angvel(w, true);
            if !touchable {
                continue;
            }
            // what rapier will end the substep with, as predicted: its own gravity and user
            // forces, `Δv_plain` less the set's gyroscopic term
            let (v, w) = (from_vec3(v), from_vec3(w));
            let mut own = g.dv_plain;
            {
                let mut a = own.fixed_rows_mut::<3>(3);
                a -= &g.gyro;
            }
            *vp = Vector6::new(
                v.x + own[0],
                v.y + own[1],
                v.z + own[2],
                w.x + own[3],
                w.y + own[4],
                w.z + own[5],
            );
            *scale = [
                v.norm_squared() + own.fixed_rows::<3>(0).norm_squared(),
                w.norm_squared() + own.fixed_rows::<3>(3).norm_squared(),
            ];
        }
    }

    /// Stage 7: the force transmitted over the substep (`−P/h`) into the readout, and the
    /// energy book, the one place where the update's own work is booked, and the work that
    /// bodies which are not dynamic (kinematic bodies with a prescribed motion) did through
    /// the joints ([`KjointSet::driven_work`]).
    ///
    /// The impulse `P` of a joint does the work `W = P·(q̇⁻ + q̇⁺)/2` on its bodies over the
    /// substep (`q̇⁻` the rates at its start, `q̇⁺` at its end as the solve predicts them), so
    /// the joint takes up `−W`. The law books its own share (stored elastic energy,
    /// damping, friction, stops) from its forces along the measured motion; what the update
    /// did beyond that — the numerical damping of unresolved DOFs, the difference between
    /// the implicit impulse and the law's force on a DOF the substep cannot resolve — is
    /// booked as [`crate::law::JointEnergy::numerical`], so that the joint's energy is
    /// exactly what the bodies gave it. (The law's share of a substep is booked at the next
    /// evaluation; the sums telescope. Until then `numerical` holds it: where the energies
    /// are read, [`Kjoint::closed_energy`] adds it to the law's fields, predicted from the
    /// forces the prepare stage wrote for it, [`prepare::outstanding_forces`].)
    ///
    /// In the same loop, the joints the prepare stage flagged ([`health::suspect`]) are
    /// checked on what they measured at the start of the substep ([`health`]): a warning,
    /// once per joint and kind (again as it grows fourfold), when anchors separate or a stop is overrun beyond its bound;
    /// an error naming the joint and remedies when the separation shows the run is unstable
    /// (the first one is returned once every joint is stored).
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn stage_store_results(
        &mut self,
        h: f64,
        readouts: Readouts,
        broken: &mut Vec<(KjointHandle, law::BreakCause)>,
        run: std::ops::Range<usize>,
    ) -> Result<(), SimError> {
        let time = self.time;
        let mut failure = Ok(());
        let data = &mut self.data;
        let fold_all = readouts == Readouts::All;
        let records = self.joints[self.active.clone()].as_ptr();
        let fold_ahead =
            (fold_all && prefetch::worth::<Kjoint>(self.active.len())).then(fold_offsets);
        // the transmitted force −P/h by one reciprocal (within an ulp of the quotient)
        let minus_inv_h = -1.0 / h;
        let active = self.active.clone();
        let ahead = prefetch::worth::<SolverJoint>(active.len());
        let joints = &mut self.joints[active.start + run.start..active.start + run.end];
        for (ji, j) in run.zip(joints) {
            if ahead {
                // what this loop reads of the substep's data, STORE_AHEAD joints ahead: the
                // solver block's sides and Jacobians, the prepared rates, the stored results
                let a = ji + STORE_AHEAD;
                let sj = data.joints.list.as_ptr().wrapping_add(a);
                prefetch::field_of!(sj, SolverJoint, bodies);
                prefetch::field_of!(sj, SolverJoint, jac);
                prefetch::value(data.prepared.as_ptr().wrapping_add(a));
                prefetch::value(data.stored.as_ptr().wrapping_add(a));
                if let Some(offsets) = fold_ahead {
                    prefetch_folded(records.wrapping_add(a), offsets);
                }
            }
            let p = &data.impulses[ji];
            let sj = &data.joints[ji];
            let prep = &mut data.prepared[ji];
            let rate = Vector6::from_column_slice(&data.motion[ji].rate);
            // q̇⁺ = q̇⁻ + Σ_s J_s·Δv_s (Δv_s = u_s + Δv_ext,s, the body's velocity change), so
            // P·(q̇⁻ + q̇⁺)/2 = P·q̇⁻ + ½·Σ_s g_s·Δv_s with g_s = J_sᵀ·P, which the next
            // substep's end-rate correction reuses (a product with the Jacobians per side
            // instead of two)
            let p_rate = p.dot(&rate);
            let mut p_change = 0.0;
            for (s, slot) in sj.bodies.iter().enumerate() {
                prep.side_impulse[s] = match slot {
                    Some(bi) => {
                        let bi = *bi as usize;
                        let g = sj.jac.tr_mul(s, p);
                        p_change += g.dot(&(data.velocity[bi] + data.bodies[bi].dv_ext));
                        g
                    }
                    None => Vector6::zeros(),
                };
            }
            let mut work_on_bodies = p_rate + 0.5 * p_change;
            // of which the bodies that are not dynamic took `P·q̇_d`, `q̇_d = J·v` of those
            // sides (`prepare::driven_rates`, from the poses the prepare stage read; their
            // velocity is constant over the substep): the rates the solve's end power holds.
            // Their work through the joint is booked on the law's basis instead. The law
            // books its energy by the trapezoid of its forces at its evaluations (the
            // substeps' starts) over the displacement between them, the kinematic side's
            // `d_n = h·q̇_d` included; the impulse is the force at the substep's start,
            // `P_n = −h·F_n` up to the implicit correction `G·Δq̇`, so `P·q̇_d` booked
            // `F_n·d_n`, a left rectangle: `½·(F_n+1 − F_n)·d_n` less each substep than the
            // law, `−(h/2)·∫F·a_d dt` over a run once the boundary terms are out, O(h), booked
            // as `numerical` dissipation and as work of the motion (a 1 kg mass on an
            // undamped 400 N/m spring on a base shaken by 0.05·sin(4πt) m: 1.09 J
            // "dissipated" and 1.09 J of false work in 10 s at 4 substeps of 1/60 s, 0.27 J
            // at 16). The trapezoid `Σ ½·(F_n + F_n+1)·d_n`, regrouped by node, books at each
            // substep the force at its start over the mean of the displacements on either
            // side of it, the force taken as the impulse transmitted:
            //   W_d = −F_n·½·(d_n−1 + d_n) = P_n·½·(d_n−1 + d_n)/h,
            // `d_n−1` kept from the previous substep (`SubstepData::driven_before`; none at
            // the first or after a re-analysis: half a rectangle, bounded). It differs from
            // `P·q̇_d` only where the motion's velocity changes (`½·P·(d_n−1 − d_n)/h`): a
            // lift at a steady speed through a stiff joint books what the joint transmits,
            // as before (the law's `F_n` there is not, where the substep does not resolve the
            // DOF). `stored.work` takes `W_d` for `P·q̇_d`, so the joint still gives what the
            // motion gave it and the balance closes as before; the impulses and the motion
            // are untouched. Only where a side is kinematic (the ground of a scene of
            // pendulums is fixed: nothing here); one at rest gives `d_n = 0` and books the
            // half of its last displacement that the trapezoid still holds.
            let mut end_power = p_rate + p_change;
            let kinematic = |s: usize| {
                sj.bodies[s].is_none() && data.watched_kinematic[data.watched_of[ji][s] as usize]
            };
            if kinematic(0) || kinematic(1) {
                let watched = |s: usize| match sj.bodies[s] {
                    Some(_) => None,
                    None => Some(&data.watched_pose[data.watched_of[ji][s] as usize]),
                };
                let driven = prepare::driven_rates([watched(0), watched(1)], &sj.jac);
                let p_driven = p.dot(&driven);
                let d_now = driven * h;
                let (next, d_before) = &mut data.driven_before[ji];
                let mut way = d_now;
                if *next == time {
                    way += *d_before;
                }
                (*next, *d_before) = (time + h, d_now);
                let w_driven = 0.5 * p.dot(&way) / h;
                self.driven_work -= w_driven;
                work_on_bodies += w_driven - p_driven;
                end_power -= p_driven;
            }
            prep.end_power = end_power;
            let prep = &data.prepared[ji];
            let stored = &mut data.stored[ji];
            stored.work = work_on_bodies;
            stored.applied = std::array::from_fn(|i| p[i] * minus_inv_h);
            stored.pending = true;
            // the record itself at a readout substep, else only for the joints whose
            // checks read it now
            let (suspect, breakable) = (prep.suspect, data.breakable[ji]);
            if fold_all || suspect || breakable {
                prepare::fold_stored(j, stored);
            }
            if suspect {
                let size = data.prepared[ji].size;
                let on_unstable = self.settings.on_unstable;
                // its first body that rapier's contacts pushed over the last substep (a
                // foot on the ground), whose opening the run does not stop at: a change of
                // its linear velocity beyond the solve's prediction (a contact's impulse
                // always has one; rapier's integration of a fast spin changes the angular
                // velocity alone)
                let pushed = |s: &Option<u32>| {
                    s.is_some_and(|bi| {
                        let dv = &data.dv_contact[bi as usize];
                        dv[0] != 0.0 || dv[1] != 0.0 || dv[2] != 0.0
                    })
                };
                let contact = (data.any_contact)
                    .then(|| sj.bodies.iter().position(pushed))
                    .flatten()
                    .map(|s| s as u8 + 1);
                let checked = health::check(
                    j,
                    ji,
                    size,
                    (time, h, self.settings.substeps),
                    (on_unstable, contact),
                    &mut self.events,
                );
                if failure.is_ok() {
                    failure = checked;
                }
            }
            if breakable {
                if let Some(cause) = breaking(j) {
                    // removed after the loop (allocates only when a joint breaks)
                    broken.push((j.handle, cause));
                }
            }
        }
        failure
    }

    /// Writes what the store stage left in the substep's data ([`StoredJoint`]) into every
    /// joint's record: the transmitted force and energies of its readout, and its energy
    /// book. Called where a step ends, before each hook of [`KjointSet::step_with`], at the
    /// end of [`KjointSet::apply_substep`], and before the set changes (the topology is
    /// analysed again, a joint is removed); nothing to do after a substep whose store stage
    /// wrote them ([`Readouts::All`]), the one before each of the first three.
    pub(crate) fn fold_stored_results(&mut self) {
        for k in 0..self.tile_joints.len() {
            self.enter_tile(k, false);
            self.fold_tile();
            self.leave_tile(k, false);
        }
    }

    /// [`Self::fold_stored_results`] of the tile in [`Self::data`].
    fn fold_tile(&mut self) {
        let data = &mut self.data;
        if !std::mem::replace(&mut data.unfolded, false) {
            return;
        }
        // where `fold_stored` writes in a record, where the records leave the cache: its
        // energies, booked law energy and transmitted force, and the readout's (a record is
        // 1.6 KB: these are 3 to 5 lines)
        let active = self.active.clone();
        let offsets = prefetch::worth::<Kjoint>(active.len()).then(fold_offsets);
        let base = self.joints[active.clone()].as_ptr();
        let records = self.joints[active].iter_mut().zip(&mut data.stored);
        // last joint first ("Direction of the loops" in the module's documentation)
        for (ji, (j, stored)) in records.enumerate().rev() {
            if let Some(offsets) = offsets {
                prefetch_folded(base.wrapping_add(ji.wrapping_sub(FOLD_AHEAD)), offsets);
            }
            prepare::fold_stored(j, stored);
        }
    }

    /// Removes the joints that broke in this substep, each with its event
    /// (docs/breakable.md §3): after the store loop, never inside it. The set re-analyses
    /// its topology at the next substep.
    fn remove_broken_joints(&mut self, broken: Vec<(KjointHandle, law::BreakCause)>) {
        for (h, cause) in broken {
            self.remove_with_event(h, |energy, last| KjointEventKind::JointBroke {
                cause,
                energy,
                last,
            });
        }
    }
}

/// Whether joint `j` breaks on what it transmitted over the substep just stored
/// (docs/breakable.md §1): `F = |applied[0..3]|`, `M = |applied[3..6]|`, and the energy
/// its law dissipated, `D = damping + friction + stop`.
fn breaking(j: &Kjoint) -> Option<law::BreakCause> {
    let c = j.break_criterion.as_ref()?;
    let a = &j.state.as_ref()?.applied.0;
    let f = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let m = (a[3] * a[3] + a[4] * a[4] + a[5] * a[5]).sqrt();
    let e = &j.law.energy;
    c.check(f, m, e.damping + e.friction + e.stop)
}

/// [`SubstepData::driven_before`] saved with its NaN ("none yet") as nothing: JSON has no
/// NaN (`serde_json` wrote `null`, and refused it when read back).
#[cfg(feature = "serde-serialize")]
mod nan_as_none {
    use nalgebra::Vector6;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &[(f64, Vector6<f64>)], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|(t, d)| ((!t.is_nan()).then_some(*t), d)))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Vec<(f64, Vector6<f64>)>, D::Error> {
        let v = Vec::<(Option<f64>, Vector6<f64>)>::deserialize(d)?;
        Ok(v.into_iter()
            .map(|(t, d)| (t.unwrap_or(f64::NAN), d))
            .collect())
    }
}
