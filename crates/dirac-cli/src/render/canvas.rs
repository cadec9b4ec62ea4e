//! An 8-bit RGB image in memory: pixels set by the rasteriser, text and charts drawn into it
//! by plotters, written as PNG by the `png` crate (so I/O errors keep their `io::Error`).

use std::fs::File;
use std::io::{self, BufWriter};
use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;
use plotters::style::FontStyle;

/// DejaVu Sans (Bitstream Vera licence, see `assets/DejaVuSans-LICENSE.txt`). Vendored so text
/// renders identically everywhere, without fontconfig or system fonts.
static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// The font family name the vendored font is registered under.
pub const FONT_FAMILY: &str = "sans-serif";

/// Makes the vendored font available to plotters' `ab_glyph` text backend (once per process).
pub fn register_font() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        // The font is a fixed, valid TrueType file; were it rejected, drawing text would fail
        // later with plotters' "font unavailable", which callers report as a drawing error.
        let _ = plotters::style::register_font(FONT_FAMILY, FontStyle::Normal, FONT);
    });
}

/// An RGB image, rows top to bottom, three bytes per pixel.
#[derive(Debug, Clone)]
pub struct Canvas {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Canvas {
    /// A `width × height` canvas filled with `background`.
    pub fn new(width: u32, height: u32, background: [u8; 3]) -> Self {
        Self {
            width,
            height,
            rgb: background.repeat(width as usize * height as usize),
        }
    }

    /// Width in pixels.
    #[cfg(test)]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[cfg(test)]
    pub fn height(&self) -> u32 {
        self.height
    }

    fn offset(&self, x: u32, y: u32) -> usize {
        3 * (y as usize * self.width as usize + x as usize)
    }

    /// The pixel at column `x`, row `y` (which must be inside the canvas).
    #[cfg(test)]
    pub fn get(&self, x: u32, y: u32) -> [u8; 3] {
        let i = self.offset(x, y);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Sets the pixel at column `x`, row `y`; outside the canvas nothing happens.
    pub fn set(&mut self, x: u32, y: u32, colour: [u8; 3]) {
        if x < self.width && y < self.height {
            let i = self.offset(x, y);
            self.rgb[i..i + 3].copy_from_slice(&colour);
        }
    }

    /// Copies `image` with its top-left corner at `(x, y)`, clipped to the canvas.
    pub fn blit(&mut self, x: u32, y: u32, image: &Canvas) {
        let columns = image.width.min(self.width.saturating_sub(x));
        for row in 0..image.height.min(self.height.saturating_sub(y)) {
            let from = image.offset(0, row);
            let to = self.offset(x, y + row);
            let length = 3 * columns as usize;
            self.rgb[to..to + length].copy_from_slice(&image.rgb[from..from + length]);
        }
    }

    /// The canvas reduced by `factor` in each direction, every pixel the mean of a
    /// `factor × factor` block (a box filter: the anti-aliasing of supersampled drawing).
    pub fn downsample(&self, factor: u32) -> Canvas {
        let (width, height) = (self.width / factor, self.height / factor);
        let mut small = Canvas::new(width, height, [0, 0, 0]);
        let count = factor * factor;
        for y in 0..height {
            for x in 0..width {
                let mut sum = [0u32; 3];
                for sy in 0..factor {
                    let row = self.offset(x * factor, y * factor + sy);
                    for pixel in self.rgb[row..row + 3 * factor as usize].chunks_exact(3) {
                        for c in 0..3 {
                            sum[c] += u32::from(pixel[c]);
                        }
                    }
                }
                // Rounded mean; fits in u8 because every term does.
                small.set(x, y, sum.map(|s| ((s + count / 2) / count) as u8));
            }
        }
        small
    }

    /// A plotters drawing area on the canvas, for text and charts.
    pub fn drawing_area(&mut self) -> DrawingArea<BitMapBackend<'_>, plotters::coord::Shift> {
        register_font();
        BitMapBackend::with_buffer(&mut self.rgb, (self.width, self.height)).into_drawing_area()
    }

    /// Writes the canvas as an 8-bit RGB PNG.
    pub fn write_png(&self, path: &Path) -> io::Result<()> {
        let file = BufWriter::new(File::create(path)?);
        let mut encoder = png::Encoder::new(file, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(into_io)?;
        writer.write_image_data(&self.rgb).map_err(into_io)?;
        writer.finish().map_err(into_io)
    }
}

/// The I/O error inside a PNG encoding error; the other kinds (bad parameters, limits) cannot
/// arise for a canvas whose buffer matches its size, and are passed on as `Other`.
fn into_io(error: png::EncodingError) -> io::Error {
    match error {
        png::EncodingError::IoError(error) => error,
        other => io::Error::other(other),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blit_copies_and_clips() {
        let mut canvas = Canvas::new(4, 3, [0, 0, 0]);
        let patch = Canvas::new(3, 3, [9, 8, 7]);
        canvas.blit(2, 1, &patch);
        assert_eq!(canvas.get(1, 1), [0, 0, 0]);
        assert_eq!(canvas.get(2, 1), [9, 8, 7]);
        assert_eq!(canvas.get(3, 2), [9, 8, 7]);
        assert_eq!(canvas.get(3, 0), [0, 0, 0]);
    }

    #[test]
    fn downsampling_averages_blocks() {
        let mut canvas = Canvas::new(4, 2, [0, 0, 0]);
        canvas.set(0, 0, [255, 100, 4]);
        canvas.set(3, 1, [8, 8, 8]);
        let small = canvas.downsample(2);
        assert_eq!((small.width(), small.height()), (2, 1));
        assert_eq!(small.get(0, 0), [64, 25, 1]);
        assert_eq!(small.get(1, 0), [2, 2, 2]);
    }

    #[test]
    fn text_is_drawn_with_the_vendored_font() {
        let mut canvas = Canvas::new(60, 20, [255, 255, 255]);
        canvas
            .drawing_area()
            .draw(&Text::new("Ag", (2, 2), (FONT_FAMILY, 14.0).into_font()))
            .expect("text draws");
        let dark = (0..20)
            .flat_map(|y| (0..60).map(move |x| (x, y)))
            .filter(|&(x, y)| canvas.get(x, y)[0] < 128)
            .count();
        assert!(dark > 10, "only {dark} dark pixels");
    }
}
