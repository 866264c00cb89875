//! Contacts left out between a joint's bodies (`KjointBuilder::contacts_enabled(false)`,
//! `KjointSet::set_contacts_enabled`), as rapier's own joints leave them out: an arm whose
//! box overlaps its base at the hinge, as a robot's adjacent links and a slider-crank's
//! rods do.

mod common;

use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{is_contact_filter, JointType, KjointHandle, KjointProperty, KjointSet};

const MASS: f64 = 2.0;
const G: f64 = 9.81;

/// A fixed base (a 0.2 m cube at the origin) and a 1.2 m arm hanging from a hinge about z at
/// the origin, its box overlapping the base's; the hinge's contacts as `contacts`.
struct Scene {
    world: PhysicsWorld,
    joints: KjointSet,
    hinge: KjointHandle,
    base: RigidBodyHandle,
    arm: RigidBodyHandle,
    base_collider: ColliderHandle,
    arm_collider: ColliderHandle,
}

fn scene(contacts: bool) -> Scene {
    let (mut world, _) = common::world(Vector::new(0.0, -G as Real, 0.0));
    let base = world.insert_body(RigidBodyBuilder::fixed());
    let base_collider = world.insert_collider(ColliderBuilder::cuboid(0.1, 0.1, 0.1), Some(base));
    let (arm, arm_collider) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, -0.5, 0.0))
            .can_sleep(false),
        ColliderBuilder::cuboid(0.05, 0.6, 0.05).mass(MASS as Real),
    );
    let mut joints = common::joints(4);
    let hinge = common::add(
        &mut joints,
        &world,
        KjointProperty::new(JointType::Revolute),
        base,
        arm,
        |b| {
            b.world_axis(Vector::Z)
                .local_anchor2(Vector::new(0.0, 0.5, 0.0))
                .contacts_enabled(contacts)
        },
    );
    Scene {
        world,
        joints,
        hinge,
        base,
        arm,
        base_collider,
        arm_collider,
    }
}

impl Scene {
    fn frames(&mut self, n: usize) {
        for _ in 0..n {
            self.joints.step(&mut self.world, 1.0 / 60.0).unwrap();
        }
    }

    /// Whether rapier has an active contact between the base and the arm.
    fn touching(&self) -> bool {
        (self.world.narrow_phase)
            .contact_pair(self.base_collider, self.arm_collider)
            .is_some_and(|p| p.has_any_active_contact())
    }

    /// The arm's centre's distance from where it hangs \[m\].
    fn displaced(&self) -> f64 {
        let c = self.world.bodies[self.arm].translation();
        (c - Vector::new(0.0, -0.5, 0.0)).length() as f64
    }

    fn force(&self) -> f64 {
        common::applied_force(self.joints.get(self.hinge).unwrap())
    }
}

#[test]
fn an_arm_whose_contacts_with_its_base_are_off_hangs_on_its_hinge_alone() {
    // contacts on (rapier's default): the base pushes the overlapping arm out, against the
    // hinge, and the hinge carries that push on top of the weight
    let mut on = scene(true);
    let mut worst_on = 0.0_f64;
    for _ in 0..60 {
        on.frames(1);
        worst_on = worst_on.max((on.force() - MASS * G).abs());
    }
    assert!(on.touching());
    assert!(on.world.impulse_joints.is_empty());
    // contacts off: the hinge carries the weight, nothing else
    // (after the first half second: the hinge takes the weight up over its first substeps)
    let mut off = scene(false);
    off.frames(30);
    let mut worst_off = 0.0_f64;
    for _ in 0..30 {
        off.frames(1);
        worst_off = worst_off.max((off.force() - MASS * G).abs());
    }
    println!(
        "force off the weight: contacts on {worst_on:.3} N (arm {:.4} m out), off \
         {worst_off:.2e} N (arm {:.2e} m out)",
        on.displaced(),
        off.displaced()
    );
    assert!(!off.touching());
    assert!(
        worst_off <= 1e-3 * MASS * G,
        "force {worst_off} N off the weight"
    );
    assert!(off.displaced() <= 1e-4, "arm {} m out", off.displaced());
    assert!(
        worst_on > 0.1 * MASS * G || on.displaced() > 1e-2,
        "contacts on: force {worst_on} N off the weight, arm {} m out",
        on.displaced()
    );
    // the set's one rapier joint, which rapier's solve does not see
    let filters: Vec<_> = off.world.impulse_joints.iter().collect();
    assert_eq!(filters.len(), 1);
    let (_, f) = filters[0];
    assert!(is_contact_filter(f));
    assert_eq!((f.body1(), f.body2()), (off.base, off.arm));
    assert!(!off.joints.get(off.hinge).unwrap().contacts_enabled());
}

/// Driving rapier yourself (`prepare`, then `apply_substep` and rapier's step at every
/// substep, README "own loop"): the arm with its contacts off hangs on its hinge alone too.
/// `prepare`'s zero-length rapier step ran before the set had put its filter in the world
/// and found the overlap: the arm was held in the base by 1956 N for good (an engine
/// integrator's trial, 2026-12-05).
#[test]
fn an_own_loop_leaves_the_contacts_out_from_the_first_substep() {
    let mut s = scene(false);
    s.joints.prepare(&mut s.world);
    let h = 1.0 / 240.0;
    let mut worst = 0.0_f64;
    for k in 0..240 {
        s.joints
            .apply_substep(&mut s.world.bodies, s.world.gravity, h)
            .unwrap();
        s.world.integration_parameters.dt = h as Real;
        s.world.integration_parameters.num_solver_iterations = 1;
        s.world.step();
        s.joints.advance_time(h).unwrap();
        s.joints.check_quarantine(&s.world).unwrap();
        if k >= 120 {
            worst = worst.max((s.force() - MASS * G).abs());
        }
    }
    println!(
        "own loop: force off the weight {worst:.2e} N, arm {:.2e} m out",
        s.displaced()
    );
    assert!(!s.touching());
    assert!(worst <= 1e-3 * MASS * G, "force {worst} N off the weight");
    assert!(s.displaced() <= 1e-4, "arm {} m out", s.displaced());
}

#[test]
fn the_pair_is_left_apart_and_each_body_still_collides_with_the_rest() {
    let mut s = scene(false);
    // a ball dropped on the base, one thrown at the arm from the side
    let dropped = common::ball(&mut s.world, 0.5, 0.05, Vector::new(0.07, 0.5, 0.0));
    let thrown = common::ball(&mut s.world, 0.5, 0.05, Vector::new(0.4, -0.9, 0.0));
    s.world.bodies[thrown].set_linvel(Vector::new(-3.0, 0.0, 0.0), true);
    s.world.gravity = Vector::ZERO;
    s.world.bodies[dropped].set_linvel(Vector::new(0.0, -2.0, 0.0), true);
    s.frames(30);
    // the dropped ball stopped on the base's top (its centre 0.15 m up), the arm was hit
    let y = s.world.bodies[dropped].translation().y as f64;
    assert!((y - 0.15).abs() < 0.01, "dropped ball at y = {y}");
    let w = s.world.bodies[s.arm].angvel().z as f64;
    let v = s.world.bodies[thrown].linvel().x as f64;
    assert!(w.abs() > 0.1, "arm turning at {w} rad/s");
    assert!(v > -2.0, "thrown ball still at {v} m/s");
    assert!(!s.touching());
}

#[test]
fn removing_the_joint_or_switching_its_contacts_on_lets_the_bodies_collide_again() {
    // switched on: the set's rapier joint leaves the world, the base pushes the arm
    let mut s = scene(false);
    s.frames(10);
    assert_eq!(s.world.impulse_joints.len(), 1);
    assert!(s.joints.set_contacts_enabled(s.hinge, true));
    s.frames(1);
    assert!(s.world.impulse_joints.is_empty());
    assert!(s.touching());
    // and off again: apart again once rapier updates the pair (which moves: the push)
    assert!(s.joints.set_contacts_enabled(s.hinge, false));
    s.frames(1);
    assert_eq!(s.world.impulse_joints.len(), 1);
    s.frames(5);
    assert!(!s.touching());
    // removed: the arm falls through the base's box, which now pushes it
    let mut s = scene(false);
    s.frames(10);
    assert!(s.joints.remove(s.hinge).is_some());
    s.frames(1);
    assert!(s.world.impulse_joints.is_empty());
    assert!(s.touching());
    assert!(!s.joints.set_contacts_enabled(s.hinge, true));
}

#[test]
fn a_body_removed_from_the_world_takes_the_filter_and_the_joint_along() {
    let mut s = scene(false);
    s.frames(2);
    assert!(s.world.remove_body(s.arm).is_some());
    assert!(s.world.impulse_joints.is_empty());
    s.frames(2);
    assert!(s.joints.is_empty());
    assert!(s.world.impulse_joints.is_empty());
}

/// A scene's `contacts = false` on a joint: its two colliding bodies stay apart; without
/// the key they touch.
#[test]
fn a_scene_joint_leaves_its_bodies_contacts_out() {
    use rapier_kjoint::scene;
    let text = |contacts: &str| {
        format!(
            r#"duration = 0.1
gravity = [0.0, 0.0, 0.0]

[[bodies]]
name = "a"
shape = {{ type = "cuboid", half_extents = [0.3, 0.1, 0.1] }}
mass = 1.0
collide = true

[[bodies]]
name = "b"
shape = {{ type = "cuboid", half_extents = [0.3, 0.1, 0.1] }}
mass = 1.0
translation = [0.5, 0.0, 0.0]
collide = true

[[joints]]
name = "hinge"
body1 = "a"
body2 = "b"
anchor1 = [0.25, 0.0, 0.0]
anchor2 = [-0.25, 0.0, 0.0]
property = {{ type = "revolute" }}
{contacts}
"#
        )
    };
    let touching = |contacts: &str| {
        let path = common::cli::temp_file("contacts-scene", "hinge.toml", &text(contacts));
        let (sc, src) = scene::load(&path).unwrap();
        let mut built = scene::build(&sc, &src).unwrap();
        let h = built.joints.find("hinge").unwrap();
        let enabled = built.joints.get(h).unwrap().contacts_enabled();
        for _ in 0..6 {
            built.joints.step(&mut built.world, 1.0 / 60.0).unwrap();
        }
        let w = &built.world;
        let colliders = |name: &str| {
            let (_, hb) = built.bodies.iter().find(|(n, _)| n == name).unwrap();
            w.bodies[*hb].colliders().to_vec()
        };
        let (ca, cb) = (colliders("a")[0], colliders("b")[0]);
        let touch =
            (w.narrow_phase.contact_pair(ca, cb)).is_some_and(|p| p.has_any_active_contact());
        (enabled, touch)
    };
    assert_eq!(touching(""), (true, true));
    assert_eq!(touching("contacts = false"), (false, false));
}
