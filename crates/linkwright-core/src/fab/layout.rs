//! Connecting the linkage to the bodies (paper §7.1): which printed members exist (links, joint
//! connectors, the slider guide), which rigid carrier each rides on, where connector posts stand on the
//! bodies, and which joints are pins fused straight onto a body.

use super::settings::Dims;
use super::shapes::Region;
use super::FabError;
use crate::geom::{point_segment_distance, Point, Rigid};
use crate::kinematics::{BodyFrames, Trace};
use crate::mechanism::{Mechanism, PartKind};
use crate::scene::Problem;
use i_overlay::core::fill_rule::FillRule;
use i_overlay::float::simplify::SimplifyShape;

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
}

/// A flat printed part on one layer: the convex hull of discs of radius `half_width` around `core`.
#[derive(Clone, Debug, PartialEq)]
pub struct Member {
    pub name: String,
    pub kind: MemberKind,
    /// Index into [`Layout::carriers`].
    pub carrier: usize,
    /// Disc centres in the carrier's frame (the joints, and the post for connectors).
    pub core: Vec<Point>,
    /// The joints this member turns on (or slides on, for the guide).
    pub joints: Vec<usize>,
    /// Connectors and the guide: where the square post stands, carrier frame.
    pub post: Option<Point>,
    /// The guide: the ends of the slot's centre line, ground frame.
    pub slot: Option<(Point, Point)>,
}

/// A joint pin fused to a body or the ground (the joint lies deep enough inside it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPin {
    pub carrier: usize,
    /// Position in the carrier's frame.
    pub at: Point,
}

/// Every printed member and how it is carried, for one mechanism in one scene.
#[derive(Clone, Debug)]
pub struct Layout {
    pub carriers: Vec<Carrier>,
    /// For each carrier, the first two joints whose frame places it (links), unused otherwise.
    link_frames: Vec<(usize, usize)>,
    pub members: Vec<Member>,
    /// `L_j` of paper eq. 17: the members that turn on joint j.
    pub joint_members: Vec<Vec<usize>>,
    /// Joints whose pin is fused to a body or the ground.
    pub body_pins: Vec<Option<BodyPin>>,
    /// The slider joint, if any (its pin runs in the guide's slot).
    pub slider_joint: Option<usize>,
    /// Round pads added to bodies too thin for a post: (carrier, centre in its frame, radius). They are
    /// fused to the body's outline, in the bodies' plane, and checked against every other body along
    /// the motion.
    pub pads: Vec<(usize, Point, f64)>,
    pub dims: Dims,
    frames: BodyFrames,
}

/// Everything about a scene fabrication needs before any mechanism: the ground's region (the union
/// of the fixed bodies), each body's outline, and the sizes. Build it once and reuse it for many
/// mechanisms (the synthesis does).
#[derive(Clone, Debug)]
pub struct SceneShapes {
    /// The union of the fixed bodies: one region per connected piece.
    pub ground: Vec<Region>,
    /// Each moving body's outline in its own frame, as a region.
    pub bodies: Vec<Region>,
    pub first_poses: Vec<Rigid>,
    pub dims: Dims,
}

impl SceneShapes {
    pub fn new(problem: &Problem, dims: Dims) -> SceneShapes {
        let contours: Vec<Vec<[f64; 2]>> = problem
            .fixed
            .iter()
            .map(|p| {
                let mut c: Vec<[f64; 2]> = p.vertices().iter().map(|v| [v.x, v.y]).collect();
                if p.signed_area() < 0.0 {
                    c.reverse();
                }
                c
            })
            .collect();
        let ground = if contours.is_empty() {
            Vec::new()
        } else {
            contours
                .simplify_shape(FillRule::NonZero)
                .into_iter()
                .map(|shape| Region {
                    contours: shape
                        .into_iter()
                        .map(|c| c.into_iter().map(|[x, y]| Point::new(x, y)).collect())
                        .collect(),
                })
                .filter(|r: &Region| !r.contours.is_empty())
                .collect()
        };
        let bodies = problem
            .bodies
            .iter()
            .map(|b| {
                let mut c = b.outline.vertices().to_vec();
                if b.outline.signed_area() < 0.0 {
                    c.reverse();
                }
                Region { contours: vec![c] }
            })
            .collect();
        SceneShapes { ground, bodies, first_poses: problem.bodies.iter().map(|b| b.poses[0]).collect(), dims }
    }

    /// The region of a carrier that can hold posts and pins, in the carrier's frame.
    fn regions(&self, carrier: Carrier) -> &[Region] {
        match carrier {
            Carrier::Ground => &self.ground,
            Carrier::Body(b) => std::slice::from_ref(&self.bodies[b]),
            Carrier::Link(_) => &[],
        }
    }
}

/// A pillar already standing on a carrier: position and radius.
type Pillar = (Point, f64);

impl Layout {
    /// Connects every joint of `mechanism` to the parts that carry it. `trace` is the motion (its rows
    /// give the slider's stroke).
    /// With `body_pins`, a joint lying deep inside its body gets a pin fused to the body; without, every
    /// body joint gets a connector (as in the paper), which leaves the solver more freedom.
    pub fn new(
        shapes: &SceneShapes,
        mechanism: &Mechanism,
        trace: &Trace,
        body_pins: bool,
    ) -> Result<Layout, FabError> {
        let topo = &mechanism.topology;
        let dims = shapes.dims;
        let n = topo.joint_count();
        if topo.body_count != shapes.bodies.len() {
            return Err(FabError::Mismatch(format!(
                "the design moves {} bodies, the scene has {}",
                topo.body_count,
                shapes.bodies.len()
            )));
        }
        let mut carriers = vec![Carrier::Ground];
        let mut link_frames = vec![(0, 0)];
        for b in 0..topo.body_count {
            carriers.push(Carrier::Body(b));
            link_frames.push((0, 0));
        }
        let frames = BodyFrames::new(mechanism, &shapes.first_poses);
        let mut members = Vec::new();
        let mut joint_members = vec![Vec::new(); n];
        for (pi, part) in topo.parts.iter().enumerate() {
            if part.kind != PartKind::Link {
                continue;
            }
            if part.joints.len() < 2 {
                return Err(FabError::Mismatch(format!("link {} carries fewer than two joints", part.name)));
            }
            let (a, b) = (part.joints[0], part.joints[1]);
            let frame = link_frame(mechanism.joints[a], mechanism.joints[b]);
            let c = carriers.len();
            carriers.push(Carrier::Link(pi));
            link_frames.push((a, b));
            let core: Vec<Point> = part.joints.iter().map(|&j| frame.inverse().apply(mechanism.joints[j])).collect();
            let need = dims.min_joint_spacing();
            for (x, &ja) in part.joints.iter().enumerate() {
                for &jb in &part.joints[x + 1..] {
                    if mechanism.joints[ja].distance(mechanism.joints[jb]) < need {
                        return Err(FabError::JointsTooClose {
                            link: part.name.clone(),
                            a: topo.joint_names[ja].clone(),
                            b: topo.joint_names[jb].clone(),
                            need_mm: need * dims.mm_per_unit,
                        });
                    }
                }
            }
            for &j in &part.joints {
                joint_members[j].push(members.len());
            }
            members.push(Member {
                name: part.name.clone(),
                kind: MemberKind::Link,
                carrier: c,
                core,
                joints: part.joints.clone(),
                post: None,
                slot: None,
            });
        }

        // Joints on the ground and on bodies: a pin fused to the body when the joint lies deep inside
        // it, otherwise a connector from the nearest place a post fits.
        let mut pillars: Vec<Vec<Pillar>> = vec![Vec::new(); carriers.len()];
        let mut pins = vec![None; n];
        let mut pads: Vec<(usize, Point, f64)> = Vec::new();
        let mut connectors: Vec<Vec<(Point, Point)>> = vec![Vec::new(); carriers.len()];
        // Where the links are at every row (world), to keep posts out of their way.
        let link_rows: Vec<Vec<Vec<Point>>> = (0..trace.len())
            .map(|r| {
                if r % trace.len().div_ceil(90).max(1) != 0 {
                    return Vec::new();
                }
                let row = trace.row(r);
                members
                    .iter()
                    .map(|m| {
                        let (a, b) = link_frames[m.carrier];
                        let pose = link_frame(row[a], row[b]);
                        m.core.iter().map(|&c| pose.apply(c)).collect()
                    })
                    .collect()
            })
            .collect();
        let sweep_reach = dims.half_width + dims.post_collar_radius + dims.clearance;
        // A preference only (validity comes from the recorded constraints), so every few rows suffice.
        let stride = trace.len().div_ceil(90).max(1);
        let swept = |ci: usize, p: Point| -> bool {
            (0..trace.len()).step_by(stride).any(|r| {
                let pose = if ci == 0 { Rigid::IDENTITY } else { frames.pose(ci - 1, trace.row(r)) };
                let w = pose.apply(p);
                link_rows[r].iter().any(|core| super::shapes::point_core_distance(w, core) < sweep_reach)
            })
        };
        for part in &topo.parts {
            let (carrier, ci) = match part.kind {
                PartKind::Fixed => (Carrier::Ground, 0),
                PartKind::Body(b) => (Carrier::Body(b), 1 + b),
                PartKind::Link => continue,
            };
            let to_local = carrier_first_pose(carrier, shapes, mechanism).inverse();
            for &j in &part.joints {
                let at = to_local.apply(mechanism.joints[j]);
                let regions = shapes.regions(carrier);
                if regions.is_empty() {
                    return Err(FabError::NoGround);
                }
                let free = |p: Point, r: f64, placed: &[Pillar]| {
                    placed.iter().all(|&(q, rq)| p.distance(q) >= r + rq + dims.wall)
                };
                let depth = |p: Point| regions.iter().map(|r| r.depth(p)).fold(f64::NEG_INFINITY, f64::max);
                if body_pins && depth(at) >= dims.pin_depth() && free(at, dims.boss_radius, &pillars[ci]) {
                    pillars[ci].push((at, dims.boss_radius));
                    pins[j] = Some(BodyPin { carrier: ci, at });
                    continue;
                }
                let min_reach = dims.boss_radius + dims.post_collar_radius + dims.wall;
                // Connectors of one body must not cover each other's posts both ways (no layer order
                // could then exist): prefer posts that neither cover nor are covered, then posts that
                // are not both.
                let reach = dims.half_width + dims.post_collar_radius + dims.clearance;
                let mine = &connectors[ci];
                let clear = |level: u8| {
                    move |p: Point| {
                        mine.iter().all(|&(q, jq): &(Point, Point)| {
                            let new_covers_old = point_segment_distance(q, p, at) < reach;
                            let old_covers_new = point_segment_distance(p, q, jq) < reach;
                            match level {
                                2 => !new_covers_old && !old_covers_new,
                                1 => !(new_covers_old && old_covers_new),
                                _ => true,
                            }
                        })
                    }
                };
                // Nearest first; a place no other member sweeps over is worth a longer connector.
                let mut fallback = None;
                let mut chosen = None;
                // The paper's place first: the nearest boundary point pushed in, when it is good.
                if let Some((q, inward)) = regions
                    .iter()
                    .filter_map(|r| r.nearest_boundary(at).map(|(q, n)| (q.distance(at), q, n)))
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|(_, q, n)| (q, n))
                {
                    let p = q + inward * (dims.post_depth() * 1.05);
                    let deep = regions.iter().any(|r| r.depth(p) >= dims.post_depth());
                    let apart = pillars[ci].iter().all(|&(o, ro)| p.distance(o) >= dims.post_collar_radius + ro + 1e-9);
                    if deep && apart && p.distance(at) >= min_reach && clear(2)(p) && !swept(ci, p) {
                        chosen = Some(p);
                    }
                }
                if chosen.is_none() {
                    // The grid once; then the strictest rule that leaves an unswept place.
                    let cands = find_posts(
                        regions,
                        at,
                        dims.post_depth(),
                        min_reach,
                        dims.post_collar_radius,
                        &pillars[ci],
                        &|_| true,
                        96,
                    );
                    'levels: for level in [2u8, 1, 0] {
                        let rule = clear(level);
                        for &p in cands.iter().filter(|&&p| rule(p)).take(24) {
                            if !swept(ci, p) {
                                chosen = Some(p);
                                break 'levels;
                            }
                        }
                        if fallback.is_none() {
                            fallback = cands.iter().copied().find(|&p| rule(p));
                        }
                    }
                }
                let post = match chosen.or(fallback) {
                    Some(p) => p,
                    None => {
                        let mut candidates = Vec::new();
                        for level in [2u8, 1, 0] {
                            candidates = pad_posts(
                                regions,
                                at,
                                dims.post_depth(),
                                min_reach,
                                dims.post_collar_radius,
                                &pillars[ci],
                                &clear(level),
                            );
                            if !candidates.is_empty() {
                                break;
                            }
                        }
                        if candidates.is_empty() {
                            return Err(FabError::NoRoomForPost {
                                joint: topo.joint_names[j].clone(),
                                body: carrier_name(carrier, shapes),
                            });
                        }
                        let mut first_hit = None;
                        let mut chosen = None;
                        for p in candidates {
                            match pad_hit(shapes, &frames, trace, ci, p, dims.post_depth(), &pads) {
                                None => {
                                    chosen = Some(p);
                                    break;
                                }
                                Some(deg) => {
                                    first_hit.get_or_insert(deg);
                                }
                            }
                        }
                        let Some(p) = chosen else {
                            return Err(FabError::PadCollides {
                                body: carrier_name(carrier, shapes),
                                at_deg: first_hit.unwrap_or(0.0),
                            });
                        };
                        pads.push((ci, p, dims.post_depth()));
                        p
                    }
                };
                pillars[ci].push((post, dims.post_collar_radius));
                connectors[ci].push((post, at));
                joint_members[j].push(members.len());
                members.push(Member {
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

        // The slider guide: a slotted plate over the stroke, fixed to the ground by one post.
        if let (Some(j), Some(line)) = (topo.slider_joint, mechanism.slider) {
            let along = (0..trace.len()).map(|r| (trace.row(r)[j] - line.point).dot(line.direction));
            let (lo, hi) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| (lo.min(s), hi.max(s)));
            if !(lo.is_finite() && hi.is_finite()) {
                return Err(FabError::Mismatch("the slider's stroke is empty".into()));
            }
            let (s0, s1) = (line.point + line.direction * lo, line.point + line.direction * hi);
            let mid = s0.lerp(s1, 0.5);
            let min_reach = 0.5 * s0.distance(s1) + dims.half_width + dims.post_collar_radius + dims.wall;
            let post = find_posts(
                &shapes.ground,
                mid,
                dims.post_depth(),
                min_reach,
                dims.post_collar_radius,
                &pillars[0],
                &|_| true,
                1,
            )
            .first()
            .copied()
            .ok_or_else(|| FabError::NoRoomForPost {
                joint: format!("{} (slider guide)", topo.joint_names[j]),
                body: "ground".into(),
            })?;
            pillars[0].push((post, dims.post_collar_radius));
            joint_members[j].push(members.len());
            members.push(Member {
                name: "slider_guide".into(),
                kind: MemberKind::Guide,
                carrier: 0,
                core: vec![s0, s1, post],
                joints: vec![j],
                post: Some(post),
                slot: Some((s0, s1)),
            });
        }
        let layout = Layout {
            carriers,
            link_frames,
            members,
            joint_members,
            body_pins: pins,
            slider_joint: topo.slider_joint,
            pads,
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

    /// The member whose name is `name`.
    pub fn member(&self, name: &str) -> Option<usize> {
        self.members.iter().position(|m| m.name == name)
    }
}

/// A link's frame: origin at its first joint, x axis towards its second.
fn link_frame(a: Point, b: Point) -> Rigid {
    Rigid::from_frame(a, b - a)
}

fn carrier_first_pose(carrier: Carrier, shapes: &SceneShapes, _m: &Mechanism) -> Rigid {
    match carrier {
        Carrier::Body(b) => shapes.first_poses[b],
        _ => Rigid::IDENTITY,
    }
}

/// The crank angle (degrees) of the first row where a pad of `radius` at `at` on carrier `c` (0 the
/// ground, 1 + b body b) enters another body or pad, or `None`.
fn pad_hit(
    shapes: &SceneShapes,
    frames: &BodyFrames,
    trace: &Trace,
    c: usize,
    at: Point,
    radius: f64,
    pads: &[(usize, Point, f64)],
) -> Option<f64> {
    let tol = 1e-3 * radius;
    let pose = |k: usize, row: &[Point]| if k == 0 { Rigid::IDENTITY } else { frames.pose(k - 1, row) };
    for r in 0..trace.len() {
        let row = trace.row(r);
        let centre = pose(c, row).apply(at);
        let pad = crate::geom::Polygon::new(super::shapes::circle(centre, radius, 24));
        for other in (0..=shapes.bodies.len()).filter(|&o| o != c) {
            let regions: &[Region] =
                if other == 0 { &shapes.ground } else { std::slice::from_ref(&shapes.bodies[other - 1]) };
            let placed = pose(other, row);
            let hit = regions.iter().any(|region| {
                pad.penetrates(&crate::geom::Polygon::new(region.contours[0].clone()).transformed(&placed), tol)
            }) || pads
                .iter()
                .filter(|p| p.0 == other)
                .any(|&(_, q, rq)| placed.apply(q).distance(centre) < radius + rq - tol);
            if hit {
                return Some(trace.thetas[r].to_degrees());
            }
        }
    }
    None
}

/// For a body too thin for a post: places on the body's medial line for the post, nearest the joint
/// first (a round pad of radius `depth` is then fused to the body there).
#[allow(clippy::too_many_arguments, reason = "the placement rules of one post, named at the call sites")]
fn pad_posts(
    regions: &[Region],
    joint: Point,
    depth: f64,
    min_reach: f64,
    radius: f64,
    placed: &[Pillar],
    clear: &dyn Fn(Point) -> bool,
) -> Vec<Point> {
    let wall_free = |p: Point| placed.iter().all(|&(q, rq)| p.distance(q) >= radius + rq + 1e-9) && clear(p);
    let mut found: Vec<(f64, Point)> = Vec::new();
    for r in regions {
        for c in &r.contours {
            let n = c.len();
            for i in 0..n {
                let (a, b) = (c[i], c[(i + 1) % n]);
                let steps = ((a.distance(b) / (0.5 * depth)).ceil() as usize).max(1);
                for k in 0..steps {
                    let q = a.lerp(b, k as f64 / steps as f64);
                    // The deepest point straight inwards from q.
                    let normal = {
                        let e = (b - a).perp().normalized();
                        if r.contains(q + e * (1e-4 * depth)) {
                            e
                        } else {
                            -e
                        }
                    };
                    let mut deepest = (f64::NEG_INFINITY, q);
                    for t in 1..=20 {
                        let p = q + normal * (depth * t as f64 / 20.0);
                        let dp = r.depth(p);
                        if dp > deepest.0 {
                            deepest = (dp, p);
                        }
                    }
                    let p = deepest.1;
                    if deepest.0 <= 0.0 || !wall_free(p) || p.distance(joint) < min_reach {
                        continue;
                    }
                    found.push((p.distance(joint), p));
                }
            }
        }
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<Point> = Vec::new();
    for (_, p) in found {
        if out.iter().all(|q| q.distance(p) >= 0.5 * depth) {
            out.push(p);
        }
        if out.len() >= 240 {
            break;
        }
    }
    out
}

fn carrier_name(carrier: Carrier, _shapes: &SceneShapes) -> String {
    match carrier {
        Carrier::Ground => "ground".into(),
        Carrier::Body(b) => format!("moving body {b}"),
        Carrier::Link(p) => format!("link {p}"),
    }
}

/// The place nearest to `joint` where a post of column radius `radius` stands at least `depth` inside
/// the regions, at least `min_reach` from the joint, clear of the pillars already placed. Tries the
/// nearest boundary point pushed inwards first (paper §7.1), then a grid over the regions.
#[allow(clippy::too_many_arguments, reason = "the placement rules of one post, named at the call sites")]
fn find_posts(
    regions: &[Region],
    joint: Point,
    depth: f64,
    min_reach: f64,
    radius: f64,
    placed: &[Pillar],
    clear: &dyn Fn(Point) -> bool,
    limit: usize,
) -> Vec<Point> {
    let wall_free = |p: Point| placed.iter().all(|&(q, rq)| p.distance(q) >= radius + rq + 1e-9) && clear(p);
    let deep = |p: Point| regions.iter().any(|r| r.deeper_than(p, depth));
    let ok = |p: Point| deep(p) && wall_free(p) && p.distance(joint) >= min_reach;
    let mut found: Vec<(f64, Point)> = Vec::new();
    for r in regions {
        if let Some((q, inward)) = r.nearest_boundary(joint) {
            let p = q + inward * (depth * 1.05);
            if ok(p) {
                found.push((-1.0, p));
            }
        }
    }
    for r in regions {
        let Some(bb) = r.aabb() else { continue };
        // A window around the joint, wide enough to reach into the region.
        let reach = r.boundary_distance(joint).max(0.0) + 8.0 * depth + min_reach;
        let (x0, x1) = (bb.min.x.max(joint.x - reach), bb.max.x.min(joint.x + reach));
        let (y0, y1) = (bb.min.y.max(joint.y - reach), bb.max.y.min(joint.y + reach));
        if x1 < x0 || y1 < y0 {
            continue;
        }
        let step = (depth / 3.0).max((x1 - x0).max(y1 - y0) / 64.0);
        let nx = ((x1 - x0) / step).ceil() as usize + 1;
        let ny = ((y1 - y0) / step).ceil() as usize + 1;
        for ix in 0..nx {
            for iy in 0..ny {
                let p = Point::new(x0 + ix as f64 * step, y0 + iy as f64 * step);
                let d = p.distance(joint);
                if d >= min_reach && r.deeper_than(p, depth) && wall_free(p) {
                    found.push((d, p));
                }
            }
        }
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<Point> = Vec::new();
    for (_, p) in found {
        if out.iter().all(|q| q.distance(p) >= 0.5 * depth) {
            out.push(p);
        }
        if out.len() >= limit {
            break;
        }
    }
    out
}
