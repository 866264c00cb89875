//! The automatic blocked stiffness (`Kn = 0`, issue 13 item 1): the implicit rule of
//! `law::stiffness` for the builder, scene files and URDF robots, from the load side each
//! joint holds up; the Radioss rule of spec §5 for properties read from a deck.

mod common;
use approx::assert_relative_eq;
use rapier_kjoint::law::stiffness::{self, JointLoad};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::{AutomaticStiffness, JointType, KjointProperty, KjointSet};

const H: f64 = 1.0 / 240.0;

#[test]
fn implicit_rule_numbers() {
    // the check of the doc: 1 kg, I_L = 0.25 kg·m², anchor 0.5 m from the origin, 240 Hz
    let load = JointLoad {
        mass: 1.0,
        inertia: 0.25,
        anchor_distance: 0.5,
    };
    assert_relative_eq!(load.radius_of_gyration(), 0.5);
    assert_relative_eq!(load.pose_scale(), 1.0);
    let kappa = stiffness::implicit_kappa(H, 1.0);
    let k = stiffness::implicit_blocked_stiffness(&KjointProperty::new(JointType::Fixed), &load, H);
    // f32 poses: the noise bound 0.01·9.81·h²/(ε·r) = 14.29 < 16 governs at r = 1 m
    #[cfg(not(feature = "f64"))]
    {
        assert_relative_eq!(
            kappa,
            0.01 * 9.81 * H * H / (f32::EPSILON as f64),
            epsilon = 1e-12
        );
        assert_relative_eq!(kappa, 14.2868, max_relative = 1e-5);
        assert_relative_eq!(k.translational, 8.2292e5, max_relative = 1e-4);
    }
    // f64 poses: the bound is 7.7e9 at r = 1 m, κ = 16 (K = 16·57600 = 9.216e5 N/m)
    #[cfg(feature = "f64")]
    {
        assert_eq!(kappa, stiffness::IMPLICIT_KAPPA);
        assert_relative_eq!(
            stiffness::implicit_kappa(H, 1e9),
            0.01 * 9.81 * H * H / (f64::EPSILON * 1e9),
            epsilon = 1e-12
        );
        assert_relative_eq!(k.translational, 9.216e5, max_relative = 1e-12);
    }
    assert_relative_eq!(k.rotational, 0.25 * k.translational, max_relative = 1e-12);
    // near the origin the target κ = 16 (ω·h = 4) governs; ScF scales both
    assert_eq!(stiffness::implicit_kappa(H, 0.1), stiffness::IMPLICIT_KAPPA);
    let scaled = KjointProperty::new(JointType::Fixed).with_scale_factor(2.0);
    let k2 = stiffness::implicit_blocked_stiffness(&scaled, &load, H);
    assert_relative_eq!(
        k2.translational,
        2.0 * k.translational,
        max_relative = 1e-12
    );
    // the weight of the load deflects the joint by a·h²/κ: 12 µm here
    assert_relative_eq!(
        9.81 / k.translational,
        9.81 * H * H / kappa,
        max_relative = 1e-12
    );
    assert!(9.81 / k.translational < 1.2e-5);
}

/// Load sides: a chain hanging from the world carries everything below each joint; a free
/// pair, the lighter side; a loop, its island.
#[test]
fn each_joint_holds_up_its_load_side() {
    let (mut w, ground) = common::world(Vector::ZERO);
    let inertia = Vector::splat(0.01);
    // ground – a (2 kg) – b (1 kg) – c (0.5 kg), all at the origin: the mean inertia about
    // the anchor is the bodies' own, 0.01 each
    let a = common::point_body(&mut w, 2.0, inertia, Vector::ZERO);
    let b = common::point_body(&mut w, 1.0, inertia, Vector::ZERO);
    let c = common::point_body(&mut w, 0.5, inertia, Vector::ZERO);
    // a free pair: d (3 kg) – e (1 kg)
    let d = common::point_body(&mut w, 3.0, inertia, Vector::new(5.0, 0.0, 0.0));
    let e = common::point_body(&mut w, 1.0, inertia, Vector::new(5.0, 0.0, 0.0));
    // a loop: f, g, h (1 kg each), f–g–h–f, with f hanging from the world
    let f = common::point_body(&mut w, 1.0, inertia, Vector::new(0.0, 5.0, 0.0));
    let g = common::point_body(&mut w, 1.0, inertia, Vector::new(0.0, 5.0, 0.0));
    let h = common::point_body(&mut w, 1.0, inertia, Vector::new(0.0, 5.0, 0.0));
    let mut set = KjointSet::new();
    let p = || KjointProperty::new(JointType::Spherical);
    let mut add = |b1, b2| common::add(&mut set, &w, p(), b1, b2, |b| b);
    let j = [
        add(ground, a),
        add(a, b),
        add(b, c),
        add(d, e),
        add(ground, f),
        add(f, g),
        add(g, h),
        add(h, f),
    ];
    w.step();
    let loads = set.joint_loads(&w.bodies);
    let m = |k: usize| loads[&j[k]].unwrap().mass;
    assert_relative_eq!(m(0), 3.5, max_relative = 1e-6);
    assert_relative_eq!(m(1), 1.5, max_relative = 1e-6);
    assert_relative_eq!(m(2), 0.5, max_relative = 1e-6);
    assert_relative_eq!(m(3), 1.0, max_relative = 1e-6);
    // the joint to the world holds the whole loop up; the loop's joints, the loop
    for k in 4..8 {
        assert_relative_eq!(m(k), 3.0, max_relative = 1e-6);
    }
    let l = loads[&j[0]].unwrap();
    assert_relative_eq!(l.inertia, 0.03, max_relative = 1e-5);
    assert_relative_eq!(l.anchor_distance, 0.0);
    // an offset load: c's 0.5 kg 1 m from b's anchor adds ⅔·m·d² to the mean inertia
    let (mut w, ground) = common::world(Vector::ZERO);
    let a = common::point_body(&mut w, 2.0, inertia, Vector::new(0.0, 0.0, 0.0));
    let b = common::point_body(&mut w, 0.5, inertia, Vector::new(1.0, 0.0, 0.0));
    let mut set = KjointSet::new();
    let j0 = common::add(&mut set, &w, p(), ground, a, |b| b);
    let j1 = common::add(&mut set, &w, p(), a, b, |b| b);
    w.step();
    let loads = set.joint_loads(&w.bodies);
    assert_relative_eq!(
        loads[&j1].unwrap().inertia,
        0.01 + 2.0 / 3.0 * 0.5,
        max_relative = 1e-5
    );
    assert_relative_eq!(
        loads[&j0].unwrap().inertia,
        0.02 + 2.0 / 3.0 * 0.5,
        max_relative = 1e-5
    );
}

/// A 1 m, 1 kg rod hanging at rest from a hinge at its top, default property: the joint
/// carries its weight with a sag of a·h²/κ_eff (micrometres), where the Radioss rule of the
/// same property sags by millimetres.
/// A payload added after the start (a gripper's load, a body whose mass the user sets):
/// the automatic stiffness follows the masses it is resolved from. Two 1 kg balls hang
/// one below the other on spherical joints, 0.5 m apart; after 1 s the lower one takes a
/// 50 kg payload (`set_additional_mass_properties`). The lower joint now holds up 51 kg instead of
/// 1, the upper one 52 instead of 2: their `K = κ_eff·m_L/h²` grow 51- and 26-fold, and
/// each still deflects by the rule's `a·h²/κ_eff` (≈ 11 µm at 240 Hz) under the weight
/// below it. Before, the stiffness kept its first value and the lower joint sagged 51
/// times as far (0.5 mm), the upper one 26 times.
#[test]
fn a_payload_added_after_the_start_is_held_as_stiffly() {
    let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
    let upper = common::point_body(
        &mut w,
        1.0,
        Vector::splat(0.01),
        Vector::new(0.0, -0.5, 0.0),
    );
    let lower = common::point_body(
        &mut w,
        1.0,
        Vector::splat(0.01),
        Vector::new(0.0, -1.0, 0.0),
    );
    let mut set = common::joints(4);
    let ball = || KjointProperty::new(JointType::Spherical);
    let top = common::add(&mut set, &w, ball(), ground, upper, |b| {
        b.local_anchor2(Vector::new(0.0, 0.5, 0.0))
    });
    let mid = common::add(&mut set, &w, ball(), upper, lower, |b| {
        b.local_anchor2(Vector::new(0.0, 0.5, 0.0))
    });
    for _ in 0..60 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
    }
    let kn = |set: &KjointSet, j| {
        set.get(j)
            .unwrap()
            .blocked_stiffness()
            .unwrap()
            .translational
    };
    let before = [kn(&set, top), kn(&set, mid)];
    let payload = MassProperties::new(Vector::ZERO, 51.0, Vector::splat(0.51));
    w.bodies[lower].set_additional_mass_properties(payload, true);
    let mut worst = [0.0f64; 2];
    for _ in 0..120 {
        set.step(&mut w, 1.0 / 60.0).unwrap();
        for (k, j) in [top, mid].into_iter().enumerate() {
            worst[k] = worst[k].max(common::world_gap(set.get(j).unwrap()));
        }
    }
    assert_relative_eq!(w.bodies[lower].mass() as f64, 51.0, max_relative = 1e-6);
    let after = [kn(&set, top), kn(&set, mid)];
    println!("K before {before:?} N/m, after {after:?} N/m, worst gaps after {worst:?} m");
    // (the mean inertia about each anchor does not enter the translational stiffness; the
    // lower joint's κ_eff is the f32 noise bound's, which follows its load's distance from
    // the origin: that moved by the sag)
    assert_relative_eq!(after[0] / before[0], 26.0, max_relative = 1e-6);
    assert_relative_eq!(after[1] / before[1], 51.0, max_relative = 1e-4);
    for (k, j) in [top, mid].into_iter().enumerate() {
        let kappa = after[k] / (if k == 0 { 52.0 } else { 51.0 }) * H * H;
        let sag = 9.81 * H * H / kappa;
        let gap = common::world_gap(set.get(j).unwrap());
        assert!(
            gap < 1.05 * sag,
            "joint {k}: gap at rest {gap} m, a·h²/κ = {sag} m"
        );
        // (the payload's weight comes on at once: the joint overshoots its rest once)
        assert!(
            worst[k] < 2.5 * sag,
            "joint {k}: worst gap {} m, a·h²/κ = {sag} m",
            worst[k]
        );
    }
}

#[test]
fn a_rod_hangs_within_its_sag_bound_and_radioss_properties_keep_spec_5() {
    let sag = |rule: AutomaticStiffness| {
        let prop = KjointProperty::new(JointType::Revolute).with_automatic(rule);
        let (mut w, mut set, j) = common::hanging_rod(prop);
        for _ in 0..60 {
            set.step(&mut w, 1.0 / 60.0).unwrap();
        }
        let jt = set.get(j).unwrap();
        let s = jt.state().unwrap();
        let gap = (0..3).map(|i| s.q[i].powi(2)).sum::<f64>().sqrt();
        (gap, jt.blocked_stiffness().unwrap())
    };
    let (gap, k) = sag(AutomaticStiffness::Implicit);
    // the rod alone hangs on the joint (m_L = 1 kg), so K = κ_eff·m_L/h²
    let kappa = k.translational * H * H;
    assert!(kappa > 10.0 && kappa <= 16.0, "κ_eff = {kappa}");
    let bound = 9.81 * H * H / kappa;
    println!(
        "implicit: K = {:.4e} N/m, gap {gap:.3e} m (a·h²/κ = {bound:.3e} m)",
        k.translational
    );
    assert!(gap < 1.5 * bound, "gap {gap} m");
    let (gap_r, k_r) = sag(AutomaticStiffness::Radioss);
    println!(
        "radioss: K = {:.4e} N/m, gap {gap_r:.3e} m",
        k_r.translational
    );
    // spec §5 for a body with the anchor 0.5 m from its centre: min(2m, 0.8·I/r²)/(α·h²)
    // (the mean principal inertia of the 0.04 × 1 × 0.04 m box, the anchor 0.5 m from it)
    let i_mean = (2.0 * (1.0 + 0.0016) + 0.0032) / 36.0;
    let adt2 = stiffness::ALPHA * H * H;
    let kx = (2.0 / adt2).min(0.8 * i_mean / (adt2 * 0.25));
    assert_relative_eq!(k_r.translational, kx, max_relative = 1e-4);
    assert!(gap_r > 100.0 * gap, "radioss {gap_r} m vs implicit {gap} m");
}

#[test]
fn deck_properties_use_the_radioss_rule_and_scenes_may_ask_for_it() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/decks/revolute_stop.rad"),
    )
    .unwrap();
    let deck =
        rapier_kjoint::io::radioss::RadiossDeck::from_str(&text, "revolute_stop.rad").unwrap();
    let p = deck.property_si(2).expect("prop 2");
    assert_eq!(p.kn, 0.0);
    assert_eq!(p.automatic, AutomaticStiffness::Radioss);
    // the builder's default
    assert_eq!(
        KjointProperty::new(JointType::Revolute).automatic,
        AutomaticStiffness::Implicit
    );
    // scenes: `automatic` on an inline property; refused on a deck reference
    let dir = common::cli::temp_dir("auto");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/decks/revolute_stop.rad"),
        dir.join("deck.rad"),
    )
    .unwrap();
    let scene = |property: &str| {
        format!(
            "duration = 0.1\n[[bodies]]\nname = \"b\"\nshape = {{ type = \"ball\", radius = 0.1 }}\n\
             mass = 1.0\n[[joints]]\nname = \"j\"\nbody1 = \"world\"\nbody2 = \"b\"\n\
             property = {property}\n"
        )
    };
    let build = |text: String| {
        let path = dir.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        let (s, src) = rapier_kjoint::scene::load(&path).map_err(|e| e.to_string())?;
        rapier_kjoint::scene::build(&s, &src).map_err(|e| e.to_string())
    };
    let refused = |text: String| match build(text) {
        Ok(_) => panic!("accepted"),
        Err(e) => e,
    };
    let built = build(scene("{ type = \"spherical\", automatic = \"radioss\" }")).unwrap();
    let (_, j) = built.joints.iter().next().unwrap();
    assert_eq!(j.property().automatic, AutomaticStiffness::Radioss);
    let built = build(scene("{ type = \"spherical\" }")).unwrap();
    let (_, j) = built.joints.iter().next().unwrap();
    assert_eq!(j.property().automatic, AutomaticStiffness::Implicit);
    let built = build(scene("{ deck = \"deck.rad\", id = 2 }")).unwrap();
    let (_, j) = built.joints.iter().next().unwrap();
    assert_eq!(j.property().automatic, AutomaticStiffness::Radioss);
    let err = refused(scene(
        "{ deck = \"deck.rad\", id = 2, automatic = \"implicit\" }",
    ));
    assert!(err.contains("no inline property fields"), "{err}");
    let err = refused(scene("{ type = \"spherical\", automatic = \"soft\" }"));
    assert!(err.contains("automatic"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 10-link chain (0.1 kg balls 0.1 m apart, spherical joints, `Kn = 0`) hanging at rest
/// under the ground, stepped with 4 substeps: at 60 Hz frames, or after a first frame of
/// 0.1 s (a game's loading hitch), or with the frames shortened to 1/240 s after 1 s. The
/// automatic stiffness follows the substep: once the frames are 1/60 s again, each joint's
/// stiffness and sag are those of the run stepped at 60 Hz throughout, whatever frame came
/// first (the first frame's stiffness, 36 times softer, stayed for the whole run: the
/// chain hung 35 times as far apart; an engine integrator's trial, 2026-12-05).
#[test]
fn the_automatic_stiffness_follows_a_change_of_frame_length() {
    let run = |frames: &[(usize, f64)]| {
        let (mut w, ground) = common::world(Vector::new(0.0, -9.81, 0.0));
        let mut set = common::joints(4);
        let mut handles = Vec::new();
        let mut above = ground;
        for i in 1..=10 {
            let ball = common::point_body(
                &mut w,
                0.1,
                Vector::splat(1e-4),
                Vector::new(0.0, -0.1 * i as Real, 0.0),
            );
            let prop = KjointProperty::new(JointType::Spherical);
            handles.push(common::add(&mut set, &w, prop, above, ball, |b| {
                b.local_anchor2(Vector::new(0.0, 0.1, 0.0))
            }));
            above = ball;
        }
        for &(n, dt) in frames {
            for _ in 0..n {
                set.step(&mut w, dt).unwrap();
            }
        }
        let kn: Vec<f64> = handles
            .iter()
            .map(|h| {
                set.get(*h)
                    .unwrap()
                    .blocked_stiffness()
                    .unwrap()
                    .translational
            })
            .collect();
        let gap = common::world_gap(set.get(handles[0]).unwrap());
        (kn, gap)
    };
    let (kn_60, gap_60) = run(&[(120, 1.0 / 60.0)]);
    let (kn_hitch, gap_hitch) = run(&[(1, 0.1), (120, 1.0 / 60.0)]);
    let (kn_240, gap_240) = run(&[(60, 1.0 / 60.0), (240, 1.0 / 240.0)]);
    println!(
        "top joint: at 60 Hz K {:.4e} N/m, gap {gap_60:.3e} m; after a 0.1 s frame K {:.4e}, \
         gap {gap_hitch:.3e} m; at 240 Hz after 60 Hz K {:.4e}, gap {gap_240:.3e} m",
        kn_60[0], kn_hitch[0], kn_240[0]
    );
    // the top joint carries the whole chain (1 kg): it sags by a·h²/κ_eff at the substep
    let h = 1.0 / 240.0;
    let kappa = kn_60[0] / 1.0 * h * h;
    assert!(kappa > 1.0 && kappa <= 16.0 * (1.0 + 1e-6), "κ_eff {kappa}");
    assert_relative_eq!(gap_60, 9.81 * h * h / kappa, max_relative = 0.05);
    // (the lowest joints' κ_eff is the f32 noise bound's, which follows the load's distance
    // from the origin at the resolution: the chain had sagged further then, 0.5 %)
    for (a, b) in kn_hitch.iter().zip(&kn_60) {
        assert_relative_eq!(*a, *b, max_relative = 0.01);
    }
    assert_relative_eq!(gap_hitch, gap_60, max_relative = 0.05);
    // at frames of 1/240 s, those of a run at 240 Hz throughout: 1.76 times stiffer (the
    // f32 noise bound, which does not grow as 1/h², holds its κ_eff at 1.76 there)
    let (kn_ref, gap_ref) = run(&[(60, 1.0 / 240.0)]);
    for (a, b) in kn_240.iter().zip(&kn_ref) {
        assert_relative_eq!(*a, *b, max_relative = 0.01);
    }
    assert_relative_eq!(gap_240, gap_ref, max_relative = 0.05);
    assert!(kn_240[0] > 1.5 * kn_60[0], "{} vs {}", kn_240[0], kn_60[0]);
}
