//! The cameras: orbit (bevy_panorbit_camera), free fly, and follow the
//! selected body. The camera key (C) and the panel switch between them.

use bevy::camera::RenderTarget;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::input::mouse::AccumulatedMouseMotion;
use bevy::prelude::*;
use bevy::render::view::NoIndirectDrawing;
use bevy_egui::input::EguiWantsInput;
use bevy_panorbit_camera::{PanOrbitCamera, PanOrbitCameraPlugin};

use super::main_camera::MainCamera;
use super::selection::{Selection, select_on_click};
use crate::components::{BodyId, Position};
use crate::ui::session::{CameraMode, OffscreenTarget, SandboxSettings};
use crate::ui::sets::SandboxSystems;

/// Distance of the camera from the origin at start, before the first scene
/// is framed.
const START_DISTANCE: f32 = 4000.0;

/// The camera and its controls.
pub struct CameraPlugin;

impl Plugin for CameraPlugin {
    fn build(&self, app: &mut App) {
        app.add_plugins(PanOrbitCameraPlugin)
            .add_systems(Startup, spawn_camera)
            .add_systems(
                Update,
                (
                    frame_scene,
                    camera_key,
                    fly_camera,
                    orbit_and_follow.after(select_on_click),
                )
                    .chain()
                    .in_set(SandboxSystems::View),
            );
    }
}

/// Free-fly speed in world units per second (Shift: ten times that).
pub const FLY_SPEED: f32 = 600.0;
/// Radians of turn per pixel of mouse motion.
const LOOK_SENSITIVITY: f32 = 0.003;

/// Spawns the camera looking at the origin.
fn spawn_camera(mut commands: Commands, offscreen: Option<Res<OffscreenTarget>>) {
    let distance = START_DISTANCE;
    let mut camera = commands.spawn((
        Name::new("Camera"),
        MainCamera,
        Camera3d::default(),
        Projection::Perspective(PerspectiveProjection {
            far: 1.0e7,
            near: 0.5,
            ..default()
        }),
        // Colors are final as the shaders write them (no LUT needed).
        Tonemapping::None,
        // The instanced body draw issues direct draws.
        NoIndirectDrawing,
        Transform::from_xyz(0.0, distance * 0.45, distance).looking_at(Vec3::ZERO, Vec3::Y),
        PanOrbitCamera {
            focus: Vec3::ZERO,
            radius: Some(distance * 1.1),
            pitch: Some(0.42),
            yaw: Some(0.55),
            zoom_lower_limit: 1.0,
            ..default()
        },
    ));
    // Offscreen: into the image instead of the window.
    if let Some(OffscreenTarget(image)) = offscreen.as_deref() {
        camera.insert(RenderTarget::Image(image.clone().into()));
    }
}

/// Once, after the first scene is built: backs the orbit camera off far
/// enough to see most bodies (nine in ten, sampled).
fn frame_scene(
    bodies: Query<&Position, With<BodyId>>,
    mut camera: Single<&mut PanOrbitCamera, With<MainCamera>>,
    mut framed: Local<bool>,
) {
    if *framed || bodies.is_empty() {
        return;
    }
    *framed = true;
    let mut radii: Vec<f32> = bodies.iter().step_by(97).map(|p| p.0.length()).collect();
    if radii.is_empty() {
        return;
    }
    radii.sort_by(f32::total_cmp);
    let reach = radii[(radii.len() - 1) * 9 / 10].max(10.0);
    camera.target_radius = reach * 2.6;
    camera.radius = Some(reach * 2.6);
    camera.force_update = true;
}

/// Cycles the camera on C (unless egui has the keyboard).
fn camera_key(keys: Res<ButtonInput<KeyCode>>, egui: Res<EguiWantsInput>, mut settings: ResMut<SandboxSettings>) {
    if keys.just_pressed(KeyCode::KeyC) && !egui.wants_keyboard_input() {
        settings.camera = settings.camera.next();
    }
}

/// Enables the orbit controller outside free fly, and points it at the
/// selected body while following.
fn orbit_and_follow(
    settings: Res<SandboxSettings>,
    selection: Res<Selection>,
    bodies: Query<&Position>,
    mut camera: Single<&mut PanOrbitCamera, With<MainCamera>>,
) {
    let enabled = settings.camera != CameraMode::Fly;
    if camera.enabled != enabled {
        camera.enabled = enabled;
        // Orbit resumes from where it was; force it to redraw.
        camera.force_update = true;
    }
    if settings.camera == CameraMode::Follow
        && let Some(target) = selection.entity.and_then(|e| bodies.get(e).ok())
    {
        camera.target_focus = target.0;
        camera.focus = target.0;
        camera.force_update = true;
    }
}

/// Free flight: WASD forward/left/back/right, Q/E down/up, Shift fast;
/// hold the right mouse button to look around.
fn fly_camera(
    settings: Res<SandboxSettings>,
    keys: Res<ButtonInput<KeyCode>>,
    buttons: Res<ButtonInput<MouseButton>>,
    motion: Res<AccumulatedMouseMotion>,
    egui: Res<EguiWantsInput>,
    time: Res<Time<Real>>,
    mut camera: Single<&mut Transform, With<MainCamera>>,
) {
    if settings.camera != CameraMode::Fly {
        return;
    }
    if buttons.pressed(MouseButton::Right) && !egui.wants_pointer_input() && motion.delta != Vec2::ZERO {
        let (yaw, pitch, _) = camera.rotation.to_euler(EulerRot::YXZ);
        let yaw = yaw - motion.delta.x * LOOK_SENSITIVITY;
        let pitch = (pitch - motion.delta.y * LOOK_SENSITIVITY).clamp(-1.54, 1.54);
        camera.rotation = Quat::from_euler(EulerRot::YXZ, yaw, pitch, 0.0);
    }
    if egui.wants_keyboard_input() {
        return;
    }
    let axes = [
        (KeyCode::KeyW, camera.forward().as_vec3()),
        (KeyCode::KeyS, camera.back().as_vec3()),
        (KeyCode::KeyA, camera.left().as_vec3()),
        (KeyCode::KeyD, camera.right().as_vec3()),
        (KeyCode::KeyE, Vec3::Y),
        (KeyCode::KeyQ, Vec3::NEG_Y),
    ];
    let direction: Vec3 = axes.iter().filter(|(k, _)| keys.pressed(*k)).map(|(_, d)| *d).sum();
    if direction != Vec3::ZERO {
        let fast = keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]);
        let speed = if fast { FLY_SPEED * 10.0 } else { FLY_SPEED };
        camera.translation += direction.normalize() * speed * time.delta_secs();
    }
}
