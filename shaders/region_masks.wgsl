// Segmentation, step 3 of 3, for the diagnostics: each target pixel's region (`region_of`). The
// blend works out the regions of the pixels it repairs itself, and the statistics' FI and
// near-BE counts follow from the rectangles alone (`segmentation::read_back`).
// #import gbuffer
// #import segmentation
// #import regions

struct Params {
    extent: vec2u,
    has_stencil: u32,
}
var<immediate> params: Params;

@group(0) @binding(0) var target_stencil: texture_2d<u32>;
@group(0) @binding(1) var<storage, read> rects: RectTable;
@group(0) @binding(2) var regions: texture_storage_2d<r32uint, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (all(p < params.extent)) {
        textureStore(regions, p, vec4u(region_of(p, params.has_stencil), 0u, 0u, 0u));
    }
}
