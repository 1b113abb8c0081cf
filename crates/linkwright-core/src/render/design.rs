//! The static design sheet: the scene, the input poses, the linkage at its first pose, the joint paths
//! and where the linkage actually puts the bodies at each pose.

use super::layers::{self, label, polygon};
use super::sheet::Sheet;
use super::style::Style;
use super::svg::{close, Element};
use super::RenderInput;
use crate::geom::{Point, Vec2};
use crate::mechanism::PartKind;

/// Most points of one joint path on the sheet.
const MAX_PATH_POINTS: usize = 720;

/// The static design sheet as SVG text (world coordinates, y up, fitted to everything drawn).
///
/// Draws, bottom to top: the linkage region (dashed blue), avoid regions (red hatch), fixed bodies
/// (grey), each moving body at every input pose (translucent, numbered from 1), the outline the linkage
/// reaches at each `pose_steps` configuration (dashed), the joint paths along the trace, the slider
/// guide, the moving bodies at the first pose, the linkage at the first pose (binary links as thick
/// lines, the crank red, ternary links as triangles, ground pivots on ground symbols), the joint names,
/// a title with a legend, and under the drawing each link's length and each ground pivot's position in
/// the scene's units.
pub fn design_svg(input: &RenderInput) -> String {
    let notes: &'static [&'static str] = match input.problem.path() {
        Some(_) => &["1: where the body starts", "wide: the path drawn, thin: as the tracer follows it"],
        None => &["1…N: input poses", "dashed: as the linkage reaches them"],
    };
    let sheet = Sheet::new(input, MAX_PATH_POINTS, notes).with_footer(dimensions(input));
    let mut out = String::new();
    layers::open_document(&sheet, &mut out);
    layers::open_world(&sheet, &mut out);
    layers::backdrop(&sheet, &mut out);
    layers::onion_skins(&sheet, &mut out);
    reached_poses(&sheet, &mut out);
    layers::joint_paths(&sheet, &mut out);
    layers::drawn_and_traced_path(&sheet, &mut out);
    layers::slider_guide(&sheet, &mut out);
    bodies_at_first_pose(&sheet, &mut out);
    linkage_at_first_pose(&sheet, &mut out);
    close(&mut out, "g");
    layers::pose_numbers(&sheet, &mut out);
    joint_names(&sheet, &mut out);
    layers::title(&sheet, &mut out);
    layers::footer(&sheet, &mut out);
    close(&mut out, "svg");
    out
}

/// Each body where the linkage puts it at the configuration offered for each input pose.
fn reached_poses(sheet: &Sheet, out: &mut String) {
    for (_, s) in sheet.pose_steps() {
        let row = sheet.row(s);
        for (b, body) in sheet.input.problem.bodies.iter().enumerate() {
            let outline = body.outline.transformed(&sheet.body_pose(b, row));
            Element::new("polygon")
                .attr("class", "reached")
                .attr("stroke", Style::body_colour(b))
                .attr("points", sheet.num.points(outline.vertices().iter().copied()))
                .empty(out);
        }
    }
}

/// The moving bodies, solid, at their first input pose, each with a bracket joining the joints it
/// carries (so a joint outside the outline is seen to be fixed to the body).
fn bodies_at_first_pose(sheet: &Sheet, out: &mut String) {
    let topo = sheet.topology();
    for (b, body) in sheet.input.problem.bodies.iter().enumerate() {
        let colour = Style::body_colour(b);
        polygon(sheet, &body.outline.transformed(&body.poses[0]), "body", Some(colour), out);
        if b < topo.body_count {
            let joints: Vec<Point> =
                topo.body_part(b).joints.iter().map(|&j| sheet.input.mechanism.joints[j]).collect();
            layers::bracket(sheet, &joints, colour, out);
        }
    }
}

/// Links, the slider block, ground symbols and joints at the first pose.
fn linkage_at_first_pose(sheet: &Sheet, out: &mut String) {
    let mechanism = sheet.input.mechanism;
    for (i, part) in mechanism.topology.parts.iter().enumerate() {
        if part.kind == PartKind::Link {
            layers::link(sheet, i, &mechanism.joints).empty(out);
        }
    }
    if let (Some(line), Some(j)) = (mechanism.slider, mechanism.topology.slider_joint) {
        let at = mechanism.joints[j];
        Element::new("g").attr("transform", format!("translate({})", sheet.num.points([at]))).open(out);
        layers::slider_block(sheet, line.direction).empty(out);
        close(out, "g");
    }
    layers::ground_symbols(sheet, out);
    for &p in &mechanism.joints {
        layers::joint(sheet, p).empty(out);
    }
}

/// Each joint's name beside it, up and to the right.
fn joint_names(sheet: &Sheet, out: &mut String) {
    let mechanism = sheet.input.mechanism;
    let offset = Vec2::new(sheet.style.joint * 1.3, sheet.style.joint * 1.3);
    for (name, &p) in mechanism.topology.joint_names.iter().zip(&mechanism.joints) {
        label(sheet, p + offset, name, "joint-label", None, out);
    }
}

/// What a person building the linkage measures, in the scene's units: every link side's length
/// (joint to joint) and every ground pivot's position. Labels at the links would bury a compact
/// linkage, so they are listed, by the joint names the drawing shows.
pub(crate) fn dimensions(input: &RenderInput) -> Vec<Vec<String>> {
    let mechanism = input.mechanism;
    let topology = &mechanism.topology;
    let (joints, names, units) = (&mechanism.joints, &topology.joint_names, &input.problem.units);
    let mut links = vec![format!("Links ({units}):")];
    for part in topology.parts.iter().filter(|p| p.kind == PartKind::Link) {
        let sides: Vec<(usize, usize)> = match part.joints[..] {
            [a, b] => vec![(a, b)],
            ref ring => (0..ring.len()).map(|i| (ring[i], ring[(i + 1) % ring.len()])).collect(),
        };
        for (a, b) in sides {
            links.push(format!("{}–{} {}", names[a], names[b], dimension(joints[a].distance(joints[b]))));
        }
    }
    let mut pivots = vec![format!("Ground pivots ({units}):")];
    for &j in topology.fixed_joints() {
        pivots.push(format!("{} ({}, {})", names[j], dimension(joints[j].x), dimension(joints[j].y)));
    }
    let mut groups = vec![links, pivots];
    if let (Some(line), Some(j)) = (mechanism.slider, topology.slider_joint) {
        let degrees = line.direction.y.atan2(line.direction.x).to_degrees();
        groups.push(vec![format!(
            "Slider ({units}): {} runs on the line through ({}, {}) at {}°",
            names[j],
            dimension(line.point.x),
            dimension(line.point.y),
            dimension(degrees)
        )]);
    }
    groups
}

/// A length or coordinate for a label: three significant figures, whole units from 100 up.
pub(crate) fn dimension(v: f64) -> String {
    let a = v.abs();
    let decimals = if a >= 100.0 {
        0
    } else if a >= 10.0 {
        1
    } else if a >= 1.0 {
        2
    } else {
        3
    };
    let text = format!("{v:.decimals$}");
    // No "-0.00" for a value that rounds to zero.
    if text.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        text.trim_start_matches('-').to_string()
    } else {
        text
    }
}
