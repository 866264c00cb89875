//! A three-joint arm read from `assets/urdf/arm.urdf`, run under gravity with its URDF
//! friction, damping and limits as KJOINT2 laws and stops.
//!
//! ```sh
//! cargo run --release --example urdf_arm                    # prints the joint angles
//! cargo run --release --example urdf_arm --features rerun   # also records arm.rrd
//! rerun arm.rrd                                             # opens the recording
//! ```
//!
//! Options: `--seconds S` (default 4), `--rrd PATH` (default `arm.rrd`), `--csv PATH` (writes
//! the joint history `t, shoulder [rad], elbow [rad], wrist [m]` at every frame).

use rapier_kjoint::io::urdf::{UrdfOptions, UrdfRobot};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{Dof, KjointSet, SubstepSettings};
use std::io::Write;

fn main() {
    if let Err(e) = run() {
        eprintln!("urdf_arm: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let mut seconds = 4.0f64;
    let mut csv: Option<String> = None;
    let mut rrd = String::from("arm.rrd");
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--seconds" => seconds = value()?.parse()?,
            "--csv" => csv = Some(value()?),
            "--rrd" => rrd = value()?,
            _ => return Err(format!("unknown argument `{a}`").into()),
        }
    }
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(format!("--seconds must be > 0, got {seconds}").into());
    }

    let frame_dt = 1.0 / 60.0;
    let substeps = 4;
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81), // URDF robots are z-up
        ..Default::default()
    };
    let mut joints = KjointSet::with_settings(SubstepSettings {
        substeps,
        ..Default::default()
    });
    let options = UrdfOptions {
        substep: frame_dt / substeps as f64, // for the friction stiffness rule
        ..Default::default()
    };
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/urdf/arm.urdf");
    // describe (no world touched), then insert
    let robot = UrdfRobot::from_file(path, &options)?.insert(&mut world, &mut joints)?;
    for n in &robot.notices {
        println!("notice: {n}");
    }
    let names = [
        ("shoulder", Dof::Rx, "rad"),
        ("elbow", Dof::Rx, "rad"),
        ("wrist", Dof::Dx, "m"),
    ];
    let handles: Vec<_> = names
        .iter()
        .map(|(n, _, _)| {
            robot
                .joints
                .get(*n)
                .copied()
                .ok_or(format!("no joint `{n}`"))
        })
        .collect::<Result<_, _>>()?;

    #[cfg(feature = "rerun")]
    let mut logger = {
        use rapier_kjoint::output::rerun_log::RerunLogger;
        println!("recording to {rrd}");
        RerunLogger::save(&rrd)?.with_urdf_robot(&robot)
    };
    let mut csv = match csv {
        Some(p) => {
            let mut f = std::io::BufWriter::new(std::fs::File::create(&p)?);
            writeln!(f, "t,shoulder,elbow,wrist")?;
            Some(f)
        }
        None => None,
    };

    let frames = (seconds / frame_dt).round() as usize;
    for frame in 1..=frames {
        joints.step(&mut world, frame_dt)?;
        let t = joints.time();
        // the joints' readouts are measured at the start of the step's last substep
        let t_q = (handles.first())
            .and_then(|h| joints.get(*h)?.state())
            .map_or(t, |s| s.time);
        let q: Vec<f64> = handles
            .iter()
            .zip(&names)
            .map(|(h, (_, dof, _))| {
                joints
                    .get(*h)
                    .and_then(|j| j.dof_value(*dof))
                    .unwrap_or(f64::NAN)
            })
            .collect();
        #[cfg(feature = "rerun")]
        {
            use rapier_kjoint::output::Observer;
            let events = joints.drain_events();
            logger.record(t, &world, &joints, &events)?;
        }
        if let Some(f) = csv.as_mut() {
            writeln!(f, "{t_q:.6},{:.6},{:.6},{:.6}", q[0], q[1], q[2])?;
        }
        if frame % 15 == 0 {
            let parts: Vec<String> = names
                .iter()
                .zip(&q)
                .map(|((n, _, u), v)| format!("{n} {v:+.4} {u}"))
                .collect();
            println!("t = {t_q:5.3} s   {}", parts.join("   "));
        }
    }
    #[cfg(feature = "rerun")]
    {
        use rapier_kjoint::output::Observer;
        logger.finish()?;
        println!("wrote {rrd}: open it with `rerun {rrd}`");
    }
    #[cfg(not(feature = "rerun"))]
    if rrd != "arm.rrd" {
        println!("note: --rrd {rrd} ignored: built without the `rerun` feature");
    }
    if let Some(mut f) = csv {
        f.flush()?;
    }
    Ok(())
}
