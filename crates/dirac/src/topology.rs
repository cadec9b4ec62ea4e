//! Topology of a validated mesh: boundary loops, connected components, Euler characteristic
//! and genus; selecting components ([`TriMesh::select_component`]).

use std::fmt;
use std::str::FromStr;

use qsparse::DisjointSets;
use thiserror::Error;

use crate::mesh::boundary_of;
use crate::{Edge, TriMesh};

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

/// The component of every face (faces joined across interior edges), numbered by smallest
/// face, and the number of components.
fn face_components(face_count: usize, edges: &[Edge]) -> (Vec<usize>, usize) {
    let mut sets = DisjointSets::new(face_count);
    for e in edges {
        if let Some(g) = e.opposite_face {
            sets.union(e.face, g);
        }
    }
    let mut component_of_root = vec![usize::MAX; face_count];
    let mut face_component = vec![0; face_count];
    let mut count = 0;
    for t in 0..face_count {
        let root = sets.find(t);
        if component_of_root[root] == usize::MAX {
            component_of_root[root] = count;
            count += 1;
        }
        face_component[t] = component_of_root[root];
    }
    (face_component, count)
}

/// Which connected components [`TriMesh::select_component`] keeps. Parses from and prints as
/// `all`, `largest` or a component index (`0`, `1`, …).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ComponentSelection {
    /// The whole mesh.
    #[default]
    All,
    /// The component with the most faces (ties: the one with the smaller index).
    Largest,
    /// The component of this index, in the order of [`Topology::components`] (by smallest face
    /// index).
    Index(usize),
}

impl fmt::Display for ComponentSelection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::All => f.write_str("all"),
            Self::Largest => f.write_str("largest"),
            Self::Index(i) => write!(f, "{i}"),
        }
    }
}

impl FromStr for ComponentSelection {
    type Err = ComponentSelectionParseError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text {
            "all" => Ok(Self::All),
            "largest" => Ok(Self::Largest),
            _ => text
                .parse()
                .map(Self::Index)
                .map_err(|_| ComponentSelectionParseError(text.to_string())),
        }
    }
}

/// A text that is not `all`, `largest` or a component index.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error(
    "`{0}` is not a component selection: expected `all`, `largest` or a component index (0, 1, …)"
)]
pub struct ComponentSelectionParseError(pub String);

/// Why [`TriMesh::select_component`] failed.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum ComponentError {
    /// The index names no component.
    #[error(
        "component {index} does not exist: the mesh has {count} connected component{} \
         (indices 0 to {}); use `largest` or `all`",
        if *count == 1 { "" } else { "s" },
        count.saturating_sub(1)
    )]
    OutOfRange {
        /// The index asked for.
        index: usize,
        /// Number of components (at least 1: a mesh has a face).
        count: usize,
    },
}

impl TriMesh {
    /// The connected components chosen by `selection` as a mesh of their own, with, for each of
    /// its vertices, the index of that vertex in `self` (`vertex_origin`). Faces and vertices
    /// keep their relative order; [`ComponentSelection::All`] returns a copy of the mesh and
    /// the identity. Components are those of [`TriMesh::topology`].
    pub fn select_component(
        &self,
        selection: ComponentSelection,
    ) -> Result<(TriMesh, Vec<usize>), ComponentError> {
        // `None`: the largest component.
        let index = match selection {
            ComponentSelection::All => {
                return Ok((self.clone(), (0..self.vertex_count()).collect()));
            }
            ComponentSelection::Index(index) => Some(index),
            ComponentSelection::Largest => None,
        };
        let (face_component, count) = face_components(self.face_count(), &self.edges());
        let chosen = match index {
            Some(index) if index >= count => {
                return Err(ComponentError::OutOfRange { index, count });
            }
            Some(index) => index,
            None => {
                let mut sizes = vec![0usize; count];
                for &c in &face_component {
                    sizes[c] += 1;
                }
                // The first maximum: ties go to the smaller index.
                (0..count).fold(0, |best, c| if sizes[c] > sizes[best] { c } else { best })
            }
        };
        let keep: Vec<bool> = face_component.iter().map(|&c| c == chosen).collect();
        Ok(self.with_components_of(&keep))
    }

    /// Boundary loops, components, Euler characteristic and genus (see [`Topology`]).
    pub fn topology(&self) -> Topology {
        let edges = self.edges();
        let (face_component, count) = face_components(self.face_count(), &edges);
        let empty = Component {
            vertices: 0,
            edges: 0,
            faces: 0,
            boundary_loops: 0,
            euler_characteristic: 0,
            genus: 0,
        };
        let mut components = vec![empty; count];
        for &c in &face_component {
            components[c].faces += 1;
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
        // outgoing boundary edge. Taken from the edges at hand: finding them again (a sort of
        // all 3|F| edge uses) would double the cost of this function.
        let boundary = boundary_of(&edges);
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
