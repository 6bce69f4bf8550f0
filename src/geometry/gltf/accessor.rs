//! glTF buffers and accessors: each buffer read once when first used (the `.glb`'s BIN chunk, a
//! data URI or a regular file inside the `.gltf`'s folder: [`BUFFER_RULE`]), each accessor read with every byte range checked
//! before anything is allocated from a number in the file (glTF 2.0 sections 3.6.2 and 5.1).
use std::path::{Component, Path, PathBuf};

use ::gltf::json;
use base64::Engine as _;
use json::accessor::{ComponentType, Type};
use json::validation::Checked;

use crate::geometry::mesh_file::{ReadFile, Refused, BUFFER_RULE};

/// The buffers of a file, each loaded on first use.
pub(super) struct Buffers<'a> {
    root: &'a json::Root,
    /// The `.glb`'s BIN chunk.
    blob: Option<&'a [u8]>,
    /// The folder of the `.gltf`, that relative URIs are resolved against.
    dir: PathBuf,
    read: ReadFile<'a>,
    loaded: Vec<Option<Vec<u8>>>,
    /// Bytes of the file itself: with the buffers loaded so far, a bound on how many elements
    /// an accessor without a bufferView (zeros) may have.
    file_len: usize,
}

/// An accessor's elements as f32 vectors of `N` components (normalized integers mapped to
/// [-1, 1] or [0, 1], plain integers converted), or as u32 indices.
pub(super) type Vecs<const N: usize> = Vec<[f32; N]>;

impl<'a> Buffers<'a> {
    /// The buffers of `root`; `blob` is the `.glb`'s BIN chunk, `file` the path of the glTF
    /// file (`file_len` bytes), `read` reads a buffer's file.
    pub fn new(
        root: &'a json::Root,
        blob: Option<&'a [u8]>,
        file: &Path,
        file_len: usize,
        read: ReadFile<'a>,
    ) -> Self {
        Buffers {
            root,
            blob,
            dir: file.parent().unwrap_or(Path::new("")).to_path_buf(),
            read,
            loaded: vec![None; root.buffers.len()],
            file_len,
        }
    }

    /// The bytes of buffer `i` (exactly its `byteLength`), read on first use.
    fn buffer(&mut self, i: usize) -> Result<&[u8], String> {
        let b = self.root.buffers.get(i).ok_or_else(|| {
            format!(
                "buffer {i} does not exist (the file has {})",
                self.root.buffers.len()
            )
        })?;
        if self.loaded[i].is_none() {
            let what = match &b.name {
                Some(n) => format!("buffer {i} {n:?}"),
                None => format!("buffer {i}"),
            };
            let data = match &b.uri {
                None if i == 0 => self.blob.map(<[u8]>::to_vec).ok_or_else(|| {
                    format!("{what} has no uri and the file has no BIN chunk: give it a uri (a file beside the .gltf or a data URI)")
                })?,
                None => {
                    return Err(format!(
                        "{what} has no uri: only buffer 0 of a .glb may leave it out (its BIN chunk)"
                    ))
                }
                Some(uri) => self.fetch(&what, uri)?,
            };
            let want = b.byte_length.0;
            if (data.len() as u64) < want {
                return Err(format!(
                    "{what} is {} bytes, but its byteLength says {want}: the data is cut short (re-export or re-download the file)",
                    data.len()
                ));
            }
            self.loaded[i] = Some(data[..want as usize].to_vec());
        }
        Ok(self.loaded[i].as_deref().unwrap_or_default())
    }

    /// A buffer's bytes from its URI: a base64 data URI, or a relative file path
    /// (percent-encoded, RFC 3986 section 2.1) resolved against the `.gltf`'s folder, which
    /// it must not leave ([`BUFFER_RULE`]: checked here on the decoded path, before anything is
    /// read; links and the kind of file are the `read` function's to check, as
    /// [`crate::geometry::input::read_inside`] does).
    fn fetch(&self, what: &str, uri: &str) -> Result<Vec<u8>, String> {
        if let Some(rest) = uri.strip_prefix("data:") {
            let Some((_, payload)) = rest.split_once(";base64,") else {
                return Err(format!(
                    "{what}: its data URI is not base64 (`data:...;base64,...`)"
                ));
            };
            return base64::engine::general_purpose::STANDARD
                .decode(payload)
                .map_err(|e| format!("{what}: its data URI is not valid base64 ({e})"));
        }
        let scheme = uri.split_once(':').map(|(s, _)| s).filter(|s| {
            s.len() > 1
                && s.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
        });
        let rel = percent_decode(uri)
            .ok_or_else(|| format!("{what}: its uri {uri:?} has a bad %-escape"))?;
        let decoded = if rel == uri {
            String::new()
        } else {
            format!(" ({rel:?} once %-decoded)")
        };
        let copy = "; copy the file into the .gltf's folder and name it there";
        let refused =
            |why: &str| format!("{what}: its uri {uri:?}{decoded} {why}: {BUFFER_RULE}{copy}");
        if let Some(s) = scheme {
            return Err(refused(&format!("is a {s}: URI, not a relative file path")));
        }
        if Path::new(&rel).is_absolute() {
            return Err(refused("is an absolute path, not a relative one"));
        }
        if leaves_its_folder(Path::new(&rel)) {
            return Err(refused("leads outside the .gltf's folder (through `..`)"));
        }
        let file = self.dir.join(&rel);
        (self.read)(&file).map_err(|e| match e.get_ref().and_then(|r| r.downcast_ref::<Refused>()) {
            Some(why) => format!(
                "{what}: its uri {uri:?} names {}, which {why}: {BUFFER_RULE}{}",
                file.display(),
                if why.0.contains("outside") {
                    copy
                } else {
                    "; give a regular file"
                }
            ),
            None => format!(
                "{what}: cannot read its file {} ({e}): keep the .bin files beside the .gltf, or use the .glb",
                file.display()
            ),
        })
    }

    /// The bytes of buffer view `v` from `offset` on, and its stride.
    fn view(&mut self, v: usize) -> Result<(&[u8], Option<usize>), String> {
        let root = self.root;
        let view = root.buffer_views.get(v).ok_or_else(|| {
            format!(
                "bufferView {v} does not exist (the file has {})",
                root.buffer_views.len()
            )
        })?;
        let start = view.byte_offset.map_or(0, |o| o.0);
        let len = view.byte_length.0;
        let buffer = view.buffer.value();
        let data = self
            .buffer(buffer)
            .map_err(|e| format!("bufferView {v}: {e}"))?;
        let end = start
            .checked_add(len)
            .filter(|&e| e <= data.len() as u64)
            .ok_or_else(|| {
                format!(
                    "bufferView {v} spans bytes {start}..{} of buffer {buffer}, which has {}",
                    start as u128 + len as u128,
                    data.len()
                )
            })?;
        let stride = view.byte_stride.map(|s| s.0);
        Ok((&data[start as usize..end as usize], stride))
    }

    /// The elements of accessor `a` as `N`-vectors (`Vec3` accessors for `N` = 3).
    pub fn vecs<const N: usize>(&mut self, a: usize) -> Result<Vecs<N>, String> {
        let acc = self.accessor(a)?;
        let ty = checked(&acc.type_, "type")?;
        let want = match N {
            1 => Type::Scalar,
            2 => Type::Vec2,
            3 => Type::Vec3,
            _ => Type::Vec4,
        };
        if ty != want {
            return Err(format!("accessor {a} is {ty:?}, expected {want:?}"));
        }
        let ct = checked(&acc.component_type, "componentType")?.0;
        let mut out: Vecs<N> = match acc.buffer_view {
            Some(v) => {
                let count = usize::try_from(acc.count.0).unwrap_or(usize::MAX);
                let offset = acc.byte_offset.map_or(0, |o| o.0);
                let (bytes, stride) = self
                    .view(v.value())
                    .map_err(|e| format!("accessor {a}: {e}"))?;
                // The range check comes before the allocation it bounds.
                let e = Elements::new(bytes, offset, stride, ct, N, count)
                    .map_err(|e| format!("accessor {a} (bufferView {}): {e}", v.value()))?;
                (0..count)
                    .map(|i| std::array::from_fn(|k| e.get(i, k, acc.normalized)))
                    .collect()
            }
            None => vec![[0.0; N]; self.zeros_count(a, acc.count.0)?],
        };
        if let Some(sparse) = &acc.sparse {
            self.apply_sparse(a, sparse, ct, acc.normalized, &mut out)?;
        }
        Ok(out)
    }

    /// The elements of an index accessor (`SCALAR` of unsigned byte, short or int, not sparse).
    pub fn indices(&mut self, a: usize) -> Result<Vec<u32>, String> {
        let acc = self.accessor(a)?;
        let ct = checked(&acc.component_type, "componentType")?.0;
        if !matches!(
            ct,
            ComponentType::U8 | ComponentType::U16 | ComponentType::U32
        ) || checked(&acc.type_, "type")? != Type::Scalar
        {
            return Err(format!(
                "accessor {a} holds indices as {:?} of {ct:?}; glTF indices are scalars of unsigned byte, short or int",
                acc.type_
            ));
        }
        if acc.sparse.is_some() {
            return Err(format!(
                "accessor {a}: sparse index accessors are not read; write the indices out"
            ));
        }
        let count = usize::try_from(acc.count.0).unwrap_or(usize::MAX);
        let Some(v) = acc.buffer_view else {
            return Ok(vec![0; self.zeros_count(a, acc.count.0)?]);
        };
        let offset = acc.byte_offset.map_or(0, |o| o.0);
        let (bytes, stride) = self
            .view(v.value())
            .map_err(|e| format!("accessor {a}: {e}"))?;
        let e = Elements::new(bytes, offset, stride, ct, 1, count)
            .map_err(|e| format!("accessor {a} (bufferView {}): {e}", v.value()))?;
        Ok((0..count).map(|i| e.index(i)).collect())
    }

    fn accessor(&self, a: usize) -> Result<&'a json::Accessor, String> {
        let root = self.root;
        root.accessors.get(a).ok_or_else(|| {
            format!(
                "accessor {a} does not exist (the file has {})",
                root.accessors.len()
            )
        })
    }

    /// The count of an accessor without a bufferView (all zeros), refused when larger than
    /// the bytes read so far (the file and its buffers): a real one (a morph target's sparse
    /// deltas) never has more elements than its mesh's positions took bytes, and no allocation
    /// may be sized by a number the file made up.
    fn zeros_count(&self, a: usize, count: u64) -> Result<usize, String> {
        let read: usize = self.file_len + self.loaded.iter().flatten().map(Vec::len).sum::<usize>();
        if count > read as u64 {
            return Err(format!(
                "accessor {a} has no bufferView and count {count}, more elements than the {read} bytes read (the file and its buffers so far)"
            ));
        }
        Ok(count as usize)
    }

    fn apply_sparse<const N: usize>(
        &mut self,
        a: usize,
        sparse: &json::accessor::sparse::Sparse,
        ct: ComponentType,
        normalized: bool,
        out: &mut Vecs<N>,
    ) -> Result<(), String> {
        let n = usize::try_from(sparse.count.0).unwrap_or(usize::MAX);
        let ict = checked(
            &sparse.indices.component_type,
            "sparse.indices.componentType",
        )?
        .0;
        let iv = sparse.indices.buffer_view.value();
        let (bytes, _) = self
            .view(iv)
            .map_err(|e| format!("accessor {a} sparse indices: {e}"))?;
        let idx = Elements::new(bytes, sparse.indices.byte_offset.0, None, ict, 1, n)
            .map_err(|e| format!("accessor {a} sparse indices (bufferView {iv}): {e}"))?;
        if !matches!(
            ict,
            ComponentType::U8 | ComponentType::U16 | ComponentType::U32
        ) {
            return Err(format!(
                "accessor {a}: its sparse indices are {ict:?}, not unsigned integers"
            ));
        }
        let idx: Vec<usize> = (0..n).map(|i| idx.index(i) as usize).collect();
        let vv = sparse.values.buffer_view.value();
        let (bytes, _) = self
            .view(vv)
            .map_err(|e| format!("accessor {a} sparse values: {e}"))?;
        let vals = Elements::new(bytes, sparse.values.byte_offset.0, None, ct, N, n)
            .map_err(|e| format!("accessor {a} sparse values (bufferView {vv}): {e}"))?;
        let len = out.len();
        for (k, &i) in idx.iter().enumerate() {
            let o = out.get_mut(i).ok_or_else(|| {
                format!("accessor {a}: sparse index {i} (entry {k}) is past its {len} elements")
            })?;
            *o = std::array::from_fn(|c| vals.get(k, c, normalized));
        }
        Ok(())
    }
}

fn checked<T: Copy>(c: &Checked<T>, field: &str) -> Result<T, String> {
    match c {
        Checked::Valid(v) => Ok(*v),
        Checked::Invalid => Err(format!("its {field} is not one glTF 2.0 defines")),
    }
}

/// Bytes of one component.
fn component_size(ct: ComponentType) -> usize {
    match ct {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

/// The elements of an accessor inside its buffer view, after the range check.
struct Elements<'b> {
    bytes: &'b [u8],
    offset: usize,
    stride: usize,
    ct: ComponentType,
}

impl<'b> Elements<'b> {
    /// Checks that `count` elements of `n` components of `ct`, `stride` bytes apart (tightly
    /// packed when none), starting `offset` bytes in, lie inside `bytes`.
    fn new(
        bytes: &'b [u8],
        offset: u64,
        stride: Option<usize>,
        ct: ComponentType,
        n: usize,
        count: usize,
    ) -> Result<Self, String> {
        let size = component_size(ct) * n;
        let stride = stride.unwrap_or(size);
        if stride < size {
            return Err(format!(
                "its byteStride {stride} is smaller than one element ({size} bytes)"
            ));
        }
        if count == 0 {
            return Ok(Elements {
                bytes,
                offset: 0,
                stride,
                ct,
            });
        }
        let end = (count as u128 - 1) * stride as u128 + size as u128 + offset as u128;
        if end > bytes.len() as u128 {
            return Err(format!(
                "{count} elements of {size} bytes, {stride} apart from byte {offset}, need {end} bytes; the bufferView has {}: the accessor is out of range",
                bytes.len()
            ));
        }
        Ok(Elements {
            bytes,
            offset: offset as usize,
            stride,
            ct,
        })
    }

    /// Component `c` of element `i` as f32: floats as they are, normalized integers by the
    /// glTF 2.0 rule (section 3.11: signed `max(c / (2^(b-1) - 1), -1)`, unsigned
    /// `c / (2^b - 1)`), other integers converted.
    fn get(&self, i: usize, c: usize, normalized: bool) -> f32 {
        let at = self.offset + i * self.stride + c * component_size(self.ct);
        let b = &self.bytes[at..];
        match self.ct {
            ComponentType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            ComponentType::I8 => {
                let v = b[0] as i8 as f32;
                if normalized {
                    (v / 127.0).max(-1.0)
                } else {
                    v
                }
            }
            ComponentType::U8 => {
                let v = b[0] as f32;
                if normalized {
                    v / 255.0
                } else {
                    v
                }
            }
            ComponentType::I16 => {
                let v = i16::from_le_bytes([b[0], b[1]]) as f32;
                if normalized {
                    (v / 32767.0).max(-1.0)
                } else {
                    v
                }
            }
            ComponentType::U16 => {
                let v = u16::from_le_bytes([b[0], b[1]]) as f32;
                if normalized {
                    v / 65535.0
                } else {
                    v
                }
            }
            ComponentType::U32 => {
                let v = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32;
                if normalized {
                    v / 4294967295.0
                } else {
                    v
                }
            }
        }
    }
}

impl Elements<'_> {
    /// Element `i` of an unsigned integer scalar accessor, exactly.
    fn index(&self, i: usize) -> u32 {
        let b = &self.bytes[self.offset + i * self.stride..];
        match self.ct {
            ComponentType::U8 | ComponentType::I8 => u32::from(b[0]),
            ComponentType::U16 | ComponentType::I16 => u32::from(u16::from_le_bytes([b[0], b[1]])),
            ComponentType::U32 | ComponentType::F32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        }
    }
}

/// Whether the relative path `rel` climbs above the folder it starts in: more `..` than the
/// names before them (`a/../b` stays, `a/../../b` leaves), as written, before any link.
fn leaves_its_folder(rel: &Path) -> bool {
    let mut depth = 0usize;
    for c in rel.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth == 0 => return true,
            Component::ParentDir => depth -= 1,
            Component::RootDir | Component::Prefix(_) => return true,
        }
    }
    false
}

/// `%XX` escapes decoded (RFC 3986 section 2.1); `None` for a malformed escape or a result
/// that is not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_escapes_decode_and_bad_ones_are_refused() {
        assert_eq!(
            percent_decode("my%20mesh.bin").as_deref(),
            Some("my mesh.bin")
        );
        assert_eq!(percent_decode("a%2"), None);
        assert_eq!(percent_decode("a%zz"), None);
    }

    #[test]
    fn normalized_integers_follow_the_gltf_rule() {
        // -128 and -127 both map to -1 (the max(.., -1) clamp); 127 to 1.
        let bytes = [0x80u8, 0x81, 0x7f, 0x00];
        let e = Elements::new(&bytes, 0, None, ComponentType::I8, 1, 4).unwrap();
        let v: Vec<f32> = (0..4).map(|i| e.get(i, 0, true)).collect();
        assert_eq!(v, [-1.0, -1.0, 1.0, 0.0]);
        let s = [0xffu8, 0x7f, 0x01, 0x80];
        let e = Elements::new(&s, 0, None, ComponentType::I16, 1, 2).unwrap();
        assert_eq!([e.get(0, 0, true), e.get(1, 0, true)], [1.0, -1.0]);
        assert_eq!(e.get(0, 0, false), 32767.0);
    }

    #[test]
    fn an_element_past_the_view_is_refused_before_reading() {
        let bytes = [0u8; 24];
        // Two vec3 floats fit exactly; a third, or an offset of 4, does not.
        assert!(Elements::new(&bytes, 0, None, ComponentType::F32, 3, 2).is_ok());
        let e = Elements::new(&bytes, 0, None, ComponentType::F32, 3, 3)
            .err()
            .unwrap();
        assert!(e.contains("out of range"), "{e}");
        assert!(Elements::new(&bytes, 4, None, ComponentType::F32, 3, 2).is_err());
        // A stride below the element size is refused; a larger one is used.
        assert!(Elements::new(&bytes, 0, Some(8), ComponentType::F32, 3, 1).is_err());
        assert!(Elements::new(&bytes, 0, Some(16), ComponentType::F32, 2, 2).is_ok());
    }
}
