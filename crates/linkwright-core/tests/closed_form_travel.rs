//! The closed-form travel check of single-loop plans against re-simulation: random four-bars and
//! slider-cranks swept at a thousandth of a radian must agree with it on assembly and on the least
//! transmission sine.

use linkwright_core::geom::{Point, Vec2};
use linkwright_core::kinematics::Plan;
use linkwright_core::{Mechanism, SliderLine, Topology};
use proptest::prelude::*;
use std::f64::consts::TAU;
use std::sync::Arc;

const STEP: f64 = 1e-3;

fn mechanism(topology: Topology, named: &[(&str, Point)], slider: Option<SliderLine>) -> Mechanism {
    let mut joints = vec![Point::ORIGIN; topology.joint_count()];
    for &(name, p) in named {
        joints[topology.joint(name).expect("a joint of the topology")] = p;
    }
    Mechanism { topology: Arc::new(topology), joints, slider }
}

/// Sweeps `plan` from `from` over `span` radians at [`STEP`]: `None` when some row fails to assemble,
/// else the least transmission sine of the rows.
fn swept(plan: &Plan, from: f64, span: f64) -> Option<f64> {
    let steps = (span.abs() / STEP).ceil() as usize;
    let mut pos = vec![Point::ORIGIN; plan.joint_count()];
    let mut least: f64 = 1.0;
    for s in 0..=steps {
        plan.solve(from + span * s as f64 / steps as f64, &mut pos).ok()?;
        least = least.min(plan.min_transmission_sine(&pos));
    }
    Some(least)
}

/// The closed form and the sweep agree: an assembling travel has the swept least sine (to what the
/// step can miss), and a travel the closed form refuses either fails to assemble in the sweep too or
/// comes to a dead point, where the transmission sine falls to zero.
fn agree(plan: &Plan, from: f64, span: f64) -> Result<(), TestCaseError> {
    let closed = plan.closed_form_travel(from, from + span).expect("a single-loop plan");
    match (closed, swept(plan, from, span)) {
        (Ok(sine), Some(least)) => {
            prop_assert!(least >= sine - 1e-9, "swept {least} below the closed form's {sine}");
            prop_assert!(least <= sine + 5e-3, "swept {least} far above the closed form's {sine}");
        }
        (Ok(sine), None) => prop_assert!(false, "the closed form assembles (sine {sine}), the sweep does not"),
        (Err(_), Some(least)) => prop_assert!(least < 0.05, "refused, but the sweep assembles with sine {least}"),
        (Err(_), None) => {}
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn four_bar_travel_agrees_with_a_fine_sweep(
        crank in 0.2..2.0f64, crank_angle in -3.2..3.2f64,
        cx in -3.0..3.0f64, cy in -3.0..3.0f64, dx in -3.0..3.0f64, dy in -3.0..3.0f64,
        span in -TAU + 0.01..TAU - 0.01,
    ) {
        let pivot = Point::new(0.0, 0.0);
        let tip = pivot + Vec2::from_angle(crank_angle) * crank;
        let (coupler_joint, ground) = (Point::new(cx, cy), Point::new(dx, dy));
        prop_assume!(tip.distance(coupler_joint) > 0.1 && ground.distance(coupler_joint) > 0.1);
        prop_assume!(ground.distance(tip) > 0.1);
        let m = mechanism(Topology::chain(1), &[("q0", pivot), ("p1", tip), ("q1", coupler_joint), ("r0", ground)], None);
        let plan = Plan::compile(&m).expect("a four-bar compiles");
        agree(&plan, crank_angle, span)?;
    }

    #[test]
    fn slider_crank_travel_agrees_with_a_fine_sweep(
        crank in 0.2..2.0f64, crank_angle in -3.2..3.2f64,
        sx in -3.0..3.0f64, sy in -3.0..3.0f64, guide in -3.2..3.2f64,
        span in -TAU + 0.01..TAU - 0.01,
    ) {
        let pivot = Point::new(0.0, 0.0);
        let tip = pivot + Vec2::from_angle(crank_angle) * crank;
        let slider = Point::new(sx, sy);
        prop_assume!(tip.distance(slider) > 0.1);
        let line = SliderLine { point: slider, direction: Vec2::from_angle(guide) };
        let m = mechanism(Topology::slider_crank(), &[("q0", pivot), ("p1", tip), ("q1", slider)], Some(line));
        let plan = Plan::compile(&m).expect("a slider-crank compiles");
        agree(&plan, crank_angle, span)?;
    }
}

#[test]
fn plans_with_two_dyads_have_no_closed_form() {
    let names = ["p1", "p2", "q0", "q1", "q2", "r0", "r1"];
    let topology = Topology::chain(2);
    let spots = [(1.0, 0.0), (3.0, 1.0), (0.0, 0.0), (2.0, 2.0), (4.0, 3.0), (5.0, 0.0), (2.5, -1.0)];
    let named: Vec<(&str, Point)> = names.iter().zip(spots).map(|(&n, (x, y))| (n, Point::new(x, y))).collect();
    let plan = Plan::compile(&mechanism(topology, &named, None)).expect("the six-bar compiles");
    assert!(plan.closed_form_travel(0.0, 1.0).is_none());
}
