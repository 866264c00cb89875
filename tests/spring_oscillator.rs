//! An undamped 1 kg body on a free translational DOF, K = 1000 N/m, amplitude 0.1 m, 60 Hz
//! frames with 4 substeps: the amplitude must stay within 1 % after 10 s and the period
//! within 0.5 % of 2π√(m/K). (rapier's own spring joint loses most of its amplitude here.)
//!
//! The substeps are driven by hand (`apply_substep` + one rapier step of `h = 1/240 s`,
//! exactly what `KjointSet::step` does for a 60 Hz frame with 4 substeps) so that the
//! position can be sampled at every substep and the peaks located precisely.

// Casts to rapier's `Real` (f32) are the identity with the `f64` feature.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

mod common;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, DofLaw, JointType, KjointProperty};

#[test]
fn undamped_spring_keeps_amplitude_and_period() {
    let (mut w, ground) = common::world(Vector::ZERO);
    let body = common::ball(&mut w, 1.0, 0.1, Vector::ZERO);
    let mut set = common::joints(4);
    let prop =
        KjointProperty::new(JointType::Translational).with_dof(Dof::Dx, DofLaw::spring(1000.0));
    // The joint is created at rest (both anchors at the origin), then the body is pulled
    // 0.1 m along the free axis and released.
    common::add(&mut set, &w, prop, ground, body, |b| {
        b.world_frame1(Rotation::IDENTITY)
    });
    w.bodies[body].set_translation(Vector::new(0.1, 0.0, 0.0), true);
    set.prepare(&mut w);

    let h = 1.0 / 240.0;
    w.integration_parameters.dt = h as Real;
    w.integration_parameters.num_solver_iterations = 1;
    let mut xs = vec![0.1f64];
    for _ in 0..(10 * 240) {
        set.apply_substep(&mut w.bodies, w.gravity, h).unwrap();
        w.step();
        set.advance_time(h).unwrap();
        xs.push(w.bodies[body].translation().x as f64);
    }
    // peaks of x (parabolic interpolation through the three samples around each maximum)
    let mut peaks = Vec::new();
    for i in 1..xs.len() - 1 {
        if xs[i] > xs[i - 1] && xs[i] >= xs[i + 1] && xs[i] > 0.0 {
            let (a, b, c) = (xs[i - 1], xs[i], xs[i + 1]);
            let d = 0.5 * (a - c) / (a - 2.0 * b + c);
            peaks.push(((i as f64 + d) * h, b - 0.25 * (a - c) * d));
        }
    }
    let n = peaks.len() - 1;
    let period = (peaks[n].0 - peaks[0].0) / n as f64;
    let exact = 2.0 * std::f64::consts::PI * (1.0f64 / 1000.0).sqrt();
    let amp = peaks[n].1;
    println!(
        "{} peaks, last amplitude {amp}, period {period}, exact {exact}",
        n + 1
    );
    assert!(peaks[n].0 > 9.5, "the last peak is at {} s", peaks[n].0);
    assert!((amp - 0.1).abs() < 1e-3, "amplitude {amp} after 10 s");
    assert!(
        (period - exact).abs() / exact < 5e-3,
        "period {period} vs {exact}"
    );
}
