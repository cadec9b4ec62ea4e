//! Mesh generators for tests and benchmarks: icosphere, torus (with optional detail and random
//! tessellations), open cylinder (with its exact normals), subdivided cube, flat grid, and
//! sphere patches with ragged boundaries. Every generator is deterministic; the random ones
//! take a seed ([`SplitMix64`]).

use std::collections::HashMap;
use std::f64::consts::TAU;

use thiserror::Error;

use crate::geometry::{dot, normalize, scale};
use crate::{MeshError, TriMesh};
use qscalar::random::SplitMix64;

/// Why a generator could not build its mesh.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum GeneratorError {
    /// A parameter is outside its documented range.
    #[error("parameter `{name}` = {value} must be {requirement}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// The generated mesh failed validation (for example a detail amplitude that folds it).
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// Fails with [`GeneratorError::InvalidParameter`] unless `ok`.
fn require(
    ok: bool,
    name: &'static str,
    value: f64,
    requirement: &'static str,
) -> Result<(), GeneratorError> {
    if ok {
        Ok(())
    } else {
        Err(GeneratorError::InvalidParameter {
            name,
            value,
            requirement,
        })
    }
}

/// Two triangles per cell of a grid of `nu × nv` cells, counter-clockwise in the `(u, v)`
/// parameter plane. `index(i, j)` is the vertex at grid point `(i, j)`, `0 ≤ i ≤ nu`,
/// `0 ≤ j ≤ nv` (the caller wraps periodic directions). Cell `(i, j)` is split along the
/// diagonal `(i, j)–(i+1, j+1)` unless `other_diagonal(i, j)`.
fn grid_faces(
    nu: usize,
    nv: usize,
    index: impl Fn(usize, usize) -> usize,
    mut other_diagonal: impl FnMut(usize, usize) -> bool,
) -> Vec<[usize; 3]> {
    let mut faces = Vec::with_capacity(2 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            if other_diagonal(i, j) {
                faces.extend_from_slice(&[[a, b, d], [b, c, d]]);
            } else {
                faces.extend_from_slice(&[[a, b, c], [a, c, d]]);
            }
        }
    }
    faces
}

/// The icosahedron subdivided `level` times by edge midpoints, projected to the unit sphere:
/// `10·4^level + 2` vertices, `20·4^level` faces, counter-clockwise seen from outside.
pub fn icosphere(level: u32) -> TriMesh {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<[f64; 3]> = [
        [-1.0, phi, 0.0],
        [1.0, phi, 0.0],
        [-1.0, -phi, 0.0],
        [1.0, -phi, 0.0],
        [0.0, -1.0, phi],
        [0.0, 1.0, phi],
        [0.0, -1.0, -phi],
        [0.0, 1.0, -phi],
        [phi, 0.0, -1.0],
        [phi, 0.0, 1.0],
        [-phi, 0.0, -1.0],
        [-phi, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| normalize(p))
    .collect();
    let mut faces: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoint: HashMap<(usize, usize), usize> = HashMap::new();
        let mut mid = |a: usize, b: usize, positions: &mut Vec<[f64; 3]>| {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (positions[a], positions[b]);
                positions.push(normalize(scale(
                    [p[0] + q[0], p[1] + q[1], p[2] + q[2]],
                    0.5,
                )));
                positions.len() - 1
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for &[a, b, c] in &faces {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    TriMesh::new(positions, faces).expect("the icosphere is a valid mesh")
}

/// Detail added to a torus: a displacement `h·f(u, v)` along the outward unit normal, where
/// `u` is the angle around the major circle, `v` the angle around the tube, `h` the amplitude
/// and `|f| ≤ 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Detail {
    /// No displacement.
    None,
    /// An egg-crate of bumps, `f = cos(a u)·cos(b v)` with `frequency = [a, b]`.
    Bumps {
        /// `h`.
        amplitude: f64,
        /// Bumps around the major circle and around the tube.
        frequency: [u32; 2],
    },
    /// `frequency` sharp-crested ridges running around the tube, `f = 1 − 2|sin(k u / 2)|`.
    Ridges {
        /// `h`.
        amplitude: f64,
        /// Number of ridges `k`.
        frequency: u32,
    },
    /// Smooth periodic noise: `f = Σ_m a_m cos(p_m u + q_m v + φ_m) / Σ_m a_m` over 12 modes
    /// with integer `p_m, q_m ∈ [−6, 6]` (not both zero), `a_m = 1/√(p_m² + q_m²)` and
    /// `φ_m ∈ [0, 2π)`, all drawn from `seed`.
    Noise {
        /// `h`.
        amplitude: f64,
        /// Seed of the modes.
        seed: u64,
    },
}

impl Detail {
    fn amplitude(&self) -> f64 {
        match *self {
            Detail::None => 0.0,
            Detail::Bumps { amplitude, .. }
            | Detail::Ridges { amplitude, .. }
            | Detail::Noise { amplitude, .. } => amplitude,
        }
    }

    /// The displacement `h·f(u, v)`.
    fn displacement(&self) -> Box<dyn Fn(f64, f64) -> f64> {
        match *self {
            Detail::None => Box::new(|_, _| 0.0),
            Detail::Bumps {
                amplitude,
                frequency: [a, b],
            } => Box::new(move |u, v| amplitude * (a as f64 * u).cos() * (b as f64 * v).cos()),
            Detail::Ridges {
                amplitude,
                frequency,
            } => Box::new(move |u, _| {
                amplitude * (1.0 - 2.0 * (frequency as f64 * u / 2.0).sin().abs())
            }),
            Detail::Noise { amplitude, seed } => {
                let mut rng = SplitMix64::new(seed);
                let mut modes = Vec::with_capacity(12);
                while modes.len() < 12 {
                    let p = (rng.next_u64() % 13) as f64 - 6.0;
                    let q = (rng.next_u64() % 13) as f64 - 6.0;
                    if p != 0.0 || q != 0.0 {
                        modes.push((p, q, 1.0 / p.hypot(q), rng.uniform(0.0, TAU)));
                    }
                }
                let total: f64 = modes.iter().map(|m| m.2).sum();
                Box::new(move |u, v| {
                    amplitude / total
                        * modes
                            .iter()
                            .map(|&(p, q, a, phase)| a * (p * u + q * v + phase).cos())
                            .sum::<f64>()
                })
            }
        }
    }
}

/// A random tessellation of a parameter grid: every grid vertex moves by an independent
/// uniform offset in `[−jitter, jitter]` grid spacings in each parameter direction (the
/// vertex stays on the surface), and every cell takes a random diagonal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RandomTessellation {
    /// Largest offset, in grid spacings; at most 0.25 so that no triangle folds over.
    pub jitter: f64,
    /// Seed of the offsets and diagonals.
    pub seed: u64,
}

/// A torus around the z axis:
/// `p(u, v) = ((R + r cos v) cos u, (R + r cos v) sin u, r sin v) + h f(u, v) n(u, v)` with the
/// outward normal `n = (cos v cos u, cos v sin u, sin v)` and the [`Detail`] `h f`. Grid vertex
/// `(i, j)`, `u = 2π i / major_segments`, `v = 2π j / minor_segments`, has index
/// `i · minor_segments + j`. `major_segments · minor_segments` vertices, twice as many faces,
/// counter-clockwise seen from outside; genus 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Torus {
    /// Major radius `R > r + |h|`.
    pub major_radius: f64,
    /// Minor (tube) radius `r > |h|`.
    pub minor_radius: f64,
    /// Grid points around the major circle, at least 3.
    pub major_segments: usize,
    /// Grid points around the tube, at least 3.
    pub minor_segments: usize,
    /// Displacement along the normal.
    pub detail: Detail,
    /// Regular grid (`None`) or a random tessellation of the same surface.
    pub tessellation: Option<RandomTessellation>,
}

impl Torus {
    /// A smooth torus on a regular grid.
    pub fn new(
        major_radius: f64,
        minor_radius: f64,
        major_segments: usize,
        minor_segments: usize,
    ) -> Self {
        Self {
            major_radius,
            minor_radius,
            major_segments,
            minor_segments,
            detail: Detail::None,
            tessellation: None,
        }
    }

    /// Builds the mesh.
    pub fn mesh(&self) -> Result<TriMesh, GeneratorError> {
        let (big_r, r, h) = (
            self.major_radius,
            self.minor_radius,
            self.detail.amplitude().abs(),
        );
        require(h.is_finite(), "amplitude", h, "finite")?;
        require(
            r > h && r.is_finite(),
            "minor_radius",
            r,
            "finite and > |amplitude|",
        )?;
        require(
            big_r > r + h && big_r.is_finite(),
            "major_radius",
            big_r,
            "finite and > minor_radius + |amplitude|",
        )?;
        let (nu, nv) = (self.major_segments, self.minor_segments);
        require(nu >= 3, "major_segments", nu as f64, "at least 3")?;
        require(nv >= 3, "minor_segments", nv as f64, "at least 3")?;
        if let Some(t) = self.tessellation {
            require(
                (0.0..=0.25).contains(&t.jitter),
                "jitter",
                t.jitter,
                "in [0, 0.25]",
            )?;
        }

        let displacement = self.detail.displacement();
        let mut rng = self
            .tessellation
            .map(|t| (SplitMix64::new(t.seed), t.jitter));
        let mut positions = Vec::with_capacity(nu * nv);
        for i in 0..nu {
            for j in 0..nv {
                let (mut u, mut v) = (TAU * i as f64 / nu as f64, TAU * j as f64 / nv as f64);
                if let Some((rng, jitter)) = rng.as_mut() {
                    u += rng.uniform(-*jitter, *jitter) * TAU / nu as f64;
                    v += rng.uniform(-*jitter, *jitter) * TAU / nv as f64;
                }
                let n = [v.cos() * u.cos(), v.cos() * u.sin(), v.sin()];
                let d = r + displacement(u, v);
                let ring = [big_r * u.cos(), big_r * u.sin(), 0.0];
                positions.push([ring[0] + d * n[0], ring[1] + d * n[1], ring[2] + d * n[2]]);
            }
        }
        let faces = grid_faces(
            nu,
            nv,
            |i, j| (i % nu) * nv + j % nv,
            |_, _| rng.as_mut().is_some_and(|(rng, _)| rng.next_u64() & 1 == 1),
        );
        Ok(TriMesh::new(positions, faces)?)
    }
}

/// The open cylinder of radius 1 around the z axis from `z = 0` to `z = height`: `rings` rings
/// of `segments` vertices each, aligned in angle. Vertex `i` of ring `j` has index
/// `j · segments + i` and position `(cos θ_i, sin θ_i, height · j / (rings − 1))`,
/// `θ_i = 2π i / segments`. `segments · rings` vertices, `2 · segments · (rings − 1)` faces,
/// counter-clockwise seen from outside; two boundary loops. Exact normals:
/// [`cylinder_normals`].
pub fn cylinder(segments: usize, rings: usize, height: f64) -> Result<TriMesh, GeneratorError> {
    require(segments >= 3, "segments", segments as f64, "at least 3")?;
    require(rings >= 2, "rings", rings as f64, "at least 2")?;
    require(
        height > 0.0 && height.is_finite(),
        "height",
        height,
        "finite and positive",
    )?;
    let positions = (0..rings)
        .flat_map(|j| {
            (0..segments).map(move |i| {
                let theta = TAU * i as f64 / segments as f64;
                let z = height * j as f64 / (rings - 1) as f64;
                [theta.cos(), theta.sin(), z]
            })
        })
        .collect();
    let faces = grid_faces(
        segments,
        rings - 1,
        |i, j| j * segments + i % segments,
        |_, _| false,
    );
    Ok(TriMesh::new(positions, faces)?)
}

/// The exact outward unit normals `(cos θ_i, sin θ_i, 0)` of the vertices of
/// [`cylinder`]`(segments, rings, _)`, in the same order.
pub fn cylinder_normals(segments: usize, rings: usize) -> Vec<[f64; 3]> {
    (0..rings)
        .flat_map(|_| {
            (0..segments).map(move |i| {
                let theta = TAU * i as f64 / segments as f64;
                [theta.cos(), theta.sin(), 0.0]
            })
        })
        .collect()
}

/// The surface of the cube `[−1, 1]³` with an `n × n` grid of squares on each side, each
/// square split into two triangles: `6n² + 2` vertices, `12n²` faces, closed, counter-clockwise
/// seen from outside. Vertices are numbered in order of first appearance, sides in the order
/// −x, +x, −y, +y, −z, +z.
pub fn subdivided_cube(n: usize) -> Result<TriMesh, GeneratorError> {
    require(n >= 1, "n", n as f64, "at least 1")?;
    let mut index: HashMap<[usize; 3], usize> = HashMap::new();
    let mut positions = Vec::with_capacity(6 * n * n + 2);
    let mut faces = Vec::with_capacity(12 * n * n);
    for axis in 0..3 {
        for outward in [false, true] {
            // (e_b, e_c) is right-handed about e_axis; swapping them faces the −axis side.
            let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
            let (u_axis, v_axis) = if outward { (b, c) } else { (c, b) };
            let mut side = vec![0; (n + 1) * (n + 1)];
            for j in 0..=n {
                for i in 0..=n {
                    let mut lattice = [0; 3];
                    lattice[axis] = if outward { n } else { 0 };
                    lattice[u_axis] = i;
                    lattice[v_axis] = j;
                    side[j * (n + 1) + i] = *index.entry(lattice).or_insert_with(|| {
                        positions.push(lattice.map(|x| 2.0 * x as f64 / n as f64 - 1.0));
                        positions.len() - 1
                    });
                }
            }
            faces.extend(grid_faces(n, n, |i, j| side[j * (n + 1) + i], |_, _| false));
        }
    }
    Ok(TriMesh::new(positions, faces)?)
}

/// A flat rectangle `[−width/2, width/2] × [−depth/2, depth/2]` in the plane `z = 0` with
/// `nx × ny` squares split into two triangles each: vertex `(i, j)` has index
/// `j · (nx + 1) + i`; `(nx + 1)(ny + 1)` vertices, `2 nx ny` faces, normal `+z`, one boundary
/// loop.
pub fn grid(nx: usize, ny: usize, width: f64, depth: f64) -> Result<TriMesh, GeneratorError> {
    require(nx >= 1, "nx", nx as f64, "at least 1")?;
    require(ny >= 1, "ny", ny as f64, "at least 1")?;
    for (name, value) in [("width", width), ("depth", depth)] {
        require(
            value > 0.0 && value.is_finite(),
            name,
            value,
            "finite and positive",
        )?;
    }
    let positions = (0..=ny)
        .flat_map(|j| {
            (0..=nx).map(move |i| {
                [
                    width * (i as f64 / nx as f64 - 0.5),
                    depth * (j as f64 / ny as f64 - 0.5),
                    0.0,
                ]
            })
        })
        .collect();
    let faces = grid_faces(nx, ny, |i, j| j * (nx + 1) + i, |_, _| false);
    Ok(TriMesh::new(positions, faces)?)
}

/// A disk-like patch of an icosphere (optionally bumpy) around `center`, with a ragged
/// boundary. Patches that differ only in `seed` share every face whose centroid lies within
/// geodesic distance `radius` of `center` and differ outside it.
///
/// Construction, on [`icosphere`]`(level)` with positions `p ↦ p (1 + b sin 4x sin 4y sin 4z)`
/// (`b = bump_amplitude`):
/// 1. face `t` is a candidate if the geodesic distance `d_t` from `center` to the direction
///    of its centroid satisfies `d_t < radius + raggedness · ξ_t`, with `ξ_t` uniform in
///    `[0, 1)` drawn from `seed`;
/// 2. the patch is the candidates edge-connected to the face nearest `center`;
/// 3. repeatedly, faces enclosed by the patch (not edge-connected to the face farthest from
///    `center` without crossing the patch) are added, and where the patch touches itself at a
///    vertex all faces around that vertex are added, until the patch is a manifold disk;
/// 4. unused vertices are removed (vertices keep their relative order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpherePatch {
    /// Subdivision level of the icosphere.
    pub level: u32,
    /// Direction of the patch centre (normalized internally).
    pub center: [f64; 3],
    /// Geodesic radius (radians) of the part every seed keeps, in `(0, π/2)`.
    pub radius: f64,
    /// Largest extra reach (radians) of the ragged band, `≥ 0`, with `radius + raggedness < π`.
    pub raggedness: f64,
    /// Radial bump amplitude `b`, `|b| < 0.5`.
    pub bump_amplitude: f64,
    /// Seed of the ragged band.
    pub seed: u64,
}

impl SpherePatch {
    /// Builds the patch.
    pub fn mesh(&self) -> Result<TriMesh, GeneratorError> {
        let c = self.center;
        let c_norm = dot(c, c).sqrt();
        require(
            c_norm > 0.0 && c_norm.is_finite(),
            "center",
            c_norm,
            "a finite non-zero vector (value: its length)",
        )?;
        let c = scale(c, 1.0 / c_norm);
        require(
            self.radius > 0.0 && self.radius < std::f64::consts::FRAC_PI_2,
            "radius",
            self.radius,
            "in (0, π/2)",
        )?;
        require(
            self.raggedness >= 0.0 && self.radius + self.raggedness < std::f64::consts::PI,
            "raggedness",
            self.raggedness,
            "≥ 0 with radius + raggedness < π",
        )?;
        require(
            self.bump_amplitude.abs() < 0.5,
            "bump_amplitude",
            self.bump_amplitude,
            "in (−0.5, 0.5)",
        )?;
        let b = self.bump_amplitude;
        let sphere = icosphere(self.level).map_positions(|p| {
            scale(
                p,
                1.0 + b * (4.0 * p[0]).sin() * (4.0 * p[1]).sin() * (4.0 * p[2]).sin(),
            )
        })?;

        // Geodesic distance of each face (centroid direction) from the centre.
        let faces = sphere.faces();
        let distance: Vec<f64> = faces
            .iter()
            .map(|f| {
                let s = f.iter().fold([0.0; 3], |acc, &v| {
                    let p = sphere.positions()[v];
                    [acc[0] + p[0], acc[1] + p[1], acc[2] + p[2]]
                });
                dot(normalize(s), c).clamp(-1.0, 1.0).acos()
            })
            .collect();
        let mut neighbours = vec![Vec::with_capacity(3); faces.len()];
        for e in sphere.edges() {
            if let Some(g) = e.opposite_face {
                neighbours[e.face].push(g);
                neighbours[g].push(e.face);
            }
        }
        let mut vertex_faces = vec![Vec::new(); sphere.vertex_count()];
        for (t, f) in faces.iter().enumerate() {
            for &v in f {
                vertex_faces[v].push(t);
            }
        }
        let nearest = argmin(&distance);
        let farthest = argmin(&distance.iter().map(|d| -d).collect::<Vec<_>>());

        let mut rng = SplitMix64::new(self.seed);
        let candidate: Vec<bool> = distance
            .iter()
            .map(|&d| d < self.radius + self.raggedness * rng.next_f64())
            .collect();
        let mut in_patch = reachable(&neighbours, nearest, |t| candidate[t]);
        loop {
            let outside = reachable(&neighbours, farthest, |t| !in_patch[t]);
            for t in 0..faces.len() {
                in_patch[t] |= !outside[t];
            }
            let patch_faces: Vec<[usize; 3]> = (0..faces.len())
                .filter(|&t| in_patch[t])
                .map(|t| faces[t])
                .collect();
            match TriMesh::with_unreferenced_removed(sphere.positions().to_vec(), patch_faces) {
                Ok((mesh, _)) => return Ok(mesh),
                Err(MeshError::NonManifoldVertex { vertex, .. }) => {
                    for &t in &vertex_faces[vertex] {
                        in_patch[t] = true;
                    }
                }
                Err(e) => return Err(e.into()),
            }
        }
    }
}

/// Index of the smallest value (the first one on ties).
fn argmin(values: &[f64]) -> usize {
    (0..values.len()).fold(0, |best, i| if values[i] < values[best] { i } else { best })
}

/// Faces reachable from `start` through neighbours that satisfy `allowed` (`start` included
/// if it does).
fn reachable(
    neighbours: &[Vec<usize>],
    start: usize,
    allowed: impl Fn(usize) -> bool,
) -> Vec<bool> {
    let mut seen = vec![false; neighbours.len()];
    let mut stack = Vec::new();
    if allowed(start) {
        seen[start] = true;
        stack.push(start);
    }
    while let Some(t) = stack.pop() {
        for &g in &neighbours[t] {
            if !seen[g] && allowed(g) {
                seen[g] = true;
                stack.push(g);
            }
        }
    }
    seen
}
