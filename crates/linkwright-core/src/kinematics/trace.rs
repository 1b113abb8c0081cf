//! A motion sampled along the crank's travel, and the moving bodies' poses along it.

use super::plan::Plan;
use super::DyadError;
use crate::geom::{Isometry, Point, Rigid, Vec2};
use crate::mechanism::Mechanism;

/// Why a sweep stopped.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("the linkage cannot assemble at crank angle {theta_deg:.2}° (step {step}: {cause})")]
pub struct SweepError {
    /// The crank angle at which the linkage came apart, degrees.
    pub theta_deg: f64,
    /// The index of the plan's step that failed ([`Plan::steps`]).
    pub step: usize,
    /// Why that step has no solution.
    pub cause: DyadError,
}

/// Joint positions at a sequence of crank angles along one travel.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    /// Crank angles, radians, unwrapped, in travel order.
    pub thetas: Vec<f64>,
    /// `thetas.len() × joint_count` positions, one row per angle.
    pub positions: Vec<Point>,
    /// Joints per row.
    pub joint_count: usize,
}

impl Trace {
    /// An empty trace for mechanisms with `joint_count` joints.
    pub fn new(joint_count: usize) -> Trace {
        Trace { joint_count, ..Trace::default() }
    }

    /// Sweeps the crank from `from` to `to` (radians) in equal steps of at most `max_step`, keeping the
    /// plan's branches. Reuses `self`'s buffers.
    ///
    /// # Examples
    ///
    /// A full turn of the crank-rocker four-bar of [`Plan`]'s example, in steps of at most 1°. Its
    /// rocker r0–q1 swings between the two positions where crank and coupler lie on one line, with
    /// q0–q1 as long as b + a and b − a; the law of cosines in the triangle q0 r0 q1 gives the rocker's
    /// angle at each.
    ///
    /// ```
    /// # use linkwright_core::geom::Point;
    /// # use linkwright_core::kinematics::Plan;
    /// # use linkwright_core::{Mechanism, Topology};
    /// # use std::sync::Arc;
    /// # let (a, b, c, d) = (1.0, 20f64.sqrt(), 3.0, 4.0);
    /// # let topology = Topology::chain(1);
    /// # let [q0, r0, p1, q1] = ["q0", "r0", "p1", "q1"].map(|name| topology.joint(name).unwrap());
    /// # let mut joints = vec![Point::ORIGIN; topology.joint_count()];
    /// # joints[q0] = Point::new(0.0, 0.0);
    /// # joints[r0] = Point::new(d, 0.0);
    /// # joints[p1] = Point::new(0.0, a);
    /// # joints[q1] = Point::new(d, c);
    /// # let mechanism = Mechanism { topology: Arc::new(topology), joints, slider: None };
    /// # let plan = Plan::compile(&mechanism)?;
    /// use linkwright_core::kinematics::Trace;
    /// use std::f64::consts::TAU;
    ///
    /// let start = mechanism.crank_start();
    /// let mut trace = Trace::new(plan.joint_count());
    /// trace.sweep(&plan, start, start + TAU, 1f64.to_radians())?;
    /// // A full turn brings the linkage back to its first pose.
    /// assert!(trace.row(0)[q1].distance(Point::new(d, c)) < 1e-12);
    /// assert!(trace.row(trace.len() - 1)[q1].distance(Point::new(d, c)) < 1e-12);
    ///
    /// // The rocker's angle at r0, from r0→q0, with q0–q1 of length e.
    /// let rocker_angle = |e: f64| ((c * c + d * d - e * e) / (2.0 * c * d)).acos();
    /// let swing = rocker_angle(b + a) - rocker_angle(b - a);
    /// let (mut lowest, mut highest) = (f64::MAX, f64::MIN);
    /// for s in 0..trace.len() {
    ///     let angle = (trace.row(s)[q1] - trace.row(s)[r0]).angle();
    ///     (lowest, highest) = (lowest.min(angle), highest.max(angle));
    /// }
    /// // Rows 1° apart miss the extremes, where the rocker stops, only by a second-order amount.
    /// assert!((highest - lowest - swing).abs() < 1e-4, "{} != {swing}", highest - lowest);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn sweep(&mut self, plan: &Plan, from: f64, to: f64, max_step: f64) -> Result<(), SweepError> {
        let n = plan.joint_count();
        self.clear(n);
        let steps = Trace::sweep_rows(from, to, max_step) - 1;
        self.positions.resize((steps + 1) * n, Point::ORIGIN);
        // The crank's direction turns by one fixed rotation per step; it is recomputed from its angle
        // every few steps so rounding cannot build up.
        let turn = Rigid::new((to - from) / steps as f64, Vec2::ZERO);
        let mut crank = Vec2::ZERO;
        for (s, row) in self.positions.chunks_exact_mut(n).enumerate() {
            let theta = from + (to - from) * (s as f64 / steps as f64);
            crank = if s % 32 == 0 { Vec2::from_angle(theta) } else { turn.rotate(crank) };
            plan.place_crank(crank, row);
            self.thetas.push(theta);
        }
        plan.solve_rows(&mut self.positions).map_err(|(row, step, cause)| {
            let theta_deg = self.thetas[row].to_degrees();
            self.thetas.truncate(row);
            self.positions.truncate(row * n);
            SweepError { theta_deg, step, cause }
        })
    }

    /// How many rows [`Trace::sweep`] gives from `from` to `to` in steps of at most `max_step`.
    pub fn sweep_rows(from: f64, to: f64, max_step: f64) -> usize {
        (((to - from).abs() / max_step).ceil() as usize).max(1) + 1
    }

    /// Room for `rows` more rows than the trace holds.
    pub fn reserve_rows(&mut self, rows: usize) {
        self.thetas.reserve(rows);
        self.positions.reserve(rows * self.joint_count);
    }

    /// Empties the trace, keeping its buffers.
    pub fn clear(&mut self, joint_count: usize) {
        self.joint_count = joint_count;
        self.thetas.clear();
        self.positions.clear();
    }

    /// Solves the plan at `theta` and appends the configuration; on failure the trace is unchanged.
    pub fn push(&mut self, plan: &Plan, theta: f64) -> Result<(), SweepError> {
        let n = self.joint_count;
        let start = self.positions.len();
        self.positions.resize(start + n, Point::ORIGIN);
        if let Err((step, cause)) = plan.solve(theta, &mut self.positions[start..]) {
            self.positions.truncate(start);
            return Err(SweepError { theta_deg: theta.to_degrees(), step, cause });
        }
        self.thetas.push(theta);
        Ok(())
    }

    /// Rearranges the trace in place into: row 0 of `inserted`, the rows `kept[0]`, row 1 of
    /// `inserted`, the rows `kept[1]`, ..., the last row of `inserted` (one more than there are
    /// ranges). `kept` ascends without overlap; `inserted` holds whole rows of this trace's joints,
    /// with their angles in `inserted_thetas`.
    ///
    /// Built in place rather than by copying the kept rows into a new trace: copying them costs 3% of
    /// the folding table's time, more than its instructions suggest (`perf record -e cpu-clock
    /// linkwright bench examples/k1_table.json --threads 1 --repeat 5`, the scene's `"mechanism"` set
    /// to `"chain"`).
    pub fn splice_rows(&mut self, kept: &[std::ops::Range<usize>], inserted_thetas: &[f64], inserted: &[Point]) {
        let n = self.joint_count;
        debug_assert_eq!(inserted_thetas.len(), kept.len() + 1);
        debug_assert_eq!(inserted.len(), inserted_thetas.len() * n);
        // Where each kept range starts in the result.
        let destination = |i: usize| i + 1 + kept[..i].iter().map(|r| r.len()).sum::<usize>();
        let len = inserted_thetas.len() + kept.iter().map(|r| r.len()).sum::<usize>();
        if len > self.len() {
            self.thetas.resize(len, 0.0);
            self.positions.resize(len * n, Point::ORIGIN);
        }
        let mut move_range = |i: usize| {
            let (from, to) = (kept[i].clone(), destination(i));
            self.thetas.copy_within(from.clone(), to);
            self.positions.copy_within(from.start * n..from.end * n, to * n);
        };
        // The ranges keep their order. One moving towards the front cannot overwrite a later range
        // (which starts after its own end) nor an earlier one moving back (which ends before its
        // destination), so those go first, front to back; then those moving back, back to front.
        let moves_back = |i: usize| destination(i) > kept[i].start;
        (0..kept.len()).filter(|&i| !moves_back(i)).for_each(&mut move_range);
        (0..kept.len()).rev().filter(|&i| moves_back(i)).for_each(&mut move_range);
        for (k, &theta) in inserted_thetas.iter().enumerate() {
            let to = if k == 0 { 0 } else { destination(k - 1) + kept[k - 1].len() };
            self.thetas[to] = theta;
            self.positions[to * n..(to + 1) * n].copy_from_slice(&inserted[k * n..(k + 1) * n]);
        }
        self.thetas.truncate(len);
        self.positions.truncate(len * n);
    }

    /// Number of rows (crank angles).
    pub fn len(&self) -> usize {
        self.thetas.len()
    }
    /// Whether the trace has no row.
    pub fn is_empty(&self) -> bool {
        self.thetas.is_empty()
    }
    /// The joints at sample `s`.
    pub fn row(&self, s: usize) -> &[Point] {
        &self.positions[s * self.joint_count..(s + 1) * self.joint_count]
    }
    /// The smallest transmission margin of `plan` (this trace's mechanism) along the whole trace,
    /// radians. Computed on demand: the engine judges most travels without it (see
    /// [`Plan::closed_form_travel`]).
    pub fn min_transmission(&self, plan: &Plan) -> f64 {
        self.min_transmission_sine(plan).asin()
    }
    /// The sine of [`Trace::min_transmission`] (cheaper, and ordered alike).
    pub fn min_transmission_sine(&self, plan: &Plan) -> f64 {
        self.least_transmission(plan).1
    }
    /// The row where the transmission margin of `plan` is smallest (the first of equals; 0 for an
    /// empty trace), with the sine of that margin.
    pub fn least_transmission(&self, plan: &Plan) -> (usize, f64) {
        (0..self.len())
            .map(|r| (r, plan.min_transmission_sine(self.row(r))))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, 1.0))
    }
}

/// How to recover each moving body's pose from the positions of two joints it carries.
#[derive(Clone, Debug)]
pub struct BodyFrames {
    /// Per body: the two joints that fix its frame, and the map from body coordinates to the frame
    /// those joints span (read at the first pose).
    frames: Vec<(usize, usize, Rigid)>,
}

impl BodyFrames {
    /// `first_poses[b]` is body b's `body_to_world` at the first pose.
    pub fn new(mechanism: &Mechanism, first_poses: &[Rigid]) -> BodyFrames {
        let topo = &mechanism.topology;
        let frames = (0..topo.body_count)
            .map(|b| {
                let part = topo.body_part(b);
                let (a, c) = (part.joints[0], part.joints[1]);
                let joints_frame = Rigid::from_frame(mechanism.joints[a], mechanism.joints[c] - mechanism.joints[a]);
                (a, c, first_poses[b].then(&joints_frame.inverse()))
            })
            .collect();
        BodyFrames { frames }
    }
    /// Body `b`'s `body_to_world` in the configuration `row`.
    pub fn pose(&self, b: usize, row: &[Point]) -> Rigid {
        let (a, c, body_to_frame) = &self.frames[b];
        body_to_frame.then(&Rigid::from_frame(row[*a], row[*c] - row[*a]))
    }
    /// [`BodyFrames::pose`] without the angle (see [`Isometry`]).
    pub fn isometry(&self, b: usize, row: &[Point]) -> Isometry {
        let (a, c, body_to_frame) = &self.frames[b];
        body_to_frame.isometry().then(&Isometry::from_frame(row[*a], row[*c] - row[*a]))
    }
    /// Number of moving bodies.
    pub fn body_count(&self) -> usize {
        self.frames.len()
    }
    /// Body `b`'s frame joints (the origin, then the joint its x axis points to) and its map from
    /// body coordinates to that frame: [`BodyFrames::pose`] is that map, then the frame the two
    /// joints span in a configuration.
    pub fn frame(&self, b: usize) -> (usize, usize, &Rigid) {
        let (a, c, body_to_frame) = &self.frames[b];
        (*a, *c, body_to_frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Splicing in place gives the trace that copying the inserted and kept rows one after the
        /// other into a new one gives, whichever way the kept ranges move and whether the result is
        /// longer or shorter.
        #[test]
        fn splicing_in_place_is_copying_in_order(
            joints in 1usize..5,
            rows in 0usize..40,
            cuts in proptest::collection::vec(0usize..40, 0..12),
        ) {
            let mut trace = Trace::new(joints);
            for r in 0..rows {
                trace.thetas.push(r as f64);
                trace.positions.extend((0..joints).map(|j| Point::new(r as f64, j as f64)));
            }
            // Ascending, disjoint ranges from sorted cut points, every other gap skipped.
            let mut cuts: Vec<usize> = cuts.into_iter().map(|c| c.min(rows)).collect();
            cuts.sort_unstable();
            let kept: Vec<std::ops::Range<usize>> = cuts.chunks_exact(2).map(|c| c[0]..c[1]).collect();
            let inserted_thetas: Vec<f64> = (0..=kept.len()).map(|k| -1.0 - k as f64).collect();
            let inserted: Vec<Point> =
                inserted_thetas.iter().flat_map(|&t| (0..joints).map(move |j| Point::new(t, -(j as f64)))).collect();

            let mut expected = Trace::new(joints);
            for (k, &theta) in inserted_thetas.iter().enumerate() {
                expected.thetas.push(theta);
                expected.positions.extend_from_slice(&inserted[k * joints..(k + 1) * joints]);
                if let Some(range) = kept.get(k) {
                    expected.thetas.extend_from_slice(&trace.thetas[range.clone()]);
                    expected.positions.extend_from_slice(&trace.positions[range.start * joints..range.end * joints]);
                }
            }
            trace.splice_rows(&kept, &inserted_thetas, &inserted);
            prop_assert_eq!(&trace.thetas, &expected.thetas);
            prop_assert_eq!(&trace.positions, &expected.positions);
        }
    }
}
