//! Connecting the linkage to the bodies (paper §7.1): which printed members exist (links, joint
//! connectors, the slider guide, the frame of a scene without a fixed body), which rigid carrier each
//! rides on, where connector posts stand on the bodies ([`super::posts`]), and which joints are pins
//! fused straight onto a body, and where the hooks of counterbalance springs stand ([`Hook`]).

use super::error::{FabError, HookRefusal};
use super::plates::{self, Misfit};
use super::posts::{self, Pad, Pillar, SceneShapes};
use super::settings::{Bed, Dims};
use crate::geom::{point_segment_distance, Point, Rigid};
use crate::kinematics::{BodyFrames, Trace};
use crate::mechanism::{Mechanism, PartKind};
use serde::{Deserialize, Serialize};

/// A rigid thing the printed members ride on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Carrier {
    /// The fixed bodies.
    Ground,
    /// Moving body with this index.
    Body(usize),
    /// The link part with this index in the topology's parts.
    Link(usize),
}

/// What a printed member is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MemberKind {
    /// A binary bar or a ternary plate of the linkage.
    Link,
    /// A joint connector: a bar fixed to a body (or the ground) by a square post, carrying a joint.
    Connector,
    /// The slider's guide: a slotted plate fixed to the ground by a post.
    Guide,
    /// A scene without a fixed body: a plate on its own layer joining the ground joints (and holding
    /// the slider's slot), which the hand holds or a base is fixed to.
    Frame,
    /// A bar fixed to a body (or the ground) by a square post, carrying a spring's hook where the
    /// body has no room for it.
    Bracket,
}

/// Where a counterbalance spring is hooked: a part of the design and a point on it, scene units, at
/// the first pose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Anchor {
    /// The part's name, as in the design's `mechanism.parts` (the fixed part for a ground anchor).
    pub part: String,
    /// Where on it, at the first pose.
    pub point: Point,
}

/// An extension spring to hook: its ground end, then its moving end.
pub type SpringEnds = [Anchor; 2];

/// What a spring's hook stands on. The hook is a capped pin pointing away from the bodies; the
/// springs hang beyond the outermost layer of their face, so every part the hook rises through must
/// stay clear of it along the motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HookBase {
    /// The slab of its carrier (a moving body or the ground).
    Body,
    /// This member: a link (its plate reaching the anchor), a bracket, or the frame.
    Member(usize),
    /// The pin of this joint, lengthened beyond the outermost member on it.
    Joint(usize),
}

/// One hook of a counterbalance spring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hook {
    /// The spring's index in the springs asked for; its two hooks are the ground end, then the moving end.
    pub spring: usize,
    /// Index into [`Layout::carriers`]: what carries the hook.
    pub carrier: usize,
    /// Where it stands, carrier frame.
    pub at: Point,
    /// What it stands on.
    pub base: HookBase,
}

/// The slot a slider's pin runs in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slot {
    /// The slider joint.
    pub joint: usize,
    /// The ends of the slot's centre line, ground frame.
    pub ends: (Point, Point),
}

/// A flat printed part on one layer: the convex hull of discs of radius `half_width` around `core`.
#[derive(Clone, Debug, PartialEq)]
pub struct Member {
    /// Unique among the members: a link's part name, `connector_JOINT`, `slider_guide` or `frame`.
    pub name: String,
    /// What the member is.
    pub kind: MemberKind,
    /// Index into [`Layout::carriers`].
    pub carrier: usize,
    /// Disc centres in the carrier's frame: links and the frame their joints in order (then the
    /// frame's slot ends), connectors their post then their joint, the guide its slot ends then its post.
    pub core: Vec<Point>,
    /// The joints this member turns on (or slides on, for the slot).
    pub joints: Vec<usize>,
    /// Connectors and the guide: where the square post stands, carrier frame.
    pub post: Option<Point>,
    /// The guide (or the frame): the slot its slider joint runs in.
    pub slot: Option<Slot>,
}

impl Member {
    /// Where the member turns on joint `j`, carrier frame: `None` for a joint it does not carry or
    /// the one running in its slot.
    pub fn joint_at(&self, j: usize) -> Option<Point> {
        if self.slot.is_some_and(|s| s.joint == j) {
            return None;
        }
        let k = self.joints.iter().position(|&x| x == j)?;
        match self.kind {
            MemberKind::Connector => self.core.get(1).copied(),
            MemberKind::Link | MemberKind::Frame => self.core.get(k).copied(),
            MemberKind::Guide | MemberKind::Bracket => None,
        }
    }
}

/// A joint pin fused to a body or the ground (the joint lies deep enough inside it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPin {
    /// The body (or the ground) it stands on, as an index into [`Layout::carriers`].
    pub carrier: usize,
    /// Position in the carrier's frame.
    pub at: Point,
}

/// Every printed member and how it is carried, for one mechanism in one scene.
#[derive(Clone, Debug)]
pub struct Layout {
    /// Every rigid thing a member rides on: the ground, then each moving body, then each link.
    pub carriers: Vec<Carrier>,
    /// For each carrier, the first two joints whose frame places it (links), unused otherwise.
    link_frames: Vec<(usize, usize)>,
    /// Every printed member.
    pub members: Vec<Member>,
    /// `L_j` of paper eq. 17: the members that turn on joint j.
    pub joint_members: Vec<Vec<usize>>,
    /// Joints whose pin is fused to a body or the ground.
    pub body_pins: Vec<Option<BodyPin>>,
    /// The slider joint, if any (its pin runs in the guide's slot).
    pub slider_joint: Option<usize>,
    /// Round pads added to bodies too thin for a post. They are fused to the body's outline, in the
    /// bodies' plane, and checked against every other body along the motion.
    pub pads: Vec<Pad>,
    /// The hooks of the counterbalance springs, two per spring (ground end first).
    pub hooks: Vec<Hook>,
    /// The frame's foot in a scene without a fixed body: a disc in the bodies' plane, standing on the
    /// table where no body comes along the motion, carrying the frame's post.
    pub foot: Option<Pad>,
    /// The print settings in scene units.
    pub dims: Dims,
    frames: BodyFrames,
}

impl Layout {
    /// Connects every joint of `mechanism` to the parts that carry it. `trace` is the motion (its rows
    /// give the slider's stroke).
    /// With `body_pins`, a joint lying deep inside its body gets a pin fused to the body; without, every
    /// body joint gets a connector (as in the paper), which leaves the solver more freedom. Each of
    /// `springs` gets a hook at both ends, placed like a joint's pin: on the joint when the anchor is
    /// one, on a link's plate (widened to reach it), fused to the body when deep inside it, otherwise on
    /// a bracket from a post.
    pub(crate) fn new(
        shapes: &SceneShapes,
        mechanism: &Mechanism,
        trace: &Trace,
        body_pins: bool,
        springs: &[SpringEnds],
    ) -> Result<Layout, FabError> {
        let topo = &mechanism.topology;
        let dims = shapes.dims;
        if topo.body_count != shapes.bodies.len() {
            return Err(FabError::Mismatch(format!(
                "the design moves {} bodies, the scene has {}",
                topo.body_count,
                shapes.bodies.len()
            )));
        }
        let frames = BodyFrames::new(mechanism, &shapes.first_poses);
        let placed = Placed::links(mechanism, dims)?;
        let sweep = Sweep::new(&placed, &frames, trace, dims);
        // Every carrier's pose along the motion, for pads (computed when a body needs one).
        let poses = std::cell::OnceCell::new();
        let poses = || poses.get_or_init(|| posts::Poses::new(&frames, trace));
        let standing =
            Standing { shapes, poses: &poses, pillars: vec![Vec::new(); placed.carriers.len()], pads: Vec::new() };
        let mut connecting = Connecting { shapes, mechanism, trace, frames: &frames, sweep, standing, placed };
        let (pins, frame_joints) = connecting.joints(body_pins)?;
        let frame_slot = connecting.slider_guide()?;
        let foot = connecting.frame(&frame_joints, frame_slot)?;
        let hooks = connecting.hooks(springs, body_pins)?;
        let Connecting { placed: Placed { carriers, link_frames, members, joint_members }, standing, .. } = connecting;
        let layout = Layout {
            carriers,
            link_frames,
            members,
            joint_members,
            body_pins: pins,
            slider_joint: topo.slider_joint,
            pads: standing.pads,
            hooks,
            foot,
            dims,
            frames,
        };
        Ok(layout)
    }

    /// Every carrier's `carrier_to_world` in the configuration `row`.
    pub fn carrier_poses(&self, row: &[Point], out: &mut Vec<Rigid>) {
        out.clear();
        for (c, carrier) in self.carriers.iter().enumerate() {
            out.push(match *carrier {
                Carrier::Ground => Rigid::IDENTITY,
                Carrier::Body(b) => self.frames.pose(b, row),
                Carrier::Link(_) => {
                    let (a, b) = self.link_frames[c];
                    link_frame(row[a], row[b])
                }
            });
        }
    }

    /// The members that fit the print bed in no turn, each with what it would take.
    pub fn off_bed(&self, bed: &Bed) -> Vec<(usize, Misfit)> {
        let mm = self.dims.mm_per_unit;
        self.members
            .iter()
            .enumerate()
            .filter_map(|(i, m)| {
                let core: Vec<Point> = m.core.iter().map(|p| Point::new(p.x * mm, p.y * mm)).collect();
                plates::misfit(&core, self.dims.half_width * mm, bed).map(|f| (i, f))
            })
            .collect()
    }

    /// [`FabError::OffBed`] for the members in `misfits` (as [`Layout::off_bed`] gives them).
    pub(crate) fn off_bed_error(&self, misfits: &[(usize, Misfit)], bed: &Bed) -> FabError {
        let parts: Vec<String> = misfits
            .iter()
            .map(|(i, f)| format!("{} ({:.0} × {:.0} mm)", self.members[*i].name, f.footprint_mm[0], f.footprint_mm[1]))
            .collect();
        FabError::OffBed {
            parts: parts.join(", "),
            width: bed.width - 2.0 * bed.margin,
            depth: bed.depth - 2.0 * bed.margin,
            square_bed_mm: misfits.iter().map(|m| m.1.square_bed_mm).fold(0.0, f64::max),
            max_scale: misfits.iter().map(|m| m.1.max_scale).fold(f64::INFINITY, f64::min),
        }
    }

    /// Where hook `k` stands in the configuration `row`, given every carrier's pose there.
    pub fn hook_at(&self, k: usize, row: &[Point], poses: &[Rigid]) -> Point {
        let hook = &self.hooks[k];
        match hook.base {
            HookBase::Joint(j) => row[j],
            _ => poses[hook.carrier].apply(hook.at),
        }
    }

    /// How many springs have hooks.
    pub fn spring_count(&self) -> usize {
        self.hooks.iter().map(|h| h.spring + 1).max().unwrap_or(0)
    }

    /// The member whose name is `name`.
    pub fn member(&self, name: &str) -> Option<usize> {
        self.members.iter().position(|m| m.name == name)
    }
}

/// The carriers and the members placed so far, while [`Layout::new`] adds them kind by kind.
struct Placed {
    carriers: Vec<Carrier>,
    /// For each carrier, the first two joints whose frame places it (links), unused otherwise.
    link_frames: Vec<(usize, usize)>,
    members: Vec<Member>,
    /// The members that turn on each joint.
    joint_members: Vec<Vec<usize>>,
}

impl Placed {
    /// The ground and the moving bodies, then a carrier and a member for each link of `mechanism`.
    fn links(mechanism: &Mechanism, dims: Dims) -> Result<Placed, FabError> {
        let topo = &mechanism.topology;
        let mut placed = Placed {
            carriers: vec![Carrier::Ground],
            link_frames: vec![(0, 0)],
            members: Vec::new(),
            joint_members: vec![Vec::new(); topo.joint_count()],
        };
        for b in 0..topo.body_count {
            placed.carriers.push(Carrier::Body(b));
            placed.link_frames.push((0, 0));
        }
        for (pi, part) in topo.parts.iter().enumerate() {
            if part.kind != PartKind::Link {
                continue;
            }
            if part.joints.len() < 2 {
                return Err(FabError::Mismatch(format!("link {} carries fewer than two joints", part.name)));
            }
            let (a, b) = (part.joints[0], part.joints[1]);
            let frame = link_frame(mechanism.joints[a], mechanism.joints[b]);
            let c = placed.carriers.len();
            placed.carriers.push(Carrier::Link(pi));
            placed.link_frames.push((a, b));
            let core: Vec<Point> = part.joints.iter().map(|&j| frame.inverse().apply(mechanism.joints[j])).collect();
            too_close(&part.name, &part.joints, mechanism, dims)?;
            placed.push(Member {
                name: part.name.clone(),
                kind: MemberKind::Link,
                carrier: c,
                core,
                joints: part.joints.clone(),
                post: None,
                slot: None,
            });
        }
        Ok(placed)
    }

    /// Adds `member`, which turns on its joints; its index.
    fn push(&mut self, member: Member) -> usize {
        let i = self.members.len();
        for &j in &member.joints {
            self.joint_members[j].push(i);
        }
        self.members.push(member);
        i
    }
}

/// Where the links pass along the motion, to keep posts out of their way. A preference only
/// (validity comes from the recorded constraints), so every few rows suffice.
struct Sweep<'a> {
    frames: &'a BodyFrames,
    trace: &'a Trace,
    /// Every link's core (world) at every `stride`-th row, empty at the other rows.
    link_rows: Vec<Vec<Vec<Point>>>,
    stride: usize,
    /// How close to a link's core a post's collar is passed over.
    reach: f64,
}

impl<'a> Sweep<'a> {
    /// The sweep of the links `placed` holds (only links, so far).
    fn new(placed: &Placed, frames: &'a BodyFrames, trace: &'a Trace, dims: Dims) -> Sweep<'a> {
        let link_rows: Vec<Vec<Vec<Point>>> = (0..trace.len())
            .map(|r| {
                if r % trace.len().div_ceil(90).max(1) != 0 {
                    return Vec::new();
                }
                let row = trace.row(r);
                placed
                    .members
                    .iter()
                    .map(|m| {
                        let (a, b) = placed.link_frames[m.carrier];
                        let pose = link_frame(row[a], row[b]);
                        m.core.iter().map(|&c| pose.apply(c)).collect()
                    })
                    .collect()
            })
            .collect();
        Sweep {
            frames,
            trace,
            link_rows,
            stride: trace.len().div_ceil(90).max(1),
            reach: dims.half_width + dims.post_collar_radius + dims.clearance,
        }
    }

    /// Whether some link passes over point `p` of carrier `ci` (its frame) along the motion.
    fn swept(&self, ci: usize, p: Point) -> bool {
        (0..self.trace.len()).step_by(self.stride).any(|r| {
            let pose = if ci == 0 { Rigid::IDENTITY } else { self.frames.pose(ci - 1, self.trace.row(r)) };
            let w = pose.apply(p);
            self.link_rows[r].iter().any(|core| super::shapes::point_core_distance(w, core) < self.reach)
        })
    }
}

/// What [`Layout::new`] places the rest with once the links are placed: the scene and the motion,
/// where the links pass, what stands on each carrier so far, and the members placed so far.
struct Connecting<'a> {
    shapes: &'a SceneShapes,
    mechanism: &'a Mechanism,
    trace: &'a Trace,
    frames: &'a BodyFrames,
    sweep: Sweep<'a>,
    standing: Standing<'a>,
    placed: Placed,
}

impl Connecting<'_> {
    /// Joints on the ground and on bodies: a pin fused to the body when the joint lies deep inside
    /// it (with `body_pins`), otherwise a connector from a post (see [`super::posts`]). Without a
    /// fixed body, the ground joints are held by a printed frame instead. Returns each joint's pin
    /// fused to a body, and the joints the frame must hold.
    fn joints(&mut self, body_pins: bool) -> Result<(Vec<Option<BodyPin>>, Vec<usize>), FabError> {
        let (shapes, mechanism) = (self.shapes, self.mechanism);
        let topo = &mechanism.topology;
        let dims = shapes.dims;
        let mut pins = vec![None; topo.joint_count()];
        let mut connectors: Vec<Vec<(Point, Point)>> = vec![Vec::new(); self.placed.carriers.len()];
        let mut frame_joints: Vec<usize> = Vec::new();
        for part in &topo.parts {
            let (carrier, ci) = match part.kind {
                PartKind::Fixed => (Carrier::Ground, 0),
                PartKind::Body(b) => (Carrier::Body(b), 1 + b),
                PartKind::Link => continue,
            };
            let regions = shapes.carrier_regions(ci);
            if regions.is_empty() {
                frame_joints.extend(&part.joints);
                continue;
            }
            let to_local = carrier_first_pose(carrier, shapes).inverse();
            for &j in &part.joints {
                let at = to_local.apply(mechanism.joints[j]);
                if body_pins && self.standing.fuse(ci, at, dims.boss_radius) {
                    pins[j] = Some(BodyPin { carrier: ci, at });
                    continue;
                }
                // Connectors of one body must not cover each other's posts both ways (no layer order
                // could then exist): prefer posts that neither cover nor are covered, then posts that
                // are not both.
                let reach = dims.half_width + dims.post_collar_radius + dims.clearance;
                let mine = &connectors[ci];
                let clear = |p: Point, level: u8| {
                    mine.iter().all(|&(q, jq): &(Point, Point)| {
                        let new_covers_old = point_segment_distance(q, p, at) < reach;
                        let old_covers_new = point_segment_distance(p, q, jq) < reach;
                        match level {
                            2 => !new_covers_old && !old_covers_new,
                            1 => !(new_covers_old && old_covers_new),
                            _ => true,
                        }
                    })
                };
                let sweep = &self.sweep;
                let swept_here = |p: Point| sweep.swept(ci, p);
                let rules = posts::Rules { clear: &clear, swept: &swept_here };
                let min_reach = dims.boss_radius + dims.post_collar_radius + dims.wall;
                let post = self
                    .standing
                    .post(ci, (at, at), min_reach, &rules)
                    .map_err(|e| refusal(e, &topo.joint_names[j], carrier))?;
                connectors[ci].push((post, at));
                self.placed.push(Member {
                    name: format!("connector_{}", topo.joint_names[j]),
                    kind: MemberKind::Connector,
                    carrier: ci,
                    core: vec![post, at],
                    joints: vec![j],
                    post: Some(post),
                    slot: None,
                });
            }
        }
        Ok((pins, frame_joints))
    }

    /// The slider guide: a slotted plate over the stroke, fixed to the ground by one post. Without a
    /// fixed body the frame carries the slot instead: returns that slot.
    fn slider_guide(&mut self) -> Result<Option<Slot>, FabError> {
        let (mechanism, trace, dims) = (self.mechanism, self.trace, self.shapes.dims);
        let topo = &mechanism.topology;
        let (Some(j), Some(line)) = (topo.slider_joint, mechanism.slider) else { return Ok(None) };
        let along = (0..trace.len()).map(|r| (trace.row(r)[j] - line.point).dot(line.direction));
        let (lo, hi) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| (lo.min(s), hi.max(s)));
        if !(lo.is_finite() && hi.is_finite()) {
            return Err(FabError::Mismatch("the slider's stroke is empty".into()));
        }
        let slot = Slot { joint: j, ends: (line.point + line.direction * lo, line.point + line.direction * hi) };
        if self.shapes.ground.is_empty() {
            return Ok(Some(slot));
        }
        let sweep = &self.sweep;
        let swept_here = |p: Point| sweep.swept(0, p);
        let rules = posts::Rules { clear: &|_, _| true, swept: &swept_here };
        // Clear of the slider's own members running along the slot.
        let min_reach = dims.half_width + dims.post_collar_radius + dims.wall;
        let post = self
            .standing
            .post(0, slot.ends, min_reach, &rules)
            .map_err(|e| refusal(e, &format!("{} (slider guide)", topo.joint_names[j]), Carrier::Ground))?;
        self.placed.push(Member {
            name: "slider_guide".into(),
            kind: MemberKind::Guide,
            carrier: 0,
            core: vec![slot.ends.0, slot.ends.1, post],
            joints: vec![j],
            post: Some(post),
            slot: Some(slot),
        });
        Ok(None)
    }

    /// No fixed body: a frame on its own layer joins the ground joints `frame_joints` (and carries
    /// `frame_slot`), held by a square post on a foot that stands on the table where no body comes.
    /// Returns the foot, when one has a place.
    fn frame(&mut self, frame_joints: &[usize], frame_slot: Option<Slot>) -> Result<Option<Pad>, FabError> {
        if frame_joints.is_empty() && frame_slot.is_none() {
            return Ok(None);
        }
        let (shapes, mechanism, dims) = (self.shapes, self.mechanism, self.shapes.dims);
        too_close("the frame", frame_joints, mechanism, dims)?;
        let mut core: Vec<Point> = frame_joints.iter().map(|&j| mechanism.joints[j]).collect();
        let mut joints = frame_joints.to_vec();
        if let Some(slot) = frame_slot {
            core.extend([slot.ends.0, slot.ends.1]);
            joints.push(slot.joint);
        }
        let standing = &self.standing;
        let hit =
            |p: Point| posts::pad_hit(shapes, (standing.poses)(), 0, p, dims.post_depth(), &standing.pads).is_some();
        let at = posts::foot(&core, &dims, &|p| self.sweep.swept(0, p), &hit);
        let mut foot = None;
        if let Some(p) = at {
            core.push(p);
            foot = Some(Pad { carrier: 0, centre: p, radius: dims.post_depth() });
        }
        self.placed.push(Member {
            name: "frame".into(),
            kind: MemberKind::Frame,
            carrier: 0,
            core,
            joints,
            post: at,
            slot: frame_slot,
        });
        Ok(foot)
    }

    /// The springs' hooks, two per spring (ground end first), placed after every joint (the joints'
    /// posts take the best places).
    fn hooks(&mut self, springs: &[SpringEnds], body_pins: bool) -> Result<Vec<Hook>, FabError> {
        let mut hooks = Vec::new();
        for (s, ends) in springs.iter().enumerate() {
            for (anchor, end) in ends.iter().zip(["ground", "moving"]) {
                hooks.push(self.hook(s, anchor, end, body_pins)?);
            }
        }
        Ok(hooks)
    }

    /// The hook at `anchor`, the `end` ("ground" or "moving") of spring `s`: on the joint's pin when
    /// the anchor is a joint, on a link's plate widened to reach it, fused to the body when deep inside
    /// it (with `body_pins`), otherwise on a bracket from a post.
    fn hook(&mut self, s: usize, anchor: &Anchor, end: &str, body_pins: bool) -> Result<Hook, FabError> {
        let (shapes, topo, dims) = (self.shapes, &self.mechanism.topology, self.shapes.dims);
        let row0 = self.trace.row(0);
        let refuse = |why| FabError::SpringHook { spring: s + 1, part: anchor.part.clone(), why };
        let Some(pi) = topo.parts.iter().position(|p| p.name == anchor.part) else {
            return Err(refuse(HookRefusal::NoSuchPart));
        };
        if !(anchor.point.x.is_finite() && anchor.point.y.is_finite()) {
            return Err(refuse(HookRefusal::NotFinite));
        }
        let part = &topo.parts[pi];
        let placed = &mut self.placed;
        let ci = match part.kind {
            PartKind::Fixed => 0,
            PartKind::Body(b) => 1 + b,
            PartKind::Link => placed.carriers.iter().position(|&c| c == Carrier::Link(pi)).unwrap_or(0),
        };
        let pose0 = match placed.carriers[ci] {
            Carrier::Ground => Rigid::IDENTITY,
            Carrier::Body(b) => self.frames.pose(b, row0),
            Carrier::Link(_) => link_frame(row0[placed.link_frames[ci].0], row0[placed.link_frames[ci].1]),
        };
        let at = pose0.inverse().apply(anchor.point);
        let mut hook = Hook { spring: s, carrier: ci, at, base: HookBase::Body };
        // An anchor on one of the part's joints hooks on that joint's pin.
        let on_joint =
            |j: &&usize| row0[**j].distance(anchor.point) <= 1e-9 * (1.0 + anchor.point.distance(Point::ORIGIN));
        if let Some(&j) = part.joints.iter().find(on_joint) {
            hook.base = HookBase::Joint(j);
            return Ok(hook);
        }
        // Links and the frame carry nothing but their plate; bodies have regions.
        let regions: &[super::shapes::Region] =
            if ci < 1 + shapes.bodies.len() { shapes.carrier_regions(ci) } else { &[] };
        let plate = placed.members.iter().position(|m| {
            m.carrier == ci && (m.kind == MemberKind::Link || (regions.is_empty() && m.kind == MemberKind::Frame))
        });
        if let Some(mi) = plate {
            // The plate is widened to the anchor; the hook must clear the holes of its joints.
            let members = &mut placed.members;
            let holes = members[mi].joints.len().min(members[mi].core.len());
            if members[mi].core[..holes].iter().any(|c| c.distance(at) < dims.hook_clear_of_joints()) {
                return Err(refuse(HookRefusal::BesideJoint));
            }
            members[mi].core.push(at);
            hook.base = HookBase::Member(mi);
            return Ok(hook);
        }
        if body_pins && self.standing.fuse(ci, at, dims.cap_base_radius) {
            return Ok(hook);
        }
        let sweep = &self.sweep;
        let swept_here = |p: Point| sweep.swept(ci, p);
        let rules = posts::Rules { clear: &|_, _| true, swept: &swept_here };
        let min_reach = dims.cap_base_radius + dims.post_collar_radius + dims.wall;
        let post = self.standing.post(ci, (at, at), min_reach, &rules).map_err(|_| refuse(HookRefusal::NoRoom))?;
        hook.base = HookBase::Member(self.placed.push(Member {
            name: format!("spring{}_{end}_bracket", s + 1),
            kind: MemberKind::Bracket,
            carrier: ci,
            core: vec![post, at],
            joints: Vec::new(),
            post: Some(post),
            slot: None,
        }));
        Ok(hook)
    }
}

/// The pillars standing on every carrier so far (index as [`Layout::carriers`]), and the pads fused to
/// thin bodies for their posts, while joints, the guide and spring hooks are placed one after another.
struct Standing<'a> {
    shapes: &'a SceneShapes,
    /// Every carrier's pose along the motion, computed when a pad is first tested.
    poses: &'a dyn Fn() -> &'a posts::Poses,
    pillars: Vec<Vec<Pillar>>,
    pads: Vec<Pad>,
}

impl Standing<'_> {
    /// Fuses a pillar of `radius` to carrier `ci` at `at` when it lies deep enough inside the carrier
    /// for a pin and clear of the pillars there; whether it did.
    fn fuse(&mut self, ci: usize, at: Point, radius: f64) -> bool {
        let dims = &self.shapes.dims;
        let depth = self.shapes.carrier_regions(ci).iter().map(|r| r.depth(at)).fold(f64::NEG_INFINITY, f64::max);
        let free = self.pillars[ci].iter().all(|&(q, rq)| at.distance(q) >= radius + rq + dims.wall);
        let fused = depth >= dims.pin_depth() && free;
        if fused {
            self.pillars[ci].push((at, radius));
        }
        fused
    }

    /// A square post on carrier `ci` reaching `target` and at least `min_reach` from it ([`posts::place`]
    /// with `rules`), standing among the carrier's pillars, with the pad it needs on a thin body.
    fn post(
        &mut self,
        ci: usize,
        target: (Point, Point),
        min_reach: f64,
        rules: &posts::Rules,
    ) -> Result<Point, posts::Refusal> {
        let (shapes, poses, pads) = (self.shapes, self.poses, &self.pads);
        let hit = |p: Point, r: f64| posts::pad_hit(shapes, poses(), ci, p, r, pads);
        let carrier_pads: Vec<Pad> = pads.iter().filter(|p| p.carrier == ci).copied().collect();
        let query = posts::Query {
            regions: shapes.carrier_regions(ci),
            thin: &shapes.thin[ci],
            target,
            min_reach,
            placed: &self.pillars[ci],
            pads: &carrier_pads,
            pad_hit: &hit,
        };
        let site = posts::place(&query, rules, &shapes.dims)?;
        if let Some(radius) = site.pad {
            self.pads.push(Pad { carrier: ci, centre: site.at, radius });
        }
        self.pillars[ci].push((site.at, shapes.dims.post_collar_radius));
        Ok(site.at)
    }
}

/// A link's frame: origin at its first joint, x axis towards its second.
fn link_frame(a: Point, b: Point) -> Rigid {
    Rigid::from_frame(a, b - a)
}

fn carrier_first_pose(carrier: Carrier, shapes: &SceneShapes) -> Rigid {
    match carrier {
        Carrier::Body(b) => shapes.first_poses[b],
        _ => Rigid::IDENTITY,
    }
}

/// The error for a post that has no place on `carrier`.
fn refusal(e: posts::Refusal, joint: &str, carrier: Carrier) -> FabError {
    let body = carrier_name(carrier);
    match e {
        posts::Refusal::NoRoom => FabError::NoRoomForPost { joint: joint.to_string(), body },
        posts::Refusal::PadsCollide { at_deg } => FabError::PadCollides { joint: joint.to_string(), body, at_deg },
    }
}

/// [`FabError::JointsTooClose`] when two of `joints` are closer than two pins need.
fn too_close(name: &str, joints: &[usize], mechanism: &Mechanism, dims: Dims) -> Result<(), FabError> {
    let need = dims.min_joint_spacing();
    for (x, &ja) in joints.iter().enumerate() {
        for &jb in &joints[x + 1..] {
            if mechanism.joints[ja].distance(mechanism.joints[jb]) < need {
                let names = &mechanism.topology.joint_names;
                return Err(FabError::JointsTooClose {
                    link: name.to_string(),
                    a: names[ja].clone(),
                    b: names[jb].clone(),
                    need_mm: need * dims.mm_per_unit,
                });
            }
        }
    }
    Ok(())
}

fn carrier_name(carrier: Carrier) -> String {
    match carrier {
        Carrier::Ground => "ground".into(),
        Carrier::Body(b) => format!("moving body {b}"),
        Carrier::Link(p) => format!("link {p}"),
    }
}
