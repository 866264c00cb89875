//! A saved state of a rapier world and its joint set ([`Snapshot`]).

use crate::rapier::prelude::*;

use super::KjointSet;

/// A rapier world and its [`KjointSet`], saved to be restored later: an episode reset, a
/// game rolled back to a saved frame, a search that tries several actions from one state.
/// A restored world and set step on with the same bits as the originals would have.
///
/// rapier's `PhysicsWorld` is not `Clone`: its pipelines and CCD solver are workspace. The
/// snapshot holds clones of its state (gravity, integration parameters, islands, broad and
/// narrow phases, bodies, colliders, impulse and multibody joints, soft bodies) and of the
/// joint set, which carries its joints' law states (friction, stops, sensor locks, motors),
/// sensors, energies and what a substep carries to the next (the contact prediction, the
/// energy book's pending correction, the islands' rest); the set's solver workspace is
/// built again from the topology at the restore. With the cargo feature `serde-serialize`
/// (which turns rapier's on) a snapshot is `Serialize` and `Deserialize`, to be saved to a
/// file; so are rapier's `PhysicsWorld` and the [`KjointSet`] themselves.
///
/// ```
/// use rapier_kjoint::prelude::*;
/// use rapier_kjoint::rapier::prelude::*;
///
/// let mut world = PhysicsWorld::default();
/// let ground = world.insert_body(RigidBodyBuilder::fixed());
/// let (bob, _) = world.insert(
///     RigidBodyBuilder::dynamic().translation(Vector::new(0.3, -1.0, 0.0)),
///     ColliderBuilder::ball(0.1).mass(1.0),
/// );
/// let mut joints = KjointSet::new();
/// joints
///     .insert(KjointBuilder::new(KjointProperty::new(JointType::Spherical)), ground, bob, &world.bodies)
///     .unwrap();
/// for _ in 0..30 {
///     joints.step(&mut world, 1.0 / 60.0).unwrap();
/// }
/// let saved = Snapshot::take(&world, &joints);
/// for _ in 0..30 {
///     joints.step(&mut world, 1.0 / 60.0).unwrap();
/// }
/// let there = *world.bodies[bob].position();
///
/// saved.restore_into(&mut world, &mut joints); // back half a second
/// for _ in 0..30 {
///     joints.step(&mut world, 1.0 / 60.0).unwrap();
/// }
/// assert_eq!(*world.bodies[bob].position(), there); // the same bits
/// ```
#[derive(Clone)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct Snapshot {
    gravity: Vector,
    integration_parameters: IntegrationParameters,
    islands: IslandManager,
    broad_phase: BroadPhaseBvh,
    narrow_phase: NarrowPhase,
    bodies: RigidBodySet,
    colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    joints: KjointSet,
}

/// What a snapshot holds, in numbers (rapier's `PhysicsWorld` has no `Debug`): the set's
/// time, the bodies, colliders and rapier joints of the world, and the KJOINT2 joints.
impl std::fmt::Debug for Snapshot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Snapshot")
            .field("time", &self.joints.time())
            .field("gravity", &self.gravity)
            .field("bodies", &self.bodies.len())
            .field("colliders", &self.colliders.len())
            .field("impulse_joints", &self.impulse_joints.len())
            .field("kjoints", &self.joints.len())
            .finish_non_exhaustive()
    }
}

impl Snapshot {
    /// Saves `world` and `joints` as they are now.
    pub fn take(world: &PhysicsWorld, joints: &KjointSet) -> Self {
        Snapshot {
            gravity: world.gravity,
            integration_parameters: world.integration_parameters,
            islands: world.islands.clone(),
            broad_phase: world.broad_phase.clone(),
            narrow_phase: world.narrow_phase.clone(),
            bodies: world.bodies.clone(),
            colliders: world.colliders.clone(),
            impulse_joints: world.impulse_joints.clone(),
            multibody_joints: world.multibody_joints.clone(),
            soft_bodies: world.soft_bodies.clone(),
            joints: joints.clone(),
        }
    }

    /// A new world and joint set in the saved state (fresh pipelines and CCD solver); the
    /// snapshot stays, to be restored again.
    pub fn restore(&self) -> (PhysicsWorld, KjointSet) {
        let mut world = PhysicsWorld::default();
        let mut joints = KjointSet::new();
        self.restore_into(&mut world, &mut joints);
        (world, joints)
    }

    /// Puts `world` and `joints` back in the saved state, keeping `world`'s pipelines and
    /// CCD solver (workspace); the snapshot stays, to be restored again.
    pub fn restore_into(&self, world: &mut PhysicsWorld, joints: &mut KjointSet) {
        world.gravity = self.gravity;
        world.integration_parameters = self.integration_parameters;
        world.islands.clone_from(&self.islands);
        world.broad_phase.clone_from(&self.broad_phase);
        world.narrow_phase.clone_from(&self.narrow_phase);
        world.bodies.clone_from(&self.bodies);
        world.colliders.clone_from(&self.colliders);
        world.impulse_joints.clone_from(&self.impulse_joints);
        world.multibody_joints.clone_from(&self.multibody_joints);
        world.soft_bodies.clone_from(&self.soft_bodies);
        joints.clone_from(&self.joints);
    }

    /// The saved joint set.
    pub fn joints(&self) -> &KjointSet {
        &self.joints
    }

    /// The saved bodies.
    pub fn bodies(&self) -> &RigidBodySet {
        &self.bodies
    }
}
