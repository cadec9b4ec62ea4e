//! Charts: `dirac_cli::plot` and `dirac plot spectra` write SVGs whose legends name every
//! series and PNGs of the chart size with content, and reject bad data, file types and
//! operator lists with messages that name them.

mod support;

use std::fs;
use std::path::PathBuf;

use dirac::generators::icosphere;
use dirac::io::write_obj;
use dirac_cli::plot::{
    Axes, Corner, Level, PlotError, PointGroup, Series, plot_points, plot_points_with_levels,
    plot_spectra,
};

use support::{Picture, assert_usage_errors, dirac, stderr, temporary, text};

fn two_series() -> Vec<Series> {
    vec![
        Series {
            label: "alpha mesh".to_string(),
            values: vec![0.0, 1.5, 1.5, 4.0, 6.25],
        },
        Series {
            label: "beta mesh".to_string(),
            values: vec![-2.0, 2.5, -3.0],
        },
    ]
}

#[test]
fn spectra_charts_have_legend_axis_labels_and_title() {
    let svg_path = temporary("plot_spectra.svg");
    plot_spectra(&two_series(), "two spectra", &svg_path).expect("plots");
    let svg = fs::read_to_string(&svg_path).expect("the SVG exists");
    for text in [
        "alpha mesh",
        "beta mesh",
        "two spectra",
        "eigenvalue index",
        "eigenvalue λ",
    ] {
        assert!(svg.contains(text), "{text} missing from the SVG");
    }

    let png_path = temporary("plot_spectra.PNG");
    plot_spectra(&two_series(), "two spectra", &png_path).expect("plots");
    let picture = Picture::read(&png_path);
    assert_eq!((picture.width, picture.height), (900, 600));
    // White background, two palette colours, anti-aliased text and lines.
    assert!(picture.colours() > 50, "{} colours", picture.colours());
}

#[test]
fn point_charts_have_one_legend_entry_per_group() {
    let groups = [
        PointGroup {
            label: "organic".to_string(),
            points: vec![(0.0, 0.0), (1.0, 0.5), (0.2, 0.9)],
        },
        PointGroup {
            label: "man-made".to_string(),
            points: vec![(3.0, -1.0)],
        },
    ];
    let path = temporary("plot_points.svg");
    plot_points(&groups, "shapes", &path).expect("plots");
    let svg = fs::read_to_string(&path).expect("the SVG exists");
    assert!(svg.contains("organic") && svg.contains("man-made") && svg.contains("shapes"));
    // One dot per point plus one legend marker per group.
    assert_eq!(svg.matches("<circle").count(), 4 + 2, "{svg}");
}

fn score_groups() -> Vec<PointGroup> {
    vec![
        PointGroup {
            label: "low scores".to_string(),
            // x from 11 on, so that no x tick reads 1 or 10.
            points: vec![(11.0, 1.0), (12.0, 10.0)],
        },
        PointGroup {
            label: "high scores".to_string(),
            points: vec![(13.0, 1000.0), (14.0, 10000.0)],
        },
    ]
}

const LOG_AXES: Axes = Axes {
    x: "shape rank",
    y: "score",
    log_y: true,
    legend: Corner::LowerRight,
};

#[test]
fn level_charts_draw_their_levels_on_a_logarithmic_axis() {
    let levels = [Level {
        label: "threshold 100".to_string(),
        value: 100.0,
    }];
    let path = temporary("plot_levels.svg");
    plot_points_with_levels(&score_groups(), &levels, LOG_AXES, "scores", &path).expect("plots");
    let svg = fs::read_to_string(&path).expect("the SVG exists");
    for text in [
        "low scores",
        "high scores",
        "threshold 100",
        "shape rank",
        "score",
    ] {
        assert!(svg.contains(text), "{text} missing from the SVG");
    }
    // Equal steps of the y ticks are equal factors: a linear axis over [1, 10⁴] would label
    // neither 1 nor 10 (its ticks are multiples of 1000), the logarithmic one labels both.
    let texts: Vec<&str> = svg
        .split("</text>")
        .filter_map(|chunk| chunk.rsplit_once('>').map(|(_, text)| text.trim()))
        .collect();
    for tick in ["1", "10", "100", "1000"] {
        assert!(texts.contains(&tick), "tick {tick} missing from {texts:?}");
    }
    assert_eq!(svg.matches("<circle").count(), 4 + 2, "{svg}");
}

#[test]
fn a_logarithmic_axis_rejects_values_it_cannot_show() {
    let path = temporary("never-written-levels.svg");
    let mut groups = score_groups();
    groups[1].points[1].1 = 0.0;
    match plot_points_with_levels(&groups, &[], LOG_AXES, "t", &path) {
        Err(PlotError::NonPositive {
            label,
            index,
            value,
        }) => {
            assert_eq!((label.as_str(), index, value), ("high scores", 1, 0.0))
        }
        other => panic!("{other:?}"),
    }
    let negative_level = [Level {
        label: "below zero".to_string(),
        value: -1.0,
    }];
    let error = plot_points_with_levels(&score_groups(), &negative_level, LOG_AXES, "t", &path)
        .expect_err("a negative level");
    assert!(error.to_string().contains("below zero"), "{error}");
    assert!(!path.exists());
    // The same data on a linear axis are fine.
    let linear = Axes {
        log_y: false,
        ..LOG_AXES
    };
    let path = temporary("plot_levels_linear.svg");
    plot_points_with_levels(&groups, &negative_level, linear, "t", &path).expect("plots");
}

#[test]
fn bad_data_and_file_types_are_rejected() {
    let path = temporary("plot_spectra.jpg");
    let error = plot_spectra(&two_series(), "t", &path).expect_err("no JPEG");
    assert!(
        matches!(error, PlotError::UnsupportedFormat { .. }),
        "{error}"
    );
    assert!(error.to_string().contains("plot_spectra.jpg"), "{error}");
    assert!(!path.exists());

    let mut series = two_series();
    series[1].values[2] = f64::INFINITY;
    let error = plot_spectra(&series, "t", &temporary("x.svg")).expect_err("infinite");
    assert!(error.to_string().contains("beta mesh"), "{error}");

    let unwritable = temporary("no-such-directory").join("chart.svg");
    let error = plot_spectra(&two_series(), "t", &unwritable).expect_err("I/O");
    assert!(matches!(error, PlotError::Io { .. }), "{error}");
    assert!(error.to_string().contains("no-such-directory"), "{error}");
}

/// An icosphere of level 1 (42 vertices), scaled by `scale`, as an OBJ file.
fn sphere_file(name: &str, scale: f64) -> PathBuf {
    let path = temporary(name);
    let mesh = icosphere(1).scaled(scale).expect("a valid scale");
    write_obj(&mesh, &path).expect("the temporary directory is writable");
    path
}

#[test]
fn the_command_draws_one_line_per_mesh_or_operator() {
    let small = sphere_file("plot_sphere_small.obj", 1.0);
    let large = sphere_file("plot_sphere_large.obj", 2.0);
    let (small, large) = (text(&small), text(&large));
    let out = temporary("plot_cli_meshes.svg");
    let out = text(&out);
    let meshes = dirac(&[
        "plot", "spectra", small, large, "-k", "4", "--quiet", "--out", out,
    ]);
    assert!(meshes.status.success(), "{}", stderr(&meshes));
    let svg = fs::read_to_string(out).expect("the SVG exists");
    assert!(svg.contains("plot_sphere_small.obj") && svg.contains("plot_sphere_large.obj"));
    assert!(
        svg.contains("relative-dirac"),
        "the title names the operator"
    );

    let out = temporary("plot_cli_operators.png");
    let operators = dirac(&[
        "plot",
        "spectra",
        small,
        "--operators",
        "laplace,family:0.5",
        "-k",
        "4",
        "--quiet",
        "--out",
        text(&out),
    ]);
    assert!(operators.status.success(), "{}", stderr(&operators));
    assert_eq!(Picture::read(&out).width, 900);
}

#[test]
fn the_command_reports_bad_operators_and_files() {
    let mesh = sphere_file("plot_sphere_errors.obj", 1.0);
    let base = [
        "plot",
        "spectra",
        text(&mesh),
        "-k",
        "3",
        "--quiet",
        "--out",
    ];
    let gif = temporary("plot_cli.gif");
    assert_usage_errors(
        &base,
        &[
            (
                &["x.svg", "--operators", "dirac"],
                "unknown operator \"dirac\"",
            ),
            (
                &["x.svg", "--operators", "laplace", "--operator", "squared"],
                "--operator",
            ),
            (&["x.svg", "--operators", "laplace,family"], "family:T"),
            (&["x.svg", "--operators", "family:1.5"], "outside [0, 1]"),
            (&[text(&gif)], "plot_cli.gif"),
        ],
    );

    let help = dirac(&["plot", "spectra", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(
        help.contains("Examples:") && help.contains("--operators"),
        "{help}"
    );
}
