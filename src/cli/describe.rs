//! What `kjoint check` prints of a joint: its property with every default applied, its
//! connector law, and the rapier joints of robots; all in SI.

use rapier_kjoint::figure::fmt_num;
use rapier_kjoint::law::flex_joint::FlexMode;
use rapier_kjoint::law::{ConnectorLaw, Dof, KjointProperty};
use rapier_kjoint::rapier::dynamics::{ImpulseJointHandle, JointAxis};
use rapier_kjoint::rapier::pipeline::PhysicsWorld;

/// A rapier impulse joint of a URDF robot: its bodies, free axes, limits and motors (SI).
pub(super) fn rapier_joint(name: &str, world: &PhysicsWorld, h: ImpulseJointHandle) -> String {
    let Some(j) = world.impulse_joints.get(h) else {
        return String::new();
    };
    let d = &j.data;
    let mut s = format!("\nrapier joint `{name}` (impulse joint, solved by rapier)\n");
    for (axis, label, unit, force) in [
        (JointAxis::LinX, "x", "m", "N"),
        (JointAxis::LinY, "y", "m", "N"),
        (JointAxis::LinZ, "z", "m", "N"),
        (JointAxis::AngX, "rx", "rad", "N·m"),
        (JointAxis::AngY, "ry", "rad", "N·m"),
        (JointAxis::AngZ, "rz", "rad", "N·m"),
    ] {
        if d.locked_axes.contains(axis.into()) {
            continue;
        }
        s += &format!("  {label} free");
        if let Some(l) = d.limits(axis) {
            s += &format!(
                ", limits [{}, {}] {unit}",
                fmt_num(l.min as f64),
                fmt_num(l.max as f64)
            );
        }
        if let Some(m) = d.motor(axis) {
            s += &format!(
                ", motor ({:?}) target {} {unit}, stiffness {} {force}/{unit}, damping {} \
                 {force}·s/{unit}, max force {} {force}",
                m.model,
                fmt_num(m.target_pos as f64),
                fmt_num(m.stiffness as f64),
                fmt_num(m.damping as f64),
                fmt_num(m.max_force as f64)
            );
        }
        s += "\n";
    }
    s
}

/// Every field of a property with its default applied and its unit (SI). Numbers in
/// exponent form when they are very large or small ([`fmt_num`]); curves with their points.
/// `written` is the property as its input wrote it, which says which values are defaults
/// (`(default)`): a deck's before its blank `ScF` became 10 of its work units in SI, else
/// `p` itself.
pub(super) fn property(p: &KjointProperty, written: &KjointProperty, indent: &str) -> String {
    let n = fmt_num;
    let mut s = String::new();
    let jt = p.joint_type;
    let free: Vec<Dof> = Dof::ALL.into_iter().filter(|d| jt.is_free(*d)).collect();
    let free_dofs = match free.as_slice() {
        [] => "none".to_string(),
        free => free.iter().map(|d| d.name()).collect::<Vec<_>>().join(", "),
    };
    s += &format!(
        "{indent}type {} ({}), free DOFs: {}\n",
        jt.number(),
        jt.name(),
        free_dofs
    );
    let default = |v: f64| if v == 0.0 { " (default)" } else { "" };
    if p.automatic_stiffness() {
        s += &format!("{indent}Kn = 0 N/m: automatic blocked stiffness from the substep\n");
        s += &format!(
            "{indent}ScF = {}{} (scales both automatic stiffnesses)\n",
            n(p.resolved_scale_factor()),
            default(written.scale_factor)
        );
    } else {
        s += &format!("{indent}Kn = {} N/m\n", n(p.kn));
        // (the lower bound of KR a zero-length joint gets: a kg-mm-ms deck with ScF left
        // blank has KR = 0.1 N·m/rad, which `check` showed only as the formula; an analyst's
        // trial, 2026-12-04)
        s += &format!(
            "{indent}ScF = {} m²{} (KR = Kn·max(ScF, L0²) ≥ {} N·m/rad)\n",
            n(p.resolved_scale_factor()),
            default(written.scale_factor),
            n(p.kn * p.resolved_scale_factor())
        );
    }
    s += &format!(
        "{indent}Cr = {}{}\n",
        n(p.resolved_critical_damping()),
        default(written.critical_damping)
    );
    s += &format!(
        "{indent}sensor: {}\n",
        p.sensor.map_or("none".to_string(), |id| id.to_string())
    );
    for d in free {
        s += &dof(p, d, indent);
    }
    s
}

/// The law of free DOF `d` of `p`: its stops' stiffness, its stiffness, stops, viscosity
/// and friction, with their curves.
fn dof(p: &KjointProperty, d: Dof, indent: &str) -> String {
    let n = fmt_num;
    let mut s = String::new();
    let law = p.dof(d);
    let (k, l, v, c, f, sm, sp, ff) = if d.is_rotation() {
        (
            "N·m/rad",
            "rad",
            "rad/s",
            "N·m·s/rad",
            "N·m",
            "SA-",
            "SA+",
            "FM",
        )
    } else {
        ("N/m", "m", "m/s", "N·s/m", "N", "SD-", "SD+", "FF")
    };
    // a curve's points, abscissa unit and ordinate unit (the ordinate is scaled)
    let curve = |c: &Option<rapier_kjoint::Curve>, x: &str, y: &str| match c {
        Some(c) => format!(
            " x curve [{}] ({x}, {y})",
            c.points()
                .map(|(px, py)| format!("({}, {})", n(px), n(py)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        None => String::new(),
    };
    let stop = |v: f64| {
        if v == 0.0 {
            "none".to_string()
        } else {
            format!("{} {l}", n(v))
        }
    };
    if law.has_stops() {
        let by = if law.friction_active() {
            format!(
                "the friction spring Kf = {} {k} (friction active: its cap is lifted \
                 beyond a stop)",
                n(law.friction_stiffness)
            )
        } else if law.friction_stiffness > 0.0 {
            format!("Kf = {} {k}", n(law.friction_stiffness))
        } else if p.automatic_stiffness() {
            "the automatic blocked stiffness".to_string()
        } else if d.is_rotation() {
            "KR = Kn·max(ScF, L0²)".to_string()
        } else {
            format!("Kn = {} N/m", n(p.kn))
        };
        s += &format!("{indent}{} stop stiffness: {by}\n", d.name());
    }
    let (curve_k, curve_c, curve_f) = (
        curve(&law.stiffness_curve, l, f),
        curve(&law.viscosity_curve, v, f),
        curve(&law.friction_curve, l, f),
    );
    // a value on a curve is its dimensionless scale; alone, the law's constant in its unit
    let unit = |curve: &str, unit: &'static str| if curve.is_empty() { unit } else { "(scale)" };
    let (k_unit, c_unit, f_unit) = (unit(&curve_k, k), unit(&curve_c, c), unit(&curve_f, f));
    s += &format!(
        "{indent}{}: K = {} {k_unit}{curve_k}; {sm} = {}, {sp} = {}, Icomb = {}; C = {} \
         {c_unit}{curve_c}; Kf = {} {k}, {ff} = {} {f_unit}{curve_f}{}\n",
        d.name(),
        n(law.stiffness_scale()),
        stop(law.stop_min),
        stop(law.stop_max),
        u8::from(law.coupled_stops),
        n(law.viscosity_scale()),
        n(law.friction_stiffness),
        n(law.friction_scale()),
        if law.friction_active() {
            String::new()
        } else {
            format!(" (friction inactive: needs Kf > 0 and {ff} > 0 or a curve)")
        }
    );
    s
}

/// The connector law of a joint, in SI (nothing for none).
pub(super) fn connector(law: &ConnectorLaw, indent: &str) -> String {
    let pts = |c: &rapier_kjoint::Curve| {
        c.points()
            .map(|(x, y)| format!("({} rad, {} N·m)", fmt_num(x), fmt_num(y)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    match law {
        ConnectorLaw::None => String::new(),
        ConnectorLaw::PlanarFriction(p) => {
            let auto = |k: f64, unit: &str, blocked: &str| {
                if k > 0.0 {
                    format!("{} {unit}", fmt_num(k))
                } else {
                    format!("automatic ({blocked})")
                }
            };
            format!(
                "{indent}planar friction: mu = {}, R = {} m, F_int = {} N, M_int = {} N·m, \
                 Kf = {}, Kr = {}\n",
                fmt_num(p.mu),
                fmt_num(p.radius),
                fmt_num(p.internal_force),
                fmt_num(p.internal_moment),
                auto(p.stick_stiffness, "N/m", "the automatic KX of the substep"),
                auto(
                    p.stick_rotational_stiffness,
                    "N·m/rad",
                    "the automatic KR of the substep"
                ),
            )
        }
        ConnectorLaw::JointFriction(j) => {
            let auto = |k: f64, unit: &str| {
                if k > 0.0 {
                    format!("{} {unit}", fmt_num(k))
                } else {
                    "automatic".to_string()
                }
            };
            format!(
                "{indent}joint friction: mu = {}, R_pin = {} m, L = {} m, R_thrust = {} m, \
                 F_pre = {} N, Kf = {}, Kr = {}\n",
                fmt_num(j.mu),
                fmt_num(j.pin_radius),
                fmt_num(j.length),
                fmt_num(j.thrust_radius),
                fmt_num(j.preload),
                auto(j.stick_stiffness, "N/m"),
                auto(j.stick_rotational_stiffness, "N·m/rad"),
            )
        }
        ConnectorLaw::FlexJoint(f) => {
            let mode = match f.law.mode() {
                FlexMode::Classical => "classical (law of the total angle)",
                FlexMode::Decoupled => "decoupled bending and torsion",
                FlexMode::Dynamic if f.law.bending.is_some() => {
                    "quasi-static bending (IPRO), then dynamic bilinear hysteretic"
                }
                // (IPRO = 0: the hysteretic law acts in both phases, docs/flex_joint.md §4)
                FlexMode::Dynamic => {
                    "bilinear hysteretic bending, restarted from the state reached at the switch"
                }
            };
            let mut s = format!("{indent}flex joint: {mode}\n");
            if let Some(c) = &f.law.bending {
                s += &format!("{indent}  bending law (IPRO): {}\n", pts(c));
            }
            if let Some(c) = &f.law.torsion {
                s += &format!("{indent}  torsion law (IPROT): {}\n", pts(c));
            }
            if let Some(d) = &f.law.dynamic {
                // Ktor is read only without a torsion law (docs/flex_joint.md §2)
                let ignored = if f.law.torsion.is_some() {
                    " (ignored: the torsion law IPROT)"
                } else {
                    ""
                };
                s += &format!(
                    "{indent}  *FLEXPROADD: Ktor = {} N·m/rad{ignored}, Kdyn_ini = {} N·m/rad, \
                     Kdyn_lim = {} N·m/rad, Angle_lim = {} rad, CP = {} N·m·s/rad \
                     (yield moment {} N·m)\n",
                    fmt_num(d.torsion_stiffness),
                    fmt_num(d.kdyn_ini),
                    fmt_num(d.kdyn_lim),
                    fmt_num(d.angle_lim),
                    fmt_num(d.torsion_damping),
                    fmt_num(d.yield_moment())
                );
            }
            s += &format!(
                "{indent}  switch to dynamic: {}\n",
                f.switch_time
                    .map_or("none (only by an explicit call)".to_string(), |t| format!(
                        "at {t} s"
                    ))
            );
            s
        }
    }
}
