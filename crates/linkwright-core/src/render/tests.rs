//! Tests of the pictures: read back with an independent XML reader, counted, and checked against the
//! kinematics they draw.

use super::animation::MAX_FRAMES;
use super::sheet::sample;
use super::style::Style;
use super::{animation_svg, design_svg, RenderInput};
use crate::geom::testing::assert_close;
use crate::geom::{Point, Rigid, Vec2};
use crate::kinematics::{BodyFrames, Plan, Trace};
use crate::mechanism::{Mechanism, SliderLine, Topology};
use crate::scene::{Problem, Scene};
use roxmltree::{Document, Node};
use std::sync::Arc;

/// A scene built around a hand-made mechanism: a body rectangle along the first two joints of each
/// body, three poses taken from the mechanism's own motion (the middle one nudged, so the design
/// misses it a little), a fixed slab below, a region around the ground pivots and an avoid square.
struct Fixture {
    problem: Problem,
    mechanism: Mechanism,
    trace: Trace,
    pose_steps: Vec<usize>,
}

impl Fixture {
    fn new(
        name: &str,
        body_names: &[&str],
        topology: Topology,
        joints: Vec<Point>,
        slider: Option<SliderLine>,
    ) -> Self {
        Self::with_steps(name, body_names, topology, joints, slider, 60)
    }

    fn with_steps(
        name: &str,
        body_names: &[&str],
        topology: Topology,
        joints: Vec<Point>,
        slider: Option<SliderLine>,
        steps: usize,
    ) -> Self {
        let mechanism = Mechanism { topology: Arc::new(topology), joints, slider };
        let plan = Plan::compile(&mechanism).expect("the fixture compiles");
        let start = mechanism.crank_start();
        let mut trace = Trace::default();
        // The largest travel up to 60° either way that assembles all along.
        let travel = [60.0f64, -60.0, 40.0, -40.0, 20.0, -20.0, 10.0, -10.0]
            .into_iter()
            .find(|deg| {
                let to = start + deg.to_radians();
                trace.sweep(&plan, start, to, (to - start).abs() / steps as f64).is_ok()
            })
            .expect("the fixture moves");
        assert!(travel.abs() > 0.0);
        let topo = &mechanism.topology;
        let first_poses: Vec<Rigid> = (0..topo.body_count)
            .map(|b| {
                let part = topo.body_part(b);
                let (a, c) = (mechanism.joints[part.joints[0]], mechanism.joints[part.joints[1]]);
                Rigid::from_frame(a, c - a)
            })
            .collect();
        let frames = BodyFrames::new(&mechanism, &first_poses);
        let last = trace.len() - 1;
        let pose_steps = vec![0, last / 2, last];
        let mut moving = Vec::new();
        for (b, first) in first_poses.iter().enumerate() {
            let part = topo.body_part(b);
            let len = mechanism.joints[part.joints[0]].distance(mechanism.joints[part.joints[1]]);
            let poses: Vec<[f64; 3]> = pose_steps
                .iter()
                .enumerate()
                .map(|(i, &s)| {
                    let pose = if i == 0 { *first } else { frames.pose(b, trace.row(s)) };
                    let mut p = pose.to_pose();
                    if i == 1 {
                        p[0] += 0.08;
                        p[1] -= 0.05;
                        p[2] += 2.0;
                    }
                    p
                })
                .collect();
            moving.push(serde_json::json!({
                "name": body_names[b],
                "polygon": [[-0.3, -0.35], [len + 0.3, -0.35], [len + 0.3, 0.35], [-0.3, 0.35]],
                "poses": poses,
            }));
        }
        let ground: Vec<Point> = topo.fixed_joints().iter().map(|&j| mechanism.joints[j]).collect();
        let (lo_x, hi_x) = ground.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.x), b.max(p.x)));
        let right = mechanism.joints.iter().map(|p| p.x).fold(hi_x, f64::max);
        let lo_y = ground.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        let hi_y = ground.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
        let scene = serde_json::json!({
            "linkwright": "scene/1",
            "name": name,
            "fixed_bodies": [{"name": "slab", "polygon": [[lo_x - 1.5, lo_y - 1.4], [hi_x + 1.5, lo_y - 1.4], [hi_x + 1.5, lo_y - 0.8], [lo_x - 1.5, lo_y - 0.8]]}],
            "moving_bodies": moving,
            "linkage_region": [[lo_x - 1.0, lo_y - 0.7], [hi_x + 1.0, lo_y - 0.7], [hi_x + 1.0, hi_y + 1.0], [lo_x - 1.0, hi_y + 1.0]],
            "avoid_regions": [[[right + 1.5, lo_y - 0.5], [right + 2.5, lo_y - 0.5], [right + 2.5, lo_y + 0.5], [right + 1.5, lo_y + 0.5]]],
        });
        let scene = Scene::from_json(&scene.to_string()).expect("the fixture scene parses");
        let problem = Problem::new(&scene).unwrap_or_else(|issues| panic!("the fixture scene is valid: {issues:?}"));
        Fixture { problem, mechanism, trace, pose_steps }
    }

    fn input(&self) -> RenderInput<'_> {
        RenderInput {
            problem: &self.problem,
            mechanism: &self.mechanism,
            trace: &self.trace,
            pose_steps: &self.pose_steps,
        }
    }
}

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

/// The four-bar of the brief: joints in `Topology::chain(1)` order p1, q0, q1, r0.
fn four_bar(name: &str, body: &str) -> Fixture {
    Fixture::new(name, &[body], Topology::chain(1), vec![p(1., 2.), p(0., 0.), p(4., 3.), p(5., 0.)], None)
}

/// A Watt-I six-bar: joints in `Topology::chain(2)` order p1, p2, q0, q1, q2, r0, r1.
fn six_bar() -> Fixture {
    let joints = vec![p(1., 2.), p(5., 4.), p(0., 0.), p(3., 3.), p(6.5, 5.5), p(6., 0.), p(2., 4.)];
    Fixture::new("watt", &["arm", "hand"], Topology::chain(2), joints, None)
}

/// A slider-crank: joints q0, p1, q1, the slider joint running on the horizontal line through q1.
fn slider_crank() -> Fixture {
    let slider = SliderLine { point: p(4., 0.5), direction: Vec2::new(1., 0.) };
    Fixture::new(
        "slide",
        &["carriage"],
        Topology::slider_crank(),
        vec![p(0., 0.), p(1., 1.5), p(4., 0.5)],
        Some(slider),
    )
}

fn class_is<'a>(class: &'a str) -> impl Fn(&Node) -> bool + 'a {
    move |n: &Node| n.attribute("class").is_some_and(|c| c.split(' ').any(|c| c == class))
}

fn count(doc: &Document, tag: &str, class: &str) -> usize {
    doc.descendants().filter(|n| n.has_tag_name(tag)).filter(class_is(class)).count()
}

fn points_of(n: &Node) -> Vec<Point> {
    n.attribute("points")
        .unwrap()
        .split(' ')
        .map(|xy| {
            let (x, y) = xy.split_once(',').unwrap();
            p(x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

fn number(n: &Node, attribute: &str) -> f64 {
    n.attribute(attribute).unwrap_or_else(|| panic!("{attribute} missing")).parse().unwrap()
}

#[test]
fn design_sheet_has_every_layer() {
    let f = four_bar("bed", "bed");
    let svg = design_svg(&f.input());
    let doc = Document::parse(&svg).expect("well-formed XML");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    assert_eq!(count(&doc, "polygon", "fixed"), f.problem.fixed.len());
    assert_eq!(count(&doc, "polygon", "region"), 1);
    assert_eq!(count(&doc, "polygon", "avoid"), f.problem.avoid.len());
    for (b, body) in f.problem.bodies.iter().enumerate() {
        let colour = Style::body_colour(b);
        let skins = doc.descendants().filter(class_is("pose")).filter(|n| n.attribute("stroke") == Some(colour));
        assert_eq!(skins.count(), body.poses.len());
    }
    let numbers: Vec<&str> = doc.descendants().filter(class_is("pose-label")).filter_map(|n| n.text()).collect();
    assert_eq!(numbers, ["1", "2", "3"]);
    assert_eq!(count(&doc, "polygon", "reached"), f.pose_steps.len() * f.problem.bodies.len());
    assert_eq!(count(&doc, "polygon", "body"), 1);
    // Two moving joints (p1, q1), each traced through every row.
    let paths: Vec<Node> = doc.descendants().filter(class_is("path")).collect();
    assert_eq!(paths.len(), 2);
    for path in &paths {
        assert_eq!(points_of(path).len(), f.trace.len());
    }
    // Crank and rocker, four joints, two ground symbols, four names.
    assert_eq!(count(&doc, "line", "link"), 2);
    assert_eq!(count(&doc, "line", "crank"), 1);
    assert_eq!(count(&doc, "circle", "joint"), 4);
    assert_eq!(count(&doc, "polygon", "ground"), 2);
    let names: Vec<&str> = doc.descendants().filter(class_is("joint-label")).filter_map(|n| n.text()).collect();
    assert_eq!(names, ["p1", "q0", "q1", "r0"]);
    assert!(svg.contains("four-bar linkage"));
}

/// Under the drawing, every link's length and every ground pivot's position, read back and measured
/// against the mechanism's joints to the digits shown.
#[test]
fn design_sheet_lists_the_dimensions_to_build_it() {
    for f in [four_bar("bed", "bed"), six_bar(), slider_crank()] {
        let svg = design_svg(&f.input());
        let doc = Document::parse(&svg).expect("well-formed XML");
        let footer: Vec<&str> = doc.descendants().filter(class_is("footer")).filter_map(|n| n.text()).collect();
        let text = footer.join("   ");
        let topo = &f.mechanism.topology;
        let joint = |name: &str| f.mechanism.joints[topo.joint(name).unwrap()];
        // "name value" where value is shown with its own digits: within half its last digit.
        let close = |shown: &str, truth: f64| {
            let decimals = shown.split('.').nth(1).map_or(0, str::len) as i32;
            let v: f64 = shown.parse().unwrap_or_else(|_| panic!("{shown} in {text}"));
            assert!((v - truth).abs() <= 0.5 * 10f64.powi(-decimals) + 1e-12, "{shown} for {truth} in {text}");
        };
        assert!(text.starts_with(&format!("Links ({}):", f.problem.units)), "{text}");
        for (a, b) in topo.link_pairs() {
            let (na, nb) = (&topo.joint_names[a], &topo.joint_names[b]);
            let (key, other) = (format!("{na}–{nb} "), format!("{nb}–{na} "));
            let at =
                text.find(&key).or_else(|| text.find(&other)).unwrap_or_else(|| panic!("{key} missing from {text}"));
            let shown = text[at + key.len()..].split_whitespace().next().unwrap();
            close(shown, joint(&topo.joint_names[a]).distance(joint(&topo.joint_names[b])));
        }
        for &j in topo.fixed_joints() {
            let key = format!("{} (", topo.joint_names[j]);
            let at = text.rfind(&key).unwrap_or_else(|| panic!("{key} missing from {text}"));
            let inside = text[at + key.len()..].split(')').next().unwrap();
            let (x, y) = inside.split_once(", ").unwrap();
            close(x, f.mechanism.joints[j].x);
            close(y, f.mechanism.joints[j].y);
        }
        assert_eq!(text.contains("Slider ("), f.mechanism.slider.is_some(), "{text}");
    }
}

/// The world group's `matrix(a,b,c,d,e,f)` as a map from world to picture coordinates.
fn world_to_screen(doc: &Document) -> impl Fn(Point) -> (f64, f64) {
    let world = doc.descendants().find(|n| n.attribute("transform").is_some_and(|t| t.starts_with("matrix("))).unwrap();
    let t = world.attribute("transform").unwrap();
    let m: Vec<f64> = t["matrix(".len()..t.len() - 1].split(',').map(|v| v.parse().unwrap()).collect();
    assert_eq!((m[1], m[2]), (0.0, 0.0));
    assert!(m[0] > 0.0 && m[3] == -m[0], "uniform scale with y flipped up: {t}");
    move |p: Point| (m[0] * p.x + m[4], m[3] * p.y + m[5])
}

#[test]
fn the_world_is_drawn_y_up_inside_the_view_box() {
    let f = four_bar("bed", "bed");
    let svg = design_svg(&f.input());
    let doc = Document::parse(&svg).unwrap();
    let view: Vec<f64> =
        doc.root_element().attribute("viewBox").unwrap().split(' ').map(|v| v.parse().unwrap()).collect();
    assert_eq!((view[0], view[1]), (0.0, 0.0));
    let screen = world_to_screen(&doc);
    let world = doc.descendants().find(|n| n.attribute("transform").is_some_and(|t| t.starts_with("matrix("))).unwrap();
    let mut checked = 0;
    for n in world.descendants().filter(|n| n.has_tag_name("polygon") || n.has_tag_name("polyline")) {
        for q in points_of(&n) {
            let (x, y) = screen(q);
            assert!(x >= 0.0 && x <= view[2] && y >= 0.0 && y <= view[3], "{q:?} at {x},{y} outside {view:?}");
            checked += 1;
        }
    }
    assert!(checked > 20);
    // The crank pivot q0 is below the coupler joint p1 in the world, so lower (larger y) in the picture.
    let (_, q0_y) = screen(f.mechanism.joint("q0").unwrap());
    let (_, p1_y) = screen(f.mechanism.joint("p1").unwrap());
    assert!(q0_y > p1_y);
    // A pose number sits at its outline's centroid, in picture coordinates, outside the flipped group.
    let c = f.problem.bodies[0].outline.transformed(&f.problem.bodies[0].poses[2]).centroid();
    let label = doc.descendants().filter(class_is("pose-label")).find(|n| n.text() == Some("3")).unwrap();
    assert!(!label.ancestors().any(|a| a == world));
    let (cx, cy) = screen(c);
    assert_close(number(&label, "x"), cx, 0.01);
    assert!((number(&label, "y") - cy).abs() < 0.02 * view[3]);
}

#[test]
fn names_are_escaped() {
    let f = four_bar("bed <&> \"frame\"", "lid<1>&");
    let svg = design_svg(&f.input());
    assert!(!svg.contains("<&>") && !svg.contains("lid<1>"));
    assert!(svg.contains("bed &lt;&amp;&gt; &quot;frame&quot;"));
    let doc = Document::parse(&svg).unwrap();
    let texts: Vec<&str> = doc.descendants().filter_map(|n| n.text()).collect();
    assert!(texts.contains(&"bed <&> \"frame\""));
    assert!(texts.contains(&"lid<1>&"));
    Document::parse(&animation_svg(&f.input(), 2.0)).expect("the animation escapes too");
}

#[test]
fn control_characters_in_names_still_give_well_formed_xml() {
    // Validation refuses such names in a scene; the renderer still copes with a problem built by hand.
    let mut f = four_bar("bed", "lid");
    f.problem.name = "bed\0\u{1}\u{1b}".into();
    f.problem.bodies[0].name = "lid\u{7}\u{ffff}".into();
    for svg in [design_svg(&f.input()), animation_svg(&f.input(), 2.0)] {
        let doc = Document::parse(&svg).expect("well-formed XML");
        let texts: Vec<&str> = doc.descendants().filter_map(|n| n.text()).collect();
        assert!(texts.contains(&"bed") && texts.contains(&"lid"), "{texts:?}");
        assert!(!svg.chars().any(|c| c.is_control() && !matches!(c, '\n' | '\t' | '\r')));
    }
}

#[test]
fn output_is_deterministic() {
    let f = six_bar();
    assert_eq!(design_svg(&f.input()), design_svg(&f.input()));
    assert_eq!(animation_svg(&f.input(), 3.0), animation_svg(&f.input(), 3.0));
}

#[test]
fn six_bar_draws_ternary_links_and_body_brackets() {
    let f = six_bar();
    let doc_text = design_svg(&f.input());
    let doc = Document::parse(&doc_text).unwrap();
    assert_eq!(count(&doc, "polygon", "ternary"), 1);
    assert_eq!(count(&doc, "line", "link"), 2);
    assert_eq!(count(&doc, "polygon", "bracket"), 1, "body 1 carries p1, q1, r1");
    assert_eq!(count(&doc, "polyline", "bracket"), 1, "body 2 carries p2, q2");
    assert_eq!(count(&doc, "polyline", "path"), 5);
    assert_eq!(count(&doc, "polygon", "pose"), 6);
    assert!(doc_text.contains("Watt-I six-bar"));
}

#[test]
fn slider_crank_draws_its_guide_over_the_whole_stroke() {
    let f = slider_crank();
    let doc_text = design_svg(&f.input());
    let doc = Document::parse(&doc_text).unwrap();
    let guide = doc.descendants().find(class_is("guide")).expect("a guide");
    let xs: Vec<f64> = (0..f.trace.len()).map(|s| f.trace.row(s)[2].x).collect();
    let (lo, hi) = xs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    let (x1, x2) = (number(&guide, "x1"), number(&guide, "x2"));
    assert!(x1 < lo && x2 > hi && hi - lo > 0.1, "guide {x1}..{x2}, stroke {lo}..{hi}");
    assert!(x2 - x1 < hi - lo + 0.1 * f.problem.scale);
    assert_close(number(&guide, "y1"), 0.5, 1e-3);
    assert_eq!(count(&doc, "rect", "slider"), 1);
    assert_eq!(count(&doc, "polygon", "ground"), 1);
    assert!(doc_text.contains("slider-crank"));
}

/// Every `animate`/`animateTransform` of `doc`, checked for consistent timing; returns them.
fn animations<'a>(doc: &'a Document, frames: usize, seconds: f64) -> Vec<Node<'a, 'a>> {
    let all: Vec<Node> =
        doc.descendants().filter(|n| n.has_tag_name("animate") || n.has_tag_name("animateTransform")).collect();
    for a in &all {
        let values: Vec<&str> = a.attribute("values").unwrap().split(';').collect();
        let times: Vec<f64> = a.attribute("keyTimes").unwrap().split(';').map(|t| t.parse().unwrap()).collect();
        assert_eq!(values.len(), times.len());
        assert_eq!(values.len(), 2 * frames - 1, "forward then back");
        assert_eq!(values.first(), values.last(), "loops back to the start");
        assert_eq!(times[0], 0.0);
        assert_eq!(*times.last().unwrap(), 1.0);
        assert!(times.windows(2).all(|w| w[0] <= w[1]));
        assert_eq!(a.attribute("repeatCount"), Some("indefinite"));
        assert_eq!(a.attribute("dur"), Some(format!("{}s", 2.0 * seconds).as_str()));
    }
    all
}

#[test]
fn animation_moves_every_moving_part_forward_and_back() {
    let f = four_bar("bed", "bed");
    let svg = animation_svg(&f.input(), 2.5);
    let doc = Document::parse(&svg).expect("well-formed XML");
    let all = animations(&doc, f.trace.len(), 2.5);
    // Body: translate + rotate; crank and rocker: 4 ends each; joints p1, q1: cx, cy.
    assert_eq!(all.len(), 2 + 8 + 4);
    // Static renderers see the first frame: every base attribute equals the first value.
    for a in all.iter().filter(|a| a.has_tag_name("animate")) {
        let name = a.attribute("attributeName").unwrap();
        let parent = a.parent_element().unwrap();
        let first = a.attribute("values").unwrap().split(';').next().unwrap();
        assert_eq!(parent.attribute(name), Some(first), "{name}");
    }
    assert_eq!(count(&doc, "polygon", "pose"), 3);
    assert_eq!(count(&doc, "polygon", "fixed"), 1);
}

#[test]
fn animated_body_follows_the_linkage() {
    let f = six_bar();
    let svg = animation_svg(&f.input(), 1.0);
    let doc = Document::parse(&svg).unwrap();
    let first_poses: Vec<Rigid> = f.problem.bodies.iter().map(|b| b.poses[0]).collect();
    let frames = BodyFrames::new(&f.mechanism, &first_poses);
    let translations: Vec<Node> = doc
        .descendants()
        .filter(|n| n.attribute("type") == Some("translate") && n.has_tag_name("animateTransform"))
        .collect();
    let rotations: Vec<Node> = doc.descendants().filter(|n| n.attribute("type") == Some("rotate")).collect();
    assert_eq!((translations.len(), rotations.len()), (2, 2));
    let k = f.trace.len() / 3;
    for (b, body) in f.problem.bodies.iter().enumerate() {
        let t: Vec<f64> = translations[b]
            .attribute("values")
            .unwrap()
            .split(';')
            .nth(k)
            .unwrap()
            .split(',')
            .map(|v| v.parse().unwrap())
            .collect();
        let deg: f64 = rotations[b].attribute("values").unwrap().split(';').nth(k).unwrap().parse().unwrap();
        let drawn = Rigid::new(deg.to_radians(), Vec2::new(t[0], t[1]));
        let expected = frames.pose(b, f.trace.row(k));
        for &v in body.outline.vertices() {
            let (a, e) = (drawn.apply(v), expected.apply(v));
            assert!(a.distance(e) < 1e-3 * f.problem.scale, "body {b}: {a:?} vs {e:?}");
        }
    }
    for r in &rotations {
        let deg: Vec<f64> = r.attribute("values").unwrap().split(';').map(|v| v.parse().unwrap()).collect();
        assert!(deg.windows(2).all(|w| (w[1] - w[0]).abs() < 45.0), "rotation unwrapped frame to frame");
    }
    // The ternary link's corners animate as one points list.
    let ternary = doc.descendants().find(class_is("ternary")).unwrap();
    let anim = ternary.children().find(|n| n.has_tag_name("animate")).unwrap();
    assert_eq!(anim.attribute("attributeName"), Some("points"));
    animations(&doc, f.trace.len(), 1.0);
}

#[test]
fn long_traces_are_subsampled() {
    let joints = vec![p(1., 2.), p(0., 0.), p(4., 3.), p(5., 0.)];
    let f = Fixture::with_steps("long", &["bed"], Topology::chain(1), joints, None, 1000);
    assert!(f.trace.len() > MAX_FRAMES);
    let svg = animation_svg(&f.input(), 4.0);
    let doc = Document::parse(&svg).unwrap();
    let frames = sample(f.trace.len(), MAX_FRAMES).len();
    assert!(frames <= MAX_FRAMES);
    assert!(!animations(&doc, frames, 4.0).is_empty());
    assert!(svg.len() < 400_000, "{} bytes", svg.len());
}

#[test]
fn an_empty_trace_draws_the_linkage_standing_still() {
    let mut f = four_bar("still", "bed");
    f.trace = Trace::default();
    f.pose_steps.clear();
    let design = design_svg(&f.input());
    let doc = Document::parse(&design).unwrap();
    assert_eq!(count(&doc, "circle", "joint"), 4);
    assert_eq!(count(&doc, "polyline", "path"), 0);
    let animation = animation_svg(&f.input(), 1.0);
    let doc = Document::parse(&animation).unwrap();
    assert_eq!(animations(&doc, 1, 1.0).len(), 0);
}

#[test]
fn sampling_keeps_the_ends() {
    assert_eq!(sample(5, 180), vec![0, 1, 2, 3, 4]);
    let s = sample(1001, 180);
    assert_eq!((s.len(), s[0], *s.last().unwrap()), (180, 0, 1000));
    assert!(s.windows(2).all(|w| w[0] < w[1]));
}

/// Writes the pictures of the fixtures to /tmp for a person to look at:
/// `cargo test -p linkwright-core render::tests::write_pictures -- --ignored`.
#[test]
#[ignore = "writes files for a visual check"]
fn write_pictures() {
    for (name, f) in [("four_bar", four_bar("bed <&>", "bed")), ("six_bar", six_bar()), ("slider", slider_crank())] {
        std::fs::write(format!("/tmp/{name}_design.svg"), design_svg(&f.input())).unwrap();
        std::fs::write(format!("/tmp/{name}_animation.svg"), animation_svg(&f.input(), 3.0)).unwrap();
    }
}
