//! [`MainCamera`], shared by the cameras and picking.

use bevy::prelude::*;

/// The one 3D camera.
#[derive(Component, Debug)]
pub struct MainCamera;
