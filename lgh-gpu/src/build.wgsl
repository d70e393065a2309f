// The hierarchy built on the GPU (paper Sec. 3): the input lights counted in level-1 cells and
// sorted by cell (sort.wgsl), then each level's lights splatted from the input lights by eqs. (1), (2),
// (4) and (5). Every sum is gathered by one invocation or one workgroup in a fixed order — no
// float atomics — so the same lights give the same bits on every run. Driven by build.rs; the
// prefix sums are scan.wgsl's.
//
// Cells and vertices are numbered by Morton code on a grid of 2^bits level-1 cells a side, so a
// level-ℓ cell is a contiguous run of level-1 cells: Morton(c) << 3(ℓ−1) onwards.

struct Light {
    position: vec3<f32>,
    intensity: vec3<f32>,
}

// An input light in the sorted order, as the splat reads it: its place in its level-1 cell
// (cell units), luminance, RGB intensity and its level-1 cell packed 10 bits an axis.
struct Sorted {
    frac: vec3<f32>,
    luminance: f32,
    intensity: vec3<f32>,
    cell: u32,
}

@group(0) @binding(1) var<storage, read_write> positions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> intensities: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(4) var<storage, read_write> starts: array<u32>;
@group(0) @binding(5) var<storage, read_write> order: array<u32>;
@group(0) @binding(6) var<storage, read_write> sorted: array<Sorted>;
@group(0) @binding(7) var<storage, read_write> slots: array<u32>;
@group(0) @binding(8) var<storage, read_write> out: array<Light>;
@group(0) @binding(9) var<storage, read_write> extras: array<vec4<f32>>;
@group(0) @binding(10) var<storage, read_write> keys: array<u32>;
// Each level's vertices, in their numbering: vertex v's slot (its Morton code).
@group(0) @binding(12) var<storage, read_write> vertex_slots: array<u32>;

// Rec. 709 luminance, lgh-core's LUMINANCE_WEIGHTS.
const LUMINANCE: vec3<f32> = vec3<f32>(0.2126, 0.7152, 0.0722);


fn pack(c: vec3<u32>) -> u32 {
    return c.x | (c.y << 10u) | (c.z << 20u);
}

fn unpack(c: u32) -> vec3<u32> {
    return vec3<u32>(c & 0x3ffu, (c >> 10u) & 0x3ffu, c >> 20u);
}

struct Located {
    cell: vec3<u32>,
    frac: vec3<f32>,
}

// A light's level-1 cell and its place in it, clamped to the grid as lgh-core's `locate`.
fn locate_light(p: vec3<f32>) -> Located {
    let t = (p - step.origin) / step.h1;
    let c = clamp(floor(t), vec3<f32>(0.0), vec3<f32>(f32(step.max_cell)));
    return Located(vec3<u32>(c), clamp(t - c, vec3<f32>(0.0), vec3<f32>(1.0)));
}

// Each input light counted in its level-1 cell, and given its cell's Morton code as the key
// the radix sort (sort.wgsl) orders the lights by, ties by index.
@compute @workgroup_size(WORKGROUP)
fn locate(@builtin(global_invocation_id) id: vec3<u32>,
          @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat(id, groups);
    if i >= step.n {
        return;
    }
    let m = morton3(locate_light(positions[i].xyz).cell);
    atomicAdd(&counts[m], 1u);
    keys[i] = m;
    order[i] = i;
}

// The counts copied for the scan (which makes them the cells' starts), with a 0 after them
// (which the scan makes the total); the counts go back to 0, ready for the next build.
@compute @workgroup_size(WORKGROUP)
fn copy_counts(@builtin(global_invocation_id) id: vec3<u32>,
               @builtin(num_workgroups) groups: vec3<u32>) {
    let m = flat(id, groups);
    if m >= step.count {
        return;
    }
    starts[m] = atomicExchange(&counts[m], 0u);
    if m == 0u {
        starts[step.count] = 0u;
    }
}

// The input lights in the sorted order, for the splat, and as level 0 of the query (a light
// weaker than the threshold given no intensity: it adds nothing, as lgh-core's query skips it).
@compute @workgroup_size(WORKGROUP)
fn gather_sorted(@builtin(global_invocation_id) id: vec3<u32>,
                 @builtin(num_workgroups) groups: vec3<u32>) {
    let j = flat(id, groups);
    if j >= step.n {
        return;
    }
    let i = order[j];
    let p = positions[i].xyz;
    let intensity = intensities[i].xyz;
    let at = locate_light(p);
    let luminance = dot(intensity, LUMINANCE);
    sorted[j] = Sorted(at.frac, luminance, intensity, pack(at.cell));
    let reported = luminance > 0.0 && luminance >= step.threshold;
    out[j] = Light(p, select(vec3<f32>(0.0), intensity, reported));
    extras[j] = vec4<f32>(0.0);
}

// Corner k of a cell is at offset (k & 1, (k >> 1) & 1, k >> 2).
fn corner(k: u32) -> vec3<u32> {
    return vec3<u32>(k & 1u, (k >> 1u) & 1u, k >> 2u);
}

// Level-ℓ cells a side.
fn cells_a_side() -> u32 {
    return 1u << (step.bits - (step.level - 1u));
}

// The sorted input lights of level-ℓ cell c: a run of level-1 cells.
fn cell_range(c: vec3<u32>) -> vec2<u32> {
    let shift = 3u * (step.level - 1u);
    let m = morton3(c);
    return vec2<u32>(starts[m << shift], starts[(m + 1u) << shift]);
}

// Each marked slot m of level ℓ listed under its vertex's number (the splats run over the
// list, not over every slot).
@compute @workgroup_size(WORKGROUP)
fn list_vertices(@builtin(global_invocation_id) id: vec3<u32>,
                 @builtin(num_workgroups) groups: vec3<u32>) {
    let m = flat(id, groups);
    if m >= step.count {
        return;
    }
    let v = slots[step.slot_offset + m];
    if slots[step.slot_offset + m + 1u] != v {
        vertex_slots[step.list_offset + v] = m;
    }
}

// A vertex's sums over the lights of its eight cells, offsets o from the vertex in cell units
// and v = w·‖I‖ (lgh-core's MomentSums): Σ w I (eq. 1), Σ v, Σ v o (eq. 2), Σ v o² (eq. 4).
struct Sums {
    intensity: vec3<f32>,
    weight: f32,
    first: vec3<f32>,
    second: vec3<f32>,
}

// The sorted lights of the cell of which vertex q is corner k; none where that cell is off
// the grid.
fn corner_cell(q: vec3<u32>, k: u32) -> vec2<u32> {
    let o = corner(k);
    if any(q < o) || any(q - o >= vec3<u32>(cells_a_side())) {
        return vec2<u32>(0u);
    }
    return cell_range(q - o);
}

// A sorted light's place in its level-ℓ cell, in cell units, from its place in its level-1 cell
// (lgh-core's splat_input).
fn place(light: Sorted) -> vec3<f32> {
    let sub = step.level - 1u;
    let mask = vec3<u32>((1u << sub) - 1u);
    let scale = 1.0 / f32(1u << sub);
    return min((vec3<f32>(unpack(light.cell) & mask) + light.frac) * scale, vec3<f32>(1.0));
}

// Eq. (1)'s trilinear weight at corner o of a light at g in its cell.
fn weight(g: vec3<f32>, o: vec3<u32>) -> f32 {
    let wa = select(vec3<f32>(1.0) - g, g, o == vec3<u32>(1u));
    return wa.x * wa.y * wa.z;
}

// Lights j ≡ lane (mod lanes) of each of vertex q's cells, cell by cell.
fn moment_sums(q: vec3<u32>, lane: u32, lanes: u32) -> Sums {
    var s = Sums(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), vec3<f32>(0.0));
    for (var k = 0u; k < 8u; k++) {
        let r = corner_cell(q, k);
        let o = corner(k);
        for (var j = r.x + lane; j < r.y; j += lanes) {
            let light = sorted[j];
            let g = place(light);
            let w = weight(g, o);
            let v = w * light.luminance;
            let off = g - vec3<f32>(o);
            s.intensity += w * light.intensity;
            s.weight += v;
            s.first += v * off;
            s.second += v * (off * off);
        }
    }
    return s;
}

// Σ v ‖o − mean‖ of eq. (5) over the same lights.
fn size_sum(q: vec3<u32>, mean: vec3<f32>, lane: u32, lanes: u32) -> f32 {
    var sum = 0.0;
    for (var k = 0u; k < 8u; k++) {
        let r = corner_cell(q, k);
        let o = corner(k);
        for (var j = r.x + lane; j < r.y; j += lanes) {
            let light = sorted[j];
            let g = place(light);
            sum += weight(g, o) * light.luminance * length(g - (vec3<f32>(o) + mean));
        }
    }
    return sum;
}

// The illumination centre relative to the vertex, in cell units (eq. 2): the vertex itself
// where it gathers no luminance.
fn centre(s: Sums) -> vec3<f32> {
    if s.weight > 0.0 {
        return s.first / s.weight;
    }
    return vec3<f32>(0.0);
}

// Vertex v (slot m, at q) of level ℓ written as the query's light and its variance (eq. 4) and
// size (eq. 5).
fn write_vertex(q: vec3<u32>, v: u32, s: Sums, mean: vec3<f32>, size_sum: f32) {
    let h = step.h1 * f32(1u << (step.level - 1u));
    var variance = vec3<f32>(0.0);
    var size = 0.0;
    if s.weight > 0.0 {
        variance = max(s.second / s.weight - mean * mean, vec3<f32>(0.0)) * h * h;
        size = size_sum / s.weight * h;
    }
    let position = step.origin + (vec3<f32>(q) + mean) * h;
    let luminance = dot(s.intensity, LUMINANCE);
    let reported = luminance > 0.0 && luminance >= step.threshold;
    out[step.light_base + v] = Light(position, select(vec3<f32>(0.0), s.intensity, reported));
    extras[step.light_base + v] = vec4<f32>(variance, size);
}

// One invocation a vertex: the levels whose vertices gather a few lights.
@compute @workgroup_size(WORKGROUP)
fn splat(@builtin(global_invocation_id) id: vec3<u32>,
         @builtin(num_workgroups) groups: vec3<u32>) {
    let v = flat(id, groups);
    if v >= step.count {
        return;
    }
    let q = demorton3(vertex_slots[step.list_offset + v]);
    let s = moment_sums(q, 0u, 1u);
    let mean = centre(s);
    write_vertex(q, v, s, mean, size_sum(q, mean, 0u, 1u));
}

// The coarse levels, whose vertices gather many lights each: vertex v's work split over
// `parts` workgroups, part g's lanes summing every (WORKGROUP·parts)-th light of each cell, its
// lanes' sums added in a fixed tree and written to partials[v·parts + g]; the parts then added
// in a fixed order by a workgroup a vertex. Entries: [0] Σ w I and Σ v, [1] Σ v o, [2] Σ v o²,
// [3] the centre (part 0, once known), [4].x Σ v ‖o − centre‖.
@group(0) @binding(11) var<storage, read_write> partials: array<array<vec4<f32>, 5>>;

var<workgroup> lane_sums: array<array<vec4<f32>, 3>, WORKGROUP>;

// Which vertex v (at q) and part g workgroup wg of a parts kernel works on (w = v·parts + g),
// or none past the level's vertices — the same answer for the whole workgroup.
struct Part {
    w: u32,
    v: u32,
    q: vec3<u32>,
    g: u32,
    busy: bool,
}

fn part(wg: vec3<u32>, groups: vec3<u32>, parts: u32) -> Part {
    let w = wg.x + wg.y * groups.x;
    if w >= step.count * parts {
        return Part(w, 0u, vec3<u32>(0u), 0u, false);
    }
    let v = w / parts;
    return Part(w, v, demorton3(vertex_slots[step.list_offset + v]), w % parts, true);
}

// The workgroup's lane sums added in a fixed tree into lane_sums[0].
fn reduce(lane: u32) {
    for (var stride = WORKGROUP / 2u; stride > 0u; stride /= 2u) {
        if lane < stride {
            for (var a = 0u; a < 3u; a++) {
                lane_sums[lane][a] += lane_sums[lane + stride][a];
            }
        }
        workgroupBarrier();
    }
}

// Part g of vertex v's moment sums (eqs. 1, 2, 4).
@compute @workgroup_size(WORKGROUP)
fn moment_parts(@builtin(local_invocation_index) lane: u32,
                @builtin(workgroup_id) wg: vec3<u32>,
                @builtin(num_workgroups) groups: vec3<u32>) {
    let p = part(wg, groups, step.parts);
    if !p.busy {
        return;
    }
    let s = moment_sums(p.q, p.g * WORKGROUP + lane, WORKGROUP * step.parts);
    lane_sums[lane] = array<vec4<f32>, 3>(vec4<f32>(s.intensity, s.weight),
                                          vec4<f32>(s.first, 0.0), vec4<f32>(s.second, 0.0));
    workgroupBarrier();
    reduce(lane);
    if lane == 0u {
        for (var a = 0u; a < 3u; a++) {
            partials[p.w][a] = lane_sums[0][a];
        }
    }
}

// The parts' moment sums of vertex v added into part 0 (lane l adds parts l, l + 64, …,
// then the lanes' sums in a fixed tree), and its centre.
@compute @workgroup_size(WORKGROUP)
fn finish_moments(@builtin(local_invocation_index) lane: u32,
                  @builtin(workgroup_id) wg: vec3<u32>,
                  @builtin(num_workgroups) groups: vec3<u32>) {
    let p = part(wg, groups, 1u);
    if !p.busy {
        return;
    }
    let first = p.v * step.parts;
    var sum = array<vec4<f32>, 3>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    for (var g = lane; g < step.parts; g += WORKGROUP) {
        for (var a = 0u; a < 3u; a++) {
            sum[a] += partials[first + g][a];
        }
    }
    lane_sums[lane] = sum;
    workgroupBarrier();
    reduce(lane);
    if lane == 0u {
        let total = lane_sums[0];
        for (var a = 0u; a < 3u; a++) {
            partials[first][a] = total[a];
        }
        let s = Sums(total[0].xyz, total[0].w, total[1].xyz, total[2].xyz);
        partials[first][3] = vec4<f32>(centre(s), 0.0);
    }
}

// Part g of vertex v's sum of eq. (5).
@compute @workgroup_size(WORKGROUP)
fn size_parts(@builtin(local_invocation_index) lane: u32,
              @builtin(workgroup_id) wg: vec3<u32>,
              @builtin(num_workgroups) groups: vec3<u32>) {
    let p = part(wg, groups, step.parts);
    if !p.busy {
        return;
    }
    let mean = partials[p.v * step.parts][3].xyz;
    let sum = size_sum(p.q, mean, p.g * WORKGROUP + lane, WORKGROUP * step.parts);
    lane_sums[lane][0] = vec4<f32>(sum, 0.0, 0.0, 0.0);
    lane_sums[lane][1] = vec4<f32>(0.0);
    lane_sums[lane][2] = vec4<f32>(0.0);
    workgroupBarrier();
    reduce(lane);
    if lane == 0u {
        partials[p.w][4] = lane_sums[0][0];
    }
}

// Vertex v's light written from its parts' sums (added as in finish_moments).
@compute @workgroup_size(WORKGROUP)
fn finish_vertices(@builtin(local_invocation_index) lane: u32,
                   @builtin(workgroup_id) wg: vec3<u32>,
                   @builtin(num_workgroups) groups: vec3<u32>) {
    let p = part(wg, groups, 1u);
    if !p.busy {
        return;
    }
    let first = p.v * step.parts;
    var sum = 0.0;
    for (var g = lane; g < step.parts; g += WORKGROUP) {
        sum += partials[first + g][4].x;
    }
    lane_sums[lane][0] = vec4<f32>(sum, 0.0, 0.0, 0.0);
    lane_sums[lane][1] = vec4<f32>(0.0);
    lane_sums[lane][2] = vec4<f32>(0.0);
    workgroupBarrier();
    reduce(lane);
    if lane == 0u {
        let t = partials[first];
        let s = Sums(t[0].xyz, t[0].w, t[1].xyz, t[2].xyz);
        write_vertex(p.q, p.v, s, t[3].xyz, lane_sums[0][0].x);
    }
}
