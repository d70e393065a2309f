// A build dispatch's uniform (layout.rs's BuildStep), at a dynamic offset: shared by the build's
// modules (build.wgsl, mark.wgsl), each appended to this file (kernels.rs).

struct Step {
    // The grid: its origin and level-1 spacing.
    origin: vec3<f32>,
    h1: f32,
    // Input lights; Morton bits a side; this level ℓ; the top level.
    n: u32,
    bits: u32,
    level: u32,
    top: u32,
    // The largest level-1 cell coordinate (lights beyond are clamped into it); where this
    // level's vertex slots begin in `slots`; where its lights begin in `out`; its weak-light
    // threshold (0 on the top level).
    max_cell: u32,
    slot_offset: u32,
    light_base: u32,
    threshold: f32,
    // Items of this dispatch (lights, cells, vertex slots or vertices), and the workgroups each
    // vertex's sums are split over (the coarse levels' splat).
    count: u32,
    parts: u32,
    // Where level ℓ's vertices begin in `vertex_slots`.
    list_offset: u32,
    _pad0: u32,
}

@group(0) @binding(0) var<uniform> step: Step;

const WORKGROUP: u32 = 64u;

// Invocation id's item: id.x + id.y · groups.x · WORKGROUP.
fn flat(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * WORKGROUP;
}
