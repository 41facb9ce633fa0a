//! The interactive window (feature `gui`): renderer, cameras, egui panel and
//! HUD. Not built yet — `kessler run` says so and runs headless instead.
