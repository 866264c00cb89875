//! Radioss deck reader: the two manual examples, unit conversion with numbers, one test per
//! malformed input (line and field of the error), and no-panic property tests.

use std::path::{Path, PathBuf};

mod common;

use approx::assert_relative_eq;
use proptest::prelude::*;
use rapier_kjoint::io::diagnostic::BaseQuantity;
use rapier_kjoint::io::radioss::{DeckErrorKind, RadiossDeck};
use rapier_kjoint::io::units::{property_to_si, UnitSystem};
use rapier_kjoint::{Dof, JointType};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/decks")
        .join(name)
}

/// Integer field, 10 columns.
fn i(v: impl ToString) -> String {
    format!("{:>10}", v.to_string())
}
/// Real field, 20 columns.
fn r(v: impl ToString) -> String {
    format!("{:>20}", v.to_string())
}

fn deck(lines: &[String]) -> String {
    lines.join("\n") + "\n"
}

/// A `/SKEW/FIX/id` block at the origin whose Y' and Z' are `y` and `z`: its lines, one
/// string (the title line and three cards of three fields).
fn skew_cards(id: u32, title: &str, y: [f64; 3], z: [f64; 3]) -> String {
    let axes = |v: [f64; 3]| v.map(r).concat();
    [
        format!("/SKEW/FIX/{id}"),
        title.to_string(),
        axes([0.0; 3]),
        axes(y),
        axes(z),
    ]
    .join("\n")
}

/// A KJOINT2 block of type `ty` with the given first-card extras and DOF cards.
fn prop(id: &str, first: String, dof_cards: &[String]) -> Vec<String> {
    let mut v = vec![format!("/PROP/TYPE45/{id}"), "title".into(), first];
    v.extend_from_slice(dof_cards);
    v
}

fn first_card(ty: i64, kn: &str, scf: &str, cr: &str, sens: u32) -> String {
    format!("{}{}{}{}{}", i(ty), r(kn), r(scf), r(cr), i(sens))
}

fn k_card(k: &str, fct: u32, sm: &str, sp: &str, icomb: i64) -> String {
    format!("{}{}{}{}{}", r(k), i(fct), r(sm), r(sp), i(icomb))
}

fn c_card(c: &str, fct: u32) -> String {
    format!("{}{}", r(c), i(fct))
}

fn f_card(kf: &str, ff: &str, fct: u32) -> String {
    format!("{}{}{}", r(kf), r(ff), i(fct))
}

/// A revolute joint (one free rotation, rx) with the given rx cards.
fn revolute(k: String, c: String, f: String) -> String {
    deck(&prop("1", first_card(2, "0", "0", "0", 0), &[k, c, f]))
}

fn ok_rx() -> (String, String, String) {
    (
        k_card("0", 0, "0", ".52", 0),
        c_card("0", 0),
        f_card("0", "100", 0),
    )
}

/// Parses `text` and returns the error's (line, field, kind).
fn error_of(text: &str) -> (usize, String, DeckErrorKind) {
    match RadiossDeck::from_str(text, "test.rad") {
        Ok(d) => panic!("expected an error, got {d:#?}"),
        Err(e) => {
            assert_eq!(e.file, "test.rad");
            // The message names file, line and field.
            let msg = e.to_string();
            assert!(
                msg.starts_with(&format!("test.rad:{}: field `{}`", e.line, e.field)),
                "{msg}"
            );
            (e.line, e.field, *e.kind)
        }
    }
}

// ---------------------------------------------------------------------------------------
// The two examples of the manual page
// ---------------------------------------------------------------------------------------

#[test]
fn example_revolute_with_stop() {
    let deck = RadiossDeck::from_file(asset("revolute_stop.rad")).unwrap();
    assert!(deck.file.ends_with("revolute_stop.rad"));
    assert!(deck.notices.is_empty(), "{:?}", deck.notices);

    let unit = &deck.units[&2];
    assert_eq!(unit.title, "unit for prop");
    assert_eq!(unit.names, ["kg", "mm", "ms"].map(String::from));
    assert_eq!(unit.system, UnitSystem::new(1.0, 1e-3, 1e-3).unwrap());

    let e = deck.property(2).unwrap();
    assert_eq!(e.title, "Revolute");
    assert_eq!(e.line, 6);
    assert_eq!(e.unit_id, Some(2));
    assert_eq!((e.skew1, e.skew2), (None, None));
    let p = &e.property;
    assert_eq!(p.joint_type, JointType::Revolute);
    assert_eq!(p.kn, 0.0);
    assert!(p.automatic_stiffness());
    assert_eq!(p.scale_factor, 0.0);
    assert_eq!(p.resolved_scale_factor(), 1.0);
    assert_eq!(p.critical_damping, 0.0);
    assert_eq!(p.resolved_critical_damping(), 0.05);
    assert_eq!(p.sensor, None);
    let rx = p.dof(Dof::Rx);
    assert_eq!(rx.stiffness, 0.0);
    assert_eq!(rx.stop_min, 0.0);
    assert_eq!(rx.stop_max, 0.52);
    assert!(!rx.coupled_stops);
    assert_eq!(rx.viscosity, 0.0);
    assert_eq!(rx.friction_stiffness, 0.0);
    assert_eq!(rx.friction, 100.0);
    assert!(!rx.friction_active(), "Kf = 0: friction inactive");
    assert!(rx.stiffness_curve.is_none() && rx.friction_curve.is_none());
    // Blocked DOFs carry nothing.
    for d in [Dof::Dx, Dof::Dy, Dof::Dz, Dof::Ry, Dof::Rz] {
        assert_eq!(p.dof(d), &Default::default());
    }

    // SI: angles are not converted; a moment in kg·mm²/ms² is exactly 1 N·m.
    let si = deck.property_si(2).unwrap();
    assert_eq!(si.dof(Dof::Rx).stop_max, 0.52);
    assert_eq!(si.dof(Dof::Rx).stop_min, 0.0);
    assert_relative_eq!(si.dof(Dof::Rx).friction, 100.0, max_relative = 1e-12);
    assert_eq!(si.kn, 0.0);
    assert_eq!(si.resolved_scale_factor(), 1.0);
    assert_eq!(si.resolved_critical_damping(), 0.05);
    assert!(!si.dof(Dof::Rx).friction_active());
}

#[test]
fn example_translational_with_stops() {
    let deck = RadiossDeck::from_file(asset("translational_stops.rad")).unwrap();
    assert!(deck.notices.is_empty(), "{:?}", deck.notices);
    let e = deck.property(12).unwrap();
    assert_eq!(e.title, "Translational");
    let p = &e.property;
    assert_eq!(p.joint_type, JointType::Translational);
    assert_eq!(p.kn, 0.0);
    assert_eq!(p.resolved_scale_factor(), 1.0);
    assert_eq!(p.critical_damping, 0.2);
    assert_eq!(p.resolved_critical_damping(), 0.2);
    let dx = p.dof(Dof::Dx);
    assert_eq!((dx.stop_min, dx.stop_max), (-100.0, 100.0));
    assert_eq!(dx.friction_stiffness, 1000.0);
    assert_eq!(dx.friction, 0.0);
    assert!(!dx.friction_active(), "FF = 0 and no function: no friction");
    assert!(!dx.coupled_stops);

    // SI: mm → m; a stiffness unit of kg-mm-ms is kg/ms² = 1e6 N/m, so Kf = 1000 → 1e9 N/m.
    let si = deck.property_si(12).unwrap();
    let dx = si.dof(Dof::Dx);
    assert_relative_eq!(dx.stop_min, -0.1, max_relative = 1e-12);
    assert_relative_eq!(dx.stop_max, 0.1, max_relative = 1e-12);
    assert_relative_eq!(dx.friction_stiffness, 1e9, max_relative = 1e-12);
    assert_eq!(si.critical_damping, 0.2);
    assert_eq!(si.kn, 0.0);
}

/// The resolved values printed by `kjoint check` for the seeds are the deck values in SI with
/// the spec's defaults applied: Kn = 0 → automatic; ScF = 0 → 1 with Kn = 0; Cr = 0 → 0.05;
/// the stop stiffness is Kf when Kf > 0, else the blocked stiffness; friction needs Kf > 0
/// and FF > 0.
#[test]
fn check_command_prints_the_seeds_resolved_with_spec_defaults() {
    let rev = common::cli::kjoint_check(&asset("revolute_stop.rad"));
    let deck = RadiossDeck::from_file(asset("revolute_stop.rad")).unwrap();
    let p = deck.property_si(2).unwrap();
    // The printed numbers are the resolved ones of the library...
    assert_eq!(p.resolved_critical_damping(), 0.05);
    assert_eq!(p.resolved_scale_factor(), 1.0);
    assert!(p.automatic_stiffness());
    for line in [
        "property 2 `Revolute`",
        "unit_ID 2 (mass 1 kg, length 0.001 m, time 0.001 s), converted to SI",
        "type 2 (revolute), free DOFs: rx",
        "Kn = 0 N/m: automatic blocked stiffness from the substep",
        "ScF = 1 (default)",
        "Cr = 0.05 (default)",
        "sensor: none",
        "rx stop stiffness: the automatic blocked stiffness",
        "SA- = none, SA+ = 0.52 rad, Icomb = 0",
        // FM is a moment: kg·mm²/ms² = 1 N·m, so 100 stays 100.
        "Kf = 0 N·m/rad, FM = 100 N·m (friction inactive",
        // a rotation's friction is FM: the reason names FM, not the translations' FF
        "(friction inactive: needs Kf > 0 and FM > 0 or a curve)",
    ] {
        assert!(rev.contains(line), "missing `{line}` in\n{rev}");
    }
    assert!(!rev.contains("dx:"), "only the free DOF is listed:\n{rev}");

    let tr = common::cli::kjoint_check(&asset("translational_stops.rad"));
    for line in [
        "property 12 `Translational`",
        "type 6 (translational), free DOFs: dx",
        "ScF = 1 (default)",
        "Cr = 0.2\n",
        // mm → m; a stiffness of kg/ms² is 1e6 N/m.
        "dx stop stiffness: Kf = 1000000000 N/m",
        "SD- = -0.1 m, SD+ = 0.1 m, Icomb = 0",
        "FF = 0 N (friction inactive: needs Kf > 0 and FF > 0 or a curve)",
    ] {
        assert!(tr.contains(line), "missing `{line}` in\n{tr}");
    }
}

/// A scene that references a seed deck resolves the same property as the deck itself.
#[test]
fn check_command_resolves_deck_references_of_scenes() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    for (scene, deck, id) in [
        ("seed_revolute_stop.toml", "revolute_stop.rad", 2),
        (
            "seed_translational_stops.toml",
            "translational_stops.rad",
            12,
        ),
    ] {
        let from_scene = common::cli::kjoint_check(&scenes.join(scene));
        let from_deck = common::cli::kjoint_check(&asset(deck));
        assert!(
            from_scene.contains(&format!("prop_ID {id}")),
            "{from_scene}"
        );
        let block = |s: &str| -> Vec<String> {
            s.lines()
                .skip_while(|l| !l.starts_with("  type "))
                .take_while(|l| l.starts_with("  "))
                .map(String::from)
                .collect()
        };
        assert!(!block(&from_deck).is_empty());
        // the scene's joint also has bodies: its resolved stiffness and stable steps follow
        // the property (a deck alone has none)
        let mut scene_block = block(&from_scene);
        let resolved = scene_block.split_off(block(&from_deck).len());
        assert!(
            resolved.len() == 2
                && resolved[0].starts_with("  blocked stiffness for the substep")
                && resolved[1].starts_with("  explicit stable steps"),
            "{resolved:?}"
        );
        assert_eq!(scene_block, block(&from_deck), "{scene}");
        assert!(from_scene.trim_end().ends_with("ok"));
    }
}

// ---------------------------------------------------------------------------------------
// Reading features
// ---------------------------------------------------------------------------------------

#[test]
fn kjoint2_alias_short_lines_and_missing_dof_cards() {
    // Short first card (only Type), no DOF cards at all for a planar joint (dy, dz, rx).
    let text = "/PROP/KJOINT2/5\nplanar\n         4\n";
    let deck = RadiossDeck::from_str(text, "short.rad").unwrap();
    let p = &deck.property(5).unwrap().property;
    assert_eq!(p.joint_type, JointType::Planar);
    assert_eq!(p.kn, 0.0);
    assert_eq!(p.dof(Dof::Dy), &Default::default());
    assert_eq!(deck.notices.len(), 1);
    assert_eq!(deck.notices[0].line, 3);
    assert!(
        deck.notices[0].message.contains("dy.K"),
        "{:?}",
        deck.notices
    );
    // Without a unit the SI property is the property as written.
    assert_eq!(deck.property_si(5), Some(p));
}

#[test]
fn fortran_reals_and_blank_fields() {
    let text = deck(&prop(
        "3",
        format!("{}{}{}{}", i(6), r("1.5d3"), r(""), r("1.E-1")),
        &[
            format!("{}{}{}{}", r("2.5E+02"), i(""), r("-.5"), r("5")),
            String::new(),
            f_card("1+2", "3.", 0),
        ],
    ));
    let deck = RadiossDeck::from_str(&text, "t.rad").unwrap();
    let p = &deck.property(3).unwrap().property;
    assert_eq!(p.kn, 1500.0);
    assert_eq!(p.scale_factor, 0.0);
    assert_eq!(p.critical_damping, 0.1);
    let dx = p.dof(Dof::Dx);
    assert_eq!(dx.stiffness, 250.0);
    assert_eq!((dx.stop_min, dx.stop_max), (-0.5, 5.0));
    assert_eq!(dx.viscosity, 0.0);
    assert_eq!((dx.friction_stiffness, dx.friction), (100.0, 3.0));
    assert!(dx.friction_active());
}

#[test]
fn functions_are_resolved_and_converted_per_dof_family() {
    // Translational joint in kg-mm-ms with a force-displacement function (two pairs per
    // line), a force-velocity function and a friction function.
    let text = deck(&[
        "/UNIT/1".into(),
        "kg mm ms".into(),
        format!("{}{}{}", r("kg"), r("mm"), r("ms")),
        "/FUNCT/10".into(),
        "force vs displacement [kN, mm]".into(),
        format!("{}{}{}{}", r(-10), r(-5), r(0), r(0)),
        format!("{}{}", r(10), r(5)),
        "/FUNCT/11".into(),
        "force vs velocity".into(),
        format!("{}{}", r(0), r(0)),
        format!("{}{}", r(2), r(1)),
        "/FUNCT/12".into(),
        "friction".into(),
        format!("{}{}{}{}", r(0), r(1), r(1), r(1)),
        "/PROP/TYPE45/1/1".into(),
        "slider".into(),
        first_card(6, "2", "50", "0", 0),
        k_card("3", 10, "-100", "100", 0),
        c_card("0", 11),
        f_card("1000", "0", 12),
    ]);
    let deck = RadiossDeck::from_str(&text, "f.rad").unwrap();
    let e = deck.property(1).unwrap();
    assert_eq!(e.function_ids[0].stiffness, Some(10));
    assert_eq!(e.function_ids[0].viscosity, Some(11));
    assert_eq!(e.function_ids[0].friction, Some(12));
    let dx = e.property.dof(Dof::Dx);
    let pts: Vec<_> = dx.stiffness_curve.as_ref().unwrap().points().collect();
    assert_eq!(pts, vec![(-10.0, -5.0), (0.0, 0.0), (10.0, 5.0)]);
    assert_eq!(dx.viscosity_scale(), 1.0);
    assert!(dx.friction_active());

    let si = deck.property_si(1).unwrap();
    // Kn = 2 kg/ms² = 2e6 N/m; with Kn > 0, ScF is an area that Radioss reads in the work
    // units, not the property's: without /BEGIN they are SI, 50 m².
    assert_relative_eq!(si.kn, 2e6, max_relative = 1e-12);
    assert_relative_eq!(si.scale_factor, 50.0, max_relative = 1e-12);
    let dx = si.dof(Dof::Dx);
    // The scale in front of a function is a pure number.
    assert_eq!(dx.stiffness, 3.0);
    let k: Vec<_> = dx.stiffness_curve.as_ref().unwrap().points().collect();
    for ((x, y), (ex, ey)) in k.iter().zip([(-0.01, -5e3), (0.0, 0.0), (0.01, 5e3)]) {
        assert_relative_eq!(*x, ex, max_relative = 1e-12);
        assert_relative_eq!(*y, ey, max_relative = 1e-12);
    }
    // Velocity mm/ms = m/s (factor 1), force ×1e3.
    let c: Vec<_> = dx.viscosity_curve.as_ref().unwrap().points().collect();
    assert_relative_eq!(c[1].0, 2.0, max_relative = 1e-12);
    assert_relative_eq!(c[1].1, 1e3, max_relative = 1e-12);
    let f: Vec<_> = dx.friction_curve.as_ref().unwrap().points().collect();
    assert_relative_eq!(f[0].1, 1e3, max_relative = 1e-12);
    assert_relative_eq!(dx.friction_stiffness, 1e9, max_relative = 1e-12);
    assert_relative_eq!(dx.stop_max, 0.1, max_relative = 1e-12);
}

#[test]
fn rotational_conversion_in_g_cm_s() {
    // g-cm-s: moment unit g·cm²/s² = 1e-3·1e-4 = 1e-7 N·m; rotational viscosity 1e-7 N·m·s;
    // angular velocity unchanged (1/s).
    let text = deck(&[
        "/UNIT/3".into(),
        "cgs".into(),
        format!("{}{}{}", r("g"), r("cm"), r("s")),
        "/PROP/TYPE45/4/3".into(),
        "revolute".into(),
        first_card(2, "0", "7", ".1", 0),
        k_card("20", 0, "-1.5", "1.5", 0),
        c_card("4", 0),
        f_card("6", "8", 0),
    ]);
    let deck = RadiossDeck::from_str(&text, "cgs.rad").unwrap();
    let rx = deck.property_si(4).unwrap().dof(Dof::Rx).clone();
    assert_relative_eq!(rx.stiffness, 20e-7, max_relative = 1e-12);
    assert_eq!((rx.stop_min, rx.stop_max), (-1.5, 1.5));
    assert_relative_eq!(rx.viscosity, 4e-7, max_relative = 1e-12);
    assert_relative_eq!(rx.friction_stiffness, 6e-7, max_relative = 1e-12);
    assert_relative_eq!(rx.friction, 8e-7, max_relative = 1e-12);
    // Kn = 0: ScF is a pure number.
    assert_eq!(deck.property_si(4).unwrap().scale_factor, 7.0);

    // The same conversion through the public function, with the kg-mm-ms factors.
    let p = deck.property(4).unwrap().property.clone();
    let si = property_to_si(&p, &UnitSystem::from_names("kg", "mm", "ms").unwrap()).unwrap();
    assert_relative_eq!(si.dof(Dof::Rx).stiffness, 20.0, max_relative = 1e-12);
    assert_relative_eq!(si.dof(Dof::Rx).viscosity, 4e-3, max_relative = 1e-12);
}

#[test]
fn whole_model_deck_with_skews_sensors_and_skipped_blocks() {
    let text = deck(&[
        "#RADIOSS STARTER".into(),
        "/BEGIN".into(),
        "model".into(),
        format!("{}{}", i(2019), i(0)),
        format!("{}{}{}", r("kg"), r("mm"), r("ms")),
        format!("{}{}{}", r("kg"), r("mm"), r("ms")),
        "/NODE".into(),
        format!("{}{}{}{}", i(1), r(0), r(0), r(0)),
        "/UNIT/9".into(),
        "ms".into(),
        format!("{}{}{}", r("kg"), r("mm"), r("ms")),
        "/SKEW/FIX/3/9".into(),
        "frame".into(),
        format!("{}{}{}", r(10), r(20), r(30)),
        format!("{}{}{}", r(0), r(2), r(0)),
        format!("{}{}{}", r(0), r(1), r(5)),
        "/SENSOR/TIME/8/9".into(),
        "lock at 5 ms".into(),
        r(5),
        "/PROP/SHELL/1".into(),
        "shell".into(),
        "/PROP/TYPE45/1".into(),
        "hinge".into(),
        format!("{}{}", first_card(2, "1e4", "0", "0", 8), i(3)),
        k_card("0", 0, "0", "0", 0),
        c_card("0", 0),
        f_card("0", "0", 0),
        "/PART/1".into(),
        "part".into(),
        format!("{}{}", i(1), i(1)),
        "/END".into(),
        "/PROP/TYPE45/99".into(),
        "after the end: not read".into(),
    ]);
    let deck = RadiossDeck::from_str(&text, "model.rad").unwrap();
    let e = deck.property(1).unwrap();
    assert_eq!(e.property.sensor, Some(8));
    assert_eq!((e.skew1, e.skew2), (Some(3), None));
    assert_eq!(e.property.kn, 1e4);
    // without a unit_ID, in /BEGIN's input units: kN/mm = 1e6 N/m
    assert_relative_eq!(deck.property_si(1).unwrap().kn, 1e10, max_relative = 1e-12);
    assert_eq!(deck.properties.len(), 1);

    let s = &deck.sensors[&8];
    assert_eq!(s.tdelay, 5.0);
    assert_relative_eq!(s.tdelay_si(), 5e-3, max_relative = 1e-12);
    let sk = &deck.skews[&3];
    let o = sk.origin_si();
    assert_relative_eq!(o[2], 0.03, max_relative = 1e-12);
    let [x, y, z] = sk.axes();
    assert_eq!(y, [0.0, 1.0, 0.0]);
    assert_relative_eq!(x[0], 1.0, max_relative = 1e-12);
    assert_relative_eq!(z[2], 1.0, max_relative = 1e-12);

    let skipped: Vec<(usize, &str)> = deck
        .notices
        .iter()
        .map(|n| (n.line, n.message.as_str()))
        .collect();
    let lines: Vec<usize> = skipped.iter().map(|s| s.0).collect();
    assert_eq!(lines, vec![2, 7, 20, 28], "{skipped:?}");
    assert!(skipped[0].1.contains(
        "/BEGIN: values on keywords without a /unit_ID are in its input units (kg mm ms)"
    ));
    assert!(skipped[1].1.contains("/NODE"));
    assert!(skipped[2].1.contains("/PROP/SHELL/1"));
    assert!(skipped[3].1.contains("/PART/1"));
}

/// A deck in kg-mm-ms (force kN, moment kN·mm = N·m, stiffness kN/mm = 1e6 N/m), as crash
/// decks are written: every value whose keyword has no `/unit_ID` is in `/BEGIN`'s input
/// units (it was read as SI: a joint 1e6 times too soft); a keyword with its own `/unit_ID`
/// keeps it.
#[test]
fn begin_input_units_apply_to_keywords_without_a_unit_id() {
    let begin = |input: String| {
        vec![
            "/BEGIN".to_string(),
            "crash model".into(),
            format!("{}{}", i(2022), i(0)),
            input,
            format!("{}{}{}", r("kg"), r("mm"), r("ms")),
        ]
    };
    let rest: Vec<String> = [
        vec![
            "/SKEW/FIX/3".to_string(),
            "frame".into(),
            format!("{}{}{}", r(10), r(20), r(30)),
            format!("{}{}{}", r(0), r(1), r(0)),
            format!("{}{}{}", r(0), r(0), r(1)),
            "/SENSOR/TIME/8".into(),
            "lock at 5 ms".into(),
            r(5),
            "/UNIT/2".into(),
            "SI".into(),
            format!("{}{}{}", r("kg"), r("m"), r("s")),
        ],
        prop(
            "1",
            format!("{}{}", first_card(2, "2", "0", "0", 8), i(3)),
            &[
                k_card("3", 0, "0", "0", 0),
                c_card("0.5", 0),
                f_card("0", "0", 0),
            ],
        ),
        prop(
            "2/2",
            first_card(2, "2", "0", "0", 0),
            &[
                k_card("3", 0, "0", "0", 0),
                c_card("0", 0),
                f_card("0", "0", 0),
            ],
        ),
    ]
    .concat();
    // the input units written, then blank (they default to the work units, kg mm ms)
    for input in [format!("{}{}{}", r("kg"), r("mm"), r("ms")), String::new()] {
        let text = deck(&[begin(input), rest.clone()].concat());
        let deck = RadiossDeck::from_str(&text, "kg_mm_ms.rad").unwrap();
        let units = deck.input_units.as_ref().unwrap();
        assert_eq!(units.names, ["kg", "mm", "ms"].map(String::from));
        assert_eq!(units.system, UnitSystem::new(1.0, 1e-3, 1e-3).unwrap());
        let p = deck.property_si(1).unwrap();
        assert_relative_eq!(p.kn, 2e6, max_relative = 1e-12);
        // ScF left at 0 with Kn > 0: its default 10 is in the deck's units, 10 mm²
        assert_relative_eq!(p.resolved_scale_factor(), 1e-5, max_relative = 1e-12);
        assert_relative_eq!(p.dof(Dof::Rx).stiffness, 3.0, max_relative = 1e-12);
        // kN·mm·ms/rad = 1e-3 N·m·s/rad
        assert_relative_eq!(p.dof(Dof::Rx).viscosity, 5e-4, max_relative = 1e-12);
        assert_relative_eq!(deck.sensors[&8].tdelay_si(), 5e-3, max_relative = 1e-12);
        assert_relative_eq!(deck.skews[&3].origin_si()[2], 0.03, max_relative = 1e-12);
        // its own unit system wins, except for ScF with Kn > 0: its default 10 is in the
        // work units (kg mm ms), 10 mm², whatever the property's units
        let own = deck.property_si(2).unwrap();
        assert_eq!((own.kn, own.dof(Dof::Rx).stiffness), (2.0, 3.0));
        assert_relative_eq!(own.resolved_scale_factor(), 1e-5, max_relative = 1e-12);
        let notice = &deck.notices[0];
        assert_eq!(notice.line, 1);
        assert!(
            notice.message.contains("input units (kg mm ms)"),
            "{notice}"
        );
        // `kjoint check` says which unit system each property was read in
        let dir = common::cli::fresh_temp_dir("begin-units");
        let path = dir.join("kg_mm_ms.rad");
        std::fs::write(&path, &text).unwrap();
        let out = common::cli::kjoint_check(&path);
        assert!(
            out.contains(
                "/BEGIN's input units (mass 1 kg, length 0.001 m, time 0.001 s), converted to SI"
            ) && out.contains("unit_ID 2 (mass 1 kg, length 1 m, time 1 s)"),
            "{out}"
        );
    }
}

/// Law review finding 4: with Kn > 0, ScF is an area that Radioss reads in `/BEGIN`'s WORK
/// units whatever the property's units (the cfg gives SCALE no dimension, hm_read_prop45.F
/// converts Kn alone, rini45.F forms KR = KNN·MAX(SCF, LEN2) with LEN2 in work units). A
/// deck with input units kg-m-s and work units kg-mm-ms: Kn = 1e6 N/m with ScF blank (10 mm²)
/// gives KR = 1e6·1e-5 = 10 N·m/rad (it was converted from the input units: 10 m², KR = 1e7);
/// with its own unit_ID in kg-m-s and ScF = 50 (50 mm²), KR = 50 N·m/rad (it was 5e7). L0 = 0.
#[test]
fn scf_is_an_area_in_the_work_units_whatever_the_input_units() {
    let text = deck(
        &[
            vec![
                "/BEGIN".to_string(),
                "input in m, work in mm".into(),
                format!("{}{}", i(2022), i(0)),
                format!("{}{}{}", r("kg"), r("m"), r("s")),
                format!("{}{}{}", r("kg"), r("mm"), r("ms")),
                "/UNIT/2".into(),
                "SI".into(),
                format!("{}{}{}", r("kg"), r("m"), r("s")),
            ],
            prop(
                "1",
                first_card(2, "1e6", "0", "0", 0),
                &[
                    k_card("0", 0, "0", "0", 0),
                    c_card("0", 0),
                    f_card("0", "0", 0),
                ],
            ),
            prop(
                "2/2",
                first_card(2, "1e6", "50", "0", 0),
                &[
                    k_card("0", 0, "0", "0", 0),
                    c_card("0", 0),
                    f_card("0", "0", 0),
                ],
            ),
        ]
        .concat(),
    );
    let deck = RadiossDeck::from_str(&text, "m_in_mm_work.rad").unwrap();
    for (id, kr) in [(1, 10.0), (2, 50.0)] {
        let p = deck.property_si(id).unwrap().clone();
        assert_relative_eq!(p.kn, 1e6, max_relative = 1e-12);
        let (mut w, ground) = common::world(rapier_kjoint::rapier::prelude::Vector::ZERO);
        let body = common::point_body(
            &mut w,
            1.0,
            rapier_kjoint::rapier::prelude::Vector::splat(0.1),
            rapier_kjoint::rapier::prelude::Vector::ZERO,
        );
        let mut set = common::joints(1);
        let j = common::add(&mut set, &w, p, ground, body, |b| b);
        set.step(&mut w, 1e-6).unwrap();
        let joint = set.get(j).unwrap();
        assert_eq!(joint.initial_length(), 0.0);
        let k = joint.blocked_stiffness().unwrap();
        assert_relative_eq!(k.translational, 1e6, max_relative = 1e-12);
        assert_relative_eq!(k.rotational, kr, max_relative = 1e-12);
    }
    // `kjoint check` says that a blank ScF is the default (10 of the work units, 10 mm²),
    // as it says of a blank Cr: it printed `ScF = 0.00001 m²` without it. Of the deck, and
    // of a scene that uses its properties; with the least KR it gives (a zero-length joint's).
    let dir = common::cli::fresh_temp_dir("scf-default");
    let path = dir.join("m_in_mm_work.rad");
    std::fs::write(&path, &text).unwrap();
    let scene = dir.join("scf.toml");
    std::fs::write(
        &scene,
        "duration = 0.1\n\n[[bodies]]\nname = \"b\"\nshape = { type = \"ball\", radius = 0.1 \
         }\nmass = 1.0\n\n[[joints]]\nname = \"blank\"\nbody1 = \"world\"\nbody2 = \"b\"\n\
         property = { deck = \"m_in_mm_work.rad\", id = 1 }\n\n[[joints]]\nname = \"fifty\"\n\
         body1 = \"world\"\nbody2 = \"b\"\nproperty = { deck = \"m_in_mm_work.rad\", id = 2 }\n",
    )
    .unwrap();
    for out in [
        common::cli::kjoint_check(&path),
        common::cli::kjoint_check(&scene),
    ] {
        let scf: Vec<&str> = out.lines().filter(|l| l.contains("ScF =")).collect();
        assert_eq!(
            scf,
            [
                "  ScF = 0.00001 m² (default) (KR = Kn·max(ScF, L0²) ≥ 10 N·m/rad)",
                "  ScF = 0.00005 m² (KR = Kn·max(ScF, L0²) ≥ 50 N·m/rad)"
            ],
            "{out}"
        );
    }
}

/// Law review finding 2: Radioss ignores the Skew_ID2 of types 5 to 8 (universal,
/// translational, Oldham, fixed) with warning 1134 and θ0 = 0 (rini45.F, INIT_SKEW45). A
/// fixed joint (Kn = 1e4, ScF = 1: KR = 1e4 N·m/rad, L0 = 0) whose Skew_ID2 is Skew_ID1
/// turned 0.3 rad about x: the reader drops Skew_ID2 with a notice naming the property and
/// the line of its first card, and the scene's joint holds no moment (Mx = 0; the skew
/// applied gave Mx = KR·0.3 = 3000 N·m, which the API's world_frame2 still gives).
#[test]
fn skew2_is_ignored_on_types_5_to_8_as_radioss_does() {
    use rapier_kjoint::rapier::prelude::{Rotation, Vector};
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    let text = deck(&[
        skew_cards(1, "world", [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
        skew_cards(2, "turned 0.3 rad about x", [0.0, c, s], [0.0, -s, c]),
        "/PROP/TYPE45/7".into(),
        "fixed with skew2".into(),
        format!("{}{}{}", first_card(8, "1e4", "1", "0", 0), i(1), i(2)),
    ]);
    let deck = RadiossDeck::from_str(&text, "fixed.rad").unwrap();
    let e = deck.property(7).unwrap();
    assert_eq!((e.skew1, e.skew2), (Some(1), None));
    let notes: Vec<_> = deck
        .notices
        .iter()
        .filter(|n| n.message.contains("Skew_ID2"))
        .collect();
    assert_eq!(notes.len(), 1, "{:?}", deck.notices);
    assert_eq!(notes[0].line, 13);
    assert!(
        notes[0].message.contains("/PROP/TYPE45/7")
            && notes[0]
                .message
                .contains("Skew_ID2 = 2 is ignored on Type 8 (fixed)")
            && notes[0].message.contains("warning 1134"),
        "{}",
        notes[0]
    );

    // through a scene, as a deck property is used: no preload, and the notice is shown
    let dir = common::cli::fresh_temp_dir("fixed-skew2");
    std::fs::write(dir.join("fixed.rad"), &text).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(
        &path,
        "duration = 0.1\ngravity = [0, 0, 0]\n[[bodies]]\nname = \"b\"\n\
         shape = { type = \"ball\", radius = 0.1 }\nmass = 1.0\n[[joints]]\nname = \"j\"\n\
         body1 = \"world\"\nbody2 = \"b\"\nproperty = { deck = \"fixed.rad\", id = 7 }\n",
    )
    .unwrap();
    let (sc, src) = rapier_kjoint::scene::load(&path).unwrap();
    let mut built = rapier_kjoint::scene::build(&sc, &src).unwrap();
    assert!(
        built.notices.iter().any(|n| n.contains("warning 1134")),
        "{:?}",
        built.notices
    );
    built.joints.step(&mut built.world, 1e-6).unwrap();
    let (_, j) = built.joints.iter().next().unwrap();
    let st = j.state().unwrap();
    assert!(st.force[3].abs() < 1e-6, "Mx = {}", st.force[3]);
    assert!(st.q[3].abs() < 1e-9, "θx = {}", st.q[3]);

    // the API keeps applying world_frame2 on every type: KR·0.3 = 3000 N·m
    let (mut w, ground) = common::world(Vector::ZERO);
    let body = common::point_body(&mut w, 1.0, Vector::splat(0.1), Vector::ZERO);
    let mut set = common::joints(1);
    let prop = deck.property_si(7).unwrap().clone();
    assert_eq!((prop.kn, prop.scale_factor), (1e4, 1.0));
    let h = common::add(&mut set, &w, prop, ground, body, |b| {
        b.world_frame2(Rotation::from_rotation_x(0.3))
    });
    set.step(&mut w, 1e-6).unwrap();
    let mx = set.get(h).unwrap().state().unwrap().force[3];
    assert!((mx.abs() - 3000.0).abs() < 1e-3, "Mx = {mx}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn error_two_begin_blocks_or_an_unknown_begin_unit() {
    let begin = "/BEGIN\nrun\n      2022\n";
    let text = format!("{begin}\n\n{begin}");
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (6, "keyword"));
    assert!(
        matches!(&kind, DeckErrorKind::InvalidKeyword { expected, .. }
            if expected.contains("first is at line 1")),
        "{kind:?}"
    );
    let text = format!("{begin}{}{}{}\n", r("kg"), r("furlong"), r("s"));
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (4, "Input_length_unit"));
    assert!(matches!(
        kind,
        DeckErrorKind::UnknownUnit {
            quantity: BaseQuantity::Length,
            ..
        }
    ));
}

// ---------------------------------------------------------------------------------------
// Malformed input: one test each, checking line and field
// ---------------------------------------------------------------------------------------

#[test]
fn error_unknown_joint_type() {
    let (k, c, f) = ok_rx();
    let text = revolute(k, c, f).replacen("         2", "        10", 1);
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (3, "Type"));
    assert_eq!(
        kind,
        DeckErrorKind::UnknownJointType {
            value: 10,
            hint: String::new()
        }
    );
}

/// A deck without the property's title line, or with its first card shifted by a column,
/// read "unknown joint type 0" and nothing more (a Radioss analyst's trial, 2026-12-05): the
/// error now says what the layout suggests.
#[test]
fn error_unknown_joint_type_says_a_missing_title_or_a_shifted_card() {
    let (k, c, f) = ok_rx();
    let text = revolute(k, c, f);
    // the title line removed: the first card is read as the title, the second as the first
    let lines: Vec<&str> = text.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.starts_with("/PROP/TYPE45"))
        .unwrap();
    let mut no_title = lines.clone();
    no_title.remove(at + 1);
    let (_, field, kind) = error_of(&(no_title.join("\n") + "\n"));
    assert_eq!(field, "Type");
    let said = kind.to_string();
    assert!(
        said.contains("unknown joint type") && said.contains("is the title line missing?"),
        "{said}"
    );
    // the first card shifted right by a column: Type's columns blank
    let mut shifted: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    shifted[at + 2] = format!("          {}", shifted[at + 2].trim_start());
    let (_, _, kind) = error_of(&(shifted.join("\n") + "\n"));
    let said = kind.to_string();
    assert!(said.contains("is the card shifted?"), "{said}");
}

#[test]
fn error_missing_title() {
    let (line, field, kind) = error_of("#c\n/PROP/TYPE45/4\n");
    assert_eq!((line, field.as_str()), (2, "prop_title"));
    assert!(matches!(kind, DeckErrorKind::MissingCard { .. }));
}

#[test]
fn error_missing_first_card() {
    let (line, field, kind) = error_of("/PROP/TYPE45/4\ntitle\n# only comments\n/NODE\n");
    assert_eq!((line, field.as_str()), (1, "Type"));
    match kind {
        DeckErrorKind::MissingCard { card, block } => {
            assert_eq!(card, "Type Kn ScF Cr sens_ID Skew_ID1 Skew_ID2");
            assert_eq!(block, "/PROP/TYPE45/4");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn error_number_does_not_parse() {
    let (k, c, f) = ok_rx();
    let text = revolute(k, c, f).replacen(&r("0"), &r("1.0.0"), 1);
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (3, "Kn"));
    assert!(matches!(kind, DeckErrorKind::InvalidNumber { .. }));

    // A real in an integer field.
    let (_, c, f) = ok_rx();
    let k = format!("{}{}{}{}{}", r("0"), i("1.5"), r("0"), r(".52"), i(0));
    let (line, field, _) = error_of(&revolute(k, c, f));
    assert_eq!((line, field.as_str()), (4, "rx.fct_K"));
}

#[test]
fn error_stop_of_the_wrong_sign() {
    let (_, c, f) = ok_rx();
    let (line, field, kind) = error_of(&revolute(k_card("0", 0, ".3", ".52", 0), c, f));
    assert_eq!((line, field.as_str()), (4, "rx.SA-"));
    assert!(matches!(kind, DeckErrorKind::Property(_)));

    let text = deck(&prop(
        "2",
        first_card(6, "0", "0", "0", 0),
        &[k_card("0", 0, "-1", "-2", 0)],
    ));
    let (line, field, _) = error_of(&text);
    assert_eq!((line, field.as_str()), (4, "dx.SD+"));
}

#[test]
fn error_negative_spring_or_viscosity() {
    let (_, c, f) = ok_rx();
    let (line, field, kind) = error_of(&revolute(k_card("-5", 0, "0", ".52", 0), c, f));
    assert_eq!((line, field.as_str()), (4, "rx.K"));
    assert!(
        kind.to_string().contains("expected a value >= 0 [N·m/rad"),
        "{kind}"
    );
    let (k, _, f) = ok_rx();
    let (line, field, kind) = error_of(&revolute(k, c_card("-2", 0), f));
    assert_eq!((line, field.as_str()), (5, "rx.C"));
    assert!(
        kind.to_string()
            .contains("expected a value >= 0 [N·m·s/rad"),
        "{kind}"
    );
}

/// A curve that the property refuses is named on its own card's line, with its Radioss
/// name: `[[-1, 5], [1, -5]]` as a hinge's `fct_FM`, a negative friction force, on its
/// friction card (line 9), as its `fct_C`, a falling viscosity, on its viscosity card
/// (line 8). They were named on the
/// K card's line, and a rotation's friction curve as `fct_FF` (a review, 2026-12-06).
#[test]
fn error_a_refused_curve_is_named_on_its_card() {
    // a hinge: its first card, then rx's K, C and friction cards (lines 7, 8, 9), with the
    // curve 13 given as `fct_C` or `fct_FM`
    let deck = |c_card: &str, f_card: &str| {
        format!(
            "/FUNCT/13\nfalls\n                  -1                   5                   1                  -5\n\
             /PROP/TYPE45/2\nhinge\n         2                   0                   0                   0         0\n\
             \x20                  3         0                  -1                   1         0\n{c_card}\n{f_card}\n"
        )
    };
    let (line, field, kind) = error_of(&deck(
        "                   0         0",
        "                1000                   1        13",
    ));
    assert_eq!((line, field.as_str()), (9, "rx.fct_FM"), "{kind}");
    assert!(kind.to_string().contains("values >= 0"), "{kind}");
    let (line, field, kind) = error_of(&deck(
        "                   1        13",
        "                   0                   0         0",
    ));
    assert_eq!((line, field.as_str()), (8, "rx.fct_C"), "{kind}");
    assert!(kind.to_string().contains("first slope"), "{kind}");
}

#[test]
fn error_coupled_stops_with_unequal_values() {
    // Oldham (type 7): free dy and dz, both coupled but with different stops.
    let text = deck(&prop(
        "2",
        first_card(7, "0", "0", "0", 0),
        &[
            k_card("0", 0, "-1", "1", 1),
            c_card("0", 0),
            f_card("0", "0", 0),
            k_card("0", 0, "-2", "2", 1),
            c_card("0", 0),
            f_card("0", "0", 0),
        ],
    ));
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (7, "dz.Icomb"));
    assert!(matches!(kind, DeckErrorKind::Property(_)));
}

/// Issue 12, item 5: `Icomb = 1` on a single DOF is refused (coupling needs two or three
/// DOFs of one family; OpenRadioss silently treats it as an independent stop).
#[test]
fn error_icomb_on_a_single_dof() {
    let (_, c, f) = ok_rx();
    let text = revolute(k_card("0", 0, "-1", "1", 1), c, f);
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (4, "rx.Icomb"));
    let msg = RadiossDeck::from_str(&text, "test.rad")
        .unwrap_err()
        .to_string();
    assert!(msg.contains("two or three free DOFs"), "{msg}");
    assert!(matches!(kind, DeckErrorKind::Property(_)));
}

/// Issue 12, item 5: Kn = 1e308 makes KR = Kn·ScF = 1e309 overflow: refused on the first
/// card, field Kn, with the reason (and the number printed as 1e308, not 309 digits).
#[test]
fn error_kn_whose_rotational_stiffness_overflows() {
    let (k, c, f) = ok_rx();
    let text = deck(&prop("1", first_card(2, "1e308", "0", "0", 0), &[k, c, f]));
    let (line, field, _) = error_of(&text);
    assert_eq!((line, field.as_str()), (3, "Kn"));
    let msg = RadiossDeck::from_str(&text, "test.rad")
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("invalid kn (Kn) = 1e308") && msg.contains("is finite"),
        "{msg}"
    );
    assert!(msg.len() < 300, "{msg}");
    // 1e307 (KR = 1e308) is accepted; a huge ScF is named when it is the culprit
    let (k, c, f) = ok_rx();
    RadiossDeck::from_str(
        &deck(&prop("1", first_card(2, "1e307", "0", "0", 0), &[k, c, f])),
        "ok.rad",
    )
    .unwrap();
    let (k, c, f) = ok_rx();
    let (line, field, _) = error_of(&deck(&prop(
        "1",
        first_card(2, "10", "1e308", "0", 0),
        &[k, c, f],
    )));
    assert_eq!((line, field.as_str()), (3, "ScF"));
}

#[test]
fn error_icomb_not_0_or_1() {
    let (_, c, f) = ok_rx();
    let (line, field, _) = error_of(&revolute(k_card("0", 0, "-1", "1", 2), c, f));
    assert_eq!((line, field.as_str()), (4, "rx.Icomb"));
}

#[test]
fn error_damping_ratio_out_of_range() {
    let (k, c, f) = ok_rx();
    let text = revolute(k, c, f).replacen(
        &first_card(2, "0", "0", "0", 0),
        &first_card(2, "0", "0", "1.5", 0),
        1,
    );
    let (line, field, _) = error_of(&text);
    assert_eq!((line, field.as_str()), (3, "Cr"));
}

#[test]
fn error_unknown_function() {
    let (_, c, f) = ok_rx();
    let (line, field, kind) = error_of(&revolute(k_card("1", 7, "0", ".52", 0), c, f));
    assert_eq!((line, field.as_str()), (4, "rx.fct_K"));
    assert!(matches!(
        kind,
        DeckErrorKind::UnknownReference {
            what: "function",
            id: 7,
            ..
        }
    ));
    let (k, c, _) = ok_rx();
    let (line, field, _) = error_of(&revolute(k, c, f_card("1", "1", 9)));
    assert_eq!((line, field.as_str()), (6, "rx.fct_FM"));
}

#[test]
fn error_unknown_skew() {
    let (k, c, f) = ok_rx();
    let text = revolute(k, c, f).replacen(
        &first_card(2, "0", "0", "0", 0),
        &format!("{}{}{}", first_card(2, "0", "0", "0", 0), i(0), i(4)),
        1,
    );
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (3, "Skew_ID2"));
    assert!(matches!(
        kind,
        DeckErrorKind::UnknownReference {
            what: "skew",
            id: 4,
            ..
        }
    ));

    // A skew defined by a block the reader skips is named in the message.
    let text = format!("{text}/SKEW/MOV/4\nmoving\n{}\n", i(1) + &i(2) + &i(3));
    let (_, _, kind) = error_of(&text);
    match kind {
        DeckErrorKind::UnknownReference { note, .. } => assert!(note.contains("/SKEW/MOV/4")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn error_unknown_sensor() {
    let (k, c, f) = ok_rx();
    let text = revolute(k, c, f).replacen(
        &first_card(2, "0", "0", "0", 0),
        &first_card(2, "0", "0", "0", 5),
        1,
    );
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (3, "sens_ID"));
    assert!(matches!(
        kind,
        DeckErrorKind::UnknownReference {
            what: "sensor",
            id: 5,
            ..
        }
    ));
}

#[test]
fn error_unknown_unit() {
    let (k, c, f) = ok_rx();
    let text = revolute(k, c, f).replacen("/PROP/TYPE45/1", "/PROP/TYPE45/1/6", 1);
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (1, "unit_ID"));
    assert!(matches!(
        kind,
        DeckErrorKind::UnknownReference {
            what: "unit system",
            id: 6,
            ..
        }
    ));
}

#[test]
fn error_nan_and_infinity() {
    let (k, c, f) = ok_rx();
    let text = revolute(k, c, f).replacen(
        &first_card(2, "0", "0", "0", 0),
        &first_card(2, "0", "0", "NaN", 0),
        1,
    );
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (3, "Cr"));
    assert!(matches!(kind, DeckErrorKind::NotFinite { .. }));

    let (_, c, f) = ok_rx();
    let (line, field, kind) = error_of(&revolute(k_card("inf", 0, "0", "1", 0), c, f));
    assert_eq!((line, field.as_str()), (4, "rx.K"));
    assert!(matches!(kind, DeckErrorKind::NotFinite { .. }));

    let (_, c, f) = ok_rx();
    let (_, field, kind) = error_of(&revolute(k_card("1e400", 0, "0", "1", 0), c, f));
    assert_eq!(field, "rx.K");
    assert!(matches!(kind, DeckErrorKind::NotFinite { .. }));
}

#[test]
fn error_conversion_overflow() {
    // Finite as written, infinite in SI (1e305 kg/mus² in N/m).
    let text = deck(&[
        "/UNIT/1".into(),
        "u".into(),
        format!("{}{}{}", r("kg"), r("m"), r("mus")),
        "/PROP/TYPE45/1/1".into(),
        "t".into(),
        first_card(6, "1e305", "0", "0", 0),
    ]);
    let (line, field, _) = error_of(&text);
    assert_eq!((line, field.as_str()), (6, "Kn"));
}

#[test]
fn error_bad_keyword_ids_and_duplicates() {
    let (line, field, _) = error_of("/PROP/TYPE45/x\nt\n");
    assert_eq!((line, field.as_str()), (1, "prop_ID"));
    let (line, field, _) = error_of("/PROP/TYPE45\nt\n");
    assert_eq!((line, field.as_str()), (1, "prop_ID"));
    let (line, field, _) = error_of("/PROP/TYPE45/1/2/3\nt\n");
    assert_eq!((line, field.as_str()), (1, "keyword"));
    let (k, c, f) = ok_rx();
    let one = revolute(k, c, f);
    let (line, field, kind) = error_of(&format!("{one}{one}"));
    assert_eq!((line, field.as_str()), (7, "prop_ID"));
    assert_eq!(
        kind,
        DeckErrorKind::DuplicateId {
            what: "property",
            id: 1,
            first_line: 1
        }
    );
}

#[test]
fn error_function_abscissas_not_increasing() {
    let text = format!(
        "/FUNCT/1\nf\n{}{}\n{}{}{}{}\n",
        r(0),
        r(0),
        r(1),
        r(1),
        r(1),
        r(2)
    );
    let (line, field, _) = error_of(&text);
    assert_eq!((line, field.as_str()), (4, "X"));
    let (line, field, kind) = error_of("/FUNCT/1\nno points\n");
    assert_eq!((line, field.as_str()), (1, "X"));
    assert!(matches!(kind, DeckErrorKind::MissingCard { .. }));
}

/// A `/FUNCT` of one point (OpenRadioss warns, message 1874) was read as the constant `Y`:
/// a spring `(0.1, 5)` held 5 N·m at every angle. Refused at the point's line, saying that
/// a constant is two points with the same value; two equal `Y` are that constant.
#[test]
fn error_function_of_one_point() {
    let text = format!("/FUNCT/7\none point\n\n{}{}\n", r(0.1), r(5.0));
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (4, "X"));
    assert_eq!(
        kind.to_string(),
        "invalid curve: 1 point: expected at least 2 points (a constant is two points with the \
         same value)"
    );
    let flat = format!(
        "/FUNCT/7\nconstant\n{}{}{}{}\n",
        r(0.0),
        r(5.0),
        r(1.0),
        r(5.0)
    );
    let deck = RadiossDeck::from_str(&flat, "flat.rad").unwrap();
    let c = &deck.functions[&7].curve;
    assert_eq!((c.value(-2.0), c.value(3.0)), (5.0, 5.0));
}

#[test]
fn error_unknown_unit_name() {
    let text = format!("/UNIT/1\nu\n{}{}{}\n", r("kg"), r("furlong"), r("s"));
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (3, "L_unit"));
    assert!(matches!(
        kind,
        DeckErrorKind::UnknownUnit {
            quantity: BaseQuantity::Length,
            ..
        }
    ));
}

#[test]
fn error_degenerate_skew_and_negative_delay() {
    let text = format!(
        "/SKEW/FIX/1\ns\n{}\n{}{}\n{}{}\n",
        r(0),
        r(0),
        r(1),
        r(0),
        r(-3)
    );
    let (line, field, _) = error_of(&text);
    assert_eq!((line, field.as_str()), (5, "X2"));
    let (line, field, _) = error_of(&format!("/SKEW/FIX/1\ns\n{}\n", r(0)));
    assert_eq!((line, field.as_str()), (1, "X1"));
    let (line, field, _) = error_of(&format!("/SENSOR/TIME/1\ns\n{}\n", r(-1)));
    assert_eq!((line, field.as_str()), (3, "Tdelay"));
}

#[test]
fn error_file_that_cannot_be_read() {
    let e = RadiossDeck::from_file(asset("no_such_deck.rad")).unwrap_err();
    assert_eq!(e.line, 0);
    assert!(e.file.ends_with("no_such_deck.rad"));
    assert!(matches!(*e.kind, DeckErrorKind::Io(_)));
}

// ---------------------------------------------------------------------------------------
// No panic on any input
// ---------------------------------------------------------------------------------------

fn seeds() -> [String; 2] {
    [
        std::fs::read_to_string(asset("revolute_stop.rad")).unwrap(),
        std::fs::read_to_string(asset("translational_stops.rad")).unwrap(),
    ]
}

#[derive(Debug, Clone)]
enum Edit {
    DeleteLine(usize),
    ReplaceChar(usize, usize, char),
    Truncate(usize, usize),
    DuplicateLine(usize),
    InsertLine(usize, String),
}

fn edit() -> impl Strategy<Value = Edit> {
    let fragment = prop_oneof![
        Just("/PROP/TYPE45/3/2".to_string()),
        Just("/FUNCT/1".to_string()),
        Just("/UNIT/2".to_string()),
        Just("/SKEW/FIX/1".to_string()),
        Just("/SENSOR/TIME/1".to_string()),
        Just("/END".to_string()),
        Just("#ENDDATA".to_string()),
        "[ 0-9.eEdD+-]{0,90}",
        any::<String>(),
    ];
    prop_oneof![
        any::<usize>().prop_map(Edit::DeleteLine),
        (any::<usize>(), any::<usize>(), any::<char>())
            .prop_map(|(l, c, ch)| Edit::ReplaceChar(l, c, ch)),
        (any::<usize>(), 0usize..100).prop_map(|(l, c)| Edit::Truncate(l, c)),
        any::<usize>().prop_map(Edit::DuplicateLine),
        (any::<usize>(), fragment).prop_map(|(l, s)| Edit::InsertLine(l, s)),
    ]
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    for e in edits {
        let n = lines.len().max(1);
        match e {
            Edit::DeleteLine(l) if !lines.is_empty() => {
                lines.remove(l % n);
            }
            Edit::ReplaceChar(l, c, ch) if !lines.is_empty() => {
                let line = &mut lines[l % n];
                let mut chars: Vec<char> = line.chars().collect();
                if !chars.is_empty() {
                    let k = c % chars.len();
                    chars[k] = *ch;
                    *line = chars.into_iter().collect();
                }
            }
            Edit::Truncate(l, c) if !lines.is_empty() => {
                let line = &mut lines[l % n];
                *line = line.chars().take(*c).collect();
            }
            Edit::DuplicateLine(l) if !lines.is_empty() => {
                let copy = lines[l % n].clone();
                lines.insert(l % n, copy);
            }
            Edit::InsertLine(l, s) => lines.insert(l % (lines.len() + 1), s.clone()),
            _ => {}
        }
    }
    lines.join("\n")
}

fn check_no_panic(text: &str) -> Result<RadiossDeck, ()> {
    match RadiossDeck::from_str(text, "fuzz.rad") {
        Ok(deck) => {
            // Whatever parsed is valid, in SI too.
            for e in deck.properties.values() {
                assert!(e.property.validate().is_ok());
                assert!(e.property_si.validate().is_ok());
            }
            Ok(deck)
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
            Err(())
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn no_panic_on_arbitrary_text(text in any::<String>(), multi in "(?s).{0,400}") {
        let _ = check_no_panic(&text);
        let _ = check_no_panic(&multi);
        let _ = check_no_panic(&format!("/PROP/TYPE45/1\n{multi}"));
    }

    #[test]
    fn no_panic_on_deck_like_text(
        lines in proptest::collection::vec(
            prop_oneof![
                Just("/PROP/TYPE45/1/1".to_string()),
                Just("/PROP/KJOINT2/2".to_string()),
                Just("/FUNCT/1".to_string()),
                Just("/UNIT/1".to_string()),
                Just("/SKEW/FIX/1/1".to_string()),
                Just("/SENSOR/TIME/1".to_string()),
                Just("/SKEW/MOV/2".to_string()),
                "[ 0-9.eEdD+-]{0,100}",
                "[ a-zA-Z0-9µé日/#$.+-]{0,100}",
            ],
            0..30,
        )
    ) {
        let _ = check_no_panic(&lines.join("\n"));
    }

    #[test]
    fn no_panic_on_mutated_seed_decks(
        which in 0usize..2,
        edits in proptest::collection::vec(edit(), 0..8),
    ) {
        let text = apply(&seeds()[which], &edits);
        let _ = check_no_panic(&text);
    }
}

#[test]
fn unmutated_seeds_pass_the_fuzz_check() {
    for s in seeds() {
        assert!(check_no_panic(&apply(&s, &[])).is_ok());
    }
}

/// Issue 12, item 9: `kjoint check` prints a curve's points (it printed "curve of 3
/// points") and large or small numbers in exponent form (1e300 was printed as 301 digits).
#[test]
fn check_command_prints_curve_points_and_compact_numbers() {
    let text = deck(&[
        "/PROP/TYPE45/1".into(),
        "hinge".into(),
        first_card(2, "0", "0", "0", 0),
        k_card("2", 7, "0", "0", 0),
        c_card("0", 0),
        f_card("1e300", "1e-12", 0),
        "/FUNCT/7".into(),
        "moment".into(),
        format!("{}{}", r("0"), r("0")),
        format!("{}{}", r("0.5"), r("10")),
        format!("{}{}", r("1"), r("15")),
    ]);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("kjoint-check");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("curve.rad");
    std::fs::write(&path, text).unwrap();
    let out = common::cli::kjoint_check(&path);
    for line in [
        // with a curve, K is its dimensionless scale (it was printed in N·m/rad)
        "rx: K = 2 (scale) x curve [(0, 0), (0.5, 10), (1, 15)] (rad, N·m);",
        "Kf = 1e300 N·m/rad, FM = 1e-12 N·m",
    ] {
        assert!(out.contains(line), "missing `{line}` in\n{out}");
    }
    assert!(!out.contains("points"), "{out}");
    assert!(out.lines().all(|l| l.len() < 300), "{out}");
}

/// An error inside a block names that block's keyword line, so that in a deck of many
/// properties the user sees which one: here the second of two KJOINT2 properties.
#[test]
fn error_names_its_block() {
    let (k, c, f) = ok_rx();
    let good = prop("1", first_card(2, "0", "0", "0", 0), &[k, c, f]);
    let (k, c, f) = ok_rx();
    let bad = prop("7", first_card(2, "1.0.0", "0", "0", 0), &[k, c, f]);
    let text = deck(&[good, bad].concat());
    let e = RadiossDeck::from_str(&text, "two.rad").unwrap_err();
    assert_eq!((e.line, e.field.as_str()), (9, "Kn")); // its first card
    assert_eq!(e.block, "/PROP/TYPE45/7");
    assert!(
        e.to_string()
            .starts_with("two.rad:9: field `Kn` of /PROP/TYPE45/7: "),
        "{e}"
    );
    // and so do the errors found once the deck is read: a value out of its range
    // (Cr = -1, Kn = -5) and a reference to no block (sens_ID = 4)
    for (kn, cr, sens, field) in [
        ("0", "-1", 0, "Cr"),
        ("-5", "0", 0, "Kn"),
        ("0", "0", 4, "sens_ID"),
    ] {
        let (k, c, f) = ok_rx();
        let good = prop("1", first_card(2, "0", "0", "0", 0), &[k, c, f]);
        let (k, c, f) = ok_rx();
        let bad = prop("7", first_card(2, kn, "0", cr, sens), &[k, c, f]);
        let e = RadiossDeck::from_str(&deck(&[good, bad].concat()), "two.rad").unwrap_err();
        assert_eq!((e.line, e.field.as_str()), (9, field), "{e}");
        assert_eq!(e.block, "/PROP/TYPE45/7", "{e}");
        let head = format!("two.rad:9: field `{field}` of /PROP/TYPE45/7: ");
        assert!(e.to_string().starts_with(&head), "{e}");
    }
}

/// A keyword Radioss does not have was skipped with a notice: `/FUNC/7` (for `/FUNCT/7`) on
/// line 19 left function 7 undefined, and the error came at line 16, the property that
/// referenced it, with no word of line 19. OpenRadioss refuses an unknown keyword; so does
/// the reader, at its line, naming the keyword it most likely means. A Radioss keyword it
/// does not read (`/NODE`) is still skipped with a notice, and a reference to a block of a
/// subtype it does not read names a close one (`/SENSOR/TIM/3`: a misspelt `/SENSOR/TIME`?).
#[test]
fn an_unknown_keyword_is_an_error_at_its_line() {
    let prop = deck(&[
        "/PROP/TYPE45/2".into(),
        "slider curve".into(),
        first_card(6, "0", "0", "0", 0),
        k_card("0", 7, "0", "0", 0),
        c_card("0", 0),
        f_card("0", "0", 0),
    ]);
    let funct = |kw: &str| format!("{kw}\nspring\n{}{}\n{}{}\n", r(0), r(0), r(10), r(200));
    let text = format!("{prop}{}", funct("/FUNC/7"));
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (7, "keyword"));
    assert_eq!(
        kind,
        DeckErrorKind::UnknownKeyword {
            keyword: "/FUNC".into(),
            likely: Some("/FUNCT".into()),
            reason: "not a keyword of Radioss (OpenRadioss refuses it too)".into(),
        }
    );
    let e = RadiossDeck::from_str(&text, "t.rad")
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "t.rad:7: field `keyword` of /FUNC/7: unknown keyword /FUNC (a misspelt /FUNCT?): not \
         a keyword of Radioss (OpenRadioss refuses it too)"
    );
    // one far from every keyword: refused, without a guess
    let (_, _, kind) = error_of(&format!("{prop}{}", funct("/XYZZY/7")));
    assert!(
        matches!(&kind, DeckErrorKind::UnknownKeyword { likely: None, .. }),
        "{kind:?}"
    );
    // a Radioss keyword the reader does not read is skipped, lower case too
    let text = format!("/node\n{}\n{prop}{}", i(1), funct("/FUNCT/7"));
    let d = RadiossDeck::from_str(&text, "t.rad").unwrap();
    assert_eq!(d.notices.len(), 1, "{:?}", d.notices);
    assert!(
        d.notices[0].message.contains("/node skipped"),
        "{:?}",
        d.notices
    );
    // a subtype the reader does not read, close to the one it reads
    let text = format!(
        "{}/SENSOR/TIM/3\nsensor\n{}\n",
        prop.replace(
            &first_card(6, "0", "0", "0", 0),
            &first_card(6, "0", "0", "0", 3)
        ),
        r(1)
    ) + &funct("/FUNCT/7");
    let (line, field, kind) = error_of(&text);
    assert_eq!((line, field.as_str()), (3, "sens_ID"));
    let DeckErrorKind::UnknownReference { note, .. } = kind else {
        panic!("{kind:?}")
    };
    assert!(
        note.contains(
            "/SENSOR/TIM/3 at line 7, which this reader does not support: a misspelt \
                       /SENSOR/TIME?"
        ),
        "{note}"
    );
}

/// `/PROP/TYP45/1` (for `/PROP/TYPE45/1`) was skipped with a notice, and the deck then
/// failed with "no /PROP/TYPE45 (KJOINT2) property", without a line (a Radioss analyst's
/// trial, 2026-12-04). A property keyword of no Radioss type is an error at its line naming
/// `/PROP/TYPE45`; `/PROP/TYPE46` (a type the reader does not read) is still skipped.
#[test]
fn a_misspelt_property_type_is_an_error_at_its_line() {
    let prop = |kw: &str| {
        deck(&[
            kw.into(),
            "slider".into(),
            first_card(6, "0", "0", "0", 0),
            k_card("1000", 0, "0", "0", 0),
            c_card("0", 0),
            f_card("0", "0", 0),
        ])
    };
    let (line, field, kind) = error_of(&format!("/NODE\n{}\n{}", i(1), prop("/PROP/TYP45/1")));
    assert_eq!((line, field.as_str()), (3, "keyword"));
    assert!(
        matches!(&kind, DeckErrorKind::UnknownKeyword { keyword, likely: Some(l), .. }
            if keyword == "/PROP/TYP45" && l == "/PROP/TYPE45"),
        "{kind:?}"
    );
    let text = format!("{}{}", prop("/PROP/TYPE46/2"), prop("/PROP/TYPE45/1"));
    let d = RadiossDeck::from_str(&text, "t.rad").unwrap();
    assert!(d.property(1).is_some());
    assert!(
        d.notices
            .iter()
            .any(|n| n.message.contains("/PROP/TYPE46/2 skipped")),
        "{:?}",
        d.notices
    );
}

/// A revolute joint (Type 2) takes an initial angle about its x axis only: a `Skew_ID2`
/// whose X' leaves Skew_ID1's is an error at the property's first card naming `Skew_ID2`
/// and the angle between the axes. It was read, and the scene then refused the joint
/// naming `world_frame2`, without the deck's line (a Radioss analyst's trial,
/// 2026-12-04). A skew turned about X' alone is read.
#[test]
fn a_revolute_skew2_off_its_x_axis_is_an_error_at_its_line() {
    let text = |about_z: bool| {
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let (y, z) = if about_z {
            ([-s, c, 0.0], [0.0, 0.0, 1.0])
        } else {
            ([0.0, c, s], [0.0, -s, c])
        };
        deck(&[
            skew_cards(1, "world", [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            skew_cards(2, "turned 0.3 rad", y, z),
            "/PROP/TYPE45/5".into(),
            "hinge with skew2".into(),
            format!("{}{}{}", first_card(2, "1e4", "1", "0", 0), i(1), i(2)),
        ])
    };
    let (line, field, kind) = error_of(&text(true));
    assert_eq!((line, field.as_str()), (13, "Skew_ID2"));
    assert!(
        matches!(&kind, DeckErrorKind::InvalidValue { value, expected }
            if value == "2" && expected.contains("Skew_ID1 = 1") && expected.contains("17.1887°")
                && expected.contains("initial angle about X' only")),
        "{kind:?}"
    );
    let d = RadiossDeck::from_str(&text(false), "t.rad").unwrap();
    assert_eq!(d.property(5).unwrap().skew2, Some(2));

    // `kjoint check` prints the skews' axes and the initial angle, and warns of an initial
    // angle beyond the stops (0.3 rad, stops at ±0.2 rad): the stop acts from the start
    let stops = format!(
        "{}{}{}",
        k_card("0", 0, "-0.2", "0.2", 0),
        "\n".to_string() + &c_card("0", 0),
        "\n".to_string() + &f_card("0", "0", 0)
    );
    let path = common::cli::temp_file("skew2-check", "hinge.rad", &(text(false) + &stops + "\n"));
    let out = common::cli::kjoint_check(&path);
    assert!(
        out.contains(
            "Skew_ID2 = 2: X' = [1.000, 0, 0], Y' = [0, 0.9553, 0.2955], Z' = [0, -0.2955, 0.9553]"
        ),
        "{out}"
    );
    assert!(
        out.contains("initial angle about X' (Skew_ID1 to Skew_ID2): θ0 = 0.3000 rad (17.19°)")
            && out.contains("warning: θ0 is beyond the rx stops [-0.2, 0.2] rad"),
        "{out}"
    );
}
