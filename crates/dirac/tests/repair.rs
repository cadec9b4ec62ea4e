//! `dirac::repair`: every defect, built by hand so the expected report is known by
//! construction, is repaired into a mesh `TriMesh::new` accepts; repair is idempotent; a
//! triangle soup repairs to the mesh it was made from (same spectrum); components are kept and
//! can be selected.

use dirac::generators::{Torus, grid, icosphere};
use dirac::io::RawMesh;
use dirac::repair::{Change, RepairError, RepairOptions, Repaired, repair, slivers};
use dirac::spectrum::{Operator, SpectrumOptions, spectrum};
use dirac::{ComponentError, ComponentSelection, MeshError, TriMesh};
use proptest::prelude::*;

fn raw(positions: Vec<[f64; 3]>, faces: Vec<[usize; 3]>) -> RawMesh {
    RawMesh { positions, faces }
}

fn raw_of(mesh: &TriMesh) -> RawMesh {
    raw(mesh.positions().to_vec(), mesh.faces().to_vec())
}

fn fixed(input: RawMesh) -> Repaired {
    repair(input, &RepairOptions::default()).unwrap_or_else(|e| panic!("repair failed: {e}"))
}

fn change<T>(count: usize, examples: Vec<T>) -> Change<T> {
    Change { count, examples }
}

/// Repairing the result changes nothing and reports nothing.
fn assert_idempotent(once: &Repaired) {
    let twice = fixed(raw_of(&once.mesh));
    assert!(
        twice.report.is_empty(),
        "second repair reported:\n{}",
        twice.report
    );
    assert_eq!(twice.mesh, once.mesh);
    assert_eq!(
        twice.vertex_origin,
        (0..once.mesh.vertex_count()).collect::<Vec<_>>()
    );
    assert_eq!(
        twice.face_origin,
        (0..once.mesh.face_count()).collect::<Vec<_>>()
    );
}

/// The unit tetrahedron, faces counter-clockwise seen from outside.
fn tetrahedron() -> RawMesh {
    raw(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
}

/// The unit square in the plane z = 0 as two triangles (vertices 0–3).
fn square() -> RawMesh {
    raw(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

/// The square with `extra` vertices appended and `faces` added after its two.
fn square_with(extra: &[[f64; 3]], faces: &[[usize; 3]]) -> RawMesh {
    let mut mesh = square();
    mesh.positions.extend_from_slice(extra);
    mesh.faces.extend_from_slice(faces);
    mesh
}

fn rejected(input: &RawMesh) -> MeshError {
    input
        .clone()
        .into_mesh()
        .expect_err("TriMesh::new rejects the defect")
}

/// The square with the faces and vertices named removed, as expected after repair.
fn assert_is_square(repaired: &Repaired) {
    let square = square();
    assert_eq!(repaired.mesh.positions(), &square.positions[..]);
    assert_eq!(repaired.mesh.faces(), &square.faces[..]);
    assert_eq!(repaired.vertex_origin, [0, 1, 2, 3]);
    assert_eq!(repaired.face_origin, [0, 1]);
}

#[test]
fn the_hand_built_meshes_are_valid() {
    assert!(tetrahedron().into_mesh().unwrap().topology().is_closed());
    assert!(square().into_mesh().is_ok());
}

#[test]
fn a_clean_mesh_passes_through_unchanged() {
    for mesh in [
        icosphere(2),
        Torus::new(2.0, 0.7, 12, 8).mesh().unwrap(),
        grid(3, 2, 1.0, 1.0).unwrap(),
    ] {
        let repaired = fixed(raw_of(&mesh));
        assert!(repaired.report.is_empty(), "{}", repaired.report);
        assert_eq!(repaired.report.to_string(), "nothing to repair");
        assert_eq!(repaired.mesh, mesh);
        assert_eq!(
            repaired.vertex_origin,
            (0..mesh.vertex_count()).collect::<Vec<_>>()
        );
        assert_eq!(
            repaired.face_origin,
            (0..mesh.face_count()).collect::<Vec<_>>()
        );
    }
}

#[test]
fn duplicated_vertex_is_merged() {
    // Vertex 4 is a copy of vertex 0, used by face 1 in its place: valid, but open.
    let mut input = tetrahedron();
    input.positions.push([0.0, 0.0, 0.0]);
    input.faces[1] = [4, 1, 3];
    let before = input
        .clone()
        .into_mesh()
        .expect("a soup-like seam is a valid mesh");
    assert!(!before.topology().is_closed());
    let repaired = fixed(input);
    assert_eq!(repaired.report.merged_vertices, change(1, vec![[4, 0]]));
    assert_eq!(repaired.mesh.faces(), &tetrahedron().faces[..]);
    assert_eq!(repaired.vertex_origin, [0, 1, 2, 3]);
    assert!(repaired.mesh.topology().is_closed());
    assert_eq!(repaired.report.lines().count(), 1);
    assert_eq!(
        repaired.report.to_string(),
        "merged 1 vertex into a coincident one (4→0)"
    );
    assert_idempotent(&repaired);
}

#[test]
fn nearly_coincident_vertices_merge_within_the_tolerance_only() {
    // The copy of vertex 0 is 1e-12 away (the box diagonal is √3): merged by default, kept
    // apart with a tolerance of 0.
    let mut input = tetrahedron();
    input.positions.push([1e-12, 0.0, 0.0]);
    input.faces[1] = [4, 1, 3];
    assert_eq!(fixed(input.clone()).report.merged_vertices.count, 1);
    let mut exact = RepairOptions::default();
    exact.merge_distance = 0.0;
    let kept = repair(input, &exact).unwrap();
    assert!(kept.report.is_empty(), "{}", kept.report);
    assert_eq!(kept.mesh.vertex_count(), 5);
}

#[test]
fn bad_merge_distance_is_a_typed_error() {
    for bad in [-1e-9, f64::NAN, f64::INFINITY] {
        let mut options = RepairOptions::default();
        options.merge_distance = bad;
        let error = repair(tetrahedron(), &options).unwrap_err();
        assert!(
            matches!(error, RepairError::InvalidMergeDistance(_)),
            "{error}"
        );
    }
}

#[test]
fn zero_area_face_is_removed() {
    // Face 2 lies on the x axis (vertices 1, 4, 5 collinear).
    let input = square_with(&[[2.0, 0.0, 0.0], [3.0, 0.0, 0.0]], &[[1, 4, 5]]);
    assert_eq!(rejected(&input), MeshError::ZeroAreaFace { face: 2 });
    let repaired = fixed(input);
    assert_eq!(repaired.report.removed_faces_zero_area, change(1, vec![2]));
    assert_eq!(repaired.report.removed_unreferenced, change(2, vec![4, 5]));
    assert_eq!(repaired.report.lines().count(), 2);
    assert_is_square(&repaired);
    assert_idempotent(&repaired);
}

#[test]
fn sliver_within_the_merge_tolerance_is_removed() {
    // Face 2 is glued to edge 0–1 with its apex 1e-12 off that edge: a valid mesh for
    // TriMesh::new would accept its area, but the height is below the tolerance 1e-9 · √2.
    let input = square_with(&[[0.5, -1e-12, 0.0]], &[[1, 0, 4]]);
    let repaired = fixed(input.clone());
    assert_eq!(repaired.report.removed_faces_zero_area, change(1, vec![2]));
    assert_eq!(repaired.report.removed_unreferenced, change(1, vec![4]));
    assert_is_square(&repaired);
    assert_idempotent(&repaired);
    // A height above the tolerance is kept: the triangle is small, not degenerate.
    let input = square_with(&[[0.5, -1e-6, 0.0]], &[[1, 0, 4]]);
    let repaired = fixed(input);
    assert!(repaired.report.is_empty(), "{}", repaired.report);
    assert_eq!(repaired.mesh.face_count(), 3);
}

/// The slivers a valid mesh holds are the faces the repair drops as such: the height of each
/// from its coordinates against the tolerance `1e-9` times the bounding box's diagonal.
#[test]
fn slivers_are_the_faces_the_repair_drops_as_such() {
    for (height, expected) in [(1e-12, vec![2]), (1e-6, vec![])] {
        let input = square_with(&[[0.5, -height, 0.0]], &[[1, 0, 4]]);
        let mesh = TriMesh::new(input.positions.clone(), input.faces.clone()).unwrap();
        let diagonal = (1.0f64 + (1.0 + height) * (1.0 + height)).sqrt();
        // Face 2 has its longest edge 0–1 of length 1: its height is `2 · area`.
        assert_eq!(height <= 1e-9 * diagonal, !expected.is_empty());
        assert_eq!(slivers(&mesh), expected);
        assert_eq!(
            repair(input, &RepairOptions::default())
                .unwrap()
                .report
                .removed_faces_zero_area
                .examples,
            expected
        );
    }
}

#[test]
fn face_with_a_degenerate_angle_is_removed() {
    // A needle 10²⁰⁰ long and 10⁻¹⁰⁰ wide: its area is fine, but the cotangent at vertex 5
    // overflows. Its size would make the relative merge tolerance huge, so merge nothing.
    let input = square_with(
        &[[0.0, 0.0, 5.0], [1e200, 0.0, 5.0], [0.0, 1e-100, 5.0]],
        &[[4, 5, 6]],
    );
    assert_eq!(
        rejected(&input),
        MeshError::DegenerateAngle { face: 2, vertex: 5 }
    );
    let mut options = RepairOptions::default();
    options.merge_distance = 0.0;
    let repaired = repair(input, &options).unwrap();
    assert_eq!(
        repaired.report.removed_faces_degenerate_angle,
        change(1, vec![2])
    );
    assert_eq!(
        repaired.report.removed_unreferenced,
        change(3, vec![4, 5, 6])
    );
    assert_eq!(repaired.report.lines().count(), 2);
    assert_is_square(&repaired);
}

#[test]
fn unreferenced_vertex_is_removed() {
    let input = square_with(&[[5.0, 5.0, 5.0]], &[]);
    assert_eq!(
        rejected(&input),
        MeshError::UnreferencedVertex { vertex: 4 }
    );
    let repaired = fixed(input);
    assert_eq!(repaired.report.removed_unreferenced, change(1, vec![4]));
    assert_eq!(repaired.report.lines().count(), 1);
    assert_is_square(&repaired);
    assert_idempotent(&repaired);
}

#[test]
fn non_finite_coordinate_and_bad_indices_remove_their_faces() {
    let input = square_with(
        &[[f64::NAN, 0.0, 0.0], [0.5, f64::INFINITY, 0.0]],
        &[[1, 4, 2], [0, 1, 99], [2, 5, 3], [0, 0, 1]],
    );
    assert_eq!(
        rejected(&input),
        MeshError::IndexOutOfRange {
            face: 3,
            vertex: 99,
            vertex_count: 6
        }
    );
    let repaired = fixed(input);
    let report = &repaired.report;
    assert_eq!(report.removed_faces_non_finite, change(2, vec![2, 4]));
    assert_eq!(report.removed_faces_out_of_range, change(1, vec![3]));
    assert_eq!(report.removed_faces_repeated_vertex, change(1, vec![5]));
    assert_eq!(report.removed_unreferenced, change(2, vec![4, 5]));
    assert_eq!(report.lines().count(), 4);
    assert_is_square(&repaired);
    assert_idempotent(&repaired);
}

#[test]
fn duplicate_faces_are_removed_in_any_order_or_orientation() {
    // Face 2 is face 0 rotated, face 3 is face 0 reversed.
    let input = square_with(&[], &[[1, 2, 0], [2, 1, 0]]);
    assert!(matches!(
        rejected(&input),
        MeshError::NonManifoldEdge { .. }
    ));
    let repaired = fixed(input);
    assert_eq!(
        repaired.report.removed_duplicate_faces,
        change(2, vec![[2, 0], [3, 0]])
    );
    assert_eq!(repaired.report.lines().count(), 1);
    assert_is_square(&repaired);
    assert_idempotent(&repaired);
}

#[test]
fn fin_on_an_edge_is_split_off() {
    // Three faces on edge 0–1: faces 0 and 1 traverse it in opposite directions and stay
    // glued; the fin, face 2, gets its own copies of vertices 0 and 1.
    let input = raw(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, -1.0, 0.0],
            [0.5, 0.0, 1.0],
        ],
        vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
    );
    assert_eq!(
        rejected(&input),
        MeshError::NonManifoldEdge {
            edge: [0, 1],
            faces: vec![0, 1, 2]
        }
    );
    let repaired = fixed(input);
    let report = &repaired.report;
    assert_eq!(report.split_edges, change(1, vec![[0, 1]]));
    assert_eq!(report.split_vertices, change(2, vec![[0, 2], [1, 2]]));
    assert_eq!(report.lines().count(), 2);
    assert_eq!(repaired.vertex_origin, [0, 0, 1, 1, 2, 3, 4]);
    let topology = repaired.mesh.topology();
    assert_eq!(topology.components.len(), 2);
    assert_eq!(
        [topology.components[0].faces, topology.components[1].faces],
        [2, 1]
    );
    assert_idempotent(&repaired);
}

/// Two tetrahedra touching at vertex 0 (the second is the first reflected through it).
fn two_tetrahedra() -> RawMesh {
    let mut input = tetrahedron();
    input
        .positions
        .extend([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]);
    // The reflection reverses orientation, so each reflected face is listed reversed.
    input
        .faces
        .extend([[0, 4, 5], [0, 6, 4], [0, 5, 6], [4, 6, 5]]);
    input
}

#[test]
fn bowtie_vertex_is_split_into_one_vertex_per_fan() {
    let input = two_tetrahedra();
    let second = raw(input.positions.clone(), input.faces[4..].to_vec());
    assert!(
        second.into_mesh_removing_unreferenced().is_ok(),
        "the second tetrahedron is valid"
    );
    assert_eq!(
        rejected(&input),
        MeshError::NonManifoldVertex { vertex: 0, fans: 2 }
    );
    let repaired = fixed(input);
    assert_eq!(repaired.report.split_vertices, change(1, vec![[0, 2]]));
    assert_eq!(repaired.report.lines().count(), 1);
    assert_eq!(repaired.vertex_origin, [0, 0, 1, 2, 3, 4, 5, 6]);
    let topology = repaired.mesh.topology();
    assert!(topology.is_closed());
    assert_eq!(topology.components.len(), 2);
    assert_eq!(topology.euler_characteristic, 4);
    assert_idempotent(&repaired);
}

#[test]
fn coincident_apexes_of_separate_sheets_are_neither_merged_nor_split() {
    // As the bowtie, but the second tetrahedron has its own copy of the shared vertex: merging
    // would pinch the surface, so the two copies stay apart and nothing is reported.
    let mut input = two_tetrahedra();
    input.positions.push([0.0, 0.0, 0.0]);
    for face in &mut input.faces[4..] {
        for v in face.iter_mut().filter(|v| **v == 0) {
            *v = 7;
        }
    }
    let valid = input
        .clone()
        .into_mesh()
        .expect("two touching but separate tetrahedra");
    let repaired = fixed(input);
    assert!(repaired.report.is_empty(), "{}", repaired.report);
    assert_eq!(repaired.mesh, valid);
}

#[test]
fn one_flipped_face_is_flipped_back() {
    for flipped in 0..4 {
        let mut input = tetrahedron();
        let [i, j, k] = input.faces[flipped];
        input.faces[flipped] = [i, k, j];
        assert!(matches!(
            rejected(&input),
            MeshError::InconsistentOrientation { .. }
        ));
        let repaired = fixed(input);
        // The other three faces hold most of the area, whichever face was flipped.
        assert_eq!(repaired.report.flipped_faces, change(1, vec![flipped]));
        assert_eq!(repaired.report.lines().count(), 1);
        assert_eq!(repaired.mesh.faces(), &tetrahedron().faces[..]);
        assert_idempotent(&repaired);
    }
}

/// A ring of 5 quads, its last quad glued to the first with a half twist (a Möbius strip) or
/// without (a flat annulus).
fn ring(twisted: bool) -> RawMesh {
    let n = 5;
    let mut positions = Vec::new();
    for i in 0..n {
        let u = std::f64::consts::TAU * i as f64 / n as f64;
        for w in [-0.3, 0.3] {
            let (r, z) = if twisted {
                (1.0 + w * (u / 2.0).cos(), w * (u / 2.0).sin())
            } else {
                (1.0 + w, 0.0)
            };
            positions.push([r * u.cos(), r * u.sin(), z]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..n {
        let (a, b) = (2 * i, 2 * i + 1);
        // The last quad joins the first rung, the twisted strip upside down.
        let (c, d) = match (i + 1 < n, twisted) {
            (true, _) => (2 * i + 2, 2 * i + 3),
            (false, true) => (1, 0),
            (false, false) => (0, 1),
        };
        faces.push([a, c, d]);
        faces.push([a, d, b]);
    }
    raw(positions, faces)
}

#[test]
fn mobius_strip_is_a_typed_error() {
    let input = ring(true);
    // Validation says so too, instead of naming two faces that repair would not reconcile.
    let invalid = rejected(&input);
    assert!(
        matches!(invalid, MeshError::NonOrientable { face } if face < input.faces.len()),
        "{invalid}"
    );
    assert!(invalid.to_string().contains("not orientable"), "{invalid}");
    let error = repair(input, &RepairOptions::default()).unwrap_err();
    assert!(
        matches!(error, RepairError::NonOrientable { component: 0, .. }),
        "{error}"
    );
    assert!(error.to_string().contains("not orientable"), "{error}");
}

#[test]
fn a_flipped_face_of_a_twisted_strip_is_not_orientable_but_of_an_annulus_it_is_fixed() {
    for flipped in 0..10 {
        let with_flip = |mut input: RawMesh| {
            let [i, j, k] = input.faces[flipped];
            input.faces[flipped] = [i, k, j];
            input
        };
        let annulus = with_flip(ring(false));
        assert!(matches!(
            rejected(&annulus),
            MeshError::InconsistentOrientation { .. }
        ));
        assert_eq!(fixed(annulus).report.flipped_faces.count, 1);
        assert!(matches!(
            rejected(&with_flip(ring(true))),
            MeshError::NonOrientable { .. }
        ));
    }
}

#[test]
fn nothing_left_is_a_typed_error() {
    let input = raw(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
        vec![[0, 1, 2], [0, 1, 7]],
    );
    assert_eq!(
        repair(input, &RepairOptions::default()).unwrap_err(),
        RepairError::NoFacesLeft { faces: 2 }
    );
    assert_eq!(
        repair(RawMesh::default(), &RepairOptions::default()).unwrap_err(),
        RepairError::NoFacesLeft { faces: 0 }
    );
}

/// `mesh` as a triangle soup: face `t` gets the vertices `3t, 3t + 1, 3t + 2` of its own.
fn soup(mesh: &TriMesh) -> RawMesh {
    let p = mesh.positions();
    raw(
        mesh.faces().iter().flat_map(|f| f.map(|v| p[v])).collect(),
        (0..mesh.face_count())
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect(),
    )
}

fn eigenvalues(mesh: &TriMesh, operator: Operator) -> Vec<f64> {
    spectrum(mesh, &SpectrumOptions::new(operator, 10))
        .unwrap_or_else(|e| panic!("{operator:?}: {e}"))
        .eigenvalues
}

#[test]
fn a_triangle_soup_repairs_to_the_mesh_it_came_from() {
    let torus = Torus::new(2.0, 0.7, 16, 10).mesh().unwrap();
    for mesh in [icosphere(2), torus] {
        let input = soup(&mesh);
        let repaired = fixed(input.clone());
        let report = &repaired.report;
        assert_eq!(
            report.merged_vertices.count,
            3 * mesh.face_count() - mesh.vertex_count()
        );
        assert_eq!(report.lines().count(), 1, "{report}");
        assert_eq!(repaired.mesh.vertex_count(), mesh.vertex_count());
        assert_eq!(
            repaired.face_origin,
            (0..mesh.face_count()).collect::<Vec<_>>()
        );
        // Each output face has the corners of its soup face, in the same cyclic order.
        for (t, face) in repaired.mesh.faces().iter().enumerate() {
            let corners = face.map(|v| repaired.mesh.positions()[v]);
            let soup_corners = input.faces[t].map(|v| input.positions[v]);
            assert_eq!(corners, soup_corners, "face {t}");
            // The origin of a vertex is its first copy: the soup vertex of its first face.
            for (c, &v) in face.iter().enumerate() {
                assert_eq!(input.positions[repaired.vertex_origin[v]], corners[c]);
            }
        }
        assert_eq!(repaired.mesh.topology(), mesh.topology());
        for operator in [Operator::Laplace, Operator::RelativeDirac] {
            let (got, want) = (
                eigenvalues(&repaired.mesh, operator),
                eigenvalues(&mesh, operator),
            );
            for (g, w) in got.iter().zip(&want) {
                assert!(
                    (g - w).abs() <= 1e-10 * w.abs().max(1.0),
                    "{operator:?}: {got:?} vs {want:?}"
                );
            }
        }
        assert_idempotent(&repaired);
    }
}

/// Three icospheres of 1, 2 and 3 subdivision levels, side by side (not touching).
fn three_spheres() -> TriMesh {
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for (i, level) in [1, 3, 2].into_iter().enumerate() {
        let sphere = icosphere(level);
        let offset = positions.len();
        let shift = 3.0 * i as f64;
        positions.extend(
            sphere
                .positions()
                .iter()
                .map(|p| [p[0] + shift, p[1], p[2]]),
        );
        faces.extend(sphere.faces().iter().map(|f| f.map(|v| v + offset)));
    }
    TriMesh::new(positions, faces).unwrap()
}

#[test]
fn components_are_kept_and_can_be_selected() {
    let mesh = three_spheres();
    let repaired = fixed(raw_of(&mesh));
    assert!(repaired.report.is_empty(), "{}", repaired.report);
    let mut options = SpectrumOptions::new(Operator::Laplace, 4);
    options.include_kernel = true;
    let values = spectrum(&repaired.mesh, &options).unwrap().eigenvalues;
    assert!(values[..3].iter().all(|l| l.abs() < 1e-8), "{values:?}");
    assert!(values[3] > 0.1, "{values:?}");

    let (largest, origin) = mesh.select_component(ComponentSelection::Largest).unwrap();
    let level3 = icosphere(3);
    assert_eq!(largest.faces(), level3.faces());
    let first = icosphere(1).vertex_count();
    assert_eq!(
        origin,
        (first..first + level3.vertex_count()).collect::<Vec<_>>()
    );
    for (v, &o) in origin.iter().enumerate() {
        assert_eq!(largest.positions()[v], mesh.positions()[o]);
    }
    let values = spectrum(&largest, &options).unwrap().eigenvalues;
    assert!(values[0].abs() < 1e-8 && values[1] > 0.1, "{values:?}");

    let (last, _) = mesh.select_component(ComponentSelection::Index(2)).unwrap();
    assert_eq!(last.faces(), icosphere(2).faces());
    let (all, identity) = mesh.select_component(ComponentSelection::All).unwrap();
    assert_eq!(all, mesh);
    assert_eq!(identity, (0..mesh.vertex_count()).collect::<Vec<_>>());
    let error = mesh
        .select_component(ComponentSelection::Index(3))
        .unwrap_err();
    assert_eq!(error, ComponentError::OutOfRange { index: 3, count: 3 });
    assert!(
        error.to_string().contains("has 3 connected components"),
        "{error}"
    );
}

#[test]
fn largest_component_ties_go_to_the_smaller_index() {
    let input = two_tetrahedra();
    let mesh = fixed(input).mesh;
    let (first, origin) = mesh.select_component(ComponentSelection::Largest).unwrap();
    assert_eq!(first.faces(), &tetrahedron().faces[..]);
    assert_eq!(origin, [0, 2, 3, 4]);
}

#[test]
fn component_selection_parses_and_prints() {
    for (text, selection) in [
        ("all", ComponentSelection::All),
        ("largest", ComponentSelection::Largest),
        ("0", ComponentSelection::Index(0)),
        ("17", ComponentSelection::Index(17)),
    ] {
        assert_eq!(text.parse::<ComponentSelection>(), Ok(selection));
        assert_eq!(selection.to_string(), text);
    }
    for bad in ["", "Largest", "-1", "1.5", "biggest"] {
        let error = bad.parse::<ComponentSelection>().unwrap_err();
        assert!(
            error
                .to_string()
                .contains("expected `all`, `largest` or a component index")
        );
    }
}

#[test]
fn report_lines_name_counts_and_examples() {
    // The square and seven copies of its face 0: seven removed, five shown.
    let input = square_with(&[], &[[0, 1, 2]; 7]);
    let report = fixed(input).report;
    assert_eq!(report.removed_duplicate_faces.count, 7);
    assert_eq!(
        report.to_string(),
        "removed 7 duplicate faces (e.g. 2 = 0, 3 = 0, 4 = 0, 5 = 0, 6 = 0, …)"
    );
}

// Random meshes with random defects: repair never panics; when it succeeds, the result is
// valid and repairing it again changes nothing.

/// A base mesh (small sphere, grid or torus) as positions and faces.
fn base() -> impl Strategy<Value = RawMesh> {
    prop_oneof![
        Just(raw_of(&icosphere(1))),
        Just(raw_of(&grid(3, 2, 1.0, 1.0).unwrap())),
        Just(raw_of(&Torus::new(2.0, 0.7, 6, 4).mesh().unwrap())),
        Just(tetrahedron()),
    ]
}

/// One defect, applied with random numbers.
#[derive(Debug, Clone)]
enum Defect {
    /// Give every face its own vertices.
    Soup,
    /// Copy face `n` (rotated `r` times, reversed if `flag`).
    Duplicate(usize, usize, bool),
    /// Reverse face `n`.
    Flip(usize),
    /// Move vertex `n` onto vertex `m` (degenerate faces, pinches).
    Collapse(usize, usize),
    /// Nudge vertex `n` by `x` (a tiny amount: merges).
    Jitter(usize, f64),
    /// A face on three arbitrary vertices (fins, non-manifold vertices, holes).
    Extra([usize; 3]),
    /// An index out of range in face `n`.
    OutOfRange(usize),
    /// A non-finite coordinate at vertex `n`.
    NonFinite(usize),
    /// A vertex no face uses.
    Unreferenced,
    /// Drop face `n`.
    Remove(usize),
}

fn defect() -> impl Strategy<Value = Defect> {
    let i = 0..64usize;
    prop_oneof![
        Just(Defect::Soup),
        (i.clone(), 0..3usize, any::<bool>()).prop_map(|(n, r, b)| Defect::Duplicate(n, r, b)),
        i.clone().prop_map(Defect::Flip),
        (i.clone(), i.clone()).prop_map(|(n, m)| Defect::Collapse(n, m)),
        (i.clone(), -1e-10..1e-10f64).prop_map(|(n, x)| Defect::Jitter(n, x)),
        [i.clone(), i.clone(), i.clone()].prop_map(Defect::Extra),
        i.clone().prop_map(Defect::OutOfRange),
        i.clone().prop_map(Defect::NonFinite),
        Just(Defect::Unreferenced),
        i.prop_map(Defect::Remove),
    ]
}

fn apply(mesh: &mut RawMesh, defect: &Defect) {
    let (nv, nf) = (mesh.positions.len(), mesh.faces.len());
    if nv == 0 || nf == 0 {
        return;
    }
    match *defect {
        Defect::Soup => *mesh = soup_raw(mesh),
        Defect::Duplicate(n, r, reversed) => {
            let mut f = mesh.faces[n % nf];
            f.rotate_left(r);
            if reversed {
                f.swap(1, 2);
            }
            mesh.faces.push(f);
        }
        Defect::Flip(n) => mesh.faces[n % nf].swap(1, 2),
        Defect::Collapse(n, m) => mesh.positions[n % nv] = mesh.positions[m % nv],
        Defect::Jitter(n, x) => mesh.positions[n % nv][0] += x,
        Defect::Extra(f) => mesh.faces.push(f.map(|v| v % nv)),
        Defect::OutOfRange(n) => mesh.faces[n % nf][n % 3] = nv + n,
        Defect::NonFinite(n) => mesh.positions[n % nv][n % 3] = f64::NAN,
        Defect::Unreferenced => mesh.positions.push([7.0, 7.0, 7.0]),
        Defect::Remove(n) => {
            mesh.faces.remove(n % nf);
        }
    }
}

/// [`soup`] of an unvalidated mesh (indices in range assumed; others are kept as they are).
fn soup_raw(mesh: &RawMesh) -> RawMesh {
    let mut out = RawMesh::default();
    for f in &mesh.faces {
        let base = out.positions.len();
        for &v in f {
            out.positions
                .push(mesh.positions.get(v).copied().unwrap_or([0.0; 3]));
        }
        out.faces.push([base, base + 1, base + 2]);
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn repair_of_random_defects_is_valid_and_idempotent(
        mut mesh in base(),
        defects in prop::collection::vec(defect(), 0..6),
    ) {
        for d in &defects {
            apply(&mut mesh, d);
        }
        let input = mesh.clone();
        match repair(mesh, &RepairOptions::default()) {
            Ok(repaired) => {
                let out = &repaired.mesh;
                prop_assert!(TriMesh::new(out.positions().to_vec(), out.faces().to_vec()).is_ok());
                prop_assert_eq!(repaired.vertex_origin.len(), out.vertex_count());
                prop_assert_eq!(repaired.face_origin.len(), out.face_count());
                prop_assert!(repaired.face_origin.windows(2).all(|w| w[0] < w[1]));
                // Each output face has the vertex set of its input face, up to merging: every
                // corner comes from a vertex within the tolerance of its input corner.
                let tolerance = 1e-9 * 100.0;
                for (t, face) in out.faces().iter().enumerate() {
                    let input_face = input.faces[repaired.face_origin[t]];
                    for &v in face {
                        let p = out.positions()[v];
                        let near = input_face.iter().any(|&w| {
                            let q = input.positions[w];
                            (0..3).all(|c| (p[c] - q[c]).abs() <= tolerance)
                        });
                        prop_assert!(near, "face {t}: vertex {v} is none of its input corners");
                    }
                }
                let twice = repair(raw_of(out), &RepairOptions::default());
                prop_assert!(twice.is_ok(), "second repair failed: {:?}", twice.err());
                let twice = twice.unwrap();
                prop_assert!(twice.report.is_empty(), "second repair reported:\n{}", twice.report);
                prop_assert_eq!(&twice.mesh, out);
            }
            Err(error) => prop_assert!(!error.to_string().is_empty()),
        }
    }
}
