//! The paper's flickering variants (Secs. 3.1, 3.2, Fig. 9), options of the build and of the
//! blending so that their flicker can be measured one flag away from the paper's method
//! (`lgh bench flicker`): each does what it says, and the defaults are the paper's.

use lgh_core::glam::Vec3;
use lgh_core::{Clustering, GridSettings, LightPosition, LightingGridHierarchy, PointLight};
use wasm_bindgen_test::wasm_bindgen_test;

// In a browser (wasm32), see docs/embedding.md.
wasm_bindgen_test::wasm_bindgen_test_configure!(run_in_browser);

/// One light at `(0.3, 0.7, 0.2)` of a unit level-1 cell whose corner is the origin.
fn one_light(settings: GridSettings) -> LightingGridHierarchy {
    let lights = [PointLight::new(
        Vec3::new(0.3, 0.7, 0.2),
        Vec3::new(1.0, 2.0, 3.0),
    )];
    let settings = GridSettings {
        h1: Some(1.0),
        origin: Some(Vec3::ZERO),
        max_level: Some(2),
        ..settings
    };
    LightingGridHierarchy::build(&lights, &settings).unwrap()
}

#[wasm_bindgen_test(unsupported = test)]
fn the_default_is_the_papers_trilinear_splat_at_illumination_centres() {
    let d = GridSettings::default();
    assert_eq!(d.clustering, Clustering::Trilinear);
    assert_eq!(d.position, LightPosition::IlluminationCentre);
    let h = one_light(GridSettings::default());
    let level = h.level(1);
    // Eight vertices share the light, each at the light's own position (its illumination
    // centre), with its trilinear weight.
    assert_eq!(level.len(), 8);
    for i in 0..8 {
        assert!((level.position(i) - Vec3::new(0.3, 0.7, 0.2)).length() < 1e-6);
    }
    let w = |i: usize| level.intensity(i).x;
    let total: f32 = (0..8).map(w).sum();
    assert!((total - 1.0).abs() < 1e-6);
    assert!((0..8).all(|i| w(i) > 0.0 && w(i) < 0.5));
}

#[wasm_bindgen_test(unsupported = test)]
fn nearest_vertex_clustering_gives_each_light_whole_to_one_vertex() {
    let h = one_light(GridSettings {
        clustering: Clustering::NearestVertex,
        ..Default::default()
    });
    let level = h.level(1);
    let lit: Vec<usize> = (0..level.len())
        .filter(|&i| level.intensity(i) != Vec3::ZERO)
        .collect();
    assert_eq!(lit.len(), 1);
    assert_eq!(level.intensity(lit[0]), Vec3::new(1.0, 2.0, 3.0));
    // The nearest corner of (0.3, 0.7, 0.2) is (0, 1, 0).
    let v = h.vertex(1, lit[0] as u32).unwrap();
    let o = h.vertex(1, 0).unwrap(); // vertex 0 is the cell's corner (0, 0, 0)
    assert_eq!([v[0] - o[0], v[1] - o[1], v[2] - o[2]], [0, 1, 0]);
    assert!((level.position(lit[0]) - Vec3::new(0.3, 0.7, 0.2)).length() < 1e-6);
}

#[wasm_bindgen_test(unsupported = test)]
fn grid_vertex_positions_put_coarse_lights_on_their_vertices() {
    let h = one_light(GridSettings {
        position: LightPosition::GridVertex,
        ..Default::default()
    });
    for l in 1..=2 {
        let level = h.level(l);
        let spacing = h.h(l);
        for i in 0..level.len() {
            let p = level.position(i) / spacing;
            assert_eq!(
                p,
                p.round(),
                "level {l} light {i} at {p} (cells) is off its vertex"
            );
        }

        // The intensities are the paper's (only the positions move).
        let paper = one_light(GridSettings::default());
        for i in 0..level.len() {
            assert_eq!(level.intensity(i), paper.level(l).intensity(i));
        }
    }
    // Level 0 is the input lights whatever the variant.
    assert_eq!(h.level(0).position(0), Vec3::new(0.3, 0.7, 0.2));
}
