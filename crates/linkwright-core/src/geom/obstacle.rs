//! Fixed obstacles (fixed bodies, avoid regions) prepared once, for the many penetration and distance
//! tests that sampling and the collision sweep run against them.
//!
//! The answers are those of the brute force, [`penetrates_unchecked`](super::penetrates_unchecked)
//! and [`outline_distance`](super::outline_distance): the same expressions, evaluated on every pair
//! of features that can decide them, which are found faster.
//!
//! - The edges come in chains of a few consecutive ones, neighbours along the boundary, each with the
//!   box around it: a chain far from a mover's edge is skipped at once.
//! - A uniform grid over the obstacle tells, for each cell, whether it lies inside, outside, or within
//!   the contact tolerance of the boundary, so that most of the mover's points are placed in constant
//!   time (the even-odd test of a point near the boundary reads only the edges of its row of cells
//!   that reach its column); and it lists the edges near each cell, for the distances of the mover's
//!   vertices.
//! - The vertices, sorted by x, give those near a mover's edge.
//!
//! Exactness rests on margins, a slack of 1e-9 of the obstacle's coordinates, far above the rounding of
//! these computations: a list holds every edge within its reach, and a little more.

use super::polygon::Aabb;
use super::polygon::{boundary_distance_raw, closer, contains_deeply_raw, contains_raw, crosses_ray, segment_box};
use super::rigid::Isometry;
use super::segment::{point_segment_distance, segments_cross};
use super::vector::{Point, Vec2};
use std::ops::Range;

/// Cells along the longer side of an obstacle's box.
const CELLS: f64 = 32.0;
/// How far the cells' lists of nearby edges reach, in cells: a mover's vertex nearer than this to the
/// obstacle finds its distance there (the sweep asks for distances mostly when they are small).
const NEAR: f64 = 2.0;
/// Edges per chain.
const CHAIN: usize = 4;

/// A fixed polygon and the contact tolerance, prepared for fast tests of moving outlines against it.
#[derive(Clone, Debug)]
pub(crate) struct Obstacle {
    vertices: Vec<Point>,
    tol: f64,
    bounds: Aabb,
    /// Edge `i` runs from vertex `i` to the next; its box and its midpoint.
    edges: Vec<(Point, Point)>,
    edge_boxes: Vec<Aabb>,
    /// Per edge, its direction and inverse squared length (0 for a point).
    edge_steps: Vec<(Vec2, f64)>,
    midpoints: Vec<Point>,
    /// Chains of consecutive edges, and the box around each (and around their midpoints).
    chains: Vec<(Aabb, Range<usize>)>,
    /// The vertices by increasing x.
    by_x: Vec<Point>,
    grid: Grid,
    /// Per cell, where it lies.
    regions: Vec<Region>,
    /// Per cell, the edges within `listed_within` of it (and a little more).
    nearby: Lists,
    listed_within: f64,
    /// Per row of cells, the edges within the tolerance of it, those that reach farthest right first.
    row_edges: Lists,
    /// Per cell, how many of its row's edges reach its column or beyond: the only ones that a ray from
    /// a point of the cell towards +x can cross.
    rightward: Vec<usize>,
}

/// Where a cell of the grid lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Region {
    /// Inside, farther than the tolerance from the boundary.
    Inside,
    /// Outside, farther than the tolerance from the boundary.
    Outside,
    /// Within the tolerance of the boundary, or near enough that rounding could say so.
    Boundary,
}

impl Obstacle {
    /// Prepares the polygon `vertices` (in order, either winding) for tests with contact tolerance `tol`.
    pub(crate) fn new(vertices: &[Point], tol: f64) -> Obstacle {
        let n = vertices.len();
        let edges: Vec<(Point, Point)> = (0..n).map(|i| (vertices[i], vertices[(i + 1) % n])).collect();
        let edge_boxes: Vec<Aabb> = edges.iter().map(|&(a, b)| segment_box(a, b)).collect();
        let midpoints: Vec<Point> = edges.iter().map(|&(a, b)| a.lerp(b, 0.5)).collect();
        let edge_steps = edges
            .iter()
            .map(|&(a, b)| {
                let ab = b - a;
                (ab, if ab.norm_sq() > 0.0 { 1.0 / ab.norm_sq() } else { 0.0 })
            })
            .collect();
        let bounds = Aabb::around(vertices.iter().copied()).unwrap_or(Aabb { min: Point::ORIGIN, max: Point::ORIGIN });
        let size = bounds.width().max(bounds.height());
        let scale = [bounds.min.x, bounds.min.y, bounds.max.x, bounds.max.y].iter().fold(size, |s, c| s.max(c.abs()));
        let slack = 1e-9 * scale;
        let touch = tol + slack;
        let cell = (size / CELLS).max(touch).max(f64::MIN_POSITIVE);
        let near = NEAR * cell + slack;
        // An outer ring of cells farther than `near` from every edge: points beyond the grid, clamped
        // into it, find no edge near.
        let pad = near + 2.0 * slack + cell;
        let grid = Grid {
            origin: bounds.min - Vec2::new(pad, pad),
            cell,
            per_cell: 1.0 / cell,
            slack,
            cols: ((bounds.width() + 2.0 * pad) / cell) as usize + 1,
            rows: ((bounds.height() + 2.0 * pad) / cell) as usize + 1,
        };
        let cells = grid.cols * grid.rows;
        let mut touched = vec![false; cells];
        let mut row_edges = vec![Vec::new(); grid.rows];
        let mut nearby = vec![Vec::new(); cells];
        for (i, &(a, b)) in edges.iter().enumerate() {
            grid.spans(a, b, touch, |row, first, last| {
                touched[row * grid.cols + first..=row * grid.cols + last].fill(true);
                row_edges[row].push((last, i));
            });
            grid.spans(a, b, near, |row, first, last| {
                (first..=last).for_each(|col| nearby[row * grid.cols + col].push(i));
            });
        }
        let mut rightward = vec![0; cells];
        for (row, list) in row_edges.iter_mut().enumerate() {
            list.sort_by_key(|&(last, _)| std::cmp::Reverse(last));
            for col in 0..grid.cols {
                rightward[row * grid.cols + col] = list.iter().take_while(|&&(last, _)| last >= col).count();
            }
        }
        let regions = (0..cells)
            .map(|k| match (touched[k], contains_raw(vertices, grid.center(k))) {
                (true, _) => Region::Boundary,
                (false, true) => Region::Inside,
                (false, false) => Region::Outside,
            })
            .collect();
        let chains = (0..n)
            .step_by(CHAIN)
            .map(|start| {
                let chain = start..n.min(start + CHAIN);
                let mut bb = edge_boxes[start];
                chain.clone().for_each(|j| {
                    bb = bb.union(&edge_boxes[j]);
                    bb.include(midpoints[j]);
                });
                (bb, chain)
            })
            .collect();
        let mut by_x = vertices.to_vec();
        by_x.sort_by(|p, q| p.x.total_cmp(&q.x));
        Obstacle {
            vertices: vertices.to_vec(),
            tol,
            bounds,
            edges,
            edge_boxes,
            edge_steps,
            midpoints,
            chains,
            by_x,
            grid,
            regions,
            nearby: Lists::new(nearby),
            listed_within: near - slack,
            row_edges: Lists::new(
                row_edges.into_iter().map(|list| list.into_iter().map(|(_, i)| i).collect()).collect(),
            ),
            rightward,
        }
    }

    /// The polygon's vertices, as given.
    #[cfg(test)]
    pub(crate) fn vertices(&self) -> &[Point] {
        &self.vertices
    }
    /// The polygon's bounding box.
    pub(crate) fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Whether `mover` (a closed outline, or a segment when it has two points) penetrates the obstacle
    /// deeper than the contact tolerance: [`penetrates_unchecked`](super::penetrates_unchecked)`(mover,
    /// vertices, tol)`, exactly.
    pub(crate) fn penetrated_by(&self, mover: &[Point]) -> bool {
        let Some(mover_box) = Aabb::around(mover.iter().copied()) else { return false };
        self.edges_cross(mover) || self.mover_points_inside(mover) || self.probes_inside(mover, &mover_box, |_| None)
    }

    /// [`Obstacle::penetrated_by`] for a mover whose vertices `mover` are those of `shape` (an outline
    /// prepared in its own frame, with the same tolerance) placed by `pose`: the same answer. Whether a
    /// point of this obstacle lies deep inside the mover is read from `shape`'s grid, the point taken
    /// into the mover's frame, wherever the grid decides it; only points near the mover's boundary
    /// are tested against its edges. The grid's margins, far above the rounding of that change of
    /// frame, keep the answers those of the brute force.
    pub(crate) fn penetrated_by_shape(&self, mover: &[Point], shape: &Obstacle, pose: &Isometry) -> bool {
        let Some(mover_box) = Aabb::around(mover.iter().copied()) else { return false };
        let to_shape = pose.inverse();
        self.edges_cross(mover)
            || self.mover_points_inside(mover)
            || self.probes_inside(mover, &mover_box, |p| shape.decided_deep(to_shape.apply(p)))
    }

    /// [`Obstacle::penetrated_by`]'s verdict for every placement of the outline `mover` (at least
    /// three points) that a rigid motion reaches from this one without moving any point of `mover`
    /// farther than `reach`, on the way too; `None` where it may differ between them.
    ///
    /// - `Some(false)` when the boundaries do not meet, are farther apart than `reach`, and neither
    ///   outline holds the other: along any such motion the boundaries never meet, so no edge crosses
    ///   and no point of either enters the other.
    /// - `Some(true)` when a vertex or edge midpoint of one lies inside the other deeper than the
    ///   tolerance plus `reach`: it stays deeper than the tolerance, on the same side.
    ///
    /// Both keep a margin of 1e-8 of the coordinates, far above the rounding of the placements and of
    /// the brute force's expressions.
    pub(crate) fn penetration_within(&self, mover: &[Point], reach: f64) -> Option<bool> {
        let obstacle = &self.vertices[..];
        if mover.len() < 3 || obstacle.len() < 3 || reach.is_nan() || reach < 0.0 {
            return None;
        }
        let scale = obstacle.iter().chain(mover).fold(reach, |s, p| s.max(p.x.abs()).max(p.y.abs()));
        let margin = 1e-8 * scale;
        let deep = self.tol + reach + margin;
        let mover_box = Aabb::around(mover.iter().copied())?;
        // Boxes apart: so are the outlines, and their boundaries by at least the gap.
        if mover_box.gap(&self.bounds) > reach + margin {
            return Some(false);
        }
        // The vertex-to-edge distances are the boundaries' distance only where no edges meet.
        if !self.edges_meet(mover) {
            let distance = self.boundary_distance(mover);
            if !distance.is_finite() {
                return None;
            }
            if distance > reach + margin {
                // Either the outlines are apart, or one holds the other whole.
                let held = contains_raw(obstacle, mover[0]) || contains_raw(mover, obstacle[0]);
                return if held { (distance > deep).then_some(true) } else { Some(false) };
            }
        }
        // A point of one outline deeper than `deep` inside the other (in the other's box, then).
        let deep_in = |points: &[Point], poly: &[Point], poly_box: &Aabb| {
            let n = points.len();
            (0..n).any(|i| {
                [points[i], points[i].lerp(points[(i + 1) % n], 0.5)]
                    .into_iter()
                    .any(|q| poly_box.contains(q) && contains_raw(poly, q) && boundary_distance_raw(poly, q) > deep)
            })
        };
        (deep_in(mover, obstacle, &self.bounds) || deep_in(obstacle, mover, &mover_box)).then_some(true)
    }

    /// Whether an edge of the outline `mover` and one of the obstacle's meet or nearly do: crossing,
    /// touching, or on a common line (no tolerance; a pair that rounding could call apart counts).
    fn edges_meet(&self, mover: &[Point]) -> bool {
        let n = mover.len();
        let side = |a: Point, b: Point, c: Point| (b - a).cross(c - a);
        (0..n).any(|i| {
            let (a0, a1) = (mover[i], mover[(i + 1) % n]);
            let edge_a = segment_box(a0, a1);
            self.edges.iter().zip(&self.edge_boxes).any(|(&(b0, b1), edge_b)| {
                edge_a.overlaps(edge_b, -self.grid.slack)
                    && side(a0, a1, b0) * side(a0, a1, b1) <= 0.0
                    && side(b0, b1, a0) * side(b0, b1, a1) <= 0.0
            })
        })
    }

    /// The least distance between the boundaries of `mover` (an outline, or a segment when it has two
    /// points) and of the obstacle: [`outline_distance`](super::outline_distance)`(mover, vertices)`,
    /// up to rounding (both skip pairs whose boxes are no nearer than the best distance so far, and
    /// they meet the pairs in different orders).
    pub(crate) fn boundary_distance(&self, mover: &[Point]) -> f64 {
        // As in `outline_distance`, a two-point outline has one edge.
        let edge_count = |n: usize| if n == 2 { 1 } else { n };
        let obstacle_edges = edge_count(self.vertices.len());
        let mut best = f64::INFINITY;
        // The mover's vertices against the edges listed near them: each vertex's distance, when it is
        // within the lists' reach.
        for &v in mover {
            for &j in self.nearby.of(self.grid.cell_of(v)).iter().filter(|&&j| j < obstacle_edges) {
                best = best.min(self.edge_distance_sq(j, v));
            }
        }
        // The obstacle's vertices against the mover's edges.
        let n = mover.len();
        for i in 0..edge_count(n) {
            self.vertices_to_edge(mover[i], mover[(i + 1) % n], &mut best);
        }
        // Beyond the lists' reach (then every vertex is), the mover's vertices against all the edges.
        if best > self.listed_within * self.listed_within {
            for &v in mover {
                self.vertex_to_edges(v, obstacle_edges, &mut best);
            }
        }
        best.sqrt()
    }

    /// An edge of the mover crossing one of the obstacle's, among the pairs whose boxes overlap (grown
    /// by the tolerance), which are those the brute force tests.
    fn edges_cross(&self, mover: &[Point]) -> bool {
        let (n, tol) = (mover.len(), self.tol);
        for i in 0..n {
            let (a0, a1) = (mover[i], mover[(i + 1) % n]);
            let edge_a = segment_box(a0, a1);
            if !edge_a.overlaps(&self.bounds, -tol) {
                continue;
            }
            for (chain_box, chain) in &self.chains {
                if !edge_a.overlaps(chain_box, -tol) {
                    continue;
                }
                for j in chain.clone() {
                    let (b0, b1) = self.edges[j];
                    if edge_a.overlaps(&self.edge_boxes[j], -tol) && segments_cross(a0, a1, b0, b1, tol) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// A vertex or edge midpoint of the mover deep inside the obstacle.
    fn mover_points_inside(&self, mover: &[Point]) -> bool {
        let n = mover.len();
        (0..n).any(|i| self.deeply_contains(mover[i]) || self.deeply_contains(mover[i].lerp(mover[(i + 1) % n], 0.5)))
    }

    /// A vertex or edge midpoint of the obstacle, in the mover's box, deep inside the mover: as
    /// `decided` says when it says, else tested against the mover's edges (a few points against a
    /// small outline: brute force).
    fn probes_inside(&self, mover: &[Point], mover_box: &Aabb, decided: impl Fn(Point) -> Option<bool>) -> bool {
        let meets = |b: &Aabb| {
            b.min.x <= mover_box.max.x
                && mover_box.min.x <= b.max.x
                && b.min.y <= mover_box.max.y
                && mover_box.min.y <= b.max.y
        };
        let deep =
            |p: Point| mover_box.contains(p) && decided(p).unwrap_or_else(|| contains_deeply_raw(mover, p, self.tol));
        self.chains
            .iter()
            .filter(|(chain_box, _)| meets(chain_box))
            .any(|(_, chain)| chain.clone().any(|j| deep(self.vertices[j]) || deep(self.midpoints[j])))
    }

    /// Whether `p` lies inside, farther than the tolerance from the boundary, when its cell of the grid
    /// decides it for every point near it (within the slack); `None` near the boundary. With a
    /// tolerance of 0, whether `p` lies inside, as the even-odd test answers, where the grid decides.
    pub(crate) fn decided_deep(&self, p: Point) -> Option<bool> {
        match self.regions[self.grid.cell_of(p)] {
            Region::Inside => Some(true),
            Region::Outside => Some(false),
            Region::Boundary => None,
        }
    }

    /// Whether `p` lies inside, farther than the tolerance from the boundary, as the brute force's box
    /// test and `contains_deeply_raw` answer.
    fn deeply_contains(&self, p: Point) -> bool {
        if !self.bounds.contains(p) {
            return false;
        }
        let cell = self.grid.cell_of(p);
        match self.regions[cell] {
            // The even-odd test answers the same anywhere in the cell (and right, this far from the
            // boundary).
            Region::Inside => true,
            Region::Outside => false,
            // The even-odd test counts only edges crossing the ray right of `p`, which reach this
            // column, and the edges within the tolerance are listed. Most points near the boundary
            // are outside: the cheaper test first.
            Region::Boundary => {
                let row = cell / self.grid.cols;
                let crossings = self.row_edges.of(row)[..self.rightward[cell]]
                    .iter()
                    .filter(|&&j| crosses_ray(self.edges[j].0, self.edges[j].1, p))
                    .count();
                crossings % 2 == 1
                    && self
                        .nearby
                        .of(cell)
                        .iter()
                        .all(|&j| point_segment_distance(p, self.edges[j].0, self.edges[j].1) > self.tol)
            }
        }
    }

    /// The squared distance from `p` to edge `j`: [`point_segment_distance_sq`](super::point_segment_distance_sq) with the edge's
    /// direction and inverse squared length kept (a multiplication where it divides; the distances
    /// agree to rounding, as `boundary_distance` promises).
    fn edge_distance_sq(&self, j: usize, p: Point) -> f64 {
        let (a, (ab, inverse)) = (self.edges[j].0, self.edge_steps[j]);
        let t = ((p - a).dot(ab) * inverse).clamp(0.0, 1.0);
        (p - (a + ab * t)).norm_sq()
    }

    /// Lowers `best` (squared) to the distances between the obstacle's vertices and the segment
    /// `a0`–`a1`, among the vertices nearer than the best so far to the segment's box.
    fn vertices_to_edge(&self, a0: Point, a1: Point, best: &mut f64) {
        let edge_a = segment_box(a0, a1);
        if edge_a.gap_sq(&self.bounds) >= *best {
            return;
        }
        let r = Vec2::new(1.0, 1.0) * (best.sqrt() + self.grid.slack);
        let reach = Aabb { min: edge_a.min - r, max: edge_a.max + r };
        let from = self.by_x.partition_point(|w| w.x < reach.min.x);
        for &w in self.by_x[from..].iter().take_while(|w| w.x <= reach.max.x) {
            if reach.contains(w) {
                closer(best, w, (a0, a1), &edge_a);
            }
        }
    }

    /// Lowers `best` (squared) to the distances between `v` and the first `count` edges, among the
    /// chains nearer than the best so far.
    fn vertex_to_edges(&self, v: Point, count: usize, best: &mut f64) {
        let point = Aabb { min: v, max: v };
        if point.gap_sq(&self.bounds) >= *best {
            return;
        }
        for (chain_box, chain) in &self.chains {
            if point.gap_sq(chain_box) < *best {
                for j in chain.start..chain.end.min(count) {
                    closer(best, v, self.edges[j], &self.edge_boxes[j]);
                }
            }
        }
    }
}

/// A uniform grid of square cells, row after row.
#[derive(Clone, Debug)]
struct Grid {
    origin: Point,
    cell: f64,
    /// `1 / cell`: a point's cell is found by multiplying (a division takes several times as long,
    /// and the cells' margins hold either rounding).
    per_cell: f64,
    /// A length far above the rounding of coordinates near the grid.
    slack: f64,
    cols: usize,
    rows: usize,
}

impl Grid {
    fn col(&self, x: f64) -> usize {
        index((x - self.origin.x) * self.per_cell, self.cols)
    }
    fn row(&self, y: f64) -> usize {
        index((y - self.origin.y) * self.per_cell, self.rows)
    }
    /// The cell of `p`, or the nearest border cell when `p` is beyond the grid.
    fn cell_of(&self, p: Point) -> usize {
        self.row(p.y) * self.cols + self.col(p.x)
    }
    fn center(&self, k: usize) -> Point {
        let (row, col) = (k / self.cols, k % self.cols);
        self.origin + Vec2::new(col as f64 + 0.5, row as f64 + 0.5) * self.cell
    }

    /// Calls `visit(row, first, last)` with spans of cells, one per row, that together hold every cell
    /// within `margin` of the segment `p`–`q` (and within the slack more, for the rounding of the rows'
    /// bounds and of the clip).
    fn spans(&self, p: Point, q: Point, margin: f64, mut visit: impl FnMut(usize, usize, usize)) {
        let (d, grow) = (q - p, margin + self.slack);
        for row in self.row(p.y.min(q.y) - grow)..=self.row(p.y.max(q.y) + grow) {
            // The part of the segment within the row's band, grown.
            let low = self.origin.y + row as f64 * self.cell - grow;
            let high = low + self.cell + 2.0 * grow;
            let (x0, x1) = if d.y == 0.0 {
                (p.x, q.x)
            } else {
                let at = |y: f64| p.x + d.x * ((y - p.y) / d.y).clamp(0.0, 1.0);
                (at(low), at(high))
            };
            visit(row, self.col(x0.min(x1) - grow), self.col(x0.max(x1) + grow));
        }
    }
}

/// The index of coordinate `t` (in cells from the origin), clamped to `0..n`.
fn index(t: f64, n: usize) -> usize {
    // `as` truncates, which floors what `max` left non-negative, saturates, and takes NaN to 0; through
    // `u32`, it is far cheaper than to `usize`.
    (t.max(0.0) as u32 as usize).min(n - 1)
}

/// One list of indices per cell (or row), stored end to end.
#[derive(Clone, Debug)]
struct Lists {
    start: Vec<usize>,
    items: Vec<usize>,
}

impl Lists {
    fn new(lists: Vec<Vec<usize>>) -> Lists {
        let mut start = vec![0];
        start.extend(lists.iter().scan(0, |end, list| {
            *end += list.len();
            Some(*end)
        }));
        Lists { start, items: lists.concat() }
    }
    fn of(&self, k: usize) -> &[usize] {
        &self.items[self.start[k]..self.start[k + 1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{outline_distance, penetrates_unchecked, Polygon, Rigid};
    use crate::scene::{Problem, Scene};
    use proptest::prelude::*;
    use rand::{RngExt, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// Both answers for `mover` are the brute force's: the same penetration verdict, the same
    /// distance up to rounding (of the coordinates: a pair the brute force skips for a box one unit in
    /// the last place farther than the best so far can be a little nearer). Returns the verdict.
    fn assert_agrees(obstacle: &Obstacle, mover: &[Point]) -> bool {
        let (vertices, tol) = (obstacle.vertices(), obstacle.tol);
        let penetrates = penetrates_unchecked(mover, vertices, tol);
        assert_eq!(
            obstacle.penetrated_by(mover),
            penetrates,
            "penetration by {mover:?} of {vertices:?}, tolerance {tol}"
        );
        let (fast, brute) = (obstacle.boundary_distance(mover), outline_distance(mover, vertices));
        let scale = vertices.iter().chain(mover).fold(0.0, |s: f64, p| s.max(p.x.abs()).max(p.y.abs()));
        assert!(
            fast == brute || (fast - brute).abs() <= 1e-12 * scale,
            "distance {fast} != {brute} between {mover:?} and {vertices:?}"
        );
        penetrates
    }

    /// A polygon around `center` with `n` vertices in angular order at distances up to `radius`:
    /// convex when `concave` is false (all on the circle), star-shaped otherwise.
    fn star(rng: &mut Xoshiro256PlusPlus, n: usize, center: Point, radius: f64, concave: bool) -> Vec<Point> {
        let turn = rng.random_range(0.0..std::f64::consts::TAU);
        (0..n)
            .map(|i| {
                let angle = turn + (i as f64 + rng.random_range(0.0..0.9)) * std::f64::consts::TAU / n as f64;
                let r = if concave { radius * rng.random_range(0.2..1.0) } else { radius };
                center + Vec2::from_angle(angle) * r
            })
            .collect()
    }

    /// A polygon with axis-parallel edges and a notch, like a frame around a cavity: its edges meet
    /// the axis-parallel edges of movers exactly.
    fn notched(origin: Point, size: f64) -> Vec<Point> {
        [[0., 0.], [4., 0.], [4., 3.], [3., 3.], [3., 1.], [1., 1.], [1., 3.], [0., 3.]]
            .iter()
            .map(|&[x, y]| origin + Vec2::new(x, y) * (size / 4.0))
            .collect()
    }

    /// A mover of some kind near `obstacle`: a polygon or a segment anywhere about it, one with a
    /// vertex on (or within a few tolerances of) an edge or a vertex, one sliding along an edge, or a
    /// degenerate one.
    fn mover(rng: &mut Xoshiro256PlusPlus, obstacle: &Obstacle) -> Vec<Point> {
        let bb = obstacle.bounds();
        let size = bb.width().max(bb.height()).max(1e-9);
        let tol = obstacle.tol;
        let anywhere = |rng: &mut Xoshiro256PlusPlus| {
            Point::new(
                rng.random_range(bb.min.x - 0.3 * size..=bb.max.x + 0.3 * size),
                rng.random_range(bb.min.y - 0.3 * size..=bb.max.y + 0.3 * size),
            )
        };
        let edges = obstacle.vertices().len();
        // A point on an edge, or off it along the normal by a few tolerances (on either side, at
        // exactly the tolerance too).
        let near_edge = |rng: &mut Xoshiro256PlusPlus, t: f64| {
            let (a, b) = obstacle.edges[rng.random_range(0..edges)];
            let offset = [0.0, 0.5, 1.0, 2.0, -0.5, -1.0, -2.0][rng.random_range(0..7)] * tol;
            let normal = if a == b { Vec2::new(0.0, 1.0) } else { (b - a).perp().normalized() };
            (a.lerp(b, t) + normal * offset, b - a)
        };
        match rng.random_range(0..7) {
            0 => {
                let (n, radius, center, concave) =
                    (rng.random_range(3..12), size * rng.random_range(0.02..1.0), anywhere(rng), rng.random_bool(0.5));
                star(rng, n, center, radius, concave)
            }
            1 => vec![anywhere(rng), anywhere(rng)],
            2 => {
                // A vertex on an edge (at its ends and middle too) or near it.
                let t = [0.0, 0.5, 1.0, rng.random_range(0.0..1.0)][rng.random_range(0..4)];
                let (q, _) = near_edge(rng, t);
                let (n, radius, concave) =
                    (rng.random_range(2..8), size * rng.random_range(0.01..0.5), rng.random_bool(0.5));
                let mut outline = star(rng, n, q, radius, concave);
                let shift = q - outline[0];
                outline.iter_mut().for_each(|p| *p = *p + shift);
                outline
            }
            3 => {
                // An edge along an edge, on it or a few tolerances off, with a third vertex on
                // either side (or none: a segment).
                let (s, t) = (rng.random_range(-0.2..1.2), rng.random_range(-0.2..1.2));
                let (p, along) = near_edge(rng, s);
                let q = p + along * (t - s);
                let side = along.perp() * rng.random_range(-1.0..1.0);
                if rng.random_bool(0.3) {
                    vec![p, q]
                } else {
                    vec![p, q, p.lerp(q, 0.5) + side]
                }
            }
            4 => {
                // A vertex on one of the obstacle's vertices.
                let w = obstacle.vertices()[rng.random_range(0..edges)];
                vec![w, w + Vec2::from_angle(rng.random_range(0.0..7.0)) * size * 0.3, anywhere(rng)]
            }
            5 => {
                // The obstacle itself, moved a little (the same edges, nearly coincident).
                let shift = Vec2::new(rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0)) * tol;
                obstacle.vertices().iter().map(|&p| p + shift).collect()
            }
            _ => {
                // Degenerate: one point, a point-like segment, three points on a line.
                let p = anywhere(rng);
                match rng.random_range(0..3) {
                    0 => vec![p],
                    1 => vec![p, p],
                    _ => {
                        let q = anywhere(rng);
                        vec![p, p.lerp(q, 0.3), q]
                    }
                }
            }
        }
    }

    proptest! {
        /// Random convex, star-shaped and notched obstacles at scales from 1e-3 to 1e3 and far from
        /// the origin, against random movers of every kind.
        #[test]
        fn agrees_with_the_brute_force(seed in any::<u64>(), n in 3..40usize, shape in 0..3u8,
                                       scale in -3.0..3.0f64, far in any::<bool>(), tol_kind in 0..4usize) {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let size = 10f64.powf(scale);
            let center = if far { Point::new(1e4, -3e4) } else { Point::ORIGIN };
            let vertices = match shape {
                0 => star(&mut rng, n, center, size, false),
                1 => star(&mut rng, n, center, size, true),
                _ => notched(center, size),
            };
            let tol = [0.0, 1e-6, 1e-3, 0.05][tol_kind] * size;
            let obstacle = Obstacle::new(&vertices, tol);
            let verdicts: usize = (0..64).map(|_| assert_agrees(&obstacle, &mover(&mut rng, &obstacle)) as usize).sum();
            // Both verdicts occur, so both are compared.
            prop_assert!(verdicts > 0 && verdicts < 64, "{verdicts} of 64 penetrate");
        }
    }

    proptest! {
        /// A mover given as an outline prepared in its own frame and a pose: the outline's grid tells
        /// which of the obstacle's points lie deep inside the mover as the brute force does. Outlines
        /// from a fifth of the obstacle's size to three times it (covering it whole), placed anywhere
        /// about it (or beyond, to their size) or with a vertex on or a few tolerances off an edge.
        #[test]
        fn placed_shapes_agree_with_the_brute_force(seed in any::<u64>(), n in 3..40usize, notch in any::<bool>(),
                                                    scale in -3.0..3.0f64, far in any::<bool>(), tol_kind in 0..4usize) {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let size = 10f64.powf(scale);
            let center = if far { Point::new(1e4, -3e4) } else { Point::ORIGIN };
            let vertices = if notch { notched(center, size) } else { star(&mut rng, n, center, size, true) };
            let tol = [0.0, 1e-6, 1e-3, 0.05][tol_kind] * size;
            let obstacle = Obstacle::new(&vertices, tol);
            let bb = obstacle.bounds();
            let mut verdicts = 0;
            for k in 0..64 {
                let (m, radius, concave) = (rng.random_range(3..12), size * rng.random_range(0.2..3.0), rng.random_bool(0.5));
                let local = star(&mut rng, m, Point::ORIGIN, radius, concave);
                let shape = Obstacle::new(&local, tol);
                // Where the shape's origin goes, or its first vertex on or near an edge.
                let (anchor, target) = if k % 2 == 0 {
                    let reach = Vec2::new(radius, radius);
                    let (lo, hi) = (bb.min - reach, bb.max + reach);
                    (Point::ORIGIN, Point::new(rng.random_range(lo.x..=hi.x), rng.random_range(lo.y..=hi.y)))
                } else {
                    let (a, b) = obstacle.edges[rng.random_range(0..obstacle.edges.len())];
                    let offset = [0.0, 0.5, 1.0, 2.0, -0.5, -1.0, -2.0][rng.random_range(0..7)] * tol;
                    (local[0], a.lerp(b, rng.random_range(0.0..1.0)) + (b - a).perp().normalized() * offset)
                };
                let angle = rng.random_range(0.0..std::f64::consts::TAU);
                let pose = Rigid::new(angle, target - Rigid::new(angle, Vec2::ZERO).apply(anchor));
                let placed: Vec<Point> = local.iter().map(|&p| pose.apply(p)).collect();
                let brute = penetrates_unchecked(&placed, &vertices, tol);
                prop_assert_eq!(obstacle.penetrated_by_shape(&placed, &shape, &pose.isometry()), brute, "{:?} placed by {:?}", local, pose);
                verdicts += brute as usize;
            }
            prop_assert!(verdicts > 0 && verdicts < 64, "{} of 64 penetrate", verdicts);
        }
    }

    proptest! {
        /// A verdict for every placement within reach is the brute force's at placements as far as
        /// the reach allows (every point moved by up to it), and both verdicts occur.
        #[test]
        fn verdicts_within_reach_hold_for_every_placement(seed in any::<u64>(), n in 3..30usize, notch in any::<bool>(),
                                                           scale in -2.0..2.0f64, tol_kind in 0..3usize) {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let size = 10f64.powf(scale);
            let vertices = if notch { notched(Point::ORIGIN, size) } else { star(&mut rng, n, Point::ORIGIN, size, true) };
            let tol = [0.0, 1e-3, 0.05][tol_kind] * size;
            let obstacle = Obstacle::new(&vertices, tol);
            let mut decided = [0usize; 2];
            for _ in 0..48 {
                let mover = mover(&mut rng, &obstacle);
                if mover.len() < 3 {
                    continue;
                }
                let reach = size * [0.0, 0.01, 0.1, 0.4][rng.random_range(0..4)];
                let Some(verdict) = obstacle.penetration_within(&mover, reach) else { continue };
                decided[verdict as usize] += 1;
                // Rigid motions about a point of the mover, scaled so that the farthest point moves
                // by the whole reach (or a part of it).
                let pivot = mover[rng.random_range(0..mover.len())];
                let arm = mover.iter().fold(0.0, |r: f64, &p| r.max(p.distance(pivot)));
                for _ in 0..8 {
                    let (turn, shift): (f64, Vec2) = (rng.random_range(-1.0..1.0), Vec2::from_angle(rng.random_range(0.0..7.0)));
                    let budget = reach * [1.0, rng.random_range(0.0..1.0)][rng.random_range(0..2)];
                    let share = rng.random_range(0.0..=1.0);
                    let angle = if arm > 0.0 { turn.signum() * share * budget / arm } else { 0.0 };
                    let shift = shift * ((1.0 - share) * budget);
                    let motion = Rigid::new(angle, Vec2::ZERO);
                    let moved: Vec<Point> = mover.iter().map(|&p| pivot + motion.rotate(p - pivot) + shift).collect();
                    prop_assert_eq!(penetrates_unchecked(&moved, &vertices, tol), verdict, "{:?} moved to {:?}, reach {}", mover, moved, reach);
                }
            }
            prop_assert!(decided[0] + decided[1] > 0, "no verdict");
        }
    }

    /// Both verdicts within reach occur on the shapes of the property test.
    #[test]
    fn verdicts_within_reach_are_often_decided() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let mut counts = [0usize; 3];
        for _ in 0..1000 {
            let vertices = star(&mut rng, 12, Point::ORIGIN, 1.0, true);
            let obstacle = Obstacle::new(&vertices, 1e-3);
            let mover = mover(&mut rng, &obstacle);
            if mover.len() >= 3 {
                counts[obstacle.penetration_within(&mover, 0.05).map_or(2, usize::from)] += 1;
            }
        }
        assert!(counts[0] > 40 && counts[1] > 40, "clear, penetrated, undecided: {counts:?}");
    }

    #[test]
    fn degenerate_obstacles_agree_with_the_brute_force() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
        let p = Point::new;
        for vertices in [vec![], vec![p(1., 2.)], vec![p(0., 0.), p(3., 1.)], vec![p(0., 0.), p(1., 1.), p(2., 2.)]] {
            let obstacle = Obstacle::new(&vertices, 1e-3);
            for _ in 0..200 {
                let n = rng.random_range(1..6);
                let mover: Vec<Point> =
                    (0..n).map(|_| p(rng.random_range(-1.0..4.0), rng.random_range(-1.0..4.0))).collect();
                assert_agrees(&obstacle, &mover);
            }
        }
    }

    /// The fixed bodies and avoid regions of every example scene, against its moving bodies along
    /// their poses (and nudged off them) and against segments across its linkage region.
    #[test]
    fn agrees_with_the_brute_force_on_the_reference_scenes() {
        let dir = format!("{}/../../examples", env!("CARGO_MANIFEST_DIR"));
        let mut scenes = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "json") {
                continue;
            }
            let problem = Problem::new(&Scene::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap()).unwrap();
            let tol = problem.contact_tolerance();
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(scenes);
            let mut movers = Vec::new();
            // Each body's placed outline and its pose, for the test with the body's own grid.
            let mut placed: Vec<(Vec<Point>, Rigid)> = Vec::new();
            for body in &problem.bodies {
                for pair in body.poses.windows(2) {
                    for k in 0..=40 {
                        let t = k as f64 / 40.0;
                        let pose = Rigid::new(
                            pair[0].angle() + t * (pair[1].angle() - pair[0].angle()),
                            pair[0].translation() + (pair[1].translation() - pair[0].translation()) * t,
                        );
                        let nudge = Vec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)) * (3.0 * tol);
                        let outline = body.outline.transformed(&pose);
                        movers.push(outline.vertices().iter().map(|&p| p + nudge).collect::<Vec<_>>());
                        movers.push(outline.vertices().to_vec());
                        let nudged = Rigid::new(pose.angle(), pose.translation() + nudge);
                        placed.push((body.outline.vertices().iter().map(|&p| nudged.apply(p)).collect(), nudged));
                        placed.push((outline.vertices().to_vec(), pose));
                    }
                }
            }
            let region = problem.region.aabb();
            let inside = |rng: &mut Xoshiro256PlusPlus| {
                Point::new(rng.random_range(region.min.x..=region.max.x), rng.random_range(region.min.y..=region.max.y))
            };
            movers.extend((0..500).map(|_| vec![inside(&mut rng), inside(&mut rng)]));
            let obstacles = problem.fixed.iter().chain(&problem.avoid).map(Polygon::vertices);
            for vertices in obstacles {
                let obstacle = Obstacle::new(vertices, tol);
                for mover in &movers {
                    assert_agrees(&obstacle, mover);
                }
                for (b, body) in problem.bodies.iter().enumerate() {
                    let shape = Obstacle::new(body.outline.vertices(), tol);
                    let per_body = placed.len() / problem.bodies.len();
                    for (mover, pose) in &placed[b * per_body..(b + 1) * per_body] {
                        let brute = penetrates_unchecked(mover, vertices, tol);
                        assert_eq!(
                            obstacle.penetrated_by_shape(mover, &shape, &pose.isometry()),
                            brute,
                            "{mover:?} placed by {pose:?}"
                        );
                    }
                }
            }
            scenes += 1;
        }
        assert!(scenes >= 10, "{scenes} example scenes");
    }
}
