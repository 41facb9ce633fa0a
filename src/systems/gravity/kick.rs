//! The pull the stage sums by ([`prepare_pull`], `Auto` decided), the
//! sources it sums ([`collect_sources`]) and the kick `v += a·dt`
//! ([`gravity_kernel`]), at the update's start or, with the leapfrog, after
//! the first half drift.

use bevy::prelude::*;

use super::source::{GravitySource, acceleration_at};
use super::tree::Octree;
use super::walk::{RegionShare, group_accelerations, region_shares};
use crate::components::{BodyId, GravityRole, Mass, Position, PreviousPosition, Velocity};
use crate::execution::{Execution, Split, StageExecution};
use crate::resources::{GravityMethod, Integrator};
use crate::systems::SimulationSystems;

/// The columns the gravity kernel reads and writes.
pub type GravityColumns<'a> = (
    &'a [BodyId],
    Roles<'a>,
    &'a mut [Position],
    &'a mut [PreviousPosition],
    &'a mut [Velocity],
);

/// A table's gravity roles, as the kernel reads them: each body's where
/// the table stores them, or none stored, its bodies all adopters
/// ([`GravityRole`]'s rule).
#[derive(Clone, Copy, Debug)]
pub enum Roles<'a> {
    /// Each body's role.
    Each(&'a [GravityRole]),
    /// This many bodies, every one an adopter.
    Adopters(usize),
}

impl<'a> Roles<'a> {
    /// The roles of a table of `len` bodies whose role column is `stored`.
    pub fn of_table(stored: Option<&'a [GravityRole]>, len: usize) -> Self {
        stored.map_or(Self::Adopters(len), Self::Each)
    }
}

impl Split for Roles<'_> {
    fn len(&self) -> usize {
        match self {
            Self::Each(roles) => roles.len(),
            Self::Adopters(len) => *len,
        }
    }

    fn split_at(self, mid: usize) -> (Self, Self) {
        match self {
            Self::Each(roles) => {
                let (a, b) = roles.split_at(mid);
                (Self::Each(a), Self::Each(b))
            }
            Self::Adopters(len) => (Self::Adopters(mid), Self::Adopters(len - mid)),
        }
    }
}

/// Where the pull comes from: every source, or their octree.
#[derive(Clone, Copy, Debug)]
pub enum Pull<'a> {
    /// The sources, summed one by one in id order.
    Direct(&'a [GravitySource]),
    /// Their Barnes–Hut tree, with its opening angle, and the acceleration
    /// of each of the sources (sorted by id), which the tree computes group
    /// by group beforehand; an adopter that is no source walks the tree on
    /// its own.
    Tree {
        /// The tree.
        tree: &'a Octree,
        /// Its opening angle θ.
        theta: f64,
        /// The sources, sorted by id.
        sources: &'a [GravitySource],
        /// The acceleration of each of `sources`.
        accelerations: &'a [Vec3],
    },
}

impl Pull<'_> {
    /// The method this pull sums by: `Direct` or `Tree`.
    pub fn method(&self) -> GravityMethod {
        match *self {
            Self::Direct(_) => GravityMethod::Direct,
            Self::Tree { theta, .. } => GravityMethod::Tree { theta: theta as f32 },
        }
    }

    /// The acceleration of the body `id` at `position` (`ε²` = `softening2`).
    #[inline]
    pub fn at(&self, id: BodyId, position: Vec3, softening2: f64) -> Vec3 {
        self.at_after(id, position, softening2, &mut 0)
    }

    /// [`at`](Self::at) for bodies asked about in order: `next` is where
    /// the previous body's source was, plus one, and becomes this body's.
    /// Bodies are stored in about the order of their ids, so a source is
    /// most often found there without a search. Always inlined: called
    /// once a body in the kick's loops.
    #[inline(always)]
    pub fn at_after(&self, id: BodyId, position: Vec3, softening2: f64, next: &mut usize) -> Vec3 {
        match *self {
            Self::Direct(sources) => acceleration_at(id, position, sources, softening2),
            Self::Tree {
                tree,
                theta,
                sources,
                accelerations,
            } => {
                let found = match sources.get(*next) {
                    Some(s) if s.id == id => Ok(*next),
                    _ => sources.binary_search_by_key(&id, |s| s.id),
                };
                match found {
                    Ok(k) => {
                        *next = k + 1;
                        accelerations[k]
                    }
                    Err(_) => tree.acceleration_at(id, position, theta, softening2),
                }
            }
        }
    }
}

/// What a tree pull is made in, kept between updates: the tree and the
/// sources' accelerations through it.
#[derive(Clone, Debug, Default)]
pub struct PullScratch {
    tree: Octree,
    accelerations: Vec<Vec3>,
}

/// The gravity stage's pull as `method` asks for it (`Auto` decided by
/// the number of sources, [`GravityMethod::resolve`]), over `sources`
/// (sorted by id) for `bodies` bodies, and the stage's execution: split as
/// the policy says for the stage's work, weighed in pulls (bodies ×
/// sources, or × about 1 000 through the tree), the unit its calibration
/// measured with the thesis's single source. A tree is built and its
/// sources' accelerations computed here, in `scratch`.
pub fn prepare_pull<'a>(
    method: GravityMethod,
    sources: &'a [GravitySource],
    bodies: usize,
    softening2: f64,
    execution: &'a Execution,
    scratch: &'a mut PullScratch,
) -> (Pull<'a>, StageExecution<'a>) {
    // Resolved: never `Auto`.
    let method = method.resolve(sources.len());
    let pulls_per_body = match method {
        GravityMethod::Tree { .. } => sources.len().min(TREE_PULLS_PER_BODY),
        GravityMethod::Direct | GravityMethod::Auto => sources.len(),
    };
    let work = bodies.saturating_mul(pulls_per_body.max(1));
    let stage = execution.for_stage(SimulationSystems::Gravity.name(), work);
    let pull = match method {
        GravityMethod::Tree { theta } => tree_pull(sources, f64::from(theta), softening2, stage, scratch),
        GravityMethod::Direct | GravityMethod::Auto => Pull::Direct(sources),
    };
    (pull, stage)
}

/// The pull through the Barnes–Hut tree over `sources` (sorted by id):
/// rebuilds the tree and computes every source's acceleration, the region
/// walks and then the groups split among threads as `stage` says.
fn tree_pull<'a>(
    sources: &'a [GravitySource],
    theta: f64,
    softening2: f64,
    stage: StageExecution<'_>,
    scratch: &'a mut PullScratch,
) -> Pull<'a> {
    let PullScratch { tree, accelerations } = scratch;
    tree.rebuild_split(sources, stage);
    let tree = &*tree;
    let shares: Vec<RegionShare> = stage
        .map_uneven_chunks(0..tree.region_count(), |regions| {
            region_shares(tree, regions, theta, softening2)
        })
        .into_iter()
        .flatten()
        .collect();
    let by_group = stage.map_uneven_chunks(0..tree.group_count(), |groups| {
        group_accelerations(tree, groups, &shares, theta, softening2)
    });
    accelerations.clear();
    accelerations.resize(sources.len(), Vec3::ZERO);
    let in_leaf_order = by_group.iter().flatten();
    debug_assert_eq!(
        in_leaf_order.clone().count(),
        sources.len(),
        "every source is in one group"
    );
    for (&a, &k) in in_leaf_order.zip(tree.given_order()) {
        accelerations[k as usize] = a;
    }
    Pull::Tree {
        tree,
        theta,
        sources,
        accelerations,
    }
}

/// Where a body is after half an update's drift, `p + v·(dt/2)` with
/// `half` = `dt/2`: the leapfrog's midpoint. The kernel moves every body
/// there and [`collect_sources`] places the sources there, with the same
/// bits, so a body finds itself among the sources.
#[inline]
pub fn half_drift(position: Vec3, velocity: Vec3, half: f32) -> Vec3 {
    position + velocity * half
}

/// Kernel: the kick `v += a·dt` of every adopter in the columns, `a` being
/// the gravitational pull where `integrator` evaluates it; other bodies
/// keep their velocity.
///
/// - `SemiImplicitEuler` (the thesis): `a` at the position, which stays;
///   the integrate stage then drifts a whole step.
/// - `Leapfrog`: every body first drifts half a step
///   (`half_drift`), keeping its position as the previous one, and `a`
///   is the pull at that midpoint (the sources placed there by
///   [`collect_sources`]); the integrate stage drifts the second half.
pub fn gravity_kernel(
    (ids, roles, positions, previous, velocities): GravityColumns<'_>,
    pull: Pull<'_>,
    softening2: f64,
    dt: f32,
    integrator: Integrator,
) {
    let columns = (ids, positions, previous, velocities);
    match roles {
        Roles::Each(roles) => kick(columns, roles.iter().copied(), pull, softening2, dt, integrator),
        Roles::Adopters(_) => kick(
            columns,
            std::iter::repeat(GravityRole::Adopter),
            pull,
            softening2,
            dt,
            integrator,
        ),
    }
}

/// [`gravity_kernel`]'s loop, with the roles as an iterator: a table that
/// stores none gets one of adopters only, whose test the compiler takes out
/// of the loop. Its four copies (two role shapes, two integrators) each
/// inline [`Pull::at_after`], which the compiler otherwise called, 17 %
/// slower in parallel (docs/benchmarks.md, "Bytes won back").
fn kick(
    (ids, positions, previous, velocities): (&[BodyId], &mut [Position], &mut [PreviousPosition], &mut [Velocity]),
    roles: impl Iterator<Item = GravityRole>,
    pull: Pull<'_>,
    softening2: f64,
    dt: f32,
    integrator: Integrator,
) {
    let mut next = 0;
    match integrator {
        Integrator::SemiImplicitEuler => {
            for (((id, role), p), v) in ids.iter().zip(roles).zip(positions.iter()).zip(velocities) {
                if role.is_adopter() {
                    v.0 += pull.at_after(*id, p.0, softening2, &mut next) * dt;
                }
            }
        }
        Integrator::Leapfrog => {
            let half = dt * 0.5;
            let bodies = ids.iter().zip(roles).zip(positions).zip(previous).zip(velocities);
            for ((((id, role), p), prev), v) in bodies {
                prev.0 = p.0;
                p.0 = half_drift(p.0, v.0, half);
                if role.is_adopter() {
                    v.0 += pull.at_after(*id, p.0, softening2, &mut next) * dt;
                }
            }
        }
    }
}

/// About how many nodes and sources a body sums through the tree at
/// `θ = 0.5` (measured: near a thousand for 10 000 sources), for the split
/// policy.
const TREE_PULLS_PER_BODY: usize = 1000;

/// Roles tested at once by [`collect_sources`].
const SCAN_BLOCK: usize = 256;

/// One table's columns that [`collect_sources`] reads: its roles where it
/// stores them (a table that stores none holds adopters only, no source).
pub type SourceColumns<'a> = (
    &'a [BodyId],
    &'a [Position],
    &'a [Velocity],
    &'a [Mass],
    Option<&'a [GravityRole]>,
);

/// The sources among the bodies in `tables`, sorted by id so the sum order
/// is fixed, where `integrator` evaluates the pull: at their positions, or
/// for the leapfrog half a drift on (`half_drift`). Only the role column
/// is read for every body (sources are few).
pub fn collect_sources<'a>(
    tables: impl Iterator<Item = SourceColumns<'a>>,
    gravitational_constant: f64,
    integrator: Integrator,
    dt: f32,
    out: &mut Vec<GravitySource>,
) {
    out.clear();
    let half = dt * 0.5;
    for (ids, positions, velocities, masses, roles) in tables {
        let Some(roles) = roles else { continue };
        // Blocks without a source are skipped by a branch-free test that
        // the compiler vectorizes: a million roles take microseconds.
        for (block, block_roles) in roles.chunks(SCAN_BLOCK).enumerate() {
            if !block_roles.iter().fold(false, |any, role| any | role.is_source()) {
                continue;
            }
            for (k, role) in block_roles.iter().enumerate() {
                if role.is_source() {
                    let row = block * SCAN_BLOCK + k;
                    let position = match integrator {
                        Integrator::SemiImplicitEuler => positions[row].0,
                        Integrator::Leapfrog => half_drift(positions[row].0, velocities[row].0, half),
                    };
                    out.push(GravitySource {
                        id: ids[row],
                        position: position.as_dvec3(),
                        gm: gravitational_constant * f64::from(masses[row].0),
                    });
                }
            }
        }
    }
    out.sort_unstable_by_key(|s| s.id);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::gravity::source::tests::source;

    #[test]
    fn kernel_kicks_adopters_only() {
        let ids = [BodyId(1), BodyId(2), BodyId(3), BodyId(4)];
        let start = [Position(Vec3::new(1.0, 0.0, 0.0)); 4];
        let roles = [
            GravityRole::Adopter,
            GravityRole::Source,
            GravityRole::Inert,
            GravityRole::SourceAndAdopter,
        ];
        let mut positions = start;
        let mut previous = [PreviousPosition::default(); 4];
        let mut velocities = [Velocity(Vec3::ONE); 4];
        // Unit pull towards the origin for half a step: v.x = 1 − 0.5.
        gravity_kernel(
            (
                &ids,
                Roles::Each(&roles),
                &mut positions,
                &mut previous,
                &mut velocities,
            ),
            Pull::Direct(&[source(0, [0.0; 3], 1.0)]),
            0.0,
            0.5,
            Integrator::SemiImplicitEuler,
        );
        let vx: Vec<f32> = velocities.iter().map(|v| v.0.x).collect();
        assert_eq!(vx, [0.5, 1.0, 1.0, 0.5]);
        assert!(velocities.iter().all(|v| v.0.yz() == Vec2::ONE));
        assert_eq!(
            positions, start,
            "semi-implicit Euler leaves the drift to the integrate stage"
        );
    }

    /// A table that stores no roles holds adopters only: the kernel kicks
    /// every body in it as it kicks adopters whose roles are stored, and
    /// its roles split in two like a column.
    #[test]
    fn a_table_without_roles_is_kicked_as_adopters() {
        let ids = [BodyId(1), BodyId(2), BodyId(3)];
        let start = [
            Position(Vec3::new(1.0, 0.0, 0.0)),
            Position(Vec3::new(0.0, 2.0, 0.0)),
            Position(Vec3::new(0.0, 0.0, -3.0)),
        ];
        let sources = [source(0, [0.0; 3], 1.0)];
        let kicked = |roles: Roles<'_>, integrator: Integrator| {
            let mut positions = start;
            let mut previous = [PreviousPosition::default(); 3];
            let mut velocities = [Velocity(Vec3::ONE); 3];
            gravity_kernel(
                (&ids, roles, &mut positions, &mut previous, &mut velocities),
                Pull::Direct(&sources),
                0.0,
                0.5,
                integrator,
            );
            (positions, previous, velocities)
        };
        let adopters = [GravityRole::Adopter; 3];
        for integrator in [Integrator::SemiImplicitEuler, Integrator::Leapfrog] {
            let unstored = kicked(Roles::of_table(None, 3), integrator);
            assert_eq!(unstored, kicked(Roles::Each(&adopters), integrator));
            assert!(unstored.2.iter().all(|v| v.0 != Vec3::ONE), "every body kicked");
        }
        let (a, b) = Roles::of_table(None, 3).split_at(1);
        assert_eq!((a.len(), b.len()), (1, 2));
        assert!(matches!(a, Roles::Adopters(1)) && matches!(b, Roles::Adopters(2)));
    }

    /// The leapfrog's first half: every body drifts `v·dt/2` from where it
    /// was (kept as its previous position), and adopters are kicked by the
    /// pull at that midpoint, not at the start.
    #[test]
    fn the_leapfrog_kicks_at_the_midpoint_of_the_drift() {
        let ids = [BodyId(1), BodyId(2)];
        let roles = [GravityRole::Adopter, GravityRole::Inert];
        let mut positions = [Position(Vec3::new(2.0, 0.0, 0.0)); 2];
        let mut previous = [PreviousPosition::default(); 2];
        // Moving in +x at 4 for dt = 1: the midpoint is x = 4.
        let mut velocities = [Velocity(Vec3::new(4.0, 0.0, 0.0)); 2];
        gravity_kernel(
            (
                &ids,
                Roles::Each(&roles),
                &mut positions,
                &mut previous,
                &mut velocities,
            ),
            Pull::Direct(&[source(0, [0.0; 3], 1.0)]),
            0.0,
            1.0,
            Integrator::Leapfrog,
        );
        assert_eq!(previous.map(|p| p.0.x), [2.0, 2.0]);
        assert_eq!(positions.map(|p| p.0.x), [4.0, 4.0]);
        // G·m/r² = 1/16 at the midpoint (it would be 1/4 at the start).
        assert_eq!(velocities.map(|v| v.0.x), [4.0 - 1.0 / 16.0, 4.0]);
    }

    /// With the leapfrog the sources stand half a drift on, exactly where
    /// the kernel moves each body: a source that is an adopter finds
    /// itself among them and does not pull itself.
    #[test]
    fn the_leapfrogs_sources_stand_where_the_kernel_moves_the_bodies() {
        let ids = [BodyId(3), BodyId(5)];
        let mut positions = [Position(Vec3::new(0.1, 0.2, 0.3)), Position(Vec3::new(10.0, 0.0, 0.0))];
        let mut velocities = [Velocity(Vec3::new(0.7, -0.3, 0.9)), Velocity(Vec3::ZERO)];
        let masses = [Mass(1.0); 2];
        let roles = [GravityRole::SourceAndAdopter, GravityRole::Source];
        let mut sources = Vec::new();
        let table = (&ids[..], &positions[..], &velocities[..], &masses[..], Some(&roles[..]));
        collect_sources(std::iter::once(table), 1.0, Integrator::Leapfrog, 0.3, &mut sources);
        let mut previous = [PreviousPosition::default(); 2];
        let start = velocities[0].0;
        gravity_kernel(
            (
                &ids,
                Roles::Each(&roles),
                &mut positions,
                &mut previous,
                &mut velocities,
            ),
            Pull::Direct(&sources),
            0.0,
            0.3,
            Integrator::Leapfrog,
        );
        assert_eq!(sources[0].position, positions[0].0.as_dvec3());
        assert_eq!(sources[1].position, positions[1].0.as_dvec3());
        // Only the second source pulls the first, at the midpoint.
        let other = Pull::Direct(&sources[1..]).at(BodyId(3), positions[0].0, 0.0);
        assert!(other.x > 0.0);
        assert_eq!(velocities[0].0, start + other * 0.3);
    }

    /// The kick looks each body's source up after the previous body's: in
    /// id order, shuffled, and with adopters that are no source among
    /// them, every body gets the pull `at` gives it on its own.
    #[test]
    fn the_kick_finds_each_bodys_pull_in_any_order() {
        use crate::execution::ExecutionMode;
        let execution = Execution::new(ExecutionMode::Sequential, 1).unwrap();
        let mut rng = crate::maths::Rng::new(8);
        // Sources have even ids; odd ids are adopters only.
        let sources: Vec<GravitySource> = (0..600u64)
            .map(|i| source(2 * i, [0; 3].map(|_| rng.symmetric(100.0)), 1.0))
            .collect();
        let mut scratch = PullScratch::default();
        let tree = GravityMethod::Tree { theta: 0.5 };
        let (pull, _) = prepare_pull(tree, &sources, 900, 1.0, &execution, &mut scratch);
        let mut bodies: Vec<(BodyId, Vec3, GravityRole)> = sources
            .iter()
            .map(|s| (s.id, s.position.as_vec3(), GravityRole::SourceAndAdopter))
            .chain((0..300u64).map(|i| {
                let p = Vec3::new(rng.symmetric(100.0) as f32, 1.0, 2.0);
                (BodyId(2 * i + 1), p, GravityRole::Adopter)
            }))
            .collect();
        for order in 0..3 {
            match order {
                0 => bodies.sort_by_key(|b| b.0),
                1 => bodies.reverse(),
                _ => bodies.sort_by_key(|b| (b.0.0 * 7919) % 1201),
            }
            let ids: Vec<BodyId> = bodies.iter().map(|b| b.0).collect();
            let mut positions: Vec<Position> = bodies.iter().map(|b| Position(b.1)).collect();
            let roles: Vec<GravityRole> = bodies.iter().map(|b| b.2).collect();
            let mut previous = vec![PreviousPosition::default(); bodies.len()];
            let mut velocities = vec![Velocity(Vec3::ZERO); bodies.len()];
            let columns = (
                &ids[..],
                Roles::Each(&roles[..]),
                &mut positions[..],
                &mut previous[..],
                &mut velocities[..],
            );
            gravity_kernel(columns, pull, 1.0, 1.0, Integrator::SemiImplicitEuler);
            for ((id, p, _), v) in bodies.iter().zip(&velocities) {
                assert_eq!(v.0, pull.at(*id, *p, 1.0), "order {order}, body {id:?}");
                assert_ne!(v.0, Vec3::ZERO);
            }
        }
    }

    /// `Auto` sums a few sources directly, exactly as `Direct` does, and
    /// from [`AUTO_TREE_FROM`](crate::resources::AUTO_TREE_FROM) on through
    /// the tree, exactly as `Tree(0.5)` does.
    #[test]
    fn auto_pulls_as_direct_below_the_count_and_as_the_tree_from_it() {
        use crate::execution::ExecutionMode;
        use crate::resources::AUTO_TREE_FROM;
        let execution = Execution::new(ExecutionMode::Sequential, 1).unwrap();
        let cloud = |count: usize| -> Vec<GravitySource> {
            let mut rng = crate::maths::Rng::new(5);
            (0..count as u64)
                .map(|i| source(i, [0; 3].map(|_| rng.symmetric(100.0)), 1.0))
                .collect()
        };
        // The method the pull used, and every source's pull.
        let pulls = |method: GravityMethod, sources: &[GravitySource]| -> (GravityMethod, Vec<Vec3>) {
            let mut scratch = PullScratch::default();
            let (pull, _) = prepare_pull(method, sources, sources.len(), 1.0, &execution, &mut scratch);
            (
                pull.method(),
                sources
                    .iter()
                    .map(|s| pull.at(s.id, s.position.as_vec3(), 1.0))
                    .collect(),
            )
        };
        let tree = GravityMethod::Tree { theta: 0.5 };
        let few = cloud(AUTO_TREE_FROM - 1);
        let (used, auto) = pulls(GravityMethod::Auto, &few);
        assert_eq!(used, GravityMethod::Direct);
        assert_eq!(auto, pulls(GravityMethod::Direct, &few).1);
        let many = cloud(AUTO_TREE_FROM);
        let (used, auto) = pulls(GravityMethod::Auto, &many);
        assert_eq!(used, tree);
        assert_eq!(auto, pulls(tree, &many).1);
    }
}
