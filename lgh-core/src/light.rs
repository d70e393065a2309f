//! Point lights, the input set `S0` of the paper.

use glam::Vec3;

/// Rec. 709 luminance weights: `‖I‖` in the paper (eq. 2) is the luminance of an RGB intensity.
pub const LUMINANCE_WEIGHTS: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// Luminance `‖I‖` of an RGB triple (Rec. 709 weights).
#[inline]
pub fn luminance(rgb: Vec3) -> f32 {
    rgb.dot(LUMINANCE_WEIGHTS)
}

/// An input point light `j ∈ S0`: position `p0_j` and RGB radiant intensity `I0_j` (W/sr).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct PointLight {
    /// Position `p0_j`.
    pub position: Vec3,
    /// RGB radiant intensity `I0_j` in W/sr; every channel finite and ≥ 0.
    pub intensity: Vec3,
}

impl PointLight {
    /// A light at `position` with RGB intensity `intensity`.
    pub const fn new(position: Vec3, intensity: Vec3) -> Self {
        PointLight {
            position,
            intensity,
        }
    }
}

/// A light of the hierarchy: a level-ℓ light `i ∈ S_ℓ` (a grid vertex) or, at level 0, an input light.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct GridLight {
    /// Illumination centre `p_ℓi` (eq. 2); the light's position for shading.
    pub position: Vec3,
    /// Total intensity `I_ℓi = Σ_j w_ij I0_j` (eq. 1).
    pub intensity: Vec3,
    /// Per-axis variance `σ²_ℓi` of the represented light positions (eq. 4); zero at level 0.
    pub variance: Vec3,
    /// Size `s_ℓi`: the weighted mean distance of the represented lights from the centre (eq. 5).
    pub size: f32,
    /// `‖I_ℓi‖`, the luminance of `intensity` (used for weak-light pruning).
    pub luminance: f32,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn luminance_weights_sum_to_one() {
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
        assert_eq!(luminance(Vec3::ZERO), 0.0);
    }
}
