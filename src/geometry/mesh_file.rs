//! What a mesh file is and what a reader drew of it: the [`Format`] and its [`Encoding`], how
//! a format is told (magic bytes, then extension), and the provenance a reader returns
//! ([`MeshInput`]: for glTF the scene, nodes, meshes and primitives drawn). The readers
//! ([`super::obj`], [`super::gltf`], [`super::ply`]) and the seam that dispatches to them
//! ([`super::input`]) both use it; it uses neither.
use std::fmt::Write as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// A mesh file format: one reader each.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Format {
    /// Wavefront OBJ ([`super::obj`], on tobj).
    #[default]
    Obj,
    /// glTF 2.0, `.gltf` (JSON) or `.glb` (binary) ([`super::gltf`], on the gltf crate).
    Gltf,
    /// Stanford PLY, ASCII or binary ([`super::ply`], on ply-rs-bw).
    Ply,
}

/// How a file of its [`Format`] is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Encoding {
    /// OBJ's text.
    #[default]
    Text,
    /// A `.gltf`: JSON, buffers in files beside it or in data URIs.
    Json,
    /// A `.glb`: the binary container (JSON chunk and BIN chunk).
    Glb,
    /// PLY `format ascii 1.0`.
    Ascii,
    /// PLY `format binary_little_endian 1.0`.
    BinaryLittleEndian,
    /// PLY `format binary_big_endian 1.0`.
    BinaryBigEndian,
}

impl Format {
    /// Every format, in the order messages list them.
    pub const ALL: [Format; 3] = [Format::Obj, Format::Gltf, Format::Ply];

    /// The format's name as its specification writes it.
    pub fn name(self) -> &'static str {
        match self {
            Format::Obj => "OBJ",
            Format::Gltf => "glTF 2.0",
            Format::Ply => "PLY",
        }
    }

    /// The file extensions of the format (lower case, no dot).
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            Format::Obj => &["obj"],
            Format::Gltf => &["gltf", "glb"],
            Format::Ply => &["ply"],
        }
    }

    /// The format a file's extension names (case-insensitive), if any.
    pub fn of_extension(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Format::ALL
            .into_iter()
            .find(|f| f.extensions().contains(&ext.as_str()))
    }

    /// The format the first bytes prove: a `.glb`'s magic `glTF` (glTF 2.0 section 4.4.2) or
    /// PLY's first line `ply` (Turk's PLY description: "ply" then an end of line; a UTF-8
    /// byte-order mark before it skipped, as the PLY reader does). OBJ and a `.gltf`'s JSON
    /// have no magic.
    pub fn of_magic(bytes: &[u8]) -> Option<Format> {
        let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        if bytes.starts_with(b"glTF") {
            Some(Format::Gltf)
        } else if text.starts_with(b"ply\n") || text.starts_with(b"ply\r\n") {
            Some(Format::Ply)
        } else {
            None
        }
    }

    /// The format of the file at `path` whose content is `bytes`: the magic bytes when they
    /// prove one, else the extension, else JSON (`{` first) is a `.gltf`. A file none of these
    /// name is an [`Error::Input`] listing what is read.
    pub fn detect(path: &Path, bytes: &[u8]) -> Result<Format> {
        if let Some(f) = Format::of_magic(bytes).or_else(|| Format::of_extension(path)) {
            return Ok(f);
        }
        let first = bytes.iter().find(|b| !b.is_ascii_whitespace());
        if first == Some(&b'{') {
            return Ok(Format::Gltf);
        }
        Err(Error::input(
            path,
            None,
            format!(
                "not a mesh file shadelab reads: give {} (by extension; .glb and PLY files are also recognised by their first bytes)",
                supported_list()
            ),
        ))
    }
}

/// `.obj, .gltf, .glb or .ply`: the extensions read, for messages.
pub fn supported_list() -> String {
    let exts: Vec<String> = Format::ALL
        .iter()
        .flat_map(|f| f.extensions())
        .map(|e| format!(".{e}"))
        .collect();
    match exts.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => exts.join(""),
    }
}

/// Reads a file a mesh refers to (a glTF buffer): given its path, resolved against the mesh
/// file's folder.
pub type ReadFile<'a> = &'a dyn Fn(&Path) -> std::io::Result<Vec<u8>>;

/// Where a glTF buffer may come from, for messages and docs/scenes.md.
pub const BUFFER_RULE: &str = "shadelab reads a buffer from a data URI, a .glb's BIN chunk or a regular file inside the .gltf's folder (or a folder under it), named by a relative path that stays inside once %-decoded and with its links resolved";

/// Why [`read_inside`] refused a file that exists: the reason, for the reader's message (the
/// `std::io::Error` it travels in has kind `PermissionDenied`).
#[derive(Debug)]
pub struct Refused(pub String);

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Refused {}

/// The bytes of `file` (a glTF buffer's path, already joined to `folder`, the `.gltf`'s folder),
/// read only when it is a regular file inside `folder` once every link is resolved
/// ([`BUFFER_RULE`]): a link out of the folder, a FIFO, a device or a folder is refused as
/// [`Refused`], before it is opened. The file is opened without following a last link and
/// without blocking (`O_NOFOLLOW | O_NONBLOCK`) and checked again once open, so a file swapped
/// for a FIFO between the check and the open cannot block the read either.
pub fn read_inside(folder: &Path, file: &Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read as _;
    let refuse =
        |why: String| std::io::Error::new(std::io::ErrorKind::PermissionDenied, Refused(why));
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    let folder = folder.canonicalize()?;
    let real = file.canonicalize()?;
    if !real.starts_with(&folder) {
        return Err(refuse(format!(
            "resolves to {}, outside the .gltf's folder {}",
            real.display(),
            folder.display()
        )));
    }
    let not_regular = |m: &std::fs::Metadata| -> Option<String> {
        let what = kind_of(&m.file_type())?;
        Some(format!("is {what}, not a regular file"))
    };
    if let Some(why) = not_regular(&std::fs::metadata(&real)?) {
        return Err(refuse(why));
    }
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        options.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
    }
    let mut f = options.open(&real)?;
    if let Some(why) = not_regular(&f.metadata()?) {
        return Err(refuse(why));
    }
    let mut bytes = Vec::new();
    f.read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// What a file that is not a regular file is, for messages; `None` for a regular file.
fn kind_of(t: &std::fs::FileType) -> Option<&'static str> {
    if t.is_file() {
        return None;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if t.is_fifo() {
            return Some("a FIFO");
        }
        if t.is_char_device() || t.is_block_device() {
            return Some("a device");
        }
        if t.is_socket() {
            return Some("a socket");
        }
    }
    Some(if t.is_dir() {
        "a folder"
    } else {
        "a special file"
    })
}

/// A numbered object of a file (a glTF scene, node or mesh): its index and, if the file gives
/// one, its name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Named {
    pub index: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
}

impl std::fmt::Display for Named {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.name {
            Some(n) => write!(f, "{} {n:?}", self.index),
            None => write!(f, "{}", self.index),
        }
    }
}

/// Why a glTF scene was the one drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SceneChoice {
    /// The file's `scene` (its default scene).
    Default,
    /// The file names no default scene: its first.
    First,
}

/// The glTF scene drawn, and why that one.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct DrawnScene {
    #[serde(flatten)]
    pub scene: Named,
    pub choice: SceneChoice,
}

/// Where a drawn triangle's normals came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalSource {
    /// The file's own (glTF `NORMAL`, PLY `nx ny nz`, OBJ `vn`).
    File,
    /// Computed smooth, as for an OBJ without normals ([`super::soup`]).
    Computed,
}

/// One glTF primitive drawn: the node that places it (none when the file has no scene and each
/// mesh is drawn once, untransformed), the mesh, the primitive's index in it, its triangles
/// (before zero-area ones are dropped) and where its normals came from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Part {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<Named>,
    pub mesh: Named,
    pub primitive: usize,
    pub triangles: usize,
    pub normals: NormalSource,
}

/// What a reader read and drew of a file: the outputs' provenance of a mesh (summary.json's
/// `mesh_input`, the report's provenance).
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct MeshInput {
    pub format: Format,
    pub encoding: Encoding,
    /// glTF: the scene drawn and why; none for OBJ and PLY, or a glTF without scenes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<DrawnScene>,
    /// glTF: every primitive drawn, in drawing order; empty for OBJ and PLY (the whole file).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<Part>,
}

impl MeshInput {
    /// A file read whole (OBJ, PLY): no scene, no parts.
    pub fn whole(format: Format, encoding: Encoding) -> Self {
        MeshInput {
            format,
            encoding,
            scene: None,
            parts: Vec::new(),
        }
    }

    /// One line for people: the format and encoding, and for glTF the scene and up to 8 of the
    /// parts drawn (the rest counted).
    pub fn describe(&self) -> String {
        let enc = match self.encoding {
            Encoding::Text => "text",
            Encoding::Json => ".gltf JSON",
            Encoding::Glb => ".glb binary",
            Encoding::Ascii => "ASCII",
            Encoding::BinaryLittleEndian => "binary little endian",
            Encoding::BinaryBigEndian => "binary big endian",
        };
        let mut s = format!("{} ({enc})", self.format.name());
        match &self.scene {
            Some(DrawnScene {
                scene,
                choice: SceneChoice::Default,
            }) => {
                let _ = write!(s, ", scene {scene} (the default scene)");
            }
            Some(DrawnScene {
                scene,
                choice: SceneChoice::First,
            }) => {
                let _ = write!(s, ", scene {scene} (no default scene: the first)");
            }
            None if self.format == Format::Gltf => s.push_str(", no scene: every mesh once"),
            None => {}
        }
        for (i, p) in self.parts.iter().enumerate() {
            if i == 8 {
                let _ = write!(s, "; and {} more primitives", self.parts.len() - 8);
                break;
            }
            let _ = write!(
                s,
                "{}mesh {} primitive {}",
                if i == 0 { ": " } else { "; " },
                p.mesh,
                p.primitive
            );
            if let Some(n) = &p.node {
                let _ = write!(s, " at node {n}");
            }
            let _ = write!(
                s,
                " ({}, normals {})",
                super::soup::plural(p.triangles, "triangle", "triangles"),
                match p.normals {
                    NormalSource::File => "from the file",
                    NormalSource::Computed => "computed",
                }
            );
        }
        s
    }
}
