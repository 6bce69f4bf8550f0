//! The mesh-input seam: one function ([`load_mesh`]) reads any supported file, choosing the
//! [`Format`] by magic bytes, then by extension; one function ([`mesh_files`]) lists the mesh
//! files of a folder. Scenes (`mesh = "..."`), `--mesh`, `--models DIR`, `corpus` and `tune`
//! read meshes only through here.
//!
//! A format is one reader in its own file ([`super::obj`], [`super::gltf`], [`super::ply`]),
//! each returning the fitted [`Mesh`] and a [`LoadReport`] whose [`MeshInput`] says what was
//! drawn (format, encoding, and for glTF the scene, nodes, meshes and primitives).
use std::path::{Path, PathBuf};

pub use super::mesh_file::{
    read_inside, supported_list, DrawnScene, Encoding, Format, MeshInput, Named, NormalSource,
    Part, ReadFile, Refused, SceneChoice, BUFFER_RULE,
};
use super::{LoadReport, Mesh};
use crate::error::{Error, Result};

/// Reads a mesh file of any [`Format`] into a fitted triangle soup ([`super::fit_unit`]), with
/// the report of what was read and drawn.
///
/// A glTF's buffer files are read by [`read_inside`] the file's folder ([`BUFFER_RULE`]).
///
/// Errors: a missing or unreadable file is [`Error::Io`]; anything wrong in it is
/// [`Error::Input`] naming the file and, where the format has them, the line (OBJ, PLY's ASCII
/// part) or the object (glTF: mesh, primitive, accessor, buffer; PLY: element).
pub fn load_mesh(path: &Path) -> Result<(Mesh, LoadReport)> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let folder = path.parent().unwrap_or(Path::new(""));
    parse_mesh(path, &bytes, &|p| read_inside(folder, p))
}

/// [`load_mesh`] on bytes already read: `path` names the file in messages and gives the
/// folder that the files it refers to are resolved against, `read` reads those (the fuzz
/// harness passes one that never touches the disk).
pub fn parse_mesh(path: &Path, bytes: &[u8], read: ReadFile) -> Result<(Mesh, LoadReport)> {
    let format = Format::detect(path, bytes)?;
    let (mesh, mut report) = match format {
        Format::Obj => super::obj::parse_obj(path, bytes)?,
        Format::Gltf => super::gltf::parse_gltf(path, bytes, read)?,
        Format::Ply => super::ply::parse_ply(path, bytes)?,
    };
    if let Some(by_ext) = Format::of_extension(path).filter(|&f| f != format) {
        report.warnings.insert(
            0,
            format!(
                "the extension says {} but the content is {}: read as {}",
                by_ext.name(),
                format.name(),
                format.name()
            ),
        );
    }
    Ok((mesh, report))
}

/// Whether `path` has the extension of a [`Format`].
pub fn is_mesh_file(path: &Path) -> bool {
    Format::of_extension(path).is_some()
}

/// How deep [`mesh_files`] looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Depth {
    /// The folder's own files.
    Flat,
    /// The folder and every folder under it.
    Recursive,
}

/// Every mesh file of `dir` (an extension of a [`Format`], case-insensitive), sorted by path;
/// hidden entries (a leading `.`) and `skip` (an output folder inside `dir`) left out.
///
/// Errors: an unreadable folder is [`Error::Io`]; a folder without a mesh file is
/// [`Error::Usage`] naming it and the extensions read.
pub fn mesh_files(dir: &Path, depth: Depth, skip: Option<&Path>) -> Result<Vec<PathBuf>> {
    let skip = skip.and_then(|s| s.canonicalize().ok());
    let mut files = Vec::new();
    walk(dir, depth, skip.as_deref(), &mut files)?;
    files.sort();
    if files.is_empty() {
        return Err(Error::Usage(format!(
            "no mesh files ({}) in {}",
            supported_list(),
            dir.display()
        )));
    }
    Ok(files)
}

fn walk(dir: &Path, depth: Depth, skip: Option<&Path>, out: &mut Vec<PathBuf>) -> Result<()> {
    for e in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let e = e.map_err(|e| Error::io(dir, e))?;
        let path = e.path();
        if e.file_name().to_string_lossy().starts_with('.') {
            continue;
        }
        if skip.is_some() && path.canonicalize().ok().as_deref() == skip {
            continue;
        }
        if path.is_dir() {
            if depth == Depth::Recursive {
                walk(&path, depth, skip, out)?;
            }
        } else if is_mesh_file(&path) {
            out.push(path);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn magic_bytes_win_over_the_extension_then_the_extension_then_json() {
        let p = |s: &str| PathBuf::from(s);
        assert_eq!(
            Format::detect(&p("a.obj"), b"glTF\x02\0\0\0").unwrap(),
            Format::Gltf
        );
        assert_eq!(
            Format::detect(&p("a.obj"), b"ply\r\nformat").unwrap(),
            Format::Ply
        );
        assert_eq!(
            Format::detect(&p("a.PLY"), b"v 0 0 0").unwrap(),
            Format::Ply
        );
        assert_eq!(Format::detect(&p("a.GLB"), b"{}").unwrap(), Format::Gltf);
        assert_eq!(
            Format::detect(&p("noext"), b" \n{\"asset\":{}}").unwrap(),
            Format::Gltf
        );
        assert_eq!(
            Format::detect(&p("a.obj"), b"v 0 0 0").unwrap(),
            Format::Obj
        );
        // "plywood" is not PLY's first line; an unknown extension without magic is refused.
        let e = Format::detect(&p("a.stl"), b"plywood\n").unwrap_err();
        assert!(
            e.to_string().contains("give .obj, .gltf, .glb or .ply"),
            "{e}"
        );
    }

    #[test]
    fn a_file_whose_extension_lies_is_read_by_its_content_with_a_note() {
        let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        let none = |_: &Path| Err(std::io::Error::from(std::io::ErrorKind::NotFound));
        let (m, r) = parse_mesh(Path::new("tri.obj"), ply, &none).unwrap();
        assert_eq!(m.triangle_count(), 1);
        assert_eq!(r.input.format, Format::Ply);
        assert_eq!(
            r.warnings[0],
            "the extension says OBJ but the content is PLY: read as PLY"
        );
        let (_, r) = parse_mesh(Path::new("tri.ply"), ply, &none).unwrap();
        assert!(
            !r.warnings.iter().any(|w| w.contains("extension says")),
            "{r:?}"
        );
    }
}
