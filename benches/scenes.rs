//! Scenes of the solver benchmarks (issue 11, item 7), each built twice on the same bodies:
//!
//! * **KJOINT2** ([`Scene::kjoint`]): a [`PhysicsWorld`] + [`KjointSet`] with KJOINT2 joints
//!   (`Kn` = [`KN`] = 1e12 unless the scene says otherwise, [`SUBSTEPS`] = 4 substeps of a
//!   [`FRAME`] = 1/60 s frame, rapier at 1 solver iteration per substep, the crate's
//!   default);
//! * **rapier** ([`Scene::rapier`]): the same bodies with rapier 0.36 revolute / spherical
//!   impulse joints (`RevoluteJointBuilder`, `SphericalJointBuilder`), `dt` = 1/60 s and
//!   `integration_parameters.num_solver_iterations = 4`, one `world.step()` per frame; or,
//!   for the contact scene, the same bodies *without* joints stepped like the KJOINT2 world
//!   (4 × `world.step()` of 1/240 s per frame, 1 solver iteration), see [`Reference`].
//!
//! A frame is [`KjointWorld::frame`] / [`RapierWorld::frame`]: what the benchmarks time.
//!
//! Every scene is a plain description ([`Scene`]: bodies, then joints in insertion order) so
//! that tests can build it too, without criterion:
//!
//! ```ignore
//! #[path = "../benches/scenes.rs"]
//! mod scenes;
//! let mut k = scenes::four_bar(false).kjoint();
//! k.frame();
//! ```
//!
//! Body 0 of every scene is a fixed body at the origin (the "world"); joints to it hold the
//! structure up. Gravity is 9.81 m/s² along −y. Rods are slender: mass `m` and length `L`
//! on the local x axis, principal inertia `(0.1·I, I, I)` with `I = m·L²/12`, no collider
//! (so no contacts) except in [`capsules_on_ground`]. No body sleeps but in
//! [`resting_pendulums`].
//!
//! | scene | bodies | joints |
//! |---|---|---|
//! | [`chain`]`(n)` | n rods 0.1 m, 0.1 kg, end to end | n revolute (z), the first to the world |
//! | [`pendulums`]`(n)` | n rods 0.1 m, 0.1 kg on a grid | n revolute (z), each to the world |
//! | [`resting_pendulums`]`(n)` | the same hanging at rest, asleep | the same |
//! | [`tree`]`(depth, order)` | 2^depth − 1 rods 0.1 m, 0.1 kg, a complete binary tree | as many revolute (z) |
//! | [`hub`]`(n)` | a 3 kg ball + n rods 0.1 m, 0.1 kg on it | n + 1 spherical |
//! | [`capsules_on_ground`]`(g)` | 3·g capsules of 1 kg + a ground box | 2·g revolute (z) |
//! | [`four_bar`]`(grounded)` | 4 links (3 when the world is the fourth) | 4 revolute (z), a cycle |
//!
//! The URDF arm is loaded from a file rather than described: [`urdf_arm_kjoint`],
//! [`urdf_arm_rapier`]. [`peak_memory_run`] builds and steps a chain for the peak-memory
//! measurement (`examples/peak_memory.rs`, and the solver bench in child processes).
//!
//! This file has no criterion dependency; benches and tests include it with `#[path]`.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]
#![allow(dead_code)]

use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    JointType, KjointBuilder, KjointHandle, KjointProperty, KjointSet, SubstepSettings,
};

/// A frame \[s\] (60 Hz).
pub const FRAME: f64 = 1.0 / 60.0;
/// KJOINT2 substeps per frame; also rapier's `num_solver_iterations` in the reference.
pub const SUBSTEPS: usize = 4;
/// Frames a scene runs untimed before a timing of its cost growth (the bench's
/// interleaved exponents, `examples/chain_frames.rs`): the first substep analyses the
/// topology and allocates the set's arrays, which timed over 15 frames of 10 000 links
/// weighed ten times what they weigh over 150 frames of 1000.
pub const SETTLE_FRAMES: usize = 3;
/// `Kn` \[N/m\] of every KJOINT2 joint unless a scene says otherwise.
pub const KN: f64 = 1e12;
/// Length \[m\] of a rod.
pub const LINK: Real = 0.1;
/// Mass \[kg\] of a rod.
pub const MASS: Real = 0.1;
/// Gravity \[m/s²\] (along −y).
pub const GRAVITY: Real = 9.81;

/// A body of a scene: its builder and its colliders (most have none).
#[derive(Clone, Debug)]
pub struct BodySpec {
    /// The rigid body (pose, mass properties, initial velocity).
    pub body: RigidBodyBuilder,
    /// Colliders attached to it.
    pub colliders: Vec<ColliderBuilder>,
}

/// What a joint lets free.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    /// One rotation about `axis` (world coordinates, at creation).
    Revolute {
        /// Hinge axis in world coordinates.
        axis: Vector,
    },
    /// Three rotations.
    Spherical,
}

/// A joint of a scene. `body1`, `body2` index [`Scene::bodies`]; the anchors are in each
/// body's local coordinates and coincide in the world at creation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointSpec {
    /// Index of body 1.
    pub body1: usize,
    /// Index of body 2.
    pub body2: usize,
    /// Anchor on body 1 (its local coordinates) \[m\].
    pub anchor1: Vector,
    /// Anchor on body 2 (its local coordinates) \[m\].
    pub anchor2: Vector,
    /// Revolute or spherical.
    pub kind: JointKind,
}

/// What the KJOINT2 world is compared with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    /// The same bodies on rapier impulse joints, `dt` = 1/60 s, 4 solver iterations.
    ImpulseJoints,
    /// The same bodies without any joint, stepped as the KJOINT2 world steps rapier:
    /// 4 × `world.step()` of 1/240 s per frame, 1 solver iteration (the cost of the bodies and
    /// contacts alone, so the ratio is what the joints add).
    Unjointed,
}

/// A scene: bodies (body 0 the fixed world) and joints, in insertion order.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Short name (with its size).
    pub name: String,
    /// Bodies; body 0 is fixed at the origin.
    pub bodies: Vec<BodySpec>,
    /// Joints in insertion order (for KJOINT2 also the elimination order of its solver).
    pub joints: Vec<JointSpec>,
    /// `Kn` of the KJOINT2 joints \[N/m\].
    pub kn: f64,
    /// What [`Scene::rapier`] builds.
    pub reference: Reference,
}

/// A KJOINT2 world: rapier bodies, KJOINT2 joints, stepped by frames of [`FRAME`].
pub struct KjointWorld {
    /// The rapier world (bodies, colliders; no rapier joints).
    pub world: PhysicsWorld,
    /// The KJOINT2 joints.
    pub joints: KjointSet,
    /// Body handles, index-aligned with [`Scene::bodies`].
    pub bodies: Vec<RigidBodyHandle>,
    /// Joint handles, index-aligned with [`Scene::joints`].
    pub handles: Vec<KjointHandle>,
}

impl KjointWorld {
    /// One 60 Hz frame: [`SUBSTEPS`] substeps of joint solve + `world.step()`.
    pub fn frame(&mut self) {
        self.joints
            .step(&mut self.world, FRAME)
            .expect("KJOINT2 frame");
    }
}

/// A rapier reference world.
pub struct RapierWorld {
    /// The rapier world (bodies, colliders and impulse joints).
    pub world: PhysicsWorld,
    /// Body handles, index-aligned with [`Scene::bodies`] (URDF: the links).
    pub bodies: Vec<RigidBodyHandle>,
    /// Impulse joints (empty for [`Reference::Unjointed`]).
    pub joints: Vec<ImpulseJointHandle>,
    /// `world.step()` calls per frame (1, or 4 for [`Reference::Unjointed`]).
    pub steps_per_frame: usize,
    /// Whether every body is taken through `RigidBodySet::get_mut` before each step, as the
    /// joint set writes the velocities of its bodies ([`Scene::rapier_unjointed_written`]).
    pub write_bodies: bool,
}

impl RapierWorld {
    /// One 60 Hz frame.
    pub fn frame(&mut self) {
        for _ in 0..self.steps_per_frame {
            if self.write_bodies {
                for h in &self.bodies {
                    // marks the body as changed by the user, nothing else
                    let _ = self.world.bodies.get_mut(*h);
                }
            }
            self.world.step();
        }
    }
}

/// A slender rod of length `length` and mass `mass` on its local x axis, centred at
/// `center`, turned by `rotation`.
pub fn rod(center: Vector, rotation: Rotation, length: Real, mass: Real) -> BodySpec {
    let i = mass * length * length / 12.0;
    BodySpec {
        body: RigidBodyBuilder::dynamic()
            .translation(center)
            .rotation(rotation.to_scaled_axis())
            .can_sleep(false)
            .additional_mass_properties(MassProperties::new(
                Vector::ZERO,
                mass,
                Vector::new(0.1 * i, i, i),
            )),
        colliders: Vec::new(),
    }
}

/// The fixed world body at the origin.
fn world_body() -> BodySpec {
    BodySpec {
        body: RigidBodyBuilder::fixed(),
        colliders: Vec::new(),
    }
}

/// Revolute joint about world z.
const HINGE_Z: JointKind = JointKind::Revolute { axis: Vector::Z };

/// Anchor at the near end of a rod (local −x).
fn near_end(length: Real) -> Vector {
    Vector::new(-length / 2.0, 0.0, 0.0)
}

/// Anchor at the far end of a rod (local +x).
fn far_end(length: Real) -> Vector {
    Vector::new(length / 2.0, 0.0, 0.0)
}

/// The direction of a rod released at 30° from the vertical, hanging down and to +x.
fn released_at_30() -> Vector {
    Vector::new(0.5, -(Real::sqrt(3.0)) / 2.0, 0.0)
}

/// **Chain**: `n` rods of [`LINK`] = 0.1 m and [`MASS`] = 0.1 kg end to end, hung from the
/// world at the origin by a revolute joint and joined by revolute joints (axis world z),
/// released straight at 30° from the vertical (the chain of `benches/kjoint.rs`). Joints are
/// inserted from the top: the insertion order is the chain order (no fill-in for a
/// Cholesky in that order). Measures the per-joint cost of a long, stiff, sequential system.
pub fn chain(n: usize) -> Scene {
    Scene {
        name: format!("chain of {n}"),
        ..chains(1, n)
    }
}

/// **Chains**: `k` chains of `n` links each, every one the [`chain`] of `n` links hung from
/// its own pivot on the world (0.3 m apart along z; the first at the origin). Each chain is
/// an island of its own, so a set of `k·n` joints steps them one tile after another
/// (`src/dynamics/tiles.rs`: every stage over one chain before the next chain starts) where
/// the one chain of `k·n` links is stepped stage by stage over all of its joints. Measures
/// what a chain's working set costs:
/// `k = 10, n = 1000` has the 10 000-link chain's bodies and joints, with the 1000-link
/// chain's working set per tile.
pub fn chains(k: usize, n: usize) -> Scene {
    let dir = released_at_30();
    let rot = Rotation::from_rotation_arc(Vector::X, dir);
    let mut bodies = vec![world_body()];
    let mut joints = Vec::with_capacity(k * n);
    for c in 0..k {
        let pivot = Vector::new(0.0, 0.0, 0.3 * c as Real);
        // the chain's first rod
        let first = bodies.len();
        for i in 0..n {
            bodies.push(rod(
                pivot + dir * (LINK * (i as Real + 0.5)),
                rot,
                LINK,
                MASS,
            ));
            joints.push(JointSpec {
                // the world for the first joint, else the previous rod
                body1: if i == 0 { 0 } else { first + i - 1 },
                body2: first + i,
                anchor1: if i == 0 { pivot } else { far_end(LINK) },
                anchor2: near_end(LINK),
                kind: HINGE_Z,
            });
        }
    }
    Scene {
        name: format!("{k} chains of {n}"),
        bodies,
        joints,
        kn: KN,
        reference: Reference::ImpulseJoints,
    }
}

/// **Pendulums**: `n` independent rods (0.1 m, 0.1 kg), each hung from the world by one
/// revolute joint (axis z) at its end, pivots on a 0.3 m grid of 100 columns in the x-z
/// plane, all released at 30°. The joint system is block-diagonal: measures the per-joint
/// overhead with no coupling at all.
pub fn pendulums(n: usize) -> Scene {
    let dir = released_at_30();
    let rot = Rotation::from_rotation_arc(Vector::X, dir);
    let mut bodies = vec![world_body()];
    let mut joints = Vec::with_capacity(n);
    for k in 0..n {
        let pivot = Vector::new(0.3 * (k % 100) as Real, 0.0, 0.3 * (k / 100) as Real);
        bodies.push(rod(pivot + dir * (LINK / 2.0), rot, LINK, MASS));
        joints.push(JointSpec {
            body1: 0,
            body2: k + 1,
            anchor1: pivot,
            anchor2: near_end(LINK),
            kind: HINGE_Z,
        });
    }
    Scene {
        name: format!("{n} pendulums"),
        bodies,
        joints,
        kn: KN,
        reference: Reference::ImpulseJoints,
    }
}

/// **Resting pendulums**: the [`pendulums`] hanging straight down at rest, their rods able
/// to sleep (rapier's default thresholds): after half a second both worlds put them to
/// sleep (the KJOINT2 set its islands, `src/dynamics/sleep.rs`; rapier its impulse joints'
/// islands). Measures what a crowd of mechanisms at rest costs.
pub fn resting_pendulums(n: usize) -> Scene {
    let mut scene = pendulums(n);
    let down = Rotation::from_rotation_arc(Vector::X, -Vector::Y);
    for (k, b) in scene.bodies.iter_mut().enumerate().skip(1) {
        let pivot = Vector::new(
            0.3 * ((k - 1) % 100) as Real,
            0.0,
            0.3 * ((k - 1) / 100) as Real,
        );
        b.body = b
            .body
            .clone()
            .translation(pivot - Vector::Y * (LINK / 2.0))
            .rotation(down.to_scaled_axis())
            .can_sleep(true);
    }
    Scene {
        name: format!("{n} resting pendulums"),
        ..scene
    }
}

/// Joint insertion order of a [`tree`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TreeOrder {
    /// Breadth first from the root: the root's joint first, the leaves' last.
    RootFirst,
    /// The reverse: the deepest level first, the root's joint last.
    LeavesFirst,
}

/// Number of rods (and joints) of a [`tree`] of `depth` levels: 2^depth − 1.
pub fn tree_size(depth: u32) -> usize {
    (1usize << depth) - 1
}

/// **Binary tree**: a complete binary tree of `depth` levels, 2^depth − 1 rods (0.1 m,
/// 0.1 kg; depth 9 = 511 rods and joints, 12 = 4095), all revolute joints about world z.
/// The root rod hangs from the world at the origin, released at 30° from the vertical; the
/// two children of a rod are hinged at its far end, turned ±25° from it (rods overlap in
/// space: they have no colliders). Bodies are inserted in breadth-first order in both
/// orders; only the joint insertion order differs ([`TreeOrder`]): root first, a Cholesky
/// in insertion order fills in catastrophically; leaves first it does not. Measures the
/// sensitivity of the solver to the joint order.
pub fn tree(depth: u32, order: TreeOrder) -> Scene {
    let n = tree_size(depth);
    let spread = Real::to_radians(25.0);
    let root_angle = -Real::to_radians(60.0); // 30° from the vertical, towards +x
    let mut bodies = vec![world_body()];
    let mut angle: Vec<Real> = vec![0.0; n];
    let mut start = vec![Vector::ZERO; n];
    let mut joints = Vec::with_capacity(n);
    for k in 0..n {
        // breadth-first index: parent (k − 1)/2, children 2k + 1 and 2k + 2
        if k == 0 {
            angle[0] = root_angle;
        } else {
            let p = (k - 1) / 2;
            let side = if k % 2 == 1 { 1.0 } else { -1.0 };
            angle[k] = angle[p] + side * spread;
            let pdir = Vector::new(angle[p].cos(), angle[p].sin(), 0.0);
            start[k] = start[p] + pdir * LINK;
        }
        let dir = Vector::new(angle[k].cos(), angle[k].sin(), 0.0);
        let rot = Rotation::from_rotation_z(angle[k]);
        bodies.push(rod(start[k] + dir * (LINK / 2.0), rot, LINK, MASS));
        joints.push(JointSpec {
            body1: if k == 0 { 0 } else { (k - 1) / 2 + 1 },
            body2: k + 1,
            anchor1: if k == 0 { Vector::ZERO } else { far_end(LINK) },
            anchor2: near_end(LINK),
            kind: HINGE_Z,
        });
    }
    let name = match order {
        TreeOrder::RootFirst => format!("tree of {n}, root first"),
        TreeOrder::LeavesFirst => {
            joints.reverse();
            format!("tree of {n}, leaves first")
        }
    };
    Scene {
        name,
        bodies,
        joints,
        kn: KN,
        reference: Reference::ImpulseJoints,
    }
}

/// **Trees**: `k` leaves-first [`tree`]s of `depth` levels, the `c`-th shifted 0.3·c m along
/// z (its root hinged to the world there). Each tree is an island of its own, so a set of
/// `k` trees of 511 joints is stepped two trees a tile (`src/dynamics/tiles.rs`) where the
/// one tree of 4095 is stepped stage by stage over all of its joints: with `k = 8, depth =
/// 9` the tree of 4095's number of bodies and joints, with the working set of a tile
/// (what `chains` measures for the chain).
pub fn trees(k: usize, depth: u32) -> Scene {
    let mut bodies = vec![world_body()];
    let mut joints = Vec::new();
    for c in 0..k {
        let base = bodies.len() - 1;
        let shift = Vector::new(0.0, 0.0, 0.3 * c as Real);
        let one = tree(depth, TreeOrder::LeavesFirst);
        for mut b in one.bodies.into_iter().skip(1) {
            b.body.position.translation += shift;
            bodies.push(b);
        }
        for mut j in one.joints {
            if j.body1 == 0 {
                j.anchor1 += shift;
            } else {
                j.body1 += base;
            }
            j.body2 += base;
            joints.push(j);
        }
    }
    Scene {
        name: format!("{k} trees of {}", tree_size(depth)),
        bodies,
        joints,
        kn: KN,
        reference: Reference::ImpulseJoints,
    }
}

/// Radius \[m\] of the [`hub`] ball.
pub const HUB_RADIUS: Real = 0.1;
/// Mass \[kg\] of the [`hub`] ball.
pub const HUB_MASS: Real = 3.0;

/// **Hub**: one dynamic ball (radius 0.1 m, 3 kg) hung from the world by a spherical joint
/// at its top, with `n` rods (0.1 m, 0.1 kg) each attached to its surface by a spherical
/// joint, pointing outwards along `n` directions spread evenly on the sphere (Fibonacci
/// lattice). `n` + 1 joints, the hub's first; all `n` + 1 share the ball, so `J M⁻¹ Jᵀ` has
/// a dense (6(n+1))² block: measures the cost of a body with many joints.
pub fn hub(n: usize) -> Scene {
    let i = 0.4 * HUB_MASS * HUB_RADIUS * HUB_RADIUS;
    let mut bodies = vec![
        world_body(),
        BodySpec {
            body: RigidBodyBuilder::dynamic()
                .can_sleep(false)
                .additional_mass_properties(MassProperties::new(
                    Vector::ZERO,
                    HUB_MASS,
                    Vector::splat(i),
                )),
            colliders: Vec::new(),
        },
    ];
    let top = Vector::new(0.0, HUB_RADIUS, 0.0);
    let mut joints = vec![JointSpec {
        body1: 0,
        body2: 1,
        anchor1: top,
        anchor2: top,
        kind: JointKind::Spherical,
    }];
    let golden = std::f64::consts::PI as Real * (3.0 - Real::sqrt(5.0));
    for k in 0..n {
        let y = 1.0 - 2.0 * (k as Real + 0.5) / n as Real;
        let r = (1.0 - y * y).max(0.0).sqrt();
        let phi = golden * k as Real;
        let dir = Vector::new(r * phi.cos(), y, r * phi.sin());
        let rot = Rotation::from_rotation_arc(Vector::X, dir);
        bodies.push(rod(dir * (HUB_RADIUS + LINK / 2.0), rot, LINK, MASS));
        joints.push(JointSpec {
            body1: 1,
            body2: k + 2,
            anchor1: dir * HUB_RADIUS,
            anchor2: near_end(LINK),
            kind: JointKind::Spherical,
        });
    }
    Scene {
        name: format!("hub with {n} rods"),
        bodies,
        joints,
        kn: KN,
        reference: Reference::ImpulseJoints,
    }
}

/// Capsule radius \[m\] of [`capsules_on_ground`].
pub const CAPSULE_RADIUS: Real = 0.05;
/// Capsule half-height \[m\] (of the segment) of [`capsules_on_ground`].
pub const CAPSULE_HALF_HEIGHT: Real = 0.15;
/// Capsule mass \[kg\] of [`capsules_on_ground`].
pub const CAPSULE_MASS: Real = 1.0;

/// **Contacts**: `groups` groups (50 in the benchmark) of 3 capsules (radius 5 cm, 0.4 m
/// long, 1 kg each) hinged end to end by 2 revolute joints about world z, with a 5 cm gap
/// between the capsules' tips (the hinge is in the gap, so a hinge does not put its two
/// capsules in contact unless it folds by more than ~95°). The groups start on a grid of
/// 5 columns along x (1.8 m apart) by 10 along z (0.6 m apart), 0.3–0.75 m above a fixed
/// ground box (a collider of body 0, top at y = 0), tilted by −15°…+15° about z, and fall
/// onto it. Every collider collides with every other (groups can hit each other).
/// The reference is [`Reference::Unjointed`]: the same bodies without joints stepped as
/// the KJOINT2 world steps rapier, so the ratio is what the KJOINT2 joints add to a scene
/// dominated by contacts. (The benchmark starts timing once the groups have landed.)
pub fn capsules_on_ground(groups: usize) -> Scene {
    let r = CAPSULE_RADIUS;
    let hh = CAPSULE_HALF_HEIGHT;
    let gap = r;
    let pitch = 2.0 * (hh + r) + gap; // centre to centre along a group
    let hinge = hh + r + gap / 2.0; // centre to hinge
    let mut ground = world_body();
    ground
        .colliders
        .push(ColliderBuilder::cuboid(12.0, 0.1, 8.0).translation(Vector::new(4.0, -0.1, 3.0)));
    let mut bodies = vec![ground];
    let mut joints = Vec::with_capacity(2 * groups);
    for g in 0..groups {
        let col = g % 5;
        let row = g / 5;
        let tilt = (((g * 37) % 31) as Real - 15.0).to_radians();
        let rot = Rotation::from_rotation_z(tilt);
        let dir = rot * Vector::X;
        let base = Vector::new(
            1.8 * col as Real,
            0.3 + 0.15 * (g % 4) as Real,
            0.6 * row as Real,
        );
        for c in 0..3 {
            let center = base + dir * (pitch * (c as Real - 1.0));
            bodies.push(BodySpec {
                body: RigidBodyBuilder::dynamic()
                    .translation(center)
                    .rotation(rot.to_scaled_axis())
                    .can_sleep(false),
                colliders: vec![ColliderBuilder::capsule_x(hh, r).mass(CAPSULE_MASS)],
            });
            if c > 0 {
                let b2 = bodies.len() - 1;
                joints.push(JointSpec {
                    body1: b2 - 1,
                    body2: b2,
                    anchor1: Vector::new(hinge, 0.0, 0.0),
                    anchor2: Vector::new(-hinge, 0.0, 0.0),
                    kind: HINGE_Z,
                });
            }
        }
    }
    Scene {
        name: format!("{groups} groups of 3 hinged capsules"),
        bodies,
        joints,
        kn: KN,
        reference: Reference::Unjointed,
    }
}

/// **Four-bar linkage** (a closed loop of 4 revolute joints about world z, in the x-y
/// plane), for the solver's equivalence tests. Pivots A = (0, 0), B = (0, 0.2),
/// C = (0.4, 0.3), D = (0.4, 0) \[m\]; links AD (0.4 m, "ground"), AB (crank, 0.2 m),
/// BC (coupler, 0.41 m), CD (rocker, 0.3 m) are rods of 1 kg/m. The crank starts turning
/// at 2 rad/s about z (the other links at rest: the joints make the velocities consistent
/// in the first substeps), under gravity.
///
/// * `grounded = true`: AD is the fixed world body (body 0); bodies AB, BC, CD (1–3) and
///   joints A (world–AB), B (AB–BC), C (BC–CD), D (CD–world). The loop closes through the
///   fixed body, so in `J M⁻¹ Jᵀ` the joints only form a path.
/// * `grounded = false`: AD is a dynamic body too (body 1; body 0 is an unused fixed
///   body), joints A (AD–AB), B (AB–BC), C (BC–CD), D (CD–AD): a genuine 4-cycle among
///   dynamic bodies. The loop falls freely under gravity while it moves.
///
/// Four revolute joints in 3-D over-constrain a planar loop (redundant constraints): a
/// direct solver must cope with a singular unregularised system.
pub fn four_bar(grounded: bool) -> Scene {
    let a = Vector::new(0.0, 0.0, 0.0);
    let b = Vector::new(0.0, 0.2, 0.0);
    let c = Vector::new(0.4, 0.3, 0.0);
    let d = Vector::new(0.4, 0.0, 0.0);
    let link = |p: Vector, q: Vector| {
        let v = q - p;
        let l = v.length();
        let rot = Rotation::from_rotation_z(v.y.atan2(v.x));
        rod((p + q) / 2.0, rot, l, l)
    };
    let mut bodies = vec![world_body()];
    let ground = if grounded {
        0
    } else {
        bodies.push(link(a, d));
        1
    };
    let crank = bodies.len();
    let mut crank_body = link(a, b);
    crank_body.body = crank_body.body.angvel(Vector::new(0.0, 0.0, 2.0));
    bodies.push(crank_body);
    let coupler = bodies.len();
    bodies.push(link(b, c));
    let rocker = bodies.len();
    bodies.push(link(c, d));
    let len = |p: Vector, q: Vector| (q - p).length();
    // a pivot at the start (−x end) or the end (+x end) of a link; the world's at the point
    let start = |p: Vector, q: Vector| near_end(len(p, q));
    let end = |p: Vector, q: Vector| far_end(len(p, q));
    let on_ground = |at_a: bool, point: Vector| {
        if grounded {
            point
        } else if at_a {
            start(a, d)
        } else {
            end(a, d)
        }
    };
    let joints = vec![
        JointSpec {
            body1: ground,
            body2: crank,
            anchor1: on_ground(true, a),
            anchor2: start(a, b),
            kind: HINGE_Z,
        },
        JointSpec {
            body1: crank,
            body2: coupler,
            anchor1: end(a, b),
            anchor2: start(b, c),
            kind: HINGE_Z,
        },
        JointSpec {
            body1: coupler,
            body2: rocker,
            anchor1: end(b, c),
            anchor2: start(c, d),
            kind: HINGE_Z,
        },
        JointSpec {
            body1: rocker,
            body2: ground,
            anchor1: end(c, d),
            anchor2: on_ground(false, d),
            kind: HINGE_Z,
        },
    ];
    Scene {
        name: if grounded {
            "four-bar, grounded".into()
        } else {
            "four-bar, free".into()
        },
        bodies,
        joints,
        kn: KN,
        reference: Reference::ImpulseJoints,
    }
}

/// **Ring** of `n ≥ 3` rods (1 kg/m, 0.2 m each) forming a regular polygon in the x-y
/// plane, hinged about z at its corners, the first corner also hinged to the world: one
/// island of `n + 1` joints with a loop among dynamic bodies (a closed track or belt). It
/// folds under gravity from the polygon, hanging from the pinned corner.
pub fn ring(n: usize) -> Scene {
    let n = n.max(3);
    let side: Real = 0.2;
    let radius = side / (2.0 * (std::f64::consts::PI as Real / n as Real).sin());
    let corner = |k: usize| {
        let a = 2.0 * std::f64::consts::PI as Real * k as Real / n as Real;
        Vector::new(radius * a.cos(), radius * a.sin(), 0.0)
    };
    let mut bodies = vec![world_body()];
    for k in 0..n {
        let (p, q) = (corner(k), corner((k + 1) % n));
        let v = q - p;
        bodies.push(rod(
            (p + q) / 2.0,
            Rotation::from_rotation_z(v.y.atan2(v.x)),
            side,
            side,
        ));
    }
    let mut joints: Vec<JointSpec> = (0..n)
        .map(|k| JointSpec {
            body1: 1 + k,
            body2: 1 + (k + 1) % n,
            anchor1: far_end(side),
            anchor2: near_end(side),
            kind: HINGE_Z,
        })
        .collect();
    joints.push(JointSpec {
        body1: 0,
        body2: 1,
        anchor1: corner(0),
        anchor2: near_end(side),
        kind: HINGE_Z,
    });
    Scene {
        name: format!("ring of {n} rods"),
        bodies,
        joints,
        kn: KN,
        reference: Reference::ImpulseJoints,
    }
}

impl Scene {
    /// Number of joints.
    pub fn joint_count(&self) -> usize {
        self.joints.len()
    }

    fn insert_bodies(&self, w: &mut PhysicsWorld) -> Vec<RigidBodyHandle> {
        self.bodies
            .iter()
            .map(|b| {
                let h = w.insert_body(b.body.clone());
                for c in &b.colliders {
                    w.insert_collider(c.clone(), Some(h));
                }
                h
            })
            .collect()
    }

    fn world(&self) -> (PhysicsWorld, Vec<RigidBodyHandle>) {
        let mut w = PhysicsWorld {
            gravity: Vector::new(0.0, -GRAVITY, 0.0),
            ..Default::default()
        };
        let bodies = self.insert_bodies(&mut w);
        (w, bodies)
    }

    /// The KJOINT2 world: the bodies, and the joints as KJOINT2 revolute / spherical joints
    /// with `Kn` = [`Scene::kn`] (other parameters default), [`SUBSTEPS`] substeps.
    /// Prepared ([`KjointSet::prepare`]: rapier has computed the masses), not stepped.
    pub fn kjoint(&self) -> KjointWorld {
        let (mut world, bodies) = self.world();
        let mut joints = KjointSet::with_settings(SubstepSettings {
            substeps: SUBSTEPS,
            ..Default::default()
        });
        let revolute = KjointProperty::new(JointType::Revolute).with_kn(self.kn);
        let spherical = KjointProperty::new(JointType::Spherical).with_kn(self.kn);
        let handles = self
            .joints
            .iter()
            .map(|j| {
                let builder = match j.kind {
                    JointKind::Revolute { axis } => KjointBuilder::new(revolute.clone())
                        .world_frame1(Rotation::from_rotation_arc(Vector::X, axis.normalize())),
                    JointKind::Spherical => KjointBuilder::new(spherical.clone()),
                }
                .local_anchor1(j.anchor1)
                .local_anchor2(j.anchor2);
                joints
                    .insert(builder, bodies[j.body1], bodies[j.body2], &world.bodies)
                    .expect("KJOINT2 joint")
            })
            .collect();
        joints.prepare(&mut world);
        KjointWorld {
            world,
            joints,
            bodies,
            handles,
        }
    }

    /// The reference world of [`Scene::reference`]: [`Scene::rapier_joints`] or
    /// [`Scene::rapier_unjointed`].
    pub fn rapier(&self) -> RapierWorld {
        match self.reference {
            Reference::ImpulseJoints => self.rapier_joints(),
            Reference::Unjointed => self.rapier_unjointed(),
        }
    }

    /// The same bodies on rapier impulse joints (`RevoluteJointBuilder` with the hinge axis
    /// in each body's local coordinates, `SphericalJointBuilder`), inserted in the same
    /// order; `dt` = 1/60 s, `num_solver_iterations` = [`SUBSTEPS`], one step per frame.
    pub fn rapier_joints(&self) -> RapierWorld {
        let (mut world, bodies) = self.world();
        world.integration_parameters.dt = FRAME as Real;
        world.integration_parameters.num_solver_iterations = SUBSTEPS;
        let joints = self
            .joints
            .iter()
            .map(|j| {
                let (h1, h2) = (bodies[j.body1], bodies[j.body2]);
                let joint: GenericJoint = match j.kind {
                    JointKind::Revolute { axis } => {
                        let axis = axis.normalize();
                        let local1 = world.bodies[h1].rotation().inverse() * axis;
                        let local2 = world.bodies[h2].rotation().inverse() * axis;
                        let mut g: GenericJoint = RevoluteJointBuilder::new(local1)
                            .local_anchor1(j.anchor1)
                            .local_anchor2(j.anchor2)
                            .into();
                        g.set_local_axis2(local2);
                        g
                    }
                    JointKind::Spherical => SphericalJointBuilder::new()
                        .local_anchor1(j.anchor1)
                        .local_anchor2(j.anchor2)
                        .into(),
                };
                world.insert_impulse_joint(h1, h2, joint)
            })
            .collect();
        RapierWorld {
            world,
            bodies,
            joints,
            steps_per_frame: 1,
            write_bodies: false,
        }
    }

    /// The same bodies without joints, stepped as [`KjointSet::step`] steps rapier:
    /// [`SUBSTEPS`] × `world.step()` of `dt` = [`FRAME`]/[`SUBSTEPS`], 1 solver iteration.
    pub fn rapier_unjointed(&self) -> RapierWorld {
        let (mut world, bodies) = self.world();
        let settings = SubstepSettings::default();
        world.integration_parameters.dt = (FRAME / SUBSTEPS as f64) as Real;
        world.integration_parameters.num_solver_iterations = settings.rapier_iterations;
        RapierWorld {
            world,
            bodies,
            joints: Vec::new(),
            steps_per_frame: SUBSTEPS,
            write_bodies: false,
        }
    }

    /// [`Self::rapier_unjointed`], with every body taken through `RigidBodySet::get_mut`
    /// before each step, as the joint set takes the bodies it writes velocities into: what
    /// rapier does for bodies changed between its steps (it checks them, handles them as
    /// user changes and rebuilds its solver contact graph), without any joint.
    pub fn rapier_unjointed_written(&self) -> RapierWorld {
        RapierWorld {
            write_bodies: true,
            ..self.rapier_unjointed()
        }
    }

    /// Largest distance \[m\] between the two world anchors of any joint of the scene, on
    /// `bodies` (handles index-aligned with [`Scene::bodies`]) of `world`.
    pub fn anchor_gap(&self, world: &PhysicsWorld, bodies: &[RigidBodyHandle]) -> Real {
        self.joints
            .iter()
            .map(|j| {
                let p1 = world.bodies[bodies[j.body1]].position() * j.anchor1;
                let p2 = world.bodies[bodies[j.body2]].position() * j.anchor2;
                (p1 - p2).length()
            })
            .fold(0.0, Real::max)
    }
}

/// Which world a peak-memory run builds ([`peak_memory_run`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemorySide {
    /// Nothing: the process' own baseline.
    Baseline,
    /// The scene on KJOINT2 joints.
    Kjoint,
    /// The scene on rapier impulse joints.
    Rapier,
}

impl MemorySide {
    /// `baseline`, `kjoint2` or `rapier`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "baseline" | "none" => Some(MemorySide::Baseline),
            "kjoint2" | "kjoint" => Some(MemorySide::Kjoint),
            "rapier" => Some(MemorySide::Rapier),
            _ => None,
        }
    }
}

/// Builds the [`chain`] of `links` on `side` and steps it `frames` frames, then returns
/// the process' peak resident memory \[KiB\] ([`peak_resident_kib`]). Meant to run in a
/// fresh process (the peak never goes down).
pub fn peak_memory_run(side: MemorySide, links: usize, frames: usize) -> Option<u64> {
    match side {
        MemorySide::Baseline => {}
        MemorySide::Kjoint => {
            let mut k = chain(links).kjoint();
            for _ in 0..frames {
                k.frame();
            }
        }
        MemorySide::Rapier => {
            let mut r = chain(links).rapier();
            for _ in 0..frames {
                r.frame();
            }
        }
    }
    peak_resident_kib()
}

/// Peak resident memory of this process \[KiB\]: `VmHWM` of `/proc/self/status` (Linux;
/// `None` elsewhere).
pub fn peak_resident_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The URDF arm the crate ships (`assets/urdf/arm.urdf`: a fixed base, shoulder and elbow
/// revolute with friction, damping and limits, a prismatic wrist; 4 bodies, 3 joints).
pub const URDF_ARM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/urdf/arm.urdf");

/// Gravity of URDF robots (z up).
fn urdf_gravity() -> Vector {
    Vector::new(0.0, 0.0, -GRAVITY)
}

/// **URDF arm, KJOINT2**: [`URDF_ARM`] loaded with the crate's `io::urdf::UrdfRobot` (described, then inserted) and
/// its defaults, as `examples/urdf_arm.rs` does (automatic stiffness `Kn` = 0, the URDF
/// friction, damping and limits as KJOINT2 laws and stops, friction stiffness for the
/// 1/240 s substep, no self-collisions), [`SUBSTEPS`] substeps. Prepared, not stepped.
/// `bodies` are the links in name order.
#[allow(clippy::result_large_err)] // (the crate's `UrdfError`, through a closure)
pub fn urdf_arm_kjoint() -> KjointWorld {
    use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
    let mut world = PhysicsWorld {
        gravity: urdf_gravity(),
        ..Default::default()
    };
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps: SUBSTEPS,
        ..Default::default()
    });
    let options = UrdfOptions {
        substep: FRAME / SUBSTEPS as f64,
        ..Default::default()
    };
    let robot = UrdfRobot::from_file(URDF_ARM, &options)
        .and_then(|r| r.insert(&mut world, &mut joints))
        .expect("the URDF arm");
    joints.prepare(&mut world);
    KjointWorld {
        world,
        bodies: robot.links.values().copied().collect(),
        handles: robot.joints.values().copied().collect(),
        joints,
    }
}

/// **URDF arm, rapier**: the same file through `rapier3d-urdf` with impulse joints
/// (`insert_using_impulse_joints`; revolute and prismatic with their limits, no friction or
/// damping: rapier3d-urdf ignores `<dynamics>`), the same bodies as [`urdf_arm_kjoint`]
/// (fixed root, URDF inertias, density-0 colliders that do not collide with each other),
/// `dt` = 1/60 s, `num_solver_iterations` = [`SUBSTEPS`]. Not with the `f64` feature
/// (rapier3d-urdf builds f32 rapier objects; the crate's loader converts them, this
/// reference scene does not).
#[cfg(not(feature = "f64"))]
pub fn urdf_arm_rapier() -> RapierWorld {
    use rapier3d_urdf::{UrdfLoaderOptions, UrdfRobot};
    let mut world = PhysicsWorld {
        gravity: urdf_gravity(),
        ..Default::default()
    };
    world.integration_parameters.dt = FRAME as Real;
    world.integration_parameters.num_solver_iterations = SUBSTEPS;
    // the collision groups of the crate's loader: robot colliders ignore each other
    let group = Group::GROUP_32;
    let options = UrdfLoaderOptions {
        make_roots_fixed: true,
        collider_blueprint: ColliderBuilder::default().density(0.0).collision_groups(
            InteractionGroups::new(group, Group::ALL ^ group, InteractionTestMode::And),
        ),
        rigid_body_blueprint: RigidBodyBuilder::dynamic().can_sleep(false),
        ..Default::default()
    };
    let (robot, _) = UrdfRobot::from_file(URDF_ARM, options, None).expect("the URDF arm");
    let handles = robot.insert_using_impulse_joints(
        &mut world.bodies,
        &mut world.colliders,
        &mut world.impulse_joints,
    );
    RapierWorld {
        bodies: handles.links.iter().map(|l| l.body).collect(),
        joints: handles.joints.iter().map(|j| j.joint).collect(),
        world,
        steps_per_frame: 1,
        write_bodies: false,
    }
}
