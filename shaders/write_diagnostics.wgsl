// Copies the per-pixel intermediate results into the engine's diagnostics image, for debug views
// and evaluation: R = hole (1) or valid (0), G = region (0 far-BE, 0.5 near-BE, 1 FI),
// B = LBP code / 255, A = 1.
// #import gbuffer

struct Params {
    extent: vec2u,
}
var<immediate> params: Params;

@group(0) @binding(0) var warped: texture_storage_2d<rgba16float, read>;
@group(0) @binding(1) var regions: texture_2d<u32>;
@group(0) @binding(2) var lbp: texture_2d<f32>;
@group(0) @binding(3) var diagnostics: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let p = id.xy;
    if (any(p >= params.extent)) {
        return;
    }
    let hole = select(0.0, 1.0, is_hole(textureLoad(warped, p).a));
    let region = f32(textureLoad(regions, p, 0).r) * 0.5;
    textureStore(diagnostics, p, vec4f(hole, region, textureLoad(lbp, p, 0).r, 1.0));
}
