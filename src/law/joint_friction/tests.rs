use super::*;
use approx::assert_relative_eq;
use JointType::{Cylindrical, Revolute, Translational};

/// Reactions `(f_x, f_y, f_z, m_x, m_y, m_z)`: radial 500 N, bending 5 N·m, torsion 7 N·m,
/// axial 50 N.
const R: [f64; 6] = [50.0, 300.0, 400.0, 7.0, 3.0, 4.0];

fn revolute() -> JointFriction {
    JointFriction {
        mu: 0.1,
        pin_radius: 0.02,
        length: 0.1,
        thrust_radius: 0.03,
        preload: 10.0,
        stick_rotational_stiffness: 1.0e4,
        ..Default::default()
    }
}

fn slider(mu: f64, pin_radius: f64) -> JointFriction {
    JointFriction {
        mu,
        pin_radius,
        length: 0.1,
        stick_stiffness: 1.0e6,
        ..Default::default()
    }
}

/// Drives `(dx, dθ)` in small equal steps until the spring slips; returns (f, m) then.
fn threshold(
    law: &JointFriction,
    joint: JointType,
    reactions: [f64; 6],
    step: (f64, f64),
) -> (f64, f64) {
    let mut st = JointFrictionState::default();
    let input = JointFrictionInput {
        reactions,
        dx: step.0,
        dtheta: step.1,
    };
    for _ in 0..1_000_000 {
        let o = law.evaluate(joint, &mut st, &input);
        if o.sliding {
            return (o.force, o.moment);
        }
    }
    panic!("never slipped");
}

#[test]
fn validation_names_the_field() {
    let err = |l: JointFriction, j: JointType| l.validate_for(j).unwrap_err().to_string();
    assert!(revolute().validate_for(Revolute).is_ok());
    assert!(slider(0.2, 0.0).validate_for(Translational).is_ok());
    assert!(slider(0.2, 0.01).validate_for(Cylindrical).is_ok());
    assert!(err(
        JointFriction {
            mu: -0.1,
            ..revolute()
        },
        Revolute
    )
    .contains("mu"));
    assert!(err(
        JointFriction {
            mu: f64::NAN,
            ..revolute()
        },
        Revolute
    )
    .contains("mu"));
    let inf = JointFriction {
        preload: f64::INFINITY,
        ..revolute()
    };
    assert!(err(inf, Revolute).contains("preload"));
    let neg = JointFriction {
        length: -1.0,
        ..revolute()
    };
    assert!(err(neg, Revolute).contains("length"));
    // within a scene's range, and a length that keeps M/L finite
    for bad in [
        JointFriction {
            length: 1e-308,
            ..revolute()
        },
        JointFriction {
            length: 1e13,
            ..revolute()
        },
    ] {
        assert!(err(bad, Revolute).contains("invalid length"), "{bad:?}");
    }
    let huge_mu = JointFriction {
        mu: 1e300,
        ..revolute()
    };
    assert!(err(huge_mu, Revolute).contains("invalid mu"));
    let huge_pin = JointFriction {
        pin_radius: 1e308,
        ..revolute()
    };
    assert!(err(huge_pin, Revolute).contains("invalid pin_radius"));
    let no_pin = JointFriction {
        pin_radius: 0.0,
        ..revolute()
    };
    assert!(err(no_pin, Revolute).contains("pin_radius"));
    // Parameters the type does not use are refused, not ignored.
    assert!(err(slider(0.2, 0.01), Translational).contains("pin_radius"));
    let thrust = JointFriction {
        thrust_radius: 0.1,
        ..slider(0.2, 0.01)
    };
    assert!(err(thrust, Cylindrical).contains("thrust_radius"));
    let kf = JointFriction {
        stick_stiffness: 1.0,
        ..revolute()
    };
    assert!(err(kf, Revolute).contains("stick_stiffness"));
    let kr = JointFriction {
        stick_rotational_stiffness: 1.0,
        ..slider(0.2, 0.0)
    };
    assert!(err(kr, Translational).contains("stick_rotational_stiffness"));
}

#[test]
fn normal_force_and_cap_by_hand() {
    let l = revolute();
    // 500 + 5/0.1 + 10 = 560 N; cap = 0.1·(0.02·560 + 0.03·50) = 1.27 N·m.
    assert_relative_eq!(l.normal_force(Revolute, &R), 560.0, epsilon = 1e-9);
    assert_relative_eq!(l.cap(Revolute, 560.0, -50.0), 1.27, epsilon = 1e-12);
    assert_relative_eq!(l.normal_force(Cylindrical, &R), 560.0, epsilon = 1e-9);
    // Translational: torsion joins the bending, √(3² + 4² + 7²)/0.1 = 86.0233 N.
    let t = 500.0 + 74f64.sqrt() / 0.1 + 10.0;
    assert_relative_eq!(l.normal_force(Translational, &R), t, epsilon = 1e-9);
    assert_relative_eq!(l.cap(Translational, t, 50.0), 0.1 * t, epsilon = 1e-12);
    // L = 0: moments ignored; a preload larger than the load: absolute value.
    let l0 = JointFriction {
        length: 0.0,
        preload: -800.0,
        ..l
    };
    assert_relative_eq!(l0.normal_force(Revolute, &R), 300.0, epsilon = 1e-9);
}

#[test]
fn revolute_slips_at_mu_r_pin_normal_force_plus_thrust() {
    let l = revolute();
    let (f, m) = threshold(&l, Revolute, R, (1.0, -1.0e-6));
    assert_eq!(f, 0.0); // the axial translation is blocked: no friction force
    assert_relative_eq!(m, -1.27, max_relative = 0.01);
}

#[test]
fn translational_threshold_for_three_loads_and_a_moment() {
    let l = slider(0.3, 0.0);
    for (load, bend) in [(100.0, 0.0), (1000.0, 0.0), (2500.0, 0.0), (1000.0, 20.0)] {
        let r = [0.0, 0.0, load, 0.0, bend, 0.0];
        let f_n = load + bend / 0.1;
        let (f, m) = threshold(&l, Translational, r, (1.0e-7, 1.0));
        assert_eq!(m, 0.0);
        assert_relative_eq!(f, 0.3 * f_n, max_relative = 0.01);
    }
}

#[test]
fn cylindrical_slips_on_one_resultant() {
    let l = slider(0.25, 0.02);
    let r = [0.0, 800.0, 0.0, 0.0, 0.0, 0.0]; // F_N = 800 N, cap 200 N
                                              // Sliding alone: f = 200 N.
    let (f, _) = threshold(&l, Cylindrical, r, (1.0e-7, 0.0));
    assert_relative_eq!(f, 200.0, max_relative = 0.01);
    // Turning alone: m = R_pin·200 = 4 N·m.
    let (_, m) = threshold(&l, Cylindrical, r, (0.0, 5.0e-6));
    assert_relative_eq!(m, 4.0, max_relative = 0.01);
    // Equal surface motion both ways (Δx = R·Δθ): |(f, m/R)| = 200, each 200/√2.
    let (f, m) = threshold(&l, Cylindrical, r, (1.0e-7, 5.0e-6));
    assert_relative_eq!(f, 200.0 / 2f64.sqrt(), max_relative = 0.01);
    assert_relative_eq!(m / 0.02, 200.0 / 2f64.sqrt(), max_relative = 0.01);
}

#[test]
fn cylindrical_tangent_in_dof_coordinates() {
    let l = slider(0.25, 0.02);
    let mut st = JointFrictionState::default();
    let input = |dx, dtheta| JointFrictionInput {
        reactions: [0.0, 800.0, 0.0, 0.0, 0.0, 0.0],
        dx,
        dtheta,
    };
    let o = l.evaluate(Cylindrical, &mut st, &input(1.0e-5, 0.0));
    assert!(!o.sliding);
    // Stick: diag(Kf, Kf·R²) = diag(1e6, 400).
    assert_eq!(o.tangent, Matrix2::new(1.0e6, 0.0, 0.0, 400.0));
    assert_eq!(l.dof_stiffness(Cylindrical), [1.0e6, 400.0]);
    // Slide along x: trial 10 + 1e6·3e-4 = 310 N > 200 N; zero along x, Kf·R²·c/|s*| about x.
    let o = l.evaluate(Cylindrical, &mut st, &input(3.0e-4, 0.0));
    assert!(o.sliding);
    assert_relative_eq!(o.force, 200.0, epsilon = 1e-9);
    assert_relative_eq!(o.tangent[(0, 0)], 0.0, epsilon = 1e-9);
    assert_relative_eq!(o.tangent[(1, 1)], 400.0 * 200.0 / 310.0, epsilon = 1e-9);
    assert_relative_eq!(o.slip, 110.0 / 1.0e6, epsilon = 1e-15);
    assert_relative_eq!(o.dissipated, 200.0 * 110.0 / 1.0e6, epsilon = 1e-12);
}

#[test]
fn load_unload_reverse_and_falling_cap_by_hand() {
    // Kf = 1000 N/m, μ = 0.5, F_N = 100 N: cap 50 N.
    let l = JointFriction {
        mu: 0.5,
        stick_stiffness: 1000.0,
        ..Default::default()
    };
    let mut st = JointFrictionState::default();
    let mut step = |load: f64, dx: f64| {
        let reactions = [0.0, load, 0.0, 0.0, 0.0, 0.0];
        l.evaluate(
            Translational,
            &mut st,
            &JointFrictionInput {
                reactions,
                dx,
                dtheta: 0.0,
            },
        )
    };
    let o = step(100.0, 0.03); // 30 N, stick
    assert!(!o.sliding);
    assert_relative_eq!(o.force, 30.0);
    assert_relative_eq!(o.stored, 0.45, epsilon = 1e-12);
    let o = step(100.0, 0.04); // trial 70 N: 50 N, slip 0.02 m, 1 J
    assert!(o.sliding);
    assert_relative_eq!(o.force, 50.0);
    assert_relative_eq!(o.dissipated, 1.0, epsilon = 1e-12);
    let o = step(100.0, -0.13); // trial −80 N: −50 N, slip 0.03 m, 1.5 J
    assert_relative_eq!(o.force, -50.0, epsilon = 1e-12);
    assert_relative_eq!(o.dissipated, 1.5, epsilon = 1e-12);
    // The load falls to 40 N (cap 20 N) at rest: the spring releases (50² − 20²)/2000 J.
    let o = step(40.0, 0.0);
    assert!(o.sliding);
    assert_relative_eq!(o.force, -20.0, epsilon = 1e-12);
    assert_relative_eq!(o.dissipated, 1.05, epsilon = 1e-12);
    assert_relative_eq!(st.dissipated, 3.55, epsilon = 1e-12);
}
