//! The float32 software engine stays bit-identical to the engine of main dd926e6 (before its
//! kernels became generic over the scalar, issue 23): every method on every shipped scene,
//! hashed (SHA-256 of the colour and normal images' f32 bits) against
//! tests/data/software/f32_frames.json, which that engine wrote (`SHADELAB_BLESS=1 cargo test
//! --release software::golden`). A method added after it (the guards, any new row) has no
//! entry and is judged by its twin in `engines`; an entry whose method is gone fails. The
//! frames of slerp and spherical_angular that call `acos` were re-recorded (5 entries) when the
//! engines took their own acos (src/method/real.rs `acos_f32`) instead of the platform's
//! `acosf`, whose bits differ between glibc 2.36 and 2.41 (Debian 12 and 13): the frames are
//! now the same on both.
use std::collections::BTreeMap;

use sha2::{Digest, Sha256};
use shadelab::method::{find, METHODS};
use shadelab::scene::SceneInputs;
use shadelab::software;

use crate::support::*;

const SCENES: &[&str] = SHIPPED_SCENES;
const SIZE: u32 = 96;
/// How many methods the recording holds for each scene (the table at dd926e6, before issue
/// 23's guards): a recording that lost one fails, and a new row needs no entry.
const RECORDED: usize = 35;

fn golden_path() -> std::path::PathBuf {
    root().join("tests/data/software/f32_frames.json")
}

/// SHA-256 of the frame's colour and normal f32 bits, hex.
fn frame_hash(frame: &shadelab::frame::Frame) -> String {
    let mut h = Sha256::new();
    for px in frame.color.iter().chain(&frame.normal) {
        for v in px {
            h.update(v.to_bits().to_le_bytes());
        }
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

fn hash_of(scene: &str, method: &str) -> String {
    let s = shipped_scene(scene, SIZE);
    let m = find(method).unwrap();
    let inputs = SceneInputs::new(&s, m.geometry);
    let (frame, _) = software::render(&inputs, m, 2, false).unwrap();
    frame_hash(&frame)
}

#[test]
fn f32_software_frames_are_bit_identical_to_the_recorded_engine() {
    if std::env::var("SHADELAB_BLESS").as_deref() == Ok("1") {
        let mut all = BTreeMap::new();
        for s in SCENES {
            for m in METHODS {
                all.insert(format!("{s}/{}", m.name), hash_of(s, m.name));
            }
        }
        let text = serde_json::to_string_pretty(&all).unwrap() + "\n";
        std::fs::write(golden_path(), text).unwrap();
        return;
    }
    let text = std::fs::read_to_string(golden_path()).unwrap();
    let golden: BTreeMap<String, String> = serde_json::from_str(&text).unwrap();
    // Every scene records the same RECORDED methods; a key naming a method that is gone
    // fails in `find`.
    for s in SCENES {
        let recorded = |s: &str| -> Vec<&str> {
            let keys = golden
                .keys()
                .filter_map(|k| k.strip_prefix(&format!("{s}/")));
            keys.map(|m| m.split('/').next().unwrap()).collect()
        };
        assert_eq!(recorded(s).len(), RECORDED, "{s}: {:?}", recorded(s));
        assert_eq!(recorded(s), recorded(SCENES[0]), "{s}");
    }
    let mut differ = Vec::new();
    for (key, want) in &golden {
        let (scene, method) = key.split_once('/').unwrap();
        if hash_of(scene, method) != *want {
            differ.push(key.clone());
        }
    }
    assert!(differ.is_empty(), "f32 frames changed: {differ:?}");
}

#[test]
fn the_frame_hash_sees_one_bit() {
    let s = shipped_scene("torus", 32);
    let m = find("phong_exact").unwrap();
    let (mut frame, _) = software::render(&SceneInputs::new(&s, m.geometry), m, 1, false).unwrap();
    let before = frame_hash(&frame);
    let i = frame.color.iter().position(|c| c[3] > 0.0).unwrap();
    frame.color[i][0] = f32::from_bits(frame.color[i][0].to_bits() ^ 1);
    assert_ne!(frame_hash(&frame), before);
}
