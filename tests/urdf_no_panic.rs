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
        let text = common::fuzz::mutate(ARM, edits);
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

/// Found by fuzzing the shipped URDF files through their scenes: values that are finite as
/// f64 but not in rapier's f32 (an origin or inertia of 1e300: NaN poses and energies, exit
/// 0), sizes that overflow parry's contact queries (a cylinder 1e38 long: a panic in EPA)
/// and a cylinder radius of -0 (parry asserts the sign bit: a panic) are refused at the
/// door, naming the link or joint and the field.
#[test]
fn out_of_range_and_negative_zero_values_are_refused_naming_the_field() {
    // the collision cylinder of the forearm (the first cylinder is its visual)
    let cylinder = r#"<collision><origin xyz="0.15 0 0" rpy="0 1.5707963 0"/><geometry><cylinder radius="0.03" length="0.3"/>"#;
    let cases = [
        (
            cylinder,
            cylinder.replace(r#"radius="0.03""#, r#"radius="-0.0""#),
            "link `forearm` (line 35): invalid collision.geometry.cylinder.radius = -0: expected a size >= 0",
        ),
        (
            cylinder,
            cylinder.replace(r#"length="0.3""#, r#"length="1e38""#),
            "link `forearm` (line 35): invalid collision.geometry.cylinder.length = 1e38: expected a finite \
             number within ±1e12",
        ),
        (
            r#"<origin xyz="0.4 0 0"/>"#,
            r#"<origin xyz="0.4 1e300 0"/>"#.to_string(),
            "joint `elbow` (line 62): invalid origin.xyz = [0.4, 1e300, 0.0]: expected a finite number \
             within ±1e12",
        ),
        (
            r#"<mass value="1.0"/>"#,
            r#"<mass value="1e20"/>"#.to_string(),
            "link `forearm` (line 31): invalid inertial.mass = 1e20",
        ),
        (
            r#"ixx="0.00045""#,
            r#"ixx="1e300""#.to_string(),
            "link `forearm` (line 32): invalid inertial.inertia.ixx = 1e300",
        ),
    ];
    for (from, to, message) in cases {
        assert!(ARM.contains(from), "{from}");
        let text = ARM.replacen(from, &to, 1);
        let (mut world, _) = common::world(Vector::new(0.0, 0.0, -9.81));
        let mut joints = KjointSet::new();
        let e = common::robot::insert_urdf_str(
            &text,
            "fuzz.urdf",
            &mut world,
            &mut joints,
            &UrdfOptions::default(),
        )
        .unwrap_err();
        let s = e.to_string();
        assert!(
            s.starts_with(&format!("fuzz.urdf: {message}")),
            "`{s}` should start with `fuzz.urdf: {message}`"
        );
    }
}
