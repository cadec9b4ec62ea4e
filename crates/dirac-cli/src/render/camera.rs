//! The camera: a view direction from azimuth and elevation, placed on the mesh's bounding
//! sphere, and the projection of vertices to pixel coordinates framed to fill a viewport.

use dirac::geometry::{bounding_box, dot, norm, sub};

use super::{Projection, View};

/// Vertical field of view of the perspective camera. Narrow, so the mesh looks as in a
/// figure rather than through a wide-angle lens.
const FIELD_OF_VIEW_DEGREES: f64 = 30.0;

/// Fraction of the viewport the framed mesh may fill (the rest is a margin).
const FILL: f64 = 0.94;

/// A vertex after projection: pixel coordinates (`y` down), depth along the view direction and
/// `1/w` of the homogeneous coordinate, which makes interpolation perspective-correct.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projected {
    /// Column, in pixels.
    pub x: f64,
    /// Row, in pixels (downwards).
    pub y: f64,
    /// Distance in front of the camera (smaller is nearer).
    pub depth: f64,
    /// `1/depth` for perspective, 1 for orthographic projection.
    pub inv_w: f64,
}

/// A camera looking at the centre of a bounding sphere.
#[derive(Debug, Clone)]
pub struct Camera {
    projection: Projection,
    center: [f64; 3],
    /// Orthonormal frame: right, up, and towards the viewer.
    right: [f64; 3],
    up: [f64; 3],
    back: [f64; 3],
    /// Distance of the eye from the centre (perspective).
    distance: f64,
}

impl Camera {
    /// Looks from `view` at the bounding sphere of `positions` (centre of the bounding box,
    /// radius to the farthest vertex). `positions` must not be empty.
    pub fn new(positions: &[[f64; 3]], view: View, projection: Projection) -> Self {
        let (low, high) = bounding_box(positions.iter().copied()).unwrap_or_default();
        let center: [f64; 3] = std::array::from_fn(|c| 0.5 * (low[c] + high[c]));
        let radius = positions
            .iter()
            .map(|&p| norm(sub(p, center)))
            .fold(0.0, f64::max);
        let (az, el) = (
            view.azimuth_degrees.to_radians(),
            view.elevation_degrees.to_radians(),
        );
        // Spherical coordinates about the +y axis; the frame is defined for every angle,
        // including the poles, because `up` is the derivative in elevation, not a cross
        // product with a fixed world axis.
        let back = [az.sin() * el.cos(), el.sin(), az.cos() * el.cos()];
        let right = [az.cos(), 0.0, -az.sin()];
        let up = [-az.sin() * el.sin(), el.cos(), -az.cos() * el.sin()];
        let half_fov = (0.5 * FIELD_OF_VIEW_DEGREES).to_radians();
        Self {
            projection,
            center,
            right,
            up,
            back,
            // At this distance the whole sphere lies inside the field of view and in front of
            // the eye, so every depth is positive.
            distance: radius.max(f64::MIN_POSITIVE) / half_fov.sin(),
        }
    }

    /// The unit vector from `point` towards the eye (for orthographic projection, the view
    /// direction reversed).
    pub fn towards_eye(&self, point: [f64; 3]) -> [f64; 3] {
        match self.projection {
            Projection::Orthographic => self.back,
            Projection::Perspective => {
                let eye: [f64; 3] =
                    std::array::from_fn(|c| self.center[c] + self.distance * self.back[c]);
                let d = sub(eye, point);
                let length = norm(d);
                d.map(|x| x / length)
            }
        }
    }

    /// Components of a direction in the camera frame (right, up, towards the viewer).
    pub fn to_camera(&self, direction: [f64; 3]) -> [f64; 3] {
        [
            dot(direction, self.right),
            dot(direction, self.up),
            dot(direction, self.back),
        ]
    }

    /// Projects `positions` into a `width × height` pixel viewport, scaled and centred so the
    /// projected mesh fills [`FILL`] of it in the tighter direction.
    pub fn project(&self, positions: &[[f64; 3]], width: f64, height: f64) -> Vec<Projected> {
        // Image-plane coordinates at unit focal length, before framing.
        let plane: Vec<(f64, f64, f64, f64)> = positions
            .iter()
            .map(|&p| {
                let [x, y, z] = self.to_camera(sub(p, self.center));
                let depth = self.distance - z;
                match self.projection {
                    Projection::Perspective => (x / depth, y / depth, depth, 1.0 / depth),
                    Projection::Orthographic => (x, y, depth, 1.0),
                }
            })
            .collect();
        let (mut low, mut high) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &(x, y, _, _) in &plane {
            low = [low[0].min(x), low[1].min(y)];
            high = [high[0].max(x), high[1].max(y)];
        }
        let extent = [high[0] - low[0], high[1] - low[1]];
        let scale = FILL
            * (width / extent[0].max(f64::MIN_POSITIVE))
                .min(height / extent[1].max(f64::MIN_POSITIVE));
        let mid = [0.5 * (low[0] + high[0]), 0.5 * (low[1] + high[1])];
        plane
            .into_iter()
            .map(|(x, y, depth, inv_w)| Projected {
                x: 0.5 * width + scale * (x - mid[0]),
                y: 0.5 * height - scale * (y - mid[1]),
                depth,
                inv_w,
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The eight corners of a cube of side 2 around (1, 2, 3).
    fn cube() -> Vec<[f64; 3]> {
        (0..8)
            .map(|i| {
                [
                    f64::from(i & 1) * 2.0,
                    f64::from((i >> 1) & 1) * 2.0 + 1.0,
                    f64::from((i >> 2) & 1) * 2.0 + 2.0,
                ]
            })
            .collect()
    }

    #[test]
    fn front_view_puts_positive_z_nearer_and_positive_y_up() {
        for projection in [Projection::Perspective, Projection::Orthographic] {
            let camera = Camera::new(&cube(), View::new(0.0, 0.0), projection);
            let p = camera.project(&cube(), 100.0, 100.0);
            // Corner 7 = (2, 3, 4) is nearer than corner 0 = (0, 1, 2), right of and above it.
            assert!(p[7].depth < p[0].depth, "{projection:?}");
            assert!(p[7].x > p[0].x && p[7].y < p[0].y, "{projection:?}");
            assert!(p.iter().all(|q| q.depth > 0.0));
            // Framed: the extent spans FILL of the viewport, centred.
            let (min_x, max_x) = p
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| {
                    (a.min(q.x), b.max(q.x))
                });
            assert!(
                (max_x - min_x - 100.0 * FILL).abs() < 1e-9,
                "{projection:?}"
            );
            assert!((min_x + max_x - 100.0).abs() < 1e-9, "{projection:?}");
        }
    }

    #[test]
    fn the_frame_is_orthonormal_at_the_poles() {
        let camera = Camera::new(&cube(), View::new(30.0, 90.0), Projection::Orthographic);
        let frame = [camera.right, camera.up, camera.back];
        for (i, a) in frame.iter().enumerate() {
            for (j, b) in frame.iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((dot(*a, *b) - expected).abs() < 1e-12, "{i} {j}");
            }
        }
        // Looking straight down: +y points at the viewer.
        assert!((camera.to_camera([0.0, 1.0, 0.0])[2] - 1.0).abs() < 1e-12);
    }
}
