//! Part solids from a depth ordering (paper §7.3, fig. 9): links and connectors on their layers with
//! pins, bosses and holes at their joints, connectors held by square posts fused to the bodies, the
//! slotted slider guide, and the bodies extruded with their posts and pins.
//!
//! At every joint the members are stacked by layer. The pin is fused to the body when the joint lies
//! inside it, otherwise to the innermost member (paper fig. 9e puts it on the middle one; printing
//! flat needs it on the innermost, pointing outwards). Every member but the outermost has a boss up
//! to the next member, so the stack is held with an axial gap between neighbours; the pin ends in a
//! snap cap above the outermost member. A spring's hook is such a pin, standing on what carries it and
//! capped beyond the spring's axis.

use super::depth::{Face, Ordering};
use super::error::FabError;
use super::layout::{HookBase, Layout, MemberKind};
use super::posts::SceneShapes;
use super::settings::{Bed, Dims};
use super::shapes::{circle, rounded_outline, stadium};
use super::solid::{ring_outline, Feature, Mesh, RingShape, Slab};
use crate::geom::Point;
use i_overlay::core::overlay_rule::OverlayRule;
use serde::Serialize;

/// What a printed part is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// A binary bar or ternary plate of the linkage.
    Link,
    /// A bar fixed to a body (or the ground) by a square post, carrying a joint.
    Connector,
    /// The slider's slotted guide, fixed to the ground.
    Guide,
    /// A moving body (or one half of it when it carries parts on both faces).
    Body,
    /// A piece of the fixed bodies.
    Ground,
    /// The frame holding the ground joints of a scene without a fixed body.
    Frame,
    /// A bar fixed to a body (or the ground) by a square post, carrying a spring's hook.
    SpringBracket,
}

/// A prism: a planar region (outline minus holes) between two heights, in a part's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Prism {
    /// The region's outer boundary.
    pub outline: Vec<Point>,
    /// Holes cut out of it.
    pub holes: Vec<Vec<Point>>,
    /// Its bottom and top heights.
    pub z: (f64, f64),
}

/// A printed part.
#[derive(Clone, Debug)]
pub struct Part {
    /// Unique, usable as a file name.
    pub name: String,
    /// What the part is.
    pub role: Role,
    /// Index into [`Layout::carriers`]: what moves it.
    pub carrier: usize,
    /// The member it is, for links, connectors and the guide.
    pub member: Option<usize>,
    /// The face of the bodies it is on.
    pub face: Face,
    /// Layer (1 next to the bodies), 0 for bodies and ground.
    pub layer: u32,
    /// The solid in the carrier's frame, at its assembled heights (z = 0 is the front face of the
    /// bodies, which span `-body_thickness..0`).
    pub mesh: Mesh,
    /// The solid as prisms, same frame and heights (exact up to the snap cap's taper, which is
    /// replaced by its widest section).
    pub prisms: Vec<Prism>,
    /// Outline then holes, carrier frame: the laser-cutting profile.
    pub profile: Vec<Vec<Point>>,
    /// Bodies only: what fabrication adds to the body as drawn (the pads fused to it for posts, the
    /// whole foot of a frame), in the bodies' plane, as prisms.
    pub pads: Vec<Prism>,
    /// The solid laid flat for printing: its base face on z = 0, pins and posts pointing up.
    pub print_mesh: Mesh,
}

/// Heights `(bottom, top)`.
pub type Heights = (f64, f64);
/// A hole a pin goes through: (part, hole centre in its carrier frame, hole radius, heights).
pub type HoleSeat = (usize, Point, f64, Heights);
/// A slot a pin runs in: (part, slot ends in its carrier frame, half width, heights).
pub type SlotSeat = (usize, (Point, Point), f64, Heights);
/// A pin: (part, axis in its carrier frame, shaft heights).
type PinAt = (usize, Point, Heights);
/// One printed slab of a body: name, face, heights, the studs on it.
type Half<'a> = (String, Face, Heights, Vec<&'a Spec>);

/// A pin and the holes it must sit in, for checking.
#[derive(Clone, Debug)]
pub struct PinSeat {
    /// The joint the pin is.
    pub joint: usize,
    /// Part that carries the pin (an index into [`Fabrication::parts`](super::fabrication::Fabrication::parts)).
    pub pin_part: usize,
    /// The pin's axis in that part's carrier frame.
    pub pin_at: Point,
    /// The pin's radius.
    pub pin_radius: f64,
    /// Heights of the pin's shaft (assembled).
    pub shaft: (f64, f64),
    /// Parts with a hole for the pin: (part, hole centre in its carrier frame, hole radius, heights).
    pub holes: Vec<HoleSeat>,
    /// The guide's slot: (part, slot ends, half width, heights).
    pub slot: Option<SlotSeat>,
}

/// The shape of one feature, from which its mesh feature and its prisms both come.
enum Spec {
    Hole { c: Point, r: f64 },
    Socket { c: Point, half: f64 },
    Bossed { c: Point, r: f64, rb: f64, top: f64 },
    Stud { c: Point, steps: Vec<(f64, RingShape)>, top: f64, tip: Option<RingShape> },
}

impl Spec {
    fn feature(&self, z0: f64, z1: f64) -> Feature {
        match self {
            Spec::Hole { c, r } => Feature::hole(*c, *r, z0, z1),
            Spec::Socket { c, half } => Feature::socket(*c, *half, z0, z1),
            Spec::Bossed { c, r, rb, top } => Feature::bossed_hole(*c, *r, *rb, z0, z1, *top),
            Spec::Stud { c, steps, top, tip } => Feature::stud(*c, z1, steps, *top, *tip),
        }
    }
    /// The hole this feature cuts through the slab.
    fn slab_hole(&self, seg: usize) -> Option<Vec<Point>> {
        match self {
            Spec::Hole { c, r } | Spec::Bossed { c, r, .. } => Some(circle(*c, *r, seg)),
            Spec::Socket { c, half } => Some(ring_outline(*c, RingShape::Square(*half), seg)),
            Spec::Stud { .. } => None,
        }
    }
    /// Prisms above the slab's top face `z1`.
    fn prisms(&self, z1: f64, seg: usize) -> Vec<Prism> {
        match self {
            Spec::Bossed { c, r, rb, top } => {
                vec![Prism { outline: circle(*c, *rb, seg), holes: vec![circle(*c, *r, seg)], z: (z1, *top) }]
            }
            Spec::Stud { c, steps, top, .. } => {
                let mut out = Vec::new();
                for (k, &(z, shape)) in steps.iter().enumerate() {
                    let end = steps.get(k + 1).map_or(*top, |s| s.0);
                    if end > z {
                        out.push(Prism { outline: ring_outline(*c, shape, seg), holes: vec![], z: (z, end) });
                    }
                }
                out
            }
            _ => Vec::new(),
        }
    }
}

/// Builds every part. `layer_z(k)` heights follow paper eq. 20 ([`Dims::layer_bottom`]).
pub(crate) fn build(
    shapes: &SceneShapes,
    layout: &Layout,
    ordering: &Ordering,
    body_names: &[String],
    bed: &Bed,
) -> Result<(Vec<Part>, Vec<PinSeat>), FabError> {
    let stacking = Stacking::new(shapes, layout, ordering);
    let mut parts: Vec<Part> = Vec::new();
    // Pins and holes are recorded per joint while the members are built.
    let mut seats = JointSeats::new(layout.joint_members.len());
    for i in 0..layout.members.len() {
        let part = stacking.member_part(i, parts.len(), &mut seats)?;
        parts.push(part);
    }
    // Bodies and ground: slabs with the posts and pins that stand on them, per face.
    for (c, _) in layout.carriers.iter().enumerate().take(1 + shapes.bodies.len()) {
        stacking.carrier_parts(c, body_names, bed, &mut parts, &mut seats)?;
    }
    Ok((parts, seats.pin_seats(layout.dims.pin_radius)))
}

/// What every part is built from: the scene's shapes, the layout, the ordering's layers and each
/// joint's members from the innermost out.
struct Stacking<'a> {
    shapes: &'a SceneShapes,
    layout: &'a Layout,
    ordering: &'a Ordering,
    d: &'a Dims,
    /// Each joint's members from the innermost out.
    stacks: Vec<Vec<usize>>,
}

/// What stands on one carrier's slab: the studs on each face (pins, posts, hooks), and the joints'
/// pins among them as `(joint, position, face, shaft heights)`.
struct SlabStuds {
    front: Vec<Spec>,
    back: Vec<Spec>,
    pins: Vec<(usize, Point, Face, Heights)>,
}

/// One piece of a carrier's slab as it is printed.
struct SlabPiece<'a> {
    name: String,
    /// Its outline, then its holes.
    contours: Vec<Vec<Point>>,
    /// The slab as drawn, which the piece less is what fabrication adds to the body (the pads, the
    /// whole foot of a frame); `None` when nothing is added.
    drawn: Option<&'a [Vec<Point>]>,
}

/// The pins and the holes and slot each sits in, by joint, recorded while the parts are built.
struct JointSeats {
    pin: Vec<Option<PinAt>>,
    holes: Vec<Vec<HoleSeat>>,
    slot: Vec<Option<SlotSeat>>,
}

impl JointSeats {
    fn new(joints: usize) -> JointSeats {
        JointSeats { pin: vec![None; joints], holes: vec![Vec::new(); joints], slot: vec![None; joints] }
    }

    /// Every pin of radius `pin_radius` with the holes and the slot it sits in.
    fn pin_seats(self, pin_radius: f64) -> Vec<PinSeat> {
        let mut seats = Vec::new();
        for (j, pin) in self.pin.iter().enumerate() {
            let Some((pin_part, pin_at, shaft)) = *pin else { continue };
            seats.push(PinSeat {
                joint: j,
                pin_part,
                pin_at,
                pin_radius,
                shaft,
                holes: self.holes[j].clone(),
                slot: self.slot[j],
            });
        }
        seats
    }
}

impl<'a> Stacking<'a> {
    fn new(shapes: &'a SceneShapes, layout: &'a Layout, ordering: &'a Ordering) -> Stacking<'a> {
        let stacks = layout
            .joint_members
            .iter()
            .map(|l| {
                let mut l = l.clone();
                l.sort_by_key(|&i| ordering.layer[i]);
                l
            })
            .collect();
        Stacking { shapes, layout, ordering, d: &layout.dims, stacks }
    }

    /// The bottom of member `i`'s layer.
    fn bottom(&self, i: usize) -> f64 {
        self.d.layer_bottom(self.ordering.layer[i])
    }

    /// The top of member `i`'s layer.
    fn top(&self, i: usize) -> f64 {
        self.d.layer_top(self.ordering.layer[i])
    }

    /// The base of the caps of `spring`'s hooks: the springs hang beyond the outermost layer of their
    /// face.
    fn hook_cap(&self, spring: usize) -> f64 {
        let ordering = self.ordering;
        self.d.hook_cap_base(ordering.layers_on(ordering.spring_face[spring]), ordering.spring_level[spring])
    }

    /// A hook of `spring` at `c`, standing on `base`.
    fn hook_stud(&self, c: Point, base: f64, spring: usize) -> Spec {
        let d = self.d;
        let zc = self.hook_cap(spring);
        let steps = vec![(base, RingShape::Circle(d.pin_radius)), (zc, RingShape::Circle(d.cap_base_radius))];
        Spec::Stud { c, steps, top: zc + d.cap_height, tip: Some(RingShape::Circle(d.cap_tip_radius)) }
    }

    /// Where joint `j`'s pin ends in its snap cap: above the outermost member on the joint, or beyond
    /// the spring's axis when a spring hooks on it.
    fn cap_base(&self, j: usize) -> f64 {
        let hooked = self.layout.hooks.iter().find(|h| h.base == HookBase::Joint(j));
        match (hooked, self.stacks[j].last()) {
            (Some(h), _) => self.hook_cap(h.spring),
            (None, Some(&i)) => self.top(i) + self.d.gap,
            (None, None) => 0.0,
        }
    }

    /// The steps of joint `j`'s pin standing on `base`, with a collar up to `collar_top` when that is
    /// above the base, and the height of its tip.
    fn pin_steps(&self, base: f64, collar_top: f64, j: usize) -> (Vec<(f64, RingShape)>, f64) {
        let d = self.d;
        let zc = self.cap_base(j);
        let mut steps = Vec::new();
        if collar_top > base + 1e-9 {
            steps.push((base, RingShape::Circle(d.boss_radius)));
            steps.push((collar_top, RingShape::Circle(d.pin_radius)));
        } else {
            steps.push((base, RingShape::Circle(d.pin_radius)));
        }
        steps.push((zc, RingShape::Circle(d.cap_base_radius)));
        (steps, zc + d.cap_height)
    }

    /// Height `z` on the front face mirrored to the back face.
    fn mirror_z(&self, z: f64) -> f64 {
        -self.d.body_thickness - z
    }

    /// Member `i`'s part (to be `parts[part_index]`): its plate on its layer, with at each joint the
    /// pin (innermost member, unless the pin is fused to a body), a boss (members below the outermost)
    /// or a hole, the socket of its post, and the hooks standing on it. Records its pins, holes and
    /// slot in `seats`.
    fn member_part(&self, i: usize, part_index: usize, seats: &mut JointSeats) -> Result<Part, FabError> {
        let (d, layout) = (self.d, self.layout);
        let seg = d.segments;
        let m = &layout.members[i];
        let (z0, z1) = (self.bottom(i), self.top(i));
        let mut specs = Vec::new();
        let mut holes = Vec::new();
        let face = self.ordering.face[i];
        let zr = |a: f64, b: f64| if face == Face::Front { (a, b) } else { (self.mirror_z(b), self.mirror_z(a)) };
        for &j in &m.joints {
            let stack = &self.stacks[j];
            let pos = stack.iter().position(|&x| x == i).unwrap_or(0);
            let Some(at) = m.joint_at(j) else {
                if let Some(slot) = m.slot.filter(|s| s.joint == j) {
                    let (s0, s1) = slot.ends;
                    holes.push(stadium(s0, s1, d.hole_radius, seg));
                    seats.slot[j] = Some((part_index, (s0, s1), d.hole_radius, zr(z0, z1)));
                }
                continue;
            };
            if pos == 0 && layout.body_pins[j].is_none() {
                let collar_top = stack.get(1).map_or(z1, |&n| self.bottom(n) - d.gap);
                let (steps, tip) = self.pin_steps(z1, collar_top, j);
                seats.pin[j] = Some((part_index, at, zr(z1, self.cap_base(j))));
                specs.push(Spec::Stud { c: at, steps, top: tip, tip: Some(RingShape::Circle(d.cap_tip_radius)) });
            } else if pos + 1 < stack.len() {
                let boss_top = self.bottom(stack[pos + 1]) - d.gap;
                seats.holes[j].push((part_index, at, d.hole_radius, zr(z0, boss_top)));
                specs.push(Spec::Bossed { c: at, r: d.hole_radius, rb: d.boss_radius, top: boss_top });
            } else {
                seats.holes[j].push((part_index, at, d.hole_radius, zr(z0, z1)));
                specs.push(Spec::Hole { c: at, r: d.hole_radius });
            }
        }
        if let Some(p) = m.post {
            specs.push(Spec::Socket { c: p, half: d.post_half + d.clearance });
        }
        for h in layout.hooks.iter().filter(|h| h.base == HookBase::Member(i)) {
            specs.push(self.hook_stud(h.at, z1, h.spring));
        }
        let outline = rounded_outline(&m.core, d.half_width, seg);
        let role = match m.kind {
            MemberKind::Link => Role::Link,
            MemberKind::Connector => Role::Connector,
            MemberKind::Guide => Role::Guide,
            MemberKind::Frame => Role::Frame,
            MemberKind::Bracket => Role::SpringBracket,
        };
        let layer = self.ordering.layer[i];
        assemble(m.name.clone(), role, m.carrier, Some(i), face, layer, outline, holes, (z0, z1), &specs, seg, d)
    }

    /// The parts of carrier `c` (the ground or a body): its slab in the pieces it is printed as,
    /// each on one face or split into a front and a back half when studs stand on both. Records the
    /// pins fused to it in `seats`.
    fn carrier_parts(
        &self,
        c: usize,
        body_names: &[String],
        bed: &Bed,
        parts: &mut Vec<Part>,
        seats: &mut JointSeats,
    ) -> Result<(), FabError> {
        let (d, layout) = (self.d, self.layout);
        let studs = self.slab_studs(c);
        for (name, outline, holes) in self.slab_outlines(c, body_names) {
            let region = super::shapes::Region {
                contours: std::iter::once(outline.clone()).chain(holes.iter().cloned()).collect(),
            };
            let pads = self.pads_on(c, &region);
            let merged = super::shapes::union_with_discs(&region.contours, &pads, d.segments);
            // What fabrication adds to the body as drawn (the pads, the whole foot), which the check
            // tests against the other bodies.
            let drawn: &[Vec<Point>] = if layout.foot.is_some() && c == 0 { &[] } else { &region.contours };
            for (name, contours) in self.bed_pieces(name, merged, &studs, bed) {
                let piece = SlabPiece { name, contours, drawn: (!pads.is_empty()).then_some(drawn) };
                self.piece_parts(c, piece, &studs, parts, seats)?;
            }
        }
        Ok(())
    }

    /// What stands on carrier `c`'s slab: the joints' pins fused to it, the hooks standing on it and
    /// the posts of the members it carries, each on its face.
    fn slab_studs(&self, c: usize) -> SlabStuds {
        let (d, layout, ordering) = (self.d, self.layout, self.ordering);
        let mut studs = SlabStuds { front: Vec::new(), back: Vec::new(), pins: Vec::new() };
        for (j, bp) in layout.body_pins.iter().enumerate() {
            let Some(bp) = bp.filter(|b| b.carrier == c) else { continue };
            let stack = &self.stacks[j];
            let Some(&first) = stack.first() else { continue };
            let face = ordering.face[first];
            let (steps, tip) = self.pin_steps(0.0, self.bottom(first) - d.gap, j);
            studs.pins.push((j, bp.at, face, (0.0, self.cap_base(j))));
            let spec = Spec::Stud { c: bp.at, steps, top: tip, tip: Some(RingShape::Circle(d.cap_tip_radius)) };
            studs.on(face, spec);
        }
        for h in layout.hooks.iter().filter(|h| h.base == HookBase::Body && h.carrier == c) {
            studs.on(ordering.spring_face[h.spring], self.hook_stud(h.at, 0.0, h.spring));
        }
        for (i, m) in layout.members.iter().enumerate() {
            let (Some(p), true) = (m.post, m.carrier == c) else { continue };
            let collar_top = self.bottom(i) - d.gap;
            let mut steps = Vec::new();
            if collar_top > 1e-9 {
                steps.push((0.0, RingShape::Circle(d.post_collar_radius)));
                steps.push((collar_top, RingShape::Square(d.post_half)));
            } else {
                steps.push((0.0, RingShape::Square(d.post_half)));
            }
            let zc = self.top(i) + d.gap;
            steps.push((zc, RingShape::Square(d.post_cap_half)));
            let tip_half = (d.post_half - (d.pin_radius - d.cap_tip_radius)).max(0.25 * d.post_half);
            let spec = Spec::Stud { c: p, steps, top: zc + d.cap_height, tip: Some(RingShape::Square(tip_half)) };
            studs.on(ordering.face[i], spec);
        }
        studs
    }

    /// The slab pieces carrier `c` is printed as, each a name, an outline and its holes: the frame's
    /// foot, the pieces of the ground, or the body.
    fn slab_outlines(&self, c: usize, body_names: &[String]) -> Vec<(String, Vec<Point>, Vec<Vec<Point>>)> {
        let (shapes, seg) = (self.shapes, self.d.segments);
        if let (0, Some(foot)) = (c, self.layout.foot) {
            vec![("foot".to_string(), circle(foot.centre, foot.radius, seg), Vec::new())]
        } else if c == 0 {
            let many = shapes.ground.len() > 1;
            shapes
                .ground
                .iter()
                .enumerate()
                .map(|(k, r)| {
                    let name = if many { format!("ground_{}", k + 1) } else { "ground".to_string() };
                    (name, r.contours[0].clone(), r.contours[1..].to_vec())
                })
                .collect()
        } else {
            vec![(body_names[c - 1].clone(), shapes.bodies[c - 1].contours[0].clone(), Vec::new())]
        }
    }

    /// The pads fused to `region`, a slab piece of carrier `c` (each pad on the piece it is fused to:
    /// the nearest, when the ground is in pieces), and the frame's foot on the ground, which is tested
    /// against the bodies like a pad (it is no body as drawn).
    fn pads_on(&self, c: usize, region: &super::shapes::Region) -> Vec<(Point, f64)> {
        let layout = self.layout;
        let nearest_piece = |p: Point| {
            let depth = |r: &super::shapes::Region| r.depth(p);
            self.shapes.carrier_regions(c).iter().map(depth).fold(f64::NEG_INFINITY, f64::max)
        };
        layout
            .pads
            .iter()
            .filter(|p| p.carrier == c && region.depth(p.centre) >= nearest_piece(p.centre))
            .chain(layout.foot.iter().filter(|_| c == 0))
            .map(|p| (p.centre, p.radius))
            .collect()
    }

    /// The slab `merged` (outline, then holes), named `name`, as pieces that fit the bed: itself, or
    /// when too large for the bed, cut into pieces joined by dovetails, clear of the studs.
    fn bed_pieces(
        &self,
        name: String,
        merged: Vec<Vec<Point>>,
        studs: &SlabStuds,
        bed: &Bed,
    ) -> Vec<(String, Vec<Vec<Point>>)> {
        let d = self.d;
        let mm: Vec<Point> = merged[0].iter().map(|p| Point::new(p.x * d.mm_per_unit, p.y * d.mm_per_unit)).collect();
        if super::plates::fits_bed(&mm, bed) {
            return vec![(name, merged)];
        }
        let keep: Vec<(Point, f64)> = studs.front.iter().chain(studs.back.iter()).filter_map(stud_disc).collect();
        let fits = |outline: &[Point]| {
            let mm: Vec<Point> = outline.iter().map(|p| Point::new(p.x * d.mm_per_unit, p.y * d.mm_per_unit)).collect();
            super::plates::fits_bed(&mm, bed)
        };
        match super::split::split(&merged, super::plates::long_axis(&merged[0]), &keep, d, &fits) {
            Some(split) => split.into_iter().enumerate().map(|(k, c)| (format!("{name}_{}", k + 1), c)).collect(),
            None => vec![(name, merged)],
        }
    }

    /// The parts of `piece` of carrier `c`'s slab: one slab with the studs standing on it, or a front
    /// and a back half when studs stand on both faces. Records the pins fused to it in `seats`.
    fn piece_parts(
        &self,
        c: usize,
        piece: SlabPiece,
        studs: &SlabStuds,
        parts: &mut Vec<Part>,
        seats: &mut JointSeats,
    ) -> Result<(), FabError> {
        let d = self.d;
        let SlabPiece { name, contours, drawn } = piece;
        let (outline, holes) = (contours[0].clone(), contours[1..].to_vec());
        let region = super::shapes::Region { contours };
        let mine = |s: &Spec| match s {
            Spec::Stud { c, .. } => region.contains(*c),
            _ => false,
        };
        let f: Vec<&Spec> = studs.front.iter().filter(|s| mine(s)).collect();
        let b: Vec<&Spec> = studs.back.iter().filter(|s| mine(s)).collect();
        let t = d.body_thickness;
        let halves: Vec<Half> = match (f.is_empty(), b.is_empty()) {
            (_, true) => vec![(name.clone(), Face::Front, (-t, 0.0), f)],
            (true, false) => vec![(name.clone(), Face::Back, (-t, 0.0), b)],
            (false, false) => vec![
                (format!("{name}_front"), Face::Front, (-0.5 * t, 0.0), f),
                (format!("{name}_back"), Face::Back, (-0.5 * t, 0.0), b),
            ],
        };
        let role = if c == 0 { Role::Ground } else { Role::Body };
        for (pname, face, (z0, z1), specs) in halves {
            let idx = parts.len();
            for &(j, at, pf, shaft) in &studs.pins {
                if pf == face && region.contains(at) {
                    let shaft =
                        if face == Face::Front { shaft } else { (self.mirror_z(shaft.1), self.mirror_z(shaft.0)) };
                    seats.pin[j] = Some((idx, at, shaft));
                }
            }
            let owned: Vec<Spec> = specs.into_iter().map(clone_spec).collect();
            let mut part = assemble(
                pname,
                role,
                c,
                None,
                face,
                0,
                outline.clone(),
                holes.clone(),
                (z0, z1),
                &owned,
                d.segments,
                d,
            )?;
            let zr = part.prisms[0].z;
            if let Some(drawn) = drawn {
                part.pads = super::shapes::overlay(&region.contours, drawn, OverlayRule::Difference)
                    .into_iter()
                    .filter(|c| !sliver(&c[0], d.wall))
                    .map(|mut c| Prism { outline: c.remove(0), holes: c, z: zr })
                    .collect();
            }
            parts.push(part);
        }
        Ok(())
    }
}

impl SlabStuds {
    /// Adds `spec` to the studs of `face`.
    fn on(&mut self, face: Face, spec: Spec) {
        match face {
            Face::Front => self.front.push(spec),
            Face::Back => self.back.push(spec),
        }
    }
}

/// Whether a piece of a polygon difference is a sliver left by rounding (on average thinner than a
/// tenth of a wall) rather than material.
fn sliver(outline: &[Point], wall: f64) -> bool {
    let poly = crate::geom::Polygon::new(outline.to_vec());
    let perimeter: f64 = poly.edges().map(|(a, b)| a.distance(b)).sum();
    2.0 * poly.area() < 0.1 * wall * perimeter
}

/// The disc a stud stands on: its centre and widest radius.
fn stud_disc(s: &Spec) -> Option<(Point, f64)> {
    match s {
        Spec::Stud { c, steps, .. } => {
            let r = steps
                .iter()
                .map(|&(_, shape)| match shape {
                    RingShape::Circle(r) => r,
                    RingShape::Square(h) => h * std::f64::consts::SQRT_2,
                    RingShape::Apex => 0.0,
                })
                .fold(0.0, f64::max);
            Some((*c, r))
        }
        _ => None,
    }
}

fn clone_spec(s: &Spec) -> Spec {
    match s {
        Spec::Hole { c, r } => Spec::Hole { c: *c, r: *r },
        Spec::Socket { c, half } => Spec::Socket { c: *c, half: *half },
        Spec::Bossed { c, r, rb, top } => Spec::Bossed { c: *c, r: *r, rb: *rb, top: *top },
        Spec::Stud { c, steps, top, tip } => Spec::Stud { c: *c, steps: steps.clone(), top: *top, tip: *tip },
    }
}

/// One part: its slab with features meshed in front-face heights, then placed on its face.
#[allow(clippy::too_many_arguments, reason = "one call site per kind of part; a struct would only rename them")]
fn assemble(
    name: String,
    role: Role,
    carrier: usize,
    member: Option<usize>,
    face: Face,
    layer: u32,
    outline: Vec<Point>,
    mut holes: Vec<Vec<Point>>,
    (z0, z1): (f64, f64),
    specs: &[Spec],
    seg: usize,
    d: &Dims,
) -> Result<Part, FabError> {
    let contour_holes = holes.clone();
    let slab = Slab {
        outline: outline.clone(),
        holes: contour_holes,
        z0,
        z1,
        through: specs.iter().filter(|s| !matches!(s, Spec::Stud { .. })).map(|s| s.feature(z0, z1)).collect(),
        studs: specs.iter().filter(|s| matches!(s, Spec::Stud { .. })).map(|s| s.feature(z0, z1)).collect(),
    };
    let local = slab.mesh(seg).map_err(|e| FabError::Mesh(format!("{name}: {e}")))?;
    holes.extend(specs.iter().filter_map(|s| s.slab_hole(seg)));
    let mut prisms = vec![Prism { outline: outline.clone(), holes: holes.clone(), z: (z0, z1) }];
    for s in specs {
        prisms.extend(s.prisms(z1, seg));
    }
    let (lo, _) = local.bounds();
    let print_mesh = local.mapped(|v| [v[0], v[1], v[2] - lo[2]], false);
    let t = d.body_thickness;
    let (mesh, prisms) = if face == Face::Front {
        (local, prisms)
    } else {
        // Mirror through the bodies' middle plane: z ↦ −t − z (reverses orientation).
        let m = local.mapped(|v| [v[0], v[1], -t - v[2]], true);
        let p = prisms.into_iter().map(|p| Prism { z: (-t - p.z.1, -t - p.z.0), ..p }).collect();
        (m, p)
    };
    // The laser-cutting profile: a cut part takes separate pins and posts, so every stud becomes a hole
    // (a round pin hole, or the square socket of a post).
    let mut profile = vec![outline];
    profile.extend(holes);
    for s in specs {
        if let Spec::Stud { c, steps, .. } = s {
            let square = steps.iter().any(|&(_, shape)| matches!(shape, RingShape::Square(_)));
            profile.push(if square {
                ring_outline(*c, RingShape::Square(d.post_half + d.clearance), seg)
            } else {
                circle(*c, d.hole_radius, seg)
            });
        }
    }
    Ok(Part { name, role, carrier, member, face, layer, mesh, prisms, profile, print_mesh, pads: Vec::new() })
}
