//! Sleeping: a jointed island at rest is put to sleep as a whole, and woken as a whole.
//!
//! rapier's island manager does not see KJOINT2 joints, and the set writes the velocities
//! of the bodies it holds at every substep (waking them), so rapier alone would either keep
//! every jointed body awake or put the bodies of one mechanism to sleep one by one. The set
//! therefore decides for its own islands (joints linked through dynamic bodies), with
//! rapier's thresholds:
//!
//! * **Rest.** At the end of every [`KjointSet::step`], a body is at rest by rapier's rule
//!   (`RigidBodyActivation`), taken on its velocities: half the speed of its farthest
//!   point, `(|v| + |ω|·r)/2` (`r` its mass properties' `max_extent`), below the linear
//!   threshold times the world's length unit (rapier's default 0.05 m/s), and its angular
//!   speed below π/2 rad/s (below the angular threshold, 0.5 rad/s, for a body without
//!   colliders). An island has been at rest since the last step at which one of its
//!   bodies was not; once that is at least the longest `time_until_sleep` of its bodies
//!   (rapier's default 0.5 s), every body of the island is put to sleep
//!   (`RigidBody::sleep`, which zeroes its velocities), with the free bodies it reaches
//!   through contacts and rapier's joints that rapier finds eligible to sleep, unless it
//!   reaches an awake body that is not (rapier would go on simulating it, flagged asleep,
//!   with its joints left out).
//! * **Never.** An island does not sleep when one of its bodies cannot
//!   (`can_sleep(false)`: negative thresholds; the URDF, MJCF and scene loaders build their
//!   bodies so unless told), one of its joints has a sensor (a sensor can lock it at any
//!   time), or one of its joints holds a kinematic body (a prescribed motion drives it).
//! * **Asleep.** A joint whose dynamic bodies all sleep is left out of the substep's stages
//!   ([`super::tiles::tile_joints`]: a short run of asleep joints between awake ones is
//!   stepped within their tile, its bodies as fixed ones, where a tile of its own would
//!   cost more); its readout and energies keep their values. The set checks the asleep
//!   islands' bodies, and the bodies under their joints that are not dynamic (their type
//!   and pose), at the first substep of every step, and rapier's active set at the others.
//! * **Woken.** When rapier wakes one body of an asleep island (a contact, the user's
//!   `wake_up`, `set_linvel(…, true)`, a force), one of its bodies moves, a body under one
//!   of its joints is removed, switched or moved, or a joint is inserted, removed or
//!   changed at one of its bodies, the next substep wakes every body of the island
//!   (`RigidBody::wake_up(true)`) and steps its joints again; its rest starts over.
//!
//! The decision is taken per island of the set's last analysis (once per topology change),
//! so that a step costs one read of each body's velocities and thresholds where an island
//! may sleep, and nothing where none may (no island whose bodies can all sleep). Falling
//! asleep and waking change the topology, but give no start notices again.

use super::joint::Kjoint;
use super::joint_set::KjointSet;
use super::substep::is_dynamic;
use crate::rapier::dynamics::{RigidBody, RigidBodyHandle, RigidBodySet};
use crate::rapier::math::Real;
use crate::rapier::pipeline::PhysicsWorld;

/// Whether the set steps the body as dynamic: dynamic, enabled and not asleep.
pub(super) fn is_awake_dynamic(b: &RigidBody) -> bool {
    is_dynamic(b) && !b.is_sleeping()
}

/// The islands of a tile (joints linked through its solver bodies) and what the sleep
/// stage needs of them, analysed with the tile's topology.
#[derive(Debug, Default, Clone)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct Islands {
    /// Island of each solver body of the tile.
    of_body: Vec<u32>,
    /// Per island: whether it may sleep at all (module documentation, "Never").
    may: Vec<bool>,
    /// Per island: the longest `time_until_sleep` of its bodies \[s\].
    until: Vec<f64>,
    /// Per island, written by the sleep stage: a body not at rest at this step.
    moving: Vec<bool>,
    /// Per island: the set's time since which every body has been at rest \[s\] (from its
    /// joints' [`Kjoint::rest_since`] at the analysis, written back into them at the next
    /// by [`fold_rest`]).
    since: Vec<f64>,
    /// Whether any island of the tile may sleep (else the sleep stage skips the tile).
    any: bool,
}

impl Islands {
    /// The island of the tile's solver body `slot`.
    pub(super) fn of(&self, slot: usize) -> usize {
        self.of_body[slot] as usize
    }

    /// The number of islands of the tile.
    pub(super) fn count(&self) -> usize {
        self.may.len()
    }

    /// The islands of the joints `joints` of a tile whose sides are `sides` (solver body
    /// slots, `None` where not dynamic), `handles` its solver bodies and `watched` /
    /// `watched_of` its other bodies.
    pub(super) fn analyse(
        joints: &[Kjoint],
        sides: &[[Option<u32>; 2]],
        handles: &[RigidBodyHandle],
        watched: &[RigidBodyHandle],
        watched_of: &[[u32; 2]],
        bodies: &RigidBodySet,
    ) -> Islands {
        let nb = handles.len();
        // compact island ids, in the order of their first body
        let roots = crate::dynamics::solve::topology::body_roots(nb, sides);
        let mut id = vec![u32::MAX; nb];
        let mut of_body = Vec::with_capacity(nb);
        let mut count = 0u32;
        for r in roots {
            if id[r as usize] == u32::MAX {
                id[r as usize] = count;
                count += 1;
            }
            of_body.push(id[r as usize]);
        }
        let n = count as usize;
        let mut since = vec![f64::NEG_INFINITY; n];
        let mut may = vec![true; n];
        let mut until = vec![0.0f64; n];
        for (slot, hb) in handles.iter().enumerate() {
            let i = of_body[slot] as usize;
            match bodies.get(*hb) {
                Some(b) => {
                    let a = b.activation();
                    if a.normalized_linear_threshold < 0.0 || a.angular_threshold < 0.0 {
                        may[i] = false;
                    }
                    until[i] = until[i].max(a.time_until_sleep as f64);
                }
                None => may[i] = false,
            }
        }
        for ((j, s), w) in joints.iter().zip(sides).zip(watched_of) {
            let Some(slot) = s.iter().flatten().next() else {
                continue;
            };
            let i = of_body[*slot as usize] as usize;
            since[i] = since[i].max(j.rest_since);
            let kinematic = (0..2).any(|side| {
                s[side].is_none()
                    && watched
                        .get(w[side] as usize)
                        .and_then(|hb| bodies.get(*hb))
                        .is_some_and(|b| b.is_kinematic())
            });
            if kinematic || j.property.sensor.is_some() {
                may[i] = false;
            }
        }
        Islands {
            of_body,
            any: may.iter().any(|m| *m),
            may,
            until,
            moving: vec![false; n],
            since,
        }
    }
}

/// Writes the rest of each island of a tile into its joints `joints` (the tile's, with
/// their `sides`) and leaves the tile without islands (the stage skips it until the next
/// analysis): a joint keeps the later of its own ([`KjointSet::get_mut`] restarts it) and
/// its island's.
fn fold_rest_of(isl: &mut Islands, joints: &mut [Kjoint], sides: &[[Option<u32>; 2]]) {
    if isl.since.is_empty() {
        return;
    }
    for (j, s) in joints.iter_mut().zip(sides) {
        if let Some(slot) = s.iter().flatten().next() {
            let since = isl.since[isl.of_body[*slot as usize] as usize];
            j.rest_since = j.rest_since.max(since);
        }
    }
    *isl = Islands::default();
}

/// Whether a body is at rest by rapier's rule (`RigidBodyActivation::update_energy`), on
/// its velocities rather than its displacement over the step: half the speed of its
/// farthest point, `(|v| + |ω|·r)/2` (`r` its mass properties' `max_extent`), below the
/// linear threshold times the length unit, and its angular speed below π/2 (or, for a body
/// without colliders, `r` = 0, below the angular threshold); never for a body that cannot
/// sleep (a negative threshold).
fn at_rest(b: &RigidBody, length_unit: f64) -> bool {
    let a = b.activation();
    let (lin, ang) = (
        a.normalized_linear_threshold as f64,
        a.angular_threshold as f64,
    );
    let r = b.mass_properties().max_extent() as f64;
    let (v, w) = (b.linvel().length() as f64, b.angvel().length() as f64);
    let angular = if r > 0.0 {
        w < std::f64::consts::FRAC_PI_2
    } else {
        w < ang
    };
    // rapier: `drift·0.5 < threshold·dt`, the drift the farthest point's displacement over
    // the step
    lin >= 0.0 && ang >= 0.0 && angular && 0.5 * (v + w * r) < lin * length_unit
}

/// A body the set may count as asleep: dynamic, flagged asleep and not moving (a body put
/// to sleep that rapier still simulates, its island touching an awake body, moves).
fn sleeping(b: &RigidBody) -> bool {
    is_dynamic(b) && b.is_sleeping() && !b.is_moving()
}

/// A body that is not dynamic under an asleep joint, as it was when the island fell asleep:
/// its type and pose (a change wakes the island).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(super) struct Anchor {
    handle: RigidBodyHandle,
    body_type: crate::rapier::dynamics::RigidBodyType,
    pose: crate::rapier::math::Pose,
    /// (disabled, the body takes its joints out of the stages)
    enabled: bool,
}

impl Anchor {
    fn of(handle: RigidBodyHandle, b: &RigidBody) -> Anchor {
        Anchor {
            handle,
            body_type: b.body_type(),
            pose: *b.position(),
            enabled: b.is_enabled(),
        }
    }

    /// Whether the body is still there, of the same type, where it was, enabled.
    fn unchanged(&self, bodies: &RigidBodySet) -> bool {
        bodies
            .get(self.handle)
            .is_some_and(|b| Anchor::of(self.handle, b) == *self)
    }
}

/// The asleep islands' bodies, as the last analysis left them.
#[derive(Debug, Clone, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct Asleep {
    /// Their sleeping bodies.
    bodies: Vec<RigidBodyHandle>,
    /// The bodies of their joints that are not dynamic.
    anchors: Vec<Anchor>,
    /// [`Self::bodies`] as bits by handle index, for [`KjointSet::woken_in_step`].
    bits: Vec<u64>,
}

impl Asleep {
    fn is_empty(&self) -> bool {
        self.bodies.is_empty() && self.anchors.is_empty()
    }

    /// Whether every sleeping body still sleeps without moving, and every anchor is
    /// unchanged (else the set analyses its topology again, which wakes the island).
    pub(super) fn unchanged(&self, bodies: &RigidBodySet) -> bool {
        self.still_asleep(bodies) && self.anchors.iter().all(|a| a.unchanged(bodies))
    }

    /// Whether every sleeping body still sleeps without moving.
    fn still_asleep(&self, bodies: &RigidBodySet) -> bool {
        (self.bodies.iter()).all(|hb| bodies.get(*hb).is_some_and(sleeping))
    }

    /// Whether `hb` is one of the sleeping bodies.
    pub(super) fn holds(&self, hb: RigidBodyHandle) -> bool {
        self.marked(hb)
    }

    fn marked(&self, hb: RigidBodyHandle) -> bool {
        let i = hb.into_raw_parts().0 as usize;
        (self.bits.get(i / 64)).is_some_and(|w| w & (1 << (i % 64)) != 0)
    }
}

/// The bodies as bits by their handle's index.
fn bits_of(handles: &[RigidBodyHandle]) -> Vec<u64> {
    let mut bits = Vec::new();
    for hb in handles {
        let i = hb.into_raw_parts().0 as usize;
        if bits.len() <= i / 64 {
            bits.resize(i / 64 + 1, 0);
        }
        bits[i / 64] |= 1 << (i % 64);
    }
    bits
}

/// Before an analysis: wakes every island that must wake and restarts its rest at `now`,
/// then returns, for each joint, whether it is asleep (its island has sleeping bodies and
/// no awake one), and leaves in `asleep` the bodies of the asleep islands. An island wakes
/// (every body `wake_up(true)`) where one of its bodies:
///
/// * is in `wake` (a joint inserted, removed or changed at it),
/// * was asleep (in `asleep`) and is awake now or moves (rapier, the user),
/// * is flagged asleep but moves (rapier simulates it: its island touches an awake body),
/// * is awake beside sleeping ones (a mixed island),
///
/// or where one of its joints holds an anchor of `asleep` that changed (removed, switched,
/// moved).
pub(super) fn settle(
    joints: &mut [Kjoint],
    bodies: &mut RigidBodySet,
    wake: &mut Vec<RigidBodyHandle>,
    asleep: &mut Asleep,
    now: f64,
) -> Vec<bool> {
    use std::collections::HashSet;
    let n = joints.len();
    // the bodies whose island restarts (of `wake`, the dynamic ones: a joint inserted at
    // the ground restarts no other island held by the ground)
    let mut restart = HashSet::new();
    // (each woken here too, in the order given: a body whose last joint was removed has no
    // island left)
    for hb in wake.drain(..) {
        if bodies.get(hb).is_some_and(is_dynamic) && restart.insert(hb) && bodies[hb].is_sleeping()
        {
            bodies[hb].wake_up(true);
        }
    }
    for hb in &asleep.bodies {
        if !bodies.get(*hb).is_some_and(sleeping) {
            restart.insert(*hb);
        }
    }
    for a in &asleep.anchors {
        if !a.unchanged(bodies) {
            restart.insert(a.handle);
        }
    }
    *asleep = Asleep::default();
    let mut any_sleeping = false;
    for j in joints.iter() {
        for hb in [j.body1, j.body2] {
            match bodies.get(hb) {
                Some(b) if is_dynamic(b) && b.is_sleeping() && b.is_moving() => {
                    restart.insert(hb);
                }
                Some(b) if sleeping(b) => any_sleeping = true,
                _ => {}
            }
        }
    }
    let restarts = |j: &Kjoint| restart.contains(&j.body1) || restart.contains(&j.body2);
    if !any_sleeping && !joints.iter().any(restarts) {
        return vec![false; n];
    }
    // the islands of joints linked through dynamic bodies, asleep or not
    let island = super::tiles::joint_islands(joints, bodies, is_dynamic);
    // per island root: an awake body, a sleeping one, a reason to restart
    let mut awake = vec![false; n];
    let mut slept = vec![false; n];
    let mut again = vec![false; n];
    for (k, j) in joints.iter().enumerate() {
        let r = island[k];
        again[r] |= restarts(j);
        for hb in [j.body1, j.body2] {
            match bodies.get(hb) {
                Some(b) if sleeping(b) => slept[r] = true,
                Some(b) if is_dynamic(b) => awake[r] = true,
                _ => {}
            }
        }
    }
    let mut flags = vec![false; n];
    for (k, j) in joints.iter_mut().enumerate() {
        let r = island[k];
        if again[r] || (awake[r] && slept[r]) {
            for hb in [j.body1, j.body2] {
                if bodies
                    .get(hb)
                    .is_some_and(|b| is_dynamic(b) && b.is_sleeping())
                {
                    bodies[hb].wake_up(true);
                }
            }
            j.rest_since = now;
        } else if slept[r] {
            flags[k] = true;
            for hb in [j.body1, j.body2] {
                let Some(b) = bodies.get(hb) else { continue };
                if sleeping(b) {
                    if !asleep.bodies.contains(&hb) {
                        asleep.bodies.push(hb);
                    }
                } else if !is_dynamic(b) && !asleep.anchors.iter().any(|a| a.handle == hb) {
                    asleep.anchors.push(Anchor::of(hb, b));
                }
            }
        }
    }
    asleep.bits = bits_of(&asleep.bodies);
    flags
}

/// Which check of the asleep bodies the topology stage makes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(super) enum AsleepCheck {
    /// Every asleep body and anchor, by its state ([`Asleep::unchanged`]): at the first
    /// substep of a step (the user's changes between steps), and in a set stepped through
    /// `apply_substep`.
    #[default]
    Every,
    /// None: [`KjointSet::woken_in_step`] looked for them in rapier's active set.
    Done,
}

impl KjointSet {
    /// At the substeps of a step after its first: whether rapier has woken one of the asleep
    /// bodies in its last step (a contact), read from its active set (the bodies it
    /// simulates), or from the bodies themselves where those are fewer. The set's topology
    /// is then analysed again (which wakes the island).
    pub(super) fn woken_in_step(
        &mut self,
        bodies: &RigidBodySet,
        islands: &crate::rapier::dynamics::IslandManager,
    ) {
        if self.asleep.is_empty() {
            self.asleep_check = AsleepCheck::Every;
            return;
        }
        let asleep = &self.asleep;
        let woken = if islands.num_active_bodies() < asleep.bodies.len() {
            // (a body the set has just put to sleep stays in the active set until rapier's
            // next step; it counts once awake or moving)
            islands
                .active_bodies()
                .any(|hb| asleep.marked(hb) && !bodies.get(hb).is_some_and(sleeping))
        } else {
            !asleep.still_asleep(bodies)
        };
        if woken {
            self.data.valid = false;
        }
        self.asleep_check = AsleepCheck::Done;
    }

    /// Before a substep of a step that may be the first after the user's changes (the first
    /// substep, or every one with a hook): an awake island whose body the user woke with
    /// `wake_up(true)` (itself, or through `add_force(…, true)`, `set_linvel(…, true)`, …)
    /// starts its rest over, as rapier's timer of that body does: a constant load added
    /// with a wake every frame keeps it awake, as it keeps a body without joints awake.
    /// The wake is read from rapier's timer (`time_since_can_sleep`), 0 after a strong wake:
    /// the set's own velocity writes reset it too, but rapier's step after them adds its
    /// substep again for a body at rest (a moving body reads 0 as well, and its island's
    /// rest restarts anyway).
    pub(super) fn rest_restarted_by_wakes(&mut self, bodies: &RigidBodySet) {
        let now = self.time;
        for data in std::iter::once(&mut self.data).chain(&mut self.tiles) {
            let isl = &mut data.islands;
            if !isl.any {
                continue;
            }
            for (slot, hb) in data.handles.iter().enumerate() {
                if bodies
                    .get(*hb)
                    .is_some_and(|b| b.activation().time_since_can_sleep == 0.0)
                {
                    isl.since[isl.of_body[slot] as usize] = now;
                }
            }
        }
    }

    /// After rapier's step: the timer of an island's body that rapier's step reset
    /// (`time_since_can_sleep` = 0) is set to the smallest positive value, so that
    /// [`Self::rest_restarted_by_wakes`] reads as a wake only what happened after rapier's
    /// step (the user's `wake_up(true)`, a force added with a wake). rapier's step resets it
    /// for its own reasons too, a contact between two jointed islands touching and parting
    /// from substep to substep among them: two ragdolls at rest across each other
    /// (0.4 mm/s) never slept, their rest started over at every step. Whether a body moves
    /// is the sleep stage's own test, on its velocities. rapier's own decisions only read
    /// whether the timer reached `time_until_sleep`, which this does not change. Called
    /// after the substeps whose timers are read next: a step's last, or every one with a
    /// hook (a read of each body of the islands that may sleep, as the sleep stage's).
    pub(super) fn keep_rest_through_rapier(&mut self, bodies: &mut RigidBodySet) {
        for data in std::iter::once(&self.data).chain(&self.tiles) {
            if !data.islands.any {
                continue;
            }
            for hb in &data.handles {
                // read first: `get_mut` marks the body as changed for rapier's next step
                let reset = (bodies.get(*hb)).is_some_and(|b| {
                    b.activation().time_since_can_sleep == 0.0 && !b.is_sleeping()
                });
                if reset {
                    bodies[*hb].activation_mut().time_since_can_sleep = Real::MIN_POSITIVE;
                }
            }
        }
    }

    /// The islands' rest into the joints' records ([`Kjoint::rest_since`]), while the
    /// tiles still match the joints: before a joint leaves the set, and before the
    /// topology is analysed again.
    pub(super) fn fold_rest(&mut self) {
        let tiles = std::iter::once(&mut self.data).chain(&mut self.tiles);
        for (data, range) in tiles.zip(&self.tile_joints) {
            if let Some(joints) = self.joints.get_mut(range.clone()) {
                fold_rest_of(&mut data.islands, joints, &data.sides);
            }
        }
    }

    /// The sleep stage, at the end of a step (module documentation): the rest of every
    /// island that may sleep, and the islands at rest long enough put to sleep (the set
    /// analyses its topology again at the next substep, leaving their joints out).
    ///
    /// rapier sleeps an island of its own (bodies linked by contacts and by its joints) only
    /// as a whole: a body put to sleep with an awake neighbour would go on being simulated,
    /// flagged asleep, with its KJOINT2 joints left out. So an island going to sleep takes
    /// along the free bodies it reaches through touching contacts and rapier's joints that
    /// rapier finds eligible to sleep (a box resting on a jointed tray, whose rapier timer
    /// the set's velocity writes keep resetting), and stays awake where it reaches an awake
    /// body that is not: moving, unable to sleep, of an island of the set that stays awake;
    /// it searches through the kinematic bodies rapier finds eligible (rapier's islands hold
    /// them), and stays awake at the others.
    pub(super) fn stage_sleep(&mut self, world: &mut PhysicsWorld) {
        use std::collections::HashSet;
        let now = self.time;
        let length_unit = world.integration_parameters.length_unit as f64;
        let PhysicsWorld {
            bodies,
            colliders,
            narrow_phase,
            impulse_joints,
            multibody_joints,
            ..
        } = world;
        // the bodies of the islands at rest long enough, with their island (its tile and
        // its index there)
        let mut going = Vec::new();
        let tiles = std::iter::once(&mut self.data).chain(&mut self.tiles);
        for (tile, data) in tiles.enumerate() {
            let isl = &mut data.islands;
            if !isl.any {
                continue;
            }
            isl.moving.fill(false);
            for (slot, hb) in data.handles.iter().enumerate() {
                if !bodies.get(*hb).is_some_and(|b| at_rest(b, length_unit)) {
                    isl.moving[isl.of_body[slot] as usize] = true;
                }
            }
            // from here on, `moving[i]`: island i stays awake
            for i in 0..isl.since.len() {
                if isl.moving[i] {
                    isl.since[i] = now;
                } else {
                    isl.moving[i] = !(isl.may[i] && now - isl.since[i] >= isl.until[i]);
                }
            }
            for (slot, hb) in data.handles.iter().enumerate() {
                let i = isl.of_body[slot];
                if !isl.moving[i as usize] {
                    going.push((*hb, (tile, i)));
                }
            }
        }
        if going.is_empty() {
            return;
        }
        // the neighbours of a body through rapier: touching contacts, its joints
        let neighbours = |hb: RigidBodyHandle| -> Vec<RigidBodyHandle> {
            let mut out = Vec::new();
            for c in bodies[hb].colliders() {
                for pair in narrow_phase.contact_pairs_with(*c) {
                    if pair.has_any_active_contact() {
                        let other = if pair.collider1 == *c {
                            pair.collider2
                        } else {
                            pair.collider1
                        };
                        out.extend(colliders.get(other).and_then(|o| o.parent()));
                    }
                }
            }
            let joints = impulse_joints.attached_joints(hb);
            out.extend(joints.map(|(b1, b2, ..)| if b1 == hb { b2 } else { b1 }));
            out.extend(multibody_joints.attached_bodies(hb));
            out
        };
        let mut islands: Vec<(usize, u32)> = going.iter().map(|(_, key)| *key).collect();
        islands.sort_unstable();
        islands.dedup();
        // an island kept awake keeps awake those that reach it: until nothing changes
        let mut awake: HashSet<(usize, u32)> = HashSet::new();
        let mut along: Vec<RigidBodyHandle> = Vec::new();
        loop {
            let asleep_now: HashSet<RigidBodyHandle> = (going.iter())
                .filter(|(_, key)| !awake.contains(key))
                .map(|(hb, _)| *hb)
                .collect();
            let staying: HashSet<RigidBodyHandle> = (std::iter::once(&self.data))
                .chain(&self.tiles)
                .flat_map(|d| d.handles.iter().copied())
                .filter(|hb| !asleep_now.contains(hb))
                .collect();
            along.clear();
            let mut changed = false;
            for key in &islands {
                if awake.contains(key) {
                    continue;
                }
                let mut queue: Vec<RigidBodyHandle> = (going.iter())
                    .filter(|(_, k)| k == key)
                    .map(|(hb, _)| *hb)
                    .collect();
                let mut seen: HashSet<RigidBodyHandle> = queue.iter().copied().collect();
                let mut taken = Vec::new();
                let mut reaches_awake = false;
                while let Some(b) = queue.pop() {
                    for ob in neighbours(b) {
                        if !seen.insert(ob) || asleep_now.contains(&ob) {
                            continue;
                        }
                        let Some(o) = bodies.get(ob) else { continue };
                        if staying.contains(&ob) || (o.is_sleeping() && o.is_moving()) {
                            // (flagged asleep and moving: rapier simulates it)
                            reaches_awake = true;
                        } else if o.is_kinematic() && o.is_enabled() {
                            // rapier's islands hold kinematic bodies too: searched through
                            // where rapier finds it eligible (still for `time_until_sleep`)
                            if o.activation().is_eligible_for_sleep() {
                                queue.push(ob);
                            } else {
                                reaches_awake = true;
                            }
                        } else if is_dynamic(o) && !o.is_sleeping() {
                            if o.activation().is_eligible_for_sleep() {
                                taken.push(ob);
                                queue.push(ob);
                            } else {
                                reaches_awake = true;
                            }
                        }
                    }
                }
                if reaches_awake {
                    awake.insert(*key);
                    changed = true;
                } else {
                    along.extend(taken);
                }
            }
            if !changed {
                break;
            }
        }
        // the rest of an island put to sleep starts over: woken before the set has seen it
        // asleep (between this step and the next, `wake_up`, a push), it has to be at rest
        // for its `time_until_sleep` again, as rapier's `wake_up(true)` restarts a body's
        // timer (it fell straight back asleep at the end of the next step)
        for key in islands.iter().filter(|key| !awake.contains(key)) {
            let (tile, i) = *key;
            let data = match tile {
                0 => &mut self.data,
                k => &mut self.tiles[k - 1],
            };
            data.islands.since[i as usize] = now;
        }
        let mut slept = false;
        let mut done: HashSet<RigidBodyHandle> = HashSet::new();
        let bodies_going = (going.iter())
            .filter(|(_, key)| !awake.contains(key))
            .map(|(hb, _)| *hb);
        for hb in bodies_going.chain(along) {
            if done.insert(hb) {
                bodies[hb].sleep();
                slept = true;
            }
        }
        if slept {
            self.data.valid = false;
        }
    }
}
