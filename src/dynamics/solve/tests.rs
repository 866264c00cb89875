//! The structured solve against the dense joint-space reference, at every substep of scenes
//! that exercise each path: a chain, a tree inserted root first, a hub, closed loops, and
//! hinged groups in contact with the ground. The impulses must agree to 1e-9 relative.

use super::topology::NodeKind;
use super::{joint_block, MassBlocks, SolverBody, SolverJoint, SolverJoints};
use crate::dynamics::EventSource;
use crate::rapier::prelude::*;
use crate::{JointType, KjointBuilder, KjointProperty, KjointSet, SubstepSettings};
use nalgebra::{Matrix6, Vector6};

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

fn hinge(kn: f64) -> KjointBuilder {
    let axis_z = Rotation::from_rotation_arc(Vector::X, Vector::Z);
    KjointBuilder::new(KjointProperty::new(JointType::Revolute).with_kn(kn)).world_frame1(axis_z)
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
    let mut w = PhysicsWorld {
        gravity: Vector::new(0.0, -9.81, 0.0),
        ..Default::default()
    };
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
        KjointBuilder::new(KjointProperty::new(JointType::Spherical).with_kn(1e10)),
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
            KjointBuilder::new(KjointProperty::new(JointType::Spherical).with_kn(1e10))
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

/// A closed ring of rods hinged at `corners` (a polygon), the first rod also hinged to the
/// world at the first corner: one island of `corners.len() + 1` joints with a loop.
fn hinged_ring(
    w: &mut PhysicsWorld,
    set: &mut KjointSet,
    ground: RigidBodyHandle,
    corners: &[Vector],
) {
    let n = corners.len();
    let mut bars = Vec::new();
    for k in 0..n {
        let (a, b) = (corners[k], corners[(k + 1) % n]);
        bars.push((rod(w, (a + b) * 0.5), a, b));
    }
    for k in 0..n {
        let (b1, _, end1) = bars[k];
        let (b2, start2, _) = bars[(k + 1) % n];
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
}

/// A four-bar linkage and rings of ten and seventy rods (the loop solve's factorisation by
/// blocks, the rings in faer's fill-reducing order) and two rods joined by twelve hinges
/// (faer's sparse factorisation: every pair of the hinges is coupled) next to a tree island.
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
    hinged_ring(&mut w, &mut set, ground, &corners);
    // rings of n rods (polygons of side LINK) hung from the world at one corner, to the
    // left of the others
    let polygon = |n: usize, x: Real| -> Vec<Vector> {
        let radius = LINK / (2.0 * (std::f64::consts::PI as Real / n as Real).sin());
        let centre = Vector::new(x - radius, -radius, 0.0);
        (0..n)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_2 as Real
                    + k as Real * std::f64::consts::TAU as Real / n as Real;
                centre + Vector::new(a.cos(), a.sin(), 0.0) * radius
            })
            .collect()
    };
    hinged_ring(&mut w, &mut set, ground, &polygon(10, -0.8));
    hinged_ring(&mut w, &mut set, ground, &polygon(70, -2.0));
    // two rods side by side, 2 cm apart, hinged to each other at twelve points along them: an island
    // whose twelve joints all share both bodies
    let (r1, r2) = (
        rod(&mut w, Vector::new(3.0, -0.2, 0.0)),
        rod(&mut w, Vector::new(3.02, -0.2, 0.0)),
    );
    for k in 0..12 {
        let y = -LINK / 2.0 + LINK * k as Real / 11.0;
        set.insert(
            hinge(1e8)
                .local_anchor1(Vector::new(0.01, y, 0.0))
                .local_anchor2(Vector::new(-0.01, y, 0.0)),
            r1,
            r2,
            &w.bodies,
        )
        .unwrap();
    }
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
            KjointBuilder::new(KjointProperty::new(JointType::Spherical).with_kn(1e9))
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
    assert_eq!(set.island_count(), 6);
    assert_eq!(set.loop_joints().len(), 14, "{:?}", set.loop_joints());
    // both factorisations
    let factors = set.solver_factorisations();
    assert_eq!(factors, (3, 1), "(by blocks, sparse) loop islands");
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
    let e1 = set.get(h1).unwrap().energy();
    w.remove_body(b);
    set.step(&mut w, 1.0 / 60.0).unwrap();
    let events = set.drain_events();
    assert_eq!(events.len(), 1, "{events:?}");
    assert!(matches!(events[0].source, EventSource::Joint { handle, .. } if handle == h1));
    // the joint left the set (as rapier's impulse joints of a removed body); its energies
    // are kept with the removed ones
    assert!(set.get(h1).is_none() && !set.contains(h1));
    assert_eq!(set.len(), 1);
    assert_eq!(set.removed_energy(), e1);
    assert!(set.get(h0).is_some() && set.contains(h0));
    assert_eq!(set.attached_joints(a).count(), 1);
    // a joint inserted afterwards never answers to the removed joint's handle
    let c = rod(&mut w, Vector::new(0.0, -1.5 * LINK, 0.0));
    let h2 = set
        .insert(
            hinge(1e9).local_anchor1(-up).local_anchor2(up),
            a,
            c,
            &w.bodies,
        )
        .unwrap();
    assert_ne!(h2, h1);
    assert!(set.get(h1).is_none());
    assert_eq!(set.get(h2).unwrap().body2(), c);
    w.remove_body(c);
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

/// Double-double numbers (Dekker): the residuals of the accuracy test, exact enough that
/// one correction solved in `f64` gives the true solution to far better than the errors
/// measured.
#[derive(Debug, Clone, Copy, Default)]
struct Dd(f64, f64);

impl Dd {
    fn fast(s: f64, e: f64) -> Dd {
        let hi = s + e;
        Dd(hi, e - (hi - s))
    }
    fn add(self, o: Dd) -> Dd {
        let s = self.0 + o.0;
        let bb = s - self.0;
        let e = (self.0 - (s - bb)) + (o.0 - bb);
        Dd::fast(s, e + self.1 + o.1)
    }
    fn mul(self, b: f64) -> Dd {
        let p = self.0 * b;
        let e = self.0.mul_add(b, -p) + self.1 * b;
        Dd::fast(p, e)
    }
}

/// The residual `r − (G⁻¹ + J·M⁻¹·Jᵀ)·P` of the joint-space system, in double-double.
fn residual(joints: &SolverJoints, bodies: &[SolverBody], p: &[Vector6<f64>]) -> Vec<Vector6<f64>> {
    // w_b = Σ Jᵀ·P, then u_b = M⁻¹·w_b
    let mut w = vec![[Dd::default(); 6]; bodies.len()];
    for (sj, pj) in joints.iter().zip(p) {
        for s in 0..2 {
            if let Some(b) = sj.bodies[s] {
                let jac = sj.jac.matrix(s);
                for c in 0..6 {
                    for r in 0..6 {
                        let t = Dd(jac[(r, c)], 0.0).mul(pj[r]);
                        w[b as usize][c] = w[b as usize][c].add(t);
                    }
                }
            }
        }
    }
    let u: Vec<[Dd; 6]> = w
        .iter()
        .zip(bodies)
        .map(|(wb, sb)| {
            let m = sb.inv_mass.matrix();
            std::array::from_fn(|r| {
                (0..6).fold(Dd::default(), |acc, c| acc.add(wb[c].mul(m[(r, c)])))
            })
        })
        .collect();
    joints
        .iter()
        .enumerate()
        .zip(p)
        .map(|((j, sj), pj)| {
            let (mut g_inv, mut r) = (Matrix6::zeros(), Vector6::zeros());
            joint_block(joints, bodies, j as u32, &mut g_inv, &mut r).unwrap();
            Vector6::from_fn(|row, _| {
                let mut acc = Dd(r[row], 0.0);
                for c in 0..6 {
                    acc = acc.add(Dd(g_inv[(row, c)], 0.0).mul(-pj[c]));
                }
                for s in 0..2 {
                    if let Some(b) = sj.bodies[s] {
                        let jac = sj.jac.matrix(s);
                        for c in 0..6 {
                            acc = acc.add(u[b as usize][c].mul(-jac[(row, c)]));
                        }
                    }
                }
                acc.0 + acc.1
            })
        })
        .collect()
}

/// Errors of the joint-space links and of the body + joint form against the true solution
/// of the last substep of `set` (one tree island). Returns `(links, body + joint)`, each
/// `(impulses, velocities)` relative to the largest, and prints them per DOF.
fn link_errors(set: &KjointSet, label: &str) -> ((f64, f64), (f64, f64)) {
    use super::topology::{self, Plan};
    use super::tree::TreeSolve;
    let data = &set.data;
    let (joints, bodies) = (&data.joints, &data.bodies);
    let active = vec![true; joints.len()];
    let plans = topology::analyse(bodies.len(), &data.sides, &active);
    assert_eq!(plans.len(), 1);
    let Plan::Tree(nodes) = plans[0].plan.clone() else {
        panic!("a tree")
    };
    let run = |links: bool, rhs: Option<&[Vector6<f64>]>| {
        let mut nodes = nodes.clone();
        if !links {
            nodes.iter_mut().for_each(|n| n.link = false);
        }

        let mut t = TreeSolve::new(nodes);
        t.load(joints, bodies).unwrap();
        if let Some(rhs) = rhs {
            for (j, x) in t.rhs_mut() {
                *x = rhs[j as usize];
            }
        }
        t.eliminate(joints, bodies).unwrap();
        t.substitute(joints, bodies);
        let mut p = vec![Vector6::zeros(); joints.len()];
        let mut u = vec![Vector6::zeros(); bodies.len()];
        for (n, x) in t.nodes.iter().zip(&t.x) {
            match n.kind {
                NodeKind::Joint(j) => p[j as usize] = *x,
                NodeKind::Body(b) => u[b as usize] = *x,
            }
        }
        (p, u)
    };
    // the true solution: the body + joint solution corrected twice by the exact residual
    let (mut p_true, _) = run(false, None);
    for _ in 0..2 {
        let res = residual(joints, bodies, &p_true);
        let (d, _) = run(false, Some(&res));
        for (p, d) in p_true.iter_mut().zip(&d) {
            *p += d;
        }
    }
    let velocity = |p: &[Vector6<f64>]| {
        let mut w = vec![Vector6::zeros(); bodies.len()];
        for (sj, pj) in joints.iter().zip(p) {
            for s in 0..2 {
                if let Some(b) = sj.bodies[s] {
                    w[b as usize] += sj.jac.tr_mul(s, pj);
                }
            }
        }
        w.iter()
            .zip(bodies)
            .map(|(w, b)| b.inv_mass.matrix() * w)
            .collect::<Vec<_>>()
    };
    let u_true = velocity(&p_true);
    let pmax = p_true.iter().map(|v| v.amax()).fold(0.0, f64::max);
    let umax = u_true.iter().map(|v| v.amax()).fold(0.0, f64::max);
    let scales: Vec<String> = (0..6)
        .map(|r| {
            format!(
                "{:.1e}",
                p_true.iter().map(|v| v[r].abs()).fold(0.0, f64::max) / pmax
            )
        })
        .collect();
    let uscales: Vec<String> = (0..6)
        .map(|r| {
            format!(
                "{:.1e}",
                u_true.iter().map(|v| v[r].abs()).fold(0.0, f64::max) / umax
            )
        })
        .collect();
    println!(
        "{label}: |P| {pmax:.2e}, DOF scales {}; |u| {umax:.2e}, scales {}",
        scales.join(" "),
        uscales.join(" ")
    );
    let worst = |a: &[Vector6<f64>], b: &[Vector6<f64>], rows: std::ops::Range<usize>| {
        let scale = b
            .iter()
            .flat_map(|v| rows.clone().map(move |r| v[r].abs()))
            .fold(0.0, f64::max);
        let e = a
            .iter()
            .zip(b)
            .flat_map(|(x, y)| rows.clone().map(move |r| (x[r] - y[r]).abs()))
            .fold(0.0, f64::max);
        e / scale.max(f64::MIN_POSITIVE)
    };
    let mut out = [(0.0, 0.0); 2];
    for (k, links) in [true, false].into_iter().enumerate() {
        let (p, u) = run(links, None);
        let per_dof: Vec<String> = (0..6)
            .map(|r| format!("{:.1e}", worst(&p, &p_true, r..r + 1)))
            .collect();
        let per_u: Vec<String> = (0..6)
            .map(|r| format!("{:.1e}", worst(&u, &u_true, r..r + 1)))
            .collect();
        println!("   u per component {}", per_u.join(" "));
        println!(
            "{label} {}: P {:.2e} (per DOF {}), u linear {:.2e} angular {:.2e}",
            if links { "links     " } else { "body+joint" },
            worst(&p, &p_true, 0..6),
            per_dof.join(" "),
            worst(&u, &u_true, 0..3),
            worst(&u, &u_true, 3..6),
        );
        out[k] = (worst(&p, &p_true, 0..6), worst(&u, &u_true, 0..6));
    }
    (out[0], out[1])
}

/// A chain of `n` rods at `kn` released at 30°, rotations locked as `rotations` says,
/// stepped `frames` frames.
fn long_chain(n: usize, kn: f64, rotations: [bool; 3], frames: usize) -> KjointSet {
    let (mut w, mut set, ground) = new_world();
    let dir = Vector::new(0.5, -(Real::sqrt(3.0)) / 2.0, 0.0);
    let rot = Rotation::from_rotation_arc(Vector::X, dir);
    let mut prev = ground;
    for k in 0..n {
        let i = 0.1 * LINK * LINK / 12.0;
        let at = dir * (LINK * (k as Real + 0.5));
        let b = w.insert_body(
            RigidBodyBuilder::dynamic()
                .translation(at)
                .rotation(rot.to_scaled_axis())
                .enabled_rotations(rotations[0], rotations[1], rotations[2])
                .can_sleep(false)
                .additional_mass_properties(MassProperties::new(
                    Vector::ZERO,
                    0.1,
                    Vector::new(0.1 * i, i, i),
                )),
        );
        let pa = if k == 0 { Vector::ZERO } else { half() };
        joint(&mut set, &w, prev, b, pa, -half(), kn);
        prev = b;
    }
    for _ in 0..frames {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    set
}

/// The joint-space elimination of links against the body + joint form, both against the
/// true solution (exact residual): long stiff chains, free and with locked rotations. The
/// joint-space form is the less accurate of the two on long stiff chains (the tree module's
/// *Accuracy*): both are printed (`--nocapture`), the links' errors are bounded.
#[test]
fn links_stay_accurate_on_long_stiff_chains() {
    for (n, kn, rot, label) in [
        (30, 1e12, [true; 3], "chain 30"),
        (1000, 1e12, [true; 3], "chain 1000"),
        (1000, 1e8, [true; 3], "chain 1000 Kn 1e8"),
        (1000, 1e12, [false, false, true], "chain 1000 z only"),
        (1000, 1e12, [false; 3], "chain 1000 no rotation"),
    ] {
        let set = long_chain(n, kn, rot, 30);
        let ((p, u), _) = link_errors(&set, label);
        assert!(
            p < 1e-10 && u < 1e-10,
            "{label}: impulses {p:e}, velocities {u:e}"
        );
    }
}

/// Time of one tree solve of the last substep of `set`, links in the joint-space form and
/// all bodies in the body + joint form, interleaved: (links, body + joint) in ns per joint,
/// the minimum over `rounds` rounds.
fn time_forms(set: &KjointSet, rounds: usize) -> (f64, f64) {
    use super::topology::{self, Plan};
    use super::tree::TreeSolve;
    let data = &set.data;
    let (joints, bodies) = (&data.joints, &data.bodies);
    let active = vec![true; joints.len()];
    let mut nodes = Vec::new();
    for plan in topology::analyse(bodies.len(), &data.sides, &active) {
        let Plan::Tree(n) = plan.plan else {
            panic!("trees only")
        };
        let offset = nodes.len() as u32;
        nodes.extend(n.into_iter().map(|mut n| {
            if n.parent != u32::MAX {
                n.parent += offset;
            }
            n
        }));
    }
    let mut plain = nodes.clone();
    plain.iter_mut().for_each(|n| n.link = false);
    let mut solvers = [TreeSolve::new(nodes), TreeSolve::new(plain)];
    let mut best = [f64::INFINITY; 2];
    let reps = (20_000 / joints.len()).max(1);
    let only = std::env::var("KJ_FORM").ok();
    for _ in 0..rounds {
        for (k, (s, b)) in solvers.iter_mut().zip(best.iter_mut()).enumerate() {
            if only.as_deref().is_some_and(|o| o != ["links", "body"][k]) {
                continue;
            }
            let t = std::time::Instant::now();
            for _ in 0..reps {
                s.solve(joints, bodies).unwrap();
                std::hint::black_box(&s.x);
            }
            *b = b.min(t.elapsed().as_secs_f64() * 1e9 / (reps * joints.len()) as f64);
        }
    }
    (best[0], best[1])
}

/// The tree solve alone on the last substep of chains, links in the joint-space form
/// against every body in the body + joint form: `cargo test --release --lib time_links --
/// --ignored --nocapture` (`KJ_FORM=links` or `KJ_FORM=body` times one form only, for a
/// profiler).
#[test]
#[ignore = "a timing, in release"]
fn time_links() {
    for (n, label) in [
        (1000, "chain 1000"),
        (100, "chain 100"),
        (10000, "chain 10000"),
    ] {
        let set = long_chain(n, 1e12, [true; 3], 5);
        let (l, b) = time_forms(&set, 300);
        println!(
            "{label}: links {l:.1} ns/joint, body+joint {b:.1} ns/joint, ratio {:.3}",
            l / b
        );
    }
}

/// A tree rooted at a body with one child joint (a link without a parent joint, which
/// [`super::topology`] never makes: its roots are joints), on hand-made blocks with full
/// Jacobians: world – j0 – b0 – j1 – b1 – j2 – b2, rooted at b2, and the same rooted at j0
/// as the topology roots it. Both forms, against the dense reference, with every `G`
/// diagonal and with a coupled one (the side table of [`SolverJoints`]).
#[test]
fn a_link_at_the_root_matches_the_dense_solve() {
    use super::topology::TreeNode;
    use super::tree::TreeSolve;
    let f = |seed: usize| {
        Matrix6::from_fn(|r, c| (((r * 7 + c * 13 + seed * 29) % 17) as f64 - 8.0) / 8.0)
    };
    let body = |k: usize| {
        let a = f(k + 10).fixed_view::<3, 3>(0, 0).into_owned();
        let inertia = a * a.transpose() + nalgebra::Matrix3::identity() * 0.5;
        let inv_mass = MassBlocks {
            linear: nalgebra::Vector3::repeat(1.0 + 0.5 * k as f64),
            angular: inertia,
        };
        SolverBody {
            inv_mass,
            dv_ext: Vector6::from_fn(|r, _| 0.1 * (r as f64 - 2.0) * (k as f64 + 1.0)),
            mass: Some(MassBlocks {
                linear: inv_mass.linear.map(|m| 1.0 / m),
                angular: inertia.try_inverse().unwrap(),
            }),
        }
    };
    let bodies: Vec<SolverBody> = (0..3).map(body).collect();
    let joint = |k: usize, sides: [Option<u32>; 2]| SolverJoint {
        bodies: sides,
        // every block of a joint's Jacobians full (T, R and the two lever blocks
        // `−T·[a_s]×`), the rotation rates × linear velocities zero as in every joint
        jac: {
            let (a, b) = (f(2 * k), f(2 * k + 1));
            super::RateJacobians {
                t: a.fixed_view::<3, 3>(0, 0).into_owned(),
                r: a.fixed_view::<3, 3>(3, 3).into_owned(),
                arm: [
                    a.fixed_view::<3, 1>(0, 3).into_owned(),
                    b.fixed_view::<3, 1>(0, 3).into_owned(),
                ],
            }
        },
        explicit: Vector6::from_fn(|r, _| (r as f64 + 1.0) * (k as f64 - 0.5)),
        ..SolverJoint::default()
    };
    let node = |kind, parent: u32, side: u8, link| TreeNode {
        kind,
        parent,
        side,
        link,
    };
    use NodeKind::{Body, Joint};
    let at_body = vec![
        node(Joint(0), 1, 1, false),
        node(Body(0), 2, 0, true),
        node(Joint(1), 3, 1, false),
        node(Body(1), 4, 0, true),
        node(Joint(2), 5, 1, false),
        node(Body(2), u32::MAX, 0, true),
    ];
    let at_joint = vec![
        node(Body(2), 1, 1, false),
        node(Joint(2), 2, 0, false),
        node(Body(1), 3, 1, true),
        node(Joint(1), 4, 0, false),
        node(Body(0), 5, 1, true),
        node(Joint(0), u32::MAX, 0, false),
    ];
    // one stiff, one soft, one free DOF among the others; with `coupled`, the middle joint's
    // G also couples its DOFs (positive definite: diagonally dominant), from the side table
    for coupled in [false, true] {
        let mut joints = SolverJoints::from(vec![
            joint(0, [None, Some(0)]),
            joint(1, [Some(0), Some(1)]),
            joint(2, [Some(1), Some(2)]),
        ]);
        for k in 0..3 {
            let mut g = Matrix6::from_diagonal(&Vector6::new(1e6, 1e-3, 0.0, 2.0, 1e6, 0.5));
            if coupled && k == 1 {
                g = Matrix6::from_diagonal(&Vector6::new(1e6, 1.0, 1.0, 2.0, 1e6, 1.5));
                for (r, c, v) in [(1, 0, 0.3), (2, 1, -0.4), (5, 3, 0.7), (4, 0, 1e3)] {
                    g[(r, c)] = v;
                    g[(c, r)] = v;
                }
            }
            joints.set_g(k, &g);
        }
        assert_eq!(joints.coupled.len(), coupled as usize);
        assert_eq!(joints.g(1)[(5, 3)], if coupled { 0.7 } else { 0.0 });
        let reference = super::reference_solve(&joints, &bodies);
        // the second is the topology's own plan
        let sides: Vec<_> = joints.iter().map(|j| j.bodies).collect();
        let plans = super::topology::analyse(3, &sides, &[true; 3]);
        assert_eq!(plans[0].plan, super::topology::Plan::Tree(at_joint.clone()));
        for (nodes, label) in [(&at_body, "rooted at b2"), (&at_joint, "rooted at j0")] {
            for links in [true, false] {
                let mut nodes = nodes.clone();
                nodes.iter_mut().for_each(|n| n.link &= links);
                let mut t = TreeSolve::new(nodes);
                t.solve(&joints, &bodies).unwrap();
                let mut p = [Vector6::zeros(); 3];
                let mut u = [Vector6::zeros(); 3];
                for (n, x) in t.nodes.iter().zip(&t.x) {
                    match n.kind {
                        Joint(j) => p[j as usize] = *x,
                        Body(b) => u[b as usize] = *x,
                    }
                }
                let scale = reference.iter().map(|v| v.amax()).fold(0.0, f64::max);
                for j in 0..3 {
                    let e = (p[j] - reference[j]).amax() / scale;
                    assert!(e < 1e-9, "{label}, links {links}: joint {j} off by {e:e}");
                }
                // u = M⁻¹·Σ Jᵀ·P
                for (b, sb) in bodies.iter().enumerate() {
                    let mut w = Vector6::zeros();
                    for (sj, pj) in joints.iter().zip(&reference) {
                        for s in 0..2 {
                            if sj.bodies[s] == Some(b as u32) {
                                w += sj.jac.tr_mul(s, pj);
                            }
                        }
                    }
                    let expected = sb.inv_mass.matrix() * w;
                    let e = (u[b] - expected).amax() / expected.amax();
                    assert!(e < 1e-9, "{label}, links {links}: body {b} off by {e:e}");
                }
            }
        }
    }
}

/// Every joint of a body reads its `SolverBody` each substep: kept to its blocks (96 bytes
/// each for `M⁻¹` and `M` where the 6×6 took 288, plus `Δv_ext` and the tag of `M`).
#[test]
fn solver_body_is_compact() {
    assert_eq!(std::mem::size_of::<MassBlocks>(), 96);
    assert_eq!(std::mem::size_of::<SolverBody>(), 248);
    // and every joint reads its SolverJoint: G by its diagonal (SolverJoints), the
    // Jacobians by T, R and the lever arms (RateJacobians)
    assert_eq!(std::mem::size_of::<super::RateJacobians>(), 192);
    assert_eq!(std::mem::size_of::<SolverJoint>(), 312);
}

/// A pseudo-random generator of uniform numbers in [−1, 1) (no dependency, reproducible).
pub(super) fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut seed = seed;
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// Pseudo-random rate Jacobians (entries in [−1, 1)).
pub(super) fn random_jacobians(rand: &mut impl FnMut() -> f64) -> super::RateJacobians {
    let mut m3 = || nalgebra::Matrix3::from_fn(|_, _| rand());
    let (t, r) = (m3(), m3());
    let mut v3 = || nalgebra::Vector3::from_fn(|_, _| rand());
    super::RateJacobians {
        t,
        r,
        arm: [v3(), v3()],
    }
}

/// A pseudo-random block-diagonal inverse mass over six decades: the world inertia
/// `B·Bᵀ + 0.1` scaled, and every fourth case (`n % 4 == 0`) a locked translation.
pub(super) fn random_mass(rand: &mut impl FnMut() -> f64, n: usize) -> MassBlocks {
    use nalgebra::{Matrix3, Vector3};
    let b = Matrix3::from_fn(|_, _| rand());
    let scale = 10f64.powf(6.0 * rand());
    MassBlocks {
        linear: Vector3::new(rand().abs(), if n % 4 == 0 { 0.0 } else { 1.0 }, 2.0) * scale,
        angular: (b * b.transpose() + Matrix3::identity() * 0.1) * scale,
    }
}

/// The positive part of a symmetric 3×3 by nalgebra's eigen-decomposition.
fn eigen_positive_part(k: &nalgebra::Matrix3<f64>) -> nalgebra::Matrix3<f64> {
    let eig = k.symmetric_eigen();
    let pos = eig.eigenvalues.map(|l: f64| l.max(0.0));
    eig.eigenvectors * nalgebra::Matrix3::from_diagonal(&pos) * eig.eigenvectors.transpose()
}

/// (f, r) pairs of every kind: random directions over ±100 decades of magnitude, nearly and
/// exactly parallel and antiparallel, orthogonal, zero.
fn force_lever_pairs() -> Vec<(nalgebra::Vector3<f64>, nalgebra::Vector3<f64>)> {
    use nalgebra::Vector3;
    let mut rand = uniform(2024);
    let mut pairs = Vec::new();
    for n in 0..6000 {
        let r = Vector3::new(rand(), rand(), rand()) * 10f64.powf(100.0 * rand());
        let scale = 10f64.powf(100.0 * rand());
        let dir = Vector3::new(rand(), rand(), rand());
        let f = match n % 6 {
            0 | 1 => dir * scale,
            // nearly in line with the lever, pulling or pushing
            2 => (r.normalize() + dir * 1e-7) * scale,
            3 => (-r.normalize() + dir * 1e-7) * scale,
            // exactly in line (a multiple of r), or orthogonal to it
            4 => r * (rand() * scale / r.norm()),
            _ => r.cross(&dir) * (scale / r.norm()),
        };
        pairs.push((f, r));
    }
    let (x, y) = (Vector3::x(), Vector3::y());
    pairs.extend([
        (Vector3::zeros(), x),
        (x, Vector3::zeros()),
        (Vector3::zeros(), Vector3::zeros()),
        (x * 3.0, x * 2.0),
        (-x * 3.0, x * 2.0),
        (y * 3.0, x * 2.0),
        (x * 1e-300, y * 1e-5),
    ]);
    pairs
}

/// The closed form of one force's positive part against the eigen-decomposition and the
/// general path, to 1e-12 of `|f|·|r|`.
#[test]
fn single_force_positive_part_equals_the_general_one() {
    use super::{geometric_stiffness, positive_part::positive_part, single_force_positive_part};
    for (f, r) in force_lever_pairs() {
        let k = geometric_stiffness(&f, &r);
        // |f|·|r| within a factor 3 (|f|² underflows below 1e-154)
        let scale = f.amax() * r.amax();
        let got = single_force_positive_part(&f, &r)
            .expect("finite")
            .unwrap_or_else(nalgebra::Matrix3::zeros);
        let expected = eigen_positive_part(&k);
        assert!(
            (got - expected).amax() <= 1e-12 * scale,
            "f {f:?}, r {r:?}: off by {:e} of |f|·|r|",
            (got - expected).amax() / scale
        );
        // the general path's characteristic polynomial ((|f|·|r|)³) over- or underflows
        // beyond ±60 decades
        if !(1e-60..1e60).contains(&scale) {
            continue;
        }
        let general = positive_part(&k).unwrap_or_else(nalgebra::Matrix3::zeros);
        assert!(
            (got - general).amax() <= 1e-12 * scale,
            "f {f:?}, r {r:?}: off the general path by {:e} of |f|·|r|",
            (got - general).amax() / scale
        );
        assert_eq!(got, got.transpose());
    }
    // not finite: the general path decides
    let inf = nalgebra::Vector3::new(f64::INFINITY, 0.0, 0.0);
    assert_eq!(
        single_force_positive_part(&inf, &nalgebra::Vector3::x()),
        None
    );
}

/// The closed form of one force's positive part as it was computed from the unit vectors
/// `f̂`, `r̂` (six divisions and `a/|v|²`): the reference of the form without them.
fn unit_vector_single_force_positive_part(
    f: &nalgebra::Vector3<f64>,
    r: &nalgebra::Vector3<f64>,
) -> Option<nalgebra::Matrix3<f64>> {
    let (mf, mr) = (f.amax(), r.amax());
    if mf == 0.0 || mr == 0.0 {
        return None;
    }
    // scaled to a largest component of 1 (exact), scaled back
    let (f, r) = (f / mf, r / mr);
    let (nf, nr) = (f.norm(), r.norm());
    let (fh, rh) = (f / nf, r / nr);
    let p = nf * nr;
    let c = fh.dot(&rh);
    let a = p * c;
    let u = rh - fh;
    let k = if a >= 0.0 {
        let v = rh + fh;
        nalgebra::Matrix3::identity() * a + u * u.transpose() * (0.25 * p)
            - v * v.transpose() * (a / v.norm_squared())
    } else {
        let k = 0.25 * p * (1.0 + c) / (1.0 - c);
        if k.is_nan() || k <= 0.0 {
            return None;
        }
        u * u.transpose() * k
    };
    Some(k * (mf * mr))
}

/// The form without unit vectors against the one with them, to 1e-14 of `|f|·|r|`: the
/// same closed form, the round-off of its scale factors moved.
#[test]
fn single_force_positive_part_equals_the_unit_vector_form() {
    use super::single_force_positive_part;
    let mut worst = 0.0f64;
    for (f, r) in force_lever_pairs() {
        let scale = f.amax() * r.amax();
        let got = single_force_positive_part(&f, &r)
            .expect("finite")
            .unwrap_or_else(nalgebra::Matrix3::zeros);
        let old =
            unit_vector_single_force_positive_part(&f, &r).unwrap_or_else(nalgebra::Matrix3::zeros);
        let e = (got - old).amax() / scale.max(f64::MIN_POSITIVE);
        worst = worst.max(e);
        assert!(e <= 1e-14, "f {f:?}, r {r:?}: off by {e:e} of |f|·|r|");
    }
    println!("worst difference {worst:e} of |f|·|r|");
}

/// The positive part of two forces' stiffness (a chain's interior link, the middle capsule
/// of the contact scene: [`super::GeometricLoad`] with two forces, the general path) against
/// the eigen-decomposition, to 1e-12 of the largest `|f|·|r|`, on the pairs of
/// [`force_lever_pairs`] within ±40 decades taken two by two (the second force pulling
/// nearly against the first in a third of the cases: a link under tension).
#[test]
fn two_forces_positive_part_equals_the_eigen_decomposition() {
    use super::{positive_part::positive_part, GeometricLoad};
    let pairs: Vec<_> = force_lever_pairs()
        .into_iter()
        .filter(|(f, r)| (1e-40..1e40).contains(&(f.amax() * r.amax())))
        .collect();
    let mut rand = uniform(99);
    for (n, w) in pairs.windows(2).enumerate() {
        let (f1, r1) = w[0];
        let (mut f2, mut r2) = w[1];
        if n % 3 == 0 {
            // the other joint of a link: lever and force nearly opposite to the first
            let jitter = nalgebra::Vector3::new(rand(), rand(), rand()) * 1e-3;
            f2 = -f1 * (1.0 + 0.1 * rand()) + jitter * f1.norm();
            r2 = -r1 * (1.0 + 0.1 * rand()) + jitter * r1.norm();
        }
        let mut load = GeometricLoad::NONE;
        load.add(&f1, &r1);
        load.add(&f2, &r2);
        let k = load.stiffness();
        let scale = (f1.amax() * r1.amax()).max(f2.amax() * r2.amax());
        let got = positive_part(&k).unwrap_or_else(nalgebra::Matrix3::zeros);
        let expected = eigen_positive_part(&k);
        assert!(
            (got - expected).amax() <= 1e-12 * scale,
            "{n}: {k} off by {:e}",
            (got - expected).amax() / scale
        );
    }
}

/// The load keeps one force as it is and sums the stiffnesses of several exactly as a sum
/// from zero would.
#[test]
fn geometric_load_sums_its_forces() {
    use super::{geometric_stiffness, GeometricLoad};
    use nalgebra::{Matrix3, Vector3};
    let mut rand = uniform(7);
    let mut load = GeometricLoad::NONE;
    for _round in 0..3 {
        load.clear();
        assert_eq!(load.stiffness(), Matrix3::zeros());
        let mut sum = Matrix3::zeros();
        for _ in 0..4 {
            let f = Vector3::new(rand(), rand(), rand()) * 100.0;
            let r = Vector3::new(rand(), rand(), rand());
            load.add(&f, &r);
            sum += geometric_stiffness(&f, &r);
            assert_eq!(load.stiffness(), sum);
        }
    }
}

/// The augmented inertia from the inertia itself (a symmetric 3×3 inverse) against the
/// general form from the inverse inertia, on bodies of every shape and loads from none to
/// a thousand times the inertia.
#[test]
fn augmented_inertia_equals_the_general_form() {
    use super::single_force_positive_part;
    use nalgebra::{Matrix3, UnitQuaternion, Vector3};
    let mut rand = uniform(99);
    for n in 0..3000 {
        let q = UnitQuaternion::from_scaled_axis(Vector3::new(rand(), rand(), rand()) * 3.0);
        let rot = q.to_rotation_matrix().into_inner();
        let scale = 10f64.powf(6.0 * rand());
        // principal inertias from a sphere to a slender rod (1e-3)
        let p = Vector3::new(1.0, 0.5 + rand().abs(), 10f64.powf(-3.0 * rand().abs())) * scale;
        let inertia = rot * Matrix3::from_diagonal(&p) * rot.transpose();
        let inv = rot * Matrix3::from_diagonal(&p.map(|x| 1.0 / x)) * rot.transpose();
        let body = SolverBody {
            inv_mass: MassBlocks {
                linear: Vector3::new(1.0, 1.0, 1.0),
                angular: inv,
            },
            dv_ext: Vector6::new(0.1, 0.2, 0.3, rand(), rand(), rand()),
            mass: Some(MassBlocks {
                linear: Vector3::new(1.0, 1.0, 1.0),
                angular: inertia,
            }),
        };
        let f = Vector3::new(rand(), rand(), rand());
        let r = Vector3::new(rand(), rand(), rand());
        let load = 10f64.powf(3.0 * rand()) * scale / (f.norm() * r.norm());
        let skp = match n % 3 {
            0 => Matrix3::zeros(),
            _ => single_force_positive_part(&(load * f), &r)
                .unwrap()
                .unwrap_or_default(),
        };
        let (mut fast, mut general) = (body.clone(), body.clone());
        fast.add_augmented_inertia(&skp);
        general.add_augmented_inertia_general(&skp);
        // the reference: nalgebra's Cholesky inverse of I + s·K⁺ (backward stable: within a
        // few κ·ε of the exact inverse, κ its condition number). The cofactor inverse of the
        // fast form stays within 16·κ·ε of it (κ up to 3e4 here: 1e-11), and so within
        // 1e-12 of the general form wherever κ < 300; the general form, through the
        // products with I⁻¹ of a slender body under a large load, was measured up to
        // 9e4·κ·ε (1e-8) off it
        let aug = inertia + skp;
        let eig = aug.symmetric_eigen().eigenvalues;
        let kappa = eig.max() / eig.min();
        let reference = aug.cholesky().unwrap().inverse();
        let off = |m: &Matrix3<f64>| (m - reference).amax() / reference.amax();
        let (of, og) = (off(&fast.inv_mass.angular), off(&general.inv_mass.angular));
        assert!(
            of <= 16.0 * kappa * f64::EPSILON,
            "case {n}: I⁻¹ off by {of:e} (κ {kappa:e}), the general form by {og:e}"
        );
        let close = |a: &Matrix3<f64>, b: &Matrix3<f64>| (a - b).amax() <= 1e-12 * b.amax();
        let (mf, mg) = (fast.mass.unwrap().angular, general.mass.unwrap().angular);
        assert!(close(&mf, &mg), "{mf} vs {mg}");
        // Δω' = (I + s·K⁺)⁻¹·I·Δω, against the reference's
        let dw = |b: &SolverBody| b.dv_ext.fixed_rows::<3>(3).into_owned();
        let expected = reference * (inertia * dw(&body));
        let (df, dg) = (
            (dw(&fast) - expected).amax() / expected.amax(),
            (dw(&general) - expected).amax() / expected.amax(),
        );
        assert!(
            df <= 16.0 * kappa * f64::EPSILON,
            "case {n}: Δω off by {df:e} (κ {kappa:e}), the general form by {dg:e}"
        );
        assert_eq!(
            fast.dv_ext.fixed_rows::<3>(0),
            body.dv_ext.fixed_rows::<3>(0)
        );
    }
}

/// `set_g` keeps a block whose entries off the diagonal are all ±0 by its diagonal, and any
/// other (a tiny entry, a NaN) whole.
#[test]
fn set_g_tells_a_diagonal_block() {
    use super::NOT_COUPLED;
    let mut joints = SolverJoints::from(vec![SolverJoint::default()]);
    let mut g = Matrix6::from_diagonal(&Vector6::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0));
    g[(1, 4)] = -0.0;
    joints.set_g(0, &g);
    assert_eq!(joints[0].g_coupled, NOT_COUPLED);
    assert_eq!(joints[0].g_diagonal, g.diagonal());
    for v in [1e-300, -f64::MIN_POSITIVE, f64::NAN, f64::INFINITY] {
        let mut c = g;
        c[(5, 0)] = v;
        joints.coupled.clear();
        joints.set_g(0, &c);
        assert_eq!(joints[0].g_coupled, 0, "{v}");
    }
}

/// [`super::jacobian_weighted_diagonal`] against the row-by-row quadratic forms it replaced
/// and the diagonal of the dense `J·M⁻¹·Jᵀ`, both sides, on 4000 pseudo-random Jacobians and
/// inverse masses (one translation locked in a quarter) over twelve decades: every entry is
/// a sum of non-negative terms, so they agree to a few ulps relative.
#[test]
fn jacobian_weighted_diagonal_equals_the_quadratic_forms() {
    use nalgebra::RowVector3;
    let mut rand = uniform(4242);
    for n in 0..4000 {
        let jac = random_jacobians(&mut rand);
        let mb = random_mass(&mut rand, n);
        for s in 0..2 {
            let got = super::jacobian_weighted_diagonal(&jac, s, &mb);
            let quadratic = |row: RowVector3<f64>| (row * mb.angular).dot(&row);
            let (t, l, r) = (&jac.t, &jac.lever(s), &jac.r);
            let j = jac.matrix(s);
            let dense = (j * mb.matrix() * j.transpose()).diagonal();
            for k in 0..3 {
                let old = (0..3)
                    .map(|c| mb.linear[c] * t[(k, c)] * t[(k, c)])
                    .sum::<f64>()
                    + quadratic(l.row(k).into_owned());
                let old_r = quadratic(r.row(k).into_owned());
                for (g, o, d) in [(got[k], old, dense[k]), (got[3 + k], old_r, dense[3 + k])] {
                    assert!(
                        (g - o).abs() <= 8.0 * f64::EPSILON * o,
                        "{n} {s} {k}: {g} {o}"
                    );
                    assert!((g - d).abs() <= 1e-13 * d, "{n} {s} {k}: {g} {d}");
                }
            }
        }
    }
}

/// [`super::jacobian_weighted_diagonal_of_sides`] with both sides against the sides one by
/// one ([`super::jacobian_weighted_diagonal`] summed, the form the prepare stage took) on
/// 20 000 pseudo-random Jacobians and pairs of inverse masses over twelve decades: within a
/// few ulps of the sum of the terms' magnitudes (`Σ_k m⁻¹_k·T_rk² + Σ_s (|L_s|·|I⁻¹_s|·|L_s|ᵀ)_rr`
/// and `(|R|·(|I⁻¹_1| + |I⁻¹_2|)·|R|ᵀ)_rr`, the usual bound of a sum of products; the
/// quadratic forms' terms may cancel), entry by entry.
#[test]
fn weighted_diagonal_of_both_sides_equals_the_sides_sum() {
    let mut rand = uniform(9191);
    let mut worst = 0.0f64;
    for n in 0..20000 {
        let jac = random_jacobians(&mut rand);
        let (m1, m2) = (random_mass(&mut rand, n), random_mass(&mut rand, n / 3));
        let both = super::jacobian_weighted_diagonal_of_sides(&jac, [Some(&m1), Some(&m2)]);
        let sum = super::jacobian_weighted_diagonal(&jac, 0, &m1)
            + super::jacobian_weighted_diagonal(&jac, 1, &m2);
        let (i1, i2) = (m1.angular.abs(), m2.angular.abs());
        let (t, r) = (jac.t.abs(), jac.r.abs());
        let (l1, l2) = (jac.lever(0).abs(), jac.lever(1).abs());
        let lin = t * nalgebra::Matrix3::from_diagonal(&(m1.linear + m2.linear)) * t.transpose();
        let quad = l1 * i1 * l1.transpose() + l2 * i2 * l2.transpose();
        let ang = r * (i1 + i2) * r.transpose();
        for k in 0..6 {
            let scale = if k < 3 {
                lin[(k, k)] + quad[(k, k)]
            } else {
                ang[(k - 3, k - 3)]
            };
            let e = (both[k] - sum[k]).abs() / scale;
            worst = worst.max(e);
            assert!(e <= 8.0 * f64::EPSILON, "{n} {k}: {} {}", both[k], sum[k]);
        }
        let one = super::jacobian_weighted_diagonal(&jac, 1, &m2);
        assert_eq!(
            super::jacobian_weighted_diagonal_of_sides(&jac, [None, Some(&m2)]),
            one
        );
    }
    println!("both sides at once: {worst:e} of the terms' magnitudes from the sides' sum");
}

/// A forest's nodes taken round-robin ([`super::interleave`]): every tree keeps its nodes'
/// order and its parent links, and consecutive nodes belong to different trees while more
/// than one tree has nodes left.
#[test]
fn interleaved_forest_keeps_each_tree_and_alternates_them() {
    use super::topology::TreeNode;
    // three trees of 3, 1 and 2 nodes, parents within each tree (the last node its root)
    let node = |kind, parent| TreeNode {
        kind,
        parent,
        side: 0,
        link: false,
    };
    let forest = vec![
        node(NodeKind::Body(0), 1),
        node(NodeKind::Joint(0), 2),
        node(NodeKind::Body(1), u32::MAX),
        node(NodeKind::Joint(1), u32::MAX),
        node(NodeKind::Body(2), 5),
        node(NodeKind::Joint(2), u32::MAX),
    ];
    let starts = [0, 3, 4];
    let nodes = super::interleave(&forest, &starts);
    let kinds: Vec<NodeKind> = nodes.iter().map(|n| n.kind).collect();
    assert_eq!(
        kinds,
        [
            NodeKind::Body(0),
            NodeKind::Joint(1),
            NodeKind::Body(2),
            NodeKind::Joint(0),
            NodeKind::Joint(2),
            NodeKind::Body(1),
        ]
    );
    // every node's parent is the same node as before, and comes after it
    let position = |k: NodeKind| nodes.iter().position(|n| n.kind == k).unwrap() as u32;
    for old in &forest {
        let new = &nodes[position(old.kind) as usize];
        if old.parent == u32::MAX {
            assert_eq!(new.parent, u32::MAX);
        } else {
            let parent_kind = forest[old.parent as usize].kind;
            assert_eq!(new.parent, position(parent_kind));
            assert!(new.parent > position(old.kind), "a parent before its child");
        }
    }
}

/// A set of varied islands inserted interleaved (pendulums, hinged chains of two and three
/// rods, a closed triangle of ball joints, a sprung slider, a rod driven by a kinematic
/// body, a pendulum whose joint breaks): stepped whole and in tiles of at least `tile`
/// joints ([`crate::dynamics::tiles`]). Returns the world, the set and a body to remove.
fn varied_islands(tile: Option<usize>) -> (PhysicsWorld, KjointSet, RigidBodyHandle) {
    use crate::{BreakCriterion, Dof, DofLaw};
    let (mut w, mut set, ground) = new_world();
    set.tile_joints_min = tile;
    let up = Vector::new(0.0, LINK / 2.0, 0.0);
    let mut removable = ground;
    for g in 0..3 {
        let x = 0.5 * g as Real;
        // a pendulum released at 30° (its rod along the swing)
        let p = rod(&mut w, Vector::new(x + 0.025, -0.043, 0.0));
        let hp = hinge(1e9).local_anchor1(Vector::new(x, 0.0, 0.0));
        let hp = hp.local_anchor2(Vector::new(-0.025, 0.043, 0.0));
        set.insert(hp, ground, p, &w.bodies).unwrap();
        // a hinged chain of 2 + g rods hung from the ground
        let mut prev = ground;
        for k in 0..2 + g {
            let b = rod(&mut w, Vector::new(x + 0.1, -(k as Real + 0.5) * LINK, 0.1));
            let anchor1 = if k == 0 {
                Vector::new(x + 0.1, 0.0, 0.1)
            } else {
                -up
            };
            let j = hinge(1e8 * (1 + g) as f64)
                .local_anchor1(anchor1)
                .local_anchor2(up);
            set.insert(j, prev, b, &w.bodies).unwrap();
            prev = b;
            if g == 1 && k == 2 {
                removable = b;
            }
        }
        // a sprung slider along y with a stop (that never sleeps: the whole set stays one
        // tile, `dynamics::sleep` leaving asleep joints out of the tiles)
        let (s, _) = w.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(x, -1.0, 0.5))
                .can_sleep(false),
            ColliderBuilder::ball(0.05).mass(1.0 + g as Real),
        );
        let slide = KjointProperty::new(JointType::Translational).with_dof(
            Dof::Dx,
            DofLaw::spring(800.0 + 100.0 * g as f64).with_viscosity(5.0),
        );
        let slide = KjointBuilder::new(slide)
            .world_frame1(Rotation::from_rotation_arc(Vector::X, Vector::Y))
            .local_anchor1(Vector::new(x, -0.9, 0.5));
        set.insert(slide, ground, s, &w.bodies).unwrap();
    }
    // a closed triangle of ball joints among three free rods (the loop solve)
    let ball = KjointBuilder::new(KjointProperty::new(JointType::Spherical).with_kn(1e8));
    let corners = [
        Vector::new(2.0, 0.0, 0.0),
        Vector::new(2.1, 0.0, 0.0),
        Vector::new(2.05, 0.0866, 0.0),
    ];
    let tri: Vec<_> = (0..3)
        .map(|k| rod(&mut w, (corners[k] + corners[(k + 1) % 3]) / 2.0))
        .collect();
    for k in 0..3 {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        let c = corners[(k + 1) % 3];
        let ca = c - w.bodies[a].translation();
        let cb = c - w.bodies[b].translation();
        set.insert(
            ball.clone().local_anchor1(ca).local_anchor2(cb),
            a,
            b,
            &w.bodies,
        )
        .unwrap();
    }
    // a rod hinged to a kinematic body that moves
    let kin = w.insert_body(
        RigidBodyBuilder::kinematic_velocity_based()
            .translation(Vector::new(3.0, 0.0, 0.0))
            .linvel(Vector::new(0.2, 0.0, 0.0)),
    );
    let driven = rod(&mut w, Vector::new(3.0, -LINK / 2.0, 0.0));
    set.insert(hinge(1e9).local_anchor2(up), kin, driven, &w.bodies)
        .unwrap();
    // a pendulum on a joint that breaks under its swing
    let weak = rod(&mut w, Vector::new(3.5 + 0.025, -0.043, 0.0));
    let hw = hinge(1e9)
        .local_anchor1(Vector::new(3.5, 0.0, 0.0))
        .local_anchor2(Vector::new(-0.025, 0.043, 0.0))
        .break_when(BreakCriterion::force(1.05));
    set.insert(hw, ground, weak, &w.bodies).unwrap();
    (w, set, removable)
}

/// The bits of every body's pose and velocity and every joint's energies and readout.
fn state_bits(w: &PhysicsWorld, set: &KjointSet) -> Vec<u64> {
    let mut bits = Vec::new();
    for (_, b) in w.bodies.iter() {
        let (p, r) = (b.translation(), b.rotation());
        let (v, a) = (b.linvel(), b.angvel());
        for x in [
            p.x, p.y, p.z, r.x, r.y, r.z, r.w, v.x, v.y, v.z, a.x, a.y, a.z,
        ] {
            bits.push((x as f64).to_bits());
        }
    }
    for (_, j) in set.iter() {
        let e = j.energy();
        for x in [
            e.elastic,
            e.damping,
            e.friction,
            e.stop,
            e.internal,
            e.numerical,
        ] {
            bits.push(x.to_bits());
        }
        let s = j.state().expect("a readout");
        bits.extend(s.applied.0.iter().chain(&s.q.0).map(|x| x.to_bits()));
    }
    bits
}

/// A set stepped in tiles gives every body and joint the same bits as stepped whole,
/// through a joint breaking and a body removed from the world (the topology analysed
/// again, in tiles).
#[test]
fn tiles_give_the_same_bits() {
    let (mut w1, mut whole, gone1) = varied_islands(None);
    let (mut w2, mut tiled, gone2) = varied_islands(Some(3));
    let joints = whole.len();
    for frame in 0..90 {
        if frame == 45 {
            w1.remove_body(gone1);
            w2.remove_body(gone2);
        }
        whole.step(&mut w1, 1.0 / 60.0).unwrap();
        tiled.step(&mut w2, 1.0 / 60.0).unwrap();
        assert!(
            state_bits(&w1, &whole) == state_bits(&w2, &tiled),
            "frame {frame}: the tiled set differs"
        );
    }
    // it was tiled (several tiles of whole islands), and something broke and detached
    assert!(
        whole.tiles.is_empty() && tiled.tile_joints.len() >= 4,
        "{:?}",
        tiled.tile_joints
    );
    assert_eq!(whole.island_count(), tiled.island_count());
    assert_eq!(whole.loop_joints().len(), 1);
    assert_eq!(tiled.loop_joints(), whole.loop_joints());
    assert!(
        whole.len() <= joints - 2,
        "{} of {joints} joints left",
        whole.len()
    );
    assert_eq!(tiled.len(), whole.len());
    let kinds = |set: &mut KjointSet| -> Vec<String> {
        let mut k: Vec<String> = set
            .drain_events()
            .iter()
            .map(|e| format!("{:?}", e.kind))
            .collect();
        k.sort();
        k
    };
    assert_eq!(kinds(&mut whole), kinds(&mut tiled));
}

/// The tiles: cuts only between whole islands, each tile at least the minimum.
#[test]
fn tiles_hold_whole_islands() {
    let (w, set, _) = varied_islands(None);
    let joints: Vec<_> = set.iter().map(|(_, j)| j.clone()).collect();
    let tiles =
        crate::dynamics::tiles::tile_joints(&joints, &w.bodies, 3, &vec![false; joints.len()]);
    // per group: 1 pendulum, 2 + g chain joints, 1 slider; then the triangle (3), the
    // driven rod, the weak pendulum
    let ends: Vec<usize> = tiles.iter().map(|r| r.end).collect();
    assert_eq!(tiles[0].start, 0);
    for pair in tiles.windows(2) {
        assert_eq!(pair[0].end, pair[1].start);
        assert!(pair[0].len() >= 3);
    }
    assert_eq!(*ends.last().unwrap(), joints.len());
    // the triangle (joints 15, 16, 17) is never cut
    assert!(!ends.contains(&16) && !ends.contains(&17), "{ends:?}");
    // fewer than twice the minimum: one tile
    let one =
        crate::dynamics::tiles::tile_joints(&joints, &w.bodies, 11, &vec![false; joints.len()]);
    assert_eq!(one, vec![0..joints.len()]);
}

/// The tiles leave out runs of asleep joints: a long one, one that ends the set; a short
/// one after a small tile is stepped within it.
#[test]
fn tiles_leave_out_runs_of_asleep_joints() {
    use crate::dynamics::tiles::{tile_joints, ASLEEP_RUN, ASLEEP_TILE};
    let (mut w, mut set, ground) = new_world();
    for k in 0..200 {
        let x = 0.3 * k as Real;
        let p = rod(&mut w, Vector::new(x, -LINK / 2.0, 0.0));
        let j = hinge(1e9)
            .local_anchor1(Vector::new(x, 0.0, 0.0))
            .local_anchor2(Vector::new(0.0, LINK / 2.0, 0.0));
        set.insert(j, ground, p, &w.bodies).unwrap();
    }
    let joints: Vec<_> = set.iter().map(|(_, j)| j.clone()).collect();
    let mut asleep = vec![false; 200];
    // a long run (30), a short run (2) after a tile of 10, a short run (3) after a tile of
    // 70, and a run that ends the set
    asleep[10..40].fill(true);
    asleep[50..52].fill(true);
    asleep[122..125].fill(true);
    asleep[180..].fill(true);
    const { assert!(30 >= ASLEEP_RUN && 3 < ASLEEP_RUN && 10 < ASLEEP_TILE && 70 >= ASLEEP_TILE) };
    let tiles = tile_joints(&joints, &w.bodies, 1000, &asleep);
    assert_eq!(tiles, vec![0..10, 40..122, 125..180]);
    // nothing asleep: one tile, as before
    assert_eq!(
        tile_joints(&joints, &w.bodies, 1000, &[false; 200]),
        vec![0..200]
    );
    // everything asleep: none
    assert!(tile_joints(&joints, &w.bodies, 1000, &[true; 200]).is_empty());
}

/// Pendulums released at different angles, in tiles of four alike islands: the tiles after
/// the first borrow its solver, and every body has the same bits as stepped whole.
#[test]
fn alike_tiles_share_one_solver_with_the_same_bits() {
    let pendulums = |tile: Option<usize>| {
        let (mut w, mut set, ground) = new_world();
        set.tile_joints_min = tile;
        for k in 0..26 {
            let a = (10.0 + 3.0 * k as Real).to_radians();
            let (s, c) = (a.sin() * LINK / 2.0, a.cos() * LINK / 2.0);
            let x = 0.3 * k as Real;
            let p = rod(&mut w, Vector::new(x + s, -c, 0.0));
            let j = hinge(1e9)
                .local_anchor1(Vector::new(x, 0.0, 0.0))
                .local_anchor2(Vector::new(-s, c, 0.0));
            set.insert(j, ground, p, &w.bodies).unwrap();
        }
        (w, set)
    };
    let (mut w1, mut whole) = pendulums(None);
    let (mut w2, mut tiled) = pendulums(Some(4));
    for frame in 0..60 {
        whole.step(&mut w1, 1.0 / 60.0).unwrap();
        tiled.step(&mut w2, 1.0 / 60.0).unwrap();
        assert!(
            state_bits(&w1, &whole) == state_bits(&w2, &tiled),
            "frame {frame}: the tiled set differs"
        );
    }
    // 26 = 4 + 4 + 4 + 4 + 4 + 6: the last tile alone has its own solver
    assert_eq!(tiled.tile_joints.len(), 6);
    let shared: Vec<bool> = tiled.tiles.iter().map(|t| t.shares_solver).collect();
    assert_eq!(shared, [true, true, true, true, false]);
    assert_eq!(tiled.island_count(), 26);
    assert_eq!(whole.island_count(), 26);
}

/// Hinged chains of two rods in tiles of four joints: the top rod of one chain disabled
/// (`set_enabled(false)`) takes both its joints out of its tile, its lower rod falls at g,
/// and the other chains keep the same bits as in the set stepped whole; enabled again, the
/// chain is stepped again, still with the whole set's bits.
#[test]
fn a_disabled_body_leaves_its_tile_with_the_same_bits_as_the_whole_set() {
    let chains = |tile: Option<usize>| {
        let (mut w, mut set, ground) = new_world();
        set.tile_joints_min = tile;
        let up = Vector::new(0.0, LINK / 2.0, 0.0);
        let mut tops = Vec::new();
        let mut lows = Vec::new();
        for k in 0..12 {
            let x = 0.3 * k as Real;
            let top = rod(&mut w, Vector::new(x, -LINK / 2.0, 0.0));
            let low = rod(&mut w, Vector::new(x, -1.5 * LINK, 0.0));
            w.bodies[low].set_linvel(Vector::new(0.1 * k as Real, 0.0, 0.0), true);
            let j = hinge(1e9)
                .local_anchor1(Vector::new(x, 0.0, 0.0))
                .local_anchor2(up);
            set.insert(j, ground, top, &w.bodies).unwrap();
            let j = hinge(1e9).local_anchor1(-up).local_anchor2(up);
            set.insert(j, top, low, &w.bodies).unwrap();
            tops.push(top);
            lows.push(low);
        }
        (w, set, tops, lows)
    };
    let (mut w1, mut whole, tops, lows) = chains(None);
    let (mut w2, mut tiled, _, _) = chains(Some(4));
    let frames = |n: usize,
                  w1: &mut PhysicsWorld,
                  whole: &mut KjointSet,
                  w2: &mut PhysicsWorld,
                  tiled: &mut KjointSet| {
        for frame in 0..n {
            whole.step(w1, 1.0 / 60.0).unwrap();
            tiled.step(w2, 1.0 / 60.0).unwrap();
            assert!(
                state_bits(w1, whole) == state_bits(w2, tiled),
                "frame {frame}: the tiled set differs"
            );
        }
    };
    frames(10, &mut w1, &mut whole, &mut w2, &mut tiled);
    assert!(tiled.tile_joints.len() > 1);
    let saved = w2.bodies[lows[5]].clone();
    for w in [&mut w1, &mut w2] {
        w.bodies[tops[5]].set_enabled(false);
    }
    let v0 = w2.bodies[lows[5]].linvel().y as f64;
    frames(10, &mut w1, &mut whole, &mut w2, &mut tiled);
    let a = (w2.bodies[lows[5]].linvel().y as f64 - v0) / (10.0 / 60.0);
    assert!((a + 9.81).abs() < 1e-3, "the freed rod falls at {a} m/s²");
    assert_eq!(tiled.iter().filter(|(_, j)| !j.is_enabled()).count(), 2);
    // the low rod put back where and as it was, the top rod enabled again
    for w in [&mut w1, &mut w2] {
        let b = &mut w.bodies[lows[5]];
        b.set_position(*saved.position(), true);
        b.set_linvel(saved.linvel(), true);
        b.set_angvel(saved.angvel(), true);
        w.bodies[tops[5]].set_enabled(true);
    }
    frames(10, &mut w1, &mut whole, &mut w2, &mut tiled);
    assert!(tiled.iter().all(|(_, j)| j.is_enabled()));
    let gap = (saved.translation() - w2.bodies[lows[5]].translation()).length();
    assert!(gap < 0.05, "the low rod {gap} m from where it was put back");
}

/// Pendulums of automatic stiffness, stepped whole and in tiles of four: the rod of the
/// fifth takes a tenfold payload (`set_additional_mass_properties`) after 10 frames, and
/// both sets resolve its joint's stiffness again from the new mass (the tiled set checks
/// the masses before its tiles, a substep later than the whole set, after its gather
/// stage): `K` tenfold, the other joints' unchanged, and the pendulum's sag at rest the
/// rule's `a·h²/κ_eff` in both.
#[test]
fn a_payload_is_resolved_in_a_tiled_set_as_in_the_whole_set() {
    let pendulums = |tile: Option<usize>| {
        let (mut w, mut set, ground) = new_world();
        set.tile_joints_min = tile;
        let mut rods = Vec::new();
        for k in 0..12 {
            let x = 0.3 * k as Real;
            let p = rod(&mut w, Vector::new(x, -LINK / 2.0, 0.0));
            let j = hinge(0.0)
                .local_anchor1(Vector::new(x, 0.0, 0.0))
                .local_anchor2(Vector::new(0.0, LINK / 2.0, 0.0));
            rods.push((set.insert(j, ground, p, &w.bodies).unwrap(), p));
        }
        (w, set, rods)
    };
    let kn = |set: &KjointSet, j| set.get(j).unwrap().blocked.unwrap().translational;
    for tile in [None, Some(4)] {
        let (mut w, mut set, rods) = pendulums(tile);
        for _ in 0..10 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        let before: Vec<f64> = rods.iter().map(|(j, _)| kn(&set, *j)).collect();
        let i = 0.1 * LINK * LINK / 12.0;
        let payload = MassProperties::new(Vector::ZERO, 1.0, Vector::new(i, 10.0 * i, 10.0 * i));
        w.bodies[rods[4].1].set_additional_mass_properties(payload, true);
        for _ in 0..60 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        assert_eq!(set.tiles.is_empty(), tile.is_none());
        for (k, (j, _)) in rods.iter().enumerate() {
            let ratio = kn(&set, *j) / before[k];
            let expected = if k == 4 { 10.0 } else { 1.0 };
            assert!(
                (ratio - expected).abs() < 1e-3 * expected,
                "tiles {tile:?}, pendulum {k}: K grew {ratio}-fold"
            );
        }
        let h = 1.0 / 240.0;
        let kappa = kn(&set, rods[4].0) * h * h / 1.0;
        let s = set.get(rods[4].0).unwrap().state().unwrap();
        let gap = (s.q[0] * s.q[0] + s.q[1] * s.q[1] + s.q[2] * s.q[2]).sqrt();
        let sag = 9.81 * h * h / kappa;
        assert!(
            gap < 1.1 * sag,
            "tiles {tile:?}: the heavy pendulum's gap {gap} m, a·h²/κ {sag} m"
        );
    }
}
