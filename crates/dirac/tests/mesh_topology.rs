//! Topology reports (boundary loops, components, Euler characteristic, genus) against known
//! truth: closed-form counts of generated meshes, the built-in `spot`, and the counts in the
//! table of `../shared/meshes/README.md` when that directory is present.

use std::path::PathBuf;

use dirac::generators::{Torus, cylinder, grid, icosphere, subdivided_cube};
use dirac::io::read_mesh;
use dirac::{TriMesh, default_mesh};

#[test]
fn icosphere_is_a_closed_sphere() {
    let t = icosphere(2).topology();
    assert_eq!((t.vertices, t.edges, t.faces), (162, 480, 320));
    assert_eq!(t.euler_characteristic, 2);
    assert_eq!(t.genus(), 0);
    assert!(t.is_closed());
    assert_eq!(t.components.len(), 1);
}

#[test]
fn torus_has_genus_one() {
    let t = Torus::new(3.0, 1.0, 24, 12).mesh().unwrap().topology();
    assert_eq!((t.vertices, t.edges, t.faces), (288, 864, 576));
    assert_eq!(t.euler_characteristic, 0);
    assert_eq!(t.genus(), 1);
    assert!(t.is_closed());
}

#[test]
fn cylinder_has_two_boundary_loops_around_its_rings() {
    let (n, rings) = (24, 10);
    let t = cylinder(n, rings, 3.0).unwrap().topology();
    assert_eq!(t.euler_characteristic, 0);
    assert_eq!(t.genus(), 0);
    assert_eq!(t.boundary_loops.len(), 2);
    let mut loops: Vec<Vec<usize>> = t
        .boundary_loops
        .iter()
        .map(|l| {
            let mut l = l.clone();
            l.sort();
            l
        })
        .collect();
    loops.sort();
    // Bottom ring 0..n and top ring (rings−1)·n.. (documented vertex numbering).
    assert_eq!(loops[0], (0..n).collect::<Vec<_>>());
    assert_eq!(loops[1], ((rings - 1) * n..rings * n).collect::<Vec<_>>());
}

#[test]
fn subdivided_cube_is_a_closed_sphere() {
    let t = subdivided_cube(5).unwrap().topology();
    assert_eq!((t.vertices, t.faces), (6 * 25 + 2, 12 * 25));
    assert_eq!(t.edges, 18 * 25);
    assert_eq!(t.euler_characteristic, 2);
    assert_eq!(t.genus(), 0);
    assert!(t.is_closed());
}

#[test]
fn flat_grid_is_a_disk() {
    let t = grid(3, 2, 3.0, 2.0).unwrap().topology();
    assert_eq!(t.euler_characteristic, 1);
    assert_eq!(t.genus(), 0);
    assert_eq!(t.boundary_loops.len(), 1);
    assert_eq!(t.boundary_loops[0].len(), 2 * (3 + 2));
}

#[test]
fn a_removed_face_leaves_a_loop_traversed_against_it() {
    let sphere = icosphere(1);
    let mut faces = sphere.faces().to_vec();
    let [a, b, c] = faces.remove(7);
    let t = TriMesh::new(sphere.positions().to_vec(), faces)
        .unwrap()
        .topology();
    assert_eq!(t.euler_characteristic, 1);
    assert_eq!(t.genus(), 0);
    assert_eq!(t.boundary_loops.len(), 1);
    let l = &t.boundary_loops[0];
    let rotations = [vec![a, c, b], vec![c, b, a], vec![b, a, c]];
    assert!(
        rotations.contains(l),
        "loop {l:?} vs removed face {:?}",
        [a, b, c]
    );
}

#[test]
fn disjoint_components_are_counted_separately() {
    let sphere = icosphere(1);
    let torus = Torus::new(3.0, 1.0, 8, 6).mesh().unwrap();
    let n = sphere.vertex_count();
    let moved = torus.translated([10.0, 0.0, 0.0]).unwrap();
    let positions = [sphere.positions(), moved.positions()].concat();
    let faces = sphere
        .faces()
        .iter()
        .copied()
        .chain(torus.faces().iter().map(|f| f.map(|v| v + n)))
        .collect();
    let t = TriMesh::new(positions, faces).unwrap().topology();
    assert_eq!(t.components.len(), 2);
    assert_eq!(t.euler_characteristic, 2);
    assert_eq!(t.genus(), 1);
    assert_eq!(
        [t.components[0].genus, t.components[1].genus],
        [0, 1],
        "components in order of their first face"
    );
    assert_eq!(t.components[1].vertices, 48);
}

#[test]
fn spot_is_the_default_mesh() {
    let spot = default_mesh();
    let t = spot.topology();
    assert_eq!((t.vertices, t.faces), (2930, 5856));
    assert!(t.is_closed());
    assert_eq!(t.genus(), 0);
    assert_eq!(t.components.len(), 1);
}

/// One row of the table in `../shared/meshes/README.md`.
struct Expected {
    file: &'static str,
    vertices: usize,
    faces: usize,
    boundary_edges: &'static [usize],
    genus: usize,
}

#[test]
fn shared_meshes_match_the_readme_table() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes");
    if !dir.is_dir() {
        println!("skipped: {} is not present", dir.display());
        return;
    }
    let table = [
        Expected {
            file: "decimated-knight.off",
            vertices: 502,
            faces: 1000,
            boundary_edges: &[],
            genus: 0,
        },
        Expected {
            file: "bumpy-cube.off",
            vertices: 1250,
            faces: 2496,
            boundary_edges: &[],
            genus: 0,
        },
        Expected {
            file: "spot.obj",
            vertices: 2930,
            faces: 5856,
            boundary_edges: &[],
            genus: 0,
        },
        Expected {
            file: "fertility.off",
            vertices: 4494,
            faces: 9000,
            boundary_edges: &[],
            genus: 4,
        },
        Expected {
            file: "fandisk.off",
            vertices: 7229,
            faces: 14454,
            boundary_edges: &[],
            genus: 0,
        },
        Expected {
            file: "rocker-arm.obj",
            vertices: 10044,
            faces: 20088,
            boundary_edges: &[],
            genus: 1,
        },
        Expected {
            file: "camelhead.off",
            vertices: 11381,
            faces: 22704,
            boundary_edges: &[56],
            genus: 0,
        },
        Expected {
            file: "armadillo.obj",
            vertices: 43243,
            faces: 86482,
            boundary_edges: &[],
            genus: 0,
        },
    ];
    for e in table {
        let mesh = read_mesh(dir.join(e.file)).unwrap_or_else(|err| panic!("{err}"));
        let t = mesh.topology();
        assert_eq!((t.vertices, t.faces), (e.vertices, e.faces), "{}", e.file);
        let loops: Vec<usize> = t.boundary_loops.iter().map(Vec::len).collect();
        assert_eq!(loops, e.boundary_edges, "{}", e.file);
        assert_eq!(t.genus(), e.genus, "{}", e.file);
        assert_eq!(t.components.len(), 1, "{}", e.file);
    }
}
