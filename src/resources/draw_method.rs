//! [`DrawMethod`]: how the window draws the bodies — a name shared by the
//! window's settings, the command line and benchmark configs (the window
//! itself is behind the `gui` feature; the name is not).

use serde::{Deserialize, Serialize};

/// How the bodies are drawn: the thesis's three methods (its Tables 1–3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum DrawMethod {
    /// All cubes in one instanced draw call (the fast way; thesis Table 3).
    #[default]
    Instanced,
    /// One Bevy mesh entity per body, all sharing one mesh (Bevy batches
    /// them, but every entity is extracted and culled; thesis Table 2).
    /// Settings files from before the three methods call it `Meshes`.
    #[serde(alias = "Meshes")]
    SharedMesh,
    /// One mesh entity per body with its own copy of the cube's geometry:
    /// redundant data and one draw per body (thesis Table 1).
    MeshPerBody,
}

impl DrawMethod {
    /// Every method, the thesis's order.
    pub const ALL: [Self; 3] = [Self::MeshPerBody, Self::SharedMesh, Self::Instanced];

    /// Lower-case name, as on the command line and in CSV files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Instanced => "instanced",
            Self::SharedMesh => "shared-mesh",
            Self::MeshPerBody => "mesh-per-body",
        }
    }

    /// What the panel calls it.
    pub fn label(self) -> &'static str {
        match self {
            Self::Instanced => "instanced",
            Self::SharedMesh => "one shared mesh",
            Self::MeshPerBody => "a mesh per body",
        }
    }
}

impl std::fmt::Display for DrawMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
