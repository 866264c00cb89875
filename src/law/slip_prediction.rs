//! A sticking friction spring that the substep would load beyond its cap slips from the
//! start of the substep (docs/kjoint2.md §4.4, §4.6).
//!
//! The law (§4.4) is explicit: it sees a friction spring slip at the evaluation after its
//! trial force passed the cap. Radioss' time step is short enough for that; a substep of
//! the implicit update is not. While the spring sticks, the update takes the DOF as held
//! by the stiffness `K_f`, with the critical damping of a sticking spring (§4.6) and, where
//! the substep does not resolve `K_f`, the update's numerical damping `c_num = h·K_f·s`
//! ([`crate::dynamics`]'s unresolved damping): a hinge of `K_f` = 1e6 N·m/rad and a
//! friction moment of 5 N·m on a 20 kg door turning at 3 rad/s transmitted 2412 N·m in the
//! substep it started to move, braking the door to 1.55 rad/s in 1/480 s, where friction
//! can take 0.006 rad/s; 11.5 J of its 19.2 J went to `numerical` (a user trial,
//! 2026-12-04).
//!
//! # Law
//! For one DOF of effective inverse mass `W` (`J·M⁻¹·Jᵀ`'s diagonal), tangent stiffness
//! `K_t` and damping `C_t` (the numerical damping included), the update's impulse is
//! `P = −h·F − G·Δq̇` with `G = h·(h·K_t/β + C_t)` and `Δq̇ = W·P` (the DOF alone), so the
//! force it transmits over the substep is
//!
//! ```text
//! T = F/(1 + W·G).
//! ```
//!
//! The sticking friction spring's share of `F` beyond the law is its force `s` and the
//! numerical damping its unresolved stiffness brings, `c_num·q̇` (the critical damping
//! `c_c` of a sticking spring, §4.6, is the law's: a damper beside the spring, not capped
//! with it, as in Radioss). Where
//!
//! ```text
//! |T_f| = |s + c_num·q̇| / (1 + W·G)  >  cap
//! ```
//!
//! the spring cannot hold the DOF within its cap over the substep: it **slips from the
//! start of the substep**, transmitting `sign(T_f)·cap`, with neither its stiffness `K_f`
//! nor the critical damping of a sticking spring in the tangent (the update's numerical
//! damping then has no `K_f` to damp). Otherwise it sticks, as the law says. A spring the
//! substep resolves (`c_num = 0`) has `|T_f| ≤ |s| ≤ cap`: it is the law's, which sees it
//! slip at the evaluation after its trial force passed the cap, one substep of `c_c·q̇`
//! at most (at `K_f` = 1e5 the door above lost 0.6 J so).
//!
//! `W` is the diagonal's, at least the DOF's effective inverse mass once the joint's other
//! DOFs hold (a door's hinge: 0.94 against 0.23 1/(kg·m²)), so `T_f` is at most the force
//! the update transmits: a slip is never predicted where the spring would hold the DOF
//! within its cap. Nor does a predicted slip reverse the DOF: with `s` within the cap,
//! `|T_f| > cap` needs `c_num·|q̇| > cap·W·G ≥ cap·W·h·c_num`, so `|q̇| > cap·W·h`, more
//! than the rate the cap takes out of the DOF over the substep, `cap·W_eff·h`.
//!
//! The law's own state is left as the law set it (the spring force `s`, which its next
//! evaluation loads on and caps, booking the slip's work then); what the update uses, the
//! output's force, tangents and status, and the force the law's next evaluation takes as
//! this one's in its trapezoidal work, are the slip's. Not predicted: a DOF in a stop
//! (the friction spring is the stop, §4.2) or locked by a sensor.

use super::{FrictionStatus, KjointProperty, LawOutput, LawState, StopContact};

/// Holds each sticking friction spring of `out` (the law's output at rates `rate`, whose
/// state `state` the law just wrote) to its cap over a substep `h` of the implicit update
/// of bound `beta`, where the update would pass more (module docs). `w`: each DOF's
/// effective inverse mass `W` (1/kg or 1/(kg·m²)); `c_num`: the update's numerical damping
/// of each DOF; `c_friction`: the part of it the friction spring's `K_f` brings (`c_num`
/// less what the DOF's other stiffness alone would get: a rotation under tension or a stiff
/// spring beside a resolved `K_f` is not the spring's to hold); `kt`: the diagonal of the tangent stiffness the update uses, lowered by
/// `K_f` where a slip is predicted. Returns whether a slip was predicted (the caller's
/// numerical damping, computed from `kt`, is then to be computed again).
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn predict_slips(
    prop: &KjointProperty,
    out: &mut LawOutput,
    state: &mut LawState,
    rate: &[f64; 6],
    w: &[f64; 6],
    c_num: &[f64; 6],
    c_friction: &[f64; 6],
    kt: &mut [f64; 6],
    h: f64,
    beta: f64,
) -> bool {
    let mut any = false;
    for i in 0..6 {
        let st = &out.status[i];
        if st.friction != FrictionStatus::Stick || st.stop != StopContact::None || st.locked {
            continue;
        }
        // the KJOINT2 law's friction spring only (a connector's friction, which reports in
        // the same status, is its own law's)
        let law = &prop.dofs[i];
        if !law.friction_active() {
            continue;
        }
        let kf = law.friction_stiffness;
        let cap = out.friction_cap[i];
        let cc = out.critical_damping[i];
        let g = h * (h * kt[i] / beta + out.damping[(i, i)] + c_num[i]);
        let t = (out.parts[i].friction + c_friction[i] * rate[i]) / (1.0 + w[i] * g);
        if !(t.abs() > cap && t.is_finite()) {
            continue;
        }
        let p = &mut out.parts[i];
        // (the law's own force and damping by their change: `out` may hold a connector's
        // parts too, which the law's state does not)
        let change = t.signum() * cap - p.friction - cc * rate[i];
        p.friction = t.signum() * cap;
        p.damping -= cc * rate[i];
        out.damping[(i, i)] -= cc;
        out.stiffness[(i, i)] -= kf;
        kt[i] -= kf;
        out.critical_damping[i] = 0.0;
        out.status[i].friction = FrictionStatus::Slip;
        out.total[i] = p.total();
        state.prev_force[i] += change;
        state.prev_damping[i] -= cc * rate[i];
        state.prev_critical[i] = 0.0;
        any = true;
    }
    any
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::{evaluate, BlockedStiffness, LawParams};
    use crate::{Dof, DofLaw, JointType};

    /// A hinge with a friction spring `kf` and a friction moment of 5 N·m, evaluated at rest
    /// on its first call and then turning at `omega` [rad/s].
    fn door(kf: f64, omega: f64) -> (KjointProperty, LawOutput, LawState) {
        let prop = KjointProperty::new(JointType::Revolute)
            .with_kn(1e6)
            .with_dof(Dof::Rx, DofLaw::default().with_friction(kf, 5.0));
        let params = LawParams {
            blocked: BlockedStiffness {
                translational: 1e6,
                rotational: 1e6,
            },
            reduced_mass: 20.0,
            reduced_inertia: 1.07,
        };
        let mut state = LawState::default();
        let mut rate = [0.0; 6];
        rate[3] = omega;
        let out = evaluate(&prop, &params, &[0.0; 6], &rate, false, &mut state);
        (prop, out, state)
    }

    #[test]
    fn a_spring_that_would_pass_its_cap_slips_at_the_cap() {
        let (h, w) = (1.0 / 480.0, [0.94; 6]);
        let (prop, mut out, mut state) = door(1e6, 3.0);
        assert_eq!(out.status[3].friction, FrictionStatus::Stick);
        let cc = out.critical_damping[3];
        assert!(cc > 0.0);
        // the update's numerical damping of the unresolved `K_f`: h·K_f
        let mut c_num = [0.0; 6];
        c_num[3] = h * 1e6;
        let mut kt: [f64; 6] = std::array::from_fn(|i| out.stiffness[(i, i)]);
        let k_before = kt[3];
        let d_before = out.damping[(3, 3)];
        let mut rate = [0.0; 6];
        rate[3] = 3.0;
        assert!(predict_slips(
            &prop, &mut out, &mut state, &rate, &w, &c_num, &c_num, &mut kt, h, 3.0
        ));
        assert_eq!(out.status[3].friction, FrictionStatus::Slip);
        assert_eq!(out.parts[3].friction, 5.0);
        assert_eq!(
            out.total[3], 5.0,
            "the friction alone: no viscosity, no spring"
        );
        assert_eq!(kt[3], k_before - 1e6);
        assert_eq!(out.stiffness[(3, 3)], kt[3]);
        assert!((out.damping[(3, 3)] - (d_before - cc)).abs() < 1e-12);
        assert_eq!(state.prev_force[3], 5.0);
        // the law's own spring state is the law's (it caps it at its next evaluation)
        assert_eq!(state.friction_force[3], 0.0);
        // the blocked DOFs are untouched
        assert!(out.total[0] == 0.0 && out.status[0].blocked);
    }

    #[test]
    fn a_spring_that_holds_within_its_cap_sticks() {
        // 1e-4 rad/s: the stick transmits c_num·q̇/(1 + W·G) ≈ 0.03 N·m < 5 N·m
        let (h, w) = (1.0 / 480.0, [0.94; 6]);
        let (prop, mut out, mut state) = door(1e6, 1e-4);
        let mut c_num = [0.0; 6];
        c_num[3] = h * 1e6;
        let mut kt: [f64; 6] = std::array::from_fn(|i| out.stiffness[(i, i)]);
        let before = (out.clone(), kt);
        let mut rate = [0.0; 6];
        rate[3] = 1e-4;
        assert!(!predict_slips(
            &prop, &mut out, &mut state, &rate, &w, &c_num, &c_num, &mut kt, h, 3.0
        ));
        assert_eq!((out, kt), before);
    }

    #[test]
    fn a_predicted_slip_needs_more_rate_than_the_cap_takes_out_in_a_substep() {
        // the bound of the module docs: wherever a slip is predicted, |q̇| > cap·W·h
        let h = 1.0 / 240.0;
        for kf in [1e2, 1e4, 1e6, 1e9] {
            for w in [0.01, 1.0, 100.0] {
                for omega in [1e-6, 1e-4, 1e-2, 1.0, 10.0] {
                    let (prop, mut out, mut state) = door(kf, omega);
                    let mut kt: [f64; 6] = std::array::from_fn(|i| out.stiffness[(i, i)]);
                    let mut c_num = [0.0; 6];
                    // the numerical damping of an unresolved K_f, as the update gives it
                    c_num[3] = if kf * w * h * h > 4.0 { h * kf } else { 0.0 };
                    let mut rate = [0.0; 6];
                    rate[3] = omega;
                    let slipped = predict_slips(
                        &prop, &mut out, &mut state, &rate, &[w; 6], &c_num, &c_num, &mut kt, h,
                        3.0,
                    );
                    assert!(
                        !slipped || omega > 5.0 * w * h,
                        "kf {kf} w {w} ω {omega}: slip predicted below cap·W·h"
                    );
                }
            }
        }
    }
}
