// Each level's vertices marked (paper Sec. 3: "levels are sparse", a vertex exists where a light
// lies in one of its eight cells): every slot cleared, then every light's level-ℓ cell marks its
// eight corners with an integer atomic OR of 1 (the same slots marked whatever the order). The
// scan (scan.wgsl) then numbers the marked vertices. Appended to step.wgsl and morton.wgsl;
// driven by build.rs. The slots are build.wgsl's binding 7, seen here as atomics.

@group(0) @binding(7) var<storage, read_write> marks: array<atomic<u32>>;
@group(0) @binding(10) var<storage, read_write> sorted_keys: array<u32>;

// Level ℓ's vertex slots, and the 0 after them that the scan makes the total, cleared.
@compute @workgroup_size(WORKGROUP)
fn clear_slots(@builtin(global_invocation_id) id: vec3<u32>,
               @builtin(num_workgroups) groups: vec3<u32>) {
    let m = flat(id, groups);
    if m <= step.count {
        atomicStore(&marks[step.slot_offset + m], 0u);
    }
}

// Light j's level-ℓ cell (its level-1 cell's Morton code, the sort's key, shifted) marks the
// cell's eight corners.
@compute @workgroup_size(WORKGROUP)
fn mark_corners(@builtin(global_invocation_id) id: vec3<u32>,
                @builtin(num_workgroups) groups: vec3<u32>) {
    let j = flat(id, groups);
    if j >= step.n {
        return;
    }
    let c = demorton3(sorted_keys[j]) >> vec3<u32>(step.level - 1u);
    for (var k = 0u; k < 8u; k++) {
        let q = c + vec3<u32>(k & 1u, (k >> 1u) & 1u, k >> 2u);
        atomicOr(&marks[step.slot_offset + morton3(q)], 1u);
    }
}
