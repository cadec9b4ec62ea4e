//! A z-buffered triangle rasteriser with Gouraud interpolation of a colour-map coordinate and
//! a light intensity, and box-filter downsampling for supersampled anti-aliasing.

use super::camera::Projected;
use super::canvas::Canvas;
use super::colormap::viridis;

/// A triangle corner as the rasteriser sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corner {
    /// Screen position, depth and `1/w`.
    pub at: Projected,
    /// Colour-map coordinate in `[0, 1]`.
    pub value: f64,
    /// Light intensity (a factor on the colour).
    pub light: f64,
}

/// What the nearest surface left in one sample. Single precision halves the memory of the
/// z-buffer; relative depth differences of 10⁻⁷ are far below what a mesh can show.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fragment {
    /// Depth of the nearest surface so far.
    pub depth: f32,
    /// Interpolated colour-map coordinate.
    pub value: f32,
    /// Interpolated light intensity.
    pub light: f32,
    /// The face drawn here.
    pub face: u32,
}

/// A grid of samples, each empty (background) or holding the nearest fragment.
#[derive(Debug, Clone)]
pub struct Raster {
    width: usize,
    height: usize,
    samples: Vec<Option<Fragment>>,
}

impl Raster {
    /// An empty raster of `width × height` samples.
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            samples: vec![None; width * height],
        }
    }

    /// The fragment at column `x`, row `y` (None for background or outside).
    #[cfg(test)]
    pub fn fragment(&self, x: usize, y: usize) -> Option<Fragment> {
        if x < self.width && y < self.height {
            self.samples[y * self.width + x]
        } else {
            None
        }
    }

    /// Draws one triangle, face `face` of the mesh: every sample whose centre lies inside it
    /// or on its edges is written if the triangle is nearer there than what the sample holds.
    /// Attributes are interpolated perspective-correctly (barycentric weights divided by `w`).
    pub fn draw(&mut self, corners: [Corner; 3], face: u32) {
        let [a, b, c] = corners.map(|corner| corner.at);
        let area = edge(a, b, c.x, c.y);
        // Degenerate in screen space (seen edge-on): covers no sample centre reliably.
        if area.abs() < 1e-12 {
            return;
        }
        let clamp_to = |v: f64, limit: usize| v.max(0.0).min(limit as f64) as usize;
        let x0 = clamp_to(a.x.min(b.x).min(c.x).floor(), self.width);
        let x1 = clamp_to(a.x.max(b.x).max(c.x).ceil(), self.width);
        let y0 = clamp_to(a.y.min(b.y).min(c.y).floor(), self.height);
        let y1 = clamp_to(a.y.max(b.y).max(c.y).ceil(), self.height);
        for y in y0..y1 {
            let py = y as f64 + 0.5;
            for x in x0..x1 {
                let px = x as f64 + 0.5;
                // Barycentric coordinates; dividing by the signed area makes them
                // non-negative inside for either winding.
                let weights = [
                    edge(b, c, px, py) / area,
                    edge(c, a, px, py) / area,
                    edge(a, b, px, py) / area,
                ];
                if weights.iter().any(|&w| w < 0.0) {
                    continue;
                }
                let perspective = [0, 1, 2].map(|i| weights[i] * corners[i].at.inv_w);
                let total: f64 = perspective.iter().sum();
                let interpolate = |f: &dyn Fn(&Corner) -> f64| {
                    (0..3).map(|i| perspective[i] * f(&corners[i])).sum::<f64>() / total
                };
                let depth = interpolate(&|corner| corner.at.depth) as f32;
                let sample = &mut self.samples[y * self.width + x];
                if sample.is_none_or(|held| depth < held.depth) {
                    *sample = Some(Fragment {
                        depth,
                        value: interpolate(&|corner| corner.value) as f32,
                        light: interpolate(&|corner| corner.light) as f32,
                        face,
                    });
                }
            }
        }
    }

    /// Shades every sample: viridis of the value times the light, `background` where empty.
    pub fn shade(&self, background: [u8; 3]) -> Canvas {
        self.shade_with(background, |_, _, fragment| {
            lit(viridis(f64::from(fragment.value)), fragment.light)
        })
    }

    /// Shades every sample by segment: the colour `colour(labels[face])` times the light, and
    /// `ink` where a sample within `radius` samples (a square window) shows a face of another
    /// segment, which draws the segments' boundaries; `background` where empty.
    pub fn shade_segments(
        &self,
        background: [u8; 3],
        labels: &[usize],
        colour: impl Fn(usize) -> [u8; 3],
        ink: [u8; 3],
        radius: usize,
    ) -> Canvas {
        let segment =
            |x: usize, y: usize| self.samples[y * self.width + x].map(|f| labels[f.face as usize]);
        self.shade_with(background, |x, y, fragment| {
            let own = labels[fragment.face as usize];
            let (x0, x1) = (x.saturating_sub(radius), (x + radius).min(self.width - 1));
            let (y0, y1) = (y.saturating_sub(radius), (y + radius).min(self.height - 1));
            let boundary = (y0..=y1)
                .any(|v| (x0..=x1).any(|u| segment(u, v).is_some_and(|other| other != own)));
            if boundary {
                ink
            } else {
                lit(colour(own), fragment.light)
            }
        })
    }

    /// A canvas with `shade(x, y, fragment)` at every covered sample, `background` elsewhere.
    fn shade_with(
        &self,
        background: [u8; 3],
        shade: impl Fn(usize, usize, &Fragment) -> [u8; 3],
    ) -> Canvas {
        let mut canvas = Canvas::new(self.width as u32, self.height as u32, background);
        for y in 0..self.height {
            for x in 0..self.width {
                if let Some(fragment) = &self.samples[y * self.width + x] {
                    canvas.set(x as u32, y as u32, shade(x, y, fragment));
                }
            }
        }
        canvas
    }
}

/// `colour` scaled by the light intensity.
fn lit(colour: [u8; 3], light: f32) -> [u8; 3] {
    colour.map(|c| (f64::from(c) * f64::from(light)).round().clamp(0.0, 255.0) as u8)
}

/// Twice the signed area of the triangle `a, b, (x, y)` (the edge function of `ab`).
fn edge(a: Projected, b: Projected, x: f64, y: f64) -> f64 {
    (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An orthographic corner at pixel position `(x, y)` and `depth`.
    fn corner(x: f64, y: f64, depth: f64, value: f64) -> Corner {
        Corner {
            at: Projected {
                x,
                y,
                depth,
                inv_w: 1.0,
            },
            value,
            light: 1.0,
        }
    }

    #[test]
    fn a_triangle_covers_exactly_the_sample_centres_inside_it() {
        let mut raster = Raster::new(10, 10);
        // Legs of 8 pixels along the axes: centres (i + ½, j + ½) with i + j ≤ 7 are inside
        // or on the hypotenuse x + y = 8.
        raster.draw(
            [
                corner(0.0, 0.0, 1.0, 0.5),
                corner(8.0, 0.0, 1.0, 0.5),
                corner(0.0, 8.0, 1.0, 0.5),
            ],
            0,
        );
        for y in 0..10 {
            for x in 0..10 {
                assert_eq!(
                    raster.fragment(x, y).is_some(),
                    x + y <= 7,
                    "pixel ({x}, {y})"
                );
            }
        }
    }

    #[test]
    fn both_windings_and_partly_offscreen_triangles_are_drawn() {
        let mut raster = Raster::new(4, 4);
        // Clockwise on screen (the first test's triangle is counter-clockwise); the
        // hypotenuse x + y = 6 passes between the centres of (0, 0) and (3, 3).
        raster.draw(
            [
                corner(-10.0, -10.0, 1.0, 0.0),
                corner(-10.0, 16.0, 1.0, 0.0),
                corner(16.0, -10.0, 1.0, 0.0),
            ],
            0,
        );
        assert!(raster.fragment(0, 0).is_some() && raster.fragment(3, 3).is_none());
        assert!(raster.fragment(4, 0).is_none(), "outside the raster");
    }

    #[test]
    fn the_z_buffer_keeps_the_nearer_face_in_either_drawing_order() {
        let near = [
            corner(0.0, 0.0, 1.0, 1.0),
            corner(6.0, 0.0, 1.0, 1.0),
            corner(0.0, 6.0, 1.0, 1.0),
        ];
        let far = [
            corner(0.0, 0.0, 2.0, 0.0),
            corner(6.0, 0.0, 2.0, 0.0),
            corner(6.0, 6.0, 2.0, 0.0),
        ];
        for order in [[near, far], [far, near]] {
            let mut raster = Raster::new(6, 6);
            for triangle in order {
                raster.draw(triangle, 0);
            }
            // (2, 1) is in both: the near face wins; (5, 4) is only in the far one.
            assert_eq!(raster.fragment(2, 1).map(|f| f.value), Some(1.0));
            assert_eq!(raster.fragment(5, 4).map(|f| f.value), Some(0.0));
        }
    }

    #[test]
    fn attributes_are_interpolated_linearly_in_orthographic_projection() {
        let mut raster = Raster::new(8, 8);
        raster.draw(
            [
                corner(0.0, 0.0, 1.0, 0.0),
                corner(8.0, 0.0, 3.0, 1.0),
                corner(0.0, 8.0, 1.0, 0.0),
            ],
            0,
        );
        let fragment = raster.fragment(1, 2).expect("covered");
        // At (1.5, 2.5) the weight of the second corner is x/8.
        assert!((fragment.value - 1.5 / 8.0).abs() < 1e-7);
        assert!((fragment.depth - (1.0 + 2.0 * 1.5 / 8.0)).abs() < 1e-6);
    }

    #[test]
    fn shading_scales_the_colour_map_by_the_light_and_fills_the_background() {
        let mut raster = Raster::new(3, 1);
        let mut dim = [
            corner(0.0, 0.0, 1.0, 1.0),
            corner(1.0, 0.0, 1.0, 1.0),
            corner(0.0, 2.0, 1.0, 1.0),
        ];
        for c in &mut dim {
            c.light = 0.5;
        }
        raster.draw(dim, 0);
        let canvas = raster.shade([255, 255, 255]);
        let [r, g, b] = viridis(1.0);
        let half = |c: u8| (f64::from(c) * 0.5).round() as u8;
        assert_eq!(canvas.get(0, 0), [half(r), half(g), half(b)]);
        assert_eq!(canvas.get(2, 0), [255, 255, 255]);
    }

    #[test]
    fn segment_shading_draws_flat_colours_and_a_boundary_line() {
        // Two triangles sharing the diagonal of an 8 × 8 square: faces 0 and 1 in segments 0
        // and 1, lit fully.
        let mut raster = Raster::new(8, 8);
        raster.draw(
            [
                corner(0.0, 0.0, 1.0, 0.0),
                corner(8.0, 0.0, 1.0, 0.0),
                corner(0.0, 8.0, 1.0, 0.0),
            ],
            0,
        );
        raster.draw(
            [
                corner(8.0, 0.0, 1.0, 0.0),
                corner(8.0, 8.0, 1.0, 0.0),
                corner(0.0, 8.0, 1.0, 0.0),
            ],
            1,
        );
        let colours = [[200, 0, 0], [0, 0, 200]];
        let ink = [1, 2, 3];
        let canvas = raster.shade_segments([255; 3], &[0, 1], |s| colours[s], ink, 1);
        assert_eq!(canvas.get(0, 0), colours[0]);
        assert_eq!(canvas.get(7, 7), colours[1]);
        // Centres (3.5, 3.5) and (4.5, 3.5) lie on either side of x + y = 8: the line.
        assert_eq!(canvas.get(3, 3), ink);
        assert_eq!(canvas.get(4, 3), ink);
        // Same segment on both faces: no line.
        let plain = raster.shade_segments([255; 3], &[0, 0], |s| colours[s], ink, 1);
        assert_eq!(plain.get(3, 3), colours[0]);
    }
}
