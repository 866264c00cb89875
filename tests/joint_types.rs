//! For each of the nine types: under a constant force and torque, the blocked DOFs stay
//! within a few times their static deflection `F/Kn`, `T/KR`, and the free DOFs move freely
//! (`½·(F/m)·t²`).

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{JointType, KjointProperty};

#[test]
fn nine_types_block_and_free_the_right_dofs() {
    let (kn, scf) = (1e5, 10.0); // KR = Kn·ScF = 1e6 N·m/rad (zero-length joint)
    let force = Vector::new(3.0, 4.0, 5.0);
    let torque = Vector::new(0.3, 0.4, 0.5);
    let (m, inertia): (Real, Real) = (1.0, 0.1);
    let t_end = 0.25;
    for n in 1..=9 {
        let jt = JointType::from_number(n).unwrap();
        let (mut w, ground) = common::world(Vector::ZERO);
        let b = common::point_body(&mut w, m, Vector::splat(inertia), Vector::ZERO);
        let mut set = common::joints(4);
        let prop = KjointProperty::new(jt).with_kn(kn).with_scale_factor(scf);
        let j = common::add(&mut set, &w, prop, ground, b, |bl| {
            bl.world_frame1(Rotation::IDENTITY)
        });
        w.bodies[b].add_force(force, true);
        w.bodies[b].add_torque(torque, true);
        for _ in 0..(t_end * 60.0) as usize {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        let s = set.get(j).unwrap().state().unwrap();
        let free = jt.free_dofs();
        let load = [force.x, force.y, force.z, torque.x, torque.y, torque.z];
        for i in 0..6 {
            let q = s.q[i].abs();
            if free[i] {
                // ½·a·t² with a = F/m or T/I, at the last evaluation time
                let t = s.time;
                let expect = 0.5 * (load[i] / if i < 3 { m } else { inertia }) as f64 * t * t;
                assert!(
                    (q - expect).abs() < 0.1 * expect,
                    "type {n} ({}) free dof {i}: |q| = {q}, expected ≈ {expect}",
                    jt.name()
                );
            } else {
                let k = if i < 3 { kn } else { kn * scf };
                let mut tol = 3.0 * load[i] as f64 / k + 1e-6;
                if jt == JointType::Universal && i == 3 {
                    // The Cardan joint's blocked θx: rapier turns a body at a constant ω over
                    // a substep, which leaves a Cardan motion at second order
                    // (Δθx = −½·θ̇y·θ̇z·h²); the penalty corrects it every substep, so θx
                    // carries a bias of that order (≈ 1.4·θ̇y·θ̇z·h² measured).
                    let h = 1.0 / 240.0;
                    tol += 2.0 * (s.rate[4] * s.rate[5]).abs() * h * h;
                }
                assert!(
                    q < tol,
                    "type {n} ({}) blocked dof {i}: |q| = {q} > {tol}",
                    jt.name()
                );
            }
        }
    }
}
