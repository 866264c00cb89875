//! Meshes for drawing, shared by the robot readers ([`crate::io::urdf`]) and the outputs
//! ([`crate::output`]): [`LinkMesh`], a mesh read in a link's frame (part of a robot
//! description, before it is inserted), and [`VisualMesh`], the same mesh on the body the link
//! became. They are never simulated.

use crate::rapier::dynamics::RigidBodyHandle;
use std::path::PathBuf;

/// A `<visual>` mesh of a link, in the link's frame, read but not yet on a body (a robot
/// description's [`crate::io::robot::RobotLink::visual_meshes`]).
#[derive(Debug, Clone, PartialEq)]
pub struct LinkMesh {
    /// The mesh file, resolved.
    pub file: PathBuf,
    /// Vertices in the link (body) frame \[m\]: the URDF `<origin>` and `scale` applied.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles, as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

/// A `<visual>` mesh of a link on its inserted body, for drawing (never simulated).
#[derive(Debug, Clone, PartialEq)]
pub struct VisualMesh {
    /// The link's name.
    pub link: String,
    /// The link's body.
    pub body: RigidBodyHandle,
    /// The mesh file, resolved.
    pub file: PathBuf,
    /// Vertices in the body (link) frame \[m\]: the URDF `<origin>` and `scale` applied.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles, as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

impl VisualMesh {
    /// The mesh `mesh` of the link `link`, on the body `body` it was inserted as.
    pub fn on_body(link: &str, body: RigidBodyHandle, mesh: LinkMesh) -> Self {
        VisualMesh {
            link: link.to_string(),
            body,
            file: mesh.file,
            vertices: mesh.vertices,
            triangles: mesh.triangles,
        }
    }
}
