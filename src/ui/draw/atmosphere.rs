//! The atmosphere's rim: a translucent ring around the Earth's silhouette,
//! turned to face the camera every frame, whose glow peaks at the limb and
//! fades on the night side (`atmosphere.wgsl`). A ring costs only the rim's
//! pixels; a shell around the planet would shade its whole disc a second
//! time (measured: the default scene's frame time under software rendering).

use bevy::asset::{RenderAssetUsages, load_internal_asset, uuid_handle};
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;
use bevy::render::render_resource::AsBindGroup;
use bevy::shader::ShaderRef;
use bevy::transform::TransformSystems;

use super::backdrop::sun_direction;
use crate::ui::view::MainCamera;

const SHADER: Handle<Shader> = uuid_handle!("9d3a41c2-6b1e-4f0a-8c55-2e7b9a1f4d60");

/// Inner and outer radius of the ring, in silhouette radii.
pub const RING_RADII: (f32, f32) = (0.93, 1.07);
/// Segments around the ring.
const RING_SEGMENTS: u32 = 128;

/// The atmosphere's material: a colour and the sun's direction.
#[derive(Asset, TypePath, AsBindGroup, Debug, Clone)]
pub struct AtmosphereMaterial {
    /// Linear RGB of the glow; alpha is its strength at the limb.
    #[uniform(0)]
    pub color: LinearRgba,
    /// Direction towards the sun, w unused.
    #[uniform(0)]
    pub sun: Vec4,
}

impl Default for AtmosphereMaterial {
    fn default() -> Self {
        Self {
            color: LinearRgba::new(0.35, 0.6, 1.0, 0.9),
            sun: sun_direction().extend(0.0),
        }
    }
}

impl Material for AtmosphereMaterial {
    fn fragment_shader() -> ShaderRef {
        SHADER.into()
    }

    fn alpha_mode(&self) -> AlphaMode {
        AlphaMode::Blend
    }
}

/// The ring of a planet's atmosphere: a child of the planet's sphere.
#[derive(Component, Debug)]
pub struct AtmosphereVisual;

/// Registers the atmosphere's shader and material, and turns the rings to
/// the camera.
pub struct AtmospherePlugin;

impl Plugin for AtmospherePlugin {
    fn build(&self, app: &mut App) {
        load_internal_asset!(app, SHADER, "atmosphere.wgsl", Shader::from_wgsl);
        app.add_plugins(MaterialPlugin::<AtmosphereMaterial>::default())
            .add_systems(PostUpdate, face_camera.before(TransformSystems::Propagate));
    }
}

/// A flat ring in the x–y plane between [`RING_RADII`]: normals point
/// outwards in the plane, `uv.x` is the radius.
pub fn ring_mesh() -> Mesh {
    let (inner, outer) = RING_RADII;
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for i in 0..=RING_SEGMENTS {
        let angle = i as f32 / RING_SEGMENTS as f32 * std::f32::consts::TAU;
        let radial = Vec3::new(angle.cos(), angle.sin(), 0.0);
        for r in [inner, outer] {
            positions.push((radial * r).to_array());
            normals.push(radial.to_array());
            uvs.push([r, 0.0]);
        }
    }
    let indices: Vec<u32> = (0..RING_SEGMENTS)
        .flat_map(|i| {
            let k = 2 * i;
            [k, k + 1, k + 3, k, k + 3, k + 2]
        })
        .collect();
    Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::RENDER_WORLD)
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
        .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs)
        .with_inserted_indices(Indices::U32(indices))
}

/// Where a ring sits, in its planet's frame (a unit sphere): facing the
/// camera at `distance` planet radii along `toward`, in the plane of the
/// circle where the view grazes the sphere, sized to that circle. `None`
/// when the camera is inside the planet.
pub fn ring_transform(toward: Vec3, distance: f32) -> Option<Transform> {
    // (NaN too: the camera exactly at the center.)
    if distance.partial_cmp(&1.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let inverse = 1.0 / distance;
    Some(Transform {
        translation: toward * inverse,
        rotation: Quat::from_rotation_arc(Vec3::Z, toward),
        scale: Vec3::splat((1.0 - inverse * inverse).sqrt()),
    })
}

fn face_camera(
    camera: Query<&Transform, (With<MainCamera>, Without<AtmosphereVisual>)>,
    planets: Query<&Transform, (Without<AtmosphereVisual>, Without<MainCamera>)>,
    mut rings: Query<(&ChildOf, &mut Transform, &mut Visibility), With<AtmosphereVisual>>,
) {
    let Ok(camera) = camera.single() else {
        return;
    };
    for (parent, mut transform, mut visibility) in &mut rings {
        let Ok(planet) = planets.get(parent.parent()) else {
            continue;
        };
        // The camera's offset in the planet's own (turned) frame.
        let offset = planet.rotation.inverse() * (camera.translation - planet.translation);
        let radius = planet.scale.x.max(f32::MIN_POSITIVE);
        match offset
            .try_normalize()
            .and_then(|toward| ring_transform(toward, offset.length() / radius))
        {
            Some(placed) => {
                *transform = placed;
                visibility.set_if_neq(Visibility::Inherited);
            }
            None => {
                visibility.set_if_neq(Visibility::Hidden);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ring_lies_on_the_silhouette_circle() {
        let toward = Vec3::new(1.0, 2.0, -0.5).normalize();
        let t = ring_transform(toward, 3.0).unwrap();
        // A point on the ring's limb (radius 1 in its own frame) is on the
        // unit sphere, and the line from the camera to it grazes the sphere.
        let limb = t.transform_point(Vec3::X);
        assert!((limb.length() - 1.0).abs() < 1e-5, "{limb}");
        let camera = toward * 3.0;
        assert!((camera - limb).dot(limb).abs() < 1e-5, "tangent");
        assert!(
            t.rotation.mul_vec3(Vec3::Z).abs_diff_eq(toward, 1e-5),
            "faces the camera"
        );
        assert!(ring_transform(toward, 0.5).is_none(), "inside the planet");
    }
}
