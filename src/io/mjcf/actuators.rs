//! MJCF `<position>`, `<velocity>` and `<motor>` actuators on hinges and slides as KJOINT2
//! motors ([`crate::KjointMotor`]), at the control the model starts with.
//!
//! MuJoCo's actuator of gear `g` on a joint `q` has the length `l = g·q` and the rate
//! `l̇ = g·q̇`; its force `f` acts on the joint as `τ = g·f`.
//!
//! * `<position kp kv>`: `f = kp·(u − l) − kv·l̇`, so `τ = g²·kp·(u/g − q) − g²·kv·q̇`: a
//!   motor towards `q* = u/g` of stiffness `g²·kp` and damping `g²·kv` (`kp` 1 and `kv` 0
//!   by default, as MuJoCo's).
//! * `<velocity kv>`: `f = kv·(u − l̇)`, so `τ = g²·kv·(u/g − q̇)`: a motor towards `q̇* = u/g`
//!   of damping `g²·kv`.
//! * `<motor>`: `f = u`, so `τ = g·u`: a motor of constant force `g·u`
//!   ([`crate::KjointMotor::force`]), capped at `|g|·max(|u_lo|, |u_hi|)` where the control
//!   is limited (MuJoCo clamps `u` into `ctrlrange`); a program sets the torque with
//!   [`crate::UrdfRobotHandles::set_motor_force`] (`g·u`, as a `τ` of the joint).
//!
//! * `<general>` of a fixed gain and no activation dynamics (`gaintype="fixed"`,
//!   `dyntype="none"`, the defaults), its bias none or affine: `f = gain·u + b0 + b1·l +
//!   b2·l̇` (`gain = gainprm[0]`, `b = biasprm`), so `τ = g·(gain·u + b0) − g²·(−b1)·q −
//!   g²·(−b2)·q̇`. With `b1 < 0`: a motor of stiffness `−g²·b1` and damping `−g²·b2`
//!   towards `q* = (gain·u + b0)/(−g·b1)` (MuJoCo Menagerie's servos, `gainprm="kp"
//!   biasprm="0 -kp -kv"`: `<position>`'s); else with `b2 < 0`: a motor of damping
//!   `−g²·b2` towards `q̇* = (gain·u + b0)/(−g·b2)`; else a constant force `g·(gain·u +
//!   b0)`, capped where the control is limited at its largest over `ctrlrange`. A bias
//!   that pushes away from its target (`b1 > 0` or `b2 > 0`) is refused.
//!
//! `u` is the control at the start (the `ctrl` of the keyframe [`crate::io::urdf::UrdfOptions::keyframe`]
//! names where it gives one, else 0), clamped into `ctrlrange` where the control is limited
//! (`ctrllimited`, or `auto` with `autolimits`); a program moves it with
//! [`crate::UrdfRobotHandles::set_motor_target`] (a `q` of the file, `u/g`). A limited
//! force (`forcerange`) caps `|τ|` at `|g|·max(|f_lo|, |f_hi|)` (an asymmetric range with
//! a notice). The targets are `q`s of the file: the KJOINT2 joint measures `q − q0` from its
//! position at insertion `q0` ([`crate::io::robot::RobotJoint::initial_position`], `ref`
//! included), and its motor is driven to `q* − q0`.
//!
//! Not mapped (a notice each kind): `<general>` of another gain, bias or activation
//! dynamics (`gaintype="affine"` or `"muscle"`, `dyntype="filter"`, ...), `<intvelocity>`,
//! `<damper>` (0 at `u = 0`), actuators of tendons, sites or bodies, and a second actuator
//! on a joint.

use crate::law::KjointMotor;
use rapier3d_mjcf::mjcf_rs::extras::{Actuator, ActuatorKind};
use rapier3d_mjcf::mjcf_rs::model::Model;
use std::collections::HashMap;

/// The motors of a model's actuators that can be mapped, by joint name, and a notice for
/// each kind of the others.
#[derive(Debug, Default)]
pub(super) struct Actuators<'a> {
    /// The mapped actuator of each joint, with its control at the start (before the clamp
    /// into its range).
    by_joint: HashMap<&'a str, (&'a Actuator, f64)>,
    /// What is not mapped, a notice each.
    pub notices: Vec<String>,
}

impl<'a> Actuators<'a> {
    /// Sorts out the model's actuators; `ctrl`: the controls at the start, one per actuator
    /// in the model's order (a keyframe's, checked for its length), or none (all 0).
    pub fn of(model: &'a Model, ctrl: &[f64]) -> Self {
        let mut a = Actuators::default();
        let mut skipped: Vec<(&str, String)> = Vec::new();
        for (k, act) in model.actuators.iter().enumerate() {
            let label = act.name.clone().unwrap_or_else(|| format!("actuator {k}"));
            let mapped = match act.kind {
                ActuatorKind::Position | ActuatorKind::Velocity | ActuatorKind::Motor => true,
                ActuatorKind::General => general_law(act).is_some(),
                _ => false,
            };
            let why = match (mapped, act.joint.as_deref()) {
                (true, Some(j)) => {
                    if a.by_joint.contains_key(j) {
                        Some("a second actuator on the same joint")
                    } else if !(act.gear[0].is_finite() && act.gear[0] != 0.0) {
                        Some("a gear of 0 or not finite")
                    } else {
                        a.by_joint
                            .insert(j, (act, ctrl.get(k).copied().unwrap_or(0.0)));
                        None
                    }
                }
                (true, None) => Some("not on a joint (a tendon, site or body)"),
                _ if act.kind == ActuatorKind::General => Some(
                    "a <general> of another gain, bias or activation dynamics than a fixed \
                     gain, an affine bias and none",
                ),
                _ => Some("an <intvelocity>, <damper> or other kind"),
            };
            if let Some(why) = why {
                skipped.push((why, label));
            }
        }
        let mut kinds: Vec<&str> = skipped.iter().map(|(w, _)| *w).collect();
        kinds.dedup();
        kinds.sort_unstable();
        kinds.dedup();
        for kind in kinds {
            let names: Vec<&str> = (skipped.iter())
                .filter(|(w, _)| *w == kind)
                .map(|(_, n)| n.as_str())
                .collect();
            a.notices.push(format!(
                "{} actuator(s) not mapped, {kind}: {}",
                names.len(),
                names.join(", ")
            ));
        }
        a
    }

    /// Whether an actuator that could be mapped drives the joint `name`.
    pub fn drives(&self, name: &str) -> bool {
        self.by_joint.contains_key(name)
    }

    /// The motor of the actuator on the joint `name` (a hinge or slide standing at `q0` at
    /// insertion, [rad or m]), with a notice where its force range is asymmetric; `None`
    /// without one; an error (what was expected) for settings a motor refuses (a negative
    /// `kp`, say).
    pub fn motor(
        &self,
        model: &Model,
        name: &str,
        q0: f64,
        notices: &mut Vec<String>,
    ) -> Result<Option<KjointMotor>, String> {
        let Some(&(act, start)) = self.by_joint.get(name) else {
            return Ok(None);
        };
        let g = act.gear[0];
        let autolimits = model.compiler.autolimits;
        let ctrl_range = act
            .ctrl_range
            .filter(|_| act.ctrl_limited.resolve(autolimits, true));
        let ctrl = ctrl_range.map_or(start, |[lo, hi]| start.clamp(lo, hi));
        let target = ctrl / g;
        let mut motor = match act.kind {
            ActuatorKind::Position => {
                let (kp, kv) = (act.kp.unwrap_or(1.0), act.kv.unwrap_or(0.0));
                KjointMotor::position(target - q0, g * g * kp, g * g * kv)
            }
            ActuatorKind::Motor => {
                let motor = KjointMotor::force(g * ctrl);
                match ctrl_range {
                    Some([lo, hi]) => motor.max_force(g.abs() * lo.abs().max(hi.abs())),
                    None => motor,
                }
            }
            ActuatorKind::General => general_motor(act, g, ctrl, ctrl_range, q0)?,
            _ => KjointMotor::velocity(target, g * g * act.kv.unwrap_or(1.0)),
        };
        if let Some([lo, hi]) = act.force_range {
            if act.force_limited.resolve(autolimits, true) {
                let cap = lo.abs().max(hi.abs());
                if lo != -hi {
                    notices.push(format!(
                        "actuator on joint `{name}`: forcerange [{lo}, {hi}] is not symmetric: \
                         the motor is capped at ±{cap} (times the gear)"
                    ));
                }
                motor = motor.max_force(motor.max_force.min(g.abs() * cap));
            }
        }
        motor.validate().map_err(|e| {
            format!("an actuator this crate can map (gear {g}, kp, kv, ctrlrange, forcerange): {e}")
        })?;
        Ok(Some(motor))
    }
}

/// The force law `f = gain·u + b0 + b1·l + b2·l̇` of a `<general>` actuator this crate maps
/// (a fixed gain, a bias none or affine, no activation dynamics), as `(gain, [b0, b1,
/// b2])`; `None` for the others. MuJoCo's defaults: `gainprm` 1 0 …, `biasprm` 0 ….
fn general_law(act: &Actuator) -> Option<(f64, [f64; 3])> {
    let is = |v: &Option<String>, names: &[&str]| v.as_deref().is_none_or(|v| names.contains(&v));
    if !(is(&act.gain_type, &["fixed"])
        && is(&act.bias_type, &["none", "affine"])
        && is(&act.dyn_type, &["none"]))
    {
        return None;
    }
    let gain = act.gainprm.first().copied().unwrap_or(1.0);
    let affine = act.bias_type.as_deref() == Some("affine");
    let b = |i: usize| {
        if affine {
            act.biasprm.get(i).copied().unwrap_or(0.0)
        } else {
            0.0
        }
    };
    Some((gain, [b(0), b(1), b(2)]))
}

/// The motor of a `<general>` actuator of gear `g` at the control `ctrl` (module docs): a
/// servo towards a position where its bias has a position term, towards a velocity where
/// it has only a rate term, else a constant force.
fn general_motor(
    act: &Actuator,
    g: f64,
    ctrl: f64,
    ctrl_range: Option<[f64; 2]>,
    q0: f64,
) -> Result<KjointMotor, String> {
    let (gain, [b0, b1, b2]) =
        general_law(act).ok_or("a <general> actuator of a fixed gain and an affine bias")?;
    if b1 > 0.0 || b2 > 0.0 {
        return Err(format!(
            "a <general> actuator whose bias pulls towards its target: biasprm[1] and \
             biasprm[2] <= 0 (here {b1} and {b2})"
        ));
    }
    // the part of the force that does not depend on the joint's motion
    let drive = gain * ctrl + b0;
    Ok(if b1 < 0.0 {
        KjointMotor::position(drive / (-g * b1) - q0, -g * g * b1, -g * g * b2)
    } else if b2 < 0.0 {
        KjointMotor::velocity(drive / (-g * b2), -g * g * b2)
    } else {
        let motor = KjointMotor::force(g * drive);
        match ctrl_range {
            Some([lo, hi]) => {
                let most = (gain * lo + b0).abs().max((gain * hi + b0).abs());
                motor.max_force(g.abs() * most)
            }
            None => motor,
        }
    })
}
