//! Rendered targets back to the host, bit for bit: out of a read-back buffer the driver copied
//! a target into, or in place from a host colour target (linear, mapped: no copy by the
//! driver), into a frame's vectors (a recycled frame's memory when there is one).
use crate::error::{Error, Result};
use crate::gpu::vk::{Buffer, Image, OneShot};

/// Read-back bytes as pixels, bit for bit, into a fresh vector ([`read_back_into`]).
pub(super) fn read_back<T: bytemuck::Pod>(bytes: &[u8]) -> Vec<T> {
    read_back_into(bytes, Vec::new())
}

/// Read-back bytes as pixels, bit for bit, into the memory of `into` (a frame handed back): its
/// length becomes exactly the pixels of `bytes` and every one of them is overwritten, whatever
/// it held or however long it was, so the result equals a fresh read-back. Its pages are warm,
/// so the copy takes no page faults (a fresh 16 MB vector per image faulted every page in). A
/// vector with too little room is dropped, not grown: growing would copy its stale contents.
/// A plain copy where the mapped memory is aligned for `T` (it always is: Vulkan maps at least
/// 64-byte aligned), else pixel by pixel; never zeroed first.
fn read_back_into<T: bytemuck::Pod>(bytes: &[u8], into: Vec<T>) -> Vec<T> {
    let n = bytes.len() / std::mem::size_of::<T>();
    let mut into = emptied(into, n);
    extend_pixels(&mut into, bytes);
    into
}

/// `into` emptied, with room for `n` pixels (a new vector when it has less: see
/// [`read_back_into`]).
fn emptied<T>(mut into: Vec<T>, n: usize) -> Vec<T> {
    into.clear();
    if into.capacity() < n {
        into = Vec::with_capacity(n);
    }
    into
}

/// Appends the pixels of `bytes` to `into`, bit for bit (aligned: one copy; else pixel by pixel).
fn extend_pixels<T: bytemuck::Pod>(into: &mut Vec<T>, bytes: &[u8]) {
    match bytemuck::try_cast_slice::<u8, T>(bytes) {
        Ok(pixels) => into.extend_from_slice(pixels),
        Err(_) => into.extend(
            bytes
                .chunks_exact(std::mem::size_of::<T>())
                .map(bytemuck::pod_read_unaligned::<T>),
        ),
    }
}

/// A colour target's pixels read into the memory of `into` as [`read_back_into`] does: in place
/// from a host target (row by row, zeroing it for the next render: [`Image::take_rows`]), else
/// from its read-back buffer.
pub(super) fn take_pixels(
    image: &mut Image,
    buf: Option<&Buffer>,
    into: Vec<[f32; 4]>,
) -> Result<Vec<[f32; 4]>> {
    let size = image.byte_size() as usize;
    match buf {
        Some(b) if !image.is_host_target() => Ok(read_back_into(&b.bytes()[..size], into)),
        _ => {
            let mut into = emptied(into, size / std::mem::size_of::<[f32; 4]>());
            image.take_rows(|row| extend_pixels(&mut into, row))?;
            Ok(into)
        }
    }
}

/// Records what makes a rendered colour target readable on the host: a host-read barrier for a
/// host target, else a copy into its read-back buffer.
pub(super) fn record_read(cmd: &mut OneShot, image: &Image, buf: Option<&Buffer>) -> Result<()> {
    match buf {
        _ if image.is_host_target() => cmd.make_host_readable(image),
        Some(b) => cmd.copy_image_to_buffer(image, b),
        None => {
            return Err(Error::Internal(
                "a copied colour target has no read-back buffer".into(),
            ))
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::read_back_into;

    /// Pixels as bytes, as a read-back buffer holds them.
    fn bytes(px: &[[f32; 4]]) -> Vec<u8> {
        bytemuck::cast_slice(px).to_vec()
    }

    #[test]
    fn read_back_into_overwrites_any_recycled_vector() {
        let px: Vec<[f32; 4]> = (0..50).map(|i| [i as f32, -0.0, 1.5, f32::MIN]).collect();
        let raw = bytes(&px);
        for stale in [0, 1, 49, 50, 51, 200] {
            let got = read_back_into(&raw, vec![[f32::NAN; 4]; stale]);
            assert_eq!(bytes(&got), raw, "recycled vector of {stale} pixels");
        }
        // The unaligned path (bytes at an odd address) gives the same pixels.
        let mut shifted = vec![0u8; raw.len() + 1];
        shifted[1..].copy_from_slice(&raw);
        let got = read_back_into::<[f32; 4]>(&shifted[1..], vec![[f32::NAN; 4]; 7]);
        assert_eq!(bytes(&got), raw);
        // Teeth: overwriting in place without taking the length from the bytes keeps the stale
        // tail, which the comparison above sees.
        let mut in_place = vec![[f32::NAN; 4]; 51];
        in_place[..50].copy_from_slice(&px);
        assert_ne!(bytes(&in_place), raw);
    }
}
