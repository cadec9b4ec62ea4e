//! Pictures of functions on meshes: `dirac_cli::render::render_png` and `dirac render` write
//! PNGs of the requested size with actual content; `dirac render --quantity hks|dks|wks` draws
//! the library's descriptors at the documented default time or energy (checked against a
//! picture of the library's values); bad input and bad combinations of options are rejected
//! with messages that name the field, the size, the mode, the option or the file.

mod support;

use std::fs;
use std::path::{Path, PathBuf};

use dirac::TriMesh;
use dirac::descriptors::{
    Modes, WaveSampling, ZERO_TOLERANCE, dirac_kernel_signature, heat_kernel_signature,
    wave_kernel_signature,
};
use dirac::generators::icosphere;
use dirac::io::{read_mesh, write_obj};
use dirac::spectrum::{Operator, Spectrum};
use dirac_cli::render::{Field, RenderError, RenderOptions, View, format_value, render_png};

use support::{
    Picture, assert_success, assert_usage_errors, bumpy_sphere, dirac, library, scratch, stderr,
    temporary, text, write_off,
};

/// The height (y coordinate) of every vertex.
fn height_field(mesh: &TriMesh) -> Field {
    Field {
        label: "height".to_string(),
        values: mesh.positions().iter().map(|p| p[1]).collect(),
    }
}

fn small(width: u32, height: u32) -> RenderOptions {
    RenderOptions {
        width,
        height,
        supersampling: 2,
        ..RenderOptions::default()
    }
}

#[test]
fn one_field_fills_the_requested_size_with_a_shaded_mesh() {
    let mesh = icosphere(2);
    let path = temporary("render_one.png");
    render_png(&mesh, &[height_field(&mesh)], &small(160, 120), &path).expect("renders");
    let picture = Picture::read(&path);
    assert_eq!((picture.width, picture.height), (160, 120));
    // Background in the corners; many colours (gradient, shading, anti-aliasing, text).
    assert_eq!(picture.pixel(0, 0), [255, 255, 255]);
    assert_eq!(picture.pixel(159, 119), [255, 255, 255]);
    assert!(picture.colours() > 200, "{} colours", picture.colours());
    // The centre shows the sphere, in viridis (blue-green, not grey or white).
    let [r, g, b] = picture.pixel(80, 55);
    assert!(g > r && b > r, "centre pixel {:?}", [r, g, b]);
}

#[test]
fn several_fields_make_a_grid_and_the_view_changes_the_picture() {
    let mesh = icosphere(2);
    let fields: Vec<Field> = (0..3)
        .map(|axis| Field {
            label: format!("coordinate {axis}"),
            values: mesh.positions().iter().map(|p| p[axis]).collect(),
        })
        .collect();
    let path = temporary("render_grid.png");
    render_png(&mesh, &fields, &small(300, 110), &path).expect("renders");
    let grid = Picture::read(&path);
    assert_eq!((grid.width, grid.height), (300, 110));
    // Three panels side by side, each with ink; the gaps between them stay white.
    for panel in 0..3 {
        assert!(
            grid.ink(panel * 100 + 20, panel * 100 + 80) > 500,
            "panel {panel}"
        );
        assert_eq!(
            grid.ink(panel * 100, panel * 100 + 1),
            0,
            "left edge of panel {panel}"
        );
    }

    let turned = RenderOptions {
        view: View::new(90.0, 0.0),
        ..small(300, 110)
    };
    let other = temporary("render_grid_turned.png");
    render_png(&mesh, &fields, &turned, &other).expect("renders");
    assert_ne!(Picture::read(&other).rgb, grid.rgb);
}

#[test]
fn bad_input_is_rejected_with_a_message_naming_it() {
    let mesh = icosphere(1);
    let path = temporary("render_never_written.png");
    let short = Field {
        label: "too short".to_string(),
        values: vec![0.0; 3],
    };
    let error = render_png(&mesh, &[short], &small(100, 100), &path).expect_err("short field");
    assert!(matches!(
        error,
        RenderError::FieldLength {
            values: 3,
            vertices: 42,
            ..
        }
    ));
    assert!(error.to_string().contains("too short"), "{error}");

    let mut nan = height_field(&mesh);
    nan.values[7] = f64::NAN;
    let error = render_png(&mesh, &[nan], &small(100, 100), &path).expect_err("NaN");
    assert!(
        matches!(error, RenderError::NonFinite { vertex: 7, .. }),
        "{error}"
    );

    let field = height_field(&mesh);
    let error =
        render_png(&mesh, std::slice::from_ref(&field), &small(0, 100), &path).expect_err("zero");
    assert!(
        matches!(
            error,
            RenderError::ZeroSize {
                width: 0,
                height: 100
            }
        ),
        "{error}"
    );
    let error = render_png(
        &mesh,
        &[field.clone(), field.clone()],
        &small(60, 40),
        &path,
    )
    .expect_err("panels too small");
    assert!(matches!(error, RenderError::TooSmall { .. }), "{error}");
    assert!(!path.exists());

    let unwritable = temporary("no-such-directory").join("picture.png");
    let error = render_png(&mesh, &[field], &small(100, 100), &unwritable).expect_err("I/O");
    assert!(matches!(error, RenderError::Io { .. }), "{error}");
    assert!(error.to_string().contains("no-such-directory"), "{error}");
}

#[test]
fn a_non_finite_view_is_rejected_naming_it() {
    // Seen while writing the `render` fuzz target: NaN or ∞ angles projected every vertex to
    // NaN, so the picture was written without the mesh.
    let mesh = icosphere(1);
    let path = temporary("render_non_finite_view.png");
    let _ = fs::remove_file(&path);
    for view in [
        View::new(f64::NAN, 20.0),
        View::new(30.0, f64::INFINITY),
        View::new(f64::NEG_INFINITY, f64::NAN),
    ] {
        let options = RenderOptions {
            view,
            ..small(100, 100)
        };
        let error = render_png(&mesh, &[height_field(&mesh)], &options, &path)
            .expect_err("no direction to look from");
        assert!(
            matches!(error, RenderError::NonFiniteView { .. }),
            "{error}"
        );
        assert!(error.to_string().contains(&view.to_string()), "{error}");
    }
    assert!(!path.exists());
}

#[test]
fn values_spanning_more_than_the_largest_float_are_shaded_like_moderate_ones() {
    // Seen while writing the `render` fuzz target: with values near ±f64::MAX the range
    // overflowed to ∞ and every positive value was drawn as NaN, i.e. at the low end of the
    // colour map.
    let mesh = icosphere(2);
    let moderate = height_field(&mesh);
    let top = moderate.values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let extreme = Field {
        label: moderate.label.clone(),
        values: moderate.values.iter().map(|v| v / top * f64::MAX).collect(),
    };
    let pictures = [(moderate, "moderate"), (extreme, "extreme")].map(|(field, name)| {
        let path = temporary(&format!("render_range_{name}.png"));
        render_png(&mesh, &[field], &small(160, 160), &path).expect("renders");
        Picture::read(&path)
    });
    // Same mesh, same colours; only the numbers under the colour bar (the bottom fifth)
    // differ.
    let rows = 3 * (pictures[0].width * pictures[0].height * 4 / 5) as usize;
    let worst = pictures[0].rgb[..rows]
        .iter()
        .zip(&pictures[1].rgb[..rows])
        .map(|(a, b)| a.abs_diff(*b))
        .max();
    assert!(worst <= Some(2), "channels differ by {worst:?}");
}

/// An icosphere of level 2 (162 vertices) as the OBJ file `name`: one per test, since tests
/// run in parallel and one rewriting a shared file while another's command reads it gave
/// that command an empty mesh.
fn sphere_file(name: &str) -> PathBuf {
    let path = temporary(name);
    write_obj(&icosphere(2), &path).expect("the temporary directory is writable");
    path
}

/// Runs `dirac render MESH --quiet --out OUT` with `extra` arguments, checks that it
/// succeeded and decodes the picture.
fn render_command(mesh: &str, out: &Path, extra: &[&str]) -> Picture {
    let _ = fs::remove_file(out);
    let output = dirac(&[&["render", mesh, "--quiet", "--out", text(out)], extra].concat());
    assert_success(&output);
    Picture::read(out)
}

#[test]
fn the_command_renders_one_mode_a_grid_and_the_potential() {
    let mesh = sphere_file("render_cli_icosphere2.obj");
    let cases: [(&str, &[&str], (u32, u32)); 3] = [
        (
            "render_cli_mode.png",
            &["--mode", "2", "--size", "150x130"],
            (150, 130),
        ),
        (
            "render_cli_grid.png",
            &[
                "--operator",
                "laplace",
                "--grid",
                "3",
                "--size",
                "330x120",
                "--view",
                "-30,10",
            ],
            (330, 120),
        ),
        (
            "render_cli_potential.png",
            &[
                "--quantity",
                "potential",
                "--well-radius",
                "0.5",
                "--size",
                "120x120",
            ],
            (120, 120),
        ),
    ];
    for (name, extra, size) in cases {
        let picture = render_command(text(&mesh), &temporary(name), extra);
        assert_eq!((picture.width, picture.height), size, "{name}");
        assert!(
            picture.colours() > 100,
            "{name}: {} colours",
            picture.colours()
        );
    }
}

/// The picture `render_png` makes of one field with the options `dirac render --size WxH`
/// uses by default.
fn library_picture(
    mesh: &TriMesh,
    field: Field,
    (width, height): (u32, u32),
    name: &str,
) -> Picture {
    let options = RenderOptions {
        width,
        height,
        ..RenderOptions::default()
    };
    let path = temporary(name);
    render_png(mesh, &[field], &options, &path).expect("renders");
    Picture::read(&path)
}

/// Checks that the command's picture is the library's up to rounding (every channel within
/// 2 levels), and that it has real content.
fn assert_alike(command: &Picture, library: &Picture, what: &str) {
    assert_eq!(
        (command.width, command.height),
        (library.width, library.height),
        "{what}"
    );
    assert!(
        command.colours() > 100,
        "{what}: {} colours",
        command.colours()
    );
    let worst = command
        .rgb
        .iter()
        .zip(&library.rgb)
        .map(|(a, b)| a.abs_diff(*b))
        .max();
    assert!(worst <= Some(2), "{what}: channels differ by {worst:?}");
}

/// Smallest and largest |λ| over the nonzero eigenvalues, as the descriptors' default
/// samplings define them.
fn nonzero_range(spectrum: &Spectrum) -> (f64, f64) {
    let largest = spectrum
        .eigenvalues
        .iter()
        .fold(0.0_f64, |m, l| m.max(l.abs()));
    spectrum
        .eigenvalues
        .iter()
        .map(|l| l.abs())
        .filter(|&l| l > ZERO_TOLERANCE * largest)
        .fold((f64::INFINITY, 0.0), |(lo, hi), l| (lo.min(l), hi.max(l)))
}

#[test]
fn descriptor_pictures_show_the_library_descriptors_at_the_documented_defaults() {
    let dir = scratch("render_descriptors");
    let file = write_off(&bumpy_sphere(2, 11, 0.1), dir.join("bumpy.off"));
    let mesh = read_mesh(&file).expect("the OFF file reads back");
    let file = text(&file);
    let size = (160, 140);
    let common = ["-k", "12", "--size", "160x140"];
    let dirac_spectrum = library(&mesh, Operator::RelativeDirac, 12);
    let dirac_modes = Modes::from_spectrum(&dirac_spectrum).expect("valid modes");

    // The command's picture against the library's field, drawn by `render_png`.
    let check = |what: &str, arguments: &[&str], field: Field| {
        let out = dir.join(format!("{what}.png"));
        let command = render_command(file, &out, &[&common[..], arguments].concat());
        let expected = library_picture(&mesh, field, size, &format!("render_{what}_library.png"));
        assert_alike(&command, &expected, what);
    };

    // DKS of D_N at the middle of the default times, 4 ln 10 / √(|λ|min |λ|max).
    let (low, high) = nonzero_range(&dirac_spectrum);
    let time = 4.0 * 10f64.ln() / (low * high).sqrt();
    let dks = dirac_kernel_signature(&dirac_modes, &[time]).expect("a valid time");
    let field = Field {
        label: format!("DKS  t = {}", format_value(time)),
        values: dks.column(0),
    };
    check("dks", &["--quantity", "dks"], field);

    // HKS of the Laplacian at a given time, whatever --operator says.
    let laplace = library(&mesh, Operator::Laplace, 12);
    let laplace_modes = Modes::from_spectrum(&laplace).expect("valid modes");
    let hks = heat_kernel_signature(&laplace_modes, &[0.5]).expect("a valid time");
    let field = Field {
        label: "HKS  t = 0.5".to_string(),
        values: hks.column(0),
    };
    let arguments = [
        "--quantity",
        "hks",
        "--time",
        "0.5",
        "--operator",
        "squared",
    ];
    check("hks", &arguments, field);

    // WKS of D_N at the middle of the default energies, (ln|λ|min + ln|λ|max) / 2, with the
    // default width σ = 7 (ln|λ|max − ln|λ|min) / 100.
    let energy = (low.ln() + high.ln()) / 2.0;
    let sampling = WaveSampling {
        energies: vec![energy],
        sigma: 7.0 * (high.ln() - low.ln()) / 100.0,
    };
    let wks = wave_kernel_signature(&dirac_modes, &sampling).expect("a valid sampling");
    let field = Field {
        label: format!("WKS  e = {}", format_value(energy)),
        values: wks.column(0),
    };
    check("wks", &["--quantity", "wks"], field);

    // --grid 3: three panels of default times, each with a shaded mesh, different pictures.
    let grid = render_command(
        file,
        &dir.join("dks-grid.png"),
        &[
            "--quantity",
            "dks",
            "-k",
            "12",
            "--grid",
            "3",
            "--size",
            "330x120",
        ],
    );
    assert_eq!((grid.width, grid.height), (330, 120));
    let panels: Vec<Vec<u8>> = (0..3)
        .map(|panel| {
            assert!(
                grid.ink(panel * 110 + 20, panel * 110 + 90) > 500,
                "panel {panel}"
            );
            (0..grid.height)
                .flat_map(|y| (panel * 110..(panel + 1) * 110).map(move |x| (x, y)))
                .flat_map(|(x, y)| grid.pixel(x, y))
                .collect()
        })
        .collect();
    assert!(panels[0] != panels[1] && panels[1] != panels[2]);
}

#[test]
fn the_command_reports_bad_modes_sizes_and_files() {
    let mesh = sphere_file("render_errors_icosphere2.obj");
    let mesh = text(&mesh);
    let out = temporary("render_cli_never.png");
    assert_usage_errors(
        &["render", mesh, "--quiet", "--out", text(&out)],
        &[
            (&["--mode", "162"], "--mode 162"),
            (&["--mode", "150", "--grid", "20"], "170 eigenpairs"),
            (&["--mode", "-1"], "-1"),
            (&["--size", "0x10"], "positive"),
            (&["--size", "big"], "WIDTHxHEIGHT"),
            (&["--quantity", "potential"], "--well-radius"),
            (
                &[
                    "--quantity",
                    "potential",
                    "--well-radius",
                    "0.5",
                    "--grid",
                    "2",
                ],
                "--grid does not apply",
            ),
            (&["--quantity", "dks", "--mode", "2"], "--mode applies only"),
            (
                &["--time", "1"],
                "--time applies only to --quantity hks or dks",
            ),
            (&["--quantity", "wks", "--time", "1"], "--time applies only"),
            (
                &["--quantity", "hks", "--energy", "1"],
                "--energy applies only",
            ),
            (&["--quantity", "dks", "--time", "0"], "not positive"),
            (
                &["--quantity", "dks", "--time", "1", "--grid", "2"],
                "does not combine",
            ),
        ],
    );
    assert!(!out.exists());

    let missing = dirac(&["render", "no-such-mesh.obj", "--out", text(&out)]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(
        stderr(&missing).contains("no-such-mesh.obj"),
        "{}",
        stderr(&missing)
    );

    // A descriptor the spectrum cannot give: k = 1 leaves one nonzero |λ|, no energy range.
    let output = dirac(&[
        "render",
        mesh,
        "--quiet",
        "--quantity",
        "wks",
        "-k",
        "1",
        "--out",
        text(&out),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("render_errors_icosphere2.obj")
            && stderr(&output).contains("two distinct"),
        "{}",
        stderr(&output)
    );

    let unwritable = temporary("no-such-directory").join("x.png");
    let output = dirac(&["render", mesh, "--quiet", "--out", text(&unwritable)]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("no-such-directory"),
        "{}",
        stderr(&output)
    );

    let help = dirac(&["render", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(
        help.contains("Examples:") && help.contains("--grid") && help.contains("--quantity dks"),
        "{help}"
    );
}

#[test]
fn a_reader_that_went_away_is_not_a_panic() {
    // `dirac render … | head -0`: the picture is written, the closing message has no reader.
    let out = support::scratch("render_closed_pipe").join("spot.png");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_dirac"))
        .args(["render", "-k", "4", "--out", support::text(&out)])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the dirac binary runs");
    drop(child.stdout.take());
    let output = child.wait_with_output().expect("the run ends");
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        support::stderr(&output)
    );
    assert!(out.is_file());
}
