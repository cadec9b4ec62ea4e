//! Experiment (paper Fig. 3): the relative Dirac operator `D_{f1,f2}` of a surface `f1` and a
//! deformed copy `f2` with the same triangulation. Where `f2` is contracted by a factor `s`
//! relative to `f1`, `D_{f1,f2} ≈ s D_{f1}` locally, so the eigenvalues of smallest `|λ|`
//! belong to functions that live there: the eigenfunctions point at where the two surfaces
//! differ. The measure is the *concentration* of a mode in the deformed region `R`, its mass
//! `Σ_{p∈R} Ā_p |φ_p|²` (of 1) against the region's share of the area — 1 for a mode that
//! ignores the region, larger when the mode lives there.

use dirac::geometry::{barycentric_masses, norm, sub};
use dirac::spectrum::{Operator, Spectrum, SpectrumOptions, relative_spectrum, spectrum};
use dirac::{MeshError, TriMesh};

use crate::ExperimentError;

/// A contraction of the surface towards a point: `f2 = c + (f1 − c)(1 − a w(|f1 − c|/r))`
/// with the plateau `w(t) = 1` for `t ≤ ½`, `w = (1 − u²)²`, `u = 2t − 1`, for `½ < t < 1` and
/// 0 outside, so `f2 = f1` outside the ball of radius `r` around `c` and the ball of radius
/// `r/2` is scaled by `1 − a` (there `D_{f1,f2} = (1 − a) D_{f1}`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contraction {
    /// The centre `c`.
    pub center: [f64; 3],
    /// The radius `r` of the deformed region.
    pub radius: f64,
    /// The amount `a ∈ [0, 1)`.
    pub amount: f64,
}

impl Contraction {
    /// The weight `w(|p − c|/r)` at `p`: 1 within half the radius, 0 from the radius on.
    pub fn weight(&self, p: [f64; 3]) -> f64 {
        let t = norm(sub(p, self.center)) / self.radius;
        let u = (2.0 * t - 1.0).max(0.0);
        if u < 1.0 { (1.0 - u * u).powi(2) } else { 0.0 }
    }

    /// The deformed copy of `mesh` (same triangulation).
    pub fn apply(&self, mesh: &TriMesh) -> Result<TriMesh, MeshError> {
        mesh.map_positions(|p| {
            let w = self.weight(p);
            if w == 0.0 {
                // Exactly `f1` outside, not `c + (f1 − c)` rounded.
                return p;
            }
            let s = 1.0 - self.amount * w;
            let d = sub(p, self.center);
            [
                self.center[0] + s * d[0],
                self.center[1] + s * d[1],
                self.center[2] + s * d[2],
            ]
        })
    }

    /// Whether vertex position `p` is in the deformed region (`|p − c| < r`).
    pub fn contains(&self, p: [f64; 3]) -> bool {
        self.weight(p) > 0.0
    }
}

/// Each mode's concentration in the region of `contraction`: `Σ_{p∈R} Ā_p |φ_p|²` over the
/// region's share of the total mass (eigenvectors have unit mass norm).
pub fn concentrations(mesh: &TriMesh, contraction: &Contraction, spectrum: &Spectrum) -> Vec<f64> {
    let masses = barycentric_masses(mesh);
    let inside: Vec<bool> = mesh
        .positions()
        .iter()
        .map(|&p| contraction.contains(p))
        .collect();
    let share = masses
        .iter()
        .zip(&inside)
        .filter(|(_, i)| **i)
        .map(|(m, _)| m)
        .sum::<f64>()
        / masses.iter().sum::<f64>();
    spectrum
        .eigenvectors
        .iter()
        .map(|phi| {
            let mass: f64 = (phi.iter().zip(&masses).zip(&inside))
                .filter(|(_, i)| **i)
                .map(|((q, m), _)| m * q.norm_sqr())
                .sum();
            mass / share
        })
        .collect()
}

/// The spectra of `D_{f1,f2}` (`f2` the contracted copy) and, for comparison, of
/// `D_{f1,f1} = D_f`, `k` pairs each.
pub struct TwoSurfaces {
    /// The deformed copy `f2`.
    pub deformed: TriMesh,
    /// Spectrum of `D_{f1,f2}`.
    pub relative: Spectrum,
    /// Spectrum of the extrinsic Dirac operator `D_{f1}`.
    pub extrinsic: Spectrum,
}

/// Solves both operators on `mesh` and its contraction.
pub fn run(
    mesh: &TriMesh,
    contraction: &Contraction,
    k: usize,
) -> Result<TwoSurfaces, ExperimentError> {
    let deformed = contraction.apply(mesh)?;
    let fail = |operator| {
        move |source| ExperimentError::Spectrum {
            operator,
            mesh: 0,
            source,
        }
    };
    let relative = relative_spectrum(
        mesh,
        &deformed,
        &SpectrumOptions::new(Operator::RelativeDirac, k),
    )
    .map_err(fail(Operator::RelativeDirac))?;
    let extrinsic = spectrum(mesh, &SpectrumOptions::new(Operator::ExtrinsicDirac, k))
        .map_err(fail(Operator::ExtrinsicDirac))?;
    Ok(TwoSurfaces {
        deformed,
        relative,
        extrinsic,
    })
}
