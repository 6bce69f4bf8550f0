//! The compile store per method: a child's reply cut into one entry per method, so that a
//! request which shares methods with earlier ones (tune's candidates for another mesh beside
//! the same baselines, a report with one more method) compiles only what is new. A method's
//! programs are compiled on their own, in request order, and their rows are contiguous in a
//! reply (draw, then kernels; tests/store.rs checks that a merged reply equals a fresh one),
//! so the merge of per-method replies in the request's order is the reply of the whole.
use super::request::{ChildReport, ChildRequest};

/// `req` asking for `methods` alone (no probes: probes are compiled with the whole request).
pub fn sub_request(req: &ChildRequest, methods: &[String]) -> ChildRequest {
    ChildRequest {
        methods: methods.to_vec(),
        probes: Vec::new(),
        ..req.clone()
    }
}

/// `r` cut per method of `methods`: each part has the method's rows and skip notes and the
/// reply's device fields; `None` when a row names a method outside `methods` (a probe), so
/// that such a reply is not cut.
pub fn split(r: &ChildReport, methods: &[String]) -> Option<Vec<ChildReport>> {
    if r.compiled.iter().any(|c| !methods.contains(&c.method)) {
        return None;
    }
    let share = r.elapsed_ms / methods.len().max(1) as f64;
    Some(
        methods
            .iter()
            .map(|m| ChildReport {
                compiled: r
                    .compiled
                    .iter()
                    .filter(|c| &c.method == m)
                    .cloned()
                    .collect(),
                skipped: r
                    .skipped
                    .iter()
                    .filter(|s| s.split_once(": ").is_some_and(|(name, _)| name == m))
                    .cloned()
                    .collect(),
                elapsed_ms: share,
                ..r.clone()
            })
            .collect(),
    )
}

/// The reply of the whole request from its methods' parts, in the request's order: the device
/// fields of the first part, every part's rows and skip notes, the compile times added.
pub fn merge(parts: Vec<ChildReport>) -> Option<ChildReport> {
    let mut it = parts.into_iter();
    let mut whole = it.next()?;
    for p in it {
        whole.compiled.extend(p.compiled);
        whole.skipped.extend(p.skipped);
        whole.elapsed_ms += p.elapsed_ms;
    }
    Some(whole)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::isa::request::{Compiled, CompiledKind};

    fn row(method: &str, kind: CompiledKind) -> Compiled {
        Compiled {
            method: method.into(),
            program: method.into(),
            kind,
            repeat: None,
            executables: Vec::new(),
        }
    }

    fn reply(rows: Vec<Compiled>, skipped: &[&str]) -> ChildReport {
        ChildReport {
            family: "amd:navi21".into(),
            device_name: "d".into(),
            driver_name: "radv".into(),
            driver_info: "Mesa".into(),
            api_version: "1.3".into(),
            compiled: rows,
            elapsed_ms: 30.0,
            float16: Some(true),
            skipped: skipped.iter().map(|s| s.to_string()).collect(),
        }
    }

    #[test]
    fn a_reply_cut_per_method_merges_back_to_itself() {
        let methods: Vec<String> = ["phong_exact", "flat", "gouraud"].map(String::from).into();
        let whole = reply(
            vec![
                row("phong_exact", CompiledKind::Draw),
                row("phong_exact", CompiledKind::Kernel),
                row("flat", CompiledKind::Draw),
                row("gouraud", CompiledKind::Draw),
            ],
            &["gouraud: no gl_VertexID"],
        );
        let parts = split(&whole, &methods).unwrap();
        assert_eq!(parts.len(), 3);
        assert_eq!(parts[0].compiled.len(), 2);
        assert_eq!(parts[2].skipped, ["gouraud: no gl_VertexID"]);
        assert!(parts[1].skipped.is_empty());
        let back = merge(parts).unwrap();
        assert_eq!(
            serde_json::to_value(&back).unwrap(),
            serde_json::to_value(&whole).unwrap()
        );
        // Teeth: parts merged in another order are another reply.
        let mut parts = split(&whole, &methods).unwrap();
        parts.swap(0, 1);
        assert_ne!(
            serde_json::to_value(merge(parts).unwrap()).unwrap(),
            serde_json::to_value(&whole).unwrap()
        );
    }

    #[test]
    fn a_reply_with_a_probe_is_not_cut() {
        let whole = reply(
            vec![
                row("phong_exact", CompiledKind::Draw),
                row("probe_a", CompiledKind::Probe),
            ],
            &[],
        );
        assert!(split(&whole, &["phong_exact".to_string()]).is_none());
        assert!(merge(Vec::new()).is_none());
    }
}
