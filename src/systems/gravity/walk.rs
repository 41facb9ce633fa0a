//! The walks of the tree (docs/design.md, "Gravity"): every source's
//! acceleration, region by region.
//!
//! First each region (at most [`REGION_SIZE`](super::tree::REGION_SIZE)
//! sources) walks the tree once, for its bounding box and its groups'
//! boxes. A node the region's box takes whole, every group takes whole
//! too; a node no group takes whole, every group opens; a leaf reached
//! through such nodes, every group sums one by one. Those are the
//! region's lists, summed once for each of its bodies there and then
//! ([`RegionShare::sums`]), instead of being copied into every group's
//! lists. Sources of the leaves the region opens that lie beyond
//! [`local_reach`] of its center go to the region's local expansion
//! (`local.rs`), summed once for all its bodies instead of once per
//! body; a node wholly beyond that reach that the region does not take
//! whole, it opens for its groups. Then each group walks only the nodes
//! left in between, which some of the region's groups take whole and
//! others not; a body's pull is its group's sums, plus its region's, plus
//! the local expansion: the lists together are the ones its group's own
//! walk of the whole tree would give. Both halves are split among threads
//! in small chunks, since their cost varies.

use std::ops::Range;

use bevy::math::{DVec3, Vec3};

use super::columns::GroupLists;
use super::kernel::group_pulls;
use super::local_expansion::{Local, LocalExpansion, LocalSources};
use super::tree::{Octree, Step, bounds};

/// Room a near list starts with (in a uniform cloud of 100 000 a region's
/// lists hold about 1 200 sources and 270 nodes, a group's own about 1 000
/// and 200; a shattered cluster's more); its far list gets a quarter.
const LIST_CAPACITY: usize = 4096;

/// The least distance from the center of the box `lo..=hi` at which a
/// source joins the local expansion of the region in the box: `2·ρ/θ`, `ρ`
/// half the box's diagonal (`inverse_theta` = `1/θ`), so that no body of
/// the region is farther from the center than `θ/2` of the source's
/// distance; at least `2·ρ` (for `θ` above 1), so that the series always
/// converges and no source of the region is ever in its own expansion;
/// infinite for `θ = 0`.
fn local_reach(lo: DVec3, hi: DVec3, inverse_theta: f64) -> f64 {
    if inverse_theta.is_infinite() {
        return f64::INFINITY;
    }
    (hi - lo).length() * inverse_theta.max(1.0)
}

/// What a region's walk shares with its groups (see the module's
/// documentation).
#[derive(Clone, Debug, Default)]
pub struct RegionShare {
    /// The pull of the region's lists on each of its sources, in leaf
    /// order.
    sums: Vec<DVec3>,
    /// Nodes whose subtrees each group walks itself.
    open: Vec<u32>,
    /// The local expansion of the distant sources, if there are any.
    local: Option<Local>,
}

/// What a region's walk finds for all its groups, kept between regions.
#[derive(Debug, Default)]
struct RegionLists {
    /// Runs of sources (leaf order) every group sums one by one.
    near: Vec<Range<usize>>,
    /// Nodes every group takes whole.
    far: Vec<u32>,
    /// The sources of the local expansion.
    distant: LocalSources,
}

/// Appends `range` to `runs`, joined to the last run if they touch.
fn push_run(runs: &mut Vec<Range<usize>>, range: Range<usize>) {
    match runs.last_mut() {
        Some(last) if last.end == range.start => last.end = range.end,
        _ => runs.push(range),
    }
}

/// Kernel, first half: what the regions `regions` of `tree` (a range of
/// region indices) share with their groups, and the pull of the region's
/// lists on each of its sources, with the opening angle `theta` and
/// softening `ε²` = `softening2`.
pub fn region_shares(tree: &Octree, regions: Range<usize>, theta: f64, softening2: f64) -> Vec<RegionShare> {
    let inverse_theta = theta.recip();
    let mut found = RegionLists::default();
    let mut lists = GroupLists::with_capacity(LIST_CAPACITY, LIST_CAPACITY / 4);
    let mut boxes = Vec::new();
    tree.regions()[regions.clone()]
        .iter()
        .zip(regions)
        .map(|(region, r)| {
            let members = &tree.sources()[region.sources.start as usize..region.sources.end as usize];
            let (lo, hi) = bounds(members);
            boxes.clear();
            boxes.extend(
                tree.groups_of(r)
                    .iter()
                    .map(|group| bounds(&tree.sources()[group.start as usize..group.end as usize])),
            );
            let mut share = RegionShare::default();
            region_walk(tree, lo, hi, &boxes, inverse_theta, &mut share.open, &mut found);
            let center = (lo + hi) * 0.5;
            share.local = (!found.distant.is_empty()).then(|| Local {
                center,
                expansion: LocalExpansion::of(&found.distant, softening2),
            });
            fill(tree, &mut lists, center, &found.near, &found.far);
            share.sums.reserve_exact(members.len());
            group_pulls(&lists, members, softening2, &mut share.sums);
            share
        })
        .collect()
}

/// Kernel, second half: the acceleration of every source in the groups
/// `groups` of `tree` (a range of group indices), in leaf order, given
/// `shares`, every region's share, with the opening angle `theta` and
/// softening `ε²` = `softening2`. Each source's sum depends on its region
/// and group alone, never on how regions and groups are split among
/// threads.
pub fn group_accelerations(
    tree: &Octree,
    groups: Range<usize>,
    shares: &[RegionShare],
    theta: f64,
    softening2: f64,
) -> Vec<Vec3> {
    let inverse_theta = theta.recip();
    let sources = tree.sources();
    let (mut near, mut far, mut sums) = (Vec::new(), Vec::new(), Vec::new());
    let mut lists = GroupLists::with_capacity(LIST_CAPACITY, LIST_CAPACITY / 4);
    let mut out = Vec::with_capacity(tree.groups()[groups.clone()].iter().map(|g| g.len()).sum());
    for (group, &region) in tree.groups()[groups.clone()].iter().zip(&tree.group_regions()[groups]) {
        let share = &shares[region as usize];
        let members = &sources[group.start as usize..group.end as usize];
        let (lo, hi) = bounds(members);
        near.clear();
        far.clear();
        for &root in &share.open {
            tree.walk(root as usize, lo, hi, inverse_theta, |step| match step {
                Step::Leaf(node) => push_run(&mut near, node.range()),
                Step::Whole(i) => far.push(i),
            });
        }
        fill(tree, &mut lists, (lo + hi) * 0.5, &near, &far);
        sums.clear();
        group_pulls(&lists, members, softening2, &mut sums);
        // This group's sources among its region's.
        let first = (group.start - tree.regions()[region as usize].sources.start) as usize;
        let region_sums = &share.sums[first..first + members.len()];
        out.extend(members.iter().zip(&sums).zip(region_sums).map(|((s, &own), &shared)| {
            let sum = own + shared;
            match &share.local {
                Some(local) => (sum + local.at(s.position)).as_vec3(),
                None => sum.as_vec3(),
            }
        }));
    }
    out
}

/// Fills `lists`, relative to `center`, with the sources of the runs
/// `near` (leaf order) and the nodes `far` of `tree`, padded.
fn fill(tree: &Octree, lists: &mut GroupLists, center: DVec3, near: &[Range<usize>], far: &[u32]) {
    let (nodes, moments) = tree.nodes();
    lists.clear(center);
    for run in near {
        lists.push_near(tree.columns(), run.clone());
    }
    lists.extend_far(far.iter().map(|&i| {
        let (node, m) = (&nodes[i as usize], &moments[i as usize]);
        (node.com, m.gm, m.quad)
    }));
    lists.pad();
}

/// The region walk of `tree` for the box `lo..=hi` of the groups in
/// `boxes`: the subtrees the groups walk themselves into `open`, the rest
/// into `found` (see the module's documentation).
fn region_walk(
    tree: &Octree,
    lo: DVec3,
    hi: DVec3,
    boxes: &[(DVec3, DVec3)],
    inverse_theta: f64,
    open: &mut Vec<u32>,
    found: &mut RegionLists,
) {
    let RegionLists { near, far, distant } = found;
    near.clear();
    far.clear();
    open.clear();
    distant.clear();
    let (nodes, _) = tree.nodes();
    let sources = tree.sources();
    let center = (lo + hi) * 0.5;
    let reach = local_reach(lo, hi, inverse_theta);
    let beyond = |d: DVec3| d.length_squared() > reach * reach;
    let mut i = 0;
    while i < nodes.len() {
        let node = &nodes[i];
        if node.leaf {
            let (middle, half) = node.cube();
            if !beyond((center - middle).abs() + half) {
                push_run(near, node.range());
            } else {
                // Its farthest corner is beyond: source by source.
                for (k, s) in sources[node.range()].iter().enumerate() {
                    if beyond(s.position - center) {
                        distant.push(s.position - center, s.gm);
                    } else {
                        let k = node.first as usize + k;
                        push_run(near, k..k + 1);
                    }
                }
            }
        } else if node.accepts(lo, hi, inverse_theta) {
            far.push(i as u32);
        } else if node.opened_by_all(lo, hi, inverse_theta)
            || boxes.iter().all(|&(lo, hi)| !node.accepts(lo, hi, inverse_theta))
            || beyond(center - node.clamp(center))
        {
            // Opened by every group (surely by any box in the region's,
            // or else by each group's own box), or so far that the
            // region decides for its groups: it opens the node, its
            // leaves go to the local expansion.
            i += 1;
            continue;
        } else {
            open.push(i as u32);
        }
        i = node.skip as usize;
    }
    distant.pad();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::BodyId;
    use crate::maths;
    use crate::maths::Rng;
    use crate::systems::gravity::source::{GravitySource, acceleration_at};
    use crate::systems::gravity::tree::tests::{cluster, uniform};

    /// Every source's acceleration from the walks, in the order given; the
    /// regions cut into uneven chunks as threads would.
    fn walked(sources: &[GravitySource], theta: f64) -> Vec<Vec3> {
        let mut tree = Octree::default();
        tree.rebuild(sources);
        let cuts = |n: usize| [0, n / 7, n / 3, n / 3 + 1, n];
        let shares: Vec<RegionShare> = cuts(tree.region_count())
            .windows(2)
            .flat_map(|w| region_shares(&tree, w[0]..w[1], theta, 1.0))
            .collect();
        let mut out = vec![Vec3::ZERO; sources.len()];
        let group_cuts = cuts(tree.group_count());
        let leaf_order = group_cuts
            .windows(2)
            .flat_map(|w| group_accelerations(&tree, w[0]..w[1], &shares, theta, 1.0));
        for (a, &k) in leaf_order.zip(tree.given_order()) {
            out[k as usize] = a;
        }
        assert_eq!(tree.given_order().len(), sources.len());
        out
    }

    /// Relative errors against the direct sum, sorted.
    fn errors(sources: &[GravitySource], theta: f64) -> Vec<f64> {
        let mut e: Vec<f64> = walked(sources, theta)
            .iter()
            .zip(sources)
            .map(|(a, s)| {
                let d = acceleration_at(s.id, s.position.as_vec3(), sources, 1.0).as_dvec3();
                (a.as_dvec3() - d).length() / d.length()
            })
            .collect();
        e.sort_unstable_by(f64::total_cmp);
        e
    }

    /// At θ = 0, each body's error against the direct sum over the sum of
    /// the sizes of the terms (`Σ G·m·|d|/(|d|² + ε²)^{3/2}`), sorted.
    fn rounding_of_terms(sources: &[GravitySource]) -> Vec<f64> {
        let mut e: Vec<f64> = walked(sources, 0.0)
            .iter()
            .zip(sources)
            .map(|(a, b)| {
                let d = acceleration_at(b.id, b.position.as_vec3(), sources, 1.0).as_dvec3();
                let size: f64 = sources
                    .iter()
                    .map(|s| {
                        let r = (s.position - b.position).length();
                        s.gm * r / maths::pow(r * r + 1.0, 1.5)
                    })
                    .sum();
                (a.as_dvec3() - d).length() / size
            })
            .collect();
        e.sort_unstable_by(f64::total_cmp);
        e
    }

    #[test]
    fn the_walks_meet_the_goal_and_give_the_direct_sum_at_theta_zero() {
        let sources = cluster(3000, 1);
        let e = errors(&sources, 0.5);
        let (median, p99) = (e[e.len() / 2], e[e.len() * 99 / 100]);
        eprintln!("walks, θ = 0.5: median relative error {median:.2e}, 99th percentile {p99:.2e}");
        assert!(median <= 1e-3 && p99 <= 1e-2, "median {median}, 99th percentile {p99}");
        // θ = 0: the direct sum to f32 precision. The near sums are f32
        // from positions relative to the region's or the group's center:
        // about one f32 rounding of the pull at the median. Each term errs
        // by about |x − c|·2⁻²⁴ in the distance (a source's offset from the
        // center rounded), which for the pair of a body and a neighbor
        // within the softening is many roundings of the term, yet less than
        // the f32 positions' own rounding of |x|·2⁻²⁴; against the terms
        // summed, that is below 10⁻⁵.
        let e = errors(&sources, 0.0);
        let (median, worst) = (e[e.len() / 2], e[e.len() - 1]);
        let terms = rounding_of_terms(&sources);
        eprintln!(
            "walks, θ = 0: median relative error {median:.2e}, worst {worst:.2e}; worst against the terms summed {:.2e}",
            terms[terms.len() - 1]
        );
        assert!(median <= 1e-7, "θ = 0: median {median}");
        let worst_of_terms = terms[terms.len() - 1];
        assert!(
            worst_of_terms <= 1e-5,
            "θ = 0: worst against the terms {worst_of_terms}"
        );
    }

    /// Where the region's local reach opens nothing for its groups (in a
    /// uniform cloud no node lies wholly beyond it, and no source goes to an
    /// expansion), a region's lists and each of its groups' own lists
    /// together hold exactly what the group's own walk of the whole tree
    /// would: the same sources one by one and the same nodes whole, none
    /// twice.
    #[test]
    fn a_regions_lists_and_a_groups_own_are_the_groups_whole_walk() {
        let mut tree = Octree::default();
        tree.rebuild(&uniform(6000, 500.0, 6.674, 21));
        let inverse_theta = 2.0;
        // Sources summed one by one and nodes taken whole, sorted.
        let lists = |runs: &[Range<usize>], far: &[u32]| {
            let mut near: Vec<usize> = runs.iter().flat_map(Range::clone).collect();
            let mut far = far.to_vec();
            near.sort_unstable();
            far.sort_unstable();
            (near, far)
        };
        let walk = |roots: &[u32], (lo, hi): (DVec3, DVec3)| {
            let (mut runs, mut far) = (Vec::new(), Vec::new());
            for &root in roots {
                tree.walk(root as usize, lo, hi, inverse_theta, |step| match step {
                    Step::Leaf(node) => runs.push(node.range()),
                    Step::Whole(i) => far.push(i),
                });
            }
            (runs, far)
        };
        let (mut open, mut found) = (Vec::new(), RegionLists::default());
        let (mut checked, mut own) = (0, 0);
        for (r, region) in tree.regions().iter().enumerate() {
            let (lo, hi) = bounds(&tree.sources()[region.sources.start as usize..region.sources.end as usize]);
            let boxes: Vec<(DVec3, DVec3)> = tree
                .groups_of(r)
                .iter()
                .map(|g| bounds(&tree.sources()[g.start as usize..g.end as usize]))
                .collect();
            region_walk(&tree, lo, hi, &boxes, inverse_theta, &mut open, &mut found);
            assert!(found.distant.is_empty(), "region {r} expanded sources");
            for &group in &boxes {
                let (mut runs, mut far) = walk(&open, group);
                own += runs.len() + far.len();
                runs.extend(found.near.iter().cloned());
                far.extend(&found.far);
                let (whole_runs, whole_far) = walk(&[0], group);
                assert_eq!(lists(&runs, &far), lists(&whole_runs, &whole_far), "region {r}");
                checked += 1;
            }
            // The region shares something with its groups.
            assert!(!found.near.is_empty() && !found.far.is_empty(), "region {r}");
        }
        assert_eq!(checked, tree.group_count());
        // The groups' own walks find something too.
        assert!(own > 0);
    }

    /// A dense clump in a wide, sparse halo: the halo's leaves are as big as
    /// their distance, so the clump's bodies would sum the halo one by one;
    /// the clump's regions expand it instead, and the pulls still meet the
    /// goal.
    #[test]
    fn a_clump_in_a_sparse_halo_expands_the_halo_and_meets_the_goal() {
        let mut rng = Rng::new(11);
        let sources: Vec<GravitySource> = (0..3000)
            .map(|i| {
                let dir = DVec3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0));
                let r = if i % 3 == 0 {
                    rng.range(100.0, 20_000.0)
                } else {
                    rng.range(0.0, 30.0)
                };
                GravitySource {
                    id: BodyId(i),
                    position: dir.normalize_or_zero() * r,
                    gm: 6.674 * rng.range(0.5, 2.0),
                }
            })
            .collect();
        let mut tree = Octree::default();
        tree.rebuild(&sources);
        let (mut open, mut found) = (Vec::new(), RegionLists::default());
        let (lo, hi) = tree
            .regions()
            .iter()
            .map(|r| bounds(&tree.sources()[r.sources.start as usize..r.sources.end as usize]))
            .min_by(|a, b| (a.1 - a.0).length().total_cmp(&(b.1 - b.0).length()))
            .unwrap();
        region_walk(&tree, lo, hi, &[(lo, hi)], 2.0, &mut open, &mut found);
        assert!(found.distant.count() > 500, "{} expanded", found.distant.count());
        let e = errors(&sources, 0.5);
        let (median, p99) = (e[e.len() / 2], e[e.len() * 99 / 100]);
        eprintln!("clump and halo, θ = 0.5: median relative error {median:.2e}, 99th percentile {p99:.2e}");
        assert!(median <= 1e-3 && p99 <= 1e-2, "median {median}, 99th percentile {p99}");
    }

    /// However the regions and groups are cut among threads, the same
    /// bits; and at the largest `θ` no source of a region is in its own
    /// local expansion, so every pull stays finite and near the direct sum.
    #[test]
    fn the_cut_does_not_change_the_bits_and_the_largest_theta_is_sane() {
        let sources = cluster(3000, 3);
        let mut tree = Octree::default();
        tree.rebuild(&sources);
        let whole: Vec<RegionShare> = region_shares(&tree, 0..tree.region_count(), 0.5, 1.0);
        let once = group_accelerations(&tree, 0..tree.group_count(), &whole, 0.5, 1.0);
        let bits = |v: &[Vec3]| {
            v.iter()
                .flat_map(|a| a.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        let cut = walked(&sources, 0.5);
        let leaf_order: Vec<Vec3> = tree.given_order().iter().map(|&k| cut[k as usize]).collect();
        assert_eq!(bits(&leaf_order), bits(&once));
        let inverse_theta = 1.0 / f64::from(crate::resources::MAX_THETA);
        for region in tree.regions() {
            let members = &tree.sources()[region.sources.start as usize..region.sources.end as usize];
            let (lo, hi) = bounds(members);
            let reach = local_reach(lo, hi, inverse_theta);
            let center = (lo + hi) * 0.5;
            assert!(members.iter().all(|s| (s.position - center).length() * 2.0 <= reach));
        }
        let e = errors(&sources, f64::from(crate::resources::MAX_THETA));
        let (median, worst) = (e[e.len() / 2], e[e.len() - 1]);
        eprintln!("walks, θ = 2: median relative error {median:.2e}, worst {worst:.2e}");
        assert!(worst.is_finite() && median < 0.05, "median {median}, worst {worst}");
    }

    /// Sources spread over every scale up to 10²⁵ (so that some nodes are
    /// wider than `f32`'s squares allow and taken whole from farther still):
    /// every pull is finite, through the walks and the single-point walk,
    /// at θ = 0.5 and at the largest θ.
    #[test]
    fn sources_spread_to_the_largest_scales_pull_finitely() {
        let mut rng = Rng::new(17);
        let sources: Vec<GravitySource> = (0..3000)
            .map(|i| {
                let dir = DVec3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0)).normalize_or_zero();
                GravitySource {
                    id: BodyId(i),
                    position: (dir * maths::pow(10.0, rng.range(0.0, 25.0))).as_vec3().as_dvec3(),
                    gm: 6.674 * rng.range(0.5, 2.0),
                }
            })
            .collect();
        let mut tree = Octree::default();
        tree.rebuild(&sources);
        for theta in [0.5, f64::from(crate::resources::MAX_THETA)] {
            let walked = walked(&sources, theta);
            for (a, s) in walked.iter().zip(&sources) {
                assert!(a.is_finite(), "θ = {theta}: {a} at {}", s.position);
                let alone = tree.acceleration_at(BodyId(u64::MAX), s.position.as_vec3() + Vec3::X, theta, 1.0);
                assert!(alone.is_finite(), "θ = {theta}: {alone} near {}", s.position);
            }
        }
    }

    /// A leaf at the deepest level holds every source on one point, more
    /// than a group's worth: it is a group too, and every source gets its
    /// own acceleration.
    #[test]
    fn sources_on_one_point_beyond_a_group_are_a_group_too() {
        let mut sources: Vec<GravitySource> = (0..40)
            .map(|i| GravitySource {
                id: BodyId(i),
                position: DVec3::splat(3.0),
                gm: 1.0,
            })
            .collect();
        sources.push(GravitySource {
            id: BodyId(40),
            position: DVec3::new(13.0, 3.0, 3.0),
            gm: 2.0,
        });
        let got = walked(&sources, 0.5);
        // Each of the 40 feels the lone source 10 away (softening 1) and not
        // the others on its point; the lone one feels all 40.
        let pull = |gm: f64| (gm * 10.0 / (101.0 * 101f64.sqrt())) as f32;
        for a in &got[..40] {
            assert!((a.x - pull(2.0)).abs() < 1e-6 && a.y == 0.0, "{a}");
        }
        assert!((got[40].x + pull(40.0)).abs() < 1e-5, "{}", got[40]);
    }
}
