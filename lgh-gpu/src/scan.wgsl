// An exclusive prefix sum of u32 in place, on the GPU, in a fixed order (integers: the same
// bits on every run): the counting sort's cell starts and the levels' vertex numbering in
// build.wgsl. Driven by scan.rs, which recurses on the blocks' sums.

struct Step {
    // Where the values begin in `data`, and how many.
    offset: u32,
    count: u32,
    // Where each block of BLOCK values writes its sum (scan_blocks) or reads its scanned
    // sum (add_sums).
    sums: u32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> step: Step;
@group(0) @binding(1) var<storage, read_write> data: array<u32>;

const BLOCK: u32 = 256u;
var<workgroup> shared_values: array<u32, BLOCK>;

fn block_index(wg: vec3<u32>, groups: vec3<u32>) -> u32 {
    return wg.x + wg.y * groups.x;
}

// Each block of BLOCK values scanned (Hillis–Steele in workgroup memory: a fixed tree of
// integer additions), its total written to data[sums + block].
@compute @workgroup_size(BLOCK)
fn scan_blocks(@builtin(local_invocation_index) lane: u32,
               @builtin(workgroup_id) wg: vec3<u32>,
               @builtin(num_workgroups) groups: vec3<u32>) {
    let block = block_index(wg, groups);
    let i = block * BLOCK + lane;
    var value = 0u;
    if i < step.count {
        value = data[step.offset + i];
    }
    shared_values[lane] = value;
    workgroupBarrier();
    for (var d = 1u; d < BLOCK; d *= 2u) {
        var add = 0u;
        if lane >= d {
            add = shared_values[lane - d];
        }
        workgroupBarrier();
        shared_values[lane] += add;
        workgroupBarrier();
    }
    // shared_values now holds the inclusive sums.
    if i < step.count {
        data[step.offset + i] = shared_values[lane] - value;
    }
    if lane == BLOCK - 1u && block * BLOCK < step.count {
        data[step.sums + block] = shared_values[lane];
    }
}

// Each value of block b raised by the scanned sum of the blocks before it.
@compute @workgroup_size(BLOCK)
fn add_sums(@builtin(local_invocation_index) lane: u32,
            @builtin(workgroup_id) wg: vec3<u32>,
            @builtin(num_workgroups) groups: vec3<u32>) {
    let block = block_index(wg, groups);
    let i = block * BLOCK + lane;
    if i < step.count {
        data[step.offset + i] += data[step.sums + block];
    }
}
