//! The robot loaders' rapier objects in the world's rapier.
//!
//! `rapier3d-urdf` and `rapier3d-mjcf` 0.36 build their bodies, colliders and joints with
//! `rapier3d` (f32) and have no f64 variant. Without the `f64` feature the world is that
//! rapier and these functions are copies. With it, the loaders still build f32 objects, and
//! these functions rebuild them in `rapier3d-f64` field by field (every field a loader sets:
//! body type, pose, velocities, added mass properties, damping, gravity scale, sleeping,
//! CCD, locked axes; collider shape, pose on its body, mass properties, friction,
//! restitution, groups, hooks, events; joint frames, axes, limits, motors, softness). The
//! f32 values convert exactly; what a description gives beyond f32 (a URDF origin's 7th
//! digit) was already rounded by the loader. The crate reads the description's own numbers
//! (f64) where it uses them itself: URDF inertials for the friction stiffness, MJCF ranges
//! for the stops.
//!
//! Shapes: the ones the loaders make (ball, cuboid, capsule, cylinder, cone, half-space,
//! convex polyhedron, triangle mesh, height field, and compounds of them); another is an
//! error naming it.

#[cfg(not(feature = "f64"))]
mod imp {
    use crate::rapier::dynamics::{GenericJoint, RigidBody};
    use crate::rapier::geometry::Collider;

    /// A loader's body in the world's rapier.
    pub(crate) fn body(b: &RigidBody) -> RigidBody {
        b.clone()
    }

    /// A loader's collider in the world's rapier (an error names a shape it cannot convert).
    pub(crate) fn collider(c: &Collider) -> Result<Collider, String> {
        Ok(c.clone())
    }

    /// A loader's joint in the world's rapier.
    pub(crate) fn joint(j: &GenericJoint) -> GenericJoint {
        *j
    }
}

#[cfg(feature = "f64")]
mod imp {
    use crate::dynamics::from_f32::{pose, quat, vec3};
    use crate::rapier::dynamics as wd;
    use crate::rapier::geometry as wg;
    use rapier3d::dynamics as fd;
    use rapier3d::geometry as fg;

    fn mass_properties(m: &fd::MassProperties) -> wd::MassProperties {
        wd::MassProperties {
            local_com: vec3(m.local_com),
            inv_mass: m.inv_mass.into(),
            inv_principal_inertia: vec3(m.inv_principal_inertia),
            principal_inertia_local_frame: quat(m.principal_inertia_local_frame),
        }
    }

    /// A loader's (f32) body in the world's rapier (f64).
    pub(crate) fn body(b: &fd::RigidBody) -> wd::RigidBody {
        let body_type = match b.body_type() {
            fd::RigidBodyType::Dynamic => wd::RigidBodyType::Dynamic,
            fd::RigidBodyType::Fixed => wd::RigidBodyType::Fixed,
            fd::RigidBodyType::KinematicPositionBased => wd::RigidBodyType::KinematicPositionBased,
            fd::RigidBodyType::KinematicVelocityBased => wd::RigidBodyType::KinematicVelocityBased,
            // soft-body proxies are made by rapier itself, never by a loader
            fd::RigidBodyType::SoftFrame => wd::RigidBodyType::Dynamic,
        };
        let mut builder = wd::RigidBodyBuilder::new(body_type)
            .pose(pose(b.position()))
            .linvel(vec3(b.linvel()))
            .angvel(vec3(b.angvel()))
            .gravity_scale(b.gravity_scale().into())
            .linear_damping(b.linear_damping().into())
            .angular_damping(b.angular_damping().into())
            .dominance_group(b.dominance_group())
            .ccd_enabled(b.is_ccd_enabled())
            .soft_ccd_prediction(b.soft_ccd_prediction().into())
            .allow_fast_rotation(b.is_fast_rotation_allowed())
            .gyroscopic_forces_enabled(b.gyroscopic_forces_enabled())
            .locked_axes(wd::LockedAxes::from_bits_truncate(b.locked_axes().bits()))
            .additional_solver_iterations(b.additional_solver_iterations())
            .enabled(b.is_enabled())
            .user_data(b.user_data);
        if let Some(extra) = &b.mass_properties().additional_local_mprops {
            builder = match **extra {
                fd::RigidBodyAdditionalMassProps::MassProps(m) => {
                    builder.additional_mass_properties(mass_properties(&m))
                }
                fd::RigidBodyAdditionalMassProps::Mass(m) => builder.additional_mass(m.into()),
            };
        }
        let mut out = builder.build();
        // the sleep thresholds (`can_sleep(false)` makes them negative)
        let (a, o) = (b.activation(), out.activation_mut());
        o.normalized_linear_threshold = a.normalized_linear_threshold.into();
        o.angular_threshold = a.angular_threshold.into();
        o.time_until_sleep = a.time_until_sleep.into();
        o.sleeping = a.sleeping;
        out
    }

    fn shape(s: &fg::SharedShape) -> Result<wg::SharedShape, String> {
        use fg::TypedShape as T;
        Ok(match s.as_typed_shape() {
            T::Ball(b) => wg::SharedShape::ball(b.radius.into()),
            T::Cuboid(c) => {
                let h = vec3(c.half_extents);
                wg::SharedShape::cuboid(h.x, h.y, h.z)
            }
            T::Capsule(c) => {
                wg::SharedShape::capsule(vec3(c.segment.a), vec3(c.segment.b), c.radius.into())
            }
            T::Cylinder(c) => wg::SharedShape::cylinder(c.half_height.into(), c.radius.into()),
            T::Cone(c) => wg::SharedShape::cone(c.half_height.into(), c.radius.into()),
            T::HalfSpace(h) => wg::SharedShape::halfspace(vec3(h.normal)),
            T::ConvexPolyhedron(c) => {
                let points: Vec<_> = c.points().iter().map(|p| vec3(*p)).collect();
                wg::SharedShape::convex_hull(&points)
                    .ok_or("a convex polyhedron whose f64 hull is degenerate")?
            }
            T::TriMesh(m) => wg::SharedShape::trimesh_with_flags(
                m.vertices().iter().map(|p| vec3(*p)).collect(),
                m.indices().to_vec(),
                wg::TriMeshFlags::from_bits_truncate(m.flags().bits()),
            )
            .map_err(|e| format!("a triangle mesh rapier3d-f64 refuses: {e}"))?,
            T::HeightField(h) => {
                let heights = h.heights();
                wg::SharedShape::heightfield_with_flags(
                    crate::rapier::parry::utils::Array2::new(
                        heights.nrows(),
                        heights.ncols(),
                        heights.data().iter().map(|&z| z.into()).collect(),
                    ),
                    vec3(h.scale()),
                    wg::HeightFieldFlags::from_bits_truncate(h.flags().bits()),
                )
            }
            T::Compound(c) => wg::SharedShape::compound(
                c.shapes()
                    .iter()
                    .map(|(p, s)| Ok((pose(p), shape(s)?)))
                    .collect::<Result<_, String>>()?,
            ),
            _ => {
                return Err(format!(
                    "a {:?} shape, which the f64 build does not convert",
                    s.shape_type()
                ))
            }
        })
    }

    fn groups(g: fg::InteractionGroups) -> wg::InteractionGroups {
        wg::InteractionGroups::new(
            wg::Group::from_bits_truncate(g.memberships.bits()),
            wg::Group::from_bits_truncate(g.filter.bits()),
            match g.test_mode {
                fg::InteractionTestMode::And => wg::InteractionTestMode::And,
                fg::InteractionTestMode::Or => wg::InteractionTestMode::Or,
            },
        )
    }

    fn combine_rule(r: fd::CoefficientCombineRule) -> wd::CoefficientCombineRule {
        match r {
            fd::CoefficientCombineRule::Average => wd::CoefficientCombineRule::Average,
            fd::CoefficientCombineRule::Min => wd::CoefficientCombineRule::Min,
            fd::CoefficientCombineRule::Multiply => wd::CoefficientCombineRule::Multiply,
            fd::CoefficientCombineRule::Max => wd::CoefficientCombineRule::Max,
            fd::CoefficientCombineRule::ClampedSum => wd::CoefficientCombineRule::ClampedSum,
            fd::CoefficientCombineRule::GeometricMean => wd::CoefficientCombineRule::GeometricMean,
        }
    }

    /// A loader's (f32) collider, not yet on a body, in the world's rapier (f64); an error
    /// names a shape it cannot convert.
    pub(crate) fn collider(c: &fg::Collider) -> Result<wg::Collider, String> {
        Ok(wg::ColliderBuilder::new(shape(c.shared_shape())?)
            .position(pose(c.position()))
            .mass_properties(mass_properties(&c.mass_properties()))
            .friction(c.friction().into())
            .friction_combine_rule(combine_rule(c.friction_combine_rule()))
            .restitution(c.restitution().into())
            .restitution_combine_rule(combine_rule(c.restitution_combine_rule()))
            .collision_groups(groups(c.collision_groups()))
            .solver_groups(groups(c.solver_groups()))
            .active_hooks(crate::rapier::pipeline::ActiveHooks::from_bits_truncate(
                c.active_hooks().bits(),
            ))
            .active_events(crate::rapier::pipeline::ActiveEvents::from_bits_truncate(
                c.active_events().bits(),
            ))
            .active_collision_types(wg::ActiveCollisionTypes::from_bits_truncate(
                c.active_collision_types().bits(),
            ))
            .sensor(c.is_sensor())
            .contact_skin(c.contact_skin().into())
            .contact_force_event_threshold(c.contact_force_event_threshold().into())
            .enabled(c.is_enabled())
            .user_data(c.user_data)
            .build())
    }

    /// A loader's (f32) joint in the world's rapier (f64).
    pub(crate) fn joint(j: &fd::GenericJoint) -> wd::GenericJoint {
        let axes = |m: fd::JointAxesMask| wd::JointAxesMask::from_bits_truncate(m.bits());
        wd::GenericJoint {
            local_frame1: pose(&j.local_frame1),
            local_frame2: pose(&j.local_frame2),
            locked_axes: axes(j.locked_axes),
            limit_axes: axes(j.limit_axes),
            motor_axes: axes(j.motor_axes),
            coupled_axes: axes(j.coupled_axes),
            limits: j.limits.map(|l| wd::JointLimits {
                min: l.min.into(),
                max: l.max.into(),
                impulse: l.impulse.into(),
            }),
            motors: j.motors.map(|m| wd::JointMotor {
                target_vel: m.target_vel.into(),
                target_pos: m.target_pos.into(),
                stiffness: m.stiffness.into(),
                damping: m.damping.into(),
                max_force: m.max_force.into(),
                impulse: m.impulse.into(),
                model: match m.model {
                    fd::MotorModel::AccelerationBased => wd::MotorModel::AccelerationBased,
                    fd::MotorModel::ForceBased => wd::MotorModel::ForceBased,
                },
            }),
            softness: wd::SpringCoefficients {
                natural_frequency: j.softness.natural_frequency.into(),
                damping_ratio: j.softness.damping_ratio.into(),
            },
            contacts_enabled: j.contacts_enabled,
            enabled: match j.enabled {
                fd::JointEnabled::Enabled => wd::JointEnabled::Enabled,
                fd::JointEnabled::DisabledByAttachedBody => {
                    wd::JointEnabled::DisabledByAttachedBody
                }
                fd::JointEnabled::Disabled => wd::JointEnabled::Disabled,
            },
            user_data: j.user_data,
        }
    }
}

pub(crate) use imp::{body, collider, joint};

/// The conversions keep what the loaders set: every shape kind's bounding box and mass
/// properties, a body's pose, mass and sleeping, a joint's frames, axes, limits and motors.
#[cfg(all(test, feature = "f64"))]
mod tests {
    use super::*;
    use rapier3d::dynamics as fd;
    use rapier3d::geometry as fg;
    use rapier3d::math::{Pose as FPose, Rotation as FRot, Vector as FVec};

    fn close(a: f64, b: f32) -> bool {
        (a - b as f64).abs() <= 1e-6 * (1.0 + a.abs())
    }

    #[test]
    fn every_shape_the_loaders_make_keeps_its_box_and_mass() {
        let cube: Vec<FVec> = (0..8)
            .map(|i| FVec::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32))
            .collect();
        let tris = vec![[0, 1, 2], [1, 3, 2], [4, 6, 5], [5, 6, 7]];
        let shapes = [
            fg::SharedShape::ball(0.3),
            fg::SharedShape::cuboid(0.1, 0.2, 0.3),
            fg::SharedShape::capsule_z(0.4, 0.1),
            fg::SharedShape::cylinder(0.25, 0.05),
            fg::SharedShape::cone(0.25, 0.05),
            fg::SharedShape::halfspace(FVec::Z),
            fg::SharedShape::convex_hull(&cube).unwrap(),
            fg::SharedShape::trimesh(cube.clone(), tris).unwrap(),
            fg::SharedShape::heightfield(
                rapier3d::parry::utils::Array2::new(2, 3, vec![0.0, 0.1, 0.2, 0.3, 0.4, 0.5]),
                FVec::new(2.0, 1.0, 3.0),
            ),
            fg::SharedShape::compound(vec![
                (
                    FPose::translation(0.5, 0.0, 0.0),
                    fg::SharedShape::ball(0.1),
                ),
                (FPose::IDENTITY, fg::SharedShape::cuboid(0.1, 0.1, 0.1)),
            ]),
        ];
        for s in shapes {
            let c = fg::ColliderBuilder::new(s.clone())
                .position(FPose::from_parts(
                    FVec::new(0.1, -0.2, 0.3),
                    FRot::from_rotation_x(0.3),
                ))
                .density(2.0)
                .friction(0.7)
                .restitution(0.2)
                .collision_groups(fg::InteractionGroups::new(
                    fg::Group::GROUP_32,
                    fg::Group::GROUP_1,
                    fg::InteractionTestMode::Or,
                ))
                .build();
            let w = collider(&c).unwrap();
            let name = format!("{:?}", s.shape_type());
            assert_eq!(format!("{:?}", w.shape().shape_type()), name);
            if name != "HalfSpace" {
                let (a, b) = (w.shape().compute_local_aabb(), s.compute_local_aabb());
                for k in 0..3 {
                    assert!(
                        close(a.mins[k], b.mins[k]) && close(a.maxs[k], b.maxs[k]),
                        "{name}"
                    );
                }
            }
            let (mw, mf) = (w.mass_properties(), c.mass_properties());
            assert!(
                close(mw.mass(), mf.mass()),
                "{name}: {} {}",
                mw.mass(),
                mf.mass()
            );
            for k in 0..3 {
                assert!(close(mw.local_com[k], mf.local_com[k]), "{name}");
                assert!(
                    close(mw.principal_inertia()[k], mf.principal_inertia()[k]),
                    "{name}"
                );
            }
            assert!(close(w.position().translation.y, -0.2));
            assert!(close(w.position().rotation.x, c.position().rotation.x));
            assert!(close(w.friction(), 0.7) && close(w.restitution(), 0.2));
            let g = w.collision_groups();
            assert_eq!(g.memberships.bits(), fg::Group::GROUP_32.bits());
            assert_eq!(g.filter.bits(), fg::Group::GROUP_1.bits());
            assert_eq!(
                g.test_mode,
                crate::rapier::geometry::InteractionTestMode::Or
            );
        }
        // a shape no loader makes is an error naming it
        let seg = fg::ColliderBuilder::new(fg::SharedShape::segment(FVec::ZERO, FVec::X)).build();
        let e = collider(&seg).unwrap_err();
        assert!(e.contains("Segment"), "{e}");
    }

    #[test]
    fn a_body_keeps_its_pose_mass_and_sleeping() {
        let mp = fd::MassProperties::with_principal_inertia_frame(
            FVec::new(0.0, 0.1, 0.0),
            2.5,
            FVec::new(0.1, 0.2, 0.3),
            FRot::from_rotation_y(0.4),
        );
        let b = fd::RigidBodyBuilder::dynamic()
            .pose(FPose::from_parts(
                FVec::new(1.0, 2.0, 3.0),
                FRot::from_rotation_z(0.5),
            ))
            .additional_mass_properties(mp)
            .gravity_scale(0.5)
            .linear_damping(0.1)
            .can_sleep(false)
            .build();
        let w = body(&b);
        assert!(w.is_dynamic());
        assert!(close(w.translation().z, 3.0) && close(w.rotation().z, b.rotation().z));
        let extra = w
            .mass_properties()
            .additional_local_mprops
            .as_deref()
            .copied();
        let Some(crate::rapier::dynamics::RigidBodyAdditionalMassProps::MassProps(m)) = extra
        else {
            panic!("no added mass properties: {extra:?}");
        };
        assert!(close(m.mass(), 2.5) && close(m.local_com.y, 0.1));
        assert!(close(m.principal_inertia().z, 0.3));
        assert!(close(w.gravity_scale(), 0.5) && close(w.linear_damping(), 0.1));
        assert!(w.activation().angular_threshold < 0.0, "never sleeps");
        let fixed = body(&fd::RigidBodyBuilder::fixed().build());
        assert!(fixed.is_fixed());
    }

    #[test]
    fn a_joint_keeps_its_frames_axes_limits_and_motor() {
        let mut j = fd::GenericJointBuilder::new(fd::JointAxesMask::LOCKED_REVOLUTE_AXES)
            .local_anchor1(FVec::new(0.0, 0.5, 0.0))
            .local_axis2(FVec::new(0.0, 0.6, 0.8))
            .limits(fd::JointAxis::AngX, [-0.3, 0.7])
            .build();
        j.set_motor_model(fd::JointAxis::AngX, fd::MotorModel::ForceBased);
        j.set_motor_position(fd::JointAxis::AngX, 0.2, 100.0, 5.0);
        let w = joint(&j);
        assert_eq!(w.locked_axes.bits(), j.locked_axes.bits());
        assert_eq!(w.limit_axes.bits(), j.limit_axes.bits());
        assert_eq!(w.motor_axes.bits(), j.motor_axes.bits());
        assert!(close(w.local_frame1.translation.y, 0.5));
        assert!(close(w.local_frame2.rotation.x, j.local_frame2.rotation.x));
        let ax = crate::rapier::dynamics::JointAxis::AngX;
        let l = w.limits(ax).unwrap();
        assert!(close(l.min, -0.3) && close(l.max, 0.7));
        let m = w.motor(ax).unwrap();
        assert!(close(m.target_pos, 0.2) && close(m.stiffness, 100.0) && close(m.damping, 5.0));
        assert_eq!(
            w.motor_model(ax),
            Some(crate::rapier::dynamics::MotorModel::ForceBased)
        );
    }
}
