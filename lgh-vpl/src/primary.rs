//! The primary lights of a surface scene (paper Sec. 6.4, Fig. 13): what the virtual point
//! lights' paths start from. Emissive faces (MTL `Ke`) are area lights; a scene without them
//! takes lights from the command line: `point:X,Y,Z,R,G,B` (intensity, W/sr),
//! `spot:X,Y,Z,DX,DY,DZ,ANGLE,R,G,B` (intensity on its axis, a hard cone of half-angle ANGLE
//! degrees) or `sun:DX,DY,DZ,R,G,B` (irradiance, W/m², travelling along D).

use std::fmt;
use std::str::FromStr;

use lgh_core::glam::Vec3;

use crate::mesh::Mesh;

/// One primary light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PrimaryLight {
    /// An isotropic point: radiant intensity `intensity` (W/sr) in every direction.
    Point {
        /// Position.
        position: Vec3,
        /// Radiant intensity, W/sr.
        intensity: Vec3,
    },
    /// A spot: intensity `intensity` inside the cone of half-angle `acos(cos_half_angle)` about
    /// `direction`, none outside.
    Spot {
        /// Position.
        position: Vec3,
        /// Unit axis.
        direction: Vec3,
        /// Cosine of the cone's half-angle.
        cos_half_angle: f32,
        /// Radiant intensity inside the cone, W/sr.
        intensity: Vec3,
    },
    /// A distant light: irradiance `irradiance` (W/m², on a plane facing it) travelling along
    /// the unit vector `direction`.
    Sun {
        /// Unit direction of travel.
        direction: Vec3,
        /// Irradiance, W/m².
        irradiance: Vec3,
    },
    /// Triangle `triangle` of the mesh, emitting radiance `radiance` (W/(sr m²)) from its front.
    Area {
        /// The triangle.
        triangle: u32,
        /// Emitted radiance.
        radiance: Vec3,
    },
}

/// Why a light's text (`point:…`, `spot:…`, `sun:…`) could not be read: the text and the
/// reason, which a command line words with its own flag.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LightParseError {
    light: String,
    reason: String,
}

impl LightParseError {
    /// The text that could not be read.
    ///
    /// ```
    /// use lgh_vpl::primary::PrimaryLight;
    /// let e = "lamp:1,2,3".parse::<PrimaryLight>().unwrap_err();
    /// assert_eq!(e.light(), "lamp:1,2,3");
    /// ```
    #[must_use]
    pub fn light(&self) -> &str {
        &self.light
    }

    /// Why, with the form expected.
    ///
    /// ```
    /// use lgh_vpl::primary::PrimaryLight;
    /// let e = "point:0,1".parse::<PrimaryLight>().unwrap_err();
    /// assert_eq!(e.reason(), "2 numbers, not 6 (expected point:X,Y,Z,R,G,B)");
    /// ```
    #[must_use]
    pub fn reason(&self) -> &str {
        &self.reason
    }
}

impl fmt::Display for LightParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "primary light {}: {}", self.light, self.reason)
    }
}

impl std::error::Error for LightParseError {}

impl FromStr for PrimaryLight {
    type Err = LightParseError;

    /// ```
    /// use lgh_core::glam::Vec3;
    /// use lgh_vpl::primary::PrimaryLight;
    ///
    /// let p: PrimaryLight = "point:0,5,0,10,10,8".parse()?;
    /// assert_eq!(p, PrimaryLight::Point { position: Vec3::new(0.0, 5.0, 0.0), intensity: Vec3::new(10.0, 10.0, 8.0) });
    /// let sun: PrimaryLight = "sun:0,-2,0,3,3,3".parse()?;
    /// assert!(matches!(sun, PrimaryLight::Sun { direction, .. } if direction == Vec3::NEG_Y));
    /// assert!("spot:0,5,0,0,-1,0,30,1,1,1".parse::<PrimaryLight>().is_ok());
    /// let e = "point:0,5,0".parse::<PrimaryLight>().unwrap_err();
    /// assert!(e.to_string().contains("point:X,Y,Z,R,G,B"), "{e}");
    /// # Ok::<(), lgh_vpl::primary::LightParseError>(())
    /// ```
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (kind, rest) = s.split_once(':').unwrap_or((s, ""));
        let (form, n) = match kind {
            "point" => ("point:X,Y,Z,R,G,B", 6),
            "spot" => ("spot:X,Y,Z,DX,DY,DZ,ANGLE,R,G,B", 10),
            "sun" => ("sun:DX,DY,DZ,R,G,B", 6),
            _ => {
                return Err(LightParseError {
                    light: s.to_owned(),
                    reason: "expected point:…, spot:… or sun:…".to_owned(),
                })
            }
        };
        let bad = |why: &str| LightParseError {
            light: s.to_owned(),
            reason: format!("{why} (expected {form})"),
        };
        let v: Vec<f32> = rest
            .split(',')
            .map(|x| x.trim().parse::<f32>())
            .collect::<Result<_, _>>()
            .map_err(|_| bad("not numbers"))?;
        if v.len() != n {
            return Err(bad(&format!("{} numbers, not {n}", v.len())));
        }
        if v.iter().any(|x| !x.is_finite()) {
            return Err(bad("a number is not finite"));
        }
        let colour = Vec3::new(v[n - 3], v[n - 2], v[n - 1]);
        if colour.min_element() < 0.0 || colour == Vec3::ZERO {
            return Err(bad("the colour must be non-negative and not black"));
        }
        let unit = |d: Vec3| {
            d.try_normalize()
                .ok_or_else(|| bad("the direction must not be zero"))
        };
        Ok(match kind {
            "point" => PrimaryLight::Point {
                position: Vec3::new(v[0], v[1], v[2]),
                intensity: colour,
            },
            "spot" => {
                if !(v[6] > 0.0 && v[6] <= 180.0) {
                    return Err(bad("the angle must be in (0, 180] degrees"));
                }
                PrimaryLight::Spot {
                    position: Vec3::new(v[0], v[1], v[2]),
                    direction: unit(Vec3::new(v[3], v[4], v[5]))?,
                    cos_half_angle: v[6].to_radians().cos(),
                    intensity: colour,
                }
            }
            _ => PrimaryLight::Sun {
                direction: unit(Vec3::new(v[0], v[1], v[2]))?,
                irradiance: colour,
            },
        })
    }
}

impl PrimaryLight {
    /// Total emitted power Φ (W) into a scene whose bounding sphere has radius `scene_radius`:
    /// `4π I` for a point, `2π (1 − cos θ) I` for a spot, `π R² E` for the sun (what crosses
    /// the scene's disc), `π A L_e` for an area light of area `A` (a Lambertian emitter).
    #[must_use]
    pub fn power(&self, mesh: &Mesh, scene_radius: f32) -> Vec3 {
        use std::f32::consts::PI;
        match *self {
            PrimaryLight::Point { intensity, .. } => 4.0 * PI * intensity,
            PrimaryLight::Spot {
                cos_half_angle,
                intensity,
                ..
            } => 2.0 * PI * (1.0 - cos_half_angle) * intensity,
            PrimaryLight::Sun { irradiance, .. } => PI * scene_radius * scene_radius * irradiance,
            PrimaryLight::Area { triangle, radiance } => PI * mesh.area(triangle) * radiance,
        }
    }
}

/// The area lights of `mesh`: one per triangle with a non-zero emission.
#[must_use]
pub fn area_lights(mesh: &Mesh) -> Vec<PrimaryLight> {
    (0..mesh.triangles().len() as u32)
        .filter_map(|t| {
            let radiance = mesh.emission(t);
            (radiance != Vec3::ZERO).then_some(PrimaryLight::Area {
                triangle: t,
                radiance,
            })
        })
        .collect()
}
