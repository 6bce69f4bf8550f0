//! Output files: every file the tool writes goes through [`write_atomic`], so an interrupted run
//! never leaves a truncated PNG, OBJ or NPY behind (temp file in the same directory + rename).
pub mod chart;
pub mod colormap;
pub mod heatmap;
pub mod provenance;
pub mod srgb;
mod steps;
pub mod terminal;

pub use provenance::Provenance;
pub use srgb::srgb8;
use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};

/// Writes `path` atomically: `fill` writes into a temporary file in the same directory, which is
/// flushed, synced and renamed over `path` only when `fill` succeeded. On error (or a panic)
/// the previous content of `path`, if any, is untouched, and the temporary file is removed; on
/// SIGINT/SIGTERM the signal's cleanup removes it, and after a SIGKILL the next run that writes
/// into the folder does ([`crate::cleanup`]: the name `.shadelab-<pid>-<n>.tmp` carries the
/// run's pid). Creates missing parent directories.
pub fn write_atomic<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    write_atomic_as(path, Durability::Synced, fill)
}

/// Whether a file is synced to disk before it is renamed into place. Either way it appears
/// whole or not at all to a run that is killed; only a power cut tells them apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Durability {
    /// fsync, then rename: every output but the bulk below.
    Synced,
    /// Renamed without an fsync of its own, for thousands of small files (isa's disassembly:
    /// 3.6 ms per fsync on the project's disk, 2026-11-28); their writer calls
    /// [`sync_filesystem`] once before its completion marker.
    Batched,
}

/// [`write_atomic`] with the given [`Durability`].
pub fn write_atomic_as<F>(path: &Path, durability: Durability, fill: F) -> Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    crate::cleanup::sweep_once(dir);
    let mut tmp = crate::cleanup::TempFile::create_in(dir).map_err(|e| Error::io(dir, e))?;
    {
        let mut w = std::io::BufWriter::new(tmp.file());
        fill(&mut w).map_err(|e| Error::io(path, e))?;
        w.flush().map_err(|e| Error::io(path, e))?;
    }
    if durability == Durability::Synced {
        tmp.file().sync_all().map_err(|e| Error::io(path, e))?;
    }
    // Outputs are ordinary files, readable like any other (0644).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(0o644))
            .map_err(|e| Error::io(path, e))?;
    }
    tmp.persist(path).map_err(|e| Error::io(path, e))?;
    Ok(())
}

/// Flushes every file written so far on the filesystem of `dir` to disk (syncfs): once after
/// many [`Durability::Batched`] writes.
pub fn sync_filesystem(dir: &Path) -> Result<()> {
    let f = std::fs::File::open(dir).map_err(|e| Error::io(dir, e))?;
    use std::os::fd::AsRawFd;
    // SAFETY: a plain system call on a descriptor this function owns.
    if unsafe { libc::syncfs(f.as_raw_fd()) } != 0 {
        return Err(Error::io(dir, std::io::Error::last_os_error()));
    }
    Ok(())
}

/// Removes the completion marker `path` of an earlier run (none is fine): a run calls it when
/// it starts and writes the marker last, so a run that fails in between never leaves a marker
/// of its own nor its predecessor's (docs/testing.md lists each command's marker).
pub fn remove_marker(path: &Path) -> Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::io(path, e)),
        _ => Ok(()),
    }
}

/// [`write_atomic`] for a byte buffer already in memory.
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic(path, |w| w.write_all(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_whole_file_and_creates_parents() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a/b/c.txt");
        write_bytes_atomic(&p, b"hello").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"hello");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            assert_eq!(
                std::fs::metadata(&p).unwrap().permissions().mode() & 0o777,
                0o644
            );
        }
    }

    #[test]
    fn failed_write_keeps_old_content_and_leaves_no_temp_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.png");
        std::fs::write(&p, b"old").unwrap();
        let r = write_atomic(&p, |w| {
            w.write_all(b"partial")?;
            Err(std::io::Error::other("interrupted"))
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        let leftovers: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(leftovers, vec![std::ffi::OsString::from("out.png")]);
    }
}

/// An alpha value as 8 bits (clamped to [0, 1]; NaN becomes 0).
pub fn alpha8(a: f32) -> u8 {
    (a.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// Writes a linear RGBA float image as an 8-bit sRGB PNG (alpha kept: 0 on the background).
/// NaN and Inf become 0.
pub fn write_png_srgb(path: &Path, width: u32, height: u32, pixels: &[[f32; 4]]) -> Result<()> {
    let bytes: Vec<u8> = pixels
        .iter()
        .flat_map(|p| [srgb8(p[0]), srgb8(p[1]), srgb8(p[2]), alpha8(p[3])])
        .collect();
    write_png_rgba8(path, width, height, &bytes)
}

/// Writes 8-bit RGBA bytes as a PNG.
pub fn write_png_rgba8(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<()> {
    use image::ImageEncoder;
    write_atomic(path, |w| {
        // zlib level 4, rows unfiltered: on the report's 222 renders of the shipped scenes
        // 5.4 MB against 8.8 MB at the fast level, about 2 ms each (busy); the default level
        // (6) saves 0.2 MB more for twice the time, and the Sub filter 0.5 MB for four times.
        image::codecs::png::PngEncoder::new_with_quality(
            w,
            image::codecs::png::CompressionType::Level(4),
            image::codecs::png::FilterType::NoFilter,
        )
        .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
        .map_err(std::io::Error::other)
    })
}

/// Writes a float image as a NumPy `.npy` array of shape (height, width, 4), dtype `<f4`,
/// rows from the top of the image: `numpy.load(path)` reads it.
pub fn write_npy_rgba(path: &Path, width: u32, height: u32, pixels: &[[f32; 4]]) -> Result<()> {
    use npyz::WriterBuilder;
    write_atomic(path, |w| {
        let mut npy = npyz::WriteOptions::<f32>::new()
            .default_dtype()
            .shape(&[height as u64, width as u64, 4])
            .writer(w)
            .begin_nd()?;
        npy.extend(pixels.iter().flatten().copied())?;
        npy.finish()
    })
}

#[cfg(test)]
mod image_tests {
    use super::*;

    #[test]
    fn srgb_endpoints_and_midpoint() {
        assert_eq!(srgb8(0.0), 0);
        assert_eq!(srgb8(1.0), 255);
        assert_eq!(srgb8(2.0), 255);
        assert_eq!(srgb8(f32::NAN), 0);
        // linear 0.5 is sRGB 0.7354 -> 188
        assert_eq!(srgb8(0.5), 188);
    }

    #[test]
    fn npy_header_and_payload() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.npy");
        let px = [[1.0f32, 2.0, 3.0, 4.0], [5.0, 6.0, 7.0, 8.0]];
        write_npy_rgba(&p, 2, 1, &px).unwrap();
        let bytes = std::fs::read(&p).unwrap();
        assert_eq!(&bytes[..6], b"\x93NUMPY");
        let header = String::from_utf8_lossy(&bytes[10..bytes.len() - 32]);
        // npyz writes a trailing comma, "(1, 2, 4, )", which Python reads as the same tuple.
        assert!(
            header.contains("'shape': (1, 2, 4") && header.contains("<f4"),
            "{header}"
        );
        let payload: Vec<f32> = bytes[bytes.len() - 32..]
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(payload, px.iter().flatten().copied().collect::<Vec<_>>());
    }

    #[test]
    fn png_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.png");
        write_png_srgb(&p, 2, 1, &[[1.0, 0.0, 0.5, 1.0], [0.0; 4]]).unwrap();
        let img = image::open(&p).unwrap().to_rgba8();
        assert_eq!(img.dimensions(), (2, 1));
        assert_eq!(img.get_pixel(0, 0).0, [255, 0, 188, 255]);
        assert_eq!(img.get_pixel(1, 0).0, [0, 0, 0, 0]);
    }
}

/// A progress bar on stderr, drawn only when `enabled` and stderr is a terminal.
pub fn progress_bar(enabled: bool, n: u64) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !enabled || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(n);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg} ({elapsed})")
    {
        bar.set_style(style);
    }
    bar
}
