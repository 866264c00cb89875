//! The scenes of the solver benchmarks (`benches/scenes.rs`), at small sizes: every joint's
//! anchors coincide at creation on both sides, the KJOINT2 joints hold over half a second,
//! the two tree orders have the same bodies and the same joints, each of the chains moves as
//! the chain of its length alone, and the capsules land on the ground. (Also shows how a
//! test includes the scenes.)

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

#[path = "../benches/scenes.rs"]
mod scenes;

use scenes::{Scene, TreeOrder};

fn small_scenes() -> Vec<Scene> {
    vec![
        scenes::chain(6),
        scenes::chains(3, 4),
        scenes::trees(2, 3),
        scenes::pendulums(5),
        scenes::resting_pendulums(5),
        scenes::tree(3, TreeOrder::RootFirst),
        scenes::tree(3, TreeOrder::LeavesFirst),
        scenes::hub(6),
        scenes::capsules_on_ground(2),
        scenes::four_bar(true),
        scenes::four_bar(false),
    ]
}

#[test]
fn anchors_coincide_at_creation_on_both_sides() {
    for s in small_scenes() {
        let k = s.kjoint();
        assert_eq!(k.handles.len(), s.joints.len(), "{}", s.name);
        let gap = s.anchor_gap(&k.world, &k.bodies);
        assert!(gap < 1e-5, "{}: KJOINT2 anchors {gap} m apart", s.name);
        let r = s.rapier_joints();
        assert_eq!(r.joints.len(), s.joints.len(), "{}", s.name);
        let gap = s.anchor_gap(&r.world, &r.bodies);
        assert!(gap < 1e-5, "{}: rapier anchors {gap} m apart", s.name);
    }
}

#[test]
fn kjoint2_joints_hold() {
    // not the capsules: their landing impacts open the hinges by up to ~1 cm for a frame
    // (rapier's contact impulses come after the joints' in each substep)
    for s in small_scenes()
        .into_iter()
        .filter(|s| !s.name.contains("capsules"))
    {
        let mut k = s.kjoint();
        let mut worst: rapier_kjoint::rapier::math::Real = 0.0;
        for _ in 0..30 {
            k.frame();
            worst = worst.max(s.anchor_gap(&k.world, &k.bodies));
        }
        assert!(worst < 1e-3, "{}: anchors {worst} m apart", s.name);
    }
}

#[test]
fn tree_orders_differ_only_in_joint_order() {
    let a = scenes::tree(4, TreeOrder::RootFirst);
    let b = scenes::tree(4, TreeOrder::LeavesFirst);
    assert_eq!(a.joints.len(), 15);
    assert_eq!(a.bodies.len(), b.bodies.len());
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        assert_eq!(x.body, y.body);
    }
    let mut rev = b.joints.clone();
    rev.reverse();
    assert_eq!(a.joints, rev);
    // root first: the world joint first; leaves first: a leaf's joint first
    assert_eq!(a.joints[0].body1, 0);
    assert_eq!(b.joints[0].body2, 15);
}

/// `chains(k, n)` is `k` copies of `chain(n)`, 0.3 m apart along z (what the harness's
/// comparison of the two relies on): after 30 frames of swinging, every rod of every chain
/// is where the same rod of the lone chain is, within a micrometre (round-off of the f32
/// poses, which are not the same numbers away from z = 0).
#[test]
fn each_of_the_chains_moves_as_the_lone_chain() {
    let (k, n) = (3, 5);
    let lone = scenes::chain(n);
    let many = scenes::chains(k, n);
    assert_eq!(many.joints.len(), k * n);
    let mut a = lone.kjoint();
    let mut b = many.kjoint();
    for _ in 0..30 {
        a.frame();
        b.frame();
    }
    for c in 0..k {
        let dz = 0.3 * c as rapier_kjoint::rapier::math::Real;
        for i in 0..n {
            let p = a.world.bodies[a.bodies[1 + i]].translation();
            let q = b.world.bodies[b.bodies[1 + c * n + i]].translation();
            let q = q - rapier_kjoint::rapier::math::Vector::new(0.0, 0.0, dz);
            assert!(
                (p - q).length() < 1e-6,
                "chain {c}, rod {i}: {p} against {q}"
            );
        }
    }
    // the lone chain swung (the comparison is not of two chains at rest)
    let start = lone.kjoint();
    let tip = |w: &scenes::KjointWorld| w.world.bodies[w.bodies[n]].translation();
    let swing = (tip(&a) - tip(&start)).length();
    assert!(swing > 0.05, "the tip moved {swing} m in half a second");
}

#[test]
fn capsules_land_on_the_ground() {
    let s = scenes::capsules_on_ground(2);
    let mut k = s.kjoint();
    let mut r = s.rapier();
    assert_eq!(r.steps_per_frame, scenes::SUBSTEPS);
    assert!(r.joints.is_empty());
    for _ in 0..90 {
        k.frame();
        r.frame();
    }
    // at rest the hinges are closed again
    let gap = s.anchor_gap(&k.world, &k.bodies);
    assert!(gap < 1e-3, "KJOINT2 hinges {gap} m apart at rest");
    for (w, bodies) in [(&k.world, &k.bodies), (&r.world, &r.bodies)] {
        for &b in &bodies[1..] {
            let body = &w.bodies[b];
            let y = body.translation().y;
            assert!(
                (0.0..0.2).contains(&y) && body.linvel().length() < 0.5,
                "capsule at y = {y}, speed {}",
                body.linvel().length()
            );
        }
    }
}

/// The contact bench's third reference takes every body through `get_mut` before each step,
/// as the joint set does: rapier's bookkeeping of those bodies must not move them (the
/// reference would then time another motion). Same bodies at the same places within a
/// micrometre after the landing (its contact graph, rebuilt at every step, may order the
/// contacts differently: round-off only).
#[test]
fn writing_the_bodies_leaves_the_reference_motion_alone() {
    let s = scenes::capsules_on_ground(2);
    let mut plain = s.rapier();
    let mut written = s.rapier_unjointed_written();
    assert!(written.write_bodies && !plain.write_bodies);
    for _ in 0..90 {
        plain.frame();
        written.frame();
    }
    let mut moved = 0.0f64;
    for (&a, &b) in plain.bodies.iter().zip(&written.bodies) {
        let (pa, pb) = (&plain.world.bodies[a], &written.world.bodies[b]);
        moved = moved.max((pa.translation() - pb.translation()).length() as f64);
        // the capsules fell: a frozen world would pass the comparison
        if pa.is_dynamic() {
            assert!(
                pa.translation().y < 0.3,
                "capsule at y = {}",
                pa.translation().y
            );
        }
    }
    assert!(moved < 1e-6, "the written world's bodies {moved} m away");
}

/// The resting pendulums are asleep on both sides once the bench has settled them (90
/// frames), so that the bench times a crowd at rest; and still hang where they were.
#[test]
fn the_resting_pendulums_are_asleep_on_both_sides_when_timed() {
    let s = scenes::resting_pendulums(12);
    let mut k = s.kjoint();
    let mut r = s.rapier();
    for _ in 0..90 {
        k.frame();
        r.frame();
    }
    for (side, world, bodies) in [
        ("KJOINT2", &k.world, &k.bodies),
        ("rapier", &r.world, &r.bodies),
    ] {
        for h in &bodies[1..] {
            let b = &world.bodies[*h];
            assert!(b.is_sleeping(), "{side}: a rod is awake");
            assert!(
                b.translation().y < -0.049 && b.translation().y > -0.051,
                "{side}: moved"
            );
        }
    }
}

/// `trees(k, depth)` is `k` copies of the leaves-first `tree(depth)` (what the harness's
/// comparison of the two relies on): after 10 frames the lone tree's rods have moved by
/// centimetres, and every rod of every tree is where the same rod of the lone tree is within
/// a thousandth of that (6.5 µm for 14 cm here; a rod hinged elsewhere or to another parent
/// would be centimetres off). Not within a micrometre over 30 frames as the chains: the f32
/// poses of a tree 0.6 m along z round otherwise than at z = 0, and the tree's swing
/// amplifies it to a fraction of a millimetre.
#[test]
fn each_of_the_trees_moves_as_the_lone_tree() {
    const FRAMES: usize = 10;
    let (k, depth) = (3, 3);
    let lone = scenes::tree(depth, TreeOrder::LeavesFirst);
    let many = scenes::trees(k, depth);
    let n = scenes::tree_size(depth);
    assert_eq!(many.joints.len(), k * n);
    let start = lone.kjoint();
    let mut a = lone.kjoint();
    let mut b = many.kjoint();
    let at = |w: &scenes::KjointWorld, body: usize| w.world.bodies[w.bodies[body]].translation();
    for _ in 0..FRAMES {
        a.frame();
        b.frame();
    }
    // the largest distance of a rod from where it started in the lone tree
    let moved = (0..n)
        .map(|i| (at(&a, 1 + i) - at(&start, 1 + i)).length())
        .fold(0.0, rapier_kjoint::rapier::math::Real::max);
    let mut worst: rapier_kjoint::rapier::math::Real = 0.0;
    for c in 0..k {
        let dz = 0.3 * c as rapier_kjoint::rapier::math::Real;
        for i in 0..n {
            let q = at(&b, 1 + c * n + i) - rapier_kjoint::rapier::math::Vector::new(0.0, 0.0, dz);
            worst = worst.max((at(&a, 1 + i) - q).length());
        }
    }
    println!("rods moved up to {moved} m; the trees' rods {worst} m from the lone tree's");
    assert!(moved > 1e-2, "the lone tree moved {moved} m");
    assert!(worst < 1e-3 * moved, "{worst} m apart for {moved} m moved");
}
