//! Sleeping jointed islands (`dynamics::sleep`): an island at rest sleeps as a whole and
//! costs nothing, and anything that wakes one of its bodies wakes all of them.

mod common;

use common::{add, anchor_gap, joints, world};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{
    Dof, DofLaw, JointType, KjointHandle, KjointProperty, KjointSet, SubstepPhase,
};

const FRAME: f64 = 1.0 / 60.0;

/// A ball of 1 kg (radius 0.1 m) at `pos` that may sleep (rapier's default thresholds).
fn sleepy_ball(w: &mut PhysicsWorld, pos: Vector) -> RigidBodyHandle {
    w.insert(
        RigidBodyBuilder::dynamic().translation(pos),
        ColliderBuilder::ball(0.1).mass(1.0),
    )
    .0
}

/// `n` balls hung 0.5 m apart below the ground at `x` by spherical joints, each anchored at
/// the centre of the body above it (the first at the origin of the ground, shifted by `x`).
fn chain(
    w: &mut PhysicsWorld,
    set: &mut KjointSet,
    ground: RigidBodyHandle,
    x: Real,
    n: usize,
) -> (Vec<RigidBodyHandle>, Vec<KjointHandle>) {
    let mut balls = Vec::new();
    let mut hinges = Vec::new();
    let mut above = ground;
    for i in 0..n {
        let b = sleepy_ball(w, Vector::new(x, -0.5 * (i as Real + 1.0), 0.0));
        let anchor1 = if i == 0 {
            Vector::new(x, 0.0, 0.0)
        } else {
            Vector::ZERO
        };
        let prop = KjointProperty::new(JointType::Spherical);
        hinges.push(add(set, w, prop, above, b, |j| {
            j.local_anchor1(anchor1)
                .local_anchor2(Vector::new(0.0, 0.5, 0.0))
        }));
        balls.push(b);
        above = b;
    }
    (balls, hinges)
}

fn step(w: &mut PhysicsWorld, set: &mut KjointSet, frames: usize) {
    for _ in 0..frames {
        set.step(w, FRAME).expect("a sound step");
    }
}

fn largest_gap(set: &KjointSet) -> f64 {
    set.iter().map(|(_, j)| anchor_gap(j)).fold(0.0, f64::max)
}

#[test]
fn a_chain_at_rest_sleeps_whole_and_is_left_out_of_the_substeps() {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let (balls, hinges) = chain(&mut w, &mut set, ground, 0.0, 3);
    // rapier's thresholds: 0.05 m/s for 0.5 s. The chain starts at rest, so it sleeps
    // after its first 0.5 s (plus the settling of its sag, m·g/K, within a few substeps)
    step(&mut w, &mut set, 20);
    assert!(balls.iter().all(|b| !w.bodies[*b].is_sleeping()), "not yet");
    step(&mut w, &mut set, 40);
    assert!(
        balls.iter().all(|b| w.bodies[*b].is_sleeping()),
        "every ball of the chain sleeps after 1 s at rest"
    );
    let state = |set: &KjointSet, h| set.get(h).unwrap().state().unwrap().clone();
    let before: Vec<_> = hinges.iter().map(|h| state(&set, *h)).collect();
    let poses: Vec<_> = balls.iter().map(|b| *w.bodies[*b].position()).collect();
    step(&mut w, &mut set, 120);
    for ((h, s), (b, p)) in hinges.iter().zip(&before).zip(balls.iter().zip(&poses)) {
        let now = state(&set, *h);
        // left out of the substeps: the readout is the one of the step it fell asleep at
        assert_eq!(now.time, s.time, "{h:?} is not stepped while asleep");
        assert_eq!(w.bodies[*b].position(), p, "an asleep ball does not move");
    }
    // what the asleep joints carry: the top one the weight of the three balls
    let top = &before[0];
    let weight = 3.0 * 9.81;
    let f = (top.applied.0.iter().take(3).map(|f| f * f).sum::<f64>()).sqrt();
    assert!(
        (f - weight).abs() < 1e-3 * weight,
        "top joint carries {f} N"
    );
    assert!(largest_gap(&set) < 1e-3);
}

/// What [`shot_at_chain`] saw.
struct Shot {
    /// The substep (counted from the throw) after which rapier had woken the hit link.
    hit: Option<usize>,
    /// The substep after which every link was awake.
    all: Option<usize>,
    /// The largest anchor gap over every substep \[m\].
    gap: f64,
    /// How far the top link moved \[m\].
    moved: f64,
}

/// A ball without gravity thrown at 4 m/s at the lowest link of a 3-ball chain that has
/// rested 1 s (asleep by then, unless `sleepless`), followed for 2 s.
fn shot_at_chain(sleepless: bool) -> Shot {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let (balls, _) = chain(&mut w, &mut set, ground, 0.0, 3);
    if sleepless {
        for b in &balls {
            w.bodies[*b].activation_mut().normalized_linear_threshold = -1.0;
        }
    }
    step(&mut w, &mut set, 60);
    assert!(balls
        .iter()
        .all(|b| w.bodies[*b].is_sleeping() != sleepless));
    let top = w.bodies[balls[0]].translation();
    w.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-0.9, -1.5, 0.0))
            .linvel(Vector::new(4.0, 0.0, 0.0))
            .gravity_scale(0.0),
        ColliderBuilder::ball(0.1).mass(1.0),
    );
    let (mut hit, mut all) = (None, None);
    let mut substep = 0usize;
    let mut gap: f64 = 0.0;
    for _ in 0..120 {
        set.step_with(&mut w, FRAME, |phase, w, set| {
            if phase == SubstepPhase::After {
                let awake = |b: &RigidBodyHandle| !w.bodies[*b].is_sleeping();
                if hit.is_none() && awake(&balls[2]) {
                    hit = Some(substep);
                }
                if all.is_none() && balls.iter().all(awake) {
                    all = Some(substep);
                }
                gap = gap.max(largest_gap(set));
                substep += 1;
            }
            Ok::<(), rapier_kjoint::SimError>(())
        })
        .unwrap();
    }
    let moved = (w.bodies[balls[0]].translation() - top).length() as f64;
    Shot {
        hit,
        all,
        gap,
        moved,
    }
}

#[test]
fn a_ball_that_hits_one_link_wakes_the_whole_chain_which_holds() {
    let shot = shot_at_chain(false);
    let (hit, all) = (shot.hit.expect("the shot hit the chain"), shot.all.unwrap());
    // within a step too (rapier's active set read at every substep)
    assert_ne!(
        hit % 4,
        3,
        "the hit fell at a step's last substep: move the shot"
    );
    assert_eq!(
        all,
        hit + 1,
        "the set woke the whole chain at its next substep"
    );
    // it holds as the chain that never slept, but for the substep of the hit: rapier wakes
    // the link inside its step, after the joints' solve, so the link falls unsupported
    // over that substep (g·h = 0.04 m/s, carried into the next ones; 0.37 mm more here).
    // The hit itself opens both chains: rapier's contact moves the link within its substep
    // before any joint answers (README, "Joints against rapier's contacts")
    let awake = shot_at_chain(true);
    assert!(
        awake.gap > 1e-3,
        "the hit opens the awake chain: {} m",
        awake.gap
    );
    assert!(
        shot.gap < awake.gap + 0.5e-3,
        "largest anchor gap {} m, against {} m in the chain that never slept",
        shot.gap,
        awake.gap
    );
    assert!(
        shot.moved > 1e-3,
        "the hit reached the top link: {} m",
        shot.moved
    );
    assert!(
        (shot.moved - awake.moved).abs() < 0.1 * awake.moved,
        "top link moved {} m, against {} m",
        shot.moved,
        awake.moved
    );
}

#[test]
fn waking_one_body_by_hand_wakes_its_island_only() {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let (left, _) = chain(&mut w, &mut set, ground, 0.0, 3);
    let (right, _) = chain(&mut w, &mut set, ground, 2.0, 2);
    step(&mut w, &mut set, 60);
    assert!(left
        .iter()
        .chain(&right)
        .all(|b| w.bodies[*b].is_sleeping()));
    w.bodies[left[2]].set_linvel(Vector::new(0.5, 0.0, 0.0), true);
    step(&mut w, &mut set, 1);
    assert!(
        left.iter().all(|b| !w.bodies[*b].is_sleeping()),
        "left awake"
    );
    assert!(
        right.iter().all(|b| w.bodies[*b].is_sleeping()),
        "right asleep"
    );
    // the push travels up the chain through its joints, which hold
    step(&mut w, &mut set, 10);
    assert!(w.bodies[left[0]].linvel().length() > 1e-3);
    assert!(largest_gap(&set) < 1e-3);
}

/// A chain of 3 whose middle ball cannot sleep, a pendulum swinging, one at rest (all of
/// them unable to sleep with `sleepless`), stepped 2 s: the world and the three groups.
fn three_groups(sleepless: bool) -> (PhysicsWorld, [Vec<RigidBodyHandle>; 3]) {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let (stubborn, _) = chain(&mut w, &mut set, ground, 0.0, 3);
    w.bodies[stubborn[1]]
        .activation_mut()
        .normalized_linear_threshold = -1.0;
    let (swinging, _) = chain(&mut w, &mut set, ground, 2.0, 1);
    w.bodies[swinging[0]].set_linvel(Vector::new(0.0, 0.0, 1.0), true);
    let (resting, _) = chain(&mut w, &mut set, ground, 4.0, 1);
    if sleepless {
        for b in stubborn.iter().chain(&swinging).chain(&resting) {
            w.bodies[*b].activation_mut().normalized_linear_threshold = -1.0;
        }
    }
    step(&mut w, &mut set, 120);
    (w, [stubborn, swinging, resting])
}

#[test]
fn an_island_sleeps_only_when_all_of_it_can_and_changes_nothing_for_the_others() {
    let (w, [stubborn, swinging, resting]) = three_groups(false);
    assert!(stubborn.iter().all(|b| !w.bodies[*b].is_sleeping()));
    assert!(!w.bodies[swinging[0]].is_sleeping());
    assert!(w.bodies[resting[0]].is_sleeping());
    // the same bits for the bodies that stayed awake as where nothing could sleep
    let (v, _) = three_groups(true);
    for b in stubborn.iter().chain(&swinging) {
        assert_eq!(w.bodies[*b].position(), v.bodies[*b].position());
        assert_eq!(w.bodies[*b].linvel(), v.bodies[*b].linvel());
    }
    assert!(
        w.bodies[swinging[0]].linvel().length() > 0.1,
        "still swinging"
    );
}

#[test]
fn sensor_and_kinematic_joints_keep_their_island_awake() {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    set.add_sensor(7, rapier_kjoint::SensorCondition::Time(100.0))
        .unwrap();
    let b = sleepy_ball(&mut w, Vector::new(0.0, -0.5, 0.0));
    let prop = KjointProperty::new(JointType::Spherical).with_sensor(7);
    add(&mut set, &w, prop, ground, b, |j| {
        j.local_anchor2(Vector::new(0.0, 0.5, 0.0))
    });
    let crane = w.insert_body(RigidBodyBuilder::kinematic_velocity_based());
    let c = sleepy_ball(&mut w, Vector::new(2.0, -0.5, 0.0));
    let prop = KjointProperty::new(JointType::Spherical);
    add(&mut set, &w, prop, crane, c, |j| {
        j.local_anchor1(Vector::new(2.0, 0.0, 0.0))
            .local_anchor2(Vector::new(0.0, 0.5, 0.0))
    });
    // and, beside them, a pendulum like the first without its sensor
    let (plain, _) = chain(&mut w, &mut set, ground, 4.0, 1);
    step(&mut w, &mut set, 120);
    assert!(w.bodies[plain[0]].is_sleeping());
    assert!(
        !w.bodies[b].is_sleeping(),
        "a sensor may lock the joint at any time"
    );
    assert!(
        !w.bodies[c].is_sleeping(),
        "a kinematic body may move at any time"
    );
}

#[test]
fn a_joint_inserted_between_sleeping_bodies_wakes_them_into_one_island() {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let (a, _) = chain(&mut w, &mut set, ground, 0.0, 1);
    let (b, _) = chain(&mut w, &mut set, ground, 0.5, 1);
    step(&mut w, &mut set, 60);
    assert!(w.bodies[a[0]].is_sleeping() && w.bodies[b[0]].is_sleeping());
    // a free joint with a spring on x between the two balls (at rest as inserted)
    let prop = KjointProperty::new(JointType::Free).with_dof(Dof::Dx, DofLaw::spring(100.0));
    add(&mut set, &w, prop, a[0], b[0], |j| {
        j.local_anchor2(Vector::new(-0.5, 0.0, 0.0))
    });
    step(&mut w, &mut set, 1);
    assert!(!w.bodies[a[0]].is_sleeping() && !w.bodies[b[0]].is_sleeping());
    // at rest again, the two pendulums and the spring sleep as one island
    step(&mut w, &mut set, 60);
    assert!(w.bodies[a[0]].is_sleeping() && w.bodies[b[0]].is_sleeping());
    w.bodies[b[0]].wake_up(true);
    step(&mut w, &mut set, 1);
    assert!(!w.bodies[a[0]].is_sleeping(), "woken through the spring");
}

/// Two 2-link chains whose joints are inserted in turn (A1, B1, A2, B2), then a pendulum C:
/// A and C swing, B rests (with `sleepless`, nothing can sleep), stepped 2 s. Once B
/// sleeps, the stages step A's joints with B1 among them (inside A's run, its sleeping
/// bodies as fixed ones) and C in a tile of its own.
fn interleaved(sleepless: bool) -> (PhysicsWorld, KjointSet, [Vec<RigidBodyHandle>; 3]) {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let ball = |w: &mut PhysicsWorld, x: Real, y: Real| sleepy_ball(w, Vector::new(x, y, 0.0));
    let (a1, a2) = (ball(&mut w, 0.0, -0.5), ball(&mut w, 0.0, -1.0));
    let (b1, b2) = (ball(&mut w, 2.0, -0.5), ball(&mut w, 2.0, -1.0));
    let c1 = ball(&mut w, 4.0, -0.5);
    let link = |set: &mut KjointSet, w: &PhysicsWorld, above, below, x: Real| {
        let prop = KjointProperty::new(JointType::Spherical);
        add(set, w, prop, above, below, |j| {
            j.local_anchor1(Vector::new(x, 0.0, 0.0))
                .local_anchor2(Vector::new(0.0, 0.5, 0.0))
        });
    };
    link(&mut set, &w, ground, a1, 0.0);
    link(&mut set, &w, ground, b1, 2.0);
    link(&mut set, &w, a1, a2, 0.0);
    link(&mut set, &w, b1, b2, 0.0);
    link(&mut set, &w, ground, c1, 4.0);
    w.bodies[a2].set_linvel(Vector::new(0.0, 0.0, 1.0), true);
    w.bodies[c1].set_linvel(Vector::new(1.0, 0.0, 0.0), true);
    let groups = [vec![a1, a2], vec![b1, b2], vec![c1]];
    if sleepless {
        for b in groups.iter().flatten() {
            w.bodies[*b].activation_mut().normalized_linear_threshold = -1.0;
        }
    }
    step(&mut w, &mut set, 60);
    (w, set, groups)
}

#[test]
fn an_asleep_joint_between_the_joints_of_an_awake_island_stays_asleep() {
    let (mut w, mut set, [a, b, c]) = interleaved(false);
    let (mut v, mut unset, _) = interleaved(true);
    assert!(b.iter().all(|h| w.bodies[*h].is_sleeping()));
    let poses: Vec<_> = b.iter().map(|h| *w.bodies[*h].position()).collect();
    step(&mut w, &mut set, 60);
    step(&mut v, &mut unset, 60);
    for (h, p) in b.iter().zip(&poses) {
        assert!(w.bodies[*h].is_sleeping());
        assert_eq!(w.bodies[*h].position(), p);
    }
    // the swinging chain and pendulum: the same bits as where nothing sleeps
    for h in a.iter().chain(&c) {
        assert!(!w.bodies[*h].is_sleeping());
        assert_eq!(w.bodies[*h].position(), v.bodies[*h].position());
    }
    assert!(largest_gap(&set) < 1e-3);
}

/// The frame at which a damped pendulum pushed at the start falls asleep, with a joint
/// inserted elsewhere at frame 25 and removed at frame 31 (`churn`: after it came to rest,
/// about frame 10), or without.
fn frame_asleep(churn: bool) -> usize {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let b = w
        .insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, -0.5, 0.0))
                .linear_damping(5.0)
                .linvel(Vector::new(0.0, 0.0, 0.3)),
            ColliderBuilder::ball(0.1).mass(1.0),
        )
        .0;
    let prop = KjointProperty::new(JointType::Spherical);
    add(&mut set, &w, prop, ground, b, |j| {
        j.local_anchor2(Vector::new(0.0, 0.5, 0.0))
    });
    let other = sleepy_ball(&mut w, Vector::new(3.0, -0.5, 0.0));
    let mut extra = None;
    for frame in 0..240 {
        if churn && frame == 25 {
            let prop = KjointProperty::new(JointType::Spherical);
            extra = Some(add(&mut set, &w, prop, ground, other, |j| {
                j.local_anchor1(Vector::new(3.0, 0.0, 0.0))
                    .local_anchor2(Vector::new(0.0, 0.5, 0.0))
            }));
        }
        if churn && frame == 31 {
            set.remove(extra.unwrap()).unwrap();
        }
        step(&mut w, &mut set, 1);
        if w.bodies[b].is_sleeping() {
            return frame;
        }
    }
    panic!("never slept");
}

#[test]
fn a_change_elsewhere_does_not_restart_an_islands_rest() {
    let (quiet, churned) = (frame_asleep(false), frame_asleep(true));
    // moving for its first ≈0.17 s, asleep 0.5 s after it came to rest
    assert!(quiet > 35, "asleep at frame {quiet}");
    assert!(quiet.abs_diff(churned) <= 1, "{quiet} against {churned}");
}

/// A two-link URDF pendulum hanging straight down from a fixed base, loaded with
/// `can_sleep` as given, stepped 1.5 s: whether its links sleep.
fn urdf_pendulum_sleeps(can_sleep: bool) -> bool {
    use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
    let link = |name: &str| {
        format!(
            r#"<link name="{name}"><inertial><origin xyz="0 0 -0.25"/><mass value="1"/>
               <inertia ixx="0.02" iyy="0.02" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>"#
        )
    };
    let joint = |name: &str, parent: &str, child: &str, z: f64| {
        format!(
            r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>
               <origin xyz="0 0 {z}"/><axis xyz="1 0 0"/>
               <limit lower="-3" upper="3" effort="10" velocity="10"/></joint>"#
        )
    };
    let text = format!(
        r#"<robot name="pendulum"><link name="base"/>{}{}{}{}</robot>"#,
        link("upper"),
        link("lower"),
        joint("shoulder", "base", "upper", 0.0),
        joint("elbow", "upper", "lower", -0.5)
    );
    let options = UrdfOptions {
        can_sleep,
        ..Default::default()
    };
    let robot = UrdfRobot::from_str(&text, "pendulum.urdf", ".", &options).unwrap();
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..Default::default()
    };
    let mut set = joints(4);
    let handles = robot.insert(&mut w, &mut set).unwrap();
    step(&mut w, &mut set, 90);
    let links = [&handles.links["upper"], &handles.links["lower"]];
    let asleep = links
        .iter()
        .filter(|h| w.bodies[***h].is_sleeping())
        .count();
    assert!(asleep == 0 || asleep == 2, "one link of the two asleep");
    asleep == 2
}

#[test]
fn a_urdf_robot_sleeps_only_when_its_options_let_it() {
    assert!(urdf_pendulum_sleeps(true));
    assert!(!urdf_pendulum_sleeps(false));
}

/// A pendulum of one sleepy ball 0.5 m below `pivot` (a body of the world), its joint's
/// handle.
fn pendulum_from(
    w: &mut PhysicsWorld,
    set: &mut KjointSet,
    pivot: RigidBodyHandle,
    at: Vector,
) -> (RigidBodyHandle, KjointHandle) {
    let b = sleepy_ball(w, at - Vector::new(0.0, 0.5, 0.0));
    let anchor1 = at - w.bodies[pivot].translation();
    let prop = KjointProperty::new(JointType::Spherical);
    let j = add(set, w, prop, pivot, b, |j| {
        j.local_anchor1(anchor1)
            .local_anchor2(Vector::new(0.0, 0.5, 0.0))
    });
    (b, j)
}

#[test]
fn a_tray_under_a_box_that_never_sleeps_is_never_put_to_sleep() {
    let (mut w, mut set, tray, boxed) = tray_and_box(false);
    // rapier keeps simulating a body that touches an awake one: asleep, it would fall with
    // its joint left out
    for frame in 0..180 {
        step(&mut w, &mut set, 1);
        assert!(!w.bodies[tray].is_sleeping(), "frame {frame}");
    }
    let y = w.bodies[tray].translation().y;
    assert!(y.abs() < 1e-3, "the tray hangs where it was: y = {y} m");
    // put to sleep by hand, it is woken and held
    w.bodies[tray].sleep();
    step(&mut w, &mut set, 30);
    assert!(!w.bodies[tray].is_sleeping());
    let y = w.bodies[tray].translation().y;
    assert!(
        y.abs() < 1e-3,
        "the tray still hangs where it was: y = {y} m"
    );
    assert!(w.bodies[boxed].translation().y > 0.1, "the box on it");
}

#[test]
fn a_wheel_turning_slowly_is_not_stopped() {
    // a ball of radius 1 m on a revolute joint about x through its centre, turning at
    // 0.3 rad/s: its rim moves at 0.3 m/s, beyond rapier's 0.05 m/s (its angular speed
    // is below the 0.5 rad/s threshold, which rapier applies to bodies without colliders)
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let wheel = w
        .insert(
            RigidBodyBuilder::dynamic().angvel(Vector::new(0.3, 0.0, 0.0)),
            ColliderBuilder::ball(1.0).mass(1.0),
        )
        .0;
    let prop = KjointProperty::new(JointType::Revolute);
    add(&mut set, &w, prop, ground, wheel, |j| j);
    step(&mut w, &mut set, 180);
    assert!(!w.bodies[wheel].is_sleeping());
    let wx = w.bodies[wheel].angvel().x;
    assert!((wx - 0.3).abs() < 0.01, "ω = {wx} rad/s");
}

#[test]
fn a_force_on_a_sleeping_pendulum_wakes_it_for_good() {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let (b, _) = pendulum_from(&mut w, &mut set, ground, Vector::ZERO);
    step(&mut w, &mut set, 60);
    assert!(w.bodies[b].is_sleeping());
    // 0.5 N sideways on 1 kg hung 0.5 m: it settles 0.5·0.5/9.81 = 25 mm aside, swinging
    // about that
    w.bodies[b].add_force(Vector::new(0.0, 0.0, 0.5), true);
    step(&mut w, &mut set, 6);
    assert!(!w.bodies[b].is_sleeping(), "woken and its rest restarted");
    let mut most: Real = 0.0;
    for _ in 0..30 {
        step(&mut w, &mut set, 1);
        most = most.max(w.bodies[b].translation().z);
    }
    assert!(most > 0.02, "it swung out to {most} m");
}

#[test]
fn a_joint_removed_from_a_sleeping_island_lets_it_move() {
    // a ball held at (0.2, −0.5) by two pivots, at (0, 0) and (0.4, 0): static until one
    // joint goes, then it swings about the other
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let b = sleepy_ball(&mut w, Vector::new(0.2, -0.5, 0.0));
    let prop = KjointProperty::new(JointType::Spherical);
    add(&mut set, &w, prop.clone(), ground, b, |j| {
        j.local_anchor2(Vector::new(-0.2, 0.5, 0.0))
    });
    let right = add(&mut set, &w, prop, ground, b, |j| {
        j.local_anchor1(Vector::new(0.4, 0.0, 0.0))
            .local_anchor2(Vector::new(0.2, 0.5, 0.0))
    });
    step(&mut w, &mut set, 60);
    assert!(w.bodies[b].is_sleeping());
    set.remove(right).unwrap();
    step(&mut w, &mut set, 30);
    assert!(!w.bodies[b].is_sleeping());
    let dx = (w.bodies[b].translation().x - 0.2).abs();
    assert!(dx > 0.05, "it swung: {dx} m");
}

#[test]
fn a_sleeping_islands_fixed_side_switched_moved_or_removed_wakes_it() {
    for change in ["dynamic", "moved", "removed"] {
        let (mut w, _) = world(Vector::new(0.0, -9.81, 0.0));
        let mut set = joints(4);
        // (its mass for when it is switched to dynamic)
        let pivot = w.insert_body(
            RigidBodyBuilder::fixed()
                .translation(Vector::new(0.0, 1.0, 0.0))
                .additional_mass(1.0),
        );
        let (b, j) = pendulum_from(&mut w, &mut set, pivot, Vector::new(0.0, 1.0, 0.0));
        step(&mut w, &mut set, 60);
        assert!(w.bodies[b].is_sleeping(), "{change}");
        match change {
            "dynamic" => w.bodies[pivot].set_body_type(RigidBodyType::Dynamic, false),
            "moved" => w.bodies[pivot].set_translation(Vector::new(0.05, 1.0, 0.0), false),
            _ => {
                w.remove_body(pivot);
            }
        }
        step(&mut w, &mut set, 30);
        assert!(!w.bodies[b].is_sleeping(), "{change}: woken");
        match change {
            // falls with its pivot, held by the joint
            "dynamic" => {
                let (yb, yp) = (w.bodies[b].translation().y, w.bodies[pivot].translation().y);
                assert!(
                    yb < 0.4 && (yp - yb - 0.5).abs() < 1e-3,
                    "{change}: {yb}, {yp}"
                );
            }
            // pulled after it
            "moved" => assert!(w.bodies[b].translation().x > 0.01, "{change}"),
            // its joint leaves the set, with its event
            _ => {
                assert!(set.get(j).is_none(), "{change}");
                assert!(set.drain_events().iter().any(|e| matches!(
                    e.kind,
                    rapier_kjoint::KjointEventKind::JointDetached { .. }
                )));
            }
        }
    }
}

#[test]
fn sensors_fire_while_every_joint_sleeps() {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    set.add_sensor(3, rapier_kjoint::SensorCondition::Time(2.0))
        .unwrap();
    let (b, _) = pendulum_from(&mut w, &mut set, ground, Vector::ZERO);
    step(&mut w, &mut set, 150);
    assert!(w.bodies[b].is_sleeping());
    assert!(set.sensor_active(3), "the sensor fired at 2 s");
}

#[test]
fn islands_sleeping_and_waking_do_not_repeat_the_start_notices() {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    // a stiff spring on a free rotation of a light rod that never sleeps: the set notices
    // at its start that the substep does not resolve it
    let rod = common::cuboid(
        &mut w,
        0.01,
        Vector::new(0.02, 0.2, 0.02),
        Vector::new(2.0, -0.2, 0.0),
    );
    let prop = KjointProperty::new(JointType::Revolute).with_dof(Dof::Rx, DofLaw::spring(1e6));
    add(&mut set, &w, prop, ground, rod, |j| {
        j.local_anchor1(Vector::new(2.0, 0.0, 0.0))
            .local_anchor2(Vector::new(0.0, 0.2, 0.0))
    });
    let (b, _) = pendulum_from(&mut w, &mut set, ground, Vector::ZERO);
    let notices = |set: &mut KjointSet| {
        set.drain_events()
            .iter()
            .filter(|e| {
                matches!(
                    e.kind,
                    rapier_kjoint::KjointEventKind::StiffnessBeyondSubstep { .. }
                )
            })
            .count()
    };
    step(&mut w, &mut set, 1);
    let first = notices(&mut set);
    assert!(first > 0, "the stiff spring is noticed");
    for _ in 0..3 {
        step(&mut w, &mut set, 60);
        assert!(w.bodies[b].is_sleeping());
        w.bodies[b].wake_up(true);
    }
    assert_eq!(notices(&mut set), 0, "given once");
}

/// A tray hung from its centre 0.5 m above by a spherical joint, and a box of 0.5 kg lying
/// on it (`box_sleeps`: whether the box may sleep).
fn tray_and_box(box_sleeps: bool) -> (PhysicsWorld, KjointSet, RigidBodyHandle, RigidBodyHandle) {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let tray = w
        .insert(
            RigidBodyBuilder::dynamic(),
            ColliderBuilder::cuboid(0.5, 0.05, 0.5).mass(1.0),
        )
        .0;
    let prop = KjointProperty::new(JointType::Spherical);
    add(&mut set, &w, prop, ground, tray, |j| {
        j.local_anchor1(Vector::new(0.0, 0.5, 0.0))
            .local_anchor2(Vector::new(0.0, 0.5, 0.0))
    });
    let boxed = w
        .insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, 0.15, 0.0))
                .can_sleep(box_sleeps),
            ColliderBuilder::cuboid(0.1, 0.1, 0.1).mass(0.5),
        )
        .0;
    (w, set, tray, boxed)
}

#[test]
fn a_tray_and_the_box_at_rest_on_it_sleep_together() {
    // the set's velocity writes keep resetting the tray's rapier timer, so rapier alone
    // would never put the box and the tray to sleep: the set takes the box along
    let (mut w, mut set, tray, boxed) = tray_and_box(true);
    step(&mut w, &mut set, 120);
    assert!(w.bodies[tray].is_sleeping() && w.bodies[boxed].is_sleeping());
    let y = w.bodies[tray].translation().y;
    assert!(y.abs() < 1e-3, "the tray hangs where it was: y = {y} m");
    // and both wake when the box is pushed
    w.bodies[boxed].set_linvel(Vector::new(0.2, 0.0, 0.0), true);
    step(&mut w, &mut set, 2);
    assert!(!w.bodies[tray].is_sleeping() && !w.bodies[boxed].is_sleeping());
}

#[test]
fn an_island_held_by_rapiers_joint_to_an_awake_body_stays_awake() {
    // ball A on a KJOINT2 joint, ball B that cannot sleep swinging below it on rapier's
    // own spherical joint
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let (a, _) = pendulum_from(&mut w, &mut set, ground, Vector::ZERO);
    let b = w.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, -1.0, 0.0))
            .linvel(Vector::new(0.0, 0.0, 0.5))
            .can_sleep(false)
            .additional_mass(0.1),
    );
    let joint = SphericalJointBuilder::new()
        .local_anchor1(Vector::new(0.0, -0.5, 0.0))
        .local_anchor2(Vector::ZERO);
    w.impulse_joints.insert(a, b, joint, true);
    for frame in 0..120 {
        step(&mut w, &mut set, 1);
        assert!(!w.bodies[a].is_sleeping(), "frame {frame}");
    }
}

#[test]
fn a_clone_keeps_the_islands_rest() {
    let frame_of_sleep = |clone_at: Option<usize>| {
        let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
        let mut set = joints(4);
        let (b, _) = pendulum_from(&mut w, &mut set, ground, Vector::ZERO);
        w.bodies[b].set_linvel(Vector::new(0.0, 0.0, 0.3), true);
        w.bodies[b].set_linear_damping(5.0);
        for frame in 0..240 {
            if Some(frame) == clone_at {
                set = set.clone();
            }
            step(&mut w, &mut set, 1);
            if w.bodies[b].is_sleeping() {
                return frame;
            }
        }
        panic!("never slept");
    };
    let original = frame_of_sleep(None);
    // cloned at rest, before it sleeps
    let cloned = frame_of_sleep(Some(original - 10));
    assert!(
        original.abs_diff(cloned) <= 1,
        "{original} against {cloned}"
    );
}

#[test]
fn a_body_woken_in_a_hook_within_a_step_is_held_at_once() {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let (b, _) = pendulum_from(&mut w, &mut set, ground, Vector::ZERO);
    step(&mut w, &mut set, 60);
    assert!(w.bodies[b].is_sleeping());
    let rest = w.bodies[b].translation().y;
    // a sideways force from the third substep of a step on: the ball swings out and up,
    // never down (it would fall unsupported over a substep its joint was left out of)
    let mut substep = 0;
    let mut lowest = rest;
    for _ in 0..3 {
        set.step_with(&mut w, FRAME, |phase, w, _| {
            match phase {
                SubstepPhase::Before if substep == 2 => {
                    w.bodies[b].add_force(Vector::new(0.0, 0.0, 0.5), true);
                }
                SubstepPhase::After => {
                    lowest = lowest.min(w.bodies[b].translation().y);
                    substep += 1;
                }
                _ => {}
            }
            Ok::<(), rapier_kjoint::SimError>(())
        })
        .unwrap();
    }
    assert!(!w.bodies[b].is_sleeping());
    assert!(rest - lowest < 1e-5, "it dropped {} m", rest - lowest);
}

#[test]
fn a_still_kinematic_slab_links_the_tray_to_a_ball_that_never_sleeps() {
    // the tray and its box rest on a kinematic slab that does not move, and a ball that
    // cannot sleep lies on the slab 2 m away: rapier's island holds all four (kinematic
    // bodies are in rapier's islands), so it never sleeps, nor may the tray
    let (mut w, mut set, tray, boxed) = tray_and_box(true);
    let slab = w
        .insert(
            RigidBodyBuilder::kinematic_velocity_based().translation(Vector::new(0.0, -0.1, 0.0)),
            ColliderBuilder::cuboid(3.0, 0.05, 3.0),
        )
        .0;
    w.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(2.0, 0.05, 0.0))
            .can_sleep(false),
        ColliderBuilder::ball(0.1).mass(1.0),
    );
    let mut lowest: Real = 0.0;
    for frame in 0..240 {
        step(&mut w, &mut set, 1);
        assert!(!w.bodies[tray].is_sleeping(), "frame {frame}");
        lowest = lowest.min(w.bodies[tray].translation().y);
    }
    assert!(lowest > -1e-3, "the tray held: lowest {lowest} m");
    assert!(!w.bodies[boxed].is_sleeping() && !w.bodies[slab].is_moving());
}

/// A door of 20 kg (0.8 m × 2 m × 4 cm) hinged at its edge about the vertical, at rest,
/// stepped until the step that puts it to sleep: the world, the set, the door and its hinge.
fn sleeping_door() -> (PhysicsWorld, KjointSet, RigidBodyHandle, KjointHandle) {
    let (mut w, ground) = world(Vector::new(0.0, -9.81, 0.0));
    let mut set = joints(4);
    let door = w
        .insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(0.4, 1.0, 0.0)),
            ColliderBuilder::cuboid(0.4, 1.0, 0.02).mass(20.0),
        )
        .0;
    let hinge = add(
        &mut set,
        &w,
        KjointProperty::new(JointType::Revolute),
        ground,
        door,
        |j| {
            j.world_frame1(Rotation::from_rotation_arc(Vector::X, Vector::Y))
                .local_anchor1(Vector::new(0.0, 1.0, 0.0))
                .local_anchor2(Vector::new(-0.4, 0.0, 0.0))
        },
    );
    for _ in 0..120 {
        step(&mut w, &mut set, 1);
        if w.bodies[door].is_sleeping() {
            return (w, set, door, hinge);
        }
    }
    panic!("the door at rest never fell asleep");
}

/// Woken by hand right after it fell asleep (before the set had seen it asleep), the door
/// stays awake for its `time_until_sleep` (0.5 s) again, as rapier's timer of a body does:
/// it fell straight back asleep at the end of the next step.
#[test]
fn a_wake_right_after_falling_asleep_restarts_the_rest() {
    let (mut w, mut set, door, _) = sleeping_door();
    let until = w.bodies[door].activation().time_until_sleep as f64;
    w.bodies[door].wake_up(true);
    let mut awake = 0;
    while !w.bodies[door].is_sleeping() && awake < 120 {
        step(&mut w, &mut set, 1);
        awake += 1;
    }
    let frames = (until / FRAME).round() as usize;
    assert!(
        (frames..=frames + 2).contains(&awake),
        "awake {awake} frames, rest of {frames} expected"
    );
}

/// A slow push added with a wake every frame (`add_torque(…, true)`, as a game pushes a door)
/// keeps the door awake, as it keeps a body without joints awake: 0.2 N·m on the door's
/// `I = m·(w² + t²)/12 + m·(w/2)² = 4.267 kg·m²` turns it by `T·t²/(2·I)` = 0.0937 rad in
/// 2 s. It read 0.007 rad when the island went back to sleep every 0.5 s at rest by the
/// speed rule (0.2 N·m is far below it: 0.047 rad/s² from rest).
#[test]
fn a_push_with_a_wake_every_frame_keeps_the_door_moving() {
    let (mut w, mut set, door, hinge) = sleeping_door();
    let torque = 0.2;
    let mut asleep = 0;
    for _ in 0..120 {
        let b = &mut w.bodies[door];
        b.reset_torques(false);
        b.add_torque(Vector::new(0.0, torque, 0.0), true);
        step(&mut w, &mut set, 1);
        asleep += usize::from(w.bodies[door].is_sleeping());
    }
    assert_eq!(asleep, 0, "frames ending asleep while pushed");
    let inertia = 20.0 * (0.8f64 * 0.8 + 0.04 * 0.04) / 12.0 + 20.0 * 0.4 * 0.4;
    let expected = torque as f64 * 2.0 * 2.0 / (2.0 * inertia);
    let q = set.get(hinge).unwrap().state().unwrap().q[Dof::Rx];
    assert!(
        (q - expected).abs() < 0.01 * expected,
        "turned {q} rad, {expected} expected"
    );
}
