//! Topology of a validated mesh: boundary loops, connected components, Euler characteristic
//! and genus.

use crate::TriMesh;
use crate::disjoint_sets::DisjointSets;

/// Counts and invariants of one connected component (faces connected through shared edges).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Component {
    /// Number of vertices.
    pub vertices: usize,
    /// Number of edges.
    pub edges: usize,
    /// Number of faces.
    pub faces: usize,
    /// Number of boundary loops `b`.
    pub boundary_loops: usize,
    /// Euler characteristic `χ = V − E + F`.
    pub euler_characteristic: i64,
    /// Genus `g = (2 − χ − b) / 2` of the oriented surface with `b` boundary loops
    /// (`χ = 2 − 2g − b`; for a closed component `g = (2 − χ) / 2`).
    pub genus: usize,
}

/// The topology of a whole mesh, from [`TriMesh::topology`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topology {
    /// Number of vertices `V`.
    pub vertices: usize,
    /// Number of edges `E`.
    pub edges: usize,
    /// Number of faces `F`.
    pub faces: usize,
    /// Euler characteristic `χ = V − E + F` of the whole mesh (the sum over components).
    pub euler_characteristic: i64,
    /// Each boundary loop as its cycle of vertices, in the direction the faces traverse the
    /// boundary edges (the surface on the left); the loop's last vertex connects to its first.
    pub boundary_loops: Vec<Vec<usize>>,
    /// The connected components, ordered by their smallest face index.
    pub components: Vec<Component>,
}

impl Topology {
    /// Whether the mesh has no boundary.
    pub fn is_closed(&self) -> bool {
        self.boundary_loops.is_empty()
    }

    /// Total genus, the sum of the components' genera.
    pub fn genus(&self) -> usize {
        self.components.iter().map(|c| c.genus).sum()
    }
}

impl TriMesh {
    /// Boundary loops, components, Euler characteristic and genus (see [`Topology`]).
    pub fn topology(&self) -> Topology {
        let edges = self.edges();

        // Components: faces joined across interior edges.
        let mut sets = DisjointSets::new(self.face_count());
        for e in &edges {
            if let Some(g) = e.opposite_face {
                sets.union(e.face, g);
            }
        }
        let mut component_of_root = vec![usize::MAX; self.face_count()];
        let mut face_component = vec![0; self.face_count()];
        let mut components = Vec::new();
        for t in 0..self.face_count() {
            let root = sets.find(t);
            if component_of_root[root] == usize::MAX {
                component_of_root[root] = components.len();
                components.push(Component {
                    vertices: 0,
                    edges: 0,
                    faces: 0,
                    boundary_loops: 0,
                    euler_characteristic: 0,
                    genus: 0,
                });
            }
            face_component[t] = component_of_root[root];
            components[face_component[t]].faces += 1;
        }
        // Every vertex is used by a face, and all its faces lie in one component.
        let mut vertex_component = vec![0; self.vertex_count()];
        for (t, f) in self.faces().iter().enumerate() {
            for &v in f {
                vertex_component[v] = face_component[t];
            }
        }
        for &c in &vertex_component {
            components[c].vertices += 1;
        }
        for e in &edges {
            components[face_component[e.face]].edges += 1;
        }

        // Boundary loops: on a vertex-manifold mesh each boundary vertex has exactly one
        // outgoing boundary edge.
        let boundary = self.boundary_edges();
        let mut next = vec![None; self.vertex_count()];
        for &[a, b] in &boundary {
            next[a] = Some(b);
        }
        let mut boundary_loops = Vec::new();
        for &[start, _] in &boundary {
            let mut cycle = Vec::new();
            let mut v = start;
            while let Some(w) = next[v].take() {
                cycle.push(v);
                v = w;
            }
            if !cycle.is_empty() {
                components[vertex_component[start]].boundary_loops += 1;
                boundary_loops.push(cycle);
            }
        }

        for c in &mut components {
            c.euler_characteristic = c.vertices as i64 - c.edges as i64 + c.faces as i64;
            c.genus = ((2 - c.euler_characteristic - c.boundary_loops as i64) / 2) as usize;
        }
        Topology {
            vertices: self.vertex_count(),
            edges: edges.len(),
            faces: self.face_count(),
            euler_characteristic: self.vertex_count() as i64 - edges.len() as i64
                + self.face_count() as i64,
            boundary_loops,
            components,
        }
    }
}
