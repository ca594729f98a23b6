// cwbvh.wgsl — closest-hit and occlusion traversal of the compressed 8-wide BVH
// (gpu::upload::cwbvh): Ylitie, Karras & Laine 2017, "Efficient Incoherent Ray Traversal on
// GPUs Through Compressed Wide BVHs" (HPG), Algorithm 1. The state is a node group (the base
// index of a node's inner children, a hit bit per child in octant order in bits 24..31, the
// node's imask in bits 0..7) and a triangle group (first slot, a hit bit per triangle in bits
// 0..23); node groups wait on the short workgroup stack of scene.wgsl, two words each.
// Children are visited in the order their slots take for the ray's octant (§3.2: slot c is
// bit 24 + (c XOR oct), highest first), not sorted by distance. Occlusion rays stop at the
// first hit. No triangle postponing (§4): one loop, triangles of a node right after it.

// Layout: gpu::layout::CwNode (read as five 16-byte words: `cw_node`; the child planes
// `q_*` are read child by child in `cw_intersect`).
struct CwNode {
    p: array<f32, 3>,
    e_imask: u32,
    child_base: u32,
    prim_base: u32,
    child_meta: array<u32, 2>,
    q_x: vec4<u32>,
    q_y: vec4<u32>,
    q_z: vec4<u32>,
}

fn cw_node(i: u32) -> CwNode {
    let a = nodes[5u * i];
    let b = nodes[5u * i + 1u];
    let p = array<f32, 3>(bitcast<f32>(a.x), bitcast<f32>(a.y), bitcast<f32>(a.z));
    let child_meta = array<u32, 2>(b.z, b.w);
    return CwNode(p, a.w, b.x, b.y, child_meta, nodes[5u * i + 2u], nodes[5u * i + 3u], nodes[5u * i + 4u]);
}

// The grid step 2^(b − 127) of exponent byte b.
fn cw_step(b: u32) -> f32 {
    return bitcast<f32>((b & 255u) << 23u);
}

// Byte `shift / 8` of each of three words, as floats.
fn cw_bytes3(x: u32, y: u32, z: u32, shift: u32) -> vec3<f32> {
    return vec3<f32>(vec3<u32>(x, y, z) >> vec3<u32>(shift) & vec3<u32>(255u));
}

// Test the four children of a half at once in vec4s (`cw_intersect_x4`): on for
// CPU-emulated adapters (`Specialization::bvh_x4`, from `GpuContext::is_software`), off on
// GPUs (docs/gpu.md "The wide BVH").
override BVH_CHILDREN_X4: bool = false;

// Hit bits of the children of node `i` (`n`) within (0, tmax): inner child c as bit
// 24 + (c XOR oct), a leaf child as its triangles' bits (its count in unary, shifted by its
// offset from `prim_base`). Each child's box is tested by `ray_box`, the BVH2's test (Ize
// 2013), on its decoded planes p + e·q — e a power of two, so e·q is exact and the plane
// rounds once, to the value upload::cwbvh checked to enclose the child (`decode`).
// Children 0–3, then 4–7, each half's six plane words read from the buffer as it starts.
// Register pressure and memory reads traded off (RADV navi21, cornell-glass `render`; the
// BVH2 kernel takes 96 VGPRs): the four children of a half at once in vec4s took 152 VGPRs;
// one child at a time, the whole node's planes in registers 104; each child's own bytes read
// from the buffer 88, but 48 reads per node, which made lavapipe (a read per lane) slower
// than with the BVH2; this form 96 with 12 reads. On a CPU-emulated adapter, where a read
// is a gather per lane and divergent branches run both sides, the vec4 form is the faster
// one, and registers do not bound occupancy: `BVH_CHILDREN_X4` picks it there.
fn cw_intersect(n: CwNode, i: u32, org: vec3<f32>, inv_d: vec3<f32>, tmax: f32, oct: u32) -> u32 {
    if BVH_CHILDREN_X4 {
        return cw_intersect_x4(n, org, inv_d, tmax, oct);
    }
    let p = v3(n.p);
    let e = vec3<f32>(cw_step(n.e_imask), cw_step(n.e_imask >> 8u), cw_step(n.e_imask >> 16u));
    let imask = n.e_imask >> 24u;
    let q = 5u * i + 2u;
    var hits = 0u;
    for (var h = 0u; h < 2u; h++) {
        let lx = nodes[q][h];
        let ly = nodes[q + 1u][h];
        let lz = nodes[q + 2u][h];
        let hx = nodes[q][2u + h];
        let hy = nodes[q + 1u][2u + h];
        let hz = nodes[q + 2u][2u + h];
        for (var k = 0u; k < 4u; k++) {
            let c = 4u * h + k;
            let shift = 8u * k;
            let m = (n.child_meta[h] >> shift) & 255u;
            if m == 0u {
                continue;
            }
            bvh_count(0u, 1u, 0u);
            let lo = p + e * cw_bytes3(lx, ly, lz, shift);
            let hi = p + e * cw_bytes3(hx, hy, hz, shift);
            if ray_box(lo, hi, org, inv_d, tmax) == F32_MAX {
                continue;
            }
            if ((imask >> c) & 1u) != 0u {
                hits |= 1u << (24u + (c ^ oct));
            } else {
                hits |= (m >> 5u) << (m & 31u);
            }
        }
    }
    return hits;
}

// The four bytes of w, low first, as floats.
fn cw_bytes(w: u32) -> vec4<f32> {
    return vec4<f32>(vec4<u32>(w, w >> 8u, w >> 16u, w >> 24u) & vec4<u32>(255u));
}

// Children 4h … 4h + 3 of `n` hit within (0, tmax): `ray_box` (Ize 2013, far distance
// widened by 1 + 2γ₃; axes the ray does not move along by the origin's place in the slab) on
// the decoded planes p + e·q — e a power of two, so e·q is exact and the plane rounds once,
// to the value upload::cwbvh checked to enclose the child (`decode`).
fn cw_hit4(n: CwNode, h: u32, org: vec3<f32>, inv_d: vec3<f32>, tmax: f32) -> vec4<bool> {
    let p = v3(n.p);
    let ex = cw_step(n.e_imask);
    let ey = cw_step(n.e_imask >> 8u);
    let ez = cw_step(n.e_imask >> 16u);
    let lx = p.x + ex * cw_bytes(n.q_x[h]);
    let hx = p.x + ex * cw_bytes(n.q_x[2u + h]);
    let ly = p.y + ey * cw_bytes(n.q_y[h]);
    let hy = p.y + ey * cw_bytes(n.q_y[2u + h]);
    let lz = p.z + ez * cw_bytes(n.q_z[h]);
    let hz = p.z + ez * cw_bytes(n.q_z[2u + h]);
    let t0x = (lx - org.x) * inv_d.x;
    let t1x = (hx - org.x) * inv_d.x;
    let t0y = (ly - org.y) * inv_d.y;
    let t1y = (hy - org.y) * inv_d.y;
    let t0z = (lz - org.z) * inv_d.z;
    let t1z = (hz - org.z) * inv_d.z;
    let flat = abs(inv_d) == vec3<f32>(F32_MAX);
    let big = vec4<f32>(F32_MAX);
    let tnx = select(min(t0x, t1x), -big, flat.x);
    let tny = select(min(t0y, t1y), -big, flat.y);
    let tnz = select(min(t0z, t1z), -big, flat.z);
    let tfx = select(max(t0x, t1x), big, flat.x);
    let tfy = select(max(t0y, t1y), big, flat.y);
    let tfz = select(max(t0z, t1z), big, flat.z);
    let tnear = max(max(tnx, tny), max(tnz, vec4<f32>(0.0)));
    let tfar = min(min(tfx, tfy), min(tfz, vec4<f32>(tmax))) * 1.0000004;
    let in_x = vec4<bool>(!flat.x) | ((lx <= vec4<f32>(org.x)) & (vec4<f32>(org.x) <= hx));
    let in_y = vec4<bool>(!flat.y) | ((ly <= vec4<f32>(org.y)) & (vec4<f32>(org.y) <= hy));
    let in_z = vec4<bool>(!flat.z) | ((lz <= vec4<f32>(org.z)) & (vec4<f32>(org.z) <= hz));
    return (tnear <= tfar) & in_x & in_y & in_z;
}

// `cw_intersect` with the four children of a half tested at once in vec4s (`cw_hit4`): the
// same boxes, the same hit bits.
fn cw_intersect_x4(n: CwNode, org: vec3<f32>, inv_d: vec3<f32>, tmax: f32, oct: u32) -> u32 {
    let imask = n.e_imask >> 24u;
    var hits = 0u;
    for (var h = 0u; h < 2u; h++) {
        let hit = cw_hit4(n, h, org, inv_d, tmax);
        let metas = n.child_meta[h];
        for (var k = 0u; k < 4u; k++) {
            let m = (metas >> (8u * k)) & 255u;
            if m == 0u {
                continue;
            }
            bvh_count(0u, 1u, 0u);
            if !hit[k] {
                continue;
            }
            let c = 4u * h + k;
            if ((imask >> c) & 1u) != 0u {
                hits |= 1u << (24u + (c ^ oct));
            } else {
                hits |= (m >> 5u) << (m & 31u);
            }
        }
    }
    return hits;
}

// `traverse` over the CWBVH (Algorithm 1 of Ylitie et al.).
fn traverse_cwbvh(org: vec3<f32>, dir: vec3<f32>, tmax_in: f32, any_hit: bool) -> Hit {
    var hit = Hit(false, tmax_in, 0u, 0.0, 0.0);
    let wr = watertight_ray_new(org, dir);
    let inv_d = ray_inv_dir(dir);
    // The ray's octant, inverted: a child's slot XOR this is its traversal priority.
    let oct = select(4u, 0u, dir.x < 0.0) | select(2u, 0u, dir.y < 0.0) | select(1u, 0u, dir.z < 0.0);
    // The root alone as a node group: bit 31 with no imask bits below it names node 0.
    var group = vec2<u32>(0u, 0x80000000u);
    var sp = 0u;
    loop {
        var tris = vec2<u32>(0u, 0u);
        if (group.y & 0xff000000u) != 0u {
            // The group's next node: its highest hit bit; the rest of the group waits.
            let bit = firstLeadingBit(group.y);
            let slot = (bit - 24u) ^ oct;
            let node = group.x + countOneBits(group.y & ((1u << slot) - 1u));
            group.y &= ~(1u << bit);
            if (group.y & 0xff000000u) != 0u && sp + 2u <= BVH_STACK_SIZE {
                BVH_STACK[sp * WORKGROUP_LANES + LANE] = group.x;
                BVH_STACK[(sp + 1u) * WORKGROUP_LANES + LANE] = group.y;
                sp += 2u;
            }
            let n = cw_node(node);
            bvh_count(1u, 0u, 0u);
            let hits = cw_intersect(n, node, org, inv_d, hit.t, oct);
            group = vec2<u32>(n.child_base, (hits & 0xff000000u) | (n.e_imask >> 24u));
            tris = vec2<u32>(n.prim_base, hits & 0x00ffffffu);
        }
        while tris.y != 0u {
            let slot = tris.x + firstTrailingBit(tris.y);
            tris.y &= tris.y - 1u;
            bvh_count(0u, 0u, 1u);
            let r = watertight_ray_intersect(wr, triangles[slot], hit.t);
            if r.w > 0.0 {
                hit = Hit(true, r.x, slot, r.y, r.z);
                if any_hit {
                    return hit;
                }
            }
        }
        if (group.y & 0xff000000u) == 0u {
            if sp == 0u {
                break;
            }
            sp -= 2u;
            group = vec2<u32>(BVH_STACK[sp * WORKGROUP_LANES + LANE], BVH_STACK[(sp + 1u) * WORKGROUP_LANES + LANE]);
        }
    }
    return hit;
}
