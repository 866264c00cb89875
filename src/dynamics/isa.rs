//! The substep compiled twice, for the x86-64 baseline (SSE2, two f64 lanes) and for
//! processors with AVX2 (four lanes), the one to run chosen at run time.
//!
//! A user's build targets the baseline unless they ask for more (`-C target-cpu`), and the
//! substep's arithmetic is mostly 3×3 and 6×6 blocks whose rows the compiler vectorises: on
//! the contact scene of the benchmarks (README, *Solver benchmarks*), the AVX2 compilation
//! runs the joint set's work in 13 % fewer instructions (2–3 % of the frame's time).
//! [`KjointSet::substep`] calls each of its hot stages (gather, prepare, solve, apply, store)
//! through a function of its own compiled with AVX2 enabled when the processor has it, and
//! through its baseline twin otherwise (`compiled_twice!` in `substep.rs`); the stages and
//! the functions of their hot path are `#[inline(always)]` in release builds, so that each
//! is compiled into both twins.
//!
//! **The results are the same bits.** Only AVX2 is enabled, not FMA: every product and sum
//! is the same IEEE operation on the same operands in the same order, four lanes at a time
//! instead of two (Rust neither fuses nor reassociates floating-point operations unless
//! told to). The test `avx2_and_baseline_substeps_give_the_same_bits` steps a world that
//! takes every path of the substep both ways and compares the states bit for bit.
//!
//! **One function a stage, not one for the whole substep.** Until 2026-11-29 the whole
//! substep was inlined into one function compiled twice; LLVM's optimisation passes grow
//! faster than a function, and that one was among the largest it is given: the release
//! build of the library took 474 s on the 2-core machine of CI, most of it in those passes.
//! Compiled stage by stage, a release build of the library and two examples took 112 s
//! instead of 407 s; the bench scenes' states are the same bits after 90 frames, and the
//! contact scene (`chain_frames 50 60 kjoint2 contacts 2`, callgrind) ran 0.13 % fewer
//! instructions (1406.6 against 1408.4 million; the substep's own 571.0 against 572.2).
//!
//! **Builds with debug assertions do not force the inlining** (cargo's `dev` and `test`
//! profiles: every `#[inline(always)]` of the crate is written
//! `#[cfg_attr(not(debug_assertions), inline(always))]`). In the `test` profile (opt-level
//! 1), with the substep in one function, the forced inlining took 453 s of the library's
//! compile (14 s without); the crate's targets of `cargo test --all-targets` took 1598 s of
//! compile time instead of 319 s (2026-11-29). Without it each AVX2 stage mostly calls the
//! baseline compilation of its functions, so in those builds the same-bits test would
//! compare a function with itself: it runs in release only (`cargo test --release --lib
//! avx2`).
//!
//! [`KjointSet::substep`]: super::KjointSet

/// Whether this processor runs the AVX2 compilation of the substep: an x86-64 processor
/// with AVX2 (detected once by the standard library, then a cached flag).
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
#[inline]
pub(crate) fn avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

#[cfg(test)]
mod tests {
    use crate::rapier::prelude::*;
    use crate::{Curve, Dof, DofLaw, JointType, KjointBuilder, KjointProperty, KjointSet};

    /// A world that takes every path of the substep: groups of three hinged capsules falling
    /// onto a ground box (contacts, tree islands, the geometric stiffness of one and two
    /// forces), a four-bar (a loop island), a hub carrying four spherical joints, and a free
    /// joint whose laws use every mechanism (curve spring and viscosity, friction, stops
    /// coupled on the rotations), swinging under gravity.
    fn world(baseline_only: bool) -> (PhysicsWorld, KjointSet, Vec<RigidBodyHandle>) {
        let mut w = PhysicsWorld {
            gravity: Vector::new(0.0, -9.81, 0.0),
            ..Default::default()
        };
        let mut set = KjointSet::new();
        set.baseline_only = baseline_only;
        let (ground, _) = w.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
            ColliderBuilder::cuboid(5.0, 0.5, 5.0),
        );
        let axis_z = Rotation::from_rotation_arc(Vector::X, Vector::Z);
        let hinge = || {
            KjointBuilder::new(KjointProperty::new(JointType::Revolute).with_kn(1e10))
                .world_frame1(axis_z)
        };
        let mut bodies = Vec::new();
        for g in 0..4 {
            let mut prev = None;
            for k in 0..3 {
                let (b, _) = w.insert(
                    RigidBodyBuilder::dynamic()
                        .translation(Vector::new(
                            (g as Real - 2.0) * 0.5 + 0.25 * k as Real,
                            0.3 + 0.05 * g as Real,
                            0.0,
                        ))
                        .rotation(Vector::new(0.1 * g as Real, 0.0, 1.5)),
                    ColliderBuilder::capsule_y(0.1, 0.04),
                );
                if let Some(p) = prev {
                    let j = hinge()
                        .local_anchor1(Vector::new(0.0, -0.125, 0.0))
                        .local_anchor2(Vector::new(0.0, 0.125, 0.0));
                    set.insert(j, p, b, &w.bodies).unwrap();
                }
                prev = Some(b);
                bodies.push(b);
            }
        }
        // away from the ground: a four-bar pinned at one corner, a hub, the free joint
        let rod = |w: &mut PhysicsWorld, at: Vector| {
            w.insert_body(
                RigidBodyBuilder::dynamic()
                    .translation(at)
                    .additional_mass_properties(MassProperties::new(
                        Vector::ZERO,
                        0.1,
                        Vector::new(1e-4, 2e-4, 3e-4),
                    )),
            )
        };
        let o = Vector::new(0.0, 3.0, 0.0);
        let corners = [
            o,
            o + Vector::new(0.1, 0.0, 0.0),
            o + Vector::new(0.1, -0.1, 0.0),
            o + Vector::new(0.0, -0.1, 0.0),
        ];
        let bars: Vec<_> = (0..4)
            .map(|k| {
                let (a, b) = (corners[k], corners[(k + 1) % 4]);
                (rod(&mut w, (a + b) * 0.5), a, b)
            })
            .collect();
        for k in 0..4 {
            let (b1, _, end1) = bars[k];
            let (b2, start2, _) = bars[(k + 1) % 4];
            let pa = end1 - w.bodies[b1].translation();
            let pb = start2 - w.bodies[b2].translation();
            let j = hinge().local_anchor1(pa).local_anchor2(pb);
            set.insert(j, b1, b2, &w.bodies).unwrap();
            bodies.push(b1);
        }
        let pin = corners[0] - w.bodies[bars[0].0].translation();
        let j = hinge().local_anchor1(corners[0]).local_anchor2(pin);
        set.insert(j, ground, bars[0].0, &w.bodies).unwrap();
        let hub = rod(&mut w, Vector::new(1.0, 3.0, 0.0));
        bodies.push(hub);
        for k in 0..4 {
            let dir = Rotation::from_rotation_z(k as Real * 1.5) * Vector::X;
            let leaf = rod(&mut w, Vector::new(1.0, 3.0, 0.0) + dir * 0.2);
            let j = KjointBuilder::new(KjointProperty::new(JointType::Spherical).with_kn(1e9))
                .local_anchor1(dir * 0.1)
                .local_anchor2(-dir * 0.1);
            set.insert(j, hub, leaf, &w.bodies).unwrap();
            bodies.push(leaf);
        }
        let curve = Curve::new(vec![(-1.0, -2.0), (0.0, 0.0), (1.0, 1.0)]).unwrap();
        let mut every = KjointProperty::new(JointType::Free).with_kn(1e6);
        for d in Dof::ALL {
            let mut l = DofLaw::spring(10.0)
                .with_stops(-0.05, 0.05)
                .with_friction(1e3, 0.05);
            l.stiffness_curve = Some(curve.clone());
            l.viscosity = 0.01;
            l.viscosity_curve = Some(curve.clone());
            if d.is_rotation() {
                l = l.with_coupled_stops();
            }
            every = every.with_dof(d, l);
        }
        let swing = rod(&mut w, Vector::new(2.0, 2.9, 0.0));
        let j = KjointBuilder::new(every)
            .local_anchor1(Vector::new(2.0, 3.0, 0.0))
            .local_anchor2(Vector::new(0.0, 0.1, 0.0));
        set.insert(j, ground, swing, &w.bodies).unwrap();
        bodies.push(swing);
        set.prepare(&mut w);
        (w, set, bodies)
    }

    /// The bits of every body's pose and velocity, and of every joint's readout and energies.
    fn bits(w: &PhysicsWorld, set: &KjointSet, bodies: &[RigidBodyHandle]) -> Vec<u64> {
        let mut out = Vec::new();
        for b in bodies {
            let rb = &w.bodies[*b];
            let v = [rb.translation(), rb.linvel(), rb.angvel()];
            out.extend(
                v.iter()
                    .flat_map(|v| v.to_array())
                    .map(|x| x.to_bits() as u64),
            );
            out.extend(rb.rotation().to_array().map(|x| x.to_bits() as u64));
        }
        for (_, j) in set.iter() {
            let s = j.state().expect("stepped");
            let e = j.energy();
            out.extend(
                [
                    e.elastic,
                    e.kinetic,
                    e.damping,
                    e.friction,
                    e.stop,
                    e.numerical,
                ]
                .map(f64::to_bits),
            );
            for v in [s.q.0, s.rate.0, s.force.0, s.applied.0] {
                out.extend(v.map(f64::to_bits));
            }
        }
        out
    }

    /// The AVX2 compilation of the substep gives the same bits as the baseline one, state
    /// by state, over 60 frames of a world that takes every path ([`world`]). On a processor
    /// without AVX2 both runs take the baseline (the test then compares it with itself).
    #[test]
    #[cfg_attr(
        debug_assertions,
        ignore = "without the forced inlining of release builds both runs take one compilation"
    )]
    fn avx2_and_baseline_substeps_give_the_same_bits() {
        if !super::avx2() {
            eprintln!("no AVX2 on this processor: both runs take the baseline compilation");
        }
        let (mut wa, mut a, bodies) = world(false);
        let (mut wb, mut b, _) = world(true);
        for frame in 0..60 {
            a.step(&mut wa, 1.0 / 60.0).unwrap();
            b.step(&mut wb, 1.0 / 60.0).unwrap();
            let (x, y) = (bits(&wa, &a, &bodies), bits(&wb, &b, &bodies));
            let first = x.iter().zip(&y).position(|(p, q)| p != q);
            assert_eq!(first, None, "frame {frame}: entry {first:?} differs");
        }
        // the world moved: the capsules fell onto the ground, the mechanisms swung
        let fell = wa.bodies[bodies[0]].translation().y;
        assert!(fell < 0.2, "{fell}");
        let swing = wa.bodies[*bodies.last().unwrap()].linvel().length();
        assert!(swing > 0.0, "{swing}");
    }
}
