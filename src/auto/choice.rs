//! `auto`'s per-triangle choice: the cheapest method (in a given cost order) whose f64 error on
//! each triangle stays within the budget, judged before drawing from the triangle's vertex
//! normals and the scene's lighting (lights, H, shininess) at a grid of barycentric samples; and
//! its cache (this process, then disk).
//!
//! A tuned row (`shadelab tune`'s file, [`crate::method::tuned`]) is proven only on its domain
//! of z: it is drawn on a triangle only when the triangle's exact range of z
//! ([`crate::geometry::zdomain::triangle_z_range`]) lies inside that domain ([`licensed`]),
//! the proof licensing it; the samples are judged on top, as for every method.
use glam::DVec3;

use crate::scene::SceneInputs;

/// The sampled error is doubled before it is compared with the budget: the samples may miss
/// the peak between them.
pub const AUTO_MARGIN: f64 = 1.0;
/// Subdivisions of the barycentric sample grid per triangle edge ((n+1)(n+2)/2 samples).
pub const AUTO_GRID: usize = 6;

/// The barycentric weights of the sample grid ([`AUTO_GRID`]).
fn sample_weights() -> Vec<DVec3> {
    let n = AUTO_GRID;
    (0..=n)
        .flat_map(|i| (0..=n - i).map(move |j| (i, j)))
        .map(|(i, j)| {
            let (a, b) = (i as f64 / n as f64, j as f64 / n as f64);
            DVec3::new(1.0 - a - b, a, b)
        })
        .collect()
}

/// Triangle `t`'s samples and their exact colours.
fn samples(
    inputs: &SceneInputs,
    lighting: &crate::method::formulas::Lighting,
    weights: &[DVec3],
    t: usize,
) -> (Vec<crate::method::twins::Fragment>, Vec<DVec3>) {
    let frags: Vec<_> = weights
        .iter()
        .map(|&w| inputs.fragment(t, w, glam::DVec2::ZERO))
        .collect();
    let exact = frags
        .iter()
        .map(|f| {
            lighting.shade(crate::method::formulas::normalize_exact(
                f.interpolated_normal(),
            ))
        })
        .collect();
    (frags, exact)
}

/// Where each method may be drawn: the proven domain of z of a tuned row, None (anywhere) for
/// the others.
pub fn licences(order: &[&'static crate::method::Method]) -> Vec<Option<[f64; 2]>> {
    order
        .iter()
        .map(|m| crate::method::tuned::proven_domain(m))
        .collect()
}

/// Whether a method with `licence` ([`licences`]) may be drawn on triangle `t`: anywhere
/// without one; for a tuned row only when the triangle's range of z lies inside its proven
/// domain.
pub fn licensed(licence: Option<[f64; 2]>, inputs: &SceneInputs, t: usize) -> bool {
    licence.is_none_or(|[lo, hi]| {
        let z = crate::geometry::zdomain::triangle_z_range(inputs.vertex_normals(t));
        z.lo >= lo && z.hi <= hi
    })
}

/// Whether `m` keeps the budget (with the margin) at every sample.
fn passes(
    m: &crate::method::Method,
    lighting: &crate::method::formulas::Lighting,
    (frags, exact): &(Vec<crate::method::twins::Fragment>, Vec<DVec3>),
    budget: f64,
) -> bool {
    frags.iter().zip(exact).all(|(f, e)| {
        let c = m.eval_f64(f, lighting).color;
        let err = super::colour_error((c - *e).abs().to_array());
        err.is_finite() && err * (1.0 + AUTO_MARGIN) <= budget
    })
}

/// Whether `m` keeps the budget on every triangle of `triangles` by the same test as
/// [`choose`] (the grouping's merges check what they move).
pub fn within_budget(
    inputs: &SceneInputs,
    m: &crate::method::Method,
    triangles: &[usize],
    budget: f64,
) -> bool {
    let lighting = inputs.lighting();
    let weights = sample_weights();
    let licence = crate::method::tuned::proven_domain(m);
    triangles.iter().all(|&t| {
        licensed(licence, inputs, t)
            && passes(
                m,
                &lighting,
                &samples(inputs, &lighting, &weights, t),
                budget,
            )
    })
}

/// The per-triangle choice: index into `order` for every triangle of `inputs`.
pub fn choose(
    inputs: &SceneInputs,
    order: &[&'static crate::method::Method],
    budget: f64,
) -> Vec<usize> {
    let lighting = inputs.lighting();
    let weights = sample_weights();
    let tris = inputs.triangle_count();
    let licence = licences(order);
    let pick = |t: usize| -> usize {
        let s = samples(inputs, &lighting, &weights, t);
        order
            .iter()
            .zip(&licence)
            .position(|(m, l)| licensed(*l, inputs, t) && passes(m, &lighting, &s, budget))
            .unwrap_or(order.len() - 1)
    };
    // A worker that panicked (a bug) gives no choice at all.
    crate::parallel::map_indices(tris, pick).unwrap_or_default()
}

/// Where a choice came from: computed now, or found in the cache of this process or on disk.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ChoiceSource {
    Computed,
    Memory,
    Disk,
}

/// The code a choice depends on: this file, the budget's error definition, and the f64 methods it
/// evaluates. Part of [`cache_key`] (a stale cache entry from a build with other formulas was
/// read as valid before).
pub const CHOICE_SOURCES: [&str; 8] = [
    include_str!("choice.rs"),
    include_str!("../method/tuned.rs"),
    include_str!("../geometry/zdomain.rs"),
    include_str!("mod.rs"),
    include_str!("../method/formulas.rs"),
    include_str!("../method/scanline.rs"),
    include_str!("../method/twins.rs"),
    include_str!("../method/table.rs"),
];

/// A cached per-triangle choice and where it came from.
#[derive(Debug, Clone)]
pub struct Choice {
    pub pick: Vec<usize>,
    pub source: ChoiceSource,
}

/// The cache key of a choice: SHA-256 of everything [`choose`] reads (the triangles' window
/// corners and normals, the lighting and material as uploaded, the candidates in order, the
/// budget, the margin and the sample grid), the crate version, and the source of the code that
/// computes the choice ([`CHOICE_SOURCES`]), so a build whose formulas or error definition differ
/// never reads another build's choices.
pub fn cache_key(
    inputs: &SceneInputs,
    order: &[&'static crate::method::Method],
    budget: f64,
) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    h.update(b"shadelab auto choice 1\0");
    h.update(env!("CARGO_PKG_VERSION").as_bytes());
    for source in CHOICE_SOURCES {
        h.update(source.as_bytes());
    }
    h.update(AUTO_MARGIN.to_le_bytes());
    h.update((AUTO_GRID as u64).to_le_bytes());
    h.update(budget.to_le_bytes());
    for m in order {
        h.update(m.name.as_bytes());
        h.update(b"\0");
        // a method file's bytes (a tuned row's coefficients and domain)
        if let Some(u) = crate::method::user::of(m) {
            h.update(u.sha256.as_bytes());
        }
    }
    h.update((inputs.triangle_count() as u64).to_le_bytes());
    h.update(bytemuck::cast_slice::<[f32; 2], u8>(&inputs.window));
    h.update(bytemuck::cast_slice::<[f32; 3], u8>(&inputs.view_normals));
    h.update(bytemuck::cast_slice::<[f32; 3], u8>(&inputs.flat_normals));
    h.update(bytemuck::cast_slice::<[[f32; 3]; 3], u8>(&inputs.pn_mids));
    h.update(bytemuck::bytes_of(&inputs.params));
    h.update(inputs.light_count.to_le_bytes());
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// The folder of the on-disk cache: `$SHADELAB_CACHE_DIR` (empty: no disk cache), else
/// `$XDG_CACHE_HOME/shadelab`, else `$HOME/.cache/shadelab`.
pub fn cache_dir() -> Option<std::path::PathBuf> {
    use std::path::PathBuf;
    let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty());
    if let Some(v) = std::env::var_os("SHADELAB_CACHE_DIR") {
        return (!v.is_empty()).then(|| PathBuf::from(v));
    }
    var("XDG_CACHE_HOME")
        .map(|d| PathBuf::from(d).join("shadelab"))
        .or_else(|| var("HOME").map(|h| PathBuf::from(h).join(".cache").join("shadelab")))
}

static MEMORY: std::sync::Mutex<Vec<(String, Vec<usize>)>> = std::sync::Mutex::new(Vec::new());

/// [`choose`], cached per mesh, camera, lights, material, candidates and budget ([`cache_key`]):
/// first in this process, then on disk (`<cache_dir>/auto/<key>.json`, written atomically); an
/// entry that does not fit the scene (wrong length, an index beyond the candidates) is ignored
/// and recomputed. A cache that cannot be written is skipped with a note on stderr.
pub fn choose_cached(
    inputs: &SceneInputs,
    order: &[&'static crate::method::Method],
    budget: f64,
) -> Choice {
    choose_cached_in(inputs, order, budget, cache_dir().as_deref())
}

/// [`choose_cached`] with the disk cache in `dir` (None: this process's cache only).
pub fn choose_cached_in(
    inputs: &SceneInputs,
    order: &[&'static crate::method::Method],
    budget: f64,
    dir: Option<&std::path::Path>,
) -> Choice {
    let key = cache_key(inputs, order, budget);
    let fits =
        |p: &[usize]| p.len() == inputs.triangle_count() && p.iter().all(|&k| k < order.len());
    if let Ok(m) = MEMORY.lock() {
        if let Some((_, p)) = m.iter().find(|(k, p)| *k == key && fits(p)) {
            return Choice {
                pick: p.clone(),
                source: ChoiceSource::Memory,
            };
        }
    }
    let file = dir.map(|d| d.join("auto").join(format!("{key}.json")));
    let from_disk = file
        .as_ref()
        .and_then(|f| std::fs::read(f).ok())
        .and_then(|b| serde_json::from_slice::<Vec<usize>>(&b).ok())
        .filter(|p| fits(p));
    let (pick, source) = match from_disk {
        Some(p) => (p, ChoiceSource::Disk),
        None => {
            let p = choose(inputs, order, budget);
            if let Some(f) = &file {
                let written = serde_json::to_vec(&p)
                    .map_err(|e| e.to_string())
                    .and_then(|b| {
                        if let Some(d) = f.parent() {
                            std::fs::create_dir_all(d).map_err(|e| e.to_string())?;
                        }
                        crate::output::write_bytes_atomic(f, &b).map_err(|e| e.to_string())
                    });
                if let Err(e) = written {
                    log::warn!("auto: choice not cached on disk ({}): {e}", f.display());
                }
            }
            (p, ChoiceSource::Computed)
        }
    };
    if let Ok(mut m) = MEMORY.lock() {
        m.push((key, pick.clone()));
    }
    Choice { pick, source }
}

/// Drops `key` from this process's cache (tests).
#[cfg(test)]
fn forget(key: &str) {
    if let Ok(mut m) = MEMORY.lock() {
        m.retain(|(k, _)| k != key);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn torus() -> SceneInputs {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/torus.toml");
        let scene = crate::scene::load_scene(&path).unwrap();
        SceneInputs::new(&scene, crate::method::Geometry::Mesh)
    }

    fn order() -> Vec<&'static crate::method::Method> {
        let m = |n| crate::method::find(n).unwrap();
        vec![
            crate::method::vertex_lit_reference(),
            m("newton_raphson"),
            crate::method::phong_exact(),
        ]
    }

    /// Computed once, then found in memory, then on disk; the same choice every time; a disk
    /// entry that does not fit the scene is recomputed; another budget is another entry.
    #[test]
    fn a_choice_is_cached_in_memory_and_on_disk() {
        let dir = tempfile::tempdir().unwrap();
        let (inputs, order) = (torus(), order());
        // A budget no other test uses, so that no other test fills this entry.
        let budget = 0.003_141_59;
        let key = cache_key(&inputs, &order, budget);
        let first = choose_cached_in(&inputs, &order, budget, Some(dir.path()));
        assert_eq!(first.source, ChoiceSource::Computed);
        assert_eq!(first.pick, choose(&inputs, &order, budget));
        let second = choose_cached_in(&inputs, &order, budget, Some(dir.path()));
        assert_eq!(second.source, ChoiceSource::Memory);
        assert_eq!(second.pick, first.pick);
        forget(&key);
        let third = choose_cached_in(&inputs, &order, budget, Some(dir.path()));
        assert_eq!(third.source, ChoiceSource::Disk);
        assert_eq!(third.pick, first.pick);
        // Teeth: a disk entry of the wrong length is not used.
        forget(&key);
        let file = dir.path().join("auto").join(format!("{key}.json"));
        std::fs::write(&file, "[0, 1]").unwrap();
        let fourth = choose_cached_in(&inputs, &order, budget, Some(dir.path()));
        assert_eq!(fourth.source, ChoiceSource::Computed);
        assert_eq!(fourth.pick, first.pick);
        // The key follows the budget and the candidates.
        assert_ne!(cache_key(&inputs, &order, budget * 2.0), key);
        assert_ne!(cache_key(&inputs, &order[1..], budget), key);
    }
}
