#[path = "../benches/scenes.rs"]
mod scenes;
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10000);
    let frames: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let scene = scenes::chain(n);
    let mut s = scene.kjoint();
    let sub: usize = std::env::args()
        .nth(3)
        .and_then(|s| s.parse().ok())
        .unwrap_or(4);
    s.joints.set_settings(rapier_kjoint::SubstepSettings {
        substeps: sub,
        ..Default::default()
    });
    let e0 = rapier_kjoint::dynamics::energy::mechanical_energy(&s.world.bodies, s.world.gravity);
    let t = std::time::Instant::now();
    for f in 0..frames {
        s.frame();
        if f % 15 == 14 {
            let gap = scene.anchor_gap(&s.world, &s.bodies);
            let (mut worst, mut at) = (0.0f32, 0usize);
            for (k, j) in scene.joints.iter().enumerate() {
                let p1 = s.world.bodies[s.bodies[j.body1]].position() * j.anchor1;
                let p2 = s.world.bodies[s.bodies[j.body2]].position() * j.anchor2;
                let g = (p1 - p2).length();
                if g > worst {
                    worst = g;
                    at = k;
                }
            }
            let w = s.world.bodies[s.bodies[at + 1]].angvel().length();
            let p = s.world.bodies[s.bodies[at + 1]].translation();
            let last = s.world.bodies[*s.bodies.last().unwrap()].translation();
            let lv = s.world.bodies[*s.bodies.last().unwrap()].linvel().length();
            eprintln!("   bottom ({:.2},{:.2}) |v|={lv:.2}", last.x, last.y);
            eprintln!("   worst joint {at} at ({:.1},{:.1}) |w|={w:.1}", p.x, p.y);
            let e = rapier_kjoint::dynamics::energy::mechanical_energy(
                &s.world.bodies,
                s.world.gravity,
            );
            let stored: f64 = s
                .joints
                .iter()
                .map(|(_, j)| j.state().map_or(0.0, |st| st.energy.elastic))
                .sum();
            let num: f64 = s
                .joints
                .iter()
                .map(|(_, j)| j.state().map_or(0.0, |st| st.energy.numerical))
                .sum();
            eprintln!(
                "t={:.2} gap={:.3e} E-E0={:.4e} stored={:.3e} num={:.3e}",
                (f + 1) as f64 / 60.0,
                gap,
                e - e0,
                stored,
                num
            );
        }
    }
    eprintln!(
        "{:.3} ms/frame",
        t.elapsed().as_secs_f64() * 1e3 / frames as f64
    );
}
