//! The energy that the stiff parts of a free DOF's law store: an independent stop in
//! contact, the sensor lock, the friction spring, and a coupled stop in contact. The
//! substep scales it to the stiffness the implicit update realises
//! (`K̃ = K/(1 + h²·K·w/β)`, `dynamics::solve::realised_stiffness`), which the law cannot
//! know (docs/kjoint2.md §4.8).

use super::kjoint2::{coupled_group, stop_stiffness};
use super::{
    BlockedStiffness, Dof, DofStatus, FrictionStatus, KjointProperty, LawState, StopContact,
};

/// Energy \[J\] stored on the free DOF `dof` at `q` by its stop (independent, in contact,
/// without friction: `½·k_s·(q − SD)²`), its sensor lock (`½·K_b·(q − q_s)²`) and its
/// friction spring (`½·s²/Kf`, the stop when friction is active), as the law books them in
/// [`super::JointEnergy::elastic`] after an evaluation that gave `status`. Coupled stops
/// are not included (their energy is shared by the DOFs of the family).
pub fn stored_energy_of_dof(
    prop: &KjointProperty,
    blocked: &BlockedStiffness,
    status: &DofStatus,
    state: &LawState,
    dof: Dof,
    q: f64,
) -> f64 {
    let i = dof.index();
    let law = &prop.dofs[i];
    let kb = blocked.of(dof);
    let mut e = 0.0;
    // While a sensor lock holds the DOF (docs/kjoint2.md §4.5) its friction spring and stop
    // no longer act (the status says so: no friction state, no stop contact) and the lock
    // spring alone is stiff; the held force and the energy of the activation are not a
    // stiffness (`SensorLock::held_released`).
    if law.friction_active() && status.friction != FrictionStatus::None {
        let s = state.friction_force[i];
        if law.friction_stiffness > 0.0 {
            e += 0.5 * s * s / law.friction_stiffness;
        }
    } else if !law.coupled_stops {
        let stop = match status.stop {
            StopContact::Max => Some(law.stop_max),
            StopContact::Min => Some(law.stop_min),
            _ => None,
        };
        if let Some(sd) = stop {
            let ks = stop_stiffness(law.friction_stiffness, kb);
            e += 0.5 * ks * (q - sd) * (q - sd);
        }
    }
    if let Some(lock) = state.lock.as_deref() {
        let d = q - lock.values[i];
        e += 0.5 * kb * d * d;
    }
    if e.is_finite() {
        e
    } else {
        0.0
    }
}

/// The coupled stop in contact of the family whose first DOF is `first` (0: the
/// translations, 3: the rotations), if any: its energy `½·k_s·(d − R)²` \[J\] as the law
/// books it, its stiffness `k_s` and the unit direction `n` (per DOF, zero outside the
/// group) along which it acts, `d = |q_c − c|` over the group's DOFs. Without friction only
/// (with it the friction springs are the stop, in [`stored_energy_of_dof`]).
///
/// A plain function the substep inlines, one family at a time (an iterator over both
/// families had its closures compiled out of line, without the substep's AVX2, once the
/// substep's function grew).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn coupled_stop_contact(
    prop: &KjointProperty,
    blocked: &BlockedStiffness,
    q: &[f64; 6],
    first: usize,
) -> Option<(f64, f64, [f64; 6])> {
    let free = prop.joint_type.free_dofs();
    let g = coupled_group(prop, &free, first)?;
    let members = &g.members[..g.len];
    let law = &prop.dofs[members[0]];
    if law.friction_active() {
        return None;
    }
    // (the squares summed from 0 as `Iterator::sum` does from −0: the same bits, the squares
    // being ≥ +0)
    let mut d2 = 0.0;
    for &i in members {
        d2 += (q[i] - g.centre).powi(2);
    }
    let d = d2.sqrt();
    if !(d > g.radius && d > 0.0) {
        return None;
    }
    let ks = stop_stiffness(law.friction_stiffness, blocked.of(Dof::ALL[members[0]]));
    let mut n = [0.0; 6];
    for &i in members {
        n[i] = (q[i] - g.centre) / d;
    }
    let pen = d - g.radius;
    Some((0.5 * ks * pen * pen, ks, n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::{evaluate, LawParams};
    use crate::{DofLaw, JointType};

    /// Kn = 1e6 N/m, KR = 1e4 N·m/rad.
    fn params() -> LawParams {
        LawParams {
            blocked: BlockedStiffness {
                translational: 1e6,
                rotational: 1e4,
            },
            reduced_mass: 1.0,
            reduced_inertia: 0.1,
        }
    }

    /// The energy of a stop in contact and of a lock, as the law books them: the law's
    /// elastic energy minus the blocked DOFs' `½·K_b·q²` equals this function's sum.
    #[test]
    fn equals_what_the_law_books_for_a_stop_and_a_lock() {
        let prop = KjointProperty::new(JointType::Revolute)
            .with_dof(Dof::Rx, DofLaw::default().with_stops(-0.2, 0.1));
        let params = params();
        let rx = Dof::Rx.index();
        let mut q = [1e-4, -2e-4, 0.0, 0.15, 1e-3, 0.0];
        let rate = [0.0; 6];
        let blocked_energy = |q: &[f64; 6]| {
            (0..6)
                .filter(|&i| i != rx)
                .map(|i| 0.5 * params.blocked.of(Dof::ALL[i]) * q[i] * q[i])
                .sum::<f64>()
        };
        let mut st = LawState::default();
        let out = evaluate(&prop, &params, &q, &rate, false, &mut st);
        let e = stored_energy_of_dof(&prop, &params.blocked, &out.status[rx], &st, Dof::Rx, q[rx]);
        // the stop alone: ½·KR·0.05²
        assert!((e - 0.5 * 1e4 * 0.05 * 0.05).abs() < 1e-9, "{e}");
        assert!((st.energy.elastic - blocked_energy(&q) - e).abs() < 1e-9);
        // locked at 0.15 (the stop 0.05 in, carrying KR·0.05 = 500), then moved to 0.17: the
        // lock holds the stop's force and energy (docs/kjoint2.md §4.5), and its own spring
        // (0.02) is the only stiff part
        let out = evaluate(&prop, &params, &q, &rate, true, &mut st);
        let e = stored_energy_of_dof(&prop, &params.blocked, &out.status[rx], &st, Dof::Rx, q[rx]);
        assert!(
            (e - 0.5 * 1e4 * 0.05 * 0.05).abs() < 1e-9,
            "at activation: the stop, {e}"
        );
        q[rx] = 0.17;
        let out = evaluate(&prop, &params, &q, &rate, true, &mut st);
        let e = stored_energy_of_dof(&prop, &params.blocked, &out.status[rx], &st, Dof::Rx, q[rx]);
        let want = 0.5 * 1e4 * 0.02f64.powi(2);
        assert!((e - want).abs() < 1e-9, "{e} vs {want}");
        let held = 0.5 * 1e4 * 0.05f64.powi(2) + 500.0 * 0.02;
        assert!((st.energy.elastic - blocked_energy(&q) - held - e).abs() < 1e-9);
    }

    /// A conical stop (coupled ry, rz of a spherical joint, ±0.2 rad) reached at
    /// (0.18, 0.16): d = 0.2408, ½·KR·(d − 0.2)² along n = (0.18, 0.16)/d, as the law books.
    #[test]
    fn a_coupled_stop_in_contact_equals_what_the_law_books() {
        let cone = DofLaw::default().with_stops(-0.2, 0.2).with_coupled_stops();
        let prop = KjointProperty::new(JointType::Spherical)
            .with_dof(Dof::Ry, cone.clone())
            .with_dof(Dof::Rz, cone);
        let params = params();
        let q = [0.0, 0.0, 0.0, 0.0, 0.18, 0.16];
        let mut st = LawState::default();
        let _ = evaluate(&prop, &params, &q, &[0.0; 6], false, &mut st);
        let contacts: Vec<_> = [0, 3]
            .into_iter()
            .filter_map(|first| coupled_stop_contact(&prop, &params.blocked, &q, first))
            .collect();
        assert_eq!(contacts.len(), 1);
        let (e, ks, n) = contacts[0];
        let d = (0.18f64.powi(2) + 0.16f64.powi(2)).sqrt();
        assert!((e - 0.5 * 1e4 * (d - 0.2).powi(2)).abs() < 1e-12, "{e}");
        assert_eq!(ks, 1e4);
        assert!((n[4] - 0.18 / d).abs() < 1e-12 && (n[5] - 0.16 / d).abs() < 1e-12);
        assert!(
            (st.energy.elastic - e).abs() < 1e-9,
            "law {}",
            st.energy.elastic
        );
    }
}
