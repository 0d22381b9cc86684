// One Brownian step of a batch of independent polymers (replicas), the model of
// src/sim/polymer.rs in single precision. noise.wgsl is prepended.
//
// Per step the host records: clear the cell counts, `bin` (every bead into its cell's slots),
// `advance` (each bead sums its own forces, pair forces through the 27 neighbour cells, and moves).
// Each invocation writes only its own bead, and pair forces are summed in fixed point (integer
// addition is associative), so the result does not depend on the order in which beads land in
// a cell: the same seed gives the same trajectory on a given device.

struct Params {
    n_total: u32,          // beads in the batch
    n_per_replica: u32,    // beads of one replica
    grid_mode: u32,        // 0: hashed cells; 1: a periodic cube of grid^3 cells; 2: a cube of
                           // grid^3 cells from `origin` (beads outside go to its edge cells)
    grid: u32,             // cells per side of the cube
    table_mask: u32,       // hashed cells: buckets - 1 (a power of two)
    slots: u32,            // bead slots per cell
    cells_per_replica: u32,// cube: grid^3
    dedupe: u32,           // 1: two of the 27 neighbour cells may be one bucket
    n_buckets: u32,        // cells or buckets in all (the overflow word follows them)
    inv_cell: f32,         // 1 / cell side
    side: f32,             // periodic cube side (0: open space)
    cutoff2: f32,          // squared range of the pair forces (0: none)
    dt: f32,
    noise: f32,            // sqrt(2 dt)
    repulsion: u32,        // 0 none, 1 polynomial, 2 WCA
    rep_energy: f32,       // polynomial height / WCA epsilon
    rep_radius: f32,       // polynomial radius / WCA sigma
    attraction: u32,       // 1: beads of one type attract
    att_energy: f32,
    att_radius: f32,
    bond: u32,             // 0 harmonic, 1 FENE
    bond_a: f32,           // harmonic rest length / FENE K
    bond_b: f32,           // harmonic wiggle / FENE R0
    angle_k: f32,
    sphere: u32,           // 1: spherical wall
    sphere_radius: f32,
    sphere_k: f32,
    extra_length: f32,     // extra (loop-extrusion) bonds: rest length
    extra_wiggle: f32,     // and wiggle
    excluded: u32,         // |i - j| <= excluded on one chain: no pair force
    origin: f32,           // bounded cube: its lowest corner on every axis
    pad1: u32,
}

struct Clock {
    base_lo: u32,
    base_hi: u32,
    pad0: u32,
    pad1: u32,
}

struct Tick {
    step: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> clock: Clock;
@group(0) @binding(2) var<uniform> tick: Tick;
@group(0) @binding(3) var<storage, read> pos_in: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> pos_out: array<vec4<f32>>;
// x: bit 0 bonded to the previous bead, bit 1 to the next, bits 8-15 the type; y: chain id;
// z: the bead's cell at the last `bin`.
@group(0) @binding(5) var<storage, read_write> info: array<vec4<u32>>;
@group(0) @binding(6) var<storage, read> keys: array<vec2<u32>>;
// Extra bonds as compressed rows: offsets (n_total + 1), then the partners.
@group(0) @binding(7) var<storage, read> extra: array<u32>;
@group(0) @binding(8) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(9) var<storage, read_write> cell_slots: array<u32>;
// The counts of the previous step, zeroed for the next one.
@group(0) @binding(10) var<storage, read_write> stale: array<atomic<u32>>;

const WORKGROUP: u32 = 128u;
// Pair forces are summed as integers in units of 1 / FIXED (kT / b); one pair's force is held
// within +-PAIR_CAP, so up to ~500 neighbours fit in an i32.
const FIXED: f32 = 4096.0;
const PAIR_CAP: f32 = 1.0e3;
// Polynomial repulsion constant m = 6^6 / 7^7.
const POLY_MIN: f32 = 0.05665287;
const PI: f32 = 3.141592653589793;

fn bead_index(gid: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return gid.x + gid.y * nwg.x * WORKGROUP;
}

fn cell_of(p: vec3<f32>) -> vec3<i32> {
    let g = i32(params.grid) - 1;
    if params.grid_mode == 1u {
        let w = p - params.side * floor(p / params.side);
        return min(vec3<i32>(floor(w * params.inv_cell)), vec3<i32>(g));
    }
    if params.grid_mode == 2u {
        // Clamping keeps every pair within range in neighbouring (or the same) cells.
        let c = floor((p - vec3<f32>(params.origin)) * params.inv_cell);
        return vec3<i32>(clamp(c, vec3<f32>(0.0), vec3<f32>(f32(g))));
    }
    return vec3<i32>(floor(p * params.inv_cell));
}

// Whether neighbour cell `c` exists (outside a bounded cube it does not).
fn cell_exists(c: vec3<i32>) -> bool {
    if params.grid_mode != 2u {
        return true;
    }
    let g = i32(params.grid);
    return all(c >= vec3<i32>(0)) && all(c < vec3<i32>(g));
}

fn bucket_of(c: vec3<i32>, replica: u32) -> u32 {
    let g = i32(params.grid);
    if params.grid_mode == 1u {
        let w = ((c % g) + g) % g;
        return replica * params.cells_per_replica + u32((w.x * g + w.y) * g + w.z);
    }
    if params.grid_mode == 2u {
        return replica * params.cells_per_replica + u32((c.x * g + c.y) * g + c.z);
    }
    var h = (u32(c.x) * 73856093u) ^ (u32(c.y) * 19349663u) ^ (u32(c.z) * 83492791u)
        ^ (replica * 2654435761u);
    h ^= h >> 16u;
    h *= 0x7feb352du;
    h ^= h >> 15u;
    h *= 0x846ca68bu;
    h ^= h >> 16u;
    return h & params.table_mask;
}

@compute @workgroup_size(128)
fn bin(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = bead_index(gid, nwg);
    if i >= params.n_total {
        return;
    }
    let replica = i / params.n_per_replica;
    atomicStore(&stale[info[i].z], 0u);
    let b = bucket_of(cell_of(pos_in[i].xyz), replica);
    info[i].z = b;
    let slot = atomicAdd(&counts[b], 1u);
    if slot < params.slots {
        cell_slots[b * params.slots + slot] = i;
    } else {
        // The host reads the largest occupancy seen and re-runs the batch with more slots.
        atomicMax(&counts[params.n_buckets], slot + 1u);
    }
}

// -(dE/dr) / r of a chain bond at squared length r2.
fn bond_factor(r2: f32) -> f32 {
    if params.bond == 0u {
        let r = sqrt(r2);
        if r <= 0.0 {
            return 0.0;
        }
        return -2.0 * (r - params.bond_a) / (params.bond_b * params.bond_b) / r;
    }
    let ratio2 = min(r2 / (params.bond_b * params.bond_b), 0.98);
    return -params.bond_a / (1.0 - ratio2);
}

fn extra_factor(r2: f32) -> f32 {
    let r = sqrt(r2);
    if r <= 0.0 {
        return 0.0;
    }
    return -2.0 * (r - params.extra_length) / (params.extra_wiggle * params.extra_wiggle) / r;
}

// -(dE/dr) / r of a non-bonded pair at squared distance r2.
fn pair_factor(r2: f32, same_type: bool) -> f32 {
    var factor = 0.0;
    if params.repulsion == 1u {
        let sigma2 = params.rep_radius * params.rep_radius;
        if r2 < sigma2 {
            let x = 6.0 / 7.0 * r2 / sigma2;
            let x5 = x * x * x * x * x;
            let x6 = x5 * x;
            factor -= params.rep_energy / POLY_MIN * (7.0 * x6 - 6.0 * x5) * 2.0 * (6.0 / 7.0) / sigma2;
        }
    } else if params.repulsion == 2u {
        let sigma2 = params.rep_radius * params.rep_radius;
        if r2 < sigma2 * 1.2599210498948732 {
            let s2 = sigma2 / r2;
            let s6 = s2 * s2 * s2;
            factor += 24.0 * params.rep_energy * (2.0 * s6 * s6 - s6) / r2;
        }
    }
    if same_type && r2 < params.att_radius * params.att_radius && r2 > 1.0 {
        let r = sqrt(r2);
        let phase = PI * (r - 1.0) / (params.att_radius - 1.0);
        let slope = params.att_energy * PI * sin(phase) / (2.0 * (params.att_radius - 1.0));
        factor -= slope / r;
    }
    return factor;
}

// The force of the angle centred at bead c (beads c - 1, c, c + 1) on its bead `role`
// (0, 1 or 2), E = k (1 - cos theta).
fn angle_force(c: u32, role: u32) -> vec3<f32> {
    let p0 = pos_in[c - 1u].xyz;
    let p1 = pos_in[c].xyz;
    let p2 = pos_in[c + 1u].xyz;
    let b1 = p1 - p0;
    let b2 = p2 - p1;
    let l1 = length(b1);
    let l2 = length(b2);
    if l1 == 0.0 || l2 == 0.0 {
        return vec3<f32>(0.0);
    }
    let cosine = dot(b1, b2) / (l1 * l2);
    let d1 = b2 / (l1 * l2) - cosine * b1 / (l1 * l1);
    let d2 = b1 / (l1 * l2) - cosine * b2 / (l2 * l2);
    let k = params.angle_k;
    if role == 0u {
        return -k * d1;
    }
    if role == 1u {
        return k * (d1 - d2);
    }
    return k * d2;
}

fn has_angle(c: u32) -> bool {
    return (info[c].x & 3u) == 3u;
}

fn bonded_force(i: u32, p: vec3<f32>) -> vec3<f32> {
    var f = vec3<f32>(0.0);
    let flags = info[i].x;
    if (flags & 1u) != 0u {
        let d = p - pos_in[i - 1u].xyz;
        f += bond_factor(dot(d, d)) * d;
    }
    if (flags & 2u) != 0u {
        let d = p - pos_in[i + 1u].xyz;
        f += bond_factor(dot(d, d)) * d;
    }
    let first = extra[i];
    let last = extra[i + 1u];
    for (var k = first; k < last; k++) {
        let d = p - pos_in[extra[k]].xyz;
        f += extra_factor(dot(d, d)) * d;
    }
    if params.angle_k > 0.0 {
        if (flags & 1u) != 0u && has_angle(i - 1u) {
            f += angle_force(i - 1u, 2u);
        }
        if (flags & 3u) == 3u {
            f += angle_force(i, 1u);
        }
        if (flags & 2u) != 0u && has_angle(i + 1u) {
            f += angle_force(i + 1u, 0u);
        }
    }
    if params.sphere == 1u {
        let r = length(p);
        if r > params.sphere_radius {
            f += -2.0 * params.sphere_k * (r - params.sphere_radius) / r * p;
        }
    }
    return f;
}

fn pair_force(i: u32, p: vec3<f32>) -> vec3<f32> {
    if params.cutoff2 <= 0.0 {
        return vec3<f32>(0.0);
    }
    let replica = i / params.n_per_replica;
    let me = info[i];
    let my_type = (me.x >> 8u) & 255u;
    let c = cell_of(p);
    var seen: array<u32, 27>;
    var n_seen = 0u;
    var sum = vec3<i32>(0);
    for (var dz = -1; dz <= 1; dz++) {
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let neighbour = c + vec3<i32>(dx, dy, dz);
                if !cell_exists(neighbour) {
                    continue;
                }
                let b = bucket_of(neighbour, replica);
                if params.dedupe == 1u {
                    var repeated = false;
                    for (var k = 0u; k < n_seen; k++) {
                        if seen[k] == b {
                            repeated = true;
                            break;
                        }
                    }
                    if repeated {
                        continue;
                    }
                    seen[n_seen] = b;
                    n_seen++;
                }
                let n = min(atomicLoad(&counts[b]), params.slots);
                for (var s = 0u; s < n; s++) {
                    let j = cell_slots[b * params.slots + s];
                    if j == i {
                        continue;
                    }
                    var d = p - pos_in[j].xyz;
                    if params.side > 0.0 {
                        d -= params.side * round(d / params.side);
                    }
                    let r2 = dot(d, d);
                    if r2 >= params.cutoff2 {
                        continue;
                    }
                    let other = info[j];
                    if j / params.n_per_replica != replica {
                        continue;
                    }
                    let gap = max(i, j) - min(i, j);
                    if other.y == me.y && gap <= params.excluded {
                        continue;
                    }
                    let same_type = params.attraction == 1u && ((other.x >> 8u) & 255u) == my_type;
                    let f = clamp(pair_factor(r2, same_type) * d, vec3<f32>(-PAIR_CAP), vec3<f32>(PAIR_CAP));
                    sum += vec3<i32>(round(f * FIXED));
                }
            }
        }
    }
    return vec3<f32>(sum) * (1.0 / FIXED);
}

@compute @workgroup_size(128)
fn advance(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = bead_index(gid, nwg);
    if i >= params.n_total {
        return;
    }
    let p = pos_in[i].xyz;
    let f = bonded_force(i, p) + pair_force(i, p);
    let replica = i / params.n_per_replica;
    let step_lo = clock.base_lo + tick.step;
    let step_hi = clock.base_hi + select(0u, 1u, step_lo < clock.base_lo);
    let z = bead_normals(keys[replica], step_lo, step_hi, i - replica * params.n_per_replica);
    pos_out[i] = vec4<f32>(p + f * params.dt + params.noise * z, 0.0);
}

// The four noise words of every bead at the clock's step, as bits, into pos_out (checked
// against src/sim/noise.rs).
@compute @workgroup_size(128)
fn noise_words(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = bead_index(gid, nwg);
    if i >= params.n_total {
        return;
    }
    let replica = i / params.n_per_replica;
    let w = bead_words(keys[replica], clock.base_lo + tick.step, clock.base_hi, i - replica * params.n_per_replica);
    pos_out[i] = bitcast<vec4<f32>>(w);
}
