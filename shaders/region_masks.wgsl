// Segmentation, step 3 of 3, for the networks and the diagnostics: each target pixel's region.
// FI where a dynamic object covers it, near-BE where it lies inside a grown rectangle but shows
// the background, far-BE elsewhere. (The statistics' FI and near-BE counts follow from the
// rectangles alone: `segmentation::read_back`.)
// #import gbuffer
// #import segmentation

struct Params {
    extent: vec2u,
    has_stencil: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var target_stencil: texture_2d<u32>;
@group(0) @binding(1) var<storage, read> rects: RectTable;
@group(0) @binding(2) var regions: texture_storage_2d<r32uint, write>;

fn region_of(p: vec2u) -> u32 {
    if (params.has_stencil != ABSENT && textureLoad(target_stencil, p, 0).r != 0u) {
        return REGION_FI;
    }
    let count = min(rects.rect_count, MAX_OBJECTS);
    for (var i = 0u; i < count; i++) {
        let rect = rects.rects[i];
        if (all(p >= vec2u(rect.left, rect.top)) && all(p < vec2u(rect.right, rect.bottom))) {
            return REGION_NEAR_BE;
        }
    }
    return REGION_FAR_BE;
}

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (all(p < params.extent)) {
        textureStore(regions, p, vec4u(region_of(p), 0u, 0u, 0u));
    }
}
