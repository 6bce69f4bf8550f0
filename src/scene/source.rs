//! Where a scene comes from, as data: a scene file or an OBJ mesh, and the command line's
//! overrides (size, interpolation, culling). The CLI parses it once; a child process is given
//! the same value in its request and loads the same scene ([`SceneSource::load`]).
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::{Cull, Interpolation, Scene};
use crate::error::{Error, Result};

/// A scene file or a mesh, with overrides.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct SceneSource {
    /// A scene file (TOML).
    pub scene: Option<PathBuf>,
    /// An OBJ mesh (camera fitted to its bounds, default light and material).
    pub mesh: Option<PathBuf>,
    pub size: Option<(u32, u32)>,
    pub interpolation: Option<Interpolation>,
    pub cull: Option<Cull>,
}

impl SceneSource {
    /// The scene, with the overrides applied (an OBJ's camera refitted to the size's aspect).
    pub fn load(&self) -> Result<Scene> {
        let mut scene = match (&self.scene, &self.mesh) {
            (Some(s), _) => super::load_scene(s)?,
            (None, Some(m)) => super::scene_for_mesh(m)?,
            (None, None) => return Err(Error::Usage("give --scene FILE or --mesh FILE".into())),
        };
        if let Some((w, h)) = self.size {
            scene.width = w;
            scene.height = h;
            if self.scene.is_none() && h > 0 {
                // A mesh: the camera was fitted for the default aspect; refit it for this one.
                scene.camera = super::fit_camera(scene.camera.fov_y_deg, w as f64 / h as f64);
            }
        }
        if let Some(i) = self.interpolation {
            scene.interpolation = i;
        }
        if let Some(c) = self.cull {
            scene.cull = c;
        }
        Ok(scene)
    }
}
