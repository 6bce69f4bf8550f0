//! Memory before it is allocated: what a job needs at an image size ([`Need`]: bytes per pixel
//! and a fixed part, measured) against what the machine has (`MemAvailable` of /proc/meminfo,
//! or `SHADELAB_MEMORY` to cap it) and, for the device's images, the device's largest heap. A
//! size that does not fit is refused (exit 2) with what it needs, what there is and the largest
//! size that fits, before any image is allocated: 16384x16384, the size cap, needs about 48 GB
//! in compare, and failed late with "vkBindImageMemory failed: ERROR_OUT_OF_DEVICE_MEMORY" or
//! an abort.
use crate::error::{Error, Result};

/// What a job needs: `per_pixel` bytes for each pixel of its image size, plus `fixed`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Need {
    /// The job, in the message ("compare").
    pub job: &'static str,
    pub per_pixel: u64,
    pub fixed: u64,
}

const MB: u64 = 1 << 20;

/// The device's images of a draw and their read-back (colour and normal targets, ids,
/// weights, depth) plus the process's fixed part: peak RSS (`/usr/bin/time -f %M`) of `render`
/// on sphere_coarse, lavapipe, 2026-11-28, the project's 2-core AMD EPYC: 130 MiB at
/// 1024x1024, 252 MiB at 2048x2048, 736 MiB at 4096x4096 (39 bytes per pixel and 93 MiB), and
/// 1248 MiB at 4096x4096 with `--float --normals` (72 bytes per pixel: the normal target too).
pub const DRAW: Need = Need {
    job: "a draw",
    per_pixel: 72,
    fixed: 100 * MB,
};

/// `compare` of one method: the draw, the f64 truth and its prepared reference, FLIP's
/// images, the metrics: peak RSS of `compare --methods phong_exact` on sphere_coarse (as
/// [`DRAW`]) at 2048x2048 (837 MiB) and 4096x4096 (3041 MiB): a slope of 175 bytes per pixel
/// (180 taken) and 105 MiB.
pub const COMPARE: Need = Need {
    job: "compare",
    per_pixel: 180,
    fixed: 110 * MB,
};

/// Each method compare analyses beside the first (two workers: at most two more at a time):
/// 46 bytes per pixel (2 methods at 2048x2048: 1024 MiB; 4: 1195 MiB).
pub const COMPARE_PER_EXTRA_METHOD: u64 = 46;

/// [`COMPARE`] for `methods` methods analysed (at most three at a time).
pub fn compare(methods: usize) -> Need {
    Need {
        per_pixel: COMPARE.per_pixel
            + COMPARE_PER_EXTRA_METHOD * methods.saturating_sub(1).min(2) as u64,
        ..COMPARE
    }
}

impl Need {
    /// Bytes at `width` x `height`.
    pub fn bytes(&self, width: u32, height: u32) -> u64 {
        self.fixed + self.per_pixel * u64::from(width) * u64::from(height)
    }
}

/// The memory a run may use: `SHADELAB_MEMORY` (bytes, or with a K, M, G or T suffix) when
/// set, else `MemAvailable` of /proc/meminfo; None when neither can be read.
pub fn available() -> Option<u64> {
    if let Some(v) = std::env::var("SHADELAB_MEMORY")
        .ok()
        .filter(|v| !v.is_empty())
    {
        return parse_bytes(&v);
    }
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    proc_bytes(&text, "MemAvailable:")
}

/// The value of the line starting with `key` (`MemAvailable:`, `VmRSS:`) of a /proc file in
/// kB (/proc/meminfo, /proc/PID/status, proc(5)), as bytes.
pub fn proc_bytes(text: &str, key: &str) -> Option<u64> {
    let kb: u64 = text
        .lines()
        .find_map(|l| l.strip_prefix(key))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb * 1024)
}

/// `123`, `4G`, `512M`... as bytes.
pub fn parse_bytes(s: &str) -> Option<u64> {
    let s = s.trim();
    let (num, unit) = match s.char_indices().find(|(_, c)| c.is_ascii_alphabetic()) {
        Some((i, _)) => (&s[..i], &s[i..]),
        None => (s, ""),
    };
    let scale: u64 = match unit.to_ascii_uppercase().trim_end_matches('B') {
        "" => 1,
        "K" => 1 << 10,
        "M" => 1 << 20,
        "G" => 1 << 30,
        "T" => 1 << 40,
        _ => return None,
    };
    let v: f64 = num.trim().parse().ok()?;
    (v.is_finite() && v >= 0.0).then_some((v * scale as f64) as u64)
}

fn gb(b: u64) -> String {
    format!("{:.1} GB", b as f64 / 1e9)
}

/// Refuses `width` x `height` when `need` does not fit the memory a run may use
/// ([`available`]) or, given, the device heap `heap` (bytes): the message says how much it
/// needs, what there is, the largest square that fits and what to lower. An unknown amount of
/// memory refuses nothing.
pub fn check(need: &Need, width: u32, height: u32, heap: Option<u64>) -> Result<()> {
    check_against(need, width, height, available(), heap)
}

/// [`check`] against `available` bytes.
pub fn check_against(
    need: &Need,
    width: u32,
    height: u32,
    available: Option<u64>,
    heap: Option<u64>,
) -> Result<()> {
    let limits: Vec<(u64, String)> = available
        .map(|a| (a, format!("{} available", gb(a))))
        .into_iter()
        .chain(heap.map(|h| (h, format!("the device's heap is {}", gb(h)))))
        .collect();
    let Some((room, _)) = limits.iter().min_by_key(|(b, _)| *b) else {
        return Ok(());
    };
    let bytes = need.bytes(width, height);
    if bytes <= *room {
        return Ok(());
    }
    let side = (room.saturating_sub(need.fixed) / need.per_pixel.max(1)) as f64;
    let side = side.sqrt().floor() as u64;
    let how = limits
        .iter()
        .map(|(_, s)| s.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    Err(Error::Usage(format!(
        "{} at {width}x{height} needs about {} ({} bytes per pixel, measured), and {how}: lower \
         the image size (--size, or [image] width and height; at most about {side}x{side} here), \
         or set SHADELAB_MEMORY to the memory it may use",
        need.job,
        gb(bytes),
        need.per_pixel
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The arithmetic of the estimate and the refusal, on made-up machines.
    #[test]
    fn a_size_that_does_not_fit_is_refused_with_figures() {
        let gib = 1u64 << 30;
        // the measured peaks are what the model gives (within 5 %)
        let near = |got: u64, want_mb: f64| ((got as f64 / MB as f64) / want_mb - 1.0).abs() < 0.05;
        assert!(near(compare(1).bytes(4096, 4096), 3041.0));
        assert!(near(compare(1).bytes(2048, 2048), 837.0));
        assert!(near(compare(2).bytes(2048, 2048), 1024.0));
        assert!(near(compare(3).bytes(2048, 2048), 1195.0));
        assert!(near(DRAW.bytes(4096, 4096), 1248.0));
        // 16384x16384 compare: about 48 GB
        let e = check_against(&compare(1), 16384, 16384, Some(22 * gib), None)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("compare at 16384x16384 needs about 48.")
                && e.contains("23.6 GB available"),
            "{e}"
        );
        assert!(
            e.contains("at most about 11") && e.contains("--size"),
            "{e}"
        );
        // the heap counts when it is the smaller
        let e = check_against(&DRAW, 8192, 8192, Some(64 * gib), Some(2 * gib))
            .unwrap_err()
            .to_string();
        assert!(e.contains("the device's heap is 2.1 GB"), "{e}");
        assert!(check_against(&compare(3), 1024, 1024, Some(gib), None).is_ok());
        assert!(check_against(&compare(3), 16384, 16384, None, None).is_ok());
        assert_eq!(parse_bytes("4G"), Some(4 * gib));
        assert_eq!(parse_bytes("512 MB"), Some(512 * MB));
        assert_eq!(parse_bytes("12"), Some(12));
        assert_eq!(parse_bytes("lots"), None);
    }
}
