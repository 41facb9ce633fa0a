//! The Earth's and the Moon's surfaces, generated at start from seeded
//! noise (no image files, no network): equirectangular RGBA pictures that
//! wrap a UV sphere. The Earth has oceans (30 % land), continents coloured
//! by latitude and moisture, ice caps and clouds; the Moon is grey with dark
//! maria and bright-rimmed craters.
//!
//! Noise is sampled on the unit sphere in 3-D, so the pictures have no seam
//! at the date line and no pinch at the poles.

use bevy::math::Vec3;
use rayon::prelude::*;

use crate::maths::Rng;

/// Share of the Earth's surface that is land.
pub const LAND_SHARE: f32 = 0.3;

/// An sRGB picture, 4 bytes per pixel, rows from the north pole down.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    /// Pixels per row (longitude).
    pub width: u32,
    /// Rows (latitude).
    pub height: u32,
    /// RGBA bytes, row by row.
    pub rgba: Vec<u8>,
}

/// Value noise on the integer lattice, smoothly interpolated, in `[0, 1]`.
fn value_noise(p: Vec3, seed: u32) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let smooth = f * f * (Vec3::splat(3.0) - 2.0 * f);
    let (x, y, z) = (cell.x as i32, cell.y as i32, cell.z as i32);
    let corner = |dx: i32, dy: i32, dz: i32| lattice(x + dx, y + dy, z + dz, seed);
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(corner(0, 0, 0), corner(1, 0, 0), smooth.x);
    let x10 = lerp(corner(0, 1, 0), corner(1, 1, 0), smooth.x);
    let x01 = lerp(corner(0, 0, 1), corner(1, 0, 1), smooth.x);
    let x11 = lerp(corner(0, 1, 1), corner(1, 1, 1), smooth.x);
    lerp(lerp(x00, x10, smooth.y), lerp(x01, x11, smooth.y), smooth.z)
}

/// A lattice point's value in `[0, 1]`, from an integer hash.
fn lattice(x: i32, y: i32, z: i32, seed: u32) -> f32 {
    let mut h = (x as u32).wrapping_mul(0x8da6_b343)
        ^ (y as u32).wrapping_mul(0xd816_3841)
        ^ (z as u32).wrapping_mul(0xcb1a_b31f)
        ^ seed.wrapping_mul(0x9e37_79b9);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297a_2d39);
    h ^= h >> 15;
    (h >> 8) as f32 / (1 << 24) as f32
}

/// Fractal noise: `octaves` layers of value noise, each twice as fine and
/// half as strong; about `[0, 1]`.
fn fbm(p: Vec3, octaves: u32, seed: u32) -> f32 {
    let (mut sum, mut amplitude, mut frequency, mut norm) = (0.0, 0.5, 1.0, 0.0);
    for octave in 0..octaves {
        sum += amplitude * value_noise(p * frequency, seed.wrapping_add(octave));
        norm += amplitude;
        amplitude *= 0.5;
        frequency *= 2.03;
    }
    sum / norm
}

/// The direction on the unit sphere that pixel (`x`, `y`) shows, and its
/// latitude in degrees. Matches Bevy's UV sphere: its poles on ±z, u with
/// the longitude around z from +x, v from the north pole (+z) down. (The
/// window turns the sphere so that its north pole points up, +y.)
fn direction(x: u32, y: u32, width: u32, height: u32) -> (Vec3, f32) {
    let u = (x as f32 + 0.5) / width as f32;
    let v = (y as f32 + 0.5) / height as f32;
    let longitude = u * std::f32::consts::TAU;
    let latitude = (0.5 - v) * std::f32::consts::PI;
    let (sin_lat, cos_lat) = latitude.sin_cos();
    (
        Vec3::new(cos_lat * longitude.cos(), cos_lat * longitude.sin(), sin_lat),
        latitude.to_degrees(),
    )
}

/// Every pixel's value of `f(index, direction, latitude)`, rows in
/// parallel, in row order.
fn per_pixel<T: Send>(width: u32, height: u32, f: impl Fn(usize, Vec3, f32) -> T + Sync) -> Vec<T> {
    (0..height)
        .into_par_iter()
        .flat_map_iter(|y| {
            let f = &f;
            (0..width).map(move |x| {
                let (d, lat) = direction(x, y, width, height);
                f((y * width + x) as usize, d, lat)
            })
        })
        .collect()
}

fn mix(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    let t = t.clamp(0.0, 1.0);
    [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t)
}

fn to_bytes(rgb: [f32; 3]) -> [u8; 4] {
    let [r, g, b] = rgb.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
    [r, g, b, 255]
}

/// The Earth, `width` × `width / 2` pixels, from `seed`.
pub fn earth(width: u32, seed: u32) -> Picture {
    let height = (width / 2).max(1);
    // Elevation; the sea level is the quantile that leaves LAND_SHARE dry.
    let elevation = per_pixel(width, height, |_, d, _| {
        let warp = Vec3::new(
            fbm(d * 2.0 + Vec3::splat(11.0), 3, seed ^ 0x51),
            fbm(d * 2.0 + Vec3::splat(23.0), 3, seed ^ 0x52),
            fbm(d * 2.0 + Vec3::splat(37.0), 3, seed ^ 0x53),
        );
        fbm(d * 1.7 + warp * 1.2, 7, seed)
    });
    let mut sorted = elevation.clone();
    sorted.sort_unstable_by(f32::total_cmp);
    let sea = sorted[((1.0 - LAND_SHARE) * (sorted.len() - 1) as f32) as usize];
    let top = sorted[sorted.len() - 1].max(sea + 1e-3);
    let colors = per_pixel(width, height, |i, d, lat| {
        let e = elevation[i];
        let polar = lat.abs() + 10.0 * (fbm(d * 6.0, 3, seed ^ 0x77) - 0.5);
        let mut rgb = if e <= sea {
            let depth = ((sea - e) / 0.12).clamp(0.0, 1.0);
            mix([0.09, 0.30, 0.52], [0.02, 0.07, 0.24], depth.sqrt())
        } else {
            let height = (e - sea) / (top - sea);
            let moisture = fbm(d * 3.0 + Vec3::splat(5.0), 5, seed ^ 0x99);
            // Deserts around the subtropics, forests where it is wet.
            let subtropic = 1.0 - ((lat.abs() - 24.0) / 14.0).powi(2).min(1.0);
            let dry = (subtropic * 0.7 + (0.5 - moisture) * 1.6).clamp(0.0, 1.0);
            let green = mix(
                [0.11, 0.30, 0.09],
                [0.30, 0.40, 0.16],
                moisture * 0.6 + lat.abs() / 120.0,
            );
            let land = mix(green, [0.74, 0.63, 0.42], dry);
            let rock = mix(land, [0.42, 0.37, 0.31], ((height - 0.45) * 3.0).clamp(0.0, 1.0));
            mix(rock, [0.95, 0.95, 0.97], ((height - 0.8) * 6.0).clamp(0.0, 1.0))
        };
        // Ice caps, on land and sea.
        rgb = mix(rgb, [0.93, 0.95, 0.98], (polar - 68.0) / 4.0);
        // Clouds: wispy bands, thinnest in the subtropics.
        let cloud = fbm(d * 3.5 + Vec3::new(0.0, lat / 30.0, 0.0), 6, seed ^ 0xc1);
        rgb = mix(rgb, [0.97, 0.97, 0.98], (cloud - 0.56) * 3.0);
        to_bytes(rgb)
    });
    Picture {
        width,
        height,
        rgba: colors.concat(),
    }
}

/// The Moon, `width` × `width / 2` pixels, from `seed`.
pub fn moon(width: u32, seed: u32) -> Picture {
    let height = (width / 2).max(1);
    let mut rng = Rng::new(u64::from(seed));
    // Craters: a direction and an angular radius; many small, few large.
    let craters: Vec<(Vec3, f32)> = (0..220)
        .map(|_| {
            let z = rng.symmetric(1.0) as f32;
            let phi = rng.unit() as f32 * std::f32::consts::TAU;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let size = 0.02 + 0.16 * (rng.unit() as f32).powi(4);
            (Vec3::new(r * phi.cos(), z, r * phi.sin()), size)
        })
        .collect();
    let colors = per_pixel(width, height, |_, d, _| {
        let maria = fbm(d * 1.3 + Vec3::splat(3.0), 4, seed ^ 0x3a);
        let grain = fbm(d * 24.0, 3, seed ^ 0x5b);
        let mut shade = 0.62 + 0.12 * (grain - 0.5);
        shade -= 0.2 * ((maria - 0.53) * 8.0).clamp(0.0, 1.0);
        for &(center, size) in &craters {
            let angle = d.dot(center).clamp(-1.0, 1.0).acos();
            let t = angle / size;
            if t < 1.0 {
                shade *= 0.78 + 0.12 * t * t;
            } else if t < 1.25 {
                shade *= 1.0 + 0.25 * (1.0 - (t - 1.125).abs() * 8.0).max(0.0);
            }
        }
        to_bytes([shade, shade * 0.98, shade * 0.95])
    });
    Picture {
        width,
        height,
        rgba: colors.concat(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb(p: &Picture, x: u32, y: u32) -> [u8; 3] {
        let i = ((y * p.width + x) * 4) as usize;
        [p.rgba[i], p.rgba[i + 1], p.rgba[i + 2]]
    }

    fn is_ocean(rgb: [u8; 3]) -> bool {
        let [r, g, b] = rgb.map(u16::from);
        b > 50 && b > r + 30 && b > g
    }

    fn is_ice([r, g, b]: [u8; 3]) -> bool {
        r.min(g).min(b) > 200
    }

    #[test]
    fn the_earth_is_mostly_ocean_with_continents_and_white_poles() {
        let p = earth(256, 7);
        assert_eq!((p.width, p.height, p.rgba.len()), (256, 128, 256 * 128 * 4));
        let band = |rows: std::ops::Range<u32>| -> Vec<[u8; 3]> {
            rows.flat_map(|y| (0..p.width).map(move |x| (x, y)))
                .map(|(x, y)| rgb(&p, x, y))
                .collect()
        };
        let share = |pixels: &[[u8; 3]], f: fn([u8; 3]) -> bool| {
            pixels.iter().filter(|c| f(**c)).count() as f64 / pixels.len() as f64
        };
        let tropics = band(40..88);
        let ocean = share(&tropics, is_ocean);
        assert!((0.35..0.85).contains(&ocean), "ocean share between the tropics {ocean}");
        let land = tropics.iter().filter(|c| !is_ocean(**c) && !is_ice(**c)).count();
        assert!(land as f64 / tropics.len() as f64 > 0.1, "continents: {land}");
        for (name, rows) in [("north", 0..5), ("south", 123..128)] {
            let ice = share(&band(rows), is_ice);
            assert!(ice > 0.8, "{name} pole ice share {ice}");
        }
        // No seam at the date line: the first and last columns look alike.
        let alike = (0..p.height)
            .filter(|&y| {
                let (a, b) = (rgb(&p, 0, y), rgb(&p, p.width - 1, y));
                (0..3).all(|k| a[k].abs_diff(b[k]) < 40)
            })
            .count();
        assert!(alike as f64 > 0.9 * f64::from(p.height), "seam: {alike} rows alike");
        assert_eq!(earth(256, 7), p, "the same seed, the same Earth");
    }

    #[test]
    fn the_moon_is_grey_with_dark_and_bright_patches() {
        let p = moon(256, 3);
        let pixels: Vec<[u8; 3]> = (0..p.height)
            .flat_map(|y| (0..p.width).map(move |x| (x, y)))
            .map(|(x, y)| rgb(&p, x, y))
            .collect();
        assert!(pixels.iter().all(|[r, _, b]| r.abs_diff(*b) < 20), "grey, not coloured");
        let brightness: Vec<u8> = pixels.iter().map(|c| c[0]).collect();
        let (lo, hi) = (brightness.iter().min().unwrap(), brightness.iter().max().unwrap());
        assert!(hi - lo > 60, "maria and craters give contrast: {lo}..{hi}");
    }
}
