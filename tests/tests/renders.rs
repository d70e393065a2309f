//! Determinism of whole renders across thread counts, through every crate: a volume render
//! (lgh-volume's ray marcher with ray-marched shadows through lgh-core's hierarchy, with and
//! without the multiple-scattering pass, and the path tracer) and a surface render (lgh-vpl
//! over the light octree and the hierarchy) give the same
//! pixels, bit for bit, on 1, 2 and 3 rayon threads. The paper's cure for flicker is a renderer
//! whose output depends only on its input; a farm splits frames over machines with different
//! core counts, so this is the property it relies on.

use lgh_core::glam::Vec3;
use lgh_core::octree::{LightOctree, OctreeBackend};
use lgh_core::{LghBackend, LightingGridHierarchy, ManyLights};
use lgh_image::Image;
use lgh_tests::{image_bits, on};
use lgh_volume::pathtrace::{self, PathSettings};
use lgh_volume::render::{Camera, Framing, MarchSettings};
use lgh_volume::{procedural, ExplosionLights, FrameRender, Medium, Method, Shadows};
use lgh_vpl::paquette::{self, Surface, TestScene};

/// `render` on 1, 2 and 3 threads: the same bits every time, and not a black image.
fn same_on_any_thread_count(what: &str, render: impl Fn() -> Image + Sync) {
    let reference = on(1, &render);
    assert!(
        reference.pixels.iter().any(|p| p.max_element() > 0.0),
        "{what}: the test needs light in the image"
    );
    for threads in [2, 3] {
        assert!(
            image_bits(&on(threads, &render)) == image_bits(&reference),
            "{what}: pixels differ on {threads} threads"
        );
    }
}

#[test]
fn volume_renders_are_bit_identical_on_any_thread_count() {
    let volume = procedural(40, 0.5).unwrap();
    let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
    let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
    let (lo, hi) = volume.active_bounds().unwrap();
    let camera = Camera::frame(lo, hi, 24, 16).unwrap();
    let march = MarchSettings::default();
    for method in [Method::Lgh { alpha: 2.0 }, Method::Brute] {
        same_on_any_thread_count(&format!("ray marcher, {method:?}"), || {
            FrameRender::new(&lights, method, &volume, &medium, &march, &())
                .and_then(|f| f.render(&camera, &()))
                .unwrap()
                .0
        });
    }
    let settings = PathSettings {
        spp: 4,
        ..Default::default()
    };
    same_on_any_thread_count("path tracer", || {
        pathtrace::render(&volume, &medium, &camera, &settings, &|_| {}).unwrap()
    });
}

#[test]
fn multiple_scattering_is_bit_identical_on_any_thread_count() {
    // The scattering pass (fluence at every voxel with smoke in chunks of 1024 voxels: three
    // chunks here, shared out differently on each pool; cube maps per depth) and the render
    // with its merged lights. (With ray-marched shadows, or brute force, the pass takes this
    // test past its time; what could depend on the pool — the chunks, the cube maps' batches,
    // the pixel loop — is the same code.)
    let volume = procedural(32, 0.5).unwrap();
    let medium = Medium::new(1.0, 9.0, 1e-4, 1000.0).unwrap();
    let emission = ExplosionLights::new(&[&volume], &medium).unwrap();
    let (lo, hi) = volume.active_bounds().unwrap();
    let camera = Camera::frame(lo, hi, 16, 10).unwrap();
    let march = MarchSettings {
        shadows: Shadows::CubeMap,
        scatter_depth: 1,
        ..Default::default()
    };
    same_on_any_thread_count("scattering", || {
        let lgh = Method::Lgh { alpha: 2.0 };
        let frame = FrameRender::new(&emission, lgh, &volume, &medium, &march, &()).unwrap();
        let (mut image, _) = frame.render(&camera, &()).unwrap();
        // The merged lights' intensities too, as more pixels.
        image
            .pixels
            .extend(frame.lights().lights().iter().map(|l| l.intensity));
        image
    });
}

#[test]
fn surface_renders_are_bit_identical_on_any_thread_count() {
    let built = paquette::build(TestScene::Udem, 256, Surface::Specular, 32, 24).unwrap();
    let hierarchy = LightingGridHierarchy::build(&built.lights, &Default::default()).unwrap();
    let octree = LightOctree::build(&built.lights, &Default::default()).unwrap();
    let lgh = LghBackend::new(&hierarchy, 2.0).unwrap();
    let tree = OctreeBackend::new(&octree, paquette::PAPER_THRESHOLD).unwrap();
    same_on_any_thread_count("surface, lgh", || surface(&built, &lgh));
    same_on_any_thread_count("surface, octree", || surface(&built, &tree));
}

/// The test scene rendered through `backend`.
fn surface<B: ManyLights + Sync>(built: &paquette::Built, backend: &B) -> Image {
    lgh_vpl::render(&built.scene, &built.camera, backend, |_| {})
        .unwrap()
        .image
}

#[test]
fn a_volume_render_does_not_depend_on_pixel_order() {
    // The same pixels rendered as a list (another rayon split) equal the full image's.
    let volume = procedural(32, 0.5).unwrap();
    let medium = Medium::new(2.0, 6.0, 1e-4, 1000.0).unwrap();
    let lights = ExplosionLights::new(&[&volume], &medium).unwrap();
    let camera = Camera::frame(Vec3::splat(-1.0), Vec3::splat(1.0), 12, 8).unwrap();
    let march = MarchSettings::default();
    let lgh = Method::Lgh { alpha: 2.0 };
    let frame = FrameRender::new(&lights, lgh, &volume, &medium, &march, &()).unwrap();
    let (image, _) = frame.render(&camera, &()).unwrap();
    let pixels: Vec<[usize; 2]> = (0..8)
        .rev()
        .flat_map(|y| (0..12).map(move |x| [x, y]))
        .collect();
    let (list, _) = frame.render_pixels(&camera, &pixels).unwrap();
    for (&[x, y], p) in pixels.iter().zip(&list) {
        assert_eq!(
            p.to_array().map(f32::to_bits),
            image.pixels[y * 12 + x].to_array().map(f32::to_bits)
        );
    }
}
