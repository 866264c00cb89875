//! User trial (game developer): misusing the API on a one-corner car (chassis, hub, wheel).
//! Every case runs under catch_unwind: a panic is a finding.
//!
//! `cargo run --release --example trial_car_misuse`

use rapier_kjoint::prelude::*;
use rapier_kjoint::rapier::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};

struct Corner {
    world: PhysicsWorld,
    joints: KjointSet,
    ground: RigidBodyHandle,
    chassis: RigidBodyHandle,
    hub: RigidBodyHandle,
    wheel: RigidBodyHandle,
    susp: KjointHandle,
    axle: KjointHandle,
}

fn susp_prop() -> KjointProperty {
    KjointProperty::new(JointType::Translational).with_dof(
        Dof::Dx,
        DofLaw::spring(40_000.0)
            .with_viscosity(3000.0)
            .with_stops(-0.08, 0.08),
    )
}

fn corner() -> Corner {
    let mut world = PhysicsWorld::default();
    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(50.0, 0.5, 50.0),
    );
    let (chassis, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.65, 0.0)),
        ColliderBuilder::cuboid(0.3, 0.1, 0.3).mass(200.0),
    );
    let hub = world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 0.35, 0.0))
            .additional_mass_properties(MassProperties::new(
                Vector::ZERO,
                5.0,
                Vector::splat(0.02),
            )),
    );
    let (wheel, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.35, 0.0)),
        ColliderBuilder::ball(0.35).mass(20.0),
    );
    let mut joints = KjointSet::new();
    let susp = joints
        .insert(
            KjointBuilder::new(susp_prop())
                .name("susp")
                .world_axis(Vector::Y)
                .local_anchor1(Vector::new(0.0, -0.3, 0.0)),
            chassis,
            hub,
            &world.bodies,
        )
        .unwrap();
    let axle = joints
        .insert(
            KjointBuilder::new(KjointProperty::new(JointType::Revolute))
                .name("axle")
                .world_axis(Vector::Z)
                .contacts_enabled(false),
            hub,
            wheel,
            &world.bodies,
        )
        .unwrap();
    Corner {
        world,
        joints,
        ground,
        chassis,
        hub,
        wheel,
        susp,
        axle,
    }
}

fn case(name: &str, f: impl FnOnce() -> String) {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(s) => println!("[{name}] {s}"),
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            println!("[{name}] *** PANIC: {msg}");
        }
    }
}

fn res<T: std::fmt::Debug>(r: Result<T, SimError>) -> String {
    match r {
        Ok(v) => format!("Ok({v:?})"),
        Err(e) => format!("Err: {e}"),
    }
}

fn insert_susp(c: &mut Corner, law: DofLaw) -> Result<KjointHandle, SimError> {
    c.joints.insert(
        KjointBuilder::new(KjointProperty::new(JointType::Translational).with_dof(Dof::Dx, law))
            .world_axis(Vector::Y),
        c.chassis,
        c.hub,
        &c.world.bodies,
    )
}

fn steps(c: &mut Corner, n: usize) -> String {
    for k in 0..n {
        if let Err(e) = c.joints.step(&mut c.world, 1.0 / 60.0) {
            return format!("step {k}: Err: {e}");
        }
    }
    let p = c.world.bodies.get(c.chassis).map(|b| b.translation());
    format!("{n} steps Ok; chassis at {p:?}")
}

fn events(c: &mut Corner) -> String {
    let ev = c.joints.drain_events();
    let v: Vec<String> = ev.iter().take(4).map(|e| e.to_string()).collect();
    format!("{} events: {}", ev.len(), v.join(" | "))
}

fn main() {
    // ---- invalid laws
    case("spring NaN", || {
        res(insert_susp(&mut corner(), DofLaw::spring(f64::NAN)))
    });
    case("spring -1", || {
        res(insert_susp(&mut corner(), DofLaw::spring(-1.0)))
    });
    case("spring inf", || {
        res(insert_susp(&mut corner(), DofLaw::spring(f64::INFINITY)))
    });
    case("viscosity NaN", || {
        res(insert_susp(
            &mut corner(),
            DofLaw::spring(1.0).with_viscosity(f64::NAN),
        ))
    });
    case("stops swapped (0.1, -0.1)", || {
        res(insert_susp(
            &mut corner(),
            DofLaw::spring(1.0).with_stops(0.1, -0.1),
        ))
    });
    case("stops NaN", || {
        res(insert_susp(
            &mut corner(),
            DofLaw::spring(1.0).with_stops(f64::NAN, 0.1),
        ))
    });
    case("limits not bracketing 0 (0.05, 0.1)", || {
        res(insert_susp(
            &mut corner(),
            DofLaw::spring(1.0).with_limits(0.05, 0.1),
        ))
    });
    case("law on blocked DOF (translational Dy)", || {
        let mut c = corner();
        res(c.joints.insert(
            KjointBuilder::new(
                KjointProperty::new(JointType::Translational)
                    .with_dof(Dof::Dy, DofLaw::spring(1.0)),
            ),
            c.chassis,
            c.hub,
            &c.world.bodies,
        ))
    });
    case("kn NaN", || {
        let mut c = corner();
        res(c.joints.insert(
            KjointBuilder::new(susp_prop().with_kn(f64::NAN)),
            c.chassis,
            c.hub,
            &c.world.bodies,
        ))
    });
    case("kn 1e30 then step", || {
        let mut c = corner();
        let r = c.joints.insert(
            KjointBuilder::new(susp_prop().with_kn(1e30)),
            c.chassis,
            c.hub,
            &c.world.bodies,
        );
        format!("{} ; {} ; {}", res(r), steps(&mut c, 60), events(&mut c))
    });
    case("spring 1e12 (very stiff suspension) then step", || {
        let mut c = corner();
        let r = insert_susp(&mut c, DofLaw::spring(1e12));
        format!("{} ; {} ; {}", res(r), steps(&mut c, 60), events(&mut c))
    });
    // ---- frames
    case("world_axis zero", || {
        let mut c = corner();
        res(c.joints.insert(
            KjointBuilder::new(susp_prop()).world_axis(Vector::ZERO),
            c.chassis,
            c.hub,
            &c.world.bodies,
        ))
    });
    case("world_axis NaN", || {
        let mut c = corner();
        res(c.joints.insert(
            KjointBuilder::new(susp_prop()).world_axis(Vector::new(f32::NAN, 1.0, 0.0)),
            c.chassis,
            c.hub,
            &c.world.bodies,
        ))
    });
    case("local_anchor1 NaN", || {
        let mut c = corner();
        res(c.joints.insert(
            KjointBuilder::new(susp_prop()).local_anchor1(Vector::new(f32::NAN, 0.0, 0.0)),
            c.chassis,
            c.hub,
            &c.world.bodies,
        ))
    });
    case("world_frame1 non-normalized quaternion (0,0,0,2)", || {
        let mut c = corner();
        let r = c.joints.insert(
            KjointBuilder::new(susp_prop()).world_frame1(Rotation::from_xyzw(0.0, 0.0, 0.0, 2.0)),
            c.chassis,
            c.hub,
            &c.world.bodies,
        );
        format!("{} ; {}", res(r), steps(&mut c, 10))
    });
    case("world_frame1 zero quaternion", || {
        let mut c = corner();
        let r = c.joints.insert(
            KjointBuilder::new(susp_prop()).world_frame1(Rotation::from_xyzw(0.0, 0.0, 0.0, 0.0)),
            c.chassis,
            c.hub,
            &c.world.bodies,
        );
        format!("{} ; {}", res(r), steps(&mut c, 10))
    });
    // ---- handles
    case("insert with invalid body handle", || {
        let mut c = corner();
        res(c.joints.insert(
            KjointBuilder::new(susp_prop()),
            c.chassis,
            RigidBodyHandle::invalid(),
            &c.world.bodies,
        ))
    });
    case("insert same body twice", || {
        let mut c = corner();
        res(c.joints.insert(
            KjointBuilder::new(susp_prop()),
            c.chassis,
            c.chassis,
            &c.world.bodies,
        ))
    });
    case("insert ground-ground", || {
        let mut c = corner();
        res(c.joints.insert(
            KjointBuilder::new(susp_prop()),
            c.ground,
            c.ground,
            &c.world.bodies,
        ))
    });
    case(
        "invalid KjointHandle: get/get_mut/set_motor/set_enabled/remove",
        || {
            let mut c = corner();
            let h = KjointHandle::invalid();
            format!(
                "get {:?}, get_mut {:?}, set_motor {}, set_enabled {}, remove {:?}, contains {}",
                c.joints.get(h).is_some(),
                c.joints.get_mut(h).is_some(),
                res(c
                    .joints
                    .set_motor(h, Dof::Rx, Some(KjointMotor::velocity(1.0, 1.0)))),
                c.joints.set_enabled(h, false),
                c.joints.remove(h).map(|j| j.name),
                c.joints.contains(h)
            )
        },
    );
    case("handle of a removed joint (stale)", || {
        let mut c = corner();
        let r = c.joints.remove(c.axle).map(|j| j.name);
        let h2 = c
            .joints
            .insert(
                KjointBuilder::new(KjointProperty::new(JointType::Revolute)).world_axis(Vector::Z),
                c.hub,
                c.wheel,
                &c.world.bodies,
            )
            .unwrap();
        format!(
            "removed {:?}; stale get {:?}; new handle {:?} vs old {:?}",
            r,
            c.joints.get(c.axle).map(|j| j.name.clone()),
            h2.into_raw_parts(),
            c.axle.into_raw_parts()
        )
    });
    case("KjointHandle from another set", || {
        let c = corner();
        let other = corner();
        // the other set's handles point to the same slots: a user mixing sets
        format!(
            "other.get(c.susp) finds {:?}",
            other.joints.get(c.susp).map(|j| j.name.clone())
        )
    });
    // ---- motors
    case("motor NaN target", || {
        let mut c = corner();
        res(c
            .joints
            .set_motor(c.axle, Dof::Rx, Some(KjointMotor::velocity(f64::NAN, 10.0))))
    });
    case("motor negative max_force", || {
        let mut c = corner();
        res(c.joints.set_motor(
            c.axle,
            Dof::Rx,
            Some(KjointMotor::velocity(1.0, 10.0).max_force(-5.0)),
        ))
    });
    case("motor on blocked DOF (axle Dy)", || {
        let mut c = corner();
        res(c
            .joints
            .set_motor(c.axle, Dof::Dy, Some(KjointMotor::velocity(1.0, 10.0))))
    });
    case("motor force inf", || {
        let mut c = corner();
        res(c
            .joints
            .set_motor(c.axle, Dof::Rx, Some(KjointMotor::force(f64::INFINITY))))
    });
    case("builder motor NaN -> insert", || {
        let mut c = corner();
        res(c.joints.insert(
            KjointBuilder::new(KjointProperty::new(JointType::Revolute))
                .world_axis(Vector::Z)
                .motor(Dof::Rx, KjointMotor::velocity(f64::NAN, 1.0)),
            c.hub,
            c.wheel,
            &c.world.bodies,
        ))
    });
    case("set_property changes joint type", || {
        let mut c = corner();
        let j = c.joints.get_mut(c.axle).unwrap();
        res(j.set_property(KjointProperty::new(JointType::Spherical)))
    });
    case("set_property NaN spring via get_mut", || {
        let mut c = corner();
        let j = c.joints.get_mut(c.susp).unwrap();
        res(j.set_property(
            KjointProperty::new(JointType::Translational)
                .with_dof(Dof::Dx, DofLaw::spring(f64::NAN)),
        ))
    });
    case(
        "direct field write property NaN is impossible? (property() is &)",
        || "property() returns &KjointProperty: no unchecked write path".into(),
    );
    // ---- stepping
    for dt in [0.0, -1.0 / 60.0, f64::NAN, f64::INFINITY, 10.0, 1e-30] {
        case(&format!("step dt = {dt}"), || {
            let mut c = corner();
            res(c.joints.step(&mut c.world, dt))
        });
    }
    case("substeps = 0", || {
        let mut c = corner();
        c.joints.set_settings(SubstepSettings {
            substeps: 0,
            ..Default::default()
        });
        res(c.joints.step(&mut c.world, 1.0 / 60.0))
    });
    case(
        "world.integration_parameters.dt = NaN then kjoint step",
        || {
            let mut c = corner();
            c.world.integration_parameters.dt = f32::NAN;
            let r = c.joints.step(&mut c.world, 1.0 / 60.0);
            format!(
                "{} ; dt after = {}",
                res(r),
                c.world.integration_parameters.dt
            )
        },
    );
    // ---- bodies
    case("chassis linvel NaN, then step", || {
        let mut c = corner();
        steps(&mut c, 5);
        c.world.bodies[c.chassis].set_linvel(Vector::new(f32::NAN, 0.0, 0.0), true);
        let r = c.joints.step(&mut c.world, 1.0 / 60.0);
        let r2 = c.joints.step(&mut c.world, 1.0 / 60.0);
        format!("{} ; again: {} ; {}", res(r), res(r2), events(&mut c))
    });
    case("NaN force on chassis (add_force), then step", || {
        let mut c = corner();
        steps(&mut c, 5);
        c.world.bodies[c.chassis].add_force(Vector::new(0.0, f32::NAN, 0.0), true);
        let r = c.joints.step(&mut c.world, 1.0 / 60.0);
        format!("{} ; {}", res(r), events(&mut c))
    });
    case("huge torque on wheel 1e12 N*m, then step 60", || {
        let mut c = corner();
        steps(&mut c, 5);
        let mut out = String::new();
        for k in 0..60 {
            c.world.bodies[c.wheel].add_torque(Vector::new(0.0, 0.0, 1e12), true);
            if let Err(e) = c.joints.step(&mut c.world, 1.0 / 60.0) {
                out = format!("step {k}: Err: {e}");
                break;
            }
        }
        let w = c.world.bodies[c.wheel].angvel();
        format!("{out} wheel angvel {w:?} ; {}", events(&mut c))
    });
    case(
        "remove the wheel body (world.remove_body), then step",
        || {
            let mut c = corner();
            steps(&mut c, 5);
            c.world.remove_body(c.wheel);
            let r = steps(&mut c, 5);
            format!(
                "{r} ; axle still in set: {} ; {}",
                c.joints.contains(c.axle),
                events(&mut c)
            )
        },
    );
    case("remove the hub (middle of chain), then step", || {
        let mut c = corner();
        steps(&mut c, 5);
        c.world.remove_body(c.hub);
        let r = steps(&mut c, 30);
        format!(
            "{r} ; susp {} axle {} ; {}",
            c.joints.contains(c.susp),
            c.joints.contains(c.axle),
            events(&mut c)
        )
    });
    case("remove body before first step", || {
        let mut c = corner();
        c.world.remove_body(c.wheel);
        let r = steps(&mut c, 5);
        format!("{r} ; {}", events(&mut c))
    });
    case("remove wheel then get(axle).state()", || {
        let mut c = corner();
        steps(&mut c, 5);
        c.world.remove_body(c.wheel);
        let s = c
            .joints
            .get(c.axle)
            .map(|j| j.closed_energy(&c.world.bodies));
        format!("closed_energy with body gone: {s:?}")
    });
    case("insert joint on removed body handle", || {
        let mut c = corner();
        c.world.remove_body(c.wheel);
        res(c.joints.insert(
            KjointBuilder::new(KjointProperty::new(JointType::Revolute)),
            c.hub,
            c.wheel,
            &c.world.bodies,
        ))
    });
    case(
        "body handle reused after removal (new body gets the old index)",
        || {
            let mut c = corner();
            steps(&mut c, 5);
            c.world.remove_body(c.wheel);
            let (nb, _) = c.world.insert(
                RigidBodyBuilder::dynamic().translation(Vector::new(5.0, 3.0, 0.0)),
                ColliderBuilder::ball(0.2).mass(1.0),
            );
            let r = steps(&mut c, 5);
            format!(
                "new body {:?} vs old {:?}; {r}; axle in set {}; new body y = {:.3} ; {}",
                nb.into_raw_parts(),
                c.wheel.into_raw_parts(),
                c.joints.contains(c.axle),
                c.world.bodies[nb].translation().y,
                events(&mut c)
            )
        },
    );
    case("switch chassis to fixed after insertion", || {
        let mut c = corner();
        steps(&mut c, 5);
        c.world.bodies[c.chassis].set_body_type(RigidBodyType::Fixed, true);
        let r = steps(&mut c, 30);
        format!("{r} ; {}", events(&mut c))
    });
    case(
        "switch hub AND wheel to fixed (joint between two fixed)",
        || {
            let mut c = corner();
            steps(&mut c, 5);
            c.world.bodies[c.hub].set_body_type(RigidBodyType::Fixed, true);
            c.world.bodies[c.wheel].set_body_type(RigidBodyType::Fixed, true);
            let r = steps(&mut c, 30);
            format!("{r} ; {}", events(&mut c))
        },
    );
    case("massless dynamic hub (no collider, no mass)", || {
        let mut world = PhysicsWorld::default();
        let g = world.insert_body(RigidBodyBuilder::fixed());
        let hub =
            world.insert_body(RigidBodyBuilder::dynamic().translation(Vector::new(0.0, -0.5, 0.0)));
        let mut joints = KjointSet::new();
        let r = joints.insert(
            KjointBuilder::new(susp_prop()).world_axis(Vector::Y),
            g,
            hub,
            &world.bodies,
        );
        let mut out = res(r);
        for k in 0..30 {
            if let Err(e) = joints.step(&mut world, 1.0 / 60.0) {
                out += &format!(" ; step {k}: Err: {e}");
                break;
            }
        }
        let ev: Vec<String> = joints
            .drain_events()
            .iter()
            .take(3)
            .map(|e| e.to_string())
            .collect();
        format!(
            "{out} ; hub y = {} ; events {:?}",
            world.bodies[hub].translation().y,
            ev
        )
    });
    case(
        "teleport the chassis 10 m up (set_translation) while jointed",
        || {
            let mut c = corner();
            steps(&mut c, 30);
            c.world.bodies[c.chassis].set_translation(Vector::new(0.0, 10.65, 0.0), true);
            let mut out = String::new();
            let mut maxv: f32 = 0.0;
            for k in 0..60 {
                if let Err(e) = c.joints.step(&mut c.world, 1.0 / 60.0) {
                    out = format!("step {k}: Err: {e}");
                    break;
                }
                maxv = maxv.max(c.world.bodies[c.hub].linvel().length());
            }
            format!(
                "{out} hub max speed {maxv:.1} m/s, hub y {:.3}, chassis y {:.3}; {}",
                c.world.bodies[c.hub].translation().y,
                c.world.bodies[c.chassis].translation().y,
                events(&mut c)
            )
        },
    );
    case("readout before first step", || {
        let c = corner();
        format!(
            "state() = {:?}",
            c.joints.get(c.susp).unwrap().state().map(|s| s.time)
        )
    });
}
