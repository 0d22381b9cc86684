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

// The four words of `bead` at the step (lo, hi): counters (lo, 2 bead) and (lo, 2 bead + 1)
// under the key whose second word is xored with the step's high word.
fn bead_words(key: vec2<u32>, step_lo: u32, step_hi: u32, bead: u32) -> vec4<u32> {
    let k = vec2<u32>(key.x, key.y ^ step_hi);
    let ab = threefry(k, vec2<u32>(step_lo, bead * 2u));
    let cd = threefry(k, vec2<u32>(step_lo, bead * 2u + 1u));
    return vec4<u32>(ab, cd);
}

fn unit_uniform(w: u32) -> f32 {
    return (f32(w >> 8u) + 0.5) * (1.0 / 16777216.0);
}

// Three standard normals (Box-Muller on the four words).
fn bead_normals(key: vec2<u32>, step_lo: u32, step_hi: u32, bead: u32) -> vec3<f32> {
    let w = bead_words(key, step_lo, step_hi, bead);
    let r1 = sqrt(-2.0 * log(unit_uniform(w.x)));
    let r2 = sqrt(-2.0 * log(unit_uniform(w.z)));
    let t1 = 6.283185307179586 * unit_uniform(w.y);
    let t2 = 6.283185307179586 * unit_uniform(w.w);
    return vec3<f32>(r1 * cos(t1), r1 * sin(t1), r2 * cos(t2));
}
