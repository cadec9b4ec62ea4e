//! Pictures of functions on a mesh, like the paper's Figures 1, 5 and 6: a headless software
//! rasteriser draws the mesh shaded by a per-vertex scalar through the viridis colour map, with
//! Lambert + ambient lighting, a title and a colour bar per panel, several fields in a grid.
//!
//! - **Camera**: looks at the centre of the mesh's bounding sphere from the direction given by
//!   [`View`] (azimuth about the +y axis from +z towards +x, elevation towards +y; +y is up on
//!   screen), from far enough that the whole sphere is in view; the projected mesh is then
//!   framed to fill the panel. Perspective (30° field of view) or orthographic.
//! - **Shading**: per-vertex values are mapped linearly from their own minimum and maximum
//!   (per panel) to viridis; the light (a fixed direction from the upper left of the viewer,
//!   ambient 0.3 + diffuse 0.7, two-sided) is computed at the vertices from area-weighted vertex
//!   normals and interpolated with the values across each triangle (Gouraud), perspective-
//!   correctly, behind a z-buffer.
//! - **Anti-aliasing**: the whole picture (meshes, colour bars, text) is drawn at
//!   `supersampling²` samples per pixel and box filtered.
//! - **Text** uses the vendored DejaVu Sans through plotters' `ab_glyph` backend.

mod camera;
pub(crate) mod canvas;
mod colormap;
mod raster;

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use dirac::TriMesh;
use dirac::geometry::{cross, dot, norm, sub, vertex_normals};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use thiserror::Error;

use camera::{Camera, Projected};
use canvas::{Canvas, FONT_FAMILY};
pub use colormap::segment_colour;
use colormap::viridis;
use raster::{Corner, Raster};

/// A function on the vertices of a mesh, to be drawn as one panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    /// The panel's title.
    pub label: String,
    /// One value per vertex.
    pub values: Vec<f64>,
}

/// Where the camera looks from, in degrees: the view direction is
/// `(sin az cos el, sin el, cos az cos el)` from the mesh's centre towards the eye, so
/// `0,0` looks along −z with +y up, `90,0` along −x, `0,90` straight down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Rotation about the +y axis, from +z towards +x.
    pub azimuth_degrees: f64,
    /// Angle above the xz-plane.
    pub elevation_degrees: f64,
}

impl View {
    /// The view from azimuth and elevation in degrees.
    pub const fn new(azimuth_degrees: f64, elevation_degrees: f64) -> Self {
        Self {
            azimuth_degrees,
            elevation_degrees,
        }
    }
}

impl Default for View {
    /// `140,20`: a three-quarter view from a little above that shows the built-in `spot`
    /// (y up, facing −z) with its face, flank and legs.
    fn default() -> Self {
        Self::new(DEFAULT_AZIMUTH, DEFAULT_ELEVATION)
    }
}

/// Azimuth of the default view.
const DEFAULT_AZIMUTH: f64 = 140.0;
/// Elevation of the default view.
const DEFAULT_ELEVATION: f64 = 20.0;

/// A view that is not `AZIMUTH,ELEVATION` with two finite numbers.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("`{text}` is not a view AZIMUTH,ELEVATION in degrees (for example `30,20`)")]
pub struct ViewParseError {
    text: String,
}

impl FromStr for View {
    type Err = ViewParseError;

    /// Parses `"az,el"` (degrees, spaces allowed around the numbers).
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let error = || ViewParseError {
            text: text.to_string(),
        };
        let (azimuth, elevation) = text.split_once(',').ok_or_else(error)?;
        let angle = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(error)
        };
        Ok(Self::new(angle(azimuth)?, angle(elevation)?))
    }
}

impl fmt::Display for View {
    /// `az,el`, the form [`View::from_str`] reads.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{}", self.azimuth_degrees, self.elevation_degrees)
    }
}

/// How 3-D points become pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Projection {
    /// Central projection with a 30° field of view.
    #[default]
    Perspective,
    /// Parallel projection.
    Orthographic,
}

/// Size, view and layout of a picture.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Width of the whole image in pixels.
    pub width: u32,
    /// Height of the whole image in pixels.
    pub height: u32,
    /// Where the camera looks from; both angles must be finite.
    pub view: View,
    /// Panels per row for several fields; `None` chooses the count that makes the panels
    /// closest to square.
    pub columns: Option<usize>,
    /// Perspective or orthographic.
    pub projection: Projection,
    /// Samples per pixel along each axis (1 = no anti-aliasing). Reduced automatically for
    /// large images so the supersampled image has at most 2²⁴ samples.
    pub supersampling: u32,
}

impl Default for RenderOptions {
    /// 800×600, the default view, automatic columns, perspective, 3×3 supersampling.
    fn default() -> Self {
        Self {
            width: 800,
            height: 600,
            view: View::default(),
            columns: None,
            projection: Projection::Perspective,
            supersampling: 3,
        }
    }
}

/// Largest image side accepted, in pixels.
pub const MAX_SIDE: u32 = 4096;

/// Smallest panel side, in pixels: room for a title, a colour bar and a picture.
pub const MIN_PANEL: u32 = 48;

/// The most panels an image of `width × height` pixels holds, each at least [`MIN_PANEL`]
/// pixels on a side: callers check a panel count with it before computing the fields.
pub fn max_panels(width: u32, height: u32) -> usize {
    (width / MIN_PANEL) as usize * (height / MIN_PANEL) as usize
}

/// Most samples of the supersampled image (bounds memory: 3 bytes each for the image, 16 for
/// the z-buffer of a panel).
const MAX_SAMPLES: u64 = 1 << 24;

/// Why a picture could not be made.
#[derive(Debug, Error)]
pub enum RenderError {
    /// The list of fields is empty.
    #[error("nothing to render: no fields given")]
    NoFields,
    /// A field does not have one value per vertex.
    #[error("field `{label}` has {values} values but the mesh has {vertices} vertices")]
    FieldLength {
        /// The field's label.
        label: String,
        /// Number of values it has.
        values: usize,
        /// Number of vertices of the mesh.
        vertices: usize,
    },
    /// A field has a NaN or infinite value.
    #[error("field `{label}` has the non-finite value {value} at vertex {vertex}")]
    NonFinite {
        /// The field's label.
        label: String,
        /// The first such vertex.
        vertex: usize,
        /// Its value.
        value: f64,
    },
    /// Width or height is zero.
    #[error("the image size {width}x{height} has a zero side")]
    ZeroSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// Width or height exceeds [`MAX_SIDE`].
    #[error("the image size {width}x{height} exceeds the largest side of {MAX_SIDE} pixels")]
    TooLarge {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// An angle of the view is NaN or infinite ([`View::from_str`] never gives one, but the
    /// fields are public); there is no direction to look from.
    #[error("the view {view} has a non-finite angle")]
    NonFiniteView {
        /// The requested view.
        view: View,
    },
    /// `columns` is `Some(0)`.
    #[error("the number of columns must be positive")]
    ZeroColumns,
    /// `supersampling` is 0.
    #[error("the supersampling factor must be at least 1")]
    ZeroSupersampling,
    /// The panels of the grid would be smaller than [`MIN_PANEL`].
    #[error(
        "the image size {width}x{height} is too small for {fields} panels in {columns} columns \
         (each panel needs at least {MIN_PANEL}x{MIN_PANEL} pixels)"
    )]
    TooSmall {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Number of panels.
        fields: usize,
        /// Panels per row.
        columns: usize,
    },
    /// A segmentation does not have one label per face.
    #[error("the segmentation has {labels} labels but the mesh has {faces} faces")]
    LabelCount {
        /// Labels given.
        labels: usize,
        /// Faces of the mesh.
        faces: usize,
    },
    /// Drawing the titles or labels failed.
    #[error("cannot draw the text of the picture: {0}")]
    Text(String),
    /// Writing the file failed.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What failed.
        source: io::Error,
    },
}

/// Renders `fields` on `mesh` into the PNG file `path`: one panel of `width × height` for one
/// field, a grid of panels filling `width × height` for several.
pub fn render_png(
    mesh: &TriMesh,
    fields: &[Field],
    options: &RenderOptions,
    path: &Path,
) -> Result<(), RenderError> {
    render(mesh, fields, options)?
        .write_png(path)
        .map_err(|source| RenderError::Io {
            path: path.to_path_buf(),
            source,
        })
}

/// Renders a segmentation of `mesh` into the PNG file `path`: one panel of
/// `width × height` titled `title`, every face in the flat colour of its segment
/// ([`segment_colour`]`(labels[face])`) under the same lighting as [`render_png`], and dark
/// lines where faces of different segments meet on screen (the segments' boundaries, and
/// where one segment passes in front of another). `options.columns` is not used.
pub fn render_segments_png(
    mesh: &TriMesh,
    labels: &[usize],
    title: &str,
    options: &RenderOptions,
    path: &Path,
) -> Result<(), RenderError> {
    render_segments(mesh, labels, title, options)?
        .write_png(path)
        .map_err(|source| RenderError::Io {
            path: path.to_path_buf(),
            source,
        })
}

/// The picture of [`render_segments_png`] in memory.
fn render_segments(
    mesh: &TriMesh,
    labels: &[usize],
    title: &str,
    options: &RenderOptions,
) -> Result<Canvas, RenderError> {
    validate_options(options)?;
    if labels.len() != mesh.face_count() {
        return Err(RenderError::LabelCount {
            labels: labels.len(),
            faces: mesh.face_count(),
        });
    }
    let (width, height) = (options.width, options.height);
    if width < MIN_PANEL || height < MIN_PANEL {
        return Err(RenderError::TooSmall {
            width,
            height,
            fields: 1,
            columns: 1,
        });
    }
    let factor = supersampling(options.supersampling, width, height);
    let cell = Rect {
        x: 0,
        y: 0,
        width: width * factor,
        height: height * factor,
    };
    let panel = Panel::new(cell, factor);
    let scene = Scene::new(mesh, options, panel.viewport);
    let raster = scene.draw(mesh, &vec![0.0; mesh.vertex_count()]);
    // Lines about one output pixel wide: `factor` samples.
    let radius = (factor as usize).div_ceil(2);
    let image = raster.shade_segments(BACKGROUND, labels, segment_colour, INK, radius);
    let mut canvas = Canvas::new(cell.width, cell.height, BACKGROUND);
    canvas.blit(panel.viewport.x, panel.viewport.y, &image);
    let [heading, ..] = panel.texts(title, 0.0, 0.0);
    draw_texts(&mut canvas, &[heading])?;
    Ok(canvas.downsample(factor))
}

/// White.
const BACKGROUND: [u8; 3] = [255, 255, 255];
/// Colour of text and outlines.
const INK: [u8; 3] = [30, 30, 30];
/// Light intensity where the surface faces away from the light.
const AMBIENT: f64 = 0.3;
/// Light intensity added where the surface faces the light.
const DIFFUSE: f64 = 0.7;
/// Direction towards the light in camera coordinates (right, up, towards the viewer): from
/// the upper left of the viewer, so silhouettes on the right and below are darker.
const LIGHT: [f64; 3] = [-0.36, 0.48, 0.8];
/// Panels whose aspect (width/height) is closest to this are preferred: a little taller than
/// wide, since the title and colour bar take height.
const PREFERRED_ASPECT: f64 = 0.9;

/// The whole picture in memory.
fn render(
    mesh: &TriMesh,
    fields: &[Field],
    options: &RenderOptions,
) -> Result<Canvas, RenderError> {
    validate(mesh, fields, options)?;
    let (width, height) = (options.width, options.height);
    let columns = match options.columns {
        Some(0) => return Err(RenderError::ZeroColumns),
        Some(c) => c.min(fields.len()),
        None => automatic_columns(fields.len(), width, height),
    };
    let rows = fields.len().div_ceil(columns);
    if width / (columns as u32) < MIN_PANEL || height / (rows as u32) < MIN_PANEL {
        return Err(RenderError::TooSmall {
            width,
            height,
            fields: fields.len(),
            columns,
        });
    }
    // Everything is drawn at `factor` times the size and box filtered at the end, so edges,
    // text and the colour bar are anti-aliased alike.
    let factor = supersampling(options.supersampling, width, height);
    let (big_width, big_height) = (width * factor, height * factor);
    // Cell boundaries are rounded so the cells tile the image exactly.
    let cell = |i: usize| {
        let (column, row) = ((i % columns) as u32, (i / columns) as u32);
        let (columns, rows) = (columns as u32, rows as u32);
        let x0 = column * big_width / columns;
        let y0 = row * big_height / rows;
        Rect {
            x: x0,
            y: y0,
            width: (column + 1) * big_width / columns - x0,
            height: (row + 1) * big_height / rows - y0,
        }
    };
    // Every cell has the same layout up to a pixel; the first one's viewport fixes the scene.
    let scene = Scene::new(mesh, options, Panel::new(cell(0), factor).viewport);

    let mut canvas = Canvas::new(big_width, big_height, BACKGROUND);
    let mut texts = Vec::new();
    for (i, field) in fields.iter().enumerate() {
        let panel = Panel::new(cell(i), factor);
        let (low, high) = field
            .values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        // Finite values can span more than f64::MAX (e.g. ±1e308); halving them all keeps
        // the range finite, so the extremes do not become ∞/∞ = NaN.
        let scale = if (high - low).is_finite() { 1.0 } else { 0.5 };
        let span = scale * high - scale * low;
        // A constant field has no range; show it in the middle of the map.
        let coordinate: Vec<f64> = field
            .values
            .iter()
            .map(|&v| {
                if span > 0.0 {
                    (scale * v - scale * low) / span
                } else {
                    0.5
                }
            })
            .collect();
        let image = scene.draw(mesh, &coordinate).shade(BACKGROUND);
        canvas.blit(panel.viewport.x, panel.viewport.y, &image);
        draw_colour_bar(&mut canvas, panel.bar, factor);
        texts.extend(panel.texts(&field.label, low, high));
    }
    draw_texts(&mut canvas, &texts)?;
    Ok(canvas.downsample(factor))
}

/// Checks everything about the input that does not depend on the layout.
fn validate(mesh: &TriMesh, fields: &[Field], options: &RenderOptions) -> Result<(), RenderError> {
    validate_options(options)?;
    if fields.is_empty() {
        return Err(RenderError::NoFields);
    }
    for field in fields {
        if field.values.len() != mesh.vertex_count() {
            return Err(RenderError::FieldLength {
                label: field.label.clone(),
                values: field.values.len(),
                vertices: mesh.vertex_count(),
            });
        }
        if let Some((vertex, &value)) = field
            .values
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite())
        {
            return Err(RenderError::NonFinite {
                label: field.label.clone(),
                vertex,
                value,
            });
        }
    }
    Ok(())
}

/// Checks the size, supersampling and view.
fn validate_options(options: &RenderOptions) -> Result<(), RenderError> {
    let (width, height) = (options.width, options.height);
    if width == 0 || height == 0 {
        return Err(RenderError::ZeroSize { width, height });
    }
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(RenderError::TooLarge { width, height });
    }
    if options.supersampling == 0 {
        return Err(RenderError::ZeroSupersampling);
    }
    let view = options.view;
    if !(view.azimuth_degrees.is_finite() && view.elevation_degrees.is_finite()) {
        return Err(RenderError::NonFiniteView { view });
    }
    Ok(())
}

/// The column count whose panels are closest (in log aspect) to [`PREFERRED_ASPECT`].
fn automatic_columns(fields: usize, width: u32, height: u32) -> usize {
    let misfit = |columns: usize| {
        let rows = fields.div_ceil(columns);
        let aspect = (f64::from(width) / columns as f64) / (f64::from(height) / rows as f64);
        (aspect / PREFERRED_ASPECT).ln().abs()
    };
    (1..=fields)
        .min_by(|&a, &b| misfit(a).total_cmp(&misfit(b)))
        .unwrap_or(1)
}

/// The supersampling factor actually used: the requested one, reduced until the supersampled
/// image has at most [`MAX_SAMPLES`] samples.
fn supersampling(requested: u32, width: u32, height: u32) -> u32 {
    let pixels = u64::from(width) * u64::from(height);
    let largest = (MAX_SAMPLES / pixels.max(1)).isqrt();
    // `largest` ≤ 2¹², so the conversion cannot fail.
    requested
        .min(u32::try_from(largest).unwrap_or(u32::MAX))
        .max(1)
}

/// A rectangle of pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Rect {
    x: u32,
    y: u32,
    width: u32,
    height: u32,
}

/// One text to draw: content, anchor point, anchor and size.
struct Label {
    text: String,
    at: (i32, i32),
    anchor: Pos,
    size: f64,
    /// Widest the text may be; a longer one is drawn smaller.
    max_width: u32,
}

/// The layout of one panel: title at the top, the mesh, the colour bar with its end values.
#[derive(Debug, Clone, Copy)]
struct Panel {
    cell: Rect,
    font_size: f64,
    /// Margin around the parts, in pixels.
    pad: u32,
    viewport: Rect,
    bar: Rect,
}

impl Panel {
    /// The layout of a cell of the image drawn at `factor` times the output size; the font
    /// grows with the cell's shorter side (in output pixels) within readable limits.
    fn new(cell: Rect, factor: u32) -> Self {
        let scale = f64::from(factor);
        let font_size =
            (0.065 * f64::from(cell.width.min(cell.height)) / scale).clamp(7.0, 26.0) * scale;
        let pad = (0.35 * font_size).ceil() as u32;
        let line = (1.3 * font_size).ceil() as u32;
        let bar_height = (0.6 * font_size).ceil() as u32;
        // The decorations take about 4.3 font sizes = 0.28 of the shorter side (at least 34
        // output pixels at the smallest font), less than a cell of at least MIN_PANEL pixels,
        // so the viewport is never empty.
        let viewport = Rect {
            x: cell.x + pad,
            y: cell.y + pad + line,
            width: cell.width - 2 * pad,
            height: cell.height - 3 * pad - 2 * line - bar_height,
        };
        let bar = Rect {
            x: cell.x + cell.width * 3 / 20,
            y: viewport.y + viewport.height + pad / 2,
            width: cell.width * 7 / 10,
            height: bar_height,
        };
        Self {
            cell,
            font_size,
            pad,
            viewport,
            bar,
        }
    }

    /// The title and the colour bar's end values.
    fn texts(&self, title: &str, low: f64, high: f64) -> [Label; 3] {
        let below_bar = (self.bar.y + self.bar.height + self.pad / 2) as i32;
        let label = |text: String, at: (i32, i32), anchor: Pos, max_width: u32| Label {
            text,
            at,
            anchor,
            size: self.font_size,
            max_width,
        };
        let half = self.cell.width / 2;
        [
            label(
                title.to_string(),
                ((self.cell.x + half) as i32, (self.cell.y + self.pad) as i32),
                Pos::new(HPos::Center, VPos::Top),
                self.viewport.width,
            ),
            label(
                format_value(low),
                (self.bar.x as i32, below_bar),
                Pos::new(HPos::Left, VPos::Top),
                half,
            ),
            label(
                format_value(high),
                ((self.bar.x + self.bar.width) as i32, below_bar),
                Pos::new(HPos::Right, VPos::Top),
                half,
            ),
        ]
    }
}

/// A horizontal viridis gradient, low on the left, with an outline `thickness` samples wide.
fn draw_colour_bar(canvas: &mut Canvas, bar: Rect, thickness: u32) {
    for x in 0..bar.width {
        let colour = viridis(f64::from(x) / f64::from(bar.width.saturating_sub(1).max(1)));
        for y in 0..bar.height {
            let inside = (thickness..bar.width.saturating_sub(thickness)).contains(&x)
                && (thickness..bar.height.saturating_sub(thickness)).contains(&y);
            canvas.set(bar.x + x, bar.y + y, if inside { colour } else { INK });
        }
    }
}

/// Draws the labels with plotters, shrinking any that is wider than it may be.
fn draw_texts(canvas: &mut Canvas, labels: &[Label]) -> Result<(), RenderError> {
    let area = canvas.drawing_area();
    let text_error = |e: &dyn std::error::Error| RenderError::Text(e.to_string());
    let ink = RGBColor(INK[0], INK[1], INK[2]);
    for label in labels {
        let style = |size: f64| {
            (FONT_FAMILY, size)
                .into_font()
                .color(&ink)
                .pos(label.anchor)
        };
        let (measured, _) = area
            .estimate_text_size(&label.text, &style(label.size))
            .map_err(|e| text_error(&e))?;
        let size = if measured > label.max_width {
            label.size * f64::from(label.max_width) / f64::from(measured)
        } else {
            label.size
        };
        area.draw(&Text::new(label.text.as_str(), label.at, style(size)))
            .map_err(|e| text_error(&e))?;
    }
    area.present().map_err(|e| text_error(&e))
}

/// A number for a colour-bar end or an axis tick: 3 significant digits, scientific outside
/// `[10⁻³, 10⁴)`, without trailing zeros (`3`, `0.25`, `1.5e10`).
pub fn format_value(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    let magnitude = x.abs();
    let text = if (1e-3..1e4).contains(&magnitude) {
        let decimals = (2 - magnitude.log10().floor() as i32).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.2e}")
    };
    let (mantissa, exponent) = text.split_at(text.find('e').unwrap_or(text.len()));
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.')
    } else {
        mantissa
    };
    format!("{mantissa}{exponent}")
}

/// The mesh projected into a supersampled viewport, with the light at every face corner.
struct Scene {
    projected: Vec<Projected>,
    /// Light intensity at the three corners of each face.
    light: Vec<[f64; 3]>,
    width: usize,
    height: usize,
}

impl Scene {
    fn new(mesh: &TriMesh, options: &RenderOptions, viewport: Rect) -> Self {
        let positions = mesh.positions();
        let camera = Camera::new(positions, options.view, options.projection);
        let (width, height) = (viewport.width as usize, viewport.height as usize);
        let projected = camera.project(positions, width as f64, height as f64);
        // Vertex normals fail only where a vertex's faces cancel exactly; the faces' own
        // normals are then used at that vertex's corners instead.
        let normals = vertex_normals(mesh).ok();
        let light = mesh
            .faces()
            .iter()
            .map(|&[i, j, k]| {
                let face_normal = cross(
                    sub(positions[j], positions[i]),
                    sub(positions[k], positions[i]),
                );
                let centroid: [f64; 3] = std::array::from_fn(|c| {
                    (positions[i][c] + positions[j][c] + positions[k][c]) / 3.0
                });
                // Two-sided lighting: on a face seen from behind, the normals are flipped.
                let side = if dot(face_normal, camera.towards_eye(centroid)) < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                [i, j, k].map(|v| {
                    let n = normals.as_ref().map_or(face_normal, |normals| normals[v]);
                    let n = camera.to_camera(n.map(|x| side * x / norm(n)));
                    AMBIENT + DIFFUSE * dot(n, LIGHT).max(0.0)
                })
            })
            .collect();
        Self {
            projected,
            light,
            width,
            height,
        }
    }

    /// Rasterises the mesh with colour-map coordinates `coordinate` (one per vertex).
    fn draw(&self, mesh: &TriMesh, coordinate: &[f64]) -> Raster {
        let mut raster = Raster::new(self.width, self.height);
        for (index, (face, light)) in mesh.faces().iter().zip(&self.light).enumerate() {
            let corners = [0, 1, 2].map(|c| Corner {
                at: self.projected[face[c]],
                value: coordinate[face[c]],
                light: light[c],
            });
            // Face indices fit u32: the renderer's meshes are far smaller than 2³² faces.
            raster.draw(corners, index as u32);
        }
        raster
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_parse_and_print() {
        assert_eq!("30,20".parse(), Ok(View::new(30.0, 20.0)));
        assert_eq!(" -45.5 , 0 ".parse(), Ok(View::new(-45.5, 0.0)));
        for bad in ["30", "30,", "a,b", "1,2,3", "inf,0", ""] {
            assert!(bad.parse::<View>().is_err(), "{bad:?} parsed");
        }
        let view = View::new(12.5, -3.0);
        assert_eq!(view.to_string().parse(), Ok(view));
    }

    #[test]
    fn automatic_columns_prefer_square_panels() {
        assert_eq!(automatic_columns(1, 800, 600), 1);
        assert_eq!(automatic_columns(4, 800, 220), 4);
        assert_eq!(automatic_columns(4, 800, 800), 2);
        assert_eq!(automatic_columns(3, 300, 900), 1);
    }

    #[test]
    fn values_have_three_significant_digits_and_no_trailing_zeros() {
        assert_eq!(format_value(0.0), "0");
        assert_eq!(format_value(1.23456), "1.23");
        assert_eq!(format_value(-0.0123456), "-0.0123");
        assert_eq!(format_value(123.456), "123");
        assert_eq!(format_value(3.0), "3");
        assert_eq!(format_value(0.5), "0.5");
        assert_eq!(format_value(1e10), "1e10");
        assert_eq!(format_value(-2.5e-5), "-2.5e-5");
    }

    #[test]
    fn supersampling_is_bounded_by_the_sample_budget() {
        assert_eq!(supersampling(3, 800, 600), 3);
        assert_eq!(supersampling(3, 1920, 1080), 2);
        assert_eq!(supersampling(3, 4096, 4096), 1);
        assert_eq!(supersampling(u32::MAX, 48, 48), 85, "no overflow");
    }
}
