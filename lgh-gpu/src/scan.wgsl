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

// Values a workgroup scans: THREADS invocations, ITEMS values each.
const THREADS: u32 = 256u;
const ITEMS: u32 = 4u;
const BLOCK: u32 = 1024u;
var<workgroup> values: array<u32, BLOCK>;
var<workgroup> totals: array<u32, THREADS>;

fn block_index(wg: vec3<u32>, groups: vec3<u32>) -> u32 {
    return wg.x + wg.y * groups.x;
}

// Each block of BLOCK values scanned — loaded into workgroup memory, each invocation's ITEMS
// consecutive values summed in order, the invocations' totals scanned by Hillis–Steele (a fixed
// tree of integer additions), the values written back — its total written to data[sums + block].
@compute @workgroup_size(THREADS)
fn scan_blocks(@builtin(local_invocation_index) lane: u32,
               @builtin(workgroup_id) wg: vec3<u32>,
               @builtin(num_workgroups) groups: vec3<u32>) {
    let block = block_index(wg, groups);
    let first = block * BLOCK;
    for (var i = 0u; i < ITEMS; i++) {
        let k = i * THREADS + lane;
        var value = 0u;
        if first + k < step.count {
            value = data[step.offset + first + k];
        }
        values[k] = value;
    }
    workgroupBarrier();
    var run = 0u;
    for (var i = 0u; i < ITEMS; i++) {
        let value = values[lane * ITEMS + i];
        values[lane * ITEMS + i] = run;
        run += value;
    }
    totals[lane] = run;
    workgroupBarrier();
    for (var d = 1u; d < THREADS; d *= 2u) {
        var add = 0u;
        if lane >= d {
            add = totals[lane - d];
        }
        workgroupBarrier();
        totals[lane] += add;
        workgroupBarrier();
    }
    // totals now holds the inclusive sums: the invocations before this one add up to
    // totals[lane] − run.
    let before = totals[lane] - run;
    for (var i = 0u; i < ITEMS; i++) {
        values[lane * ITEMS + i] += before;
    }
    workgroupBarrier();
    for (var i = 0u; i < ITEMS; i++) {
        let k = i * THREADS + lane;
        if first + k < step.count {
            data[step.offset + first + k] = values[k];
        }
    }
    if lane == THREADS - 1u && first < step.count {
        data[step.sums + block] = totals[lane];
    }
}

// Each value of block b raised by the scanned sum of the blocks before it.
@compute @workgroup_size(THREADS)
fn add_sums(@builtin(local_invocation_index) lane: u32,
            @builtin(workgroup_id) wg: vec3<u32>,
            @builtin(num_workgroups) groups: vec3<u32>) {
    let block = block_index(wg, groups);
    let add = data[step.sums + block];
    for (var i = 0u; i < ITEMS; i++) {
        let k = block * BLOCK + i * THREADS + lane;
        if k < step.count {
            data[step.offset + k] += add;
        }
    }
}
