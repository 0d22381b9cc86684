// Counter-based Gaussian noise: the same words as src/sim/noise.rs (Threefry-2x32, 20 rounds,
// Random123), in single precision for the Box-Muller transform.

fn rotl(x: u32, r: u32) -> u32 {
    return (x << r) | (x >> (32u - r));
}

fn four_rounds(x: vec2<u32>, r0: u32, r1: u32, r2: u32, r3: u32) -> vec2<u32> {
    var a = x.x;
    var b = x.y;
    a += b; b = rotl(b, r0) ^ a;
    a += b; b = rotl(b, r1) ^ a;
    a += b; b = rotl(b, r2) ^ a;
    a += b; b = rotl(b, r3) ^ a;
    return vec2<u32>(a, b);
}

// Threefry-2x32-20 of `ctr` under `key`: 5 groups of 4 rounds, a key injection after each.
fn threefry(key: vec2<u32>, ctr: vec2<u32>) -> vec2<u32> {
    let k2 = 0x1BD11BDAu ^ key.x ^ key.y;
    var x = vec2<u32>(ctr.x + key.x, ctr.y + key.y);
    x = four_rounds(x, 13u, 15u, 26u, 6u);
    x = vec2<u32>(x.x + key.y, x.y + k2 + 1u);
    x = four_rounds(x, 17u, 29u, 16u, 24u);
    x = vec2<u32>(x.x + k2, x.y + key.x + 2u);
    x = four_rounds(x, 13u, 15u, 26u, 6u);
    x = vec2<u32>(x.x + key.x, x.y + key.y + 3u);
    x = four_rounds(x, 17u, 29u, 16u, 24u);
    x = vec2<u32>(x.x + key.y, x.y + k2 + 4u);
    x = four_rounds(x, 13u, 15u, 26u, 6u);
    x = vec2<u32>(x.x + k2, x.y + key.x + 5u);
    return x;
}

// The four words of `bead` at the step (lo, hi): the two Box-Muller pairs its normals come
// from. Beads go in groups of four, g = bead / 4, whose counters (lo, 6 g + k), k = 0..6, give
// twelve normals; bead 4 g + l takes normals 3 l, 3 l + 1, 3 l + 2. The key's second word is
// xored with the step's high word.
fn bead_words(key: vec2<u32>, step_lo: u32, step_hi: u32, bead: u32) -> vec4<u32> {
    let k = vec2<u32>(key.x, key.y ^ step_hi);
    let first = 6u * (bead / 4u) + 3u * (bead % 4u) / 2u;
    let ab = threefry(k, vec2<u32>(step_lo, first));
    let cd = threefry(k, vec2<u32>(step_lo, first + 1u));
    return vec4<u32>(ab, cd);
}

fn unit_uniform(w: u32) -> f32 {
    return (f32(w >> 8u) + 0.5) * (1.0 / 16777216.0);
}

fn box_muller(a: u32, b: u32) -> vec2<f32> {
    let r = sqrt(-2.0 * log(unit_uniform(a)));
    let t = 6.283185307179586 * unit_uniform(b);
    return vec2<f32>(r * cos(t), r * sin(t));
}

// Three standard normals of `bead` (the first of its first pair when the bead is even).
fn bead_normals(key: vec2<u32>, step_lo: u32, step_hi: u32, bead: u32) -> vec3<f32> {
    let w = bead_words(key, step_lo, step_hi, bead);
    let first = box_muller(w.x, w.y);
    let second = box_muller(w.z, w.w);
    if (bead & 1u) == 0u {
        return vec3<f32>(first, second.x);
    }
    return vec3<f32>(first.y, second);
}
