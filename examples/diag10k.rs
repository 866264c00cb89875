//! The chain of the solver bench swinging from 30°: after every frame, the largest anchor
//! gap of any joint so far, where and when it happened; printed once a second. The
//! diagnosis harness of the long-chain stability work (the README's "How the penalty update
//! stays stable").
//!
//! `cargo run --release --example diag10k -- [links=1000] [frames=600]`

#[path = "../benches/scenes.rs"]
mod scenes;
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000);
    let frames: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let scene = scenes::chain(n);
    let mut s = scene.kjoint();
    let mut worst: (rapier_kjoint::rapier::math::Real, usize, usize) = (0.0, 0, 0);
    for f in 0..frames {
        s.frame();
        for (k, j) in scene.joints.iter().enumerate() {
            let p1 = s.world.bodies[s.bodies[j.body1]].position() * j.anchor1;
            let p2 = s.world.bodies[s.bodies[j.body2]].position() * j.anchor2;
            let g = (p1 - p2).length();
            if g > worst.0 {
                worst = (g, f, k);
            }
        }
        if f % 60 == 59 {
            let b = &s.world.bodies[s.bodies[worst.2 + 1]];
            eprintln!(
                "t={:.1} worst so far {:.3e} at frame {} joint {} (|w| now {:.1}, |v| {:.1})",
                (f + 1) as f64 / 60.0,
                worst.0,
                worst.1,
                worst.2,
                b.angvel().length(),
                b.linvel().length()
            );
        }
    }
}
