//! Dense grids made from the real Blender cache keep every active value.

use lgh_volume::{vdb, DenseGrid};

#[test]
fn densified_grids_keep_their_active_values() {
    let Some(path) = lgh_tests::fire_frame(56) else {
        return;
    };
    let file = vdb::read(&path).unwrap();
    for name in ["density", "flame", "temperature", "velocity"] {
        let g = file.grid(name).unwrap();
        let s = g.stats();
        let (lo, hi) = s.bbox.unwrap();
        let d = DenseGrid::from_vdb(g, lo, hi).unwrap();
        assert_eq!(d.dims, [0, 1, 2].map(|a| (hi[a] - lo[a] + 1) as usize));
        // Scalars: the same f32 values summed in f64 in another order, within N·ε₆₄ (< 1e-10).
        // Vectors: the dense grid holds the f64 lengths rounded to f32 (2^-24 relative each,
        // within the 2e-7 allowed) where the statistics keep f64.
        let sum: f64 = d.data.iter().map(|&v| v as f64).sum();
        let tol = if g.components() == 1 { 1e-10 } else { 2e-7 };
        assert!(
            (sum - s.sum).abs() <= tol * s.sum.abs(),
            "{name}: {sum} vs {}",
            s.sum
        );
        assert!((d.voxel_size as f64 - g.voxel_size[0]).abs() < 1e-9);
        // Voxel (lo) sits at index_to_world · lo.
        let m = g.index_to_world;
        assert!((d.origin.x as f64 - (m[0][0] * lo[0] as f64 + m[0][3])).abs() < 1e-6);
    }
}
