//! Every `MeshError` variant is produced by a small hand-made input, and valid meshes survive
//! the transforms `translated`, `rotated`, `scaled` and `reverse_orientation`.

use dirac::generators::icosphere;
use dirac::{MeshError, TriMesh};
use proptest::prelude::*;
use qscalar::Quat;

/// Two triangles sharing the edge 0–1, counter-clockwise seen from +z.
fn square() -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    (
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
        ],
        vec![[0, 1, 2], [1, 0, 3]],
    )
}

#[test]
fn the_square_is_valid() {
    let (p, f) = square();
    assert!(TriMesh::new(p, f).is_ok());
}

#[test]
fn empty_meshes_are_rejected() {
    assert_eq!(
        TriMesh::new(vec![], vec![]),
        Err(MeshError::Empty {
            vertices: 0,
            faces: 0
        })
    );
    let (p, _) = square();
    assert_eq!(
        TriMesh::new(p, vec![]),
        Err(MeshError::Empty {
            vertices: 4,
            faces: 0
        })
    );
}

#[test]
fn out_of_range_index_names_face_and_vertex() {
    let (p, _) = square();
    assert_eq!(
        TriMesh::new(p, vec![[0, 1, 2], [1, 0, 7]]),
        Err(MeshError::IndexOutOfRange {
            face: 1,
            vertex: 7,
            vertex_count: 4
        })
    );
}

#[test]
fn repeated_index_names_face_and_vertex() {
    let (p, _) = square();
    assert_eq!(
        TriMesh::new(p.clone(), vec![[0, 1, 2], [1, 3, 3]]),
        Err(MeshError::RepeatedIndex { face: 1, vertex: 3 })
    );
    assert_eq!(
        TriMesh::new(p, vec![[2, 1, 2], [1, 0, 3]]),
        Err(MeshError::RepeatedIndex { face: 0, vertex: 2 })
    );
}

#[test]
fn unreferenced_vertex_is_an_error_or_removed_on_request() {
    let p = vec![
        [0.0, 0.0, 0.0],
        [9.0, 9.0, 9.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [f64::NAN, 0.0, 0.0],
    ];
    let f = vec![[0, 2, 3]];
    assert_eq!(
        TriMesh::new(p.clone(), f.clone()),
        Err(MeshError::UnreferencedVertex { vertex: 1 })
    );
    // Removal drops unused vertices, even non-finite ones, and reports the renumbering.
    let (mesh, old_to_new) = TriMesh::with_unreferenced_removed(p, f).unwrap();
    assert_eq!(
        mesh.positions(),
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
    assert_eq!(mesh.faces(), &[[0, 1, 2]]);
    assert_eq!(old_to_new, vec![Some(0), None, Some(1), Some(2), None]);
}

#[test]
fn non_finite_coordinates_name_the_vertex() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let (mut p, f) = square();
        p[2][1] = bad;
        assert_eq!(
            TriMesh::new(p, f),
            Err(MeshError::NonFiniteCoordinate { vertex: 2 })
        );
    }
}

#[test]
fn zero_area_faces_name_the_face() {
    let (mut p, f) = square();
    p[3] = [2.0, 0.0, 0.0]; // on the line through vertices 0 and 1
    assert_eq!(TriMesh::new(p, f), Err(MeshError::ZeroAreaFace { face: 1 }));
    // Finite coordinates whose cross product overflows.
    let (mut p, f) = square();
    p[2] = [1e300, 1e300, 0.0];
    assert_eq!(TriMesh::new(p, f), Err(MeshError::ZeroAreaFace { face: 0 }));
    // A positive but subnormal area, whose reciprocal (in every operator) overflows.
    let (p, f) = square();
    let tiny: Vec<[f64; 3]> = p.iter().map(|v| v.map(|c| c * 1e-160)).collect();
    let area: f64 = 0.5 * 1e-320;
    assert!(area > 0.0 && (1.0 / area).is_infinite());
    assert_eq!(
        TriMesh::new(tiny, f),
        Err(MeshError::ZeroAreaFace { face: 0 })
    );
}

#[test]
fn angles_with_infinite_cotangent_name_face_and_vertex() {
    // Area 1/2, but at vertex 0 the edges are 10²⁰⁰ long and 10⁻⁴⁰⁰ radians apart: the dot
    // product (the cotangent's numerator) overflows. Found by the `spectrum` fuzz target as a
    // panic in the cotangent Laplacian.
    let p = vec![[0.0, 0.0, 0.0], [1e200, 0.0, 0.0], [1e200, 1e-200, 0.0]];
    let f = vec![[0, 1, 2]];
    assert_eq!(
        TriMesh::new(p, f),
        Err(MeshError::DegenerateAngle { face: 0, vertex: 0 })
    );
}

#[test]
fn an_edge_in_three_faces_is_non_manifold() {
    let (mut p, mut f) = square();
    p.push([0.5, 0.0, 1.0]);
    f.push([0, 4, 1]);
    assert_eq!(
        TriMesh::new(p, f),
        Err(MeshError::NonManifoldEdge {
            edge: [0, 1],
            faces: vec![0, 1, 2]
        })
    );
}

#[test]
fn faces_traversing_an_edge_the_same_way_are_inconsistently_oriented() {
    let (p, _) = square();
    assert_eq!(
        TriMesh::new(p, vec![[0, 1, 2], [0, 1, 3]]),
        Err(MeshError::InconsistentOrientation {
            edge: [0, 1],
            faces: [0, 1]
        })
    );
}

#[test]
fn a_bowtie_vertex_is_non_manifold() {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [-1.0, -1.0, 0.0],
    ];
    assert_eq!(
        TriMesh::new(p, vec![[0, 1, 2], [0, 3, 4]]),
        Err(MeshError::NonManifoldVertex { vertex: 0, fans: 2 })
    );
}

#[test]
fn the_smallest_split_vertex_is_named_with_all_its_fans() {
    // Points on a helix: no three collinear, so every triangle has a shape.
    let p: Vec<[f64; 3]> = (0..15)
        .map(|v| [f64::cos(v as f64), f64::sin(v as f64), 0.3 * v as f64])
        .collect();
    // Vertex 9 joins two triangles (first in face order), vertex 2 three.
    let faces = vec![
        [9, 10, 11],
        [9, 12, 13],
        [2, 3, 4],
        [2, 5, 6],
        [2, 7, 8],
        [0, 1, 14],
    ];
    assert_eq!(
        TriMesh::new(p, faces),
        Err(MeshError::NonManifoldVertex { vertex: 2, fans: 3 })
    );
}

#[test]
fn two_closed_surfaces_touching_at_a_vertex_are_non_manifold() {
    // Two tetrahedra sharing vertex 0: every edge is manifold, the vertex is not.
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, -1.0],
    ];
    let tet = |a: usize, b: usize, c: usize, d: usize| [[a, c, b], [a, b, d], [a, d, c], [b, c, d]];
    let mut f = tet(0, 1, 2, 3).to_vec();
    f.extend(tet(0, 4, 5, 6).map(|[a, b, c]| [a, c, b]));
    assert!(TriMesh::new(p[..4].to_vec(), tet(0, 1, 2, 3).to_vec()).is_ok());
    assert_eq!(
        TriMesh::new(p, f),
        Err(MeshError::NonManifoldVertex { vertex: 0, fans: 2 })
    );
}

#[test]
fn errors_display_the_offending_element() {
    let e = MeshError::InconsistentOrientation {
        edge: [3, 8],
        faces: [4, 9],
    };
    assert_eq!(
        e.to_string(),
        "faces [4, 9] both traverse edge [3, 8] in the same direction"
    );
    let e = MeshError::NonManifoldVertex { vertex: 5, fans: 2 };
    assert_eq!(
        e.to_string(),
        "the faces around vertex 5 form 2 separate fans"
    );
}

#[test]
fn edges_are_listed_once_with_their_faces() {
    let mesh = icosphere(1);
    let edges = mesh.edges();
    assert_eq!(edges.len(), 120); // 3F/2 on a closed mesh, F = 80
    for e in &edges {
        let [a, b] = e.vertices;
        let traverses = |t: usize, a: usize, b: usize| {
            let f = mesh.faces()[t];
            (0..3).any(|c| f[c] == a && f[(c + 1) % 3] == b)
        };
        assert!(traverses(e.face, a, b));
        assert!(traverses(e.opposite_face.unwrap(), b, a));
    }
    assert!(mesh.boundary_edges().is_empty());
}

#[test]
fn boundary_edges_follow_the_face_direction() {
    let (p, f) = square();
    let mesh = TriMesh::new(p, f).unwrap();
    let mut boundary = mesh.boundary_edges();
    boundary.sort();
    assert_eq!(boundary, vec![[0, 3], [1, 2], [2, 0], [3, 1]]);
}

#[test]
fn scaling_to_zero_is_rejected() {
    assert_eq!(
        icosphere(0).scaled(0.0),
        Err(MeshError::ZeroAreaFace { face: 0 })
    );
}

fn unit_quaternion() -> impl Strategy<Value = Quat<f64>> {
    prop::array::uniform4(-1.0..1.0f64)
        .prop_filter("not too short", |a| {
            a.iter().map(|x| x * x).sum::<f64>() > 0.01
        })
        .prop_map(|a| Quat::new(a[0], a[1], a[2], a[3]).normalize())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Flipping any single face of a closed mesh breaks orientation at that face.
    #[test]
    fn flipping_one_face_is_detected(t in 0usize..80) {
        let mesh = icosphere(1);
        let mut faces = mesh.faces().to_vec();
        faces[t].swap(1, 2);
        match TriMesh::new(mesh.positions().to_vec(), faces) {
            Err(MeshError::InconsistentOrientation { faces, .. }) => prop_assert!(faces.contains(&t)),
            other => prop_assert!(false, "unexpected {:?}", other),
        }
    }

    /// Rigid motions keep lengths and areas; reversing orientation twice is the identity.
    #[test]
    fn rigid_motions_keep_the_mesh_valid(
        r in unit_quaternion(),
        t in prop::array::uniform3(-10.0..10.0f64),
    ) {
        let mesh = icosphere(1);
        let moved = mesh.rotated(r).unwrap().translated(t).unwrap();
        prop_assert_eq!(moved.faces(), mesh.faces());
        for face in 0..mesh.face_count() {
            prop_assert!((moved.face_area(face) - mesh.face_area(face)).abs() < 1e-12);
        }
        let centroid = moved.positions().iter().fold([0.0; 3], |s, p| [s[0] + p[0], s[1] + p[1], s[2] + p[2]]);
        for k in 0..3 {
            prop_assert!((centroid[k] / 42.0 - t[k]).abs() < 1e-9);
        }
        prop_assert_eq!(mesh.reverse_orientation().reverse_orientation(), mesh);
    }

    /// Scaling by `s` multiplies every area by `s²`.
    #[test]
    fn scaling_multiplies_areas(s in 0.1..10.0f64) {
        let mesh = icosphere(1);
        let scaled = mesh.scaled(s).unwrap();
        for face in 0..mesh.face_count() {
            prop_assert!((scaled.face_area(face) - s * s * mesh.face_area(face)).abs() < 1e-12 * s * s);
        }
    }
}
