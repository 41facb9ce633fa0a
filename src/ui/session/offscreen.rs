//! Rendering without a display (`kessler run --offscreen`): the camera
//! draws into an image instead of a window, as Bevy's `headless_renderer`
//! example does, so that a GPU server without an X server runs the same
//! scripted runs, screenshots and films.

use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};

/// The image an offscreen run draws into; its presence means "offscreen".
#[derive(Resource, Clone, Debug)]
pub struct OffscreenTarget(pub Handle<Image>);

/// The picture's size, as the window's.
pub const OFFSCREEN_SIZE: (u32, u32) = (1280, 800);

impl OffscreenTarget {
    /// A new target image of [`OFFSCREEN_SIZE`] in `images`, one a
    /// screenshot can copy from.
    pub fn new(images: &mut Assets<Image>) -> Self {
        let (width, height) = OFFSCREEN_SIZE;
        let mut image = Image::new_target_texture(width, height, TextureFormat::Rgba8UnormSrgb, None);
        image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
        Self(images.add(image))
    }
}

/// The `number`th picture of a film in `dir`: `frame-000001.png`, … (the
/// names ffmpeg's `-i frame-%06d.png` reads in order).
pub fn frame_path(dir: &std::path::Path, number: u64) -> std::path::PathBuf {
    dir.join(format!("{}{number:06}.{}", FRAME_NAMES.0, FRAME_NAMES.1))
}

/// How a film's pictures are named: their prefix and extension.
pub const FRAME_NAMES: (&str, &str) = ("frame-", "png");
