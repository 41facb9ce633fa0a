//! The CSV state dump of `kessler headless --dump` (docs/design.md,
//! "Command line"): one row per body, sorted by id, floats in Rust's
//! shortest round-trip form. Written atomically with
//! [`write_atomically`](crate::output::write_atomically).

use std::io::{self, Write};

use crate::components::BodyState;

/// The header line — a stable contract.
pub const HEADER: &str = "id,x,y,z,vx,vy,vz,mass,hx,hy,hz,role,interacts";

/// Writes the header and one row per body, in the order given.
pub fn write_csv(bodies: &[BodyState], mut out: impl Write) -> io::Result<()> {
    BodyState::check_all_finite(bodies)?;
    writeln!(out, "{HEADER}")?;
    for b in bodies {
        let (p, v, h) = (b.position, b.velocity, b.half_extents);
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            b.id.0,
            p.x,
            p.y,
            p.z,
            v.x,
            v.y,
            v.z,
            b.mass,
            h.x,
            h.y,
            h.z,
            b.role.name(),
            b.interacts
        )?;
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use bevy::math::Vec3;

    use super::*;
    use crate::components::{BodyId, GravityRole};

    #[test]
    fn rows_use_shortest_round_trip_floats() {
        let body = BodyState {
            id: BodyId(3),
            position: Vec3::new(0.1, -2.0, 1e-7),
            velocity: Vec3::new(0.81694555, 0.0, -0.0),
            mass: 4000.0,
            half_extents: Vec3::splat(430.0),
            role: GravityRole::SourceAndAdopter,
            interacts: false,
            previous: Vec3::ZERO,
            spherical: true,
        };
        let mut out = Vec::new();
        write_csv(&[body], &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            format!("{HEADER}\n3,0.1,-2,0.0000001,0.81694555,0,-0,4000,430,430,430,SourceAndAdopter,false\n")
        );
        let x: f32 = "0.81694555".parse().unwrap();
        assert_eq!(x.to_bits(), 0.81694555f32.to_bits());
    }
}
