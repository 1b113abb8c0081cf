//! The structure of a linkage without its dimensions: named joints, the rigid parts that carry
//! them, the driver and the slider joint; one constructor per family's linkage.

use crate::scene::MechanismType;

/// What a rigid part is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PartKind {
    /// The ground (all fixed bodies).
    Fixed,
    /// Moving body with this 0-based index in the scene.
    Body(usize),
    /// A binary or ternary link.
    Link,
}

/// A rigid part and the joints (indices into the topology's joints) it carries.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// The part's name in design files: `ground`, `body1`, `crank`, `link1`, `rocker`, ...
    pub name: String,
    /// What the part is.
    pub kind: PartKind,
    /// The joints it carries, as indices into [`Topology::joint_names`].
    pub joints: Vec<usize>,
}

/// The structure of a mechanism without its dimensions.
#[derive(Clone, Debug, PartialEq)]
pub struct Topology {
    /// The family the topology belongs to.
    pub mechanism_type: MechanismType,
    /// Number of moving bodies K.
    pub body_count: usize,
    /// Every joint's name (`q0`, `p1`, ...); a joint's index here is its index everywhere else.
    pub joint_names: Vec<String>,
    /// The rigid parts: the ground, one per moving body, and the links.
    pub parts: Vec<Part>,
    /// The driver link turns about `driver_pivot` (a ground joint); its moving end is `driver_tip`.
    pub driver_pivot: usize,
    /// The driver link's moving end.
    pub driver_tip: usize,
    /// The joint that runs on the slider line, for the slider-crank.
    pub slider_joint: Option<usize>,
}

impl Topology {
    /// The multi-bar chain for `k ≥ 1` moving bodies (paper §4.2, fig. 3).
    ///
    /// # Examples
    ///
    /// One moving body: the four-bar, its ground pivots `q0`, `r0`, the crank `q0–p1`, the body as its
    /// coupler `p1–q1` and the rocker `r0–q1`. Every further body adds three joints.
    ///
    /// ```
    /// use linkwright_core::Topology;
    ///
    /// let four_bar = Topology::chain(1);
    /// assert_eq!(four_bar.joint_names, ["p1", "q0", "q1", "r0"]);
    /// let parts: Vec<&str> = four_bar.parts.iter().map(|p| p.name.as_str()).collect();
    /// assert_eq!(parts, ["ground", "body1", "crank", "rocker"]);
    /// let ground = four_bar.fixed_joints();
    /// assert_eq!(ground, [four_bar.joint("q0").unwrap(), four_bar.joint("r0").unwrap()]);
    /// assert_eq!((four_bar.driver_pivot, four_bar.driver_tip), (ground[0], four_bar.joint("p1").unwrap()));
    ///
    /// // The Watt-I six-bar.
    /// assert_eq!(Topology::chain(2).joint_count(), 7);
    /// ```
    pub fn chain(k: usize) -> Topology {
        assert!(k >= 1, "a chain needs at least one moving body");
        let mut names = Vec::new();
        let mut add = |n: String| {
            names.push(n);
            names.len() - 1
        };
        let p: Vec<usize> = (0..=k).map(|i| if i == 0 { usize::MAX } else { add(format!("p{i}")) }).collect();
        let q: Vec<usize> = (0..=k).map(|i| add(format!("q{i}"))).collect();
        let r: Vec<usize> = (0..k).map(|i| add(format!("r{i}"))).collect();
        let mut parts = vec![Part { name: "ground".into(), kind: PartKind::Fixed, joints: vec![q[0], r[0]] }];
        for b in 1..=k {
            let mut joints = vec![p[b], q[b]];
            if b < k {
                joints.push(r[b]);
            }
            parts.push(Part { name: format!("body{b}"), kind: PartKind::Body(b - 1), joints });
        }
        parts.push(Part { name: "crank".into(), kind: PartKind::Link, joints: vec![q[0], p[1]] });
        for t in 1..k {
            parts.push(Part { name: format!("link{t}"), kind: PartKind::Link, joints: vec![r[t - 1], q[t], p[t + 1]] });
        }
        parts.push(Part {
            name: if k == 1 { "rocker".into() } else { format!("link{k}") },
            kind: PartKind::Link,
            joints: vec![r[k - 1], q[k]],
        });
        Topology {
            mechanism_type: MechanismType::Chain,
            body_count: k,
            joint_names: names,
            parts,
            driver_pivot: q[0],
            driver_tip: p[1],
            slider_joint: None,
        }
    }

    /// The most poses through which this topology generally has exact solutions (paper §4.2,
    /// [`Family::max_exact_poses`](super::Family::max_exact_poses)). With more poses, a linkage can only approximate the motion.
    ///
    /// # Examples
    ///
    /// A four-bar's coupler can be guided exactly through five poses (Burmester's bound).
    ///
    /// ```
    /// use linkwright_core::Topology;
    ///
    /// assert_eq!(Topology::chain(1).max_exact_poses(), 5);
    /// assert_eq!(Topology::chain(2).max_exact_poses(), 3);
    /// assert_eq!(Topology::slider_crank().max_exact_poses(), 4);
    /// ```
    pub fn max_exact_poses(&self) -> usize {
        self.mechanism_type.family().max_exact_poses(self.body_count)
    }

    /// The RRRP slider-crank for one moving body (paper §4.3).
    pub fn slider_crank() -> Topology {
        Topology {
            mechanism_type: MechanismType::SliderCrank,
            body_count: 1,
            joint_names: vec!["q0".into(), "p1".into(), "q1".into()],
            parts: vec![
                Part { name: "ground".into(), kind: PartKind::Fixed, joints: vec![0] },
                Part { name: "body1".into(), kind: PartKind::Body(0), joints: vec![1, 2] },
                Part { name: "crank".into(), kind: PartKind::Link, joints: vec![0, 1] },
            ],
            driver_pivot: 0,
            driver_tip: 1,
            slider_joint: Some(2),
        }
    }

    /// The Watt-II six-bar for one moving body: the four-bar `q0 p1 q1 r0` of [`Topology::chain`]`(1)`
    /// carries the body, and its input link, now the ternary `link2` (`q0, p1, t1`), is driven by a
    /// second four-bar: the crank turns about the ground pivot `u0` and its tip `u1` pushes `t1`
    /// through `link1`. The crank need not be the body's own link, so it can sit where there is room
    /// for it and turn a motor's full circle while the body's four-bar only rocks.
    pub fn watt_two() -> Topology {
        let [q0, p1, q1, r0, u0, u1, t1] = [0, 1, 2, 3, 4, 5, 6];
        let links = [("crank", &[u0, u1][..]), ("link1", &[u1, t1]), ("link2", &[q0, p1, t1]), ("rocker", &[r0, q1])];
        Topology::one_body_six_bar(MechanismType::WattTwo, ["u1", "t1"], links, [u0, u1])
    }

    /// The Stephenson-III six-bar for one moving body: a four-bar `q0 a1 b1 u0` (crank `q0 a1`,
    /// rocker `u0 b1`) whose coupler, the ternary `link1` (`a1 b1 p1`), carries the body at `p1`; the
    /// body's other joint `q1` turns on the ground link `r0 q1`. The body follows the coupler point's
    /// path, turned by its own link.
    pub fn stephenson_three() -> Topology {
        let [q0, p1, q1, r0, u0, a1, b1] = [0, 1, 2, 3, 4, 5, 6];
        let links = [("crank", &[q0, a1][..]), ("link1", &[a1, b1, p1]), ("rocker", &[u0, b1]), ("link2", &[r0, q1])];
        Topology::one_body_six_bar(MechanismType::StephensonThree, ["a1", "b1"], links, [q0, a1])
    }

    /// A six-bar for one moving body: the ground carries `q0`, `r0`, `u0` and the body `p1`, `q1`
    /// (joints 0–4, in the order `q0 p1 q1 r0 u0`), two more joints (5 and 6) are called `extra`,
    /// and `links` join them; the crank turns about `driver[0]`, its tip is `driver[1]`.
    fn one_body_six_bar(
        mechanism_type: MechanismType,
        extra: [&str; 2],
        links: [(&str, &[usize]); 4],
        driver: [usize; 2],
    ) -> Topology {
        let names = ["q0", "p1", "q1", "r0", "u0"].into_iter().chain(extra);
        let part = |name: &str, kind, joints: &[usize]| Part { name: name.into(), kind, joints: joints.to_vec() };
        let mut parts = vec![part("ground", PartKind::Fixed, &[0, 3, 4]), part("body1", PartKind::Body(0), &[1, 2])];
        parts.extend(links.iter().map(|&(name, joints)| part(name, PartKind::Link, joints)));
        Topology {
            mechanism_type,
            body_count: 1,
            joint_names: names.map(str::to_string).collect(),
            parts,
            driver_pivot: driver[0],
            driver_tip: driver[1],
            slider_joint: None,
        }
    }

    /// Joints carried by links only (neither the ground nor a moving body carries them): where
    /// they are at a pose follows from the others' ([`Topology::chain`] and the slider-crank have
    /// none; the Watt-II six-bar has `u1` and `t1`).
    pub fn link_only_joints(&self) -> Vec<usize> {
        (0..self.joint_count())
            .filter(|&j| self.parts.iter().all(|p| p.kind == PartKind::Link || !p.joints.contains(&j)))
            .collect()
    }

    /// Number of joints.
    pub fn joint_count(&self) -> usize {
        self.joint_names.len()
    }
    /// The index of the joint called `name`.
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.joint_names.iter().position(|n| n == name)
    }
    /// The part of moving body `body`.
    pub fn body_part(&self, body: usize) -> &Part {
        self.parts.iter().find(|p| p.kind == PartKind::Body(body)).expect("every body has a part")
    }
    /// Joints carried by the ground.
    pub fn fixed_joints(&self) -> &[usize] {
        &self.parts.iter().find(|p| p.kind == PartKind::Fixed).expect("a ground part").joints
    }
    /// Joints carried by moving bodies, the set J_M of paper eq. 10–11, with the body that carries each.
    pub fn body_joints(&self) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for part in &self.parts {
            if let PartKind::Body(b) = part.kind {
                out.extend(part.joints.iter().map(|&j| (j, b)));
            }
        }
        out
    }
    /// Every pair of joints that a part holds at a fixed distance, each pair once: the links of eq. 13
    /// and the rigidity terms of eq. 3. Pairs within the ground or within a body are left out (they are
    /// not links).
    pub fn link_pairs(&self) -> Vec<(usize, usize)> {
        self.pairs_of(|p| p.kind == PartKind::Link)
    }
    /// Every pair of joints on one part (links, bodies, ground), which must stay apart to be built.
    pub fn part_pairs(&self) -> Vec<(usize, usize)> {
        self.pairs_of(|_| true)
    }
    fn pairs_of(&self, keep: impl Fn(&Part) -> bool) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for part in self.parts.iter().filter(|p| keep(p)) {
            for (i, &a) in part.joints.iter().enumerate() {
                for &b in &part.joints[i + 1..] {
                    out.push((a, b));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chain_has_3k_plus_1_joints_and_one_degree_of_freedom() {
        for k in 1..=8 {
            let t = Topology::chain(k);
            assert_eq!(t.joint_count(), 3 * k + 1);
            // Grübler: M = 3(n − 1) − 2 j, counting a joint shared by m parts as m − 1 joints.
            let n = t.parts.len() as i64;
            let mut j = 0i64;
            for joint in 0..t.joint_count() {
                let m = t.parts.iter().filter(|p| p.joints.contains(&joint)).count() as i64;
                j += m - 1;
            }
            assert_eq!(3 * (n - 1) - 2 * j, 1, "K = {k}");
        }
    }

    /// Grübler's count for the Watt-II six-bar, its two ternary parts (the ground and `link2`)
    /// adjacent through `q0`, and the two joints only links carry.
    #[test]
    fn watt_two_has_one_degree_of_freedom_and_adjacent_ternary_parts() {
        let t = Topology::watt_two();
        let n = t.parts.len() as i64;
        let j: i64 = (0..t.joint_count())
            .map(|joint| t.parts.iter().filter(|p| p.joints.contains(&joint)).count() as i64 - 1)
            .sum();
        assert_eq!(3 * (n - 1) - 2 * j, 1);
        let ternary: Vec<&Part> = t.parts.iter().filter(|p| p.joints.len() == 3).collect();
        assert_eq!(ternary.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(), ["ground", "link2"]);
        assert_eq!(t.link_only_joints(), [t.joint("u1").unwrap(), t.joint("t1").unwrap()]);
        assert!(
            Topology::chain(3).link_only_joints().is_empty() && Topology::slider_crank().link_only_joints().is_empty()
        );
    }

    #[test]
    fn watt_six_bar_has_adjacent_ternary_links() {
        let t = Topology::chain(2);
        let ternary: Vec<&Part> = t.parts.iter().filter(|p| p.joints.len() == 3).collect();
        assert_eq!(ternary.len(), 2);
        assert!(ternary[0].joints.iter().any(|j| ternary[1].joints.contains(j)));
    }
}
