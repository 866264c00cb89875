//! The planar friction law ([`PlanarFriction`], docs/planar_friction.md) as a connector: see
//! the module documentation of [`super`], "Planar friction (type 4)".

use super::joint_friction::{moments_at_anchor2, Evaluation};
use super::PlanarFrictionReport;
use crate::law::planar_friction::{PlanarFrictionInput, PlanarFrictionState};
use crate::law::{FrictionStatus, JointEnergy, LawOutput, PlanarFriction};
use nalgebra::Vector2;

fn status(sliding: bool) -> FrictionStatus {
    if sliding {
        FrictionStatus::Slip
    } else {
        FrictionStatus::Stick
    }
}

/// One evaluation: adds tangents, damping and statuses to `out` and the energies to
/// `energy`, accumulates the slips `(in-plane, twist)`; returns the connector's forces, its
/// stick damping coefficients `c` (the stick damping force is `c·q̇`) and the readout.
pub(super) fn apply(
    p: &PlanarFriction,
    st: &mut PlanarFrictionState,
    ev: &Evaluation,
    slip_total: &mut [f64; 2],
    out: &mut LawOutput,
    energy: &mut JointEnergy,
) -> ([f64; 6], [f64; 6], PlanarFrictionReport) {
    let (params, dq) = (ev.params, &ev.dq);
    let (mut force, mut damp) = ([0.0; 6], [0.0; 6]);
    let mut law = *p;
    if law.stick_stiffness == 0.0 {
        law.stick_stiffness = ev.automatic.translational;
    }
    if law.stick_rotational_stiffness == 0.0 {
        law.stick_rotational_stiffness = ev.automatic.rotational;
    }
    // Moments carried at anchor 2 (the puck).
    let r = moments_at_anchor2(&ev.lever, &out.total);
    let input = PlanarFrictionInput {
        f1: r[0],
        m2: r[4],
        m3: r[5],
        du: Vector2::new(dq[1], dq[2]),
        dur1: dq[3],
    };
    let o = law.evaluate(st, &input);
    force[1] = o.force.x;
    force[2] = o.force.y;
    force[3] = o.moment;
    for (k, (i, j)) in [(1, 1), (1, 2), (2, 1), (2, 2)].into_iter().enumerate() {
        out.stiffness[(i, j)] += o.tangent[(k / 2, k % 2)];
    }
    out.stiffness[(3, 3)] += o.rotational_tangent;
    let cr = ev.prop.resolved_critical_damping();
    if !o.sliding {
        let c = cr * (law.stick_stiffness * params.reduced_mass).max(0.0).sqrt();
        for i in [1, 2] {
            damp[i] = c;
            out.damping[(i, i)] += c;
        }
    }
    if !o.twist_sliding {
        let c = cr
            * (law.stick_rotational_stiffness * params.reduced_inertia)
                .max(0.0)
                .sqrt();
        damp[3] = c;
        out.damping[(3, 3)] += c;
    }
    for i in [1, 2] {
        out.status[i].friction = status(o.sliding);
    }
    out.status[3].friction = status(o.twist_sliding);
    slip_total[0] += o.slip;
    slip_total[1] += o.twist_slip;
    energy.friction += o.dissipated;
    energy.elastic += o.stored;
    let report = PlanarFrictionReport {
        normal_force: o.normal_force,
        normal_moment: o.normal_moment,
        friction_force: [o.force.x, o.force.y],
        friction_moment: o.moment,
        sliding: status(o.sliding),
        twist: status(o.twist_sliding),
        slip: o.slip,
        slip_total: slip_total[0],
        twist_slip: o.twist_slip,
        twist_slip_total: slip_total[1],
        stick_stiffness: [law.stick_stiffness, law.stick_rotational_stiffness],
        stored: o.stored,
        dissipated: st.dissipated_sliding + st.dissipated_twist,
    };
    (force, damp, report)
}
