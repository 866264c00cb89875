//! Health checks of a run, cheap enough to stay on (a few comparisons per joint and
//! substep), on what each joint measured at the start of the substep:
//!
//! - **At the start** (and after every topology change), a [`Severity::Notice`](super::Severity::Notice) for every
//!   free DOF whose spring, stop, friction spring or connector law (a flex joint's bending
//!   or torsion) the substep cannot resolve: `ω = √(K·W) > 1/h` with `W`
//!   the DOF's own effective inverse mass; where none is unresolved alone, for their sum,
//!   the DOF's tangent while they act at once (a spring beside a sticking friction spring),
//!   which is what the numerical damping judges. Such a DOF is held by the implicit update and its
//!   oscillation is damped numerically; the notice names the joint, the DOF and the substep
//!   count per frame that would resolve it. Blocked DOFs are unresolved by design (that is
//!   what holds them) and get no notice, nor does a stop without a friction spring, which
//!   holds at the blocked stiffness.
//! - **At the start** (and after every topology change), a notice for a joint of automatic
//!   stiffness so far from the origin that the f32 rounding of its poses over a substep
//!   squared, `ε·r/h²`, exceeds the load acceleration its stiffness is sized for
//!   ([`FAR_FROM_ORIGIN`], [`KjointEventKind::StiffnessLoweredFarFromOrigin`]): its
//!   distance from the origin, the stiffness it got, the rounding the force it transmits
//!   carries, and the remedies (a model near the origin, the `f64` feature, fewer
//!   substeps).
//! - A [`Severity::Warning`](super::Severity::Warning), once per joint and kind (and again
//!   whenever the value grows [`WARNING_GROWTH`]-fold over the last one given), when the anchors separate along the
//!   blocked translations by more than [`GAP_WARNING`] of the joint's size and at least
//!   [`GAP_FLOOR`]; when a blocked rotation exceeds [`ROTATION_WARNING`]; when a stop
//!   is overrun by more than [`STOP_WARNING`] (rad, or for a translation that fraction of
//!   the size or of the stop's travel, the larger).
//! - An error ([`SimError::Unstable`]) naming the joint and remedies as soon as the anchors
//!   are more than [`GAP_ERROR`] of the joint's size apart, or a blocked rotation exceeds
//!   [`ROTATION_ERROR`], **and** the separation is more than [`UNEXPLAINED`] times what the
//!   force the joint transmits explains through its blocked stiffness (`|F|/K`): the joint
//!   no longer holds as its law says and the run is stopped, once the substep is complete
//!   (the world as at the end of any substep: a failed step no longer left the impulses in
//!   the velocities without advancing, which every retry pumped further, a teleported head
//!   38 → 52 → 58 m/s with the time held, a game developer's trial of 2026-12-05). With
//!   [`OnUnstable::Warn`] the run goes on with a [`KjointEventKind::NoLongerHolds`] warning
//!   instead (naming the load on each opening, the blocked stiffness it meets and the
//!   deflection they account for, as the error does), the joint pulling its bodies back;
//!   so it does, whatever the setting, where
//!   rapier's contacts pushed a body of the joint during its excursion beyond the warning
//!   bounds (they act after the joints are solved in each substep), unless the opening
//!   grows fourfold or stays beyond the bounds longer than a push's does
//!   ([`contact_credit_span`]: 16 substeps, at least 0.05 s). A soft penalty joint of
//!   explicit stiffness (`Kn > 0`, the user's choice) that stretches under its load as its stiffness says is not unstable, however
//!   far it stretches; it gets the warning. One of **automatic** stiffness (`Kn = 0`) is:
//!   the set's rule chose that stiffness to hold the joint, and an opening beyond the error
//!   bounds that its load explains says the substep is too long for the load (the rule's
//!   stiffness goes as `1/h²`; a 20 t chassis on 5 kg hubs at one substep of 0.05 s ran on
//!   with its axles 4.6 m apart and exited 0, a vehicle developer's trial of 2026-12-06):
//!   the error then names the load and the stiffness it met, for each opening beyond the
//!   bounds that its own load explains (the gap through its force and `Kn`, the rotation
//!   through its moment and `KR`, both where both are). Such an opening under a
//!   contact keeps the contact's credit (stopped when it grows fourfold or stays): a
//!   push's implicit pull-back `K·q/(1 + κ)` is as explained by the load, and what tells
//!   them apart is that a push's opening comes back.
//!
//! The joint's **size** is a property of the joint, not of its motion: the sum of the lever
//! arms from each dynamic body's centre of mass to its own anchor (fixed in the body), each
//! at least the body's largest radius of gyration `√(I_max/m)` (a hinge through a body's
//! centre of mass is judged on the body's extent), the sum at least the initial length `L0`
//! and [`MIN_SIZE`]; a fixed or kinematic side adds nothing.
//! It is computed once at each analysis of the set's topology (an insertion, a removal, a
//! body switched between dynamic and fixed), not per substep. A rod of 1 m pinned at its end
//! has the size 0.5 m however far its anchors part (it was measured from the anchors'
//! current mid-point, and grew with the gap it was to judge).

use super::event::{
    DofStiffness, EventSource, HealthRemedy, KjointEvent, KjointEventKind, StopRemedy,
    CONTACT_OPENS, REMEDY, TELEPORT,
};
use super::joint::Kjoint;
use crate::error::SimError;
use crate::figure::format_figure as fig;
use crate::kinematics::BodyPose;
use crate::law::flex_joint::FlexMode;
use crate::law::stiffness::NoiseBound;
use crate::law::ConnectorLaw;
use crate::law::Dof;
use nalgebra::{UnitQuaternion, Vector3, Vector6};

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
/// Overrun of a stop that gives a warning: rad, or for a translation this fraction of the
/// joint's size or of the stop's distance from the joint's zero, the larger (the stop's
/// travel is the scale of a slider on small bodies anchored at their centres of mass).
pub const STOP_WARNING: f64 = 0.05;
/// How large the f32 rounding `ε·r` of a joint's poses, over a substep squared, must be
/// against the load acceleration its automatic stiffness is sized for
/// ([`crate::law::stiffness::LOAD_ACCELERATION`]), `ε·r/(a·h²)`, for its distance from the
/// origin to be noticed at the start (60 Hz × 4 substeps: from 1.4 km; × 16: from 89 m).
/// The noise bound holds such a joint at its floor `κ = 4`
/// ([`crate::law::stiffness::IMPLICIT_KAPPA_FLOOR`]), where it holds as near the origin,
/// but the force it transmits carries the rounding: a 1 kg ball swinging on a spherical
/// joint, its force read against its tension, 3–7 % of `m·ε·r/h²` (s.d.): 1 km out, 3.1 N
/// on its 10 N at 16 substeps, 0.3 N at 4; 5 km out 20 N and 2.4 N (2026-12-05). A model
/// near the origin, the `f64` feature or fewer substeps take it out.
pub const FAR_FROM_ORIGIN: f64 = 1.0;

/// Change \[rad\] of a spherical or free joint's rotation vector over one substep beyond
/// which it is taken for the jump of a full turn about another axis
/// ([`KjointEventKind::RotationVectorJumped`]): a quarter turn, what two bodies turning
/// against each other at rapier's cap (`π/4` a substep each) reach. Near the full-turn
/// sphere `|θ| = 2π` the vector's components across its axis move faster than the
/// rotation, by `(|θ|/2)/sin(|θ|/2)` (3.3 at `|θ| = 1.5π`, without bound at 2π): a motion
/// that passes close to a full turn about a new axis may be warned of without crossing it,
/// where the laws on the rotations see that fast change all the same.
pub const ROTATION_JUMP: f64 = std::f64::consts::FRAC_PI_2;

/// Whether joint `j`'s rotation vector jumped at its last measure ([`ROTATION_JUMP`]) where
/// a law reads its free rotations and it was not yet warned of: for [`suspect`]'s caller.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn rotation_jumped(j: &Kjoint) -> bool {
    j.measure.jump_squared() > ROTATION_JUMP * ROTATION_JUMP && !j.warned_jump && reads_rotations(j)
}

/// Whether a law reads a free rotation of joint `j` (its angle, not only its rate): a
/// spring, stops, an active friction spring, a motor or a connector law's stiffness.
fn reads_rotations(j: &Kjoint) -> bool {
    let free = j.property.joint_type.free_dofs();
    [Dof::Rx, Dof::Ry, Dof::Rz].into_iter().any(|d| {
        let law = j.property.dof(d);
        free[d.index()]
            && (law.stiffness != 0.0
                || law.stiffness_curve.is_some()
                || law.has_stops()
                || law.coupled_stops
                || law.friction_active()
                || j.motor(d).is_some()
                || j.connector.law().dof_stiffness()[d.index()] > 0.0)
    })
}

/// How many times the value a warning of a kind was last given at the same joint's value
/// must grow for that warning to be given again: a neck that warned at a 12.5 mm gap and
/// opened to 146 mm later said nothing more (a user reads the first warning as the size of
/// the trouble). A few per kind: a gap growing from the 1 mm floor to 1 m is warned of five
/// times (1, 4, 16, 64, 256 mm... each the first value above the last given times 4).
pub const WARNING_GROWTH: f64 = 4.0;

/// How long \[substeps\] an opening rapier's contacts made may stay beyond the unstable
/// bounds under `OnUnstable::Stop` before the run is stopped (or [`CONTACT_CREDIT_TIME`],
/// the longer): a push opens a joint for a few substeps, which it pulls back; an opening
/// that stays is a load the joint cannot hold. An A1 quadruped's calves, pushed by its feet
/// under random torques of ±33.5 N·m at 4 substeps, came back within 9 substeps (0.0375 s)
/// in 4 episodes of 3 s, a pendulum's pivot hit by a body within 7; a 20 t chassis's
/// axles on 5 kg hubs at 4 substeps of 12.5 ms stood open beyond the bounds for 0.5 s at a
/// time and for good from 2.6 s, warned, and the run exited 0 (a vehicle developer's trial
/// and its review, 2026-12-06).
pub const CONTACT_CREDIT_SUBSTEPS: f64 = 16.0;

/// The least time \[s\] a contact's opening may last ([`CONTACT_CREDIT_SUBSTEPS`]): at
/// many substeps an impact spans more of them.
pub const CONTACT_CREDIT_TIME: f64 = 0.05;

/// How long a contact's opening may last at a substep `h` \[s\]: the longer of
/// [`CONTACT_CREDIT_SUBSTEPS`] substeps and [`CONTACT_CREDIT_TIME`].
pub(crate) fn contact_credit_span(h: f64) -> f64 {
    (CONTACT_CREDIT_SUBSTEPS * h).max(CONTACT_CREDIT_TIME)
}

/// Why a contact's credit for an opening ended ([`unstable`]'s words).
#[derive(Debug, Clone, Copy, PartialEq)]
enum CreditEnded {
    /// The opening grew more than [`WARNING_GROWTH`]-fold since it was first beyond the
    /// bounds (`first`, in times the bounds).
    Grew { first: f64 },
    /// It stayed beyond the bounds `lasted` seconds, longer than `span`
    /// ([`contact_credit_span`]).
    Lasted { lasted: f64, span: f64 },
}

const WARNED_GAP: usize = 0;
const WARNED_ROTATION: usize = 1;
const WARNED_STOP: usize = 2;

fn source(j: &Kjoint, _index: usize) -> EventSource {
    EventSource::Joint {
        handle: j.handle,
        name: j.name.clone(),
    }
}

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
    let Some(k) = j.blocked else {
        return;
    };
    far_from_origin(j, index, k, time, events);
    for d in Dof::ALL {
        if !j.property.joint_type.is_free(d) {
            continue;
        }
        let law = j.property.dof(d);
        let i = d.index();
        let mut parts = Vec::new();
        // a curve's steepest slope times its scale, as the stable step counts it
        let k = law.stiffness_scale().abs()
            * law
                .stiffness_curve
                .as_ref()
                .map_or(1.0, |c| c.max_abs_slope());
        if k > 0.0 {
            parts.push((DofStiffness::Spring, k));
        }

        // a friction spring a robot loader chose by the implicit rule of the substep is,
        // like the blocked DOFs' automatic Kn, unresolved by design (it grows as 1/h²: the
        // notice gave every limited joint of a URDF arm with <dynamics friction> a substep
        // count at which it was stiffer still)
        let by_rule = j.friction_by_rule == Some(d);
        if law.has_stops() {
            // a stop without a friction spring holds at the blocked stiffness Kn/KR: in
            // contact the DOF is blocked, unresolved by design as the blocked DOFs are (an
            // automatic Kn grows as 1/h²: every limited joint of a URDF arm was noticed, with
            // a substep count at which its stop was stiffer still)
            if law.friction_stiffness > 0.0 && !by_rule {
                parts.push((DofStiffness::Stop, law.friction_stiffness));
            }
        } else if law.friction_active() && !by_rule {
            // while it sticks (with stops, the friction spring is the stop, above)
            parts.push((DofStiffness::Friction, law.friction_stiffness));
        }
        // the connector law's own stiffness on the DOF (a flex joint's bending, torsion)
        let kc = j.connector.law().dof_stiffness()[i];
        if kc > 0.0 {
            parts.push((DofStiffness::Connector, kc));
        }
        // the motor's stiffness, in the DOF's tangent as the others
        if let Some(m) = j.motor(d).filter(|m| m.stiffness > 0.0) {
            parts.push((DofStiffness::Motor, m.stiffness));
        }
        let omega = |k: f64| (k * w[i]).max(0.0).sqrt();
        let mut notice = |stiffness_of, k: f64| {
            let omega = omega(k);
            events.push(KjointEvent {
                source: source(j, index),
                time,
                kind: KjointEventKind::StiffnessBeyondSubstep {
                    dof: d,
                    stiffness_of,
                    stiffness: k,
                    omega,
                    substep: h,
                    substeps_needed: (omega * h * substeps as f64).ceil(),
                },
            });
        };
        let mut alone = false;
        for &(stiffness_of, k) in &parts {
            if omega(k) * h > 1.0 {
                notice(stiffness_of, k);
                alone = true;
            }
        }
        // The parts act at once (a spring in stop contact or beside a sticking friction
        // spring, a connector law under either: the friction spring is the stop where both
        // exist), and the numerical damping judges their sum, the DOF's tangent
        // (`solve::unresolved_damping`): a DOF none of whose parts is unresolved alone may
        // be unresolved with them together.
        let sum: f64 = parts.iter().map(|p| p.1).sum();
        if !alone && parts.len() > 1 && omega(sum) * h > 1.0 {
            let has = |s: DofStiffness| parts.iter().any(|p| p.0 == s);
            let together = DofStiffness::Together {
                spring: has(DofStiffness::Spring),
                stop: has(DofStiffness::Stop),
                friction: has(DofStiffness::Friction),
                connector: has(DofStiffness::Connector),
                motor: has(DofStiffness::Motor),
            };
            notice(together, sum);
        }
    }
}

/// The start notice of joint `j`, of blocked stiffness `k`, where the f32 rounding over a
/// substep squared is more than [`FAR_FROM_ORIGIN`] times the load acceleration.
fn far_from_origin(
    j: &Kjoint,
    index: usize,
    k: crate::law::BlockedStiffness,
    time: f64,
    events: &mut Vec<KjointEvent>,
) {
    let Some(bound) = j.noise_bound else {
        return;
    };
    let rounding = bound.deflection_noise() / (bound.substep * bound.substep);
    if !(rounding > FAR_FROM_ORIGIN * crate::law::stiffness::LOAD_ACCELERATION) {
        return;
    }
    events.push(KjointEvent {
        source: source(j, index),
        time,
        kind: KjointEventKind::StiffnessLoweredFarFromOrigin {
            distance: bound.load.anchor_distance,
            stiffness: k,
            origin_stiffness: k.translational * bound.origin_kappa / bound.kappa,
            kappa: bound.kappa,
            origin_kappa: bound.origin_kappa,
            noise: bound.deflection_noise(),
            rounding,
            sag: explained(bound.load_weight(), k.translational),
        },
    });
}

/// The notices of joint `j` (of size `size`) at its first substep only: a sensor's lock
/// softer than a spring it holds ([`KjointEventKind::SensorLockSofterThanSpring`]) and
/// anchors apart on its blocked translations at insertion
/// ([`KjointEventKind::AnchorsApartAtInsertion`]).
pub(crate) fn first_notices(
    j: &Kjoint,
    index: usize,
    size: f64,
    time: f64,
    events: &mut Vec<KjointEvent>,
) {
    if let (Some(_), Some(blocked)) = (j.property.sensor, j.blocked) {
        for d in Dof::ALL {
            if !j.property.joint_type.is_free(d) {
                continue;
            }
            let law = j.property.dof(d);
            let spring = law.stiffness_scale().abs()
                * (law.stiffness_curve.as_ref()).map_or(1.0, |c| c.max_abs_slope());
            let lock = blocked.of(d);
            if spring > lock {
                events.push(KjointEvent {
                    source: source(j, index),
                    time,
                    kind: KjointEventKind::SensorLockSofterThanSpring {
                        dof: d,
                        lock,
                        spring,
                    },
                });
            }
        }
    }
    // a spring curve not through (0, 0): a preload from the first substep (its value at 0
    // beyond the round-off of the curve's own values)
    for (dof, force) in j.property.spring_preloads() {
        events.push(KjointEvent {
            source: source(j, index),
            time,
            kind: KjointEventKind::SpringCurvePreload { dof, force },
        });
    }
    let d = j.frames.delta0;
    let (offset, _) = blocked_motion(j.property.joint_type, &[d.x, d.y, d.z, 0.0, 0.0, 0.0]);
    if offset > (GAP_WARNING * size).max(GAP_FLOOR) {
        events.push(KjointEvent {
            source: source(j, index),
            time,
            kind: KjointEventKind::AnchorsApartAtInsertion { offset, size },
        });
    }
}

/// A flex joint whose axis points across its bodies
/// ([`KjointEventKind::FlexJointAxisAcross`]): `sides`, each side's pose where it is
/// dynamic; `anchor`, the point the joint's forces act at; `frame`, its working frame;
/// `size`, the joint's size \[m\] (a centre of mass within a thousandth of it of the anchor
/// says nothing: the poses are f32). Not in the classical mode (a bending law alone), whose
/// law acts on the total rotation angle whatever the axes.
#[allow(clippy::too_many_arguments)] // (the joint, its bodies' poses, and where it acts)
pub(crate) fn flex_axis_across(
    j: &Kjoint,
    index: usize,
    size: f64,
    sides: [Option<&BodyPose>; 2],
    anchor: &Vector3<f64>,
    frame: &UnitQuaternion<f64>,
    time: f64,
    events: &mut Vec<KjointEvent>,
) {
    match j.connector.law() {
        ConnectorLaw::FlexJoint(f) if f.law.mode() != FlexMode::Classical => {}
        _ => return,
    }
    let axis = frame * Vector3::x();
    // the smallest angle to the axis line of the lines to the bodies' centres of mass
    // (a body whose centre of mass is at the anchor says nothing)
    let mut cos_max: Option<f64> = None;
    for pose in sides.into_iter().flatten() {
        let r = pose.com - anchor;
        let n = r.norm();
        if n > 1e-3 * size {
            let c = (r.dot(&axis) / n).abs().min(1.0);
            cos_max = Some(cos_max.map_or(c, |m: f64| m.max(c)));
        }
    }
    let Some(c) = cos_max else {
        return;
    };
    if c < std::f64::consts::FRAC_1_SQRT_2 {
        events.push(KjointEvent {
            source: source(j, index),
            time,
            kind: KjointEventKind::FlexJointAxisAcross {
                axis: [axis.x, axis.y, axis.z],
                angle: c.acos(),
            },
        });
    }
}

/// The separation `|q_t|` \[m\] of the blocked translations and the largest blocked
/// rotation `max |q_r|` \[rad\] of a joint of type `ty` at `q`.
pub(crate) fn blocked_motion(ty: crate::law::JointType, q: &[f64; 6]) -> (f64, f64) {
    let free = ty.free_dofs();
    let mut gap2 = 0.0;
    for i in 0..3 {
        if !free[i] {
            gap2 += q[i] * q[i];
        }
    }
    let mut rot = 0.0f64;
    for i in 3..6 {
        if !free[i] {
            rot = rot.max(q[i].abs());
        }
    }
    (gap2.sqrt(), rot)
}

/// The first free DOF of `property` at `q` beyond one of its stops by more than the warning
/// bound ([`STOP_WARNING`] rad, or that fraction of `size` or of the stop's distance from
/// the joint's zero, the larger, for a translation), and by how much.
fn stop_overrun(
    property: &crate::law::KjointProperty,
    q: &[f64; 6],
    size: f64,
) -> Option<(Dof, f64)> {
    independent_overrun(property, q, size).or_else(|| coupled_overrun(property, q, size))
}

/// [`stop_overrun`] of the independent stops (a coupled stop's members are left to
/// [`coupled_overrun`]).
fn independent_overrun(
    property: &crate::law::KjointProperty,
    q: &[f64; 6],
    size: f64,
) -> Option<(Dof, f64)> {
    let free = property.joint_type.free_dofs();
    for d in Dof::ALL {
        if !free[d.index()] {
            continue;
        }
        let law = property.dof(d);
        if law.coupled_stops {
            // the members' stop is their family's circle (below)
            continue;
        }
        let v = q[d.index()];
        let (over, stop) = if law.stop_max > 0.0 && v > law.stop_max {
            (v - law.stop_max, law.stop_max)
        } else if law.stop_min < 0.0 && v < law.stop_min {
            (law.stop_min - v, -law.stop_min)
        } else {
            (0.0, 0.0)
        };
        // a translation's scale: the joint's size or the stop's travel, the larger (a slider
        // anchored at its bodies' centres of mass has the size of their radii of gyration)
        let bound = if d.is_rotation() {
            STOP_WARNING
        } else {
            STOP_WARNING * size.max(stop)
        };
        if over > bound {
            return Some((d, over));
        }
    }
    None
}

/// [`stop_overrun`] of the coupled stops (spec §4.3): the members' distance `d` from the
/// centre beyond the radius `R`, named by the member farthest from it (a Radioss analyst's
/// planar joint overran its coupled stop by 9.7 mm unwarned, where an independent stop's
/// 8.9 mm was warned of).
fn coupled_overrun(
    property: &crate::law::KjointProperty,
    q: &[f64; 6],
    size: f64,
) -> Option<(Dof, f64)> {
    let free = property.joint_type.free_dofs();
    for first in [0, 3] {
        let Some(g) = crate::law::kjoint2::coupled_group(property, &free, first) else {
            continue;
        };
        let members = &g.members[..g.len];
        let d = (members.iter())
            .map(|&i| (q[i] - g.centre).powi(2))
            .sum::<f64>()
            .sqrt();
        let over = d - g.radius;
        let bound = if first == 3 {
            STOP_WARNING
        } else {
            STOP_WARNING * size.max(g.radius)
        };
        if over > bound {
            let far = (members.iter().copied())
                .max_by(|&a, &b| (q[a] - g.centre).abs().total_cmp(&(q[b] - g.centre).abs()))?;
            return Some((Dof::from_index(far)?, over));
        }
    }
    None
}

/// The first free DOF of `property` at `q` beyond the end of its spring's curve where the
/// curve's extrapolation pushes it outwards ([`crate::law::CurveData::runaway_bounds`]), on
/// a side without a stop: the DOF, its value, where the push begins and the spring's
/// tangent stiffness `K·f'` there.
fn spring_runaway(
    property: &crate::law::KjointProperty,
    q: &[f64; 6],
) -> Option<(Dof, f64, f64, f64)> {
    let free = property.joint_type.free_dofs();
    for d in Dof::ALL {
        if !free[d.index()] {
            continue;
        }
        let law = property.dof(d);
        let Some(curve) = law.stiffness_curve.as_ref() else {
            continue;
        };
        let v = q[d.index()];
        let (lo, hi) = curve.runaway_bounds();
        let edge = if v > hi && !(law.stop_max > 0.0) {
            hi
        } else if v < lo && !(law.stop_min < 0.0) {
            lo
        } else {
            continue;
        };
        return Some((d, v, edge, law.stiffness_scale() * curve.slope(v)));
    }
    None
}

/// Whether [`check`] can find anything on a joint that measured `q` and has size `size`: a
/// blocked separation or rotation beyond the lower of its warning and error bounds, a stop
/// overrun beyond its bound, or a spring running off its curve ([`spring_runaway`]). Evaluated in the prepare stage, while the joint's data
/// is in cache, so that the store stage reads a healthy joint's readout and property again
/// only when this says so (at 10 000 joints those reads were 9 % of the frame). `shape`:
/// the property's, found once per analysis (the independent and coupled stops screened
/// where it has them).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn suspect(
    property: &crate::law::KjointProperty,
    q: &[f64; 6],
    size: f64,
    screens: Screens,
    shape: &crate::law::PropertyShape,
) -> bool {
    let (gap, rot) = blocked_motion(property.joint_type, q);
    gap > GAP_WARNING.min(GAP_ERROR) * size
        || rot > ROTATION_WARNING.min(ROTATION_ERROR)
        || (shape.independent_stops && independent_overrun(property, q, size).is_some())
        || (shape.coupled_stops && coupled_overrun(property, q, size).is_some())
        || (screens.curves && spring_runaway(property, q).is_some())
}

/// Which of [`suspect`]'s screens a joint needs beyond the blocked DOFs and the stops (the
/// property's shape, `law::PropertyShape`), found once per analysis (`Screens::of`): the prepare stage runs the screen for
/// every joint at every substep, and most joints have none of these (looking for them cost
/// the 1000-link chain 1 % of its frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct Screens {
    /// A free DOF whose spring is a curve ([`spring_runaway`]).
    pub curves: bool,
    /// Rotations measured by the rotation vector, free ones among them
    /// ([`rotation_jumped`]).
    pub rotation_vector: bool,
}

impl Screens {
    /// The screens joint `j` needs.
    pub(crate) fn of(j: &Kjoint) -> Screens {
        let p = &j.property;
        let free = p.joint_type.free_dofs();
        let any = |f: &dyn Fn(&crate::law::DofLaw) -> bool| {
            Dof::ALL.into_iter().any(|d| free[d.index()] && f(p.dof(d)))
        };
        Screens {
            curves: any(&|l| l.stiffness_curve.is_some()),
            rotation_vector: j.frames.measure == crate::kinematics::RotationMeasure::RotationVector
                && free[3..].iter().any(|f| *f),
        }
    }

    /// Every screen (a restored snapshot that has none recorded).
    #[allow(dead_code)] // (serde's default)
    pub(crate) fn all() -> Screens {
        Screens {
            curves: true,
            rotation_vector: true,
        }
    }
}

/// The force `|F_t|` \[N\] the joint transmits along its blocked translations and the
/// largest moment \[N·m\] about its blocked rotations, from its `applied` forces.
fn blocked_load(ty: crate::law::JointType, applied: &[f64; 6]) -> (f64, f64) {
    let (mut f2, mut moment) = (0.0, 0.0f64);
    for d in Dof::ALL {
        if !ty.is_free(d) {
            let f = applied[d.index()];
            if d.is_rotation() {
                moment = moment.max(f.abs());
            } else {
                f2 += f * f;
            }
        }
    }
    (f2.sqrt(), moment)
}

/// The substeps a frame, `[fewest, most]`, that would bring an opening a contact made at
/// `substeps` a frame, `over` times its warning bound, within it
/// ([`HealthRemedy::ContactPushed`]): `n·√over` to `n·over`, rounded up, each at most the
/// [`crate::scene::MAX_SUBSTEPS`] a set takes (`[0, 0]` where `over` is not a number above
/// 1). Advice beyond it is advice the set refuses: an opening 20 times its bound at 10 000
/// substeps a frame was told "about 44722 to 200000"; it is now told 44722 to 100000, the
/// text adding what to change where that is not enough, and where even `n·√over` is
/// beyond it (`[MAX, MAX]`, an opening 9 times its bound at 50 000) that no substep count
/// a set takes is sure to do and what must change instead.
pub(crate) fn contact_substeps(substeps: usize, over: f64) -> [u32; 2] {
    if !(over > 1.0) || substeps == 0 {
        return [0, 0];
    }
    let n = substeps as f64;
    let at = |x: f64| x.ceil().min(crate::scene::MAX_SUBSTEPS as f64) as u32;
    [at(n * over.sqrt()), at(n * over)]
}

/// The deflection `x/k` a load `x` explains through a stiffness `k` (infinite for `k = 0`).
fn explained(x: f64, k: f64) -> f64 {
    if k > 0.0 {
        x / k
    } else {
        f64::INFINITY
    }
}

/// What a step does when a joint no longer holds: its anchors more than [`GAP_ERROR`] of
/// its size apart, or a blocked rotation beyond [`ROTATION_ERROR`], each more than
/// [`UNEXPLAINED`] times what the force it transmits explains (a body moved away from the
/// body it is jointed to, a frame far too long for the joint, a blow the substep misses),
/// or, for a joint of automatic stiffness (`Kn = 0`), whatever that force explains (a load
/// the rule's stiffness at this substep cannot hold).
/// [`crate::SubstepSettings::on_unstable`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub enum OnUnstable {
    /// The run is stopped, as a crash code stops it: the step completes the substep on
    /// which the joint came apart (its impulses applied, rapier advanced, the time moved
    /// on, the bodies checked and put to sleep as at a step's end, `step_with`'s `After`
    /// hook called) and returns [`SimError::Unstable`] naming the joint and remedies. A
    /// further step goes on from there. The default. Not where rapier's contacts opened
    /// the joint (they pushed a body of it during its excursion beyond the warning bounds:
    /// a foot driven into the ground, a hard landing): that gives the `NoLongerHolds`
    /// warning naming them and the run goes on while the joint comes back, unless the
    /// opening grows fourfold or stays beyond the bounds longer than a push's does
    /// ([`CONTACT_CREDIT_SUBSTEPS`] substeps, at least [`CONTACT_CREDIT_TIME`]).
    #[default]
    Stop,
    /// The run goes on: a [`KjointEventKind::NoLongerHolds`] warning (once per joint, again
    /// whenever it is fourfold worse), and the joint pulls its bodies back at its blocked
    /// stiffness within a few substeps, far harder than rapier's joints do (their
    /// correction is capped). For a game or a learning loop, where a teleported body or a
    /// hard landing must not stop the world. (The solve's own failures, a matrix that is
    /// not positive definite or not finite, still stop the step, before any impulse is
    /// applied.)
    Warn,
}

/// Whether a joint no longer holds: its anchors `gap` apart beyond [`GAP_ERROR`] of `size`,
/// and its blocked rotation `rot` beyond [`ROTATION_ERROR`], each more than [`UNEXPLAINED`]
/// times what its load `(force, moment)` explains through `k`, or whatever its load explains
/// where the stiffness is `automatic` (`Kn = 0`: the set's rule chose it to hold the joint,
/// the user no softness).
fn no_longer_holds(
    (gap, rot): (f64, f64),
    (force, moment): (f64, f64),
    k: crate::law::BlockedStiffness,
    size: f64,
    automatic: bool,
) -> (bool, bool) {
    // (a stiffness of 0 or not finite, a body of no inertia under the Radioss rule, is not
    // one the rule chose to hold the joint)
    let held = |k: f64| automatic && k > 0.0 && k.is_finite();
    (
        gap > GAP_ERROR * size
            && (held(k.translational) || gap > UNEXPLAINED * explained(force, k.translational)),
        rot > ROTATION_ERROR
            && (held(k.rotational) || rot > UNEXPLAINED * explained(moment, k.rotational)),
    )
}

/// How far beyond the error bounds a joint is whose openings `apart` are beyond them (1 at
/// them): the larger of `gap` over [`GAP_ERROR`] of `size` and `rot` over
/// [`ROTATION_ERROR`], of those apart.
fn beyond_bounds((gap_apart, rot_apart): (bool, bool), (gap, rot): (f64, f64), size: f64) -> f64 {
    let gap = if gap_apart {
        gap / (GAP_ERROR * size)
    } else {
        0.0
    };
    gap.max(if rot_apart { rot / ROTATION_ERROR } else { 0.0 })
}

/// An opening of a joint: the separation of its anchors along the blocked translations, or
/// its largest blocked rotation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Opening {
    /// The anchors' separation \[m\] (its load a force \[N\], its stiffness `Kn` \[N/m\]).
    Gap,
    /// The largest blocked rotation \[rad\] (its load a moment \[N·m\], its stiffness `KR`
    /// \[N·m/rad\]).
    Rotation,
}

/// One of a joint's openings beyond the error bounds with the load on it and the blocked
/// stiffness the load meets: what the error (where the load explains the opening,
/// [`Self::explains`]) and the [`KjointEventKind::NoLongerHolds`] warning name
/// ([`Self::words`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LoadExplains {
    /// Which opening.
    pub opening: Opening,
    /// How far open \[m or rad\].
    pub value: f64,
    /// The load on its blocked DOFs \[N or N·m\].
    pub load: f64,
    /// The blocked stiffness \[N/m or N·m/rad\].
    pub stiffness: f64,
}

impl LoadExplains {
    /// The openings beyond their bounds (`apart`: the gap's, the rotation's) with the load
    /// on each and the stiffness it meets: the gap with the force and `Kn`, the rotation
    /// with the moment and `KR`.
    pub(crate) fn of_openings(
        (gap_apart, rot_apart): (bool, bool),
        (gap, rot): (f64, f64),
        (force, moment): (f64, f64),
        k: crate::law::BlockedStiffness,
    ) -> impl Iterator<Item = LoadExplains> {
        [
            (gap_apart, Opening::Gap, gap, force, k.translational),
            (rot_apart, Opening::Rotation, rot, moment, k.rotational),
        ]
        .into_iter()
        .filter(|o| o.0)
        .map(|(_, opening, value, load, stiffness)| LoadExplains {
            opening,
            value,
            load,
            stiffness,
        })
    }

    /// Whether the load explains the opening within [`UNEXPLAINED`].
    pub(crate) fn explains(&self) -> bool {
        self.value <= UNEXPLAINED * explained(self.load, self.stiffness)
    }

    /// `its load of 19620 N accounts for 0.3000 m of the gap through the automatic blocked
    /// stiffness 65400 N/m this substep gives it` (`automatic`: the set's rule chose the
    /// stiffness, `Kn = 0`; else `through its blocked stiffness 65400 N/m`).
    pub(crate) fn words(&self, automatic: bool) -> String {
        let (load_unit, x_unit, k_unit, of) = match self.opening {
            Opening::Gap => ("N", "m", "N/m", "the gap"),
            Opening::Rotation => ("N·m", "rad", "N·m/rad", "the rotation"),
        };
        let (through, gives) = if automatic {
            ("the automatic", " this substep gives it")
        } else {
            ("its", "")
        };
        format!(
            "its load of {} {load_unit} accounts for {} {x_unit} of {of} through {through} \
             blocked stiffness {} {k_unit}{gives}",
            fig(self.load),
            fig(explained(self.load, self.stiffness)),
            fig(self.stiffness),
        )
    }
}

/// The openings of a joint of automatic stiffness beyond the error bounds (`apart`: the
/// gap's, the rotation's, [`no_longer_holds`]) that its load explains within
/// [`UNEXPLAINED`]: each tested against its own load (the gap against the force, the
/// rotation against the moment), both where both are apart. (Only the gap was tested where
/// both were apart: a rotation its moment explained beside a gap its force did not was
/// stopped naming no load, and the error named the gap alone.)
fn explained_openings(
    apart: (bool, bool),
    openings: (f64, f64),
    loads: (f64, f64),
    k: crate::law::BlockedStiffness,
) -> Vec<LoadExplains> {
    LoadExplains::of_openings(apart, openings, loads, k)
        .filter(LoadExplains::explains)
        .collect()
}

/// The error of joint `name` that no longer holds ([`no_longer_holds`]: its anchors `gap`
/// apart and its blocked rotation `rot`, each beyond its bound where `apart` says so), at
/// `time`; `contact`: its body that rapier's contacts pushed ([`CONTACT_OPENS`]), `ended`
/// why their credit for the opening ended ([`CreditEnded`]); `by_load`: the openings its load
/// explains through its automatic stiffness ([`explained_openings`]).
fn unstable(
    name: &str,
    (gap_apart, rot_apart): (bool, bool),
    (gap, rot): (f64, f64),
    size: f64,
    (contact, ended): (Option<u8>, Option<CreditEnded>),
    by_load: &[LoadExplains],
    time: f64,
) -> SimError {
    let anchors = format!(
        "anchors {} m apart, more than half of the joint's size {} m",
        fig(gap),
        fig(size)
    );
    let rotation = format!("a blocked rotation of {rot:.3} rad");
    let what = match (gap_apart, rot_apart) {
        (true, true) => format!("{anchors}, and {rotation}"),
        (true, false) => anchors,
        _ => rotation,
    };
    let contact = match (contact, ended) {
        (Some(body), Some(CreditEnded::Grew { first })) => format!(
            "; its body {body} {CONTACT_OPENS}, and the opening grew more than fourfold since \
             ({} times the bounds, then {})",
            fig(beyond_bounds((gap_apart, rot_apart), (gap, rot), size)),
            fig(first)
        ),
        (Some(body), Some(CreditEnded::Lasted { lasted, span })) => format!(
            "; its body {body} {CONTACT_OPENS}, but the joint stayed open beyond the bounds \
             for {} s, longer than the {} s ({} substeps, at least {} s) in which it pulls a \
             push's opening back",
            fig(lasted),
            fig(span),
            CONTACT_CREDIT_SUBSTEPS,
            CONTACT_CREDIT_TIME
        ),
        (Some(body), None) => format!("; its body {body} {CONTACT_OPENS}"),
        _ => String::new(),
    };
    // a load the automatic stiffness of this substep holds only that far apart
    let load = if by_load.is_empty() {
        String::new()
    } else {
        let words: Vec<String> = by_load.iter().map(|l| l.words(true)).collect();
        format!("; {}{AUTOMATIC_REMEDY}", words.join(", and "))
    };
    SimError::Unstable {
        time,
        reason: format!(
            "joint `{name}`: {what}: the joint no longer holds and the run is unstable{contact}; \
             remedies: {REMEDY}{load}; {TELEPORT}; or set `SubstepSettings::on_unstable` to \
             `OnUnstable::Warn` to have the joint pull its bodies back and the run go on"
        ),
    }
}

/// The remedy of a joint of automatic stiffness whose opening its load explains, after
/// [`LoadExplains::words`].
pub(crate) const AUTOMATIC_REMEDY: &str = " (the rule's stiffness grows as 1/h²: fourfold \
     with twice the substeps), or set a larger scale factor ScF or an explicit Kn";

/// What to advise for a separation `x` of which its load `load` explains `explained` through
/// the stiffness `k`: one the blocked stiffness explains (within a factor of 2) is a soft
/// joint (a larger Kn holds it); one it does not explain is dynamics the substep misses.
/// Where the stiffness is the implicit rule's lowered by the f32 noise bound (`bound`), the
/// soft joint is told so and what raises it ([`HealthRemedy::NoiseBoundedStiffness`]).
fn remedy(x: f64, load: f64, explained: f64, k: f64, bound: Option<NoiseBound>) -> HealthRemedy {
    // at the floor the bound no longer sets the stiffness (a shorter substep gives more)
    let bound = bound.filter(NoiseBound::sets_stiffness);
    if x <= 2.0 * explained {
        match bound {
            Some(bound) => HealthRemedy::NoiseBoundedStiffness {
                stiffness: k,
                load,
                bound,
            },
            None => HealthRemedy::LargerBlockedStiffness { stiffness: k },
        }
    } else {
        HealthRemedy::ShorterSubstep
    }
}

/// The checks of joint `j` on its last readout at the set's `time` of a substep `h` (see the
/// module docs): the error of a joint that no longer holds where `on_unstable` stops the
/// run and the contacts did not open it (else its warning; `contact`: its body, 1 or 2,
/// that rapier's contacts pushed over the last substep), and the warnings not yet given for
/// this joint.
pub(crate) fn check(
    j: &mut Kjoint,
    index: usize,
    size: f64,
    (time, h, substeps): (f64, f64, usize),
    (on_unstable, contact): (OnUnstable, Option<u8>),
    events: &mut Vec<KjointEvent>,
) -> Result<(), SimError> {
    let Some(state) = j.state.as_ref() else {
        return Ok(());
    };
    let ty = j.property.joint_type;
    let (gap, rot) = blocked_motion(ty, &state.q);
    // what the transmitted force explains through the blocked stiffness
    let (force, moment) = blocked_load(ty, &state.applied);
    let Some(k) = j.blocked else {
        return Ok(());
    };
    // The body of the joint that rapier's contacts pushed during its current excursion
    // beyond the warning bounds (or past a stop's: where these checks run at every
    // substep), the excursion a new one where the last check was not at the last substep.
    if time - j.checked_at > 1.5 * h {
        j.pushed_open = 0;
        j.opened_by_contact = 0.0;
    }
    j.checked_at = time;
    if let Some(body) = contact {
        j.pushed_open = body;
    }
    let automatic = j.property.automatic_stiffness();
    let apart = no_longer_holds((gap, rot), (force, moment), k, size, automatic);
    if apart.0 || apart.1 {
        // how far beyond the bounds (1 at them), given again when fourfold worse
        let beyond = beyond_bounds(apart, (gap, rot), size);
        // An opening rapier's contacts made (they act after the joints are solved in each
        // substep, so a hard one opens a joint before it answers) is warned of, not
        // stopped, until the joint is back within the bounds, as long as it does not grow
        // fourfold: the joint pulls its bodies back, and rapier's own joints flex as far
        // (an A1 quadruped under random torques of ±5 N·m on the ground: 0.5 rad about a
        // calf's blocked axis at 4 substeps, where rapier's impulse joints reach 0.26 rad,
        // 0.72 rad under ±33.5 N·m).
        if j.pushed_open != 0 && j.opened_by_contact == 0.0 {
            j.opened_by_contact = beyond as f32;
            j.opened_at = time;
        }
        // (an opening its load explains through an automatic stiffness is one as well: the
        // implicit pull-back `K·q/(1 + κ)` of a push explains it within 1 + κ, which the
        // load test cannot tell from a load the stiffness cannot hold; a review of
        // 2026-12-06. Such a joint under a contact stops when the opening grows fourfold,
        // the 20 t chassis's axles at 0.73 m at one substep, or stays, at 4 substeps)
        let by_load = explained_openings(apart, (gap, rot), (force, moment), k);
        let pushed = (j.pushed_open != 0).then_some(j.pushed_open);
        // (the credit ends where the opening grows fourfold, or stays beyond the bounds
        // longer than a push's opening does: a load the joint cannot hold)
        let first = f64::from(j.opened_by_contact);
        let (lasted, span) = (time - j.opened_at, contact_credit_span(h));
        let ended = if first == 0.0 {
            None
        } else if beyond > WARNING_GROWTH * first {
            Some(CreditEnded::Grew { first })
        } else if lasted > span + 0.5 * h {
            Some(CreditEnded::Lasted { lasted, span })
        } else {
            None
        };
        let by_contact = first > 0.0 && ended.is_none();
        if on_unstable == OnUnstable::Stop && !by_contact {
            return Err(unstable(
                &j.name,
                apart,
                (gap, rot),
                size,
                (pushed, ended),
                &by_load,
                time,
            ));
        }
        let last = f64::from(j.warned_apart);
        if last == 0.0 || beyond > WARNING_GROWTH * last {
            j.warned_apart = beyond as f32;
            events.push(KjointEvent {
                source: source(j, index),
                time,
                kind: KjointEventKind::NoLongerHolds {
                    gap,
                    size,
                    rotation: rot,
                    contact: pushed,
                    force,
                    moment,
                    stiffness: k,
                    automatic,
                },
            });
        }
    } else if j.opened_by_contact > 0.0 {
        // back within the bounds: a later opening needs a push of its own
        j.opened_by_contact = 0.0;
        j.pushed_open = contact.unwrap_or(0);
    }
    // a separation its stiffness does not explain, where rapier's contacts pushed a body
    // of the joint during the excursion, is theirs
    let pushed = j.pushed_open;
    // the remedy of an opening `x` beyond its warning bound under the load `load` through
    // the stiffness `stiffness`
    let noise_bound = j.noise_bound;
    let advise = |x: f64, bound: f64, load: f64, stiffness: f64| match remedy(
        x,
        load,
        explained(load, stiffness),
        stiffness,
        noise_bound,
    ) {
        HealthRemedy::ShorterSubstep if pushed != 0 => HealthRemedy::ContactPushed {
            body: pushed,
            substeps: contact_substeps(substeps, x / bound),
        },
        r => r,
    };
    let mut found: Vec<(usize, f64, KjointEventKind)> = Vec::new();
    let gap_bound = (GAP_WARNING * size).max(GAP_FLOOR);
    if gap > gap_bound {
        let remedy = advise(gap, gap_bound, force, k.translational);
        found.push((
            WARNED_GAP,
            gap,
            KjointEventKind::AnchorsSeparating { gap, size, remedy },
        ));
    }
    if rot > ROTATION_WARNING {
        let remedy = advise(rot, ROTATION_WARNING, moment, k.rotational);
        let kind = KjointEventKind::BlockedRotation { angle: rot, remedy };
        found.push((WARNED_ROTATION, rot, kind));
    }
    if let Some((dof, overrun)) = stop_overrun(&j.property, &state.q, size) {
        let kf = j.property.dof(dof).friction_stiffness;
        let blocked = k.of(dof);
        let remedy = match &j.noise_bound {
            // (not where a robot loader chose Kf by the substep's rule: the user wrote none)
            _ if kf > 0.0 && j.friction_by_rule != Some(dof) => {
                StopRemedy::FrictionSpring { stiffness: kf }
            }
            // (in the bound's regime, where no substep gives more; at the floor a shorter
            // one does)
            Some(bound)
                if j.property.automatic_stiffness()
                    && bound.sets_stiffness()
                    && bound.origin_kappa > 2.0 * bound.kappa =>
            {
                StopRemedy::NoiseBounded {
                    stiffness: blocked,
                    distance: bound.load.anchor_distance,
                    lowered: bound.origin_kappa / bound.kappa,
                }
            }
            _ => StopRemedy::ShorterSubstep { stiffness: blocked },
        };
        let kind = KjointEventKind::StopOverrun {
            dof,
            overrun,
            remedy,
        };
        found.push((WARNED_STOP, overrun, kind));
    }
    if rotation_jumped(j) {
        j.warned_jump = true;
        let angle = (state.q[3].powi(2) + state.q[4].powi(2) + state.q[5].powi(2)).sqrt();
        let kind = KjointEventKind::RotationVectorJumped {
            angle,
            jump: j.measure.jump_squared().sqrt(),
        };
        events.push(KjointEvent {
            source: source(j, index),
            time,
            kind,
        });
    }
    if let Some((dof, value, edge, stiffness)) = spring_runaway(&j.property, &state.q) {
        let last = f64::from(j.warned_runaway);
        if last == 0.0 || value.abs() > WARNING_GROWTH * last {
            j.warned_runaway = value.abs() as f32;
            let kind = KjointEventKind::SpringRunsAway {
                dof,
                value,
                edge,
                stiffness,
            };
            events.push(KjointEvent {
                source: source(j, index),
                time,
                kind,
            });
        }
    }
    // once per joint and kind, and again each time it grows [`WARNING_GROWTH`]-fold
    for (k, value, kind) in found {
        let last = f64::from(j.warned[k]);
        if last == 0.0 || value > WARNING_GROWTH * last {
            j.warned[k] = value as f32;
            events.push(KjointEvent {
                source: source(j, index),
                time,
                kind,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{contact_substeps, HealthRemedy, KjointEventKind};
    use super::{explained_openings, no_longer_holds, unstable};
    use crate::law::BlockedStiffness;

    /// A `NoLongerHolds` warning saved before it named its load reads back, with no load
    /// and no stiffness (0), and its text names none.
    #[cfg(feature = "serde-serialize")]
    #[test]
    fn a_no_longer_holds_warning_saved_without_its_load_reads_back() {
        let old = r#"{"NoLongerHolds":{"gap":0.4,"size":0.5,"rotation":0.0,"contact":2}}"#;
        let read: KjointEventKind = serde_json::from_str(old).expect("an old warning");
        let KjointEventKind::NoLongerHolds {
            gap,
            contact,
            force,
            moment,
            stiffness,
            automatic,
            ..
        } = read
        else {
            panic!("{read:?}")
        };
        assert_eq!((gap, contact), (0.4, Some(2)));
        assert_eq!((force, moment, automatic), (0.0, 0.0, false));
        assert_eq!((stiffness.translational, stiffness.rotational), (0.0, 0.0));
        let text = read.to_string();
        assert!(text.contains("anchors 0.4000 m apart"), "{text}");
        assert!(!text.contains("its load of"), "{text}");
    }

    /// The error of a joint `axle` of automatic stiffness `k` and size 1 m with its anchors
    /// `gap` apart and its blocked rotation `rot`, under `(force, moment)`, as `check`
    /// gives it.
    fn error_of(gap: f64, rot: f64, force: f64, moment: f64, k: BlockedStiffness) -> String {
        let apart = no_longer_holds((gap, rot), (force, moment), k, 1.0, true);
        assert_eq!(apart, (true, true));
        let by_load = explained_openings(apart, (gap, rot), (force, moment), k);
        unstable("axle", apart, (gap, rot), 1.0, (None, None), &by_load, 1.0).to_string()
    }

    /// Both the gap and the blocked rotation of a joint of automatic stiffness beyond the
    /// error bounds: each is tested against its own load and named where that load explains
    /// it. A rotation of 0.8 rad that a moment of 1000 N·m explains through KR = 2000
    /// N·m/rad (0.5 rad), beside a gap of 1 m that 10 N explains 1 mm of through Kn = 1e4
    /// N/m, was stopped naming no load (only the gap was tested); the error now names the
    /// moment, and the force where the gap is the one explained, and both where both are.
    #[test]
    fn an_error_names_the_load_that_explains_each_opening() {
        let k = BlockedStiffness {
            translational: 1e4,
            rotational: 2000.0,
        };
        let text = error_of(1.0, 0.8, 10.0, 1000.0, k);
        println!("{text}");
        for said in [
            "joint `axle`: anchors 1.000 m apart, more than half of the joint's size 1.000 m, \
             and a blocked rotation of 0.800 rad: the joint no longer holds",
            "its load of 1000 N·m accounts for 0.5000 rad of the rotation through the \
             automatic blocked stiffness 2000 N·m/rad this substep gives it (the rule's \
             stiffness grows as 1/h²",
        ] {
            assert!(text.contains(said), "{said}: {text}");
        }
        assert!(!text.contains("of the gap"), "{text}");

        // the gap explained by its force (1e4 N: 1 m), the rotation not by its moment
        let text = error_of(1.0, 0.8, 1e4, 1.0, k);
        assert!(
            text.contains(
                "its load of 10000 N accounts for 1.000 m of the gap through the automatic \
                 blocked stiffness 10000 N/m this substep gives it (the rule's"
            ),
            "{text}"
        );
        assert!(!text.contains("of the rotation"), "{text}");

        // both explained: both named, each with its own load and stiffness
        let text = error_of(1.0, 0.8, 1e4, 1000.0, k);
        assert!(
            text.contains(
                "its load of 10000 N accounts for 1.000 m of the gap through the automatic \
                 blocked stiffness 10000 N/m this substep gives it, and its load of 1000 N·m \
                 accounts for 0.5000 rad of the rotation through the automatic blocked \
                 stiffness 2000 N·m/rad this substep gives it (the rule's"
            ),
            "{text}"
        );

        // neither: no load named, the remedies of dynamics the substep misses
        let text = error_of(1.0, 0.8, 10.0, 1.0, k);
        assert!(!text.contains("accounts for"), "{text}");
        assert!(text.contains("remedies: more substeps"), "{text}");
    }

    /// `n·√r` to `n·r`, rounded up: the Talos humanoid's ankle at 82 mrad (4.1 times its
    /// 20 mrad bound) at 4 substeps is told 9 to 17 (it stood at 8 with 28 mrad, at 16 with
    /// 3.6); nothing where the opening is not beyond its bound.
    #[test]
    fn the_substeps_a_contact_s_opening_needs() {
        assert_eq!(contact_substeps(4, 4.1), [9, 17]);
        assert_eq!(contact_substeps(8, 1.4), [10, 12]);
        assert_eq!(contact_substeps(4, 1.0), [0, 0]);
        assert_eq!(contact_substeps(4, f64::NAN), [0, 0]);
        assert_eq!(contact_substeps(0, 3.0), [0, 0]);
        assert_eq!(contact_substeps(4, f64::INFINITY), [100_000, 100_000]);
    }

    /// The advice is within the 100 000 substeps a frame a set takes
    /// ([`crate::scene::MAX_SUBSTEPS`]): an opening 20 times its bound at 10 000 substeps
    /// was told "about 44722 to 200000"; it is told 44722 to 100000 and what to change
    /// where that is not enough; one 9 times its bound at 50 000 (`n·√r` = 150 000) is
    /// told that no count a set takes is sure to do, and what must.
    #[test]
    fn the_substeps_a_contact_s_opening_needs_are_those_a_set_takes() {
        assert_eq!(crate::scene::MAX_SUBSTEPS, 100_000);
        assert_eq!(contact_substeps(10_000, 20.0), [44_722, 100_000]);
        assert_eq!(contact_substeps(50_000, 9.0), [100_000, 100_000]);
        assert_eq!(contact_substeps(100_000, 1.5), [100_000, 100_000]);
        let text = |n: usize, over: f64| {
            let remedy = HealthRemedy::ContactPushed {
                body: 2,
                substeps: contact_substeps(n, over),
            };
            let gap = over * 0.002;
            KjointEventKind::AnchorsSeparating {
                gap,
                size: 0.1,
                remedy,
            }
            .to_string()
        };
        // every count the text names is one a set takes
        let counts = |t: &str| -> Vec<f64> {
            let (_, advice) = t.split_once("(about ").expect(t);
            (advice.split(|c: char| !c.is_ascii_digit()))
                .filter(|w| !w.is_empty())
                .map(|w| w.parse().unwrap())
                .collect()
        };
        let capped = text(10_000, 20.0);
        println!("{capped}");
        assert!(
            capped.contains(
                "about 44722 to 100000 substeps a frame would keep this opening within the \
                 warning's bound"
            ),
            "{capped}"
        );
        assert!(
            capped.contains(
                "100000 is the most a set takes: where it is not enough, a smaller frame time \
                 step (the substep is the frame's over the substeps), a stiffer joint (a \
                 larger Kn, or scale factor ScF for one of automatic stiffness) or lighter \
                 loads must do the rest)"
            ),
            "{capped}"
        );
        assert!(counts(&capped).iter().all(|&c| c <= 100_000.0), "{capped}");
        let beyond = text(50_000, 9.0);
        println!("{beyond}");
        assert!(
            beyond.contains(
                "(about 100000 substeps a frame or more would keep this opening within the \
                 warning's bound, and 100000 is the most a set takes: a smaller frame time \
                 step"
            ),
            "{beyond}"
        );
        assert!(!beyond.contains("to 100000"), "{beyond}");
        assert!(counts(&beyond).iter().all(|&c| c <= 100_000.0), "{beyond}");
        // within the set's counts, as before: no word of them
        let within = text(4, 4.1);
        assert!(
            within.contains(
                "(about 9 to 17 substeps a frame would keep this opening within the warning's \
                 bound: a contact's opening shrinks as the substep squared to as the substep)"
            ),
            "{within}"
        );
    }
}
