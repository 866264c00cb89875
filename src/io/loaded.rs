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
