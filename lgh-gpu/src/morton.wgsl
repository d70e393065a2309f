// Morton codes of cells and vertices (coordinates below 2^10): the bits of x, y, z interleaved,
// x lowest. Appended to the kernels that number cells so (kernels.rs).

// The bits of v spread to every third bit: one axis of a Morton code.
fn spread3(v: u32) -> u32 {
    var x = v & 0x3ffu;
    x = (x | (x << 16u)) & 0x030000ffu;
    x = (x | (x << 8u)) & 0x0300f00fu;
    x = (x | (x << 4u)) & 0x030c30c3u;
    x = (x | (x << 2u)) & 0x09249249u;
    return x;
}

// The inverse of spread3.
fn compact3(v: u32) -> u32 {
    var x = v & 0x09249249u;
    x = (x | (x >> 2u)) & 0x030c30c3u;
    x = (x | (x >> 4u)) & 0x0300f00fu;
    x = (x | (x >> 8u)) & 0x030000ffu;
    x = (x | (x >> 16u)) & 0x3ffu;
    return x;
}

fn morton3(c: vec3<u32>) -> u32 {
    return spread3(c.x) | (spread3(c.y) << 1u) | (spread3(c.z) << 2u);
}

fn demorton3(m: u32) -> vec3<u32> {
    return vec3<u32>(compact3(m), compact3(m >> 1u), compact3(m >> 2u));
}
