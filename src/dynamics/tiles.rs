//! Tiles: a large set of many islands stepped a group of islands at a time.
//!
//! Half of what a substep reads and writes for a joint is its own scratch (the gathered and
//! solver bodies, the geometric loads, the solver blocks, the motions and rotations, the
//! impulses and velocities: [`Scratch`]), written by one stage and read by the next within
//! the substep. Stepped over 10 000 joints at once, each stage's scratch has left the cache
//! before the next stage reads it, and the next substep writes it again from memory. A set
//! of many islands (10 000 pendulums, a crowd of robots) is therefore cut into **tiles**:
//! contiguous runs of joints (in insertion order) that hold whole islands, at least
//! [`TILE_JOINTS`] joints each, each with the topology and persistent arrays of its own
//! [`SubstepData`] and all of them sharing one [`Scratch`], which stays in the cache. Every
//! stage then runs over one tile before the next tile starts.
//!
//! A tile whose topology is the first tile's (a crowd of alike mechanisms, inserted one
//! after the other) borrows the first tile's solver instead of keeping a workspace of its
//! own. The topology stage checks every tile's dynamic bodies before any tile is stepped
//! (what the gather stage checks as it reads them in a set of one tile), so that a body
//! removed or switched is found before any tile has moved.
//!
//! A tile is solved exactly as the whole set was, joint for joint and body for body in the
//! same order: the results are the same bits (tests `tiles_give_the_same_bits`,
//! `alike_tiles_share_one_solver_with_the_same_bits`). What changes is the order of the
//! events of one substep (a tile's start notices and health warnings before the next
//! tile's), and an error inside a substep (a non-finite body or joint, a failed solve) is
//! returned once the tiles before the failing one have been applied. A set of fewer than
//! `2·TILE_JOINTS` joints, or one island as large as a long chain, is one tile and stepped
//! as before. The figures are in docs/performance_log.md ("Tiles").

use super::joint::Kjoint;
use super::solve::{GeometricLoad, SolverBody, SolverJoint, SolverJoints};
use super::substep::{GatheredBody, SubstepData};
use crate::kinematics;
use crate::rapier::dynamics::RigidBodySet;
use nalgebra::Vector6;
use std::ops::Range;

/// Joints a tile holds at least: 1000 joints' scratch is about 2 MB, which the cache keeps
/// (tiles of 250 joints gained as much on 10 000 pendulums, and a tile of many joints
/// costs less per joint in its stages' loop overheads).
pub(crate) const TILE_JOINTS: usize = 1000;

/// The per-substep arrays of a tile: written and read within one substep, rewritten at
/// the next (every element, before anything reads it), so that the tiles share one.
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    bodies: Vec<SolverBody>,
    gathered: Vec<GatheredBody>,
    geo: Vec<GeometricLoad>,
    joints: SolverJoints,
    motion: Vec<kinematics::JointMotion>,
    rotation: Vec<kinematics::Measured>,
    impulses: Vec<Vector6<f64>>,
    velocity: Vec<Vector6<f64>>,
}

impl Clone for Scratch {
    /// A clone fills its own scratch at its first substep.
    fn clone(&self) -> Self {
        Scratch::default()
    }
}

impl Scratch {
    /// Exchanges the scratch arrays of `data` (a tile's, which keeps none between its
    /// substeps) with these, sized to the tile: `bodies` solver bodies, `joints` joints.
    /// Called twice around a tile's stages; allocates only until the largest tile's size
    /// has been reached.
    pub(crate) fn exchange(&mut self, data: &mut SubstepData, bodies: usize, joints: usize) {
        use std::mem::swap;
        swap(&mut self.bodies, &mut data.bodies);
        swap(&mut self.gathered, &mut data.gathered);
        swap(&mut self.geo, &mut data.geo);
        swap(&mut self.joints, &mut data.joints);
        swap(&mut self.motion, &mut data.motion);
        swap(&mut self.rotation, &mut data.rotation);
        swap(&mut self.impulses, &mut data.impulses);
        swap(&mut self.velocity, &mut data.velocity);
        // (the values only fill a grown array: every element is written before it is read)
        data.bodies.resize(bodies, SolverBody::empty());
        data.gathered.resize(bodies, GatheredBody::empty());
        data.geo.resize(bodies, GeometricLoad::NONE);
        data.velocity.resize(bodies, Vector6::zeros());
        data.joints.list.resize(joints, SolverJoint::default());
        data.motion.resize(joints, super::substep::motion_at_rest());
        data.rotation
            .resize(joints, super::substep::rotation_at_rest());
        data.impulses.resize(joints, Vector6::zeros());
    }

    /// Takes the scratch arrays out of a freshly analysed tile (they are this scratch's
    /// from then on).
    pub(crate) fn strip(data: &mut SubstepData) {
        data.bodies = Vec::new();
        data.gathered = Vec::new();
        data.geo = Vec::new();
        data.joints = SolverJoints::default();
        data.motion = Vec::new();
        data.rotation = Vec::new();
        data.impulses = Vec::new();
        data.velocity = Vec::new();
    }
}

/// The island of every joint (joints linked through the bodies `links` accepts, by
/// union–find), as the index of a joint of it (the first).
pub(crate) fn joint_islands(
    joints: &[Kjoint],
    bodies: &RigidBodySet,
    links: impl Fn(&crate::rapier::dynamics::RigidBody) -> bool,
) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..joints.len()).collect();
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
            if !bodies.get(hb).is_some_and(&links) {
                continue;
            }
            let other = *first_of_body.entry(hb).or_insert(k);
            let (a, b) = (root(&mut parent, k), root(&mut parent, other));
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    (0..joints.len()).map(|k| root(&mut parent, k)).collect()
}

/// A run of at least this many asleep joints is left out of the tiles wherever an island
/// ends before it (a shorter one only after a tile of [`ASLEEP_TILE`] joints).
pub(crate) const ASLEEP_RUN: usize = 16;
/// A tile of at least this many joints ends before a run of asleep joints.
pub(crate) const ASLEEP_TILE: usize = 64;

/// The joints of each tile: contiguous ranges of `joints` (in order), each of whole islands
/// (joints linked through awake dynamic bodies) and of at least `min` joints, covering
/// every joint but runs of `asleep` ones between islands ([`super::sleep`]: those of
/// [`ASLEEP_RUN`] joints or more, those that end the set, those after a tile of
/// [`ASLEEP_TILE`] joints; an asleep joint within a tile is stepped with it, its sleeping
/// bodies as fixed ones); one range of every joint when nothing is asleep and fewer than
/// two such tiles can be made.
///
/// The islands by union–find over the awake dynamic bodies; a cut between joints `k − 1`
/// and `k` is allowed where no island has joints on both sides of it (the last joint of
/// every island met so far is before `k`).
pub(crate) fn tile_joints(
    joints: &[Kjoint],
    bodies: &RigidBodySet,
    min: usize,
    asleep: &[bool],
) -> Vec<Range<usize>> {
    let n = joints.len();
    let any_asleep = asleep.iter().any(|a| *a);
    #[allow(clippy::single_range_in_vec_init)] // (one tile of every joint, not the joints)
    let whole = vec![0..n];
    if n == 0 || (!any_asleep && n < 2 * min.max(1)) {
        return whole;
    }
    let island = joint_islands(joints, bodies, super::sleep::is_awake_dynamic);
    // the last joint of each island
    let mut last = vec![0usize; n];
    for (k, r) in island.iter().enumerate() {
        last[*r] = k;
    }
    // the length of the run of asleep joints that starts at each joint
    let mut run = vec![0usize; n + 1];
    for k in (0..n).rev() {
        run[k] = if asleep[k] { run[k + 1] + 1 } else { 0 };
    }
    let mut tiles = Vec::new();
    let (mut start, mut reach) = (None, 0);
    for k in 0..n {
        let s = match start {
            Some(s) => s,
            // between tiles, an asleep joint is left out
            None if asleep[k] => continue,
            None => *start.insert(k),
        };
        reach = reach.max(last[island[k]]);
        // a cut after joint k: every island met so far ends at k or before; made where
        // both sides hold `min` joints, or before a run of asleep joints that is long or
        // ends the set, or follows a tile of some size (else the run is stepped within the
        // tile: a tile costs more than a few joints whose bodies are all fixed)
        let asleep_after = run[k + 1];
        let skip = asleep_after > 0
            && (asleep_after >= ASLEEP_RUN
                || k + 1 + asleep_after == n
                || k + 1 - s >= ASLEEP_TILE);
        if reach == k && (skip || (k + 1 - s >= min && n - (k + 1) >= min)) {
            tiles.push(s..k + 1);
            start = None;
        }
    }
    if let Some(s) = start {
        tiles.push(s..n);
    }
    tiles
}
