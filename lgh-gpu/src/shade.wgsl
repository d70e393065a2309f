// Eq. (1)'s blended sum at shading points, with a Lambertian response, unshadowed (paper
// Sec. 3): L = ρ/π · Σ_ℓ Σ_i B_ℓ(d)·g(d)·I_ℓi·max(0, n·ω), d = ‖p_ℓi − x‖, g(d) = 1/max(d, h0)².
// Driven by hierarchy.rs; the structs mirror layout.rs.

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
}

struct Params {
    levels: u32,
    points: u32,
    h0: f32,
    // Lights from this index on are in `lights_hi` (one binding holds at most the device's
    // binding size: 128 MiB on lavapipe).
    split: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> levels: array<Level>;
@group(0) @binding(2) var<storage, read> starts: array<u32>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
@group(0) @binding(6) var<storage, read> lights_hi: array<Light>;
@group(0) @binding(4) var<storage, read> points: array<Point>;
@group(0) @binding(5) var<storage, read_write> radiance: array<vec4<f32>>;

const WORKGROUP: u32 = 64u;
const INV_PI: f32 = 0.31830988618379067;

// B_ℓ(d) = clamp(min(a d + c1, c2 − b d), 0, 1), ramp = [a, c1, b, c2] (eq. 3).
fn blend(ramp: vec4<f32>, d: f32) -> f32 {
    let rise = d * ramp.x + ramp.y;
    let fall = ramp.w - d * ramp.z;
    return clamp(min(rise, fall), 0.0, 1.0);
}

// What light k of `level` adds at x with normal n: B·I·g·max(0, n·ω), 0 outside the level's
// support (d² ≤ inner² or d² > outer², as lgh-core's scan).
fn contribution(level: Level, k: u32, x: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let i = level.first_light + k;
    var light: Light;
    if i < params.split {
        light = lights[i];
    } else {
        light = lights_hi[i - params.split];
    }
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

// The lights of `level` within its reach of x: the cells that meet the ball, or every light
// where the level has no cells (the top level).
fn level_sum(level: Level, x: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    if level.dims.x == 0u {
        for (var k = 0u; k < level.light_count; k++) {
            sum += contribution(level, k, x, n);
        }
        return sum;
    }
    let reach = sqrt(level.outer2);
    let lo = floor((x - vec3<f32>(reach) - level.origin) / level.cell);
    let hi = floor((x + vec3<f32>(reach) - level.origin) / level.cell);
    let top = vec3<f32>(level.dims - vec3<u32>(1u));
    if any(hi < vec3<f32>(0.0)) || any(lo > top) {
        return sum;
    }
    let a = vec3<u32>(max(lo, vec3<f32>(0.0)));
    let b = vec3<u32>(min(hi, top));
    for (var z = a.z; z <= b.z; z++) {
        for (var y = a.y; y <= b.y; y++) {
            let row = level.first_cell + (z * level.dims.y + y) * level.dims.x;
            let start = starts[row + a.x];
            let end = starts[row + b.x + 1u];
            for (var k = start; k < end; k++) {
                sum += contribution(level, k, x, n);
            }
        }
    }
    return sum;
}

@compute @workgroup_size(WORKGROUP)
fn shade(@builtin(global_invocation_id) id: vec3<u32>,
         @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.x + id.y * groups.x * WORKGROUP;
    if i >= params.points {
        return;
    }
    let p = points[i];
    var sum = vec3<f32>(0.0);
    for (var l = 0u; l < params.levels; l++) {
        sum += level_sum(levels[l], p.position, p.normal);
    }
    radiance[i] = vec4<f32>(sum * p.albedo * INV_PI, 0.0);
}
