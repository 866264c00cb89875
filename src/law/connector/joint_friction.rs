//! The joint friction law (docs/joint_friction.md, [`JointFriction`]) as a connector: the
//! revolute, cylindrical and translational joints' load-dependent friction on `δx` and/or
//! `θx`, the normal force read from the KJOINT2 totals of their blocked DOFs in the same
//! evaluation, the moments referred to anchor 2 (as the planar friction reads its own,
//! [`super`]).
//!
//! Added to the KJOINT2 output: the friction force `f` on `F[0]` and moment `m` on `F[3]`
//! (part `friction`), the tangent `∂(f, m)/∂(δx, θx)` on `K[{0,3}, {0,3}]`, and while sticking
//! the critical stick damping `Cr·√(k·m)` on each DOF the law acts on (`k` its stick
//! stiffness, [`JointFriction::dof_stiffness`]; `m` the reduced mass or inertia).

use super::{ConnectorError, FrictionStatus};
use crate::law::joint_friction::{JointFrictionInput, JointFrictionState};
use crate::law::{
    BlockedStiffness, Dof, JointEnergy, JointFriction, JointType, KjointProperty, LawOutput,
    LawParams,
};
use serde::Serialize;

/// Readout of the joint friction law after an evaluation (joint frame).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "serde-serialize", derive(serde::Deserialize))]
pub struct JointFrictionReport {
    /// Normal force `F_N` \[N\] (docs/joint_friction.md §2).
    pub normal_force: f64,
    /// Friction bound \[N; N·m on a revolute joint\] (docs/joint_friction.md §3).
    pub cap: f64,
    /// Friction force along the axis `f` \[N\] (internal-force sign, without the stick
    /// damping; 0 on a revolute joint).
    pub friction_force: f64,
    /// Friction moment about the axis `m` \[N·m\] (without the stick damping; 0 on a
    /// translational joint).
    pub friction_moment: f64,
    /// Stick/slip.
    pub sliding: FrictionStatus,
    /// Slip of this evaluation `Δλ` \[m, the surface slip; rad on a revolute joint\].
    pub slip: f64,
    /// Accumulated slip `Σ Δλ` \[m; rad on a revolute joint\].
    pub slip_total: f64,
    /// Stick stiffnesses used on `(δx [N/m], θx [N·m/rad])` (automatic ones resolved; 0 on a
    /// DOF the law does not act on).
    pub stick_stiffness: [f64; 2],
    /// Elastic energy of the friction spring \[J\].
    pub stored: f64,
    /// Energy dissipated by friction since the start \[J\].
    pub dissipated: f64,
}

impl JointFrictionReport {
    /// The values of its channels (`joint_friction`, named in `JOINT_FRICTION_CHANNELS`):
    /// `normal_force` \[N\], `cap` \[N or N·m\], `friction_force` \[N\], `friction_moment`
    /// \[N·m\], `sliding` (1 stick, 2 slip), `slip_total` \[m or rad\], `stored`,
    /// `dissipated` \[J\].
    pub(super) fn channels(&self) -> Vec<f64> {
        vec![
            self.normal_force,
            self.cap,
            self.friction_force,
            self.friction_moment,
            status_code(self.sliding),
            self.slip_total,
            self.stored,
            self.dissipated,
        ]
    }
}

/// 0 none, 1 stick, 2 slip.
pub(super) fn status_code(s: FrictionStatus) -> f64 {
    match s {
        FrictionStatus::None => 0.0,
        FrictionStatus::Stick => 1.0,
        FrictionStatus::Slip => 2.0,
    }
}

/// The free DOFs the law acts on: `θx` (index 3) of a revolute joint, `δx` (0) of a
/// translational one, both of a cylindrical one (only `δx` when `R_pin = 0`).
fn acting_dofs(law: &JointFriction, joint: JointType) -> Vec<usize> {
    match joint {
        JointType::Revolute => vec![3],
        JointType::Cylindrical if law.pin_radius > 0.0 => vec![0, 3],
        _ => vec![0],
    }
}

/// Checks the law against the property: a revolute, cylindrical or translational joint,
/// valid parameters for it, no KJOINT2 friction (`FF`) on a DOF the law acts on.
pub(super) fn validate(law: &JointFriction, prop: &KjointProperty) -> Result<(), ConnectorError> {
    let name = "joint friction";
    if !JointFriction::JOINT_TYPES.contains(&prop.joint_type) {
        return Err(ConnectorError::UnsupportedJointType {
            law: name,
            supported: "revolute (type 2), cylindrical (type 3) or translational (type 6)",
            found: prop.joint_type,
        });
    }
    law.validate_for(prop.joint_type)
        .map_err(|source| ConnectorError::Property { law: name, source })?;
    for i in acting_dofs(law, prop.joint_type) {
        if prop.dofs[i].friction_active() {
            return Err(ConnectorError::Conflict {
                law: name,
                reason: format!(
                    "the property also has KJOINT2 friction (FF) on {}: remove it, the joint \
                     friction law replaces it",
                    Dof::ALL[i].name()
                ),
            });
        }
    }
    Ok(())
}

/// The law with its automatic stick stiffnesses resolved to `automatic` (a stiffness the
/// joint type does not use stays unused, [`JointFriction::dof_stiffness`]).
pub(super) fn resolved(law: &JointFriction, automatic: &BlockedStiffness) -> JointFriction {
    let mut l = *law;
    if l.stick_stiffness == 0.0 {
        l.stick_stiffness = automatic.translational;
    }
    if l.stick_rotational_stiffness == 0.0 {
        l.stick_rotational_stiffness = automatic.rotational;
    }
    l
}

/// The KJOINT2 totals `(F, M)` with the moments referred to anchor 2: `M − l×F`, `l` =
/// anchor 2 from the point the force acts at ([`super::ConnectorInput::lever`]: ½·(p2 − p1)
/// at KJOINT2's mid-point, docs/kjoint2.md §4.7; 0 for a joint measured at anchor 2).
pub(super) fn moments_at_anchor2(l: &[f64; 3], f: &[f64; 6]) -> [f64; 6] {
    let lxf = [
        l[1] * f[2] - l[2] * f[1],
        l[2] * f[0] - l[0] * f[2],
        l[0] * f[1] - l[1] * f[0],
    ];
    let mut r = *f;
    for i in 0..3 {
        r[3 + i] -= lxf[i];
    }
    r
}

/// What one evaluation needs besides the law and its state.
pub(super) struct Evaluation<'a> {
    pub prop: &'a KjointProperty,
    pub params: &'a LawParams,
    pub automatic: BlockedStiffness,
    pub dq: [f64; 6],
    /// [`super::ConnectorInput::lever`].
    pub lever: [f64; 3],
}

/// One evaluation: adds tangents, damping and statuses to `out` and the energies to
/// `energy`; returns the connector's forces, its stick damping coefficients `c` (the stick
/// damping force is `c·q̇`) and the readout.
pub(super) fn apply(
    law: &JointFriction,
    st: &mut JointFrictionState,
    ev: &Evaluation,
    slip_total: &mut f64,
    out: &mut LawOutput,
    energy: &mut JointEnergy,
) -> ([f64; 6], [f64; 6], JointFrictionReport) {
    let joint = ev.prop.joint_type;
    let law = resolved(law, &ev.automatic);
    // Moments carried at anchor 2 (the carriage, the bushing), docs/joint_friction.md §2.
    let reactions = moments_at_anchor2(&ev.lever, &out.total);
    let input = JointFrictionInput {
        reactions,
        dx: ev.dq[0],
        dtheta: ev.dq[3],
    };
    let o = law.evaluate(joint, st, &input);
    let (mut force, mut damp) = ([0.0; 6], [0.0; 6]);
    force[0] = o.force;
    force[3] = o.moment;
    let idx = [0, 3];
    for a in 0..2 {
        for b in 0..2 {
            out.stiffness[(idx[a], idx[b])] += o.tangent[(a, b)];
        }
    }
    let k = law.dof_stiffness(joint);
    let status = if o.sliding {
        FrictionStatus::Slip
    } else {
        FrictionStatus::Stick
    };
    let cr = ev.prop.resolved_critical_damping();
    for i in acting_dofs(&law, joint) {
        let slot = i / 3;
        out.status[i].friction = status;
        if !o.sliding {
            let m = if i == 0 {
                ev.params.reduced_mass
            } else {
                ev.params.reduced_inertia
            };
            let c = cr * (k[slot] * m).max(0.0).sqrt();
            damp[i] = c;
            out.damping[(i, i)] += c;
        }
    }
    *slip_total += o.slip;
    energy.friction += o.dissipated;
    energy.elastic += o.stored;
    let report = JointFrictionReport {
        normal_force: o.normal_force,
        cap: o.cap,
        friction_force: o.force,
        friction_moment: o.moment,
        sliding: status,
        slip: o.slip,
        slip_total: *slip_total,
        stick_stiffness: k,
        stored: o.stored,
        dissipated: st.dissipated,
    };
    (force, damp, report)
}
