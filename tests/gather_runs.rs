//! The gather stage takes the bodies a run of 128 at a time (`GATHER_RUN` in
//! src/dynamics/substep.rs), and finds a dynamic body removed from rapier as it reaches it:
//! in a later run than the first, the runs before are gathered when it stops, analyses the
//! set again and gathers every body again. The velocity change rapier's contacts gave each
//! body over the last substep of the frame before (measured where that frame ended, and
//! rescaled to the new substep length where the frame's `dt` changed) must then be taken
//! once, not once per gather: a world whose body is removed that way must step bit for bit
//! as one whose set was told of the removal before the frame (analysed before it gathers).

#[path = "../benches/scenes.rs"]
mod scenes;

/// Every body's pose and velocity, bit for bit (widened to `f64`, exactly, in a
/// single-precision build), and the set's joint count.
fn state(w: &scenes::KjointWorld) -> (Vec<u64>, usize) {
    let mut bits = Vec::new();
    for (_, b) in w.world.bodies.iter() {
        let (t, r) = (b.translation(), b.rotation());
        let (v, a) = (b.linvel(), b.angvel());
        for x in [
            t.x, t.y, t.z, r.x, r.y, r.z, r.w, v.x, v.y, v.z, a.x, a.y, a.z,
        ] {
            bits.push(f64::from(x).to_bits());
        }
    }
    (bits, w.joints.len())
}

#[test]
fn a_body_removed_in_a_later_run_takes_the_contacts_change_once() {
    // 50 groups of three capsules resting on a box: 150 jointed bodies, the last group's in
    // the second run of 128
    let scene = scenes::capsules_on_ground(50);
    let (mut told, mut found) = (scene.kjoint(), scene.kjoint());
    for _ in 0..60 {
        told.frame();
        found.frame();
    }
    assert_eq!(state(&told), state(&found));
    // the last group's middle capsule leaves both worlds; the set of one is told at once,
    // the other's finds the body gone in its gather stage
    let last = *told.bodies.last().unwrap();
    let middle = told.bodies[told.bodies.len() - 2];
    assert_eq!(middle, found.bodies[found.bodies.len() - 2]);
    for w in [&mut told, &mut found] {
        w.world.remove_body(middle);
    }
    let detached = told.joints.remove_joints_attached_to_rigid_body(middle);
    assert_eq!(detached.len(), 2);
    // the next frames at 50 Hz rather than 60: the stored contact change rescaled
    let dt = 1.0 / 50.0;
    for _ in 0..5 {
        told.joints.step(&mut told.world, dt).expect("told");
        found.joints.step(&mut found.world, dt).expect("found");
    }
    let (told_state, told_joints) = state(&told);
    let (found_state, found_joints) = state(&found);
    assert_eq!((told_joints, found_joints), (98, 98));
    // the capsules of the first run rest on the ground held by their contacts: what the
    // solve took from them decides their velocities to the last bit
    assert!(told.world.bodies.get(last).is_some());
    assert_eq!(told_state.len(), found_state.len());
    let differing = (told_state.iter().zip(&found_state))
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differing,
        0,
        "{differing} of {} values differ",
        told_state.len()
    );
}
