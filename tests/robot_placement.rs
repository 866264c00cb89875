//! A scene's `[[robots]]` entry placed (`position`, `rotation`) and named (`name`): two
//! copies of the URDF arm side by side, `left` and `right`, 1 m apart and the right one
//! turned 90° about z. What a user looks at: where the bodies stand once loaded (each link
//! where the unplaced robot's is, moved by the placement), the joints of both robots in the
//! run under their prefixed names, holding under gravity as the unplaced arm's do, and the
//! placed arms moving as the unplaced one does, moved; and the errors of a wrong entry, at
//! their field and line.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

use nalgebra::{UnitQuaternion, Vector3};
use rapier_kjoint::dynamics::KjointEvent;
use rapier_kjoint::law::Dof;
use rapier_kjoint::output::{Observer, OutputError};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::scene::{self, BuiltScene, RunOptions, SceneError};
use rapier_kjoint::KjointSet;
use std::collections::BTreeMap;
use std::path::PathBuf;

mod common;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The shipped arm's path, as a TOML string.
fn arm() -> String {
    format!(
        "{:?}",
        root().join("assets/urdf/arm.urdf").display().to_string()
    )
}

/// The settings of the shipped URDF arm scene (`assets/scenes/urdf_arm.toml`): 60 Hz
/// frames of 4 substeps, z-up gravity; 1 s.
const SETTINGS: &str = "dt = 0.016666666666666666\nsubsteps = 4\nduration = 1.0\n\
                        gravity = [0.0, 0.0, -9.81]\n";

/// Writes `text` to `name` and loads and builds it.
fn build(name: &str, text: &str) -> Result<BuiltScene, SceneError> {
    // a file of its own per call: the tests run in parallel and several build
    // `unplaced.toml` with different options (one read another's half-written file:
    // "missing field `duration`")
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = format!("robot-placement/{call}");
    let path = common::cli::temp_file(&dir, name, text);
    let (sc, src) = scene::load(&path)?;
    scene::build(&sc, &src)
}

/// The error of the scene `text` (written to `name`).
fn error(name: &str, text: &str) -> SceneError {
    match build(name, text) {
        Ok(_) => panic!("{name}: accepted:\n{text}"),
        Err(e) => e,
    }
}

/// 1-based line of the `n`-th (0-based) line containing `needle`.
fn nth_line_of(text: &str, needle: &str, n: usize) -> usize {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.contains(needle))
        .nth(n)
        .unwrap_or_else(|| panic!("`{needle}` not {n} times in the text"))
        .0
        + 1
}

fn line_of(text: &str, needle: &str) -> usize {
    nth_line_of(text, needle, 0)
}

/// A rigid placement in f64: rotation then translation.
#[derive(Clone, Copy)]
struct Place {
    rot: UnitQuaternion<f64>,
    pos: Vector3<f64>,
}

impl Place {
    fn new(pos: [f64; 3], z_angle: f64) -> Place {
        Place {
            rot: UnitQuaternion::from_axis_angle(&Vector3::z_axis(), z_angle),
            pos: Vector3::from(pos),
        }
    }
    fn point(&self, p: Vector3<f64>) -> Vector3<f64> {
        self.rot * p + self.pos
    }
}

fn v64(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x as f64, v.y as f64, v.z as f64)
}

fn q64(q: Rotation) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        q.w as f64, q.x as f64, q.y as f64, q.z as f64,
    ))
}

/// A joint's frame as the state reports it (`[x, y, z, w]`).
fn frame64(f: [f64; 4]) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(f[3], f[0], f[1], f[2]))
}

fn body(built: &BuiltScene, name: &str) -> RigidBodyHandle {
    built
        .bodies
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, h)| *h)
        .unwrap_or_else(|| panic!("no body `{name}` in {:?}", names(built)))
}

fn names(built: &BuiltScene) -> Vec<&str> {
    built.bodies.iter().map(|(n, _)| n.as_str()).collect()
}

/// The arm's links and joints, as its file names them.
const LINKS: [&str; 4] = ["base_link", "upper_arm", "forearm", "hand"];
const JOINTS: [&str; 3] = ["elbow", "shoulder", "wrist"];

/// A body's pose: position and rotation.
type BodyPose = (Vector3<f64>, UnitQuaternion<f64>);

/// A joint's DOF values and its frame in the world.
type JointRecord = ([f64; 6], UnitQuaternion<f64>);

/// What a run showed, per joint and per body, at every substep.
#[derive(Default, Clone)]
struct Watch {
    /// Bodies followed, by name.
    bodies: Vec<(String, RigidBodyHandle)>,
    /// Per record: time, per followed body its pose (position, rotation).
    poses: Vec<(f64, Vec<BodyPose>)>,
    /// Per record: per joint name, its DOF values and its frame in the world (none before
    /// the first substep).
    joints: Vec<BTreeMap<String, JointRecord>>,
    /// Per joint name, the worst distance of its anchors along its blocked translations [m].
    gap: BTreeMap<String, f64>,
}

impl Observer for Watch {
    fn record(
        &mut self,
        time: f64,
        world: &PhysicsWorld,
        joints: &KjointSet,
        _events: &[KjointEvent],
    ) -> Result<(), OutputError> {
        let poses = self
            .bodies
            .iter()
            .map(|(_, h)| {
                let p = world.bodies[*h].position();
                (v64(p.translation), q64(p.rotation))
            })
            .collect();
        self.poses.push((time, poses));
        let mut now = BTreeMap::new();
        for (_, j) in joints.iter() {
            let Some(s) = j.state() else { continue };
            let jt = j.property().joint_type;
            let blocked = [Dof::Dx, Dof::Dy, Dof::Dz]
                .into_iter()
                .filter(|d| !jt.is_free(*d))
                .map(|d| s.q[d].powi(2))
                .sum::<f64>()
                .sqrt();
            let worst = self.gap.entry(j.name.clone()).or_insert(0.0);
            // a NaN counts as the worst
            if blocked.is_nan() || blocked > *worst {
                *worst = blocked;
            }
            now.insert(j.name.clone(), (s.q.0, frame64(s.frame)));
        }
        self.joints.push(now);
        Ok(())
    }
}

/// Runs `built` for its duration, recording at every substep, following `bodies`.
fn run(built: &mut BuiltScene, bodies: &[String]) -> Watch {
    let mut watch = Watch {
        bodies: bodies.iter().map(|n| (n.clone(), body(built, n))).collect(),
        ..Default::default()
    };
    let options = RunOptions {
        log: Some(scene::schema::LogEvery::Substep),
        ..Default::default()
    };
    scene::run(built, &options, &mut [&mut watch], &mut |_, _| {}).unwrap();
    watch
}

/// The angle between two rotations [rad].
fn angle(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> f64 {
    a.angle_to(b)
}

/// The unplaced arm alone, as the scene loads it, with the robot options `options` (a
/// TOML table's lines).
fn unplaced_scene(options: &str) -> BuiltScene {
    let text = format!("{SETTINGS}\n[[robots]]\nurdf = {}\n{options}", arm());
    build("unplaced.toml", &text).unwrap()
}

/// The run of the unplaced arm alone, with the robot options `options`.
fn unplaced_run(options: &str) -> Watch {
    let links: Vec<String> = LINKS.iter().map(|s| s.to_string()).collect();
    run(&mut unplaced_scene(options), &links)
}

const QUARTER: f64 = std::f64::consts::FRAC_PI_2;

/// The two arms: `left` at y = −0.5 m, `right` at y = +0.5 m turned 90° about z, both
/// with the robot options `options` (a TOML table's lines, without its header).
fn two_arms_text(options: &str) -> String {
    let options = match options {
        "" => String::new(),
        o => format!("[robots.options]\n{o}"),
    };
    format!(
        "{SETTINGS}
[[robots]]
urdf = {arm}
name = \"left\"
position = [0.0, -0.5, 0.0]
{options}
[[robots]]
urdf = {arm}
name = \"right\"
position = [0.0, 0.5, 0.0]
rotation = {{ axis = [0, 0, 1], angle = {QUARTER} }}
{options}",
        arm = arm()
    )
}

/// The placements of [`two_arms_text`].
fn places() -> [(&'static str, Place); 2] {
    [
        ("left", Place::new([0.0, -0.5, 0.0], 0.0)),
        ("right", Place::new([0.0, 0.5, 0.0], QUARTER)),
    ]
}

/// The links of both arms, `left/...` then `right/...` in [`LINKS`] order.
fn both_arms_links() -> Vec<String> {
    places()
        .iter()
        .flat_map(|(r, _)| LINKS.iter().map(move |l| format!("{r}/{l}")))
        .collect()
}

/// How far the placed robot `name`'s run (`watch`, bodies `{name}/{link}` in `LINKS` order)
/// is from the unplaced one's (`reference`) moved by `place`, over the whole run: the worst
/// link position [m], link rotation [rad], joint DOF value [m or rad] and joint frame
/// [rad].
fn distance_to_reference(
    watch: &Watch,
    offset: usize,
    reference: &Watch,
    name: &str,
    place: &Place,
) -> (f64, f64, f64, f64) {
    distance_to_reference_of(watch, offset, reference, name, place, &JOINTS)
}

/// [`distance_to_reference`] over the joints `joints` (file names) only.
fn distance_to_reference_of(
    watch: &Watch,
    offset: usize,
    reference: &Watch,
    name: &str,
    place: &Place,
    joints: &[&str],
) -> (f64, f64, f64, f64) {
    assert_eq!(watch.poses.len(), reference.poses.len());
    let (mut dp, mut dr, mut dq, mut df) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (k, ((t, placed), (t0, unplaced))) in watch.poses.iter().zip(&reference.poses).enumerate() {
        assert_eq!(t, t0);
        for (i, (p0, r0)) in unplaced.iter().enumerate() {
            let (p, r) = placed[offset + i];
            dp = dp.max((p - place.point(*p0)).norm());
            dr = dr.max(angle(&r, &(place.rot * r0)));
        }
        // (no joint state before the first substep)
        for j in joints.iter().filter(|_| !reference.joints[k].is_empty()) {
            let (q0, f0) = &reference.joints[k][*j];
            let (q, f) = &watch.joints[k][&format!("{name}/{j}")];
            for d in 0..6 {
                dq = dq.max((q[d] - q0[d]).abs());
            }
            df = df.max(angle(f, &(place.rot * f0)));
        }
    }
    (dp, dr, dq, df)
}

/// Two copies of the arm, named and placed: every body stands where the unplaced robot's
/// does, moved by its robot's placement (to f32 rounding), the bases exactly at their
/// placements; both robots' six joints are in the run under their prefixed names and hold
/// under gravity within the bound of the robot scenes (anchors within 1 mm,
/// `tests/scene_run.rs`), as the unplaced arm's do.
#[test]
fn two_named_arms_stand_where_they_are_placed_and_hold_under_gravity() {
    let reference = unplaced_scene("");
    let ref_watch = unplaced_run("");
    let mut built = build("two_arms.toml", &two_arms_text("")).unwrap();
    let places = places();
    // the bodies: the links of both, prefixed; nothing under the file's names
    let mut listed = names(&built);
    listed.sort();
    let mut expected = both_arms_links();
    expected.sort();
    assert_eq!(listed, expected);
    // each base at its placement, each link where the unplaced robot's is, moved
    for (robot, place) in &places {
        let base = built.world.bodies[body(&built, &format!("{robot}/base_link"))].position();
        let (t, r) = (v64(base.translation), q64(base.rotation));
        assert!((t - place.pos).norm() < 1e-7, "{robot}: base at {t:?}");
        assert!(angle(&r, &place.rot) < 1e-6, "{robot}: base turned {r:?}");
        assert!(!built.world.bodies[body(&built, &format!("{robot}/base_link"))].is_dynamic());
        for link in LINKS {
            let p0 = reference.world.bodies[body(&reference, link)].position();
            let p = built.world.bodies[body(&built, &format!("{robot}/{link}"))].position();
            let want = place.point(v64(p0.translation));
            let d = (v64(p.translation) - want).norm();
            assert!(d < 1e-6, "{robot}/{link}: {d} m from {want:?}");
            let da = angle(&q64(p.rotation), &(place.rot * q64(p0.rotation)));
            assert!(da < 1e-6, "{robot}/{link}: turned {da} rad off");
            // and its colliders with it
            let c0 = reference.world.bodies[body(&reference, link)].colliders()[0];
            let c = built.world.bodies[body(&built, &format!("{robot}/{link}"))].colliders()[0];
            let (c0, c) = (
                reference.world.colliders[c0].position(),
                built.world.colliders[c].position(),
            );
            let d = (v64(c.translation) - place.point(v64(c0.translation))).norm();
            assert!(d < 1e-6, "{robot}/{link} collider: {d} m off");
        }
    }
    // both robots' joints are in the set, prefixed
    let mut joints: Vec<String> = built.joints.iter().map(|(_, j)| j.name.clone()).collect();
    joints.sort();
    let expected: Vec<String> = places
        .iter()
        .flat_map(|(r, _)| JOINTS.iter().map(move |j| format!("{r}/{j}")))
        .collect();
    assert_eq!(joints, expected);

    // 1 s under gravity, every substep recorded
    let watch = run(&mut built, &both_arms_links());
    assert_eq!(watch.gap.len(), 6, "{:?}", watch.gap);
    for (joint, gap) in &watch.gap {
        assert!(*gap < 1e-3, "{joint}: anchors {gap} m apart");
    }
    // the joints' frames after the first substep: the unplaced arm's, turned by the
    // placement
    for (robot, place) in &places {
        for j in JOINTS {
            let f0 = ref_watch.joints[1][j].1;
            let f = watch.joints[1][&format!("{robot}/{j}")].1;
            assert!(angle(&f, &(place.rot * f0)) < 1e-6, "{robot}/{j}");
        }
    }
    println!(
        "anchor gaps: placed {:?}, unplaced {:?}",
        watch.gap, ref_watch.gap
    );
}

/// Robot options under which the arm's law does not depend on where it stands: a given
/// `Kn` (its stops the same) and given friction stiffnesses (about what the automatic rule
/// gives the unplaced arm). The automatic ones are sized from the load each joint carries
/// **and its distance from the origin** (the f32 noise bound of the implicit rule,
/// `law::stiffness::implicit_kappa`), so an arm placed away from the origin gets other
/// stiffnesses, as any model there would.
const FIXED_LAW: &str = "kn = 2e6
joints.shoulder.friction_stiffness = 4e5
joints.elbow.friction_stiffness = 8e4
joints.wrist.friction_stiffness = 4e5
";

/// A placed robot moves as the unplaced one does, moved by its placement: the arm falls
/// from its horizontal start, the shoulder and the wrist hit their stops at 0.27 s and the
/// elbow is whipped into its 0.8 rad stop.
///
/// * With a law that does not depend on where the arm stands ([`FIXED_LAW`]), over the
///   whole run (every substep): every link within 1 mm and 1 mrad of the unplaced arm's
///   pose moved by the placement, every joint value within 1 mrad (or 1 mm) and every
///   joint frame within 1 mrad. Measured: 2.0e-4 m and 1.9e-4 rad for `right` (turned and
///   moved), 2e-12 for `left` (moved along y, across the arm's plane of motion: its
///   coordinates in that plane are the unplaced ones); turned about the origin alone it
///   was 1.2e-6 rad. What is left is the rounding of f32 coordinates at another place
///   (6e-8 m at 1 m), grown through the stop impacts; the bound is 5 times the worst.
/// * With the default automatic stiffness (what the scene of the first test runs), the
///   stiffnesses of a placed arm are those of its distance from the origin (lower further
///   out), which changes how the stop impacts at 0.27 s throw the elbow: so up to the
///   impacts (0.25 s) the arms move as the unplaced one within 1 mrad (measured 0.38 mrad,
///   `right`; 0.016 mrad `left`), and at the end of the run they rest on the same stops
///   within 0.1 mrad (or 0.1 mm; measured 0.022 mm, `right`'s wrist).
///
/// The figures are f32's; with the `f64` feature (whose noise bound does not bite here)
/// both cases follow the unplaced arm within 4e-15.
#[test]
fn a_placed_arm_moves_as_the_unplaced_one_moved() {
    let reference = unplaced_run(&format!("[robots.options]\n{FIXED_LAW}"));
    let mut built = build("fixed_law.toml", &two_arms_text(FIXED_LAW)).unwrap();
    let watch = run(&mut built, &both_arms_links());
    // (the arm fell: the hand dropped, the elbow reached its stop)
    let hand0 = reference.poses[0].1[3].0;
    let hand1 = reference.poses.last().unwrap().1[3].0;
    assert!(hand0.z - hand1.z > 0.2, "{hand0:?} -> {hand1:?}");
    for (k, (robot, place)) in places().iter().enumerate() {
        let (dp, dr, dq, df) = distance_to_reference(&watch, 4 * k, &reference, robot, place);
        println!("{robot}, given law: links {dp:.3e} m, {dr:.3e} rad; joints {dq:.3e}, frames {df:.3e} rad");
        assert!(
            dp < 1e-3 && dr < 1e-3,
            "{robot}: links {dp} m, {dr} rad off"
        );
        assert!(
            dq < 1e-3 && df < 1e-3,
            "{robot}: joints {dq}, frames {df} rad off"
        );
    }

    // the default automatic stiffness
    let reference = unplaced_run("");
    let mut built = build("automatic.toml", &two_arms_text("")).unwrap();
    let watch = run(&mut built, &both_arms_links());
    let before = |w: &Watch| Watch {
        bodies: Vec::new(),
        poses: w.poses.iter().filter(|p| p.0 <= 0.25).cloned().collect(),
        joints: w.joints[..w.poses.iter().filter(|p| p.0 <= 0.25).count()].to_vec(),
        gap: BTreeMap::new(),
    };
    let (early, early_ref) = (before(&watch), before(&reference));
    assert!(early.poses.len() > 50, "{}", early.poses.len());
    let end = |w: &Watch, prefix: &str| {
        JOINTS.map(|j| w.joints.last().unwrap()[&format!("{prefix}{j}")].0)
    };
    for (k, (robot, place)) in places().iter().enumerate() {
        let (dp, dr, dq, df) = distance_to_reference(&early, 4 * k, &early_ref, robot, place);
        println!("{robot}, automatic, to 0.25 s: links {dp:.3e} m, {dr:.3e} rad; joints {dq:.3e}, frames {df:.3e} rad");
        assert!(
            dp < 1e-3 && dr < 1e-3,
            "{robot}: links {dp} m, {dr} rad off"
        );
        assert!(
            dq < 1e-3 && df < 1e-3,
            "{robot}: joints {dq}, frames {df} rad off"
        );
        let (placed, unplaced) = (end(&watch, &format!("{robot}/")), end(&reference, ""));
        for ((j, q), q0) in JOINTS.iter().zip(placed).zip(unplaced) {
            let worst = (0..6).map(|d| (q[d] - q0[d]).abs()).fold(0.0, f64::max);
            println!("{robot}/{j} at the end: {worst:.3e} from the unplaced arm's");
            assert!(worst < 1e-4, "{robot}/{j}: {q:?} vs {q0:?}");
        }
    }
}

/// A placed robot whose elbow is a rapier impulse joint (`engine = "rapier"`, the rest
/// KJOINT2 with [`FIXED_LAW`]): the rapier joint's frames are the links' own, so the
/// placement moves them with the links. Until the stops are hit (0.27 s) every link stands
/// within 1e-5 m and 1e-5 rad of the unplaced arm's (with the same override) moved by the
/// placement; after, a rounding difference of rapier's hard limits at an impact grows
/// (a robot turned by 1e-5 rad reads 0.05 rad apart by 0.5 s, as the robot turned 90°
/// does), so over the whole run what is checked is what the user looks at: the rapier
/// elbow's anchors stay together in both placed robots as in the unplaced one. And `kjoint
/// check` says where each robot stands and what it made.
#[test]
fn a_placed_robot_with_a_rapier_joint_moves_as_the_unplaced_one() {
    let options = FIXED_LAW.replace(
        "joints.elbow.friction_stiffness = 8e4",
        "joints.elbow.engine = \"rapier\"",
    );
    let unplaced = unplaced_scene(&format!("[robots.options]\n{options}"));
    let links: Vec<String> = LINKS.iter().map(|s| s.to_string()).collect();
    let reference = run(
        &mut unplaced_scene(&format!("[robots.options]\n{options}")),
        &links,
    );
    let text = two_arms_text(&options);
    let mut built = build("rapier_elbow.toml", &text).unwrap();
    let names: Vec<&str> = built
        .rapier_joints
        .iter()
        .map(|(n, _)| n.as_str())
        .collect();
    assert_eq!(names, ["left/elbow", "right/elbow"]);
    let elbow = |b: &BuiltScene, k: usize| {
        let j = &b
            .world
            .impulse_joints
            .get(b.rapier_joints[k].1)
            .unwrap()
            .data;
        (
            v64(j.local_frame1.translation),
            v64(j.local_frame2.translation),
        )
    };
    let frames = [elbow(&built, 0), elbow(&built, 1)];
    let frame0 = elbow(&unplaced, 0);
    let watch = run(&mut built, &both_arms_links());
    // (the arm fell: the hand dropped by more than 0.2 m)
    let hand0 = reference.poses[0].1[3].0;
    let hand1 = reference.poses.last().unwrap().1[3].0;
    assert!(hand0.z - hand1.z > 0.2, "{hand0:?} -> {hand1:?}");
    // before the stops
    let until = |w: &Watch, t: f64| {
        let n = w.poses.iter().filter(|p| p.0 <= t).count();
        Watch {
            bodies: Vec::new(),
            poses: w.poses[..n].to_vec(),
            joints: w.joints[..n].to_vec(),
            gap: BTreeMap::new(),
        }
    };
    let (early, early_ref) = (until(&watch, 0.25), until(&reference, 0.25));
    assert!(early.poses.len() > 50, "{}", early.poses.len());
    for (k, (robot, place)) in places().iter().enumerate() {
        let kjoints = ["shoulder", "wrist"];
        let (dp, dr, dq, df) =
            distance_to_reference_of(&early, 4 * k, &early_ref, robot, place, &kjoints);
        println!("{robot}, rapier elbow, to 0.25 s: links {dp:.3e} m, {dr:.3e} rad; joints {dq:.3e}, frames {df:.3e} rad");
        assert!(
            dp < 1e-5 && dr < 1e-5,
            "{robot}: links {dp} m, {dr} rad off"
        );
        assert!(
            dq < 1e-5 && df < 1e-5,
            "{robot}: joints {dq}, frames {df} rad off"
        );
    }
    // the rapier elbow's anchors over the whole run (upper_arm and forearm: links 1 and 2)
    let gap = |w: &Watch, offset: usize, (a1, a2): (Vector3<f64>, Vector3<f64>)| {
        w.poses
            .iter()
            .map(|(_, p)| {
                let ((p1, r1), (p2, r2)) = (p[offset + 1], p[offset + 2]);
                ((p1 + r1 * a1) - (p2 + r2 * a2)).norm()
            })
            .fold(0.0, f64::max)
    };
    let reference_gap = gap(&reference, 0, frame0);
    println!("unplaced: rapier elbow's anchors at most {reference_gap:.3e} m apart");
    for (k, (robot, _)) in places().iter().enumerate() {
        let g = gap(&watch, 4 * k, frames[k]);
        println!("{robot}: rapier elbow's anchors at most {g:.3e} m apart");
        assert!(
            g < 1e-3 && g < 2.0 * reference_gap + 1e-5,
            "{robot}: {g} m (unplaced {reference_gap})"
        );
    }
    // what `kjoint check` says of the robots
    let path = common::cli::temp_file("robot-placement", "rapier_elbow_check.toml", &text);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_kjoint"))
        .arg("check")
        .arg(&path)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    let urdf = root().join("assets/urdf/arm.urdf").display().to_string();
    for line in [
        format!(
            "robot `left` (4 bodies, 2 KJOINT2 joints, 1 rapier joint): URDF {urdf}, its \
             frame at [0, -0.5000, 0] m, not turned"
        ),
        format!(
            "robot `right` (4 bodies, 2 KJOINT2 joints, 1 rapier joint): URDF {urdf}, its \
             frame at [0, 0.5000, 0] m, turned 1.571 rad (90.00°) about [0, 0, 1.000]"
        ),
    ] {
        assert!(
            stdout.lines().any(|l| l == line),
            "{line}\nnot in\n{stdout}"
        );
    }
}

/// The rest of the scene names a named robot's bodies and joints by their prefixed names:
/// a `[[joints]]` ball tethered to `left/hand`, a sensor watching `right/wrist`, a load on
/// `left/forearm`; the file's names are unknown then, refused at the field and its line.
/// The outputs name the joints so, their CSV files with `_` for `/` (`left_elbow.csv`,
/// `index.csv` giving the joint of each file). The overrides keep the file's names.
#[test]
fn the_scene_names_a_named_robot_s_parts_by_their_prefixed_names() {
    let tail = r#"
[[bodies]]
name = "ball"
shape = { type = "ball", radius = 0.05 }
mass = 0.2
translation = [0.8, -0.5, 0.0]

[[joints]]
name = "tether"
body1 = "left/hand"
body2 = "ball"
anchor1 = [0.08, 0, 0]
property = { type = "spherical" }

[[sensors]]
id = 1
joint = "right/wrist"
dof = "dx"
passes = 0.04

[[loads]]
body = "left/forearm"
force = [0, 0, -1]
"#;
    let options = "joints.elbow = { friction = 0.6 }\n";
    let text = two_arms_text(options) + tail;
    let built = build("references.toml", &text).unwrap();
    let mut joints: Vec<String> = built.joints.iter().map(|(_, j)| j.name.clone()).collect();
    joints.sort();
    assert_eq!(
        joints,
        [
            "left/elbow",
            "left/shoulder",
            "left/wrist",
            "right/elbow",
            "right/shoulder",
            "right/wrist",
            "tether"
        ]
    );
    // the override by the file's name reached both copies' elbows
    for (_, j) in built
        .joints
        .iter()
        .filter(|(_, j)| j.name.ends_with("/elbow"))
    {
        assert_eq!(j.property().dofs[3].friction, 0.6, "{}", j.name);
    }
    // the tether holds the ball at the hand, where the placed hand is
    let tether = built
        .joints
        .iter()
        .find(|(_, j)| j.name == "tether")
        .unwrap()
        .1;
    let hand = body(&built, "left/hand");
    assert_eq!(tether.body1(), hand);

    // run from the command line: the files of the prefixed joints
    let path = common::cli::temp_file("robot-placement", "references_run.toml", &text);
    let csv = common::cli::fresh_temp_dir("robot-placement-csv");
    let stdout = common::cli::kjoint_run(&path, Some(&csv), &[] as &[&str]);
    assert!(stdout.contains("7 joints"), "{stdout}");
    assert!(stdout.contains("left/elbow"), "{stdout}");
    let index = std::fs::read_to_string(csv.join("index.csv")).unwrap();
    for robot in ["left", "right"] {
        for j in JOINTS {
            assert!(
                csv.join(format!("{robot}_{j}.csv")).is_file(),
                "{robot}_{j}.csv"
            );
            assert!(
                index.contains(&format!("\"{robot}/{j}\",\"{robot}_{j}.csv\"")),
                "{index}"
            );
        }
    }
    let events = std::fs::read_to_string(csv.join("events.csv")).unwrap();
    assert!(
        events.contains("joint `right/wrist` dx passed 0.04 m"),
        "{events}"
    );

    // the file's own names are not the scene's any more: refused at their field and line
    for (what, field, needle) in [
        (
            "body1 = \"left/hand\"",
            "joints[0].body1",
            "no body named `hand`",
        ),
        ("joint = \"right/wrist\"", "sensors[0].joint", "`wrist`"),
        ("body = \"left/forearm\"", "loads[0].body", "`forearm`"),
    ] {
        let bare = what.replace("left/", "").replace("right/", "");
        let t = text.replace(what, &bare);
        let e = error("unknown.toml", &t);
        assert_eq!(e.field, field, "{e}");
        assert_eq!(e.line, line_of(&t, &bare), "{e}");
        assert!(e.message.contains(needle), "{e}");
        // the message lists the names that exist, prefixed
        let listed = if field == "sensors[0].joint" {
            "right/wrist"
        } else {
            "left/hand"
        };
        assert!(e.message.contains(listed), "{e}");
    }
}

/// An MJCF model placed and named the same way: the double pendulum's fixed base stands at
/// the placement of its `pos="0 0 1"`, its bodies and joints are `p/...`.
#[test]
fn an_mjcf_model_is_placed_and_named_as_a_urdf_robot() {
    let pendulum = format!(
        "{:?}",
        root()
            .join("assets/mjcf/pendulum.xml")
            .display()
            .to_string()
    );
    let text = format!(
        "{SETTINGS}\n[[robots]]\nmjcf = {pendulum}\nname = \"p\"\nposition = [2.0, 0.0, 0.5]\n\
         rotation = {{ quaternion = [0, 0, 0.7071067811865476, 0.7071067811865476] }}\n"
    );
    let built = build("mjcf.toml", &text).unwrap();
    let reference = build(
        "mjcf_ref.toml",
        &format!("{SETTINGS}\n[[robots]]\nmjcf = {pendulum}\n"),
    )
    .unwrap();
    let place = Place::new([2.0, 0.0, 0.5], QUARTER);
    for link in ["base", "upper", "lower"] {
        let p0 = reference.world.bodies[body(&reference, link)].position();
        let p = built.world.bodies[body(&built, &format!("p/{link}"))].position();
        let d = (v64(p.translation) - place.point(v64(p0.translation))).norm();
        assert!(d < 1e-6, "p/{link}: {d} m off");
        let da = angle(&q64(p.rotation), &(place.rot * q64(p0.rotation)));
        assert!(da < 1e-6, "p/{link}: turned {da} rad off");
    }
    let base = v64(built.world.bodies[body(&built, "p/base")].translation());
    assert!(
        (base - Vector3::new(2.0, 0.0, 1.5)).norm() < 1e-6,
        "{base:?}"
    );
    let mut joints: Vec<String> = built.joints.iter().map(|(_, j)| j.name.clone()).collect();
    joints.sort();
    assert_eq!(joints, ["p/elbow", "p/shoulder"]);
    // the notices say which copy they are about
    assert!(
        built.notices.iter().all(|n| n.contains("(robot `p`)")),
        "{:?}",
        built.notices
    );
}

/// A robot whose massless root link is `world` (ROS): unplaced it is the scene's `world`
/// (as before); placed it stands where the robot does, a fixed body named `{name}/world`,
/// and the scene's `world` stays the ground at the origin.
#[test]
fn a_placed_robot_s_world_link_stands_where_the_robot_does() {
    let unit = r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;
    let urdf = format!(
        r#"<robot name="r">
  <link name="world"><visual><geometry><box size="1 1 0.01"/></geometry></visual></link>
  <link name="base">{unit}</link>
  <joint name="yaw" type="revolute"><parent link="world"/><child link="base"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"#
    );
    let file = common::cli::temp_file("robot-placement", "world_link.urdf", &urdf);
    let robot = |extra: &str| {
        format!(
            "{SETTINGS}\n[[robots]]\nurdf = {:?}\n{extra}\n[[bodies]]\nname = \"b\"\n\
             shape = {{ type = \"ball\", radius = 0.1 }}\n\n[[joints]]\nname = \"j\"\n\
             body1 = \"world\"\nbody2 = \"b\"\nproperty = {{ type = \"spherical\" }}\n",
            file.display().to_string()
        )
    };
    // named and placed: `w/world` at the placement, the scene's `world` at the origin
    let built = build(
        "world_link.toml",
        &robot("name = \"w\"\nposition = [1, 2, 3]"),
    )
    .unwrap();
    let w = body(&built, "w/world");
    assert!(!built.world.bodies[w].is_dynamic());
    let at = v64(built.world.bodies[w].translation());
    assert!((at - Vector3::new(1.0, 2.0, 3.0)).norm() < 1e-6, "{at:?}");
    let ground = body(&built, "world");
    assert_ne!(ground, w);
    assert_eq!(
        v64(built.world.bodies[ground].translation()),
        Vector3::zeros()
    );
    // unnamed and placed: not the scene's `world` either (no name of its own)
    let built = build("world_link2.toml", &robot("position = [1, 2, 3]")).unwrap();
    let ground = body(&built, "world");
    assert_eq!(
        v64(built.world.bodies[ground].translation()),
        Vector3::zeros()
    );
    assert!(!names(&built).iter().any(|n| n.ends_with("/world")));
    // named, unplaced: the scene's `world`, as an unnamed robot's is
    let built = build("world_link3.toml", &robot("name = \"w\"")).unwrap();
    let ground = body(&built, "world");
    let yaw = built
        .joints
        .iter()
        .find(|(_, j)| j.name == "w/yaw")
        .unwrap()
        .1;
    assert_eq!(yaw.body1(), ground);
}

/// A wrong `[[robots]]` entry is refused before anything runs, at its field and line, with
/// the scene's own checks of a body's `translation` and `rotation`.
#[test]
fn a_wrong_placement_or_name_is_refused_at_its_field_and_line() {
    let base = |extra: &str| format!("{SETTINGS}\n[[robots]]\nurdf = {}\n{extra}", arm());
    // NaN, infinite, beyond ±1e12
    for (value, index, message) in [
        ("[nan, 0, 0]", 0, "not a finite number"),
        ("[0, inf, 0]", 1, "not a finite number"),
        ("[0, 0, 1e13]", 2, "out of range"),
    ] {
        let t = base(&format!("position = {value}\n"));
        let e = error("position.toml", &t);
        assert_eq!(e.field, format!("robots[0].position[{index}]"), "{e}");
        assert_eq!(e.line, line_of(&t, "position ="), "{e}");
        assert!(e.message.contains(message), "{e}");
    }
    // a wrong length, in TOML and in JSON
    let t = base("position = [1, 2]\n");
    let e = error("position_len.toml", &t);
    assert_eq!(e.field, "robots[0].position", "{e}");
    assert_eq!(e.line, line_of(&t, "position ="), "{e}");
    assert!(e.message.contains("an array of length 3"), "{e}");
    let json = format!(
        "{{\n  \"duration\": 0.1,\n  \"robots\": [\n    {{\n      \"urdf\": {},\n      \
         \"position\": [1, 2, 3, 4]\n    }}\n  ]\n}}\n",
        arm()
    );
    let e = error("position_len.json", &json);
    assert_eq!(e.field, "robots[0].position", "{e}");
    assert_eq!(e.line, line_of(&json, "\"position\""), "{e}");
    assert!(e.message.contains("an array of length 3"), "{e}");
    // a JSON scene takes the same fields (and checks them the same)
    let json_ok = json.replace("[1, 2, 3, 4]", "[1, 2, 3],\n      \"name\": \"a\"");
    let built = build("placed.json", &json_ok).unwrap();
    let b = v64(built.world.bodies[body(&built, "a/base_link")].translation());
    assert_eq!(b, Vector3::new(1.0, 2.0, 3.0));
    let json_nan = json_ok.replace(
        "[1, 2, 3]",
        "[1, 2, 3],\n      \"rotation\": { \"axis\": [0, 0, 0], \"angle\": 1 }",
    );
    let e = error("rotation.json", &json_nan);
    assert_eq!(e.field, "robots[0].rotation.axis", "{e}");
    assert_eq!(e.line, line_of(&json_nan, "\"rotation\""), "{e}");
    // a rotation as a body's: a zero axis, a quaternion that is not a unit one, both forms
    for (value, field, message) in [
        (
            "{ axis = [0, 0, 0], angle = 1 }",
            "robots[0].rotation.axis",
            "zero",
        ),
        (
            "{ quaternion = [0, 0, 0, 2] }",
            "robots[0].rotation.quaternion",
            "unit quaternion",
        ),
        (
            "{ axis = [0, 0, 1], angle = nan }",
            "robots[0].rotation.angle",
            "not a finite",
        ),
        (
            "{ axis = [0, 0, 1], angle = 1, quaternion = [0, 0, 0, 1] }",
            "robots[0].rotation",
            "either",
        ),
    ] {
        let t = base(&format!("rotation = {value}\n"));
        let e = error("rotation.toml", &t);
        assert_eq!(e.field, field, "{e}");
        assert_eq!(e.line, line_of(&t, "rotation ="), "{e}");
        assert!(e.message.contains(message), "{e}");
    }
    // an empty name
    let t = base("name = \" \"\n");
    let e = error("name.toml", &t);
    assert_eq!(e.field, "robots[0].name", "{e}");
    assert_eq!(e.line, line_of(&t, "name ="), "{e}");
    // the pose is the entry's, not an option
    let t = base("[robots.options]\nbase_pose = 1\n");
    let e = error("base_pose.toml", &t);
    assert!(e.message.contains("unknown field `base_pose`"), "{e}");
    // two unnamed copies: their names clash, at the second entry's file (as before)
    let t = base("") + &format!("\n[[robots]]\nurdf = {}\nposition = [0, 1, 0]\n", arm());
    let e = error("clash.toml", &t);
    assert_eq!(e.field, "robots[1].urdf", "{e}");
    assert_eq!(e.line, nth_line_of(&t, "urdf =", 1), "{e}");
    assert!(e.message.contains("has the name of another body"), "{e}");
    // two copies under one name: at the second entry's name
    let t = base("name = \"a\"\n")
        + &format!(
            "\n[[robots]]\nurdf = {}\nname = \"a\"\nposition = [0, 1, 0]\n",
            arm()
        );
    let e = error("clash_named.toml", &t);
    assert_eq!(e.field, "robots[1].name", "{e}");
    assert_eq!(e.line, nth_line_of(&t, "name =", 1), "{e}");
    assert!(e.message.contains("link `a/base_link`"), "{e}");
    // a named copy beside an unnamed one: no clash
    let t = base("")
        + &format!(
            "\n[[robots]]\nurdf = {}\nname = \"b\"\nposition = [0, 1, 0]\n",
            arm()
        );
    let built = build("no_clash.toml", &t).unwrap();
    assert_eq!(built.joints.len(), 6);
}

/// The library's side: `UrdfOptions::base_pose` places a robot read by the program, and
/// `RobotDescription::prefix_names` names a copy; a pose that is not finite is refused
/// naming the option.
#[test]
fn a_program_places_and_names_a_robot_through_the_options() {
    use rapier_kjoint::io::urdf::{UrdfError, UrdfOptions, UrdfRobot};
    let file = root().join("assets/urdf/arm.urdf");
    let place = Pose::from_parts(
        Vector::new(1.0, 2.0, 0.0),
        Rotation::from_axis_angle(Vector::Z, QUARTER as Real),
    );
    let options = UrdfOptions {
        base_pose: place,
        ..Default::default()
    };
    let (mut world, mut joints) = (PhysicsWorld::default(), KjointSet::new());
    let mut description = UrdfRobot::from_file(&file, &options).unwrap();
    description.prefix_names("a");
    let robot = description.insert(&mut world, &mut joints).unwrap();
    let names: Vec<&str> = robot.joints.keys().map(|s| s.as_str()).collect();
    assert_eq!(names, ["a/elbow", "a/shoulder", "a/wrist"]);
    let base = world.bodies[robot.links["a/base_link"]].position();
    assert!((v64(base.translation) - Vector3::new(1.0, 2.0, 0.0)).norm() < 1e-6);
    // the KJOINT2 joint's own name, which the outputs show, is the prefixed one
    let shoulder = joints.get(robot.joints["a/shoulder"]).unwrap();
    assert_eq!(shoulder.name, "a/shoulder");
    let bad = UrdfOptions {
        base_pose: Pose::from_translation(Vector::new(Real::NAN, 0.0, 0.0)),
        ..Default::default()
    };
    match UrdfRobot::from_file(&file, &bad) {
        Err(e @ UrdfError::Field { .. }) => {
            assert!(e.to_string().contains("base_pose.translation"), "{e}")
        }
        other => panic!("{other:?}"),
    }
}

/// A robot placed into the ground is warned of before the run, naming the bodies and how
/// deep they start. Placed on its side 0.2 m into a ground box, MuJoCo Menagerie's Go1
/// ended its run at 0.0375 s with "simulation unstable … a blocked rotation of 0.701 rad",
/// whose remedies (substeps, loads) were not the cause, and the scene said nothing. Here
/// the shipped MJCF pendulum's arms (capsules of radius 0.02 m along x, 0.95 m below the
/// model's origin) are placed with their axis level with the world's z = 0, inside a ground
/// box whose top is at z = 0.1: 0.12 m deep. Placed 5 mm into it (below
/// `START_OVERLAP`, 1 cm) or above it, nothing is said.
#[test]
fn a_robot_placed_into_the_ground_is_warned_of_with_its_depth() {
    let mjcf = format!(
        "{:?}",
        root()
            .join("assets/mjcf/pendulum.xml")
            .display()
            .to_string()
    );
    let scene = |z: f64| {
        format!(
            "{SETTINGS}\n[[bodies]]\nname = \"ground\"\nkind = \"fixed\"\n\
             shape = {{ type = \"cuboid\", half_extents = [2.0, 2.0, 0.1] }}\n\
             translation = [0.0, 0.0, 0.0]\ncollide = true\n\n\
             [[robots]]\nmjcf = {mjcf}\nposition = [0.0, 0.0, {z}]\n"
        )
    };
    let built = build("into_ground.toml", &scene(-0.95)).unwrap();
    let w: Vec<&String> = (built.warnings.iter())
        .filter(|w| w.contains("inside"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", built.warnings);
    assert!(
        w[0].starts_with("bodies `")
            && w[0].contains("`upper` (0.1200 m)")
            && w[0].contains("`lower` (0.1200 m)")
            && w[0].contains("start inside `ground`")
            && w[0].contains("a robot's `position`"),
        "{}",
        w[0]
    );
    // 5 mm in (the capsules' bottom at 0.095 m), and 0.95 m above: nothing said
    for z in [-0.95 + 0.115, 0.0] {
        let built = build("above_ground.toml", &scene(z)).unwrap();
        assert!(
            !built.warnings.iter().any(|w| w.contains("inside")),
            "z = {z}: {:?}",
            built.warnings
        );
    }
}
