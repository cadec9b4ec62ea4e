//! Test data for mesh repair: deliberately broken copies of every mesh in a directory, made
//! here rather than committed. For each `NAME.off|obj|ply` it writes `NAME.obj` (the clean
//! mesh) and one OBJ per defect:
//!
//! | file | defect | without repair |
//! |---|---|---|
//! | `NAME-soup.obj` | every face has its own three vertices (STL-style soup) | valid, but every face is a component of its own: the spectrum is that of separate triangles |
//! | `NAME-hole.obj` | the faces around vertex 0 removed | vertex 0 is unused |
//! | `NAME-fin.obj` | a third face on the first face's first edge | non-manifold edge |
//! | `NAME-flipped.obj` | every 50th face reversed | inconsistent orientation |
//! | `NAME-stray.obj` | a small tetrahedron beside the mesh, unconnected | valid: a second component (`--component largest` drops it) |
//! | `NAME-degenerate.obj` | a zero-area sliver on an edge, an unused vertex | unused vertex, zero-area face, non-manifold edge |
//!
//! `cargo run --release -p experiments --example broken_meshes -- IN_DIR OUT_DIR`
//! (e.g. `IN_DIR = $MESHES/psb`), then `dirac batch OUT_DIR --repair --out spectra/`
//! (docs/USER_GUIDE.md, "Repairing meshes").

use std::fs::{self, File};
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use dirac::TriMesh;
use dirac::geometry::{bounding_box, norm, sub};
use dirac::io::{Format, RawMesh, read_mesh};

/// A defect: the clean mesh to a broken copy.
type Break = fn(&TriMesh) -> RawMesh;

/// The defects and their file-name suffixes.
const DEFECTS: [(&str, Break); 6] = [
    ("soup", soup),
    ("hole", hole),
    ("fin", fin),
    ("flipped", flipped),
    ("stray", stray),
    ("degenerate", degenerate),
];

fn raw(mesh: &TriMesh) -> RawMesh {
    RawMesh {
        positions: mesh.positions().to_vec(),
        faces: mesh.faces().to_vec(),
    }
}

fn soup(mesh: &TriMesh) -> RawMesh {
    let mut broken = RawMesh::default();
    for face in mesh.faces() {
        let first = broken.positions.len();
        broken.positions.extend(face.map(|v| mesh.positions()[v]));
        broken.faces.push([first, first + 1, first + 2]);
    }
    broken
}

fn hole(mesh: &TriMesh) -> RawMesh {
    let mut broken = raw(mesh);
    broken.faces.retain(|face| !face.contains(&0));
    broken
}

/// The bounding box of the mesh.
fn bounds(mesh: &TriMesh) -> ([f64; 3], [f64; 3]) {
    bounding_box(mesh.positions().iter().copied()).unwrap_or_default()
}

/// The length of the bounding box's diagonal.
fn diagonal(mesh: &TriMesh) -> f64 {
    let (low, high) = bounds(mesh);
    norm(sub(high, low))
}

fn fin(mesh: &TriMesh) -> RawMesh {
    let mut broken = raw(mesh);
    let [a, b, c] = mesh.faces()[0];
    let [pa, pb, pc] = [a, b, c].map(|v| mesh.positions()[v]);
    // The apex mirrors c across the edge's midpoint and lifts it off the surface.
    let lift = 0.05 * diagonal(mesh);
    let apex = [0, 1, 2].map(|i| pa[i] + pb[i] - pc[i] + if i == 2 { lift } else { 0.0 });
    broken.positions.push(apex);
    broken.faces.push([b, a, broken.positions.len() - 1]);
    broken
}

fn flipped(mesh: &TriMesh) -> RawMesh {
    let mut broken = raw(mesh);
    for face in broken.faces.iter_mut().step_by(50) {
        face.swap(1, 2);
    }
    broken
}

fn stray(mesh: &TriMesh) -> RawMesh {
    let mut broken = raw(mesh);
    let size = 0.05 * diagonal(mesh);
    let (_, corner) = bounds(mesh);
    let base = [0, 1, 2].map(|i| corner[i] + size);
    let first = broken.positions.len();
    broken.positions.extend([
        base,
        [base[0] + size, base[1], base[2]],
        [base[0], base[1] + size, base[2]],
        [base[0], base[1], base[2] + size],
    ]);
    for face in [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
        broken.faces.push(face.map(|v| first + v));
    }
    broken
}

fn degenerate(mesh: &TriMesh) -> RawMesh {
    let mut broken = raw(mesh);
    let [a, b, _] = mesh.faces()[0];
    let (pa, pb) = (mesh.positions()[a], mesh.positions()[b]);
    broken
        .positions
        .push([0, 1, 2].map(|i| 0.5 * (pa[i] + pb[i])));
    broken.faces.push([a, b, broken.positions.len() - 1]);
    broken.positions.push([0.0; 3]); // referenced by no face
    broken
}

fn write(raw: &RawMesh, path: &Path) -> Result<(), String> {
    let file = File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    raw.write_obj_to(&mut BufWriter::new(file))
        .map_err(|e| format!("{}: {e}", path.display()))
}

fn run(input: &Path, output: &Path) -> Result<usize, String> {
    fs::create_dir_all(output).map_err(|e| format!("{}: {e}", output.display()))?;
    let mut meshes: Vec<PathBuf> = fs::read_dir(input)
        .map_err(|e| format!("{}: {e}", input.display()))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| Format::from_path(path).is_some())
        .collect();
    meshes.sort();
    for path in &meshes {
        let mesh = read_mesh(path).map_err(|e| e.to_string())?;
        let stem = path.file_stem().unwrap_or_default().to_string_lossy();
        write(&raw(&mesh), &output.join(format!("{stem}.obj")))?;
        for (defect, make) in DEFECTS {
            write(&make(&mesh), &output.join(format!("{stem}-{defect}.obj")))?;
        }
    }
    Ok(meshes.len())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        eprintln!("usage: broken_meshes IN_DIR OUT_DIR");
        return ExitCode::from(2);
    };
    match run(Path::new(input), Path::new(output)) {
        Ok(count) => {
            println!(
                "{output}: {count} clean meshes and {} broken copies",
                count * DEFECTS.len()
            );
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}
