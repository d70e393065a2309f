// A stable least-significant-digit radix sort of (key, value) pairs, 8 bits a pass, in a fixed
// order: each tile of TILE pairs counts its digits (integer atomics in workgroup memory: the
// same counts whatever their order), the counts of all tiles are scanned digit by digit
// (scan.wgsl), and each pair goes to its digit's place after the pairs of earlier tiles and
// the earlier pairs of its own tile. No loop runs longer than TILE (Mesa's lavapipe cuts loops
// at 65,535 iterations). Driven by sort.rs; the build sorts its lights by cell with it.

struct Pass {
    // Pairs; the digit's shift; tiles of TILE pairs.
    count: u32,
    shift: u32,
    tiles: u32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> pass_: Pass;
@group(0) @binding(1) var<storage, read_write> keys_in: array<u32>;
@group(0) @binding(2) var<storage, read_write> values_in: array<u32>;
@group(0) @binding(3) var<storage, read_write> keys_out: array<u32>;
@group(0) @binding(4) var<storage, read_write> values_out: array<u32>;
// Digit d of tile t counted at d·tiles + t, then scanned into its place.
@group(0) @binding(5) var<storage, read_write> histogram: array<u32>;

const TILE: u32 = 256u;
const RADIX: u32 = 256u;

var<workgroup> tile_counts: array<atomic<u32>, RADIX>;
var<workgroup> tile_digits: array<u32, TILE>;

fn tile_index(wg: vec3<u32>, groups: vec3<u32>) -> u32 {
    return wg.x + wg.y * groups.x;
}

fn digit(key: u32) -> u32 {
    return (key >> pass_.shift) & (RADIX - 1u);
}

// Each tile's digits counted.
@compute @workgroup_size(TILE)
fn count_digits(@builtin(local_invocation_index) lane: u32,
                @builtin(workgroup_id) wg: vec3<u32>,
                @builtin(num_workgroups) groups: vec3<u32>) {
    let tile = tile_index(wg, groups);
    if tile >= pass_.tiles {
        return;
    }
    atomicStore(&tile_counts[lane], 0u);
    workgroupBarrier();
    let i = tile * TILE + lane;
    if i < pass_.count {
        atomicAdd(&tile_counts[digit(keys_in[i])], 1u);
    }
    workgroupBarrier();
    histogram[lane * pass_.tiles + tile] = atomicLoad(&tile_counts[lane]);
    if tile == 0u && lane == 0u {
        histogram[RADIX * pass_.tiles] = 0u;
    }
}

// Each pair to its place: its digit's start for its tile, plus the pairs of its tile before it
// with the same digit.
@compute @workgroup_size(TILE)
fn scatter_digits(@builtin(local_invocation_index) lane: u32,
                  @builtin(workgroup_id) wg: vec3<u32>,
                  @builtin(num_workgroups) groups: vec3<u32>) {
    let tile = tile_index(wg, groups);
    if tile >= pass_.tiles {
        return;
    }
    let i = tile * TILE + lane;
    var d = RADIX;
    if i < pass_.count {
        d = digit(keys_in[i]);
    }
    tile_digits[lane] = d;
    workgroupBarrier();
    if i >= pass_.count {
        return;
    }
    var rank = 0u;
    for (var k = 0u; k < lane; k++) {
        rank += select(0u, 1u, tile_digits[k] == d);
    }
    let at = histogram[d * pass_.tiles + tile] + rank;
    keys_out[at] = keys_in[i];
    values_out[at] = values_in[i];
}
