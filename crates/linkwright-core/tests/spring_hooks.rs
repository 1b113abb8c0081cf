//! Counterbalance springs on printed parts: the parts carry a hook at both ends of every spring, and
//! the fabrication's own checks (computed from the parts' prisms, not from the ordering's reasoning)
//! find each hook at its spring's axis and nothing in the spring's way along the motion.

use linkwright_core::fab::{check, fabricate_design_with_springs, Anchor, FabError, Face, HookRefusal, PrintSettings};
use linkwright_core::geom::Point;
use linkwright_core::hooked::{fabricate_with_springs, Hooked};
use linkwright_core::testbed::{known_scene, Known};
use linkwright_core::{Problem, Silent};

/// Known four-bars and six-bars drawn in millimetres, fabricated with the springs that balance them.
fn hooked() -> Vec<Hooked> {
    let mut out = Vec::new();
    for (kind, seed) in [(Known::chain(1), 3), (Known::chain(1), 7), (Known::chain(2), 5)] {
        let known = known_scene(kind, 3, seed, 100.0).expect("a known scene");
        let problem = Problem::new(&known.scene).expect("a valid scene");
        let design = known.design();
        match fabricate_with_springs(&problem, &design, &PrintSettings::default(), &Silent) {
            Ok(h) => out.push(h),
            Err(e) => println!("{kind} seed {seed}: {e}"),
        }
    }
    out
}

#[test]
fn every_spring_hangs_on_its_hooks_and_clear_of_every_part() {
    let made = hooked();
    let springs: usize = made.iter().map(|h| h.fabrication.springs.len()).sum();
    assert!(springs >= 2, "too few springs hooked to test anything: {springs}");
    for h in &made {
        let f = &h.fabrication;
        let report = check(f);
        assert!(report.ok(), "{report:?}");
        // The springs hooked are the springs chosen, and each hook stands where its anchor is at the
        // first pose.
        assert_eq!(f.springs.len(), h.balance.springs.len());
        let mut poses = Vec::new();
        f.layout.carrier_poses(f.trace.row(0), &mut poses);
        for (k, hook) in f.layout.hooks.iter().enumerate() {
            let anchor = &f.springs[hook.spring][k % 2];
            let at = f.layout.hook_at(k, f.trace.row(0), &poses);
            assert!(at.distance(anchor.point) < 1e-6, "hook {k} at {at:?}, anchor {:?}", anchor.point);
        }
        assert!(h.balance.peak_with_springs_nm < h.torque.peak_nm);
    }
}

#[test]
fn the_check_finds_a_spring_hung_where_its_hooks_are_not() {
    let made = hooked();
    let h = made.iter().find(|h| !h.fabrication.springs.is_empty()).expect("a fabrication with a spring");
    let mut moved = h.fabrication.clone();
    let face = &mut moved.ordering.spring_face[0];
    *face = if *face == Face::Front { Face::Back } else { Face::Front };
    let report = check(&moved);
    assert!(report.springs.iter().any(|s| s.contains("no hook")), "{:?}", report.springs);
}

#[test]
fn the_check_finds_a_part_in_a_springs_way() {
    // Every member said to lie on the first layer: the springs' axes come down among the parts, which
    // stay at their real heights.
    let met = hooked().iter().filter(|h| !h.fabrication.springs.is_empty()).any(|h| {
        let mut lowered = h.fabrication.clone();
        lowered.ordering.layer.iter_mut().for_each(|l| *l = 1);
        check(&lowered).springs.iter().any(|s| s.contains(" meets "))
    });
    assert!(met, "no spring brought down among the parts meets one");
}

#[test]
fn anchors_on_unknown_parts_or_off_the_numbers_are_refused_with_their_spring() {
    let known = known_scene(Known::chain(1), 3, 3, 100.0).expect("a known scene");
    let problem = Problem::new(&known.scene).expect("a valid scene");
    let design = known.design();
    let ground = |point: Point| Anchor { part: "ground".into(), point };
    let at = |part: &str, point: Point| Anchor { part: part.into(), point };
    let settings = PrintSettings::default();
    let cases = [
        (at("no such part", Point::new(0.0, 0.0)), HookRefusal::NoSuchPart),
        (at("body1", Point::new(f64::NAN, 0.0)), HookRefusal::NotFinite),
    ];
    for (moving, why) in cases {
        let ends = [ground(Point::new(0.0, 0.0)), moving.clone()];
        match fabricate_design_with_springs(&problem, &design, &settings, &[ends]) {
            Err(FabError::SpringHook { spring: 1, part, why: got }) => {
                assert_eq!((part, got), (moving.part, why));
            }
            other => panic!("{moving:?}: {:?}", other.map(|f| f.springs)),
        }
    }
}
