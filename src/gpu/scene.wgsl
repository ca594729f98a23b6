// scene.wgsl — scene buffers (their structs generated from gpu::layout into the prelude,
// checked by naga reflection in tests/gpu.rs), the traversal entry (`traverse`: the BVH2
// here, or the compressed wide BVH of cwbvh.wgsl by `BVH_WIDE`) with a short stack, and the
// watertight triangle test.
// Twin of src/bvh.rs (the CPU walks its own wide BVH over the same triangles; closest hits
// agree).

// struct BvhNode: generated from `gpu::layout::BvhNode` (the prelude).

// A triangle in BVH leaf order (slot k = bvh2.primitive_indices[k]).
// struct Triangle: generated from `gpu::layout::Triangle` (the prelude).

// struct Vertex: generated from `gpu::layout::Vertex` (the prelude).

// struct Material: generated from `gpu::layout::Material` (the prelude).

// One entry of the light distribution, `kind` = LIGHT_*; light.wgsl interprets it.
// struct Light: generated from `gpu::layout::Light` (the prelude).

// The tree's nodes as 16-byte words: a BVH2 node is two (`bvh2_node`), a CWBVH node five
// (`cw_node` in cwbvh.wgsl); `BVH_WIDE` says which tree `upload::GpuBvh` put here.
@group(0) @binding(1) var<storage, read> nodes: array<vec4<u32>>;
@group(0) @binding(2) var<storage, read> triangles: array<Triangle>;
@group(0) @binding(3) var<storage, read> vertices: array<Vertex>;
@group(0) @binding(4) var<storage, read> materials: array<Material>;
@group(0) @binding(5) var<storage, read> lights: array<Light>;
// Texture references and texels in one buffer (gpu::upload::pack_textures): reference slot r
// occupies vec4s 3r .. 3r + 3 (header, matrix, translation), texels follow (linear RGBA).
@group(0) @binding(8) var<storage, read> texels: array<vec4<f32>>;

struct Hit {
    found: bool,
    t: f32,
    // Leaf slot of the triangle.
    slot: u32,
    b1: f32,
    b2: f32,
}

// Per-ray constants of the watertight test: Woop, Benthin & Wald 2013, "Watertight
// Ray/Triangle Intersection" (JCGT 2(1)), §3 (axis permutation and shear).
struct WatertightRay {
    org: vec3<f32>,
    kx: u32,
    ky: u32,
    kz: u32,
    sx: f32,
    sy: f32,
    sz: f32,
}

fn watertight_ray_new(org: vec3<f32>, dir: vec3<f32>) -> WatertightRay {
    let a = abs(dir);
    var kz = 2u;
    if a.x > a.y {
        if a.x > a.z {
            kz = 0u;
        }
    } else if a.y > a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    if dir[kz] < 0.0 {
        let tmp = kx;
        kx = ky;
        ky = tmp;
    }
    return WatertightRay(org, kx, ky, kz, dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]);
}

// a·b − c·d with one rounding error (replaces the CPU's f64 re-evaluation, which WGSL lacks).
// Kahan's difference of products; Jeannerod, Louvet & Muller 2013, Math. Comp. 82(284).
fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let err = fma(-c, d, cd);
    let dop = fma(a, b, -cd);
    return dop + err;
}

// Returns (t, b1, b2) or None. Woop et al. 2013, algorithm of §3 (no back-face culling);
// exact-zero edge functions are re-evaluated with `difference_of_products` (§3.3).
fn watertight_ray_intersect(r: WatertightRay, tri: Triangle, tmax: f32) -> vec4<f32> {
    let a = v3(tri.p0) - r.org;
    let b = v3(tri.p1) - r.org;
    let c = v3(tri.p2) - r.org;
    let ax = a[r.kx] - r.sx * a[r.kz];
    let ay = a[r.ky] - r.sy * a[r.kz];
    let bx = b[r.kx] - r.sx * b[r.kz];
    let by = b[r.ky] - r.sy * b[r.kz];
    let cx = c[r.kx] - r.sx * c[r.kz];
    let cy = c[r.ky] - r.sy * c[r.kz];
    var u = cx * by - cy * bx;
    var v = ax * cy - ay * cx;
    var w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        u = difference_of_products(cx, by, cy, bx);
        v = difference_of_products(ax, cy, ay, cx);
        w = difference_of_products(bx, ay, by, ax);
    }
    let miss = vec4<f32>(0.0, 0.0, 0.0, -1.0);
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return miss;
    }
    let det = u + v + w;
    if det == 0.0 {
        return miss;
    }
    let az = r.sz * a[r.kz];
    let bz = r.sz * b[r.kz];
    let cz = r.sz * c[r.kz];
    let t_scaled = u * az + v * bz + w * cz;
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    if !(t > 0.0 && t < tmax) {
        return miss;
    }
    return vec4<f32>(t, v * inv, w * inv, 1.0);
}

// Slab test; far distance widened by 1 + 2γ₃ so boxes never miss a hit on their faces.
// Ize 2013, "Robust BVH Ray Traversal" (JCGT 2(2)), §3. An axis the ray does not move along
// (`ray_inv_dir`'s ±F32_MAX) constrains nothing when the origin lies in its slab, faces
// included, and excludes the box otherwise — the CPU's NaN-ignoring min/max (bvh::slab): with
// the finite stand-in alone, a ray lying in a box's face plane got the distance 0 there and
// missed boxes ahead of it (tests/gpu_bvh.rs, rays in box faces).
fn ray_box(lo: vec3<f32>, hi: vec3<f32>, org: vec3<f32>, inv_d: vec3<f32>, tmax: f32) -> f32 {
    let flat = abs(inv_d) == vec3<f32>(F32_MAX);
    if any(flat & ((org < lo) | (org > hi))) {
        return F32_MAX;
    }
    let t0 = (lo - org) * inv_d;
    let t1 = (hi - org) * inv_d;
    let tn = select(min(t0, t1), vec3<f32>(-F32_MAX), flat);
    let tf = select(max(t0, t1), vec3<f32>(F32_MAX), flat);
    let tnear = max(max(tn.x, tn.y), max(tn.z, 0.0));
    let tfar = min(min(tf.x, tf.y), min(tf.z, tmax)) * 1.0000004;
    if tnear <= tfar {
        return tnear;
    }
    return F32_MAX;
}

// Words of each invocation's traversal stack (override; `Specialization::bvh_stack`): for the
// BVH2 one per entry, the uploaded tree's depth rounded up to a multiple of 8, at most 64
// (gpu::upload checks the depth); for the CWBVH two per node group
// (`upload::cwbvh_stack_words`). An ordered traversal holds at most one entry per level above
// the current node, so the depth bounds it; sized to the scene, the stack takes no more
// workgroup memory than the tree needs (the memory that limits occupancy: docs/gpu.md
// "Register pressure").
override BVH_STACK_SIZE: u32 = 64u;
// The workgroup's stacks (a named override: naga cannot specialise an array size written as
// an override expression).
override BVH_STACK_WORDS: u32 = BVH_STACK_SIZE * WORKGROUP_LANES;

// Invocations per workgroup of every kernel that traverses (8×8 or 64×1).
const WORKGROUP_LANES: u32 = 64u;

// The traversal stacks of the workgroup's invocations live in workgroup memory, not in
// registers: a 64-entry array per invocation held 64 VGPRs and was zeroed on every call
// (WGSL zero-initialises function variables). Entry i of lane l is at i·64 + l, so the lanes
// of a wave touch distinct banks. Each lane only ever reads its own entries: no barrier.
var<workgroup> BVH_STACK: array<u32, BVH_STACK_WORDS>;
// This invocation's lane (local_invocation_index), set first thing by every entry point.
var<private> LANE: u32;

// The tree is the compressed 8-wide BVH (cwbvh.wgsl), not the BVH2 (override;
// `Specialization::bvh_wide`).
override BVH_WIDE: bool = true;

// Traversal work of the BVH probe (bvh_probe.wgsl sets BVH_COUNT; every other kernel leaves
// it false, so the counting compiles out): node records visited, child boxes tested,
// triangles tested.
override BVH_COUNT: bool = false;
var<private> BVH_WORK: vec3<u32>;

fn bvh_count(nodes_visited: u32, boxes: u32, tris: u32) {
    if BVH_COUNT {
        BVH_WORK += vec3<u32>(nodes_visited, boxes, tris);
    }
}

// BVH2 node i.
fn bvh2_node(i: u32) -> BvhNode {
    let a = nodes[2u * i];
    let b = nodes[2u * i + 1u];
    let lo = array<f32, 3>(bitcast<f32>(a.x), bitcast<f32>(a.y), bitcast<f32>(a.z));
    let hi = array<f32, 3>(bitcast<f32>(b.x), bitcast<f32>(b.y), bitcast<f32>(b.z));
    return BvhNode(lo, a.w, hi, b.w);
}

// 1/dir for the slab tests. 1/±0 = ±Inf is what the slab test wants; WGSL gives an
// indeterminate value there, so substitute a huge finite reciprocal of the right sign.
fn ray_inv_dir(dir: vec3<f32>) -> vec3<f32> {
    var inv_d: vec3<f32>;
    for (var k = 0u; k < 3u; k++) {
        if dir[k] == 0.0 {
            inv_d[k] = select(F32_MAX, -F32_MAX, bitcast<u32>(dir[k]) != 0u);
        } else {
            inv_d[k] = 1.0 / dir[k];
        }
    }
    return inv_d;
}

// Closest hit (any_hit = false) or first hit (any_hit = true) along org + t·dir, t ∈ (0, tmax).
fn traverse(org: vec3<f32>, dir: vec3<f32>, tmax_in: f32, any_hit: bool) -> Hit {
    if BVH_WIDE {
        return traverse_cwbvh(org, dir, tmax_in, any_hit);
    }
    return traverse_bvh2(org, dir, tmax_in, any_hit);
}

// `traverse` over the BVH2: the nearer child first, the farther one on the stack.
fn traverse_bvh2(org: vec3<f32>, dir: vec3<f32>, tmax_in: f32, any_hit: bool) -> Hit {
    var hit = Hit(false, tmax_in, 0u, 0.0, 0.0);
    let wr = watertight_ray_new(org, dir);
    let inv_d = ray_inv_dir(dir);
    var sp = 0u;
    var node = 0u;
    let root = bvh2_node(0u);
    bvh_count(0u, 1u, 0u);
    if ray_box(v3(root.lo), v3(root.hi), org, inv_d, hit.t) == F32_MAX {
        return hit;
    }
    loop {
        let n = bvh2_node(node);
        bvh_count(1u, 0u, 0u);
        if n.prim_count > 0u {
            for (var i = 0u; i < n.prim_count; i++) {
                let slot = n.first_index + i;
                bvh_count(0u, 0u, 1u);
                let r = watertight_ray_intersect(wr, triangles[slot], hit.t);
                if r.w > 0.0 {
                    hit = Hit(true, r.x, slot, r.y, r.z);
                    if any_hit {
                        return hit;
                    }
                }
            }
        } else {
            let l = n.first_index;
            let nl = bvh2_node(l);
            let nr = bvh2_node(l + 1u);
            bvh_count(0u, 2u, 0u);
            let tl = ray_box(v3(nl.lo), v3(nl.hi), org, inv_d, hit.t);
            let tr = ray_box(v3(nr.lo), v3(nr.hi), org, inv_d, hit.t);
            let hl = tl != F32_MAX;
            let hr = tr != F32_MAX;
            if hl && hr {
                var near = l;
                var far = l + 1u;
                if tr < tl {
                    near = l + 1u;
                    far = l;
                }
                if sp < BVH_STACK_SIZE {
                    BVH_STACK[sp * WORKGROUP_LANES + LANE] = far;
                    sp++;
                }
                node = near;
                continue;
            } else if hl {
                node = l;
                continue;
            } else if hr {
                node = l + 1u;
                continue;
            }
        }
        if sp == 0u {
            break;
        }
        sp--;
        node = BVH_STACK[sp * WORKGROUP_LANES + LANE];
    }
    return hit;
}

// Closest hit along origin + t·dir for t in (0, tmax). Twin of `Bvh::intersect`.
fn bvh_intersect(origin: vec3<f32>, dir: vec3<f32>, tmax: f32) -> Hit {
    return traverse(origin, dir, tmax, false);
}

// True if anything is hit along origin + t·dir for t in (0, tmax). Twin of `Bvh::occluded`.
fn bvh_occluded(origin: vec3<f32>, dir: vec3<f32>, tmax: f32) -> bool {
    return traverse(origin, dir, tmax, true).found;
}

// ---------------------------------------------------------------------------------------------
// Textures (scene::material::sample_texture)

override HAS_TEXTURES: bool = true;

// i mod n in [0, n) (n > 0) with only non-negative operands of `%`: GLSL leaves `%` of a
// negative operand undefined, and on wgpu's GL backend (llvmpipe) a bilinear lookup across a
// repeating edge read row 0 instead of the last row (tests/light_twin.rs on GL).
fn mod_floor(i: i32, n: i32) -> i32 {
    if i >= 0 {
        return i % n;
    }
    return n - 1 - (-(i + 1)) % n;
}

// `wrap_index` of scene::material (i64 there; i32 here: |uv · size| < 2³¹).
fn wrap_index(i: i32, n: u32, w: u32) -> u32 {
    let nn = i32(n);
    var r: i32;
    if w == WRAP_CLAMP_TO_EDGE {
        r = clamp(i, 0, nn - 1);
    } else if w == WRAP_MIRRORED_REPEAT {
        let p = 2 * nn;
        let m = mod_floor(i, p);
        if m < nn {
            r = m;
        } else {
            r = p - 1 - m;
        }
    } else {
        r = mod_floor(i, nn);
    }
    return u32(r);
}

fn texture_texel(offset: u32, width: u32, height: u32, flags: u32, x: i32, y: i32) -> vec4<f32> {
    let xi = wrap_index(x, width, flags & 3u);
    let yi = wrap_index(y, height, (flags >> 2u) & 3u);
    return texels[offset + yi * width + xi];
}

// Look a texture up at `uv` (wrap mode, nearest or bilinear). Missing texture → white.
fn sample_texture(slot: u32, uv_in: vec2<f32>) -> vec4<f32> {
    let one = vec4<f32>(1.0);
    if !HAS_TEXTURES || slot == NO_TEXTURE {
        return one;
    }
    let head = bitcast<vec4<u32>>(texels[3u * slot]);
    let offset = head.x;
    let width = head.y;
    let height = head.z;
    let flags = head.w;
    if (flags & TEX_VALID) == 0u {
        return one;
    }
    // Affine2::transform_point2: matrix2 · uv + translation (glam column order).
    let mtx = texels[3u * slot + 1u];
    let tr = texels[3u * slot + 2u];
    let uv = vec2<f32>(mtx.x, mtx.y) * uv_in.x + vec2<f32>(mtx.z, mtx.w) * uv_in.y + tr.xy;
    let fx = uv.x * f32(width) - 0.5;
    let fy = uv.y * f32(height) - 0.5;
    if !is_finite_f32(fx) || !is_finite_f32(fy) {
        return one;
    }
    if (flags & TEX_LINEAR) != 0u {
        let x0 = floor(fx);
        let y0 = floor(fy);
        let ax = fx - x0;
        let ay = fy - y0;
        let xi = i32(x0);
        let yi = i32(y0);
        let top = texture_texel(offset, width, height, flags, xi, yi) * (1.0 - ax) + texture_texel(offset, width, height, flags, xi + 1, yi) * ax;
        let bot = texture_texel(offset, width, height, flags, xi, yi + 1) * (1.0 - ax) + texture_texel(offset, width, height, flags, xi + 1, yi + 1) * ax;
        return top * (1.0 - ay) + bot * ay;
    }
    return texture_texel(offset, width, height, flags, i32(floor(fx + 0.5)), i32(floor(fy + 0.5)));
}
