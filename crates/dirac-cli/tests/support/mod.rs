//! What the end-to-end tests share: temporary files, test meshes written by hand, running the
//! binary and checking its exit codes, the library's spectra to compare with, and decoding
//! PNGs.
//!
//! Every test binary compiles this module and uses a part of it, hence `dead_code` is allowed.
#![allow(dead_code)]

use std::fs::{self, File};
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use dirac::TriMesh;
use dirac::generators::icosphere;
use dirac::spectrum::{Operator, Spectrum, SpectrumOptions, spectrum};
use qscalar::random::SplitMix64;

/// A file name in the test's temporary directory.
pub fn temporary(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// A fresh, empty directory in the test's temporary directory.
pub fn scratch(name: &str) -> PathBuf {
    let dir = temporary(name);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("the temporary directory is writable");
    dir
}

/// `path` as a command-line argument.
pub fn text(path: &Path) -> &str {
    path.to_str().expect("UTF-8 path")
}

/// Runs `dirac` with `args`.
pub fn dirac(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dirac"))
        .args(args)
        .output()
        .expect("the dirac binary runs")
}

/// The standard error of a run, as text.
pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Checks that a run succeeded, showing its exit code and stderr otherwise.
pub fn assert_success(output: &Output) {
    assert!(
        output.status.success(),
        "exit {:?}, stderr: {}",
        output.status.code(),
        stderr(output)
    );
}

/// Runs `dirac` with `base` followed by each case's arguments and checks that each is a usage
/// error (exit code 2) whose message contains the case's text.
pub fn assert_usage_errors(base: &[&str], cases: &[(&[&str], &str)]) {
    for (extra, expected) in cases {
        let output = dirac(&[base, extra].concat());
        let message = stderr(&output);
        assert_eq!(output.status.code(), Some(2), "{extra:?}: {message}");
        assert!(message.contains(expected), "{extra:?}: {message}");
    }
}

/// The level-`level` icosphere with every vertex moved radially by a seeded random factor in
/// `1 ± amplitude`: no symmetry, so no degenerate eigenvalues.
pub fn bumpy_sphere(level: u32, seed: u64, amplitude: f64) -> TriMesh {
    let mut rng = SplitMix64::new(seed);
    icosphere(level)
        .map_positions(|p| p.map(|c| c * (1.0 + rng.uniform(-amplitude, amplitude))))
        .expect("a mildly perturbed sphere is valid")
}

/// Writes `mesh` as an OFF file at `path`, by hand (full precision, and so that the reader is
/// exercised independently of any writer); returns `path`.
pub fn write_off(mesh: &TriMesh, path: PathBuf) -> PathBuf {
    let mut text = format!("OFF\n{} {} 0\n", mesh.vertex_count(), mesh.face_count());
    for [x, y, z] in mesh.positions() {
        text += &format!("{x} {y} {z}\n");
    }
    for [i, j, k] in mesh.faces() {
        text += &format!("3 {i} {j} {k}\n");
    }
    fs::write(&path, text).expect("the temporary directory is writable");
    path
}

/// The library's `k` eigenpairs of `operator` on `mesh` with the default options, to compare
/// the binary's output with.
pub fn library(mesh: &TriMesh, operator: Operator, k: usize) -> Spectrum {
    spectrum(mesh, &SpectrumOptions::new(operator, k)).expect("the library solves it")
}

/// A decoded 8-bit RGB picture.
pub struct Picture {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Rows top to bottom, three bytes per pixel.
    pub rgb: Vec<u8>,
}

impl Picture {
    /// Decodes the PNG at `path`, which must be 8-bit RGB (what `dirac` writes).
    pub fn read(path: &Path) -> Self {
        let file = File::open(path).expect("the PNG exists");
        let mut reader = png::Decoder::new(BufReader::new(file))
            .read_info()
            .expect("a PNG header");
        let mut rgb = vec![0; reader.output_buffer_size().expect("a sane size")];
        let info = reader.next_frame(&mut rgb).expect("PNG data");
        assert_eq!(info.color_type, png::ColorType::Rgb);
        assert_eq!(info.bit_depth, png::BitDepth::Eight);
        rgb.truncate(info.buffer_size());
        Self {
            width: info.width,
            height: info.height,
            rgb,
        }
    }

    /// Number of distinct colours.
    pub fn colours(&self) -> usize {
        let mut colours: Vec<&[u8]> = self.rgb.chunks(3).collect();
        colours.sort_unstable();
        colours.dedup();
        colours.len()
    }

    /// The pixel at column `x`, row `y`.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y * self.width + x) as usize;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Number of non-white pixels in columns `x0..x1`.
    pub fn ink(&self, x0: u32, x1: u32) -> usize {
        (0..self.height)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .filter(|&(x, y)| self.pixel(x, y) != [255, 255, 255])
            .count()
    }
}
