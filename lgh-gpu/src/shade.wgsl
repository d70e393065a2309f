// Eq. (1)'s blended sum at shading points, with a Lambertian response, unshadowed (paper
// Sec. 3): L = ρ/π · Σ_ℓ Σ_i B_ℓ(d)·g(d)·I_ℓi·max(0, n·ω). Appended to walk.wgsl; driven by
// hierarchy.rs.

@group(0) @binding(5) var<storage, read_write> radiance: array<vec4<f32>>;

var<private> sum: vec3<f32>;

fn visit(i: u32, light: Light, term: vec3<f32>) {
    sum += term;
}

@compute @workgroup_size(WORKGROUP)
fn shade(@builtin(global_invocation_id) id: vec3<u32>,
         @builtin(num_workgroups) groups: vec3<u32>) {
    let i = point_index(id, groups);
    if i >= params.points {
        return;
    }
    let p = points[i];
    sum = vec3<f32>(0.0);
    walk(p.position, p.normal);
    radiance[i] = vec4<f32>(sum * p.albedo * INV_PI, 0.0);
}
