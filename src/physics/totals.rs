//! Not a stage: the totals over all bodies that tell what the physics
//! conserves — mass (shattering keeps it), momentum (bouncing and
//! shattering keep it; gravity from fixed sources does not) and kinetic
//! energy (bounces keep it; a shatter loses the pair's relative motion and
//! gains the fragments' spread, a net loss at the default spread; gravity trades it
//! for potential energy). Summed in f64 in query order, so both execution
//! modes give the same figures.

use bevy::math::{DVec3, Vec3};

/// Sums over the bodies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Totals {
    /// Number of bodies.
    pub bodies: u64,
    /// Total mass, mass units.
    pub mass: f64,
    /// Total kinetic energy `Σ ½·m·|v|²`.
    pub kinetic_energy: f64,
    /// Total momentum `Σ m·v`.
    pub momentum: DVec3,
}

impl Totals {
    /// Kernel: the totals over `(mass, velocity)` of every body.
    pub fn of(bodies: impl Iterator<Item = (f32, Vec3)>) -> Self {
        bodies.fold(Self::default(), |mut t, (mass, velocity)| {
            let (m, v) = (f64::from(mass), velocity.as_dvec3());
            t.bodies += 1;
            t.mass += m;
            t.kinetic_energy += 0.5 * m * v.length_squared();
            t.momentum += m * v;
            t
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_mass_energy_and_momentum() {
        let t = Totals::of([(2.0, Vec3::new(3.0, 0.0, 0.0)), (1.0, Vec3::new(0.0, -4.0, 2.0))].into_iter());
        assert_eq!(t.bodies, 2);
        assert_eq!(t.mass, 3.0);
        assert_eq!(t.kinetic_energy, 9.0 + 10.0);
        assert_eq!(t.momentum, DVec3::new(6.0, -4.0, 2.0));
    }
}
