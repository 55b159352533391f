//! Isotropic linear elastic material, small strain.
//!
//! Voigt order is xx yy zz yz xz xy, with engineering shear strains
//! γ_yz = 2ε_yz, …, so that σ = C ε with
//!
//! ```text
//!     ⎡λ+2μ  λ    λ   0 0 0⎤
//!     ⎢ λ   λ+2μ  λ   0 0 0⎥        λ = E ν / ((1+ν)(1−2ν))
//! C = ⎢ λ    λ   λ+2μ 0 0 0⎥        μ = E / (2(1+ν))
//!     ⎢ 0    0    0   μ 0 0⎥
//!     ⎢ 0    0    0   0 μ 0⎥
//!     ⎣ 0    0    0   0 0 μ⎦
//! ```

/// The largest Poisson's ratio: λ/μ = 2ν/(1−2ν) ≤ 5·10⁴. Beyond it these
/// displacement-based elements lock (the volumetric part of K dominates the
/// rest by more than the solvers resolve) and K is singular to round-off.
pub const MAX_POISSON: f64 = 0.49999;

/// The smallest and largest Young's modulus: E and 1/E within
/// [`seam::MAX_MAGNITUDE`], so that stiffness, stresses and displacements stay
/// far from overflow.
pub const YOUNG_RANGE: (f64, f64) = (1e-50, seam::MAX_MAGNITUDE);

/// Why a material is rejected.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum MaterialError {
    /// Young's modulus is not a positive number.
    #[error("Young's modulus E = {0:?} must be positive")]
    Young(f64),
    /// Young's modulus is outside [`YOUNG_RANGE`].
    #[error("Young's modulus E = {0:e} is out of range: seam computes with {lo:e} ≤ E ≤ {hi:e} (in any consistent units)", lo = YOUNG_RANGE.0, hi = YOUNG_RANGE.1)]
    YoungOutOfRange(f64),
    /// Poisson's ratio is outside (−1, 0.5).
    #[error("Poisson's ratio ν = {0:?} must lie in (-1, 0.5)")]
    Poisson(f64),
    /// Poisson's ratio is above [`MAX_POISSON`].
    #[error("Poisson's ratio ν = {0:?} is too close to 0.5 (volumetric locking): with these displacement-based elements the stiffness is singular to round-off; use ν ≤ {MAX_POISSON}")]
    Locking(f64),
}

/// An isotropic linear elastic material: Young's modulus E and Poisson's ratio ν.
///
/// Valid by construction: 0 < E < ∞ and −1 < ν < ½ (C is then positive definite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    young: f64,
    poisson: f64,
}

impl Material {
    /// A material after checking 0 < E, E within [`YOUNG_RANGE`],
    /// −1 < ν < ½ and ν ≤ [`MAX_POISSON`].
    ///
    /// # Errors
    /// [`MaterialError`] naming the offending value (NaN included).
    pub fn new(young: f64, poisson: f64) -> Result<Material, MaterialError> {
        if young.is_nan() || young <= 0.0 {
            return Err(MaterialError::Young(young));
        }
        if !(YOUNG_RANGE.0..=YOUNG_RANGE.1).contains(&young) {
            return Err(MaterialError::YoungOutOfRange(young));
        }
        if !(poisson > -1.0 && poisson < 0.5) {
            return Err(MaterialError::Poisson(poisson));
        }
        if poisson > MAX_POISSON {
            return Err(MaterialError::Locking(poisson));
        }
        Ok(Material { young, poisson })
    }

    /// Young's modulus E.
    pub fn young(&self) -> f64 {
        self.young
    }

    /// Poisson's ratio ν.
    pub fn poisson(&self) -> f64 {
        self.poisson
    }

    /// The Lamé parameters (λ, μ) = (Eν/((1+ν)(1−2ν)), E/(2(1+ν))).
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        (e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu)))
    }

    /// The 6×6 elasticity matrix C in Voigt order xx yy zz yz xz xy (module doc).
    pub fn c(&self) -> [[f64; 6]; 6] {
        let (l, m) = self.lame();
        let mut c = [[0.0; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = l;
            }
            c[i][i] = l + 2.0 * m;
            c[i + 3][i + 3] = m;
        }
        c
    }

    /// σ = C ε for a Voigt strain (engineering shears):
    /// σ_ii = λ tr ε + 2μ ε_ii, τ = μ γ.
    pub fn stress(&self, strain: [f64; 6]) -> [f64; 6] {
        let (l, m) = self.lame();
        let tr = strain[0] + strain[1] + strain[2];
        [
            l * tr + 2.0 * m * strain[0],
            l * tr + 2.0 * m * strain[1],
            l * tr + 2.0 * m * strain[2],
            m * strain[3],
            m * strain[4],
            m * strain[5],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lame_and_c() {
        let m = Material::new(210e9, 0.3).unwrap();
        let (l, mu) = m.lame();
        assert!((l - 121.153_846_153_846_15e9).abs() < 1e-3);
        assert!((mu - 80.769_230_769_230_77e9).abs() < 1e-3);
        let c = m.c();
        assert_eq!(c[0][1], l);
        assert_eq!(c[3][3], mu);
        assert_eq!(c[0][3], 0.0);
        // Uniaxial stress: ε = (1, −ν, −ν, 0, 0, 0)/E gives σ = (1, 0, 0, …).
        let e = 1.0 / 210e9;
        let s = m.stress([e, -0.3 * e, -0.3 * e, 0.0, 0.0, 0.0]);
        assert!((s[0] - 1.0).abs() < 1e-12 && s[1].abs() < 1e-12 && s[2].abs() < 1e-12);
        // stress() is C·ε.
        let eps = [0.1, -0.2, 0.3, 0.05, -0.07, 0.02];
        let s = Material::new(2.0, 0.25).unwrap();
        let (sigma, c) = (s.stress(eps), s.c());
        for i in 0..6 {
            let ce: f64 = (0..6).map(|j| c[i][j] * eps[j]).sum();
            assert!((ce - sigma[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn invalid_values_are_named() {
        assert_eq!(Material::new(0.0, 0.3), Err(MaterialError::Young(0.0)));
        assert_eq!(Material::new(-1.0, 0.3), Err(MaterialError::Young(-1.0)));
        assert!(matches!(Material::new(f64::NAN, 0.3), Err(MaterialError::Young(_))));
        assert_eq!(Material::new(1.0, 0.5), Err(MaterialError::Poisson(0.5)));
        assert_eq!(Material::new(1.0, -1.0), Err(MaterialError::Poisson(-1.0)));
        assert!(matches!(Material::new(1.0, f64::NAN), Err(MaterialError::Poisson(_))));
        assert_eq!(
            Material::new(1.0, 0.7).unwrap_err().to_string(),
            "Poisson's ratio ν = 0.7 must lie in (-1, 0.5)"
        );
        assert!(Material::new(1.0, -0.99).is_ok());
        // The ranges of the case checks: out of range and locking are their own errors.
        assert_eq!(Material::new(1e308, 0.3), Err(MaterialError::YoungOutOfRange(1e308)));
        assert_eq!(Material::new(f64::INFINITY, 0.3), Err(MaterialError::YoungOutOfRange(f64::INFINITY)));
        assert_eq!(Material::new(1e-300, 0.3), Err(MaterialError::YoungOutOfRange(1e-300)));
        assert!(Material::new(1e50, 0.3).is_ok() && Material::new(1e-50, 0.3).is_ok());
        assert_eq!(
            Material::new(1e308, 0.3).unwrap_err().to_string(),
            "Young's modulus E = 1e308 is out of range: seam computes with 1e-50 ≤ E ≤ 1e50 (in any consistent units)"
        );
        assert_eq!(Material::new(1.0, 0.4999999999), Err(MaterialError::Locking(0.4999999999)));
        assert!(Material::new(1.0, 0.4999999999).unwrap_err().to_string().starts_with(
            "Poisson's ratio ν = 0.4999999999 is too close to 0.5 (volumetric locking): with these \
             displacement-based elements the stiffness is singular to round-off; use ν ≤ 0.49999"
        ));
        assert!(Material::new(1.0, MAX_POISSON).is_ok());
    }
}
