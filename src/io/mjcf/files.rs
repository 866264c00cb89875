//! The files an MJCF model reads besides itself, held to the size cap of input files
//! ([`crate::io::MAX_INPUT_BYTES`]): mjcf-rs reads an `<include>`d file whole and
//! `rapier3d-mjcf` a mesh whole, without a cap (an `<include file="/dev/zero"/>` grew until
//! the memory ran out). Both are checked here before either reads them.

use crate::io::urdf::UrdfError;
use crate::io::InputErrorKind;
use rapier3d_mjcf::mjcf_rs::assets::Mesh;
use rapier3d_mjcf::mjcf_rs::body::{Body, Geom, GeomType};
use rapier3d_mjcf::mjcf_rs::model::Model;
use std::path::{Path, PathBuf};

/// How deep `<include>`s are followed (mjcf-rs refuses a cycle itself).
const MAX_INCLUDE_DEPTH: usize = 32;

/// Reads every file `<include>`d by `text` (whose includes are relative to `base`), and the
/// files those include, through the capped reader: a file larger than the cap, a device, a
/// file that cannot be read or is not XML is an error naming the element, its line in
/// `file` and the included file. Returns the included files read (their path as written
/// in errors, and their text), in document order, for the checks that read the model as
/// written ([`super::unread`]).
pub(super) fn check_includes(
    file: &str,
    text: &str,
    base: &Path,
) -> Result<Vec<(String, String)>, UrdfError> {
    let mut included = Vec::new();
    check_includes_at(file, text, base, 0, &mut included)?;
    Ok(included)
}

fn check_includes_at(
    file: &str,
    text: &str,
    base: &Path,
    depth: usize,
    out: &mut Vec<(String, String)>,
) -> Result<(), UrdfError> {
    if depth > MAX_INCLUDE_DEPTH {
        return Ok(());
    }
    // (a text that is not XML is mjcf-rs's to report)
    let Ok(doc) = roxmltree::Document::parse(text) else {
        return Ok(());
    };
    // an `<asset><model name file>` (a sub-model for `<attach>`) is read whole by mjcf-rs
    // too: one beyond the size cap is refused alike (a `/dev/zero` sub-model was read until
    // memory ran out); one mjcf-rs cannot load it skips, and the `<attach>` naming it gets
    // a notice (`super::unread`). It is not walked.
    let read_whole = |n: &roxmltree::Node| {
        n.has_tag_name("include")
            || (n.has_tag_name("model")
                && n.has_attribute("name")
                && n.parent().is_some_and(|p| p.has_tag_name("asset")))
    };
    for node in doc.descendants().filter(read_whole) {
        let Some(name) = node.attribute("file") else {
            continue;
        };
        let tag = node.tag_name().name();
        let given = Path::new(name);
        let path = if given.is_absolute() {
            given.to_path_buf()
        } else {
            base.join(given)
        };
        let line = doc.text_pos_at(node.range().start).row;
        let read = crate::io::read_input_text(&path);
        if tag == "model"
            && !matches!(&read, Err(e) if matches!(e.kind, InputErrorKind::TooLarge { .. }))
        {
            continue;
        }
        let included = read.map_err(|e| UrdfError::Mjcf {
            file: file.to_string(),
            message: format!("<{tag} file=\"{name}\"> (line {line}): {}", e.kind.reason()),
        })?;
        // (mjcf-rs names neither the included file nor the include of a text that is not
        // XML: `XML parse error: unknown token at 1:1`)
        if let Err(e) = roxmltree::Document::parse(&included) {
            return Err(UrdfError::Mjcf {
                file: file.to_string(),
                message: format!(
                    "<{tag} file=\"{name}\"> (line {line}): `{}` is not XML: {e}",
                    path.display()
                ),
            });
        }
        let inner_base = path.parent().unwrap_or(Path::new(""));
        let inner = path.display().to_string();
        // (in document order: the include before the files it includes)
        let at = out.len();
        out.push((inner.clone(), String::new()));
        check_includes_at(&inner, &included, inner_base, depth + 1, out)?;
        out[at].1 = included;
    }
    Ok(())
}

/// A mesh geom of a model and what its `mesh=` resolves to ([`mesh_geoms`]).
pub(super) struct MeshGeom<'a> {
    /// The index of its body in the model (`model.bodies`, 0 the world).
    pub body_index: usize,
    /// Its body.
    pub body: &'a Body,
    /// Its index among its body's geoms.
    pub geom_index: usize,
    /// The geom.
    pub geom: &'a Geom,
    /// What its `mesh=` names.
    pub mesh: MeshOf<'a>,
}

/// What a mesh geom's `mesh=` names.
pub(super) enum MeshOf<'a> {
    /// No `mesh=`.
    Unnamed,
    /// A name that no `<mesh>` of `<asset>` declares.
    Undeclared(&'a str),
    /// A declared mesh, and its file resolved as `rapier3d-mjcf` resolves it (`meshdir`,
    /// relative to the model's directory); `None` without a `file=`.
    Declared {
        /// The mesh's name.
        name: &'a str,
        /// The `<mesh>` of `<asset>`.
        mesh: &'a Mesh,
        /// Its file.
        file: Option<PathBuf>,
    },
}

/// Every mesh geom of `model` (of `<worldbody>` itself and of every body, in model order)
/// with what its mesh resolves to against `base`: the one walk of the checks of mesh files
/// ([`check_mesh_files`]) and of the notices of meshes that are skipped
/// (`check::mesh_notices`). The world's geoms count: `rapier3d-mjcf` builds them as
/// colliders of the world (a mesh of `<worldbody>` with `file="/dev/zero"` was read until
/// the memory ran out, when only the bodies' geoms were walked).
pub(super) fn mesh_geoms<'a>(
    model: &'a Model,
    base: &'a Path,
) -> impl Iterator<Item = MeshGeom<'a>> + 'a {
    model.bodies.iter().enumerate().flat_map(move |(i, entry)| {
        let body = &entry.body;
        let geoms = body.geoms.iter().enumerate();
        geoms
            .filter(|(_, g)| g.type_ == GeomType::Mesh)
            .map(move |(k, geom)| {
                let mesh = match geom.mesh.as_deref() {
                    None => MeshOf::Unnamed,
                    Some(name) => match model.assets.mesh(name) {
                        None => MeshOf::Undeclared(name),
                        Some(mesh) => MeshOf::Declared {
                            name,
                            mesh,
                            file: model.resolve_mesh_file(mesh, base),
                        },
                    },
                };
                MeshGeom {
                    body_index: i,
                    body,
                    geom_index: k,
                    geom,
                    mesh,
                }
            })
    })
}

/// Checks the file of every mesh a geom of `model` uses (relative to `base`): one that is
/// there but is not a regular file, or is larger than the cap, is an error naming the mesh
/// and the file (a mesh file that is not there is skipped with a notice:
/// `check::mesh_notices`).
pub(super) fn check_mesh_files(file: &str, model: &Model, base: &Path) -> Result<(), UrdfError> {
    for g in mesh_geoms(model, base) {
        let MeshOf::Declared {
            name,
            file: Some(path),
            ..
        } = g.mesh
        else {
            continue;
        };
        let Ok(meta) = std::fs::metadata(&path) else {
            continue;
        };
        let why = if !meta.is_file() {
            "is not a regular file".to_string()
        } else if meta.len() > crate::io::MAX_INPUT_BYTES {
            crate::io::InputErrorKind::TooLarge {
                cap: crate::io::MAX_INPUT_BYTES,
            }
            .to_string()
        } else {
            continue;
        };
        return Err(UrdfError::Mjcf {
            file: file.to_string(),
            message: format!("mesh `{name}`: file `{}` {why}", path.display()),
        });
    }
    Ok(())
}
