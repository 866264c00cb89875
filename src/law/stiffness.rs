//! Blocked-DOF stiffness (spec §5): user `Kn` or automatic from the substep, and the
//! stable-step estimate of an explicit update.

use super::kjoint2::BlockedStiffness;
use super::property::Kjoint2Property;

/// Radioss' safety factor `α` in the automatic stiffness.
pub const ALPHA: f64 = 4.1;

/// Mass data of one body of a joint, as the stiffness formulas need it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyMass {
    /// Mass \[kg\]; `f64::INFINITY` for a fixed body.
    pub mass: f64,
    /// Mean principal inertia [kg·m²]; `f64::INFINITY` for a fixed body.
    pub inertia: f64,
    /// Squared distance from the anchor to the body's centre of mass \[m²\].
    pub anchor_offset_sq: f64,
}

impl BodyMass {
    /// A fixed (world) body anchored at its centre of mass: infinite mass and inertia.
    pub const FIXED: BodyMass = BodyMass {
        mass: f64::INFINITY,
        inertia: f64::INFINITY,
        anchor_offset_sq: 0.0,
    };
    /// A fixed (world) body whose anchor is `√anchor_offset_sq` from its centre of mass: it
    /// does not bound the automatic stiffness, but its offset is part of `r²` (spec §5; the
    /// Radioss QA model's spring node is 75 from the fixed rigid body's centre of mass).
    pub fn fixed(anchor_offset_sq: f64) -> BodyMass {
        BodyMass {
            anchor_offset_sq,
            ..BodyMass::FIXED
        }
    }
    /// `true` for a fixed body (infinite mass).
    pub fn is_fixed(&self) -> bool {
        !self.mass.is_finite()
    }
}

/// Blocked stiffness for a joint with user `Kn > 0`: `KR = Kn·max(ScF, L0²)`.
pub fn user_blocked_stiffness(prop: &Kjoint2Property, initial_length: f64) -> BlockedStiffness {
    let kn = prop.kn;
    BlockedStiffness {
        translational: kn,
        rotational: kn
            * prop
                .resolved_scale_factor()
                .max(initial_length * initial_length),
    }
}

/// Automatic blocked stiffness (`Kn = 0`), computed from the substep `dt`:
///
/// `r² = max_i |anchor_i − com_i|² + |anchor_1 − anchor_2|²`,
/// `Kx_i = min(2·m_i/(α·dt²), 0.8·I_i/(α·dt²·r²))` (second term only when `r² > 0`),
/// `KX = min(Kx_1, Kx_2)`, `KR = min_i I_i/(α·dt²)`, both times `ScF`.
///
/// `share[i]` (in (0, 1]) is the fraction of body `i`'s stiffness budget this joint may
/// take; the joint set passes `1/n_i` with `n_i` the number of automatic joints on body `i`
/// after the user-stiffness joints on it have taken theirs. A fixed body does not bound the
/// minimum, but its anchor offset counts in `r²` ([`BodyMass::fixed`]). A body with zero
/// inertia (a point mass) drops the inertia term instead of giving a zero translational
/// stiffness, and gives `KR = 0`.
///
/// Check (the OpenRadioss KJOINT2 QA model): a fixed body with the anchor 75 from its centre
/// of mass, a 156 kg body with `I = 31200` anchored at its centre, `dt = 1.475e-3`:
/// `KX = 0.8·31200/(4.1·dt²·75²) = 4.97455e5`, `KR = 31200/(4.1·dt²) = 3.49773e9`.
pub fn automatic_blocked_stiffness(
    prop: &Kjoint2Property,
    bodies: [BodyMass; 2],
    initial_length: f64,
    dt: f64,
    share: [f64; 2],
) -> BlockedStiffness {
    let adt2 = ALPHA * dt * dt;
    let r2 = bodies
        .iter()
        .map(|b| b.anchor_offset_sq)
        .fold(0.0, f64::max)
        + initial_length * initial_length;
    let mut kx = f64::INFINITY;
    let mut kr = f64::INFINITY;
    for (b, s) in bodies.iter().zip(share) {
        if b.is_fixed() {
            continue;
        }
        let mut k = 2.0 * b.mass / adt2;
        if r2 > 0.0 && b.inertia > 0.0 {
            k = k.min(0.8 * b.inertia / (adt2 * r2));
        }
        kx = kx.min(k * s);
        if b.inertia > 0.0 {
            kr = kr.min(b.inertia / adt2 * s);
        } else {
            kr = 0.0;
        }
    }
    let scf = prop.resolved_scale_factor();
    BlockedStiffness {
        translational: if kx.is_finite() { kx * scf } else { 0.0 },
        rotational: if kr.is_finite() { kr * scf } else { 0.0 },
    }
}

/// Stable time steps of an explicit (central difference) update of one joint, as
/// OpenRadioss estimates them (spec §5): translational and rotational separately.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct StableDt {
    /// `dt_trans = 0.9·min_i √(m_i/S)` \[s\] (`∞` when nothing bounds it).
    pub translational: f64,
    /// `dt_rot = 0.9·min_i √(2·I_i/(S_r + S·L²))` \[s\] (`∞` when nothing bounds it).
    pub rotational: f64,
}

impl StableDt {
    /// The smaller of the two \[s\].
    pub fn min(&self) -> f64 {
        self.translational.min(self.rotational)
    }
}

/// Stable time steps of an explicit update of this joint (spec §5), as OpenRadioss computes
/// them: the nodal translational stiffness receives `2·S` and the rotational one
/// `S_r + S·L²`, so
///
/// `dt_trans = 0.9·min_i √(m_i/S)`, `dt_rot = 0.9·min_i √(2·I_i/(S_r + S·L²))`,
///
/// with `S = K·(ξ + √(1+ξ²))²`, `S_r = K_r·(ξ + √(1+ξ²))²`, `ξ` the largest active damping
/// ratio, `K`/`K_r` the largest translational / rotational tangent stiffness, `L` the joint
/// length. Fixed bodies and bodies without inertia do not bound the step.
///
/// Check: a fixed joint between a fixed node and a body of `m = I = 1`, `L = 0`, `Kn = 1e4`,
/// `KR = 1e5` (ScF = 10), `ξ = 0.05`: `dt_trans = 8.561e-3`, `dt_rot = 3.829e-3`.
///
/// The crate's own update is unconditionally stable; this tells whether a substep would be
/// safe for Radioss' explicit scheme, and how far the joint is from the explicit regime.
pub fn stable_dt(
    bodies: [BodyMass; 2],
    k_trans: f64,
    k_rot: f64,
    xi: f64,
    length: f64,
) -> StableDt {
    let f = (xi + (1.0 + xi * xi).sqrt()).powi(2);
    let s = k_trans * f;
    let s_rot = k_rot * f + s * length * length;
    let mut dt = StableDt {
        translational: f64::INFINITY,
        rotational: f64::INFINITY,
    };
    for b in bodies.iter().filter(|b| !b.is_fixed()) {
        if s > 0.0 {
            dt.translational = dt.translational.min((b.mass / s).sqrt());
        }
        if s_rot > 0.0 && b.inertia > 0.0 {
            dt.rotational = dt.rotational.min((2.0 * b.inertia / s_rot).sqrt());
        }
    }
    StableDt {
        translational: 0.9 * dt.translational,
        rotational: 0.9 * dt.rotational,
    }
}
