//! The URDF loader does not panic on user input: numeric attributes of the shipped arm are
//! replaced by arbitrary numbers and words, joint types and link references are swapped,
//! text is cut; every result is `Ok` or a typed error, and a loaded robot steps one frame
//! (an error is allowed, a panic is not). `PROPTEST_CASES=10000` runs it longer.

mod common;

use proptest::prelude::*;
use rapier_kjoint::io::urdf::UrdfOptions;
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::KjointSet;

const ARM: &str = include_str!("../assets/urdf/arm.urdf");

fn run(text: &str) {
    let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
    let mut joints = KjointSet::new();
    if common::robot::insert_urdf_str(
        text,
        "fuzz.urdf",
        &mut world,
        &mut joints,
        &UrdfOptions::default(),
    )
    .is_ok()
    {
        let _ = joints.step(&mut world, 1.0 / 60.0);
    }
}

/// The byte ranges of every quoted attribute value in the arm.
fn attribute_values() -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let b = ARM.as_bytes();
    let mut i = 0;
    while i + 1 < b.len() {
        if b[i] == b'=' && b[i + 1] == b'"' {
            if let Some(len) = ARM[i + 2..].find('"') {
                out.push((i + 2, i + 2 + len));
                i += 2 + len;
            }
        }
        i += 1;
    }
    out
}

fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<f64>().prop_map(|v| v.to_string()),
        (-1e3f64..1e3).prop_map(|v| v.to_string()),
        Just("nan".to_string()),
        Just("-inf".to_string()),
        Just("0 0 0".to_string()),
        Just("1e308 1e308 1e308".to_string()),
        Just("-1 -1 -1".to_string()),
        Just("revolute".to_string()),
        Just("continuous".to_string()),
        Just("prismatic".to_string()),
        Just("fixed".to_string()),
        Just("floating".to_string()),
        Just("planar".to_string()),
        Just("spherical".to_string()),
        Just("base_link".to_string()),
        Just("hand".to_string()),
        Just("upper_arm".to_string()),
        "[ a-z0-9.eE+-]{0,12}",
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn no_panic_on_mutated_attributes(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), value()), 1..6)
    ) {
        let spans = attribute_values();
        let mut chosen: Vec<(usize, usize, String)> = edits
            .into_iter()
            .map(|(i, v)| {
                let (a, b) = spans[i.index(spans.len())];
                (a, b, v)
            })
            .collect();
        chosen.sort_by_key(|c| std::cmp::Reverse(c.0));
        chosen.dedup_by_key(|c| c.0);
        let mut text = ARM.to_string();
        for (a, b, v) in chosen {
            text.replace_range(a..b, &v);
        }
        run(&text);
    }

    #[test]
    fn no_panic_on_cut_text(cut in 0usize..ARM.len(), text in "(?s).{0,200}") {
        let mut c = cut;
        while !ARM.is_char_boundary(c) {
            c -= 1;
        }
        run(&ARM[..c]);
        run(&format!("{}{text}", &ARM[..c]));
        run(&text);
    }
}
