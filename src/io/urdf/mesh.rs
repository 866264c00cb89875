//! Mesh files of a URDF robot: where a `<mesh filename>` is ([`resolve_mesh_path`], with
//! the resolution of every mesh of a robot before `rapier3d-urdf` reads the collision ones),
//! and the `<visual>` meshes read for drawing ([`LinkMesh`]).

use super::options::{CollisionMeshes, UrdfOptions};
use crate::io::visual::LinkMesh;
use nalgebra::{Rotation3, Vector3};
use rapier3d_urdf::urdf_rs;
use std::path::{Path, PathBuf};

/// The file of a URDF mesh `filename`: `package://PKG/rest` is looked up as
/// `DIR/PKG/rest` in `package_dirs`, then in the ancestors of `base` (an ancestor named
/// `PKG`, or one holding a `PKG` directory); `file://path` is `path`; anything else is
/// relative to `base`. `None` when no candidate exists.
pub fn resolve_mesh_path(filename: &str, base: &Path, package_dirs: &[PathBuf]) -> Option<PathBuf> {
    if let Some(rest) = filename.strip_prefix("package://") {
        let (pkg, rel) = rest.split_once('/')?;
        let in_dirs = package_dirs.iter().map(|d| d.join(pkg).join(rel));
        let up = base.ancestors().flat_map(|a| {
            let named = (a.file_name().is_some_and(|n| n == pkg)).then(|| a.join(rel));
            named
                .into_iter()
                .chain(std::iter::once(a.join(pkg).join(rel)))
        });
        return in_dirs.chain(up).find(|p| p.is_file());
    }
    let p = match filename.strip_prefix("file://") {
        Some(abs) => PathBuf::from(abs),
        None => base.join(filename),
    };
    p.is_file().then_some(p)
}

/// The vertices and triangles of a mesh file (STL, COLLADA, Wavefront), each vertex mapped
/// by `map`; an error saying why when the file cannot be parsed or has no triangle (an empty
/// file). The one reading of the visual meshes of URDF links and of the check of MJCF mesh
/// files (`crate::io::mjcf`, whose loader skips such a mesh with a log line only).
#[allow(clippy::type_complexity)] // (the vertices and triangles, as parry's trimesh takes them)
pub(crate) fn read_mesh_file(
    file: &Path,
    map: impl Fn([f32; 3]) -> [f32; 3],
) -> Result<(Vec<[f32; 3]>, Vec<[u32; 3]>), String> {
    let scene = rapier3d_meshloader::mesh_loader::Loader::default()
        .load(file)
        .map_err(|e| e.to_string())?;
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for m in scene.meshes {
        let off = vertices.len() as u32;
        let n = m.vertices.len() as u32;
        vertices.extend(m.vertices.iter().map(|v| map(*v)));
        for f in &m.faces {
            if f.iter().all(|i| *i < n) {
                triangles.push([f[0] + off, f[1] + off, f[2] + off]);
            }
        }
    }
    if triangles.is_empty() {
        return Err("no triangles".into());
    }
    Ok((vertices, triangles))
}

/// Reads a mesh file into link-frame triangles: `origin · (scale ⊙ v)`.
fn read_visual_mesh(
    file: &Path,
    origin: &urdf_rs::Pose,
    scale: Option<urdf_rs::Vec3>,
) -> Result<LinkMesh, String> {
    let sc = scale.map_or([1.0; 3], |s| s.0);
    let [r, p, y] = origin.rpy.0;
    let rot = Rotation3::from_euler_angles(r, p, y);
    let t = Vector3::from(origin.xyz.0);
    let (vertices, triangles) = read_mesh_file(file, |v| {
        let w =
            rot * Vector3::new(
                v[0] as f64 * sc[0],
                v[1] as f64 * sc[1],
                v[2] as f64 * sc[2],
            ) + t;
        [w.x as f32, w.y as f32, w.z as f32]
    })?;
    Ok(LinkMesh {
        file: file.to_path_buf(),
        vertices,
        triangles,
    })
}

/// Resolves the mesh paths of `robot`'s geometries to files (relative to `base`, see
/// [`resolve_mesh_path`]); meshes that are not found or are larger than the size cap of
/// input files are removed, with a notice. With [`CollisionMeshes::Ignore`], collision
/// meshes are removed.
pub(super) fn resolve_meshes(
    robot: &mut urdf_rs::Robot,
    base: &Path,
    options: &UrdfOptions,
    notices: &mut Vec<String>,
) {
    for link in robot.links.iter_mut() {
        let name = link.name.clone();
        let mut resolve = |kind: &str, g: &mut urdf_rs::Geometry| -> bool {
            let urdf_rs::Geometry::Mesh { filename, .. } = g else {
                return true;
            };
            match resolve_mesh_path(filename, base, &options.package_dirs) {
                Some(p)
                    if std::fs::metadata(&p)
                        .is_ok_and(|m| m.len() > crate::io::MAX_INPUT_BYTES) =>
                {
                    notices.push(format!(
                        "link `{name}`: {kind} mesh `{}` is larger than the size cap of input \
                         files ({} bytes, rapier_kjoint::io::MAX_INPUT_BYTES): skipped",
                        p.display(),
                        crate::io::MAX_INPUT_BYTES
                    ));
                    false
                }
                Some(p) => {
                    *filename = p.display().to_string();
                    true
                }
                None => {
                    // (a file read from the working directory has an empty base)
                    let from = if base.as_os_str().is_empty() {
                        Path::new(".")
                    } else {
                        base
                    };
                    notices.push(format!(
                        "link `{name}`: {kind} mesh `{filename}` not found (from {}): skipped",
                        from.display()
                    ));
                    false
                }
            }
        };
        link.collision
            .retain_mut(|c| resolve("collision", &mut c.geometry));
        link.visual
            .retain_mut(|v| resolve("visual", &mut v.geometry));
        if options.collision_meshes == CollisionMeshes::Ignore {
            link.collision
                .retain(|c| !matches!(c.geometry, urdf_rs::Geometry::Mesh { .. }));
        }
    }
}

/// The `<visual>` meshes of `link` (paths already resolved), read into its frame; a mesh
/// that cannot be read is skipped with a notice.
pub(super) fn read_visual_meshes(link: &urdf_rs::Link, notices: &mut Vec<String>) -> Vec<LinkMesh> {
    let mut meshes = Vec::new();
    for v in &link.visual {
        let urdf_rs::Geometry::Mesh { filename, scale } = &v.geometry else {
            continue;
        };
        match read_visual_mesh(Path::new(filename), &v.origin, *scale) {
            Ok(mesh) => meshes.push(mesh),
            Err(e) => notices.push(format!(
                "link `{}`: visual mesh `{filename}` unreadable: {e}",
                link.name
            )),
        }
    }
    meshes
}
