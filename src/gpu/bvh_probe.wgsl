// bvh_probe.wgsl — the traversal probe (gpu::bvh_probe): `traverse` (BVH2 or CWBVH, by
// BVH_WIDE) on a list of rays with its work counted (BVH_COUNT). tests/gpu_bvh.rs runs it
// over the real trees and over a one-leaf BVH2 (a brute-force loop over every slot in the
// same code) and checks that both return exactly the same closest hit. Assembled after
// scene.wgsl and cwbvh.wgsl (`gpu::pipeline::bvh_probe_source`).

struct BvhProbeRay {
    org: array<f32, 3>,
    tmax: f32,
    dir: array<f32, 3>,
    // 1: occlusion (first hit), 0: closest hit.
    any_hit: u32,
}

struct BvhProbeOut {
    t: f32,
    // Leaf slot of the triangle hit.
    slot: u32,
    b1: f32,
    b2: f32,
    found: u32,
    // Node records visited, child boxes tested, triangles tested (`traverse` only).
    nodes: u32,
    boxes: u32,
    tris: u32,
}

@group(0) @binding(20) var<storage, read> probe_rays: array<BvhProbeRay>;
@group(0) @binding(21) var<storage, read_write> probe_out: array<BvhProbeOut>;

fn probe_result(h: Hit) -> BvhProbeOut {
    return BvhProbeOut(h.t, h.slot, h.b1, h.b2, u32(h.found), BVH_WORK.x, BVH_WORK.y, BVH_WORK.z);
}

@compute @workgroup_size(64, 1, 1)
fn bvh_probe(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    LANE = lane;
    let i = gid.x;
    if i >= arrayLength(&probe_rays) {
        return;
    }
    let r = probe_rays[i];
    BVH_WORK = vec3<u32>(0u);
    probe_out[i] = probe_result(traverse(v3(r.org), v3(r.dir), r.tmax, r.any_hit != 0u));
}
