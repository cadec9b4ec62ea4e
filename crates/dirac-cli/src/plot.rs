//! Charts: spectra of several meshes or operators in one picture (eigenvalue index against
//! eigenvalue, like the paper's Figures 8 and 13) and labelled 2-D point sets (like Figure 9),
//! optionally on a logarithmic y axis with horizontal reference levels (a score per shape and
//! its thresholds), each with a title, axis labels and a legend, written as PNG or SVG by the
//! file's extension.
//!
//! Groups are told apart by colour, from the Okabe–Ito palette (distinguishable with the
//! common colour-vision deficiencies), repeated after eight groups.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use thiserror::Error;

use crate::render::canvas::{Canvas, FONT_FAMILY, register_font};
use crate::render::format_value;

/// The eigenvalues of one spectrum, in order (`values[i]` is plotted at index `i`).
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry.
    pub label: String,
    /// Eigenvalues.
    pub values: Vec<f64>,
}

/// A set of points in the plane drawn in one colour.
#[derive(Debug, Clone, PartialEq)]
pub struct PointGroup {
    /// Legend entry.
    pub label: String,
    /// The points `(x, y)`.
    pub points: Vec<(f64, f64)>,
}

/// A horizontal line across the whole chart at height `value` (a threshold, say).
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    /// Legend entry.
    pub label: String,
    /// Its height on the y axis.
    pub value: f64,
}

/// The axis descriptions and the y scale of [`plot_points_with_levels`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axes<'a> {
    /// Description of the x axis.
    pub x: &'a str,
    /// Description of the y axis.
    pub y: &'a str,
    /// A logarithmic y axis (every y value and level must then be positive).
    pub log_y: bool,
    /// Where the legend goes (a corner the data leave free).
    pub legend: Corner,
}

/// A corner of a chart's plotting area.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Corner {
    /// Top left (the default of every chart).
    #[default]
    UpperLeft,
    /// Top right.
    UpperRight,
    /// Bottom left.
    LowerLeft,
    /// Bottom right.
    LowerRight,
}

impl Corner {
    /// The plotters position.
    fn position(self) -> SeriesLabelPosition {
        match self {
            Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
            Corner::UpperRight => SeriesLabelPosition::UpperRight,
            Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
            Corner::LowerRight => SeriesLabelPosition::LowerRight,
        }
    }
}

/// Why a chart could not be made.
#[derive(Debug, Error)]
pub enum PlotError {
    /// There are no series or groups, or all are empty.
    #[error("nothing to plot: no data points")]
    Empty,
    /// A value is NaN or infinite.
    #[error("`{label}` has the non-finite value {value} at index {index}")]
    NonFinite {
        /// The series' or group's label.
        label: String,
        /// Index of the value (of the point for a group).
        index: usize,
        /// The value.
        value: f64,
    },
    /// A y value or level is zero or negative on a logarithmic y axis.
    #[error(
        "`{label}` has the value {value} at index {index}, which a logarithmic axis cannot show \
         (only positive values)"
    )]
    NonPositive {
        /// The group's or level's label.
        label: String,
        /// Index of the point (0 for a level).
        index: usize,
        /// The value.
        value: f64,
    },
    /// The file name ends neither in `.png` nor in `.svg`.
    #[error("{}: unknown picture format (the file name must end in .png or .svg)", path.display())]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
    },
    /// plotters failed to draw the chart.
    #[error("cannot draw {}: {message}", path.display())]
    Draw {
        /// The file.
        path: PathBuf,
        /// What failed.
        message: String,
    },
    /// Writing the file failed.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What failed.
        source: io::Error,
    },
}

/// Plots each series as eigenvalue against its index (from 0), points joined by lines, into
/// `path` (`.png` or `.svg`).
pub fn plot_spectra(series: &[Series], title: &str, path: &Path) -> Result<(), PlotError> {
    let groups = series
        .iter()
        .map(|s| {
            let points = s
                .values
                .iter()
                .enumerate()
                .map(|(i, &v)| (i as f64, v))
                .collect();
            (s.label.as_str(), points)
        })
        .collect();
    // At most one tick per index, so the ticks fall on whole numbers.
    let longest = series.iter().map(|s| s.values.len()).max().unwrap_or(0);
    let chart = Chart {
        title,
        x_description: "eigenvalue index",
        y_description: "eigenvalue λ",
        groups,
        lines: true,
        x_ticks: longest.clamp(1, DEFAULT_TICKS),
        levels: Vec::new(),
        log_y: false,
        legend: Corner::UpperLeft,
    };
    chart.save(path)
}

/// Plots each group's points as dots of one colour into `path` (`.png` or `.svg`).
pub fn plot_points(groups: &[PointGroup], title: &str, path: &Path) -> Result<(), PlotError> {
    let axes = Axes {
        x: "first coordinate",
        y: "second coordinate",
        log_y: false,
        legend: Corner::UpperLeft,
    };
    plot_points_with_levels(groups, &[], axes, title, path)
}

/// Plots each group's points as dots of one colour and each level as a horizontal line across
/// the chart (colours continuing the groups'), with the axes described by `axes`, y
/// logarithmic when `axes.log_y`, into `path` (`.png` or `.svg`).
pub fn plot_points_with_levels(
    groups: &[PointGroup],
    levels: &[Level],
    axes: Axes,
    title: &str,
    path: &Path,
) -> Result<(), PlotError> {
    let chart = Chart {
        title,
        x_description: axes.x,
        y_description: axes.y,
        groups: groups
            .iter()
            .map(|g| (g.label.as_str(), g.points.clone()))
            .collect(),
        lines: false,
        x_ticks: DEFAULT_TICKS,
        levels: levels.iter().map(|l| (l.label.as_str(), l.value)).collect(),
        log_y: axes.log_y,
        legend: axes.legend,
    };
    chart.save(path)
}

/// Most tick labels on an axis.
const DEFAULT_TICKS: usize = 10;

/// Size of a chart in pixels.
const SIZE: (u32, u32) = (900, 600);

/// The Okabe–Ito palette without its black and yellow (too close to the axes and to the white
/// background), then those two.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(240, 228, 66),
];

/// What every kind of chart has in common: labelled groups of points and horizontal levels on
/// a linear x axis and a linear or logarithmic y axis.
struct Chart<'a> {
    title: &'a str,
    x_description: &'a str,
    y_description: &'a str,
    groups: Vec<(&'a str, Vec<(f64, f64)>)>,
    /// Join each group's points in order.
    lines: bool,
    /// Most tick labels on the x axis.
    x_ticks: usize,
    /// Horizontal lines: legend entry and height.
    levels: Vec<(&'a str, f64)>,
    /// Logarithmic y axis: drawn as `log₁₀ y` on a linear axis whose tick labels show `y`.
    log_y: bool,
    /// Where the legend goes.
    legend: Corner,
}

impl Chart<'_> {
    /// Checks the data and writes the chart in the format the extension of `path` names.
    fn save(&self, path: &Path) -> Result<(), PlotError> {
        self.validate()?;
        let draw_error = |e: &dyn std::error::Error| PlotError::Draw {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        let io_error = |source| PlotError::Io {
            path: path.to_path_buf(),
            source,
        };
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("png") => {
                let mut canvas = Canvas::new(SIZE.0, SIZE.1, [255, 255, 255]);
                self.draw(canvas.drawing_area())
                    .map_err(|e| draw_error(&e))?;
                canvas.write_png(path).map_err(io_error)
            }
            Some("svg") => {
                let mut svg = String::new();
                // SVG text is laid out with the font's metrics (legend box, label areas).
                register_font();
                self.draw(SVGBackend::with_string(&mut svg, SIZE).into_drawing_area())
                    .map_err(|e| draw_error(&e))?;
                fs::write(path, svg).map_err(io_error)
            }
            _ => Err(PlotError::UnsupportedFormat {
                path: path.to_path_buf(),
            }),
        }
    }

    fn validate(&self) -> Result<(), PlotError> {
        if self.groups.iter().all(|(_, points)| points.is_empty()) {
            return Err(PlotError::Empty);
        }
        let levels = self
            .levels
            .iter()
            .map(|&(label, y)| (label, vec![(0.0, y)]));
        let all: Vec<(&str, Vec<(f64, f64)>)> = self.groups.iter().cloned().chain(levels).collect();
        for (label, points) in &all {
            for (index, &(x, y)) in points.iter().enumerate() {
                let error = if let Some(value) = [x, y].into_iter().find(|v| !v.is_finite()) {
                    PlotError::NonFinite {
                        label: label.to_string(),
                        index,
                        value,
                    }
                } else if self.log_y && y <= 0.0 {
                    PlotError::NonPositive {
                        label: label.to_string(),
                        index,
                        value: y,
                    }
                } else {
                    continue;
                };
                return Err(error);
            }
        }
        Ok(())
    }

    /// The height at which `y` is drawn: `log₁₀ y` on a logarithmic axis.
    fn drawn_y(&self, y: f64) -> f64 {
        if self.log_y { y.log10() } else { y }
    }

    fn draw<DB: DrawingBackend>(
        &self,
        area: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        area.fill(&WHITE)?;
        let groups: Vec<(&str, Vec<(f64, f64)>)> = self
            .groups
            .iter()
            .map(|(label, points)| {
                let drawn = points.iter().map(|&(x, y)| (x, self.drawn_y(y)));
                (*label, drawn.collect())
            })
            .collect();
        let levels: Vec<(&str, f64)> = (self.levels.iter())
            .map(|&(label, y)| (label, self.drawn_y(y)))
            .collect();
        let all = || groups.iter().flat_map(|(_, points)| points.iter());
        let x_range = padded_range(all().map(|p| p.0));
        let y_range = padded_range(all().map(|p| p.1).chain(levels.iter().map(|l| l.1)));
        let (x_low, x_high) = (x_range.start, x_range.end);
        let y_label = |y: &f64| format_value(if self.log_y { 10f64.powf(*y) } else { *y });
        let mut chart = ChartBuilder::on(&area)
            .caption(self.title, (FONT_FAMILY, 24))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(x_range, y_range)?;
        chart
            .configure_mesh()
            .x_desc(self.x_description)
            .y_desc(self.y_description)
            .label_style((FONT_FAMILY, 14))
            .axis_desc_style((FONT_FAMILY, 16))
            .x_labels(self.x_ticks)
            .y_labels(DEFAULT_TICKS)
            .x_label_formatter(&|x| format_value(*x))
            .y_label_formatter(&y_label)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        // Levels first, so that the dots stay visible on top of them.
        for (j, &(label, y)) in levels.iter().enumerate() {
            let colour = PALETTE[(groups.len() + j) % PALETTE.len()];
            chart
                .draw_series(LineSeries::new(
                    [(x_low, y), (x_high, y)],
                    colour.stroke_width(2),
                ))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        for (i, (label, points)) in groups.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            // Lines first, so the dots stay visible on top of them.
            if self.lines {
                chart
                    .draw_series(LineSeries::new(
                        points.iter().copied(),
                        colour.stroke_width(2),
                    ))?
                    .label(*label)
                    .legend(move |(x, y)| {
                        PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2))
                    });
            }
            let dots =
                chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
            if !self.lines {
                dots.label(*label)
                    .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
            }
        }
        chart
            .configure_series_labels()
            .position(self.legend.position())
            .label_font((FONT_FAMILY, 15))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(120, 120, 120))
            .draw()?;
        area.present()
    }
}

/// The range of `values` widened by 5% on each side (by 1 around a single value), so no point
/// sits on the frame.
fn padded_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (low, high) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
        (l.min(v), h.max(v))
    });
    let margin = if high > low { 0.05 * (high - low) } else { 1.0 };
    low - margin..high + margin
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_padded_and_never_empty() {
        let range = padded_range([0.0, 10.0, 5.0].into_iter());
        assert_eq!(range, -0.5..10.5);
        let single = padded_range([3.0].into_iter());
        assert_eq!(single, 2.0..4.0);
    }

    #[test]
    fn bad_data_is_rejected_before_any_file_is_touched() {
        let path = Path::new("/nonexistent-directory/never-written.png");
        let empty = [Series {
            label: "a".into(),
            values: vec![],
        }];
        assert!(matches!(
            plot_spectra(&empty, "t", path),
            Err(PlotError::Empty)
        ));
        let nan = [PointGroup {
            label: "b".into(),
            points: vec![(0.0, 1.0), (f64::NAN, 2.0)],
        }];
        match plot_points(&nan, "t", path) {
            Err(PlotError::NonFinite { label, index, .. }) => {
                assert_eq!((label.as_str(), index), ("b", 1))
            }
            other => panic!("{other:?}"),
        }
    }
}
