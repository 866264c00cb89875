//! The riser deck reader: the seed's three examples, one test per malformed input, and a
//! no-panic property test.

mod common;

use approx::assert_relative_eq;
use proptest::prelude::*;
use rapier_kjoint::io::riser::{DeckError, DeckErrorKind, RiserDeck};
use rapier_kjoint::law::flex_joint::{FlexJointInput, FlexJointState, FlexMode};

/// The explanation of an unknown index.
const NOTE: &str = " (no such record in the deck; 0 = none)";

fn deck(name: &str) -> String {
    format!("{}/assets/decks/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn example1_classical_multilinear() {
    let d = RiserDeck::from_file(deck("flexjoint_example1.dat")).unwrap();
    assert_eq!(d.joints.len(), 1);
    let j = &d.joints[0];
    assert_eq!((j.id, j.origin_node, j.end_node), (3, 1, 3));
    assert_eq!((j.ipro, j.imat, j.iprot), (3, 0, 0));
    assert_eq!(j.length, 0.0);
    assert_eq!(j.line, 5);
    assert_eq!(j.law.mode(), FlexMode::Classical);
    let c = j.law.bending.as_ref().unwrap();
    let pts: Vec<_> = c.points().collect();
    assert_eq!(pts, vec![(0.0, 0.0), (0.0174533, 1e9)]);
    assert!(j.law.torsion.is_none() && j.law.dynamic.is_none());
    // Linear law on the total angle: pure torsion of 0.5° gives 0.5e9 N·m.
    let mut st = FlexJointState::default();
    let o = j.law.evaluate(
        &mut st,
        &FlexJointInput {
            theta: nalgebra::Vector3::new(0.0174533 / 2.0, 0.0, 0.0),
            ..Default::default()
        },
    );
    assert_relative_eq!(o.torsion_moment, 0.5e9, max_relative = 1e-9);
    assert!(d.notices.is_empty());
}

#[test]
fn example2_static_multilinear_dynamic_bilinear() {
    let d = RiserDeck::from_file(deck("flexjoint_example2.dat")).unwrap();
    assert_eq!(d.joints.len(), 1);
    let j = &d.joints[0];
    assert_eq!((j.id, j.origin_node, j.end_node), (3, 1, 3));
    assert_eq!((j.ipro, j.imat, j.iprot), (3, 2, 0));
    assert_eq!(j.law.mode(), FlexMode::Dynamic);
    let pts: Vec<_> = j.law.bending.as_ref().unwrap().points().collect();
    assert_eq!(
        pts,
        vec![(0.0, 0.0), (0.00872665, 25000.0), (0.0174533, 35000.0)]
    );
    assert!(j.law.torsion.is_none());
    let p = j.law.dynamic.unwrap();
    assert_eq!(p.torsion_stiffness, 5.72958e8);
    assert_eq!(p.iflag, 1);
    assert_eq!(p.kdyn_ini, 4.0107e6);
    assert_eq!(p.kdyn_lim, 1.718873e6);
    assert_eq!(p.angle_lim, 1.74533e-3);
    assert_eq!(p.teta, 0.0);
    assert_eq!(p.torsion_damping, 3.008e6);
    // 70 kN·m/deg and 30 kN·m/deg, 0.1 deg.
    assert_relative_eq!(
        p.kdyn_ini * 1f64.to_radians(),
        70_000.0,
        max_relative = 1e-3
    );
    assert_relative_eq!(
        p.kdyn_lim * 1f64.to_radians(),
        30_000.0,
        max_relative = 1e-3
    );
    assert_relative_eq!(p.angle_lim.to_degrees(), 0.1, max_relative = 1e-4);
    assert_eq!(d.flex_props[&2].line, 7);
    assert_eq!(d.spring_laws[&3].line, 3);
}

#[test]
fn example3_bilinear_in_both_phases() {
    let d = RiserDeck::from_file(deck("flexjoint_example3.dat")).unwrap();
    let j = &d.joints[0];
    assert_eq!((j.id, j.origin_node, j.end_node), (3, 1, 3));
    assert_eq!((j.ipro, j.imat, j.iprot), (0, 2, 0));
    assert_eq!(j.law.mode(), FlexMode::Dynamic);
    assert!(j.law.bending.is_none() && j.law.torsion.is_none());
    let p = j.law.dynamic.unwrap();
    assert_eq!(p.torsion_stiffness, 5.72958e8);
    assert_eq!(p.kdyn_ini, 4.0107e6);
    assert!(d.spring_laws.is_empty());
}

fn parse_err(text: &str) -> DeckError {
    RiserDeck::from_str(text, "bad.dat").expect_err("the deck should be rejected")
}

fn check(text: &str, line: usize, field: &str) -> DeckErrorKind {
    let e = parse_err(text);
    assert_eq!(e.line, line, "{e}");
    assert_eq!(e.field, field, "{e}");
    let msg = e.to_string();
    assert!(msg.starts_with(&format!("bad.dat:{line}:")), "{msg}");
    assert!(msg.contains(field), "{msg}");
    // and the keyword of the record's block
    assert!(e.block.starts_with('*') && msg.contains(&e.block), "{msg}");
    *e.kind
}

#[test]
fn unknown_ipro() {
    let k = check(
        "*SPRINGPRO\n3 2 0 0 1 10\n*FLEXJOINT\n3 1 3 4 0 0.\n",
        4,
        "IPRO",
    );
    assert_eq!(
        k,
        DeckErrorKind::UnknownReference {
            what: "*SPRINGPRO law",
            id: 4,
            note: NOTE.into()
        }
    );
}

#[test]
fn unknown_imat() {
    let k = check(
        "*SPRINGPRO\n3 2 0 0 1 10\n*FLEXJOINT\nC comment\n3 1 3 3 7 0.\n",
        5,
        "IMAT",
    );
    assert_eq!(
        k,
        DeckErrorKind::UnknownReference {
            what: "*FLEXPROADD record",
            id: 7,
            note: NOTE.into()
        }
    );
}

#[test]
fn unknown_iprot() {
    let k = check(
        "*SPRINGPRO\n3 2 0 0 1 10\n\n*FLEXJOINT\n3 1 3 3 0 0. 9\n",
        5,
        "IPROT",
    );
    assert_eq!(
        k,
        DeckErrorKind::UnknownReference {
            what: "*SPRINGPRO law",
            id: 9,
            note: NOTE.into()
        }
    );
}

#[test]
fn no_law_at_all() {
    let k = check("*FLEXJOINT\n3 1 3 0 0 0.\n", 2, "IPRO");
    assert!(matches!(k, DeckErrorKind::Property(_)));
}

/// A `*SPRINGPRO` law of one pair was read as a constant (its one moment at every angle);
/// of none, as before, refused: both at `NPAIRS`, saying that a constant is two pairs.
#[test]
fn fewer_than_two_pairs() {
    for (text, n) in [("*SPRINGPRO\n3 1 0 0\n", "1"), ("*SPRINGPRO\n3 0\n", "0")] {
        let k = check(text, 2, "NPAIRS");
        assert_eq!(
            k,
            DeckErrorKind::InvalidValue {
                value: n.into(),
                expected: "at least 2 (angle, moment) pairs (a constant is two pairs with the \
                           same moment)"
                    .into()
            }
        );
    }
}

#[test]
fn odd_number_of_pair_values() {
    let k = check("*SPRINGPRO\n3 2 0 0 1\n", 2, "NPAIRS");
    assert_eq!(
        k,
        DeckErrorKind::PairCount {
            npairs: 2,
            values: 3
        }
    );
}

#[test]
fn npairs_not_matching_count() {
    let k = check("c header\n*SPRINGPRO\n3 3 0 0 1 10\n", 3, "NPAIRS");
    assert_eq!(
        k,
        DeckErrorKind::PairCount {
            npairs: 3,
            values: 4
        }
    );
}

#[test]
fn unsupported_iflag() {
    let k = check(
        "*FLEXPROADD\n2 5.72958e8 2 4.0107e6 1.718873e6 1.74533e-3 0 3.008e6\n",
        2,
        "IFLAG",
    );
    assert_eq!(k, DeckErrorKind::UnsupportedIflag(2));
}

#[test]
fn number_that_does_not_parse() {
    let k = check("*SPRINGPRO\n3 2 0 0 1.0x 10\n", 2, "x2");
    assert!(matches!(k, DeckErrorKind::InvalidNumber { .. }));
    let k = check("*FLEXJOINT\n3 1 three 3 0 0.\n", 2, "JE");
    assert!(matches!(k, DeckErrorKind::InvalidNumber { .. }));
    let k = check("*FLEXJOINT\n3 1 3 2.5 0 0.\n", 2, "IPRO");
    assert!(matches!(
        k,
        DeckErrorKind::InvalidNumber {
            expected: "an integer",
            ..
        }
    ));
    let k = check("*FLEXJOINT\n-3 1 3 3 0 0.\n", 2, "NEL");
    assert!(matches!(
        k,
        DeckErrorKind::InvalidNumber {
            expected: "a non-negative integer",
            ..
        }
    ));
}

#[test]
fn nan_and_infinity() {
    let k = check(
        "*FLEXPROADD\n2 5.72958e8 1 NaN 1.718873e6 1.74533e-3 0 3.008e6\n",
        2,
        "Kdyn_ini",
    );
    assert!(matches!(k, DeckErrorKind::NotFinite { .. }));
    let k = check("*SPRINGPRO\n3 2 0 0 inf 10\n", 2, "x2");
    assert!(matches!(k, DeckErrorKind::NotFinite { .. }));
    let k = check("*FLEXJOINT\n3 1 3 3 0 1e999\n", 2, "LENGTH");
    assert!(matches!(k, DeckErrorKind::NotFinite { .. }));
}

#[test]
fn missing_and_extra_fields() {
    let k = check("*FLEXJOINT\n3 1 3 3 0\n", 2, "LENGTH");
    assert_eq!(k, DeckErrorKind::MissingField);
    let k = check("*FLEXPROADD\n2 5.7e8 1 4e6 1.7e6 1.7e-3 0\n", 2, "CP");
    assert_eq!(k, DeckErrorKind::MissingField);
    let k = check("*FLEXJOINT\n3 1 3 3 0 0. 0 5\n", 2, "(end of record)");
    assert_eq!(k, DeckErrorKind::TooManyFields { found: 8, max: 7 });
}

#[test]
fn out_of_range_values() {
    // Kdyn_lim > Kdyn_ini.
    check("*FLEXPROADD\n2 5.7e8 1 4e6 5e6 1.7e-3 0 0\n", 2, "Kdyn_lim");
    // A yield moment Kdyn_ini·Angle_lim beyond f64 (found by fuzzing flexjoint_example2.dat:
    // `kjoint check` printed `yield moment inf N·m` and exited 0).
    check(
        "*FLEXPROADD\n2 5.7e8 1 4e6 1.7e6 1e308 0 0\n",
        2,
        "Angle_lim",
    );
    let e = parse_err("*FLEXPROADD\n2 5.7e8 1 1e308 1.7e6 4 0 0\n");
    assert_eq!(e.field, "Kdyn_ini", "{e}");
    assert!(
        e.to_string()
            .contains("yield moment My = Kdyn_ini·Angle_lim = 1e308·4e0 is finite"),
        "{e}"
    );
    // Angles not increasing.
    check("*SPRINGPRO\n3 3 0 0 1 10 0.5 20\n", 2, "pairs");
    // Law not through the origin, reported at the law's own line (it was reported at the
    // *FLEXJOINT that reads it, field IPRO: the user looked for the error on the wrong line)
    let k = check(
        "*SPRINGPRO\n3 2 0 5 1 10\n*FLEXJOINT\n3 1 3 3 0 0.\n",
        2,
        "pairs",
    );
    assert!(
        matches!(&k, DeckErrorKind::InvalidValue { value, .. } if value == "M(0) = 5"),
        "{k:?}"
    );
}

/// A law whose moment falls is a negative stiffness: refused at the `*SPRINGPRO` line, on
/// the `y` of the pair where it falls (`kjoint check` said `ok` to both decks below, and
/// `kjoint run` stopped later with "the joint system is not positive definite", or not at
/// all when the bodies' inertia outweighed the negative stiffness).
#[test]
fn falling_laws_are_negative_stiffness() {
    // all negative: M(1°) = -1e9 N·m
    let k = check(
        "*SPRINGPRO\n3 2 0 0 0.0174533 -1e9\n*FLEXJOINT\n3 1 3 3 0 0.\n",
        2,
        "y2",
    );
    assert!(
        matches!(&k, DeckErrorKind::InvalidValue { value, expected }
            if value == "-1000000000" && expected.contains("negative stiffness")),
        "{k:?}"
    );
    // softening: 25 kN·m at 0.5°, then 20 kN·m at 1°
    let e = parse_err("c softening\n*SPRINGPRO\n3 3 0 0 0.00872665 25000 0.0174533 20000\n");
    assert_eq!((e.line, e.field.as_str()), (3, "y3"), "{e}");
    assert!(e.to_string().contains("a moment >= y2 = 25000"), "{e}");
    // a torsion law falling, given to the law directly (scene files, the API)
    use rapier_kjoint::law::{Curve, FlexJointLaw};
    let bending = Curve::new([(0.0, 0.0), (0.01, 100.0)]).unwrap();
    let torsion = Curve::new([(-1.0, -5.0), (0.0, 0.0), (1.0, -5.0)]).unwrap();
    let err = FlexJointLaw::new(Some(bending.clone()), Some(torsion), None).unwrap_err();
    assert!(err.to_string().contains("IPROT"), "{err}");
    // flat and rising laws stay accepted
    let flat = Curve::new([(0.0, 0.0), (0.01, 100.0), (0.02, 100.0)]).unwrap();
    assert!(FlexJointLaw::new(Some(flat), None, None).is_ok());
    assert!(FlexJointLaw::new(Some(bending), None, None).is_ok());
}

#[test]
fn duplicate_ids() {
    let k = check("*SPRINGPRO\n3 2 0 0 1 10\n3 2 0 0 1 20\n", 3, "INDEX");
    assert_eq!(
        k,
        DeckErrorKind::DuplicateId {
            what: "*SPRINGPRO law",
            id: 3,
            first_line: 2
        }
    );
    check(
        "*SPRINGPRO\n3 2 0 0 1 10\n*FLEXJOINT\n1 1 2 3 0 0\n1 2 3 3 0 0\n",
        5,
        "NEL",
    );
}

#[test]
fn skipped_keywords_teta_fortran_reals_and_any_order() {
    let text = "\
*NODE
1 0 0 0
*FLEXJOINT
  5 10 11 3 2 12.5D0 4
*SPRINGPRO
3 2 0 0 1.0D-2 1.0D+4
4 2 0. 0. 1. 2.
*FLEXPROADD
2 1e8 1. 4e6 1e6 1e-3 0.3 0
*END
";
    let d = RiserDeck::from_str(text, "mixed.dat").unwrap();
    let j = &d.joints[0];
    assert_eq!(
        (j.id, j.origin_node, j.end_node, j.ipro, j.imat, j.iprot),
        (5, 10, 11, 3, 2, 4)
    );
    assert_eq!(j.length, 12.5);
    assert_eq!(j.law.bending.as_ref().unwrap().value(1e-2), 1e4);
    assert_eq!(j.law.torsion.as_ref().unwrap().value(0.5), 1.0);
    let lines: Vec<_> = d.notices.iter().map(|n| n.line).collect();
    assert_eq!(lines, vec![1, 4, 9, 10], "{:?}", d.notices);
    assert!(d.notices[2].message.contains("Teta"));
    // (a notice, printed as one: `notice, file:line: *FLEXPROADD …`, not "notice, …:
    // warning: …", the double label a riser engineer's trial read, 2026-12-04)
    assert!(
        d.notices[2].message.starts_with("*FLEXPROADD"),
        "{:?}",
        d.notices[2]
    );
    assert!(d.notices[1].message.contains("Ktor"));
}

#[test]
fn missing_file_is_an_io_error() {
    let e = RiserDeck::from_file("/nonexistent/deck.dat").unwrap_err();
    assert!(matches!(*e.kind, DeckErrorKind::Io(_)));
    assert_eq!(e.line, 0);
}

fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("*FLEXJOINT".to_string()),
        Just("*SPRINGPRO".to_string()),
        Just("*FLEXPROADD".to_string()),
        Just("*OTHER".to_string()),
        Just("C".to_string()),
        Just("\n".to_string()),
        Just("nan".to_string()),
        Just("-inf".to_string()),
        Just("1e999".to_string()),
        Just("1.5D3".to_string()),
        Just("18446744073709551616".to_string()),
        (0u8..6).prop_map(|i| i.to_string()),
        any::<i64>().prop_map(|i| i.to_string()),
        any::<f64>().prop_map(|f| f.to_string()),
        "[ -~]{0,6}",
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn never_panics_on_arbitrary_text(s in "\\PC*") {
        let _ = RiserDeck::from_str(&s, "fuzz.dat");
    }

    #[test]
    fn never_panics_on_keyword_soup(tokens in prop::collection::vec(token(), 0..80)) {
        let text = tokens.join(" ");
        let text = text.replace(" \n ", "\n");
        if let Err(e) = RiserDeck::from_str(&text, "fuzz.dat") {
            let _ = e.to_string();
        }
    }

    #[test]
    fn well_formed_decks_parse(
        pairs in prop::collection::vec((1e-4f64..1.0, 0.0f64..1e6), 1..6),
        ipro in 0u64..2,
        iprot in 0u64..2,
    ) {
        let mut x = 0.0;
        let mut y = 0.0;
        let mut vals = vec!["0".to_string(), "0".to_string()];
        for (dx, dy) in &pairs {
            x += dx;
            y += dy;
            vals.push(format!("{x:e}"));
            vals.push(format!("{y:e}"));
        }
        let text = format!(
            "*SPRINGPRO\n1 {} {}\n*FLEXPROADD\n1 1e8 1 4e6 1e6 1e-3 0 0\n*FLEXJOINT\n7 1 2 {ipro} 1 0. {iprot}\n",
            pairs.len() + 1,
            vals.join(" ")
        );
        let d = RiserDeck::from_str(&text, "ok.dat").unwrap();
        prop_assert_eq!(d.joints.len(), 1);
        prop_assert_eq!(d.joints[0].law.bending.is_some(), ipro == 1);
        prop_assert_eq!(d.joints[0].law.torsion.is_some(), iprot == 1);
    }
}

#[test]
fn iflag_zero_or_fractional_and_forward_references() {
    // IFLAG 0 (no law) and 1.5 (not an integer) name the line and the field.
    let k = check(
        "c\n*FLEXPROADD\n2 5.7e8 0 4.0e6 1.7e6 1.7e-3 0 3.0e6\n",
        3,
        "IFLAG",
    );
    assert_eq!(k, DeckErrorKind::UnsupportedIflag(0));
    check(
        "*FLEXPROADD\n2 5.7e8 1.5 4.0e6 1.7e6 1.7e-3 0 3.0e6\n",
        2,
        "IFLAG",
    );
    // An unknown index in a *FLEXJOINT that comes before the tables is resolved at the end
    // of the deck and still names the *FLEXJOINT line.
    let k = check(
        "*FLEXJOINT\n3 1 3 3 5 0.\n*SPRINGPRO\n3 2 0 0 1 10\n*FLEXPROADD\n2 5.7e8 1 4.0e6 1.7e6 1.7e-3 0 3.0e6\n",
        2,
        "IMAT",
    );
    assert_eq!(
        k,
        DeckErrorKind::UnknownReference {
            what: "*FLEXPROADD record",
            id: 5,
            note: NOTE.into()
        }
    );
}

/// What `kjoint check` says of a dynamic flex joint's bending and torsion is what the law
/// does (docs/flex_joint.md §2, §4): without a bending law (IPRO = 0, example 3) the
/// hysteretic law acts in both phases (it said "quasi-static bending, then dynamic
/// bilinear hysteretic"), and `Ktor` beside a torsion law (IPROT) is ignored (it printed
/// `Ktor` as if it acted).
#[test]
fn check_describes_the_dynamic_modes_as_they_act() {
    let three = common::cli::kjoint_check(std::path::Path::new(&deck("flexjoint_example3.dat")));
    assert!(
        three.contains("flex joint: bilinear hysteretic bending, restarted from the state")
            && three.contains("Ktor = 572958000 N·m/rad, Kdyn_ini"),
        "{three}"
    );
    let two = common::cli::kjoint_check(std::path::Path::new(&deck("flexjoint_example2.dat")));
    assert!(
        two.contains("flex joint: quasi-static bending (IPRO), then dynamic bilinear hysteretic"),
        "{two}"
    );
    // example 2 with a torsion law (IPROT = 3, the bending law's table)
    let text = std::fs::read_to_string(deck("flexjoint_example2.dat"))
        .unwrap()
        .replace("3 1 3 3 2 0.", "3 1 3 3 2 0. 3");
    let path = common::cli::temp_file("riser-check", "iprot.dat", &text);
    let iprot = common::cli::kjoint_check(&path);
    assert!(
        iprot.contains("torsion law (IPROT)")
            && iprot.contains("Ktor = 572958000 N·m/rad (ignored: the torsion law IPROT)"),
        "{iprot}"
    );
}

/// A keyword close to one the reader reads was skipped with a notice: `*FLEXJOINTS`'s
/// element disappeared from the run (`check` said ok), and `*FLEXPROAD`'s record was
/// reported missing at the `*FLEXJOINT` that referenced it, with no word of line 3. Such a
/// keyword is now an error at its own line naming the keyword it most likely means.
#[test]
fn a_keyword_close_to_a_known_one_is_an_error_at_its_line() {
    for (text, line, written, likely) in [
        (
            "*SPRINGPRO\n3 2 0 0 0.0087 25000\n*FLEXPROAD\n2 5e8 1 4e6 1e6 1e-3 0 3e6\n\
             *FLEXJOINT\n3 1 3 3 2 0.\n",
            3,
            "*FLEXPROAD",
            "*FLEXPROADD",
        ),
        (
            "*SPRINGPRO\n3 2 0 0 0.0087 25000\n*FLEXJOINTS\n3 1 3 3 0 0.\n*FLEXJOINT\n4 1 3 3 \
             0 0.\n",
            3,
            "*FLEXJOINTS",
            "*FLEXJOINT",
        ),
        (
            "*springproo\n3 2 0 0 1 10\n",
            1,
            "*SPRINGPROO",
            "*SPRINGPRO",
        ),
    ] {
        let e = parse_err(text);
        assert_eq!((e.line, e.field.as_str()), (line, "keyword"), "{e}");
        let DeckErrorKind::UnknownKeyword {
            keyword, likely: l, ..
        } = &*e.kind
        else {
            panic!("{e}")
        };
        assert_eq!((keyword.as_str(), l.as_deref()), (written, Some(likely)));
        assert!(
            e.to_string().starts_with(&format!(
                "bad.dat:{line}: field `keyword`: unknown keyword {written} (a misspelt {likely}?)"
            )),
            "{e}"
        );
    }
}

/// A keyword far from the three is another program's, skipped with a notice; when a law or
/// record is then missing, the error names the skipped keywords as the likely cause (with
/// the question for one that may be the missing keyword misspelt).
#[test]
fn a_missing_law_names_the_keywords_skipped_as_unknown() {
    let e = parse_err("*SPRING\n3 2 0 0 1 10\n*FLEXJOINT\n3 1 3 3 0 0.\n");
    assert_eq!((e.line, e.field.as_str()), (4, "IPRO"), "{e}");
    assert_eq!(
        *e.kind,
        DeckErrorKind::UnknownReference {
            what: "*SPRINGPRO law",
            id: 3,
            note: " (no such record in the deck; 0 = none; the deck skipped *SPRING at line 1 \
                   as an unknown keyword: a misspelt *SPRINGPRO?)"
                .into()
        }
    );
    let e = parse_err("*LAW\n3 2 0 0 1 10\n*NODES\n1 2\n*FLEXJOINT\n3 1 3 3 0 0.\n");
    assert!(
        e.to_string().ends_with(
            "*SPRINGPRO law 3 does not exist (no such record in the deck; 0 = none; the deck \
             skipped *LAW at line 1 and *NODES at line 3 as unknown keywords)"
        ),
        "{e}"
    );
    // the same deck with the law under its keyword reads, the other keyword skipped
    let d = RiserDeck::from_str(
        "*NODES\n1 2\n*SPRINGPRO\n3 2 0 0 1 10\n*FLEXJOINT\n3 1 3 3 0 0.\n",
        "ok.dat",
    )
    .unwrap();
    assert_eq!(d.joints.len(), 1);
    assert_eq!(d.notices.len(), 1, "{:?}", d.notices);
    assert!(d.notices[0].message.contains("*NODES"), "{:?}", d.notices);
}

/// A bending law with points at negative angles gets a notice at the `*FLEXJOINT` that
/// reads it: the bending moment is a law of the bending angle's magnitude, and those points
/// are never read (accepted without a word before; a riser engineer's trial, 2026-12-04).
/// The same table as a torsion law (odd or as written) gives none.
#[test]
fn a_bending_law_at_negative_angles_is_noticed() {
    let text = "*SPRINGPRO\n3 3 -0.01 -1e4 0 0 0.01 1e4\n*FLEXJOINT\n5 1 2 3 0 1.0 3\n";
    let d = RiserDeck::from_str(text, "neg.dat").unwrap();
    assert_eq!(d.notices.len(), 1, "{:?}", d.notices);
    let n = &d.notices[0];
    assert_eq!(n.line, 4);
    assert!(
        n.message
            .contains("*FLEXJOINT 5 (IPRO = 3, IMAT = 0, IPROT = 3): the bending law has points at negative angles (from -0.01 rad)"),
        "{n:?}"
    );
    // (the joint is as read: its positive half is the law)
    assert_eq!(d.joints[0].law.bending.as_ref().unwrap().value(0.01), 1e4);
    let torsion_only = "*SPRINGPRO\n3 3 -0.01 -1e4 0 0 0.01 1e4\n*SPRINGPRO\n4 2 0 0 0.01 1e4\n*FLEXJOINT\n5 1 2 4 0 1.0 3\n";
    let d = RiserDeck::from_str(torsion_only, "neg_torsion.dat").unwrap();
    assert!(d.notices.is_empty(), "{:?}", d.notices);
}

/// A valid law the deck most likely did not mean is noticed at its `*FLEXJOINT`: a
/// dynamic record with `Ktor = 0` and no torsion law (IPROT) leaves the riser free about
/// its axis but for `CP`, and a bending law of zero moment carries nothing (both accepted
/// without a word before; an offshore engineer's trial, 2026-12-06). With a torsion law,
/// or `Ktor > 0`, no notice.
#[test]
fn a_free_torsion_or_a_zero_bending_law_is_noticed() {
    let deck = |bending: &str, ktor: &str, iprot: &str| {
        format!(
            "*SPRINGPRO\n3 {bending}\n*SPRINGPRO\n4 2 0 0 0.01 1e4\n*FLEXPROADD\n2 {ktor} 1 4.0107e6 \
             1.718873e6 1.74533e-3 0 3.008e6\n*FLEXJOINT\n5 1 2 3 2 1.0 {iprot}\n"
        )
    };
    let notices = |text: String| {
        let d = RiserDeck::from_str(&text, "free.dat").unwrap();
        d.notices
            .iter()
            .map(|n| n.message.clone())
            .collect::<Vec<_>>()
    };
    let free = notices(deck("2 0 0 0.01 25000", "0", "0"));
    assert_eq!(free.len(), 1, "{free:?}");
    assert!(
        free[0].contains(
            "*FLEXJOINT 5 (IPRO = 3, IMAT = 2, IPROT = 0): no torsion law and a torsion \
             stiffness Ktor of 0: the flex joint puts no stiffness on the riser's turn about \
             its axis, only its torsion damping CP = 3008000 N·m·s/rad (SI)"
        ),
        "{free:?}"
    );
    let zero = notices(deck("2 0 0 0.01 0", "5.72958e8", "0"));
    assert_eq!(zero.len(), 1, "{zero:?}");
    assert!(
        zero[0].contains(
            "the bending law is zero at every angle: the joint carries no bending moment in \
             its quasi-static phase"
        ),
        "{zero:?}"
    );
    assert!(notices(deck("2 0 0 0.01 25000", "0", "4")).is_empty());
    assert!(notices(deck("2 0 0 0.01 25000", "5.72958e8", "0")).is_empty());
}

/// A deck whose `*SPRINGPRO` keyword line is missing: its law's data, before any keyword,
/// are skipped (a notice), and the `*FLEXJOINT` that reads the law says so where it names
/// the missing law ("law 3 does not exist" alone before; a riser engineer's trial,
/// 2026-12-04).
#[test]
fn a_missing_law_names_the_data_skipped_before_any_keyword() {
    let e = parse_err("3 2 0 0 0.01 1e4\n*FLEXJOINT\n5 1 2 3 0 1.0\n");
    let text = e.to_string();
    assert_eq!(e.line, 3, "{text}");
    assert!(
        text.contains("*SPRINGPRO law 3 does not exist")
            && text.contains(
                "the deck skipped its data from line 1, before any keyword: a missing \
                 *SPRINGPRO line?"
            ),
        "{text}"
    );
}
