// The query's walk (paper Sec. 3): every light of every level within the level's reach of a
// shading point, and what it adds there with a Lambertian response, unshadowed:
// B_ℓ(d)·g(d)·I_ℓi·max(0, n·ω), d = ‖p_ℓi − x‖, g(d) = 1/max(d, h0)² (eqs. 1 and 3).
// Shared by the kernels that walk the hierarchy (shade.wgsl, gather.wgsl): each defines
// `visit(light, term)`, which the walk calls for every light with a term that may be non-zero.
// The structs mirror layout.rs.

struct Light {
    position: vec3<f32>,
    intensity: vec3<f32>,
}

struct Point {
    position: vec3<f32>,
    normal: vec3<f32>,
    albedo: vec3<f32>,
}

struct Level {
    origin: vec3<f32>,
    cell: f32,
    dims: vec3<u32>,
    first_cell: u32,
    first_light: u32,
    light_count: u32,
    inner2: f32,
    outer2: f32,
    ramp: vec4<f32>,
    // How far a light may lie outside its cell.
    margin: f32,
    // Cell c's lights are starts[first_cell + stride·c] .. starts[first_cell + stride·(c + 1)].
    stride: u32,
    // How cells are numbered: CELLS_ROWS, (z·dims.y + y)·dims.x + x; CELLS_MORTON, by the
    // Morton code of (x, y, z).
    order: u32,
    // Where the cell starts are: STARTS_CELLS, `starts`; STARTS_SLOTS, `slots`.
    bank: u32,
}

struct Params {
    levels: u32,
    points: u32,
    h0: f32,
    // Lights from this index on are in `lights_hi` (one binding holds at most the device's
    // binding size: 128 MiB on lavapipe).
    split: u32,
    // The gather's draws per point and its seed (unused by the shade).
    k: u32,
    seed: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> levels: array<Level>;
@group(0) @binding(2) var<storage, read> starts: array<u32>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
@group(0) @binding(6) var<storage, read> lights_hi: array<Light>;
@group(0) @binding(4) var<storage, read> points: array<Point>;
@group(0) @binding(7) var<storage, read> slots: array<u32>;

const WORKGROUP: u32 = 64u;
const INV_PI: f32 = 0.31830988618379067;
const CELLS_ROWS: u32 = 0u;
const CELLS_MORTON: u32 = 1u;
const STARTS_CELLS: u32 = 0u;
const STARTS_SLOTS: u32 = 1u;

// B_ℓ(d) = clamp(min(a d + c1, c2 − b d), 0, 1), ramp = [a, c1, b, c2] (eq. 3).
fn blend(ramp: vec4<f32>, d: f32) -> f32 {
    let rise = d * ramp.x + ramp.y;
    let fall = ramp.w - d * ramp.z;
    return clamp(min(rise, fall), 0.0, 1.0);
}

fn light_at(i: u32) -> Light {
    if i < params.split {
        return lights[i];
    }
    return lights_hi[i - params.split];
}

// What light i of `level` adds at x with normal n: B·I·g·max(0, n·ω), 0 outside the level's
// support (d² ≤ inner² or d² > outer², as lgh-core's scan).
fn contribution(level: Level, light: Light, x: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let v = light.position - x;
    let d2 = dot(v, v);
    if !(d2 > level.inner2 && d2 <= level.outer2) {
        return vec3<f32>(0.0);
    }
    let d = sqrt(d2);
    let c = max(d, params.h0);
    var cosine = 0.0;
    if d > 0.0 {
        cosine = max(dot(n, v) / d, 0.0);
    }
    return light.intensity * (blend(level.ramp, d) * (1.0 / (c * c)) * cosine);
}

// The lights start..end of the level's buffer, each visited with its term.
fn visit_range(level: Level, start: u32, end: u32, x: vec3<f32>, n: vec3<f32>) {
    for (var k = start; k < end; k++) {
        let i = level.first_light + k;
        let light = light_at(i);
        visit(i, light, contribution(level, light, x, n));
    }
}

// Entry i of the level's bank of cell starts.
fn cell_start(level: Level, i: u32) -> u32 {
    if level.bank == STARTS_SLOTS {
        return slots[i];
    }
    return starts[i];
}

// The lights of `level` within its reach of x: the cells that meet the ball (widened by how far
// a light may lie outside its cell), or every light where the level has no cells (the top).
fn walk_level(level: Level, x: vec3<f32>, n: vec3<f32>) {
    if level.dims.x == 0u {
        visit_range(level, 0u, level.light_count, x, n);
        return;
    }
    let reach = sqrt(level.outer2) + level.margin;
    let lo = floor((x - vec3<f32>(reach) - level.origin) / level.cell);
    let hi = floor((x + vec3<f32>(reach) - level.origin) / level.cell);
    let top = vec3<f32>(level.dims - vec3<u32>(1u));
    if any(hi < vec3<f32>(0.0)) || any(lo > top) {
        return;
    }
    let a = vec3<u32>(max(lo, vec3<f32>(0.0)));
    let b = vec3<u32>(min(hi, top));
    let s = level.stride;
    for (var z = a.z; z <= b.z; z++) {
        for (var y = a.y; y <= b.y; y++) {
            if level.order == CELLS_ROWS {
                let row = (z * level.dims.y + y) * level.dims.x;
                let start = cell_start(level, level.first_cell + s * (row + a.x));
                let end = cell_start(level, level.first_cell + s * (row + b.x + 1u));
                visit_range(level, start, end, x, n);
            } else {
                for (var c = a.x; c <= b.x; c++) {
                    // A cell whose box (widened by the margin) is beyond the reach: skipped.
                    let low = level.origin + vec3<f32>(vec3<u32>(c, y, z)) * level.cell
                        - vec3<f32>(level.margin);
                    let high = low + vec3<f32>(level.cell + 2.0 * level.margin);
                    let out = max(max(low - x, x - high), vec3<f32>(0.0));
                    if dot(out, out) > level.outer2 {
                        continue;
                    }
                    let m = morton3(vec3<u32>(c, y, z));
                    let start = cell_start(level, level.first_cell + s * m);
                    let end = cell_start(level, level.first_cell + s * (m + 1u));
                    visit_range(level, start, end, x, n);
                }
            }
        }
    }
}

// Every level's lights within reach of x.
fn walk(x: vec3<f32>, n: vec3<f32>) {
    for (var l = 0u; l < params.levels; l++) {
        walk_level(levels[l], x, n);
    }
}

// The shading point of this invocation: id.x + id.y · groups.x · WORKGROUP.
fn point_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * WORKGROUP;
}
