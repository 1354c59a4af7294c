// Segmentation, step 3 of 3: each target pixel's region. FI where a dynamic object covers it,
// near-BE where it lies inside a grown rectangle but shows the background, far-BE elsewhere.
// Counts the FI and near-BE pixels; writes the regions only where a later pass reads them.
// #import gbuffer
// #import segmentation
// #import tallies

struct Params {
    extent: vec2u,
    // 0 when no pass reads the regions: a placeholder is bound.
    write_regions: u32,
    has_stencil: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var target_stencil: texture_2d<u32>;
@group(0) @binding(1) var<storage, read_write> segmentation: Segmentation;
@group(0) @binding(2) var regions: texture_storage_2d<r32uint, write>;

// The workgroup's tallies (tallies.wgsl).
const TALLY_FI: u32 = 0u;
const TALLY_NEAR_BE: u32 = 1u;

fn region_of(p: vec2u) -> u32 {
    if (params.has_stencil != ABSENT && textureLoad(target_stencil, p, 0).r != 0u) {
        return REGION_FI;
    }
    let count = atomicLoad(&segmentation.rect_count);
    for (var i = 0u; i < count; i++) {
        let rect = segmentation.rects[i];
        if (all(p >= vec2u(rect.left, rect.top)) && all(p < vec2u(rect.right, rect.bottom))) {
            return REGION_NEAR_BE;
        }
    }
    return REGION_FAR_BE;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) lane: u32) {
    open_tallies(lane);
    let p = id.xy;
    if (all(p < params.extent)) {
        let region = region_of(p);
        if (params.write_regions != 0u) {
            textureStore(regions, p, vec4u(region, 0u, 0u, 0u));
        }
        if (region == REGION_FI) {
            atomicAdd(&group_tallies[TALLY_FI], 1u);
        } else if (region == REGION_NEAR_BE) {
            atomicAdd(&group_tallies[TALLY_NEAR_BE], 1u);
        }
    }
    if (close_tallies(lane)) {
        atomicAdd(&segmentation.fi_pixels, atomicLoad(&group_tallies[TALLY_FI]));
        atomicAdd(&segmentation.near_be_pixels, atomicLoad(&group_tallies[TALLY_NEAR_BE]));
    }
}
