//! Tests of [`super`] (`src/law/flex_joint.rs`).

use super::*;
use approx::assert_relative_eq;

/// `*SPRINGPRO 3 3 0 0 0.00872665 25000 0.0174533 35000`.
fn law3() -> Curve {
    Curve::new([(0.0, 0.0), (0.00872665, 25000.0), (0.0174533, 35000.0)]).unwrap()
}

/// `*FLEXPROADD 2 5.72958e8 1 4.0107e6 1.718873e6 1.74533e-3 0 3.008e6`.
fn proadd() -> FlexProAdd {
    FlexProAdd {
        torsion_stiffness: 5.72958e8,
        iflag: 1,
        kdyn_ini: 4.0107e6,
        kdyn_lim: 1.718873e6,
        angle_lim: 1.74533e-3,
        teta: 0.0,
        torsion_damping: 3.008e6,
    }
}

fn at(theta: Vector3<f64>) -> FlexJointInput {
    FlexJointInput {
        theta,
        ..Default::default()
    }
}

/// Drives the law along `path` of rotation vectors, returning the outputs and the
/// trapezoidal work `∫ M·dθ`.
fn drive(
    law: &FlexJointLaw,
    st: &mut FlexJointState,
    path: impl IntoIterator<Item = Vector3<f64>>,
) -> (Vec<FlexJointOutput>, f64) {
    let mut outs = Vec::new();
    let mut work = 0.0;
    let mut prev: Option<(Vector3<f64>, Vector3<f64>)> = None;
    for th in path {
        let dtheta = prev.map_or(Vector3::zeros(), |(p, _)| th - p);
        let o = law.evaluate(
            st,
            &FlexJointInput {
                theta: th,
                dtheta,
                rate: Vector3::zeros(),
            },
        );
        if let Some((p, m)) = prev {
            work += 0.5 * (m + o.moment).dot(&(th - p));
        }
        prev = Some((th, o.moment));
        outs.push(o);
    }
    (outs, work)
}

#[test]
fn slow_bending_sweep_reproduces_springpro_table() {
    let law = FlexJointLaw::new(Some(law3()), None, Some(proadd())).unwrap();
    let mut st = FlexJointState::default();
    let dir = Vector2::new(0.6, -0.8);
    let n = 2000;
    let amax = 0.0174533;
    let path = (0..=n).map(|i| {
        let a = amax * i as f64 / n as f64;
        Vector3::new(0.0, dir.x * a, dir.y * a)
    });
    let (outs, work) = drive(&law, &mut st, path);
    for (i, m) in [(1000, 25000.0), (2000, 35000.0), (500, 12500.0)] {
        let o = &outs[i];
        assert_relative_eq!(o.bending_moment, m, max_relative = 1e-5);
        assert_relative_eq!(o.bending_axis, dir, epsilon = 1e-12);
        // Moment along the bending vector, restoring sign.
        assert_relative_eq!(
            Vector2::new(o.moment.y, o.moment.z).normalize(),
            dir,
            epsilon = 1e-12
        );
        assert_eq!(o.phase, FlexPhase::QuasiStatic);
    }
    // Static phase is elastic: work = stored energy = area under the table.
    let area = 0.5 * 0.00872665 * 25000.0 + 0.5 * (25000.0 + 35000.0) * (0.0174533 - 0.00872665);
    assert_relative_eq!(work, area, max_relative = 1e-6);
    assert_relative_eq!(outs[n].elastic_energy, area, max_relative = 1e-6);
    // Tilt direction is perpendicular to the bending axis.
    assert_relative_eq!(outs[n].tilt_direction.dot(&dir), 0.0, epsilon = 1e-12);
}

#[test]
fn classical_mode_acts_on_total_angle() {
    let law = FlexJointLaw::new(Some(law3()), None, None).unwrap();
    assert_eq!(law.mode(), FlexMode::Classical);
    let a = 0.012;
    let mut st = FlexJointState::default();
    let torsion = law.evaluate(&mut st, &at(Vector3::new(a, 0.0, 0.0)));
    let bending = law.evaluate(&mut st, &at(Vector3::new(0.0, 0.0, a)));
    let mixed = law.evaluate(&mut st, &at(Vector3::new(a, a, 0.0) / 2f64.sqrt()));
    let expected = law3().value(a);
    assert_relative_eq!(torsion.moment.norm(), expected, max_relative = 1e-12);
    assert_relative_eq!(torsion.moment.x, expected, max_relative = 1e-12);
    assert_relative_eq!(bending.moment.z, expected, max_relative = 1e-12);
    assert_relative_eq!(mixed.moment.norm(), expected, max_relative = 1e-12);
    // Tangent: slope along θ, secant across.
    let k = mixed.stiffness;
    let n = Vector3::new(1.0, 1.0, 0.0) / 2f64.sqrt();
    assert_relative_eq!((k * n).dot(&n), law3().slope(a), max_relative = 1e-9);
    assert_relative_eq!(k[(2, 2)], expected / a, max_relative = 1e-9);
    // Finite-difference check of the tangent.
    let th = Vector3::new(0.008, -0.009, 0.005);
    let m0 = law.evaluate(&mut st, &at(th));
    for j in 0..3 {
        let mut d = Vector3::zeros();
        d[j] = 1e-8;
        let m1 = law.evaluate(&mut st, &at(th + d)).moment;
        let col = (m1 - m0.moment) / 1e-8;
        assert_relative_eq!(
            col,
            m0.stiffness.column(j).into_owned(),
            epsilon = 1e-5 * m0.stiffness.norm()
        );
    }
}

#[test]
fn decoupled_torsion_follows_its_own_law() {
    let tor = Curve::new([(0.0, 0.0), (0.01, 1000.0), (0.02, 1500.0)]).unwrap();
    let law = FlexJointLaw::new(Some(law3()), Some(tor.clone()), None).unwrap();
    assert_eq!(law.mode(), FlexMode::Decoupled);
    let mut st = FlexJointState::default();
    let o = law.evaluate(&mut st, &at(Vector3::new(0.015, 0.00872665, 0.0)));
    assert_relative_eq!(o.torsion_moment, 1250.0, max_relative = 1e-12);
    assert_relative_eq!(o.moment.y, 25000.0, max_relative = 1e-6);
    assert_relative_eq!(o.moment.z, 0.0);
    // Odd extension for negative torsion.
    let o = law.evaluate(&mut st, &at(Vector3::new(-0.015, 0.0, 0.0)));
    assert_relative_eq!(o.torsion_moment, -1250.0, max_relative = 1e-12);
    assert_relative_eq!(o.stiffness[(0, 0)], 50000.0, max_relative = 1e-9);
    assert_relative_eq!(o.bending_moment, 0.0);
    // IMAT set, IPROT set: Ktor ignored, damping CP added.
    let law = FlexJointLaw::new(Some(law3()), Some(tor), Some(proadd())).unwrap();
    let o = law.evaluate(
        &mut st,
        &FlexJointInput {
            theta: Vector3::new(0.01, 0.0, 0.0),
            dtheta: Vector3::new(1e-4, 0.0, 0.0),
            rate: Vector3::new(0.1, 0.0, 0.0),
        },
    );
    assert_relative_eq!(
        o.torsion_moment,
        1000.0 + 3.008e6 * 0.1,
        max_relative = 1e-12
    );
    assert_relative_eq!(o.damping[(0, 0)], 3.008e6);
    assert_relative_eq!(o.dissipated, 3.008e6 * 0.1 * 1e-4, max_relative = 1e-12);
    // IMAT set, IPROT unset: linear Ktor.
    let law = FlexJointLaw::new(Some(law3()), None, Some(proadd())).unwrap();
    let o = law.evaluate(&mut st, &at(Vector3::new(-1e-3, 0.0, 0.0)));
    assert_relative_eq!(o.torsion_moment, -5.72958e5, max_relative = 1e-12);
}

fn cyclic_loop(law: &FlexJointLaw, static_angle: Vector2<f64>, dir: Vector2<f64>) {
    let d = law.dynamic.unwrap();
    let a = 3.0 * d.angle_lim;
    let mut st = FlexJointState::default();
    // Quasi-static ramp to the static angle.
    let ramp = (0..=200).map(|i| {
        let b = static_angle * (i as f64 / 200.0);
        Vector3::new(0.0, b.x, b.y)
    });
    drive(law, &mut st, ramp);
    assert!(law.switch_to_dynamic(&mut st, 12.5));
    assert!(!law.switch_to_dynamic(&mut st, 13.0));
    assert_eq!(st.switch.unwrap().time, 12.5);
    // First quarter: 0 -> +a, then one full cycle +a -> -a -> +a.
    let n = 4000;
    let pos = |s: f64| {
        let b = static_angle + dir * (a * s);
        Vector3::new(0.0, b.x, b.y)
    };
    drive(
        law,
        &mut st,
        (0..=n / 4).map(|i| pos(i as f64 / (n / 4) as f64)),
    );
    let d0 = st.dissipated_hysteresis;
    let cycle = (0..=n).map(|i| pos((i as f64 / n as f64 * std::f64::consts::TAU).cos()));
    let (outs, work) = drive(law, &mut st, cycle);
    let expected = d.loop_area(a);
    assert_relative_eq!(
        expected,
        8.0 * d.angle_lim.powi(2) * (d.kdyn_ini - d.kdyn_lim),
        max_relative = 1e-12
    );
    let dissipated = st.dissipated_hysteresis - d0;
    assert_relative_eq!(dissipated, expected, max_relative = 0.02);
    // The loop closes: the work of the moment over the cycle is its area.
    assert_relative_eq!(work, expected, max_relative = 0.02);
    let first = outs.first().unwrap();
    let last = outs.last().unwrap();
    assert_relative_eq!(first.moment, last.moment, epsilon = 1e-6 * d.yield_moment());
    // Tip moment: static + My + Kdyn_lim (a − φy).
    let tip = d.yield_moment() + d.kdyn_lim * (a - d.angle_lim);
    let ms = st.switch.unwrap().moment;
    assert_relative_eq!(
        Vector2::new(last.moment.y, last.moment.z) - ms,
        dir * tip,
        max_relative = 1e-6
    );
    assert!(outs.iter().any(|o| o.yielding));
    assert!(outs.iter().all(|o| o.phase == FlexPhase::Dynamic));
}

#[test]
fn cyclic_bending_loop_area_with_static_law() {
    let law = FlexJointLaw::new(Some(law3()), None, Some(proadd())).unwrap();
    cyclic_loop(&law, Vector2::new(0.005, 0.002), Vector2::new(0.0, 1.0));
}

#[test]
fn cyclic_bending_loop_area_flexproadd_both_phases() {
    let law = FlexJointLaw::new(None, None, Some(proadd())).unwrap();
    let dir = Vector2::new(1.0, -1.0).normalize();
    cyclic_loop(&law, Vector2::new(-0.004, 0.0), dir);
}

#[test]
fn hysteretic_energy_balance_and_tangent() {
    // Work of the moment = stored + dissipated on an arbitrary 2-D path.
    let law = FlexJointLaw::new(None, None, Some(proadd())).unwrap();
    let mut st = FlexJointState::default();
    let path = (0..=20000).map(|i| {
        let t = i as f64 * 1e-3;
        Vector3::new(
            0.0,
            0.006 * (1.3 * t).sin(),
            0.004 * (0.7 * t).cos() - 0.004,
        )
    });
    let (outs, work) = drive(&law, &mut st, path);
    let last = outs.last().unwrap();
    assert_relative_eq!(
        work,
        last.elastic_energy + st.dissipated_hysteresis,
        max_relative = 1e-3
    );
    // Monotonic static ramp with IPRO = 0 follows the bilinear curve.
    let d = proadd();
    let mut st = FlexJointState::default();
    let path = (0..=300).map(|i| Vector3::new(0.0, 0.0, 4.0 * d.angle_lim * i as f64 / 300.0));
    let (outs, _) = drive(&law, &mut st, path);
    let o = outs.last().unwrap();
    assert_relative_eq!(
        o.moment.z,
        d.yield_moment() + d.kdyn_lim * 3.0 * d.angle_lim,
        max_relative = 1e-9
    );
    assert_relative_eq!(o.stiffness[(2, 2)], d.kdyn_lim, max_relative = 1e-9);
    assert!(o.stiffness[(1, 1)] < d.kdyn_ini && o.stiffness[(1, 1)] > 0.0);
    // Finite-difference check of the consistent tangent while yielding.
    let th = Vector3::new(0.0, 1e-3, 4.0 * d.angle_lim + 1e-5);
    for j in 1..3 {
        let mut s0 = st;
        let mut s1 = st;
        let o0 = law.evaluate(&mut s0, &at(th));
        let mut dth = Vector3::zeros();
        dth[j] = 1e-9;
        let o1 = law.evaluate(&mut s1, &at(th + dth));
        let col = (o1.moment - o0.moment) / 1e-9;
        assert_relative_eq!(
            col,
            o0.stiffness.column(j).into_owned(),
            epsilon = 1e-3 * d.kdyn_ini
        );
    }
}

#[test]
fn validation() {
    assert!(FlexJointLaw::new(None, None, None).is_err());
    let mut p = proadd();
    p.iflag = 2;
    let e = FlexJointLaw::new(None, None, Some(p)).unwrap_err();
    assert!(e.to_string().contains("IFLAG"), "{e}");
    let mut p = proadd();
    p.kdyn_lim = 2.0 * p.kdyn_ini;
    assert!(p.validate().is_err());
    let mut p = proadd();
    p.angle_lim = 0.0;
    assert!(p.validate().is_err());
    let mut p = proadd();
    p.torsion_damping = f64::NAN;
    assert!(p.validate().is_err());
    let shifted = Curve::new([(0.0, 5.0), (1.0, 10.0)]).unwrap();
    assert!(FlexJointLaw::new(Some(shifted), None, None).is_err());
    // Kdyn_lim = Kdyn_ini: purely elastic, no dissipation.
    let mut p = proadd();
    p.kdyn_lim = p.kdyn_ini;
    let law = FlexJointLaw::new(None, None, Some(p)).unwrap();
    let mut st = FlexJointState::default();
    let o = law.evaluate(&mut st, &at(Vector3::new(0.0, 0.01, 0.0)));
    assert!(!o.yielding);
    assert_relative_eq!(o.moment.y, p.kdyn_ini * 0.01);
}
