//! Barnes–Hut: gravity from many sources through an octree (docs/design.md,
//! "Gravity"). The sources, already sorted by id, are split into octants
//! (a stable sort, so each leaf keeps id order) until at most
//! [`LEAF_SIZE`] remain; each node keeps its total `G·m` and center of
//! mass and its quadrupole moment. A body sums a node as a point mass plus
//! its quadrupole term when the node's edge `s` and
//! the distance `d` to its center of mass satisfy `s < θ·d` and the body is
//! outside the node's cube; otherwise it opens the node, down to the leaves,
//! whose sources it sums one by one. Nodes are stored depth first, each
//! with the index past its subtree, so the walk needs no stack and always
//! adds in the same order: the result does not depend on how the bodies are
//! split among threads. With `θ = 0` no node is summed as a whole and the
//! tree gives the direct sum, in another order.

use bevy::math::DVec3;
use bevy::prelude::*;

use super::gravity::{GravitySource, add_pulls};
use crate::components::BodyId;

/// Most sources in a leaf.
pub const LEAF_SIZE: usize = 8;
/// Deepest level: coincident sources end up in one leaf here.
const MAX_DEPTH: u32 = 40;

/// One node of the tree.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    /// Center of mass (weighted by `G·m`; the cube's center if it is 0).
    com: DVec3,
    /// Total `G·m`.
    gm: f64,
    /// Quadrupole `Σ G·m·(3·x·xᵀ − |x|²·I)` about the center of mass, as
    /// xx, yy, zz, xy, xz, yz.
    quad: [f64; 6],
    /// The node's cube: center and half its edge.
    center: DVec3,
    half: f64,
    /// Index of the first node after this node's subtree.
    skip: u32,
    /// Leaf: its sources, `first..first + count`; `count == 0` inside.
    first: u32,
    count: u32,
}

/// An octree over gravity sources.
#[derive(Clone, Debug, Default)]
pub struct Octree {
    nodes: Vec<Node>,
    /// The sources in leaf order.
    sources: Vec<GravitySource>,
}

/// The pull of a node's point mass and quadrupole on a body at `r` from
/// its center of mass (`r2 = |r|² + ε²`):
/// `−gm·r/r³ + Q·r/r⁵ − (5/2)·(rᵀQr)·r/r⁷`.
#[inline]
fn far_field(node: &Node, r: DVec3, r2: f64) -> DVec3 {
    let [xx, yy, zz, xy, xz, yz] = node.quad;
    let qr = DVec3::new(
        xx * r.x + xy * r.y + xz * r.z,
        xy * r.x + yy * r.y + yz * r.z,
        xz * r.x + yz * r.y + zz * r.z,
    );
    let inv_r2 = 1.0 / r2;
    let inv_r3 = inv_r2 * inv_r2.sqrt();
    let inv_r5 = inv_r3 * inv_r2;
    -r * (node.gm * inv_r3) + qr * inv_r5 - r * (2.5 * r.dot(qr) * inv_r5 * inv_r2)
}

fn octant(p: DVec3, center: DVec3) -> usize {
    usize::from(p.x >= center.x) | usize::from(p.y >= center.y) << 1 | usize::from(p.z >= center.z) << 2
}

impl Octree {
    /// Kernel: the tree over `sources` (in the order given, which fixes the
    /// order of every sum), reusing this tree's buffers.
    pub fn rebuild(&mut self, sources: &[GravitySource]) {
        self.nodes.clear();
        self.sources.clear();
        self.sources.extend_from_slice(sources);
        if sources.is_empty() {
            return;
        }
        let (lo, hi) = sources.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), s| (lo.min(s.position), hi.max(s.position)),
        );
        let center = (lo + hi) * 0.5;
        let half = ((hi - lo).max_element() * 0.5).max(f64::MIN_POSITIVE);
        let mut sources = std::mem::take(&mut self.sources);
        self.build(&mut sources, 0, center, half, 0);
        self.sources = sources;
    }

    /// Builds the node of `items` (the sources `first..` in leaf order)
    /// and its subtree, depth first.
    fn build(&mut self, items: &mut [GravitySource], first: usize, center: DVec3, half: f64, depth: u32) {
        let index = self.nodes.len();
        let gm: f64 = items.iter().map(|s| s.gm).sum();
        let com = if gm > 0.0 {
            items.iter().map(|s| s.position * s.gm).sum::<DVec3>() / gm
        } else {
            center
        };
        let mut quad = [0.0; 6];
        for s in items.iter() {
            let x = s.position - com;
            let r2 = x.length_squared();
            let terms = [
                3.0 * x.x * x.x - r2,
                3.0 * x.y * x.y - r2,
                3.0 * x.z * x.z - r2,
                3.0 * x.x * x.y,
                3.0 * x.x * x.z,
                3.0 * x.y * x.z,
            ];
            for (q, t) in quad.iter_mut().zip(terms) {
                *q += s.gm * t;
            }
        }
        let leaf = items.len() <= LEAF_SIZE || depth >= MAX_DEPTH;
        self.nodes.push(Node {
            com,
            gm,
            quad,
            center,
            half,
            skip: 0,
            first: first as u32,
            count: if leaf { items.len() as u32 } else { 0 },
        });
        if !leaf {
            // Stable: within an octant the sources keep their order.
            items.sort_by_key(|s| octant(s.position, center));
            let mut start = 0;
            for k in 0..8 {
                let end = start + items[start..].partition_point(|s| octant(s.position, center) == k);
                if end > start {
                    let sign = |bit: usize| if k & bit != 0 { 0.5 } else { -0.5 };
                    let child = center + DVec3::new(sign(1), sign(2), sign(4)) * half;
                    self.build(&mut items[start..end], first + start, child, half * 0.5, depth + 1);
                }
                start = end;
            }
        }
        self.nodes[index].skip = self.nodes.len() as u32;
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True when there are no sources.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Kernel: the acceleration of the body `id` at `position`, with the
    /// opening angle `theta` and softening `ε²` = `softening2`.
    pub fn acceleration_at(&self, id: BodyId, position: Vec3, theta: f64, softening2: f64) -> Vec3 {
        let p = position.as_dvec3();
        let theta2 = theta * theta;
        let mut a = DVec3::ZERO;
        let mut i = 0;
        while i < self.nodes.len() {
            let node = &self.nodes[i];
            if node.count > 0 {
                let leaf = &self.sources[node.first as usize..(node.first + node.count) as usize];
                add_pulls(&mut a, id, p, leaf, softening2);
                i = node.skip as usize;
                continue;
            }
            let d = node.com - p;
            let r2 = d.length_squared();
            let edge = 2.0 * node.half;
            let inside = (p - node.center).abs().max_element() <= node.half;
            if !inside && edge * edge < theta2 * r2 {
                a += far_field(node, -d, r2 + softening2);
                i = node.skip as usize;
            } else {
                i += 1;
            }
        }
        a.as_vec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use crate::systems::acceleration_at;

    /// A Plummer-like cluster: dense core, sparse halo, unequal masses.
    fn cluster(count: usize, seed: u64) -> Vec<GravitySource> {
        let mut rng = Rng::new(seed);
        (0..count)
            .map(|i| {
                let r = 100.0 / (rng.range(0.01, 1.0).powf(-2.0 / 3.0) - 1.0).sqrt();
                let z = rng.symmetric(1.0);
                let phi = rng.range(0.0, std::f64::consts::TAU);
                let s = (1.0 - z * z).sqrt();
                GravitySource {
                    id: BodyId(i as u64),
                    position: (DVec3::new(s * phi.cos(), s * phi.sin(), z) * r.min(5000.0))
                        .as_vec3()
                        .as_dvec3(),
                    gm: 6.674 * rng.range(0.5, 2.0),
                }
            })
            .collect()
    }

    fn relative_errors(sources: &[GravitySource], theta: f64) -> Vec<f64> {
        let mut tree = Octree::default();
        tree.rebuild(sources);
        let mut errors: Vec<f64> = sources
            .iter()
            .map(|s| {
                let p = s.position.as_vec3();
                let direct = acceleration_at(s.id, p, sources, 1.0).as_dvec3();
                let approx = tree.acceleration_at(s.id, p, theta, 1.0).as_dvec3();
                (approx - direct).length() / direct.length()
            })
            .collect();
        errors.sort_unstable_by(f64::total_cmp);
        errors
    }

    #[test]
    fn the_tree_matches_the_direct_sum_within_the_goal_at_theta_one_half() {
        let errors = relative_errors(&cluster(3000, 1), 0.5);
        let (median, p99) = (errors[errors.len() / 2], errors[errors.len() * 99 / 100]);
        eprintln!("θ = 0.5: median relative error {median:.2e}, 99th percentile {p99:.2e}");
        assert!(median <= 1e-3, "median relative error {median}");
        assert!(p99 <= 1e-2, "99th percentile {p99}");
    }

    #[test]
    fn theta_zero_is_the_direct_sum() {
        let errors = relative_errors(&cluster(1000, 2), 0.0);
        let worst = errors[errors.len() - 1];
        assert!(worst <= 1e-6, "worst relative error {worst}");
    }

    #[test]
    fn coincident_sources_and_no_sources_are_fine() {
        let mut tree = Octree::default();
        tree.rebuild(&[]);
        assert_eq!(tree.acceleration_at(BodyId(0), Vec3::ONE, 0.5, 0.0), Vec3::ZERO);
        let same: Vec<GravitySource> = (0..50)
            .map(|i| GravitySource {
                id: BodyId(i),
                position: DVec3::splat(3.0),
                gm: 1.0,
            })
            .collect();
        tree.rebuild(&same);
        let a = tree.acceleration_at(BodyId(99), Vec3::new(5.0, 3.0, 3.0), 0.5, 0.0);
        assert!((a.x + 50.0 / 4.0).abs() < 1e-4, "{a}");
    }
}
