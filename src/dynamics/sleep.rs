//! Sleeping: a jointed island at rest is put to sleep as a whole, and woken as a whole.
//!
//! rapier's island manager does not see KJOINT2 joints, and the set writes the velocities
//! of the bodies it holds at every substep (waking them), so rapier alone would either keep
//! every jointed body awake or put the bodies of one mechanism to sleep one by one. The set
//! therefore decides for its own islands (joints linked through dynamic bodies), with
//! rapier's thresholds:
//!
//! * **Rest.** At the end of every [`KjointSet::step`], a body is at rest when its speed
//!   is below its activation's linear threshold times the world's length unit and its
//!   angular speed below its angular threshold (`RigidBodyActivation`; rapier's defaults
//!   0.05 m/s and 0.5 rad/s). An island has been at rest since the last step at which one
//!   of its bodies was not; once that is at least the longest `time_until_sleep` of its
//!   bodies (rapier's default 0.5 s), every body of the island is put to sleep
//!   (`RigidBody::sleep`, which zeroes its velocities).
//! * **Never.** An island does not sleep when one of its bodies cannot
//!   (`can_sleep(false)`: negative thresholds; the URDF, MJCF and scene loaders build their
//!   bodies so), one of its joints has a sensor (a sensor can lock it at any time), or one
//!   of its joints holds a kinematic body (a prescribed motion drives it).
//! * **Asleep.** A joint whose dynamic bodies all sleep is left out of the substep's stages
//!   (it costs nothing; its readout and energies keep their last values). The set checks
//!   at every substep that those bodies still sleep and have not moved.
//! * **Woken.** When rapier wakes one body of an asleep island (a contact, the user's
//!   `wake_up`, `set_linvel(…, true)`, a force), or a joint is inserted, removed or changed
//!   at one of its bodies, the next substep wakes every body of the island
//!   (`RigidBody::wake_up(true)`) and steps its joints again; its rest starts over.
//!
//! The decision is taken per island of the set's last analysis (once per topology change),
//! so that a step costs one read of each body's velocities and thresholds where an island
//! may sleep, and nothing where none may (no island whose bodies can all sleep).

use super::joint::Kjoint;
use super::joint_set::KjointSet;
use super::substep::is_dynamic;
use crate::rapier::dynamics::{RigidBody, RigidBodyHandle, RigidBodySet};

/// Whether the set steps the body as dynamic: dynamic, enabled and not asleep.
pub(super) fn is_awake_dynamic(b: &RigidBody) -> bool {
    is_dynamic(b) && !b.is_sleeping()
}

/// The islands of a tile (joints linked through its solver bodies) and what the sleep
/// stage needs of them, analysed with the tile's topology.
#[derive(Debug, Default, Clone)]
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
        let mut parent: Vec<u32> = (0..nb as u32).collect();
        fn root(parent: &mut [u32], mut i: u32) -> u32 {
            while parent[i as usize] != i {
                parent[i as usize] = parent[parent[i as usize] as usize];
                i = parent[i as usize];
            }
            i
        }
        for s in sides {
            if let [Some(a), Some(b)] = *s {
                let (a, b) = (root(&mut parent, a), root(&mut parent, b));
                if a != b {
                    parent[a.max(b) as usize] = a.min(b);
                }
            }
        }
        // compact island ids, in the order of their first body
        let mut id = vec![u32::MAX; nb];
        let mut of_body = Vec::with_capacity(nb);
        let mut count = 0u32;
        for b in 0..nb as u32 {
            let r = root(&mut parent, b) as usize;
            if id[r] == u32::MAX {
                id[r] = count;
                count += 1;
            }
            of_body.push(id[r]);
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

/// Whether a body is at rest by its activation's thresholds (module documentation,
/// "Rest"): never for a body that cannot sleep.
fn at_rest(b: &RigidBody, length_unit: f64) -> bool {
    let a = b.activation();
    let (lin, ang) = (
        a.normalized_linear_threshold as f64,
        a.angular_threshold as f64,
    );
    lin >= 0.0
        && ang >= 0.0
        && (b.linvel().length() as f64) < lin * length_unit
        && (b.angvel().length() as f64) < ang
}

/// Before an analysis: wakes the bodies in `wake` (a joint inserted, removed or changed),
/// then every sleeping body of an island (joints linked through dynamic bodies, asleep or
/// not) that has an awake one, restarting the rest of that island's joints at `now`.
/// Returns, for each joint, whether it is asleep (no awake dynamic body, a sleeping one),
/// and leaves the sleeping bodies of the asleep islands in `asleep`.
pub(super) fn settle(
    joints: &mut [Kjoint],
    bodies: &mut RigidBodySet,
    wake: &mut Vec<RigidBodyHandle>,
    asleep: &mut Vec<RigidBodyHandle>,
    now: f64,
) -> Vec<bool> {
    for hb in wake.drain(..) {
        if bodies
            .get(hb)
            .is_some_and(|b| is_dynamic(b) && b.is_sleeping())
        {
            bodies[hb].wake_up(true);
        }
    }
    asleep.clear();
    let n = joints.len();
    let sleeping = |b: &RigidBody| is_dynamic(b) && b.is_sleeping();
    let any_sleeping = joints.iter().any(|j| {
        [j.body1, j.body2]
            .iter()
            .any(|hb| bodies.get(*hb).is_some_and(sleeping))
    });
    if !any_sleeping {
        return vec![false; n];
    }
    // union–find over the joints: two joints of one dynamic body (asleep or not) are one
    // island
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut first_of_body = std::collections::HashMap::new();
    for (k, j) in joints.iter().enumerate() {
        for hb in [j.body1, j.body2] {
            if !bodies.get(hb).is_some_and(is_dynamic) {
                continue;
            }
            let other = *first_of_body.entry(hb).or_insert(k);
            let (a, b) = (root(&mut parent, k), root(&mut parent, other));
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    // per island root: an awake body, a sleeping one
    let mut awake = vec![false; n];
    let mut slept = vec![false; n];
    for (k, j) in joints.iter().enumerate() {
        let r = root(&mut parent, k);
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
        let r = root(&mut parent, k);
        if !slept[r] {
            continue;
        }
        if awake[r] {
            for hb in [j.body1, j.body2] {
                if bodies.get(hb).is_some_and(sleeping) {
                    bodies[hb].wake_up(true);
                }
            }
            j.rest_since = now;
        } else {
            flags[k] = true;
            for hb in [j.body1, j.body2] {
                if bodies.get(hb).is_some_and(sleeping) && !asleep.contains(&hb) {
                    asleep.push(hb);
                }
            }
        }
    }
    flags
}

/// Whether every body of the asleep islands still exists, is dynamic, sleeps and has not
/// moved (else the set analyses its topology again, which wakes the island).
pub(super) fn asleep_unchanged(asleep: &[RigidBodyHandle], bodies: &RigidBodySet) -> bool {
    asleep.iter().all(|hb| {
        bodies
            .get(*hb)
            .is_some_and(|b| is_dynamic(b) && b.is_sleeping() && !b.is_moving())
    })
}

/// The asleep bodies as bits by their handle's index, for [`KjointSet::woken_in_step`].
pub(super) fn asleep_bits(asleep: &[RigidBodyHandle]) -> Vec<u64> {
    let mut bits = Vec::new();
    for hb in asleep {
        let i = hb.into_raw_parts().0 as usize;
        if bits.len() <= i / 64 {
            bits.resize(i / 64 + 1, 0);
        }
        bits[i / 64] |= 1 << (i % 64);
    }
    bits
}

/// Which check of the asleep bodies the topology stage makes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) enum AsleepCheck {
    /// Every asleep body, by its state ([`asleep_unchanged`]): at the first substep of a
    /// step (the user's changes between steps), and in a set stepped through
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
        let woken = if islands.num_active_bodies() < self.asleep.len() {
            let bits = &self.asleep_bits;
            // (a body the set has just put to sleep stays in the active set until rapier's
            // next step; it counts once awake or moving)
            islands.active_bodies().any(|hb| {
                let i = hb.into_raw_parts().0 as usize;
                bits.get(i / 64).is_some_and(|w| w & (1 << (i % 64)) != 0)
                    && !asleep_unchanged(&[hb], bodies)
            })
        } else {
            !asleep_unchanged(&self.asleep, bodies)
        };
        if woken {
            self.data.valid = false;
        }
        self.asleep_check = AsleepCheck::Done;
    }
}

impl KjointSet {
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
    pub(super) fn stage_sleep(&mut self, bodies: &mut RigidBodySet, length_unit: f64) {
        let now = self.time;
        let mut slept = false;
        for data in std::iter::once(&mut self.data).chain(&mut self.tiles) {
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
                if !isl.moving[isl.of_body[slot] as usize] {
                    if let Some(b) = bodies.get_mut(*hb) {
                        b.sleep();
                        slept = true;
                    }
                }
            }
        }
        if slept {
            self.data.valid = false;
        }
    }
}
