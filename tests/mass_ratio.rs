//! A 100 kg ball swinging on a chain of ten 0.1 kg links (a mass ratio of 1000 between
//! neighbours), released horizontal, at 60 Hz × 4 substeps for 5 s: the KJOINT2 spherical
//! joints (automatic stiffness) keep every anchor gap within a millimetre, the energy never
//! grows, and what the bodies lose is what the joints book as dissipated; rapier's own
//! spherical joints on the same bodies, stepped with the same substeps, stretch by
//! centimetres (an iterative solver converges slowly across such a ratio).

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{JointType, KjointProperty};

/// What a run of the chain shows: the largest anchor gap \[m\], the largest rise of the
/// total energy over its start \[J\], the energy lost by the end \[J\], what the joints
/// booked as dissipated \[J\], and `M·g·L` of the ball \[J\].
struct Run {
    max_gap: f64,
    max_rise: f64,
    lost: f64,
    dissipated: f64,
    scale: f64,
}

fn swing(kjoint: bool) -> Run {
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    let (n, link, m, heavy, r): (usize, Real, Real, Real, Real) = (10, 0.1, 0.1, 100.0, 0.2);
    let rod = Vector::new(
        m * link * link / 1200.0,
        m * link * link / 12.0,
        m * link * link / 12.0,
    );
    let substeps = 4;
    let mut set = common::joints(substeps);
    let prop = KjointProperty::new(JointType::Spherical);
    let mut prev = ground;
    let mut pairs = Vec::new();
    for i in 0..=n {
        let (b, a2) = if i < n {
            let x = link * (i as Real + 0.5);
            let b = common::point_body(&mut w, m, rod, Vector::new(x, 0.0, 0.0));
            (b, Vector::new(-link / 2.0, 0.0, 0.0))
        } else {
            let x = link * n as Real + r;
            let b = common::point_body(
                &mut w,
                heavy,
                Vector::splat(0.4 * heavy * r * r),
                Vector::new(x, 0.0, 0.0),
            );
            (b, Vector::new(-r, 0.0, 0.0))
        };
        let a1 = if i == 0 {
            Vector::ZERO
        } else {
            Vector::new(link / 2.0, 0.0, 0.0)
        };
        if kjoint {
            common::add(&mut set, &w, prop.clone(), prev, b, |bl| {
                bl.local_anchor1(a1).local_anchor2(a2)
            });
        } else {
            let j = SphericalJointBuilder::new()
                .local_anchor1(a1)
                .local_anchor2(a2);
            w.impulse_joints.insert(prev, b, j, true);
        }
        pairs.push((prev, b, a1, a2));
        prev = b;
    }
    let e0 = common::total_energy(&w, &set);
    let (mut max_gap, mut max_rise) = (0.0f64, f64::NEG_INFINITY);
    let dt: Real = 1.0 / 60.0;
    for _ in 0..300 {
        if kjoint {
            set.step(&mut w, dt as f64).unwrap();
        } else {
            w.integration_parameters.dt = dt / substeps as Real;
            for _ in 0..substeps {
                w.step();
            }
        }
        for &(a, b, a1, a2) in &pairs {
            let gap = w.bodies[a].position() * a1 - w.bodies[b].position() * a2;
            max_gap = max_gap.max(gap.length() as f64);
        }
        max_rise = max_rise.max(common::total_energy(&w, &set) - e0);
    }
    Run {
        max_gap,
        max_rise,
        lost: e0 - common::total_energy(&w, &set),
        dissipated: common::dissipated(&set),
        scale: heavy as f64 * 9.81 * (link as f64 * n as f64 + r as f64),
    }
}

#[test]
fn a_heavy_ball_on_a_light_chain_keeps_its_joints_closed_and_books_what_it_loses() {
    let k = swing(true);
    let rapier = swing(false);
    println!(
        "KJOINT2: max gap {:.3e} m, max rise {:.3e} J, lost {:.1} J, booked {:.1} J (M·g·L {:.0} J); \
         rapier: max gap {:.3e} m",
        k.max_gap, k.max_rise, k.lost, k.dissipated, k.scale, rapier.max_gap
    );
    // measured 0.55 mm (rapier's joints 101 mm)
    assert!(k.max_gap < 1e-3, "gap {} m", k.max_gap);
    assert!(
        k.max_gap * 50.0 < rapier.max_gap,
        "{} against rapier's {}",
        k.max_gap,
        rapier.max_gap
    );
    // never above the start (measured −0.34 J at most: it only loses)
    assert!(
        k.max_rise <= 1e-3 * k.scale,
        "energy rose by {} J",
        k.max_rise
    );
    // the loss (151 J, 13 % of M·g·L, the numerical damping of the DOFs the substep
    // cannot resolve; 93 J at 16 substeps) is booked: 155 J
    assert!(k.lost > 0.0);
    assert!(
        (k.lost - k.dissipated).abs() <= 0.01 * k.scale,
        "lost {} J, booked {} J",
        k.lost,
        k.dissipated
    );
}
