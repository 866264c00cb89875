//! Ragdolls on KJOINT2 joints at rest fall asleep (`dynamics::sleep`), also when they rest
//! on each other: the pair of a user trial's 50-ragdoll scene that never slept. The ragdoll
//! (72 kg, 11 capsules, spherical joints with cone and twist stops, revolute elbows and
//! knees, a viscosity on every free rotation so that it comes to rest) is the trial's.
#![allow(dead_code)]
// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;

pub struct Part {
    pub name: &'static str,
    pub center: Vector, // ragdoll frame (origin at the pelvis centre, y up, standing)
    pub shape: fn() -> ColliderBuilder,
    pub mass: Real,
}

#[derive(Clone, Copy)]
pub enum Kind {
    /// twist axis (ragdoll frame), cone half-angle, twist half-range
    Sph {
        axis: Vector,
        cone: Real,
        twist: Real,
    },
    /// hinge axis (ragdoll frame), stops
    Rev { axis: Vector, lo: Real, hi: Real },
}

pub struct JDef {
    pub name: &'static str,
    pub b1: usize,
    pub b2: usize,
    pub anchor: Vector, // ragdoll frame
    pub kind: Kind,
}

const Y0: Real = 1.0; // pelvis height in the standing layout

fn v(x: Real, y: Real, z: Real) -> Vector {
    Vector::new(x, y - Y0, z)
}

pub fn parts() -> Vec<Part> {
    vec![
        Part {
            name: "pelvis",
            center: v(0.0, 1.0, 0.0),
            shape: || ColliderBuilder::capsule_x(0.08, 0.1),
            mass: 11.0,
        },
        Part {
            name: "torso",
            center: v(0.0, 1.38, 0.0),
            shape: || ColliderBuilder::capsule_y(0.14, 0.13),
            mass: 20.0,
        },
        Part {
            name: "head",
            center: v(0.0, 1.80, 0.0),
            shape: || ColliderBuilder::ball(0.11),
            mass: 5.0,
        },
        Part {
            name: "uarm_l",
            center: v(-0.24, 1.40, 0.0),
            shape: || ColliderBuilder::capsule_y(0.12, 0.05),
            mass: 2.5,
        },
        Part {
            name: "larm_l",
            center: v(-0.24, 1.03, 0.0),
            shape: || ColliderBuilder::capsule_y(0.13, 0.045),
            mass: 2.0,
        },
        Part {
            name: "uarm_r",
            center: v(0.24, 1.40, 0.0),
            shape: || ColliderBuilder::capsule_y(0.12, 0.05),
            mass: 2.5,
        },
        Part {
            name: "larm_r",
            center: v(0.24, 1.03, 0.0),
            shape: || ColliderBuilder::capsule_y(0.13, 0.045),
            mass: 2.0,
        },
        Part {
            name: "thigh_l",
            center: v(-0.1, 0.70, 0.0),
            shape: || ColliderBuilder::capsule_y(0.15, 0.07),
            mass: 9.0,
        },
        Part {
            name: "shin_l",
            center: v(-0.1, 0.25, 0.0),
            shape: || ColliderBuilder::capsule_y(0.15, 0.055),
            mass: 4.5,
        },
        Part {
            name: "thigh_r",
            center: v(0.1, 0.70, 0.0),
            shape: || ColliderBuilder::capsule_y(0.15, 0.07),
            mass: 9.0,
        },
        Part {
            name: "shin_r",
            center: v(0.1, 0.25, 0.0),
            shape: || ColliderBuilder::capsule_y(0.15, 0.055),
            mass: 4.5,
        },
    ]
}

pub fn joints() -> Vec<JDef> {
    let down = Vector::new(0.0, -1.0, 0.0);
    let up = Vector::new(0.0, 1.0, 0.0);
    let x = Vector::new(1.0, 0.0, 0.0);
    vec![
        JDef {
            name: "spine",
            b1: 0,
            b2: 1,
            anchor: v(0.0, 1.105, 0.0),
            kind: Kind::Sph {
                axis: up,
                cone: 0.4,
                twist: 0.3,
            },
        },
        JDef {
            name: "neck",
            b1: 1,
            b2: 2,
            anchor: v(0.0, 1.675, 0.0),
            kind: Kind::Sph {
                axis: up,
                cone: 0.6,
                twist: 0.6,
            },
        },
        JDef {
            name: "shoulder_l",
            b1: 1,
            b2: 3,
            anchor: v(-0.24, 1.585, 0.0),
            kind: Kind::Sph {
                axis: down,
                cone: 1.2,
                twist: 0.8,
            },
        },
        JDef {
            name: "elbow_l",
            b1: 3,
            b2: 4,
            anchor: v(-0.24, 1.2125, 0.0),
            kind: Kind::Rev {
                axis: x,
                lo: -2.4,
                hi: 0.05,
            },
        },
        JDef {
            name: "shoulder_r",
            b1: 1,
            b2: 5,
            anchor: v(0.24, 1.585, 0.0),
            kind: Kind::Sph {
                axis: down,
                cone: 1.2,
                twist: 0.8,
            },
        },
        JDef {
            name: "elbow_r",
            b1: 5,
            b2: 6,
            anchor: v(0.24, 1.2125, 0.0),
            kind: Kind::Rev {
                axis: x,
                lo: -2.4,
                hi: 0.05,
            },
        },
        JDef {
            name: "hip_l",
            b1: 0,
            b2: 7,
            anchor: v(-0.1, 0.91, 0.0),
            kind: Kind::Sph {
                axis: down,
                cone: 1.2,
                twist: 0.5,
            },
        },
        JDef {
            name: "knee_l",
            b1: 7,
            b2: 8,
            anchor: v(-0.1, 0.4675, 0.0),
            kind: Kind::Rev {
                axis: x,
                lo: -0.05,
                hi: 2.4,
            },
        },
        JDef {
            name: "hip_r",
            b1: 0,
            b2: 9,
            anchor: v(0.1, 0.91, 0.0),
            kind: Kind::Sph {
                axis: down,
                cone: 1.2,
                twist: 0.5,
            },
        },
        JDef {
            name: "knee_r",
            b1: 9,
            b2: 10,
            anchor: v(0.1, 0.4675, 0.0),
            kind: Kind::Rev {
                axis: x,
                lo: -0.05,
                hi: 2.4,
            },
        },
    ]
}

/// The parts each part must not collide with (its joint neighbours), as a bit mask.
fn neighbours(i: usize) -> u32 {
    let mut m = 0u32;
    for j in joints() {
        if j.b1 == i {
            m |= 1 << j.b2;
        }
        if j.b2 == i {
            m |= 1 << j.b1;
        }
    }
    m
}

pub fn groups(i: usize) -> InteractionGroups {
    InteractionGroups::new(
        Group::from_bits_truncate(1 << i),
        Group::from_bits_truncate(!neighbours(i)),
        InteractionTestMode::And,
    )
}

/// Placement of a ragdoll: its frame's rotation and the world position of its pelvis.
#[derive(Clone, Copy)]
pub struct Placement {
    pub rot: Rotation,
    pub pos: Vector,
}

pub fn spawn_bodies(world: &mut PhysicsWorld, p: Placement, vel: Vector) -> Vec<RigidBodyHandle> {
    parts()
        .iter()
        .enumerate()
        .map(|(i, part)| {
            let c = p.pos + p.rot * part.center;
            let (h, _) = world.insert(
                RigidBodyBuilder::dynamic()
                    .translation(c)
                    .rotation(p.rot.to_scaled_axis())
                    .linvel(vel),
                (part.shape)()
                    .mass(part.mass)
                    .collision_groups(groups(i))
                    .friction(0.7),
            );
            h
        })
        .collect()
}

/// KJOINT2 joints (automatic stiffness unless `kn` is given).
pub fn kjoint_joints(
    set: &mut KjointSet,
    world: &PhysicsWorld,
    bodies: &[RigidBodyHandle],
    p: Placement,
    kn: Option<f64>,
    tag: usize,
) -> Vec<KjointHandle> {
    kjoint_joints_visc(set, world, bodies, p, kn, tag, 0.0)
}

/// [`kjoint_joints`] with a viscosity `visc` [N·m·s/rad] on every free rotation (0: none).
pub fn kjoint_joints_visc(
    set: &mut KjointSet,
    world: &PhysicsWorld,
    bodies: &[RigidBodyHandle],
    p: Placement,
    kn: Option<f64>,
    tag: usize,
    visc: f64,
) -> Vec<KjointHandle> {
    let law = |lo: f64, hi: f64| {
        let l = DofLaw::default().with_stops(lo, hi);
        if visc > 0.0 {
            l.with_viscosity(visc)
        } else {
            l
        }
    };
    let ps = parts();
    joints()
        .iter()
        .map(|j| {
            let (ty, axis) = match j.kind {
                Kind::Sph { axis, .. } => (JointType::Spherical, axis),
                Kind::Rev { axis, .. } => (JointType::Revolute, axis),
            };
            let mut prop = KjointProperty::new(ty);
            if let Some(kn) = kn {
                prop = prop.with_kn(kn);
            }
            match j.kind {
                Kind::Sph { cone, twist, .. } => {
                    let c = law(-cone as f64, cone as f64).with_coupled_stops();
                    prop = prop
                        .with_dof(Dof::Rx, law(-twist as f64, twist as f64))
                        .with_dof(Dof::Ry, c.clone())
                        .with_dof(Dof::Rz, c);
                }
                Kind::Rev { lo, hi, .. } => {
                    prop = prop.with_dof(Dof::Rx, law(lo as f64, hi as f64));
                }
            }
            let frame = p.rot * Rotation::from_rotation_arc(Vector::X, axis);
            set.insert(
                KjointBuilder::new(prop)
                    .name(format!("r{tag}_{}", j.name))
                    .world_frame1(frame)
                    .local_anchor1(j.anchor - ps[j.b1].center)
                    .local_anchor2(j.anchor - ps[j.b2].center),
                bodies[j.b1],
                bodies[j.b2],
                &world.bodies,
            )
            .expect("kjoint insert")
        })
        .collect()
}

pub fn placements(n: usize) -> Vec<Placement> {
    let mut out = Vec::new();
    for k in 0..n {
        let cell = k % 25;
        let layer = k / 25;
        let (cx, cz) = ((cell % 5) as Real * 2.4, (cell / 5) as Real * 2.4);
        let jit = (((k * 37) % 17) as Real / 16.0) - 0.5; // -0.5..0.5
        let yaw = if layer == 0 {
            0.3 * jit
        } else {
            1.4 + 0.3 * jit
        };
        let tilt = std::f32::consts::FRAC_PI_2 as Real + 0.4 * jit; // lying, face down-ish
        let rot = Rotation::from_rotation_y(yaw) * Rotation::from_rotation_x(tilt);
        let h = if layer == 0 {
            1.0 + 0.5 * (jit + 0.5)
        } else {
            2.3 + 0.7 * (jit + 0.5)
        };
        out.push(Placement {
            rot,
            pos: Vector::new(cx, h, cz),
        });
    }
    out
}

/// Ragdolls 11 and 36 of the trial's scene: the second dropped across the first. Every
/// body's rest measure `(|v| + |ω|·r)/2` stayed at or below 0.014 m/s from 2.5 to 10 s and
/// no body slept: rapier's step reset the sleep timer of two of their bodies (0.4 mm/s)
/// at every step, which the set read as the user's wake, starting the pair's rest over. They
/// sleep now within 5 s (rapier's own joints put such a pair to sleep).
#[test]
fn two_ragdolls_resting_on_each_other_fall_asleep() {
    let pl = placements(50);
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81, 0.0),
        ..Default::default()
    };
    let g = w.insert_body(RigidBodyBuilder::fixed());
    w.insert_collider(
        ColliderBuilder::cuboid(20.0, 0.5, 20.0)
            .translation(Vector::new(0.0, -0.5, 4.8))
            .friction(0.7),
        Some(g),
    );
    let mut set = KjointSet::new();
    let mut bodies = Vec::new();
    for (tag, k) in [11usize, 36].into_iter().enumerate() {
        let mut p = pl[k];
        p.pos.x -= 4.8;
        let b = spawn_bodies(&mut w, p, Vector::ZERO);
        kjoint_joints_visc(&mut set, &w, &b, p, None, tag, 2.0);
        bodies.extend(b);
    }
    let mut asleep_at = None;
    for f in 1..=600 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        if asleep_at.is_none() && bodies.iter().all(|h| w.bodies[*h].is_sleeping()) {
            asleep_at = Some(f as f64 / 60.0);
        }
    }
    let t = asleep_at.expect("the two ragdolls never slept in 10 s");
    assert!(t < 5.0, "asleep at {t} s");
    assert!(
        bodies.iter().all(|h| w.bodies[*h].is_sleeping()),
        "woke again"
    );
}
