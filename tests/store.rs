//! The compile store (src/isa/store.rs) on real compilers: figures read from it equal freshly
//! compiled ones on every family that is set up (with teeth: a doctored entry is told apart),
//! a corrupt entry is detected, removed and compiled again, a changed compiler identity (a
//! route's file rebuilt) misses, two processes filling the store at once leave it whole, and
//! `--no-cache` neither reads nor writes it. Each test has a store of its own in a temporary
//! folder; families whose route is not set up are skipped with a `SKIPPED` line.
use std::path::{Path, PathBuf};

use shadelab::gpu::vk::StatValue;
use shadelab::isa::store::{self, Source, Store};
use shadelab::isa::{self, IsaOptions, IsaReport, Precision};
use shadelab::method;

use crate::isa::families_ready;
use crate::support::{bin, read_json};

/// Methods with a draw and an isolated kernel each, small enough for every family in seconds.
const METHODS: [&str; 2] = ["gouraud", "phong_exact"];
/// The entries one family's run leaves: the whole request's and one per method.
const ENTRIES_PER_FAMILY: usize = 1 + METHODS.len();

/// Whether `e` is the entry of the whole request (all of [`METHODS`]), not a method's.
fn is_whole(e: &store::Entry) -> bool {
    e.material.request["methods"].as_array().map(Vec::len) == Some(METHODS.len())
}

/// The path of the entry of the whole request in `s`.
fn whole_entry(s: &Store) -> PathBuf {
    s.entries()
        .unwrap()
        .into_iter()
        .map(|e| e.path)
        .find(|p| is_whole(&store::decode(&std::fs::read(p).unwrap()).unwrap()))
        .expect("the whole request's entry")
}

fn options(families: &[String], store: Option<Store>) -> IsaOptions {
    IsaOptions {
        methods: METHODS.iter().map(|m| method::find(m).unwrap()).collect(),
        families: families.to_vec(),
        driver_files: None,
        scene: None,
        exe: PathBuf::from(env!("CARGO_BIN_EXE_shadelab")),
        precision: Precision::F32,
        probes: Vec::new(),
        store,
    }
}

fn isa_run(opts: &IsaOptions) -> IsaReport {
    isa::run(opts, &|_| {}).expect("isa run")
}

/// The source of each compiled family.
fn sources(r: &IsaReport) -> Vec<(String, Option<Source>)> {
    r.families
        .iter()
        .filter(|f| f.supported)
        .map(|f| (f.id.clone(), f.source))
        .collect()
}

/// Whether two reports hold the same figures: rows (statistics, hashes, ratios), each
/// family's status, driver and statistics' names, the disassembly.
pub(crate) fn same_figures(a: &IsaReport, b: &IsaReport) -> Result<(), String> {
    let rows = |r: &IsaReport| serde_json::to_value(&r.results).unwrap();
    if rows(a) != rows(b) {
        return Err("the rows differ".into());
    }
    for (x, y) in a.families.iter().zip(&b.families) {
        let key = |f: &isa::FamilyStatus| {
            (
                f.id.clone(),
                f.supported,
                f.driver_info.clone(),
                f.device_name.clone(),
                serde_json::to_value(&f.statistics).unwrap(),
                f.compiler_id.clone(),
            )
        };
        if key(x) != key(y) {
            return Err(format!("family {} differs", x.id));
        }
    }
    if a.disassembly != b.disassembly {
        return Err("the disassembly differs".into());
    }
    Ok(())
}

/// Every default family whose route is set up; the others each get a `SKIPPED` line (or fail
/// under SHADELAB_REQUIRE_VENDORS=1 / SHADELAB_REQUIRE_COMPILERS=1).
pub(crate) fn set_up_families(test: &str) -> Vec<String> {
    isa::route::default_family_ids()
        .into_iter()
        .filter(|f| {
            let (vendor, chip) = isa::route::resolve(f).unwrap();
            let require = if vendor.setup_command_for(&chip).contains("make compilers") {
                "SHADELAB_REQUIRE_COMPILERS"
            } else {
                "SHADELAB_REQUIRE_VENDORS"
            };
            families_ready(test, &[f.as_str()], require)
        })
        .collect()
}

/// Figures read from the store equal freshly compiled ones on every set-up family; teeth: an
/// entry whose statistics were changed (and its checksum recomputed, so it reads as sound)
/// gives other figures, and the comparison says so.
#[test]
fn figures_from_the_store_equal_fresh_ones_on_every_family() {
    let families =
        set_up_families("store::figures_from_the_store_equal_fresh_ones_on_every_family");
    if families.is_empty() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let s = Store::at(dir.path());
    let fresh = isa_run(&options(&families, None));
    let filled = isa_run(&options(&families, Some(s.clone())));
    let read = isa_run(&options(&families, Some(s.clone())));
    assert!(!fresh.supported().is_empty(), "{:#?}", fresh.families);
    assert!(sources(&fresh)
        .iter()
        .all(|(_, s)| *s == Some(Source::Compiled)));
    assert!(sources(&filled)
        .iter()
        .all(|(_, s)| *s == Some(Source::Compiled)));
    let from_store = sources(&read);
    assert!(
        from_store
            .iter()
            .all(|(_, s)| *s == Some(Source::FromStore)),
        "{from_store:?}"
    );
    assert_eq!(from_store.len(), fresh.supported().len());
    same_figures(&fresh, &read).unwrap();
    same_figures(&fresh, &filled).unwrap();
    // Teeth: a doctored but well-formed entry is read, and its figures are not fresh ones.
    let entries = s.verify().unwrap().sound;
    let mut e = entries
        .into_iter()
        .find(|e| {
            // The whole request's entry: the one the run reads first.
            is_whole(e)
                && e.reply()
                    .is_some_and(|r| r.compiled.iter().any(|c| !c.executables.is_empty()))
        })
        .expect("an entry with executables");
    let reply = e.reply_mut().unwrap();
    for x in reply
        .compiled
        .iter_mut()
        .flat_map(|c| c.executables.iter_mut())
    {
        for st in &mut x.statistics {
            st.value = StatValue::Float(st.value.as_f64() + 1000.0);
        }
    }
    let path = s.path_of(&e.material.key());
    std::fs::write(&path, store::encode(&e).unwrap()).unwrap();
    let doctored = isa_run(&options(&families, Some(s)));
    assert!(
        same_figures(&fresh, &doctored).is_err(),
        "a changed statistic went unnoticed"
    );
}

/// A request that shares methods with stored ones compiles only its new methods: the others
/// are read from their own entries, and the whole equals a fresh compile of it. A request of
/// stored methods alone starts no child. Teeth: a doctored method entry shows in the merged
/// figures.
#[test]
fn a_request_sharing_methods_compiles_only_the_new_ones() {
    let fams = ["amd:navi21".to_string()];
    if !families_ready(
        "store::a_request_sharing_methods_compiles_only_the_new_ones",
        &["amd:navi21"],
        "SHADELAB_REQUIRE_VENDORS",
    ) {
        return;
    }
    let with = |names: &[&str], store: Option<Store>| IsaOptions {
        methods: names.iter().map(|m| method::find(m).unwrap()).collect(),
        ..options(&fams, store)
    };
    let dir = tempfile::tempdir().unwrap();
    let s = Store::at(dir.path());
    isa_run(&options(&fams, Some(s.clone())));
    assert_eq!(s.entries().unwrap().len(), ENTRIES_PER_FAMILY);
    // One method more: compiled (that method alone), stored as its own entry and the whole.
    let three = ["gouraud", "phong_exact", "flat"];
    let grown = isa_run(&with(&three, Some(s.clone())));
    assert_eq!(
        sources(&grown),
        vec![(fams[0].clone(), Some(Source::Compiled))]
    );
    assert_eq!(s.entries().unwrap().len(), ENTRIES_PER_FAMILY + 2);
    let fresh = isa_run(&with(&three, None));
    same_figures(&fresh, &grown).unwrap();
    // Stored methods in another combination: read, no child, the fresh figures.
    let two = ["phong_exact", "flat"];
    let read = isa_run(&with(&two, Some(s.clone())));
    assert_eq!(
        sources(&read),
        vec![(fams[0].clone(), Some(Source::FromStore))]
    );
    same_figures(&isa_run(&with(&two, None)), &read).unwrap();
    // Teeth: flat's own entry doctored (well formed) is what the merged run reads.
    let mut e = s
        .verify()
        .unwrap()
        .sound
        .into_iter()
        .find(|e| e.material.request["methods"] == serde_json::json!(["flat"]))
        .expect("flat's entry");
    for x in e
        .reply_mut()
        .unwrap()
        .compiled
        .iter_mut()
        .flat_map(|c| c.executables.iter_mut())
    {
        for st in &mut x.statistics {
            st.value = StatValue::Float(st.value.as_f64() + 1000.0);
        }
    }
    std::fs::write(s.path_of(&e.material.key()), store::encode(&e).unwrap()).unwrap();
    let doctored = isa_run(&with(&["flat", "gouraud"], Some(s)));
    assert!(
        same_figures(&isa_run(&with(&["flat", "gouraud"], None)), &doctored).is_err(),
        "the merged run did not read the method entries"
    );
}

/// A corrupt entry (one byte changed, or cut short) is detected, removed and compiled again:
/// the family's source is `compiled`, its figures the fresh ones, and the store is whole
/// again. Teeth: untouched, the same entry is read (`from_store`).
#[test]
fn a_corrupt_entry_is_detected_and_compiled_again() {
    let fams = ["amd:navi21".to_string()];
    if !families_ready(
        "store::a_corrupt_entry_is_detected_and_compiled_again",
        &["amd:navi21"],
        "SHADELAB_REQUIRE_VENDORS",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let s = Store::at(dir.path());
    let fresh = isa_run(&options(&fams, Some(s.clone())));
    let hit = isa_run(&options(&fams, Some(s.clone())));
    assert_eq!(
        sources(&hit),
        vec![(fams[0].clone(), Some(Source::FromStore))]
    );
    // Every entry of the run damaged alike (the whole request's and each method's: an intact
    // one would be read instead of compiling).
    let entries: Vec<PathBuf> = s.entries().unwrap().into_iter().map(|e| e.path).collect();
    assert_eq!(entries.len(), ENTRIES_PER_FAMILY);
    assert!(whole_entry(&s).exists());
    for damage in [
        |b: &mut Vec<u8>| {
            let i = b.len() - 10;
            b[i] ^= 0x20;
        },
        |b: &mut Vec<u8>| b.truncate(b.len() / 2),
    ] {
        for entry in &entries {
            let mut bytes = std::fs::read(entry).unwrap();
            damage(&mut bytes);
            std::fs::write(entry, &bytes).unwrap();
        }
        let again = isa_run(&options(&fams, Some(s.clone())));
        assert_eq!(
            sources(&again),
            vec![(fams[0].clone(), Some(Source::Compiled))]
        );
        same_figures(&fresh, &again).unwrap();
        let v = s.verify().unwrap();
        let (sound, removed) = (v.sound, v.removed);
        assert_eq!((sound.len(), removed.len()), (ENTRIES_PER_FAMILY, 0));
    }
}

/// A changed compiler identity misses: the route's ICD manifest touched (as a rebuild or a
/// package upgrade does) is another key, compiled again; untouched, it hits.
#[test]
fn a_changed_compiler_identity_misses() {
    if !families_ready(
        "store::a_changed_compiler_identity_misses",
        &["amd:navi21"],
        "SHADELAB_REQUIRE_VENDORS",
    ) {
        return;
    }
    let (amd, _) = isa::route::resolve("amd:navi21").unwrap();
    let system = amd.setup(None).unwrap();
    let manifest = PathBuf::from(system.get("ICD").unwrap());
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("radeon_icd.json");
    std::fs::copy(&manifest, &copy).unwrap();
    let s = Store::at(dir.path().join("store"));
    let opts = IsaOptions {
        driver_files: Some(copy.clone()),
        ..options(&["amd:navi21".to_string()], Some(s.clone()))
    };
    let id = "amd:navi21".to_string();
    let first = isa_run(&opts);
    assert_eq!(sources(&first), vec![(id.clone(), Some(Source::Compiled))]);
    let second = isa_run(&opts);
    assert_eq!(
        sources(&second),
        vec![(id.clone(), Some(Source::FromStore))]
    );
    touch(&copy, 3600);
    let third = isa_run(&opts);
    assert_eq!(sources(&third), vec![(id.clone(), Some(Source::Compiled))]);
    assert_ne!(first.families[0].compiler_id, third.families[0].compiler_id);
    let rows = |r: &IsaReport| serde_json::to_value(&r.results).unwrap();
    assert_eq!(rows(&first), rows(&third));
    assert_eq!(s.entries().unwrap().len(), 2 * ENTRIES_PER_FAMILY);
    // The system's manifest is another environment: another identity as well.
    let system_run = isa_run(&IsaOptions {
        driver_files: None,
        ..opts.clone()
    });
    assert_eq!(sources(&system_run), vec![(id, Some(Source::Compiled))]);
}

/// Sets `path`'s modification time `secs` seconds back.
fn touch(path: &Path, secs: u64) {
    let f = std::fs::OpenOptions::new().append(true).open(path).unwrap();
    f.set_modified(std::time::SystemTime::now() - std::time::Duration::from_secs(secs))
        .unwrap();
}

/// `shadelab isa` on `families` into `out` with the store in `store`.
fn isa_process(families: &str, out: &Path, store: &Path, extra: &[&str]) -> std::process::Child {
    bin()
        .args([
            "isa",
            "--methods",
            "gouraud",
            "--families",
            families,
            "--out",
        ])
        .arg(out)
        .args(extra)
        .env(store::ENV_DIR, store)
        .env_remove(store::ENV_OFF)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

fn family_sources(out: &Path) -> Vec<String> {
    read_json(out.join("isa.json"))["families"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["supported"] == true)
        .map(|f| f["source"].as_str().unwrap_or("none").to_string())
        .collect()
}

/// Two processes filling one store at once both succeed; every entry is whole (checksum,
/// length, key), no temporary file is left, one entry per family; a third run reads every
/// family from it with the same rows. Then `--no-cache` neither reads nor writes the store.
#[test]
fn two_processes_filling_the_store_at_once_leave_it_whole() {
    let fams = ["amd:tahiti", "amd:vega10", "amd:navi10", "amd:navi21"];
    if !families_ready(
        "store::two_processes_filling_the_store_at_once_leave_it_whole",
        &fams,
        "SHADELAB_REQUIRE_VENDORS",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let store_dir = dir.path().join("store");
    let list = fams.join(",");
    let outs: Vec<PathBuf> = (0..3).map(|i| dir.path().join(format!("out{i}"))).collect();
    let a = isa_process(&list, &outs[0], &store_dir, &[]);
    let b = isa_process(&list, &outs[1], &store_dir, &[]);
    for c in [a, b] {
        let o = c.wait_with_output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let s = Store::at(&store_dir);
    let v = s.verify().unwrap();
    let (sound, removed) = (v.sound, v.removed);
    assert!(removed.is_empty(), "{removed:?}");
    assert_eq!(sound.len(), fams.len() * ENTRIES_PER_FAMILY);
    let names: Vec<String> = std::fs::read_dir(&store_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| n.ends_with(".entry")), "{names:?}");
    let o = isa_process(&list, &outs[2], &store_dir, &[])
        .wait_with_output()
        .unwrap();
    assert!(o.status.success());
    assert_eq!(family_sources(&outs[2]), vec!["from_store"; fams.len()]);
    let rows = |d: &Path| read_json(d.join("isa.json"))["results"].clone();
    assert_eq!(rows(&outs[0]), rows(&outs[2]));
    // --no-cache: compiled now, and the store is not written (an emptied store stays empty).
    s.prune_to(0).unwrap();
    let o = isa_process(&list, &outs[2], &store_dir, &["--no-cache"])
        .wait_with_output()
        .unwrap();
    assert!(o.status.success());
    assert_eq!(family_sources(&outs[2]), vec!["compiled"; fams.len()]);
    assert!(s.entries().unwrap().is_empty());
    // Teeth of that check: without --no-cache the same run writes the store.
    let o = isa_process(&list, &outs[2], &store_dir, &[])
        .wait_with_output()
        .unwrap();
    assert!(o.status.success());
    assert_eq!(s.entries().unwrap().len(), fams.len() * ENTRIES_PER_FAMILY);
    let (code, out, _) = {
        let o = bin()
            .args(["cache", "--verify"])
            .env(store::ENV_DIR, &store_dir)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            (),
        )
    };
    assert_eq!(code, Some(0));
    assert!(
        out.contains(&format!(
            "{} sound, 0 removed",
            fams.len() * ENTRIES_PER_FAMILY
        )),
        "{out}"
    );
    assert!(
        out.contains(&format!("amd:navi21: {ENTRIES_PER_FAMILY}")),
        "{out}"
    );
}

/// A child's own refusal (float16 on a chip without float16 arithmetic) is stored and read
/// back: no child is asked again. Teeth: a stored refusal whose words were changed comes back
/// with those words, so the second run's answer is the store's.
#[test]
fn a_refusal_is_stored_and_read_back() {
    if !families_ready(
        "store::a_refusal_is_stored_and_read_back",
        &["amd:tahiti"],
        "SHADELAB_REQUIRE_VENDORS",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let s = Store::at(dir.path());
    let opts = IsaOptions {
        precision: Precision::F16,
        ..options(&["amd:tahiti".to_string()], Some(s.clone()))
    };
    let first = isa_run(&opts);
    assert!(!first.families[0].supported, "{:#?}", first.families);
    assert!(
        first.families[0].status.contains("float16"),
        "{:#?}",
        first.families
    );
    let mut entries = s.verify().unwrap().sound;
    assert_eq!(entries.len(), 1);
    let mut e = entries.pop().unwrap();
    let store::Stored::Refused(why) = &e.stored else {
        panic!("not a refusal: {:?}", e.stored)
    };
    assert!(first.families[0].status.ends_with(why.as_str()), "{why}");
    e.stored = store::Stored::Refused("the store's own words".into());
    std::fs::write(s.path_of(&e.material.key()), store::encode(&e).unwrap()).unwrap();
    let second = isa_run(&opts);
    assert!(
        second.families[0].status.ends_with("the store's own words"),
        "{:#?}",
        second.families
    );
}
