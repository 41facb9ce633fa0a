//! Swept detection's contacts in time order (docs/design.md, "Contacts in
//! time order"): every contact of an update, chains included. Each pair
//! the broad phase found gets its first touch on the bodies' paths; the
//! earliest touch acts first; a body whose path it changes is tested again
//! from that moment against its pairs, and — where its new path leaves the
//! box the broad phase swept for it — against every body that path
//! reaches; until no contact is left. A pair that shatters leaves its
//! fragments where it met, and they take part from then on as any body
//! does. A Newton's cradle ends as the analytic sequence of elastic
//! collisions does.
//!
//! Contacts are taken in the order of their time, ties in the order their
//! pairs were found (the broad phase's pairs in id order, then pairs found
//! along the way in the order found, each search's bodies in id order), so
//! the result does not depend on threads or on how bodies are stored.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;

use super::contact::Motion;
use super::escaped::Escaped;
use super::outcomes::ShatterBudget;
use super::swept::{Contact, Meeting, SweptBody, first_contact, respond_swept};
use crate::components::BodyState;
use crate::execution::StageExecution;
use crate::physics::Aabb;
use crate::systems::shatter::PendingShatters;
use crate::systems::sort::boxes::swept_box;
use crate::systems::sweep::Pair;

/// Most contacts that change a path (bounces and separations) per body
/// taking part, within one update: past it the rest of the update's
/// contacts wait for the next update, a bounce's bodies staying where
/// they touch with their new velocities (`Contacts::hold`), and are counted
/// ([`Resolved::deferred`]; absorptions, which change no path, go on).
/// Elastic chains end after a few contacts a body; a body caught between
/// two walls takes one contact for each time it crosses the gap
/// (tests/swept.rs). Never reached in the shipped scenes (the timeline's
/// `deferred` column; docs/benchmarks.md).
pub const MAX_CONTACTS_PER_BODY: usize = 64;

/// Where the contacts find bodies beyond the broad phase's pairs.
pub(super) trait Neighbourhood {
    /// The state of `entity` as the response found it.
    fn state(&self, entity: Entity) -> Option<BodyState>;
    /// Appends to `out` every body whose box in this update's broad phase
    /// overlaps `region` (in any order; one may come more than once).
    fn reached(&self, region: &Aabb, out: &mut Vec<Entity>);
    /// Calls `f` with every cell of the broad phase's grid that `region`
    /// covers.
    fn cells(&self, region: &Aabb, f: &mut dyn FnMut(u32));
    /// The grid's finest cells per unit length (0: no grid).
    fn cells_per_unit(&self) -> f32;
}

/// What the contacts of an update did.
#[derive(Debug, Default)]
pub(super) struct Resolved {
    /// Bodies absorbed (re-entries), with their state at the touch, in
    /// time order (no entity: a fragment made this update).
    pub reentries: Vec<(Option<Entity>, BodyState)>,
    /// Every body whose motion changed: where it ends the update and its
    /// velocity.
    pub motions: Vec<(Entity, Motion)>,
    /// Pairs that shattered, in time order, and their fragments where
    /// they end the update.
    pub shatters: PendingShatters,
    /// Contacts that bounced or separated a pair.
    pub responses: usize,
    /// Shatters the budget refused (the pair bounced).
    pub refused: usize,
    /// Contacts left for the next update past [`MAX_CONTACTS_PER_BODY`]
    /// (`Contacts::hold`).
    pub deferred: usize,
}

/// What a shatter needs besides the pair: the impact speed from which
/// interacting bodies shatter, the time step and what a shatter may make.
pub(super) struct Rules<'a> {
    /// Impact speed `|v1 − v2|` from which a pair shatters.
    pub threshold: f32,
    /// The time step.
    pub dt: f32,
    /// The fragment floor, the body budget and the ids.
    pub budget: ShatterBudget<'a>,
}

/// A body taking part in the update's contacts.
struct Tracked {
    /// None for a fragment made this update.
    entity: Option<Entity>,
    state: BodyState,
    /// Its path through the rest of the update.
    path: SweptBody,
    /// Bumped whenever the path changes: touches found on an older path
    /// are stale.
    version: u32,
    /// Shattered or absorbed: in no further contact.
    gone: bool,
    /// Pushed apart once this update: not again (bodies piled on one
    /// another would otherwise push each other back and forth).
    separated: bool,
    /// Whether its motion changed.
    changed: bool,
    /// The box the broad phase swept for it.
    broad: Aabb,
    /// The box its current path sweeps.
    reach: Aabb,
    /// The last search (for what a new path reaches) that found it.
    seen: u32,
    /// The pairs it is in (indices into the pair list).
    pairs: Vec<u32>,
}

/// A touch found: when, which pair, on which paths.
struct Touch {
    meeting: Meeting,
    pair: u32,
    versions: [u32; 2],
}

impl Touch {
    fn key(&self) -> (f64, u32) {
        (self.meeting.time(), self.pair)
    }
}

impl PartialEq for Touch {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Touch {}

impl PartialOrd for Touch {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Touch {
    /// Reversed, so that the heap gives the earliest touch first (ties:
    /// the pair found first).
    fn cmp(&self, other: &Self) -> Ordering {
        let ((s, p), (t, q)) = (self.key(), other.key());
        t.total_cmp(&s).then(q.cmp(&p))
    }
}

/// The contacts' working state.
struct Contacts<'n, N: Neighbourhood> {
    world: &'n N,
    bodies: Vec<Tracked>,
    index: HashMap<Entity, u32>,
    pairs: Vec<[u32; 2]>,
    known: HashSet<[u32; 2]>,
    touches: BinaryHeap<Touch>,
    /// Bodies whose path left their broad-phase box (which the grid knows
    /// them by), filed where their paths go (an entry may be stale: its
    /// body's path has moved on).
    escaped: Escaped,
    /// Searches made so far (see [`Tracked::seen`]).
    stamp: u32,
}

impl<N: Neighbourhood> Contacts<'_, N> {
    /// The index of `entity` among the tracked bodies, tracking it (on the
    /// path the drift gave it) if it is not yet.
    fn track(&mut self, entity: Entity) -> Option<u32> {
        if let Some(&i) = self.index.get(&entity) {
            return Some(i);
        }
        let state = self.world.state(entity)?;
        let broad = swept_box(state.previous, state.position, state.half_extents);
        let i = self.push(Some(entity), state, SweptBody::from(&(&state).into()), broad);
        self.index.insert(entity, i);
        Some(i)
    }

    /// Adds a tracked body on `path`, within `broad` as the broad phase
    /// knows it; its index.
    fn push(&mut self, entity: Option<Entity>, state: BodyState, path: SweptBody, broad: Aabb) -> u32 {
        let i = self.bodies.len() as u32;
        self.bodies.push(Tracked {
            entity,
            state,
            path,
            version: 0,
            gone: false,
            separated: false,
            changed: false,
            broad,
            reach: broad,
            seen: 0,
            pairs: Vec::new(),
        });
        i
    }

    /// Adds the pair `i`, `j` unless known or neither interacts; its index.
    fn add_pair(&mut self, i: u32, j: u32) -> Option<u32> {
        let (a, b) = (&self.bodies[i as usize], &self.bodies[j as usize]);
        if i == j || (!a.state.interacts && !b.state.interacts) || !self.known.insert([i.min(j), i.max(j)]) {
            return None;
        }
        let pair = self.pairs.len() as u32;
        self.pairs.push([i, j]);
        self.bodies[i as usize].pairs.push(pair);
        self.bodies[j as usize].pairs.push(pair);
        Some(pair)
    }

    /// Tests `pair` on the current paths; a touch found waits its turn.
    fn test(&mut self, pair: u32) {
        let [i, j] = self.pairs[pair as usize];
        let (a, b) = (&self.bodies[i as usize], &self.bodies[j as usize]);
        if a.gone || b.gone {
            return;
        }
        if let Some(meeting) = first_contact(&a.path, &b.path) {
            self.touches.push(Touch {
                meeting,
                pair,
                versions: [a.version, b.version],
            });
        }
    }

    /// Body `i` took a new path: tested again against its pairs and
    /// against every body the path reaches beyond what is known.
    fn moved(&mut self, i: u32, path: SweptBody, separated: bool) {
        let body = &mut self.bodies[i as usize];
        body.path = path;
        body.version += 1;
        body.changed = true;
        body.separated |= separated;
        let region = path.swept_box();
        body.reach = region;
        // What the new path may meet beyond its pairs, each tracked body
        // once (stamped with this search) and only where its own path's
        // box overlaps the new one's.
        self.stamp += 1;
        let stamp = self.stamp;
        self.bodies[i as usize].seen = stamp;
        // Within the box the broad phase swept for it, its partners are
        // known: every body whose box there overlaps it is in its pairs.
        // Beyond, only a search through the grid finds them all (the box
        // around its earlier paths is no bound: a path that turned twice
        // passes places none of them covered; tests/swept.rs).
        let covered = within(&region, &self.bodies[i as usize].broad);
        let mut found = Vec::new();
        let bodies = &mut self.bodies;
        let mut take = |m: u32, found: &mut Vec<u32>| {
            let other = &mut bodies[m as usize];
            if other.seen != stamp && !other.gone && other.reach.overlaps(&region) {
                other.seen = stamp;
                found.push(m);
            }
        };
        // Bodies that escaped their broad-phase boxes, which the grid knows
        // only by those: filed where their paths go.
        self.escaped
            .near(&region, &|r, f| self.world.cells(r, f), &mut |m| take(m, &mut found));
        if !covered {
            let mut reached = Vec::new();
            self.world.reached(&region, &mut reached);
            let mut new = Vec::new();
            for entity in reached {
                match self.index.get(&entity) {
                    Some(&m) => take(m, &mut found),
                    None => new.extend(
                        self.world
                            .state(entity)
                            .filter(|s| swept_box(s.previous, s.position, s.half_extents).overlaps(&region))
                            .map(|s| (s.id, entity)),
                    ),
                }
            }
            new.sort_unstable();
            new.dedup();
            found.sort_unstable();
            for (_, entity) in new {
                if let Some(m) = self.track(entity) {
                    found.push(m);
                }
            }
            self.escaped.file(i, &region, &|r, f| self.world.cells(r, f));
        } else {
            found.sort_unstable();
        }
        for m in found {
            self.add_pair(i, m);
        }
        for k in 0..self.bodies[i as usize].pairs.len() {
            let pair = self.bodies[i as usize].pairs[k];
            self.test(pair);
        }
    }

    /// A fragment made at share `s` of an update of `dt`: from where it is
    /// made it moves on along its velocity, tested as a body whose path
    /// left the broad phase's boxes (the grid does not know it).
    fn made(&mut self, fragment: BodyState, s: f64, dt: f32) {
        let (position, velocity) = (fragment.position.as_dvec3(), fragment.velocity.as_dvec3());
        let path = SweptBody::from(&(&fragment).into()).moved_on(s, position, velocity, dt);
        let i = self.push(None, fragment, path, NOWHERE);
        self.moved(i, path, false);
    }

    /// The state of body `i` at share `s` of the update, moving as it does
    /// then.
    fn state_at(&self, i: u32, s: f64) -> BodyState {
        let body = &self.bodies[i as usize];
        BodyState {
            position: body.path.at(s).as_vec3(),
            velocity: body.path.velocity.as_vec3(),
            ..body.state
        }
    }
}

/// The box of no points: within it lies no path, and its union with a box
/// is that box.
const NOWHERE: Aabb = Aabb {
    min: Vec3::INFINITY,
    max: Vec3::NEG_INFINITY,
};

/// Whether `inner` lies within `outer`.
fn within(inner: &Aabb, outer: &Aabb) -> bool {
    inner.min.cmpge(outer.min).all() && inner.max.cmple(outer.max).all()
}

/// Every contact of the update in time order, starting from the broad
/// phase's `pairs` (first touches found as `stage` splits them), until no
/// contact is left; past [`MAX_CONTACTS_PER_BODY`] path changes, held
/// (`Contacts::hold`) instead of acted on, absorptions excepted.
pub(super) fn resolve_in_time_order<N: Neighbourhood>(
    pairs: &[Pair],
    world: &N,
    stage: StageExecution<'_>,
    mut rules: Rules<'_>,
) -> Resolved {
    let mut contacts = Contacts::of_pairs(pairs, world, stage);
    let mut resolved = Resolved::default();
    let first_id = rules.budget.next_id();
    // The bound counts the bodies the update started with and the
    // fragments it made.
    let tracked = contacts.bodies.len();
    let mut changes = 0;
    while let Some(touch) = contacts.touches.pop() {
        if rules.budget.outgrown().is_some() {
            // A shatter would have outgrown the memory: the run stops.
            break;
        }
        let [i, j] = contacts.pairs[touch.pair as usize];
        let (a, b) = (&contacts.bodies[i as usize], &contacts.bodies[j as usize]);
        if a.gone || b.gone || [a.version, b.version] != touch.versions {
            continue;
        }
        let absorbing = a.state.absorbs || b.state.absorbs;
        if !absorbing && changes >= MAX_CONTACTS_PER_BODY * (tracked + rules.budget.ids_since(first_id) as usize) {
            resolved.deferred += usize::from(contacts.hold([i, j], touch.meeting, rules.dt));
            continue;
        }
        changes += contacts.act([i, j], touch.meeting, &mut rules, &mut resolved);
    }
    for body in contacts.bodies.iter().filter(|b| !b.gone) {
        let (position, velocity) = (body.path.end.as_vec3(), body.path.velocity.as_vec3());
        match body.entity {
            Some(entity) if body.changed => resolved.motions.push((entity, Motion { position, velocity })),
            Some(_) => {}
            // Made this update: moved on from where it was made.
            None => resolved.shatters.fragments.push(BodyState {
                previous: body.state.position,
                position,
                velocity,
                ..body.state
            }),
        }
    }
    resolved.shatters.ids = rules.budget.ids_since(first_id);
    resolved.shatters.outgrown = rules.budget.outgrown();
    resolved
}

impl<'n, N: Neighbourhood> Contacts<'n, N> {
    /// The bodies of the broad phase's `pairs`, and each pair's first
    /// touch on the drift's paths (found as `stage` splits the pairs).
    fn of_pairs(pairs: &[Pair], world: &'n N, stage: StageExecution<'_>) -> Self {
        let mut contacts = Self {
            world,
            bodies: Vec::new(),
            index: HashMap::default(),
            pairs: Vec::new(),
            known: HashSet::default(),
            touches: BinaryHeap::new(),
            escaped: Escaped::new(world.cells_per_unit()),
            stamp: 0,
        };
        for pair in pairs {
            if let (Some(i), Some(j)) = (contacts.track(pair.entity_a), contacts.track(pair.entity_b)) {
                contacts.add_pair(i, j);
            }
        }
        let bodies = &contacts.bodies;
        let first: Vec<Option<Meeting>> = stage
            .map_chunks(contacts.pairs.as_slice(), |chunk: &[[u32; 2]]| {
                chunk
                    .iter()
                    .map(|&[i, j]| first_contact(&bodies[i as usize].path, &bodies[j as usize].path))
                    .collect::<Vec<_>>()
            })
            .concat();
        contacts.touches = first
            .into_iter()
            .enumerate()
            .filter_map(|(pair, meeting)| {
                Some(Touch {
                    meeting: meeting?,
                    pair: pair as u32,
                    versions: [0, 0],
                })
            })
            .collect();
        contacts
    }

    /// Past [`MAX_CONTACTS_PER_BODY`]: the contact of bodies `i` and `j`
    /// at `meeting`, whose touch is current, if it would act. A bounce
    /// still exchanges the velocities, but each body it changes stays where
    /// they touch for the rest of the update, its new velocity moving it
    /// on from there in the next (so it leaves the other, as it would have
    /// within this update); the rest of its motion in this update is
    /// dropped. A pair that overlapped already is left as it is, to be
    /// pushed apart in the next update. True when the contact would have
    /// acted (a deferred contact). Each bounce held here stops a body that
    /// was moving (one of two already still gives nothing more): the
    /// update's contacts end.
    fn hold(&mut self, [i, j]: [u32; 2], meeting: Meeting, dt: f32) -> bool {
        let (a, b) = (&self.bodies[i as usize], &self.bodies[j as usize]);
        let still = |path: &SweptBody| path.start == path.end;
        let (pa, pb) = match respond_swept(&a.path, &b.path, meeting, f32::INFINITY, dt) {
            Contact::Bounce(..) if still(&a.path) && still(&b.path) => return true,
            Contact::Bounce(pa, pb) => (pa, pb),
            Contact::Separate(..) => return true,
            Contact::Ignore | Contact::Shatter => return false,
        };
        for (k, bounced) in [(i, pa), (j, pb)] {
            // From where they touch, on for none of the update.
            if let Some(bounced) = bounced {
                self.moved(
                    k,
                    SweptBody {
                        end: bounced.start,
                        ..bounced
                    },
                    false,
                );
            }
        }
        true
    }

    /// The contact of bodies `i` and `j` at `meeting`, whose touch is
    /// current: an absorber takes its partner; else a shatter (if the
    /// budget allows it), a bounce or a separation. Returns how many paths
    /// it changed.
    fn act(&mut self, [i, j]: [u32; 2], meeting: Meeting, rules: &mut Rules<'_>, resolved: &mut Resolved) -> usize {
        let s = meeting.time();
        let (a, b) = (&self.bodies[i as usize], &self.bodies[j as usize]);
        let (path_a, path_b) = (a.path, b.path);
        let separated_before = [a.separated, b.separated];
        // A fragment made this update shatters no more in it (else a
        // floorless cascade could shatter without end within one update).
        let made_now = a.entity.is_none() || b.entity.is_none();
        if a.state.absorbs || b.state.absorbs {
            for (k, other) in [(i, j), (j, i)] {
                let (body, by) = (&self.bodies[k as usize], &self.bodies[other as usize]);
                if by.state.absorbs && body.state.interacts && !body.gone {
                    resolved.reentries.push((body.entity, self.state_at(k, s)));
                    self.bodies[k as usize].gone = true;
                    rules.budget.absorbed();
                }
            }
            return 0;
        }
        let mut contact = respond_swept(&path_a, &path_b, meeting, rules.threshold, rules.dt);
        if contact == Contact::Shatter {
            let states = [self.state_at(i, s), self.state_at(j, s)];
            if !made_now && let Some(made) = rules.budget.shatter(&states[0], &states[1]) {
                resolved.shatters.pairs += 1;
                for k in [i, j] {
                    let body = &mut self.bodies[k as usize];
                    body.gone = true;
                    resolved.shatters.shattered.extend(body.entity);
                }
                for fragment in made {
                    self.made(fragment, s, rules.dt);
                }
                return 0;
            }
            if rules.budget.outgrown().is_some() {
                return 0;
            }
            resolved.refused += 1;
            contact = respond_swept(&path_a, &path_b, meeting, f32::INFINITY, rules.dt);
        }
        let (paths, separated) = match contact {
            Contact::Bounce(pa, pb) => ([pa, pb], false),
            Contact::Separate(pa, pb)
                if !(pa.is_some() && separated_before[0] || pb.is_some() && separated_before[1]) =>
            {
                ([pa, pb], true)
            }
            Contact::Separate(..) | Contact::Ignore | Contact::Shatter => return 0,
        };
        resolved.responses += 1;
        let mut changed = 0;
        for (k, path) in [i, j].into_iter().zip(paths) {
            if let Some(path) = path {
                changed += 1;
                self.moved(k, path, separated);
            }
        }
        changed
    }
}
