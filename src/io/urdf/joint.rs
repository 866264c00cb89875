//! URDF joints → joints: the KJOINT2 type and stops of a URDF joint (`kjoint_type`,
//! `stops_from_limits`), its KJOINT2 builder, the per-joint overrides, and the rapier impulse
//! joint of a joint built by rapier (`engine = "rapier"`).

use super::error::{in_range, ErrorContext, UrdfError, RANGE};
use super::options::{JointOverride, RapierMotor};
use crate::figure::fmt_num;
use crate::law::{Dof, JointType, KjointMotor, KjointProperty};
use crate::rapier::dynamics::{GenericJoint, JointAxesMask, JointAxis, MotorModel};
use crate::rapier::math::{Pose, Real, Rotation};
use crate::KjointBuilder;
use rapier3d_urdf::urdf_rs;

pub use crate::law::ZERO_LIMIT;

/// The KJOINT2 type of a URDF joint type (module docs, "Mapping").
pub(super) fn kjoint_type(t: &urdf_rs::JointType) -> JointType {
    match t {
        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => JointType::Revolute,
        urdf_rs::JointType::Prismatic => JointType::Translational,
        urdf_rs::JointType::Fixed => JointType::Fixed,
        urdf_rs::JointType::Floating => JointType::Free,
        urdf_rs::JointType::Planar => JointType::Planar,
        urdf_rs::JointType::Spherical => JointType::Spherical,
    }
}

/// The DOF that carries a joint's URDF axis data (limits, dynamics, overrides).
pub(crate) fn axis_dof(t: JointType) -> Option<Dof> {
    match t {
        JointType::Revolute | JointType::Planar => Some(Dof::Rx),
        JointType::Translational => Some(Dof::Dx),
        _ => None,
    }
}

/// The DOF a motor of a robot joint of type `t` drives: the axis of a revolute
/// (continuous) or prismatic joint; none for the others (a planar joint's `rx` included).
pub(crate) fn motor_dof(t: JointType) -> Option<Dof> {
    axis_dof(t).filter(|_| t != JointType::Planar)
}

/// URDF limits → KJOINT2 stops `(SD-, SD+)`, and a notice when they had to be changed.
pub(crate) fn stops_from_limits(lower: f64, upper: f64) -> ((f64, f64), Option<String>) {
    if lower == 0.0 && upper == 0.0 {
        return (
            (0.0, 0.0),
            Some("limit lower = upper = 0: read as no limits".into()),
        );
    }
    let mut note = None;
    let lo = if lower == f64::NEG_INFINITY {
        0.0
    } else if lower > 0.0 {
        note = Some(format!(
            "limit [{lower}, {upper}] excludes the initial position 0: widened to include \
             it (an initial position within it, options.initial_positions, keeps it)"
        ));
        -ZERO_LIMIT
    } else if lower == 0.0 {
        -ZERO_LIMIT
    } else {
        lower
    };
    let hi = if upper == f64::INFINITY {
        0.0
    } else if upper < 0.0 {
        note = Some(format!(
            "limit [{lower}, {upper}] excludes the initial position 0: widened to include \
             it (an initial position within it, options.initial_positions, keeps it)"
        ));
        ZERO_LIMIT
    } else if upper == 0.0 {
        ZERO_LIMIT
    } else {
        upper
    };
    ((lo, hi), note)
}

/// The rapier impulse joint of a URDF joint whose override says `engine = "rapier"`:
/// `rapier3d-urdf`'s joint (frames at the URDF joint origin, the axis as the joint's x, the
/// URDF limits on the axis), with the limits read as for the KJOINT2 stops where rapier
/// would read them otherwise and the override's motor (module docs, "Rapier joints"). `q0`:
/// the joint's initial position (its links stand there: rapier measures from the zero pose).
pub(super) fn rapier_joint(
    context: &ErrorContext,
    name: &str,
    src: &urdf_rs::Joint,
    mut joint: GenericJoint,
    ov: &JointOverride,
    q0: f64,
    notices: &mut Vec<String>,
) -> Result<GenericJoint, UrdfError> {
    let el = format!("options.joints.`{name}`");
    let kjoint_fields = [
        ("property", ov.property.is_some()),
        ("kn", ov.kn.is_some()),
        ("critical_damping", ov.critical_damping.is_some()),
        ("stiffness", ov.stiffness.is_some()),
        ("viscosity", ov.viscosity.is_some()),
        ("friction", ov.friction.is_some()),
        ("friction_stiffness", ov.friction_stiffness.is_some()),
        ("armature", ov.armature.is_some()),
        ("stop_min", ov.stop_min.is_some()),
        ("stop_max", ov.stop_max.is_some()),
        ("joint_friction", ov.joint_friction.is_some()),
        ("break", ov.break_criterion.is_some()),
    ];
    if let Some((f, _)) = kjoint_fields.iter().find(|(_, set)| *set) {
        return Err(context.field(
            &el,
            *f,
            "(set)",
            "nothing: a rapier joint (engine = \"rapier\") takes no KJOINT2 field, only `motor` \
             (its limits are the URDF's)",
        ));
    }
    let axis = match src.joint_type {
        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => Some(JointAxis::AngX),
        urdf_rs::JointType::Prismatic => Some(JointAxis::LinX),
        _ => None,
    };
    if let Some(axis) = axis.filter(|_| src.joint_type != urdf_rs::JointType::Continuous) {
        let (lo, hi) = (src.limit.lower, src.limit.upper);
        if lo == 0.0 && hi == 0.0 {
            // the URDF default of a <limit> with effort and velocity only, as for KJOINT2
            joint.limit_axes.remove(JointAxesMask::from(axis));
            notices.push(format!(
                "joint `{name}`: limit lower = upper = 0: read as no limits"
            ));
        } else {
            // rapier's limits have two sides: an infinite one becomes a far one
            let side = |v: f64| v.clamp(-FAR_LIMIT, FAR_LIMIT) as Real;
            joint.set_limits(axis, [side(lo), side(hi)]);
            if lo > q0 || hi < q0 {
                notices.push(format!(
                    "joint `{name}`: limit [{lo}, {hi}] excludes the initial position {q0}: \
                     rapier pulls the joint into it at the first step"
                ));
            }
        }
    }
    if src
        .dynamics
        .as_ref()
        .is_some_and(|d| d.damping > 0.0 || d.friction > 0.0)
    {
        notices.push(format!(
            "joint `{name}`: <dynamics> ignored on a rapier joint (give the motor damping)"
        ));
    }
    if let Some(m) = &ov.motor {
        let Some(axis) = axis else {
            return Err(context.field(
                &el,
                "motor",
                m.to_string(),
                format!(
                    "no motor on a {:?} joint: a motor drives the axis of a revolute, continuous \
                     or prismatic joint",
                    src.joint_type
                ),
            ));
        };
        checked_motor(context, &el, m)?;
        joint.set_motor_model(axis, MotorModel::ForceBased);
        joint.set_motor_position(
            axis,
            m.target as Real,
            m.stiffness as Real,
            m.damping as Real,
        );
        if let Some(f) = m.max_force {
            joint.set_motor_max_force(axis, f as Real);
        }
    }
    Ok(joint)
}

/// Checks an override's motor (`el`: the override's element): a finite target, stiffness
/// and damping ≥ 0 and not both 0, a cap > 0, every value within ±1e12.
pub(super) fn checked_motor(
    context: &ErrorContext,
    el: &str,
    m: &RapierMotor,
) -> Result<(), UrdfError> {
    let e = format!("{el}.motor");
    context.finite(&e, "target", m.target)?;
    for (f, v) in [("stiffness", m.stiffness), ("damping", m.damping)] {
        if !(in_range(v) && v >= 0.0) {
            return Err(context.field(&e, f, fmt_num(v), "a finite value >= 0 (within ±1e12)"));
        }
    }
    if m.stiffness == 0.0 && m.damping == 0.0 {
        return Err(context.field(
            &e,
            "stiffness",
            m.stiffness,
            "a value > 0 (or a damping > 0): a motor with neither does nothing",
        ));
    }
    if let Some(f) = m.max_force {
        if !(in_range(f) && f > 0.0) {
            return Err(context.field(
                &e,
                "max_force",
                fmt_num(f),
                "a finite force > 0 [N or N·m] (within ±1e12)",
            ));
        }
    }
    Ok(())
}

/// The KJOINT2 motor of an override's motor on a joint of `joint_type` standing at `q0`
/// (its target a `q` of the file, the motor's a `q − q0`), or an error naming the override
/// for a joint without one axis.
pub(super) fn kjoint_motor(
    context: &ErrorContext,
    el: &str,
    joint_type: JointType,
    m: &RapierMotor,
    q0: f64,
) -> Result<(Dof, KjointMotor), UrdfError> {
    checked_motor(context, el, m)?;
    let Some(dof) = motor_dof(joint_type) else {
        return Err(context.field(
            el,
            "motor",
            m.to_string(),
            format!(
                "no motor on a {} joint: a motor drives the axis of a revolute, continuous or \
                 prismatic joint",
                joint_type.name()
            ),
        ));
    };
    let motor = KjointMotor::position(m.target - q0, m.stiffness, m.damping)
        .max_force(m.max_force.unwrap_or(f64::INFINITY));
    Ok((dof, motor))
}

/// How far \[m or rad\] the infinite side of a rapier joint's URDF limit is put (rapier's
/// limits have two sides).
pub const FAR_LIMIT: f64 = 1e6;

/// The joint's builder made breakable by the override's `break` table, checked (the error
/// names `break.<field>`); unchanged without one.
pub(crate) fn with_break(
    context: &ErrorContext,
    joint: &str,
    builder: KjointBuilder,
    ov: Option<&JointOverride>,
) -> Result<KjointBuilder, UrdfError> {
    let Some(c) = ov.and_then(|o| o.break_criterion) else {
        return Ok(builder);
    };
    c.validate().map_err(|e| match e {
        crate::error::PropertyError::InvalidField {
            field,
            value,
            expected,
        } => context.field(
            format!("options.joints.`{joint}`"),
            format!("break.{field}"),
            value,
            expected,
        ),
        other => context.field(
            format!("options.joints.`{joint}`"),
            "break",
            "",
            other.to_string(),
        ),
    })?;
    Ok(builder.break_when(c))
}

/// The friction spring `Kf` of the axis DOF of `prop` (a robot joint's property, its
/// override applied) by the implicit rule, `rule_kf` ([`super::friction_stiffness`] of the
/// load beyond the joint), where the DOF has a friction force and no `Kf`: the file's
/// (`<dynamics friction>`, MJCF `frictionloss`) or the override's `friction` (which was
/// inactive, silently, on a joint whose file gives none). An override's
/// `friction_stiffness` or whole `property` is the user's, kept as given. Returns the DOF
/// when its `Kf` is the rule's (the start notices do not name it:
/// [`crate::KjointDescription`]'s `friction_by_rule`).
pub(crate) fn friction_by_rule(
    prop: &mut KjointProperty,
    rule_kf: f64,
    ov: Option<&JointOverride>,
) -> Option<Dof> {
    let dof = axis_dof(prop.joint_type)?;
    if ov.is_some_and(|o| o.property.is_some() || o.friction_stiffness.is_some()) {
        return None;
    }
    let law = &mut prop.dofs[dof.index()];
    if law.friction > 0.0 && law.friction_stiffness == 0.0 && rule_kf > 0.0 {
        law.friction_stiffness = rule_kf;
        return Some(dof);
    }
    None
}

/// A joint's property `prop` with the override `ov` applied (see [`JointOverride`]), validated.
pub(crate) fn apply_override(
    context: &ErrorContext,
    joint: &str,
    prop: KjointProperty,
    ov: &JointOverride,
) -> Result<KjointProperty, UrdfError> {
    let el = format!("options.joints.`{joint}`");
    check_override_numbers(context, &el, ov)?;
    let mut p = ov.property.clone().unwrap_or(prop);
    if let Some(v) = ov.kn {
        p.kn = v;
    }
    if let Some(v) = ov.critical_damping {
        p.critical_damping = v;
    }
    let fields = dof_fields(ov);
    if fields.iter().any(|(_, v)| v.is_some()) {
        let Some(dof) = axis_dof(p.joint_type) else {
            let (f, v) = fields
                .iter()
                .find(|(_, v)| v.is_some())
                .copied()
                .unwrap_or(("", None));
            return Err(context.field(
                el,
                f,
                v.unwrap_or_default(),
                format!(
                    "no per-DOF field on a {} joint (give a whole `property` instead)",
                    p.joint_type.name()
                ),
            ));
        };
        let law = &mut p.dofs[dof.index()];
        for (f, v) in fields {
            if let Some(v) = v {
                match f {
                    "stiffness" => law.stiffness = v,
                    "viscosity" => law.viscosity = v,
                    "friction" => law.friction = v,
                    "friction_stiffness" => law.friction_stiffness = v,
                    "armature" => law.armature = v,
                    "stop_min" => law.stop_min = v,
                    _ => law.stop_max = v,
                }
            }
        }
    }
    if let Some(law) = &ov.joint_friction {
        joint_friction_override(context, &el, &mut p, law, ov.friction.is_some())?;
    }
    p.validate().map_err(|source| UrdfError::Override {
        file: context.file.to_string(),
        joint: joint.to_string(),
        source,
    })?;
    Ok(p)
}

/// The override's fields of the joint's axis DOF, by their names in a scene.
fn dof_fields(ov: &JointOverride) -> [(&'static str, Option<f64>); 7] {
    [
        ("stiffness", ov.stiffness),
        ("viscosity", ov.viscosity),
        ("friction", ov.friction),
        ("friction_stiffness", ov.friction_stiffness),
        ("armature", ov.armature),
        ("stop_min", ov.stop_min),
        ("stop_max", ov.stop_max),
    ]
}

/// Every number of the override `ov` (at `el`, ``options.joints.`elbow` ``) finite and
/// within ±1e12 ([`in_range`]), as the URDF attributes they replace are (`<dynamics
/// friction="1e308">` is refused; `friction = 1e308` was not): the single fields, the
/// `break` and `joint_friction` tables, and a whole `property`'s `Kn`, `ScF`, `Cr`, DOF
/// laws and curve points. The error names the field as written under the joint's override
/// (`friction`, `break.force`, `property.dofs[3].friction_curve`). The motor of a rapier
/// joint is checked with it ([`rapier_joint`]).
fn check_override_numbers(
    context: &ErrorContext,
    el: &str,
    ov: &JointOverride,
) -> Result<(), UrdfError> {
    let mut numbers: Vec<(String, f64)> = Vec::new();
    let mut add = |field: &str, v: f64| numbers.push((field.to_string(), v));
    let joint_fields = [("kn", ov.kn), ("critical_damping", ov.critical_damping)];
    for (f, v) in joint_fields.into_iter().chain(dof_fields(ov)) {
        if let Some(v) = v {
            add(f, v);
        }
    }
    if let Some(b) = &ov.break_criterion {
        add("break.force", b.force);
        add("break.moment", b.moment);
        add("break.force_exponent", b.force_exponent);
        add("break.moment_exponent", b.moment_exponent);
        add("break.dissipated_energy", b.dissipated_energy);
    }
    if let Some(j) = &ov.joint_friction {
        add("joint_friction.mu", j.mu);
        add("joint_friction.pin_radius", j.pin_radius);
        add("joint_friction.length", j.length);
        add("joint_friction.thrust_radius", j.thrust_radius);
        add("joint_friction.preload", j.preload);
        add("joint_friction.stick_stiffness", j.stick_stiffness);
        let f = "joint_friction.stick_rotational_stiffness";
        add(f, j.stick_rotational_stiffness);
    }
    let mut curves = Vec::new();
    if let Some(p) = &ov.property {
        add("property.kn", p.kn);
        add("property.scale_factor", p.scale_factor);
        add("property.critical_damping", p.critical_damping);
        for (i, law) in p.dofs.iter().enumerate() {
            let d = format!("property.dofs[{i}]");
            add(&format!("{d}.stiffness"), law.stiffness);
            add(&format!("{d}.stop_min"), law.stop_min);
            add(&format!("{d}.stop_max"), law.stop_max);
            add(&format!("{d}.viscosity"), law.viscosity);
            add(&format!("{d}.friction_stiffness"), law.friction_stiffness);
            add(&format!("{d}.friction"), law.friction);
            add(&format!("{d}.armature"), law.armature);
            for (f, c) in [
                ("stiffness_curve", &law.stiffness_curve),
                ("viscosity_curve", &law.viscosity_curve),
                ("friction_curve", &law.friction_curve),
            ] {
                if let Some(c) = c {
                    curves.push((format!("{d}.{f}"), c));
                }
            }
        }
    }
    for (field, v) in numbers {
        context.finite(el, &field, v)?;
    }
    for (field, c) in curves {
        if let Some((x, y)) = c.points().find(|(x, y)| !(in_range(*x) && in_range(*y))) {
            let point = format!("a point [{}, {}]", fmt_num(x), fmt_num(y));
            return Err(context.field(el, field, point, RANGE));
        }
    }
    Ok(())
}

/// Checks a `joint_friction` override against the joint's type and drops the axis DOF's
/// constant friction (`FF`, from `<dynamics friction>`) it replaces.
fn joint_friction_override(
    context: &ErrorContext,
    el: &str,
    p: &mut KjointProperty,
    law: &crate::law::JointFriction,
    with_friction: bool,
) -> Result<(), UrdfError> {
    let field = |f: &str, v: String, expected: String| {
        Err(context.field(el, format!("joint_friction.{f}"), v, expected))
    };
    if with_friction {
        return field(
            "mu",
            law.mu.to_string(),
            "no `friction` beside it: both are friction on the joint's axis".into(),
        );
    }
    let types = crate::law::JointFriction::JOINT_TYPES;
    let Some(dof) = axis_dof(p.joint_type).filter(|_| types.contains(&p.joint_type)) else {
        return Err(context.field(
            el,
            "joint_friction",
            "(set)",
            format!(
                "a revolute, continuous or prismatic joint, not a {} joint",
                p.joint_type.name()
            ),
        ));
    };
    if let Err(crate::error::PropertyError::InvalidField {
        field: f,
        value,
        expected,
    }) = law.validate_for(p.joint_type)
    {
        return field(&f, value, expected);
    }
    let axis = &mut p.dofs[dof.index()];
    axis.friction = 0.0;
    axis.friction_curve = None;
    Ok(())
}

/// The joint friction law of an override, attached to `builder` (none: unchanged).
pub(crate) fn with_override_connector(
    builder: KjointBuilder,
    ov: Option<&JointOverride>,
) -> KjointBuilder {
    match ov.and_then(|o| o.joint_friction) {
        Some(law) => builder.joint_friction(law),
        None => builder,
    }
}

/// The KJOINT2 joint `name` of a description: anchors at the translations of the rapier
/// joint frames `frames` (in each body), its frame the world rotation `frame` on both sides
/// (the loaded pose is the unloaded one). With `self_collisions` the robot's links collide
/// with each other but not with the link across a joint
/// ([`KjointBuilder::contacts_enabled`]), as `rapier3d-urdf`'s joints by default and as
/// MuJoCo leaves a body and its parent apart: adjacent links overlap at their joint in most
/// descriptions; without it the robot's collision groups keep every link apart already.
pub(crate) fn kjoint_builder(
    prop: KjointProperty,
    name: &str,
    frames: (&Pose, &Pose),
    frame: Rotation,
    self_collisions: bool,
) -> KjointBuilder {
    KjointBuilder::new(prop)
        .name(name.to_string())
        .local_anchor1(frames.0.translation)
        .local_anchor2(frames.1.translation)
        .world_frame1(frame)
        .world_frame2(frame)
        .contacts_enabled(!self_collisions)
}
