//! Fuzz target: a small mesh with arbitrary geometry (perturbed icosphere or grid, scaled from
//! tiny to huge), up to three fields with arbitrary labels and values (NaN, ±∞, huge, tiny,
//! constant, wrong length), and arbitrary picture options (sizes around and beyond the limits,
//! columns, supersampling, views built directly or parsed from text, both projections) →
//! `dirac_cli::render::render_png`. The outcome must be `Ok` or a typed `RenderError` that
//! matches the input, never a panic: this is the path of `dirac render`.

#![no_main]

use std::path::Path;
use std::str::FromStr;

use dirac::TriMesh;
use dirac::generators::{grid, icosphere};
use dirac_cli::render::{
    Field, MAX_SIDE, MIN_PANEL, Projection, RenderError, RenderOptions, View, render_png,
};
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;

/// A real number: mostly moderate, sometimes tiny, huge, zero, ±∞, NaN or arbitrary bits.
fn real(u: &mut Unstructured) -> Result<f64> {
    Ok(match u.int_in_range(0..=15u8)? {
        0 => f64::from_bits(u.arbitrary()?),
        1 => f64::from(u.arbitrary::<i16>()?) * 1e-300,
        2 => f64::from(u.arbitrary::<i16>()?) * 1e300,
        3 => 0.0,
        4 => [
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MAX,
            -f64::MAX,
        ][u.choose_index(5)?],
        _ => f64::from(u.arbitrary::<i16>()?) / 256.0,
    })
}

/// A small valid mesh: icosphere or grid, vertices moved by arbitrary amounts, then scaled.
fn mesh(u: &mut Unstructured) -> Result<Option<TriMesh>> {
    let base = if u.arbitrary()? {
        icosphere(0)
    } else {
        match grid(u.int_in_range(1..=4)?, u.int_in_range(1..=4)?, 1.0, 1.0) {
            Ok(mesh) => mesh,
            Err(_) => return Ok(None),
        }
    };
    let mut positions = base.positions().to_vec();
    let perturbation = real(u)?;
    for p in &mut positions {
        for c in p {
            if u.ratio(1, 4)? {
                *c += perturbation * f64::from(u.arbitrary::<i8>()?);
            }
        }
    }
    // Whole meshes far from unit size: the camera and the framing must cope.
    let scale = match u.int_in_range(0..=7u8)? {
        // Validation rejects meshes much beyond 10^±77 (cotangents over- or underflow).
        0 => 10f64.powi(u.int_in_range(-90..=90)?),
        1 => real(u)?,
        _ => 1.0,
    };
    for c in positions.iter_mut().flatten() {
        *c *= scale;
    }
    Ok(TriMesh::new(positions, base.faces().to_vec()).ok())
}

/// Characters that text layout tends to trip over.
const AWKWARD: &[&str] = &[
    "",
    " ",
    "\n",
    "\r\n",
    "\t",
    "\0",
    "\u{301}",
    "\u{200b}",
    "\u{202e}",
    "\u{fe0f}",
    "\u{ffff}",
    "\u{10ffff}",
    "😀",
    "👩‍👩‍👧",
    "λ",
    "ﷺ",
    "𒐫",
    "ʕ•ᴥ•ʔ",
    "中文",
    "ـــ",
    "W",
];

/// Most characters of a repeated title.
const MAX_LABEL: usize = 400;

/// A title: arbitrary text, awkward characters, sometimes repeated into a long one.
fn label(u: &mut Unstructured) -> Result<String> {
    let mut text = String::new();
    for _ in 0..u.int_in_range(0..=4)? {
        if u.arbitrary()? {
            text.push_str(u.arbitrary::<&str>()?);
        } else {
            text.push_str(AWKWARD[u.choose_index(AWKWARD.len())?]);
        }
    }
    // Long enough to be shrunk to fit many times over; every glyph is drawn, so not longer.
    if u.ratio(1, 16)? && !text.is_empty() {
        let most = (MAX_LABEL / text.chars().count()).max(1);
        text = text.repeat(u.int_in_range(1..=most)?);
    }
    Ok(text)
}

fn field(u: &mut Unstructured, vertices: usize) -> Result<Field> {
    let length = match u.int_in_range(0..=15u8)? {
        0 => 0,
        1 => vertices - 1,
        2 => vertices + 1,
        _ => vertices,
    };
    let values = if u.ratio(1, 4)? {
        vec![real(u)?; length]
    } else {
        // Mostly moderate values so that the picture is drawn; `real` adds the rest.
        (0..length)
            .map(|_| {
                Ok(if u.ratio(1, 8)? {
                    real(u)?
                } else {
                    f64::from(u.arbitrary::<i8>()?)
                })
            })
            .collect::<Result<_>>()?
    };
    Ok(Field {
        label: label(u)?,
        values,
    })
}

/// An image side: mostly small, sometimes a few hundred pixels, rarely too large or exactly
/// at the limit.
fn side(u: &mut Unstructured) -> Result<u32> {
    Ok(match u.int_in_range(0..=255u8)? {
        0..=3 => u.int_in_range(MAX_SIDE + 1..=u32::MAX)?,
        4 => MAX_SIDE,
        5..=8 => u.int_in_range(97..=300)?,
        _ => u.int_in_range(0..=96)?,
    })
}

/// Most pixels of a picture the target draws: a few hundred by [`MIN_PANEL`] to 96. Every
/// execution encodes a PNG (about 1 ms for a small one, 50 ms at `MAX_SIDE × MIN_PANEL`) and
/// the CI fuzzes each target for only 20 seconds, so a side of `MAX_SIDE` always comes with a
/// side too small to draw: the limit itself is still checked through the error returned.
const MAX_PIXELS: u32 = 300 * 96;

fn view(u: &mut Unstructured) -> Result<View> {
    Ok(match u.int_in_range(0..=3u8)? {
        0 => View::default(),
        1 => View::new(real(u)?, real(u)?),
        2 => View::from_str(u.arbitrary::<&str>()?).unwrap_or_default(),
        // Printed and parsed back, as a view typed on the command line.
        _ => {
            let text = format!("{},{}", real(u)?, real(u)?);
            match View::from_str(&text) {
                Ok(view) => {
                    assert!(view.azimuth_degrees.is_finite() && view.elevation_degrees.is_finite());
                    view
                }
                Err(_) => View::default(),
            }
        }
    })
}

fn options(u: &mut Unstructured) -> Result<RenderOptions> {
    let (mut width, mut height) = (side(u)?, side(u)?);
    if width <= MAX_SIDE && height <= MAX_SIDE && width * height > MAX_PIXELS {
        if width > height {
            height = MAX_PIXELS / width;
        } else {
            width = MAX_PIXELS / height;
        }
    }
    let supersampling = match u.int_in_range(0..=15u8)? {
        0..=1 => 0,
        2 => 2,
        3 => 3,
        _ => 1,
    };
    Ok(RenderOptions {
        width,
        height,
        view: view(u)?,
        columns: match u.int_in_range(0..=7u8)? {
            0..=3 => None,
            4 => Some(u.arbitrary()?),
            _ => Some(u.int_in_range(0..=4)?),
        },
        projection: if u.arbitrary()? {
            Projection::Perspective
        } else {
            Projection::Orthographic
        },
        // Every factor multiplies the work by its square: supersample small pictures only.
        supersampling: if u64::from(width) * u64::from(height) > 64 * 64 {
            supersampling.min(1)
        } else {
            supersampling
        },
    })
}

fn run(u: &mut Unstructured) -> Result<()> {
    let Some(mesh) = mesh(u)? else {
        return Ok(());
    };
    let vertices = mesh.vertex_count();
    let fields = (0..u.int_in_range(0..=3)?)
        .map(|_| field(u, vertices))
        .collect::<Result<Vec<_>>>()?;
    let options = options(u)?;
    let result = render_png(&mesh, &fields, &options, Path::new("/dev/null"));

    // The error must be about something actually wrong with the input.
    let (width, height) = (options.width, options.height);
    let panels_fit = |columns: usize| {
        let rows = fields.len().div_ceil(columns);
        width / columns as u32 >= MIN_PANEL && height / rows as u32 >= MIN_PANEL
    };
    match result {
        Ok(()) => {
            assert!(width.min(height) >= MIN_PANEL && width.max(height) <= MAX_SIDE);
            assert!(!fields.is_empty() && options.supersampling > 0);
            assert!(fields.iter().all(|f| f.values.len() == vertices));
            assert!(fields.iter().flat_map(|f| &f.values).all(|v| v.is_finite()));
            let view = options.view;
            assert!(view.azimuth_degrees.is_finite() && view.elevation_degrees.is_finite());
        }
        Err(RenderError::ZeroSize { .. }) => assert!(width == 0 || height == 0),
        Err(RenderError::TooLarge { .. }) => assert!(width.max(height) > MAX_SIDE),
        Err(RenderError::ZeroSupersampling) => assert_eq!(options.supersampling, 0),
        Err(RenderError::NoFields) => assert!(fields.is_empty()),
        Err(RenderError::NonFiniteView { view }) => {
            assert!(!(view.azimuth_degrees.is_finite() && view.elevation_degrees.is_finite()));
        }
        Err(RenderError::ZeroColumns) => assert_eq!(options.columns, Some(0)),
        Err(RenderError::FieldLength { values, .. }) => assert_ne!(values, vertices),
        Err(RenderError::NonFinite { value, .. }) => assert!(!value.is_finite()),
        Err(RenderError::TooSmall { columns, .. }) => assert!(!panels_fit(columns)),
        // Text layout and /dev/null must work for any input.
        Err(e) => panic!("unexpected error: {e}"),
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});
