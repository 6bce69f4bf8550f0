//! The camera in f64: the fitted default camera, view and projection matrices (Vulkan clip
//! space: y down, depth 0..1).
use glam::{DMat4, DVec3, DVec4};

use super::*;

/// The camera that frames the unit sphere: eye on the direction normalize(0, 0.3, 1) (a little
/// above the equator, looking at the origin, +y up), at the distance where the sphere's
/// silhouette fills the narrower of the vertical and horizontal fields of view up to a 5%
/// margin (its radius on the image plane is 1/1.05 of the half-extent). Clip planes default.
///
/// A non-finite or non-positive `aspect` is taken as 1, and `fov_y_deg` is clamped to
/// [0.001, 179.9] degrees, so the result is always a usable camera.
pub fn fit_camera(fov_y_deg: f64, aspect: f64) -> Camera {
    let fov = if fov_y_deg.is_finite() {
        fov_y_deg.clamp(1e-3, 179.9)
    } else {
        DEFAULT_FOV_Y_DEG
    };
    let aspect = if aspect.is_finite() && aspect > 0.0 {
        aspect
    } else {
        1.0
    };
    let tan_y = (fov.to_radians() * 0.5).tan();
    let tan_half = tan_y.min(tan_y * aspect);
    // A sphere of radius 1 at distance d has a circular silhouette of radius 1/sqrt(d^2 - 1) on
    // the image plane at distance 1; set that to tan_half / 1.05 and solve for d.
    let silhouette = tan_half / 1.05;
    let distance = (1.0 + 1.0 / (silhouette * silhouette)).sqrt();
    Camera {
        eye: DVec3::new(0.0, 0.3, 1.0).normalize() * distance,
        target: DVec3::ZERO,
        up: DVec3::Y,
        fov_y_deg: fov,
        near: None,
        far: None,
    }
}
impl Camera {
    /// `|eye - target|`.
    pub fn distance(&self) -> f64 {
        (self.eye - self.target).length()
    }

    /// The clip distances: the explicit ones, else `near = max(0.01, distance - 1.5)` and
    /// `far = distance + 1.5`, which enclose the fitted unit-sphere mesh with 0.5 to spare
    /// when the camera looks at it.
    pub fn near_far(&self) -> (f64, f64) {
        let d = self.distance();
        (
            self.near.unwrap_or((d - 1.5).max(0.01)),
            self.far.unwrap_or(d + 1.5),
        )
    }

    /// Right-handed look-at view matrix: camera at the origin looking down -z, +y up, +x right.
    /// Assumes `eye != target` and `up` not parallel to the view direction (scene loading
    /// checks both); otherwise the result contains NaN.
    pub fn view(&self) -> DMat4 {
        let f = (self.target - self.eye).normalize();
        let s = f.cross(self.up).normalize();
        let u = s.cross(f);
        DMat4::from_cols(
            DVec4::new(s.x, u.x, -f.x, 0.0),
            DVec4::new(s.y, u.y, -f.y, 0.0),
            DVec4::new(s.z, u.z, -f.z, 0.0),
            DVec4::new(-s.dot(self.eye), -u.dot(self.eye), f.dot(self.eye), 1.0),
        )
    }

    /// Perspective projection from the right-handed view space into Vulkan clip space: depth
    /// 0 at `near` and 1 at `far`, and y flipped so that view +y lands at the top of the window
    /// (smaller framebuffer y) with an ordinary positive-height viewport. `aspect` is
    /// width / height.
    pub fn projection(&self, aspect: f64) -> DMat4 {
        let (near, far) = self.near_far();
        let t = (self.fov_y_deg.to_radians() * 0.5).tan();
        DMat4::from_cols(
            DVec4::new(1.0 / (aspect * t), 0.0, 0.0, 0.0),
            DVec4::new(0.0, -1.0 / t, 0.0, 0.0),
            DVec4::new(0.0, 0.0, far / (near - far), -1.0),
            DVec4::new(0.0, 0.0, near * far / (near - far), 0.0),
        )
    }
}
