//! Health checks of a run, cheap enough to stay on (a few comparisons per joint and
//! substep), on what each joint measured at the start of the substep:
//!
//! - **At the start** (and after every topology change), a [`Severity::Notice`] for every
//!   free DOF whose spring or stop the substep cannot resolve: `ω = √(K·W) > 1/h` with `W`
//!   the DOF's own effective inverse mass. Such a DOF is held by the implicit update and its
//!   oscillation is damped numerically; the notice names the joint, the DOF and the substep
//!   count per frame that would resolve it. Blocked DOFs are unresolved by design (that is
//!   what holds them) and get no notice.
//! - A [`Severity::Warning`], once per joint and kind, when the anchors separate along the
//!   blocked translations by more than [`GAP_WARNING`] of the joint's size (the lever arms
//!   from the dynamic bodies' centres of mass to the anchors, at least [`MIN_SIZE`]) and at
//!   least [`GAP_FLOOR`]; when a blocked rotation exceeds [`ROTATION_WARNING`]; when a stop
//!   is overrun by more than [`STOP_WARNING`] (rad, or that fraction of the size for a
//!   translation).
//! - An error ([`SimError::Unstable`]) naming the joint and remedies as soon as the anchors
//!   are more than [`GAP_ERROR`] of the joint's size apart, or a blocked rotation exceeds
//!   [`ROTATION_ERROR`], **and** the separation is more than [`UNEXPLAINED`] times what the
//!   force the joint transmits explains through its blocked stiffness (`|F|/K`): the joint
//!   no longer holds as its law says and the run is stopped. A soft penalty joint (a Radioss
//!   deck's automatic stiffness) that stretches under its load as its stiffness says is not
//!   unstable, however far it stretches; it gets the warning.

use super::event::{EventSource, KjointEvent, Severity};
use super::joint::Kjoint;
use crate::error::SimError;
use crate::figure::format_figure as fig;
use crate::law::Dof;
use nalgebra::Vector6;

/// Smallest size \[m\] a joint is given (a ball joint at a body's centre of mass).
pub const MIN_SIZE: f64 = 0.01;
/// Separation of the anchors, as a fraction of the joint's size, that gives a warning.
pub const GAP_WARNING: f64 = 0.02;
/// Separation \[m\] below which no warning is given, whatever the size.
pub const GAP_FLOOR: f64 = 1e-3;
/// Separation, as a fraction of the joint's size, at which the run is stopped as unstable.
pub const GAP_ERROR: f64 = 0.5;
/// Blocked rotation \[rad\] that gives a warning.
pub const ROTATION_WARNING: f64 = 0.02;
/// Blocked rotation \[rad\] at which the run is stopped as unstable.
pub const ROTATION_ERROR: f64 = 0.5;
/// How many times the deflection `|F|/K` its transmitted force explains a separation must
/// be for the run to be stopped as unstable.
pub const UNEXPLAINED: f64 = 10.0;
/// Overrun of a stop that gives a warning: rad, or this fraction of the size for a
/// translation.
pub const STOP_WARNING: f64 = 0.05;

const WARNED_GAP: u8 = 1;
const WARNED_ROTATION: u8 = 2;
const WARNED_STOP: u8 = 4;

fn source(j: &Kjoint, _index: usize) -> EventSource {
    EventSource::Joint {
        handle: j.handle,
        name: j.name.clone(),
    }
}

const REMEDY: &str = "more substeps (a shorter substep), a smaller frame time step, or \
     lighter loads";

/// The start notices of joint `j` (index `index`) for substep `h`, `w` the diagonal of its
/// own `J·M⁻¹·Jᵀ`.
pub(crate) fn start_notices(
    j: &Kjoint,
    index: usize,
    w: &Vector6<f64>,
    h: f64,
    substeps: usize,
    time: f64,
    events: &mut Vec<KjointEvent>,
) {
    let Some(blocked) = j.blocked else { return };
    for d in Dof::ALL {
        if !j.property.joint_type.is_free(d) {
            continue;
        }
        let law = j.property.dof(d);
        let i = d.index();
        let mut parts = Vec::new();
        let k = law.stiffness_scale();
        if k > 0.0 {
            parts.push(("spring", k));
        }
        if law.has_stops() {
            let ks = if law.friction_stiffness > 0.0 {
                law.friction_stiffness
            } else {
                blocked.of(d)
            };
            parts.push(("stop", ks));
        }
        for (what, k) in parts {
            let omega = (k * w[i]).max(0.0).sqrt();
            if omega * h > 1.0 {
                let unit = if d.is_rotation() { "N·m/rad" } else { "N/m" };
                let needed = (omega * h * substeps as f64).ceil();
                events.push(KjointEvent {
                    severity: Severity::Notice,
                    source: source(j, index),
                    time,
                    reason: format!(
                        "{} {what} ({} {unit}) oscillates at {} rad/s, beyond \
                         the substep (ω·h = {:.2}): it is held by the implicit update and its \
                         oscillation damped; {needed} substeps per frame would resolve it",
                        d.name(),
                        fig(k),
                        fig(omega),
                        omega * h
                    ),
                });
            }
        }
    }
}

/// The separation `|q_t|` \[m\] of the blocked translations and the largest blocked
/// rotation `max |q_r|` \[rad\] of a joint of type `ty` at `q`.
fn blocked_motion(ty: crate::law::JointType, q: &[f64; 6]) -> (f64, f64) {
    let mut gap2 = 0.0;
    let mut rot = 0.0f64;
    for d in Dof::ALL {
        if ty.is_free(d) {
            continue;
        }
        let v = q[d.index()];
        if d.is_rotation() {
            rot = rot.max(v.abs());
        } else {
            gap2 += v * v;
        }
    }
    (gap2.sqrt(), rot)
}

/// The first free DOF of `property` at `q` beyond one of its stops by more than the warning
/// bound ([`STOP_WARNING`] rad, or that fraction of `size` for a translation), and by how
/// much.
fn stop_overrun(
    property: &crate::law::KjointProperty,
    q: &[f64; 6],
    size: f64,
) -> Option<(Dof, f64)> {
    for d in Dof::ALL {
        if !property.joint_type.is_free(d) {
            continue;
        }
        let law = property.dof(d);
        let v = q[d.index()];
        let over = if law.stop_max > 0.0 && v > law.stop_max {
            v - law.stop_max
        } else if law.stop_min < 0.0 && v < law.stop_min {
            law.stop_min - v
        } else {
            0.0
        };
        let bound = if d.is_rotation() {
            STOP_WARNING
        } else {
            STOP_WARNING * size
        };
        if over > bound {
            return Some((d, over));
        }
    }
    None
}

/// Whether [`check`] can find anything on a joint that measured `q` and has size `size`: a
/// blocked separation or rotation beyond the lower of its warning and error bounds, or a
/// stop overrun beyond its bound. Evaluated in the prepare stage, while the joint's data
/// is in cache, so that the store stage reads a healthy joint's readout and property again
/// only when this says so (at 10 000 joints those reads were 9 % of the frame).
pub(crate) fn suspect(property: &crate::law::KjointProperty, q: &[f64; 6], size: f64) -> bool {
    let (gap, rot) = blocked_motion(property.joint_type, q);
    gap > GAP_WARNING.min(GAP_ERROR) * size
        || rot > ROTATION_WARNING.min(ROTATION_ERROR)
        || stop_overrun(property, q, size).is_some()
}

/// The checks of joint `j` on its last readout (see the module docs).
pub(crate) fn check(
    j: &mut Kjoint,
    index: usize,
    size: f64,
    time: f64,
    events: &mut Vec<KjointEvent>,
) -> Result<(), SimError> {
    let Some(state) = j.state.as_ref() else {
        return Ok(());
    };
    let ty = j.property.joint_type;
    let (gap, rot) = blocked_motion(ty, &state.q);
    // what the transmitted force explains through the blocked stiffness
    let (mut f2, mut moment) = (0.0, 0.0f64);
    for d in Dof::ALL {
        if !ty.is_free(d) {
            let f = state.applied[d.index()];
            if d.is_rotation() {
                moment = moment.max(f.abs());
            } else {
                f2 += f * f;
            }
        }
    }
    let Some(k) = j.blocked else {
        return Ok(());
    };
    let explained = |x: f64, k: f64| if k > 0.0 { x / k } else { f64::INFINITY };
    let gap_unstable =
        gap > GAP_ERROR * size && gap > UNEXPLAINED * explained(f2.sqrt(), k.translational);
    let rot_unstable = rot > ROTATION_ERROR && rot > UNEXPLAINED * explained(moment, k.rotational);
    if gap_unstable || rot_unstable {
        let what = if gap_unstable {
            format!(
                "anchors {} m apart, more than half of the joint's size {} m",
                fig(gap),
                fig(size)
            )
        } else {
            format!("a blocked rotation of {rot:.3} rad")
        };
        return Err(SimError::Unstable {
            time,
            reason: format!(
                "joint `{}`: {what}: the joint no longer holds and the run is unstable; \
                 remedies: {REMEDY}",
                j.name
            ),
        });
    }
    let mut warn = |bit: u8, text: String, warned: &mut u8| {
        if *warned & bit == 0 {
            *warned |= bit;
            events.push(KjointEvent {
                severity: Severity::Warning,
                source: source(j, index),
                time,
                reason: text,
            });
        }
    };
    let mut warned = j.warned;
    // a separation the blocked stiffness explains under the transmitted load is a soft joint
    // (a larger Kn holds it); one it does not explain is dynamics the substep misses
    let remedy = |x: f64, explained: f64, k: f64, unit: &str| {
        if x <= 2.0 * explained {
            format!(
                "the blocked stiffness {} {unit} gives it under the joint's load: set a \
                 larger Kn to hold the joint closer",
                fig(k)
            )
        } else {
            format!("remedies: {REMEDY}")
        }
    };
    if gap > (GAP_WARNING * size).max(GAP_FLOOR) {
        let advice = remedy(
            gap,
            explained(f2.sqrt(), k.translational),
            k.translational,
            "N/m",
        );
        warn(
            WARNED_GAP,
            format!(
                "anchors {} m apart ({:.1} % of the joint's size {} m); {advice}",
                fig(gap),
                100.0 * gap / size,
                fig(size)
            ),
            &mut warned,
        );
    }
    if rot > ROTATION_WARNING {
        let advice = remedy(
            rot,
            explained(moment, k.rotational),
            k.rotational,
            "N·m/rad",
        );
        warn(
            WARNED_ROTATION,
            format!("a blocked rotation of {} rad; {advice}", fig(rot)),
            &mut warned,
        );
    }
    if let Some((d, over)) = stop_overrun(&j.property, &state.q, size) {
        let unit = if d.is_rotation() { "rad" } else { "m" };
        warn(
            WARNED_STOP,
            format!(
                "{} overruns its stop by {} {unit}; remedies: a stiffer stop \
                 (friction stiffness Kf or Kn), more substeps",
                d.name(),
                fig(over)
            ),
            &mut warned,
        );
    }
    j.warned = warned;
    Ok(())
}
