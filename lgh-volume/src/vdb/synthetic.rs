//! OpenVDB files made from nothing, byte by byte, for tests and fuzz seeds: what the official
//! library cannot be asked to write (10⁹ tiles, tiles at the ends of the index space, a
//! compression it does not choose).

/// How a synthetic file stores its node values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    /// Raw (compression flags 0).
    Raw,
    /// zlib streams (`COMPRESS_ZIP`).
    Zip,
}

/// A length-prefixed string as OpenVDB writes it.
fn string(b: &mut Vec<u8>, s: &str) {
    b.extend((s.len() as u32).to_le_bytes());
    b.extend(s.as_bytes());
}

/// A float OpenVDB file (format 224) of one grid, `density`, voxel size 0.1, whose root holds the
/// active tiles `root_tiles` (4096³ voxels of 1.0 each) and declares `declared` children, of
/// which the first `written` are written, side by side along x: level-2 nodes whose 32³ slots
/// are all active tiles of 128³ voxels of 1.0. Written whole (`written == declared`) it is a
/// valid file of `written · 32768` tiles; with `written < declared` it is truncated.
///
/// ```
/// use lgh_volume::vdb::{parse, synthetic::{tiled_file, Storage}};
///
/// let file = parse(&tiled_file(Storage::Zip, &[[0, 0, -4096]], 1, 1))?;
/// let grid = &file.grids[0];
/// assert_eq!(grid.tiles.len(), 1 + 32768);
/// assert_eq!(grid.stats().active_voxels, 2 * 4096u64.pow(3));
/// # Ok::<(), lgh_volume::vdb::VdbError>(())
/// ```
#[must_use]
pub fn tiled_file(
    storage: Storage,
    root_tiles: &[[i32; 3]],
    declared: u32,
    written: u32,
) -> Vec<u8> {
    let mut b = 0x5644_4220i64.to_le_bytes().to_vec();
    b.extend(224u32.to_le_bytes());
    b.extend([10u32, 0].iter().flat_map(|v| v.to_le_bytes()));
    b.push(1); // grid offsets
    b.extend([b'0'; 36]); // UUID
    b.extend(0u32.to_le_bytes()); // no file metadata
    b.extend(1u32.to_le_bytes()); // one grid
    string(&mut b, "density");
    string(&mut b, "Tree_float_5_4_3");
    string(&mut b, "");
    let offsets = b.len();
    b.extend([0u8; 24]); // grid, block and end positions: set below
    let grid_pos = b.len() as i64;
    b.extend(u32::from(storage == Storage::Zip).to_le_bytes());
    b.extend(0u32.to_le_bytes()); // no grid metadata
    string(&mut b, "UniformScaleMap");
    b.extend([0.1f64; 6].iter().flat_map(|v| v.to_le_bytes())); // scale, voxel size
    b.extend([0u8; 72]); // inverse scales
    b.extend(1u32.to_le_bytes()); // buffers
    b.extend(0f32.to_le_bytes()); // background
    b.extend((root_tiles.len() as u32).to_le_bytes());
    b.extend(declared.to_le_bytes());
    for t in root_tiles {
        b.extend(t.iter().flat_map(|v| v.to_le_bytes()));
        b.extend(1f32.to_le_bytes());
        b.push(1); // active
    }
    let ones: Vec<u8> = (0..32768).flat_map(|_| 1f32.to_le_bytes()).collect();
    let values = match storage {
        Storage::Raw => ones,
        Storage::Zip => {
            let z = miniz_oxide::deflate::compress_to_vec_zlib(&ones, 6);
            [&(z.len() as i64).to_le_bytes()[..], &z].concat()
        }
    };
    for i in 0..written {
        b.extend([i as i32 * 4096, 0, 0].iter().flat_map(|v| v.to_le_bytes()));
        b.extend([0u8; 4096]); // no children
        b.extend([0xffu8; 4096]); // every slot an active tile
        b.push(0); // every value stored
        b.extend(&values);
    }
    let end = b.len() as i64;
    for (k, v) in [grid_pos, end, end].iter().enumerate() {
        b[offsets + 8 * k..offsets + 8 * k + 8].copy_from_slice(&v.to_le_bytes());
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vdb::{parse, VdbError};

    #[test]
    fn raw_and_zip_files_read_the_same_and_damage_is_an_error() {
        let raw = parse(&tiled_file(Storage::Raw, &[], 2, 2)).unwrap();
        let zip = parse(&tiled_file(Storage::Zip, &[], 2, 2)).unwrap();
        assert_eq!(raw, zip);
        assert_eq!(raw.grids[0].tiles.len(), 65536);
        assert!(matches!(
            parse(&tiled_file(Storage::Zip, &[], 3, 2)),
            Err(VdbError::Truncated { .. } | VdbError::Malformed { .. })
        ));
    }

    /// A file cut short says so; a file of full length whose data is damaged says it is
    /// malformed, never truncated (a new user's report: the two messages were swapped).
    #[test]
    fn a_cut_file_is_truncated_and_a_damaged_one_malformed() {
        let whole = tiled_file(Storage::Raw, &[], 2, 2);
        for cut in [whole.len() - 1, whole.len() / 2] {
            let e = parse(&whole[..cut]).unwrap_err();
            assert!(matches!(e, VdbError::Truncated { .. }), "cut at {cut}: {e}");
        }
        // Whole, as its header says, but announcing three nodes where two were written: its
        // data runs past the file's end.
        let e = parse(&tiled_file(Storage::Raw, &[], 3, 2)).unwrap_err();
        assert!(matches!(e, VdbError::Malformed { .. }), "{e}");
    }
}
