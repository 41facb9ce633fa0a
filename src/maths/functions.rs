//! Platform-independent maths: every transcendental function that decides
//! the state (shatter directions and sizes, the generators' orbits) comes
//! from here, and here from the [`libm`] crate, a Rust port of musl's
//! library: the same operations in the same order on every processor and
//! operating system, so the same bits (docs/design.md, "What is
//! bit-identical"). The standard library's `sin`, `cos`, `cbrt`, `powf` …
//! call the platform's C library, whose last bits differ between systems
//! (and, with glibc, between processors); `clippy.toml` forbids them in
//! the simulation, as it forbids glam's rotations built on them.
//!
//! Square roots, divisions and the other basic operations are correctly
//! rounded by IEEE 754 everywhere and need nothing from here.

use bevy::math::DQuat;

/// `(sin x, cos x)`.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    (libm::sin(x), libm::cos(x))
}

/// The cube root of `x`.
#[inline]
pub fn cbrt(x: f64) -> f64 {
    libm::cbrt(x)
}

/// `x` to the power `y`.
#[inline]
pub fn pow(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// The rotation by `angle` (radians) about the x axis.
pub fn rotation_x(angle: f64) -> DQuat {
    let (s, c) = sin_cos(angle * 0.5);
    DQuat::from_xyzw(s, 0.0, 0.0, c)
}

/// The rotation by `angle` (radians) about the y axis.
pub fn rotation_y(angle: f64) -> DQuat {
    let (s, c) = sin_cos(angle * 0.5);
    DQuat::from_xyzw(0.0, s, 0.0, c)
}

/// The rotation by `angle` (radians) about the z axis.
pub fn rotation_z(angle: f64) -> DQuat {
    let (s, c) = sin_cos(angle * 0.5);
    DQuat::from_xyzw(0.0, 0.0, s, c)
}

/// The rotation by `y` about the y axis, then `x` about the new x axis,
/// then `z` about the new z axis (Euler angles in the order y, x, z).
pub fn rotation_yxz(y: f64, x: f64, z: f64) -> DQuat {
    rotation_y(y) * rotation_x(x) * rotation_z(z)
}

#[cfg(test)]
#[expect(
    clippy::disallowed_methods,
    reason = "the platform's functions as the reference the portable ones are held to"
)]
mod tests {
    use super::*;
    use bevy::math::{DVec3, EulerRot};

    /// Within `ulps` steps of `f64` of the platform's value.
    fn near(a: f64, b: f64, ulps: u64) -> bool {
        a == b || (a.to_bits().abs_diff(b.to_bits()) <= ulps && a.signum() == b.signum())
    }

    #[test]
    fn the_portable_functions_agree_with_the_platforms_to_a_step() {
        for i in 0..10_000 {
            let x = (f64::from(i) - 5000.0) * 0.00731;
            let (s, c) = sin_cos(x);
            assert!(near(s, x.sin(), 1) && near(c, x.cos(), 1), "{x}: {s} {c}");
            assert!(near(cbrt(x), x.cbrt(), 1), "{x}");
            assert!(near(pow(x.abs(), 1.5), x.abs().powf(1.5), 1), "{x}");
        }
        assert_eq!(cbrt(27.0), 3.0);
        assert_eq!(cbrt(-0.125), -0.5);
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
    }

    #[test]
    fn the_rotations_are_glams() {
        let v = DVec3::new(0.3, -1.2, 2.0);
        for (a, b, c) in [(0.1, 2.0, -1.0), (3.0, 0.5, 6.0), (-2.5, 4.0, 0.0)] {
            let ours = rotation_yxz(a, b, c) * v;
            let glams = DQuat::from_euler(EulerRot::YXZ, a, b, c) * v;
            assert!((ours - glams).length() < 1e-14, "{ours} vs {glams}");
            let ours = rotation_x(a) * v;
            assert!((ours - DQuat::from_rotation_x(a) * v).length() < 1e-14);
            let ours = rotation_z(b) * v;
            assert!((ours - DQuat::from_rotation_z(b) * v).length() < 1e-14);
        }
    }
}
