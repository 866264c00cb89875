//! Stops that engage on the position a DOF is predicted to reach by the end of the substep
//! (docs/kjoint2.md §4.2).
//!
//! A stop of the law acts once `q` is beyond it (`q > SD+`). With a substep `h` much longer
//! than the explicit time step of Radioss, a DOF arriving at its stop with rate `q̇` would
//! pass it by up to `q̇·h` before the stop is even seen (a robot's light wrist swinging into
//! its URDF limit at 20 rad/s overruns it by 0.08 rad at 240 Hz). This module gives the
//! substep the stop contact it will have at the end of the substep, the way rapier's
//! speculative contacts do.
//!
//! # Law
//! For a free DOF with an independent stop `SD+ > 0`, still inside it (`q ≤ SD+`), whose
//! predicted position `q + h·q̇` is beyond it by `g = q + h·q̇ − SD+ > 0`, the substep adds
//!
//! ```text
//! F_s = k_s·g/β,      ∂F_s/∂q = k_s           (β the bound of the implicit update, 3)
//! ```
//!
//! (`k_s` the law's stop stiffness: `Kf` when > 0, else `Kn`/`KR`), and symmetrically at
//! `SD- < 0`. Derivation: the implicit update of one DOF of mass `m` gives
//! `m·Δq̇ = −h·F_s − (h²·k_s/β)·Δq̇`; for a stop stiffer than the substep resolves
//! (`h²·k_s ≫ m`) that is `Δq̇ = −β·F_s/(h·k_s) = −g/h`, so the DOF ends the substep exactly
//! on its stop (`q + h·(q̇ + Δq̇) = SD+`): no overrun, no rebound. A soft stop
//! (`h²·k_s ≪ m`) only starts decelerating the DOF a substep early by `h·k_s·g/(β·m)`, which
//! the next substep, in contact, takes over.
//!
//! # Holding a DOF on its stop
//! `q̇` is the rate at the start of the substep: what gravity and the other joints will add
//! to it is only known after the solve (a link resting on its stop has `q̇ ≈ 0` and is
//! pushed onto the stop by the joint it hangs from). So a stop that acted over the previous
//! substep (in contact, or predicted) **stays engaged** while the DOF is inside it, with the
//! same `F_s = k_s·g/β` even when `g < 0`: the DOF then ends the substep on its stop rather
//! than leaving it for a substep and falling back into it (a resting link would otherwise
//! bounce on its stop for ever, two substeps in four off it). Only a stop the substep does
//! not resolve is held (`ω·h > 1`, `ω² = k_s·W` with `W` the DOF's effective inverse mass):
//! a resolved stop's rebound is the law's own elastic dynamics, and holding it pulled a
//! rebounding DOF back towards the stop (a rod bouncing off a soft stop took −14 N·m, a
//! pull, in the substep it left). The held stop releases as soon as the stop's share of the
//! force the joint transmitted over the previous substep on that DOF pulled towards the stop:
//! `F − F_law ≤ 0` at `SD+`, `≥ 0` at `SD-`, with `F_law` the law's own force on the DOF
//! other than its stop's (springs, friction, damping, motor) at the substep's start. A load
//! pulling the DOF off its stop frees it one substep later; the law's own spring frees it at
//! once. (With `F` alone, a drawer whose return spring pulled it off its rigid stop stayed
//! on the stop for good: held there, the joint transmitted nothing along the slide, the
//! spring's pull and the held stop's cancelling, and a transmitted force of round-off
//! kept it held; a mechanism designer's trial, 2026-12-05.) Nothing is added while the DOF is
//! beyond the stop (the law's stop acts) or while it is locked by a sensor.
//!
//! # Rigid stops
//! A stop whose stiffness is the implicit rule's automatic one (`Kn = 0` outside Radioss
//! decks, [`crate::law::stiffness`]) and that has no friction spring (`Kf`) stands for a
//! limit, as rapier's joint limits and URDF limits are: it should stop the DOF, not
//! bounce it back. The automatic stiffness alone does not: it is `ω·h = 4` at most against
//! the load side, so a DOF arriving at its stop ends the substep a sixth of its overrun
//! beyond it, and the law's spring pushes it back out (a 20 kg door swung into its stop at
//! 1 rad/s left it at 0.025–0.05 rad/s at 4 substeps); and far from the origin or with
//! many substeps the f32 noise bound lowered it (before its floor `κ = 4`) until the
//! substep resolved it, and the stop was an elastic spring with the light damping
//! `Cr = 0.05` (at 16 substeps the door rebounded at 0.47 rad/s, a 5 kg drawer at
//! 0.94 m/s of 1 m/s, where rapier's limits stop both). Such a stop is engaged here with the stiffness
//! `k_s = max(k_s, RIGID_STOP/(h²·W))` (`RIGID_STOP` = 1e5), whenever the DOF is predicted to
//! end the substep beyond it, in contact or not, and held as an unresolved stop is: the
//! update then ends the substep on the stop (`Δq̇ = −g/h` to within
//! `β·I/(RIGID_STOP·(1/W))`, `I` the DOF's effective inertia, which the blocked DOFs and
//! the other joints make larger than the diagonal's `1/W`), as a limit of a constraint
//! solver with no restitution does. The law's stop spring still acts beyond the stop (its
//! readout), but the DOF is not left beyond it. Radioss decks keep the law's stop springs
//! ([`crate::law::AutomaticStiffness::Radioss`]), as do stops of a user `Kn` or `Kf`: a
//! stiffness the user gives is the stop's.
//!
//! # Coupled stops
//! A group of coupled stops (`Icomb = 1`, docs/kjoint2.md §4.3: the members' offsets `u = q −
//! c` from the centre held within the radius `R`, a cone limit on two rotations) is
//! predicted the same way along its normal: with `p = u + h·u̇` the predicted offset and
//! `n = p/|p|`, a group inside (`|u| ≤ R`) predicted beyond (`|p| > R`) gets
//!
//! ```text
//! F_s = (k_s·g/β)·n,    ∂F_s/∂q = k_s·n·nᵀ,    g = |p| − R
//! ```
//!
//! which ends the substep on the stop along `n` (the derivation above, along `n`, with
//! `W_n = Σ n_i²·W_i`), and leaves the motion along the rim free: a rank-one tangent, not
//! `k_s` on each member, which would stiffen the slide around the cone as much as the stop.
//! A group that acted is held while the stop's share of the force the joint transmitted
//! along the present normal, `Σ (F_i − F_law,i)·n_i`, pushed it off the stop, and a group of the implicit rule's automatic
//! stiffness without `Kf` is rigid as above (`k_s ≥ RIGID_STOP/(h²·W_n)`). Before they were
//! predicted, a rod swung into a cone of 0.5 rad at 2 rad/s came back off it at 0.48 rad/s
//! at 4 substeps and 0.89 at 16, where a hinge's independent stops held it within 0.11.
//!
//! # Energy
//! The predicted stop stores nothing (`q` is inside the stop); the work its force does is what
//! the substep's energy book calls numerical work (the inelastic part of an impact the
//! substep cannot resolve).

use super::kjoint2::{coupled_group, stop_stiffness};
use super::{AutomaticStiffness, BlockedStiffness, Dof, KjointProperty};

/// `k·W·h²` of the stiffness a rigid stop engages with (module docs, "Rigid stops"): with
/// the implicit update's `β = 3` a DOF whose effective inertia is up to 300 times that of
/// its own diagonal `1/W` still ends the substep within 1 % of its stop.
pub const RIGID_STOP: f64 = 1e5;

/// What the stop prediction of one joint reads, for a substep of `h` \[s\] of an implicit
/// update of bound `beta` (see the module docs): `transmitted` is the force the joint
/// transmitted on each DOF over the previous substep (law's sign), `law` the law's own force
/// other than its stops' at the substep's start; `inv_mass` each DOF's
/// effective inverse mass `W` (`J·M⁻¹·Jᵀ`'s diagonal, 1/kg or 1/(kg·m²)), which tells
/// whether a stop is one the substep resolves; `locked`: a sensor lock holds the joint.
#[derive(Debug, Clone, Copy)]
pub struct StopInput<'a> {
    /// The joint's property.
    pub prop: &'a KjointProperty,
    /// Its blocked stiffness (the stops' stiffness without `Kf`).
    pub blocked: &'a BlockedStiffness,
    /// The DOFs' values \[m or rad\].
    pub q: &'a [f64; 6],
    /// Their rates \[m/s or rad/s\].
    pub rate: &'a [f64; 6],
    /// The force transmitted over the previous substep \[N or N·m\].
    pub transmitted: &'a [f64; 6],
    /// The law's force other than its stops' (springs, friction, damping, motor) at the
    /// substep's start \[N or N·m\], law's sign: what of `transmitted` was not the stop's.
    pub law: &'a [f64; 6],
    /// The effective inverse masses `W`.
    pub inv_mass: &'a [f64; 6],
    /// The substep \[s\].
    pub h: f64,
    /// The implicit update's bound `β`.
    pub beta: f64,
    /// A sensor lock holds the joint.
    pub locked: bool,
}

/// The predicted stop of one DOF: force `F_s` \[N or N·m\] (in the law's sign: positive
/// pushes `q` down) and tangent stiffness `k_s` [N/m or N·m/rad]. Zero when no stop is
/// predicted.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct PredictedStop {
    /// `F_s` \[N or N·m\], in the law's sign.
    pub force: f64,
    /// `k_s` [N/m or N·m/rad]; 0: no stop predicted.
    pub stiffness: f64,
}

/// Which stop of each DOF acted over the previous substep: `1` at `SD+`, `-1` at `SD-`,
/// `0` none.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct StopPredictionState {
    /// Per DOF: `1` at `SD+`, `-1` at `SD-`, `0` none.
    pub engaged: [i8; 6],
    /// Per family (translations, rotations): its coupled stops acted.
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub coupled: [bool; 2],
}

/// The predicted stop of a group of coupled stops (module docs, "Coupled stops"): the force
/// `F_s·n_i` on each member and the tangent `k_s·n·nᵀ`. Zero stiffness: none.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PredictedCoupledStop {
    /// The group's DOFs, `members[..len]`.
    pub members: [usize; 3],
    /// How many.
    pub len: usize,
    /// The unit normal `n = p/|p|` at the predicted offset, over the members.
    pub normal: [f64; 3],
    /// `F_s = k_s·g/β` along `n` \[N or N·m\], in the law's sign (positive pushes the
    /// offset towards the centre).
    pub force: f64,
    /// `k_s` [N/m or N·m/rad]; 0: no stop predicted.
    pub stiffness: f64,
}

/// The predicted coupled stops of the two families (translations, rotations) over a
/// substep: [`predicted_stops`] for the groups of coupled stops (module docs, "Coupled
/// stops").
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn predicted_coupled_stops(
    input: &StopInput,
    state: &mut StopPredictionState,
) -> [PredictedCoupledStop; 2] {
    let (prop, q, rate, h) = (input.prop, input.q, input.rate, input.h);
    let mut out = [PredictedCoupledStop::default(); 2];
    if input.locked || !prop.has_coupled_stops() {
        state.coupled = [false; 2];
        return out;
    }
    let free = prop.joint_type.free_dofs();
    let rigid_rule = prop.automatic_stiffness() && prop.automatic == AutomaticStiffness::Implicit;
    for (f, first) in [0, 3].into_iter().enumerate() {
        let was = std::mem::take(&mut state.coupled[f]);
        let Some(c) = coupled_group(prop, &free, first) else {
            continue;
        };
        let members = &c.members[..c.len];
        let law = &prop.dofs[members[0]];
        // the offsets from the centre, now (`u`) and predicted (`p`), 0 past the members
        let u: [f64; 3] = std::array::from_fn(|a| members.get(a).map_or(0.0, |&i| q[i] - c.centre));
        let p: [f64; 3] =
            std::array::from_fn(|a| members.get(a).map_or(0.0, |&i| u[a] + h * rate[i]));
        let norm = |v: &[f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let (d, dp) = (norm(&u), norm(&p));
        if dp <= 0.0 {
            continue;
        }
        let n: [f64; 3] = std::array::from_fn(|a| p[a] / dp);
        // the effective inverse mass along n (of the diagonal, as for one DOF)
        let w_n: f64 = members
            .iter()
            .zip(n)
            .map(|(&i, n)| n * n * input.inv_mass[i])
            .sum();
        let rigid = rigid_rule && law.friction_stiffness <= 0.0 && w_n > 0.0;
        let ks = stop_stiffness(
            law.friction_stiffness,
            input.blocked.of(Dof::ALL[members[0]]),
        );
        let ks = if rigid {
            ks.max(RIGID_STOP / (h * h * w_n))
        } else {
            ks
        };
        let unresolved = ks * w_n * h * h > 1.0;
        // held where it acted and the joint pushed the offset off the stop along the
        // present normal
        let pushed: f64 = if d > 0.0 {
            members
                .iter()
                .zip(u)
                .map(|(&i, u)| (input.transmitted[i] - input.law[i]) * u / d)
                .sum()
        } else {
            0.0
        };
        let held = unresolved && was && pushed > 0.0;
        let engage = if rigid && (dp > c.radius || held) {
            true
        } else if d > c.radius {
            state.coupled[f] = true;
            continue; // in contact: the law's stop acts
        } else {
            dp > c.radius || held
        };
        if !(engage && ks > 0.0 && ks.is_finite()) {
            continue;
        }
        state.coupled[f] = true;
        out[f] = PredictedCoupledStop {
            members: c.members,
            len: c.len,
            normal: n,
            force: ks * (dp - c.radius) / input.beta,
            stiffness: ks,
        };
    }
    out
}

/// The predicted independent stops of every DOF over a substep ([`StopInput`], module docs);
/// `state` records which stops act.
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn predicted_stops(input: &StopInput, state: &mut StopPredictionState) -> [PredictedStop; 6] {
    let (prop, blocked, q, rate) = (input.prop, input.blocked, input.q, input.rate);
    let (transmitted, inv_mass) = (input.transmitted, input.inv_mass);
    // the stop's share of what the joint transmitted (module docs, "Holding a DOF")
    let stop_share = |i: usize| transmitted[i] - input.law[i];
    let (h, beta, locked) = (input.h, input.beta, input.locked);
    let mut out = [PredictedStop::default(); 6];
    // locked, or without an independent stop, every DOF below takes the first `continue`
    // (or never reaches a side): nothing engaged, nothing predicted
    if locked || !prop.has_independent_stops() {
        state.engaged = [0; 6];
        return out;
    }
    // stops of the implicit rule's automatic stiffness without a friction spring: rigid
    let rigid_rule = prop.automatic_stiffness() && prop.automatic == AutomaticStiffness::Implicit;
    for dof in Dof::ALL {
        let i = dof.index();
        let law = &prop.dofs[i];
        let was = std::mem::take(&mut state.engaged[i]);
        if locked || !prop.joint_type.is_free(dof) || law.coupled_stops {
            continue;
        }
        let rigid = rigid_rule && law.friction_stiffness <= 0.0 && inv_mass[i] > 0.0;
        let predicted = q[i] + h * rate[i];
        let ks = stop_stiffness(law.friction_stiffness, blocked.of(dof));
        // a rigid stop (module docs) engages with the stiffness that ends the substep on it
        let ks = if rigid {
            ks.max(RIGID_STOP / (h * h * inv_mass[i]))
        } else {
            ks
        };
        // a held stop only where the substep does not resolve it (`ω·h > 1`, `ω² = k_s·W`):
        // a resolved stop's rebound is the law's elastic dynamics, which holding would turn
        // into a pull towards the stop
        let unresolved = ks * inv_mass[i] * h * h > 1.0;
        // +1 / −1: the side whose stop acts now (a rigid stop is the update's whether the
        // DOF is beyond it or not: it ends the substep on it rather than pushed out of it by
        // the law's spring, and held on it where the DOF was on it, inside or beyond: a rod
        // resting on a rigid stop, pushed back by the substep that ended it on the stop, left
        // it for a substep and fell back, two substeps in a cycle)
        let held_max = unresolved && was == 1 && law.stop_max > 0.0 && stop_share(i) > 0.0;
        let held_min = unresolved && was == -1 && law.stop_min < 0.0 && stop_share(i) < 0.0;
        let side = if rigid && law.stop_max > 0.0 && (predicted > law.stop_max || held_max) {
            1
        } else if rigid && law.stop_min < 0.0 && (predicted < law.stop_min || held_min) {
            -1
        } else if law.stop_max > 0.0 && q[i] > law.stop_max {
            state.engaged[i] = 1;
            continue; // in contact: the law's stop acts
        } else if law.stop_min < 0.0 && q[i] < law.stop_min {
            state.engaged[i] = -1;
            continue;
        } else if law.stop_max > 0.0 && predicted > law.stop_max {
            1
        } else if law.stop_min < 0.0 && predicted < law.stop_min {
            -1
        } else if held_max {
            1
        } else if held_min {
            -1
        } else {
            continue;
        };
        if !(ks > 0.0 && ks.is_finite()) {
            continue;
        }
        let stop = if side > 0 { law.stop_max } else { law.stop_min };
        state.engaged[i] = side;
        out[i] = PredictedStop {
            force: ks * (predicted - stop) / beta,
            stiffness: ks,
        };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{DofLaw, JointType};

    /// The input of the predictions (positional, as the tests write them).
    #[allow(clippy::too_many_arguments)]
    fn input<'a>(
        prop: &'a KjointProperty,
        blocked: &'a BlockedStiffness,
        q: &'a [f64; 6],
        rate: &'a [f64; 6],
        transmitted: &'a [f64; 6],
        inv_mass: &'a [f64; 6],
        h: f64,
        beta: f64,
        locked: bool,
    ) -> StopInput<'a> {
        StopInput {
            prop,
            blocked,
            q,
            rate,
            transmitted,
            law: &[0.0; 6],
            inv_mass,
            h,
            beta,
            locked,
        }
    }

    /// A hinge whose stops are the law's springs (an explicit `Kn`: not rigid).
    fn hinge() -> KjointProperty {
        KjointProperty::new(JointType::Revolute)
            .with_kn(1e6)
            .with_dof(Dof::Rx, DofLaw::default().with_stops(-0.5, 0.3))
    }
    const K: BlockedStiffness = BlockedStiffness {
        translational: 1e6,
        rotational: 1e4,
    };
    /// An effective inverse mass for which the stops of `K` at `h` = 0.01 s are unresolved
    /// (`k·W·h² = 10`).
    const W: [f64; 6] = [10.0; 6];

    #[test]
    fn a_stop_is_predicted_only_when_it_would_be_crossed() {
        let p = hinge();
        let h = 0.01;
        let rx = Dof::Rx.index();
        // the predicted stop of rx at (q, q̇), locked by a sensor or not
        let at_locked = |q: f64, w: f64, locked: bool| {
            let mut qs = [0.0; 6];
            let mut rs = [0.0; 6];
            qs[rx] = q;
            rs[rx] = w;
            let mut st = StopPredictionState::default();
            predicted_stops(
                &input(&p, &K, &qs, &rs, &[0.0; 6], &W, h, 3.0, locked),
                &mut st,
            )[rx]
        };
        let at = |q: f64, w: f64| at_locked(q, w, false);
        // 0.29 + 0.01·5 = 0.34: 0.04 beyond SD+ = 0.3
        let s = at(0.29, 5.0);
        assert!((s.force - 1e4 * 0.04 / 3.0).abs() < 1e-9, "{s:?}");
        assert_eq!(s.stiffness, 1e4);
        // towards SD- = −0.5: −0.48 − 0.05 = −0.53, 0.03 beyond
        let s = at(-0.48, -5.0);
        assert!((s.force + 1e4 * 0.03 / 3.0).abs() < 1e-9, "{s:?}");
        // not reaching it, moving away from it, already in contact (the law's stop acts)
        assert_eq!(at(0.2, 5.0), PredictedStop::default());
        assert_eq!(at(0.29, -5.0), PredictedStop::default());
        assert_eq!(at(0.31, 5.0), PredictedStop::default());
        // locked by a sensor: nothing
        assert_eq!(at_locked(0.29, 5.0, true), PredictedStop::default());
    }

    /// One DOF, mass m, stop far stiffer than the substep resolves: the implicit update
    /// `m·Δq̇ = −h·F_s − (h²·k_s/β)·Δq̇` ends the substep on the stop.
    #[test]
    fn a_stiff_predicted_stop_ends_the_substep_on_the_stop() {
        let p = hinge();
        let rx = Dof::Rx.index();
        let (h, m, q0, w0) = (1.0 / 240.0, 0.01, 0.28, 12.0);
        let k = BlockedStiffness {
            translational: 1e12,
            rotational: 1e12,
        };
        let mut qs = [0.0; 6];
        let mut rs = [0.0; 6];
        qs[rx] = q0;
        rs[rx] = w0;
        let s = predicted_stops(
            &input(&p, &k, &qs, &rs, &[0.0; 6], &[1.0 / m; 6], h, 3.0, false),
            &mut StopPredictionState::default(),
        )[rx];
        let dw = -h * s.force / (m + h * h * s.stiffness / 3.0);
        let q1 = q0 + h * (w0 + dw);
        assert!((q1 - 0.3).abs() < 1e-9, "ends at {q1}");
    }

    /// A rigid stop (automatic stiffness of the implicit rule, no friction spring) ends the
    /// substep on the stop whatever the law's stiffness (here one the substep resolves,
    /// `k·W·h²` = 0.5) and whatever the DOF's inertia beyond its own diagonal (here 50 times
    /// `1/W`, as a door's about its hinge is 4 times its own): `I·Δq̇ = −h·F_s −
    /// (h²·k_s/β)·Δq̇`. Beyond the stop it brings the DOF back onto it rather than leaving
    /// the law's spring to push it out.
    #[test]
    fn a_rigid_stop_ends_the_substep_on_the_stop() {
        let p = KjointProperty::new(JointType::Revolute)
            .with_dof(Dof::Rx, DofLaw::default().with_stops(-0.5, 0.3));
        let rx = Dof::Rx.index();
        let h = 0.01;
        let w = [0.5; 6];
        let inertia = 50.0 / w[rx];
        for (q0, w0, end) in [(0.28, 12.0, 0.3), (-0.45, -20.0, -0.5), (0.305, 0.0, 0.3)] {
            let (mut qs, mut rs) = ([0.0; 6], [0.0; 6]);
            qs[rx] = q0;
            rs[rx] = w0;
            let mut st = StopPredictionState::default();
            let s = predicted_stops(
                &input(&p, &K, &qs, &rs, &[0.0; 6], &w, h, 3.0, false),
                &mut st,
            )[rx];
            assert!(s.stiffness >= RIGID_STOP / (h * h * w[rx]), "{s:?}");
            let dw = -h * s.force / (inertia + h * h * s.stiffness / 3.0);
            let q1 = q0 + h * (w0 + dw);
            // the overrun `g` the DOF would have ended with, cut to `β·50/RIGID_STOP` of it
            let g = (q0 + h * w0 - end).abs();
            assert!((q1 - end).abs() < 1.6e-3 * g, "{q1}");
        }
        // with a friction spring the stop is the spring `Kf`, not rigid
        let p = KjointProperty::new(JointType::Revolute).with_dof(
            Dof::Rx,
            DofLaw::default()
                .with_stops(-0.5, 0.3)
                .with_friction(100.0, 1.0),
        );
        let (mut qs, mut rs) = ([0.0; 6], [0.0; 6]);
        qs[rx] = 0.28;
        rs[rx] = 12.0;
        let mut st = StopPredictionState::default();
        let s = predicted_stops(
            &input(&p, &K, &qs, &rs, &[0.0; 6], &w, h, 3.0, false),
            &mut st,
        )[rx];
        assert_eq!(s.stiffness, 100.0);
    }

    /// A stop that acted holds the DOF while the transmitted force pushed it off the stop,
    /// and releases it when that force pulled towards the stop.
    #[test]
    fn a_held_stop_releases_when_the_joint_pulled_towards_it() {
        let p = hinge();
        let rx = Dof::Rx.index();
        let h = 0.01;
        let mut st = StopPredictionState::default();
        let mut qs = [0.0; 6];
        let mut rs = [0.0; 6];
        // in contact beyond SD+: the law acts, the stop is marked
        qs[rx] = 0.3001;
        let s = predicted_stops(
            &input(&p, &K, &qs, &rs, &[0.0; 6], &W, h, 3.0, false),
            &mut st,
        );
        assert_eq!(s[rx], PredictedStop::default());
        assert_eq!(st.engaged[rx], 1);
        // back inside and moving away, the stop pushed it out (F > 0): held, pulling it back
        // onto the stop, F = k·(q + h·q̇ − SD+)/β < 0
        qs[rx] = 0.2999;
        rs[rx] = 0.01;
        let mut f = [0.0; 6];
        f[rx] = 5.0;
        let s = predicted_stops(&input(&p, &K, &qs, &rs, &f, &W, h, 3.0, false), &mut st);
        let expected = 1e4 * (0.2999 + 0.0001 - 0.3) / 3.0;
        assert!((s[rx].force - expected).abs() < 1e-9, "{:?}", s[rx]);
        assert_eq!(st.engaged[rx], 1);
        // the joint then pulled the DOF towards the stop (F < 0): released
        f[rx] = -0.1;
        let s = predicted_stops(&input(&p, &K, &qs, &rs, &f, &W, h, 3.0, false), &mut st);
        assert_eq!(s[rx], PredictedStop::default());
        assert_eq!(st.engaged[rx], 0);
        // what the law's own spring transmitted is not the stop's: held on SD+ with 5 N
        // transmitted, of which the spring's pull off the stop is 50 (the stop's share −45,
        // a pull): released; with the spring's 3 N of it (the stop's share 2): held
        let mut held = StopPredictionState::default();
        held.engaged[rx] = 1;
        f[rx] = 5.0;
        for (spring, holds) in [(50.0, false), (3.0, true)] {
            let mut law = [0.0; 6];
            law[rx] = spring;
            let mut st = held;
            let input = StopInput {
                law: &law,
                ..input(&p, &K, &qs, &rs, &f, &W, h, 3.0, false)
            };
            let s = predicted_stops(&input, &mut st);
            assert_eq!(s[rx].stiffness > 0.0, holds, "spring {spring}: {:?}", s[rx]);
            assert_eq!(st.engaged[rx], i8::from(holds));
        }
    }

    /// A cone of coupled stops (ry, rz within 0.5 rad) predicted along its normal: from
    /// (0.49, 0) at (5, 3) rad/s over 0.01 s the offset is predicted at p = (0.54, 0.03),
    /// |p| = 0.540833, so g = 0.040833 along n = p/|p| with `F_s = k·g/β`; moving along the
    /// rim or away from it, nothing; in contact (|u| > R), the law's stop acts.
    #[test]
    fn a_cone_is_predicted_along_its_normal() {
        let cone = DofLaw::default().with_stops(-0.5, 0.5).with_coupled_stops();
        let p = KjointProperty::new(JointType::Spherical)
            .with_kn(1e6)
            .with_dof(Dof::Ry, cone.clone())
            .with_dof(Dof::Rz, cone);
        let (ry, rz) = (Dof::Ry.index(), Dof::Rz.index());
        let at = |q: (f64, f64), w: (f64, f64)| {
            let (mut qs, mut rs) = ([0.0; 6], [0.0; 6]);
            (qs[ry], qs[rz], rs[ry], rs[rz]) = (q.0, q.1, w.0, w.1);
            let mut st = StopPredictionState::default();
            let c = predicted_coupled_stops(
                &input(&p, &K, &qs, &rs, &[0.0; 6], &W, 0.01, 3.0, false),
                &mut st,
            );
            (c[1], st)
        };
        let (c, st) = at((0.49, 0.0), (5.0, 3.0));
        let dp = 0.54f64.hypot(0.03);
        assert_eq!(
            (c.members[..c.len].to_vec(), c.stiffness),
            (vec![ry, rz], 1e4)
        );
        assert!((c.force - 1e4 * (dp - 0.5) / 3.0).abs() < 1e-9, "{c:?}");
        assert!((c.normal[0] - 0.54 / dp).abs() < 1e-12 && (c.normal[1] - 0.03 / dp).abs() < 1e-12);
        assert!(st.coupled[1] && !st.coupled[0]);
        // inside and staying inside, moving away, in contact: none
        for (q, w) in [
            ((0.3, 0.2), (1.0, 1.0)),
            ((0.49, 0.0), (-5.0, 3.0)),
            ((0.4, 0.4), (1.0, 0.0)),
        ] {
            assert_eq!(at(q, w).0, PredictedCoupledStop::default(), "{q:?} {w:?}");
        }
        // (in contact the group is marked: held at the next substep if the joint pushed)
        assert!(at((0.4, 0.4), (1.0, 0.0)).1.coupled[1]);
    }

    /// A stop the substep resolves is not held: a DOF leaving it after a rebound is left
    /// to go (it was pulled back towards the stop, the force of a spring anchored on it).
    #[test]
    fn a_resolved_stop_is_not_held() {
        let p = hinge();
        let rx = Dof::Rx.index();
        let h = 0.01;
        let mut st = StopPredictionState::default();
        let (mut qs, mut rs, mut f) = ([0.0; 6], [0.0; 6], [0.0; 6]);
        // k·W·h² = 1e4 · 0.5 · 1e-4 = 0.5: resolved
        let w = [0.5; 6];
        qs[rx] = 0.3001;
        predicted_stops(&input(&p, &K, &qs, &rs, &f, &w, h, 3.0, false), &mut st);
        assert_eq!(st.engaged[rx], 1);
        // rebounding: inside, moving away, the stop pushed it out
        qs[rx] = 0.2999;
        rs[rx] = -2.0;
        f[rx] = 5.0;
        let s = predicted_stops(&input(&p, &K, &qs, &rs, &f, &w, h, 3.0, false), &mut st);
        assert_eq!(s[rx], PredictedStop::default());
        assert_eq!(st.engaged[rx], 0);
        // still predicted when it would cross the stop within the substep
        rs[rx] = 2.0;
        let s = predicted_stops(&input(&p, &K, &qs, &rs, &f, &w, h, 3.0, false), &mut st);
        assert!((s[rx].force - 1e4 * (0.2999 + 0.02 - 0.3) / 3.0).abs() < 1e-9);
    }
}
