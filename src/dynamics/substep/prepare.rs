//! The named steps of the prepare stage (stage 4) for one joint, called in order by
//! [`KjointSet::stage_prepare_joints`](super::super::KjointSet): each takes the data it
//! reads and writes explicitly, so that the stage's loop reads as the list of steps.

use super::StoredJoint;
use crate::dynamics::joint::{JointState, Kjoint};
use crate::dynamics::solve::{self, RateJacobians};
use crate::kinematics::{self, BodyPose, JointMotion};
use crate::law::{self, Dof, FrictionStatus, LawOutput, LawParams, PerDof, StopContact};
use nalgebra::{Matrix3, Matrix6, UnitQuaternion, Vector3, Vector6};

/// Books on the joint what the store stage left in `stored` (its [`StoredJoint`]): the work
/// of the substep's impulse, `numerical += −W − ΔE_law` (the law's own share since the last
/// booking taken out), the transmitted force into [`Kjoint::last_applied`] and, when that
/// substep wrote the joint's readout ([`StoredJoint::readout`]), with the energies into the
/// readout, then the end-rate correction (`end_rate_correction`, of the measure stage) once
/// the next substep has measured it.
/// The same operations in the same order as when the store stage wrote the record itself:
/// the results are identical.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn fold_stored(j: &mut Kjoint, stored: &mut StoredJoint) {
    if stored.pending {
        stored.pending = false;
        let law_now = law_energy(&j.law.energy);
        let e = &mut j.law.energy;
        e.numerical += -stored.work - (law_now - j.booked_law);
        j.booked_law = law_now;
        j.last_applied = stored.applied;
        if stored.readout {
            if let Some(s) = j.state.as_mut() {
                s.applied = PerDof(stored.applied);
                s.energy = *e;
            }
        }
    }
    // (`x − 0` is `x` for every `x`, −0 and NaN included: no flag for "nothing to correct")
    j.law.energy.numerical -= std::mem::take(&mut stored.correction);
}

/// What the law itself has booked of a joint's energies (stored and dissipated; the
/// update's `numerical` share is the book's).
#[cfg_attr(not(debug_assertions), inline(always))]
fn law_energy(e: &law::JointEnergy) -> f64 {
    e.elastic + e.kinetic + e.damping + e.friction + e.stop + e.motor
}

/// At the law's first evaluation: what it stored then (an initial angle between skew frames,
/// or bodies inserted away from the joint's rest) is the joint's preload
/// ([`Kjoint::preload_energy`]), not work of its bodies, so the book starts from it
/// (without this the next [`fold_stored`] charged it to `numerical`, as work the update
/// gave the bodies: a preloaded joint's damping read as −0.045 J dissipated). Called after
/// the realised stiffness has scaled the stored energy ([`scale_stored_energy`]).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn book_preload(j: &mut Kjoint) {
    let stored = law_energy(&j.law.energy);
    j.booked_law = stored;
    j.preload = stored;
}

/// `(v, ω)` of a pose.
#[cfg_attr(not(debug_assertions), inline(always))]
fn velocity6(p: &BodyPose) -> Vector6<f64> {
    let (v, w) = (p.linvel, p.angvel);
    Vector6::new(v.x, v.y, v.z, w.x, w.y, w.z)
}

/// The KJOINT2 law (docs/kjoint2.md §4) then the joint's connector law (planar friction,
/// flex joint), which adds its forces, tangents and energies to the same output. `t`: the
/// rows of the translations' frame (`T`, [`RateJacobians::t`]); `pose2`: body 2's pose (a
/// connector's lever arm is anchor 2's).
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn evaluate_law(
    j: &mut Kjoint,
    params: &LawParams,
    shape: &law::PropertyShape,
    kin: &JointMotion,
    t: &Matrix3<f64>,
    pose2: &BodyPose,
    lock: bool,
    time: f64,
    out: &mut LawOutput,
) {
    law::evaluate_into(
        &j.property,
        params,
        &kin.q,
        &kin.rate,
        lock,
        &mut j.law,
        j.motors.as_deref_mut(),
        out,
        shape.linear_free_dofs,
    );
    if !j.connector.is_some() {
        return;
    }
    let p2 = pose2.point(&j.frames.local_anchor2);
    let input = law::ConnectorInput {
        q: kin.q,
        rate: kin.rate,
        lever: (t * (p2 - kin.force_point)).into(),
        time,
    };
    j.connector
        .apply(&j.property, params, &input, out, &mut j.law.energy);
}

/// The stops the DOFs will reach by the end of the substep, engaged now, and a DOF resting
/// on its stop held on it (`law::stop_prediction`), given the force `fa` transmitted over
/// the last substep: their stiffness is added to the tangent `kt` and their force to
/// `total`. Part of the update, not of the law: the readout's law force stays the law's
/// (zero inside the stops); the transmitted force includes it. `kt`: the diagonal of the
/// tangent stiffness.
#[cfg_attr(not(debug_assertions), inline(always))]
#[allow(clippy::too_many_arguments)]
pub(super) fn engage_predicted_stops(
    j: &mut Kjoint,
    params: &LawParams,
    kin: &JointMotion,
    fa: &[f64; 6],
    w: &Vector6<f64>,
    h: f64,
    kt: &mut Vector6<f64>,
    parts: &[law::ForceParts; 6],
    stiffness: &mut Matrix6<f64>,
    total: &mut [f64; 6],
) {
    // the law's force without its stops' (`total` holds the law's and the numerical damping;
    // read only where the property has stops)
    let stops = j.property.has_independent_stops() || j.property.has_coupled_stops();
    let law_force: [f64; 6] = if stops {
        std::array::from_fn(|i| total[i] - parts[i].stop)
    } else {
        [0.0; 6]
    };
    let input = law::StopInput {
        prop: &j.property,
        blocked: &params.blocked,
        q: &kin.q,
        rate: &kin.rate,
        transmitted: fa,
        law: &law_force,
        inv_mass: &w.data.0[0],
        h,
        beta: solve::BETA,
        locked: j.law.lock.is_some(),
    };
    let predicted = law::predicted_stops(&input, &mut j.predicted_stops);
    for (i, s) in predicted.iter().enumerate() {
        if s.stiffness > 0.0 {
            kt[i] += s.stiffness;
            total[i] += s.force;
        }
    }
    // coupled stops along their normal: `F_s·n` and the tangent `k_s·n·nᵀ`, its entries off
    // the diagonal into the law's stiffness (a joint with coupled stops writes its full
    // block, [`write_g`])
    let coupled = law::predicted_coupled_stops(&input, &mut j.predicted_stops);
    for c in coupled.iter().filter(|c| c.stiffness > 0.0) {
        for a in 0..c.len {
            let i = c.members[a];
            total[i] += c.force * c.normal[a];
            kt[i] += c.stiffness * c.normal[a] * c.normal[a];
            for b in (0..c.len).filter(|&b| b != a) {
                stiffness[(i, c.members[b])] += c.stiffness * c.normal[a] * c.normal[b];
            }
        }
    }
}

/// Per DOF whose KJOINT2 friction spring sticks, the part of the numerical damping `c_num`
/// ([`solve::unresolved_damping`] of `kt` and `swing`) that its `K_f` brings: `c_num` less
/// the DOF's damping with `K_f` taken out of `kt` (`law::slip_prediction`). 0 elsewhere.
#[inline(never)]
pub(super) fn friction_share_of_damping(
    prop: &law::KjointProperty,
    out: &LawOutput,
    kt: &Vector6<f64>,
    swing: &Vector6<f64>,
    w: &Vector6<f64>,
    h: f64,
    c_num: &Vector6<f64>,
) -> [f64; 6] {
    let mut share = [0.0; 6];
    for (i, st) in out.status.iter().enumerate() {
        let law = &prop.dofs[i];
        if st.friction != FrictionStatus::Stick || !law.friction_active() {
            continue;
        }
        let mut without = *kt;
        without[i] -= law.friction_stiffness;
        let other = solve::unresolved_damping(&without, swing, w, h);
        share[i] = (c_num[i] - other[i]).max(0.0);
    }
    share
}

/// The numerical damping `c_num` of the DOFs the substep cannot resolve
/// ([`solve::unresolved_damping`]) added to the law's damping and to its force
/// (`F += c_num·q̇`, into `total`).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn add_unresolved_damping(
    out: &mut LawOutput,
    total: &mut [f64; 6],
    c_num: &Vector6<f64>,
    rate: &[f64; 6],
) {
    for i in 0..6 {
        out.damping[(i, i)] += c_num[i];
        total[i] += c_num[i] * rate[i];
    }
}

/// The energy a DOF stores is that of the stiffness the update realises, `K̃ = K/(1 + h²·K·w/β)`
/// ([`solve::realised_stiffness`]), not the law's: the joint's elastic energy loses
/// `(1 − K̃/K)` of what the law stored.
///
/// - A blocked DOF: `½·(K − K̃)·q²`.
/// - A stop, a sensor lock or a friction spring on a free DOF: its stored energy scaled by
///   the ratio `K̃/K` of the DOF's tangent stiffness (a stop on a light wrist, far stiffer
///   than the substep resolves, stored thousands of joules in a robot that has one).
/// - A coupled stop in contact, along its direction `n`, with `w_n = Σ n_i²·w_i`.
///
/// `kt`: the diagonal of the tangent stiffness.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn scale_stored_energy(
    j: &mut Kjoint,
    params: &LawParams,
    shape: &law::PropertyShape,
    kt: &Vector6<f64>,
    out: &LawOutput,
    w: &Vector6<f64>,
    q: &[f64; 6],
    h: f64,
) {
    let property = j.property();
    // the joint type's free DOFs looked up once (a match per DOF before)
    let free = property.joint_type.free_dofs();
    // a sensor lock: (engaged in this evaluation, what its activation released)
    let lock = j.law.lock.as_deref().map(|l| (l.fresh, l.held_released));
    // a lock engaging now holds what the free DOFs stored with their law's tangent: scaled
    // as at the substep before (no jump), not with the lock's `K_b`
    // (matches, not closures: those can stay out of line in the substep's AVX2 copy)
    let held_tangent = match j.law.lock.as_deref() {
        Some(l) if l.fresh => Some(l.held_tangent),
        _ => None,
    };
    let mut released = 0.0;
    // the free DOFs' share of it, which a lock engaging now keeps (docs/kjoint2.md §4.5)
    let mut released_free = 0.0;
    for (i, d) in Dof::ALL.into_iter().enumerate() {
        if !free[i] {
            let k = params.blocked.of(d);
            let kr = solve::realised_stiffness(k, w[i], h);
            released += 0.5 * (k - kr) * q[i] * q[i];
        } else {
            let k = match &held_tangent {
                Some(t) => t[i],
                None => kt[i],
            };
            if k > 0.0 {
                let ratio = solve::realised_stiffness(k, w[i], h) / k;
                let stored = law::stored_energy::stored_energy_of_dof(
                    property,
                    &params.blocked,
                    &out.status[i],
                    &j.law,
                    d,
                    q[i],
                );
                released += (1.0 - ratio) * stored;
                released_free += (1.0 - ratio) * stored;
            }
        }
    }
    // (the two families by a loop, not the iterator `coupled_stop_contacts`: its closures
    // were compiled out of line, without the substep's AVX2); no stop acts while a lock holds
    let mut first = if matches!(lock, Some((false, _))) || !shape.coupled_stops {
        6
    } else {
        0
    };
    while first < 6 {
        let contact = law::stored_energy::coupled_stop_contact(property, &params.blocked, q, first);
        if let Some((e, ks, n)) = contact {
            let wn: f64 = (0..6).map(|i| n[i] * n[i] * w[i]).sum();
            let ratio = solve::realised_stiffness(ks, wn, h) / ks;
            released += (1.0 - ratio) * e;
            released_free += (1.0 - ratio) * e;
        }
        first += 3;
    }
    // The energy the free DOFs held at activation was booked scaled at that substep; the
    // lock holds it as booked then, so its scaling goes on as it was (no jump).
    match lock {
        Some((true, _)) => {
            if let Some(l) = j.law.lock.as_deref_mut() {
                (l.held_released, l.fresh) = (released_free, false);
            }
        }
        Some((false, held_released)) => released += held_released,
        None => {}
    }
    j.law.energy.elastic -= released;
}

/// At a substep whose readout is written: the law's forces per DOF from which
/// [`Kjoint::closed_energy`] predicts the law's share of the substep
/// ([`crate::dynamics::joint::OutstandingShare`]), from its output `out` at the substep's
/// start, `kt` the diagonal of its tangent stiffness (without the predicted stops, which the
/// law does not book), `c_num` the numerical damping that `out`'s tangent damping includes
/// (the update's, not the law's) and `w` the DOFs' inverse inertia. The gradient of the
/// stored energy is scaled as [`scale_stored_energy`] scales the energy: a blocked DOF's
/// penalty by `K̃/K`, a free DOF's stop, lock and friction spring by `K̃/K` of its tangent,
/// its own spring not. Out of the prepare loop's line: one substep in four of a plain step
/// writes it, and the loop's machine code fills the instruction cache already.
#[inline(never)]
pub(super) fn outstanding_forces(
    j: &mut Kjoint,
    params: &LawParams,
    kt: &Vector6<f64>,
    out: &LawOutput,
    c_num: &Vector6<f64>,
    w: &Vector6<f64>,
    h: f64,
) {
    let free = j.property.joint_type.free_dofs();
    let s = &mut j.outstanding;
    for (i, d) in Dof::ALL.into_iter().enumerate() {
        let (p, st) = (&out.parts[i], &out.status[i]);
        let ratio = |k: f64| {
            if k > 0.0 {
                solve::realised_stiffness(k, w[i], h) / k
            } else {
                1.0
            }
        };
        let stick = st.friction == FrictionStatus::Stick;
        let gradient = if free[i] {
            let spring = if stick { p.friction } else { 0.0 };
            p.elastic + ratio(kt[i]) * (p.stop + p.sensor + spring)
        } else {
            ratio(params.blocked.of(d)) * p.elastic
        };
        s.stored_gradient[i] = gradient;
        s.damping[i] = p.damping;
        s.damping_tangent[i] = out.damping[(i, i)] - c_num[i];
        s.in_stop[i] = st.stop != StopContact::None;
        s.slip[i] = if st.friction == FrictionStatus::Slip {
            p.friction
        } else {
            0.0
        };
    }
    if let Some(d) = j.motors.as_deref_mut() {
        for i in 0..6 {
            // (the tangents are the motor's below its cap, 0 at it)
            let f = out.parts[i].motor;
            d.outstanding[i] = match &d.motors[i] {
                Some(m) if f.abs() < m.max_force => [f, m.stiffness, m.damping],
                Some(_) => [f, 0.0, 0.0],
                None => [0.0; 3],
            };
        }
    }
}

/// The joint's size \[m\] for the health checks: the lever arms `levers[s]` from each dynamic
/// side's centre of mass to its own anchor, at least its radius of gyration (fixed in the
/// body: the size does not grow as the anchors part; [`lever_arm`]), at least the initial
/// length and [`crate::dynamics::MIN_SIZE`].
/// Computed once per analysis of the set's topology ([`lever_arm`]).
pub(super) fn size(sides: &[Option<u32>; 2], levers: [f64; 2], initial_length: f64) -> f64 {
    let mut size = 0.0;
    for (slot, lever) in sides.iter().zip(levers) {
        if slot.is_some() {
            size += lever;
        }
    }
    size.max(initial_length).max(crate::dynamics::MIN_SIZE)
}

/// The lever arm \[m\] of a body's anchor `local_anchor` (in the body's frame) from its
/// centre of mass, at least the body's largest radius of gyration `√(I_max/m)`: fixed in
/// the body, whatever the body's pose. A joint at a body's centre of mass (a hinge through
/// a torso's middle, a wheel's axle) is judged on the body's own extent: a rod of length
/// `L` pinned at its end keeps its lever `L/2` (its radius of gyration is `L/√12`), a
/// 40 cm torso hinged at its middle gets 0.12 m, not nothing (its 6 mm parting as it landed
/// stopped the run as unstable, half of the 1 cm [`crate::dynamics::MIN_SIZE`]).
pub(super) fn lever_arm(
    body: &crate::rapier::dynamics::RigidBody,
    local_anchor: &nalgebra::Vector3<f64>,
) -> f64 {
    let mprops = &body.mass_properties().local_mprops;
    let com = crate::dynamics::convert::from_vec3(mprops.local_com);
    let inertia = crate::dynamics::convert::from_vec3(mprops.principal_inertia());
    let gyration = match mprops.mass() as f64 {
        m if m > 0.0 && m.is_finite() => (inertia.max() / m).sqrt(),
        _ => 0.0,
    };
    (local_anchor - com).norm().max(gyration)
}

/// The rates `J_s·(v, ω)` that the sides which are not dynamic (a kinematic body's
/// prescribed motion) give the joint; `watched[s]`: the pose of side `s` where it is not
/// dynamic.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn driven_rates(watched: [Option<&BodyPose>; 2], jac: &RateJacobians) -> Vector6<f64> {
    let mut driven = Vector6::zeros();
    for (s, pose) in watched.into_iter().enumerate() {
        // a dynamic side gives nothing here, nor a fixed body at rest (the ground of a scene
        // of pendulums)
        let Some(pose) = pose else { continue };
        if pose.linvel == Vector3::zeros() && pose.angvel == Vector3::zeros() {
            continue;
        }
        driven += jac.mul(s, &velocity6(pose));
    }
    driven
}

/// The joint's readout for this substep, written in place (the record is kilobytes per
/// joint); the transmitted force `applied` is written by the store stage once the impulse
/// is known. `frame`: the working frame `E` the rotation measure gave; `poses`: the bodies'
/// poses, whose anchors the readout reports.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn write_readout(
    j: &mut Kjoint,
    kin: &JointMotion,
    frame: &UnitQuaternion<f64>,
    poses: [&BodyPose; 2],
    out: &LawOutput,
    time: f64,
) {
    let quat = *frame;
    let (p1, p2) = kinematics::anchors(&j.frames, poses[0], poses[1]);
    let locked = j.law.lock.is_some();
    let energy = j.law.energy;
    let state = j.state.get_or_insert_with(JointState::empty);
    state.time = time;
    state.q = PerDof(kin.q);
    state.rate = PerDof(kin.rate);
    state.parts = PerDof(out.parts);
    state.force = PerDof(out.total);
    state.applied = PerDof([0.0; 6]);
    state.status = PerDof(out.status);
    // a stop the update engages before the DOF is beyond it (reached within the substep,
    // or a rigid stop holding it on it: `law::stop_prediction`) is in contact too: a door
    // held on its rigid limit read no contact while the limit carried it (a game's
    // trial, 2026-12-04, watching it for a slam's sound)
    for (st, side) in state.status.0.iter_mut().zip(j.predicted_stops.engaged) {
        if st.stop == StopContact::None && side != 0 {
            st.stop = if side > 0 {
                StopContact::Max
            } else {
                StopContact::Min
            };
        }
    }
    // (and a group of coupled stops, on each of its members)
    for (i, st) in state.status.0.iter_mut().enumerate() {
        let coupled = j.predicted_stops.coupled[i / 3] && j.property.dofs[i].coupled_stops;
        if st.stop == StopContact::None && coupled {
            st.stop = StopContact::Coupled;
        }
    }
    state.locked = locked;
    state.energy = energy;
    state.anchor1 = p1.into();
    state.anchor2 = p2.into();
    state.frame = [quat.i, quat.j, quat.k, quat.w];
    // (a joint without a connector copies nothing: the report is 400 bytes)
    let report = j.connector.report_ref();
    if report.is_some() || state.connector.is_some() {
        state.connector = *report;
    }
}

/// Writes the implicit block `G = h·(h·K_t/β + C_t)` of joint `ji`, with `kt` the diagonal
/// of `K_t` (predicted stops engaged) and `out` the law's output (its damping with the
/// unresolved DOFs' added). When the law's stiffness and damping have nothing off their
/// diagonals (every law but coupled stops and the connectors' tangents), `G` is their
/// diagonal, entry by entry the same arithmetic as the whole block: the symmetric part,
/// the block and the test of its entries are not formed. `diagonal`: the joint's laws
/// cannot write off the diagonal (no coupled stops, no connector: the law's outputs are
/// zeroed and only their diagonals written), so the 60 entries off the diagonals, which
/// are then +0, are not tested either (the contact scene's prepare stage 2.8 % shorter).
///
/// A free DOF's armature `a` ([`law::DofLaw::armature`], a rotor geared to it) adds `a` to
/// its diagonal: the rotor's force `F = a·q̈`, implicit over the substep, is the impulse
/// `P = −a·(q̇⁺ − q̇⁻) = −a·(J·Δv)`, a `G` term with no explicit part `h·Q`. It does the
/// work `P·(q̇⁻ + q̇⁺)/2 = −½·a·(q̇⁺² − q̇⁻²)` on the bodies, the change of the rotor's
/// kinetic energy, which the joint stores ([`law::JointEnergy::kinetic`], booked by the
/// prepare stage at the substep's start, where the law books its own).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn write_g(
    joints: &mut solve::SolverJoints,
    ji: usize,
    out: &LawOutput,
    kt: &Vector6<f64>,
    h: f64,
    diagonal: bool,
    armature: Option<&[f64; 6]>,
) {
    debug_assert!(
        !diagonal || (solve::is_diagonal(&out.stiffness) && solve::is_diagonal(&out.damping)),
        "a law without coupled stops or connector wrote off the diagonal"
    );
    if diagonal || (solve::is_diagonal(&out.stiffness) && solve::is_diagonal(&out.damping)) {
        let mut g = Vector6::from_fn(|i, _| h * (h / solve::BETA * kt[i] + out.damping[(i, i)]));
        if let Some(a) = armature {
            g += Vector6::from_column_slice(a);
        }
        joints.set_g_diagonal(ji, &g);
    } else {
        let mut full = 0.5 * (out.stiffness + out.stiffness.transpose());
        full.set_diagonal(kt);
        let mut g = h * (h / solve::BETA * full + out.damping);
        if let Some(a) = armature {
            for i in 0..6 {
                g[(i, i)] += a[i];
            }
        }
        joints.set_g(ji, &g);
    }
}

/// The velocity change rapier's contacts and joints gave the joint's bodies in the last
/// substep beyond the solve's prediction (`dv_contact`, [`super::ContactPrediction`]), taken
/// as recurring on the DOFs the substep resolves (`ω·h < 1`, as
/// [`solve::unresolved_damping`] judges them): `h·Q −= G·(J·δv)`, the implicit response
/// to a motion the contact will cancel again taken out of the impulse. Where the contact
/// holds the body still, the impulse is then `h·Q`, statics exact: a spring carrying a
/// wheel on the ground rests at `F/K` (it rested at `F·(1 + h·(h·K/β + C)·W)/K`). Left out:
/// the DOFs the substep does not resolve (blocked ones): there the lag of one substep in
/// the contact's response to the joint's own impulse makes a slow oscillation (a block on a
/// light foot: the joint went unstable); they keep part of the known limit of `F·h²/m` a
/// substep ([`super::held_axes`]).
/// Only for a diagonal `G` (every law but coupled stops and connectors).
///
/// The rotations the substep does not resolve (a blocked rotation, a servo beyond the
/// substep) take a share [`super::CONTACT_ROTATION_SHARE`] of the contact's change as
/// recurring: see there why (a flat foot's ankle, which carried the contact's moment only
/// through the foot's own inertia, `≈ β·I/h²`), why not all of it, and why only as far as
/// the island's weight `island_weight` explains the contact's impulse on the body. The
/// share's impulse turns a held body in the solve, and its anchor with it; the contact takes
/// that turn back, and the unresolved translations take it as recurring (see there, "the
/// anchor").
///
/// Along an axis the contacts hold a body ([`super::held_axes`]), the solve takes the body
/// `H` ([`super::HELD_MASS`]) times heavier with gravity's change `Δv_plain,a` taken out,
/// so that it sees the body move by its own `u_a` where the contact will keep it still:
/// `−u_a` is what the contact changes beyond the solve's view. The last substep measured
/// `δv_a = −(H·u_a + Δv_plain,a)` (held then: the apply stage gave the body `H·u_a`; or
/// not: `u_a = P_a·W_a/H` of the impulse the contact cancelled), so
/// `−u_a = (δv_a + Δv_plain,a)/H` is taken as recurring there instead of `δv_a`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn predict_contacts(
    sj: &mut solve::SolverJoint,
    sides: &[Option<u32>; 2],
    (dv_contact, held, gathered): (&[Vector6<f64>], &[u8], &[super::GatheredBody]),
    (kt, swing, w): (&Vector6<f64>, &Vector6<f64>, &Vector6<f64>),
    h: f64,
) {
    let mut dr = Vector6::zeros();
    // the part of `dr` from the bodies the contacts hold against gravity (a standing foot),
    // the only one the unresolved rotations take a share of
    let mut dr_held = Vector6::zeros();
    let mut any = false;
    for (s, slot) in sides.iter().enumerate() {
        if let Some(b) = slot {
            let b = *b as usize;
            let mut dv = dv_contact[b];
            let held = held[b];
            if held != 0 {
                for a in 0..3 {
                    if held & (1 << a) != 0 {
                        dv[a] = (dv[a] + gathered[b].dv_plain[a]) / super::HELD_MASS;
                    }
                }
            }
            if dv != Vector6::zeros() {
                let d = sj.jac.mul(s, &dv);
                if held != 0 {
                    // as far as the island's weight explains the contact's linear impulse
                    // ([`super::CONTACT_ROTATION_SHARE`], the gate: `d·1` is `d`)
                    dr_held += d * gathered[b].gate;
                }
                dr += d;
                any = true;
            }
        }
    }
    if !any {
        return;
    }
    // `h²·K·W` of each DOF: the substep resolves it where this is at most 1
    let stiffness: [f64; 6] = std::array::from_fn(|i| h * h * ((kt[i] + swing[i]) * w[i]));
    // the impulse the share moves the unresolved rotations by (below)
    let mut share = Vector6::zeros();
    for i in 0..6 {
        if stiffness[i] <= 1.0 {
            sj.explicit[i] -= sj.g_diagonal[i] * dr[i];
        } else if i >= 3 {
            // an unresolved rotation (a blocked one, a servo beyond the substep): a share
            // `ρ` of the change of the contacts that hold a side against gravity, whatever
            // `G` ([`super::CONTACT_ROTATION_SHARE`]).
            // The term's `−J·δv` in the system's right-hand side moves the impulse by
            // `−s·J·δv/(1/G + W)`, the share `s·G·W/(1 + G·W)` of what cancels `J·δv`
            // (`G·W > 1/3` here): `s` brings it to `ρ`
            let gw = sj.g_diagonal[i] * w[i];
            let s = (super::CONTACT_ROTATION_SHARE * (1.0 + gw) / gw).min(1.0);
            let term = sj.g_diagonal[i] * dr_held[i] * s;
            sj.explicit[i] -= term;
            share[i] = -term / (1.0 + gw);
        }
    }
    if share == Vector6::zeros() {
        return;
    }
    // The share's impulse `λ` is a couple: on a held side it turns the body in the solve
    // against the contact's turn, about the body's centre of mass, and the joint's anchor
    // on it moves with the turn (`−a_s × δω`); the unresolved translations took that as an
    // opening and pulled the other side along, but the contact takes the turn back, the
    // anchor with it, and the other side was left pulled: a gap
    // ([`super::CONTACT_ROTATION_SHARE`], "the anchor"). The change the contact will give
    // the body, `δω = −I⁻¹·(J_sᵀ·λ)_ω` (its mean inertia: a correction, and a foot's
    // principal moments are near each other), is taken as recurring on the unresolved
    // translations, whole, as the contact's own change is on the resolved DOFs.
    // The body's world inertia tensor in its place was worse (2026-12-07, f32 / f64):
    // Talos at 4 substeps 4.94 / 5.46 mm open (4.26 / 4.92), walker2d_v5 at 4 7.70 / 10.2
    // mm (6.74 / 8.50), over the walkers' 1 cm (not followed further: a capsule foot's
    // small moment about its long axis makes that turn large, which a line contact
    // perhaps does not take back as a flat foot's does).
    //
    // The share acts on rotations only (`λ = (0, λ_r)`), so the couple is
    // `J_sᵀ·λ = σ_s·(0, Rᵀ·λ_r)` and the anchor's rate on the translations
    // `(J_s·(0, δω))_t = σ_s·T·(−a_s × δω)` (`RateJacobians::tr_mul`, `mul`, without the
    // products of their zero halves).
    let unresolved: [bool; 3] = std::array::from_fn(|i| stiffness[i] > 1.0);
    if !(unresolved[0] || unresolved[1] || unresolved[2]) {
        return;
    }
    let couple = sj.jac.r.tr_mul(&Vector3::new(share[3], share[4], share[5]));
    for (side, slot) in sides.iter().enumerate() {
        let Some(b) = slot.map(|b| b as usize) else {
            continue;
        };
        let inertia = gathered[b].mean_inertia;
        if held[b] == 0 || inertia.is_nan() || inertia <= 0.0 {
            continue;
        }
        let sign = solve::RateJacobians::sign(side);
        let turn = couple * sign / -inertia;
        let anchor = sj.jac.t * -sj.jac.arm[side].cross(&turn) * sign;
        for i in 0..3 {
            if unresolved[i] {
                sj.explicit[i] -= sj.g_diagonal[i] * anchor[i];
            }
        }
    }
}
