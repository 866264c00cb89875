//! The structured solve against the dense joint-space reference, at every substep of scenes
//! that exercise each path: a chain, a tree inserted root first, a hub, closed loops, and
//! hinged groups in contact with the ground. The impulses must agree to 1e-9 relative.

use crate::rapier::prelude::*;
use crate::{JointType, Kjoint2Builder, Kjoint2Property, KjointSet, SubstepSettings};

const LINK: Real = 0.1;

fn rod(w: &mut PhysicsWorld, at: Vector) -> RigidBodyHandle {
    let i = 0.1 * LINK * LINK / 12.0;
    w.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(at)
            .can_sleep(false)
            .additional_mass_properties(MassProperties::new(
                Vector::ZERO,
                0.1,
                Vector::new(0.1 * i, i, i),
            )),
    )
}

fn hinge(kn: f64) -> Kjoint2Builder {
    let axis_z = Rotation::from_rotation_arc(Vector::X, Vector::Z);
    Kjoint2Builder::new(Kjoint2Property::new(JointType::Revolute).with_kn(kn)).frame(axis_z)
}

fn joint(
    set: &mut KjointSet,
    w: &PhysicsWorld,
    a: RigidBodyHandle,
    b: RigidBodyHandle,
    pa: Vector,
    pb: Vector,
    kn: f64,
) {
    set.insert(
        hinge(kn).local_anchor1(pa).local_anchor2(pb),
        a,
        b,
        &w.bodies,
    )
    .unwrap();
}

fn new_world() -> (PhysicsWorld, KjointSet, RigidBodyHandle) {
    let mut w = PhysicsWorld::default();
    w.gravity = Vector::new(0.0, -9.81, 0.0);
    let ground = w.insert_body(RigidBodyBuilder::fixed());
    let set = KjointSet::with_settings(SubstepSettings {
        substeps: 4,
        ..Default::default()
    });
    (w, set, ground)
}

/// Runs `frames` frames checking every substep; returns the worst relative difference.
fn worst_difference(w: &mut PhysicsWorld, set: &mut KjointSet, frames: usize) -> f64 {
    set.verify = Some(0.0);
    for _ in 0..frames {
        set.step(w, 1.0 / 60.0).unwrap();
    }
    set.verify.unwrap()
}

fn half() -> Vector {
    Vector::new(LINK / 2.0, 0.0, 0.0)
}

#[test]
fn chain_matches_the_dense_solve() {
    let (mut w, mut set, ground) = new_world();
    let dir = Vector::new(0.5, -(Real::sqrt(3.0)) / 2.0, 0.0);
    let mut prev = ground;
    for k in 0..30 {
        let b = rod(&mut w, dir * (LINK * (k as Real + 0.5)));
        let pa = if k == 0 { Vector::ZERO } else { half() };
        joint(&mut set, &w, prev, b, pa, -half(), 1e12);
        prev = b;
    }
    let e = worst_difference(&mut w, &mut set, 20);
    assert!(e < 1e-9, "chain: {e:e}");
    assert_eq!(set.island_count(), 1);
    assert!(set.loop_joints().is_empty());
}

/// A binary tree of `levels` levels of rods, joints inserted root first.
#[test]
fn tree_inserted_root_first_matches_the_dense_solve() {
    let (mut w, mut set, ground) = new_world();
    let mut level = vec![(ground, Vector::ZERO)];
    for depth in 0..5 {
        let mut next = Vec::new();
        for (parent, tip) in &level {
            let branches: &[Real] = if depth == 0 { &[0.0] } else { &[-1.0, 1.0] };
            for s in branches {
                let dir = Vector::new(0.3 * s, -1.0, 0.0).normalize();
                let at = *tip + dir * (LINK / 2.0);
                let b = rod(&mut w, at);
                // anchors in the rods' local frames (bodies unrotated)
                let pa = if *parent == ground {
                    *tip
                } else {
                    *tip - w.bodies[*parent].translation()
                };
                set.insert(
                    hinge(1e9).local_anchor1(pa).local_anchor2(*tip - at),
                    *parent,
                    b,
                    &w.bodies,
                )
                .unwrap();
                next.push((b, at + dir * (LINK / 2.0)));
            }
        }
        level = next;
    }
    assert_eq!(set.len(), 1 + 2 + 4 + 8 + 16);
    let e = worst_difference(&mut w, &mut set, 20);
    assert!(e < 1e-9, "tree: {e:e}");
    assert!(set.loop_joints().is_empty());
}

#[test]
fn hub_matches_the_dense_solve() {
    let (mut w, mut set, ground) = new_world();
    let hub = w.insert_body(
        RigidBodyBuilder::dynamic()
            .can_sleep(false)
            .additional_mass_properties(MassProperties::new(
                Vector::ZERO,
                5.0,
                Vector::splat(0.05),
            )),
    );
    set.insert(
        Kjoint2Builder::new(Kjoint2Property::new(JointType::Spherical).with_kn(1e10)),
        ground,
        hub,
        &w.bodies,
    )
    .unwrap();
    for k in 0..24 {
        let a = k as Real * std::f64::consts::TAU as Real / 24.0;
        let dir = Vector::new(a.cos(), 0.0, a.sin());
        let b = rod(&mut w, dir * (0.2 + LINK / 2.0));
        set.insert(
            Kjoint2Builder::new(Kjoint2Property::new(JointType::Spherical).with_kn(1e10))
                .local_anchor1(dir * 0.2)
                .local_anchor2(-dir * (LINK / 2.0)),
            hub,
            b,
            &w.bodies,
        )
        .unwrap();
    }
    let e = worst_difference(&mut w, &mut set, 20);
    assert!(e < 1e-9, "hub: {e:e}");
    assert_eq!(set.island_count(), 1);
}

/// A four-bar linkage and a ladder of three squares: islands with loops (faer path) next to
/// a tree island.
#[test]
fn closed_loops_match_the_dense_solve() {
    let (mut w, mut set, ground) = new_world();
    // four-bar: a square of four rods, the top one pinned to the world at both ends
    let corners = [
        Vector::new(0.0, 0.0, 0.0),
        Vector::new(LINK, 0.0, 0.0),
        Vector::new(LINK, -LINK, 0.0),
        Vector::new(0.0, -LINK, 0.0),
    ];
    let mut bars = Vec::new();
    for k in 0..4 {
        let (a, b) = (corners[k], corners[(k + 1) % 4]);
        bars.push((rod(&mut w, (a + b) * 0.5), a, b));
    }
    for k in 0..4 {
        let (b1, _, end1) = bars[k];
        let (b2, start2, _) = bars[(k + 1) % 4];
        let pa = end1 - w.bodies[b1].translation();
        let pb = start2 - w.bodies[b2].translation();
        set.insert(
            hinge(1e8).local_anchor1(pa).local_anchor2(pb),
            b1,
            b2,
            &w.bodies,
        )
        .unwrap();
    }
    set.insert(
        hinge(1e8)
            .local_anchor1(corners[0])
            .local_anchor2(corners[0] - w.bodies[bars[0].0].translation()),
        ground,
        bars[0].0,
        &w.bodies,
    )
    .unwrap();
    // a separate chain (tree island)
    let mut prev = ground;
    for k in 0..5 {
        let at = Vector::new(1.0, -LINK * (k as Real + 0.5), 0.0);
        let b = rod(&mut w, at);
        let pa = if k == 0 {
            Vector::new(1.0, 0.0, 0.0)
        } else {
            Vector::new(0.0, -LINK / 2.0, 0.0)
        };
        set.insert(
            hinge(1e12)
                .local_anchor1(pa)
                .local_anchor2(Vector::new(0.0, LINK / 2.0, 0.0)),
            prev,
            b,
            &w.bodies,
        )
        .unwrap();
        prev = b;
    }
    // two stiff joints from the world to one body: a tree in the body–joint graph (the world
    // is not a node), and the hard case for accuracy (both block the same directions)
    let p = rod(&mut w, Vector::new(2.0, -0.05, 0.0));
    for dz in [-0.02, 0.02] {
        set.insert(
            Kjoint2Builder::new(Kjoint2Property::new(JointType::Spherical).with_kn(1e9))
                .local_anchor1(Vector::new(2.0, 0.0, dz))
                .local_anchor2(Vector::new(0.0, 0.05, dz)),
            ground,
            p,
            &w.bodies,
        )
        .unwrap();
    }
    let e = worst_difference(&mut w, &mut set, 20);
    assert!(e < 1e-9, "loops: {e:e}");
    assert_eq!(set.island_count(), 3);
    assert_eq!(set.loop_joints().len(), 1, "{:?}", set.loop_joints());
}

/// Groups of three hinged capsules falling onto a ground box: joints and contacts.
#[test]
fn contact_scene_matches_the_dense_solve() {
    let (mut w, mut set, _) = new_world();
    w.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    for g in 0..6 {
        let x0 = (g as Real - 3.0) * 0.5;
        let mut prev = None;
        for k in 0..3 {
            let (b, _) = w.insert(
                RigidBodyBuilder::dynamic()
                    .translation(Vector::new(
                        x0 + 0.25 * k as Real,
                        0.3 + 0.05 * g as Real,
                        0.0,
                    ))
                    .rotation(Vector::new(0.0, 0.0, std::f64::consts::FRAC_PI_2 as Real)),
                ColliderBuilder::capsule_y(0.1, 0.04),
            );
            if let Some(p) = prev {
                set.insert(
                    hinge(1e10)
                        .local_anchor1(Vector::new(0.0, -0.125, 0.0))
                        .local_anchor2(Vector::new(0.0, 0.125, 0.0)),
                    p,
                    b,
                    &w.bodies,
                )
                .unwrap();
            }
            prev = Some(b);
        }
    }
    let e = worst_difference(&mut w, &mut set, 40);
    assert!(e < 1e-9, "contacts: {e:e}");
    assert_eq!(set.island_count(), 6);
}

#[test]
fn removing_a_jointed_body_detaches_its_joints() {
    let (mut w, mut set, ground) = new_world();
    let a = rod(&mut w, Vector::new(0.0, -LINK / 2.0, 0.0));
    let b = rod(&mut w, Vector::new(0.0, -1.5 * LINK, 0.0));
    let up = Vector::new(0.0, LINK / 2.0, 0.0);
    let h0 = set
        .insert(hinge(1e9).local_anchor2(up), ground, a, &w.bodies)
        .unwrap();
    let h1 = set
        .insert(
            hinge(1e9).local_anchor1(-up).local_anchor2(up),
            a,
            b,
            &w.bodies,
        )
        .unwrap();
    set.step(&mut w, 1.0 / 60.0).unwrap();
    w.remove_body(b);
    set.step(&mut w, 1.0 / 60.0).unwrap();
    let events = set.drain_events();
    assert_eq!(events.len(), 1, "{events:?}");
    assert!(!set.get(h1).unwrap().active);
    assert!(set.get(h0).unwrap().active);
    // the remaining rod still hangs from its joint
    for _ in 0..30 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    let s = set.get(h0).unwrap().state.as_ref().unwrap();
    let gap: f64 = (0..3)
        .map(|i| (s.anchor1[i] - s.anchor2[i]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(gap < 1e-6, "gap {gap}");
    assert!((w.bodies[a].translation().y + LINK / 2.0).abs() < 1e-4);
}
