//! The store stage leaves each substep's transmitted force and work in the set's substep data,
//! and the next substep writes them into the joint records: `KjointSet::step` writes them all
//! at the end of the step, `step_with` before each hook; and `step` writes the readouts at its
//! last substep only (the substeps before write those their checks read). What a user reads
//! after a step — every joint's readout and energies, every body's motion — must be the same
//! bit for bit whichever way the results reached the records.

#[path = "../benches/scenes.rs"]
mod scenes;

use rapier_kjoint::law::BreakCriterion;
use rapier_kjoint::rapier::math::{Rotation, Vector};
use rapier_kjoint::{
    JointState, JointType, KjointBuilder, KjointProperty, KjointSet, SubstepPhase,
};

/// Everything a user can read after `frames` frames, stepped with `step` or with `step_with`
/// and a hook that reads every joint's readout after each substep.
fn run(mut w: scenes::KjointWorld, frames: usize, with_hook: bool) -> (Vec<String>, usize) {
    let mut hook_reads = 0;
    for _ in 0..frames {
        if with_hook {
            w.joints
                .step_with(
                    &mut w.world,
                    scenes::FRAME,
                    |phase, _, set: &mut KjointSet| {
                        if phase == SubstepPhase::After {
                            hook_reads += set.iter().filter(|(_, j)| j.state().is_some()).count();
                        }
                        Ok::<(), rapier_kjoint::SimError>(())
                    },
                )
                .expect("frame");
        } else {
            w.frame();
        }
    }
    let mut seen: Vec<String> = w
        .joints
        .iter()
        .map(|(_, j)| {
            let s: &JointState = j.state().expect("a readout after the first substep");
            // Debug prints every f64 exactly (shortest round-trip form)
            format!(
                "{} {:?} {:?} {:?}",
                j.name,
                s,
                j.energy(),
                j.state().map(|s| s.applied)
            )
        })
        .collect();
    for h in &w.bodies {
        let b = &w.world.bodies[*h];
        let (t, v) = (b.translation(), b.linvel());
        seen.push(format!(
            "{:?}",
            [t.x, t.y, t.z, v.x, v.y, v.z].map(f64::from)
        ));
    }
    (seen, hook_reads)
}

fn same_both_ways(
    scene: &scenes::Scene,
    frames: usize,
    mut tweak: impl FnMut(&mut scenes::KjointWorld),
) {
    let mut a = scene.kjoint();
    let mut b = scene.kjoint();
    tweak(&mut a);
    tweak(&mut b);
    let joints = a.joints.len();
    let (deferred, _) = run(a, frames, false);
    let (folded, reads) = run(b, frames, true);
    // the hook did read readouts every substep (the folded run's records were current)
    assert_eq!(reads, joints * frames * scenes::SUBSTEPS);
    assert_eq!(deferred.len(), folded.len());
    for (d, f) in deferred.iter().zip(&folded) {
        assert_eq!(d, f, "step() and step_with() disagree");
    }
}

#[test]
fn a_chain_reads_the_same_after_step_and_step_with() {
    same_both_ways(&scenes::chain(30), 20, |_| {});
}

#[test]
fn capsules_on_the_ground_read_the_same_after_step_and_step_with() {
    // rapier's contacts act after the joint solve: the end-rate correction is not zero
    same_both_ways(&scenes::capsules_on_ground(4), 40, |_| {});
}

#[test]
fn a_chain_that_breaks_reads_the_same_after_step_and_step_with() {
    // the middle link's joint carries about the weight of 15 rods (14.7 N hanging straight,
    // less at 30°): it breaks at 10 N, and the set is re-analysed while the other joints
    // have results pending
    let scene = scenes::chain(30);
    let mut broke = Vec::new();
    for with_hook in [false, true] {
        let mut w = scene.kjoint();
        // joint 15 again, as `Scene::kjoint` built it, with a failure criterion
        let spec = &scene.joints[15];
        let scenes::JointKind::Revolute { axis } = spec.kind else {
            panic!("the chain's joints are revolute")
        };
        let builder =
            KjointBuilder::new(KjointProperty::new(JointType::Revolute).with_kn(scene.kn))
                .world_frame1(Rotation::from_rotation_arc(Vector::X, axis.normalize()))
                .local_anchor1(spec.anchor1)
                .local_anchor2(spec.anchor2)
                .break_when(BreakCriterion::force(10.0));
        w.joints.remove(w.handles[15]);
        let (b1, b2) = (w.bodies[spec.body1], w.bodies[spec.body2]);
        w.handles[15] = w
            .joints
            .insert(builder, b1, b2, &w.world.bodies)
            .expect("insert");
        let joints_before = w.joints.len();
        let (seen, _) = run(w, 10, with_hook);
        broke.push((joints_before, seen));
    }
    assert_eq!(broke[0].0, 30);
    // one joint fewer in the readouts: it broke, in both runs
    assert_eq!(broke[0].1.len(), 29 + 31);
    assert_eq!(broke[0].1, broke[1].1);
}

#[test]
fn a_chain_with_the_radioss_start_reads_the_same_after_step_and_step_with() {
    // the start's kick reads the first substep's transmitted forces, and the first substep
    // of a plain `step` writes no readout: the kick must not depend on one
    same_both_ways(&scenes::chain(30), 5, |w| {
        let mut s = *w.joints.settings();
        s.radioss_start = true;
        w.joints.set_settings(s);
    });
}
