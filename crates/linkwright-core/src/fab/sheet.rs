//! The assembly sheet: a side view of the layers at the first pose (bodies, every member on its layer,
//! pins and posts) and the order in which to put the parts together.

use super::depth::Face;
use super::fabrication::Fabrication;
use super::layout::{HookBase, MemberKind};
use super::parts::Role;
use crate::geom::{Aabb, Point, Rigid};
use std::fmt::Write as _;

/// The assembly steps, in order, as sentences.
pub fn steps(fab: &Fabrication) -> Vec<String> {
    let mut out = Vec::new();
    let parts = &fab.parts;
    let members = &fab.layout.members;
    let halves = parts.iter().any(|p| p.name.ends_with("_back"));
    out.push(format!(
        "Print the {} parts (the plates hold them all); no screws{} needed.",
        parts.len(),
        if halves { "" } else { " or glue" }
    ));
    let bodies: Vec<&str> =
        parts.iter().filter(|p| matches!(p.role, Role::Body | Role::Ground)).map(|p| p.name.as_str()).collect();
    out.push(format!("Lay {} flat, posts and pins up, in their first pose as drawn.", bodies.join(", ")));
    if let Some(frame) = parts.iter().find(|p| p.role == Role::Frame) {
        out.push(format!(
            "The scene has no fixed body: {} holds the ground joints{}; hold it (or fix it to a base) to \
             drive the mechanism.",
            frame.name,
            if fab.layout.foot.is_some() { ", on the post of foot, which stands on the table" } else { "" }
        ));
    }
    let cut: Vec<&str> = parts
        .iter()
        .filter(|p| matches!(p.role, Role::Body | Role::Ground))
        .filter(|p| p.name.rsplit_once('_').is_some_and(|(_, k)| k.parse::<u32>().is_ok()))
        .map(|p| p.name.as_str())
        .collect();
    if !cut.is_empty() {
        out.push(format!(
            "Join the pieces {} (cut to fit the bed): slide each dovetail down into its slot.",
            cut.join(", ")
        ));
    }
    if halves {
        out.push("Bodies printed in two halves: after finishing the front face, turn the object over and build the back face the same way, then glue or press the halves together.".into());
    }
    let joint = |j: usize| fab.layout_joint_name(j);
    for face in [Face::Front, Face::Back] {
        for k in 1..=fab.ordering.layers_on(face) {
            for (i, m) in
                members.iter().enumerate().filter(|(i, _)| fab.ordering.face[*i] == face && fab.ordering.layer[*i] == k)
            {
                let mut s = format!(
                    "{} face, layer {k}: {}",
                    if face == Face::Front { "Front" } else { "Back" },
                    member_part(fab, i)
                );
                if matches!(m.kind, MemberKind::Connector | MemberKind::Guide) {
                    let on = carrier_name(fab, m.carrier, m.post, face);
                    let _ = write!(s, " — its square socket onto the post on {on}");
                }
                for &j in &m.joints {
                    let seat = fab.seats.iter().find(|x| x.joint == j);
                    let carries = seat.is_some_and(|x| parts[x.pin_part].member == Some(i));
                    if m.slot.is_some_and(|slot| slot.joint == j) {
                        let _ = write!(s, "; its slot over the pin at {} (of {})", joint(j), pin_holder(fab, j));
                    } else if carries {
                        let _ = write!(s, "; its pin at {} points up", joint(j));
                    } else {
                        let _ = write!(s, "; its hole at {} over the pin of {}", joint(j), pin_holder(fab, j));
                    }
                    let outermost = fab.layout.joint_members[j].iter().all(|&o| o == i || fab.ordering.layer[o] < k);
                    if outermost && !carries {
                        let _ = write!(s, " (press until the cap at {} clicks)", joint(j));
                    }
                }
                if m.post.is_some() {
                    s.push_str(" (press until the post's cap clicks)");
                }
                out.push(s);
            }
        }
    }
    for n in 0..fab.springs.len() {
        let face = fab.ordering.spring_face[n];
        let hooks: Vec<String> = (0..2).map(|e| hook_holder(fab, 2 * n + e)).collect();
        out.push(format!(
            "Spring {}: an extension spring of at most {:.1} mm outer diameter, hung {:.1} mm beyond the {} face: hook \
             one end on the hook of {} and the other on the hook of {}.",
            n + 1,
            2.0 * fab.dims.spring_radius() * fab.dims.mm_per_unit,
            fab.spring_axis(n) * fab.dims.mm_per_unit,
            if face == Face::Front { "front" } else { "back" },
            hooks[0],
            hooks[1]
        ));
    }
    out.push("Turn the crank (or move a body by hand) from the first pose to the last: nothing should rub.".into());
    out
}

/// The printed part hook `k` stands on, in words.
pub(super) fn hook_holder(fab: &Fabrication, k: usize) -> String {
    let hook = &fab.layout.hooks[k];
    match hook.base {
        HookBase::Member(i) => member_part(fab, i).to_string(),
        HookBase::Joint(j) => format!("{} (the pin at {}, lengthened)", pin_holder(fab, j), fab.layout_joint_name(j)),
        HookBase::Body => carrier_name(fab, hook.carrier, Some(hook.at), fab.ordering.spring_face[k / 2]),
    }
}

/// The name of the part printed for member `i`.
fn member_part(fab: &Fabrication, i: usize) -> &str {
    fab.parts.iter().find(|p| p.member == Some(i)).map_or("?", |p| p.name.as_str())
}

/// The name of the part whose pin serves joint `j`.
fn pin_holder(fab: &Fabrication, j: usize) -> &str {
    fab.seats.iter().find(|s| s.joint == j).map_or("?", |s| fab.parts[s.pin_part].name.as_str())
}

/// The body part (or piece of it) that holds the point `at` of `carrier` on `face`: of a body printed
/// in two halves, the half on that face.
fn carrier_name(fab: &Fabrication, carrier: usize, at: Option<Point>, face: Face) -> String {
    // Within the outline (the profile's holes include the post's own socket).
    let holds = |p: &&super::parts::Part| {
        at.is_none_or(|a| super::shapes::Region { contours: p.profile[..1].to_vec() }.contains(a))
    };
    let holders: Vec<&super::parts::Part> =
        fab.parts.iter().filter(|p| p.carrier == carrier && p.member.is_none()).filter(holds).collect();
    holders.iter().find(|p| p.face == face).or(holders.first()).map_or("the ground".into(), |p| p.name.clone())
}

/// The sheet as SVG: the side view (x along the world, height up, exaggerated ×`zoom` for legibility)
/// and the numbered steps.
pub(crate) fn assembly_svg(fab: &Fabrication) -> String {
    let s_mm = fab.dims.mm_per_unit;
    let mut poses: Vec<Rigid> = Vec::new();
    fab.layout.carrier_poses(fab.trace.row(0), &mut poses);
    // World x-extent and heights of every part at the first pose.
    let mut boxes: Vec<(usize, f64, f64, f64, f64)> = Vec::new();
    let mut all: Option<Aabb> = None;
    for (k, p) in fab.parts.iter().enumerate() {
        let xs = p.prisms.iter().flat_map(|pr| pr.outline.iter()).map(|&q| poses[p.carrier].apply(q).x * s_mm);
        let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
        for pr in &p.prisms {
            let (z0, z1) = (pr.z.0 * s_mm, pr.z.1 * s_mm);
            let pts = pr.outline.iter().map(|&q| poses[p.carrier].apply(q).x * s_mm);
            let (a, b) = pts.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
            boxes.push((k, a, b, z0, z1));
            let bb = Aabb { min: Point::new(a, z0), max: Point::new(b, z1) };
            all = Some(all.map_or(bb, |x| x.union(&bb)));
        }
        let _ = (lo, hi);
    }
    let all = all.unwrap_or(Aabb { min: Point::ORIGIN, max: Point::new(1.0, 1.0) });
    let zoom = 3.0;
    let width = all.width().max(50.0);
    let view_h = all.height() * zoom;
    let steps = steps(fab);
    let line_h = 6.0;
    let text_top = view_h + 30.0;
    let total_h = text_top + line_h * (steps.len() as f64 + 2.0);
    let longest = steps.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f64;
    let total_w = (width + 20.0).max(260.0).max(20.0 + 2.1 * longest);
    let mut s = String::new();
    let _ = writeln!(s, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{total_w:.1}mm\" height=\"{total_h:.1}mm\" viewBox=\"0 0 {total_w:.2} {total_h:.2}\">");
    s.push_str("<style>text{font:4px sans-serif;fill:#222}.t{font-weight:bold;font-size:5px}rect{stroke:#333;stroke-width:0.15}</style>\n");
    let _ = writeln!(
        s,
        "<text class=\"t\" x=\"10\" y=\"8\">{}: side view of the layers at the first pose (heights ×{zoom})</text>",
        esc(&fab.scene_name)
    );
    let x_of = |x: f64| 10.0 + (x - all.min.x);
    let y_of = |z: f64| 14.0 + (all.max.y - z) * zoom;
    for &(k, a, b, z0, z1) in &boxes {
        let p = &fab.parts[k];
        let fill = match p.role {
            Role::Body => "#f4d58d",
            Role::Ground | Role::Frame => "#bdbdbd",
            Role::Connector => "#8ecae6",
            Role::SpringBracket => "#ffb703",
            Role::Guide => "#90be6d",
            Role::Link => {
                if p.face == Face::Front {
                    "#e76f51"
                } else {
                    "#9d4edd"
                }
            }
        };
        let _ = writeln!(
            s,
            "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"{fill}\" fill-opacity=\"0.55\"><title>{}</title></rect>",
            x_of(a),
            y_of(z1),
            (b - a).max(0.1),
            ((z1 - z0) * zoom).max(0.1),
            esc(&p.name)
        );
    }
    // Labels: each member once, at its slab.
    for p in fab.parts.iter().filter(|p| p.member.is_some()) {
        if let Some(&(_, a, _, _, z1)) = boxes.iter().find(|b| fab.parts[b.0].name == p.name) {
            let _ = writeln!(
                s,
                "<text x=\"{:.2}\" y=\"{:.2}\" font-size=\"3\">{} (L{})</text>",
                x_of(a) + 0.5,
                y_of(z1) - 0.5,
                esc(&p.name),
                p.layer
            );
        }
    }
    let _ = writeln!(
        s,
        "<text class=\"t\" x=\"10\" y=\"{:.2}\">Assembly order ({} layers)</text>",
        text_top, fab.ordering.layers
    );
    for (k, line) in steps.iter().enumerate() {
        let _ = writeln!(
            s,
            "<text x=\"10\" y=\"{:.2}\">{}. {}</text>",
            text_top + line_h * (k as f64 + 1.2),
            k + 1,
            esc(line)
        );
    }
    s.push_str("</svg>\n");
    s
}

fn esc(s: &str) -> std::borrow::Cow<'_, str> {
    crate::xml::escape(s)
}
