// For each shading point, K lights drawn in proportion to their unshadowed light there (its
// luminance), each by weighted reservoir sampling over the lights the walk visits (as the
// real-time LGH of Lin & Yuksel draws the lights of its shadow rays), with the weight that makes
// the K draws an unbiased estimate of eq. (1)'s unshadowed sum: an engine traces one shadow ray
// to each and adds weight × visibility. Appended to walk.wgsl; driven by gather.rs.

struct Sample {
    position: vec3<f32>,
    // ρ/π · term · W / w / K: the radiance it stands for, W the sum of the weights w.
    weight: vec3<f32>,
}

@group(0) @binding(5) var<storage, read_write> samples: array<Sample>;

const MAX_K: u32 = 16u;
const LUMINANCE: vec3<f32> = vec3<f32>(0.2126, 0.7152, 0.0722);

var<private> rng: u32;
var<private> total: f32;
var<private> chosen_position: array<vec3<f32>, MAX_K>;
var<private> chosen_term: array<vec3<f32>, MAX_K>;
var<private> chosen_weight: array<f32, MAX_K>;

// PCG's output permutation of a 32-bit state (O'Neill 2014).
fn pcg(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The point's next uniform number in [0, 1): the high 24 bits of a linear congruential step
// (seeded through PCG; one multiply-add a draw, as the walk draws K a light).
fn next_uniform() -> f32 {
    rng = rng * 747796405u + 2891336453u;
    return f32(rng >> 8u) * (1.0 / 16777216.0);
}

// Each reservoir keeps this light with probability w / (the weights so far).
fn visit(i: u32, light: Light, term: vec3<f32>) {
    let w = dot(term, LUMINANCE);
    if !(w > 0.0) {
        return;
    }
    total += w;
    for (var r = 0u; r < params.k; r++) {
        if next_uniform() * total < w {
            chosen_position[r] = light.position;
            chosen_term[r] = term;
            chosen_weight[r] = w;
        }
    }
}

@compute @workgroup_size(WORKGROUP)
fn gather(@builtin(global_invocation_id) id: vec3<u32>,
          @builtin(num_workgroups) groups: vec3<u32>) {
    let i = point_index(id, groups);
    if i >= params.points {
        return;
    }
    let p = points[i];
    rng = pcg(params.seed ^ pcg(i));
    total = 0.0;
    for (var r = 0u; r < MAX_K; r++) {
        chosen_position[r] = vec3<f32>(0.0);
        chosen_term[r] = vec3<f32>(0.0);
        chosen_weight[r] = 0.0;
    }
    walk(p.position, p.normal);
    let scale = p.albedo * (INV_PI / f32(params.k));
    for (var r = 0u; r < params.k; r++) {
        var weight = vec3<f32>(0.0);
        if chosen_weight[r] > 0.0 {
            weight = chosen_term[r] * (total / chosen_weight[r]) * scale;
        }
        samples[i * params.k + r] = Sample(chosen_position[r], weight);
    }
}
