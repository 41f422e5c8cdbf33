//! The viewer's orbit camera (glam): turn, zoom, pan, fit to a bounding sphere, and the
//! world-to-clip matrix. Pure math, so it is tested natively; the renderer is `viewer`.

use glam::{Mat4, Vec3};

/// Vertical field of view, radians.
pub const FOV_Y: f32 = 0.8;

/// An orbit camera around `target`: yaw and pitch in radians, distance in scene units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    pub target: Vec3,
    pub yaw: f32,
    pub pitch: f32,
    pub distance: f32,
    /// The scene's bounding radius, which scales panning and the clip planes.
    pub radius: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        Self {
            target: Vec3::ZERO,
            yaw: 0.7,
            pitch: 0.45,
            distance: 3.0,
            radius: 1.0,
        }
    }
}

impl OrbitCamera {
    /// Looks at the bounding sphere of `points` (x, y, z triples) from far enough away to see
    /// all of it; keeps the current angles. Empty input keeps the camera as it is.
    pub fn fit(&mut self, points: &[f32]) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in points.chunks_exact(3) {
            let p = Vec3::from_slice(p);
            if p.is_finite() {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return;
        }
        self.target = (lo + hi) / 2.0;
        self.radius = ((hi - lo).length() / 2.0).max(1e-6);
        self.distance = self.radius / (FOV_Y / 2.0).sin() * 1.05;
    }

    /// Turns by `dx`, `dy` radians; the pitch stops short of the poles.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw += dx;
        self.pitch = (self.pitch + dy).clamp(-1.5, 1.5);
    }

    /// Moves closer by `factor` > 1, away by `factor` < 1.
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance / factor).clamp(self.radius * 1e-3, self.radius * 1e3);
        }
    }

    /// Slides the target across the view by a fraction of the view's height.
    pub fn pan(&mut self, dx: f32, dy: f32) {
        let (right, up) = self.axes();
        let scale = 2.0 * self.distance * (FOV_Y / 2.0).tan();
        self.target += (-right * dx + up * dy) * scale;
    }

    /// Where the camera is.
    pub fn eye(&self) -> Vec3 {
        let dir = Vec3::new(
            self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.cos(),
        );
        self.target + dir * self.distance
    }

    /// The direction towards the key light: above the viewer and to the left, turning with
    /// the view, so faces turned different ways get different shades from every side.
    pub fn key_light(&self) -> Vec3 {
        let (right, up) = self.axes();
        let back = (self.eye() - self.target).normalize_or(Vec3::Z);
        (back + up * 0.8 - right * 0.5).normalize()
    }

    fn axes(&self) -> (Vec3, Vec3) {
        let forward = (self.target - self.eye()).normalize();
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        (right, right.cross(forward))
    }

    /// World to clip space for a view of the given aspect ratio (width / height).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let near = (self.distance - self.radius * 2.0).max(self.distance * 1e-3);
        let far = self.distance + self.radius * 2.0;
        // WebGPU's clip space is DirectX's: y up, depth in [0, 1].
        glam::camera::rh::proj::directx::perspective(FOV_Y, aspect.max(1e-3), near, far)
            * glam::camera::rh::view::look_at_mat4(self.eye(), self.target, Vec3::Y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fitted_camera_sees_the_whole_scene() {
        let mut camera = OrbitCamera::default();
        let cube: Vec<f32> = (0..8)
            .flat_map(|i| {
                [
                    (i & 1) as f32 * 4.0 + 10.0,
                    (i >> 1 & 1) as f32,
                    (i >> 2) as f32,
                ]
            })
            .collect();
        camera.fit(&cube);
        assert_eq!(camera.target, Vec3::new(12.0, 0.5, 0.5));
        for (yaw, pitch) in [(0.0, 0.0), (1.0, 0.3), (2.5, -1.2)] {
            camera.yaw = yaw;
            camera.pitch = pitch;
            let m = camera.view_proj(4.0 / 3.0);
            for p in cube.chunks_exact(3) {
                let clip = m * Vec3::from_slice(p).extend(1.0);
                let ndc = clip.truncate() / clip.w;
                assert!(ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0, "{ndc}");
                assert!((0.0..=1.0).contains(&ndc.z), "{ndc}");
            }
        }
    }
}
