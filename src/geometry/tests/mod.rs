//! Tests of the geometry module, one file per topic: OBJ loading, validation and fitting
//! ([`loading`]), glTF documents built in the test ([`gltf`]), normals given and computed
//! ([`normals`]), PLY files written in the test ([`ply`]), the procedural generators and the shipped meshes ([`generators`]), OBJ
//! writing ([`writing`]); the helpers they share are here.
mod generators;
mod gltf;
mod loading;
mod normals;
mod ply;
mod writing;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::error::{Error, Result};
use crate::geometry::*;
use crate::testutil::assert_close;

/// Writes `text` to `name` in a fresh temp dir, keeping the dir alive with the path.
fn temp_obj(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("create temp dir");
    let path = dir.path().join(name);
    std::fs::write(&path, text).expect("write temp OBJ");
    (dir, path)
}

fn load_text(text: &str) -> Result<(Mesh, LoadReport)> {
    let (_dir, path) = temp_obj("t.obj", text);
    load_obj(&path)
}

/// Asserts `r` is an input error at `line` whose message contains `needle`.
#[track_caller]
fn assert_input_err<T: std::fmt::Debug>(r: Result<T>, line: Option<usize>, needle: &str) {
    match r {
        Err(Error::Input {
            line: l, message, ..
        }) => {
            assert_eq!(
                l, line,
                "line of error `{message}`: left = actual, right = expected"
            );
            assert!(
                message.contains(needle),
                "message `{message}` does not contain `{needle}`"
            );
        }
        other => {
            panic!("expected an input error at line {line:?} containing `{needle}`, got {other:?}")
        }
    }
}

const UNIT_CUBE: &str = "\
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
";

/// Test generators: the shipped ones plus other parameters.
fn all_generators() -> Vec<Generator> {
    let mut g: Vec<Generator> = SHIPPED.iter().map(|(_, g)| g.clone()).collect();
    g.extend([
        Generator::UvSphere {
            segments: 3,
            rings: 2,
        },
        Generator::Icosphere { subdivisions: 2 },
        Generator::Torus {
            major_radius: 2.0,
            minor_radius: 1.9,
            major_segments: 3,
            minor_segments: 5,
        },
    ]);
    g
}
