//! Geometry of a mesh: face areas, barycentric vertex masses, the cotangent Laplacian, and the
//! small 3-vector helpers they use.

use qsparse::{SparseMatrix, TripletMatrix};

use crate::TriMesh;

/// The corners `(low, high)` of the axis-aligned bounding box of `points`, or `None` when
/// there are none.
pub fn bounding_box(points: impl IntoIterator<Item = [f64; 3]>) -> Option<([f64; 3], [f64; 3])> {
    points.into_iter().fold(None, |bounds, p| {
        let (low, high) = bounds.unwrap_or((p, p));
        Some((
            std::array::from_fn(|c| low[c].min(p[c])),
            std::array::from_fn(|c| high[c].max(p[c])),
        ))
    })
}

/// `a + b`.
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a s`.
pub fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a · b`.
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `|a|`.
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// `a / |a|`.
pub fn normalize(a: [f64; 3]) -> [f64; 3] {
    scale(a, 1.0 / norm(a))
}

/// `cot θ` of the angle θ at `apex` of the triangle (`apex`, `a`, `b`):
/// `(e₁·e₂) / |e₁×e₂|` with `e₁ = a − apex`, `e₂ = b − apex`. Finite at every corner of a
/// validated [`TriMesh`] (checked with this very function).
pub fn corner_cotangent(apex: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let (e1, e2) = (sub(a, apex), sub(b, apex));
    dot(e1, e2) / norm(cross(e1, e2))
}

/// The gradients `∇φ_c = n_t × e_c / (2A_t)` of the three linear hat functions of face
/// `t = ijk` (corner order `i, j, k`), with `n_t` the unit normal and `e_c` the edge opposite
/// corner `c`, counter-clockwise (`e_i = f_k − f_j`, …). Tangent to the face, pointing from
/// the opposite edge towards the corner, of length `1/height`; they sum to zero.
pub fn hat_gradients(mesh: &TriMesh, t: usize) -> [[f64; 3]; 3] {
    let p = mesh.positions();
    let [i, j, k] = mesh.faces()[t];
    let area_normal = cross(sub(p[j], p[i]), sub(p[k], p[i]));
    let double_area = norm(area_normal);
    // `n × e / (2A) = (2A n) × e / (2A)²`: one division, no normalisation.
    let factor = 1.0 / (double_area * double_area);
    [sub(p[k], p[j]), sub(p[i], p[k]), sub(p[j], p[i])]
        .map(|edge| scale(cross(area_normal, edge), factor))
}

/// Face areas `A_t`.
pub fn face_areas(mesh: &TriMesh) -> Vec<f64> {
    (0..mesh.face_count()).map(|t| mesh.face_area(t)).collect()
}

/// Area-weighted vertex normals (docs/MATH.md, "The operators"):
/// `N_p = normalize(Σ_{t∋p} 2A_t n_t)`, where `2A_t n_t = (f_j − f_i) × (f_k − f_i)` for face
/// `t = ijk`. Returns the first vertex whose summed normal vanishes as `Err(vertex)` (possible only
/// on degenerate configurations).
pub fn vertex_normals(mesh: &TriMesh) -> Result<Vec<[f64; 3]>, usize> {
    let p = mesh.positions();
    let mut sum = vec![[0.0; 3]; mesh.vertex_count()];
    for &[i, j, k] in mesh.faces() {
        let area_normal = cross(sub(p[j], p[i]), sub(p[k], p[i]));
        for v in [i, j, k] {
            for c in 0..3 {
                sum[v][c] += area_normal[c];
            }
        }
    }
    sum.into_iter()
        .enumerate()
        .map(|(v, n)| {
            if norm(n) > 0.0 {
                Ok(normalize(n))
            } else {
                Err(v)
            }
        })
        .collect()
}

/// Barycentric (lumped) vertex masses `Ā_p = Σ_{t∋p} A_t / 3` (docs/MATH.md, "The operators").
pub fn barycentric_masses(mesh: &TriMesh) -> Vec<f64> {
    let mut mass = vec![0.0; mesh.vertex_count()];
    for (t, face) in mesh.faces().iter().enumerate() {
        let third = mesh.face_area(t) / 3.0;
        for &p in face {
            mass[p] += third;
        }
    }
    mass
}

/// The positive-semidefinite cotangent Laplacian (docs/MATH.md, "The operators"):
/// `L_ij = −(cot α_ij + cot β_ij)/2` for an edge `ij` with opposite angles `α_ij`, `β_ij`
/// (one angle on a boundary edge: Neumann), and `L_ii = −Σ_{j≠i} L_ij`.
/// The negative of libigl's and gptoolbox's `cotmatrix`.
pub fn cotan_laplacian(mesh: &TriMesh) -> SparseMatrix<f64> {
    let n = mesh.vertex_count();
    // The diagonal is summed here and added to the sorted off-diagonal part: half the
    // triplets to sort.
    let mut t = TripletMatrix::with_capacity(n, n, 6 * mesh.face_count());
    let mut diagonal = vec![0.0; n];
    let p = mesh.positions();
    for face in mesh.faces() {
        for corner in 0..3 {
            // The angle at `k` is opposite the edge `ij`.
            let (i, j, k) = (face[corner], face[(corner + 1) % 3], face[(corner + 2) % 3]);
            let half_cot = 0.5 * corner_cotangent(p[k], p[i], p[j]);
            for (r, c) in [(i, j), (j, i)] {
                t.push(r, c, -half_cot)
                    .expect("indices and values of a validated mesh are valid");
            }
            diagonal[i] += half_cot;
            diagonal[j] += half_cot;
        }
    }
    SparseMatrix::linear_combination(
        1.0,
        &t.to_csc(),
        1.0,
        &SparseMatrix::from_diagonal(&diagonal),
    )
    .expect("two n × n matrices")
}
