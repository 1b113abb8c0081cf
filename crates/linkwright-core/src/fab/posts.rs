//! Where the square post of a connector (or of the slider guide) stands on its body or on the ground
//! (paper §7.1), from the best place to the last resort:
//! 1. the nearest place where the post's collar stands at least a wall inside the body;
//! 2. on a body too thin for that, a place on its middle line where the collar just fits (within the
//!    radial clearance of the body's edge: a solid column on a solid slab needs no wall around it);
//! 3. on a body too thin even for that (a roof panel drawn a few millimetres thick), a round pad in the
//!    bodies' plane fused to the body's side, on a side where no other body comes along the motion.
//!
//! Within each, places that no link sweeps over and whose connectors do not cover each other's posts
//! are preferred (see [`Rules`]); the depth ordering decides whether a place works.

use super::settings::Dims;
use super::shapes::Region;
use crate::geom::{point_segment_distance, Point, Rigid};
use crate::kinematics::{BodyFrames, Trace};
use crate::scene::Problem;
use i_overlay::core::fill_rule::FillRule;
use i_overlay::float::simplify::SimplifyShape;

/// Everything about a scene fabrication needs before any mechanism: the ground's region (the union
/// of the fixed bodies), each body's outline, and the sizes. Build it once and reuse it for many
/// mechanisms (the print check does, for every candidate).
#[derive(Clone, Debug)]
pub(crate) struct SceneShapes {
    /// The union of the fixed bodies: one region per connected piece.
    pub ground: Vec<Region>,
    /// Each moving body's outline in its own frame, as a region.
    pub bodies: Vec<Region>,
    pub first_poses: Vec<Rigid>,
    pub dims: Dims,
    /// For each carrier (0 the ground, `1 + b` body `b`), its places for posts on thin stretches.
    pub(super) thin: Vec<ThinSites>,
}

impl SceneShapes {
    pub(crate) fn new(problem: &Problem, dims: Dims) -> SceneShapes {
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
        let bodies: Vec<Region> = problem
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
        let thin = std::iter::once(ground.as_slice())
            .chain(bodies.iter().map(std::slice::from_ref))
            .map(|regions| ThinSites::new(regions, &dims))
            .collect();
        SceneShapes { ground, bodies, first_poses: problem.bodies.iter().map(|b| b.poses[0]).collect(), dims, thin }
    }

    /// The regions of carrier `k` (0 the ground, `1 + b` moving body `b`) that can hold posts and pins,
    /// in the carrier's frame (empty for the ground of a scene without fixed bodies).
    pub(crate) fn carrier_regions(&self, k: usize) -> &[Region] {
        match k {
            0 => &self.ground,
            _ => std::slice::from_ref(&self.bodies[k - 1]),
        }
    }
}

/// A pillar already standing on a carrier: position and radius.
pub(crate) type Pillar = (Point, f64);

/// A pad fused to a carrier's outline in the bodies' plane, carrying a post.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pad {
    /// Index into the layout's carriers (0 the ground, `1 + b` moving body `b`).
    pub carrier: usize,
    /// Centre (the post's place), carrier frame.
    pub centre: Point,
    /// The pad's radius.
    pub radius: f64,
}

/// Where a post stands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Site {
    pub at: Point,
    /// The pad fused to the body there, when the body is too thin.
    pub pad: Option<f64>,
}

/// Why no post place was found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Refusal {
    /// The carrier has no place for a post nor a side for a pad.
    NoRoom,
    /// Every pad place enters another body along the motion; the first crank angle (degrees) seen.
    PadsCollide { at_deg: f64 },
}

/// The preferences among valid places, strictest first.
pub(crate) struct Rules<'a> {
    /// Whether a place keeps the connectors of one carrier off each other's posts at strictness
    /// `level` (2: neither covers the other, 1: not both, 0: anything).
    pub clear: &'a dyn Fn(Point, u8) -> bool,
    /// Whether some link sweeps over a place along the motion.
    pub swept: &'a dyn Fn(Point) -> bool,
}

/// What a post must reach and avoid on one carrier.
pub(crate) struct Query<'a> {
    /// The carrier's regions, carrier frame.
    pub regions: &'a [Region],
    /// The joint (both ends equal) or the guide's slot, carrier frame: the post stays `min_reach` from it.
    pub target: (Point, Point),
    pub min_reach: f64,
    /// The carrier's places on thin stretches (computed once per scene).
    pub thin: &'a ThinSites,
    /// Pillars already on the carrier.
    pub placed: &'a [Pillar],
    /// Pads already fused to the carrier (carrier frame).
    pub pads: &'a [Pad],
    /// The crank angle (degrees) where a pad of this radius at this place first enters another body
    /// or pad, if it ever does.
    pub pad_hit: &'a dyn Fn(Point, f64) -> Option<f64>,
}

impl Query<'_> {
    fn reach(&self, p: Point) -> f64 {
        point_segment_distance(p, self.target.0, self.target.1)
    }
    fn apart(&self, p: Point, radius: f64) -> bool {
        self.placed.iter().all(|&(q, rq)| p.distance(q) >= radius + rq + 1e-9)
    }
    /// Whether a pad of `radius` at `p` would close a pocket with a pad already there: the two discs
    /// overlap but neither point where their circles cross lies in the body, so they enclose a gap
    /// between them and the body's side.
    fn closes_pocket(&self, p: Point, radius: f64) -> bool {
        self.pads.iter().any(|e| {
            let d = p.distance(e.centre);
            if d >= radius + e.radius || d <= (radius - e.radius).abs() {
                return false;
            }
            let a = (radius * radius - e.radius * e.radius + d * d) / (2.0 * d);
            let h = (radius * radius - a * a).max(0.0).sqrt();
            let u = (e.centre - p) / d;
            let base = p + u * a;
            [base + u.perp() * h, base - u.perp() * h].iter().all(|&x| self.regions.iter().all(|r| r.depth(x) < 0.0))
        })
    }
}

/// The place of a post of collar radius `dims.post_collar_radius`, after the module's order.
pub(crate) fn place(q: &Query, rules: &Rules, dims: &Dims) -> Result<Site, Refusal> {
    let collar = dims.post_collar_radius;
    // The paper's place first: the boundary point nearest the target pushed in, when it is good.
    let mid = q.target.0.lerp(q.target.1, 0.5);
    if let Some((b, inward)) = q
        .regions
        .iter()
        .filter_map(|r| r.nearest_boundary(mid).map(|(b, n)| (b.distance(mid), b, n)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, b, n)| (b, n))
    {
        let p = b + inward * (dims.post_depth() * 1.05);
        let deep = q.regions.iter().any(|r| r.deeper_than(p, dims.post_depth()));
        if deep && q.apart(p, collar) && q.reach(p) >= q.min_reach && (rules.clear)(p, 2) && !(rules.swept)(p) {
            return Ok(Site { at: p, pad: None });
        }
    }
    let grid = grid_places(q, dims.post_depth(), collar, 96);
    if let Some(p) = choose(&grid, rules) {
        return Ok(Site { at: p, pad: None });
    }
    let flush = middle_places(q, dims.post_flush_depth(), collar, 96);
    if let Some(p) = choose(&flush, rules) {
        return Ok(Site { at: p, pad: None });
    }
    let radius = dims.post_depth();
    let sites = pad_places(q, radius, collar);
    if sites.is_empty() {
        return Err(Refusal::NoRoom);
    }
    // The pads that stay clear of every other body (the costly test, so only the nearest few).
    let mut first_hit = None;
    let mut free = Vec::new();
    for &p in sites.iter().take(64) {
        match (q.pad_hit)(p, radius) {
            None => free.push(p),
            Some(deg) => {
                first_hit.get_or_insert(deg);
            }
        }
        if free.len() >= 3 {
            break;
        }
    }
    match choose(&free, rules) {
        Some(p) => Ok(Site { at: p, pad: Some(radius) }),
        None => Err(Refusal::PadsCollide { at_deg: first_hit.unwrap_or(0.0) }),
    }
}

/// Among places sorted nearest first: the first unswept one under the strictest rule that has one,
/// else the first under the strictest rule that admits any.
fn choose(places: &[Point], rules: &Rules) -> Option<Point> {
    for level in [2u8, 1, 0] {
        if let Some(&p) = places.iter().filter(|&&p| (rules.clear)(p, level)).take(24).find(|&&p| !(rules.swept)(p)) {
            return Some(p);
        }
    }
    [2u8, 1, 0].into_iter().find_map(|level| places.iter().copied().find(|&p| (rules.clear)(p, level)))
}

/// Places at least `depth` inside the regions on a grid around the target, nearest first (the paper's
/// place, the nearest boundary point pushed in, ahead of all).
fn grid_places(q: &Query, depth: f64, radius: f64, limit: usize) -> Vec<Point> {
    let ok = |p: Point| q.apart(p, radius) && q.reach(p) >= q.min_reach;
    let mid = q.target.0.lerp(q.target.1, 0.5);
    let half = 0.5 * q.target.0.distance(q.target.1);
    let mut found: Vec<(f64, Point)> = Vec::new();
    for r in q.regions {
        if let Some((b, inward)) = r.nearest_boundary(mid) {
            let p = b + inward * (depth * 1.05);
            if r.deeper_than(p, depth) && ok(p) {
                found.push((-1.0, p));
            }
        }
    }
    for r in q.regions {
        let Some(bb) = r.aabb() else { continue };
        // A window around the target, wide enough to reach into the region.
        let reach = r.boundary_distance(mid).max(0.0) + half + 8.0 * depth + q.min_reach;
        let (x0, x1) = (bb.min.x.max(mid.x - reach), bb.max.x.min(mid.x + reach));
        let (y0, y1) = (bb.min.y.max(mid.y - reach), bb.max.y.min(mid.y + reach));
        if x1 < x0 || y1 < y0 {
            continue;
        }
        let step = (depth / 3.0).max((x1 - x0).max(y1 - y0) / 64.0);
        let nx = ((x1 - x0) / step).ceil() as usize + 1;
        let ny = ((y1 - y0) / step).ceil() as usize + 1;
        for ix in 0..nx {
            for iy in 0..ny {
                let p = Point::new(x0 + ix as f64 * step, y0 + iy as f64 * step);
                if ok(p) && r.deeper_than(p, depth) {
                    found.push((q.reach(p), p));
                }
            }
        }
    }
    nearest_apart(found, 0.5 * depth, limit)
}

/// Most boundary samples of one region: 20 m of outline at the default post spacing (about 1 mm), far
/// beyond any printable body, so that the samples of a drawing a kilometre across (the scene format's
/// bound), and the pad and post tests over them, cost no more than those of a 20 m outline.
const MAX_BOUNDARY_SAMPLES: f64 = 20_000.0;

/// Samples of every contour every `spacing` (wider where the outline is longer than
/// [`MAX_BOUNDARY_SAMPLES`] spacings), each with its unit normal pointing into the region.
fn boundary_samples(r: &Region, spacing: f64) -> Vec<(Point, crate::geom::Vec2)> {
    let perimeter: f64 =
        r.contours.iter().flat_map(|c| (0..c.len()).map(|i| c[i].distance(c[(i + 1) % c.len()]))).sum();
    let spacing = spacing.max(perimeter / MAX_BOUNDARY_SAMPLES);
    let mut out = Vec::new();
    for c in &r.contours {
        let n = c.len();
        for i in 0..n {
            let (a, b) = (c[i], c[(i + 1) % n]);
            let len = a.distance(b);
            if len <= 0.0 {
                continue;
            }
            let e = (b - a).perp().normalized();
            let steps = ((len / spacing).ceil() as usize).max(1);
            for k in 0..steps {
                let p = a.lerp(b, (k as f64 + 0.5) / steps as f64);
                let inward = if r.contains(p + e * (1e-4 * spacing)) { e } else { -e };
                out.push((p, inward));
            }
        }
    }
    out
}

/// The deepest point straight inwards from a boundary sample, within `span`, and its depth.
fn deepest_inwards(r: &Region, b: Point, inward: crate::geom::Vec2, span: f64) -> (f64, Point) {
    let mut deepest = (f64::NEG_INFINITY, b);
    for t in 1..=24 {
        let p = b + inward * (span * t as f64 / 24.0);
        let d = r.depth(p);
        if d > deepest.0 {
            deepest = (d, p);
        }
    }
    deepest
}

/// Places on the middle line of thin stretches, at least `depth` inside, nearest the target first.
fn middle_places(q: &Query, depth: f64, radius: f64, limit: usize) -> Vec<Point> {
    let found = q
        .thin
        .middle
        .iter()
        .filter(|&&(p, d)| d >= depth && q.apart(p, radius) && q.reach(p) >= q.min_reach)
        .map(|&(p, _)| (q.reach(p), p))
        .collect();
    nearest_apart(found, 0.25 * depth, limit)
}

/// Pad centres clear of the pillars and far enough from the target, nearest first.
fn pad_places(q: &Query, radius: f64, collar: f64) -> Vec<Point> {
    let found = q
        .thin
        .pads
        .iter()
        .filter(|&&p| q.apart(p, collar) && q.reach(p) >= q.min_reach && !q.closes_pocket(p, radius))
        .map(|&p| (q.reach(p), p))
        .collect();
    nearest_apart(found, 0.25 * radius, 64)
}

/// A carrier's candidate places on thin stretches, which depend on the scene only: points of the
/// middle line (the deepest point straight inwards from each boundary sample) with their depth, and
/// centres of pads fused to the sides (reaching `2 · wall` to all the way into the body from each
/// boundary sample, bulging out on that side, and on the middle line).
#[derive(Clone, Debug, Default)]
pub(crate) struct ThinSites {
    pub middle: Vec<(Point, f64)>,
    pub pads: Vec<Point>,
}

impl ThinSites {
    pub(crate) fn new(regions: &[Region], dims: &Dims) -> ThinSites {
        let depth = dims.post_flush_depth();
        let radius = dims.post_depth();
        let mut out = ThinSites::default();
        for r in regions {
            for (b, inward) in boundary_samples(r, 0.25 * depth) {
                let (d, p) = deepest_inwards(r, b, inward, 4.0 * depth);
                out.middle.push((p, d));
            }
            let out_most = (radius - 2.0 * dims.wall).max(0.0);
            for (b, inward) in boundary_samples(r, 0.5 * radius) {
                let (_, middle) = deepest_inwards(r, b, inward, 2.0 * radius);
                out.pads.extend([out_most, 0.5 * out_most, 0.0].map(|t| b - inward * t));
                out.pads.push(middle);
            }
        }
        out
    }
}

/// The points sorted by their key, dropping any within `spacing` of one kept, at most `limit`.
fn nearest_apart(mut found: Vec<(f64, Point)>, spacing: f64, limit: usize) -> Vec<Point> {
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<Point> = Vec::new();
    for (_, p) in found {
        if out.len() >= limit {
            break;
        }
        if out.iter().all(|q| q.distance(p) >= spacing) {
            out.push(p);
        }
    }
    out
}

/// Where the foot of a frame stands (a scene without a fixed body): the place nearest the frame's
/// points `core`, a post's reach from each, where no body or pad comes (`hit`), preferring places no
/// link sweeps over; `None` when there is none within a few post depths.
pub(crate) fn foot(
    core: &[Point],
    dims: &Dims,
    swept: &dyn Fn(Point) -> bool,
    hit: &dyn Fn(Point) -> bool,
) -> Option<Point> {
    let reach = dims.boss_radius + dims.post_collar_radius + dims.wall;
    let step = dims.post_depth();
    let mut found: Vec<(f64, Point)> = Vec::new();
    for &c in core {
        for ring in 0..8 {
            let r = reach + ring as f64 * step;
            let n = ((std::f64::consts::TAU * r / step).ceil() as usize).max(8);
            for k in 0..n {
                let p = c + crate::geom::Vec2::from_angle(std::f64::consts::TAU * k as f64 / n as f64) * r;
                let nearest = core.iter().map(|q| q.distance(p)).fold(f64::INFINITY, f64::min);
                if nearest >= reach - 1e-9 {
                    found.push((nearest, p));
                }
            }
        }
    }
    let places = nearest_apart(found, 0.5 * step, 256);
    let mut first_free = None;
    for (tested, &p) in places.iter().enumerate() {
        if tested >= 96 && first_free.is_some() {
            break;
        }
        if hit(p) {
            continue;
        }
        if !swept(p) {
            return Some(p);
        }
        first_free.get_or_insert(p);
    }
    first_free
}

/// Every rigid carrier's pose (the ground, then each moving body) at every row of a motion, both ways,
/// computed once for the pad tests of one layout.
pub(crate) struct Poses {
    /// `[row][carrier]`: carrier to world, world to carrier.
    rows: Vec<Vec<(Rigid, Rigid)>>,
    thetas: Vec<f64>,
}

impl Poses {
    pub(crate) fn new(frames: &BodyFrames, trace: &Trace) -> Poses {
        let rows = (0..trace.len())
            .map(|r| {
                let row = trace.row(r);
                std::iter::once(Rigid::IDENTITY)
                    .chain((0..frames.body_count()).map(|b| frames.pose(b, row)))
                    .map(|p| (p, p.inverse()))
                    .collect()
            })
            .collect();
        Poses { rows, thetas: trace.thetas.clone() }
    }
}

/// The crank angle (degrees) of the first row where a disc of `radius` at `at` on carrier `c` (0 the
/// ground, `1 + b` body `b`) enters another carrier's region or pad, or `None`. The disc is exact (a
/// pad's outline lies inside it).
pub(crate) fn pad_hit(
    shapes: &SceneShapes,
    poses: &Poses,
    c: usize,
    at: Point,
    radius: f64,
    pads: &[Pad],
) -> Option<f64> {
    let tol = 1e-3 * radius;
    let carriers = 1 + shapes.bodies.len();
    let boxes: Vec<Option<crate::geom::Aabb>> = (0..carriers)
        .map(|k| {
            let mut bb: Option<crate::geom::Aabb> = None;
            for r in shapes.carrier_regions(k) {
                if let Some(b) = r.aabb() {
                    bb = Some(bb.map_or(b, |x| x.union(&b)));
                }
            }
            bb
        })
        .collect();
    for (r, row) in poses.rows.iter().enumerate() {
        let centre = row[c].0.apply(at);
        for other in (0..carriers).filter(|&o| o != c) {
            let (placed, to_local) = row[other];
            let local = to_local.apply(centre);
            let near_box = boxes[other].is_some_and(|b| b.overlaps(&disc_box(local, radius), 0.0));
            let hit = (near_box
                && shapes.carrier_regions(other).iter().any(|region| region.depth(local) > -(radius - tol)))
                || pads
                    .iter()
                    .filter(|p| p.carrier == other)
                    .any(|p| placed.apply(p.centre).distance(centre) < radius + p.radius - tol);
            if hit {
                return Some(poses.thetas[r].to_degrees());
            }
        }
    }
    None
}

fn disc_box(c: Point, r: f64) -> crate::geom::Aabb {
    crate::geom::Aabb { min: Point::new(c.x - r, c.y - r), max: Point::new(c.x + r, c.y + r) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fab::settings::PrintSettings;

    fn strip(thickness: f64) -> Region {
        let p = Point::new;
        Region { contours: vec![vec![p(0., 0.), p(60., 0.), p(60., thickness), p(0., thickness)]] }
    }

    fn query<'a>(
        regions: &'a [Region],
        thin: &'a ThinSites,
        joint: Point,
        hit: &'a dyn Fn(Point, f64) -> Option<f64>,
    ) -> Query<'a> {
        Query { regions, thin, target: (joint, joint), min_reach: 10.0, placed: &[], pads: &[], pad_hit: hit }
    }

    const ANY: Rules = Rules { clear: &|_, _| true, swept: &|_| false };

    #[test]
    fn a_wide_body_takes_the_post_inside_a_thin_one_on_its_middle_line_a_panel_a_pad() {
        let dims = Dims::new(&PrintSettings::default(), 1.0);
        let joint = Point::new(30.0, 25.0);
        let never: &dyn Fn(Point, f64) -> Option<f64> = &|_, _| None;
        let wide = [strip(20.0)];
        let thin = ThinSites::new(&wide, &dims);
        let site = place(&query(&wide, &thin, joint, never), &ANY, &dims).unwrap();
        assert!(site.pad.is_none() && wide[0].depth(site.at) >= dims.post_depth());
        // 9.5 mm: too thin for a wall around the collar, wide enough for the collar itself.
        let table = [strip(9.5)];
        let thin = ThinSites::new(&table, &dims);
        let site = place(&query(&table, &thin, joint, never), &ANY, &dims).unwrap();
        assert!(site.pad.is_none() && table[0].depth(site.at) >= dims.post_flush_depth());
        // 3 mm: a pad; on the side of the joint when the other side is blocked.
        let panel = [strip(3.0)];
        let thin = ThinSites::new(&panel, &dims);
        let below: &dyn Fn(Point, f64) -> Option<f64> = &|p, r| (p.y - r < -1e-6).then_some(12.0);
        let site = place(&query(&panel, &thin, joint, below), &ANY, &dims).unwrap();
        let r = site.pad.expect("a pad");
        assert!(site.at.y - r >= -1e-6 && panel[0].depth(site.at) > -(r - 2.0 * dims.wall) - 1e-9);
        // Blocked on every side: the first collision is reported.
        let always: &dyn Fn(Point, f64) -> Option<f64> = &|_, _| Some(42.0);
        let refused = place(&query(&panel, &thin, joint, always), &ANY, &dims);
        assert_eq!(refused, Err(Refusal::PadsCollide { at_deg: 42.0 }));
    }

    /// A slider guide over a thin ground bar (the tractable monitor's): its post stands on a pad, clear
    /// of the slot by the reach asked.
    #[test]
    fn a_guide_post_on_a_thin_bar_keeps_clear_of_its_slot() {
        let dims = Dims::new(&PrintSettings::default(), 1.0);
        let bar = [strip(4.6)];
        let thin = ThinSites::new(&bar, &dims);
        let never: &dyn Fn(Point, f64) -> Option<f64> = &|_, _| None;
        let slot = (Point::new(10.0, 20.0), Point::new(50.0, 20.0));
        let reach = dims.half_width + dims.post_collar_radius + dims.wall;
        let q = Query {
            regions: &bar,
            thin: &thin,
            target: slot,
            min_reach: reach,
            placed: &[],
            pads: &[],
            pad_hit: never,
        };
        let site = place(&q, &ANY, &dims).unwrap();
        assert!(site.pad.is_some());
        assert!(point_segment_distance(site.at, slot.0, slot.1) >= reach);
    }
}
