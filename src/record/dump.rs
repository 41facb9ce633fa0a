//! The CSV state dump of `kessler headless --dump` (docs/design.md,
//! "Command line"): one row per body, sorted by id, floats in Rust's
//! shortest round-trip form; every line a row of its header, so that any
//! CSV reader reads it as it is (the state's hash is in the summary line and
//! the timeline, docs/design.md, "State hash"). Written atomically with
//! [`write_atomically`](crate::output::write_atomically).

use std::io::{self, Write};

use crate::components::BodyState;

/// One body's row: its columns (the header, a stable contract) and cells
/// are declared together below.
pub struct DumpRow<'a>(pub &'a BodyState);

crate::csv_row!(DumpRow<'_>, |row| {
    id: row.0.id.0,
    x: row.0.position.x,
    y: row.0.position.y,
    z: row.0.position.z,
    vx: row.0.velocity.x,
    vy: row.0.velocity.y,
    vz: row.0.velocity.z,
    mass: row.0.mass,
    hx: row.0.half_extents.x,
    hy: row.0.half_extents.y,
    hz: row.0.half_extents.z,
    role: row.0.role.name(),
    interacts: row.0.interacts,
});

/// Writes the header and one row per body (sorted by id), refusing a
/// state with a number that is not finite.
pub fn write_csv(bodies: &[BodyState], mut out: impl Write) -> io::Result<()> {
    BodyState::check_all_finite(bodies)?;
    let rows: Vec<DumpRow<'_>> = bodies.iter().map(DumpRow).collect();
    crate::output::write_csv(&mut out, &rows)?;
    out.flush()
}

#[cfg(test)]
mod tests {
    use bevy::math::Vec3;

    use super::*;
    use crate::components::{BodyId, GravityRole};
    use crate::output::{CsvTable, header};

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
            absorbs: false,
        };
        let mut out = Vec::new();
        write_csv(&[body], &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            "id,x,y,z,vx,vy,vz,mass,hx,hy,hz,role,interacts\n3,0.1,-2,0.0000001,0.81694555,0,-0,4000,430,430,430,SourceAndAdopter,false\n"
        );
        assert_eq!(
            header::<DumpRow<'_>>(),
            "id,x,y,z,vx,vy,vz,mass,hx,hy,hz,role,interacts"
        );
        let table = CsvTable::parse::<DumpRow<'_>>(&text).unwrap();
        assert_eq!(table.column("vx").unwrap(), ["0.81694555"]);
        let x: f32 = "0.81694555".parse().unwrap();
        assert_eq!(x.to_bits(), 0.81694555f32.to_bits());
    }
}
