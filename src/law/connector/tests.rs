//! Tests of [`super`] (`src/law/connector.rs`).

use super::*;
use crate::law::{BlockedStiffness, Curve, Dof, DofLaw, FlexProAdd};
use approx::assert_relative_eq;

fn params() -> LawParams {
    LawParams {
        blocked: BlockedStiffness {
            translational: 1e6,
            rotational: 1e5,
        },
        reduced_mass: 4.0,
        reduced_inertia: 0.5,
    }
}

fn output(total: [f64; 6]) -> LawOutput {
    LawOutput {
        total,
        ..LawOutput::zeroed()
    }
}

#[test]
fn planar_normal_force_uses_the_moment_at_the_puck() {
    let prop = KjointProperty::new(JointType::Planar).with_critical_damping(0.1);
    let law =
        ConnectorLaw::PlanarFriction(PlanarFriction::new(0.5, 0.5, 0.0, 0.0, 1e4, 0.0).unwrap());
    law.validate(&prop).unwrap();
    let mut c = Connector::new(law);
    let mut energy = JointEnergy::default();
    // First evaluation sets the reference (no increment).
    let mut input = ConnectorInput {
        lever: [0.0, 0.1, 0.0],
        ..Default::default()
    };
    let total = [-100.0, 0.0, 0.0, 0.0, 30.0, 0.0];
    c.apply(&prop, &params(), &input, &mut output(total), &mut energy);
    // Slide 1 mm along y at 0.1 m/s.
    input.q[1] = 1e-3;
    input.rate[1] = 0.1;
    let mut out = output(total);
    c.apply(&prop, &params(), &input, &mut out, &mut energy);
    let Some(ConnectorReport::PlanarFriction(r)) = c.report() else {
        panic!("no report")
    };
    // l = ½·L at the mid-point: m2 = 30 − (lz f1 − lx f3) = 30; m3 = 0 − (lx f2 − ly f1) = −10.
    // F_N = 100 + √(30² + 10²)/0.5 = 163.246 N.
    assert_relative_eq!(r.normal_force, 100.0 + 1000f64.sqrt() / 0.5, epsilon = 1e-9);
    // M_N = (2/3)·0.5·100 + √1000 = 64.956 N·m.
    assert_relative_eq!(
        r.normal_moment,
        2.0 / 3.0 * 50.0 + 1000f64.sqrt(),
        epsilon = 1e-9
    );
    // Stick: s = Kf·Δu = 10 N, plus the stick damping Cr·√(Kf·m)·u̇ = 0.1·200·0.1 = 2 N.
    assert_eq!(r.sliding, FrictionStatus::Stick);
    assert_relative_eq!(out.parts[1].friction, 10.0, epsilon = 1e-12);
    assert_relative_eq!(out.parts[1].damping, 2.0, epsilon = 1e-12);
    assert_relative_eq!(out.total[1], 12.0, epsilon = 1e-12);
    assert_eq!(out.stiffness[(1, 1)], 1e4);
    assert_eq!(out.stiffness[(2, 2)], 1e4);
    assert_eq!(out.stiffness[(1, 2)], 0.0);
    // Automatic Kr = KR of the joint.
    assert_eq!(out.stiffness[(3, 3)], 1e5);
    assert_eq!(r.stick_stiffness, [1e4, 1e5]);
    assert_relative_eq!(out.damping[(1, 1)], 20.0, epsilon = 1e-12);
    assert_eq!(out.status[1].friction, FrictionStatus::Stick);
    // Stored |s|²/(2Kf) = 5 mJ; internal work ½·Δu·(F_new + F_old) = ½·1e-3·12.
    assert_relative_eq!(energy.elastic, 5e-3, epsilon = 1e-12);
    assert_relative_eq!(energy.internal, 6e-3, epsilon = 1e-12);
    assert_relative_eq!(energy.damping, 1e-3, epsilon = 1e-12);
}

#[test]
fn stick_damping_is_booked_over_an_interval_only_where_the_update_applied_it() {
    // The planar puck above (F_N = 163.2 N, μ = 0.5: cap 81.6 N; K_f = 1e4 N/m, so it slides
    // beyond 8.2 mm) with the stick damping c = Cr·√(K_f·m) = 0.1·√(1e4·4) = 20 N·s/m. The
    // update over an interval applies the damping of the evaluation at its start, at the
    // interval's end rate: `c⁻·u̇`.
    let prop = KjointProperty::new(JointType::Planar).with_critical_damping(0.1);
    let law =
        ConnectorLaw::PlanarFriction(PlanarFriction::new(0.5, 0.5, 0.0, 0.0, 1e4, 0.0).unwrap());
    let mut c = Connector::new(law);
    let mut energy = JointEnergy::default();
    let total = [-100.0, 0.0, 0.0, 0.0, 30.0, 0.0];
    let mut input = ConnectorInput {
        lever: [0.0, 0.1, 0.0],
        ..Default::default()
    };
    let sliding = |c: &Connector| match c.report() {
        Some(ConnectorReport::PlanarFriction(r)) => r.sliding,
        _ => panic!("no report"),
    };
    // at rest, sticking (c = 20 N·s/m, no rate)
    c.apply(&prop, &params(), &input, &mut output(total), &mut energy);
    assert_eq!(sliding(&c), FrictionStatus::Stick);
    // 50 mm at 0.5 m/s: it slides at the end, but stuck at the start, where the update
    // damped the interval's end rate: ½·Δu·(c⁻·u̇ + 0) = ½·0.05·20·0.5 = 0.25 J (booked with
    // the law's own damping at the end, 0 while sliding, this was 0 J)
    input.q[1] = 0.05;
    input.rate[1] = 0.5;
    let before = energy.damping;
    c.apply(&prop, &params(), &input, &mut output(total), &mut energy);
    assert_eq!(sliding(&c), FrictionStatus::Slip);
    assert_relative_eq!(energy.damping - before, 0.25, epsilon = 1e-12);
    // back 0.1 mm at −0.1 m/s: the spring unloads and sticks again, but the update slid over
    // the interval and damped none of it: 0 J (it was ½·Δu·c·u̇ = ½·1e-4·20·0.1 = 0.1 mJ)
    input.q[1] = 0.0499;
    input.rate[1] = -0.1;
    let before = energy.damping;
    c.apply(&prop, &params(), &input, &mut output(total), &mut energy);
    assert_eq!(sliding(&c), FrictionStatus::Stick);
    assert_eq!(energy.damping - before, 0.0);
    // sticking on at −0.05 m/s: both ends damped, ½·Δu·c·(u̇⁻ + u̇) = ½·1e-4·20·0.15 = 0.15 mJ
    input.q[1] = 0.0498;
    input.rate[1] = -0.05;
    let before = energy.damping;
    c.apply(&prop, &params(), &input, &mut output(total), &mut energy);
    assert_eq!(sliding(&c), FrictionStatus::Stick);
    assert_relative_eq!(energy.damping - before, 1.5e-4, epsilon = 1e-12);
}

#[test]
fn flex_joint_moment_and_tangent_go_to_the_rotations() {
    let prop = KjointProperty::new(JointType::Spherical);
    let curve = Curve::new([(0.0, 0.0), (0.01, 1000.0), (0.02, 1500.0)]).unwrap();
    let d = FlexProAdd {
        torsion_stiffness: 2e4,
        iflag: 1,
        kdyn_ini: 1e5,
        kdyn_lim: 5e4,
        angle_lim: 1e-3,
        teta: 0.0,
        torsion_damping: 300.0,
    };
    let law = FlexJointLaw::new(Some(curve), None, Some(d)).unwrap();
    let mut c = Connector::new(ConnectorLaw::FlexJoint(FlexJointConnector {
        law,
        switch_time: Some(1.0),
    }));
    let mut energy = JointEnergy::default();
    let input = ConnectorInput {
        q: [0.0, 0.0, 0.0, 0.002, 0.0, 0.015],
        rate: [0.0, 0.0, 0.0, 0.5, 0.0, 0.0],
        lever: [0.0; 3],
        time: 0.5,
    };
    let mut out = output([0.0; 6]);
    c.apply(&prop, &params(), &input, &mut out, &mut energy);
    // Torsion 2e4·0.002 = 40 N·m elastic + 300·0.5 = 150 N·m damping.
    assert_relative_eq!(out.parts[3].elastic, 40.0, epsilon = 1e-9);
    assert_relative_eq!(out.parts[3].damping, 150.0, epsilon = 1e-9);
    assert_relative_eq!(out.total[3], 190.0, epsilon = 1e-9);
    // Bending about z: the table at 0.015 rad = 1250 N·m, slope 5e4.
    assert_relative_eq!(out.total[5], 1250.0, epsilon = 1e-9);
    assert_relative_eq!(out.stiffness[(5, 5)], 5e4, epsilon = 1e-6);
    // Across the bending plane: secant 1250/0.015.
    assert_relative_eq!(out.stiffness[(4, 4)], 1250.0 / 0.015, epsilon = 1e-6);
    assert_relative_eq!(out.stiffness[(3, 3)], 2e4);
    assert_relative_eq!(out.damping[(3, 3)], 300.0);
    // Stored: ½·2e4·0.002² + (½·0.01·1000 + ½·(1000+1250)·0.005) = 0.04 + 10.625.
    assert_relative_eq!(energy.elastic, 0.04 + 10.625, epsilon = 1e-9);
    assert!(c.events().is_empty());
    // Stable-step stiffness: max(table slopes 1e5, 5e4; Kdyn_ini 1e5; Ktor 2e4).
    assert_eq!(c.law().max_stiffness(&params().blocked), (0.0, 1e5));
    // At t = 1 s the switch happens, logged once.
    let input = ConnectorInput { time: 1.0, ..input };
    c.apply(&prop, &params(), &input, &mut output([0.0; 6]), &mut energy);
    c.apply(&prop, &params(), &input, &mut output([0.0; 6]), &mut energy);
    assert_eq!(c.events().len(), 1);
    assert_eq!(
        c.events()[0].kind,
        ConnectorEventKind::FlexJointSwitched {
            cause: FlexJointSwitchCause::SwitchTime { switch_time: 1.0 }
        }
    );
    assert_eq!(
        c.events()[0].kind.to_string(),
        "flex joint switched to the dynamic phase (switch time 1 s reached)"
    );
    let Some(ConnectorReport::FlexJoint(r)) = c.report() else {
        panic!("no report")
    };
    assert_eq!(r.phase, FlexPhase::Dynamic);
    assert_eq!(r.switched_at, Some(1.0));
    assert_relative_eq!(r.bending_moment[1], 1250.0, epsilon = 1e-9);
}

#[test]
fn validation_names_the_problem() {
    let pf =
        ConnectorLaw::PlanarFriction(PlanarFriction::new(0.5, 0.0, 0.0, 0.0, 0.0, 0.0).unwrap());
    let e = pf
        .validate(&KjointProperty::new(JointType::Spherical))
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "the planar friction law needs a planar joint (type 4), not a spherical joint (type 1)"
    );
    let prop = KjointProperty::new(JointType::Planar)
        .with_dof(Dof::Rx, DofLaw::default().with_friction(10.0, 1.0));
    assert!(matches!(
        pf.validate(&prop),
        Err(ConnectorError::Conflict { .. })
    ));
    let curve = Curve::new([(0.0, 0.0), (0.01, 1000.0)]).unwrap();
    let fj = ConnectorLaw::FlexJoint(FlexJointConnector {
        law: FlexJointLaw::new(Some(curve), None, None).unwrap(),
        switch_time: Some(f64::NAN),
    });
    let e = fj
        .validate(&KjointProperty::new(JointType::Spherical))
        .unwrap_err();
    assert!(e.to_string().contains("switch_time"), "{e}");
    // Serde round trips (scene files).
    let ConnectorLaw::FlexJoint(mut f) = fj else {
        unreachable!()
    };
    f.switch_time = Some(2.0);
    let fj = ConnectorLaw::FlexJoint(f);
    for law in [fj, pf] {
        let json = serde_json::to_string(&law).unwrap();
        let back: ConnectorLaw = serde_json::from_str(&json).unwrap();
        assert_eq!(back, law, "{json}");
    }
    // The TOML shapes of the module documentation.
    let pf: ConnectorLaw = toml::from_str("[planar_friction]\nmu = 0.3\nradius = 0.05\n").unwrap();
    assert_eq!(
        pf,
        ConnectorLaw::PlanarFriction(PlanarFriction::new(0.3, 0.05, 0.0, 0.0, 0.0, 0.0).unwrap())
    );
    let text = "[flex_joint]\nswitch_time = 20.0\n[flex_joint.law]\n\
        bending = [[0.0, 0.0], [0.00872665, 25000.0], [0.0174533, 35000.0]]\n\
        [flex_joint.law.dynamic]\ntorsion_stiffness = 5.72958e8\niflag = 1\n\
        kdyn_ini = 4.0107e6\nkdyn_lim = 1.718873e6\nangle_lim = 1.74533e-3\n\
        teta = 0.0\ntorsion_damping = 3.008e6\n";
    let fj: ConnectorLaw = toml::from_str(text).unwrap();
    let ConnectorLaw::FlexJoint(f) = &fj else {
        panic!("{fj:?}")
    };
    assert_eq!(f.switch_time, Some(20.0));
    assert_eq!(f.law.mode(), crate::law::flex_joint::FlexMode::Dynamic);
    fj.validate(&KjointProperty::new(JointType::Spherical))
        .unwrap();
    // An unsorted table is refused while reading.
    assert!(toml::from_str::<ConnectorLaw>(
        "[flex_joint.law]\nbending = [[0.0, 0.0], [-1.0, 5.0]]\n"
    )
    .is_err());
}
