//! The energy that the stiff parts of a free DOF's law store: an independent stop in
//! contact, the sensor lock, the friction spring. The substep scales it to the stiffness the
//! implicit update realises (`K̃ = K/(1 + h²·K·w/β)`, `dynamics::solve::realised_stiffness`),
//! which the law cannot know.

use super::kjoint2::stop_stiffness;
use super::{BlockedStiffness, Dof, DofStatus, Kjoint2Property, LawState, StopContact};

/// Energy \[J\] stored on the free DOF `dof` at `q` by its stop (independent, in contact,
/// without friction: `½·k_s·(q − SD)²`), its sensor lock (`½·K_b·(q − q_s)²`) and its
/// friction spring (`½·s²/Kf`, the stop when friction is active), as the law books them in
/// [`super::JointEnergy::elastic`] after an evaluation that gave `status`. Coupled stops
/// are not included (their energy is shared by the DOFs of the family).
pub fn stored_energy_of_dof(
    prop: &Kjoint2Property,
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
    if law.friction_active() {
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
    if let Some(lock) = &state.lock {
        let d = q - lock[i];
        e += 0.5 * kb * d * d;
    }
    if e.is_finite() {
        e
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::{evaluate, LawParams};
    use crate::{DofLaw, JointType};

    /// The energy of a stop in contact and of a lock, as the law books them: the law's
    /// elastic energy minus the blocked DOFs' `½·K_b·q²` equals this function's sum.
    #[test]
    fn equals_what_the_law_books_for_a_stop_and_a_lock() {
        let prop = Kjoint2Property::new(JointType::Revolute)
            .with_dof(Dof::Rx, DofLaw::default().with_stops(-0.2, 0.1));
        let params = LawParams {
            blocked: BlockedStiffness {
                translational: 1e6,
                rotational: 1e4,
            },
            reduced_mass: 1.0,
            reduced_inertia: 0.1,
        };
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
        // locked at 0.15, then moved to 0.17: the stop (0.07 in) and the lock (0.02)
        let _ = evaluate(&prop, &params, &q, &rate, true, &mut st);
        q[rx] = 0.17;
        let out = evaluate(&prop, &params, &q, &rate, true, &mut st);
        let e = stored_energy_of_dof(&prop, &params.blocked, &out.status[rx], &st, Dof::Rx, q[rx]);
        let want = 0.5 * 1e4 * (0.07f64.powi(2) + 0.02f64.powi(2));
        assert!((e - want).abs() < 1e-9, "{e} vs {want}");
        assert!((st.energy.elastic - blocked_energy(&q) - e).abs() < 1e-9);
    }
}
