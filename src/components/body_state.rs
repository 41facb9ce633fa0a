//! A body as plain data, and the bundle that spawns it.

use bevy::ecs::query::QueryData;
use bevy::prelude::*;

use super::{
    Absorbs, BodyId, GravityRole, HalfExtents, Mass, NonInteracting, Position, PreviousPosition, Spherical, Velocity,
};

/// Everything a body is made of, as query data: its position and velocity
/// writable (the collision response moves bodies through it); read-only,
/// [`BodyStateQuery`], it is what a whole [`BodyState`] is read from.
#[derive(QueryData)]
#[query_data(mutable)]
pub struct BodyData {
    /// The body's id.
    pub id: &'static BodyId,
    /// Where it is.
    pub position: &'static mut Position,
    /// Where it was before the last drift.
    pub previous: &'static PreviousPosition,
    /// How it moves.
    pub velocity: &'static mut Velocity,
    /// Its mass.
    pub mass: &'static Mass,
    /// Its box's half extents.
    pub half_extents: &'static HalfExtents,
    /// Its gravity role, where it is not an adopter.
    pub role: Option<&'static GravityRole>,
    /// Whether collisions never move it (`interacts: false`).
    pub non_interacting: Has<NonInteracting>,
    /// Whether it is a ball.
    pub spherical: Has<Spherical>,
    /// Whether it absorbs what touches it.
    pub absorbs: Has<Absorbs>,
}

/// The query data a whole [`BodyState`] is read from: [`BodyData`],
/// read-only.
pub type BodyStateQuery = BodyDataReadOnly;

/// Everything a body is made of but its role where it is not an adopter
/// ([`spawn_with_roles`] spawns it with the bundle) and its markers
/// ([`insert_markers`]), in one bundle.
#[derive(Bundle, Clone, Debug)]
#[expect(missing_docs, reason = "each field is its component, documented there")]
pub struct BodyBundle {
    pub id: BodyId,
    pub position: Position,
    pub previous_position: PreviousPosition,
    pub velocity: Velocity,
    pub mass: Mass,
    pub half_extents: HalfExtents,
}

/// A body's state as plain data: what scenarios create, fragments are born
/// as, and dumps print.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    /// See [`BodyId`].
    pub id: BodyId,
    /// See [`Position`].
    pub position: Vec3,
    /// See [`Velocity`].
    pub velocity: Vec3,
    /// See [`Mass`].
    pub mass: f32,
    /// See [`HalfExtents`].
    pub half_extents: Vec3,
    /// See [`GravityRole`].
    pub role: GravityRole,
    /// False for a non-interacting body (see [`NonInteracting`]).
    pub interacts: bool,
    /// See [`PreviousPosition`]; a new body's is its position.
    pub previous: Vec3,
    /// True for a ball (see [`Spherical`]), false for a box.
    pub spherical: bool,
    /// True for a body that absorbs what touches it (see [`Absorbs`]).
    pub absorbs: bool,
}

impl BodyState {
    /// Whether its position, previous position, velocity, mass and size
    /// are all finite.
    pub fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.previous.is_finite()
            && self.velocity.is_finite()
            && self.half_extents.is_finite()
            && self.mass.is_finite()
    }

    /// Fails, naming the first body (in the order given) that is not
    /// [finite](Self::is_finite): what every writer of bodies (dump,
    /// snapshot) checks before writing anything.
    pub fn check_all_finite(bodies: &[Self]) -> std::io::Result<()> {
        match bodies.iter().find(|b| !b.is_finite()) {
            None => Ok(()),
            Some(b) => Err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("body {} has a non-finite state; nothing was written", b.id.0),
            )),
        }
    }

    /// A box that starts where it is (its previous position is its
    /// position): what scenarios and shatters create.
    pub fn new_box(
        id: BodyId,
        position: Vec3,
        velocity: Vec3,
        mass: f32,
        half_extents: Vec3,
        role: GravityRole,
        interacts: bool,
    ) -> Self {
        Self {
            id,
            position,
            velocity,
            mass,
            half_extents,
            role,
            interacts,
            previous: position,
            spherical: false,
            absorbs: false,
        }
    }

    /// The states of `bodies` (a query's items), sorted by id: the order a
    /// state's files and its hash take.
    pub fn sorted_by_id<'w, 's>(bodies: impl Iterator<Item = BodyDataReadOnlyItem<'w, 's>>) -> Vec<Self> {
        let mut states: Vec<Self> = bodies.map(Self::from_components).collect();
        states.sort_unstable_by_key(|b| b.id);
        states
    }

    /// Every body of `world`, sorted by id.
    pub fn all_in(world: &mut World) -> Vec<Self> {
        let mut query = world.query::<BodyStateQuery>();
        Self::sorted_by_id(query.iter(world))
    }

    /// A body's state from its components.
    pub fn from_components(body: BodyDataReadOnlyItem<'_, '_>) -> Self {
        Self {
            id: *body.id,
            position: body.position.0,
            velocity: body.velocity.0,
            mass: body.mass.0,
            half_extents: body.half_extents.0,
            role: GravityRole::of(body.role),
            interacts: !body.non_interacting,
            previous: body.previous.0,
            spherical: body.spherical,
            absorbs: body.absorbs,
        }
    }

    /// The bundle that spawns this body (a body that is no adopter also
    /// needs its [`GravityRole`], a non-interacting one [`NonInteracting`], a ball
    /// [`Spherical`], an absorber [`Absorbs`]: [`spawn_states`] adds them).
    pub fn bundle(&self) -> BodyBundle {
        BodyBundle {
            id: self.id,
            position: Position(self.position),
            previous_position: PreviousPosition(self.previous),
            velocity: Velocity(self.velocity),
            mass: Mass(self.mass),
            half_extents: HalfExtents(self.half_extents),
        }
    }

    /// Whether the body needs a marker besides its [`bundle`](Self::bundle)
    /// and its role.
    pub fn has_markers(&self) -> bool {
        !self.interacts || self.spherical || self.absorbs
    }
}

/// Spawns `bodies` into `world`, each with its role where it is no adopter
/// and its markers (a non-interacting body's [`NonInteracting`], a ball's
/// [`Spherical`], an absorber's [`Absorbs`]), in the order given.
pub fn spawn_states(world: &mut World, bodies: &[BodyState]) {
    let entities = spawn_with_roles(world, bodies);
    for (&entity, body) in entities.iter().zip(bodies) {
        insert_markers(world, entity, body);
    }
}

/// Spawns `bodies` without their markers: the adopters in one batch, the
/// others with their [`GravityRole`] in a second, so that no body moves
/// table for its role and each table holds its bodies in the order given.
/// Returns the entities in the order of `bodies`.
pub fn spawn_with_roles(world: &mut World, bodies: &[BodyState]) -> Vec<Entity> {
    let stored = bodies.iter().filter(|b| b.role.is_stored()).count();
    let adopters = Counted {
        items: bodies.iter().filter(|b| !b.role.is_stored()).map(BodyState::bundle),
        left: bodies.len() - stored,
    };
    let adopters: Vec<Entity> = world.spawn_batch(adopters).collect();
    let others = Counted {
        items: bodies
            .iter()
            .filter(|b| b.role.is_stored())
            .map(|b| (b.bundle(), b.role)),
        left: stored,
    };
    let others: Vec<Entity> = world.spawn_batch(others).collect();
    let (mut adopters, mut others) = (adopters.into_iter(), others.into_iter());
    bodies
        .iter()
        .map(|b| {
            if b.role.is_stored() {
                others.next()
            } else {
                adopters.next()
            }
        })
        .collect::<Option<Vec<Entity>>>()
        .expect("one entity spawned for each body")
}

/// Items of which `left` are left: `spawn_batch` makes room and entities
/// for as many as an iterator's upper bound says, which for a filter of the
/// bodies is all of them (40 bytes a body more, measured).
struct Counted<I> {
    items: I,
    left: usize,
}

impl<I: Iterator> Iterator for Counted<I> {
    type Item = I::Item;

    fn next(&mut self) -> Option<I::Item> {
        let item = self.items.next()?;
        self.left = self.left.saturating_sub(1);
        Some(item)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.left, Some(self.left))
    }
}

/// Gives a spawned body its markers: [`NonInteracting`] where it does not
/// interact, [`Spherical`] for a ball, [`Absorbs`] for an absorber (its role
/// comes with the spawn: [`spawn_with_roles`]). Each moves the body to
/// another table, where it is the last row, so that the tables' order
/// depends only on the order of the calls.
pub fn insert_markers(world: &mut World, entity: Entity, body: &BodyState) {
    if !body.has_markers() {
        return;
    }
    let mut entity = world.entity_mut(entity);
    if !body.interacts {
        entity.insert(NonInteracting);
    }
    if body.spherical {
        entity.insert(Spherical);
    }
    if body.absorbs {
        entity.insert(Absorbs);
    }
}
