//! Mechanism tests of the pure KJOINT2 law (`law::evaluate`), the blocked-stiffness formulas
//! (`law::stiffness`) and the kinematics (`kinematics::measure`) against numbers computed by
//! hand from the spec (`/work/shared/spec/kjoint2.md` §1–§5). Every expected value carries its
//! hand computation in a comment.

use nalgebra::{UnitQuaternion, Vector3, Vector6};
use proptest::prelude::*;
use rapier_kjoint::kinematics::{
    self, BodyPose, JointFrames, MeasureState, RotationMeasure, TranslationMeasure,
};
use rapier_kjoint::law::stiffness::{self, BodyMass};
use rapier_kjoint::law::{
    evaluate, BlockedStiffness, FrictionStatus, LawOutput, LawParams, LawState, StopContact,
};
use rapier_kjoint::{Curve, Dof, DofLaw, JointType, KjointProperty, PropertyError};

const DX: usize = 0;
const DY: usize = 1;
const DZ: usize = 2;
const RX: usize = 3;

fn close(actual: f64, expected: f64, tol: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: got {actual}, expected {expected} (tol {tol})"
    );
}

fn params(kn: f64, kr: f64, m: f64, i: f64) -> LawParams {
    LawParams {
        blocked: BlockedStiffness {
            translational: kn,
            rotational: kr,
        },
        reduced_mass: m,
        reduced_inertia: i,
    }
}

/// One evaluation with zero rates, the lock off, on a fresh state.
fn eval_once(prop: &KjointProperty, p: &LawParams, q: [f64; 6]) -> (LawOutput, LawState) {
    let mut st = LawState::default();
    let out = evaluate(prop, p, &q, &[0.0; 6], false, &mut st);
    (out, st)
}

fn dx(v: f64) -> [f64; 6] {
    [v, 0.0, 0.0, 0.0, 0.0, 0.0]
}

// ---------------------------------------------------------------------------------------
// 1. Independent stops (spec §4.2)
// ---------------------------------------------------------------------------------------

/// Free dx (prismatic), K = 100, SD- = -0.1, SD+ = 0.2, Kf = 0: the stop stiffness is the
/// blocked Kn = 1e4.
#[test]
fn independent_stops_use_blocked_kn_when_kf_is_zero() {
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, DofLaw::spring(100.0).with_stops(-0.1, 0.2));
    prop.validate().unwrap();
    let p = params(1e4, 1e5, 2.0, 0.5);

    // Inside: q = 0.15 → F = 100·0.15 = 15, no stop force, Kt = 100, E = ½·100·0.15² = 1.125
    let (o, st) = eval_once(&prop, &p, dx(0.15));
    close(o.parts[DX].elastic, 15.0, 1e-12, "elastic inside");
    assert_eq!(o.parts[DX].stop, 0.0);
    assert_eq!(o.status[DX].stop, StopContact::None);
    close(o.total[DX], 15.0, 1e-12, "total inside");
    close(o.stiffness[(DX, DX)], 100.0, 1e-12, "Kt inside");
    close(st.energy.elastic, 1.125, 1e-12, "elastic energy inside");

    // Exactly at SD+ = 0.2: not beyond → no stop force (F = 20)
    let (o, _) = eval_once(&prop, &p, dx(0.2));
    assert_eq!(o.parts[DX].stop, 0.0);
    assert_eq!(o.status[DX].stop, StopContact::None);
    close(o.total[DX], 20.0, 1e-12, "total at stop");

    // Beyond SD+: q = 0.25 → elastic 100·0.25 = 25, stop 1e4·(0.25 − 0.2) = 500, F = 525,
    // Kt = 100 + 1e4 = 10100, E = ½·100·0.0625 + ½·1e4·0.05² = 3.125 + 12.5 = 15.625
    let (o, st) = eval_once(&prop, &p, dx(0.25));
    close(o.parts[DX].elastic, 25.0, 1e-12, "elastic beyond SD+");
    close(o.parts[DX].stop, 500.0, 1e-9, "stop beyond SD+");
    close(o.total[DX], 525.0, 1e-9, "total beyond SD+");
    assert_eq!(o.status[DX].stop, StopContact::Max);
    assert_eq!(o.status[DX].friction, FrictionStatus::None);
    close(o.stiffness[(DX, DX)], 10100.0, 1e-9, "Kt beyond SD+");
    close(st.energy.elastic, 15.625, 1e-9, "energy beyond SD+");

    // Beyond SD-: q = -0.12 → elastic -12, stop 1e4·(-0.12 + 0.1) = -200, F = -212,
    // Kt = 10100, E = ½·100·0.0144 + ½·1e4·0.02² = 0.72 + 2 = 2.72
    let (o, st) = eval_once(&prop, &p, dx(-0.12));
    close(o.parts[DX].elastic, -12.0, 1e-12, "elastic beyond SD-");
    close(o.parts[DX].stop, -200.0, 1e-9, "stop beyond SD-");
    close(o.total[DX], -212.0, 1e-9, "total beyond SD-");
    assert_eq!(o.status[DX].stop, StopContact::Min);
    close(o.stiffness[(DX, DX)], 10100.0, 1e-9, "Kt beyond SD-");
    close(st.energy.elastic, 2.72, 1e-9, "energy beyond SD-");
}

/// Critical damping (§4.6) acts on a free DOF only while its stop is in contact.
#[test]
fn stop_contact_switches_on_critical_damping() {
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, DofLaw::spring(100.0).with_stops(-0.1, 0.2));
    let p = params(1e4, 1e5, 2.0, 0.5);
    let rate = [0.5, 0.0, 0.0, 0.0, 0.0, 0.0];

    // Inside, rate 0.5, no viscosity: no damping at all.
    let mut st = LawState::default();
    let o = evaluate(&prop, &p, &dx(0.15), &rate, false, &mut st);
    assert_eq!(o.parts[DX].damping, 0.0);
    assert_eq!(o.damping[(DX, DX)], 0.0);

    // Beyond SD+: Kt = 10100, m_r = 2, Cr = 0 → 0.05:
    // c = 0.05·√(10100·2) = 7.106335201775948, F_d = c·0.5 = 3.553167600887974
    let mut st = LawState::default();
    let o = evaluate(&prop, &p, &dx(0.25), &rate, false, &mut st);
    close(o.damping[(DX, DX)], 7.106335201775948, 1e-9, "c in stop");
    close(o.parts[DX].damping, 3.553167600887974, 1e-9, "F_d in stop");
    close(
        o.total[DX],
        525.0 + 3.553167600887974,
        1e-9,
        "total in stop",
    );
}

/// Kf = 500 > 0 is the stop stiffness; FF = 0 so friction is inactive (§1, §4.2).
#[test]
fn independent_stops_use_kf_without_friction() {
    let law = DofLaw::spring(100.0)
        .with_stops(-0.1, 0.2)
        .with_friction(500.0, 0.0);
    assert!(!law.friction_active());
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, law);
    prop.validate().unwrap();
    let p = params(1e4, 1e5, 2.0, 0.5);

    // Inside: q = 0.1 → F = 10, no friction, no stop.
    let (o, _) = eval_once(&prop, &p, dx(0.1));
    close(o.total[DX], 10.0, 1e-12, "inside");
    assert_eq!(o.parts[DX].friction, 0.0);
    assert_eq!(o.status[DX].friction, FrictionStatus::None);
    close(
        o.stiffness[(DX, DX)],
        100.0,
        1e-12,
        "Kt inside (no friction spring)",
    );

    // q = 0.3: elastic 30, stop 500·0.1 = 50, F = 80, Kt = 600,
    // E = ½·100·0.09 + ½·500·0.01 = 4.5 + 2.5 = 7
    let (o, st) = eval_once(&prop, &p, dx(0.3));
    close(o.parts[DX].stop, 50.0, 1e-9, "stop Kf beyond SD+");
    close(o.total[DX], 80.0, 1e-9, "total beyond SD+");
    assert_eq!(o.parts[DX].friction, 0.0);
    assert_eq!(o.status[DX].friction, FrictionStatus::None);
    assert_eq!(o.status[DX].stop, StopContact::Max);
    close(o.stiffness[(DX, DX)], 600.0, 1e-9, "Kt beyond SD+");
    close(st.energy.elastic, 7.0, 1e-9, "energy beyond SD+");

    // q = -0.15: elastic -15, stop 500·(-0.05) = -25, F = -40, Kt = 600,
    // E = ½·100·0.0225 + ½·500·0.0025 = 1.125 + 0.625 = 1.75
    let (o, st) = eval_once(&prop, &p, dx(-0.15));
    close(o.parts[DX].stop, -25.0, 1e-9, "stop Kf beyond SD-");
    close(o.total[DX], -40.0, 1e-9, "total beyond SD-");
    assert_eq!(o.status[DX].stop, StopContact::Min);
    close(o.stiffness[(DX, DX)], 600.0, 1e-9, "Kt beyond SD-");
    close(st.energy.elastic, 1.75, 1e-9, "energy beyond SD-");
}

/// A zero stop means "no stop on that side" (§1).
#[test]
fn zero_stop_means_no_stop_on_that_side() {
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, DofLaw::spring(100.0).with_stops(0.0, 0.2));
    let p = params(1e4, 1e5, 2.0, 0.5);
    // q = -5: only the spring, F = -500, no stop
    let (o, _) = eval_once(&prop, &p, dx(-5.0));
    assert_eq!(o.parts[DX].stop, 0.0);
    assert_eq!(o.status[DX].stop, StopContact::None);
    close(o.total[DX], -500.0, 1e-9, "no negative stop");
}

// ---------------------------------------------------------------------------------------
// 2. Coupled stops (spec §4.3) and validation (§1)
// ---------------------------------------------------------------------------------------

fn planar_coupled(min: f64, max: f64) -> KjointProperty {
    KjointProperty::new(JointType::Planar)
        .with_kn(1000.0)
        .with_dof(
            Dof::Dy,
            DofLaw::spring(0.0)
                .with_stops(min, max)
                .with_coupled_stops(),
        )
        .with_dof(
            Dof::Dz,
            DofLaw::spring(0.0)
                .with_stops(min, max)
                .with_coupled_stops(),
        )
}

#[test]
fn coupled_stops_centred_interval() {
    let prop = planar_coupled(-0.1, 0.1);
    prop.validate().unwrap();
    let p = params(1000.0, 1e4, 1.0, 1.0);

    // Inside the radius: (0.07, 0.07) → d = 0.09899 < R = 0.1: no stop force, although each
    // component alone would also be inside; and (0.09, -0.04) → d = 0.0985 < 0.1.
    for (y, z) in [(0.07, 0.07), (0.09, -0.04)] {
        let (o, st) = eval_once(&prop, &p, [0.0, y, z, 0.0, 0.0, 0.0]);
        assert_eq!(o.parts[DY].stop, 0.0);
        assert_eq!(o.parts[DZ].stop, 0.0);
        assert_eq!(o.status[DY].stop, StopContact::None);
        assert_eq!(o.status[DZ].stop, StopContact::None);
        assert_eq!(st.energy.elastic, 0.0);
    }

    // (0.08, 0.08): each component inside [-0.1, 0.1] but d = 0.113137 > R = 0.1 → force:
    // pen = 0.0131371, F_k = 1000·pen·0.08/0.113137 = 1000·(1 − 0.1/0.113137)·0.08
    //     = 80 − 100·0.08/0.1131371 = 80 − 70.7106781 = 9.2893219
    let (o, _) = eval_once(&prop, &p, [0.0, 0.08, 0.08, 0.0, 0.0, 0.0]);
    let expected = 80.0 - 8.0 / (0.08f64 * 2f64.sqrt());
    close(expected, 9.289321881345245, 1e-12, "hand value");
    close(
        o.parts[DY].stop,
        9.289321881345245,
        1e-9,
        "coupled y (diag)",
    );
    close(
        o.parts[DZ].stop,
        9.289321881345245,
        1e-9,
        "coupled z (diag)",
    );
    assert_eq!(o.status[DY].stop, StopContact::Coupled);

    // (0.3, 0.4): d = 0.5, R = 0.1, pen = 0.4, n = (0.6, 0.8):
    // F_y = 1000·0.4·0.6 = 240, F_z = 1000·0.4·0.8 = 320, E = ½·1000·0.4² = 80.
    // Kt = ks[(1 − R/d)·I + (R/d)·n nᵀ], R/d = 0.2:
    // Kt_yy = 1000(0.8 + 0.2·0.36) = 872, Kt_yz = 1000·0.2·0.48 = 96, Kt_zz = 1000(0.8 + 0.128) = 928
    let (o, st) = eval_once(&prop, &p, [0.0, 0.3, 0.4, 0.0, 0.0, 0.0]);
    close(o.parts[DY].stop, 240.0, 1e-9, "F_y");
    close(o.parts[DZ].stop, 320.0, 1e-9, "F_z");
    close(o.total[DY], 240.0, 1e-9, "total y");
    close(o.total[DZ], 320.0, 1e-9, "total z");
    assert_eq!(o.status[DY].stop, StopContact::Coupled);
    assert_eq!(o.status[DZ].stop, StopContact::Coupled);
    close(st.energy.elastic, 80.0, 1e-9, "coupled energy");
    close(o.stiffness[(DY, DY)], 872.0, 1e-9, "Kt_yy");
    close(o.stiffness[(DY, DZ)], 96.0, 1e-9, "Kt_yz");
    close(o.stiffness[(DZ, DY)], 96.0, 1e-9, "Kt_zy");
    close(o.stiffness[(DZ, DZ)], 928.0, 1e-9, "Kt_zz");
    // dx (blocked) and rx (free, no law) untouched
    assert_eq!(o.parts[DX].stop, 0.0);
    assert_eq!(o.parts[RX].stop, 0.0);
}

#[test]
fn coupled_stops_off_centre_interval() {
    // SD- = -0.1, SD+ = 0.3 → c = 0.1 on each coupled component, R = 0.2
    let prop = planar_coupled(-0.1, 0.3);
    prop.validate().unwrap();
    let p = params(1000.0, 1e4, 1.0, 1.0);

    // (0, 0): distance from c = √(0.1² + 0.1²) = 0.1414 < 0.2 → no force
    // (-0.08, 0.1): distance 0.18 < 0.2 → no force (though -0.08 is close to SD- = -0.1)
    for (y, z) in [(0.0, 0.0), (-0.08, 0.1), (0.28, 0.1)] {
        let (o, _) = eval_once(&prop, &p, [0.0, y, z, 0.0, 0.0, 0.0]);
        assert_eq!(o.parts[DY].stop, 0.0, "({y}, {z})");
        assert_eq!(o.parts[DZ].stop, 0.0, "({y}, {z})");
    }

    // (-0.15, 0.1): only y beyond SD-; d = 0.25, pen = 0.05, n = (-1, 0):
    // F_y = 1000·0.05·(-1) = -50, F_z = 0
    let (o, _) = eval_once(&prop, &p, [0.0, -0.15, 0.1, 0.0, 0.0, 0.0]);
    close(o.parts[DY].stop, -50.0, 1e-9, "F_y off-centre 1-D");
    close(o.parts[DZ].stop, 0.0, 1e-12, "F_z off-centre 1-D");

    // (0.4, 0.5): q − c = (0.3, 0.4), d = 0.5, pen = 0.3, n = (0.6, 0.8):
    // F_y = 1000·0.3·0.6 = 180, F_z = 1000·0.3·0.8 = 240, E = ½·1000·0.09 = 45
    let (o, st) = eval_once(&prop, &p, [0.0, 0.4, 0.5, 0.0, 0.0, 0.0]);
    close(o.parts[DY].stop, 180.0, 1e-9, "F_y off-centre");
    close(o.parts[DZ].stop, 240.0, 1e-9, "F_z off-centre");
    close(st.energy.elastic, 45.0, 1e-9, "energy off-centre");

    // (-0.2, -0.3): q − c = (-0.3, -0.4), same magnitude, opposite direction
    let (o, _) = eval_once(&prop, &p, [0.0, -0.2, -0.3, 0.0, 0.0, 0.0]);
    close(o.parts[DY].stop, -180.0, 1e-9, "F_y off-centre neg");
    close(o.parts[DZ].stop, -240.0, 1e-9, "F_z off-centre neg");
}

/// Coupled stops with Kf > 0: the stop stiffness is Kf (§4.2 applies to §4.3).
#[test]
fn coupled_stops_with_kf_stiffness() {
    let law = DofLaw::spring(0.0)
        .with_stops(-0.1, 0.1)
        .with_coupled_stops()
        .with_friction(50.0, 0.0);
    let prop = KjointProperty::new(JointType::Planar)
        .with_kn(1000.0)
        .with_dof(Dof::Dy, law.clone())
        .with_dof(Dof::Dz, law);
    prop.validate().unwrap();
    let p = params(1000.0, 1e4, 1.0, 1.0);
    // (0.3, 0.4): F = 50·0.4·(0.6, 0.8) = (12, 16)
    let (o, _) = eval_once(&prop, &p, [0.0, 0.3, 0.4, 0.0, 0.0, 0.0]);
    close(o.parts[DY].stop, 12.0, 1e-9, "F_y (Kf)");
    close(o.parts[DZ].stop, 16.0, 1e-9, "F_z (Kf)");
}

fn is_field_error(r: Result<(), PropertyError>, field_part: &str) {
    match r {
        Err(PropertyError::InvalidField { field, .. }) => assert!(
            field.contains(field_part),
            "error on field `{field}`, expected one mentioning `{field_part}`"
        ),
        other => panic!("expected an InvalidField error on `{field_part}`, got {other:?}"),
    }
}

#[test]
fn validation_rules() {
    // unequal stops on coupled DOFs
    let prop = KjointProperty::new(JointType::Planar)
        .with_kn(1000.0)
        .with_dof(
            Dof::Dy,
            DofLaw::spring(0.0)
                .with_stops(-0.1, 0.1)
                .with_coupled_stops(),
        )
        .with_dof(
            Dof::Dz,
            DofLaw::spring(0.0)
                .with_stops(-0.1, 0.2)
                .with_coupled_stops(),
        );
    is_field_error(prop.validate(), "dz");
    // the same stops are accepted
    planar_coupled(-0.1, 0.2).validate().unwrap();

    // stop of the wrong sign: SD- > 0, SD+ < 0
    let base = KjointProperty::new(JointType::Translational).with_kn(1000.0);
    is_field_error(
        base.clone()
            .with_dof(Dof::Dx, DofLaw::spring(1.0).with_stops(0.1, 0.2))
            .validate(),
        "stop_min",
    );
    is_field_error(
        base.clone()
            .with_dof(Dof::Dx, DofLaw::spring(1.0).with_stops(-0.1, -0.05))
            .validate(),
        "stop_max",
    );
    // rotational stop of the wrong sign (SA-), on a revolute
    is_field_error(
        KjointProperty::new(JointType::Revolute)
            .with_dof(Dof::Rx, DofLaw::spring(1.0).with_stops(0.3, 0.5))
            .validate(),
        "SA-",
    );

    // Cr outside [0, 1]
    is_field_error(
        base.clone().with_critical_damping(1.5).validate(),
        "critical_damping",
    );
    is_field_error(
        base.clone().with_critical_damping(-0.1).validate(),
        "critical_damping",
    );
    base.clone().with_critical_damping(1.0).validate().unwrap();

    // NaN
    is_field_error(base.clone().with_kn(f64::NAN).validate(), "kn");
    is_field_error(
        base.clone().with_critical_damping(f64::NAN).validate(),
        "critical_damping",
    );
    is_field_error(
        base.clone()
            .with_dof(Dof::Dx, DofLaw::spring(f64::NAN))
            .validate(),
        "stiffness",
    );
    is_field_error(
        base.clone()
            .with_dof(Dof::Dx, DofLaw::spring(1.0).with_stops(f64::NAN, 0.2))
            .validate(),
        "stop_min",
    );

    // joint type numbers
    assert_eq!(
        JointType::from_number(0),
        Err(PropertyError::UnknownJointType(0))
    );
    assert_eq!(
        JointType::from_number(10),
        Err(PropertyError::UnknownJointType(10))
    );
    assert_eq!(JointType::from_number(4), Ok(JointType::Planar));
    assert_eq!(JointType::from_number(9), Ok(JointType::Free));
}

/// Issue 12, item 5: `Icomb = 1` needs two or three DOFs of one family; a coupled group has
/// friction on all members or none (with friction the friction springs are the stop, §4.2);
/// a Kn whose KR = Kn·max(ScF, L0²) overflows is refused.
#[test]
fn validation_of_coupling_and_overflowing_stiffness() {
    let coupled = DofLaw::spring(0.0)
        .with_stops(-0.1, 0.1)
        .with_coupled_stops();
    // a single coupled DOF: the revolute's rx, or dy alone on a planar joint
    is_field_error(
        KjointProperty::new(JointType::Revolute)
            .with_dof(Dof::Rx, coupled.clone())
            .validate(),
        "rx.coupled_stops (Icomb)",
    );
    is_field_error(
        KjointProperty::new(JointType::Planar)
            .with_dof(Dof::Dy, coupled.clone())
            .with_dof(Dof::Rx, coupled.clone())
            .validate(),
        "dy.coupled_stops (Icomb)",
    );
    // friction on one coupled DOF only
    is_field_error(
        KjointProperty::new(JointType::Planar)
            .with_dof(Dof::Dy, coupled.clone().with_friction(1e3, 5.0))
            .with_dof(Dof::Dz, coupled.clone())
            .validate(),
        "dz.friction",
    );
    KjointProperty::new(JointType::Planar)
        .with_dof(Dof::Dy, coupled.clone().with_friction(1e3, 5.0))
        .with_dof(Dof::Dz, coupled.with_friction(1e3, 5.0))
        .validate()
        .unwrap();
    // KR = Kn·ScF overflows: Kn named (ScF when it is the larger)
    let base = KjointProperty::new(JointType::Fixed);
    is_field_error(base.clone().with_kn(1e308).validate(), "kn (Kn)");
    is_field_error(
        base.clone()
            .with_kn(10.0)
            .with_scale_factor(1e308)
            .validate(),
        "scale_factor (ScF)",
    );
    base.clone().with_kn(1e307).validate().unwrap();
    match base.with_kn(1e308).validate() {
        Err(PropertyError::InvalidField { value, .. }) => assert_eq!(value, "1e308"),
        other => panic!("{other:?}"),
    }
}

// ---------------------------------------------------------------------------------------
// 3. Friction (spec §4.4)
// ---------------------------------------------------------------------------------------

#[test]
fn elasto_plastic_friction_cycle() {
    // Kf = 1000, FF = 5, no spring, free dx; rates 0 so no damping.
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, DofLaw::spring(0.0).with_friction(1000.0, 5.0));
    assert!(prop.dof(Dof::Dx).friction_active());
    let p = params(1e4, 1e5, 1.0, 1.0);
    let mut st = LawState::default();

    use FrictionStatus::{Slip, Stick};
    // (q, stored force s, status, cumulative plastic slip)
    // trial s* = s + 1000·Δq, cap 5:
    let steps: [(f64, f64, FrictionStatus, f64); 11] = [
        (0.0, 0.0, Stick, 0.0),        // first call, Δq = 0
        (0.0015, 1.5, Stick, 0.0),     // s* = 1.5
        (0.003, 3.0, Stick, 0.0),      // s* = 3
        (0.0045, 4.5, Stick, 0.0),     // s* = 4.5
        (0.006, 5.0, Slip, 0.001),     // s* = 6 → 5, slip (6−5)/1000 = 0.001
        (0.0075, 5.0, Slip, 0.0025),   // s* = 6.5 → 5, slip 0.0015
        (0.006, 3.5, Stick, 0.0025),   // unloading: s* = 5 − 1.5 = 3.5 (slope Kf)
        (0.003, 0.5, Stick, 0.0025),   // s* = 3.5 − 3 = 0.5
        (0.0, -2.5, Stick, 0.0025),    // s* = 0.5 − 3 = −2.5
        (-0.003, -5.0, Slip, 0.003),   // s* = −5.5 → −5, slip 0.0005
        (-0.0045, -5.0, Slip, 0.0045), // s* = −6.5 → −5, slip 0.0015
    ];
    for (k, &(q, s, status, slip)) in steps.iter().enumerate() {
        let o = evaluate(&prop, &p, &dx(q), &[0.0; 6], false, &mut st);
        close(o.parts[DX].friction, s, 1e-9, &format!("step {k}: s"));
        close(o.total[DX], s, 1e-9, &format!("step {k}: total"));
        close(
            st.friction_force[DX],
            s,
            1e-9,
            &format!("step {k}: state s"),
        );
        assert_eq!(o.status[DX].friction, status, "step {k}");
        // tangent: Kf while sticking, 0 while slipping
        let kt = if status == Stick { 1000.0 } else { 0.0 };
        close(o.stiffness[(DX, DX)], kt, 1e-9, &format!("step {k}: Kt"));
        // dissipated = cap × plastic slip
        close(
            st.energy.friction,
            5.0 * slip,
            1e-12,
            &format!("step {k}: friction work"),
        );
        // stored = s²/(2Kf)
        close(
            st.energy.elastic,
            s * s / 2000.0,
            1e-12,
            &format!("step {k}: stored"),
        );
    }
    // total friction work 5·0.0045 = 0.0225; stored ½·25/1000 = 0.0125
    close(st.energy.friction, 0.0225, 1e-12, "friction work total");
    close(st.energy.elastic, 0.0125, 1e-12, "stored at end");
    // internal = Σ ½Δq(F_new + F_old) over the force sequence
    // 0,1.5,3,4.5,5,5,3.5,0.5,−2.5,−5,−5:
    //  .0015·0.75 + .0015·2.25 + .0015·3.75 + .0015·4.75 + .0015·5
    //  − .0015·4.25 − .003·2 − .003·(−1) − .003·(−3.75) − .0015·(−5) = 0.034125
    close(st.energy.internal, 0.034125, 1e-12, "internal energy");
}

#[test]
fn friction_with_function_of_displacement() {
    // FF = 2 scales g(δ) = 1 + 2δ (points (0,1), (1,3)); Kf = 1000; cap = 2·(1 + 2δ)
    let mut law = DofLaw::spring(0.0).with_friction(1000.0, 2.0);
    law.friction_curve = Some(Curve::new([(0.0, 1.0), (1.0, 3.0)]).unwrap());
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, law);
    let p = params(1e4, 1e5, 1.0, 1.0);
    let mut st = LawState::default();

    // q = 0: s = 0 (stick)
    let o = evaluate(&prop, &p, &dx(0.0), &[0.0; 6], false, &mut st);
    assert_eq!(o.status[DX].friction, FrictionStatus::Stick);
    // q = 0.001: s* = 1 ≤ cap = 2·1.002 = 2.004 → stick, s = 1
    let o = evaluate(&prop, &p, &dx(0.001), &[0.0; 6], false, &mut st);
    close(o.parts[DX].friction, 1.0, 1e-9, "stick under curve cap");
    assert_eq!(o.status[DX].friction, FrictionStatus::Stick);
    // q = 0.003: s* = 3 > cap = 2·1.006 = 2.012 → slip, s = 2.012,
    // work = 2.012·(3 − 2.012)/1000 = 0.001987856
    let o = evaluate(&prop, &p, &dx(0.003), &[0.0; 6], false, &mut st);
    close(o.parts[DX].friction, 2.012, 1e-9, "cap 2·g(0.003)");
    assert_eq!(o.status[DX].friction, FrictionStatus::Slip);
    close(st.energy.friction, 0.001987856, 1e-12, "work 1");
    // q = 0.5: s* = 2.012 + 497 = 499.012 > cap = 2·2 = 4 → s = 4,
    // work += 4·(499.012 − 4)/1000 = 1.980048 → total 1.982035856
    let o = evaluate(&prop, &p, &dx(0.5), &[0.0; 6], false, &mut st);
    close(o.parts[DX].friction, 4.0, 1e-9, "cap 2·g(0.5)");
    assert_eq!(o.status[DX].friction, FrictionStatus::Slip);
    close(st.energy.friction, 1.982035856, 1e-9, "work 2");
    // q = 0.499: s* = 4 − 1 = 3 ≤ cap = 2·1.998 = 3.996 → stick, s = 3
    let o = evaluate(&prop, &p, &dx(0.499), &[0.0; 6], false, &mut st);
    close(o.parts[DX].friction, 3.0, 1e-9, "unload stick");
    assert_eq!(o.status[DX].friction, FrictionStatus::Stick);

    // FF = 0 with a curve: scale 1 (§1), friction active; constant g = 3 (two points with
    // the same value)
    let mut law = DofLaw::spring(0.0).with_friction(1000.0, 0.0);
    law.friction_curve = Some(Curve::new([(0.0, 3.0), (1.0, 3.0)]).unwrap());
    assert!(law.friction_active());
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, law);
    let mut st = LawState::default();
    evaluate(&prop, &p, &dx(0.0), &[0.0; 6], false, &mut st);
    // q = 0.01: s* = 10 > cap 1·3 → s = 3 (slip)
    let o = evaluate(&prop, &p, &dx(0.01), &[0.0; 6], false, &mut st);
    close(o.parts[DX].friction, 3.0, 1e-9, "FF=0 with curve: scale 1");
    assert_eq!(o.status[DX].friction, FrictionStatus::Slip);
}

/// A stop with active friction (spec §4.2, §4.4, OpenRadioss `STDPL`): beyond the stop the
/// friction spring, its cap lifted, is the stop; no separate stop spring is added.
/// Kf = 1000, FF = 50, SD+ = 100 on a monotone path: the spring slips at 50 up to δ = 100,
/// then loads elastically: F(120) = 50 + 1000·20 = 20050 (OpenRadioss; 40050 with both
/// springs), and back at 110: 20050 − 1000·10 = 10050.
#[test]
fn stop_with_active_friction_is_the_friction_spring() {
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(
            Dof::Dx,
            DofLaw::spring(0.0)
                .with_stops(0.0, 100.0)
                .with_friction(1000.0, 50.0),
        );
    prop.validate().unwrap();
    let p = params(1e4, 1e5, 1.0, 1.0);
    let mut st = LawState::default();
    let mut last = None;
    for k in 0..=240 {
        last = Some(evaluate(
            &prop,
            &p,
            &dx(0.5 * k as f64),
            &[0.0; 6],
            false,
            &mut st,
        ));
    }
    let o = last.take().unwrap();
    close(o.total[DX], 20050.0, 1e-9, "F(120)");
    assert_eq!(o.parts[DX].stop, 0.0, "no separate stop spring");
    close(
        o.parts[DX].friction,
        20050.0,
        1e-9,
        "friction spring is the stop",
    );
    assert_eq!(o.status[DX].stop, StopContact::Max);
    assert_eq!(o.status[DX].friction, FrictionStatus::Stick);
    close(o.stiffness[(DX, DX)], 1000.0, 1e-9, "Kt = Kf once");
    // stored = 20050²/2000; dissipated = 50·(100 − 0.05) (the slip up to the stop)
    close(
        st.energy.elastic,
        20050.0 * 20050.0 / 2000.0,
        1e-6,
        "stored",
    );
    close(st.energy.friction, 50.0 * 99.95, 1e-6, "slip work");
    for k in 1..=20 {
        last = Some(evaluate(
            &prop,
            &p,
            &dx(120.0 - 0.5 * k as f64),
            &[0.0; 6],
            false,
            &mut st,
        ));
    }
    close(last.unwrap().total[DX], 10050.0, 1e-9, "F(110) unloading");
}

/// The same with coupled stops (§4.3): a planar joint, dy and dz coupled with SD∓ = ∓100,
/// friction Kf = 1000, FF = 50 on both; pushed along y to 120 and back to 110:
/// 20050 and 10050 on dy, nothing on dz, no coupled stop spring.
#[test]
fn coupled_stop_with_active_friction_is_the_friction_spring() {
    let law = DofLaw::spring(0.0)
        .with_stops(-100.0, 100.0)
        .with_coupled_stops()
        .with_friction(1000.0, 50.0);
    let prop = KjointProperty::new(JointType::Planar)
        .with_kn(1e4)
        .with_dof(Dof::Dy, law.clone())
        .with_dof(Dof::Dz, law);
    prop.validate().unwrap();
    let p = params(1e4, 1e5, 1.0, 1.0);
    let mut st = LawState::default();
    let y = |v: f64| [0.0, v, 0.0, 0.0, 0.0, 0.0];
    let mut last = None;
    for k in 0..=240 {
        last = Some(evaluate(
            &prop,
            &p,
            &y(0.5 * k as f64),
            &[0.0; 6],
            false,
            &mut st,
        ));
    }
    let o = last.take().unwrap();
    close(o.total[DY], 20050.0, 1e-9, "F_y(120)");
    close(o.total[DZ], 0.0, 1e-12, "F_z");
    assert_eq!(o.parts[DY].stop, 0.0, "no coupled stop spring");
    assert_eq!(o.status[DY].stop, StopContact::Coupled);
    for k in 1..=20 {
        last = Some(evaluate(
            &prop,
            &p,
            &y(120.0 - 0.5 * k as f64),
            &[0.0; 6],
            false,
            &mut st,
        ));
    }
    close(last.unwrap().total[DY], 10050.0, 1e-9, "F_y(110) unloading");
}

/// A friction curve whose cap falls below the stored force between two evaluations: the
/// return releases that excess at a falling force, and its energy is dissipated too.
/// Kf = 1000, FF = 10, g = 1 up to δ = 0.01, then 0.1 from δ = 0.011. Stick at δ = 0.0095
/// (s = 9.5); at δ = 0.011: s* = 11, cap 1, slip (11 − 1)/1000 = 0.01. Of the excess 10,
/// e_c = 9.5 − 1 = 8.5 comes from the fallen cap: work = (1·10 + ½·8.5²)/1000 = 0.046125
/// (cap·slip alone, 0.010, lost 8.5²/2000 = 0.036125). The energy released by the spring,
/// (9.5² − 1²)/2000 = 0.044625, is no longer missing from the balance.
#[test]
fn falling_friction_cap_dissipates_the_released_energy() {
    let mut law = DofLaw::spring(0.0).with_friction(1000.0, 10.0);
    law.friction_curve = Some(Curve::new([(0.0, 1.0), (0.01, 1.0), (0.011, 0.1)]).unwrap());
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, law);
    let p = params(1e4, 1e5, 1.0, 1.0);
    let mut st = LawState::default();
    evaluate(&prop, &p, &dx(0.0), &[0.0; 6], false, &mut st);
    let o = evaluate(&prop, &p, &dx(0.0095), &[0.0; 6], false, &mut st);
    close(o.parts[DX].friction, 9.5, 1e-9, "stick");
    let o = evaluate(&prop, &p, &dx(0.011), &[0.0; 6], false, &mut st);
    assert_eq!(o.status[DX].friction, FrictionStatus::Slip);
    close(
        o.parts[DX].friction,
        1.0,
        1e-9,
        "returned onto the fallen cap",
    );
    close(st.energy.friction, 0.046125, 1e-12, "work of the return");
}

/// A stop reached within an increment lifts the cap only for the part beyond it (§4.4):
/// Kf = 1000, FF = 50, SD+ = 100, slipping at 50 up to δ = 99, then one step to 101: the
/// spring slips at the cap up to the stop (work 50·1) and loads elastically beyond it,
/// s = 50 + 1000·1 = 1050 (the whole increment elastic gave 50 + 2000 = 2050: the stop moved
/// 1 back, by the part of the step before it). One step out to 99.9: the spring unloads
/// elastically to 50 at the stop and loads on the other side, s* = 1050 − 1100 = −50, on the
/// cap: no slip.
#[test]
fn a_stop_reached_within_a_step_lifts_the_cap_beyond_it_only() {
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(
            Dof::Dx,
            DofLaw::spring(0.0)
                .with_stops(0.0, 100.0)
                .with_friction(1000.0, 50.0),
        );
    let p = params(1e4, 1e5, 1.0, 1.0);
    let mut st = LawState::default();
    evaluate(&prop, &p, &dx(98.0), &[0.0; 6], false, &mut st);
    evaluate(&prop, &p, &dx(99.0), &[0.0; 6], false, &mut st);
    let w0 = st.energy.friction;
    let o = evaluate(&prop, &p, &dx(101.0), &[0.0; 6], false, &mut st);
    close(o.parts[DX].friction, 1050.0, 1e-9, "in the stop");
    assert_eq!(o.status[DX].friction, FrictionStatus::Stick);
    close(st.energy.friction - w0, 50.0, 1e-9, "slip up to the stop");
    let o = evaluate(&prop, &p, &dx(99.9), &[0.0; 6], false, &mut st);
    close(
        o.parts[DX].friction,
        -50.0,
        1e-9,
        "on the cap, the other way",
    );
    close(
        st.energy.friction - w0,
        50.0,
        1e-9,
        "no slip out of the stop",
    );
}

/// A stored friction force above an unchanged cap slips at the cap: only a *fallen* cap
/// releases its excess as dissipation. Kf = 1000, sticking at s = 1000 under FF = 2000 at
/// δ = 1, then the property changed to FF = 50 (`Kjoint::set_property`: the state is kept,
/// the cap is 50 at both evaluations) and one step to 1.1: s* = 1100, slip 1.05 at the cap,
/// work 50·1.05 = 52.5 (the stored 1000 above the cap is not counted as a fallen cap's
/// release, which would add ½·950²/1000 = 451.25). A stop left within a step no longer
/// gives such a force: the spring beyond a stop loads from the force it had at the stop.
#[test]
fn a_stored_force_above_an_unchanged_cap_slips_at_it() {
    let prop = |ff: f64| {
        KjointProperty::new(JointType::Translational)
            .with_kn(1e4)
            .with_dof(Dof::Dx, DofLaw::spring(0.0).with_friction(1000.0, ff))
    };
    let p = params(1e4, 1e5, 1.0, 1.0);
    let mut st = LawState::default();
    evaluate(&prop(2000.0), &p, &dx(0.0), &[0.0; 6], false, &mut st);
    let o = evaluate(&prop(2000.0), &p, &dx(1.0), &[0.0; 6], false, &mut st);
    close(o.parts[DX].friction, 1000.0, 1e-9, "sticking");
    let o = evaluate(&prop(50.0), &p, &dx(1.1), &[0.0; 6], false, &mut st);
    assert_eq!(o.status[DX].friction, FrictionStatus::Slip);
    close(o.parts[DX].friction, 50.0, 1e-9, "on the cap");
    close(st.energy.friction, 52.5, 1e-9, "slip at the cap");
}

/// A property changed while the DOF is beyond its new stop (the law's state kept): the
/// DOF did not reach the stop within the step, so nothing of the step slips under the
/// cap. Kf = 1000, FF = 50, no stop, sticking at s = 10 at δ = 100.5; then a stop at 100
/// and one step back to 100.3, still beyond it: elastic, s = 10 − 200 = −190.
#[test]
fn a_dof_beyond_a_new_stop_moves_elastically_in_it() {
    let law = DofLaw::spring(0.0).with_friction(1000.0, 50.0);
    let free = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, law.clone());
    let stopped = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, law.with_stops(0.0, 100.0));
    let p = params(1e4, 1e5, 1.0, 1.0);
    let mut st = LawState::default();
    evaluate(&free, &p, &dx(100.49), &[0.0; 6], false, &mut st);
    let o = evaluate(&free, &p, &dx(100.5), &[0.0; 6], false, &mut st);
    close(o.parts[DX].friction, 10.0, 1e-9, "sticking");
    let w0 = st.energy.friction;
    let o = evaluate(&stopped, &p, &dx(100.3), &[0.0; 6], false, &mut st);
    assert_eq!(o.status[DX].stop, StopContact::Max);
    close(o.parts[DX].friction, -190.0, 1e-9, "elastic in the stop");
    close(st.energy.friction, w0, 1e-12, "no slip");
}

/// The same with coupled stops (§4.3): an Oldham joint, dy and dz coupled with R = 0.1,
/// friction Kf = 1e5, FF = 10 on both, slipping at 10 along the diagonal up to
/// (0.06, 0.06) (|p| = 0.0848528), then one step to (0.08, 0.08) (0.1131371): the circle is
/// crossed at t = (0.1 − 0.0848528)/(0.1131371 − 0.0848528) = 0.5355339 of the step, so each
/// spring loads elastically by 1e5·(1 − t)·0.02 = 928.9322 from its cap: s = 938.9322 (the
/// whole step elastic gave 2010). Slip work up to the circle: 10·t·0.02 per DOF.
#[test]
fn a_coupled_stop_reached_within_a_step_lifts_the_cap_beyond_it_only() {
    let law = DofLaw::spring(0.0)
        .with_stops(-0.1, 0.1)
        .with_coupled_stops()
        .with_friction(1e5, 10.0);
    let prop = KjointProperty::new(JointType::Oldham)
        .with_kn(1e6)
        .with_dof(Dof::Dy, law.clone())
        .with_dof(Dof::Dz, law);
    prop.validate().unwrap();
    let p = params(1e6, 1e7, 1.0, 1.0);
    let mut st = LawState::default();
    let yz = |v: f64| [0.0, v, v, 0.0, 0.0, 0.0];
    evaluate(&prop, &p, &yz(0.05), &[0.0; 6], false, &mut st);
    let o = evaluate(&prop, &p, &yz(0.06), &[0.0; 6], false, &mut st);
    assert_eq!(o.status[DY].friction, FrictionStatus::Slip);
    let w0 = st.energy.friction;
    let o = evaluate(&prop, &p, &yz(0.08), &[0.0; 6], false, &mut st);
    let t = (0.1 - 0.06 * 2f64.sqrt()) / (0.02 * 2f64.sqrt());
    close(t, 0.5355339059327377, 1e-12, "hand value");
    for i in [DY, DZ] {
        assert_eq!(o.status[i].stop, StopContact::Coupled);
        close(o.parts[i].friction, 938.9321881345, 1e-6, "in the stop");
    }
    close(
        st.energy.friction - w0,
        2.0 * 10.0 * t * 0.02,
        1e-12,
        "slip up to the circle",
    );
}

// ---------------------------------------------------------------------------------------
// 4. Curves and linear extrapolation (spec §4.1)
// ---------------------------------------------------------------------------------------

fn curve_0_10_15() -> Curve {
    Curve::new([(0.0, 0.0), (1.0, 10.0), (2.0, 15.0)]).unwrap()
}

#[test]
fn curve_values_extrapolation_and_integral() {
    let c = curve_0_10_15();
    // f(3) = 15 + 5·1 = 20 (last slope 5), f(−1) = 0 − 10·1 = −10 (first slope 10)
    close(c.value(3.0), 20.0, 1e-12, "f(3)");
    close(c.value(-1.0), -10.0, 1e-12, "f(-1)");
    close(c.value(0.5), 5.0, 1e-12, "f(0.5)");
    close(c.value(1.5), 12.5, 1e-12, "f(1.5)");
    close(c.slope(3.0), 5.0, 1e-12, "f'(3)");
    close(c.slope(-1.0), 10.0, 1e-12, "f'(-1)");
    close(c.slope(0.5), 10.0, 1e-12, "f'(0.5)");
    // ∫₀³ f = ∫₀¹ (0+10)/2 + ∫₁² (10+15)/2 + ∫₂³ (15+20)/2 = 5 + 12.5 + 17.5 = 35
    close(c.integral(0.0, 3.0), 35.0, 1e-12, "∫0^3");
    close(c.integral_from_zero(3.0), 35.0, 1e-12, "∫0^3 from zero");
    // ∫₋₁⁰ f = (−10 + 0)/2 = −5, so ∫₀⁻¹ f = +5
    close(c.integral(-1.0, 0.0), -5.0, 1e-12, "∫-1^0");
    close(c.integral_from_zero(-1.0), 5.0, 1e-12, "∫0^-1");
    // ∫_{0.5}^{2.5} = (5+10)/2·0.5 + 12.5 + (15+17.5)/2·0.5 = 3.75 + 12.5 + 8.125 = 24.375
    close(c.integral(0.5, 2.5), 24.375, 1e-12, "∫0.5^2.5");
    close(c.integral(2.5, 0.5), -24.375, 1e-12, "∫2.5^0.5");
    // ∫₋₂⁻¹ = (−20 − 10)/2 = −15
    close(c.integral(-2.0, -1.0), -15.0, 1e-12, "∫-2^-1");
    // a constant is two points with the same value (a single point is refused)
    let k = Curve::new([(1.0, 4.0), (2.0, 4.0)]).unwrap();
    close(k.value(-7.0), 4.0, 0.0, "constant");
    close(k.integral(0.0, 2.0), 8.0, 1e-12, "∫ constant");
    assert!(Curve::new([(1.0, 4.0)]).is_err());
    // malformed curves
    assert!(Curve::new([(0.0, 0.0), (0.0, 1.0)]).is_err());
    assert!(Curve::new(std::iter::empty()).is_err());
    assert!(Curve::new([(0.0, f64::NAN)]).is_err());
}

#[test]
fn stiffness_curve_in_the_law() {
    // K = 3 scales f: F = 3·f(δ), Kt = 3·f'(δ), E = 3·∫₀^δ f
    let mut law = DofLaw::spring(3.0);
    law.stiffness_curve = Some(curve_0_10_15());
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, law);
    let p = params(1e4, 1e5, 1.0, 1.0);

    // δ = 3: F = 3·20 = 60, Kt = 3·5 = 15, E = 3·35 = 105
    let (o, st) = eval_once(&prop, &p, dx(3.0));
    close(o.parts[DX].elastic, 60.0, 1e-12, "F(3)");
    close(o.stiffness[(DX, DX)], 15.0, 1e-12, "Kt(3)");
    close(st.energy.elastic, 105.0, 1e-12, "E(3)");
    // δ = −1: F = 3·(−10) = −30, Kt = 3·10 = 30, E = 3·5 = 15
    let (o, st) = eval_once(&prop, &p, dx(-1.0));
    close(o.parts[DX].elastic, -30.0, 1e-12, "F(-1)");
    close(o.stiffness[(DX, DX)], 30.0, 1e-12, "Kt(-1)");
    close(st.energy.elastic, 15.0, 1e-12, "E(-1)");

    // K = 0 with a curve: scale 1 → F(3) = 20
    let mut law = DofLaw::spring(0.0);
    law.stiffness_curve = Some(curve_0_10_15());
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, law);
    let (o, _) = eval_once(&prop, &p, dx(3.0));
    close(o.parts[DX].elastic, 20.0, 1e-12, "F(3), K = 0 → 1");
}

// ---------------------------------------------------------------------------------------
// 5. Sensor lock: from the state at activation, no jump (spec §4.5)
// ---------------------------------------------------------------------------------------

#[test]
fn sensor_lock_engages_without_a_jump_in_stop_contact() {
    // revolute: rx free with K = 10, SA+ = 0.5; Kn = 1e4, KR = 200
    let prop = KjointProperty::new(JointType::Revolute)
        .with_kn(1e4)
        .with_sensor(1)
        .with_dof(Dof::Rx, DofLaw::spring(10.0).with_stops(0.0, 0.5));
    prop.validate().unwrap();
    let p = params(1e4, 200.0, 1.0, 0.5);
    let qb = |th: f64| [0.001, -0.002, 0.003, th, 0.01, -0.02];
    let mut st = LawState::default();

    // before the sensor: no lock
    let o = evaluate(&prop, &p, &qb(0.2), &[0.0; 6], false, &mut st);
    assert_eq!(o.parts[RX].sensor, 0.0);
    assert!(!o.status[RX].locked);
    assert!(st.lock.is_none());
    let blocked_before: Vec<f64> = [0, 1, 2, 4, 5].iter().map(|&i| o.total[i]).collect();

    // in stop contact at θx = 0.7 without the lock: elastic 10·0.7 = 7, stop
    // 200·(0.7 − 0.5) = 40, total 47
    let before = evaluate(&prop, &p, &qb(0.7), &[0.0; 6], false, &mut st.clone());
    close(before.total[RX], 47.0, 1e-9, "total before activation");
    // activation at θx = 0.7 → θs = 0.7 as it is: the sensor part starts at 0, the total
    // does not jump (OpenRadioss clipped θs to 0.5 and jumped to 87)
    let o = evaluate(&prop, &p, &qb(0.7), &[0.0; 6], true, &mut st);
    close(
        st.lock.as_ref().unwrap().values[RX],
        0.7,
        0.0,
        "lock value as at activation",
    );
    close(o.parts[RX].elastic, 7.0, 1e-12, "elastic at activation");
    close(o.parts[RX].stop, 40.0, 1e-9, "stop at activation");
    close(o.parts[RX].sensor, 0.0, 0.0, "sensor at activation");
    close(
        o.total[RX],
        before.total[RX],
        1e-12,
        "no jump at activation",
    );
    assert!(o.status[RX].locked);
    assert_eq!(o.status[RX].stop, StopContact::Max);
    // the force of the activation is held from this evaluation on, so the tangent is the
    // lock's alone, KR = 200, as at every later evaluation (it was 10 + 200 (stop) + 200
    // (lock) = 410 for this one substep, and its critical damping with it); the law's own
    // tangent, 10 + 200 = 210, is kept for the energy book
    close(o.stiffness[(RX, RX)], 200.0, 0.0, "Kt locked in stop");
    close(
        st.lock.as_ref().unwrap().held_tangent[RX],
        210.0,
        1e-12,
        "the law's tangent at activation",
    );

    // From then on the force of the activation is held (spec §4.5: "on top of the force it
    // carries at activation, held constant"): elastic 7 and stop 40 stay, the lock adds
    // KR·(θ − 0.7). θx = 0.6: 47 − 20 = 27 (the law alone would give 6 + 20 − 20 = 6).
    let o = evaluate(&prop, &p, &qb(0.6), &[0.0; 6], true, &mut st);
    close(o.parts[RX].sensor, -20.0, 1e-9, "sensor at 0.6");
    close(o.parts[RX].stop, 40.0, 1e-9, "stop force held at 0.6");
    close(o.parts[RX].elastic, 7.0, 1e-12, "elastic force held at 0.6");
    close(o.total[RX], 27.0, 1e-9, "total at 0.6");
    // the lock alone is the tangent: Kt = KR = 200 (no spring, no stop)
    close(o.stiffness[(RX, RX)], 200.0, 0.0, "Kt held");
    assert_eq!(
        o.status[RX].stop,
        StopContact::None,
        "no stop acts while held"
    );
    // stored energy: at activation ½·10·0.7² + ½·200·0.2² = 2.45 + 4 = 6.45 on θx, then
    // 47·(−0.1) + ½·200·0.01 = −4.7 + 1 → 2.75 (+ the blocked DOFs' ½·K_b·q²)
    let blocked_energy = 0.5 * 1e4 * (1e-6 + 4e-6 + 9e-6) + 0.5 * 200.0 * (1e-4 + 4e-4);
    close(
        st.energy.elastic,
        6.45 - 4.7 + 1.0 + blocked_energy,
        1e-9,
        "stored energy held",
    );
    // θx = 0.3: 47 + 200·(0.3 − 0.7) = −33 (the law would have added 3 and dropped the stop)
    let o = evaluate(&prop, &p, &qb(0.3), &[0.0; 6], true, &mut st);
    close(o.parts[RX].sensor, -80.0, 1e-9, "sensor at 0.3");
    close(o.parts[RX].stop, 40.0, 1e-9, "stop force held at 0.3");
    close(o.total[RX], -33.0, 1e-9, "total at 0.3");
    assert!(o.status[RX].locked);
    // the lock value does not move
    close(
        st.lock.as_ref().unwrap().values[RX],
        0.7,
        0.0,
        "lock value kept",
    );

    // blocked DOFs: not locked, no sensor part, forces as before (Kn·δ, KR·θ):
    // (10, −20, 30, _, 2, −4)
    let expected = [10.0, -20.0, 30.0, 0.0, 2.0, -4.0];
    for (n, &i) in [0usize, 1, 2, 4, 5].iter().enumerate() {
        assert!(!o.status[i].locked, "dof {i} locked");
        assert!(o.status[i].blocked);
        assert_eq!(o.parts[i].sensor, 0.0);
        close(o.total[i], expected[i], 1e-12, &format!("blocked dof {i}"));
        close(
            o.total[i],
            blocked_before[n],
            0.0,
            &format!("blocked dof {i} unchanged"),
        );
    }

    // critical damping while locked: θ̇ = 0.1, Kt = KR = 200 (the lock alone), I_r = 0.5
    // → c = 0.05·√(200·0.5) = 0.5, F_d = 0.05
    let mut rate = [0.0; 6];
    rate[RX] = 0.1;
    let o = evaluate(&prop, &p, &qb(0.3), &rate, true, &mut st);
    close(o.parts[RX].damping, 0.05, 1e-12, "critical damping locked");
}

#[test]
fn sensor_lock_holds_the_values_at_activation_beyond_and_inside_the_stops() {
    let prop = KjointProperty::new(JointType::Revolute)
        .with_kn(1e4)
        .with_dof(Dof::Rx, DofLaw::spring(0.0).with_stops(-0.4, 0.5));
    let p = params(1e4, 200.0, 1.0, 0.5);
    // activation at −0.9 (0.5 beyond SA−) → θs = −0.9; sensor at −0.9: 0
    let mut st = LawState::default();
    let mut q = [0.0; 6];
    q[RX] = -0.9;
    let o = evaluate(&prop, &p, &q, &[0.0; 6], true, &mut st);
    close(
        st.lock.as_ref().unwrap().values[RX],
        -0.9,
        0.0,
        "held beyond SA-",
    );
    close(o.parts[RX].sensor, 0.0, 0.0, "sensor at -0.9");
    // activation inside: θs = 0.25 exactly
    let mut st = LawState::default();
    q[RX] = 0.25;
    evaluate(&prop, &p, &q, &[0.0; 6], true, &mut st);
    close(
        st.lock.as_ref().unwrap().values[RX],
        0.25,
        0.0,
        "inside: not clipped",
    );
}

/// The universal joint's free rotations (ry, rz) are locked too (§4.5: OpenRadioss forgets
/// them, we must not).
#[test]
fn sensor_lock_covers_universal_free_rotations() {
    let prop = KjointProperty::new(JointType::Universal).with_kn(1e4);
    let p = params(1e4, 200.0, 1.0, 0.5);
    let mut st = LawState::default();
    // activation at θy = 0.3, θz = −0.2 (no stops): θs = (0.3, −0.2)
    evaluate(
        &prop,
        &p,
        &[0.0, 0.0, 0.0, 0.0, 0.3, -0.2],
        &[0.0; 6],
        true,
        &mut st,
    );
    // later θy = 0.35, θz = −0.1: sensor = 200·(0.05, 0.1) = (10, 20); rx (blocked) not locked
    let o = evaluate(
        &prop,
        &p,
        &[0.0, 0.0, 0.0, 0.0, 0.35, -0.1],
        &[0.0; 6],
        true,
        &mut st,
    );
    close(o.parts[4].sensor, 10.0, 1e-9, "ry locked");
    close(o.parts[5].sensor, 20.0, 1e-9, "rz locked");
    assert!(o.status[4].locked && o.status[5].locked);
    assert!(!o.status[RX].locked);
    assert_eq!(o.parts[RX].sensor, 0.0);
}

/// With coupled stops (the circle of radius R around c, §4.3) the lock also holds the values
/// at activation as they are (§4.5), here q = (0.3, 0.4) outside the circle of R = 0.1: the
/// lock starts with no force of its own, and the stop keeps carrying what it carried.
#[test]
fn sensor_lock_holds_coupled_values_at_activation() {
    let prop = planar_coupled(-0.1, 0.1);
    let p = params(1000.0, 1e4, 1.0, 1.0);
    let mut st = LawState::default();
    evaluate(
        &prop,
        &p,
        &[0.0, 0.3, 0.4, 0.0, 0.0, 0.0],
        &[0.0; 6],
        true,
        &mut st,
    );
    let lock = st.lock.clone().unwrap();
    close(lock.values[DY], 0.3, 0.0, "lock y as at activation");
    close(lock.values[DZ], 0.4, 0.0, "lock z as at activation");
    // the coupled stop's force at activation is held on each DOF, and no stop acts on:
    // d = 0.5, R = 0.1, ks = Kn = 1000 → 400 along n = (0.6, 0.8): (240, 320); moved on
    // to (0.31, 0.38) the lock adds Kn·(0.01, −0.02) = (10, −20)
    close(lock.held[DY].stop, 240.0, 1e-9, "coupled stop held on y");
    close(lock.held[DZ].stop, 320.0, 1e-9, "coupled stop held on z");
    let o = evaluate(
        &prop,
        &p,
        &[0.0, 0.31, 0.38, 0.0, 0.0, 0.0],
        &[0.0; 6],
        true,
        &mut st,
    );
    close(o.total[DY], 250.0, 1e-9, "y held + lock");
    close(o.total[DZ], 300.0, 1e-9, "z held + lock");
    close(
        o.stiffness[(DY, DZ)],
        0.0,
        0.0,
        "no coupled tangent while held",
    );
    close(o.stiffness[(DY, DY)], 1000.0, 0.0, "the lock's tangent");
}

// ---------------------------------------------------------------------------------------
// 6. Blocked DOFs and blocked stiffness (spec §4.1, §4.6, §5)
// ---------------------------------------------------------------------------------------

#[test]
fn blocked_dofs_penalty_and_critical_damping() {
    // fixed joint, Kn = 1e4, KR = 2000, m_r = 2·3/(2+3) = 1.2, I_r = 0.5, Cr = 0 → 0.05
    let prop = KjointProperty::new(JointType::Fixed).with_kn(1e4);
    let p = params(1e4, 2000.0, 1.2, 0.5);
    let q = [0.01, -0.02, 0.03, 0.1, -0.2, 0.05];
    let mut st = LawState::default();
    let o = evaluate(&prop, &p, &q, &[0.0; 6], false, &mut st);
    // F = (1e4·0.01, 1e4·(−0.02), 1e4·0.03, 2000·0.1, 2000·(−0.2), 2000·0.05)
    let f = [100.0, -200.0, 300.0, 200.0, -400.0, 100.0];
    #[allow(clippy::needless_range_loop)] // (`i` names the DOF in the messages)
    for i in 0..6 {
        assert!(o.status[i].blocked);
        close(o.parts[i].elastic, f[i], 1e-9, &format!("blocked F {i}"));
        close(o.total[i], f[i], 1e-9, &format!("blocked total {i}"));
        let k = if i < 3 { 1e4 } else { 2000.0 };
        close(o.stiffness[(i, i)], k, 0.0, &format!("Kt {i}"));
    }
    // E = ½·1e4·(1e-4 + 4e-4 + 9e-4) + ½·2000·(0.01 + 0.04 + 0.0025) = 7 + 52.5 = 59.5
    close(st.energy.elastic, 59.5, 1e-9, "blocked energy");

    // damping: c_t = 0.05·√(1e4·1.2) = 5.477225575051662, c_r = 0.05·√(2000·0.5) = 1.5811388
    let rate = [1.0, -2.0, 0.5, 3.0, -1.0, 0.2];
    let mut st = LawState::default();
    let o = evaluate(&prop, &p, &q, &rate, false, &mut st);
    let ct = 5.477225575051662;
    let cr = 1.5811388300841898;
    for i in 0..6 {
        let c = if i < 3 { ct } else { cr };
        close(o.damping[(i, i)], c, 1e-12, &format!("c {i}"));
        close(o.parts[i].damping, c * rate[i], 1e-12, &format!("F_d {i}"));
        close(o.total[i], f[i] + c * rate[i], 1e-9, &format!("total {i}"));
    }

    // explicit Cr = 0.2: c_t = 0.2·√12000 = 21.908902300206645
    let prop = prop.with_critical_damping(0.2);
    let mut st = LawState::default();
    let o = evaluate(&prop, &p, &q, &rate, false, &mut st);
    close(
        o.damping[(0, 0)],
        21.908902300206645,
        1e-12,
        "c_t with Cr = 0.2",
    );
}

#[test]
fn user_blocked_stiffness_numbers() {
    // Kn = 1000, ScF = 0 → 10: KR = 1000·max(10, L0²)
    let prop = KjointProperty::new(JointType::Fixed).with_kn(1000.0);
    close(
        prop.resolved_scale_factor(),
        10.0,
        0.0,
        "ScF default (Kn > 0)",
    );
    let b = stiffness::user_blocked_stiffness(&prop, 0.0);
    close(b.translational, 1000.0, 0.0, "Kn");
    close(b.rotational, 10_000.0, 1e-9, "KR = 1000·10");
    // L0 = 5: L0² = 25 > 10 → KR = 25000
    let b = stiffness::user_blocked_stiffness(&prop, 5.0);
    close(b.rotational, 25_000.0, 1e-9, "KR = 1000·25");
    // ScF = 2: L0 = 1 → KR = 2000; L0 = 1.5 → KR = 1000·2.25 = 2250
    let prop = prop.with_scale_factor(2.0);
    close(
        stiffness::user_blocked_stiffness(&prop, 1.0).rotational,
        2000.0,
        1e-9,
        "KR = 1000·2",
    );
    close(
        stiffness::user_blocked_stiffness(&prop, 1.5).rotational,
        2250.0,
        1e-9,
        "KR = 1000·2.25",
    );
    // Kn = 0: ScF default is 1
    close(
        KjointProperty::new(JointType::Fixed).resolved_scale_factor(),
        1.0,
        0.0,
        "ScF default (Kn = 0)",
    );
}

#[test]
fn automatic_blocked_stiffness_numbers() {
    let prop = KjointProperty::new(JointType::Fixed); // Kn = 0, ScF → 1
    let dt = 1e-3;
    // α·dt² = 4.1e-6
    let b1 = BodyMass {
        mass: 2.0,
        inertia: 0.1,
        anchor_offset_sq: 0.0,
    };
    let b2 = BodyMass {
        mass: 3.0,
        inertia: 0.2,
        anchor_offset_sq: 0.0,
    };
    // r² = 0: Kx_1 = 2·2/4.1e-6 = 975609.7560975611, Kx_2 = 6/4.1e-6 = 1463414.634
    // KX = 975609.756; KR = min(0.1, 0.2)/4.1e-6 = 24390.243902439
    let k = stiffness::automatic_blocked_stiffness(&prop, [b1, b2], 0.0, dt, [1.0, 1.0]);
    close(k.translational, 975609.7560975611, 1e-6, "KX, r² = 0");
    close(k.rotational, 24390.243902439026, 1e-7, "KR, r² = 0");

    // offsets 0.04 and 0.09 m², L0 = 0.4: r² = max(0.04, 0.09) + 0.16 = 0.25
    // Kx_1 = min(975609.76, 0.8·0.1/(4.1e-6·0.25) = 78048.78048780489)
    // Kx_2 = min(1463414.6, 0.8·0.2/(4.1e-6·0.25) = 156097.56)  → KX = 78048.78
    let b1o = BodyMass {
        anchor_offset_sq: 0.04,
        ..b1
    };
    let b2o = BodyMass {
        anchor_offset_sq: 0.09,
        ..b2
    };
    let k = stiffness::automatic_blocked_stiffness(&prop, [b1o, b2o], 0.4, dt, [1.0, 1.0]);
    close(k.translational, 78048.78048780489, 1e-7, "KX, r² = 0.25");
    close(k.rotational, 24390.243902439026, 1e-7, "KR, r² = 0.25");

    // ScF = 0.5 halves both
    let k = stiffness::automatic_blocked_stiffness(
        &prop.clone().with_scale_factor(0.5),
        [b1o, b2o],
        0.4,
        dt,
        [1.0, 1.0],
    );
    close(k.translational, 39024.390243902445, 1e-7, "KX·0.5");
    close(k.rotational, 12195.121951219513, 1e-7, "KR·0.5");

    // body 1 fixed: it does not bound the minimum.
    // r² = 0: KX = Kx_2 = 1463414.6341463416, KR = 0.2/4.1e-6 = 48780.48780487805
    let k =
        stiffness::automatic_blocked_stiffness(&prop, [BodyMass::FIXED, b2], 0.0, dt, [1.0, 1.0]);
    close(
        k.translational,
        1463414.6341463416,
        1e-6,
        "KX, fixed body 1",
    );
    close(k.rotational, 48780.48780487805, 1e-7, "KR, fixed body 1");
    // body 2 offset 0.09, L0 = 0: r² = 0.09, Kx_2 = min(1463414.6, 0.16/(4.1e-6·0.09)
    // = 433604.33604336047)
    let k =
        stiffness::automatic_blocked_stiffness(&prop, [BodyMass::FIXED, b2o], 0.0, dt, [1.0, 1.0]);
    close(
        k.translational,
        433604.33604336047,
        1e-6,
        "KX, fixed body 1, r² = 0.09",
    );

    // share ½ on body 1 (two automatic joints on it): Kx_1 = 975609.76/2 = 487804.878
    let k = stiffness::automatic_blocked_stiffness(&prop, [b1, b2], 0.0, dt, [0.5, 1.0]);
    close(k.translational, 487804.87804878055, 1e-6, "KX, share ½");
    close(k.rotational, 12195.121951219513, 1e-7, "KR, share ½");
}

#[test]
fn stable_dt_numbers() {
    let b1 = BodyMass {
        mass: 2.0,
        inertia: 0.1,
        anchor_offset_sq: 0.0,
    };
    let b2 = BodyMass {
        mass: 3.0,
        inertia: 0.2,
        anchor_offset_sq: 0.0,
    };
    // (These numbers were √2 too large on translation before: the nodal translational
    // stiffness of OpenRadioss receives 2·S, so the term is √(m/S), not √(2m/S).)
    // ξ = 0.75: (0.75 + √(1 + 0.5625))² = (0.75 + 1.25)² = 4 → S = 4·1e4 = 4e4, S_r = 4·250 = 1000
    // translation: 0.9·min(√(2/4e4), √(3/4e4)) = 0.9·√5e-5 = 0.00636396103067893
    // rotation (L = 0): 0.9·min(√(2·0.1/1000), √(2·0.2/1000)) = 0.9·√2e-4 = 0.012727922061357857
    let dt = stiffness::stable_dt([b1, b2], 1e4, 250.0, 0.75, 0.0);
    close(dt.translational, 0.00636396103067893, 1e-15, "dt_trans");
    close(dt.rotational, 0.012727922061357857, 1e-15, "dt_rot");
    close(dt.min(), 0.00636396103067893, 1e-15, "dt");
    // ξ = 0: factor 1: translation 0.9·√(2/1e4) = 0.012727922061357857
    let dt = stiffness::stable_dt([b1, b2], 1e4, 250.0, 0.0, 0.0);
    close(
        dt.translational,
        0.012727922061357857,
        1e-15,
        "dt_trans, ξ = 0",
    );
    // L = 0.1: S_r + S·L² = 1000 + 4e4·0.01 = 1400: 0.9·√(0.2/1400) = 0.010757057484009542
    let dt = stiffness::stable_dt([b1, b2], 1e4, 250.0, 0.75, 0.1);
    close(
        dt.rotational,
        0.010757057484009542,
        1e-15,
        "dt_rot, L = 0.1",
    );
    // body 1 fixed: translation 0.9·√(3/4e4) = 0.007794228634059948, rotation 0.9·√(4e-4) = 0.018
    let dt = stiffness::stable_dt([BodyMass::FIXED, b2], 1e4, 250.0, 0.75, 0.0);
    close(
        dt.translational,
        0.007794228634059948,
        1e-15,
        "dt_trans, fixed body",
    );
    close(dt.rotational, 0.018, 1e-15, "dt_rot, fixed body");
}

/// Spec §5 check (issue 12, item 3): a fixed joint (type 8) between a fixed node and a body
/// of m = I = 1, L0 = 0, Kn = 1e4, ScF = 10 (KR = 1e5), Cr = 0.05:
/// f = (0.05 + √1.0025)² = 1.1051249219725041, dt_trans = 0.9·√(1/(1e4·f)) = 8.561e-3 (the crate gave
/// 1.2107e-2, √2 larger), dt_rot = 0.9·√(2/(1e5·f)) = 3.829e-3.
#[test]
fn stable_dt_of_the_spec_check() {
    let body = BodyMass {
        mass: 1.0,
        inertia: 1.0,
        anchor_offset_sq: 0.0,
    };
    let dt = stiffness::stable_dt([BodyMass::FIXED, body], 1e4, 1e5, 0.05, 0.0);
    close(dt.translational, 0.008561242977525352, 1e-15, "dt_trans");
    close(dt.rotational, 0.0038287042539278788, 1e-15, "dt_rot");
    assert!(
        (dt.translational - 8.561e-3).abs() < 0.5e-6,
        "{}",
        dt.translational
    );
    assert!(
        (dt.rotational - 3.829e-3).abs() < 0.5e-6,
        "{}",
        dt.rotational
    );
}

/// Spec §5 check (issue 12, item 2), the OpenRadioss KJOINT2 QA model: body 1 fixed with the
/// spring node 75 from its centre of mass, body 2 of 156 kg, I = 31200, anchored at its
/// centre, L0 = 0, dt = 1.475e-3 (α·dt² = 8.9200625e-6): r² = 75² = 5625 (the fixed body's
/// offset counts), KX = min(2·156/(α·dt²), 0.8·31200/(α·dt²·5625)) = 4.97455e5 (the crate
/// gave 3.4977e7 with the fixed body's offset taken as 0), KR = 31200/(α·dt²) = 3.49773e9.
#[test]
fn automatic_stiffness_counts_the_fixed_body_offset() {
    let prop = KjointProperty::new(JointType::Spherical);
    let rb2 = BodyMass {
        mass: 156.0,
        inertia: 31200.0,
        anchor_offset_sq: 0.0,
    };
    let dt = 1.475e-3;
    let k = stiffness::automatic_blocked_stiffness(
        &prop,
        [BodyMass::fixed(75.0 * 75.0), rb2],
        0.0,
        dt,
        [1.0, 1.0],
    );
    let adt2 = 4.1 * dt * dt;
    close(k.translational, 0.8 * 31200.0 / (adt2 * 5625.0), 1e-6, "KX");
    close(k.rotational, 31200.0 / adt2, 1e-3, "KR");
    assert!(
        (k.translational / 4.97455e5 - 1.0).abs() < 1e-6,
        "KX = {}",
        k.translational
    );
    assert!(
        (k.rotational / 3.49773e9 - 1.0).abs() < 1e-6,
        "KR = {}",
        k.rotational
    );
}

// ---------------------------------------------------------------------------------------
// 7. Energy (spec §4.8)
// ---------------------------------------------------------------------------------------

#[test]
fn linear_spring_energy_is_exact() {
    // K = 200, 0 → 0.1 in 10 equal steps: internal = ½·200·0.1² = 1 (trapezoid exact)
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, DofLaw::spring(200.0));
    let p = params(1e4, 1e5, 1.0, 1.0);
    let mut st = LawState::default();
    for k in 0..=10 {
        evaluate(&prop, &p, &dx(0.01 * k as f64), &[0.0; 6], false, &mut st);
    }
    close(st.energy.internal, 1.0, 1e-12, "internal");
    close(st.energy.elastic, 1.0, 1e-12, "elastic");
    assert_eq!(st.energy.damping, 0.0);
    assert_eq!(st.energy.friction, 0.0);
    assert_eq!(st.energy.stop, 0.0);
}

#[test]
fn viscous_work_with_constant_rate() {
    // K = 200, C = 10, rate 2: damping force 20 at every step,
    // damping work = C·rate·Δq = 10·2·0.1 = 2; internal = 1 + 2 = 3; elastic = 1
    let prop = KjointProperty::new(JointType::Translational)
        .with_kn(1e4)
        .with_dof(Dof::Dx, DofLaw::spring(200.0).with_viscosity(10.0));
    let p = params(1e4, 1e5, 1.0, 1.0);
    let rate = [2.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let mut st = LawState::default();
    for k in 0..=10 {
        let o = evaluate(&prop, &p, &dx(0.01 * k as f64), &rate, false, &mut st);
        close(o.parts[DX].damping, 20.0, 1e-12, "C·v");
    }
    close(st.energy.damping, 2.0, 1e-12, "damping work");
    close(st.energy.internal, 3.0, 1e-12, "internal");
    close(st.energy.elastic, 1.0, 1e-12, "elastic");
    close(st.energy.dissipated(), 2.0, 1e-12, "dissipated");
}

// ---------------------------------------------------------------------------------------
// 8. Kinematics: moment balance, rigid motion, swap, unwrapped twist (spec §3, §4.7)
// ---------------------------------------------------------------------------------------

struct Pair {
    frames: JointFrames,
    b1: BodyPose,
    b2: BodyPose,
}

fn quat(axis: [f64; 3], angle: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vector3::new(axis[0], axis[1], axis[2])),
        angle,
    )
}

/// Two rotated bodies with centres of mass off the anchors and 1.3 m between the anchors.
fn pair(measure: RotationMeasure) -> Pair {
    let la1 = Vector3::new(0.3, -0.2, 0.1);
    let la2 = Vector3::new(-0.1, 0.25, 0.4);
    let r1 = quat([0.2, 1.0, -0.3], 0.7);
    let r2 = quat([-0.5, 0.4, 1.0], 1.1);
    let t1 = Vector3::new(1.0, 2.0, -0.5);
    let p1 = t1 + r1 * la1;
    let p2 = p1 + 1.3 * Vector3::new(2.0, -1.0, 2.0).normalize();
    let t2 = p2 - r2 * la2;
    let b1 = BodyPose {
        translation: t1,
        rotation: r1,
        com: t1 + r1 * Vector3::new(0.05, 0.1, -0.07),
        linvel: Vector3::new(0.3, -0.1, 0.2),
        angvel: Vector3::new(0.5, 0.2, -0.4),
    };
    let b2 = BodyPose {
        translation: t2,
        rotation: r2,
        com: t2 + r2 * Vector3::new(-0.2, 0.03, 0.15),
        linvel: Vector3::new(-0.4, 0.6, 0.1),
        angvel: Vector3::new(-0.3, 0.7, 0.25),
    };
    let frames = JointFrames {
        local_anchor1: la1,
        local_anchor2: la2,
        local_frame1: quat([1.0, 0.0, 0.2], 0.3),
        // body 2's frame: chosen so that the relative rotation is moderate
        local_frame2: r2.inverse() * r1 * quat([1.0, 0.0, 0.2], 0.3) * quat([0.3, 1.0, 0.5], 0.4),
        delta0: Vector3::new(1.2, 0.1, -0.2),
        measure,
        translation: TranslationMeasure::MidPoint,
    };
    Pair { frames, b1, b2 }
}

#[test]
fn moment_balance_of_a_long_joint() {
    for m in [
        RotationMeasure::RotationVector,
        RotationMeasure::TwistX,
        RotationMeasure::Cardan,
    ] {
        let Pair { frames, b1, b2 } = pair(m);
        let kin = kinematics::measure(&frames, &b1, &b2, &mut MeasureState::default());
        let l = kin.p2 - kin.p1;
        close(l.norm(), 1.3, 1e-12, "joint length");
        // q's translation + δ0 is L in E, so its norm is 1.3 too
        let dq = Vector3::new(kin.q[0], kin.q[1], kin.q[2]) + frames.delta0;
        close(dq.norm(), 1.3, 1e-12, "|δ + δ0|");

        let pv = Vector6::new(3.0, -7.0, 11.0, 0.5, -2.0, 1.5);
        let w1 = kin.jac1.transpose() * pv;
        let w2 = kin.jac2.transpose() * pv;
        let f1 = w1.fixed_rows::<3>(0).into_owned();
        let t1 = w1.fixed_rows::<3>(3).into_owned();
        let f2 = w2.fixed_rows::<3>(0).into_owned();
        let t2 = w2.fixed_rows::<3>(3).into_owned();
        let total_f = f1 + f2;
        let total_m = b1.com.cross(&f1) + t1 + b2.com.cross(&f2) + t2;
        assert!(total_f.norm() < 1e-9, "{m:?}: total force {total_f}");
        assert!(total_m.norm() < 1e-9, "{m:?}: total moment {total_m}");
        // and the forces are not trivially zero
        assert!(f1.norm() > 1.0);

        // §4.7 with internal force (F, M) = P: body 1 gets +E·F at p1 and E(M + ½ L_E×F);
        // body 2 gets −E·F at p2 and −E(M − ½ L_E×F). The generalised force of an internal
        // force is −Jᵀ·P, so −jac1ᵀP must equal that wrench reduced to the centre of mass.
        let e = kin.frame.matrix();
        let ff = Vector3::new(pv[0], pv[1], pv[2]);
        let mm = Vector3::new(pv[3], pv[4], pv[5]);
        let le = e.transpose() * l;
        let f1_spec = e * ff;
        let m1_spec = (kin.p1 - b1.com).cross(&f1_spec) + e * (mm + 0.5 * le.cross(&ff));
        let f2_spec = -(e * ff);
        let m2_spec = (kin.p2 - b2.com).cross(&f2_spec) - e * (mm - 0.5 * le.cross(&ff));
        assert!((-f1 - f1_spec).norm() < 1e-9, "{m:?}: body 1 force vs §4.7");
        assert!((-f2 - f2_spec).norm() < 1e-9, "{m:?}: body 2 force vs §4.7");
        if m != RotationMeasure::Cardan {
            // (the universal joint's moments are conjugate to its Cardan rates, not E-axes)
            assert!(
                (-t1 - m1_spec).norm() < 1e-9,
                "{m:?}: body 1 moment vs §4.7"
            );
            assert!(
                (-t2 - m2_spec).norm() < 1e-9,
                "{m:?}: body 2 moment vs §4.7"
            );
        }

        // rates = jac1·(v1, ω1) + jac2·(v2, ω2)
        let v1 = Vector6::new(
            b1.linvel.x,
            b1.linvel.y,
            b1.linvel.z,
            b1.angvel.x,
            b1.angvel.y,
            b1.angvel.z,
        );
        let v2 = Vector6::new(
            b2.linvel.x,
            b2.linvel.y,
            b2.linvel.z,
            b2.angvel.x,
            b2.angvel.y,
            b2.angvel.z,
        );
        let r = kin.jac1 * v1 + kin.jac2 * v2;
        for i in 0..6 {
            close(r[i], kin.rate[i], 1e-12, &format!("{m:?}: rate {i} = J·v"));
        }
    }
}

#[test]
fn rigid_motion_gives_zero_rates() {
    for m in [
        RotationMeasure::RotationVector,
        RotationMeasure::TwistX,
        RotationMeasure::Cardan,
    ] {
        let Pair {
            frames,
            mut b1,
            mut b2,
        } = pair(m);
        let w = Vector3::new(0.8, -1.3, 0.45);
        b1.angvel = w;
        b1.linvel = Vector3::new(0.2, -0.7, 1.1);
        b2.angvel = w;
        b2.linvel = b1.linvel + w.cross(&(b2.com - b1.com));
        let kin = kinematics::measure(&frames, &b1, &b2, &mut MeasureState::default());
        for i in 0..6 {
            assert!(
                kin.rate[i].abs() < 1e-12,
                "{m:?}: rate {i} = {} for a rigid motion",
                kin.rate[i]
            );
        }
    }
}

#[test]
fn swapping_the_bodies_flips_q() {
    for m in [RotationMeasure::RotationVector, RotationMeasure::TwistX] {
        let Pair { frames, b1, b2 } = pair(m);
        let kin = kinematics::measure(&frames, &b1, &b2, &mut MeasureState::default());
        // swapped joint: anchors and frames exchanged, δ0 → −δ0 (same working frame E)
        let swapped = JointFrames {
            local_anchor1: frames.local_anchor2,
            local_anchor2: frames.local_anchor1,
            local_frame1: frames.local_frame2,
            local_frame2: frames.local_frame1,
            delta0: -frames.delta0,
            measure: m,
            translation: TranslationMeasure::MidPoint,
        };
        let ks = kinematics::measure(&swapped, &b2, &b1, &mut MeasureState::default());
        // sanity: the relative rotation is not tiny
        let th = Vector3::new(kin.q[3], kin.q[4], kin.q[5]).norm();
        assert!(th > 0.2, "{m:?}: |θ| = {th}");
        for i in 0..6 {
            close(ks.q[i], -kin.q[i], 1e-12, &format!("{m:?}: q {i} flips"));
            close(
                ks.rate[i],
                -kin.rate[i],
                1e-12,
                &format!("{m:?}: rate {i} flips"),
            );
        }
        // the working frame is the same
        assert!(
            (ks.frame.matrix() - kin.frame.matrix()).norm() < 1e-12,
            "{m:?}: frame differs"
        );
    }
}

/// Issue 12, item 4: the universal joint is a Cardan joint. Body 2 turned by R_y(a)·R_z(b)
/// relative to body 1 (a = b = 0.3), the cross's y arm on body 1 and z arm on body 2: the
/// blocked θx is 0 (OpenRadioss' frame is built from one axis of each body), θy = a, θz = b.
/// The rotation vector's x component, which the crate penalised, is ½·a·b = 0.045 to second
/// order (0.04568 exactly).
#[test]
fn universal_joint_measures_cardan_angles() {
    let frames = |measure| JointFrames {
        local_anchor1: Vector3::zeros(),
        local_anchor2: Vector3::zeros(),
        local_frame1: UnitQuaternion::identity(),
        local_frame2: UnitQuaternion::identity(),
        delta0: Vector3::zeros(),
        measure,
        translation: TranslationMeasure::MidPoint,
    };
    let b1 = BodyPose::identity();
    for (a, b) in [(0.3, 0.3), (-0.7, 0.2), (1.2, -2.5)] {
        let b2 = BodyPose {
            rotation: quat([0.0, 1.0, 0.0], a) * quat([0.0, 0.0, 1.0], b),
            ..BodyPose::identity()
        };
        let kin = kinematics::measure(
            &frames(RotationMeasure::Cardan),
            &b1,
            &b2,
            &mut MeasureState::default(),
        );
        close(kin.q[3], 0.0, 1e-14, "blocked θx of a Cardan motion");
        close(kin.q[4], a, 1e-14, "θy");
        close(kin.q[5], b, 1e-14, "θz");
    }
    let b2 = BodyPose {
        rotation: quat([0.0, 1.0, 0.0], 0.3) * quat([0.0, 0.0, 1.0], 0.3),
        ..BodyPose::identity()
    };
    let rv = kinematics::measure(
        &frames(RotationMeasure::RotationVector),
        &b1,
        &b2,
        &mut MeasureState::default(),
    );
    close(rv.q[3], 0.045, 1e-3, "rotation vector: θx ≈ ½·a·b");
    // a deviation of the arms from 90° is the blocked θx: R_y(a)·R_x(c)·R_z(b)
    let b2 = BodyPose {
        rotation: quat([0.0, 1.0, 0.0], 0.4)
            * quat([1.0, 0.0, 0.0], 0.05)
            * quat([0.0, 0.0, 1.0], -0.6),
        ..BodyPose::identity()
    };
    let kin = kinematics::measure(
        &frames(RotationMeasure::Cardan),
        &b1,
        &b2,
        &mut MeasureState::default(),
    );
    close(kin.q[3], 0.05, 1e-14, "θx = deviation of the arms");
    close(kin.q[4], 0.4, 1e-14, "θy");
    close(kin.q[5], -0.6, 1e-14, "θz");
}

/// The Cardan rates (and the Jacobian rows, which give them) are the time derivatives of
/// the Cardan angles: along a smooth motion of both bodies, central differences of θ match
/// the reported θ̇ to O(dt²); the free angles are continued over full turns.
#[test]
fn cardan_rates_are_the_derivatives_of_the_angles() {
    let Pair { frames, .. } = pair(RotationMeasure::Cardan);
    let w1 = Vector3::new(0.4, -0.9, 0.3);
    let w2 = Vector3::new(-0.2, 1.7, 2.9);
    let pose = |t: f64, w: Vector3<f64>, r0: UnitQuaternion<f64>| BodyPose {
        rotation: UnitQuaternion::from_scaled_axis(w * t) * r0,
        angvel: w,
        ..BodyPose::identity()
    };
    let (r1, r2) = (quat([0.2, 1.0, -0.3], 0.7), quat([-0.5, 0.4, 1.0], 1.1));
    let mut st = MeasureState::default();
    let dt = 1e-5;
    let mut prev: Option<[f64; 6]> = None;
    let mut max_turn: f64 = 0.0;
    for k in 0..=4000 {
        let t = k as f64 * 1e-3;
        let (p1, p2) = (pose(t, w1, r1), pose(t, w2, r2));
        let kin = kinematics::measure(&frames, &p1, &p2, &mut st);
        if let Some(p) = prev {
            // continuity (no jump of 2π)
            for (i, (a, b)) in kin.q.iter().zip(p).enumerate().skip(3) {
                assert!((a - b).abs() < 0.05, "jump of q{i} at t = {t}");
            }
        }
        prev = Some(kin.q);
        max_turn = max_turn.max(kin.q[5].abs());
        if k % 500 == 250 {
            let mut sa = st;
            let mut sb = st;
            let qa = kinematics::measure(
                &frames,
                &pose(t - dt, w1, r1),
                &pose(t - dt, w2, r2),
                &mut sa,
            )
            .q;
            let qb = kinematics::measure(
                &frames,
                &pose(t + dt, w1, r1),
                &pose(t + dt, w2, r2),
                &mut sb,
            )
            .q;
            for i in 3..6 {
                let fd = (qb[i] - qa[i]) / (2.0 * dt);
                close(kin.rate[i], fd, 1e-6, &format!("θ̇{i} at t = {t}"));
            }
        }
    }
    assert!(max_turn > 3.3, "θz continued past π: {max_turn}");
}

/// Revolute: a relative twist of 7 rad about x in small increments, split symmetrically
/// between the bodies on top of a common rotation R0: θx = 7 (unwrapped), θy = θz = 0, and
/// returning to 0 gives 0 exactly (no drift).
#[test]
fn twist_is_unwrapped_and_does_not_drift() {
    let r0 = quat([0.3, -0.5, 0.8], 0.9);
    let frames = JointFrames {
        local_anchor1: Vector3::new(0.0, 0.0, 0.0),
        local_anchor2: Vector3::new(0.0, 0.0, 0.0),
        local_frame1: UnitQuaternion::identity(),
        local_frame2: UnitQuaternion::identity(),
        delta0: Vector3::zeros(),
        measure: RotationMeasure::TwistX,
        translation: TranslationMeasure::MidPoint,
    };
    let pose = |a: f64, b1: bool| BodyPose {
        rotation: r0 * quat([1.0, 0.0, 0.0], if b1 { -0.5 * a } else { 0.5 * a }),
        ..BodyPose::identity()
    };
    let mut ms = MeasureState::default();
    let n = 140; // 0.05 rad per step
    let mut last = 0.0;
    for k in 0..=n {
        let a = 7.0 * k as f64 / n as f64;
        let kin = kinematics::measure(&frames, &pose(a, true), &pose(a, false), &mut ms);
        close(kin.q[3], a, 1e-9, &format!("θx at {a}"));
        assert!(kin.q[4].abs() < 1e-9 && kin.q[5].abs() < 1e-9);
        // E's x axis is the common joint axis R0·x
        let ex = kin.frame * Vector3::x();
        assert!((ex - r0 * Vector3::x()).norm() < 1e-9);
        last = kin.q[3];
    }
    close(last, 7.0, 1e-9, "θx = 7 after the turn");
    for k in (0..n).rev() {
        let a = 7.0 * k as f64 / n as f64;
        let kin = kinematics::measure(&frames, &pose(a, true), &pose(a, false), &mut ms);
        close(kin.q[3], a, 1e-9, &format!("θx back at {a}"));
        last = kin.q[3];
    }
    close(last, 0.0, 1e-12, "θx back to 0");

    // the same path with the rotation-vector measure (free joint) is also continued past π
    let frames = JointFrames {
        measure: RotationMeasure::RotationVector,
        ..frames
    };
    let mut ms = MeasureState::default();
    for k in 0..=n {
        let a = 7.0 * k as f64 / n as f64;
        last = kinematics::measure(&frames, &pose(a, true), &pose(a, false), &mut ms).q[3];
        close(last, a, 1e-9, &format!("rotation vector θx at {a}"));
    }
    close(last, 7.0, 1e-9, "rotation vector θx = 7");
}

// ---------------------------------------------------------------------------------------
// 9. No input makes the law non-finite (issue 12, item 5)
// ---------------------------------------------------------------------------------------

/// A finite value of any magnitude, zero included.
fn any_size() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        (-1.0f64..1.0, -300i32..=308).prop_map(|(m, e)| m * 10f64.powi(e)),
        -10.0f64..10.0,
    ]
}

fn any_curve() -> impl Strategy<Value = Option<Curve>> {
    proptest::option::of(
        proptest::collection::vec((any_size(), any_size()), 1..4).prop_filter_map(
            "valid curve",
            |mut pts| {
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                Curve::new(pts).ok()
            },
        ),
    )
}

fn any_law() -> impl Strategy<Value = DofLaw> {
    (
        (
            any_size(),
            any_curve(),
            any_size(),
            any_size(),
            any::<bool>(),
        ),
        (any_size(), any_curve()),
        (any_size(), any_size(), any_curve()),
    )
        .prop_map(
            |((k, kc, smin, smax, icomb), (c, cc), (kf, ff, fc))| DofLaw {
                // a negative spring or viscosity is refused (a curve's values may be negative)
                stiffness: k.abs(),
                stiffness_curve: kc,
                stop_min: -smin.abs(),
                stop_max: smax.abs(),
                coupled_stops: icomb,
                viscosity: c.abs(),
                // a viscosity curve whose end falls is refused: its values sorted rising
                // (none where a slope so overflows)
                viscosity_curve: cc.and_then(|c| {
                    let (x, mut y): (Vec<f64>, Vec<f64>) = c.points().unzip();
                    y.sort_by(f64::total_cmp);
                    Curve::new(x.into_iter().zip(y)).ok()
                }),
                friction_stiffness: kf.abs(),
                friction: ff.abs(),
                // a friction curve's values are caps, refused negative: their sizes
                friction_curve: fc
                    .and_then(|c| Curve::new(c.points().map(|(x, y)| (x, y.abs()))).ok()),
                // (a rotor changes no force of the law: the solve's `G`)
                armature: 0.0,
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    /// Any valid property, any finite blocked stiffness and masses, any finite q and rates
    /// (several evaluations, the lock switching on midway): every force, tangent, energy
    /// and stored friction force stays finite.
    #[test]
    fn evaluate_is_finite_for_any_valid_input(
        ty in 1i64..=9,
        kn in any_size(),
        scf in any_size(),
        laws in proptest::collection::vec(any_law(), 6),
        blocked in (any_size(), any_size(), any_size(), any_size()),
        qs in proptest::collection::vec(proptest::collection::vec(any_size(), 12), 1..5),
    ) {
        let mut prop = KjointProperty::new(JointType::from_number(ty).unwrap())
            .with_kn(kn.abs())
            .with_scale_factor(scf.abs());
        for (d, l) in Dof::ALL.into_iter().zip(laws) {
            // laws only on the free DOFs (a law on a blocked DOF is refused)
            if prop.joint_type.is_free(d) {
                prop = prop.with_dof(d, l);
            }
        }
        prop_assume!(prop.validate().is_ok());
        let p = params(blocked.0.abs(), blocked.1.abs(), blocked.2.abs(), blocked.3.abs());
        let mut st = LawState::default();
        let n = qs.len();
        for (k, v) in qs.into_iter().enumerate() {
            let q: [f64; 6] = std::array::from_fn(|i| v[i]);
            let rate: [f64; 6] = std::array::from_fn(|i| v[6 + i]);
            let o = evaluate(&prop, &p, &q, &rate, k >= n / 2, &mut st);
            for i in 0..6 {
                let pt = &o.parts[i];
                for x in [pt.elastic, pt.damping, pt.friction, pt.stop, pt.sensor, o.total[i]] {
                    prop_assert!(x.is_finite(), "part of DOF {i}: {x} ({o:?})");
                }
                prop_assert!(st.friction_force[i].is_finite());
            }
            prop_assert!(o.stiffness.iter().chain(o.damping.iter()).all(|x| x.is_finite()));
            let e = st.energy;
            for x in [e.elastic, e.damping, e.friction, e.stop, e.internal] {
                prop_assert!(x.is_finite(), "energy {x}");
            }
        }
    }
}
