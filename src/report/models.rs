//! Cost models as a person names them: by vendor and family ("AMD (all 6)", "Intel tgl,
//! adl"), and the whole set in words ([`scope`]), read from each model's typed id
//! ([`CostModelId::kind`]), never from its text.
use crate::cost::{CostKind, CostModel, CostModelId, IdKind};
use crate::method::Precision;

/// A cost model's vendor (or source) as a key and as a person names it: a GPU family's vendor
/// by the name its route gives ([`crate::isa::route::Vendor::name`]: `isa:intel:tgl` is
/// Intel's), a bare chip's a GPU's, lavapipe's timings lavapipe's, any other model its own.
pub fn vendor_of(id: &CostModelId) -> (String, String) {
    match id.kind() {
        IdKind::Isa {
            vendor: Some(v), ..
        } => {
            let shown = crate::isa::route::VENDORS
                .iter()
                .find(|x| x.prefix() == v)
                .map_or(v.as_str(), |x| x.name());
            (v.clone(), shown.to_string())
        }
        IdKind::Isa { vendor: None, .. } => ("isa".into(), "GPU".into()),
        IdKind::Lavapipe => ("lavapipe".into(), "lavapipe".into()),
        IdKind::Other => (id.to_string(), id.to_string()),
    }
}

/// `ids` (a subset of `all`) named compactly: a vendor's every family in one precision as
/// "AMD (all 6)", a part of them as "Intel tgl, adl", other models by their title.
pub fn describe(ids: &[CostModelId], all: &[CostModel]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut done: Vec<(String, Precision)> = Vec::new();
    for m in all.iter().filter(|m| ids.contains(&m.id)) {
        if m.kind != CostKind::Static {
            parts.push(m.title.clone());
            continue;
        }
        let (v, shown) = vendor_of(&m.id);
        if done.contains(&(v.clone(), m.precision)) {
            continue;
        }
        done.push((v.clone(), m.precision));
        let same = |x: &&CostModel| {
            x.kind == CostKind::Static && x.precision == m.precision && vendor_of(&x.id).0 == v
        };
        let group: Vec<&CostModel> = all.iter().filter(same).collect();
        let members: Vec<&str> = group
            .iter()
            .filter(|x| ids.contains(&x.id))
            .map(|x| x.id.chip().unwrap_or(x.id.as_str()))
            .collect();
        let f16 = if m.precision == Precision::F16 {
            " float16"
        } else {
            ""
        };
        parts.push(if members.len() == group.len() && group.len() > 1 {
            format!("{shown}{f16} (all {})", group.len())
        } else {
            format!("{shown}{f16} {}", members.join(", "))
        });
    }
    parts.join("; ")
}

/// What the models are, in words: "lavapipe frame time, ..., and the static cost of 18 GPU
/// families of 4 vendors (AMD 6, Intel 5, NVIDIA 5, TeraScale 2), 9 of them in float16 too".
pub fn scope(all: &[CostModel]) -> String {
    let mut parts: Vec<String> = all
        .iter()
        .filter(|m| m.kind != CostKind::Static)
        .map(|m| m.title.clone())
        .collect();
    let statics = |p: Precision| -> Vec<&CostModel> {
        all.iter()
            .filter(|m| m.kind == CostKind::Static && m.precision == p)
            .collect()
    };
    let (f32s, f16s) = (statics(Precision::F32), statics(Precision::F16));
    let mut vendors: Vec<(String, usize)> = Vec::new();
    for m in &f32s {
        let shown = vendor_of(&m.id).1;
        match vendors.iter_mut().find(|(v, _)| *v == shown) {
            Some((_, n)) => *n += 1,
            None => vendors.push((shown, 1)),
        }
    }
    if !f32s.is_empty() {
        let by: Vec<String> = vendors.iter().map(|(v, n)| format!("{v} {n}")).collect();
        let mut s = format!(
            "the static cost of {} GPU {} of {} {} ({})",
            f32s.len(),
            plural(f32s.len(), "family", "families"),
            vendors.len(),
            plural(vendors.len(), "vendor", "vendors"),
            by.join(", ")
        );
        if !f16s.is_empty() {
            s += &format!(", {} of them in float16 too", f16s.len());
        }
        parts.push(s);
    } else if !f16s.is_empty() {
        parts.push(format!(
            "the static cost of {} GPU {} in float16",
            f16s.len(),
            plural(f16s.len(), "family", "families")
        ));
    }
    match parts.len() {
        0 => String::new(),
        1 => parts.remove(0),
        n => format!("{} and {}", parts[..n - 1].join(", "), parts[n - 1]),
    }
}

/// `a, b and c`.
pub(super) fn and_list(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

pub(super) fn plural<'a>(n: usize, one: &'a str, many: &'a str) -> &'a str {
    if n == 1 {
        one
    } else {
        many
    }
}
