//! Barnes–Hut: gravity from many sources through an octree (docs/design.md,
//! "Gravity"). The sources, already sorted by id, are split into octants
//! (a stable counting sort, so each leaf keeps id order) until at most
//! [`LEAF_SIZE`] remain; each node keeps its total `G·m`, center of mass
//! and quadrupole moment, and the cube around its sources' bounding box
//! (edge `s`). A body sums a node as a point mass plus its quadrupole term
//! when it lies outside that cube and farther than `s/θ + δ` from the
//! center of mass, `δ` the center of mass's offset from the cube's center
//! (the classical `s < θ·d` on the space the sources take up, made safe
//! for a lopsided node); otherwise it opens the node, down to the leaves,
//! whose sources it sums one by one. Nodes are stored depth first, each
//! with the index past its subtree, so the walk needs no stack and always
//! adds in the same order: the result does not depend on how the bodies are
//! split among threads. With `θ = 0` no node is summed as a whole and the
//! tree gives the direct sum, in another order.
//!
//! Longer than 600 lines: `impl Octree` is kept whole in this file (the
//! build, the moments, the node test the walks share), the walks being
//! functions of `&Octree` in `walk.rs` (ARCHITECTURE.md, "Gravity's
//! ladder").

use bevy::math::DVec3;
use bevy::prelude::*;

use super::columns::LeafSources;
use super::kernel::far_term;
use super::source::{GravitySource, add_pulls};
use crate::components::BodyId;
use crate::execution::StageExecution;

/// Most sources in a leaf.
pub const LEAF_SIZE: usize = 8;
/// Deepest level: coincident sources end up in one leaf here.
const MAX_DEPTH: u32 = 40;

/// One node of the tree as the walks read it, in one cache line; what it
/// pulls with when taken whole is in [`Moments`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
pub(super) struct Node {
    /// Center of mass (weighted by `G·m`; the box's center if it is 0).
    pub(super) com: DVec3,
    /// How far the center of mass is from the cube's center.
    pub(super) offset: f64,
    /// The cube around its sources' bounding box: center and half its
    /// edge `s` (the box's longest), in `f32`, widened so that it holds
    /// the exact cube.
    pub(super) center: Vec3,
    pub(super) half: f32,
    /// Index of the first node after this node's subtree.
    pub(super) skip: u32,
    /// The sources of its subtree, `first..first + len` in leaf order.
    pub(super) first: u32,
    pub(super) len: u32,
    /// Whether it is a leaf (its sources are summed one by one).
    pub(super) leaf: bool,
}

const _: () = assert!(size_of::<Node>() == 64, "a node is one cache line");

/// What a node pulls with when taken whole, in `f32`, as the far sums
/// take it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Moments {
    /// Total `G·m`.
    pub(super) gm: f32,
    /// Quadrupole `Σ G·m·(3·x·xᵀ − |x|²·I)` about the center of mass per
    /// unit of the total `G·m` (0 if that is 0), as xx, yy, zz, xy, xz, yz.
    pub(super) quad: [f32; 6],
}

impl Node {
    /// Its sources' range in leaf order.
    pub(super) fn range(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.len) as usize
    }

    /// The least distance from the center of mass at which the node may
    /// pull as a whole: `s/θ + δ`, `s` its edge and `δ` its offset
    /// (`inverse_theta` = `1/θ`); infinite for `θ = 0` (the widened edge is
    /// never 0).
    pub(super) fn reach(&self, inverse_theta: f64) -> f64 {
        2.0 * f64::from(self.half) * inverse_theta + self.offset
    }

    /// Its cube: center and half the edge in each axis.
    pub(super) fn cube(&self) -> (DVec3, DVec3) {
        (self.center.as_dvec3(), DVec3::splat(f64::from(self.half)))
    }

    /// The point of its cube nearest to `p`.
    pub(super) fn clamp(&self, p: DVec3) -> DVec3 {
        let (center, half) = self.cube();
        p.clamp(center - half, center + half)
    }

    /// Whether every box within `lo..=hi` opens the node (none may take it
    /// whole, [`accepts`](Self::accepts)): the box lies in the node's cube,
    /// or no point of it is farther than [`reach`](Self::reach) from the
    /// center of mass.
    pub(super) fn opened_by_all(&self, lo: DVec3, hi: DVec3, inverse_theta: f64) -> bool {
        let (center, half) = self.cube();
        let inside = lo.cmpge(center - half).all() && hi.cmple(center + half).all();
        let farthest = (self.com - lo).abs().max((self.com - hi).abs());
        let reach = self.reach(inverse_theta);
        inside || farthest.length_squared() <= reach * reach
    }

    /// Whether the node may pull every point of the box `lo..=hi` as a
    /// whole: the box lies outside the node's cube, and farther than
    /// [`reach`](Self::reach) from the center of mass. Every point in the
    /// box then meets the single-point test too.
    pub(super) fn accepts(&self, lo: DVec3, hi: DVec3, inverse_theta: f64) -> bool {
        let (center, half) = self.cube();
        let apart = (lo - center).cmpgt(half).any() || (center - hi).cmpgt(half).any();
        let nearest = self.com.clamp(lo, hi);
        let reach = self.reach(inverse_theta);
        apart && reach * reach < (self.com - nearest).length_squared()
    }
}

/// Most sources in a group: the bodies that go down one list of
/// interactions together (`walk.rs`).
pub const GROUP_SIZE: u32 = 64;

/// Most sources in a region: the groups whose walks share one walk of the
/// tree for the region as a whole (`walk.rs`).
pub const REGION_SIZE: u32 = 256;

/// What a walk ([`Octree::walk`]) comes to.
pub(super) enum Step<'a> {
    /// A leaf it opens: its sources are summed one by one.
    Leaf(&'a Node),
    /// A node it takes whole, by its index.
    Whole(u32),
}

/// A run of sibling nodes: the nodes `nodes` (from the first to the end
/// of the last one's subtree) and their sources in leaf order.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Run {
    pub(super) nodes: std::ops::Range<u32>,
    pub(super) sources: std::ops::Range<u32>,
}

/// An octree over gravity sources.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Octree {
    tree: Nodes,
    /// The sources in leaf order.
    sources: Vec<GravitySource>,
    /// The same as columns.
    columns: LeafSources,
    /// For each source in leaf order, its index in the order given.
    given: Vec<u32>,
    /// The regions, runs of sibling nodes of at most [`REGION_SIZE`]
    /// sources, in leaf order (see [`collect`](Self::collect)).
    regions: Vec<Run>,
    /// The groups, runs of sibling nodes of at most [`GROUP_SIZE`] sources
    /// within the regions, in leaf order; together they hold every source
    /// once.
    groups: Vec<std::ops::Range<u32>>,
    /// For each group, the index of its region.
    group_regions: Vec<u32>,
    /// Buffers the build sorts in, kept so that a rebuild allocates nothing
    /// in proportion to the sources once their count stops growing.
    buffers: BuildBuffers,
}

/// What [`Octree::rebuild`] sorts the sources in: the items in the order
/// given and then in leaf order, room to sort a node's items into octants,
/// and each root octant's nodes. Scratch space, not part of the tree's
/// value: trees compare equal whatever their buffers hold.
#[derive(Clone, Debug, Default)]
struct BuildBuffers {
    items: Vec<Item>,
    scratch: Vec<Item>,
    pieces: Vec<Nodes>,
}

impl PartialEq for BuildBuffers {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

fn octant(p: DVec3, center: DVec3) -> usize {
    usize::from(p.x >= center.x) | usize::from(p.y >= center.y) << 1 | usize::from(p.z >= center.z) << 2
}

/// The least and greatest corner of the sources' positions.
pub(super) fn bounds<'a>(sources: impl IntoIterator<Item = &'a GravitySource>) -> (DVec3, DVec3) {
    sources.into_iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), s| (lo.min(s.position), hi.max(s.position)),
    )
}

/// A source with its index in the order the tree was built from.
type Item = (GravitySource, u32);

/// The subtree of one of the root's octants, built on its own: its items
/// (sorted into leaf order in place), as much room to sort them in, the
/// nodes it builds (indices from 0), where its items start in leaf order,
/// the octant's center and half edge, and, once built, what it adds up to.
struct Piece<'a> {
    items: &'a mut [Item],
    scratch: &'a mut [Item],
    nodes: &'a mut Nodes,
    first: usize,
    center: DVec3,
    half: f64,
    summary: Summary,
}

impl Piece<'_> {
    /// Kernel: builds the piece's subtree (the root's child, at depth 1).
    fn build(&mut self) {
        self.summary = build(
            self.nodes,
            self.items,
            self.scratch,
            self.first,
            self.center,
            self.half,
            1,
        );
    }
}

/// What a subtree adds up to: its sources' bounding box, total `G·m`,
/// center of mass and quadrupole `Σ G·m·(3·x·xᵀ − |x|²·I)` about it.
#[derive(Clone, Copy, Debug, Default)]
struct Summary {
    lo: DVec3,
    hi: DVec3,
    gm: f64,
    com: DVec3,
    quad: [f64; 6],
}

/// `Σ gm·(3·d·dᵀ − |d|²·I)` terms of a mass `gm` at `d`, added to `quad`.
fn add_quadrupole(quad: &mut [f64; 6], gm: f64, d: DVec3) {
    let r2 = d.length_squared();
    let terms = [
        3.0 * d.x * d.x - r2,
        3.0 * d.y * d.y - r2,
        3.0 * d.z * d.z - r2,
        3.0 * d.x * d.y,
        3.0 * d.x * d.z,
        3.0 * d.y * d.z,
    ];
    for (q, t) in quad.iter_mut().zip(terms) {
        *q += gm * t;
    }
}

impl Summary {
    /// Of a leaf's sources, one by one.
    fn of(items: &[Item]) -> Self {
        let (lo, hi) = bounds(items.iter().map(|(s, _)| s));
        let gm: f64 = items.iter().map(|(s, _)| s.gm).sum();
        let com = if gm > 0.0 {
            items.iter().map(|(s, _)| s.position * s.gm).sum::<DVec3>() / gm
        } else {
            (lo + hi) * 0.5
        };
        let mut quad = [0.0; 6];
        for (s, _) in items {
            add_quadrupole(&mut quad, s.gm, s.position - com);
        }
        Self { lo, hi, gm, com, quad }
    }

    /// Of a node's children, in order: each child's quadrupole moved to the
    /// node's center of mass (the parallel-axis theorem), so building is
    /// linear in the sources.
    fn combine(parts: &[Summary]) -> Self {
        let lo = parts.iter().fold(DVec3::splat(f64::INFINITY), |lo, p| lo.min(p.lo));
        let hi = parts.iter().fold(DVec3::splat(f64::NEG_INFINITY), |hi, p| hi.max(p.hi));
        let gm: f64 = parts.iter().map(|p| p.gm).sum();
        let com = if gm > 0.0 {
            parts.iter().map(|p| p.com * p.gm).sum::<DVec3>() / gm
        } else {
            (lo + hi) * 0.5
        };
        let mut quad = [0.0; 6];
        for p in parts {
            for (q, child) in quad.iter_mut().zip(p.quad) {
                *q += child;
            }
            add_quadrupole(&mut quad, p.gm, p.com - com);
        }
        Self { lo, hi, gm, com, quad }
    }
}

/// The node of `len` sources `first..` in leaf order at `depth`, as
/// `summary` adds them up; `skip` is set once its subtree is built.
fn node_of(summary: &Summary, first: usize, len: usize, depth: u32) -> (Node, Moments) {
    let Summary {
        lo,
        hi,
        gm,
        com,
        mut quad,
    } = *summary;
    let (center, half) = ((lo + hi) * 0.5, (hi - lo).max_element() * 0.5);
    // Per unit of G·m, as the far sums take it; components below f32's
    // precision of the largest (or below its normal range) are rounding
    // noise, and as f32 subnormals they would slow the far sums many times
    // over: they become 0.
    let per_gm = if gm > 0.0 { gm.recip() } else { 0.0 };
    quad.iter_mut().for_each(|q| *q *= per_gm);
    let largest = quad.iter().fold(0.0, |m: f64, q| m.max(q.abs()));
    let floor = (largest * f64::from(f32::EPSILON)).max(f64::from(f32::MIN_POSITIVE));
    quad.iter_mut().filter(|q| q.abs() < floor).for_each(|q| *q = 0.0);
    let near = center.as_vec3();
    let widened = half + (center - near.as_dvec3()).abs().max_element();
    let node = Node {
        com,
        offset: com.distance(center),
        center: near,
        half: (widened as f32).next_up(),
        skip: 0,
        first: first as u32,
        len: len as u32,
        leaf: is_leaf(len, depth),
    };
    // A quadrupole beyond f32's range (a node wider than about 10¹⁹) is
    // held within it, so that the far sums stay finite wherever r² is.
    let most = f64::from(f32::MAX / 16.0);
    (
        node,
        Moments {
            gm: gm as f32,
            quad: quad.map(|q| q.clamp(-most, most) as f32),
        },
    )
}

/// Whether a node of `len` sources at `depth` is a leaf.
fn is_leaf(len: usize, depth: u32) -> bool {
    len <= LEAF_SIZE || depth >= MAX_DEPTH
}

/// Each octant of a node: its items' range (empty if it has none) and
/// its center.
type Octants = [(std::ops::Range<usize>, DVec3); 8];

/// Sorts the items of a node centered at `center` into its octants
/// (stably: within an octant they keep their order), using `scratch` (as
/// long as `items`), and returns each octant's range in `items` and its
/// center.
fn octants(items: &mut [Item], scratch: &mut [Item], center: DVec3, half: f64) -> Octants {
    scratch.copy_from_slice(items);
    sort_into_octants(scratch.iter().copied(), items, center, half)
}

/// Places the items `given` (as many as `into` holds) into `into`, sorted
/// into the octants of a node centered at `center` as [`octants`] does.
fn sort_into_octants(
    given: impl Iterator<Item = Item> + Clone,
    into: &mut [Item],
    center: DVec3,
    half: f64,
) -> Octants {
    // A counting sort: count each octant, then place every item after the
    // ones before it, in the order given.
    let mut counts = [0; 8];
    for (s, _) in given.clone() {
        counts[octant(s.position, center)] += 1;
    }
    let mut next = [0; 8];
    for k in 1..8 {
        next[k] = next[k - 1] + counts[k - 1];
    }
    let starts = next;
    for item in given {
        let k = octant(item.0.position, center);
        into[next[k]] = item;
        next[k] += 1;
    }
    std::array::from_fn(|k| {
        let sign = |bit: usize| if k & bit != 0 { 0.5 } else { -0.5 };
        let range = starts[k]..starts[k] + counts[k];
        (range, center + DVec3::new(sign(1), sign(2), sign(4)) * half)
    })
}

/// Nodes and their moments, depth first.
#[derive(Clone, Debug, Default, PartialEq)]
struct Nodes {
    nodes: Vec<Node>,
    moments: Vec<Moments>,
}

impl Nodes {
    fn clear(&mut self) {
        self.nodes.clear();
        self.moments.clear();
    }

    fn push(&mut self, (node, moments): (Node, Moments)) {
        self.nodes.push(node);
        self.moments.push(moments);
    }

    /// Appends `other`'s nodes, their indices shifted past these.
    fn append(&mut self, other: &Nodes) {
        let offset = self.nodes.len() as u32;
        self.nodes.extend(other.nodes.iter().map(|n| Node {
            skip: n.skip + offset,
            ..*n
        }));
        self.moments.extend_from_slice(&other.moments);
    }
}

/// Kernel: builds the subtree of `items` (the sources `first..` in leaf
/// order) depth first into `nodes`, whose indices start at its length,
/// sorting `items` into leaf order (in `scratch`, as long) and returns what
/// they add up to.
fn build(
    nodes: &mut Nodes,
    items: &mut [Item],
    scratch: &mut [Item],
    first: usize,
    center: DVec3,
    half: f64,
    depth: u32,
) -> Summary {
    let index = nodes.nodes.len();
    nodes.push((Node::default(), Moments::default()));
    let summary = if is_leaf(items.len(), depth) {
        Summary::of(items)
    } else {
        let mut parts = [Summary::default(); 8];
        let mut count = 0;
        for (range, child) in octants(items, scratch, center, half) {
            if !range.is_empty() {
                let (mine, room) = (&mut items[range.clone()], &mut scratch[range.clone()]);
                parts[count] = build(nodes, mine, room, first + range.start, child, half * 0.5, depth + 1);
                count += 1;
            }
        }
        Summary::combine(&parts[..count])
    };
    let (node, moments) = node_of(&summary, first, items.len(), depth);
    nodes.nodes[index] = Node {
        skip: nodes.nodes.len() as u32,
        ..node
    };
    nodes.moments[index] = moments;
    summary
}

impl Octree {
    /// Kernel: the tree over `sources` (in the order given, which fixes the
    /// order of every sum), reusing this tree's buffers; built on this
    /// thread.
    pub fn rebuild(&mut self, sources: &[GravitySource]) {
        self.rebuild_with(sources, |pieces| pieces.iter_mut().for_each(Piece::build));
    }

    /// [`rebuild`](Self::rebuild) with the root's octants built in
    /// parallel as `stage` splits them: the same tree, bit for bit (each
    /// octant's subtree is built the same way wherever it is built, and
    /// the pieces are joined in octant order).
    pub fn rebuild_split(&mut self, sources: &[GravitySource], stage: StageExecution<'_>) {
        self.rebuild_with(sources, |pieces| {
            stage.for_chunks(pieces, |chunk: &mut [Piece]| chunk.iter_mut().for_each(Piece::build));
        });
    }

    /// The tree over `sources`: the root here, the subtrees of its octants
    /// by `build_pieces`.
    fn rebuild_with(&mut self, sources: &[GravitySource], build_pieces: impl FnOnce(&mut [Piece])) {
        self.tree.clear();
        self.regions.clear();
        self.groups.clear();
        self.group_regions.clear();
        self.sources.clear();
        self.columns.fill(&[]);
        self.given.clear();
        if sources.is_empty() {
            return;
        }
        let (lo, hi) = bounds(sources);
        let center = (lo + hi) * 0.5;
        let half = ((hi - lo).max_element() * 0.5).max(f64::MIN_POSITIVE);
        let BuildBuffers {
            items,
            scratch,
            pieces: piece_nodes,
        } = &mut self.buffers;
        // Sized without copying (only growing writes): the sort fills them.
        let (count, blank) = (sources.len(), (sources[0], 0));
        items.resize(count, blank);
        scratch.resize(count, blank);
        let given = sources.iter().copied().zip(0..);
        self.tree.push((Node::default(), Moments::default()));
        let summary = if is_leaf(count, 0) {
            items.iter_mut().zip(given).for_each(|(item, source)| *item = source);
            Summary::of(items)
        } else {
            let children = sort_into_octants(given, items, center, half);
            piece_nodes.resize_with(children.len(), Nodes::default);
            let (mut items, mut scratch) = (&mut items[..], &mut scratch[..]);
            let mut pieces = Vec::with_capacity(children.len());
            for ((range, child), nodes) in children.into_iter().zip(piece_nodes.iter_mut()) {
                let (mine, rest) = std::mem::take(&mut items).split_at_mut(range.len());
                let (room, spare) = std::mem::take(&mut scratch).split_at_mut(range.len());
                (items, scratch) = (rest, spare);
                nodes.clear();
                if !range.is_empty() {
                    pieces.push(Piece {
                        items: mine,
                        scratch: room,
                        nodes,
                        first: range.start,
                        center: child,
                        half: half * 0.5,
                        summary: Summary::default(),
                    });
                }
            }
            build_pieces(&mut pieces);
            let mut parts = [Summary::default(); 8];
            for (part, piece) in parts.iter_mut().zip(&pieces) {
                self.tree.append(piece.nodes);
                *part = piece.summary;
            }
            Summary::combine(&parts[..pieces.len()])
        };
        self.sources.extend(self.buffers.items.iter().map(|(s, _)| *s));
        self.given.extend(self.buffers.items.iter().map(|(_, k)| *k));
        let (root, moments) = node_of(&summary, 0, sources.len(), 0);
        self.tree.nodes[0] = Node {
            skip: self.tree.nodes.len() as u32,
            ..root
        };
        self.tree.moments[0] = moments;
        self.columns.fill(&self.sources);
        let mut regions = std::mem::take(&mut self.regions);
        self.collect(0, REGION_SIZE, &mut regions);
        let mut groups = Vec::new();
        for (index, region) in regions.iter().enumerate() {
            self.collect_siblings(region.nodes.clone(), GROUP_SIZE, &mut groups);
            self.groups.extend(groups.iter().map(|g| g.sources.clone()));
            self.group_regions.extend(groups.drain(..).map(|_| index as u32));
        }
        self.regions = regions;
    }

    /// The runs of at most `size` sources that the subtree of the node
    /// `index` falls into, appended to `runs` in leaf order: the node itself
    /// if it holds at most `size` or is a leaf (a leaf holds more only at
    /// the deepest level, sources on one point; it is a run all the same,
    /// so that every source is in exactly one run); else its children's
    /// ([`collect_siblings`](Self::collect_siblings)).
    fn collect(&self, index: usize, size: u32, runs: &mut Vec<Run>) {
        let node = &self.tree.nodes[index];
        if node.len <= size || node.leaf {
            runs.push(Run {
                nodes: index as u32..node.skip,
                sources: node.first..node.first + node.len,
            });
        } else {
            self.collect_siblings(index as u32 + 1..node.skip, size, runs);
        }
    }

    /// The runs of the sibling nodes that fill `nodes` (the first of them
    /// and the end of the last one's subtree): small siblings next to each
    /// other taken together up to `size` sources (siblings, so close to
    /// each other), and the runs of the big ones.
    fn collect_siblings(&self, nodes: std::ops::Range<u32>, size: u32, runs: &mut Vec<Run>) {
        let mut run: Option<Run> = None;
        let mut child = nodes.start as usize;
        while child < nodes.end as usize {
            let c = &self.tree.nodes[child];
            if c.len <= size {
                run = match run {
                    Some(r) if r.sources.len() + c.len as usize <= size as usize => Some(Run {
                        nodes: r.nodes.start..c.skip,
                        sources: r.sources.start..c.first + c.len,
                    }),
                    r => {
                        runs.extend(r);
                        Some(Run {
                            nodes: child as u32..c.skip,
                            sources: c.first..c.first + c.len,
                        })
                    }
                };
            } else {
                runs.extend(run.take());
                self.collect(child, size, runs);
            }
            child = c.skip as usize;
        }
        runs.extend(run);
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.tree.nodes.len()
    }

    /// True when there are no sources.
    pub fn is_empty(&self) -> bool {
        self.tree.nodes.is_empty()
    }

    /// Kernel: the acceleration of the body `id` at `position`, with the
    /// opening angle `theta` and softening `ε²` = `softening2`.
    pub fn acceleration_at(&self, id: BodyId, position: Vec3, theta: f64, softening2: f64) -> Vec3 {
        let p = position.as_dvec3();
        let mut a = DVec3::ZERO;
        if self.is_empty() {
            return Vec3::ZERO;
        }
        self.walk(0, p, p, theta.recip(), |step| match step {
            Step::Leaf(node) => add_pulls(&mut a, id, p, &self.sources[node.range()], softening2),
            Step::Whole(i) => {
                let (node, &Moments { gm, quad }) = (&self.tree.nodes[i as usize], &self.tree.moments[i as usize]);
                let term = far_term(gm, quad, (p - node.com).as_vec3().to_array(), softening2 as f32);
                a += Vec3::from_array(term).as_dvec3();
            }
        });
        a.as_vec3()
    }

    /// The Barnes–Hut walk of the subtree of the node `root` for the box
    /// `lo..=hi` (a point when `lo == hi`), depth first: each node the box
    /// takes whole ([`Node::accepts`]) and each leaf it opens, in turn, to
    /// `visit`.
    pub(super) fn walk<'a>(
        &'a self,
        root: usize,
        lo: DVec3,
        hi: DVec3,
        inverse_theta: f64,
        mut visit: impl FnMut(Step<'a>),
    ) {
        let nodes = &self.tree.nodes;
        let mut i = root;
        while i < nodes[root].skip as usize {
            let node = &nodes[i];
            if node.leaf {
                visit(Step::Leaf(node));
                i = node.skip as usize;
            } else if node.accepts(lo, hi, inverse_theta) {
                visit(Step::Whole(i as u32));
                i = node.skip as usize;
            } else {
                i += 1;
            }
        }
    }

    /// The nodes in depth-first order, and what each pulls with whole.
    pub(super) fn nodes(&self) -> (&[Node], &[Moments]) {
        (&self.tree.nodes, &self.tree.moments)
    }

    /// The sources in leaf order.
    pub(super) fn sources(&self) -> &[GravitySource] {
        &self.sources
    }

    /// The sources in leaf order, as columns.
    pub(super) fn columns(&self) -> &LeafSources {
        &self.columns
    }

    /// The regions, in leaf order.
    pub(super) fn regions(&self) -> &[Run] {
        &self.regions
    }

    /// The groups, in leaf order.
    pub(super) fn groups(&self) -> &[std::ops::Range<u32>] {
        &self.groups
    }

    /// For each group, the index of its region.
    pub(super) fn group_regions(&self) -> &[u32] {
        &self.group_regions
    }

    /// The groups of the region `region` (groups follow their regions in
    /// leaf order).
    pub(super) fn groups_of(&self, region: usize) -> &[std::ops::Range<u32>] {
        let region = region as u32;
        let start = self.group_regions.partition_point(|&r| r < region);
        let end = self.group_regions.partition_point(|&r| r <= region);
        &self.groups[start..end]
    }

    /// Number of regions (see `walk.rs`).
    pub fn region_count(&self) -> usize {
        self.regions.len()
    }

    /// Number of groups (see `walk.rs`).
    pub fn group_count(&self) -> usize {
        self.groups.len()
    }

    /// For each source in leaf order, its index in the order the tree was
    /// built from.
    pub fn given_order(&self) -> &[u32] {
        &self.given
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::maths;
    use crate::maths::Rng;
    use crate::systems::gravity::source::acceleration_at;

    /// `count` sources of `G·m` = `gm` uniform in the cube of half edge
    /// `half` about the origin.
    pub(in crate::systems::gravity) fn uniform(count: u64, half: f64, gm: f64, seed: u64) -> Vec<GravitySource> {
        let mut rng = Rng::new(seed);
        (0..count)
            .map(|i| GravitySource {
                id: BodyId(i),
                position: DVec3::new(rng.symmetric(half), rng.symmetric(half), rng.symmetric(half)),
                gm,
            })
            .collect()
    }

    /// A Plummer-like cluster of `count` sources (dense core, sparse halo,
    /// unequal masses), radius capped at 5 000.
    pub(in crate::systems::gravity) fn cluster(count: usize, seed: u64) -> Vec<GravitySource> {
        let mut rng = Rng::new(seed);
        (0..count)
            .map(|i| {
                let r = 100.0 / (maths::pow(rng.range(0.01, 1.0), -2.0 / 3.0) - 1.0).sqrt();
                let z = rng.symmetric(1.0);
                let (sin, cos) = maths::sin_cos(rng.range(0.0, std::f64::consts::TAU));
                let s = (1.0 - z * z).sqrt();
                GravitySource {
                    id: BodyId(i as u64),
                    position: (DVec3::new(s * cos, s * sin, z) * r.min(5000.0)).as_vec3().as_dvec3(),
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
    fn the_tree_built_in_parallel_is_the_tree_built_on_one_thread() {
        use crate::execution::{Execution, ExecutionMode};
        let sources = cluster(5000, 4);
        let mut whole = Octree::default();
        whole.rebuild(&sources);
        let execution = Execution::new(ExecutionMode::Parallel, 3).unwrap().fine_grained();
        let mut split = Octree::default();
        split.rebuild_split(&sources, execution.for_stage("test", sources.len()));
        assert!(whole.len() > 500);
        assert_eq!(split, whole);
    }

    /// A tree rebuilt over and over, its buffers reused at other counts
    /// (fewer, a root that is a leaf, none, more again), is each time the
    /// tree a fresh one builds, on one thread or split.
    #[test]
    fn a_rebuilt_tree_is_a_fresh_tree_whatever_its_buffers_held() {
        use crate::execution::{Execution, ExecutionMode};
        let execution = Execution::new(ExecutionMode::Parallel, 3).unwrap().fine_grained();
        let (mut reused, mut reused_split) = (Octree::default(), Octree::default());
        for (count, seed) in [(5000, 1), (300, 2), (5, 3), (0, 4), (7000, 5)] {
            let sources = cluster(count, seed);
            let mut fresh = Octree::default();
            fresh.rebuild(&sources);
            reused.rebuild(&sources);
            reused_split.rebuild_split(&sources, execution.for_stage("test", count));
            assert_eq!(reused, fresh, "{count} sources");
            assert_eq!(reused_split, fresh, "{count} sources, split");
            assert_eq!(fresh.given_order().len(), count);
        }
    }

    #[test]
    fn theta_zero_is_the_direct_sum() {
        let errors = relative_errors(&cluster(1000, 2), 0.0);
        let worst = errors[errors.len() - 1];
        assert!(worst <= 1e-6, "worst relative error {worst}");
    }

    #[test]
    fn groups_hold_every_source_once_in_leaf_order_at_most_a_group_size_each() {
        for (count, seed) in [(5000, 4), (300, 5), (33, 6)] {
            let mut tree = Octree::default();
            tree.rebuild(&cluster(count, seed));
            let mut next = 0;
            for group in &tree.groups {
                assert_eq!(group.start, next, "groups follow each other in leaf order");
                assert!((1..=GROUP_SIZE as usize).contains(&group.len()), "{group:?}");
                next = group.end;
            }
            assert_eq!(next as usize, count);
        }
        // Sibling nodes are taken together: a uniform cloud walks in fewer
        // groups than it has highest nodes of at most a group's size (here
        // the octree's second level holds about 1.25 groups' worth, so the
        // highest such nodes are its children, of about a sixth each).
        let mut tree = Octree::default();
        tree.rebuild(&uniform(u64::from(GROUP_SIZE) * 80, 1.0, 1.0, 7));
        let mut nodes = 0;
        let mut i = 0;
        while i < tree.tree.nodes.len() {
            let node = &tree.tree.nodes[i];
            if node.len <= GROUP_SIZE || node.leaf {
                nodes += 1;
                i = node.skip as usize;
            } else {
                i += 1;
            }
        }
        assert!(
            tree.groups().len() * 2 < nodes,
            "{} groups for {nodes} nodes",
            tree.groups().len()
        );
    }

    /// A quadrupole component that is only rounding noise (two sources on
    /// the x axis but for one `f32` step in y) is 0, not an `f32`
    /// subnormal that slows the far sums.
    #[test]
    fn rounding_noise_in_the_quadrupole_is_zero() {
        let y = 1.0f32;
        let sources = [
            GravitySource {
                id: BodyId(0),
                position: DVec3::new(-3.0, f64::from(y), 0.0),
                gm: 1.0,
            },
            GravitySource {
                id: BodyId(1),
                position: DVec3::new(3.0, f64::from(y.next_up()), 0.0),
                gm: 1.0,
            },
        ];
        let items: Vec<Item> = sources.iter().copied().zip(0..).collect();
        let (_, moments) = node_of(&Summary::of(&items), 0, items.len(), 0);
        let [xx, yy, zz, xy, xz, yz] = moments.quad;
        assert_eq!((xy, xz, yz), (0.0, 0.0, 0.0), "{:?}", moments.quad);
        assert!((xx - 18.0).abs() < 1e-9 && (yy + 9.0).abs() < 1e-9 && (zz + 9.0).abs() < 1e-9);
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
