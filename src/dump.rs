//! The CSV state dump of `kessler headless --dump` (DESIGN §5): one row per
//! body, sorted by id, floats in Rust's shortest round-trip form.

use std::io::{self, Write};
use std::path::Path;

use crate::components::BodyState;

/// The header line — a stable contract.
pub const HEADER: &str = "id,x,y,z,vx,vy,vz,mass,hx,hy,hz,role,interacts";

/// Writes the header and one row per body, in the order given.
pub fn write_csv(bodies: &[BodyState], mut out: impl Write) -> io::Result<()> {
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

/// Writes to `path` through `write`, into a temporary file in the same folder
/// that is then renamed, so that `path` is either the old file or the whole
/// new one.
pub fn write_atomically(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "not a file name"))?;
    let tmp = dir.join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    let result = (|| {
        let mut file = io::BufWriter::new(std::fs::File::create(&tmp)?);
        write(&mut file)?;
        file.into_inner().map_err(io::IntoInnerError::into_error)?.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
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

    #[test]
    fn atomic_write_replaces_whole_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        std::fs::write(&path, "old").unwrap();
        write_atomically(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        let failed = write_atomically(&path, |_| Err(io::Error::other("boom")));
        assert!(failed.is_err());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "temporary file left behind"
        );
    }
}
