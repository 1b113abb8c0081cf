//! The kinematic solver against numbers nobody here computed: published position traces of a four-bar,
//! a slider-crank and a Watt-I six-bar (see `fixtures/reference-kinematics/README.md` for where they come
//! from). Every published number is checked to the precision it is printed with, no looser.
//!
//! Tolerances:
//! - Positions and lengths are printed with 6 decimals, so a published value is within half a unit of the
//!   6th decimal (5e-7) of the exact one; [`POS_TOL`] is that half unit plus a hair for f64 rounding.
//! - Angles are printed with 4 decimals (half a unit: 5e-5°) and were computed by the publisher from the
//!   *printed* (rounded) positions, so each angle tolerance adds the angle that a half-unit rounding of
//!   the positions it was computed from can turn a link of the given length by ([`angle_tol_deg`]).
//! - Our own solutions must keep every length of the mechanism to [`RIGID_TOL`] (f64 round-off only).

use linkwright_core::geom::{Point, Vec2};
use linkwright_core::kinematics::{circle_circle, Branch, Plan};
use linkwright_core::{Mechanism, SliderLine, Topology};
use serde_json::Value;
use std::sync::Arc;

const FOUR_BAR: &str = include_str!("fixtures/reference-kinematics/four_bar.json");
const SLIDER_CRANK: &str = include_str!("fixtures/reference-kinematics/slider_crank.json");
const WATT_I: &str = include_str!("fixtures/reference-kinematics/watt_i.json");

/// Half a unit of the 6th decimal, plus f64 slack.
const POS_TOL: f64 = 0.5e-6 + 1e-12;
/// Half a unit of the 4th decimal, degrees.
const ANGLE_PRINT_TOL_DEG: f64 = 0.5e-4;
/// How far a solved configuration may drift from the mechanism's own lengths (round-off only).
const RIGID_TOL: f64 = 1e-9;

/// The tolerance of a printed angle of a link of length `len` whose two end positions were each printed
/// rounded to 6 decimals (`rounded_ends` of them: 1 when the other end is an exact pivot).
fn angle_tol_deg(len: f64, rounded_ends: f64) -> f64 {
    let position_rounding = rounded_ends * std::f64::consts::SQRT_2 * 0.5e-6;
    ANGLE_PRINT_TOL_DEG + (position_rounding / len).to_degrees()
}

fn parse(text: &str) -> Value {
    serde_json::from_str(text).expect("a fixture is valid JSON")
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("expected a number, found {v}"))
}

fn point(v: &Value) -> Point {
    Point::new(num(&v[0]), num(&v[1]))
}

fn rows(doc: &Value) -> &Vec<Value> {
    doc["rows"].as_array().expect("a rows array")
}

/// `a − b` in degrees, wrapped into (−180, 180].
fn angle_diff_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    if d > 180.0 {
        d - 360.0
    } else {
        d
    }
}

/// The angle between `u` and `v`, degrees in [0, 180].
fn angle_between_deg(u: Vec2, v: Vec2) -> f64 {
    u.cross(v).abs().atan2(u.dot(v)).to_degrees()
}

fn assert_near(what: &str, ours: f64, published: f64, tol: f64) {
    assert!(
        (ours - published).abs() <= tol,
        "{what}: ours {ours}, published {published}, difference {:e} > tolerance {tol:e}",
        ours - published
    );
}

fn assert_angle_near(what: &str, ours_deg: f64, published_deg: f64, tol: f64) {
    let d = angle_diff_deg(ours_deg, published_deg);
    assert!(d.abs() <= tol, "{what}: ours {ours_deg}°, published {published_deg}°, difference {d:e}° > {tol:e}°");
}

fn assert_point_near(what: &str, ours: Point, published: Point, tol: f64) {
    assert_near(&format!("{what}.x"), ours.x, published.x, tol);
    assert_near(&format!("{what}.y"), ours.y, published.y, tol);
}

/// A mechanism of `topology` with the named joints at the given first-pose positions.
fn mechanism(topology: Topology, joints: &[(&str, Point)], slider: Option<SliderLine>) -> Mechanism {
    assert_eq!(joints.len(), topology.joint_count(), "every joint is given");
    let mut positions = vec![Point::new(f64::NAN, f64::NAN); topology.joint_count()];
    for &(name, p) in joints {
        positions[topology.joint(name).unwrap_or_else(|| panic!("no joint {name}"))] = p;
    }
    Mechanism { topology: Arc::new(topology), joints: positions, slider }
}

/// Every pair of joints some moving part (link or body) holds rigidly, with its first-pose length.
fn rigid_pairs(m: &Mechanism) -> Vec<(usize, usize, f64)> {
    let mut out: Vec<(usize, usize, f64)> =
        m.topology.link_pairs().into_iter().map(|(a, b)| (a, b, m.joints[a].distance(m.joints[b]))).collect();
    for b in 0..m.topology.body_count {
        let joints = &m.topology.body_part(b).joints;
        for (i, &x) in joints.iter().enumerate() {
            for &y in &joints[i + 1..] {
                out.push((x, y, m.joints[x].distance(m.joints[y])));
            }
        }
    }
    out
}

fn assert_rigid(m: &Mechanism, pairs: &[(usize, usize, f64)], pos: &[Point], at: &str) {
    for &(a, b, len) in pairs {
        let now = pos[a].distance(pos[b]);
        assert!(
            (now - len).abs() <= RIGID_TOL,
            "{at}: |{}{}| = {now}, first pose {len}",
            m.topology.joint_names[a],
            m.topology.joint_names[b]
        );
    }
}

#[test]
fn four_bar_matches_the_published_coupler_trace() {
    let doc = parse(FOUR_BAR);
    let a = point(&doc["ground_pivots"]["A"]);
    let d = point(&doc["ground_pivots"]["D"]);
    let lengths = &doc["lengths"];
    let (crank, coupler, rocker, ground) =
        (num(&lengths["crank"]), num(&lengths["coupler"]), num(&lengths["rocker"]), num(&lengths["ground"]));
    let rows = rows(&doc);
    let first = &rows[0];
    let c0 = Point::new(num(&first[1]), num(&first[2]));
    let crank0_deg = num(&first[0]);

    // The crank angle convention, from the data: of the two places B can take at the first row (at the
    // crank's length from A and the coupler's from C), the published theta3 (direction B→C) picks one,
    // and that one sits at the first row's crank angle measured from +x: the column is the absolute,
    // counter-clockwise crank angle (the README's "from the first row" is the same thing, the first row
    // being 0°).
    let b0 = [Branch::Positive, Branch::Negative]
        .into_iter()
        .map(|br| circle_circle(a, crank, c0, coupler, br).expect("the first row assembles"))
        .find(|&b| angle_diff_deg((c0 - b).angle().to_degrees(), num(&first[3])).abs() < 0.01)
        .expect("one assembly of B matches the published theta3");
    // Loose only because the coupler length is itself rounded to 6 decimals: this pins the convention,
    // the trace below checks it to the printed precision.
    assert_angle_near("initial crank angle", (b0 - a).angle().to_degrees(), crank0_deg, 1e-3);
    let crank_start = crank0_deg.to_radians();
    let b0 = a + Vec2::from_angle(crank_start) * crank;

    let m = mechanism(Topology::chain(1), &[("q0", a), ("p1", b0), ("q1", c0), ("r0", d)], None);
    // The first pose has the published lengths, to their printed precision.
    assert_near("crank", a.distance(b0), crank, POS_TOL);
    assert_near("coupler", b0.distance(c0), coupler, POS_TOL);
    assert_near("rocker", d.distance(c0), rocker, POS_TOL);
    assert_near("ground", a.distance(d), ground, POS_TOL);

    let plan = Plan::compile(&m).expect("the four-bar compiles");
    let pairs = rigid_pairs(&m);
    let (jb, jc) = (m.topology.joint("p1").unwrap(), m.topology.joint("q1").unwrap());
    let mut pos = vec![Point::ORIGIN; plan.joint_count()];
    let theta3_tol = angle_tol_deg(coupler, 2.0);
    let theta4_tol = angle_tol_deg(rocker, 1.0);
    for row in rows {
        let crank_deg = num(&row[0]);
        let at = format!("crank {crank_deg}°");
        plan.solve(crank_start + (crank_deg - crank0_deg).to_radians(), &mut pos)
            .unwrap_or_else(|e| panic!("{at}: does not assemble: {e:?}"));
        assert_rigid(&m, &pairs, &pos, &at);
        let (b, c) = (pos[jb], pos[jc]);
        assert_point_near(&format!("{at}: C"), c, Point::new(num(&row[1]), num(&row[2])), POS_TOL);
        assert_angle_near(&format!("{at}: theta3"), (c - b).angle().to_degrees(), num(&row[3]), theta3_tol);
        assert_angle_near(&format!("{at}: theta4"), (c - d).angle().to_degrees(), num(&row[4]), theta4_tol);
        let mu = angle_between_deg(b - c, d - c);
        assert_angle_near(&format!("{at}: mu"), mu, num(&row[5]), theta3_tol + theta4_tol);
    }
}

#[test]
fn slider_crank_matches_the_published_piston_trace() {
    let doc = parse(SLIDER_CRANK);
    let pivot = point(&doc["crank_pivot"]);
    let lengths = &doc["lengths"];
    let (crank, rod, offset) = (num(&lengths["crank"]), num(&lengths["rod"]), num(&lengths["offset"]));
    // "y=<axis height>, piston on -x side"
    let axis = doc["slider_axis"].as_str().expect("a slider axis description");
    let axis_y: f64 = axis
        .strip_prefix("y=")
        .and_then(|s| s.split(',').next())
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or_else(|| panic!("unexpected slider axis {axis:?}"));
    assert!(axis.contains("piston on -x side"), "{axis}");
    assert_near("axis height", axis_y, pivot.y + offset, 1e-12);

    let rows = rows(&doc);
    let first = &rows[0];
    let crank_start = num(&first[0]).to_radians();
    let b0 = pivot + Vec2::from_angle(crank_start) * crank;
    let c0 = Point::new(num(&first[1]), axis_y);
    assert_near("rod", b0.distance(c0), rod, POS_TOL);
    assert!(c0.x < b0.x, "the first row has the piston on the -x side of the crank tip");

    let line = SliderLine { point: c0, direction: Vec2::new(1.0, 0.0) };
    let m = mechanism(Topology::slider_crank(), &[("q0", pivot), ("p1", b0), ("q1", c0)], Some(line));
    let plan = Plan::compile(&m).expect("the slider-crank compiles");
    // Piston on the -x side: behind the foot of the crank tip on the +x guide.
    assert_eq!(plan.branches(), vec![Branch::Negative]);

    let pairs = rigid_pairs(&m);
    let (jb, jc) = (m.topology.joint("p1").unwrap(), m.topology.joint("q1").unwrap());
    let mut pos = vec![Point::ORIGIN; plan.joint_count()];
    let rod_tol = angle_tol_deg(rod, 2.0);
    for row in rows {
        let crank_deg = num(&row[0]);
        let at = format!("crank {crank_deg}°");
        // The column is the absolute crank angle (the first row, 90°, puts the tip straight above the
        // pivot, which is what its published piston position and rod angle need).
        plan.solve(crank_deg.to_radians(), &mut pos).unwrap_or_else(|e| panic!("{at}: does not assemble: {e:?}"));
        assert_rigid(&m, &pairs, &pos, &at);
        let (b, c) = (pos[jb], pos[jc]);
        assert_near(&format!("{at}: crank"), b.distance(pivot), crank, RIGID_TOL);
        assert_near(&format!("{at}: slider on the axis"), c.y, axis_y, RIGID_TOL);
        assert_near(&format!("{at}: slider x"), c.x, num(&row[1]), POS_TOL);
        assert_angle_near(&format!("{at}: rod angle"), (b - c).angle().to_degrees(), num(&row[2]), rod_tol);
    }
}

/// Our chain(2) joints and the Watt-I's published names. Ground A–G; crank A–B; ternary body BCD;
/// ternary link GCF pivoted at G; binary links FE (body 2) and DE.
const WATT_NAMES: [(&str, &str); 7] =
    [("q0", "A"), ("r0", "G"), ("p1", "B"), ("q1", "C"), ("r1", "D"), ("p2", "F"), ("q2", "E")];

/// The Watt-I's fixed pivots are not published. Both are round numbers at the 2-decimal precision of the
/// published first row: A is the centre of the circle of radius AB the rows' B lie on, G the meeting
/// point of the circles of radius CG about C and FG about F. The test checks them against every
/// published length they take part in.
const WATT_A: Point = Point::new(-3.74, -2.41);
const WATT_G: Point = Point::new(7.32, -3.51);

#[test]
fn watt_i_six_bar_matches_the_published_first_steps() {
    let doc = parse(WATT_I);
    let lengths = doc["lengths"].as_object().expect("a lengths object");
    let rows = rows(&doc);
    let columns: Vec<&str> =
        doc["rows_columns"].as_array().expect("columns").iter().map(|c| c.as_str().expect("a name")).collect();
    assert_eq!(columns, ["input_increment_deg", "B", "C", "D", "E", "F"]);
    let published = |row: &Value, name: &str| -> Point {
        match name {
            "A" => WATT_A,
            "G" => WATT_G,
            _ => point(&row[columns.iter().position(|c| *c == name).expect("a published joint")]),
        }
    };

    // The published rigid parts are exactly chain(2)'s.
    let topology = Topology::chain(2);
    let ours_of = |published_name: &str| WATT_NAMES.iter().find(|(_, p)| *p == published_name).unwrap().0;
    let part_names = |part: &str| -> Vec<&str> {
        let part = topology.parts.iter().find(|p| p.name == part).expect("a part");
        let mut names: Vec<&str> = part
            .joints
            .iter()
            .map(|&j| WATT_NAMES.iter().find(|(o, _)| *o == topology.joint_names[j]).unwrap().1)
            .collect();
        names.sort_unstable();
        names
    };
    assert_eq!(part_names("ground"), ["A", "G"]);
    assert_eq!(part_names("crank"), ["A", "B"]);
    assert_eq!(part_names("body1"), ["B", "C", "D"]);
    assert_eq!(part_names("link1"), ["C", "F", "G"]);
    assert_eq!(part_names("body2"), ["E", "F"]);
    assert_eq!(part_names("link2"), ["D", "E"]);

    let first = &rows[0];
    let joints: Vec<(&str, Point)> = WATT_NAMES.iter().map(|&(ours, name)| (ours, published(first, name))).collect();
    let m = mechanism(topology.clone(), &joints, None);
    // Every published length, at the first pose (exact 2-decimal positions) to the printed precision.
    assert_eq!(lengths.len(), 10);
    for (pair, len) in lengths {
        let (x, y) = (&pair[..1], &pair[1..]);
        let ours = m.joint(ours_of(x)).unwrap().distance(m.joint(ours_of(y)).unwrap());
        assert_near(&format!("|{pair}|"), ours, num(len), POS_TOL);
    }

    // The input's direction, from the data: the published B turns about A by +1° per row
    // (counter-clockwise); half-unit rounding of B moves its angle by at most ~1e-5°.
    let b_angle = |row: &Value| (published(row, "B") - WATT_A).angle().to_degrees();
    for pair in rows.windows(2) {
        let step = num(&pair[1][0]) - num(&pair[0][0]);
        assert_angle_near("B's turn per row", angle_diff_deg(b_angle(&pair[1]), b_angle(&pair[0])), step, 1e-4);
    }

    let plan = Plan::compile(&m).expect("the Watt-I compiles");
    let pairs = rigid_pairs(&m);
    let crank_start = m.crank_start();
    let mut pos = vec![Point::ORIGIN; plan.joint_count()];
    for row in rows {
        let inc = num(&row[0]);
        let at = format!("input +{inc}°");
        plan.solve(crank_start + inc.to_radians(), &mut pos)
            .unwrap_or_else(|e| panic!("{at}: does not assemble: {e:?}"));
        assert_rigid(&m, &pairs, &pos, &at);
        for (pair, len) in lengths {
            let (x, y) = (&pair[..1], &pair[1..]);
            let (jx, jy) = (topology.joint(ours_of(x)).unwrap(), topology.joint(ours_of(y)).unwrap());
            // Our lengths are the first pose's, which are within the printed precision of the published.
            assert_near(&format!("{at}: |{pair}|"), pos[jx].distance(pos[jy]), num(len), POS_TOL + RIGID_TOL);
        }
        for name in ["B", "C", "D", "E", "F"] {
            let j = topology.joint(ours_of(name)).unwrap();
            assert_point_near(&format!("{at}: {name}"), pos[j], published(row, name), POS_TOL);
        }
    }
}
